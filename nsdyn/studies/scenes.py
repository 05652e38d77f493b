"""One scene run of any kind, as a study task: the summary dict, no figures, no files kept.

``run_scene_summary(cfg, source)`` dispatches on ``[scene] kind``:

* ``isolated``: the frame on friction isolators, built and simulated in this process with the
  scene's solver settings (what ``nsdyn run --json --no-figures`` prints, without the
  histories file). The structural reduction (Craig–Bampton of the frame, seconds) does not
  depend on the isolator springs and dampers, so each process keeps it per (frame, fidelity,
  f_max, diaphragm) and adds the isolators of each task, ``K* = K_s + Dᵀ diag(k_lam) D``,
  ``C* = C_s + Dᵀ diag(c) D`` — the same assembly ``build_system`` does;
* ``deck``, ``building3d`` (two-component records, the incident angle, base shear):
  :func:`nsdyn.studies.scenes3c.run_summary`;
* other kinds: ``nsdyn.models.<kind>.scene.run_scene(cfg, source=…, out_dir=<temporary>,
  figures=False, quiet=True)``.

A record may be simulated (``[motion] simulated = {generator, seed, duration, dt}``, seed
000's modulated white noise or Kanai–Tajimi), synthesised in the worker from its seed (and
written to the temporary directory for kinds that read files). ``run_batch(tasks)`` runs
tasks one after another, one row per task; a task that raises gives a row with ``status =
"failed"`` and the error, and the batch goes on."""

from __future__ import annotations

import copy
import importlib
import json
import math
import tempfile
import threading
import time
import warnings
from dataclasses import replace
from functools import lru_cache
from pathlib import Path

from nsdyn._checks import NotedWarning
from nsdyn.models.scenefile import SceneError, scaled_record, scene_kind, scene_module
from nsdyn.studies.steps import check_step_count, checked_step, fixed_step
from nsdyn.studies.study import KINDS3C

ERROR_CHARS = 400  # longest error text kept in a failed row
MOTION_CACHE = 32  # parsed records kept per process
_systems: dict = {}  # (frame, fidelity, f_max, diaphragm) -> isolator-free system
_lock = threading.Lock()  # the system cache is shared by the threads of a threaded worker


@lru_cache(maxsize=MOTION_CACHE)
def _read(record: str, units: str | None, dt: float | None, column: int | str | None = None):
    from nsdyn.ground import read_motion

    kw = {k: v for k, v in (("units", units), ("dt", dt), ("column", column)) if v is not None}
    return read_motion(record, **kw)


def simulated_motion(spec: dict):
    """The simulated record of a ``[motion] simulated`` table."""
    from nsdyn.ground import kanai_tajimi, modulated_white_noise

    gen = spec.get("generator", "modulated_white_noise")
    name = f"{gen}-seed{spec['seed']}"
    if gen == "kanai_tajimi":
        return kanai_tajimi(
            spec["duration"], seed=spec["seed"], dt=spec["dt"], vertical_ratio=2 / 3, name=name
        )
    return modulated_white_noise(spec["duration"], dt=spec["dt"], seed=spec["seed"], name=name)


def scene_motion(cfg: dict, source: str = "<scene>"):
    """The ground motion of a scene's ``[motion]`` table (record or simulated; vertical, pga,
    t_end applied as ``nsdyn run`` applies them)."""
    mo = cfg["motion"]
    if "simulated" in mo:
        motion = simulated_motion(mo["simulated"])
    else:
        motion = _read(str(mo["record"]), mo.get("units"), mo.get("dt"), mo.get("column"))
    if not mo.get("vertical", True):
        motion = motion.with_vertical(None)
    motion = scaled_record(motion, mo, source)
    if "t_end" in mo:
        try:
            motion = motion.until(float(mo["t_end"]))
        except ValueError as e:  # an end within the record's first step
            raise SceneError(f"{source}: motion.{e}") from None
    return motion


def _isolated_system(cfg: dict, source: str):
    from nsdyn.models.isolated.system import _add_isolators, isolation_from_config

    try:
        iso = isolation_from_config(cfg.get("isolation", {}), source)
    except ValueError as e:
        raise SceneError(str(e)) from None
    base = _base_system(cfg, iso)
    if base.isolation is None:  # fixed base
        return base
    K, C = _add_isolators(base.K, base.C, base.D, iso)
    return replace(base, K=K, C=C, isolation=iso, _static=None)


