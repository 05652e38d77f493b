"""Beam-theory stresses in a cross-section of the cylinder (solid circular section).

The part P above the section at body height z_s (mass m' = m(2H − z_s)/2H, length L' = 2H − z_s,
centre of mass at z' = (2H + z_s)/2) is loaded by the lower part with force and moment
F_s = m'(a' + g e_z),  M_s = J'α + ω×J'ω + (L'/2) e₃ × F_s  (Newton–Euler of P). In body axes
(F₁, F₂, F₃, M₁, M₂, M₃), with A = πr², I = πr⁴/4, J = πr⁴/2 and (x, y) a section point:

    σ_zz = −M₁ y/I + M₂ x/I − F₃/A
    τ_xz =  M₃ y/J − F₁ (r² − x²)/(3I) + F₂ x y/(3I)
    τ_yz = −M₃ x/J − F₂ (r² − y²)/(3I) + F₁ x y/(3I)

(the shear-force terms: Jourawski on chords, F (r² − y²)/(3I) along the force, and across it
the component that turns the stress at a chord's ends along the rim, so that the rim is free
of traction, τ·n = 0). These integrate back to the resultants on P, whose face at the section
has the outward normal −e_z: F₁ = −∫τ_xz dA, F₂ = −∫τ_yz dA, M₃ = ∫(y τ_xz − x τ_yz) dA (and
F₃ = −∫σ_zz dA, M₁ = −∫y σ_zz dA, M₂ = ∫x σ_zz dA). Seed 000's eq. (3.89) prints the torque
term of τ_xz as −M₃ y/J, which in the convention of its own σ_zz (3.86) integrates to −M₃;
the sign here is the consistent one. Principal stresses
σ₁,₃ = σ/2 ± √(σ²/4 + τ²), σ₂ = 0 and τ_max = √(σ²/4 + τ²), at the points A (r, 0), B (0, r),
C (−r, 0), D (0, −r), E (0, 0). All stresses are divided by σ_st = mg/(πr²).
"""

from __future__ import annotations

import numpy as np

from nsdyn.models.cylinder.simulate import CylinderResult, point_acceleration

POINTS = {"A": (1.0, 0.0), "B": (0.0, 1.0), "C": (-1.0, 0.0), "D": (0.0, -1.0), "E": (0.0, 0.0)}


def section_resultants(res: CylinderResult, z_s: float | None = None) -> tuple[np.ndarray, ...]:
    """(F (n, 3), M (n, 3)) on the part above body height ``z_s`` (default H), body axes."""
    p = res.params
    z_s = p.H if z_s is None else float(z_s)
    if not 0.0 <= z_s < 2 * p.H:
        raise ValueError(f"z_s: expected a height in [0, 2H) = [0, {2 * p.H}), got {z_s!r}")
    L = 2 * p.H - z_s
    mp = p.m * L / (2 * p.H)
    zc = 0.5 * (2 * p.H + z_s)
    It = mp * (3 * p.r**2 + L**2) / 12.0
    Ia = p.Ia * L / (2 * p.H)  # axial inertia scales with the mass of P
    a = point_acceleration(res, zc)
    a[:, 2] += p.g
    Fw = mp * a
    R = res.R
    e3 = R[:, :, 2]
    om, al = res.omega, res.omega_dot

    def J(v):
        return It * v + (Ia - It) * e3 * np.sum(e3 * v, axis=1, keepdims=True)

    Mw = J(al) + np.cross(om, J(om)) + 0.5 * L * np.cross(e3, Fw)
    Fb = np.einsum("nji,nj->ni", R, Fw)
    Mb = np.einsum("nji,nj->ni", R, Mw)
    return Fb, Mb


def shear_stresses(F1, F2, M3, x: float, y: float, r: float) -> tuple:
    """(τ_xz, τ_yz) at the section point (x, y) from the shear forces F₁, F₂ and the torque
    M₃ (module text)."""
    I, J = 0.25 * np.pi * r**4, 0.5 * np.pi * r**4
    txz = M3 * y / J - F1 * (r * r - x * x) / (3 * I) + F2 * x * y / (3 * I)
    tyz = -M3 * x / J - F2 * (r * r - y * y) / (3 * I) + F1 * x * y / (3 * I)
    return txz, tyz


def point_stresses(res: CylinderResult, z_s: float | None = None) -> dict[str, dict]:
    """Per point A–E: σ_zz, σ₁, σ₃, τ_max histories (n,), normalised by mg/(πr²)."""
    p = res.params
    r = p.r
    A, I = np.pi * r**2, 0.25 * np.pi * r**4
    F, M = section_resultants(res, z_s)
    sst = p.m * p.g / A
    out = {}
    for name, (xf, yf) in POINTS.items():
        x, y = xf * r, yf * r
        sig = -M[:, 0] * y / I + M[:, 1] * x / I - F[:, 2] / A
        txz, tyz = shear_stresses(F[:, 0], F[:, 1], M[:, 2], x, y, r)
        tmax = np.sqrt(0.25 * sig**2 + txz**2 + tyz**2)
        out[name] = {
            "sigma_zz": sig / sst,
            "sigma_1": (0.5 * sig + tmax) / sst,
            "sigma_3": (0.5 * sig - tmax) / sst,
            "tau_max": tmax / sst,
        }
    return out


def peak_stresses(res: CylinderResult, z_s: float | None = None) -> dict[str, float]:
    """Peaks over the five points and time: max σ₁, min σ₃, max τ_max (normalised)."""
    st = point_stresses(res, z_s)
    return {
        "sigma_1": float(max(np.max(v["sigma_1"]) for v in st.values())),
        "sigma_3": float(min(np.min(v["sigma_3"]) for v in st.values())),
        "tau_max": float(max(np.max(v["tau_max"]) for v in st.values())),
    }
