"""Command line: ``nsdyn SUBCOMMAND ...``.

Each subcommand is two functions, ``configure(parser)`` adding its arguments and
``run(args) -> int`` doing the work, registered in :data:`COMMANDS`. To add one, write the
pair and add a :class:`Command` entry; :func:`main` builds the parser from the table.

Errors the user can fix (bad frame file, unwritable output directory) print one line to
stderr and exit with status 2; no traceback.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from nsdyn.atomic import atomic_open, save_figure
from nsdyn.frame import FrameFileError, base_isolation_frequency, load_frame

__all__ = ["COMMANDS", "Command", "build_parser", "main"]

DEFAULT_OUT = "nsdyn-out"  # directory for figures
DEFAULT_FMAX = 5.0  # Hz, Craig–Bampton cut-off (seed 004)
DEFAULT_KLAM = 5.0e4  # N/m, laminated-bearing lateral stiffness (seed 004 eq. 16)
N_LIST = 10  # fixed-base modes listed by `modes`
N_DRAW = 4  # mode shapes drawn by `modes`
EXIT_USER_ERROR = 2  # bad input the user can fix (same as argparse usage errors)
EXIT_NUMERICS = 3  # the numerics failed (step underflow, Newton divergence, uplift, ...)
USER_ERRORS: tuple[type[BaseException], ...] = (FrameFileError, OSError)


def _user_errors() -> tuple[type[BaseException], ...]:
    from nsdyn.records import RecordFileError
    from nsdyn.scene import SceneError

    return (*USER_ERRORS, SceneError, RecordFileError)


def _numerics_errors() -> tuple[type[BaseException], ...]:
    from nsdyn.integrate import IntegrationError, UpliftError

    return (IntegrationError, UpliftError)


@dataclass(frozen=True)
class Command:
    """A subcommand: one-line help, argument set-up, and the function that runs it."""

    help: str
    configure: Callable[[argparse.ArgumentParser], None]
    run: Callable[[argparse.Namespace], int]


def _positive_float(s: str) -> float:
    try:
        v = float(s)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {s!r}") from None
    if not v > 0:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {s!r}")
    return v


# --------------------------------------------------------------------------- modes


def configure_modes(p: argparse.ArgumentParser) -> None:
    p.add_argument("frame", help="bundled frame name (e.g. office-11) or path to a .toml file")
    p.add_argument(
        "--fmax",
        type=_positive_float,
        default=DEFAULT_FMAX,
        metavar="HZ",
        help=f"Craig–Bampton cut-off frequency (default {DEFAULT_FMAX:g}; 'inf' keeps all)",
    )
    p.add_argument(
        "--klam",
        type=_positive_float,
        default=DEFAULT_KLAM,
        metavar="N_PER_M",
        help=f"lateral stiffness of one laminated bearing for f_bis (default {DEFAULT_KLAM:g})",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object and nothing else")
    p.add_argument(
        "--out",
        metavar="DIR",
        default=None,
        help=f"directory for the mode-shape PNG (default {DEFAULT_OUT}/; with --json, none)",
    )


def modes_summary(frame, f_max: float, k_lam: float) -> tuple[dict, np.ndarray, np.ndarray]:
    """Numbers reported by ``nsdyn modes`` plus the listed frequencies and shapes."""
    from nsdyn.reduction import damping_ratios, fixed_base_modes, mode_type, reduce_frame

    K, M = frame.assemble()
    f, Phi = fixed_base_modes(K, M, frame.boundary_dofs, n_modes=N_LIST)
    cb = reduce_frame(frame, f_max)
    summary = {
        "frame": frame.name,
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


def run_modes(args: argparse.Namespace) -> int:
    frame = load_frame(args.frame)
    s, f, Phi = modes_summary(frame, args.fmax, args.klam)
    out = args.out if args.out is not None else (None if args.json else DEFAULT_OUT)
    if out is not None:
        from nsdyn.plot import plot_mode_shapes

        path = Path(out) / f"modes-{frame.name}.png"
        save_figure(plot_mode_shapes(frame, f, Phi, n=N_DRAW), path)
        s["figure"] = str(path)
    if args.json:
        print(json.dumps(s))
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
        print(f"  {k + 1:2d}  {fk:7.3f}   {t:8s}  {z:.3f}")
    print(f"total mass M_s = {s['total_mass_kg']:.4g} kg")
    print(f"f_bis = sqrt({len(frame.base_nodes)} K_lam / M_s) / 2pi = {s['f_bis_hz']:.4f} Hz")
    print(f"  (K_lam = {s['k_lam_n_per_m']:g} N/m)")
    if "figure" in s:
        print(f"mode shapes: {s['figure']}")
    return 0


# --------------------------------------------------------------------------- run


def configure_run(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "scene", nargs="?", default=None, help="scene TOML (default: the bundled default scene)"
    )
    p.add_argument("--frame", help="bundled frame name or frame TOML path")
    p.add_argument("--record", help="bundled record name or path to a ground-motion file")
    p.add_argument("--pga", type=_positive_float, metavar="MPS2", help="scale to this PGA")
    p.add_argument("--fixed-base", action="store_true", help="the fixed-base linear frame")
    p.add_argument(
        "--fidelity",
        choices=["fixed", "rigid", "cb", "full", "auto"],
        help="model fidelity; 'auto' asks the model advisor and prints its choice and evidence",
    )
    p.add_argument("--fmax", type=_positive_float, metavar="HZ", help="Craig–Bampton cut-off")
    p.add_argument("--friction", choices=["arctan", "switch", "none"], help="friction law")
    p.add_argument("--method", help="integrator: radau, dopri5, genalpha, hht, event")
    p.add_argument("--t-end", type=_positive_float, metavar="S", help="stop at this time")
    p.add_argument("--out", default=DEFAULT_OUT, metavar="DIR", help="output directory")
    p.add_argument("--json", action="store_true", help="print one JSON object and nothing else")
    p.add_argument("--no-figures", action="store_true", help="skip the PNG figures")
    p.add_argument(
        "--resume", action="store_true", help="continue an interrupted run from its checkpoint"
    )


def _scene_overrides(args: argparse.Namespace) -> dict:
    o: dict = {}
    if args.frame:
        o.setdefault("scene", {})["frame"] = args.frame
    if args.fidelity and args.fidelity != "auto":
        o.setdefault("scene", {})["fidelity"] = args.fidelity
    if args.fixed_base:
        o.setdefault("scene", {})["fidelity"] = "fixed"
    if args.fmax:
        o.setdefault("scene", {})["f_max"] = args.fmax
    if args.record:
        o.setdefault("motion", {})["record"] = args.record
    if args.pga:
        o.setdefault("motion", {})["pga"] = args.pga
    if args.t_end:
        o.setdefault("motion", {})["t_end"] = args.t_end
    if args.method:
        o.setdefault("solver", {})["method"] = args.method
    return o


def run_run(args: argparse.Namespace) -> int:
    from nsdyn.scene import build_scene, load_scene
    from nsdyn.transient import output_grid, simulate

    cfg = load_scene(args.scene, _scene_overrides(args))
    if args.friction:
        cfg.setdefault("isolation", {})["law"] = args.friction
    system, motion = build_scene(cfg)
    if args.fidelity == "auto":
        from nsdyn.advisor import advise
        from nsdyn.system import build_system

        advice = advise(system.frame, motion, isolation=system.isolation)
        print(advice.report(), file=sys.stderr)
        system = build_system(
            system.frame,
            system.isolation,
            fidelity=advice.fidelity,
            f_max=advice.f_max or 5.0,
        )
    sv = cfg["solver"]
    method = sv.get("method", "radau")
    if method == "event" and system.isolation is not None:
        system = system.with_isolation(law="switch")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    stem = "run"
    ckpt = out / f".{stem}-checkpoint.npz"
    if not args.resume:
        ckpt.unlink(missing_ok=True)
    quiet = args.json

    def progress(t, t_end, wall):
        if not quiet and wall > 1.0:
            print(f"  t = {t:7.2f} / {t_end:.2f} s   ({wall:5.1f} s)", file=sys.stderr)

    res = simulate(
        system,
        motion,
        method=method,
        rtol=sv["rtol"],
        atol=tuple(sv["atol"]) if isinstance(sv.get("atol"), list) else sv.get("atol"),
        dt=sv.get("dt"),
        t_eval=output_grid(motion, sv.get("dt_out")),
        uplift=sv.get("uplift", "raise"),
        progress=progress,
        checkpoint=ckpt,
    )
    ckpt.unlink(missing_ok=True)
    s = res.summary()
    s["record"] = motion.name
    s["pga_mps2"] = float(motion.pga)
    hist = out / f"{stem}-histories.npz"
    with atomic_open(hist, "wb") as fh:
        np.savez(
            fh,
            t=res.t,
            x=res.x,
            x_iso=res.response.x_iso,
            top_drift=res.response.top_drift,
            normal_forces=res.response.lam,
            friction_forces=res.response.tau,
        )
    s["histories"] = str(hist)
    if not args.no_figures:
        from nsdyn.plot import plot_transient

        fig_path = out / f"{stem}.png"
        save_figure(plot_transient(res), fig_path)
        s["figure"] = str(fig_path)
    if args.json:
        print(json.dumps(s))
        return 0
    print(f"model   {s['model']}   record {s['record']} (PGA {s['pga_mps2']:.2f} m/s²)")
    print(f"method  {s['method']}: {s['n_steps']} steps, run {s['wall_s']:.3f} s", end="")
    print(f" (+ JIT compile/load {s['compile_s']:.1f} s)")
    rows = [
        ("peak isolator displacement x_iso", f"{s['x_iso_max_m']:.4f} m"),
        ("peak interstorey drift ratio", f"{s['idr_max']:.3e}"),
        ("peak absolute floor acceleration", f"{s['floor_acc_max_mps2']:.3f} m/s²"),
        ("peak roof drift x_top - x_iso", f"{s['roof_drift_max_m']:.4f} m"),
        ("minimum normal force", f"{s['min_normal_force_N']:.4g} N"),
        ("share of time all isolators stick", f"{s['stick_fraction']:.2f}"),
        ("energy balance closure error", f"{s['energy_closure']:.2e}"),
        ("uplift", "none" if not s["uplift"] else str(s["uplift"])),
    ]
    for k, v in rows:
        print(f"  {k:36s} {v}")
    print(f"histories: {hist}")
    if "figure" in s:
        print(f"figure:    {s['figure']}")
    return 0


# --------------------------------------------------------------------------- table

COMMANDS: dict[str, Command] = {
    "modes": Command(
        help="fixed-base modes, dof counts (full and Craig–Bampton), mass and f_bis",
        configure=configure_modes,
        run=run_modes,
    ),
    "sweep": Command(
        help="frequency-amplitude diagrams of periodic solutions (shooting + continuation)",
        configure=lambda p: _lazy("nsdyn.sweep").configure(p),
        run=lambda a: _lazy("nsdyn.sweep").run(a),
    ),
    "bench": Command(
        help="work-precision, fidelity and stability benchmarks (speed against accuracy)",
        configure=lambda p: _lazy("nsdyn.bench").configure(p),
        run=lambda a: _lazy("nsdyn.bench").run(a),
    ),
    "run": Command(
        help="transient earthquake run of a scene (default: office-11 isolated, synthetic record)",
        configure=configure_run,
        run=run_run,
    ),
}


def _lazy(module: str):
    import importlib

    return importlib.import_module(module)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="nsdyn", description="Non-smooth dynamics of friction base-isolated frames."
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, cmd in COMMANDS.items():
        p = sub.add_parser(name, help=cmd.help, description=cmd.help)
        cmd.configure(p)
        p.set_defaults(_run=cmd.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``nsdyn`` script; returns the exit status."""
    args = build_parser().parse_args(argv)
    try:
        return int(args._run(args))
    except _user_errors() as exc:
        print(f"nsdyn {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_USER_ERROR
    except _numerics_errors() as exc:
        print(f"nsdyn {args.command}: numerical failure: {exc}", file=sys.stderr)
        return EXIT_NUMERICS


if __name__ == "__main__":
    sys.exit(main())
