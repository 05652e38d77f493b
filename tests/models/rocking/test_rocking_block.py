"""Housner's rigid block: closed forms, energy relations, lift-off, impacts, overturning, Zeno."""

from __future__ import annotations

import math
import os
import subprocess
import sys

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from nsdyn.ground.pulses import Pulse, one_sine, rectangular
from nsdyn.models.rocking import RockingBlock, simulate_rocking

COLUMN = RockingBlock(width=0.3, height=1.2)  # seed 003 Table 2 column 2 (2H = 1.2 m, 2B = 0.3 m)


def _quarter_exact(theta_m: float, alpha: float, p: float) -> float:
    """Time from theta = 0 to the peak theta_m by quadrature of the exact energy relation
    theta'² / (2 p²) = cos(alpha - theta_m) - cos(alpha - theta) (Housner 1963), with
    theta = theta_m (1 - u²) removing the 1/sqrt singularity at the peak."""

    def f(u):
        th = theta_m * (1.0 - u * u)
        den = 4.0 * math.sin(alpha - 0.5 * (th + theta_m)) * math.sin(0.5 * theta_m * u * u)
        return 2.0 * theta_m * u / (p * math.sqrt(den))

    return quad(f, 0.0, 1.0, epsabs=1e-14, epsrel=1e-13, limit=200)[0]


def test_free_rocking_period_linearised_housner_closed_form():
    """Linearised free rocking: quarter period (1/p) acosh(1 / (1 - theta_m / alpha))
    (Housner 1963); each half-cycle between impacts uses the peak between them."""
    blk = RockingBlock(width=0.3, height=1.2, linear=True)
    a, p = blk.alpha, blk.p
    res = simulate_rocking(blk, t_end=8.0, theta0=0.6 * a, dt_out=0)
    t_imp = res.impacts[:, 0]
    assert t_imp[0] == pytest.approx(math.acosh(1.0 / (1.0 - 0.6)) / p, rel=1e-8)
    pk = np.abs(res.peaks[:, 1])  # the release point is not a located peak: pk[n] follows impact n
    for n in range(8):
        half = 2.0 * math.acosh(1.0 / (1.0 - pk[n] / a)) / p
        assert t_imp[n + 1] - t_imp[n] == pytest.approx(half, rel=1e-7)


def test_a_plastic_impact_stops_the_block_at_its_first_impact():
    """r = 0 (a perfectly plastic impact, refused before): released from 0.6 alpha the block
    rests from its first impact on, at Housner's linearised quarter period (1/p) acosh(1 /
    (1 - 0.6)), after one impact and with theta 0 afterwards."""
    blk = RockingBlock(width=0.3, height=1.2, linear=True, r=0.0)
    res = simulate_rocking(blk, t_end=3.0, theta0=0.6 * blk.alpha, dt_out=0.01)
    s = res.summary()
    t1 = math.acosh(1.0 / (1.0 - 0.6)) / blk.p
    assert s["outcome"] == "rest" and s["n_impacts"] == 1
    assert s["t_rest_s"] == pytest.approx(t1, rel=1e-8)
    assert np.all(res.theta[res.t > t1] == 0.0)


def test_free_rocking_period_exact_quadrature_of_energy_relation():
    """Exact equation: times between impacts equal twice the quadrature of the energy relation
    from theta = 0 to the peak in between."""
    a, p = COLUMN.alpha, COLUMN.p
    res = simulate_rocking(COLUMN, t_end=6.0, theta0=0.8 * a, dt_out=0)
    t_imp = res.impacts[:, 0]
    assert t_imp[0] == pytest.approx(_quarter_exact(0.8 * a, a, p), rel=1e-8)
    pk = np.abs(res.peaks[:, 1])
    for n in range(6):
        assert t_imp[n + 1] - t_imp[n] == pytest.approx(2 * _quarter_exact(pk[n], a, p), rel=1e-7)


