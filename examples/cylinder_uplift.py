"""Rigid cylinder on a Winkler foundation: design, statics and one simulated earthquake.

Designs k and c for 3 Hz rocking at 10 % damping (H = 4 m, r = 1 m, m = 1 kg), gives the
static settlement and the uplift onset, and runs the tensionless, bonded and fixed-base cases
under one three-component simulated earthquake. Run: ``python examples/cylinder_uplift.py``.

Writes the figure examples/figures/cylinder-uplift.png (the tensionless case's motion under
earthquake seed 1, the committed figure the docs embed), replacing it, and prints its path
(``--out DIR``: into DIR instead).
"""

from __future__ import annotations

from pathlib import Path

from nsdyn.atomic import save_figure
from nsdyn.models.cylinder import (
    CylinderParams,
    design_foundation,
    earthquake,
    simulate,
    static_settlement,
    uplift_onset,
)
from nsdyn.models.cylinder.figures import motion_figure
from nsdyn.models.cylinder.stresses import peak_stresses

FIGURE = Path(__file__).parent / "figures" / "cylinder-uplift.png"


def main(seed: int = 1, duration: float = 20.0, figure: bool = False) -> dict:
    """Numbers of the example: design, statics, peak responses per foundation case."""
    k, c = design_foundation(3.0, 0.10, r=1.0, H=4.0, m=1.0)
    p = CylinderParams(r=1.0, H=4.0, m=1.0, k=k, c=c)
    th_u, M_u = uplift_onset(p)
    out = {"k": k, "c": c, "settlement": static_settlement(p), "theta_u": th_u, "M_u": M_u}
    dt, ag = earthquake(seed, duration)
    for case in ("tensionless", "bonded", "fixed"):
        res = simulate(p.with_(foundation=case), ag, dt)
        out[case] = {
            "tilt": float(res.tilt.max()),
            "uplift": float(1 - res.contact_fraction.min()),
            **peak_stresses(res),
        }
        if figure and case == "tensionless":
            save_figure(motion_figure(res, title=f"tensionless, earthquake seed {seed}"), FIGURE)
    return out


if __name__ == "__main__":
    from nsdyn.cli.args import figure_script

    FIGURE = figure_script(__doc__, FIGURE)
    r = main(figure=True)
    print(f"figure: {FIGURE}")
    print(f"k = {r['k']:.1f} N/m3, c = {r['c']:.2f} N s/m3, settlement {r['settlement']:.3e} m")
    print(f"uplift onset: tilt {r['theta_u']:.3e} rad, moment {r['M_u']:.4f} N m (mgr/4)")
    for case in ("tensionless", "bonded", "fixed"):
        v = r[case]
        print(
            f"{case:12s} tilt {v['tilt']:.4f} uplift {v['uplift']:.2f} "
            f"tau_max {v['tau_max']:.3f} sigma_1 {v['sigma_1']:.3f} sigma_3 {v['sigma_3']:.3f}"
        )
