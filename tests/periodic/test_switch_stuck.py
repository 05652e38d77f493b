"""Switch-model orbits whose isolators stick all period: a family of orbits, one per offset.

While an isolator sticks its displacement is frozen, so on an orbit where it sticks all period
any shift of that displacement (within the friction cone) gives another periodic orbit: the
monodromy has the multiplier 1 exactly and ``Phi - I`` is singular. Shooting holds the frozen
displacements at the guess and takes the least-squares step on the rest.

Checks: (i) a two-mass oscillator whose isolator sticks all period: the offset is held and the upper
mass's steady state is the linear FRF; (ii) the office
frame (CB-5, A = 0.5 m/s^2) at 1.0, 2.0 and 2.95 Hz: one Newton step to the round-off of the
map (the period map is affine on the stuck orbit), and against the event-driven switch
integrator (``nsdyn.simulate(method="event")``, independent code): from rest its isolators
come to rest on a member of the stuck family (shooting from its end state converges to a
stuck orbit), and started on the orbit it is back after one period to 1e-5 of the orbit's
amplitudes (the integrator runs at rtol 1e-9).
"""

import math

import numpy as np
import pytest

import nsdyn
from nsdyn.ground.excitation import Harmonic
from nsdyn.models.isolated.builders import system_from_matrices
from nsdyn.models.isolated.scene import build_scene, load_scene
from nsdyn.models.isolated.system import Isolation
from nsdyn.periodic import warm_start
from nsdyn.periodic.shooting import orbit_amplitudes
from nsdyn.periodic.switch import FROZEN_T_TOL, V_ZERO, shoot_switch, switch_problem

A_BASE = 0.5  # m/s^2
STUCK_FREQS = (1.0, 2.0, 2.95)  # Hz: the base sticks all period after the start


def test_stuck_two_mass_oscillator_holds_its_offset():
    """Two masses on a friction isolator (base mass m1 on the isolator, m2 on a spring above),
    base excitation A sin(w t) with (m1 + m2) A well below mu (m1 + m2) g: the isolator sticks
    all period at any offset x1 = delta in the cone. From a guess with the base at delta and
    the upper mass off its orbit, shooting keeps x1 = delta and v1 = 0 and solves the upper
    mass's linear steady state: x2 - x1 = Re(H e^{i w t}) with H the FRF of the fixed-base
    oscillator (k2, c2) to the ground acceleration (relative coordinates), to 1e-9; the
    monodromy keeps the multiplier 1 of the family."""
    m1, m2, k2, c2, mu, A, f = 1.0, 1.0, (2 * math.pi) ** 2, 0.2, 0.2, 0.5, 0.8
    iso = Isolation(k_lam=0.0, c=0.0, mu=mu, law="switch")
    sysm = system_from_matrices(
        [[m1, 0.0], [0.0, m2]], [[c2, -c2], [-c2, c2]], [[k2, -k2], [-k2, k2]], iso_dofs=[0],
        influence=[1.0, 1.0], isolation=iso, weight=(m1 + m2) * iso.g, levels=[[0], [1]],
    )  # fmt: skip
    pb = switch_problem(sysm, A)
    delta = 0.01
    guess = np.zeros(pb.dim)
    full = np.array([delta, delta + 0.02, 0.0, 0.1])  # [x1, x2, v1, v2]
    guess[:] = pb.to_minimal(full[None])[0]
    res = shoot_switch(pb, f, guess, tol=1e-12)
    assert res.converged, res.message
    x1, x2, v1, v2 = pb.to_full(res.x0[None])[0]
    assert abs(x1 - delta) <= 1e-12 and abs(v1) <= 1e-12
    w = 2 * math.pi * f
    H = -m2 / (k2 - m2 * w * w + 1j * c2 * w)  # relative response to A e^{i w t}
    # sin(w t) = Re(-i e^{i w t}): y(t) = Re(-i A H e^{i w t})
    y0, yd0 = (-1j * A * H).real, (-1j * A * H * 1j * w).real
    assert abs((x2 - x1) - y0) <= 1e-9 * abs(A * H)
    assert abs(v2 - yd0) <= 1e-9 * abs(A * H) * w
    assert np.abs(res.multipliers).max() == pytest.approx(1.0, abs=1e-9)


@pytest.fixture(scope="module")
def frame_problem():
    frame, _ = build_scene(load_scene(None))
    system = frame.with_isolation(law="switch")
    return system, switch_problem(system, A_BASE)


@pytest.fixture(scope="module")
def stuck_orbits(frame_problem):
    _, pb = frame_problem
    return {f: shoot_switch(pb, f, warm_start(pb, f, None, None)) for f in STUCK_FREQS}


