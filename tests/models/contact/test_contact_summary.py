"""Contact bodies: the initial tilt as an angle or a fraction of alpha, summaries with units in
their names, and the histories (event-driven, Moreau–Jean, compliant ground) as DataFrame /
Dataset.

Sources: a rectangle of width 2b and height 2h rocks about a base corner with alpha =
atan(b/h) (module text of nsdyn.models.contact.body); the two ways of giving the tilt put the
same float into the initial state."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nsdyn import FrictionLaw, RigidBody
from nsdyn.models.contact import CompliantGround, simulate_compliant, simulate_event
from nsdyn.models.contact.moreau import simulate_moreau
from nsdyn.models.contact.scene import build, format_summary
from nsdyn.models.scenefile import SceneError

BODY = RigidBody.rectangle(0.5, 2.0, mass=100.0)
LAW = FrictionLaw(0.8)


def test_tilt_as_fraction_of_alpha_is_the_angle():
    alpha = math.atan2(0.25, 1.0)
    a = simulate_event(BODY, LAW, t_end=0.05, theta0_over_alpha=0.4, dt_out=0.01)
    b = simulate_event(BODY, LAW, t_end=0.05, theta0=0.4 * alpha, dt_out=0.01)
    assert a.q[0, 2] == pytest.approx(0.4 * alpha, rel=1e-15)
    np.testing.assert_array_equal(a.q, b.q)
    with pytest.raises(ValueError, match="not both"):
        simulate_moreau(BODY, LAW, t_end=0.05, theta0=0.1, theta0_over_alpha=0.4)


def test_scene_tilt_either_way_and_not_both():
    cfg = {"scene": {"kind": "contact"}, "body": {"width": 0.5, "height": 2.0},
           "friction": {"mu_s": 0.8},
           "motion": {"t_end": 0.1, "theta0_over_alpha": 0.5}}  # fmt: skip
    opts = build(cfg, "c.toml")[4]
    assert opts["theta0"] == pytest.approx(0.5 * math.atan2(0.25, 1.0), rel=1e-15)
    cfg["motion"]["theta0"] = 0.1
    with pytest.raises(SceneError, match=r"c\.toml: motion\.theta0_over_alpha: .*not both"):
        build(cfg, "c.toml")


@pytest.mark.parametrize("solver", ["event", "moreau", "compliant"])
def test_to_dataframe_round_trips_the_histories(solver, assert_round_trip):
    if solver == "event":
        res = simulate_event(BODY, LAW, t_end=0.3, theta0_over_alpha=0.5, dt_out=0.01)
    elif solver == "moreau":
        res = simulate_moreau(BODY, LAW, t_end=0.3, h=1e-3, theta0_over_alpha=0.5, dt_out=0.01)
    else:
        ground = CompliantGround.from_ratio(BODY, 1e7, 0.1)
        res = simulate_compliant(BODY, LAW, ground, t_end=0.05, dt_out=0.005)
    assert_round_trip(res)
    s = res.summary()
    assert {"max_slide_m", "max_tilt_rad", "time_in_mode_s"} <= set(s)
    assert not {"max_slide", "max_tilt", "t_overturn", "time_in_mode"} & set(s)


def test_text_summary_units():
    s = {"name": "x", "first_motion": "rock", "max_slide_m": 0.001, "max_tilt_rad": 0.02,
         "t_overturn_s": None, "overturned": False, "time_in_mode_s": {"rock": 0.5}}  # fmt: skip
    text = format_summary(s)
    assert "peak slide         0.001 m" in text and "peak tilt          0.02 rad" in text
    assert "time in rock       0.5 s" in text
    assert "peak slide 0.001 m, peak tilt 0.02 rad" in text.splitlines()[0]


def test_round_off_tilt_is_reported_as_no_rocking():
    # a tilt of 1e-15 rad is integration round-off, not rocking: below 1 % of alpha (the
    # figures' tilt floor) the outcome says so instead of printing the noise
    from nsdyn.models.contact.scene import outcome

    s = {"first_motion": "slide", "max_slide_m": 0.05, "max_tilt_rad": 1.5e-14,
         "alpha_rad": math.atan2(0.55, 0.5), "overturned": False}  # fmt: skip
    line = outcome(s)[1]
    assert "no rocking" in line and "e-14" not in line
    s["max_tilt_rad"] = 0.1
    assert "peak tilt 0.1 rad" in outcome(s)[1]
