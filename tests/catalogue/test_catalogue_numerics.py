"""Catalogue of numerical failures: each one provoked on a small system with a tiny budget.

Contract: a failure is reported, never silent — an exception (or a result flagged as failed)
whose message gives the time (or frequency) reached, the reason and what to try. Rows:
step budget / underflow (stiff problem on an explicit method), Newton divergence (fixed step
over a discontinuous friction law), non-finite state (a record that turns NaN), uplift (a
rigid block tipping), shooting non-convergence (a Newton budget of one iteration on a friction
orbit), Zeno accumulation of impacts (a rocking block coming to rest), overturning, and the
cylinder's step budget. Library rows at the end: bad arguments of the excitations, isolator
parameters, shooting and frequency ranges (one ValueError naming the argument and the expected
form, before any integration), a stability verdict checked against a second map before
"unstable" is reported, and a spectrum NaN that says "not found up to a_max". Related rows
elsewhere: tests/solve/test_integrate.py
(test_dopri5_reports_stiffness_instead_of_grinding, test_fixed_step_newton_failure_is_reported,
test_nan_in_ground_record_is_reported, test_uplift_of_a_rocking_block),
tests/models/rocking/test_rocking_block.py (Zeno, overturning criteria),
tests/models/cylinder/test_cylinder_dynamics.py (step budget).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from nsdyn import Harmonic, Table
from nsdyn.models.isolated.params import pack
from nsdyn.models.isolated.statespace import demo_frame
from nsdyn.models.isolated.system import Isolation, build_system
from nsdyn.solve.integrate import IntegrationError, UpliftError, solve

G = 9.81
M_C, MU_C, K_C = 2.0, 0.3, 2.0 * (2 * np.pi) ** 2  # 1 Hz Coulomb oscillator


def _coulomb(law: str, eps: float = 7500.0, ground=None) -> tuple:
    """One mass on a friction isolator (q = [x, y], contact y = 0 carries m g)."""
    return pack(np.eye(2) * M_C, np.zeros((2, 2)), np.diag([K_C, 0.0]), np.eye(2),
                R=[[0.0, 1.0]], D=[[1.0, 0.0]], mu=MU_C, lam_static=[M_C * G], law=law,
                eps=eps, g=G, ground=ground)  # fmt: skip


def _time_in(msg: str) -> float:
    m = re.search(r"t = ([-+0-9.eE]+)", msg)
    assert m, f"no time in {msg!r}"
    return float(m.group(1))


def test_step_budget_on_a_stiff_problem_names_time_reason_and_remedy():
    # eps = 1e6 s/m: the arctan friction law is stiff; dopri5 with 2000 steps cannot cross 1 s
    P = _coulomb("arctan", eps=1e6, ground=Harmonic(5.0, 1.0))
    with pytest.raises(IntegrationError) as ei:
        solve(P, np.zeros(4), np.linspace(0.0, 1.0, 11), method="dopri5", max_steps=2000)
    e = ei.value
    assert e.reason in ("max_steps", "step_underflow")
    assert 0.0 < e.t < 1.0 and _time_in(str(e)) == pytest.approx(e.t, rel=1e-5)
    assert "'radau'" in str(e)  # what to try


def test_fixed_step_budget_names_the_small_step_not_stiffness():
    # a fixed step spends (t_end - t_start) / dt = 1 s / 1e-4 s = 1e4 steps on any problem: a
    # budget of 100 runs out because the step is small; the message must not say "stiff"
    P = _coulomb("arctan", eps=100.0, ground=Harmonic(1.0, 1.0))
    with pytest.raises(IntegrationError) as ei:
        solve(P, np.zeros(4), np.linspace(0.0, 1.0, 11), method="genalpha", dt=1e-4,
              max_steps=100)  # fmt: skip
    e = ei.value
    assert e.reason == "max_steps" and 0.0 < e.t < 1.0
    assert "too small" in str(e) and "larger dt" in str(e) and "stiff" not in str(e)
    assert "the budget given is below the default" in str(e)  # a budget the caller cut first


def test_the_default_budget_spent_names_the_cause_not_the_budget(monkeypatch):
    # max_steps at its default (made 100 here): a budget the problem spends; the advice is
    # the method's, not "raise the budget you gave"
    from nsdyn.solve import integrate

    monkeypatch.setattr(integrate, "DEFAULT_MAX_STEPS", 100)
    P = _coulomb("arctan", eps=100.0, ground=Harmonic(1.0, 1.0))
    with pytest.raises(IntegrationError) as ei:
        solve(P, np.zeros(4), np.linspace(0.0, 1.0, 11), method="genalpha", dt=1e-4,
              max_steps=100)  # fmt: skip
    assert ei.value.reason == "max_steps"
    assert "below the default" not in str(ei.value) and "increase max_steps" in str(ei.value)


def test_newton_divergence_names_time_step_and_remedy():
    # the switch law's stick is set-valued: a fixed step stops at the same velocity reversal
    # whatever its size (the times converge to one instant as dt shrinks 100-fold), so the
    # remedy named is the event method, not a smaller dt (which the message led with)
    P = _coulomb("switch", ground=Harmonic(5.0, 1.0))
    ts = []
    for dt in (0.05, 0.005, 0.0005):
        with pytest.raises(IntegrationError) as ei:
            solve(P, np.zeros(4), np.linspace(0.0, 2.0, 5), method="genalpha", dt=dt)
        e = ei.value
        assert e.reason == "newton_divergence" and 0.0 < e.t < 2.0
        assert f"dt = {dt:g}" in str(e) and "a smaller dt does not help" in str(e)
        assert "use method 'event'" in str(e)
        ts.append(e.t)
    assert abs(ts[2] - ts[1]) <= 0.005 + 0.0005  # (within the coarser step of the two)


@pytest.mark.parametrize("method", ["radau", "dopri5"])
def test_non_finite_state_names_time_and_cause(method):
    tab = Table(0.0, 0.01, np.full(201, 1.0))  # (Table refuses NaN samples: written after)
    tab.a_hor[100:] = np.nan  # the record turns NaN at t = 1 s
    P = _coulomb("arctan", eps=100.0, ground=tab)
    with pytest.raises(IntegrationError) as ei:
        solve(P, np.zeros(4), np.linspace(0, 2, 21), method=method)
    e = ei.value
    assert 0.9 <= e.t <= 1.0 and "NaN" in str(e)


def test_uplift_names_contact_time_and_option():
    # rigid superstructure on two contacts, high friction, strong sine: it tips about one edge
    s = build_system(demo_frame(), Isolation(mu=0.8, eps=1000.0), fidelity="rigid")
    x0, _ = s.static_equilibrium()
    with pytest.raises(UpliftError) as ei:
        solve(s.params(Harmonic(6.0, 1.0)), x0, np.linspace(0.0, 1.0, 101))
    e = ei.value
    assert 0.0 < e.t < 0.5 and "contact" in str(e)
    assert _time_in(str(e)) == pytest.approx(e.t, rel=1e-4)
    assert "warn" in str(e)  # the option that continues through uplift


def test_shooting_non_convergence_is_flagged_with_residual():
    from nsdyn import periodic as pr

    s = build_system(demo_frame(), Isolation(mu=0.05, eps=50.0), fidelity="rigid")
    prob = pr.frame_problem(s, 2.0)
    res = pr.shoot(prob, 0.5, max_iter=1, tol=1e-14)
    assert not res.converged
    assert res.f == 0.5  # the frequency it is reported for
    assert "no convergence in 1 Newton iterations" in res.message and "residual" in res.message


def test_zeno_accumulation_comes_to_rest_at_a_reported_time():
    from nsdyn.models.rocking.block import RockingBlock, simulate_rocking

    blk = RockingBlock(width=0.4, height=2.0, r=0.8, linear=True)
    res = simulate_rocking(blk, t_end=60.0, theta0=0.5 * blk.alpha, dt_out=0.01)
    # impacts accumulate (period ratio r per impact): a finite rest time, a finite count
    assert res.outcome == "rest" and math.isfinite(res.t_rest) and 0 < res.t_rest < 60.0
    assert 3 <= res.n_impacts < 200
    assert np.all(res.theta[res.t > res.t_rest + 0.01] == 0.0)


def test_overturning_is_reported_with_its_time():
    # Housner (1963), linearised block, rectangular pulse of duration t1: overturns iff
    # a / (g alpha) >= 1 / (1 - exp(-p t1)); 2 % above that threshold it must overturn
    from nsdyn.ground.pulses import Pulse
    from nsdyn.models.rocking.block import RockingBlock, simulate_rocking

    blk = RockingBlock(width=0.4, height=2.0, linear=True)
    t1 = 0.8 / blk.p
    a_c = blk.g * blk.alpha / (1.0 - math.exp(-blk.p * t1))
    pulse = Pulse("rect", -1.02 * a_c, math.pi / t1, 1, 0.0, 0.0)
    res = simulate_rocking(blk, pulse, t_end=15.0)
    assert res.overturned and math.isfinite(res.t_overturn) and 0 < res.t_overturn < 15.0
    assert res.outcome == "overturned"


def test_cylinder_step_budget_names_time_and_reason():
    from nsdyn.models.cylinder import CylinderParams
    from nsdyn.models.cylinder.simulate import SimulationError, simulate

    P = CylinderParams()
    with pytest.raises(SimulationError) as ei:
        simulate(P.with_(k=1e14, c=0.0), np.full((3, 3), 50.0), 0.5, max_steps=2000)
    assert re.search(r"at t = .* s: step budget", str(ei.value))


N_FAILURES = 9  # rows above that provoke a failure (non-finite counted once)


# ---- library: bad arguments (one ValueError naming the argument and the expected form) and
# verdicts that must not come from the discretisation or the search's resolution ----------
def _switch_oscillator():
    from nsdyn.models.isolated.builders import system_from_matrices

    iso = Isolation(k_lam=0.0, c=0.0, mu=0.1, law="switch")
    return system_from_matrices([[1.0]], [[0.1]], [[(2 * np.pi) ** 2]], iso_dofs=[0],
                                influence=[1.0], isolation=iso, weight=iso.g,
                                levels=[[0]])  # fmt: skip


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: Harmonic(1.0, -0.1), r"^Harmonic\.f_hor: expected a positive frequency \[Hz\]"),
        (lambda: Harmonic(1.0, 0.0), r"^Harmonic\.f_hor: expected a positive frequency"),
        (lambda: Harmonic(1.0, math.nan), r"^Harmonic\.f_hor: expected a finite number"),
        (lambda: Isolation(mu=-0.1), r"^isolation\.mu: expected a finite non-negative number"),
        (lambda: Isolation(eps=-1.0), r"^isolation\.eps: expected a finite positive number"),
        (lambda: Isolation(eps=[1.0, 2.0]), r"^isolation\.eps: expected one \(for every "),
        # a negative value of a number that must be positive is not asked for "non-negative"
        # (zero is refused too: the law needs a positive scale, gravity a positive value)
        (lambda: Isolation(g=-9.81), r"^isolation\.g: expected a finite positive number"),
        (lambda: Isolation(law="switch", eta=-1e-4), r"^isolation\.eta: expected a finite pos"),
    ],
    ids=["harmonic-f-negative", "harmonic-f-zero", "harmonic-f-nan", "mu-negative",
         "eps-negative", "eps-a-list", "g-negative", "eta-negative"],
)  # fmt: skip
def test_bad_excitation_or_isolator_value_is_refused_where_it_is_built(call, message):
    with pytest.raises(ValueError, match=message):
        call()


@pytest.mark.parametrize(
    "options, message",
    [
        ({"fmin": -0.5, "fmax": 2.0}, r"^fmin: expected a forcing frequency in"),
        ({"fmin": 2.0, "fmax": 1.0}, r"^fmax: expected a frequency above fmin = 2 Hz, got 1"),
        ({"fmin": 1.0, "fmax": 2.0, "points": 0}, r"^points: expected an integer from 1 to 10000"),
    ],
    ids=["fmin-negative", "fmin-above-fmax", "no-points"],
)
def test_switch_response_bad_range_is_refused_before_any_orbit(options, message):
    from nsdyn.periodic import switch_response

    with pytest.raises(ValueError, match=message):
        switch_response(_switch_oscillator(), 1.0, **options)


def test_shooting_at_a_negative_frequency_is_refused_not_converged():
    # it used to return converged=True after 0 iterations with a multiplier of 3.8e54
    from nsdyn.periodic import shoot_switch, switch_problem

    with pytest.raises(ValueError, match=r"^f: expected a forcing frequency in"):
        shoot_switch(switch_problem(_switch_oscillator(), 1.0), -0.1)


def test_growth_of_the_discrete_map_is_checked_before_unstable_is_reported():
    # a dissipative isolator (c > 0, arctan friction) has every exact multiplier inside the
    # unit circle; the SDIRK3 map gives |rho| ~ 2 at 1.83 Hz, A = 8 m/s^2 (not AN-stable): the
    # point must be stable, with a note naming the scheme's growth and the check
    from nsdyn import periodic as pr
    from nsdyn.models.isolated.builders import system_from_matrices

    iso = Isolation(k_lam=0.0, c=0.0, mu=0.3, law="arctan", eps=7500.0)
    osc = system_from_matrices([[1.0]], [[0.5]], [[(2 * np.pi) ** 2]], iso_dofs=[0],
                               influence=[1.0], isolation=iso, weight=iso.g,
                               levels=[[0]])  # fmt: skip
    c = pr.continue_sequential(pr.frame_problem(osc, 8.0), [1.83],
                               disc=pr.Discretisation(method="sdirk3"))  # fmt: skip
    (p,) = c.points
    assert p.stable is True and p.max_multiplier < 1.0
    assert "is the scheme's" in p.note and "backward Euler" in p.note


def test_spectrum_nan_says_not_found_up_to_a_max():
    from concurrent.futures import ThreadPoolExecutor

    from nsdyn.models.rocking import RockingBlock
    from nsdyn.models.rocking.spectra import overturning_spectrum

    with ThreadPoolExecutor(1) as ex:
        blk = RockingBlock(width=0.3, height=1.2)
        sp = overturning_spectrum(blk, [1.0], executor=ex, a_max=1.05)
    assert math.isnan(sp.a_min_ratio[0]) and sp.status == ["no overturning up to a_max"]


def test_a_failure_under_an_atol_far_below_the_states_says_so():
    # the Coulomb oscillator's event run (examples/scenes/isolated-coulomb-force.toml, rtol
    # 1e-8) under atol 1e-30 stopped as "chattering stick-slip or Zeno behaviour", advising
    # tighter tolerances, on a response with a stick fraction of 0.003; at the scene's 1e-10
    # it runs. The failure now names the atol as a cause to rule out first
    from pathlib import Path

    from nsdyn.models.isolated.scene import build_scene, load_scene
    from nsdyn.solve.integrate import ATOL_STALL
    from nsdyn.solve.transient import simulate

    scene = Path(__file__).resolve().parents[2] / "examples/scenes/isolated-coulomb-force.toml"
    system, force = build_scene(load_scene(scene))
    kw = dict(method="event", rtol=1e-8, t_end=10.0, dt_out=0.01)
    for atol in (1e-10, ATOL_STALL):  # (the scene's, and the floor the message names)
        ok = simulate(system, force, atol=atol, **kw)
        assert 0.0 < ok.summary()["stick_fraction"] < 0.01
    with pytest.raises(IntegrationError, match=r"atol = 1e-30 is far below the states' size: .*"
                                               r"retry with a larger atol"):  # fmt: skip
        simulate(system, force, atol=1e-30, **kw)


def test_a_stalled_unilateral_run_under_a_huge_baumgarte_gain_names_it_first():
    # the uplift-pocket scene with isolation.alpha = 1e8 (its stabilisation alpha^2 R q equals
    # gravity at a gap of 1e-15 m) stopped at its first lift-off with "lower eps, or use
    # method 'event'", advice on a law it does not have; the gain is named first now
    from pathlib import Path

    from nsdyn.models.isolated.scene import build_scene, load_scene
    from nsdyn.solve.transient import simulate

    scene = Path(__file__).resolve().parents[2] / "examples/scenes/isolated-uplift-pocket.toml"
    cfg = load_scene(scene)
    cfg["isolation"]["alpha"] = 1e8
    system, motion = build_scene(cfg)
    with pytest.raises(IntegrationError, match=r"^step size fell below .*: the contacts' "
                                               r"Baumgarte gain alpha = 1e\+08 1/s"):  # fmt: skip
        simulate(system, motion, method="radau", t_end=13.0, contact="unilateral")
