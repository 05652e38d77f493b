"""Friction laws of the base contacts: Coulomb with static and dynamic coefficients.

    mu(v) = mu_d + (mu_s - mu_d) exp(-C |v|)          (C >= 0; C = 0 gives mu = mu_s)

and the classical jump law (C = infinity): mu_s while sticking, mu_d as soon as |v| > 0.
A sticking contact holds while |lam_T| <= mu_s lam_N; a slipping one carries
lam_T = -mu(|v_T|) sign(v_T) lam_N.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nsdyn._checks import number


@dataclass(frozen=True)
class FrictionLaw:
    """Static/dynamic Coulomb friction ``mu_s >= mu_d >= 0`` with decay constant ``C`` [s/m]."""

    mu_s: float
    mu_d: float | None = None
    C: float = math.inf

    def __post_init__(self):
        mu_d = self.mu_s if self.mu_d is None else self.mu_d
        object.__setattr__(self, "mu_d", mu_d)
        for name, val in (("mu_s", self.mu_s), ("mu_d", mu_d)):
            number(name, val, "a non-negative friction coefficient", lambda x: x >= 0)
        if mu_d > self.mu_s:
            raise ValueError(f"mu_d: the dynamic coefficient must not exceed the static one "
                             f"(mu_s = {self.mu_s}), got mu_d = {mu_d}")  # fmt: skip
        if isinstance(self.C, str | bool) or not (self.C >= 0):  # ('x': a TypeError)
            raise ValueError(f"C: expected a non-negative decay constant [s/m], got {self.C!r}")

    @property
    def cdec(self) -> float:
        """Kernel form of C (-1 for the jump law)."""
        return -1.0 if math.isinf(self.C) else float(self.C)

    def mu(self, v) -> np.ndarray:
        """mu(v) at slip velocities ``v`` (mu_s at v = 0)."""
        v = np.abs(np.asarray(v, dtype=float))
        if math.isinf(self.C):
            return np.where(v == 0, self.mu_s, self.mu_d)
        return self.mu_d + (self.mu_s - self.mu_d) * np.exp(-self.C * v)
