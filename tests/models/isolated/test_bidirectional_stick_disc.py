"""Switch law with a stick disc: a stuck isolator never holds a force outside its disc; a
stick band too narrow is reported; a brief rim contact is located (both laws).

Source: the Coulomb law in the plane (the stick force of a stuck isolator lies in the disc
|τ| <= μ_s N; stick → slip is the event where it reaches the rim). Along the whole history,
every output sample whose isolator is in stick must satisfy the disc condition. Tolerance:
the switch law's stick test admits |τ| <= μ_s N (1 + STICK_RTOL), and an event is located to
EVENT_TTOL = 1e-11 s past the crossing; the stick force changes at most at
|dτ/dt| <= m |ȧ_g| + k |v| + ... ~ 1e4 N/s here, i.e. by ~1e-7 N within that bracket against
μ_s N ~ 5e2 N. A relative slack of 1e-6 covers both with margin; the failure it guards
against (a break-away missed because a slip-start re-stuck at once) holds |τ| at 1.6 μ_s N.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from nsdyn.ground.orbit import HarmonicPlane
from nsdyn.models.isolated import _kplanerun as kr
from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.deck import rigid_deck, sdof_plane, simulate_plane
from nsdyn.models.isolated.plane_result import PlaneIntegrationError

G = 9.81
SLACK = 1e-6


def _worst_stuck_ratio(r, mu_s):
    """Largest |τ|/(μ_s N) over the samples in stick (0 when none sticks)."""
    stuck = r.modes == 0
    if not np.any(stuck):
        return 0.0
    tau = np.hypot(r.friction[..., 0], r.friction[..., 1])
    ratio = tau / (np.asarray(mu_s) * r.N)
    return float(np.max(ratio[stuck]))


def test_break_away_after_a_re_stick_at_the_same_instant_is_not_missed():
    # A mass on a flat slider with a laminated rubber spring (0.5 Hz, 5 % damping) under an
    # elliptical orbit, starting stuck just inside its disc: at the located break-away the
    # slip must begin (direction of the stick force) and the mass may stick again only with
    # its force inside the disc.
    m = 1000.0
    k = m * (2 * math.pi * 0.5) ** 2
    c = 2 * 0.05 * math.sqrt(k * m)
    s = sdof_plane(m, Bearing(Friction(0.05), k_lam=k, c=c), g=G)
    o = HarmonicPlane.elliptical(0.45, 0.8, 0.4, 30.0)
    r = simulate_plane(s, o, law="switch", y0=[-2e-5, 0, 0, 0, 0, 0], t_end=1 / 0.45,
                       dt_out=0.01, rtol=1e-10, atol=(1e-12, 1e-12))  # fmt: skip
    assert kr.STICK_RTOL < SLACK
    assert _worst_stuck_ratio(r, 0.05) <= 1.0 + SLACK
    # the orbit's demand exceeds the disc (|τ| reaches 1.6 μ N stuck): it must slip at all
    assert np.any(r.modes == 1)


def test_stuck_isolators_stay_inside_their_disc_under_random_orbits():
    # Seeded random SDOFs and orbits (frequency, semi-axes, angle, sense, static above kinetic
    # friction, a small initial offset); the disc condition at every stuck sample.
    rng = np.random.default_rng(20261128)
    for _ in range(6):
        m = 1000.0
        fn = rng.uniform(0.3, 0.8)
        k = m * (2 * math.pi * fn) ** 2
        c = 2 * rng.uniform(0.0, 0.1) * math.sqrt(k * m)
        mu = rng.uniform(0.03, 0.08)
        mu_s = mu * rng.uniform(1.0, 1.3)
        s = sdof_plane(m, Bearing(Friction(mu, mu_static=mu_s), k_lam=k, c=c), g=G)
        f = rng.uniform(0.3, 1.0)
        A = mu_s * G * rng.uniform(0.8, 2.0)
        o = HarmonicPlane.elliptical(f, A, A * rng.uniform(0.1, 1.0), rng.uniform(0, 180),
                                     int(rng.choice([-1, 1])))  # fmt: skip
        y0 = [*(1e-4 * rng.standard_normal(2)), 0, 0, 0, 0]
        r = simulate_plane(s, o, law="switch", y0=y0, t_end=2 / f, dt_out=0.01, rtol=1e-9,
                           atol=(1e-11, 1e-11))  # fmt: skip
        assert _worst_stuck_ratio(r, mu_s) <= 1.0 + SLACK, (fn, mu, mu_s, f, A)


def test_deck_isolators_released_together_stay_inside_their_discs():
    # A deck on four flat sliders with rubber springs, eccentric mass (torsion), under an
    # elliptical orbit strong enough to release several isolators together.
    m = 4.0e4
    pos = [(-4.0, -3.0), (4.0, -3.0), (4.0, 3.0), (-4.0, 3.0)]
    k = m / 4 * (2 * math.pi * 0.5) ** 2
    b = Bearing(Friction(0.05, mu_static=0.06), k_lam=k, c=0.05 * 2 * math.sqrt(k * m / 4))
    d = rigid_deck(m, m * 8.0, pos, b, ecc=(0.5, -0.3), g=G)
    o = HarmonicPlane.elliptical(0.5, 1.0, 0.6, 20.0)
    r = simulate_plane(d, o, law="switch", t_end=4.0, dt_out=0.01, rtol=1e-9,
                       atol=(1e-11, 1e-11))  # fmt: skip
    assert np.any(r.modes == 1)
    assert _worst_stuck_ratio(r, 0.06) <= 1.0 + SLACK


def test_a_deck_whose_static_friction_is_its_kinetic_one_keeps_every_disc():
    # Four friction pendulums (R = 2.2 m, mu = mu_s = 0.05: Friction(0.05), the plainest
    # Coulomb input) under a centred deck 1.5 m above them, the bundled record: at a break-
    # away three isolators reached their rims together and started to slip; their directions,
    # aligned with the deck turning about the fourth, loaded that one to |tau| = 4 mu N while
    # it stayed stuck (the summary reported that force as the peak friction)
    from nsdyn.ground import read_motion3

    d = rigid_deck(2.0e6, 9.07e7, [(-10.0, -6.0), (10.0, -6.0), (10.0, 6.0), (-10.0, 6.0)],
                   Bearing(Friction(0.05), radius=2.2), h=1.5)  # fmt: skip
    r = simulate_plane(d, read_motion3("synthetic-wn-40s"), law="switch", t_end=10.0)
    assert np.any(r.modes == 1) and np.any(r.modes == 0)
    assert _worst_stuck_ratio(r, 0.05) <= 1.0 + SLACK
    f = np.hypot(r.friction[..., 0], r.friction[..., 1])
    assert np.max(f / (0.05 * r.N)) <= 1.0 + SLACK  # (slip or stick: Coulomb's bound)


def test_a_stick_band_far_too_narrow_is_reported_with_time_and_reason():
    # eta = 1e-12 m/s: a slip velocity passing near zero is never caught in the band, its
    # direction v/|v| turns within a step and the steps collapse; the run must stop and say
    # so (the failure is numerical, not physical: eta = 1e-5 runs the same case in hundreds
    # of steps).
    s = sdof_plane(1000.0, Bearing(Friction(0.1, mu_static=0.12), radius=2.0), g=G)
    o = HarmonicPlane.elliptical(0.5, 1.3, 0.5, 30.0)
    with pytest.raises(PlaneIntegrationError, match=r"collapsed before t = .* eta = 1e-12"):
        simulate_plane(s, o, law="switch", eta=1e-12, t_end=8.0)


@pytest.mark.parametrize("law", ["switch", "arctan"])
def test_a_brief_rim_contact_inside_a_step_is_located(law):
    # A pendulum (R = 2 m) swings out from its centre (initial speed along x, no ground motion):
    # until the rim is touched the motion does not depend on the capacity, so the run without
    # a rim, sampled on a 1 µs grid around its peak, gives the first time |u| reaches d_cap.
    # With d_cap 10 nm below the peak the contact lasts ~ 2 sqrt(2 * 1e-8 / a_peak) ~ 0.4 ms,
    # far shorter than the largest step allowed here (0.2 s) and the output step (0.5 s). The
    # contact must be reported at that time. Tolerance: the reference grid (1e-6 s) plus the
    # runs' position error (~ rtol |u| ~ 1e-10 m) over the speed there (~ 1e-4 m/s).
    mu, R = 0.02, 2.0
    fric = Friction(mu)
    o = HarmonicPlane.linear(0.5, 0.0)
    y0 = [0.0, 0.0, 0, 0.3, 0.0, 0]
    kw = dict(law=law, y0=y0, rtol=1e-9, atol=(1e-11, 1e-11))
    free = sdof_plane(1000.0, Bearing(fric, radius=R), g=G)
    ref = simulate_plane(free, o, t_end=4.0, dt_out=1e-3, **kw)
    tp = ref.t[int(np.argmax(np.hypot(ref.u[:, 0, 0], ref.u[:, 0, 1])))]
    ref = simulate_plane(free, o, t_eval=np.concatenate([[0.0], tp - 5e-3 + 1e-6 * np.arange(
        10001)]), **kw)  # fmt: skip
    r_u = np.hypot(ref.u[:, 0, 0], ref.u[:, 0, 1])
    d_cap = r_u.max() - 1e-8
    t_c = ref.t[int(np.argmax(r_u > d_cap))]
    s = sdof_plane(1000.0, Bearing(fric, radius=R, d_cap=d_cap), g=G)
    with pytest.warns(UserWarning, match="displacement capacity"):
        r = simulate_plane(s, o, t_end=4.0, dt_out=0.5, max_step=0.2, **kw)
    assert len(r.stops) == 1
    assert abs(r.stops[0]["t_first_s"] - t_c) <= 3e-6
