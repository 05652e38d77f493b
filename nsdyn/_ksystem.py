"""Numba kernels: the constrained equations of motion of a friction-isolated structure.

Governing equations (seed 004, eqs 8-15), first-order state ``x = [q, qd]``::

    M qdd = h(q, qd, ug) + R^T lam - sum_i D_i^T mu_i s_i lamf_i - sum_{j stuck} D_j^T tau_j
    h     = -C* qd - K* q - M Gamma [ug_hor, ug_ver + g]
    R qdd + 2 alpha beta R qd + alpha^2 R q = 0          (Baumgarte-stabilised contact)
    D_j qdd + kappa D_j qd = 0                            (stick, velocity-stabilised)

``lam`` are the normal forces (one per contact), ``D_i q`` is the sliding displacement of
isolator ``i``, ``s_i`` the friction direction (arctan law: (2/pi) arctan(eps v); switch
model: sign(v) in slip), ``lamf_i`` the normal force the friction uses (``lam_i`` or its static
value when frozen), ``tau_j`` the friction force of a stuck isolator (a constraint force).

Everything the kernels need is packed in one tuple ``P`` (see :func:`nsdyn.system` for the
builder); the layout is fixed by the ``I_*`` indices below. The kernels are free functions over
arrays so integrators can call them directly (numba caches them; no callbacks).

Unknowns ``y = [lam, tau_stuck]`` come from a small dense solve ``G y = -(C a0 + b)`` with
``G = C B``; accelerations are ``qdd = a0 + B y``. The analytic Jacobian uses
``d qdd = (I - B G^-1 C)(d a0 + dB y) - B G^-1 d b``.
"""

import numpy as np
from numba import njit

# ---- layout of the parameter tuple P -------------------------------------------------------
I_MIK = 0  # M^-1 K*           (n, n)
I_MIC = 1  # M^-1 C*           (n, n)
I_GAM = 2  # Gamma             (n, 2)  load influence (M^-1 M Gamma = Gamma)
I_R = 3  # contact rows R      (nc, n)
I_MIRT = 4  # M^-1 R^T         (n, nc)
I_D = 5  # sliding rows D      (ni, n)
I_MIDT = 6  # M^-1 D^T         (n, ni)
I_MU = 7  # friction coefficients (ni,)
I_LAM0 = 8  # static normal forces (ni,) used when the normal force is frozen
I_FPAR = 9  # float params, see F_*
I_IPAR = 10  # int params, see K_*
I_GPAR = 11  # ground params, see G_*
I_AH = 12  # horizontal ground acceleration samples (N,)
I_AV = 13  # vertical ground acceleration samples (N,)
I_MODE = 14  # int64 (ni,) prescribed isolator modes for LAW_MODES (+1/-1 slip, 0 stick)

F_EPS, F_ETA, F_ALPHA, F_BETA, F_KAPPA, F_G = 0, 1, 2, 3, 4, 5
N_FPAR = 6
K_LAW, K_FROZEN, K_GROUND = 0, 1, 2
N_IPAR = 3
G_T0, G_DT, G_AH, G_FH, G_AV, G_FV = 0, 1, 2, 3, 4, 5
N_GPAR = 6

LAW_NONE = 0  # no friction (mu ignored)
LAW_ARCTAN = 1  # smooth arctan law, eq (7)
LAW_SWITCH = 2  # Leine's switch model with band |v| <= eta, modes decided in the kernel
LAW_MODES = 3  # modes prescribed in P[I_MODE] (event-driven integration)

GROUND_TABLE = 0  # sampled record, linear interpolation, zero outside
GROUND_HARMONIC = 1  # A sin(2 pi f t) for both components

MODE_STICK = 0
MAX_SWITCH_PASSES = 8  # passes to settle stick/transition in the switch band


@njit(cache=True)
def ground_accel(t, P):
    """Ground acceleration [u_hor, u_ver] (without g) at time ``t``."""
    gp = P[I_GPAR]
    if P[I_IPAR][K_GROUND] == GROUND_HARMONIC:
        ah = gp[G_AH] * np.sin(2.0 * np.pi * gp[G_FH] * t)
        av = gp[G_AV] * np.sin(2.0 * np.pi * gp[G_FV] * t)
        return ah, av
    a_h = P[I_AH]
    a_v = P[I_AV]
    npts = a_h.shape[0]
    s = (t - gp[G_T0]) / gp[G_DT]
    if s < 0.0 or npts == 0:
        return 0.0, 0.0
    k = int(np.floor(s))
    if k >= npts - 1:
        if k == npts - 1 and s - k == 0.0:
            return a_h[k], a_v[k]
        return 0.0, 0.0
    w = s - k
    return (1.0 - w) * a_h[k] + w * a_h[k + 1], (1.0 - w) * a_v[k] + w * a_v[k + 1]


