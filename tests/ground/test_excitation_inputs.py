"""Harmonic excitations: a frequency that is not positive is refused where it is built.

Before, ``Harmonic(1, -0.1)`` was accepted and a run later said "dt_out: expected a positive
output step", ``f = 0`` raised ZeroDivisionError and ``f = nan`` "cannot convert float NaN to
integer". The contract: one ValueError naming the field and the expected form.
"""

import math

import pytest

from nsdyn.ground.excitation import Harmonic, HarmonicForce


@pytest.mark.parametrize("f", [-0.1, 0.0, math.nan, -math.inf])
def test_harmonic_needs_a_positive_frequency(f):
    with pytest.raises(ValueError, match=r"^Harmonic\.f_hor: expected a"):
        Harmonic(1.0, f)
    with pytest.raises(ValueError, match=r"^Harmonic\.f_ver: expected a"):
        Harmonic(1.0, 1.0, A_ver=2.0, f_ver=f)
    with pytest.raises(ValueError, match=r"^HarmonicForce\.f: expected a"):
        HarmonicForce(1e3, f, dofs=[0])


def test_a_component_without_amplitude_needs_no_frequency():
    # a vertical-only motion (no horizontal component) and the default no-vertical component
    h = Harmonic(0.0, 0.0, A_ver=3.0, f_ver=2.0)
    assert h.period == math.inf
    assert Harmonic(1.0, 0.5).f_ver == 0.0
    with pytest.raises(ValueError, match=r"positive frequency \[Hz\] \(a non-zero amplitude"):
        Harmonic(1.0, 0.0)
    with pytest.raises(ValueError, match=r"^Harmonic\.f_hor: expected a positive frequency"):
        Harmonic(0.0, -1.0)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        # complex samples lost their imaginary part with only a numpy warning; text samples
        # and a text step were converted; a text angle was read as a number
        (lambda np: _gm3(np, ax=np.ones(5) * (1 + 1j)), r"^GroundMotion3\.ax: expected real"),
        (lambda np: _gm3(np, ay=["1"] * 5), r"^GroundMotion3\.ay: expected real .* text"),
        (lambda np: _gm3(np, az=np.ones(5, bool)), r"^GroundMotion3\.az: expected real .* bool"),
        (lambda np: _gm3(np, dt="0.01"), r"^GroundMotion3\.dt: expected a positive finite"),
        (lambda np: _gm3(np, ay=np.ones(4)), r"^GroundMotion3\.ay: expected 5 samples"),
        (lambda np: _gm(np, a_hor=np.ones(5) * 1j), r"^a_hor: expected real .* complex"),
        (lambda np: _gm(np, a_ver=np.ones(3)), r"^a_ver: expected 5 samples"),
        (lambda np: _gm(np, a_hor=[[1.0, 2.0]]), r"^a_hor: expected a non-empty 1-D array"),
        (lambda np: _gm(np, dt=-0.01), r"^dt: expected a positive finite step"),
        (
            lambda np: _gm(np, a_hor=[1.0, float("inf")]),
            r"^a_hor: expected finite values, sample 1",
        ),
        # 1e308 is finite: it overflowed inside a run (the bound: 1e12 m/s², far past any
        # ground's acceleration, and past what a property test's scalings reach)
        (
            lambda np: _gm3(np, az=[1.0, 2.0, -1e308, 0.0, 0.0]),
            r"^GroundMotion3\.az: expected accelerations \[m/s²\] below 1e\+12, sample 2 is "
            r"-1e\+308$",
        ),
    ],
)
def test_ground_motions_refuse_samples_that_are_not_real_accelerations(make, match):
    import numpy as np

    with pytest.raises(ValueError, match=match):
        make(np)


def _gm3(np, **kw):
    from nsdyn.ground.motion3 import GroundMotion3

    args = {"name": "g", "t0": 0.0, "dt": 0.01, "ax": np.ones(5), "ay": np.ones(5), **kw}
    return GroundMotion3(**args)


def _gm(np, **kw):
    from nsdyn.ground.motion import GroundMotion

    return GroundMotion(**{"name": "g", "t0": 0.0, "dt": 0.01, "a_hor": np.ones(5), **kw})


def test_a_linear_orbit_refuses_a_text_angle():
    from nsdyn.ground.orbit import HarmonicPlane

    with pytest.raises(
        ValueError, match=r"^angle_deg: expected a finite angle in degrees, got '30'"
    ):
        HarmonicPlane.linear(1.0, 1.0, angle_deg="30")
    # a whole angle of 90 degrees is exact
    assert HarmonicPlane.linear(1.0, 2.0, angle_deg=90).ax == 0.0


@pytest.mark.parametrize(
    ("args", "match"),
    [
        # each ran before: one sample as a run with no motion and no word (x_iso 5.7e-15 m),
        # lists for t0 and dt failed in a run with a TypeError naming no argument, a negative
        # dt blamed dt_out, a NaN sample failed the integration ("NaN or inf in the state")
        ((0.0, 0.01, [1.0]), r"^Table\.a_hor: expected two samples or more .* got 1$"),
        (([0.0, 0.02], 0.01, [0.0, 0.0]), r"^Table\.t0: expected a finite number"),
        ((0.0, [0.01], [0.0, 0.0]), r"^Table\.dt: expected a positive step \[s\], got \[0\.01\]"),
        ((10**400, 0.01, [0.0, 0.0]), r"^Table\.t0: expected a finite number"),  # (OverflowError)
        ((0.0, 0.01, [10**400, 0.0]), r"^Table\.a_hor: expected real samples, got \[1000"),
        ((0.0, -0.01, [1.0] * 10), r"^Table\.dt: expected a positive step \[s\], got -0\.01$"),
        ((0.0, 0.01, [0.0, 1.0, math.nan, 0.0]), r"^Table\.a_hor: .* sample 2 is nan$"),
        ((0.0, 0.01, [0.0, 1.0, 2.0], [0.0, 0.0]), r"^Table\.a_ver: expected 3 samples"),
        ((0.0, 0.01, ["1", "2"]), r"^Table\.a_hor: expected real samples, got text"),
        ((0.0, 0.01, [[1.0, 2.0], [3.0, 4.0]]), r"^Table\.a_hor: expected a non-empty 1-D"),
        ((0.0, 0.01, [[1.0, 2.0], [3.0]]), r"^Table\.a_hor: expected real samples, got \[\[1"),
    ],
)
def test_a_table_refuses_what_a_ground_motion_refuses(args, match):
    from nsdyn.ground.excitation import Table

    with pytest.raises(ValueError, match=match):
        Table(*args)


def test_a_table_keeps_its_samples_as_floats_and_the_callers_array_its_own():
    import numpy as np

    from nsdyn.ground.excitation import Table

    a = np.arange(4)
    t = Table(0, 1, a, a)
    assert t.a_hor.dtype == np.float64 and t.a_ver.dtype == np.float64
    a[0] = 7  # (a copy: changing the caller's array changes no table)
    assert t.a_hor[0] == 0.0 and t.duration == 3.0 and isinstance(t.dt, float)
