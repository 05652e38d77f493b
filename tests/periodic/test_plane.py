"""Periodic orbits on a bidirectional isolator: closed-form circular slip, square law, 1-D case.

Sources: the steady circular slip of a mass on a flat slider (rubber K_lam, damper c, Coulomb
friction with a disc |f| <= mu m g) under circular ground acceleration, derived below in
complex notation (the friction force has constant magnitude and turns with the velocity, so the
problem is linear); its stability from the linearisation in the frame turning with the ground
(an autonomous system there, derived below); today's planar switch model and its exact period
map (nsdyn.periodic.switch, itself checked against Den Hartog's 1931 steady sliding solution in
test_switch_shooting.py) for the two independent 1-D laws and for linear excitation.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import expm

from nsdyn.ground.orbit import HarmonicPlane
from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.builders import system_from_matrices
from nsdyn.models.isolated.deck import sdof_plane, simulate_plane
from nsdyn.models.isolated.system import Isolation
from nsdyn.periodic import shoot, shoot_switch, switch_problem
from nsdyn.periodic.plane import FD_REL, RTOL, plane_problem, plane_response
from nsdyn.periodic.shooting import SHOOT_TOL

G = 9.81
M = 1000.0  # kg
K = M * (2 * math.pi * 0.5) ** 2  # rubber: 0.5 Hz alone
C = 2 * 0.05 * math.sqrt(K * M)  # damper: 5 % of critical for the rubber
MU = 0.05
F0 = 0.7  # Hz
A0 = 2 * MU * G  # m/s^2: twice the friction's acceleration, a permanent slip


def sdof(mu=MU):
    return sdof_plane(M, Bearing(Friction(mu), k_lam=K, c=C), g=G)


def circular(A, f):
    """a_x = A sin(w t), a_y = A sin(w t - 90 deg): a_g = -i A e^{i w t} (counter-clockwise)."""
    return HarmonicPlane.circular(f, A, +1)


def steady_circle(w, A, mu_eff, m=M, k=K, c=C):
    """Radius R and phase psi of the steady slip z = R e^{i(w t + psi)} (z = u_x + i u_y).

    With z' = i w z the friction mu m g z'/|z'| = i mu m g e^{i(w t + psi)} has constant
    magnitude, and m z'' + c z' + k z + mu m g z'/|z'| = -m a_g = i m A e^{i w t} gives

        e^{i psi} [(k - m w^2) R + i (c w R + mu m g)] = i m A,

    so ((k - m w^2) R)^2 + (c w R + mu m g)^2 = (m A)^2, a quadratic in R whose positive root
    exists for A > mu g (a permanent slip), and psi = arg(i m A / [...]). ``mu_eff`` is
    mu s(w R) for the regularised law (its friction is constant along the circle, too)."""
    D = (k - m * w * w) ** 2 + (c * w) ** 2
    b = c * w * mu_eff * m * G
    R = (-b + math.sqrt(b * b - D * ((mu_eff * m * G) ** 2 - (m * A) ** 2))) / D
    e = 1j * m * A / ((k - m * w * w) * R + 1j * (c * w * R + mu_eff * m * G))
    return R, float(np.angle(e))


def arctan_circle(w, A, mu, eps):
    """The regularised law's circle: R with mu_eff = mu (2/pi) arctan(eps w R), fixed point."""
    R = steady_circle(w, A, mu)[0]
    for _ in range(60):
        mu_eff = mu * 2 / math.pi * math.atan(eps * w * R)
        R = steady_circle(w, A, mu_eff)[0]
    return R, mu_eff


