"""The three-component ground motion: two horizontal accelerations and an optional vertical one.

A three-component record is the base acceleration ü_g(t) = [a_x(t), a_y(t), a_z(t)] in m/s²,
sampled on a uniform grid t_k = t0 + k Δt, k = 0 … n−1; x and y are horizontal, z points up and
a_z does **not** contain gravity (as ``GroundMotion.a_ver``).

Axes and the rotation convention: x, y, z are right-handed with z up, so seen from above the
direction angle θ is measured from +x towards +y (counter-clockwise). ``rotated(θ)`` turns the
motion itself by θ about z:

    [a_x'; a_y'] = R(θ) [a_x; a_y],    R(θ) = [[cos θ, −sin θ], [sin θ, cos θ]],

so a motion along +x becomes a motion along the direction θ. The components of the *same* motion
in axes turned by φ are ``rotated(−φ)``. Multiples of 90° use the exact cosines and sines 0, ±1.

Derived quantities:

    PGA_x = max_k |a_x|,  PGA_y = max_k |a_y|,  PGA_ver = max_k |a_z|,
    PGA_resultant = max_k √(a_x² + a_y²)   (invariant under rotation),
    PGA_geomean = √(PGA_x PGA_y)            (depends on the orientation of the axes).

A planar record (one horizontal component a along direction θ, vertical a_v) is the special case

    a_x = a cos θ,  a_y = a sin θ,  a_z = a_v                       (``from_planar``),

and the projection of a three-component record on the direction θ is the planar record

    a = a_x cos θ + a_y sin θ,  a_v = a_z                            (``planar``).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from nsdyn._checks import number
from nsdyn.ground.motion import (
    GroundMotion,
    Sampled,
    check_hand_pga,
    check_meta,
    pga_target,
    samples,
)

_PEAKS = ("resultant", "x", "y", "geomean")


def cos_sin_deg(angle_deg: float) -> tuple[float, float]:
    """(cos θ, sin θ) of an angle in degrees; exact (0, ±1) at multiples of 90°."""
    a = number("angle_deg", angle_deg, "a finite angle in degrees")
    q, r = divmod(a, 90.0)
    if r == 0.0:
        return ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[int(q) % 4]
    rad = math.radians(a)
    return math.cos(rad), math.sin(rad)


def _array(name: str, a, n: int | None) -> np.ndarray:
    return samples(f"GroundMotion3.{name}", a, n)


@dataclass(frozen=True, eq=False, repr=False)
class GroundMotion3(Sampled):
    """Uniformly sampled three-component base acceleration (see the module docstring).

    Attributes
    ----------
    t0 : float
        Time of the first sample [s].
    dt : float
        Sampling interval [s], uniform, > 0.
    ax, ay : ndarray, shape (n,)
        Horizontal accelerations along x and y [m/s²] (float64, C-contiguous).
    az : ndarray, shape (n,) or None
        Vertical acceleration [m/s²], up, without gravity; None when the record has none.
    name : str
        Short name (station, bundled name, file stem).
    source : str
        The files it was read from, or how it was made.
    meta : dict
        Anything else (units on file, rotation applied, seed, scale factor, …).
    """

    t0: float
    dt: float
    ax: np.ndarray
    ay: np.ndarray
    az: np.ndarray | None = None
    name: str = "motion3"
    source: str = ""
    meta: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        dt = number("GroundMotion3.dt", self.dt, "a positive finite step [s]", lambda v: v > 0)
        t0 = number("GroundMotion3.t0", self.t0, "a finite time [s]")
        ax = _array("ax", self.ax, None)
        object.__setattr__(self, "ax", ax)
        if self.ay is None:  # (it read "non-numeric values")
            raise ValueError("GroundMotion3.ay: missing; expected the second horizontal "
                             "component (zeros for none: GroundMotion3.from_planar)")  # fmt: skip
        object.__setattr__(self, "ay", _array("ay", self.ay, ax.size))
        if self.az is not None:
            object.__setattr__(self, "az", _array("az", self.az, ax.size))
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "t0", t0)
        check_meta(self)
        if not self.source:
            check_hand_pga(self, "GroundMotion3", max(self.pga_x, self.pga_y))

    def __repr__(self) -> str:
        ver = "none" if self.az is None else f"{self.pga_ver:.4g} m/s²"
        return (
            f"GroundMotion3(name={self.name!r}, n={self.n}, dt={self.dt:g} s, "
            f"duration={self.duration:g} s, pga_x={self.pga_x:.4g}, pga_y={self.pga_y:.4g}, "
            f"pga_resultant={self.pga_resultant:.4g} m/s², vertical={ver})"
        )

    # ---- derived quantities ---------------------------------------------------------------
    @property
    def n(self) -> int:
        """Number of samples."""
        return int(self.ax.size)

    @property
    def pga_x(self) -> float:
        """max_k |a_x| [m/s²]."""
        return float(np.max(np.abs(self.ax)))

    @property
    def pga_y(self) -> float:
        """max_k |a_y| [m/s²]."""
        return float(np.max(np.abs(self.ay)))

    @property
    def pga_resultant(self) -> float:
        """max_k √(a_x² + a_y²) [m/s²], the peak of the horizontal acceleration vector."""
        return float(np.max(np.hypot(self.ax, self.ay)))

    @property
    def pga_geomean(self) -> float:
        """√(PGA_x PGA_y) [m/s²], the geometric mean of the two horizontal peaks."""
        return math.sqrt(self.pga_x * self.pga_y)

    @property
    def pga_ver(self) -> float | None:
        """max_k |a_z| [m/s²], or None without a vertical component."""
        return None if self.az is None else float(np.max(np.abs(self.az)))

    def component(self, name: str) -> np.ndarray:
        """The samples of component "x", "y" or "z" (also "ver") [m/s²]; the record's own array."""
        if name == "x":
            return self.ax
        if name == "y":
            return self.ay
        if name in ("z", "ver"):
            if self.az is None:
                raise ValueError(f"{self.name!r} has no vertical component (z)")
            return self.az
        raise ValueError(f"component: expected 'x', 'y' or 'z', got {name!r}")

    def velocity(self, component: str = "x") -> np.ndarray:
        """Ground velocity of one component [m/s], trapezoidal rule from rest (as
        ``GroundMotion.velocity``)."""
        return GroundMotion(
            self.t0, self.dt, self.component(component), source=self.source
        ).velocity()

    def displacement(self, component: str = "x") -> np.ndarray:
        """Ground displacement of one component [m], trapezoidal rule twice from rest."""
        a = self.component(component)
        return GroundMotion(self.t0, self.dt, a, source=self.source).displacement()

    def as_arrays(self) -> tuple[float, float, np.ndarray, np.ndarray, np.ndarray]:
        """``(t0, dt, ax, ay, az)`` for numba kernels: float64 C-contiguous, az zeros if None.

        The arrays are the record's own (not copies); do not modify them.
        """
        az = self.az if self.az is not None else np.zeros_like(self.ax)
        return self.t0, self.dt, self.ax, self.ay, az

    # ---- transformations (each returns a new record) --------------------------------------
    def _replace(self, **changes: Any) -> GroundMotion3:
        meta = dict(self.meta)
        meta.update(changes.pop("meta_update", {}))
        return dataclasses.replace(self, meta=meta, **changes)

    def rotated(self, angle_deg: float) -> GroundMotion3:
        """The motion turned by ``angle_deg`` counter-clockwise about z (seen from above):
        [a_x'; a_y'] = R(θ)[a_x; a_y]. The vertical is unchanged; ``rotated(−θ)`` undoes it."""
        angle_deg = number("angle_deg", angle_deg, "a finite angle [deg]")
        c, s = cos_sin_deg(angle_deg)
        total = float(self.meta.get("rotation_deg", 0.0)) + float(angle_deg)
        return self._replace(
            ax=c * self.ax - s * self.ay,
            ay=s * self.ax + c * self.ay,
            meta_update={"rotation_deg": total},
        )

    def scaled_to_pga(self, target: float, component: str = "resultant") -> GroundMotion3:
        """All three components times one factor c = target / peak, so that the chosen peak
        ("resultant", "x", "y" or "geomean", see the module docstring) equals ``target`` [m/s²]."""
        if component not in _PEAKS:
            raise ValueError(f"component: expected one of {_PEAKS}, got {component!r}")
        target = pga_target(target)
        peak = {
            "resultant": lambda: self.pga_resultant,
            "x": lambda: self.pga_x,
            "y": lambda: self.pga_y,
            "geomean": lambda: self.pga_geomean,
        }[component]()
        if peak == 0.0:
            why = "(every sample)"
            if component == "geomean" and self.pga_resultant > 0.0:  # (one component at rest)
                why = f"(sqrt(PGA_x PGA_y): {'x' if self.pga_x == 0.0 else 'y'} is zero everywhere)"
            raise ValueError(f"record {self.name!r}: the {component} peak acceleration is zero "
                             f"{why}; it cannot be scaled to a peak")  # fmt: skip
        c = target / peak
        total = c * float(self.meta.get("scale_factor", 1.0))
        az = None if self.az is None else c * self.az
        return self._replace(
            ax=c * self.ax, ay=c * self.ay, az=az, meta_update={"scale_factor": total}
        )

    def _planes(self) -> tuple[GroundMotion, GroundMotion]:
        """The record as two planar records (x with z, y alone) sharing t0, dt and meta."""
        x = GroundMotion(self.t0, self.dt, self.ax, self.az, self.name, self.source, self.meta)
        y = GroundMotion(self.t0, self.dt, self.ay, None, self.name, self.source, self.meta)
        return x, y

    def _from_planes(self, x: GroundMotion, y: GroundMotion) -> GroundMotion3:
        return GroundMotion3(x.t0, x.dt, x.a_hor, y.a_hor, x.a_ver, self.name, self.source, x.meta)

    def baseline_corrected(self, order: int = 1, on: str = "velocity") -> GroundMotion3:
        """Each component corrected by ``GroundMotion.baseline_corrected`` (a linear operation,
        so it commutes with rotation)."""
        x, y = self._planes()
        return self._from_planes(x.baseline_corrected(order, on), y.baseline_corrected(order, on))

    def window(self, t_start: float, t_end: float) -> GroundMotion3:
        """The samples with t_start ≤ t ≤ t_end (absolute times), as ``GroundMotion.window``."""
        x, y = self._planes()
        return self._from_planes(x.window(t_start, t_end), y.window(t_start, t_end))

    def until(self, t_end: float) -> GroundMotion3:
        """The record from its start to ``t_end``, as ``GroundMotion.until``."""
        x, y = self._planes()
        return self._from_planes(x.until(t_end), y.until(t_end))

    def resampled(self, dt: float, method: str = "band-limited") -> GroundMotion3:
        """Each component resampled onto t0 + k dt by ``GroundMotion.resampled`` (same method,
        same filter for all three, so the record stays one rigid motion)."""
        x, y = self._planes()
        return self._from_planes(x.resampled(dt, method), y.resampled(dt, method))

    def planar(self, angle_deg: float = 0.0) -> GroundMotion:
        """The projection on the horizontal direction θ: a = a_x cos θ + a_y sin θ, with the
        vertical; a :class:`GroundMotion` (the planar models' record)."""
        c, s = cos_sin_deg(angle_deg)
        a = c * self.ax + s * self.ay  # exact at multiples of 90° (x + 0 = x)
        meta = {**self.meta, "direction_deg": float(angle_deg)}
        return GroundMotion(self.t0, self.dt, a, self.az, self.name, self.source, meta)

    @classmethod
    def from_planar(cls, motion: GroundMotion, angle_deg: float = 0.0) -> GroundMotion3:
        """A planar record as a three-component one, its horizontal component along the
        direction θ: a_x = a cos θ, a_y = a sin θ, a_z = a_ver (exactly a, 0, a_ver at θ = 0)."""
        if not isinstance(motion, GroundMotion):  # (a GroundMotion3: AttributeError 'a_hor')
            raise TypeError(f"motion: expected a planar GroundMotion, got "
                            f"{type(motion).__name__}")  # fmt: skip
        c, s = cos_sin_deg(angle_deg)
        meta = {**motion.meta, "direction_deg": float(angle_deg)}
        return cls(
            motion.t0,
            motion.dt,
            c * motion.a_hor,
            s * motion.a_hor,
            motion.a_ver,
            motion.name,
            motion.source,
            meta,
        )
