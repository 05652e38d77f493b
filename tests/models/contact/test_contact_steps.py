"""Moreau-Jean's step against the excitation and its own resolution, and run sizes refused
before any step (they ran for hours, allocated beyond memory, or answered wrongly).

Sources: Moreau-Jean is first order (Acary & Brogliato 2008), so halving a step that resolves
the response moves its peaks by about their error, and a step that does not moves them by more;
the event-driven solver is the reference (seed 002's method, checked against Housner's block).
"""

from __future__ import annotations

import math
import warnings

import pytest

import nsdyn
from nsdyn.models.contact.excite import BaseMotion
from nsdyn.models.contact.moreau import simulate_moreau

BODY = nsdyn.RigidBody.rectangle(0.5, 1.5, 1000.0)
LAW = nsdyn.FrictionLaw(0.45, 0.45, 0.0)


def test_a_step_that_skips_the_excitation_is_refused():
    # a sine of period 2 s needs h <= T/40; a record's step, h <= ten samples
    sine = BaseMotion.sine_acceleration(3.0, math.pi)
    with pytest.raises(ValueError, match=r"^h: a step of 0.5 s does not follow the excitation; "
                                         r"expected at most 0.05 s"):  # fmt: skip
        simulate_moreau(BODY, LAW, sine, t_end=3.0, h=0.5)
    rec = BaseMotion.from_motion(nsdyn.read_motion("synthetic-kt-20s").window(0.0, 2.0))
    with pytest.raises(ValueError, match=r"^h: a step of 0.2 s"):
        simulate_moreau(BODY, LAW, rec, t_end=2.0, h=0.2)
    with pytest.raises(ValueError, match=r"^h: 3e\+12 steps of 1e-12 s exceed 2e\+08"):
        simulate_moreau(BODY, LAW, None, t_end=3.0, h=1e-12)
    with pytest.raises(ValueError, match=r"^dt_out: 3e\+07 outputs"):  # every step: 720 MB
        simulate_moreau(BODY, LAW, None, t_end=3.0, h=1e-7)


def test_a_scene_says_when_its_moreau_step_does_not_resolve_the_response(tmp_path):
    # a 0.5 x 1.5 m prism under synthetic-kt-20s at 5 m/s² with its vertical component:
    # Moreau-Jean at h = 1e-3 s loses most of the event-driven run's rocking, and the run at
    # h/2 reads a peak tilt more than twice h's. The scene run says so (it was silent); the
    # event run needs no such check.
    from nsdyn.models.contact.scene import run_scene

    cfg = {"scene": {"kind": "contact"}, "body": {"width": 0.5, "height": 1.5, "mass": 1000.0},
           "friction": {"mu_s": 0.45, "C": 0.0},
           "motion": {"record": "synthetic-kt-20s", "pga": 5.0, "t_end": 12.0},
           "solver": {"method": "moreau", "h": 1e-3}}  # fmt: skip
    s = run_scene(cfg, source="m.toml", out_dir=tmp_path, figures=False, quiet=True)
    assert s["step_resolved"] is False and "does not resolve" in s["step_note"]
    assert s["h_half"]["max_tilt_rad"] > 2 * s["max_tilt_rad"]
    cfg["solver"] = {"method": "event"}
    ev = run_scene(cfg, source="m.toml", out_dir=tmp_path, figures=False, quiet=True)
    # the unresolved steps lose the rocking (the scheme's dissipation at h): their peaks grow
    # towards the event-driven one as h halves, and both stay below it
    assert "step_resolved" not in ev
    assert ev["max_tilt_rad"] > s["h_half"]["max_tilt_rad"] > s["max_tilt_rad"]
    # a quiet case resolves at the default step: the body stays at rest at h and h/2
    cfg["motion"]["pga"], cfg["solver"] = 0.5, {"method": "moreau", "h": 1e-3}
    quiet = run_scene(cfg, source="m.toml", out_dir=tmp_path, figures=False, quiet=True)
    assert quiet["step_resolved"] is True


