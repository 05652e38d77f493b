"""Radau IIA (order 5) with the analytic Jacobian, whole time loop in numba.

Collocation at c = ((4 - sqrt 6)/10, (4 + sqrt 6)/10, 1) for ``xd = f(t, x)``::

    Z_i = h sum_j a_ij f(t + c_j h, x + Z_j),   x(t + h) = x + Z_3     (i, j = 1..3)

Hairer & Wanner, *Solving ODEs II*, sec. IV.8 (RADAU5); the step logic follows scipy's
``Radau``: simplified Newton on the collocation system with the eigen-split of the Radau
matrix (one real and one complex LU of ``eig/h I - J``), Jacobian and LU reused across steps
while the Newton iteration contracts fast, the embedded 3rd-order error estimate filtered by
``(eig_real/h I - J)^-1``, and the cubic collocation polynomial as dense output.

Why Radau IIA for this problem: it is L-stable (the kHz undamped Craig-Bampton boundary modes
and the stiff arctan slope mu lam (2/pi) eps, eps up to 1e5, are damped in one step instead of
being resolved), of order 5 on the slow physics, and stiffly accurate (the step end is the
last stage, so no stiff error is propagated from the stages).

The step is exposed as :func:`radau_step` (one accepted step with retries, state in ``ctl``)
so the event-driven switch integrator (:mod:`nsdyn.solve._kevent`) drives the same stepper.
"""

import numpy as np
from numba import njit

from nsdyn.models.isolated import _kernel as ks
from nsdyn.solve import _kcommon as ki

S6 = 6.0**0.5
C = np.array([(4.0 - S6) / 10.0, (4.0 + S6) / 10.0, 1.0])
E = np.array([-13.0 - 7.0 * S6, -13.0 + 7.0 * S6, -1.0]) / 3.0
# eigenvalues of the inverse of the Radau IIA coefficient matrix (one real, one complex pair);
# the Newton matrices of the eigen-split are (eig/h) I - J
EIG_REAL = 3.0 + 3.0 ** (2.0 / 3.0) - 3.0 ** (1.0 / 3.0)
EIG_COMPLEX = complex(
    3.0 + 0.5 * (3.0 ** (1.0 / 3.0) - 3.0 ** (2.0 / 3.0)),
    -0.5 * (3.0 ** (5.0 / 6.0) + 3.0 ** (7.0 / 6.0)),
)
MU_REAL = EIG_REAL  # former name, still imported by the benchmarks
T = np.array(
    [
        [0.09443876248897524, -0.14125529502095421, 0.03002919410514742],
        [0.25021312296533332, 0.20412935229379994, -0.38294211275726192],
        [1.0, 1.0, 0.0],
    ]
)
TI = np.array(
    [
        [4.17871859155190428, 0.32768282076106237, 0.52337644549944951],
        [-4.17871859155190428, -0.32768282076106237, 0.47662355450055044],
        [0.50287263494578682, -2.57192694985560522, 0.59603920482822492],
    ]
)
# dense output: y(t + x h) = y + sum_k (Z^T PD)[:, k] x^(k+1)
PD = np.array(
    [
        [13.0 / 3.0 + 7.0 * S6 / 3.0, -23.0 / 3.0 - 22.0 * S6 / 3.0, 10.0 / 3.0 + 5.0 * S6],
        [13.0 / 3.0 - 7.0 * S6 / 3.0, -23.0 / 3.0 + 22.0 * S6 / 3.0, 10.0 / 3.0 - 5.0 * S6],
        [1.0 / 3.0, -8.0 / 3.0, 10.0 / 3.0],
    ]
)

NEWTON_MAXITER = 6  # simplified-Newton iterations per attempt
MIN_FACTOR = 0.2  # smallest step shrink per rejection
MAX_FACTOR = 10.0  # largest step growth per step
JAC_RATE = 1e-3  # recompute J after a step whose Newton needed > 2 iterations at this rate
KEEP_STEP = 1.2  # keep h (and the LU factors) when the proposed growth is below this
LU_RTOL = 1e-9  # relative change of h that forces a new LU
NEWTON_FAIL_SHRINK = 0.5  # step shrink when Newton fails with a fresh Jacobian

