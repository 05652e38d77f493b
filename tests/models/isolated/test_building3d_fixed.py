"""The fixed rung of a space frame: modal time histories under a three-component record.

Sources: the closed-form step response of a damped oscillator; a one-storey building whose
massless members are condensed statically onto its mass dofs (diaphragm master and corner
masses), integrated directly in physical coordinates with classical damping; the symmetry of
a doubly symmetric building under a ground motion along x.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.linalg as sla
from scipy.integrate import solve_ivp

from nsdyn.models.isolated import fixed_response_3d
from nsdyn.models.isolated.fixed3d import modal_histories
from nsdyn.structure import Section3D, regular_building_3d

EPS = np.finfo(float).eps


def _sec(rho_A, I_y=8e-4, I_z=8e-4):
    return Section3D(E=2.1e11, G=8.1e10, A=0.03, I_y=I_y, I_z=I_z, J=1.2e-3, rho_A=rho_A,
                     rho_Ip=0.0 if rho_A == 0 else None)  # fmt: skip


def _record(T=5.0, dt=0.01):
    t = np.arange(0.0, T + dt / 2, dt)
    w = np.sin(np.pi * t / T) ** 2
    ax = 3.0 * np.sin(2 * np.pi * 1.3 * t) * w
    ay = 2.0 * np.sin(2 * np.pi * 2.1 * t + 0.5) * w
    az = 1.0 * np.sin(2 * np.pi * 5.0 * t) * w
    return t, type("Rec", (), {"t0": 0.0, "dt": dt, "ax": ax, "ay": ay, "az": az})()


def test_piecewise_linear_step_is_exact():
    # a constant load is piecewise linear: eta = p/w^2 (1 - e^{-zwt}(cos wd t + z/sqrt(1-z^2)
    # sin wd t)) to round-off (a few eps of p/w^2 per step, 1e3 steps)
    w, z, p, dt = 7.0, 0.05, 2.0, 0.01
    t = dt * np.arange(1001)
    eta, _ = modal_histories([w], [z], np.full((1, t.size), p), dt)
    wd = w * np.sqrt(1 - z * z)
    ref = p / w**2 * (1 - np.exp(-z * w * t) * (np.cos(wd * t) + z / np.sqrt(1 - z * z)
                                                 * np.sin(wd * t)))  # fmt: skip
    assert np.abs(eta[0] - ref).max() <= 1e4 * EPS * p / w**2


def test_one_storey_building_equals_direct_integration():
    # One storey, one bay, massless members, an eccentric floor (mass offset): the mass dofs
    # are the diaphragm master (U_x, U_y, Theta) and the corners' vertical masses; the
    # members condense statically onto them (exact for massless dofs). The condensed system
    # M z'' + C z' + K* z = -M r a_g with classical damping C = M Phi diag(2 zeta w) Phi^T M
    # integrated by DOP853 (rtol 1e-10) on the linearly interpolated record; the modal
    # solution must match to 1e-6 of the peak.
    Lx, Ly, H = 6.0, 4.0, 3.5
    f = regular_building_3d("one", [Lx], [Ly], [H], _sec(0.0, I_z=5e-4), _sec(0.0), _sec(0.0),
                            floor_mass=2.0e5, mass_offset=(0.4, 0.3), zeta=0.05)  # fmt: skip
    t, rec = _record()
    res = fixed_response_3d(f, rec, n_modes=50)
    K, M = (A.toarray() for A in f.reduced())
    free = np.setdiff1d(np.arange(f.n_red), f.boundary_reduced)
    K, M = K[np.ix_(free, free)], M[np.ix_(free, free)]
    d = np.diag(M)
    assert np.count_nonzero(M - np.diag(d)) == 0  # massless members: M is diagonal
    mm, m0 = np.flatnonzero(d > 0), np.flatnonzero(d == 0)
    Ks = K[np.ix_(mm, mm)] - K[np.ix_(mm, m0)] @ np.linalg.solve(K[np.ix_(m0, m0)],
                                                                 K[np.ix_(m0, mm)])  # fmt: skip
    Mm = np.diag(d[mm])
    assert len(res.modes.f_hz) == len(mm)  # every mode kept
    w2, V = sla.eigh(Ks, Mm)
    C = Mm @ V @ np.diag(2 * 0.05 * np.sqrt(w2)) @ V.T @ Mm
    R = f.rigid_motions()[free][mm][:, :3]  # x, y, z translations of the mass dofs
    Minv = 1.0 / d[mm]
    n = len(mm)

    def rhs(tt, s):
        a = np.array([np.interp(tt, t, rec.ax), np.interp(tt, t, rec.ay),
                      np.interp(tt, t, rec.az)])  # fmt: skip
        z, v = s[:n], s[n:]
        return np.r_[v, -R @ a - Minv * (Ks @ z + C @ v)]

    Y = solve_ivp(rhs, (0, t[-1]), np.zeros(2 * n), t_eval=t, rtol=1e-10, atol=1e-14,
                  method="DOP853", max_step=0.01).y  # fmt: skip
    z = Y[:n]
    master = f.master_dofs[0]
    pos = {int(k): i for i, k in enumerate(free[mm])}
    Ux, Uy, Th = (z[pos[int(k)]] for k in master)
    c = f.diaphragms[0].centre
    dr = res.drifts
    scale = max(np.abs(Ux).max(), np.abs(Uy).max()) / H
    assert np.abs(dr.cm[0, 0] - Ux / H).max() <= 1e-6 * scale
    assert np.abs(dr.cm[0, 1] - Uy / H).max() <= 1e-6 * scale
    for q, (x, y) in enumerate(dr.corners):
        assert np.abs(dr.corner[0, q, 0] - (Ux - (y - c[1]) * Th) / H).max() <= 1e-6 * scale
        assert np.abs(dr.corner[0, q, 1] - (Uy + (x - c[0]) * Th) / H).max() <= 1e-6 * scale
    # eccentric mass: torsion is excited and the corners drift more than the centre
    assert dr.corner[0, :, 0].max() > 1.01 * np.abs(dr.cm[0, 0]).max()
    # absolute floor acceleration at the centre of mass: the relative one from the equation
    # of motion plus the ground's
    rel = np.array([rhs(tt, Y[:, j])[n:] for j, tt in enumerate(t)]).T
    ax_abs = rel[pos[int(master[0])]] + rec.ax
    ay_abs = rel[pos[int(master[1])]] + rec.ay
    assert np.abs(res.floor_acc[1, 0] - ax_abs).max() <= 1e-6 * np.abs(ax_abs).max()
    assert np.abs(res.floor_acc[1, 1] - ay_abs).max() <= 1e-6 * np.abs(ay_abs).max()
    assert np.array_equal(res.floor_acc[0, 0], rec.ax)  # the base moves with the ground
    # base shear and torsional moment: the elastic forces K* z resolved on the rigid motions
    # (x; rotation about the centre of mass)
    Fel = Ks @ z
    Vx = R[:, 0] @ Fel
    rth = f.rigid_motions(c)[free][mm][:, 3]
    assert np.abs(res.base_shear[0] - Vx).max() <= 1e-6 * np.abs(Vx).max()
    Tq = rth @ Fel
    assert np.abs(res.torsion - Tq).max() <= 1e-6 * np.abs(Tq).max()


def test_symmetric_building_under_x_motion_has_no_y_or_torsional_response(assert_round_trip):
    # doubly symmetric plan, bays unequal (x and y frequencies distinct: no degenerate pair
    # whose eigenvectors could mix x and y): the y and torsional participation of each mode is
    # round-off, eps ||M|| ||phi||^2 over the frequency gap, so y and twist stay below 1e-9 of
    # the x response
    f = regular_building_3d("sym", [6.0, 6.0], [5.0], [4.0, 3.5], _sec(240.0), _sec(160.0),
                            _sec(160.0), n_v=2, n_h=2, floor_mass=[3e5, 2e5])  # fmt: skip
    t, rec = _record()
    rec.ay = np.zeros_like(rec.ax)
    rec.az = None
    res = fixed_response_3d(f, rec, n_modes=12)
    dx = np.abs(res.drifts.cm[:, 0]).max()
    assert dx > 1e-4
    assert np.abs(res.drifts.cm[:, 1]).max() <= 1e-9 * dx
    assert np.abs(res.drifts.corner[:, :, 1]).max() <= 1e-9 * dx
    assert np.abs(res.base_shear[1]).max() <= 1e-9 * np.abs(res.base_shear[0]).max()
    L = np.hypot(12.0, 5.0)
    assert np.abs(res.torsion).max() <= 1e-9 * L * np.abs(res.base_shear[0]).max()
    assert res.summary()["corner_amplification_x"] == pytest.approx(1.0, abs=1e-8)
    # y's drifts are round-off: no amplification to report (it read a ratio of round-off, 125)
    assert res.summary()["corner_amplification_y"] is None
    assert json.dumps(res.summary(), allow_nan=False)  # (a NaN at rest was invalid JSON)
    # the tables hold the histories (they had none: to_dataframe was an AttributeError), the
    # corner drift of storey j, corner c in column 4 j + c
    assert_round_trip(res)
    h = res.histories()
    np.testing.assert_array_equal(h["drift_corner_x_{}"][:, 4 * 1 + 2], res.drifts.corner[1, 2, 0])
    np.testing.assert_array_equal(h["floor_acc_y_{}_mps2"][:, 1], res.floor_acc[1, 1])
    assert len(repr(res)) < 1000  # (the whole frame and modes were printed: 16 700 characters)
    V = np.hypot(res.base_shear[0], res.base_shear[1]).max()  # (as the isolated rungs say it)
    assert res.summary()["peak_base_shear_N"] == V >= res.summary()["peak_base_shear_x_N"]


def test_a_one_component_record_is_named_not_an_attribute_error():
    # a GroundMotion (one component) gave "'GroundMotion' object has no attribute 'ax'"
    import nsdyn

    f = regular_building_3d("one", [6.0], [5.0], [4.0], _sec(240.0), _sec(160.0), _sec(160.0),
                            floor_mass=3e5)  # fmt: skip
    with pytest.raises(TypeError, match=r"^motion: expected a three-component record"):
        fixed_response_3d(f, nsdyn.read_motion("synthetic-kt-20s"), n_modes=3)


@pytest.mark.parametrize(
    ("change", "says"),
    [
        # a negative step ran (another answer, unsaid); 0 read "modal response not finite"
        ({"dt": -0.01}, r"^motion.dt: expected a positive time step \[s\], got -0.01"),
        ({"dt": 0.0}, r"^motion.dt: expected a positive time step"),
        ({"dt": float("nan")}, r"^motion.dt: expected a positive time step"),
        # a component of another length was numpy's vstack error
        ({"ay": np.zeros(7)}, r"^motion.ay: expected 501 samples \(as ax\), got shape \(7,\)"),
        ({"ax": np.zeros(1)}, r"^motion.ax: expected a 1-D array of two samples or more"),
        ({"az": np.full(501, np.nan)}, r"^motion: expected finite samples"),
    ],
)
def test_a_bad_record_is_refused_by_field(change, says):
    f = regular_building_3d("one", [6.0], [5.0], [4.0], _sec(240.0), _sec(160.0), _sec(160.0),
                            floor_mass=3e5)  # fmt: skip
    _, rec = _record()
    for k, v in change.items():
        setattr(rec, k, v)
    with pytest.raises(ValueError, match=says):
        fixed_response_3d(f, rec, n_modes=3)


def test_modes_of_another_frame_are_refused():
    # matmul's "mismatch in its core dimension 0 ... (size 54 is different from 39)" before
    from nsdyn.structure.modes3d import fixed_base_modes_3d

    one = regular_building_3d("one", [6.0], [5.0], [4.0], _sec(240.0), _sec(160.0),
                              _sec(160.0), floor_mass=3e5)  # fmt: skip
    two = regular_building_3d("two", [6.0], [5.0], [4.0, 3.5], _sec(240.0), _sec(160.0),
                              _sec(160.0), floor_mass=3e5)  # fmt: skip
    with pytest.raises(ValueError, match=r"^modes: expected the frame's own modes"):
        fixed_response_3d(two, _record()[1], modes=fixed_base_modes_3d(one, n_modes=3))
    # a frame of the same size with stiffer columns: its modes do not diagonalise this one's
    # stiffness (they were taken by size alone); this frame's lumped-mass modes do, and run
    stiff = regular_building_3d("stiff", [6.0], [5.0], [4.0, 3.5], _sec(240.0, 2e-3, 2e-3),
                                _sec(160.0), _sec(160.0), floor_mass=3e5)  # fmt: skip
    with pytest.raises(ValueError, match=r"^modes: .*do not diagonalise its stiffness"):
        fixed_response_3d(two, _record()[1], modes=fixed_base_modes_3d(stiff, n_modes=3))
    lumped = fixed_base_modes_3d(two, n_modes=3, lumped=True)
    assert fixed_response_3d(two, _record()[1], modes=lumped).modes is lumped
