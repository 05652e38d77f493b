"""Contact kinematics, base excitation and the frictional contact LCPs (numba kernels).

Body coordinates q = (x, y, theta) of the centre of mass relative to the moving ground, mass
matrix M = diag(m, m, J).  A contact vertex r (body frame) sits at d = R(theta) r from the centre
of mass; its gap, normal and tangential velocities are

    g = y + d_y,   gd = W_N v = ydot + thetadot d_x,   v_T = W_T v = xdot - thetadot d_y,

with W_N = [0, 1, d_x], W_T = [1, 0, -d_y] and the acceleration biases
(dW_N/dt) v = -thetadot^2 d_y, (dW_T/dt) v = -thetadot^2 d_x.  Applied force in the ground frame:
f = (-m a_h(t), -m (g + a_v(t)), 0).

Frictional contacts in the plane (two-sided pyramid, exact in 2D; Anitescu-Potra form): per
contact the normal reaction lam_N, friction lam_T = beta+ - beta-, slack s,

    w_N = D_NN lam_N + D_NT lam_T + b_N        >= 0  _|_ lam_N >= 0
    w_+ = D_TN lam_N + D_TT lam_T + b_T + s    >= 0  _|_ beta+ >= 0
    w_- = -(D_TN lam_N + D_TT lam_T + b_T) + s >= 0  _|_ beta- >= 0
    mu lam_N - beta+ - beta-                   >= 0  _|_ s >= 0

(D = W M^-1 W^T), at acceleration level (b: free accelerations, sticking contacts) or at velocity
level (b: free velocities plus restitution; impulses).  A contact marked as slipping with sign
sigma has the fixed friction lam_T = -mu sigma lam_N and only its normal row.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from nsdyn._klinalg import dot3, max_abs
from nsdyn.models.contact._klcp import lemke

RETRY_SHIFT = 1e-10  # relative shift of q when Lemke's first attempt ray-terminates
REG = 0.0  # relative diagonal regularisation of the LCP (none: the lexicographic rule copes)
# ... except where two contacts' rows agree to ~1e-9 (a body sliding flat on one edge): Lemke
# then may ray-terminate with its artificial variable at ~1e-8-1e-7 of the data, its last
# pivots at round-off (which side depends on the last bits: numpy and numba versions, or the
# JIT on or off), or end on a basis round-off has spoilt (Lemke's status 3). A compliance of
# RETRY_REG x the largest inverse mass on the normal and tangential diagonal separates the
# rows, the smaller first; a velocity after an impact then misses its law by that compliance
# times the impulse (1e-6 m/s for a unit-mass 0.5 x 1.5 m prism's impulse of 0.2 m/s).
RETRY_REG = np.array([1e-8, 1e-6])

# body modes (also the index of the time-in-mode summary)
REST, SLIDE, ROCK, SLIDE_ROCK, FLIGHT, OVERTURNED = 0, 1, 2, 3, 4, 5


@njit(cache=True, error_model="numpy")
def ground_acc(t, ex, tab_h, tab_v):
    """Ground acceleration (a_h, a_v) [m/s^2] at time t.

    ex = [kind, t0, dt, amp, omega, t_on, t_off, phase]: kind 0 table (linear interpolation,
    zero outside), kind 1 sine amp sin(omega (t - t_on) + phase) on [t_on, t_off], plus the table.
    """
    ah = 0.0
    av = 0.0
    n = tab_h.shape[0]
    if n > 0:
        s = (t - ex[1]) / ex[2]
        if s >= 0.0 and s <= n - 1:
            i = min(int(s), n - 2)
            fr = s - i
            ah = (1.0 - fr) * tab_h[i] + fr * tab_h[i + 1]
            if tab_v.shape[0] == n:
                av = (1.0 - fr) * tab_v[i] + fr * tab_v[i + 1]
    if ex[0] == 1.0 and t >= ex[5] and t <= ex[6]:
        ah += ex[3] * math.sin(ex[4] * (t - ex[5]) + ex[7])
    return ah, av


@njit(cache=True, error_model="numpy")
def contact_rows(q, v, verts):
    """Gaps g (nc,), rows W_N, W_T (nc, 3), biases b_N, b_T (nc,), normal and slip velocities."""
    nc = verts.shape[0]
    c = math.cos(q[2])
    s = math.sin(q[2])
    g = np.empty(nc)
    Wn = np.zeros((nc, 3))
    Wt = np.zeros((nc, 3))
    bn = np.empty(nc)
    bt = np.empty(nc)
    gd = np.empty(nc)
    vt = np.empty(nc)
    for i in range(nc):
        dx = c * verts[i, 0] - s * verts[i, 1]
        dy = s * verts[i, 0] + c * verts[i, 1]
        g[i] = q[1] + dy
        Wn[i, 1] = 1.0
        Wn[i, 2] = dx
        Wt[i, 0] = 1.0
        Wt[i, 2] = -dy
        bn[i] = -v[2] * v[2] * dy
        bt[i] = -v[2] * v[2] * dx
        gd[i] = v[1] + v[2] * dx
        vt[i] = v[0] - v[2] * dy
    return g, Wn, Wt, bn, bt, gd, vt


@njit(cache=True, error_model="numpy")
def solve_contacts(Wn, Wt, minv, bN, bT, mu, sig, idx):
    """Frictional contact LCP on the contacts ``idx``.

    Parameters
    ----------
    Wn, Wt : (nc, 3) rows;  minv : (3,) inverse masses;  bN, bT : (nc,) free normal/tangential
    accelerations (or velocities);  mu : (nc,) friction coefficients;  sig : (nc,) 0 sticking
    (pyramid), +-1 slipping in that direction (fixed friction);  idx : (k,) contacts in the problem.

    Returns
    -------
    lamN, lamT : (nc,) reactions (zero off ``idx``);  wN : (nc,) normal accelerations (velocities)
    after the reactions;  slack : (nc,) slip tendency s = |tangential acceleration (velocity)| of
    sticking contacts (zero while they stick);  status : int (Lemke's)
    """
    nc = Wn.shape[0]
    k = idx.shape[0]
    lamN = np.zeros(nc)
    lamT = np.zeros(nc)
    wN = np.zeros(nc)
    slack = np.zeros(nc)
    if k == 0:
        return lamN, lamT, wN, slack, 0
    # sticking contacts among idx (frictionless ones carry no friction unknowns)
    ks = 0
    for a in range(k):
        if sig[idx[a]] == 0.0 and mu[idx[a]] > 0.0:
            ks += 1
    sidx = np.empty(ks, np.int64)
    j = 0
    for a in range(k):
        if sig[idx[a]] == 0.0 and mu[idx[a]] > 0.0:
            sidx[j] = idx[a]
            j += 1
    # force columns of the normal reactions: W_N - mu sigma W_T for slipping contacts
    Fn = np.zeros((k, 3))
    for a in range(k):
        i = idx[a]
        for d in range(3):
            Fn[a, d] = Wn[i, d] - mu[i] * sig[i] * Wt[i, d]
    n = k + 3 * ks
    A = np.zeros((n, n))
    qv = np.zeros(n)
    scale = 0.0
    for d in range(3):
        scale = max(scale, minv[d])
    for a in range(k):
        i = idx[a]
        qv[a] = bN[i]
        for c in range(k):
            A[a, c] = dot3(Wn[i], minv, Fn[c])
        for c in range(ks):
            dnt = dot3(Wn[i], minv, Wt[sidx[c]])
            A[a, k + c] = dnt
            A[a, k + ks + c] = -dnt
        A[a, a] += REG * scale
    for a in range(ks):
        i = sidx[a]
        rp = k + a
        rm = k + ks + a
        rs = k + 2 * ks + a
        qv[rp] = bT[i]
        qv[rm] = -bT[i]
        for c in range(k):
            dtn = dot3(Wt[i], minv, Fn[c])
            A[rp, c] = dtn
            A[rm, c] = -dtn
        for c in range(ks):
            dtt = dot3(Wt[i], minv, Wt[sidx[c]])
            A[rp, k + c] = dtt
            A[rp, k + ks + c] = -dtt
            A[rm, k + c] = -dtt
            A[rm, k + ks + c] = dtt
        A[rp, rp] += REG * scale
        A[rm, rm] += REG * scale
        A[rp, rs] = 1.0
        A[rm, rs] = 1.0
        for c in range(k):
            if idx[c] == i:
                A[rs, c] = mu[i]
        A[rs, rp] = -1.0
        A[rs, rm] = -1.0
    # the LCP is homogeneous in q: solve it for q / max|q| (Lemke's tolerances are absolute)
    qs = max_abs(qv)
    if qs == 0.0:
        return lamN, lamT, wN, slack, 0
    z, w, status = lemke(A, qv / qs)
    if status != 0:  # degenerate start: retry slightly perturbed
        z, w, status = lemke(A, qv / qs + RETRY_SHIFT)
        w -= RETRY_SHIFT
    reg = 0.0
    for r in range(RETRY_REG.shape[0]):
        if status == 0:
            break
        # degenerate rows (one edge's two contacts): retry regularised, least first
        for a in range(k + 2 * ks):
            A[a, a] += (RETRY_REG[r] - reg) * scale
        reg = RETRY_REG[r]
        z, w, status = lemke(A, qv / qs)
    z *= qs
    w *= qs
    for a in range(k):
        i = idx[a]
        lamN[i] = z[a]
        wN[i] = w[a]
    for a in range(k):
        i = idx[a]
        if sig[i] != 0.0:
            lamT[i] = -mu[i] * sig[i] * lamN[i]
    for a in range(ks):
        i = sidx[a]
        lamT[i] = z[k + a] - z[k + ks + a]
        slack[i] = z[k + 2 * ks + a]
    return lamN, lamT, wN, slack, status


@njit(cache=True, error_model="numpy")
def mu_of(v, mu_s, mu_d, cdec):
    """Friction coefficient mu(v) = mu_d + (mu_s - mu_d) exp(-C |v|); C < 0 means C = infinity
    (mu_s at rest, mu_d when slipping)."""
    if cdec < 0.0:
        return mu_s if v == 0.0 else mu_d
    return mu_d + (mu_s - mu_d) * math.exp(-cdec * abs(v))


@njit(cache=True, error_model="numpy")
def tipped(theta, ov_pos, ov_neg):
    """Whether the tilt ``theta`` [rad] lays the body on a side edge: at ``ov_pos`` rocking
    about its left corner, ``-ov_neg`` about its right one (RigidBody.overturn_tilts)."""
    return theta >= ov_pos or -theta >= ov_neg


@njit(cache=True, error_model="numpy")
def body_mode(q, v, verts, g_tol, v_tol, ov_pos, ov_neg):
    """Body mode from the state: REST, SLIDE, ROCK, SLIDE_ROCK, FLIGHT or OVERTURNED
    (:func:`tipped`)."""
    if tipped(q[2], ov_pos, ov_neg):
        return OVERTURNED
    g, Wn, Wt, bn, bt, gd, vt = contact_rows(q, v, verts)
    n_on = 0
    slip = False
    for i in range(g.shape[0]):
        if g[i] <= g_tol:
            n_on += 1
            if abs(vt[i]) > v_tol:
                slip = True
    if n_on == 0:
        return FLIGHT
    tilted = abs(q[2]) > g_tol / max(1e-300, _base_width(verts))
    if n_on >= 2 and not tilted:
        return SLIDE if slip else REST
    return SLIDE_ROCK if slip else ROCK


@njit(cache=True, error_model="numpy")
def _base_width(verts):
    lo = verts[0, 0]
    hi = verts[0, 0]
    for i in range(verts.shape[0]):
        lo = min(lo, verts[i, 0])
        hi = max(hi, verts[i, 0])
    return hi - lo
