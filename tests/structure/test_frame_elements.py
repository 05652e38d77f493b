"""Frame elements: rigid-body modes, rigid translation mass, symmetry and definiteness.

Sources: a rigid-body motion strains no fibre (3 zero modes of the free element, the other 3
deformation modes of positive energy); a rigid translation carries the element mass ρA L for any
mass model; the Rayleigh quotients of k and m are energies, so both are symmetric and positive
(semi-)definite for every E, A, I, ρA, L > 0 and every orientation (property tests, hypothesis).
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from nsdyn.structure import beam_mass, beam_stiffness, rotation


@pytest.mark.parametrize("angle", [0.0, 0.3, np.pi / 2, 2.5])
def test_element_rigid_body_modes_have_no_strain_energy(angle):
    # Source: a rigid-body motion (two translations, one small rotation) strains no fibre.
    L, c, s = 2.7, np.cos(angle), np.sin(angle)
    R = rotation(c, s)
    k = R.T @ beam_stiffness(2.1e11, 1e-2, 3e-5, L) @ R
    x2, y2 = L * c, L * s
    rigid = np.array(
        [
            [1, 0, 0, 1, 0, 0],
            [0, 1, 0, 0, 1, 0],
            [0, 0, 1, -y2, x2, 1],  # rotation about node 1: u = -th y, v = th x
        ],
        dtype=float,
    ).T
    assert np.abs(k @ rigid).max() <= 1e-9 * np.abs(k).max()
    assert np.allclose(k, k.T, rtol=0, atol=1e-12 * np.abs(k).max())
    # exactly three zero eigenvalues (6 dofs - 3 rigid modes = 3 deformation modes)
    ev = np.linalg.eigvalsh(k)
    assert np.sum(np.abs(ev) < 1e-9 * ev.max()) == 3


@pytest.mark.parametrize("lumped", [False, True])
def test_element_mass_reproduces_rigid_translation_mass(lumped):
    # Source: kinetic energy of a rigid translation is (1/2) m L v^2 for any mass model.
    rho_A, L = 80.0, 3.0
    for angle in (0.0, 0.7):
        R = rotation(np.cos(angle), np.sin(angle))
        m = R.T @ beam_mass(rho_A, L, lumped) @ R
        for d in ([1, 0, 0, 1, 0, 0], [0, 1, 0, 0, 1, 0]):
            d = np.asarray(d, float)
            assert d @ m @ d == pytest.approx(rho_A * L, rel=1e-13)
        assert np.all(np.linalg.eigvalsh(m) > 0)


def _log_uniform(lo: float, hi: float):
    """Positive floats, log-uniform in [lo, hi] (element properties span decades)."""
    return st.floats(np.log(lo), np.log(hi)).map(np.exp)


# Property ranges of real members, in SI units. With radius of gyration r = sqrt(I/A) the
# nonzero eigenvalues of k lie within min(r², L²/12) ≳ 3e-3·r² of its largest (2EI/L against
# 2EA/L and 12EI/L³), far above the round-off of the three zero ones (≈ 1e-15 of the largest).
E_RANGE = _log_uniform(1e9, 1e12)  # [Pa] timber to steel and stiffer
A_RANGE = _log_uniform(1e-4, 1e-1)  # [m²]
R_RANGE = _log_uniform(0.02, 0.5)  # radius of gyration [m]
L_RANGE = _log_uniform(0.2, 20.0)  # element length [m]
RHO_A_RANGE = _log_uniform(1.0, 1e5)  # mass per length [kg/m]
ANGLE = st.floats(-np.pi, np.pi)  # element axis angle from the global x axis [rad]
ZERO_RTOL = 1e-9  # |eigenvalue| ≤ ZERO_RTOL · largest counts as zero (round-off is ~1e-15)


def _global(k_local: np.ndarray, angle: float) -> np.ndarray:
    R = rotation(np.cos(angle), np.sin(angle))
    return R.T @ k_local @ R


@settings(max_examples=200, deadline=None)
@given(E=E_RANGE, A=A_RANGE, r=R_RANGE, L=L_RANGE, angle=ANGLE)
def test_element_stiffness_is_symmetric_psd_with_three_rigid_modes(E, A, r, L, angle):
    # Source: strain energy q·k q / 2 ≥ 0, zero exactly for the 3 rigid-body motions of a free
    # plane element (2 translations, 1 rotation); the other 3 deformation modes store energy.
    k = _global(beam_stiffness(E, A, A * r**2, L), angle)
    scale = np.abs(k).max()
    assert np.abs(k - k.T).max() <= 1e-13 * scale
    ev = np.linalg.eigvalsh(k)
    assert ev.min() >= -ZERO_RTOL * ev.max()
    assert np.sum(np.abs(ev) <= ZERO_RTOL * ev.max()) == 3
    x2, y2 = L * np.cos(angle), L * np.sin(angle)  # node 2 relative to node 1
    rigid = np.array(
        [[1, 0, 0, 1, 0, 0], [0, 1, 0, 0, 1, 0], [0, 0, 1, -y2, x2, 1]], dtype=float
    ).T  # the rotation about node 1: u = -th y, v = th x
    assert np.abs(k @ rigid).max() <= 1e-12 * scale * max(1.0, L)


@settings(max_examples=200, deadline=None)
@given(rho_A=RHO_A_RANGE, L=L_RANGE, angle=ANGLE, lumped=st.booleans())
def test_element_mass_is_symmetric_positive_definite(rho_A, L, angle, lumped):
    # Source: kinetic energy q̇·m q̇ / 2 > 0 for every motion (consistent mass is the Gram matrix
    # of independent shape functions; HRZ lumping keeps positive diagonal entries), and a rigid
    # translation in any direction carries the element mass ρA L.
    m = _global(beam_mass(rho_A, L, lumped), angle)
    scale = np.abs(m).max()
    assert np.abs(m - m.T).max() <= 1e-13 * scale
    ev = np.linalg.eigvalsh(m)
    assert ev.min() > ZERO_RTOL * ev.max()
    d = np.array([np.cos(angle), np.sin(angle), 0.0] * 2)  # unit translation along the axis
    assert d @ m @ d == pytest.approx(rho_A * L, rel=1e-12)
