"""Mode of motion initiated from rest by a horizontal base acceleration (Shenton 1996).

Rectangle of width 2b and height 2h (beta = b/h), friction mu, base acceleration a = abar g
(horizontal, acting to +x; the inertia load -m a pushes the body to -x).  Static equilibrium
holds while the friction demand and the overturning moment are both within bounds:

    rest        abar <= mu  and  abar <= beta.

Sliding without rotation needs friction mu m g at the base whose moment about the centre of mass
the normal reactions can balance only if mu <= beta:  slide  if  abar > mu  and  mu <= beta
(at the tie mu = beta the trailing reaction falls to zero but stays non-negative: the body slides
flat, it does not tilt).
Rocking about the trailing corner O with thetad = 0 (J_O = 4/3 m R^2, R^2 = b^2 + h^2):

    J_O thetadd = m g (abar h - b),
    F = m abar g - m h thetadd,  N = m g + m b thetadd   (reactions at O),

needs abar > beta and |F| <= mu N, i.e. with h = 1

    mu >= mu_rock(abar, beta) = (abar (1 + 4 beta^2) + 3 beta) / (4 + beta^2 + 3 beta abar)

(= beta at abar = beta); otherwise (beta < mu < mu_rock) the corner slips while the body rocks:
slide-rock.  Ishiyama's (1982) simpler criteria are the limits abar > mu (slide) and
abar > beta (rock).
"""

from __future__ import annotations

import math

import numpy as np

MODES = ("rest", "slide", "rock", "slide_rock")


def mu_rock(abar: float, beta: float) -> float:
    """Friction needed for pure rocking to start at base acceleration ``abar`` [g]."""
    return (abar * (1 + 4 * beta**2) + 3 * beta) / (4 + beta**2 + 3 * beta * abar)


def onset_mode(b_over_h: float, mu: float, abar: float) -> str:
    """``rest``, ``slide``, ``rock`` or ``slide_rock`` for a rectangle from rest.

    Parameters
    ----------
    b_over_h : width / height of the rectangle (beta = tan alpha) ;  mu : friction coefficient
    abar : magnitude of the base acceleration in g
    """
    if not (b_over_h > 0 and math.isfinite(b_over_h)):
        raise ValueError(f"b_over_h: expected a positive number, got {b_over_h!r}")
    if not (mu >= 0 and math.isfinite(mu)):  # (0: frictionless, any push slides)
        raise ValueError(f"mu: expected a non-negative friction coefficient, got {mu!r}")
    if not (abar >= 0 and math.isfinite(abar)):
        raise ValueError(f"abar: expected a non-negative base acceleration in g, got {abar!r}")
    beta = b_over_h
    if abar <= mu and abar <= beta:
        return "rest"
    if mu <= beta:
        return "slide"
    return "rock" if mu >= mu_rock(abar, beta) else "slide_rock"


def onset_map(b_over_h: float, mu: np.ndarray, abar: np.ndarray) -> np.ndarray:
    """(len(abar), len(mu)) array of mode indices into MODES."""
    out = np.zeros((len(abar), len(mu)), dtype=int)
    for i, a in enumerate(abar):
        for j, m in enumerate(mu):
            out[i, j] = MODES.index(onset_mode(b_over_h, float(m), float(a)))
    return out
