"""``nsdyn sweep``: frequency–amplitude curves of a scene (the work is in nsdyn.studies.sweep).

Isolated scenes (frames, shear buildings, systems from matrices) go to nsdyn.studies.sweep;
``deck`` scenes and ``building3d`` scenes at the rigid fidelity, under a harmonic orbit, to
nsdyn.studies.plane_sweep (:func:`run_plane`). Range, points and amplitudes left out on the
command line take each kind's defaults.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np

from nsdyn._checks import MAX_AMPLITUDES
from nsdyn.atomic import atomic_open, earlier_files, files_of, output_dir, save_figure
from nsdyn.cli.args import (
    above_highest,
    band_message,
    fail,
    forcing_frequency,
    holes,
    json_report,
    old_figures,
    out_dir,
    refinement,
    workers,
)
from nsdyn.cli.args import amplitude_list as _amplitude_list
from nsdyn.cli.args import count as _count
from nsdyn.studies.plane_sweep import KINDS as PLANE_KINDS
from nsdyn.studies.plane_sweep import POINTS_DEFAULT
from nsdyn.studies.sweep import (
    DEFAULT_AMPLITUDES,
    DEFAULT_OUT,
    SweepSettings,
    summarise,
    sweep_amplitudes,
    write_csv,
)


def configure(p: argparse.ArgumentParser) -> None:
    p.set_defaults(command="sweep")  # its messages name it also when run alone (tests)
    p.add_argument(
        "scene", nargs="?", default=None, help="scene TOML (default: the bundled default scene)"
    )
    p.add_argument(
        "--amplitudes",
        type=_amplitude_list,
        default=None,
        metavar="A1,A2,...",
        help=f"excitation amplitudes A_hor [m/s^2], at most {MAX_AMPLITUDES} (default "
        f"{DEFAULT_AMPLITUDES}; deck scenes: the orbit's amplitude, its shape kept; a scene's "
        "harmonic [force]: its amplitude [N])",
    )
    p.add_argument("--fmin", type=forcing_frequency, default=None, metavar="HZ",
                   help="lowest forcing frequency; default 0.01 (deck scenes: f0/4, f0 the "
                   "orbit's frequency; a fixed building3d: f1/4)")  # fmt: skip
    p.add_argument("--fmax", type=forcing_frequency, default=None, metavar="HZ",
                   help="highest forcing frequency; default 10 (deck scenes: 4 f0; a fixed "
                   "building3d: 1.25 x its highest kept mode). Not the "
                   "Craig-Bampton cut-off of nsdyn run --fmax: a sweep takes that from the "
                   "scene's [scene] f_max")  # fmt: skip
    p.add_argument(
        "--points",
        type=_count,
        default=None,
        help=f"log-spaced frequencies (default 150; deck scenes {POINTS_DEFAULT}; a fixed "
        "building3d 400)",
    )
    p.add_argument(
        "--continuation",
        choices=["sequential", "arclength"],
        default="sequential",
        help="sequential (seed) or pseudo-arclength (passes folds); default sequential",
    )
    p.add_argument(
        "--tableau",
        choices=["sdirk2", "sdirk3"],
        default="sdirk2",
        help="SDIRK integrating each period (default sdirk2; sdirk3 pays off with "
        "--steps-factor 2 or more)",
    )
    p.add_argument(
        "--steps-factor",
        type=refinement,
        default=1.0,
        metavar="K",
        help="K x the default steps per period (200 at least, one per 0.02 s), 1 <= K <= "
        "1000; error ~ 1/K^2 with sdirk2 (default 1)",
    )
    p.add_argument(
        "--friction",
        choices=["arctan", "switch"],
        default=None,
        help="friction law of the periodic orbits: the smooth arctan law, or the switch model "
        "with true stick (exact period map with saltation matrices; deck scenes: the stick "
        "disc with located events); default: the scene's",
    )
    p.add_argument(
        "--contact",
        choices=["bilateral", "unilateral"],
        default="bilateral",
        help="uplift points (a normal force <= 0 on the bilateral orbit): flagged (bilateral, "
        "the seed's model) or recomputed with lift-off and landing by a stepped sweep "
        "(unilateral; up to 30 s per point)",
    )
    p.add_argument(
        "--fidelity",
        choices=["fixed", "rigid", "cb", "full"],
        help="override the scene's: rigid, cb or full for isolated scenes; fixed (the linear "
        "steady state) or rigid (the building as a deck) for building3d scenes",
    )
    p.add_argument("--no-fallback", action="store_true", help="skip points shooting misses")
    p.add_argument("--workers", type=workers, default=None, metavar="N", help="parallel processes")
    p.add_argument(
        "--out", type=out_dir, default=DEFAULT_OUT, metavar="DIR", help="output directory"
    )
    p.add_argument("--restart", action="store_true", help="ignore checkpoints, start afresh")
    p.add_argument("--no-figures", action="store_true", help="skip the PNG")
    p.add_argument("--json", action="store_true", help="print one JSON object and nothing else")


def _note_earlier(args, out: Path, before: dict, report: dict) -> None:
    """The files an earlier command left in the folder (:func:`earlier_files`): among the
    report's notes and, without --json, said on stderr."""
    if note := earlier_files(out, before, "sweep"):
        report.setdefault("notes", []).append(note)
        if not args.json:
            print(f"nsdyn sweep: note: {note}", file=sys.stderr)


