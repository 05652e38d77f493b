"""Switch-model shooting on the office frame (CB-5, two isolators on a stiff base).

The minimal coordinates mix soft and stiff directions (``|A_k|_1`` ~1e10 s^-1 against a
spectral radius ~8e3 s^-1); the kernel works in a balanced state and locates every
stick/slip switch as a root of the exact flow. Checked here: (i) the monodromy (flows times
saltation matrices, Leine & Nijmeijer 2004, ch. 3) equals central differences of the period
map on a stick-slip orbit with eight switches; (ii) Newton on that exact map converges to a
residual far below the shooting tolerance (quadratic convergence, not a round-off stall);
(iii) the orbit is the steady state of the event-driven switch integrator
(``nsdyn.simulate(method="event")``, independent code): started on the orbit it stays there
and has the same peak floor accelerations above the isolation level to 1e-3.
"""

import numpy as np
import pytest

import nsdyn
from nsdyn.ground.excitation import Harmonic
from nsdyn.models.isolated.metrics import response
from nsdyn.models.isolated.scene import build_scene, load_scene
from nsdyn.periodic import warm_start
from nsdyn.periodic.switch import shoot_switch, switch_problem

A_BASE = 0.5  # m/s^2 (seed Fig. 11)
F = 0.463  # Hz: stick-slip orbit, both isolators stick twice per period


@pytest.fixture(scope="module")
def orbit():
    frame, _ = build_scene(load_scene(None))
    system = frame.with_isolation(law="switch")
    pb = switch_problem(system, A_BASE)
    res = shoot_switch(pb, F, warm_start(pb, F, None, None), tol=1e-9)
    return system, pb, res


def test_frame_orbit_converges_on_the_exact_map(orbit):
    _, _, res = orbit
    assert res.converged and "stalled" not in res.message, res.message
    assert res.residual <= 1e-9
    assert sum(e[2] == 0 for e in res.events) == 4  # each isolator sticks twice


def test_frame_monodromy_against_finite_differences(orbit):
    _, pb, res = orbit
    x = res.x0
    N = res.n_steps
    pm = pb.period_map(x, F, n_steps=N)
    dX = np.abs(res.X - pb.x_ref)
    m = pb.m
    block = np.repeat([dX[:, :m].max(), dX[:, m:].max()], m)  # as shooting scales
    amp = np.maximum(dX.max(axis=0), 1e-4 * block)  # stiff coordinates move little
    fd = np.empty_like(pm.monodromy)
    for j in range(pb.dim):
        e = np.zeros(pb.dim)
        e[j] = 1e-7 * amp[j]
        xp = pb.period_map(x + e, F, n_steps=N, sens=False).xT
        xm = pb.period_map(x - e, F, n_steps=N, sens=False).xT
        fd[:, j] = (xp - xm) / (2 * e[j])
    # compare in orbit-scaled coordinates (entries of very different units otherwise)
    S = amp[None, :] / amp[:, None]
    err = np.abs((pm.monodromy - fd) * S).max()
    # central differences of a stiff map with steps 1e-7 carry ~1e-4 round-off; an event
    # placed off its root (or an inaccurate exponential) gives O(1) disagreement
    assert err <= 1e-3 * np.abs(fd * S).max()


@pytest.mark.slow
def test_frame_orbit_is_the_event_driven_steady_state(orbit):
    system, pb, res = orbit
    T = 1.0 / F
    n_out = 4000  # samples per period
    t = np.linspace(0.0, 2 * T, 2 * n_out + 1)
    run = nsdyn.simulate(
        system,
        Harmonic(A_BASE, F),
        method="event",
        t_eval=t,
        x0=pb.to_full(res.x0[None])[0],
        rtol=1e-9,
    )
    xi = run.x[:, : system.n] @ system.D.T  # isolator slips
    xi_orbit = pb.to_full(res.x0[None])[0, : system.n] @ system.D.T
    x_iso = pb.orbit_quantities(F, res.X)["x_iso"]
    assert np.abs(xi[n_out] - xi_orbit).max() <= 1e-4 * x_iso  # back after one period
    last = slice(n_out, None)
    P = system.params(Harmonic(A_BASE, F), law="switch")
    ref = response(system, t[last], run.x[last], P).floor_acc_by_level
    pm = pb.period_map(res.x0, F, n_steps=n_out, sens=False, store=True)
    q = pb.orbit_quantities(F, pm.X)
    assert abs(q["acc_floors"] / ref[1:].max() - 1) <= 1e-3
    # x_iso from res.n_steps samples against 4000: both are extrema on the dense output of
    # the same exact flow; the coarse one can only err across a stick (an acceleration jump
    # of at most 2 mu g, where the dense output's polynomial errs by at most jump * h^2 / 8,
    # h its sample spacing; extrema.py's module text)
    iso = system.isolation
    h = T / res.n_steps
    assert abs(q["x_iso"] - x_iso) <= 2 * iso.mu * iso.g * h * h / 8


