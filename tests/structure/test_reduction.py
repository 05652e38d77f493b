"""Craig–Bampton reduction and fixed-base modes.

Sources: Craig & Bampton (AIAA J. 6(7), 1968) for the basis; the Rayleigh–Ritz /
Cauchy-interlacing theorem for bounds (a Ritz space gives upper bounds, nested spaces give
monotone ones); rigid-body kinematics for the influence vectors; seed 004 Sect. 2 for the
office's 13 generalised dofs at 5 Hz.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

import nsdyn.structure.reduction as red
from nsdyn.structure.reduction import (
    craig_bampton,
    damping_ratios,
    fixed_base_modes,
    kinetic_energy_shares,
    mode_type,
    reduce_frame,
)


def full_fixed_hz(K, M, boundary, n):
    """Reference: dense generalized eigenproblem of the clamped full model."""
    K, M = K.toarray(), M.toarray()
    i = np.setdiff1d(np.arange(K.shape[0]), boundary)
    lam = sla.eigh(K[np.ix_(i, i)], M[np.ix_(i, i)], eigvals_only=True)
    return np.sqrt(lam[:n]) / (2 * np.pi)


def test_office_reduces_to_13_dofs_at_5_hz(office):
    # Source: seed 004 Sect. 2: 435 dofs -> 13 generalised dofs (6 boundary + 7 modal).
    cb = reduce_frame(office, 5.0)
    assert (cb.n_b, cb.n_modes, cb.n_red) == (6, 7, 13)
    assert cb.T.shape == (435, 13)
    assert np.all(cb.f_hz <= 5.0)


def test_kept_fixed_interface_frequencies_are_exact(office, office_km):
    # Source: with q_b = 0 the CB basis is the span of the kept fixed-interface modes, whose
    # Ritz values are those modes' eigenvalues exactly (to round-off, rtol 1e-9).
    K, M = office_km
    cb = craig_bampton(K, M, office.boundary_dofs, 5.0, office.zeta, r=office.influence())
    nb = cb.n_b
    lam = sla.eigh(cb.K[nb:, nb:], cb.M[nb:, nb:], eigvals_only=True)
    ref = full_fixed_hz(K, M, office.boundary_dofs, cb.n_modes)
    assert np.sqrt(lam) / (2 * np.pi) == pytest.approx(ref, rel=1e-9)
    assert cb.f_hz == pytest.approx(ref, rel=1e-9)
    # modal block is diagonal with unit mass, and constraint/modal stiffness coupling vanishes
    assert np.allclose(cb.M[nb:, nb:], np.eye(cb.n_modes), atol=1e-9)
    assert np.abs(cb.K[:nb, nb:]).max() <= 1e-9 * np.abs(cb.K).max()


def test_ritz_frequencies_decrease_monotonically_to_the_full_model(office, office_km):
    # Source: Rayleigh–Ritz. Larger f_max gives nested CB spaces, so every reduced
    # frequency is >= the full one and non-increasing in f_max; f_max = inf is the full
    # model in another basis (rtol 1e-8). Boundary condition: base nodes' y and theta
    # clamped, x free (the frame slides rigidly: one zero mode, dropped).
    K, M = office_km
    b = office.boundary_dofs
    keep_b = [0, 3]  # x1, x2 in q_b order
    clamp_full = b[[1, 2, 4, 5]]
    free = np.setdiff1d(np.arange(office.n_dof), clamp_full)
    Kd, Md = K.toarray(), M.toarray()
    lam = sla.eigh(Kd[np.ix_(free, free)], Md[np.ix_(free, free)], eigvals_only=True)
    n = 8
    full = np.sqrt(np.abs(lam[1 : n + 1])) / (2 * np.pi)
    prev = None
    for f_max in (1.0, 3.0, 5.0, 10.0, 20.0, np.inf):
        cb = craig_bampton(K, M, b, f_max, office.zeta, r=office.influence())
        q = np.r_[keep_b, np.arange(cb.n_b, cb.n_red)]
        lr = sla.eigh(cb.K[np.ix_(q, q)], cb.M[np.ix_(q, q)], eigvals_only=True)
        m = min(n, len(lr) - 1)
        f = np.sqrt(np.abs(lr[1 : m + 1])) / (2 * np.pi)
        assert np.all(f >= full[:m] * (1 - 1e-8)), f_max  # round-off allowance
        if prev is not None:
            k = min(len(prev), m)
            assert np.all(f[:k] <= prev[:k] * (1 + 1e-8)), f_max
        prev = f
    assert prev == pytest.approx(full, rel=1e-8)


@pytest.mark.parametrize("f_max", [5.0, np.inf])
def test_influence_vectors_are_exact_and_carry_total_mass(office, office_km, f_max):
    # Source: K r = 0 for rigid translation r => Psi r_b = r_i, so T Gamma = r with
    # Gamma = [r_b; 0], and Gamma^T M_red Gamma = r^T M r = total mass (rtol 1e-10).
    K, M = office_km
    r = office.influence()
    cb = craig_bampton(K, M, office.boundary_dofs, f_max, office.zeta, r=r)
    assert np.abs(cb.T @ cb.Gamma - r).max() < 1e-8
    assert np.all(cb.Gamma[cb.n_b :] == 0)
    assert cb.Gamma[: cb.n_b].tolist() == [[1, 0], [0, 1], [0, 0], [1, 0], [0, 1], [0, 0]]
    gmg = cb.Gamma.T @ cb.M @ cb.Gamma
    assert gmg[0, 0] == pytest.approx(office.total_mass, rel=1e-10)
    assert gmg[1, 1] == pytest.approx(office.total_mass, rel=1e-10)
    assert abs(gmg[0, 1]) < 1e-10 * office.total_mass
    # default r (node triples x, y, theta) gives the same Gamma
    cb0 = craig_bampton(K, M, office.boundary_dofs, f_max, office.zeta)
    assert np.array_equal(cb0.Gamma, cb.Gamma)


def test_full_basis_reproduces_free_free_eigenvalues(make_portal):
    # Source: f_max = inf keeps every fixed-interface mode, T is square and invertible, so
    # the free-free spectrum (3 rigid + elastic modes) is unchanged (rtol 1e-9).
    fr = make_portal(n_v=3, n_h=4, floor_mass=4e3)
    K, M = fr.assemble()
    cb = craig_bampton(K, M, fr.boundary_dofs, np.inf, fr.zeta)
    assert cb.n_red == fr.n_dof
    a = sla.eigh(K.toarray(), M.toarray(), eigvals_only=True)
    b = sla.eigh(cb.K, cb.M, eigvals_only=True)
    assert np.all(np.abs(b[:3]) < 1e-8 * a[3])
    assert b[3:] == pytest.approx(a[3:], rel=1e-9)


def test_damping_lives_on_fixed_interface_modes_only(office, office_km):
    # Source: modal damping is assigned to fixed-base modes (seed 004 Sect. 2); boundary
    # (rigid/isolator) motion is not damped by the superstructure.
    K, M = office_km
    cb = craig_bampton(K, M, office.boundary_dofs, 5.0, [0.03, 0.04, 0.05, 0.06])
    nb = cb.n_b
    assert np.all(cb.C[:nb, :] == 0) and np.all(cb.C[:, :nb] == 0)
    assert cb.zeta.tolist() == [0.03, 0.04, 0.05, 0.06, 0.06, 0.06, 0.06]
    assert np.allclose(cb.C[nb:, nb:], np.diag(2 * cb.zeta * cb.omega), rtol=0, atol=1e-14)


def test_damping_ratios_extend_with_the_last_value():
    assert damping_ratios([0.03, 0.04], 4).tolist() == [0.03, 0.04, 0.04, 0.04]
    assert damping_ratios([0.03, 0.04, 0.05], 2).tolist() == [0.03, 0.04]
    assert damping_ratios(0.02, 3).tolist() == [0.02, 0.02, 0.02]
    with pytest.raises(ValueError):
        damping_ratios([], 2)


def test_fixed_base_modes_are_mass_normalised_and_clamped(office, office_km):
    K, M = office_km
    f, Phi = fixed_base_modes(K, M, office.boundary_dofs, f_max=5.0)
    assert len(f) == 7 and np.all(np.diff(f) > 0)
    assert np.allclose(Phi.T @ (M @ Phi), np.eye(7), atol=1e-9)
    assert np.all(Phi[office.boundary_dofs] == 0)
    f4, _ = fixed_base_modes(K, M, office.boundary_dofs, n_modes=4)
    assert f4 == pytest.approx(f[:4], rel=1e-12)
    # a negative f_max was squared (f_max = -1 kept the modes up to 1 Hz), a count below 1
    # returned nothing: both refused
    for kw in ({"f_max": -1.0}, {"f_max": 0.0}, {"n_modes": 0}, {"n_modes": -1}):
        with pytest.raises(ValueError, match=f"{next(iter(kw))}: expected"):
            fixed_base_modes(K, M, office.boundary_dofs, **kw)


def test_sparse_shift_invert_path_matches_dense(office, office_km, monkeypatch):
    # Source: same eigenproblem, two solvers (LAPACK vs ARPACK shift-invert), rtol 1e-8.
    K, M = office_km
    dense_f, dense_phi = fixed_base_modes(K, M, office.boundary_dofs, f_max=10.0)
    monkeypatch.setattr(red, "DENSE_MAX", 10)
    monkeypatch.setattr(red, "EIGSH_K0", 4)  # force the doubling loop
    f, phi = fixed_base_modes(K, M, office.boundary_dofs, f_max=10.0)
    assert f == pytest.approx(dense_f, rel=1e-8)
    # same shapes up to sign
    dots = np.abs(np.einsum("ij,ij->j", phi, M @ dense_phi))
    assert np.allclose(dots, 1.0, atol=1e-6)
    f6, _ = fixed_base_modes(K, M, office.boundary_dofs, n_modes=6)
    assert f6 == pytest.approx(dense_f[:6], rel=1e-8)


def test_every_mode_below_f_max_is_returned_when_that_is_all_of_them(office, office_km,
                                                                      monkeypatch):  # fmt: skip
    # Source: the interior problem has exactly n eigenpairs; eigsh takes k < n, so a request
    # for all of them must reach them another way (the dense solve), not stop at n - 1.
    K, M = office_km
    n = K.shape[0] - len(office.boundary_dofs)
    dense_f, _ = fixed_base_modes(K, M, office.boundary_dofs, f_max=1e9)
    assert len(dense_f) == n
    monkeypatch.setattr(red, "DENSE_MAX", 10)  # the sparse path's turn
    f, _ = fixed_base_modes(K, M, office.boundary_dofs, f_max=1e9)
    assert len(f) == n and f == pytest.approx(dense_f, rel=1e-12)


def test_sparse_modes_are_the_same_on_every_call(office, office_km, monkeypatch):
    # the shift-invert Lanczos solve starts from a fixed generic vector
    # (reduction.lanczos_start): with ARPACK's own random start two solves of one model
    # differed at round-off (an exported model's stored frequencies then differed from a
    # recomputation); now every call gives the same numbers, the planar path and the 3D one
    from nsdyn.structure import load_frame3d
    from nsdyn.structure.modes3d import fixed_base_modes_3d

    K, M = office_km
    monkeypatch.setattr(red, "DENSE_MAX", 10)
    runs = [fixed_base_modes(K, M, office.boundary_dofs, n_modes=6) for _ in range(2)]
    assert np.array_equal(runs[0][0], runs[1][0]) and np.array_equal(runs[0][1], runs[1][1])
    portal = load_frame3d("portal-3d")
    f3 = [fixed_base_modes_3d(portal, n_modes=4, method="sparse").f_hz for _ in range(2)]
    assert np.array_equal(f3[0], f3[1])


def test_a_reduction_that_misses_the_rigid_motion_says_why(office, office_km, monkeypatch):
    # the check was an assertion: a frame in millimetres (storey heights of 6000 m, its
    # stiffness too ill-conditioned) ended "nsdyn modes" in a traceback; the bound is forced
    # here (a tolerance below zero: any error fails it) to reach the message on any machine
    from nsdyn._checks import NumericalFailure

    K, M = office_km
    monkeypatch.setattr(red, "RIGID_RTOL", -1.0)
    for r in (office.influence(), None):
        with pytest.raises(NumericalFailure, match=r"^Craig-Bampton: .*check the frame's units"):
            craig_bampton(K, M, office.boundary_dofs, 5.0, office.zeta, r=r)


def test_dense_and_sparse_inputs_agree(make_portal):
    fr = make_portal(n_v=2, n_h=2, floor_mass=1e3)
    Ks, Ms = fr.assemble()
    Kd, Md = fr.assemble(sparse=False)
    a = craig_bampton(Ks, Ms, fr.boundary_dofs, 50.0, fr.zeta)
    b = craig_bampton(Kd, Md, fr.boundary_dofs, 50.0, fr.zeta)
    assert np.allclose(a.K, b.K, rtol=1e-10, atol=1e-6) and np.allclose(a.M, b.M, atol=1e-9)


def test_mode_type_of_a_vertical_cantilever(make_cantilever, cantilever_props):
    # Source: a vertical bar's bending modes move in x (lateral), its axial modes in y.
    fr = make_cantilever(20, angle=np.pi / 2)
    K, M = fr.assemble()
    f, Phi = fixed_base_modes(K, M, fr.boundary_dofs, n_modes=12)
    types = [mode_type(Phi[:, k], M, fr) for k in range(12)]
    assert types[0] == types[1] == "lateral"
    assert "vertical" in types
    # first axial frequency: (1/4L) sqrt(EA / rho_A) (clamped-free bar)
    C = cantilever_props

    f_ax = np.sqrt(C["E"] * C["A"] / C["rho_A"]) / (4 * C["L"])
    k = types.index("vertical")
    assert f[k] == pytest.approx(f_ax, rel=1e-3)
    sh = kinetic_energy_shares(Phi[:, k], M, fr)
    assert sh.sum() == pytest.approx(1.0) and sh[1] > 0.99


def test_light_members_beside_a_floor_mass_keep_the_first_mode():
    # A one-bay portal, a stiff beam on two columns under a 12 t floor: its sway is
    # 24 EI/h³ on 12 t, 6.47 Hz (the columns' axial and the beam's own flexibility only
    # lower it). Members of 1e-6 kg/m (a user's stand-in for "massless", refused by the
    # reductions) gave LAPACK's M-factored solver a mass matrix of entries 1e11 apart: it
    # returned a negative eigenvalue, printed as a 0 Hz first mode (1e-3 kg/m: 8.37 Hz).
    # The member mass moves the frequency by its share of the mass, below 1e-8
    from nsdyn.structure import Section, regular_frame

    def f1(rho_A):
        col = Section(E=2.1e11, A=0.0149, I=2.517e-4, rho_A=rho_A)
        beam = Section(E=2.1e11, A=1.0, I=1000.0, rho_A=rho_A)
        f = regular_frame("p", [6.0], [4.0], 4, 4, col, beam, floor_mass=12000.0)
        return red.fixed_base_modes(*f.assemble(), f.boundary_dofs, n_modes=1)[0][0]

    hand = np.sqrt(24 * 2.1e11 * 2.517e-4 / 4.0**3 / 12000.0) / (2 * np.pi)
    massless = f1(0.0)
    assert 0.97 * hand < massless < hand
    for rho_A in (1e-6, 1e-3):
        assert f1(rho_A) == pytest.approx(massless, rel=1e-6)
