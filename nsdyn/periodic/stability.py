"""The stability verdict of a periodic orbit, checked so that it never comes from the scheme.

An orbit is stable when every Floquet multiplier (eigenvalue of the monodromy ``Phi``) lies
inside the unit circle. The multipliers the shooting returns are those of the *discrete*
period map, and a discrete map can grow where the flow contracts. The SDIRK tableaux are
L-stable (``|R(z)| <= 1`` for ``Re z <= 0``, ``R(-inf) = 0``), but that is a statement about
``x' = lambda x`` with one fixed ``lambda``. Along a friction orbit the Jacobian changes
from stage to stage: at ``v ~ 0`` the arctan law's slope ``mu N (2/pi) eps`` is stiff, a
stage later it is not. For the scalar ``x' = lambda(t) x`` one step multiplies by
``K(z_1, .., z_s)`` (``z_i = h lambda(t_n + c_i h)``), and for a stiffly accurate SDIRK

    K(z_1 -> -inf, z_2 = .. = z_s = 0) = 1 - b_1 / gamma    (Alexander's SDIRK3: -1.773;
                                                             SDIRK2: 1 - (1 - g)/g = -1.414)

so one step can amplify by up to 1.8 although every ``Re z_i <= 0``: the methods are not
AN-stable (nor algebraically stable: SDIRK3's weight ``b_2 = -0.644`` is negative, SDIRK2's
``M_11 = (1 - g)(3 g - 1) < 0``). Refining the steps does not help until ``h`` resolves
the friction slope (``h << 1 / (mu g (2/pi) eps)`` = 7e-4 s at the seed's mu = 0.03 and
eps = 7500: steps of ~1e-4 s).

Backward Euler is algebraically stable (``b = 1``, ``M = 1``): its map of a flow that is
contractive in some inner-product norm is contractive in that norm (Burrage & Butcher 1979;
Hairer & Wanner IV.12), so its multipliers never leave the unit circle on a dissipative
system. Hence the rule (:func:`check_verdict`): an orbit the map calls unstable
(``max |rho| >= 1 + STABLE_MARGIN``) by a tableau that is not AN-stable is shot again with
backward Euler and ``REFINE_FACTOR`` times the steps: the monodromy of that map over one
period from the orbit's start (a contractive map has ``|Phi| <= 1`` at every point, on its
own orbit or not; on a genuine instability the two orbits differ by O(h));

- the check unstable as well: *unstable, confirmed* (the first multipliers are kept);
- the check stable: the growth was the scheme's, the check's multipliers are reported;
- the check's period cannot be integrated: the verdict is *unknown* (not "unstable").

The check's own damping of a mode of circular frequency ``w`` is ``exp(-w^2 h T / 2)`` per
period, ``~ 20 / N`` for ``w = 2 pi f`` (N steps per period, 0.6 % at 4 x 800 steps): an
instability weaker than that is not confirmed. An exact period map (the switch model's)
needs no check (``exact_map`` attribute of the model).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from nsdyn.periodic.bifurcation import STABLE_MARGIN
from nsdyn.periodic.discretisation import REFINE_FACTOR, Discretisation, refined
from nsdyn.periodic.protocol import STATUS_MESSAGES, STATUS_OK
from nsdyn.periodic.shooting import floquet_multipliers

AN_STABLE = ("euler",)  # tableaux whose map keeps a contractive flow contractive
CHECK_METHOD = "euler"  # the tableau of the check


def max_modulus(rho: np.ndarray) -> float:
    """Largest ``|rho|`` (NaN for none)."""
    return float(np.max(np.abs(rho))) if rho.size else float("nan")


def check_verdict(
    problem, f: float, x0: np.ndarray, rho: np.ndarray, disc: Discretisation | None
) -> tuple[np.ndarray, bool | None, str]:
    """The multipliers to report, the verdict (True stable, False unstable, None unknown)
    and a note, for an orbit from ``x0`` at ``f`` whose map (``disc``) gave ``rho``."""
    if not rho.size:
        return rho, None, ""
    r0 = max_modulus(rho)
    if r0 < 1.0 + STABLE_MARGIN:
        return rho, True, ""
    disc = disc or Discretisation()
    if getattr(problem, "exact_map", False) or disc.method in AN_STABLE:
        return rho, False, ""
    check = refined(replace(disc, method=CHECK_METHOD), REFINE_FACTOR)
    pm = problem.period_map(x0, f, disc=check, sens=True)
    what = f"the {disc.method} map's max |rho| = {r0:.4g}"
    if pm.status != STATUS_OK:
        why = STATUS_MESSAGES.get(pm.status, str(pm.status))
        return rho, None, f"stability unknown: {what}, the backward-Euler check failed ({why})"
    rc = floquet_multipliers(pm.monodromy)
    r1 = max_modulus(rc)
    how = f"backward Euler, {pm.n_steps} steps per period"
    if r1 >= 1.0 + STABLE_MARGIN:
        return rho, False, f"unstable, confirmed by {how} (max |rho| = {r1:.4g})"
    note = (
        f"stable: {what} is the scheme's (not AN-stable); multipliers of {how} "
        f"(max |rho| = {r1:.4g})"
    )
    return rc, True, note