def test_a_python_moreau_run_checks_its_step_when_asked_and_warns_of_unchecked_hops():
    # the scene's case above through the Python call: step_check=True repeats it at h/2, and
    # the result and an AccuracyWarning say the step does not resolve it (the call said nothing)
    gm = nsdyn.read_motion("synthetic-kt-20s").scaled_to_pga(5.0)
    with pytest.warns(nsdyn.AccuracyWarning, match=r"^the Moreau-Jean step does not resolve "
                                                   r"this response: max_tilt_rad"):  # fmt: skip
        r = simulate_moreau(BODY, LAW, BaseMotion.from_motion(gm), t_end=12.0, step_check=True)
    assert r.step_check["step_resolved"] is False and r.summary()["step_resolved"] is False
    assert r.step_check["h_half"]["max_tilt_rad"] > 2 * r.summary()["max_tilt_rad"]
    # free rocking of a 1 x 2 m block from alpha/2 that cannot slide (mu = 10): with e_n = 0.9
    # it hops (the stability map's inaccurate corner), and a run that hopped unchecked warns,
    # naming the first hop (the first impact at arccosh(2)/p = 0.513 s, Housner 1963); without
    # restitution it rocks on its corners and says nothing
    block, stuck = nsdyn.RigidBody.rectangle(1.0, 2.0, 1.0), nsdyn.FrictionLaw(10.0)
    kw = dict(t_end=2.0, h=1e-3, theta0_over_alpha=0.5, dt_out=0.01)
    with pytest.warns(nsdyn.AccuracyWarning, match=r"^Moreau-Jean: the body hopped \d+ times "
                                                   r"\(first at t = 0\.5\d* s\)"):  # fmt: skip
        hops = simulate_moreau(block, stuck, e_n=0.9, **kw)
    assert hops.n_hops > 0 and hops.step_check is None
    with warnings.catch_warnings():
        warnings.simplefilter("error", nsdyn.AccuracyWarning)
        rock = simulate_moreau(block, stuck, **kw)
    assert rock.n_hops == 0
    # the check at h/2 compares the final tilt too: the hops' error shows there, not in the
    # peak (the start's tilt). The event-driven run, which locates every impact, ends on the
    # side h/2 ends on, and h = 1 ms on the other (it was "resolved" by its peaks alone)
    ev = nsdyn.simulate_event(block, stuck, e_n=0.9, t_end=2.0, theta0_over_alpha=0.5,
                              dt_out=0.01).summary()["final_tilt_rad"]  # fmt: skip
    with pytest.warns(nsdyn.AccuracyWarning, match=r"does not resolve this response: "
                                                   r"final_tilt_rad"):  # fmt: skip
        checked = simulate_moreau(block, stuck, e_n=0.9, step_check=True, **kw)
    assert checked.step_check["step_resolved"] is False
    half = checked.step_check["h_half"]["final_tilt_rad"]
    assert half * ev > 0 > checked.summary()["final_tilt_rad"] * ev
    assert abs(half - ev) < 0.1 * abs(ev)


def test_a_polygon_in_other_units_than_metres_is_refused():
    with pytest.raises(ValueError, match=r"vertices in metres, within 1e\+06 m"):
        nsdyn.RigidBody.polygon([[0, 0], [1e200, 0], [1e200, 1e200], [0, 1e200]], 1.0)


def test_a_ground_too_soft_for_the_weight_is_refused_and_a_vertex_base_runs():
    # m g / (n k): a 1000 kg prism on two corners of k = 1e-3 N/m sinks 4.9e6 m (it ran, and
    # a scene reported "stayed at rest"); a diamond resting on one vertex has no base width,
    # and its settlement is measured against its size (a ZeroDivisionError before)
    from nsdyn.models.contact.compliant import CompliantGround, simulate_compliant
    from nsdyn.models.rocking.compliant import CompliantBlock
    from nsdyn.models.rocking.compliant import simulate_compliant as rock_compliant

    with pytest.raises(ValueError, match=r"^stiffness: the static settlement m g / \(n k\) = "
                                         r"4.9\d*e\+06 m"):  # fmt: skip
        simulate_compliant(BODY, LAW, CompliantGround(1e-3), t_end=0.1)
    diamond = nsdyn.RigidBody.polygon([[0, 0], [0.3, 0.5], [0, 1], [-0.3, 0.5]], 100.0)
    r = simulate_compliant(diamond, LAW, CompliantGround(1e9, 1e4), t_end=0.05, dt_out=0.01)
    assert r.t.size >= 2  # (it runs; balanced on a vertex it may topple and stop early)
    soft = CompliantBlock.from_frequency(width=0.3, height=1.2, mass=100.0, omega_v=3e-6,
                                         zeta=0.1)  # fmt: skip
    with pytest.raises(ValueError, match=r"^omega_v: the corners' static settlement"):
        rock_compliant(soft, t_end=1.0, theta0_over_alpha=0.5)