def closed_form_multipliers(w, R, psi, F, dF, m=M, k=K, c=C):
    """Floquet multipliers of the circular orbit, exp(lambda T) of the linearisation in the
    frame turning with the ground.

    With z = p e^{i w t}: m (p'' + 2 i w p' - w^2 p) + c (p' + i w p) + k p + F(|W|) W/|W|
    = i m A, W = p' + i w p, autonomous in p, with the fixed point p* = R e^{i psi}. A
    perturbation (a, b = a') changes W by dW = b + i w a, and the friction by
    F'(V) (e.dW) e + F/V (dW - (e.dW) e), e = W*/V, V = w R. Period map of z and of p are
    similar (e^{i w T} = 1), so the multipliers are exp(lambda T)."""
    V = w * R
    e = 1j * w * R * np.exp(1j * psi) / V

    def deriv(a, b):
        dW = b + 1j * w * a
        along = (np.conj(e) * dW).real
        dG = dF * along * e + F / V * (dW - along * e)
        bd = -(m * (2j * w * b - w * w * a) + c * dW + k * a + dG) / m
        return b, bd

    L = np.zeros((4, 4))
    for j in range(4):
        x = np.zeros(4)
        x[j] = 1.0
        a, b = deriv(x[0] + 1j * x[1], x[2] + 1j * x[3])
        L[:, j] = [a.real, a.imag, b.real, b.imag]
    T = 2 * math.pi / w
    rho, vec = np.linalg.eig(expm(L * T))
    return rho[np.argsort(-np.abs(rho))], np.linalg.cond(vec)


def _state(R, psi, w):
    """(x, y, x', y') at t = 0 on the circle z = R e^{i(w t + psi)}."""
    z = R * np.exp(1j * psi)
    return np.array([z.real, z.imag, (1j * w * z).real, (1j * w * z).imag])


@pytest.mark.parametrize("law", ["switch", "arctan"])
def test_shooting_converges_to_the_closed_form_circle(law):
    w = 2 * math.pi * F0
    eps = 1e6  # s/m: a sharp regularised law
    if law == "switch":
        R, mu_eff = steady_circle(w, A0, MU)[0], MU
        F, dF = MU * M * G, 0.0
    else:
        R, mu_eff = arctan_circle(w, A0, MU, eps)
        F = mu_eff * M * G
        dF = MU * M * G * 2 / math.pi * eps / (1 + (eps * w * R) ** 2)
    psi = steady_circle(w, A0, mu_eff)[1]
    own = {"eps": eps} if law == "arctan" else {}  # (the switch law has no sharpness)
    pb = plane_problem(sdof(), circular(A0, F0), law=law, **own)
    res = shoot(pb, F0)  # from rest
    assert res.converged and res.residual <= SHOOT_TOL
    rho_cf, cond = closed_form_multipliers(w, R, psi, F, dF)
    # Newton's end: |x0 - x*| <= |(I - Phi)^-1| (|H| + e), |H| <= SHOOT_TOL x the orbit's
    # excursion (per block), e ~ 1e3 RTOL the period's integration error (steps x local error);
    # |(I - Phi)^-1| <= 1 / (1 - max|rho|) on the closed form's (normal to cond) multipliers
    tol = cond * (SHOOT_TOL + 1e3 * RTOL) / (1 - abs(rho_cf[0]))
    x_cf = _state(R, psi, w)
    assert np.abs(res.x0[:2] - x_cf[:2]).max() <= tol * R
    assert np.abs(res.x0[2:] - x_cf[2:]).max() <= tol * w * R
    q = pb.orbit_quantities(F0, res.X)
    assert q["u_peak_m"] == pytest.approx(R, rel=tol)
    assert q["stick_fraction"] == 0.0
    # Floquet multipliers: the central differences err by ~ 2 RTOL^(2/3) of Phi's scale (module
    # text of nsdyn.periodic.plane), times the eigenvalue condition number
    rho = np.sort_complex(res.multipliers)
    ref = np.sort_complex(rho_cf)
    assert np.abs(rho - ref).max() <= cond * 10 * FD_REL**2
    assert res.multipliers.size == 4  # the single mass's free twist is not in the state
    if law == "arctan":
        # the regularised law's circle differs from Coulomb's by its friction deficit
        # mu (1 - s(V)) ~ mu 2 / (pi eps V): dR = (dR/dmu) dmu, here ~ 1e-6 R
        R_c = steady_circle(w, A0, MU)[0]
        dR_dmu = (steady_circle(w, A0, MU * (1 + 1e-6))[0] - R_c) / (MU * 1e-6)
        shift = dR_dmu * (mu_eff - MU)
        assert q["u_peak_m"] - R_c == pytest.approx(shift, rel=0.01, abs=tol * R)


