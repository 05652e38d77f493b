"""Benchmark: periodic orbits of the Coulomb model -- error against time per point.

For the office frame (CB-5, seed isolation, A = 0.5 m/s^2) and a single-dof viscous + Coulomb
oscillator under base excitation ``A sin(2 pi f t)``, each frequency's periodic orbit is found
by

- arctan shooting (:func:`nsdyn.periodic.shoot` on :func:`nsdyn.periodic.frame_problem`) at
  several sharpness values eps (the law's smoothing error shrinks like 1/eps);
- switch-model shooting (:func:`nsdyn.periodic.switch.shoot_switch`: exact flow between
  events, saltation matrices, true stick);
- long event-driven integration of the switch model (``nsdyn.simulate(method="event")``)
  from rest for ``PERIODS`` periods (the seed's footnote-3 check).

Error of a point: ``|x_iso / x_iso_ref - 1|`` (half the peak-to-peak isolator slip; where the
reference sticks all period, ``|x_iso| / x_ref`` with ``x_ref`` the largest reference slip of
the curve), the reference being switch shooting at ``REF_TOL`` with ``REF_SAMPLES`` samples,
from the warm start and, where that does not converge, from ``REF_WARMUP`` periods from rest.
A point that did not converge, or whose frequency has no converged reference
(``no_reference_hz``), has no error: the medians are over the measured points
(``measured_points``).
Time per point: wall time of the solve (warm start included, compilation excluded: every
kernel runs once before timing). Medians over the frequencies are charted.

``curve=True`` (``nsdyn bench switch_shooting --curve``) times instead one whole
frequency-response curve of the office frame at ``A_FRAME``, ``CURVE_POINTS`` log-spaced
frequencies from ``CURVE_FMIN`` to ``CURVE_FMAX`` (the sweep's defaults), by sequential
continuation on the switch model and on the arctan law (eps = 7500) in the same run, alternating
the two ``repeats`` times (median wall time); it reports the time per point, how each point was
found, and the largest difference of x_iso between the curves (the smoothing error of arctan),
absolute and relative to the curve's largest x_iso. Writes switch_curve.csv.
"""

from __future__ import annotations

import csv
import math
import time
from pathlib import Path

import numpy as np

from nsdyn.atomic import atomic_open, save_figure
from nsdyn.bench.common import timed_repeats

EPS_LIST = (500.0, 2000.0, 7500.0)  # s/m, arctan sharpness values compared
A_FRAME = 0.5  # m/s^2, frame amplitude (seed Fig. 11)
FRAME_FREQS = (0.06, 0.2, 0.463, 1.0, 1.26, 2.0, 2.95)  # Hz
FRAME_FREQS_QUICK = (0.463, 1.26)
OSC = dict(m=1.0, f_n=1.0, zeta=0.05, mu=0.1, A=2.0)  # oscillator (SI), base amplitude A
OSC_FREQS = (0.3, 0.5, 0.7, 0.9, 1.1, 1.5, 2.0)
OSC_FREQS_QUICK = (0.5, 0.9, 1.5)
PERIODS = 40  # event-driven integration length [periods] (oscillator)
PERIODS_FRAME = 12  # ... frame (quick: 6)
OPTIONS = ("repeats", "curve", "figures")  # options run_bench takes
FIGURES = ("switch_shooting.png",)  # the figures it draws (removed under --no-figures)
CURVE_REPEATS = 3  # timed repeats of each whole curve (--quick: 1)
CURVE_FMIN, CURVE_FMAX, CURVE_POINTS = 0.01, 10.0, 150  # the sweep's default grid
CURVE_POINTS_QUICK = 40
REF_TOL = 1e-10  # reference shooting tolerance
REF_WARMUP = 300  # periods from rest of a second reference try (the first: the warm start's)
REF_SAMPLES = 2000  # samples of the reference orbit per period
EVENT_SAMPLES = 400  # output samples per period of the event-driven runs


