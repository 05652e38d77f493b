"""Unilateral isolator contact (lift-off, flight, landing) against closed-form mechanics.

Reference problem: a rigid block (mass m) on two isolators under a vertical harmonic ground
acceleration u''_v = A sin(w t) with A > g. Relative to the ground, the block stays on the
bearings while g + u''_v >= 0 (normal force m (g + u''_v) / 2 per isolator); it lifts off when
u''_v = -g, i.e. w t1 = pi + arcsin(g / A), and then flies ballistically (gap y, y(t1) = 0,
y'(t1) = 0)::

    y'(t) = (A / w) (cos w t - cos w t1) - g (t - t1)
    y(t)  = (A / w^2) (sin w t - sin w t1) - (A / w) cos(w t1) (t - t1) - g (t - t1)^2 / 2

until it lands at y(t2) = 0 with y'(t2) < 0. Newton's impact law with coefficient e sends
y' -> -e y' and changes the kinetic energy by -(1 - e^2) m y'(t2)^2 / 2 (any dynamics text,
e.g. Pfeiffer & Glocker, *Multibody Dynamics with Unilateral Contacts*, ch. 2). After the
excitation ends, free bounces in gravity land with velocities v_{k+1} = e v_k.
"""

import numpy as np
import pytest
from scipy.optimize import brentq

from nsdyn.ground.excitation import Harmonic, Table
from nsdyn.models.isolated import Isolation, system_from_matrices
from nsdyn.solve._kimpact import V_REST
from nsdyn.solve.integrate import UpliftError, solve

G = 9.81
MASS, J, HALF_WIDTH = 1000.0, 500.0, 1.0
A_VER, F_VER = 1.5 * G, 2.0
W = 2 * np.pi * F_VER
TOL = dict(rtol=1e-8, atol=1e-10)


def block(law: str = "switch", contact: str = "detect"):
    """Rigid block q = [x, y, theta] on two isolators at x = -+HALF_WIDTH."""
    M = np.diag([MASS, MASS, J])
    Z = np.zeros((3, 3))
    iso = Isolation(k_lam=5e4, c=1e3, mu=0.1, law=law, contact=contact)
    return system_from_matrices(
        M,
        Z,
        Z,
        iso_dofs=[[1, 0, 0], [1, 0, 0]],
        influence=[[1, 0], [0, 1], [0, 0]],
        isolation=iso,
        contact_rows=[[0, 1, -HALF_WIDTH], [0, 1, HALF_WIDTH]],
    )


def ballistic():
    """(t1, t2, v2): lift-off, landing time and landing velocity of the first flight."""
    t1 = (np.pi + np.arcsin(G / A_VER)) / W

    def y(t):
        dt = t - t1
        return (
            (A_VER / W**2) * (np.sin(W * t) - np.sin(W * t1))
            - (A_VER / W) * np.cos(W * t1) * dt
            - 0.5 * G * dt**2
        )

    t2 = brentq(y, t1 + 1e-3, t1 + 1.0 / F_VER)
    v2 = (A_VER / W) * (np.cos(W * t2) - np.cos(W * t1)) - G * (t2 - t1)
    return t1, t2, v2


def run(method: str, contact: str, A: float = A_VER, t_end: float = 0.75, **kw):
    law = "switch" if method == "event" else "arctan"
    s = block(law)
    x0, _ = s.static_equilibrium()
    P = s.params(Harmonic(0.0, 0.0, A_ver=A, f_ver=F_VER))
    return solve(P, x0, np.linspace(0.0, t_end, 751), method=method, contact=contact, **kw, **TOL)


