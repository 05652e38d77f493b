"""Work-precision of the integrators: error against wall time, every method x friction law.

``nsdyn bench accuracy``: CB-5 under the two bundled synthetic records (20 s windows at PGA
3 m/s^2), each integrator over its setting (rtol, or the fixed step dt), errors against a
reference of the same model and friction law (:mod:`nsdyn.bench.common`)::

    err_x   = max_{t, i} |x_iso,i - x_iso,i^ref| / max |x_iso^ref|
    err_idr = |IDR_max / IDR_max^ref - 1|

The arctan reference is nsdyn ``radau`` at rtol 1e-10 (atol 1e-12 m), checked by ``dopri5``
(explicit Runge-Kutta, an unrelated method) at the same tolerances; the switch reference is
the event-driven method at rtol 1e-10, checked by ``radau`` on the switch law with a narrow
stick band. The agreement of each pair is written next to the table
(``accuracy-reference.csv``) and drawn on the chart as the floor below which errors are not
resolved. ``scipy-radau`` is the NumPy/SciPy baseline (:mod:`nsdyn.bench.baseline`). Speed
ratios are quoted at matched accuracy, all timed in the same run (:func:`matched_ratios`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from nsdyn.bench import common
from nsdyn.bench.baseline import run_scipy_radau

__all__ = [
    "Reference",
    "accuracy_bench",
    "accuracy_figure",
    "make_reference",
    "matched_ratios",
    "report",
    "run_bench",
    "summarise",
    "wall_to_reach",
]

# the command-line options run_bench takes (nsdyn.cli.bench passes only these)
OPTIONS = ("repeats", "records", "figures", "quiet")
FIGURES = ("accuracy.png",)  # the figures it draws (removed under --no-figures)

REF_RTOL = 1e-10  # reference tolerance (quick: QUICK_REF_RTOL)
QUICK_REF_RTOL = 1e-9
SWITCH_CHECK_ETA = 1e-7  # m/s, stick band of the radau check of the switch reference
SWITCH_CHECK_RTOL = 1e-9
# (label, method, law, setting, values); scipy-radau is the NumPy/SciPy baseline
ACCURACY_PLAN = [
    ("radau", "radau", "arctan", "rtol", [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7]),
    ("dopri5", "dopri5", "arctan", "rtol", [1e-4]),  # + the reference check at REF_RTOL
    ("genalpha", "genalpha", "arctan", "dt", [2e-3, 1e-3, 5e-4, 2e-4, 1e-4]),
    ("hht", "hht", "arctan", "dt", [2e-3, 1e-3, 5e-4, 2e-4, 1e-4]),
    ("event", "event", "switch", "rtol", [1e-3, 1e-4, 1e-5, 1e-6]),
    ("scipy-radau", "scipy", "arctan", "rtol", [1e-3, 1e-4, 1e-5]),
]
QUICK_ACCURACY_PLAN = [
    ("radau", "radau", "arctan", "rtol", [1e-2, 1e-5]),
    ("dopri5", "dopri5", "arctan", "rtol", [1e-4]),
    ("genalpha", "genalpha", "arctan", "dt", [1e-3, 2.5e-4]),
    ("hht", "hht", "arctan", "dt", [1e-3]),
    ("event", "event", "switch", "rtol", [1e-3, 1e-5]),
    ("scipy-radau", "scipy", "arctan", "rtol", [1e-3]),
]
QUICK_DOPRI5_MAX_STEPS = 20_000  # --quick: dopri5 is stiffness-bound (~4e-6 s steps); cap it
SCIPY_RECORDS = ("wn",)  # the SciPy baseline is slow: run it on these records only
MATCH_ERROR = 1e-4  # err_x the speed ratios are quoted at (cheapest run reaching it)
UNRESOLVED_FACTOR = 3.0  # charted errors below this x the reference check's are drawn hollow

# columns of the CSV tables, in order
_ACC_FIELDS = (
    "record label method law setting value status err_x err_idr err_xpeak wall_s n_timed "
    "n_steps nfev x_iso_max_m idr_max floor_acc_max_mps2 energy_closure window_s repeats "
    "compile_s quick message"
).split()


@dataclass
class Reference:
    """A tight run of one model and friction law, and an independent check of it."""

    law: str
    run: common.BenchRun
    check: common.BenchRun | None
    agreement: dict  # run_errors(check, run), or NaNs when the check was skipped

    @property
    def floor(self) -> float:
        """err_x below which charted errors are not resolved (the pair's disagreement)."""
        return self.agreement.get("err_x", float("nan"))


def make_reference(system, motion, law: str, *, quick: bool = False, check: bool = True):
    """The reference of ``law`` ("arctan" or "switch") and, with ``check``, its check.

    arctan: radau at REF_RTOL vs dopri5 at REF_RTOL (explicit; stiffness-bound ~4e-6 s steps,
    minutes on a 20 s window). switch: event at REF_RTOL vs radau on the switch law with the
    stick band narrowed to SWITCH_CHECK_ETA (the smooth integrator's band model is the only
    difference); if radau cannot follow the switch law (step underflow), event at REF_RTOL/10
    (self-convergence only). ``quick`` tightens less (QUICK_REF_RTOL).
    """
    rtol = QUICK_REF_RTOL if quick else REF_RTOL
    sys_law = system if system.isolation.law == law else system.with_isolation(law=law)
    if law == "arctan":
        ref = common.run_nsdyn(sys_law, motion, "radau", label="reference", rtol=rtol, repeats=1)
        chk = (
            common.run_nsdyn(
                sys_law, motion, "dopri5", label="reference-check", rtol=rtol, repeats=1
            )
            if check
            else None
        )
    elif law == "switch":
        ref = common.run_nsdyn(sys_law, motion, "event", label="reference", rtol=rtol, repeats=1)
        chk = None
        if check:
            s2 = sys_law.with_isolation(eta=SWITCH_CHECK_ETA)
            chk = common.run_nsdyn(
                s2, motion, "radau", label="reference-check", rtol=SWITCH_CHECK_RTOL, repeats=1
            )
            if not chk.ok:  # the smooth integrator could not follow the switch law: fall back
                chk = common.run_nsdyn(
                    sys_law, motion, "event", label="reference-check", rtol=rtol / 10, repeats=1
                )
                chk.message = "self-convergence check (radau on the switch law failed)"
    else:
        raise ValueError(f"law: expected 'arctan' or 'switch', got {law!r}")
    if not ref.ok:
        raise RuntimeError(f"reference run ({law}) failed: {ref.status}: {ref.message}")
    agreement = common.run_errors(chk, ref) if chk is not None else common.nan_errors()
    return Reference(law, ref, chk, agreement)


def wall_to_reach(rows: list[dict], label: str, record: str, target: float) -> float:
    """Cheapest median wall time among ``label``'s successful runs with err_x <= target
    (NaN if none): the work-precision front read without interpolation."""
    walls = [r["wall_s"] for r in _measured(rows, label, record) if r["err_x"] <= target]
    return float(min(walls)) if walls else float("nan")


def _measured(rows: list[dict], label: str, record: str) -> list[dict]:
    """``label``'s successful runs on ``record`` with a finite err_x."""
    return [
        r
        for r in rows
        if r["label"] == label
        and r["record"] == record
        and r["status"] == "ok"
        and np.isfinite(r.get("err_x", np.nan))
    ]


def _matched(rows, rec, a: str, b: str) -> dict:
    """Walls of ``a`` and ``b`` to reach err_x <= MATCH_ERROR (if both can), else the
    smallest error level both reach (the larger of the two methods' best errors)."""
    best = [min((r["err_x"] for r in _measured(rows, lab, rec)), default=np.nan) for lab in (a, b)]
    for e in (MATCH_ERROR, max(best)):
        wa, wb = wall_to_reach(rows, a, rec, e), wall_to_reach(rows, b, rec, e)
        if np.isfinite(wa) and np.isfinite(wb):
            return {"err_x": e, f"{a}_wall_s": wa, f"{b}_wall_s": wb, "ratio": wa / wb}
    nan = float("nan")
    return {"err_x": nan, f"{a}_wall_s": nan, f"{b}_wall_s": nan, "ratio": nan}


def matched_ratios(rows: list[dict], rec: str) -> dict:
    """Speed ratios at matched accuracy, all timed in the same run: the cheapest run of each
    method reaching err_x <= MATCH_ERROR (see :func:`wall_to_reach`); > 1: the second is faster.

    ``scipy-radau/radau``: SciPy Radau on the NumPy equations over nsdyn radau; ``event/radau``
    compares the switch model's cost with the arctan model's at the same error level.
    """
    return {
        f"{a}/radau": _matched(rows, rec, a, "radau")
        for a in ("scipy-radau", "genalpha", "hht", "event", "dopri5")
    }


def accuracy_bench(
    *,
    quick: bool = False,
    repeats: int | None = None,
    records: tuple[str, ...] = ("wn", "kt"),
    out: Path | None = common.DEFAULT_OUT,
    figures: bool = True,
    quiet: bool = False,
) -> dict:
    """Work-precision table of every integrator x friction law on CB-5 (see module docstring).

    Returns ``{"rows", "references", "ratios", "files"}``; writes ``accuracy.csv``,
    ``accuracy-reference.csv`` and ``accuracy.png`` to ``out`` (None: write nothing).
    """
    repeats = common.timed_repeats(quick, repeats)
    window = common.QUICK_WINDOW_S if quick else common.WINDOW_S
    plan = QUICK_ACCURACY_PLAN if quick else ACCURACY_PLAN
    compile_s = common.warmup({p[1] for p in plan} | {"radau", "dopri5"})
    system = common.cb5_system()
    rows: list[dict] = []
    ref_rows: list[dict] = []
    refs: dict = {}
    for rec in records:
        motion = common.bench_motion(rec, window)
        for law in ("arctan", "switch"):
            common.log(f"[accuracy] {rec}: reference ({law}) ...", quiet)
            ref = make_reference(system, motion, law, quick=quick, check=not quick)
            refs[(rec, law)] = ref
            for r in (ref.run, ref.check):
                if r is None:
                    continue
                ref_rows.append(
                    common.bench_row(
                        r, record=rec, **(common.run_errors(r, ref.run) if r is not ref.run else {})
                    )
                )
            if ref.check is not None and ref.check.label == "reference-check" and law == "arctan":
                # the dopri5 check is also dopri5's tightest point on the chart
                rows.append(
                    common.bench_row(ref.check, record=rec, **common.run_errors(ref.check, ref.run))
                )
                rows[-1]["label"] = "dopri5"
        for label, method, law, setting, values in plan:
            if method == "scipy" and rec not in SCIPY_RECORDS:
                continue
            sys_law = system if law == "arctan" else system.with_isolation(law=law)
            ref = refs[(rec, law)].run
            for v in values:
                common.log(f"[accuracy] {rec}: {label} {setting}={v:g}", quiet)
                if method == "scipy":
                    br = run_scipy_radau(sys_law, motion, v, repeats=repeats, label=label)
                else:
                    opts = {}
                    if quick and method == "dopri5":
                        opts["max_steps"] = QUICK_DOPRI5_MAX_STEPS
                    kw = {setting: v}
                    br = common.run_nsdyn(
                        sys_law, motion, method, label=label, repeats=repeats, **kw, **opts
                    )
                rows.append(common.bench_row(br, record=rec, **common.run_errors(br, ref)))
    ratios = {rec: matched_ratios(rows, rec) for rec in records}
    files = {}
    meta = {"window_s": window, "repeats": repeats, "compile_s": compile_s, "quick": quick}
    if out is not None:
        for r in rows + ref_rows:
            r.update(meta)
        floors = {k: ref.agreement for k, ref in refs.items()}
        tables = {
            "csv": ("accuracy.csv", rows, _ACC_FIELDS),
            "reference_csv": ("accuracy-reference.csv", ref_rows, _ACC_FIELDS),
        }
        chart = None
        if figures:
            chart = (
                "figure",
                "accuracy.png",
                lambda: accuracy_figure(rows, floors, records, window),
            )
        files = common.write_outputs(out, tables, chart)
    res = {"rows": rows, "reference_rows": ref_rows, "references": refs, "ratios": ratios}
    return {**res, "files": files, "meta": meta}


run_bench = common.entry_point(accuracy_bench)


def accuracy_figure(rows, floors, records, window):
    """The work-precision chart of :func:`accuracy_bench`'s rows (drawn by :mod:`nsdyn.plot`)."""
    from nsdyn.plot import work_precision_figure

    titles = {
        r: f"{common.RECORDS[r]}, {window:g} s, PGA {common.PGA:g} m/s², CB-5" for r in records
    }
    return work_precision_figure(
        rows, floors, records, titles=titles, unresolved_factor=UNRESOLVED_FACTOR
    )


def summarise(res: dict) -> dict:
    """The JSON summary of :func:`accuracy_bench`'s result: references and their agreement,
    the matched ratios, the failed runs and the files written."""
    refs = {
        f"{rec}/{law}": {
            "reference": f"{ref.run.method} rtol {ref.run.value:g}",
            "check": None if ref.check is None else f"{ref.check.method} rtol {ref.check.value:g}",
            "agreement_err_x": ref.agreement["err_x"],
            "agreement_err_idr": ref.agreement["err_idr"],
        }
        for (rec, law), ref in res["references"].items()
    }
    fails = [
        {k: r[k] for k in ("record", "label", "setting", "value", "status")}
        for r in res["rows"]
        if r["status"] != "ok"
    ]
    return {"references": refs, "ratios": res["ratios"], "failures": fails, "files": res["files"]}


def report(res: dict) -> str:
    """The human table of :func:`accuracy_bench`'s result (files excluded)."""
    s = summarise(res)
    lines = ["references (agreement of the independent check, err_x / err_idr):"]
    for k, v in s["references"].items():
        lines.append(
            f"  {k:12s} {v['reference']:18s} check {v['check'] or 'skipped (--quick)':22s} "
            f"{v['agreement_err_x']:.2e} / {v['agreement_err_idr']:.2e}"
        )
    lines.append(
        f"{'record':6s} {'method':12s} {'setting':>12s} {'err_x':>9s} {'err_idr':>9s} "
        f"{'wall [s]':>9s} {'steps':>8s}  status"
    )
    for r in res["rows"]:
        lines.append(
            f"{r['record']:6s} {r['label']:12s} {r['setting']:>5s}={r['value']:<6.2g} "
            f"{r['err_x']:9.2e} {r['err_idr']:9.2e} {r['wall_s']:9.3f} {r['n_steps']:8d}  "
            f"{r['status']}"
        )
    lines.append("speed ratios at matched accuracy (same run; > 1: the second is faster):")
    if res.get("meta", {}).get("quick"):  # (read as the full grid's, they contradicted it)
        lines.append("  (--quick: two or three settings per method, so a method is timed at "
                     "whichever of them first reaches the level, often far tighter; the "
                     "full grid's ratios are the ones to quote)")  # fmt: skip
    for rec, qs in s["ratios"].items():
        for name, q in qs.items():
            a, b = name.split("/")
            if not np.isfinite(q["ratio"]):
                lines.append(f"  {rec}: {name}: n/a (no common error level)")
                continue
            extra = " (scipy Radau, NumPy rhs)" if a == "scipy-radau" else ""
            wa, wb = q[a + "_wall_s"], q[b + "_wall_s"]
            lines.append(
                f"  {rec}: {name}{extra} at err_x = {q['err_x']:.2g}: {a} {wa:.3g} s, "
                f"{b} {wb:.3g} s -> {q['ratio']:.3g}x"
            )
    return "\n".join(lines)
