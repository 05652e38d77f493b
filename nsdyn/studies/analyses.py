"""The ``[analysis.*]`` tables of a study file: checking them, running them on the table.

``[analysis.design]``        variables (default: the grid parameters but motion.seed and
                             motion.rotate, excitation axes like the records), objectives
                             (default IDR and floor acceleration), constraints {field = upper
                             bound} (default the 400 mm gap on x_iso_max_m, seed 004 §5),
                             aggregate over records (mean | median | max), reference design
                             {parameter = value, one per variable} (e.g. the seed's eq (16)).
``[analysis.percentiles]``   quantities, by (default: the grid parameters but the excitation axes),
                             percentiles.
``[analysis.fragility]``     im (a parameter or result column, e.g. "motion.pga"), edp
                             (a result column) and limits (P[edp > limit | im]); without
                             limits a boolean edp column is the outcome; confidence. A run
                             that failed by uplift counts as an exceedance; any other failed
                             run (or one without an IM or EDP value) refuses the fit.
``[analysis.incidence]``     angle (the incident-angle parameter, default motion.rotate),
                             quantities: per record, the peaks' maximum over the angles and
                             the angle of it (:mod:`nsdyn.studies.incidence`).

Outputs in the study directory: design.csv, percentiles.csv, fragility.csv, incidence.csv and,
with figures, pareto.png, fragility.png, distributions.png, incidence.png."""

from __future__ import annotations

import math
import textwrap
from contextvars import ContextVar
from pathlib import Path

import numpy as np

from nsdyn._checks import did_you_mean, expect, is_typo
from nsdyn.atomic import save_figure
from nsdyn.models.scenefile import SceneError, number, unknown_key
from nsdyn.studies.design import (
    AGGREGATES,
    DEFAULT_PERCENTILES,
    compromise,
    design_points,
    failed_runs_note,
    few_runs_note,
    find_design,
    percentile_table,
    same_value,
)
from nsdyn.studies.fragility import (
    CONFIDENCE,
    check_spec,
    failure_note,
    fit_lognormal,
    leaning_note,
)
from nsdyn.studies.study import Study
from nsdyn.studies.table import (
    ANALYSIS_OUTPUTS,
    LEAD_COLUMNS,
    TAIL_COLUMNS,
    Table,
    column_names,
    empty_columns,
    once,
)

SEISMIC_GAP_M = 0.4  # seed 004 §5: the isolator displacement may not exceed 400 mm
DEFAULT_OBJECTIVES = ("idr_max", "floor_acc_max_mps2")  # seed 004 §5 objectives
ISOLATED_RESULTS = (  # scalar fields of the isolated frame's summary
    "x_iso_max_m",
    "idr_max",
    "floor_acc_max_mps2",
    "roof_drift_max_m",
    "min_normal_force_N",
    "stick_fraction",
    "energy_closure",
    "n_steps",
    "wall_s",
    "compile_s",
    "pga_mps2",
    "record",
    "model",
    "fidelity",
    "method",
    "kind",
)
ISOLATED_TEXT = ("record", "model", "fidelity", "method", "kind")  # its columns of text
FIELDS = {
    "design": ("variables", "objectives", "constraints", "aggregate", "reference"),
    "percentiles": ("quantities", "by", "percentiles"),
    "fragility": ("im", "edp", "limits", "confidence"),
    "incidence": ("angle", "quantities"),
}


# the columns of a study's first successful row, while check_first_row checks against them
_FIRST_ROW: ContextVar[dict | None] = ContextVar("_FIRST_ROW", default=None)


def _columns(study) -> tuple[set[str], set[str] | None]:
    """(parameter columns, result columns or None when the scene kind's are unknown: they
    are a first row's in :func:`check_first_row`)."""
    params = {p.name for p in study.parameters} | {"record", "sample"}
    if study.kind != "isolated":
        first = _FIRST_ROW.get()
        return params, None if first is None else set(first) - params
    results = set(ISOLATED_RESULTS)
    if study.keep is not None:
        results = set(study.keep)
    return params, results


