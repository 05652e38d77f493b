"""Design search over a study table: objectives per design, constraint, Pareto front, choice;
percentile tables over record sets.

A design is one combination of the design variables (e.g. K_lam, c, μ; seed 004 §5). Over the
records of a design, each objective f_k (e.g. peak IDR, peak absolute floor acceleration) is
aggregated (mean, median or max over records) and each constraint g (e.g. the peak isolator
displacement against the 400 mm seismic gap) is taken at its worst record:

    feasible  ⇔  max_records g ≤ g_max  for every constraint
                  (and min_records g ≥ g_min for a lower bound: {min = g_min}).

Design p dominates q if f_k(p) ≤ f_k(q) for all k and < for one; the Pareto front is the set of
feasible designs no feasible design dominates. One design is singled out as the compromise:
the front's minimiser of Σ_k f_k / min_front f_k (each objective relative to its best
feasible value, so objectives of different units weigh alike).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field

import numpy as np

from nsdyn.studies.table import Table

AGGREGATES = ("mean", "median", "max")
DEFAULT_PERCENTILES = (16.0, 50.0, 84.0)  # median and the ±1σ band of a lognormal spread
MATCH_RTOL = 1e-9  # a reference design matches a grid point to this relative tolerance


@dataclass
class DesignPoint:
    """One design: its variable values, aggregated objectives, worst constraints (by their
    columns: ``{name}_worst`` the largest over the records, ``{name}_least`` the smallest)."""

    values: dict
    objectives: dict
    constraints: dict
    n_records: int
    n_failed: int
    feasible: bool = False
    pareto: bool = False
    extra: dict = field(default_factory=dict)

    def row(self) -> dict:
        return (
            dict(self.values)
            | dict(self.objectives)
            | dict(self.constraints)
            | {
                "n_records": self.n_records,
                "n_failed": self.n_failed,
                "feasible": self.feasible,
                "pareto": self.pareto,
            }
        )


def _groups(table: Table, by: list[str]) -> dict[tuple, list[int]]:
    groups: dict[tuple, list[int]] = {}
    for i, r in enumerate(table.rows):
        groups.setdefault(tuple(r.get(b) for b in by), []).append(i)
    return groups


def _agg(x: np.ndarray, how: str) -> float:
    if x.size == 0 or not np.all(np.isfinite(x)):
        return float("nan")
    return float({"mean": np.mean, "median": np.median, "max": np.max, "min": np.min}[how](x))


def bounds(constraints: dict) -> list[tuple[str, str, float]]:
    """``(name, "max" | "min", bound)`` of each constraint: a number is an upper bound, a
    table ``{min = a, max = b}`` gives either or both; anything else is a ValueError naming
    ``constraints[name]``."""
    if constraints is None:
        return []
    if not isinstance(constraints, dict):
        raise TypeError(f"constraints: expected a dict of column name -> bound, got "
                        f"{constraints!r}")  # fmt: skip
    out = []
    for k, g in constraints.items():
        k = str(k)  # (numpy's np.str_ as plain text)
        sides = dict(g.items() if isinstance(g, dict) else [("max", g)])
        for side, v in sides.items():
            if side not in ("min", "max") or not _real(v) or math.isnan(v):
                raise ValueError(f"constraints[{k!r}]: expected a number (an upper bound) or "
                                 f"{{'min': a, 'max': b}}, got {g!r}")  # fmt: skip
            out.append((k, side, float(v)))
        lo, hi = float(sides.get("min", -math.inf)), float(sides.get("max", math.inf))
        if not lo <= hi or lo == math.inf or hi == -math.inf:
            raise ValueError(f"constraints[{k!r}]: {g!r}: no design can meet it (expected "
                             "min <= max, a finite min or max)")  # fmt: skip
    return out


def _real(v) -> bool:
    """A real number (numpy's too), not a bool."""
    return isinstance(v, numbers.Real) and not isinstance(v, bool | np.bool_)


def column_list(table: Table, arg: str, names, strict: bool = True, empty_ok: bool = True):
    """``names`` (any sequence of text: a list, a tuple, an array, a pandas Index) as a list
    of ``table``'s column names: a TypeError for a bare string (one column per letter) or a
    non-text entry, a ValueError for none where one is needed, and with ``strict`` a KeyError
    naming the nearest column for a name no row has (a typo read as NaN made every design
    infeasible)."""
    from nsdyn._checks import did_you_mean

    try:  # (a set has no order: its columns came in another order each run)
        listed = None if isinstance(names, str | set | frozenset) else list(names)
    except TypeError:  # (not iterable)
        listed = None
    if listed is None or not all(isinstance(n, str) for n in listed):
        raise TypeError(f"{arg}: expected a list of column names, got {names!r}")
    names = [str(n) for n in listed]  # (numpy's np.str_ as plain text)
    if not names and not empty_ok:
        raise ValueError(f"{arg}: expected one column name or more, got {names!r}")
    known = table.columns if strict and table.rows else ()
    for n in names if known else ():
        if n not in known:
            raise KeyError(f"{arg}: {n!r}: no such column{did_you_mean(n, known)}")
    return list(names)


def design_points(
    table: Table,
    variables: list[str],
    objectives: list[str],
    constraints: dict,
    aggregate: str = "mean",
    *,
    strict: bool = True,
) -> list[DesignPoint]:
    """Designs of ``table`` (grouped by ``variables``), aggregated, feasibility and front set.

    ``constraints``: name -> upper bound, or {min = ..., max = ...} (:func:`bounds`). A design
    with a failed task has NaN objectives and is neither feasible nor on the front. Every
    name must be a column of ``table`` (:func:`column_list`); ``strict=False`` reads a
    missing one as NaN (a study's analyses, whose columns a failed study may lack, say so in
    a note). An empty table has no designs.
    """
    if aggregate not in AGGREGATES:
        raise ValueError(f"aggregate: expected one of {AGGREGATES}, got {aggregate!r}")
    variables = column_list(table, "variables", variables, strict)
    objectives = column_list(table, "objectives", objectives, strict, empty_ok=False)
    constraints = {} if constraints is None else constraints  # (None: none)
    limits = bounds(constraints)
    column_list(table, "constraints", list(constraints), strict)
    if not table.rows:
        return []
    ok = np.array([r.get("status") == "ok" for r in table.rows], dtype=bool)
    cols = {k: table.column(k, False) for k in list(objectives) + list(constraints)}
    points = []
    for vals, idx in _groups(table, variables).items():
        idx = np.asarray(idx)
        good = idx[ok[idx]]
        n_failed = int(idx.size - good.size)
        obj = {k: _agg(cols[k][good], aggregate) if not n_failed else np.nan for k in objectives}
        con, feasible = {}, not n_failed
        for k, side, g in limits:  # the worst record of each bound
            worst = _agg(cols[k][good], side) if not n_failed else np.nan
            con[f"{k}_{'worst' if side == 'max' else 'least'}"] = worst
            feasible = feasible and (worst <= g if side == "max" else worst >= g)
        feasible = feasible and all(np.isfinite(v) for v in obj.values())
        points.append(
            DesignPoint(
                dict(zip(variables, vals, strict=True)), obj, con, int(idx.size), n_failed, feasible
            )
        )
    F = np.array([[p.objectives[k] for k in objectives] for p in points]).reshape(len(points), -1)
    feas = np.array([p.feasible for p in points], dtype=bool)
    for i in pareto_front(F, feas):
        points[i].pareto = True
    return points


def pareto_front(F: np.ndarray, mask: np.ndarray | None = None) -> np.ndarray:
    """Indices of the rows of ``F`` (n, k; minimised) that no other row dominates, among the
    rows ``mask`` (n booleans; default all) keeps."""
    F = np.asarray(F, dtype=float)
    if F.ndim != 2:
        raise ValueError(f"F: expected an (n, k) array of n designs' k objectives, got shape "
                         f"{F.shape}")  # fmt: skip
    mask = np.ones(F.shape[0], dtype=bool) if mask is None else np.asarray(mask, dtype=bool)
    if mask.shape != F.shape[:1]:
        raise ValueError(f"mask: expected {F.shape[0]} booleans (one per row of F), got shape "
                         f"{mask.shape}")  # fmt: skip
    idx = np.flatnonzero(mask)
    keep = []
    for i in idx:
        others = F[idx]
        dom = np.all(others <= F[i], axis=1) & np.any(others < F[i], axis=1)
        if not dom.any():
            keep.append(i)
    return np.asarray(keep, dtype=int)


def compromise(points: list[DesignPoint], objectives: list[str]) -> DesignPoint | None:
    """The front's design minimising Σ_k f_k / min_front f_k (None if nothing is feasible)."""
    front = [p for p in points if p.pareto]
    if not front:
        return None
    best = {k: min(p.objectives[k] for p in front) for k in objectives}
    scale = {k: best[k] if best[k] > 0 else 1.0 for k in objectives}
    return min(front, key=lambda p: sum(p.objectives[k] / scale[k] for k in objectives))


def same_value(a, b) -> bool:
    """Two parameter values are the same design's: numbers to MATCH_RTOL, others equal."""
    if isinstance(a, int | float) and isinstance(b, int | float):
        return abs(a - b) <= MATCH_RTOL * max(abs(a), abs(b), 1e-300)
    return a == b


def find_design(points: list[DesignPoint], values: dict) -> DesignPoint | None:
    """The design whose variables equal ``values`` (numbers to MATCH_RTOL), if any."""
    for p in points:
        if all(same_value(p.values.get(k), v) for k, v in values.items()):
            return p
    return None


def percentile_table(
    table: Table, quantities: list[str], by: list[str], q=DEFAULT_PERCENTILES, *, strict=True
) -> list[dict]:
    """Per group of ``by``: runs, and the ``q`` percentiles (a list of numbers in [0, 100])
    and mean of each quantity over the group's successful runs (records, samples). Names and
    ``strict`` as in :func:`design_points`."""
    quantities = column_list(table, "quantities", quantities, strict, empty_ok=False)
    by = column_list(table, "by", by, strict)
    try:
        qs = None if isinstance(q, str) else list(q)
    except TypeError:  # (a bare number)
        qs = None
    if qs is None or not all(_real(p) and 0 <= p <= 100 for p in qs):
        raise ValueError(f"q: expected a list of percentiles in [0, 100], got {q!r}")
    qs = [float(p) for p in qs]  # (a Fraction: numpy takes floats)
    out = []
    ok = np.array([r.get("status") == "ok" for r in table.rows], dtype=bool)
    cols = {k: table.column(k, False) for k in quantities}
    for vals, idx in _groups(table, by).items():
        idx = np.asarray(idx)
        good = idx[ok[idx]]
        row = dict(zip(by, vals, strict=True)) | {
            "n": int(good.size),
            "n_failed": int(idx.size - good.size),
        }
        for k in quantities:
            x = cols[k][good]
            x = x[np.isfinite(x)]
            for p in qs:
                row[f"{k}_p{p:g}"] = float(np.percentile(x, p)) if x.size else float("nan")
            row[f"{k}_mean"] = float(x.mean()) if x.size else float("nan")
        out.append(row)
    return out


def few_runs_note(rows: list[dict], q=DEFAULT_PERCENTILES) -> str | None:
    """A note when a group of :func:`percentile_table` has too few successful runs for its
    outer percentiles. With n runs, the p-th percentile (linear interpolation) sits at rank
    p/100 (n - 1) of the sorted runs; below rank 1 (above n - 2 for the upper one) it is only
    an interpolation between the two most extreme runs, so min(p, 100 - p) needs
    n >= 1 + 100 / min(p, 100 - p) runs (8 for the 16th and 84th). None when every group has
    them (or no percentile lies strictly inside 0-100)."""
    inner = [min(p, 100 - p) for p in q if 0 < p < 100]
    if not inner or not rows:
        return None
    need = math.ceil(1 + 100 / min(inner) - 1e-9)
    empty = sum(r["n"] == 0 for r in rows)  # (every run of the group failed: no statistic)
    few = [r["n"] for r in rows if 0 < r["n"] < need]
    gone = (f"{empty} of {len(rows)} group(s) without a successful run (their percentiles are "
            "empty)") if empty else ""  # fmt: skip
    if not few:
        return gone or None
    tails = ", ".join(f"p{p:g}" for p in q if 0 < p < 100 and 1 + 100 / min(p, 100 - p) > min(few))
    how = ("interpolated between the extreme runs" if min(few) > 1 else "interpolated "
           "between the extreme runs, or the one run's value in a group of one")  # fmt: skip
    note = (f"{len(few)} of {len(rows)} group(s) with fewer than {need} successful runs (fewest "
            f"{min(few)}): there {tails} are {how}, not estimated; add records or "
            "samples")  # fmt: skip
    return f"{gone}; {note}" if gone else note


def failed_runs_note(rows: list[dict]) -> str | None:
    """A note when groups of :func:`percentile_table` leave failed runs out (``n_failed``):
    their percentiles are the surviving runs', low where the failures were the severe runs
    (an uplift at a high PGA)."""
    hit = [r for r in rows if r.get("n_failed")]
    if not hit:
        return None
    n = sum(r["n_failed"] for r in hit)
    return (f"{len(hit)} of {len(rows)} group(s) leave failed runs out ({n} run"
            f"{'s' * (n != 1)}, column "
            "n_failed): their percentiles are the successful runs' only, low where the failed "
            "runs were the severe ones")  # fmt: skip
