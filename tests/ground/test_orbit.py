"""Harmonic ground orbits in the plane: linear, circular, elliptical; the formulas and bad input.

Expected values are analytical: with ω = 2πf, a_x = A_x sin ωt, a_y = A_y sin(ωt + φ_y),
a_z = A_z sin(ω_z t + φ_z) (the module's formulas, evaluated here with math.sin), a circular
orbit has |a| = A at every instant, a linear one stays on its line, an elliptical one satisfies
u²/A_major² + v²/A_minor² = 1 in its principal axes, and the sense of turning is the sign of
a(t) × a(t + h) = −A_x A_y sin φ_y sin ωh at every t (for the circle, φ_y = −90°·sense:
sense·A² sin ωh; positive is counter-clockwise seen from above, z up).

Round-off bound (u = 2⁻⁵³, libm sin within 1 ulp ≤ 2u of a value ≤ 1): the argument ωt + φ
is computed with absolute error ≤ u(|ωt| + 2|φ|) and sin is 1-Lipschitz, so each component is
within A u (|ωt| + 2|φ| + 3) of the formula at the exact argument; for the circle
| |a| − A | ≤ A u (|ωt| + π + 3 + 2 + 2) (two components, the product by A, hypot), taken as
A u (ω t_max + CIRCLE_SLACK).
"""

import math

import numpy as np
import pytest

from nsdyn.ground import GroundMotion3, HarmonicPlane

U = np.finfo(float).eps / 2
CIRCLE_SLACK = 12.0


def _times(f: float, periods: float = 20.0, n: int = 4001) -> np.ndarray:
    return np.linspace(0.0, periods / f, n)


@pytest.mark.parametrize("sense", [+1, -1])
@pytest.mark.parametrize("f, A", [(1.3, 2.5), (0.4, 0.7)])
def test_circular_orbit_has_constant_magnitude_and_its_sense(f, A, sense):
    h = HarmonicPlane.circular(f, A, sense)
    t = _times(f)
    ax, ay, az = h.accel(t)
    w = 2 * math.pi * f
    bound = A * U * (w * t[-1] + CIRCLE_SLACK)
    assert np.max(np.abs(np.hypot(ax, ay) - A)) <= bound
    assert np.all(az == 0.0)
    # a(t) × a(t + dt) = A² sin(ω dt) > 0 counter-clockwise (seen from above, z up)
    cross = ax[:-1] * ay[1:] - ay[:-1] * ax[1:]
    expected = sense * A**2 * math.sin(w * (t[1] - t[0]))
    assert np.all(np.abs(cross - expected) <= 4 * A * bound)


@pytest.mark.parametrize("angle", [0.0, 30.0, 90.0, 120.0, -45.0, 200.0])
def test_linear_orbit_stays_on_its_line(angle):
    f, A = 2.0, 1.5
    h = HarmonicPlane.linear(f, A, angle)
    t = _times(f, periods=5)
    ax, ay, _ = h.accel(t)
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    w = 2 * math.pi * f
    bound = A * U * (w * t[-1] + CIRCLE_SLACK)
    along, across = c * ax + s * ay, -s * ax + c * ay
    assert np.max(np.abs(across)) <= 2 * bound
    # along the line: ±A sin(ωt), one sign for the whole history (θ and θ + 180° are one line)
    sign = 1.0 if c > 1e-12 or (abs(c) <= 1e-12 and s > 0) else -1.0
    assert np.max(np.abs(along - sign * A * np.sin(w * t))) <= 2 * bound


@pytest.mark.parametrize("sense", [+1, -1])
@pytest.mark.parametrize("angle", [0.0, 25.0, 90.0, 143.0])
def test_elliptical_orbit_has_its_semi_axes_and_sense(angle, sense):
    f, a1, a2 = 1.1, 2.0, 0.8
    h = HarmonicPlane.elliptical(f, a1, a2, angle, sense)
    t = _times(f, periods=3, n=6001)
    ax, ay, _ = h.accel(t)
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    u, v = c * ax + s * ay, -s * ax + c * ay
    w = 2 * math.pi * f
    # each component within A_max u (ωt + slack) (module docstring), the constructor's phasors
    # and degree conversions within a few u relative more; the ellipse equation amplifies by
    # 2/A_minor per unit of error: bound 4 (A_max / A_minor) u (ωt + slack)
    bound = 4 * (a1 / a2) * U * (w * t[-1] + 2 * CIRCLE_SLACK)
    assert np.max(np.abs((u / a1) ** 2 + (v / a2) ** 2 - 1.0)) <= bound
    # the semi-axes are reached: max |u| = A_major, max |v| = A_minor (sampled every T/2000,
    # so the sampled peak is within A (1 − cos(π/2000)) ≈ 1.2e-6 A of it)
    assert np.max(np.abs(u)) == pytest.approx(a1, rel=2e-6)
    assert np.max(np.abs(v)) == pytest.approx(a2, rel=2e-6)
    cross = ax[:-1] * ay[1:] - ay[:-1] * ax[1:]  # = a1 a2 sin(ω dt) · sense
    assert np.all(np.sign(cross) == sense)
    assert h.accel(0.0)[0] == 0.0  # time origin: a_x starts at zero