@njit(cache=True)
def _small_solve(G, b, m):
    """Solve G y = b (m x m, m small) by Gaussian elimination with partial pivoting.

    Returns (y, ok). ``ok`` is False when G is (numerically) singular.
    """
    A = G[:m, :m].copy()
    y = b[:m].copy()
    scale = 0.0
    for i in range(m):
        for j in range(m):
            scale = max(scale, abs(A[i, j]))
    if scale == 0.0 and m > 0:
        return y, False
    for k in range(m):
        p = k
        for i in range(k + 1, m):
            if abs(A[i, k]) > abs(A[p, k]):
                p = i
        if abs(A[p, k]) <= 1e-14 * scale:
            return y, False
        if p != k:
            for j in range(m):
                A[k, j], A[p, j] = A[p, j], A[k, j]
            y[k], y[p] = y[p], y[k]
        for i in range(k + 1, m):
            f = A[i, k] / A[k, k]
            for j in range(k, m):
                A[i, j] -= f * A[k, j]
            y[i] -= f * y[k]
    for k in range(m - 1, -1, -1):
        s = y[k]
        for j in range(k + 1, m):
            s -= A[k, j] * y[j]
        y[k] = s / A[k, k]
    return y, True


@njit(cache=True)
def _direction(v, law, eps):
    """Friction direction s(v) and its slope ds/dv for the smooth laws."""
    if law == LAW_ARCTAN:
        s = (2.0 / np.pi) * np.arctan(eps * v)
        ds = (2.0 / np.pi) * eps / (1.0 + (eps * v) ** 2)
        return s, ds
    return 0.0, 0.0


@njit(cache=True)
def _assemble(t, x, P, s, ds, stuck, a0, Bt, Crow, b, want_jac):
    """Fill a0 (n,), Bt = B^T (m, n), constraint rows Crow (m, n), b (m,) for given directions.

    Returns m (number of unknowns). Rows/columns: contacts first, then stuck isolators in order.
    """
    MiK, MiC, Gam = P[I_MIK], P[I_MIC], P[I_GAM]
    R, MiRt, D, MiDt = P[I_R], P[I_MIRT], P[I_D], P[I_MIDT]
    mu, lam0, fp, ip = P[I_MU], P[I_LAM0], P[I_FPAR], P[I_IPAR]
    n = MiK.shape[0]
    nc = R.shape[0]
    ni = D.shape[0]
    q = x[:n]
    qd = x[n:]
    uh, uv = ground_accel(t, P)
    uv += fp[F_G]
    frozen = ip[K_FROZEN] == 1
    for r in range(n):
        a0[r] = -Gam[r, 0] * uh - Gam[r, 1] * uv
    a0 -= MiK @ q
    a0 -= MiC @ qd
    alpha, beta, kappa = fp[F_ALPHA], fp[F_BETA], fp[F_KAPPA]
    for k in range(nc):
        Bt[k, :] = MiRt[:, k]
        Crow[k, :] = R[k, :]
        b[k] = 2.0 * alpha * beta * (R[k, :] @ qd) + alpha * alpha * (R[k, :] @ q)
    m = nc
    for i in range(ni):
        if stuck[i]:
            Bt[m, :] = -MiDt[:, i]
            Crow[m, :] = D[i, :]
            b[m] = kappa * (D[i, :] @ qd)
            m += 1
        elif s[i] != 0.0 and mu[i] != 0.0:
            if frozen:
                a0 -= MiDt[:, i] * (mu[i] * s[i] * lam0[i])
            else:
                Bt[i, :] -= MiDt[:, i] * (mu[i] * s[i])
    return m


@njit(cache=True)
def _solve(t, x, P, s, ds, stuck, qdd, y, work_B, work_C, work_b, a0):
    """Accelerations and multipliers for fixed directions ``s`` and stuck set. Returns (m, ok)."""
    m = _assemble(t, x, P, s, ds, stuck, a0, work_B, work_C, work_b, False)
    if m == 0:
        qdd[:] = a0
        return 0, True
    n = a0.shape[0]
    G = np.empty((m, m))
    rhs_ = np.empty(m)
    for i in range(m):
        acc = work_b[i]
        for r in range(n):
            acc += work_C[i, r] * a0[r]
        rhs_[i] = -acc
        for j in range(m):
            g = 0.0
            for r in range(n):
                g += work_C[i, r] * work_B[j, r]
            G[i, j] = g
    yy, ok = _small_solve(G, rhs_, m)
    if not ok:
        # redundant constraints (e.g. two isolators sticking on one rigid base): the split of
        # the constraint forces is indeterminate; take the minimum-norm one
        yy = np.linalg.pinv(G) @ rhs_
        ok = np.all(np.isfinite(yy))
    y[:m] = yy
    for r in range(n):
        acc = a0[r]
        for k in range(m):
            acc += work_B[k, r] * yy[k]
        qdd[r] = acc
    return m, ok


