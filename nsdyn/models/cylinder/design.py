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

from nsdyn._checks import DOPRI5_REAL_AXIS, expect, number
from nsdyn.models.cylinder.params import G_STD, CylinderParams

_P = "CylinderParams (nsdyn.CylinderParams(...))"


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
    f_rock = number("f_rock", f_rock, "a positive finite frequency [Hz]", lambda v: v > 0)
    zeta = number(
        "zeta", zeta, "a damping ratio in [0, 1) (a fraction: 0.1 for 10 %)", lambda v: 0 <= v < 1
    )  # fmt: skip  (as a scene's foundation.zeta)
    p = CylinderParams(r=r, H=H, m=m, I_t=I_t, g=g)  # checks r, H, m
    J = p.It + m * H**2
    Ib = p.I_base
    w = 2.0 * math.pi * f_rock
    k = (w * w * J + m * g * H) / Ib
    c = 2.0 * zeta * math.sqrt(J * (k * Ib - m * g * H)) / Ib
    if not (math.isfinite(k) and math.isfinite(c)):
        raise ValueError(f"f_rock, r, H, m: a foundation of k = {k:g} N/m^3, c = {c:g} N s/m^3; "
                         "expected sizes and a frequency whose springs are finite")  # fmt: skip
    return k, c


def rocking_frequency(p: CylinderParams) -> tuple[float, float]:
    """(f [Hz], ζ) of small rocking about the base centre; raises if statically unstable."""
    expect("p", p, isinstance(p, CylinderParams), _P)
    J = p.It + p.m * p.H**2
    kr = p.k * p.I_base - p.m * p.g * p.H
    if kr <= 0:
        raise ValueError(f"k: k·πr⁴/4 = {p.k * p.I_base:g} must exceed mgH = {p.m * p.g * p.H:g}")
    return math.sqrt(kr / J) / (2 * math.pi), p.c * p.I_base / (2.0 * math.sqrt(kr * J))


def static_settlement(p: CylinderParams) -> float:
    """Static compression mg/(πr²k) [m] (base-centre height is its negative)."""
    expect("p", p, isinstance(p, CylinderParams), _P)
    return p.m * p.g / (p.area * p.k)


def too_soft(p: CylinderParams) -> str | None:
    """Why a foundation is too soft for the model (its base would settle deeper than its
    radius, never lifting), or None."""
    if static_settlement(p) < p.r:
        return None
    return (f"the static settlement m g / (pi r^2 k) = {static_settlement(p):.4g} m exceeds the "
            f"radius r = {p.r:g} m: the foundation is too soft (k > "
            f"{p.m * p.g / (p.area * p.r):.4g} N/m^3 needed)")  # fmt: skip


def uplift_onset(p: CylinderParams) -> tuple[float, float]:
    """(θ_u [rad], M_u [N m]): tilt and foundation moment when the upper rim starts to lift."""
    expect("p", p, isinstance(p, CylinderParams), _P)
    s = static_settlement(p) / p.r
    if s >= 1.0:
        raise ValueError(f"k: {too_soft(p)}")
    return math.asin(s), p.k * p.I_base * s


STEPS_NOTED = 1e6  # a run needing more steps than this (about a minute) is said beforehand


def too_stiff(p: CylinderParams, span: float) -> str | None:
    """Why a run of ``span`` [s] on this foundation will take long (the explicit method's steps
    bounded by the base's vertical mode, ω = sqrt(k π r² / m)), or None: a k far above the
    design's made a run of minutes with nothing on screen."""
    if p.foundation == "fixed":
        return None
    w = math.sqrt(p.k * p.area / p.m)
    steps = span * w / DOPRI5_REAL_AXIS
    if steps < STEPS_NOTED:
        return None
    return (f"foundation.k = {p.k:.4g} N/m^3 puts the base's vertical mode at "
            f"{w / (2 * math.pi):.3g} Hz: dopri5, stable only with steps below 3.3/ω, takes "
            f"of the order of {steps:.2g} steps over the {span:g} s run (minutes); a rigid "
            "base is foundation.case = 'fixed'")  # fmt: skip
