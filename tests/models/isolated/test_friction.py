"""Friction laws: they never generate energy, and stick means one thing everywhere.

Sources: the laws of seed 004 (eq 7 arctan, eqs 4–6 switch model); dissipativity of Coulomb
friction (the friction force opposes the sliding velocity, so its power τ·v is never negative).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from nsdyn import Harmonic
from nsdyn.models.isolated.defaults import EPS, ETA
from nsdyn.models.isolated.friction import (
    STICK_UTILISATION,
    arctan_direction,
    stick_velocity,
    sticks,
)

finite_v = st.floats(-10.0, 10.0, allow_nan=False)


@given(v=finite_v, eps=st.floats(1.0, 1e6))
def test_arctan_direction_opposes_nothing_and_stays_below_one(v, eps):
    s = float(arctan_direction(v, eps))
    assert s * v >= 0.0  # friction power μλ s v ≥ 0 for λ ≥ 0
    assert abs(s) < 1.0 or (abs(s) == pytest.approx(1.0) and abs(eps * v) > 1e15)


def test_stick_velocity_is_the_utilisation_threshold_of_the_arctan_law():
    # |s(v*)| = STICK_UTILISATION exactly at the returned velocity (inverse of eq 7)
    v = stick_velocity("arctan", EPS)
    assert float(arctan_direction(v, EPS)) == pytest.approx(STICK_UTILISATION, rel=1e-12)
    assert stick_velocity("switch", EPS, ETA) == ETA


def test_a_stick_mode_is_stick_whatever_the_velocity_under_the_switch_model():
    v = np.array([0.0, 1.0, 1.0])
    modes = np.array([1, 0, 1])
    assert sticks(v, "switch", modes=modes).tolist() == [True, True, False]
    # the arctan law has no stick mode: only the velocity decides
    assert sticks(v, "arctan", modes=modes).tolist() == [True, False, False]


@pytest.fixture(scope="module")
def rigid_system():
    from nsdyn import Isolation, build_system, load_frame

    return build_system(load_frame("office-11"), Isolation(law="arctan"), fidelity="rigid")


@settings(max_examples=40, deadline=None)
@given(
    v=st.tuples(st.floats(-1.0, 1.0), st.floats(-1.0, 1.0)),
    th=st.floats(-1e-3, 1e-3),
    t=st.floats(0.0, 10.0),
)
def test_kernel_friction_forces_dissipate(rigid_system, v, th, t):
    # at any state of the rigid model sliding on its isolators, each isolator's friction
    # force τ_i = μ λ_i s(v_i) has power τ_i v_i ≥ 0 while it is pressed (λ_i > 0)
    sys = rigid_system
    x0, _ = sys.static_equilibrium()
    x = x0.copy()
    n = sys.n
    vel = np.linalg.lstsq(sys.D, np.array(v), rcond=None)[0]
    x[n:] += vel
    x[:n] += sys.Q @ (sys.Q.T @ np.r_[0.0, 0.0, th][:n]) if n == 3 else 0.0
    ev = sys.evaluate(t, x, Harmonic(1.0, 0.5))
    vi = sys.D @ x[n:]
    for tau_i, v_i, lam_i in zip(ev["tau"], vi, ev["lam"], strict=True):
        if lam_i > 0 and math.isfinite(tau_i):
            assert tau_i * v_i >= -1e-12 * abs(tau_i) * max(abs(v_i), 1e-30)


@pytest.mark.parametrize("method", ["radau", "event"])
def test_a_stick_band_wider_than_the_slips_is_said_by_the_library_run(method):
    # eta = 1 m/s: the switch law's band takes every slip of a shear building under 1.5 m/s²
    # for stick (the stick fraction read 1.0 while the isolator slid); nsdyn run noted it from
    # the scene, a Python run said nothing. The event method's stick does not depend on eta:
    # only its outputs' stick fraction does, and it says that instead
    import warnings

    from nsdyn._checks import NotedWarning
    from nsdyn.models.isolated.builders import shear_building
    from nsdyn.models.isolated.system import Isolation
    from nsdyn.solve.transient import simulate

    s = shear_building([1e5], [], 0.0, isolation=Isolation(k_lam=0.0, c=0.0, mu=0.05,
                                                           law="switch", eta=1.0))  # fmt: skip
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        simulate(s, Harmonic(1.5, 1.0), n_periods=1, method=method)
    notes = [str(w.message) for w in said if issubclass(w.category, NotedWarning)]
    words = "creeps at up to 1 m/s" if method == "radau" else "stick phases do not depend on it"
    assert len(notes) == 1 and notes[0].startswith("isolation.eta = 1 m/s: ") and words in notes[0]
