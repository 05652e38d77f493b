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

The step is :func:`_step` (one accepted step with retries, state in ``ctl``), so the
event-driven integrator (:mod:`nsdyn.solve._kunilateral`) drives the same stepper: its step
kernel is a copy of it with the general kernel of the address table.
"""

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn import _kborrow as kb
from nsdyn.models.isolated import _kernel as ks
from nsdyn.solve import _kcolloc as kc
from nsdyn.solve import _kcommon as ki
from nsdyn.solve import _kflat as kf
from nsdyn.solve._kcolloc import (  # noqa: F401  (the tableau and ctl layout, re-exported)
    C_CURJ,
    C_EOLD,
    C_FACCON,
    C_H,
    C_HOLD,
    C_HPREV,
    C_HSTEP,
    C_LUH,
    C_NTOL,
    C_TNEW,
    EIG_COMPLEX,
    EIG_REAL,
    K_FACTOR,
    K_FEVAL,
    K_JAC,
    K_NEWTON,
    K_START,
    MU_REAL,
    N_CTL,
    NEWTON_MAXITER,
    PD,
    S6,
    TI,
    C,
    E,
    T,
    _error_norm,
    _factor,
    _predict_factor,
    _solve,
    newton,
)

MIN_FACTOR = 0.2  # smallest step shrink per rejection
MAX_FACTOR = 10.0  # largest step growth per step
JAC_RATE = 1e-3  # recompute J after a step whose Newton needed > 2 iterations at this rate
KEEP_STEP = 1.2  # keep h (and the LU factors) when the proposed growth is below this
LU_RTOL = 1e-9  # relative change of h that forces a new LU
NEWTON_FAIL_SHRINK = 0.5  # step shrink when Newton fails with a fresh Jacobian


@njit(cache=True, error_model="numpy")
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
        np.zeros(n2),  # iscale: 1 / (atol + |y| rtol) at the step start (Newton's norm)
        np.zeros(n2),  # err
        np.zeros(n2),  # ynew
        np.zeros(n2),  # fnew
        np.zeros((n2, 3)),  # Qd dense-output coefficients of the last accepted step
        np.zeros(n),  # qdd
        np.zeros(nc),  # lam (at ynew after an accepted step)
        np.zeros(ni),  # tau
        np.zeros(ni, dtype=np.int64),  # modes
    )


@njit(cache=True, error_model="numpy")
def restart(ctl):
    """Forget the step history (after an event changed the vector field)."""
    ctl[C_HOLD] = np.nan
    ctl[C_EOLD] = np.nan
    ctl[C_LUH] = 0.0
    ctl[C_HPREV] = 0.0
    ctl[C_FACCON] = 1.0


@njit(cache=True, error_model="numpy")
def init_control(ctl, h0, rtol):
    """Fresh stepper state in ``ctl`` (N_CTL,): first step h0, no history, Newton tolerance
    from rtol."""
    ctl[:] = 0.0
    restart(ctl)
    ctl[C_H] = h0
    ctl[C_NTOL] = max(10.0 * 2.220446049250313e-16 / rtol, min(0.03, rtol**0.5))


@njit(cache=True, error_model="numpy")
def dense(y, Qd, x, out):
    """Collocation polynomial of the last step at ``t_old + x h`` (y = state at t_old)."""
    for i in range(y.shape[0]):
        out[i] = y[i] + x * (Qd[i, 0] + x * (Qd[i, 1] + x * Qd[i, 2]))


# the general kernel of each copy of :func:`_step`, :func:`_start` and :func:`_loop`, and the
# step of each copy of :func:`_loop` (:func:`nsdyn._kaddress.specialised` binds them)
_GENERAL = kc.general_called
_STEP = None


def _step(P, t, y, f, t_lim, fixed, atol, rtol, max_step, max_steps, ws, ctl, stats, rinfo, K):
    """Take one accepted step from (t, y) (f = f(t, y)), retrying with smaller steps.

    On success returns 0 and leaves the new state in ``ws`` (ynew, fnew and lam, tau, modes
    at ynew), the dense output in Qd, the step end in ``ctl[C_TNEW]``. Otherwise returns a
    negative status (ST_*) with ``rinfo`` describing where.
    With ``fixed`` the step is ``ctl[C_H]`` (shortened only to land on ``t_lim``) and a Newton
    failure is reported instead of retried. Smooth laws with closed contacts are evaluated by
    the flat kernel; the general kernel ``_GENERAL``
    (:func:`nsdyn.solve._kcolloc.general_called` and its siblings, one per copy of this
    function, :func:`nsdyn._kaddress.specialised`) serves the rest. The flat right-hand side
    and Jacobian, the factorisation and Newton are called through
    :func:`nsdyn._kaddress.call`: directly (``K`` None) or by their addresses in the int64
    array ``K`` (:func:`radau_flat`; the slots at the end of this
    module).
    """
    J, LUr, pr, LUc, pc, Z, Z0, W, F, dW, fr, fc, ys, iscale, err, ynew, fnew, Qd = ws[:18]
    qdd, lam, tau, modes, Fl = ws[18:23]
    flat = kf.usable(P[ks.I_OPEN], Fl)
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
        iscale[j] = 1.0 / (atol[j] + abs(y[j]) * rtol)
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
                if not ka.call(K, "radau.factor", (h, J, LUr, pr, LUc, pc), _GENERAL):
                    rinfo[ki.R_H] = h
                    return ki.ST_LU_SINGULAR
                ctl[C_LUH] = h
            for i in range(3):  # loops, not _klinalg.copy_mat: this step is itself inlined
                for j in range(n2):
                    Z[i, j] = Z0[i, j]
            converged, n_iter, rate, nf, singular, dw = ka.call(K, "radau.newton", (
                P, t, y, h, ctl, stats, J, LUr, pr, LUc, pc, Z, W, F, dW, fr, fc, ys, iscale,
                qdd, lam, tau, modes, Fl, flat,
            ), _GENERAL)  # fmt: skip
            if nf:
                nonfinite = True
            if converged or ctl[C_CURJ] == 1.0 or nf or singular:
                break
            stats[ki.S_NJEV] += 1
            if not kc.jeval(t, y, P, Fl, flat, _GENERAL, K, J, ys, qdd, lam, tau, modes):
                rinfo[ki.R_H] = h
                return ki.ST_SINGULAR
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
        for j in range(n2):
            err[j] = f[j]
        en = _error_norm(err, Z, h, LUr, pr, J, ctl[C_LUH], y, ynew, atol, rtol)
        safety = 0.9 * (2 * NEWTON_MAXITER + 1) / (2 * NEWTON_MAXITER + n_iter)
        if rejected and en > 1.0:
            for j in range(n2):
                ys[j] = y[j] + err[j]
            if not (
                flat and ka.call(K, "radau.feval", (t, ys, Fl, err, qdd, lam, tau, modes), _GENERAL)
            ):
                _GENERAL(kc.G_ONE, P, t, ys, h, Z, F, ys, err, J, qdd, lam, tau, modes)
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
    ok = flat and ka.call(K, "radau.feval", (t_new, ynew, Fl, fnew, qdd, lam, tau, modes), _GENERAL)
    if not ok:
        ok = _GENERAL(kc.G_ONE, P, t_new, ynew, h, Z, F, ys, fnew, J, qdd, lam, tau, modes)
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
        stats[ki.S_NJEV] += 1
        if not kc.jeval(t_new, ynew, P, Fl, flat, _GENERAL, K, J, ys, qdd, lam, tau, modes):
            rinfo[ki.R_H] = h
            return ki.ST_SINGULAR
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


def _owned(ws, x0, t_eval, nc):
    """The arrays a run owns, around its workspace ``ws``: (stats, rinfo, ws, y, f, lam_old,
    ctl), with y = x0 (a copy), the time reached ``rinfo[R_T] = t_eval[0]`` and the stepper
    state ``ctl`` (its start-up fills it)."""
    stats = np.zeros(ki.N_STATS, dtype=np.int64)
    rinfo = np.zeros(ki.N_RINFO)
    rinfo[ki.R_T] = t_eval[0]
    return stats, rinfo, ws, x0.copy(), np.empty(x0.shape[0]), np.empty(nc), np.zeros(N_CTL)


owned_inline = njit(cache=True, error_model="numpy", inline="always")(_owned)


@njit(cache=True, error_model="numpy")
def setup(P, x0, t_eval, nc, F):
    """The arrays of a run from x0 with nc contacts: (stats, rinfo, ws, y, f, lam_old), with
    y = x0 (a copy) and the time reached ``rinfo[R_T] = t_eval[0]``; ``ws`` is
    :func:`workspace` plus ``F``, the flat parameter array of ``P``
    (:func:`nsdyn.solve._kflat.pack_flat`, numpy)."""
    ws = workspace(x0.shape[0], nc, P[ks.I_D].shape[0]) + (F,)
    return owned_inline(ws, x0, t_eval, nc)


def setup_here(P, x0, t_eval, nc):
    """:func:`setup` in the calling Python process: the arrays by numpy (the Python function
    of :func:`workspace`), nothing compiled. The default loop (:func:`radau_flat`) takes them
    so that no compiled set-up is needed before its first run (~2 s of its first
    compilation; ~20 us per call here)."""
    work = getattr(workspace, "py_func", workspace)
    return _owned(work(x0.shape[0], nc, P[ks.I_D].shape[0]) + (kf.pack_flat(P),), x0, t_eval, nc)


def _start(
    P, y, f, t_eval, h0, max_step, atol, rtol, lam_old, X, upl_t, uplift_mode, ws, stats, rinfo,
    ctl, K,
):  # fmt: skip
    """Start-up of a Radau run at (t, y), t = t_eval[0]: f = f(t, y) and
    :func:`nsdyn.solve._kcommon.start_from` (the outputs at t_eval <= t, the contact check),
    then the Jacobian at the start and the first step size (automatic when ``h0 <= 0``);
    the flat kernel where it applies, else the general kernel ``_GENERAL`` (one per copy of
    this function, as :func:`_step`).

    Returns iout, the first output still to write (-1 when the run stops here, status in
    ``stats``; nothing to step when ``iout >= nt``); the stepper state is made in ``ctl``.
    ``K``: see :func:`_step`.
    """
    J, Z, F, ys, err = ws[0], ws[5], ws[8], ws[12], ws[14]
    qdd, lam, tau, modes, Fl = ws[18:23]
    flat = kf.usable(P[ks.I_OPEN], Fl)
    t = t_eval[0]
    init_control(ctl, h0, rtol)
    ok = flat and ka.call(K, "radau.feval", (t, y, Fl, f, qdd, lam, tau, modes), _GENERAL)
    if not ok:
        ok = _GENERAL(kc.G_ONE, P, t, y, 0.0, Z, F, ys, f, J, qdd, lam, tau, modes)
    iout = ki.start_from(ok, t, y, f, lam, t_eval, X, lam_old, upl_t, uplift_mode, stats, rinfo)
    if iout < 0 or iout >= t_eval.shape[0]:
        return iout
    # lam at the start is in lam_old; the Jacobian and the trial evaluation overwrite lam
    stats[ki.S_NJEV] += 1
    if not kc.jeval(t, y, P, Fl, flat, _GENERAL, K, J, ys, qdd, lam, tau, modes):
        stats[ki.S_STATUS] = ki.ST_SINGULAR
        return -1
    if h0 <= 0.0:
        h1 = ki.initial_probe(t, y, f, t_eval[-1], rtol, atol, ys)
        if h1 > 0.0:
            t1 = t + h1
            ok = flat and ka.call(
                K, "radau.feval", (t1, ys, Fl, err, qdd, lam, tau, modes), _GENERAL
            )
            if not ok:
                _GENERAL(kc.G_ONE, P, t1, ys, 0.0, Z, F, ys, err, J, qdd, lam, tau, modes)
            stats[ki.S_NFEV] += 1
            h1 = ki.initial_finish(h1, y, f, err, t_eval[-1] - t, max_step, np.int64(3), rtol, atol)
        ctl[C_H] = h1
    ctl[C_CURJ] = 1.0
    return iout


@ka.compiled_uncounted
def accept(t, y, f, ctl, ws, t_eval, iout, X, lam_old, upl_t, uplift_mode, stats, rinfo):
    """Move to the end of the step :func:`_step` accepted: outputs at the t_eval it
    covers (from ``iout``, dense output), contact check, y, f, lam_old at the step end.
    Returns (iout, stop)."""
    ynew, fnew, Qd, lam = ws[15], ws[16], ws[17], ws[19]
    return accept_arrays(
        t, y, f, ctl, ynew, fnew, Qd, lam, t_eval, iout, X, lam_old, upl_t, uplift_mode, stats,
        rinfo,
    )  # fmt: skip


@njit(cache=True, error_model="numpy", inline="always")
def accept_arrays(
    t, y, f, ctl, ynew, fnew, Qd, lam, t_eval, iout, X, lam_old, upl_t, uplift_mode, stats, rinfo
):
    """:func:`accept` on the workspace's arrays one by one."""
    t_new = ctl[C_TNEW]
    while iout < t_eval.shape[0] and t_eval[iout] <= t_new:
        dense(y, Qd, (t_eval[iout] - t) / ctl[C_HSTEP], X[iout])
        iout += 1
    stop = ki.advance(t, t_new, y, ynew, lam_old, lam, iout, upl_t, uplift_mode, stats, rinfo)
    for j in range(f.shape[0]):
        f[j] = fnew[j]
    return iout, stop


