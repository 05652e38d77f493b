"""``nsdyn modes``: fixed-base modes, dof counts, total mass and f_bis of a frame."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from nsdyn.atomic import save_figure
from nsdyn.cli.args import positive_finite as _positive_finite
from nsdyn.cli.args import positive_float as _positive_float
from nsdyn.models.isolated.defaults import F_MAX as DEFAULT_FMAX
from nsdyn.models.isolated.defaults import K_LAM as DEFAULT_KLAM
from nsdyn.structure import base_isolation_frequency, load_frame

DEFAULT_OUT = "nsdyn-out"  # directory for figures
N_LIST = 10  # fixed-base modes listed by `modes`
N_DRAW = 4  # mode shapes drawn by `modes`


def configure(p: argparse.ArgumentParser) -> None:
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
        type=_positive_finite,
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
    from nsdyn.structure import damping_ratios, fixed_base_modes, mode_type, reduce_frame

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


def run(args: argparse.Namespace) -> int:
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
