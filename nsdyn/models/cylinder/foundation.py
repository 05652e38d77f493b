"""Winkler foundation resultants (closed forms of ``_kfound``) and the static moment–tilt curve.

For a base tilted by θ (g = (sin θ, 0) in base axes) and at height w, the tensionless
foundation pushes with p = k(−w − sinθ·a)₊; vertical equilibrium ∫p = mg fixes w(θ), and the
overturning resistance is M(θ) = ∫ a p dA. Bonded: M = k πr⁴/4 sin θ for every θ; tensionless:
the same up to uplift onset (sin θ_u = δ_st/r, M_u = mgr/4), softening after it towards mgr
(the whole weight on the rim) as θ grows.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from nsdyn.models.cylinder import _kfound
from nsdyn.models.cylinder.params import CylinderParams

KIND_NAMES = ("lifted", "partial", "full")  # contact kinds 0, 1, 2
Pair = tuple[float, float]


def segment_integrals(d: float, r: float) -> tuple[float, float, float, float]:
    """(A, S_u, I_uu, I_vv) of the part u > d of the disc of radius r (u along a diameter)."""
    out = np.empty(4)
    _kfound.segment_integrals(float(d), float(r), out)
    return tuple(float(v) for v in out)


def _kernel_args(
    w: float,
    g: Pair,
    wd: float,
    gd: Pair,
    *,
    r: float,
    k: float,
    c: float = 0.0,
    bonded: bool = False,
) -> tuple:
    """(z, r, k, c, bonded) for ``_kfound``: base state z = (w, g_a, g_b, ẇ, ġ_a, ġ_b), disc
    radius, stiffness and damping per area, bonded (else tensionless)."""
    z = np.array([w, g[0], g[1], wd, gd[0], gd[1]], dtype=float)
    return z, float(r), float(k), float(c), bool(bonded)


def resultants(w: float, g: Pair, wd: float = 0.0, gd: Pair = (0.0, 0.0), **foundation) -> dict:
    """Foundation force, base-axis moments m = ∫ρ p dA, contact area, stored energy, dissipation.

    ``g`` = (e₁·e_z, e₂·e_z): world-vertical components of the base axes; ``gd`` their rates;
    ``foundation``: the keywords ``r``, ``k`` (required), ``c`` (0) and ``bonded`` (False).
    """
    out = np.empty(6)
    kind = _kfound.resultants(*_kernel_args(w, g, wd, gd, **foundation), out)
    return {
        "F": float(out[0]),
        "m": (float(out[1]), float(out[2])),
        "area": float(out[3]),
        "V": float(out[4]),
        "D": float(out[5]),
        "contact": KIND_NAMES[kind],
    }


def jacobian(w: float, g: Pair, wd: float = 0.0, gd: Pair = (0.0, 0.0), **foundation) -> np.ndarray:
    """∂(F, m_a, m_b)/∂(w, g_a, g_b, ẇ, ġ_a, ġ_b), shape (3, 6), analytic (arguments as for
    :func:`resultants`)."""
    jac = np.empty((3, 6))
    _kfound.resultants_jac(*_kernel_args(w, g, wd, gd, **foundation), jac)
    return jac


def static_moment_tilt(p: CylinderParams, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(M, w): foundation moment about the base centre and base-centre height at tilt θ,
    with the vertical force equal to the weight (static, damping-free).

    theta : (n,) tilts in [0, π/2).
    """
    theta = np.atleast_1d(np.asarray(theta, float))
    bonded = p.foundation == "bonded"
    W = p.m * p.g
    Ms = np.empty_like(theta)
    ws = np.empty_like(theta)
    for i, th in enumerate(theta):
        s = float(np.sin(th))

        def excess(w, s=s):
            return resultants(w, (s, 0.0), r=p.r, k=p.k, bonded=bonded)["F"] - W

        lo = -W / (p.k * p.area) - s * p.r - p.r  # full contact, F > W
        hi = s * p.r  # lifted off, F = 0 < W
        w = brentq(excess, lo, hi, xtol=1e-15 * p.r, rtol=1e-14)
        # moment about the base centre: (m_a e1 + m_b e2) × e_z, with e1 = (cos θ, 0, sin θ)
        ma = resultants(w, (s, 0.0), r=p.r, k=p.k, bonded=bonded)["m"][0]
        Ms[i] = -ma * np.cos(th)
        ws[i] = w
    return Ms, ws
