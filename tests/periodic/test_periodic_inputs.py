"""Bad arguments of the periodic solvers and of the isolator parameters: one clear ValueError.

The contract (house rule for bad input): the error names the argument and the expected form,
raised where the value enters (a constructor or a solver's front door), before any
integration, instead of a ZeroDivisionError, a NaN deep inside, or a "converged" orbit of a
meaningless problem (a negative frequency integrates backwards in time; mu < 0 or eps < 0 feed
energy in).
"""

import math

import numpy as np
import pytest

from nsdyn import periodic as pr
from nsdyn.models.isolated.builders import system_from_matrices
from nsdyn.models.isolated.system import Isolation
from nsdyn.periodic.switch import shoot_switch, switch_problem, switch_response

BAD_F = [-0.1, 0.0, math.nan, math.inf, "1 Hz"]


def _oscillator(law="switch"):
    iso = Isolation(k_lam=0.0, c=0.0, mu=0.1, law=law)
    return system_from_matrices([[1.0]], [[0.1]], [[(2 * math.pi) ** 2]], iso_dofs=[0],
                                influence=[1.0], isolation=iso, weight=iso.g,
                                levels=[[0]])  # fmt: skip


@pytest.mark.parametrize("f", BAD_F)
def test_shooting_rejects_a_frequency_that_is_not_positive(f):
    prob = pr.duffing_problem(0.05, 1.0, 0.1, 0.5)
    with pytest.raises(ValueError, match=r"^f: expected a forcing frequency in \[1e-06, 1"):
        pr.shoot(prob, f)
    with pytest.raises(ValueError, match=r"^f: expected a forcing frequency in"):
        pr.steady_state_sweep(prob, f)
    with pytest.raises(ValueError, match=r"^f: expected a forcing frequency in"):
        pr.period_map(prob, prob.x_ref, f)


@pytest.mark.parametrize(
    "kw, err, match",
    [
        # 0 steps "converged" on x0 = 0 with every multiplier 1; 2.7 was cut to 2
        ({"n_steps": 0}, ValueError, r"^n_steps: expected .* steps per period >= 20"),
        ({"n_steps": 2.7}, ValueError, r"^n_steps: expected a whole number"),
        ({"x0": [0.0, 0.0, 0.0]}, ValueError, r"^x0: expected 2 finite numbers"),
        ({"x0": [math.nan, 0.0]}, ValueError, r"^x0: .* with NaN or inf"),
        ({"tol": -1.0}, ValueError, r"^tol: expected a positive finite residual"),
        ({"max_iter": -1}, ValueError, r"^max_iter: expected a whole number >= 0"),
        ({"disc": "sdirk2"}, TypeError, r"^disc: expected a Discretisation"),
    ],
)
def test_shooting_names_the_argument_it_cannot_run_on(kw, err, match):
    prob = pr.duffing_problem(0.05, 1.0, 0.1, 0.5)
    with pytest.raises(err, match=match):
        pr.shoot(prob, 0.2, **kw)
    with pytest.raises(TypeError, match=r"^problem: expected a periodic problem"):
        pr.shoot("duffing", 0.2)


def test_a_frame_without_forcing_is_not_shot():
    # amplitude 0: the steady state is the static state; shot, its residual, scaled by an
    # orbit of round-off (1.7e-12 m), read 0.46 and every point was "no period-1 response"
    import nsdyn

    system = nsdyn.build_system(nsdyn.load_frame("office-11"), fidelity="cb", f_max=5.0)
    with pytest.raises(ValueError, match=r"^amplitude 0: no forcing, so the steady state is "):
        pr.shoot(pr.frame_problem(system, 0.0), 0.5)
    with pytest.raises(ValueError, match=r"^amplitude 0: ") as e:
        nsdyn.frequency_response(system, 0.0, fmin=0.5, fmax=1.0, points=3)
    assert "x_ref" not in str(e.value)  # (no name the user never typed)


@pytest.mark.parametrize("f", BAD_F)
def test_switch_shooting_rejects_a_frequency_that_is_not_positive(f):
    # f = -0.1 used to "converge" after 0 iterations with a multiplier of 1e54
    prob = switch_problem(_oscillator(), 1.0)
    with pytest.raises(ValueError, match=r"^f: expected a forcing frequency in"):
        shoot_switch(prob, f)


