"""Closed-form acceleration pulses: one-sine, one-cosine, N-cycle sines and the Ricker wavelet.

With ``tau = t - t_start``, ``T_p = 2 pi / omega_p`` and ``D`` the duration:

- sine (N cycles):   ``a(t) = a_p sin(omega_p tau)``,  0 <= tau < D = N T_p;
- cosine (N cycles): ``a(t) = a_p cos(omega_p tau)``,  0 <= tau < D = N T_p;
- rectangular:       ``a(t) = a_p``,                   0 <= tau < D = N T_p (Housner's pulse);
- Ricker:            ``a(t) = a_p (1 - omega_p^2 s^2 / 2) exp(-omega_p^2 s^2 / 4)``,
  ``s = tau - t_c``, ``t_c = RICKER_CENTRE T_p``, 0 <= tau < D = 2 t_c
  (the symmetric Mexican-hat wavelet whose Fourier amplitude peaks at omega_p);

zero elsewhere; the vertical component, if asked for, is ``ver_ratio * a(t)``. The one-sine
pulse of seed 003 Table 4 is ``one_sine(a_p, omega_p=12.57)`` (T_p = 0.5 s). A pulse samples
itself into a :class:`~nsdyn.ground.GroundMotion`, and gives ``code()``, the flat parameter
array through which rocking kernels evaluate the same closed forms exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Real

import numpy as np

from nsdyn._checks import number
from nsdyn.ground.motion import GroundMotion

RICKER_CENTRE = 1.5  # centre of the Ricker wavelet after its start, in periods T_p (tail ~2e-10)
SHAPES = {
    "sine": 1,
    "cosine": 2,
    "ricker": 3,
    "rect": 4,
}  # pulse shape -> integer code of the kernels


@dataclass(frozen=True)
class Pulse:
    """A closed-form acceleration pulse (see the module docstring for the shapes).

    Attributes
    ----------
    shape : {"sine", "cosine", "ricker", "rect"}
    a_p : float
        Amplitude [m/s²] (sign gives the direction).
    omega_p : float
        Angular frequency [rad/s].
    n_cycles : int
        Number of full cycles (sine and cosine; 1 for Ricker).
    t_start : float
        Start time [s].
    ver_ratio : float
        Vertical acceleration as a fraction of the horizontal one (0: none).
    """

    shape: str
    a_p: float
    omega_p: float
    n_cycles: int = 1
    t_start: float = 0.0
    ver_ratio: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.shape, str) or self.shape not in SHAPES:
            raise ValueError(f"shape: expected one of {sorted(SHAPES)}, got {self.shape!r}")
        number("a_p", self.a_p, "a finite amplitude [m/s²]")
        number("omega_p", self.omega_p, "a positive angular frequency [rad/s]", lambda v: v > 0)
        # (a NaN ratio left the block standing: every vertical sample NaN, no uplift found)
        number("t_start", self.t_start, "a finite start time [s]")
        number("ver_ratio", self.ver_ratio, "a finite vertical-to-horizontal ratio")
        n = self.n_cycles
        if isinstance(n, bool) or not isinstance(n, Real) or int(n) != n or n < 1:
            raise ValueError(f"n_cycles: expected an integer >= 1, got {n!r}")

    @property
    def T_p(self) -> float:
        """Period 2 pi / omega_p [s]."""
        return 2.0 * math.pi / self.omega_p

    @property
    def duration(self) -> float:
        """Length D of the non-zero part [s]."""
        if self.shape == "ricker":
            return 2.0 * RICKER_CENTRE * self.T_p
        return self.n_cycles * self.T_p

    def scaled(self, a_p: float) -> Pulse:
        """The same pulse with amplitude ``a_p``."""
        return Pulse(self.shape, a_p, self.omega_p, self.n_cycles, self.t_start, self.ver_ratio)

    def accel(self, t: np.ndarray | float) -> np.ndarray:
        """Horizontal acceleration a(t) [m/s²], same shape as ``t``."""
        t = np.asarray(t, dtype=float)
        tau = t - self.t_start
        inside = (tau >= 0.0) & (tau < self.duration)
        w = self.omega_p
        if self.shape == "sine":
            a = self.a_p * np.sin(w * tau)
        elif self.shape == "cosine":
            a = self.a_p * np.cos(w * tau)
        elif self.shape == "rect":
            a = np.full_like(tau, self.a_p)
        else:
            s2 = (w * (tau - RICKER_CENTRE * self.T_p)) ** 2
            a = self.a_p * (1.0 - 0.5 * s2) * np.exp(-0.25 * s2)
        return np.where(inside, a, 0.0)

    def code(self) -> np.ndarray:
        """Flat parameters ``[shape code, a_p, omega_p, duration, t_start, ver_ratio, t_c]``."""
        t_c = RICKER_CENTRE * self.T_p if self.shape == "ricker" else 0.0
        return np.array(
            [
                SHAPES[self.shape],
                self.a_p,
                self.omega_p,
                self.duration,
                self.t_start,
                self.ver_ratio,
                t_c,
            ],
            dtype=np.float64,
        )

    def to_motion(self, dt: float, t_end: float | None = None) -> GroundMotion:
        """Sampled on ``0, dt, …, t_end`` (default: the end of the pulse)."""
        t_end = self.t_start + self.duration if t_end is None else t_end
        t = np.arange(int(math.floor(t_end / dt + 1e-9)) + 1) * dt
        a = self.accel(t)
        a_ver = self.ver_ratio * a if self.ver_ratio else None
        return GroundMotion(
            0.0,
            dt,
            a,
            a_ver,
            name=f"{self.shape}-pulse",
            source=repr(self),
            meta={"generator": "pulse", "shape": self.shape, "a_p": self.a_p},
        )


def one_sine(a_p: float, omega_p: float, t_start: float = 0.0, ver_ratio: float = 0.0) -> Pulse:
    """One full cycle ``a_p sin(omega_p t)`` (seed 003 Table 4: omega_p = 12.57 rad/s)."""
    return Pulse("sine", a_p, omega_p, 1, t_start, ver_ratio)


def one_cosine(a_p: float, omega_p: float, t_start: float = 0.0, ver_ratio: float = 0.0) -> Pulse:
    """One full cycle ``a_p cos(omega_p t)`` (jumps to a_p at the start)."""
    return Pulse("cosine", a_p, omega_p, 1, t_start, ver_ratio)


def n_cycle_sine(
    a_p: float, omega_p: float, n_cycles: int, t_start: float = 0.0, ver_ratio: float = 0.0
) -> Pulse:
    """``n_cycles`` full cycles of ``a_p sin(omega_p t)``."""
    return Pulse("sine", a_p, omega_p, n_cycles, t_start, ver_ratio)


def rectangular(a_p: float, duration: float, t_start: float = 0.0) -> Pulse:
    """Constant acceleration ``a_p`` for ``duration`` seconds."""
    d = number("duration", duration, "a positive duration [s]", lambda v: v > 0)
    return Pulse("rect", a_p, 2.0 * math.pi / d, 1, t_start)


def ricker(a_p: float, omega_p: float, t_start: float = 0.0, ver_ratio: float = 0.0) -> Pulse:
    """Ricker wavelet of peak ``a_p`` centred ``RICKER_CENTRE T_p`` after ``t_start``."""
    return Pulse("ricker", a_p, omega_p, 1, t_start, ver_ratio)