def _holes(amplitudes: list[dict], path, report=None, say: bool = True) -> int:
    """:func:`nsdyn.cli.args.holes` of a sweep: its points without a steady state, and the
    frequencies a sweep without the fallback skipped (no row: the report lists them)."""
    n_skip = sum(len(s.get("skipped_hz") or []) for s in amplitudes)
    n_rows = sum(s["unconverged_points"] for s in amplitudes)
    n = sum(s["points"] for s in amplitudes) + n_skip
    where = [f"{path} lists each one"] if n_rows else []
    if n_skip:
        where.append(f"{n_skip} frequencies skipped without the fallback (--json lists each "
                     "under skipped_hz)")  # fmt: skip
    return holes("sweep", n_rows + n_skip, n, "points", "; ".join(where), report, say)


def prepare_kernels(friction: str, contact: str = "bilateral") -> float:
    """Compile (or load) the kernels of a sweep in this process before the workers start
    (they then load them from numba's cache), saying on stderr what compiles while it does (a
    first use, or after an upgrade) and how long it took: for a smooth law the period map,
    its right-hand side and Jacobian (which the uplift probe,
    :func:`nsdyn.periodic.problem.uplift_probe`, calls too) and the orbit quantities' kernel,
    for the switch law its exact-flow period map and the system kernels of its tables
    (:mod:`nsdyn.periodic.switch_compile`); with ``contact="unilateral"`` also the event-driven
    loop with lift-off and landing and its metrics, which recompute the uplift points
    (:mod:`nsdyn.periodic.unilateral`). Returns the seconds spent."""
    from nsdyn.solve import methods

    if friction == "switch":
        from nsdyn.periodic import switch_compile

        cold = not switch_compile.kernels_cached()
        what = "the switch model's periodic kernels"
    else:
        from nsdyn.periodic.problem import kernels_cached

        cold = not kernels_cached()
        what = "the periodic kernels"
    uni = contact == "unilateral" and not all(
        methods.is_cached(k) for k in ("unilateral", "metrics-general")
    )
    if cold or uni:
        if uni:
            what = (
                f"{what} and the unilateral-contact loop" if cold else "the unilateral-contact loop"
            )
        print(f"compiling {what} (first use only, cached afterwards)…", file=sys.stderr, flush=True)
    t0 = time.perf_counter()
    if friction == "switch":
        switch_compile.warmup()
    else:
        from nsdyn.periodic.problem import warmup

        warmup()
    if contact == "unilateral":
        methods.warmup_unilateral()
        methods.warmup_metrics(False)
    spent = time.perf_counter() - t0
    if cold or uni:
        print(f"  compiled in {spent:.1f} s", file=sys.stderr, flush=True)
    return spent


