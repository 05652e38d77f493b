"""Numba kernels for periodic solutions: fixed-step SDIRK period map with its exact derivative.

Problems (dispatched on an integer id, right-hand sides called as module globals so the
kernels are cached across processes):

- ``PROB_FRAME``: the isolated structure on the contact manifold (seed 004 eqs 23-27),
  ``x = [z, zd]``, ``q = Q z``, ``zdd = Q^T qdd(Q z, Q zd)`` (Q orthonormal columns): the
  constrained equations of :mod:`nsdyn._ksystem` (its tuple ``P`` supplies the ground motion
  and friction settings) written on the manifold with the products of ``Z`` precomputed. On
  the manifold this equals ``[Q^T 0; 0 Q^T] ks.rhs([Q z, Q zd])`` with Jacobian
  ``blockdiag(Q^T) ks.jac blockdiag(Q)`` (checked in the tests) at a fraction of the cost.
- ``PROB_DUFFING``: ``x'' + 2 zeta w0 x' + w0^2 x + gamma x^3 = F cos(w t)``,
  ``pf = [zeta, w0, gamma, F, w]`` (``P`` is a dummy tuple of the same type).

One step of a stiffly accurate singly diagonally implicit Runge-Kutta method (tableau ``A``,
``c``, diagonal ``gamma``) solves the stage equations

    Y_i = x_n + h sum_{j<i} a_ij F_j + h gamma F(t_n + c_i h, Y_i),   x_{n+1} = Y_s

by Newton's method. The period map ``x_N = phi(x_0; T)`` with ``h = T / N`` is differentiated
*exactly as a discrete map* ("internal numerical differentiation", Bock 1981): differentiating
the stage equations at the converged stages gives

    (I - h gamma J_i) S_i = S_n + h sum_{j<i} a_ij J_j S_j                      (d/dx_0)
    (I - h gamma J_i) w_i = w_n + (1/N) sum_{j<=i} a_ij F_j + h sum_{j<i} a_ij J_j w_j   (d/dT)

with the forcing phase ``(n + c_j)/N`` independent of T. So the monodromy is the derivative of
the map actually iterated, and Newton on the shooting residual converges quadratically.
"""

import numpy as np
from numba import njit

from . import _ksystem as ks

PROB_FRAME = 0  # isolated structure on minimal coordinates (eq 27 with precomputed Z)
PROB_DUFFING = 1  # Duffing oscillator, pf = [zeta, w0, gamma, F, w]

STATUS_OK = 0
STATUS_STAGE = 1  # a stage Newton iteration did not converge
STATUS_SINGULAR = 2  # singular constraint system or iteration matrix
STATUS_NONFINITE = 3  # state became inf/nan

STAGE_MAXIT = 25  # Newton iterations per stage
STAGE_SLOW = 0.1  # contraction factor above which the iteration matrix is refreshed
STAGE_HALVINGS = 10  # backtracking halvings of a damped stage Newton update
STAGE_FULL_STEP = 1e4  # updates below this many tolerances are taken without line search
STAGE_STAGNATION = 1e3  # accept a stalled iteration this close to the tolerance (round-off)
MAX_SUBSTEPS = 64  # a failing step is retried as 2, 4, ... substeps, at most this many


# ---- layout of the manifold tuple Z (all 2-D float arrays) -------------------------------------
# q = Q z; a0 = M^-1 h = -MiK q - MiC qd - Gamma u; every product below is precomputed once.
Z_Q, Z_QT = 0, 1  # Q (n, m), Q^T (m, n)
Z_KZ, Z_CZ = 2, 3  # Q^T MiK Q, Q^T MiC Q (m, m)
Z_QG = 4  # Q^T Gamma (m, 2)
Z_QMIRT, Z_QMIDT = 5, 6  # Q^T M^-1 R^T (m, nc), Q^T M^-1 D^T (m, ni)
Z_RAZ, Z_RAV = 7, 8  # R MiK Q, R MiC Q (nc, m)
Z_RG = 9  # R Gamma (nc, 2)
Z_G0, Z_GD = 10, 11  # R M^-1 R^T (nc, nc), R M^-1 D^T (nc, ni)
Z_DQ = 12  # D Q (ni, m): sliding velocities v = D Q zd
Z_MU, Z_L0 = 13, 14  # (1, ni) friction coefficients, static normal forces
N_Z = 15


