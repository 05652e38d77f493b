"""Benchmarks: work-precision of the integrators, the fidelity ladder, stability maps.

``nsdyn bench accuracy | fidelity | stability | all [--quick] [--out DIR] [--repeats N]``

The scene of every benchmark is the office-11 frame on friction isolators (K_lam = 5e4 N/m,
c = 1e4 N s/m, mu = 0.03; arctan law with eps = 7500 s/m unless a map varies it) under the
bundled synthetic records, 20 s windows scaled to a horizontal PGA of 3 m/s^2 (vertical
component kept, as in the default scene).

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
    The ladder rigid, CB-5/10/15/20/50/100 under a low-frequency record (the white noise
    low-passed at 2 Hz) and a broadband one (the Kanai-Tajimi record, f95 = 19 Hz), all with
    radau at rtol 1e-6; relative errors of the peaks of x_iso, IDR and absolute floor
    acceleration against CB-100, against wall time. The full model is attempted (see
    FULL_ATTEMPT) and its outcome recorded.

Stability (``stability-*.csv``, ``stability.png``)
    Largest stable fixed step of dopri5 / radau / genalpha / hht / newmark (rigid and CB-5) as
    eps grows and as the Baumgarte alpha grows, scanning dt down by halves from 0.02 s; a cell
    fails if the integrator reports a failure ("flagged:<reason>"), if the benchmark's NaN or
    energy-balance check does ("checked:<reason>": the integrator called it a success), or if
    it lands further than GARBAGE_ERR from the reference ("garbage": nobody flagged it).
    Constraint drift max |R q| with alpha = 0 and 2 pi; cold-start shooting over (f, A).

Plotting lives in the ``_plot_*`` functions at the end (matplotlib imported lazily); they
belong in :mod:`nsdyn.plot` once that module's owner takes them.
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

__all__ = [
    "BenchRun",
    "Reference",
    "accuracy_bench",
    "bench_frame",
    "bench_isolation",
    "bench_motion",
    "configure",
    "fidelity_bench",
    "low_frequency_motion",
    "main",
    "numpy_equations",
    "run",
    "run_nsdyn",
    "run_scipy_radau",
    "stability_bench",
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
# The ladder, cheapest first; the last rung is the reference. The full 435-dof model is
# attempted too (FULL_ATTEMPT) but no nsdyn integrator currently runs it through a record at a
# bearable cost (radau: two 870x870 LUs per step change, hours; genalpha / fixed-step radau:
# Newton fails at the friction kink), so the reference is the richest Craig-Bampton model and
# CB-50 -> CB-100 shows how far the ladder has converged.
LADDER = [
    ("rigid", None),
    ("cb", 5.0),
    ("cb", 10.0),
    ("cb", 15.0),
    ("cb", 20.0),
    ("cb", 50.0),
    ("cb", 100.0),
]
QUICK_LADDER = [("rigid", None), ("cb", 5.0), ("cb", 10.0)]
FIDELITY_METHOD = "radau"  # one integrator for every rung
FIDELITY_RTOL = 1e-6  # time-integration error ~1e-6, far below the fidelity errors
FLOOR_RTOL = 1e-8  # the floor check: FLOOR_RUNG at FIDELITY_RTOL vs at FLOOR_RTOL
FLOOR_RUNG = ("cb", 20.0)
QUICK_FLOOR_RUNG = ("cb", 5.0)
FULL_ATTEMPT = ("genalpha", 1e-3)  # method, dt: the full model's attempt (not in --quick)

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
    repeats: int = REPEATS,
    keep_state: bool = False,
    **options,
) -> BenchRun:
    """Run :func:`nsdyn.transient.simulate` ``repeats`` times; failures become a status.

    ``dt`` with an adaptive method (radau, dopri5) steps with that fixed dt (no error
    control). A failure reported by the integrator (``IntegrationError``) ends the run with
    ``status`` = its reason; a "successful" run whose history holds NaN/inf or whose energy
    balance does not close is flagged by the benchmark itself.
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
        kw["atol"] = rtol * ATOL_FACTOR
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