@njit(cache=True)
def _workspace(P):
    n = P[I_MIK].shape[0]
    mmax = P[I_R].shape[0] + P[I_D].shape[0]
    mm = max(mmax, 1)
    return (
        np.zeros(n),
        np.zeros((mm, n)),
        np.zeros((mm, n)),
        np.zeros(mm),
        np.zeros(mm),
    )


@njit(cache=True)
def evaluate(t, x, P, qdd, lam, tau, modes):
    """Full evaluation at a state: accelerations, normal forces, friction forces and modes.

    Parameters
    ----------
    qdd : ndarray, shape (n,)        -- out: generalised accelerations
    lam : ndarray, shape (nc,)       -- out: normal (contact) forces, compressive positive
    tau : ndarray, shape (ni,)       -- out: friction force of each isolator (acting on the
                                        structure as -D_i^T tau_i), stick or slip
    modes : int64 ndarray, (ni,)     -- out: +1/-1 slip direction, 0 stick
    Returns ok (False if the constraint system is singular).
    """
    D = P[I_D]
    ni = D.shape[0]
    nc = P[I_R].shape[0]
    n = P[I_MIK].shape[0]
    fp = P[I_FPAR]
    law = P[I_IPAR][K_LAW]
    frozen = P[I_IPAR][K_FROZEN] == 1
    mu = P[I_MU]
    lam0 = P[I_LAM0]
    a0, B, Cr, b, y = _workspace(P)
    s = np.zeros(ni)
    ds = np.zeros(ni)
    stuck = np.zeros(ni, dtype=np.bool_)
    qd = x[n:]
    v = D @ qd
    if law == LAW_ARCTAN:
        for i in range(ni):
            s[i], ds[i] = _direction(v[i], law, fp[F_EPS])
    elif law == LAW_MODES:
        pm = P[I_MODE]
        for i in range(ni):
            if pm[i] == MODE_STICK:
                stuck[i] = True
            else:
                s[i] = float(pm[i])
    elif law == LAW_SWITCH:
        eta = fp[F_ETA]
        for i in range(ni):
            if abs(v[i]) > eta:
                s[i] = 1.0 if v[i] > 0 else -1.0
            else:
                stuck[i] = True
    m, ok = _solve(t, x, P, s, ds, stuck, qdd, y, B, Cr, b, a0)
    if law == LAW_SWITCH:
        # Leine's switch model: inside the band, stick while |tau| <= mu lamf, else transition
        # with the friction saturated in the direction of the would-be stick force.
        for _ in range(MAX_SWITCH_PASSES):
            changed = False
            kk = nc
            for i in range(ni):
                if stuck[i]:
                    lf = lam0[i] if frozen else y[i] if i < nc else 0.0
                    if abs(y[kk]) > mu[i] * lf:
                        stuck[i] = False
                        s[i] = 1.0 if y[kk] > 0 else -1.0
                        changed = True
                    kk += 1
            if not changed:
                break
            m, ok = _solve(t, x, P, s, ds, stuck, qdd, y, B, Cr, b, a0)
    for k in range(nc):
        lam[k] = y[k]
    kk = nc
    for i in range(ni):
        if stuck[i]:
            tau[i] = y[kk]
            modes[i] = MODE_STICK
            kk += 1
        else:
            lf = lam0[i] if frozen else (lam[i] if i < nc else 0.0)
            tau[i] = mu[i] * s[i] * lf if law != LAW_NONE else 0.0
            modes[i] = 1 if s[i] >= 0 else -1
    return ok


@njit(cache=True)
def rhs(t, x, P, out):
    """First-order right-hand side: out = [qd, qdd]. Returns False on a singular constraint."""
    n = P[I_MIK].shape[0]
    nc = P[I_R].shape[0]
    ni = P[I_D].shape[0]
    qdd = np.empty(n)
    lam = np.empty(nc)
    tau = np.empty(ni)
    modes = np.empty(ni, dtype=np.int64)
    ok = evaluate(t, x, P, qdd, lam, tau, modes)
    out[:n] = x[n:]
    out[n:] = qdd
    return ok


