"""Space-frame element and cantilevers against closed forms; a plane frame embedded in 3D.

Sources: Euler–Bernoulli beam theory (tip deflection P L³/3EI, rotation T L/GJ, elongation
P L/EA), the cantilever eigenvalue roots β L of 1 + cos βL cosh βL = 0 (Blevins, Formulas
for Natural Frequency and Mode Shape, Table 8-1), the fixed-free shaft f = (2k − 1)/(4L)
√(GJ/ρI_p), and the rigid-body motions of a free body (six in space). Round-off bounds are
derived from perturbation analysis (forward error ≤ cond × backward error), with the
backward error c n eps of a stable solver (c = 10, n the number of unknowns); no expected
value was produced by this code.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from nsdyn.structure import (
    Frame3D,
    beam3d_mass,
    beam3d_stiffness,
    fixed_base_modes,
    fixed_base_modes_3d,
    local_axes,
    planar_dofs,
)

EPS = np.finfo(float).eps
C_STABLE = 10.0  # the constant c of the backward error c n eps
BETA_L = 1.875104068711961  # first cantilever root
SEC = dict(E=2.1e11, G=8.1e10, A=1e-2, I_y=1e-5, I_z=4e-5, J=3e-5, rho_A=78.5)


def bar(n_el, d=(0.0, 0.0, 1.0), vecxz=(1.0, 0.0, 0.0), L=10.0, **kw) -> Frame3D:
    """A straight bar of n_el elements from the origin along d; node 0 is the base."""
    p = {**SEC, **kw}
    d = np.asarray(d, float) / np.linalg.norm(d)
    nodes = np.linspace(0.0, L, n_el + 1)[:, None] * d
    el = np.c_[np.arange(n_el), np.arange(1, n_el + 1)]
    return Frame3D(
        "bar",
        nodes,
        el,
        vecxz,
        p["E"],
        p["G"],
        p["A"],
        p["I_y"],
        p["I_z"],
        p["J"],
        p["rho_A"],
        p["rho_A"] * (p["I_y"] + p["I_z"]) / p["A"],
        0.0,
        [0],
        [0.02],
    )


def clamped(frame: Frame3D):
    K, M = frame.reduced()
    i = np.setdiff1d(np.arange(frame.n_red), frame.boundary_reduced)
    return K[i][:, i].toarray(), M[i][:, i].toarray(), i


def axes_by_definition(d, v):
    """OpenSees geomTransf Linear: e_y = v × e_x / |v × e_x|, e_z = e_x × e_y."""
    ex = np.asarray(d, float) / np.linalg.norm(d)
    ey = np.cross(v, ex)
    ey /= np.linalg.norm(ey)
    return ex, ey, np.cross(ex, ey)


def test_local_stiffness_is_symmetric_and_free_element_has_six_rigid_modes():
    # Source: a free body in space has exactly six rigid-body motions (3 translations,
    # 3 rotations), all in the null space of K; the rest of K is positive definite.
    # Bound: eigh's eigenvalues carry absolute error <= c n eps ||K|| (n = 12).
    k = beam3d_stiffness(2.1e11, 8.1e10, 1e-2, 2e-5, 5e-5, 3e-5, 0.8)
    assert np.array_equal(k, k.T)
    fr = bar(1, d=(1.0, 2.0, 2.0), vecxz=(0.3, -1.0, 0.5), L=0.8, I_y=2e-5, I_z=5e-5)
    K, _ = fr.assemble()
    K = K.toarray()
    lam = np.linalg.eigvalsh(K)
    bound = C_STABLE * 12 * EPS * np.abs(lam).max()
    assert np.sum(np.abs(lam) <= bound) == 6
    assert lam[6] > 1e6 * bound
    # the six rigid motions: translations, and rotations w about a point p
    p = np.array([0.4, -1.0, 2.0])
    R = []
    for j in range(3):
        t = np.zeros(12)
        t[[j, 6 + j]] = 1.0
        R.append(t)
        w = np.eye(3)[j]
        r = np.zeros(12)
        for a, x in enumerate(fr.nodes):
            r[6 * a : 6 * a + 3] = np.cross(w, x - p)
            r[6 * a + 3 : 6 * a + 6] = w
        R.append(r)
    R = np.array(R).T
    assert np.linalg.matrix_rank(R) == 6
    assert np.abs(K @ R).max() <= bound * np.abs(R).max() * 12


def test_consistent_and_lumped_mass_carry_the_element_mass():
    # Source: a rigid translation's kinetic energy is m v²/2 (m = ρA L) for any mass model
    # that contains the rigid motions; the torsional inertia is ρI_p L.
    for lumped in (False, True):
        m = beam3d_mass(78.5, 0.5, 3.0, lumped=lumped)
        assert np.array_equal(m, m.T)
        for j in range(3):
            t = np.zeros(12)
            t[[j, 6 + j]] = 1.0
            assert t @ m @ t == pytest.approx(78.5 * 3.0, rel=1e-14)
        t = np.zeros(12)
        t[[3, 9]] = 1.0
        assert t @ m @ t == pytest.approx(0.5 * 3.0, rel=1e-14)
        assert np.all(np.linalg.eigvalsh(m) > 0)


def test_local_axes_follow_the_vecxz_convention():
    # Source: the stated convention (OpenSees geomTransf Linear): v lies in the local x–z
    # plane on the side of +e_z, and (e_x, e_y, e_z) is right-handed orthonormal.
    rng = np.random.default_rng(3)
    for _ in range(20):
        d, v = rng.normal(size=3), rng.normal(size=3)
        R = local_axes(np.zeros(3), d, v)[0]
        for a, b in zip(R, axes_by_definition(d, v), strict=True):
            assert np.allclose(a, b, rtol=0, atol=10 * EPS)
        assert abs(v @ R[1]) <= 10 * EPS * np.linalg.norm(v) and v @ R[2] > 0
    with pytest.raises(ValueError, match="parallel"):
        local_axes(np.zeros(3), [0, 0, 2.0], [0, 0, -1.0])


@pytest.mark.parametrize("n_el", [1, 3])
def test_cantilever_biaxial_tip_deflections_and_torsion_are_exact(n_el):
    # Source: Euler–Bernoulli cantilever under tip loads: w = P L³/3EI in each bending
    # plane (I_z for the local y direction, I_y for local z), twist T L/GJ, elongation
    # P L/EA. Hermite elements are exact for nodal loads, so agreement is to round-off:
    # rel. error <= c n eps cond(K) (forward error of a backward-stable solve).
    d, v, L = np.array([1.0, 2.0, 2.0]), np.array([0.0, 0.0, 1.0]), 7.0
    fr = bar(n_el, d=d, vecxz=v, L=L)
    K, _, free = clamped(fr)
    bound = C_STABLE * len(free) * EPS * np.linalg.cond(K)
    ex, ey, ez = axes_by_definition(d, v)
    tip = 6 * n_el
    E, G, A, Iy, Iz, J = (SEC[k] for k in ("E", "G", "A", "I_y", "I_z", "J"))
    P = 1e3
    cases = [  # (force or moment, direction, tip dof block, expected along direction)
        ("f", ey, P * L**3 / (3 * E * Iz)),
        ("f", ez, P * L**3 / (3 * E * Iy)),
        ("f", ex, P * L / (E * A)),
        ("m", ex, P * L / (G * J)),
        ("m", ey, P * L / (E * Iy)),  # tip moment about e_y bends in the x–z plane
    ]
    for kind, e, expected in cases:
        f = np.zeros(fr.n_dof)
        o = tip + (0 if kind == "f" else 3)
        f[o : o + 3] = P * e
        u = np.zeros(fr.n_dof)
        u[free] = sla.solve(K, f[free], assume_a="pos")
        got = u[o : o + 3] @ e
        assert got == pytest.approx(expected, rel=bound), (kind, e)


def test_cantilever_bending_frequencies_converge_from_above_at_fourth_order():
    # Source: Euler–Bernoulli cantilever f_1 = 1.875² √(EI/(ρA L⁴))/2π in each principal
    # plane. Consistent mass is Rayleigh–Ritz: FE frequencies are upper bounds and, for
    # cubic Hermite elements, converge as O(h⁴) (Strang & Fix, An Analysis of the FEM,
    # Ch. 6); the fitted order must lie in [3.7, 4.3]. Torsion (linear elements): the
    # fixed-free shaft f = √(GJ/ρI_p)/4L converges from above as O(h²) (fitted >= 1.8).
    L = 2.0  # short: the first twist (≈ 310 Hz) within the lowest 8 modes
    exact = {
        k: BETA_L**2 * np.sqrt(SEC["E"] * SEC[k] / (SEC["rho_A"] * L**4)) / (2 * np.pi)
        for k in ("I_y", "I_z")
    }
    rho_Ip = SEC["rho_A"] * (SEC["I_y"] + SEC["I_z"]) / SEC["A"]
    exact["torsion"] = np.sqrt(SEC["G"] * SEC["J"] / rho_Ip) / (4 * L)
    ns = np.array([4, 8, 16])
    errs = {k: [] for k in exact}
    for n in ns:
        fr = bar(int(n), L=L)  # vertical, vecxz = X: x-sway bends about I_y, y-sway I_z
        m = fixed_base_modes_3d(fr, n_modes=8, method="dense")
        ph = m.full()
        first = {}
        for k in range(8):  # label by the dominant motion: x-sway, y-sway or twist
            e = (ph[0::6, k] ** 2).sum(), (ph[1::6, k] ** 2).sum(), (ph[5::6, k] ** 2).sum()
            first.setdefault(("I_y", "I_z", "torsion")[int(np.argmax(e))], m.f_hz[k])
        for key in exact:
            errs[key].append(first[key] / exact[key] - 1)
    for key, order_range in (("I_y", (3.7, 4.3)), ("I_z", (3.7, 4.3)), ("torsion", (1.8, 2.2))):
        e = np.array(errs[key])
        assert np.all(e > 0), (key, e)
        order = -np.polyfit(np.log(ns), np.log(e), 1)[0]
        assert order_range[0] <= order <= order_range[1], (key, order)


def test_lumped_mass_converges_to_the_same_cantilever_frequencies():
    # Source: as above; HRZ lumping is not a Ritz method (no bound) but converges at second
    # order (fitted >= 1.8) to the same Euler–Bernoulli limit in both bending planes.
    L = 10.0
    ns = np.array([4, 16, 64])
    for key, comp in (("I_y", 0), ("I_z", 1)):
        exact = BETA_L**2 * np.sqrt(SEC["E"] * SEC[key] / (SEC["rho_A"] * L**4)) / (2 * np.pi)
        errs = []
        for n in ns:
            m = fixed_base_modes_3d(bar(int(n), L=L), n_modes=2, lumped=True, method="dense")
            ph = m.full()
            k = int(np.argmax((ph[comp::6] ** 2).sum(axis=0)))  # the mode swaying that way
            errs.append(abs(m.f_hz[k] / exact - 1))
        assert errs[-1] < 1e-3
        assert -np.polyfit(np.log(ns), np.log(errs), 1)[0] >= 1.8


@pytest.mark.parametrize("plane", ["xz", "yz"])
def test_plane_frame_in_3d_equals_the_plane_frame(office, plane):
    # Source: a plane frame loaded in its plane has no out-of-plane response; its 3D
    # model must reproduce the plane model's displacements and modes. Both assemble the
    # same element matrices up to rounding (entries perturbed by ~c n eps relative), so
    # (forward error) displacements agree to c n eps cond(K), and eigenvalues of the
    # definite pencil to c n eps (cond K + cond M) (Rayleigh-quotient perturbation), with
    # n the plane model's clamped dofs; mode shapes to that over the relative gap.
    fr3 = Frame3D.from_planar(office, plane=plane, I_out=5 * office.I)
    idx, sign = planar_dofs(office.n_nodes, plane)
    K2, M2 = (A.toarray() for A in office.assemble())
    free2 = office.internal_dofs
    K2i, M2i = K2[np.ix_(free2, free2)], M2[np.ix_(free2, free2)]
    n = len(free2)
    eps_b = C_STABLE * n * EPS
    # static: a lateral load at every level and a vertical load on the roof
    f2 = np.zeros(office.n_dof)
    f2[3 * office.column_joints[1:, 0]] = 1e4
    f2[3 * office.level_nodes[-1] + 1] = -2e3
    u2 = np.zeros(office.n_dof)
    u2[free2] = sla.solve(K2i, f2[free2], assume_a="pos")
    K3, M3, free3 = clamped(fr3)
    f3 = np.zeros(fr3.n_dof)
    f3[idx] = sign * f2
    u3 = np.zeros(fr3.n_dof)
    u3[free3] = sla.solve(K3, f3[free3], assume_a="pos")
    bound = eps_b * np.linalg.cond(K2i)
    assert np.linalg.norm(sign * u3[idx] - u2) <= bound * np.linalg.norm(u2)
    out = np.setdiff1d(np.arange(fr3.n_dof), idx)
    assert np.abs(u3[out]).max() <= bound * np.abs(u2).max()
    # modes: every plane mode is a 3D mode with the same frequency and shape
    f2m, P2 = fixed_base_modes(K2, M2, office.boundary_dofs, n_modes=4)
    m3 = fixed_base_modes_3d(fr3, n_modes=24)
    P3 = m3.full()
    lam_bound = eps_b * (np.linalg.cond(K2i) + np.linalg.cond(M2i))
    lam2, lam3 = f2m**2, m3.f_hz**2
    for k in range(4):
        j = int(np.argmin(np.abs(lam3 - lam2[k])))
        assert abs(lam3[j] - lam2[k]) <= lam_bound * lam2[k], (k, lam3[j], lam2[k])
        gap = np.min(np.abs(np.delete(lam3, j) - lam3[j])) / lam3[j]
        v3 = sign * P3[idx, j]
        s = np.sign(v3 @ P2[:, k])
        assert np.linalg.norm(s * v3 - P2[:, k]) <= lam_bound / gap * np.linalg.norm(P2[:, k])


def test_from_planar_of_a_space_frame_is_a_type_error():
    # a Frame3D given where a plane Frame goes failed on its missing I (AttributeError)
    with pytest.raises(TypeError, match=r"^frame: expected a plane Frame .* got Frame3D$"):
        Frame3D.from_planar(bar(2))