def _check_column(source: str, where: str, name, study, *, result: bool) -> None:
    params, results = _columns(study)
    if not isinstance(name, str):
        raise SceneError(f"{source}: {where}: expected a column name, got {name!r}")
    if result and results is None:  # results known after a run: keep's (not "no number")
        kept = sorted({*params, *(study.keep or ())})  # (a misspelt kept one: named as such)
        if study.keep is not None and name not in {*kept, *LEAD_COLUMNS, *TAIL_COLUMNS}:
            hint = did_you_mean(name, kept) if is_typo(name, kept) else ""
            why = f"not a kept column{hint} (if it is a result, add it to study.keep)"
            if not hint:
                why = f"a result the study does not keep; add it to study.keep (now {study.keep})"
            raise SceneError(f"{source}: {where}: {name!r} is {why}")
        return
    valid = params | results if result else params
    if result and name not in valid and study.keep is not None and name in ISOLATED_RESULTS:
        raise SceneError(f"{source}: {where}: {name!r} is a result the study does not keep; "
                         f"add it to study.keep (now {list(study.keep)})")  # fmt: skip
    if result and name not in valid and study.kind != "isolated" and not is_typo(name, valid):
        return  # (a first row's columns: another task's summary, another rung's, may have it)
    if name not in valid:
        hint = did_you_mean(name, sorted(valid))
        raise SceneError(f"{source}: {where}: unknown column {name!r}{hint}")


def _check_columns(source: str, where: str, spec: dict, key: str, study, *, result: bool,
                   empty_ok: bool = False) -> None:  # fmt: skip
    """``spec[key]`` a list of column names of ``study`` (results if ``result``, else
    parameters): :func:`column_names`."""
    for name in column_names(source, where, spec, key, empty_ok):
        _check_column(source, where + key, name, study, result=result)


