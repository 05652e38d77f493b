"""Time histories of the cylinder under three-component ground acceleration.

Runs the ``_kernel`` integrator (state: base height w, unit quaternion q, ẇ, world ω and, with
base friction, the slip u of the base centre) from static equilibrium w = −mg/(πr²k), or the
fixed-base case (body = ground, no integration), and returns a :class:`CylinderResult` with the
derived responses: tilt θ = arccos(e₃·e_z) and its azimuth, contact fraction A/πr², lifted rim
height w + r sin θ, base shear m a_c,h, overturning moment, slip, and the energy balance
E_mech(t) − E_mech(0) = W_ground − E_damped − E_friction.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from nsdyn._checks import (
    MAX_OUTPUTS,
    AccuracyWarning,
    NumericalFailure,
    expect,
    finite_numbers,
    non_negative_int,
    number,
    rel_tol,
    whole,
)
from nsdyn._tabular import Tabular
from nsdyn.ground import GroundMotion, modulated_white_noise
from nsdyn.models.cylinder import _kernel as K
from nsdyn.models.cylinder.cylinder_compile import run_integrate
from nsdyn.models.cylinder.design import static_settlement, too_soft
from nsdyn.models.cylinder.params import G_STD, CylinderParams
from nsdyn.models.tilt import final_tilt, initial_tilt

RTOL = 1e-7  # default relative tolerance of the step-size controller
# E_mech sums T, m g z and the foundation's energy, each rounded, and the balance differences
# it and adds the ground's work and the dissipation: a few ulps of E_mech are round-off, not
# the run's accuracy. The closure's scale is at least this many: 10 ulps read ENERGY_WARN
ROUNDOFF_ULPS = 1000
ENERGY_WARN = 1e-2  # energy closure above which a run warns (and above 1000 rtol; a run
# closes to about 20 rtol, tests/models/cylinder)
ENERGY_WARN_MAX = 0.1  # and above this whatever rtol (at rtol 0.1 a tilt 24x too large, 1.6)
H_KINK = 1e-5  # [s] steps crossing a contact-kind change are bisected to this length
H_MIN = 1e-12  # [s] smallest step before giving up
MAX_STEPS = 20_000_000  # step budget of one run
THETA_TOPPLE = math.pi / 4  # stop criterion of the source study: tilt beyond 45°
EQ_DURATION = 20.0  # [s] default length of a simulated earthquake
EQ_DT = 0.01  # [s] output step of a simulated earthquake

S0_UNITS = {"g2s": G_STD, "m2s3": 1.0}  # amplitude factor of the white-noise intensity

_STATUS = {1: "step size underflow", 2: "non-finite state", 4: "step budget exhausted"}


class SimulationError(NumericalFailure):
    """The integrator failed; the message gives the time and the reason."""


@dataclass(repr=False, eq=False)
class CylinderResult(Tabular):
    """Histories at the sample times (n,) of the ground record; world axes throughout."""

    params: CylinderParams
    t: np.ndarray
    ag: np.ndarray  # (n, 3) ground acceleration
    w: np.ndarray  # base-centre height above the undeformed ground
    q: np.ndarray  # (n, 4) unit quaternion
    wd: np.ndarray
    omega: np.ndarray  # (n, 3)
    wdd: np.ndarray
    omega_dot: np.ndarray  # (n, 3)
    F: np.ndarray  # vertical foundation force
    M: np.ndarray  # (n, 2) horizontal foundation moment about the base centre
    area: np.ndarray  # contact area
    E_mech: np.ndarray
    E_in: np.ndarray
    E_d: np.ndarray
    u: np.ndarray  # (n, 2) slip of the base centre relative to the ground
    ud: np.ndarray  # (n, 2) slip velocity
    udd: np.ndarray  # (n, 2) slip acceleration
    f_base: np.ndarray  # (n, 2) horizontal base force on the body (restraint or friction)
    E_f: np.ndarray  # energy dissipated by base friction
    toppled_at: float | None = None
    stats: dict = field(default_factory=dict)

    @property
    def R(self) -> np.ndarray:
        """(n, 3, 3) rotation matrices."""
        return rotation_matrices(self.q)

    @property
    def e3(self) -> np.ndarray:
        """(n, 3) body axis."""
        return self.R[:, :, 2]

    @property
    def tilt(self) -> np.ndarray:
        """Tilt θ [rad] of the axis from the vertical."""
        e3 = self.e3
        return np.arctan2(np.hypot(e3[:, 0], e3[:, 1]), e3[:, 2])

    @property
    def tilt_dir(self) -> np.ndarray:
        """Azimuth [rad] of the direction the axis leans to (x → y)."""
        e3 = self.e3
        return np.arctan2(e3[:, 1], e3[:, 0])

    @property
    def contact_fraction(self) -> np.ndarray:
        return self.area / self.params.area

    @property
    def rim_lift(self) -> np.ndarray:
        """Height of the highest base-rim point above the undeformed ground [m]."""
        return self.w + self.params.r * np.sin(self.tilt)

    @property
    def a_cm(self) -> np.ndarray:
        """(n, 3) absolute acceleration of the centre of mass."""
        return point_acceleration(self, self.params.H)

    @property
    def base_shear(self) -> np.ndarray:
        """(n, 2) horizontal force of the base restraint on the body, m a_c,h."""
        return self.params.m * self.a_cm[:, :2]

    @property
    def overturning(self) -> np.ndarray:
        """|M|: overturning moment of the foundation about the base centre [N m]."""
        return np.hypot(self.M[:, 0], self.M[:, 1])

    @property
    def slip(self) -> np.ndarray:
        """|u|: horizontal slip of the base centre from its initial place on the ground [m]."""
        return np.hypot(self.u[:, 0], self.u[:, 1])

    @property
    def kinetic(self) -> np.ndarray:
        """T [J]: the kinetic energy relative to the ground (the part of ``E_mech`` that
        moves: ½ m |v_c|² + ½ ωᵀ J ω, v_c the centre of mass's velocity on the ground)."""
        p, e3, om = self.params, self.e3, self.omega
        v = np.cross(om, p.H * e3)
        v[:, :2] += self.ud
        v[:, 2] += self.wd
        Jom = p.It * om + (p.Ia - p.It) * e3 * np.sum(e3 * om, axis=1)[:, None]
        return 0.5 * p.m * np.sum(v * v, axis=1) + 0.5 * np.sum(om * Jom, axis=1)

    @property
    def energy_error(self) -> float:
        """max |E_mech − E_mech(0) − W_in + E_d + E_f| / max(W_in, E_d + E_f, T, 1e3 eps |E|):
        the balance's residual against the largest energy the run moves (the ground's work, the
        dissipated energy, or the kinetic energy T, which free vibration exchanges), at least
        the round-off of the body's own energy E_mech, ROUNDOFF_ULPS of it (a body at rest
        moves none: its residual of 5e-30 J over a kinetic energy of 4e-35 J read 1e5; one
        released at 1e-9 alpha moves 2e-16 J, and 1 ulp of its 39 J read 0.84, with a warning)."""
        res = self.E_mech - self.E_mech[0] - self.E_in + self.E_d + self.E_f
        ulps = ROUNDOFF_ULPS * np.finfo(float).eps * np.max(np.abs(self.E_mech))
        scale = max(np.max(np.abs(self.E_in)), np.max(self.E_d + self.E_f),
                    np.max(self.kinetic), ulps, 1e-300)  # fmt: skip
        return float(np.max(np.abs(res)) / scale)

    def end_tilt(self) -> dict:
        """``final_tilt_rad``, its rate ``final_tilt_rate_rad_per_s`` (a backward difference
        over the last samples) and ``past_tip_over_at_end``: past alpha = atan(r / H), leaning
        further (:func:`nsdyn.models.tilt.final_tilt`)."""
        rate = (
            [(self.tilt[-1] - self.tilt[-2]) / (self.t[-1] - self.t[-2])] if self.t.size > 1 else []
        )
        alpha = math.atan2(self.params.r, self.params.H)
        names = ("final_tilt_rad", "final_tilt_rate_rad_per_s")
        return final_tilt(self.tilt, rate, alpha, self.toppled_at is not None, names)

    def summary(self) -> dict:
        """Peaks of the run, the unit in each name (``_rad``, ``_m``, ``_N``, ``_Nm``, ``_J``,
        ``_s``); the time of toppling is None when it stood."""
        fixed = self.params.foundation == "fixed"
        return {
            "foundation": self.params.foundation,
            "max_tilt_rad": float(self.tilt.max()),
            "max_uplift_ratio": float(1.0 - self.contact_fraction.min()),
            "max_rim_lift_m": float(max(self.rim_lift.max(), 0.0)),
            "max_base_shear_N": float(np.hypot(*self.base_shear.T).max()),
            "max_overturning_Nm": float(self.overturning.max()),
            "max_slip_m": float(self.slip.max()),
            "final_slip_m": float(self.slip[-1]),
            "dissipated_dampers_J": float(self.E_d[-1]),
            "dissipated_friction_J": float(self.E_f[-1]),
            "energy_error": 0.0 if fixed else self.energy_error,
            "toppled": self.toppled_at is not None,
            "t_topple_s": self.toppled_at,
            **self.end_tilt(),
            "t_end_s": float(self.t[-1]),
            "n_steps": int(self.stats.get("accepted", 0)),
            "wall_s": float(self.stats.get("wall_s", 0.0)),
        }

    def histories(self) -> dict:
        """The state, the foundation resultants, the energies and the derived responses on the
        record's samples, world axes, units in the names (quaternion and fractions unitless)."""
        return {
            "ag_{}_m_per_s2": self.ag, "w_m": self.w, "q_{}": self.q, "wd_m_per_s": self.wd,
            "omega_{}_rad_per_s": self.omega, "F_N": self.F, "M_{}_Nm": self.M,
            "area_m2": self.area, "contact_fraction": self.contact_fraction,
            "tilt_rad": self.tilt, "tilt_dir_rad": self.tilt_dir, "rim_lift_m": self.rim_lift,
            "u_{}_m": self.u, "ud_{}_m_per_s": self.ud, "f_base_{}_N": self.f_base,
            "E_mech_J": self.E_mech, "E_in_J": self.E_in, "E_d_J": self.E_d, "E_f_J": self.E_f,
        }  # fmt: skip


def rotation_matrices(q: np.ndarray) -> np.ndarray:
    """(n, 3, 3) rotation matrices of unit quaternions q (n, 4) = (w, x, y, z)."""
    q = np.asarray(q, float)
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=1,
    )


