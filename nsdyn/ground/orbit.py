"""Harmonic ground acceleration in the plane: linear, circular and elliptical orbits (+ vertical).

The one definition of the formulas (ω = 2π f, φ_y and φ_z in degrees converted to radians):

    a_x(t) = A_x sin(ω t)
    a_y(t) = A_y sin(ω t + φ_y)
    a_z(t) = A_z sin(ω_z t + φ_z),    ω_z = 2π f_z, f_z = f when not given      [m/s², Hz]

with x, y horizontal, z up and right-handed (seen from above, angles count from +x towards +y,
counter-clockwise; the convention of :mod:`nsdyn.ground.motion3`). The horizontal acceleration
vector traces an ellipse, once per period T = 1/f:

* linear along θ: a = A sin(ω t) (cos θ, sin θ) — A_x = A|cos θ|, A_y = A|sin θ|, φ_y = 0° or
  180° (the line's direction is taken with cos θ ≥ 0; θ and θ + 180° are the same line, half a
  period apart);
* circular of radius A: A_x = A_y = A, φ_y = −90° × sense — |a(t)| = A at every instant;
  sense = +1 turns counter-clockwise seen from above, −1 clockwise (the default φ_y = +90° of
  the constructor is clockwise);
* elliptical with semi-axes A_major along θ and A_minor across it: in the principal axes
  (u along θ, v across) u = A_major sin(ω t'), v = −sense A_minor cos(ω t'); rotated by θ and
  written in the form above, with the time origin moved (t = t' + t_s) so that a_x starts at
  zero rising (its phase is zero).

The horizontal orbit is periodic with T = 1/f; the whole excitation is periodic with T only when
A_z = 0 or f_z is a whole multiple of f.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass

import numpy as np

from nsdyn._checks import number
from nsdyn.ground.motion3 import GroundMotion3, cos_sin_deg


def _finite(name: str, v, *, positive: bool = False, nonneg: bool = False) -> float:
    x = number(f"HarmonicPlane.{name}", v, "a finite number")  # text and bools refused
    if positive and not x > 0.0:
        raise ValueError(f"HarmonicPlane.{name}: expected a frequency > 0 [Hz], got {x!r}")
    if nonneg and x < 0.0:
        raise ValueError(f"HarmonicPlane.{name}: expected an amplitude >= 0 [m/s²], got {x!r}")
    return x


# the refusal of a periodic sweep of a scene whose [motion] is no orbit (a record): its fix
NOT_AN_ORBIT = ("motion.kind: nsdyn sweep needs a harmonic orbit (kind = 'orbit': linear, "
                "circular, elliptical or general), not a record; e.g. [motion] kind = 'orbit', "
                "orbit = 'linear', frequency = 1.0, amplitude = 1.0, n_periods = 10 (its shape "
                "kept; --amplitudes and --fmin, --fmax scale and range it)")  # fmt: skip


@dataclass(frozen=True)
class HarmonicPlane:
    """Harmonic ground acceleration in the plane (and vertical); see the module docstring.

    Attributes
    ----------
    f : float              frequency of the horizontal components [Hz], > 0
    ax, ay : float         amplitudes A_x, A_y [m/s²], >= 0
    phase_y_deg : float    phase φ_y of a_y relative to a_x [degrees] (default 90°)
    az : float             vertical amplitude A_z [m/s²], >= 0 (default 0)
    f_z : float or None    vertical frequency [Hz], > 0; None: the same as f
    phase_z_deg : float    vertical phase φ_z [degrees]
    """

    f: float
    ax: float
    ay: float = 0.0
    phase_y_deg: float = 90.0
    az: float = 0.0
    f_z: float | None = None
    phase_z_deg: float = 0.0

    def __post_init__(self) -> None:
        values = {
            "f": _finite("f", self.f, positive=True),
            "ax": _finite("ax", self.ax, nonneg=True),
            "ay": _finite("ay", self.ay, nonneg=True),
            "phase_y_deg": _finite("phase_y_deg", self.phase_y_deg),
            "az": _finite("az", self.az, nonneg=True),
            "phase_z_deg": _finite("phase_z_deg", self.phase_z_deg),
        }
        if self.f_z is not None:
            values["f_z"] = _finite("f_z", self.f_z, positive=True)
        for k, v in values.items():
            object.__setattr__(self, k, v)

    # ---- the orbits engineers name --------------------------------------------------------
    @classmethod
    def linear(cls, f: float, A: float, angle_deg: float = 0.0, **vertical) -> HarmonicPlane:
        """Along the direction θ: a = A sin(ω t)(cos θ, sin θ), the line taken with cos θ ≥ 0.
        ``vertical``: az, f_z, phase_z_deg."""
        c, s = cos_sin_deg(angle_deg)
        if c < 0.0 or (c == 0.0 and s < 0.0):
            c, s = -c, -s  # the same line, half a period later
        A = _finite("A", A, nonneg=True)
        return cls(f, A * c, A * abs(s), 0.0 if s >= 0.0 else 180.0, **vertical)

    @classmethod
    def circular(cls, f: float, A: float, sense: int = +1, **vertical) -> HarmonicPlane:
        """Radius A, constant |a| = A; sense +1 counter-clockwise (seen from above), −1
        clockwise. ``vertical``: az, f_z, phase_z_deg."""
        if sense not in (1, -1):
            raise ValueError(f"HarmonicPlane.sense: expected +1 or -1, got {sense!r}")
        A = _finite("A", A, nonneg=True)
        return cls(f, A, A, -90.0 * sense, **vertical)

    @classmethod
    def elliptical(
        cls,
        f: float,
        A_major: float,
        A_minor: float,
        angle_deg: float = 0.0,
        sense: int = +1,
        **vertical,
    ) -> HarmonicPlane:
        """Semi-axes A_major along θ and A_minor across it, turning counter-clockwise for
        sense = +1; the time origin is where a_x starts rising from zero (module docstring).
        ``vertical``: az, f_z, phase_z_deg (relative to that time origin)."""
        if sense not in (1, -1):
            raise ValueError(f"HarmonicPlane.sense: expected +1 or -1, got {sense!r}")
        a1 = _finite("A_major", A_major, nonneg=True)
        a2 = _finite("A_minor", A_minor, nonneg=True)
        if a2 > a1:
            raise ValueError(
                f"HarmonicPlane.A_minor: expected at most A_major = {a1:g}, got {a2:g}"
            )
        c, s = cos_sin_deg(angle_deg)
        # phasors P (a(t) = Im(P e^{iωt'})): u ↔ a1, v ↔ −sense·a2·i; x = c u − s v, y = s u + c v
        pu, pv = complex(a1, 0.0), complex(0.0, -sense * a2)
        px, py = c * pu - s * pv, s * pu + c * pv
        shift = cmath.phase(px) if abs(px) > 0.0 else 0.0
        phase_y = math.degrees(cmath.phase(py) - shift) if abs(py) > 0.0 else 0.0
        return cls(f, abs(px), abs(py), phase_y, **vertical)

    # ---- evaluation -------------------------------------------------------------------------
    @property
    def name(self) -> str:
        """The orbit in one line (run summaries): frequency, amplitudes, phase."""
        text = (f"harmonic orbit {self.f:g} Hz, A_x {self.ax:g}, A_y {self.ay:g} m/s² (phase "
                f"{self.phase_y_deg:g}°)")  # fmt: skip
        if self.az:
            text += f", A_z {self.az:g} m/s² at {self.vertical_frequency:g} Hz"
        return text

    @property
    def period(self) -> float:
        """T = 1/f [s], the period of the horizontal orbit."""
        return 1.0 / self.f

    @property
    def vertical_frequency(self) -> float:
        """f_z, or f when not given [Hz]."""
        return self.f if self.f_z is None else float(self.f_z)

    def params_rad(self) -> tuple[float, float, float, float, float, float, float]:
        """``(f, A_x, A_y, φ_y, A_z, f_z, φ_z)`` with the phases in radians and f_z resolved:
        the numbers a kernel evaluating the formulas above needs."""
        return (
            self.f,
            self.ax,
            self.ay,
            math.radians(self.phase_y_deg),
            self.az,
            self.vertical_frequency,
            math.radians(self.phase_z_deg),
        )

    def accel(self, t):
        """(a_x, a_y, a_z) [m/s²] at time(s) t [s] (scalars or arrays like t), by the formulas
        of the module docstring (a_z is zero when A_z = 0)."""
        f, A_x, A_y, phy, A_z, f_z, phz = self.params_rad()
        tt = np.asarray(t, dtype=np.float64)
        wt = 2.0 * math.pi * f * tt
        ax = A_x * np.sin(wt)
        ay = A_y * np.sin(wt + phy)
        az = np.zeros_like(wt) if A_z == 0.0 else A_z * np.sin(2.0 * math.pi * f_z * tt + phz)
        if np.ndim(wt) == 0:
            return float(ax), float(ay), float(az)
        return ax, ay, az

    def sampled(
        self, duration: float, dt: float, *, t0: float = 0.0, name: str = "harmonic-plane"
    ) -> GroundMotion3:
        """The excitation sampled on t0 + k dt, 0 ≤ k dt ≤ duration, as a record."""
        if not (math.isfinite(duration) and duration > 0.0 and math.isfinite(dt) and dt > 0.0):
            raise ValueError(
                f"sampled: expected duration > 0 and dt > 0 [s], got {duration!r}, {dt!r}"
            )
        t = t0 + dt * np.arange(int(math.floor(duration / dt * (1.0 + 1e-12))) + 1)
        ax, ay, az = self.accel(t)
        vertical = az if self.az != 0.0 else None
        return GroundMotion3(t0, dt, ax, ay, vertical, name, repr(self), {"generator": repr(self)})
