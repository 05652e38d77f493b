"""Event-driven simulation of a rigid body on the ground: smooth phases, mode switches, impacts.

Smooth phases are integrated by ``_kevent.integrate`` with the reactions of the acceleration-level
LCP.  At an event the mode is rebuilt from the state (``_settle``):

1. contacts on the ground that approach (g = 0, gd < 0) undergo an impact, solved at velocity
   level by the impulse LCP (``_kgeom.solve_contacts``) with Newton's law
   0 <= gd+ + e_n gd-  _|_  P_N >= 0 and Coulomb's law on the impulses; ``impact_law="housner"``
   uses the perfectly plastic, sticking impact, which for a rocking rectangle conserves the
   angular momentum about the striking corner, i.e. Housner's thetad+ = (1 - 1.5 sin^2 alpha)
   thetad-;
2. contacts with g = 0, gd = 0 are closed, sticking if v_T = 0, slipping with sigma = sign v_T;
3. the acceleration-level LCP opens closed contacts that accelerate away (lam_N = 0, w_N > 0)
   and makes sticking ones slip (in the direction of their tangential acceleration) when the
   cone cannot hold them; 4. positions and velocities are projected onto the closed constraints
   (positions also lift open contacts that round-off left at g < 0, so their touchdown
   indicator starts non-negative).

An impact slower than V_PLASTIC sqrt(g L) ends an accumulation: the corners that separate from
it slower than that stay closed, and the acceleration LCP decides whether they lift off.

A ground velocity jump (displacement-driven start) changes the body's ground-frame velocity by
-[u_g'] and is resolved as an impact of the same kind.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from nsdyn._checks import (
    InputWarning,
    NumericalFailure,
    expect,
    finite_numbers,
    number,
    output_step,
    output_times,
    rel_tol,
    whole,
)
from nsdyn.ground import G_EARTH
from nsdyn.models.contact import _kevent as ke
from nsdyn.models.contact._kgeom import body_mode, contact_rows, mu_of, solve_contacts
from nsdyn.models.contact.body import RigidBody
from nsdyn.models.contact.contact_compile import run_integrate, warm
from nsdyn.models.contact.excite import BaseMotion
from nsdyn.models.contact.friction import FrictionLaw
from nsdyn.models.contact.results import MODE_NAMES, ContactResult, state_mode
from nsdyn.models.tilt import initial_tilt

G_ON = 1e-8  # a contact touches when g <= G_ON * L
V_ON = 1e-8  # ... and is at rest (normal / tangential) when |velocity| <= V_ON * sqrt(g L)
V_PLASTIC = 1e-6  # impacts slower than V_PLASTIC * sqrt(g L) are plastic (ends accumulations)
MODE_G_TOL = 1e-6  # output classification: on the ground when g <= MODE_G_TOL * L
MODE_V_TOL = 1e-6  # ... slipping when |v_T| > MODE_V_TOL * sqrt(g L)
MAX_SETTLE = 8  # mode-rebuild iterations at one event
H_PER_PERIOD = 40  # a sine excitation is sampled by at least this many steps per period
EVENT_NAMES = {1: "touchdown", 2: "lift-off", 3: "stick-slip", 4: "slip-stop", 5: "overturn"}
FAIL = {
    -1: "step size underflow",
    -2: "too many steps",
    -3: "contact LCP has no solution",
    -4: "an open contact sank below the ground (missed touchdown)",
}


def tilt_angle(body: RigidBody, theta0: float | None, theta0_over_alpha: float | None) -> float:
    """The initial tilt [rad]: ``theta0``, or ``theta0_over_alpha`` times the slenderness alpha
    of the corner it rocks on (the left one for a positive tilt); one of them, or none (0)."""
    side = -1 if (theta0_over_alpha or 0.0) >= 0 else 1
    tilt = initial_tilt(theta0, theta0_over_alpha, body.corner_geometry(side)[1])
    if body.overturned(tilt):  # (every solver's start: Moreau-Jean's ran "overturned")
        pos, neg = body.overturn_tilts
        raise ValueError(
            f"{'theta0' if theta0 is not None else 'theta0_over_alpha'}: a tilt of {tilt:.4g} "
            f"rad starts the body overturned (it lies on an edge from {_side_ov(body, tilt):.4g}"
            f" rad that way); expected a tilt between {-min(neg, 0.5 * math.pi):.4g} and "
            f"{min(pos, 0.5 * math.pi):.4g} rad"
        )
    return tilt


def initial_state(body: RigidBody, theta0: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(q, v) at rest on the base, tilted by ``theta0`` about the outer corner it rocks on
    (theta0 > 0 rotates counter-clockwise about the left corner)."""
    c = body.contacts
    k = int(np.argmin(c[:, 0])) if theta0 >= 0 else int(np.argmax(c[:, 0]))
    r = c[k]
    cs, sn = math.cos(theta0), math.sin(theta0)
    # the pivot stays at its resting position (r_x, 0)
    x = r[0] - (cs * r[0] - sn * r[1])
    y = -(sn * r[0] + cs * r[1])
    return np.array([x, y, theta0]), np.zeros(3)


