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


def test_a_run_too_long_for_its_contact_or_outputs_is_refused(monkeypatch):
    # the compliant block steps at about 1/omega_v in contact (the rate its explicit stability
    # and error control set): a contact of 1e8 rad/s over 2 s is 2e8 steps, hours of
    # stepping that no signal could stop; and an error control that collapses the steps
    # further (a contact of ~3e9 rad/s: steps of ~1e-12 s) spends the step budget
    import nsdyn.models.rocking.compliant as cm
    from nsdyn._checks import NumericalFailure

    stiff = CompliantBlock.from_frequency(width=0.3, height=1.2, mass=100.0, omega_v=1e8,
                                          zeta=0.1)  # fmt: skip
    with pytest.raises(ValueError, match=r"^omega_v: a contact of 1e\+08 rad/s damped at zeta "):
        cm.simulate_compliant(stiff, t_end=2.0, theta0_over_alpha=0.5)
    # a soft contact damped a million times critically steps as finely (1 + 2 zeta), and a
    # largest step given that fine is named as such
    damped = CompliantBlock.from_frequency(width=0.3, height=1.2, mass=100.0, omega_v=300.0,
                                           zeta=1e6)  # fmt: skip
    with pytest.raises(
        ValueError, match=r"^omega_v: a contact of 300 rad/s damped at zeta = 1e\+06"
    ):
        cm.simulate_compliant(damped, t_end=2.0, theta0_over_alpha=0.5)
    with pytest.raises(ValueError, match=r"^h_max: a largest step of 1e-09 s takes 2e\+09 "):
        cm.simulate_compliant(stiff, t_end=2.0, theta0_over_alpha=0.5, h_max=1e-9)
    with pytest.raises(ValueError, match=r"^zeta: a damping ratio of 2 on a 1e\+300 kg block"):
        CompliantBlock.from_frequency(width=0.3, height=1.2, mass=1e300, omega_v=300.0, zeta=2.0)
    monkeypatch.setattr(cm, "STEP_BUDGET", 1000)  # ~840 steps of 1/omega_v, far more taken
    harder = CompliantBlock.from_frequency(width=0.3, height=1.2, mass=100.0, omega_v=3.5e9,
                                           zeta=0.1)  # fmt: skip
    with pytest.raises(NumericalFailure, match=r"1e\+03 step attempts spent"):
        cm.simulate_compliant(harder, t_end=2e-7, theta0_over_alpha=0.5, dt_out=1e-7)
    block = RockingBlock(width=0.3, height=1.2)
    with pytest.raises(ValueError, match=r"^dt_out: 1e\+12 outputs of 1e-12 s"):
        simulate_rocking(block, None, t_end=1.0, theta0=0.1, dt_out=1e-12)
    for kw in ({"theta0": 100.0}, {"theta0_over_alpha": 10.0}):  # 10 alpha = 2.45 rad
        with pytest.raises(ValueError, match=r"lays the body on its side or beyond"):
            simulate_rocking(block, None, t_end=1.0, **kw)


def test_compliant_block_past_its_balance_overturns_and_the_run_ends_there():
    """Released at theta0 = 1.2 alpha (past the balance point alpha) on stiff supports the
    block falls about its corner, theta'^2 = 2 p^2 (cos(theta0 - alpha) - cos(theta -
    alpha)) (energy; p^2 = 3 g / 4R), and reaches pi/2 at T = integral of d theta / theta'
    from theta0 to pi/2 (theta = theta0 + u^2 removes the endpoint singularity). The stiff
    supports shift the pivot by the corner's settlement g / omega_v^2 = 3e-6 m against R =
    2.24 m: ~1e-6 of T (1.76 s), asserted at 1e-4 s with the integrator's tolerance. The run
    ends there: no output past pi/2 (the supports alone let a block tumble on through the
    ground, to 4.3 rad), overturned with its time in the summary, its peak pi/2 on any
    output grid."""
    from scipy.integrate import quad

    from nsdyn.models.rocking.compliant import simulate_compliant

    B, H = 1.0, 2.0
    rigid = RockingBlock(B=B, H=H)
    al, p = rigid.alpha, rigid.p
    blk = CompliantBlock.from_frequency(B=B, H=H, mass=1000.0, omega_v=1000 * p, zeta=2.0)
    th0 = 1.2 * al
    u_end = math.sqrt(math.pi / 2 - th0)
    T, _ = quad(lambda u: 2 * u / math.sqrt(2 * p**2 * (math.cos(th0 - al)
                                                        - math.cos(th0 + u * u - al))),
                0.0, u_end, epsabs=1e-12)  # fmt: skip
    r = simulate_compliant(blk, t_end=3.0 * T, theta0=th0, dt_out=1e-3)
    assert abs(r.t_overturn - T) < 1e-4
    assert r.t[-1] <= r.t_overturn and np.abs(r.theta).max() < math.pi / 2
    s = r.summary()
    assert s["overturned"] and s["t_overturn_s"] == r.t_overturn and s["outcome"] == "overturned"
    coarse = simulate_compliant(blk, t_end=3.0 * T, theta0=th0, dt_out=0.5)
    assert coarse.t_overturn == pytest.approx(r.t_overturn, abs=1e-9)
    assert coarse.summary()["max_theta_rad"] == math.pi / 2
    still = simulate_compliant(blk, t_end=1.0, theta0=0.5 * al).summary()
    assert not still["overturned"] and still["t_overturn_s"] is None
    assert still["outcome"] == "standing"  # (as the rigid block's summary, an outcome word)


def test_a_linearised_spectrum_says_its_ratios_are_to_g_alpha(tmp_path, capsys):
    """A linearised model's ratios are to its lift-off g alpha (Housner's closed form above
    holds in it); the table and the JSON called them a_p / (g tan alpha), 20 % off for a
    frame of alpha = 0.7."""
    from nsdyn.cli import main

    blk = RockingBlock(width=0.4, height=2.0, linear=True)
    with ThreadPoolExecutor(1) as ex:
        sp = overturning_spectrum(blk, [2.0], shape="rect", rtol=1e-3, executor=ex)
    assert sp.unit == "g alpha" and sp.summary()["amplitude_unit"] == "g alpha"
    scene = tmp_path / "lin.toml"
    scene.write_text('[scene]\nkind = "rocking"\n[block]\nwidth = 0.4\nheight = 2.0\n'
                     'linear = true\n[motion]\npulse = "rect"\nf_p = 1.0\n'
                     'a_p_g = 0.3\n')  # fmt: skip
    argv = ["spectrum", str(scene), "--n", "2", "--shape", "rect", "--no-figures"]
    assert main([*argv, "--workers", "1", "--out", str(tmp_path / "o")]) == 0
    out = capsys.readouterr().out
    assert "a_min/(g α)" in out and "tan" not in out.split("mode  status")[0].splitlines()[-1]