@pytest.mark.parametrize("linear", [False, True])
def test_peak_after_each_impact_from_energy_relation(linear):
    """Peak after an impact from energy conservation with the post-impact velocity:
    exact cos(alpha - th) - cos(alpha) = th'+² / 2p²; linearised alpha th - th²/2 = th'+² / 2p²."""
    blk = RockingBlock(width=0.4, height=1.6, r=0.85, linear=linear)
    a, p = blk.alpha, blk.p
    res = simulate_rocking(blk, t_end=6.0, theta0=0.7 * a, dt_out=0)
    v = res.impacts[:10, 2]
    if linear:
        expected = a - np.sqrt(a**2 - v**2 / p**2)
    else:
        expected = a - np.arccos(np.cos(a) + v**2 / (2 * p**2))
    np.testing.assert_allclose(np.abs(res.peaks[:10, 1]), expected, rtol=1e-8)
    # the velocity arriving at each impact from the preceding peak (first: the release angle)
    pk = np.r_[0.7 * a, np.abs(res.peaks[:9, 1])]
    if linear:
        v_in = p * np.sqrt(2 * a * pk - pk**2)
    else:
        v_in = p * np.sqrt(2 * (np.cos(a - pk) - np.cos(a)))
    np.testing.assert_allclose(np.abs(res.impacts[:10, 1]), v_in, rtol=1e-8)


def test_energy_constant_between_impacts_and_r2_loss_at_each():
    """Free rocking conserves energy between impacts; at an impact (theta = 0, all energy
    kinetic) the energy drops by the factor r² (Housner: kinetic energy ratio r²)."""
    blk = COLUMN
    res = simulate_rocking(blk, t_end=4.0, theta0=0.5 * blk.alpha, dt_out=1e-3)
    e = res.energy()
    t_imp = res.impacts[:, 0]
    seg = np.searchsorted(t_imp, res.t, side="right")
    levels = []
    for k in range(6):
        ek = e[seg == k]
        assert np.ptp(ek) <= 1e-8 * ek.mean()
        levels.append(ek.mean())
    ratios = np.array(levels[1:]) / np.array(levels[:-1])
    np.testing.assert_allclose(ratios, blk.restitution**2, rtol=1e-7)


def test_uplift_threshold_g_tan_alpha():
    """Lift-off from rest only when |ü_h| > g tan(alpha) (Housner): a one-sine pulse just
    below does nothing, just above lifts at sin(w t) = g tan(alpha) / a_p; with a vertical
    component a_v = rho a_h the threshold becomes (g + a_v) tan(alpha)."""
    blk = COLUMN
    ga = blk.g * math.tan(blk.alpha)
    w = 12.57
    below = simulate_rocking(blk, one_sine(0.999 * ga, w), t_end=1.0)
    assert below.n_uplifts == 0 and below.outcome == "rest" and np.all(below.theta == 0)
    ap = 1.5 * ga
    above = simulate_rocking(blk, one_sine(ap, w), t_end=1.0)
    assert above.n_uplifts >= 1
    assert above.t_uplift == pytest.approx(math.asin(ga / ap) / w, abs=1e-10)
    rho = 0.5
    up = simulate_rocking(blk, one_sine(ap, w, ver_ratio=rho), t_end=1.0)
    t_u = math.asin(ga / (ap * (1 - rho * math.tan(blk.alpha)))) / w
    assert up.t_uplift == pytest.approx(t_u, abs=1e-10)


def test_a_ground_falling_faster_than_g_stops_a_rocking_block_too():
    """Free flight is not modelled: with g + a_v <= 0 the block leaves the ground, whether at
    rest or rocking (a rocking block went on with gravity reversed). A rectangular pulse of
    a_v = -1.5 g starting at 0.2 s under a block released at half its slenderness: the run
    stops at the pulse's start."""
    from nsdyn._checks import NumericalFailure

    blk = COLUMN
    pulse = Pulse("rect", 0.05 * blk.g, 2.0 * math.pi, 1, 0.2, -30.0)  # a_v = -30 a_h
    with pytest.raises(NumericalFailure, match=r"at t = 0.2 s: vertical ground acceleration"):
        simulate_rocking(blk, pulse, t_end=1.0, theta0=0.5 * blk.alpha)
    # the same pulse upwards (g + a_v = 2.5 g) is a rocking run
    up = Pulse("rect", 0.05 * blk.g, 2.0 * math.pi, 1, 0.2, 30.0)
    assert simulate_rocking(blk, up, t_end=1.0, theta0=0.5 * blk.alpha).t[-1] == 1.0


