"""Bonded vs tensionless vs fixed base over many simulated earthquakes (distributions).

Runs ``compare_foundations`` on a local process pool (any ``concurrent.futures.Executor``
works) and prints median and 5–95 % range of the peak responses per foundation case.
Run: ``python examples/cylinder_compare.py [N] [--out DIR] [--no-figure]`` (N earthquakes,
100 by default, at most 1000: ~0.1 s each on one CPU). The figure ``cylinder-compare.png`` is
drawn unless ``--no-figure``: into ``DIR`` with ``--out``; else the default run (N = 100)
redraws the committed examples/figures/cylinder-compare.png, and any other N writes to
``nsdyn-out/`` in the current directory (the committed figure is left alone); the script
prints where the figure went.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from nsdyn.atomic import save_figure
from nsdyn.cli.args import int_in, out_dir
from nsdyn.models.cylinder import CylinderParams, compare_foundations
from nsdyn.models.cylinder.figures import comparison_figure

FIGURE = Path(__file__).parent / "figures" / "cylinder-compare.png"
N_DEFAULT = 100  # the committed figure's earthquakes
N_MAX = 1000  # ~0.1 s per earthquake and CPU: 1000 take a minute or two on a small machine
SCRATCH = "nsdyn-out"  # a non-default run's figure, in the current directory


def main(n: int = N_DEFAULT, figure: bool = False, path: str | Path = FIGURE) -> dict:
    """{case: {metric: {median, p5, ..., p95}}} over ``n`` earthquakes (seeds 0 .. n−1); with
    ``figure``, the chart is saved to ``path``."""
    out = compare_foundations(n, CylinderParams())
    if figure:
        fig = comparison_figure(out["stats"], title=f"peaks over {n} simulated earthquakes")
        save_figure(fig, path)
    return out["stats"]


if __name__ == "__main__":
    cli = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    n_type = int_in(1, N_MAX, "earthquakes (~0.1 s each on one CPU)")
    cli.add_argument("n", nargs="?", type=n_type, default=N_DEFAULT,
                     help=f"earthquakes, 1 to {N_MAX} ({N_DEFAULT})")  # fmt: skip
    cli.add_argument("--out", type=out_dir, metavar="DIR",
                     help=f"write {FIGURE.name} into DIR (default: examples/figures for "
                     f"N = {N_DEFAULT}, else {SCRATCH}/)")  # fmt: skip
    cli.add_argument("--no-figure", action="store_true", help=f"do not draw {FIGURE.name}")
    args = cli.parse_args()
    if args.out is not None and args.no_figure:
        cli.error("--out: the figure's folder; drop --no-figure")
    if args.out is not None:
        path = Path(args.out) / FIGURE.name
    else:  # only the default run replaces the committed figure
        path = FIGURE if args.n == N_DEFAULT else Path(SCRATCH) / FIGURE.name
    print(f"{args.n} earthquakes on up to {os.cpu_count() or 1} processes ...", file=sys.stderr)
    st = main(args.n, figure=not args.no_figure, path=path)
    for case, s in st.items():
        print(
            case,
            {
                m: f"{v['median']:.4g} [{v['p5']:.3g}, {v['p95']:.3g}]"
                for m, v in s.items()
                if isinstance(v, dict)
            },
        )
    if not args.no_figure:
        print(f"figure: {path}")
