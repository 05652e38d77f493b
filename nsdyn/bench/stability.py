"""Stability maps: the largest stable fixed step, constraint drift and cold-start shooting.

``nsdyn bench stability`` (``stability-*.csv``, ``stability.png``): the largest stable fixed
step of dopri5 / radau / genalpha / hht / newmark (rigid and CB-5) as eps grows and as the
Baumgarte alpha grows, scanning dt down by halves from the record's step, 0.01 s (a longer step
is refused: it passes over samples). The stiffness scanned: the
friction slope d(mu lam s)/dv ~ (2/pi) mu lam eps and the constraint's double eigenvalue -alpha
of ::

    R qdd + 2 alpha beta R qd + alpha^2 R q = 0      (beta = 1)

A cell fails if the integrator reports a failure ("flagged:<reason>"), if the benchmark's NaN
or energy-balance check does ("checked:<reason>": the integrator called it a success), or if
it lands further than GARBAGE_ERR from the reference ("garbage": nobody flagged it), with
``err_x = max |x_iso - x_iso^ref| / max |x_iso^ref|`` against radau at STAB_REF_RTOL.
Constraint drift: ``max_t |R q|`` with alpha = 0 and 2 pi; cold-start shooting over (f, A).

Columns of ``stability-boundary.csv`` (one row per map, model, eps or alpha, method):
``dt_max_stable`` the largest dt at and below which every tested cell is "ok" (NaN: none);
``err_x_at_dt_max`` its err_x; ``dt_max_accurate`` the largest at and below which every cell
is ok with err_x <= ACCURATE_ERR (1e-2); ``failure_above`` and ``failure_message`` the
outcome and message of the smallest failing dt above dt_max_stable. The cells' table
(``stability-cells.csv``) holds every (dt, outcome, err_x, wall_s, t_fail, message).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from nsdyn.bench import common

__all__ = [
    "classify",
    "constraint_drift",
    "largest_stable_dt",
    "report",
    "run_bench",
    "scan_dt",
    "shooting_map",
    "stability_bench",
    "stability_figure",
    "stability_map",
    "stability_motion",
    "summarise",
]

# the command-line options run_bench takes (nsdyn.cli.bench passes only these)
OPTIONS = ("figures", "quiet")
FIGURES = ("stability.png",)  # the figures it draws (removed under --no-figures)

STAB_WINDOW = (0.0, 3.0)  # s, record window of the step-size maps (the PGA is at 2.8 s)
STAB_DT = [0.01 / 2**k for k in range(12)]  # 1e-2 (the record's step) ... 4.9e-6 s, from the top
STAB_METHODS = ["dopri5", "radau", "genalpha", "hht", "newmark"]  # all with a fixed step
ALPHA_MAP_EPS = 1e3  # s/m: a soft law, so that the Baumgarte eigenvalue -alpha shows
# what each map scans: (models, methods, values); quick: a corner of each
STAB_PLAN = {
    "eps": (["rigid", "cb-5"], STAB_METHODS, [1e2, 3e2, 1e3, 3e3, 1e4, 3e4, 1e5]),
    "alpha": (["rigid", "cb-5"], STAB_METHODS, [2 * np.pi, 30.0, 100.0, 300.0, 1e3, 3e3, 1e4]),
}
QUICK_STAB_PLAN = {
    "eps": (["cb-5"], ["dopri5", "genalpha"], [1e2, 1e4]),
    "alpha": (["rigid"], ["dopri5"], [2 * np.pi, 1e3]),
}
STAB_REF_RTOL = 1e-8  # radau reference of each map column (garbage / accuracy test)
QUICK_STAB_REF_RTOL = 1e-6
STAB_MAX_STEPS = 400_000  # step budget of one map cell (beyond: "budget", not tested)
STAB_OK_BELOW = 2  # stop a column after this many consecutive stable and accurate cells
ACCURATE_ERR = 1e-2  # err_x of the "accurate" boundary drawn next to the stability one
GARBAGE_ERR = 0.5  # a "successful" run further than this from the reference is garbage
DRIFT_SETTINGS = [("radau", "rtol", 1e-4), ("radau", "rtol", 1e-7), ("genalpha", "dt", 1e-3)]
QUICK_DRIFT_SETTINGS = [("radau", "rtol", 1e-4)]
SHOOT_F = [0.03, 0.05, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0, 3.0, 5.0]  # Hz
SHOOT_A = [0.1, 0.3, 1.0, 3.0]  # m/s^2
QUICK_SHOOT_F = [0.05, 1.0]
QUICK_SHOOT_A = [0.3, 3.0]

# columns of the CSV tables, in order

# columns of the CSV tables, in order
_CELL_FIELDS = "map model eps alpha method dt outcome err_x wall_s t_fail message".split()


def stability_motion(quick: bool = False):
    """The white-noise record's first 3 s (STAB_WINDOW; the PGA, 3 m/s^2, is at 2.8 s)."""
    m = common.bench_motion("wn", common.WINDOW_S)
    t0, t1 = STAB_WINDOW
    return m.window(m.t0 + t0, m.t0 + t1)


