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
from nsdyn.periodic.shooting import _weights, floquet_multipliers, orbit_amplitudes

AN_STABLE = ("euler",)  # tableaux whose map keeps a contractive flow contractive
CHECK_METHOD = "euler"  # the tableau of the check
GROWTH_PERIODS = 10  # periods a perturbation is followed to check an "unstable" verdict
GROWTH_REL = 1e-3  # its size, relative to the orbit's excursion


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


def check_growth(problem, pt) -> None:
    """Check an "unstable" verdict of the point ``pt`` (an OrbitPoint) by the map itself: from
    the orbit's start displaced by GROWTH_REL of its excursion along the growing eigenvector of
    the monodromy, GROWTH_PERIODS periods are integrated, and the mean change per period of
    the scaled distance to the start, r, replaces the multipliers (``[r]``) with a note. A
    period that cannot be integrated leaves the verdict unknown (no multipliers, the reason in
    the note)."""
    if not pt.multipliers.size or pt.max_multiplier < 1.0 + STABLE_MARGIN:
        return
    first = f"the differenced monodromy's max |rho| = {pt.max_multiplier:.4g}"

    def unknown(status):
        why = STATUS_MESSAGES.get(status, f"status {status}")
        pt.multipliers = np.zeros(0, dtype=complex)
        pt.note = "; ".join(n for n in (pt.note, f"stability unknown: {first}, its check "
                                        f"failed ({why})") if n)  # fmt: skip

    pm = problem.period_map(pt.x0, pt.f, store=True)
    if pm.status != STATUS_OK:
        return unknown(pm.status)
    rho, vec = np.linalg.eig(pm.monodromy)
    k = int(np.argmax(np.abs(rho)))
    amp = orbit_amplitudes(problem, pm.X)
    W = _weights(problem, amp)
    v = vec[:, k].real if np.any(vec[:, k].real) else vec[:, k].imag
    dx = GROWTH_REL * v / np.abs(W * v).max()
    x = pt.x0 + dx
    d0 = float(np.abs(W * dx).max())
    for _ in range(GROWTH_PERIODS):
        pk = problem.period_map(x, pt.f, n_steps=pm.n_steps, sens=False)
        if pk.status != STATUS_OK:
            return unknown(pk.status)
        x = pk.xT
    r = (float(np.abs(W * (x - pt.x0)).max()) / d0) ** (1.0 / GROWTH_PERIODS)
    verdict = "unstable, confirmed" if r >= 1.0 + STABLE_MARGIN else "stable"
    note = (f"{verdict}: {first}; a perturbation followed {GROWTH_PERIODS} periods changes by "
            f"{r:.4g} per period (reported as |rho|)")  # fmt: skip
    pt.multipliers = np.array([complex(r)])
    pt.note = "; ".join(n for n in (pt.note, note) if n)