def test_impact_times_converge_with_tolerance():
    """Impact times under a pulse approach the tight-tolerance solution as tol decreases
    (Dormand-Prince 5(4): error roughly proportional to tol)."""
    exc = one_sine(0.4 * 9.81, 12.57)
    ref = simulate_rocking(COLUMN, exc, t_end=5.0, tol=1e-13, dt_out=0).impacts[:8, 0]
    errs = []
    for tol in (1e-5, 1e-7, 1e-9, 1e-11):
        t_imp = simulate_rocking(COLUMN, exc, t_end=5.0, tol=tol, dt_out=0).impacts[:8, 0]
        errs.append(np.max(np.abs(t_imp - ref)))
    assert all(e2 < e1 for e1, e2 in zip(errs, errs[1:], strict=False))
    assert errs[-1] < 1e-8


def test_overturning_rectangular_pulse_linearised_housner_criterion():
    """Linearised block under a rectangular pulse of duration t1 overturns iff
    a / (g alpha) >= 1 / (1 - exp(-p t1)) (Housner 1963)."""
    blk = RockingBlock(width=0.4, height=2.0, linear=True)
    t1 = 0.8 / blk.p
    a_c = blk.g * blk.alpha / (1.0 - math.exp(-blk.p * t1))
    hi = simulate_rocking(blk, rectangular(-1.002 * a_c, t1), t_end=15.0)
    lo = simulate_rocking(blk, rectangular(-0.998 * a_c, t1), t_end=15.0)
    assert hi.overturned and math.isfinite(hi.t_overturn)
    assert not lo.overturned and lo.n_impacts >= 1


def test_overturning_long_constant_pulse_exact_criterion():
    """Exact equation, constant acceleration a for t1: with theta1 reached at t1 from the first
    integral theta'²/2p² = (a/g)(sin a - sin(a - th)) + cos a - cos(a - th), the block
    overturns iff (a/g)(sin alpha - sin(alpha - theta1)) >= 1 - cos(alpha) (energy to pass
    theta = alpha after the pulse); a_crit found by brentq over quadratures."""
    blk = RockingBlock(width=0.5, height=2.0)
    al, p, g = blk.alpha, blk.p, blk.g
    t1 = 1.2 / p

    def theta1(a):
        def dt_du(u, th1):  # theta = th1 u², d theta = 2 th1 u du, rate ~ u near 0
            th = th1 * u * u
            e = (a / g) * (math.sin(al) - math.sin(al - th)) + math.cos(al) - math.cos(al - th)
            return 2.0 * th1 * u / (p * math.sqrt(2.0 * e))

        return brentq(lambda th1: quad(dt_du, 0.0, 1.0, args=(th1,), epsrel=1e-12)[0] - t1,
                      1e-6, 1.5, xtol=1e-14)  # fmt: skip

    def margin(a):
        return (a / g) * (math.sin(al) - math.sin(al - theta1(a))) - (1 - math.cos(al))

    a_c = brentq(margin, 1.05 * g * math.tan(al), 3 * g * math.tan(al), xtol=1e-12)
    hi = simulate_rocking(blk, rectangular(-1.003 * a_c, t1), t_end=12.0, dt_out=0)
    lo = simulate_rocking(blk, rectangular(-0.997 * a_c, t1), t_end=12.0, dt_out=0)
    assert hi.overturned and not lo.overturned


def _zeno_rest_time_linear(blk, theta0, v_rest):
    """Closed-form rest time of linearised free rocking: first quarter period plus the sum of
    flight times 2 acosh(1 / sqrt(1 - v_k² / p² alpha²)) / p of the geometric impact velocities
    v_k = r^k v_1 until v_k <= v_rest."""
    a, p, r = blk.alpha, blk.p, blk.restitution
    t = math.acosh(1.0 / (1.0 - theta0 / a)) / p
    v = r * p * math.sqrt(2 * a * theta0 - theta0**2)
    while v > v_rest:
        t += 2.0 * math.acosh(1.0 / math.sqrt(1.0 - (v / (p * a)) ** 2)) / p
        v *= r
    return t


