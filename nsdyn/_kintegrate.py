"""Shared numba pieces of the integrators: status codes, norms, dense LU, contact monitor.

The steppers live in :mod:`nsdyn._kdopri` (explicit Dormand-Prince 5(4)), :mod:`nsdyn._kradau`
(Radau IIA order 5), :mod:`nsdyn._kgenalpha` (generalized-alpha family) and
:mod:`nsdyn._kevent` (event-driven switch model on the Radau stepper). Each runs its whole time
loop inside numba and calls the system kernels of :mod:`nsdyn._ksystem` as module globals (never
as arguments: a jitted function passed as an argument defeats numba's on-disk cache).

Every stepper reports through two small arrays: ``stats`` (int64, layout ``S_*``) and ``rinfo``
(float64, layout ``R_*``); the front door :mod:`nsdyn.integrate` turns them into a ``Solution``.
"""

import hashlib
import os
from pathlib import Path

import numpy as np
from numba import njit

from . import _ksystem as ks

# integrator kernel modules (numba-cached) and every source their compiled code depends on
KERNEL_MODULES = ("_kintegrate", "_kdopri", "_kradau", "_kgenalpha", "_kevent")
KERNEL_SOURCES = ("_ksystem",) + KERNEL_MODULES
CACHE_STAMP = "nsdyn_integrators.sha1"  # fingerprint of KERNEL_SOURCES in __pycache__


def _drop_stale_caches() -> None:
    """Delete our numba cache files when any kernel source changed since they were written.

    numba invalidates a cached function only when its *own* file changes, not when a callee
    in another file does: after an edit of ``_ksystem.py`` the integrators would silently keep
    the old system kernels compiled in. Runs at import, before any kernel is loaded.
    """
    here = Path(__file__).resolve().parent
    try:
        h = hashlib.sha1()
        for m in KERNEL_SOURCES:
            h.update((here / f"{m}.py").read_bytes())
        digest = h.hexdigest()
        stamp = here / "__pycache__" / CACHE_STAMP
        if stamp.is_file() and stamp.read_text() == digest:
            return
        dirs = [here / "__pycache__"]
        if os.environ.get("NUMBA_CACHE_DIR"):
            dirs.append(Path(os.environ["NUMBA_CACHE_DIR"]))
        for d in dirs:
            if d.is_dir():
                for m in KERNEL_MODULES:
                    for f in d.rglob(f"{m}.*.nb[ic]"):
                        f.unlink(missing_ok=True)
        stamp.parent.mkdir(exist_ok=True)
        stamp.write_text(digest)
    except OSError:  # read-only install or a concurrent cleaner: numba's own checks remain
        pass


_drop_stale_caches()

# ---- status codes (kernel -> front door; messages in nsdyn.integrate.MESSAGES) -------------
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


@njit(cache=True)
def step_floor(t):
    """Smallest admissible step at time ``t``: MIN_STEP or 10 ulp of t, whichever is larger."""
    return max(MIN_STEP, 10.0 * 2.220446049250313e-16 * abs(t))


@njit(cache=True)
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


@njit(cache=True, inline="always")
def all_finite(a):
    for i in range(a.shape[0]):
        if not np.isfinite(a[i]):
            return False
    return True


@njit(cache=True)
def scaled_rms(e, y0, y1, atol, rtol):
    """RMS norm of ``e / (atol + rtol max(|y0|, |y1|))``."""
    n = e.shape[0]
    s = 0.0
    for i in range(n):
        sc = atol[i] + rtol * max(abs(y0[i]), abs(y1[i]))
        s += (e[i] / sc) ** 2
    return np.sqrt(s / n)


@njit(cache=True, inline="always")
def feval(t, x, P, out, qdd, lam, tau, modes):
    """out = [qd, qdd] at (t, x), also normal forces ``lam``, friction ``tau`` and ``modes``.

    Returns the kernel's ok flag (False: singular constraint system).
    """
    n = qdd.shape[0]
    if not (all_finite(x) and np.isfinite(t)):
        # never hand NaN to the system kernel (its pinv fallback raises on NaN)
        out[:] = np.nan
        return False
    ok = ks.evaluate(t, x, P, qdd, lam, tau, modes)
    for i in range(n):
        out[i] = x[n + i]
        out[n + i] = qdd[i]
    return ok


