"""``nsdyn export opensees SCENE.toml [-o out.py]``: write a scene's full model as OpenSees script.

The script (:func:`nsdyn.models.isolated.opensees.export_opensees`) rebuilds the isolated
frame's full FE model (seed 004 eqs 1-15: M qdd + C* qd + K* q = -M Gamma u'' + contact and
friction forces) in openseespy, runs the scene's record and prints the peaks as JSON.
Given a 3D frame file (or a bundled 3D frame's name) instead of a scene, it writes the space
frame with a fixed base and an eigen analysis
(:func:`nsdyn.models.isolated.opensees3d.export_opensees_3d`): ``K_ii φ = ω² M_ii φ``.
Given a 3D building scene (``kind = "building3d"``), it writes the space frame on a bearing
under every base node with the scene's three-component record (fidelity "fixed": clamped)
(:func:`nsdyn.models.isolated.opensees3d_isolated.export_building_opensees`).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from nsdyn.cli.args import json_report, out_file, positive_float, positive_int

__all__ = ["configure", "run"]

TARGETS = ("opensees",)


def configure(p: argparse.ArgumentParser) -> None:
    """Arguments of ``nsdyn export``."""
    p.add_argument("target", choices=TARGETS, help="what to export to: opensees (openseespy)")
    p.add_argument(
        "scene",
        nargs="?",
        default=None,
        help="scene TOML of an isolated frame (kind 'isolated', a frame) or of a 3D building "
        "(kind 'building3d': the frame on its bearings, the record), or a 3D frame file "
        "or bundled 3D frame (fixed base, eigen analysis); default: the default scene, as "
        "nsdyn run runs it (written to office-11_opensees.py)",
    )
    p.add_argument(
        "-o",
        "--out",
        type=out_file,
        default=None,
        metavar="FILE",
        help="script to write (default: in the current folder, the scene file's or frame's "
        "name with _opensees.py; _opensees_fixed.py with --fixed-base)",
    )
    p.add_argument(
        "--dt",
        type=positive_float,
        default=None,
        metavar="S",
        help="fixed time step [s] (default: the scene's solver.dt, else 0.005)",
    )
    p.add_argument(
        "--t-end",
        type=positive_float,
        default=None,
        metavar="S",
        help="end the record at this time [s] (as nsdyn run --t-end)",
    )
    p.add_argument(
        "--damping",
        choices=("modal", "stiffness"),
        default=None,
        help="modal: modalDampingQ on the sliding structure's modes with nsdyn's damping "
        "projected on them (default); stiffness: Rayleigh beta K on the members",
    )
    p.add_argument(
        "--mass",
        choices=("consistent", "lumped"),
        default=None,
        help="3D frames: element mass of the exported model and of nsdyn's reference modes",
    )
    p.add_argument(
        "--modes",
        type=positive_int,
        default=None,
        metavar="N",
        help="3D frames: frequencies to compute (default 12)",
    )
    p.add_argument(
        "--fixed-base",
        action="store_true",
        help="3D building scenes: export the clamped frame whatever the scene's fidelity",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object and nothing else")


def _frame3d_name(scene: str) -> str | None:
    """The 3D frame's name if ``scene`` is a 3D frame file or bundled 3D frame, else None."""
    from nsdyn.structure import FrameFileError, is_frame3d

    try:
        return Path(scene).stem if is_frame3d(scene) else None
    except FrameFileError:
        return None  # not a frame file: the scene path reports its own errors


def _run_frame3d(args: argparse.Namespace, stem: str) -> int:
    from nsdyn.models.isolated.opensees3d import export_opensees_3d
    from nsdyn.models.scenefile import SceneError
    from nsdyn.structure import load_frame3d

    _only(args, "a 3D frame file", ("mass", "modes"))
    frame = load_frame3d(args.scene)
    if args.modes is not None and args.modes > MODES_MAX:  # (100 000: an eigen solve of minutes)
        raise SceneError(f"{args.scene}: --modes: expected at most {MODES_MAX} (the lowest "
                         f"modes listed beside OpenSees'), got {args.modes}")  # fmt: skip
    modes = 12 if args.modes is None else args.modes  # (at most the frame's, as its modes)
    out = Path(args.out) if args.out else Path(f"{stem}_opensees.py")
    try:
        export_opensees_3d(frame, out, mass=args.mass or "consistent", n_modes=modes)
    except ValueError as exc:  # a frame the export cannot map (e.g. a clamped diaphragm node)
        raise SceneError(f"{args.scene}: {exc}") from None
    from nsdyn.models.isolated.opensees import load_script

    d = load_script(out).DATA
    if d["n_modes"] < modes:  # (200 of a 39-dof portal listed 15, unsaid)
        print(f"nsdyn export: note: --modes {modes}: {frame.name} has {d['n_modes']} modes to "
              "list (its degrees of freedom once clamped and tied to its diaphragms)",
              file=sys.stderr)  # fmt: skip
    if args.json:
        info = {
            "frame": d["name"],
            "n_nodes": len(d["nodes"]),
            "n_elements": len(d["elements"]),
            "n_diaphragms": len(d["diaphragms"]),
            "mass": d["mass"],
            "nsdyn_f_hz": d["nsdyn_f_hz"],
        }
        print(json_report({"script": str(out), **info}))
        return 0
    print(f"wrote {out}  (fixed-base eigen analysis; run it with: python {out})")
    return 0


