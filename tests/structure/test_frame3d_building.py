"""Buildings in 3D: diaphragms, symmetric and eccentric plans, the bundled 3D office.

Sources: rigid-body kinematics (a free structure's rigid motions are in the null space of
K), the symmetry of a doubly symmetric building (translational pair degenerate, torsion
uncoupled), the closed-form single-storey model with an eccentric mass (Chopra, Dynamics of
Structures, Ch. 9.5 "unsymmetric-plan systems": 3 dofs U_x, U_y, Θ at the centre of mass,
column stiffness k = 3EI/h³ of a cantilever, torsion GJ/h), and seed 004's fixed-base
frequencies 0.46/1.27/1.98/2.98 Hz. Round-off bounds: eigenvalues through the Cholesky
factor of K carry relative error <= c n eps cond(K) λ/λ_1 (backward error c n eps of the
dense symmetric eigensolver on L⁻¹ M L⁻ᵀ, norm 1/λ_1, amplified by cond K in forming it);
a mode's component along a mode of another frequency is at most that over the relative gap.
"""

from __future__ import annotations

import numpy as np
import pytest

from nsdyn.structure import (
    Diaphragm,
    Frame3D,
    Section3D,
    fixed_base_modes_3d,
    load_frame,
    load_frame3d,
    regular_building_3d,
)

EPS = np.finfo(float).eps
C_STABLE = 10.0
E, G = 2.1e11, 8.1e10
COL = Section3D(E, G, 1e-2, 2e-4, 2e-4, 3e-4, 80.0)  # I_y = I_z: a square column
BEAM = Section3D(E, G, 8e-3, 3e-4, 2e-5, 1e-6, 65.0)  # strong axis vertical


def cond_bound(frame: Frame3D) -> float:
    """c n eps cond(K) of the clamped, diaphragm-constrained stiffness."""
    K, _ = frame.reduced()
    i = np.setdiff1d(np.arange(frame.n_red), frame.boundary_reduced)
    Kd = K[i][:, i].toarray()
    return C_STABLE * len(i) * EPS * np.linalg.cond(Kd)


def test_diaphragm_keeps_rigid_motions_free_of_strain():
    # Source: rigid-body kinematics: the constraint u = T u_r maps rigid motions of the
    # reduced model onto rigid motions of the frame, so K_r r = 0 and r^T M_r r = m.
    b = regular_building_3d(
        "b", [5.0, 7.0], [6.0], [3.5, 3.0], COL, BEAM, BEAM, 2, 2, [2e4, 1e4], zeta=0.05
    )
    K, M = b.reduced()
    r = b.rigid_motions(centre=(1.0, 2.0))
    scale = abs(K).max() * np.abs(r).max()
    assert np.abs(K @ r).max() <= C_STABLE * b.n_red * EPS * scale
    assert r[:, 0] @ (M @ r[:, 0]) == pytest.approx(b.total_mass, rel=1e-12)
    assert r[:, 2] @ (M @ r[:, 2]) == pytest.approx(b.total_mass, rel=1e-12)
    # the floor mass acts once horizontally (master) and once vertically (beam nodes)
    assert b.node_mass[:, 2].sum() == pytest.approx(3e4, rel=1e-14)
    assert b.node_mass[:, :2].sum() == 0.0


