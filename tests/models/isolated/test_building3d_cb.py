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


def pinned_reference(frame):
    """Eigenvalues ω² of the frame with its base translations clamped (dense, independent of
    the reduction), with cond(K_ii) for the round-off bound."""
    K, M = frame.reduced()
    K, M = K.toarray(), M.toarray()
    b = np.concatenate([frame.dofs(frame.base_nodes, c) for c in (0, 1, 2)])
    i = np.setdiff1d(np.arange(frame.n_red), b)
    Kii, Mii = K[np.ix_(i, i)], M[np.ix_(i, i)]
    return sla.eigh(Kii, Mii, eigvals_only=True), np.linalg.cond(Kii), len(i)


def held(sys):
    """Eigenvalues of the pair system with every slip and contact row held (q = Q z, Q the null
    space of [D; R])."""
    A = np.vstack([sys.D.reshape(-1, sys.n), sys.R])
    Q = sla.null_space(A)
    return sla.eigh(Q.T @ sys.K @ Q, Q.T @ sys.M @ Q, eigvals_only=True)


@pytest.mark.parametrize("f_max", [6.0, 20.0])
def test_held_isolators_give_the_pinned_frames_modes_within_the_ritz_bound(f_max):
    frame = building()
    lam, cond, n = pinned_reference(frame)
    sys = building_pairs(frame, FPS, f_max=f_max, min_mass=None)
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
    lam, cond, n = pinned_reference(frame)
    full = building_pairs(frame, FPS, f_max=40.0, min_mass=None)
    thin = building_pairs(frame, FPS, f_max=40.0, min_mass=1e-3)
    frac, _ = mass_fractions(full.info["cb"])
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


def test_portal_cb_with_every_mode_equals_the_full_rung_and_the_frame_on_springs():
    frame = load_frame3d("portal-3d")
    full = building_pairs(frame, FPS, fidelity="full")
    f_top = full.info["f_hz"].max()
    cb = building_pairs(frame, FPS, f_max=1.01 * f_top, min_mass=None)
    assert cb.n == full.n == frame.n_red
    m = frame.total_mass
    k_h, k_v = m * (2 * np.pi * 0.5) ** 2 / 4, 1e3 * m  # isolator-like springs per bearing
    # the frame itself on the same springs (nodal coordinates, no reduction)
    K, M = frame.reduced()
    K, M = K.toarray(), M.toarray()
    for c, k in ((0, k_h), (1, k_h), (2, k_v)):
        d = frame.dofs(frame.base_nodes, c)
        K[d, d] += k
    lam = sla.eigh(K, M, eigvals_only=True)
    eb = C_STABLE * len(lam) * EPS * np.linalg.cond(K) * lam**2 / lam[0]
    for s in (full, cb):
        lt = sla.eigh(_springs(s, k_h, k_v), s.M, eigvals_only=True)
        assert np.all(np.abs(lt - lam) <= eb)
    # a lower cut-off stays above (Ritz) and within the bound
    low = building_pairs(frame, FPS, f_max=20.0, min_mass=None)
    lt = sla.eigh(_springs(low, k_h, k_v), low.M, eigvals_only=True)
    lc = (2 * np.pi * 20.0) ** 2
    assert np.all(lt >= lam[: len(lt)] - eb[: len(lt)])
    ok = 2 * lam[: len(lt)] < lc
    assert ok.sum() >= 3
    ref = lam[: len(lt)][ok]
    assert np.all(lt[ok] <= ref / (1 - 2 * ref / lc) + eb[: len(lt)][ok])


@pytest.mark.parametrize("which", ["building", "portal"])
def test_gamma_is_the_rigid_translation_and_carries_the_rigid_body_mass(which):
    frame = building() if which == "building" else load_frame3d("portal-3d")
    sys = building_pairs(frame, FPS, fidelity="cb", f_max=30.0, min_mass=None)
    cb = sys.info["cb"]
    r = frame.rigid_motions()[:, :3]
    _, cond, n = pinned_reference(frame)
    tol = C_STABLE * n * EPS * cond  # Ψ r_b = r_i through a solve with K_ii
    assert np.abs(cb.expand_reduced(sys.Gamma) - r).max() <= tol
    # M Γ equals the reduction of the frame's own rigid-body inertia M_r r
    _, Mr = frame.reduced()
    MGr = cb.cb.T.T @ (Mr @ r)
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
    _, cond, n = pinned_reference(frame)
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
    with pytest.raises(ValueError, match="fidelity: expected one of"):
        reduce_building(frame, "rigid", 5.0, None, False)
    with pytest.raises(ValueError, match="min_mass: expected"):
        building_pairs(frame, FPS, min_mass=2.0)
    office = load_frame3d("office-11-3d")
    n_int = office.n_red - 36
    assert n_int > FULL_MAX
    with pytest.raises(ValueError, match=rf"fidelity 'full'.* {n_int} internal dofs.*'cb'"):
        building_pairs(office, FPS, fidelity="full")
