"""GroundMotion: derived quantities and transformations (scaling, baseline, resampling, window).

Expected values are exact identities (one rounding per product), closed-form error bounds of
the trapezoidal rule and of interpolation, and properties over random records (hypothesis).
"""

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from nsdyn.ground import GroundMotion, harmonic, read_motion

# ------------------------------------------------------------------------------------------
# GroundMotion transformations
# ------------------------------------------------------------------------------------------


def example_motion(n: int = 1001, dt: float = 0.01) -> GroundMotion:
    t = dt * np.arange(n)
    a = np.sin(2 * np.pi * 1.3 * t) * np.exp(-0.2 * t) + 0.3 * np.sin(2 * np.pi * 0.4 * t)
    return GroundMotion(0.0, dt, a, 0.5 * np.cos(2 * np.pi * 2.0 * t), name="example")


def test_properties_and_arrays():
    m = example_motion()
    assert (m.n, m.duration) == (1001, pytest.approx(10.0, rel=1e-15))
    np.testing.assert_allclose(m.t, 0.01 * np.arange(1001), rtol=1e-15)
    t0, dt, ah, av = m.with_vertical(None).as_arrays()
    assert (t0, dt) == (0.0, 0.01) and ah.dtype == av.dtype == np.float64
    assert ah.flags.c_contiguous and not np.any(av)
    with pytest.raises(ValueError):
        GroundMotion(0.0, 0.01, [0.0, np.nan])


def test_scaled_to_pga_exact():
    m = example_motion()
    s = m.scaled_to_pga(3.0)
    # one rounding of the product: |max|a|·(3/max|a|) − 3| ≤ 2 ulp
    assert abs(s.pga - 3.0) <= 2 * np.spacing(3.0)
    factor = 3.0 / m.pga
    np.testing.assert_allclose(s.a_ver, factor * m.a_ver, rtol=1e-15, atol=0)  # proportional
    v = m.scaled_to_pga(1.0, component="ver")
    assert abs(v.pga_ver - 1.0) <= 2 * np.spacing(1.0)


def test_baseline_removes_linear_velocity_drift_exactly():
    m = example_motion()
    offset = 0.037  # a constant acceleration offset = a linear drift c·t in velocity
    drifted = dataclasses.replace(m, a_hor=m.a_hor + offset, a_ver=m.a_ver - offset)
    c0, c1 = m.baseline_corrected(1), drifted.baseline_corrected(1)
    # the trapezoidal rule integrates a constant exactly and least squares removes c·t exactly
    np.testing.assert_allclose(c1.a_hor, c0.a_hor, rtol=0, atol=1e-13)
    np.testing.assert_allclose(c1.a_ver, c0.a_ver, rtol=0, atol=1e-13)
    v = c1.velocity()
    slope = np.polynomial.polynomial.polyfit(m.t, v, 1)[1]
    assert abs(slope) < 1e-13  # no linear trend left in the velocity
    const = GroundMotion(0.0, 0.01, np.full(500, 0.2))
    assert np.max(np.abs(const.baseline_corrected(1).a_hor)) < 1e-14
    # order 2: a linear acceleration trend (parabolic velocity drift) goes exactly as well
    ramp = dataclasses.replace(m, a_hor=m.a_hor + 0.01 * m.t)
    np.testing.assert_allclose(
        ramp.baseline_corrected(2).a_hor, m.baseline_corrected(2).a_hor, rtol=0, atol=1e-12
    )
    # on the acceleration, order 0 removes the mean: least squares on the column of ones
    # (condition 1) by an orthogonal factorisation is backward stable, so the fitted mean is
    # within n u max|a| of the exact one (Higham, Accuracy and Stability, §20.3), and the mean
    # of the result, a sum of n rounded terms, within as much again
    bound = 2 * m.n * np.finfo(float).eps / 2 * np.abs(m.a_hor).max()
    assert abs(np.mean(m.baseline_corrected(0, on="acceleration").a_hor)) <= bound


@pytest.mark.parametrize("dt_new", [0.005, 0.0125, 0.02, 0.03])
def test_resampling_preserves_low_frequency_sine(dt_new):
    A, f = 2.0, 1.0
    m = harmonic(A, f, 20.0, 0.01, phase=0.3)
    r = m.resampled(dt_new)
    assert r.duration <= m.duration + 1e-12 and r.duration > m.duration - dt_new
    exact = A * np.sin(2 * np.pi * f * r.t + 0.3)
    # Kaiser window β = 5 in resample_poly: passband ripple δ = 10^(−A_s/20) with
    # A_s = β/0.1102 + 8.7 = 54 dB → δ ≈ 2e-3 (Kaiser's design formula)
    assert np.max(np.abs(r.a_hor - exact)) <= 2e-3 * A
    lin = m.resampled(dt_new, method="linear")
    # linear interpolation error ≤ max|a''| dt_old² / 8 = A ω² dt² / 8
    bound = A * (2 * np.pi * f * m.dt) ** 2 / 8
    assert np.max(np.abs(lin.a_hor - A * np.sin(2 * np.pi * f * lin.t + 0.3))) <= bound


