"""Seed 004 §6: steady-state (periodic) analysis of the isolated office frame, Figs 9-11.

Office frame (``office-11``), Craig-Bampton f_max = 5 Hz, K_lam = 5e4 N/m, c = 1e4 N s/m,
mu = 0.03, arctan law eps = 7500 s/m (the bundled default scene). Harmonic ground acceleration
A_hor sin(2 pi f t) for A_hor in {0.1, 0.5, 1, 2} m/s^2, f = 0.01-10 Hz, sequential continuation
with shooting and the stepped-sweep fallback (:mod:`nsdyn.periodic`), amplitudes in parallel.

- Fig. 9: IDR, absolute floor acceleration a and isolator displacement x_iso against f;
- Fig. 10: x_iso of the flexible model against the rigid-superstructure model;
- Fig. 11: IDR and a of the isolated frame against the fixed-base frame (python-control FRF)
  at A_hor = 0.5 m/s^2.

Run ``python examples/seed_periodic_study.py [OUT_DIR]``; ``main()`` returns the numbers
reported in docs/guide/periodic.md (curves, findings, timings) without plotting.

``python examples/seed_periodic_study.py --timing [--amplitude 0.5 --repeats 3]`` measures the
speed of one amplitude's curve instead (:func:`timing`): the sweep's worker
(:func:`nsdyn.studies.sweep.amplitude_job`, 150 points 0.01-10 Hz, sequential, one process) repeated
after compilation, wall time per point below and above 0.1 Hz, the share of points made by
the stepped-sweep fallback, and the kernels' compile and cache-load times measured apart in
fresh processes.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from nsdyn.atomic import atomic_open, save_figure
from nsdyn.cli.args import out_dir, positive_finite, positive_int
from nsdyn.models.isolated.scene import load_scene
from nsdyn.periodic import fixed_base_response
from nsdyn.periodic.protocol import A_HIGHEST
from nsdyn.structure import base_isolation_frequency
from nsdyn.studies.sweep import (
    SweepSettings,
    amplitude_job,
    summarise,
    sweep_amplitudes,
)

AMPLITUDES = (0.1, 0.5, 1.0, 2.0)  # m/s^2, seed Fig. 9
POINTS = 150
FMIN, FMAX = 0.01, 10.0
F_LOW = 0.1  # Hz: below, periods of 10-100 s (up to 5000 steps each)


def _arrays(result: dict) -> dict:
    rows = result["rows"]

    def col(k):
        return np.array([np.nan if r[k] in ("", None) else r[k] for r in rows], dtype=float)

    return {
        "f": col("f"),
        "idr": col("IDR"),
        "acc": col("a"),
        "x_iso": col("x_iso"),
        "stick": np.array([r["stick_all_period"] is True for r in rows]),
        "method": np.array([r["method"] for r in rows]),
        "uplift": np.array([r["uplift"] is True for r in rows]),
        "converged": np.array([bool(r["converged"]) for r in rows]),
    }


def findings(curves: dict, rigid: dict, fixed05: dict, f_bis: float) -> dict:
    """The seed's statements about Figs 9-11, as numbers."""
    out = {"f_bis_eq28_hz": f_bis, "amplitudes": {}}
    for A, c in curves.items():
        f, xi, stick = c["f"], c["x_iso"], c["stick"]
        # the peak over the orbits the model holds: converged, no uplift (a normal force <= 0
        # leaves the no-uplift model; the sweep's summary skips those points too)
        low = (f < 0.2) & c["converged"] & ~c["uplift"] & np.isfinite(xi)
        k = int(np.nanargmax(np.where(low, xi, np.nan))) if low.any() else -1
        slip = ~stick
        stick_all_above = None
        if stick[-1]:
            j = len(stick)
            while j > 0 and stick[j - 1]:
                j -= 1
            stick_all_above = float(f[j])
        out["amplitudes"][A] = {
            "x_iso_peak_hz": float(f[k]) if k >= 0 else None,
            "x_iso_peak_m": float(xi[k]) if k >= 0 else None,
            "stick_whole_period_above_hz": stick_all_above,
            "slip_points_above_1hz": int(np.sum(slip & (f > 1.0))),
            "slip_points_below_1hz": int(np.sum(slip & (f <= 1.0))),
            "slip_band_hz": [float(f[slip].min()), float(f[slip].max())] if slip.any() else None,
            "fallback_share": float(np.mean(c["method"] == "sweep")),
            "uplift_band_hz": [float(f[c["uplift"]].min()), float(f[c["uplift"]].max())]
            if c["uplift"].any()
            else None,
            "unconverged_points": int(np.sum(~c["converged"])),
        }
    # Fig. 11 at 0.5 m/s^2: isolated against fixed base
    c = curves[0.5]
    ok = np.isfinite(c["idr"]) & ~c["uplift"]
    fb_idr = np.interp(c["f"], fixed05["f"], fixed05["idr"])
    fb_acc = np.interp(c["f"], fixed05["f"], fixed05["acc"])
    band = ok & (c["f"] >= 0.1) & (c["f"] <= 1.0)
    near = ok & (c["f"] >= 0.04) & (c["f"] <= 0.09)
    out["fig11"] = {
        "idr_peak_ratio_0.1_1hz": float(c["idr"][band].max() / fb_idr[band].max()),
        "acc_peak_ratio_0.1_1hz": float(c["acc"][band].max() / fb_acc[band].max()),
        "share_idr_lower_0.1_1hz": float(np.mean(c["idr"][band] < fb_idr[band])),
        "share_acc_lower_0.1_1hz": float(np.mean(c["acc"][band] < fb_acc[band])),
        "idr_ratio_at_0.46hz": float(np.interp(0.46, c["f"][ok], (c["idr"] / fb_idr)[ok])),
        "acc_ratio_at_0.46hz": float(np.interp(0.46, c["f"][ok], (c["acc"] / fb_acc)[ok])),
        "idr_ratio_near_fbis_max": float(np.max((c["idr"] / fb_idr)[near])),
        "acc_ratio_near_fbis_max": float(np.max((c["acc"] / fb_acc)[near])),
        "stick_points_idr_rel_diff_max_above_2.5hz": float(
            np.max(np.abs(c["idr"] / fb_idr - 1)[ok & c["stick"] & (c["f"] > 2.5)])
        ),
    }
    # Fig. 10: flexible vs rigid x_iso below 0.5 Hz (relative difference, per amplitude)
    out["fig10"] = {}
    for A, c in curves.items():
        r = rigid[A]
        m = (c["f"] <= 0.5) & np.isfinite(c["x_iso"]) & np.isfinite(r["x_iso"]) & ~c["stick"]
        if m.any():
            rel = np.abs(c["x_iso"][m] - r["x_iso"][m]) / c["x_iso"][m]
            out["fig10"][A] = {"median_rel_diff_below_0.5hz": float(np.median(rel))}
    return out


