"""Spot check of the arctan frequency-amplitude curves with the switch model (seed 004 §6).

The seed computes its periodic solutions (Figs 9-11) with the smooth arctan law (eps = 7500)
and states (footnote 3) that they were verified with the switch model with true stiction.
This script repeats that check on chosen points of the curves, on the seed's setup: office
frame, Craig-Bampton f_max = 5 Hz (13 dofs), K_lam = 5e4 N/m, c = 1e4 N s/m, mu = 0.03,
u''_hor = A sin(2 pi f t).

For every amplitude A:

1. arctan: sequential continuation from 0.01 Hz (:func:`nsdyn.periodic.continue_sequential`,
   shooting with the stepped-sweep fallback) on the log grid of ``nsdyn sweep`` with the spot
   frequencies inserted, so each spot point lies on the branch the sweep follows;
2. switch model: the same system with ``law="switch"`` integrated by the event-driven switch
   integrator (``nsdyn.solve.integrate.solve(method="event")``, true stick) under the
   :class:`nsdyn.Harmonic` ground, one period per call, from the arctan orbit's state at
   t = 0 (``--from-rest``: from the static equilibrium) until the Poincare map is
   stationary: the change of the isolator-slip and column-joint displacement histories from
   one period to the next, relative to their ranges, and its geometric extrapolation (as in
   :func:`nsdyn.periodic.steady_state_sweep`, with the slower of the last two contraction
   rates) must both fall below ``--tol``;
3. both orbits are sampled at the shooting grid (:class:`nsdyn.periodic.Discretisation`) and
   measured by :func:`nsdyn.models.isolated.metrics.response`: x_iso (half the peak-to-peak
   isolator slip, largest isolator), max IDR, max absolute floor acceleration a over every
   level (base included, as in ``nsdyn sweep``) and over the levels above the isolators, and
   whether the isolators stick the whole period (arctan: the sweep's creep criterion; switch:
   no slip mode during the last period).

Points where the arctan curve has no periodic solution (the stepped sweep did not settle)
or its orbit has uplift (a normal force <= 0) are flagged and not integrated. If the event
integrator reports chattering (too many events at one instant), the run continues with
Radau on the switch law (narrow band |v| <= eta = 1e-5 m/s) and the row says so;
``--switch-method radau`` uses that law throughout (a cross-check of the event method).

    python examples/switch_spot_check.py [--quick] [--out FILE.csv] [--amplitudes 0.5,2]
        [--freqs 0.06,0.463] [--tol 1e-4] [--max-periods 300] [--from-rest]
        [--switch-method event|radau]

Writes the CSV atomically and prints a table.
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
import time
from pathlib import Path

import numpy as np

from nsdyn import Harmonic
from nsdyn import periodic as pr
from nsdyn.atomic import atomic_open
from nsdyn.models.isolated.metrics import output_dofs, response
from nsdyn.models.isolated.scene import build_scene, load_scene
from nsdyn.solve.integrate import solve, warmup
from nsdyn.studies.sweep import format_csv_value

AMPLITUDES = (0.1, 0.5, 1.0, 2.0)  # m/s^2, seed Fig. 9
# near f_bis (0.060 Hz), between f_bis and f1, at f1 = 0.463 Hz, 1 Hz, at f2 and f3 (1.26,
# 2.0 Hz: slip at 2 m/s^2 in the seed), near f4 = 2.95 Hz and well above 2.5 Hz
FREQS = (0.06, 0.2, 0.463, 1.0, 1.26, 2.0, 2.95, 5.0)
QUICK_AMPLITUDES = (0.5, 2.0)
QUICK_FREQS = (0.463, 1.26, 2.95)
GRID_POINTS = 150  # the sweep's log grid 0.01-10 Hz (sequential continuation)
QUICK_GRID_POINTS = 40
FMIN, FMAX = 0.01, 10.0
# event integration: the transient runs' defaults for the event method; over three periods
# at 0.463 and 0.06 Hz (A = 0.5 m/s^2) x_iso agrees with rtol 1e-8, atol (1e-10, 1e-9) to 1e-6
RTOL, ATOL = 1e-4, (1e-8, 1e-7)
SS_TOL = 1e-4  # estimated relative distance of the displacement histories to the steady state
MAX_PERIODS = 300
MAX_TIME = 3000.0  # s of simulated time per point
XISO_FLOOR = 1e-6  # m, smallest isolator-slip range used to scale its change
XISO_SLIP = 1e-4  # m, x_iso below this in both models: "stuck" (no relative difference)
EXTRA_STATS = ("n_steps", "n_events")


# ---- arctan: the curve points --------------------------------------------------------------
def arctan_points(system, A: float, freqs, grid_points: int) -> dict:
    """Sequential continuation over the sweep grid plus ``freqs``; the points at ``freqs``."""
    grid = np.union1d(pr.log_frequencies(FMIN, FMAX, grid_points), np.asarray(freqs, float))
    grid = grid[grid <= max(freqs) * (1 + 1e-12)]
    problem = pr.frame_problem(system, A)
    t0 = time.perf_counter()
    curve = pr.continue_sequential(problem, grid)
    wall = time.perf_counter() - t0
    out = {}
    for f in freqs:
        k = int(np.argmin([abs(p.f - f) for p in curve.points]))
        p = curve.points[k]
        if abs(p.f - f) > 1e-9 * f:
            raise RuntimeError(f"continuation skipped f = {f:g} Hz at A = {A:g} m/s^2")
        out[f] = p
    return {"problem": problem, "points": out, "wall_s": wall, "n_grid": grid.size}


def arctan_orbit(problem, pt):
    """The arctan orbit of ``pt`` on the shooting grid: times and full states [q, qd]."""
    pm = pr.period_map(problem, pt.x0, pt.f, sens=False, store=True)
    X = problem.to_full(pm.X)
    t = np.linspace(0.0, 1.0 / pt.f, pm.n_steps + 1)
    return t, X


# ---- switch model: long time integration -----------------------------------------------------
def _displacements(system, X, cache):
    """Isolator slips (nt, ni) and column-joint x displacements (nt, levels * columns)."""
    if "Tj" not in cache:
        od = output_dofs(system.frame)
        cache["Tj"] = system.T[od["joints_x"].ravel()]
    q = X[:, : system.n]
    return q @ system.D.T, q @ cache["Tj"].T


def settle_switch(
    system,
    A: float,
    f: float,
    x0: np.ndarray,
    n_out: int,
    *,
    tol: float = SS_TOL,
    max_periods: int = MAX_PERIODS,
    max_time: float = MAX_TIME,
    method: str = "event",
) -> dict:
    """Integrate the switch model period by period until the displacement histories repeat.

    ``method``: "event" (event-driven, true stick; falls back to Radau when it reports
    chattering) or "radau" (Radau on the switch law's narrow band |v| <= eta throughout).

    Returns the last period (t, X), the modes at its start and its events, the number of
    periods, the last change and estimate, whether it is steady, the method(s) used and cost.
    """
    P = system.params(Harmonic(A, f), law="switch")
    T = 1.0 / f
    kmax = int(max(3, min(max_periods, math.ceil(max_time / T))))
    cache: dict = {}
    x, modes, h0 = np.asarray(x0, float), None, None
    prev = None
    deltas: list[float] = []
    est, delta = math.inf, math.inf
    steady, status = False, "no steady state"
    stats = dict.fromkeys(EXTRA_STATS, 0)
    wall = 0.0
    last = None
    k = 0
    for k in range(1, kmax + 1):
        t = (k - 1) * T + np.linspace(0.0, T, n_out + 1)
        kw = dict(rtol=RTOL, atol=ATOL, uplift="raise", on_failure="return")
        if method == "event":
            sol = solve(P, x, t, method="event", modes0=modes, h0=h0, **kw)
            if sol.status != 0 and "too many switching events" in sol.message:
                # chattering: this period again, and the rest, by Radau on the switch law
                method = "event+radau"
                wall += sol.wall_s
        if method != "event":
            sol = solve(P, x, t, method="radau", **kw)
        wall += sol.wall_s
        stats["n_steps"] += sol.n_steps
        stats["n_events"] += sol.n_events
        if not sol.success:
            status = sol.message
            break
        X = sol.x
        xi, uj = _displacements(system, X, cache)
        if prev is not None:
            dxi = np.max(np.abs(xi - prev[0])) / max(float(np.ptp(xi, axis=0).max()), XISO_FLOOR)
            duj = np.max(np.abs(uj - prev[1])) / max(float(np.ptp(uj, axis=0).max()), 1e-12)
            delta = max(dxi, duj)
            deltas.append(delta)
            if len(deltas) >= 3:
                # contraction per period: the slower of the last two (a fast transient decaying
                # first must not pass for the slow one)
                rho = max(
                    deltas[-1] / max(deltas[-2], 1e-300), deltas[-2] / max(deltas[-3], 1e-300)
                )
                est = delta * min(rho / (1.0 - rho), pr.SS_RHO_CAP) if rho < 1.0 else math.inf
                if (est < tol and delta < tol) or delta < 0.01 * tol:
                    steady, status = True, "steady"
        last = (t, X, modes, sol.events)
        prev = (xi, uj)
        if steady:
            break
        x, modes, h0 = X[-1], sol.modes, sol.h_last
    if not steady and status == "no steady state":
        status = f"no steady state after {k} periods ({k * T:.0f} s)"
    return {
        "last": last,
        "periods": k,
        "delta": delta,
        "estimate": est,
        "steady": steady,
        "status": status,
        "method": method,
        "wall_s": wall,
        **stats,
    }


# ---- metrics -----------------------------------------------------------------------------------
def orbit_metrics(system, P, t, X) -> dict:
    """x_iso (half peak-to-peak), IDR, a (all levels / above the isolators), min normal force."""
    r = response(system, t, X, P)
    xi = r.x_iso
    return {
        "x_iso": float(0.5 * np.max(np.ptp(xi, axis=0))),
        "idr": r.idr_max,
        "a": float(np.max(r.floor_acc_by_level)),
        "a_above": r.floor_acc_max,
        "min_normal_force": r.min_normal_force,
        "stick_share": r.stick_fraction,
    }


def switch_stick_all_period(modes0, events) -> bool:
    """Every isolator stuck at the start of the last period and no switching during it."""
    return modes0 is not None and bool(np.all(np.asarray(modes0) == 0)) and not events


def _rel(a: float, b: float) -> float:
    return (b - a) / a if a else math.nan


def spot_point(
    system, sw_system, A, pt, problem, *, tol, max_periods, max_time, from_rest, method="event"
):
    """One (A, f): the arctan point ``pt`` against the settled switch model."""
    f = pt.f
    q = pt.quantities
    row = {
        "A": A,
        "f": f,
        "arctan_method": pt.method,
        "arctan_converged": bool(pt.converged),
        "arctan_uplift": bool(q.get("uplift")),
        "stick_arctan": q.get("stick_all_period"),
    }
    if not pt.converged:
        row.update(switch_status=f"skipped: no arctan periodic solution ({pt.method})")
        row["stick_arctan"] = None
        return row
    t_a, X_a = arctan_orbit(problem, pt)
    m_a = orbit_metrics(system, system.params(Harmonic(A, f)), t_a, X_a)
    row.update({f"{k}_arctan": v for k, v in m_a.items()})
    row["arctan_uplift"] = row["arctan_uplift"] or bool(m_a["min_normal_force"] <= 0.0)
    if row["arctan_uplift"]:
        row.update(switch_status="skipped: uplift on the arctan orbit")
        return row
    x0 = system.static_equilibrium()[0] if from_rest else X_a[0]
    t0 = time.perf_counter()
    s = settle_switch(
        sw_system,
        A,
        f,
        x0,
        t_a.size - 1,
        tol=tol,
        max_periods=max_periods,
        max_time=max_time,
        method=method,
    )
    row.update(
        switch_method=s["method"],
        switch_status=s["status"],
        steady=s["steady"],
        periods=s["periods"],
        poincare_change=s["delta"],
        poincare_estimate=s["estimate"],
        steps_per_period=s["n_steps"] / max(s["periods"], 1),
        events_per_period=s["n_events"] / max(s["periods"], 1),
        switch_wall_s=time.perf_counter() - t0,
    )
    if s["last"] is None:
        return row
    t_s, X_s, modes0, events = s["last"]
    P_s = sw_system.params(Harmonic(A, f), law="switch")
    m_s = orbit_metrics(sw_system, P_s, t_s, X_s)
    row.update({f"{k}_switch": v for k, v in m_s.items()})
    row["switch_uplift"] = bool(m_s["min_normal_force"] <= 0.0)
    if s["method"] == "event":
        row["stick_switch"] = switch_stick_all_period(modes0, events)
    else:  # Radau on the switch law: its modes at the samples
        row["stick_switch"] = bool(m_s["stick_share"] == 1.0)
    row["events_last_period"] = len(events)
    stuck = (row["stick_arctan"] and row["stick_switch"]) or max(
        m_a["x_iso"], m_s["x_iso"]
    ) < XISO_SLIP
    row["x_iso_rel_diff"] = math.nan if stuck else _rel(m_a["x_iso"], m_s["x_iso"])
    for k in ("idr", "a", "a_above"):
        row[f"{k}_rel_diff"] = _rel(m_a[k], m_s[k])
    return row


# ---- output ------------------------------------------------------------------------------------
COLUMNS = (
    "A",
    "f",
    "arctan_method",
    "arctan_converged",
    "arctan_uplift",
    "switch_method",
    "switch_status",
    "steady",
    "periods",
    "poincare_change",
    "poincare_estimate",
    "x_iso_arctan",
    "x_iso_switch",
    "x_iso_rel_diff",
    "idr_arctan",
    "idr_switch",
    "idr_rel_diff",
    "a_arctan",
    "a_switch",
    "a_rel_diff",
    "a_above_arctan",
    "a_above_switch",
    "a_above_rel_diff",
    "stick_arctan",
    "stick_switch",
    "events_last_period",
    "stick_share_switch",
    "min_normal_force_arctan",
    "min_normal_force_switch",
    "switch_uplift",
    "steps_per_period",
    "events_per_period",
    "switch_wall_s",
)


def write_csv(path: Path, rows: list[dict]) -> None:
    with atomic_open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(COLUMNS)
        for r in rows:
            w.writerow([format_csv_value(r.get(c)) for c in COLUMNS])


def print_table(rows: list[dict], file=sys.stdout) -> None:
    def g(v, fmt):
        if v is None or (isinstance(v, float) and not math.isfinite(v)):
            return "-".rjust(len(fmt % 0.0))
        return fmt % v

    def pct(v):
        return g(None if v is None else 100 * v, "%+.2f%%")

    def yn(v):
        return "-" if v is None or v == "" else ("stick" if v else "slip")

    head = (
        f"{'A':>4} {'f [Hz]':>6} | {'x_iso arctan':>12} {'switch':>10} {'diff':>8} | "
        f"{'IDR arctan':>10} {'diff':>8} | {'a arctan':>8} {'diff':>8} | "
        f"{'a>0 arctan':>10} {'diff':>8} | {'arctan':>6} {'switch':>6} | "
        f"{'periods':>7} {'wall':>6}  note"
    )
    print(head, file=file)
    print("-" * len(head), file=file)
    for r in rows:
        note = "" if r.get("steady") else r.get("switch_status", "")
        if r.get("switch_method", "event") not in ("event", None):
            note = f"{r['switch_method']} {note}".strip()
        print(
            f"{r['A']:4.2g} {r['f']:6.3f} | {g(r.get('x_iso_arctan'), '%12.4g')} "
            f"{g(r.get('x_iso_switch'), '%10.4g')} {pct(r.get('x_iso_rel_diff')):>8} | "
            f"{g(r.get('idr_arctan'), '%10.3e')} {pct(r.get('idr_rel_diff')):>8} | "
            f"{g(r.get('a_arctan'), '%8.3f')} {pct(r.get('a_rel_diff')):>8} | "
            f"{g(r.get('a_above_arctan'), '%10.3f')} {pct(r.get('a_above_rel_diff')):>8} | "
            f"{yn(r.get('stick_arctan')):>6} {yn(r.get('stick_switch')):>6} | "
            f"{g(r.get('periods'), '%7d')} {g(r.get('switch_wall_s'), '%5.1fs')}  {note}",
            file=file,
        )
    print(
        "x_iso: half the peak-to-peak isolator slip; a: peak absolute floor acceleration over "
        "every level (base included, as in nsdyn sweep); a>0: levels above the isolators; "
        "diff = switch / arctan - 1 ('-' where both stick the whole period)",
        file=file,
    )


def _floats(s: str) -> list[float]:
    try:
        v = [float(x) for x in s.split(",") if x.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected numbers separated by commas: {s!r}") from None
    if not v or any(not (x > 0 and math.isfinite(x)) for x in v):
        raise argparse.ArgumentTypeError(f"expected positive numbers: {s!r}")
    return v


WRITTEN: list = []  # the CSV once this run has written its first point


def main(argv: list[str] | None = None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="a subset (A 0.5, 2; f 0.463-2.95 Hz)")
    ap.add_argument("--amplitudes", type=_floats, help="A [m/s^2], default 0.1,0.5,1,2")
    ap.add_argument("--freqs", type=_floats, help="spot frequencies [Hz]")
    from nsdyn.cli.args import out_file
    from nsdyn.cli.args import positive_finite as pos_float
    from nsdyn.cli.args import positive_int as pos_int

    ap.add_argument("--grid-points", type=pos_int, help="continuation grid 0.01-10 Hz (150)")
    ap.add_argument("--tol", type=pos_float, default=SS_TOL, help=f"steady-state test ({SS_TOL:g})")
    ap.add_argument("--max-periods", type=pos_int, default=MAX_PERIODS)
    ap.add_argument("--max-time", type=pos_float, default=MAX_TIME, help="simulated s per point")
    ap.add_argument("--from-rest", action="store_true", help="switch runs from static equilibrium")
    ap.add_argument(
        "--switch-method",
        choices=["event", "radau"],
        default="event",
        help="event-driven (default) or Radau on the switch law's band (slow comparison)",
    )
    ap.add_argument(
        "--out", type=out_file, default="nsdyn-out/switch-spot-check.csv", help="CSV file"
    )
    args = ap.parse_args(argv)
    amps = args.amplitudes or (QUICK_AMPLITUDES if args.quick else AMPLITUDES)
    freqs = sorted(args.freqs or (QUICK_FREQS if args.quick else FREQS))
    grid_points = args.grid_points or (QUICK_GRID_POINTS if args.quick else GRID_POINTS)

    system, _ = build_scene(load_scene(None))  # office-11, CB 5 Hz, seed isolation, arctan
    sw_system = system.with_isolation(law="switch")
    compile_s = sum(warmup(["event", "radau"]).values())
    print(
        f"{system.name}: {len(amps)} amplitudes x {len(freqs)} frequencies; kernels ready "
        f"in {compile_s:.1f} s",
        file=sys.stderr,
    )
    rows = []
    for A in amps:
        arc = arctan_points(system, A, freqs, grid_points)
        print(
            f"A = {A:g}: arctan curve, {arc['n_grid']} points, {arc['wall_s']:.1f} s",
            file=sys.stderr,
        )
        for f in freqs:
            r = spot_point(
                system,
                sw_system,
                A,
                arc["points"][f],
                arc["problem"],
                tol=args.tol,
                max_periods=args.max_periods,
                max_time=args.max_time,
                from_rest=args.from_rest,
                method=args.switch_method,
            )
            rows.append(r)
            print(
                f"  f = {f:g} Hz: {r.get('switch_status')}, {r.get('periods', 0)} periods, "
                f"{r.get('switch_wall_s', 0.0):.1f} s",
                file=sys.stderr,
            )
            write_csv(Path(args.out), rows)
            WRITTEN[:] = [args.out]
    print_table(rows)
    print(f"csv: {args.out}")
    return rows


if __name__ == "__main__":
    from nsdyn.atomic import caused_by_interrupt

    try:
        main()
    except BaseException as exc:  # Ctrl-C inside a kernel reaches Python as numba's SystemError
        if not caused_by_interrupt(exc):
            raise
        if WRITTEN:
            print(f"interrupted: {WRITTEN[0]} holds the points finished before", file=sys.stderr)
        else:  # (it said the CSV held them of none, or of an earlier run's file)
            print("interrupted before the first point finished: no CSV written (one there is "
                  "an earlier run's)", file=sys.stderr)  # fmt: skip
        sys.exit(130)