def test_line_search_trials_with_sensitivities_find_the_same_orbit(orbit, monkeypatch):
    """The switch map declares ``cheap_sensitivities``: a shortened line-search trial takes
    its monodromy at once instead of being evaluated a second time when accepted. The map's
    end state does not depend on whether sensitivities are formed, so Newton takes the same
    steps to the bit; only the repeated evaluations go (from rest at 0.3 Hz the search halves
    at three iterations)."""
    _, pb, _ = orbit
    calls = []
    real = type(pb).period_map

    def counted(self, *args, **kw):
        calls.append(kw.get("sens", True))
        return real(self, *args, **kw)

    monkeypatch.setattr(type(pb), "period_map", counted)
    runs = {}
    for cheap in (True, False):
        monkeypatch.setattr(type(pb), "cheap_sensitivities", cheap)
        calls.clear()
        res = shoot_switch(pb, 0.3)
        runs[cheap] = (res, list(calls))
    (fast, fast_calls), (slow, slow_calls) = runs[True], runs[False]
    assert fast.converged and slow.converged
    assert np.array_equal(fast.x0, slow.x0) and fast.iterations == slow.iterations
    assert fast_calls.count(False) == 1  # shoot_switch's closing map, outside Newton
    assert slow_calls.count(False) > 1 and len(fast_calls) < len(slow_calls)


def test_a_slip_against_its_own_direction_is_not_an_orbit(orbit):
    """Friction opposes the slip: between switches the map is exact and a slip velocity
    reaching zero is a switch, so at every sample of an orbit a slipping isolator moves in
    its slip's direction. The shot 0.463 Hz orbit (the event-driven steady state, above) is
    consistent; the same samples with one slipping isolator's mode reversed at one sample
    (a zero crossing gone unseen between two samples) are not."""
    from nsdyn.periodic.switch_tables import mode_sets

    _, pb, res = orbit
    pm = pb.period_map(res.x0, F, n_steps=res.n_steps, sens=False, store=True)
    assert pb.orbit_unverified(pm) == ""
    sets = mode_sets(2)
    S = sets[pm.modes]
    k = int(np.flatnonzero(np.all(S != 0, axis=1))[len(S) // 8])  # both slipping there
    flipped = S[k] * np.array([-1, 1])
    pm.modes[k] = int(np.flatnonzero(np.all(sets == flipped, axis=1))[0])
    assert pb.orbit_unverified(pm).startswith(
        f"isolator 0 slips against its own friction at t = {k * (1 / F) / res.n_steps:.4g} s (v = "
    )


@pytest.mark.slow
@pytest.mark.parametrize("f_near", [1.157, 1.356])
def test_sweep_points_at_the_stick_transition_are_the_event_driven_steady_state(f_near):
    """On 30 points from 0.3 to 3 Hz at 0.5 m/s², shooting converged at 1.16 and 1.36 Hz on
    orbits of the sampled map alone (72 and 462 m/s² at the isolation level, an isolator
    ringing against the stiff base; the stuck neighbours read about 2): started there, the
    event-driven switch integrator (independent code) fell to the stuck orbit. The points
    the sweep now reports are its steady state: the isolation level's and the floors' peak
    accelerations over the sixth period from the point's start agree to 2 %: the stuck
    orbit's peaks are sampled 200 times a period against 2000 (a harmonic's peak read N times a
    period errs by at most 1 - cos(pi/N), 1.2e-4; the frame's 3 Hz mode at 1.36 Hz forcing,
    ~90 samples its period, 6e-4), and the event run's rtol is 1e-9; the orbits refused read
    2.5 and 240 times more."""
    from nsdyn.periodic.switch import switch_response

    frame, _ = build_scene(load_scene(None))
    system = frame.with_isolation(law="switch")
    curve = switch_response(system, A_BASE, fmin=0.3, fmax=3.0, points=30)
    (p,) = [p for p in curve.points if abs(p.f - f_near) < 5e-3]
    pb = switch_problem(system, A_BASE)
    T, n_out = 1.0 / p.f, 2000
    t = np.linspace(0.0, 6 * T, 6 * n_out + 1)
    run = nsdyn.simulate(system, Harmonic(A_BASE, p.f), method="event", t_eval=t,
                         x0=pb.to_full(p.x0[None])[0], rtol=1e-9)  # fmt: skip
    P = system.params(Harmonic(A_BASE, p.f), law="switch")
    acc = response(system, t[5 * n_out :], run.x[5 * n_out :], P).floor_acc_by_level
    assert abs(p.quantities["acc"] / acc.max() - 1) <= 0.02
    assert abs(p.quantities["acc_floors"] / acc[1:].max() - 1) <= 0.02