def _loop(P, x0, t_eval, atol, rtol, h0, max_step, max_steps, fixed, uplift_mode, X, upl_t, flat,
          K, owned):  # fmt: skip
    """The run loop of :func:`radau` (inlined, ``K`` None: its callees called directly) and
    :func:`radau_flat` (compiled; ``K`` see :func:`_step`; the start-up is a callee too), each
    a copy of this function with its general kernel ``_GENERAL`` and its step ``_STEP``
    (:func:`_step` inlined, with the same general kernel). ``owned``: the arrays of the run as
    :func:`setup` returns them (:func:`radau_flat` is given those of :func:`setup_here`).

    :func:`radau_flat` is the default run's loop: a smooth law with every contact closed,
    through the flat kernel only (``flat`` True, the general kernel
    :func:`nsdyn.solve._kcolloc.flat_only`), its callees called by address (``K`` from
    :func:`nsdyn.solve.compile_split.radau_calls`; :mod:`nsdyn._kaddress`): its code holds
    none of theirs, so it compiles before or beside them, and it never compiles the general
    right-hand side or its Jacobian. Where the flat form fails (a singular ``G``) the run stops
    with ST_SINGULAR; the caller (:mod:`nsdyn.solve.methods`) then runs it with
    :func:`radau`, whose results equal this one's where both apply.

    The loop works on borrowed views (:mod:`nsdyn._kborrow`) of the arrays it owns and of its
    arguments: bit for bit the same run, without the ~480 atomic reference-count updates per
    step of passing ~40 arrays around. It returns nothing (the results are in ``owned`` and
    ``X``); :func:`radau_flat` allocates nothing and is compiled without reference counts
    (:data:`nsdyn._kaddress.NO_NRT`).
    """
    nt = t_eval.shape[0]
    stats_own, rinfo_own, ws_own, y_own, f_own, lam_own, ctl_own = owned
    if not flat:
        ws_own[22][kf.H_OK] = 0.0
    ws = kb.borrowed(ws_own)
    y, f, lam_old = kb.borrowed((y_own, f_own, lam_own))
    stats, rinfo = kb.borrowed((stats_own, rinfo_own))
    P = kb.borrowed(P)
    t_eval, atol, X, upl_t = kb.borrowed((t_eval, atol, X, upl_t))
    ctl = kb.borrowed(ctl_own)
    t = t_eval[0]
    t_end = t_eval[-1]
    iout = ka.call(K, "radau.start", (
        P, y, f, t_eval, h0, max_step, atol, rtol, lam_old, X, upl_t, uplift_mode, ws, stats,
        rinfo, ctl, K,
    ), _GENERAL)  # fmt: skip
    if iout < 0 or iout >= nt:
        return
    ynew, fnew, Qd, lam = ws[15], ws[16], ws[17], ws[19]
    while iout < nt:
        t_lim = t_end if fixed else min(t_end, ki.next_kink(t, P))
        st = _STEP(
            P, t, y, f, t_lim, fixed, atol, rtol, max_step, max_steps, ws, ctl, stats, rinfo, K
        )
        if st != ki.ST_SUCCESS:
            stats[ki.S_STATUS] = st
            rinfo[ki.R_T] = t
            break
        iout, stop = accept_arrays(
            t, y, f, ctl, ynew, fnew, Qd, lam, t_eval, iout, X, lam_old, upl_t, uplift_mode,
            stats, rinfo,
        )  # fmt: skip
        t = ctl[C_TNEW]
        if stop:
            break
    rinfo[ki.R_HNEXT] = ctl[C_H]
    kb.alive((ws_own, y_own, f_own, lam_own, ctl_own))


