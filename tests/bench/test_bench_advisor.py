"""The model advisor on the benchmark scene: the advice holds at both ends of the PGA range."""

from __future__ import annotations

import numpy as np
import pytest

from nsdyn.bench import common
from nsdyn.models.isolated.system import build_system
from nsdyn.solve.transient import simulate
from nsdyn.studies.advisor import advise, stick_probe


@pytest.fixture(scope="module")
def frame():
    return common.bench_frame()


def test_advisor_picks_fixed_base_when_isolators_never_slide(frame):
    """PGA 0.03 m/s^2 = 0.1 mu g: the switch model (event-driven) never leaves stick, the
    friction carries at most a fraction of mu lam, and the advice is the fixed-base model."""
    iso = common.bench_isolation()
    motion = common.bench_motion("wn", 10.0, pga=0.03)
    sw = build_system(frame, common.bench_isolation("switch"), fidelity="cb", f_max=5.0)
    res = simulate(sw, motion, method="event", rtol=1e-6, atol=1e-8)
    r = res.response
    assert res.stats["n_events"] == 0
    assert np.all(r.modes == 0)
    ni = sw.n_isolators
    util = np.abs(r.tau) / (common.MU * r.lam[:, :ni])
    assert util.max() < 1.0
    assert np.max(np.abs(r.x_iso - r.x_iso[0])) < 1e-9  # m: the base stays where gravity left it
    sp = stick_probe(frame, motion, iso)
    assert sp["verdict"] == "stick throughout"
    advice = advise(frame, motion, tol=0.05, isolation=iso)
    assert advice.fidelity == "fixed"
    assert advice.evidence["stick_probe"]["slip_events"] == 0
    assert advice.evidence["probes"] and advice.evidence["probes"][-1]["ok"]


def test_advisor_does_not_pick_fixed_base_at_pga_3(frame):
    """At PGA 3 m/s^2 (about 10 mu g) the isolators slide, so the advice is an isolated
    model, whatever the frequency content."""
    motion = common.bench_motion("wn", 8.0)
    advice = advise(frame, motion, tol=0.05, isolation=common.bench_isolation(), probe=False)
    assert advice.fidelity != "fixed"
    assert advice.evidence["stick_probe"]["verdict"] == "slides"
    assert advice.evidence["stick_probe"]["slip_events"] > 0


@pytest.mark.slow
def test_advisor_probes_choose_a_rung_under_tol(frame):
    """With probes, the advised rung's measured error against the next rung is under tol."""
    motion = common.bench_motion("wn", 8.0)
    advice = advise(frame, motion, tol=0.05, isolation=common.bench_isolation())
    assert advice.fidelity in ("rigid", "cb", "full")
    chosen = [p for p in advice.evidence["probes"] if p["ok"]]
    if advice.fidelity != "full":
        assert chosen and max(chosen[0]["errors"].values()) <= 0.05
    assert "idr" in advice.evidence["probes"][0]["errors"]
    # the rigid model has no interstorey drift: it cannot meet an IDR tolerance
    assert advice.evidence["probes"][0]["errors"]["idr"] == pytest.approx(1.0)


def test_advisor_refuses_what_it_cannot_judge_and_floors_tiny_peaks(frame):
    # tol = -1 or NaN returned an advice; a still record compared its rungs' round-off and
    # static drift at 100 % and advised the fixed base at 20 Hz; a peak below its floor (a
    # drift ratio of 1e-5) is no error to choose by: 9e-8 against a rigid deck's 0 refused it
    from nsdyn.ground.motion import GroundMotion
    from nsdyn.studies.advisor import PEAK_FLOOR, _rel_err

    motion = common.bench_motion("wn", 10.0, pga=0.03)
    for tol in (-1.0, float("nan"), 0.0):
        with pytest.raises(ValueError, match=r"^tol: expected a relative error > 0"):
            advise(frame, motion, tol=tol)
    still = GroundMotion(t0=0.0, dt=motion.dt, a_hor=np.zeros_like(motion.a_hor))
    with pytest.raises(ValueError, match=r"^motion: its horizontal acceleration is zero"):
        advise(frame, still)
    assert _rel_err(0.0, 9e-8, PEAK_FLOOR["idr"]) == pytest.approx(9e-3)
    assert _rel_err(0.98e-3, 1e-3, PEAK_FLOOR["idr"]) == pytest.approx(0.02)  # (above it)
