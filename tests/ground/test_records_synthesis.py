"""Synthetic ground motions: envelope, white noise and Kanai–Tajimi statistics, pulses.

Expected values are closed forms (the envelope's peak, the Kanai–Tajimi variance, harmonic and
pulse integrals) and statistical bands derived from the estimators' variances.
"""

import math

import numpy as np
import pytest
from scipy import integrate, signal

from nsdyn.ground import (
    G_STANDARD,
    harmonic,
    kanai_tajimi,
    kanai_tajimi_psd,
    modulated_white_noise,
    shinozuka_envelope,
    sine_pulse,
)

N_SIGMA = 5.0  # statistical checks: |estimate − expectation| ≤ 5 standard deviations

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


@pytest.mark.parametrize(
    ("call", "match"),
    [
        # a step of 1 s over a 0.5 s pulse gave one sample; at dt = 1/(2 f) every sample of a
        # sine pulse is sin(k pi) = 0: a record of zeros
        (lambda: sine_pulse(1.0, 2.0, dt=1.0), r"^dt: expected .* below half the period"),
        (lambda: sine_pulse(1.0, 2.0, dt=0.25), r"^dt: expected .* below half the period"),
        (lambda: harmonic(1.0, 60.0, 2.0, 0.01), r"^dt: expected .* below half the period"),
        # ordinates finer than the output were sampled, not interpolated: intensity S0 dt/dt_ord
        (lambda: modulated_white_noise(5.0, dt_ord=0.005, dt=0.01, seed=1),
         r"^dt_ord: expected an ordinate step \[s\] of at least the output step"),
        # a ground frequency past Nyquist: the exact samples alias to another process
        (lambda: kanai_tajimi(5.0, omega_g=400.0, dt=0.01, seed=1),
         r"^omega_g: expected .* below the record's Nyquist frequency"),
        (lambda: harmonic(1.0, 1.0, "5", 0.01), r"^duration: expected a positive duration"),
    ],
)  # fmt: skip
def test_a_record_that_cannot_carry_its_motion_is_refused(call, match):
    with pytest.raises(ValueError, match=match):
        call()