def radau(P, x0, t_eval, atol, rtol, h0, max_step, max_steps, fixed, uplift_mode, X, upl_t, flat):
    """Integrate from ``t_eval[0]`` to ``t_eval[-1]`` with Radau IIA; state at t_eval into X.

    Same arguments and returns as :func:`nsdyn.solve._kdopri.dopri5`. With ``fixed`` the steps are
    exactly ``h0`` and rtol/atol only set the Newton tolerance. ``flat``: evaluate smooth laws
    through :mod:`nsdyn.solve._kflat` (False: the general kernel everywhere, the baseline).
    The loop is :func:`radau_general` (the flat parameters made here, by numpy).
    """
    args = (P, x0, t_eval, atol, rtol, h0, max_step, max_steps, fixed, uplift_mode, X, upl_t)
    return radau_general(*args, flat, kf.pack_flat(P))


@njit(cache=True, error_model="numpy", nogil=True)  # (a watched chunk: checkpoint.held_call)
def radau_general(
    P, x0, t_eval, atol, rtol, h0, max_step, max_steps, fixed, uplift_mode, X, upl_t, flat, F
):  # fmt: skip
    """:func:`radau` with the flat parameter array ``F`` of ``P`` given: the general kernel's
    loop, its callees linked."""
    owned = setup(P, x0, t_eval, upl_t.shape[0], F)
    _run(P, x0, t_eval, atol, rtol, h0, max_step, max_steps, fixed, uplift_mode, X, upl_t, flat,
         None, owned)  # fmt: skip
    return owned[0], owned[1]