# ---- stepper state ``ctl`` (float64) -------------------------------------------------------
C_H = 0  # next step size to try
C_HOLD = 1  # previous accepted step (NaN: none) for the predictive controller
C_EOLD = 2  # previous error norm (NaN: none)
C_LUH = 3  # step size the LU factors belong to (0: invalid)
C_CURJ = 4  # 1 if J was evaluated at the current step start
C_HPREV = 5  # step of the dense output in Qd usable for the Newton predictor (0: none)
C_TNEW = 6  # out: end of the accepted step
C_HSTEP = 7  # out: size of the accepted step
C_NTOL = 8  # Newton tolerance
C_FACCON = 9  # rate/(1 - rate) of the last Newton iteration (RADAU5's FACCON)
N_CTL = 10


@njit(cache=True)
def workspace(n2, nc, ni):
    """Preallocated arrays of the stepper (one set per solve)."""
    n = n2 // 2
    return (
        np.zeros((n2, n2)),  # J
        np.zeros((n, n)),  # LUr: factors of the real Schur complement (see _factor)
        np.zeros(n, dtype=np.int64),  # pr
        np.zeros((n, n), dtype=np.complex128),  # LUc: the complex one
        np.zeros(n, dtype=np.int64),  # pc
        np.zeros((3, n2)),  # Z
        np.zeros((3, n2)),  # Z0
        np.zeros((3, n2)),  # W
        np.zeros((3, n2)),  # F
        np.zeros((3, n2)),  # dW
        np.zeros(n2),  # fr
        np.zeros(n2, dtype=np.complex128),  # fc
        np.zeros(n2),  # ys (stage state, scratch)
        np.zeros(n2),  # scale
        np.zeros(n2),  # err
        np.zeros(n2),  # ynew
        np.zeros(n2),  # fnew
        np.zeros((n2, 3)),  # Qd dense-output coefficients of the last accepted step
        np.zeros(n),  # qdd
        np.zeros(nc),  # lam (at ynew after an accepted step)
        np.zeros(ni),  # tau
        np.zeros(ni, dtype=np.int64),  # modes
    )


@njit(cache=True)
def restart(ctl):
    """Forget the step history (after an event changed the vector field)."""
    ctl[C_HOLD] = np.nan
    ctl[C_EOLD] = np.nan
    ctl[C_LUH] = 0.0
    ctl[C_HPREV] = 0.0
    ctl[C_FACCON] = 1.0


@njit(cache=True)
def new_control(h0, rtol):
    """Fresh stepper state: first step h0, no history, Newton tolerance from rtol."""
    ctl = np.zeros(N_CTL)
    restart(ctl)
    ctl[C_H] = h0
    ctl[C_NTOL] = max(10.0 * 2.220446049250313e-16 / rtol, min(0.03, rtol**0.5))
    return ctl


@njit(cache=True)
def dense(y, Qd, x, out):
    """Collocation polynomial of the last step at ``t_old + x h`` (y = state at t_old)."""
    for i in range(y.shape[0]):
        out[i] = y[i] + x * (Qd[i, 0] + x * (Qd[i, 1] + x * Qd[i, 2]))


@njit(cache=True)
def _factor(h, J, LUr, pr, LUc, pc):
    """LU of the Newton matrices ``g I - J`` (g = eig_real/h and eig_complex/h), reduced to n x n.

    The state is [q, qd], so ``J = [[0, I], [Jq, Jv]]`` and ``(g I - J) [dq; dv] = [r1; r2]``
    gives ``dq = (r1 + dv)/g`` and ``(g I - Jv - Jq/g) dv = r2 + Jq r1/g``: only the n x n
    Schur complement is factored (8x fewer flops than the 2n x 2n matrix).
    """
    n = LUr.shape[0]
    gr = EIG_REAL / h
    gc = EIG_COMPLEX / h
    igr = 1.0 / gr
    igc = 1.0 / gc
    for i in range(n):
        for j in range(n):
            jq = J[n + i, j]
            jv = J[n + i, n + j]
            LUr[i, j] = -jv - jq * igr
            LUc[i, j] = -jv - jq * igc
        LUr[i, i] += gr
        LUc[i, i] += gc
    return ki.lu_factor(LUr, pr) and ki.lu_factor(LUc, pc)


