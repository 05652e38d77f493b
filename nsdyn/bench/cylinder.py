"""Benchmark of the cylinder model: work–precision of one run and cost of many earthquakes.

1. One 20 s three-component simulated earthquake, tensionless foundation (strong uplift): the
   DOPRI5 kernel over rtol 1e-3 … 1e-9, error against a reference at rtol 1e-11 (itself checked
   against rtol 1e-12: the floor), err = max_t |e₃,h − e₃,h^ref| / max_t |e₃,h^ref| (horizontal
   part of the body axis, i.e. the tilt vector); wall time = median of repeats, compile apart.
2. N earthquakes for the same configuration (the three foundation cases each): time per run
   and the projected time for 1 000 earthquakes, serially and on this machine's cores.
Writes ``cylinder-wp.csv``, ``cylinder-many.csv`` and ``cylinder-wp.png`` (unless ``figures``
is False) through nsdyn.atomic. Columns of ``cylinder-wp.csv``: ``rtol``, ``wall_s`` (the
median), ``err_tilt`` (err above), ``steps`` (accepted), ``rhs_calls``, ``kink_halvings``
(steps halved onto a change of the contact's kind, the bisection onto the event) and
``energy_error`` (``CylinderResult.energy_error``: the energy balance's residual against the
largest energy the run moves). ``cylinder-many.csv``: the median wall time per run of each
foundation case, and the time of one earthquake's three cases.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np

from nsdyn.atomic import atomic_open, save_figure
from nsdyn.models.cylinder import CylinderParams, earthquake, simulate
from nsdyn.models.cylinder.study import run_batch

RTOLS = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9)  # work–precision settings
RTOLS_QUICK = (1e-4, 1e-6, 1e-8)  # quick subset
RTOL_REF = 1e-11  # reference run
RTOL_CHECK = 1e-12  # check of the reference (error floor)
REPEATS = 5  # timing repeats (median)
N_EQ, N_EQ_QUICK = 60, 6  # earthquakes of part 2
SEED = 1  # earthquake of part 1
OPTIONS = ("figures",)  # options run_bench takes
FIGURES = ("cylinder-wp.png",)  # the figures it draws (removed under --no-figures)


def _err(res, ref) -> float:
    a, b = res.e3[:, :2], ref.e3[:, :2]
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def _median_wall(p, ag, dt, rtol, repeats):
    walls = []
    for _ in range(repeats):
        tic = time.perf_counter()
        res = simulate(p, ag, dt, rtol=rtol)
        walls.append(time.perf_counter() - tic)
    return res, float(np.median(walls))


def run_bench(out_dir: Path, quick: bool, figures: bool = True) -> dict:
    """Run both parts; returns the numbers and the paths of the files written (the chart only
    with ``figures``)."""
    out_dir = Path(out_dir)
    p = CylinderParams()
    dt, ag = earthquake(SEED, 20.0)
    tic = time.perf_counter()
    simulate(p, ag[:3], dt)
    compile_s = time.perf_counter() - tic
    ref = simulate(p, ag, dt, rtol=RTOL_REF)
    floor = _err(simulate(p, ag, dt, rtol=RTOL_CHECK), ref)
    rows = []
    for rtol in RTOLS_QUICK if quick else RTOLS:
        res, wall = _median_wall(p, ag, dt, rtol, 3 if quick else REPEATS)
        rows.append({"rtol": rtol, "wall_s": wall, "err_tilt": _err(res, ref),
                     "steps": res.stats["accepted"], "rhs_calls": res.stats["rhs_calls"],
                     "kink_halvings": res.stats["kink_halvings"],
                     "energy_error": res.energy_error})  # fmt: skip
    with atomic_open(out_dir / "cylinder-wp.csv", "w") as fh:
        fh.write(",".join(rows[0]) + "\n")
        for r in rows:
            fh.write(",".join(f"{v:.6g}" for v in r.values()) + "\n")
    n = N_EQ_QUICK if quick else N_EQ
    tic = time.perf_counter()
    many = run_batch({}, list(range(n)))
    total = time.perf_counter() - tic
    per_case = {}
    for case in ("tensionless", "bonded", "fixed"):
        w = [r["wall_s"] for r in many if r["case"] == case]
        per_case[case] = float(np.median(w))
    per_eq = total / n  # all three cases, stresses included
    cores = os.cpu_count() or 1
    with atomic_open(out_dir / "cylinder-many.csv", "w") as fh:
        fh.write("case,median_wall_s_per_run\n")
        for case, w in per_case.items():
            fh.write(f"{case},{w:.6g}\n")
        fh.write(f"all_cases_per_earthquake,{per_eq:.6g}\n")
    files = [str(out_dir / "cylinder-wp.csv"), str(out_dir / "cylinder-many.csv")]
    if figures:
        files.append(str(save_figure(_figure(rows, floor), out_dir / "cylinder-wp.png")))
    return {
        "compile_s": compile_s,
        "reference_floor": floor,
        "work_precision": rows,
        "n_earthquakes": n,
        "wall_per_run_s": per_case,
        "wall_per_earthquake_all_cases_s": per_eq,
        "projected_1000_serial_s": 1000 * per_eq,
        "projected_1000_local_pool_s": 1000 * per_eq / cores,
        "cores": cores,
        "files": files,
    }


def _figure(rows, floor):
    """The work-precision chart of part 1."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6, 4), layout="constrained")
    ax = fig.add_subplot()
    ax.loglog([r["wall_s"] for r in rows], [r["err_tilt"] for r in rows], "o-", label="DOPRI5")
    for r in rows:
        ax.annotate(f"{r['rtol']:.0e}", (r["wall_s"], r["err_tilt"]), fontsize=7)
    ax.axhline(max(floor, 1e-16), color="grey", ls=":", label="reference floor")
    ax.set(xlabel="wall time [s] (median)", ylabel="max tilt-vector error / peak",
           title="cylinder, 20 s 3-component earthquake, tensionless")  # fmt: skip
    ax.legend()
    return fig
