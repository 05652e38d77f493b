"""Benchmark: the 3D office's cb rung on 12 friction pendulums under a 40 s three-component record.

The record is the bundled ``synthetic-wn-40s`` (three components, 40 s at 0.01 s: 4 000
samples, at which every time loop ends a step, since the interpolated record kinks there).
Everything is timed in one process after compilation, compile/load apart:

- the Craig–Bampton reduction of ``office-11-3d`` at f_max = 5 Hz with the participation
  filter (18 of its 194 fixed-interface modes) and the pair system's build (setup, once);
- work–precision: the cb run under the regularised law (Radau IIA) and the switch law
  (Dormand–Prince, located stick/slip events) over a range of rtol (atol = 10⁻² rtol in m
  and m/s), the median wall and CPU (``time.process_time``) of ``--repeats`` runs, the time
  inside the kernel's loop apart from the Python around it (ground packing, buffers, the
  result and the response's outputs); each run's peaks against a tight-tolerance run of the
  same model and law (rtol 10⁻⁹ regularised, 10⁻¹¹ switch): the largest relative error over
  the peak isolator displacement, base shear, drift ratios, floor accelerations and normal
  forces, and over the isolator orbits (max |u − u_ref| / max |u_ref|);
- the loops' counts: steps, rejected steps, right-hand-side evaluations, events (by
  transition: stick → slip-start → slip → stick);
- the rigid rung (the building as a rigid deck, switch law) in the same process: the CPU
  ratios are to its time.

``--evidence`` adds the cb models that keep fewer modes (``min_mass`` 3·10⁻³, 10⁻², 2·10⁻²:
25–30 coordinates instead of 33; both laws), every mode below 5 Hz (209 coordinates) and
every mode below the floor beams (3.8 Hz) (the regularised law), each at the tolerance the
chart recommends (``DEFAULT``) and compared with the default model's reference: the evidence
for the participation filter's threshold (docs/guide/frames-3d.md).
The work–precision chart goes to ``examples/figures/building3d-cb-wp.png`` (CPU time against
the largest peak error, both laws; ``--no-figure`` skips it). Run:
``python examples/bench_building3d_cb.py [--repeats 5] [--evidence] [--no-figure]
[--out DIR]``; ``--quick`` times the chart's tolerance alone (``DEFAULT``, once, against the
same references): a check that the script runs, not the chart. ``--eccentric`` runs only the
switch law on the office with a 5 % eccentricity over the record's first 8 s at rtol
10⁻⁴–10⁻⁹ (events, peak drifts, peak isolator displacement: :func:`eccentric`).
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections import Counter
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from nsdyn.cli.args import out_dir, positive_int
from nsdyn.ground import read_motion3
from nsdyn.models.isolated import _kpairsradau, _kpairsrun
from nsdyn.models.isolated import _kplane as kp
from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.building3d import building_deck
from nsdyn.models.isolated.building3d_cb import building_pairs
from nsdyn.models.isolated.building3d_response import run_building
from nsdyn.models.isolated.deck import simulate_plane
from nsdyn.structure import load_frame3d

FPS = Bearing(Friction(0.04, mu_fast=0.07, rate=30.0, mu_static=0.075), radius=2.2, d_cap=0.35)
STUB = {"f": 1.0, "ax": 0.0, "ay": 0.0}
RECORD = "synthetic-wn-40s"
FIGURE = Path(__file__).resolve().parent / "figures" / "building3d-cb-wp.png"
RTOLS = {"arctan": (1e-2, 1e-3, 1e-4, 1e-5, 1e-6), "switch": (1e-4, 1e-5, 1e-6, 1e-7)}
REFERENCE = {"arctan": 1e-9, "switch": 1e-11}  # rtol of the reference runs
DEFAULT = {"arctan": 1e-3, "switch": 1e-6}  # the work–precision chart's choice (docs)
PEAKS = ("peak_resultant_displacement_m", "peak_base_shear_N", "peak_drift_cm_x",
         "peak_drift_cm_y", "peak_floor_acc_x_mps2", "peak_floor_acc_y_mps2",
         "min_normal_force_N", "max_normal_force_N")  # fmt: skip
MODES = {kp.MODE_STICK: "stick", kp.MODE_SLIP: "slip", kp.MODE_START: "start",
         kp.MODE_FREE: "free"}  # fmt: skip


def atol(rtol: float) -> tuple[float, float]:
    return (1e-2 * rtol, 1e-2 * rtol)


@contextmanager
def kernel_clock(acc: list):
    """Time the loops' calls (appended to ``acc``) while the context is open."""
    saved = (_kpairsradau.integrate, _kpairsrun.integrate)

    def clocked(loop):
        def run(*a):
            t0 = time.perf_counter()
            st = loop(*a)
            acc.append(time.perf_counter() - t0)
            return st

        return run

    _kpairsradau.integrate, _kpairsrun.integrate = (clocked(f) for f in saved)
    try:
        yield
    finally:
        _kpairsradau.integrate, _kpairsrun.integrate = saved