@pytest.mark.parametrize(
    "field, value",
    [("mu", -0.1), ("eps", -1.0), ("mu", math.nan), ("k_lam", (5e4, -1.0)), ("c", math.inf),
     ("eta", -1e-5), ("alpha", "fast"),
     # one value for all isolators only (a list of eps or g was a TypeError from '>')
     ("eps", [7500.0, 7500.0]), ("g", [9.81, 9.8]), ("eta", [1e-5, 1e-5]), ("eps", [100.0]),
     ("g", [9.81])],
)  # fmt: skip
def test_isolation_rejects_negative_or_non_finite_parameters(field, value):
    # a list for a single-valued parameter: "one (for every isolator)"
    single = np.ndim(value) == 0 or field in ("mu", "k_lam", "c")
    one = "a " if single else r"one \(for every isolator\) "
    sign = "positive" if field in ("g", "eps") else "non-neg"  # (the default law: arctan, eps)
    with pytest.raises(ValueError, match=rf"^isolation\.{field}: expected {one}finite {sign}"):
        Isolation(**{field: value})


def test_isolation_rejects_an_unknown_law():
    with pytest.raises(ValueError, match=r"^isolation\.law: expected 'arctan', 'switch' or"):
        Isolation(law="coulomb")


def test_a_frame_problem_names_what_it_cannot_shoot():
    # a frame's name or None failed on a missing attribute (AttributeError: 'str' object has
    # no attribute 'isolation'); a non-smooth law's message did not name the argument
    for system in (None, "office-11"):
        with pytest.raises(TypeError, match=r"^system: expected an IsolatedSystem .* got "):
            pr.frame_problem(system, 1.0)
    with pytest.raises(ValueError, match=r"^law: shooting needs a smooth friction law .* got "
                       r"'bogus' \(the switch law's curve: nsdyn.switch_response, its "
                       r"problem: switch_problem\)$"):  # fmt: skip
        pr.frame_problem(_oscillator("arctan"), 1.0, law="bogus")


@pytest.mark.parametrize("amplitude", [math.nan, -1.0, math.inf])
def test_problem_constructors_reject_a_bad_amplitude(amplitude):
    with pytest.raises(ValueError, match=r"^amplitude: expected a finite forcing amplitude"):
        pr.frame_problem(_oscillator("arctan"), amplitude)
    with pytest.raises(ValueError, match=r"^amplitude: expected a finite forcing amplitude"):
        switch_problem(_oscillator(), amplitude)
    with pytest.raises(ValueError, match=r"^F: expected a finite forcing amplitude"):
        pr.duffing_problem(0.05, 1.0, 0.1, amplitude)
    with pytest.raises(ValueError, match=r"^w0: expected a finite number > 0"):
        pr.duffing_problem(0.05, 0.0, 0.1, 1.0)


def test_a_ground_acceleration_above_100_g_is_refused_a_force_is_not_capped():
    # 1e300 m/s² overflowed a sweep's uplift probe into a traceback; a force's amplitude [N]
    # has no such scale (a building's harmonic load is 1e6 N and more)
    from nsdyn.models.isolated.bearings import Bearing, Friction
    from nsdyn.models.isolated.deck import sdof_plane
    from nsdyn.periodic.plane import plane_problem
    from nsdyn.periodic.protocol import A_HIGHEST

    big = 1.01 * A_HIGHEST
    match = r"^amplitude: expected a finite forcing amplitude >= 0 and <= 1000 m/s²"
    with pytest.raises(ValueError, match=match):
        pr.frame_problem(_oscillator("arctan"), big)
    with pytest.raises(ValueError, match=match):
        switch_problem(_oscillator(), big)
    deck = sdof_plane(1.0e5, Bearing(Friction(0.05), radius=2.0))
    with pytest.raises(ValueError, match=match):
        plane_problem(deck, {"f": 1.0, "ax": 1.0}, amplitude=big)
    pr.frame_problem(_oscillator("arctan"), A_HIGHEST)  # the bound itself is taken
    from nsdyn.ground.excitation import HarmonicForce

    load = HarmonicForce(F=1.0, f=1.0, dofs=(0,))
    assert switch_problem(_oscillator(), 1e7, load=load).amplitude == 1e7