def test_window_and_with_vertical():
    m = example_motion()
    w = m.window(2.004, 3.0)
    assert w.t0 == pytest.approx(2.01, abs=1e-12) and w.n == 100
    np.testing.assert_array_equal(w.a_hor, m.a_hor[201:301])
    r = m.with_vertical(2 / 3)
    np.testing.assert_array_equal(r.a_ver, 2 / 3 * m.a_hor)
    assert m.with_vertical(None).a_ver is None
    for bad in ("0.5", True):  # (read as the ratios 0.5 and 1)
        with pytest.raises(ValueError, match=r"^a_ver: expected a ratio r"):
            m.with_vertical(bad)
    # an infinite end is the record's own (math.floor(inf) raised OverflowError); NaN is
    # refused naming the window
    assert m.window(-np.inf, np.inf).n == m.n and m.window(2.004, np.inf).n == m.n - 201
    with pytest.raises(ValueError, match="^window: expected times"):
        m.window(np.nan, 3.0)


def test_a_one_sample_record_is_not_resampled():
    # scipy's polyphase filter ended the process (SIGFPE) on one sample: refused, named
    from nsdyn.ground import GroundMotion3

    with pytest.raises(ValueError, match="resampling needs two samples or more, got 1"):
        GroundMotion(0.0, 0.01, np.array([1.0])).resampled(0.005)
    with pytest.raises(ValueError, match="resampling needs two samples or more, got 1"):
        GroundMotion3(0.0, 0.01, np.array([1.0]), np.array([1.0])).resampled(0.005)


# ------------------------------------------------------------------------------------------
# Scaling identities over random records (property tests)
# ------------------------------------------------------------------------------------------

EPS = np.finfo(float).eps
# [m/s²] a plausible sample: zero, or of magnitude 1e-6 … 50 (no product with c underflows)
ORDINATE = st.just(0.0) | st.floats(1e-6, 50.0) | st.floats(-50.0, -1e-6)
TARGET = st.floats(1e-3, 1e3)  # [m/s²] target PGA


@st.composite
def records(draw) -> GroundMotion:
    """A record of 1–200 samples with a nonzero horizontal peak, with or without vertical."""
    n = draw(st.integers(1, 200))
    a_hor = draw(arrays(np.float64, n, elements=ORDINATE).filter(lambda a: np.abs(a).max() > 1e-6))
    a_ver = draw(st.none() | arrays(np.float64, n, elements=ORDINATE))
    dt = draw(st.floats(1e-3, 0.1))  # (a source: peaks of 1e-6 m/s² are meant, not units)
    return GroundMotion(0.0, dt, a_hor, a_ver, name="random", source="hypothesis")


def _ratios(scaled: np.ndarray, original: np.ndarray) -> np.ndarray:
    keep = original != 0.0
    return scaled[keep] / original[keep]


@settings(max_examples=200, deadline=None)
@given(m=records(), target=TARGET)
def test_scaled_to_pga_is_one_factor_and_hits_the_target(m, target):
    # Source: scaling is ü → c ü with one c = target / PGA for both components, so every
    # ordinate's ratio is c (each product rounded once: ≤ 1 ulp, the ratio ≤ 2 ulp more) and
    # the new peak is c·PGA = target to two roundings.
    s = m.scaled_to_pga(target)
    c = target / m.pga
    np.testing.assert_allclose(_ratios(s.a_hor, m.a_hor), c, rtol=4 * EPS, atol=0)
    assert np.array_equal(s.a_hor == 0.0, m.a_hor == 0.0)
    if m.a_ver is not None:
        np.testing.assert_allclose(_ratios(s.a_ver, m.a_ver), c, rtol=4 * EPS, atol=0)
    assert abs(s.pga - target) <= 2 * np.spacing(target)
    assert s.meta["scale_factor"] == pytest.approx(c, rel=4 * EPS)
    assert (s.t0, s.dt, s.n) == (m.t0, m.dt, m.n)  # the time grid is untouched