def test_the_event_method_from_rest_reaches_the_closed_form_circle():
    # The transient decays at least as fast as max|rho| per period near the orbit (closed-form
    # multipliers, ~0.49 here): after 40 periods rho^40 ~ 1e-12 of the initial distance ~ R; what
    # remains is the integrator's local error at rtol 1e-9 and the stick band eta's O(eta)
    # (it never enters: the speed stays at w R).
    w = 2 * math.pi * F0
    R, psi = steady_circle(w, A0, MU)
    rho_cf, _ = closed_form_multipliers(w, R, psi, MU * M * G, 0.0)
    assert abs(rho_cf[0]) < 0.6
    n = 40
    r = simulate_plane(sdof(), circular(A0, F0), law="switch", t_end=n / F0, dt_out=0.01,
                       rtol=1e-9, atol=(1e-11, 1e-11))  # fmt: skip
    last = r.t >= (n - 1) / F0 - 1e-9
    u = r.u[last, 0]
    z = u[:, 0] + 1j * u[:, 1]
    tol = 1e-6
    np.testing.assert_allclose(np.abs(z), R, rtol=tol)
    ang = np.angle(z * np.exp(-1j * (w * r.t[last] + psi)))
    assert np.abs(ang).max() < tol
    assert np.all(r.modes[last] == 1)  # slipping throughout


def square_peak(f, A, mu=MU):
    """Peak resultant displacement of the square law: x and y each on today's planar switch
    model (frozen weight m g), x under A sin(w t), y under A sin(w t - pi/2), so y(t) = x(t - T/4)
    on the steady state; the 1-D orbit from today's exact-flow shooting (nsdyn.periodic.switch)."""
    iso = Isolation(k_lam=K, c=C, mu=mu, law="switch")
    s1 = system_from_matrices([[M]], [[0.0]], [[0.0]], iso_dofs=[0], influence=[1.0],
                              isolation=iso, weight=M * G)  # fmt: skip
    res = shoot_switch(switch_problem(s1, A), f, n_steps=400)
    assert res.converged
    x = res.X[:, 0]
    y = np.roll(x[:-1], 100)  # a quarter period later (400 samples per period)
    return float(np.hypot(x[:-1], y).max()), res


def test_two_independent_1d_laws_give_another_radius():
    # The square law resists with up to sqrt(2) mu m g when both components slip: its orbit is
    # smaller than the disc's circle by far more than the shooting tolerance (~1e-5 R above)
    w = 2 * math.pi * F0
    R = steady_circle(w, A0, MU)[0]
    pb = plane_problem(sdof(), circular(A0, F0), law="switch")
    res = shoot(pb, F0)
    disc = pb.orbit_quantities(F0, res.X)["u_peak_m"]
    assert disc == pytest.approx(R, rel=1e-5)
    sq, _ = square_peak(F0, A0)
    # the samples miss the square's peak by at most (pi/400)^2 / 2 = 3e-5 relative
    assert abs(sq / disc - 1) > 0.05
    assert sq < disc


@pytest.mark.parametrize("angle", [0.0, 30.0])
def test_linear_excitation_is_the_planar_periodic_orbit(angle):
    # Along a line the bidirectional isolator is today's planar model: the orbit starts on the
    # 1-D exact-flow orbit (rotated by the angle) and has no motion across the line. The deck's
    # switch law reverses at |v| = eta instead of 0: the reversal comes eta / a late (a ~ 1 m/s^2
    # the deceleration), a velocity error ~ 2 mu g eta / a ~ eta; eta = 1e-8 m/s here, and the
    # 1-D orbit's own shooting residual (SHOOT_TOL of the excursion) dominates
    _, r1 = square_peak(F0, A0)
    pb = plane_problem(sdof(), HarmonicPlane.linear(F0, A0, angle), law="switch", eta=1e-8)
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    res = shoot(pb, F0, np.array([r1.x0[0] * c, r1.x0[0] * s, r1.x0[1] * c, r1.x0[1] * s]))
    assert res.converged
    x, y, vx, vy = res.x0
    amp = np.abs(r1.X).max(axis=0)
    tol = 10 * SHOOT_TOL
    assert abs(x * c + y * s - r1.x0[0]) <= tol * amp[0]
    assert abs(vx * c + vy * s - r1.x0[1]) <= tol * amp[1]
    assert abs(-x * s + y * c) <= tol * amp[0]
    assert abs(-vx * s + vy * c) <= tol * amp[1]
    # and the 1-D multipliers are the along-line ones of the plane orbit
    rho1 = np.sort(np.abs(r1.multipliers))[::-1]
    rho = np.sort(np.abs(res.multipliers))[::-1]
    np.testing.assert_allclose(rho[:2], rho1, rtol=1e-4)
    assert pb.orbit_quantities(F0, res.X)["u_peak_m"] == pytest.approx(amp[0], rel=1e-4)


