"""Synthetic ground motions: modulated white noise, Kanai–Tajimi, harmonic and sine pulses.

Synthetic records (seed 000 §4.1, after Shinozuka & Sato 1967):

    ẍ_g(t) = G(t) W(t),    G(t) = 4 (e^(−0.25 t) − e^(−0.5 t))       (peak G = 1 at t = 4 ln 2)

with W stationary Gaussian white noise of intensity S0 [m²/s³].

PSD convention used throughout: S(ω) is the *two-sided* PSD in angular frequency,
R(τ) = ∫ S(ω) e^(iωτ) dω over −∞ … ∞, so ideal white noise of intensity S0 has R(τ) = 2π S0 δ(τ).
A sample of it is built as in seed 000: iid N(0, σ²) ordinates every Δ, linearly interpolated. The
interpolated process has the (time-averaged) PSD

    S(ω) = σ² Δ / (2π) · sinc⁴(ωΔ/2),     sinc(x) = sin(x)/x,

so S(0) = S0 requires σ² = 2π S0 / Δ (the factor √(2π S0/Δ) of seed 000; Ruiz & Penzien 1969).
scipy.signal.welch returns the one-sided PSD per Hz, G(f) = 4π S(2πf). Sampled at dt = Δ/L
(L integer) the record is a discrete linear interpolation of the ordinates, whose PSD is exactly
G(f) = 4π S0 [sin(π f Δ) / (L sin(π f dt))]⁴  (→ 4π S0 sinc⁴(π f Δ) for f ≪ 1/dt).

Kanai–Tajimi (Kanai 1957, Tajimi 1960): bedrock white noise w through the ground layer
ÿ + 2ζ_g ω_g ẏ + ω_g² y = −w, ü_g = −(2ζ_g ω_g ẏ + ω_g² y), so

    S_KT(ω) = S0 (ω_g⁴ + 4ζ_g²ω_g²ω²) / ((ω_g² − ω²)² + 4ζ_g²ω_g²ω²),
    var(ü_g) = π S0 ω_g (1 + 4ζ_g²) / (2ζ_g).

The filter is discretised exactly for white-noise input (Van Loan 1978), so the samples are exact
samples of the continuous KT process (their PSD is S_KT aliased at the sampling rate).

Deterministic motions: harmonic a(t) = A sin(2π f t + φ); sine pulses of n full cycles.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from nsdyn._checks import MAX_OUTPUTS, non_negative_int, number
from nsdyn.ground.motion import GroundMotion

KT_WARMUP_DECAYS = 30.0  # KT filter warm-up, in time constants 1/(ζ_g ω_g) (e^-30 ≈ 1e-13)
SEED000_S0 = 1.25e-4  # seed 000: S0 = 0.000125 m²/s³
SEED000_DT_ORD = 0.05  # seed 000: ordinates every Δ = 0.05 s
SEED000_VERTICAL_RATIO = 2.0 / 3.0  # seed 000: vertical = 2/3 of horizontal
NOISE_GENERATORS = ("modulated_white_noise", "kanai_tajimi")  # records a study simulates
KT_OMEGA_G = 15.6  # Kanai–Tajimi firm ground (Housner & Jennings 1964) [rad/s]
KT_ZETA_G = 0.6  # Kanai–Tajimi firm ground damping ratio


def _rng(seed: int | np.random.Generator | None) -> tuple[np.random.Generator, Any]:
    """A Generator and a JSON-able record of the seed (entropy of a fresh one, so that an
    unseeded run can still be repeated)."""
    if isinstance(seed, np.random.Generator):
        return seed, "numpy Generator (state not recorded)"
    if seed is None:
        ss = np.random.SeedSequence()
        return np.random.default_rng(ss), int(ss.entropy)
    seed = non_negative_int("seed", seed)
    return np.random.default_rng(seed), seed


def grid_step(duration: float, dt: float, nyquist: float | None = None) -> tuple[float, float]:
    """``(duration, dt)`` of a record sampled every dt over ``duration``, or ValueError naming
    either: a step longer than the duration, or not shorter than ``nyquist`` [s] (half the
    shortest period the record must carry)."""
    duration = number("duration", duration, "a positive duration [s]", lambda v: v > 0)
    what = f"a positive sampling step of at most the duration, {duration:g} s"
    if nyquist is not None:
        what += f", and below half the period, {nyquist:g} s"
    dt = number("dt", dt, what, lambda v: 0 < v <= duration and not (nyquist and v >= nyquist))
    if duration / dt > MAX_OUTPUTS:  # (1e9 s was a MemoryError of 745 GiB)
        raise ValueError(f"duration, dt: {duration / dt:.3g} samples; expected a record of at "
                         f"most {MAX_OUTPUTS:.0e} samples")  # fmt: skip
    return duration, dt


def noise_step(generator: str, duration: float, dt: float) -> None:
    """ValueError naming ``duration`` or ``dt`` where a :data:`NOISE_GENERATORS` record of
    default parameters cannot be sampled so (white-noise ordinates closer than the step, a
    Kanai–Tajimi ground frequency past the Nyquist frequency)."""
    if generator not in NOISE_GENERATORS:
        raise ValueError(f"generator: expected one of {list(NOISE_GENERATORS)}, got {generator!r}")
    nyq = math.pi / KT_OMEGA_G if generator == "kanai_tajimi" else None
    duration, dt = grid_step(duration, dt, nyq)
    if generator == "modulated_white_noise":
        number("dt", dt, f"a step of at most the noise's ordinate step {SEED000_DT_ORD:g} s",
               lambda v: v <= SEED000_DT_ORD * (1.0 + 1e-12))  # fmt: skip


def _grid(duration: float, dt: float, nyquist: float | None = None) -> np.ndarray:
    """Samples t = k dt over ``duration`` (see :func:`grid_step`)."""
    duration, dt = grid_step(duration, dt, nyquist)
    return dt * np.arange(int(round(duration / dt)) + 1)


def shinozuka_envelope(t: np.ndarray | float) -> np.ndarray:
    """Seed 000 eq (4.1): G(t) = 4 (e^(−0.25 t) − e^(−0.5 t)) for t ≥ 0, 0 before."""
    t = np.asarray(t, dtype=np.float64)
    tp = np.maximum(t, 0.0)
    return np.where(t >= 0.0, 4.0 * (np.exp(-0.25 * tp) - np.exp(-0.5 * tp)), 0.0)


def _noise_motion(
    generator: str,
    call: dict[str, Any],
    t: np.ndarray,
    a_hor: np.ndarray,
    a_ver: np.ndarray | None,
    params: dict[str, Any],
    name: str,
) -> GroundMotion:
    """The record of a stationary noise sample on the grid t = k dt, times G(t) when
    ``call["modulate"]``. ``call`` holds the generator's arguments in signature order (``dt``,
    the recorded ``seed``, ``modulate`` among them) and becomes the source text; the meta names
    the generator, the seed and ``params``."""
    modulate = call["modulate"]
    if modulate:
        env = shinozuka_envelope(t)
        a_hor = env * a_hor
        a_ver = None if a_ver is None else env * a_ver
    meta = {
        "generator": generator,
        "seed": call["seed"],
        **params,
        "modulation": "G(t)=4(exp(-0.25t)-exp(-0.5t))" if modulate else None,
    }
    source = f"synthetic: {generator}({', '.join(f'{k}={v}' for k, v in call.items())})"
    return GroundMotion(0.0, call["dt"], a_hor, a_ver, name=name, source=source, meta=meta)


def modulated_white_noise(
    duration: float,
    S0: float = SEED000_S0,
    dt_ord: float = SEED000_DT_ORD,
    dt: float = 0.01,
    vertical_ratio: float | None = SEED000_VERTICAL_RATIO,
    seed: int | np.random.Generator | None = None,
    *,
    modulate: bool = True,
    name: str = "modulated-white-noise",
) -> GroundMotion:
    """Seed 000 §4.1 simulated earthquake: a_hor = G(t) W1(t), a_ver = r G(t) W3(t).

    W is stationary Gaussian white noise of two-sided intensity S0 [m²/s³]: iid N(0, σ²) ordinates
    every ``dt_ord`` = Δ with σ² = 2π S0/Δ (see the module docstring), linearly interpolated to the
    output step ``dt``. W3 is independent of W1 with the same intensity; r = ``vertical_ratio``
    scales its amplitude (so RMS(a_ver)/RMS(a_hor) = r in expectation; its intensity is r² S0).
    ``modulate=False`` gives the stationary process W itself (same random numbers).
    """
    if not (math.isfinite(S0) and S0 >= 0):
        raise ValueError(f"S0: expected a non-negative spectral intensity [m²/s³], got {S0!r}")
    t = _grid(duration, dt)
    # ordinates closer than the output step would be sampled, not interpolated: the record's
    # intensity would be S0 dt / dt_ord, not S0
    number("dt_ord", dt_ord, f"an ordinate step [s] of at least the output step dt = {dt:g} s",
           lambda v: v >= dt * (1.0 - 1e-12))  # fmt: skip
    rng, seed_record = _rng(seed)
    n_ord = int(math.ceil(t[-1] / dt_ord - 1e-9)) + 1
    t_ord = dt_ord * np.arange(n_ord)
    sigma = math.sqrt(2.0 * math.pi * S0 / dt_ord)
    w_hor = sigma * rng.standard_normal(n_ord)
    w_ver = sigma * rng.standard_normal(n_ord)  # drawn always: same a_hor with or without ver
    a_hor = np.interp(t, t_ord, w_hor)
    a_ver = None if not vertical_ratio else vertical_ratio * np.interp(t, t_ord, w_ver)
    call = {
        "duration": duration,
        "S0": S0,
        "dt_ord": dt_ord,
        "dt": dt,
        "vertical_ratio": vertical_ratio,
        "seed": seed_record,
        "modulate": modulate,
    }
    params = {
        "S0": S0,
        "dt_ord": dt_ord,
        "sigma_ordinates": sigma,
        "vertical_ratio": vertical_ratio,
    }
    return _noise_motion("modulated_white_noise", call, t, a_hor, a_ver, params, name)


def kanai_tajimi_psd(
    omega: np.ndarray | float, omega_g: float = KT_OMEGA_G, zeta_g: float = KT_ZETA_G, S0=1.0
) -> np.ndarray:
    """Two-sided Kanai–Tajimi PSD S0 (ω_g⁴ + 4ζ_g²ω_g²ω²)/((ω_g² − ω²)² + 4ζ_g²ω_g²ω²)."""
    w2 = np.asarray(omega, dtype=np.float64) ** 2
    c = 4.0 * zeta_g**2 * omega_g**2
    return S0 * (omega_g**4 + c * w2) / ((omega_g**2 - w2) ** 2 + c * w2)


def _kt_stationary(
    n: int, dt: float, omega_g: float, zeta_g: float, S0: float, rng: np.random.Generator
) -> np.ndarray:
    """n exact samples (step dt) of the stationary KT process driven by white noise of intensity
    S0: Van Loan discretisation x_{k+1} = Φ x_k + L z_k, z_k ~ N(0, I), a_k = C x_k, run through
    a warm-up of KT_WARMUP_DECAYS time constants from rest so the kept part is stationary."""
    A = np.array([[0.0, 1.0], [-(omega_g**2), -2.0 * zeta_g * omega_g]])
    B = np.array([[0.0], [-1.0]])
    C = np.array([[-(omega_g**2), -2.0 * zeta_g * omega_g]])
    Qc = 2.0 * math.pi * S0 * (B @ B.T)
    from scipy import linalg, signal  # on first use: costly to import at start-up

    F = linalg.expm(np.block([[-A, Qc], [np.zeros((2, 2)), A.T]]) * dt)
    Phi = F[2:, 2:].T
    Qd = Phi @ F[:2, 2:]
    L = linalg.cholesky(0.5 * (Qd + Qd.T), lower=True)
    n_warm = int(math.ceil(KT_WARMUP_DECAYS / (zeta_g * omega_g * dt)))
    z = rng.standard_normal((n_warm + n, 2))
    a = np.zeros(n_warm + n)
    for j in range(2):
        num, den = signal.ss2tf(Phi, L, C, np.zeros((1, 2)), input=j)
        a += signal.lfilter(num[0], den, z[:, j])
    return a[n_warm:]


def kanai_tajimi(
    duration: float,
    omega_g: float = KT_OMEGA_G,
    zeta_g: float = KT_ZETA_G,
    S0: float = SEED000_S0,
    seed: int | np.random.Generator | None = None,
    *,
    dt: float = 0.01,
    modulate: bool = True,
    vertical_ratio: float | None = None,
    name: str = "kanai-tajimi",
) -> GroundMotion:
    """Kanai–Tajimi filtered white noise (see the module docstring for the filter and PSD).

    The horizontal (and, with ``vertical_ratio`` r, an independent vertical scaled by r) are
    exact samples of the stationary KT process with bedrock intensity S0; ``modulate=True``
    multiplies them by G(t) of seed 000 (a uniformly modulated process, evolutionary PSD
    G(t)² S_KT(ω)).
    """
    t = _grid(duration, dt)
    number("omega_g", omega_g, f"a positive ground frequency [rad/s] below the record's "
           f"Nyquist frequency pi/dt = {math.pi / dt:.4g} rad/s",
           lambda v: 0 < v < math.pi / dt)  # fmt: skip
    number("zeta_g", zeta_g, "a positive ground damping ratio", lambda v: v > 0)
    if not (math.isfinite(S0) and S0 >= 0):
        raise ValueError(f"S0: expected a non-negative spectral intensity [m²/s³], got {S0!r}")
    rng, seed_record = _rng(seed)
    a_hor = _kt_stationary(t.size, dt, omega_g, zeta_g, S0, rng)
    a_ver = _kt_stationary(t.size, dt, omega_g, zeta_g, S0, rng)
    a_ver = None if not vertical_ratio else vertical_ratio * a_ver
    call = {
        "duration": duration,
        "omega_g": omega_g,
        "zeta_g": zeta_g,
        "S0": S0,
        "seed": seed_record,
        "dt": dt,
        "modulate": modulate,
        "vertical_ratio": vertical_ratio,
    }
    params = {"S0": S0, "omega_g": omega_g, "zeta_g": zeta_g, "vertical_ratio": vertical_ratio}
    return _noise_motion("kanai_tajimi", call, t, a_hor, a_ver, params, name)


def harmonic(
    A: float, f: float, duration: float, dt: float, phase: float = 0.0, *, name: str = "harmonic"
) -> GroundMotion:
    """a(t) = A sin(2π f t + phase) on 0 ≤ t ≤ duration."""
    number("f", f, "a positive frequency [Hz]", lambda v: v > 0)
    t = _grid(duration, dt, nyquist=0.5 / f)
    a = A * np.sin(2.0 * np.pi * f * t + phase)
    meta = {"generator": "harmonic", "A": A, "f": f, "phase": phase}
    return GroundMotion(0.0, dt, a, None, name=name, source=f"harmonic(A={A}, f={f})", meta=meta)


def sine_pulse(
    A: float,
    f: float,
    n_cycles: int = 1,
    dt: float = 0.01,
    kind: str = "sine",
    *,
    duration: float | None = None,
    name: str = "sine-pulse",
) -> GroundMotion:
    """Pulse of ``n_cycles`` full cycles of frequency f (T_p = n_cycles/f), zero afterwards up to
    ``duration`` (default T_p); seed 003 Table 4 uses kind="sine", n_cycles=1, T_p = 0.5 s.

    kind="sine":   a = A sin(ωt): a = 0 at both ends, velocity returns to 0 at T_p, the
                   displacement keeps the offset A T_p/ω (a "forward" pulse).
    kind="cosine": a = A cos(ωt) (a jumps to A at t = 0 and from A to 0 after T_p): velocity
                   A sin(ωt)/ω and displacement A(1 − cos ωt)/ω² both return to 0 at T_p.
    """
    if kind not in ("sine", "cosine"):
        raise ValueError(f"kind must be 'sine' or 'cosine', got {kind!r}")
    if n_cycles < 1:
        raise ValueError("n_cycles must be >= 1")
    if not (math.isfinite(f) and f > 0):
        raise ValueError(f"f: expected a positive pulse frequency [Hz], got {f!r}")
    if not math.isfinite(A):
        raise ValueError(f"A: expected a finite amplitude [m/s²], got {A!r}")
    tp = n_cycles / f
    if duration is not None and not duration >= tp * (1.0 - 1e-12):  # (it was lengthened)
        raise ValueError(f"duration: expected at least the pulse's {n_cycles} cycle(s), "
                         f"T_p = {tp:g} s, or None (T_p), got {duration!r}")  # fmt: skip
    t = _grid(duration or tp, dt, nyquist=0.5 / f)
    inside = t <= tp * (1.0 + 1e-12)
    phase = 2.0 * np.pi * f * t[inside]
    a = np.zeros(t.size)
    if kind == "sine":
        a[inside] = A * np.sin(phase)
        k_end = round(tp / dt)
        if abs(k_end * dt - tp) <= 1e-9 * tp:
            a[k_end] = 0.0  # the pulse ends on a sample: sin(2π n) is 0, not ±1e-16
    else:
        a[inside] = A * np.cos(phase)
    meta = {"generator": "sine_pulse", "A": A, "f": f, "n_cycles": n_cycles, "kind": kind}
    return GroundMotion(
        0.0, dt, a, None, name=name, source=f"sine_pulse(A={A}, f={f}, {kind})", meta=meta
    )
