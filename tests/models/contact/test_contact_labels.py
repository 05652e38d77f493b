"""What the contact summaries report: the onset at the tie mu = b/h, the time and mode of the first
motion, the slip at the contacts, and Moreau-Jean's labels of pure rocking.

References: the statics of the resting rectangle (Shenton 1996; seed 002 eqs 1-4) and the
brute-force enumeration of its contact modes (tests/models/contact/test_contact_onset.py);
closed-form onset times under a sine base acceleration; the kinematics of rocking about a
sticking corner (the pivot does not move, so nothing slips).
"""

import math

import numpy as np
import pytest

from nsdyn.models.contact.body import RigidBody
from nsdyn.models.contact.event import simulate_event
from nsdyn.models.contact.excite import BaseMotion
from nsdyn.models.contact.friction import FrictionLaw
from nsdyn.models.contact.moreau import simulate_moreau
from nsdyn.models.contact.onset import onset_mode
from nsdyn.models.contact.results import MODE_NAMES

G = 9.81


@pytest.mark.parametrize("beta, abar", [(0.5, 0.8), (0.25, 0.6), (1.0, 2.0)])
def test_onset_at_the_tie_mu_equal_b_over_h_is_a_flat_slide(beta, abar):
    # mu = b/h: sliding flat needs the trailing reaction N = m g (1 - mu h / b) / 2 = 0 >= 0,
    # admissible; the body slides without tilting and both solvers agree
    assert onset_mode(beta, beta, abar) == "slide"
    body = RigidBody.rectangle(2 * beta, 2.0)
    law, mo = FrictionLaw(beta), BaseMotion.constant(abar * G)
    ev = simulate_event(body, law, mo, t_end=0.05, dt_out=0.001)
    mj = simulate_moreau(body, law, mo, t_end=0.05)
    assert ev.first_motion() == mj.first_motion() == "slide"
    assert np.max(np.abs(ev.q[:, 2])) < 1e-9


@pytest.mark.parametrize("beta, mu, abar", [(0.5, 0.3, 0.6), (0.5, 0.8, 0.7), (0.5, 0.55, 2.5),
                                            (0.5, 0.8, 0.52)])  # fmt: skip
def test_first_motion_from_rest_under_a_step_starts_at_t0(beta, mu, abar):
    # a constant acceleration from t = 0 changes the contact state at once: the first motion is
    # the onset mode at t = 0 (event-driven) or after the first step (Moreau-Jean), not when
    # a sampled displacement passes a threshold (3 to 24 ms later)
    body = RigidBody.rectangle(2 * beta, 2.0)
    law, mo = FrictionLaw(mu), BaseMotion.constant(abar * G)
    ev = simulate_event(body, law, mo, t_end=0.05, dt_out=0.001)
    assert ev.first_motion() == onset_mode(beta, mu, abar) and ev.t_first_motion() == 0.0
    h = 1e-3
    mj = simulate_moreau(body, law, mo, t_end=0.05, h=h)
    assert mj.first_motion() == onset_mode(beta, mu, abar)
    assert mj.t_first_motion() <= h * (1 + 1e-12)
    coarse = simulate_moreau(body, law, mo, t_end=0.05, h=h, dt_out=0.01)  # every 10th step
    assert coarse.first_motion() == mj.first_motion()
    assert coarse.t_first_motion() == mj.t_first_motion()
    assert ev.summary()["t_first_motion_s"] == 0.0


@pytest.mark.parametrize("beta, mu, mode", [(0.5, 0.3, "slide"), (0.5, 0.8, "rock")])
def test_first_motion_time_under_a_sine_is_the_closed_form(beta, mu, mode):
    # a_g = A sin(w t) from rest: rest holds while A sin(w t) <= g min(mu, b/h) (module text of
    # nsdyn.models.contact.onset), so the motion starts at t* = asin(g min(mu, b/h) / A) / w.
    # The event is located to the stick-slip indicator's tolerance (1e-10 g): |t - t*| is
    # bounded by 1e-10 g / (A w cos(w t*)) plus the root tolerance (1e-13 s), far below 1e-8 s.
    A, w = 0.9 * G, 2 * math.pi
    t_star = math.asin(G * min(mu, beta) / A) / w
    body = RigidBody.rectangle(2 * beta, 2.0)
    mo = BaseMotion.sine_acceleration(A, w)
    ev = simulate_event(body, FrictionLaw(mu), mo, t_end=t_star + 0.05, dt_out=0.005)
    assert ev.first_motion() == mode
    assert abs(ev.t_first_motion() - t_star) < 1e-8


def test_max_slide_is_slip_at_the_contacts_not_the_rocking_swing():
    # pure rocking (mu = 2, far above what rocking needs) from a tilt: the pivot sticks, so the
    # slip is zero up to the event solver's tolerances, while the base midpoint swings about
    # the corner by b (1 - cos theta) (~ 1 mm here), which used to be reported as the slide
    body = RigidBody.rectangle(1.0, 4.0)
    ev = simulate_event(body, FrictionLaw(2.0), None, t_end=0.3, theta0=0.15, dt_out=0.001)
    assert np.max(np.abs(ev.q[:, 2])) > 0.1
    assert ev.summary()["max_slide_m"] < 1e-7
    # sliding without rocking (b/h = 1 > mu: the friction cannot tip it): the slip is the whole
    # displacement, v0^2 / (2 mu g) (Coulomb)
    v0 = 1.0
    slid = simulate_event(RigidBody.rectangle(2.0, 2.0), FrictionLaw(0.3), None, t_end=0.5,
                          v0=[v0, 0.0, 0.0], dt_out=0.001)  # fmt: skip
    assert slid.summary()["max_slide_m"] == pytest.approx(v0**2 / (2 * 0.3 * G), rel=1e-6)


def test_moreau_labels_pure_rocking_as_rocking():
    # a 1.1 x 2.2 m prism (seed 002 case B) released at half its slenderness angle rocks on
    # sticking corners (mu = 2) with impacts; the event-driven run labels every sample "rock".
    # Moreau-Jean at its default h = 1e-3 s must too: its pivot may fall freely for a step
    # (no impulse) and its rows turn within a step, neither of which is a slip
    body = RigidBody.rectangle(1.1, 2.2)
    th = 0.5 * math.atan(1.1 / 2.2)
    law = FrictionLaw(2.0)
    ev = simulate_event(body, law, None, t_end=2.0, theta0=th, dt_out=0.001)
    mj = simulate_moreau(body, law, None, t_end=2.0, theta0=th)
    rock = MODE_NAMES.index("rock")
    assert ev.n_impacts >= 3 and np.all(ev.mode == rock)
    assert np.all(mj.mode == rock)
    # and a slide-rock start stays slide-rock (the labels do not swing the other way)
    mo = BaseMotion.constant(2.5 * G)
    sr = simulate_moreau(RigidBody.rectangle(1.0, 2.0), FrictionLaw(0.55), mo, t_end=0.05)
    assert np.all(sr.mode[1:] == MODE_NAMES.index("slide_rock"))
