"""Benchmark of the rocking family: work–precision of one block on a 40 s record, and the wall
time of one overturning spectrum.

Work–precision: seed 003 column 2 (2H = 1.2 m, 2B = 0.3 m) under the bundled 40 s synthetic
record scaled to PGA 4 m/s² (vertical kept), Dormand–Prince tolerances 1e-4 … 1e-11 against a
1e-13 reference: ``err_theta`` = max over the output grid of |theta - theta_ref| / alpha,
``err_peak`` = |max|theta| / max|theta_ref| - 1|; cost = median wall time of ``repeats`` runs
(compilation excluded: the kernel is loaded first and ``compile_s`` is reported apart).
A second series runs the seed 003 Table 4 one-sine pulse (0.40 g, 6 s), whose steps are not
bounded by record samples.
Spectrum: 40 frequencies omega_p / p in [1, 20] of a one-sine pulse, bisected to 1e-4
relative, on a local process pool (10 frequencies in quick mode).
"""

from __future__ import annotations

import csv
import statistics
import time
from pathlib import Path

import numpy as np

from nsdyn.atomic import atomic_open, save_figure

TOLS = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11)  # work-precision tolerances
REF_TOL = 1e-13  # reference tolerance
PGA = 4.0  # record PGA [m/s²]
N_FREQ = 40  # spectrum frequencies (full mode)
OPTIONS = ("figures",)  # options run_bench takes
FIGURES = ("rocking.png",)  # the figures it draws (removed under --no-figures)


def _record_runs(quick: bool, repeats: int, case: str = "record"):
    from nsdyn.ground import read_motion
    from nsdyn.ground.pulses import one_sine
    from nsdyn.models.rocking import RockingBlock, simulate_rocking

    blk = RockingBlock(width=0.3, height=1.2)
    if case == "record":
        mo = read_motion("synthetic-wn-40s").scaled_to_pga(PGA)
        t_end = mo.t0 + mo.duration
    else:  # seed 003 Table 4 pulse, 6 s: steps not bounded by record samples
        mo = one_sine(0.40 * 9.81, 4 * np.pi)
        t_end = 6.0
    ref = simulate_rocking(blk, mo, t_end=t_end, tol=REF_TOL)
    rows = []
    for tol in TOLS[1::2] if quick else TOLS:  # (quick: 1e-5 ... 1e-11, 1e-9 among them)
        walls = []
        for _ in range(repeats):
            res = simulate_rocking(blk, mo, t_end=t_end, tol=tol)
            walls.append(res.wall_s)
        n = min(res.t.size, ref.t.size)
        rows.append({
            "case": case,
            "tol": tol,
            "wall_s": statistics.median(walls),
            "err_theta": float(np.max(np.abs(res.theta[:n] - ref.theta[:n])) / blk.alpha),
            "err_peak": abs(res.max_abs_theta / ref.max_abs_theta - 1.0),
            "n_steps": res.n_steps,
            "n_impacts": res.n_impacts,
            "n_impacts_ref": ref.n_impacts,
        })  # fmt: skip
    return rows, ref


def run_bench(out_dir: Path, quick: bool, figures: bool = True) -> dict:
    """Run the rocking benchmark; writes ``rocking-wp.csv``, ``rocking-spectrum.csv`` and
    (``figures``) ``rocking.png`` into ``out_dir``; returns the headline numbers."""
    from nsdyn.models.rocking import RockingBlock
    from nsdyn.models.rocking.block import warmup
    from nsdyn.models.rocking.spectra import overturning_spectrum

    out_dir = Path(out_dir)
    compile_s = warmup()
    rows, ref = _record_runs(quick, 3 if quick else 7)
    rows_p, _ = _record_runs(quick, 3 if quick else 7, "pulse")
    with atomic_open(out_dir / "rocking-wp.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows + rows_p)
    blk = RockingBlock(width=0.3, height=1.2)
    x = np.geomspace(1.0, 20.0, 10 if quick else N_FREQ)
    overturning_spectrum(blk, x[:2])  # pool and workers warm (kernel loaded from cache)
    sp = overturning_spectrum(blk, x)
    with atomic_open(out_dir / "rocking-spectrum.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["omega_ratio", "a_min_ratio", "mode", "safe_lo_ratio", "safe_hi_ratio"])
        for i in range(x.size):
            w.writerow([x[i], sp.a_min_ratio[i], sp.mode[i], sp.safe_lo_ratio[i],
                        sp.safe_hi_ratio[i]])  # fmt: skip
    files = ["rocking-wp.csv", "rocking-spectrum.csv"]
    if figures:
        save_figure(_figure(rows, rows_p, x, sp), out_dir / "rocking.png")
        files.append("rocking.png")
    best = next(r for r in rows if r["tol"] == 1e-9)  # every tolerance list holds 1e-9
    return {
        "compile_s": compile_s,
        "record_wall_ms_tol1e-9": best["wall_s"] * 1e3,
        "record_err_theta_tol1e-9": best["err_theta"],
        "pulse_wp": [
            {"tol": r["tol"], "wall_ms": r["wall_s"] * 1e3, "err_theta": r["err_theta"]}
            for r in rows_p
        ],  # fmt: skip
        "spectrum_n_freq": int(x.size),
        "spectrum_wall_s": sp.wall_s,
        "spectrum_runs": sp.n_runs,
        "files": [str(out_dir / f) for f in files],
    }


def _figure(rows, rows_p, x, sp):
    """The work-precision chart (record and pulse) and the overturning spectrum."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 4.0), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    ax1.loglog([r["wall_s"] * 1e3 for r in rows], [max(r["err_theta"], 1e-16) for r in rows],
               "o-", label="θ on the grid / α")  # fmt: skip
    ax1.loglog([r["wall_s"] * 1e3 for r in rows], [max(r["err_peak"], 1e-16) for r in rows],
               "s--", label="max|θ| (relative)")  # fmt: skip
    ax1.loglog([r["wall_s"] * 1e3 for r in rows_p], [max(r["err_theta"], 1e-16) for r in rows_p],
               "^-", label="one-sine 0.40 g, 6 s: θ / α")  # fmt: skip
    for r in rows + rows_p:
        ax1.annotate(f"{r['tol']:.0e}", (r["wall_s"] * 1e3, max(r["err_theta"], 1e-16)),
                     fontsize=7)  # fmt: skip
    ax1.set_xlabel("wall time per run [ms] (median)")
    ax1.set_ylabel("error vs tol 1e-13")
    ax1.set_title("column 2 on a 40 s record (PGA 4 m/s²)", fontsize=9)
    ax1.legend(fontsize=8)
    ax2.plot(x, sp.a_min_ratio, "o-", ms=3, label="minimum overturning")
    ax2.fill_between(x, sp.safe_lo_ratio, sp.safe_hi_ratio, alpha=0.25, label="safe band")
    ax2.set_xlabel("ω_p / p")
    ax2.set_ylabel("a_p / (g tan α)")
    ax2.set_title(f"one-sine spectrum: {x.size} freqs in {sp.wall_s:.2f} s", fontsize=9)
    ax2.legend(fontsize=8)
    return fig


if __name__ == "__main__":
    import json
    import sys

    t0 = time.perf_counter()
    quick = "--quick" in sys.argv
    print(json.dumps(run_bench(Path("nsdyn-out/bench"), quick), indent=1))
    print(f"total {time.perf_counter() - t0:.1f} s", file=sys.stderr)