def _oscillator(law: str, eps: float = 7500.0):
    from nsdyn.models.isolated.builders import system_from_matrices
    from nsdyn.models.isolated.system import Isolation

    w = 2 * math.pi * OSC["f_n"]
    iso = Isolation(k_lam=0.0, c=0.0, mu=OSC["mu"], law=law, eps=eps)
    m = OSC["m"]
    return system_from_matrices(
        [[m]],
        [[2 * OSC["zeta"] * w * m]],
        [[m * w * w]],
        iso_dofs=[0],
        influence=[1.0],
        isolation=iso,
        weight=m * iso.g,
        levels=[[0]],
        name="1-dof Coulomb oscillator",
    )


def _frame(law: str, eps: float = 7500.0):
    from nsdyn.models.isolated.scene import build_scene, load_scene

    system, _ = build_scene(load_scene(None))
    return system.with_isolation(law=law, eps=eps)


def _x_iso(system, Xfull: np.ndarray) -> float:
    xi = Xfull[:, : system.n] @ system.D.T
    return float(0.5 * np.max(xi.max(axis=0) - xi.min(axis=0)))


def _points(make, A: float, freqs, periods: int) -> tuple[list[dict], float]:
    """All methods at all frequencies of one system, and the seconds of its warm-up (kernels
    compiled or loaded, before any timing)."""
    from nsdyn.ground.excitation import Harmonic
    from nsdyn.periodic import frame_problem, shoot, warm_start
    from nsdyn.periodic.switch import shoot_switch, switch_problem
    from nsdyn.solve.transient import simulate

    rows = []
    sw_sys = make("switch")
    sw = switch_problem(sw_sys, A)
    arcs = {eps: frame_problem(make("arctan", eps), A) for eps in EPS_LIST}
    # compile / load every kernel once before timing (its time returned apart)
    t0 = time.perf_counter()
    shoot_switch(sw, freqs[0], tol=1e-3)
    shoot(arcs[EPS_LIST[0]], freqs[0], tol=1e-3)
    simulate(sw_sys, Harmonic(A, freqs[0]), method="event", n_periods=0.1)
    warmup_s = time.perf_counter() - t0
    for f in freqs:
        T = 1.0 / f
        ref = shoot_switch(sw, f, warm_start(sw, f, None, None), tol=REF_TOL)
        if not ref.converged:  # (office frame, 1.26 Hz: from the short warm start's state)
            ref = shoot_switch(sw, f, warm_start(sw, f, None, None, REF_WARMUP), tol=REF_TOL)
        x_ref = math.nan  # no reference: the frequency's errors are not measured
        if ref.converged:
            pm = sw.period_map(ref.x0, f, n_steps=REF_SAMPLES, sens=False, store=True)
            x_ref = _x_iso(sw_sys, sw.to_full(pm.X))
        found = []
        t0 = time.perf_counter()
        res = shoot_switch(sw, f, warm_start(sw, f, None, None))
        wall = time.perf_counter() - t0
        found.append(("switch shooting", math.nan, wall, res.converged, sw, res))
        for eps, pb in arcs.items():
            t0 = time.perf_counter()
            r = shoot(pb, f, warm_start(pb, f, None, None))
            wall = time.perf_counter() - t0
            found.append(("arctan shooting", eps, wall, r.converged, pb, r))
        for name, eps, wall, ok, pb, r in found:
            x = _x_iso(sw_sys, pb.to_full(r.X)) if r.X is not None else math.nan
            rows.append(
                dict(f=f, method=name, eps=eps, wall_s=wall, converged=ok, x_iso=x, x_ref=x_ref)
            )
        t_ev = np.linspace(0.0, periods * T, periods * EVENT_SAMPLES + 1)
        t0 = time.perf_counter()
        run = simulate(sw_sys, Harmonic(A, f), method="event", t_eval=t_ev)
        wall = time.perf_counter() - t0
        x = _x_iso(sw_sys, run.x[-EVENT_SAMPLES - 1 :])
        rows.append(
            dict(
                f=f,
                method=f"event-driven, {periods} periods",
                eps=math.nan,
                wall_s=wall,
                converged=True,
                x_iso=x,
                x_ref=x_ref,
            )
        )
    scale = max((r["x_ref"] for r in rows if math.isfinite(r["x_ref"])), default=math.nan)
    for r in rows:
        big = r["x_ref"] > 1e-6 * scale
        err = abs(r["x_iso"] / r["x_ref"] - 1) if big else abs(r["x_iso"]) / scale
        # an unconverged result is not an orbit, and a frequency without a converged
        # reference has nothing to measure against: no error (NaN), counted apart
        ok = r["converged"] and math.isfinite(r["x_ref"])
        r["error"] = err if ok else math.nan
    return rows, warmup_s


