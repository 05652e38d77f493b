"""The transient speed table: nsdyn's default run against SciPy Radau at matched accuracy.

``nsdyn bench speed`` (``speed.csv``, ``speed-table.csv``, ``speed.png``): the default scene
(:mod:`nsdyn.models.isolated.scene`: office frame, CB-5, isolated, arctan eps 7500, the bundled
40 s record at PGA 3 m/s^2, radau at the scene's tolerances, output every dt_out) and, when
``shared/records`` is found, the four Kobe 1995 records at the same PGA, first 40 s. Per
record: nsdyn's steps, wall time (median of 2 x ``repeats`` runs, half before and half after
SciPy's) and errors against radau at rtol :data:`SPEED_REF_RTOL`, itself checked against
:data:`SPEED_CHECK_RTOL`::

    err_x   = max_{t, i} |x_iso,i - x_iso,i^ref| / max |x_iso^ref|,
    err_idr = |IDR_max / IDR_max^ref - 1|;

then SciPy Radau on the NumPy equations (:mod:`nsdyn.bench.baseline`) at the loosest rtol of
SCIPY_RTOLS (atol scaled with it) whose err_x is no larger (:func:`scipy_match`), timed once or
as the median of 3 when shorter than LONG_RUN_S, and the ratio of the two wall times,
``ratio = wall_SciPy / wall_nsdyn``. nsdyn lands its steps on the record's samples (the input
is piecewise linear); SciPy steps across them: part of the ratio is that, not compiled code.
Compilation is reported apart (``integrate.warmup`` in this process; ``--cold-compile``: with
an empty numba cache in a fresh process, and the wall time of ``nsdyn run --t-end 1 --json`` in
fresh processes, median of START_REPEATS, with an empty cache each time (a first run) and with
the cache a previous run filled (every later run)). ``--families``: also the first-run table of
every model family (``first-runs.csv``, :mod:`nsdyn.bench.first_runs`; several minutes).
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

from nsdyn.bench import common, first_runs
from nsdyn.bench.baseline import run_scipy_radau

__all__ = [
    "cli_start_s",
    "cold_compile_s",
    "default_run_ratio",
    "report",
    "run_bench",
    "scipy_match",
    "speed_bench",
    "speed_figure",
    "speed_markdown",
    "speed_motions",
    "speed_scene",
    "summarise",
]

# the command-line options run_bench takes (nsdyn.cli.bench passes only these)
OPTIONS = ("repeats", "figures", "quiet", "cold_compile", "families")
FIGURES = ("speed.png",)  # the figures it draws (removed under --no-figures)

SPEED_T_END = 40.0  # s: the first 40 s of every record (the bundled one is 40 s long)
SPEED_REPEATS = 5  # timed repeats of the nsdyn run (median)
QUICK_SPEED_REPEATS = 3
QUICK_SPEED_T_END = common.QUICK_WINDOW_S  # --quick: the bundled record's first 3 s (holds its PGA)
SPEED_KOBE_COMPONENT = "000"
SPEED_REF_RTOL = 1e-9  # reference: radau at this rtol, atol ATOL_FACTOR * rtol
SPEED_CHECK_RTOL = 1e-10  # its convergence check: radau 10x tighter
# SciPy's rtol grid (loosest first; the scene's rtol is added). atol keeps the scene's ratio to
# rtol: (1e-8 m, 1e-6 m/s) at rtol 1e-4 becomes (1e-10, 1e-8) at rtol 1e-6.
SCIPY_RTOLS = [1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9]
SCIPY_BUDGET_S = 1800.0  # a SciPy run still going after this is stopped (ratio: lower bound)
QUICK_SCIPY_RTOLS = [1e-6, 1e-7]  # --quick: the scene's rtol and these
QUICK_SCIPY_BUDGET_S = 60.0
START_REPEATS = 3  # fresh processes per start-time measurement (median)
START_T_END = 1.0  # s: the simulated window of the start-time run (compilation dominates)
SCIPY_REPEATS = 3  # timed runs of the matched SciPy setting when one takes < LONG_RUN_S

# columns of the CSV tables, in order
_SPEED_FIELDS = (
    "record role label method rtol atol_q atol_v status err_x err_idr err_xpeak err_acc "
    "wall_s n_timed n_steps nfev x_iso_max_m idr_max floor_acc_max_mps2 window_s compile_s "
    "cold_compile_s quick message"
).split()


def speed_scene(t_end: float | None = None):
    """``(cfg, system, motion, solver)`` of the default scene, as ``nsdyn run`` builds them.

    ``t_end`` cuts the record as ``nsdyn run --t-end`` does. ``solver``: method, rtol, atol
    (the scene's, else :func:`nsdyn.solve.transient.default_atol`) and dt_out.
    """
    from nsdyn.models.isolated.scene import build_scene, load_scene
    from nsdyn.solve.transient import default_atol

    cfg = load_scene(None, {"motion": {"t_end": float(t_end)}} if t_end else None)
    system, motion = build_scene(cfg)
    sv = cfg["solver"]
    method = sv.get("method", "radau")
    if method == "auto":  # as nsdyn run chooses it (radau for this model)
        from nsdyn.solve.auto import choose_for_system

        method = choose_for_system(system)[0]
    if method != "radau" or system.isolation is None or system.isolation.law != "arctan":
        raise ValueError("the speed table compares Radau runs of the arctan law")
    atol = sv.get("atol")
    atol = tuple(atol) if isinstance(atol, list) else atol
    solver = {
        "method": method,
        "rtol": float(sv["rtol"]),
        "atol": default_atol(method) if atol is None else atol,
        "dt_out": sv.get("dt_out"),
    }
    return cfg, system, motion, solver


def speed_motions(motion, pga: float, *, quick: bool = False, shared_dir=None) -> dict:
    """The scene's record and, unless ``quick``, the four Kobe records (when the shared
    records directory is found), each scaled to ``pga``, first SPEED_T_END seconds."""
    from nsdyn.ground import RecordFileError, default_shared_dir, kobe_records

    out = {motion.name: motion}
    if quick:
        return out
    shared = default_shared_dir() if shared_dir is None else Path(shared_dir)
    try:  # (without the shared folder a pip user's table had one row, without a word)
        if shared is None:
            raise OSError("no shared records folder (NSDYN_SHARED or shared/ beside the checkout)")
        kobe = kobe_records(shared, SPEED_KOBE_COMPONENT)
    except (OSError, RecordFileError) as e:
        common.log(f"[speed] Kobe records not used: {e}")
        return out
    for name, m in kobe.items():
        m = m.scaled_to_pga(pga)
        out[name] = m.window(m.t0, m.t0 + min(SPEED_T_END, m.duration))
    return out


def _scaled_atol(atol, rtol: float, rtol0: float):
    a = np.asarray(atol, dtype=float) * (rtol / rtol0)
    return tuple(float(v) for v in a) if a.ndim else float(a)


def scipy_match(
    system,
    motion,
    t_eval,
    ref: common.BenchRun,
    target: float,
    solver: dict,
    *,
    budget_s,
    rtols=SCIPY_RTOLS,
    quiet=False,
) -> tuple[list, common.BenchRun | None]:
    """SciPy Radau on the rtol grid until the loosest setting with err_x <= ``target``.

    Starts at the scene's tolerances, jumps to the rtol a linear error model (error ~ rtol)
    predicts, steps tighter until the target is met, then looser while it still is: the
    answer meets the target and the next looser grid rtol does not. Returns (every run,
    loosest matching run or None). A run stopped by ``budget_s`` ends the search.
    """
    grid = sorted(set(rtols) | {solver["rtol"]}, reverse=True)
    runs: dict[int, common.BenchRun] = {}

    def attempt(i: int) -> common.BenchRun:
        if i not in runs:
            rt = grid[i]
            common.log(f"[speed] {getattr(motion, 'name', '')}: scipy-radau rtol {rt:g}", quiet)
            br = run_scipy_radau(
                system,
                motion,
                rt,
                repeats=1,
                atol=_scaled_atol(solver["atol"], rt, solver["rtol"]),
                t_eval=t_eval,
                budget_s=budget_s,
            )
            br.errors = common.run_errors(br, ref)
            runs[i] = br
        return runs[i]

    def matched(br: common.BenchRun) -> bool:
        return br.ok and br.errors["err_x"] <= target

    i = grid.index(solver["rtol"])
    br = attempt(i)
    if not matched(br) and br.status != "budget":
        j = i + 1
        e = br.errors["err_x"]
        if br.ok and np.isfinite(e) and e > 0:
            r_pred = grid[i] * target / e
            j = max(i + 1, next((k for k, r in enumerate(grid) if r <= r_pred), len(grid) - 1))
        while j < len(grid):
            br = attempt(j)
            if matched(br) or br.status == "budget" or j == len(grid) - 1:
                break
            j += 1
        i = j
    best = None
    if i in runs and matched(runs[i]):
        while i > 0 and matched(attempt(i - 1)):
            i -= 1
        best = runs[i]
    return [runs[k] for k in sorted(runs)], best


def cold_compile_s(methods=("radau",)) -> float:
    """Seconds :func:`nsdyn.solve.integrate.warmup` takes in a fresh process with an empty numba
    cache: the JIT compilation a first run pays once (later processes load the cache)."""
    import subprocess

    code = (
        "import json\nfrom nsdyn.solve import integrate\n"
        f"print(json.dumps(integrate.warmup({list(methods)!r})))"
    )
    with tempfile.TemporaryDirectory(prefix="nsdyn-numba-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        root = str(Path(__file__).resolve().parents[2])
        env["PYTHONPATH"] = os.pathsep.join(p for p in (root, env.get("PYTHONPATH")) if p)
        res = subprocess.run(
            [sys.executable, "-P", "-c", code], env=env, capture_output=True, text=True, check=True
        )
    return float(sum(json.loads(res.stdout.strip().splitlines()[-1]).values()))


def _cli_env(cache: str) -> dict:
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    env["NSDYN_MODEL_CACHE"] = os.path.join(cache, "models")  # empty with the kernels'
    root = str(Path(__file__).resolve().parents[2])
    env["PYTHONPATH"] = os.pathsep.join(p for p in (root, env.get("PYTHONPATH")) if p)
    return env


def cli_start_s(repeats: int = START_REPEATS) -> dict:
    """Wall seconds of ``nsdyn run --t-end START_T_END --json`` in fresh processes: ``cold``
    with an empty numba cache each time (what a first run pays), ``cached`` once a run has
    filled the cache (every later start). Returns medians and the single runs."""
    import subprocess
    import time

    # -P: this nsdyn (PYTHONPATH), not one in the working directory (as the compile helper)
    cmd = [sys.executable, "-P", "-m", "nsdyn.cli", "run", "--t-end", f"{START_T_END:g}"]
    cmd += ["--json"]
    cmd += ["--no-figures"]

    def once(cache: str) -> float:
        with tempfile.TemporaryDirectory(prefix="nsdyn-start-") as out:
            t0 = time.perf_counter()
            subprocess.run(
                [*cmd, "--out", out], env=_cli_env(cache), capture_output=True, check=True
            )
            return time.perf_counter() - t0

    cold = []
    for _ in range(repeats):
        with tempfile.TemporaryDirectory(prefix="nsdyn-numba-") as cache:
            cold.append(once(cache))
    with tempfile.TemporaryDirectory(prefix="nsdyn-numba-") as cache:
        once(cache)  # fills the cache
        cached = [once(cache) for _ in range(repeats)]
    return {
        "cold_s": float(np.median(cold)),
        "cached_s": float(np.median(cached)),
        "cold_runs_s": cold,
        "cached_runs_s": cached,
    }


def default_run_ratio(system, motion, solver: dict, repeats: int = SPEED_REPEATS) -> dict:
    """The default ``simulate`` call (method ``radau``: smooth laws through the flat
    right-hand side of :mod:`nsdyn.solve._kflat`) against the same call with
    ``radau-generic`` (the general kernel at every evaluation: the path before), interleaved
    in this process. Returns medians of the whole call and of the integration alone, the
    ratio ``baseline / default`` (median of the per-pair ratios) and both runs' statistics."""
    import time

    from nsdyn.solve.transient import output_grid, simulate

    kw = dict(
        rtol=solver["rtol"], atol=solver["atol"], t_eval=output_grid(motion, solver["dt_out"])
    )
    calls = {"radau": [], "radau-generic": []}
    res = {}
    for _ in range(repeats):
        for method, times in calls.items():
            t0 = time.perf_counter()
            res[method] = simulate(system, motion, method=method, **kw)
            times.append((time.perf_counter() - t0, res[method].wall_s))
    new, old = np.array(calls["radau"]), np.array(calls["radau-generic"])
    out = {"repeats": repeats}
    for key, a in (("default", new), ("baseline", old)):
        r = res["radau" if key == "default" else "radau-generic"]
        out[f"{key}_call_s"] = float(np.median(a[:, 0]))
        out[f"{key}_wall_s"] = float(np.median(a[:, 1]))
        out[f"{key}_stats"] = dict(r.stats, n_steps=r.n_steps)
    out["ratio_call"] = float(np.median(old[:, 0] / new[:, 0]))
    out["ratio_wall"] = float(np.median(old[:, 1] / new[:, 1]))
    xa, xb = res["radau"].response.x_iso, res["radau-generic"].response.x_iso
    out["x_iso_rel_diff"] = float(np.max(np.abs(xa - xb)) / np.max(np.abs(xb)))
    return out


