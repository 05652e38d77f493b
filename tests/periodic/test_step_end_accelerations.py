"""Peak accelerations of an orbit whose fixed step does not resolve the friction law's switch.

A sharp arctan law (eps = 1e6 s/m: the friction turns over within 1e-6 m/s of slip) under the
default SDIRK2 discretisation (200 steps per period): every step end lands within 1/eps of zero
slip but off the law's slow manifold, so the acceleration computed from the state at a step end
(the right-hand side) reads tens of m/s² where the velocity itself changes by a few m/s² per
step. The orbit (slip, drifts) is the orbit; only those step-end accelerations are the
scheme's. ``orbit_quantities`` then reports the peaks of the velocity change over each step and
keeps the step ends' peak in ``acc_step_ends``, with a note.

Reference: the same orbit under eps = 1e5, whose step ends are resolved (no note). As eps grows
the arctan orbit tends to the Coulomb orbit with slip velocities differing by O(1/eps), so the
two laws' peak accelerations agree to the discretisation's error on accelerations: under 16x
the steps the office frame's peaks move by <= 1.3 % (0.1 Hz, A = 2 m/s²), so 3 % is allowed.
"""

import copy

import pytest

from nsdyn.models.isolated.scene import DEFAULT_SCENE, build_scene
from nsdyn.periodic import frame_problem
from nsdyn.periodic.problem import ACC_UNRESOLVED
from nsdyn.periodic.sweeps import steady_state_sweep

F = 0.3  # Hz, a stick-slip orbit of the office frame at A = 2 m/s²
A = 2.0


def steady_orbit(eps: float):
    cfg = copy.deepcopy(DEFAULT_SCENE)
    cfg["isolation"]["eps"] = eps
    system, _ = build_scene(cfg)
    pb = frame_problem(system, A)
    sw = steady_state_sweep(pb, F, monodromy=False)
    assert sw.steady, sw.message
    q = pb.orbit_quantities(F, sw.X)
    return q, pb.validity_note(q)


@pytest.fixture(scope="module")
def resolved():
    return steady_orbit(1e5)


def test_a_resolved_switch_reports_its_step_ends(resolved):
    q, note = resolved
    assert "acc_step_ends" not in q and "acc_resolved" not in q
    assert "step ends" not in note


def test_an_unresolved_switch_reports_the_velocity_change(resolved):
    ref, _ = resolved
    q, note = steady_orbit(1e6)
    assert q["acc_resolved"] is False
    assert q["acc_step_ends"] > ACC_UNRESOLVED * q["acc"]
    assert q["acc"] == pytest.approx(ref["acc"], rel=0.03)
    assert q["acc_floors"] == pytest.approx(ref["acc_floors"], rel=0.03)
    # the orbit itself is the resolved law's: slip and drift to the same tolerance
    assert q["x_iso"] == pytest.approx(ref["x_iso"], rel=0.03)
    assert q["idr"] == pytest.approx(ref["idr"], rel=0.03)
    assert f"the step ends give {q['acc_step_ends']:.3g} m/s²" in note


def test_an_uplift_beside_an_unresolved_switch_is_not_blamed_on_the_structure_alone():
    """The normal forces ride on the same right-hand side as the step ends' accelerations:
    where those are the unresolved switch's, an uplift there may be the step's as well."""
    system, _ = build_scene(copy.deepcopy(DEFAULT_SCENE))
    pb = frame_problem(system, A)
    lifted = {"uplift": True, "min_normal_force": -1e5}
    assert "or the step's" not in pb.validity_note(lifted)
    both = {**lifted, "acc_resolved": False, "acc_step_ends": 41.0, "acc": 3.7}
    assert "or the step's: its friction switch is unresolved" in pb.validity_note(both)
