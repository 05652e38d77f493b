"""Results of a rocking run: theta(t), theta'(t), impacts, peaks, energy and the outcome.

Energy per unit ``m g R`` (``R`` the semi-diagonal; for a frame the same form with its own
``p``), zero at rest::

    exact:       e = theta'² / (2 p²) + cos(alpha - |theta|) - cos(alpha)
    linearised:  e = theta'² / (2 p²) + alpha |theta| - theta² / 2

It is constant between impacts of free rocking; an impact multiplies the kinetic part by r².
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from nsdyn._tabular import Tabular
from nsdyn.models.tilt import final_tilt

OUTCOMES = ("rest", "rocking", "overturned")  # kernel outcome code -> name


@dataclass(repr=False, eq=False)
class RockingResult(Tabular):
    """One rocking time history.

    Attributes
    ----------
    t, theta, thetad : ndarray, shape (n,)
        Output grid [s], rotation [rad], angular velocity [rad/s] (cut at overturning).
    impacts : ndarray, shape (n_imp, 3)
        Impact time [s], theta' before and after [rad/s].
    peaks : ndarray, shape (n_pk, 2)
        Time [s] and theta [rad] of each extremum of |theta|.
    alpha, p, r : float
        Slenderness [rad], frequency parameter [1/s], restitution used.
    linear : bool
        Linearised equation.
    outcome : str
        "rest", "rocking" or "overturned" at the end.
    t_overturn, t_rest, t_uplift : float
        Overturning time, last time it came to rest after rocking, first lift-off (nan if none).
    max_abs_theta : float
        max |theta| over the run [rad] (from the located peaks, not just the grid).
    """

    t: np.ndarray
    theta: np.ndarray
    thetad: np.ndarray
    impacts: np.ndarray
    peaks: np.ndarray
    alpha: float
    p: float
    r: float
    linear: bool
    outcome: str
    t_overturn: float
    t_rest: float
    t_uplift: float
    max_abs_theta: float
    n_steps: int
    n_rejected: int
    n_rhs: int
    n_uplifts: int
    wall_s: float = 0.0
    meta: dict = field(default_factory=dict)

    @property
    def overturned(self) -> bool:
        return self.outcome == "overturned"

    @property
    def n_impacts(self) -> int:
        return int(self.impacts.shape[0])

    @property
    def max_theta_over_alpha(self) -> float:
        return self.max_abs_theta / self.alpha

    def energy(self, theta: np.ndarray | None = None, thetad: np.ndarray | None = None):
        """Mechanical energy per m g R (module docstring) on the grid or at given states."""
        th = self.theta if theta is None else np.asarray(theta)
        thd = self.thetad if thetad is None else np.asarray(thetad)
        return rocking_energy(th, thd, self.alpha, self.p, self.linear)

    def impact_energy_ratio(self) -> np.ndarray:
        """Kinetic energy after / before each impact, shape (n_imp,) (Housner: r²)."""
        if self.n_impacts == 0:
            return np.zeros(0)
        return (self.impacts[:, 2] / self.impacts[:, 1]) ** 2

    def summary(self) -> dict:
        """JSON-ready numbers of the run, the unit in each name (``_rad``, ``_s``, ``_per_s``);
        times of events that did not happen are None."""

        def f(x):
            return None if x is None or not math.isfinite(x) else float(x)

        return {
            "alpha_rad": self.alpha,
            "p_per_s": self.p,
            "r": self.r,
            "linear": self.linear,
            "outcome": self.outcome,
            "overturned": self.overturned,
            "t_overturn_s": f(self.t_overturn),
            "t_uplift_s": f(self.t_uplift),
            "t_rest_s": f(self.t_rest),
            "n_impacts": self.n_impacts,
            "n_uplifts": self.n_uplifts,
            "max_theta_rad": float(self.max_abs_theta),
            "max_theta_over_alpha": float(self.max_theta_over_alpha),
            **final_tilt(self.theta, self.thetad, self.alpha, self.overturned),
            "n_steps": self.n_steps,
            "n_rejected": self.n_rejected,
            "wall_s": self.wall_s,
        }

    def histories(self) -> dict:
        """Rotation [rad], angular velocity [rad/s] and energy per m g R on the output grid."""
        return {"theta_rad": self.theta, "thetad_rad_per_s": self.thetad,
                "energy_per_mgR": self.energy()}  # fmt: skip


def rocking_energy(theta, thetad, alpha: float, p: float, linear: bool = False):
    """Energy per m g R of a rocking block (module docstring); arrays broadcast."""
    th = np.abs(np.asarray(theta, dtype=float))
    thd = np.asarray(thetad, dtype=float)
    kin = thd**2 / (2.0 * p**2)
    if linear:
        return kin + alpha * th - 0.5 * th**2
    return kin + np.cos(alpha - th) - math.cos(alpha)
