"""The two solvers agree where both are valid, and the rigid block rocks like Housner's model.

1. Seed 002 cases B1 and C1 (slender prisms, mu = mu_s = 0.57 > b/h, impulsive start): the
   event-driven solver and Moreau-Jean must give the same history.  Moreau-Jean is first order,
   so the largest state difference over the whole run must fall about in proportion to h
   (ratio of 1.4-2.8 when h halves; an O(1) disagreement such as one overturning and the other
   not would not shrink) and be below K h with K = 8 m/s (rad/s): the measured constant is
   0.7 (B1) and 6.6 (C1), set by the impacts of the rocking phase, each shifted by O(h).
2. With friction too large to slip, the event-driven body and ``nsdyn.models.rocking``
   (Housner's single-degree-of-freedom block, its own kernel) see the same impacts and peaks
   under a one-sine pulse: same lift-off, first ten impact times within 1e-7 s (both locate
   events to round-off on their dense outputs at tolerances 1e-10 / 1e-11) and peaks within
   1e-5 alpha.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from nsdyn.ground import G_EARTH, sine_pulse
from nsdyn.models.contact import BaseMotion, FrictionLaw, RigidBody, simulate_event, simulate_moreau
from nsdyn.models.rocking import RockingBlock, simulate_rocking

sys.path.insert(0, str(Path(__file__).parents[3] / "examples"))
import contact_table1 as table1  # noqa: E402


def _case(name):
    a, c, T, mu_s, mu_d, _, _ = table1.CASES[name]
    body = RigidBody.rectangle(a, c, table1.MASS * c)
    A = table1.PGA * (T / (2 * math.pi)) ** 2
    motion = BaseMotion.displacement_sine(A, T, 5, "impulsive")
    return body, FrictionLaw(mu_s, mu_d, 0.0), motion, 5 * T + 2.0


@pytest.mark.parametrize("name", ["B1", "C1"])
def test_event_driven_and_moreau_jean_agree_on_slender_cases(name):
    body, fr, motion, t_end = _case(name)
    ev = simulate_event(body, fr, motion, t_end=t_end, dt_out=0.005)
    diffs = []
    for h in (5e-4, 2.5e-4):
        mj = simulate_moreau(body, fr, motion, t_end=t_end, h=h, dt_out=0.005)
        assert not mj.summary()["overturned"]
        n = min(len(mj.t), len(ev.t))
        np.testing.assert_allclose(mj.t[:n], ev.t[:n], atol=1e-9)
        diffs.append(np.max(np.abs(mj.q[:n] - ev.q[:n])))
    s = ev.summary()
    assert not s["overturned"]  # the FE run: "tilting - sticking"
    # the difference halves with h (Moreau-Jean is first order): it converges to the event run
    assert 1.4 < diffs[0] / diffs[1] < 2.8
    # the same mode at the end (B1: back at rest; C1: rocking again after the stop jump)
    assert ev.mode[-1] == mj.mode[-1]


def test_large_friction_matches_the_rocking_family_under_a_pulse():
    gm = sine_pulse(0.8 * G_EARTH, 2.0, 1, dt=0.001, duration=2.2)
    blk = RockingBlock(width=1.0, height=2.0)
    rr = simulate_rocking(blk, gm, t_end=2.2, tol=1e-10, dt_out=1e-3)
    body = RigidBody.rectangle(1.0, 2.0, 5.0)
    ev = simulate_event(body, FrictionLaw(10.0), BaseMotion.from_motion(gm), t_end=2.2,
                        impact_law="housner", dt_out=1e-4, rtol=1e-11, atol=1e-13)  # fmt: skip
    alpha = math.atan(0.5)
    lift = [t for t, name, _ in ev.events if name == "lift-off"]
    assert lift[0] == pytest.approx(rr.t_uplift, abs=1e-7)
    touch = np.array([t for t, name, _ in ev.events if name == "touchdown"])
    n = 10  # the first ten impacts; later ones (an accumulation near 2.17 s) drift apart
    assert len(touch) >= n and len(rr.impacts) >= n
    np.testing.assert_allclose(touch[:n], rr.impacts[:n, 0], atol=1e-7)
    # peaks between impacts: sampled at 1e-4 s, relative sampling error ~ (p dt)^2 / 2 ~ 1e-7
    for tp, thp in rr.peaks[1:6]:
        k = int(np.searchsorted(touch, tp))
        lo, hi = touch[k - 1], touch[k]
        sel = (ev.t > lo) & (ev.t < hi)
        assert np.abs(ev.q[sel, 2]).max() == pytest.approx(abs(thp), abs=1e-5 * alpha)
    assert ev.time_in_modes()["slide_rock"] == 0.0
