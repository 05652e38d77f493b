"""First runs of every model family: compilation and run apart, in fresh processes.

Each case (a family's default scene, the isolated frame once per method, a sweep, a study)
runs as a whole ``nsdyn`` command in a fresh Python process whose ``NUMBA_CACHE_DIR`` is a new
empty directory, the model cache (``NSDYN_MODEL_CACHE``) a new one inside it (a first run:
every kernel it needs compiles, its model is built), then once more in a fresh process with
the caches that run filled (every later start; Python writes and reads its bytecode cache, as
on a user's machine). Per case and process::

    process_s   wall time of the whole process (interpreter start, imports, compile, run, output)
    compile_s   the seconds the command reports compiling or loading its kernels (JSON summary)
    run_s       the seconds it reports for the run itself (the summary's wall_s)
    cpu_s       CPU seconds of the process and its children (the compile helper): on a shared
                machine the wall times grow with its load, the CPU time much less

plus ``notice`` (the process said on stderr that it compiles) and the load average of the
machine before the process started (:func:`os.getloadavg`, 1 min). With ``repeats`` the cases
run in rounds (every case once per round) and a row holds the medians. The targets are a first
run within FIRST_RUN_TARGET_S and a cached start within CACHED_TARGET_S of process time;
``over_s = process_s - FIRST_RUN_TARGET_S`` of the first run says by how much a case misses;
``cached_start_s``, the cached process less its reported run (a sweep's points, a study's
tasks: the work asked for), is the start the cached target is about.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

FIRST_RUN_TARGET_S = 10.0  # a first run into an empty cache, whole process [s]
CACHED_TARGET_S = 1.0  # a later start, whole process [s]
ISOLATED_T_END = 10.0  # s of the default scene's record in the isolated frame's cases
TIMEOUT_S = 1800.0  # a case still running after this is stopped (status "timeout")

_ROOT = Path(__file__).resolve().parents[2]
_SCENES = _ROOT / "examples" / "scenes"

# a study of the default scene: two tasks on the default process pool
STUDY_TOML = """[study]
name = "first-run"
[base.motion]
pga = 3.0
t_end = 5.0
[parameters]
"isolation.mu" = [0.02, 0.05]
"""


def cases() -> list[tuple[str, str, list[str]]]:
    """(family, what, ``nsdyn`` arguments) of every case; ``{out}`` stands for the output
    directory and ``{study}`` for the study file of the case."""
    iso = ["run", "--t-end", f"{ISOLATED_T_END:g}"]
    out = ["--json", "--no-figures", "--out", "{out}"]
    rows = [
        ("isolated", "radau (default)", [*iso, *out]),
        ("isolated", "event", [*iso, "--method", "event", *out]),
        ("isolated", "genalpha", [*iso, "--method", "genalpha", *out]),
        ("isolated", "genalpha-lowrank", [*iso, "--method", "genalpha-lowrank", *out]),
        ("isolated", "sweep", ["sweep", "--points", "5", *out]),
        ("rocking", "block", ["run", str(_SCENES / "rocking-seed001-cask.toml"), *out]),
        ("contact", "event", ["run", str(_SCENES / "contact-seed002-A5.toml"), *out]),
        ("cylinder", "tensionless", ["run", str(_SCENES / "cylinder-uplift.toml"), *out]),
        ("deck", "fps", ["run", str(_SCENES / "deck-fps4-3c.toml"), *out]),
        ("study", "isolated, 2 tasks", ["study", "{study}", *out]),
        ("building3d", "cb", ["run", str(_SCENES / "building3d-office-cb.toml"), *out]),
    ]
    return rows


def _env(cache: str) -> dict:
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    env["NSDYN_MODEL_CACHE"] = os.path.join(cache, "models")  # empty with the kernels'
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(_ROOT), env.get("PYTHONPATH")) if p)
    # Python's bytecode cache on, as on a user's machine: without it every process compiles
    # the source of each module whose .pyc is missing or stale (nsdyn's own: ~0.08 s)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def _reported(stdout: str) -> tuple[float, float]:
    """(compile_s, run_s) of a command's JSON summary (NaN where it reports none)."""
    nan = float("nan")
    try:
        s = json.loads(stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        return nan, nan
    if "run" in s and isinstance(s["run"], dict):  # nsdyn study: the whole study's wall time
        return nan, float(s["run"].get("wall_s", nan))
    return float(s.get("compile_s", nan)), float(s.get("wall_s", nan))


def _children_cpu_s() -> float:
    """CPU seconds (user + system) of this process's finished children (NaN off POSIX)."""
    try:
        import resource
    except ImportError:
        return float("nan")
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_case(args: list[str], cache: str, workdir: str) -> dict:
    """One fresh process of ``nsdyn *args`` with numba's cache in ``cache``: its row."""
    out = tempfile.mkdtemp(prefix="out-", dir=workdir)
    study = Path(workdir) / "first-run-study.toml"
    study.write_text(STUDY_TOML)
    argv = [a.format(out=out, study=study) for a in args]
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    cpu0 = _children_cpu_s()
    t0 = time.perf_counter()
    try:
        res = subprocess.run(
            [sys.executable, "-P", "-m", "nsdyn.cli", *argv], env=_env(cache), cwd=workdir,
            capture_output=True, text=True, timeout=TIMEOUT_S,
        )  # fmt: skip
    except subprocess.TimeoutExpired:
        return {"status": "timeout", "process_s": time.perf_counter() - t0, "load_1min": load}
    process_s = time.perf_counter() - t0
    cpu_s = _children_cpu_s() - cpu0
    compile_s, run_s = _reported(res.stdout)
    return {
        "status": "ok" if res.returncode == 0 else f"exit {res.returncode}",
        "process_s": process_s,
        "compile_s": compile_s,
        "run_s": run_s,
        "cpu_s": cpu_s,
        "notice": "compiling the" in res.stderr,
        "load_1min": load,
        "message": "" if res.returncode == 0 else " ".join(res.stderr.split())[-300:],
    }


def _median_row(reps: list[dict]) -> dict:
    """One row of several repeats of a case: the median of every number (NaN-aware), the
    other fields of the first repeat, ``repeats`` their count and ``first_process_all_s`` the
    first runs' process times."""
    row = dict(reps[0])
    for k, v in reps[0].items():
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            vals = [r[k] for r in reps if isinstance(r.get(k), (int, float))]
            vals = [x for x in vals if not np.isnan(x)]  # NaN: not measured in that repeat
            row[k] = float(np.median(vals)) if vals else v
    row["notice"] = all(r.get("notice") for r in reps) if "notice" in row else None
    row["status"] = next((r["status"] for r in reps if r["status"] != "ok"), "ok")
    return row


def first_runs(only: list[str] | None = None, log=print, repeats: int = 1) -> list[dict]:
    """The table: per case a first run into an empty cache, then a cached start (module
    docstring). ``only``: the families to run (default all). ``repeats``: rounds over all
    cases (interleaved, so a change of the machine's load spreads over every case); a row
    holds the medians."""
    todo = [c for c in cases() if not only or c[0] in only]
    runs: dict = {(f, w): [] for f, w, _ in todo}
    for _ in range(max(1, repeats)):
        for family, what, args in todo:
            with tempfile.TemporaryDirectory(prefix="nsdyn-first-") as work:
                cache = os.path.join(work, "numba")
                log(f"[first-runs] {family} {what}: first run (empty numba cache)")
                first = run_case(args, cache, work)
                log(f"[first-runs] {family} {what}: {first['process_s']:.1f} s; cached start")
                again = run_case(args, cache, work)
            runs[(family, what)].append((first, again))
    rows = []
    for (family, what), pairs in runs.items():
        first = _median_row([a for a, _ in pairs])
        again = _median_row([b for _, b in pairs])
        row = {"family": family, "what": what, "repeats": len(pairs)}
        row.update({f"first_{k}": v for k, v in first.items()})
        row.update({f"cached_{k}": v for k, v in again.items()})
        row["first_process_all_s"] = [a["process_s"] for a, _ in pairs]
        row["over_s"] = row["first_process_s"] - FIRST_RUN_TARGET_S
        # the start without the work asked for (a sweep's points, a study's tasks): the start
        # that the 1 s target is about
        row["cached_start_s"] = row["cached_process_s"] - np.nan_to_num(row.get("cached_run_s"))
        rows.append(row)
    return rows


def first_runs_markdown(rows: list[dict], load: tuple | None = None) -> str:
    """The table as Markdown: first run (process, compile, run), cached start, misses."""

    def f(v, fmt=".1f"):
        return "-" if v is None or v != v else format(v, fmt)

    lines = [
        "| family | case | first run [s] | compile [s] | run [s] | CPU [s] | notice | "
        "cached start [s] | less its run [s] | kernels loaded in [s] | "
        "over the 10 s target [s] | load (1 min) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        miss = r["over_s"]
        ok = r["first_status"] == "ok" and r["cached_status"] == "ok"
        what = r["what"] + ("" if ok else f" ({r['first_status']} / {r['cached_status']})")
        lines.append(
            f"| {r['family']} | {what} | {f(r['first_process_s'])} | "
            f"{f(r.get('first_compile_s'))} | {f(r.get('first_run_s'), '.2f')} | "
            f"{f(r.get('first_cpu_s'))} | {'yes' if r.get('first_notice') else 'no'} | "
            f"{f(r['cached_process_s'])} | {f(r.get('cached_start_s'))} | "
            f"{f(r.get('cached_compile_s'), '.2f')} | "
            f"{f(miss) if miss > 0 else 'met'} | {f(r['first_load_1min'], '.1f')} |"
        )
    if load is not None:
        lines.append(
            f"\nload average (1, 5, 15 min) at the end: {', '.join(f'{x:.1f}' for x in load)}"
        )
    return "\n".join(lines)