def peaks(r) -> dict:
    s = r.summary()
    return {k: float(s[k]) for k in PEAKS}


def errors(r, ref) -> dict:
    """Largest relative peak error (and its key) and the orbits' error against ``ref``."""
    p, q = peaks(r), peaks(ref)
    rel = {k: abs(p[k] - q[k]) / abs(q[k]) for k in PEAKS}
    worst = max(rel, key=rel.get)
    u, u0 = r.result.u, ref.result.u
    k = min(len(u), len(u0))
    return {"peak_error": rel[worst], "worst_peak": worst,
            "orbit_error": float(np.abs(u[:k] - u0[:k]).max() / np.abs(u0).max())}  # fmt: skip


def timed(system, rec, repeats: int, **kw) -> tuple[dict, object]:
    """Median wall, CPU and kernel time of ``repeats`` runs, the counts, the last result."""
    wall, cpu, kern = [], [], []
    for _ in range(repeats):
        acc: list = []
        with kernel_clock(acc):
            t0, c0 = time.perf_counter(), time.process_time()
            r = run_building(system, rec, **kw)
            cpu.append(time.process_time() - c0)
            wall.append(time.perf_counter() - t0)
        kern.append(sum(acc))
    ev = Counter(f"{MODES[int(a)]}>{MODES[int(b)]}" for a, b in r.result.events[:, 2:4])
    out = {"wall_s": statistics.median(wall), "cpu_s": statistics.median(cpu),
           "kernel_s": statistics.median(kern), "cpu_min_s": min(cpu),
           **r.result.stats, "transitions": dict(ev)}  # fmt: skip
    out["python_s"] = out["wall_s"] - out["kernel_s"]
    return out, r


def rigid_rung(frame, rec, repeats: int) -> dict:
    deck = building_deck(frame, FPS)
    simulate_plane(deck, STUB, t_end=0.04)
    wall, cpu = [], []
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        rr = simulate_plane(deck, rec)
        cpu.append(time.process_time() - c0)
        wall.append(time.perf_counter() - t0)
    F = (rr.friction + rr.restoring + rr.other).sum(axis=1)
    return {"wall_s": statistics.median(wall), "cpu_s": statistics.median(cpu),
            "steps": rr.stats["steps"],
            "peak_resultant_displacement_m": float(rr.resultant(rr.u).max()),
            "peak_base_shear_N": float(np.hypot(F[:, 0], F[:, 1]).max())}  # fmt: skip