@pytest.mark.parametrize("method", ["event", "radau"])
def test_flight_and_landing_match_the_ballistic_solution(method):
    t1, t2, v2 = ballistic()
    sol = run(method, "unilateral")
    lifts = [e for e in sol.contact_events if e[2] == "lift-off"]
    lands = [e for e in sol.contact_events if e[2] == "landing"]
    assert sorted(e[1] for e in lifts[:2]) == [0, 1]
    for e in lifts[:2]:
        assert e[0] == pytest.approx(t1, abs=1e-9)  # located on the dense output
    for e in lands[:2]:
        assert e[0] == pytest.approx(t2, abs=1e-8)
        assert e[3] == pytest.approx(v2, rel=1e-7)  # normal velocity before the impact
    # plastic landing (e = 0): the normal kinetic energy m v2^2 / 2 is lost, nothing else
    assert sol.impact_energy == pytest.approx(-0.5 * MASS * v2**2, rel=1e-7)
    # both contacts open exactly during the flight
    inside = (sol.t > t1 + 1e-6) & (sol.t < t2 - 1e-6)
    outside = (sol.t < t1 - 1e-6) | ((sol.t > t2 + 1e-6) & (sol.t < 0.8))
    assert np.all(sol.open_contacts[inside] == 1)
    assert np.all(sol.open_contacts[outside & (sol.t < t1)] == 0)
    # gap of the flight from the ground: y(t) of the closed form, at the outputs
    n = 3
    gap = sol.x[:, 1]
    tt = sol.t[inside]
    dt = tt - t1
    y = (
        (A_VER / W**2) * (np.sin(W * tt) - np.sin(W * t1))
        - (A_VER / W) * np.cos(W * t1) * dt
        - 0.5 * G * dt**2
    )
    assert np.max(np.abs(gap[inside] - y)) < 1e-7
    assert np.all(np.isfinite(sol.x[:, n:]))


def test_the_flight_time_is_the_ballistic_one_on_any_output_grid():
    # the summary's flight time per contact is t2 - t1 of the closed form, from the located
    # lift-off and landing (it was counted on the output grid: 8 % off at dt_out = 0.05 s on
    # the office frame); runs to t2 + 0.1 s, before the next lift-off at t1 + 1/F_VER
    from nsdyn.solve.transient import simulate

    t1, t2, _ = ballistic()
    s = block("arctan")
    for dt_out in (0.005, 0.1):
        r = simulate(s, Harmonic(0.0, 0.0, A_ver=A_VER, f_ver=F_VER), t_end=t2 + 0.1,
                     dt_out=dt_out, method="radau", contact="unilateral", **TOL)  # fmt: skip
        flight = r.contact_summary()["flight_time_s"]
        assert flight == pytest.approx([t2 - t1] * 2, abs=1e-8)  # the event times' tolerance


def test_the_output_step_does_not_change_the_run():
    # outputs sample a run, they do not steer it: three flights in 3.3 periods, whose end
    # 1.65 s neither 0.02 nor 0.035 s divides (the run used to end at the last output before
    # it), in chunks of 0.35 s, which 0.02 s does not divide (a chunk used to end on the output
    # after it; at 0.7 s both grids have an output 1e-16 s off the chunk's end), give the same
    # steps and contact events bit for bit
    from nsdyn.solve.transient import simulate

    s = block("arctan")
    g = Harmonic(0.0, 0.0, A_ver=A_VER, f_ver=F_VER)
    runs = [simulate(s, g, t_end=3.3 / F_VER, dt_out=dt_out, method="radau", contact="unilateral",
                     chunk_s=0.35, **TOL) for dt_out in (0.02, 0.035)]  # fmt: skip
    assert runs[0].t[-1] == runs[1].t[-1] == pytest.approx(3.3 / F_VER, rel=1e-15)
    events = [r.contact_events for r in runs]
    assert len(events[0]) >= 6 and events[0] == events[1]
    assert runs[0].n_steps == runs[1].n_steps and runs[0].stats == runs[1].stats