# ---- the copies of the step, the start-up and the loop, each with its general kernel --------
# (:func:`nsdyn._kaddress.specialised`: one source each, no kernel that only inlines another)

# the step inlined into the run loops (called, it cost the default run's loop ~7 %: ~40
# arrays passed per step)
step_flat_inline = njit(cache=True, error_model="numpy", inline="always")(
    ka.specialised(_step, "step_flat", _GENERAL=kc.flat_only)
)
step_called_inline = njit(cache=True, error_model="numpy", inline="always")(
    ka.specialised(_step, "step_called", _GENERAL=kc.general_called)
)
"""One Radau step (:func:`_step`) with :func:`nsdyn.solve._kcolloc.flat_only` (the default
loop's), :func:`~nsdyn.solve._kcolloc.general_called` (the general kernel's loop)."""

start = njit(cache=True, error_model="numpy")(
    ka.specialised(_start, "start", _GENERAL=kc.general_called)
)
"""The start-up (:func:`_start`) of the general kernel's loop (``K`` None: its callees called
directly)."""

start_flat = ka.compiled_uncounted(ka.specialised(_start, "start_flat", _GENERAL=kc.flat_only))
"""The start-up with :func:`nsdyn.solve._kcolloc.flat_only` (the default loop's, called by
address: a kernel argument would be in its declared type)."""