def test_doubly_symmetric_building_has_equal_pairs_and_uncoupled_torsion():
    # Source: a plan invariant under a quarter turn (square grid, I_y = I_z columns, the
    # same beams both ways, centred floor masses) has degenerate x/y frequency pairs; its
    # torsional modes carry no translational participation and vice versa. Bounds: see the
    # module docstring.
    b = regular_building_3d(
        "sym",
        [6.0, 6.0],
        [6.0, 6.0],
        [4.0, 3.5, 3.5],
        COL,
        BEAM,
        BEAM,
        2,
        2,
        [6e4, 6e4, 4e4],
        zeta=0.05,
    )
    m = fixed_base_modes_3d(b, n_modes=9, method="dense")
    lam = (2 * np.pi * m.f_hz) ** 2
    eb = cond_bound(b)
    tors = [k for k in range(9) if m.mass_fraction[k, 2] > 0.05]
    trans = [k for k in range(9) if m.mass_fraction[k, :2].sum() > 0.05]
    assert len(tors) >= 2 and len(trans) >= 4
    assert {m.family[k] for k in tors} == {"torsion"}
    for a, c in zip(trans[0::2], trans[1::2], strict=True):  # the pairs, ascending
        assert abs(lam[a] - lam[c]) <= eb * lam[c] / lam[0] * lam[c]
        # the computed pair's span is within angle s of the exact one (gap to every other
        # computed mode); a torsional component of size <= s gives Γ_θ²/J <= s, and each
        # fraction Γ²/m moves by at most 2s (δ(Γ²) = 2Γ δΓ with |Γ| <= √m, |δΓ| <= s√m)
        others = np.delete(lam, [a, c])
        s = eb * lam[c] / lam[0] / (np.min(np.abs(others - lam[a])) / lam[a])
        for k in (a, c):
            assert m.mass_fraction[k, 2] <= s
        # the pair together carries as much x as y participation
        fx, fy = m.mass_fraction[[a, c], 0].sum(), m.mass_fraction[[a, c], 1].sum()
        assert abs(fx - fy) <= 4 * s
        # and the pair's basis follows x and y (align_degenerate): any rotation of it is a
        # pair of modes, and the solver's came out as mixtures labelled x or y by chance
        assert (m.family[a], m.family[c]) == ("x", "y")
        assert m.mass_fraction[a, 1] <= 4 * s and m.mass_fraction[c, 0] <= 4 * s
    for t in tors:
        s = eb * lam[t] / lam[0] / (np.min(np.abs(np.delete(lam, t) - lam[t])) / lam[t])
        assert m.mass_fraction[t, :2].max() <= s


def test_mass_offset_moves_the_centre_of_mass_and_couples_torsion():
    # Source: statics: shifting every floor's mass by e moves the centre of mass of the
    # floors by e (members and vertical floor masses stay centred), i.e. by
    # e · m_floors / m_total; a doubly symmetric plan then couples translation and torsion
    # (nonzero cross participation, Chopra Ch. 9.5).
    kw = dict(zeta=0.05)
    sym = regular_building_3d(
        "s", [6.0, 6.0], [6.0, 6.0], [4.0, 3.5], COL, BEAM, BEAM, 1, 2, [6e4, 4e4], **kw
    )
    ecc = regular_building_3d(
        "e",
        [6.0, 6.0],
        [6.0, 6.0],
        [4.0, 3.5],
        COL,
        BEAM,
        BEAM,
        1,
        2,
        [6e4, 4e4],
        mass_offset=(0.6, 0.0),
        **kw,
    )
    ms, me = fixed_base_modes_3d(sym, n_modes=6), fixed_base_modes_3d(ecc, n_modes=6)
    assert np.allclose(ms.centre, [6.0, 6.0], rtol=0, atol=1e-9)
    assert ecc.total_mass == pytest.approx(sym.total_mass, rel=1e-14)
    ex = 0.6 * 1e5 / ecc.total_mass
    assert me.centre == pytest.approx([6.0 + ex, 6.0], rel=1e-12)
    # y and torsion: uncoupled to round-off in the symmetric building (the bound s of the
    # module docstring over the smallest relative gap), coupled far above it with e
    lam = ms.f_hz**2
    gap = np.min(np.diff(np.unique(np.round(lam / lam[0], 9)))) if len(lam) > 1 else 1.0
    s = cond_bound(sym) * lam[-1] / lam[0] / gap
    cross_sym = np.minimum(ms.mass_fraction[:, 1], ms.mass_fraction[:, 2]).max()
    cross_ecc = np.minimum(me.mass_fraction[:, 1], me.mass_fraction[:, 2]).max()
    assert cross_sym <= s < 1e-3 * cross_ecc


def one_storey(e_x: float, h=3.5, a=6.0, bw=4.0, m=2.0e4, J=None, n_el=3) -> Frame3D:
    """Four massless cantilever columns (corners of a × bw) tied at the top by a diaphragm
    whose mass sits e_x from the plan centre; columns have vecxz = X and I_y != I_z."""
    corners = [(0, 0), (a, 0), (a, bw), (0, bw)]
    nodes, el, dn = [], [], []
    for x, y in corners:
        ids = []
        for k in range(n_el + 1):
            ids.append(len(nodes))
            nodes.append((x, y, h * k / n_el))
        el += list(zip(ids[:-1], ids[1:], strict=True))
        dn.append(ids[-1])
    J = m * (a**2 + bw**2) / 12 if J is None else J
    d = Diaphragm(dn, (a / 2 + e_x, bw / 2), m, J)
    return Frame3D(
        "one-storey",
        np.array(nodes),
        np.array(el),
        (1.0, 0.0, 0.0),
        E,
        G,
        1e-2,
        2e-5,
        5e-5,
        4e-6,
        0.0,
        0.0,
        0.0,
        [0, n_el + 1, 2 * (n_el + 1), 3 * (n_el + 1)],
        [0.05],
        diaphragms=(d,),
    )