@njit(cache=True)
def _solve(LU, piv, J, g, b):
    """Solve ``(g I - J) x = b`` in place (b of length 2n) with the factors of :func:`_factor`."""
    n = LU.shape[0]
    ig = 1.0 / g
    for i in range(n):
        acc = 0.0 * b[0]
        for j in range(n):
            acc += J[n + i, j] * b[j]
        b[n + i] += acc * ig
    v = b[n:]
    ki.lu_solve(LU, piv, v)
    for i in range(n):
        b[i] = (b[i] + b[n + i]) * ig


@njit(cache=True)
def _error_norm(err, Z, h, LUr, pr, J, luh, y, ynew, atol, rtol):
    """Scaled norm of the embedded error estimate ``(eig_real/h I - J)^-1 (err + E Z / h)``
    (err holds f(t, y) or the filtered estimate of a first try); the estimate is left in err."""
    for j in range(err.shape[0]):
        err[j] += (E[0] * Z[0, j] + E[1] * Z[1, j] + E[2] * Z[2, j]) / h
    _solve(LUr, pr, J, EIG_REAL / luh, err)
    return ki.scaled_rms(err, y, ynew, atol, rtol)


@njit(cache=True)
def _predict_factor(h_abs, h_abs_old, en, en_old):
    if en == 0.0:
        return 1e10
    mult = 1.0
    if np.isfinite(en_old) and np.isfinite(h_abs_old):
        mult = h_abs / h_abs_old * (en_old / en) ** 0.25
    return min(1.0, mult) * en**-0.25


@njit(cache=True)
def _newton(P, t, y, h, ws, ctl, stats):
    """Simplified Newton on the collocation system; Z holds the start guess on entry.

    Convergence test as RADAU5: the error after an update is estimated as
    ``faccon * |dW|`` with ``faccon = rate/(1 - rate)``, carried over from the previous
    step for the first iteration (so a good predictor converges in one iteration); an
    iteration whose rate predicts no convergence within NEWTON_MAXITER stops (scipy).

    Returns (converged, n_iter, rate, nonfinite, singular, dW_norm).
    """
    J, LUr, pr, LUc, pc, Z, Z0, W, F, dW, fr, fc, ys, scale = ws[:14]
    qdd, lam, tau, modes = ws[18:22]
    n2 = y.shape[0]
    mr = EIG_REAL / h
    mc = EIG_COMPLEX / h
    for k in range(3):
        for j in range(n2):
            W[k, j] = TI[k, 0] * Z[0, j] + TI[k, 1] * Z[1, j] + TI[k, 2] * Z[2, j]
    tol = ctl[C_NTOL]
    faccon = max(ctl[C_FACCON], 2.220446049250313e-16) ** 0.8
    dw_old = -1.0
    rate = -1.0
    dw = 0.0
    converged = False
    nonfinite = False
    singular = False
    k = 0
    for k in range(NEWTON_MAXITER):
        for i in range(3):
            for j in range(n2):
                ys[j] = y[j] + Z[i, j]
            ok = ki.feval_inline(t + C[i] * h, ys, P, F[i], qdd, lam, tau, modes)
            if not ok:
                singular = True
        stats[ki.S_NFEV] += 3
        fin = ki.all_finite(F[0]) and ki.all_finite(F[1]) and ki.all_finite(F[2])
        if not fin:
            nonfinite = True
            break
        if singular:
            break
        for j in range(n2):
            fr[j] = TI[0, 0] * F[0, j] + TI[0, 1] * F[1, j] + TI[0, 2] * F[2, j] - mr * W[0, j]
            re = TI[1, 0] * F[0, j] + TI[1, 1] * F[1, j] + TI[1, 2] * F[2, j]
            im = TI[2, 0] * F[0, j] + TI[2, 1] * F[1, j] + TI[2, 2] * F[2, j]
            fc[j] = complex(re, im) - mc * complex(W[1, j], W[2, j])
        _solve(LUr, pr, J, EIG_REAL / ctl[C_LUH], fr)
        _solve(LUc, pc, J, EIG_COMPLEX / ctl[C_LUH], fc)
        s = 0.0
        for j in range(n2):
            dW[0, j] = fr[j]
            dW[1, j] = fc[j].real
            dW[2, j] = fc[j].imag
            s += (fr[j] / scale[j]) ** 2 + (fc[j].real / scale[j]) ** 2
            s += (fc[j].imag / scale[j]) ** 2
        dw = np.sqrt(s / (3 * n2))
        if not np.isfinite(dw):
            nonfinite = True
            break
        if dw_old >= 0.0:
            rate = dw / dw_old
        if rate >= 0.0:
            if rate >= 1.0 or rate ** (NEWTON_MAXITER - k) / (1.0 - rate) * dw > tol:
                break
            faccon = rate / (1.0 - rate)
        for i in range(3):
            for j in range(n2):
                W[i, j] += dW[i, j]
        for i in range(3):
            for j in range(n2):
                Z[i, j] = T[i, 0] * W[0, j] + T[i, 1] * W[1, j] + T[i, 2] * W[2, j]
        if faccon * dw < tol:
            converged = True
            break
        dw_old = dw
    ctl[C_FACCON] = faccon
    return converged, k + 1, rate, nonfinite, singular, dw