def main(out_dir: str = "nsdyn-out/seed-periodic", workers: int | None = None) -> dict:
    settings = SweepSettings(FMIN, FMAX, POINTS, "sequential", True)
    cfg = load_scene(None)  # office-11, cb 5 Hz, seed isolation, arctan eps 7500
    t0 = time.perf_counter()
    res = sweep_amplitudes(
        cfg, AMPLITUDES, settings, Path(out_dir) / "cb", workers=workers, quiet=True
    )
    t_cb = time.perf_counter() - t0
    rigid_cfg = load_scene(None, {"scene": {"fidelity": "rigid"}})
    res_rigid = sweep_amplitudes(
        rigid_cfg, AMPLITUDES, settings, Path(out_dir) / "rigid", workers=workers, quiet=True
    )
    frame = res[0]["frame"]
    curves = {r["A"]: _arrays(r) for r in res}
    rigid = {r["A"]: _arrays(r) for r in res_rigid}
    fixed = {
        A: fixed_base_response(frame, A, np.geomspace(FMIN, FMAX, 400), f_max=5.0)
        for A in AMPLITUDES
    }
    f_bis = base_isolation_frequency(frame, 5.0e4)
    return {
        "curves": curves,
        "rigid": rigid,
        "fixed": fixed,
        "summaries": [summarise(r) for r in res],
        "findings": findings(curves, rigid, fixed[0.5], f_bis),
        "wall_cb_s": t_cb,
        "timing": {
            r["A"]: {
                "below_0.1Hz_s": r["wall_below_0.1Hz_s"],
                "above_0.1Hz_s": r["wall_above_0.1Hz_s"],
                "total_s": r["wall_s"],
            }
            for r in res
        },
    }


# ---- speed of one curve ---------------------------------------------------------------------
_FIRST_POINT = """
import json, time
t0 = time.perf_counter()
from nsdyn import periodic as pr
from nsdyn.models.isolated.scene import build_scene, load_scene
system, _ = build_scene(load_scene(None))
problem = pr.frame_problem(system, {A})
t1 = time.perf_counter()
pr.continue_sequential(problem, [1.0])  # first point: compiles or loads the kernels
t2 = time.perf_counter()
pr.continue_sequential(problem, [1.0])
t3 = time.perf_counter()
print(json.dumps({{"setup_s": t1 - t0, "first_s": t2 - t1, "again_s": t3 - t2}}))
"""


