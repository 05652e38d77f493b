"""Benchmark: the 3D office's full rung on sparse operators and its damping, against the cb rung.

The office building (``office-11-3d``, 7 200 dofs, 5 220 after the diaphragms) on the cb
example scene's 12 friction pendulums (``examples/scenes/building3d-office-cb.toml``: 5 %
accidental eccentricity along y, grid base) under the first ``--t-end`` seconds of the bundled
three-component record ``synthetic-wn-40s``, one process, after compilation:

- the full rung in nodal coordinates (``building_pairs_sparse`` + ``run_building_sparse``,
  generalized-α at dt = 5 ms, the regularised law) with its damping choices: ``modal`` (the
  fixed-interface modes up to ``f_damp`` Hz as a low-rank term, the default 50 Hz and lower
  cut-offs) and ``stiffness`` (β K);
- the cb rung of the same scene (f_max 5 Hz, ``min_mass`` 10⁻⁴, Radau IIA at rtol 10⁻³,
  atol 10⁻⁵) as the ladder's reference.

For each: the build (reduction or mode solve, operators; wall and CPU seconds), the run (wall
and CPU), the number of damped modes, and the peaks (isolator displacement, base shear, drift
ratios at the centres of mass, floor accelerations) with their relative difference from the
cb rung's (one line per case on stderr as it ends: the default takes ~5 min). Run:
``python examples/bench_building3d_full.py [--t-end 4] [--f-damp 50,20,10]``. The default
4 s is a quick look: its peaks fall in the record's first seconds, before the isolators'
slip dominates, and differ from the cb rung's by up to ~12 % (floor acceleration; 43 % with
β K). The table in docs/guide/frames-3d.md is the 40 s run (``--t-end 40 --f-damp 50,20``).
"""

from __future__ import annotations

import argparse
import math
import sys
import time

from nsdyn.cli.args import positive_finite
from nsdyn.ground import read_motion3
from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.building3d_cb import building_pairs
from nsdyn.models.isolated.building3d_response import run_building
from nsdyn.models.isolated.building3d_sparse import run_building_sparse
from nsdyn.models.isolated.pairs_sparse import building_pairs_sparse
from nsdyn.structure import load_frame3d

FPS = Bearing(Friction(0.04, mu_fast=0.07, rate=30.0, mu_static=0.075), radius=2.2, d_cap=0.35)
ECC = (0.0, 0.05)
RECORD = "synthetic-wn-40s"
DT = 0.005
PEAKS = ("peak_resultant_displacement_m", "peak_base_shear_N", "peak_drift_cm_x",
         "peak_drift_cm_y", "peak_floor_acc_x_mps2", "peak_floor_acc_y_mps2")  # fmt: skip


def _clock():
    return time.perf_counter(), time.process_time()


def _since(c) -> tuple[float, float]:
    return time.perf_counter() - c[0], time.process_time() - c[1]


def _row(label, build, run, s, extra=None) -> dict:
    return {"run": label, "build_wall_s": build[0], "build_cpu_s": build[1],
            "run_wall_s": run[0], "run_cpu_s": run[1], **(extra or {}),
            **{k: float(s[k]) for k in PEAKS}}  # fmt: skip


def _progress(row: dict, k: int, n: int) -> None:
    """One line on stderr per finished case (a full rung's build and run take minutes)."""
    print(f"[{k}/{n}] {row['run']}: build {row['build_wall_s']:.1f} s, run "
          f"{row['run_wall_s']:.1f} s", file=sys.stderr, flush=True)  # fmt: skip


