"""Coulomb sliding of the cylinder's base: stick, slip, closed-form sliding, energy.

Independent sources: Coulomb's law for a body on a rigid-stiff base under a horizontal ground
acceleration a_g (quasi-static rocking): the base sticks while m a_g ≤ μ N = μ m g, and once it
slides the relative acceleration is −(a_g − μg) along a_g, exactly (horizontal momentum:
m a_c,h = μ N, with the rocking at rest); the work–energy balance with friction dissipation
E(t) − E(0) = W_ground − E_dampers − E_friction; a friction coefficient that is never reached
gives the restrained model (the source study's base).
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from nsdyn.models.cylinder.design import design_foundation
from nsdyn.models.cylinder.params import CylinderParams
from nsdyn.models.cylinder.scene import build
from nsdyn.models.cylinder.simulate import earthquake, simulate
from nsdyn.models.scenefile import SceneError

MU = 0.05  # friction coefficient of the ramp tests
AZ = 0.5  # azimuth of the ramp's horizontal acceleration [rad]
T_RAMP, T_END, DT = 2.0, 3.0, 1e-3  # ramp of a_g to its final value, then hold [s]


def _stiff(mu: float = MU) -> CylinderParams:
    """A rigid-stiff foundation (30 Hz rocking, 20 % damping): tilt ~ 1e-6 rad under μg."""
    k, c = design_foundation(30.0, 0.2, 1.0, 4.0, 1.0)
    return CylinderParams(k=k, c=c, mu=mu)


def _ramp(a_final: float) -> np.ndarray:
    t = np.arange(0.0, T_END + DT / 2, DT)
    a = a_final * np.minimum(t / T_RAMP, 1.0)
    return np.stack([a * math.cos(AZ), a * math.sin(AZ), 0.0 * a], axis=1)


def test_sticks_below_mu_g():
    p = _stiff()
    res = simulate(p, _ramp(0.9 * MU * p.g), DT, rtol=1e-9)
    assert res.stats["slip_starts"] == 0
    assert np.max(np.abs(res.u)) == 0.0 and np.max(np.abs(res.ud)) == 0.0
    f = np.hypot(*res.f_base.T)
    assert np.all(f <= MU * res.F)  # the stick force stays inside the friction cone
    assert f[-1] == pytest.approx(0.9 * MU * p.m * p.g, rel=1e-3)  # = m a_g at rest


def test_slides_above_mu_g_with_closed_form_acceleration():
    p = _stiff()
    a_f = 1.5 * MU * p.g
    res = simulate(p, _ramp(a_f), DT, rtol=1e-9)
    # onset where m a_g(t) = μ m g, within one sample (quasi-static ramp)
    t_on = res.t[np.argmax(res.slip > 0)]
    assert abs(t_on - T_RAMP * MU * p.g / a_f) <= 1.5 * DT
    e = np.array([math.cos(AZ), math.sin(AZ)])
    sel = res.t > T_RAMP + 0.2  # acceleration held constant, rocking transients damped
    slope = np.polyfit(res.t[sel], res.ud[sel] @ e, 1)[0]
    assert slope == pytest.approx(-(a_f - MU * p.g), rel=1e-6)
    # the slip follows the load's direction: no sideways drift
    assert np.max(np.abs(res.u @ np.array([-e[1], e[0]]))) < 1e-9 * res.slip.max()
    assert np.hypot(*res.f_base[-1]) == pytest.approx(MU * res.F[-1], rel=1e-12)
    assert res.energy_error < 1e-8 and res.E_f[-1] > 0


@pytest.mark.parametrize("foundation", ["tensionless", "bonded"])
def test_energy_closes_with_friction_dissipation(foundation):
    dt, ag = earthquake(2, duration=10.0)
    res = simulate(CylinderParams(foundation=foundation, mu=0.15), ag, dt, rtol=1e-8)
    assert res.stats["slip_starts"] >= 3  # stick–slip sequences, not one long slide
    assert res.slip.max() > 1e-3 and res.E_f[-1] > 0.05 * res.E_d[-1]
    assert np.all(np.diff(res.E_f) >= -1e-15)  # friction only dissipates
    assert res.energy_error < 1e-6


def test_friction_never_reached_equals_restrained_base():
    dt, ag = earthquake(2, duration=6.0)
    r0 = simulate(CylinderParams(), ag, dt, rtol=1e-10)
    r1 = simulate(CylinderParams(mu=50.0), ag, dt, rtol=1e-10)
    assert r1.stats["slip_starts"] == 0 and np.max(np.abs(r1.u)) == 0.0
    np.testing.assert_allclose(r1.q, r0.q, rtol=0, atol=1e-8)
    np.testing.assert_allclose(r1.f_base, r0.base_shear, rtol=0, atol=1e-8)


def test_bad_friction_input():
    with pytest.raises(ValueError, match="^mu:"):
        CylinderParams(mu=-0.1)
    with pytest.raises(ValueError, match="fixed base cannot slide"):
        CylinderParams(foundation="fixed", mu=0.3)
    cfg = {"scene": {"kind": "cylinder"}, "foundation": {"sliding": True}}
    with pytest.raises(SceneError, match="foundation.mu: missing"):
        build(cfg, "s.toml")
    bad = copy.deepcopy(cfg)
    bad["foundation"] = {"mu": 0.3}
    with pytest.raises(SceneError, match="sliding = true only"):
        build(bad, "s.toml")
    ok = {"scene": {"kind": "cylinder"}, "foundation": {"sliding": True, "mu": 0.3}}
    assert build(ok, "s.toml")[0].mu == 0.3
