"""``nsdyn run``: a transient run of a scene of any model family."""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from nsdyn._numba_cache import compile_note
from nsdyn.atomic import atomic_open, check_free, earlier_files, files_of, output_dir, save_figure
from nsdyn.cli.args import EXIT_NUMERICS, PGA_HELP, json_report, named, out_dir, stale_figures
from nsdyn.cli.args import positive_finite as _positive_finite
from nsdyn.cli.args import positive_float as _positive_float
from nsdyn.cli.args import positive_int as _positive_int
from nsdyn.cli.run_checks import (
    check_cutoff,
    check_method,
    event_law,
    explicit_steps,
    fixed_base_run,
    note_short_record,
    notes_first,
    prepare_sparse,
    record_wins,
    scene_notes,
)
from nsdyn.cli.run_resume import open_checkpoint, run_identity
from nsdyn.cli.run_summary import summary_rows
from nsdyn.models.scene_schema import RECORD_UNITS  # --units: a scene's [motion] units
from nsdyn.models.scenefile import SceneError

DEFAULT_OUT = "nsdyn-out"  # output directory
FIXED_PEAKS = ("idr_max", "floor_acc_max_mps2", "roof_drift_max_m")  # --compare-fixed's
FINISHED: list = []  # histories written by a run of this process (what an interrupt says)


def interrupted(exc: BaseException) -> bool:
    """True for Ctrl-C / SIGTERM (also wrapped by numba as a SystemError): an interrupted run
    keeps its checkpoint, which is how a rerun resumes."""
    from nsdyn.atomic import caused_by_interrupt

    return isinstance(exc, KeyboardInterrupt) or caused_by_interrupt(exc)


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("scene", nargs="?", default=None,
                   help="scene TOML (default: the bundled default scene)")  # fmt: skip
    p.add_argument("--frame", type=named, help="bundled frame name or frame TOML path")
    p.add_argument("--record", type=named, help="bundled record name or ground-motion file")
    p.add_argument("--pga", type=_positive_finite, metavar="MPS2", help=PGA_HELP)
    p.add_argument(
        "--units",
        choices=RECORD_UNITS,
        help="the record file's units ([motion] units; a file stating others is warned of)",
    )
    p.add_argument("--fixed-base", action="store_true", help="the fixed-base linear frame")
    p.add_argument(
        "--fidelity",
        choices=["fixed", "rigid", "cb", "full", "auto"],
        help="model fidelity (a 3D building's [structure] fidelity); 'auto' asks the model "
        "advisor and prints its choice and evidence",
    )
    p.add_argument("--fmax", type=_positive_float, metavar="HZ",
                   help="Craig–Bampton cut-off (a 3D building's [structure] f_max)")  # fmt: skip
    p.add_argument(
        "--friction",
        choices=["arctan", "switch", "none"],
        help="friction law (deck and building3d scenes: their [solver] law)",
    )
    p.add_argument(
        "--method",
        metavar="METHOD",
        help="integrator: auto (default: chosen from the model, reason printed), radau, "
        "radau-generic, dopri5, event (adaptive); genalpha, hht, newmark, genalpha-lowrank "
        "(fixed step, --dt)",
    )
    p.add_argument("--dt", type=_positive_finite, metavar="S",
                   help="step of the fixed-step methods (default 0.005 s, or the record's "
                   "sampling step or 1/20 of a harmonic forcing's period if shorter)")  # fmt: skip
    p.add_argument("--t-end", type=_positive_finite, metavar="S", help="stop at this time "
                   "(past a record's end an isolated frame, deck or building stops there; a "
                   "rocking, contact or cylinder scene runs on, the ground at rest; a note "
                   "says which)")  # fmt: skip
    p.add_argument(
        "--max-steps",
        type=_positive_int,
        metavar="N",
        help="step attempts per 5 s chunk of the run before it gives up (default 2000000; "
        "isolated-frame scenes)",
    )
    p.add_argument("--out", type=out_dir, default=DEFAULT_OUT, metavar="DIR",
                   help="output directory")  # fmt: skip
    p.add_argument("--json", action="store_true", help="print one JSON object and nothing else")
    p.add_argument("--no-figures", action="store_true", help="skip the PNG figures")
    p.add_argument(
        "--compare-fixed",
        action="store_true",
        help="also run the fixed-base frame under the same motion and draw it in the figure "
        "(a second run, by radau: the default run's kernels, compiled once for every model)",
    )
    p.add_argument("--resume", action="store_true", help="continue an interrupted run of an "
                   "isolated frame from its checkpoint (refused on other kinds: they keep "
                   "none)")  # fmt: skip


