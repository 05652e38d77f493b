"""Shared settings and machinery of the benchmarks: the scene, timed runs, error measures, CSV.

The scene of every benchmark is the office-11 frame on friction isolators (the seed's design
values: K_lam = 5e4 N/m, c = 1e4 N s/m, mu = 0.03; arctan law with eps = 7500 s/m unless a map
varies it), CB-5 unless a ladder varies it, under the bundled synthetic records, windows scaled
to a horizontal PGA of 3 m/s^2 (vertical component kept, as in the default scene).

Timing
    ``wall_s`` is the integration alone (``TransientResult.wall_s``: JIT compilation or cache
    loading excluded, :func:`nsdyn.solve.integrate.warmup` runs first; response metrics
    excluded), the median of ``repeats`` runs. Runs longer than :data:`LONG_RUN_S` are timed
    once (column ``n_timed``). Speed claims are ratios of timings taken in the same process.

Error measures (:func:`run_errors`, of a run against a reference of the same model)
    ``err_x``     = max over t and isolators of |x_iso - x_iso^ref| / max |x_iso^ref|, on the
                    common output times;
    ``err_idr``   = |IDR_max / IDR_max^ref - 1|;
    ``err_xpeak`` = |max |x_iso| / max |x_iso^ref| - 1|;
    ``err_acc``   = |a_floor,max / a_floor,max^ref - 1|.

A run the integrator reports as failed (``IntegrationError``) keeps its reason as ``status``;
a "successful" run whose history holds NaN/inf or whose energy balance does not close to
ENERGY_CLOSURE_MAX is flagged by the benchmark itself.

Columns of a run's row (:func:`bench_row`)
    ``label``, ``method``, ``law``; ``setting``, ``value`` (``rtol`` or ``dt`` and its
    value); ``status`` ("ok" or the failure's reason) and ``message``; ``wall_s`` (above),
    ``n_timed`` (runs timed), ``n_steps``, ``nfev`` (right-hand-side evaluations); the
    peaks ``x_iso_max_m``, ``idr_max``, ``floor_acc_max_mps2``; ``energy_closure`` = |ΔE −
    (W_in − W_visc − W_fric + W_con)| / max(|W_in|, W_visc + |W_fric|, |ΔE|, E₀), the energy
    balance's relative closure error (``Response.energy``; a run past 0.05 has blown up).

Tables are written through :func:`nsdyn.atomic.atomic_open` (temporary file, then rename).
"""

from __future__ import annotations

import csv
import inspect
import sys
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from nsdyn._checks import AccuracyWarning
from nsdyn.atomic import atomic_open, save_figure
from nsdyn.models.isolated.defaults import C_DAMPER, EPS, F_MAX, K_LAM, MU

__all__ = [
    "ATOL_FACTOR",
    "BenchRun",
    "DEFAULT_OUT",
    "ENERGY_CLOSURE_MAX",
    "EPS",
    "FRAME",
    "K_LAM",
    "LONG_RUN_S",
    "MU",
    "PGA",
    "QUICK_WINDOW_S",
    "RECORDS",
    "REPEATS",
    "WINDOW_S",
    "atol_pair",
    "bench_frame",
    "bench_isolation",
    "bench_motion",
    "bench_row",
    "cb5_system",
    "entry_point",
    "fill_from_response",
    "log",
    "nan_errors",
    "rel_error",
    "run_errors",
    "run_nsdyn",
    "timed_repeats",
    "warmup",
    "write_csv_atomic",
    "write_outputs",
]

# ---- the scene (isolator values: nsdyn.models.isolated.defaults) ------------------------------
FRAME = "office-11"
PGA = 3.0  # m/s^2, horizontal peak ground acceleration
WINDOW_S = 20.0  # s, record window of the accuracy and fidelity charts
QUICK_WINDOW_S = 3.0  # s, window in --quick mode (contains the PGA of both records)
RECORDS = {"wn": "synthetic-wn-40s", "kt": "synthetic-kt-20s"}