@pytest.mark.parametrize("e", [0.5, 1.0])
def test_landing_loses_the_laws_energy_and_never_gains(e):
    _, _, v2 = ballistic()
    sol = run("event", "unilateral", restitution=e, t_end=0.6)
    lands = [x for x in sol.contact_events if x[2] == "landing"]
    assert lands
    # Newton's law: dT = -(1 - e^2) m v^2 / 2 <= 0 (zero for e = 1, up to round-off)
    assert sol.impact_energy == pytest.approx(-(1 - e**2) * 0.5 * MASS * v2**2, abs=1e-6 * MASS)
    assert sol.impact_energy <= 1e-9 * MASS * v2**2


def test_zeno_bouncing_comes_to_rest_at_the_accumulation_time():
    """A vertical pulse lifts the block; afterwards it bounces in gravity with v_{k+1} = e v_k.
    The landing times form a geometric series with the limit (accumulation time)

        t_inf = t_1 + sum_k 2 e^k v_1 / g = t_1 + 2 v_1 e / (g (1 - e))

    (t_1, v_1: the first landing after the pulse). The rest rule ends the sequence at the
    first landing slower than V_REST, which therefore lies before t_inf by exactly the
    truncated tail 2 v_N e / (g (1 - e)) <= 2 V_REST e / (g (1 - e)) (3.1e-4 s here)."""
    e = 0.6
    dt = 0.01
    av = np.zeros(200)
    av[5:25] = -1.5 * G  # 0.2 s of a ground falling faster than gravity (zero after 0.25 s)
    s = block("switch")
    x0, _ = s.static_equilibrium()
    P = s.params(Table(0.0, dt, np.zeros_like(av), av))
    t = np.linspace(0.0, 2.0, 201)
    sol = solve(P, x0, t, method="event", contact="unilateral", restitution=e, **TOL)
    assert sol.success
    lands = [x for x in sol.contact_events if x[2] == "landing" and x[1] == 0]
    after = [x for x in lands if x[0] > 0.25]
    assert len(after) >= 10
    v = np.array([abs(x[3]) for x in after])
    tl = np.array([x[0] for x in after])
    np.testing.assert_allclose(v[1:] / v[:-1], e, rtol=1e-6)  # Newton's law, bounce by bounce
    np.testing.assert_allclose(np.diff(tl), 2 * e * v[:-1] / G, rtol=1e-6)  # flights 2 e v / g
    # the last landing is the rest landing: the first one slower than V_REST
    assert v[-1] <= V_REST < v[-2]
    t_inf = tl[0] + 2 * v[0] * e / (G * (1 - e))
    tail = 2 * v[-1] * e / (G * (1 - e))
    assert tl[-1] == pytest.approx(t_inf - tail, abs=1e-9)
    assert 0.0 < t_inf - tl[-1] <= 2 * V_REST * e / (G * (1 - e))
    # at rest on both bearings from then on, and never lifted again
    assert not [x for x in sol.contact_events if x[0] > tl[-1] and x[2] == "lift-off"]
    rest = sol.t > tl[-1]
    assert np.all(sol.open_contacts[rest] == 0)
    assert np.max(np.abs(sol.x[rest, 3:])) < 1e-9
    # energy: each landing loses (1 - e^2) m v^2 / 2, the rest landing m v^2 / 2
    lost = 0.5 * MASS * ((1 - e**2) * np.sum(v[:-1] ** 2) + v[-1] ** 2)
    lost += 0.5 * MASS * sum((1 - e**2) * x[3] ** 2 for x in lands if x[0] <= 0.25)
    assert -sol.impact_energy == pytest.approx(lost, rel=1e-6)


def test_small_excitation_all_assumptions_agree():
    """With nothing lifting, bilateral, detect and unilateral are one model."""
    sols = [run("event", c, A=0.5 * G, t_end=0.5) for c in ("bilateral", "detect", "unilateral")]
    for s in sols[1:]:
        np.testing.assert_allclose(s.x, sols[0].x, rtol=0, atol=1e-10)
    assert not sols[2].contact_events
    assert not sols[0].uplift