# ---- right-hand sides ----------------------------------------------------------------------
@njit(cache=True)
def duffing_rhs(t, x, pf, out):
    zeta, w0, gamma, F, w = pf[0], pf[1], pf[2], pf[3], pf[4]
    out[0] = x[1]
    out[1] = F * np.cos(w * t) - 2.0 * zeta * w0 * x[1] - w0 * w0 * x[0] - gamma * x[0] ** 3


@njit(cache=True)
def duffing_jac(t, x, pf, J):
    zeta, w0, gamma = pf[0], pf[1], pf[2]
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0] = -w0 * w0 - 3.0 * gamma * x[0] ** 2
    J[1, 1] = -2.0 * zeta * w0


@njit(cache=True)
def _frame_core(t, x, P, Z, want_jac, out, J):
    """Seed eqs (25)-(27) on the manifold for the smooth laws ("none", "arctan").

    ``M qdd = h + R^T lam - D^T diag(mu s) L`` with ``R qdd = 0`` (R Q = 0: the Baumgarte
    terms vanish), ``L = lam`` (or the static normal forces when frozen):
    ``G lam = r``, ``G = R M^-1 R^T - [R M^-1 D^T diag(mu s)]`` (bracket only when not frozen),
    ``r = -R a0 (+ R M^-1 D^T diag(mu s) L0 when frozen)``, ``zdd = Q^T qdd``.
    The Jacobian differentiates these formulas (``dlam = G^-1 (dr - dG lam)``).
    """
    m = Z[Z_KZ].shape[0]
    nc = Z[Z_G0].shape[0]
    ni = Z[Z_DQ].shape[0]
    ip = P[ks.I_IPAR]
    fp = P[ks.I_FPAR]
    law = ip[ks.K_LAW]
    frozen = ip[ks.K_FROZEN] == 1
    eps = fp[ks.F_EPS]
    uh, uv = ks.ground_accel(t, P)
    uv += fp[ks.F_G]
    z = x[:m]
    zd = x[m:]
    Kz, Cz, QG = Z[Z_KZ], Z[Z_CZ], Z[Z_QG]
    QMiRT, QMiDT = Z[Z_QMIRT], Z[Z_QMIDT]
    RAz, RAv, RG = Z[Z_RAZ], Z[Z_RAV], Z[Z_RG]
    G0, GD, DQ = Z[Z_G0], Z[Z_GD], Z[Z_DQ]
    mu = Z[Z_MU][0]
    L0 = Z[Z_L0][0]
    # friction directions
    s = np.zeros(ni)
    sp = np.zeros(ni)
    if law == ks.LAW_ARCTAN:
        for i in range(ni):
            v = 0.0
            for k in range(m):
                v += DQ[i, k] * zd[k]
            s[i] = (2.0 / np.pi) * np.arctan(eps * v)
            sp[i] = (2.0 / np.pi) * eps / (1.0 + (eps * v) ** 2)
    # constraint system G lam = r  (nc x nc)
    G = np.empty((nc, nc))
    r = np.empty(nc)
    for a in range(nc):
        acc = RG[a, 0] * uh + RG[a, 1] * uv  # -R a0 = R Gamma u + R MiK q + R MiC qd
        for k in range(m):
            acc += RAz[a, k] * z[k] + RAv[a, k] * zd[k]
        r[a] = acc
        for b in range(nc):
            G[a, b] = G0[a, b]
        for i in range(ni):
            if frozen:
                r[a] += GD[a, i] * mu[i] * s[i] * L0[i]
            elif i < nc:
                G[a, i] -= GD[a, i] * mu[i] * s[i]
    lam, ok = ks._small_solve(G, r, nc)
    if not ok:
        return False
    # friction force magnitudes f_i = mu s L
    fr = np.empty(ni)
    for i in range(ni):
        L = L0[i] if frozen else (lam[i] if i < nc else 0.0)
        fr[i] = mu[i] * s[i] * L
    for k in range(m):
        acc = -(QG[k, 0] * uh + QG[k, 1] * uv)
        for j in range(m):
            acc -= Kz[k, j] * z[j] + Cz[k, j] * zd[j]
        for a in range(nc):
            acc += QMiRT[k, a] * lam[a]
        for i in range(ni):
            acc -= QMiDT[k, i] * fr[i]
        out[k] = zd[k]
        out[m + k] = acc
    if not want_jac:
        return True
    # d zdd = -Kz dz - Cz dzd + QMiRT dlam - QMiDT (diag(mu s) dL + diag(mu L s') DQ dzd)
    # dlam = G^-1 (dr - dG lam), dr = RAz dz + RAv dzd (+ GD diag(mu L0 s') DQ dzd frozen),
    # dG lam = -GD diag(mu lam s') DQ dzd (not frozen)
    Glu = G.copy()
    gpiv = np.zeros(nc, dtype=np.int64)
    if not lu_factor(Glu, gpiv):
        return False
    cfr = np.empty(ni)  # d f_i / d v_i at fixed L
    for i in range(ni):
        L = L0[i] if frozen else (lam[i] if i < nc else 0.0)
        cfr[i] = mu[i] * L * sp[i]
    # dr/dx (nc, 2m), then dlam/dx = G^-1 drx
    drx = np.zeros((nc, 2 * m))
    for a in range(nc):
        for k in range(m):
            drx[a, k] = RAz[a, k]
            drx[a, m + k] = RAv[a, k]
        for i in range(ni):
            g = GD[a, i] * cfr[i]
            if g != 0.0:
                for k in range(m):
                    drx[a, m + k] += g * DQ[i, k]
    lu_solve(Glu, gpiv, drx)
    dlam = drx  # (nc, 2m)
    # effective B = QMiRT - QMiDT diag(mu s) (on lam, not frozen)
    J[:, :] = 0.0
    for k in range(m):
        J[k, m + k] = 1.0
    for k in range(m):
        for j in range(m):
            J[m + k, j] = -Kz[k, j]
            J[m + k, m + j] = -Cz[k, j]
        for a in range(nc):
            b = QMiRT[k, a]
            if not frozen and a < ni:
                b -= QMiDT[k, a] * mu[a] * s[a]
            if b != 0.0:
                for j in range(2 * m):
                    J[m + k, j] += b * dlam[a, j]
        for i in range(ni):
            g = QMiDT[k, i] * cfr[i]
            if g != 0.0:
                for j in range(m):
                    J[m + k, m + j] -= g * DQ[i, j]
    return True


