"""Ground motions: the record, its readers and writers, scaling, correction and synthesis.

A ground motion is the base acceleration ü_g(t) = [ü_hor(t), ü_ver(t)] in m/s², sampled on a uniform
grid t_k = t0 + k Δt, k = 0 … n−1. The structure is loaded by −M Γ ü with ü = [ü_hor, ü_ver + g];
gravity is *not* part of ``a_ver``.

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

Units on disk: "g" (9.80665 m/s²), "cm/s2" (= gal) or "m/s2"; in memory always m/s².
HDF5 files (e.g. the FEMA P695 sets) are not read: that would need h5py and hdf5plugin, which are
not dependencies of nsdyn.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import re
import warnings
from dataclasses import dataclass, field
from fractions import Fraction
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from scipy import integrate, linalg, signal

from .atomic import atomic_open

__all__ = [
    "G_STANDARD",
    "GroundMotion",
    "RecordFileError",
    "UnitWarning",
    "bundled_records",
    "default_shared_dir",
    "harmonic",
    "kanai_tajimi",
    "kanai_tajimi_psd",
    "kobe_records",
    "modulated_white_noise",
    "read_at2",
    "read_jma",
    "read_motion",
    "read_multi_column",
    "read_single_column",
    "read_two_column",
    "shinozuka_envelope",
    "sine_pulse",
    "unit_factor",
    "write_motion",
]

G_STANDARD = 9.80665  # standard gravity [m/s²], used to convert records in g
PGA_MAX_PLAUSIBLE = 30.0  # [m/s²] above this a record is probably in cm/s² (or m/s² read as g)
PGA_MIN_PLAUSIBLE = 0.01  # [m/s²] below this a record is probably in g read as m/s²
STEP_RTOL = 0.05  # each time step of a time column within 5 % of the median step
GRID_RTOL = 0.01  # every time stamp within 1 % of a step of the uniform grid t0 + k dt
DT_RTOL = 1e-3  # dt stated in a header vs dt of the time column
DT_DIGITS = 12  # significant digits kept of a dt fitted to a printed time column
HEADER_SEARCH_LINES = 12  # an AT2 "NPTS, DT" line must lie within the first lines
KT_WARMUP_DECAYS = 30.0  # KT filter warm-up, in time constants 1/(ζ_g ω_g) (e^-30 ≈ 1e-13)
SEED000_S0 = 1.25e-4  # seed 000: S0 = 0.000125 m²/s³
SEED000_DT_ORD = 0.05  # seed 000: ordinates every Δ = 0.05 s
SEED000_VERTICAL_RATIO = 2.0 / 3.0  # seed 000: vertical = 2/3 of horizontal
KT_OMEGA_G = 15.6  # Kanai–Tajimi firm ground (Housner & Jennings 1964) [rad/s]
KT_ZETA_G = 0.6  # Kanai–Tajimi firm ground damping ratio

_COMMENT_PREFIXES = ("#", "%", ";", "!", "//")
_NUM = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][+-]?\d+)?"
_FORTRAN_RUN = re.compile(rf"(?:{_NUM})+")
_FORTRAN_ONE = re.compile(r"[+-]?(?:\d+\.\d*|\.\d+)(?:[EeDd][+-]?\d+)?")
_TIME_NAMES = {"t", "time", "time_s", "t_s", "time(s)", "t[s]", "t(s)", "time[s]", "sec", "seconds"}
_VERTICAL_NAMES = {"a_ver", "ver", "vertical", "ud", "up", "z", "a_z", "vert", "accel_ver"}


class RecordFileError(ValueError):
    """A record file that cannot be read; names the file, the line and what was expected."""

    def __init__(self, source: str | os.PathLike, line: int | None, message: str):
        self.source = str(source)
        self.line = line
        self.reason = message
        where = f"{self.source}:{line}" if line is not None else self.source
        super().__init__(f"{where}: {message}")


class UnitWarning(UserWarning):
    """The units of a record were assumed, or its PGA looks like the wrong unit."""


# --------------------------------------------------------------------------------------------
# The record
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False, repr=False)
class GroundMotion:
    """Uniformly sampled base acceleration.

    Attributes
    ----------
    t0 : float
        Time of the first sample [s].
    dt : float
        Sampling interval [s], uniform.
    a_hor : ndarray, shape (n,)
        Horizontal ground acceleration [m/s²].
    a_ver : ndarray, shape (n,) or None
        Vertical ground acceleration [m/s²], without gravity; None when the record has none.
    name : str
        Short name (a bundled record's name, a file stem, a station).
    source : str
        Path of the file it was read from, or a description of how it was made.
    meta : dict
        Anything else (units on file, header, seed, scale factor, …).
    """

    t0: float
    dt: float
    a_hor: np.ndarray
    a_ver: np.ndarray | None = None
    name: str = "motion"
    source: str = ""
    meta: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        a_hor = np.ascontiguousarray(self.a_hor, dtype=np.float64)
        if a_hor.ndim != 1 or a_hor.size < 1:
            raise ValueError(f"a_hor must be 1-D and non-empty, got shape {a_hor.shape}")
        if not np.all(np.isfinite(a_hor)):
            raise ValueError("a_hor holds NaN or inf")
        dt = float(self.dt)
        if not (math.isfinite(dt) and dt > 0.0):
            raise ValueError(f"dt must be positive and finite, got {self.dt!r}")
        object.__setattr__(self, "a_hor", a_hor)
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "t0", float(self.t0))
        if self.a_ver is not None:
            a_ver = np.ascontiguousarray(self.a_ver, dtype=np.float64)
            if a_ver.shape != a_hor.shape:
                raise ValueError(f"a_ver has shape {a_ver.shape}, a_hor has {a_hor.shape}")
            if not np.all(np.isfinite(a_ver)):
                raise ValueError("a_ver holds NaN or inf")
            object.__setattr__(self, "a_ver", a_ver)

    def __repr__(self) -> str:
        ver = "yes" if self.a_ver is not None else "no"
        return (
            f"GroundMotion(name={self.name!r}, n={self.n}, dt={self.dt:g} s, "
            f"duration={self.duration:g} s, pga={self.pga:.4g} m/s², vertical={ver})"
        )

    # ---- derived quantities ---------------------------------------------------------------
    @property
    def n(self) -> int:
        """Number of samples."""
        return int(self.a_hor.size)

    @property
    def t(self) -> np.ndarray:
        """Sample times t0 + k dt [s], shape (n,)."""
        return self.t0 + self.dt * np.arange(self.n)

    @property
    def duration(self) -> float:
        """(n − 1) dt [s]."""
        return (self.n - 1) * self.dt

    @property
    def pga(self) -> float:
        """Horizontal peak ground acceleration max |a_hor| [m/s²]."""
        return float(np.max(np.abs(self.a_hor)))

    @property
    def pga_ver(self) -> float | None:
        """Vertical peak max |a_ver| [m/s²], or None without a vertical component."""
        return None if self.a_ver is None else float(np.max(np.abs(self.a_ver)))

    def velocity(self, component: str = "hor") -> np.ndarray:
        """Ground velocity [m/s] by the trapezoidal rule from rest, shape (n,)."""
        return integrate.cumulative_trapezoid(self._component(component), dx=self.dt, initial=0.0)

    def displacement(self, component: str = "hor") -> np.ndarray:
        """Ground displacement [m]: trapezoidal rule applied twice from rest, shape (n,)."""
        return integrate.cumulative_trapezoid(self.velocity(component), dx=self.dt, initial=0.0)

    def as_arrays(self) -> tuple[float, float, np.ndarray, np.ndarray]:
        """``(t0, dt, a_hor, a_ver)`` for numba kernels: float64 C-contiguous, a_ver zeros if None.

        The arrays are the record's own (not copies); do not modify them.
        """
        a_ver = self.a_ver if self.a_ver is not None else np.zeros_like(self.a_hor)
        return self.t0, self.dt, self.a_hor, a_ver

    # ---- transformations (each returns a new record) --------------------------------------
    def _component(self, component: str) -> np.ndarray:
        if component == "hor":
            return self.a_hor
        if component == "ver":
            if self.a_ver is None:
                raise ValueError(f"{self.name!r} has no vertical component")
            return self.a_ver
        raise ValueError(f"component must be 'hor' or 'ver', got {component!r}")

    def _replace(self, **changes: Any) -> GroundMotion:
        meta = dict(self.meta)
        meta.update(changes.pop("meta_update", {}))
        return dataclasses.replace(self, meta=meta, **changes)

    def scaled_to_pga(self, target: float, component: str = "hor") -> GroundMotion:
        """Scale both components by one factor so that max |a_component| = target [m/s²].

        The vertical component stays proportional to the horizontal one.
        """
        peak = float(np.max(np.abs(self._component(component))))
        if peak == 0.0:
            raise ValueError(f"{self.name!r}: the {component} component is zero; cannot scale")
        factor = float(target) / peak
        a_ver = None if self.a_ver is None else self.a_ver * factor
        total = factor * float(self.meta.get("scale_factor", 1.0))
        return self._replace(
            a_hor=self.a_hor * factor, a_ver=a_ver, meta_update={"scale_factor": total}
        )

    def baseline_corrected(self, order: int = 1, on: str = "velocity") -> GroundMotion:
        """Least-squares polynomial baseline correction of each component.

        ``on="velocity"`` (default, the usual correction): integrate a to v (trapezoidal rule, from
        rest), fit a polynomial p of degree ``order`` ≥ 1 to v(τ) by least squares (τ = t − t0),
        and subtract p'(τ) from a. ``order=1`` removes a constant acceleration offset, i.e. a linear
        drift in velocity (exactly: the trapezoidal rule integrates a constant exactly);
        ``order=2`` a linear acceleration trend (a parabolic velocity drift).

        ``on="acceleration"``: fit p of degree ``order`` ≥ 0 to a itself and subtract p
        (``order=0`` removes the mean).
        """
        if on == "velocity" and order < 1:
            raise ValueError("on='velocity' needs order >= 1 (order 0 changes nothing in a)")
        if on not in ("velocity", "acceleration"):
            raise ValueError(f"on must be 'velocity' or 'acceleration', got {on!r}")
        if order < 0 or order >= self.n:
            raise ValueError(f"order must be in 0 … n−1 = {self.n - 1}, got {order}")
        span = max(self.duration, self.dt)
        x = np.arange(self.n) / max(self.n - 1, 1)  # τ / duration, well conditioned
        P = np.polynomial.Polynomial

        def correct(a: np.ndarray) -> np.ndarray:
            if on == "acceleration":
                return a - P.fit(x, a, order, domain=[0.0, 1.0], window=[0.0, 1.0])(x)
            v = integrate.cumulative_trapezoid(a, dx=self.dt, initial=0.0)
            p = P.fit(x, v, order, domain=[0.0, 1.0], window=[0.0, 1.0])
            return a - p.deriv()(x) / span

        a_ver = None if self.a_ver is None else correct(self.a_ver)
        return self._replace(
            a_hor=correct(self.a_hor),
            a_ver=a_ver,
            meta_update={"baseline": f"polynomial order {order} on {on}"},
        )

    def resampled(self, dt: float, method: str = "band-limited") -> GroundMotion:
        """Resample onto t0 + k dt (k dt ≤ duration).

        ``method="band-limited"`` (default): polyphase FIR resampling (scipy.signal.resample_poly,
        Kaiser window β = 5, passband ripple ≈ 2e-3) by the rational factor old dt / new dt
        (denominator ≤ 1000), with its built-in anti-alias low-pass at the lower Nyquist
        frequency; the ends are extended by odd reflection so value and slope stay continuous.
        ``method="linear"``: linear interpolation (no anti-aliasing; error ≤ max|a''| dt_old²/8).
        """
        dt = float(dt)
        if not dt > 0.0:
            raise ValueError(f"dt must be positive, got {dt}")
        n_new = int(math.floor(self.duration / dt * (1.0 + 1e-12) + 1e-9)) + 1
        if method == "linear":
            tau_new = dt * np.arange(n_new)
            tau_old = self.dt * np.arange(self.n)

            def res(a: np.ndarray) -> np.ndarray:
                return np.interp(tau_new, tau_old, a)

        elif method == "band-limited":
            ratio = Fraction(self.dt / dt).limit_denominator(1000)
            if abs(float(ratio) - self.dt / dt) > 1e-9 * (self.dt / dt):
                raise ValueError(
                    f"dt ratio {self.dt}/{dt} is not a ratio of integers ≤ 1000; "
                    "use method='linear'"
                )
            up, down = ratio.numerator, ratio.denominator

            def res(a: np.ndarray) -> np.ndarray:
                out = signal.resample_poly(a, up, down, padtype="antireflect")
                if out.size < n_new:  # cannot happen for exact ratios; guard anyway
                    out = np.pad(out, (0, n_new - out.size), mode="edge")
                return out[:n_new]

        else:
            raise ValueError(f"method must be 'band-limited' or 'linear', got {method!r}")
        a_ver = None if self.a_ver is None else res(self.a_ver)
        return self._replace(
            dt=dt, a_hor=res(self.a_hor), a_ver=a_ver, meta_update={"resampled": method}
        )

    def window(self, t_start: float, t_end: float) -> GroundMotion:
        """The samples with t_start ≤ t ≤ t_end (absolute times; t0 becomes the first kept t)."""
        eps = 1e-9
        i0 = max(0, math.ceil((t_start - self.t0) / self.dt - eps))
        i1 = min(self.n - 1, math.floor((t_end - self.t0) / self.dt + eps))
        if i1 < i0:
            raise ValueError(f"window [{t_start}, {t_end}] holds no sample of {self.name!r}")
        a_ver = None if self.a_ver is None else self.a_ver[i0 : i1 + 1].copy()
        return self._replace(
            t0=self.t0 + i0 * self.dt, a_hor=self.a_hor[i0 : i1 + 1].copy(), a_ver=a_ver
        )

    def with_vertical(self, a_ver: np.ndarray | float | None) -> GroundMotion:
        """Set the vertical component: an array of shape (n,), a ratio r (a_ver = r a_hor, fully
        correlated), or None to remove it."""
        if a_ver is None:
            return self._replace(a_ver=None)
        if np.isscalar(a_ver):
            ratio = float(a_ver)  # type: ignore[arg-type]
            return self._replace(a_ver=ratio * self.a_hor, meta_update={"vertical_ratio": ratio})
        return self._replace(a_ver=np.asarray(a_ver, dtype=np.float64))


# --------------------------------------------------------------------------------------------
# Units
# --------------------------------------------------------------------------------------------


def unit_factor(units: str) -> tuple[str, float]:
    """``(canonical name, factor to m/s²)`` for "g", "cm/s2" (gal) or "m/s2" and their spellings
    ("gal", "cm/s^2", "cm/sec^2", "cm/s/s", "m/s^2", "mm/s2", …)."""
    s = units.strip().lower().replace(" ", "").replace("sec", "s").replace("**", "^")
    s = s.replace("^", "").replace("²", "2")
    if s in ("g", "(g)"):
        return "g", G_STANDARD
    if s in ("gal", "gals", "cm/s2", "cm/s/s", "cms-2"):
        return "cm/s2", 0.01
    if s in ("m/s2", "m/s/s", "ms-2"):
        return "m/s2", 1.0
    if s in ("mm/s2", "mm/s/s"):
        return "mm/s2", 1e-3
    raise ValueError(f"unknown acceleration unit {units!r}; use 'g', 'cm/s2' (gal) or 'm/s2'")


_UNIT_PATTERNS = [
    re.compile(r"\bunits?\s*[:=]\s*\(?\s*([A-Za-z][\w/^*²]*)", re.I),  # units: g / UNIT = gal
    re.compile(r"\bacc(?:eleration|\.)?\s+in\s+\(?\s*([A-Za-z][\w/^*²]*)", re.I),  # Acc. in cm/s/s
    re.compile(r"\bin\s+units\s+of\s+\(?\s*([A-Za-z][\w/^*²]*)", re.I),  # IN UNITS OF G
    re.compile(r"\bunits\s+are\s+\(?\s*([A-Za-z][\w/^*²]*)", re.I),  # The units are (g)
]


def _header_units(header: list[str]) -> str | None:
    """Units stated in a header, by the patterns above in priority order; None if not stated."""
    text = "\n".join(header)
    for pattern in _UNIT_PATTERNS:
        for m in pattern.finditer(text):
            try:
                return unit_factor(m.group(1).rstrip("."))[0]
            except ValueError:
                continue
    return None


def _check_pga(motion: GroundMotion) -> None:
    pga = motion.pga
    if pga > PGA_MAX_PLAUSIBLE:
        warnings.warn(
            f"{motion.source}: PGA = {pga:.4g} m/s² > {PGA_MAX_PLAUSIBLE:g} m/s²; the file is "
            "probably in cm/s² (gal) read as m/s², or in m/s² read as g: pass units=",
            UnitWarning,
            stacklevel=3,
        )
    elif pga < PGA_MIN_PLAUSIBLE:
        warnings.warn(
            f"{motion.source}: PGA = {pga:.4g} m/s² < {PGA_MIN_PLAUSIBLE:g} m/s²; the file is "
            "probably in g read as m/s² (or the record is empty): pass units=",
            UnitWarning,
            stacklevel=3,
        )


def _resolve_units(explicit: str | None, stated: str | None, source: str) -> tuple[str, float]:
    if explicit is not None:
        name, factor = unit_factor(explicit)
        if stated is not None and stated != name:
            warnings.warn(
                f"{source}: units={explicit!r} given, but the header states {stated!r}; "
                f"using {name!r}",
                UnitWarning,
                stacklevel=4,
            )
        return name, factor
    if stated is not None:
        return unit_factor(stated)
    warnings.warn(
        f"{source}: the file does not state its units; assuming m/s² (pass units=)",
        UnitWarning,
        stacklevel=4,
    )
    return "m/s2", 1.0


# --------------------------------------------------------------------------------------------
# Text parsing helpers
# --------------------------------------------------------------------------------------------


def _to_float(tok: str) -> float:
    return float(tok.replace("D", "E").replace("d", "e"))


def _is_comment(s: str) -> bool:
    return s.startswith(_COMMENT_PREFIXES)


def _strip_comment(s: str) -> str:
    for p in _COMMENT_PREFIXES:
        if s.startswith(p):
            return s[len(p) :].strip()
    return s


def _header_value(header: list[str], pattern: str) -> str | None:
    m = re.search(pattern, "\n".join(header), re.I | re.M)
    return m.group(1).strip() if m else None


def _header_info(header: list[str]) -> dict[str, Any]:
    """What a (comment-stripped) header states: units, dt, npts, t0, name, columns, seed, …"""
    info: dict[str, Any] = {"units": _header_units(header)}
    dt = _header_value(header, rf"^\s*dt\s*[:=]\s*({_NUM})\s*$") or _header_value(
        header, rf"\bdt\s*[:=]\s*({_NUM})"
    )
    if dt is not None:
        info["dt"] = _to_float(dt)
    else:
        rate = _header_value(header, rf"\bsampling\s+(?:rate|freq\w*)\s*[:=]\s*({_NUM})\s*hz")
        if rate is not None:
            info["dt"] = 1.0 / _to_float(rate)
    npts = _header_value(header, r"\bnpts\s*[:=]\s*(\d+)")
    if npts is not None:
        info["npts"] = int(npts)
    t0 = _header_value(header, rf"^\s*t0\s*[:=]\s*({_NUM})\s*$")
    if t0 is not None:
        info["t0"] = _to_float(t0)
    for key in ("name", "command", "seed", "source"):
        value = _header_value(header, rf"^\s*{key}\s*:\s*(.+)$")
        if value is not None:
            info[key] = value
    meta = _header_value(header, r"^\s*meta\s*:\s*(\{.*\})\s*$")
    if meta is not None:
        try:
            info["meta"] = json.loads(meta)
        except json.JSONDecodeError:
            pass
    columns = _header_value(header, r"\bcolumns\s*:\s*([^;\n]+)")
    if columns is not None:
        info["columns"] = [c.lower() for c in re.split(r"[\s,]+", columns) if c]
    return info


def _read_text(path: str | os.PathLike) -> str:
    try:
        return Path(path).read_text(encoding="latin-1")
    except IsADirectoryError:
        raise RecordFileError(path, None, "is a directory, expected a record file") from None


def _parse_values(lines: list[tuple[int, str]], source: str) -> tuple[np.ndarray, int]:
    """All numbers of free-format value lines (AT2, JMA blocks), in order; Fortran fields that run
    together ("-0.12345-0.23456") are split. Returns (values, number of the last data line)."""
    values: list[float] = []
    last = lines[0][0] if lines else 0
    for lineno, s in lines:
        if not s or _is_comment(s):
            continue
        last = lineno
        for tok in s.replace(",", " ").split():
            try:
                x = _to_float(tok)
            except ValueError:
                if _FORTRAN_RUN.fullmatch(tok):
                    parts = _FORTRAN_ONE.findall(tok)
                    if "".join(parts) == tok:
                        values.extend(_to_float(p) for p in parts)
                        continue
                raise RecordFileError(
                    source, lineno, f"expected numbers, found {tok!r} in {s!r}"
                ) from None
            if not math.isfinite(x):
                raise RecordFileError(source, lineno, f"expected a finite number, found {tok!r}")
            values.append(x)
    return np.asarray(values, dtype=np.float64), last


def _numbered(text: str) -> list[tuple[int, str]]:
    return [(i, s.strip()) for i, s in enumerate(text.splitlines(), start=1)]


# --------------------------------------------------------------------------------------------
# PEER AT2
# --------------------------------------------------------------------------------------------

_AT2_NGA_NPTS = re.compile(r"NPTS\s*[=:]\s*(\d+)", re.I)
_AT2_NGA_DT = re.compile(rf"\bDT\s*[=:]\s*({_NUM})", re.I)
_AT2_OLD = re.compile(rf"^\s*(\d+)\s*,?\s+({_NUM})\s*,?\s*NPTS\s*,\s*DT", re.I)


def _at2_header_line(lines: list[tuple[int, str]]) -> int | None:
    for k, (_, s) in enumerate(lines[:HEADER_SEARCH_LINES]):
        if re.search(r"\bNPTS\b", s, re.I) and re.search(r"\bDT\b", s, re.I):
            return k
    return None


def _parse_at2(
    text: str, source: str, *, units: str | None, name: str | None
) -> tuple[GroundMotion, str]:
    """PEER AT2. Header: title lines, then one line with NPTS and DT in either layout

    * NGA-West2 / PEER 1999: ``NPTS=  5372, DT=   .0100 SEC,`` (spacing free, also
      hand-edited ``NPTS =   7500 , DT =   .020 SEC ,``);
    * old PEER: ``4096    0.0100    NPTS, DT``;

    then NPTS values, any number per line (E or F format). Units from the header
    ("IN UNITS OF G", "The units are (g)"). The line holding NPTS may be anywhere in the first
    ``HEADER_SEARCH_LINES`` lines; everything before it is header.
    """
    lines = _numbered(text)
    k = _at2_header_line(lines)
    if k is None:
        raise RecordFileError(
            source,
            1,
            f"expected a PEER AT2 header line with NPTS and DT within the first "
            f"{HEADER_SEARCH_LINES} lines ('NPTS= n, DT= dt SEC' or 'n dt NPTS, DT')",
        )
    lineno, s = lines[k]
    m_n, m_dt = _AT2_NGA_NPTS.search(s), _AT2_NGA_DT.search(s)
    m_old = _AT2_OLD.search(s)
    if m_n and m_dt:
        npts, dt = int(m_n.group(1)), _to_float(m_dt.group(1))
    elif m_old:
        npts, dt = int(m_old.group(1)), _to_float(m_old.group(2))
    else:
        raise RecordFileError(
            source, lineno, f"expected 'NPTS= n, DT= dt SEC' or 'n dt NPTS, DT', found {s!r}"
        )
    if not dt > 0.0:
        raise RecordFileError(source, lineno, f"expected DT > 0, found {dt}")
    header = [h for _, h in lines[: k + 1]]
    if any(re.search(r"\b(VELOCITY|DISPLACEMENT)\b", h, re.I) for h in header[:4]) and not any(
        re.search(r"\bACCEL", h, re.I) for h in header[:4]
    ):
        raise RecordFileError(source, 1, "expected an acceleration record (header says otherwise)")
    values, last = _parse_values(lines[k + 1 :], source)
    if values.size != npts:
        raise RecordFileError(
            source,
            last,
            f"header (line {lineno}) states NPTS = {npts}, found {values.size} values",
        )
    unit_name, factor = _resolve_units(units, _header_units(header), source)
    title = header[1] if len(header) > 2 else header[0]
    motion = GroundMotion(
        t0=0.0,
        dt=dt,
        a_hor=values * factor,
        name=name or Path(source).stem,
        source=source,
        meta={"format": "at2", "file_units": unit_name, "title": title, "header": header},
    )
    return motion, unit_name


def read_at2(path: str | os.PathLike, *, units: str | None = None, name: str | None = None):
    """Read a PEER AT2 file (NGA-West2, PEER 1999 or old PEER header). Returns a GroundMotion."""
    return read_motion(path, fmt="at2", units=units, name=name)


# --------------------------------------------------------------------------------------------
# Tables: single column, two columns (t, a), several columns
# --------------------------------------------------------------------------------------------


@dataclass
class _Table:
    header: list[str]  # comment-stripped header lines
    names: list[str] | None  # lower-case column names, if the file gives them
    data: np.ndarray  # (n, m)
    linenos: np.ndarray  # (n,) file line of each row


def _parse_table(text: str, source: str) -> _Table:
    header: list[str] = []
    names: list[str] | None = None
    rows: list[list[float]] = []
    linenos: list[int] = []
    ncol = 0
    last_line = 0
    for lineno, s in _numbered(text):
        last_line = lineno
        if not s:
            continue
        if _is_comment(s):
            if not rows:
                header.append(_strip_comment(s))
            continue
        toks = s.replace(",", " ").split()
        try:
            vals = [_to_float(tok) for tok in toks]
        except ValueError:
            if rows:
                raise RecordFileError(
                    source, lineno, f"expected {ncol} numbers per line, found {s!r}"
                ) from None
            header.append(s)
            if all(re.fullmatch(r"[A-Za-z][\w()\[\]/^.-]*", tok) for tok in toks):
                names = [tok.lower() for tok in toks]
            continue
        if not rows:
            ncol = len(vals)
        elif len(vals) != ncol:
            raise RecordFileError(
                source, lineno, f"expected {ncol} numbers per line, found {len(vals)}: {s!r}"
            )
        for tok, x in zip(toks, vals, strict=True):
            if not math.isfinite(x):
                raise RecordFileError(source, lineno, f"expected a finite number, found {tok!r}")
        rows.append(vals)
        linenos.append(lineno)
    if not rows:
        raise RecordFileError(source, max(last_line, 1), "expected numeric data, found none")
    info_names = _header_info(header).get("columns")
    if info_names is not None and len(info_names) == ncol:
        names = info_names
    if names is not None and len(names) != ncol:
        names = None
    return _Table(header, names, np.asarray(rows, dtype=np.float64), np.asarray(linenos))


def _looks_like_time(col: np.ndarray) -> bool:
    """A first column is time if it mostly increases (an accelerogram's does about half the time);
    a glitch in it is then reported by :func:`_check_time` rather than taken for data."""
    return col.size >= 3 and col[-1] > col[0] and float(np.mean(np.diff(col) > 0.0)) >= 0.75


def _check_time(t: np.ndarray, linenos: np.ndarray, source: str) -> float:
    """Validate a time column (increasing, uniform) and return its dt."""
    if t.size < 2:
        raise RecordFileError(source, int(linenos[0]), "expected at least two time samples")
    d = np.diff(t)
    bad = np.flatnonzero(d <= 0.0)
    if bad.size:
        k = int(bad[0]) + 1
        raise RecordFileError(
            source, int(linenos[k]), f"expected time > {t[k - 1]:.10g} s, found {t[k]:.10g} s"
        )
    h = float(np.median(d))
    bad = np.flatnonzero(np.abs(d - h) > STEP_RTOL * h)
    if bad.size:
        k = int(bad[0]) + 1
        raise RecordFileError(
            source,
            int(linenos[k]),
            f"expected a uniform time step {h:.6g} s (±{STEP_RTOL:.0%}), found "
            f"{d[k - 1]:.6g} s (t = {t[k - 1]:.10g} → {t[k]:.10g} s)",
        )
    dt = (float(t[-1]) - float(t[0])) / (t.size - 1)
    dev = np.abs(t - (t[0] + dt * np.arange(t.size)))
    bad = np.flatnonzero(dev > GRID_RTOL * dt)
    if bad.size:
        k = int(bad[0])
        raise RecordFileError(
            source,
            int(linenos[k]),
            f"expected t = {t[0] + k * dt:.10g} s on the uniform grid (dt = {dt:.6g} s), "
            f"found {t[k]:.10g} s",
        )
    return float(f"{dt:.{DT_DIGITS}g}")


def _column_index(spec: int | str, names: list[str] | None, ncol: int, source: str) -> int:
    if isinstance(spec, str):
        if names is None or spec.lower() not in names:
            raise RecordFileError(source, None, f"expected a column named {spec!r}; has {names}")
        return names.index(spec.lower())
    idx = int(spec)
    if not -ncol <= idx < ncol:
        raise RecordFileError(source, None, f"expected column index < {ncol}, got {spec}")
    return idx % ncol


def _parse_table_motion(
    text: str,
    source: str,
    *,
    layout: str,
    units: str | None,
    dt: float | None,
    column: int | str | None,
    vertical: int | str | None,
    name: str | None,
) -> tuple[GroundMotion, str]:
    """layout: "single-column" (a; dt from header or argument), "two-column" (t, a),
    "multi-column" (time column detected by name or as an increasing first column; the rest
    acceleration columns, ``column`` picks the horizontal one — an index counted over all the
    file's columns, or a name — and a column named a_ver/UD/UP/… becomes the vertical one)."""
    tab = _parse_table(text, source)
    info = _header_info(tab.header)
    data, names = tab.data, tab.names
    n, ncol = data.shape
    first = int(tab.linenos[0])
    if layout == "single-column" and ncol != 1:
        raise RecordFileError(source, first, f"expected 1 column, found {ncol}")
    if layout == "two-column" and ncol != 2:
        raise RecordFileError(source, first, f"expected 2 columns (t, a), found {ncol}")

    tcol: int | None = None
    if names is not None and names[0] in _TIME_NAMES:
        tcol = 0
    elif layout == "two-column" or (ncol >= 2 and _looks_like_time(data[:, 0])):
        tcol = 0

    if "npts" in info and info["npts"] != n:
        raise RecordFileError(
            source, int(tab.linenos[-1]), f"header states npts = {info['npts']}, found {n} rows"
        )

    if tcol is not None:
        t = data[:, tcol]
        dt_file = _check_time(t, tab.linenos, source)
        for label, value in (("header", info.get("dt")), ("argument", dt)):
            if value is not None and abs(value - dt_file) > DT_RTOL * dt_file:
                raise RecordFileError(
                    source,
                    first,
                    f"dt = {value:g} s ({label}) but the time column has {dt_file:g} s",
                )
        dt_used = dt if dt is not None else info.get("dt", dt_file)
        t0 = info.get("t0", float(t[0]))
    else:
        dt_used = dt if dt is not None else info.get("dt")
        if dt_used is None:
            raise RecordFileError(
                source,
                first,
                "expected a sampling interval: the file has no time column and its header "
                "states no dt; pass dt=",
            )
        t0 = info.get("t0", 0.0)

    acc_cols = [j for j in range(ncol) if j != tcol]
    if not acc_cols:
        raise RecordFileError(source, first, "expected an acceleration column besides time")
    vcol: int | None = None
    if vertical is not None:
        vcol = _column_index(vertical, names, ncol, source)
    elif names is not None:
        named = [j for j in acc_cols if names[j] in _VERTICAL_NAMES]
        vcol = named[0] if named else None
    if column is not None:
        hcol = _column_index(column, names, ncol, source)
    else:
        hcol = next((j for j in acc_cols if j != vcol), acc_cols[0])
    if hcol == tcol:
        raise RecordFileError(source, first, f"column {hcol} is the time column")

    unit_name, factor = _resolve_units(units, info.get("units"), source)
    a_ver = data[:, vcol] * factor if vcol is not None and vcol != hcol else None
    meta: dict[str, Any] = dict(info.get("meta", {}))
    meta.update(
        {
            "format": layout,
            "file_units": unit_name,
            "column": hcol,
            "vertical_column": vcol if a_ver is not None else None,
            "columns": names,
            "header": tab.header,
        }
    )
    if tab.header:
        meta.setdefault("title", tab.header[0])
    for key in ("command", "seed"):
        if key in info:
            meta.setdefault(key, info[key])
    motion = GroundMotion(
        t0=t0,
        dt=dt_used,
        a_hor=data[:, hcol] * factor,
        a_ver=a_ver,
        name=name or info.get("name") or Path(source).stem,
        source=source,
        meta=meta,
    )
    return motion, unit_name


def read_two_column(
    path: str | os.PathLike, *, units: str | None = None, dt: float | None = None, name=None
) -> GroundMotion:
    """Two columns ``t a`` (whitespace or commas; ``#``/``%``/``;`` comments). The time column must
    be increasing and uniform (each step within 5 % of the median, each stamp within 1 % of a step
    of the grid); ``dt``, if given, is checked against it."""
    return read_motion(path, fmt="two-column", units=units, dt=dt, name=name)


def read_single_column(
    path: str | os.PathLike, dt: float | None = None, *, units: str | None = None, name=None
) -> GroundMotion:
    """One acceleration value per line; ``dt`` from the argument or the header (``dt = …``)."""
    return read_motion(path, fmt="single-column", units=units, dt=dt, name=name)


def read_multi_column(
    path: str | os.PathLike,
    *,
    column: int | str | None = None,
    vertical: int | str | None = None,
    dt: float | None = None,
    units: str | None = None,
    name: str | None = None,
) -> GroundMotion:
    """Several columns; see :func:`read_motion` for ``column`` and ``vertical``."""
    return read_motion(
        path, fmt="multi-column", units=units, dt=dt, column=column, vertical=vertical, name=name
    )


# --------------------------------------------------------------------------------------------
# JMA-style text
# --------------------------------------------------------------------------------------------


def _parse_jma(
    text: str,
    source: str,
    *,
    units: str | None,
    dt: float | None,
    column: int | str | None,
    vertical: int | str | None,
    name: str | None,
) -> tuple[GroundMotion, str]:
    """Two JMA-style layouts.

    * ``;``-comment layout (the JMA Kobe NS file of Mechanics_Apps): ``;`` comment lines (units
      "acc. in cm/s/s", "dt=0.02"), then one line ``dt peak`` (the peak is nominal and only kept
      in meta), then the values, any number per line.
    * JMA CSV: ``KEY = value`` header lines (``SAMPLING RATE= 100Hz``, ``UNIT = gal``), a
      ``NS,EW,UD`` names line, then comma-separated columns. Read as a table; UD is the vertical.
    """
    lines = _numbered(text)
    body = [(i, s) for i, s in lines if s and not _is_comment(s)]
    first = next((s for _, s in lines if s), "")
    if not first.startswith(";"):
        return _parse_table_motion(
            text,
            source,
            layout="multi-column",
            units=units,
            dt=dt,
            column=column,
            vertical=vertical,
            name=name,
        )
    header = [_strip_comment(s) for _, s in lines if s.startswith(";")]
    if not body:
        raise RecordFileError(source, len(lines), "expected a 'dt peak' line and data, found none")
    lineno, s = body[0]
    toks = s.replace(",", " ").split()
    try:
        dt_line, peak = (_to_float(x) for x in toks)
    except ValueError:
        raise RecordFileError(
            source, lineno, f"expected 'dt peak' (two numbers), found {s!r}"
        ) from None
    if not dt_line > 0.0:
        raise RecordFileError(source, lineno, f"expected dt > 0, found {dt_line}")
    stated_dt = _header_info(header).get("dt")
    if stated_dt is not None and abs(stated_dt - dt_line) > DT_RTOL * dt_line:
        raise RecordFileError(
            source, lineno, f"dt = {dt_line:g} s here but the comment says dt = {stated_dt:g} s"
        )
    values, _ = _parse_values(body[1:], source)
    if values.size == 0:
        raise RecordFileError(source, lineno, "expected acceleration values after 'dt peak'")
    unit_name, factor = _resolve_units(units, _header_units(header), source)
    motion = GroundMotion(
        t0=0.0,
        dt=dt if dt is not None else dt_line,
        a_hor=values * factor,
        name=name or Path(source).stem,
        source=source,
        meta={
            "format": "jma",
            "file_units": unit_name,
            "nominal_peak": peak,
            "title": header[0] if header else "",
            "header": header,
        },
    )
    return motion, unit_name


def read_jma(
    path: str | os.PathLike,
    *,
    units: str | None = None,
    column: int | str | None = None,
    vertical: int | str | None = None,
    name: str | None = None,
) -> GroundMotion:
    """Read a JMA-style text record (``;`` comments + ``dt peak`` line, or JMA CSV)."""
    return read_motion(path, fmt="jma", units=units, column=column, vertical=vertical, name=name)


# --------------------------------------------------------------------------------------------
# Front door, bundled records, writing
# --------------------------------------------------------------------------------------------

_FORMATS = ("auto", "at2", "jma", "two-column", "single-column", "multi-column")


def _bundled_root():
    """The bundled-records directory: package ``nsdyn.data.records`` when installed, else
    ``<repo>/records`` of a source tree."""
    try:
        root = resources.files("nsdyn.data.records")
        if any(p.name.endswith(".csv") for p in root.iterdir()):
            return root
    except (ModuleNotFoundError, FileNotFoundError, NotADirectoryError):
        pass
    return Path(__file__).resolve().parents[1] / "records"


def bundled_records() -> list[str]:
    """Names of the bundled synthetic records (``read_motion(name)`` reads one)."""
    root = _bundled_root()
    try:
        return sorted(p.name[:-4] for p in root.iterdir() if p.name.endswith(".csv"))
    except FileNotFoundError:
        return []


def _resolve(path_or_name: str | os.PathLike) -> tuple[str, str]:
    """(source label, text) of a file path or a bundled record name."""
    path = Path(path_or_name)
    if path.is_file():
        return str(path), _read_text(path)
    name = str(path_or_name)
    stem = name[:-4] if name.endswith(".csv") else name
    if "/" not in stem and os.sep not in stem:
        root = _bundled_root()
        item = root / f"{stem}.csv"
        if item.is_file():
            return f"nsdyn.data.records/{stem}.csv", item.read_text(encoding="latin-1")
    if path.exists():
        raise RecordFileError(path, None, "expected a record file")
    raise FileNotFoundError(
        f"{name!r} is neither a file nor a bundled record; bundled: {bundled_records()}"
    )


def _detect_format(source: str, text: str) -> str:
    suffix = Path(source).suffix.lower()
    if suffix in (".hdf5", ".h5"):
        return "hdf5"
    lines = _numbered(text)
    k = _at2_header_line(lines)
    if suffix == ".at2" or (k is not None and not _is_comment(lines[k][1])):
        return "at2"
    first = next((s for _, s in lines if s), "")
    if first.startswith(";") or re.search(r"sampling\s+rate\s*=", text[:2000], re.I):
        return "jma"
    return "multi-column"


def _split_vertical(vertical) -> tuple[int | str | None, Path | None, float | None]:
    """(column of the same table, another file, ratio) from read_motion's ``vertical``."""
    if vertical is None or vertical is False:
        return None, None, None
    if isinstance(vertical, (int, np.integer)) and not isinstance(vertical, bool):
        return int(vertical), None, None
    if isinstance(vertical, (float, np.floating)):
        return None, None, float(vertical)
    if isinstance(vertical, os.PathLike) or Path(str(vertical)).is_file():
        return None, Path(vertical), None
    return str(vertical), None, None  # a column name


def read_motion(
    path_or_name: str | os.PathLike,
    *,
    fmt: str = "auto",
    units: str | None = None,
    dt: float | None = None,
    column: int | str | None = None,
    vertical: int | str | float | os.PathLike | None = None,
    name: str | None = None,
) -> GroundMotion:
    """Read a ground motion from a file or by bundled name.

    Parameters
    ----------
    path_or_name : path or str
        A file, or the name of a bundled record (``bundled_records()``), e.g. "synthetic-wn-40s".
    fmt : {"auto", "at2", "jma", "two-column", "single-column", "multi-column"}
        "auto": AT2 if the file has an NPTS/DT header line (or ends in .AT2); JMA if it starts with
        a ``;`` comment or has a "SAMPLING RATE=" line; otherwise a table ("multi-column", which
        also covers one and two columns and the CSV files written by :func:`write_motion`).
    units : {"g", "cm/s2" (gal), "m/s2"} or None
        Units on file. None: as the header states; if it states none, m/s² with a UnitWarning.
    dt : float, optional
        Sampling interval [s] for files without a time column or header dt.
    column : int or str, optional
        The horizontal column of a table: an index over all the file's columns (time included)
        or a column name. Default: the first acceleration column that is not a vertical one.
    vertical : int, str, float or path, optional
        Vertical component: a column (index or name) of the same table; a float ratio r
        (a_ver = r a_hor); or another file, read with the same ``units``, whose dt must match
        and whose samples are zero-padded or cut to this record's length. Default: a table column
        named a_ver/ver/UD/UP/z, else none.
    name : str, optional
        Record name (default: the header's ``name:`` or the file stem).

    Raises
    ------
    RecordFileError
        Naming the file, the line and what was expected, for non-numeric rows, NaN/inf,
        non-uniform time, empty files, NPTS mismatch, missing dt.

    Warns
    -----
    UnitWarning
        Units not stated and not given; units given against the header; PGA outside
        [0.01, 30] m/s² after conversion.
    """
    if fmt not in _FORMATS:
        raise ValueError(f"fmt must be one of {_FORMATS}, got {fmt!r}")
    source, text = _resolve(path_or_name)
    kind = _detect_format(source, text) if fmt == "auto" else fmt
    if kind == "hdf5":
        raise RecordFileError(
            source,
            None,
            "HDF5 records are not read by nsdyn (it would need h5py and hdf5plugin, which are not "
            "dependencies); export the record to text first",
        )
    in_file_vertical, vertical_file, vertical_ratio = _split_vertical(vertical)
    if kind == "at2":
        if column not in (None, 0) or in_file_vertical is not None:
            raise ValueError("an AT2 file has one component: use vertical=<another file>")
        motion, unit_name = _parse_at2(text, source, units=units, name=name)
        if dt is not None and abs(dt - motion.dt) > DT_RTOL * motion.dt:
            raise RecordFileError(source, None, f"dt = {dt} given, header states {motion.dt}")
    elif kind == "jma":
        motion, unit_name = _parse_jma(
            text, source, units=units, dt=dt, column=column, vertical=in_file_vertical, name=name
        )
    else:
        motion, unit_name = _parse_table_motion(
            text,
            source,
            layout=kind,
            units=units,
            dt=dt,
            column=column,
            vertical=in_file_vertical,
            name=name,
        )
    _check_pga(motion)
    if vertical_ratio is not None:
        return motion.with_vertical(vertical_ratio)
    if vertical_file is None:
        return motion
    other = read_motion(vertical_file, units=units)
    if abs(other.dt - motion.dt) > DT_RTOL * motion.dt:
        raise RecordFileError(
            other.source, None, f"vertical dt = {other.dt:g} s, horizontal dt = {motion.dt:g} s"
        )
    a_ver = np.zeros(motion.n)
    m = min(motion.n, other.n)
    a_ver[:m] = other.a_hor[:m]
    return motion._replace(
        a_ver=a_ver, meta_update={"vertical_source": other.source, "vertical_n": other.n}
    )


def _fmt(x: float) -> str:
    return repr(float(x))  # shortest string that reads back to the same float


def write_motion(
    motion: GroundMotion,
    path: str | os.PathLike,
    *,
    command: str | None = None,
    seed: int | str | None = None,
) -> Path:
    """Write ``motion`` as CSV (columns t, a_hor[, a_ver] in m/s²) with a ``#`` header holding
    name, units, t0, dt, npts, command, seed and the JSON meta. Values are written with the
    shortest round-trip repr, so :func:`read_motion` returns them bit for bit. Atomic: written to
    a temporary file in the same directory, then renamed."""
    path = Path(path)
    command = command if command is not None else motion.meta.get("command", "")
    seed = seed if seed is not None else motion.meta.get("seed", "")
    meta = {k: v for k, v in motion.meta.items() if k != "header"}
    meta.update(command=command, seed=seed)
    columns = "t a_hor a_ver" if motion.a_ver is not None else "t a_hor"
    head = [
        "nsdyn ground motion",
        f"name: {motion.name}",
        "units: m/s2",
        f"t0: {_fmt(motion.t0)}",
        f"dt: {_fmt(motion.dt)}",
        f"npts: {motion.n}",
        f"command: {command}",
        f"seed: {seed}",
        f"source: {motion.source}",
        f"meta: {json.dumps(meta, default=str, sort_keys=True)}",
        f"columns: {columns}",
    ]
    lines = [f"# {h}" for h in head]
    t = motion.t
    if motion.a_ver is None:
        lines += [f"{t[k]:.10g},{_fmt(motion.a_hor[k])}" for k in range(motion.n)]
    else:
        lines += [
            f"{t[k]:.10g},{_fmt(motion.a_hor[k])},{_fmt(motion.a_ver[k])}" for k in range(motion.n)
        ]
    with atomic_open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write("\n".join(lines) + "\n")
    return path


# --------------------------------------------------------------------------------------------
# Shared research records (read-only, outside the package)
# --------------------------------------------------------------------------------------------


def default_shared_dir() -> Path | None:
    """``$NSDYN_SHARED`` or ``shared/`` beside the repository, if it exists (else None)."""
    env = os.environ.get("NSDYN_SHARED")
    if env:
        return Path(env) if Path(env).is_dir() else None
    # a source checkout beside shared/, or the working directory of one (installed package)
    for candidate in (
        Path(__file__).resolve().parents[2] / "shared",
        Path.cwd().resolve().parent / "shared",
        Path.cwd().resolve() / "shared",
    ):
        if candidate.is_dir():
            return candidate
    return None


def _records_dir(shared_dir: str | os.PathLike | None) -> Path:
    base = Path(shared_dir) if shared_dir is not None else default_shared_dir()
    if base is None:
        raise FileNotFoundError("no shared records directory: set NSDYN_SHARED")
    for cand in (base / "records", base):
        if (cand / "raw").is_dir():
            return cand
    raise FileNotFoundError(f"{base} holds no records/raw directory")


def kobe_records(
    shared_dir: str | os.PathLike | None = None, component: str = "000"
) -> dict[str, GroundMotion]:
    """The four 1995 Kobe records of the transient study (seed 004 §5), by station.

    Per shared/records/PROVENANCE.md:

    * "KJMA": JMA Kobe, NGA-West2 RSN1106 (raw/kobe_kjma_000.AT2 or _090, g, dt 0.02 s,
      0.834 / 0.630 g), with the UP component (raw/kobe_kjma_up.AT2) as vertical;
    * "Shin-Osaka": RSN1116 SHI000/SHI090 from the FEMA P695 far-field set
      (converted/kobe_shi000_fema_p695.txt, g, dt 0.01 s, 0.243 / 0.212 g); no vertical;
    * "Nishi-Akashi": RSN1111 NIS000/NIS090, same source (converted/kobe_nis000…, 0.509 /
      0.503 g); no vertical;
    * "unidentified": raw/kobe_unidentified_osm.dat, one horizontal component, m/s² (inferred),
      dt 0.02 s, 6.80 m/s². Its PGA matches Takarazuka (≈0.69 g) but the station is
      **unverified**; ``component`` does not apply to it.

    Parameters
    ----------
    shared_dir : path, optional
        The ``shared`` directory (or its ``records`` subdirectory). Default:
        :func:`default_shared_dir`.
    component : {"000", "090"}
        Horizontal component of the three identified stations.
    """
    if component not in ("000", "090"):
        raise ValueError(f"component must be '000' or '090', got {component!r}")
    d = _records_dir(shared_dir)
    out = {
        "KJMA": read_motion(
            d / "raw" / f"kobe_kjma_{component}.AT2",
            vertical=d / "raw" / "kobe_kjma_up.AT2",
            name="KJMA",
        ),
        "Shin-Osaka": read_motion(
            d / "converted" / f"kobe_shi{component}_fema_p695.txt", name="Shin-Osaka"
        ),
        "Nishi-Akashi": read_motion(
            d / "converted" / f"kobe_nis{component}_fema_p695.txt", name="Nishi-Akashi"
        ),
        "unidentified": read_motion(
            d / "raw" / "kobe_unidentified_osm.dat", units="m/s2", name="Kobe (unidentified)"
        ),
    }
    stations = {
        "KJMA": ("JMA Kobe (KJMA), RSN1106", component),
        "Shin-Osaka": ("Shin-Osaka (SHI), RSN1116", component),
        "Nishi-Akashi": ("Nishi-Akashi (NIS), RSN1111", component),
        "unidentified": ("unknown (PGA matches Takarazuka; unverified)", "unknown horizontal"),
    }
    return {
        k: m._replace(meta_update={"station": stations[k][0], "component": stations[k][1]})
        for k, m in out.items()
    }


# --------------------------------------------------------------------------------------------
# Synthesis
# --------------------------------------------------------------------------------------------


def _rng(seed: int | np.random.Generator | None) -> tuple[np.random.Generator, Any]:
    """A Generator and a JSON-able record of the seed (entropy of a fresh one, so that an
    unseeded run can still be repeated)."""
    if isinstance(seed, np.random.Generator):
        return seed, "numpy Generator (state not recorded)"
    if seed is None:
        ss = np.random.SeedSequence()
        return np.random.default_rng(ss), int(ss.entropy)
    return np.random.default_rng(seed), int(seed)


def _grid(duration: float, dt: float) -> np.ndarray:
    if not (duration > 0.0 and dt > 0.0):
        raise ValueError(f"duration and dt must be positive, got {duration}, {dt}")
    return dt * np.arange(int(round(duration / dt)) + 1)


def shinozuka_envelope(t: np.ndarray | float) -> np.ndarray:
    """Seed 000 eq (4.1): G(t) = 4 (e^(−0.25 t) − e^(−0.5 t)) for t ≥ 0, 0 before."""
    t = np.asarray(t, dtype=np.float64)
    tp = np.maximum(t, 0.0)
    return np.where(t >= 0.0, 4.0 * (np.exp(-0.25 * tp) - np.exp(-0.5 * tp)), 0.0)


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
    rng, seed_record = _rng(seed)
    t = _grid(duration, dt)
    n_ord = int(math.ceil(t[-1] / dt_ord - 1e-9)) + 1
    t_ord = dt_ord * np.arange(n_ord)
    sigma = math.sqrt(2.0 * math.pi * S0 / dt_ord)
    w_hor = sigma * rng.standard_normal(n_ord)
    w_ver = sigma * rng.standard_normal(n_ord)  # drawn always: same a_hor with or without ver
    a_hor = np.interp(t, t_ord, w_hor)
    a_ver = None if not vertical_ratio else vertical_ratio * np.interp(t, t_ord, w_ver)
    if modulate:
        env = shinozuka_envelope(t)
        a_hor = env * a_hor
        a_ver = None if a_ver is None else env * a_ver
    meta = {
        "generator": "modulated_white_noise",
        "seed": seed_record,
        "S0": S0,
        "dt_ord": dt_ord,
        "sigma_ordinates": sigma,
        "vertical_ratio": vertical_ratio,
        "modulation": "G(t)=4(exp(-0.25t)-exp(-0.5t))" if modulate else None,
    }
    source = (
        f"synthetic: modulated_white_noise(duration={duration}, S0={S0}, dt_ord={dt_ord}, "
        f"dt={dt}, vertical_ratio={vertical_ratio}, seed={seed_record}, modulate={modulate})"
    )
    return GroundMotion(0.0, dt, a_hor, a_ver, name=name, source=source, meta=meta)


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
    if not (omega_g > 0.0 and zeta_g > 0.0):
        raise ValueError("omega_g and zeta_g must be positive")
    rng, seed_record = _rng(seed)
    t = _grid(duration, dt)
    a_hor = _kt_stationary(t.size, dt, omega_g, zeta_g, S0, rng)
    a_ver = _kt_stationary(t.size, dt, omega_g, zeta_g, S0, rng)
    a_ver = None if not vertical_ratio else vertical_ratio * a_ver
    if modulate:
        env = shinozuka_envelope(t)
        a_hor = env * a_hor
        a_ver = None if a_ver is None else env * a_ver
    meta = {
        "generator": "kanai_tajimi",
        "seed": seed_record,
        "S0": S0,
        "omega_g": omega_g,
        "zeta_g": zeta_g,
        "vertical_ratio": vertical_ratio,
        "modulation": "G(t)=4(exp(-0.25t)-exp(-0.5t))" if modulate else None,
    }
    source = (
        f"synthetic: kanai_tajimi(duration={duration}, omega_g={omega_g}, zeta_g={zeta_g}, "
        f"S0={S0}, seed={seed_record}, dt={dt}, modulate={modulate}, "
        f"vertical_ratio={vertical_ratio})"
    )
    return GroundMotion(0.0, dt, a_hor, a_ver, name=name, source=source, meta=meta)


def harmonic(
    A: float, f: float, duration: float, dt: float, phase: float = 0.0, *, name: str = "harmonic"
) -> GroundMotion:
    """a(t) = A sin(2π f t + phase) on 0 ≤ t ≤ duration."""
    t = _grid(duration, dt)
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
    tp = n_cycles / f
    t = _grid(max(duration or tp, tp), dt)
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