def test_bilateral_records_where_it_would_lift_and_detect_stops():
    t1, _, _ = ballistic()
    sol = run("event", "bilateral", t_end=0.6)
    assert sol.success and sol.uplift  # runs through, records the would-be lift-off
    assert min(tk for tk, _ in sol.uplift) == pytest.approx(t1, abs=1e-3)
    with pytest.raises(UpliftError) as err:
        run("event", "detect", t_end=0.6)
    assert err.value.t == pytest.approx(t1, abs=1e-3)


def test_unilateral_rejects_frozen_normal_forces_and_other_methods():
    s = block("arctan")
    x0, _ = s.static_equilibrium()
    P = s.params(None)
    with pytest.raises(ValueError, match="method"):
        solve(P, x0, np.linspace(0, 0.1, 3), method="dopri5", contact="unilateral")
    with pytest.raises(ValueError, match="contact"):
        solve(P, x0, np.linspace(0, 0.1, 3), contact="sometimes")


@pytest.mark.slow
def test_symmetric_frame_under_vertical_shaking_keeps_its_isolators_together():
    """The office frame (nearly symmetric about its mid-span; Craig-Bampton model) under
    purely vertical shaking of 12 m/s^2 > g at 1 Hz: by symmetry both isolators lift off and
    land at the same instants. Each lift-off is where two normal forces
    reach zero together, and the flexible frame bounces after every plastic landing, so a
    20 s run holds some 1800 contact events, many of them such ties (the case where a contact
    set decided one contact at a time could close the contacts in turn without end, or read a
    gap left 1e-8 m below zero by the constraint stabilisation as an immediate touchdown)."""
    import nsdyn

    s = nsdyn.build_system(nsdyn.load_frame("office-11"), fidelity="cb")
    x0, _ = s.static_equilibrium()
    P = s.params(Harmonic(0.0, 0.0, A_ver=12.0, f_ver=1.0))
    sol = solve(P, x0, np.linspace(0.0, 20.0, 4001), method="radau", contact="unilateral")
    assert sol.success
    ev = {k: [(t, kind) for t, c, kind, _, _ in sol.contact_events if c == k] for k in (0, 1)}
    assert len(ev[0]) == len(ev[1]) > 100
    # symmetric pairs: same kinds, same instants (to the event location tolerance, amplified
    # by round-off asymmetry over 20 s of bouncing)
    assert [k for _, k in ev[0]] == [k for _, k in ev[1]]
    np.testing.assert_allclose([t for t, _ in ev[0]], [t for t, _ in ev[1]], rtol=0, atol=1e-6)


def test_rigid_block_on_sticking_isolators_lifts_at_the_overturning_threshold():
    """A rigid block (centre of mass at height h above its isolator plane, isolators at x =
    -+b) on isolators that stick (mu = 1 > b/h), under a horizontal ground acceleration ramp
    a_h = r t. While both contacts are closed the block moves with the ground (y'' = theta'' =
    0, slips frozen), so the isolators carry the horizontal force m a_h at the isolator plane;
    its moment m a_h h about the centre of mass unloads one contact: N = m g / 2 - m a_h h / (2 b),
    zero when a_h = g b / h (statics of a rigid block; the bearing spring and damper change
    nothing while the block moves with the ground). Lift-off at t1 = g b / (h r)."""
    h, r = 2.0, 2.0
    M = np.diag([MASS, MASS, J])
    Z = np.zeros((3, 3))
    iso = Isolation(k_lam=5e4, c=1e3, mu=1.0, law="switch", contact="unilateral")
    s = system_from_matrices(
        M,
        Z,
        Z,
        iso_dofs=[[1, 0, h], [1, 0, h]],  # the isolator plane lies h below the centre of mass
        influence=[[1, 0], [0, 1], [0, 0]],
        isolation=iso,
        contact_rows=[[0, 1, -HALF_WIDTH], [0, 1, HALF_WIDTH]],
    )
    x0, _ = s.static_equilibrium()
    dt = 0.01
    ramp = r * dt * np.arange(401)  # 0 .. 8 m/s^2 over 4 s
    P = s.params(Table(0.0, dt, ramp))
    sol = solve(P, x0, np.linspace(0.0, 3.0, 301), method="event", contact="unilateral", **TOL)
    lifts = [e for e in sol.contact_events if e[2] == "lift-off"]
    t1 = G * HALF_WIDTH / (h * r)
    assert lifts and lifts[0][0] == pytest.approx(t1, abs=1e-6)