def _scene_overrides(args: argparse.Namespace) -> dict:
    o: dict = {}
    if args.frame:
        o.setdefault("scene", {})["frame"] = args.frame
    if args.fidelity and args.fidelity != "auto":
        o.setdefault("scene", {})["fidelity"] = args.fidelity
    if args.fixed_base or args.fidelity == "fixed":
        clash = [f for f, v in (("--fidelity", args.fixed_base and args.fidelity),
                                ("--friction", args.friction),
                                ("--compare-fixed", args.compare_fixed)) if v]  # fmt: skip
        if clash:
            raise SceneError(f"{'--fixed-base' if args.fixed_base else '--fidelity fixed'}: the "
                             f"clamped linear frame has no isolators; {', '.join(clash)} cannot "
                             "apply to it")  # fmt: skip
        o.setdefault("scene", {})["fidelity"] = "fixed"
    if args.fmax:
        o.setdefault("scene", {})["f_max"] = args.fmax
    if args.record:
        o.setdefault("motion", {})["record"] = args.record
    if args.pga:
        o.setdefault("motion", {})["pga"] = args.pga
    if getattr(args, "units", None):
        o.setdefault("motion", {})["units"] = args.units
    if args.t_end:
        o.setdefault("motion", {})["t_end"] = args.t_end
    if args.method:
        o.setdefault("solver", {})["method"] = args.method
    if args.dt:
        o.setdefault("solver", {})["dt"] = args.dt
    if getattr(args, "max_steps", None):
        o.setdefault("solver", {})["max_steps"] = args.max_steps
    return o


def _t_end_wins(args: argparse.Namespace, cfg: dict) -> None:
    """``--t-end`` replaces a harmonic scene's ``n_periods`` (the duration is given once)."""
    if args.t_end:
        for table in ("motion", "force"):
            cfg.get(table, {}).pop("n_periods", None)


_ISOLATED_ONLY = (
    "frame",
    "fidelity",
    "fixed_base",
    "fmax",
    "friction",
    "resume",
    "dt",
    "max_steps",
    "compare_fixed",
)


def _check_ladder_flags(args: argparse.Namespace, raw: dict) -> None:
    """--fixed-base, --fidelity and --fmax choose among a frame's models; a scene that gives
    its ``[structure]`` directly has no such ladder (a SceneError naming the flags)."""
    flags = [
        flag
        for flag, given in (
            ("--fixed-base", args.fixed_base),
            ("--fidelity", args.fidelity not in (None, "auto")),
            ("--fmax", args.fmax),
        )
        if given
    ]
    if flags and "structure" in raw:
        kind = raw["structure"].get("kind", "?") if isinstance(raw["structure"], dict) else "?"
        raise SceneError(
            f"{args.scene}: {', '.join(flags)}: these choose among a frame's models (fixed "
            f"base, Craig-Bampton, full); this scene gives its [structure] directly (kind "
            f"{kind!r}), which is used as given"
        )


def _stem(name: str) -> str:
    from nsdyn.models.scenefile import file_stem

    return file_stem(name)