def _first_point(amplitude: float, cache_dir: str | None) -> dict:
    """Times of a fresh process's first and second curve point (``cache_dir``: an empty numba
    cache, so the kernels compile; None: numba's own cache, so they load)."""
    env = dict(os.environ)
    if cache_dir is not None:
        env["NUMBA_CACHE_DIR"] = cache_dir
    env["PYTHONPATH"] = os.pathsep.join(
        p for p in (str(Path(__file__).resolve().parents[1]), env.get("PYTHONPATH")) if p
    )
    code = _FIRST_POINT.format(A=float(amplitude))
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def timing(amplitude: float = 0.5, repeats: int = 3, points: int = POINTS) -> dict:
    """Wall time of one amplitude's curve after compilation (median of ``repeats``).

    Each repeat is the sweep's worker (:func:`nsdyn.studies.sweep.amplitude_job`: scene build,
    sequential continuation with the fallback, checkpoints) from scratch in this process.
    Compilation is measured apart, in fresh processes: the first point's time minus a second
    point's, with an empty numba cache (compile) and with numba's cache (load).
    """
    cfg = load_scene(None)
    settings = SweepSettings(FMIN, FMAX, points, "sequential", True)
    with tempfile.TemporaryDirectory() as cache:
        cold = _first_point(amplitude, cache)
    _first_point(amplitude, None)  # fills numba's cache if it is empty
    warm = _first_point(amplitude, None)
    runs = []
    with tempfile.TemporaryDirectory() as tmp:
        amplitude_job(cfg, amplitude, SweepSettings(1.0, 2.0, 2), tmp, True, True)  # warm-up
        for _ in range(repeats):
            c0 = time.process_time()
            r = amplitude_job(cfg, amplitude, settings, tmp, restart=True, quiet=True)
            cpu = time.process_time() - c0
            rows = r["rows"]
            f = np.array([x["f"] for x in rows])
            runs.append(
                {
                    "wall_s": r["wall_s"],
                    "cpu_s": cpu,
                    "below_s": r["wall_below_0.1Hz_s"],
                    "above_s": r["wall_above_0.1Hz_s"],
                    "n_below": int(np.sum(f < F_LOW)),
                    "n_above": int(np.sum(f >= F_LOW)),
                    "fallback": int(sum(x["method"] == "sweep" for x in rows)),
                    "points": len(rows),
                }
            )
    med = {k: float(np.median([r[k] for r in runs])) for k in runs[0]}
    return {
        "amplitude": amplitude,
        "points": points,
        "repeats": repeats,
        "runs": runs,
        "wall_s_median": med["wall_s"],
        "wall_s_range": [min(r["wall_s"] for r in runs), max(r["wall_s"] for r in runs)],
        "cpu_s_median": med["cpu_s"],
        "per_point_below_0.1Hz_s": med["below_s"] / max(med["n_below"], 1),
        "per_point_above_0.1Hz_s": med["above_s"] / max(med["n_above"], 1),
        "points_below_0.1Hz": int(med["n_below"]),
        "fallback_share": med["fallback"] / med["points"],
        "compile_s": cold["first_s"] - cold["again_s"],
        "cache_load_s": warm["first_s"] - warm["again_s"],
        "process_setup_s": warm["setup_s"],
    }


def print_timing(t: dict) -> None:
    lo, hi = t["wall_s_range"]
    print(
        f"one curve: A = {t['amplitude']:g} m/s^2, {t['points']} points {FMIN:g}-{FMAX:g} Hz, "
        f"sequential, one process; median of {t['repeats']} after compilation"
    )
    print(f"  wall per curve            {t['wall_s_median']:8.1f} s   (range {lo:.1f}-{hi:.1f})")
    print(f"  CPU time per curve        {t['cpu_s_median']:8.1f} s   (this process)")
    print(
        f"  per point below {F_LOW:g} Hz     {t['per_point_below_0.1Hz_s']:8.3f} s   "
        f"({t['points_below_0.1Hz']} points)"
    )
    print(
        f"  per point above {F_LOW:g} Hz     {t['per_point_above_0.1Hz_s']:8.3f} s   "
        f"({t['points'] - t['points_below_0.1Hz']} points)"
    )
    print(f"  fallback (stepped sweep)  {100 * t['fallback_share']:8.1f} %")
    print(f"  kernel compilation        {t['compile_s']:8.1f} s   (empty numba cache)")
    print(f"  kernel cache load         {t['cache_load_s']:8.1f} s   (per process)")
    print(f"  scene build + imports     {t['process_setup_s']:8.1f} s   (per process)")


