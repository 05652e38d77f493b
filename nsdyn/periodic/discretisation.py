"""How one forcing period is discretised: the SDIRK tableau and the number of fixed steps.

A period ``T`` is integrated with ``N = clip(ceil(T / dt_max), n_min, n_max)`` equal steps
``h = T / N`` of a stiffly accurate, L-stable singly diagonally implicit Runge-Kutta method

    Y_i = x_n + h sum_j a_ij F(t_n + c_i h, Y_j),   a_ij = 0 for j > i,   a_ii = gamma,
    x_{n+1} = Y_s                                   (stiffly accurate: b = last row of A)

whose stage equations are solved by Newton's method to ``rtol`` / ``atol``. The tableaux are
backward Euler (order 1) and Alexander's (1977) SDIRK2 and SDIRK3 (Hairer & Wanner IV.6).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from nsdyn._checks import expect, number, whole

STAGE_RTOL = 1e-9  # stage Newton tolerance (relative)
STAGE_ATOL = 1e-13  # stage Newton tolerance (absolute, m and m/s)
REFINE_FACTOR = 4  # more steps per period when a period cannot be integrated


def _sdirk2():
    """Alexander (1977), 2 stages, order 2, gamma = 1 - 1/sqrt(2)."""
    g = 1.0 - math.sqrt(0.5)
    return np.array([[g, 0.0], [1.0 - g, g]]), np.array([g, 1.0])


def _sdirk3():
    """Alexander (1977), 3 stages, order 3, gamma = 0.4358665215 (Hairer-Wanner IV.6)."""
    g = 0.43586652150845899942
    b1 = -(6 * g * g - 16 * g + 1) / 4
    b2 = (6 * g * g - 20 * g + 5) / 4
    A = np.array([[g, 0, 0], [(1 - g) / 2, g, 0], [b1, b2, g]])
    return A, np.array([g, (1 + g) / 2, 1.0])


TABLEAUX = {
    "euler": lambda: (np.array([[1.0]]), np.array([1.0])),  # backward Euler, order 1
    "sdirk2": _sdirk2,
    "sdirk3": _sdirk3,
}
ORDER = {"euler": 1, "sdirk2": 2, "sdirk3": 3}


# fewest steps per period: below it a step spans more than 18 degrees of the period and the
# period map errs by the order of (2 pi / N)^p, 10 % for SDIRK2 at N = 20 (3 steps gave a
# linear oscillator's resonance 66 % high, 1 step a zero orbit, each "converged")
N_MIN_FLOOR = 20
# most steps of one period given as n_steps: a step of the office's cb model (26 states) with
# its sensitivities takes ~40 us, so 10^6 steps are ~40 s per period map and minutes per
# shooting (10^9 ran for hours, as a hang)
N_STEPS_MAX = 1_000_000


@dataclass(frozen=True)
class Discretisation:
    """Fixed-step integration of one period: ``N = clip(ceil(T / dt_max), n_min, n_max)``."""

    method: str = "sdirk2"
    n_min: int = 200  # steps per period at least (high frequencies)
    dt_max: float = 0.02  # s, longest step (low frequencies: resolves the 0.5-5 Hz modes)
    n_max: int = 20000
    rtol: float = STAGE_RTOL
    atol: float = STAGE_ATOL

    def __post_init__(self) -> None:  # refused where it is made, not inside a shooting
        if self.method not in TABLEAUX:
            raise ValueError(f"method: expected one of {sorted(TABLEAUX)}, got {self.method!r}")
        for name in ("n_min", "n_max"):  # (stored as ints, the tolerances as floats: an int
            # atol of 0 was a typing error inside the compiled period map)
            v = whole(name, getattr(self, name), 1, "a whole number of steps >= 1")
            object.__setattr__(self, name, int(v))
        if self.n_min < N_MIN_FLOOR:
            raise ValueError(f"n_min: {self.n_min} steps per period do not resolve it (an "
                             f"error of order (2 pi / N)^p); expected at least "
                             f"{N_MIN_FLOOR}")  # fmt: skip
        dt_max = number("dt_max", self.dt_max, "a positive finite step [s]", lambda v: v > 0)
        object.__setattr__(self, "dt_max", dt_max)
        if self.n_min > self.n_max:
            raise ValueError(f"n_max: expected at least n_min = {self.n_min} steps, got "
                             f"{self.n_max}")  # fmt: skip
        # a stage tolerance of NaN, < 0 or >= 1 gave a wrong orbit reported as converged (one
        # too tight to meet is a stage failure the solvers report)
        rtol = number("rtol", self.rtol, "a finite relative tolerance 0 <= rtol < 1",
                      lambda v: 0 <= v < 1)  # fmt: skip
        atol = number("atol", self.atol, "a finite tolerance >= 0 [m, m/s]", lambda v: v >= 0)
        object.__setattr__(self, "rtol", rtol)
        object.__setattr__(self, "atol", atol)

    def steps(self, T: float) -> int:
        """Number of steps ``N`` for the period ``T`` [s]."""
        return int(min(self.n_max, max(self.n_min, math.ceil(T / self.dt_max - 1e-9))))

    def tableau(self) -> tuple[np.ndarray, np.ndarray]:
        """The Butcher matrix ``A`` (s, s) and nodes ``c`` (s,) of ``method``."""
        if self.method not in TABLEAUX:
            raise ValueError(f"method: expected one of {sorted(TABLEAUX)}, got {self.method!r}")
        return TABLEAUX[self.method]()


def checked_disc(disc) -> Discretisation:
    """``disc``, or the default :class:`Discretisation` for None; TypeError naming the
    argument for another kind (``"sdirk2"`` failed deep inside: ``'str' object has no
    attribute 'steps'``)."""
    if disc is None:
        return Discretisation()
    if not isinstance(disc, Discretisation):
        raise TypeError(f"disc: expected a Discretisation, got {type(disc).__name__}")
    return disc


MORE_STEPS = " (try more steps per period)"  # a period map's failure that more steps may cure


def after_refinement(problem, message: str) -> str:
    """``message`` of a shooting that failed again with ``REFINE_FACTOR`` x the steps, its
    advice to try more steps replaced by what is left: for the arctan law, a smaller eps or
    the switch law (a law too sharp for any step); else nothing more to try."""
    iso = getattr(getattr(problem, "system", None), "isolation", None)
    sharp = "; a sharp law needs a smaller eps, or the switch law"
    left = ": more steps did not help" + (sharp if getattr(iso, "law", None) == "arctan" else "")
    return message.replace(MORE_STEPS, left)


def refined(disc: Discretisation, factor: float = REFINE_FACTOR) -> Discretisation:
    """The same discretisation with ``factor`` times the steps per period (``factor`` < 1:
    fewer; at least one step)."""
    expect("disc", disc, isinstance(disc, Discretisation), "a Discretisation")
    factor = number("factor", factor, "a positive finite number", lambda v: v > 0)
    if round(disc.n_min * factor) < N_MIN_FLOOR:
        raise ValueError(f"factor: {factor:g} x {disc.n_min} steps per period is below the "
                         f"{N_MIN_FLOOR} that resolve one; expected a larger factor")  # fmt: skip
    return replace(
        disc,
        n_min=max(1, int(round(disc.n_min * factor))),
        dt_max=disc.dt_max / factor,
        n_max=max(1, int(round(disc.n_max * factor))),
    )
