"""One convention per quantity: full sizes (width 2B, height 2H) in Python as in scene files,
the initial tilt as an angle or a fraction of alpha in both, summaries with units in their
names, and the histories of blocks, frames and compliant blocks as DataFrame / Dataset.

Sources: alpha = atan(B/H), p² = 3 g / (4 R) (Housner 1963; seed 001); the equivalence of the
two ways of giving a size or a tilt is exact (the same float reaches the kernel)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from nsdyn import CompliantBlock, RockingBlock, RockingFrame, simulate_rocking
from nsdyn.models.rocking.compliant import simulate_compliant
from nsdyn.models.rocking.scene import build_model, build_motion, format_summary, run_scene
from nsdyn.models.scenefile import SceneError


def test_full_sizes_are_the_convention_half_sizes_by_name_are_the_same_block():
    # seed 003 Table 2 column 2: 2B = 0.3 m, 2H = 1.2 m, alpha = atan(0.25) = 0.2450 rad
    full = RockingBlock(width=0.3, height=1.2)
    half = RockingBlock(B=0.15, H=0.6)
    assert full == half and (full.B, full.H) == (0.15, 0.6)
    assert full.alpha == math.atan2(0.15, 0.6)  # doubling and halving are exact in floats
    assert full.p == pytest.approx(math.sqrt(3 * 9.81 / (4 * math.hypot(0.15, 0.6))), rel=1e-15)
    with pytest.warns(FutureWarning, match="width=2B, height=2H"):
        old = RockingBlock(0.15, 0.6)  # the former positional half sizes keep their meaning
    assert old == full
    frame = RockingFrame(width=0.3, height=1.2, gamma=2.0)
    assert frame == RockingFrame(B=0.15, H=0.6, gamma=2.0) and frame.column == full
    cb = CompliantBlock.from_frequency(width=0.3, height=1.2, mass=10.0, omega_v=100.0, zeta=1.0)
    assert cb.alpha == full.alpha and cb.p == full.p


@pytest.mark.parametrize(
    "kwargs, field",
    [({"width": 0.3}, "height"), ({"width": -1.0, "height": 1.0}, "width"),
     ({"width": 0.3, "height": 1.2, "B": 0.15}, "not both")],
)  # fmt: skip
def test_bad_sizes_name_the_field(kwargs, field):
    with pytest.raises(ValueError, match=field):
        RockingBlock(**kwargs)


def test_tilt_as_angle_or_fraction_of_alpha_gives_the_same_run():
    blk = RockingBlock(width=0.4, height=2.0)
    a = simulate_rocking(blk, t_end=1.0, theta0_over_alpha=0.5, dt_out=0.01)
    b = simulate_rocking(blk, t_end=1.0, theta0=0.5 * blk.alpha, dt_out=0.01)
    assert a.theta[0] == 0.5 * blk.alpha
    np.testing.assert_array_equal(a.theta, b.theta)  # the same initial value: the same run
    with pytest.raises(ValueError, match="not both"):
        simulate_rocking(blk, t_end=1.0, theta0=0.1, theta0_over_alpha=0.5)
    cb = CompliantBlock.from_frequency(width=0.4, height=2.0, mass=1.0, omega_v=300 * blk.p,
                                       zeta=2.0)  # fmt: skip
    c = simulate_compliant(cb, t_end=0.01, theta0_over_alpha=0.5, dt_out=0.005)
    assert c.theta[0] == pytest.approx(0.5 * blk.alpha, rel=1e-12)  # placed on the corner


def _scene(**motion):
    return {"scene": {"kind": "rocking"}, "block": {"width": 0.4, "height": 2.0},
            "motion": {"t_end": 0.5, **motion}}  # fmt: skip


def test_scene_takes_the_tilt_either_way_and_refuses_both():
    cfg = _scene(theta0_over_alpha=0.5)
    alpha = build_model(cfg, "s.toml").alpha
    assert build_motion(cfg, "s.toml")[2] == {"theta0_over_alpha": 0.5}
    assert build_motion(_scene(theta0=0.1), "s.toml")[2] == {"theta0": 0.1}
    with pytest.raises(SceneError, match=r"s\.toml: motion\.theta0_over_alpha: .*not both"):
        build_motion(_scene(theta0=0.1, theta0_over_alpha=0.5), "s.toml")
    assert alpha == math.atan2(0.2, 1.0)


def test_scene_summary_has_units_in_its_names_and_its_text(tmp_path):
    s = run_scene(_scene(theta0=0.05), source="s.toml", out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip
    assert s["theta0_rad"] == 0.05 and s["t_end_s"] == 0.5
    assert {"alpha_rad", "p_per_s", "max_theta_rad", "max_theta_over_alpha"} <= set(s)
    text = format_summary(s)
    for line in text.splitlines()[1:]:
        label, _, value = line.strip().partition("  ")
        try:
            float(value.split()[0])
        except (ValueError, IndexError):
            continue  # a word (name, model, outcome) or a count
        assert value.split()[-1] in ("rad", "1/s", "s", "-") or label.strip() in (
            "impacts",), line  # every measured number carries its unit  # fmt: skip


def test_summary_keys_carry_units():
    blk = RockingBlock(width=0.4, height=2.0)
    s = simulate_rocking(blk, t_end=1.0, theta0_over_alpha=0.5, dt_out=0.01).summary()
    assert s["alpha_rad"] == blk.alpha and s["p_per_s"] == blk.p
    assert s["max_theta_rad"] == pytest.approx(0.5 * blk.alpha, rel=1e-9)  # free rocking
    assert not {"alpha", "p", "max_theta", "t_overturn"} & set(s)


@pytest.mark.parametrize("model", ["block", "frame", "compliant"])
def test_to_dataframe_round_trips_the_histories(model, assert_round_trip):
    with warnings.catch_warnings():
        warnings.simplefilter("error", FutureWarning)
        if model == "compliant":
            cb = CompliantBlock.from_frequency(width=0.4, height=2.0, mass=1.0, omega_v=100.0,
                                               zeta=2.0)  # fmt: skip
            res = simulate_compliant(cb, t_end=0.05, theta0_over_alpha=0.3, dt_out=0.005)
        else:
            m = (RockingBlock(width=0.4, height=2.0) if model == "block"
                 else RockingFrame(width=0.4, height=2.0, gamma=1.0))  # fmt: skip
            res = simulate_rocking(m, t_end=1.0, theta0_over_alpha=0.5, dt_out=0.01)
    assert_round_trip(res)
    df = res.to_dataframe()
    assert df["theta_rad"].iloc[0] == pytest.approx(0.3 * res.alpha if model == "compliant"
                                                    else 0.5 * res.alpha, rel=1e-12)  # fmt: skip


def test_missing_pandas_names_the_extra(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas now raises ImportError
    res = simulate_rocking(RockingBlock(width=0.4, height=2.0), t_end=0.1, dt_out=0.01)
    with pytest.raises(ImportError, match=r"nsdyn\[frames\]"):
        res.to_dataframe()


def test_a_pulse_outside_the_run_or_a_record_of_one_sample_is_refused():
    # a pulse ending before t0 = 0 (or starting after t_end) drove nothing: "rest", unsaid
    from nsdyn.ground import GroundMotion
    from nsdyn.ground.pulses import one_sine

    b = RockingBlock(width=0.3, height=1.2)
    w = 4 * math.pi  # T_p = 0.5 s
    for t_start in (-1.0, 5.0):
        with pytest.raises(ValueError, match=r"^excitation: the pulse runs from .* outside"):
            simulate_rocking(b, one_sine(4.0, w, t_start=t_start), t_end=3.0)
    with pytest.warns(UserWarning, match=r"^excitation: the pulse starts at -0.1 s, before"):
        simulate_rocking(b, one_sine(4.0, w, t_start=-0.1), t_end=1.0)
    with pytest.raises(ValueError, match=r"^excitation: a record of 1 sample spans no time"):
        simulate_rocking(b, GroundMotion(0.0, 0.01, [5.0]), t_end=1.0)


def test_a_record_runs_to_its_end_by_default_and_other_motions_need_one():
    # as nsdyn.simulate: a record's end is the run's (t_end was required, a TypeError that
    # also hid a record given by name)
    from nsdyn.ground import GroundMotion
    from nsdyn.ground.pulses import one_sine

    b = RockingBlock(width=0.3, height=1.2)
    rec = GroundMotion(0.5, 0.01, 0.5 * np.sin(np.linspace(0.0, 20.0, 201)))  # 0.5 to 2.5 s
    r = simulate_rocking(b, rec)
    assert r.t[-1] == pytest.approx(rec.t0 + rec.duration, abs=1e-12)
    for ex, what in ((None, "free rocking"), (one_sine(4.0, 4 * math.pi), "a Pulse")):
        with pytest.raises(TypeError, match=rf"^t_end: expected the run's end .* for {what}$"):
            simulate_rocking(b, ex)
    with pytest.raises(TypeError, match=r"^excitation: expected GroundMotion, Pulse, Harm"):
        simulate_rocking(b, "synthetic-wn-40s")
    with pytest.raises(ValueError, match=r"^t_end: the record ends at 2\.5 s, at or before t0 = "
                       r"5 s; give t_end or an earlier t0$"):  # fmt: skip
        simulate_rocking(b, rec, t0=5.0)


def test_a_record_that_starts_before_the_run_is_said_and_a_scene_starts_with_it(tmp_path):
    # a record from t = -2 s, all of it before t = 0: simulate_rocking's default t0 = 0 and the
    # scene ran from 0, "rest" with the record's PGA reported, unsaid
    from nsdyn.ground import GroundMotion

    t = np.arange(-2.0, 4.0 + 1e-9, 0.01)
    a = np.where(t < 0, 5.0 * np.sin(2 * np.pi * t), 0.0)
    rec = GroundMotion(-2.0, 0.01, a)
    b = RockingBlock(width=0.3, height=1.2)
    with pytest.warns(UserWarning, match=r"^excitation: the record starts at t = -2 s, before"):
        assert simulate_rocking(b, rec, t_end=4.0).outcome == "rest"
    moved = simulate_rocking(b, rec, t_end=4.0, t0=-2.0)
    assert moved.t[0] == -2.0 and moved.outcome != "rest"
    path = tmp_path / "pre.csv"
    path.write_text("t,a_hor\n" + "".join(f"{x:.2f},{y:.9f}\n" for x, y in zip(t, a, strict=True)))
    cfg = {"scene": {"kind": "rocking"}, "block": {"width": 0.3, "height": 1.2},
           "motion": {"record": str(path), "units": "m/s2"}}  # fmt: skip
    s = run_scene(cfg, source="s.toml", out_dir=tmp_path, figures=False, quiet=True)
    with np.load(tmp_path / "rocking.npz") as d:
        assert d["t"][0] == -2.0 and s["outcome"] == moved.outcome
    # a record that starts later leaves the ground at rest before it, the run from t = 0 (a
    # start at its t0 refused an end before it, naming dt_out); one that starts at or after
    # the run's end drove nothing ("rest") and is refused
    late = tmp_path / "late.csv"
    late.write_text("t,a_hor\n" + "".join(f"{x + 2.5:.2f},{y:.9f}\n"
                                          for x, y in zip(t, a, strict=True)))  # fmt: skip
    cfg["motion"]["record"] = str(late)
    cfg["motion"]["t_end"] = 1.0
    s = run_scene(cfg, source="s.toml", out_dir=tmp_path, figures=False, quiet=True)
    with np.load(tmp_path / "rocking.npz") as d:
        assert d["t"][0] == 0.0 and d["t"][-1] == 1.0 and s["outcome"] != "rest"
    cfg["motion"]["t_end"] = 0.5
    with pytest.raises(SceneError, match=r"^s.toml: motion.t_end: the record starts at 0.5 s"):
        run_scene(cfg, source="s.toml", out_dir=tmp_path, figures=False, quiet=True)
    with pytest.raises(ValueError, match=r"^excitation: the record starts at 0.5 s, at or after"):
        simulate_rocking(b, GroundMotion(0.5, 0.01, a), t_end=0.5)
    del cfg["motion"]["t_end"]
    cfg["motion"]["record"] = str(path)
    cfg["scene"]["model"] = "compliant"
    cfg["block"]["omega_v_over_p"] = 300.0
    with pytest.raises(SceneError, match=r"^s.toml: motion.record: the record starts at t = -2"):
        run_scene(cfg, source="s.toml", out_dir=tmp_path, figures=False, quiet=True)


def test_every_rocking_body_released_past_alpha_is_leaning_past_it_at_an_early_end():
    # released a hair past alpha with the ground at rest, gravity's moment m g R sin(theta -
    # alpha) turns a block away from upright for good (on rigid or compliant corners): at an
    # end before it overturns, its summary says so (the compliant block's read "standing")
    blk = RockingBlock(width=0.5, height=2.0)
    cb = CompliantBlock.from_frequency(width=0.5, height=2.0, mass=1.0, omega_v=300 * blk.p,
                                       zeta=0.5)  # fmt: skip
    kw = dict(t_end=1.0, theta0_over_alpha=1.05, dt_out=0.01)
    for res in (simulate_rocking(blk, **kw), simulate_compliant(cb, **kw)):
        s = res.summary()
        assert not s["overturned"] and s["past_tip_over_at_end"], s
        assert s["final_theta_rad"] > 1.05 * blk.alpha and s["final_thetad_rad_per_s"] > 0
    s = simulate_rocking(blk, t_end=1.0, theta0_over_alpha=0.95, dt_out=0.01).summary()
    assert not s["past_tip_over_at_end"]  # below alpha it rocks back: no fall
    for res in (simulate_rocking(blk, **{**kw, "t_end": 4.0}),
                simulate_compliant(cb, **{**kw, "t_end": 4.0})):  # fmt: skip
        s = res.summary()  # (it falls at about 2 s: overturned, not leaning)
        assert s["overturned"] and not s["past_tip_over_at_end"]


@pytest.mark.parametrize(("key", "value", "said"), [("a_p_g", 40.0, True), ("a_p", 400.0, True),
                                                    ("a_p_g", 0.4, False)])  # fmt: skip
def test_a_pulse_amplitude_past_any_record_is_noted(tmp_path, key, value, said):
    # a_p_g = 40 typed for 0.40 g overturned the block at 0.12 s without a word; recorded
    # ground motions stay below PGA_MAX_PLAUSIBLE = 30 m/s², the records' own unit check
    cfg = {"scene": {"kind": "rocking"}, "block": {"width": 0.3, "height": 1.2},
           "motion": {"pulse": "sine", key: value, "omega_p": 12.566}}  # fmt: skip
    s = run_scene(cfg, source="s.toml", out_dir=tmp_path, figures=False, quiet=True)
    noted = [n for n in s.get("notes", []) if "past the 30 m/s² of recorded ground motions" in n]
    assert bool(noted) == said