def test_symmetric_deck_has_the_single_mass_circle():
    # Four equal isolators (each a quarter of the rubber, damper and weight) under a deck with
    # its centre of mass at the centre and h = 0 (no overturning) move as the single mass: the
    # same closed-form circle, no torsion; the deck's state has the twist (dim 6)
    from nsdyn.models.isolated.deck import rigid_deck

    pos = [[-2.0, -1.5], [2.0, -1.5], [2.0, 1.5], [-2.0, 1.5]]
    deck = rigid_deck(M, M * (4.0**2 + 3.0**2) / 12, pos,
                      Bearing(Friction(MU), k_lam=K / 4, c=C / 4), g=G)  # fmt: skip
    w = 2 * math.pi * F0
    R, psi = steady_circle(w, A0, MU)
    rho_cf, cond = closed_form_multipliers(w, R, psi, MU * M * G, 0.0)
    tol = cond * (SHOOT_TOL + 1e3 * RTOL) / (1 - abs(rho_cf[0]))
    pb = plane_problem(deck, circular(A0, F0), law="switch")
    res = shoot(pb, F0)
    assert res.converged and res.multipliers.size == 6
    q = pb.orbit_quantities(F0, res.X)
    assert q["u_peak_m"] == pytest.approx(R, rel=tol)
    assert q["torsion_peak_rad"] <= tol * R / 2.0
    # the four translational multipliers are the single mass's (torsion adds two of its own)
    for r in rho_cf:
        assert np.abs(res.multipliers - r).min() <= cond * 10 * FD_REL**2


@pytest.mark.parametrize("law", ["switch", "arctan"])
def test_elliptical_orbit_is_where_the_time_history_from_rest_ends(law):
    # No closed form for an ellipse (the slip speed varies along it):
    # the shooting orbit must be the attractor the plain time history from rest reaches. After
    # n periods the distance left is ~ max|rho|^n of the initial one (the multipliers shooting
    # reports, < 0.5 here); the time history's own error is its rtol 1e-9
    orbit = HarmonicPlane.elliptical(0.45, 0.8, 0.4, 30.0)
    pb = plane_problem(sdof(), orbit, law=law)
    res = shoot(pb, orbit.f)
    assert res.converged
    rho = float(np.abs(res.multipliers).max())
    assert rho < 0.5
    n = int(math.ceil(math.log(1e-8) / math.log(rho)))
    T = 1.0 / orbit.f
    r = simulate_plane(sdof(), orbit, law=law, t_eval=np.linspace(0.0, n * T, 50 * n + 1),
                       rtol=1e-9, atol=(1e-11, 1e-11))  # fmt: skip
    end = np.concatenate([r.q[-1, :2], r.qd[-1, :2]])
    scale = np.abs(res.X).max(axis=0)
    assert np.all(
        np.abs(end - res.x0)
        <= 1e-6 * np.concatenate([scale[:2].max() * np.ones(2), scale[2:].max() * np.ones(2)])
    )


