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
``ug`` are the excitation channels: ground accelerations, or a force history f with
``Gamma[:, 0] = -M^-1 b`` (load ``b f``; :mod:`nsdyn.models.isolated.params` packs either).

An open contact ``k`` (``P[I_OPEN][k] = 1``, unilateral runs in flight) leaves the
constraint set: ``lam_k = 0`` (its row of ``G`` is the identity), and isolator ``k`` carries
no friction and cannot stick.

Everything the kernels need is packed in one tuple ``P`` (built by ``params.pack``; layout
fixed by the ``I_*`` indices below): free functions over arrays, cached, no callbacks.

Unknowns ``y = [lam, tau_stuck]`` come from a small dense solve ``G y = -(C a0 + b)`` with
``G = C B``; accelerations are ``qdd = a0 + B y``. The analytic Jacobian uses
``d qdd = (I - B G^-1 C)(d a0 + dB y) - B G^-1 d b``.
"""

import numpy as np
from numba import njit

from nsdyn._kaddress import NO_NRT, compiled_uncounted
from nsdyn._klinalg import copy_vec, pinv_into, solve_small

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
I_WORK = 15  # float64 scratch of the kernels, length work_size(n, nc, ni)
I_OPEN = 16  # int64 (nc,) contact state: 1 open (lifted off: row, friction dropped), 0 closed
N_P = 17  # entries of P

F_EPS, F_ETA, F_ALPHA, F_BETA, F_KAPPA, F_G = 0, 1, 2, 3, 4, 5
N_FPAR = 6
K_LAW, K_FROZEN, K_GROUND, K_LOAD = 0, 1, 2, 3  # K_LOAD: LOAD_* (read outside the kernels)
N_IPAR = 4
LOAD_GROUND, LOAD_FORCE = 0, 1  # channel 0 is a ground acceleration / a force history
G_T0, G_DT, G_AH, G_FH, G_AV, G_FV, G_PH, G_PV = 0, 1, 2, 3, 4, 5, 6, 7  # PH, PV: phases
N_GPAR = 8

LAW_NONE = 0  # no friction (mu ignored)
LAW_ARCTAN = 1  # smooth arctan law, eq (7)
LAW_SWITCH = 2  # Leine's switch model with band |v| <= eta, modes decided in the kernel
LAW_MODES = 3  # modes prescribed in P[I_MODE] (event-driven integration)

GROUND_TABLE = 0  # sampled record, linear interpolation, zero outside
GROUND_HARMONIC = 1  # A sin(2 pi f t + phase) for both components

MODE_STICK = 0
MAX_SWITCH_PASSES = 8  # passes to settle stick/transition in the switch band


@njit(cache=True, error_model="numpy", inline="always")
def ground_accel(t, P):
    """Excitation channels [e_hor, e_ver] (without g) at ``t``: the load is -M Gamma e."""
    gp = P[I_GPAR]
    if P[I_IPAR][K_GROUND] == GROUND_HARMONIC:
        ah = gp[G_AH] * np.sin(2.0 * np.pi * gp[G_FH] * t + gp[G_PH])
        av = gp[G_AV] * np.sin(2.0 * np.pi * gp[G_FV] * t + gp[G_PV])
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


@njit(cache=True, error_model="numpy", inline="always")
def contact_open(P, k):
    """True when contact ``k`` exists and is open (in flight): no normal force, no friction."""
    return k < P[I_OPEN].shape[0] and P[I_OPEN][k] != 0


@njit(cache=True, error_model="numpy", inline="always")
def _direction(v, law, eps):
    """Friction direction s(v) and its slope ds/dv for the smooth laws."""
    if law == LAW_ARCTAN:
        s = (2.0 / np.pi) * np.arctan(eps * v)
        ds = (2.0 / np.pi) * eps / (1.0 + (eps * v) ** 2)
        return s, ds
    return 0.0, 0.0


# ---- scratch space ------------------------------------------------------------------------
# The kernels evaluate the right-hand side ~1e5 times per run; they allocate nothing but work
# in P[I_WORK], a float64 buffer sized by :func:`work_size` (so one P must not be used by two
# threads at once; processes each have their own copy). Allocating nothing, the system kernel
# and its Jacobian are compiled without numba's reference counts (NO_NRT, see
# :mod:`nsdyn._kaddress`): about half of their unoptimised code was that counting.


@njit(cache=True, error_model="numpy", inline="always")
def _solve_size(n, nc, ni):
    """Length of the solve's blocks of P[I_WORK] (:func:`_views`), where the Jacobian's start."""
    mm = max(nc + ni, 1)
    return n + 2 * mm * n + 3 * mm + 4 * ni + 2 * mm * mm


def work_size(n: int, nc: int, ni: int) -> int:
    """Length of the scratch buffer P[I_WORK] for n dofs, nc contacts, ni isolators: the
    solve's blocks (:func:`_views`), then the Jacobian's and the pseudo-inverse's
    (:func:`_jac_views`). Plain Python: a kernel called once from Python, numba compiled it
    in both processes of a first run (~0.4 s each)."""
    mm = max(nc + ni, 1)
    solve = getattr(_solve_size, "py_func", _solve_size)  # the kernels' own formula
    return solve(n, nc, ni) + 3 * mm * n + 4 * mm * mm + 2 * mm


@njit(cache=True, error_model="numpy", inline="always")
def _gram(X, Y, m, n, out):
    """out[:m, :m] = X[:m, :n] Y[:m, :n]^T (the constraint matrix G = C B of both the
    right-hand side and the Jacobian)."""
    for i in range(m):
        for j in range(m):
            g = 0.0
            for r in range(n):
                g += X[i, r] * Y[j, r]
            out[i, j] = g


@njit(cache=True, error_model="numpy", inline="always")
def _views(P):
    """(a0, B, Cr, b, y, rhs, s, ds, v, stuck, G, G2) carved out of P[I_WORK]."""
    W = P[I_WORK]
    n = P[I_MIK].shape[0]
    ni = P[I_D].shape[0]
    mm = max(P[I_R].shape[0] + ni, 1)
    # consecutive blocks of equal shape: [a0 | B, Cr | b, y, rhs | s, ds, v, stuck | G, G2]
    a0 = W[:n]
    o = n
    BC = W[o : o + 2 * mm * n].reshape((2, mm, n))
    o += 2 * mm * n
    vec = W[o : o + 3 * mm].reshape((3, mm))
    o += 3 * mm
    iso = W[o : o + 4 * ni].reshape((4, ni))  # s, ds, v, stuck (1.0: stuck, 0.0: sliding)
    o += 4 * ni
    GG = W[o : o + 2 * mm * mm].reshape((2, mm, mm))
    B, Cr, G, G2 = BC[0], BC[1], GG[0], GG[1]
    b, y, rhs_ = vec[0], vec[1], vec[2]
    s, ds, v, stuck = iso[0], iso[1], iso[2], iso[3]
    return a0, B, Cr, b, y, rhs_, s, ds, v, stuck, G, G2


@njit(cache=True, error_model="numpy", inline="always")
def _jac_views(P):
    """(BG (n, mm), CJ (mm, 2n), Gt, Gp, U, V (mm, mm), col, s2 (mm,)) of P[I_WORK] after the
    solve's blocks: the Jacobian's B^T G^-1 and C J, the transposed G it factors, and the
    pseudo-inverse of G with its scratch (:func:`nsdyn._klinalg.pinv_into`)."""
    W = P[I_WORK]
    n = P[I_MIK].shape[0]
    nc = P[I_R].shape[0]
    ni = P[I_D].shape[0]
    mm = max(nc + ni, 1)
    o = _solve_size(n, nc, ni)
    BG = W[o : o + mm * n].reshape((n, mm))
    o += mm * n
    CJ = W[o : o + 2 * mm * n].reshape((mm, 2 * n))
    o += 2 * mm * n
    sq = W[o : o + 4 * mm * mm].reshape((4, mm, mm))
    o += 4 * mm * mm
    vec = W[o : o + 2 * mm].reshape((2, mm))
    return BG, CJ, sq[0], sq[1], sq[2], sq[3], vec[0], vec[1]


@njit(cache=True, error_model="numpy", inline="always")
def _pinv(G, m, P):
    """The pseudo-inverse of G[:m, :m] in P[I_WORK] (:func:`_jac_views`' Gp)."""
    _BG, _CJ, _Gt, Gp, U, V, _col, s2 = _jac_views(P)
    pinv_into(G, m, Gp, U, V, s2)
    return Gp


@compiled_uncounted
def _assemble(t, x, P, s, stuck, a0, Bt, Crow, b):
    """Fill a0 (n,), Bt = B^T (m, n), constraint rows Crow (m, n), b (m,) for given directions.

    Returns m (number of unknowns). Rows/columns: contacts first, then stuck isolators in order.
    """
    MiK, MiC, Gam = P[I_MIK], P[I_MIC], P[I_GAM]
    R, MiRt, D, MiDt = P[I_R], P[I_MIRT], P[I_D], P[I_MIDT]
    mu, lam0, fp, ip = P[I_MU], P[I_LAM0], P[I_FPAR], P[I_IPAR]
    n = MiK.shape[0]
    nc = R.shape[0]
    ni = D.shape[0]
    uh, uv = ground_accel(t, P)
    uv += fp[F_G]
    frozen = ip[K_FROZEN] == 1
    for r in range(n):
        acc = -Gam[r, 0] * uh - Gam[r, 1] * uv
        for c in range(n):
            acc -= MiK[r, c] * x[c] + MiC[r, c] * x[n + c]
        a0[r] = acc
    alpha, beta, kappa = fp[F_ALPHA], fp[F_BETA], fp[F_KAPPA]
    for k in range(nc):
        rq = 0.0
        rv = 0.0
        op = contact_open(P, k)  # open: zero row and column (lam_k = 0 from G[k, k] = 1)
        for c in range(n):
            Bt[k, c] = 0.0 if op else MiRt[c, k]
            Crow[k, c] = 0.0 if op else R[k, c]
            rq += R[k, c] * x[c]
            rv += R[k, c] * x[n + c]
        b[k] = 0.0 if op else 2.0 * alpha * beta * rv + alpha * alpha * rq
    m = nc
    for i in range(ni):
        if stuck[i] != 0.0:
            dv = 0.0
            for c in range(n):
                Bt[m, c] = -MiDt[c, i]
                Crow[m, c] = D[i, c]
                dv += D[i, c] * x[n + c]
            b[m] = kappa * dv
            m += 1
        elif s[i] != 0.0 and mu[i] != 0.0:
            if frozen:
                f = mu[i] * s[i] * lam0[i]
                for c in range(n):
                    a0[c] -= MiDt[c, i] * f
            else:
                f = mu[i] * s[i]
                for c in range(n):
                    Bt[i, c] -= MiDt[c, i] * f
    return m


@njit(cache=True, error_model="numpy", inline="always")
def _solve(t, x, P, qdd, ws):
    """Accelerations and multipliers y for the directions s and stuck set in ``ws``.

    Returns (m, ok): the number of unknowns and False if the constraint system is singular.
    """
    a0, B, Cr, b, y, rhs_, s, ds, v, stuck, G, G2 = ws
    m = _assemble(t, x, P, s, stuck, a0, B, Cr, b)
    n = a0.shape[0]
    if m == 0:
        for r in range(n):
            qdd[r] = a0[r]
        return 0, True
    _gram(Cr, B, m, n, G)
    for i in range(m):
        acc = b[i]
        for r in range(n):
            acc += Cr[i, r] * a0[r]
        rhs_[i] = -acc
        for j in range(m):
            G2[i, j] = G[i, j]
        y[i] = rhs_[i]
    for k in range(P[I_R].shape[0]):
        if contact_open(P, k):
            G[k, k] = G2[k, k] = 1.0
    ok = solve_small(G2, y, m)
    if not ok:
        # redundant constraints (e.g. two isolators sticking on one rigid base): the split of
        # the constraint forces is indeterminate; take the minimum-norm one (rare)
        Gp = _pinv(G, m, P)
        ok = True
        for i in range(m):
            acc = 0.0
            for k in range(m):
                acc += Gp[i, k] * rhs_[k]
            y[i] = acc
            ok = ok and np.isfinite(acc)
    for r in range(n):
        acc = a0[r]
        for k in range(m):
            acc += B[k, r] * y[k]
        qdd[r] = acc
    return m, ok


@compiled_uncounted
def _directions(x, P, ws):
    """Set s, ds, stuck in ``ws`` from the law and the sliding velocities of state ``x``."""
    a0, B, Cr, b, y, rhs_, s, ds, v, stuck, G, G2 = ws
    D = P[I_D]
    ni = D.shape[0]
    n = P[I_MIK].shape[0]
    fp = P[I_FPAR]
    law = P[I_IPAR][K_LAW]
    for i in range(ni):
        vi = 0.0
        for c in range(n):
            vi += D[i, c] * x[n + c]
        v[i] = vi
        s[i] = 0.0
        ds[i] = 0.0
        stuck[i] = 0.0
        if contact_open(P, i):
            continue  # in flight: no friction
        if law == LAW_ARCTAN:
            s[i], ds[i] = _direction(vi, law, fp[F_EPS])
        elif law == LAW_MODES:
            pm = P[I_MODE][i]
            if pm == MODE_STICK:
                stuck[i] = 1.0
            else:
                s[i] = float(pm)
        elif law == LAW_SWITCH:
            if abs(vi) > fp[F_ETA]:
                s[i] = 1.0 if vi > 0 else -1.0
            else:
                stuck[i] = 1.0


@njit(cache=True, error_model="numpy", **NO_NRT)
def evaluate(t, x, P, qdd, lam, tau, modes):
    """Full evaluation at a state: accelerations, normal forces, friction forces and modes.

    Parameters
    ----------
    qdd : ndarray, shape (n,)        -- out: generalised accelerations
    lam : ndarray, shape (nc,)       -- out: normal (contact) forces, compressive positive
    tau : ndarray, shape (ni,)       -- out: friction force of each isolator (acting on the
                                        structure as -D_i^T tau_i), stick or slip
    modes : int64 ndarray, (ni,)     -- out: +1/-1 slip direction, 0 stick
    Returns ok (False if the constraint system is singular). Allocation-free (uses P[I_WORK]),
    so compiled without reference counts (NO_NRT).
    """
    ni = P[I_D].shape[0]
    nc = P[I_R].shape[0]
    law = P[I_IPAR][K_LAW]
    frozen = P[I_IPAR][K_FROZEN] == 1
    mu = P[I_MU]
    lam0 = P[I_LAM0]
    ws = _views(P)
    y, s, stuck = ws[4], ws[6], ws[9]
    _directions(x, P, ws)
    ok = True  # a solve, then up to MAX_SWITCH_PASSES re-solves: the inlined solve once
    for p in range(MAX_SWITCH_PASSES + 1):
        m, ok = _solve(t, x, P, qdd, ws)
        if law != LAW_SWITCH or p == MAX_SWITCH_PASSES:
            break
        # Leine's switch model: inside the band, stick while |tau| <= mu lamf, else transition
        # with the friction saturated in the direction of the would-be stick force
        changed = False
        kk = nc
        for i in range(ni):
            if stuck[i] != 0.0:
                lf = lam0[i] if frozen else y[i] if i < nc else 0.0
                if abs(y[kk]) > mu[i] * lf:
                    stuck[i] = 0.0
                    s[i] = 1.0 if y[kk] > 0 else -1.0
                    changed = True
                kk += 1
        if not changed:
            break
    for k in range(nc):
        lam[k] = y[k]
    kk = nc
    for i in range(ni):
        if stuck[i] != 0.0:
            tau[i] = y[kk]
            modes[i] = MODE_STICK
            kk += 1
        else:
            lf = lam0[i] if frozen else (lam[i] if i < nc else 0.0)
            tau[i] = mu[i] * s[i] * lf if law != LAW_NONE else 0.0
            modes[i] = 1 if s[i] >= 0 else -1
    return ok


@njit(cache=True, error_model="numpy")
def outputs(P):
    """Fresh output arrays of :func:`evaluate`: (qdd (n,), lam (nc,), tau (ni,), modes (ni,))."""
    ni = P[I_D].shape[0]
    return (
        np.empty(P[I_MIK].shape[0]),
        np.empty(P[I_R].shape[0]),
        np.empty(ni),
        np.empty(ni, dtype=np.int64),
    )


@njit(cache=True, error_model="numpy")
def rhs(t, x, P, out):
    """First-order right-hand side: out = [qd, qdd]. Returns False on a singular constraint."""
    n = P[I_MIK].shape[0]
    qdd, lam, tau, modes = outputs(P)
    ok = evaluate(t, x, P, qdd, lam, tau, modes)
    copy_vec(out[:n], x[n:])
    copy_vec(out[n:], qdd)
    return ok


@njit(cache=True, error_model="numpy")
def jac(t, x, P, J):
    """Analytic Jacobian d(rhs)/dx, shape (2n, 2n), for the current friction modes.

    For the arctan law it is exact; for the switch laws it is the Jacobian of the vector
    field with the present stick/slip modes frozen (piecewise linear there).
    With ``Jx = [Jq Jv]`` the unconstrained part (``-MiK``, ``-MiC`` and the arctan slope),
    ``qdd_x = (I - B G^-1 C) Jx - B G^-1 b_x``.
    """
    qdd, lam, tau, modes = outputs(P)
    evaluate(t, x, P, qdd, lam, tau, modes)
    jac_at(t, x, P, J, lam, modes)


@njit(cache=True, error_model="numpy", **NO_NRT)
def jac_at(t, x, P, J, lam, modes):
    """:func:`jac` once :func:`evaluate` at (t, x) left ``lam``, ``modes`` and its workspace
    (apart, a caller may evaluate by address: nsdyn.solve._kcommon.jac_table)."""
    MiK, MiC = P[I_MIK], P[I_MIC]
    R, D, MiDt = P[I_R], P[I_D], P[I_MIDT]
    mu, lam0, fp, ip = P[I_MU], P[I_LAM0], P[I_FPAR], P[I_IPAR]
    n = MiK.shape[0]
    nc = R.shape[0]
    ni = D.shape[0]
    law = ip[K_LAW]
    frozen = ip[K_FROZEN] == 1
    ws = _views(P)
    a0, B, Cr, b, y, rhs_, s, ds, v, stuck, G, G2 = ws
    # directions with the modes evaluate() settled on (switch law: after its passes)
    _directions(x, P, ws)
    if law != LAW_ARCTAN and law != LAW_NONE:
        for i in range(ni):
            s[i] = 0.0
            stuck[i] = 0.0
            if contact_open(P, i):
                continue
            if modes[i] == MODE_STICK:
                stuck[i] = 1.0
            else:
                s[i] = float(modes[i])
    m = _assemble(t, x, P, s, stuck, a0, B, Cr, b)
    for i in range(2 * n):
        for j in range(2 * n):
            J[i, j] = 0.0
    for r in range(n):
        J[r, n + r] = 1.0
        for c in range(n):
            J[n + r, c] = -MiK[r, c]
            J[n + r, n + c] = -MiC[r, c]
    for i in range(ni):
        if stuck[i] != 0.0 or ds[i] == 0.0 or mu[i] == 0.0:
            continue
        lf = lam0[i] if frozen else (lam[i] if i < nc else 0.0)
        cf = mu[i] * ds[i] * lf
        for r in range(n):
            for c in range(n):
                J[n + r, n + c] -= MiDt[r, i] * cf * D[i, c]
    if m == 0:
        return
    _gram(Cr, B, m, n, G)
    for k in range(nc):
        if contact_open(P, k):
            G[k, k] = 1.0
    # BG = B^T G^-1 (n, m): solve G^T BG^T = B row by row of B^T
    BG, CJ, Gt, _Gp, _U, _V, col, _s2 = _jac_views(P)
    for r in range(n):
        for i in range(m):
            col[i] = B[i, r]
            for j in range(m):
                Gt[i, j] = G[j, i]
        if not solve_small(Gt, col, m):
            Gp = _pinv(G, m, P)  # BG = B^T G+
            for rr in range(n):
                for k in range(m):
                    acc = 0.0
                    for i2 in range(m):
                        acc += B[i2, rr] * Gp[i2, k]
                    BG[rr, k] = acc
            break
        for k in range(m):
            BG[r, k] = col[k]
    # projector (I - B G^-1 C) on the unconstrained rows: J[n:, :] -= BG (C J[n:, :])
    for k in range(m):
        for c in range(2 * n):
            acc = 0.0
            for r in range(n):
                acc += Cr[k, r] * J[n + r, c]
            CJ[k, c] = acc
    alpha, beta, kappa = fp[F_ALPHA], fp[F_BETA], fp[F_KAPPA]
    # b_x: contacts alpha^2 R (q) and 2 alpha beta R (qd); stuck isolators kappa D (qd)
    for k in range(nc):
        for c in range(n):
            if contact_open(P, k):
                break
            CJ[k, c] += alpha * alpha * R[k, c]
            CJ[k, n + c] += 2.0 * alpha * beta * R[k, c]
    kk = nc
    for i in range(ni):
        if stuck[i] != 0.0:
            for c in range(n):
                CJ[kk, n + c] += kappa * D[i, c]
            kk += 1
    for r in range(n):
        for c in range(2 * n):
            acc = 0.0
            for k in range(m):
                acc += BG[r, k] * CJ[k, c]
            J[n + r, c] -= acc


@njit(cache=True, error_model="numpy", inline="always")
def store_row(k, QDD, LAM, TAU, MODES, qdd, lam, tau, modes):
    """Row ``k`` of the histories of an evaluation along a history (:func:`evaluate_many`)
    from the outputs of one evaluation."""
    copy_vec(QDD[k], qdd)
    copy_vec(LAM[k], lam)
    copy_vec(TAU[k], tau)
    copy_vec(MODES[k], modes)


@njit(cache=True, error_model="numpy")
def evaluate_many(t, X, P, QDD, LAM, TAU, MODES):
    """:func:`evaluate` along a history: t (nt,), X (nt, 2n) -> QDD (nt, n), LAM (nt, nc),
    TAU (nt, ni), MODES (nt, ni). Returns the number of states where the solve failed."""
    qdd, lam, tau, modes = outputs(P)
    bad = 0
    for k in range(t.shape[0]):
        if not evaluate(t[k], X[k], P, qdd, lam, tau, modes):
            bad += 1
        store_row(k, QDD, LAM, TAU, MODES, qdd, lam, tau, modes)
    return bad
