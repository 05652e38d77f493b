"""Numba kernels for periodic solutions: fixed-step SDIRK period map with its exact derivative.

The problems (right-hand sides and Jacobians) are in :mod:`nsdyn.periodic._kproblems`.

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

from nsdyn import _kaddress as ka
from nsdyn import _kborrow as kb
from nsdyn._klinalg import copy_mat, copy_vec, lu_factor, lu_solve_columns
from nsdyn.periodic._kproblems import (  # noqa: F401  (problem ids and Z layout re-exported)
    LU_RTOL,
    N_Z,
    PROB_DUFFING,
    PROB_FRAME,
    Z_CZ,
    Z_DQ,
    Z_G0,
    Z_GD,
    Z_KZ,
    Z_L0,
    Z_MU,
    Z_Q,
    Z_QG,
    Z_QMIDT,
    Z_QMIRT,
    Z_QT,
    Z_RAV,
    Z_RAZ,
    Z_RG,
    f_eval,
    frame_flat,
    j_eval,
    pack_frame,
)

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
LAGGED_TOL = 0.1  # stage tolerance factor of a period without sensitivities (see dirk_step)


@njit(cache=True, error_model="numpy")
def _jac_prod_acc(C, J, B, alpha):
    """C += alpha J B for a Jacobian ``J = [[0, I], [Jz, Jv]]`` of a state [z, zd] (every
    problem's, see :func:`_iteration_matrix`): the top rows are B's bottom rows, only the
    bottom half is a product (half the flops of a full one; plain loops, the column loop
    innermost over contiguous rows)."""
    d = J.shape[0]
    m = d // 2
    k = B.shape[1]
    for i in range(m):
        for c in range(k):
            C[i, c] += alpha * B[m + i, c]
    for i in range(m, d):
        for l in range(d):
            a = alpha * J[i, l]
            if a != 0.0:
                for c in range(k):
                    C[i, c] += a * B[l, c]


@njit(cache=True, error_model="numpy")
def _iteration_matrix(J, hg, LU, piv):
    """Factors of the iteration matrix ``I - hg J`` through its Schur complement.

    Every problem's state is [positions, velocities] (``x = [z, zd]``), so
    ``J = [[0, I], [Jz, Jv]]`` and ``(I - hg J) [x1; x2] = [b1; b2]`` gives ``x1 = b1 + hg x2``
    and ``S x2 = b2 + hg Jz b1`` with ``S = I - hg Jv - hg^2 Jz`` (m x m, m = d/2). Only S is
    factored (the "effective stiffness" of a Newmark-type step): 8x fewer flops than the
    d x d matrix, whose LU was about a third of a step. ``LU`` is (m, d): S's factors in
    ``LU[:, :m]``, ``hg Jz`` in ``LU[:, m:]``.

    Accuracy (tests/periodic/test_iteration_matrix.py): round-off in each block's norm, which
    is what the stage Newton and the shooting weights measure, also with stiff boundary modes
    (K ~ 1e10, where ``I - hg J`` has a condition number ~ 1e12); only a stiff coordinate's
    tiny displacement ``x1 = b1 + hg x2`` is a difference of large numbers, good
    componentwise to ``eps |b1| / |x1|``.
    """
    m = LU.shape[0]
    for i in range(m):
        for j in range(m):
            jz = J[m + i, j]
            LU[i, j] = -hg * J[m + i, m + j] - hg * hg * jz
            LU[i, m + j] = hg * jz
        LU[i, i] += 1.0
    return lu_factor(LU, piv, LU_RTOL)


@njit(cache=True, error_model="numpy")
def _solve_scaled(LU, piv, B, hg):
    """Solve ``(I - hg J) X = B`` in place with the factors of :func:`_iteration_matrix`."""
    m = LU.shape[0]
    k = B.shape[1]
    if k == 1:
        for i in range(m):
            acc = 0.0
            for j in range(m):
                acc += LU[i, m + j] * B[j, 0]
            B[m + i, 0] += acc
    else:  # a block (the monodromy's columns): the column loop innermost, over contiguous rows
        for i in range(m):
            for j in range(m):
                a = LU[i, m + j]
                if a != 0.0:
                    for c in range(k):
                        B[m + i, c] += a * B[j, c]
    lu_solve_columns(LU, piv, B[m:])
    for i in range(m):
        for c in range(k):
            B[i, c] += hg * B[m + i, c]


# ---- one step and the period map ----------------------------------------------------------
@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
def _block_err(v, half, sz, sv):
    """Max-norm of ``v`` in units of the block tolerances."""
    e = 0.0
    for k in range(v.shape[0]):
        e = max(e, abs(v[k]) / (sz if k < half else sv))
    return e


@njit(cache=True, error_model="numpy")
def _res_norm(res, half, sz, sv):
    """Weighted 2-norm of a stage residual (line-search merit)."""
    acc = 0.0
    for k in range(res.shape[0]):
        e = res[k, 0] / (sz if k < half else sv)
        acc += e * e
    return np.sqrt(acc)


@ka.compiled_uncounted
def dirk_step(t, h, hT, x, S, w, want_sens, problem, method, work, tmp, out, K):
    """One SDIRK step of size ``h`` from (t, x) into ``out = (xn, Sn, wn)`` (the state and its
    derivatives). ``problem = (prob, pf)`` (``pf``: a frame's flat array, see
    :func:`nsdyn.periodic._kproblems.pack_frame`), ``method = (A, c, rtol, atol)``,
    ``work = (J, LU, piv, hg_lu, Fprev)``, ``tmp`` the step's scratch (:func:`step_scratch`).

    ``J``/``LU``/``piv`` hold the latest Jacobian and the factors of the iteration matrix for
    ``hg_lu[0]``; they are updated in place. ``hT = dh/dT``. Stage Newton: damped (Armijo
    backtracking on the weighted residual), the iteration matrix refreshed whenever the
    contraction is slow. Returns (status, n_fev). ``K``: see :func:`period_map`.
    """
    prob, pf = problem
    A, c, rtol, atol = method
    J, LU, piv, hg_lu, Fprev = work
    xn, Sn, wn = out
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
    # stage slopes, sensitivities and Jacobians: row i is written before a later stage reads it
    Fs, SY, Js, wY, Y, Yt, Fi, r, res, rest, dY, Rm, rw = tmp
    for i in range(s):
        ti = t + c[i] * h
        for k in range(d):
            acc = 0.0
            for j in range(i):
                acc += A[i, j] * Fs[j, k]
            r[k] = x[k] + h * acc
            Y[k] = x[k] + c[i] * h * Fprev[k]  # explicit predictor
        if not ka.call(K, "periodic.feval", (prob, ti, Y, pf, Fi), None):
            return STATUS_SINGULAR, nfev
        nfev += 1
        for k in range(d):
            res[k, 0] = -(Y[k] - r[k] - hg * Fi[k])
        sz, sv = _block_scales(x, Y, half, rtol, atol)
        if not want_sens:  # a lagged matrix contracts linearly: stop further below tolerance
            sz *= LAGGED_TOL
            sv *= LAGGED_TOL
        rnorm = _res_norm(res, half, sz, sv)
        converged = False
        err_old = 1e300
        for it in range(STAGE_MAXIT):
            copy_mat(dY, res)
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
                ok = ka.call(K, "periodic.feval", (prob, ti, Yt, pf, Fi), None)
                nfev += 1
                for k in range(d):
                    rest[k, 0] = -(Yt[k] - r[k] - hg * Fi[k])
                rt = _res_norm(rest, half, sz, sv)
                if ok and (rt < rnorm or err * alpha <= STAGE_FULL_STEP):
                    break
                alpha *= 0.5
            copy_vec(Y, Yt)
            copy_mat(res, rest)
            rnorm = rt
            if alpha < 1.0 or (it > 0 and theta > STAGE_SLOW):
                ka.call(K, "periodic.jeval", (prob, ti, Y, pf, Fi, J), None)
                if not _iteration_matrix(J, hg, LU, piv):
                    return STATUS_SINGULAR, nfev
            err_old = err * alpha
        if not converged:
            return STATUS_STAGE, nfev
        # converged stage. With the derivative: slope and Jacobian there (the exact derivative
        # needs them; they also give the next stage's iteration matrix). Without: the slope
        # from the stage equation, F_i = (Y_i - r_i) / (h gamma), no evaluation (the form
        # Hairer & Wanner IV.8 recommend for stiff problems), and the iteration matrix lags,
        # refreshed only when the contraction is slow
        if want_sens:
            if not ka.call(K, "periodic.jeval", (prob, ti, Y, pf, Fi, J), None):
                return STATUS_SINGULAR, nfev
            nfev += 1
            if not _iteration_matrix(J, hg, LU, piv):
                return STATUS_SINGULAR, nfev
        else:
            for k in range(d):
                Fi[k] = (Y[k] - r[k]) / hg
        copy_vec(Fs[i], Fi)
        if want_sens:
            copy_mat(Js[i], J)
            copy_mat(Rm, S)
            for k in range(d):
                acc = 0.0
                for j in range(i + 1):
                    acc += A[i, j] * Fs[j, k]
                rw[k, 0] = w[k] + hT * acc
            for j in range(i):
                if A[i, j] != 0.0:
                    _jac_prod_acc(Rm, Js[j], SY[j], h * A[i, j])
                    _jac_prod_acc(rw, Js[j], wY[j].reshape((d, 1)), h * A[i, j])
            _solve_scaled(LU, piv, Rm, hg)
            _solve_scaled(LU, piv, rw, hg)
            copy_mat(SY[i], Rm)
            copy_vec(wY[i], rw[:, 0])
    copy_vec(Fprev, Fs[s - 1])
    copy_vec(xn, Y)  # stiffly accurate: x_{n+1} = Y_s
    if want_sens:
        copy_mat(Sn, SY[s - 1])
        copy_vec(wn, wY[s - 1])
    return STATUS_OK, nfev


# the period map's call of its step (:mod:`nsdyn._kaddress`): index 2 of its K
ka.slot("periodic.step", 2, dirk_step)


@njit(cache=True, error_model="numpy")
def step_scratch(s, d, want_sens):
    """Scratch of :func:`dirk_step` for ``s`` stages and ``d`` states (allocated once per
    period, not once per step): Fs, SY, Js, wY, Y, Yt, Fi, r, res, rest, dY, Rm, rw."""
    ds = d if want_sens else 1
    return (
        np.zeros((s, d)), np.zeros((s, ds, ds)), np.zeros((s, ds, ds)), np.zeros((s, d)),
        np.zeros(d), np.zeros(d), np.zeros(d), np.zeros(d), np.zeros((d, 1)), np.zeros((d, 1)),
        np.zeros((d, 1)), np.zeros((ds, ds)), np.zeros((d, 1)),
    )  # fmt: skip


@njit(cache=True, error_model="numpy")
def period_map(prob, x0, T, N, pf, A, c, want_sens, store, rtol, atol, K):
    """Integrate one period ``T`` in ``N`` SDIRK steps from ``x0`` (at t = 0).

    The step (:func:`dirk_step`), the Jacobian (:func:`nsdyn.periodic._kproblems.j_eval`,
    ~4 s of a first compilation) and the right-hand side
    (:func:`~nsdyn.periodic._kproblems.f_eval`, which the step calls) are called through
    :func:`nsdyn._kaddress.call` as ``"periodic.step"``, ``"periodic.jeval"`` and
    ``"periodic.feval"``: directly (``K`` None) or by their addresses (``K`` from
    :func:`nsdyn.periodic.problem.periodic_calls`). Linked, numba would optimise and
    translate each callee's code once more in every caller (the step's in this kernel, the
    frame's right-hand side in both); by address each compiles once, the right-hand side and
    the Jacobian beside this kernel and the step in a second process.

    A step whose stages do not converge is retried once with a fresh Jacobian, then as 2, 4,
    ... ``MAX_SUBSTEPS`` substeps (the derivative is that of the substepped map). Returns
    (xT, S, w, X, status, n_fev, n_sub): S = d xT / d x0 (zeros(1, 1) unless ``want_sens``),
    w = d xT / d T, X the states at the N + 1 step points (when ``store``), n_sub the number of
    steps that needed substeps.
    """
    d = x0.shape[0]
    h = T / N
    # the returned arrays (owned) ...
    x_own = x0.copy()
    S_own = np.eye(d) if want_sens else np.zeros((1, 1))
    w_own = np.zeros(d)
    X_own = np.zeros((N + 1, d)) if store else np.zeros((1, d))
    # ... and the scratch, all used through borrowed views (nsdyn._kborrow): no atomic
    # reference counts for the ~15 arrays each step passes on
    scratch = (
        x_own.copy(), S_own.copy(), w_own.copy(), np.empty(d), S_own.copy(), np.zeros(d),
        np.zeros((d, d)), np.zeros((d // 2, d)), np.zeros(d // 2, dtype=np.int64),
        np.zeros(1), np.zeros(d), np.zeros(d),
    )  # fmt: skip
    tmp_own = step_scratch(c.shape[0], d, want_sens)
    tmp = kb.borrowed(tmp_own)
    x, S, w, X = kb.borrowed((x_own, S_own, w_own, X_own))
    xs, Ss, ws, xn, Sn, wn, J, LU, piv, hg_lu, Fprev, Fsave = kb.borrowed(scratch)
    pf, A, c = kb.borrowed((pf, A, c))
    if store:
        copy_vec(X[0], x)
    problem = (prob, pf)
    method = (A, c, rtol, atol)
    work = (J, LU, piv, hg_lu, Fprev)
    if not ka.call(K, "periodic.jeval", (prob, 0.0, x, pf, Fprev, J), None):
        return x_own, S_own, w_own, X_own, STATUS_SINGULAR, 1, 0
    n_fev = 1
    n_sub = 0
    for n in range(N):
        tn = n * h
        copy_vec(Fsave, Fprev)
        ksub = 1
        refreshed = False
        while True:
            # one attempt: ksub substeps of h / ksub from (tn, x)
            hs = h / ksub
            copy_vec(xs, x)
            if want_sens:
                copy_mat(Ss, S)
                copy_vec(ws, w)
            status = STATUS_OK
            for j in range(ksub):
                status, nf = ka.call(K, "periodic.step", (
                    tn + j * hs, hs, hs / T, xs, Ss, ws, want_sens, problem, method, work, tmp,
                    (xn, Sn, wn), K,
                ), None)  # fmt: skip
                n_fev += nf
                if status != STATUS_OK:
                    break
                copy_vec(xs, xn)
                if want_sens:
                    copy_mat(Ss, Sn)
                    copy_vec(ws, wn)
            if status == STATUS_OK or status == STATUS_SINGULAR:
                break
            copy_vec(Fprev, Fsave)
            if not refreshed:
                # retry with a fresh Jacobian at x
                refreshed = True
                ka.call(K, "periodic.jeval", (prob, tn, x, pf, Fprev, J), None)
                hg_lu[0] = 0.0
                continue
            ksub *= 2
            if ksub > MAX_SUBSTEPS:
                break
            if ksub == 2:
                n_sub += 1
        if status != STATUS_OK:
            return x_own, S_own, w_own, X_own, status, n_fev, n_sub
        copy_vec(x, xs)
        if want_sens:
            copy_mat(S, Ss)
            copy_vec(w, ws)
        if store:
            copy_vec(X[n + 1], x)
    kb.alive((scratch, tmp_own))
    return x_own, S_own, w_own, X_own, STATUS_OK, n_fev, n_sub