# ---- timing and runs --------------------------------------------------------------------------
REPEATS = 3  # timed repeats (median)
LONG_RUN_S = 60.0  # runs longer than this are timed once
DEFAULT_OUT = Path("nsdyn-out") / "bench"
ATOL_FACTOR = 1e-2  # atol = ATOL_FACTOR * rtol [m, m/s] for every adaptive run
ENERGY_CLOSURE_MAX = 0.05  # energy-balance closure error above which a run counts as blown up


# ---- scene factories ---------------------------------------------------------------------------
def bench_frame():
    """The office-11 frame."""
    from nsdyn.structure import load_frame

    return load_frame(FRAME)


def bench_isolation(law: str = "arctan", eps: float = EPS, **changes):
    """The benchmark isolators (K_lam = 5e4, c = 1e4, mu = 0.03) with ``law`` and ``eps``."""
    from nsdyn.models.isolated.system import Isolation

    return Isolation(k_lam=K_LAM, c=C_DAMPER, mu=MU, law=law, eps=eps, **changes)


def cb5_system(frame=None):
    """The CB-5 model (Craig-Bampton at F_MAX = 5 Hz) of ``frame`` on the benchmark isolators."""
    from nsdyn.models.isolated.system import build_system

    frame = bench_frame() if frame is None else frame
    return build_system(frame, bench_isolation(), fidelity="cb", f_max=F_MAX)


def bench_motion(key: str = "wn", window_s: float = WINDOW_S, pga: float = PGA):
    """Bundled record ``RECORDS[key]``, window [0, window_s], scaled to ``pga``."""
    from nsdyn.ground import read_motion

    m = read_motion(RECORDS[key])
    return m.window(m.t0, m.t0 + window_s).scaled_to_pga(pga)


def entry_point(bench: Callable[..., dict]) -> Callable[..., dict]:
    """The uniform ``run_bench(out_dir, quick, **options) -> dict`` of a benchmark function
    ``bench(*, quick, out, **options)`` (the entry :mod:`nsdyn.bench` registers)."""

    def run_bench(out_dir: Path, quick: bool, **options) -> dict:
        return bench(quick=quick, out=out_dir, **options)

    run_bench.__doc__ = f":func:`{bench.__name__}` writing into ``out_dir``; options: OPTIONS."
    # its signature: (out_dir, quick, *, the options of ``bench``), as callers inspect it
    pos = inspect.Parameter.POSITIONAL_OR_KEYWORD
    opts = [p for n, p in inspect.signature(bench).parameters.items() if n not in ("quick", "out")]
    run_bench.__signature__ = inspect.Signature(
        [
            inspect.Parameter("out_dir", pos, annotation="Path"),
            inspect.Parameter("quick", pos, annotation="bool"),
            *opts,
        ],
        return_annotation="dict",
    )
    return run_bench


def timed_repeats(quick: bool, repeats: int | None, default: int = REPEATS) -> int:
    """Timed repeats of a benchmark: ``repeats`` if given, else 1 in --quick mode, else
    ``default``."""
    if repeats is not None:
        return repeats
    return 1 if quick else default


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


def fill_from_response(run: BenchRun, t, x, resp) -> BenchRun:
    """Copy the history and peaks of ``resp`` into ``run``; flag NaN output or an energy
    balance that does not close (ENERGY_CLOSURE_MAX)."""
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
    """Run :func:`nsdyn.solve.transient.simulate` ``repeats`` times; failures become a status.

    ``atol`` defaults to ``ATOL_FACTOR * rtol`` (a number or a pair (displacements,
    velocities) may be given). ``dt`` with an adaptive method (radau, dopri5) steps with that
    fixed dt (no error control). A failure reported by the integrator (``IntegrationError``)
    ends the run with ``status`` = its reason; a "successful" run whose history holds NaN/inf
    or whose energy balance does not close is flagged by the benchmark itself.
    """
    from nsdyn.solve.integrate import METHODS, IntegrationError
    from nsdyn.solve.transient import simulate

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
            with warnings.catch_warnings():  # (coarse on purpose: its error is charted)
                warnings.simplefilter("ignore", AccuracyWarning)
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
    fill_from_response(br, res.t, res.x, res.response)
    if not keep_state:
        br.x = None
    return br


