"""Bonded vs tensionless vs fixed base over many simulated earthquakes (distributions).

Runs ``compare_foundations`` on a local process pool (any ``concurrent.futures.Executor``
works) and prints median and 5–95 % range of the peak responses per foundation case.
Run: ``python examples/cylinder_compare.py [N] [--no-figure]`` (N earthquakes, 100 by default;
the figure examples/figures/cylinder-compare.png is redrawn unless ``--no-figure``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from nsdyn.atomic import save_figure
from nsdyn.models.cylinder import CylinderParams, compare_foundations
from nsdyn.models.cylinder.figures import comparison_figure

FIGURE = Path(__file__).parent / "figures" / "cylinder-compare.png"


def main(n: int = 100, figure: bool = False) -> dict:
    """{case: {metric: {median, p5, ..., p95}}} over ``n`` earthquakes (seeds 0 .. n−1)."""
    out = compare_foundations(n, CylinderParams())
    if figure:
        fig = comparison_figure(out["stats"], title=f"peaks over {n} simulated earthquakes")
        save_figure(fig, FIGURE)
    return out["stats"]


if __name__ == "__main__":
    cli = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    cli.add_argument("n", nargs="?", type=int, default=100, help="earthquakes (100)")
    cli.add_argument("--no-figure", action="store_true", help=f"do not redraw {FIGURE.name}")
    args = cli.parse_args()
    if args.n < 1:
        cli.error(f"n: expected a positive number of earthquakes, got {args.n}")
    st = main(args.n, figure=not args.no_figure)
    for case, s in st.items():
        print(
            case,
            {
                m: f"{v['median']:.4g} [{v['p5']:.3g}, {v['p95']:.3g}]"
                for m, v in s.items()
                if isinstance(v, dict)
            },
        )