# a start's corner may lie this fraction of the body's size in a rigid ground: a restart from
# a Moreau-Jean state (corners 0.2 mm in the ground for a 1.5 m body at h = 1 ms) passes,
# a body placed a centimetre in it does not
Q0_DEPTH = 1e-3


def start_state(body: RigidBody, tilt: float, q0, v0, tilted: bool, rigid: bool = True):
    """(q, v) of a run: at rest tilted by ``tilt`` (:func:`initial_state`), or (q0, v0).
    ValueError for a q0 or v0 that is not three finite numbers, a q0 beside a tilt
    (``tilted``: theta0 or theta0_over_alpha given; the tilt was dropped) and, on a
    ``rigid`` ground, a q0 with a corner below it (the event solver lifted the body out
    without a word, Moreau-Jean left it 0.25 m in the ground "at rest")."""
    q, v = initial_state(body, tilt)
    given = {}
    for name, val in (("q0", q0), ("v0", v0)):
        if val is not None:
            given[name] = finite_numbers(name, val, "3 finite values (x, y, theta)", 3).copy()
    if "q0" in given and tilted:
        raise ValueError("q0: the start is given as a tilt (theta0 or theta0_over_alpha) and "
                         "as q0; give one of them")  # fmt: skip
    if "q0" in given:
        q = given["q0"]
        c = body.contacts
        y = q[1] + math.sin(q[2]) * c[:, 0] + math.cos(q[2]) * c[:, 1]
        size = float(np.ptp(body.verts, axis=0).max())
        if rigid and y.min() < -Q0_DEPTH * size:
            raise ValueError(f"q0: a corner starts {-y.min():.4g} m below the rigid ground; "
                             "expected every corner at or above it")  # fmt: skip
        if body.overturned(q[2]):  # (4 rad ran, "not overturned", as theta0 is refused)
            raise ValueError(f"q0: a tilt of {q[2]:.4g} rad is at or past the body's "
                             f"overturning tilt {_side_ov(body, q[2]):.4g} rad that way; "
                             "expected a smaller one")  # fmt: skip
    return q, given.get("v0", v)


def check_parts(body, friction, motion) -> None:
    """TypeError naming a body, friction law or motion of the wrong kind (the event and the
    Moreau-Jean runs: AttributeErrors 'verts', 'mu_s', 'resolving_step' from inside)."""
    expect("body", body, hasattr(body, "verts") and hasattr(body, "contacts"),
           "a RigidBody (nsdyn.RigidBody.rectangle(width, height, mass))")  # fmt: skip
    expect("friction", friction, hasattr(friction, "mu_s"),
           "a FrictionLaw (nsdyn.FrictionLaw(mu_s, mu_d))")  # fmt: skip
    if motion is not None and not hasattr(motion, "jumps"):
        raise TypeError(
            f"motion: expected a BaseMotion (nsdyn.BaseMotion.displacement_sine, ...), got "
            f"{type(motion).__name__}; nsdyn.BaseMotion.from_motion(record) makes one from a "
            "ground-motion record"
        )
    if motion is not None and motion.tab_h.size:  # a record before t = 0 ran unfelt, unsaid
        from nsdyn.ground.formats import early_record_note

        if note := early_record_note(float(motion.ex[1]), 0.0, "a contact run starts at t = 0: "
                                     "shift the record's clock to start there"):  # fmt: skip
            warnings.warn(f"motion: {note}", InputWarning, stacklevel=3)