def run(args: argparse.Namespace) -> int:
    from nsdyn.models.isolated.scene import SceneError, load_scene
    from nsdyn.models.scenefile import number, read_toml, scene_kind
    from nsdyn.periodic import fixed_base_response, log_frequencies
    from nsdyn.studies.sweep import SWITCH_A_NOTE, unused_scene_notes

    if args.scene is not None:
        try:
            raw = read_toml(args.scene)
            kind = scene_kind(raw, str(args.scene))
        except SceneError as e:
            return fail(args, e)
        st = raw.get("structure") if isinstance(raw.get("structure"), dict) else {}
        if kind == "building3d" and (args.fidelity or st.get("fidelity")) == "fixed":
            from nsdyn.cli.sweep_fixed3d import run_fixed3d  # linear: the exact steady state

            return run_fixed3d(args, {**raw, "structure": {**st, "fidelity": "fixed"}})
        if kind in PLANE_KINDS:
            return run_plane(args, raw)
        if kind != "isolated":
            return fail(
                args,
                f"{args.scene}: scene.kind: sweeps take isolated, deck and "
                f"building3d scenes, got {kind!r}",
            )
    given = (args.fmin is not None, args.fmax is not None)
    args.fmin = 0.01 if args.fmin is None else args.fmin
    args.fmax = 10.0 if args.fmax is None else args.fmax
    args.points = 150 if args.points is None else args.points
    overrides = {"scene": {"fidelity": args.fidelity}} if args.fidelity else None
    try:
        cfg = load_scene(args.scene, overrides)
    except SceneError as e:
        return fail(args, e)
    if args.fidelity and "structure" in cfg:  # (it named scene.fidelity, which was not given)
        return fail(args, f"{args.scene}: --fidelity: chooses among a frame's models; this "
                    "scene gives its [structure] directly, which is used as given")  # fmt: skip
    if cfg["scene"].get("fidelity", "cb") == "fixed":
        where = "--fidelity fixed" if args.fidelity else f"{args.scene}: scene.fidelity"
        return fail(args, f"{where}: the fixed-base model is linear; use an isolated fidelity")
    force = cfg.get("force", {})
    mo = cfg.get("motion", {}) if cfg.get("motion", {}).get("kind") == "harmonic" else {}
    table = "force" if "amplitude" in force else "motion" if "amplitude" in mo else None
    where = "--amplitudes" if args.amplitudes else f"{args.scene}: {table}.amplitude"
    if not args.amplitudes and table:  # a harmonic scene: its amplitude [N or m/s²]
        amp = number(str(args.scene), f"{table}.amplitude", (force or mo)["amplitude"],
                     positive=False)  # fmt: skip
        if not abs(amp) > 0:
            return fail(args, f"{args.scene}: {table}.amplitude: 0 sweeps nothing; give a "
                        "non-zero amplitude or --amplitudes")  # fmt: skip
        args.amplitudes = [abs(amp)]
    args.amplitudes = args.amplitudes or _amplitude_list(DEFAULT_AMPLITUDES)
    if table != "force" and (why := above_highest(args.amplitudes, where, "sweep")):
        return fail(args, why)
    friction = args.friction or cfg.get("isolation", {}).get("law", "arctan")
    if args.friction:  # the flag wins over the scene's law (its eps and the rest kept)
        cfg.setdefault("isolation", {})["law"] = args.friction
    if args.contact == "unilateral" and friction == "switch":  # (a traceback after the curve)
        law = "--friction switch" if args.friction else f"{args.scene}: isolation.law 'switch'"
        return fail(args, f"--contact unilateral: its lift-off orbits are shot on the arctan "
                    f"law, got {law}; expected --friction arctan")  # fmt: skip
    if not args.fmax > args.fmin:
        return fail(args, band_message("sweep", args.fmin, args.fmax, given))
    notes = unused_scene_notes(raw, bool(mo), args.contact) if args.scene else []
    notes += [SWITCH_A_NOTE] * (friction == "switch")
    for note in notes if not args.json else ():
        print(f"nsdyn sweep: note: {note}", file=sys.stderr)  # (before the run, as it goes)
    settings = SweepSettings(
        args.fmin,
        args.fmax,
        args.points,
        args.continuation,
        not args.no_fallback,
        args.tableau,
        args.steps_factor,
        "switch" if friction == "switch" else "arctan",
        args.contact,
    )
    with output_dir(Path(args.out), "sweep") as out:  # (none left empty by a failure)
        before = files_of(out)
        compile_s = prepare_kernels(settings.friction, settings.contact)  # apart from its wall
        t0 = time.perf_counter()
        results = sweep_amplitudes(cfg, args.amplitudes, settings, out, workers=args.workers,
                                   restart=args.restart, quiet=args.json)  # fmt: skip
        csv_path = out / "sweep.csv"
        gone = old_figures(out, ["sweep.png"], "sweep", args)  # (redrawn after the table)
        write_csv(csv_path, results)
        report = {
            "model": results[0]["model"],
            "csv": str(csv_path),
            "settings": asdict(settings),
            "wall_s": time.perf_counter() - t0,
            "compile_s": compile_s,
            "amplitudes": [summarise(r) for r in results],
            **({"notes": notes + [gone] * bool(gone)} if notes or gone else {}),  # (said)
        }
        if not args.no_figures:
            freqs = log_frequencies(args.fmin, args.fmax, 300)
            frame, fm = results[0]["frame"], results[0]["f_max"] or 5.0
            fixed = None  # the fixed-base reference needs a frame and a ground acceleration
            if frame is not None and table != "force":
                amps = [r["A"] for r in results]  # linear: one solve for every amplitude
                resp = fixed_base_response(frame, amps, freqs, f_max=fm)
                fixed = dict(zip(amps, resp, strict=True))
            fig_path = out / "sweep.png"
            from nsdyn.plot import sweep_figure

            save_figure(sweep_figure(results, fixed), fig_path, dpi=120)
            report["figure"] = str(fig_path)
        _note_earlier(args, out, before, report)
    if args.json:  # (its holes' status and line first, in the report)
        status = _holes(report["amplitudes"], csv_path, report)
        print(json_report(report, default=float))
        return status
    print(
        f"model {report['model']}: {settings.points} frequencies "
        f"{settings.fmin:.10g}-{settings.fmax:.10g} Hz, {settings.continuation} continuation"
        + (" (the curve's points: its own steps)" if settings.continuation == "arclength" else "")
    )
    unit = "[N]   " if "force" in cfg else "[m/s²]"  # a harmonic force's amplitude, or A_hor
    print(
        f"   A {unit}  points  fallback  uplift  unstable  stick above [Hz]  x_iso max [m]  "
        "wall [s]"
    )

    def g(v, fmt):
        return "-" if v is None else format(v, fmt)

    for s in report["amplitudes"]:
        print(
            f"   {s['A']:8.5g}  {s['points']:6d}  {s['fallback_points']:8d}  "
            f"{s['uplift_points']:6d}  {s['unstable_points']:8d}  "
            f"{g(s['stick_all_period_above_hz'], '.3g'):>16s}  {g(s['x_iso_max_m'], '.4g'):>13s}  "
            f"{s['wall_s']:8.1f}"
        )
    if any(s["stick_all_period_above_hz"] is not None for s in report["amplitudes"]):
        n = max(s["points"] for s in report["amplitudes"])  # (arclength: the curve's own)
        print(f"   (stick above: the curve's points above it stick the whole period; a slip "
              f"band between two of its {n} points is not seen)")  # fmt: skip
    if any(s["uplift_points"] for s in report["amplitudes"]):
        print(
            "   (uplift: a normal force <= 0 somewhere in the period, or, where no period could"
            " be integrated, within two periods of the guess; maxima skip those points"
            + (
                ", except those the unilateral sweep settled)"
                if settings.contact == "unilateral"
                else "; --contact unilateral recomputes them with lift-off and landing)"
            )
        )
        for s in report["amplitudes"]:
            if s.get("unilateral_points"):
                print(
                    f"   A = {s['A']:g}: {s['unilateral_points']} points with lift-off and landing"
                )
    for s in report["amplitudes"]:
        for line in [*gap_lines(s), *jump_lines(s), *resumed_lines(s)]:
            print(f"   A = {s['A']:g}: {line}")
    print(f"csv:    {csv_path}")
    if "figure" in report:
        print(f"figure: {report['figure']}")
    sys.stdout.flush()
    return _holes(report["amplitudes"], csv_path)


