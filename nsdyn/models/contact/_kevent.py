"""Event-driven integration of the body between events (numba kernel).

Between events the contact set (closed/open) and the friction state (stick / slip sigma) are
fixed; the reactions at every right-hand-side evaluation come from the acceleration-level LCP
(``_kgeom.solve_contacts``), so

    M qdd = f(t) + W_N^T lam_N + W_T^T lam_T,    y = (q, v),  y' = (v, qdd).

Dormand-Prince 5(4) with error control advances y; every accepted step the event indicators
(normalised, positive while the mode holds) are checked and a sign change is located on the
cubic Hermite dense output by the Illinois method:

    open contact:       g_i / L + G_TOUCH             (touchdown)
    closed contact:     lam_N / (m g) - w_N / g       (lift-off)
    sticking contact:   S_TOL - s / g  (s: LCP slip tendency)  (stick -> slip)
    slipping contact:   sigma v_T / sqrt(g L)         (slip stops or reverses)
    body:               min(theta_ov+ - theta, theta_ov- + theta)   (overturned)

The kernel returns at the first event (or t_end); the caller switches the mode.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn import _kborrow as kb
from nsdyn._klinalg import copy_vec, matvec, tmatvec
from nsdyn.models.contact._kgeom import contact_rows, ground_acc, mu_of, solve_contacts

SAFETY = 0.9  # step-size controller safety factor
FAC_MIN, FAC_MAX = 0.2, 5.0  # bounds of the step-size change per step
H_MIN_REL = 1e-14  # step underflow: h < H_MIN_REL * max(1, |t|)
ROOT_ITERS = 60  # Illinois iterations to locate an event
ROOT_TOL = 1e-13  # relative event-time tolerance
S_TOL = 1e-10  # slip tendency (in g) that ends sticking (above the LCP's round-off)
G_SINK = 1e-6  # an open contact this far below the ground (in L) is a failure, not a state
G_TOUCH = 1e-13  # open contacts touch down at g = -G_TOUCH L (a start at g = -0 still sees it)

# event codes
EV_END, EV_TOUCH, EV_LIFT, EV_SLIP, EV_STOP, EV_OVER = 0, 1, 2, 3, 4, 5
EV_UNDERFLOW, EV_MAXSTEPS, EV_LCP, EV_SINK = -1, -2, -3, -4


@njit(cache=True, error_model="numpy")
def rhs(t, y, sig, closed, verts, minv, par, ex, tab_h, tab_v):
    """(y', indicators (2 nc + 1,), lam_N, lam_T, LCP status) of the fixed-mode dynamics.

    par = [m, g, mu_s, mu_d, C (-1: infinity), theta_ov+, L, theta_ov-].
    """
    nc = verts.shape[0]
    m = par[0]
    grav = par[1]
    L = par[6]
    q = y[:3]
    v = y[3:]
    ah, av = ground_acc(t, ex, tab_h, tab_v)
    f = np.array([-m * ah, -m * (grav + av), 0.0])
    g, Wn, Wt, bn, bt, gd, vt = contact_rows(q, v, verts)
    a0 = minv * f
    bN = matvec(Wn, a0) + bn
    bT = matvec(Wt, a0) + bt
    mu = np.empty(nc)
    nk = 0
    for i in range(nc):
        if closed[i]:
            nk += 1
        mu[i] = par[2] if sig[i] == 0.0 else mu_of(vt[i], par[2], par[3], par[4])
    idx = np.empty(nk, np.int64)
    j = 0
    for i in range(nc):
        if closed[i]:
            idx[j] = i
            j += 1
    lamN, lamT, wN, slack, status = solve_contacts(Wn, Wt, minv, bN, bT, mu, sig, idx)
    F = f + tmatvec(Wn, lamN) + tmatvec(Wt, lamT)
    dy = np.empty(6)
    copy_vec(dy[:3], v)
    copy_vec(dy[3:], minv * F)
    ind = np.empty(2 * nc + 1)
    vs = math.sqrt(grav * L)
    for i in range(nc):
        if closed[i]:
            ind[i] = lamN[i] / (m * grav) - wN[i] / grav
            if sig[i] == 0.0:
                ind[nc + i] = S_TOL - slack[i] / grav
            else:
                ind[nc + i] = sig[i] * vt[i] / vs
        else:
            ind[i] = g[i] / L + G_TOUCH
            ind[nc + i] = 1.0
    ind[2 * nc] = min(par[5] - q[2], par[7] + q[2])
    return dy, ind, lamN, lamT, status


# the right-hand side by address (:func:`nsdyn._kaddress.tcall`, declared and put in the table
# by nsdyn.models.contact.contact_compile): the loop's seven call sites would otherwise link
# (and LLVM optimise and translate) a copy of it and of the LCP solver into the loop's code
ka.tslot("contact.rhs", rhs, "nsdyn.models.contact.contact_compile:callees")


@njit(cache=True, error_model="numpy", inline="always")
def rhs_t(t, y, sig, closed, verts, minv, par, ex, tab_h, tab_v):
    """:func:`rhs` called by its address in the table of :mod:`nsdyn._kaddress`."""
    return ka.tcall("contact.rhs", (t, y, sig, closed, verts, minv, par, ex, tab_h, tab_v))


@njit(cache=True, error_model="numpy")
def _hermite(t0, h, y0, f0, y1, f1, t):
    s = (t - t0) / h
    h00 = (1 + 2 * s) * (1 - s) ** 2
    h10 = s * (1 - s) ** 2
    h01 = s * s * (3 - 2 * s)
    h11 = s * s * (s - 1)
    return h00 * y0 + h10 * h * f0 + h01 * y1 + h11 * h * f1


@njit(cache=True, error_model="numpy")
def to_next_sample(t, t_end, ex, n):
    """Time from ``t`` to the excitation's next breakpoint before ``t_end`` (inf without one,
    or at ``t_end`` to round-off): a record's next sample, a sine's switch-on or -off time.
    Steps end on them, where the excitation kinks or jumps. A step across one saw its
    indicators at the step's ends alone, and an excursion around the breakpoint between (a
    2 ms lift-off around a sample at 1.00 s) was passed over."""
    tol = 4.0 * H_MIN_REL * max(1.0, abs(t))  # (a t on a breakpoint, to round-off: the next)
    best = math.inf
    if n >= 2:
        s = (t - ex[1]) / ex[2]
        k = max(math.floor(s + max(1e-9, tol / ex[2])) + 1.0, 0.0)
        if k <= n - 1:
            best = ex[1] + k * ex[2] - t
    if ex[0] == 1.0:
        for tb in (ex[5], ex[6]):
            if t + tol < tb < t + best:
                best = tb - t
    if t + best >= t_end - max(1e-9 * best, tol):  # (one at t_end: t_end is the step's)
        return math.inf
    return best


@njit(cache=True, error_model="numpy")
def integrate(t, y, t_end, h, sig, closed, verts, minv, par, ex, tab_h, tab_v,
              rtol, atol, t_out, y_out, iout, max_steps, h_max):  # fmt: skip
    """Integrate from (t, y) until the first event or ``t_end``.

    Writes the dense-output samples at ``t_out[iout:]`` up to the stop into ``y_out``.
    ``h_max`` bounds the step: a body at rest has y' = 0 and a zero error estimate, so without
    it the steps would stride over the excitation (and the stick-slip / lift-off it causes).

    Returns
    -------
    t, y, h (next step), code (EV_*), which (indicator index), iout, n_steps, n_rhs
    """
    # borrowed views (nsdyn._kborrow) of the arguments each evaluation takes: no atomic
    # reference counts per stage (y, returned, stays counted)
    sig, closed, verts, minv, par, ex, tab_h, tab_v, t_out, y_out = kb.borrowed(
        (sig, closed, verts, minv, par, ex, tab_h, tab_v, t_out, y_out)
    )
    nc = verts.shape[0]
    ni = 2 * nc + 1
    f0, ind0, _, _, st = rhs_t(t, y, sig, closed, verts, minv, par, ex, tab_h, tab_v)
    nrhs = 1
    if st != 0:
        return t, y, h, EV_LCP, -1, iout, 0, nrhs
    k = np.zeros((7, 6))
    nsteps = 0
    while nsteps < max_steps:
        if t >= t_end:
            return t, y, h, EV_END, -1, iout, nsteps, nrhs
        h = min(h, t_end - t, h_max)
        hs = to_next_sample(t, t_end, ex, tab_h.shape[0])
        if hs <= h * (1.0 + 1e-9):  # on the sample (a step of h_max stopped a sliver short)
            h = hs
        if t_end - t - h <= 1e-9 * h:  # (no sliver left before t_end)
            h = t_end - t
        if h < H_MIN_REL * max(1.0, abs(t)):
            return t, y, h, EV_UNDERFLOW, -1, iout, nsteps, nrhs
        copy_vec(k[0], f0)
        y2 = y + h * (0.2 * k[0])
        copy_vec(k[1], rhs_t(t + 0.2 * h, y2, sig, closed, verts, minv, par, ex, tab_h, tab_v)[0])
        y2 = y + h * (3 / 40 * k[0] + 9 / 40 * k[1])
        copy_vec(k[2], rhs_t(t + 0.3 * h, y2, sig, closed, verts, minv, par, ex, tab_h, tab_v)[0])
        y2 = y + h * (44 / 45 * k[0] - 56 / 15 * k[1] + 32 / 9 * k[2])
        copy_vec(k[3], rhs_t(t + 0.8 * h, y2, sig, closed, verts, minv, par, ex, tab_h, tab_v)[0])
        y2 = y + h * (19372 / 6561 * k[0] - 25360 / 2187 * k[1] + 64448 / 6561 * k[2]
                      - 212 / 729 * k[3])  # fmt: skip
        copy_vec(k[4], rhs_t(t + 8 / 9 * h, y2, sig, closed, verts, minv, par, ex, tab_h, tab_v)[0])
        y2 = y + h * (9017 / 3168 * k[0] - 355 / 33 * k[1] + 46732 / 5247 * k[2]
                      + 49 / 176 * k[3] - 5103 / 18656 * k[4])  # fmt: skip
        copy_vec(k[5], rhs_t(t + h, y2, sig, closed, verts, minv, par, ex, tab_h, tab_v)[0])
        y1 = y + h * (35 / 384 * k[0] + 500 / 1113 * k[2] + 125 / 192 * k[3]
                      - 2187 / 6784 * k[4] + 11 / 84 * k[5])  # fmt: skip
        f1, ind1, _, _, st = rhs_t(t + h, y1, sig, closed, verts, minv, par, ex, tab_h, tab_v)
        nrhs += 6
        copy_vec(k[6], f1)
        err = h * (71 / 57600 * k[0] - 71 / 16695 * k[2] + 71 / 1920 * k[3]
                   - 17253 / 339200 * k[4] + 22 / 525 * k[5] - 1 / 40 * k[6])  # fmt: skip
        en = 0.0
        for i in range(6):
            sc = atol + rtol * max(abs(y[i]), abs(y1[i]))
            en += (err[i] / sc) ** 2
        en = math.sqrt(en / 6)
        if not np.isfinite(en) or st != 0:
            en = 1e10
        if en > 1.0:
            h *= max(FAC_MIN, SAFETY * en ** (-0.2))
            continue
        nsteps += 1
        # event search on [t, t + h]
        first = -1
        t_ev = t + h
        for i in range(ni):
            if ind0[i] >= 0.0 and ind1[i] < 0.0:
                # Illinois on the Hermite interpolant
                ta, tb = t, t + h
                fa, fb = ind0[i], ind1[i]
                side = 0
                for _ in range(ROOT_ITERS):
                    tc = (fb * ta - fa * tb) / (fb - fa)
                    tc = min(max(tc, ta), tb)
                    yc = _hermite(t, h, y, f0, y1, f1, tc)
                    fc = rhs_t(tc, yc, sig, closed, verts, minv, par, ex, tab_h, tab_v)[1][i]
                    nrhs += 1
                    if fc >= 0.0:
                        ta, fa = tc, fc
                        if side == -1:
                            fb *= 0.5
                        side = -1
                    else:
                        tb, fb = tc, fc
                        if side == 1:
                            fa *= 0.5
                        side = 1
                    if tb - ta < ROOT_TOL * max(1.0, abs(tb)):
                        break
                if tb < t_ev:
                    t_ev = tb
                    first = i
        # closed contacts drifting off the ground count as a lift-off at the step end
        if first < 0:
            g = contact_rows(y1[:3], y1[3:], verts)[0]
            for i in range(nc):
                if closed[i] and g[i] > 1e-9 * par[6]:
                    first = i
                    break
                if not closed[i] and g[i] < -G_SINK * par[6]:  # a touchdown went unseen
                    return t + h, y1, h, EV_SINK, i, iout, nsteps, nrhs
        t_stop = t_ev if first >= 0 else t + h
        y_stop = y1 if (first < 0 or t_ev == t + h) else _hermite(t, h, y, f0, y1, f1, t_ev)
        while iout < t_out.shape[0] and t_out[iout] <= t_stop:
            copy_vec(y_out[iout], _hermite(t, h, y, f0, y1, f1, t_out[iout]))
            iout += 1
        fac = min(FAC_MAX, SAFETY * max(en, 1e-10) ** (-0.2))
        if first >= 0:
            code = EV_OVER
            if first < nc:
                code = EV_LIFT if closed[first] else EV_TOUCH
            elif first < 2 * nc:
                code = EV_SLIP if sig[first - nc] == 0.0 else EV_STOP
            return t_stop, y_stop, h, code, first, iout, nsteps, nrhs
        t = t + h
        y = y1
        f0 = f1
        ind0 = ind1
        h *= fac
    return t, y, h, EV_MAXSTEPS, -1, iout, nsteps, nrhs
