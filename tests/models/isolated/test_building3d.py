"""The rigid rung of a space frame on isolators: deck constants and response.

Sources: the mass, first and second moments of a lumped mass distribution (closed forms of
the generator's floor masses: a uniform slab's J = m (L_x² + L_y²) / 12 about its centre,
four equal corner masses' J = m (L_x² + L_y²) / 4); the symmetry of a doubly symmetric deck
under a ground motion along x; a linear 3-dof system (flat sliders with rubber and dampers,
no friction) integrated directly in centre-of-mass coordinates.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from nsdyn.models.isolated import building_deck, deck_constants
from nsdyn.models.isolated.bearings import Bearing, BearingError, Friction
from nsdyn.models.isolated.deck import simulate_plane
from nsdyn.structure import Section3D, accidental_eccentricity, regular_building_3d

EPS = np.finfo(float).eps
COL = Section3D(E=2.1e11, G=8.1e10, A=0.03, I_y=8e-4, I_z=8e-4, J=1.2e-3, rho_A=240.0)
BEAM = Section3D(E=2.1e11, G=8.1e10, A=0.02, I_y=2e-3, I_z=1e-4, J=1e-5, rho_A=160.0)
FLOORS = [4.0e5, 3.5e5, 2.0e5]
HS = [4.0, 3.5, 3.5]
BX, BY = [6.0, 6.0], [5.0]


def _massless(s: Section3D) -> Section3D:
    return Section3D(E=s.E, G=s.G, A=s.A, I_y=s.I_y, I_z=s.I_z, J=s.J, rho_A=0.0, rho_Ip=0.0)


def _building(rho=True, **kw):
    c, b = (COL, BEAM) if rho else (_massless(COL), _massless(BEAM))
    kw.setdefault("floor_mass", FLOORS)
    return regular_building_3d("b", BX, BY, HS, c, b, b, n_v=2, n_h=2, **kw)


def test_mass_is_the_sum_of_member_and_floor_masses():
    # m = r_x^T M r_x equals sum rho_A L + floor masses (consistent mass reproduces rigid
    # translation exactly); round-off of a sum over ~10^3 entries: 1e3 eps relative
    f = _building()
    k = deck_constants(f)
    ref = f.total_mass
    assert ref > sum(FLOORS)  # members carry mass too
    assert k["m"] == pytest.approx(ref, rel=1e3 * EPS)
    # a doubly symmetric building: centre of mass at the plan centre
    assert np.allclose(k["centre"], [6.0, 2.5], rtol=0, atol=1e3 * EPS * 12.0)


def test_polar_inertia_and_height_of_lumped_floor_masses():
    # members massless: m = sum m_s, J = sum m_s (L_x^2 + L_y^2)/12 (uniform slabs about the
    # plan centre), h = sum m_s z_s / sum m_s
    f = _building(rho=False)
    k = deck_constants(f)
    ms, zs = np.array(FLOORS), np.cumsum(HS)
    Lx, Ly = sum(BX), sum(BY)
    assert k["m"] == pytest.approx(ms.sum(), rel=1e3 * EPS)
    assert k["J"] == pytest.approx(ms.sum() * (Lx**2 + Ly**2) / 12, rel=1e3 * EPS)
    assert k["h"] == pytest.approx((ms * zs).sum() / ms.sum(), rel=1e3 * EPS)


def test_polar_inertia_of_corner_masses_without_diaphragms():
    # one bay, no diaphragms, beams one element each: each level's mass sits in x, y, z on its
    # four corners (tributary beam length: a quarter each), J = sum m_s (L_x^2 + L_y^2)/4
    Lx, Ly = 7.0, 4.0
    f = regular_building_3d("c", [Lx], [Ly], HS, _massless(COL), _massless(BEAM),
                            _massless(BEAM), floor_mass=FLOORS, diaphragms=False)  # fmt: skip
    k = deck_constants(f)
    assert k["J"] == pytest.approx(sum(FLOORS) * (Lx**2 + Ly**2) / 4, rel=1e3 * EPS)
    assert np.allclose(k["centre"], [Lx / 2, Ly / 2], rtol=0, atol=1e3 * EPS * Lx)


def test_accidental_eccentricity_moves_the_centre_of_mass():
    # every floor's mass moves by 0.05 L_y; with massless members the whole mass does, and the
    # polar moment about the moved centre is unchanged
    f = _building(rho=False)
    e = accidental_eccentricity(f, f_y=0.05)
    k0, k1 = deck_constants(f), deck_constants(e)
    assert k1["centre"][1] - k0["centre"][1] == pytest.approx(0.05 * sum(BY), rel=1e6 * EPS)
    assert k1["centre"][0] == pytest.approx(k0["centre"][0], abs=1e3 * EPS * 12)
    assert k1["J"] == pytest.approx(k0["J"], rel=1e3 * EPS)
    deck = building_deck(e, Bearing(Friction(0.05), radius=2.0))
    assert np.allclose(deck.ecc, [0.0, 0.05 * sum(BY)], atol=1e3 * EPS * 12)
    assert deck.positions.shape == (6, 2)


def test_one_bearing_per_base_node():
    f = _building()
    b = Bearing(Friction(0.05), radius=2.0)
    with pytest.raises(BearingError, match="one per base node"):
        building_deck(f, [b] * 5)


def _record(ay=True, T=4.0, dt=0.01, scale=1.0):
    t = np.arange(0.0, T + dt / 2, dt)
    w = np.sin(np.pi * t / T) ** 2
    ax = 3.0 * scale * np.sin(2 * np.pi * 0.7 * t) * w
    a_y = 2.0 * scale * np.sin(2 * np.pi * 1.1 * t + 0.5) * w if ay else np.zeros_like(t)
    return t, (0.0, dt, ax, a_y, None)


def test_symmetric_building_under_x_motion_neither_slips_in_y_nor_twists():
    # Symmetry: under a_y = 0 the y equation and the moment have only round-off sources (the
    # centre of mass from the mass matrix is exact to ~1e3 eps of the plan, the sums over 6
    # isolators to c n_i eps); the switch law holds a sticking isolator through a stabilised
    # constraint whose error the step control keeps below the absolute tolerance atol. So
    # the y slip and the twist's slip at the plan's corners stay below atol = 1e-8 m, while
    # the x slip is of order 0.1 m.
    f = _building()
    deck = building_deck(f, Bearing(Friction(0.06), radius=2.5))
    _, rec = _record(ay=False)
    atol = 1e-8
    res = simulate_plane(deck, rec, atol=(atol, atol))
    ux = np.abs(res.u[..., 0]).max()
    assert ux > 1e-2  # it slid
    L = 0.5 * np.hypot(sum(BX), sum(BY))
    assert np.abs(res.u[..., 1]).max() <= atol
    assert np.abs(res.theta).max() * L <= atol


def test_eccentric_linear_deck_twists_as_the_direct_integration():
    # Flat sliders without friction (mu = 0), rubber k and damper c each: the deck is the
    # linear system diag(m, m, J) z'' + C z' + K z = -diag(m, m, 0) [a_x, a_y, 0] in the
    # coordinates z = (x, y, theta) of the centre of mass, K = k sum [[1, 0, -Y], [0, 1, X],
    # [-Y, X, X^2 + Y^2]] with (X, Y) the isolators about the centre of mass (C alike with c).
    # The 5 % accidental eccentricity couples x and y to the twist. Tolerance: both runs
    # at rtol 1e-8 / 1e-10, far below the 1e-4 of the peak asserted.
    f = accidental_eccentricity(_building(), f_y=0.05)
    kc = deck_constants(f)
    k_lam, c = 2.0e6, 1.0e5
    deck = building_deck(f, Bearing(Friction(0.0), k_lam=k_lam, c=c))
    t, rec = _record(scale=0.3)  # no uplift: overturning well below the weight's moment
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = simulate_plane(deck, rec, law="arctan", rtol=1e-8, atol=(1e-10, 1e-10))
    P = f.nodes[f.base_nodes, :2] - kc["centre"]
    X, Y = P.T
    S = np.array([[len(X), 0, -Y.sum()], [0, len(X), X.sum()],
                  [-Y.sum(), X.sum(), (X**2 + Y**2).sum()]])  # fmt: skip
    m, J = kc["m"], kc["J"]
    Mi = 1.0 / np.array([m, m, J])
    ax, ay = rec[2], rec[3]

    def rhs(tt, s):
        g = np.array([np.interp(tt, t, ax), np.interp(tt, t, ay), 0.0])
        z, v = s[:3], s[3:]
        return np.r_[v, Mi * (-(k_lam * S @ z + c * S @ v)) - g * (Mi * np.array([m, m, 0]))]

    ref = solve_ivp(rhs, (0, t[-1]), np.zeros(6), t_eval=res.t, rtol=1e-10, atol=1e-13,
                    max_step=0.01, method="DOP853").y  # fmt: skip
    e = deck.ecc
    th = res.q[:, 2]
    xc, yc = res.q[:, 0] - e[1] * th, res.q[:, 1] + e[0] * th
    scale = np.abs(ref[:2]).max()
    assert np.abs(ref[2]).max() * 6.0 > 1e-3 * scale  # the eccentricity makes it twist
    assert np.abs(xc - ref[0]).max() <= 1e-4 * scale
    assert np.abs(yc - ref[1]).max() <= 1e-4 * scale
    assert np.abs(th - ref[2]).max() <= 1e-4 * np.abs(ref[2]).max()


def test_friction_pendulums_under_an_eccentric_mass_do_not_twist():
    # Self-centring in torsion: a pendulum's force is N_i (u_i / R + mu(|v_i|) v_i / |v_i|),
    # the same vector f times N_i at every isolator while the deck does not twist. Their
    # resultant f sum N_i acts at p = sum N_i r_i / sum N_i, which the overturning moment
    # moves from the centre of mass c along the deck's acceleration, itself along f (f is
    # the only horizontal force): (p - c) x f = 0, no torque, whatever the eccentricity and
    # the velocity-dependent mu. With the smooth law the twist has only round-off sources,
    # so its slip at the plan's corners stays below atol = 1e-10 m; flat sliders with rubber
    # (stiffness centre at the isolators' centroid) twist the same eccentric deck.
    f = accidental_eccentricity(_building(), f_y=0.05)
    L = 0.5 * np.hypot(sum(BX), sum(BY))
    _, rec = _record(scale=0.3)  # no uplift (as above)
    atol = 1e-10
    fps = Bearing(Friction(0.04, mu_fast=0.07, rate=30.0), radius=2.5)
    rubber = Bearing(Friction(0.04), k_lam=2.0e6)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = simulate_plane(building_deck(f, fps), rec, law="arctan", atol=(atol, atol))
        twisted = simulate_plane(building_deck(f, rubber), rec, law="arctan", atol=(atol, atol))
    assert np.abs(res.u).max() > 1e-3  # it slid
    assert np.abs(res.theta).max() * L <= atol
    assert np.abs(twisted.theta).max() * L > 1e4 * atol


def test_a_centre_of_mass_outside_the_kern_names_the_eccentricity():
    # three rows of isolators 5 m apart: the rigid plate's kern reaches sum(y^2) / (3 * 5 m)
    # = 3.3 m from the centre, and the floors moved 49 % of the 10 m plan put the centre of
    # mass beyond it: an isolator would pull at rest. The error says the frame's centre of
    # mass, where it is, and which scene field moves it (it named a deck field, "b.ecc")
    c, b = _massless(COL), _massless(BEAM)
    f = regular_building_3d("b", BX, [5.0, 5.0], HS, c, b, b, n_v=2, n_h=2, floor_mass=FLOORS)
    e = accidental_eccentricity(f, f_y=-0.49)
    with pytest.raises(
        BearingError,
        match=r"^b: its centre of mass, \(.*\) m from the "
        r"isolators' centre, lies outside the kern.*structure\.eccentricity",
    ):
        building_deck(e, Bearing(Friction(0.05), radius=2.0))
