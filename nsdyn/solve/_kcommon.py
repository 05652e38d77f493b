"""Shared numba pieces of the integrators: status codes, norms, dense LU, contact monitor.

The steppers live in :mod:`nsdyn.solve._kdopri` (explicit Dormand-Prince 5(4)),
:mod:`nsdyn.solve._kradau` (Radau IIA order 5), :mod:`nsdyn.solve._kgenalpha`
(generalized-alpha family) and :mod:`nsdyn.solve._kevent` (event-driven switch model on the
Radau stepper). Each integrates the first-order system of the isolated frame::

    xd = f(t, x) = [qd, qdd(t, q, qd)],   x = [q, qd]

(accelerations, normal forces lam and friction forces tau from the system kernel
:mod:`nsdyn.models.isolated._kernel`), runs its whole time loop inside numba and calls the
system kernels as module globals, never as arguments (a kernel's type holds its dispatcher's
identity, random per process: numba's cache entries of a caller typed with it would never be
found by another process, the compile helper's included); the default Radau loop's callees
are passed as addresses (:mod:`nsdyn._kaddress`), and kernels that differ only in their
callees are copies of one source (:func:`nsdyn._kaddress.specialised`).

Every stepper reports through two small arrays: ``stats`` (int64, layout ``S_*``) and
``rinfo`` (float64, layout ``R_*``); the front door :mod:`nsdyn.solve.integrate` turns them
into a ``Solution``.
"""

from pathlib import Path

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn import _klinalg as kl
from nsdyn._klinalg import all_finite, copy_vec, lu_factor, lu_solve  # noqa: F401  (the integrators' LU)
from nsdyn._numba_cache import drop_stale, guard_family
from nsdyn.models.isolated import _kernel as ks

# integrator kernel modules (numba-cached, in this folder); their compiled code also depends on
# the isolated frame's system kernel, which they inline
KERNEL_MODULES = (
    "_kcommon",
    "_kdopri",
    "_kradau",
    "_kflat",
    "_kcolloc",
    "_kgenalpha",
    "_klowrank",
    "_kevent",
    "_kimpact",
    "_kunilateral",
)

# stale caches across files: the system kernel and the shared LU are compiled into ours
_NSDYN = Path(__file__).resolve().parents[1]
# (and the Radau loop's calls by address are declared in compile_split.py, see _kaddress.py)
guard_family(
    __file__,
    [_NSDYN / "models" / "isolated" / "_kernel.py", _NSDYN / "_klinalg.py", _NSDYN / "_kborrow.py",
     _NSDYN / "_kaddress.py", Path(__file__).resolve().parent / "compile_split.py"],
)  # fmt: skip
# the table's system kernel and Jacobian (sys_evaluate, sys_jac_at below) are copies of
# _kernel's, cached beside them, with this file's calls by address: its cache goes with ours
drop_stale(
    _NSDYN / "models" / "isolated",
    ["_kernel"],
    [_NSDYN / "models" / "isolated" / "_kernel.py", Path(__file__), _NSDYN / "_klinalg.py",
     _NSDYN / "_kaddress.py", Path(__file__).resolve().parent / "compile_split.py"],
)  # fmt: skip

# ---- status codes (kernel -> front door; messages in nsdyn.solve.integrate.MESSAGES) -------------
ST_SUCCESS = 0  # reached the last output time
ST_STEP_UNDERFLOW = -1  # step size fell below the floor
ST_MAX_STEPS = -2  # step budget exhausted
ST_NONFINITE = -3  # NaN/inf in the state or right-hand side
ST_SINGULAR = -4  # constraint system (contacts + stuck isolators) singular
ST_NEWTON = -5  # fixed-step Newton iteration diverged / did not converge
ST_UPLIFT = -6  # a normal force reached zero (uplift) with uplift="raise"
ST_LU_SINGULAR = -7  # iteration matrix singular
ST_EVENTS = -8  # too many switching events at (nearly) one instant, or event buffer full