def main(repeats: int = 5, evidence: bool = False, rtols: dict = RTOLS) -> dict:
    rec = read_motion3(RECORD)
    frame = load_frame3d("office-11-3d")
    out: dict = {"record": rec.name, "duration_s": float(rec.duration), "dt_s": float(rec.dt),
                 "repeats": repeats}  # fmt: skip
    t0 = time.perf_counter()
    sys5 = building_pairs(frame, FPS, f_max=5.0)
    sys5.operators()
    out["setup_s"] = time.perf_counter() - t0
    info = sys5.info
    out["cb"] = {"n": sys5.n, "modes_below_f_max": info["n_modes_below_f_max"],
                 "modes_kept": info["n_modes"], "dropped_mass": info["dropped_mass"]}  # fmt: skip
    for law in ("arctan", "switch"):
        t0 = time.perf_counter()
        run_building(sys5, STUB, law=law, t_end=0.04)
        out[f"compile_{law}_s"] = time.perf_counter() - t0
    out["rigid"] = rigid_rung(frame, rec, repeats)
    refs, rows = {}, []
    for law in ("arctan", "switch"):
        rt = REFERENCE[law]
        ref_t, refs[law] = timed(sys5, rec, 1, law=law, rtol=rt, atol=atol(rt))
        rows.append({"law": law, "rtol": rt, "reference": True, **ref_t, **peaks(refs[law])})
        for rt in rtols[law]:
            t, r = timed(sys5, rec, repeats, law=law, rtol=rt, atol=atol(rt))
            rows.append({"law": law, "rtol": rt, "reference": False, **t, **peaks(r),
                         **errors(r, refs[law])})  # fmt: skip
    for v in rows:
        v["ratio_to_rigid"] = v["cpu_s"] / out["rigid"]["cpu_s"]
    out["runs"] = rows
    if evidence:
        ev = []
        for label, kw in (("5 Hz, min_mass 3e-3", {"f_max": 5.0, "min_mass": 3e-3}),
                          ("5 Hz, min_mass 1e-2", {"f_max": 5.0, "min_mass": 1e-2}),
                          ("5 Hz, min_mass 2e-2", {"f_max": 5.0, "min_mass": 2e-2}),
                          ("3.8 Hz, every mode", {"f_max": 3.8, "min_mass": None}),
                          ("5 Hz, every mode", {"f_max": 5.0, "min_mass": None})):  # fmt: skip
            t0 = time.perf_counter()
            s = building_pairs(frame, FPS, **kw)
            build = time.perf_counter() - t0
            for law in ("arctan", "switch") if kw["min_mass"] else ("arctan",):
                rt = DEFAULT[law]
                t, r = timed(s, rec, 1, law=law, rtol=rt, atol=atol(rt))
                ev.append({"model": label, "n": s.n, "law": law, "rtol": rt, "setup_s": build,
                           **t, **peaks(r), **errors(r, refs[law])})  # fmt: skip
        out["evidence"] = ev
    return out


ECC_RTOLS = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9)


def eccentric(t_end: float = 8.0) -> list[dict]:
    """The switch law on the office with a 5 % eccentricity along y (the cb model above, the
    first ``t_end`` s of the record) over ``ECC_RTOLS``: events, peak drifts at the centres of
    mass and peak isolator displacement (docs/guide/frames-3d.md: another event sequence, not
    a smooth error, at loose tolerances)."""
    t0, dt, ax, ay, az = read_motion3(RECORD).as_arrays()
    n = int(round(t_end / dt)) + 1
    rec = (t0, dt, ax[:n], ay[:n], az[:n])
    s = building_pairs(load_frame3d("office-11-3d"), FPS, f_max=5.0, eccentricity=(0.0, 0.05))
    rows = []
    for rt in ECC_RTOLS:
        r = run_building(s, rec, law="switch", rtol=rt, atol=atol(rt))
        sm = r.summary()
        rows.append({"rtol": rt, "events": len(r.result.events),
                     **{k: float(sm[k]) for k in ("peak_drift_cm_x", "peak_drift_cm_y",
                                                  "peak_resultant_displacement_m")}})  # fmt: skip
    return rows


def _print(out: dict) -> None:
    cb = out["cb"]
    print(f"office-11-3d cb rung, f_max 5 Hz: {cb['n']} coordinates ({cb['modes_kept']} of "
          f"{cb['modes_below_f_max']} fixed-interface modes kept; dropped mass fractions x, y, "
          f"z, torsion {', '.join(f'{v:.1e}' for v in cb['dropped_mass'])}); setup "
          f"{out['setup_s']:.1f} s; record {out['record']} ({out['duration_s']:g} s at "
          f"{out['dt_s']:g} s); medians of {out['repeats']} runs")  # fmt: skip
    print(f"compile/load: arctan {out['compile_arctan_s']:.1f} s, switch "
          f"{out['compile_switch_s']:.1f} s")  # fmt: skip
    r = out["rigid"]
    print(f"rigid deck: wall {r['wall_s']:.3f} s, CPU {r['cpu_s']:.3f} s, {r['steps']} steps, "
          f"|u| {r['peak_resultant_displacement_m']:.4f} m, |V| "
          f"{r['peak_base_shear_N'] / 1e6:.3f} MN")  # fmt: skip
    head = (f"{'run':17s} {'wall':>6s} {'cpu':>6s} {'kern':>6s} {'py':>5s} {'xrig':>5s} "
            f"{'steps':>6s} {'rej':>5s} {'evals':>7s} {'ev':>4s} {'peak err':>9s} "
            f"{'orbit err':>9s} worst / transitions")  # fmt: skip
    print(head)
    for v in out["runs"] + out.get("evidence", []):
        label = v.get("model", "") + f" {v['law']} {v['rtol']:.0e}" + ("*" * v["reference"]
                                                                        if "reference" in v
                                                                        else "")  # fmt: skip
        err = (f"{v['peak_error']:9.1e} {v['orbit_error']:9.1e} {v['worst_peak']}"
               if "peak_error" in v else f"{'(ref)':>9s} {'':9s}")  # fmt: skip
        tr = " ".join(f"{k} {n}" for k, n in sorted(v["transitions"].items()))
        print(f"{label.strip():17s} {v['wall_s']:6.3f} {v['cpu_s']:6.3f} {v['kernel_s']:6.3f} "
              f"{v['python_s']:5.3f} {v['cpu_s'] / out['rigid']['cpu_s']:5.1f} {v['steps']:6d} "
              f"{v['rejected']:5d} {v['evaluations']:7d} {v['events']:4d} {err} {tr}")  # fmt: skip