def _figure(tables: dict):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(tables), figsize=(6 * len(tables), 4.5), squeeze=False)
    for ax, (name, rows) in zip(axes[0], tables.items(), strict=False):
        keys = sorted({(r["method"], r["eps"]) for r in rows}, key=str)
        for method, eps in keys:
            sel = [
                r
                for r in rows
                if r["method"] == method
                and r["eps"] is eps
                or (r["method"] == method and r["eps"] == eps)
            ]
            w = np.median([r["wall_s"] for r in sel])
            errs = [max(r["error"], 1e-16) for r in sel if math.isfinite(r["error"])]
            if not errs:
                continue
            e = np.median(errs)
            label = method if not math.isfinite(eps) else f"{method}, eps = {eps:g}"
            ax.loglog(w, e, "o", ms=8, label=label)
        ax.set_xlabel("time per point [s] (median over frequencies)")
        ax.set_ylabel("relative error of x_iso (median)")
        ax.set_title(name)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def _curves(quick: bool, repeats: int) -> dict:
    """Switch and arctan curves of the office frame, timed alternately ``repeats`` times."""
    from nsdyn.periodic import frame_problem
    from nsdyn.periodic.continuation import continue_range
    from nsdyn.periodic.switch import switch_problem

    points = CURVE_POINTS_QUICK if quick else CURVE_POINTS
    probs = {
        "switch": switch_problem(_frame("switch"), A_FRAME),
        "arctan": frame_problem(_frame("arctan"), A_FRAME),
    }
    for pb in probs.values():  # compile / load the kernels before timing
        continue_range(pb, fmin=0.4, fmax=0.5, points=2)
    walls = {k: [] for k in probs}
    curves = {}
    for _ in range(max(int(repeats), 1)):
        for name, pb in probs.items():
            t0 = time.perf_counter()
            curves[name] = continue_range(
                pb, fmin=CURVE_FMIN, fmax=CURVE_FMAX, points=points, continuation="sequential"
            )
            walls[name].append(time.perf_counter() - t0)
    return {"points": points, "walls": walls, "curves": curves}