@njit(cache=True)
def f_eval(prob, t, x, P, Z, pf, out):
    """Right-hand side of problem ``prob`` on its state ``x``; returns False on failure."""
    if prob == PROB_FRAME:
        return _frame_core(t, x, P, Z, False, out, out.reshape((1, -1)))
    duffing_rhs(t, x, pf, out)
    return True


@njit(cache=True)
def j_eval(prob, t, x, P, Z, pf, F, J):
    """Right-hand side ``F`` and Jacobian ``J = dF/dx`` of problem ``prob``; returns ok."""
    if prob == PROB_FRAME:
        return _frame_core(t, x, P, Z, True, F, J)
    duffing_rhs(t, x, pf, F)
    duffing_jac(t, x, pf, J)
    return True


# ---- small dense LU (partial pivoting) -----------------------------------------------------
@njit(cache=True)
def lu_factor(A, piv):
    """In-place LU of A (d x d) with row pivots ``piv``; returns False if singular."""
    d = A.shape[0]
    scale = 0.0
    for i in range(d):
        for j in range(d):
            scale = max(scale, abs(A[i, j]))
    for k in range(d):
        p = k
        big = abs(A[k, k])
        for i in range(k + 1, d):
            if abs(A[i, k]) > big:
                big = abs(A[i, k])
                p = i
        piv[k] = p
        if big <= 1e-300 or big <= 1e-15 * scale:
            return False
        if p != k:
            for j in range(d):
                tmp = A[k, j]
                A[k, j] = A[p, j]
                A[p, j] = tmp
        inv = 1.0 / A[k, k]
        for i in range(k + 1, d):
            A[i, k] *= inv
            f = A[i, k]
            if f != 0.0:
                for j in range(k + 1, d):
                    A[i, j] -= f * A[k, j]
    return True