FIGURES = {  # the figures a run of each other kind draws (by the scene's name)
    "rocking": lambda name: ["rocking.png"],
    "contact": lambda name: ["contact.png"],
    "cylinder": lambda name: [f"{_stem(name)}.png"],
    "deck": lambda name: ["deck.png"],
    "building3d": lambda name: ["building3d-deformed.png", "building3d-modes.png"],
}


def _run_other_kind(args: argparse.Namespace, kind: str, cfg: dict) -> int:
    """``nsdyn run`` on a scene of another model family (``[scene] kind``)."""
    import importlib

    from nsdyn.models.scenefile import scene_module

    if args.friction and kind in ("deck", "building3d"):  # their [solver] law
        if args.friction == "none":
            raise SceneError(f"{args.scene}: --friction none: a {kind} scene's bearings keep "
                             "their friction; expected 'switch' or 'arctan'")  # fmt: skip
        cfg.setdefault("solver", {})["law"] = args.friction  # (an error names the flag)
    own = ("fidelity", "fmax") if kind == "building3d" else ()  # its [structure] keys
    law = ("friction",) if kind in ("deck", "building3d") else ()  # (its [solver] law)
    bad = [f"--{k.replace('_', '-')}" for k in _ISOLATED_ONLY
           if k not in own + law and getattr(args, k, None)]  # fmt: skip
    rung = [f for f in bad if f in ("--fidelity", "--fmax")]  # (a 3D building's too)
    bad = [f for f in bad if f not in rung]
    if bad or rung:
        verb = "applies" if len(bad) == 1 else "apply"
        fixed = ("; a 3D building's fixed base is its rung --fidelity fixed" * bool(own)
                 * any(f in bad for f in ("--fixed-base", "--compare-fixed"))
                 + "; a 3D building's step is its [solver] dt"
                 * (bool(own) and "--dt" in bad))  # fmt: skip
        said = [f"{', '.join(bad)} {verb} to isolated-frame scenes only{fixed}"] * bool(bad)
        said += [f"{' and '.join(rung)} appl{'ies' if len(rung) == 1 else 'y'} to isolated-"
                 "frame scenes and 3D buildings (their [structure] rung)"] * bool(rung)  # fmt: skip
        raise SceneError(f"{args.scene}: {'; '.join(said)}")
    if args.method and kind in ("deck", "building3d"):
        raise SceneError(f"{args.scene}: --method: a {kind} scene's integrator follows its "
                         "[solver] law (and fidelity); --method applies to isolated-frame, "
                         "rocking, contact and cylinder scenes")  # fmt: skip
    mod = importlib.import_module(scene_module(kind))
    record_wins(args, cfg, getattr(mod, "RECORD_REPLACES", ()), False, kind)
    given = _scene_overrides(args)
    if own:  # a 3D building's rung and cut-off: its [structure] fidelity and f_max ("auto":
        sc = given.get("scene", {})  # its own advisor, as the scene's fidelity = "auto")
        sc.update({"fidelity": "auto"} if args.fidelity == "auto" else {})
        given["structure"] = {k: sc.pop(k) for k in ("fidelity", "f_max") if k in sc}
    for table, vals in given.items():
        if not isinstance(cfg.get(table, {}), dict):
            continue  # (not a table: the family's reader names it)
        for k, v in vals.items():  # the file stays checked where an option replaces its value
            old = cfg.get(table, {}).get(k)
            if isinstance(v, int | float) and old is not None and (isinstance(old, bool) or
                    not isinstance(old, int | float) or not 0 <= old < float("inf")):  # fmt: skip
                raise SceneError(f"{args.scene}: {table}.{k}: expected a finite number >= 0, "
                                 f"got {old!r}")  # fmt: skip
        cfg.setdefault(table, {}).update(vals)
    _t_end_wins(args, cfg)
    said: list = []  # (files an earlier command left there: a note, said below)
    with output_dir(Path(args.out), "run", said.append) as out:
        s = mod.run_scene(
            cfg, source=str(args.scene), out_dir=out, figures=not args.no_figures, quiet=args.json
        )
        fig_mod = getattr(mod, "FIGURE_MODULE", None)  # figures drawn by a later stage (plot)
        if fig_mod and not args.no_figures:
            s["files"] += importlib.import_module(fig_mod).scene_figures(s, out)
        if args.no_figures:
            name = cfg.get("scene", {}).get("name", Path(str(args.scene)).stem)
            said.append(stale_figures(out, FIGURES[kind](name), "run", quiet=True))
    notes_first(args, s)
    for note in filter(None, said):  # (said here, and among the summary's notes)
        s.setdefault("notes", []).append(note)
        if not args.json:
            print(f"nsdyn run: note: {note}", file=sys.stderr)
    ran = s.get("t_end_s", s.get("t_end"))
    req = args.t_end or cfg.get("motion", {}).get("t_end")  # (--t-end, or the scene's)
    short = isinstance(ran, int | float) and isinstance(req, int | float) and ran < req - 1e-6
    short = short and not any(f"t_end = {req:g} s" in n for n in s.get("notes", []))  # (said)
    ended = s.get("uplift") or s.get("t_overturn_s") is not None or s.get("toppled_at")
    if short and not ended:  # (an uplift, an overturn or a cylinder's toppling end it too)
        from nsdyn.ground.formats import past_record_note

        note = past_record_note(req, ran, runs_on=False, what="excitation")
        s.setdefault("notes", []).append(note)  # (--json: the summary's notes)
        if not args.json:
            print(f"nsdyn run: note: {note}", file=sys.stderr)
    # a deck or 3D building whose normal force reached zero: exit 3, its files up to the uplift
    status = EXIT_NUMERICS if s.get("uplift") and kind in ("deck", "building3d") else 0
    if status:  # the failure's one line on stderr, as every failure's (its files written)
        from nsdyn.models.isolated.deck_scene import uplift_error

        head = {"status": status, "error": uplift_error(s)}
        print(f"nsdyn run: error: {head['error']}", file=sys.stderr)
    if args.json:  # a failed run's JSON leads with status and error, as every failure's does
        print(json_report({**(head if status else {}), **s}))
        return status
    print(mod.format_summary(s))
    return status