def check_analysis(study) -> None:
    """Check ``study.analysis`` (SceneError naming the field)."""
    src, an = study.source, study.analysis
    if not isinstance(an, dict):
        raise SceneError(f"{src}: analysis: expected tables [analysis.design] ...")
    for name, spec in an.items():
        if name not in FIELDS:
            raise unknown_key(src, "analysis.", name, FIELDS)
        if not isinstance(spec, dict):
            raise SceneError(f"{src}: analysis.{name}: expected a table [analysis.{name}], "
                             f"got {spec!r}")  # fmt: skip
        for key in spec:
            if key not in FIELDS[name]:
                raise unknown_key(src, f"analysis.{name}.", key, FIELDS[name])
    other = study.kind != "isolated"  # (no isolated-frame results: the defaults' names)
    for name, key in (("design", "objectives"), ("percentiles", "quantities")):
        spec = an.get(name)
        kept = name == "percentiles" and study.keep  # (percentiles default to the kept)
        if spec is not None and other and key not in spec and not kept:  # ([]: refused below)
            raise SceneError(f"{src}: analysis.{name}.{key}: missing; the default "
                             f"({', '.join(DEFAULT_OBJECTIVES)}) is an isolated frame's, a "
                             f"{study.kind} scene has none of it (an all-NaN table)")  # fmt: skip
    d = an.get("design")
    if d is not None:
        where = "analysis.design."
        _check_columns(src, where, d, "variables", study, result=False)
        _check_columns(src, where, d, "objectives", study, result=True)
        for key in ("constraints", "reference"):
            if not isinstance(d.get(key, {}), dict):
                raise SceneError(f"{src}: analysis.design.{key}: expected a table {{name = "
                                 f"value, ...}}, got {d[key]!r}")  # fmt: skip
        for k, g in d.get("constraints", {}).items():
            where = f"analysis.design.constraints.{k}"
            _check_column(src, "analysis.design.constraints", k, study, result=True)
            if isinstance(g, dict):  # {min = a, max = b}: either or both
                if not g or set(g) - {"min", "max"}:
                    raise SceneError(f"{src}: {where}: expected an upper bound or a table "
                                     f"{{min = ..., max = ...}}, got {g!r}")  # fmt: skip
                for side, v in g.items():
                    number(src, f"{where}.{side}", v, positive=False)
                if "min" in g and "max" in g and not g["min"] <= g["max"]:  # (no design fits)
                    raise SceneError(f"{src}: {where}: expected min <= max, got {g!r}")
            else:
                number(src, where, g)
        if d.get("aggregate", "mean") not in AGGREGATES:
            raise SceneError(
                f"{src}: analysis.design.aggregate: expected one of {list(AGGREGATES)}"
            )
        grids = {p.name: p.values for p in study.parameters if not p.random}
        ref, variables = d.get("reference", {}), d.get("variables") or _grid_names(study)
        lost, extra = [k for k in variables if k not in ref], [k for k in ref if k not in variables]
        if ref and (lost or extra):  # (a partial one matched the first design that fit it)
            said = ", ".join([f"missing {lost}"] * bool(lost) + [f"got {extra}"] * bool(extra))
            raise SceneError(f"{src}: analysis.design.reference: expected a value for each "
                             f"design variable {variables}, {said}")  # fmt: skip
        for k, v in ref.items():
            _check_column(src, "analysis.design.reference", k, study, result=False)
            vals = grids.get(k, ())
            if vals and not any(same_value(g, v) for g in vals):
                raise SceneError(
                    f"{src}: analysis.design.reference.{k}: {v!r} is not a value of the grid "
                    f"{list(vals)}; the reference is one of the designs run"
                )
    p = an.get("percentiles")
    if p is not None:
        where = "analysis.percentiles."
        _check_columns(src, where, p, "quantities", study, result=True)
        # (by = []: one row over every run, not the default grouping)
        _check_columns(src, where, p, "by", study, result=False, empty_ok=True)
        pcts = p.get("percentiles", list(DEFAULT_PERCENTILES))
        if not isinstance(pcts, list) or not pcts:  # (a number raised a TypeError)
            raise SceneError(f"{src}: analysis.percentiles.percentiles: expected a list of "
                             f"percentiles in 0..100, got {pcts!r}")  # fmt: skip
        for i, q in enumerate(pcts):
            field = f"analysis.percentiles.percentiles[{i}]"
            if not 0 <= number(src, field, q, allow_zero=True) <= 100:
                raise SceneError(f"{src}: {field}: expected 0..100, got {q!r}")
        once(src, "analysis.percentiles.percentiles", pcts)
    if an.get("incidence") is not None:
        from nsdyn.studies import incidence

        incidence.check(study, an["incidence"])
        if an["incidence"].get("quantities"):  # (a misspelt one ran every task, then NaN)
            _check_columns(src, "analysis.incidence.", an["incidence"], "quantities", study,
                           result=True)  # fmt: skip
    f = an.get("fragility")
    if f is not None:
        for key in ("im", "edp"):
            if key not in f:
                raise SceneError(f"{src}: analysis.fragility.{key}: missing (required)")
            _check_column(src, f"analysis.fragility.{key}", f[key], study, result=True)
        v = (_FIRST_ROW.get() or {}).get(f["edp"])  # (its first run's value, or None)
        numeric = (
            f["edp"] in ISOLATED_RESULTS and f["edp"] not in ISOLATED_TEXT
            if study.kind == "isolated"
            else type(v) is float or (type(v) is int and v not in (0, 1))
        )  # fmt: skip  (a bool: an outcome)
        check_spec(src, f, numeric)


