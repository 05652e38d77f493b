"""The ground-motion record: one uniformly sampled base acceleration and its transformations.

A ground motion is the base acceleration ü_g(t) = [ü_hor(t), ü_ver(t)] in m/s², sampled on a uniform
grid t_k = t0 + k Δt, k = 0 … n−1. The structure is loaded by −M Γ ü with ü = [ü_hor, ü_ver + g];
gravity is *not* part of ``a_ver``. Derived quantities:

    PGA = max_k |ü_hor(t_k)|,
    v(t_k) = Σ_{j<k} Δt (ü_j + ü_{j+1}) / 2   (trapezoidal rule from rest), u(t_k) likewise from v.

Transformations each return a new record: scaling by one factor c = PGA_target / PGA (both
components, ü → c ü), least-squares polynomial baseline correction (on v or on ü), resampling
(polyphase band-limited or linear) and windowing.

Units on disk: "g" (9.80665 m/s²), "cm/s2" (= gal), "mm/s2" or "m/s2"; in memory always m/s².
A record file's stated units are found by the patterns of ``_UNIT_PATTERNS``; a PGA outside
[PGA_MIN_PLAUSIBLE, PGA_MAX_PLAUSIBLE] after conversion warns of a probable unit mistake.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import warnings
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np

from nsdyn._checks import MAX_OUTPUTS, InputWarning, number, real_samples, whole

A_SAMPLE_MAX = 1e12  # m/s²: a sample beyond it is no acceleration at all (samples refuses it)


def samples(name: str, a, n: int | None = None) -> np.ndarray:
    """``a`` as a non-empty 1-D float64 array of finite accelerations (``n`` of them when
    given), or ValueError naming ``name`` (:func:`nsdyn._checks.real_samples`)."""
    arr = real_samples(name, a, "real accelerations [m/s²]")
    if n is not None and arr.size != n:
        raise ValueError(f"{name}: expected {n} samples (as the first component), got {arr.size}")
    if np.any(big := np.abs(arr) > A_SAMPLE_MAX):  # (1e308 overflowed inside a run)
        k = int(np.flatnonzero(big)[0])
        raise ValueError(f"{name}: expected accelerations [m/s²] below {A_SAMPLE_MAX:g}, "
                         f"sample {k} is {arr[k]:g}")  # fmt: skip
    return arr


def check_meta(motion) -> None:
    """A record's ``name`` and ``source`` as text and ``meta`` as a dict, or TypeError naming
    the field (``meta=None`` failed later, in a run's notes)."""
    for key, kind, what in (("name", str, "text"), ("source", str, "text"),
                            ("meta", dict, "a dict")):  # fmt: skip
        v = getattr(motion, key)
        if not isinstance(v, kind):
            raise TypeError(f"{key}: expected {what}, got {type(v).__name__}")


def _cumulative_trapezoid(y, dx: float, initial: float = 0.0):
    """scipy.integrate.cumulative_trapezoid, imported on first use (scipy's integrate and signal
    modules cost ~0.4 s at start-up, which every command line call would pay)."""
    from scipy.integrate import cumulative_trapezoid

    return cumulative_trapezoid(y, dx=dx, initial=initial)


G_STANDARD = 9.80665  # standard gravity [m/s²], used to convert records in g
PGA_MAX_PLAUSIBLE = 30.0  # [m/s²] above this a record is probably in cm/s² (or m/s² read as g)
PGA_MIN_PLAUSIBLE = 0.01  # [m/s²] below this a record is probably in g read as m/s²
# [s] an earthquake record sampled coarser holds nothing above 2.5 Hz: a time column or a
# header's dt is probably in ms (a step of 10 s read from 0, 10, 20, ... ms)
DT_MAX_PLAUSIBLE = 0.2


class RecordFileError(ValueError):
    """A record file that cannot be read; names the file, the line and what was expected."""

    def __init__(
        self, source: str | os.PathLike, line: int | None, message: str, argument: str | None = None
    ):
        self.source = str(source)
        self.line = line
        self.reason = message
        self.argument = argument  # the reader's keyword the file contradicts (e.g. "dt"), if any
        where = f"{self.source}:{line}" if line is not None else self.source
        super().__init__(f"{where}: {message}")


# what scaled_to_pga takes (the message's words): up to 100 g, far above any earthquake's (a
# scene's pga = 1e30 ran and reported a slip of 7.7e26 m)
PGA_TARGET_MAX = 1000.0  # [m/s²]
PGA_TARGET = f"a finite PGA from 0 to {PGA_TARGET_MAX:g} m/s² (100 g)"


def record_pga_said(pga: float) -> str | None:
    """The refusal of a record run as read whose PGA [m/s²] is above what ``pga`` scales to
    (:data:`PGA_TARGET_MAX`, 100 g: a record in units it was not read in; 3e5 g ran until an
    isolator lifted off), or None. A scene names its field before it."""
    if not pga > PGA_TARGET_MAX:
        return None
    return (f"the record's PGA as read is {pga:.4g} m/s², above {PGA_TARGET_MAX:g} m/s² (100 g),"
            " the most a scene runs: are its units right? Give them (motion.units; nsdyn run "
            "--units), or scale the record (motion.pga; --pga)")  # fmt: skip


def pga_target(target) -> float:
    """``target`` [m/s²] as a float if it is a PGA :func:`GroundMotion.scaled_to_pga` takes
    (:data:`PGA_TARGET`), else a ValueError naming it. One above
    :data:`PGA_MAX_PLAUSIBLE` is taken and said (a UnitWarning: 300 typed in gal ran at 30 g)."""
    v = number("target", target, PGA_TARGET, lambda v: 0.0 <= v <= PGA_TARGET_MAX)
    if v > PGA_MAX_PLAUSIBLE:
        g = PGA_MAX_PLAUSIBLE / G_STANDARD  # (no value in the text: a study says it once)
        warnings.warn(f"a PGA above {PGA_MAX_PLAUSIBLE:g} m/s² ({g:.2g} g), beyond recorded "
                      "ground motions, is given: is it in gal (cm/s²)? A PGA is given in m/s²",
                      UnitWarning, stacklevel=3)  # fmt: skip
    return v


# how a user gives a record's units, in the library and in a scene file
UNITS_HINT = (
    'in a scene [motion] units = "gal", "g" or "m/s2" (a study: [base.motion]); nsdyn run '
    "--units gal; in Python units='gal'"
)


class UnitError(ValueError):
    """An acceleration unit given to a reader that it does not know (``argument`` "units")."""

    argument = "units"


class UnitWarning(InputWarning):
    """The units of a record were assumed, or its PGA looks like the wrong unit."""


# --------------------------------------------------------------------------------------------
# The record
# --------------------------------------------------------------------------------------------


class Sampled:
    """Sample times and duration of a record of ``n`` samples at step ``dt`` from ``t0``."""

    @property
    def t(self) -> np.ndarray:
        """Sample times t0 + k dt [s], shape (n,)."""
        return self.t0 + self.dt * np.arange(self.n)

    @property
    def duration(self) -> float:
        """(n − 1) dt [s]."""
        return (self.n - 1) * self.dt


@dataclass(frozen=True, eq=False, repr=False)
class GroundMotion(Sampled):
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
        a_hor = samples("a_hor", self.a_hor)
        dt = number("dt", self.dt, "a positive finite step [s]", lambda v: v > 0)
        object.__setattr__(self, "a_hor", a_hor)
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "t0", number("t0", self.t0, "a finite time [s]"))
        if self.a_ver is not None:
            object.__setattr__(self, "a_ver", samples("a_ver", self.a_ver, a_hor.size))
        check_meta(self)
        if not self.source:
            check_hand_pga(self, "GroundMotion", self.pga)

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
    def pga(self) -> float:
        """Horizontal peak ground acceleration max |a_hor| [m/s²]."""
        return float(np.max(np.abs(self.a_hor)))

    @property
    def pga_ver(self) -> float | None:
        """Vertical peak max |a_ver| [m/s²], or None without a vertical component."""
        return None if self.a_ver is None else float(np.max(np.abs(self.a_ver)))

    def velocity(self, component: str = "hor") -> np.ndarray:
        """Ground velocity [m/s] by the trapezoidal rule from rest, shape (n,)."""
        return _cumulative_trapezoid(self._component(component), dx=self.dt, initial=0.0)

    def displacement(self, component: str = "hor") -> np.ndarray:
        """Ground displacement [m]: trapezoidal rule applied twice from rest, shape (n,)."""
        return _cumulative_trapezoid(self.velocity(component), dx=self.dt, initial=0.0)

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

        ``component``: "hor" (default) scales to the horizontal peak, "ver" to the vertical
        one; either way the two keep their ratio. ``target`` from 0 (a record at rest) to
        1000 m/s² (100 g), else a ValueError; above 30 m/s² a UnitWarning (in gal?). A
        ValueError too for a component that is zero at every sample.
        """
        target = pga_target(target)
        peak = float(np.max(np.abs(self._component(component))))
        if peak == 0.0:
            what = "horizontal" if component == "hor" else "vertical"
            raise ValueError(
                f"record {self.name!r}: the {what} acceleration is zero at every sample; "
                "it cannot be scaled to a peak"
            )
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
        order = whole("order", order, 0, "a whole polynomial degree >= 0")  # (1.5: numpy's)
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
            v = _cumulative_trapezoid(a, dx=self.dt, initial=0.0)
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
        dt = number("dt", dt, "a positive finite step [s]", lambda v: v > 0)
        if self.n < 2:  # (scipy's polyphase filter ends the process on one sample)
            raise ValueError(f"{self.name!r}: resampling needs two samples or more, got {self.n}")
        if not self.duration / dt <= MAX_OUTPUTS:  # (1e-9 s built 2e10 samples: 160 GB)
            raise ValueError(f"dt: {self.duration / dt:.3g} samples of {dt:g} s over "
                             f"{self.duration:g} s exceed {MAX_OUTPUTS:.0e}; expected a longer "
                             "step")  # fmt: skip
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
                from scipy import signal  # imported here: scipy.signal costs ~0.3 s at start-up

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
        """The samples with t_start ≤ t ≤ t_end (absolute times; t0 becomes the first kept t).
        A window reaching past the record keeps the samples there are: ``window(30, 100)`` of
        a 40 s record is 10 s long (``.duration`` says it; ValueError when none is left)."""
        for v in (t_start, t_end):  # (an infinite end: the record's own end)
            number("window", v, "times [s] (inf: the record's end)", finite=False)
        eps = 1e-9
        x0 = (t_start - self.t0) / self.dt - eps  # (an infinite end: the record's own end)
        x1 = (t_end - self.t0) / self.dt + eps
        i0 = 0 if x0 <= 0 else self.n if x0 > self.n else math.ceil(x0)
        i1 = self.n - 1 if x1 >= self.n - 1 else -1 if x1 < 0 else math.floor(x1)
        if i1 < i0:
            raise ValueError(f"window [{t_start}, {t_end}] holds no sample of {self.name!r}")
        a_ver = None if self.a_ver is None else self.a_ver[i0 : i1 + 1].copy()
        return self._replace(
            t0=self.t0 + i0 * self.dt, a_hor=self.a_hor[i0 : i1 + 1].copy(), a_ver=a_ver
        )

    def until(self, t_end: float) -> GroundMotion:
        """The record from its start to ``t_end`` (an absolute time, as a run's ``t_end``);
        ValueError ("t_end: ...") unless the cut keeps at least one step of the record."""
        if isinstance(t_end, str | bytes | bool | np.bool_):  # ("1" was taken as 1 s)
            raise ValueError(f"t_end: expected an end time [s] (a number), got {t_end!r}")
        t_end = float(t_end)
        if not (math.isfinite(t_end) and t_end >= self.t0 + self.dt * (1 - 1e-9)):
            raise ValueError(
                f"t_end: expected an end at least one record step ({self.dt:g} s) after the "
                f"record's start ({self.t0:g} s), got {t_end:g}"
            )
        return self.window(self.t0, t_end)

    def with_vertical(self, a_ver: np.ndarray | float | None) -> GroundMotion:
        """Set the vertical component: an array of shape (n,), a ratio r (a_ver = r a_hor, fully
        correlated), or None to remove it."""
        if a_ver is None:
            return self._replace(a_ver=None)
        if np.isscalar(a_ver):  # ("0.5" and True were read as ratios 0.5 and 1)
            ratio = number("a_ver", a_ver, "a ratio r (a_ver = r a_hor), an array of the "
                           "record's samples or None")  # fmt: skip
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
    raise ValueError(
        f"unknown acceleration unit {units!r}; use 'g', 'gal' (cm/s2), 'mm/s2' or 'm/s2'"
    )


_S, _WORD = r"[ \t]", r"([A-Za-z][\w/^*²]*)"  # (spaces within a line: a pattern is one line's)
_UNIT_PATTERNS = [
    re.compile(rf"\bunits?{_S}*[:=]{_S}*\(?{_S}*{_WORD}", re.I),  # units: g / UNIT = gal
    re.compile(rf"\bacc(?:eleration|\.)?{_S}+in{_S}+\(?{_S}*{_WORD}", re.I),  # Acc. in cm/s/s
    re.compile(rf"\bin{_S}+units{_S}+of{_S}+\(?{_S}*{_WORD}", re.I),  # IN UNITS OF G
    re.compile(rf"\bunits{_S}+are{_S}+\(?{_S}*{_WORD}", re.I),  # The units are (g)
    # a line of "units WORD" alone, without its colon ("units m/s^2" was "not stated")
    re.compile(rf"^[^\w\n]*units?{_S}+\(?{_S}*{_WORD}\)?{_S}*$", re.I | re.M),
]


UNKNOWN_UNITS = "unknown:"  # header_units' prefix of a "units: WORD" it does not know
CONFLICT_UNITS = "conflict:"  # header_units' prefix of two different units it states
# a unit on a line about a peak or a spectrum, not the record's samples ("Peak given in units
# of g" in a file of cm/s/s): no conflict with the samples' unit
_ASIDE = re.compile(r"peak|max|pga|spectr|sensor", re.I)
# the first pattern anchored at a line's start (one source for the two)
_UNITS_LINE = re.compile(r"^[ \t]*" + _UNIT_PATTERNS[0].pattern.removeprefix(r"\b"), re.I | re.M)


def header_units(header: list[str]) -> str | None:
    """Units stated in a header, by the patterns above in priority order; None if not stated.
    Two different units stated by phrases not on a line about a peak (``_ASIDE``) give
    ``CONFLICT_UNITS`` and their names (refused unless units are given). A line "units:
    WORD" (it states units and nothing else) whose word is no unit gives ``UNKNOWN_UNITS +
    WORD`` (:func:`nsdyn.ground.formats.resolve_units` refuses it); the looser phrases of the
    patterns ("time units: s", "acc. in ...") are skipped when their word is no unit."""
    text = "\n".join(header)
    stated = []  # (aside, name, factor) in priority order: a line about a peak is an aside
    for pattern in _UNIT_PATTERNS:
        for m in pattern.finditer(text):
            try:
                name, factor = unit_factor(m.group(1).rstrip("."))
            except ValueError:
                continue
            # the phrase holding the unit, from the line's last separator before it ("max =
            # 0.3 g, units: gal": the units' phrase is no aside)
            start = max(text.rfind(c, 0, m.start()) for c in "\n,;") + 1
            stated.append((bool(_ASIDE.search(text[start : m.end()])), name, factor))
    if stated:  # the first phrase not an aside, else the first (as the patterns rank them)
        _, name, factor = min(stated, key=lambda x: x[0])
        other = next((n for aside, n, f in stated if not aside and f != factor), None)
        if other is not None:  # ("units: g" over "units: gal" or "acc. in cm/s/s": the first
            return f"{CONFLICT_UNITS}{name!r} and {other!r}"  # won, unsaid)
        return name
    m = _UNITS_LINE.search(text)  # a line that states units and nothing else ("time units:
    return UNKNOWN_UNITS + m.group(1) if m else None  # s" is not one)


_UNIT_SCALE = (("cm/s² (gal)", 0.01), ("m/s²", 1.0), ("g", G_STANDARD))


def _likelier_units(units: str, larger: bool) -> str:
    """The units a file read with ``units`` is probably in: those larger (``larger``) or
    smaller than them, e.g. 'm/s² or g' for a file read as gal whose PGA is too small."""
    try:
        f = unit_factor(units)[1]
    except ValueError:
        return "other units"
    names = [n for n, k in _UNIT_SCALE if (k > f if larger else k < f)]
    return " or ".join(names) if names else "other units"


def check_pga(motion: GroundMotion, units: str | None = None) -> None:
    """Warn (UnitWarning) when the PGA lies outside the plausible range of m/s² (the advice
    depends on whether the reader was given the file's ``units``: then the likelier units
    are those larger, or smaller, than the ones given), or the sampling step is above
    :data:`DT_MAX_PLAUSIBLE` (a time in milliseconds read as seconds)."""
    pga = motion.pga
    given = units is not None
    fix = (f"check the units given, units={units!r}" if given
           else f"give its units ({UNITS_HINT})")  # fmt: skip
    if pga == 0.0:
        warnings.warn(f"{motion.source}: the record is zero at every sample", UnitWarning,
                      stacklevel=3)  # fmt: skip
    elif pga > PGA_MAX_PLAUSIBLE:
        why = (f"probably in {_likelier_units(units, False)}, read as {units!r}" if given
               else "probably in cm/s² (gal) read as m/s², or in m/s² read as g")  # fmt: skip
        warnings.warn(
            f"{motion.source}: PGA = {pga:.4g} m/s² > {PGA_MAX_PLAUSIBLE:g} m/s²; the file is "
            f"{why}: {fix}",
            UnitWarning,
            stacklevel=3,
        )
    elif pga < PGA_MIN_PLAUSIBLE:
        why = (f"probably in {_likelier_units(units, True)}, read as {units!r}" if given
               else "probably in g read as m/s²")  # fmt: skip
        warnings.warn(
            f"{motion.source}: PGA = {pga:.4g} m/s² < {PGA_MIN_PLAUSIBLE:g} m/s²; the file is "
            f"{why}: {fix}",
            UnitWarning,
            stacklevel=3,
        )
    if motion.dt > DT_MAX_PLAUSIBLE:
        warnings.warn(
            f"{motion.source}: a sampling step of {motion.dt:g} s > {DT_MAX_PLAUSIBLE:g} s (no "
            f"content above {0.5 / motion.dt:.2g} Hz); is the time column, or the header's "
            "dt, in milliseconds? (nsdyn reads times in seconds; a header may say 'dt = 20 ms')",
            UnitWarning,
            stacklevel=3,
        )


BY_HAND = "samples given in Python"  # the source of a record built from arrays


def check_hand_pga(motion, kind: str, pga: float) -> None:
    """A record built from arrays (no ``source``) takes m/s²: warn (UnitWarning, at the
    caller's line) when its horizontal peak ``pga`` lies outside the plausible range (a zero
    record is a free vibration's, and stays silent), then name its source :data:`BY_HAND`
    so that records derived from it do not warn again."""
    if pga > PGA_MAX_PLAUSIBLE or 0.0 < pga < PGA_MIN_PLAUSIBLE:
        side = (f"> {PGA_MAX_PLAUSIBLE:g} m/s²; in cm/s² (gal)? multiply by 0.01"
                if pga > PGA_MAX_PLAUSIBLE
                else f"< {PGA_MIN_PLAUSIBLE:g} m/s²; in g? multiply by {G_STANDARD}")  # fmt: skip
        warnings.warn(
            f"{kind}: horizontal PGA = {pga:.4g} m/s² {side} ({kind} takes m/s²; "
            "give source= to say where the samples come from and silence this)",
            UnitWarning,
            stacklevel=4,
        )
    object.__setattr__(motion, "source", BY_HAND)