@njit(cache=True)
def radau_step(P, t, y, f, t_lim, fixed, atol, rtol, max_step, max_steps, ws, ctl, stats, rinfo):
    """Take one accepted step from (t, y) (f = f(t, y)), retrying with smaller steps.

    On success returns 0 and leaves the new state in ``ws`` (ynew, fnew and lam, tau, modes
    at ynew), the dense output in Qd, the step end in ``ctl[C_TNEW]``. Otherwise returns a
    negative status (ST_*) with ``rinfo`` describing where.
    With ``fixed`` the step is ``ctl[C_H]`` (shortened only to land on ``t_lim``) and a Newton
    failure is reported instead of retried.
    """
    J, LUr, pr, LUc, pc, Z, Z0, W, F, dW, fr, fc, ys, scale, err, ynew, fnew, Qd = ws[:18]
    qdd, lam, tau, modes = ws[18:22]
    n2 = y.shape[0]
    h_abs = ctl[C_H]
    h_abs_old = ctl[C_HOLD]
    en_old = ctl[C_EOLD]
    if not fixed and h_abs > max_step:
        h_abs = max_step
        h_abs_old = np.nan
        en_old = np.nan
    floor = ki.step_floor(t)
    rejected = False
    nonfinite = False
    n_iter = 0
    rate = 0.0
    en = 0.0
    safety = 0.9
    t_new = t
    h = h_abs
    for j in range(n2):
        scale[j] = atol[j] + abs(y[j]) * rtol
    while True:
        rinfo[ki.R_H] = h_abs
        if stats[ki.S_NSTEP] + stats[ki.S_NREJ] >= max_steps:
            return ki.ST_MAX_STEPS
        if h_abs < floor:
            return ki.ST_NONFINITE if nonfinite else ki.ST_STEP_UNDERFLOW
        d = t_lim - t
        if not fixed and h_abs < d < np.inf:
            # equal steps to the next kink: no sliver step before it, and the same h (so the
            # same LU factors) through a run of sample intervals
            h_abs = d / np.ceil(d / h_abs * (1.0 - 1e-9))
        t_new = t + h_abs
        if t_new > t_lim - 1e-9 * h_abs:
            t_new = t_lim
        h = t_new - t
        # Newton start: extrapolated collocation polynomial of the previous step
        hp = ctl[C_HPREV]
        for i in range(3):
            if hp > 0.0:
                x = 1.0 + h * C[i] / hp
                for j in range(n2):
                    Z0[i, j] = (
                        (x - 1.0) * Qd[j, 0]
                        + (x * x - 1.0) * Qd[j, 1]
                        + (x * x * x - 1.0) * Qd[j, 2]
                    )
            else:
                for j in range(n2):
                    Z0[i, j] = 0.0
        converged = False
        singular = False
        dw = 0.0
        while True:
            if abs(ctl[C_LUH] - h) > LU_RTOL * h:
                stats[ki.S_NLU] += 2
                if not _factor(h, J, LUr, pr, LUc, pc):
                    rinfo[ki.R_H] = h
                    return ki.ST_LU_SINGULAR
                ctl[C_LUH] = h
            Z[:, :] = Z0
            converged, n_iter, rate, nf, singular, dw = _newton(P, t, y, h, ws, ctl, stats)
            if nf:
                nonfinite = True
            if converged or ctl[C_CURJ] == 1.0 or nf or singular:
                break
            ki.jeval(t, y, P, J)
            stats[ki.S_NJEV] += 1
            ctl[C_CURJ] = 1.0
            ctl[C_LUH] = 0.0
        if singular and not nonfinite:
            rinfo[ki.R_H] = h
            return ki.ST_SINGULAR
        if not converged:
            stats[ki.S_NREJ] += 1
            if fixed:
                rinfo[ki.R_H] = h
                rinfo[ki.R_RES] = dw
                return ki.ST_NONFINITE if nonfinite else ki.ST_NEWTON
            h_abs *= NEWTON_FAIL_SHRINK
            ctl[C_LUH] = 0.0
            continue
        for j in range(n2):
            ynew[j] = y[j] + Z[2, j]
        if fixed:
            break
        err[:] = f
        en = _error_norm(err, Z, h, LUr, pr, J, ctl[C_LUH], y, ynew, atol, rtol)
        safety = 0.9 * (2 * NEWTON_MAXITER + 1) / (2 * NEWTON_MAXITER + n_iter)
        if rejected and en > 1.0:
            for j in range(n2):
                ys[j] = y[j] + err[j]
            ki.feval(t, ys, P, err, qdd, lam, tau, modes)
            stats[ki.S_NFEV] += 1
            en = _error_norm(err, Z, h, LUr, pr, J, ctl[C_LUH], y, ynew, atol, rtol)
        if not (en <= 1.0):
            if not np.isfinite(en):
                nonfinite = True
                h_abs *= MIN_FACTOR
            else:
                h_abs *= max(MIN_FACTOR, safety * _predict_factor(h_abs, h_abs_old, en, en_old))
            ctl[C_LUH] = 0.0
            rejected = True
            stats[ki.S_NREJ] += 1
            continue
        break
    # accepted: the state at the step end (also its normal forces for the contact monitor)
    ok = ki.feval(t_new, ynew, P, fnew, qdd, lam, tau, modes)
    stats[ki.S_NFEV] += 1
    if not (ki.all_finite(ynew) and ki.all_finite(fnew)):
        rinfo[ki.R_H] = h
        return ki.ST_NONFINITE
    if not ok:
        rinfo[ki.R_H] = h
        return ki.ST_SINGULAR
    recompute_jac = n_iter > 2 and rate > JAC_RATE
    if fixed:
        ctl[C_H] = h_abs
    else:
        factor = min(MAX_FACTOR, safety * _predict_factor(h, h_abs_old, en, en_old))
        if not recompute_jac and factor < KEEP_STEP:
            factor = 1.0
        ctl[C_HOLD] = h
        ctl[C_EOLD] = en
        ctl[C_H] = h * factor
    # the LU factors stay valid while J does and the step size is unchanged (a step cut to the
    # next kink may well be the same as the last one)
    ctl[C_CURJ] = 0.0
    if recompute_jac:
        ki.jeval(t_new, ynew, P, J)
        stats[ki.S_NJEV] += 1
        ctl[C_CURJ] = 1.0
        ctl[C_LUH] = 0.0
    for j in range(n2):
        for k in range(3):
            Qd[j, k] = Z[0, j] * PD[0, k] + Z[1, j] * PD[1, k] + Z[2, j] * PD[2, k]
    ctl[C_HPREV] = h
    ctl[C_TNEW] = t_new
    ctl[C_HSTEP] = h
    stats[ki.S_NSTEP] += 1
    return ki.ST_SUCCESS