def classify(run: common.BenchRun, ref: common.BenchRun | None) -> tuple[str, float]:
    """(outcome, err_x) of one map cell.

    outcome: "ok"; "flagged:<reason>" (the integrator raised); "checked:<reason>" (the
    benchmark's NaN / energy-balance check caught it); "garbage" (reported as a success, passed
    those checks, but further than GARBAGE_ERR from the reference: a failure nobody flagged);
    "budget" (more than STAB_MAX_STEPS steps: not tested).
    """
    if run.status == "max_steps":
        return "budget", float("nan")
    if run.status in ("nan_output", "energy_blowup"):
        err = (
            common.run_errors(run, ref, flagged=True)["err_x"] if ref is not None else float("nan")
        )
        return f"checked:{run.status}", err
    if not run.ok:
        return f"flagged:{run.status}", float("nan")
    err = common.run_errors(run, ref)["err_x"] if ref is not None else float("nan")
    if np.isfinite(err) and err > GARBAGE_ERR:
        return "garbage", err
    return "ok", err


def scan_dt(
    system, motion, method: str, ref: common.BenchRun | None, dts=STAB_DT, accurate: bool = True
) -> list[dict]:
    """Cells of one (system, method) column, dt decreasing, until STAB_OK_BELOW consecutive
    cells are ok and (with ``accurate``) accurate: err_x <= ACCURATE_ERR."""
    cells = []
    n_good = 0
    for dt in dts:
        if motion.duration / dt > STAB_MAX_STEPS:
            cells.append({"dt": dt, "outcome": "budget", "err_x": float("nan"), "message": ""})
            continue
        br = common.run_nsdyn(system, motion, method, dt=dt, repeats=1, max_steps=STAB_MAX_STEPS)
        outcome, err = classify(br, ref)
        cells.append(
            {
                "dt": dt,
                "outcome": outcome,
                "err_x": err,
                "wall_s": br.wall_s,
                "t_fail": br.t_fail,
                "message": br.message,
            }
        )
        good = outcome == "ok" and (ref is None or not accurate or err <= ACCURATE_ERR)
        n_good = n_good + 1 if good else 0
        if n_good >= STAB_OK_BELOW:
            break
    return cells


def largest_stable_dt(cells: list[dict], max_err: float = np.inf) -> float:
    """Largest dt of a column at and below which every tested cell is ok (and, with
    ``max_err``, has err_x <= max_err); NaN if none."""
    best = float("nan")
    for c in sorted(cells, key=lambda c: c["dt"]):
        if c["outcome"] == "budget":
            continue
        if c["outcome"] != "ok" or not (c["err_x"] <= max_err or max_err == np.inf):
            break
        best = c["dt"]
    return best


def _build_map_system(frame, kind: str, model: str, value: float):
    from nsdyn.models.isolated.system import build_system

    iso = (
        common.bench_isolation(eps=value)
        if kind == "eps"
        else common.bench_isolation(eps=ALPHA_MAP_EPS, alpha=value)
    )
    if model == "rigid":
        return build_system(frame, iso, fidelity="rigid")
    return build_system(frame, iso, fidelity="cb", f_max=float(model.split("-")[1]))


def stability_map(
    frame, kind: str, plan, motion, quiet=False, quick: bool = False
) -> tuple[list, list]:
    """Cells (one per run) and boundary rows (one per model x value x method) of one map.

    ``quick``: a looser reference (QUICK_STAB_REF_RTOL) and no scan for the accurate boundary.
    """
    models, methods, values = plan
    cells_rows, bound_rows = [], []
    for value in values:
        for model in models:
            system = _build_map_system(frame, kind, model, value)
            rtol = QUICK_STAB_REF_RTOL if quick else STAB_REF_RTOL
            ref = common.run_nsdyn(system, motion, "radau", label="reference", rtol=rtol, repeats=1)
            if not ref.ok:
                common.log(
                    f"[stability] {kind} = {value:g}, {model}: reference failed: {ref.message}"
                )
                ref = None
            for method in methods:
                common.log(f"[stability] {kind} = {value:g}, {model}: {method}", quiet)
                cells = scan_dt(system, motion, method, ref, accurate=not quick)
                dt_max = largest_stable_dt(cells)
                dt_acc = largest_stable_dt(cells, ACCURATE_ERR) if ref is not None else np.nan
                above = [c for c in cells if c["dt"] > dt_max and c["outcome"] != "budget"]
                fail = min(above, key=lambda c: c["dt"]) if above else None
                at = next((c for c in cells if c["dt"] == dt_max), {})
                for c in cells:
                    cells_rows.append(
                        {"map": kind, "model": model, kind: value, "method": method, **c}
                    )
                bound_rows.append(
                    {
                        "map": kind,
                        "model": model,
                        kind: value,
                        "method": method,
                        "dt_max_stable": dt_max,
                        "err_x_at_dt_max": at.get("err_x", np.nan),
                        "dt_max_accurate": dt_acc,
                        "failure_above": fail["outcome"] if fail else "",
                        "failure_message": fail["message"] if fail else "",
                    }
                )
    return cells_rows, bound_rows


