"""First ten minutes with nsdyn: the Coulomb oscillator, a shear building, the office frame.

Three runs, one figure each (``examples/figures/first-*.png``):

1. a mass on a friction isolator released from 0.1 m: the amplitude drops by 4 mu g / w^2
   per cycle (Coulomb's linear decay) until it sticks;
2. a 3-storey shear building on an isolator under the first 20 s of the bundled 40 s record
   at PGA 3 m/s², against the same building with its isolator stuck (fixed base);
3. the office frame of seed 004 (Craig–Bampton, 13 dofs) under the same record.

``main()`` returns the numbers the figures show.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

from nsdyn._checks import NotedWarning
from nsdyn.atomic import save_figure
from nsdyn.ground import read_motion
from nsdyn.models.isolated.builders import shear_building
from nsdyn.models.isolated.system import Isolation, build_system
from nsdyn.solve.transient import simulate
from nsdyn.structure import load_frame

FIGURES = Path(__file__).resolve().parent / "figures"
RECORD_S = 20.0  # s of the bundled record used for the building runs


def coulomb_oscillator() -> tuple[dict, object]:
    from matplotlib.figure import Figure

    m, k, mu, g = 1000.0, 4.0e4, 0.05, 9.81
    s = shear_building([m], [], 0.0, isolation=Isolation(k_lam=k, c=0.0, mu=mu, law="switch"))
    r = simulate(s, None, method="event", t_end=3.0, dt_out=1e-3, x0=[0.1, 0.0])
    w = np.sqrt(k / m)
    fig = Figure(figsize=(6.5, 3.2))
    ax = fig.subplots()
    ax.plot(r.t, r.x[:, 0], lw=1.0, label="nsdyn (event-driven switch model)")
    env = np.maximum(0.1 - 4 * mu * g / w**2 * r.t * w / (2 * np.pi), mu * g / w**2)
    ax.plot(r.t, env, "k--", lw=0.8, label="envelope 0.1 m - (4 μg/ω²) per cycle")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("x [m]")
    ax.legend(fontsize=8)
    ax.set_title("Coulomb oscillator: linear decay, then stick", fontsize=10)
    fig.tight_layout()
    out = {
        "decrement_per_cycle_m": 4 * mu * g / w**2,
        "dead_band_m": mu * g / w**2,
        "x_final_m": float(r.x[-1, 0]),
        "t": r.t,
        "x": r.x[:, 0],
        "period_s": 2 * np.pi / w,
    }
    return out, fig


def shear_building_run() -> tuple[dict, object]:
    from matplotlib.figure import Figure

    rec = read_motion("synthetic-wn-40s").scaled_to_pga(3.0).window(0.0, RECORD_S)
    rec = rec.with_vertical(None)  # a shear building has no vertical dofs to feel it
    kw = dict(heights=3.0)
    args = ([2.0e4, 1.0e4, 1.0e4, 1.0e4], [2.0e7, 1.5e7, 1.0e7], 0.05)
    iso = Isolation(k_lam=2.0e5, c=2.0e4, mu=0.05, law="arctan", eps=500.0)
    isolated = simulate(shear_building(*args, isolation=iso, **kw), rec)
    with warnings.catch_warnings():  # mu = 10 on purpose (not a percentage): never slides
        warnings.simplefilter("ignore", NotedWarning)
        stuck = Isolation(k_lam=2.0e5, c=2.0e4, mu=10.0, law="switch")
    fixed = simulate(shear_building(*args, isolation=stuck, **kw), rec)
    fig = Figure(figsize=(8, 3.4))
    ax1, ax2 = fig.subplots(1, 2)
    ax1.plot(isolated.t, isolated.response.x_iso[:, 0], lw=0.8)
    ax1.set_xlabel("t [s]")
    ax1.set_ylabel("isolator slip [m]")
    lv = np.arange(4)
    for r, lab in ((isolated, "on friction isolator"), (fixed, "isolator stuck")):
        ax2.plot(r.response.floor_acc_by_level, lv, "o-", label=lab)
    ax2.set_xlabel("peak absolute acceleration [m/s²]")
    ax2.set_ylabel("level")
    ax2.legend(fontsize=8)
    fig.suptitle("3-storey shear building, 20 s of the bundled record at PGA 3 m/s²", fontsize=10)
    fig.tight_layout()
    out = {
        "x_iso_max_m": isolated.response.x_iso_max,
        "floor_acc_max_isolated_mps2": isolated.response.floor_acc_max,
        "floor_acc_max_stuck_mps2": fixed.response.floor_acc_max,
    }
    return out, fig


def office_frame() -> tuple[dict, object]:
    from nsdyn.plot import plot_transient

    rec = read_motion("synthetic-wn-40s").scaled_to_pga(3.0).window(0.0, RECORD_S)
    system = build_system(load_frame("office-11"), Isolation(), fidelity="cb", f_max=5.0)
    r = simulate(system, rec)
    out = {"x_iso_max_m": r.response.x_iso_max, "idr_max": r.response.idr_max}
    return out, plot_transient(r, rec)


def main(figures: bool = True, folder: Path = FIGURES) -> dict:
    """The numbers of the three runs; their figures written into ``folder`` (default the
    documentation's own, ``examples/figures``) unless ``figures`` is False."""
    out = {}
    for key, fn in (
        ("coulomb", coulomb_oscillator),
        ("shear", shear_building_run),
        ("office", office_frame),
    ):
        nums, fig = fn()
        if figures:
            path = Path(folder) / f"first-{key}.png"
            save_figure(fig, path, dpi=110)
            print(f"figure: {path}", file=sys.stderr)
        out[key] = nums
    return out


if __name__ == "__main__":
    import argparse

    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    from nsdyn.cli.args import out_dir

    ap.add_argument(
        "--out",
        type=out_dir,  # (checked before the models run: a file there was a traceback after)
        default=str(FIGURES),
        help=f"folder for the figures (default {FIGURES}, the documentation's)",
    )
    args = ap.parse_args()
    import json

    res = main(folder=Path(args.out))
    # histories (arrays) are printed as their shapes only
    print(json.dumps(res, indent=1, default=lambda a: f"<array {getattr(a, 'shape', '')}>"))