def _plot(out: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(3, 3, figsize=(15, 10))
    for A, c0 in out["curves"].items():
        # points with uplift (negative normal force) are outside the model's validity
        c = {
            k: (np.where(c0["uplift"], np.nan, v) if k in ("idr", "acc", "x_iso") else v)
            for k, v in c0.items()
        }
        (ln,) = ax[0, 0].loglog(c["f"], c["idr"], label=f"A = {A:g}")
        ax[1, 0].loglog(c["f"], c["acc"], color=ln.get_color())
        ax[2, 0].loglog(c["f"], np.where(c["stick"], np.nan, c["x_iso"]), color=ln.get_color())
        r = out["rigid"][A]
        ax[0, 1].loglog(
            c["f"],
            np.where(c["stick"], np.nan, c["x_iso"]),
            color=ln.get_color(),
            label=f"flexible A = {A:g}",
        )
        ax[0, 1].loglog(
            r["f"], np.where(r["stick"], np.nan, r["x_iso"]), "--", color=ln.get_color()
        )
    c, fb = out["curves"][0.5], out["fixed"][0.5]
    ax[0, 2].loglog(c["f"], c["idr"], label="isolated")
    ax[0, 2].loglog(fb["f"], fb["idr"], "--", label="fixed base")
    ax[1, 2].loglog(c["f"], c["acc"], label="isolated")
    ax[1, 2].loglog(fb["f"], fb["acc"], "--", label="fixed base")
    ax[0, 0].set_title("Fig. 9 (points with uplift omitted)")
    ax[0, 1].set_title("Fig. 10: x_iso flexible (solid) vs rigid (dashed)")
    ax[0, 2].set_title("Fig. 11: A = 0.5 m/s²")
    for a, lab in zip(ax[:, 0], ("IDR", "a [m/s²]", "x_iso [m]"), strict=True):
        a.set_ylabel(lab)
    for a in ax.ravel():
        a.grid(True, which="both", alpha=0.3)
        a.set_xlabel("f [Hz]")
    ax[0, 0].legend(fontsize=8)
    ax[0, 1].legend(fontsize=7)
    ax[0, 2].legend(fontsize=8)
    ax[2, 1].axis("off")
    ax[2, 2].axis("off")
    ax[1, 1].axis("off")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    save_figure(fig, path, dpi=110)


def amplitude_arg(s: str) -> float:
    """``--amplitude``: a ground acceleration [m/s^2] above 0, at most ``A_HIGHEST`` (what the
    periodic solver takes)."""
    v = positive_finite(s)
    if v > A_HIGHEST:
        raise argparse.ArgumentTypeError(
            f"expected a ground acceleration of at most {A_HIGHEST:g} m/s^2, got {s!r}"
        )
    return v


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description="seed 004 §6: periodic study (Figs 9-11)")
    ap.add_argument("out_dir", nargs="?", type=out_dir, default="nsdyn-out/seed-periodic")
    ap.add_argument("--timing", action="store_true", help="time one amplitude's curve only")
    ap.add_argument("--amplitude", type=amplitude_arg, default=0.5,
                    help=f"--timing: A [m/s^2], above 0, at most {A_HIGHEST:g} (0.5)")  # fmt: skip
    ap.add_argument("--repeats", type=positive_int, default=3, help="--timing: repeats (median)")
    args = ap.parse_args()
    if args.timing:
        t = timing(args.amplitude, args.repeats)
        print_timing(t)
        with atomic_open(Path(args.out_dir) / "timing.json") as fh:
            json.dump(t, fh, indent=1)
        raise SystemExit(0)
    out = main(args.out_dir)
    fig = Path(args.out_dir) / "seed-periodic-figs9-11.png"
    _plot(out, fig)
    print(
        json.dumps(
            {"findings": out["findings"], "timing": out["timing"], "summaries": out["summaries"]},
            indent=1,
            default=str,
        )
    )
    print(f"figure {fig}; the curves' tables in {Path(args.out_dir) / 'cb'} and "
          f"{Path(args.out_dir) / 'rigid'}", file=sys.stderr)  # fmt: skip