def _speed_row(run: common.BenchRun, record: str, role: str, **extra) -> dict:
    row = common.bench_row(run, record=record, role=role, **run.errors)
    row.update(extra)
    return row


def speed_bench(
    *,
    quick: bool = False,
    cold_compile: bool = False,
    families: bool = False,
    shared_dir=None,
    repeats: int | None = None,
    out: Path | None = common.DEFAULT_OUT,
    figures: bool = True,
    quiet: bool = False,
) -> dict:
    """The transient speed table: nsdyn radau at the default scene's tolerances against SciPy
    Radau on the NumPy equations at matched accuracy, per record (module docstring, "Speed").

    Returns ``{"rows", "table", "files", "meta"}``; writes ``speed.csv`` (every run),
    ``speed-table.csv`` (one row per record) and ``speed.png`` to ``out`` (None: nothing).
    """
    from nsdyn.solve.transient import output_grid

    repeats = (QUICK_SPEED_REPEATS if quick else SPEED_REPEATS) if repeats is None else repeats
    cfg, system, motion, solver = speed_scene(QUICK_SPEED_T_END if quick else None)
    compile_s = common.warmup([solver["method"]])
    common.log("[speed] the default run against the general right-hand side (baseline)", quiet)
    default_run = default_run_ratio(system, motion, solver, max(repeats, 5))
    cold_s = cold_compile_s([solver["method"]]) if cold_compile else float("nan")
    starts = cli_start_s() if cold_compile else {"cold_s": float("nan"), "cached_s": float("nan")}
    budget = QUICK_SCIPY_BUDGET_S if quick else SCIPY_BUDGET_S
    pga = float(cfg["motion"].get("pga", common.PGA))
    motions = speed_motions(motion, pga, quick=quick, shared_dir=shared_dir)
    atol_q, atol_v = common.atol_pair(solver["atol"])
    rows, table = [], []
    for name, m in motions.items():
        t_eval = output_grid(m, solver["dt_out"])
        common.log(f"[speed] {name}: reference radau rtol {SPEED_REF_RTOL:g}, check", quiet)
        kw = dict(repeats=1, t_eval=t_eval)
        ref = common.run_nsdyn(system, m, "radau", label="reference", rtol=SPEED_REF_RTOL, **kw)
        if not ref.ok:
            raise RuntimeError(f"speed reference ({name}) failed: {ref.status}: {ref.message}")
        chk = common.run_nsdyn(
            system, m, "radau", label="reference-check", rtol=SPEED_CHECK_RTOL, **kw
        )
        chk.errors = common.run_errors(chk, ref)
        ref.errors = common.nan_errors()
        common.log(f"[speed] {name}: nsdyn radau at the scene's tolerances ({repeats} runs)", quiet)
        ns = common.run_nsdyn(
            system,
            m,
            "radau",
            label="nsdyn-radau",
            rtol=solver["rtol"],
            atol=solver["atol"],
            repeats=repeats,
            t_eval=t_eval,
        )
        ns.errors = common.run_errors(ns, ref)
        runs, best = [], None
        if ns.ok:
            runs, best = scipy_match(
                system,
                m,
                t_eval,
                ref,
                ns.errors["err_x"],
                solver,
                budget_s=budget,
                rtols=QUICK_SCIPY_RTOLS if quick else SCIPY_RTOLS,
                quiet=quiet,
            )
        # time nsdyn again after SciPy's runs (the machine's load drifts over minutes): the
        # median of the runs before and after
        more_ns = common.run_nsdyn(
            system,
            m,
            "radau",
            rtol=solver["rtol"],
            atol=solver["atol"],
            repeats=repeats,
            t_eval=t_eval,
        )
        if more_ns.ok:
            ns.walls.extend(more_ns.walls)
        if best is not None and not quick and best.wall_s < common.LONG_RUN_S and SCIPY_REPEATS > 1:
            more = run_scipy_radau(
                system,
                m,
                best.value,
                repeats=SCIPY_REPEATS - 1,
                atol=_scaled_atol(solver["atol"], best.value, solver["rtol"]),
                t_eval=t_eval,
            )
            if more.ok:
                best.walls.extend(more.walls)
        same = next((r for r in runs if r.value == solver["rtol"]), None)
        done = [
            (ref, "reference", (ref.value * common.ATOL_FACTOR,) * 2),
            (chk, "reference-check", (chk.value * common.ATOL_FACTOR,) * 2),
            (ns, "nsdyn", (atol_q, atol_v)),
        ]
        for r in runs:
            role = "scipy-matched" if r is best else "scipy-search"
            done.append(
                (r, role, common.atol_pair(_scaled_atol(solver["atol"], r.value, solver["rtol"])))
            )
        for r, role, (aq, av) in done:
            rows.append(
                _speed_row(r, name, role, rtol=r.value, atol_q=aq, atol_v=av, window_s=m.duration)
            )
        if best is not None:
            ratio, bound = best.wall_s / ns.wall_s, ""
        else:  # no SciPy run reached the error: its longest (failed) try bounds the ratio
            longest = max((r.wall_s for r in runs), default=float("nan"))
            ratio, bound = longest / ns.wall_s, ">"
        table.append(
            {
                "record": name,
                "window_s": float(m.duration),
                "n_steps": ns.n_steps,
                "wall_s": ns.wall_s,
                "n_timed": len(ns.walls),
                "err_x": ns.errors["err_x"],
                "err_idr": ns.errors["err_idr"],
                "ref_check_err_x": chk.errors["err_x"],
                "ref_check_err_idr": chk.errors["err_idr"],
                "scipy_rtol": best.value if best else float("nan"),
                "scipy_wall_s": best.wall_s if best else float("nan"),
                "scipy_n_timed": len(best.walls) if best else 0,
                "scipy_n_steps": best.n_steps if best else 0,
                "scipy_err_x": best.errors["err_x"] if best else float("nan"),
                "scipy_err_idr": best.errors["err_idr"] if best else float("nan"),
                "ratio": ratio,
                "ratio_bound": bound,
                "scipy_same_tol_wall_s": same.wall_s if same else float("nan"),
                "scipy_same_tol_err_x": same.errors["err_x"] if same else float("nan"),
                "scipy_same_tol_err_idr": same.errors["err_idr"] if same else float("nan"),
                "status": ns.status,
            }
        )
    meta = {
        "scene": cfg.get("_source", "<default scene>"),
        "model": system.name,
        "rtol": solver["rtol"],
        "atol_q": atol_q,
        "atol_v": atol_v,
        "dt_out": solver["dt_out"],
        "pga": pga,
        "repeats": repeats,
        "compile_s": compile_s,
        "cold_compile_s": cold_s,
        "cli_cold_start_s": starts["cold_s"],
        "cli_cached_start_s": starts["cached_s"],
        "quick": quick,
        "default_run": default_run,
    }
    for r in rows:
        r.update({k: meta[k] for k in ("compile_s", "cold_compile_s", "quick")})
    for r in table:
        r.update({k: v for k, v in meta.items() if k not in ("scene", "default_run")})
    first = first_runs.first_runs(log=lambda m: common.log(m, quiet)) if families else []
    files = {}
    if out is not None:
        tables = {
            "csv": ("speed.csv", rows, _SPEED_FIELDS),
            "table_csv": ("speed-table.csv", table, None),
            **({"first_runs_csv": ("first-runs.csv", first, None)} if first else {}),
        }
        chart = ("figure", "speed.png", lambda: speed_figure(rows, table)) if figures else None
        files = common.write_outputs(out, tables, chart)
    return {"rows": rows, "table": table, "files": files, "meta": meta, "first_runs": first}


