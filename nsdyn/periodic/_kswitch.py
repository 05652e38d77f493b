"""Numba kernel: the period map of the switch model (modes held between events) with its
exact monodromy (flows between events times saltation matrices at the switches).

With the isolator modes fixed (slip +1/-1, stick 0; law LAW_MODES of the system kernel) the
equations on minimal coordinates ``x = [z, zd]`` are linear with constant and harmonic
forcing, so with the forcing states ``[1, sin wt, cos wt]`` appended the augmented state
``y = [x, 1, sin wt, cos wt]`` obeys ``y' = Ab_k y`` (``k`` the mode set) and the flow over
``s`` is exact: ``y(t + s) = expm(Ab_k s) y(t)``; its block ``expm(A_k s)`` is the
sensitivity ``dx(t + s) / dx(t)``. Switching functions are linear in ``y``:

    slip s:   g = s v_i = c . y,   c = s V_i               (slip -> stick or reversal at g = 0)
    stick:    g = mu_i lamf_i -+ tau_i = c . y             (stick -> slip at g = 0)

with ``tau = TAU_k y``, ``lamf = LF_k y``. A period of ``N`` equal steps ``h = T / N``
(``expm(Ab_k h)`` computed once per mode set): a root is bracketed per step from the values
and slopes ``g' = c . Ab_k y`` at both ends (sign change, or a dip of the Hermite cubic whose
exact value is negative), then located by safeguarded Newton on the exact ``g(s)``. At a
switch from ``f-`` to ``f+`` (``f = Ab y``) the sensitivity jumps by the saltation matrix
(Leine & Nijmeijer 2004, non-autonomous switching surface)

    S = I + (f+ - f-) n^T / (c . f-),    n = c[:dim],                 Phi <- S Phi

so the monodromy is the product of flows and saltations. At slip -> stick ``n^T f+ = 0``
(``v = 0`` is held), so ``n^T S = 0``: a stick phase gives an exact zero multiplier.

Grazing is measured per period: at every event ``|c . f-| / (w scale)`` and at every dip of
a switching function that does not cross zero its minimum ``/ scale`` (not for a function
starting at its zero, which a switch just made) (``scale``: ``mu lamf``
for a stick row, the largest ``|v_i|`` so far for a slip row); the smallest is returned.
"""

import numpy as np
from numba import njit

from nsdyn import _kborrow as kb
from nsdyn._klinalg import copy_vec, lu_factor, lu_solve_columns

STATUS_OK = 0
STATUS_SINGULAR = 2  # singular Pade denominator (expm)
STATUS_NONFINITE = 3  # non-finite state
STATUS_EVENTS = 5  # more switching events in one step than MAX_STEP_EVENTS

NEWTON_MAXIT = 60  # safeguarded Newton iterations per root
ROOT_XTOL = 1e-14  # root tolerance, relative to the step
MAX_STEP_EVENTS = 32  # switches within one step before reporting chattering
STICK_RTOL = 1e-12  # relative slack of the stick test |tau| <= mu lamf
MAX_EVENTS = 256  # events recorded per period
START_RTOL = 1e-9  # a switching function below this x its scale at a step start sits at zero

# Pade(13) coefficients (Higham 2005)
_B13 = np.array(
    [
        64764752532480000.0,
        32382376266240000.0,
        7771770303897600.0,
        1187353796428800.0,
        129060195264000.0,
        10559470521600.0,
        670442572800.0,
        33522128640.0,
        1323241920.0,
        40840800.0,
        960960.0,
        16380.0,
        182.0,
        1.0,
    ]
)
THETA13 = 5.371920351148152  # 1-norm bound of the Pade(13) approximant


@njit(cache=True, error_model="numpy")
def expm(A):
    """Matrix exponential by Pade(13) scaling and squaring (Higham 2005). Returns (E, ok)."""
    n = A.shape[0]
    nrm = 0.0
    for j in range(n):
        s = 0.0
        for i in range(n):
            s += abs(A[i, j])
        nrm = max(nrm, s)
    sq = 0
    if nrm > THETA13:
        sq = int(np.ceil(np.log2(nrm / THETA13)))
    As = A / (2.0**sq)
    b = _B13
    Id = np.eye(n)
    A2 = As @ As
    A4 = A2 @ A2
    A6 = A4 @ A2
    U = As @ (A6 @ (b[13] * A6 + b[11] * A4 + b[9] * A2) + b[7] * A6 + b[5] * A4 + b[3] * A2)
    U = U + As * b[1]
    V = A6 @ (b[12] * A6 + b[10] * A4 + b[8] * A2) + b[6] * A6 + b[4] * A4 + b[2] * A2
    V = V + b[0] * Id
    P = V - U
    E = V + U
    piv = np.zeros(n, dtype=np.int64)
    if not lu_factor(P, piv, 0.0):
        return E, False
    lu_solve_columns(P, piv, E)
    for _ in range(sq):
        E = E @ E
    return E, True


