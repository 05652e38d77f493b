"""Overturning spectra by bisection against Housner's rectangular-pulse criterion, and the
compliant-support block's effective restitution against Housner's as the ground stiffens."""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from nsdyn.models.rocking import RockingBlock, simulate_rocking
from nsdyn.models.rocking.block import housner_restitution
from nsdyn.models.rocking.compliant import CompliantBlock, effective_restitution
from nsdyn.models.rocking.spectra import overturning_spectrum


def test_spectrum_rectangular_pulse_matches_housner_closed_form():
    """Linearised block, rectangular pulse of duration T_p = 2 pi / omega_p: minimum
    overturning a / (g alpha) = 1 / (1 - exp(-2 pi p / omega_p)) (Housner 1963)."""
    blk = RockingBlock(width=0.4, height=2.0, linear=True)
    x = np.array([0.5, 2.0, 6.0])
    with ThreadPoolExecutor(1) as ex:
        sp = overturning_spectrum(blk, x, shape="rect", rtol=1e-5, executor=ex)
    expected = 1.0 / (1.0 - np.exp(-2 * np.pi / x))
    np.testing.assert_allclose(sp.a_min_ratio, expected, rtol=3e-5)
    assert np.all(sp.mode == 2)  # overturns on the first excursion, no impact


def test_spectrum_one_sine_has_impact_mode_and_grows_with_frequency():
    """One-sine pulse (Zhang & Makris 2001): at low omega_p / p the block overturns after an
    impact (mode 1) just above lift-off, and the minimum amplitude grows with frequency."""
    blk = RockingBlock(width=0.3, height=1.2)
    with ThreadPoolExecutor(1) as ex:
        sp = overturning_spectrum(blk, [1.5, 3.0, 6.0], executor=ex)
    assert sp.mode[0] == 1
    assert np.all(np.diff(sp.a_min_ratio) > 0) and sp.a_min_ratio[0] > 1.0


@pytest.mark.parametrize("zeta", [2.0])
def test_compliant_effective_restitution_approaches_housner(zeta):
    """Seed 001 model 1 (cask 2 m x 4 m, 124.8 t on spring-damper corners): r_eff from free
    rocking tends to Housner's 1 - 1.5 sin² alpha = 0.700 (seed Table 2: 0.700) as the
    contact frequency omega_v / p grows; soft ground dissipates more."""
    B, H, m = 1.0, 2.0, 124800.0
    r_h = housner_restitution(math.atan2(B, H))
    p = RockingBlock(B=B, H=H).p
    err = {}
    for ratio in (10.0, 30.0, 300.0, 1000.0):
        blk = CompliantBlock.from_frequency(B=B, H=H, mass=m, omega_v=ratio * p, zeta=zeta)
        err[ratio] = effective_restitution(blk) - r_h
    assert err[10.0] < -0.05 and err[30.0] < -0.01
    assert abs(err[300.0]) < 1e-3 and abs(err[1000.0]) < 1e-3


def test_compliant_stiff_ground_follows_rigid_block_history():
    """Stiff, well damped supports: the first impact time of free rocking equals Housner's
    rigid block's to within the contact time scale."""
    from nsdyn.models.rocking.compliant import simulate_compliant

    B, H = 1.0, 2.0
    rigid = RockingBlock(B=B, H=H)
    blk = CompliantBlock.from_frequency(B=B, H=H, mass=1000.0, omega_v=1000 * rigid.p, zeta=2.0)
    r = simulate_compliant(blk, t_end=1.5, theta0=0.5 * rigid.alpha, dt_out=1e-4)
    t_cross = r.t[np.argmax(r.theta < 0)]
    t_ref = simulate_rocking(rigid, t_end=1.5, theta0=0.5 * rigid.alpha).impacts[0, 0]
    assert abs(t_cross - t_ref) < 10.0 / blk.omega_v
