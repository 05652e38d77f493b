"""Study runs on bidirectional isolators (scene kinds ``deck`` and ``building3d``): records with
two horizontal components, the incident angle, the outputs of each run, kernels warmed once.

Records. Every record of such a study has two horizontal components a_x, a_y (and optionally
a vertical a_z): a pair of files (``[records] pairs = [{x, y, z}]``, read together, one Δt
and one length), a ``t, ax, ay[, az]`` CSV, a bundled record with a second horizontal
component, or a simulated pair (a_x from the seed, a_y from an independent stream of the same
seed, no vertical).

Incident angle. The parameter ``motion.rotate`` = θ [deg] turns the horizontal pair
(:meth:`nsdyn.ground.GroundMotion3.rotated`; exact cosines and sines at multiples of 90°):

    a_x' = a_x cos θ − a_y sin θ,   a_y' = a_x sin θ + a_y cos θ,   a_z' = a_z.

θ + 180° is the point reflection of θ's motion: a linear model (the fixed rung) answers it with
the reflected response, the same peaks, so 0–180° covers every incident direction; a deck
whose centre of mass is above the sliding surfaces (h > 0) answers it with other normal
forces (the overturning moment changes sign), so its peaks need not repeat.

Outputs of each run, besides the family's summary (units in the key names):

    peak_base_shear_N = max_t |Σ_i F_i(t)|          rigid, cb and full rungs: F_i = friction +
                                                     restoring + damper and rim force of
                                                     isolator i
                      = max_t |(V_x, V_y)(t)|        fixed rung: the elastic storey forces
    peak_corner_drift = max over storeys, plan corners and x, y of the drift ratio (fixed, cb
                        and full rungs; with the drifts at the centres of mass, the floor
                        accelerations and the torsional moment of the rung's summary)
    incident_angle_deg, pga_resultant_mps2           (the record as run: turned and scaled)

The cb and full rungs also say their ``path`` ("dense", or "sparse" for a full rung on sparse
operators, ``solver.path``) and why. The rigid, fixed, cb and full rungs run here from the
family's readers (``build_system``, ``build_motion``, ``build_solver``; the pair rungs by
:mod:`nsdyn.models.isolated.building3d_pairs_run`), without files; a rung this module does
not know (a new fidelity of ``building3d``) runs through the family's ``run_scene`` in a
temporary directory and keeps its summary as it is (:data:`RUNGS` is the place to add its
outputs). Before the workers start, :func:`warm_kernels` compiles the plane
kernels and the cb and full rungs' pair kernels (dense or sparse path, the law) once.
"""

from __future__ import annotations

import copy
import importlib
import json
import tempfile
import threading
import warnings
from pathlib import Path

import numpy as np

from nsdyn.models.scenefile import SceneError, grid_fields, scene_module
from nsdyn.studies.study import KINDS3C, PAIR_FIELDS, RecordSpec

SYSTEM_CACHE = 16  # built systems (frame, deck constants) kept per process
_systems: dict = {}
_modes: dict = {}  # id(frame), n_modes -> (frame, its fixed-base modes)
_lock = threading.Lock()


# ---- study files -----------------------------------------------------------------------------
def scene_fields(kind: str) -> set[str]:
    """Dotted fields a study parameter may vary on a scene of ``kind`` (its schema's keys)."""
    mod = importlib.import_module(scene_module(kind))
    return {f"{t}.{k}" for t, keys in mod.TABLES.items() if keys for k in keys} | {
        f"motion.{k}" for k in _motion_keys()
    }


def _motion_keys() -> tuple:
    from nsdyn.ground.table3 import RECORD3_KEYS

    return RECORD3_KEYS


def _err(source: str, where: str, msg: str) -> SceneError:
    return SceneError(f"{source}: {where}: {msg}")


