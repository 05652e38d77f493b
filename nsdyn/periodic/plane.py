"""Periodic orbits of a deck (or a single mass) on bidirectional isolators under a harmonic orbit.

The ground acceleration of :mod:`nsdyn.ground.orbit` (linear, circular or elliptical),

    a_x = A_x sin ωt,   a_y = A_y sin(ωt + φ_y),   (a_z = A_z sin(k ωt + φ_z), k a whole number)

repeats with T = 2π/ω = 1/f, and a steady response of the deck of
:mod:`nsdyn.models.isolated.deck` starts a period where it ends: x0 = [q, q̇](0) solves

    H(x0) = φ_T(x0) − x0 = 0,

with φ_T the period map. φ_T integrates the deck's own equations over [0, T] with the time loops
of :func:`~nsdyn.models.isolated.deck.simulate_plane` at tight tolerances (``rtol`` 1e-10):
Dormand–Prince with located stick–slip events for the switch law (stick disc), Radau IIA for
the regularised law. The monodromy Φ = ∂φ_T/∂x0 comes from central differences of that map,

    Φ e_j ≈ [φ_T(x0 + δ_j e_j) − φ_T(x0 − δ_j e_j)] / (2 δ_j),   δ_j = FD_REL · a_j,

a_j the orbit's excursion in x0_j's block (displacements, velocities). An adaptive step
sequence makes the computed map non-smooth in x0 at its integration error e ~ rtol · a, so the
difference errs by about e/δ + δ² |φ'''|/6: with δ = rtol^(1/3) a both terms are ~ rtol^(2/3),
a relative error of ~ 5e-7 of Φ's entries (and of the Floquet multipliers, the eigenvalues of
Φ) at rtol = 1e-10. Newton's method converges with this Jacobian (its error only slows the
last iterations). The switch law's stick band |v| <= η adds a noise of its own to an orbit
with stick–slip events, about η / (the orbit's velocity excursion) relative: on slow
stick–slip orbits the default band 1e-5 m/s leaves a noise floor near the shooting tolerance.
Where the orbit switches between stick and slip the map is only piecewise smooth and a
difference straddling a switch is not a derivative: near a stick–slip transition (a slip or
stick phase shrinking to nothing) shooting may fail, and the point then comes from the stepped
sweep (time integration until the map is stationary) with the reason in its note. Such
multipliers can be wrong too, so an orbit they call unstable is checked by the map itself
(:func:`~nsdyn.periodic.stability.check_growth`): a perturbation along the growing direction
is followed GROWTH_PERIODS periods, and the verdict (and the reported |ρ|) is its growth or
decay per period.

A single mass (one isolator, no eccentricity) has a free twist θ̈ = 0 that carries no load: its
state is (x, y, ẋ, ẏ), dim 4; a deck's is [q, q̇], dim 6. A triple friction pendulum adds the
8 internal slips of its series model (regularised law only), the state then being
[q, internal slips, q̇]: the difference steps follow displacements and velocities, while the
shooting residual's two halves (scaled by their own excursions) put half the internal slips
with the velocities.

Shooting, the stepped sweep, sequential and pseudo-arclength continuation in f are those of
:mod:`nsdyn.periodic` (:class:`PlaneProblem` satisfies
:class:`nsdyn.periodic.protocol.PeriodicModel`); the curve's response quantity is the peak
resultant isolator displacement max_t |u_i(t)|, located between the samples on the cubic
Hermite interpolant of (u, v).
"""

from __future__ import annotations

import math

import numpy as np