@pytest.mark.parametrize("e_x", [0.0, 0.6, 1.5])
def test_eccentric_mass_couples_y_and_torsion_as_the_three_dof_model_says(e_x):
    # Source: Chopra Ch. 9.5: with the mass centre C at e_x from the stiffness centre and
    # cantilever columns (x-stiffness k_x = 3EI_y/h³ for vecxz = X, k_y = 3EI_z/h³, twist
    # k_t = GJ/h), U_x decouples (ω² = 4k_x/m) and (U_y, Θ) obey
    #   [[4k_y, −4k_y e], [−4k_y e, K_θθ]] − ω² diag(m, J) singular,
    #   K_θθ = 4k_x (b/2)² + 4k_y ((a/2)² + e²) + 4k_t,
    # a quadratic in ω²; the mode ratio Θ/U_y = (ω² m − 4k_y)/(−4k_y e). Massless columns
    # statically condense exactly onto the three master dofs.
    h, a, bw, m = 3.5, 6.0, 4.0, 2.0e4
    J = m * (a**2 + bw**2) / 12
    fr = one_storey(e_x, h, a, bw, m, J)
    kx, ky, kt = 3 * E * 2e-5 / h**3, 3 * E * 5e-5 / h**3, G * 4e-6 / h
    Kyy, Kyt = 4 * ky, -4 * ky * e_x
    Ktt = 4 * kx * (bw / 2) ** 2 + 4 * ky * ((a / 2) ** 2 + e_x**2) + 4 * kt
    B, C = Kyy * J + Ktt * m, Kyy * Ktt - Kyt**2
    disc = np.sqrt(B**2 - 4 * m * J * C)
    lam_exact = np.sort([4 * kx / m, (B - disc) / (2 * m * J), (B + disc) / (2 * m * J)])
    for method in ("dense",):  # 3 massive dofs: too few for a Lanczos space
        md = fixed_base_modes_3d(fr, n_modes=3, method=method)
        lam = (2 * np.pi * md.f_hz) ** 2
        eb = cond_bound(fr)
        assert np.all(np.abs(lam - lam_exact) <= eb * lam_exact * lam_exact / lam_exact[0])
        Ux, Uy, Th = md.phi[fr.master_dofs[0]]
        for k in range(3):
            # M-norm error of mode k <= s (gap bound); components then within s/sqrt(m|J)
            gap = np.min(np.abs(np.delete(lam_exact, k) - lam_exact[k])) / lam_exact[k]
            s = eb * lam_exact[k] / lam_exact[0] / gap
            if k == int(np.argmin(np.abs(lam_exact - 4 * kx / m))):
                assert abs(Uy[k]) <= s / np.sqrt(m) and abs(Th[k]) <= s / np.sqrt(J)
                continue
            assert abs(Ux[k]) <= s / np.sqrt(m)
            if e_x == 0:
                assert min(abs(Uy[k]) * np.sqrt(m), abs(Th[k]) * np.sqrt(J)) <= s
            else:
                ratio = (lam_exact[k] * m - Kyy) / Kyt
                tol = s * (1 / (np.sqrt(J) * abs(Th[k])) + 1 / (np.sqrt(m) * abs(Uy[k])))
                assert Th[k] / Uy[k] == pytest.approx(ratio, rel=tol)


def test_bundled_3d_office_keeps_the_seed_frequencies_in_x():
    # Source: seed 004 Sect. 2: the office's transverse (plane-frame) fixed-base
    # frequencies 0.46 / 1.27 / 1.98 / 2.98 Hz. The 3D building repeats that frame six
    # times with six plane-frame levels of mass per floor, so its x family must meet the
    # seed's numbers within the plane frame's own tolerance (+-3 %); each level weighs
    # six plane-frame levels exactly (mass conservation of the construction).
    b = load_frame3d("office-11-3d")
    plane = load_frame("office-11")
    assert b.total_mass == pytest.approx(6 * plane.total_mass, rel=1e-12)
    assert len(b.base_nodes) == 12 and len(b.diaphragms) == 11
    m = fixed_base_modes_3d(b, n_modes=12)
    fx = m.f_hz[m.of_family("x")][:4]
    assert fx == pytest.approx([0.46, 1.27, 1.98, 2.98], rel=0.03)
    # two translational families and torsion, each led by a mode of large participation
    for fam, col in (("x", 0), ("y", 1), ("torsion", 2)):
        first = m.of_family(fam)[0]
        assert m.mass_fraction[first, col] > 0.6


