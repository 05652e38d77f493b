"""Moreau-Jean time stepping of the body (numba kernel).

Per step [t_k, t_k + h] (theta-method, impulses P = h lam at velocity level):

    q_m   = q_k + h/2 v_k,                 active set  {i : g_i(q_m) <= G_ACT L}
    v_f   = v_k + h M^-1 f(t_k + theta h)  (+ the ground velocity jumps in the step)
    v_k+1 = v_f + M^-1 (W_N^T P_N + W_T^T P_T)
    q_k+1 = q_k + h ((1 - theta) v_k + theta v_k+1)

with Newton's law at velocity level on the active contacts,
0 <= W_N v_k+1 + e_n W_N v_k  _|_  P_N >= 0, and Coulomb's law on the impulses
(|P_T| <= mu(v_T,k) P_N, sliding opposite to v_T,k+1) solved as one LCP (``_kgeom``).  Impacts
and their accumulations are simply absorbed into the steps; the scheme is first order.

Body mode of a step (the output labels), from the step's impulses rather than from thresholds on
the positions alone: a corner that carried a normal impulse is on the ground, slipping when
|v_T,k+1| > v_tol (a sticking one has v_T,k+1 = 0 by the LCP); a corner without impulse is off
when it separates (W_N v_k+1 > v_tol) or its gap exceeds g_tol, and otherwise keeps its state.
The last rule matters: the theta-method lets a rocking pivot rise by O(h^2) and fall freely for
one step now and then (no impulse, a tangential velocity ~ g h); that is not a slip.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from nsdyn import _kborrow as kb
from nsdyn._klinalg import all_finite, copy_vec, matvec, tmatvec
from nsdyn.models.contact._kgeom import (
    FLIGHT,
    OVERTURNED,
    REST,
    ROCK,
    SLIDE,
    SLIDE_ROCK,
    contact_rows,
    ground_acc,
    mu_of,
    solve_contacts,
    tipped,
)

G_ACT = 1e-9  # a contact is active when its predicted gap is below G_ACT * L
JUMP_EPS = 1e-9  # a jump within JUMP_EPS h of a step's end belongs to the next step
# a contact whose slip after a step is below V_REST sqrt(g L) (the LCP's round-off of a held
# corner, ~1e-18 m/s, far below it) was held by that step: static friction in the next one
V_REST = 1e-10
S_PAST = 4.0  # a landing corner's slip is read at most this many steps ahead (landing_slip)


@njit(cache=True, error_model="numpy")
def step_mode(q, v, PN, Wn, Wt, verts, g_tol, v_tol, on, slipping):
    """Update the corners' state ``on``, ``slipping`` after a step with normal impulses ``PN``
    (module text) and return the body mode (REST, SLIDE, ROCK, SLIDE_ROCK or FLIGHT). The
    velocities are the step's own, ``W_N v``, ``W_T v`` with the rows of the step (at its
    midpoint): those the LCP holds at zero for a sticking corner (at q_k+1 the rows turn by
    theta' h / 2, and a sticking pivot would show a slip ~ theta'^2 h b)."""
    g = contact_rows(q, v, verts)[0]
    gd = matvec(Wn, v)
    vt = matvec(Wt, v)
    n_on = 0
    slip = False
    for i in range(g.shape[0]):
        if PN[i] > 0.0:
            on[i] = True
            slipping[i] = abs(vt[i]) > v_tol
        elif gd[i] > v_tol or g[i] > g_tol:
            on[i] = False
            slipping[i] = False
        if on[i]:
            n_on += 1
            slip = slip or slipping[i]
    if n_on == 0:
        return FLIGHT
    if n_on == 1:
        return SLIDE_ROCK if slip else ROCK
    return SLIDE if slip else REST


@njit(cache=True, error_model="numpy")
def landing_slip(q, v, h, i, verts, on, held):
    """Slip velocity of corner ``i`` where it touches down in the step from ``q`` with the
    velocity ``v``, relative to a corner ``held`` on the ground (a stuck pivot: its own slip
    at the step's start is O(h) from the turned rows, not a motion): at the point of the
    straight path ``q + s h v`` where the gap, linear in s through the step's start and end,
    reaches the level of the lowest corner ``on`` the ground (at most 0: the theta-method
    lets a pivot sink O(h)), in the step or after it. A rectangle rocking about one corner
    lands the other at rest (it moves vertically at theta = 0); at the step's midpoint, or at
    a gap of 0 below a sunk pivot, its slip is O(h) (3e-4 m/s at h = 1e-3 s on a 0.5 x 1.5 m
    prism)."""
    ga = contact_rows(q, v, verts)[0]
    gb = contact_rows(q + h * v, v, verts)[0]
    la = lb = 0.0
    p = -1
    for j in range(ga.shape[0]):
        if on[j] and j != i:
            la, lb = min(la, ga[j]), min(lb, gb[j])
            if held[j] and (p < 0 or ga[j] < ga[p]):
                p = j
    a, b = ga[i] - la, gb[i] - lb
    # past the step's end too (a few steps at most): a pivot that landed from a fall sank
    # v h / 2, deeper than a rocking corner comes down in a step, active a step before its level
    s = min(a / (a - b), S_PAST) if a > 0.0 and b < a else 0.0
    vt = contact_rows(q + s * h * v, v, verts)[6]
    return vt[i] - vt[p] if p >= 0 else vt[i]


@njit(cache=True, error_model="numpy")
def moreau(q0, v0, t0, h, nsteps, theta, e_n, verts, minv, par, ex, tab_h, tab_v,
           jumps, stride, g_tol, v_tol):  # fmt: skip
    """Run ``nsteps`` steps of size ``h`` from (t0, q0, v0).

    par = [m, g, mu_s, mu_d, C (-1: infinity), theta_ov+, L, theta_ov-].  jumps: (nj, 2) rows
    (t, ground velocity jump), sorted by t.  Every ``stride`` steps the state and body mode
    are stored.

    Returns
    -------
    t (nout,), q (nout, 3), v (nout, 3), mode (nout,), n_done (steps taken), status
    (0 done, 1 overturned, -1 LCP failure, -2 non-finite state), t_stop, first (time of the
    first step whose mode is not rest, -1 if none; that mode), at every step whatever stride
    """
    # borrowed views (nsdyn._kborrow) of the arguments: no atomic reference counts per step
    verts, minv, par, ex, tab_h, tab_v, jumps = kb.borrowed(
        (verts, minv, par, ex, tab_h, tab_v, jumps)
    )
    nc = verts.shape[0]
    m = par[0]
    grav = par[1]
    L = par[6]
    nout = nsteps // stride + 1
    t_o = np.zeros(nout)
    q_o = np.zeros((nout, 3))
    v_o = np.zeros((nout, 3))
    md_o = np.zeros(nout, np.int64)
    q = q0.copy()
    v = v0.copy()
    t_o[0] = t0
    copy_vec(q_o[0], q)
    copy_vec(v_o[0], v)
    g0, _, _, _, _, _, vt0 = contact_rows(q, v, verts)
    on = np.zeros(nc, np.bool_)
    slipping = np.zeros(nc, np.bool_)
    v_rest = V_REST * math.sqrt(grav * L)
    held = np.zeros(nc, np.bool_)  # stuck by the last step's LCP (at the start: at rest)
    for i in range(nc):
        on[i] = g0[i] <= g_tol
        slipping[i] = on[i] and abs(vt0[i]) > v_tol
        held[i] = on[i] and abs(vt0[i]) <= v_rest
    _, Wn0, Wt0, _, _, _, _ = contact_rows(q, v, verts)
    md_o[0] = step_mode(q, v, np.zeros(nc), Wn0, Wt0, verts, g_tol, v_tol, on, slipping)
    if tipped(q[2], par[5], par[7]):
        md_o[0] = OVERTURNED
    first = np.array([t0 if md_o[0] != REST else -1.0, float(md_o[0])])  # first non-rest step
    io = 1
    sig = np.zeros(nc)
    mu = np.empty(nc)  # (each step's friction coefficients and its corners solved again)
    again = np.zeros(nc, np.bool_)
    status = 0
    k = 0
    t = t0
    jn = 0
    while k < nsteps:
        t = t0 + k * h
        vk = v.copy()
        # each jump once, in the step containing it (a count, not a float test on t = t0 + k h)
        while jn < jumps.shape[0] and jumps[jn, 0] < t + h * (1.0 - JUMP_EPS):
            if jumps[jn, 0] >= t0:
                vk[0] -= jumps[jn, 1]
                if jumps[jn, 1] != 0.0:  # (the ground moved under the corners: none held)
                    held[:] = False
            jn += 1
        qm = q + 0.5 * h * vk
        g, Wn, Wt, bn, bt, gd, vt = contact_rows(qm, vk, verts)
        ah, av = ground_acc(t + theta * h, ex, tab_h, tab_v)
        f = np.array([-m * ah, -m * (grav + av), 0.0])
        vf = vk + h * minv * f
        na = 0
        for i in range(nc):
            if g[i] <= G_ACT * L:
                na += 1
        idx = np.empty(na, np.int64)
        j = 0
        for i in range(nc):
            if g[i] <= G_ACT * L:
                idx[j] = i
                j += 1
        for i in range(nc):  # static friction at a corner the last step held, whose v_T
            # here is the LCP's round-off or O(h) from the turned rows, never exactly 0 (the
            # jump law read mu_d for a body at rest); and at a corner landing from the air
            # at rest (within v_tol, as step_mode labels a slip)
            lands = not on[i] and g[i] <= G_ACT * L
            rest = held[i] or (lands and abs(landing_slip(q, vk, h, i, verts, on, held)) <= v_tol)
            mu[i] = par[2] if rest else mu_of(vt[i], par[2], par[3], par[4])
        bN = matvec(Wn, vf) + e_n * matvec(Wn, vk)
        bT = matvec(Wt, vf)
        PN, PT, wN, slack, st = solve_contacts(Wn, Wt, minv, bN, bT, mu, sig, idx)
        if st != 0:
            status = -1
            break
        v = vf + minv * (tmatvec(Wn, PN) + tmatvec(Wt, PT))
        vt_held = matvec(Wt, v)  # (the step's rows: those the LCP holds at zero)
        # a slip that reverses in the step passed through rest, where static friction acts:
        # solved again with mu_s at those corners, kept if it holds them (a reversal at mu_d
        # otherwise, as the kinetic friction after a break-away)
        again[:] = False  # (the corners solved again; no others judged)
        for i in range(nc):
            if not held[i] and PN[i] > 0.0 and vt[i] * vt_held[i] < 0.0 and mu[i] < par[2]:
                mu[i] = par[2]
                again[i] = True
        if again.any():
            PN2, PT2, wN2, slack2, st2 = solve_contacts(Wn, Wt, minv, bN, bT, mu, sig, idx)
            v2 = vf + minv * (tmatvec(Wn, PN2) + tmatvec(Wt, PT2))
            vt2 = matvec(Wt, v2)
            stops = st2 == 0
            for i in range(nc):
                if again[i] and abs(vt2[i]) > v_rest:
                    stops = False
            if stops:
                PN, PT, v, vt_held = PN2, PT2, v2, vt2
        q = q + h * ((1.0 - theta) * vk + theta * v)
        k += 1
        t = t0 + k * h
        if not (all_finite(q) and all_finite(v)):
            status = -2
            break
        over = tipped(q[2], par[5], par[7])
        md = step_mode(q, v, PN, Wn, Wt, verts, g_tol, v_tol, on, slipping)
        for i in range(nc):  # held: stuck by this step's LCP; a held corner without impulse
            # (a pivot the theta-method lets fall freely for a step) stays held while on the
            # ground (step_mode), not a slip to be met with mu_d at its next impulse
            held[i] = abs(vt_held[i]) <= v_rest if PN[i] > 0.0 else held[i] and on[i]
        if first[0] < 0.0 and (md != REST or over):
            first[0] = t
            first[1] = OVERTURNED if over else md
        if k % stride == 0 or over:
            if io < nout:
                t_o[io] = t
                copy_vec(q_o[io], q)
                copy_vec(v_o[io], v)
                md_o[io] = OVERTURNED if over else md
                io += 1
        if over:
            status = 1
            break
    return t_o[:io], q_o[:io], v_o[:io], md_o[:io], k, status, t, first