from nsdyn._checks import RTOL_MIN
from nsdyn.models.isolated import _kplane as kp
from nsdyn.models.isolated import _kplaneradau as krad
from nsdyn.models.isolated import _kplanerun as kr
from nsdyn.models.isolated import deck_compile
from nsdyn.models.isolated.bearings import B_MUS
from nsdyn.models.isolated.deck import PlaneSystem, kernel_params
from nsdyn.models.isolated.defaults import EPS, ETA
from nsdyn.models.isolated.friction import stick_slip_note, stick_velocity, sticks
from nsdyn.models.isolated.tolerances import arctan_atol
from nsdyn.periodic.continuation import continue_range
from nsdyn.periodic.curve import Curve
from nsdyn.periodic.discretisation import Discretisation
from nsdyn.periodic.protocol import (
    A_HIGHEST,
    STATUS_MESSAGES,
    STATUS_OK,
    PeriodMap,
    check_amplitude,
    check_frequency,
    check_map_args,
)
from nsdyn.periodic.stability import check_growth

RTOL = 1e-10  # the period map's relative tolerance
ATOL = 1e-12  # ... absolute [m, m/s] (the regularised law's velocity part capped at 0.1/eps)
FD_REL = RTOL ** (1.0 / 3.0)  # central-difference step / orbit excursion (module text)
FD_FLOOR = 1e-4  # excursion [m, m/s] below which the difference step is taken from this
SAMPLES_MIN = 256  # orbit samples per period at least
MAX_STEPS = 2_000_000  # integration steps per period
EV_ROWS = 20_000  # event rows kept per period (the count is exact)
STATUS_BASE = 100  # the deck loops' status s is reported as STATUS_BASE + s
STATUS_UPLIFT = STATUS_BASE + kr.ST_UPLIFT
STATUS_HELD = STATUS_BASE + 50  # a stuck isolator held outside its disc (outside_disc)
CHECK_SAMPLES = 64  # outputs of a period integrated only for its end (the disc check's)
DISC_SLACK = 1e-6  # relative excess of a stick force over mu_s N taken as a missed release
_WHY = {
    kr.ST_UNDERFLOW: "step size underflow (a stiff regularised law: lower eps)",
    kr.ST_MAX_STEPS: f"more than {MAX_STEPS} steps in one period",
    kr.ST_NONFINITE: "the state became inf/nan",
    kr.ST_SINGULAR: "singular equations of motion",
    kr.ST_UPLIFT: "a normal force reached zero (uplift)",
    kr.ST_CHATTER: "chattering stick-slip events",
    kr.ST_EVENTS: "too many stick-slip events",
    kr.ST_NEWTON: "Radau IIA's Newton iterations diverge (lower eps)",
    kr.ST_STALL: "the steps collapsed (a friction law too sharp for the steps: the switch "
    "law's stick band eta too narrow, or the arctan law's eps too large: raise eta or lower eps)",
}
_WHY[STATUS_HELD - STATUS_BASE] = (
    "a stuck isolator held outside its friction disc (a missed break-away of the time loop)"
)
for _code, _msg in _WHY.items():
    STATUS_MESSAGES.setdefault(STATUS_BASE + _code, f"deck period: {_msg}")
LAWS = ("switch", "arctan")


