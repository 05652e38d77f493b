"""Steady states by plain time integration: the stepped-sweep fallback and the warm start.

Whole forcing periods are integrated, ``x_(k+1) = phi_T(x_k)``, until the Poincare map is
stationary. Near a stable orbit the change ``delta_k = |x_k - x_(k-1)|`` (per block, relative
to the orbit's excursion) contracts geometrically, ``delta_(k+1) ~ rho delta_k`` with ``rho``
the largest multiplier's modulus, so the distance left to the steady state is

    |x_k - x*| ~ delta_k rho / (1 - rho).

This is the fallback where shooting fails and the start of a curve (a few periods from rest
before the first Newton solve). It uses only the period map of a
:class:`nsdyn.periodic.protocol.PeriodicModel`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nsdyn._brief import brief_repr
from nsdyn._checks import flag, number, whole
from nsdyn.periodic.discretisation import Discretisation, checked_disc
from nsdyn.periodic.protocol import (
    STATUS_MESSAGES,
    STATUS_NOT_STEADY,
    STATUS_OK,
    PeriodicModel,
    check_frequency,
    check_map_args,
)
from nsdyn.periodic.shooting import orbit_amplitudes

SS_TOL = 1e-6  # steady-state test of the sweep fallback (estimated distance, relative)
SS_MAX_PERIODS = 400  # longest sweep fallback [periods]
SS_MAX_TIME = 4000.0  # ... and [s] of simulated time
SS_RHO_CAP = 1e3  # largest extrapolation factor rho / (1 - rho) of the steady-state estimate
WARMUP_PERIODS = 2  # plain periods integrated before the first shooting solve
SS_WINDOW = 50  # periods over which the sweep measures its contraction (stagnation test)


@dataclass(repr=False)
class SweepResult:
    """Outcome of a stepped sweep at frequency ``f``."""

    __repr__ = brief_repr  # arrays by shape, not in full

    f: float
    x0: np.ndarray  # state at the start of the last period
    X: np.ndarray  # last period
    periods: int
    estimate: float  # estimated distance to the steady state (relative)
    steady: bool
    monodromy: np.ndarray | None
    n_steps: int
    message: str
    periods_done: int = 0  # periods integrated successfully (X is the last of them)
    status: int = STATUS_OK  # what ended the sweep (STATUS_NOT_STEADY, a period's failure)
    x_stop: np.ndarray | None = None  # start of the period that could not be integrated


def steady_state_sweep(
    problem: PeriodicModel,
    f: float,
    x0: np.ndarray | None = None,
    *,
    tol: float = SS_TOL,
    max_periods: int = SS_MAX_PERIODS,
    max_time: float = SS_MAX_TIME,
    disc: Discretisation | None = None,
    monodromy: bool = True,
) -> SweepResult:
    """Time-integrate whole periods until the Poincare map ``x(kT)`` is stationary.

    The change ``delta_k = |x(kT) - x((k-1)T)|`` (per block, relative to the orbit's excursion)
    contracts by ``rho = delta_k / delta_(k-1)`` per period; the distance left to the steady
    state is estimated as ``delta_k min(rho / (1 - rho), SS_RHO_CAP)`` and must fall below
    ``tol`` (or ``delta_k`` below ``tol / 100``, the round-off floor). A sweep that cannot get
    there stops early: from period ``2 SS_WINDOW`` on, the contraction over the last window,
    ``r = (max of the last 10 delta / max of the 10 a window earlier)^(1 / SS_WINDOW)``, predicts
    the periods still needed, ``log(tol / delta_k) / log r`` (infinite for ``r >= 1``: a response
    that is not period-1, such as period doubling or a grazing-induced irregular motion); past
    twice the allowed periods it is "not steady" now. Each period is one kernel
    call (the per-call overhead is < 0.1 % of a period). The last period's monodromy matrix
    (one extra period) is returned as ``result.monodromy``: its eigenvalues
    (:func:`~nsdyn.periodic.shooting.floquet_multipliers`) are an approximate stability verdict.
    """
    f = check_frequency(f)
    x = problem.x_ref.copy() if x0 is None else check_map_args(problem.x_ref, x0, None, disc)
    _check_sweep(tol, max_periods, max_time)
    flag("monodromy", monodromy)
    disc = checked_disc(disc)
    T = 1.0 / f
    N = disc.steps(T)
    kmax = int(max(3, min(max_periods, math.ceil(max_time / T))))
    m = problem.dim // 2
    d_old = math.inf
    est = math.inf
    status = STATUS_NOT_STEADY
    X = None
    x_start = x  # start of the period held in X
    k = 0
    done = 0
    deltas: list[float] = []
    stalled = False
    for k in range(1, kmax + 1):
        pm = problem.period_map(x, f, n_steps=N, disc=disc, sens=False, store=True)
        if pm.status != STATUS_OK:
            status = pm.status
            break
        X = pm.X
        x_start = x
        done += 1
        amp_z, amp_v = orbit_amplitudes(problem, X)
        dx = np.abs(pm.xT - x)
        delta = max(dx[:m].max() / amp_z, dx[m:].max() / amp_v)
        rho = delta / d_old if math.isfinite(d_old) and d_old > 0 else math.inf
        est = delta * min(rho / (1.0 - rho), SS_RHO_CAP) if rho < 1.0 else math.inf
        if k >= 3 and (est < tol or delta < 0.01 * tol):
            status = STATUS_OK
            est = min(est, delta)
            break
        deltas.append(delta)
        if k >= 2 * SS_WINDOW and stagnated(deltas, k, kmax, tol):
            stalled = True
            break
        d_old = delta
        x = pm.xT
    steady = status == STATUS_OK
    msg = (
        f"steady after {k} periods (estimate {est:.1e})"
        if steady
        else f"{STATUS_MESSAGES[int(status)]} ({k} periods, estimate {est:.1e})"
    )
    if stalled:
        msg += (
            f"; stopped early: the change per period no longer contracts (still {deltas[-1]:.1e}"
            f" after {k} periods; not a period-1 response, or one too slow to reach)"
        )
    x_stop = None if status in (STATUS_OK, STATUS_NOT_STEADY) else x
    x = x_start  # x0 and the monodromy belong to the period returned in X
    M = None
    if monodromy and status in (STATUS_OK, STATUS_NOT_STEADY) and X is not None:
        pm = problem.period_map(x, f, n_steps=N, disc=disc, sens=True)
        if pm.status == STATUS_OK:
            M = pm.monodromy
    if X is None:
        X = np.vstack([x, x])
    return SweepResult(f, x, X, int(k), float(est), steady, M, N, msg, done, int(status), x_stop)


def _check_sweep(tol, max_periods, max_time) -> None:
    """The numbers of :func:`steady_state_sweep`, named when it cannot run on them (a tol of
    -1 ended in a math domain error; 0 periods or a negative time ran 3 periods)."""
    number("tol", tol, "a positive finite steady-state tolerance", lambda v: v > 0)
    whole("max_periods", max_periods, 1, "a whole number of periods >= 1")
    number("max_time", max_time, "a positive finite time [s]", lambda v: v > 0)


def stagnated(deltas: list, k: int, kmax: int, tol: float, window: int = SS_WINDOW) -> bool:
    """True when the contraction of the changes per period ``deltas`` over the last ``window``
    periods cannot bring them below ``tol`` within twice the ``kmax`` periods allowed (see
    :func:`steady_state_sweep`); needs ``len(deltas) >= window + 10``."""
    now = max(deltas[-10:])
    then = max(deltas[-window - 10 : -window])
    if not (now > 0.0 and then > 0.0):
        return False
    r = (now / then) ** (1.0 / window)
    if r >= 1.0:
        return True
    return k + math.log(tol / now) / math.log(r) > 2 * kmax


def warm_start(
    problem: PeriodicModel,
    f: float,
    x0: np.ndarray | None,
    disc: Discretisation | None,
    periods: int = WARMUP_PERIODS,
) -> np.ndarray:
    """A shooting guess at ``f``: ``periods`` periods integrated from ``x0`` (None: the static
    state), stopping early if a period cannot be integrated."""
    x = problem.x_ref.copy() if x0 is None else check_map_args(problem.x_ref, x0, None, disc)
    whole("periods", periods, 0, "a whole number of periods >= 0")
    for _ in range(periods):
        pm = problem.period_map(x, f, disc=disc, sens=False)
        if pm.status != STATUS_OK:
            break
        x = pm.xT
    return x