def _hung_frame(nodes, elements, node_mass):
    vecxz = [(1.0, 0, 0), (0, 0, 1.0)][: len(elements)]  # (a column, a beam along x)
    return Frame3D("m", np.array(nodes), elements, vecxz, E, G, 1e-2, 1e-5, 1e-5, 1e-5,
                   10.0, None, node_mass, [0], [0.05],
                   diaphragms=(Diaphragm([1, 2], (0.5, 0.0), 0.0, 0.0),))  # fmt: skip


def test_a_node_on_a_diaphragm_and_no_member_is_refused_when_built():
    # node 2 is only on a diaphragm with node 1: the diaphragm holds its ux, uy and rz, its
    # uz, rx and ry have no stiffness (K singular); the loader named no node before
    with pytest.raises(ValueError, match=r"^nodes\[2\]: on a diaphragm and no element"):
        _hung_frame([[0.0, 0.0, 0.0], [0.0, 0.0, 3.0], [1.0, 0.0, 3.0]], [[0, 1]],
                    [[0, 0, 0], [0, 0, 0], [5.0, 5.0, 5.0]])  # fmt: skip


@pytest.mark.parametrize("method", ["dense", "sparse"])
def test_a_mechanism_is_reported_not_returned_as_modes(method):
    # a member 2-3 hangs from the diaphragm of nodes 1 and 2 only: the diaphragm holds their
    # ux, uy and rz, the member's uz and its tilt about the diaphragm's line are free, K is
    # singular (a mechanism), which must stop the eigensolver with a reason instead of
    # returning garbage modes
    fr = _hung_frame([[0.0, 0.0, 0.0], [0.0, 0.0, 3.0], [1.0, 0.0, 3.0], [2.0, 0.0, 3.0]],
                     [[0, 1], [2, 3]], [[0, 0, 0], [0, 0, 0], [5.0] * 3, [5.0] * 3])  # fmt: skip
    with pytest.raises(ValueError, match="mechanism|positive definite"):
        fixed_base_modes_3d(fr, n_modes=2, method=method)


def test_bad_building_input_is_refused_not_ignored():
    # a mass offset moves the diaphragms' mass; without diaphragms it would be dropped silently
    with pytest.raises(ValueError, match="mass_offset.*without diaphragms"):
        regular_building_3d(
            "b", [6.0], [6.0], [4.0], COL, BEAM, BEAM, floor_mass=1e4, diaphragms=False,
            mass_offset=(0.5, 0.0),
        )  # fmt: skip
    # a negative node index would tie another node (numpy counts from the end)
    nodes = np.array([[0.0, 0, 0], [0, 0, 3.0], [4.0, 0, 3.0]])
    with pytest.raises(ValueError, match="diaphragm 0: node index out of range"):
        Frame3D(
            "d", nodes, [[0, 1], [1, 2]], (0.0, 1.0, 0.0), E, G, 1e-2, 1e-5, 1e-5, 1e-5, 10.0,
            None, 0.0, [0], [0.05], diaphragms=(Diaphragm([1, -1], (2.0, 0.0), 1e3, 1e3),),
        )  # fmt: skip
    # a NaN damping ratio passed (NaN < 0 and NaN >= 1 are both false) and the modal response
    # failed later without naming zeta
    with pytest.raises(ValueError, match=r"zeta must be a non-empty list of damping ratios in \[0"
                       r".*got \[nan, 0.04\]"):  # fmt: skip
        regular_building_3d("b", [6.0], [6.0], [4.0], COL, BEAM, BEAM, floor_mass=1e4,
                            zeta=[float("nan"), 0.04])  # fmt: skip

    # a massless frame has no mode of finite frequency and no centre of mass: refused, not an
    # empty result with a NaN centre
    for mass, needle in (
        (0.0, "no mode of finite frequency"),
        ([[0, 0, 0]] * 2 + [[0, 0, 1e2]], "no horizontal mass"),
    ):
        fr = Frame3D(
            "m", nodes, [[0, 1], [1, 2]], (0.0, 1.0, 0.0), E, G, 1e-2, 1e-5, 1e-5, 1e-5, 0.0,
            None, mass, [0], [0.05],
        )  # fmt: skip
        with pytest.raises(ValueError, match=needle):
            fixed_base_modes_3d(fr, n_modes=3, method="dense")
    with pytest.raises(TypeError, match=r"^name: expected a frame's name"):  # (None was kept)
        regular_building_3d(None, [6.0], [6.0], [4.0], COL, BEAM, BEAM, floor_mass=1e4)
    # lumped="yes" was taken as True (text is truthy)
    b = regular_building_3d("b", [6.0], [6.0], [4.0], COL, BEAM, BEAM, floor_mass=1e4)
    with pytest.raises(TypeError, match=r"^lumped: expected True or False, got 'yes'"):
        fixed_base_modes_3d(b, n_modes=3, lumped="yes")
    # a bad section value names the element and the field
    with pytest.raises(ValueError, match=r"element 1: E must be finite and > 0, got -1.0"):
        Frame3D(
            "s", nodes, [[0, 1], [1, 2]], (0.0, 1.0, 0.0), [E, -1.0], G, 1e-2, 1e-5, 1e-5, 1e-5,
            10.0, None, 0.0, [0], [0.05],
        )  # fmt: skip


