"""Steady states through the uplift band: the stepped sweep with unilateral isolator contact.

Where the bilateral orbit of a frequency-response curve has a normal force ``lam_k <= 0`` (the
seed's model outside its validity), the isolators lift off. The flow is then event-driven:
between events the constrained equations with the closed contacts (seed 004, eqs 8-15, Radau);
at a lift-off (``lam_k = 0`` falling) contact ``k`` opens, its gap ``g_k = R_k q`` is tracked
and it carries neither normal force nor friction; at a landing (``g_k = 0`` closing) Newton's
law ``v_n+ = -e v_n-`` applies through an impulse (``nsdyn.solve`` with
``contact="unilateral"``). Shooting through those events would need saltation matrices at
every lift-off and landing; here whole periods ``T = 1 / f`` are integrated instead, from the
bilateral orbit's start, until the Poincare map ``x(kT)`` settles -- the test of
:func:`nsdyn.periodic.sweeps.steady_state_sweep`: with ``delta_k = |x(kT) - x((k-1)T)|`` per
block relative to the period's excursion and ``rho = delta_k / delta_(k-1)``, steady when
``delta_k rho / (1 - rho) < tol``; a change per period that stops contracting ends the sweep
early (not a period-1 response).

The quantities of the last period come from the response metrics with the open-contact
history (accelerations of the free flight and of the contact phases): peak IDR, peak absolute
acceleration (all levels / floors above the base), half the peak-to-peak isolator slip, the
smallest normal force of the closed contacts, and the uplift measures: the fraction of the
period with a contact open, lift-offs and landings per period, the largest landing impulse
[N s] and landing velocity [m/s].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from nsdyn.periodic.protocol import check_frequency
from nsdyn.periodic.sweeps import stagnated

UNI_TOL = 1e-4  # steady-state test of the unilateral sweep (relative change per period)
UNI_MAX_PERIODS = 80  # longest unilateral sweep [periods]
UNI_SAMPLES = 200  # output samples per period (metrics of the last period)
UNI_BUDGET_S = 30.0  # wall-time budget of one point [s] (a chattering flight is slow)
EXCURSION_FLOOR = 1e-9  # floor of the per-block excursions (a period at rest)


@dataclass
class UnilateralPoint:
    """Outcome of the unilateral stepped sweep at frequency ``f``."""

    f: float
    steady: bool
    periods: int
    estimate: float  # estimated relative distance to the steady state
    message: str
    quantities: dict = field(default_factory=dict)
    x_end: np.ndarray | None = None  # full state [q, qd] at the end (next point's start)
    open_end: np.ndarray | None = None  # contact states at the end (1 open)


def unilateral_steady_state(
    problem,
    f: float,
    x0_full: np.ndarray,
    *,
    open0=None,
    restitution: float = 0.0,
    tol: float = UNI_TOL,
    max_periods: int = UNI_MAX_PERIODS,
    samples: int = UNI_SAMPLES,
    budget_s: float = UNI_BUDGET_S,
) -> UnilateralPoint:
    """Integrate whole periods of the frame ``problem``
    (:func:`nsdyn.periodic.frame_problem`) at ``f`` with lift-off and landing from the full
    state ``x0_full`` (contact states ``open0``) until the Poincare map settles (module
    text); ``restitution``: Newton's e of a landing; ``budget_s``: wall time after which
    the sweep stops, not steady, and says so."""
    import time

    from nsdyn.solve.integrate import solve

    t_start = time.perf_counter()
    if problem.system is None:
        raise ValueError("the unilateral sweep needs a frame problem (frame_problem(system, A))")
    T = 1.0 / check_frequency(f)
    P, _ = problem.at(f)
    n = problem.system.n
    x = np.array(x0_full, dtype=float)
    op = None if open0 is None else np.asarray(open0, dtype=np.int64)
    h0 = None
    d_old = math.inf
    est = math.inf
    deltas: list[float] = []
    steady = False
    note = ""
    sol = None
    k = 0
    for k in range(1, max_periods + 1):
        t = (k - 1) * T + np.linspace(0.0, T, samples + 1)
        kw = {} if h0 is None else {"h0": h0}
        sol = solve(
            P, x, t, method="radau", contact="unilateral", restitution=restitution,
            open0=op, on_failure="return", **kw,
        )  # fmt: skip
        if not sol.success:
            t_fail = sol.t[-1] if sol.t.size else t[0]
            note = f"period {k} failed at t = {t_fail:.4g} s: {sol.message}"
            break
        X = sol.x
        exc_q = max(float(np.ptp(X[:, :n], axis=0).max()), EXCURSION_FLOOR)
        exc_v = max(float(np.ptp(X[:, n:], axis=0).max()), EXCURSION_FLOOR)
        dx = np.abs(X[-1] - x)
        delta = max(float(dx[:n].max()) / exc_q, float(dx[n:].max()) / exc_v)
        rho = delta / d_old if math.isfinite(d_old) and d_old > 0 else math.inf
        est = delta * min(rho / (1.0 - rho), 1e3) if rho < 1.0 else math.inf
        x, op, h0 = X[-1].copy(), sol.open_end, sol.h_last or None
        if k >= 3 and (est < tol or delta < 0.01 * tol):
            steady = True
            est = min(est, delta)
            break
        deltas.append(delta)
        if len(deltas) >= 30 and stagnated(deltas, k, max_periods, tol, window=20):
            note = "the change per period no longer contracts (not a period-1 response)"
            break
        if time.perf_counter() - t_start > budget_s:
            n_ev = len(sol.contact_events)
            note = (
                f"stopped at the {budget_s:g} s budget ({n_ev} contact events in the last period)"
            )
            break
        d_old = delta
    msg = f"{'steady' if steady else 'not steady'} after {k} periods (estimate {est:.1e})"
    if note:
        msg = f"{msg}; {note}"
    q = _quantities(problem, sol, T) if sol is not None and sol.t.size > 1 else {}
    return UnilateralPoint(f, steady, k, float(est), msg, q, x, op)


def _quantities(problem, sol, T: float) -> dict:
    """Metrics of the last integrated period (module text)."""
    from nsdyn.models.isolated.metrics import response
    from nsdyn.solve.transient import general_evaluations

    system = problem.system
    P, _ = problem.at(1.0 / T)
    ev = general_evaluations(P, sol.t, sol.x, sol.open_contacts)
    r = response(system, sol.t, sol.x, P, sol.open_contacts, evaluated=ev)
    xi = r.x_iso
    opened = sol.open_contacts if sol.open_contacts is not None else np.zeros((sol.t.size, 1))
    closed = opened == 0
    lam = np.where(closed, r.lam, np.inf) if r.lam.size else r.lam
    lifts = [e for e in sol.contact_events if e[2] == "lift-off"]
    lands = [e for e in sol.contact_events if e[2] == "landing"]
    acc = r.floor_acc_by_level
    return {
        "idr": r.idr_max,
        "acc": float(np.max(acc)) if acc.size else math.nan,
        "acc_floors": r.floor_acc_max,
        "x_iso": float(0.5 * np.max(np.ptp(xi, axis=0))) if xi.size else 0.0,
        "min_normal_force": float(np.min(lam)) if lam.size and np.isfinite(lam).any() else math.nan,
        "flight_fraction": float(np.mean(np.any(opened != 0, axis=1))),
        "lift_offs_per_period": len(lifts),
        "landings_per_period": len(lands),
        "max_landing_impulse_Ns": max((abs(e[4]) for e in lands), default=0.0),
        "max_landing_velocity_mps": max((abs(e[3]) for e in lands), default=0.0),
        "stick_all_period": False,
        "uplift": True,
    }


def unilateral_rows(problem, points: list, rows: list[dict], progress=None, **options) -> int:
    """Recompute the uplift points of a bilateral curve (``points`` of
    :class:`nsdyn.periodic.curve.OrbitPoint` and their CSV ``rows``, in frequency order) with
    :func:`unilateral_steady_state`: each starts from the previous unilateral point's end
    state when the previous point was one too (following the branch), else from its own
    bilateral orbit. The rows get the unilateral quantities, ``method = "unilateral"``,
    ``converged`` = steady and the sweep's message as note. Returns the count recomputed."""
    prev = None
    done = 0
    for pt, row in zip(points, rows, strict=True):
        if row.get("uplift") is not True or pt.x0 is None:
            prev = None
            continue
        if prev is not None:
            x_start, open0 = prev.x_end, prev.open_end
        else:
            x_start, open0 = problem.to_full(pt.x0), None
        u = unilateral_steady_state(problem, pt.f, x_start, open0=open0, **options)
        q = u.quantities
        row.update(
            IDR=q.get("idr", math.nan),
            a=q.get("acc", math.nan),
            a_floors=q.get("acc_floors", math.nan),
            x_iso=q.get("x_iso", math.nan),
            stick_all_period=False,
            stable="",
            max_multiplier_modulus=math.nan,
            method="unilateral",
            newton_iterations=0,
            residual=u.estimate,
            converged=u.steady,
            flight_fraction=q.get("flight_fraction", math.nan),
            lift_offs_per_period=q.get("lift_offs_per_period", ""),
            max_landing_impulse_Ns=q.get("max_landing_impulse_Ns", math.nan),
            note=u.message,
        )
        prev = u if u.steady else None
        done += 1
        if progress is not None:
            progress(pt.f, u)
    return done