def orbit_shape(orbit) -> tuple[float, tuple]:
    """(amplitude A, shape) of a harmonic orbit (a :class:`~nsdyn.ground.orbit.HarmonicPlane`
    or an object/dict with ``f, ax, ay, phase_y_deg, az, f_z, phase_z_deg``): A is the largest
    horizontal acceleration max_t |a(t)| (the radius of a circle, the major semi-axis of an
    ellipse, the amplitude along a line): with the phasor P = (A_x, A_y e^{iφ_y}),
    A² = (|P|² + |A_x² + A_y² e^{2iφ_y}|)/2. The shape ``(a_x, a_y, φ_y [rad], a_z, k,
    φ_z [rad])`` holds the amplitudes per unit A and the vertical frequency as the whole
    multiple k of f (a vertical component at another frequency is not periodic with T:
    ValueError)."""

    if isinstance(orbit, dict):  # as the time histories read it (pack_ground)
        from nsdyn.models.isolated.deck import orbit_of

        orbit = orbit_of(orbit)
    elif not hasattr(orbit, "f"):  # ("circular" was "orbit.f: ... got nan")
        raise TypeError(f"orbit: expected a HarmonicPlane or a dict of f, ax, ay, ..., got "
                        f"{type(orbit).__name__}")  # fmt: skip

    def get(name, default=0.0):
        v = getattr(orbit, name, default)
        return default if v is None else float(v)

    f = get("f", math.nan)
    if not (math.isfinite(f) and f > 0):
        raise ValueError(f"orbit.f: expected a frequency > 0 [Hz], got {f!r}")
    ax, ay, az = get("ax"), get("ay"), get("az")
    phy = math.radians(get("phase_y_deg"))
    e2 = complex(math.cos(2 * phy), math.sin(2 * phy))
    A = math.sqrt(0.5 * (ax * ax + ay * ay + abs(ax * ax + ay * ay * e2)))
    if not (math.isfinite(A) and A > 0 and ax >= 0 and ay >= 0 and az >= 0):
        raise ValueError(f"orbit: expected horizontal amplitudes >= 0, not both zero, got "
                         f"{ax!r}, {ay!r}")  # fmt: skip
    k = 1.0
    if az > 0:
        k = get("f_z", f) / f
        if abs(k - round(k)) > 1e-9 * k or round(k) < 1:
            raise ValueError(f"orbit.f_z: a vertical component at {get('f_z', f):g} Hz is not "
                             f"periodic with the horizontal period 1/{f:g} s; expected a whole "
                             "multiple of f")  # fmt: skip
        k = float(round(k))
    shape = (ax / A, ay / A, phy, az / A, k,
             math.radians(get("phase_z_deg")))  # fmt: skip
    return A, shape