def resumed_lines(s: dict) -> list[str]:
    """A curve resumed from its checkpoint: how many points it took from there (its wall
    time is this run's, those points' not in it)."""
    k = s.get("resumed_points") or 0
    if not k:
        return []
    return [f"{k} of {s['points']} points resumed from the checkpoint (wall [s]: this run's "
            "points only)"]  # fmt: skip


def jump_lines(s: dict) -> list[str]:
    """Steps of a sequential curve from one branch to another (two periodic orbits coexist
    at the lower frequency: a fold lies between the two points)."""
    return [f"the curve jumped to another branch between f = {j['f_a']:.4g} and "
            f"{j['f_b']:.4g} Hz (two periodic orbits at {j['f_a']:.4g} Hz: a fold lies "
            "between); --continuation arclength follows the branch through it"
            for j in s.get("jumps") or []]  # fmt: skip


def gap_lines(s: dict) -> list[str]:
    """Where a curve has no steady state (failed points; frequencies a curve without the
    stepped-sweep fallback skipped), and why."""
    out = []
    stop = s.get("arclength_stop")
    if stop:
        out.append(f"arclength stopped at f = {stop['f_hz']:.4g} Hz ({stop['reason']}); the "
                   "band above it continued sequentially")  # fmt: skip
    fl = s.get("failures") or []
    if fl:
        fs = [x["f"] for x in fl]
        at = (f"f = {fs[0]:.4g} Hz" if len(fl) == 1
              else f"f = {min(fs):.4g}-{max(fs):.4g} Hz")  # fmt: skip
        out.append(f"{len(fl)} point{'s' * (len(fl) != 1)} without a steady state, {at} "
                   f"(first: {fl[0]['reason']})")  # fmt: skip
    sk = s.get("skipped_hz") or []
    if sk:
        shown = ", ".join(f"{f:.4g}" for f in sk[:8]) + (", ..." if len(sk) > 8 else "")
        why = (s.get("skipped_why") or ["?"])[0]
        out.append(f"{len(sk)} frequencies without a periodic orbit skipped (--no-fallback: "
                   f"no stepped sweep): f = {shown} Hz (first: {why})")  # fmt: skip
    return out


