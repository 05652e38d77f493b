"""Friction of the isolators: the laws, their default parameters, and the one definition of stick.

Friction force of isolator i with normal force λ_i and sliding velocity v_i = D_i q̇ (seed 004):

    arctan law (eq 7):   F_i = μ_i λ_i s_i,  s_i = (2/π) arctan(ε v_i)  (ε in s/m; the
                         seed calls it dimensionless)
    switch model (eqs 4–6, Leine): slip |v_i| > η: s_i = sign(v_i);
                         stick |v_i| ≤ η and |τ_i| ≤ μ_i λ_i: τ_i is a constraint force
                         solved with the normal forces, holding D_i q̈ + κ D_i q̇ = 0 (the
                         seed's D_i q̈ = 0, with κ = 2 α β by default: the band's velocity
                         decays instead of drifting);
                         transition |v_i| ≤ η and |τ_i| > μ_i λ_i: the friction saturated,
                         s_i = sign(τ_i), the direction of the would-be stick force.

**Stick**, for every consumer (run metrics, periodic orbits, sweeps, spot checks):

- switch model / event-driven runs: the isolator is in its stick mode, or inside the band
  |v| ≤ η;
- arctan law, which has no stick phase: the friction force stays below ``STICK_UTILISATION``
  of its limit, |s(v)| ≤ 0.9 ⇔ |v| ≤ tan(0.45 π)/ε — an isolator that Coulomb friction would
  hold creeps at v = tan(πF/(2μλ))/ε, so its force stays below the limit, while a sliding one
  has |s| → 1.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from nsdyn.models.isolated.defaults import EPS, EPS_MAX, ETA, MU  # noqa: F401  (re-exported)

STICK_UTILISATION = 0.9  # arctan law: "stick" while |s(v)| <= this (friction below 90 %)

ETA_COARSE = 1e-3  # m/s: a switch band above this lets a stuck isolator creep visibly
SLIP_V_MAX = 10.0  # m/s, beyond any isolator's slip velocity in an earthquake
LAW_NAMES = ("none", "arctan", "switch")  # laws a user chooses ("modes" is internal)
# the keys one law reads and the others do not: key -> (its law, what it is); the scene
# readers name them when the run's law is another (an isolated frame's, a deck's notes)
LAW_KEYS = {
    "eps": ("arctan", "the arctan law's sharpness"),
    "eta": ("switch", "the switch law's stick band"),
    "kappa": ("switch", "the switch law's stick stabilisation"),
}


def sharpness_in_range(name: str, eps, error: type = ValueError) -> None:
    """``error`` (a ValueError; a scene's SceneError) naming ``name`` when the arctan
    sharpness ``eps`` passes :data:`EPS_MAX`."""
    if isinstance(eps, numbers.Real) and eps > EPS_MAX:
        raise error(f"{name}: expected an arctan sharpness of at most {EPS_MAX:g} s/m (a "
                         f"turn at 1/eps = {1 / EPS_MAX:g} m/s, ten times what gravity adds to a "
                         f"velocity in the solvers' smallest step), got {eps:g}; the sharp limit "
                         "is the switch law (law 'switch', true stick)")  # fmt: skip


def arctan_direction(v, eps: float = EPS):
    """s(v) = (2/π) arctan(ε v): the arctan law's friction direction, |s| < 1."""
    return (2.0 / math.pi) * np.arctan(eps * np.asarray(v, dtype=float))


def stick_velocity(law: str, eps: float = EPS, eta: float = ETA) -> float:
    """Largest |v| [m/s] at which an isolator under ``law`` counts as sticking."""
    if law == "arctan":
        return math.tan(0.5 * math.pi * STICK_UTILISATION) / eps
    if law in ("switch", "modes"):
        return eta
    if law == "none":
        return 0.0
    raise ValueError(f"friction law: expected one of {list(LAW_NAMES)}, got {law!r}")


# a periodic orbit's stick fraction below this is no stick phase: the samples a reversal of the
# slip passes inside the law's stick band (the office frame's slipping orbits at 2 m/s²: one
# at 0.0014, the next smallest 0.015, most 0.02-0.5)
STICK_SLIP_MIN = 0.01


def stick_slip(stick_fraction) -> bool:
    """Whether an orbit of this stick fraction sticks over part of its period: from
    :data:`STICK_SLIP_MIN` to below 1 (None and NaN: no)."""
    return stick_fraction is not None and STICK_SLIP_MIN <= stick_fraction < 1.0


def stick_slip_note(stick_fraction, law: str, eps: float = EPS) -> str | None:
    """A periodic orbit's note when it sticks over part of its period (``STICK_SLIP_MIN`` <=
    ``stick_fraction`` < 1; None otherwise, NaN included): under the arctan law its stick
    phases creep, and a small orbit can differ from true stick's many times over."""
    s = stick_fraction
    if not stick_slip(s):
        return None
    creep = (f": under the arctan law its stick phases creep at up to "
             f"{stick_velocity('arctan', eps):.2g} m/s (eps = {eps:g} s/m), and a small "
             "orbit can differ from true stick's many times over (confirm with --friction "
             "switch)")  # fmt: skip
    return f"stick-slip orbit (stick fraction {s:.3g})" + creep * (law == "arctan")  # fmt: skip


def sticks(v, law: str, eps: float = EPS, eta: float = ETA, modes=None) -> np.ndarray:
    """Boolean array: which isolators stick, from their sliding velocities ``v`` (any shape).

    ``modes`` (same shape, 0 = stick, ±1 = slip), when the law decides them (switch model,
    event-driven runs), count as well: a stick mode is stick whatever the velocity.
    """
    s = np.abs(np.asarray(v, dtype=float)) <= stick_velocity(law, eps, eta)
    if modes is not None and law != "arctan":
        s |= np.asarray(modes) == 0
    return s


def unread_law_keys(law: str, eps: float = EPS, eta: float = ETA, kappa=None) -> list[str]:
    """The keys of :data:`LAW_KEYS` given away from their defaults (``kappa``: given at all)
    that ``law`` does not read: the arctan law has no stick band nor stick stabilisation, the
    switch law no sharpness."""
    given = {"eps": eps != EPS, "eta": eta != ETA, "kappa": kappa is not None}
    return [k for k, (own, _) in LAW_KEYS.items() if given[k] and own != law]


def coarse_law_note(law: str, eps: float = EPS, eta: float = ETA, where: str = "solver") -> str:
    """One line when the law's parameter blurs the friction it models, else "": the switch
    law's stick band ``eta`` above :data:`ETA_COARSE` (a "stuck" isolator creeps at up to
    eta, tens of mm over a record, and the peaks follow it), or an arctan ``eps`` whose
    friction reaches STICK_UTILISATION of mu N only beyond :data:`SLIP_V_MAX` (no friction to
    speak of: a viscous damper 2/pi mu N eps at the slips, and every instant counts as
    stick). ``where``: the table the key is in ("": a Python argument)."""
    where = f"{where}." if where else ""
    if law in ("switch", "modes") and eta > ETA_COARSE:
        return (f"{where}eta = {eta:g} m/s: the switch law holds a stuck isolator only to "
                f"|v| <= eta, so it creeps at up to {eta:g} m/s and the peaks depend on eta "
                f"(default {ETA:g} m/s; expected at most {ETA_COARSE:g})")  # fmt: skip
    v = stick_velocity("arctan", eps) if law == "arctan" else 0.0
    if v > SLIP_V_MAX:
        return (f"{where}eps = {eps:g} s/m: the arctan friction reaches "
                f"{STICK_UTILISATION:.0%} of mu N only at a slip velocity of {v:.2g} m/s: at "
                f"slips well below {1.0 / eps:.2g} m/s it is a viscous damper (2/pi mu N "
                "eps), and the share of time all isolators stick counts every instant below "
                f"{v:.2g} m/s (typical eps: 1e3-1e5 s/m)")  # fmt: skip
    return ""