def test_circular_is_the_elliptical_orbit_with_equal_axes():
    f, A = 0.9, 1.7
    for sense in (+1, -1):
        e = HarmonicPlane.elliptical(f, A, A, 0.0, sense)
        c = HarmonicPlane.circular(f, A, sense)
        assert (e.ax, e.ay, e.phase_y_deg) == (c.ax, c.ay, c.phase_y_deg)


def test_the_formulas_component_by_component():
    h = HarmonicPlane(f=0.7, ax=1.2, ay=0.5, phase_y_deg=35.0, az=0.9, f_z=2.1, phase_z_deg=-20.0)
    for t in (0.0, 0.13, 1.7, 9.3):
        ax, ay, az = h.accel(t)
        w, wz = 2 * math.pi * 0.7, 2 * math.pi * 2.1
        tol = 2.0 * U * (wz * t + 8.0)
        assert ax == pytest.approx(1.2 * math.sin(w * t), abs=tol)
        assert ay == pytest.approx(0.5 * math.sin(w * t + math.radians(35.0)), abs=tol)
        assert az == pytest.approx(0.9 * math.sin(wz * t + math.radians(-20.0)), abs=tol)
    assert h.period == pytest.approx(1 / 0.7, rel=U)
    p = h.params_rad()  # what a kernel evaluating the same formulas is given
    assert p == (0.7, 1.2, 0.5, math.radians(35.0), 0.9, 2.1, math.radians(-20.0))
    same = HarmonicPlane(f=0.7, ax=1.0, az=0.5)  # f_z defaults to f
    assert same.vertical_frequency == 0.7
    assert same.accel(0.25 / 0.7)[2] == pytest.approx(0.5, abs=8 * U)  # sin(π/2)


def test_sampled_record_is_the_formula_on_the_grid():
    h = HarmonicPlane.elliptical(1.5, 1.0, 0.5, 30.0, az=0.3)
    rec = h.sampled(2.0, 0.01)
    assert isinstance(rec, GroundMotion3) and (rec.n, rec.dt) == (201, 0.01)
    ax, ay, az = h.accel(rec.t)
    assert np.array_equal(rec.ax, ax) and np.array_equal(rec.ay, ay)
    assert np.array_equal(rec.az, az)
    assert HarmonicPlane.circular(1.0, 1.0).sampled(1.0, 0.1).az is None


@pytest.mark.parametrize(
    "kwargs, needles",
    [
        (dict(f=0.0, ax=1.0), ["f", "> 0"]),
        (dict(f=-1.0, ax=1.0), ["f", "> 0"]),
        (dict(f=float("nan"), ax=1.0), ["f", "finite"]),
        (dict(f=float("inf"), ax=1.0), ["f", "finite"]),
        (dict(f=1.0, ax=-1.0), ["ax", ">= 0"]),
        (dict(f=1.0, ax=1.0, ay=float("nan")), ["ay", "finite"]),
        (dict(f=1.0, ax=1.0, az=-0.1), ["az", ">= 0"]),
        (dict(f=1.0, ax=1.0, f_z=0.0), ["f_z", "> 0"]),
        (dict(f=1.0, ax=1.0, phase_y_deg=float("inf")), ["phase_y_deg", "finite"]),
        (dict(f=1.0, ax="one"), ["ax", "number"]),
    ],
)
def test_bad_orbit_is_refused_in_one_line(kwargs, needles):
    with pytest.raises(ValueError) as ei:
        HarmonicPlane(**kwargs)
    msg = str(ei.value)
    assert "\n" not in msg and msg.startswith("HarmonicPlane.")
    for needle in needles:
        assert needle in msg


def test_bad_helper_arguments():
    with pytest.raises(ValueError, match="A_minor: expected at most A_major"):
        HarmonicPlane.elliptical(1.0, 1.0, 2.0)
    with pytest.raises(ValueError, match="sense"):
        HarmonicPlane.circular(1.0, 1.0, sense=2)
    with pytest.raises(ValueError, match="A: expected an amplitude >= 0"):
        HarmonicPlane.linear(1.0, -1.0, 0.0)


def test_an_orbit_object_without_its_phase_has_the_orbit_s_default_phase():
    # the kernel's ground parameters of an object with f, ax, ay and no phase_y_deg took
    # φ_y = 0 (a line), a dict or a HarmonicPlane of the same values 90° (a circle): one
    # default, HarmonicPlane's
    from types import SimpleNamespace

    from nsdyn.models.isolated import _kplane as kp
    from nsdyn.models.isolated.plane_ground import pack_ground

    ref = pack_ground(HarmonicPlane(f=0.5, ax=2.0, ay=2.0))[1]
    assert ref[kp.GP_PHY] == math.radians(90.0)
    for ground in ({"f": 0.5, "ax": 2.0, "ay": 2.0}, SimpleNamespace(f=0.5, ax=2.0, ay=2.0)):
        np.testing.assert_array_equal(pack_ground(ground)[1], ref)
    line = pack_ground(SimpleNamespace(f=0.5, ax=2.0, ay=2.0, phase_y_deg=0.0))[1]
    assert line[kp.GP_PHY] == 0.0