def run_scipy_radau(
    system, motion, rtol: float, *, repeats: int = REPEATS, label: str = "scipy-radau"
) -> BenchRun:
    """:func:`scipy.integrate.solve_ivp` (Radau) on :func:`numpy_equations`; same outputs."""
    from scipy.integrate import solve_ivp

    from .metrics import response
    from .transient import output_grid

    br = BenchRun(label, "scipy", "arctan", "rtol", float(rtol))
    fun, jac = numpy_equations(system, motion)
    x0, _ = system.static_equilibrium()
    t_eval = output_grid(motion)
    sol = None
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        s = solve_ivp(
            fun,
            (t_eval[0], t_eval[-1]),
            x0,
            method="Radau",
            t_eval=t_eval,
            rtol=rtol,
            atol=rtol * ATOL_FACTOR,
            jac=jac,
        )
        br.walls.append(time.perf_counter() - t0)
        if s.status != 0:
            br.status, br.message = "scipy_failed", s.message
            return br
        sol = sol or s
        if br.walls[-1] > LONG_RUN_S:
            break
    br.n_steps, br.nfev = int(sol.t.size), int(sol.nfev)
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
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}-", suffix=".csv")
    try:
        with os.fdopen(fd, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=fieldnames, extrasaction="ignore")
            w.writeheader()
            for r in rows:
                w.writerow({k: _csv_value(r.get(k, "")) for k in fieldnames})
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def _csv_value(v):
    if isinstance(v, float | np.floating):
        return "" if not np.isfinite(v) else f"{float(v):.6g}"
    return v


def _save_figure(fig, path: Path) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}-", suffix=".png")
    try:
        with os.fdopen(fd, "wb") as fh:
            fig.savefig(fh, format="png", dpi=110)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


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
            fig = _plot_accuracy(rows, floors, records, window)
            files["figure"] = str(_save_figure(fig, out / "accuracy.png"))
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