def _side_ov(body: RigidBody, theta: float) -> float:
    """The overturning tilt [rad] on the side ``theta`` tips the body."""
    pos, neg = body.overturn_tilts
    return pos if theta >= 0 else -neg


def _params(body: RigidBody, fr: FrictionLaw, g: float) -> np.ndarray:
    L = float(np.ptp(body.verts, axis=0).max())
    pos, neg = body.overturn_tilts
    return np.array([body.mass, g, fr.mu_s, fr.mu_d, fr.cdec, pos, L, neg])


def impact(body, par, q, v, e_n, near):
    """Velocity after the impact of the contacts ``near`` (Newton restitution ``e_n``)."""
    verts, minv = body.contacts, body.minv
    g, Wn, Wt, bn, bt, gd, vt = contact_rows(q, v, verts)
    nc = len(verts)
    # a corner at rest (|v_T| within V_ON sqrt(g L), as _settle's stick) takes mu_s: a pivot's
    # v_T after the projection, and a rectangle's landing corner's at the located touchdown,
    # are round-off, never exactly 0, and the jump law read mu_d there
    rest = V_ON * math.sqrt(par[1] * par[6])
    mu = np.array([par[2] if abs(vt[i]) <= rest else mu_of(vt[i], par[2], par[3], par[4])
                   for i in range(nc)])  # fmt: skip
    bN = gd + e_n * np.minimum(gd, 0.0)
    idx = np.flatnonzero(near).astype(np.int64)
    PN, PT, wN, _, st = solve_contacts(Wn, Wt, minv, bN, vt, mu, np.zeros(nc), idx)
    if st != 0:  # (two corners sliding alike on one edge: their tangential rows are equal and
        # the pyramid's LCP degenerate) the slipping corners with their friction against the
        # slip the impact leaves: against the slip before, turned where the impulse reverses it
        sig = np.where(np.abs(vt) > rest, np.sign(vt), 0.0)
        for _ in range(3):
            PN, PT, wN, _, st = solve_contacts(Wn, Wt, minv, bN, vt, mu, sig, idx)
            after = Wt @ (v + minv * (Wn.T @ PN + Wt.T @ PT))
            turned = (sig != 0.0) & (sig * after < -rest)
            if st != 0 or not turned.any():
                break
            sig = np.where(turned, np.sign(after), sig)
        st = st or int(turned.any())  # (no direction the friction opposes: no solution)
    if st != 0:
        raise NumericalFailure("impact LCP has no solution")
    out = v + minv * (Wn.T @ PN + Wt.T @ PT)
    # a slip the impulse reverses passed through rest in the impact, where static friction
    # acts: solved again with mu_s at those corners, kept if it holds them within this
    # solver's stick test (Moreau-Jean's rule, with its own rest tolerance)
    vt_out = Wt @ out
    again = (PN > 0.0) & (vt * vt_out < 0.0) & (mu < par[2])
    if again.any():
        mu = np.where(again, par[2], mu)
        PN, PT, wN, _, st = solve_contacts(Wn, Wt, minv, bN, vt, mu, np.zeros(nc), idx)
        held = v + minv * (Wn.T @ PN + Wt.T @ PT)
        if st == 0 and np.all(np.abs(Wt[again] @ held) <= rest):
            out = held
    return out