def test_an_unstable_verdict_from_a_wrong_monodromy_is_checked_by_the_map():
    # A differenced monodromy that is wrong (here scaled by 10, as a difference straddling a
    # stick-slip switch can be) calls the stable closed-form circle unstable (and shooting
    # fails: the stepped sweep finds the point). The check follows a perturbation e for 10
    # periods on the map itself: |e_10| <= cond(V) rho^10 |e_0| in the 2-norm of the
    # eigenbasis V, and its scaled max-norm (4 entries; the blocks' scales differ by w = V/R)
    # adds the factors 2 x 2 x w, so the rate per period is at most (4 cond w)^(1/10) rho with
    # the closed-form rho ~ 0.49: the point is reported stable, that rate as |rho|
    from nsdyn.periodic.plane import PlaneProblem, plane_response

    pb = plane_problem(sdof(), circular(A0, F0), law="switch")

    def wrong(x0, f, **kw):
        pm = PlaneProblem.period_map(pb, x0, f, **kw)
        if pm.monodromy is not None:
            pm.monodromy = 10.0 * pm.monodromy
        return pm

    pb.period_map = wrong
    curve = plane_response(pb, fmin=F0, fmax=1.2 * F0, points=2)
    for p in curve.points:
        w = 2 * math.pi * p.f
        R, psi = steady_circle(w, A0, MU)
        rho_cf, cond = closed_form_multipliers(w, R, psi, MU * M * G, 0.0)
        assert p.converged and p.stable is True and p.multipliers.size == 1
        assert abs(p.multipliers[0]) <= (4 * cond * w) ** 0.1 * abs(rho_cf[0]) < 1.0
        assert "differenced monodromy's max |rho|" in p.note and "stable" in p.note
    assert not curve.bifurcations


@pytest.mark.slow
def test_a_triple_pendulum_orbit_is_where_the_time_history_from_rest_ends():
    # The triple pendulum's series model (8 internal slips, regularised law) under a circular
    # orbit: the shooting orbit is the attractor of the plain time history from rest, reached
    # to ~ max|rho|^n of the initial distance after n periods (time history at rtol 1e-9)
    import tomllib
    from pathlib import Path

    from nsdyn.models.isolated.tfp import tfp_from_config

    scene = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "deck-tfp4-3c.toml"
    bearing = tfp_from_config(tomllib.loads(scene.read_text())["bearing"], "bearing")
    mass = sdof_plane(M, bearing, g=G)
    orbit = HarmonicPlane.circular(0.5, 2.0)
    pb = plane_problem(mass, orbit, law="arctan")
    assert pb.dim == 12  # x, y, 8 internal slips, x', y'
    res = shoot(pb, orbit.f)
    assert res.converged
    rho = float(np.abs(res.multipliers).max())
    assert rho < 0.9
    n = int(math.ceil(math.log(1e-7) / math.log(rho)))
    T = 1.0 / orbit.f
    r = simulate_plane(mass, orbit, law="arctan", t_eval=np.linspace(0.0, n * T, 20 * n + 1),
                       rtol=1e-9, atol=(1e-11, 1e-11))  # fmt: skip
    end = np.concatenate([r.q[-1, :2], r.qd[-1, :2]])
    x0 = res.x0[[0, 1, -2, -1]]
    scale = np.abs(res.X).max(axis=0)[[0, -1]].max()
    assert np.abs(end - x0).max() <= 1e-5 * scale
    # the bearing is isotropic and the excitation turns uniformly: the steady orbit is a
    # uniformly turning circle, |u| constant, so the last period's samples give its peak
    q = pb.orbit_quantities(orbit.f, res.X)
    last = np.hypot(*r.u[-21:, 0].T)
    assert last.max() - last.min() <= 1e-5 * last.max()
    assert q["u_peak_m"] == pytest.approx(last.max(), rel=1e-5)


@pytest.mark.parametrize(
    "orbit",
    [
        HarmonicPlane.circular(0.7, 1.3, -1),
        HarmonicPlane.linear(0.7, 1.3, 115.0),
        HarmonicPlane.elliptical(0.7, 1.3, 0.4, 30.0),
        HarmonicPlane(0.7, 1.1, 0.6, 47.0),
    ],
)
def test_the_sweep_amplitude_is_the_orbits_largest_acceleration(orbit):
    # A of a deck sweep scales the orbit: its largest |a(t)| (an ellipse's major semi-axis),
    # against 200 001 samples of HarmonicPlane.accel over a period (sampling error of a smooth
    # maximum (pi/200000)^2 / 2 ~ 1e-10); the shape times A is the orbit again
    from nsdyn.periodic.plane import orbit_shape

    A, shape = orbit_shape(orbit)
    ax, ay, _ = orbit.accel(np.linspace(0.0, orbit.period, 200_001))
    assert A == pytest.approx(np.hypot(ax, ay).max(), rel=1e-9)
    assert (shape[0] * A, shape[1] * A) == pytest.approx((orbit.ax, orbit.ay), rel=1e-14)
    assert shape[2] == pytest.approx(math.radians(orbit.phase_y_deg), rel=1e-14)