def _base_system(cfg: dict, iso):
    """The frame scene's model without its isolators (built once per frame, fidelity, cut-off
    and base diaphragm)."""
    from nsdyn.models.isolated.system import Isolation, build_system
    from nsdyn.structure import load_frame

    sc = cfg["scene"]
    fidelity = sc.get("fidelity", "cb")
    f_max = float(sc.get("f_max", 5.0)) if fidelity in ("cb", "fixed") else None  # (cut-offs)
    key = (sc["frame"], fidelity, f_max, iso.diaphragm_EA, iso.diaphragm_EI)
    with _lock:
        base = _systems.get(key)
        if base is None:
            bare = Isolation(
                k_lam=0.0, c=0.0, diaphragm_EA=iso.diaphragm_EA, diaphragm_EI=iso.diaphragm_EI
            )
            base = build_system(load_frame(sc["frame"]), bare, fidelity=fidelity, f_max=f_max)
            _systems[key] = base
    return base


def _custom_excitation(cfg: dict) -> bool:
    """A [structure] scene, a force, or a harmonic motion: built as ``nsdyn run`` builds it."""
    return (
        "structure" in cfg
        or "force" in cfg
        or cfg.get("motion", {}).get("kind", "record") != "record"
    )


def _run_isolated(cfg: dict, source: str) -> dict:
    from nsdyn._checks import AccuracyWarning
    from nsdyn.models.isolated.scene import outcome
    from nsdyn.solve.integrate import UpliftWarning
    from nsdyn.solve.transient import output_grid, simulate

    duration: dict = {}
    if _custom_excitation(cfg):
        from nsdyn.models.isolated.scene import build_scene_run

        system, motion, duration = build_scene_run({**cfg, "_source": source})
    else:
        system = _isolated_system(cfg, source)
        motion = scene_motion(cfg, source)
    sv = cfg["solver"]
    method = sv.get("method", "auto")
    if method == "event" and system.isolation is not None:
        system = replace(system, isolation=system.isolation.changed(law="switch"), _static=None)
    atol = sv.get("atol")
    t_eval = output_grid(motion, sv.get("dt_out"), **duration)
    dt = fixed_step(method, sv, motion)
    check_step_count(source, method, dt, t_eval, sv.get("max_steps"))
    with warnings.catch_warnings():  # uplift = "warn": the summary's uplift and outcome say it
        warnings.simplefilter("ignore", UpliftWarning)
        warnings.simplefilter("ignore", AccuracyWarning)  # (the row's notes say it)
        res = simulate(
            system,
            motion,
            method=method,
            rtol=sv["rtol"],
            atol=tuple(atol) if isinstance(atol, list) else atol,
            dt=dt,
            t_eval=t_eval,
            uplift=sv.get("uplift", "raise"),
            **({"restitution": sv["restitution"]} if "restitution" in sv else {}),
            **({"max_steps": int(sv["max_steps"])} if "max_steps" in sv else {}),
        )
    s = res.summary()
    s.update(kind="isolated", outcome=outcome(s)[0])
    if hasattr(motion, "pga"):  # a record (a harmonic or a force has no PGA)
        s.update(record=motion.name, pga_mps2=float(motion.pga))
    return s


def _run_other(kind: str, cfg: dict, source: str) -> dict:
    mod = importlib.import_module(scene_module(kind))
    cfg = copy.deepcopy(cfg)
    with tempfile.TemporaryDirectory(prefix="nsdyn-task-") as tmp:
        sim = cfg.get("motion", {}).pop("simulated", None)
        if sim is not None:
            from nsdyn.ground import write_motion

            cfg["motion"]["record"] = str(
                write_motion(simulated_motion(sim), Path(tmp) / "rec.csv")
            )
        s = mod.run_scene(cfg, source=source, out_dir=Path(tmp), figures=False, quiet=True)
    return {k: v for k, v in s.items() if not (isinstance(v, str) and v.startswith(tmp))}


_BUILDERS = {  # the functions of a family's scene module that read and check a scene
    "rocking": ("build_model", "build_motion", "build_solver"),
    "contact": ("build",),
    "cylinder": ("build",),
    "deck": ("build_system", "build_motion", "build_solver"),
    "building3d": ("build_system", "build_motion", "build_solver"),
}


