"""The uplift boundary: the smallest harmonic amplitude at which an isolator's normal force
reaches zero in steady state, per forcing frequency.

Definition. Under ``u''_hor = A sin(2 pi f t)`` (or a harmonic force ``A sin(2 pi f t +
phase)`` on ``load``'s dofs) let ``x*(f, A)`` be the periodic orbit (period ``T = 1 / f``) of
the bilateral model (every contact held, smooth friction law: :func:`frame_problem`), followed
from the static state in ``A``. Its uplift margin is

    g(f, A) = min_{0 <= t_j <= T} min_k lam_k(t_j; x*(f, A))        [N]

(``orbit_quantities(...)["min_normal_force"]``: the normal forces ``lam_k`` at the orbit's
fixed steps ``t_j``), with ``g(f, 0) = min_k lam_k,static > 0``. The critical amplitude is

    A*(f) = min { A > 0 : g(f, A) = 0 }.

Above ``A*`` the bilateral model pulls an isolator down, i.e. a real isolator lifts off.

Root finding on ``A -> g(f, A)``: the static point ``(0, g0)`` costs nothing; from it and the
first amplitude tried the secant predicts the zero (exact when the orbit scales linearly with
``A``, e.g. while every isolator sticks), aimed ``rtol / 2`` past it; secant steps repeat
(each at most ``GROW_MAX`` times the amplitude) until ``g`` changes sign, then the Illinois
variant of regula falsi shrinks the bracket ``[A_below, A_above]`` to ``rtol A``. Each
evaluation is one shooting solve started from the nearest solved orbit scaled to the new
amplitude, ``x0 = x_ref + (A / A_near) (x0_near - x_ref)`` (exact for a linear system);
if it fails, from that guess carried ``WARMUP_PERIODS`` periods along, then with
``REFINE_FACTOR`` times the steps (if a period could not be integrated), then by the stepped
sweep (whole periods integrated from the last Newton iterate until the Poincare map is
stationary to ``SWEEP_TOL_FACTOR rtol``). An amplitude where all of these fail caps the
search: the next try is halfway back to the last good amplitude (``MAX_RETREATS`` times at
most); the frequency is reported as failed, with that amplitude and the reason, when the
retreats run out or the last good amplitude is within ``rtol`` of the cap. Statuses: "ok",
"no uplift below a_hi", "shooting failed at A=...: reason", "search stopped after
``MAX_EVALS`` evaluations: A* in [...]". The first amplitude at the next frequency is
``FIRST_FACTOR`` times the last ``A*`` (or ``a_lo``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from nsdyn._checks import number
from nsdyn.periodic.bifurcation import STABLE_MARGIN
from nsdyn.periodic.discretisation import REFINE_FACTOR, Discretisation, refined
from nsdyn.periodic.problem import frame_problem
from nsdyn.periodic.protocol import A_HIGHEST
from nsdyn.periodic.shooting import ShootingResult, shoot
from nsdyn.periodic.stability import check_verdict, max_modulus
from nsdyn.periodic.sweeps import WARMUP_PERIODS, steady_state_sweep, warm_start

A_LO = 0.25  # first amplitude tried at the first frequency [m/s² or N]
A_HI = 20.0  # largest amplitude searched [m/s² or N]
RTOL = 1e-3  # relative width of the final bracket on A
GROW_MAX = 4.0  # a secant extrapolation multiplies the amplitude by at most this
FIRST_FACTOR = 0.97  # first amplitude at the next frequency, times the previous A*
MAX_EVALS = 24  # shooting-based evaluations of g per frequency
MAX_RETREATS = 4  # halvings back towards the last good amplitude after a failure
SWEEP_TOL_FACTOR = 0.1  # the stepped sweep's steady-state tolerance, times rtol
SWEEP_PERIODS = 200  # longest stepped sweep [periods]

STATUS_OK = "ok"
STATUS_NO_UPLIFT = "no uplift below a_hi"


@dataclass
class UpliftPoint:
    """The uplift search at one frequency ``f``.

    ``a_crit``: A* (NaN unless ``status`` is ``"ok"``), interpolated in the final bracket
    ``[a_below, a_above]`` whose margins ``g_below > 0 >= g_above`` [N] were computed;
    ``a_below = 0`` is the static state. ``rho_max``: largest Floquet multiplier modulus of the
    orbit at ``a_below`` (stable below 1; NaN at the static state or when the check of a
    growth could not decide, :mod:`nsdyn.periodic.stability`; ``stability_note`` says how
    a growth was checked). ``a_fail``: the smallest
    amplitude at which no orbit was found (NaN if none). ``evaluations``: every
    amplitude tried, ``(A, g or NaN, note)``. ``x0_below`` / ``x0_above``: orbit starts
    (minimal coordinates) at the bracket ends.
    """

    f: float
    a_crit: float
    status: str
    a_below: float
    a_above: float
    g_below: float
    g_above: float
    shootings: int
    sweeps: int
    rho_max: float
    wall_s: float
    a_fail: float = math.nan
    evaluations: list = field(default_factory=list)
    x0_below: np.ndarray | None = field(default=None, repr=False)
    x0_above: np.ndarray | None = field(default=None, repr=False)
    stability_note: str = ""

    @property
    def ok(self) -> bool:
        return self.status == STATUS_OK

    @property
    def stable(self) -> bool | None:
        return None if math.isnan(self.rho_max) else bool(self.rho_max < 1.0 + STABLE_MARGIN)

    def to_dict(self) -> dict:
        def num(v):
            return None if not math.isfinite(v) else float(v)

        return {
            "f_hz": float(self.f),
            "a_crit": num(self.a_crit),
            "status": self.status,
            "a_below": num(self.a_below),
            "a_above": num(self.a_above),
            "min_normal_force_below_N": num(self.g_below),
            "min_normal_force_above_N": num(self.g_above),
            "shootings": int(self.shootings),
            "stepped_sweeps": int(self.sweeps),
            "max_multiplier_below": num(self.rho_max),
            "stable_below": self.stable,
            "stability_note": self.stability_note,
            "a_fail": num(self.a_fail),
            "wall_s": float(self.wall_s),
            "evaluations": [[float(a), num(g), n] for a, g, n in self.evaluations],
        }


@dataclass
class UpliftBoundary:
    """A*(f) over a set of frequencies (see the module text)."""

    points: list[UpliftPoint]
    model: str
    static_force: float  # g(f, 0) = min static normal force [N]
    a_lo: float
    a_hi: float
    rtol: float
    excitation: str = "ground acceleration [m/s²]"

    @property
    def f(self) -> np.ndarray:
        return np.array([p.f for p in self.points])

    @property
    def a_crit(self) -> np.ndarray:
        return np.array([p.a_crit for p in self.points])

    @property
    def status(self) -> list[str]:
        return [p.status for p in self.points]

    @property
    def ok(self) -> np.ndarray:
        return np.array([p.ok for p in self.points], dtype=bool)

    def to_dict(self) -> dict:
        return {
            "model": self.model,
            "excitation": self.excitation,
            "static_min_normal_force_N": self.static_force,
            "a_lo": self.a_lo,
            "a_hi": self.a_hi,
            "rtol": self.rtol,
            "points": [p.to_dict() for p in self.points],
        }


class _Margin:
    """``g(f, A)`` by shooting, warm-started from the nearest solved orbit, counting solves."""

    def __init__(self, base, disc: Discretisation, sweep_tol: float):
        self.base = base
        self.disc = disc
        self.sweep_tol = sweep_tol
        self.shootings = 0
        self.sweeps = 0

    def guess(self, A: float, near: tuple[float, np.ndarray] | None) -> np.ndarray:
        xr = self.base.x_ref
        if near is None or near[0] <= 0.0:
            return xr.copy()
        return xr + (A / near[0]) * (near[1] - xr)

    def __call__(self, f: float, A: float, near) -> tuple[float, object, str]:
        """(g, ShootingResult or None, note) at amplitude ``A``."""
        problem = replace(self.base, amplitude=float(A))
        x = self.guess(A, near)
        whys, integration_failed, last = [], False, x
        tries = [(x, self.disc, ""), (None, self.disc, f"{WARMUP_PERIODS} warm-up periods")]
        k = 0
        while k < len(tries):
            g0, disc, how = tries[k]
            k += 1
            if g0 is None:
                g0 = warm_start(problem, f, x, disc)
            self.shootings += 1
            res = shoot(problem, f, g0, disc=disc)
            if res.converged:
                q = problem.orbit_quantities(f, res.X)
                return float(q["min_normal_force"]), res, how
            if res.message not in whys:
                whys.append(res.message)
            if res.monodromy is None:
                integration_failed = True
            else:
                last = res.x0  # the last Newton iterate: the sweep's start
            if k == len(tries) and integration_failed and disc is self.disc:
                tries.append((x, refined(self.disc), f"{REFINE_FACTOR}x steps per period"))
        why = "; ".join(whys)
        self.sweeps += 1
        sw = steady_state_sweep(
            problem, f, last, tol=self.sweep_tol, max_periods=SWEEP_PERIODS, disc=self.disc
        )
        if sw.steady and sw.monodromy is not None:
            q = problem.orbit_quantities(f, sw.X)
            res = ShootingResult(
                f, sw.x0, True, sw.periods, sw.estimate, sw.monodromy, None, sw.X, sw.n_steps
            )
            return float(q["min_normal_force"]), res, f"stepped sweep ({why})"
        return math.nan, None, f"{why}; stepped sweep: {sw.message}"


def _secant_zero(a0: float, g0: float, a1: float, g1: float) -> float:
    """Zero of the line through (a0, g0), (a1, g1); inf when it does not fall to the right."""
    if g1 >= g0 or a1 == a0:
        return math.inf
    return a1 - g1 * (a1 - a0) / (g1 - g0)


def _search(margin: _Margin, f, a_first, a_hi, rtol, g_static, near) -> UpliftPoint:
    """A* at one frequency (module text); ``near`` is (A, x0) of a solved orbit or None."""
    t0 = time.perf_counter()
    n0, s0 = margin.shootings, margin.sweeps
    x_ref = margin.base.x_ref
    below = [0.0, g_static, x_ref.copy(), None]  # A, g, x0, multipliers
    prev = None  # the good point before `below` (secant)
    above = None  # [A, g, x0]
    cap, cap_note = math.inf, ""  # smallest amplitude at which no orbit was found, and why
    evals: list = []
    retreats = 0
    last_side = 0  # Illinois: which end was replaced last (-1 below, +1 above)
    wb = wa = math.nan  # Illinois: the ends' margins as used by the interpolation
    A = min(max(a_first, 0.0), a_hi)
    status = ""
    while True:
        if len(evals) >= MAX_EVALS:
            top = math.inf if above is None else above[0]
            status = (
                f"search stopped after {MAX_EVALS} evaluations: A* in [{below[0]:.4g}, {top:.4g}]"
            )
            break
        g, res, note = margin(f, A, near)
        evals.append((A, g, note))
        if res is None:
            if A < cap:
                cap, cap_note = A, note
        else:
            near = (A, res.x0)
            side = -1 if g > 0.0 else +1
            if side < 0 and A > below[0]:
                prev, below = below, [A, g, res.x0.copy(), _multipliers(res)]
                wb = g
                if last_side < 0:
                    wa *= 0.5
            elif side > 0 and (above is None or A < above[0]):
                first = above is None
                above = [A, g, res.x0.copy()]
                wa, wb = g, (below[1] if first else wb)
                if last_side > 0:
                    wb *= 0.5
            last_side = side
            if above is not None and (above[0] - below[0] <= rtol * above[0] or g == 0.0):
                status = STATUS_OK
                break
            if above is None and A >= a_hi:
                status = STATUS_NO_UPLIFT
                break
        top = min(cap, math.inf if above is None else above[0])
        if above is None and prev is None:  # only the static point: the first try failed
            A = top
        elif above is None:  # secant extrapolation from the last two points below
            r = _secant_zero(prev[0], prev[1], below[0], below[1])
            A = min(r * (1.0 + 0.5 * rtol), GROW_MAX * below[0], a_hi)
        else:  # Illinois in the bracket, kept rtol / 2 inside its ends
            width = above[0] - below[0]
            step = 0.5 * rtol * above[0]
            A = below[0] + wb * width / (wb - wa)
            A = min(max(A, below[0] + step), above[0] - step)
        if A >= cap:  # no orbit found at or above cap: halfway back to the last good point
            retreats += 1
            if retreats > MAX_RETREATS or top - below[0] <= rtol * top:
                status = f"shooting failed at A={cap:.4g}: {cap_note}"
                break
            A = below[0] + 0.5 * (top - below[0])
    a_crit = math.nan
    if status == STATUS_OK:
        a_crit = (
            above[0]
            if above[1] == 0.0
            else below[0] + below[1] * (above[0] - below[0]) / (below[1] - above[1])
        )
    rho_max, why = math.nan, ""
    if below[3] is not None:  # the verdict on the orbit below A*, a growth checked
        problem = replace(margin.base, amplitude=float(below[0]))
        rho, verdict, why = check_verdict(problem, f, below[2], below[3], margin.disc)
        rho_max = math.nan if verdict is None else max_modulus(rho)
    return UpliftPoint(
        f=float(f),
        a_crit=float(a_crit),
        status=status,
        a_below=float(below[0]),
        a_above=math.inf if above is None else float(above[0]),
        g_below=float(below[1]),
        g_above=math.nan if above is None else float(above[1]),
        shootings=margin.shootings - n0,
        sweeps=margin.sweeps - s0,
        rho_max=float(rho_max),
        wall_s=time.perf_counter() - t0,
        a_fail=float(cap) if math.isfinite(cap) else math.nan,
        evaluations=evals,
        x0_below=below[2],
        x0_above=None if above is None else above[2],
        stability_note=why,
    )


def _multipliers(res) -> np.ndarray | None:
    return res.multipliers if res.monodromy is not None else None


def uplift_boundary(
    system,
    freqs,
    *,
    a_lo: float = A_LO,
    a_hi: float = A_HI,
    rtol: float = RTOL,
    progress=None,
    law: str | None = None,
    load=None,
    disc: Discretisation | None = None,
) -> UpliftBoundary:
    """A*(f) of an isolated ``system`` at each of ``freqs`` [Hz] (module text).

    ``a_lo``: first amplitude tried (later frequencies start from ``FIRST_FACTOR`` times the
    last A*); ``a_hi``: largest amplitude searched (``status`` "no uplift below a_hi" when the
    orbit at ``a_hi`` keeps every normal force positive); ``rtol``: relative width of the final
    bracket. ``law`` (a smooth law, default the system's), ``load`` (a
    :class:`nsdyn.ground.HarmonicForce`: A is then a force [N]) as for :func:`frame_problem`;
    ``disc`` the period's discretisation. ``progress(point, k, n)`` is called after each
    frequency. Failures are reported per frequency in ``status``, never raised.
    """
    freqs = np.asarray(freqs, dtype=float).reshape(-1)
    if freqs.size == 0 or not np.all(np.isfinite(freqs)) or np.any(freqs <= 0):
        raise ValueError(f"freqs: expected positive finite frequencies [Hz], got {freqs!r}")
    a_lo = number("a_lo", a_lo, "a positive finite amplitude", lambda v: v > 0)
    top = A_HIGHEST if load is None else math.inf  # (a ground acceleration: at most 100 g)
    a_hi = number("a_hi", a_hi, f"a finite amplitude above a_lo = {a_lo:g}" + (
        f" and at most {A_HIGHEST:g} m/s² (100 g)" if load is None else ""),
        lambda v: a_lo < v <= top)  # fmt: skip
    rtol = number("rtol", rtol, "a number in (0, 0.5)", lambda v: 0.0 < v < 0.5)
    if progress is not None and not callable(progress):  # (it failed after the first point)
        raise TypeError(f"progress: expected a callable (point, k, n), got "
                        f"{type(progress).__name__}")  # fmt: skip
    if getattr(system, "n_contacts", 0) == 0:
        raise ValueError("the system has no contacts: no normal force can reach zero")
    base = frame_problem(system, a_lo, law=law, load=load)
    disc = disc or Discretisation()
    g_static = _static_margin(base, float(freqs[0]))
    if not g_static > 0.0:
        raise ValueError(f"static normal forces: expected all > 0, the smallest is {g_static:g} N")
    margin = _Margin(base, disc, SWEEP_TOL_FACTOR * rtol)
    points: list[UpliftPoint] = []
    near = None
    a_first = a_lo
    for k, f in enumerate(freqs):
        pt = _search(margin, float(f), a_first, a_hi, rtol, g_static, near)
        points.append(pt)
        if pt.a_below > 0.0:
            near = (pt.a_below, pt.x0_below)
        if pt.ok:
            a_first = FIRST_FACTOR * pt.a_crit
        if progress is not None:
            progress(pt, k + 1, freqs.size)
    exc = "ground acceleration [m/s²]" if load is None else "force [N]"
    return UpliftBoundary(points, system.name, g_static, a_lo, a_hi, rtol, exc)


def _static_margin(problem, f: float) -> float:
    """g(f, 0): the smallest normal force of the unforced static state."""
    zero = replace(problem, amplitude=0.0)
    X = np.vstack([problem.x_ref, problem.x_ref])
    return float(zero.orbit_quantities(f, X)["min_normal_force"])