run_bench = common.entry_point(speed_bench)


def speed_markdown(res: dict) -> str:
    """The speed table as markdown (the README's), with its settings."""
    meta = res["meta"]
    lines = [
        f"{meta['model']}, radau at rtol {meta['rtol']:g}, atol ({meta['atol_q']:g} m, "
        f"{meta['atol_v']:g} m/s), output every {meta['dt_out']:g} s; PGA {meta['pga']:g} m/s²; "
        f"wall = median of {2 * meta['repeats']} runs after compilation ({meta['repeats']} "
        "before SciPy's runs, as many after); errors against radau at "
        f"rtol {SPEED_REF_RTOL:g} (reference check: rtol {SPEED_CHECK_RTOL:g}).",
        "",
        "| record | window | steps | wall [s] | err x_iso | err IDR | reference check "
        "x_iso / IDR | SciPy rtol | SciPy steps | SciPy wall [s] | SciPy err x_iso | "
        "SciPy err IDR | SciPy / nsdyn |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for t in res["table"]:
        sc = (
            f"{t['scipy_rtol']:.0e} | {t['scipy_n_steps']} | {t['scipy_wall_s']:.3g}"
            f"{'' if t['scipy_n_timed'] > 1 else ' (1 run)'} | {t['scipy_err_x']:.1e} | "
            f"{t['scipy_err_idr']:.1e}"
            if np.isfinite(t["scipy_rtol"])
            else "none reached it | | | |"
        )
        lines.append(
            f"| {t['record']} | {t['window_s']:g} s | {t['n_steps']} | {t['wall_s']:.3f} | "
            f"{t['err_x']:.1e} | {t['err_idr']:.1e} | {t['ref_check_err_x']:.0e} / "
            f"{t['ref_check_err_idr']:.0e} | {sc} | {t['ratio_bound']}{t['ratio']:.0f}× |"
        )
    lines += [f"\n{t['record']}: SciPy's run is {t['err_x'] / t['scipy_err_x']:.0f}× more accurate "
              "than nsdyn's (no rtol of its grid between): the ratio overstates the speed-up"
              for t in res["table"] if t["scipy_err_x"] < 0.1 * t["err_x"]]  # fmt: skip
    comp = f"compilation (integrate.warmup, this process): {meta['compile_s']:.2f} s"
    if np.isfinite(meta["cold_compile_s"]):
        comp += f"; with an empty numba cache: {meta['cold_compile_s']:.0f} s"
    if np.isfinite(meta.get("cli_cold_start_s", float("nan"))):
        comp += (
            f"; `nsdyn run --t-end {START_T_END:g} --json` start (median of {START_REPEATS} "
            f"fresh processes): first run {meta['cli_cold_start_s']:.1f} s, cached "
            f"{meta['cli_cached_start_s']:.1f} s"
        )
    d = meta.get("default_run")
    if d:
        lines.append(
            f"\nThe default run (`simulate`, {d['default_stats']['n_steps']} steps): "
            f"{1e3 * d['default_call_s']:.1f} ms (integration {1e3 * d['default_wall_s']:.1f} ms)"
            f" against {1e3 * d['baseline_call_s']:.1f} ms ({1e3 * d['baseline_wall_s']:.1f} ms)"
            f" with the general right-hand side: {d['ratio_call']:.2f}× "
            f"({d['ratio_wall']:.2f}× on the integration), each the median of {d['repeats']} "
            f"interleaved pairs' ratios; x_iso histories differ by {d['x_iso_rel_diff']:.1e}."
        )
    lines += ["", comp]
    same = [t for t in res["table"] if np.isfinite(t["scipy_same_tol_wall_s"])]
    if same:
        lines.append(
            "SciPy at nsdyn's own tolerances: "
            + "; ".join(
                f"{t['record']} {t['scipy_same_tol_wall_s']:.3g} s, err x_iso "
                f"{t['scipy_same_tol_err_x']:.1e}"
                for t in same
            )
        )
    if res.get("first_runs"):
        lines += ["", first_runs.first_runs_markdown(res["first_runs"], os.getloadavg())]
    return "\n".join(lines)


def speed_figure(rows, table):
    """The chart of :func:`speed_bench` (drawn by :mod:`nsdyn.plot`)."""
    from nsdyn import plot

    return plot.speed_figure(rows, table)


def report(res: dict) -> str:
    """The human table of :func:`speed_bench`'s result (files excluded)."""
    return speed_markdown(res)


def summarise(res: dict) -> dict:
    """The JSON summary of :func:`speed_bench`'s result: the table, its settings, the files."""
    keys = ("table", "meta", "files", "first_runs")
    return {k: res[k] for k in keys if k in res}