def check_scene(cfg: dict, source: str) -> list[str]:
    """Check a complete scene of any kind as ``nsdyn run`` checks a scene file, without
    running it: :class:`SceneError` naming ``source`` and the field. A study calls it on every
    task before the first one runs, so a bad parameter value is refused up front. Returns the
    notes the family's reader gives (keys it does not read: ``"solver.h not used: ..."``)."""
    kind = scene_kind(cfg, source)
    if kind == "isolated":
        from nsdyn.models.isolated.scene import unused_notes

        return unused_notes(cfg) + _check_isolated(cfg, source)
    mod = importlib.import_module(scene_module(kind))
    cfg = _record_for_simulated(cfg, kind)
    notes: list[str] = []
    try:
        for name in _BUILDERS.get(kind, ()):
            if kind in KINDS3C and name == "build_system":  # kept per process (the frame)
                from nsdyn.studies.scenes3c import build_system

                notes += mod.build_notes(cfg, build_system(kind, cfg, source))
                continue
            out = getattr(mod, name)(cfg, source)
            if kind in KINDS3C and name == "build_motion":  # (a record cut: said, as a run)
                notes += [n for n in [mod.record_end_note(cfg, out[0])] if n]
            for part in out if isinstance(out, tuple) else (out,):
                if isinstance(part, dict) and isinstance(part.get("notes"), list):
                    notes += [n for n in part["notes"] if isinstance(n, str)]
    except SceneError:
        raise
    except (OSError, ValueError) as e:  # a bad value the family's reader let through
        raise SceneError(f"{source}: {' '.join(str(e).split())}") from None
    return notes


def _record_for_simulated(cfg: dict, kind: str) -> dict:
    """A copy of ``cfg`` whose simulated record (written to a file in the worker) is a bundled
    record: any record stands for it where its samples do not matter."""
    cfg = copy.deepcopy(cfg)
    if cfg.get("motion", {}).pop("simulated", None) is not None:
        from nsdyn.ground import bundled_records, bundled_records3

        cfg["motion"]["record"] = (bundled_records3() if kind in KINDS3C else bundled_records())[0]
    return cfg


WARMED_KINDS = ("rocking", "contact", "cylinder")  # scene modules with warm_key, warm_scene


def warm_scene_kernels(tasks) -> list[str]:
    """Compile the rocking, contact and cylinder kernels the tasks call once, here, before the
    workers start (each family's ``warm_scene``, announced on stderr when it compiles): every
    worker then loads them from numba's cache instead of compiling them side by side, each
    with its own helper process. One task per family and ``warm_key`` (what selects the
    compiled code); a scene whose warm-up fails is left to its task (a failed row, as
    without the warm-up). Returns the families it warmed."""
    seen, done = set(), []
    for t in tasks:
        if t.kind not in WARMED_KINDS:
            continue
        mod = importlib.import_module(scene_module(t.kind))
        cfg = _record_for_simulated(t.cfg, t.kind)
        key = (t.kind, mod.warm_key(cfg))
        if key in seen:
            continue
        seen.add(key)
        try:
            mod.warm_scene(cfg, t.source)
        except Exception:  # noqa: BLE001  (the task's own run reports it: a failed row)
            continue
        done.append(t.kind)
    return done