# ---- integer statistics, float info ---------------------------------------------------------
S_STATUS, S_NSTEP, S_NREJ, S_NFEV, S_NJEV, S_NLU, S_NOUT, S_NEVENT, S_CONTACT = range(9)
N_STATS = 9
R_T, R_H, R_RES = 0, 1, 2  # time of stop, last step size, last Newton residual
R_HNEXT = 3  # step size to continue with (next proposed step; dt for fixed steps)
N_RINFO = 4

UPLIFT_RAISE, UPLIFT_WARN = 0, 1

# ---- tuning constants --------------------------------------------------------------------------
MIN_STEP = 1e-12  # s, absolute floor of the step size (plus 10 ulp of t)
NEWTON_DIV_RATE = 1.0  # contraction rate above which a Newton iteration counts as diverging


@njit(cache=True, error_model="numpy")
def step_floor(t):
    """Smallest admissible step at time ``t``: MIN_STEP or 10 ulp of t, whichever is larger."""
    return max(MIN_STEP, 10.0 * 2.220446049250313e-16 * abs(t))


@njit(cache=True, error_model="numpy", inline="always")
def next_kink(t, P):
    """First sample time of a tabulated ground record strictly after ``t`` (inf if none).

    The record is interpolated linearly, so the right-hand side has a kink at every sample:
    adaptive steps end on them (as SUNDIALS' tstop / diffrax's jump_ts) instead of being
    rejected and shrunk around each one.
    """
    if P[ks.I_IPAR][ks.K_GROUND] != ks.GROUND_TABLE:
        return np.inf
    npts = P[ks.I_AH].shape[0]
    if npts == 0:
        return np.inf
    gp = P[ks.I_GPAR]
    t0 = gp[ks.G_T0]
    dt = gp[ks.G_DT]
    k = np.floor((t - t0) / dt) + 1.0
    if k < 0.0:
        k = 0.0
    tk = t0 + k * dt
    if tk <= t + 1e-9 * dt:
        k += 1.0
        tk = t0 + k * dt
    if k > npts - 1:
        return np.inf
    return tk


@njit(cache=True, error_model="numpy")
def largest(a):
    """The largest entry of a non-empty vector of finite values (``np.max`` without its
    temporaries: callable from a loop without reference counts, :data:`nsdyn._kaddress.NO_NRT`)."""
    m = a[0]
    for i in range(1, a.shape[0]):
        if a[i] > m:
            m = a[i]
    return m


@njit(cache=True, error_model="numpy")
def scaled_rms(e, y0, y1, atol, rtol):
    """RMS norm of ``e / (atol + rtol max(|y0|, |y1|))``."""
    n = e.shape[0]
    s = 0.0
    for i in range(n):
        sc = atol[i] + rtol * max(abs(y0[i]), abs(y1[i]))
        s += (e[i] / sc) ** 2
    return np.sqrt(s / n)


@njit(cache=True, error_model="numpy", inline="always")
def finite_input(t, x, out):
    """False (out NaN-filled) for a non-finite state or time: the system kernel never sees
    NaN (its minimum-norm fallback would only return NaN)."""
    if all_finite(x) and np.isfinite(t):
        return True
    out[:] = np.nan
    return False


@njit(cache=True, error_model="numpy", inline="always")
def first_order(x, qdd, out):
    """out = [qd, qdd] from the state x = [q, qd] and the accelerations."""
    n = qdd.shape[0]
    for i in range(n):
        out[i] = x[n + i]
        out[n + i] = qdd[i]


@njit(cache=True, error_model="numpy", inline="always")
def feval(t, x, P, out, qdd, lam, tau, modes):
    """out = [qd, qdd] at (t, x), also normal forces ``lam``, friction ``tau`` and ``modes``.

    Returns the kernel's ok flag (False: singular constraint system or non-finite input).
    """
    if not finite_input(t, x, out):
        return False
    ok = ks.evaluate(t, x, P, qdd, lam, tau, modes)
    first_order(x, qdd, out)
    return ok