@pytest.mark.parametrize("f", STUCK_FREQS)
def test_frame_stuck_orbit_converges(frame_problem, stuck_orbits, f, newton_roundoff):
    """Newton lands on the map's round-off (the map is affine where nothing switches); both
    isolators frozen, the family's two multipliers 1.

    Not a fixed count of Newton updates: the orbit starts with the isolators at rest on the
    edge of the stuck set (a 1e-6 shift of the displacements makes one slip), so whether an
    update's trial orbit is stuck at its start depends on the round-off of that update, and a
    flipped decision costs further updates. The final residual is bounded by the round-off
    of the last update of an affine map (``newton_roundoff``, tests/conftest.py)."""
    _, pb = frame_problem
    res = stuck_orbits[f]
    assert res.converged and "stalled" not in res.message, res.message
    assert res.iterations >= 1 and res.history[0] > 1e-6  # the guess is off the orbit
    bound = newton_roundoff(pb, res, warm_start(pb, f, None, None))
    assert res.residual <= bound, (res.residual, bound)
    pm = pb.period_map(res.x0, f, n_steps=res.n_steps, sens=False)
    assert list(pb.stuck_all_period(pm)) == [0, 1]
    rho = np.sort(np.abs(res.multipliers))[::-1]
    assert np.allclose(rho[:2], 1.0, atol=1e-9) and rho[2] < 1.0


@pytest.mark.slow
@pytest.mark.parametrize("f", STUCK_FREQS)
def test_frame_stuck_orbit_against_event_driven(frame_problem, stuck_orbits, f):
    """From rest the event-driven run comes to rest in the stuck family: its isolators are
    frozen over the last period, and shooting from its end state converges to an orbit on
    which both isolators stick all period. Which member is not compared: at 2.95 Hz the
    family's peak stick force meets the friction cone, and whether an isolator slips there
    once (1e-5 m) is decided by round-off (the warm start's period map and this machine's
    arithmetic pick it; see the test above). Started on the shooting orbit the run is back
    after one period, each coordinate to 1e-5 of its excursion (the integrator runs at
    rtol 1e-9)."""
    system, pb = frame_problem
    res = stuck_orbits[f]
    T = 1.0 / f
    n, m = system.n, pb.m
    x_orbit = pb.to_full(res.x0[None])[0]
    # from rest: the isolators slip (or not) in the first periods, then stay frozen
    t_eval = np.concatenate([[0.0], np.linspace(3 * T, 4 * T, 33)])
    run = nsdyn.simulate(system, Harmonic(A_BASE, f), method="event", t_eval=t_eval, rtol=1e-9)
    xi_last = run.x[1:, :n] @ system.D.T
    xi_end = xi_last[-1]
    # frozen: equal over the period to 1e-12 m (the round-off of D x is ~1e-16 of the
    # millimetre-scale state: a stuck isolator does not drift)
    assert np.all(np.abs(xi_last - xi_end) <= 1e-12 + 1e-9 * np.abs(xi_end))
    fam = shoot_switch(pb, f, pb.to_minimal(run.x[-1][None])[0])
    assert fam.converged, fam.message
    pm = pb.period_map(fam.x0, f, n_steps=fam.n_steps, sens=False)
    assert list(pb.stuck_all_period(pm)) == [0, 1]
    # started on the orbit: back after one period, each coordinate to 1e-5 of its excursion
    # (floored at 1e-4 of its block's: stiff coordinates hardly move)
    one = nsdyn.simulate(
        system, Harmonic(A_BASE, f), method="event", t_eval=np.array([0.0, T]), x0=x_orbit,
        rtol=1e-9,
    )  # fmt: skip
    back = pb.to_minimal(one.x[-1])
    dX = np.abs(res.X - pb.x_ref)
    block = np.repeat(orbit_amplitudes(pb, res.X), m)
    amp = np.maximum(dX.max(axis=0), 1e-4 * block)
    assert np.all(np.abs(back - res.x0) <= 1e-5 * amp)


def test_round_off_start_velocity_is_no_slip(frame_problem, stuck_orbits):
    """A stuck orbit whose start carries an isolator velocity a round-off above ``V_ZERO``
    (10 V_ZERO = 1e-12 m/s, as a Newton update leaves it) starts in a slip mode that sticks
    within ~1e-15 s. That slip of no duration is not an event of the orbit: the point is
    stuck all period with no events, and its peaks are those of the clean start to 1e-6
    relative (the start moves the isolators by ~V T = 5e-13 m against millimetres, and the
    accelerations by O(1e-12)) -- not the slip mode's acceleration at t = 0 (~80 m/s² on the
    base level before)."""
    system, pb = frame_problem
    f = 2.0
    res = stuck_orbits[f]
    clean = pb.orbit_quantities(f, res.X)
    DQ = system.D @ pb.Q  # isolator velocities from the minimal velocities
    dzd = np.linalg.lstsq(DQ, np.full(system.n_isolators, 10 * V_ZERO), rcond=None)[0]
    X = res.X.copy()
    X[0, pb.m :] += dzd
    assert np.all(np.abs(DQ @ X[0, pb.m :]) > V_ZERO)
    pm = pb.period_map(X[0], f, n_steps=X.shape[0] - 1, sens=False)
    assert pm.events and max(e[0] for e in pm.events) <= FROZEN_T_TOL / f  # no duration
    q = pb.orbit_quantities(f, X)
    assert q["stick_all_period"] is True and q["events"] == 0
    for key in ("idr", "acc", "acc_floors", "min_normal_force"):
        assert q[key] == pytest.approx(clean[key], rel=1e-6), key