@pytest.mark.parametrize("r", [0.7, 0.95])
def test_zeno_free_rocking_comes_to_rest_at_accumulation_time(r):
    """Impacts accumulate (Zeno); the block comes to rest at the closed-form accumulation time
    with a finite number of impacts and stays at rest."""
    blk = RockingBlock(width=0.4, height=2.0, r=r, linear=True)
    v_rest = 1e-6 * blk.p * blk.alpha
    res = simulate_rocking(blk, t_end=60.0, theta0=0.5 * blk.alpha, dt_out=0.01)
    assert res.outcome == "rest"
    assert res.t_rest == pytest.approx(_zeno_rest_time_linear(blk, 0.5 * blk.alpha, v_rest),
                                       abs=1e-6)  # fmt: skip
    n_expected = math.ceil(math.log(v_rest / (r * blk.p * blk.alpha * math.sqrt(0.75)))
                           / math.log(r))  # fmt: skip
    assert abs(res.n_impacts - n_expected) <= 1
    assert np.all(res.theta[res.t > res.t_rest + 0.01] == 0.0)


def test_perfectly_elastic_block_keeps_rocking():
    """r = 1: no loss, the amplitude never decays (energy conservation)."""
    blk = RockingBlock(width=0.4, height=2.0, r=1.0)
    res = simulate_rocking(blk, t_end=20.0, theta0=0.3 * blk.alpha)
    assert res.outcome == "rocking"
    np.testing.assert_allclose(np.abs(res.peaks[:, 1]), 0.3 * blk.alpha, rtol=1e-6)


def test_pulse_closed_forms_match_kernel_samples():
    """The kernel evaluates the same closed forms as nsdyn.ground.pulses (one formula each)."""
    from numba import njit

    from nsdyn.models.rocking._kground import GK_PULSE, RIGHT_LIMIT, ground

    @njit  # ground has no Python entry point (only compiled code calls it); the limit and the
    def sample(t, left, kind, gp, tab):  # kind as arguments: typed as the loop's, not literal
        return ground(t, left, kind, gp, tab, tab)

    t = np.linspace(-0.1, 2.0, 97)
    for pl in (Pulse("sine", 2.0, 7.0, 2), Pulse("cosine", -1.5, 9.0), Pulse("ricker", 3.0, 11.0),
               Pulse("rect", 1.0, 5.0, 1, 0.2, 0.3)):  # fmt: skip
        ref = pl.accel(t)
        got = np.array([sample(ti, RIGHT_LIMIT, np.int64(GK_PULSE), pl.code(), ref) for ti in t])
        np.testing.assert_allclose(got[:, 0], ref, atol=1e-14)
        np.testing.assert_allclose(got[:, 1], pl.ver_ratio * ref, atol=1e-14)


def test_numba_disabled_gives_the_same_closed_form():
    """NUMBA_DISABLE_JIT=1: the pure-interpreter kernel reproduces Housner's first impact time."""
    code = (
        "import math\n"
        "from nsdyn.models.rocking import RockingBlock, simulate_rocking\n"
        "b = RockingBlock(width=0.4, height=2.0, linear=True)\n"
        "r = simulate_rocking(b, t_end=1.5, theta0=0.5 * b.alpha, dt_out=0)\n"
        "print(abs(r.impacts[0, 0] - math.acosh(2.0) / b.p))\n"
    )
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         timeout=120, check=True)  # fmt: skip
    assert float(out.stdout.strip()) < 1e-9


def test_housner_restitution_is_refused_where_it_is_no_restitution():
    # 1 - 1.5 sin² alpha vanishes at sin² alpha = 2/3 (alpha = 54.7°) and is negative beyond
    # (a squat block's run refuses it); alphas outside (0, pi/2) gave numbers
    from nsdyn.models.rocking.block import RockingBlock, housner_restitution

    edge = math.asin(math.sqrt(2.0 / 3.0))
    assert housner_restitution(edge) == pytest.approx(0.0, abs=4 * np.finfo(float).eps)
    for alpha in (0.0, -0.1, math.pi / 2, 2.0, float("nan")):
        with pytest.raises(ValueError, match=r"alpha: expected a slenderness in \(0, pi/2\)"):
            housner_restitution(alpha)
    assert RockingBlock(width=3.0, height=1.0).restitution < 0  # (a run refuses it)


