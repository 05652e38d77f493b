"""Moreau-Jean time stepping of a rigid body on the ground (driver of ``_kmoreau``).

theta-method on velocities with impulses at velocity level each step (see ``_kmoreau``):
first order, robust through impact accumulations, sticking and hops; no event location.
"""

from __future__ import annotations

import math

import numpy as np

from nsdyn._checks import NumericalFailure, number, output_count, output_step, step_count
from nsdyn.ground import G_EARTH
from nsdyn.models.contact import _kmoreau as km
from nsdyn.models.contact.body import RigidBody
from nsdyn.models.contact.event import _params, check_parts, start_state, tilt_angle
from nsdyn.models.contact.excite import BaseMotion
from nsdyn.models.contact.friction import FrictionLaw
from nsdyn.models.contact.results import ContactResult

MODE_G_TOL = 1e-5  # output classification: on the ground when g <= MODE_G_TOL * L
MODE_V_TOL = 1e-5  # ... slipping when |v_T| > MODE_V_TOL * sqrt(g L)
STATUS = {-1: "contact LCP has no solution", -2: "non-finite state"}


def check_step(h: float, motion: BaseMotion) -> None:
    """ValueError naming ``h`` when the step does not follow the excitation (longer than
    :meth:`BaseMotion.resolving_step`)."""
    top = motion.resolving_step()
    if h > top * (1 + 1e-9):
        raise ValueError(f"h: a step of {h:g} s does not follow the excitation; expected at "
                         f"most {top:.3g} s (ten of a record's sampling steps, or 1/40 of a "
                         "sine's period)")  # fmt: skip


def step_grid(t_end: float, h: float, dt_out: float | None = None) -> None:
    """A run's steps of ``h`` over ``t_end`` and its outputs every ``dt_out`` (at least a
    step): ValueError naming h or dt_out (too many, or a step longer than the run)."""
    step_count(t_end, h)
    output_step(dt_out, t_end, off=False)  # (one longer than the run: a lone sample at t = 0)
    output_count(t_end, max(dt_out or h, h))
    if h > t_end:  # (h = 0.6 s over 1 s ran to 1.2 s; 2 s: no step, one sample)
        raise ValueError(f"h: a step of {h:g} s is longer than the run (t_end = {t_end:g} s)")


def simulate_moreau(body: RigidBody, friction: FrictionLaw, motion: BaseMotion | None = None, *,
                    t_end: float, h: float = 1e-3, theta: float = 0.5, e_n: float = 0.0,
                    theta0: float | None = None, theta0_over_alpha: float | None = None,
                    q0=None, v0=None, dt_out: float | None = None,
                    g: float = G_EARTH) -> ContactResult:  # fmt: skip
    """Moreau-Jean run with step ``h``, storing every ``dt_out`` (default: every step; rounded
    to a whole number of steps, at least one: the result's ``t`` holds the times kept), from
    rest (tilted by ``theta0`` [rad] or ``theta0_over_alpha``) or from (q0, v0).

    The scheme is first order and passes through impacts without locating them: where the
    body hops (``result.n_hops``) or rocks with restitution, its default step can be
    qualitatively wrong (docs/guide/contact.md, the stability map). Repeat the run at ``h/2``
    and compare the peaks, as a scene's step check does (``solver.step_check``), or use
    :func:`nsdyn.models.contact.event.simulate_event`; this call itself says nothing."""
    check_parts(body, friction, motion)
    body = body.unit_mass()  # (the same motion; forces of order g in the LCPs)
    h = number("h", h, "a positive step size [s]", lambda v: v > 0)
    theta = number("theta", theta, "0.5 <= theta <= 1", lambda v: 0.5 <= v <= 1.0)
    e_n = number("e_n", e_n, "a restitution coefficient in [0, 1]", lambda v: 0.0 <= v <= 1.0)
    mo = motion or BaseMotion.none()
    t_end = number("t_end", t_end, "a positive duration [s]", lambda v: v > 0)
    number("g", g, "a positive gravity [m/s²]", lambda v: v > 0)
    step_grid(t_end, h, dt_out)
    check_step(h, mo)
    par = _params(body, friction, g)
    tilted = theta0 is not None or theta0_over_alpha is not None
    q, v = start_state(body, tilt_angle(body, theta0, theta0_over_alpha), q0, v0, tilted)
    n = int(round(t_end / h))
    stride = max(1, int(round((dt_out or h) / h)))
    L = par[6]
    t, qs, vs, md, k, status, t_stop, first = km.moreau(
        q, v, 0.0, h, n, theta, e_n, body.contacts, body.minv, par, mo.ex, mo.tab_h, mo.tab_v,
        _sorted_jumps(mo.jumps), stride,
        MODE_G_TOL * L, MODE_V_TOL * math.sqrt(g * L))  # fmt: skip
    if status < 0:
        raise NumericalFailure(f"Moreau-Jean: {STATUS[status]} at t = {t_stop:.9g} s")
    first_change = (float(first[0]), int(first[1])) if first[0] >= 0.0 else None
    res = ContactResult(t, qs, vs, md, "moreau", body.contacts.mean(axis=0), body.theta_ov,
                        0, t_stop if status == 1 else None, [], k, k, body.contacts,
                        MODE_G_TOL * L, first_change)  # fmt: skip
    res.n_impacts = _count_impacts(res, body, L)
    return res


def _sorted_jumps(jumps) -> np.ndarray:
    """(nj, 2) ground velocity jumps sorted by time, C-contiguous for the kernel."""
    j = np.asarray(jumps, dtype=np.float64).reshape(-1, 2)
    return np.ascontiguousarray(j[np.argsort(j[:, 0], kind="stable")])


def _count_impacts(res: ContactResult, body: RigidBody, L: float) -> int:
    """Touchdowns seen on the samples (a base corner's gap closing)."""
    from nsdyn.models.contact._kgeom import contact_rows

    on = np.array([contact_rows(q, v, body.contacts)[0] <= MODE_G_TOL * L
                   for q, v in zip(res.q, res.v, strict=True)])  # fmt: skip
    if len(on) < 2:
        return 0
    return int(np.count_nonzero(on[1:] & ~on[:-1]))
