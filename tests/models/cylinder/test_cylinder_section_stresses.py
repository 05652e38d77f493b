"""The section's shear stresses (nsdyn.models.cylinder.stresses): the beam-theory conditions
they are built on, checked on the formulas alone."""

import math

import numpy as np
import pytest

from nsdyn.models.cylinder.stresses import shear_stresses


@pytest.mark.parametrize("F1, F2", [(1.0, 0.0), (0.0, 1.0), (0.6, -0.8)])
@pytest.mark.parametrize("angle", np.linspace(0.0, 2.0 * math.pi, 13))
def test_the_rim_is_free_of_traction_under_shear(F1, F2, angle):
    # on the rim the stress vector (τ_xz, τ_yz) has no normal component (a free surface);
    # the torque's part is tangential by itself. Round-off: terms of order F/(3I) r^3
    r = 0.7
    x, y = r * math.cos(angle), r * math.sin(angle)
    txz, tyz = shear_stresses(F1, F2, 0.4, x, y, r)
    I = 0.25 * math.pi * r**4
    assert abs(txz * x + tyz * y) <= 1e-14 * r**3 / I


def test_the_centre_carries_four_thirds_of_the_mean_shear():
    # Jourawski on the diameter of a solid circle: τ(0) = F r² / (3 I) = (4/3) F / A
    r = 0.5
    txz, tyz = shear_stresses(0.0, 2.0, 0.0, 0.0, 0.0, r)
    assert txz == 0.0
    assert tyz == pytest.approx(-4.0 / 3.0 * 2.0 / (math.pi * r * r), rel=1e-14)


def test_the_torque_gives_the_saint_venant_stress():
    # τ = M₃ ρ / J at radius ρ, tangential
    r, M3 = 0.5, 3.0
    txz, tyz = shear_stresses(0.0, 0.0, M3, 0.3, 0.0, r)
    assert txz == 0.0 and tyz == pytest.approx(-M3 * 0.3 / (0.5 * math.pi * r**4), rel=1e-14)


def test_the_shear_stresses_integrate_back_to_the_resultants_on_the_upper_part():
    # statics of the section: the lower part loads P through P's face of outward normal -e_z,
    # whose traction is (-τ_xz, -τ_yz, -σ_zz) (σ_zz = -F₃/A: F₃ > 0 compresses); so
    # F₁ = -∫τ_xz dA, F₂ = -∫τ_yz dA and M₃ = ∫(y τ_xz - x τ_yz) dA. (Seed 000's eq. 3.89
    # prints the torque term of τ_xz as -M₃ y/J, which integrates to -M₃ in this convention.)
    # Quadrature: Gauss-Legendre in the radius (the integrands are polynomials of degree
    # <= 4 in it) and the trapezoid rule in the angle (exact for their trigonometric degree
    # <= 3), so the sums are exact to round-off (1e-13 of the largest term)
    r, F1, F2, M3 = 0.8, 0.6, -1.3, 2.1
    g, w = np.polynomial.legendre.leggauss(6)
    rho, wr = 0.5 * r * (g + 1.0), 0.5 * r * w
    th = np.linspace(0.0, 2.0 * math.pi, 16, endpoint=False)
    R, TH = np.meshgrid(rho, th, indexing="ij")
    x, y = R * np.cos(TH), R * np.sin(TH)
    dA = (wr * rho)[:, None] * (2.0 * math.pi / th.size)
    txz, tyz = shear_stresses(F1, F2, M3, x, y, r)
    got = (-(txz * dA).sum(), -(tyz * dA).sum(), ((y * txz - x * tyz) * dA).sum())
    assert got == pytest.approx((F1, F2, M3), abs=1e-13 * max(abs(F1), abs(F2), abs(M3) / r))