def constraint_drift(system, motion, settings=DRIFT_SETTINGS, quiet=False) -> tuple[list, dict]:
    """max_t |R q| without Baumgarte stabilisation (alpha = 0) and with the default alpha."""
    rows, hist = [], {}
    for alpha in (0.0, system.isolation.alpha):
        s = system.with_isolation(alpha=alpha)
        for method, setting, value in settings:
            common.log(f"[stability] drift: alpha = {alpha:g}, {method} {setting}={value:g}", quiet)
            br = common.run_nsdyn(s, motion, method, repeats=1, keep_state=True, **{setting: value})
            if br.ok:
                Rq = np.abs(br.x[:, : s.n] @ s.R.T).max(axis=1)
                Rv = np.abs(br.x[:, s.n :] @ s.R.T).max(axis=1)
                hist[(alpha, method, value)] = (br.t, Rq)
                drift, vdrift = float(Rq.max()), float(Rv.max())
            else:
                drift = vdrift = float("nan")
            rows.append(
                {
                    "map": "drift",
                    "alpha": alpha,
                    "method": method,
                    "setting": setting,
                    "value": value,
                    "status": br.status,
                    "max_abs_Rq_m": drift,
                    "max_abs_Rqd_mps": vdrift,
                    "wall_s": br.wall_s,
                    "message": br.message,
                }
            )
    return rows, hist


def shooting_map(system, f_values, a_values, quiet=False) -> list[dict]:
    """Cold-start shooting (from the static equilibrium) on a grid of (f, A); converged or why not.

    Uses :func:`nsdyn.periodic.shoot` if the module imports and runs; otherwise one row saying
    why it was not used.
    """
    try:
        from nsdyn import periodic
    except Exception as e:  # the module is being written by another engineer
        return [{"map": "shooting", "status": "unavailable", "message": repr(e)}]
    rows = []
    for A in a_values:
        try:
            prob = periodic.frame_problem(system, A)
        except Exception as e:
            return [{"map": "shooting", "status": "unavailable", "message": repr(e)}]
        for f in f_values:
            common.log(f"[stability] shooting: A = {A:g} m/s2, f = {f:g} Hz", quiet)
            t0 = time.perf_counter()
            try:
                r = periodic.shoot(prob, f)
                status = "converged" if r.converged else "failed"
                msg, it, res = r.message, r.iterations, r.residual
            except Exception as e:
                status, msg, it, res = "error", repr(e), -1, float("nan")
            rows.append(
                {
                    "map": "shooting",
                    "f_hz": f,
                    "A_mps2": A,
                    "status": status,
                    "reason": _shoot_reason(msg) if status != "converged" else "",
                    "iterations": it,
                    "residual": res,
                    "wall_s": time.perf_counter() - t0,
                    "message": msg,
                }
            )
    return rows


def _shoot_reason(msg: str) -> str:
    m = msg.lower()
    for key, reason in (
        ("stage newton", "stage_newton"),
        ("line search", "line_search"),
        ("no convergence", "max_iterations"),
        ("singular", "singular"),
        ("not finite", "nonfinite"),
        ("inf/nan", "nonfinite"),
    ):
        if key in m:
            return reason
    return "other"


