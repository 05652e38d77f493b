"""``[analysis.incidence]``: peaks against the incident angle of a two-component record.

A study that varies the incident angle θ (``motion.rotate``, see :mod:`nsdyn.studies.scenes3c`)
answers, per record (and per value of every other grid parameter), the engineer's question
"which direction of the record governs, and by how much": for each quantity q,

    q_max = max_θ q(θ),   θ_max = argmax_θ q(θ),   q_min = min_θ q(θ),
    directionality = q_max / q_min,   q_0 = q(θ = 0)   (the record as recorded),

and over the records, the envelope max_records q(θ) per angle. Keys::

    [analysis.incidence]
    angle = "motion.rotate"                  # the angle parameter (default)
    quantities = ["peak_resultant_displacement_m", "peak_base_shear_N"]   # default: those
                                             # of DEFAULT_QUANTITIES the table has

Outputs in the study directory: ``incidence.csv`` (one row per record and group) and, with
figures, ``incidence.png`` (q(θ) per record, its maximum marked, the envelope dashed).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from nsdyn.atomic import save_figure
from nsdyn.models.scenefile import SceneError
from nsdyn.studies.table import Table, column_names

ANGLE = "motion.rotate"
FIELDS = ("angle", "quantities")
DEFAULT_QUANTITIES = (
    "peak_resultant_displacement_m",
    "peak_torsion_rad",
    "peak_base_shear_N",
    "peak_corner_drift",
)
LABELS = {
    "peak_resultant_displacement_m": "peak resultant isolator displacement [m]",
    "peak_torsion_rad": "peak torsion [rad]",
    "peak_base_shear_N": "peak resultant base shear [N]",
    "peak_corner_drift": "peak corner drift ratio [-]",
}


ROUND_OFF = 1e-12  # [SI] a peak this small is round-off (a symmetric deck's torsion)
TIE_REL = 1e-9  # peaks equal to within this (relative) are one: the same response's round-off
# (θ and θ + 180° on a linear model differ by a few ulps) is far below it, and an adaptive
# run's differences (~rtol) above it; the smallest angle of a tie is reported


def check(study, spec: dict) -> None:
    """``[analysis.incidence]`` of ``study`` (SceneError naming the field)."""
    src = study.source
    angle = spec.get("angle", ANGLE)
    if not (angle == ANGLE or (isinstance(angle, str) and angle.endswith("_deg"))):
        raise SceneError(f"{src}: analysis.incidence.angle: expected an angle in degrees, "
                         f"\"{ANGLE}\" (or a parameter named ..._deg), got {angle!r}")  # fmt: skip
    grid = [p.name for p in study.parameters if not p.random]
    if angle not in grid:
        raise SceneError(f"{src}: analysis.incidence.angle: {angle!r} is not a grid parameter "
                         f"of this study; vary it, e.g. \"{ANGLE}\" = "
                         "{ linspace = [0, 180, 13] }")  # fmt: skip
    values = next(p.values for p in study.parameters if p.name == angle)
    if len(values) < 2:  # ("max at 30 deg", a directionality of 1 from one angle)
        raise SceneError(f"{src}: analysis.incidence.angle: {angle!r} takes one value "
                         f"({values[0]!r}); an incidence analysis compares two angles or "
                         "more")  # fmt: skip
    column_names(src, "analysis.incidence.", spec, "quantities")


def incidence_rows(table: Table, angle: str, quantities: list[str], by: list[str]) -> list[dict]:
    """Per group of ``by`` (record and the other grid parameters): for every quantity its
    maximum over the angles, the angle of it, the minimum, their ratio and the value at 0,
    over the successful runs; ``n_failed`` counts the group's failed angles (an uplift at the
    worst angle is no value, and says so)."""
    groups: dict[tuple, list[dict]] = {}
    failed: dict[tuple, int] = {}
    for r in table.rows:
        key = tuple(r.get(b) for b in by)
        if r.get("status") == "ok":
            groups.setdefault(key, []).append(r)
        else:
            failed[key] = failed.get(key, 0) + 1
    out = []
    for key, rs in groups.items():
        th = np.array([float(r[angle]) for r in rs])
        row = dict(zip(by, key, strict=True)) | {"n_angles": int(th.size),
                                                 "n_failed": failed.get(key, 0)}  # fmt: skip
        for q in quantities:
            v = np.array([float(r[q]) if isinstance(r.get(q), int | float) else np.nan
                          for r in rs])  # fmt: skip
            good = np.isfinite(v)
            if not good.any():
                row.update({f"{q}_max": np.nan, f"{q}_angle_of_max_deg": np.nan,
                            f"{q}_min": np.nan, f"{q}_directionality": np.nan,
                            f"{q}_at_0": np.nan})  # fmt: skip
                continue
            i, j = np.nanargmax(np.where(good, v, -np.inf)), np.nanargmin(np.where(good, v, np.inf))
            k = angle_of_max(th, v)
            at0 = v[np.isclose(th, 0.0) & good]
            real = abs(v[i]) > ROUND_OFF  # (a deck's torsion of 1e-19 rad had a worst angle)
            row.update({
                f"{q}_max": float(v[i]), f"{q}_angle_of_max_deg": float(th[k]) if real else np.nan,
                f"{q}_min": float(v[j]),
                f"{q}_directionality": float(v[i] / v[j]) if v[j] > 0 and real else np.nan,
                f"{q}_at_0": float(at0[0]) if at0.size else np.nan,
            })  # fmt: skip
        out.append(row)
    for key, n in failed.items():  # a group whose every angle failed: no value, its count
        if key not in groups:
            out.append(
                dict(zip(by, key, strict=True))
                | {"n_angles": 0, "n_failed": n}
                | {
                    f"{q}_{k}": np.nan
                    for q in quantities
                    for k in ("max", "angle_of_max_deg", "min", "directionality", "at_0")
                }
            )
    return out


def angle_of_max(th: np.ndarray, v: np.ndarray) -> int:
    """The index of the largest finite ``v`` (not all NaN); of peaks equal to within
    :data:`TIE_REL` (one response's round-off), the one at the smallest angle ``th``, not the
    last bit's."""
    good = np.isfinite(v)
    top = np.max(v[good])
    tie = np.flatnonzero(good & (v >= top - TIE_REL * abs(top)))
    return int(tie[np.argmin(th[tie])])


def incidence_figure(table: Table, angle: str, quantities: list[str], by: list[str], title=""):
    """q(θ) per record (and group), its maximum marked; the envelope over the records dashed
    (when the records are the only groups)."""
    from matplotlib.figure import Figure

    n = max(1, len(quantities))
    fig = Figure(figsize=(4.2 * n, 3.6), layout="constrained")
    rows = [r for r in table.rows if r.get("status") == "ok"]
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        groups.setdefault(tuple(r.get(b) for b in by), []).append(r)
    for k, q in enumerate(quantities):
        ax = fig.add_subplot(1, n, k + 1)
        env: dict[float, float] = {}
        for g, (key, rs) in enumerate(groups.items()):
            pts = sorted((float(r[angle]), r.get(q)) for r in rs)
            th = np.array([p[0] for p in pts])
            v = np.array([float(p[1]) if isinstance(p[1], int | float) else np.nan for p in pts])
            label = ", ".join(str(x) for x in key)
            ax.plot(th, v, "o-", ms=3, lw=1, color=f"C{g % 10}", label=label)
            if np.isfinite(v).any() and abs(np.nanmax(v)) > ROUND_OFF:  # (else no angle)
                i = angle_of_max(th, v)  # (the table's angle_of_max_deg)
                ax.plot(th[i], v[i], "*", ms=10, color=f"C{g % 10}", mec="k")
            for a, b in zip(th, v, strict=True):
                if np.isfinite(b):
                    env[a] = max(env.get(a, -np.inf), b)
        if env and len(groups) > 1 and by == ["record"]:  # records alone: their envelope
            a = np.array(sorted(env))
            ax.plot(a, [env[x] for x in a], "k--", lw=1, label="max over records")
        ax.set_xlabel("incident angle θ [deg]")
        ax.set_ylabel(LABELS.get(q, q), fontsize=8)
        ax.grid(alpha=0.3)
        if k == 0:
            ax.legend(fontsize=7)
    fig.suptitle(title or "peaks against the incident angle (★ the largest)", fontsize=9)
    return fig


def run(study, table: Table, spec: dict, out: Path, figures: bool) -> dict:
    """The analysis on the study's table: incidence.csv (and incidence.png)."""
    angle = spec.get("angle", ANGLE)
    present = {c for r in table.rows for c, v in r.items() if isinstance(v, int | float)}
    quantities = spec.get("quantities") or [q for q in DEFAULT_QUANTITIES if q in present]
    by = ["record"] + [p.name for p in study.parameters if not p.random and p.name != angle]
    rows = incidence_rows(table, angle, quantities, by)
    if rows:
        Table(rows).write_csv(out / "incidence.csv")
    res = {"angle": angle, "quantities": quantities, "by": by, "rows": rows,
           "table": str(out / "incidence.csv")}  # fmt: skip
    nil = [
        q
        for q in quantities
        if rows and all(abs(r.get(f"{q}_max", np.nan)) <= ROUND_OFF for r in rows)
    ]  # fmt: skip  (NaN: no value)
    if nil:
        res["note"] = (f"{', '.join(map(repr, nil))}: at most {ROUND_OFF:g} at every angle "
                       "(round-off of a response the model does not have): no worst angle, no "
                       "directionality")  # fmt: skip
    if figures and rows and quantities:
        fig = incidence_figure(table, angle, quantities, by, title=study.name)
        res["figure"] = str(save_figure(fig, out / "incidence.png"))
    return res
