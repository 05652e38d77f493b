"""Explicit Dormand-Prince 5(4) with dense output, whole time loop in numba.

Dormand & Prince (1980); step control and 4th-order dense output as Hairer, Norsett & Wanner
I, sec. II.4-II.6 (the coefficients are scipy's ``RK45``). Local extrapolation: the 5th-order
solution is propagated, the 4th-order embedded one only estimates the error. Outputs at
``t_eval`` come from the dense output, never from shortened steps.

Non-stiff only: the arctan slope mu lam (2/pi) eps limits the stable step, whatever the
tolerance: ~2e-6 s on the office frame's cb model (Jacobian eigenvalues -1.6e6 and -1.1e6 /s
at rest at eps = 7500, both from the slope; the stability boundary of the method is at
|h lambda| ~ 3.3). The Craig-Bampton boundary modes (0.2-1.2 kHz on the office frame, up to
10 kHz on the portal) limit it next: ~4e-4 s on the office frame without friction.
"""

import numpy as np
from numba import njit

from nsdyn import _kborrow as kb
from nsdyn._klinalg import copy_vec
from nsdyn.models.isolated import _kernel as ks
from nsdyn.solve import _kcommon as ki

SAFETY = 0.9  # step-size safety factor
MIN_FACTOR = 0.2  # smallest step shrink per rejection
MAX_FACTOR = 10.0  # largest step growth per step
ERR_EXP = -0.2  # -1/(order of the error estimator + 1)
NONFINITE_SHRINK = 0.25  # step shrink after a step that produced NaN/inf

C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0])
A = np.array(
    [
        [0.0, 0.0, 0.0, 0.0, 0.0],
        [1 / 5, 0.0, 0.0, 0.0, 0.0],
        [3 / 40, 9 / 40, 0.0, 0.0, 0.0],
        [44 / 45, -56 / 15, 32 / 9, 0.0, 0.0],
        [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0.0],
        [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656],
    ]
)
B = np.array([35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84])
E = np.array([-71 / 57600, 0.0, 71 / 16695, -71 / 1920, 17253 / 339200, -22 / 525, 1 / 40])
# dense output: y(t + x h) = y + h sum_j K_j sum_m PD[j, m] x^(m+1)
PD = np.array(
    [
        [1.0, -8048581381 / 2820520608, 8663915743 / 2820520608, -12715105075 / 11282082432],
        [0.0, 0.0, 0.0, 0.0],
        [0.0, 131558114200 / 32700410799, -68118460800 / 10900136933, 87487479700 / 32700410799],
        [0.0, -1754552775 / 470086768, 14199869525 / 1410260304, -10690763975 / 1880347072],
        [
            0.0,
            127303824393 / 49829197408,
            -318862633887 / 49829197408,
            701980252875 / 199316789632,
        ],
        [0.0, -282668133 / 205662961, 2019193451 / 616988883, -1453857185 / 822651844],
        [0.0, 40617522 / 29380423, -110615467 / 29380423, 69997945 / 29380423],
    ]
)


@njit(cache=True, error_model="numpy")
def _dense(t, h, y, K, tout, out):
    x = (tout - t) / h
    n = y.shape[0]
    for i in range(n):
        out[i] = y[i]
    for j in range(7):
        b = x * (PD[j, 0] + x * (PD[j, 1] + x * (PD[j, 2] + x * PD[j, 3])))
        if b != 0.0:
            for i in range(n):
                out[i] += h * b * K[j, i]