def tilt_quaternion(theta: float, azimuth: float) -> np.ndarray:
    """Quaternion leaning the axis by θ towards azimuth (rotation about e_z × lean direction)."""
    ax = np.array([-math.sin(azimuth), math.cos(azimuth), 0.0])
    return np.r_[math.cos(theta / 2), math.sin(theta / 2) * ax]


def point_acceleration(res: CylinderResult, z_body: float) -> np.ndarray:
    """(n, 3) absolute acceleration of the axis point at body height ``z_body`` above the base."""
    rho = z_body * res.e3
    om, al = res.omega, res.omega_dot
    cen = np.cross(om, np.cross(om, rho))
    a = res.ag + np.cross(al, rho) + cen
    a[:, :2] += res.udd
    a[:, 2] += res.wdd
    return a


def simulate(
    p: CylinderParams,
    ag: np.ndarray,
    dt: float,
    *,
    t0: float = 0.0,
    rtol: float = RTOL,
    theta0: float | None = None,
    theta0_over_alpha: float | None = None,
    azimuth0: float = 0.0,
    omega0: tuple[float, float, float] = (0.0, 0.0, 0.0),
    w0: float | None = None,
    h_kink: float = H_KINK,
    theta_topple: float = THETA_TOPPLE,
    max_steps: int = MAX_STEPS,
    t_end: float | None = None,
) -> CylinderResult:
    """Response to ground acceleration ``ag`` (n, 3) = (a_x, a_y, a_z) sampled every ``dt``
    (``t_end``: run to this time on the record's clock, whose first sample is at ``t0``: the
    record cut there or the ground at rest after its end, as the other families' ``t_end``;
    ``ag`` None with it: the ground at rest throughout).

    Starts at rest in static equilibrium (or tilted by ``theta0`` [rad], or by
    ``theta0_over_alpha`` times alpha = atan(r / H), towards ``azimuth0`` [rad], angular
    velocity ``omega0`` [rad/s]). A tilted body is placed on the foundation: its base centre
    at the height where the foundation carries its weight at that tilt
    (:func:`nsdyn.models.cylinder.foundation.static_moment_tilt`), unless ``w0`` [m] gives
    it. A tilt at or past ``theta_topple`` is refused (the run would stop at once), as is a
    start other than at rest upright on a fixed base. Raises :class:`SimulationError` on
    failure.
    """
    expect("p", p, isinstance(p, CylinderParams), "CylinderParams (nsdyn.CylinderParams(...))")
    theta0 = initial_tilt(theta0, theta0_over_alpha, math.atan2(p.r, p.H))
    if hasattr(ag, "ax"):  # a three-component record object
        raise TypeError(
            f"ag: expected an (n, 3) array of (a_x, a_y, a_z) [m/s²], got a "
            f"{type(ag).__name__}; its as_arrays() gives (t0, dt, ax, ay, az) to stack"
        )
    dt = number("dt", dt, "a positive step [s]", lambda v: v > 0)
    t0 = number("t0", t0, "a finite start time [s]")  # (NaN: no step, a "result" of rest)
    if t_end is not None:  # (a free rocking: no record; t_end was "simulate() got an ...")
        number("t_end", t_end, f"an end on the record's clock at least one step ({dt:g} s) "
               f"after t0 = {t0:g} s", lambda v: v - t0 >= dt * (1 - 1e-9))  # fmt: skip
        n_end = int(math.floor((t_end - t0) / dt + 1e-9)) + 1  # (the sample at or before it)
        if (t_end - t0) / dt > MAX_OUTPUTS:  # (1e9 s allocated its ground table; as a scene's)
            raise ValueError(f"t_end: {(t_end - t0) / dt:.3g} samples of {dt:g} s exceed "
                             f"{MAX_OUTPUTS:.0e}; expected an earlier end")  # fmt: skip
        ag = np.zeros((max(n_end, 2), 3)) if ag is None else ag
        ag = np.ascontiguousarray(ag, dtype=float)
        if ag.ndim == 2 and ag.shape[0] >= 2:
            ag = np.vstack([ag, np.zeros((max(n_end - ag.shape[0], 0), ag.shape[1]))])[:n_end]
    if ag is None:
        raise ValueError("ag: expected an (n, 3) array of (a_x, a_y, a_z) [m/s²], got None; "
                         "with t_end, None runs the ground at rest")  # fmt: skip
    try:  # (a record's name: "could not convert string to float", naming no argument)
        ag = np.ascontiguousarray(ag, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"ag: expected an (n, 3) array of (a_x, a_y, a_z) [m/s²], got "
                         f"{type(ag).__name__} {ag!r:.40}") from None  # fmt: skip
    if ag.ndim != 2 or ag.shape[1] != 3 or ag.shape[0] < 2:
        raise ValueError(f"ag: expected shape (n >= 2, 3), got {ag.shape}")
    if not np.all(np.isfinite(ag)):
        raise ValueError("ag: contains non-finite values")
    rel_tol("rtol", rtol)
    number("azimuth0", azimuth0, "a finite azimuth [rad]")
    if w0 is not None:  # (w0 = -100 m: a 1 m body started 100 m inside its foundation)
        number("w0", w0, f"a base-centre height of at least -r = {-p.r:g} m (within the "
               "foundation's reach, as its static settlement must be)",
               lambda v: v >= -p.r)  # fmt: skip
    omega0 = tuple(finite_numbers("omega0", omega0, "three finite rates (wx, wy, wz) [rad/s]", 3))
    number("h_kink", h_kink, "a positive step bound [s]", lambda v: v > 0)
    whole("max_steps", max_steps, 1, "a whole number of steps >= 1")
    number("theta_topple", theta_topple, "a toppling tilt in (0, pi/2) [rad]",
           lambda v: 0 < v < 0.5 * math.pi)  # fmt: skip
    if not abs(theta0) < theta_topple:
        raise ValueError(f"theta0: a tilt of {abs(theta0):.4g} rad is at or past theta_topple "
                         f"= {theta_topple:.4g} rad, where a run stops as toppled; expected a "
                         "smaller tilt")  # fmt: skip
    n = ag.shape[0]
    if p.foundation == "fixed":
        if theta0 != 0.0 or w0 is not None or any(omega0):  # (they were dropped)
            raise ValueError(
                "theta0, w0, omega0: a fixed base holds the body upright at rest "
                "on the ground; expected none of them with foundation 'fixed'"
            )
        return _fixed(p, ag, dt, t0)
    dst = static_settlement(p)
    if too_soft(p):  # (the base 3 m deep, never lifting: a scene refuses it, so does a call)
        raise ValueError(f"k: {too_soft(p)}")
    y0 = np.zeros(K.NY)
    if w0 is None and theta0 != 0.0:  # placed at its tilt: the foundation carries the weight
        from nsdyn.models.cylinder.foundation import static_moment_tilt

        w0 = float(static_moment_tilt(p, np.array([abs(theta0)]))[1][0])
    y0[0] = -dst if w0 is None else float(w0)
    y0[1:5] = tilt_quaternion(theta0, azimuth0)
    y0[6:9] = omega0
    w_v = math.sqrt(p.k * p.area / p.m)  # vertical foundation frequency [rad/s]
    scale = np.array([dst] + [dst / p.r] * 4 + [dst * w_v] + [dst / p.r * w_v] * 3 + [1.0, 1.0]
                     + [dst] * 2 + [dst * w_v] * 2 + [1.0])  # fmt: skip
    atol = rtol * scale
    hist = np.full((n, K.NOUT), np.nan)
    stats = np.zeros(6)
    cos_top = math.cos(theta_topple)
    tic = time.perf_counter()
    status = run_integrate((
        t0, dt, ag, y0.copy(), p.kernel_array(), rtol, atol, h_kink, H_MIN, int(max_steps),
        cos_top, hist, stats, K.workspace(),
    ))  # fmt: skip
    wall = time.perf_counter() - tic
    if status in _STATUS:
        raise SimulationError(f"cylinder integration failed at t = {stats[0]:.6g} s: "
                              f"{_STATUS[status]} (rtol={rtol:g})")  # fmt: skip
    toppled = float(stats[0]) if status == K.TOPPLED else None
    ag_out = ag
    if toppled is not None:  # the histories end at the toppling instant (the last row)
        hist = hist[~np.isnan(hist[:, 0])]
        ag_out = ag[: hist.shape[0]].copy()
        j = hist.shape[0] - 1
        w = (toppled - (t0 + (j - 1) * dt)) / dt
        ag_out[j] = (1.0 - w) * ag[j - 1] + w * ag[j]
    st = {"accepted": int(stats[1]), "rejected": int(stats[2]), "kink_halvings": int(stats[3]),
          "rhs_calls": int(stats[4]), "slip_starts": int(stats[5]), "wall_s": wall}  # fmt: skip
    res = _result(p, hist, ag_out[: hist.shape[0]], toppled, st)
    if res.energy_error > energy_bound(rtol):  # (0.39 was returned unsaid)
        import warnings

        warnings.warn(f"cylinder: the energy balance closes only to {res.energy_error:.2g} of "
                      f"the energy the run moves, far above what rtol = {rtol:g} gives (about "
                      "20 rtol): the run is not accurate; tighten rtol, or check the body's and "
                      "foundation's scales", AccuracyWarning, stacklevel=2)  # fmt: skip
    return res