class PlaneProblem:
    """The :class:`~nsdyn.periodic.protocol.PeriodicModel` of a deck under ``amplitude``
    times an orbit ``shape`` (:func:`orbit_shape`) at any frequency (module text)."""

    exact_map = True  # the flow integrated to a tolerance, not a fixed-step discretisation

    def __init__(self, system: PlaneSystem, amplitude: float, shape: tuple, *,
                 law: str = "switch", eps: float = EPS, eta: float = ETA,
                 rtol: float = RTOL, atol: float = ATOL) -> None:  # fmt: skip
        if getattr(system, "has_tfp", False) and law != "arctan":
            raise ValueError(
                "law: a triple friction pendulum runs with the regularised law 'arctan' (its "
                f"series model has no stick events), got {law!r}"
            )
        if law not in LAWS:
            raise ValueError(f"law: expected one of {list(LAWS)}, got {law!r}")
        if not (math.isfinite(rtol) and RTOL_MIN <= rtol < 1e-3):
            raise ValueError(f"rtol: expected a number in [{RTOL_MIN:.2g}, 1e-3), got {rtol!r}")
        self.system, self.law, self.eps, self.eta = system, law, float(eps), float(eta)
        self.amplitude = check_amplitude(amplitude, highest=A_HIGHEST)  # [m/s²]
        self.shape = tuple(float(s) for s in shape)
        self.params = kernel_params(system, law, self.eps, self.eta, None)
        self.loop = krad.integrate if law == "arctan" else kr.integrate
        self.rtol = float(rtol)
        self.atol = arctan_atol(atol, self.eps) if law == "arctan" else (float(atol),) * 2
        ex, ey = (float(e) for e in system.ecc)
        self.twist = system.n_isolators > 1 or ex != 0.0 or ey != 0.0
        self.n_states = int(getattr(system, "n_states", 6))
        q, v = ([0, 1, 2], [3, 4, 5]) if self.twist else ([0, 1], [3, 4])
        self.rows = np.array(q + list(range(6, self.n_states)) + v)  # [q, internal slips, q̇]
        self.velocity = np.isin(self.rows, v)  # the velocity entries of the state
        self.x_ref = np.zeros(self.rows.size)
        self.name = system.name

    @property
    def dim(self) -> int:
        return self.rows.size

    # ---- the period map ------------------------------------------------------------------
    def ground(self, f: float) -> np.ndarray:
        """The kernels' harmonic ground parameters at ``f``."""
        ax, ay, phy, az, k, phz = self.shape
        gp = np.zeros(kp.N_GP)
        gp[kp.GP_DT] = 1.0
        gp[kp.GP_F], gp[kp.GP_AX], gp[kp.GP_AY], gp[kp.GP_PHY] = f, ax, ay, phy
        gp[kp.GP_AX] *= self.amplitude
        gp[kp.GP_AY] *= self.amplitude
        gp[kp.GP_AZ], gp[kp.GP_FZ], gp[kp.GP_PHZ] = az * self.amplitude, k * f, phz
        return gp

    def full_state(self, x: np.ndarray) -> np.ndarray:
        """[q, q̇, internal slips] of a state of this problem (the kernels' order)."""
        y = np.zeros(self.n_states)
        y[self.rows] = x
        return y

    def run(self, x0: np.ndarray, f: float, samples: int, full: bool = False):
        """One period from ``x0`` with ``samples + 1`` outputs: (status, X (samples + 1, 6),
        and with ``full`` the kernel outputs (N, friction, restoring, modes, info, stops))."""
        M, pos, bp, nd, sp = self.params
        ni = pos.shape[0]
        T = 1.0 / f
        gp = self.ground(f)
        hmax = T / (20.0 * max(1.0, self.shape[4]))
        cfg = np.array([self.rtol, self.atol[0], self.atol[1], min(1e-4, hmax), hmax,
                        float(MAX_STEPS)])  # fmt: skip
        t_eval = np.linspace(0.0, T, samples + 1)
        nt = t_eval.size
        X = np.full((nt, self.n_states), np.nan)
        NO = np.full((nt, ni), np.nan)
        FF, FR, FO = (np.full((nt, ni, 2), np.nan) for _ in range(3))
        MO = np.zeros((nt, ni), dtype=np.int64)
        EV = np.zeros((EV_ROWS if full else 16, 6))
        stops = np.zeros((ni, 3))
        stops[:, kr.P_TFIRST] = np.nan
        info = np.zeros(kr.N_INFO)
        args = (self.full_state(x0), t_eval, np.full(ni, kp.MODE_SLIP, dtype=np.int64),
                np.zeros((ni, 2)), M, pos, bp, nd, sp, kp.G_HARMONIC, gp, np.zeros((3, 0)), cfg,
                X, NO, FF, FR, FO, MO, EV, stops, info)  # fmt: skip
        st = deck_compile.run_loop(self.loop, args, self.law == "switch")
        st = STATUS_OK if int(st) == kr.ST_OK else STATUS_BASE + int(st)
        if st == STATUS_OK and not np.all(np.isfinite(X[-1])):
            st = STATUS_BASE + kr.ST_NONFINITE
        if st == STATUS_OK and self.law == "switch" and self.outside_disc(NO, FF, MO):
            st = STATUS_HELD
        return st, X, ((NO, FF, FR, MO, info, stops) if full else None)

    def fd_step(self) -> float:
        """Relative central-difference step rtol^(1/3) (module text)."""
        return self.rtol ** (1.0 / 3.0)

    def outside_disc(self, NO: np.ndarray, FF: np.ndarray, MO: np.ndarray) -> bool:
        """True when an output holds a stuck isolator whose stick force lies outside its disc
        |τ| <= μ_s N (by more than DISC_SLACK): a break-away the time loop did not locate (its
        switching function already <= 0 where it restarted), which would make the period
        garbage. Checked at the outputs only."""
        bp = self.params[2]
        for i in range(NO.shape[1]):
            k = np.flatnonzero(MO[:, i] == kp.MODE_STICK)
            if not k.size:
                continue
            lim = np.array([bp[i, B_MUS] * kp.pressure_factor(bp, i, float(n)) * n
                            for n in NO[k, i]])  # fmt: skip
            if np.any(np.hypot(FF[k, i, 0], FF[k, i, 1]) > lim * (1.0 + DISC_SLACK)):
                return True
        return False

    def samples(self, f: float, n_steps: int | None, disc: Discretisation | None) -> int:
        """Orbit samples per period: ``n_steps``, else the discretisation's step count (the
        integration itself is adaptive), at least SAMPLES_MIN."""
        if n_steps is None:
            n_steps = (disc or Discretisation()).steps(1.0 / f)
        return max(int(n_steps), SAMPLES_MIN)

    def period_map(self, x0, f, *, n_steps=None, disc=None, sens=True, store=False) -> PeriodMap:
        """One period ``T = 1/f`` from ``x0`` (protocol of
        :class:`~nsdyn.periodic.protocol.PeriodicModel`); the monodromy by central differences
        (module text), ``dxdT`` None (continuation differentiates the map in T)."""
        f = check_frequency(f)
        x0 = check_map_args(self.x_ref, x0, n_steps, disc)
        n = self.samples(f, n_steps, disc)
        st, X, _ = self.run(x0, f, n if (store or sens) else CHECK_SAMPLES)
        Xs = X[:, self.rows]
        if st != STATUS_OK:
            return PeriodMap(x0.copy(), None, None, None, st, n, 1, 0)
        Phi = None
        runs = 1
        if sens:
            d = self.dim
            vel = self.velocity
            exc = np.abs(Xs - Xs[0]).max(axis=0)  # (the orbit's excursion per entry)
            amp = np.where(vel, max(exc[vel].max(), FD_FLOOR),
                           max(exc[~vel].max(), FD_FLOOR))  # fmt: skip
            rel = self.fd_step()
            Phi = np.empty((d, d))
            for j in range(d):
                dj = rel * amp[j]
                ends = []
                for s in (1.0, -1.0):
                    xp = x0.copy()
                    xp[j] += s * dj
                    stp, Xp, _ = self.run(xp, f, CHECK_SAMPLES)
                    runs += 1
                    if stp != STATUS_OK:
                        return PeriodMap(Xs[-1].copy(), None, None, None, stp, n, runs, 0)
                    ends.append(Xp[-1, self.rows])
                Phi[:, j] = (ends[0] - ends[1]) / (2.0 * dj)
        return PeriodMap(Xs[-1].copy(), Phi, None, Xs if store else None, STATUS_OK, n, runs, 0)

    # ---- what a point reports --------------------------------------------------------------
    def frozen_rows(self, pm: PeriodMap):
        """The displacement rows when the switch law's orbit sticks all period (any start
        inside the disc is an orbit: multipliers 1, held at the guess by shooting)."""
        if self.law != "switch" or pm.X is None:
            return None
        if np.abs(pm.X[:, self.velocity]).max() > self.eta:
            return None
        return np.eye(self.dim)[~self.velocity]

    def orbit_quantities(self, f: float, X: np.ndarray) -> dict:
        """Peak resultant isolator displacement (``u_peak_m``, max over isolators and time;
        ``u_peak_isolator`` the isolator reaching it), peak component, peak resultant
        friction, peak torsion, least normal force, stick fraction and events per period of
        the orbit from ``X[0]`` (integrated once more with its forces)."""
        n = X.shape[0] - 1
        st, Y, out = self.run(np.asarray(X[0], dtype=float), f, n, full=True)
        if st != STATUS_OK:
            q, _ = self.quantities_without_orbit(f, X[0])
            return q
        NO, FF, FR, MO, info, stops = out
        pos = self.system.positions
        u = _slip(Y[:, :3], pos)
        v = _slip(Y[:, 3:], pos)
        h = 1.0 / (f * n)
        peaks = [hermite_peak(u[:, i], v[:, i], h) for i in range(pos.shape[0])]
        speed = np.hypot(v[..., 0], v[..., 1])
        modes = MO if self.law == "switch" else None
        stick = sticks(speed, self.law, eps=self.eps, eta=self.eta, modes=modes)
        if getattr(self.system, "has_tfp", False):  # a TFP sticks when no surface slides
            from nsdyn.models.isolated.tfp import surfaces_stuck

            t = np.linspace(0.0, 1.0 / f, n + 1)
            v_stick = stick_velocity(self.law, self.eps, self.eta)
            stick = surfaces_stuck(Y, t, self.system.internal_offsets(), v_stick, stick)
        return {
            "u_peak_m": float(max(peaks)),
            "u_peak_isolator": int(np.argmax(peaks)),
            "u_component_peak_m": component_peak(u, v, h),
            "friction_peak_N": float(np.hypot(FF[..., 0], FF[..., 1]).max()),
            "restoring_peak_N": float(np.hypot(FR[..., 0], FR[..., 1]).max()),
            "torsion_peak_rad": float(np.abs(Y[:, 2]).max()),
            "normal_min_N": float(NO.min()),
            "stick_fraction": float(stick[:-1].mean()),
            "events_per_period": int(info[kr.I_NEV]),
            "rim_contact": bool(np.any(np.isfinite(stops[:, kr.P_TFIRST]))),
            "uplift": False,
        }

    def quantities_without_orbit(
        self, f: float, x0: np.ndarray, periods: int = 1
    ) -> tuple[dict, str]:
        """NaN quantities of a point whose period could not be integrated, and why (the
        ``periods`` periods from ``x0``: uplift, or the loop's failure)."""
        if periods < 1:
            raise ValueError(f"periods: expected an integer >= 1, got {periods!r}")
        x = np.asarray(x0, dtype=float)
        for _ in range(periods):  # the forcing is T-periodic: each period from the last state
            st, X, _ = self.run(x, f, 1)
            if st != STATUS_OK:
                break
            x = X[-1, self.rows]  # the problem's state (as the period map's end)
        nan = math.nan
        q = {"u_peak_m": nan, "u_component_peak_m": nan, "friction_peak_N": nan,
             "restoring_peak_N": nan, "torsion_peak_rad": nan, "normal_min_N": nan,
             "stick_fraction": nan, "events_per_period": None, "rim_contact": None,
             "uplift": st == STATUS_UPLIFT}  # fmt: skip
        why = "" if st == STATUS_OK else STATUS_MESSAGES.get(st, f"status {st}")
        return q, why

    def validity_note(self, q: dict) -> str:
        """Remarks on a point outside the model's validity or near a stick–slip transition."""
        notes = []
        if q.get("uplift"):
            notes.append("uplift: a normal force reaches zero in the period")
        if q.get("rim_contact"):
            notes.append("an isolator reaches its displacement capacity (rim stop)")
        stick_slip = stick_slip_note(q.get("stick_fraction"), self.law, self.eps)
        return "; ".join(notes + [stick_slip] * bool(stick_slip))