def parse_pairs(source: str, study_dir: Path, pairs) -> list[RecordSpec]:
    """``[records] pairs``: a list of tables ``{name, x, y, z}`` (files relative to the study
    file; ``z`` optional). Each is read once here, so a pair of different time steps or lengths
    is refused before any task runs, naming the entry and component."""
    from nsdyn.ground import read_motion3

    if not isinstance(pairs, list) or not pairs:
        raise _err(source, "records.pairs", "expected a list of tables [{ name = ..., "
                   f"x = <file>, y = <file>, z = <file> }}], got {pairs!r}")  # fmt: skip
    out = []
    for i, p in enumerate(pairs):
        where = f"records.pairs[{i}]"
        if not isinstance(p, dict):
            raise _err(source, where, f"expected a table {{x = <file>, y = <file>}}, got {p!r}")
        for key in p:
            if key not in PAIR_FIELDS:
                raise _err(source, f"{where}.{key}", f"unknown field; expected some of "
                           f"{list(PAIR_FIELDS)}")  # fmt: skip
        files = {}
        for key in ("x", "y", "z"):
            if key not in p:
                if key == "z":
                    continue
                raise _err(source, f"{where}.{key}", "missing; expected the file of the "
                           f"{key} component")  # fmt: skip
            if not isinstance(p[key], str):
                raise _err(source, f"{where}.{key}", f"expected a file name, got {p[key]!r}")
            path = Path(p[key]).expanduser()
            path = path if path.is_absolute() else study_dir / path
            if not path.is_file():
                raise _err(source, f"{where}.{key}", f"no such file: {path}")
            files[key] = str(path)
        try:
            read_motion3(files["x"], files["y"], files.get("z"))
        except (OSError, ValueError) as e:
            text = " ".join(str(e).split()).replace(
                "pass trim=True (in a scene, [motion] trim = true) to cut all components to "
                "the shortest",
                "the components of one record need one length (a study's pairs have no trim: "
                "cut the files to one length)",
            )
            key = next((k for k in ("z", "y") if f"{k} component" in text), "x")
            raise _err(source, f"{where}.{key}", text) from None
        name = p.get("name", Path(files["x"]).stem)
        if not isinstance(name, str) or not name:
            raise _err(source, f"{where}.name", f"expected a non-empty string, got {name!r}")
        comps = (files["x"], files["y"], files.get("z"))
        out.append(RecordSpec(name, components=comps))
    return out


def check_two_components(source: str, records: list[RecordSpec]) -> None:
    """A bundled record named for a two-component study must have its second component."""
    from nsdyn.ground import bundled_records, bundled_records3

    for r in records:
        if r.path is not None and r.path in bundled_records() and r.path not in bundled_records3():
            raise _err(source, "records.names", f"{r.path!r} has one horizontal component; a "
                       f"deck or building3d study needs two: {bundled_records3()}, a t, ax, ay "
                       "CSV or [records] pairs")  # fmt: skip


# ---- one run ---------------------------------------------------------------------------------
def simulated_pair(spec: dict):
    """The two-component record of a ``[motion] simulated`` table: a_x as the planar studies'
    simulated record of that seed, a_y from the same generator on an independent stream
    (``SeedSequence([seed, 1])``), no vertical."""
    from nsdyn.ground import GroundMotion3
    from nsdyn.studies.scenes import simulated_motion

    x = simulated_motion(spec)
    seed_y = int(np.random.SeedSequence([int(spec["seed"]), 1]).generate_state(1)[0])
    y = simulated_motion({**spec, "seed": seed_y})
    n = min(x.n, y.n)
    src = f"simulated pair, seed {spec['seed']}"
    return GroundMotion3(x.t0, x.dt, x.a_hor[:n], y.a_hor[:n], None, x.name, src,
                         {"seed": spec["seed"]})  # fmt: skip


def build_system(kind: str, cfg: dict, source: str):
    """The family's ``build_system(cfg, source)``, kept per process for the same structure and
    bearing (the frame's reading and its mass integrals are the slow part of a check)."""
    mod = importlib.import_module(scene_module(kind))
    frame = cfg.get("structure", {}).get("frame3d")
    ident = (
        str(Path(frame).resolve()) if isinstance(frame, str) and Path(frame).is_file() else frame
    )
    sv = cfg.get("solver", {}) if isinstance(cfg.get("solver"), dict) else {}
    path = {k: sv.get(k) for k in ("path", "law", "contact")}  # (a full rung's dense or sparse)
    key = json.dumps([kind, ident, path, {k: v for k, v in cfg.items() if k not in ("motion",
                      "solver", "scene")}], sort_keys=True, default=str)  # fmt: skip
    with _lock:
        hit = _systems.get(key)
    if hit is not None:
        return hit
    built = mod.build_system(cfg, source)
    with _lock:
        if len(_systems) >= SYSTEM_CACHE:
            _systems.pop(next(iter(_systems)))
        _systems[key] = built
    return built