@pytest.mark.parametrize(
    "options, message",
    [
        ({"fmin": -0.5, "fmax": 2.0}, r"^fmin: expected a forcing frequency in"),
        ({"fmin": 0.0, "fmax": 2.0}, r"^fmin: expected a forcing frequency in"),
        ({"fmin": 2.0, "fmax": 1.0}, r"^fmax: expected a frequency above fmin = 2 Hz, got 1"),
        ({"fmin": 1.0, "fmax": math.nan}, r"^fmax: expected a forcing frequency in"),
        ({"fmin": 1.0, "fmax": 2.0, "points": 0}, r"^points: expected an integer from 1 to 10000"),
        (
            {"fmin": 1.0, "fmax": 2.0, "points": 2.5},
            r"^points: expected an integer from 1 to 10000",
        ),
        # 10^12 points: numpy's MemoryError of 7 TiB
        ({"fmin": 1.0, "fmax": 2.0, "points": 10**12}, r"^points: expected an integer from 1 "),
    ],
)
@pytest.mark.parametrize("continuation", ["sequential", "arclength"])
def test_switch_response_rejects_a_bad_frequency_range(options, message, continuation):
    # fmin < 0 gave a NaN error from deep inside, fmin > fmax one point, points = 0 an empty
    # curve: each is now one error naming the argument, before any orbit is computed
    with pytest.raises(ValueError, match=message):
        switch_response(_oscillator(), 1.0, continuation=continuation, **options)


def test_sequential_continuation_rejects_unordered_frequencies():
    prob = pr.duffing_problem(0.05, 1.0, 0.1, 0.5)
    with pytest.raises(ValueError, match=r"^freqs: expected increasing finite frequencies > 0"):
        pr.continue_sequential(prob, [0.3, 0.2, 0.1])
    # a generator ended in float()'s message, text "0.3" was quoted as the number 0.3
    for freqs, said in (((f for f in [0.3, 0.5]), "<generator"), ("0.3", "'0.3'")):
        with pytest.raises(ValueError, match=rf"^freqs: expected increasing .* got {said}"):
            pr.continue_sequential(prob, freqs)
    with pytest.raises(ValueError, match=r"^fmax: expected a frequency above fmin"):
        pr.log_frequencies(1.0, 0.5, 10)
    # one point of a range was fmin alone, fmax dropped without a word
    with pytest.raises(ValueError, match=r"^points: expected at least 2 to span fmin = 1 to"):
        pr.continue_range(prob, fmin=1.0, fmax=2.0, points=1)
    assert pr.log_frequencies(1.5, 1.5, 1).tolist() == [1.5]  # fmin == fmax: one frequency


@pytest.mark.parametrize("f", [-1.0, 0.0, math.nan])
def test_unilateral_sweep_rejects_a_frequency_that_is_not_positive(frame, f):
    import numpy as np

    from nsdyn.models.isolated.system import build_system

    s = build_system(frame, Isolation(), fidelity="rigid")
    with pytest.raises(ValueError, match=r"^f: expected a forcing frequency in"):
        pr.unilateral_steady_state(pr.frame_problem(s, 1.0), f, np.zeros(2 * s.n))


@pytest.mark.parametrize(
    "kw, match",
    [({"method": "sdirk4"}, r"^method: expected one of \['euler', 'sdirk2', 'sdirk3'\]"),
     ({"method": "SDIRK2"}, r"^method: expected one of"),
     ({"n_min": 0}, r"^n_min: expected a whole number of steps >= 1"),
     ({"n_max": 2.5}, r"^n_max: expected a whole number"),
     ({"dt_max": 0.0}, r"^dt_max: expected a positive finite step"),
     ({"dt_max": True}, r"^dt_max: expected a positive finite step"),
     ({"n_min": 500, "n_max": 100}, r"^n_max: expected at least n_min = 500 steps, got 100"),
     # a stage tolerance of NaN, < 0 or >= 1 gave a wrong orbit reported as converged
     ({"rtol": math.nan}, r"^rtol: expected a finite relative tolerance 0 <= rtol < 1"),
     ({"rtol": -1.0}, r"^rtol: expected a finite relative tolerance"),
     ({"rtol": 10.0}, r"^rtol: expected a finite relative tolerance"),
     ({"atol": -1.0}, r"^atol: expected a finite tolerance >= 0"),
     ({"atol": math.nan}, r"^atol: expected a finite tolerance >= 0"),
     # 3 steps per period gave a linear resonance 66 % high, 1 a zero orbit, both "converged"
     ({"n_min": 3}, r"^n_min: 3 steps per period do not resolve it"),
     ({"n_min": 19, "n_max": 19}, r"^n_min: 19 steps per period do not resolve it")],
)  # fmt: skip
def test_a_discretisation_is_checked_where_it_is_made(kw, match):
    # an unknown tableau was accepted and failed inside the first shooting's traceback
    with pytest.raises(ValueError, match=match):
        pr.Discretisation(**kw)


