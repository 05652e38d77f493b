"""A rigid body on compliant ground: tensionless spring-dashpot corners with Coulomb friction.

The same :class:`RigidBody`, :class:`FrictionLaw` and :class:`BaseMotion` as the rigid-ground
solvers, but each base corner rests on a tensionless spring-dashpot (k, c) with a tangential
stick spring k_t and Coulomb's law mu(v) = mu_d + (mu_s - mu_d) exp(-C |v|) (jump law for
C = infinity: mu_s to break a stuck corner loose, mu_d while it slips); equations in
:mod:`._kcompliant`.  Static settlement on n base corners: delta_s = m g / (n k).

Ground from a damping ratio: the vertical contact frequency on all n corners is
omega_v = sqrt(n k / m) and c = 2 zeta sqrt(k m / n) per corner (a point mass on one linear
spring-dashpot that may pull rebounds with e = exp(-pi zeta / sqrt(1 - zeta^2)); on the
tensionless one here it leaves when the force k delta + c delta' falls to zero, before
delta does, and rebounds a little more: e = 0.744 against 0.729 at zeta = 0.1, 0.451
against 0.372 at zeta = 0.3).  The stick spring defaults
to k_t = k (the tangential stiffness of an elastic contact is close to the normal one,
Mindlin: k_t / k = 2 (1 - nu) / (2 - nu), from 1 at nu = 0 to 0.67 at nu = 0.5).

A displacement-driven ground's velocity jump [u_g'] changes the body's ground-frame velocity by
-[u_g'] at once; the compliant corners then carry it off with finite forces.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from nsdyn._checks import (
    MAX_STEPS,
    NumericalFailure,
    expect,
    flag,
    number,
    output_times,
    step_count,
)
from nsdyn.ground import G_EARTH
from nsdyn.models.contact import _kcompliant as kc
from nsdyn.models.contact.body import RigidBody
from nsdyn.models.contact.excite import BaseMotion
from nsdyn.models.contact.friction import FrictionLaw
from nsdyn.models.contact.results import MODE_NAMES, ContactResult

H_FRAC = 0.02  # step as a fraction of the explicit stability limit (0.25 overturned C2 spuriously)
H_PER_PERIOD = 40  # a sine excitation is sampled by at least this many steps per period


@dataclass(frozen=True)
class CompliantGround:
    """Per-corner normal stiffness ``k`` [N/m] and damping ``c`` [N s/m], stick spring ``k_t``
    [N/m] (default k)."""

    k: float
    c: float = 0.0
    k_t: float | None = None

    def __post_init__(self) -> None:
        if not (isinstance(self.k, int | float) and math.isfinite(self.k) and self.k > 0):
            raise ValueError(f"k: expected a positive stiffness per corner [N/m], "
                             f"got {self.k!r}")  # fmt: skip
        if not (isinstance(self.c, int | float) and math.isfinite(self.c) and self.c >= 0):
            raise ValueError(f"c: expected a non-negative damping per corner [N s/m], "
                             f"got {self.c!r}")  # fmt: skip
        kt = self.k_t
        if kt is not None and not (isinstance(kt, int | float) and math.isfinite(kt) and kt > 0):
            raise ValueError(f"k_t: expected a positive stick stiffness [N/m], "
                             f"got {self.k_t!r}")  # fmt: skip

    @classmethod
    def from_ratio(cls, body: RigidBody, k: float, zeta: float) -> CompliantGround:
        """Stiffness ``k`` per corner and damping ratio ``zeta`` of the vertical contact mode."""
        number("k", k, "a positive stiffness per corner [N/m]", lambda v: v > 0)
        number("zeta", zeta, "a non-negative damping ratio", lambda v: v >= 0)
        n = len(body.base)
        return cls(float(k), 2.0 * zeta * math.sqrt(k * body.mass / n))

    @property
    def kt(self) -> float:
        return self.k if self.k_t is None else float(self.k_t)

    def settlement(self, body: RigidBody, g: float = G_EARTH) -> float:
        """Static settlement m g / (n k) on the n base corners [m]."""
        return body.mass * g / (len(body.base) * self.k)


@dataclass(repr=False, eq=False)
class CompliantResult(ContactResult):
    """A :class:`ContactResult` plus the energy terms of the compliant ground.

    e_spring : (n, 2) normal and stick-spring energies [J];  w_ext : (n,) work of the ground's
    inertial load;  w_contact : (n,) work of the contact forces on the body;  h : step [s]
    """

    e_spring: np.ndarray = None
    w_ext: np.ndarray = None
    w_contact: np.ndarray = None
    n_on: np.ndarray = None
    h: float = 0.0
    wall_s: float = 0.0

    def mechanical_energy(self, mass: float, J: float, g: float = G_EARTH) -> np.ndarray:
        """(n,) kinetic + potential + spring energies [J]."""
        return self.energy(mass, J, g) + self.e_spring.sum(axis=1)

    def dissipated(self, mass: float, J: float, g: float = G_EARTH) -> np.ndarray:
        """(n,) energy dissipated by the dashpots and by slip since t = 0 [J]:
        D = -W_contact - (E_springs - E_springs(0))."""
        es = self.e_spring.sum(axis=1)
        return -self.w_contact - (es - es[0])

    def summary(self) -> dict:
        s = super().summary()
        lift = self.n_on < len(self.base_idx)
        s["n_liftoffs"] = int(np.count_nonzero(lift[1:] & ~lift[:-1]))
        s["max_uplift_m"] = float(np.max(self.uplift)) if len(self.t) else 0.0
        s["step_s"] = float(self.h)
        return s

    def histories(self) -> dict:
        """The rigid body's histories, the spring energies, the works of the ground's inertial
        load and of the contact forces, the corners on the ground and the uplift."""
        out = super().histories()
        out.update({"spring_energy_normal_J": self.e_spring[:, 0],
                    "spring_energy_stick_J": self.e_spring[:, 1], "work_ground_J": self.w_ext,
                    "work_contact_J": self.w_contact, "n_on": self.n_on,
                    "uplift_m": self.uplift})  # fmt: skip
        return out

    base_idx: np.ndarray = None
    uplift: np.ndarray = None


def _params(body: RigidBody, friction: FrictionLaw, ground: CompliantGround, g: float):
    p = np.zeros(kc.N_P)
    p[kc.P_M], p[kc.P_J], p[kc.P_G] = body.mass, body.J, g
    p[kc.P_K], p[kc.P_C], p[kc.P_KT] = ground.k, ground.c, ground.kt
    p[kc.P_MUS], p[kc.P_MUD], p[kc.P_CDEC] = friction.mu_s, friction.mu_d, friction.cdec
    p[kc.P_THOV], p[kc.P_THOV_NEG] = body.overturn_tilts
    return p


def stable_step(body: RigidBody, ground: CompliantGround) -> tuple[float, float]:
    """Explicit stability limit 2 (sqrt(1 + zeta^2) - zeta) / omega_max [s], with
    omega_max^2 <= sum_j (k + k_t)(1/m + |r_j|^2 / J) (trace bound of M^-1 K) and
    zeta = c omega_max / (2 k) the damping ratio of that mode; and that zeta."""
    r2 = np.sum(body.contacts**2, axis=1)
    w2 = float(np.sum((ground.k + ground.kt) * (1.0 / body.mass + r2 / body.J)))
    w = math.sqrt(w2)
    zeta = ground.c * w / (2.0 * ground.k)
    # (as written, free of cancellation and overflow: a damping ratio of 1e300 gave inf)
    return 2.0 / (math.hypot(1.0, zeta) + zeta) / w, zeta


def ground_step(body: RigidBody, ground: CompliantGround, t_end: float | None = None) -> float:
    """The explicit stability limit (:func:`stable_step`); ValueError naming the ground's
    ``stiffness`` (``stick_stiffness`` when a given one is the stiffer, ``damping`` past a
    damping ratio of 1) when a run of ``t_end`` takes more than ``MAX_STEPS`` steps of
    H_FRAC of it."""
    h_stab, zeta = stable_step(body, ground)
    h = H_FRAC * h_stab
    if t_end is not None and not t_end / h <= MAX_STEPS:
        stick = ground.k_t is not None and ground.kt > ground.k
        field = "stick_stiffness" if stick else "damping" if zeta > 1 else "stiffness"
        raise ValueError(f"{field}: the ground's stiffness "
                         f"and damping bound the explicit step to {h:.3g} s, {t_end / h:.3g} "
                         f"steps over {t_end:g} s, more than {MAX_STEPS:.0e}; expected a "
                         "softer or less damped ground (or a shorter run)")  # fmt: skip
    return h_stab


SETTLE_MAX = 0.1  # the static settlement m g / (n k): at most this part of the body's base


def check_settlement(body: RigidBody, ground: CompliantGround, g: float = G_EARTH) -> None:
    """ValueError naming ``stiffness`` when the weight settles the base corners by more than
    ``SETTLE_MAX`` of the base width (of the body's size when it rests on one vertex)."""
    verts = body.verts
    width = float(np.ptp(verts[body.base, 0])) or float(np.ptp(verts, axis=0).max())
    weight = body.mass * g / len(body.base)  # per base corner
    if weight / ground.k > SETTLE_MAX * width:
        raise ValueError(f"stiffness: the static settlement m g / (n k) = {weight / ground.k:.3g} "
                         f"m is more than {SETTLE_MAX:.0%} of the base ({width:.3g} m); "
                         f"expected k >= {weight / (SETTLE_MAX * width):.3g} N/m")  # fmt: skip


def simulate_compliant(
    body: RigidBody,
    friction: FrictionLaw,
    ground: CompliantGround,
    motion: BaseMotion | None = None,
    *,
    t_end: float,
    theta0: float | None = None,
    theta0_over_alpha: float | None = None,
    q0=None,
    v0=None,
    settled: bool = True,
    h: float | None = None,
    dt_out: float = 0.005,
    g: float = G_EARTH,
) -> CompliantResult:
    """Response of ``body`` on compliant ground from rest (settled by m g / (n k) unless
    ``settled=False``), tilted by ``theta0`` [rad] (or ``theta0_over_alpha`` times the
    slenderness) about the corner it rocks on, which then carries the weight (settled by
    m g / k), or from (q0, v0) [ground frame].  ``h`` defaults to H_FRAC times the stability
    limit.  Raises RuntimeError with the time on a non-finite state."""
    from nsdyn.models.contact.event import check_parts, initial_state, start_state, tilt_angle

    for name, val, kind, what in (
        ("body", body, RigidBody, "a RigidBody (nsdyn.RigidBody.rectangle(width, height, mass))"),
        ("friction", friction, FrictionLaw, "a FrictionLaw (nsdyn.FrictionLaw(mu_s, mu_d))"),
        ("ground", ground, CompliantGround, "a CompliantGround (stiffness k, damping c)"),
    ):  # (a stiffness given as the ground: "'float' object has no attribute 'k'")
        expect(name, val, isinstance(val, kind), what)
    if motion is not None and not hasattr(motion, "jumps"):
        expect("motion", motion, False, "a BaseMotion (nsdyn.BaseMotion.from_motion(record))")
    check_parts(body, friction, motion)  # (a record before t = 0: warned)
    tilt = tilt_angle(body, theta0, theta0_over_alpha)
    mo = motion or BaseMotion.none()
    flag("settled", settled)
    check_settlement(body, ground, g)
    h_stab = ground_step(body, ground, t_end if h is None else None)  # (its own step)
    h = H_FRAC * h_stab if h is None else float(h)
    if not (0 < h < h_stab):
        raise ValueError(f"h: expected 0 < h < {h_stab:.3e} s (explicit stability), got {h!r}")
    if mo.ex[0] == 1.0 and mo.ex[4] > 0:
        h = min(h, 2 * math.pi / mo.ex[4] / H_PER_PERIOD)
    if mo.tab_h.size:
        h = min(h, mo.ex[2])
    step_count(t_end, h, "t_end")  # (h follows the ground: soften it or shorten the run)
    p = _params(body, friction, ground, g)
    verts = body.contacts
    q = np.array([0.0, body.y0, 0.0])
    if settled:
        q[1] -= ground.settlement(body, g)
    if tilt != 0.0:  # (about the corner at rest on the ground, then settled under the weight)
        q = initial_state(body, tilt)[0]
        q[1] -= body.mass * g / ground.k if settled else 0.0
    tilted = theta0 is not None or theta0_over_alpha is not None  # (a compliant ground: a
    given, vh = start_state(body, 0.0, q0, v0, tilted, rigid=False)  # corner may start in it)
    q = given if q0 is not None else q
    anchor = np.full(len(verts), np.nan)
    stuck = np.ones(len(verts))
    acc = np.zeros(2)
    t_out = output_times(0.0, t_end, dt_out)  # (t_end the last: filled after the loop)
    y_out = np.full((len(t_out), kc.N_OUT), np.nan)
    jumps = sorted(tuple(j) for j in mo.jumps if 0.0 <= j[0] <= t_end)
    t, iout, n_steps, t_over = 0.0, 0, 0, None
    w0 = time.perf_counter()
    while t < t_end:
        for tj, dv in jumps:
            if tj == t:
                vh[0] -= dv
        nxt = min([t_end] + [tj for tj, _ in jumps if tj > t])
        st, t, iout, ns = kc.integrate(t, nxt, h, q, vh, verts, anchor, stuck, p, mo.ex,
                                       mo.tab_h, mo.tab_v, acc, t_out, y_out, iout)  # fmt: skip
        n_steps += ns
        if st == kc.ST_NONFINITE:
            raise NumericalFailure(f"compliant ground: non-finite state at t = {t:.9g} s")
        if st == kc.ST_OVER:
            t_over = t
            break
    if t_over is None and iout < len(t_out):  # the end's rows: the steps write their starts'
        f, info = np.zeros(3), np.zeros(4)  # (it ended one output step before t_end)
        kc.forces(t_end, q, vh, verts, anchor, stuck, p, mo.ex, mo.tab_h, mo.tab_v, f, info)
        v_end = vh + 0.5 * h * f / np.array([body.mass, body.mass, body.J])  # (v(t_end))
        y_out[iout:] = np.concatenate([q, v_end, info[:2], acc, info[2:]])  # (each the
        iout = len(t_out)  # state at its nearest step, as the kernel's rows)
    wall = time.perf_counter() - w0
    n = iout
    y = y_out[:n]
    mode = _modes(y, len(verts))
    if t_over is not None:
        mode[-1] = MODE_NAMES.index("overturned")
    c, s = np.cos(y[:, 2]), np.sin(y[:, 2])
    highest = np.max(y[:, 1:2] + s[:, None] * verts[:, 0] + c[:, None] * verts[:, 1], axis=1)
    xb = verts[:, 0].mean(), verts[:, 1].mean()
    n_on = y[:, 10].astype(int)
    # touchdowns seen on the samples, as the rigid solvers count impacts: corners that came
    # back onto the springs between two outputs (smooth here, no impact law)
    touchdowns = int(np.sum(np.maximum(np.diff(n_on), 0))) if n else 0
    return CompliantResult(
        t_out[:n], y[:, :3].copy(), y[:, 3:6].copy(), mode, "compliant", np.array(xb),
        body.theta_ov, touchdowns, t_over, [], n_steps, n_steps, e_spring=y[:, 6:8].copy(),
        w_ext=y[:, 8].copy(), w_contact=y[:, 9].copy(), n_on=n_on, h=h,
        wall_s=wall, base_idx=np.arange(len(verts)), uplift=np.maximum(highest, 0.0),
        contacts=verts, on_tol=0.0,
    )  # fmt: skip


def _modes(y: np.ndarray, nc: int) -> np.ndarray:
    """Body mode of each output row from the corners on the ground and slipping."""
    n_on, n_slip = y[:, 10], y[:, 11]
    mode = np.where(n_slip > 0, MODE_NAMES.index("slide_rock"), MODE_NAMES.index("rock"))
    full = n_on >= nc
    mode = np.where(full & (n_slip > 0), MODE_NAMES.index("slide"), mode)
    mode = np.where(full & (n_slip == 0), MODE_NAMES.index("rest"), mode)
    mode = np.where(n_on == 0, MODE_NAMES.index("flight"), mode)
    return mode.astype(int)
