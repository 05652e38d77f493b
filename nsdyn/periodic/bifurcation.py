"""Bifurcations along a curve of periodic orbits, from their Floquet multipliers.

An orbit is stable while every multiplier ``rho`` (eigenvalue of the monodromy) lies inside the
unit circle, ``|rho| < 1``. Between consecutive points of a curve, a change in the number of
multipliers outside it tells which way stability was lost:

    real rho through +1        fold (saddle-node, turning point of the curve)
    real rho through -1        period doubling
    complex pair |rho| = 1     Neimark-Sacker (torus)

The crossing is located by linear interpolation in ``log f`` of ``|rho| - 1``. Along a
pseudo-arclength curve a fold also shows as a turn of ``f(s)``; it is placed at the vertex of
the parabola ``log f(s)`` through the three points around the turn.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from nsdyn.periodic.curve import OrbitPoint

RHO_REAL = 1e-7  # |Im rho| / |rho| below which a multiplier counts as real
STABLE_MARGIN = 1e-9  # stable when max |rho| < 1 + this

KINDS = ("fold", "period-doubling", "Neimark-Sacker")  # in the order of multiplier_counts


def _real(rho: np.ndarray) -> np.ndarray:
    """Which multipliers count as real (|Im rho| / |rho| at most RHO_REAL)."""
    return np.abs(rho.imag) <= RHO_REAL * np.maximum(np.abs(rho), 1e-300)


def multiplier_counts(rho: np.ndarray) -> tuple[int, int, int]:
    """(real > +1, real < -1, complex outside the unit circle) among multipliers ``rho``."""
    real = _real(rho)
    out = np.abs(rho) > 1.0 + STABLE_MARGIN
    return (
        int(np.sum(real & out & (rho.real > 0))),
        int(np.sum(real & out & (rho.real < 0))),
        int(np.sum(~real & out)),
    )


def family_note(rho: np.ndarray) -> str:
    """A note when ``rho`` holds real multipliers at 1 to round-off (a stable-looking orbit
    that is one of a family along a neutral direction: a slip held all period, a stuck
    isolator or a pendulum's surface below its friction, may sit anywhere it stopped; a flat
    slider without a restoring force, anywhere at all), else ""."""
    k = int(np.sum(_real(rho) & (np.abs(rho.real - 1.0) <= STABLE_MARGIN)))
    if not k:
        return ""
    return (f"one of a family of orbits ({k} multiplier{'s' * (k > 1)} at 1: a neutral "
            "direction, a surface stuck all period or a slider without restoring force, keeps "
            "any offset; this orbit keeps the previous point's, so its peaks depend on the "
            "path; a run from rest picks one)")  # fmt: skip


def detect_bifurcations(points: list[OrbitPoint]) -> list[dict]:
    """Bifurcations between consecutive points from changes in the multiplier counts.

    Folds are also located where f turns along an arclength curve (a local extremum of f
    between consecutive points); the fold frequency is the vertex of a parabola log f(s)
    through the three points around the turn, and a change of the multipliers beside that
    turn is the same fold (listed once, by "turning point and multipliers", with the
    multipliers' estimate as ``f_multipliers``). An arclength point and a
    stepped sweep's point (the fallback where the corrector failed) are not neighbours on one
    branch: the sweep lands on whichever orbit attracts, so a change between them is no
    bifurcation and is not listed.
    """
    turns = {i for i in range(1, len(points) - 1) if _turns(points[i - 1 : i + 2])}
    out = []
    for i, (a, b) in enumerate(zip(points[:-1], points[1:], strict=False)):
        if not (a.multipliers.size and b.multipliers.size):
            continue
        if a.method != b.method and "arclength" in (a.method, b.method):
            # a jump between the branch and the sweep's attractor (arclength found the fold
            # it passed on its own; a sequential branch ends at its fold, so its jump to the
            # sweep's orbit is where the fold lies, and is kept)
            continue
        ca, cb = multiplier_counts(a.multipliers), multiplier_counts(b.multipliers)
        for k, kind in enumerate(KINDS):
            if ca[k] != cb[k]:
                out.append(
                    {
                        "pair": i,
                        "kind": kind,
                        "f": _interp_crossing(a, b, k),
                        "f_a": a.f,
                        "f_b": b.f,
                        "by": "multipliers",
                        "unstable_before": ca[k] > 0,
                    }
                )
    for i in sorted(turns):
        trip = points[i - 1 : i + 2]
        rho = trip[0].multipliers
        turn = {
            "kind": "fold",
            "f": _parabola_vertex(trip),
            "f_a": trip[0].f,
            "f_b": trip[2].f,
            "by": "turning point",
            "unstable_before": multiplier_counts(rho)[0] > 0 if rho.size else None,
        }
        same = [b for b in out if b["kind"] == "fold" and b.get("pair") in (i - 1, i)]
        if same:  # the multiplier through +1 nearest the turn: the same fold, its estimate kept
            near = min(same, key=lambda b: abs(math.log(b["f"] / turn["f"])))
            turn.update(by="turning point and multipliers", f_multipliers=near["f"])
            out = [b for b in out if b is not near]
        out.append(turn)
    for b in out:
        b.pop("pair", None)
    return out


def _turns(trip: list[OrbitPoint]) -> bool:
    """Whether f turns at the middle one of three arclength points (a local extremum)."""
    if not all(p.method == "arclength" and np.isfinite(p.s) for p in trip):
        return False
    fa, fb, fc = (p.f for p in trip)
    return (fb > fa and fb > fc) or (fb < fa and fb < fc)


def _parabola_vertex(trip: list[OrbitPoint]) -> float:
    """Frequency at the vertex of the parabola log f(s) through three points."""
    s = np.array([p.s for p in trip])
    y = np.array([math.log(p.f) for p in trip])
    if len(trip) < 3 or not np.all(np.isfinite(s)):
        return float(np.exp(y[np.argmax(np.abs(y - y.mean()))]))
    c2, c1, c0 = np.polyfit(s - s[1], y, 2)
    if c2 == 0:
        return float(np.exp(y[1]))
    sv = -c1 / (2 * c2)
    return float(np.exp(c0 - c1 * c1 / (4 * c2)) if abs(sv) <= np.ptp(s) else np.exp(y[1]))


def _interp_crossing(a: OrbitPoint, b: OrbitPoint, kind: int) -> float:
    """Frequency where the crossing multiplier reaches the unit circle (linear in log f)."""

    def crit(p):
        rho = p.multipliers
        if kind < 2:
            r = rho[_real(rho)].real
            if not r.size:
                return math.nan
            return float(r.max()) - 1.0 if kind == 0 else -float(r.min()) - 1.0
        c = rho[~_real(rho)]
        return float(np.abs(c).max()) - 1.0 if c.size else math.nan

    ga, gb = crit(a), crit(b)
    la, lb = math.log(a.f), math.log(b.f)
    if np.isfinite(ga) and np.isfinite(gb) and ga != gb:
        return float(math.exp(la + (lb - la) * ga / (ga - gb)))
    return float(math.sqrt(a.f * b.f))
