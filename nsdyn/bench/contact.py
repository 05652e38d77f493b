"""Benchmark of the contact family: work-precision of the two solvers, and where each fails.

Work-precision: a prism 0.5 m x 1.5 m (b/h = 1/3) with mu = 0.45 (C = 0) on the bundled
synthetic record (first 20 s, scaled to PGA 7 m/s^2, vertical kept): it lifts off at 0.9988 s,
rocks until 6.1 s and does not slide. Event-driven at rtol 1e-4 ... 1e-10 (atol = 1e-3 rtol)
and Moreau-Jean at h = 4e-3 ... 1e-4 s against an event-driven reference at rtol 1e-12:

    err_theta = max_t |theta - theta_ref| / alpha,   err_slide = max_t |s - s_ref| / b

on the common 0.01 s grid (s: slide of the base midpoint, b: half the base width; the
reference barely slides, 1e-12 m, so a solver's slide error is its spurious slip measured
against the body's size, as the tilt's is against alpha), and err_theta over t <= T_SPLIT:
the two solvers agree to first order in h until 2.2 s, then each converges to its own
history, apart by up to 0.09 alpha, the split forming in near-uplift accumulations of
micro-impacts after 2.2 s (2e-3 alpha at 2.55 s, 1e-2 alpha at 4.0 s; Moreau-Jean at h = 1e-4
and 5e-5 s reach the same 0.090 alpha).
Cost: median wall time of ``repeats`` runs; compilation (or cache loading) is timed apart by a
short first run.

Stability map: free rocking of a 1 m x 2 m block released at theta0 = alpha / 2, friction 10,
Newton restitution e_n in {0, 0.3, 0.6, 0.9}, 4 s.  Moreau-Jean over h, event-driven over
rtol; each run is "ok", "inaccurate" (err_theta > FAIL_ERR against a reference of the same e_n)
or "raised" (the solver detected its own failure: too many events, step underflow, LCP).
"""

from __future__ import annotations

import math
import statistics
import time
from pathlib import Path

import numpy as np

from nsdyn.atomic import save_figure
from nsdyn.bench.common import log, write_csv_atomic

PGA = 7.0  # m/s^2, record PGA of the work-precision run
T_END = 20.0  # s, record window
RTOLS = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)  # event-driven tolerances
HS = (4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1e-4)  # Moreau-Jean steps [s]
REF_RTOL = 1e-12  # reference tolerance (event-driven)
DT_OUT = 0.01  # s, comparison grid
MAP_EN = (0.0, 0.3, 0.6, 0.9)  # restitution coefficients of the stability map
MAP_HS = (1e-2, 3e-3, 1e-3, 3e-4, 1e-4)  # Moreau-Jean steps of the map [s]
MAP_RTOLS = (1e-5, 1e-7, 1e-9, 1e-11)  # event-driven tolerances of the map
MAP_T = 4.0  # s, map runs (hops and accumulations from about 2 s on for e_n >= 0.6)
MAP_MAX_EVENTS = 3000  # event budget of a map run
FAIL_ERR = 0.1  # err_theta above which a map run counts as inaccurate
OPTIONS = ("figures",)  # options run_bench takes
FIGURES = ("contact-wp.png", "contact-map.png")  # the figures it draws (removed under --no-figures)
T_SPLIT = 2.2  # s, the two solvers' limits part in near-threshold accumulations after it


def _wp_setup():
    from nsdyn.ground import read_motion
    from nsdyn.models.contact import BaseMotion, FrictionLaw, RigidBody

    gm = read_motion("synthetic-wn-40s").scaled_to_pga(PGA).window(0.0, T_END)
    body = RigidBody.rectangle(0.5, 1.5, 1000.0)
    return body, FrictionLaw(0.45, 0.45, 0.0), BaseMotion.from_motion(gm)