def run_plane(args: argparse.Namespace, cfg: dict) -> int:
    """``nsdyn sweep`` on a deck or rigid building3d scene under a harmonic orbit: the curves
    of the peak resultant isolator displacement (sweep.csv, sweep.json, sweep.png)."""
    from nsdyn.models.scenefile import SceneError
    from nsdyn.studies.plane_sweep import (
        PlaneSweepSettings,
        default_range,
        plane_scene,
        summarise,
        sweep_plane,
        write_csv,
    )

    source = str(args.scene)
    if args.fidelity is not None and cfg.get("scene", {}).get("kind") == "deck":
        return fail(
            args,
            f"{source}: --fidelity: a deck scene has one model, the rigid "
            "deck; the fidelities are those of isolated and building3d scenes",
        )
    if args.fidelity is not None:
        cfg = {**cfg, "structure": {**cfg.get("structure", {}), "fidelity": args.fidelity}}
    given = (("--contact", args.contact != "bilateral"), ("--tableau", args.tableau != "sdirk2"),
             ("--steps-factor", args.steps_factor != 1.0))  # fmt: skip
    unused = [flag for flag, off in given if off]
    if unused:  # (each flag's own reason: --steps-factor was said to be about contact)
        why = {"--contact": "their orbits keep the plate's contact; an uplift ends a period"}
        text = "; ".join(dict.fromkeys(why.get(f, "their period map is integrated adaptively")
                                       for f in unused))  # fmt: skip
        kind = cfg.get("scene", {}).get("kind", "deck")
        return fail(args, f"{source}: {', '.join(unused)}: not for {kind} scenes ({text})")
    try:
        sc = plane_scene(cfg, source)
    except SceneError as e:
        from nsdyn.cli.app import flagged

        return fail(args, flagged(" ".join(str(e).split()), args))
    lo, hi = default_range(sc["orbit"])
    sw = sc["sweep"]  # the scene's [sweep] table; the flags win
    fmin = sw.get("f_min", lo) if args.fmin is None else args.fmin
    fmax = sw.get("f_max", hi) if args.fmax is None else args.fmax
    if not fmax > fmin:
        given = (args.fmin is not None, args.fmax is not None)
        scene = tuple(f"sweep.{k} of {source}" if k in sw else None for k in ("f_min", "f_max"))
        return fail(args, band_message("sweep", fmin, fmax, given, scene))
    from nsdyn.periodic.plane import orbit_shape

    amplitudes = args.amplitudes or sw.get("amplitudes") or [orbit_shape(sc["orbit"])[0]]
    where = ("--amplitudes" if args.amplitudes else f"{source}: sweep.amplitudes"
             if sw.get("amplitudes") else f"{source}: motion.amplitude")  # fmt: skip
    if why := above_highest(amplitudes, where, "sweep"):
        return fail(args, why)
    if len(set(amplitudes)) < len(amplitudes):  # (each computed twice, the rows doubled)
        return fail(args, f"{source}: sweep.amplitudes: expected distinct amplitudes, got "
                    f"{list(amplitudes)}")  # fmt: skip
    law = args.friction or sw.get("law") or sc["solver"]["law"]
    if getattr(sc["system"], "has_tfp", False) and law != "arctan":
        where = "--friction" if args.friction else f"{source}: solver.law"
        return fail(args, f"{where}: a triple friction pendulum runs with the regularised law "
                    f"'arctan' (its series model has no stick events), got {law!r}")  # fmt: skip
    flat = [getattr(b, "radius", None) == math.inf and not b.k_lam > 0
            for b in getattr(sc["system"], "bearings", ())]  # fmt: skip
    if flat and all(flat):  # (a 487 km "stable" orbit at 2.8 Hz, with k_lam = 0)
        return fail(args, f"{source}: bearing.k_lam: flat sliders without a spring hold the "
                    "deck with no restoring force: no orbit has a position of its own (each is "
                    "one of a family, at any offset); expected k_lam > 0 or a pendulum (type "
                    "'fps' or 'tfp')")  # fmt: skip
    points = args.points or sw.get("points") or POINTS_DEFAULT
    settings = PlaneSweepSettings(fmin, fmax, points, args.continuation,
                                  not args.no_fallback, law)  # fmt: skip
    from nsdyn.models.isolated.bearings import slip_ratio_note
    from nsdyn.models.isolated.deck_scene import warm

    with output_dir(Path(args.out), "sweep") as out:  # (none left empty by a failure)
        before = files_of(out)
        before.pop("sweep.json", None)  # (written last, after the note on the others)
        compile_s = warm(sc["system"], law)  # announced on a first use, before the workers
        t0 = time.perf_counter()
        results = sweep_plane(cfg, source, amplitudes, settings, out, workers=args.workers,
                              restart=args.restart, quiet=args.json)  # fmt: skip
        csv_path = out / "sweep.csv"
        gone = old_figures(out, ["sweep.png"], "sweep", args)  # (redrawn after the table)
        write_csv(csv_path, results)
        o = sc["orbit"]
        report = {
            "kind": sc["kind"], "model": sc["name"], "csv": str(csv_path),
            "orbit": {"f_hz": o.f, "ax": o.ax, "ay": o.ay, "phase_y_deg": o.phase_y_deg,
                      "az": o.az, "f_z": o.f_z, "phase_z_deg": o.phase_z_deg},
            "settings": asdict(settings), "wall_s": time.perf_counter() - t0,
            "compile_s": compile_s, "amplitudes": [summarise(r) for r in results],
        }  # fmt: skip
        bearings = getattr(sc["system"], "bearings", ())
        peaks = np.zeros(len(bearings))  # each isolator's largest peak where it was the largest
        for row in (x for r in results for x in r["rows"] if x["converged"]):
            k = row.get("u_peak_isolator")
            if isinstance(k, int) and 0 <= k < len(bearings):
                peaks[k] = max(peaks[k], float(row["u_peak_m"]))
        big = slip_ratio_note(bearings, peaks) if bearings else None
        if notes := [n for n in (gone, big) if n]:  # (--no-figures removed the figure, said)
            report["notes"] = notes
        if big and not args.json:  # (a run says so; the orbits past the radius said nothing)
            print(f"nsdyn sweep: note: {big}", file=sys.stderr)
        if not args.no_figures:
            from nsdyn.plot.plane_sweep import plane_sweep_figure

            fig_path = out / "sweep.png"
            title = f"{sc['name']}: law {settings.law}"
            save_figure(plane_sweep_figure(results, title), fig_path, dpi=120)
            report["figure"] = str(fig_path)
        _note_earlier(args, out, before, report)
        json_path = out / "sweep.json"
        report["json"] = str(json_path)
        status = _holes(report["amplitudes"], json_path, report, say=False)  # (the file's too)
        with atomic_open(json_path, "w") as fh:
            fh.write(json_report(report, default=float, indent=1))  # (its status too)
    if args.json:  # (its holes' line first, then the report with their status)
        _holes(report["amplitudes"], json_path)
        print(json_report(report, default=float))
        return status
    print(f"{sc['kind']} {sc['name']}: {settings.points} frequencies {fmin:g}-{fmax:g} Hz, "
          f"law {settings.law}, {settings.continuation} continuation")  # fmt: skip
    print("   A [m/s²]  points  fallback  unstable  stick-slip  |u|max [m]  at f [Hz]  wall [s]")

    def g(v, fmt):
        return "-" if v is None else format(v, fmt)

    for s in report["amplitudes"]:
        print(f"   {s['A']:8.5g}  {s['points']:6d}  {s['fallback_points']:8d}  "
              f"{s['unstable_points']:8d}  {s['stick_slip_points']:10d}  "
              f"{g(s['u_peak_max_m'], '.4g'):>10s}  {g(s['u_peak_max_f_hz'], '.4g'):>9s}  "
              f"{s['wall_s']:8.1f}")  # fmt: skip
        for fl in s["failures"]:
            print(f"   A = {s['A']:g}: f = {fl['f']:.5g} Hz: {fl['reason']}")
        said = [f"{n} point{'s' * (n != 1)} with {what}" for n, what in (
            (s["uplift_points"], "uplift (left out of |u|max)"),
            (s["rim_contact_points"], "a rim contact")) if n]  # fmt: skip
        if said:
            print(f"   A = {s['A']:g}: {', '.join(said)}")
        if n := s.get("family_points"):
            print(f"   A = {s['A']:g}: {n} point{'s are' if n != 1 else ' is'} one of a family of "
                  "orbits (multipliers at 1: a neutral direction keeps any offset), their "
                  "peaks depend on the path (the note column)")  # fmt: skip
        for line in [*jump_lines(s), *resumed_lines(s)]:
            print(f"   A = {s['A']:g}: {line}")
    print(f"csv:    {csv_path}")
    print(f"json:   {json_path}")
    if "figure" in report:
        print(f"figure: {report['figure']}")
    sys.stdout.flush()
    return _holes(report["amplitudes"], json_path)
