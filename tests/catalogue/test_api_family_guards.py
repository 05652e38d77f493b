"""The library calls of the rocking, contact and cylinder families refuse a start or a
setting that has no meaning, naming the argument, where before they ran on it.

Each case is one that gave a result without a word (or never returned): a rocking run with
h_max = 0 looped for ever, a pulse with a NaN vertical ratio left the block standing, a
contact body started 0.25 m inside a rigid ground was lifted out (event) or left there "at
rest" (Moreau-Jean), a tilt given beside q0 was dropped, the Housner law dropped e_n, a
Moreau-Jean step longer than the run ran past it, a cylinder run from t0 = NaN took no step
and reported a tilt of 0.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import nsdyn

BLOCK = nsdyn.RockingBlock(width=0.3, height=1.2)
PULSE = nsdyn.one_sine(3.924, 4 * math.pi)


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"h_max": 0}, r"^h_max: expected a largest step of at least"),
        ({"v_rest": -1.0}, r"^v_rest: expected a rest threshold >= 0"),
        ({"theta_fall": 5.0}, r"^theta_fall: expected an overturning tilt in \(alpha, pi/2\]"),
        ({"theta_fall": 0.0}, r"^theta_fall: expected an overturning tilt"),
        ({"t0": math.nan}, r"^t0: expected a finite start time"),
        ({"thetad0": math.nan}, r"^thetad0: expected a finite angular velocity"),
        ({"max_impacts": 2.5}, r"^max_impacts: expected a whole number >= 1"),
    ],
)
def test_a_rocking_run_refuses_settings_without_meaning(kw, match):
    with pytest.raises(ValueError, match=match):
        nsdyn.simulate_rocking(BLOCK, PULSE, t_end=1.0, **kw)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: nsdyn.one_sine(3.9, 12.0, ver_ratio=math.nan), r"^ver_ratio: expected a finite"),
        (lambda: nsdyn.one_sine(3.9, 12.0, t_start=math.inf), r"^t_start: expected a finite"),
        (lambda: nsdyn.rectangular(3.0, 0.0), r"^duration: expected a positive duration"),
        (lambda: nsdyn.one_sine("3", 4.0), r"^a_p: expected a finite amplitude"),
        (lambda: nsdyn.n_cycle_sine(1.0, 1.0, True), r"^n_cycles: expected an integer >= 1"),
    ],
)
def test_a_pulse_refuses_what_is_not_a_number(make, match):
    with pytest.raises(ValueError, match=match):
        make()


BODY = nsdyn.RigidBody.rectangle(0.5, 1.5, 1000.0)
LAW = nsdyn.FrictionLaw(0.6, 0.6, 0)


@pytest.mark.parametrize("solver", ["event", "moreau"])
def test_a_contact_start_inside_the_ground_or_given_twice_is_refused(solver):
    run = nsdyn.simulate_event if solver == "event" else nsdyn.simulate_moreau
    # the rectangle's centre rests at half its height, 0.75 m: at 0.5 m a corner is 0.25 m in
    with pytest.raises(ValueError, match=r"^q0: a corner starts 0.25 m below the rigid ground"):
        run(BODY, LAW, None, t_end=1.0, q0=[0.0, 0.5, 0.0])
    with pytest.raises(ValueError, match=r"^q0: the start is given as a tilt .* and as q0"):
        run(BODY, LAW, None, t_end=1.0, theta0=0.1, q0=[0.0, 0.75, 0.0])
    with pytest.raises(ValueError, match=r"^v0: expected 3 finite values"):
        run(BODY, LAW, None, t_end=1.0, v0=[math.nan, 0.0, 0.0])
    # at rest on the ground exactly: accepted, and it stays there (no excitation)
    r = run(BODY, LAW, None, t_end=0.2, q0=[0.0, 0.75, 0.0])
    assert np.array_equal(r.q[0], [0.0, 0.75, 0.0])


def test_the_housner_law_takes_no_restitution_and_a_moreau_step_fits_the_run():
    with pytest.raises(ValueError, match=r"^e_n: the Housner law is plastic"):
        nsdyn.simulate_event(BODY, LAW, None, t_end=1.0, impact_law="housner", e_n=0.9)
    with pytest.raises(ValueError, match=r"^h: a step of 0.6 s is longer than the run"):
        nsdyn.simulate_moreau(BODY, LAW, None, t_end=0.5, h=0.6, theta0_over_alpha=0.5)


def test_a_cylinder_run_refuses_a_start_without_meaning_and_rest_balances():
    dt, ag = nsdyn.cylinder_earthquake(2, duration=1.0)
    p = nsdyn.CylinderParams()
    for kw, match in (({"t0": math.nan}, r"^t0: expected a finite start time"),
                      ({"omega0": (0.0, 0.0)}, r"^omega0: expected three finite rates"),
                      ({"omega0": (True, 0.0, 0.0)}, r"^omega0: expected three finite rates"),
                      ({"theta_topple": 3.0}, r"^theta_topple: expected a toppling tilt"),
                      ({"h_kink": 0.0}, r"^h_kink: expected a positive step bound")):  # fmt: skip
        with pytest.raises(ValueError, match=match):
            nsdyn.simulate_cylinder(p, ag, dt, **kw)
    # at rest the balance moves no energy: its residual is round-off of the body's own energy
    # E_mech (39 J), not a ratio of two round-offs (it read 1.4e5)
    rest = nsdyn.simulate_cylinder(p, np.zeros((501, 3)), 0.01)
    assert rest.energy_error <= 1e3 * np.finfo(float).eps


def test_a_cylinder_call_refuses_what_its_scene_refuses():
    from nsdyn.models.cylinder.design import design_foundation, rocking_frequency
    from nsdyn.models.cylinder.simulate import from_motions
    from nsdyn.models.cylinder.study import compare_foundations

    dt, ag = nsdyn.cylinder_earthquake(2, duration=1.0)
    # k = 1 N/m³ settles m g / (pi r^2 k) = 9.81 / pi = 3.12 m > r = 1 m: the base sank 3.1 m
    # and never lifted (tensionless equal to bonded), where a scene refuses the foundation
    with pytest.raises(ValueError, match=r"^k: the static settlement .* = 3\.123 m exceeds"):
        nsdyn.simulate_cylinder(nsdyn.CylinderParams(k=1.0), ag, dt)
    with pytest.raises(ValueError, match=r"^max_steps: expected a whole number of steps >= 1"):
        nsdyn.simulate_cylinder(nsdyn.CylinderParams(), ag, dt, max_steps="10")
    with pytest.raises(ValueError, match=r"^r, H, m, k: expected sizes whose inertias"):
        nsdyn.CylinderParams(H=1e300)  # (an OverflowError in the run)
    for args, match in (((3, math.inf, 1, 4, 1), r"^zeta: expected a damping ratio in \[0, 1\)"),
                        ((3, 5, 1, 4, 1), r"^zeta: expected a damping ratio"),
                        ((math.inf, 0.1, 1, 4, 1), r"^f_rock: expected a positive finite"),
                        (("3", 0.1, 1, 4, 1), r"^f_rock: expected")):  # fmt: skip
        with pytest.raises(ValueError, match=match):  # (k = inf returned; '3' a TypeError)
            design_foundation(*args)
    for call, err, match in ((lambda: compare_foundations("3"), ValueError, r"^n: expected"),
                             (lambda: compare_foundations(1, {"r": 1}), TypeError, r"^params: "),
                             (lambda: compare_foundations(1, executor="x"), TypeError,
                              r"^executor: expected a concurrent"),
                             (lambda: from_motions(ag), TypeError, r"^mx: expected a GroundMotion"),
                             (lambda: rocking_frequency("x"), TypeError, r"^p: expected"),
                             ):  # fmt: skip
        with pytest.raises(err, match=match):  # (AttributeErrors and TypeErrors from inside)
            call()


def test_a_ground_motion_keeps_its_own_samples():
    # it kept the caller's array: a[0] = 100 afterwards changed the record and its PGA
    a = np.array([0.1, 0.2, -0.3, 0.05])
    g = nsdyn.GroundMotion(0.0, 0.01, a)
    a[0] = 100.0
    assert g.a_hor[0] == 0.1 and g.pga == 0.3


def test_numpy_scalars_are_numbers_and_text_flags_are_refused():
    # np.float32(0.3) was refused as "no positive size"; linear="no" was taken as True
    blk = nsdyn.RockingBlock(width=np.float32(0.5), height=np.int64(2), mass=np.float32(2.0))
    assert (blk.width, blk.height, blk.mass) == (0.5, 2.0, 2.0)  # (exact in float32: 2^-1)
    assert nsdyn.RigidBody.rectangle(np.float32(1.0), 2.0).mass == 1.0
    with pytest.raises(TypeError, match=r"^linear: expected True or False, got 'no'"):
        nsdyn.RockingBlock(width=0.3, height=1.2, linear="no")
    with pytest.raises(TypeError, match=r"^linear: expected True or False"):
        nsdyn.RockingFrame(width=0.3, height=1.2, gamma=1.0, linear="no")
    with pytest.raises(TypeError, match=r"^trim: expected True or False"):
        nsdyn.read_motion3("synthetic-wn-40s", trim="no")


@pytest.mark.parametrize(
    ("call", "err", "match"),
    [
        # ZeroDivisionError, numpy's "negative dimensions", AttributeErrors and a math domain
        # error before
        (lambda: nsdyn.simulate_compliant(nsdyn.CompliantBlock(width=1.0, height=2.0,
                                          mass=1e3, k=1e7, c=1e4), t_end=1.0, dt_out=0),
         ValueError, r"^dt_out: expected a positive output step"),
        (lambda: nsdyn.simulate_compliant(nsdyn.CompliantBlock(width=1.0, height=2.0,
                                          mass=1e3, k=1e7, c=1e4), t_end=1.0, h_max=0),
         ValueError, r"^h_max: expected a positive largest step"),
        (lambda: nsdyn.simulate_event(BODY, LAW, None, t_end=1.0, g=-9.81),
         ValueError, r"^g: expected a positive number"),
        (lambda: nsdyn.simulate_moreau(BODY, LAW, None, t_end=1.0, g=0.0),
         ValueError, r"^g: expected a positive gravity"),
        (lambda: nsdyn.write_motion(nsdyn.read_motion3("synthetic-wn-40s"), "x.csv"),
         TypeError, r"^motion: expected a GroundMotion, got GroundMotion3; write_motion3"),
        (lambda: nsdyn.overturning_spectrum(nsdyn.CompliantBlock(width=1.0, height=2.0,
                                            mass=1.0, k=1e5, c=1.0), "sine", [1.0]),
         TypeError, r"^model: expected a RockingBlock or RockingFrame"),
        # text where a number belongs: a comparison or division failed inside before
        (lambda: nsdyn.simulate_rocking(BLOCK, None, t_end="2", theta0=0.1),
         ValueError, r"^t_end: expected a finite end time > t0"),
        (lambda: nsdyn.simulate_compliant(nsdyn.CompliantBlock(width=1.0, height=2.0,
                                          mass=1e3, k=1e7, c=1e4), t_end="1"),
         ValueError, r"^t_end: expected a positive finite end time"),
        (lambda: nsdyn.simulate_moreau(BODY, LAW, None, t_end="1"),
         ValueError, r"^t_end: expected a positive duration"),
        (lambda: nsdyn.simulate_moreau(BODY, LAW, None, t_end=1.0, theta="1"),
         ValueError, r"^theta: expected 0.5 <= theta <= 1"),
        (lambda: nsdyn.CylinderParams(k=[1.0, 2.0]),
         ValueError, r"^k: expected a positive finite number"),
        (lambda: nsdyn.read_motion("synthetic-wn-40s", dt="0.01"),
         ValueError, r"^dt: expected a positive sampling interval"),
    ],
)  # fmt: skip
def test_calls_name_the_argument_instead_of_failing_inside(call, err, match, tmp_path,
                                                           monkeypatch):  # fmt: skip
    monkeypatch.chdir(tmp_path)
    with pytest.raises(err, match=match):
        call()


def test_the_compliant_contact_names_a_ground_of_the_wrong_kind():
    from nsdyn.models.contact.compliant import simulate_compliant

    with pytest.raises(TypeError, match=r"^ground: expected a CompliantGround"):
        simulate_compliant(BODY, LAW, 1e8, t_end=1.0)


def test_a_restart_from_a_moreau_jean_state_is_a_valid_start():
    # Moreau-Jean leaves its corners a fraction of a millimetre in the ground (0.18 mm here):
    # a restart from its last state must run, a body placed 0.25 m in the ground must not
    law = nsdyn.FrictionLaw(0.6, 0.6, 0)
    r = nsdyn.simulate_moreau(BODY, law, None, t_end=1.0, theta0_over_alpha=0.5, h=1e-3)
    again = nsdyn.simulate_moreau(BODY, law, None, t_end=0.1, q0=r.q[-1], v0=r.v[-1])
    assert np.array_equal(again.q[0], r.q[-1])


def test_whole_numpy_counts_and_iterables_of_sections_are_taken():
    from nsdyn.structure import Section, regular_frame

    assert nsdyn.n_cycle_sine(1.0, 2.0, np.int64(2)).n_cycles == 2
    s = Section(E=2e11, A=0.01, I=1e-4, rho_A=80.0)
    gen = regular_frame("f", [6.0], [3.0, 3.0], 1, 1, (s for _ in range(2)), s, floor_mass=1e4)
    lst = regular_frame("f", [6.0], [3.0, 3.0], 1, 1, [s, s], s, floor_mass=1e4)
    assert np.array_equal(gen.nodes, lst.nodes) and len(gen.elements) == len(lst.elements)


@pytest.mark.parametrize(
    ("args", "match"),
    [
        # the plain constructor took any arrays: a clockwise outline, a base off the ground
        (lambda b: (b.verts[::-1], b.mass, b.J, b.base), r"^verts: expected the vertices counter"),
        (lambda b: (b.verts, 0.0, b.J, b.base), r"^mass: expected a positive mass"),
        (lambda b: (b.verts, b.mass, "1", b.base), r"^J: expected a positive moment of inertia"),
        (lambda b: (b.verts, b.mass, b.J, [2, 3]), r"^base: expected the indices of the lowest"),
        (lambda b: (b.verts, b.mass, b.J, []), r"^base: expected the indices of the lowest"),
        # a part of the base: its other corner's side was the base edge (overturned at 0 rad)
        (lambda b: (b.verts, b.mass, b.J, b.base[:1]), r"^base: expected the indices of the l"),
    ],
)  # fmt: skip
def test_a_rigid_body_built_directly_is_checked_as_its_builders_check(args, match):
    with pytest.raises(ValueError, match=match):
        nsdyn.RigidBody(*args(BODY))
    same = nsdyn.RigidBody(BODY.verts, BODY.mass, BODY.J, BODY.base)  # a valid body: equal
    assert np.array_equal(same.contacts, BODY.contacts) and same.verts is not BODY.verts


def test_a_displacement_sine_s_ramps_belong_to_the_smooth_start_and_do_not_overlap():
    with pytest.raises(ValueError, match=r"^t_ramp: the ramps of start='smooth'"):
        nsdyn.BaseMotion.displacement_sine(0.01, 0.5, 4, "impulsive", t_ramp=0.5)
    with pytest.raises(ValueError, match=r"^t_ramp: expected .* at most half the motion, 1 s"):
        nsdyn.BaseMotion.displacement_sine(0.01, 0.5, 4, "smooth", t_ramp=1.5)


def test_rocking_and_contact_runs_refuse_what_they_would_run_wrong_or_for_ever():
    blk = nsdyn.RockingBlock(width=0.3, height=1.2)
    # a phase was dropped (phase pi/2 lifted the block at the phase-0 time); a vertical alone
    # was scaled to A_hor = 0 and dropped: 'rest' under 2 g up
    up = nsdyn.Harmonic(0.0, 1.0, A_ver=-20.0, f_ver=1.0)
    for exc, match in ((nsdyn.Harmonic(3.0, 1.0, phase=math.pi / 2), r"^Harmonic\.phase: "),
                       (up, r"^Harmonic\.A_hor: ")):  # fmt: skip
        with pytest.raises(ValueError, match=match):
            nsdyn.simulate_rocking(blk, exc, t_end=1.0)
    # a pulse of 1e7 rad/s stepped for minutes, 1e300 for ever (p = sqrt(3 g / 4 R) with
    # R = sqrt(0.15² + 0.6²) = 0.61847 m: p = 3.4491 /s, and 1e7 / p = 2.8993e6)
    with pytest.raises(
        ValueError, match=r"^excitation: a frequency of 1e\+07 rad/s, 2\.8993e\+06 "
    ):
        nsdyn.simulate_rocking(blk, nsdyn.Pulse("sine", 3.92, 1e7), t_end=6.0, dt_out=0.002)
    comp = nsdyn.CompliantBlock.from_frequency(width=0.3, height=1.2, mass=1.0, omega_v=300.0,
                                               zeta=2.0)  # fmt: skip
    with pytest.raises(
        ValueError, match=r"^excitation: a frequency of 1e\+07 rad/s, 2\.8993e\+06 "
    ):
        nsdyn.simulate_compliant(comp, nsdyn.Pulse("sine", 3.92, 1e7), t_end=6.0)  # (the same p)
    with pytest.raises(ValueError, match=r"^h_max: expected a largest step of at least"):
        nsdyn.simulate_rocking(blk, None, t_end=1.0, h_max=1e-12, theta0_over_alpha=0.5)
    # a contact body's start past overturning through q0 ran "not overturned" (theta0 is refused)
    with pytest.raises(ValueError, match=r"^q0: a tilt of 4 rad is at or past"):
        nsdyn.simulate_event(BODY, LAW, None, t_end=1.0, q0=[0.0, 2.0, 4.0])
    with pytest.raises(TypeError, match=r"^body: expected a RigidBody"):
        nsdyn.simulate_moreau(None, LAW, None, t_end=1.0)
    # the contact family keeps a harmonic's phase (sin(omega t + phase))
    assert nsdyn.BaseMotion.from_motion(nsdyn.Harmonic(3.0, 1.0, phase=1.0)).ex[7] == 1.0


@pytest.mark.parametrize(
    ("call", "match"),
    [
        # text compared with numbers (TypeErrors from inside), True taken as 1, NaN or a negative
        # stiffness run to a "non-finite state" or silently
        (lambda: nsdyn.RockingBlock(width=0.3, height=1.2, r="0.5"), r"^r: expected 0 <= r <= 1"),
        (lambda: nsdyn.RockingBlock(width=0.3, height=1.2, r=True), r"^r: expected 0 <= r <= 1"),
        # half sizes are named as given (H = -1 was "height: ..., got -2")
        (lambda: nsdyn.RockingBlock(B=0.5, H=-1.0), r"^RockingBlock: H: expected a positive size "
         r"\[m\], got -1\.0$"),
        (lambda: nsdyn.RockingBlock(B=0.5), r"^RockingBlock: H: missing \(the half height"),
        (lambda: nsdyn.FrictionLaw(0.5, 0.4, C="x"), r"^C: expected a non-negative decay"),
        (lambda: nsdyn.simulate_event(BODY, LAW, None, t_end=0.1, e_n="0.5"), r"^e_n: expected"),
        (lambda: nsdyn.simulate_event(BODY, LAW, None, t_end=0.1, max_events=2.5),
         r"^max_events: expected a whole number"),
        (lambda: nsdyn.CompliantBlock(width=1.0, height=2.0, mass=1e3, k=1e7, c=1e4, k_t=-1e9),
         r"^k_t: expected a positive number"),
        (lambda: nsdyn.CompliantBlock.from_frequency(width=1.0, height=2.0, mass=1e3,
                                                     omega_v=1e300, zeta=1.0),
         r"^omega_v: expected a positive frequency"),
        (lambda: nsdyn.simulate_compliant(nsdyn.CompliantBlock(width=1.0, height=2.0, mass=1e3,
                                                               k=1e7, c=1e4), t_end=0.1, tol=5),
         r"^tol: expected a relative tolerance"),
        (lambda: nsdyn.BaseMotion.sine_acceleration(8.0, 1.0, t_on=math.nan), r"^t_on: expected"),
        (lambda: nsdyn.BaseMotion.sine_acceleration("3", 1.0), r"^amp: expected a finite"),
        (lambda: nsdyn.overturning_spectrum(nsdyn.RockingBlock(width=0.3, height=1.2), [[1, 2]]),
         r"^omega_ratios: expected frequency ratios"),
        # 1e6 smooth cycles tabulated at 4000 a period: a MemoryError of 30 GiB
        (lambda: nsdyn.BaseMotion.displacement_sine(0.01, 1.0, 10**6, "smooth"),
         r"^n_cycles: expected a whole number >= 1 \(at most 6250"),
    ],
)  # fmt: skip
def test_rocking_and_contact_parts_refuse_values_they_cannot_mean(call, match):
    with pytest.raises(ValueError, match=match):
        call()
