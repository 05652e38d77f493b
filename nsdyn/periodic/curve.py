"""Frequency-response curves: one periodic orbit per point, with its provenance and stability.

A point holds the orbit's start ``x0`` at frequency ``f``, the Floquet multipliers ``rho``
(stable when ``max |rho| < 1``; a growth is checked against a second map before it is called
unstable, :mod:`nsdyn.periodic.stability`; none when that check could not decide, the note then
gives the first map's value), the response quantities of its model, and how it was found:
by shooting (``H(x0, f) = phi_T(x0) - x0 = 0`` to the shooting tolerance, sequentially or
along the arclength ``s``) or by the stepped sweep (its residual is then the estimated
distance to the steady state). A curve collects the points of one forcing amplitude and the
bifurcations detected between them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from nsdyn._brief import brief_repr
from nsdyn.periodic.bifurcation import STABLE_MARGIN, family_note
from nsdyn.periodic.discretisation import Discretisation
from nsdyn.periodic.protocol import PeriodicModel
from nsdyn.periodic.shooting import ShootingResult, floquet_multipliers
from nsdyn.periodic.stability import check_verdict
from nsdyn.periodic.sweeps import WARMUP_PERIODS, SweepResult


@dataclass
class OrbitPoint:
    """One periodic solution on a frequency-response curve."""

    f: float
    x0: np.ndarray
    method: str  # "shooting" (sequential), "arclength" or "sweep"
    converged: bool
    iterations: int
    residual: float
    multipliers: np.ndarray
    n_steps: int
    note: str = ""  # why shooting failed (sweep points) or other remarks
    quantities: dict = field(default_factory=dict)
    s: float = float("nan")  # arclength along the curve (arclength points)
    dlogf_ds: float = float("nan")  # tangent's parameter component
    X: np.ndarray | None = field(default=None, repr=False)

    @property
    def max_multiplier(self) -> float:
        return float(np.max(np.abs(self.multipliers))) if self.multipliers.size else math.nan

    @property
    def stable(self) -> bool | None:
        if not self.multipliers.size or not self.converged:  # (no orbit: no verdict on it)
            return None
        return bool(self.max_multiplier < 1.0 + STABLE_MARGIN)


@dataclass(repr=False)
class Curve:
    """A frequency-response curve of periodic solutions at one forcing amplitude."""

    __repr__ = brief_repr  # arrays by shape, not in full

    amplitude: float
    points: list[OrbitPoint]
    bifurcations: list[dict] = field(default_factory=list)
    info: dict = field(default_factory=dict)

    def column(self, name: str) -> np.ndarray:
        """A per-point attribute or quantity as an array (``"f"``, ``"idr"``, ...)."""
        vals = []
        for p in self.points:
            v = p.quantities.get(name) if name in p.quantities else getattr(p, name)
            vals.append(np.nan if v is None else v)
        return np.asarray(vals)

    def rows(self) -> list[dict]:
        """One flat record per point (the sweep CSV)."""
        out = []
        for p in self.points:
            q = p.quantities
            out.append(
                {
                    "f": p.f,
                    "A": self.amplitude,
                    "IDR": q.get("idr", math.nan),
                    "a": q.get("acc", math.nan),
                    "a_floors": q.get("acc_floors", math.nan),
                    "x_iso": q.get("x_iso", math.nan),
                    "stick_all_period": q.get("stick_all_period", ""),
                    "stable": "" if p.stable is None else p.stable,
                    "max_multiplier_modulus": p.max_multiplier,
                    "method": p.method,
                    "newton_iterations": p.iterations,
                    "residual": p.residual,
                    "converged": p.converged,
                    "n_steps": p.n_steps,
                    "uplift": q.get("uplift", ""),
                    "note": p.note,
                }
            )
        return out


def _point_from_shoot(
    problem: PeriodicModel,
    res: ShootingResult,
    method: str,
    note: str = "",
    disc: Discretisation | None = None,
) -> OrbitPoint:
    """A point from a converged shooting solve (``disc``: the map's discretisation; a growth
    is checked, :func:`nsdyn.periodic.stability.check_verdict`)."""
    rho = floquet_multipliers(res.monodromy)
    rho, verdict, why = check_verdict(problem, res.f, res.x0, rho, disc)
    rho = rho if verdict is not None else np.zeros(0)  # undecided: no multipliers (the note)
    q = problem.orbit_quantities(res.f, res.X)
    notes = (note, why, problem.validity_note(q), family_note(rho))
    note = "; ".join(n for n in notes if n)
    return OrbitPoint(
        res.f,
        res.x0.copy(),
        method,
        True,
        res.iterations,
        res.residual,
        rho,
        res.n_steps,
        note,
        q,
        X=res.X,
    )


def _point_from_sweep(
    problem: PeriodicModel, sw: SweepResult, why: str, disc: Discretisation | None = None
) -> OrbitPoint:
    """A point from the stepped sweep; its 'residual' is the estimated distance to the steady
    state. Quantities are NaN, with the model's verdict on uplift, when a period could not be
    integrated: the first one, or a later one that stopped the sweep (the period before it
    would pass for the point's; the deck's loop stops at an uplift). A growth of the last
    period's multipliers is checked as for a shooting point."""
    rho = floquet_multipliers(sw.monodromy) if sw.monodromy is not None else np.zeros(0)
    rho, verdict, check = check_verdict(problem, sw.f, sw.x0, rho, disc)
    rho = rho if verdict is not None or not rho.size else np.zeros(0)
    probe = ""
    stopped = sw.periods_done > 0 and sw.x_stop is not None  # a later period failed
    if sw.periods_done > 0 and not stopped:
        q = problem.orbit_quantities(sw.f, sw.X)
    elif stopped:
        q, probe = problem.quantities_without_orbit(sw.f, sw.x_stop, 1)  # the failing period
    else:
        # the horizon of continuation's retry decision (as many periods as the warm start)
        q, probe = problem.quantities_without_orbit(sw.f, sw.x0, WARMUP_PERIODS)
    notes = (f"shooting failed: {why}", f"sweep: {sw.message}", check, probe,
             problem.validity_note(q))  # fmt: skip
    return OrbitPoint(
        sw.f,
        sw.x0.copy(),
        "sweep",
        sw.steady,
        0,
        sw.estimate,
        rho,
        sw.n_steps,
        "; ".join(n for n in notes if n),
        q,
        X=sw.X if sw.periods_done > 0 and not stopped else None,
    )
