"""Onset of motion from rest (Shenton 1996, Ishiyama 1982) against a brute-force enumeration of
the contact modes of the resting rectangle (Newton-Euler with each combination of stick / slip /
lift at the two corners; a mode is admissible when its reactions and accelerations satisfy
Signorini and Coulomb), and the event-driven solver starting in that mode."""

import itertools

import numpy as np
import pytest

from nsdyn.models.contact.body import RigidBody
from nsdyn.models.contact.event import simulate_event
from nsdyn.models.contact.excite import BaseMotion
from nsdyn.models.contact.friction import FrictionLaw
from nsdyn.models.contact.onset import mu_rock, onset_mode

G = 9.81
TOL = 1e-9


def admissible_modes(beta, mu, abar):
    """Modes of a rectangle (b = beta, h = 1, m = 1) at rest under base acceleration abar g."""
    b, h, m = beta, 1.0, 1.0
    J = m * (b * b + h * h) / 3  # (2b)^2 + (2h)^2 over 12
    corners = [(-b, -h), (b, -h)]
    found = set()
    # rest: a = 0; total friction and the moment fix N_L, N_R
    F = m * abar * G
    NL = 0.5 * (m * G) - F * h / (2 * b)  # moment about the centre: b (N_R - N_L) + h F = 0
    NR = m * G - NL
    if NL >= -TOL and NR >= -TOL and abs(F) <= mu * m * G + TOL:
        found.add("rest")
    # every other combination: unknowns (xdd, ydd, thdd, F_L, N_L, F_R, N_R)
    for states in itertools.product(("lift", "stick", "+", "-"), repeat=2):
        if states == ("stick", "stick"):
            continue
        A = np.zeros((7, 7))
        rhs = np.zeros(7)
        A[0, [0, 3, 5]] = [m, -1, -1]
        rhs[0] = -m * abar * G
        A[1, [1, 4, 6]] = [m, -1, -1]
        rhs[1] = -m * G
        A[2, 2] = J
        for k, (rx, ry) in enumerate(corners):
            A[2, 3 + 2 * k] = ry  # torque r x F = rx N - ry F
            A[2, 4 + 2 * k] = -rx
        row = 3
        for k, (rx, ry) in enumerate(corners):
            st = states[k]
            if st == "lift":
                A[row, 3 + 2 * k] = 1
                A[row + 1, 4 + 2 * k] = 1
            else:
                A[row, [1, 2]] = [1, rx]  # normal acceleration 0
                if st == "stick":
                    A[row + 1, [0, 2]] = [1, -ry]
                else:
                    s = 1 if st == "+" else -1
                    A[row + 1, 3 + 2 * k] = 1
                    A[row + 1, 4 + 2 * k] = s * mu
            row += 2
        try:
            x = np.linalg.solve(A, rhs)
        except np.linalg.LinAlgError:
            continue
        ok = True
        for k, (rx, ry) in enumerate(corners):
            Fk, Nk = x[3 + 2 * k], x[4 + 2 * k]
            an = x[1] + x[2] * rx
            at = x[0] - x[2] * ry
            st = states[k]
            if st == "lift":
                ok &= an >= -TOL
            else:
                ok &= Nk >= -TOL
                if st == "stick":
                    ok &= abs(Fk) <= mu * Nk + TOL
                else:
                    ok &= (1 if st == "+" else -1) * at > TOL
        if not ok or states == ("lift", "lift"):
            continue
        n_on = sum(s != "lift" for s in states)
        slip = any(s in "+-" for s in states)
        found.add(
            ("slide" if slip else "rest") if n_on == 2 else ("slide_rock" if slip else "rock")
        )
    return found


# no grid point lies on a mode boundary (ā = μ or ā = b/h), where the classification is a tie
GRID = [(beta, mu, a) for beta in (0.2, 0.5, 1.1) for mu in (0.1, 0.3, 0.57, 0.8, 1.5)
        for a in (0.05, 0.25, 0.45, 0.7, 1.2, 3.0)]  # fmt: skip
assert all(abs(a - mu) > 1e-6 and abs(a - beta) > 1e-6 for beta, mu, a in GRID)


@pytest.mark.parametrize("beta, mu, abar", GRID)
def test_onset_classifier_is_the_admissible_mode(beta, mu, abar):
    modes = admissible_modes(beta, mu, abar)
    assert modes == {onset_mode(beta, mu, abar)}


def test_closed_form_boundaries():
    # Ishiyama's limits: rest below min(mu, b/h); rock needs mu > b/h at the rocking threshold
    assert onset_mode(0.5, 0.3, 0.29) == "rest" and onset_mode(0.5, 0.3, 0.31) == "slide"
    assert onset_mode(0.5, 0.8, 0.49) == "rest" and onset_mode(0.5, 0.8, 0.51) == "rock"
    assert mu_rock(0.5, 0.5) == pytest.approx(0.5)  # continuous at abar = b/h
    assert onset_mode(0.5, 0.52, 5.0) == "slide_rock"
    # frictionless (mu = 0, refused as "not positive" before): any push slides, none rests
    assert onset_mode(0.5, 0.0, 1e-3) == "slide" and onset_mode(0.5, 0.0, 0.0) == "rest"


@pytest.mark.parametrize("beta, mu, abar", [(0.5, 0.3, 0.6), (0.5, 0.8, 0.7), (0.5, 0.55, 2.5),
                                            (0.5, 0.8, 0.3)])  # fmt: skip
def test_event_driven_starts_in_the_onset_mode(beta, mu, abar):
    body = RigidBody.rectangle(2 * beta, 2.0)
    res = simulate_event(body, FrictionLaw(mu), BaseMotion.constant(abar * G), t_end=0.05,
                         dt_out=0.01)  # fmt: skip
    assert res.first_motion() == onset_mode(beta, mu, abar)


def test_a_lift_off_inside_a_steps_span_of_a_record_is_found():
    # A body at rest on its base feels the ground acceleration alone until it tips: the
    # 0.5 x 1.5 m block (mu 0.45 > b/h, so rocking comes first) lifts off the first time
    # |a_h| > (g + a_v) b/h on the record as interpolated (linear between its samples). On the
    # bundled record at PGA 7 m/s² that holds first for 2 ms around the sample at 1.00 s, a
    # window the steps, not aligned with the samples, strode over: onset was reported 0.23 s
    # late. Located on a grid of dt/1000 here, so to 1e-5 s.
    from nsdyn.ground import read_motion

    rec = read_motion("synthetic-wn-40s").scaled_to_pga(7.0)
    t_end = 1.5
    base = BaseMotion.from_motion(rec)
    t = np.arange(0.0, t_end, rec.dt / 1000)
    ah = np.interp(t, rec.t, rec.a_hor)
    av = np.interp(t, rec.t, rec.a_ver) if rec.a_ver is not None else 0.0 * t
    tips = np.abs(ah) > (G + av) * (0.5 / 1.5)
    assert tips.any()
    t_hand = t[np.argmax(tips)]
    res = simulate_event(RigidBody.rectangle(0.5, 1.5, 100.0), FrictionLaw(0.45, 0.45, 0.0),
                         base, t_end=t_end, dt_out=0.01)  # fmt: skip
    s = res.summary()
    assert s["first_motion"] == "rock"
    assert s["t_first_motion_s"] == pytest.approx(t_hand, abs=2e-5)
