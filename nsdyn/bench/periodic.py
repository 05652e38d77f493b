"""Work-precision of periodic solutions: shooting and the steady-state sweep on CB-5.

``nsdyn bench periodic`` (``periodic.csv``, ``periodic.png``): CB-5 under the harmonic ground
acceleration ``u_h(t) = A sin(2 pi f t)`` at the (A, f) cells of PERIODIC_CELLS; a periodic
orbit is a fixed point of the period map, ``x(T; x0) = x0`` with ``T = 1/f``. Each point starts
from the orbit at the previous frequency of a 150-point log grid (a sequential continuation's
guess). Shooting (:func:`nsdyn.periodic.shoot`, SDIRK2 / SDIRK3 with a multiple of the default
steps per period) and the steady-state sweep (:func:`nsdyn.periodic.steady_state_sweep`, its
tolerance varied, default steps and 4x): relative errors of the orbit's quantities against
the reference orbit,

    err_xbar = |x_bar_iso / x_bar_iso^ref - 1|,   err_idr = |IDR / IDR^ref - 1|,

(shooting, SDIRK3, 16x steps, its quantities from a densely sampled radau period:
:func:`dense_orbit_quantities`), checked by 32x steps, against the wall time of a point.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from nsdyn.bench import common

__all__ = [
    "dense_orbit_quantities",
    "periodic_bench",
    "periodic_disc",
    "periodic_figure",
    "periodic_markdown",
    "periodic_summary",
    "report",
    "run_bench",
    "summarise",
]

# the command-line options run_bench takes (nsdyn.cli.bench passes only these)
OPTIONS = ("repeats", "figures", "quiet")
FIGURES = ("periodic.png",)  # the figures it draws (removed under --no-figures)

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

# columns of the CSV tables, in order
_PER_FIELDS = (
    "A_mps2 f_hz label method setting value status err_xbar err_idr wall_s n_timed "
    "n_per_period iterations periods residual closure x_bar_iso_m idr repeats compile_s quick "
    "model message"
).split()


def periodic_disc(method: str, factor: float):
    """The default :class:`nsdyn.periodic.Discretisation` with ``factor`` x the steps."""
    from nsdyn.periodic import Discretisation, refined

    return refined(Discretisation(method=method), factor)


def _orbit_errors(q: dict, ref: dict) -> dict:
    if not q or not np.isfinite(q.get("x_iso", np.nan)):
        return {"err_xbar": float("nan"), "err_idr": float("nan")}
    return {
        "err_xbar": common.rel_error(q["x_iso"], ref["x_iso"]),
        "err_idr": common.rel_error(q["idr"], ref["idr"]),
    }


def _periodic_point(problem, f, guess, kind, disc, tol, repeats):
    """One point by shooting or by the steady-state sweep: (row fields, orbit quantities)."""
    from nsdyn import periodic as pe

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
    from nsdyn import periodic as pe
    from nsdyn.solve.integrate import solve

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
    out: Path | None = common.DEFAULT_OUT,
    figures: bool = True,
    quiet: bool = False,
) -> dict:
    """Work-precision of periodic solutions: shooting (steps per period) and the steady-state
    sweep (its tolerance) on CB-5, errors of x_bar_iso and peak IDR against a tight shooting
    reference, against the wall time of one point (module docstring, "Periodic").

    Returns ``{"rows", "references", "files", "meta"}``; writes ``periodic.csv`` and
    ``periodic.png`` to ``out`` (None: nothing).
    """
    from nsdyn import periodic as pe

    repeats = common.timed_repeats(quick, repeats, PERIODIC_REPEATS)
    cells = QUICK_PERIODIC_CELLS if quick else PERIODIC_CELLS
    plan = QUICK_PERIODIC_PLAN if quick else PERIODIC_PLAN
    system = common.cb5_system()
    t0 = time.perf_counter()
    warm = pe.frame_problem(system, 1.0)
    pe.period_map(warm, warm.x_ref, 1.0, n_steps=4)  # compile or load the period-map kernel
    compile_s = time.perf_counter() - t0 + common.warmup(["radau"])
    rows, refs = [], {}
    for A, f in cells:
        problem = pe.frame_problem(system, A)
        f_prev = f / PERIODIC_GUESS_RATIO
        d4 = periodic_disc("sdirk3", 4)
        g = pe.shoot(problem, f_prev, pe.warm_start(problem, f_prev, None, d4), disc=d4)
        guess = g.x0 if g.converged else problem.x_ref.copy()
        cell = {"A_mps2": A, "f_hz": f}
        common.log(f"[periodic] A = {A:g} m/s2, f = {f:g} Hz: reference and check", quiet)
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
            common.log(f"[periodic] A = {A:g}, f = {f:g}: reference failed", quiet)
            continue
        ref_q = found["reference"]
        agree = _orbit_errors(found.get("reference-check", {}), ref_q)
        rows[-1].update(agree)
        refs[(A, f)] = {"reference": ref_q, "check": agree, "closure": rows[-2]["closure"]}
        for label, kind, meth, setting, values in plan:
            for v in values:
                common.log(f"[periodic] A = {A:g}, f = {f:g}: {label} {setting} = {v:g}", quiet)
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
        chart = ("figure", "periodic.png", lambda: periodic_figure(rows)) if figures else None
        files = common.write_outputs(out, {"csv": ("periodic.csv", rows, _PER_FIELDS)}, chart)
    return {"rows": rows, "references": refs, "files": files, "meta": meta}


run_bench = common.entry_point(periodic_bench)


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


def periodic_figure(rows):
    """The chart of :func:`periodic_bench` (drawn by :mod:`nsdyn.plot`)."""
    from nsdyn.plot import periodic_work_precision_figure

    return periodic_work_precision_figure(rows)


def report(res: dict) -> str:
    """The human tables of :func:`periodic_bench`'s result (files excluded)."""
    return periodic_markdown(res)


def summarise(res: dict) -> dict:
    """The JSON summary of :func:`periodic_bench`'s result: per-setting summary, references."""
    return {
        "summary": periodic_summary(res["rows"]),
        "references": [
            {"A_mps2": A, "f_hz": f, **{k: v for k, v in r.items() if k != "reference"}}
            for (A, f), r in res["references"].items()
        ],
        "files": res["files"],
    }