def energy_bound(rtol: float) -> float:
    """The energy closure above which a run at ``rtol`` warns: ENERGY_WARN, or 1000 rtol, up
    to ENERGY_WARN_MAX (a closure of 1.6 at rtol 0.1 went unsaid under a bound of 100)."""
    return min(max(ENERGY_WARN, 1e3 * rtol), ENERGY_WARN_MAX)


def _result(p, hist, ag, toppled, st) -> CylinderResult:
    ny = K.NY
    y = hist[:, 1 : 1 + ny]
    acc = hist[:, 1 + ny : 7 + ny]
    aux = hist[:, 7 + ny :]
    return CylinderResult(
        params=p,
        t=hist[:, 0],
        ag=ag,
        w=y[:, 0],
        q=y[:, 1:5],
        wd=y[:, 5],
        omega=y[:, 6:9],
        wdd=acc[:, 2],
        omega_dot=acc[:, 3:6],
        F=aux[:, 0],
        M=aux[:, 1:3],
        area=aux[:, 3],
        E_mech=aux[:, 6],
        E_in=y[:, 9],
        E_d=y[:, 10],
        u=y[:, K.IU : K.IU + 2],
        ud=y[:, K.IUD : K.IUD + 2],
        udd=acc[:, 0:2],
        f_base=aux[:, 7:9],
        E_f=y[:, K.IEF],
        toppled_at=toppled,
        stats=st,
    )