@njit(cache=True)
def setup(P, x0, t_eval, nc):
    """The arrays of a run from x0 with nc contacts: (stats, rinfo, ws, y, f, lam_old), with
    y = x0 (a copy) and the time reached ``rinfo[R_T] = t_eval[0]``."""
    n2 = x0.shape[0]
    ws = workspace(n2, nc, P[ks.I_D].shape[0])
    stats = np.zeros(ki.N_STATS, dtype=np.int64)
    rinfo = np.zeros(ki.N_RINFO)
    rinfo[ki.R_T] = t_eval[0]
    return stats, rinfo, ws, x0.copy(), np.empty(n2), np.empty(nc)


@njit(cache=True)
def start(
    P, y, f, t_eval, h0, max_step, atol, rtol, lam_old, X, upl_t, uplift_mode, ws, stats, rinfo
):
    """Start-up of a Radau run at (t, y), t = t_eval[0]: :func:`nsdyn.solve._kcommon.start`
    (f = f(t, y), the outputs at t_eval <= t, the contact check), then the Jacobian at the
    start and the first step size (automatic when ``h0 <= 0``).

    Returns (iout, ctl): the first output still to write (-1 when the run stops here, status
    in ``stats``; nothing to step when ``iout >= nt``) and the stepper state.
    """
    J = ws[0]
    qdd, lam, tau, modes = ws[18:22]
    t = t_eval[0]
    ctl = new_control(h0, rtol)
    iout = ki.start(
        t, y, P, f, qdd, lam, tau, modes, t_eval, X, lam_old, upl_t, uplift_mode, stats, rinfo
    )
    if iout < 0 or iout >= t_eval.shape[0]:
        return iout, ctl
    ki.jeval(t, y, P, J)
    stats[ki.S_NJEV] += 1
    if h0 <= 0.0:
        ctl[C_H] = ki.initial_step(
            t, y, f, t_eval[-1], max_step, 3, rtol, atol, P, ws[12], ws[14], qdd, lam, tau, modes
        )
        stats[ki.S_NFEV] += 1
    ctl[C_CURJ] = 1.0
    return iout, ctl