def _slip(Q: np.ndarray, pos: np.ndarray) -> np.ndarray:
    """Isolator slips (or slip velocities) (nt, ni, 2) of deck states ``Q`` (nt, 3)."""
    out = np.empty((Q.shape[0], pos.shape[0], 2))
    out[:, :, 0] = Q[:, [0]] - Q[:, [2]] * pos[:, 1]
    out[:, :, 1] = Q[:, [1]] + Q[:, [2]] * pos[:, 0]
    return out


def hermite_peak(u: np.ndarray, v: np.ndarray, h: float) -> float:
    """max_t |u(t)| of a plane trajectory sampled at spacing ``h`` (``u``, ``v``: (n, 2)
    positions and velocities), refined between the samples next to the largest sample on the
    cubic Hermite interpolant of each component (error ~ h⁴ |u''''| / 384)."""
    r = np.hypot(u[:, 0], u[:, 1])
    k = int(np.argmax(r))
    best = float(r[k])
    s = np.linspace(0.0, 1.0, 65)
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
    h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
    for a in (k - 1, k):
        if a < 0 or a + 1 >= r.size:
            continue
        p = (h00[:, None] * u[a] + h10[:, None] * h * v[a] + h01[:, None] * u[a + 1]
             + h11[:, None] * h * v[a + 1])  # fmt: skip
        best = max(best, float(np.hypot(p[:, 0], p[:, 1]).max()))
    return best