@settings(max_examples=200, deadline=None)
@given(m=records(), first=TARGET, target=TARGET)
def test_scaling_twice_is_scaling_once(m, first, target):
    # Source: c2 (c1 ü) = (c2 c1) ü with c2 c1 = target / PGA: the composition is the single
    # scaling, to a few roundings per ordinate (each bounded by |ü'| ≤ target), and the
    # recorded scale factors compose by multiplication.
    once = m.scaled_to_pga(target)
    twice = m.scaled_to_pga(first).scaled_to_pga(target)
    tol = 8 * np.spacing(target)
    assert np.abs(twice.a_hor - once.a_hor).max() <= tol
    if m.a_ver is not None:
        ver_tol = 8 * EPS * np.abs(once.a_ver).max()
        assert np.abs(twice.a_ver - once.a_ver).max() <= ver_tol
    assert twice.meta["scale_factor"] == pytest.approx(once.meta["scale_factor"], rel=8 * EPS)
    assert abs(twice.pga - target) <= 2 * np.spacing(target)


@settings(max_examples=100, deadline=None)
@given(m=records().filter(lambda m: m.a_ver is not None and m.pga_ver > 1e-6), target=TARGET)
def test_scaled_to_vertical_pga(m, target):
    # Source: component="ver" takes c = target / PGA_ver for both components.
    s = m.scaled_to_pga(target, component="ver")
    assert abs(s.pga_ver - target) <= 2 * np.spacing(target)
    np.testing.assert_allclose(_ratios(s.a_hor, m.a_hor), target / m.pga_ver, rtol=4 * EPS)


def test_until_cuts_at_an_absolute_end_and_refuses_an_end_within_the_first_step():
    # t_end is a time on the record's own clock (a run's t_end): a record that starts at
    # 10 s cut at 10.5 s keeps the samples 10.00 … 10.50; an end before 10 + dt keeps one
    # sample, a run of no time, and is refused naming t_end
    m = GroundMotion(t0=10.0, dt=0.01, a_hor=np.arange(200.0))
    cut = m.until(10.5)
    assert cut.t0 == 10.0 and cut.n == 51 and cut.a_hor[-1] == 50.0
    for bad in (10.0 + 1e-9, 10.0, 5.0, float("nan")):
        with pytest.raises(ValueError, match=r"^t_end: expected an end at least one record step"):
            m.until(bad)
    assert m.until(10.01).n == 2
    for bad in ("10.5", True):  # (text and a bool were read as times)
        with pytest.raises(ValueError, match=r"^t_end: expected an end time \[s\] \(a number\)"):
            m.until(bad)


def test_a_record_names_the_argument_it_cannot_use():
    # each was an error from inside numpy or Python (or, for meta=None, one in a later run)
    from nsdyn import GroundMotion3, motion3_from_table
    from nsdyn.ground import modulated_white_noise

    m = GroundMotion(0.0, 0.01, np.sin(0.1 * np.arange(100)))
    for call, err, match in (
        (lambda: m.window(None, 1.0), ValueError, r"^window: expected times"),
        (lambda: m.baseline_corrected(order=1.5), ValueError, r"^order: expected a whole"),
        (lambda: m.resampled("abc"), ValueError, r"^dt: expected a positive finite step"),
        # 1e-9 s built 1e9 samples of the 0.99 s record (8 GB)
        (lambda: m.resampled(1e-9, "linear"), ValueError, r"^dt: 9.9e\+08 samples of 1e-09 s"),
        (lambda: GroundMotion(0.0, 0.01, [1.0, 2.0], meta=None), TypeError, r"^meta: expected"),
        (lambda: GroundMotion3.from_planar(GroundMotion3(0.0, 0.01, [1.0, 2], [1.0, 2])),
         TypeError, r"^motion: expected a planar GroundMotion"),
        (lambda: motion3_from_table("x"), TypeError, r"^table: expected a \[motion\] table"),
        # 1e11 samples: a MemoryError of 745 GiB
        (lambda: modulated_white_noise(1e9), ValueError, r"^duration, dt: 1e\+11 samples"),
        # pathlib's "expected str, bytes or os.PathLike object, not NoneType"
        (lambda: read_motion(None), TypeError, r"^path_or_name: expected a file path or a"),
        # "ay: expected real accelerations [m/s²], got non-numeric values"
        (lambda: GroundMotion3(0.0, 0.01, [1.0, 2.0], None), ValueError,
         r"^GroundMotion3.ay: missing; expected the second horizontal component"),
    ):  # fmt: skip
        with pytest.raises(err, match=match):
            call()
    assert m.window(0.5, math.inf).n == 50  # (an infinite end: the record's own)