@njit(cache=True, error_model="numpy")
def feval_called(t, x, P, out, qdd, lam, tau, modes):
    """:func:`feval` compiled once and called, for the sites off the hot loops (the start, the
    first step size, the rare fallbacks): numba types and lowers an inlined function again at
    every call site, which adds up to seconds of a first run's compilation."""
    return feval(t, x, P, out, qdd, lam, tau, modes)


@njit(cache=True, error_model="numpy")
def jeval(t, x, P, J):
    """Analytic Jacobian at (t, x) into J; NaN-filled (False) for a non-finite state."""
    if not all_finite(x):
        J[:, :] = np.nan
        return False
    ks.jac(t, x, P, J)
    return True


@ka.compiled_only
def jac_table(t, x, P, J):
    """:func:`nsdyn.models.isolated._kernel.jac` with the system kernel and the Jacobian's
    own kernel (:func:`sys_jac_at`) called by their addresses
    (``"sys.evaluate"``, ``"sys.jac_at"``): compiled without a copy of either, so beside
    them."""
    qdd, lam, tau, modes = ks.outputs(P)
    ka.tcall("sys.evaluate", (t, x, P, qdd, lam, tau, modes))
    ka.tcall("sys.jac_at", (t, x, P, J, lam, modes))


# the system kernel and its Jacobian by address (:func:`nsdyn._kaddress.tcall`): the kernels
# of the event-driven loop call them so, each of which would otherwise link (and LLVM optimise
# and translate again) its own copy of the ~250-block system kernel (its rows below)
_DECLARE = "nsdyn.solve.compile_split:event_callees"
ka.tslot("sys.jac", jac_table, _DECLARE)


@njit(cache=True, error_model="numpy", inline="always")
def assemble_t(t, x, P, s, stuck, a0, Bt, Crow, b):
    """The system kernel's assembly (:func:`nsdyn.models.isolated._kernel._assemble`) by its
    address (``"sys.assemble"``)."""
    return ka.tcall("sys.assemble", (t, x, P, s, stuck, a0, Bt, Crow, b))


@njit(cache=True, error_model="numpy", inline="always")
def solve_small_t(A, y, m):
    """:func:`nsdyn._klinalg.solve_small` by its address (``"sys.solve_small"``)."""
    return ka.tcall("sys.solve_small", (A, y, m))


@njit(cache=True, error_model="numpy", inline="always")
def pinv_into_t(A, m, out, U, V, s2):
    """:func:`nsdyn._klinalg.pinv_into` by its address (``"sys.pinv"``)."""
    ka.tcall("sys.pinv", (A, m, out, U, V, s2))


# the system kernel and its Jacobian's own kernel of the table (rows "sys.evaluate",
# "sys.jac_at"): the sources of nsdyn.models.isolated._kernel.evaluate and jac_at, with the
# assembly, the small solve and the pseudo-inverse called by their addresses instead of
# linked, so each compiles once, beside them: a linked copy was LLVM optimised and translated
# again in each kernel, half of its code (docs/dev/first-runs.md)
_inline = njit(cache=True, error_model="numpy", inline="always")
_pinv_t = _inline(ka.specialised(ks._pinv, "_pinv_t", pinv_into=pinv_into_t))
_by_address = {"_assemble": assemble_t, "solve_small": solve_small_t, "_pinv": _pinv_t}
_solve_t = _inline(ka.specialised(ks._solve, "_solve_t", **_by_address))
sys_evaluate = ka.compiled_uncounted(ka.specialised(ks.evaluate, "sys_evaluate", _solve=_solve_t))
sys_jac_at = ka.compiled_uncounted(ka.specialised(ks.jac_at, "sys_jac_at", **_by_address))
ka.tslot("sys.evaluate", sys_evaluate, _DECLARE)
ka.tslot("sys.jac_at", sys_jac_at, _DECLARE)
ka.tslot("sys.assemble", ks._assemble, _DECLARE)
ka.tslot("sys.solve_small", kl.solve_small, _DECLARE)
ka.tslot("sys.pinv", kl.pinv_into, _DECLARE)
# the rows of the system kernel and what it calls by address, then of its Jacobian (by
# address, its own kernel), and their kernels: what a run that calls them needs compiled
EVALUATE_ROWS = ("sys.evaluate", "sys.assemble", "sys.solve_small", "sys.pinv")
SYSTEM_ROWS = (*EVALUATE_ROWS, "sys.jac", "sys.jac_at")
EVALUATE_KERNELS = tuple(ka.TSLOTS[name] for name in EVALUATE_ROWS)
JAC_KERNELS = tuple(ka.TSLOTS[name] for name in SYSTEM_ROWS[len(EVALUATE_ROWS) :])