def test_a_discretisation_holds_floats_and_ints_whatever_it_was_given():
    # atol = 0 (a Python int) reached the compiled period map as an int: a typing error
    d = pr.Discretisation(rtol=0, atol=1, dt_max=1, n_min=np.int64(40))
    assert [type(v) for v in (d.rtol, d.atol, d.dt_max, d.n_min)] == [float, float, float, int]
    assert pr.refined(d, 0.5).n_min == 20
    with pytest.raises(ValueError, match=r"^factor: 0\.25 x 40 steps per period is below"):
        pr.refined(d, 0.25)


@pytest.mark.parametrize("continuation", ["sequential", "arclength"])
@pytest.mark.parametrize(
    ("kw", "match"),
    [
        # each failed deep inside: "'str' object has no attribute 'steps'", "'int' object is
        # not callable" after the first point, "'int' object has no attribute 'f'"
        ({"disc": "sdirk2"}, r"^disc: expected a Discretisation, got str"),
        ({"progress": 5}, r"^progress: expected a callable"),
        ({"start": [1, 2]}, r"^start: expected the OrbitPoints of a curve"),
    ],
)
def test_continuation_names_an_option_of_the_wrong_kind(continuation, kw, match):
    prob = pr.duffing_problem(0.02, 1.0, 0.3, 0.045)
    with pytest.raises(TypeError, match=match):
        if continuation == "sequential":
            pr.continue_sequential(prob, [0.15, 0.16], **kw)
        else:
            pr.continue_arclength(prob, 0.15, 0.16, points=3, **kw)


def test_a_point_without_an_orbit_has_no_stability_verdict():
    # a stepped sweep that did not reach its steady state kept the multipliers of its last
    # period, and the CSV called the point stable; no orbit, no verdict (the CSV's cell empty)
    from nsdyn.periodic.curve import OrbitPoint

    rho = np.array([0.5, 0.2])
    args = (1.0, np.zeros(2), "sweep")
    assert OrbitPoint(*args, False, 0, 0.1, rho, 10, "", {}).stable is None
    assert OrbitPoint(*args, True, 0, 1e-9, rho, 10, "", {}).stable is True
    # a grazing orbit: its note says the multipliers are unreliable, and the CSV called it
    # stable beside that note; no verdict either (its multipliers still reported)
    grazing = OrbitPoint(*args, True, 0, 1e-9, rho, 10, "grazing: …", {"graze": 1e-5})
    assert grazing.stable is None and grazing.max_multiplier == 0.5
    clear = OrbitPoint(*args, True, 0, 1e-9, rho, 10, "", {"graze": 0.1})
    assert clear.stable is True


@pytest.mark.parametrize("curve", [pr.frequency_response, switch_response])
def test_a_curve_says_its_loads_own_force_amplitude_is_not_used(curve):
    # HarmonicForce(500, ...) with amplitude 1 ran at 1 N without a word: the curve's force
    # amplitude is `amplitude` (the load gives dofs, weights, phase); the same F: no warning
    import warnings

    from nsdyn._checks import InputWarning
    from nsdyn.ground.excitation import HarmonicForce

    law = "arctan" if curve is pr.frequency_response else "switch"
    kw = dict(fmin=1.0, fmax=1.0, points=1)
    with pytest.warns(InputWarning, match=r"^load: its F = 2 N is not used: a curve's force "
                      r"amplitude is amplitude \(1 N"):  # fmt: skip
        curve(_oscillator(law), 1.0, load=HarmonicForce(2.0, 1.0, dofs=(0,)), **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        curve(_oscillator(law), 1.0, load=HarmonicForce(1.0, 1.0, dofs=(0,)), **kw)
        for bad in (math.nan, None):  # (checked before the note: its text broke on them)
            with pytest.raises((ValueError, TypeError), match=r"^amplitude: expected"):
                curve(_oscillator(law), bad, load=HarmonicForce(2.0, 1.0, dofs=(0,)), **kw)


def test_points_says_a_curve_needs_two_unless_it_is_one_frequency():
    # points=0 said "from 1", and then 1 was refused for fmin < fmax
    with pytest.raises(
        ValueError,
        match=r"^points: expected an integer from 1 to 10000 "
        r"\(frequencies on the curve; 2 or more unless fmax = fmin\), got 0",
    ):
        pr.frequency_response(_oscillator("arctan"), 1.0, fmin=0.5, fmax=0.6, points=0)
