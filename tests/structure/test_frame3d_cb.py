"""Craig–Bampton reduction of space frames with the isolator nodes as the interface.

Sources: the Rayleigh–Ritz theory of the CB space (nsdyn.structure.reduction3d's docstring:
every CB eigenvalue of the model on boundary springs lies above the full one, decreases as
f_max grows through nested spaces, and λ_k ≤ λ̃_k ≤ λ_k / (1 − 2 λ_k/λ_c) with λ_c > (2π
f_max)²); statics (the constraint modes are the exact response to boundary displacements
with unloaded interior, and rigid translations are spanned by them); the plane frame as the
special case of the space frame (Frame3D.from_planar). Round-off bounds: a dense symmetric
solve carries relative error <= c n eps cond(K); eigenvalues of a definite pencil through
the same factorisation c n eps cond(K) λ/λ_1 (as in test_frame3d_building).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from nsdyn.structure import (
    Frame3D,
    Section3D,
    craig_bampton,
    fixed_base_modes_3d,
    load_frame,
    load_frame3d,
    regular_building_3d,
)
from nsdyn.structure.reduction3d import craig_bampton_3d

EPS = np.finfo(float).eps
C_STABLE = 10.0
E, G = 2.1e11, 8.1e10
COL = Section3D(E, G, 1e-2, 2e-4, 9e-5, 3e-5, 80.0)
BEAM = Section3D(E, G, 8e-3, 3e-4, 2e-5, 1e-6, 65.0)
DENSE = 10**6  # dense fixed-interface modes: the stated eigh round-off applies


def building() -> Frame3D:
    return regular_building_3d(
        "cb",
        [5.0, 7.0],
        [6.0],
        [4.0, 3.5, 3.5],
        COL,
        BEAM,
        BEAM,
        n_v=2,
        n_h=2,
        floor_mass=[3e4, 3e4, 2e4],
        mass_offset=(0.8, -0.4),
        zeta=0.05,
    )


def springs(frame: Frame3D, comps, k_h: float, k_v: float, k_r: float = 0.0) -> dict:
    """Isolator-like springs on the base nodes' dofs (component -> stiffness)."""
    ks = {0: k_h, 1: k_h, 2: k_v, 3: k_r, 4: k_r, 5: k_r}
    return {c: ks[c] for c in comps}


def supported_full(frame, spr):
    K, M = frame.reduced()
    K = K.toarray()
    for c, k in spr.items():
        K[frame.dofs(frame.base_nodes, c), frame.dofs(frame.base_nodes, c)] += k
    return K, M.toarray()


def supported_cb(cb, spr):
    K = cb.K.copy()
    for c, k in spr.items():
        idx = cb.boundary_index(c)
        K[idx, idx] += k
    return K, cb.M


@pytest.mark.parametrize("boundary", ["translations", "all"])
def test_cb_frequencies_converge_from_above_within_the_ritz_bound(boundary):
    b = building()
    comps = (0, 1, 2) if boundary == "translations" else tuple(range(6))
    m_tot = b.total_mass
    spr = springs(b, comps, m_tot * (2 * np.pi * 0.5) ** 2 / 6, 1e3 * m_tot, 1e8)
    Kf, Mf = supported_full(b, spr)
    lam = sla.eigh(Kf, Mf, eigvals_only=True)
    eb = C_STABLE * len(lam) * EPS * np.linalg.cond(Kf)
    prev = None
    for f_max in (8.0, 16.0, 32.0, 64.0):
        cb = craig_bampton_3d(b, f_max, boundary=boundary, dense_max=DENSE)
        assert np.all(cb.f_hz <= f_max) and cb.n_b == len(comps) * 6
        lt = sla.eigh(*supported_cb(cb, spr), eigvals_only=True)
        lc = (2 * np.pi * f_max) ** 2
        slack = eb * lam[: len(lt)] ** 2 / lam[0]
        assert np.all(lt >= lam[: len(lt)] - slack)  # Ritz: from above
        ok = 2 * lam[: len(lt)] < lc
        assert ok.sum() >= 3
        upper = lam[: len(lt)][ok] / (1 - 2 * lam[: len(lt)][ok] / lc)
        assert np.all(lt[ok] <= upper + slack[ok])
        if prev is not None:  # nested spaces: non-increasing
            n = len(prev)
            assert np.all(lt[:n] <= prev + eb * prev**2 / lam[0])
        prev = lt
    # all modes kept: the full model in another basis
    cb = craig_bampton_3d(b, np.inf, boundary=boundary, dense_max=DENSE)
    lt = sla.eigh(*supported_cb(cb, spr), eigvals_only=True)
    assert np.all(np.abs(lt - lam) <= eb * lam**2 / lam[0])