def check_first_row(study, row: dict) -> None:
    """The analyses' result columns of a scene kind whose results are known only after a run
    (all but the isolated frame's: a deck, a 3D building, rocking, contact, cylinder) checked
    against the columns of its first successful ``row``: a quantity a typo away from one of
    them (:func:`nsdyn._checks.is_typo`) stops the study after one run (its rows kept; the run
    resumes), not after all of them with a NaN table; one farther off may be another task's
    column."""
    if study.kind == "isolated" or not study.analysis or row.get("status") != "ok":
        return
    token = _FIRST_ROW.set(dict(row))
    try:
        check_analysis(study)
    except SceneError as e:
        raise SceneError(
            f"{e} (the columns of a {study.kind} scene's first run; its rows "
            "are kept, and the study resumes once the name is fixed)"
        ) from None
    finally:
        _FIRST_ROW.reset(token)


# grid parameters that draw the excitation, not the design: runs over them are a design's
# records (the cylinder's simulated earthquake's seed), aggregated as records are
EXCITATION_AXES = ("motion.seed", "motion.rotate")  # a record's draws and incident angles


def _grid_names(study) -> list[str]:
    return [p.name for p in study.parameters if not p.random and p.name not in EXCITATION_AXES]


def _write_rows(rows: list[dict], path: Path) -> None:
    Table(rows).write_csv(path) if rows else None


def boolean_note(table: Table, names) -> str | None:
    """A note naming the quantities of a percentile table that are true/false outcomes
    (overturned, toppled): their percentiles are 0s and 1s, interpolated between runs, which
    reads like a number it is not; the fraction of runs where they hold is what says something."""
    ok = [r for r in table.rows if r.get("status") == "ok"]
    flags = [n for n in dict.fromkeys(names)
             if any(isinstance(r.get(n), bool) for r in ok)
             and all(isinstance(r.get(n), bool) or r.get(n) is None for r in ok)]  # fmt: skip
    if not flags:
        return None
    return (f"{', '.join(map(repr, flags))}: true or false in every run, so their percentiles "
            "are of 0s and 1s (interpolated between runs); the fraction of runs where they are "
            "true is a fragility's or a design constraint's reading")  # fmt: skip


def _fixed_base_gap(study, table: Table) -> Table:
    """``table`` with the fixed-base runs' isolator displacement 0: no isolator crosses the
    seismic gap (their summaries have no ``x_iso_max_m``: missing, or NaN read back from the
    CSV, made every fixed-base design infeasible under a gap constraint). A run is of the
    fixed base by its ``fidelity`` column, its ``scene.fidelity`` parameter, or the base
    scene's (a ``keep`` list without ``fidelity``)."""
    from nsdyn.studies.scenes import is_number

    base = ((getattr(study, "base", None) or {}).get("scene") or {}).get("fidelity")

    def fixed(r: dict) -> bool:  # (x_iso none, or NaN from a CSV: no isolator)
        fid = r.get("fidelity", r.get("scene.fidelity", base))
        return fid == "fixed" and not is_number(r.get("x_iso_max_m"))

    rows = [{**r, "x_iso_max_m": 0.0} if fixed(r) and r.get("status") == "ok" else r
            for r in table.rows]  # fmt: skip
    return Table(rows, table.param_names)


def _add_note(res: dict, text: str) -> None:
    """``text`` after the notes ``res["note"]`` holds ("; " between them)."""
    res["note"] = "; ".join(filter(None, [res.get("note"), text]))