def _settle(body, par, mo, t, y, e_n, closed, sig):
    """Rebuild the contact mode at an event (impacts first); returns (y, n_impacts)."""
    verts, minv = body.contacts, body.minv
    L, vs = par[6], math.sqrt(par[1] * par[6])
    q, v = y[:3].copy(), y[3:].copy()
    n_imp = 0
    g, Wn, Wt, bn, bt, gd, vt = contact_rows(q, v, verts)
    near = g <= G_ON * L
    v_close = V_ON * vs
    if np.any(near & (gd < -V_ON * vs)):
        slow = np.min(gd[near]) >= -V_PLASTIC * vs
        v = impact(body, par, q, v, 0.0 if slow else e_n, near)
        n_imp = 1
        g, Wn, Wt, bn, bt, gd, vt = contact_rows(q, v, verts)
        if slow:  # end of an impact accumulation: the corners that barely separate stay closed
            v_close = V_PLASTIC * vs
    closed[:] = near & (gd <= v_close)
    sig[:] = np.where(closed & (np.abs(vt) > V_ON * vs), np.sign(vt), 0.0)
    cl = closed.astype(np.float64)
    for _ in range(MAX_SETTLE):
        yy = np.concatenate([q, v])
        dy, ind, lamN, lamT, st = ke.rhs(t, yy, sig, cl, verts, minv, par, mo.ex, mo.tab_h,
                                         mo.tab_v)  # fmt: skip
        if st != 0:
            raise NumericalFailure(
                f"event-driven: contact LCP has no solution at t = {t:.9g} s (with large "
                "friction a rigid body's contact forces can have none, Painlevé's paradox; "
                "the Moreau-Jean method, solver.method = 'moreau', resolves it by impulses)"
            )
        nc = len(verts)
        changed = False
        for i in range(nc):
            if cl[i] and ind[i] < 0:
                cl[i], sig[i], changed = 0.0, 0.0, True
            elif cl[i] and sig[i] == 0 and ind[nc + i] < 0:
                aT = Wt[i] @ dy[3:] + bt[i]
                sig[i], changed = (1.0 if aT > 0 else -1.0), True
        if not changed:
            break
    closed[:] = cl > 0
    # project onto the closed constraints (positions, then velocities)
    c_idx = np.flatnonzero(closed)
    p_idx = np.flatnonzero(closed | (near & (g < 0.0)))  # open contacts are lifted to g = 0
    if len(p_idx):
        A = Wn[p_idx] * minv
        q -= A.T @ np.linalg.lstsq(A @ Wn[p_idx].T, g[p_idx], rcond=1e-12)[0]
    if len(c_idx):
        g, Wn, Wt, bn, bt, gd, vt = contact_rows(q, v, verts)
        rows = [Wn[i] for i in c_idx] + [Wt[i] for i in c_idx if sig[i] == 0]
        C = np.array(rows)
        v -= (C * minv).T @ np.linalg.lstsq((C * minv) @ C.T, C @ v, rcond=1e-12)[0]
    return np.concatenate([q, v]), n_imp


def _h_max(mo: BaseMotion) -> float:
    """Largest step that still samples the excitation: a record's dt, a sine's period / 40."""
    h = math.inf
    if len(mo.tab_h):
        h = float(mo.ex[2])
    if mo.ex[0] == 1.0 and mo.ex[4] > 0:
        h = min(h, 2 * math.pi / float(mo.ex[4]) / H_PER_PERIOD)
    return h