@pytest.mark.parametrize("boundary", ["translations", "all"])
def test_static_boundary_deformation_and_rigid_translation_are_reproduced(boundary):
    # Source: the constraint modes are the static response to unit boundary displacements
    # with the interior unloaded; K_r r = 0 puts the rigid translations in their span.
    b = building()
    cb = craig_bampton_3d(b, 6.0, boundary=boundary)
    K, _ = b.reduced()
    K = K.toarray()
    bd = np.concatenate([[b.dofs(n, c) for c in cb.components] for n in b.base_nodes])
    i = np.setdiff1d(np.arange(b.n_red), bd)
    rng = np.random.default_rng(7)
    ub = rng.standard_normal(len(bd)) * 1e-2
    ui = -np.linalg.solve(K[np.ix_(i, i)], K[np.ix_(i, bd)] @ ub)
    q = np.zeros(cb.n_red)
    q[: cb.n_b] = ub
    qr = cb.expand_reduced(q)
    tol = C_STABLE * len(i) * EPS * np.linalg.cond(K[np.ix_(i, i)]) * np.abs(ui).max()
    assert np.abs(qr[bd] - ub).max() == 0.0
    assert np.abs(qr[i] - ui).max() <= tol
    # the interior equations hold: no interior force from a boundary deformation
    assert np.abs((K @ qr)[i]).max() <= tol * np.abs(K).max()
    r = b.rigid_motions()[:, :3]
    assert np.abs(cb.expand_reduced(cb.Gamma) - r).max() <= 1e-12
    # boundary forces on isolator springs: Guyan's static condensation is exact
    spr = springs(b, cb.components, 1e7, 1e9, 1e8)
    Kf, _ = supported_full(b, spr)
    Kc, _ = supported_cb(cb, spr)
    fb = rng.standard_normal(cb.n_b) * 1e4
    f = np.zeros(b.n_red)
    f[bd] = fb
    u_full = np.linalg.solve(Kf, f)
    fc = np.zeros(cb.n_red)
    fc[: cb.n_b] = fb
    u_cb = cb.expand_reduced(np.linalg.solve(Kc, fc))
    tol = C_STABLE * b.n_red * EPS * np.linalg.cond(Kf) * np.abs(u_full).max()
    assert np.abs(u_cb - u_full).max() <= tol


