"""With large friction the body rocks exactly like Housner's model (Housner 1963): impacts conserve
the angular momentum about the striking corner, thetad+ = (1 - 1.5 sin^2 alpha) thetad-, and
between impacts the exact energy relation J_O thetad^2 / 2 + m g R cos(alpha - |theta|) = const
holds; impact times and peaks are computed here by quadrature of that relation."""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from nsdyn.models.contact.body import RigidBody
from nsdyn.models.contact.event import simulate_event
from nsdyn.models.contact.friction import FrictionLaw
from nsdyn.models.contact.moreau import simulate_moreau

G = 9.81


def housner_sequence(R, alpha, theta0, n):
    """Impact times and the peaks between them of free Housner rocking released at theta0."""
    p2 = 3 * G / (4 * R)  # m g R / J_O for a rectangle

    def quarter(th):  # time to fall from rest at th to theta = 0
        f = lambda x: 1 / math.sqrt(2 * p2 * (math.cos(alpha - th) - math.cos(alpha - x)))  # noqa: E731
        # substitute x = th (1 - u^2) to remove the end-point singularity
        return quad(lambda u: f(th * (1 - u * u)) * 2 * th * u, 0, 1, limit=200)[0]

    r = 1 - 1.5 * math.sin(alpha) ** 2
    times, peaks = [], [theta0]
    t, th = quarter(theta0), theta0
    times.append(t)
    for _ in range(n - 1):
        w2 = 2 * p2 * (math.cos(alpha - th) - math.cos(alpha)) * r * r
        th = brentq(lambda x, w2=w2: 2 * p2 * (math.cos(alpha) - math.cos(alpha - x)) + w2,
                    0, alpha)  # fmt: skip
        peaks.append(th)
        t += 2 * quarter(th)
        times.append(t)
    return np.array(times), np.array(peaks), r


@pytest.mark.parametrize("width, height", [(1.0, 2.0), (1.1, 3.3)])
def test_large_friction_event_driven_rocks_like_housner(width, height):
    body = RigidBody.rectangle(width, height, 7.0)
    R, alpha, _ = body.corner_geometry()
    th0 = 0.6 * alpha
    t_ref, pk_ref, r = housner_sequence(R, alpha, th0, 5)
    res = simulate_event(body, FrictionLaw(10.0), t_end=t_ref[-1] + 0.01, impact_law="housner",
                         theta0=th0, dt_out=1e-4, rtol=1e-11, atol=1e-13)  # fmt: skip
    touch = np.array([t for t, name, _ in res.events if name == "touchdown"])[:5]
    np.testing.assert_allclose(touch, t_ref, rtol=1e-5)  # cubic Hermite event location
    # peaks between impacts (sampled at 1e-4 s: relative error ~ (p dt)^2)
    for k in range(1, 5):
        sel = (res.t > t_ref[k - 1]) & (res.t < t_ref[k])
        assert abs(np.abs(res.q[sel, 2]).max() - pk_ref[k]) < 1e-5 * pk_ref[0]
    # the corner never slips and the body never flies
    tim = res.time_in_modes()
    assert tim["slide"] == tim["slide_rock"] == tim["flight"] == 0.0


def test_moreau_jean_rocking_peaks_approach_housner():
    """Moreau-Jean (e_n = 0, sticking) reproduces Housner's peaks to O(h) (penetration O(h))."""
    body = RigidBody.rectangle(1.0, 2.0)
    R, alpha, _ = body.corner_geometry()
    t_ref, pk_ref, _ = housner_sequence(R, alpha, 0.6 * alpha, 4)
    h = 5e-4
    res = simulate_moreau(body, FrictionLaw(10.0), t_end=t_ref[-1] + 0.05, h=h,
                          theta0=0.6 * alpha)  # fmt: skip
    for k in (1, 2, 3):
        sel = (res.t > t_ref[k - 1] + 0.02) & (res.t < t_ref[k] - 0.02)
        # bound: a few steps of rotation at the impact speed, h p alpha
        assert abs(np.abs(res.q[sel, 2]).max() - pk_ref[k]) < 3 * h * math.sqrt(3 * G / (4 * R))