def _errors(res, ref, alpha: float, b: float, t_max: float = math.inf) -> tuple[float, float]:
    """(err_theta, err_slide) of ``res`` against ``ref`` up to ``t_max`` (module text)."""
    n = min(len(res.t), len(ref.t))
    if n < len(ref.t) or not np.all(np.isfinite(res.q[:n])):
        return math.nan, math.nan
    n = min(n, int(np.searchsorted(ref.t, t_max, side="right")))
    e_th = float(np.max(np.abs(res.q[:n, 2] - ref.q[:n, 2]))) / alpha
    return e_th, float(np.max(np.abs(res.slide[:n] - ref.slide[:n]))) / b


def _timed(run, repeats: int):
    walls, res = [], None
    for _ in range(repeats):
        w0 = time.perf_counter()
        res = run()
        walls.append(time.perf_counter() - w0)
    return res, statistics.median(walls)


def work_precision(quick: bool, repeats: int) -> tuple[list[dict], float, dict]:
    """Rows (solver, setting, wall_s, errors, steps, status), compile_s, reference summary."""
    from nsdyn.models.contact import simulate_event, simulate_moreau

    body, fr, mo = _wp_setup()
    alpha, b = body.corner_geometry()[1], 0.5 * body.width
    w0 = time.perf_counter()
    simulate_event(body, fr, mo, t_end=0.05)
    simulate_moreau(body, fr, mo, t_end=0.05, h=1e-3)
    compile_s = time.perf_counter() - w0
    ref = simulate_event(body, fr, mo, t_end=T_END, rtol=REF_RTOL, atol=1e-3 * REF_RTOL,
                         dt_out=DT_OUT)  # fmt: skip
    rows = []
    settings = [("event", r) for r in (RTOLS[::3] if quick else RTOLS)]
    settings += [("moreau", h) for h in (HS[::2] if quick else HS)]
    for solver, x in settings:
        if solver == "event":
            run = lambda x=x: simulate_event(body, fr, mo, t_end=T_END, rtol=x,  # noqa: E731
                                             atol=1e-3 * x, dt_out=DT_OUT)  # fmt: skip
        else:
            run = lambda x=x: simulate_moreau(body, fr, mo, t_end=T_END, h=x,  # noqa: E731
                                              dt_out=DT_OUT)  # fmt: skip
        try:
            res, wall = _timed(run, repeats)
            (e_th, e_s), early = _errors(res, ref, alpha, b), _errors(res, ref, alpha, b, T_SPLIT)
            rows.append({"solver": solver, "setting": x, "wall_s": wall, "err_theta": e_th,
                         "err_slide": e_s, "err_theta_early": early[0],
                         "n_steps": res.n_steps, "status": "ok"})  # fmt: skip
        except RuntimeError as err:
            rows.append({"solver": solver, "setting": x, "wall_s": math.nan,
                         "err_theta": math.nan, "err_slide": math.nan,
                         "err_theta_early": math.nan, "n_steps": 0,
                         "status": str(err)})  # fmt: skip
        log(f"contact wp: {solver} {x:g}: {rows[-1]['status']}")
    return rows, compile_s, ref.summary()


def _map_reference(body, fr, e_n, theta0):
    """Event-driven at rtol 1e-12, or Moreau-Jean at h = 2e-5 s if the former raises."""
    from nsdyn.models.contact import simulate_event, simulate_moreau

    try:
        return simulate_event(
            body,
            fr,
            t_end=MAP_T,
            e_n=e_n,
            theta0=theta0,
            rtol=1e-12,
            atol=1e-15,
            dt_out=DT_OUT,
            max_events=20 * MAP_MAX_EVENTS,
        ), "event"
    except RuntimeError:
        return simulate_moreau(body, fr, t_end=MAP_T, e_n=e_n, theta0=theta0, h=2e-5,
                               dt_out=DT_OUT), "moreau"  # fmt: skip


