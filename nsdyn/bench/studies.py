"""Study throughput: tasks per second of 40 s isolated-frame runs on a local process pool and
on a Dask LocalCluster (same run, same tasks), the per-task overhead, projected wall times.

Tasks: the default scene (office frame, CB-5, arctan, radau at the run tolerances) on the
bundled 40 s record at PGA 3 m/s², μ varied so every task has its own key. Each engine runs
the same tasks from an empty table, batched automatically and one task per batch.

    overhead per task = (wall × workers − Σ task_s) / n_tasks

(``task_s`` is measured inside the worker around one run; everything else — submitting,
pickling, scheduling, result transfer, writing the table's parts, idle workers at the end —
is overhead). A worker's first task also builds the Craig–Bampton reduction and loads the
compiled kernels: reported apart as ``startup_s`` (largest first-task time minus the median).

Projection for N workers: ``T(N) = startup + ceil(n / N) × (t_task + overhead)`` with the
median ``t_task`` and the batched overhead of the Dask run, for the seed's design search
(the bundled grid: 80 designs × 4 Kobe records = 320 runs) and a 1 000-record Monte-Carlo.
"""

from __future__ import annotations

import csv
import io
import math
import tempfile
import textwrap
import time
from pathlib import Path

import numpy as np

from nsdyn.atomic import atomic_open, save_figure

QUICK_TASKS = 16  # tasks per engine, --quick
FULL_TASKS = 64  # tasks per engine
WORKERS = 2  # processes per engine (the machine's cores)
PROJECT_WORKERS = (1, 2, 8, 32, 128)  # cluster sizes of the projection
OPTIONS = ("figures",)  # options run_bench takes
FIGURES = ("studies.png",)  # the figures it draws (removed under --no-figures)
PROJECT_STUDIES = {"seed design search (320 runs)": 320, "Monte-Carlo, 1000 records": 1000}

_STUDY = """
[study]
name = "bench-{engine}"
batch = {batch}
keep = ["x_iso_max_m", "idr_max", "wall_s"]

[base.motion]
t_end = 40.0

[parameters]
"isolation.mu" = {{ linspace = [0.02, 0.05, {n}] }}
"""


def _engine(name: str, batch: int, n: int, tmp: Path):
    from nsdyn.studies.execute import dask_executor, run_study
    from nsdyn.studies.study import load_study

    p = tmp / f"{name}-{batch}.toml"
    p.write_text(textwrap.dedent(_STUDY.format(engine=name, batch=batch, n=n)))
    study = load_study(p)
    t0 = time.perf_counter()
    if name == "dask-local":
        with dask_executor(n_local=WORKERS) as ex:
            t_up = time.perf_counter() - t0
            res = run_study(study, tmp / f"out-{name}-{batch}", executor=ex, fresh=True)
    else:
        t_up = 0.0
        res = run_study(study, tmp / f"out-{name}-{batch}", workers=WORKERS, fresh=True)
    task_s = res.table.column("task_s")
    t_med = float(np.median(task_s))
    return {
        "engine": name,
        "batch": res.batch,
        "n_tasks": res.n_tasks,
        "workers": res.workers,
        "n_failed": res.n_failed,
        "cluster_start_s": t_up,
        "wall_s": res.wall_s,
        "tasks_per_s": res.n_tasks / res.wall_s,
        "task_s_median": t_med,
        "startup_s": float(np.max(task_s) - t_med),
        "overhead_per_task_s": (res.wall_s * res.workers - float(np.sum(task_s))) / res.n_tasks,
    }


def projections(row: dict) -> list[dict]:
    """Projected wall times of PROJECT_STUDIES on PROJECT_WORKERS workers (see module doc)."""
    per = row["task_s_median"] + max(row["overhead_per_task_s"], 0.0)
    return [
        {
            "study": s,
            "n_tasks": n,
            "workers": w,
            "wall_s": row["startup_s"] + math.ceil(n / w) * per,
        }
        for s, n in PROJECT_STUDIES.items()
        for w in PROJECT_WORKERS
    ]


def _csv(rows: list[dict]) -> str:
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(rows[0]), lineterminator="\n")
    w.writeheader()
    w.writerows(rows)
    return buf.getvalue()


def run_bench(out_dir: Path, quick: bool, figures: bool = True) -> dict:
    """Run the throughput benchmark; write studies.csv, studies-projection.csv and
    (``figures``) studies.png."""
    out = Path(out_dir)
    n = QUICK_TASKS if quick else FULL_TASKS
    engines = [("local-pool", 0), ("local-pool", 1)]
    try:
        import distributed  # noqa: F401

        engines += [("dask-local", 0), ("dask-local", 1)]
    except ImportError:
        pass
    with tempfile.TemporaryDirectory(prefix="nsdyn-bench-studies-") as tmp:
        rows = [_engine(name, batch, n, Path(tmp)) for name, batch in engines]
    batched = [r for r in rows if r["batch"] > 1] or rows
    ref = next((r for r in batched if r["engine"] == "dask-local"), batched[0])
    proj = projections(ref)
    with atomic_open(out / "studies.csv", "w", newline="") as fh:
        fh.write(_csv(rows))
    with atomic_open(out / "studies-projection.csv", "w", newline="") as fh:
        fh.write(_csv(proj))
    written = ["studies.csv", "studies-projection.csv"]
    if figures:
        from nsdyn.studies.figures import throughput_figure

        save_figure(throughput_figure(rows, proj), out / "studies.png")
        written.append("studies.png")
    pool = next(r for r in rows if r["engine"] == "local-pool" and r["batch"] > 1)
    res = {
        "engines": rows,
        "projection": proj,
        "projection_basis": ref["engine"],
        "files": [str(out / f) for f in written],
    }
    if ref is not pool:
        res["dask_over_pool_wall"] = ref["wall_s"] / pool["wall_s"]
    return res