def test_the_most_slender_block_is_the_one_the_limit_names():
    # "expected at least 1e-4 rad (a block at most 10 000 times as tall as wide)" refused the
    # block 10 000 times as tall as wide: its atan(1e-4) is 3e-13 below 1e-4
    from nsdyn.models.rocking.block import RockingBlock

    for height in (1.0, 1.2, 3.7):
        assert RockingBlock(width=1e-4 * height, height=height).alpha > 0
        with pytest.raises(ValueError, match=r"width / height = 9.9e-05; expected at least 0.0001 "
                           r"\(a block at most 10 000 times as tall as wide\)"):  # fmt: skip
            RockingBlock(width=0.99e-4 * height, height=height)


def test_any_model_with_the_documented_attributes_rocks():
    """simulate_rocking runs any model exposing p, alpha, restitution, linear and g (the
    module's promise): one without a given ``r`` failed once r = 0 was told from Housner's;
    linearised free rocking from 0.6 alpha reaches its first impact at (1/p) acosh(2.5)."""
    from types import SimpleNamespace

    m = SimpleNamespace(p=COLUMN.p, alpha=COLUMN.alpha, restitution=0.9, linear=True, g=9.81)
    res = simulate_rocking(m, t_end=2.0, theta0=0.6 * m.alpha, dt_out=0)
    assert res.impacts[0, 0] == pytest.approx(math.acosh(1.0 / (1.0 - 0.6)) / m.p, rel=1e-8)


@pytest.mark.parametrize("rho", [1.5, -1.5])
@pytest.mark.parametrize("gamma", [None, 5.0])
def test_a_ground_falling_faster_than_g_stops_the_run_at_that_instant(rho, gamma):
    """Free flight is not modelled: the run stops where g + ü_v first reaches 0. For a one-sine
    pulse with ü_v = rho a_p sin(w t) that is sin(w t) = -g / (rho a_p), here while the block
    or frame rocks: it was said at the next step's start (0.0820 s for 0.0784 s)
    (nsdyn.models.rocking.fall finds it before the run)."""
    from nsdyn import RockingFrame
    from nsdyn._checks import NumericalFailure

    g = 9.81
    ap, w = 0.8 * g, 4 * math.pi
    s = -g / (rho * ap)
    x = math.asin(s) if s > 0 else math.pi - math.asin(s)  # first w t in (0, 2 pi) with sin = s
    kw = {"width": 0.3, "height": 1.2, "g": g}
    model = RockingBlock(**kw) if gamma is None else RockingFrame(**kw, gamma=gamma)
    with pytest.raises(NumericalFailure, match="free flight is not modelled") as e:
        simulate_rocking(model, one_sine(ap, w, ver_ratio=rho), t_end=1.0)
    t_said = float(str(e.value).split("at t = ")[1].split(" s")[0])
    assert t_said == pytest.approx(x / w, rel=1e-5)  # (the message's 6 digits)


def test_an_impact_buffer_filled_says_what_to_change():
    # "too many impacts (raise max_impacts)" asked a scene's user for a key no scene has.
    # Free rocking from 0.5 alpha with r = 0.9 has tens of impacts before rest: 3 fill it
    from nsdyn._checks import NumericalFailure

    blk = RockingBlock(width=0.3, height=1.2, r=0.9)
    with pytest.raises(NumericalFailure, match=r"more than max_impacts = 3 impacts \(raise it, "
                       r"or shorten t_end: a scene's motion.t_end\)$"):  # fmt: skip
        simulate_rocking(blk, t_end=30.0, theta0=0.5 * blk.alpha, max_impacts=3)