def run_curve_bench(out_dir: Path, quick: bool, repeats: int | None = None) -> dict:
    """One full curve on the switch model against the arctan curve; writes switch_curve.csv."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    res = _curves(quick, timed_repeats(quick, repeats, CURVE_REPEATS))
    sw, ar = res["curves"]["switch"].points, res["curves"]["arctan"].points
    xs = np.array([p.quantities.get("x_iso", math.nan) for p in sw])
    xa = np.array([p.quantities.get("x_iso", math.nan) for p in ar])
    n = min(len(xs), len(xa))
    diff = np.abs(xs[:n] - xa[:n])
    k = int(np.nanargmax(diff)) if n else 0
    csv_path = out_dir / "switch_curve.csv"
    with atomic_open(csv_path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(("f", "x_iso_switch", "x_iso_arctan", "method_switch", "method_arctan"))
        for a, b in zip(sw[:n], ar[:n], strict=True):
            qa, qb = a.quantities, b.quantities
            w.writerow((a.f, qa.get("x_iso"), qb.get("x_iso"), a.method, b.method))
    med = {k_: float(np.median(v)) for k_, v in res["walls"].items()}
    methods = {
        name: {m: sum(p.method == m for p in c.points) for m in {p.method for p in c.points}}
        for name, c in res["curves"].items()
    }
    return {
        "csv": str(csv_path),
        "wall_s": time.perf_counter() - t0,
        "points": res["points"],
        "repeats": len(res["walls"]["switch"]),
        "median_curve_s": med,
        "per_point_s": {k_: v / res["points"] for k_, v in med.items()},
        "ratio_switch_to_arctan": med["switch"] / med["arctan"],
        "methods": methods,
        "max_abs_dx_iso_m": float(diff[k]) if n else math.nan,
        "max_rel_dx_iso": float(diff[k] / np.nanmax(xs)) if n else math.nan,
        "f_of_max_dx_iso": float(sw[k].f) if n else math.nan,
    }


def run_bench(
    out_dir: Path,
    quick: bool,
    repeats: int | None = None,
    curve: bool = False,
    figures: bool = True,
) -> dict:
    """Error against time per point for both systems; writes switch_shooting.csv and (with
    ``figures``; else ``"png"`` is None) .png.
    ``curve``: the whole-curve timing instead (:func:`run_curve_bench`)."""
    if curve:
        return run_curve_bench(out_dir, quick, repeats)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    tables = {
        "1-dof viscous + Coulomb oscillator": _points(
            _oscillator, OSC["A"], OSC_FREQS_QUICK if quick else OSC_FREQS, PERIODS
        ),
        f"office frame CB-5, A = {A_FRAME:g} m/s^2": _points(
            _frame,
            A_FRAME,
            FRAME_FREQS_QUICK if quick else FRAME_FREQS,
            PERIODS_FRAME // 2 if quick else PERIODS_FRAME,
        ),
    }
    warmup_s = sum(w for _, w in tables.values())
    tables = {name: rows for name, (rows, _) in tables.items()}
    cols = ("system", "f", "method", "eps", "wall_s", "converged", "x_iso", "x_ref", "error")
    csv_path = out_dir / "switch_shooting.csv"
    with atomic_open(csv_path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        for name, rows in tables.items():
            for r in rows:
                w.writerow([name] + [r[c] for c in cols[1:]])
    png = None
    if figures:
        png = save_figure(_figure(tables), out_dir / "switch_shooting.png", dpi=110)
    summary = {}
    for name, rows in tables.items():
        for method in sorted({(r["method"], r["eps"]) for r in rows}, key=str):
            sel = [
                r
                for r in rows
                if (r["method"], r["eps"]) == method
                or (r["method"] == method[0] and math.isnan(r["eps"]) and math.isnan(method[1]))
            ]
            key = method[0] if math.isnan(method[1]) else f"{method[0]} eps={method[1]:g}"
            errs = [r["error"] for r in sel if math.isfinite(r["error"])]
            summary[f"{name} | {key}"] = {
                "median_wall_s": float(np.median([r["wall_s"] for r in sel])),
                "median_error": float(np.median(errs)) if errs else math.nan,
                "measured_points": len(errs),  # converged, against a converged reference
                "converged": int(sum(bool(r["converged"]) for r in sel)),
                "points": len(sel),
            }
    no_ref = {name: sorted({r["f"] for r in rows if not math.isfinite(r["x_ref"])})
              for name, rows in tables.items()}  # fmt: skip
    out = {
        "csv": str(csv_path),
        "png": None if png is None else str(png),
        "wall_s": time.perf_counter() - t0,
        "warmup_s": warmup_s,  # (in wall_s; in no point's time)
        "methods": summary,
    }
    if any(no_ref.values()):
        out["no_reference_hz"] = {k: v for k, v in no_ref.items() if v}
    return out