@njit(cache=True, error_model="numpy")
def evaluate_many_t(t, X, P, QDD, LAM, TAU, MODES):
    """:func:`nsdyn.models.isolated._kernel.evaluate_many` with the system kernel called by its
    address (``"sys.evaluate"``): the response metrics of a run whose loop compiled the system
    kernel compile only this loop, not a second copy of it. Returns the number of states
    where the solve failed."""
    qdd, lam, tau, modes = ks.outputs(P)
    bad = 0
    for k in range(t.shape[0]):
        if not ka.tcall("sys.evaluate", (t[k], X[k], P, qdd, lam, tau, modes)):
            bad += 1
        ks.store_row(k, QDD, LAM, TAU, MODES, qdd, lam, tau, modes)
    return bad


@njit(cache=True, error_model="numpy", inline="always")
def feval_t(t, x, P, out, qdd, lam, tau, modes):
    """:func:`feval` with the system kernel called by its address in the table of
    :mod:`nsdyn._kaddress` (``"sys.evaluate"``)."""
    if not finite_input(t, x, out):
        return False
    ok = ka.tcall("sys.evaluate", (t, x, P, qdd, lam, tau, modes))
    first_order(x, qdd, out)
    return ok


@njit(cache=True, error_model="numpy", inline="always")
def jeval_t(t, x, P, J):
    """:func:`jeval` with the system kernel's Jacobian called by its address in the table of
    :mod:`nsdyn._kaddress` (``"sys.jac"``)."""
    if not all_finite(x):
        J[:, :] = np.nan
        return False
    ka.tcall("sys.jac", (t, x, P, J))
    return True


@njit(cache=True, error_model="numpy")
def check_contacts(t_old, t_new, lam_old, lam_new, upl_t, uplift_mode, stats, rinfo):
    """Record the first uplift (lam_k <= 0) of every contact; True if the run must stop.

    The uplift instant is interpolated linearly in lam between the two step ends.
    """
    stop = False
    t_first = np.inf
    for k in range(lam_new.shape[0]):
        if lam_new[k] <= 0.0 and np.isnan(upl_t[k]):
            lo = lam_old[k]
            tk = t_new
            if lo > 0.0 and t_new > t_old:
                tk = t_old + (t_new - t_old) * lo / (lo - lam_new[k])
            upl_t[k] = tk
            if uplift_mode == UPLIFT_RAISE and tk < t_first:
                t_first = tk
                stats[S_STATUS] = ST_UPLIFT
                stats[S_CONTACT] = k
                rinfo[R_T] = tk
                stop = True
    return stop


@ka.compiled_uncounted
def advance(t, t_new, y, ynew, lam_old, lam, iout, upl_t, uplift_mode, stats, rinfo):
    """Bookkeeping of an accepted step [t, t_new] whose outputs up to ``iout`` are written:
    the contact check, then y = ynew, lam_old = lam and the time reached (unless stopped).

    Returns True when the run must stop (uplift with ``uplift="raise"``).
    """
    stats[S_NOUT] = iout
    stop = check_contacts(t, t_new, lam_old, lam, upl_t, uplift_mode, stats, rinfo)
    if not stop:
        rinfo[R_T] = t_new
    copy_vec(y, ynew)
    copy_vec(lam_old, lam)
    return stop