def _fixed(p: CylinderParams, ag: np.ndarray, dt: float, t0: float) -> CylinderResult:
    """Rigid ground, body fixed to it: every point accelerates with the ground."""
    n = ag.shape[0]
    z = np.zeros(n)
    z3 = np.zeros((n, 3))
    q = np.zeros((n, 4))
    q[:, 0] = 1.0
    a_up = ag[:, 2] + p.g
    M = np.stack([-p.m * p.H * ag[:, 1], p.m * p.H * ag[:, 0]], axis=1)  # ρ × m(a_g + g e_z)
    z2 = np.zeros((n, 2))
    return CylinderResult(p, t0 + dt * np.arange(n), ag, z, q, z, z3, z, z3, p.m * a_up, M,
                          np.full(n, p.area), z, z, z, z2, z2, z2, p.m * ag[:, :2], z, None,
                          {"wall_s": 0.0})  # fmt: skip


def earthquake(
    seed: int, duration: float = EQ_DURATION, dt: float = EQ_DT, *, s0_units: str = "g2s"
) -> tuple[float, np.ndarray]:
    """(dt, ag (n, 3)): the source study's simulated earthquake, two independent horizontal
    components and a vertical one at 2/3 of their amplitude, from one seed number.

    ``s0_units``: how S0 = 0.000125 is read — ``"g2s"`` (g² s: accelerations in g, scaled by
    9.81; this reproduces the study's tilts and uplift) or ``"m2s3"`` (m²/s³, 9.81× weaker).
    """
    if s0_units not in S0_UNITS:
        raise ValueError(f"s0_units: expected one of {list(S0_UNITS)}, got {s0_units!r}")
    rng = np.random.default_rng(non_negative_int("seed", seed))
    m1 = modulated_white_noise(duration, dt=dt, seed=rng)
    m2 = modulated_white_noise(duration, dt=dt, seed=rng)
    return dt, S0_UNITS[s0_units] * np.stack([m1.a_hor, m2.a_hor, m1.a_ver], axis=1)