@pytest.mark.parametrize("shape", ["sine", "cosine", "ricker"])
def test_a_dip_below_minus_g_shorter_than_a_step_is_found(shape):
    """A vertical peak of 1.0001 g under a rocking block: g + ü_v < 0 for ~1 % of a period,
    less than a step, and the run went on (checked at each step's start). The instant is the
    closed form's first root (scipy's brentq on the pulse's own formula between its start and
    its first extreme)."""
    from scipy.optimize import brentq

    from nsdyn._checks import NumericalFailure

    blk = COLUMN
    g, w, rho = blk.g, 10.0, -1.0001 / 0.01  # a_v = -1.0001 g at the horizontal's peak
    pulse = Pulse(shape, 0.01 * blk.g, w, 1, 0.0, rho)
    f = {"sine": lambda t: g + rho * pulse.a_p * math.sin(w * t),
         "cosine": lambda t: g + rho * pulse.a_p * math.cos(w * t)}  # fmt: skip
    if shape == "ricker":
        t_c = 1.5 * pulse.T_p
        f["ricker"] = lambda t: g + rho * pulse.a_p * float(pulse.accel(t)) / pulse.a_p
        exact = brentq(f["ricker"], t_c - math.sqrt(6) / w, t_c, xtol=1e-14)
    elif shape == "sine":
        exact = brentq(f["sine"], 0.0, 0.5 * math.pi / w, xtol=1e-14)
    else:  # the cosine starts at its peak: from the pulse's start
        exact = 0.0
    with pytest.raises(NumericalFailure, match="free flight is not modelled") as e:
        simulate_rocking(blk, pulse, t_end=pulse.duration + 0.5, theta0_over_alpha=0.5)
    t_said = float(str(e.value).split("at t = ")[1].split(" s")[0])
    assert t_said == pytest.approx(exact, rel=1e-5, abs=1e-12)  # (the message's 6 digits)


def test_a_record_falling_below_minus_g_between_samples_is_said_at_its_crossing():
    """A record is linear between samples: from -0.9 g at 1.20 s to -2.15 g at 1.25 s it
    crosses -g at 1.204 s, under a block rocking with r = 0 that would hit the ground just
    after (at 1.2096 s under -0.9 g); the crossing was said at the impact."""
    from nsdyn._checks import NumericalFailure
    from nsdyn.ground.motion import GroundMotion

    g, dt = 9.81, 0.05
    blk = RockingBlock(width=0.3, height=1.2, r=0.0, g=g)
    av = np.full(41, -0.9 * g)
    av[25:] = -2.15 * g  # the sample at 1.25 s and on
    rec = GroundMotion(t0=0.0, dt=dt, a_hor=np.zeros(41), a_ver=av)
    with pytest.raises(NumericalFailure, match="free flight is not modelled") as e:
        simulate_rocking(blk, rec, t_end=1.9, theta0_over_alpha=0.5)
    assert float(str(e.value).split("at t = ")[1].split(" s")[0]) == pytest.approx(1.204, rel=1e-6)


def test_a_record_falls_only_where_the_kernel_feels_its_ground():
    """The ground is 0 before a record's first sample and after its last: a record from 1 s
    whose first vertical sample is -1.5 g fails at 1 s (a ramp from t0 = 0 said 0.667 s), and
    a run from that record's last sample, -1.5 g, feels none of it (0.2 s was said)."""
    from nsdyn._checks import NumericalFailure
    from nsdyn.ground.motion import GroundMotion

    blk = RockingBlock(width=0.4, height=2.0)
    g = blk.g
    rec = GroundMotion(1.0, 0.01, np.zeros(21), np.array([-1.5 * g] + [0.0] * 20), source="t")
    with pytest.raises(NumericalFailure, match=r"at t = 1 s: vertical ground acceleration"):
        simulate_rocking(blk, rec, t_end=1.2)
    last = GroundMotion(0.0, 0.01, np.zeros(21), np.array([0.0] * 20 + [-1.5 * g]), source="t")
    assert simulate_rocking(blk, last, t0=0.2, t_end=1.0).outcome == "rest"


def test_a_run_in_negative_time_ends():
    # the kernel stopped at t_end (1 - 1e-15), past a negative t_end: it stepped for ever
    import subprocess
    import sys

    code = ("from nsdyn import RockingBlock, simulate_rocking; b = RockingBlock(width=0.4, "
            "height=2.0); print(simulate_rocking(b, t0=-1.0, t_end=-0.5, "
            "theta0_over_alpha=0.5).t[-1])")  # fmt: skip
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0 and float(r.stdout) == pytest.approx(-0.5, abs=1e-12)
