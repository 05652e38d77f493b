"""Storey drifts at the centre of mass and at the plan corners; accidental eccentricity.

Sources: the one-storey building on four cantilever columns (Chopra, Dynamics of Structures,
Ch. 9.5, unsymmetric-plan systems): column stiffnesses k_x = 3EI_y/h³ (vecxz = X), k_y =
3EI_z/h³, twist k_t = GJ/h, stiffness centre at the plan centre, so that a force F_y at the
centre of mass e_x from it gives U_y = F/4k_y there and Θ = F e_x / K_θθ, K_θθ = 4k_x (b/2)² +
4k_y (a/2)² + 4k_t, and a plan point at x moves U_y + (x − a/2) Θ; its three-dof eigenproblem
[[4k_y, −4k_y e], [−4k_y e, K_θθ + 4k_y e²]] − ω² diag(m, J) for (U_y, Θ) at the centre of
mass, U_x uncoupled at ω² = 4k_x/m. Hermite columns are exact for end loads, so the frame
meets these to round-off: c n eps cond(K) (relative), and eigenvalues to c n eps cond(K)
λ/λ_1 (as in test_frame3d_building).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from nsdyn.structure import Diaphragm, Frame3D, fixed_base_modes_3d, load_frame3d
from nsdyn.structure.storey3d import accidental_eccentricity, storey_drifts_3d

EPS = np.finfo(float).eps
C_STABLE = 10.0
E, G = 2.1e11, 8.1e10
H, A_, B_, M_ = 3.5, 6.0, 4.0, 2.0e4
I_Y, I_Z, J_T = 2e-5, 5e-5, 4e-6
KX, KY, KT = 3 * E * I_Y / H**3, 3 * E * I_Z / H**3, G * J_T / H
KTT = 4 * KX * (B_ / 2) ** 2 + 4 * KY * (A_ / 2) ** 2 + 4 * KT


def one_storey(e_x: float = 0.0, n_el: int = 3) -> Frame3D:
    corners = [(0, 0), (A_, 0), (A_, B_), (0, B_)]
    nodes, el, top = [], [], []
    for x, y in corners:
        ids = []
        for k in range(n_el + 1):
            ids.append(len(nodes))
            nodes.append((x, y, H * k / n_el))
        el += list(zip(ids[:-1], ids[1:], strict=True))
        top.append(ids[-1])
    J = M_ * (A_**2 + B_**2) / 12
    d = Diaphragm(top, (A_ / 2 + e_x, B_ / 2), M_, J)
    base = [0, n_el + 1, 2 * (n_el + 1), 3 * (n_el + 1)]
    return Frame3D(
        "one", np.array(nodes), np.array(el), (1.0, 0.0, 0.0), E, G, 1e-2, I_Y, I_Z, J_T,
        0.0, 0.0, 0.0, base, [0.05], diaphragms=(d,),
    )  # fmt: skip


def static(frame: Frame3D, load: dict) -> tuple[np.ndarray, float]:
    """Full displacements under master loads {(diaphragm, 0|1|2): value}, clamped base, and
    the round-off bound c n eps cond(K_ii)."""
    K, _ = frame.reduced()
    i = np.setdiff1d(np.arange(frame.n_red), frame.boundary_reduced)
    f = np.zeros(frame.n_red)
    for (k, j), v in load.items():
        f[frame.master_dofs[k, j]] = v
    q = np.zeros(frame.n_red)
    Kii = K[i][:, i]
    q[i] = spla.spsolve(Kii.tocsc(), f[i])
    return frame.expand(q), C_STABLE * len(i) * EPS * np.linalg.cond(Kii.toarray())


@pytest.mark.parametrize("e_x", [0.0, 0.9])
def test_corner_drifts_of_a_one_storey_building_under_a_force_at_the_mass_centre(e_x):
    fr = one_storey(e_x)
    F = 1e5
    u, eb = static(fr, {(0, 1): F})
    d = storey_drifts_3d(fr, u)
    th = F * e_x / KTT
    uy_s = F / (4 * KY)
    assert d.heights == pytest.approx([H], rel=1e-15)
    assert d.cm[0, 1] == pytest.approx((uy_s + e_x * th) / H, rel=eb)
    assert abs(d.cm[0, 0]) <= eb * uy_s / H
    for k, (x, y) in enumerate(d.corners):
        assert d.corner[0, k, 1] == pytest.approx((uy_s + (x - A_ / 2) * th) / H, rel=eb)
        assert d.corner[0, k, 0] == pytest.approx(-(y - B_ / 2) * th / H, abs=eb * uy_s / H)
    amp = (uy_s + A_ / 2 * th) / (uy_s + e_x * th)
    assert d.amplification[0, 1] == pytest.approx(amp, rel=4 * eb)
    if e_x == 0:  # a floor that only translates: every point drifts alike
        assert d.amplification[0, 1] == pytest.approx(1.0, rel=4 * eb)


def test_torsional_mode_drifts_only_at_the_corners():
    # Source: rigid floor kinematics: a pure twist Θ about the centre of mass moves a corner
    # (x, y) by (−(y − y_c) Θ, (x − x_c) Θ) and the centre not at all.
    fr = one_storey(0.0)
    m = fixed_base_modes_3d(fr, n_modes=3, method="dense")
    k = int(np.argmax(m.mass_fraction[:, 2]))
    u = m.full()[:, k]
    th = m.phi[fr.master_dofs[0, 2], k]
    d = storey_drifts_3d(fr, u)
    # the computed mode's translation is round-off: <= s/√m, s = eb λ_k/λ_1 over the gap
    K, _ = fr.reduced()
    i = np.setdiff1d(np.arange(fr.n_red), fr.boundary_reduced)
    eb = C_STABLE * len(i) * EPS * np.linalg.cond(K[i][:, i].toarray())
    lam = m.f_hz**2
    gap = np.min(np.abs(np.delete(lam, k) - lam[k])) / lam[k]
    tol = eb * lam[k] / lam[0] / gap / np.sqrt(M_) / H
    assert np.abs(d.cm[0]).max() <= tol
    for j, (x, y) in enumerate(d.corners):
        want = np.array([-(y - B_ / 2), x - A_ / 2]) * th / H
        assert np.abs(d.corner[0, j] - want).max() <= tol
        assert np.abs(want).max() > 1e6 * tol
    # a time history (trailing axis) gives the same numbers column by column
    dd = storey_drifts_3d(fr, np.stack([u, 2 * u], axis=1))
    assert dd.corner.shape == (1, 4, 2, 2)
    assert np.allclose(dd.corner[..., 1], 2 * d.corner, rtol=1e-14, atol=0)


@pytest.mark.parametrize("frac", [0.05, -0.05])
def test_a_five_percent_shift_couples_as_the_three_dof_model_says(frac):
    fr = accidental_eccentricity(one_storey(0.0), f_x=frac)
    d0 = fr.diaphragms[0]
    e = frac * A_
    assert d0.centre == pytest.approx([A_ / 2 + e, B_ / 2], rel=1e-15)
    assert (d0.mass, d0.inertia) == (M_, M_ * (A_**2 + B_**2) / 12)
    J = d0.inertia
    Kyy, Kyt, Ktt = 4 * KY, -4 * KY * e, KTT + 4 * KY * e**2
    Bq, Cq = Kyy * J + Ktt * M_, Kyy * Ktt - Kyt**2
    disc = np.sqrt(Bq**2 - 4 * M_ * J * Cq)
    lam_exact = np.sort([4 * KX / M_, (Bq - disc) / (2 * M_ * J), (Bq + disc) / (2 * M_ * J)])
    md = fixed_base_modes_3d(fr, n_modes=3, method="dense")
    lam = (2 * np.pi * md.f_hz) ** 2
    K, _ = fr.reduced()
    i = np.setdiff1d(np.arange(fr.n_red), fr.boundary_reduced)
    eb = C_STABLE * len(i) * EPS * np.linalg.cond(K[i][:, i].toarray())
    assert np.all(np.abs(lam - lam_exact) <= eb * lam_exact**2 / lam_exact[0])
    # the coupled modes' ratio Θ/U_y = (ω² m − 4k_y)/(−4k_y e) (mode shape of the 3-dof
    # model); a mode's M-norm error is at most s = eb λ_k/λ_1 over its relative gap, so each
    # component moves by <= s/√m or s/√J
    _, Uy, Th = md.phi[fr.master_dofs[0]]
    ix = int(np.argmin(np.abs(lam_exact - 4 * KX / M_)))
    for k in (j for j in range(3) if j != ix):
        gap = np.min(np.abs(np.delete(lam_exact, k) - lam_exact[k])) / lam_exact[k]
        s = eb * lam_exact[k] / lam_exact[0] / gap
        tol = s * (1 / (np.sqrt(J) * abs(Th[k])) + 1 / (np.sqrt(M_) * abs(Uy[k])))
        ratio = (lam_exact[k] * M_ - Kyy) / Kyt
        assert Th[k] / Uy[k] == pytest.approx(ratio, rel=tol)


def test_accidental_eccentricity_of_the_3d_office_moves_every_floor_by_five_percent():
    b = load_frame3d("office-11-3d")
    e = accidental_eccentricity(b, f_y=0.05)
    for d0, d1 in zip(b.diaphragms, e.diaphragms, strict=True):
        assert d1.centre - d0.centre == pytest.approx([0.0, 0.05 * 80.0], abs=1e-12)
        assert (d1.mass, d1.inertia) == (d0.mass, d0.inertia)
    assert e.total_mass == b.total_mass


def test_bad_input_is_named():
    fr = one_storey()
    with pytest.raises(ValueError, match="f_x: expected a fraction"):
        accidental_eccentricity(fr, f_x=0.7)
    with pytest.raises(ValueError, match="u has 5 rows"):
        storey_drifts_3d(fr, np.zeros(5))
