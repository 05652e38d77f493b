"""Single friction pendulum and velocity-dependent friction against their closed forms.

Sources: the friction pendulum's restoring force N u / R (Zayas, Low & Mahin 1990; Constantinou
et al., MCEER reports): with mu = 0 an undamped oscillator of period 2 pi sqrt(R/g) whatever the
mass; Coulomb friction dissipating mu W per unit slip, 4 mu W D per cycle of amplitude D; the
PTFE/steel law mu(v) = mu_fast - (mu_fast - mu_slow) exp(-a |v|) (Constantinou, Mokha &
Reinhorn 1990).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from nsdyn.models.isolated.bearings import Bearing, BearingError, Friction
from nsdyn.models.isolated.deck import rigid_deck, sdof_plane, simulate_plane

G = 9.81


def _trapezoid(y, x):
    """The trapezoidal rule (numpy < 2 has no np.trapezoid)."""
    y, x = np.asarray(y), np.asarray(x)
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))


def _quiet(T, dt=0.01):
    n = int(round(T / dt)) + 1
    return (0.0, dt, np.zeros(n), np.zeros(n), None)


@pytest.mark.parametrize("m", [100.0, 1.0e5])
def test_pendulum_period_is_2pi_sqrt_R_over_g_whatever_the_mass(m):
    # mu = 0: m u'' = -N u / R with N = m g, so u'' = -(g/R) u: the period 2 pi sqrt(R/g)
    # does not depend on m. Released from u0 along x with the tangential speed w u0 along y the
    # orbit is a circle of radius u0 (a conical pendulum). Tolerance: rtol 1e-10 runs.
    R, u0 = 2.5, 0.1
    w = math.sqrt(G / R)
    s = sdof_plane(m, Bearing(Friction(0.0), radius=R), g=G)
    T = 2 * math.pi / w
    r = simulate_plane(s, _quiet(3 * T, T / 4000), y0=[u0, 0, 0, 0, w * u0, 0], rtol=1e-11,
                       atol=(1e-13, 1e-13))  # fmt: skip
    u = r.u[:, 0]
    np.testing.assert_allclose(np.hypot(u[:, 0], u[:, 1]), u0, rtol=1e-8)
    ang = np.unwrap(np.arctan2(u[:, 1], u[:, 0]))
    np.testing.assert_allclose(ang, w * r.t, atol=1e-7)  # one turn per 2 pi sqrt(R/g)
    # and a plane swing from rest: zero crossings of u_x half a period apart
    r = simulate_plane(s, _quiet(3 * T, T / 4000), y0=[u0, 0, 0, 0, 0, 0], rtol=1e-11,
                       atol=(1e-13, 1e-13))  # fmt: skip
    x = r.u[:, 0, 0]
    k = np.flatnonzero((x[:-1] > 0) & (x[1:] <= 0))
    tc = r.t[k] - x[k] * (r.t[k + 1] - r.t[k]) / (x[k + 1] - x[k])
    np.testing.assert_allclose(np.diff(tc), T, rtol=1e-6)  # linear interpolation of crossings


def test_energy_dissipated_per_cycle_is_4_mu_W_D():
    # One-direction harmonic shaking of a friction pendulum: slip runs between reversal points
    # and friction resists with mu W all along it, so a cycle with strokes D1 + D2 (reversal to
    # reversal and back) dissipates mu W (D1 + D2) = 4 mu W D with D = (D1 + D2)/4, the
    # amplitude (D1 = D2 = 2D for a cycle centred on its mean; the centre of a friction
    # pendulum's forced cycle may creep within its stick range +-mu R, so the strokes are
    # measured). The pendulum's restoring force N u / R (N = W) is conservative: its loop
    # encloses nothing. Tolerance: trapezoid rule over 4000 outputs per cycle.
    m, R, mu, f = 2000.0, 2.0, 0.06, 1.0
    s = sdof_plane(m, Bearing(Friction(mu), radius=R), g=G)
    T = 1.0 / f
    r = simulate_plane(s, {"f": f, "ax": 3.0, "ay": 0.0}, t_end=15 * T, dt_out=T / 4000,
                       rtol=1e-10, atol=(1e-12, 1e-12))  # fmt: skip
    vx = r.v[:, 0, 0]
    rev = np.flatnonzero(np.sign(vx[1:]) * np.sign(vx[:-1]) < 0)  # reversals of the slip
    k0, k2 = rev[-3], rev[-1] + 1  # the last full cycle: reversal, reversal, reversal
    ux = r.u[k0:k2, 0, 0]
    strokes = np.abs(np.diff(r.u[rev[-3:], 0, 0]))
    D = strokes.sum() / 4
    assert D > 0.05 and abs(strokes[0] - strokes[1]) < 0.05 * strokes.sum()
    W = m * G
    area = _trapezoid(r.friction[k0:k2, 0, 0], ux)
    assert area == pytest.approx(4 * mu * W * D, rel=2e-4)
    # conservative: the loop integral is the potential energy change W (u1^2 - u0^2) / (2R)
    dV = W * (ux[-1] ** 2 - ux[0] ** 2) / (2 * R)
    assert _trapezoid(r.restoring[k0:k2, 0, 0], ux) == pytest.approx(dV, abs=1e-6 * area)
    assert np.abs(r.u[:, 0, 1]).max() == 0.0  # no excitation across, no slip across


@pytest.mark.parametrize("law", ["switch", "arctan"])
def test_velocity_dependent_friction_follows_its_law_along_a_velocity_ramp(law):
    # A flat slider under a constant ground acceleration A > mu_fast g slides with a growing
    # speed (a ramp from 0 to ~1 m/s). Friction read from the motion, f = -m (A + u''), with u''
    # by central differences of the output velocity, follows mu(v) m g,
    # mu(v) = mu_fast - (mu_fast - mu_slow) exp(-a v), and the switch law breaks away at
    # mu_s m g: the block holds until A exceeds mu_s g.
    m, mu_slow, mu_fast, rate, mu_s = 500.0, 0.04, 0.12, 15.0, 0.15
    fr = Friction(mu_slow, mu_fast=mu_fast, rate=rate, mu_static=mu_s)
    s = sdof_plane(m, Bearing(fr), g=G)
    dt = 2.5e-4
    n = 8001
    A = 0.2 * G
    ax = np.full(n, A)
    ax[0] = 0.0
    r = simulate_plane(s, (0.0, dt, ax, np.zeros(n), None), law=law, rtol=1e-11,
                       atol=(1e-13, 1e-13))  # fmt: skip
    v = -r.v[:, 0, 0]  # slides towards -x
    assert v[-1] > 0.5
    acc = (v[2:] - v[:-2]) / (2 * dt)
    f_motion = m * (A - acc)
    mu_v = mu_fast - (mu_fast - mu_slow) * np.exp(-rate * v[1:-1])
    ok = v[1:-1] > 0.05  # sliding (and past the arctan law's creep range)
    if law == "arctan":
        mu_v = mu_v * (2 / math.pi) * np.arctan(7500.0 * v[1:-1])
    # central difference error dt^2/6 |v'''|, v' = A - mu(v) g: |v'''| = |mu'' g v'^2 + mu' g v''|
    # <= g (|mu''| v'^2 + |mu'| g |mu'| v') (regularised law: its own terms, tiny above 0.05 m/s)
    vv, a1 = v[1:-1], A - mu_v * G
    mu1 = (mu_fast - mu_slow) * rate * np.exp(-rate * vv)
    # (leading term; the next, O(dt^4), adds well under 5 % at this dt)
    bound = 1.05 * m * dt**2 / 6 * G * (rate * mu1 * a1**2 + mu1**2 * G * a1) + 1e-6
    assert np.all(np.abs(f_motion - mu_v * m * G)[ok] <= bound[ok])


def test_friction_pendulum_deck_has_no_torsion_from_an_eccentric_mass():
    # Friction pendulums carry horizontal forces proportional to their normal forces (N u/R
    # and mu N): with the rigid-plate normal forces, whose resultant passes through the centre
    # of mass, their resultant acts there too, so an eccentric deck on identical pendulums
    # translates without twisting (h = 0, regularised law: the same slip at every isolator is
    # a solution). Flat sliders on rubber resist at the isolators' centroid: the same deck twists.
    pos = [(-4.0, -3.0), (4.0, -3.0), (4.0, 3.0), (-4.0, 3.0)]
    dt = 0.01
    t = np.arange(0.0, 8.0 + dt / 2, dt)
    ax = 2.5 * np.sin(2 * np.pi * 0.6 * t) * np.sin(np.pi * t / 8.0) ** 2
    ay = 1.8 * np.sin(2 * np.pi * 0.9 * t + 1.0) * np.sin(np.pi * t / 8.0) ** 2
    rec = (0.0, dt, ax, ay, None)
    fps = Bearing(Friction(0.05), radius=2.0)
    flat = Bearing(Friction(0.05), k_lam=2.0e4, c=0.0)
    kw = dict(m=4.0e4, J=4.0e4 * (64 + 36) / 12, positions=pos, ecc=(1.2, -0.8), g=G)
    r1 = simulate_plane(rigid_deck(bearings=fps, **kw), rec, law="arctan")
    r2 = simulate_plane(rigid_deck(bearings=flat, **kw), rec, law="arctan")
    peak = r1.summary()["peak_resultant_displacement_m"]
    assert peak > 0.02
    assert np.abs(r1.theta).max() * 5.0 < 1e-9 * peak  # round-off only
    assert np.abs(r2.theta).max() * 5.0 > 1e-2 * r2.summary()["peak_resultant_displacement_m"]


def test_capacity_below_the_pendulums_stick_range_is_refused():
    # a pendulum at rest anywhere with |u| <= mu_s R (N u/R <= mu_s N): a capacity inside that
    # range would leave the bearing resting on its rim; refused when the bearing is made (a
    # design checked with Bearing(...) alone passed, the refusal came at its run)
    with pytest.raises(BearingError, match=r"bearing.d_cap: .*mu_s R"):
        Bearing(Friction(0.05), radius=2.0, d_cap=0.08)
    # a coefficient given as a percentage (4 for 4 %) ends here first: the refusal says so
    with pytest.raises(BearingError, match=r"mu_s R = 8 m .*mu_s = 4: a friction coefficient "
                       r"above 1 .*a percentage given as a number\?\)$"):  # fmt: skip
        sdof_plane(1000.0, Bearing(Friction(4.0), radius=2.0, d_cap=0.35))
    # and a radius in mm (2200 for 2.2 m): 0.075 x 2200 = 165 m past any rim; the radius is
    # the field named (d_cap was)
    with pytest.raises(BearingError, match=r"^bearing.radius: R = 2200 m is above the 20 m of "
                       r"built pendulums \(in cm or mm\?\): its stick range mu_s R = 165 m passes "
                       r"the capacity d_cap = 0.35 m; expected R in m$"):  # fmt: skip
        sdof_plane(1000.0, Bearing(Friction(0.075), radius=2200.0, d_cap=0.35))
    with pytest.raises(BearingError, match=r"bearing.d_cap: expected a positive number"):
        Bearing(Friction(0.05), radius=2.0, d_cap=0.0)


@pytest.mark.parametrize("key", ["k_stop", "c_stop"])
def test_a_rim_stop_without_a_capacity_is_refused(key):
    # the rim acts beyond d_cap; without one its stiffness or damping did nothing
    with pytest.raises(BearingError, match=rf"^bearing\.{key}: the rim stop acts beyond"):
        Bearing(Friction(0.05), radius=2.0, **{key: 1e9})