def fidelity_bench(
    *,
    quick: bool = False,
    repeats: int | None = None,
    out: Path | None = DEFAULT_OUT,
    figures: bool = True,
    quiet: bool = False,
    full_attempt: bool | None = None,
) -> dict:
    """Error of each rung of the model ladder against the reference rung, against its cost.

    Every rung runs with the same integrator (radau, rtol FIDELITY_RTOL), so costs compare
    like with like; the time-integration error is bounded by FLOOR_RUNG at FLOOR_RTOL (row
    ``<rung> rtol 1e-08``, drawn as the floor). The full model is attempted with FULL_ATTEMPT
    (``full_attempt``, default: not in --quick); its row records the outcome.
    """
    from .system import build_system

    repeats = (1 if quick else REPEATS) if repeats is None else repeats
    window = QUICK_WINDOW_S if quick else WINDOW_S
    ladder = QUICK_LADDER if quick else LADDER
    floor_rung = _rung_name(*(QUICK_FLOOR_RUNG if quick else FLOOR_RUNG))
    full_attempt = (not quick) if full_attempt is None else full_attempt
    compile_s = _warmup([FIDELITY_METHOD] + ([FULL_ATTEMPT[0]] if full_attempt else []))
    frame = bench_frame()
    iso = bench_isolation("arctan")
    systems = {}
    for fid, fm in ladder:
        systems[_rung_name(fid, fm)] = build_system(frame, iso, fidelity=fid, f_max=fm or 5.0)
    ref_name = _rung_name(*ladder[-1])
    rows = []
    for rec, motion in fidelity_motions(window).items():
        runs = {}
        for name, system in systems.items():
            _log(f"[fidelity] {rec}: {name} (n = {system.n})", quiet)
            runs[name] = run_nsdyn(
                system, motion, FIDELITY_METHOD, label=name, rtol=FIDELITY_RTOL, repeats=repeats
            )
        ref = runs[ref_name]
        for name, system in systems.items():
            br = runs[name]
            e = run_errors(br, ref) if ref.ok else _nan_errors()
            rows.append(_row(br, record=rec, model=name, n_dof=system.n, reference=ref_name, **e))
        _log(f"[fidelity] {rec}: {floor_rung} at rtol {FLOOR_RTOL:g} (floor check)", quiet)
        tight = run_nsdyn(
            systems[floor_rung],
            motion,
            FIDELITY_METHOD,
            label=floor_rung,
            rtol=FLOOR_RTOL,
            repeats=1,
        )
        e = run_errors(runs[floor_rung], tight) if tight.ok else _nan_errors()
        rows.append(
            _row(
                tight,
                record=rec,
                model=f"{floor_rung} rtol {FLOOR_RTOL:g}",
                n_dof=systems[floor_rung].n,
                reference=f"floor: {floor_rung} at rtol {FIDELITY_RTOL:g} vs {FLOOR_RTOL:g}",
                **e,
            )
        )
        if full_attempt:
            method, dt = FULL_ATTEMPT
            full = build_system(frame, iso, fidelity="full")
            _log(f"[fidelity] {rec}: full (n = {full.n}) with {method}, dt = {dt:g}", quiet)
            br = run_nsdyn(full, motion, method, label="full", dt=dt, repeats=1)
            e = run_errors(br, ref) if ref.ok else _nan_errors()
            rows.append(_row(br, record=rec, model="full", n_dof=full.n, reference=ref_name, **e))
    meta = {
        "window_s": window,
        "repeats": repeats,
        "compile_s": compile_s,
        "quick": quick,
    }
    for r in rows:
        r.update(meta)
    files = {}
    if out is not None:
        out = Path(out)
        files["csv"] = str(write_csv_atomic(out / "fidelity.csv", rows, _FID_FIELDS))
        if figures:
            files["figure"] = str(_save_figure(_plot_fidelity(rows), out / "fidelity.png"))
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
            fig = _plot_stability(eps_bound, a_bound, eps_cells + a_cells, drift_hist, shoot_rows)
            files["figure"] = str(_save_figure(fig, out / "stability.png"))
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


# ---- figures (matplotlib imported lazily; candidates for nsdyn.plot) ---------------------------
_STYLE = {
    "radau": ("C0", "o", "-"),
    "dopri5": ("C1", "v", "-"),
    "genalpha": ("C2", "s", "-"),
    "hht": ("C4", "D", "-"),
    "newmark": ("C5", "P", "-"),
    "event": ("C3", "^", "--"),
    "scipy-radau": ("0.4", "x", ":"),
}


