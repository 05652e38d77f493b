"""Bidirectional isolators: the vector laws against the planar model and closed-form solutions.

Sources: seed 004 (the arctan law eq 7 and the switch model eqs 4-6, today's planar model in
``nsdyn.models.isolated``), Coulomb's law with a friction disc |f| <= mu N (steady state derived
below), and the stick threshold of a rigid block on a rough plane.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pytest

from nsdyn.ground.excitation import Table
from nsdyn.ground.orbit import HarmonicPlane
from nsdyn.models.isolated import _kplane as kp
from nsdyn.models.isolated import _kplanerun as kr
from nsdyn.models.isolated.bearings import Bearing, BearingError, Friction
from nsdyn.models.isolated.builders import system_from_matrices
from nsdyn.models.isolated.deck import PLANE_ATOL, kernel_params, sdof_plane, simulate_plane
from nsdyn.models.isolated.friction import arctan_direction
from nsdyn.models.isolated.system import Isolation
from nsdyn.solve.transient import simulate

G = 9.81
M = 1000.0


def _forces(system, law, y, t=0.0, modes=None, ground=None, eps=7500.0):
    """(qdd, N, Ff) of the kernel at one state (no excitation unless ``ground`` given)."""
    Mm, pos, bp, nd, sp = kernel_params(system, law, eps, 1e-5, None)
    ni = pos.shape[0]
    modes = np.full(ni, kp.MODE_SLIP, dtype=np.int64) if modes is None else modes
    gk, gp, tab = kp.G_TABLE, np.array([0.0, 1.0] + [0.0] * 7), np.zeros((3, 0))
    if ground is not None:
        gk, gp, tab = ground
    out = (np.zeros(3), np.zeros(ni), np.zeros((ni, 2)), np.zeros((ni, 2)), np.zeros((ni, 2)))
    st = kp.evaluate(t, np.asarray(y, float), modes, np.zeros((ni, 2)), Mm, pos, bp, nd, sp, gk,
                     gp, tab, kp.workspace(ni), *out)  # fmt: skip
    assert st == kp.ST_OK
    return out[0], out[1], out[2]


@pytest.mark.parametrize("angle", [0.0, 30.0, 137.0])
def test_regularised_vector_law_is_the_arctan_law_along_its_velocity(angle):
    # f = mu N (2/pi) arctan(eps |v|) v/|v|: along any direction the magnitude is the 1-D
    # arctan law of seed 004 (friction.arctan_direction), and f is parallel to v
    mu, eps = 0.05, 7500.0
    s = sdof_plane(M, Bearing(Friction(mu)), g=G)
    for speed in (1e-6, 1e-4, 3e-3, 0.2):
        c, sn = math.cos(math.radians(angle)), math.sin(math.radians(angle))
        _, N, Ff = _forces(s, "arctan", [0, 0, 0, speed * c, speed * sn, 0], eps=eps)
        assert N[0] == pytest.approx(M * G, rel=1e-15)
        mag = mu * M * G * float(arctan_direction(speed, eps))
        np.testing.assert_allclose(Ff[0], [mag * c, mag * sn], rtol=1e-13, atol=1e-12 * mag)


def _record(dt=0.005, T=8.0):
    """A smooth-enough broadband test signal: three sines under a sin^2 window [m/s^2]."""
    t = np.arange(0.0, T + dt / 2, dt)
    a = (2.2 * np.sin(2 * np.pi * 0.7 * t) + 1.3 * np.sin(2 * np.pi * 1.9 * t + 0.4)
         + 0.8 * np.sin(2 * np.pi * 3.1 * t + 1.0)) * np.sin(np.pi * t / T) ** 2  # fmt: skip
    return t, a


@pytest.mark.parametrize("law", ["arctan", "switch"])
@pytest.mark.parametrize("angle", [0.0, 35.0])
def test_one_component_excitation_equals_the_planar_model(law, angle):
    # A mass on a flat slider (rubber k, damper c, constant mu) shaken along the direction
    # `angle` is today's planar model (system_from_matrices, frozen weight, method radau for
    # the arctan law, the event method for the switch model) along that line, and stays on it.
    # Tolerance: both runs at rtol 1e-9; the switch law sticks at |v| = eta instead of v = 0,
    # which moves the slip by at most eta / kappa + eta^2 / (2 a) ~ 1e-9 m with eta = 1e-8.
    k, c, mu, eta = 2.0e4, 1.0e3, 0.05, 1e-8
    dt = 0.005
    t, a = _record(dt)
    iso = Isolation(k_lam=k, c=c, mu=mu, law=law, eta=eta)
    s1 = system_from_matrices([[M]], [[0.0]], [[0.0]], iso_dofs=[0], influence=[1.0],
                              isolation=iso, weight=M * G)  # fmt: skip
    method = "radau" if law == "arctan" else "event"
    r1 = simulate(s1, Table(0.0, dt, a), method=method, rtol=1e-10, atol=1e-12, t_eval=t,
                  x0=np.zeros(2))  # fmt: skip
    x1 = r1.x[:, 0]
    c_, s_ = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    s2 = sdof_plane(M, Bearing(Friction(mu), k_lam=k, c=c), g=G)
    own = {"eta": eta} if law == "switch" else {}  # (the arctan law has no stick band)
    r2 = simulate_plane(s2, (0.0, dt, a * c_, a * s_, None), law=law, t_eval=t, rtol=1e-10,
                        atol=(1e-12, 1e-12), **own)  # fmt: skip
    u = r2.u[:, 0, :]
    along = u[:, 0] * c_ + u[:, 1] * s_
    across = -u[:, 0] * s_ + u[:, 1] * c_
    peak = np.abs(x1).max()
    assert peak > 0.02  # the isolator slides (mu g = 0.49 m/s^2 < the peak 3.6 m/s^2)
    assert np.abs(along - x1).max() < 2e-7 * peak
    assert np.abs(across).max() < 1e-9 * peak


def _circular(A, f):
    # a_x = A sin(w t), a_y = A sin(w t - 90 deg) = -A cos(w t): a_g = -i A e^{i w t}
    return {"f": f, "ax": A, "ay": A, "phase_y_deg": -90.0}


def _steady_state(A, w, mu_eff):
    """Speed V and phase phi of the steady slip under circular ground acceleration.

    Complex notation z = u_x + i u_y, a_g = -i A e^{i w t}. With the slip velocity
    z' = V e^{i(w t + phi)} of constant speed V the friction force mu m g z'/|z'| is a vector of
    constant magnitude turning with it, and m z'' = -m a_g - mu m g z'/|z'| gives

        i w V e^{i phi} = i A - mu g e^{i phi}  =>  e^{i phi} (mu g + i w V) = i A,

    so |mu g + i w V| = A:  V = sqrt(A^2 - (mu g)^2) / w  (a steady slip needs A > mu g), and
    phi = pi/2 - atan2(w V, mu g): the slip velocity lags the ground velocity's direction.
    ``mu_eff`` = mu s(V) for the regularised law (s = (2/pi) arctan(eps V) at the constant V).
    """
    V = math.sqrt(A * A - (mu_eff * G) ** 2) / w
    return V, math.pi / 2 - math.atan2(w * V, mu_eff * G)


@pytest.mark.parametrize(
    ("law", "integrator"), [("switch", "auto"), ("arctan", "radau"), ("arctan", "dopri5")]
)
def test_circular_excitation_steady_slip_has_the_closed_form_speed_and_phase(law, integrator):
    mu, f, eps = 0.1, 1.0, 7500.0
    A, w = 2 * mu * G, 2 * math.pi * f
    s = sdof_plane(M, Bearing(Friction(mu)), g=G)
    r = simulate_plane(s, _circular(A, f), law=law, t_end=20.0, dt_out=0.01, eps=eps,
                       integrator=integrator)  # fmt: skip
    mu_eff = mu
    if law == "arctan":  # the regularised friction at the steady speed: fixed point in V
        V = _steady_state(A, w, mu)[0]
        for _ in range(50):
            mu_eff = mu * float(arctan_direction(V, eps))
            V = _steady_state(A, w, mu_eff)[0]
    V, phi = _steady_state(A, w, mu_eff)
    last = r.t > 18.0  # two periods, after 18 of transient
    v = r.v[last, 0, :]
    speed = np.hypot(v[:, 0], v[:, 1])
    ang = np.angle((v[:, 0] + 1j * v[:, 1]) * np.exp(-1j * (w * r.t[last] + phi)))
    # The transient: in the frame turning with the ground, p = z' e^{-i w t} obeys
    # p' = -i w p + i A - mu g p/|p|; about p* = V e^{i phi} a radial/tangential perturbation
    # (r, s) has r' = w s, s' = -w r - (mu g / V) s, so it decays as exp(-mu g t / (2 V)):
    # rate w / (2 sqrt 3) = 1.8 /s at A = 2 mu g, e^-33 after 18 s. What remains is the
    # integrator's local error, which the contracting orbit does not accumulate: per step
    # within rtol |v| + atol_v (rtol 1e-6, the law's default atol_v), relative to V:
    tol = 1e-6 + PLANE_ATOL[law][1] / V
    assert np.abs(speed / V - 1).max() < tol
    assert np.abs(ang).max() < 5 * tol
    fr = np.hypot(*r.friction[last, 0, :].T)
    # switch: exactly mu m g; arctan: s(V) moves by (2/pi) eps V / (1 + (eps V)^2) x tol
    eV = eps * V
    bound = 1e-12 if law == "switch" else 2 / math.pi * eV / (1 + eV * eV) * tol + 1e-12
    np.testing.assert_allclose(fr, mu_eff * M * G, rtol=bound)


def test_two_independent_1d_laws_differ_from_the_disc():
    # The square law (x and y each with its own 1-D Coulomb law, today's planar model run
    # twice) lets the resultant friction reach sqrt(2) mu m g whenever both components slip;
    # the disc caps it at mu m g. Circular excitation at A = 2 mu g keeps both components
    # slipping at once for most of the cycle, so the square's peak is sqrt(2) mu m g exactly.
    mu, f = 0.1, 1.0
    A, w = 2 * mu * G, 2 * math.pi * f
    dt = 0.002
    t = np.arange(0.0, 10.0 + dt / 2, dt)
    iso = Isolation(k_lam=0.0, c=0.0, mu=mu, law="switch", eta=1e-8)
    s1 = system_from_matrices([[M]], [[0.0]], [[0.0]], iso_dofs=[0], influence=[1.0],
                              isolation=iso, weight=M * G)  # fmt: skip
    ax, ay = A * np.sin(w * t), -A * np.cos(w * t)
    vel = []
    for a in (ax, ay):
        r = simulate(s1, Table(0.0, dt, a), method="event", rtol=1e-9, atol=1e-11, t_eval=t,
                     x0=np.zeros(2))  # fmt: skip
        vel.append(r.x[:, 1])
    both = (np.abs(vel[0]) > 1e-3) & (np.abs(vel[1]) > 1e-3)
    assert both[t > 5].mean() > 0.5
    f_square = mu * M * G * math.sqrt(2.0)  # each component mu m g while slipping
    r2 = simulate_plane(sdof_plane(M, Bearing(Friction(mu)), g=G), _circular(A, f),
                        t_end=10.0, dt_out=dt)  # fmt: skip
    f_disc = np.hypot(*r2.friction[:, 0, :].T).max()
    assert f_disc <= mu * M * G * (1 + 1e-9)
    assert f_square / f_disc > 1.41
    # and the square's slip speed is not constant: the disc's steady speed V is not reached
    V = _steady_state(A, w, mu)[0]
    sq_speed = np.hypot(vel[0], vel[1])[t > 8]
    assert np.abs(sq_speed / V - 1).max() > 0.05


@pytest.mark.parametrize("angle", [0.0, 25.0, 90.0, 200.0])
def test_below_the_stick_threshold_the_mass_stays_stuck_in_any_direction(angle):
    # A spring-free slider holds while |a_g| < mu_s g (the disc radius), whatever the
    # direction, also above the kinetic mu_d g: the static coefficient is the disc's radius.
    mu_d, mu_s = 0.05, 0.1
    A = 0.95 * mu_s * G  # > mu_d g
    sysm = sdof_plane(M, Bearing(Friction(mu_d, mu_static=mu_s)), g=G)
    line = dataclasses.asdict(HarmonicPlane.linear(1.3, A, angle))  # amplitudes >= 0
    for orbit in (line, _circular(A, 1.3)):
        r = simulate_plane(sysm, orbit, t_end=5.0)
        # held: q'' = -kappa q' + the round-off of the 5 x 5 stick solve, ~ eps |a_g| per step,
        # which over 5 s (v ~ 1e-15 m/s damped by kappa) stays far below 1e-12 m
        assert np.abs(r.u).max() < 1e-12
        assert r.stats["events"] == 0 and np.all(r.modes == kp.MODE_STICK)
        fr = np.hypot(*r.friction[:, 0, :].T)
        assert fr.max() <= mu_s * M * G  # the stick force m |a_g| stays inside the disc
        w = 2 * math.pi * 1.3
        ph = math.radians(orbit["phase_y_deg"])
        ag = np.hypot(orbit["ax"] * np.sin(w * r.t), orbit["ay"] * np.sin(w * r.t + ph))
        np.testing.assert_allclose(fr, M * ag, rtol=0, atol=1e-9 * M * A)  # tau = -m a_g


def test_break_away_starts_in_the_direction_of_the_stick_force():
    # a_g = (b, c t): the stick force tau = -m a_g (what friction must hold) reaches the disc
    # mu_s m g at t* = sqrt((mu_s g)^2 - b^2) / c; the slip starts along tau(t*)/|tau(t*)|.
    # The switch law's disc is mu_s N (1 + STICK_RTOL) (its stick test and its switching
    # function alike), so the event lies at that radius: t* with mu_s (1 + STICK_RTOL).
    mu_s, mu_d, b, c = 0.1, 0.08, 0.6, 0.5
    dt = 0.01
    t = np.arange(0.0, 3.0 + dt / 2, dt)
    ax, ay = np.full_like(t, b), c * t
    r = simulate_plane(sdof_plane(M, Bearing(Friction(mu_d, mu_static=mu_s)), g=G),
                       (0.0, dt, ax, ay, None))  # fmt: skip
    t_star = math.sqrt((mu_s * (1 + kr.STICK_RTOL) * G) ** 2 - b * b) / c
    ev = r.events[r.events[:, 3] == kp.MODE_START]
    assert ev.shape[0] >= 1
    assert ev[0, 0] == pytest.approx(t_star, abs=1e-9)
    tau = -np.array([b, c * t_star])
    np.testing.assert_allclose(ev[0, 4:6], tau / np.linalg.norm(tau), atol=1e-9)
    # once sliding, the velocity points (nearly) along that direction
    k = np.searchsorted(r.t, t_star + 0.02)
    v = r.v[k, 0]
    assert np.dot(v, tau) / (np.linalg.norm(v) * np.linalg.norm(tau)) > 0.99


def test_static_below_kinetic_friction_is_refused():
    with pytest.raises(BearingError, match=r"friction.mu_static: .*static friction below kinetic"):
        Friction(0.05, mu_static=0.04)
    with pytest.raises(BearingError, match=r"mu_static"):
        Friction(0.03, mu_fast=0.08, rate=20.0, mu_static=0.05)  # mu_d reaches 0.08
    with pytest.raises(BearingError, match=r"bearing.radius: expected a positive number"):
        Bearing(Friction(0.05), radius=0.0)
    with pytest.raises(BearingError, match=r"bearing.radius"):
        Bearing(Friction(0.05), radius=-2.0)


def test_no_silent_failure_on_unknown_law():
    with pytest.raises(ValueError, match="law: expected one of"):
        simulate_plane(sdof_plane(M, Bearing(Friction(0.05))), _circular(1.0, 1.0), law="coulomb",
                       t_end=1.0)  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        simulate_plane(sdof_plane(M, Bearing(Friction(0.05))), _circular(0.1, 1.0), t_end=0.5)


@pytest.mark.parametrize("law", ["switch", "arctan"])
def test_closed_form_orbit_is_a_fixed_point_of_the_period_map(law):
    # Shooting's condition: started on the closed-form steady slip (z' = V e^{i phi} at t = 0)
    # the period map returns the same velocity and closes the displacement circle, with no
    # transient; the residual is the integrator's (rtol 1e-10), for the regularised law with
    # its own mu_eff = mu s(V).
    mu, f, eps = 0.1, 1.0, 7500.0
    A, w = 2 * mu * G, 2 * math.pi * f
    mu_eff = mu
    if law == "arctan":
        V = _steady_state(A, w, mu)[0]
        for _ in range(50):
            mu_eff = mu * float(arctan_direction(V, eps))
            V = _steady_state(A, w, mu_eff)[0]
    V, phi = _steady_state(A, w, mu_eff)
    v0 = V * np.exp(1j * phi)
    y0 = [0.0, 0.0, 0.0, v0.real, v0.imag, 0.0]
    s = sdof_plane(M, Bearing(Friction(mu)), g=G)
    r = simulate_plane(s, _circular(A, f), law=law, t_eval=np.linspace(0.0, 1.0 / f, 401),
                       y0=y0, eps=eps, rtol=1e-10, atol=(1e-12, 1e-12))  # fmt: skip
    v = r.v[:, 0]
    assert np.abs(v[-1] - v[0]).max() < 1e-8 * V  # the period map's residual
    assert np.abs(r.u[-1, 0]).max() < 1e-8 * V / w  # the orbit closes
    np.testing.assert_allclose(np.hypot(v[:, 0], v[:, 1]), V, rtol=1e-8)  # constant speed