def _design(study, table: Table, spec: dict, out: Path, figures: bool) -> dict:
    from nsdyn.studies.figures import pareto_figure

    variables = spec.get("variables") or _grid_names(study)
    objectives = spec.get("objectives") or list(DEFAULT_OBJECTIVES)
    gap = {"x_iso_max_m": SEISMIC_GAP_M} if study.kind == "isolated" else {}  # (a frame's gap)
    constraints = spec.get("constraints", gap)
    if "x_iso_max_m" in constraints and study.kind == "isolated":
        table = _fixed_base_gap(study, table)
    empty = empty_columns(table, [*objectives, *constraints])
    how = spec.get("aggregate", "mean")
    points = design_points(table, variables, objectives, constraints, how, strict=False)
    _write_rows([p.row() for p in points], out / "design.csv")
    chosen = compromise(points, objectives)
    ref = find_design(points, spec["reference"]) if spec.get("reference") else None
    res = {
        "n_designs": len(points),
        "n_feasible": sum(p.feasible for p in points),
        "pareto": [p.row() for p in points if p.pareto],
        "chosen": None if chosen is None else chosen.row(),
        "reference": None if ref is None else ref.row(),
        "table": str(out / "design.csv"),
        **({"note": empty} if empty else {}),
    }
    pooled = [f"{n} ({k} values)" for n in _grid_names(study) if n not in variables
              and (k := len({str(v) for v in table.values(n)})) > 1]  # fmt: skip
    lost = sum(not all(math.isfinite(v) for v in p.objectives.values()) for p in points)
    if lost and table.ok():  # (a failed run's design: NaN objectives, unsaid)
        _add_note(res, f"{lost} of {len(points)} designs without an objective (a run failed or "
                  "lacks it): left out of the front")  # fmt: skip
    if pooled:  # (a variable left out was aggregated as if it were records, unsaid)
        why = (f"each design pools the runs of every {', '.join(pooled)} with its records: "
               "name it among the variables for a design each")  # fmt: skip
        _add_note(res, why)
    if ref is not None:
        res["reference_dominated_by"] = [
            p.values
            for p in points
            if p.feasible
            and all(p.objectives[k] <= ref.objectives[k] for k in objectives)
            and any(p.objectives[k] < ref.objectives[k] for k in objectives)
        ]
    if not table.ok():  # (empty axes were drawn; an earlier figure would sit beside)
        _add_note(res, "no run succeeded: no design has an objective, no figure is drawn")
        (out / ANALYSIS_OUTPUTS["design"][1]).unlink(missing_ok=True)
    elif figures and len(objectives) >= 2:
        fig = pareto_figure(points, objectives[:2], chosen, ref, title=study.name)
        res["figure"] = str(save_figure(fig, out / "pareto.png"))
    return res


# A failed run whose error is itself the limit state: the isolated frame lifted off its
# isolators (the no-uplift model stopped at the uplift). These are the most severe runs of a
# study; leaving them out would bias the curve low, so they count as exceedances.
EXCEEDANCE_FAILURES = {"UpliftError": "uplift"}


def fragility_outcomes(table: Table, im_name: str, edp_name: str) -> dict:
    """The runs a fragility fit may use, failures placed by their physical meaning.

    Returns im, edp (``inf`` for a failure that is an exceedance: past every limit), the count
    of such failures by meaning, and ``refuse``: why no fit is honest (failed runs without a
    physical outcome, or runs without an IM or EDP value), or None.
    """
    im, edp = table.column(im_name, False), table.column(edp_name, False)
    status = [r.get("status") for r in table.rows]
    keep = np.zeros(len(table.rows), dtype=bool)
    counted: dict[str, int] = {}
    unknown: list[str] = []  # failed runs whose failure says nothing of the outcome
    missing: list[str] = []  # successful runs without a value (a result they do not give)
    below = 0  # successful runs at IM <= 0, which a lognormal curve cannot place
    for i, r in enumerate(table.rows):
        if not (np.isfinite(im[i]) and im[i] > 0):
            if status[i] != "ok":
                unknown.append(f"no {im_name} value ({r.get('error') or 'none'})")
            elif np.isnan(im[i]):
                missing.append(im_name)
            else:
                below += 1
            continue
        if status[i] == "ok":
            if np.isnan(edp[i]):
                missing.append(edp_name)
                continue
            keep[i] = True
            continue
        err = str(r.get("error", ""))
        meaning = EXCEEDANCE_FAILURES.get(err.split(":", 1)[0].strip())
        if meaning is None:
            unknown.append(err)
            continue
        counted[meaning] = counted.get(meaning, 0) + 1
        edp[i], keep[i] = np.inf, True
    refuse = None
    text = [(n, r[n]) for n in (im_name, edp_name) for r in table.rows
            if r.get("status") == "ok" and isinstance(r.get(n), str)]  # fmt: skip
    if text:  # (it read "runs have no outcome that can be counted ... fix them and rerun")
        return {"im": im[keep], "edp": edp[keep], "counted": counted, "below": below,
                "refuse": f"fragility: {text[0][0]!r} is a text column ({text[0][1]!r}, ...), "
                          "not a number: a fragility needs a numeric IM and EDP"}  # fmt: skip
    absent = empty_columns(table, [im_name, edp_name])  # (a column no run has: not failures)
    if absent:
        refuse = f"fragility: {absent}"
    elif missing:  # (it said "fix them and rerun (--retry-failed)" of runs that had not failed)
        refuse = (
            f"fragility: {len(missing)} successful runs have no {missing[0]} value (a "
            "result these runs do not give); expected an IM and EDP every run gives"
        )
    elif unknown:
        first = textwrap.shorten(unknown[0], 160, placeholder=" ...")
        refuse = (f"fragility: {len(unknown)} runs have no outcome that can be counted as survived "
                  f"or exceeded (first: {first}); fix them and rerun (--retry-failed), a fit "
                  "without them would be biased")  # fmt: skip
    return {"im": im[keep], "edp": edp[keep], "counted": counted, "refuse": refuse,
            "below": below}  # fmt: skip


