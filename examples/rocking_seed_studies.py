"""Seed studies of the rocking family (seeds 001 and 003), with the numbers docs/guide/rocking.md
quotes.

Seed 001: the storage cask (2 m x 4 m, 124.8 t, aspect ratio 2): Housner's r, free rocking,
the 1 g sine at 0.81-1.0 Hz with r = 0.82 (amplitude growth in the first cycles), and the
block on spring-damper supports (effective r against ground stiffness, Table 2 model 1).
Seed 003: Table 1 (column 2H = 1.2 m, 2B = 0.3 m under the 0.40 g, T_p = 0.5 s one-sine
pulse: impact times and restitution), the Table 4 pulses on the columns and frames of
Tables 2-3, and the 19.2 m frame (2B = 3.2 m, gamma = 4) under San Salvador GIC090 (read in
place from the shared records; the Kobe Takarazuka record is not available).

Run: ``python examples/rocking_seed_studies.py [--out DIR]`` (figures into examples/figures/ or
DIR).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

from nsdyn.atomic import save_figure
from nsdyn.ground import G_EARTH, default_shared_dir, read_motion
from nsdyn.ground.pulses import n_cycle_sine, one_sine
from nsdyn.models.rocking import RockingBlock, simulate_rocking
from nsdyn.models.rocking.compliant import CompliantBlock, effective_restitution
from nsdyn.models.rocking.figures import history_figure, restitution_figure
from nsdyn.models.rocking.frame import RockingFrame, cg_displacement

FIG_DIR = Path(__file__).resolve().parent / "figures"
SAN_SALVADOR = "raw/sansalvador1986_gic090_osm.txt"  # relative to the shared records folder
TABLE4 = [(1.2, 0.4, 0.55), (1.2, 0.3, 0.40), (2.0, 0.4, 0.30), (2.0, 0.2, 0.15)]  # 2H, 2B, a_p/g
SEED003_T1 = {2: 2.00, 6: 4.61, 9: 5.74}  # seed 003 Table 1: analytical impact times [s]


def seed001(quick: bool) -> dict:
    cask = RockingBlock(width=2.0, height=4.0, mass=124800.0)
    out = {"seed001_housner_r": cask.restitution, "seed001_alpha": cask.alpha}
    free = simulate_rocking(cask, t_end=10.0, theta0_over_alpha=0.5, dt_out=0.01)
    out["seed001_free_peaks_over_alpha"] = [
        float(x) for x in np.abs(free.peaks[:4, 1]) / cask.alpha
    ]
    growth = {}
    blk = RockingBlock(width=2.0, height=4.0, r=0.82, mass=124800.0)
    for f in (0.81, 0.85, 0.9, 0.95, 1.0):
        res = simulate_rocking(blk, n_cycle_sine(G_EARTH, 2 * math.pi * f, 8), t_end=10.0,
                               dt_out=0.005)  # fmt: skip
        pk = np.abs(res.peaks[:, 1])
        k = int(np.argmax(pk[:12]))
        growth[f] = {"first_peak_over_alpha": float(pk[0] / blk.alpha),
                     "max_over_first": float(pk[k] / pk[0]), "half_cycle_of_max": k + 1,
                     "outcome": res.outcome}  # fmt: skip
        if f == 0.81 and not quick:
            fig = history_figure(res.t, res.theta, blk.alpha, "seed 001 cask, 1 g sine 0.81 Hz, "
                                 "r = 0.82", res.impacts)  # fmt: skip
            save_figure(fig, FIG_DIR / "rocking-seed001-sine.png")
    out["seed001_sine"] = growth
    ratios = [10, 30, 100, 300, 1000] if not quick else [30, 300]
    r_eff = {}
    for zeta in (0.5, 1.0, 2.0) if not quick else (2.0,):
        r_eff[f"ζ = {zeta}"] = [effective_restitution(CompliantBlock.from_frequency(
            width=2.0, height=4.0, mass=124800.0, omega_v=x * cask.p, zeta=zeta))
            for x in ratios]  # fmt: skip
    out["seed001_compliant_ratios"] = ratios
    out["seed001_compliant_r_eff"] = r_eff
    if not quick:
        save_figure(restitution_figure(ratios, r_eff, cask.restitution, 0.700),
                    FIG_DIR / "rocking-restitution.png")  # fmt: skip
    return out


def seed003(quick: bool) -> dict:
    out = {}
    col = RockingBlock(width=0.3, height=1.2)
    res = simulate_rocking(col, one_sine(0.40 * G_EARTH, 4 * math.pi), t_end=6.5, dt_out=0.002)
    imp = res.impacts
    out["seed003_table1_r"] = float(np.median(imp[:, 2] / imp[:, 1]))
    out["seed003_table1_times"] = {n: (float(imp[n - 1, 0]), t) for n, t in SEED003_T1.items()}
    out["seed003_table1_max_theta_over_alpha"] = res.max_theta_over_alpha
    if not quick:
        title = "seed 003 column 2, one-sine 0.40 g, T_p = 0.5 s"
        fig = history_figure(res.t, res.theta, col.alpha, title, imp)
        save_figure(fig, FIG_DIR / "rocking-seed003-column.png")
    table4 = []
    for h2, b2, ag in TABLE4:
        for model in (RockingBlock(width=b2, height=h2),
                      RockingFrame(width=b2, height=h2, gamma=5.0)):  # fmt: skip
            r = simulate_rocking(model, one_sine(ag * G_EARTH, 4 * math.pi), t_end=8.0, dt_out=0)
            table4.append({"2H": h2, "2B": b2, "a_p_g": ag, "model": type(model).__name__,
                           "r": model.restitution, "max_theta_over_alpha": r.max_theta_over_alpha,
                           "n_impacts": r.n_impacts, "outcome": r.outcome})  # fmt: skip
    out["seed003_table4"] = table4
    path = default_shared_dir() / "records" / SAN_SALVADOR if default_shared_dir() else None
    if path is not None and path.exists():
        mo = read_motion(path, units="m/s2")
        fr = RockingFrame(width=3.2, height=19.2, gamma=4.0)
        r = simulate_rocking(fr, mo, t_end=20.0, dt_out=0.005)
        u, v = cg_displacement(r.theta, fr.alpha, fr.R, factor=2.0)
        out["seed003_san_salvador"] = {
            "pga_g": mo.pga / G_EARTH,
            "max_theta_over_alpha": r.max_theta_over_alpha,
            "max_beam_u_m": float(np.max(np.abs(u))),
            "max_beam_v_m": float(np.max(v)),
            "outcome": r.outcome,
            "n_impacts": r.n_impacts,
        }
    else:
        out["seed003_san_salvador"] = "record not found under the shared records folder: skipped"
    out["seed003_takarazuka"] = "not available"
    return out


def main(quick: bool = False) -> dict:
    """All the numbers (``quick``: fewer stiffnesses, no figures)."""
    return {**seed001(quick), **seed003(quick)}


if __name__ == "__main__":
    import argparse
    import json

    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    from nsdyn.cli.args import out_dir

    ap.add_argument("--quick", action="store_true", help="fewer stiffnesses, no figures")
    ap.add_argument(
        "--out", type=out_dir, metavar="DIR", help="folder of the figures (default: the docs')"
    )
    a = ap.parse_args()
    FIG_DIR = FIG_DIR if a.out is None else Path(a.out)
    print(json.dumps(main(a.quick), indent=1, default=str, ensure_ascii=False))
    print("no figures (--quick)" if a.quick else f"figures in {FIG_DIR}", file=sys.stderr)
