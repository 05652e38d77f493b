"""Analytic and tabulated excitations that the kernels evaluate themselves: ground or force.

Ground accelerations (load ``-M Gamma [ü_hor, ü_ver + g]``, Gamma the influence vectors):

- ``Harmonic``: ``ü_hor(t) = A_hor sin(2π f_hor t + phase)`` plus an optional vertical
  ``ü_ver(t) = A_ver sin(2π f_ver t + phase_ver)`` [m/s², Hz, rad];
- ``Table``: uniformly sampled accelerations, linearly interpolated, zero outside the table;
- a recorded or synthesised :class:`nsdyn.ground.GroundMotion` (``as_arrays()``).

Forces (load ``b F(t)``, with the load vector ``b = Σ_k w_k e_{dof_k}`` over chosen dofs):

- ``HarmonicForce``: ``F(t) = F sin(2π f t + phase)`` [N, Hz, rad];
- ``ForceTable``: a sampled force history [N] (linear interpolation, zero outside), also from
  a ground record scaled to a force (``ForceTable.from_motion(motion, dofs, scale)``).

A harmonic excitation has no natural end: a transient run needs its duration (``t_end`` or
``n_periods``); tables and records end with their last sample (:func:`natural_end`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nsdyn._checks import forcing_frequency, number, real_samples

G_EARTH = 9.81  # m/s², gravity acting on the models (records in g use G_STANDARD)


def _finite(name: str, v) -> float:
    """``v`` as a float; text, a bool or a non-finite value is refused naming ``name``."""
    return number(name, v, "a finite number")


def _spanning(name: str, a, what: str = "real samples") -> np.ndarray:
    """:func:`nsdyn._checks.real_samples` of a table: two samples or more (one spans no
    time), or ValueError naming ``name``."""
    arr = real_samples(name, a, what)
    if arr.size < 2:
        raise ValueError(f"{name}: expected two samples or more (a table spans time), got "
                         f"{arr.size}")  # fmt: skip
    return arr


def _frequency(name: str, f, amplitude) -> None:
    """A harmonic component's frequency: finite and >= 0, and > 0 when its amplitude is not
    zero (a component without amplitude needs no frequency)."""
    f, a = _finite(name, f), float(amplitude)
    if f < 0 or (f == 0 and a != 0):
        raise ValueError(
            f"{name}: expected a positive frequency [Hz] (a non-zero amplitude needs one), "
            f"got {f:g}"
        )


@dataclass(frozen=True)
class Harmonic:
    """Harmonic ground acceleration ``A_hor sin(2π f_hor t + phase)`` (+ optional vertical).

    Attributes
    ----------
    A_hor, f_hor : float       amplitude [m/s²] and frequency [Hz] of the horizontal component
    A_ver, f_ver : float       the same for the vertical component (default none)
    phase, phase_ver : float   phases [rad] at t = 0 (sin: the excitation starts at zero)

    Every value is finite; a frequency is >= 0, and > 0 where its amplitude is not zero.
    """

    A_hor: float
    f_hor: float
    A_ver: float = 0.0
    f_ver: float = 0.0
    phase: float = 0.0
    phase_ver: float = 0.0

    def __post_init__(self) -> None:
        for k in ("A_hor", "f_hor", "A_ver", "f_ver", "phase", "phase_ver"):
            object.__setattr__(self, k, _finite(f"Harmonic.{k}", getattr(self, k)))
        _frequency("Harmonic.f_hor", self.f_hor, self.A_hor)
        _frequency("Harmonic.f_ver", self.f_ver, self.A_ver)

    @property
    def period(self) -> float:
        """Period of the horizontal component [s] (inf for f_hor = 0)."""
        return 1.0 / self.f_hor if self.f_hor else math.inf

    @property
    def fastest_period(self) -> float:
        """Period of its fastest component [s] (a vertical one's where it has an amplitude):
        the default output step samples it (:data:`nsdyn.solve.transient.HARMONIC_SAMPLES`)."""
        f = forcing_frequency(self)  # (the components' one rule)
        return min(self.period, 1.0 / f if f else math.inf)


@dataclass(frozen=True)
class Table:
    """Sampled ground acceleration (uniform ``dt``, linear interpolation, zero outside).

    Checked where it is built: ``t0`` finite, ``dt`` > 0, ``a_hor`` two or more finite real
    samples [m/s²] (a force's [N] where a :class:`ForceTable` makes the table), ``a_ver`` as
    many; bad input is refused naming the field (``Table.dt``, ``Table.a_hor``, ...). Unlike a
    :class:`nsdyn.ground.GroundMotion`'s, the samples have no magnitude bound (forces pass
    through a table) and one sample is refused here, not by the run.
    """

    t0: float
    dt: float
    a_hor: np.ndarray
    a_ver: np.ndarray | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "t0", _finite("Table.t0", self.t0))
        dt = number("Table.dt", self.dt, "a positive step [s]", lambda v: v > 0)
        object.__setattr__(self, "dt", dt)
        a_hor = _spanning("Table.a_hor", self.a_hor)  # (one sample: a run without a word)
        object.__setattr__(self, "a_hor", a_hor)
        if self.a_ver is not None:
            a_ver = real_samples("Table.a_ver", self.a_ver)
            if a_ver.shape != a_hor.shape:
                raise ValueError(f"Table.a_ver: expected {a_hor.size} samples (as a_hor), "
                                 f"got {a_ver.size}")  # fmt: skip
            object.__setattr__(self, "a_ver", a_ver)

    @property
    def duration(self) -> float:
        return self.dt * max(len(self.a_hor) - 1, 0)


def _load_dofs(dofs, weights) -> tuple[tuple[int, ...], tuple[float, ...]]:
    d = np.atleast_1d(np.asarray(dofs))
    if d.size == 0 or d.ndim != 1 or not np.issubdtype(d.dtype, np.integer):
        raise ValueError(f"dofs: expected one or more integer dof indices, got {dofs!r}")
    if np.any(d < 0) or len(set(d.tolist())) != d.size:
        raise ValueError(f"dofs: expected distinct non-negative indices, got {d.tolist()}")
    if weights is None:
        w = np.ones(d.size)
    else:
        w = np.atleast_1d(np.asarray(weights, dtype=float))
        if w.shape != d.shape or not np.all(np.isfinite(w)):
            raise ValueError(
                f"weights: expected {d.size} finite numbers (one per dof), got {weights!r}"
            )
    return tuple(int(k) for k in d), tuple(float(x) for x in w)


class _ForceLoad:
    """Load vector ``b`` of a force excitation: weight ``w_k`` at dof ``dofs[k]``."""

    dofs: tuple
    weights: tuple

    def load_vector(self, n: int) -> np.ndarray:
        """``b`` (n,): the force F(t) acts as ``b F(t)`` on the equations of motion."""
        if max(self.dofs) >= n:
            raise ValueError(
                f"{type(self).__name__}.dofs: index {max(self.dofs)} out of range for a "
                f"system with {n} dofs"
            )
        b = np.zeros(n)
        b[list(self.dofs)] = self.weights
        return b


@dataclass(frozen=True)
class HarmonicForce(_ForceLoad):
    """Harmonic force ``F sin(2π f t + phase)`` [N] at ``dofs`` (load ``b F(t)``).

    ``weights`` (one per dof, default 1) distribute it: ``b = Σ_k weights_k e_{dofs_k}``.
    """

    F: float
    f: float
    dofs: tuple
    weights: tuple | None = None
    phase: float = 0.0

    def __post_init__(self) -> None:
        for k in ("F", "f", "phase"):
            object.__setattr__(self, k, _finite(f"HarmonicForce.{k}", getattr(self, k)))
        _frequency("HarmonicForce.f", self.f, self.F)
        d, w = _load_dofs(self.dofs, self.weights)
        object.__setattr__(self, "dofs", d)
        object.__setattr__(self, "weights", w)

    @property
    def period(self) -> float:
        return 1.0 / self.f if self.f else math.inf

    def channel(self) -> Harmonic:
        """The time function F(t) as the kernels evaluate it."""
        return Harmonic(self.F, self.f, phase=self.phase)

    def at_frequency(self, f: float, F: float | None = None) -> HarmonicForce:
        """The same load at another frequency (and amplitude)."""
        return HarmonicForce(self.F if F is None else F, f, self.dofs, self.weights, self.phase)


@dataclass(frozen=True)
class ForceTable(_ForceLoad):
    """Sampled force history ``F`` [N] at ``dofs`` (uniform ``dt``, linear interpolation,
    zero outside); load ``b F(t)`` as for :class:`HarmonicForce`."""

    t0: float
    dt: float
    F: np.ndarray
    dofs: tuple
    weights: tuple | None = None
    name: str = "force"

    def __post_init__(self) -> None:
        try:  # (ragged lists: numpy's "inhomogeneous shape", naming nothing)
            F = np.asarray(self.F)
        except (TypeError, ValueError):
            raise ValueError(f"ForceTable.F: expected real forces [N], got {self.F!r}"[:200]
                             ) from None  # fmt: skip
        if F.ndim > 1 and max(F.shape) != F.size:  # a table of several columns
            raise ValueError(
                f"ForceTable.F: expected one force history (shape (n,)), got shape {F.shape}; "
                "the load pattern is the vector b (one force applied at dofs)"
            )
        # (text, complex and bools refused: complex forces lost their imaginary part with only
        # numpy's warning; one sample: "t_end" blamed, not given)
        F = _spanning("ForceTable.F", F.reshape(-1) if F.ndim != 1 else F, "real forces [N]")
        # (as a float: a numpy float32 step's end fell beside its last sample's time)
        dt = number("ForceTable.dt", self.dt, "a positive step [s]", lambda v: v > 0)
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "t0", _finite("ForceTable.t0", self.t0))
        d, w = _load_dofs(self.dofs, self.weights)
        object.__setattr__(self, "F", F)
        object.__setattr__(self, "dofs", d)
        object.__setattr__(self, "weights", w)

    @property
    def duration(self) -> float:
        return self.dt * (self.F.size - 1)

    @property
    def t(self) -> np.ndarray:
        return self.t0 + self.dt * np.arange(self.F.size)

    def channel(self) -> Table:
        return Table(float(self.t0), float(self.dt), self.F)

    @classmethod
    def from_motion(cls, motion, dofs, scale: float, weights=None) -> ForceTable:
        """A ground record's horizontal acceleration as a force ``scale * a_hor(t)`` [N].

        ``scale`` [N per m/s², e.g. ``-m`` for the effective earthquake force on a mass m]
        has no default: the force's size is the caller's choice.
        """
        t0, dt, ah, _ = motion.as_arrays()
        name = f"{getattr(motion, 'name', 'record')} x {scale:g} N/(m/s²)"
        return cls(
            float(t0), float(dt), _finite("scale", scale) * np.asarray(ah), dofs, weights, name
        )


FORCES = (HarmonicForce, ForceTable)  # the force excitations (load b F(t))


def is_force(excitation) -> bool:
    """True for a force excitation (load ``b F(t)``), False for a ground acceleration."""
    return isinstance(excitation, FORCES)


def natural_end(excitation) -> float | None:
    """Last instant of an excitation with one (a table or record), None for a harmonic one."""
    if excitation is None or isinstance(excitation, Harmonic | HarmonicForce):
        return None
    t0 = float(getattr(excitation, "t0", 0.0))
    if hasattr(excitation, "duration"):
        return t0 + float(excitation.duration)
    return None