def main(t_end: float = 4.0, f_damps=(50.0, 20.0, 10.0)) -> list[dict]:
    rec = read_motion3(RECORD).window(0.0, t_end)
    frame = load_frame3d("office-11-3d")
    rows = []
    c = _clock()
    cb = building_pairs(frame, FPS, f_max=5.0, min_mass=1e-4, eccentricity=ECC)
    cb.operators()
    build = _since(c)
    run_building(cb, rec, law="arctan", rtol=1e-3, atol=(1e-5, 1e-5), t_end=0.04)  # compiles
    c = _clock()
    r = run_building(cb, rec, law="arctan", rtol=1e-3, atol=(1e-5, 1e-5))
    rows.append(_row("cb (5 Hz, min_mass 1e-4)", build, _since(c), r.summary(),
                     {"n": cb.n, "damped_modes": cb.info["n_modes"]}))  # fmt: skip
    cases = [("modal", f) for f in f_damps] + [("stiffness", None)]
    _progress(rows[-1], 1, len(cases) + 1)
    for damping, f_damp in cases:
        c = _clock()
        s = building_pairs_sparse(frame, FPS, damping=damping, f_damp=f_damp, eccentricity=ECC)
        build = _since(c)
        run_building_sparse(s, rec, dt=DT, t_end=0.02)  # compiles or loads the kernels
        c = _clock()
        r = run_building_sparse(s, rec, dt=DT)
        label = f"full, modal to {f_damp:g} Hz" if damping == "modal" else "full, stiffness βK"
        rows.append(_row(label, build, _since(c), r.summary(),
                         {"n": s.n, "damped_modes": int(s.c.size)}))  # fmt: skip
        _progress(rows[-1], len(rows), len(cases) + 1)
    ref = rows[0]
    for v in rows:
        v["largest_peak_difference"] = max(abs(v[k] / ref[k] - 1) for k in PEAKS)
    return rows


def _print(rows, t_end) -> None:
    print(f"office-11-3d on 12 friction pendulums, {RECORD} 0-{t_end:g} s, dt {DT:g} s (full)")
    print(f"{'run':28s} {'n':>5s} {'modes':>5s} {'build':>13s} {'run':>13s} {'|u| m':>7s} "
          f"{'|V| MN':>6s} {'drift x,y %':>11s} {'acc x,y':>10s} {'vs cb':>6s}")  # fmt: skip
    for v in rows:
        print(f"{v['run']:28s} {v['n']:5d} {v['damped_modes']:5d} "
              f"{v['build_wall_s']:5.1f}/{v['build_cpu_s']:5.1f} s "
              f"{v['run_wall_s']:5.1f}/{v['run_cpu_s']:5.1f} s "
              f"{v['peak_resultant_displacement_m']:7.4f} {v['peak_base_shear_N'] / 1e6:6.2f} "
              f"{100 * v['peak_drift_cm_x']:5.3f},{100 * v['peak_drift_cm_y']:5.3f} "
              f"{v['peak_floor_acc_x_mps2']:4.2f},{v['peak_floor_acc_y_mps2']:4.2f} "
              f"{100 * v['largest_peak_difference']:5.1f}%")  # fmt: skip
    print("(build and run: wall/CPU seconds)")


def _positives(s: str) -> tuple[float, ...]:
    """An argparse type: positive numbers separated by commas."""
    try:
        v = tuple(float(x) for x in s.split(",") if x.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected numbers separated by commas: {s!r}") from None
    if not v or not all(x > 0 and math.isfinite(x) for x in v):
        raise argparse.ArgumentTypeError(f"expected positive numbers: {s!r}")
    return v


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=positive_finite, default=4.0, help="seconds of the record [4]")
    ap.add_argument("--f-damp", type=_positives, default=(50.0, 20.0, 10.0),
                    help="modal cut-offs [Hz] (50,20,10)")  # fmt: skip
    a = ap.parse_args()
    whole = read_motion3(RECORD)
    span = (whole.n - 1) * whole.dt
    if a.t_end > span * (1 + 1e-12):  # (cut to the record without a word, titled 0-t_end)
        ap.error(f"argument --t-end: the record {RECORD} spans {span:g} s; expected at most that")
    _print(main(a.t_end, a.f_damp), a.t_end)