def stability_map(quick: bool) -> list[dict]:
    """Rows (solver, e_n, setting, status, err_theta, n_events or steps, wall_s, reason)."""
    from nsdyn.models.contact import FrictionLaw, RigidBody, simulate_event, simulate_moreau

    body = RigidBody.rectangle(1.0, 2.0, 1.0)
    alpha = body.corner_geometry()[1]
    fr = FrictionLaw(10.0)
    th0 = 0.5 * alpha
    rows = []
    ens = MAP_EN[::3] if quick else MAP_EN
    for e_n in ens:
        ref, ref_kind = _map_reference(body, fr, e_n, th0)
        runs = [("moreau", h) for h in (MAP_HS[::2] if quick else MAP_HS)]
        runs += [("event", r) for r in (MAP_RTOLS[::2] if quick else MAP_RTOLS)]
        for solver, x in runs:
            w0 = time.perf_counter()
            try:
                if solver == "event":
                    res = simulate_event(body, fr, t_end=MAP_T, e_n=e_n, theta0=th0, rtol=x,
                                         atol=1e-3 * x, dt_out=DT_OUT,
                                         max_events=MAP_MAX_EVENTS)  # fmt: skip
                    work = len(res.events)
                else:
                    res = simulate_moreau(body, fr, t_end=MAP_T, e_n=e_n, theta0=th0, h=x,
                                          dt_out=DT_OUT)  # fmt: skip
                    work = res.n_steps
                err = _errors(res, ref, alpha, 0.5 * body.width)[0]
                status = "ok" if err <= FAIL_ERR else "inaccurate"
                reason = ""
            except RuntimeError as exc:
                err, work, status, reason = math.nan, 0, "raised", str(exc)
            rows.append({"solver": solver, "e_n": e_n, "setting": x, "status": status,
                         "err_theta": err, "work": work,
                         "wall_s": time.perf_counter() - w0, "reference": ref_kind,
                         "reason": reason})  # fmt: skip
    return rows


def _figure_wp(rows, compile_s):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.5, 4.5), layout="constrained")
    ax = fig.subplots()
    for solver, mk, lab in (("event", "o-", "event-driven (rtol)"),
                            ("moreau", "s-", "Moreau-Jean (h)")):  # fmt: skip
        rr = [r for r in rows if r["solver"] == solver and r["status"] == "ok"]
        w = [r["wall_s"] * 1e3 for r in rr]
        ax.loglog(w, [max(r["err_theta"], 1e-16) for r in rr], mk, label=f"{lab}: θ / α")
        ax.loglog(w, [max(r["err_slide"], 1e-16) for r in rr], mk[0] + "--", mfc="none",
                  label=f"{lab}: slide / b")  # fmt: skip
        ax.loglog(w, [max(r["err_theta_early"], 1e-16) for r in rr], mk[0] + ":", ms=4,
                  label=f"{lab}: θ / α, t ≤ {T_SPLIT:g} s")  # fmt: skip
        for r in rr:
            ax.annotate(f"{r['setting']:.0e}", (r["wall_s"] * 1e3, max(r["err_theta"], 1e-16)),
                        fontsize=7)  # fmt: skip
    ax.set_xlabel("wall time per 20 s run [ms] (median)")
    ax.set_ylabel("max error vs event-driven rtol 1e-12")
    ax.set_title(f"0.5 × 1.5 m prism, μ = 0.45, record PGA {PGA:g} m/s² "
                 f"(compile/load {compile_s:.1f} s apart)", fontsize=9)  # fmt: skip
    ax.legend(fontsize=7)
    return fig