def _pooled(table: Table, study, im_name: str) -> dict:
    """{grid parameter: its number of values} of the parameters other than the IM that one
    fragility curve pools; a parameter the IM follows (one IM value per parameter value: the
    record's PGA beside a grid over motion.pga) is the IM's own axis, not pooled."""
    im = table.column(im_name, False)
    out = {}
    for n in _grid_names(study):
        vals = [str(v) for v in table.values(n)]
        if n == im_name or len(set(vals)) < 2:
            continue
        spread = {v: np.unique(np.round(im[[i for i, w in enumerate(vals) if w == v]], 9))
                  for v in set(vals)}  # fmt: skip
        if any(np.isfinite(s).sum() > 1 for s in spread.values()):
            out[n] = len(set(vals))
    return out


def _fragility(study, table: Table, spec: dict, out: Path, figures: bool) -> dict:
    from nsdyn.studies.figures import fragility_figure

    runs = fragility_outcomes(table, spec["im"], spec["edp"])
    im, edp = runs["im"], runs["edp"]
    note = failure_note(runs["counted"])
    n_counted = sum(runs["counted"].values())
    limits = spec.get("limits") or [None]
    fits, rows = [], []
    for lim in limits:
        exceeded = edp > lim if lim is not None else edp > 0.5
        base = {"limit": lim, "n_failed_as_exceedance": n_counted, "failures": note or "none"}
        values = np.asarray(edp, float)
        flags = np.isin(values[np.isfinite(values)], (0.0, 1.0)).all()
        refuse = runs["refuse"] or (None if lim is not None or flags else (
            f"limits: missing, and {spec['edp']!r} is not a true/false outcome (its values "
            "are not 0 and 1): give the limit its exceedance is counted at"))  # fmt: skip
        if refuse is not None:
            rows.append(base | {"error": refuse})
            fits.append((lim, None, im, exceeded))
            continue
        try:
            fit = fit_lognormal(im, exceeded)
        except ValueError as e:
            rows.append(base | {"error": str(e)})
            fits.append((lim, None, im, exceeded))
            continue
        rows.append(base | fit.as_dict())
        fits.append((lim, fit, im, exceeded))
    _write_rows(rows, out / "fragility.csv")
    res = {"im": spec["im"], "edp": spec["edp"], "fits": rows, "table": str(out / "fragility.csv")}
    if runs["below"]:  # (they were left out without a word)
        res["note"] = (f"{runs['below']} successful run{'s' * (runs['below'] != 1)} at "
                       f"{spec['im']} <= 0 left out: a "
                       "lognormal fragility places only IM > 0")  # fmt: skip
    if note:
        res["failures"] = note
    if lean := leaning_note(spec["edp"], table):  # (still falling at t_end: "standing")
        _add_note(res, lean)
    pooled = [f"{n} ({k} values)" for n, k in _pooled(table, study, spec["im"]).items()]
    if pooled:  # (one curve over every design, without a word)
        _add_note(res, f"one curve over the runs of every {', '.join(pooled)}: run a study per "
                  "value for a curve each")  # fmt: skip
    if figures:
        conf = spec.get("confidence", CONFIDENCE)
        title = study.name + (f" ({note})" if note else "")
        if all(f[1] is None for f in fits):  # (it blamed failed runs, with none failed; a
            # figure of points alone read as a fit)
            title = f"{study.name}: no fit (fragility.csv says why)"
        fig = fragility_figure(fits, spec["im"], spec["edp"], conf, title=title)
        res["figure"] = str(save_figure(fig, out / "fragility.png"))
    return res


