"""Switch-model shooting against long event-driven integration of the same model.

A base-excited viscous + Coulomb oscillator ``m x'' + c x' + k x + mu m g sign(x') =
-m A sin(2 pi f t)`` is integrated from rest by the event-driven switch integrator
(``nsdyn.simulate(..., method="event")``, modes held between located stick/slip switches,
independent of the shooting code) until the transient has decayed; its state at the start of
the last period equals the shooting solution to 1e-5 (relative to the orbit's amplitude), on
pure-slip and on stick-slip orbits.
"""

import math

import numpy as np
import pytest

import nsdyn
from nsdyn.ground.excitation import Harmonic
from nsdyn.models.isolated.builders import system_from_matrices
from nsdyn.models.isolated.system import Isolation
from nsdyn.periodic.switch import shoot_switch, switch_problem

W1 = 2.0 * math.pi  # rad/s
ZETA = 0.1
PERIODS = 40  # transient e^(-zeta w1 t) < 1e-8 after 40 periods at f >= 0.7 Hz (with friction)


def oscillator(mu):
    iso = Isolation(k_lam=0.0, c=0.0, mu=mu, law="switch")
    return system_from_matrices(
        [[1.0]],
        [[2 * ZETA * W1]],
        [[W1**2]],
        iso_dofs=[0],
        influence=[1.0],
        isolation=iso,
        weight=iso.g,
        levels=[[0]],
    )


@pytest.mark.parametrize(
    "mu, A, f, stick",
    [
        pytest.param(0.05, 3.0, 0.9, False, marks=pytest.mark.slow),  # ~15 s: many events
        (0.2, 2.5, 0.7, True),
        (0.1, 2.0, 1.6, False),
    ],
)
def test_shooting_matches_event_integration(mu, A, f, stick):
    sysm = oscillator(mu)
    pb = switch_problem(sysm, A)
    res = shoot_switch(pb, f, tol=1e-11)
    assert res.converged, res.message
    assert any(e[2] == 0 for e in res.events) == stick
    T = 1.0 / f
    t = np.linspace(0.0, PERIODS * T, PERIODS * 50 + 1)
    run = nsdyn.simulate(
        sysm, Harmonic(A, f), method="event", t_eval=t, rtol=1e-11, atol=(1e-13, 1e-13)
    )
    x_end = pb.to_minimal(run.x[-1])
    x_prev = pb.to_minimal(run.x[-51])
    amp = max(np.abs(res.X[:, 0]).max(), 1e-12)
    vamp = max(np.abs(res.X[:, 1]).max(), 1e-12)
    # the integration has settled (period-to-period change far below the tolerance) ...
    assert abs(x_end[0] - x_prev[0]) < 1e-7 * amp
    # ... onto the shooting orbit
    assert abs(x_end[0] - res.x0[0]) <= 1e-5 * amp
    assert abs(x_end[1] - res.x0[1]) <= 1e-5 * vamp
