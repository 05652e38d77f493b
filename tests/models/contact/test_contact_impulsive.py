"""Impulsive versus smooth start of a displacement-driven sine (seed 002's excitation).

u_g = A sin(w t) switched on at t = 0 jumps the ground velocity by A w.  In the ground frame the
body's velocity jumps by -A w; its normal velocity does not change, so the normal impulse is
zero and, by Coulomb's law, so is the friction impulse: the rigid body keeps xd(0+) = -A w.
Then, while it slides (no rotation for mu < b/h), xdd = A w^2 sin(w t) + mu g, so

    xd(t) = -A w cos(w t) + mu g t,    x(t) = -A sin(w t) + mu g t^2 / 2,

the slip stops at the first root t* of mu g t = A w cos(w t) and the body then sticks for good
(the ground acceleration A w^2 < mu_s g).  The slide is |x(t*)| (with mu = mu_d of the sliding
phase).  A smooth start (sin^2 ramp over one period) keeps the ground acceleration below mu g and
(b/h) g: the body never leaves rest.
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from nsdyn.ground import G_EARTH
from nsdyn.models.contact import BaseMotion, FrictionLaw, RigidBody, simulate_event, simulate_moreau

PGA, T = 1.6, 1.98  # seed 002 case A1 (prism 1.1 x 1.0 m)


def closed_form_slide(A, w, mu, g=G_EARTH):
    """(t*, x(t*)) of the slide after the impulsive start."""
    ts = brentq(lambda t: mu * g * t - A * w * math.cos(w * t), 0.0, math.pi / (2 * w))
    return ts, -A * math.sin(w * ts) + 0.5 * mu * g * ts**2


@pytest.mark.parametrize(
    "mu_s, mu_d, C, mu_slide", [(0.4, 0.2, 0.0, 0.4), (0.4, 0.2, math.inf, 0.2)]
)
def test_impulsive_start_slips_by_the_closed_form_amount(mu_s, mu_d, C, mu_slide):
    body = RigidBody.rectangle(1.1, 1.0, 2272.6)
    w = 2 * math.pi / T
    A = PGA / w**2
    motion = BaseMotion.displacement_sine(A, T, 5, "impulsive")
    fr = FrictionLaw(mu_s, mu_d, C)
    ts, xs = closed_form_slide(A, w, mu_slide)
    ev = simulate_event(body, fr, motion, t_end=1.0, dt_out=1e-3)
    assert ev.v[0, 0] == pytest.approx(-A * w, rel=1e-12)  # no friction impulse at the jump
    stops = [t for t, name, _ in ev.events if name == "slip-stop"]
    assert stops[0] == pytest.approx(ts, rel=1e-7)
    assert ev.slide[-1] == pytest.approx(xs, rel=1e-6)
    assert np.all(np.abs(ev.q[:, 2]) < 1e-12)  # pure sliding (mu < b/h)
    # Moreau-Jean: first order; bound two steps at the jump velocity
    h = 1e-4
    mj = simulate_moreau(body, fr, motion, t_end=1.0, h=h, dt_out=1e-3)
    assert abs(mj.slide[-1] - xs) < 2 * A * w * h


def test_smooth_start_never_leaves_rest():
    body = RigidBody.rectangle(1.1, 1.0, 2272.6)
    A = PGA * (T / (2 * math.pi)) ** 2
    motion = BaseMotion.displacement_sine(A, T, 5, "smooth")
    assert np.abs(motion.tab_h).max() < 0.4 * G_EARTH  # below mu g and (b/h) g
    fr = FrictionLaw(0.4, 0.2)
    for res in (simulate_event(body, fr, motion, t_end=5 * T, dt_out=0.01),
                simulate_moreau(body, fr, motion, t_end=5 * T, h=1e-3, dt_out=0.01)):  # fmt: skip
        assert np.abs(res.slide).max() < 1e-12
        assert np.all(res.mode == 0)
