"""Benchmarks: work-precision of the integrators, the fidelity ladder, stability maps, the
transient speed table and the work-precision of periodic solutions.

``nsdyn bench accuracy | fidelity | stability | speed | periodic | all [--quick] [--out DIR]
[--repeats N]``

The scene of every benchmark is the office-11 frame on friction isolators (K_lam = 5e4 N/m,
c = 1e4 N s/m, mu = 0.03; arctan law with eps = 7500 s/m unless a map varies it). Accuracy,
fidelity and stability use the bundled synthetic records, 20 s windows scaled to a horizontal
PGA of 3 m/s^2 (vertical component kept, as in the default scene); speed uses the default
scene itself and the Kobe records; periodic a harmonic ground acceleration.

Timing
    ``wall_s`` is the integration alone (``TransientResult.wall_s``: JIT compilation or cache
    loading excluded, :func:`nsdyn.integrate.warmup` runs first; response metrics excluded),
    the median of ``repeats`` runs. Runs longer than :data:`LONG_RUN_S` are timed once (column
    ``n_timed``). Speed claims are ratios of timings taken in the same process.

Accuracy (against a reference of the same model and friction law)
    ``err_x``   = max over t and isolators of |x_iso - x_iso^ref| / max |x_iso^ref|, on the
                  record's sample times;
    ``err_idr`` = |IDR_max / IDR_max^ref - 1|.
    The arctan reference is nsdyn ``radau`` at rtol 1e-10 (atol 1e-12 m), checked by
    ``dopri5`` (explicit Runge-Kutta, an unrelated method) at the same tolerances; the switch
    reference is the event-driven method at rtol 1e-10, checked by ``radau`` on the switch law
    with a narrow stick band. The agreement of each pair is written next to the table
    (``accuracy-reference.csv``) and drawn on the chart as the floor below which errors are
    not resolved.

Baseline
    ``scipy-radau`` is :func:`scipy.integrate.solve_ivp` (method "Radau") on a plain-NumPy
    re-implementation of the same equations (:func:`numpy_equations`: arctan law, contact
    forces from the same Baumgarte-stabilised constraint solve, analytic Jacobian), checked
    against the numba kernel to round-off in the tests.

Fidelity (``fidelity.csv``, ``fidelity.png``)
    The ladder rigid, CB-5/10/15/20/50/100, full (435 dofs) under a low-frequency record (the
    white noise low-passed at 2 Hz) and a broadband one (the Kanai-Tajimi record, f95 = 19 Hz),
    all with radau at the transient defaults (what ``nsdyn run`` uses); relative errors of the
    peaks of x_iso, IDR and absolute floor acceleration against the full model, against wall
    time. Why the full model needs those tolerances: :func:`acceleration_roundoff`.

Speed (``speed.csv``, ``speed-table.csv``, ``speed.png``)
    The default scene (:mod:`nsdyn.scene`: office frame, CB-5, isolated, arctan eps 7500, the
    bundled 40 s record at PGA 3 m/s^2, radau at the scene's tolerances, output every dt_out)
    and, when ``shared/records`` is found, the four Kobe 1995 records at the same PGA, first
    40 s. Per record: nsdyn's steps, wall time (median of 2 x ``repeats`` runs, half before and
    half after SciPy's) and errors of the x_iso history and the peak IDR against radau at
    SPEED_REF_RTOL, itself checked against SPEED_CHECK_RTOL; then SciPy Radau on the NumPy
    equations at the loosest rtol of SCIPY_RTOLS (atol scaled with it) whose x_iso error is
    no larger (:func:`scipy_match`), timed once or as the median of 3 when shorter than
    LONG_RUN_S, and the ratio of the two wall times. nsdyn lands its steps on the record's
    samples (the input is piecewise linear); SciPy steps across them: part of the ratio is
    that, not compiled code. Compilation is reported apart (``integrate.warmup`` in this
    process; ``--cold-compile``: with an empty numba cache in a fresh process).

Periodic (``periodic.csv``, ``periodic.png``)
    CB-5 under ``A sin(2 pi f t)`` at the (A, f) cells of PERIODIC_CELLS; each point starts
    from the orbit at the previous frequency of a 150-point log grid (a sequential
    continuation's guess). Shooting (:func:`nsdyn.periodic.shoot`, SDIRK2 / SDIRK3 with a
    multiple of the default steps per period) and the steady-state sweep
    (:func:`nsdyn.periodic.steady_state_sweep`, its tolerance varied, default steps and 4x):
    relative errors of x_bar_iso and the peak IDR against the reference orbit (shooting,
    SDIRK3, 16x steps, its quantities from a densely sampled radau period:
    :func:`dense_orbit_quantities`), checked by 32x steps, against the wall time of a point.

Stability (``stability-*.csv``, ``stability.png``)
    Largest stable fixed step of dopri5 / radau / genalpha / hht / newmark (rigid and CB-5) as
    eps grows and as the Baumgarte alpha grows, scanning dt down by halves from 0.02 s; a cell
    fails if the integrator reports a failure ("flagged:<reason>"), if the benchmark's NaN or
    energy-balance check does ("checked:<reason>": the integrator called it a success), or if
    it lands further than GARBAGE_ERR from the reference ("garbage": nobody flagged it).
    Constraint drift max |R q| with alpha = 0 and 2 pi; cold-start shooting over (f, A).

The charts are drawn by :mod:`nsdyn.plot` (``*_figure`` here pass it the benchmark's settings).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .atomic import atomic_open, save_figure

__all__ = [
    "BenchRun",
    "Reference",
    "acceleration_roundoff",
    "accuracy_bench",
    "accuracy_figure",
    "bench_frame",
    "bench_isolation",
    "bench_motion",
    "configure",
    "dense_orbit_quantities",
    "fidelity_bench",
    "fidelity_figure",
    "low_frequency_motion",
    "main",
    "newton_noise_floor",
    "numpy_equations",
    "periodic_bench",
    "periodic_figure",
    "periodic_markdown",
    "periodic_summary",
    "run",
    "run_nsdyn",
    "run_scipy_radau",
    "scipy_match",
    "speed_bench",
    "speed_figure",
    "speed_markdown",
    "stability_bench",
    "stability_figure",
    "write_csv_atomic",
]

# ---- the scene --------------------------------------------------------------------------------
FRAME = "office-11"
K_LAM = 5.0e4  # N/m, laminated bearing, per isolator
C_ISO = 1.0e4  # N s/m, viscous damper, per isolator
MU = 0.03  # friction coefficient
EPS = 7500.0  # s/m, arctan sharpness of the charts
PGA = 3.0  # m/s^2, horizontal peak ground acceleration
WINDOW_S = 20.0  # s, record window of the accuracy and fidelity charts
QUICK_WINDOW_S = 3.0  # s, window in --quick mode (contains the PGA of both records)
RECORDS = {"wn": "synthetic-wn-40s", "kt": "synthetic-kt-20s"}
LOWPASS_HZ = 2.0  # Hz, corner of the low-frequency record (4th-order Butterworth, zero phase)

# ---- timing -----------------------------------------------------------------------------------
REPEATS = 3  # timed repeats (median)
LONG_RUN_S = 60.0  # runs longer than this are timed once
DEFAULT_OUT = Path("nsdyn-out") / "bench"

# ---- accuracy ---------------------------------------------------------------------------------
ATOL_FACTOR = 1e-2  # atol = ATOL_FACTOR * rtol [m, m/s] for every adaptive run
REF_RTOL = 1e-10  # reference tolerance (quick: QUICK_REF_RTOL)
QUICK_REF_RTOL = 1e-9
SWITCH_CHECK_ETA = 1e-7  # m/s, stick band of the radau check of the switch reference
SWITCH_CHECK_RTOL = 1e-9
# (label, method, law, setting, values); scipy-radau is the NumPy/SciPy baseline
ACCURACY_PLAN = [
    ("radau", "radau", "arctan", "rtol", [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7]),
    ("dopri5", "dopri5", "arctan", "rtol", [1e-4]),  # + the reference check at REF_RTOL
    ("genalpha", "genalpha", "arctan", "dt", [2e-3, 1e-3, 5e-4, 2e-4, 1e-4]),
    ("hht", "hht", "arctan", "dt", [2e-3, 1e-3, 5e-4, 2e-4, 1e-4]),
    ("event", "event", "switch", "rtol", [1e-3, 1e-4, 1e-5, 1e-6]),
    ("scipy-radau", "scipy", "arctan", "rtol", [1e-3, 1e-4, 1e-5]),
]
QUICK_ACCURACY_PLAN = [
    ("radau", "radau", "arctan", "rtol", [1e-2, 1e-5]),
    ("dopri5", "dopri5", "arctan", "rtol", [1e-4]),
    ("genalpha", "genalpha", "arctan", "dt", [1e-3, 2.5e-4]),
    ("hht", "hht", "arctan", "dt", [1e-3]),
    ("event", "event", "switch", "rtol", [1e-3, 1e-5]),
    ("scipy-radau", "scipy", "arctan", "rtol", [1e-3]),
]
QUICK_DOPRI5_MAX_STEPS = 20_000  # --quick: dopri5 is stiffness-bound (~4e-6 s steps); cap it
SCIPY_RECORDS = ("wn",)  # the SciPy baseline is slow: run it on these records only
MATCH_ERROR = 1e-4  # err_x the speed ratios are quoted at (cheapest run reaching it)
UNRESOLVED_FACTOR = 3.0  # charted errors below this x the reference check's are drawn hollow

# ---- fidelity ---------------------------------------------------------------------------------
# The ladder, cheapest first; the last rung that runs is the reference. Every rung runs with
# radau at the transient defaults (nsdyn.transient: rtol 1e-4, atol (1e-8 m, 1e-6 m/s)), what
# `nsdyn run` uses, so costs compare like with like and are the costs a user pays. The full
# 435-dof model needs them: its acceleration carries a float64 round-off of ~1e-6 m/s^2 (the
# base-diaphragm stiffness 1e11 against the tiny rotational inertia of the base nodes;
# max |M^-1 K*| ~ 6e13), which at rtol 1e-6 / atol 1e-8 exceeds what the Newton iterations of
# genalpha (dt 1e-3: it failed at t = 1.5 s) and radau (h ~ 1e-3 s) can resolve, and at rtol
# 1e-6 radau needs ~80 s per simulated second. See acceleration_roundoff() and
# newton_noise_floor().
LADDER = [
    ("rigid", None),
    ("cb", 5.0),
    ("cb", 10.0),
    ("cb", 15.0),
    ("cb", 20.0),
    ("cb", 50.0),
    ("cb", 100.0),
    ("full", None),
]
QUICK_LADDER = [("rigid", None), ("cb", 5.0), ("cb", 10.0)]
FIDELITY_METHOD = "radau"  # one integrator for every rung
FIDELITY_RTOL = None  # None: the transient defaults (DEFAULT_RTOL, default_atol("radau"))
FLOOR_RTOL = 1e-8  # the floor check: FLOOR_RUNG at the ladder's tolerances vs at FLOOR_RTOL
FLOOR_RUNG = ("cb", 20.0)
QUICK_FLOOR_RUNG = ("cb", 5.0)

# ---- stability --------------------------------------------------------------------------------
STAB_WINDOW = (0.0, 3.0)  # s, record window of the step-size maps (the PGA is at 2.8 s)
STAB_DT = [0.02 / 2**k for k in range(13)]  # 2e-2 ... 4.9e-6 s, scanned from the top
STAB_METHODS = ["dopri5", "radau", "genalpha", "hht", "newmark"]  # all with a fixed step
ALPHA_MAP_EPS = 1e3  # s/m: a soft law, so that the Baumgarte eigenvalue -alpha shows
# what each map scans: (models, methods, values); quick: a corner of each
STAB_PLAN = {
    "eps": (["rigid", "cb-5"], STAB_METHODS, [1e2, 3e2, 1e3, 3e3, 1e4, 3e4, 1e5]),
    "alpha": (["rigid", "cb-5"], STAB_METHODS, [2 * np.pi, 30.0, 100.0, 300.0, 1e3, 3e3, 1e4]),
}
QUICK_STAB_PLAN = {
    "eps": (["cb-5"], ["dopri5", "genalpha"], [1e2, 1e4]),
    "alpha": (["rigid"], ["dopri5"], [2 * np.pi, 1e3]),
}
STAB_REF_RTOL = 1e-8  # radau reference of each map column (garbage / accuracy test)
QUICK_STAB_REF_RTOL = 1e-6
STAB_MAX_STEPS = 400_000  # step budget of one map cell (beyond: "budget", not tested)
STAB_OK_BELOW = 2  # stop a column after this many consecutive stable and accurate cells
ACCURATE_ERR = 1e-2  # err_x of the "accurate" boundary drawn next to the stability one
GARBAGE_ERR = 0.5  # a "successful" run further than this from the reference is garbage
ENERGY_CLOSURE_MAX = 0.05  # energy-balance closure error above which a run counts as blown up
DRIFT_SETTINGS = [("radau", "rtol", 1e-4), ("radau", "rtol", 1e-7), ("genalpha", "dt", 1e-3)]
QUICK_DRIFT_SETTINGS = [("radau", "rtol", 1e-4)]
SHOOT_F = [0.03, 0.05, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0, 3.0, 5.0]  # Hz
SHOOT_A = [0.1, 0.3, 1.0, 3.0]  # m/s^2
QUICK_SHOOT_F = [0.05, 1.0]
QUICK_SHOOT_A = [0.3, 3.0]


# ---- scene factories ---------------------------------------------------------------------------
def bench_frame():
    """The office-11 frame."""
    from .frame import load_frame

    return load_frame(FRAME)


def bench_isolation(law: str = "arctan", eps: float = EPS, **changes):
    """The benchmark isolators (K_lam = 5e4, c = 1e4, mu = 0.03) with ``law`` and ``eps``."""
    from .system import Isolation

    return Isolation(k_lam=K_LAM, c=C_ISO, mu=MU, law=law, eps=eps, **changes)


def bench_motion(key: str = "wn", window_s: float = WINDOW_S, pga: float = PGA):
    """Bundled record ``RECORDS[key]``, window [0, window_s], scaled to ``pga``."""
    from .records import read_motion

    m = read_motion(RECORDS[key])
    return m.window(m.t0, m.t0 + window_s).scaled_to_pga(pga)


def low_frequency_motion(window_s: float = WINDOW_S, pga: float = PGA, f_c: float = LOWPASS_HZ):
    """The synthetic white noise low-passed at ``f_c`` (4th-order Butterworth, zero phase,
    both components), then scaled to ``pga``: a record with no energy above ~2 f_c."""
    from scipy import signal

    m = bench_motion("wn", window_s, pga)
    sos = signal.butter(4, f_c, fs=1.0 / m.dt, output="sos")
    a_ver = None if m.a_ver is None else signal.sosfiltfilt(sos, m.a_ver)
    lp = m._replace(
        a_hor=signal.sosfiltfilt(sos, m.a_hor),
        a_ver=a_ver,
        name=f"{m.name} low-passed {f_c:g} Hz",
        meta_update={"lowpass_hz": f_c},
    )
    return lp.scaled_to_pga(pga)


# ---- the plain-NumPy equations (baseline and independent check) -------------------------------
def numpy_equations(system, motion) -> tuple[Callable, Callable]:
    """Right-hand side ``f(t, x)`` and Jacobian ``J(t, x)`` of the isolated system in plain NumPy.

    The same equations as the numba kernel (:mod:`nsdyn._ksystem`) for the arctan law with the
    live normal force, written again from the system matrices::

        a0  = -Gamma [u_h, u_v + g] - M^-1 K* q - M^-1 C* qd
        B   = M^-1 R^T - M^-1 D^T diag(mu s),   s = (2/pi) arctan(eps D qd)
        lam = -(R B)^-1 (R a0 + 2 alpha beta R qd + alpha^2 R q),   qdd = a0 + B lam

    Jacobian: ``d qdd = (I - B G^-1 R)(d a0 + dB lam) - B G^-1 d b`` with ``G = R B``.
    Ground acceleration: linear interpolation of the record, zero outside it.
    """
    iso = system.isolation
    if iso is None or iso.law != "arctan" or iso.frozen_normal:
        raise ValueError("numpy_equations: only the arctan law with live normal forces")
    R, D = system.R, system.D
    n, nc, ni = system.n, R.shape[0], D.shape[0]
    if ni != nc:
        raise ValueError("numpy_equations: expects one contact per isolator")
    mu = iso.per_isolator("mu", ni)
    eps, alpha, beta, g = iso.eps, iso.alpha, iso.beta, iso.g
    Minv = np.linalg.inv(system.M)
    MiK, MiC = Minv @ system.K, Minv @ system.C
    MiRt, MiDt = Minv @ R.T, Minv @ D.T
    Gam = system.Gamma
    t0, dt, a_h, a_v = motion.as_arrays()
    tg = t0 + dt * np.arange(a_h.size)
    eye = np.eye(n)

    def parts(t, x):
        q, qd = x[:n], x[n:]
        if tg[0] <= t <= tg[-1]:
            ug = np.array([np.interp(t, tg, a_h), np.interp(t, tg, a_v) + g])
        else:
            ug = np.array([0.0, g])
        a0 = -Gam @ ug - MiK @ q - MiC @ qd
        v = D @ qd
        B = MiRt - MiDt * (mu * (2.0 / np.pi) * np.arctan(eps * v))
        G = R @ B
        b = 2.0 * alpha * beta * (R @ qd) + alpha**2 * (R @ q)
        lam = np.linalg.solve(G, -(R @ a0 + b))
        return a0, B, G, lam, v

    def fun(t, x):
        a0, B, _, lam, _ = parts(t, x)
        return np.concatenate([x[n:], a0 + B @ lam])

    def jac(t, x):
        _, B, G, lam, v = parts(t, x)
        ds = (2.0 / np.pi) * eps / (1.0 + (eps * v) ** 2)
        BG = B @ np.linalg.inv(G)
        proj = eye - BG @ R
        J = np.zeros((2 * n, 2 * n))
        J[:n, n:] = eye
        J[n:, :n] = -proj @ MiK - alpha**2 * (BG @ R)
        J[n:, n:] = proj @ (-MiC - (MiDt * (mu * ds * lam)) @ D) - 2 * alpha * beta * (BG @ R)
        return J

    return fun, jac


# ---- runs -------------------------------------------------------------------------------------
@dataclass
class BenchRun:
    """One benchmark run: its setting, outcome, timings and response metrics.

    ``status`` is "ok" or the failure the code reported (an IntegrationError reason such as
    "newton_divergence", "max_steps", "nonfinite"; or the benchmark's own checks "nan_output",
    "energy_blowup"). ``walls`` holds every timed repeat; ``wall_s`` is their median.
    """

    label: str
    method: str
    law: str
    setting: str  # "rtol" or "dt"
    value: float
    status: str = "ok"
    message: str = ""
    t_fail: float = float("nan")
    walls: list = field(default_factory=list)
    n_steps: int = 0
    nfev: int = 0
    t: np.ndarray | None = None
    x: np.ndarray | None = None
    x_iso: np.ndarray | None = None
    idr_max: float = float("nan")
    floor_acc_max: float = float("nan")
    energy_closure: float = float("nan")
    errors: dict = field(default_factory=dict)  # run_errors against a reference, if measured

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    @property
    def wall_s(self) -> float:
        return float(np.median(self.walls)) if self.walls else float("nan")

    @property
    def x_iso_max(self) -> float:
        return float(np.max(np.abs(self.x_iso))) if self.x_iso is not None else float("nan")


def _fill_from_response(run: BenchRun, t, x, resp) -> BenchRun:
    run.t, run.x, run.x_iso = t, x, resp.x_iso
    run.idr_max = resp.idr_max
    run.floor_acc_max = resp.floor_acc_max
    run.energy_closure = float(resp.energy.get("closure", float("nan")))
    if not np.all(np.isfinite(x)):
        run.status, run.message = "nan_output", "the returned history holds NaN or inf"
    elif run.energy_closure > ENERGY_CLOSURE_MAX:
        run.status = "energy_blowup"
        run.message = f"energy balance closure error {run.energy_closure:.2g}"
    return run


def run_nsdyn(
    system,
    motion,
    method: str,
    *,
    label: str | None = None,
    rtol: float | None = None,
    dt: float | None = None,
    atol=None,
    repeats: int = REPEATS,
    keep_state: bool = False,
    **options,
) -> BenchRun:
    """Run :func:`nsdyn.transient.simulate` ``repeats`` times; failures become a status.

    ``atol`` defaults to ``ATOL_FACTOR * rtol`` (a number or a pair (displacements,
    velocities) may be given). ``dt`` with an adaptive method (radau, dopri5) steps with that
    fixed dt (no error control). A failure reported by the integrator (``IntegrationError``)
    ends the run with ``status`` = its reason; a "successful" run whose history holds NaN/inf
    or whose energy balance does not close is flagged by the benchmark itself.
    """
    from .integrate import METHODS, IntegrationError
    from .transient import simulate

    law = system.isolation.law if system.isolation is not None else "none"
    setting, value = ("dt", dt) if dt is not None else ("rtol", rtol)
    br = BenchRun(label or method, method, law, setting, float(value))
    kw = dict(options)
    if dt is not None:
        kw["dt"] = dt
        if not METHODS[method].fixed_step:
            kw["adaptive"] = False
    else:
        kw["rtol"] = rtol
        kw["atol"] = rtol * ATOL_FACTOR if atol is None else atol
    res = None
    for _ in range(max(1, repeats)):
        try:
            r = simulate(system, motion, method=method, **kw)
        except IntegrationError as e:
            br.status, br.message, br.t_fail = e.reason, str(e), float(e.t)
            return br
        br.walls.append(r.wall_s)
        if res is None:
            res = r
            br.n_steps, br.nfev = r.n_steps, int(r.stats.get("nfev", 0))
        if r.wall_s > LONG_RUN_S:
            break
    _fill_from_response(br, res.t, res.x, res.response)
    if not keep_state:
        br.x = None
    return br


class _OverBudget(Exception):
    """A SciPy run exceeded its wall-time budget."""


def run_scipy_radau(
    system,
    motion,
    rtol: float,
    *,
    repeats: int = REPEATS,
    label: str = "scipy-radau",
    atol=None,
    t_eval: np.ndarray | None = None,
    budget_s: float | None = None,
) -> BenchRun:
    """:func:`scipy.integrate.solve_ivp` (Radau) on :func:`numpy_equations`; same outputs.

    ``atol`` defaults to ``ATOL_FACTOR * rtol``; a pair (displacements, velocities) is expanded
    as nsdyn does. ``t_eval`` defaults to the record's sample times. A run still going after
    ``budget_s`` seconds of wall time is stopped (status "budget").
    """
    from scipy.integrate import Radau, solve_ivp

    from .metrics import response
    from .transient import output_grid

    steps = [0]

    class CountingRadau(Radau):
        """SciPy's Radau, counting accepted steps (one call per step, no other change)."""

        def _step_impl(self):
            ok, msg = super()._step_impl()
            steps[0] += ok
            return ok, msg

    br = BenchRun(label, "scipy", "arctan", "rtol", float(rtol))
    fun, jac = numpy_equations(system, motion)
    x0, _ = system.static_equilibrium()
    t_eval = output_grid(motion) if t_eval is None else np.asarray(t_eval, dtype=float)
    a = np.asarray(rtol * ATOL_FACTOR if atol is None else atol, dtype=float)
    atol_arr = np.repeat(a, system.n) if a.shape == (2,) else a
    sol = None
    for _ in range(max(1, repeats)):
        steps[0] = 0
        t0 = time.perf_counter()
        f = fun
        if budget_s is not None:
            calls = [0]

            def f(t, x, _t0=t0, _calls=calls):
                _calls[0] += 1
                if _calls[0] % 1000 == 0 and time.perf_counter() - _t0 > budget_s:
                    raise _OverBudget
                return fun(t, x)

        try:
            s = solve_ivp(
                f,
                (t_eval[0], t_eval[-1]),
                x0,
                method=CountingRadau,
                t_eval=t_eval,
                rtol=rtol,
                atol=atol_arr,
                jac=jac,
            )
        except _OverBudget:
            br.walls.append(time.perf_counter() - t0)
            br.status = "budget"
            br.message = f"stopped after {budget_s:g} s of wall time"
            return br
        br.walls.append(time.perf_counter() - t0)
        if s.status != 0:
            br.status, br.message = "scipy_failed", s.message
            return br
        if sol is None:
            sol, br.n_steps = s, int(steps[0])
        if br.walls[-1] > LONG_RUN_S:
            break
    br.nfev = int(sol.nfev)
    X = np.ascontiguousarray(sol.y.T)
    return _fill_from_response(br, sol.t, X, response(system, sol.t, X, system.params(motion)))


