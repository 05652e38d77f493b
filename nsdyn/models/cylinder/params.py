"""Parameters of the rigid cylinder on a Winkler foundation, checked on construction.

Solid homogeneous cylinder of radius r, height 2H, mass m: centroidal inertia about a diameter
I_t = m(3r² + 4H²)/12 and about the axis I_a = m r²/2 (either may be given instead). The
foundation carries springs k [N/m³] and dashpots c [N s/m³] per unit base area; ``foundation``
is ``"tensionless"`` (springs push only: uplift), ``"bonded"`` (they pull too) or ``"fixed"``
(rigid ground, the body moves with it). ``mu`` (Coulomb friction coefficient) lets the base
centre slide horizontally on a Winkler foundation; ``None`` keeps it restrained (the source
study's assumption).
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass, replace

import numpy as np

from nsdyn._checks import number

FOUNDATIONS = ("tensionless", "bonded", "fixed")  # foundation cases of the model
G_STD = 9.81  # gravity used by the source study [m/s²]


@dataclass(frozen=True)
class CylinderParams:
    """Cylinder (r, H, m, inertia) and foundation (k, c, case). Lengths m, masses kg."""

    r: float = 1.0
    H: float = 4.0
    m: float = 1.0
    k: float = 9814.0
    c: float = 103.6
    foundation: str = "tensionless"
    g: float = G_STD
    I_t: float | None = None  # centroidal inertia about a diameter (default: solid cylinder)
    I_a: float | None = None  # inertia about the axis (default: solid cylinder)
    mu: float | None = None  # base friction coefficient; None: base restrained horizontally

    def __post_init__(self) -> None:
        pos, non_neg = "a positive finite number", "a non-negative finite number"
        for name in ("r", "H", "m", "k", "g"):
            number(name, getattr(self, name), pos, lambda v: v > 0)
        number("c", self.c, non_neg, lambda v: v >= 0)
        for name in ("I_t", "I_a"):
            if getattr(self, name) is not None:
                number(name, getattr(self, name), pos, lambda v: v > 0)
        try:  # (H = 1e300: an OverflowError in a run)
            derived = (self.It, self.Ia, self.m * self.g * self.H, self.k * self.I_base)
        except OverflowError:
            derived = (math.inf,)
        if not all(math.isfinite(v) for v in derived):
            got = ", ".join(f"{k} = {getattr(self, k):g}" for k in ("r", "H", "m", "k"))
            raise ValueError(
                f"r, H, m, k: expected sizes whose inertias and moments are finite "
                f"(I_t = m (3 r^2 + 4 H^2) / 12, m g H, k pi r^4 / 4), got {got}"
            )
        if self.mu is not None:
            number("mu", self.mu, non_neg, lambda v: v >= 0)
            if self.foundation == "fixed":
                raise ValueError(
                    "mu: a fixed base cannot slide; give a stiff Winkler foundation instead"
                )
        if self.foundation not in FOUNDATIONS:
            close = difflib.get_close_matches(str(self.foundation), FOUNDATIONS, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ValueError(
                f"foundation: expected one of {list(FOUNDATIONS)}, got {self.foundation!r}{hint}"
            )

    @property
    def height(self) -> float:
        """Full height 2H [m] (the scenes' ``height``; ``H`` is the half height)."""
        return 2.0 * self.H

    @property
    def It(self) -> float:
        """Centroidal moment of inertia about a diameter [kg m²]."""
        if self.I_t is not None:
            return float(self.I_t)
        return self.m * (3.0 * self.r**2 + 4.0 * self.H**2) / 12.0

    @property
    def Ia(self) -> float:
        """Moment of inertia about the axis [kg m²]."""
        return float(self.I_a) if self.I_a is not None else 0.5 * self.m * self.r**2

    @property
    def area(self) -> float:
        """Base area πr²."""
        return math.pi * self.r**2

    @property
    def I_base(self) -> float:
        """Second moment of the base disc about a diameter, πr⁴/4."""
        return 0.25 * math.pi * self.r**4

    def with_(self, **changes) -> CylinderParams:
        """A copy with some fields changed (checked again)."""
        return replace(self, **changes)

    @property
    def sliding(self) -> bool:
        """True when the base may slide (a friction coefficient is given)."""
        return self.mu is not None

    def kernel_array(self) -> np.ndarray:
        """(m, H, r, I_t, I_a, k, c, g, bonded, μ) for the kernel; μ = −1: restrained base."""
        bonded = 1.0 if self.foundation == "bonded" else 0.0
        mu = -1.0 if self.mu is None else float(self.mu)
        return np.array(
            [self.m, self.H, self.r, self.It, self.Ia, self.k, self.c, self.g, bonded, mu], float
        )