def run_analyses(study, table: Table, out_dir: str | Path, figures: bool = True) -> dict:
    """Every ``[analysis.*]`` of the study on its table; CSVs (and PNGs) in ``out_dir``."""
    ok = isinstance(study, Study) or hasattr(study, "analysis")  # (a stand-in of its analyses)
    expect("study", study, ok, "a Study (nsdyn.load_study(path) reads one)")
    expect("table", table, isinstance(table, Table), "a study's Table (run_study(...).table or "
           "read_results(out_dir); a DataFrame is a copy of one)")  # fmt: skip
    out = Path(out_dir)
    an = study.analysis
    res: dict = {}
    for part, (table_file, figure_file) in ANALYSIS_OUTPUTS.items():  # an earlier run's
        if part not in an:  # (an analysis dropped from the study left its files beside)
            (out / table_file).unlink(missing_ok=True)
        if part not in an or not figures:  # (--no-figures left an earlier run's figure)
            (out / figure_file).unlink(missing_ok=True)
    if "design" in an:
        res["design"] = _design(study, table, an["design"], out, figures)
    if "percentiles" in an:
        spec = an["percentiles"]
        q = spec.get("quantities") or list(study.keep or DEFAULT_OBJECTIVES)
        by = spec.get("by", _grid_names(study))
        pct = tuple(spec.get("percentiles", DEFAULT_PERCENTILES))
        rows = percentile_table(table, q, by, pct, strict=False)  # (noted below)
        _write_rows(rows, out / "percentiles.csv")
        res["percentiles"] = {"rows": rows, "table": str(out / "percentiles.csv")}
        notes = (empty_columns(table, q, True), boolean_note(table, q), few_runs_note(rows, pct),
                 failed_runs_note(rows))  # fmt: skip
        note = "; ".join(n for n in notes if n)
        if note:
            res["percentiles"]["note"] = note
        if not rows or not table.ok():  # (no figure drawn, or empty axes: an earlier one
            (out / ANALYSIS_OUTPUTS["percentiles"][1]).unlink(missing_ok=True)  # goes)
        if figures and rows and table.ok():
            from nsdyn.studies.figures import distribution_figure  # (matplotlib: on use)

            fig = distribution_figure(table.ok(), q, title=study.name)
            res["percentiles"]["figure"] = str(save_figure(fig, out / "distributions.png"))
    if "fragility" in an:
        res["fragility"] = _fragility(study, table, an["fragility"], out, figures)
    if "incidence" in an:
        from nsdyn.studies import incidence

        res["incidence"] = incidence.run(study, table, an["incidence"], out, figures)
        if note := empty_columns(table, res["incidence"].get("quantities") or []):
            _add_note(res["incidence"], note)
    return _finite(res)


def _finite(obj):
    """JSON-safe: NaN and inf become None."""
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_finite(v) for v in obj]
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, np.floating | np.integer | np.bool_):
        return _finite(obj.item())
    return obj
