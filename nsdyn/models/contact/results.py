"""Histories of a contact simulation and their summary (time in each mode, slide, tilt, hops).

Body modes: rest, slide, rock, slide-rock, flight (hop), overturned.  Slide is the slip at the
contacts: while base corner i stays on the ground its ground-frame position
x_c,i = x + (R(theta) r_i)_x changes only by slipping (d x_c,i / dt = v_T,i), so between two
samples where a corner touches at both ends the slip is Delta x_c,i (mean over the touching
corners; none in flight), and

    slide(t_k) = sum_{j < k} mean_{i touching at j, j+1} (x_c,i(t_j+1) - x_c,i(t_j)).

Rocking about a corner that sticks adds nothing (the base midpoint's swing is not a slide). Tilt
is |theta|, a hop an entry into flight, overturning the tilt reaching its side's overturning
tilt (RigidBody.overturn_tilts: the body lies on a side). The first motion is the mode entered
at the first change of the contact state (an event of the event-driven solver, at its located
time; a step of Moreau-Jean), not the first sample whose displacement passes a threshold.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from nsdyn._tabular import Tabular

MODE_NAMES = ("rest", "slide", "rock", "slide_rock", "flight", "overturned")
TILT_FLOOR = 0.01  # a peak tilt below this fraction of alpha is no rocking (figures, summaries)


def slenderness(body, theta: float | None = None) -> float:
    """The smaller slenderness alpha [rad] of the body's two outer base corners (the angle from
    the vertical of the line from the corner to the centre of mass): the scale of its tilt;
    with a tilt ``theta``, the alpha of the corner it rocks about (theta > 0: the left one)."""
    if theta is not None:
        return body.corner_geometry(-1 if theta >= 0 else 1)[1]
    return min(body.corner_geometry(-1)[1], body.corner_geometry(1)[1])


@dataclass(repr=False, eq=False)
class ContactResult(Tabular):
    """Sampled history of a body on the ground (ground frame).

    Attributes
    ----------
    t : (n,);  q : (n, 3) (x, y, theta);  v : (n, 3);  mode : (n,) index into MODE_NAMES
    events : list of (t, name, contact) (event-driven) ;  n_impacts ;  t_overturn (or None)
    base_mid : (2,) base midpoint relative to the centre of mass (body frame)
    contacts : (nc, 2) base corners (body frame) and ``on_tol`` [m]: a corner touches the
        ground when its gap is at most on_tol (None: ``slide`` is the base midpoint's shift)
    first_change : (t, mode index) of the first contact state other than rest, when the solver
        knows it (event-driven: after the mode rebuild at an event)
    step_check : Moreau-Jean's check of its step at h/2 when asked for (``step_resolved``,
        ``h_half``, ``step_note``; in the summary), else None
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    mode: np.ndarray
    solver: str
    base_mid: np.ndarray
    theta_ov: float  # the smaller of the body's two overturning tilts [rad]
    n_impacts: int = 0
    t_overturn: float | None = None
    events: list = field(default_factory=list)
    n_steps: int = 0
    n_rhs: int = 0
    contacts: np.ndarray | None = None
    on_tol: float = 0.0
    first_change: tuple | None = None
    step_check: dict | None = None

    @property
    def slide(self) -> np.ndarray:
        """(n,) slip at the contacts relative to the ground [m] (module text)."""
        c, s = np.cos(self.q[:, 2]), np.sin(self.q[:, 2])
        if self.contacts is None or len(self.t) < 2:
            xb = self.q[:, 0] + c * self.base_mid[0] - s * self.base_mid[1]
            return xb - xb[0]
        r = self.contacts
        xc = self.q[:, :1] + c[:, None] * r[None, :, 0] - s[:, None] * r[None, :, 1]
        gap = self.q[:, 1:2] + s[:, None] * r[None, :, 0] + c[:, None] * r[None, :, 1]
        on = gap <= self.on_tol
        both = on[:-1] & on[1:]
        n_on = both.sum(axis=1)
        inc = np.where(n_on > 0, (np.diff(xc, axis=0) * both).sum(axis=1) / np.maximum(n_on, 1),
                       0.0)  # fmt: skip
        return np.concatenate([[0.0], np.cumsum(inc)])

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
    def hop_times(self) -> np.ndarray:
        """The output times at which the body entered flight."""
        fl = self.mode == MODE_NAMES.index("flight")
        return self.t[1:][fl[1:] & ~fl[:-1]]

    @property
    def n_hops(self) -> int:
        """Number of entries into flight."""
        return int(self.hop_times.size)

    def summary(self) -> dict:
        """JSON-serialisable summary, the unit in each name (``_m``, ``_rad``, ``_s``)."""
        over = self.t_overturn is not None
        return {
            "solver": self.solver,
            "time_in_mode_s": self.time_in_modes(),
            "max_slide_m": float(np.max(np.abs(self.slide))) if len(self.t) else 0.0,
            "max_tilt_rad": float(np.max(np.abs(self.q[:, 2]))) if len(self.t) else 0.0,
            "final_tilt_rad": float(self.q[-1, 2]) if len(self.t) else 0.0,
            "final_omega_rad_per_s": float(self.v[-1, 2]) if len(self.t) else 0.0,
            "n_hops": self.n_hops,
            "n_impacts": int(self.n_impacts),
            "overturned": bool(over),
            "t_overturn_s": float(self.t_overturn) if over else None,
            "first_motion": self.first_motion(),
            "t_first_motion_s": finite_or_none(self.t_first_motion()),
            "n_steps": int(self.n_steps),
            **(self.step_check or {}),
        }

    def histories(self) -> dict:
        """Position and velocity of the centre of mass in the ground frame, the tilt, the mode
        (index into MODE_NAMES) and the slide, units in the names."""
        q, v = self.q, self.v
        return {"x_m": q[:, 0], "y_m": q[:, 1], "theta_rad": q[:, 2],
                "vx_m_per_s": v[:, 0], "vy_m_per_s": v[:, 1], "omega_rad_per_s": v[:, 2],
                "mode": self.mode, "slide_m": self.slide}  # fmt: skip

    def _first(self) -> tuple[float, int]:
        if self.first_change is not None:
            return float(self.first_change[0]), int(self.first_change[1])
        moving = np.flatnonzero(self.mode != 0)
        return (float(self.t[moving[0]]), int(self.mode[moving[0]])) if len(moving) else (
            math.nan, 0)  # fmt: skip

    def first_motion(self) -> str:
        """Name of the first mode other than rest (``rest`` if none): from the first change of
        the contact state when the solver reports it, else from the sampled modes."""
        return MODE_NAMES[self._first()[1]]

    def t_first_motion(self) -> float:
        """Time [s] of that first change (NaN if the body never leaves rest)."""
        return self._first()[0]


def state_mode(closed: np.ndarray, slipping: np.ndarray) -> int:
    """Body mode of a contact state without thresholds: no corner closed -> flight, one ->
    rock (slide_rock if it slips), two or more -> rest (slide if any slips)."""
    n = int(np.count_nonzero(closed))
    slip = bool(np.any(closed & slipping))
    if n == 0:
        return MODE_NAMES.index("flight")
    if n == 1:
        return MODE_NAMES.index("slide_rock" if slip else "rock")
    return MODE_NAMES.index("slide" if slip else "rest")


def finite_or_none(x: float | None) -> float | None:
    """``x`` if finite, else None (JSON)."""
    return None if x is None or not math.isfinite(x) else float(x)