def figure(out: dict, path: Path = FIGURE) -> Path:
    """Work–precision: median CPU time against the largest relative peak error."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FixedLocator, NullFormatter, ScalarFormatter

    from nsdyn.atomic import save_figure

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for law, mark in (("arctan", "o-"), ("switch", "s-")):
        rows = [v for v in out["runs"] if v["law"] == law and not v["reference"]]
        e = [max(v["peak_error"], 1e-12) for v in rows]
        name = "regularised (Radau IIA)" if law == "arctan" else "switch (Dormand–Prince)"
        ax.loglog([v["cpu_s"] for v in rows], e, mark, label=name)
        for v, ei in zip(rows, e, strict=True):
            ax.annotate(f"{v['rtol']:.0e}", (v["cpu_s"], ei), fontsize=7,
                        textcoords="offset points", xytext=(4, 3))  # fmt: skip
    ax.axvline(out["rigid"]["cpu_s"], color="0.5", ls=":", label="rigid deck (switch)")
    ax.axvline(1.0, color="r", ls="--", lw=0.8, label="1 s")
    ax.xaxis.set_major_locator(FixedLocator([0.1, 0.2, 0.5, 1, 2, 5, 10]))
    ax.xaxis.set_major_formatter(ScalarFormatter())
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("CPU time of the 40 s run [s] (median)")
    ax.set_ylabel("largest relative peak error")
    ax.set_title(f"office-11-3d, cb rung ({out['cb']['n']} coordinates), {out['record']}",
                 fontsize=10)  # fmt: skip
    ax.legend(fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path)


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--repeats", type=positive_int, default=5, help="runs per tolerance (median)")
    p.add_argument("--evidence", action="store_true", help="also the other cb models")
    p.add_argument("--no-figure", action="store_true", help="skip the work-precision chart")
    p.add_argument("--quick", action="store_true", help="the chart's tolerances alone, once")
    ecc = "only the switch law on the eccentric office's first 8 s, by rtol"
    p.add_argument("--eccentric", action="store_true", help=ecc)
    where = f"folder of the chart (default {FIGURE.parent}: the docs' copy)"
    p.add_argument("--out", type=out_dir, metavar="DIR", help=where)
    args = p.parse_args()
    if args.eccentric:
        print("office-11-3d cb, 5 % eccentricity along y, switch law, first 8 s of the record")
        for v in eccentric():
            print(f"rtol {v['rtol']:.0e}: {v['events']:4d} events, drift x, y "
                  f"{v['peak_drift_cm_x']:.9f}, {v['peak_drift_cm_y']:.9f}, |u| "
                  f"{v['peak_resultant_displacement_m']:.9f} m")  # fmt: skip
        raise SystemExit(0)
    if args.quick:
        res = main(repeats=1, evidence=args.evidence, rtols={k: (v,) for k, v in DEFAULT.items()})
    else:
        res = main(repeats=args.repeats, evidence=args.evidence)
    _print(res)
    if not args.no_figure:
        path = FIGURE if args.out is None else Path(args.out) / FIGURE.name
        print(f"figure: {figure(res, path)}")