MODES_MAX = 200  # modes a 3D frame's export lists (nsdyn's and the script's eigen solves)
_OPTIONS = ("dt", "t_end", "damping", "mass", "modes", "fixed_base")


def _only(args: argparse.Namespace, what: str, takes: tuple[str, ...]) -> None:
    """Refuse the options given that the export of ``what`` does not use (one line)."""
    from nsdyn.models.scenefile import SceneError

    unused = [k for k in _OPTIONS if k not in takes and getattr(args, k) not in (None, False)]
    if unused:
        flags = ", ".join("--" + k.replace("_", "-") for k in unused)
        ok = ", ".join("--" + k.replace("_", "-") for k in takes)
        raise SceneError(f"{args.scene or '<default scene>'}: {flags}: not used by the export "
                         f"of {what} (its options: {ok})")  # fmt: skip


def _is_building3d(scene: str) -> bool:
    from nsdyn.models.scenefile import SceneError, read_toml, scene_kind

    if not (scene.endswith(".toml") and Path(scene).is_file()):
        return False
    try:
        return scene_kind(read_toml(scene), scene) == "building3d"
    except SceneError:
        return False  # the isolated path reports the file's own error


def _run_building3d(args: argparse.Namespace) -> int:
    from nsdyn.models.isolated.opensees3d_isolated import export_building_opensees

    _only(args, "a 3D building scene", ("dt", "t_end", "fixed_base"))
    scene = Path(args.scene)
    # default: in the current folder (never beside the scene, which may be the package's), the
    # clamped building under a name of its own (it replaced the isolated one's script)
    tail = "_opensees_fixed.py" if args.fixed_base else "_opensees.py"
    out = Path(args.out) if args.out else Path(f"{scene.stem}{tail}")
    export_building_opensees(scene, out, dt=args.dt, t_end=args.t_end,
                             fixed_base=True if args.fixed_base else None)  # fmt: skip
    from nsdyn.models.isolated.opensees import load_script

    d = load_script(out).DATA
    if args.t_end and d["duration"] < args.t_end - 1e-6 and not args.json:  # (as the frame's)
        print(f"nsdyn export: note: --t-end {args.t_end:g} s is past the record's end; the "
              f"script runs {d['duration']:g} s", file=sys.stderr)  # fmt: skip
    if args.json:
        info = {
            "frame": d["name"],
            "n_nodes": len(d["nodes"]),
            "n_elements": len(d["elements"]),
            "fixed_base": d["fixed_base"],
            "bearings": sorted({b["type"] for b in d["bearings"]}),
            "k_init": [b["k_init"] for b in d["bearings"]],
            "dt": d["dt"],
            "duration_s": d["duration"],
        }
        print(json_report({"script": str(out), **info}))
        return 0
    print(f"wrote {out}  (run it with: python {out} [--out DIR] [--t-end S])")
    return 0


def run(args: argparse.Namespace) -> int:
    """Write the script; print where (and the model's key numbers)."""
    from nsdyn.models.isolated.opensees import export_opensees

    if args.scene is None:  # the default scene, the one `nsdyn run` runs without a file
        from nsdyn.models.isolated.defaults import FRAME
        from nsdyn.models.isolated.scene import load_scene

        scene = load_scene(None, {"scene": {"fidelity": "full"}})
        named = Path(f"{FRAME}_opensees.py")
    else:
        stem = _frame3d_name(args.scene)
        if stem is not None:
            return _run_frame3d(args, stem)
        if _is_building3d(args.scene):
            return _run_building3d(args)
        scene = Path(args.scene)
        named = Path(f"{scene.stem}_opensees.py")  # in the current folder
    _only(args, "an isolated-frame scene", ("dt", "t_end", "damping"))
    out = Path(args.out) if args.out else named
    export_opensees(scene, out, dt=args.dt, t_end=args.t_end, damping=args.damping or "modal")
    data = load_script_data(out) if args.json or args.t_end else None
    if args.t_end and data["duration_s"] < args.t_end - 1e-6 and not args.json:
        print(f"nsdyn export: note: --t-end {args.t_end:g} s is past the record's end; the "
              f"script runs {data['duration_s']:g} s", file=sys.stderr)  # fmt: skip
    if args.json:
        print(json_report({"script": str(out), **data}))
        return 0
    print(f"wrote {out}  (run it with: python {out} [--t-end S])")
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