def simulate_event(body: RigidBody, friction: FrictionLaw, motion: BaseMotion | None = None, *,
                   t_end: float, e_n: float = 0.0, impact_law: str = "newton",
                   theta0: float | None = None, theta0_over_alpha: float | None = None,
                   q0=None, v0=None, rtol: float = 1e-9,
                   atol: float = 1e-12, dt_out: float = 0.005, max_events: int = 20000,
                   g: float = G_EARTH) -> ContactResult:  # fmt: skip
    """Event-driven simulation from rest (tilted by ``theta0`` [rad] or ``theta0_over_alpha``
    times the corner's slenderness) or from (q0, v0).

    ``impact_law``: ``"newton"`` (restitution ``e_n``) or ``"housner"`` (plastic, sticking).
    ``t_end`` [s]; ``q0``, ``v0``: a start of the body's coordinates and velocities in place
    of rest; ``rtol``, ``atol``: the integrator's tolerances between events; ``dt_out``:
    output step [s]; ``max_events``: events (impacts, stick-slip switches, lift-offs) before
    the run stops; ``g`` [m/s²]. Raises RuntimeError with the time on step underflow, LCP
    failure or too many events.
    """
    if impact_law not in ("newton", "housner"):
        raise ValueError(f"impact_law: expected 'newton' or 'housner', got {impact_law!r}")
    e_n = number("e_n", e_n, "a restitution coefficient in [0, 1]", lambda v: 0.0 <= v <= 1.0)
    whole("max_events", max_events, 1, "a whole number of events >= 1")
    if impact_law == "housner" and e_n != 0.0:  # (dropped: the histories equalled e_n = 0)
        raise ValueError("e_n: the Housner law is plastic (the corner sticks); a restitution "
                         "coefficient is Newton's law's (impact_law='newton')")  # fmt: skip
    check_parts(body, friction, motion)
    body = body.unit_mass()  # (the same motion; forces of order g in the LCPs)
    for name, val in (("t_end", t_end), ("dt_out", dt_out), ("atol", atol), ("g", g)):
        number(name, val, "a positive number", lambda v: v > 0)  # (g <= 0: math domain)
    rel_tol("rtol", rtol)
    output_step(dt_out, t_end, off=False)
    e = 0.0 if impact_law == "housner" else float(e_n)
    tilt = tilt_angle(body, theta0, theta0_over_alpha)
    warm()  # a first run: the loop here, the right-hand side in a helper
    mo = motion or BaseMotion.none()
    par = _params(body, friction, g)
    verts, minv = body.contacts, body.minv
    nc = len(verts)
    tilted = theta0 is not None or theta0_over_alpha is not None
    q, v = start_state(body, tilt, q0, v0, tilted)
    t_out = output_times(0.0, t_end, dt_out)  # (t_end the last: it ended a sample before)
    y_out = np.full((len(t_out), 6), np.nan)
    jumps = [tuple(j) for j in mo.jumps if 0.0 <= j[0] <= t_end]
    closed = np.zeros(nc, bool)
    sig = np.zeros(nc)
    t = 0.0
    y = np.concatenate([q, v])
    for tj, dv in jumps:
        if tj == 0.0:
            y[3] -= dv
    y, n_imp = _settle(body, par, mo, t, y, e, closed, sig)
    # the first contact state other than rest, at its time (the output samples lag it)
    first = None if state_mode(closed, sig != 0) == 0 else (t, state_mode(closed, sig != 0))
    iout = 0
    events: list = []
    h = 1e-3 * math.sqrt(par[6] / g)
    h_max = _h_max(mo)
    n_steps = n_rhs = 0
    t_over = None
    while t < t_end:
        nxt = min([t_end] + [tj for tj, _ in jumps if tj > t])
        t, y, h, code, which, iout, ns, nr = run_integrate((
            t, y, nxt, h, sig, closed.astype(np.float64), verts, minv, par, mo.ex, mo.tab_h,
            mo.tab_v, rtol, atol, t_out, y_out, iout, 1_000_000, h_max))  # fmt: skip
        n_steps += ns
        n_rhs += nr
        if code < 0:
            raise NumericalFailure(f"event-driven: {FAIL[code]} at t = {t:.9g} s")
        if code == ke.EV_OVER:
            t_over = t
            events.append((t, "overturn", -1))
            if first is None:
                first = (t, MODE_NAMES.index("overturned"))
            break
        if code == ke.EV_END:
            for tj, dv in jumps:
                if tj == t:
                    y[3] -= dv
                    events.append((t, "ground velocity jump", -1))
        else:
            events.append((t, EVENT_NAMES[code], which % nc))
        if len(events) > max_events:
            raise NumericalFailure(f"event-driven: more than {max_events} events by t = {t:.9g} s "
                               "(impact accumulation or chattering)")  # fmt: skip
        y, k = _settle(body, par, mo, t, y, e, closed, sig)
        n_imp += k
        if first is None and state_mode(closed, sig != 0) != 0:
            first = (t, state_mode(closed, sig != 0))
        h = max(h, 1e-6 * math.sqrt(par[6] / g))
    ok = ~np.isnan(y_out[:, 0])
    t_s, q_s, v_s = t_out[ok], y_out[ok, :3], y_out[ok, 3:]
    mode = np.array([body_mode(q_s[i], v_s[i], verts, MODE_G_TOL * par[6],
                               MODE_V_TOL * math.sqrt(g * par[6]), par[5], par[7])
                     for i in range(len(t_s))], dtype=np.int64)  # fmt: skip
    if t_over is not None:
        t_s = np.append(t_s, t_over)
        q_s = np.vstack([q_s, y[:3]])
        v_s = np.vstack([v_s, y[3:]])
        mode = np.append(mode, 5)
    base_mid = body.contacts.mean(axis=0)
    return ContactResult(t_s, q_s, v_s, mode, "event", base_mid, body.theta_ov, n_imp, t_over,
                         events, n_steps, n_rhs, body.contacts, MODE_G_TOL * par[6],
                         first)  # fmt: skip
