"""Peak accelerations of an orbit whose fixed steps do not resolve the friction law's switch.

An arctan law turns the friction over within 1/eps of zero slip, far inside one fixed step
(SDIRK2, 200+ steps per period). A step end that lands in that turn reads, from the state, an
acceleration the motion does not have. ``orbit_quantities`` holds each such step end to the
velocity changes of the two steps beside it (:mod:`nsdyn.periodic.step_ends`) and keeps the
raw peak in ``acc_step_ends``, with a note.

Checked against independent references: the same orbit with 8x the steps (unspoilt there),
and the orbit of a law 10x softer (eps 1e5, resolved: as eps grows the arctan orbit tends to
the Coulomb orbit with slip velocities differing by O(1/eps)). Tolerances: the default
discretisation's error on peak accelerations, 1.6 % at most against 16x the steps on the
office frame's stick-slip orbits at A = 2 m/s² (0.08-0.36 Hz), so 3 %.
"""

import copy

import pytest

from nsdyn.models.isolated.scene import DEFAULT_SCENE, build_scene
from nsdyn.periodic import frame_problem
from nsdyn.periodic.discretisation import Discretisation, refined
from nsdyn.periodic.shooting import shoot
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
    assert q["acc_step_ends"] > 5 * ref["acc"]  # the spoilt step ends: 41 m/s² against 3.75
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
    both = {**lifted, "acc_resolved": False, "acc_step_ends": 41.0, "acc": 3.7, "acc_held": 30}
    assert "or the step's: its friction switch is unresolved" in pb.validity_note(both)


def test_a_spoilt_step_end_of_the_default_law_is_held_to_the_converged_peak():
    """The default law (eps = 7500) at A = 2 m/s², 0.355 Hz, 200 steps per period: step ends
    in the friction's turn read 3.86 m/s², 9 % above the peak of the orbit with 8x the steps
    (no step end spoilt there, 3.54 m/s²); held, they give the converged peak."""
    system, _ = build_scene(copy.deepcopy(DEFAULT_SCENE))
    pb = frame_problem(system, A)
    f = 0.355
    coarse = shoot(pb, f, steady_state_sweep(pb, f, monodromy=False).x0)
    fine = shoot(pb, f, coarse.x0, disc=refined(Discretisation(), 8))
    assert coarse.converged and fine.converged
    q, ref = pb.orbit_quantities(f, coarse.X), pb.orbit_quantities(f, fine.X)
    assert "acc_resolved" not in ref
    assert q["acc_resolved"] is False and q["acc_step_ends"] > 1.05 * ref["acc"]
    assert q["acc"] == pytest.approx(ref["acc"], rel=0.03)
