"""Bonded vs tensionless vs fixed base over many simulated earthquakes (distributions).

Runs ``compare_foundations`` on a local process pool (any ``concurrent.futures.Executor``
works) and prints median and 5–95 % range of the peak responses per foundation case.
Run: ``python examples/cylinder_compare.py [N]``.
"""

from __future__ import annotations

import sys
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
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100
    st = main(n, figure=True)
    for case, s in st.items():
        print(
            case,
            {
                m: f"{v['median']:.4g} [{v['p5']:.3g}, {v['p95']:.3g}]"
                for m, v in s.items()
                if isinstance(v, dict)
            },
        )