@njit(cache=True, error_model="numpy")
def start(t, y, P, f, qdd, lam, tau, modes, t_eval, X, lam_old, upl_t, uplift_mode, stats, rinfo):
    """The common start of every integrator at (t, y): f = f(t, y) (with lam, tau, modes),
    the outputs at t_eval <= t written to X, lam_old = lam, and the contact check.

    Returns the index of the first output still to write, or -1 when the run stops here
    (status set in ``stats``: non-finite start, singular constraints, or uplift).
    """
    ok = feval_called(t, y, P, f, qdd, lam, tau, modes)
    return start_from(ok, t, y, f, lam, t_eval, X, lam_old, upl_t, uplift_mode, stats, rinfo)


@ka.compiled_uncounted
def start_from(ok, t, y, f, lam, t_eval, X, lam_old, upl_t, uplift_mode, stats, rinfo):
    """:func:`start` once the caller has evaluated f = f(t, y) and lam (``ok``: its flag)."""
    stats[S_NFEV] += 1
    if not (all_finite(y) and all_finite(f)):
        stats[S_STATUS] = ST_NONFINITE
        return -1
    if not ok:
        stats[S_STATUS] = ST_SINGULAR
        return -1
    copy_vec(lam_old, lam)
    iout = 0
    while iout < t_eval.shape[0] and t_eval[iout] <= t:
        copy_vec(X[iout], y)
        iout += 1
    stats[S_NOUT] = iout
    if check_contacts(t, t, lam, lam, upl_t, uplift_mode, stats, rinfo):
        return -1
    return iout


@njit(cache=True, error_model="numpy")
def initial_step(t0, y0, f0, t_end, max_step, order, rtol, atol, P, y1, f1, qdd, lam, tau, modes):
    """Starting step size (Hairer, Norsett & Wanner I, sec. II.4; as scipy's
    ``select_initial_step``). Costs one right-hand side evaluation."""
    h0 = initial_probe(t0, y0, f0, t_end, rtol, atol, y1)
    if h0 == 0.0:
        return 0.0
    feval_called(t0 + h0, y1, P, f1, qdd, lam, tau, modes)
    return initial_finish(h0, y0, f0, f1, t_end - t0, max_step, order, rtol, atol)


@ka.compiled_uncounted
def initial_probe(t0, y0, f0, t_end, rtol, atol, y1):
    """First half of :func:`initial_step`: the trial step h0 (0.0 for an empty interval) and
    the Euler state ``y1 = y0 + h0 f0`` at which the caller evaluates ``f1``."""
    n = y0.shape[0]
    length = abs(t_end - t0)
    if length == 0.0:
        return 0.0
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        sc = atol[i] + abs(y0[i]) * rtol
        d0 += (y0[i] / sc) ** 2
        d1 += (f0[i] / sc) ** 2
    d0 = np.sqrt(d0 / n)
    d1 = np.sqrt(d1 / n)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, length)
    for i in range(n):
        y1[i] = y0[i] + h0 * f0[i]
    return h0


@ka.compiled_uncounted
def initial_finish(h0, y0, f0, f1, length, max_step, order, rtol, atol):
    """Second half of :func:`initial_step`, given ``f1 = f(t0 + h0, y1)``."""
    n = y0.shape[0]
    length = abs(length)
    d1 = 0.0
    d2 = 0.0
    for i in range(n):
        sc = atol[i] + abs(y0[i]) * rtol
        d1 += (f0[i] / sc) ** 2
        d2 += ((f1[i] - f0[i]) / sc) ** 2
    d1 = np.sqrt(d1 / n)
    d2 = np.sqrt(d2 / n) / h0
    if not np.isfinite(d2):
        return max(MIN_STEP, h0 * 1e-3)
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (order + 1))
    return min(100.0 * h0, h1, length, max_step)
