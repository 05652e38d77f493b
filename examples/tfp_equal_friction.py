"""A triple friction pendulum with four equal friction coefficients against its single pendulum.

With μ1 = μ2 = μ3 = μ4 the TFP's series model (nsdyn.models.isolated.tfp) is, in the
rigid-plastic limit, the single friction pendulum of radius R1 + R4: every element yields at
the same force and their slips stay proportional, s_k = R̄_k p. The model reaches that limit
through an elastic stage (one spring κ_e N, κ_e = μ/u_y, with a dashpot of ratio ζ_e across
it: undamped, ζ_e = 0, and the default ζ_e = 1 are both run) and a viscoplastic flow of
relaxation time τ ∝ u_y, so its peaks converge as u_y → 0 (as a trend, not at every halving:
the velocity errors of successive breakaways add with signs of their own). This script
measures how: a
2 000 t mass on one bearing (R1 = R4 = 2.2 m, R2 = R3 = 0.3 m, μ = 0.05) under the bundled
record ``synthetic-wn-40s`` (all three components, and its x component alone), the TFP
(regularised law, Radau IIA) at u_y = 0.25 (the default), 0.125, 0.05 and 0.025 mm against
the single pendulum R = 4.4 m under the switch law (true stick). Each row: the peak slip and
its relative gap, and √(μ g u_y), the speed at which the undamped elastic stage's stored
energy puts the mass when it starts to slide (the single pendulum always starts from rest).

    python examples/tfp_equal_friction.py
"""

from __future__ import annotations

import math

import numpy as np

from nsdyn.ground import read_motion3
from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.deck import sdof_plane, simulate_plane
from nsdyn.models.isolated.tfp import TripleBearing

MU, MASS, G = 0.05, 2.0e6, 9.81
GEOMETRY = dict(R1=2.2, R2=0.3, R3=0.3, R4=2.2, d1=0.40, d2=0.06, d3=0.06, d4=0.40)
U_Y = (2.5e-4, 1.25e-4, 5e-5, 2.5e-5)
ZETA_E = (0.0, 1.0)


def ground(components: str):
    """The record as raw arrays (t0, dt, a_x, a_y, a_z) with ``components`` kept."""
    rec = read_motion3("synthetic-wn-40s")
    zero = np.zeros(rec.n)
    pick = {c: np.array(getattr(rec, f"a{c}")) if c in components else zero for c in "xy"}
    az = np.array(rec.az) if "z" in components and rec.az is not None else None
    return rec.t0, rec.dt, pick["x"], pick["y"], az


def peak(bearing, motion, law: str) -> float:
    r = simulate_plane(sdof_plane(MASS, bearing), motion, law=law)
    return float(r.summary()["peak_resultant_displacement_m"])


def main(u_ys=U_Y, components=("xyz", "x"), zetas=ZETA_E) -> list[dict]:
    rows = []
    for comp in components:
        motion = ground(comp)
        ref = peak(Bearing(Friction(MU), radius=GEOMETRY["R1"] + GEOMETRY["R4"]), motion, "switch")
        for zeta in zetas:
            for u_y in u_ys:
                tfp = TripleBearing(**GEOMETRY, mu1=MU, mu2=MU, mu3=MU, mu4=MU, u_y=u_y,
                                    zeta_e=zeta)  # fmt: skip
                p = peak(tfp, motion, "arctan")
                rows.append({"components": comp, "zeta_e": zeta, "u_y_mm": u_y * 1e3,
                             "sfp_peak_m": ref, "tfp_peak_m": p, "gap": p / ref - 1.0,
                             "onset_speed_mps": math.sqrt(MU * G * u_y)})  # fmt: skip
    print("| components | ζ_e | u_y [mm] | SFP peak [m] | TFP peak [m] | gap | √(μ g u_y) [m/s] |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['components']} | {r['zeta_e']:g} | {r['u_y_mm']:g} | {r['sfp_peak_m']:.4f} | "
              f"{r['tfp_peak_m']:.4f} | {100 * r['gap']:+.2f} % | "
              f"{r['onset_speed_mps']:.4f} |")  # fmt: skip
    return rows


if __name__ == "__main__":
    import argparse

    argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    ).parse_args()  # --help; no options
    main()