@pytest.mark.parametrize(
    ("kw", "err", "match"),
    [
        # each failed inside numpy or Python with a message naming no argument
        ({"bays_x": "6"}, ValueError, r"^bays_x: expected a non-empty list of finite numbers"),
        ({"storey_heights": []}, ValueError, r"^storey_heights: expected a non-empty list of "),
        ({"storey_heights": [[4.0]]}, ValueError, r"^storey_heights: expected a non-empty list"),
        ({"columns": 5}, TypeError, r"^columns: expected a Section3D or a list of them, got int"),
        ({"n_v": 1.5}, ValueError, r"^n_v: expected a whole number of elements per column"),
        ({"mass_offset": (0.1, 0.2, 0.3)}, ValueError, r"^mass_offset: expected 2 finite numbers"),
        ({"mass_offset": "0.1"}, ValueError, r"^mass_offset: expected 2 finite numbers"),
        ({"beam_x_vecxz": (1.0, 0.0)}, ValueError, r"^beam_x_vecxz: expected 3 finite numbers"),
        # "diaphragm mass must be >= 0 and finite", naming no argument
        ({"floor_mass": -1.0}, ValueError, r"^floor_mass: expected one value >= 0 or 1 of them"),
        ({"floor_mass": "1e4"}, ValueError, r"^floor_mass: expected a non-empty list of finite"),
    ],
)
def test_the_building_generator_names_an_argument_of_the_wrong_form(kw, err, match):
    args = {"floor_mass": 1e4, **kw}
    sizes = {k: args.pop(k) for k in ("bays_x", "storey_heights", "columns") if k in args}
    with pytest.raises(err, match=match):
        regular_building_3d("b", sizes.get("bays_x", [6.0]), [6.0],
                            sizes.get("storey_heights", [4.0]), sizes.get("columns", COL), BEAM,
                            BEAM, **args)  # fmt: skip


def test_auto_solves_densely_for_many_modes_and_sparsely_for_few(monkeypatch):
    # the documented rule of fixed_base_modes_3d: Lanczos for few modes of a large model, the
    # dense solve for more than 1/DENSE_FRACTION of them (Lanczos for 5000 of 5181 modes ran
    # for minutes without an end)
    from nsdyn.structure import modes3d

    b = regular_building_3d("b", [6.0, 6.0, 6.0], [6.0, 6.0], [4.0, 3.5, 3.5], COL, BEAM, BEAM,
                            2, 2, [6e4, 6e4, 4e4], zeta=0.05)  # fmt: skip
    n = b.n_red - len(b.boundary_reduced)
    assert modes3d.DENSE_MAX < n <= modes3d.DENSE_MANY_MAX

    def refused(*_):
        raise AssertionError("the other eigensolver")

    monkeypatch.setattr(modes3d, "_eig_sparse", refused)
    many = n // modes3d.DENSE_FRACTION + 1
    assert len(fixed_base_modes_3d(b, n_modes=many).f_hz) == many
    monkeypatch.undo()
    monkeypatch.setattr(modes3d, "_eig_dense", refused)
    assert len(fixed_base_modes_3d(b, n_modes=12).f_hz) == 12