def _plane(system, mod, cfg: dict, source: str) -> dict:
    from nsdyn.models.isolated.deck import simulate_plane

    exc, t_end = mod.build_motion(cfg, source)
    kw = mod.build_solver(cfg, source)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with grid_fields(source):
            res = simulate_plane(system, exc, t_end=t_end, **kw)
    s = res.summary()
    F = (res.friction + res.restoring + res.other).sum(axis=1)  # (nt, 2) on the ground
    s["peak_base_shear_N"] = float(np.hypot(F[:, 0], F[:, 1]).max())
    s["warnings"] = [str(w.message) for w in caught]
    return s | _motion_columns(exc, cfg)


def _fixed(sysd: dict, mod, cfg: dict, source: str) -> dict:
    from nsdyn.models.isolated.fixed3d import fixed_response_3d

    exc, _ = mod.build_motion(cfg, source)
    if not hasattr(exc, "dt"):
        raise SceneError(f"{source}: motion.kind: the fixed rung needs a record "
                         "(kind = 'record3'), not an orbit")  # fmt: skip
    r = fixed_response_3d(sysd["frame"], exc, modes=_fixed_modes(sysd))
    s = r.summary()  # (its peak_base_shear_N the resultant's)
    s["peak_corner_drift"] = max(s["peak_drift_corner_x"], s["peak_drift_corner_y"])
    return s | _motion_columns(exc, cfg)


def _fixed_modes(sysd: dict):
    """The fixed-base modes of a built system's frame, kept per process with the system (the
    eigensolution is most of a fixed-rung task)."""
    from nsdyn.structure import fixed_base_modes_3d

    frame, n = sysd["frame"], sysd["n_modes"]
    with _lock:
        hit = _modes.get((id(frame), n))
    if hit is not None and hit[0] is frame:
        return hit[1]
    modes = fixed_base_modes_3d(frame, n_modes=n)
    with _lock:
        if len(_modes) >= SYSTEM_CACHE:
            _modes.pop(next(iter(_modes)))
        _modes[(id(frame), n)] = (frame, modes)
    return modes


def _motion_columns(exc, cfg: dict) -> dict:
    out = {"incident_angle_deg": float(cfg.get("motion", {}).get("rotate", 0.0))}
    if hasattr(exc, "pga_resultant"):
        out["pga_resultant_mps2"] = exc.pga_resultant
    return out


def _rigid(sysd: dict, mod, cfg: dict, source: str) -> dict:
    return _plane(sysd["deck"], mod, cfg, source)


def _pairs(sysd: dict, mod, cfg: dict, source: str) -> dict:
    """The cb and full rungs (dense, or sparse for a full rung on sparse operators) by
    :func:`~nsdyn.models.isolated.building3d_pairs_run.run_pairs`, without files."""
    from nsdyn.models.isolated.building3d_pairs_run import run_pairs, sparse_solver

    exc, t_end = mod.build_motion(cfg, source)
    kw = mod.build_solver(cfg, source)
    info = sysd["pairs"].info  # (the system is kept per structure; the solver is the task's)
    dt = sparse_solver(cfg, source, info["path_why"]) if info["path"] == "sparse" else None
    _, s, _ = run_pairs(sysd, exc, t_end, kw, dt)
    s["peak_corner_drift"] = max(s["peak_drift_corner_x"], s["peak_drift_corner_y"])
    return s | _motion_columns(exc, cfg)


# building3d fidelity -> its study runner
RUNGS = {"rigid": _rigid, "fixed": _fixed, "cb": _pairs, "full": _pairs}


