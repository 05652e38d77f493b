"""The cylinder: the initial tilt (an angle or a fraction of alpha = atan(r/H), in Python and
in scenes), a summary with units in its names, and the histories as DataFrame / Dataset.

Sources: the tilt of the axis of the quaternion cos(θ/2) + sin(θ/2) n (n horizontal) is θ
(exact up to the round-off of arctan2 of the rotation matrix, a few ulp of θ)."""

from __future__ import annotations

import math

import pytest

from nsdyn.models.cylinder import CylinderParams, earthquake, simulate
from nsdyn.models.cylinder.scene import build, format_summary, run_scene
from nsdyn.models.scenefile import SceneError

EPS = 2.220446049250313e-16


def _short():
    return earthquake(0, duration=0.3, dt=0.01)


def test_tilt_as_fraction_of_alpha():
    p = CylinderParams()
    dt, ag = _short()
    res = simulate(p, ag * 0.0, dt, theta0_over_alpha=0.2, azimuth0=0.5)
    alpha = math.atan2(p.r, p.H)
    # the quaternion's tilt back through R and arctan2: a few ulp of theta (10 eps relative)
    assert abs(res.tilt[0] - 0.2 * alpha) <= 10 * EPS * 0.2 * alpha
    assert res.tilt_dir[0] == pytest.approx(0.5, abs=1e-12)
    with pytest.raises(ValueError, match="not both"):
        simulate(p, ag, dt, theta0=0.01, theta0_over_alpha=0.2)


def _cfg(**motion):
    return {"scene": {"kind": "cylinder"}, "motion": {"duration": 0.3, **motion}}


def test_scene_tilt_either_way(tmp_path):
    opts = build(_cfg(theta0=0.01), "y.toml")[3]
    assert opts["tilt"] == {"theta0": 0.01}
    with pytest.raises(SceneError, match=r"y\.toml: motion\.theta0_over_alpha: .*not both"):
        build(_cfg(theta0=0.01, theta0_over_alpha=0.1), "y.toml")
    fixed = _cfg(theta0=0.01)
    fixed["foundation"] = {"case": "fixed"}
    with pytest.raises(SceneError, match=r"motion\.theta0: a fixed base cannot start tilted"):
        build(fixed, "y.toml")
    s = run_scene(_cfg(theta0=0.01), source="y.toml", out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip
    assert abs(s["theta0_rad"] - 0.01) <= 10 * EPS * 0.01
    text = format_summary(s)
    assert "initial tilt [rad]" in text and "N/m³" in text


def test_scene_takes_the_full_height_or_the_half_height():
    full = _cfg()
    full["cylinder"] = {"r": 1.0, "height": 6.0}
    half = _cfg()
    half["cylinder"] = {"r": 1.0, "H": 3.0}
    p_full, p_half = build(full, "y.toml")[0], build(half, "y.toml")[0]
    assert p_full == p_half and p_full.height == 6.0  # halving is exact in floats
    full["cylinder"]["H"] = 3.0
    with pytest.raises(SceneError, match=r"y\.toml: cylinder\.height: .*not both"):
        build(full, "y.toml")


def test_to_dataframe_round_trips_the_histories(assert_round_trip):
    dt, ag = _short()
    res = simulate(CylinderParams(), ag, dt)
    assert_round_trip(res)
    s = res.summary()
    assert s["max_tilt_rad"] == float(res.tilt.max())
    assert {"max_base_shear_N", "max_overturning_Nm", "max_rim_lift_m", "t_end_s"} <= set(s)