def _check_isolated(cfg: dict, source: str) -> list[str]:
    """:func:`check_scene` of an isolated frame's scene; its note on a friction law's
    parameter that blurs the friction (a run's NotedWarning, ignored in a study's runs)."""
    from nsdyn.models.isolated.bearings import stiff_bearing_check
    from nsdyn.models.isolated.scene import (
        _check,
        build_structure,
        check_restitution,
        unused_isolation,
    )
    from nsdyn.models.isolated.scene_structure import force_excitation, harmonic_motion
    from nsdyn.models.isolated.system import PER_ISOLATOR, isolation_from_config
    from nsdyn.solve.methods import METHODS
    from nsdyn.solve.run_inputs import law_note
    from nsdyn.solve.transient import output_grid

    tables = {k: copy.deepcopy(v) for k, v in cfg.items() if not k.startswith("_")}
    mo = tables.get("motion", {})
    mo.pop("simulated", None)
    _check(tables, source)
    check_restitution(cfg, source)
    try:
        iso = isolation_from_config(cfg.get("isolation", {}), source)
    except ValueError as e:
        raise SceneError(str(e)) from None
    sv = cfg.get("solver", {})
    method = sv.get("method", "auto")
    if method != "auto" and method not in METHODS:  # auto: chosen from the model (simulate)
        raise SceneError(
            f"{source}: solver.method: unknown integrator {method!r}; expected 'auto' or one "
            f"of {sorted(METHODS)}"
        )
    system = None
    if "structure" in cfg:
        system = build_structure(cfg, iso, source)
    else:  # the frame read once per file: a bad one refused here, its notes said here once
        frame = cfg.get("scene", {}).get("frame")
        try:
            p = Path(frame) if isinstance(frame, str) else None  # (a file's version: its mtime)
            n_iso = p and _frame_read(frame, p.stat().st_mtime_ns if p.is_file() else None)
        except ValueError as e:  # (FrameFileError; a 3D frame's as nsdyn run says it)
            hint = ("; a 3D building is a scene of kind 'building3d' that names it as "
                    "[structure] frame3d") * (getattr(e, "field", None) == "frame3d")  # fmt: skip
            raise SceneError(f"{source}: scene.frame: {e}{hint}") from None
        try:  # a list of the wrong length: every task failed on it (frame: merged default's)
            _ = [iso.per_isolator(k, n_iso) for k in PER_ISOLATOR if n_iso]
            base = _base_system(cfg, iso) if n_iso else None  # (a spring past the structure)
            if base is not None and base.isolation is not None:
                stiff_bearing_check(iso.per_isolator("k_lam", n_iso), base.K.diagonal())
        except ValueError as e:
            raise SceneError(f"{source}: {e}") from None
    duration: dict = {}
    try:
        if "force" in cfg:
            excitation, duration = force_excitation(cfg["force"], source, cfg.get("motion"))
        elif cfg.get("motion", {}).get("kind") == "harmonic":
            excitation, duration = harmonic_motion(cfg["motion"], source)
        else:
            excitation = scene_motion(cfg, source)
        t_eval = output_grid(excitation, sv.get("dt_out"), **duration)
    except SceneError:
        raise
    except (OSError, ValueError) as e:  # a record that cannot be read, a window without samples
        from nsdyn.ground import RecordFileError

        field = "motion.record" if isinstance(e, OSError | RecordFileError) else "motion"
        raise SceneError(f"{source}: {field}: {' '.join(str(e).split())}") from None
    dt = checked_step(method, sv, excitation, t_eval, source)
    check_step_count(source, method, dt, t_eval, sv.get("max_steps"))
    if method == "auto" and "dt" in sv:  # (a fixed step for an adaptive choice: every row fails)
        try:
            _auto_step(system or _isolated_system(cfg, source), sv["dt"], source)
        except ValueError as e:  # (a value the model refuses: isolation.k_lam of 7 for 2)
            raise e if isinstance(e, SceneError) else SceneError(f"{source}: {e}") from None
    if "structure" not in cfg and cfg.get("scene", {}).get("fidelity") == "fixed":
        return []  # (its [isolation] note: unused_notes)
    normal = system is not None and system.normal_force is not None
    unused = [f"{k} not used: {why}" for k, why in unused_isolation(cfg, iso, given_normal=normal)]
    return unused + [n for n in [law_note(iso, method)] if n]


def _auto_step(system, dt, source: str) -> None:
    """SceneError naming solver.dt when ``method = "auto"`` chooses an adaptive method for
    ``system`` (:func:`nsdyn.solve.auto.choose_for_system`), which takes no step."""
    from nsdyn.solve.auto import choose_for_system
    from nsdyn.solve.methods import METHODS

    method, reason = choose_for_system(system)
    if not METHODS[method].fixed_step:
        raise SceneError(
            f"{source}: solver.dt: {dt:g} is the step of a fixed-step method, but method "
            f"'auto' chooses the adaptive {method!r} here ({reason}); set solver.method to a "
            "fixed-step method (genalpha, genalpha-lowrank, ...), or drop solver.dt"
        )


@lru_cache(maxsize=MOTION_CACHE)
def _frame_read(name: str, mtime) -> int:
    """The number of isolators (base nodes) of the frame ``name`` (a file or a bundled
    name), read once per version (``mtime``)."""
    from nsdyn.structure import load_frame

    return len(load_frame(name).base_nodes)


MOTION_COLUMNS = ("pga_mps2", "pga_resultant_mps2", "incident_angle_deg")


def run_scene_summary(cfg: dict, source: str) -> dict:
    """Run the scene ``cfg`` of any kind and return its JSON summary (no figures, no files)."""
    kind = scene_kind(cfg, source)
    if kind == "isolated":
        return _run_isolated(cfg, source)
    if kind in KINDS3C:
        from nsdyn.studies.scenes3c import run_summary

        s = run_summary(kind, cfg, source)
        if s.get("uplift"):  # the run left the model's domain: a failed row, as the frame's
            from nsdyn.models.isolated.deck_scene import uplift_error
            from nsdyn.solve.integrate import UpliftError

            u = s["uplift"]
            e = UpliftError(uplift_error(s, files=False), u["t_s"], u["isolator"])
            # the motion's columns stay in the failed row (a fragility's intensity measure)
            e.columns = {k: s[k] for k in MOTION_COLUMNS if k in s}
            raise e
        return s
    return _run_other(kind, cfg, source)