@njit(cache=True)
def lu_solve(LU, piv, B):
    """Solve in place LU X = B for B of shape (d, k)."""
    d = LU.shape[0]
    k = B.shape[1]
    for i in range(d):
        p = piv[i]
        if p != i:
            for c in range(k):
                tmp = B[i, c]
                B[i, c] = B[p, c]
                B[p, c] = tmp
    for i in range(d):
        for j in range(i):
            f = LU[i, j]
            if f != 0.0:
                for c in range(k):
                    B[i, c] -= f * B[j, c]
    for i in range(d - 1, -1, -1):
        for j in range(i + 1, d):
            f = LU[i, j]
            if f != 0.0:
                for c in range(k):
                    B[i, c] -= f * B[j, c]
        inv = 1.0 / LU[i, i]
        for c in range(k):
            B[i, c] *= inv


@njit(cache=True)
def _gemm_acc(C, A, B, alpha):
    """C += alpha A B for square matrices (plain loops: small, and quick to compile)."""
    d = A.shape[0]
    for i in range(d):
        for k in range(d):
            a = alpha * A[i, k]
            if a != 0.0:
                for j in range(B.shape[1]):
                    C[i, j] += a * B[k, j]


@njit(cache=True)
def _iteration_matrix(J, hg, LU, piv):
    """LU of the scaled iteration matrix Dr (I - hg J) Dc, Dr = diag(1, hg), Dc = diag(1, 1/hg).

    For a mechanical state [positions, velocities] the scaled matrix is
    [[I, -I], [hg^2 K, I + hg C]]-like: well conditioned where the unscaled one (stiff
    boundary modes, K ~ 1e10) has a condition number ~ 1e12 that spoils the derivatives.
    """
    d = J.shape[0]
    half = d // 2
    for i in range(d):
        ri = hg if i >= half else 1.0
        for j in range(d):
            cj = 1.0 / hg if j >= half else 1.0
            LU[i, j] = -hg * J[i, j] * ri * cj
        LU[i, i] += 1.0  # ri * cj = 1 on the diagonal
    return lu_factor(LU, piv)


@njit(cache=True)
def _solve_scaled(LU, piv, B, hg):
    """Solve (I - hg J) X = B in place with the scaled factors of :func:`_iteration_matrix`."""
    d = B.shape[0]
    half = d // 2
    for i in range(half, d):
        for k in range(B.shape[1]):
            B[i, k] *= hg
    lu_solve(LU, piv, B)
    for i in range(half, d):
        for k in range(B.shape[1]):
            B[i, k] /= hg


# ---- one step and the period map ----------------------------------------------------------
@njit(cache=True)
def _block_scales(x, Y, half, rtol, atol):
    """Tolerance per block (positions, velocities): atol + rtol * max(|x|, |Y|) in the block.

    Fixed during a stage solve, so the line-search merit is one function of Y.
    """
    ymz = 0.0
    ymv = 0.0
    for k in range(Y.shape[0]):
        a = max(abs(x[k]), abs(Y[k]))
        if k < half:
            ymz = max(ymz, a)
        else:
            ymv = max(ymv, a)
    return atol + rtol * ymz, atol + rtol * ymv


@njit(cache=True)
def _block_err(v, half, sz, sv):
    """Max-norm of ``v`` in units of the block tolerances."""
    e = 0.0
    for k in range(v.shape[0]):
        e = max(e, abs(v[k]) / (sz if k < half else sv))
    return e


@njit(cache=True)
def _res_norm(res, half, sz, sv):
    """Weighted 2-norm of a stage residual (line-search merit)."""
    acc = 0.0
    for k in range(res.shape[0]):
        e = res[k, 0] / (sz if k < half else sv)
        acc += e * e
    return np.sqrt(acc)