def stability_bench(
    *,
    quick: bool = False,
    out: Path | None = common.DEFAULT_OUT,
    figures: bool = True,
    quiet: bool = False,
) -> dict:
    """Largest stable fixed step vs eps and vs alpha; constraint drift; shooting failures."""
    plan = QUICK_STAB_PLAN if quick else STAB_PLAN
    methods = {m for _, ms, _ in plan.values() for m in ms}
    compile_s = common.warmup(methods | {"radau"})
    frame = common.bench_frame()
    motion = stability_motion(quick)
    eps_cells, eps_bound = stability_map(frame, "eps", plan["eps"], motion, quiet, quick)
    a_cells, a_bound = stability_map(frame, "alpha", plan["alpha"], motion, quiet, quick)
    cb5 = common.cb5_system(frame)
    drift_motion = common.bench_motion("wn", common.QUICK_WINDOW_S if quick else common.WINDOW_S)
    drift_rows, drift_hist = constraint_drift(
        cb5, drift_motion, QUICK_DRIFT_SETTINGS if quick else DRIFT_SETTINGS, quiet=quiet
    )
    shoot_rows = shooting_map(
        cb5,
        QUICK_SHOOT_F if quick else SHOOT_F,
        QUICK_SHOOT_A if quick else SHOOT_A,
        quiet=quiet,
    )
    garbage = [c for c in eps_cells + a_cells if c["outcome"] == "garbage"]
    meta = {"window_s": motion.duration, "compile_s": compile_s, "quick": quick}
    files = {}
    if out is not None:
        tables = {
            "cells_csv": ("stability-cells.csv", eps_cells + a_cells, _CELL_FIELDS),
            "boundary_csv": ("stability-boundary.csv", eps_bound + a_bound, _BOUND_FIELDS),
            "drift_csv": ("stability-drift.csv", drift_rows, None),
            "shooting_csv": ("stability-shooting.csv", shoot_rows, None),
        }
        chart = None
        if figures:
            cells = eps_cells + a_cells
            args = (eps_bound, a_bound, cells, drift_hist, shoot_rows)
            chart = ("figure", "stability.png", lambda: stability_figure(*args))
        files = common.write_outputs(out, tables, chart)
    return {
        "eps_cells": eps_cells,
        "eps_boundary": eps_bound,
        "alpha_cells": a_cells,
        "alpha_boundary": a_bound,
        "drift": drift_rows,
        "shooting": shoot_rows,
        "unflagged_garbage": garbage,
        "files": files,
        "meta": meta,
    }


run_bench = common.entry_point(stability_bench)


_BOUND_FIELDS = (
    "map model eps alpha method dt_max_stable err_x_at_dt_max dt_max_accurate failure_above "
    "failure_message"
).split()


def stability_figure(eps_bound, a_bound, cells, drift_hist, shoot_rows):
    """The maps of :func:`stability_bench` (drawn by :mod:`nsdyn.plot`)."""
    from nsdyn import plot

    return plot.stability_figure(
        eps_bound,
        a_bound,
        cells,
        drift_hist,
        shoot_rows,
        methods=STAB_METHODS,
        dt_top=STAB_DT[0],
        alpha_eps=ALPHA_MAP_EPS,
        accurate=ACCURATE_ERR,
    )


def summarise(res: dict) -> dict:
    """The JSON summary of :func:`stability_bench`'s result: all but the cells."""
    return {k: v for k, v in res.items() if k not in ("eps_cells", "alpha_cells")}


def report(res: dict) -> str:
    """The human summary of :func:`stability_bench`'s result (files excluded)."""
    lines = [
        f"compilation (or its cache's load), before any timing: {res['meta']['compile_s']:.2f} s",
        "largest stable fixed step [s] and the failure the code reported above it:",
    ]
    for b in res["eps_boundary"] + res["alpha_boundary"]:
        key = "eps" if b["map"] == "eps" else "alpha"
        acc = b["dt_max_accurate"]  # NaN: no tested step met the accuracy bound
        acc = f"at and below {acc:.3g}" if np.isfinite(acc) else "at no tested step"
        lines.append(
            f"  {key}={b[key]:<8.3g} {b['model']:6s} {b['method']:9s} "
            f"{b['dt_max_stable']:9.3g} (err_x there {b['err_x_at_dt_max']:.2g}; accurate "
            f"{acc})  failure above: {b['failure_above'] or '-'}"
        )
    lines.append("constraint drift max |R q| [m]:")
    for d in res["drift"]:
        lines.append(
            f"  alpha={d['alpha']:<6.3g} {d['method']:9s} {d['setting']}={d['value']:<6.2g} "
            f"{d['max_abs_Rq_m']:.3e}  {d['status']}"
        )
    sr = [r for r in res["shooting"] if "f_hz" in r]
    if sr:
        bad = [r for r in sr if r["status"] != "converged"]
        lines.append(f"shooting: {len(sr) - len(bad)}/{len(sr)} converged; failures:")
        for r in bad:
            lines.append(f"  f={r['f_hz']:g} Hz A={r['A_mps2']:g} m/s2: {r['reason']}")
    else:
        why = res["shooting"][0]["message"] if res["shooting"] else ""
        lines.append(f"shooting: not run ({why})")
    g = res["unflagged_garbage"]
    lines.append(f"unflagged garbage cells: {len(g)}")
    for c in g:
        lines.append(
            f"  {c['map']}={c.get(c['map'])} {c['model']} {c['method']} dt={c['dt']:g}: "
            f"err_x {c['err_x']:.2g}"
        )
    return "\n".join(lines)
