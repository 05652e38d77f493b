"""Design of the Winkler foundation and its static quantities.

Small rocking about the base centre (vertical motion and rolling frozen, bonded or not yet
lifted) obeys  (I_t + mH²) θ̈ + c I_b θ̇ + (k I_b − mgH) θ = 0,  I_b = πr⁴/4, so for a target
rocking frequency f [Hz] and damping ratio ζ:

    k = [(2πf)² (I_t + mH²) + mgH] / I_b,     c = 2ζ √((I_t + mH²)(k I_b − mgH)) / I_b.

Static settlement δ_st = mg/(πr²k). A tensionless base starts to lift when the compression at
the upper rim vanishes: tilt θ_u with r sin θ_u = δ_st, moment M_u = k I_b sin θ_u = mg r/4
(the resultant reaches the kern of the circle, r/4).
"""

from __future__ import annotations

import math

from nsdyn.models.cylinder.params import G_STD, CylinderParams


def design_foundation(
    f_rock: float,
    zeta: float,
    r: float,
    H: float,
    m: float,
    *,
    I_t: float | None = None,
    g: float = G_STD,
) -> tuple[float, float]:
    """(k, c) per unit area giving rocking frequency ``f_rock`` [Hz] and damping ratio ``zeta``."""
    if not f_rock > 0:
        raise ValueError(f"f_rock: expected a positive frequency [Hz], got {f_rock!r}")
    if not zeta >= 0:
        raise ValueError(f"zeta: expected a non-negative damping ratio, got {zeta!r}")
    p = CylinderParams(r=r, H=H, m=m, I_t=I_t, g=g)  # checks r, H, m
    J = p.It + m * H**2
    Ib = p.I_base
    w = 2.0 * math.pi * f_rock
    k = (w * w * J + m * g * H) / Ib
    c = 2.0 * zeta * math.sqrt(J * (k * Ib - m * g * H)) / Ib
    return k, c


def rocking_frequency(p: CylinderParams) -> tuple[float, float]:
    """(f [Hz], ζ) of small rocking about the base centre; raises if statically unstable."""
    J = p.It + p.m * p.H**2
    kr = p.k * p.I_base - p.m * p.g * p.H
    if kr <= 0:
        raise ValueError(f"k: k·πr⁴/4 = {p.k * p.I_base:g} must exceed mgH = {p.m * p.g * p.H:g}")
    return math.sqrt(kr / J) / (2 * math.pi), p.c * p.I_base / (2.0 * math.sqrt(kr * J))


def static_settlement(p: CylinderParams) -> float:
    """Static compression mg/(πr²k) [m] (base-centre height is its negative)."""
    return p.m * p.g / (p.area * p.k)


def uplift_onset(p: CylinderParams) -> tuple[float, float]:
    """(θ_u [rad], M_u [N m]): tilt and foundation moment when the upper rim starts to lift."""
    s = static_settlement(p) / p.r
    if s >= 1.0:
        raise ValueError("k: settlement exceeds r; the foundation is too soft")
    return math.asin(s), p.k * p.I_base * s