@njit(cache=True)
def dirk_step(
    prob,
    t,
    h,
    hT,
    x,
    S,
    w,
    want_sens,
    P,
    Z,
    pf,
    A,
    c,
    rtol,
    atol,
    J,
    LU,
    piv,
    hg_lu,
    Fprev,
    xn,
    Sn,
    wn,
):
    """One SDIRK step of size ``h`` from (t, x) into ``xn`` (and its derivatives Sn, wn).

    ``J``/``LU``/``piv`` hold the latest Jacobian and the factors of the iteration matrix for
    ``hg_lu[0]``; they are updated in place. ``hT = dh/dT``. Stage Newton: damped (Armijo
    backtracking on the weighted residual), the iteration matrix refreshed whenever the
    contraction is slow. Returns (status, n_fev).
    """
    d = x.shape[0]
    half = d // 2
    s = c.shape[0]
    gam = A[0, 0]
    hg = h * gam
    nfev = 0
    if hg_lu[0] != hg:
        if not _iteration_matrix(J, hg, LU, piv):
            return STATUS_SINGULAR, nfev
        hg_lu[0] = hg
    Fs = np.zeros((s, d))
    if want_sens:
        SY = np.zeros((s, d, d))
        Js = np.zeros((s, d, d))
    else:
        SY = np.zeros((1, 1, 1))
        Js = np.zeros((1, 1, 1))
    wY = np.zeros((s, d))
    Y = np.empty(d)
    Yt = np.empty(d)
    Fi = np.empty(d)
    r = np.empty(d)
    res = np.empty((d, 1))
    rest = np.empty((d, 1))
    for i in range(s):
        ti = t + c[i] * h
        for k in range(d):
            acc = 0.0
            for j in range(i):
                acc += A[i, j] * Fs[j, k]
            r[k] = x[k] + h * acc
            Y[k] = x[k] + c[i] * h * Fprev[k]  # explicit predictor
        if not f_eval(prob, ti, Y, P, Z, pf, Fi):
            return STATUS_SINGULAR, nfev
        nfev += 1
        for k in range(d):
            res[k, 0] = -(Y[k] - r[k] - hg * Fi[k])
        sz, sv = _block_scales(x, Y, half, rtol, atol)
        rnorm = _res_norm(res, half, sz, sv)
        converged = False
        err_old = 1e300
        for it in range(STAGE_MAXIT):
            dY = res.copy()
            _solve_scaled(LU, piv, dY, hg)
            err = _block_err(dY[:, 0], half, sz, sv)
            if not np.isfinite(err):
                return STATUS_NONFINITE, nfev
            theta = err / err_old
            if (
                err <= 1.0
                or (it > 0 and theta < 1.0 and err * theta / (1.0 - theta) <= 1.0)
                or (it > 1 and theta > STAGE_SLOW and err <= STAGE_STAGNATION)
            ):
                for k in range(d):
                    Y[k] += dY[k, 0]
                converged = True
                break
            # damped update far from the solution: backtrack on the weighted residual (close
            # to it the residual is at its round-off floor and the full step is taken)
            alpha = 1.0
            for _ in range(STAGE_HALVINGS):
                for k in range(d):
                    Yt[k] = Y[k] + alpha * dY[k, 0]
                ok = f_eval(prob, ti, Yt, P, Z, pf, Fi)
                nfev += 1
                for k in range(d):
                    rest[k, 0] = -(Yt[k] - r[k] - hg * Fi[k])
                rt = _res_norm(rest, half, sz, sv)
                if ok and (rt < rnorm or err * alpha <= STAGE_FULL_STEP):
                    break
                alpha *= 0.5
            Y[:] = Yt
            res[:, :] = rest
            rnorm = rt
            if alpha < 1.0 or (it > 0 and theta > STAGE_SLOW):
                j_eval(prob, ti, Y, P, Z, pf, Fi, J)
                if not _iteration_matrix(J, hg, LU, piv):
                    return STATUS_SINGULAR, nfev
            err_old = err * alpha
        if not converged:
            return STATUS_STAGE, nfev
        # converged stage: slope and Jacobian there (the exact derivative needs them; they
        # also give the iteration matrix of the next stage)
        if not j_eval(prob, ti, Y, P, Z, pf, Fi, J):
            return STATUS_SINGULAR, nfev
        nfev += 1
        if not _iteration_matrix(J, hg, LU, piv):
            return STATUS_SINGULAR, nfev
        Fs[i] = Fi
        if want_sens:
            Js[i] = J
            Rm = S.copy()
            rw = np.empty((d, 1))
            for k in range(d):
                acc = 0.0
                for j in range(i + 1):
                    acc += A[i, j] * Fs[j, k]
                rw[k, 0] = w[k] + hT * acc
            for j in range(i):
                if A[i, j] != 0.0:
                    _gemm_acc(Rm, Js[j], SY[j], h * A[i, j])
                    haj = h * A[i, j]
                    for k in range(d):
                        acc = 0.0
                        for l in range(d):
                            acc += Js[j, k, l] * wY[j, l]
                        rw[k, 0] += haj * acc
            _solve_scaled(LU, piv, Rm, hg)
            _solve_scaled(LU, piv, rw, hg)
            SY[i] = Rm
            wY[i] = rw[:, 0]
    Fprev[:] = Fs[s - 1]
    xn[:] = Y  # stiffly accurate: x_{n+1} = Y_s
    if want_sens:
        Sn[:, :] = SY[s - 1]
        wn[:] = wY[s - 1]
    return STATUS_OK, nfev