def _figure_map(rows):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 4.0), layout="constrained")
    axes = fig.subplots(1, 2)
    for ax, solver, xlab in ((axes[0], "moreau", "h [s]"), (axes[1], "event", "rtol")):
        rr = [r for r in rows if r["solver"] == solver]
        xs = sorted({r["setting"] for r in rr}, reverse=True)
        es = sorted({r["e_n"] for r in rr})
        img = np.full((len(es), len(xs)), np.nan)
        for r in rr:
            i, j = es.index(r["e_n"]), xs.index(r["setting"])
            if r["status"] != "raised":
                img[i, j] = math.log10(max(r["err_theta"], 1e-12))
            else:
                ax.text(j, i, "raised", ha="center", va="center", fontsize=7, color="red")
            if r["status"] == "inaccurate":
                ax.text(j, i, "✗", ha="center", va="center", fontsize=12, color="k")
        im = ax.imshow(img, origin="lower", aspect="auto", vmin=-8, vmax=0, cmap="viridis")
        ax.set_xticks(range(len(xs)), [f"{x:.0e}" for x in xs], fontsize=7)
        ax.set_yticks(range(len(es)), [f"{e:g}" for e in es])
        ax.set_xlabel(xlab)
        ax.set_ylabel("restitution e_n")
        ax.set_title(f"{solver}: log10 max|θ − θ_ref| / α over {MAP_T:g} s "
                     f"(✗: > {FAIL_ERR:g})", fontsize=8)  # fmt: skip
        fig.colorbar(im, ax=ax)
    return fig


def run_bench(out_dir: Path, quick: bool, figures: bool = True) -> dict:
    """Run the contact benchmark; writes ``contact-wp.csv``, ``contact-map.csv`` and
    (``figures``) the charts ``contact-wp.png``, ``contact-map.png`` into ``out_dir``; returns
    the headline numbers."""
    out_dir = Path(out_dir)
    repeats = 3 if quick else 5
    rows, compile_s, ref = work_precision(quick, repeats)
    maprows = stability_map(quick)
    files = [
        str(write_csv_atomic(out_dir / "contact-wp.csv", rows)),
        str(write_csv_atomic(out_dir / "contact-map.csv", maprows)),
    ]
    if figures:
        files += [
            str(save_figure(_figure_wp(rows, compile_s), out_dir / "contact-wp.png")),
            str(save_figure(_figure_map(maprows), out_dir / "contact-map.png")),
        ]
    ok = [r for r in rows if r["status"] == "ok"]

    def cheapest(solver, tol):
        good = [r for r in ok if r["solver"] == solver and r["err_theta"] <= tol]
        return min((r["wall_s"] for r in good), default=math.nan)

    ev, mj = cheapest("event", 1e-3), cheapest("moreau", 1e-3)
    ev_e = min((r["wall_s"] for r in ok if r["solver"] == "event"
                and r["err_theta_early"] <= 1e-4), default=math.nan)  # fmt: skip
    mj_e = min((r["wall_s"] for r in ok if r["solver"] == "moreau"
                and r["err_theta_early"] <= 1e-4), default=math.nan)  # fmt: skip
    return {
        "compile_s": compile_s,
        "reference": {
            k: ref[k] for k in ("max_tilt_rad", "max_slide_m", "n_impacts", "overturned")
        },
        "wall_ms_err1e-3_event": ev * 1e3,
        "wall_ms_err1e-3_moreau": mj * 1e3,
        "speedup_event_over_moreau_at_err1e-3": mj / ev,
        "speedup_event_over_moreau_at_early_err1e-4": mj_e / ev_e,
        "wp": [
            {
                "solver": r["solver"],
                "setting": r["setting"],
                "wall_ms": r["wall_s"] * 1e3,
                "err_theta": r["err_theta"],
            }
            for r in rows
        ],  # fmt: skip
        "map_failures": [
            {"solver": r["solver"], "e_n": r["e_n"], "setting": r["setting"], "status": r["status"]}
            for r in maprows
            if r["status"] != "ok"
        ],  # fmt: skip
        "files": files,
    }


if __name__ == "__main__":
    import json
    import sys

    t0 = time.perf_counter()
    print(json.dumps(run_bench(Path("nsdyn-out/bench"), "--quick" in sys.argv), indent=1))
    print(f"total {time.perf_counter() - t0:.1f} s", file=sys.stderr)
