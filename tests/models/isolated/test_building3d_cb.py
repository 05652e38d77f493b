"""The cb and full rungs of a space frame on isolators: the pair system's matrices.

Sources: the fixed-interface modes of the Craig–Bampton space are the frame's modes with the
interface held (here pinned feet: the base translations clamped, rotations free), and the CB
space is a Ritz space, so on any springs its eigenvalues obey λ_k ≤ λ̃_k ≤ λ_k/(1 − 2λ_k/λ_c)
(nsdyn.structure.reduction3d's docstring); with every mode kept it is the full model in
another basis; rigid translations lie in the constraint modes' span (K r = 0), so T Γ = r and
Γᵀ M Γ is the rigid-body mass: the sum of member, node and floor masses (x and y) and of
member and node masses (z; the diaphragms' mass acts in their plane only). Round-off: a
dense symmetric-definite eigenproblem through a factor of K carries c n eps cond(K) λ²/λ_1
(as tests/structure/test_frame3d_cb.py); sums over ~10³ mass entries 10³ eps relative.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from nsdyn.models.isolated.bearings import Bearing, BearingError, Friction
from nsdyn.models.isolated.building3d_cb import (
    FULL_MAX,
    base_grid,
    building_pairs,
    mass_fractions,
    reduce_building,
)
from nsdyn.structure import Section3D, load_frame3d, regular_building_3d

EPS = np.finfo(float).eps
C_STABLE = 10.0
E, G = 2.1e11, 8.1e10
COL = Section3D(E, G, 1e-2, 2e-4, 9e-5, 3e-5, 80.0)
BEAM = Section3D(E, G, 8e-3, 3e-4, 2e-5, 1e-6, 65.0)
FPS = Bearing(Friction(0.05), radius=2.0)


def building():
    return regular_building_3d("cb3", [5.0, 7.0], [6.0], [4.0, 3.5, 3.5], COL, BEAM, BEAM,
                               n_v=2, n_h=2, floor_mass=[3e4, 3e4, 2e4], mass_offset=(0.8, -0.4),
                               zeta=0.05)  # fmt: skip


def pinned_reference(frame, base="pinned"):
    """Eigenvalues ω² of the frame with its base translations clamped (dense, independent of
    the reduction; with base="grid" the frame with its feet tied, base_grid), with cond(K)
    of the held model for the round-off bound and its size."""
    model = base_grid(frame) if base == "grid" else frame
    K, M = model.reduced()
    K, M = K.toarray(), M.toarray()
    rows = np.concatenate([model.dofs(model.base_nodes, c) for c in (0, 1, 2)])
    Q = sla.null_space(model.T[rows].toarray())  # q_r with every foot's translation zero
    Kh, Mh = Q.T @ K @ Q, Q.T @ M @ Q
    return sla.eigh(Kh, Mh, eigvals_only=True), np.linalg.cond(Kh), len(Kh)


def held(sys):
    """Eigenvalues of the pair system with every slip and contact row held (q = Q z, Q the null
    space of [D; R])."""
    A = np.vstack([sys.D.reshape(-1, sys.n), sys.R])
    Q = sla.null_space(A)
    return sla.eigh(Q.T @ sys.K @ Q, Q.T @ sys.M @ Q, eigvals_only=True)


@pytest.mark.parametrize("base", ["pinned", "grid"])
@pytest.mark.parametrize("f_max", [6.0, 20.0])
def test_held_isolators_give_the_fixed_base_frames_modes_within_the_ritz_bound(f_max, base):
    frame = building()
    lam, cond, n = pinned_reference(frame, base)
    sys = building_pairs(frame, FPS, f_max=f_max, min_mass=None, base=base)
    lt = held(sys)
    wc = (2 * np.pi * f_max) ** 2
    assert len(lt) == np.count_nonzero(lam <= wc) >= 3  # every mode below f_max, none above
    lc = lam[len(lt)]  # the lowest dropped ω²
    ref = lam[: len(lt)]
    slack = C_STABLE * n * EPS * cond * ref**2 / lam[0]
    assert np.all(lt >= ref - slack)
    ok = 2 * ref < lc
    assert np.all(lt[ok] <= ref[ok] / (1 - 2 * ref[ok] / lc) + slack[ok])
    # the fixed-interface modes are the held system's exact modes: equal to round-off
    assert np.all(np.abs(lt - ref) <= slack)


def test_participation_filter_keeps_a_subset_of_the_pinned_modes():
    frame = building()
    lam, cond, n = pinned_reference(frame, "grid")
    full = building_pairs(frame, FPS, f_max=40.0, min_mass=None)
    thin = building_pairs(frame, FPS, f_max=40.0, min_mass=1e-3)
    frac = mass_fractions(full.info["frame"], full.info["cb"])
    kept = frac.max(axis=1) >= 1e-3
    assert 0 < kept.sum() < len(kept) and thin.info["n_modes"] == kept.sum()
    assert thin.info["dropped_mass"] == pytest.approx(frac[~kept].sum(axis=0), rel=1e-12)
    lt = held(thin)
    slack = C_STABLE * n * EPS * cond * lam[len(lt)] ** 2 / lam[0]
    for v in lt:  # each held eigenvalue is one of the frame's
        assert np.min(np.abs(lam - v)) <= slack


def _springs(sys, k_h, k_v):
    D2 = sys.D.reshape(-1, sys.n)
    return sys.K + k_h * D2.T @ D2 + k_v * sys.R.T @ sys.R


@pytest.mark.parametrize("base", ["pinned", "grid"])
def test_portal_cb_with_every_mode_equals_the_full_rung_and_the_frame_on_springs(base):
    frame = load_frame3d("portal-3d")
    full = building_pairs(frame, FPS, fidelity="full", base=base)
    f_top = full.info["f_hz"].max()
    cb = building_pairs(frame, FPS, f_max=1.01 * f_top, min_mass=None, base=base)
    model = full.info["frame"]
    assert cb.n == full.n == model.n_red
    m = frame.total_mass
    k_h, k_v = m * (2 * np.pi * 0.5) ** 2 / 4, 1e3 * m  # isolator-like springs per bearing
    # the frame itself on the same springs under every foot (no reduction)
    K, M = model.reduced()
    K, M = K.toarray(), M.toarray()
    for c, k in ((0, k_h), (1, k_h), (2, k_v)):
        B = model.T[model.dofs(model.base_nodes, c)].toarray()
        K += k * B.T @ B
    lam = sla.eigh(K, M, eigvals_only=True)
    eb = C_STABLE * len(lam) * EPS * np.linalg.cond(K) * lam**2 / lam[0]
    for s in (full, cb):
        lt = sla.eigh(_springs(s, k_h, k_v), s.M, eigvals_only=True)
        assert np.all(np.abs(lt - lam) <= eb)
    # a lower cut-off stays above (Ritz) and within the bound
    low = building_pairs(frame, FPS, f_max=20.0, min_mass=None, base=base)
    lt = sla.eigh(_springs(low, k_h, k_v), low.M, eigvals_only=True)
    lc = (2 * np.pi * 20.0) ** 2
    assert np.all(lt >= lam[: len(lt)] - eb[: len(lt)])
    ok = 2 * lam[: len(lt)] < lc
    assert ok.sum() >= 3
    ref = lam[: len(lt)][ok]
    assert np.all(lt[ok] <= ref / (1 - 2 * ref / lc) + eb[: len(lt)][ok])


@pytest.mark.parametrize("base", ["pinned", "grid"])
@pytest.mark.parametrize("which", ["building", "portal"])
def test_gamma_is_the_rigid_translation_and_carries_the_rigid_body_mass(which, base):
    frame = building() if which == "building" else load_frame3d("portal-3d")
    sys = building_pairs(frame, FPS, fidelity="cb", f_max=30.0, min_mass=None, base=base)
    cb, model = sys.info["cb"], sys.info["frame"]
    r = model.rigid_motions()[:, :3]
    _, cond, n = pinned_reference(frame, base)
    tol = C_STABLE * n * EPS * cond  # Ψ r_b = r_i through a solve with K_ii
    assert np.abs(cb.T @ sys.Gamma - r).max() <= tol
    # M Γ equals the reduction of the frame's own rigid-body inertia M_r r
    _, Mr = model.reduced()
    MGr = cb.T.T @ (Mr @ r)
    assert np.abs(sys.M @ sys.Gamma - MGr).max() <= tol * np.abs(MGr).max()
    members = float(np.sum(frame.rho_A * frame.lengths))
    m_xy = members + frame.node_mass[:, 0].sum() + sum(d.mass for d in frame.diaphragms)
    m_z = members + frame.node_mass[:, 2].sum()
    GMG = sys.Gamma.T @ sys.M @ sys.Gamma
    ref = np.diag([m_xy, m_xy, m_z])
    assert np.abs(GMG - ref).max() <= (tol + 1e3 * EPS) * m_xy


def test_outputs_map_q_to_floor_motions_and_drifts():
    # a rigid translation of the whole building moves every floor by it and drifts nothing
    frame = building()
    sys = building_pairs(frame, FPS, f_max=20.0)
    nl = len(sys.info["levels_z"])
    _, cond, n = pinned_reference(frame, "grid")
    tol = C_STABLE * n * EPS * cond  # T Γ = r to the round-off of Ψ (a solve with K_ii)
    U = sys.T @ sys.Gamma  # (3 nl, 3)
    assert sys.T.shape == (3 * nl, sys.n)
    ref = np.zeros((nl, 3, 3))
    ref[:, 0, 0] = ref[:, 1, 1] = 1.0  # x, y translations; z moves no floor in plan
    assert np.abs(U.reshape(nl, 3, 3) - ref).max() <= tol
    h = sys.info["heights"].min()
    assert np.abs(sys.info["drift_cm_map"] @ sys.Gamma).max() <= 2 * tol / h
    assert np.abs(sys.info["drift_corner_map"] @ sys.Gamma).max() <= 2 * tol / h


def test_bad_input_is_named():
    frame = building()
    with pytest.raises(BearingError, match="bearings: expected one bearing or 6"):
        building_pairs(frame, (FPS, FPS))
    # a list of one is one bearing for all, as the bearing itself is (it was refused with
    # "expected one bearing ..., got 1"): the same model, bearing for bearing
    from nsdyn.models.isolated.building3d import building_deck

    assert building_pairs(frame, [FPS]).bearings == building_pairs(frame, FPS).bearings
    assert building_deck(frame, [FPS]).bearings == building_deck(frame, FPS).bearings
    with pytest.raises(ValueError, match="fidelity: expected one of"):
        reduce_building(frame, "rigid")
    with pytest.raises(ValueError, match="base: expected one of"):
        building_pairs(frame, FPS, base="slab")
    with pytest.raises(ValueError, match="f_max: expected a positive"):
        building_pairs(frame, FPS, f_max=-2.0)
    with pytest.raises(ValueError, match="min_mass: expected"):
        building_pairs(frame, FPS, min_mass=2.0)
    # a scalar was "'float' object is not iterable", text was read character by character
    for ecc in (0.05, "0.05", (0.1, 0.2, 0.3)):
        with pytest.raises(ValueError, match=r"^eccentricity: expected a pair \(f_x, f_y\)"):
            building_pairs(frame, FPS, eccentricity=ecc)
    office = load_frame3d("office-11-3d")
    n_int = office.n_red - 36  # pinned: three interface dofs per foot
    assert n_int > FULL_MAX
    with pytest.raises(ValueError, match=rf"fidelity 'full'.* {n_int} internal dofs.*'cb'"):
        building_pairs(office, FPS, fidelity="full", base="pinned")


# ---- runs (simulate_pairs) -------------------------------------------------------------


def _record(scale_y=1.0, scale_z=1.0, t_end=10.0, factor=1.0):
    from nsdyn.ground import read_motion3

    t0, dt, ax, ay, az = read_motion3("synthetic-wn-40s").as_arrays()
    n = int(round(t_end / dt)) + 1
    return (t0, dt, factor * ax[:n], scale_y * factor * ay[:n], scale_z * factor * az[:n])


def symmetric_building(scale: float):
    # equal bays: the vertical and horizontal mass centres coincide (the rigid deck puts the
    # weight at the horizontal centre of mass)
    col = Section3D(E * scale, G * scale, 1e-2, 2e-4, 9e-5, 3e-5, 80.0)
    beam = Section3D(E * scale, G * scale, 8e-3, 3e-4, 2e-5, 1e-6, 65.0)
    return regular_building_3d("sym", [6.0, 6.0], [5.0], [4.0, 3.5, 3.5], col, beam, beam,
                               n_v=2, n_h=2, floor_mass=[3e4, 3e4, 2e4], zeta=0.05)  # fmt: skip


def test_a_stiff_building_on_isolators_moves_as_the_rigid_deck():
    # Rigid-body limit: the building's deformation under the isolated motion is of relative
    # size (ω_iso/ω_1)² (quasi-static response of its first mode, ω_iso = √(g/R) the pendulum
    # frequency), so with E scaled by s the cb rung's peak isolator displacement tends to the
    # rigid deck's within 10 (f_iso/f_1)² plus the two runs' integration error (steps × rtol).
    from nsdyn.models.isolated.building3d import building_deck
    from nsdyn.models.isolated.building3d_response import run_building
    from nsdyn.models.isolated.deck import simulate_plane

    ground, kw = _record(), {"law": "arctan", "rtol": 1e-8, "atol": (1e-10, 1e-10)}
    rigid = simulate_plane(building_deck(symmetric_building(1.0), FPS), ground, **kw)
    u_rigid = float(rigid.resultant(rigid.u).max())
    s = 1e4
    sys = building_pairs(symmetric_building(s), FPS, f_max=30.0)
    r = run_building(sys, ground, **kw).result
    f1 = np.sqrt(s) * pinned_reference(symmetric_building(1.0), "grid")[0][0] ** 0.5 / (2 * np.pi)
    f_iso = np.sqrt(9.80665 / FPS.radius) / (2 * np.pi)
    tol = 10 * (f_iso / f1) ** 2 + (rigid.stats["steps"] + r.stats["steps"]) * kw["rtol"]
    assert tol < 1e-3
    assert float(r.resultant(r.u).max()) == pytest.approx(u_rigid, rel=tol)


def test_a_symmetric_portal_moved_along_x_has_no_y_response_and_no_torsion(assert_round_trip):
    # The portal is mirror-symmetric about its mid-plane y = 2.5 m, and so is a ground motion
    # along x: the y slips, y drifts, y base shear, torsional moment and floor twist vanish
    # exactly; what is left is round-off of forming M⁻¹K, M⁻¹C (relative c n eps cond(M))
    from nsdyn.models.isolated.building3d_response import run_building

    sys = building_pairs(load_frame3d("portal-3d"), FPS, f_max=100.0)
    r = run_building(sys, _record(0.0, 0.0, factor=1 / 3), law="arctan")
    assert r.result.uplift is None
    rel = C_STABLE * sys.n * EPS * np.linalg.cond(sys.M)
    u, size = r.result.u, 6.0
    assert np.abs(u[..., 1]).max() <= rel * np.abs(u[..., 0]).max()
    assert np.abs(r.drifts.cm[:, 1]).max() <= rel * np.abs(r.drifts.cm[:, 0]).max()
    assert np.abs(r.drifts.corner[:, :, 1]).max() <= rel * np.abs(r.drifts.corner[:, :, 0]).max()
    assert np.abs(r.base_shear[1]).max() <= rel * np.abs(r.base_shear[0]).max()
    assert np.abs(r.torsion).max() <= rel * size * np.abs(r.base_shear[0]).max()
    theta = r.result.outputs[:, 2::3]
    assert np.abs(theta).max() <= rel * np.abs(u[..., 0]).max() / size
    rc = r.roof_corner  # (4, 2, nt): the untwisted roof moves alike at its four corners
    assert np.abs(rc[:, 1]).max() <= rel * np.abs(rc[:, 0]).max()
    assert np.abs(rc[:, 0] - rc[:1, 0]).max() <= rel * np.abs(rc[:, 0]).max()
    assert_round_trip(r)  # (the response had no tables)
    np.testing.assert_array_equal(r.histories()["roof_corner_y_{}_m"][:, 3], rc[3, 1])
    assert len(repr(r)) < 2000  # (its arrays were printed in full: 25 000 characters)


def _motion():
    from nsdyn.ground import read_motion3

    return read_motion3("synthetic-wn-40s")


def test_advisor_picks_the_rigid_deck_for_a_stiff_building_and_fixed_when_nothing_slides():
    # the rigid-body limit above: a stiff building's cb peaks equal the rigid deck's far
    # within tol, so the cheaper rigid rung answers; with friction μ = 0.3 above the record's
    # resultant PGA scaled to 1 m/s² (< 0.3 g) a stiff building never slides: the fixed rung
    from nsdyn.studies.advisor import advise_3d

    kw = {"solver": {"law": "arctan"}, "f_max": 30.0}
    b = symmetric_building(1e4)
    a = advise_3d(b, FPS, _motion(), **kw)
    assert a.fidelity == "rigid"
    assert max(a.evidence["probes"][0]["errors"].values()) <= 0.05
    assert "advised model: rigid" in a.report()
    sticky = Bearing(Friction(0.3), radius=2.0)
    weak = _motion().scaled_to_pga(1.0)
    assert weak.pga_resultant < 0.3 * 9.80665
    a = advise_3d(b, sticky, weak, **kw)
    assert a.fidelity == "fixed" and a.evidence["cb_probe"]["stick_fraction"] == 1.0
    # drifts need the elastic building: never the rigid deck
    a = advise_3d(b, FPS, _motion(), metrics=("isolator_displacement", "drift"), **kw)
    assert a.fidelity == "cb" and a.evidence["probes"] == []


@pytest.mark.parametrize("base", ["pinned", "grid"])
def test_the_rest_state_carries_the_weight_on_held_contacts(base):
    # statics: R q₀ = 0 exactly (the contact rows' coordinates are removed), Σ λ = m_z g
    # (vertical equilibrium of the whole building: Rᵀλ balances Γ_zᵀ M Γ_z g, since Γ_zᵀ K = 0
    # and the slip rows carry no vertical load), and the equations K* q₀ = −M Γ_z g + Rᵀ λ hold
    # to the round-off of a Cholesky solve, c n eps cond(K*) |f|
    frame = building()
    sys = building_pairs(frame, FPS, f_max=20.0, base=base)
    q0, lam = sys.info["y0"][: sys.n], sys.info["static_normal"]
    assert np.all(sys.R @ q0 == 0.0) and np.all(lam > 0)
    m_z = float(np.sum(frame.rho_A * frame.lengths) + frame.node_mass[:, 2].sum())
    assert lam.sum() == pytest.approx(m_z * sys.g, rel=1e3 * EPS)
    D2 = sys.D.reshape(-1, sys.n)
    Ks = sys.K + D2.T @ ((np.repeat(lam, 2) / FPS.radius)[:, None] * D2)
    f = -sys.M @ sys.Gamma[:, 2] * sys.g
    res = Ks @ q0 - f - sys.R.T @ lam
    free = np.flatnonzero(~np.any(sys.R, axis=0))
    bound = C_STABLE * sys.n * EPS * np.linalg.cond(Ks[np.ix_(free, free)]) * np.abs(f).max()
    assert np.abs(res).max() <= bound
    q_own, lam_own = sys.static_equilibrium()  # the pair system starts from this state
    assert np.array_equal(q_own, q0) and np.array_equal(lam_own, lam)


def test_flat_sliders_without_rubber_start_with_every_slip_at_zero():
    """Flat sliders (infinite radius, no rubber) give K* no stiffness along the slips: its
    in-plane rigid motions are null directions, which gravity (vertical) does not load, and
    friction holds the isolators where they start. The static state must carry no slip and
    its normal forces must carry the weight exactly (sum of λ = m g). A Cholesky factor of
    the singular K* exists in round-off and gave centimetres of arbitrary slip."""
    flat = Bearing(Friction(0.05), radius=np.inf)
    sys = building_pairs(building(), flat, f_max=5.0)
    q0, lam0 = sys.static_equilibrium()
    slips = sys.D.reshape(-1, sys.n) @ q0
    r_z = sys.Gamma[:, 2]  # the rigid vertical translation: its mass is the building's
    weight = float(r_z @ sys.M @ r_z) * sys.g
    assert np.abs(slips).max() <= 1e-12
    assert lam0.sum() == pytest.approx(weight, rel=1e-9)
