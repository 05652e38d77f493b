"""Numba kernel: closed-form Winkler resultants over the contact part of the base disc.

Base point ρ = (a, b) in body base axes (e₁, e₂); with gᵢ = eᵢ·e_z (world vertical component of
the base axes) and w the height of the base centre above the undeformed ground, the spring
compression is δ(ρ) = −w − g·ρ and its rate δ̇ = −ẇ − ġ·ρ. The traction p = kδ + cδ̇ is linear
in ρ, so every resultant is a combination of the area moments of the contact region C:

    A = ∫_C dA,  S = ∫_C ρ dA,  I = ∫_C ρρᵀ dA.

Tensionless: C = {δ > 0} ∩ disc. With s = |g|, n = −g/s (downhill), u = n·ρ, v = t·ρ, C is the
circular segment u > d, d = w/s (clipped to [−r, r]); with γ = arccos(d/r), h = √(r² − d²):

    A   = r²γ − d h,            S_u = (2/3) h³,
    I_uu = (r⁴/4)(γ − sin4γ/4),  I_vv = (2/3) r⁴ (3γ/8 − sin2γ/4 + sin4γ/32),

S = S_u n, I = I_uu nnᵀ + I_vv ttᵀ. Bonded: the whole disc (A = πr², S = 0, I = πr⁴/4 𝟙).
Resultants: F = ∫p = α₀A + α·S, m = ∫ρp = α₀S + Iα with α₀ = −(kw + cẇ), α = −(kg + cġ);
stored energy V = ½k∫δ², dissipation D = c∫δ̇².

Jacobian (Leibniz rule): the spring part vanishes on the chord, so ∂(F,m)/∂(w,g) = −k(A,S;S,I);
the damper part adds the chord term −(1/s)∮ p_c (1, ρ, ρρᵀ) ds over u = d, |v| ≤ h.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

TINY_TILT = 1e-300  # |g| below this counts as exactly upright (direction undefined)


@njit(cache=True, error_model="numpy")
def segment_integrals(d: float, r: float, out: np.ndarray) -> None:
    """out[:4] = (A, S_u, I_uu, I_vv) of the disc part u > d (d clipped to [−r, r])."""
    if d <= -r:
        out[0] = math.pi * r * r
        out[1] = 0.0
        out[2] = 0.25 * math.pi * r**4
        out[3] = out[2]
        return
    if d >= r:
        out[0] = 0.0
        out[1] = 0.0
        out[2] = 0.0
        out[3] = 0.0
        return
    h = math.sqrt(r * r - d * d)
    gam = math.acos(d / r)
    r2 = r * r
    s2 = 2.0 * h * d / r2  # sin 2γ
    c2 = (d * d - h * h) / r2  # cos 2γ
    s4 = 2.0 * s2 * c2  # sin 4γ
    out[0] = r2 * gam - d * h
    out[1] = 2.0 / 3.0 * h**3
    out[2] = 0.25 * r2 * r2 * (gam - 0.25 * s4)
    out[3] = 2.0 / 3.0 * r2 * r2 * (0.375 * gam - 0.25 * s2 + s4 / 32.0)


@njit(cache=True, error_model="numpy")
def contact_moments(w: float, gx: float, gy: float, r: float, bonded: bool, mom: np.ndarray) -> int:
    """mom = (A, Sa, Sb, Iaa, Iab, Ibb, na, nb, d, h, s) of the contact region; returns its kind.

    Kind: 0 no contact, 1 partial (a circular segment), 2 full disc.
    """
    seg = np.empty(4)
    s = math.sqrt(gx * gx + gy * gy)
    mom[10] = s
    if bonded or (s <= TINY_TILT and w < 0.0) or (s > TINY_TILT and w <= -s * r):
        kind = 2
        d = -r
    elif (s <= TINY_TILT) or w >= s * r:
        kind = 0
        d = r
    else:
        kind = 1
        d = w / s
    if s > TINY_TILT:
        na = -gx / s
        nb = -gy / s
    else:
        na = 1.0
        nb = 0.0
    segment_integrals(d, r, seg)
    A, Su, Iuu, Ivv = seg[0], seg[1], seg[2], seg[3]
    mom[0] = A
    mom[1] = Su * na
    mom[2] = Su * nb
    mom[3] = Ivv + (Iuu - Ivv) * na * na
    mom[4] = (Iuu - Ivv) * na * nb
    mom[5] = Ivv + (Iuu - Ivv) * nb * nb
    mom[6] = na
    mom[7] = nb
    mom[8] = d
    mom[9] = math.sqrt(max(r * r - d * d, 0.0))
    return kind


@njit(cache=True, error_model="numpy")
def resultants(z: np.ndarray, r: float, k: float, c: float, bonded: bool, out: np.ndarray) -> int:
    """out = (F, m_a, m_b, A, V, D): force, base-axis moments ∫ρp, area, energy, dissipation,
    at the base state z = (w, g_a, g_b, ẇ, ġ_a, ġ_b); returns the contact kind."""
    w, gx, gy, wd, gxd, gyd = z[0], z[1], z[2], z[3], z[4], z[5]
    mom = np.empty(11)
    kind = contact_moments(w, gx, gy, r, bonded, mom)
    A, Sa, Sb, Iaa, Iab, Ibb = mom[0], mom[1], mom[2], mom[3], mom[4], mom[5]
    a0 = -(k * w + c * wd)
    aa = -(k * gx + c * gxd)
    ab = -(k * gy + c * gyd)
    out[0] = a0 * A + aa * Sa + ab * Sb
    out[1] = a0 * Sa + Iaa * aa + Iab * ab
    out[2] = a0 * Sb + Iab * aa + Ibb * ab
    out[3] = A
    out[4] = 0.5 * k * (w * w * A + 2.0 * w * (gx * Sa + gy * Sb) + quad(gx, gy, Iaa, Iab, Ibb))
    out[5] = c * (wd * wd * A + 2.0 * wd * (gxd * Sa + gyd * Sb) + quad(gxd, gyd, Iaa, Iab, Ibb))
    return kind


@njit(cache=True, error_model="numpy")
def quad(x: float, y: float, Iaa: float, Iab: float, Ibb: float) -> float:
    """(x, y) I (x, y)ᵀ for the symmetric 2×2 I."""
    return x * x * Iaa + 2.0 * x * y * Iab + y * y * Ibb


@njit(cache=True, error_model="numpy")
def resultants_jac(z: np.ndarray, r: float, k: float, c: float, bonded: bool, jac: np.ndarray):
    """jac[i, j] = ∂(F, m_a, m_b)_i / ∂z_j (3×6) at z = (w, g_a, g_b, ẇ, ġ_a, ġ_b), exact."""
    w, gx, gy, wd, gxd, gyd = z[0], z[1], z[2], z[3], z[4], z[5]
    mom = np.empty(11)
    kind = contact_moments(w, gx, gy, r, bonded, mom)
    A, Sa, Sb, Iaa, Iab, Ibb = mom[0], mom[1], mom[2], mom[3], mom[4], mom[5]
    blk = np.array([[A, Sa, Sb], [Sa, Iaa, Iab], [Sb, Iab, Ibb]])
    for i in range(3):
        for j in range(3):
            jac[i, j] = -k * blk[i, j]
            jac[i, 3 + j] = -c * blk[i, j]
    if kind != 1 or c == 0.0:
        return
    # chord u = d, v in [-h, h]: p_c = c(-wd - gd.rho) = beta0 - v*beta1
    na, nb, d, h, s = mom[6], mom[7], mom[8], mom[9], mom[10]
    ta, tb = -nb, na
    beta0 = c * (-wd - d * (gxd * na + gyd * nb))
    beta1 = c * (gxd * ta + gyd * tb)
    L0 = 2.0 * h  # ∫ds
    L2 = 2.0 / 3.0 * h**3  # ∫v²ds
    # chord integrals of p_c * (1, rho, rho rho^T)
    c0 = beta0 * L0
    c1a = beta0 * L0 * d * na - beta1 * L2 * ta
    c1b = beta0 * L0 * d * nb - beta1 * L2 * tb
    caa = beta0 * (L0 * d * d * na * na + L2 * ta * ta) - beta1 * L2 * d * 2.0 * na * ta
    cab = beta0 * (L0 * d * d * na * nb + L2 * ta * tb) - beta1 * L2 * d * (na * tb + ta * nb)
    cbb = beta0 * (L0 * d * d * nb * nb + L2 * tb * tb) - beta1 * L2 * d * 2.0 * nb * tb
    chord = np.array([[c0, c1a, c1b], [c1a, caa, cab], [c1b, cab, cbb]])
    for i in range(3):
        for j in range(3):
            jac[i, j] -= chord[i, j] / s