@njit(cache=True, inline="always")
def feval_inline(t, x, P, out, qdd, lam, tau, modes):
    """:func:`feval` with the system kernel inlined (for the hottest call site only)."""
    n = qdd.shape[0]
    if not (all_finite(x) and np.isfinite(t)):
        out[:] = np.nan
        return False
    ok = ks.evaluate_inline(t, x, P, qdd, lam, tau, modes)
    for i in range(n):
        out[i] = x[n + i]
        out[n + i] = qdd[i]
    return ok


@njit(cache=True)
def jeval(t, x, P, J):
    """Analytic Jacobian at (t, x) into J; NaN-filled (False) for a non-finite state."""
    if not all_finite(x):
        J[:, :] = np.nan
        return False
    ks.jac(t, x, P, J)
    return True


@njit(cache=True)
def lu_factor(A, piv):
    """In-place LU with partial pivoting of a dense square matrix (real or complex).

    Returns False on an exactly zero or non-finite pivot.
    """
    n = A.shape[0]
    for k in range(n):
        p = k
        amax = abs(A[k, k])
        for i in range(k + 1, n):
            a = abs(A[i, k])
            if a > amax:
                amax = a
                p = i
        piv[k] = p
        if amax == 0.0 or not np.isfinite(amax):
            return False
        if p != k:
            for j in range(n):
                tmp = A[k, j]
                A[k, j] = A[p, j]
                A[p, j] = tmp
        inv = 1.0 / A[k, k]
        for i in range(k + 1, n):
            f = A[i, k] * inv
            A[i, k] = f
            if f != 0.0:
                for j in range(k + 1, n):
                    A[i, j] -= f * A[k, j]
    return True


@njit(cache=True)
def lu_solve(LU, piv, b):
    """Solve in place with the factors of :func:`lu_factor`."""
    n = LU.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
    for i in range(n):
        s = b[i]
        for j in range(i):
            s -= LU[i, j] * b[j]
        b[i] = s
    for i in range(n - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, n):
            s -= LU[i, j] * b[j]
        b[i] = s / LU[i, i]


@njit(cache=True)
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


@njit(cache=True)
def start(t, y, P, f, qdd, lam, tau, modes, t_eval, X, lam_old, upl_t, uplift_mode, stats, rinfo):
    """The common start of every integrator at (t, y): f = f(t, y) (with lam, tau, modes),
    the outputs at t_eval <= t written to X, lam_old = lam, and the contact check.

    Returns the index of the first output still to write, or -1 when the run stops here
    (status set in ``stats``: non-finite start, singular constraints, or uplift).
    """
    ok = feval(t, y, P, f, qdd, lam, tau, modes)
    stats[S_NFEV] += 1
    if not (all_finite(y) and all_finite(f)):
        stats[S_STATUS] = ST_NONFINITE
        return -1
    if not ok:
        stats[S_STATUS] = ST_SINGULAR
        return -1
    lam_old[:] = lam
    iout = 0
    while iout < t_eval.shape[0] and t_eval[iout] <= t:
        X[iout] = y
        iout += 1
    stats[S_NOUT] = iout
    if check_contacts(t, t, lam, lam, upl_t, uplift_mode, stats, rinfo):
        return -1
    return iout


@njit(cache=True)
def initial_step(t0, y0, f0, t_end, max_step, order, rtol, atol, P, y1, f1, qdd, lam, tau, modes):
    """Starting step size (Hairer, Norsett & Wanner I, sec. II.4; as scipy's
    ``select_initial_step``). Costs one right-hand side evaluation."""
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
    feval(t0 + h0, y1, P, f1, qdd, lam, tau, modes)
    d2 = 0.0
    for i in range(n):
        sc = atol[i] + abs(y0[i]) * rtol
        d2 += ((f1[i] - f0[i]) / sc) ** 2
    d2 = np.sqrt(d2 / n) / h0
    if not np.isfinite(d2):
        return max(MIN_STEP, h0 * 1e-3)
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (order + 1))
    return min(100.0 * h0, h1, length, max_step)