radau_flat = njit(cache=True, error_model="numpy", nogil=True, **ka.NO_NRT)(
    ka.specialised(_loop, "radau_flat", _GENERAL=kc.flat_only, _STEP=step_flat_inline)
)
"""The default run's loop (:func:`_loop`): the flat kernel only, its callees by address."""

_run = njit(cache=True, error_model="numpy", inline="always")(
    ka.specialised(_loop, "loop_called", _GENERAL=kc.general_called, _STEP=step_called_inline)
)

# the callees of the step, the start-up and the loop (:mod:`nsdyn._kaddress`): their index in
# ``K`` and the kernel called directly when ``K`` is None (Newton and the start-up: the copy
# for the caller's general kernel)
ka.slot("radau.feval", K_FEVAL, kf.feval_flat)
ka.slot("radau.jac", K_JAC, kf.jac_flat_here)
ka.slot("radau.factor", K_FACTOR, _factor)
ka.slot("radau.newton", K_NEWTON, kc.NEWTON_FOR)
ka.slot("radau.start", K_START, {kc.general_called: start, kc.flat_only: start_flat})

# the kernels whose addresses the default loop (radau_flat) takes, in the order of K
FLAT_CALLEES = (kf.feval_flat, kf.jac_flat_here, _factor, kc.newton_flat, start_flat)