def test_every_failure_status_of_the_deck_loops_has_a_reason():
    # a shooting failure is reported with its reason: every non-OK status the deck's time
    # loops can return (the ST_* constants of _kplanerun) must map to a message, never to a
    # bare number
    from nsdyn.models.isolated import _kplanerun as kr
    from nsdyn.periodic.plane import _WHY

    codes = {v for k, v in vars(kr).items() if k.startswith("ST_") and k != "ST_OK"}
    assert codes, "no status constants found"
    assert codes <= set(_WHY), sorted(codes - set(_WHY))


def test_a_triple_pendulum_orbit_with_stuck_surfaces_is_one_of_a_family():
    # A mass on a TFP whose outer surfaces stay below their friction all period (φ peaks
    # below μ1 = 0.06) while the inner slider slides: the series model's stuck element k has
    # ṡ_k = 0 exactly, so shifting u and s_1 together by δ leaves the stage's stretch e, hence
    # φ and every other element, unchanged (g_1 moves by δ/R̄_1, still inside μ1): another
    # orbit. The monodromy has multipliers 1 along such shifts, and the point says it is one
    # of a family (its peaks depend on the path). Checked by integrating one period from the
    # shifted start: it returns to it to the shooting tolerance.
    from nsdyn.models.isolated.tfp import tfp_from_config

    cfg = {"R1": 2.2, "R2": 0.3, "R3": 0.3, "R4": 2.2, "mu1": 0.06, "mu2": 0.02, "mu3": 0.02,
           "mu4": 0.10, "d1": 0.40, "d2": 0.06, "d3": 0.06, "d4": 0.40}  # fmt: skip
    mass = sdof_plane(1.0e5, tfp_from_config(cfg, "bearing"), g=G)
    pb = plane_problem(mass, HarmonicPlane.linear(1.5, 1.0), law="arctan")
    curve = plane_response(pb, fmin=1.4, fmax=1.5, points=2)
    for p in curve.points:
        assert p.converged and "family of orbits" in p.note, p.note
        assert p.quantities["friction_peak_N"] < 0.06 * 1.0e5 * G  # φ < μ1: outer stuck
    p = curve.points[-1]
    rho, vec = np.linalg.eig(pb.period_map(p.x0, p.f).monodromy)
    k = int(np.argmin(np.abs(rho - 1.0)))
    assert abs(rho[k] - 1.0) <= 1e-9
    v = np.real(vec[:, k])
    v *= 1e-3 / np.abs(v[:2]).max()  # a 1 mm shift of the mass
    st, X, _ = pb.run(p.x0 + v, p.f, 200)
    # the shooting tolerance of the orbit's largest displacement and velocity
    big = np.abs(p.X).max(axis=0)
    scale = np.where(pb.velocity, big[pb.velocity].max(), big[~pb.velocity].max())
    assert st == 0 and np.all(np.abs(X[-1, pb.rows] - (p.x0 + v)) <= 10 * SHOOT_TOL * scale)


def test_an_arctan_stick_slip_orbit_says_its_stick_creeps():
    # a linear orbit of amplitude just above mu g at 3 Hz: the switch law's orbit barely
    # slips (1e-6 m) where the arctan law's creeps to 56x that, and its note only said
    # "stick-slip orbit"; an arctan stick-slip point now names the creep and the switch law
    from nsdyn.models.isolated.friction import stick_velocity

    pb = plane_problem(sdof(), HarmonicPlane.linear(3.0, A0, 0.0), law="arctan")
    q = {"stick_fraction": 0.65, "uplift": False, "rim_contact": False}
    note = pb.validity_note(q)
    v = stick_velocity("arctan", pb.eps)
    assert note.startswith("stick-slip orbit (stick fraction 0.65): under the arctan law its "
                           f"stick phases creep at up to {v:.2g} m/s")  # fmt: skip
    assert note.endswith("(confirm with --friction switch)")
    switch = plane_problem(sdof(), HarmonicPlane.linear(3.0, A0, 0.0), law="switch")
    assert switch.validity_note(q) == "stick-slip orbit (stick fraction 0.65)"