@njit(cache=True)
def jac(t, x, P, J):
    """Analytic Jacobian d(rhs)/dx, shape (2n, 2n), for the current friction modes.

    For the arctan law it is exact; for the switch laws it is the Jacobian of the vector
    field with the present stick/slip modes frozen (piecewise linear there).
    """
    MiK, MiC = P[I_MIK], P[I_MIC]
    R, D, MiDt = P[I_R], P[I_D], P[I_MIDT]
    mu, lam0, fp, ip = P[I_MU], P[I_LAM0], P[I_FPAR], P[I_IPAR]
    n = MiK.shape[0]
    nc = R.shape[0]
    ni = D.shape[0]
    law = ip[K_LAW]
    frozen = ip[K_FROZEN] == 1
    qdd = np.empty(n)
    lam = np.empty(nc)
    tau = np.empty(ni)
    modes = np.empty(ni, dtype=np.int64)
    evaluate(t, x, P, qdd, lam, tau, modes)
    s = np.zeros(ni)
    ds = np.zeros(ni)
    stuck = np.zeros(ni, dtype=np.bool_)
    v = D @ x[n:]
    for i in range(ni):
        if law == LAW_ARCTAN:
            s[i], ds[i] = _direction(v[i], law, fp[F_EPS])
        elif law != LAW_NONE:
            if modes[i] == MODE_STICK:
                stuck[i] = True
            else:
                s[i] = float(modes[i])
    a0, B, Cr, b, y = _workspace(P)
    m = _assemble(t, x, P, s, ds, stuck, a0, B, Cr, b, True)
    # d a0 + dB y: position part -MiK, velocity part -MiC + E
    Jq = -MiK.copy()
    Jv = -MiC.copy()
    for i in range(ni):
        if stuck[i] or ds[i] == 0.0 or mu[i] == 0.0:
            continue
        lf = lam0[i] if frozen else (lam[i] if i < nc else 0.0)
        c = mu[i] * ds[i] * lf
        for r in range(n):
            for cidx in range(n):
                Jv[r, cidx] -= MiDt[r, i] * c * D[i, cidx]
    if m > 0:
        Cm = np.ascontiguousarray(Cr[:m, :])
        G = Cm @ np.ascontiguousarray(B[:m, :].T)
        Ginv = np.linalg.pinv(G)
        BG = np.ascontiguousarray(np.ascontiguousarray(B[:m, :].T) @ Ginv)  # (n, m)
        # projector (I - B G^-1 C) applied to Jq and Jv
        Jq = Jq - BG @ (Cm @ Jq)
        Jv = Jv - BG @ (Cm @ Jv)
        alpha, beta, kappa = fp[F_ALPHA], fp[F_BETA], fp[F_KAPPA]
        # - B G^-1 d b
        for k in range(nc):
            for cidx in range(n):
                for r in range(n):
                    Jq[r, cidx] -= BG[r, k] * alpha * alpha * R[k, cidx]
                    Jv[r, cidx] -= BG[r, k] * 2.0 * alpha * beta * R[k, cidx]
        kk = nc
        for i in range(ni):
            if stuck[i]:
                for cidx in range(n):
                    for r in range(n):
                        Jv[r, cidx] -= BG[r, kk] * kappa * D[i, cidx]
                kk += 1
    J[:, :] = 0.0
    for r in range(n):
        J[r, n + r] = 1.0
    J[n:, :n] = Jq
    J[n:, n:] = Jv


@njit(cache=True)
def sliding_velocities(x, P):
    """Sliding velocities v_i = D_i qd of all isolators."""
    n = P[I_MIK].shape[0]
    return P[I_D] @ x[n:]


@njit(cache=True)
def evaluate_many(t, X, P, QDD, LAM, TAU, MODES):
    """:func:`evaluate` along a history: t (nt,), X (nt, 2n) -> QDD (nt, n), LAM (nt, nc),
    TAU (nt, ni), MODES (nt, ni). Returns the number of states where the solve failed."""
    n = P[I_MIK].shape[0]
    nc = P[I_R].shape[0]
    ni = P[I_D].shape[0]
    qdd = np.empty(n)
    lam = np.empty(nc)
    tau = np.empty(ni)
    modes = np.empty(ni, dtype=np.int64)
    bad = 0
    for k in range(t.shape[0]):
        ok = evaluate(t[k], X[k], P, qdd, lam, tau, modes)
        if not ok:
            bad += 1
        QDD[k] = qdd
        LAM[k] = lam
        TAU[k] = tau
        MODES[k] = modes
    return bad


@njit(cache=True)
def ground_many(t, P):
    """Ground acceleration [u_hor, u_ver] (without g) at many times, shape (nt, 2)."""
    out = np.empty((t.shape[0], 2))
    for k in range(t.shape[0]):
        out[k, 0], out[k, 1] = ground_accel(t[k], P)
    return out
