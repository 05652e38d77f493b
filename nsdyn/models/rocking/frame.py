"""The Makris–Vassiliou rocking frame: two equal free-standing columns and a rigid cap beam.

Columns (mass m, 2B wide, 2H high, semi-diagonal R, slenderness alpha, I_O = 4 m R² / 3) rock
about base corners on side s = sgn(theta); the beam (mass m_b = 2 gamma m) rests on the diagonally
opposite top corners and translates with them, at distance 2R from the base pivots.

Lagrangian (one dof theta), with ``c = cos(s alpha - theta)``::

    T = 2 (1/2) I_O theta'² + (1/2) m_b (2R theta')² = (4/3) m R² (1 + 3 gamma) theta'²
    V = 2 m g R c + m_b g (2R) c = 2 m g R (1 + 2 gamma) c     (columns at R, beam at 2R)
    Q = -2 m R (1 + 2 gamma) (ü_h / g) g cos(s alpha - theta)  (ground inertia on each body)

so the frame obeys the block equation with ``p_f² = p² (1 + 2 gamma) / (1 + 3 gamma)``,
``p² = 3 g / (4 R)``, the same alpha and the same lift-off threshold g tan(alpha).

Impact (angular momentum about the new pivots of each body, beam velocity 2R theta' at
angle alpha: its horizontal part is kept, its vertical part reversed)::

    (8/3) m R² (1 + 3 gamma) theta'+ = [2 I_O (1 - 1.5 sin² alpha) + m_b 4 R² cos 2 alpha] theta'-
    r_f = (1 - 1.5 sin² alpha + 3 gamma cos 2 alpha) / (1 + 3 gamma)

(Makris & Vassiliou 2013, as seed 003 gives it in its text; its Table 3 lists the values).
gamma -> 0 gives the free column.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nsdyn._checks import flag, number
from nsdyn.ground import G_EARTH
from nsdyn.models.rocking.block import (
    RockingBlock,
    block_sizes,
    former_positional,
    housner_restitution,
)


def frame_frequency_ratio(gamma: float) -> float:
    """p_frame / p_column = sqrt((1 + 2 gamma) / (1 + 3 gamma))."""
    return math.sqrt((1.0 + 2.0 * gamma) / (1.0 + 3.0 * gamma))


def frame_restitution(alpha: float, gamma: float) -> float:
    """r_f = (1 - 1.5 sin² alpha + 3 gamma cos 2 alpha) / (1 + 3 gamma)."""
    return (housner_restitution(alpha) + 3.0 * gamma * math.cos(2.0 * alpha)) / (1.0 + 3.0 * gamma)


@dataclass(frozen=True, init=False)
class RockingFrame:
    """Two columns of full ``width`` 2B and ``height`` 2H [m] (or half sizes ``B``, ``H`` by
    name) and a cap beam of mass ratio ``gamma = m_beam / (2 m_column)``; ``r`` overrides the
    derived restitution."""

    width: float
    height: float
    gamma: float
    r: float | None = None
    linear: bool = False
    g: float = G_EARTH
    column_mass: float = 1.0

    def __init__(
        self,
        *args,
        width: float | None = None,
        height: float | None = None,
        gamma: float | None = None,
        r: float | None = None,
        linear: bool = False,
        g: float = G_EARTH,
        column_mass: float = 1.0,
        B: float | None = None,
        H: float | None = None,
    ) -> None:
        # the former positional (B, H, gamma, r, linear, g, column_mass)
        gamma, r, linear, g, column_mass = former_positional(
            args, (gamma, r, linear, g, column_mass)
        )
        w, h = block_sizes("RockingFrame", args[:2], width, height, B, H)
        if gamma is None:
            raise ValueError("RockingFrame: gamma: missing (m_beam / (2 m_column), >= 0)")
        gamma = number("gamma", gamma, "a non-negative number (m_beam / (2 m_column))",
                       lambda x: x >= 0)  # fmt: skip
        vals = {"width": w, "height": h, "gamma": gamma, "r": r, "linear": flag("linear", linear),
                "g": g, "column_mass": column_mass}  # fmt: skip
        for name, v in vals.items():
            object.__setattr__(self, name, v)
        self.column  # checks r, g and the mass  # noqa: B018
        if not (math.isfinite(self.gamma) and self.gamma >= 0):
            raise ValueError(f"gamma: expected a non-negative number, got {self.gamma!r}")
        if self.r is not None:  # ("0.5" or True: a TypeError, or taken as 1)
            number("r", self.r, "0 <= r <= 1", lambda v: 0.0 <= v <= 1.0)

    @property
    def B(self) -> float:
        """Half-width of a column [m]."""
        return 0.5 * self.width

    @property
    def H(self) -> float:
        """Half-height of a column [m]."""
        return 0.5 * self.height

    @property
    def column(self) -> RockingBlock:
        """One column alone (gamma = 0)."""
        return RockingBlock(width=self.width, height=self.height, linear=self.linear, g=self.g,
                            mass=self.column_mass)  # fmt: skip

    @property
    def alpha(self) -> float:
        return self.column.alpha

    @property
    def R(self) -> float:
        return self.column.R

    @property
    def p(self) -> float:
        """Frame frequency parameter p sqrt((1 + 2 gamma) / (1 + 3 gamma)) [1/s]."""
        return self.column.p * frame_frequency_ratio(self.gamma)

    @property
    def restitution(self) -> float:
        return frame_restitution(self.alpha, self.gamma) if self.r is None else float(self.r)

    @property
    def uplift_accel(self) -> float:
        return self.column.uplift_accel


def cg_displacement(theta, alpha: float, R: float, factor: float = 1.0):
    """Horizontal and vertical displacement of a point at ``factor R`` from the pivot along the
    diagonal (factor 1: a column's centre of gravity; 2: the cap beam) [m]."""
    th = np.asarray(theta, dtype=float)
    a = np.abs(th)
    u = np.sign(th) * factor * R * (math.sin(alpha) - np.sin(alpha - a))
    v = factor * R * (np.cos(alpha - a) - math.cos(alpha))
    return u, v
