"""Moreau-Jean time stepping of a rigid body on the ground (driver of ``_kmoreau``).

theta-method on velocities with impulses at velocity level each step (see ``_kmoreau``):
first order, robust through impact accumulations, sticking and hops; no event location.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from nsdyn._checks import (
    AccuracyWarning,
    NumericalFailure,
    number,
    output_count,
    output_step,
    step_count,
)
from nsdyn.ground import G_EARTH
from nsdyn.models.contact import _kmoreau as km
from nsdyn.models.contact.body import RigidBody
from nsdyn.models.contact.event import _params, check_parts, start_state, tilt_angle
from nsdyn.models.contact.excite import BaseMotion
from nsdyn.models.contact.friction import FrictionLaw
from nsdyn.models.contact.results import ContactResult, slenderness

MODE_G_TOL = 1e-5  # output classification: on the ground when g <= MODE_G_TOL * L
MODE_V_TOL = 1e-5  # ... slipping when |v_T| > MODE_V_TOL * sqrt(g L)
STATUS = {-1: "contact LCP has no solution", -2: "non-finite state"}
STEP_CHECK_RTOL = 0.1  # peaks at h and h/2 farther apart than this: the step is too long


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
                    g: float = G_EARTH, step_check: bool = False) -> ContactResult:  # fmt: skip
    """Moreau-Jean run with step ``h``, storing every ``dt_out`` (default: every step; rounded
    to a whole number of steps, at least one: the result's ``t`` holds the times kept), from
    rest (tilted by ``theta0`` [rad] or ``theta0_over_alpha``) or from (q0, v0).

    The scheme is first order and passes through impacts without locating them: where the
    body hops (``result.n_hops``) or rocks through many impacts, its step can be qualitatively
    wrong (docs/guide/contact.md, the stability map). ``step_check=True`` repeats the run at
    ``h/2`` and compares the peak tilt and slide and the final tilt (within
    ``STEP_CHECK_RTOL`` above a floor of 1 % of the slenderness, 1e-4 of the body's size for
    the slide), as a scene does: the result's
    ``step_check`` holds ``step_resolved`` (None: the run at h/2 failed), ``h_half``
    and, unless resolved, ``step_note``, which an :class:`~nsdyn.AccuracyWarning` also says.
    Without it, a run that hopped warns that its step is unchecked; otherwise it says nothing.
    :func:`nsdyn.models.contact.event.simulate_event` locates every impact instead."""
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
    q_start, v_start = q.copy(), v.copy()  # (a step check restarts from them)
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
    if step_check:  # (the same outputs: only the steps halve)
        kw = dict(t_end=t_end, theta=theta, e_n=e_n, q0=q_start, v0=v_start, g=g,
                  dt_out=max(dt_out or h, h))  # fmt: skip
        res.step_check = half_step_check(
            res, body, h, lambda h2: simulate_moreau(body, friction, motion, h=h2, **kw)
        )
        if res.step_check["step_resolved"] is not True:
            warnings.warn(res.step_check["step_note"], AccuracyWarning, stacklevel=2)
    elif res.n_hops:
        warnings.warn(f"Moreau-Jean: the body hopped {res.n_hops} times (first at t = "
                      f"{res.hop_times[0]:.4g} s); a step of h = {h:g} s passes impacts "
                      "unlocated and can be qualitatively wrong here, and nothing checked it: pass "
                      "step_check=True (a rerun at h/2) or use simulate_event",
                      AccuracyWarning, stacklevel=2)  # fmt: skip
    return res


def half_step_check(
    res: ContactResult, body: RigidBody, h: float, rerun, h_name: str = "h",
    instead: str = "the event-driven solver",
) -> dict:  # fmt: skip
    """The run ``res`` at step ``h`` against ``rerun(h / 2)`` (the scheme is first order: the
    peaks move by about their error): ``step_resolved`` when the peak tilt and slide and the
    final tilt agree within ``STEP_CHECK_RTOL`` above a floor of 1 % of the slenderness and
    1e-4 of the body's size (None: the rerun failed), ``h_half`` (the rerun's values), and
    unless resolved ``step_note`` saying both and advising a smaller ``h_name`` or
    ``instead``."""
    try:
        with warnings.catch_warnings():  # (its hops are the run's own)
            warnings.simplefilter("ignore", AccuracyWarning)
            half = rerun(0.5 * h).summary()
    except (ValueError, NumericalFailure) as e:  # the run stands; the check could not be made
        return {"step_resolved": None, "step_note": f"the check at h/2 failed: {e}"}
    s = res.summary()
    alpha, size = slenderness(body), float(np.ptp(body.contacts, axis=0).max())
    off = []
    keys = (
        ("max_tilt_rad", 0.01 * alpha),
        ("max_slide_m", 1e-4 * size),
        ("final_tilt_rad", 0.01 * alpha),
    )  # (a hop's error shows in the end, not the peak)
    for k, floor in keys:  # fmt: skip
        a, b = s[k], half[k]
        if abs(a - b) > STEP_CHECK_RTOL * max(abs(a), abs(b)) + floor:
            off.append(f"{k} {a:.4g} at h = {h:g} s, {b:.4g} at h/2")
    out = {"step_resolved": not off, "h_half": {k: half[k] for k, _ in keys}}
    if off:
        out["step_note"] = ("the Moreau-Jean step does not resolve this response: "
                            + "; ".join(off) + f": use a smaller {h_name} (first order: halve "
                            f"it until the peaks settle) or {instead}")  # fmt: skip
    return out


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
