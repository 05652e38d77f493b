"""Pressure-dependent friction of a bidirectional isolator against its formula.

Source: the pressure factor of PTFE-type composites on polished steel, μ(p) = μ(p_ref) ·
0.7^((p − p_ref)/50 MPa) (Kumar, Whittaker & Constantinou 2015, "Characterizing friction in
sliding isolation bearings", Earthquake Engng Struct. Dyn. 44(9)), friction decreasing as the
contact pressure p = N/A rises (Mokha, Constantinou & Reinhorn 1990; Constantinou et al. 1990).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from nsdyn.models.isolated.bearings import Bearing, BearingError, Friction, bearing_from_config
from nsdyn.models.isolated.deck import sdof_plane, simulate_plane

G = 9.81
AREA, P_REF = 1.2e-4, 40.0e6  # m^2, Pa: 41 MPa at rest for 500 kg
LN = math.log(0.7) / (AREA * 50.0e6)  # d ln k_p / dN [1/N]


def k_p(N):
    return 0.7 ** ((np.asarray(N) / AREA - P_REF) / 50.0e6)


@pytest.mark.parametrize("law", ["switch", "arctan"])
def test_friction_follows_the_pressure_factor_along_a_ramp_of_the_normal_force(law):
    # A flat slider under a constant ground acceleration A (sliding all along) and a vertical
    # ramp a_z = k t: N = m (g + k t) rises from m g to 1.8 m g (41 -> 74 MPa), and the
    # friction read from the motion, f = m (A - v') (v' by central differences of the output
    # velocity), follows mu k_p(N) N (arctan law: times (2/pi) arctan(eps v)). Bound: the
    # central difference's dt^2/6 |v'''|, m v''' = -d^2/dt^2 [P a(v)], P = mu k_p(N) N with
    # P'' = mu Ndot^2 k_p (2 c + c^2 N), c = ln 0.7 / (50 MPa A), and the arctan factor's
    # own derivatives.
    m, mu = 500.0, 0.10
    b = Bearing(Friction(mu, mu_static=0.12), area=AREA, p_ref=P_REF)
    s = sdof_plane(m, b, g=G)
    dt, n = 2.5e-4, 8001
    t = dt * np.arange(n)
    A, k = 0.25 * G, 0.4 * G  # (k t reaches 0.8 g at 2 s)
    ax = np.full(n, A)
    ax[0] = 0.0
    r = simulate_plane(s, (0.0, dt, ax, np.zeros(n), k * t), law=law, rtol=1e-11,
                       atol=(1e-13, 1e-13))  # fmt: skip
    N = m * (G + k * r.t)
    np.testing.assert_allclose(r.N[:, 0], N, rtol=1e-12)
    v = -r.v[:, 0, 0]
    assert v[-1] > 0.5
    acc = (v[2:] - v[:-2]) / (2 * dt)
    f_motion = m * (A - acc)
    Nc, vc, eps = N[1:-1], v[1:-1], 7500.0
    # f = P(t) a(v): P = mu k_p(N) N, a = (2/pi) arctan(eps v) (arctan law) or 1 (switch)
    P = mu * k_p(Nc) * Nc
    P1 = mu * m * k * k_p(Nc) * (1 + LN * Nc)
    P2 = mu * (m * k) ** 2 * k_p(Nc) * (2 * LN + LN**2 * Nc)
    if law == "arctan":
        a = (2 / math.pi) * np.arctan(eps * vc)
        a1 = (2 / math.pi) * eps / (1 + (eps * vc) ** 2)
        a2 = -(2 / math.pi) * 2 * eps**3 * vc / (1 + (eps * vc) ** 2) ** 2
    else:
        a, a1, a2 = np.ones_like(vc), 0.0 * vc, 0.0 * vc
    ref = P * a
    v1 = A - ref / m
    v2 = -(P1 * a + P * a1 * v1) / m
    v3 = (np.abs(P2 * a) + 2 * np.abs(P1 * a1 * v1)
          + np.abs(P) * (np.abs(a2) * v1**2 + np.abs(a1 * v2))) / m  # fmt: skip
    ok = vc > 0.05
    bound = 1.05 * m * dt**2 / 6 * v3 + 1e-6  # (leading term; the next adds well under 5 %)
    assert np.all(np.abs(f_motion - ref)[ok] <= bound[ok])
    # the factor did matter: k_p fell by a fifth along the ramp
    assert k_p(N[-1]) < 0.8 * k_p(N[0])


def test_stick_disc_shrinks_with_the_pressure_factor():
    # Switch law: a block held by its stick disc mu_s k_p(N) N breaks away when the ground
    # acceleration a_x = c t reaches mu_s k_p(m g / A) g (N = m g constant): at
    # t* = mu_s k_p g / c, to the output step.
    m, mu, mu_s, c, p_ref = 500.0, 0.10, 0.12, 0.5, 20.0e6  # (41 MPa at rest: k_p = 0.86)
    s = sdof_plane(m, Bearing(Friction(mu, mu_static=mu_s), area=AREA, p_ref=p_ref), g=G)
    dt = 1e-3
    t = np.arange(0.0, 4.0 + dt / 2, dt)
    r = simulate_plane(s, (0.0, dt, c * t, 0 * t, None), law="switch", rtol=1e-10,
                       atol=(1e-12, 1e-12))  # fmt: skip
    t_star = mu_s * 0.7 ** ((m * G / AREA - p_ref) / 50.0e6) * G / c
    moving = np.flatnonzero(r.modes[:, 0] != 0)
    assert moving.size and r.t[moving[0]] == pytest.approx(t_star, abs=1.01 * dt)
    assert abs(t_star - mu_s * G / c) > 20 * dt  # (without the factor it would differ)


def test_pressure_keys_come_in_pairs_and_are_positive():
    with pytest.raises(BearingError, match=r"^bearing\.p_ref: missing; pressure-dependent"):
        Bearing(Friction(0.05), radius=2.0, area=0.1)
    with pytest.raises(BearingError, match=r"^b\.area: expected a positive number"):
        bearing_from_config({"type": "fps", "radius": 2.0, "mu": 0.05, "area": -1.0,
                             "p_ref": 3e7}, "b")  # fmt: skip
    b = bearing_from_config({"type": "fps", "radius": 2.0, "mu": 0.05, "area": 0.1,
                             "p_ref": 3e7}, "b")  # fmt: skip
    np.testing.assert_allclose(b.pressure_factor([3e6, 8e6]), [1.0, 0.7], rtol=1e-14)