def warmup(methods) -> float:
    """Compile (or load from the numba cache) the kernels of ``methods``; seconds taken."""
    from nsdyn.solve.integrate import warmup as integrate_warmup

    return float(sum(integrate_warmup([m for m in methods if m != "scipy"]).values()))


# ---- error measures ---------------------------------------------------------------------------
def rel_error(a: float, b: float) -> float:
    """|a / b - 1|; 0 when both are 0, inf when only ``b`` is."""
    return abs(a / b - 1.0) if b != 0 else (0.0 if a == 0 else float("inf"))


def nan_errors() -> dict:
    """The error measures of a run that could not be measured."""
    return {k: float("nan") for k in ("err_x", "err_idr", "err_xpeak", "err_acc")}


def run_errors(run: BenchRun, ref: BenchRun, *, flagged: bool = False) -> dict:
    """``err_x`` (history), ``err_idr``, ``err_xpeak`` and ``err_acc`` (peaks) of ``run``.

    NaN for a failed run, unless ``flagged`` (then any run with a full history is measured,
    e.g. one the benchmark's own energy check flagged)."""
    if (not run.ok and not flagged) or run.x_iso is None or run.x_iso.shape != ref.x_iso.shape:
        return nan_errors()
    return {
        "err_x": float(np.max(np.abs(run.x_iso - ref.x_iso)) / ref.x_iso_max),
        "err_idr": rel_error(run.idr_max, ref.idr_max),
        "err_xpeak": rel_error(run.x_iso_max, ref.x_iso_max),
        "err_acc": rel_error(run.floor_acc_max, ref.floor_acc_max),
    }


def atol_pair(atol) -> tuple[float, float]:
    """(displacement, velocity) absolute tolerances of a number or a pair."""
    a = np.atleast_1d(np.asarray(atol, dtype=float))
    return float(a[0]), float(a[-1])


# ---- output -----------------------------------------------------------------------------------
def write_csv_atomic(path: Path, rows: list[dict], fieldnames: list[str] | None = None) -> Path:
    """Write ``rows`` as CSV to a temporary file next to ``path``, then rename it over ``path``.

    ``fieldnames`` defaults to every key in order of first appearance; non-finite floats are
    written as empty cells, other floats with 6 significant digits.
    """
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


def write_outputs(out: Path, tables: dict, chart=None) -> dict[str, str]:
    """Write a benchmark's tables and chart into ``out``; returns ``{key: path}``.

    ``tables``: ``{key: (file name, rows, fieldnames or None)}``, written in order by
    :func:`write_csv_atomic`; ``chart``: None or ``(key, file name, draw)`` with ``draw()``
    returning the figure, saved last through :func:`nsdyn.atomic.save_figure`. An earlier
    run's chart goes before the new tables come (an interrupt between them left it beside
    tables it did not draw).
    """
    out = Path(out)
    if chart is not None:
        (out / chart[1]).unlink(missing_ok=True)
    files = {}
    for key, (name, rows, fieldnames) in tables.items():
        files[key] = str(write_csv_atomic(out / name, rows, fieldnames))
    if chart is not None:
        key, name, draw = chart
        files[key] = str(save_figure(draw(), out / name))
    return files


def _csv_value(v):
    if isinstance(v, float | np.floating):
        return "" if not np.isfinite(v) else f"{float(v):.6g}"
    return v


def log(msg: str, quiet: bool = False) -> None:
    """A progress line on stderr (nothing when ``quiet``)."""
    if not quiet:
        print(msg, file=sys.stderr, flush=True)


def bench_row(run: BenchRun, **extra) -> dict:
    """The CSV row of one run: its setting, outcome, cost and peaks, then ``extra``."""
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