@njit(cache=True, error_model="numpy")
def mode_index(modes):
    """Index of a mode set: sum_i (modes_i + 1) 3^i."""
    k = 0
    p = 1
    for i in range(modes.shape[0]):
        k += (modes[i] + 1) * p
        p *= 3
    return k


@njit(cache=True, error_model="numpy")
def _rows(k, modes, V, TAU, LF, mu, i):
    """Switching rows of isolator ``i`` in mode set ``k``: (c1, c2, nrow). Slip: one row
    ``s V_i``; stick: ``mu LF_i - TAU_i`` and ``mu LF_i + TAU_i``."""
    if modes[i] != 0:
        return modes[i] * V[i], V[i] * 0.0, 1
    return mu[i] * LF[k, i] - TAU[k, i], mu[i] * LF[k, i] + TAU[k, i], 2


@njit(cache=True, error_model="numpy")
def _holds(tau, limit):
    """Stick test: a friction limit ``limit = mu lamf > 0`` holds the stick force ``tau``."""
    return limit > 0.0 and abs(tau) <= limit * (1.0 + STICK_RTOL)


@njit(cache=True, error_model="numpy")
def _release(y, modes, TAU, LF, mu):
    """In place: every stuck isolator whose stick force leaves the friction cone slips along
    that force, repeated until nothing changes (a release changes the others' stick forces)."""
    ni = modes.shape[0]
    for _ in range(2 * ni + 2):
        k = mode_index(modes)
        changed = False
        for i in range(ni):
            if modes[i] == 0:
                tau = TAU[k, i] @ y
                if not _holds(tau, mu[i] * (LF[k, i] @ y)):
                    modes[i] = 1 if tau >= 0.0 else -1
                    changed = True
        if not changed:
            break


@njit(cache=True, error_model="numpy")
def settle(y, modes, trigger, kind, V, TAU, LF, mu):
    """Consistent modes after isolator ``trigger`` reached its switching surface (kind 0:
    slip -> v = 0; 1: stick -> friction limit). A slip reaching v = 0 sticks if the stick force
    stays within the cone, else reverses; a stick slips along its stick force; then every stuck
    isolator whose stick force leaves the cone slips (repeated until nothing changes)."""
    new = modes.copy()
    if kind == 0:
        new[trigger] = 0
    else:
        k = mode_index(new)
        tau = TAU[k, trigger] @ y
        new[trigger] = 1 if tau >= 0.0 else -1
    _release(y, new, TAU, LF, mu)
    return new


@njit(cache=True, error_model="numpy")
def initial_modes(y, V, TAU, LF, mu, v_zero):
    """Modes at the period start: slip along v where |v| > v_zero, else the stick test."""
    ni = V.shape[0]
    modes = np.zeros(ni, dtype=np.int64)
    for i in range(ni):
        v = V[i] @ y
        if abs(v) > v_zero:
            modes[i] = 1 if v > 0.0 else -1
    _release(y, modes, TAU, LF, mu)
    return modes


@njit(cache=True, error_model="numpy")
def _g_exact(Ab, c, y, s):
    """g(s) = c . expm(Ab s) y and its slope c . Ab y(s)."""
    E, ok = expm(Ab * s)
    ys = E @ y
    return c @ ys, c @ (Ab @ ys)


@njit(cache=True, error_model="numpy")
def _root(Ab, c, y, a, b, ga, gb, ha):
    """Root of g on [a, b] with g(a) = ga > 0 >= gb = g(b): Newton on the exact g, kept in
    the bracket (bisection when a step leaves it). Stops when the Newton correction or the
    bracket falls below ``ROOT_XTOL ha``; returns the last Newton estimate of the root."""
    s = a - ga * (b - a) / (gb - ga)
    tol = ROOT_XTOL * ha
    for _ in range(NEWTON_MAXIT):
        if not (a < s < b):
            s = 0.5 * (a + b)
        g, gd = _g_exact(Ab, c, y, s)
        if g > 0.0:
            a = s
        else:
            b = s
            if g == 0.0:
                return s
        if b - a <= tol:
            return b
        if gd == 0.0:
            s = 0.5 * (a + b)
            continue
        step = g / gd
        s = s - step
        if abs(step) <= tol:
            # quadratic convergence: s is within round-off of the root
            return min(max(s, a), b)
    return b


