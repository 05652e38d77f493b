"""``nsdyn export opensees SCENE.toml [-o out.py]``: write a scene's full model as OpenSees script.

The script (:func:`nsdyn.models.isolated.opensees.export_opensees`) rebuilds the isolated
frame's full FE model (seed 004 eqs 1-15: M qdd + C* qd + K* q = -M Gamma u'' + contact and
friction forces) in openseespy, runs the scene's record and prints the peaks as JSON.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from nsdyn.cli.args import positive_float

__all__ = ["configure", "run"]

TARGETS = ("opensees",)


def configure(p: argparse.ArgumentParser) -> None:
    """Arguments of ``nsdyn export``."""
    p.add_argument("target", choices=TARGETS, help="what to export to: opensees (openseespy)")
    p.add_argument("scene", help="scene TOML of an isolated frame (kind 'isolated', a frame)")
    p.add_argument(
        "-o",
        "--out",
        default=None,
        metavar="FILE",
        help="script to write (default: the scene's name with _opensees.py)",
    )
    p.add_argument(
        "--dt",
        type=positive_float,
        default=None,
        metavar="S",
        help="fixed time step [s] (default: the scene's solver.dt, else 0.005)",
    )
    p.add_argument(
        "--t-end", type=positive_float, default=None, metavar="S", help="cut the record here [s]"
    )
    p.add_argument(
        "--damping",
        choices=("modal", "stiffness"),
        default="modal",
        help="modal: modalDampingQ on the sliding structure's modes with nsdyn's damping "
        "projected on them (default); stiffness: Rayleigh beta K on the members",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object and nothing else")


def run(args: argparse.Namespace) -> int:
    """Write the script; print where (and the model's key numbers)."""
    from nsdyn.models.isolated.opensees import export_opensees

    scene = Path(args.scene)
    out = Path(args.out) if args.out else scene.with_name(f"{scene.stem}_opensees.py")
    export_opensees(scene, out, dt=args.dt, t_end=args.t_end, damping=args.damping)
    data = load_script_data(out) if args.json else None
    if args.json:
        print(json.dumps({"script": str(out), **data}))
        return 0
    print(f"wrote {out}  (run it with: python {out})")
    return 0


def load_script_data(path: Path) -> dict:
    """The key numbers of an exported script (without importing OpenSees)."""
    from nsdyn.models.isolated.opensees import load_script

    d = load_script(path).DATA
    return {
        "frame": d["name"],
        "n_nodes": len(d["nodes"]),
        "n_elements": len(d["elements"]),
        "dt": d["dt"],
        "duration_s": d["duration"],
        "k_init": d["k_init"],
        "damping": d["damping"],
        "modal_modes": len(d["modal_zeta"]),
    }