def from_motions(
    mx: GroundMotion, my: GroundMotion | None = None, mz: GroundMotion | None = None
) -> tuple[float, np.ndarray]:
    """(dt, ag) from one or two horizontal records and a vertical one (``mz``'s a_hor; without
    it ``mx``'s a_ver, if any), cut to the shortest; the steps must agree."""
    others = {"my": my, "mz": mz}
    for name, m in {"mx": mx, **others}.items():
        ok = m is None and name != "mx" or isinstance(m, GroundMotion)
        expect(name, m, ok, "a GroundMotion (nsdyn.read_motion(path), nsdyn.GroundMotion(...))")
    n = min([mx.n] + [m.n for m in others.values() if m is not None])
    for name, m in others.items():
        if m is not None and abs(m.dt - mx.dt) > 1e-12 * mx.dt:
            raise ValueError(f"{name}.dt: expected the step of mx ({mx.dt}), got {m.dt}")
    ag = np.zeros((n, 3))
    ag[:, 0] = mx.a_hor[:n]
    if my is not None:
        ag[:, 1] = my.a_hor[:n]
    if mz is not None:
        ag[:, 2] = mz.a_hor[:n]
    elif mx.a_ver is not None:
        ag[:, 2] = mx.a_ver[:n]
    return mx.dt, ag