def test_planar_frame_in_3d_reduces_to_the_planar_cb():
    # Source: the plane frame is the special case; its in-plane dofs (x, y, θ) are the 3D
    # (u_x, u_z, −θ_y). Fixed-interface frequencies of the 2D CB are among the 3D ones, and
    # on the same springs the 2D CB model's frequencies are among the 3D CB model's.
    boundary = "all"  # on pins alone a single plane frame turns about its base line
    f2 = load_frame("office-11")
    f3 = Frame3D.from_planar(f2, plane="xz")
    with pytest.raises(ValueError, match="mechanism or singular.*boundary='all'"):
        craig_bampton_3d(f3, 5.0, boundary="translations", dense_max=DENSE)
    f_max = 20.0
    K2, M2 = f2.assemble()
    K2 = K2.toarray() if hasattr(K2, "toarray") else K2
    M2 = M2.toarray() if hasattr(M2, "toarray") else M2
    per2 = (0, 1, 2) if boundary == "all" else (0, 1)
    bd2 = (3 * f2.base_nodes[:, None] + np.array(per2)).ravel()
    cb2 = craig_bampton(K2, M2, bd2, f_max, f2.zeta, r=f2.influence(), dense_max=DENSE)
    cb3 = craig_bampton_3d(f3, f_max, boundary=boundary, dense_max=DENSE)
    K3, _ = f3.reduced()
    eb = C_STABLE * f3.n_red * EPS * np.linalg.cond(K3.toarray() + np.eye(f3.n_red) * 1e3)
    l2, l3 = cb2.omega**2, cb3.omega**2
    assert len(l3) > len(l2) > 5
    for lam in l2:
        assert np.min(np.abs(l3 - lam)) <= eb * lam**2 / l2[0]
    # each in-plane mode is damped as the plane frame's: the ratio of its own mode (the 3D
    # frequency order put two soft out-of-plane modes first, which took the plane's first
    # two ratios and left the in-plane ones 5 % and 6 % where the plane has 3 % and 4 %)
    assert np.ptp(cb2.zeta) > 0
    for j, lam in enumerate(l2):
        assert cb3.zeta[np.argmin(np.abs(l3 - lam))] == cb2.zeta[j]
    # supported: 2D springs on (x, y[, θ]); the same on the 3D (u_x, u_z[, θ_y]) plus the
    # out-of-plane dofs
    k = {0: 5e6, 1: 1e10, 2: 1e8}
    K2s = cb2.K.copy()
    for j, c in enumerate(per2):
        idx = np.arange(len(f2.base_nodes)) * len(per2) + j
        K2s[idx, idx] += k[c]
    K3s = cb3.K.copy()
    for c3, kk in ((0, k[0]), (2, k[1]), (4, k[2]), (1, 5e6), (3, 1e8), (5, 1e8)):
        if c3 in cb3.components:
            idx = cb3.boundary_index(c3)
            K3s[idx, idx] += kk
    s2 = sla.eigh(K2s, cb2.M, eigvals_only=True)
    s3 = sla.eigh(K3s, cb3.M, eigvals_only=True)
    for lam in s2[:10]:
        assert np.min(np.abs(s3 - lam)) <= eb * lam**2 / s2[0]


def test_bad_input_is_named():
    b = building()
    with pytest.raises(ValueError, match="boundary: expected one of"):
        craig_bampton_3d(b, 5.0, boundary="pins")
    with pytest.raises(ValueError, match="f_max: expected a positive"):
        craig_bampton_3d(b, -1.0)
    with pytest.raises(ValueError, match="f_max = inf keeps all"):
        craig_bampton_3d(b, np.inf, dense_max=10)
    # coordinates of another model: numpy's "mismatch in its core dimension 0" before
    cb = craig_bampton_3d(b, 5.0)
    n_cb, n_r = cb.cb.T.shape[1], b.T.shape[1]
    with pytest.raises(ValueError, match=rf"^q: expected {n_cb} coordinates .*got shape \(3,\)"):
        cb.expand(np.zeros(3))
    with pytest.raises(ValueError, match=rf"^q_r: expected {n_r} coordinates"):
        b.expand(np.zeros((n_r + 1, 2)))
    assert cb.expand(np.zeros((n_cb, 4))).shape == (b.T.shape[0], 4)  # a history passes


@pytest.mark.slow
def test_3d_office_cb_at_5_hz_keeps_the_fixed_base_modes():
    # Source: with all six base dofs as the interface, the fixed-interface modes are the
    # clamped fixed-base modes (fixed_base_modes_3d, a separate solve); the model size is
    # 72 interface dofs plus the fixed-base modes up to 5 Hz (docs/guide/frames-3d.md).
    b = load_frame3d("office-11-3d")
    cb = craig_bampton_3d(b, 5.0, boundary="all")
    m = fixed_base_modes_3d(b, n_modes=cb.n_modes + 1)
    assert m.f_hz[-1] > 5.0 >= m.f_hz[-2]
    assert cb.f_hz == pytest.approx(m.f_hz[:-1], rel=1e-8)
    assert cb.n_red == 72 + cb.n_modes


def test_boundary_index_names_the_interface_components():
    cb = craig_bampton_3d(building(), 6.0, boundary="translations")
    n = len(cb.boundary_nodes)
    assert list(cb.boundary_index("uy")) == list(cb.boundary_index(1)) == list(range(1, 3 * n, 3))
    with pytest.raises(ValueError, match=r"'vy': expected one of \['ux', 'uy', 'uz'\]"):
        cb.boundary_index("vy")
    with pytest.raises(ValueError, match=r"'rz' is not an interface dof: \['ux', 'uy', 'uz'\]"):
        cb.boundary_index("rz")
