"""Benchmark: the 3D office's cb rung on 12 friction pendulums under a 40 s three-component record.

Times (wall clock, this machine, after compilation; the compile/load time apart):

- the Craig–Bampton reduction of ``office-11-3d`` at f_max = 5 Hz with the participation
  filter (the floor beams' local modes dropped) and the pair system's build;
- the cb run under ``synthetic-wn-40s`` with the regularised law (Radau IIA) at rtol 1e-4
  and 1e-6, and with the switch law (Dormand–Prince, located stick/slip events) at 1e-6;
- the rigid rung (the building as a rigid deck) in the same process, and the ratio of the
  CPU times (``time.process_time``: less sensitive than the wall clock to a shared machine).

``--evidence`` also builds the cb rung without the filter (every mode below 5 Hz) and below
the floor beams (f_max = 3.8 Hz) and runs them: the peaks against the filtered model's, the
evidence for the filter (docs/guide/frames-3d.md). Run: ``python examples/bench_building3d_cb.py``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from nsdyn.ground import read_motion3
from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.building3d import building_deck
from nsdyn.models.isolated.building3d_cb import building_pairs
from nsdyn.models.isolated.building3d_response import run_building
from nsdyn.models.isolated.deck import simulate_plane
from nsdyn.structure import load_frame3d

FPS = Bearing(Friction(0.04, mu_fast=0.07, rate=30.0, mu_static=0.075), radius=2.2, d_cap=0.35)
STUB = {"f": 1.0, "ax": 0.0, "ay": 0.0}


def _peaks(r) -> dict:
    s = r.summary()
    return {k: s[k] for k in ("peak_resultant_displacement_m", "peak_base_shear_N",
                              "peak_drift_cm_x", "peak_drift_cm_y", "peak_floor_acc_x_m_s2",
                              "peak_floor_acc_y_m_s2", "min_normal_force_N",
                              "max_normal_force_N")}  # fmt: skip


def _timed_run(system, rec, **kw) -> tuple[float, dict, int]:
    t0, c0 = time.perf_counter(), time.process_time()
    r = run_building(system, rec, **kw)
    cpu = time.process_time() - c0
    return time.perf_counter() - t0, {"cpu_s": cpu, **_peaks(r)}, r.result.stats["steps"]


def main(evidence: bool = False) -> dict:
    rec = read_motion3("synthetic-wn-40s")
    frame = load_frame3d("office-11-3d")
    out: dict = {"record": rec.name, "duration_s": float(rec.duration)}
    t0 = time.perf_counter()
    sys5 = building_pairs(frame, FPS, f_max=5.0)
    out["reduction_s"] = time.perf_counter() - t0
    info = sys5.info
    out["cb"] = {"n": sys5.n, "modes_below_f_max": info["n_modes_below_f_max"],
                 "modes_kept": info["n_modes"], "dropped_mass": info["dropped_mass"]}  # fmt: skip
    runs = {}
    for law in ("arctan", "switch"):
        t0 = time.perf_counter()
        run_building(sys5, STUB, law=law, t_end=0.04)
        out[f"compile_{law}_s"] = time.perf_counter() - t0
    for label, kw in (("arctan rtol 1e-4", {"law": "arctan", "rtol": 1e-4,
                                            "atol": (1e-6, 1e-6)}),
                      ("arctan rtol 1e-6", {"law": "arctan"}),
                      ("switch rtol 1e-6", {"law": "switch"})):  # fmt: skip
        wall, peaks, steps = _timed_run(sys5, rec, **kw)
        runs[label] = {"wall_s": wall, "steps": steps, **peaks}
    deck = building_deck(frame, FPS)
    simulate_plane(deck, STUB, t_end=0.04)
    t0, c0 = time.perf_counter(), time.process_time()
    rr = simulate_plane(deck, rec)
    rigid_s, rigid_cpu = time.perf_counter() - t0, time.process_time() - c0
    F = (rr.friction + rr.restoring + rr.other).sum(axis=1)
    out["rigid"] = {
        "wall_s": rigid_s,
        "cpu_s": rigid_cpu,
        "steps": rr.stats["steps"],
        "peak_resultant_displacement_m": float(rr.resultant(rr.u).max()),
        "peak_base_shear_N": float(np.hypot(F[:, 0], F[:, 1]).max()),
    }
    for v in runs.values():
        v["ratio_to_rigid"] = v["cpu_s"] / rigid_cpu
    out["runs"] = runs
    if evidence:
        ev = {}
        for label, kw in (("5 Hz, every mode", {"f_max": 5.0, "min_mass": None}),
                          ("3.8 Hz, every mode", {"f_max": 3.8, "min_mass": None})):  # fmt: skip
            t0 = time.perf_counter()
            s = building_pairs(frame, FPS, **kw)
            build = time.perf_counter() - t0
            wall, peaks, steps = _timed_run(s, rec, law="arctan", rtol=1e-4, atol=(1e-6, 1e-6))
            ev[label] = {"n": s.n, "reduction_s": build, "wall_s": wall, "steps": steps, **peaks}
        out["evidence"] = ev
    return out


def _print(out: dict) -> None:
    cb = out["cb"]
    print(f"office-11-3d cb rung, f_max 5 Hz: {cb['n']} coordinates ({cb['modes_kept']} of "
          f"{cb['modes_below_f_max']} fixed-interface modes kept; dropped mass fractions x, y, "
          f"z, torsion {', '.join(f'{v:.1e}' for v in cb['dropped_mass'])}); reduction "
          f"{out['reduction_s']:.1f} s")  # fmt: skip
    print(f"compile/load: arctan {out['compile_arctan_s']:.1f} s, switch "
          f"{out['compile_switch_s']:.1f} s")  # fmt: skip
    r = out["rigid"]
    print(f"{'run':20s} {'wall s':>7s} {'cpu s':>7s} {'steps':>7s} {'x rigid':>7s} "
          f"{'|u| m':>8s} {'|V| MN':>7s} {'drift x':>8s} {'drift y':>8s} {'acc x':>6s} "
          f"{'acc y':>6s}")  # fmt: skip
    print(f"{'rigid deck':20s} {r['wall_s']:7.3f} {r['cpu_s']:7.3f} {r['steps']:7d} {1.0:7.1f} "
          f"{r['peak_resultant_displacement_m']:8.4f} "
          f"{r['peak_base_shear_N'] / 1e6:7.3f}")  # fmt: skip
    rows = list(out["runs"].items()) + list(out.get("evidence", {}).items())
    for label, v in rows:
        print(f"{label:20s} {v['wall_s']:7.3f} {v['cpu_s']:7.3f} {v['steps']:7d} "
              f"{v['cpu_s'] / r['cpu_s']:7.1f} {v['peak_resultant_displacement_m']:8.4f} "
              f"{v['peak_base_shear_N'] / 1e6:7.3f} {v['peak_drift_cm_x']:8.5f} "
              f"{v['peak_drift_cm_y']:8.5f} {v['peak_floor_acc_x_m_s2']:6.2f} "
              f"{v['peak_floor_acc_y_m_s2']:6.2f}")  # fmt: skip


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--evidence", action="store_true", help="also the unfiltered cb models")
    _print(main(evidence=p.parse_args().evidence))
