"""A rigid block on tensionless spring–damper corner supports (seed 001 model 1), and its
effective coefficient of restitution measured from free rocking. Here ``k`` is the spring
stiffness and ``c`` the damping; seed 001 names them the other way round (its c the stiffness,
its k the damping constant): swap them when taking its model-1 values.

Supports (per corner): vertical ``N = max(0, k d + c d')`` while the corner penetrates by
``d > 0``, horizontal no-slip spring–damper ``k_t, c_t`` from the touchdown point; see
:mod:`._kcompliant` for the equations of the planar rigid body (x, y, theta). Lift-off and
impact come out of the contact law.

Stiffness and damping are set from the vertical contact frequency of the block resting on
both corners, ``omega_v = sqrt(2 k / m)``, and the contact damping ratio ``zeta``:
``c = zeta sqrt(2 k m)`` (i.e. ``2 zeta omega_v m / 2`` per corner), ``k_t = k``, ``c_t = c``.

Effective restitution (seed 001 Table 2 approach): from successive peaks theta_n, theta_n+1
of free rocking, ``r_eff² = (cos(alpha - theta_n+1) - cos alpha) / (cos(alpha - theta_n) -
cos alpha)`` (the energy relation of the rigid block), averaged over the first impacts.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from nsdyn._checks import NumericalFailure, number, output_count, rel_tol
from nsdyn._tabular import Tabular
from nsdyn.ground import G_EARTH
from nsdyn.models.rocking import _kcompliant as kc
from nsdyn.models.rocking.block import (
    HalfSizes,
    _excitation,
    block_sizes,
    check_frequency,
    former_positional,
)
from nsdyn.models.tilt import final_tilt, initial_tilt

TOL = 1e-8  # default relative tolerance
PEAK_MIN = 0.05  # peaks below this fraction of alpha are not used for r_eff (contact noise)
DT_OUT = 1e-3  # default output step [s]
STEP_BUDGET = 20_000_000  # step attempts of one run (~6 s at 3.5e6 steps/s)
H_MAX_P = 0.05  # largest step in units of 1/p
H_MAX_CONTACT = 1.0  # largest step in units of 1/(omega_v (1 + 2 zeta)) (explicit stability)


@dataclass(frozen=True, init=False)
class CompliantBlock(HalfSizes):
    """Block of full ``width`` 2B and ``height`` 2H [m] (or half sizes ``B``, ``H`` by name) and
    mass ``mass`` [kg] on corner supports ``k`` [N/m], ``c`` [N s/m] (vertical), ``k_t``,
    ``c_t`` (horizontal; default the vertical ones)."""

    width: float
    height: float
    mass: float
    k: float
    c: float
    k_t: float | None = None
    c_t: float | None = None
    g: float = G_EARTH

    def __init__(self, *args, width: float | None = None, height: float | None = None,
                 mass: float | None = None, k: float | None = None, c: float | None = None,
                 k_t: float | None = None, c_t: float | None = None, g: float = G_EARTH,
                 B: float | None = None, H: float | None = None) -> None:  # fmt: skip
        # the former positional (B, H, mass, k, c, k_t, c_t, g)
        mass, k, c, k_t, c_t, g = former_positional(args, (mass, k, c, k_t, c_t, g))
        w, h = block_sizes("CompliantBlock", args[:2], width, height, B, H)
        for name, v in (("width", w), ("height", h), ("mass", mass), ("k", k), ("c", c),
                        ("k_t", k_t), ("c_t", c_t), ("g", g)):  # fmt: skip
            object.__setattr__(self, name, v)
        for name in ("mass", "k", "g"):
            object.__setattr__(self, name, number(name, getattr(self, name), "a positive number",
                                                  lambda x: x > 0))  # fmt: skip
        object.__setattr__(self, "c", number("c", self.c, "a non-negative number",
                                             lambda x: x >= 0))  # fmt: skip
        for name, ok, what in (("k_t", lambda x: x > 0, "a positive number"),
                               ("c_t", lambda x: x >= 0, "a non-negative number")):  # fmt: skip
            if getattr(self, name) is not None:  # (k_t = -1e9 ran; 'x' failed at the run)
                object.__setattr__(self, name, number(name, getattr(self, name), what, ok))

    @classmethod
    def from_frequency(cls, *args, width: float | None = None, height: float | None = None,
                       mass: float | None = None, omega_v: float | None = None,
                       zeta: float | None = None, g: float = G_EARTH, B: float | None = None,
                       H: float | None = None) -> CompliantBlock:  # fmt: skip
        """Supports giving the vertical contact frequency ``omega_v`` [rad/s] and ratio zeta."""
        # the former positional (B, H, mass, omega_v, zeta, g)
        mass, omega_v, zeta, g = former_positional(args, (mass, omega_v, zeta, g))
        w, h = block_sizes("CompliantBlock", args[:2], width, height, B, H)
        for name, v in (("mass", mass), ("omega_v", omega_v), ("zeta", zeta)):
            if v is None:
                raise ValueError(f"CompliantBlock.from_frequency: {name}: missing")
        mass = number("mass", mass, "a positive mass [kg]", lambda x: x > 0)
        zeta = number("zeta", zeta, "a damping ratio >= 0", lambda x: x >= 0)
        omega_v = number("omega_v", omega_v, "a positive frequency [rad/s] whose stiffness "
                         "0.5 mass omega_v^2 is finite",
                         lambda x: x > 0 and math.isfinite(0.5 * mass * x * x))  # fmt: skip
        k = 0.5 * mass * omega_v**2
        c = zeta * math.sqrt(2.0 * k * mass)
        if not math.isfinite(c):  # (the dataclass blamed c, which was not given)
            raise ValueError(f"zeta: a damping ratio of {zeta:g} on a {mass:g} kg block at "
                             f"{omega_v:g} rad/s gives c = zeta sqrt(2 k mass) = {c:g}; expected "
                             "a finite damping")  # fmt: skip
        return cls(width=w, height=h, mass=mass, k=k, c=c, g=g)

    @property
    def alpha(self) -> float:
        return math.atan2(self.B, self.H)

    @property
    def p(self) -> float:
        """Frequency parameter of the rigid block sqrt(3 g / 4R) [1/s]."""
        return math.sqrt(3.0 * self.g / (4.0 * math.hypot(self.B, self.H)))

    @property
    def omega_v(self) -> float:
        return math.sqrt(2.0 * self.k / self.mass)

    @property
    def I_c(self) -> float:
        return self.mass * (self.B**2 + self.H**2) / 3.0


@dataclass(repr=False, eq=False)
class CompliantResult(Tabular):
    """Time history ``t`` (n,), ``y`` (n, 8) = [x, y, phi, x', y', phi', e_0, e_1]; theta = -phi.
    ``t_overturn``: the time |theta| reached pi/2, where the run ended (NaN: it did not)."""

    t: np.ndarray
    y: np.ndarray
    alpha: float
    n_steps: int
    wall_s: float
    t_overturn: float = math.nan
    half_sizes: tuple = (math.nan, math.nan)  # (B, H): the corners' place on the block

    @property
    def theta(self) -> np.ndarray:
        return -self.y[:, 2]

    def flights(self) -> dict:
        """The block off the ground, both corners above it, on the output grid: ``n_flights``
        (the times it left), ``max_flight_height_m`` (the lower corner's greatest height) and
        ``t_first_flight_s`` (None: it never flew). The rigid block stops there (free flight
        is not modelled); the compliant corners let it fly, which a summary should say."""
        B, H = self.half_sizes
        c, s = np.cos(self.y[:, 2]), np.sin(self.y[:, 2])
        low = np.minimum(self.y[:, 1] + s * -B - c * H, self.y[:, 1] + s * B - c * H)
        up = low > 0.0
        starts = np.flatnonzero(up & ~np.concatenate(([False], up[:-1])))
        return {"n_flights": int(starts.size),
                "max_flight_height_m": float(low[up].max()) if up.any() else 0.0,
                "t_first_flight_s": float(self.t[starts[0]]) if starts.size else None}  # fmt: skip

    @property
    def thetad(self) -> np.ndarray:
        return -self.y[:, 5]

    def peaks(self) -> np.ndarray:
        """(time, theta) of each extremum of |theta| (parabola through the grid maximum)."""
        th = self.theta
        out = []
        for i in range(1, th.size - 1):
            a, b, c = abs(th[i - 1]), abs(th[i]), abs(th[i + 1])
            if b >= a and b > c and np.sign(th[i - 1]) == np.sign(th[i]) == np.sign(th[i + 1]):
                den = a - 2 * b + c
                d = 0.5 * (a - c) / den if den != 0 else 0.0
                dt = self.t[1] - self.t[0]
                out.append((self.t[i] + d * dt, np.sign(th[i]) * (b - 0.25 * (a - c) * d)))
        return np.array(out).reshape(-1, 2)

    def summary(self) -> dict:
        """JSON-ready numbers of the run, the unit in each name; ``outcome`` "overturned" or
        "standing" (a rigid block's "rest" and "rocking" count impacts, which this contact
        has none of)."""
        over = math.isfinite(self.t_overturn)  # (then it reached pi/2, between two outputs)
        peak = math.pi / 2 if over else float(np.max(np.abs(self.theta)))
        return {
            "alpha_rad": self.alpha,
            "max_theta_rad": peak,
            "max_theta_over_alpha": peak / self.alpha,
            "outcome": "overturned" if over else "standing",  # (no impacts to rest on)
            "overturned": over,
            "t_overturn_s": self.t_overturn if math.isfinite(self.t_overturn) else None,
            **final_tilt(self.theta, self.thetad, self.alpha, over),
            **self.flights(),
            "n_steps": self.n_steps,
            "wall_s": self.wall_s,
        }

    def histories(self) -> dict:
        """The state on the output grid (relative to the moving ground), units in the names."""
        y = self.y
        return {"x_m": y[:, 0], "y_m": y[:, 1], "theta_rad": self.theta,
                "xd_m_per_s": y[:, 3], "yd_m_per_s": y[:, 4], "thetad_rad_per_s": self.thetad,
                "spring_stretch_left_m": y[:, 6], "spring_stretch_right_m": y[:, 7]}  # fmt: skip


SETTLE_MAX = 0.1  # the corners' static settlement g / omega_v^2: at most this part of the width


def check_settlement(model: CompliantBlock) -> None:
    """ValueError naming ``omega_v`` when the weight settles the corners by more than
    ``SETTLE_MAX`` of the block's width (k = m omega_v^2 / 2 per corner)."""
    settle = model.g / model.omega_v**2
    if settle > SETTLE_MAX * model.width:
        least = math.sqrt(model.g / (SETTLE_MAX * model.width))
        raise ValueError(f"omega_v: the corners' static settlement g / omega_v^2 = {settle:.3g} "
                         f"m is more than {SETTLE_MAX:.0%} of the width; expected omega_v >= "
                         f"{least:.3g} rad/s ({least / model.p:.3g} p)")  # fmt: skip


def simulate_compliant(
    model: CompliantBlock,
    excitation=None,
    *,
    t_end: float,
    theta0: float | None = None,
    theta0_over_alpha: float | None = None,
    tol: float = TOL,
    dt_out: float = DT_OUT,
    h_max: float | None = None,
) -> CompliantResult:
    """Response of the block on corner supports; starts at rest on the ground (theta0 = 0,
    static settlement) or tilted by ``theta0`` [rad] (or ``theta0_over_alpha`` times alpha) on
    one corner that carries the weight. The run ends early where the block overturns (|theta|
    reaches pi/2: ``result.t_overturn``)."""
    if not isinstance(model, CompliantBlock):
        raise TypeError(f"model: expected a CompliantBlock (nsdyn.CompliantBlock.from_frequency("
                        f"width=..., height=..., mass=..., omega_v=..., zeta=...)), got "
                        f"{type(model).__name__}; a rigid block or frame rocks by Housner's "
                        "impacts: nsdyn.simulate_rocking(model, ...)")  # fmt: skip
    t_end = number("t_end", t_end, "a positive finite end time [s]", lambda v: v > 0)
    rel_tol("tol", tol)  # (0 or NaN: "non-finite state" at t = 0; 5 ran)
    theta0 = initial_tilt(theta0, theta0_over_alpha, model.alpha)
    check_settlement(model)
    check_frequency(model, excitation)
    how = "a compliant run starts at t = 0: shift the record's clock to start there"
    gk, gp, tab_h, tab_v, _ = _excitation(excitation, t_end, 0.0, how)
    q = np.zeros(kc.N_Q)
    q[kc.Q_M] = model.mass
    q[kc.Q_I] = model.I_c
    q[kc.Q_B] = model.B
    q[kc.Q_H] = model.H
    q[kc.Q_K] = model.k
    q[kc.Q_C] = model.c
    q[kc.Q_KT] = model.k if model.k_t is None else model.k_t
    q[kc.Q_CT] = model.c if model.c_t is None else model.c_t
    q[kc.Q_G] = model.g
    q[kc.Q_WV] = model.omega_v
    q[kc.Q_TOL] = tol
    given = h_max is not None
    if given:  # (0 divided by zero)
        h_max = number("h_max", h_max, "a positive largest step [s]", lambda v: v > 0)
    else:  # resolve the contact: explicit stability and no step through a corner
        zeta = model.c / math.sqrt(2.0 * model.k * model.mass)
        h_max = min(H_MAX_P / model.p, H_MAX_CONTACT / (model.omega_v * (1.0 + 2.0 * zeta)))
    q[kc.Q_HMAX] = h_max
    if t_end / h_max > STEP_BUDGET:  # the contact's steps over the run: minutes and more
        steps = f"{t_end / h_max:.3g} over the run, beyond {STEP_BUDGET:.0e}"
        raise ValueError(
            f"h_max: a largest step of {h_max:.3g} s takes {steps}; expected a larger step or a "
            "shorter run"
            if given
            else f"omega_v: a contact of {model.omega_v:.3g} rad/s damped at zeta = {zeta:.3g} "
            f"needs steps of {h_max:.3g} s (∝ 1/(omega_v (1 + 2 zeta))), {steps}; expected a "
            "softer or less damped contact or a shorter run"
        )
    q[kc.Q_BUDGET] = STEP_BUDGET  # (the error control may take far smaller steps)
    d_static = model.mass * model.g / (2.0 * model.k)
    y0 = np.zeros(8)
    if theta0 == 0.0:
        y0[1] = model.H - d_static
    else:
        s = math.copysign(1.0, theta0)
        phi = -theta0
        corner = np.array([s * model.B, -2.0 * d_static])
        bx, by = s * model.B, -model.H
        y0[0] = corner[0] - (math.cos(phi) * bx - math.sin(phi) * by)
        y0[1] = corner[1] - (math.sin(phi) * bx + math.cos(phi) * by)
        y0[2] = phi
    scale_x = 1e-3 * model.B  # absolute tolerance scales: lengths, angle, rates
    atol = tol * np.array([scale_x, scale_x, 1e-3 * model.alpha,
                           model.p * scale_x, model.p * scale_x, 1e-3 * model.p * model.alpha,
                           scale_x, scale_x])  # fmt: skip
    n_out = output_count(t_end, dt_out)
    out = np.zeros((n_out, 8))
    info = np.zeros(kc.N_J)
    w0 = time.perf_counter()
    st = kc.integrate(q, atol, gk, gp, tab_h, tab_v, y0, 0.0, float(t_end), dt_out, out, info)
    wall = time.perf_counter() - w0
    if st != kc.ST_OK:
        why = {kc.ST_UNDERFLOW: "step size underflow", kc.ST_NONFINITE: "non-finite state"}.get(
            st, f"{STEP_BUDGET:.0e} step attempts spent (a contact too stiff for the tolerance: "
            "a softer contact or a shorter run)")  # fmt: skip
        raise NumericalFailure(f"compliant block failed at t = {info[kc.J_TFAIL]:.6g} s: {why}")
    n = int(info[kc.J_NOUT])
    return CompliantResult(dt_out * np.arange(n), out[:n].copy(), model.alpha,
                           int(info[kc.J_NSTEP]), wall, float(info[kc.J_TOVER]),
                           (model.B, model.H))  # fmt: skip


def effective_restitution(model: CompliantBlock, theta0_over_alpha: float = 0.5,
                          n_impacts: int = 3, t_end: float | None = None) -> float:  # fmt: skip
    """Mean r_eff over the first ``n_impacts`` impacts of free rocking from theta0 (energy
    relation of the rigid block between successive peaks; module docstring)."""
    al = model.alpha
    t_end = t_end if t_end is not None else 4.0 * (n_impacts + 1) / model.p
    res = simulate_compliant(model, t_end=t_end, theta0_over_alpha=theta0_over_alpha,
                             dt_out=min(DT_OUT, 0.002 / model.p))  # fmt: skip
    pk = np.abs(res.peaks()[:, 1])
    pk = np.r_[theta0_over_alpha * al, pk[pk > PEAK_MIN * al]]
    if pk.size < 2:
        raise RuntimeError("no rocking peaks found: the block did not rock")
    e = np.cos(al - pk) - math.cos(al)
    r = np.sqrt(e[1:] / e[:-1])[:n_impacts]
    return float(np.mean(r))