def component_peak(u: np.ndarray, v: np.ndarray, h: float) -> float:
    """max over isolators and directions of max_t |u_c(t)|, refined as :func:`hermite_peak`
    (``u``, ``v``: (n, n_iso, 2)): a slip along x alone has its resultant's peak."""
    zero = np.zeros(u.shape[0])
    return max(
        hermite_peak(np.c_[u[:, i, c], zero], np.c_[v[:, i, c], zero], h)
        for i in range(u.shape[1])
        for c in range(2)
    )


def plane_problem(system: PlaneSystem, orbit, *, amplitude: float | None = None,
                  **options) -> PlaneProblem:  # fmt: skip
    """The periodic problem of ``system`` under the harmonic ``orbit`` (its shape; its
    amplitude unless ``amplitude`` [m/s²] is given; its frequency is the continuation's).
    ``options``: law, eps, eta, rtol, atol of :class:`PlaneProblem`."""
    if not isinstance(system, PlaneSystem):
        raise TypeError(f"system: expected a PlaneSystem (sdof_plane, rigid_deck or "
                        f"building_deck), got {type(system).__name__}")  # fmt: skip
    A, shape = orbit_shape(orbit)
    return PlaneProblem(system, A if amplitude is None else amplitude, shape, **options)


def plane_response(problem: PlaneProblem, **options) -> Curve:
    """Periodic orbits of ``problem`` continued in f (``options``: fmin, fmax, points,
    continuation "sequential" | "arclength", fallback, progress, start, x0, ... of
    :func:`nsdyn.periodic.continuation.continue_range`). An "unstable" point is checked by
    :func:`~nsdyn.periodic.stability.check_growth`. The curve's ``info["failures"]`` lists the
    frequencies where shooting failed, with the reason (:func:`nsdyn.periodic.curve.failures`)."""
    user = options.get("progress")

    def progress(pt, k, n):
        check_growth(problem, pt)
        if user is not None:
            user(pt, k, n)

    options["progress"] = progress
    curve = continue_range(problem, **options)
    curve.info.update({"model": problem.name, "law": problem.law})
    return curve


