"""Where does uplift start? The uplift boundary A*(f) of the office frame on its isolators.

The bundled default scene (office-11, Craig-Bampton at 5 Hz, seed isolators, arctan friction)
under u''_hor = A sin(2 pi f t): for each frequency the smallest A at which the steady orbit's
smallest isolator normal force reaches zero (nsdyn.periodic.uplift), with the search cost per
frequency (median wall time and shooting solves), the rigid-frame overturning threshold
g b / h_cm for comparison, and the figure ``uplift_boundary.png``.

    python examples/uplift_boundary.py                # redraws examples/figures/uplift_boundary.png
    python examples/uplift_boundary.py --points 20    # a quicker, coarser boundary: nsdyn-out/
    python examples/uplift_boundary.py --out DIR      # the figure into DIR

The default run (40 points) redraws the committed examples/figures/uplift_boundary.png; any
other ``--points`` (2 to 400, about a second each, more at the lowest frequencies) without
``--out`` writes the figure to ``nsdyn-out/`` in the current directory and leaves the
committed one alone. The script
prints where the figure went.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from nsdyn.cli.args import int_in, out_dir
from nsdyn.models.isolated.scene import build_scene, load_scene
from nsdyn.periodic import log_frequencies
from nsdyn.periodic.uplift import uplift_boundary
from nsdyn.plot.uplift import uplift_boundary_figure

FIGURE = Path(__file__).resolve().parent / "figures" / "uplift_boundary.png"
POINTS_DEFAULT = 40  # the committed figure's frequencies
POINTS_MAX = 400  # about 1 s per frequency (2 s at the lowest): 400 take several minutes
SCRATCH = "nsdyn-out"  # a non-default run's figure, in the current directory


def overturning_threshold(frame, g: float) -> float:
    """g b / h_cm of the frame as a rigid body on two supports: b half the support spacing,
    h_cm the centre of mass above the support plane (members + added masses)."""
    nodes, el = np.asarray(frame.nodes), np.asarray(frame.elements)
    length = np.linalg.norm(nodes[el[:, 1]] - nodes[el[:, 0]], axis=1)
    m_el = np.asarray(frame.rho_A) * length
    y_el = 0.5 * (nodes[el[:, 0], 1] + nodes[el[:, 1], 1])
    m_node = np.asarray(frame.node_mass)
    base = np.asarray(frame.base_nodes)
    h_cm = (m_el @ y_el + m_node @ nodes[:, 1]) / (m_el.sum() + m_node.sum())
    h_cm -= nodes[base, 1].mean()
    b = 0.5 * np.ptp(nodes[base, 0])
    return g * b / h_cm


def main(
    points: int = POINTS_DEFAULT, fmin: float = 0.01, fmax: float = 1.0, figure=FIGURE
) -> dict:
    system, _ = build_scene(load_scene(None))
    freqs = log_frequencies(fmin, fmax, points)
    res = uplift_boundary(system, freqs)
    if figure is not None:
        uplift_boundary_figure(res, figure)
    walls = np.array([p.wall_s for p in res.points])
    shots = np.array([p.shootings for p in res.points])
    a_rigid = overturning_threshold(system.frame, system.isolation.g)
    ok = res.ok
    i_min = int(np.nanargmin(np.where(ok, res.a_crit, np.nan))) if ok.any() else None
    out = {
        "model": res.model,
        "static_min_normal_force_N": res.static_force,
        "rigid_overturning_threshold": a_rigid,
        "points": [p.to_dict() for p in res.points],
        "ok": int(ok.sum()),
        "no_uplift": int(sum(s.startswith("no uplift") for s in res.status)),
        "failed": int((~ok).sum() - sum(s.startswith("no uplift") for s in res.status)),
        "lowest": None if i_min is None else (float(res.f[i_min]), float(res.a_crit[i_min])),
        "highest_f_with_uplift": float(res.f[ok].max()) if ok.any() else None,
        "median_wall_s": float(np.median(walls)),
        "median_shootings": float(np.median(shots)),
        "total_wall_s": float(walls.sum()),
        "figure": None if figure is None else str(figure),
    }
    print(f"{res.model}: min static normal force {res.static_force / 1e3:.0f} kN")
    print(f"rigid frame on two supports: g b / h_cm = {a_rigid:.3f} m/s²")
    print("   f [Hz]  A* [m/s²]  shootings  wall [s]  status")
    for p in res.points:
        a = f"{p.a_crit:9.3f}" if p.ok else "        -"
        print(f"{p.f:9.4f}  {a}  {p.shootings:9d}  {p.wall_s:8.2f}  {p.status}")
    if out["lowest"]:
        print(f"lowest A* = {out['lowest'][1]:.3f} m/s² at f = {out['lowest'][0]:.4f} Hz")
        print(f"highest frequency with uplift below 20 m/s²: {out['highest_f_with_uplift']:.3f} Hz")
    print(
        f"{out['ok']} found, {out['no_uplift']} without uplift, {out['failed']} failed; per "
        f"frequency: median {out['median_wall_s']:.2f} s, median {out['median_shootings']:.0f} "
        f"shootings; total {out['total_wall_s']:.1f} s"
    )
    if figure is not None:
        print(f"figure: {figure}")
    return out


if __name__ == "__main__":
    cli = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    points = int_in(2, POINTS_MAX, "frequencies (about a second each)")
    cli.add_argument("--points", type=points, default=POINTS_DEFAULT,
                     help=f"log-spaced frequencies, 2 to {POINTS_MAX} (40)")  # fmt: skip
    cli.add_argument("--out", type=out_dir, metavar="DIR",
                     help=f"write {FIGURE.name} into DIR (default: examples/figures for "
                     f"{POINTS_DEFAULT} points, else {SCRATCH}/)")  # fmt: skip
    args = cli.parse_args()
    if args.out is not None:
        path = Path(args.out) / FIGURE.name
    else:  # only the default run replaces the committed figure
        path = FIGURE if args.points == POINTS_DEFAULT else Path(SCRATCH) / FIGURE.name
    print(f"{args.points} frequencies, about a second each ...", file=sys.stderr)
    main(points=args.points, figure=path)