@njit(cache=True, error_model="numpy")
def _hermite_min(g0, g1, d0, d1, h):
    """Position (in [0, h]) and value of the minimum of the cubic Hermite interpolant."""
    # p(u) = g0 H00 + h d0 H10 + g1 H01 + h d1 H11, u in [0, 1]
    a3 = 2.0 * g0 - 2.0 * g1 + h * d0 + h * d1
    a2 = -3.0 * g0 + 3.0 * g1 - 2.0 * h * d0 - h * d1
    a1 = h * d0
    best_u, best = 0.0, g0
    # p'(u) = 3 a3 u^2 + 2 a2 u + a1
    qa, qb, qc = 3.0 * a3, 2.0 * a2, a1
    cands = np.empty(2)
    nc = 0
    if qa == 0.0:
        if qb != 0.0:
            cands[0] = -qc / qb
            nc = 1
    else:
        disc = qb * qb - 4.0 * qa * qc
        if disc >= 0.0:
            r = np.sqrt(disc)
            cands[0] = (-qb - r) / (2.0 * qa)
            cands[1] = (-qb + r) / (2.0 * qa)
            nc = 2
    for j in range(nc):
        u = cands[j]
        if 0.0 < u < 1.0:
            p = g0 + u * (a1 + u * (a2 + u * a3))
            if p < best:
                best_u, best = u, p
    return best_u * h, best


@njit(cache=True, error_model="numpy")
def _detect(Ab, rows, scales, nrows, y, y1, fy, fy1, h, graze):
    """Earliest root in (0, h] of the switching rows (``rows[j]``, j < nrows) along the exact
    flow; returns (s, j) with j = -1 when none. A dip that stays above zero updates
    ``graze[0]`` with its exact minimum over the row's scale ``scales[j]``."""
    s_best = 2.0 * h
    j_best = -1
    for j in range(nrows):
        c = rows[j]
        g0, g1 = c @ y, c @ y1
        d0, d1 = c @ fy, c @ fy1
        a, ga = 0.0, g0
        found = False
        if g1 < 0.0:
            if g0 > 0.0:
                found = True
            elif d0 > 0.0:
                # just switched onto this function (g0 ~ 0): start from its rise
                um, _ = _hermite_min(-g0, -g1, -d0, -d1, h)
                gm, _ = _g_exact(Ab, c, y, um)
                if gm > 0.0:
                    a, ga, found = um, gm, True
        elif d0 < 0.0 and d1 >= 0.0 and g0 > 0.0:
            # a minimum inside the step or at its end: a dip below zero is a pair of roots
            sm, pm = _hermite_min(g0, g1, d0, d1, h)
            gm = min(pm, g1)
            if pm < 0.5 * min(g0, g1):
                gm, _ = _g_exact(Ab, c, y, sm)
                if gm < 0.0:
                    s = _root(Ab, c, y, 0.0, sm, g0, gm, h)
                    if s < s_best:
                        s_best, j_best = s, j
                    continue
            if g0 > START_RTOL * scales[j]:
                # (a function that starts at its zero -- the switch just made -- and rises
                # tangentially, as a slip starting from rest does, is not a graze)
                graze[0] = min(graze[0], gm / max(scales[j], 1e-300))
        if found:
            s = _root(Ab, c, y, a, h, ga, g1, h)
            if s < s_best:
                s_best, j_best = s, j
    return s_best, j_best