def run_summary(kind: str, cfg: dict, source: str) -> dict:
    """Run one task of a ``deck`` or ``building3d`` study; its summary with the outputs of the
    module docstring (no figures, no files kept)."""
    mod = importlib.import_module(scene_module(kind))
    cfg = copy.deepcopy(cfg)
    with tempfile.TemporaryDirectory(prefix="nsdyn-task-") as tmp:
        sim = cfg.get("motion", {}).pop("simulated", None)
        if sim is not None:
            from nsdyn.ground import write_motion3

            path = write_motion3(simulated_pair(sim), Path(tmp) / "rec.csv")
            cfg["motion"]["record"] = str(path)
        built = build_system(kind, cfg, source)
        if kind == "deck":
            s = _plane(built, mod, cfg, source)
        elif built["fidelity"] in RUNGS:
            s = RUNGS[built["fidelity"]](built, mod, cfg, source)
        else:  # a rung this module does not know: the family's own run, its summary
            s = mod.run_scene(cfg, source=source, out_dir=Path(tmp), figures=False, quiet=True)
            s = {k: v for k, v in s.items() if not (isinstance(v, str) and v.startswith(tmp))}
            s |= {"incident_angle_deg": float(cfg.get("motion", {}).get("rotate", 0.0))}
    s["kind"] = kind
    if kind == "building3d":
        s["fidelity"] = built["fidelity"]
    return s


# ---- before the workers start -----------------------------------------------------------------
def _plane_laws(tasks) -> set[str]:
    laws = set()
    for t in tasks:
        if t.kind not in KINDS3C:
            continue
        fidelity = t.cfg.get("structure", {}).get("fidelity", "rigid")
        if t.kind == "building3d" and fidelity not in ("rigid", "auto"):
            continue
        laws.add(t.cfg.get("solver", {}).get("law", "switch"))
    return laws


def _pair_runs(tasks) -> set[tuple[str, str, str]]:
    """(path, law, contact) of the building3d tasks on the cb, full and auto rungs (auto
    probes cb); a task whose scene is faulty is left to its own check."""
    from nsdyn.models.isolated import building3d_scene as b3

    out, paths = set(), {}
    for t in tasks:
        st = t.cfg.get("structure", {})
        if t.kind != "building3d" or st.get("fidelity") not in ("cb", "full", "auto"):
            continue
        key = json.dumps([st.get("frame3d"), st.get("base"), st.get("fidelity")], default=str)
        try:
            if key not in paths:
                paths[key] = b3.pairs_path(t.cfg, t.source)
            kw = b3.build_solver(t.cfg, t.source)
            law, contact = kw["law"], kw["contact"]
        except SceneError:
            continue
        path = paths[key]
        if path == "dense" or "law" not in t.cfg.get("solver", {}) or law == "arctan":
            sparse = path == "sparse"
            out.add((path, "arctan" if sparse else law, "detect" if sparse else contact))
    return out


def warm_kernels(tasks) -> list[str]:
    """Compile the plane kernels of the tasks' friction laws once, here, before the workers
    start: numba writes them to its cache and every worker then loads them (a second) instead
    of compiling them side by side (a minute each, on a first run). The same for the pair
    kernels of building3d tasks on the cb, full and auto rungs (the dense or sparse path, the
    law), on a short run of the bundled portal. Returns the laws (and "building3d <path>
    <law>") it compiled (none when the cache holds them)."""
    from nsdyn.models.isolated.bearings import bearing_from_config
    from nsdyn.models.isolated.deck import sdof_plane
    from nsdyn.models.isolated.deck_scene import kernels_cached, warm

    done = []
    for law in sorted(_plane_laws(tasks)):
        if law not in ("switch", "arctan") or kernels_cached(law):
            continue  # a bad law is the task check's to report
        system = sdof_plane(1.0, bearing_from_config({"type": "fps", "radius": 1.0, "mu": 0.05},
                                                     "bearing"))  # fmt: skip
        warm(system, law)
        done.append(law)
    from nsdyn._numba_cache import all_cached
    from nsdyn.models.isolated.building3d_pairs_run import pair_kernels, warm_pairs

    for path, law, contact in sorted(_pair_runs(tasks)):
        if law in ("switch", "arctan") and not all_cached(pair_kernels(path, law, contact)):
            warm_pairs(path, law, contact=contact)
            done.append(f"building3d {path} {law}" + (f" {contact}" if contact != "detect" else ""))
    return done
