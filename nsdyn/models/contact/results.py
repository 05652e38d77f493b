"""Histories of a contact simulation and their summary (time in each mode, slide, tilt, hops).

Body modes: rest, slide, rock, slide-rock, flight (hop), overturned.  Slide is the horizontal
displacement of the base midpoint relative to the ground, tilt |theta|, a hop an entry into
flight, overturning the tilt reaching theta_ov (the body lies on a side).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

MODE_NAMES = ("rest", "slide", "rock", "slide_rock", "flight", "overturned")


@dataclass
class ContactResult:
    """Sampled history of a body on the ground (ground frame).

    Attributes
    ----------
    t : (n,);  q : (n, 3) (x, y, theta);  v : (n, 3);  mode : (n,) index into MODE_NAMES
    events : list of (t, name, contact) (event-driven) ;  n_impacts ;  t_overturn (or None)
    base_mid : (2,) base midpoint relative to the centre of mass (body frame)
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    mode: np.ndarray
    solver: str
    base_mid: np.ndarray
    theta_ov: float
    n_impacts: int = 0
    t_overturn: float | None = None
    events: list = field(default_factory=list)
    n_steps: int = 0
    n_rhs: int = 0

    @property
    def slide(self) -> np.ndarray:
        """(n,) horizontal displacement of the base midpoint relative to the ground [m]."""
        c, s = np.cos(self.q[:, 2]), np.sin(self.q[:, 2])
        xb = self.q[:, 0] + c * self.base_mid[0] - s * self.base_mid[1]
        return xb - xb[0]

    def energy(self, mass: float, J: float, g: float) -> np.ndarray:
        """(n,) kinetic + potential energy in the ground frame [J]."""
        v = self.v
        return 0.5 * mass * (v[:, 0] ** 2 + v[:, 1] ** 2) + 0.5 * J * v[:, 2] ** 2 + \
            mass * g * self.q[:, 1]  # fmt: skip

    def time_in_modes(self) -> dict:
        """Seconds spent in each mode (sample-and-hold over the output grid)."""
        dt = np.diff(self.t)
        out = dict.fromkeys(MODE_NAMES, 0.0)
        for k, name in enumerate(MODE_NAMES):
            out[name] = float(dt[self.mode[:-1] == k].sum())
        return out

    @property
    def n_hops(self) -> int:
        """Number of entries into flight."""
        fl = self.mode == MODE_NAMES.index("flight")
        return int(np.count_nonzero(fl[1:] & ~fl[:-1]))

    def summary(self) -> dict:
        """JSON-serialisable summary."""
        over = self.t_overturn is not None
        return {
            "solver": self.solver,
            "time_in_mode": self.time_in_modes(),
            "max_slide": float(np.max(np.abs(self.slide))) if len(self.t) else 0.0,
            "max_tilt": float(np.max(np.abs(self.q[:, 2]))) if len(self.t) else 0.0,
            "n_hops": self.n_hops,
            "n_impacts": int(self.n_impacts),
            "overturned": bool(over),
            "t_overturn": float(self.t_overturn) if over else None,
            "first_motion": self.first_motion(),
            "n_steps": int(self.n_steps),
        }

    def first_motion(self) -> str:
        """Name of the first mode other than rest (``rest`` if none)."""
        moving = np.flatnonzero(self.mode != 0)
        return MODE_NAMES[int(self.mode[moving[0]])] if len(moving) else "rest"


def finite_or_none(x: float | None) -> float | None:
    """``x`` if finite, else None (JSON)."""
    return None if x is None or not math.isfinite(x) else float(x)