@njit(cache=True, error_model="numpy")
def period_map(AB, V, TAU, LF, mu, x0, w, T, N, v_zero, want_sens, store, ev_t, ev_i, ev_m, ev_g):
    """One period ``T`` in ``N`` steps from ``x0`` (t = 0, forcing phase 0).

    AB (K, D, D) augmented matrices of every mode set, V (ni, D) sliding-velocity rows,
    TAU / LF (K, ni, D) friction-force / friction-normal-force rows, mu (ni,), w = 2 pi / T.
    Events go to ``ev_t, ev_i, ev_m, ev_g`` (time, isolator, new mode, grazing measure
    ``|c . f-| / (w scale)``). Returns (xT, Phi, X, MK, status, n_events, graze): MK (N + 1,)
    the mode-set index at each sample, graze the smallest grazing measure of the period.
    """
    # borrowed views (nsdyn._kborrow) of the arguments: no atomic reference counts per step
    # (the returned arrays are this function's own)
    AB, V, TAU, LF, mu, x0, ev_t, ev_i, ev_m, ev_g = kb.borrowed(
        (AB, V, TAU, LF, mu, x0, ev_t, ev_i, ev_m, ev_g)
    )
    d = x0.shape[0]
    Dd = d + 3
    K = AB.shape[0]
    ni = V.shape[0]
    h = T / N
    E = np.zeros((K, Dd, Dd))
    have = np.zeros(K, dtype=np.bool_)
    y = np.zeros(Dd)
    copy_vec(y[:d], x0)
    y[d] = 1.0
    y[d + 2] = 1.0
    Phi = np.eye(d) if want_sens else np.zeros((1, 1))
    X = np.zeros((N + 1, d)) if store else np.zeros((1, d))
    MK = np.zeros(N + 1, dtype=np.int64)
    if store:
        copy_vec(X[0], x0)
    modes = initial_modes(y, V, TAU, LF, mu, v_zero)
    k = mode_index(modes)
    MK[0] = k
    nev = 0
    graze = np.full(1, np.inf)
    rown = np.zeros(2 * ni, dtype=np.int64)  # isolator of each candidate row
    allrows = np.zeros((2 * ni, Dd))
    scales = np.zeros(2 * ni)  # natural size of each row: mu lamf (stick), max |v| (slip)
    vmax = np.full(ni, 1e-300)
    for i in range(ni):
        vmax[i] = max(vmax[i], abs(V[i] @ y))
    for n in range(N):
        t = n * h
        rem = h
        count = 0
        while True:
            if rem == h:
                if not have[k]:
                    Ek, ok = expm(AB[k] * h)
                    if not ok:
                        return y[:d], Phi, X, MK, STATUS_SINGULAR, nev, graze[0]
                    E[k] = Ek
                    have[k] = True
                Es = E[k]
            else:
                Es, ok = expm(AB[k] * rem)
                if not ok:
                    return y[:d], Phi, X, MK, STATUS_SINGULAR, nev, graze[0]
            y1 = Es @ y
            fy = AB[k] @ y
            fy1 = AB[k] @ y1
            nr = np.int64(0)
            for i in range(ni):
                c1, c2, m = _rows(k, modes, V, TAU, LF, mu, i)
                sc = vmax[i] if m == 1 else abs(mu[i] * (LF[k, i] @ y))
                allrows[nr] = c1
                scales[nr] = sc
                rown[nr] = i
                nr += 1
                if m == 2:
                    allrows[nr] = c2
                    scales[nr] = sc
                    rown[nr] = i
                    nr += 1
            s_ev, j = _detect(AB[k], allrows, scales, nr, y, y1, fy, fy1, rem, graze)
            if j < 0:
                if want_sens:
                    Phi = np.ascontiguousarray(Es[:d, :d]) @ Phi
                y = y1
                for i in range(ni):
                    vmax[i] = max(vmax[i], abs(V[i] @ y))
                break
            count += 1
            if count > MAX_STEP_EVENTS:
                return y[:d], Phi, X, MK, STATUS_EVENTS, nev, graze[0]
            Ee, ok = expm(AB[k] * s_ev)
            if not ok:
                return y[:d], Phi, X, MK, STATUS_SINGULAR, nev, graze[0]
            ye = Ee @ y
            i_ev = rown[j]
            kind = 0 if modes[i_ev] != 0 else 1
            c = allrows[j].copy()
            new = settle(ye, modes, i_ev, kind, V, TAU, LF, mu)
            k2 = mode_index(new)
            fm = AB[k] @ ye
            fp = AB[k2] @ ye
            den = c @ fm
            gm = abs(den) / max(w * scales[j], 1e-300)
            graze[0] = min(graze[0], gm)
            if want_sens:
                Phi = np.ascontiguousarray(Ee[:d, :d]) @ Phi
                if den != 0.0:
                    nPhi = c[:d] @ Phi  # n^T Phi, then Phi += (f+ - f-) n^T Phi / den
                    for a in range(d):
                        jump = (fp[a] - fm[a]) / den
                        if jump != 0.0:
                            for b in range(d):
                                Phi[a, b] += jump * nPhi[b]
            if nev < ev_t.shape[0]:
                ev_t[nev] = t + s_ev
                ev_i[nev] = i_ev
                ev_m[nev] = new[i_ev]
                ev_g[nev] = gm
            nev += 1
            y = ye
            modes = new
            k = k2
            t += s_ev
            rem -= s_ev
            if rem <= ROOT_XTOL * h:
                break
        for a in range(Dd):
            if not np.isfinite(y[a]):
                return y[:d], Phi, X, MK, STATUS_NONFINITE, nev, graze[0]
        if store:
            copy_vec(X[n + 1], y[:d])
        MK[n + 1] = k
    return y[:d], Phi, X, MK, STATUS_OK, nev, graze[0]
