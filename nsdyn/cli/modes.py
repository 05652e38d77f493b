"""``nsdyn modes``: fixed-base modes, dof counts, total mass and f_bis of a frame.

A 3D frame file (a ``[frame3d]`` table) lists its modes with their family (x, y, torsion,
vertical, local) and effective-mass fractions in x, y and θz instead.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from nsdyn.atomic import save_figure
from nsdyn.cli.args import json_report, out_dir
from nsdyn.cli.args import positive_finite as _positive_finite
from nsdyn.cli.args import positive_float as _positive_float
from nsdyn.models.isolated.defaults import F_MAX as DEFAULT_FMAX
from nsdyn.models.isolated.defaults import FRAME as DEFAULT_FRAME
from nsdyn.models.isolated.defaults import K_LAM as DEFAULT_KLAM
from nsdyn.models.scenefile import file_stem
from nsdyn.structure import base_isolation_frequency, load_frame

DEFAULT_OUT = "nsdyn-out"  # directory for figures
N_LIST = 10  # fixed-base modes listed by `modes`
N_DRAW = 4  # mode shapes drawn by `modes`
N_LIST_3D = 12  # fixed-base modes listed for a 3D frame (four of each family, typically)


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "frame",
        nargs="?",
        default=DEFAULT_FRAME,
        help="bundled frame name, path to a frame .toml file, or a scene naming a frame "
        f"(default: the default scene's frame, {DEFAULT_FRAME})",
    )
    p.add_argument(
        "--fmax",
        type=_positive_float,
        default=None,
        metavar="HZ",
        help=f"Craig–Bampton cut-off frequency (default {DEFAULT_FMAX:g}; 'inf' keeps all)",
    )
    p.add_argument(
        "--klam",
        type=_positive_finite,
        default=None,
        metavar="N_PER_M",
        help=f"lateral stiffness of one laminated bearing for f_bis (default: a scene's "
        f"[isolation] k_lam, else {DEFAULT_KLAM:g})",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object and nothing else")
    p.add_argument(
        "--out",
        type=out_dir,
        metavar="DIR",
        default=None,
        help=f"directory for the mode-shape PNG (default {DEFAULT_OUT}/; with --json and no "
        "--out, none)",
    )


def modes_summary(frame, f_max: float, k_lam: float) -> tuple[dict, np.ndarray, np.ndarray]:
    """Numbers reported by ``nsdyn modes`` plus the listed frequencies and shapes."""
    from nsdyn.structure import damping_ratios, fixed_base_modes, mode_type, reduce_frame

    K, M = frame.assemble()
    f, Phi = fixed_base_modes(K, M, frame.boundary_dofs, n_modes=N_LIST)
    cb = reduce_frame(frame, f_max)
    summary = {
        "frame": frame.name,
        "kind": "plane",  # (a 3D frame's: "3d")
        "n_nodes": frame.n_nodes,
        "n_dof": frame.n_dof,
        "n_boundary": int(len(frame.boundary_dofs)),
        "f_max_hz": f_max if math.isfinite(f_max) else None,
        "n_modes_kept": cb.n_modes,
        "n_reduced": cb.n_red,
        "frequencies_hz": [float(x) for x in f],
        "mode_types": [mode_type(Phi[:, k], M, frame) for k in range(len(f))],
        "damping_ratios": damping_ratios(frame.zeta, len(f)).tolist(),
        "total_mass_kg": frame.total_mass,
        "k_lam_n_per_m": k_lam,
        "f_bis_hz": base_isolation_frequency(frame, k_lam),
    }
    return summary, f, Phi


# a common rule of thumb of isolation design: an isolation period of at least 3 fixed-base
# periods; with f_bis above f_1/3 nsdyn modes says so
ISOLATION_RATIO = 3.0

SCENE_TABLES = ("scene", "isolation", "motion", "solver", "structure", "force")


def _scene_frame(arg: str) -> tuple[str, float | None, float | None, str | None]:
    """The frame ``nsdyn modes ARG`` lists: ``arg`` itself (a frame file or bundled name), or
    the frame a scene file names (``[scene] frame``, ``[structure] frame3d``; an isolated
    scene without either, or a scene of tables alone, runs the default frame); a scene
    without a frame is refused. With the scene's ``[isolation] k_lam`` (a number) and its
    Craig–Bampton cut-off (``[scene] f_max``, a positive number), or None; and the scene's
    field that names the frame (None: ``arg`` is the frame)."""
    import tomllib

    from nsdyn import _textfile as textfile
    from nsdyn.models.scenefile import SceneError, resolve_paths

    p = Path(arg)
    try:
        data = tomllib.loads(textfile.read(p)) if p.suffix == ".toml" and p.is_file() else {}
    except (OSError, ValueError):  # (TOMLDecodeError is one)
        return arg, None, None, None  # the frame reader names the problem
    scene_like = (
        "frame" not in data
        and "frame3d" not in data
        and any(isinstance(data.get(t), dict) for t in SCENE_TABLES)
    )
    if not scene_like:
        return arg, None, None, None
    data = resolve_paths({"scene": {}} | data, p.parent, arg)
    kind = data["scene"].get("kind", "isolated")
    if kind == "isolated":  # checked as nsdyn run checks it (a k_lam = -5 read as none)
        from nsdyn.models.isolated.scene import load_scene

        ends = [data.get(t) for t in ("motion", "force") if isinstance(data.get(t), dict)]
        open_end = any(not {"t_end", "n_periods"} & t.keys() for t in ends)  # (a harmonic's,
        load_scene(p, {"motion": {"t_end": 1.0}} if open_end else None)  # as nsdyn run --t-end)
    frame = data["scene"].get("frame") or data.get("structure", {}).get("frame3d")
    field = "scene.frame" if data["scene"].get("frame") or frame is None else "structure.frame3d"
    if kind == "isolated" and frame is None and "structure" not in data:
        frame = DEFAULT_FRAME
    if not isinstance(frame, str):
        raise SceneError(
            f"{arg}: a scene of kind {kind!r} without a frame; nsdyn modes takes a frame file, "
            "a bundled frame's name, or a scene that names a frame ([scene] frame, "
            "[structure] frame3d)"
        )
    k_lam = (
        data.get("isolation", {}).get("k_lam") if isinstance(data.get("isolation"), dict) else None
    )
    vals = k_lam if isinstance(k_lam, list) else [k_lam]  # one per isolator: their mean
    fm = data["scene"].get("f_max")
    fm = float(fm) if isinstance(fm, int | float) and not isinstance(fm, bool) and fm > 0 else None
    if vals and all(
        isinstance(v, int | float) and not isinstance(v, bool) and v >= 0 for v in vals
    ):
        return frame, float(sum(vals)) / len(vals), fm, field
    return frame, None, fm, field


def _frame_of_scene(given: str, frame: str, field: str | None) -> bool:
    """Whether ``frame`` is a 3D frame; a scene's (``field`` names it) is refused as ``nsdyn
    run`` refuses it: missing, or a plane frame as ``[structure] frame3d``, a 3D frame as
    ``[scene] frame``."""
    from nsdyn.models.scenefile import SceneError
    from nsdyn.structure import FrameFileError, is_frame3d

    try:
        space = is_frame3d(frame)
    except FrameFileError as e:
        if field is None:
            raise
        raise SceneError(f"{given}: {field}: {e}") from None
    if field is not None and space != (field == "structure.frame3d"):
        want = (
            "a 3D frame ([frame3d]; bundled: office-11-3d, portal-3d)"
            if not space
            else "a plane frame (a 3D frame is a building3d scene's [structure] frame3d)"
        )
        raise SceneError(f"{given}: {field}: expected {want}, got {frame}")
    return space


def run(args: argparse.Namespace) -> int:
    given = str(args.frame)
    args.frame, scene_klam, scene_fmax, field = _scene_frame(given)
    space = _frame_of_scene(given, args.frame, field)
    klam_from_scene = args.klam is None and scene_klam is not None and not space
    fmax_from_scene = args.fmax is None and scene_fmax is not None and not space
    if field is not None:  # a scene: its frame alone, as the frame file defines it
        with_klam = f"; f_bis with its K_lam = {scene_klam:g} N/m" if klam_from_scene else ""
        with_fmax = f"; its cut-off f_max = {scene_fmax:g} Hz" if fmax_from_scene else ""
        left = "eccentricity, bearings or mode count" if space else "isolators"
        print(f"nsdyn modes: note: the fixed-base modes of {args.frame}, the frame {given} "
              f"names, as its frame file defines it (without the scene's {left}{with_klam}"
              f"{with_fmax})", file=sys.stderr)  # fmt: skip
    if space:
        return _run3d(args)
    frame = load_frame(args.frame)
    if not frame.total_mass > 0:  # (a ZeroDivisionError from f_bis)
        from nsdyn.models.scenefile import SceneError

        raise SceneError(f"{args.frame}: frame {frame.name!r} has no mass (rho_A = 0 on every "
                         "element and no node mass): no mode of finite frequency")  # fmt: skip
    fmax = scene_fmax if fmax_from_scene else DEFAULT_FMAX if args.fmax is None else args.fmax
    klam = scene_klam if klam_from_scene else DEFAULT_KLAM if args.klam is None else args.klam
    s, f, Phi = modes_summary(frame, fmax, klam)
    notes = []
    if not s["n_modes_kept"] and f.size:  # (as nsdyn run says of such a model)
        notes.append(f"Craig-Bampton at f_max = {fmax:g} Hz keeps no flexible mode (the "
                     f"first fixed-interface mode is at {f[0]:.4g} Hz): a run's structure "
                     "would move quasi-statically; raise --fmax above it")  # fmt: skip
    lateral = [fk for fk, t in zip(f, s["mode_types"], strict=True) if t == "lateral"]
    if lateral and s["f_bis_hz"] > lateral[0] / ISOLATION_RATIO:
        notes.append(f"f_bis = {s['f_bis_hz']:.4g} Hz is {s['f_bis_hz'] / lateral[0]:.3g} x "
                     f"the first lateral fixed-base mode ({lateral[0]:.4g} Hz): the rigid-body "
                     "estimate holds well below it, and an isolated design aims at 1/"
                     f"{ISOLATION_RATIO:g} or less; K_lam = {klam:g} N/m is a stiff "
                     "bearing")  # fmt: skip
    if notes:
        s["notes"] = notes
        if not args.json:
            for n in notes:
                print(f"nsdyn modes: note: {n}", file=sys.stderr)
    out = args.out if args.out is not None else (None if args.json else DEFAULT_OUT)
    if out is not None:
        from nsdyn.plot import plot_mode_shapes

        path = Path(out) / f"modes-{file_stem(frame.name)}.png"
        save_figure(plot_mode_shapes(frame, f, Phi, n=N_DRAW), path)
        s["figure"] = str(path)
    if args.json:
        print(json_report(s))
        return 0
    fmax = "inf" if s["f_max_hz"] is None else f"{s['f_max_hz']:g} Hz"
    print(f"frame {s['frame']}: {s['n_nodes']} nodes, {s['n_dof']} dofs")
    print(
        f"Craig–Bampton at f_max = {fmax}: {s['n_boundary']} boundary + "
        f"{s['n_modes_kept']} modal = {s['n_reduced']} generalised dofs"
    )
    print("fixed-base modes:")
    print("   #   f [Hz]   type      zeta")
    rows = zip(s["frequencies_hz"], s["mode_types"], s["damping_ratios"], strict=True)
    for k, (fk, t, z) in enumerate(rows):
        print(f"  {k + 1:2d}  {fk:7.4g}   {t:8s}  {z:.3f}")
    print(f"total mass M_s = {s['total_mass_kg']:.4g} kg")
    print(f"f_bis = sqrt({len(frame.base_nodes)} K_lam / M_s) / 2pi = {s['f_bis_hz']:.4g} Hz")
    print(f"  (K_lam = {s['k_lam_n_per_m']:g} N/m)")
    if "figure" in s:
        print(f"mode shapes: {s['figure']}")
    return 0


def _run3d(args: argparse.Namespace) -> int:
    """``nsdyn modes`` of a space frame: families and participation; no Craig–Bampton yet."""
    from nsdyn.models.scenefile import SceneError
    from nsdyn.structure import damping_ratios, fixed_base_modes_3d, load_frame3d

    plane = {"--fmax": "the Craig–Bampton cut-off", "--klam": "the bearing stiffness of f_bis"}
    given = [f for f, v in (("--fmax", args.fmax), ("--klam", args.klam)) if v is not None]
    if given:
        raise SceneError(f"{args.frame}: {', '.join(given)}: {' and '.join(map(plane.get, given))}"
                         " of a plane frame; a 3D frame lists its fixed-base modes")  # fmt: skip
    frame = load_frame3d(args.frame)
    try:
        m = fixed_base_modes_3d(frame, n_modes=N_LIST_3D)
    except ValueError as e:  # (a frame without mass: no mode of finite frequency)
        raise SceneError(f"{args.frame}: {e}") from None
    s = {
        "frame": frame.name,
        "kind": "3d",
        "n_nodes": frame.n_nodes,
        "n_dof": frame.n_dof,
        "n_dof_after_diaphragms": frame.n_red,
        "n_diaphragms": len(frame.diaphragms),
        "frequencies_hz": [float(x) for x in m.f_hz],
        "families": list(m.family),
        "mass_fractions_x_y_theta": m.mass_fraction.round(6).tolist(),
        "damping_ratios": damping_ratios(frame.zeta, len(m.f_hz)).tolist(),
        "total_mass_kg": frame.total_mass,
        "mass_centre_m": m.centre.tolist(),
    }
    out = args.out if args.out is not None else (None if args.json else DEFAULT_OUT)
    if out is not None:
        from nsdyn.plot.frames3d import plot_mode_shapes_3d

        path = Path(out) / f"modes-{file_stem(frame.name)}.png"
        save_figure(plot_mode_shapes_3d(m, n=N_DRAW), path)
        s["figure"] = str(path)
    if args.json:
        print(json_report(s))
        return 0
    print(f"frame {s['frame']} (3D): {s['n_nodes']} nodes, {s['n_dof']} dofs")
    nd = s["n_diaphragms"]
    print(f"  {nd} rigid diaphragm{'s' * (nd != 1)}: {s['n_dof_after_diaphragms']} dofs after them")
    print("fixed-base modes (effective-mass fractions in x, y and rotation θz):")
    print("   #   f [Hz]   family      m_x    m_y    J_θ   zeta")
    for k, (fk, fam) in enumerate(zip(s["frequencies_hz"], s["families"], strict=True)):
        fx, fy, ft = m.mass_fraction[k]
        z = s["damping_ratios"][k]
        print(f"  {k + 1:2d}  {fk:7.4g}   {fam:9s} {fx:6.3f} {fy:6.3f} {ft:6.3f}  {z:.3f}")
    print(f"total mass M_s = {s['total_mass_kg']:.4g} kg at x, y = {m.centre.round(3).tolist()} m")
    if "figure" in s:
        print(f"mode shapes: {s['figure']}")
    return 0