def _cell(v):
    """A table cell: numbers, strings and booleans as they are; anything else as JSON."""
    if v is None or isinstance(v, bool | int | str):
        return v
    if isinstance(v, float):
        return v
    if hasattr(v, "item") and getattr(v, "ndim", 1) == 0:
        return v.item()
    return json.dumps(v)


def result_columns(summary: dict, keep, source: str = "<study>") -> dict:
    """The kept fields of a summary: ``keep`` (any type, non-scalars as JSON; a name this
    summary lacks an empty cell, see :func:`missing_kept`) or every scalar."""
    if keep is None:
        return {
            k: _cell(v)
            for k, v in summary.items()
            if v is None or isinstance(v, bool | int | float | str)
        }
    return {k: _cell(summary[k]) if k in summary else None for k in keep}


MISSING_MARK = "not in this task's run summary (an empty cell):"


def missing_kept(summary: dict, keep, source: str = "<study>") -> str:
    """A note naming the names of ``keep`` this summary lacks, each with its nearest field
    (a misspelt name, or a field of another rung or scene kind of the study: a rigid deck's
    summary has no corner drift), or "" when it has them all."""
    missing = [k for k in keep or () if k not in summary]
    if not missing:
        return ""
    import difflib

    hints = []
    for k in missing:
        close = difflib.get_close_matches(k, list(summary), n=1)
        if close:
            hints.append(f"did you mean {close[0]!r} for {k!r}?")
    head = (f"{source}: study.keep: {MISSING_MARK} {', '.join(map(repr, missing))}; "
            + "".join(h + " " for h in hints) + "its fields: ")  # fmt: skip
    fields = sorted(summary)
    text = ", ".join(fields)
    if len(head) + len(text) > ERROR_CHARS:  # the row keeps ERROR_CHARS: end at a whole name
        room = ERROR_CHARS - len(head) - len(f", ... ({len(fields)} in all)")
        shown = []
        for f in fields:
            if len(", ".join([*shown, f])) > room:
                break
            shown.append(f)
        text = ", ".join([*shown, "..."]) + f" ({len(fields)} in all)"
    return head + text


def missing_names(note: str) -> list[str]:
    """The kept names a row's note (:func:`missing_kept`) says its summary lacks."""
    import ast

    if MISSING_MARK not in (note or ""):
        return []
    names = note.split(MISSING_MARK, 1)[1].split(";", 1)[0]
    return list(ast.literal_eval(f"[{names}]"))


def near_kept(note: str) -> list[tuple[str, str]]:
    """The (kept name, nearest field) pairs of a row's note (:func:`missing_kept`'s hints)."""
    import ast
    import re

    text = r"'(?:[^'\\]|\\.)*'"  # (a repr in single quotes)
    hints = re.findall(rf"did you mean ({text}) for ({text})\?", note or "")
    return [(ast.literal_eval(k), ast.literal_eval(near)) for near, k in hints]


def run_task(task) -> dict:
    """One row: the task's input columns, ``status``, ``error``, ``task_s`` and its results."""
    row = task.columns()
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():  # (the study said its tasks' notes once, as it
            warnings.simplefilter("ignore", NotedWarning)  # checked them: check_tasks)
            s = run_scene_summary(task.cfg, task.source)
        own = set(row)  # the task's columns: a summary's "record" wrote over the table's
        row.update({k: v for k, v in result_columns(s, task.keep, task.source).items()
                    if k not in own})  # fmt: skip
        note = missing_kept(s, task.keep, task.source)  # the cell is empty, and says why
        row["status"], row["error"] = "ok", note[:ERROR_CHARS]
    except Exception as e:  # a failing task is a result, not the end of the study
        row.update({k: v for k, v in getattr(e, "columns", {}).items() if k not in row})
        row.update({k: None for k in task.keep or () if k not in row})  # (empty, not absent)
        msg = " ".join(f"{type(e).__name__}: {e}".split())
        row["status"], row["error"] = "failed", msg[:ERROR_CHARS]
    row["task_s"] = time.perf_counter() - t0
    return row


def run_batch(tasks: list) -> list[dict]:
    """Rows of ``tasks`` run in order (the function executors call)."""
    return [run_task(t) for t in tasks]


def is_number(v) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