@njit(cache=True)
def period_map(prob, x0, T, N, P, Z, pf, A, c, want_sens, store, rtol, atol):
    """Integrate one period ``T`` in ``N`` SDIRK steps from ``x0`` (at t = 0).

    A step whose stages do not converge is retried once with a fresh Jacobian, then as 2, 4,
    ... ``MAX_SUBSTEPS`` substeps (the derivative is that of the substepped map). Returns
    (xT, S, w, X, status, n_fev, n_sub): S = d xT / d x0 (zeros(1, 1) unless ``want_sens``),
    w = d xT / d T, X the states at the N + 1 step points (when ``store``), n_sub the number of
    steps that needed substeps.
    """
    d = x0.shape[0]
    h = T / N
    x = x0.copy()
    S = np.eye(d) if want_sens else np.zeros((1, 1))
    w = np.zeros(d)
    xs = x.copy()
    Ss = S.copy()
    ws = w.copy()
    xn = np.empty(d)
    Sn = S.copy()
    wn = np.zeros(d)
    X = np.zeros((N + 1, d)) if store else np.zeros((1, d))
    if store:
        X[0] = x
    J = np.zeros((d, d))
    LU = np.zeros((d, d))
    piv = np.zeros(d, dtype=np.int64)
    hg_lu = np.zeros(1)
    Fprev = np.zeros(d)
    Fsave = np.zeros(d)
    if not j_eval(prob, 0.0, x, P, Z, pf, Fprev, J):
        return x, S, w, X, STATUS_SINGULAR, 1, 0
    n_fev = 1
    n_sub = 0
    for n in range(N):
        tn = n * h
        Fsave[:] = Fprev
        ksub = 1
        refreshed = False
        while True:
            # one attempt: ksub substeps of h / ksub from (tn, x)
            hs = h / ksub
            xs[:] = x
            if want_sens:
                Ss[:, :] = S
                ws[:] = w
            status = STATUS_OK
            for j in range(ksub):
                status, nf = dirk_step(
                    prob,
                    tn + j * hs,
                    hs,
                    hs / T,
                    xs,
                    Ss,
                    ws,
                    want_sens,
                    P,
                    Z,
                    pf,
                    A,
                    c,
                    rtol,
                    atol,
                    J,
                    LU,
                    piv,
                    hg_lu,
                    Fprev,
                    xn,
                    Sn,
                    wn,
                )
                n_fev += nf
                if status != STATUS_OK:
                    break
                xs[:] = xn
                if want_sens:
                    Ss[:, :] = Sn
                    ws[:] = wn
            if status == STATUS_OK or status == STATUS_SINGULAR:
                break
            Fprev[:] = Fsave
            if not refreshed:
                # retry with a fresh Jacobian at x
                refreshed = True
                j_eval(prob, tn, x, P, Z, pf, Fprev, J)
                hg_lu[0] = 0.0
                continue
            ksub *= 2
            if ksub > MAX_SUBSTEPS:
                break
            if ksub == 2:
                n_sub += 1
        if status != STATUS_OK:
            return x, S, w, X, status, n_fev, n_sub
        x[:] = xs
        if want_sens:
            S[:, :] = Ss
            w[:] = ws
        if store:
            X[n + 1] = x
    return x, S, w, X, STATUS_OK, n_fev, n_sub