@njit(cache=True, error_model="numpy", nogil=True)  # (a watched chunk: checkpoint.held_call)
def dopri5(P, x0, t_eval, atol, rtol, h0, max_step, max_steps, fixed, uplift_mode, X, upl_t):
    """Integrate from ``t_eval[0]`` to ``t_eval[-1]``, writing the state at ``t_eval`` in X.

    Parameters
    ----------
    x0 : (2n,) initial state; t_eval : (nt,) sorted output times; atol : (2n,)
    h0 : initial step (<= 0: automatic); fixed : if True take steps of exactly h0 (no error
    control; the last step is shortened to land on t_eval[-1]).
    X : (nt, 2n) out; upl_t : (nc,) out, first uplift time per contact (NaN: none).

    Returns (stats, rinfo); see :mod:`nsdyn.solve._kcommon`.
    """
    n2 = x0.shape[0]
    nc = upl_t.shape[0]
    nt = t_eval.shape[0]
    stats = np.zeros(ki.N_STATS, dtype=np.int64)
    rinfo = np.zeros(ki.N_RINFO)
    K = np.empty((7, n2))
    y = x0.copy()
    ynew = np.empty(n2)
    ytmp = np.empty(n2)
    err = np.empty(n2)
    qdd, lam, tau, modes = ks.outputs(P)
    lam_old = np.empty(nc)
    # the loop works on borrowed views (nsdyn._kborrow) of these and of its arguments: no
    # atomic reference counts for the arrays each step passes on; the owned stats/rinfo return
    own = (stats, rinfo, K, y, ynew, ytmp, err, qdd, lam, tau, modes, lam_old)
    stats, rinfo, K, y, ynew, ytmp, err, qdd, lam, tau, modes, lam_old = kb.borrowed(own)
    P = kb.borrowed(P)
    x0, t_eval, atol, X, upl_t = kb.borrowed((x0, t_eval, atol, X, upl_t))
    t = t_eval[0]
    t_end = t_eval[-1]
    rinfo[ki.R_T] = t

    iout = ki.start(
        t, y, P, K[0], qdd, lam, tau, modes, t_eval, X, lam_old, upl_t, uplift_mode, stats, rinfo
    )
    if iout < 0:
        return own[0], own[1]

    if h0 > 0.0:
        h = h0
    else:
        order = np.int64(4)  # typed: initial_finish compiles once for every method
        h = ki.initial_step(
            t, y, K[0], t_end, max_step, order, rtol, atol, P, ytmp, K[1], qdd, lam, tau, modes
        )
        stats[ki.S_NFEV] += 1
    rejected = False
    nonfinite = False
    n_try = 0
    while iout < nt:
        if n_try >= max_steps:
            stats[ki.S_STATUS] = ki.ST_MAX_STEPS
            break
        if h < ki.step_floor(t):
            stats[ki.S_STATUS] = ki.ST_NONFINITE if nonfinite else ki.ST_STEP_UNDERFLOW
            break
        h = min(h, max_step)
        t_lim = t_end if fixed else min(t_end, ki.next_kink(t, P))
        t_new = t + h
        if t_new >= t_lim or (fixed and t_new > t_lim - 1e-9 * h):
            t_new = t_lim
        hh = t_new - t
        n_try += 1
        for s in range(1, 6):
            for i in range(n2):
                acc = 0.0
                for j in range(s):
                    acc += A[s, j] * K[j, i]
                ytmp[i] = y[i] + hh * acc
            ok = ki.feval(t + C[s] * hh, ytmp, P, K[s], qdd, lam, tau, modes)
        for i in range(n2):
            acc = 0.0
            for j in range(6):
                acc += B[j] * K[j, i]
            ynew[i] = y[i] + hh * acc
        ok = ki.feval(t_new, ynew, P, K[6], qdd, lam, tau, modes)
        stats[ki.S_NFEV] += 6
        finite = ki.all_finite(ynew) and ki.all_finite(K[6])
        if finite:
            for s in range(1, 6):
                if not ki.all_finite(K[s]):
                    finite = False
        if not finite:
            nonfinite = True
            stats[ki.S_NREJ] += 1
            rinfo[ki.R_T] = t
            if fixed:
                stats[ki.S_STATUS] = ki.ST_NONFINITE
                break
            h = hh * NONFINITE_SHRINK
            rejected = True
            continue
        if not ok:
            stats[ki.S_STATUS] = ki.ST_SINGULAR
            rinfo[ki.R_T] = t_new
            break
        if fixed:
            h_next = h
        else:
            for i in range(n2):
                acc = 0.0
                for j in range(7):
                    acc += E[j] * K[j, i]
                err[i] = hh * acc
            en = ki.scaled_rms(err, y, ynew, atol, rtol)
            if en < 1.0:
                if en == 0.0:
                    factor = MAX_FACTOR
                else:
                    factor = min(MAX_FACTOR, SAFETY * en**ERR_EXP)
                if rejected:
                    factor = min(1.0, factor)
                h_next = hh * factor
            else:
                h = hh * max(MIN_FACTOR, SAFETY * en**ERR_EXP)
                rejected = True
                stats[ki.S_NREJ] += 1
                continue
        # accepted
        while iout < nt and t_eval[iout] <= t_new:
            _dense(t, hh, y, K, t_eval[iout], X[iout])
            iout += 1
        stats[ki.S_NSTEP] += 1
        rinfo[ki.R_H] = hh
        stop = ki.advance(t, t_new, y, ynew, lam_old, lam, iout, upl_t, uplift_mode, stats, rinfo)
        t = t_new
        copy_vec(K[0], K[6])  # first same as last
        rejected = False
        nonfinite = False
        h = h_next
        if stop:
            break
    rinfo[ki.R_HNEXT] = h
    st = stats[ki.S_STATUS]
    if st != ki.ST_SUCCESS and st != ki.ST_UPLIFT and st != ki.ST_SINGULAR:
        rinfo[ki.R_T] = t
        rinfo[ki.R_H] = h
    kb.alive(own)
    return own[0], own[1]