def run_errors(run: BenchRun, ref: BenchRun, *, flagged: bool = False) -> dict:
    """``err_x`` (history), ``err_idr``, ``err_xpeak`` and ``err_acc`` (peaks) of ``run``.

    NaN for a failed run, unless ``flagged`` (then any run with a full history is measured,
    e.g. one the benchmark's own energy check flagged)."""
    if (not run.ok and not flagged) or run.x_iso is None or run.x_iso.shape != ref.x_iso.shape:
        return _nan_errors()
    return {
        "err_x": float(np.max(np.abs(run.x_iso - ref.x_iso)) / ref.x_iso_max),
        "err_idr": _rel(run.idr_max, ref.idr_max),
        "err_xpeak": _rel(run.x_iso_max, ref.x_iso_max),
        "err_acc": _rel(run.floor_acc_max, ref.floor_acc_max),
    }


def _nan_errors() -> dict:
    return {k: float("nan") for k in ("err_x", "err_idr", "err_xpeak", "err_acc")}


def _rel(a: float, b: float) -> float:
    return abs(a / b - 1.0) if b != 0 else (0.0 if a == 0 else float("inf"))


# ---- output -----------------------------------------------------------------------------------
def write_csv_atomic(path: Path, rows: list[dict], fieldnames: list[str] | None = None) -> Path:
    """Write ``rows`` as CSV to a temporary file next to ``path``, then rename it over ``path``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if fieldnames is None:
        fieldnames = []
        for r in rows:
            fieldnames.extend(k for k in r if k not in fieldnames)
    with atomic_open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fieldnames, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: _csv_value(r.get(k, "")) for k in fieldnames})
    return path


def _csv_value(v):
    if isinstance(v, float | np.floating):
        return "" if not np.isfinite(v) else f"{float(v):.6g}"
    return v


def _log(msg: str, quiet: bool = False) -> None:
    if not quiet:
        print(msg, file=sys.stderr, flush=True)


def _warmup(methods) -> float:
    from .integrate import warmup

    return float(sum(warmup([m for m in methods if m != "scipy"]).values()))


def _row(run: BenchRun, **extra) -> dict:
    row = {
        "label": run.label,
        "method": run.method,
        "law": run.law,
        "setting": run.setting,
        "value": run.value,
        "status": run.status,
        "wall_s": run.wall_s,
        "n_timed": len(run.walls),
        "n_steps": run.n_steps,
        "nfev": run.nfev,
        "x_iso_max_m": run.x_iso_max,
        "idr_max": run.idr_max,
        "floor_acc_max_mps2": run.floor_acc_max,
        "energy_closure": run.energy_closure,
    }
    row.update(extra)
    row["message"] = run.message
    return row


# ---- 1. work-precision ------------------------------------------------------------------------
@dataclass
class Reference:
    """A tight run of one model and friction law, and an independent check of it."""

    law: str
    run: BenchRun
    check: BenchRun | None
    agreement: dict  # run_errors(check, run), or NaNs when the check was skipped

    @property
    def floor(self) -> float:
        """err_x below which charted errors are not resolved (the pair's disagreement)."""
        return self.agreement.get("err_x", float("nan"))


def make_reference(system, motion, law: str, *, quick: bool = False, check: bool = True):
    """The reference of ``law`` ("arctan" or "switch") and, with ``check``, its check.

    arctan: radau at REF_RTOL vs dopri5 at REF_RTOL (explicit; stiffness-bound ~4e-6 s steps,
    minutes on a 20 s window). switch: event at REF_RTOL vs radau on the switch law with the
    stick band narrowed to SWITCH_CHECK_ETA (the smooth integrator's band model is the only
    difference); if radau cannot follow the switch law (step underflow), event at REF_RTOL/10
    (self-convergence only). ``quick`` tightens less (QUICK_REF_RTOL).
    """
    rtol = QUICK_REF_RTOL if quick else REF_RTOL
    sys_law = system if system.isolation.law == law else system.with_isolation(law=law)
    if law == "arctan":
        ref = run_nsdyn(sys_law, motion, "radau", label="reference", rtol=rtol, repeats=1)
        chk = (
            run_nsdyn(sys_law, motion, "dopri5", label="reference-check", rtol=rtol, repeats=1)
            if check
            else None
        )
    elif law == "switch":
        ref = run_nsdyn(sys_law, motion, "event", label="reference", rtol=rtol, repeats=1)
        chk = None
        if check:
            s2 = sys_law.with_isolation(eta=SWITCH_CHECK_ETA)
            chk = run_nsdyn(
                s2, motion, "radau", label="reference-check", rtol=SWITCH_CHECK_RTOL, repeats=1
            )
            if not chk.ok:  # the smooth integrator could not follow the switch law: fall back
                chk = run_nsdyn(
                    sys_law, motion, "event", label="reference-check", rtol=rtol / 10, repeats=1
                )
                chk.message = "self-convergence check (radau on the switch law failed)"
    else:
        raise ValueError(f"law: expected 'arctan' or 'switch', got {law!r}")
    if not ref.ok:
        raise RuntimeError(f"reference run ({law}) failed: {ref.status}: {ref.message}")
    if chk is not None:
        agreement = run_errors(chk, ref)
    else:
        agreement = _nan_errors()
    return Reference(law, ref, chk, agreement)


def wall_to_reach(rows: list[dict], label: str, record: str, target: float) -> float:
    """Cheapest median wall time among ``label``'s successful runs with err_x <= target
    (NaN if none): the work-precision front read without interpolation."""
    walls = [
        r["wall_s"]
        for r in rows
        if r["label"] == label
        and r["record"] == record
        and r["status"] == "ok"
        and np.isfinite(r.get("err_x", np.nan))
        and r["err_x"] <= target
    ]
    return float(min(walls)) if walls else float("nan")


def _matched(rows, rec, a: str, b: str) -> dict:
    """Walls of ``a`` and ``b`` to reach err_x <= MATCH_ERROR (if both can), else the
    smallest error level both reach (the larger of the two methods' best errors)."""
    best = [
        min(
            (
                r["err_x"]
                for r in rows
                if r["label"] == lab
                and r["record"] == rec
                and r["status"] == "ok"
                and np.isfinite(r.get("err_x", np.nan))
            ),
            default=np.nan,
        )
        for lab in (a, b)
    ]
    for e in (MATCH_ERROR, max(best)):
        wa, wb = wall_to_reach(rows, a, rec, e), wall_to_reach(rows, b, rec, e)
        if np.isfinite(wa) and np.isfinite(wb):
            return {"err_x": e, f"{a}_wall_s": wa, f"{b}_wall_s": wb, "ratio": wa / wb}
    nan = float("nan")
    return {"err_x": nan, f"{a}_wall_s": nan, f"{b}_wall_s": nan, "ratio": nan}


def matched_ratios(rows: list[dict], rec: str) -> dict:
    """Speed ratios at matched accuracy, all timed in the same run: the cheapest run of each
    method reaching err_x <= MATCH_ERROR (see :func:`wall_to_reach`); > 1: the second is faster.

    ``scipy-radau/radau``: SciPy Radau on the NumPy equations over nsdyn radau; ``event/radau``
    compares the switch model's cost with the arctan model's at the same error level.
    """
    return {
        "scipy-radau/radau": _matched(rows, rec, "scipy-radau", "radau"),
        "genalpha/radau": _matched(rows, rec, "genalpha", "radau"),
        "hht/radau": _matched(rows, rec, "hht", "radau"),
        "event/radau": _matched(rows, rec, "event", "radau"),
        "dopri5/radau": _matched(rows, rec, "dopri5", "radau"),
    }


def accuracy_bench(
    *,
    quick: bool = False,
    repeats: int | None = None,
    records: tuple[str, ...] = ("wn", "kt"),
    out: Path | None = DEFAULT_OUT,
    figures: bool = True,
    quiet: bool = False,
) -> dict:
    """Work-precision table of every integrator x friction law on CB-5 (see module docstring).

    Returns ``{"rows", "references", "ratios", "files"}``; writes ``accuracy.csv``,
    ``accuracy-reference.csv`` and ``accuracy.png`` to ``out`` (None: write nothing).
    """
    from .system import build_system

    repeats = (1 if quick else REPEATS) if repeats is None else repeats
    window = QUICK_WINDOW_S if quick else WINDOW_S
    plan = QUICK_ACCURACY_PLAN if quick else ACCURACY_PLAN
    compile_s = _warmup({p[1] for p in plan} | {"radau", "dopri5"})
    frame = bench_frame()
    system = build_system(frame, bench_isolation("arctan"), fidelity="cb", f_max=5.0)
    rows: list[dict] = []
    ref_rows: list[dict] = []
    refs: dict = {}
    for rec in records:
        motion = bench_motion(rec, window)
        for law in ("arctan", "switch"):
            _log(f"[accuracy] {rec}: reference ({law}) ...", quiet)
            ref = make_reference(system, motion, law, quick=quick, check=not quick)
            refs[(rec, law)] = ref
            for r in (ref.run, ref.check):
                if r is None:
                    continue
                ref_rows.append(
                    _row(r, record=rec, **(run_errors(r, ref.run) if r is not ref.run else {}))
                )
            if ref.check is not None and ref.check.label == "reference-check" and law == "arctan":
                # the dopri5 check is also dopri5's tightest point on the chart
                rows.append(_row(ref.check, record=rec, **run_errors(ref.check, ref.run)))
                rows[-1]["label"] = "dopri5"
        for label, method, law, setting, values in plan:
            if method == "scipy" and rec not in SCIPY_RECORDS:
                continue
            sys_law = system if law == "arctan" else system.with_isolation(law=law)
            ref = refs[(rec, law)].run
            for v in values:
                _log(f"[accuracy] {rec}: {label} {setting}={v:g}", quiet)
                if method == "scipy":
                    br = run_scipy_radau(sys_law, motion, v, repeats=repeats, label=label)
                else:
                    opts = {}
                    if quick and method == "dopri5":
                        opts["max_steps"] = QUICK_DOPRI5_MAX_STEPS
                    kw = {setting: v}
                    br = run_nsdyn(
                        sys_law, motion, method, label=label, repeats=repeats, **kw, **opts
                    )
                rows.append(_row(br, record=rec, **run_errors(br, ref)))
    ratios = {rec: matched_ratios(rows, rec) for rec in records}
    files = {}
    meta = {"window_s": window, "repeats": repeats, "compile_s": compile_s, "quick": quick}
    if out is not None:
        out = Path(out)
        for r in rows + ref_rows:
            r.update(meta)
        files["csv"] = str(write_csv_atomic(out / "accuracy.csv", rows, _ACC_FIELDS))
        files["reference_csv"] = str(
            write_csv_atomic(out / "accuracy-reference.csv", ref_rows, _ACC_FIELDS)
        )
        if figures:
            floors = {k: ref.agreement for k, ref in refs.items()}
            fig = accuracy_figure(rows, floors, records, window)
            files["figure"] = str(save_figure(fig, out / "accuracy.png"))
    return {
        "rows": rows,
        "reference_rows": ref_rows,
        "references": refs,
        "ratios": ratios,
        "files": files,
        "meta": meta,
    }


_ACC_FIELDS = [
    "record",
    "label",
    "method",
    "law",
    "setting",
    "value",
    "status",
    "err_x",
    "err_idr",
    "err_xpeak",
    "wall_s",
    "n_timed",
    "n_steps",
    "nfev",
    "x_iso_max_m",
    "idr_max",
    "floor_acc_max_mps2",
    "energy_closure",
    "window_s",
    "repeats",
    "compile_s",
    "quick",
    "message",
]


# ---- 2. fidelity ladder -----------------------------------------------------------------------
def _rung_name(fidelity: str, f_max: float | None) -> str:
    return f"cb-{f_max:g}" if fidelity == "cb" else fidelity


def fidelity_motions(window_s: float) -> dict:
    """The two records of the fidelity chart: low-frequency and broadband."""
    return {
        "low-frequency": low_frequency_motion(window_s),
        "broadband": bench_motion("kt", window_s),
    }


def acceleration_roundoff(system, motion, t: float, x: np.ndarray) -> np.ndarray:
    """|qdd_float64 - qdd_exact| at (t, x): the kernel's accelerations against the same
    formulas (:func:`numpy_equations`) evaluated in long double from the same float64 data.

    This is the noise floor below which no Newton iteration on the accelerations can
    converge. Arctan law with live normal forces and two contacts (every rung of the ladder).
    """
    from . import _ksystem as ks

    L = np.longdouble
    n = system.n
    P = system.params(motion)
    f = np.empty(2 * n)
    ks.rhs(float(t), np.ascontiguousarray(x, dtype=float), P, f)
    MiK, MiC, Gam = (P[k].astype(L) for k in (ks.I_MIK, ks.I_MIC, ks.I_GAM))
    R, MiRt, D, MiDt = (P[k].astype(L) for k in (ks.I_R, ks.I_MIRT, ks.I_D, ks.I_MIDT))
    fp = P[ks.I_FPAR]
    eps, alpha, beta, g = (L(fp[k]) for k in (ks.F_EPS, ks.F_ALPHA, ks.F_BETA, ks.F_G))
    ah, av = ks.ground_accel(float(t), P)
    q, qd = np.asarray(x[:n]).astype(L), np.asarray(x[n:]).astype(L)
    a0 = -(Gam @ np.array([L(ah), L(av) + g])) - MiK @ q - MiC @ qd
    s = (L(2) / L(np.pi)) * np.arctan(eps * (D @ qd))
    B = MiRt - MiDt * (P[ks.I_MU].astype(L) * s)
    G = R @ B
    r = -(R @ a0 + L(2) * alpha * beta * (R @ qd) + alpha**2 * (R @ q))
    det = G[0, 0] * G[1, 1] - G[0, 1] * G[1, 0]
    lam = np.array([G[1, 1] * r[0] - G[0, 1] * r[1], G[0, 0] * r[1] - G[1, 0] * r[0]]) / det
    return np.abs(f[n:] - (a0 + B @ lam).astype(float))


def newton_noise_floor(
    x: np.ndarray, da: np.ndarray, rtol: float, atol, h: float = 1e-3, method: str = "radau"
) -> float:
    """An acceleration error ``da`` as a multiple of a Newton iteration's convergence
    threshold: above 1, Newton cannot certify convergence whatever the step's Jacobian.

    ``radau``: one simplified-Newton update of the real stage moves the velocities by about
    ``(h / mu) da`` and the positions by ``(h / mu)^2 da`` (``mu`` the real eigenvalue of the
    inverse Radau IIA matrix), scaled by ``atol + rtol |x|``, RMS-averaged; threshold
    ``max(10 eps / rtol, min(0.03, rtol^0.5))`` (:mod:`nsdyn._kradau`).
    ``genalpha`` (rho_inf 0.8, fixed step ``h``): the update is ``gamma h da`` and
    ``beta h^2 da``, same scaling; threshold NEWTON_TOL of :mod:`nsdyn._kgenalpha`.
    """
    n = da.size
    aq, av = _atol_pair(atol)
    if method == "radau":
        from ._kradau import MU_REAL

        gv = h / MU_REAL
        gq = gv * gv
        tol = max(10.0 * np.finfo(float).eps / rtol, min(0.03, rtol**0.5))
    elif method == "genalpha":
        from ._kgenalpha import FAMILY_GENALPHA, NEWTON_TOL, parameters

        _, _, beta, gamma = parameters(FAMILY_GENALPHA, 0.8)
        gq, gv, tol = beta * h * h, gamma * h, NEWTON_TOL
    else:
        raise ValueError(f"method: expected 'radau' or 'genalpha', got {method!r}")
    sq = gq * da / (aq + rtol * np.abs(x[:n]))
    sv = gv * da / (av + rtol * np.abs(x[n:]))
    return float(np.sqrt((np.sum(sq**2) + np.sum(sv**2)) / (2 * n))) / tol


def fidelity_tolerances() -> tuple[float, object]:
    """(rtol, atol) of every rung: FIDELITY_RTOL with atol ATOL_FACTOR * rtol, or the
    transient defaults when FIDELITY_RTOL is None."""
    from .transient import DEFAULT_RTOL, default_atol

    if FIDELITY_RTOL is None:
        return DEFAULT_RTOL, default_atol(FIDELITY_METHOD)
    return FIDELITY_RTOL, FIDELITY_RTOL * ATOL_FACTOR


def fidelity_bench(
    *,
    quick: bool = False,
    repeats: int | None = None,
    out: Path | None = DEFAULT_OUT,
    figures: bool = True,
    quiet: bool = False,
    ladder: list | None = None,
) -> dict:
    """Error of each rung of the model ladder against the reference rung, against its cost.

    Every rung runs with the same integrator and tolerances (:func:`fidelity_tolerances`), so
    costs compare like with like; the time-integration error is bounded by FLOOR_RUNG at
    FLOOR_RTOL (row ``<rung> rtol 1e-08``, drawn as the floor). The reference of a record is
    the last rung of the ladder that ran through it (the full model unless it failed; its row
    then records why).
    """
    from .system import build_system

    repeats = (1 if quick else REPEATS) if repeats is None else repeats
    window = QUICK_WINDOW_S if quick else WINDOW_S
    ladder = (QUICK_LADDER if quick else LADDER) if ladder is None else ladder
    floor_rung = _rung_name(*(QUICK_FLOOR_RUNG if quick else FLOOR_RUNG))
    rtol, atol = fidelity_tolerances()
    compile_s = _warmup([FIDELITY_METHOD])
    frame = bench_frame()
    iso = bench_isolation("arctan")
    systems = {}
    for fid, fm in ladder:
        systems[_rung_name(fid, fm)] = build_system(frame, iso, fidelity=fid, f_max=fm or 5.0)
    if floor_rung not in systems:
        fid, fm = QUICK_FLOOR_RUNG if quick else FLOOR_RUNG
        systems_floor = build_system(frame, iso, fidelity=fid, f_max=fm)
    else:
        systems_floor = systems[floor_rung]
    rows = []
    for rec, motion in fidelity_motions(window).items():
        runs = {}
        for name, system in systems.items():
            _log(f"[fidelity] {rec}: {name} (n = {system.n})", quiet)
            runs[name] = run_nsdyn(
                system,
                motion,
                FIDELITY_METHOD,
                label=name,
                rtol=rtol,
                atol=atol,
                repeats=repeats,
            )
        ok = [name for name in systems if runs[name].ok]
        ref_name = ok[-1] if ok else ""
        ref = runs[ref_name] if ok else None
        for name, system in systems.items():
            br = runs[name]
            e = run_errors(br, ref) if ref is not None else _nan_errors()
            rows.append(_row(br, record=rec, model=name, n_dof=system.n, reference=ref_name, **e))
        _log(f"[fidelity] {rec}: {floor_rung} at rtol {FLOOR_RTOL:g} (floor check)", quiet)
        tight = run_nsdyn(
            systems_floor, motion, FIDELITY_METHOD, label=floor_rung, rtol=FLOOR_RTOL, repeats=1
        )
        loose = runs.get(floor_rung) or run_nsdyn(
            systems_floor, motion, FIDELITY_METHOD, rtol=rtol, atol=atol, repeats=1
        )
        e = run_errors(loose, tight) if tight.ok else _nan_errors()
        rows.append(
            _row(
                tight,
                record=rec,
                model=f"{floor_rung} rtol {FLOOR_RTOL:g}",
                n_dof=systems_floor.n,
                reference=f"floor: {floor_rung} at rtol {rtol:g} vs {FLOOR_RTOL:g}",
                **e,
            )
        )
    meta = {
        "window_s": window,
        "repeats": repeats,
        "compile_s": compile_s,
        "quick": quick,
        "rtol": rtol,
        "atol": str(atol),
    }
    for r in rows:
        r.update(meta)
    files = {}
    if out is not None:
        out = Path(out)
        files["csv"] = str(write_csv_atomic(out / "fidelity.csv", rows, _FID_FIELDS))
        if figures:
            files["figure"] = str(save_figure(fidelity_figure(rows), out / "fidelity.png"))
    return {"rows": rows, "files": files, "meta": meta}


_FID_FIELDS = [
    "record",
    "model",
    "n_dof",
    "reference",
    "status",
    "err_xpeak",
    "err_idr",
    "err_acc",
    "err_x",
    "wall_s",
    "n_timed",
    "n_steps",
    "x_iso_max_m",
    "idr_max",
    "floor_acc_max_mps2",
    "energy_closure",
    "method",
    "setting",
    "value",
    "window_s",
    "repeats",
    "compile_s",
    "quick",
    "rtol",
    "atol",
    "message",
]


# ---- 3. stability maps ------------------------------------------------------------------------
def stability_motion(quick: bool = False):
    """The white-noise record's first 3 s (STAB_WINDOW; the PGA, 3 m/s^2, is at 2.8 s)."""
    m = bench_motion("wn", WINDOW_S)
    t0, t1 = STAB_WINDOW
    return m.window(m.t0 + t0, m.t0 + t1)


def classify(run: BenchRun, ref: BenchRun | None) -> tuple[str, float]:
    """(outcome, err_x) of one map cell.

    outcome: "ok"; "flagged:<reason>" (the integrator raised); "checked:<reason>" (the
    benchmark's NaN / energy-balance check caught it); "garbage" (reported as a success, passed
    those checks, but further than GARBAGE_ERR from the reference: a failure nobody flagged);
    "budget" (more than STAB_MAX_STEPS steps: not tested).
    """
    if run.status == "max_steps":
        return "budget", float("nan")
    if run.status in ("nan_output", "energy_blowup"):
        err = run_errors(run, ref, flagged=True)["err_x"] if ref is not None else float("nan")
        return f"checked:{run.status}", err
    if not run.ok:
        return f"flagged:{run.status}", float("nan")
    err = run_errors(run, ref)["err_x"] if ref is not None else float("nan")
    if np.isfinite(err) and err > GARBAGE_ERR:
        return "garbage", err
    return "ok", err


def scan_dt(
    system, motion, method: str, ref: BenchRun | None, dts=STAB_DT, accurate: bool = True
) -> list[dict]:
    """Cells of one (system, method) column, dt decreasing, until STAB_OK_BELOW consecutive
    cells are ok and (with ``accurate``) accurate: err_x <= ACCURATE_ERR."""
    cells = []
    n_good = 0
    for dt in dts:
        if motion.duration / dt > STAB_MAX_STEPS:
            cells.append({"dt": dt, "outcome": "budget", "err_x": float("nan"), "message": ""})
            continue
        br = run_nsdyn(system, motion, method, dt=dt, repeats=1, max_steps=STAB_MAX_STEPS)
        outcome, err = classify(br, ref)
        cells.append(
            {
                "dt": dt,
                "outcome": outcome,
                "err_x": err,
                "wall_s": br.wall_s,
                "t_fail": br.t_fail,
                "message": br.message,
            }
        )
        good = outcome == "ok" and (ref is None or not accurate or err <= ACCURATE_ERR)
        n_good = n_good + 1 if good else 0
        if n_good >= STAB_OK_BELOW:
            break
    return cells


def largest_stable_dt(cells: list[dict], max_err: float = np.inf) -> float:
    """Largest dt of a column at and below which every tested cell is ok (and, with
    ``max_err``, has err_x <= max_err); NaN if none."""
    best = float("nan")
    for c in sorted(cells, key=lambda c: c["dt"]):
        if c["outcome"] == "budget":
            continue
        if c["outcome"] != "ok" or not (c["err_x"] <= max_err or max_err == np.inf):
            break
        best = c["dt"]
    return best


def _build_map_system(frame, kind: str, model: str, value: float):
    from .system import build_system

    iso = (
        bench_isolation(eps=value)
        if kind == "eps"
        else bench_isolation(eps=ALPHA_MAP_EPS, alpha=value)
    )
    if model == "rigid":
        return build_system(frame, iso, fidelity="rigid")
    return build_system(frame, iso, fidelity="cb", f_max=float(model.split("-")[1]))


def stability_map(
    frame, kind: str, plan, motion, quiet=False, quick: bool = False
) -> tuple[list, list]:
    """Cells (one per run) and boundary rows (one per model x value x method) of one map.

    ``quick``: a looser reference (QUICK_STAB_REF_RTOL) and no scan for the accurate boundary.
    """
    models, methods, values = plan
    cells_rows, bound_rows = [], []
    for value in values:
        for model in models:
            system = _build_map_system(frame, kind, model, value)
            rtol = QUICK_STAB_REF_RTOL if quick else STAB_REF_RTOL
            ref = run_nsdyn(system, motion, "radau", label="reference", rtol=rtol, repeats=1)
            if not ref.ok:
                _log(f"[stability] {kind} = {value:g}, {model}: reference failed: {ref.message}")
                ref = None
            for method in methods:
                _log(f"[stability] {kind} = {value:g}, {model}: {method}", quiet)
                cells = scan_dt(system, motion, method, ref, accurate=not quick)
                dt_max = largest_stable_dt(cells)
                dt_acc = largest_stable_dt(cells, ACCURATE_ERR) if ref is not None else np.nan
                above = [c for c in cells if c["dt"] > dt_max and c["outcome"] != "budget"]
                fail = min(above, key=lambda c: c["dt"]) if above else None
                at = next((c for c in cells if c["dt"] == dt_max), {})
                for c in cells:
                    cells_rows.append(
                        {"map": kind, "model": model, kind: value, "method": method, **c}
                    )
                bound_rows.append(
                    {
                        "map": kind,
                        "model": model,
                        kind: value,
                        "method": method,
                        "dt_max_stable": dt_max,
                        "err_x_at_dt_max": at.get("err_x", np.nan),
                        "dt_max_accurate": dt_acc,
                        "failure_above": fail["outcome"] if fail else "",
                        "failure_message": fail["message"] if fail else "",
                    }
                )
    return cells_rows, bound_rows


def constraint_drift(system, motion, settings=DRIFT_SETTINGS, quiet=False) -> tuple[list, dict]:
    """max_t |R q| without Baumgarte stabilisation (alpha = 0) and with the default alpha."""
    rows, hist = [], {}
    for alpha in (0.0, system.isolation.alpha):
        s = system.with_isolation(alpha=alpha)
        for method, setting, value in settings:
            _log(f"[stability] drift: alpha = {alpha:g}, {method} {setting}={value:g}", quiet)
            br = run_nsdyn(s, motion, method, repeats=1, keep_state=True, **{setting: value})
            if br.ok:
                Rq = np.abs(br.x[:, : s.n] @ s.R.T).max(axis=1)
                Rv = np.abs(br.x[:, s.n :] @ s.R.T).max(axis=1)
                hist[(alpha, method, value)] = (br.t, Rq)
                drift, vdrift = float(Rq.max()), float(Rv.max())
            else:
                drift = vdrift = float("nan")
            rows.append(
                {
                    "map": "drift",
                    "alpha": alpha,
                    "method": method,
                    "setting": setting,
                    "value": value,
                    "status": br.status,
                    "max_abs_Rq_m": drift,
                    "max_abs_Rqd_mps": vdrift,
                    "wall_s": br.wall_s,
                    "message": br.message,
                }
            )
    return rows, hist


def shooting_map(system, f_values, a_values, quiet=False) -> list[dict]:
    """Cold-start shooting (from the static equilibrium) on a grid of (f, A); converged or why not.

    Uses :func:`nsdyn.periodic.shoot` if the module imports and runs; otherwise one row saying
    why it was not used.
    """
    try:
        from . import periodic
    except Exception as e:  # the module is being written by another engineer
        return [{"map": "shooting", "status": "unavailable", "message": repr(e)}]
    rows = []
    for A in a_values:
        try:
            prob = periodic.frame_problem(system, A)
        except Exception as e:
            return [{"map": "shooting", "status": "unavailable", "message": repr(e)}]
        for f in f_values:
            _log(f"[stability] shooting: A = {A:g} m/s2, f = {f:g} Hz", quiet)
            t0 = time.perf_counter()
            try:
                r = periodic.shoot(prob, f)
                status = "converged" if r.converged else "failed"
                msg, it, res = r.message, r.iterations, r.residual
            except Exception as e:
                status, msg, it, res = "error", repr(e), -1, float("nan")
            rows.append(
                {
                    "map": "shooting",
                    "f_hz": f,
                    "A_mps2": A,
                    "status": status,
                    "reason": _shoot_reason(msg) if status != "converged" else "",
                    "iterations": it,
                    "residual": res,
                    "wall_s": time.perf_counter() - t0,
                    "message": msg,
                }
            )
    return rows


def _shoot_reason(msg: str) -> str:
    m = msg.lower()
    for key, reason in (
        ("stage newton", "stage_newton"),
        ("line search", "line_search"),
        ("no convergence", "max_iterations"),
        ("singular", "singular"),
        ("not finite", "nonfinite"),
        ("inf/nan", "nonfinite"),
    ):
        if key in m:
            return reason
    return "other"


def stability_bench(
    *,
    quick: bool = False,
    out: Path | None = DEFAULT_OUT,
    figures: bool = True,
    quiet: bool = False,
) -> dict:
    """Largest stable fixed step vs eps and vs alpha; constraint drift; shooting failures."""
    from .system import build_system

    plan = QUICK_STAB_PLAN if quick else STAB_PLAN
    methods = {m for _, ms, _ in plan.values() for m in ms}
    compile_s = _warmup(methods | {"radau"})
    frame = bench_frame()
    motion = stability_motion(quick)
    eps_cells, eps_bound = stability_map(frame, "eps", plan["eps"], motion, quiet, quick)
    a_cells, a_bound = stability_map(frame, "alpha", plan["alpha"], motion, quiet, quick)
    cb5 = build_system(frame, bench_isolation(), fidelity="cb", f_max=5.0)
    drift_motion = bench_motion("wn", QUICK_WINDOW_S if quick else WINDOW_S)
    drift_rows, drift_hist = constraint_drift(
        cb5, drift_motion, QUICK_DRIFT_SETTINGS if quick else DRIFT_SETTINGS, quiet=quiet
    )
    shoot_rows = shooting_map(
        cb5,
        QUICK_SHOOT_F if quick else SHOOT_F,
        QUICK_SHOOT_A if quick else SHOOT_A,
        quiet=quiet,
    )
    garbage = [c for c in eps_cells + a_cells if c["outcome"] == "garbage"]
    meta = {"window_s": motion.duration, "compile_s": compile_s, "quick": quick}
    files = {}
    if out is not None:
        out = Path(out)
        files["cells_csv"] = str(
            write_csv_atomic(out / "stability-cells.csv", eps_cells + a_cells, _CELL_FIELDS)
        )
        files["boundary_csv"] = str(
            write_csv_atomic(out / "stability-boundary.csv", eps_bound + a_bound, _BOUND_FIELDS)
        )
        files["drift_csv"] = str(write_csv_atomic(out / "stability-drift.csv", drift_rows))
        files["shooting_csv"] = str(write_csv_atomic(out / "stability-shooting.csv", shoot_rows))
        if figures:
            fig = stability_figure(eps_bound, a_bound, eps_cells + a_cells, drift_hist, shoot_rows)
            files["figure"] = str(save_figure(fig, out / "stability.png"))
    return {
        "eps_cells": eps_cells,
        "eps_boundary": eps_bound,
        "alpha_cells": a_cells,
        "alpha_boundary": a_bound,
        "drift": drift_rows,
        "shooting": shoot_rows,
        "unflagged_garbage": garbage,
        "files": files,
        "meta": meta,
    }


_CELL_FIELDS = [
    "map",
    "model",
    "eps",
    "alpha",
    "method",
    "dt",
    "outcome",
    "err_x",
    "wall_s",
    "t_fail",
    "message",
]
_BOUND_FIELDS = [
    "map",
    "model",
    "eps",
    "alpha",
    "method",
    "dt_max_stable",
    "err_x_at_dt_max",
    "dt_max_accurate",
    "failure_above",
    "failure_message",
]


# ---- 4. transient speed table -----------------------------------------------------------------
SPEED_T_END = 40.0  # s: the first 40 s of every record (the bundled one is 40 s long)
SPEED_REPEATS = 5  # timed repeats of the nsdyn run (median)
QUICK_SPEED_REPEATS = 3
QUICK_SPEED_T_END = QUICK_WINDOW_S  # --quick: the bundled record's first 3 s (holds its PGA)
SPEED_KOBE_COMPONENT = "000"
SPEED_REF_RTOL = 1e-9  # reference: radau at this rtol, atol ATOL_FACTOR * rtol
SPEED_CHECK_RTOL = 1e-10  # its convergence check: radau 10x tighter
# SciPy's rtol grid (loosest first; the scene's rtol is added). atol keeps the scene's ratio to
# rtol: (1e-8 m, 1e-6 m/s) at rtol 1e-4 becomes (1e-10, 1e-8) at rtol 1e-6.
SCIPY_RTOLS = [1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9]
SCIPY_BUDGET_S = 1800.0  # a SciPy run still going after this is stopped (ratio: lower bound)
QUICK_SCIPY_RTOLS = [1e-6, 1e-7]  # --quick: the scene's rtol and these
QUICK_SCIPY_BUDGET_S = 60.0
SCIPY_REPEATS = 3  # timed runs of the matched SciPy setting when one takes < LONG_RUN_S


def speed_scene(t_end: float | None = None):
    """``(cfg, system, motion, solver)`` of the default scene, as ``nsdyn run`` builds them.

    ``t_end`` cuts the record as ``nsdyn run --t-end`` does. ``solver``: method, rtol, atol
    (the scene's, else :func:`nsdyn.transient.default_atol`) and dt_out.
    """
    from .scene import build_scene, load_scene
    from .transient import default_atol

    cfg = load_scene(None, {"motion": {"t_end": float(t_end)}} if t_end else None)
    system, motion = build_scene(cfg)
    sv = cfg["solver"]
    method = sv.get("method", "radau")
    if method != "radau" or system.isolation is None or system.isolation.law != "arctan":
        raise ValueError("the speed table compares Radau runs of the arctan law")
    atol = sv.get("atol")
    atol = tuple(atol) if isinstance(atol, list) else atol
    solver = {
        "method": method,
        "rtol": float(sv["rtol"]),
        "atol": default_atol(method) if atol is None else atol,
        "dt_out": sv.get("dt_out"),
    }
    return cfg, system, motion, solver


def speed_motions(motion, pga: float, *, quick: bool = False, shared_dir=None) -> dict:
    """The scene's record and, unless ``quick``, the four Kobe records (when the shared
    records directory is found), each scaled to ``pga``, first SPEED_T_END seconds."""
    from .records import RecordFileError, default_shared_dir, kobe_records

    out = {motion.name: motion}
    if quick:
        return out
    shared = default_shared_dir() if shared_dir is None else Path(shared_dir)
    if shared is None:
        return out
    try:
        kobe = kobe_records(shared, SPEED_KOBE_COMPONENT)
    except (OSError, RecordFileError) as e:
        _log(f"[speed] Kobe records not used: {e}")
        return out
    for name, m in kobe.items():
        m = m.scaled_to_pga(pga)
        out[name] = m.window(m.t0, m.t0 + min(SPEED_T_END, m.duration))
    return out


def _scaled_atol(atol, rtol: float, rtol0: float):
    a = np.asarray(atol, dtype=float) * (rtol / rtol0)
    return tuple(float(v) for v in a) if a.ndim else float(a)


def _atol_pair(atol) -> tuple[float, float]:
    a = np.atleast_1d(np.asarray(atol, dtype=float))
    return float(a[0]), float(a[-1])


def scipy_match(
    system,
    motion,
    t_eval,
    ref: BenchRun,
    target: float,
    solver: dict,
    *,
    budget_s,
    rtols=SCIPY_RTOLS,
    quiet=False,
) -> tuple[list, BenchRun | None]:
    """SciPy Radau on the rtol grid until the loosest setting with err_x <= ``target``.

    Starts at the scene's tolerances, jumps to the rtol a linear error model (error ~ rtol)
    predicts, steps tighter until the target is met, then looser while it still is: the
    answer meets the target and the next looser grid rtol does not. Returns (every run,
    loosest matching run or None). A run stopped by ``budget_s`` ends the search.
    """
    grid = sorted(set(rtols) | {solver["rtol"]}, reverse=True)
    runs: dict[int, BenchRun] = {}

    def attempt(i: int) -> BenchRun:
        if i not in runs:
            rt = grid[i]
            _log(f"[speed] {getattr(motion, 'name', '')}: scipy-radau rtol {rt:g}", quiet)
            br = run_scipy_radau(
                system,
                motion,
                rt,
                repeats=1,
                atol=_scaled_atol(solver["atol"], rt, solver["rtol"]),
                t_eval=t_eval,
                budget_s=budget_s,
            )
            br.errors = run_errors(br, ref)
            runs[i] = br
        return runs[i]

    def matched(br: BenchRun) -> bool:
        return br.ok and br.errors["err_x"] <= target

    i = grid.index(solver["rtol"])
    br = attempt(i)
    if not matched(br) and br.status != "budget":
        j = i + 1
        e = br.errors["err_x"]
        if br.ok and np.isfinite(e) and e > 0:
            r_pred = grid[i] * target / e
            j = max(i + 1, next((k for k, r in enumerate(grid) if r <= r_pred), len(grid) - 1))
        while j < len(grid):
            br = attempt(j)
            if matched(br) or br.status == "budget" or j == len(grid) - 1:
                break
            j += 1
        i = j
    best = None
    if i in runs and matched(runs[i]):
        while i > 0 and matched(attempt(i - 1)):
            i -= 1
        best = runs[i]
    return [runs[k] for k in sorted(runs)], best


def cold_compile_s(methods=("radau",)) -> float:
    """Seconds :func:`nsdyn.integrate.warmup` takes in a fresh process with an empty numba
    cache: the JIT compilation a first run pays once (later processes load the cache)."""
    import subprocess

    code = (
        "import json\nfrom nsdyn import integrate\n"
        f"print(json.dumps(integrate.warmup({list(methods)!r})))"
    )
    with tempfile.TemporaryDirectory(prefix="nsdyn-numba-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        root = str(Path(__file__).resolve().parents[1])
        env["PYTHONPATH"] = os.pathsep.join(p for p in (root, env.get("PYTHONPATH")) if p)
        res = subprocess.run(
            [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
        )
    return float(sum(json.loads(res.stdout.strip().splitlines()[-1]).values()))


def _speed_row(run: BenchRun, record: str, role: str, **extra) -> dict:
    row = _row(run, record=record, role=role, **run.errors)
    row.update(extra)
    return row


def speed_bench(
    *,
    quick: bool = False,
    repeats: int | None = None,
    out: Path | None = DEFAULT_OUT,
    figures: bool = True,
    quiet: bool = False,
    shared_dir=None,
    cold_compile: bool = False,
) -> dict:
    """The transient speed table: nsdyn radau at the default scene's tolerances against SciPy
    Radau on the NumPy equations at matched accuracy, per record (module docstring, "Speed").

    Returns ``{"rows", "table", "files", "meta"}``; writes ``speed.csv`` (every run),
    ``speed-table.csv`` (one row per record) and ``speed.png`` to ``out`` (None: nothing).
    """
    from .transient import output_grid

    repeats = (QUICK_SPEED_REPEATS if quick else SPEED_REPEATS) if repeats is None else repeats
    cfg, system, motion, solver = speed_scene(QUICK_SPEED_T_END if quick else None)
    compile_s = _warmup([solver["method"]])
    cold_s = cold_compile_s([solver["method"]]) if cold_compile else float("nan")
    budget = QUICK_SCIPY_BUDGET_S if quick else SCIPY_BUDGET_S
    pga = float(cfg["motion"].get("pga", PGA))
    motions = speed_motions(motion, pga, quick=quick, shared_dir=shared_dir)
    atol_q, atol_v = _atol_pair(solver["atol"])
    rows, table = [], []
    for name, m in motions.items():
        t_eval = output_grid(m, solver["dt_out"])
        _log(f"[speed] {name}: reference radau rtol {SPEED_REF_RTOL:g}, check", quiet)
        kw = dict(repeats=1, t_eval=t_eval)
        ref = run_nsdyn(system, m, "radau", label="reference", rtol=SPEED_REF_RTOL, **kw)
        if not ref.ok:
            raise RuntimeError(f"speed reference ({name}) failed: {ref.status}: {ref.message}")
        chk = run_nsdyn(system, m, "radau", label="reference-check", rtol=SPEED_CHECK_RTOL, **kw)
        chk.errors = run_errors(chk, ref)
        ref.errors = _nan_errors()
        _log(f"[speed] {name}: nsdyn radau at the scene's tolerances ({repeats} runs)", quiet)
        ns = run_nsdyn(
            system,
            m,
            "radau",
            label="nsdyn-radau",
            rtol=solver["rtol"],
            atol=solver["atol"],
            repeats=repeats,
            t_eval=t_eval,
        )
        ns.errors = run_errors(ns, ref)
        runs, best = [], None
        if ns.ok:
            runs, best = scipy_match(
                system,
                m,
                t_eval,
                ref,
                ns.errors["err_x"],
                solver,
                budget_s=budget,
                rtols=QUICK_SCIPY_RTOLS if quick else SCIPY_RTOLS,
                quiet=quiet,
            )
        # time nsdyn again after SciPy's runs (the machine's load drifts over minutes): the
        # median of the runs before and after
        more_ns = run_nsdyn(
            system,
            m,
            "radau",
            rtol=solver["rtol"],
            atol=solver["atol"],
            repeats=repeats,
            t_eval=t_eval,
        )
        if more_ns.ok:
            ns.walls.extend(more_ns.walls)
        if best is not None and not quick and best.wall_s < LONG_RUN_S and SCIPY_REPEATS > 1:
            more = run_scipy_radau(
                system,
                m,
                best.value,
                repeats=SCIPY_REPEATS - 1,
                atol=_scaled_atol(solver["atol"], best.value, solver["rtol"]),
                t_eval=t_eval,
            )
            if more.ok:
                best.walls.extend(more.walls)
        same = next((r for r in runs if r.value == solver["rtol"]), None)
        done = [
            (ref, "reference", (ref.value * ATOL_FACTOR,) * 2),
            (chk, "reference-check", (chk.value * ATOL_FACTOR,) * 2),
            (ns, "nsdyn", (atol_q, atol_v)),
        ]
        for r in runs:
            role = "scipy-matched" if r is best else "scipy-search"
            done.append(
                (r, role, _atol_pair(_scaled_atol(solver["atol"], r.value, solver["rtol"])))
            )
        for r, role, (aq, av) in done:
            rows.append(
                _speed_row(r, name, role, rtol=r.value, atol_q=aq, atol_v=av, window_s=m.duration)
            )
        if best is not None:
            ratio, bound = best.wall_s / ns.wall_s, ""
        else:  # no SciPy run reached the error: its longest (failed) try bounds the ratio
            longest = max((r.wall_s for r in runs), default=float("nan"))
            ratio, bound = longest / ns.wall_s, ">"
        table.append(
            {
                "record": name,
                "window_s": float(m.duration),
                "n_steps": ns.n_steps,
                "wall_s": ns.wall_s,
                "n_timed": len(ns.walls),
                "err_x": ns.errors["err_x"],
                "err_idr": ns.errors["err_idr"],
                "ref_check_err_x": chk.errors["err_x"],
                "ref_check_err_idr": chk.errors["err_idr"],
                "scipy_rtol": best.value if best else float("nan"),
                "scipy_wall_s": best.wall_s if best else float("nan"),
                "scipy_n_timed": len(best.walls) if best else 0,
                "scipy_n_steps": best.n_steps if best else 0,
                "scipy_err_x": best.errors["err_x"] if best else float("nan"),
                "scipy_err_idr": best.errors["err_idr"] if best else float("nan"),
                "ratio": ratio,
                "ratio_bound": bound,
                "scipy_same_tol_wall_s": same.wall_s if same else float("nan"),
                "scipy_same_tol_err_x": same.errors["err_x"] if same else float("nan"),
                "scipy_same_tol_err_idr": same.errors["err_idr"] if same else float("nan"),
                "status": ns.status,
            }
        )
    meta = {
        "scene": cfg.get("_source", "<default scene>"),
        "model": system.name,
        "rtol": solver["rtol"],
        "atol_q": atol_q,
        "atol_v": atol_v,
        "dt_out": solver["dt_out"],
        "pga": pga,
        "repeats": repeats,
        "compile_s": compile_s,
        "cold_compile_s": cold_s,
        "quick": quick,
    }
    for r in rows:
        r.update({k: meta[k] for k in ("compile_s", "cold_compile_s", "quick")})
    for r in table:
        r.update({k: v for k, v in meta.items() if k != "scene"})
    files = {}
    if out is not None:
        out = Path(out)
        files["csv"] = str(write_csv_atomic(out / "speed.csv", rows, _SPEED_FIELDS))
        files["table_csv"] = str(write_csv_atomic(out / "speed-table.csv", table))
        if figures:
            files["figure"] = str(save_figure(speed_figure(rows, table), out / "speed.png"))
    return {"rows": rows, "table": table, "files": files, "meta": meta}


_SPEED_FIELDS = [
    "record",
    "role",
    "label",
    "method",
    "rtol",
    "atol_q",
    "atol_v",
    "status",
    "err_x",
    "err_idr",
    "err_xpeak",
    "err_acc",
    "wall_s",
    "n_timed",
    "n_steps",
    "nfev",
    "x_iso_max_m",
    "idr_max",
    "floor_acc_max_mps2",
    "window_s",
    "compile_s",
    "cold_compile_s",
    "quick",
    "message",
]


def speed_markdown(res: dict) -> str:
    """The speed table as markdown (the README's), with its settings."""
    meta = res["meta"]
    lines = [
        f"{meta['model']}, radau at rtol {meta['rtol']:g}, atol ({meta['atol_q']:g} m, "
        f"{meta['atol_v']:g} m/s), output every {meta['dt_out']:g} s; PGA {meta['pga']:g} m/s²; "
        f"wall = median of {2 * meta['repeats']} runs after compilation ({meta['repeats']} "
        "before SciPy's runs, as many after); errors against radau at "
        f"rtol {SPEED_REF_RTOL:g} (reference check: rtol {SPEED_CHECK_RTOL:g}).",
        "",
        "| record | window | steps | wall [s] | err x_iso | err IDR | reference check "
        "x_iso / IDR | SciPy rtol | SciPy steps | SciPy wall [s] | SciPy err x_iso | "
        "SciPy err IDR | SciPy / nsdyn |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for t in res["table"]:
        sc = (
            f"{t['scipy_rtol']:.0e} | {t['scipy_n_steps']} | {t['scipy_wall_s']:.3g}"
            f"{'' if t['scipy_n_timed'] > 1 else ' (1 run)'} | {t['scipy_err_x']:.1e} | "
            f"{t['scipy_err_idr']:.1e}"
            if np.isfinite(t["scipy_rtol"])
            else "none reached it | | | |"
        )
        lines.append(
            f"| {t['record']} | {t['window_s']:g} s | {t['n_steps']} | {t['wall_s']:.3f} | "
            f"{t['err_x']:.1e} | {t['err_idr']:.1e} | {t['ref_check_err_x']:.0e} / "
            f"{t['ref_check_err_idr']:.0e} | {sc} | {t['ratio_bound']}{t['ratio']:.0f}× |"
        )
    comp = f"compilation (integrate.warmup, this process): {meta['compile_s']:.2f} s"
    if np.isfinite(meta["cold_compile_s"]):
        comp += f"; with an empty numba cache: {meta['cold_compile_s']:.0f} s"
    lines += ["", comp]
    same = [t for t in res["table"] if np.isfinite(t["scipy_same_tol_wall_s"])]
    if same:
        lines.append(
            "SciPy at nsdyn's own tolerances: "
            + "; ".join(
                f"{t['record']} {t['scipy_same_tol_wall_s']:.3g} s, err x_iso "
                f"{t['scipy_same_tol_err_x']:.1e}"
                for t in same
            )
        )
    return "\n".join(lines)


# ---- 5. periodic work-precision ---------------------------------------------------------------
# (A [m/s^2], f [Hz]) cells: f_bis, the first fixed-base mode, between the 2nd and 3rd, and
# above the 4th, where the isolators stick all period. A = 2 m/s^2 at 0.06 Hz is left out: an
# isolator lifts off there (negative normal force), outside the no-uplift model.
PERIODIC_CELLS = [
    (0.5, 0.06),
    (0.5, 0.46),
    (0.5, 1.5),
    (0.5, 4.0),
    (2.0, 0.46),
    (2.0, 1.5),
    (2.0, 4.0),
]
QUICK_PERIODIC_CELLS = [(0.5, 0.46), (2.0, 4.0)]
# every point starts from the orbit at the previous frequency of a 150-point log grid over
# 0.01-10 Hz, as in a sequential continuation (`nsdyn sweep` defaults)
PERIODIC_GUESS_RATIO = 10.0 ** (3.0 / 149.0)
# (label, kind, SDIRK tableau, setting, values): "steps" multiplies the default steps per
# period (Discretisation: n_min 200, dt_max 0.02 s); "tol" is the sweep's steady-state tol
PERIODIC_PLAN = [
    ("shooting sdirk2", "shoot", "sdirk2", "steps", [0.25, 0.5, 1, 2, 4, 8]),
    ("shooting sdirk3", "shoot", "sdirk3", "steps", [0.25, 0.5, 1, 2, 4]),
    ("sweep sdirk2", "sweep", "sdirk2", "tol", [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7]),
    ("sweep sdirk2 4x steps", "sweep", "sdirk2", "tol", [1e-3, 1e-5, 1e-7]),
]
QUICK_PERIODIC_PLAN = [
    ("shooting sdirk2", "shoot", "sdirk2", "steps", [0.5, 2]),
    ("sweep sdirk2", "sweep", "sdirk2", "tol", [1e-3, 1e-5]),
]
PERIODIC_SWEEP_STEPS = {"sweep sdirk2": 1.0, "sweep sdirk2 4x steps": 4.0}
# reference orbit: shooting with (tableau, x default steps, tol); its quantities are those of
# the continuous orbit through it: radau over one period, sampled PERIODIC_SAMPLES times (the
# methods' own values are peaks over their step points, so their sampling error counts)
PERIODIC_REF = ("sdirk3", 16, 1e-9)
PERIODIC_CHECK = ("sdirk3", 32, 1e-9)  # the check: twice the steps, same dense evaluation
PERIODIC_RADAU_RTOL = 1e-10
PERIODIC_SAMPLES = 16384
PERIODIC_REPEATS = 3  # timed runs per point (median) when one takes < PERIODIC_REPEAT_BELOW_S
PERIODIC_REPEAT_BELOW_S = 2.0


def periodic_disc(method: str, factor: float):
    """The default :class:`nsdyn.periodic.Discretisation` with ``factor`` x the steps."""
    from .periodic import Discretisation, refined

    return refined(Discretisation(method=method), factor)


def _orbit_errors(q: dict, ref: dict) -> dict:
    if not q or not np.isfinite(q.get("x_iso", np.nan)):
        return {"err_xbar": float("nan"), "err_idr": float("nan")}
    return {"err_xbar": _rel(q["x_iso"], ref["x_iso"]), "err_idr": _rel(q["idr"], ref["idr"])}


def _periodic_point(problem, f, guess, kind, disc, tol, repeats):
    """One point by shooting or by the steady-state sweep: (row fields, orbit quantities)."""
    from . import periodic as pe

    walls = []
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        if kind == "shoot":
            r = pe.shoot(problem, f, guess, disc=disc, **({} if tol is None else {"tol": tol}))
        else:
            r = pe.steady_state_sweep(problem, f, guess, tol=tol, disc=disc, monodromy=False)
        walls.append(time.perf_counter() - t0)
        if walls[-1] > PERIODIC_REPEAT_BELOW_S:
            break
    if kind == "shoot":
        ok, X = r.converged, r.X
        fields = {"iterations": r.iterations, "residual": r.residual, "message": r.message}
    else:
        ok, X = r.steady, (r.X if r.periods_done > 0 else None)
        fields = {"periods": r.periods, "residual": r.estimate, "message": r.message}
    q = pe.orbit_quantities(problem, f, X) if ok and X is not None else {}
    status = "ok" if ok else ("failed" if kind == "shoot" else "not_steady")
    if q.get("uplift"):
        status = "uplift"
    fields.update(
        status=status,
        n_per_period=int(r.n_steps),
        wall_s=float(np.median(walls)),
        n_timed=len(walls),
        x_bar_iso_m=q.get("x_iso", float("nan")),
        idr=q.get("idr", float("nan")),
    )
    return fields, q, r


def dense_orbit_quantities(problem, f: float, x0: np.ndarray, samples: int = PERIODIC_SAMPLES):
    """Quantities of the continuous orbit through ``x0`` (minimal coordinates): one period of
    radau (rtol PERIODIC_RADAU_RTOL) in the coordinates q with the Baumgarte contacts, sampled
    ``samples`` times. Returns (quantities, closure, wall_s); ``closure`` is |x(T) - x(0)|
    relative to the orbit's excursion (per block, the larger): small when x0 is periodic."""
    from . import periodic as pe
    from .integrate import solve

    m = problem.m
    t = np.linspace(0.0, 1.0 / f, int(samples) + 1)
    P, _ = problem.at(f)
    xq = problem.to_full(x0)
    sol = solve(P, xq, t, method="radau", rtol=PERIODIC_RADAU_RTOL, atol=PERIODIC_RADAU_RTOL * 1e-2)
    Xz = problem.to_minimal(sol.x)
    amp = pe.orbit_amplitudes(problem, Xz)
    d = np.abs(Xz[-1] - Xz[0])
    closure = max(float(d[:m].max()) / amp[0], float(d[m:].max()) / amp[1])
    return pe.orbit_quantities(problem, f, Xz), closure, sol.wall_s


def periodic_bench(
    *,
    quick: bool = False,
    repeats: int | None = None,
    out: Path | None = DEFAULT_OUT,
    figures: bool = True,
    quiet: bool = False,
) -> dict:
    """Work-precision of periodic solutions: shooting (steps per period) and the steady-state
    sweep (its tolerance) on CB-5, errors of x_bar_iso and peak IDR against a tight shooting
    reference, against the wall time of one point (module docstring, "Periodic").

    Returns ``{"rows", "references", "files", "meta"}``; writes ``periodic.csv`` and
    ``periodic.png`` to ``out`` (None: nothing).
    """
    from . import periodic as pe
    from .system import build_system

    repeats = (1 if quick else PERIODIC_REPEATS) if repeats is None else repeats
    cells = QUICK_PERIODIC_CELLS if quick else PERIODIC_CELLS
    plan = QUICK_PERIODIC_PLAN if quick else PERIODIC_PLAN
    system = build_system(bench_frame(), bench_isolation(), fidelity="cb", f_max=5.0)
    t0 = time.perf_counter()
    warm = pe.frame_problem(system, 1.0)
    pe.period_map(warm, warm.x_ref, 1.0, n_steps=4)  # compile or load the period-map kernel
    compile_s = time.perf_counter() - t0 + _warmup(["radau"])
    rows, refs = [], {}
    for A, f in cells:
        problem = pe.frame_problem(system, A)
        f_prev = f / PERIODIC_GUESS_RATIO
        d4 = periodic_disc("sdirk3", 4)
        g = pe.shoot(problem, f_prev, pe.warm_start(problem, f_prev, None, d4), disc=d4)
        guess = g.x0 if g.converged else problem.x_ref.copy()
        cell = {"A_mps2": A, "f_hz": f}
        _log(f"[periodic] A = {A:g} m/s2, f = {f:g} Hz: reference and check", quiet)
        found = {}
        for label, (meth, k, tol) in (
            ("reference", PERIODIC_REF),
            ("reference-check", PERIODIC_CHECK),
        ):
            fields, _, res = _periodic_point(
                problem, f, guess, "shoot", periodic_disc(meth, k), tol, 1
            )
            row = {**cell, "label": label, "method": "shoot", "setting": "steps", "value": k}
            if fields["status"] == "ok":
                q, closure, w = dense_orbit_quantities(problem, f, res.x0)
                fields.update(x_bar_iso_m=q["x_iso"], idr=q["idr"], closure=closure)
                fields["message"] += f"; dense radau evaluation {w:.2g} s"
                found[label] = q
            rows.append({**row, **fields})
        if "reference" not in found:
            _log(f"[periodic] A = {A:g}, f = {f:g}: reference failed", quiet)
            continue
        ref_q = found["reference"]
        agree = _orbit_errors(found.get("reference-check", {}), ref_q)
        rows[-1].update(agree)
        refs[(A, f)] = {"reference": ref_q, "check": agree, "closure": rows[-2]["closure"]}
        for label, kind, meth, setting, values in plan:
            for v in values:
                _log(f"[periodic] A = {A:g}, f = {f:g}: {label} {setting} = {v:g}", quiet)
                if kind == "shoot":
                    disc, tol = periodic_disc(meth, v), None
                else:
                    disc, tol = periodic_disc(meth, PERIODIC_SWEEP_STEPS.get(label, 1.0)), v
                fields, q, _ = _periodic_point(problem, f, guess, kind, disc, tol, repeats)
                rows.append(
                    {
                        **cell,
                        "label": label,
                        "method": kind,
                        "setting": setting,
                        "value": v,
                        **fields,
                        **_orbit_errors(q, ref_q),
                    }
                )
    meta = {"repeats": repeats, "compile_s": compile_s, "quick": quick, "model": system.name}
    for r in rows:
        r.update({k: meta[k] for k in ("repeats", "compile_s", "quick", "model")})
    files = {}
    if out is not None:
        out = Path(out)
        files["csv"] = str(write_csv_atomic(out / "periodic.csv", rows, _PER_FIELDS))
        if figures:
            files["figure"] = str(save_figure(periodic_figure(rows), out / "periodic.png"))
    return {"rows": rows, "references": refs, "files": files, "meta": meta}


_PER_FIELDS = [
    "A_mps2",
    "f_hz",
    "label",
    "method",
    "setting",
    "value",
    "status",
    "err_xbar",
    "err_idr",
    "wall_s",
    "n_timed",
    "n_per_period",
    "iterations",
    "periods",
    "residual",
    "closure",
    "x_bar_iso_m",
    "idr",
    "repeats",
    "compile_s",
    "quick",
    "model",
    "message",
]


def periodic_markdown(res: dict) -> str:
    """The references (with their checks) and the per-setting summary as markdown."""
    ref, chk = PERIODIC_REF, PERIODIC_CHECK
    lines = [
        f"{res['meta']['model']}; reference orbit: shooting {ref[0]} with {ref[1]}x the "
        f"default steps per period (tol {ref[2]:g}); its x̄_iso and IDR from radau (rtol "
        f"{PERIODIC_RADAU_RTOL:g}) over one period, {PERIODIC_SAMPLES} samples; check: the "
        f"same with {chk[1]}x the steps; closure: |x(T) - x(0)| of the radau period.",
        "",
        "| A [m/s²] | f [Hz] | x̄_iso [m] | peak IDR | check x̄_iso / IDR | closure |",
        "|---|---|---|---|---|---|",
    ]
    for (A, f), r in res["references"].items():
        q, c = r["reference"], r["check"]
        lines.append(
            f"| {A:g} | {f:g} | {q['x_iso']:.4g} | {q['idr']:.4g} | {c['err_xbar']:.0e} / "
            f"{c['err_idr']:.0e} | {r['closure']:.0e} |"
        )
    lines += [
        "",
        "| method | setting | points (failed) | worst err x̄_iso | worst err IDR | "
        "median wall per point [s] | longest [s] |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in periodic_summary(res["rows"]):
        setting = f"{r['value']:g}x steps" if r["setting"] == "steps" else f"tol {r['value']:g}"
        lines.append(
            f"| {r['label']} | {setting} | {r['points']} ({r['failed']}) | "
            f"{r['max_err_xbar']:.1e} | {r['max_err_idr']:.1e} | {r['median_wall_s']:.3g} | "
            f"{r['max_wall_s']:.3g} |"
        )
    lines += ["", f"compilation / cache load: {res['meta']['compile_s']:.2f} s"]
    return "\n".join(lines)


def periodic_summary(rows: list[dict]) -> list[dict]:
    """Per method and setting over all cells: the worst errors, the median and the largest
    wall time per point, and how many points failed."""
    out = []
    keys = list(
        dict.fromkeys((r["label"], r["value"]) for r in rows if "reference" not in r["label"])
    )
    for label, v in keys:
        mine = [r for r in rows if r["label"] == label and r["value"] == v]
        ok = [r for r in mine if r["status"] == "ok"]
        out.append(
            {
                "label": label,
                "setting": mine[0]["setting"],
                "value": v,
                "points": len(mine),
                "failed": len(mine) - len(ok),
                "max_err_xbar": max((r["err_xbar"] for r in ok), default=float("nan")),
                "max_err_idr": max((r["err_idr"] for r in ok), default=float("nan")),
                "median_wall_s": float(np.median([r["wall_s"] for r in ok]))
                if ok
                else float("nan"),
                "max_wall_s": max((r["wall_s"] for r in ok), default=float("nan")),
            }
        )
    return out


# ---- figures (drawn by nsdyn.plot) ------------------------------------------------------------
def accuracy_figure(rows, floors, records, window):
    """The work-precision chart of :func:`accuracy_bench`'s rows."""
    from .plot import work_precision_figure

    titles = {r: f"{RECORDS[r]}, {window:g} s, PGA {PGA:g} m/s², CB-5" for r in records}
    return work_precision_figure(
        rows, floors, records, titles=titles, unresolved_factor=UNRESOLVED_FACTOR
    )


def fidelity_figure(rows):
    """The model-ladder chart of :func:`fidelity_bench`'s rows."""
    from . import plot

    return plot.fidelity_figure(rows, method=FIDELITY_METHOD)


def stability_figure(eps_bound, a_bound, cells, drift_hist, shoot_rows):
    """The maps of :func:`stability_bench`."""
    from . import plot

    return plot.stability_figure(
        eps_bound,
        a_bound,
        cells,
        drift_hist,
        shoot_rows,
        methods=STAB_METHODS,
        dt_top=STAB_DT[0],
        alpha_eps=ALPHA_MAP_EPS,
        accurate=ACCURATE_ERR,
    )


def speed_figure(rows, table):
    """The chart of :func:`speed_bench`."""
    from . import plot

    return plot.speed_figure(rows, table)


def periodic_figure(rows):
    """The chart of :func:`periodic_bench`."""
    from .plot import periodic_work_precision_figure

    return periodic_work_precision_figure(rows)


# ---- command line -----------------------------------------------------------------------------
ALL_BENCHES = ["accuracy", "fidelity", "stability", "speed", "periodic"]


def _positive_int(s: str) -> int:
    try:
        v = int(s)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {s!r}") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"expected >= 1, got {s!r}")
    return v


def configure(p: argparse.ArgumentParser) -> None:
    """Arguments of ``nsdyn bench``."""
    p.add_argument(
        "what",
        choices=["accuracy", "fidelity", "stability", "speed", "periodic", "all"],
        help="accuracy: work-precision chart; fidelity: model ladder; stability: step-size, "
        "drift and shooting maps; speed: transient speed table against SciPy; periodic: "
        "work-precision of shooting and the steady-state sweep",
    )
    p.add_argument("--quick", action="store_true", help="short windows and few points (CI)")
    p.add_argument("--out", default=str(DEFAULT_OUT), metavar="DIR", help="output directory")
    p.add_argument(
        "--repeats",
        type=_positive_int,
        default=None,
        metavar="N",
        help=f"timed repeats per point, median quoted (default {REPEATS}; --quick: 1)",
    )
    p.add_argument(
        "--records",
        default="wn,kt",
        metavar="LIST",
        help="accuracy: comma-separated records among wn (white noise), kt (Kanai-Tajimi)",
    )
    p.add_argument(
        "--cold-compile",
        action="store_true",
        help="speed: also time the JIT compilation with an empty numba cache (a few minutes)",
    )
    p.add_argument("--no-figures", action="store_true", help="write the CSV tables only")
    p.add_argument("--json", action="store_true", help="print one JSON summary and nothing else")


def _summary_accuracy(res: dict) -> dict:
    refs = {
        f"{rec}/{law}": {
            "reference": f"{ref.run.method} rtol {ref.run.value:g}",
            "check": None if ref.check is None else f"{ref.check.method} rtol {ref.check.value:g}",
            "agreement_err_x": ref.agreement["err_x"],
            "agreement_err_idr": ref.agreement["err_idr"],
        }
        for (rec, law), ref in res["references"].items()
    }
    fails = [
        {k: r[k] for k in ("record", "label", "setting", "value", "status")}
        for r in res["rows"]
        if r["status"] != "ok"
    ]
    return {"references": refs, "ratios": res["ratios"], "failures": fails, "files": res["files"]}


def _print_accuracy(res: dict) -> None:
    s = _summary_accuracy(res)
    print("references (agreement of the independent check, err_x / err_idr):")
    for k, v in s["references"].items():
        print(
            f"  {k:12s} {v['reference']:18s} check {v['check'] or 'skipped (--quick)':22s} "
            f"{v['agreement_err_x']:.2e} / {v['agreement_err_idr']:.2e}"
        )
    print(
        f"{'record':6s} {'method':12s} {'setting':>12s} {'err_x':>9s} {'err_idr':>9s} "
        f"{'wall [s]':>9s} {'steps':>8s}  status"
    )
    for r in res["rows"]:
        print(
            f"{r['record']:6s} {r['label']:12s} {r['setting']:>5s}={r['value']:<6.0e} "
            f"{r['err_x']:9.2e} {r['err_idr']:9.2e} {r['wall_s']:9.3f} {r['n_steps']:8d}  "
            f"{r['status']}"
        )
    print("speed ratios at matched accuracy (same run; > 1: the second is faster):")
    for rec, qs in s["ratios"].items():
        for name, q in qs.items():
            a, b = name.split("/")
            if not np.isfinite(q["ratio"]):
                print(f"  {rec}: {name}: n/a (no common error level)")
                continue
            extra = " (scipy Radau, NumPy rhs)" if a == "scipy-radau" else ""
            wa, wb = q[a + "_wall_s"], q[b + "_wall_s"]
            print(
                f"  {rec}: {name}{extra} at err_x = {q['err_x']:.2g}: {a} {wa:.3g} s, "
                f"{b} {wb:.3g} s -> {q['ratio']:.3g}x"
            )
    for k, v in s["files"].items():
        print(f"{k}: {v}")


def _print_fidelity(res: dict) -> None:
    print(
        f"{'record':14s} {'model':12s} {'dofs':>5s} {'x_iso':>9s} {'IDR':>9s} {'acc':>9s} "
        f"{'wall [s]':>9s}  status  (errors vs {res['rows'][0]['reference']})"
    )
    for r in res["rows"]:
        print(
            f"{r['record']:14s} {r['model']:12s} {r['n_dof']:5d} {r['err_xpeak']:9.2e} "
            f"{r['err_idr']:9.2e} {r['err_acc']:9.2e} {r['wall_s']:9.3f}  {r['status']}"
        )
    for k, v in res["files"].items():
        print(f"{k}: {v}")


def _print_stability(res: dict) -> None:
    print("largest stable fixed step [s] and the failure the code reported above it:")
    for b in res["eps_boundary"] + res["alpha_boundary"]:
        key = "eps" if b["map"] == "eps" else "alpha"
        print(
            f"  {key}={b[key]:<8.3g} {b['model']:6s} {b['method']:9s} "
            f"{b['dt_max_stable']:9.3g} (err_x there {b['err_x_at_dt_max']:.2g}; accurate "
            f"below {b['dt_max_accurate']:.3g})  failure above: {b['failure_above'] or '-'}"
        )
    print("constraint drift max |R q| [m]:")
    for d in res["drift"]:
        print(
            f"  alpha={d['alpha']:<6.3g} {d['method']:9s} {d['setting']}={d['value']:<6.0e} "
            f"{d['max_abs_Rq_m']:.3e}  {d['status']}"
        )
    sr = [r for r in res["shooting"] if "f_hz" in r]
    if sr:
        bad = [r for r in sr if r["status"] != "converged"]
        print(f"shooting: {len(sr) - len(bad)}/{len(sr)} converged; failures:")
        for r in bad:
            print(f"  f={r['f_hz']:g} Hz A={r['A_mps2']:g} m/s2: {r['reason']}")
    else:
        print(f"shooting: not run ({res['shooting'][0]['message'] if res['shooting'] else ''})")
    g = res["unflagged_garbage"]
    print(f"unflagged garbage cells: {len(g)}")
    for c in g:
        print(
            f"  {c['map']}={c.get(c['map'])} {c['model']} {c['method']} dt={c['dt']:g}: "
            f"err_x {c['err_x']:.2g}"
        )
    for k, v in res["files"].items():
        print(f"{k}: {v}")


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, float | np.floating):
        return float(obj) if np.isfinite(obj) else None
    if isinstance(obj, np.integer):
        return int(obj)
    return obj


def run(args: argparse.Namespace) -> int:
    """Run ``nsdyn bench``; returns the exit status (0 ok, 2 bad arguments)."""
    out = Path(args.out)
    figures = not args.no_figures
    quiet = args.json
    records = tuple(r.strip() for r in args.records.split(",") if r.strip())
    bad = [r for r in records if r not in RECORDS]
    if bad or not records:
        print(
            f"nsdyn bench: error: --records: expected some of {sorted(RECORDS)}, got {bad}",
            file=sys.stderr,
        )
        return 2
    whats = ALL_BENCHES if args.what == "all" else [args.what]
    summary = {}
    for what in whats:
        if what == "accuracy":
            res = accuracy_bench(
                quick=args.quick,
                repeats=args.repeats,
                records=records,
                out=out,
                figures=figures,
                quiet=quiet,
            )
            summary["accuracy"] = _summary_accuracy(res)
            if not args.json:
                _print_accuracy(res)
        elif what == "fidelity":
            res = fidelity_bench(
                quick=args.quick, repeats=args.repeats, out=out, figures=figures, quiet=quiet
            )
            summary["fidelity"] = {
                "rows": [{k: v for k, v in r.items() if k != "message"} for r in res["rows"]],
                "files": res["files"],
            }
            if not args.json:
                _print_fidelity(res)
        elif what == "speed":
            res = speed_bench(
                quick=args.quick,
                repeats=args.repeats,
                out=out,
                figures=figures,
                quiet=quiet,
                cold_compile=getattr(args, "cold_compile", False),
            )
            summary["speed"] = {"table": res["table"], "meta": res["meta"], "files": res["files"]}
            if not args.json:
                print(speed_markdown(res))
                for k, v in res["files"].items():
                    print(f"{k}: {v}")
        elif what == "periodic":
            res = periodic_bench(
                quick=args.quick, repeats=args.repeats, out=out, figures=figures, quiet=quiet
            )
            summary["periodic"] = {
                "summary": periodic_summary(res["rows"]),
                "references": [
                    {"A_mps2": A, "f_hz": f, **{k: v for k, v in r.items() if k != "reference"}}
                    for (A, f), r in res["references"].items()
                ],
                "files": res["files"],
            }
            if not args.json:
                print(periodic_markdown(res))
                for k, v in res["files"].items():
                    print(f"{k}: {v}")
        else:
            res = stability_bench(quick=args.quick, out=out, figures=figures, quiet=quiet)
            summary["stability"] = {
                k: v for k, v in res.items() if k not in ("eps_cells", "alpha_cells")
            }
            if not args.json:
                _print_stability(res)
    if args.json:
        print(json.dumps(_jsonable(summary)))
    return 0


def main(argv: list[str] | None = None) -> int:
    """``python -m nsdyn.bench ...`` (the same as ``nsdyn bench ...``)."""
    parser = argparse.ArgumentParser(prog="nsdyn bench", description=__doc__.splitlines()[0])
    configure(parser)
    return run(parser.parse_args(argv))


if __name__ == "__main__":
    sys.exit(main())
