"""Periodic orbits of the true Coulomb model by shooting: the switch model with saltation matrices.

A base-excited viscous + Coulomb oscillator and the office frame (CB-5, seed isolation,
A = 0.5 m/s^2): the switch-model orbit at a few frequencies, its events and Floquet
multipliers (a stick phase gives an exact zero multiplier), against arctan shooting. On the
frame the switch orbit is shot from the arctan orbit's start (from ``warm_start`` alone its
Newton fails the line search at 1.26 Hz); an orbit that does not converge says why, and the
script then exits with status 1.

    python examples/switch_shooting.py
    python examples/switch_shooting.py --curve [--out DIR]   # one 150-point curve, switch
                                                 # vs arctan, timed; tables in DIR (nsdyn-out)
"""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np

from nsdyn.cli.args import out_dir
from nsdyn.models.isolated.builders import system_from_matrices
from nsdyn.models.isolated.scene import build_scene, load_scene
from nsdyn.models.isolated.system import Isolation
from nsdyn.periodic import frame_problem, shoot, shoot_switch, switch_problem, warm_start


def main() -> dict:
    out = {}
    w = 2 * math.pi
    iso = Isolation(k_lam=0.0, c=0.0, mu=0.2, law="switch")
    osc = system_from_matrices(
        [[1.0]],
        [[0.1 * w]],
        [[w * w]],
        iso_dofs=[0],
        influence=[1.0],
        isolation=iso,
        weight=iso.g,
        levels=[[0]],
    )
    pb = switch_problem(osc, 2.5)
    for f in (0.5, 0.7, 1.5):
        r = shoot_switch(pb, f, tol=1e-10)
        out[f"osc {f} Hz"] = {
            "converged": r.converged,
            "x0": r.x0.tolist(),
            "events": len(r.events),
            "min_multiplier": float(np.abs(r.multipliers).min()),
        }
    frame, _ = build_scene(load_scene(None))
    sw, ar = switch_problem(frame, 0.5), frame_problem(frame, 0.5)
    for f in (0.463, 1.26):
        a = shoot(ar, f, warm_start(ar, f, None, None))
        r = shoot_switch(sw, f, a.x0 if a.converged else warm_start(sw, f, None, None))
        out[f"frame {f} Hz"] = {  # an orbit that did not converge has no x_iso: its reason
            "converged": r.converged,
            "x_iso_switch": sw.orbit_quantities(f, r.X)["x_iso"] if r.converged else None,
            "x_iso_arctan": ar.orbit_quantities(f, a.X)["x_iso"] if a.converged else None,
            "events": len(r.events),
            **({} if r.converged else {"why": r.message}),
        }
    for k, v in out.items():
        print(k, v)
    return out


def curve(out: str) -> dict:
    """The whole-curve benchmark (nsdyn bench switch_shooting --curve), one repeat, its tables
    in ``out``."""
    from nsdyn.bench.switch_shooting import run_curve_bench

    res = run_curve_bench(out, quick=False, repeats=1)
    for k, v in res.items():
        print(k, v)
    return res


if __name__ == "__main__":
    cli = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    cli.add_argument("--curve", action="store_true", help="one 150-point curve, timed")
    cli.add_argument("--out", type=out_dir, help="--curve: output folder (nsdyn-out)")
    args = cli.parse_args()
    if args.out is not None and not args.curve:
        cli.error("--out: the --curve run's output folder; give --curve too")
    if args.curve:
        args.out = args.out or "nsdyn-out"
        curve(args.out)
    else:
        res = main()
        sys.exit(0 if all(v.get("converged") for v in res.values()) else 1)