def prepare_kernels(method: str, flat: bool = True) -> float:
    """Compile (or load from numba's cache) the integrator and metrics kernels of a run,
    saying on stderr what is compiling while it does (a first run, or after an upgrade) and
    how long it took. ``flat``: the run's law is a smooth one (arctan or none), served by the
    flat kernel alone (see :func:`nsdyn.solve.methods.kernel_for`). Returns the seconds
    spent."""
    from nsdyn.solve.methods import METHODS, is_cached, kernel_for, metrics_for, warmup_kernel

    if method not in METHODS:  # the run reports the unknown method with the valid names
        return 0.0
    kernel = kernel_for(method, flat=flat)
    metrics = metrics_for(kernel)
    cold = not (is_cached(kernel) and is_cached(metrics))
    if cold:
        print(
            f"compiling the {method} integrator (first run only, cached afterwards)…",
            file=sys.stderr,
            flush=True,
        )
    t0 = time.perf_counter()
    warmup_kernel(kernel, metrics=metrics)
    spent = time.perf_counter() - t0
    if cold:
        print(f"  compiled in {spent:.1f} s", file=sys.stderr, flush=True)
    return spent


def run(args: argparse.Namespace) -> int:
    from nsdyn.models.isolated.scene import (
        build_scene_run,
        load_scene,
        outcome,
        with_isolation_cached,
    )
    from nsdyn.models.scenefile import SceneError, read_toml, scene_kind

    FINISHED.clear()  # (this run's, not an earlier one's of this process)
    check_free(Path(args.out))  # a folder another command writes: its one line, before any other
    if args.scene is not None:
        raw = read_toml(args.scene)
        kind = scene_kind(raw, str(args.scene))
        if kind != "isolated":
            return _run_other_kind(args, kind, raw)
        _check_ladder_flags(args, raw)
        record_wins(args, raw, ())  # (a harmonic scene: --record and --pga refused)
    scene_fid = (raw.get("scene") or {}).get("fidelity") if args.scene is not None else None
    check_cutoff(args.fmax, args.fidelity or scene_fid)
    from nsdyn.solve.transient import output_grid, simulate

    cfg = load_scene(args.scene, _scene_overrides(args))
    _t_end_wins(args, cfg)
    if args.friction:
        cfg.setdefault("isolation", {})["law"] = args.friction
    method = cfg.get("solver", {}).get("method", "auto")
    given = args.friction or ((raw.get("isolation") or {}).get("law") if args.scene else None)
    if given in ("arctan", "none") and method == "event":  # (the switch law ran instead)
        what = (f"--friction {given}" if args.friction else
                f"isolation.law: {given!r} with solver.method 'event'")  # fmt: skip
        raise SceneError(f"{cfg.get('_source', '<default scene>')}: {what}: the event method "
                         "integrates the switch model (true stick); expected the switch law, or "
                         "a method of the smooth law ('radau', 'genalpha', …)")  # fmt: skip
    check_method(method, cfg)  # before the model's build
    system, motion, duration = build_scene_run(cfg)
    notes = scene_notes(cfg, motion, args.json, system, raw if args.scene else None)
    if args.compare_fixed and system.frame is None:
        raise SceneError(f"{args.scene or '<default scene>'}: --compare-fixed needs a frame; "
                         "this scene's [structure] has none")  # fmt: skip
    if args.fidelity == "auto" and system.frame is None:
        raise SceneError(
            f"{args.scene}: --fidelity auto: the model advisor chooses among a frame's models; "
            "this scene's [structure] has no frame"
        )
    if args.fidelity == "auto":
        from nsdyn.models.isolated.system import build_system
        from nsdyn.studies.advisor import advise

        advice = advise(system.frame, motion, isolation=system.isolation)
        print(advice.report(), file=sys.stderr)
        system = build_system(system.frame, system.isolation, fidelity=advice.fidelity,
                              f_max=advice.f_max)  # fmt: skip
    sv = cfg["solver"]
    source = cfg.get("_source", "<scene>")
    try:
        t_eval = output_grid(motion, sv.get("dt_out"), **duration)
    except ValueError as e:  # the field it names: solver.dt_out, or motion's t_end / n_periods
        field = str(e).split(":")[0]
        table = {"dt_out": "solver.", "t_end": "motion.", "n_periods": "motion."}
        prefix = table.get(field, "" if field == "motion" else "motion: ")
        of = (
            f" (the run is the record's span: {motion.source}, {motion.n} samples at "
            f"{motion.dt:g} s)"
        ) * (field == "dt_out" and not duration and hasattr(motion, "n"))
        raise SceneError(f"{source}: {prefix}{e}{of}") from None
    from nsdyn.solve.auto import choose_for_system, step_reason

    method, reason = sv.get("method", "auto"), ""
    if method == "auto":  # by the model's size, friction law and contact; said in one line
        method, reason = choose_for_system(system)
    check_method(method, cfg)
    from nsdyn.solve.auto import sparse_path

    dense = None if sparse_path(system, method) else system.dense_refusal()
    if dense:  # (a traceback after the build; auto's radau for the switch law too)
        said = f" ({reason})" if reason else ""
        raise SceneError(f"{source}: solver.method: {method!r}{said} cannot run this model: "
                         f"{dense}")  # fmt: skip
    from nsdyn.solve.methods import METHODS
    from nsdyn.studies.steps import checked_step

    if METHODS[method].fixed_step:  # 5 ms, or the record's sampling step if shorter; checked
        sv["dt"] = checked_step(method, sv, motion, t_eval, source)
        reason = step_reason(reason, sv["dt"])
    smooth = system  # (its law, said after the checks where "event" replaces it)
    if method == "event" and system.isolation is not None:
        system = with_isolation_cached(system, law="switch")
    t_req = cfg.get("motion", {}).get("t_end")
    short = t_req is not None and t_eval[-1] < float(t_req) - 1e-9  # (cut at a sample)
    if short and note_short_record(cfg, motion) is None:  # (past the record: said above)
        from nsdyn.ground.formats import between_samples_note

        t_to = float(t_eval[-1])
        dt = float(getattr(motion, "dt", 0.0)) or float(t_req) - t_to
        notes.append(between_samples_note(float(t_req), t_to, dt)
                     or f"t_end = {float(t_req):g} s: the run ends at {t_to:g} s")  # fmt: skip
        if not args.json:
            print(f"nsdyn run: note: {notes[-1]}", file=sys.stderr)
    from nsdyn.studies.steps import check_step_count

    try:
        check_step_count(source, method, sv.get("dt"), t_eval, sv.get("max_steps"))
    except SceneError as e:  # (the method the run did not name: which choice it was)
        raise SceneError(f"{e} (method {reason})" if reason else str(e)) from None
    if reason and not args.json:  # (after the checks: a refused run is one line)
        print(f"method  {reason}", file=sys.stderr)
    notes += explicit_steps(method, system, float(t_eval[-1] - t_eval[0]), args.json,
                            sv.get("max_steps"))  # fmt: skip
    notes += event_law(smooth, args.json) if method == "event" else []
    out = Path(args.out)
    stem = "run"
    ident = run_identity(cfg, args.fidelity, motion)
    quiet = args.json

    from nsdyn._progress import reporter

    say = reporter(lambda line: print(line, file=sys.stderr))  # --json: on a terminal's stderr
    progress = None if quiet and not sys.stderr.isatty() else say

    from nsdyn.solve.integrate import UpliftWarning
    from nsdyn.solve.methods import FLAT_LAWS

    before = files_of(out)  # (what an earlier command left: said at the end)
    with output_dir(out, "run"):
        ckpt, identity, t_resumed = open_checkpoint(out, ident, args.resume, quiet, notes)
        resumed = ckpt.is_file()  # a checkpoint of an earlier run: never deleted here
        try:
            with atomic_open(identity, "w") as fh:
                fh.write(json.dumps(ident, sort_keys=True))
            iso = system.isolation
            if sparse_path(system, method):  # its kernels, and a large model's damped modes
                compile_s = prepare_sparse(system, quiet)
            else:
                compile_s = prepare_kernels(method, iso is None or iso.law in FLAT_LAWS)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", UpliftWarning)
                res = simulate(
                    system,
                    motion,
                    method=method,
                    rtol=sv["rtol"],
                    atol=tuple(sv["atol"]) if isinstance(sv.get("atol"), list) else sv.get("atol"),
                    dt=sv.get("dt"),
                    t_eval=t_eval,
                    uplift=sv.get("uplift", "raise"),
                    **({"restitution": sv["restitution"]} if "restitution" in sv else {}),
                    progress=progress,
                    checkpoint=ckpt,
                    **({"max_steps": int(sv["max_steps"])} if "max_steps" in sv else {}),
                )
        except BaseException as exc:
            if not resumed and not interrupted(exc):  # the failed run's own files go
                ckpt.unlink(missing_ok=True)
                identity.unlink(missing_ok=True)
            elif not ckpt.is_file():  # stopped before its first checkpoint: nothing to resume
                identity.unlink(missing_ok=True)
            raise
        ckpt.unlink(missing_ok=True)
        identity.unlink(missing_ok=True)
        for w in caught:  # uplift: one clean line below; anything else as Python shows it
            if not issubclass(w.category, UpliftWarning) and str(w.message) not in res.notes:
                warnings.showwarning(w.message, w.category, w.filename, w.lineno)
        s = res.summary()
        s["method_reason"] = reason or s.get("method_reason", "")
        if t_resumed is not None:  # histories and n_steps are the whole run's, wall_s this part's
            s["resumed_from_s"] = t_resumed
        s["compile_s"] = float(s["compile_s"]) + compile_s
        s["record"] = getattr(motion, "name", s["excitation"])
        if hasattr(motion, "pga"):
            s["pga_mps2"] = float(motion.pga)  # of the motion run: the window, with --t-end
            if "pga" in cfg.get("motion", {}):  # the record was scaled to this before the window
                s["record_pga_mps2"] = float(cfg["motion"]["pga"])
        hist = out / f"{stem}-histories.npz"
        if not args.no_figures:  # an earlier run's figure goes as the new histories come (an
            (out / f"{stem}.png").unlink(missing_ok=True)  # interrupt left it beside them)
        with atomic_open(hist, "wb") as fh:
            np.savez(
                fh,
                t=res.t,
                x=res.x,
                x_iso=res.response.x_iso,
                top_drift=res.response.top_drift,
                normal_forces=res.response.lam,
                friction_forces=res.response.tau,
            )
        s["histories"] = str(hist)
        FINISHED.append(str(hist))
        for note in s.get("notes", []):  # the run's own (a fixed step's unresolved peaks)
            if note.startswith("dt_out = ") and any(n.startswith("dt_out = ") for n in notes):
                continue  # (said before the run, naming solver.dt_out)
            notes.append(note)
            if not args.json:
                print(f"nsdyn run: note: {note}", file=sys.stderr)
        s["notes"] = notes
        word, text = outcome(s)
        s["outcome"] = word
        if s.get("uplift"):  # uplift = "warn": the run went on outside the model's domain
            print(f"nsdyn run: warning: {text}", file=sys.stderr)
        fixed = fixed_base_run(system, motion, t_eval, quiet) if args.compare_fixed else None
        if fixed is not None:  # its peaks, beside the run's (the figure alone had them)
            fs = fixed.summary()
            s["fixed_base"] = {k: fs[k] for k in FIXED_PEAKS if k in fs}
        if args.no_figures:
            s["notes"] += [g for g in [stale_figures(out, [f"{stem}.png"], "run", args.json)] if g]
        else:
            from nsdyn.plot import plot_transient

            fig_path = out / f"{stem}.png"
            fig = plot_transient(res, motion, fixed=fixed, note=f"outcome: {text.split(':')[0]}",
                                 alert=bool(s.get("uplift")))  # fmt: skip
            save_figure(fig, fig_path)
            s["figure"] = str(fig_path)
            FINISHED.append(s["figure"])
        if note := earlier_files(out, before, "run"):
            s["notes"].append(note)
            if not args.json:
                print(f"nsdyn run: note: {note}", file=sys.stderr)
        if args.json:
            print(json_report(s))
            return 0
        pga = f" (PGA {s['pga_mps2']:.3g} m/s²)" if "pga_mps2" in s else ""
        if pga and "t_end" in cfg.get("motion", {}):  # (a window: not the record's PGA)
            pga = f" (peak {s['pga_mps2']:.3g} m/s² over the run, to t_end)"
        scaled = s.get("record_pga_mps2")
        if scaled is not None and abs(scaled - s["pga_mps2"]) > 5e-3:  # a shortened record
            pga = (f" (record scaled to PGA {s['record_pga_mps2']:.3g} m/s²; peak "
                   f"{s['pga_mps2']:.3g} m/s² over the run)")  # fmt: skip
        print(f"outcome {text}")
        print(f"model   {s['model']}   excitation {s['record']}{pga}")
        print(f"method  {s['method']}: {s['n_steps']} steps, run {s['wall_s']:.3f} s "
              f"({compile_note(s['compile_s'])})")  # fmt: skip
        for line in summary_rows(s):
            print(line)
        print(f"histories: {hist}")
        if "figure" in s:
            print(f"figure:    {s['figure']}")
        return 0