def curve_rows(curve: Curve) -> list[dict]:
    """One flat record per point (the deck sweep's CSV; a point without a steady state
    without its response, as :meth:`Curve.rows`)."""
    rows = []
    for p in curve.points:
        q = (
            p.quantities
            if p.converged
            else {k: p.quantities.get(k, "") for k in ("uplift", "rim_contact")}
        )  # fmt: skip  (what ended the transient: said)
        rows.append({
            "f": p.f, "A": curve.amplitude, "u_peak_m": q.get("u_peak_m", math.nan),
            "u_component_peak_m": q.get("u_component_peak_m", math.nan),
            "friction_peak_N": q.get("friction_peak_N", math.nan),
            "torsion_peak_rad": q.get("torsion_peak_rad", math.nan),
            "normal_min_N": q.get("normal_min_N", math.nan),
            "stick_fraction": q.get("stick_fraction", math.nan),
            "events_per_period": q.get("events_per_period", ""),
            "stable": "" if p.stable is None else p.stable,
            "max_multiplier_modulus": p.max_multiplier if p.converged else math.nan,
            "method": p.method,
            "newton_iterations": p.iterations, "residual": p.residual,
            "converged": p.converged, "samples": p.n_steps, "uplift": q.get("uplift", ""),
            "rim_contact": q.get("rim_contact", ""), "note": p.note,
            "u_peak_isolator": q.get("u_peak_isolator"),  # (not a CSV column)
        })  # fmt: skip
    return rows