@njit(cache=True)
def accept(t, y, f, ctl, ws, t_eval, iout, X, lam_old, upl_t, uplift_mode, stats, rinfo):
    """Move to the end of the step :func:`radau_step` accepted: outputs at the t_eval it
    covers (from ``iout``, dense output), contact check, y, f, lam_old at the step end.
    Returns (iout, stop)."""
    t_new = ctl[C_TNEW]
    ynew, fnew, Qd, lam = ws[15], ws[16], ws[17], ws[19]
    while iout < t_eval.shape[0] and t_eval[iout] <= t_new:
        dense(y, Qd, (t_eval[iout] - t) / ctl[C_HSTEP], X[iout])
        iout += 1
    stop = ki.advance(t, t_new, y, ynew, lam_old, lam, iout, upl_t, uplift_mode, stats, rinfo)
    f[:] = fnew
    return iout, stop


@njit(cache=True)
def radau(P, x0, t_eval, atol, rtol, h0, max_step, max_steps, fixed, uplift_mode, X, upl_t):
    """Integrate from ``t_eval[0]`` to ``t_eval[-1]`` with Radau IIA; state at t_eval into X.

    Same arguments and returns as :func:`nsdyn.solve._kdopri.dopri5`. With ``fixed`` the steps are
    exactly ``h0`` and rtol/atol only set the Newton tolerance.
    """
    nt = t_eval.shape[0]
    stats, rinfo, ws, y, f, lam_old = setup(P, x0, t_eval, upl_t.shape[0])
    t = t_eval[0]
    t_end = t_eval[-1]
    iout, ctl = start(
        P, y, f, t_eval, h0, max_step, atol, rtol, lam_old, X, upl_t, uplift_mode, ws, stats, rinfo
    )
    if iout < 0 or iout >= nt:
        return stats, rinfo
    while iout < nt:
        t_lim = t_end if fixed else min(t_end, ki.next_kink(t, P))
        st = radau_step(
            P, t, y, f, t_lim, fixed, atol, rtol, max_step, max_steps, ws, ctl, stats, rinfo
        )
        if st != ki.ST_SUCCESS:
            stats[ki.S_STATUS] = st
            rinfo[ki.R_T] = t
            break
        iout, stop = accept(
            t, y, f, ctl, ws, t_eval, iout, X, lam_old, upl_t, uplift_mode, stats, rinfo
        )
        t = ctl[C_TNEW]
        if stop:
            break
    rinfo[ki.R_HNEXT] = ctl[C_H]
    return stats, rinfo
