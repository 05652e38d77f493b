"""Base motion of the body: ground accelerations for the kernels plus ground velocity jumps.

The body is written in the frame of the ground, which loads it with -m a_h(t) horizontally and
-m a_v(t) vertically.  A displacement-driven ground u_g(t) gives a_h = u_g'' where smooth, and a
velocity jump [u_g'] at a kink (a displacement sine A sin(w t) switched on at t = 0 jumps by A w);
in the ground frame the body's velocity jumps by -[u_g'], which the contacts resolve as an impact
(impulsive start).  A smooth start multiplies the sine by a ramp sin^2(pi t / (2 T_r)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from nsdyn._checks import number
from nsdyn.ground import GroundMotion, Harmonic, Table

N_PER_PERIOD = 4000  # samples per period of a tabulated displacement-driven sine
TABLE_MAX = 25_000_000  # samples of such a table (200 MB; 1e6 cycles asked for 30 GiB)


@dataclass(frozen=True)
class BaseMotion:
    """Kernel form of a base excitation.

    Attributes
    ----------
    ex : (8,) [kind, t0, dt, amp, omega, t_on, t_off, phase] (see ``_kgeom.ground_acc``)
    tab_h, tab_v : sampled accelerations [m/s^2] (tab_v empty or of the length of tab_h)
    jumps : (nj, 2) rows (t, ground velocity jump [m/s])
    u_g : optional callable t -> ground displacement, for absolute positions in plots
    """

    ex: np.ndarray
    tab_h: np.ndarray
    tab_v: np.ndarray
    jumps: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    name: str = "base motion"

    def __post_init__(self) -> None:
        """The kernel's arrays, each checked where it is made (a list was an AttributeError
        in the solver, a NaN table a step underflow at t = 0)."""
        shapes = {"ex": "(8,)", "tab_h": "(n,)", "tab_v": "(0,) or tab_h's", "jumps": "(nj, 2)"}
        for name, form in shapes.items():
            try:
                a = np.asarray(getattr(self, name), dtype=np.float64, order="C")  # (the
                # kernels' layout; no copy of a table in it; a 0-D value stays one)
            except (TypeError, ValueError):
                a = np.full(0, np.nan)  # (refused below)
            if name == "jumps" and a.size == 0:
                a = a.reshape(0, 2)
            ok = {"ex": a.shape == (8,), "tab_h": a.ndim == 1,
                  "tab_v": a.ndim == 1 and a.size in (0, np.size(self.tab_h)),
                  "jumps": a.ndim == 2 and a.shape[1:] == (2,)}[name]  # fmt: skip
            bad = np.isnan(a).any() if name == "ex" else not np.all(np.isfinite(a))  # (t_off inf)
            if not ok or bad:
                raise ValueError(f"{name}: expected finite numbers of shape {form} (the kernel's "
                                 f"form: BaseMotion.from_motion, sine_acceleration, ... make "
                                 f"it), got {getattr(self, name)!r:.60}")  # fmt: skip
            object.__setattr__(self, name, a)

    def resolving_step(self, per_period: int = 40, per_sample: int = 10) -> float:
        """The longest fixed step that follows this motion: ``per_sample`` sampling steps of
        a table (a longer step skips its samples), or 1/``per_period`` of a sine's period
        (inf without excitation)."""
        if self.tab_h.size:
            return per_sample * float(self.ex[2])
        if self.ex[0] == 1.0 and self.ex[4] > 0:
            return 2 * math.pi / float(self.ex[4]) / per_period
        return math.inf

    @classmethod
    def none(cls) -> BaseMotion:
        """No excitation (free motion)."""
        return cls(np.array([0.0, 0, 1, 0, 0, 0, 0, 0]), np.zeros(0), np.zeros(0), name="none")

    @classmethod
    def sine_acceleration(cls, amp: float, omega: float, t_on: float = 0.0,
                          t_off: float = math.inf, phase: float = 0.0) -> BaseMotion:  # fmt: skip
        """a_h = amp sin(omega (t - t_on) + phase) on [t_on, t_off] [m/s^2, rad/s]."""
        # (a NaN amplitude ended in a step underflow, "3" in a numba TypingError, a NaN t_on
        # ran without any excitation)
        amp = number("amp", amp, "a finite amplitude [m/s²]")
        omega = number("omega", omega, "a finite frequency >= 0 [rad/s]", lambda v: v >= 0)
        t_on = number("t_on", t_on, "a finite start time [s]")
        phase = number("phase", phase, "a finite phase [rad]")
        number("t_off", t_off, f"an end time after t_on = {t_on:g} s (inf: none)",
               lambda v: v > t_on, finite=False)  # fmt: skip
        ex = np.array([1.0, 0, 1, amp, omega, t_on, min(t_off, 1e300), phase])
        return cls(ex, np.zeros(0), np.zeros(0), name="sine acceleration")

    @classmethod
    def constant(cls, a: float, t_on: float = 0.0) -> BaseMotion:
        """Constant base acceleration ``a`` [m/s^2] from ``t_on``."""
        return cls.sine_acceleration(a, 0.0, t_on, math.inf, math.pi / 2)

    @classmethod
    def from_motion(cls, motion, vertical: bool = True) -> BaseMotion:
        """From a :class:`GroundMotion`, ``Table`` or ``Harmonic`` of ``nsdyn.ground``."""
        if isinstance(motion, GroundMotion):
            t0, dt, ah, av = motion.as_arrays()
            av = np.asarray(av, float) if (vertical and av is not None) else np.zeros(0)
            ex = np.array([0.0, t0, dt, 0, 0, 0, 0, 0])
            return cls(ex, np.ascontiguousarray(ah, float), np.ascontiguousarray(av),
                       name=getattr(motion, "name", "record"))  # fmt: skip
        if isinstance(motion, Table):
            av = motion.a_ver if (vertical and motion.a_ver is not None) else np.zeros(0)
            ex = np.array([0.0, motion.t0, motion.dt, 0, 0, 0, 0, 0])
            return cls(ex, np.asarray(motion.a_hor, float), np.asarray(av, float), name="table")
        if isinstance(motion, Harmonic):
            if motion.A_ver:
                raise ValueError("motion: a vertical harmonic is not supported by contact models")
            return cls.sine_acceleration(
                motion.A_hor, 2 * math.pi * motion.f_hor, phase=motion.phase
            )  # fmt: skip  (it was dropped)
        raise TypeError(f"motion: expected a GroundMotion, Table or Harmonic, got "
                         f"{type(motion).__name__}")  # fmt: skip

    @classmethod
    def displacement_sine(
        cls, A: float, period: float, n_cycles: int = 5, start: str = "impulsive",
        t_ramp: float | None = None,
    ) -> BaseMotion:  # fmt: skip
        """Ground displacement u_g = A sin(2 pi t / T) for ``n_cycles`` periods.

        ``start="impulsive"``: switched on and off abruptly (velocity jumps +-A w at both ends);
        ``start="smooth"``: the sine times sin^2 ramps of length ``t_ramp`` (default one period,
        at most half the motion: ramps that do not overlap) at both ends, tabulated at
        ``N_PER_PERIOD`` samples per period.
        """
        if start not in ("impulsive", "smooth"):
            raise ValueError(f"start: expected 'impulsive' or 'smooth', got {start!r}")
        number("A", A, "a finite amplitude [m]")
        number("period", period, "a positive period [s]", lambda v: v > 0)
        most = TABLE_MAX // N_PER_PERIOD if start == "smooth" else math.inf  # (1e6: 30 GiB)
        what = "a whole number >= 1" + (f" (at most {most:g}, tabulated at {N_PER_PERIOD} a "
                                        "period)" if start == "smooth" else "")  # fmt: skip
        number("n_cycles", n_cycles, what, lambda v: 1 <= v <= most and v == int(v))
        w = 2 * math.pi / period
        t_end = n_cycles * period
        if t_ramp is not None and start == "impulsive":  # (it was dropped without a word)
            raise ValueError("t_ramp: the ramps of start='smooth'; an impulsive start has none")
        if t_ramp is not None:  # (ramps longer than half the motion overlap: no sine left)
            number("t_ramp", t_ramp, f"a positive ramp length [s] of at most half the motion, "
                   f"{t_end / 2:g} s", lambda v: 0 < v <= t_end / 2)  # fmt: skip
        if start == "impulsive":
            ex = np.array([1.0, 0, 1, -A * w * w, w, 0.0, t_end, 0.0])
            jumps = np.array([[0.0, A * w], [t_end, -A * w * math.cos(w * t_end)]])
            return cls(ex, np.zeros(0), np.zeros(0), jumps, "displacement sine (impulsive)")
        tr = min(period, t_end / 2) if t_ramp is None else float(t_ramp)
        dt = period / N_PER_PERIOD
        t = np.arange(0.0, t_end + dt / 2, dt)
        u = A * np.sin(w * t) * _ramp(t, tr, t_end)
        a = np.gradient(np.gradient(u, dt), dt)
        a[0] = a[-1] = 0.0
        ex = np.array([0.0, 0.0, dt, 0, 0, 0, 0, 0])
        return cls(ex, a, np.zeros(0), np.zeros((0, 2)), "displacement sine (smooth)")


def _ramp(t: np.ndarray, tr: float, t_end: float) -> np.ndarray:
    """sin^2 ramp up on [0, tr] and down on [t_end - tr, t_end]."""
    r = np.ones_like(t)
    up = t < tr
    r[up] = np.sin(0.5 * math.pi * t[up] / tr) ** 2
    dn = t > t_end - tr
    r[dn] = np.sin(0.5 * math.pi * (t_end - t[dn]) / tr) ** 2
    return r