def test_rigid_block_rocking_on_one_corner_matches_housner_for_small_tilts():
    """The unilateral frame made rigid, its isolators sticking, is Housner's rocking block.

    Tilted by phi0 onto its right contact (left contact open, the corner at (b, -h) from the
    centre of mass held by the closed contact and the stuck isolator) and released at rest
    without excitation, the block rotates about that corner until the left contact lands.
    Housner (1963): I_O phi'' = -m g R sin(alpha - phi), R = sqrt(b^2 + h^2),
    alpha = atan(b / h), I_O = J + m R^2 -- integrated here by SciPy to 1e-12 as the
    reference. nsdyn's constraints are linear in the rotation, so it solves the same motion
    with sin(alpha - phi) ~ sin(alpha) (no P-Delta): the two agree to O(phi0 / tan(alpha))
    = O(phi0 h / b). At phi0 = 1e-4, h / b = 2 that is 2e-4: the impact time and the landing
    velocity of the left corner, 2 b phi'(impact), must agree to 1e-3 relative.
    """
    from scipy.integrate import solve_ivp

    h, b, phi0 = 2.0, HALF_WIDTH, 1e-4
    M = np.diag([MASS, MASS, J])
    Z = np.zeros((3, 3))
    iso = Isolation(k_lam=5e4, c=1e3, mu=1.0, law="switch", contact="unilateral")
    s = system_from_matrices(
        M,
        Z,
        Z,
        iso_dofs=[[1, 0, h], [1, 0, h]],
        influence=[[1, 0], [0, 1], [0, 0]],
        isolation=iso,
        contact_rows=[[0, 1, -b], [0, 1, b]],
    )
    theta = -phi0  # left corner up: the right corner (x, y) + theta (h, b) stays put
    x0 = np.array([-h * theta, -b * theta, theta, 0.0, 0.0, 0.0])
    P = s.params(Harmonic(0.0, 0.0))
    sol = solve(
        P, x0, np.linspace(0.0, 0.05, 51), method="event", contact="unilateral",
        open0=np.array([1, 0]), on_failure="return", **TOL,
    )  # fmt: skip
    # after the landing all four rows hold the 3-dof block (two contacts, two stuck isolators
    # on the same plane: D rows equal), which the kernel reports as singular -- the rocking
    # phase and its landing are what is compared
    lands = [e for e in sol.contact_events if e[2] == "landing" and e[1] == 0]
    assert lands, sol.contact_events
    t_nsdyn, v_nsdyn = lands[0][0], abs(lands[0][3])

    R, alpha = np.hypot(b, h), np.arctan2(b, h)
    I_O = J + MASS * R**2
    p2 = MASS * G * R / I_O

    def rock(t, z):
        return [z[1], -p2 * np.sin(alpha - z[0])]

    def impact(t, z):
        return z[0]

    impact.terminal, impact.direction = True, -1
    ref = solve_ivp(rock, (0.0, 1.0), [phi0, 0.0], events=impact, rtol=1e-12, atol=1e-15)
    t_h, w_h = ref.t_events[0][0], abs(ref.y_events[0][0][1])
    assert t_nsdyn == pytest.approx(t_h, rel=1e-3)
    assert v_nsdyn == pytest.approx(2 * b * w_h, rel=1e-3)