def _plot_accuracy(rows, floors, records, window):
    """Error vs wall time, one line per method; ``floors[(record, law)]`` holds the reference
    checks' agreement (err_x, err_idr), drawn as horizontal lines."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.2 * len(records), 8.0))
    axs = np.atleast_2d(fig.subplots(2, len(records), squeeze=False))
    for j, rec in enumerate(records):
        for i, (col, name) in enumerate((("err_x", "x_iso history"), ("err_idr", "peak IDR"))):
            ax = axs[i, j]
            for label in _STYLE:
                # connected in the order of the setting (loosest first), not of the cost
                run_pts = sorted(
                    (-r["value"], r["wall_s"], r[col])
                    for r in rows
                    if r["record"] == rec
                    and r["label"] == label
                    and r["status"] == "ok"
                    and np.isfinite(r.get(col, np.nan))
                    and r[col] > 0
                )
                pts = [(w, e) for _, w, e in run_pts]
                if not pts:
                    continue
                c, mk, ls = _STYLE[label]
                lab = label + (" (switch model)" if label == "event" else "")
                ax.plot(*zip(*pts, strict=True), ls=ls, marker=mk, color=c, ms=4, label=lab)
                fl = floors.get((rec, "switch" if label == "event" else "arctan"), {})
                low = [p for p in pts if p[1] < UNRESOLVED_FACTOR * fl.get(col, np.nan)]
                if low:
                    ax.plot(*zip(*low, strict=True), ls="", marker=mk, color=c, ms=4, mfc="w")
            for law, ls in (("arctan", ":"), ("switch", "-.")):
                fl = floors.get((rec, law), {})
                if np.isfinite(fl.get(col, np.nan)):
                    ax.axhline(
                        fl[col],
                        color="0.6",
                        ls=ls,
                        lw=0.8,
                        label=f"reference check ({law})",
                    )
            bad = [r for r in rows if r["record"] == rec and r["status"] != "ok"]
            if bad and i == 0:
                ax.text(
                    0.02,
                    0.02,
                    "failed (reported by the code):\n"
                    + "\n".join(
                        f"{r['label']} {r['setting']}={r['value']:g}: {r['status']}" for r in bad
                    ),
                    transform=ax.transAxes,
                    fontsize=6,
                    va="bottom",
                )
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("wall time [s] (after compilation, median)")
            ax.set_ylabel(f"relative error, {name} (hollow: < {UNRESOLVED_FACTOR:g}x check)")
            ax.set_title(f"{RECORDS[rec]}, {window:g} s, PGA {PGA:g} m/s², CB-5", fontsize=9)
            ax.grid(True, which="both", lw=0.3)
    axs[0, 0].legend(fontsize=7)
    fig.tight_layout()
    return fig


def _plot_fidelity(rows):
    from matplotlib.figure import Figure

    recs = list(dict.fromkeys(r["record"] for r in rows))
    fig = Figure(figsize=(5.6 * len(recs), 4.6))
    axs = fig.subplots(1, len(recs), squeeze=False)[0]
    metrics = (
        ("err_xpeak", "x_iso peak", "C0"),
        ("err_idr", "IDR peak", "C2"),
        ("err_acc", "floor acc. peak", "C3"),
    )
    for ax, rec in zip(axs, recs, strict=True):
        mine = [r for r in rows if r["record"] == rec]
        ladder = [
            r for r in mine if not r["model"].startswith("floor") and "rtol" not in r["model"]
        ]
        ok = [r for r in ladder if r["status"] == "ok" and r["model"] != r["reference"]]
        ref = ladder[0]["reference"] if ladder else ""
        for key, name, c in metrics:
            pts = [(r["wall_s"], max(r[key], 1e-9), r["model"]) for r in ok]
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", color=c, ms=4, label=name)
                if key == "err_acc":
                    for w, e, m in pts:
                        ax.annotate(
                            m, (w, e), fontsize=7, xytext=(3, 3), textcoords="offset points"
                        )
        floor = [r for r in mine if "rtol" in r["model"]]
        if floor:
            f0 = np.nanmax([floor[0].get(k, np.nan) for k, _, _ in metrics])
            if np.isfinite(f0):
                ax.axhline(max(f0, 1e-9), color="0.5", ls=":", lw=0.8, label="integration floor")
        ref_wall = next((r["wall_s"] for r in ladder if r["model"] == ref), float("nan"))
        if np.isfinite(ref_wall):
            ax.axvline(ref_wall, color="0.5", ls="--", lw=0.8, label=f"{ref} (reference) cost")
        bad = [r for r in mine if r["status"] != "ok"]
        if bad:
            ax.text(
                0.02,
                0.02,
                "\n".join(f"{r['model']}: {r['status']}" for r in bad),
                transform=ax.transAxes,
                fontsize=7,
                va="bottom",
            )
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(f"wall time [s] ({FIDELITY_METHOD}, rtol {FIDELITY_RTOL:g}, median)")
        ax.set_ylabel(f"relative error of the peak vs {ref}")
        ax.set_title(f"{rec} record", fontsize=9)
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    return fig


def _plot_stability(eps_bound, a_bound, cells, drift_hist, shoot_rows):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 8.5))
    axs = fig.subplots(2, 2)
    for ax, bound, key, xl in (
        (axs[0, 0], eps_bound, "eps", "arctan sharpness eps [s/m]"),
        (axs[0, 1], a_bound, "alpha", f"Baumgarte alpha [1/s] (eps = {ALPHA_MAP_EPS:g})"),
    ):
        for model, ls in (("rigid", "--"), ("cb-5", "-")):
            for method in STAB_METHODS:
                pts = sorted(
                    (b[key], b["dt_max_stable"])
                    for b in bound
                    if b["model"] == model and b["method"] == method
                )
                if not pts:
                    continue
                c, mk, _ = _STYLE[method]
                ax.plot(
                    *zip(*pts, strict=True),
                    ls=ls,
                    marker=mk,
                    color=c,
                    ms=4,
                    label=f"{method} ({model})",
                )
                acc = sorted(
                    (b[key], b["dt_max_accurate"])
                    for b in bound
                    if b["model"] == model and b["method"] == method
                )
                ax.plot(*zip(*acc, strict=True), ls=":", color=c, lw=0.8, alpha=0.7)
        ax.axhline(STAB_DT[0], color="0.5", ls="--", lw=0.6)
        ax.text(
            0.01,
            STAB_DT[0],
            " top of the scanned range",
            fontsize=6,
            va="bottom",
            transform=ax.get_yaxis_transform(),
        )
        chk = [c for c in cells if c["map"] == key and c["outcome"].startswith("checked")]
        if chk:
            ax.plot(
                [c[key] for c in chk],
                [c["dt"] for c in chk],
                "kx",
                ms=6,
                label="success reported, energy check failed",
            )
        bad = [c for c in cells if c["map"] == key and c["outcome"] == "garbage"]
        if bad:
            ax.plot(
                [c[key] for c in bad], [c["dt"] for c in bad], "k*", ms=9, label="unflagged garbage"
            )
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xl)
        ax.set_ylabel(f"largest stable fixed step [s] (dotted: err_x <= {ACCURATE_ERR:g})")
        ax.grid(True, which="both", lw=0.3)
    axs[0, 0].legend(fontsize=6, ncol=2)
    ax = axs[1, 0]
    for (alpha, method, value), (t, Rq) in drift_hist.items():
        ax.semilogy(
            t,
            np.maximum(Rq, 1e-18),
            lw=0.8,
            ls="-" if alpha == 0 else "--",
            label=f"alpha = {alpha:.3g}, {method} {value:g}",
        )
    ax.set_xlabel("t [s]")
    ax.set_ylabel("constraint drift max |R q| [m]")
    ax.legend(fontsize=6)
    ax.grid(True, which="both", lw=0.3)
    ax = axs[1, 1]
    sr = [r for r in shoot_rows if "f_hz" in r]
    if sr:
        for st, mk, c in (("converged", "o", "C2"), ("failed", "x", "C3"), ("error", "s", "k")):
            pts = [(r["f_hz"], r["A_mps2"]) for r in sr if r["status"] == st]
            if pts:
                ax.plot(*zip(*pts, strict=True), mk, color=c, ms=7, ls="", label=st)
        for r in sr:
            if r["status"] != "converged":
                ax.annotate(
                    r["reason"],
                    (r["f_hz"], r["A_mps2"]),
                    fontsize=6,
                    xytext=(3, 3),
                    textcoords="offset points",
                )
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.legend(fontsize=7)
    else:
        msg = shoot_rows[0]["message"] if shoot_rows else "not run"
        ax.text(
            0.5,
            0.5,
            f"periodic module not usable:\n{msg[:80]}",
            ha="center",
            transform=ax.transAxes,
            fontsize=8,
        )
    ax.set_xlabel("forcing frequency f [Hz]")
    ax.set_ylabel("amplitude A [m/s²]")
    ax.set_title("cold-start shooting, CB-5, eps = 7500", fontsize=9)
    fig.tight_layout()
    return fig


# ---- command line -----------------------------------------------------------------------------
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
        choices=["accuracy", "fidelity", "stability", "all"],
        help="accuracy: work-precision chart; fidelity: model ladder; stability: step-size, "
        "drift and shooting maps",
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
    whats = ["accuracy", "fidelity", "stability"] if args.what == "all" else [args.what]
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
