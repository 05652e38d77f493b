"""``nsdyn run`` on 3D building scenes (``[scene] kind = "building3d"``): every rung of the ladder.

Tables (keys in :mod:`nsdyn.models.isolated.building3d_scene_keys`):

* ``[structure]`` ``frame3d`` (a bundled 3D frame or a file), ``fidelity`` "rigid" | "fixed" |
  "cb" | "full" | "auto", ``eccentricity`` [f_x, f_y] (accidental, fractions of the plan),
  ``n_modes`` (fixed), ``f_max``, ``min_mass``, ``base`` (cb and full), ``damping`` and
  ``f_damp`` (full on sparse operators);
* ``[bearing]``, ``[motion]``, ``[solver]``: those of the deck scene
  (:mod:`nsdyn.models.isolated.deck_scene`), ``[solver] dt`` the sparse full rung's step.

``rigid``: the frame as the rigid deck of :func:`nsdyn.models.isolated.building3d.building_deck`
(m, J, centre of mass and its height from the mass matrix), one bearing under every base node,
integrated by :func:`~nsdyn.models.isolated.deck.simulate_plane`; writes ``building3d.npz``
(deck histories). ``fixed``: :func:`nsdyn.models.isolated.fixed3d.fixed_response_3d` under a
three-component record, storey drifts at the centre of mass and the corners, floor
accelerations, base shear and torsional moment; writes ``building3d.npz`` (those histories).
``cb`` / ``full``: the pair system of :func:`nsdyn.models.isolated.building3d_cb.building_pairs`
run by :func:`~nsdyn.models.isolated.pairs.simulate_pairs` from its static state; writes
``building3d.npz`` (isolator orbits, normal and bearing forces, drifts at the centres of mass
and the corners, floor accelerations, base shear and torsional moment); triple friction
pendulums there run with the regularised law on Radau IIA (contact "detect" or "bilateral";
their internal slips in the state, :mod:`nsdyn.models.isolated.pairs`). ``full`` on a frame
above the dense full rung's limit runs the same model on sparse operators
(:mod:`nsdyn.models.isolated.building3d_pairs_run`: the path, its step, law and damping
``structure.damping``); the summary's ``path`` and ``path_why`` say which ran and why. ``auto``:
:func:`nsdyn.models.isolated.building3d_advice.advise_building` probes the rungs on the
record, prints its evidence and runs the rung it advises. ``nsdyn run`` prints the summary.
"""

from __future__ import annotations

import math
import sys
import time
import warnings
from contextlib import nullcontext
from pathlib import Path

import numpy as np

from nsdyn._checks import NotedWarning
from nsdyn.atomic import atomic_open
from nsdyn.models.isolated.bearings import (
    BearingError,
    bearing_from_config,
    bearing_notes,
    slip_ratio_note,
)
from nsdyn.models.isolated.building3d_pairs_run import (
    PATHS,
    check_sparse_step,
    full_path,
    path_line,
    peak_field,
    run_pairs,
    sparse_solver,
    warm_pairs,
    warming,
)
from nsdyn.models.isolated.building3d_scene_keys import (
    BASES,
    DAMPINGS,
    FIDELITIES,
    SCHEMA,
    format_summary,
    unused_keys,
)
from nsdyn.models.isolated.building3d_shape import fixed_peak_shape, rigid_peak_shape, write_shape
from nsdyn.models.isolated.deck_scene import build_motion as deck_motion
from nsdyn.models.isolated.deck_scene import build_solver as deck_solver
from nsdyn.models.isolated.deck_scene import (
    record_end_note,
    record_scale,
    scene_law,
)
from nsdyn.models.isolated.friction import coarse_law_note
from nsdyn.models.isolated.plane_energy import closure_note
from nsdyn.models.scenefile import SceneError, check_fields, grid_fields, number

__all__ = ["build_motion", "build_solver", "build_system", "format_summary", "pairs_path",
           "run_scene"]  # fmt: skip

TABLES = SCHEMA.fields()
FIGURE_MODULE = "nsdyn.plot.frames3d"  # draws the figures from building3d-shape.npz


def _eccentricity(t: dict, source: str) -> list:
    """``structure.eccentricity`` checked (before a build's notice), and the frame's name."""
    name = t.get("frame3d")
    if not isinstance(name, str) or not name:
        got = "nothing (missing)" if name is None else repr(name)
        raise SceneError(f"{source}: structure.frame3d: expected a bundled 3D frame name "
                         f"(office-11-3d) or a 3D frame file, got {got}")  # fmt: skip
    ecc = t.get("eccentricity", [0.0, 0.0])
    ok = isinstance(ecc, list) and len(ecc) == 2 and all(
        isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
        and abs(v) < 0.5 for v in ecc
    )  # fmt: skip
    if not ok:
        raise SceneError(f"{source}: structure.eccentricity: expected [f_x, f_y], fractions of "
                         f"the plan dimensions in (-0.5, 0.5), got {ecc!r}")  # fmt: skip
    return ecc


def _frame(t: dict, source: str):
    from nsdyn.structure import accidental_eccentricity, load_frame3d

    ecc = _eccentricity(t, source)
    try:  # a file beside the scene: made findable by read_toml
        frame = load_frame3d(t["frame3d"])
    except (OSError, ValueError) as e:
        raise SceneError(f"{source}: structure.frame3d: {' '.join(str(e).split())}") from None
    if any(ecc):
        try:
            frame = accidental_eccentricity(frame, float(ecc[0]), float(ecc[1]))
        except ValueError as e:
            raise SceneError(f"{source}: structure.eccentricity: {e}") from None
    return frame


def _cb_options(t: dict, source: str) -> dict:
    """f_max, min_mass, base, damping, f_damp of ``[structure]`` (SceneError naming the
    field; f_damp None: pairs_sparse's default)."""
    out = {}
    for key, default, lo_open in (("f_max", 5.0, True), ("min_mass", 1e-4, False),
                                  ("f_damp", None, True)):  # fmt: skip
        v = t.get(key, default)
        if v is None:
            out[key] = None
            continue
        ok = isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
        if not (ok and (v > 0 if lo_open else 0 <= v < 1)):
            want = "a positive frequency [Hz]" if lo_open else "a fraction in [0, 1)"
            raise SceneError(f"{source}: structure.{key}: expected {want}, got {v!r}")
        out[key] = float(v)
    out["base"] = t.get("base", "grid")
    if out["base"] not in BASES:
        raise SceneError(f"{source}: structure.base: expected one of {list(BASES)}, got "
                         f"{out['base']!r}")  # fmt: skip
    out["damping"] = t.get("damping", "modal")
    if out["damping"] not in DAMPINGS:
        raise SceneError(f"{source}: structure.damping: expected one of {list(DAMPINGS)}, got "
                         f"{out['damping']!r}")  # fmt: skip
    return out


def _bearing(cfg: dict, source: str, fid: str):
    if "bearing" not in cfg:
        raise SceneError(f"{source}: bearing: missing; the {fid} rung needs a [bearing] "
                         "table (type, radius, mu, d_cap, …)")  # fmt: skip
    try:
        return bearing_from_config(cfg["bearing"], "bearing")
    except BearingError as e:
        raise SceneError(f"{source}: {e}") from None


def pairs_path(cfg: dict, source: str) -> str:
    """The path ("dense" or "sparse") a scene's cb or full run takes (its frame read, not
    reduced; a study's parent asks it to compile the right kernels)."""
    t = cfg.get("structure", {})
    if t.get("fidelity") != "full":
        return "dense"
    return _full_path(_frame(t, source), _bearing(cfg, source, "full"), cfg, source)[0]


def _full_path(frame, bearing, cfg: dict, source: str) -> tuple[str, str]:
    """:func:`full_path` of a scene's full rung (its base, law, contact, bearing and
    ``solver.path``; SceneError naming the field)."""
    solver, base = cfg.get("solver", {}), cfg.get("structure", {}).get("base", "grid")
    try:  # the law the scene runs, so that "auto" never changes the friction model
        return full_path(frame, base, scene_law(cfg), solver.get("contact", "detect"), bearing,
                         _path(cfg, source))  # fmt: skip
    except SceneError as e:
        raise SceneError(f"{source}: {e}") from None


def _sparse_pairs(frame, bearing, opts: dict, cfg: dict, source: str, why: str):
    """The full rung's SparsePairSystem (module text; SceneError naming the field)."""
    from nsdyn._model_cache import cached_build
    from nsdyn.models.isolated.pairs import PairSystemError
    from nsdyn.models.isolated.pairs_sparse import building_pairs_sparse

    sparse_solver(cfg, source, why, bearing)
    f_damp = opts["f_damp"] if opts["damping"] == "modal" else None  # (noted as not used)
    kw = {"damping": opts["damping"], "f_damp": f_damp, "base": opts["base"]}
    try:  # run again, it loads the system (the damped modes' eigenproblem: seconds)
        system = cached_build("building3d-pairs-sparse", (frame, bearing, sorted(kw.items())),
                              lambda: building_pairs_sparse(frame, bearing, **kw))  # fmt: skip
    except PairSystemError as e:
        msg = " ".join(str(e).split())
        where = "bearing" if ".bearings[" in msg else "structure"
        msg = "positive definite mass" in msg and frame.massless_note("full") or msg
        raise SceneError(f"{source}: {where}: {msg} (the full rung on sparse operators: "
                         f"{why})") from None  # fmt: skip
    except (BearingError, ValueError) as e:
        raise SceneError(f"{source}: structure: {' '.join(str(e).split())}") from None
    system.info.update(path="sparse", path_why=why)
    return system


def build_pairs(frame, bearing, fid: str, opts: dict, source: str, cfg: dict | None = None):
    """The cb or full pair system of a scene's frame (SceneError naming the field): a dense
    PairSystem, or for "full" on the sparse path a SparsePairSystem (:func:`full_path`);
    ``info["path"]``, ``info["path_why"]`` say which and why."""
    from nsdyn.models.isolated.building3d_cb import building_pairs

    path, why = "dense", f"the cb rung: the fixed-interface modes up to {opts['f_max']:g} Hz"
    if fid == "full":
        path, why = _full_path(frame, bearing, cfg or {}, source)
    if path == "sparse":
        return _sparse_pairs(frame, bearing, opts, cfg or {}, source, why)
    from nsdyn._model_cache import cached_build

    kw = {"fidelity": fid, "f_max": opts["f_max"], "min_mass": opts["min_mass"] or None,
          "base": opts["base"]}  # fmt: skip
    try:  # a scene run again loads its pair system (the reduction's eigenproblem: seconds)
        system = cached_build("building3d-pairs", (frame, bearing, sorted(kw.items())),
                              lambda: building_pairs(frame, bearing, **kw))  # fmt: skip
    except BearingError as e:  # (a PairSystemError too: a singular M, its massless node)
        bare = "positive definite mass" in str(e) and frame.massless_note(fid)
        raise SceneError(f"{source}: {f'structure: {bare}' if bare else e}") from None
    except ValueError as e:
        raise SceneError(f"{source}: structure: {' '.join(str(e).split())}") from None
    system.info.update(path="dense", path_why=why)
    return system


def _deck(frame, bearing, source: str):
    """The rigid deck of ``frame`` on ``bearing`` (SceneError naming the field): the rigid
    rung's system and every rung's static forces (it checks a pendulum's rim, pairs don't)."""
    from nsdyn.models.isolated.building3d import building_deck

    try:
        return building_deck(frame, bearing)
    except (BearingError, ValueError) as e:
        raise SceneError(f"{source}: {e}") from None


def build_system(cfg: dict, source: str, warm: bool = False, notice=None) -> dict:
    """{"fidelity", "frame", "deck" (rigid) or None, "statics" (the rigid deck of every
    isolated rung: its static forces), "pairs" (cb, full) or None, "bearing", "n_modes",
    "cb" (f_max, min_mass, base)} of a scene (SceneError naming the field).
    ``warm``: a cb or full rung's first compilation runs while its model builds
    (:func:`~nsdyn.models.isolated.building3d_pairs_run.warming`; ``nsdyn run``), and the
    dict holds ``compile_s`` and ``wait_s`` (the build's wait for it). ``notice()`` is
    called once the scene's fields are checked, before the frame is read and built."""
    check_fields({k: v for k, v in cfg.items() if k != "motion"},
                 {k: v for k, v in TABLES.items() if k != "motion"}, source, TABLES)  # fmt: skip
    t = cfg.get("structure")
    if not isinstance(t, dict):
        raise SceneError(f"{source}: structure: missing; expected a [structure] table with "
                         "frame3d = <bundled name or file>")  # fmt: skip
    fid = t.get("fidelity", "rigid")
    if fid not in FIDELITIES:
        raise SceneError(f"{source}: structure.fidelity: expected one of {list(FIDELITIES)}, "
                         f"got {fid!r}")  # fmt: skip
    n_modes = t.get("n_modes", 24)
    if isinstance(n_modes, bool) or not isinstance(n_modes, int) or n_modes < 1:
        raise SceneError(f"{source}: structure.n_modes: expected an integer >= 1, got "
                         f"{n_modes!r}")  # fmt: skip
    opts = _cb_options(t, source)
    if "dt" in cfg.get("solver", {}):  # the sparse full rung's step, checked on every rung
        number(source, "solver.dt", cfg["solver"]["dt"])
    bearing = _bearing(cfg, source, fid) if fid != "fixed" else None
    _eccentricity(t, source)
    if notice is not None:  # (it came before a refused structure.base or a missing bearing)
        notice()
    frame = _frame(t, source)
    pairs = None
    times: dict = {}
    statics = _deck(frame, bearing, source) if bearing is not None else None  # (seconds
    if fid in ("cb", "full"):  # before a reduction that its bearing's mistake would waste)
        path = "dense" if fid == "cb" else _full_path(frame, bearing, cfg, source)[0]
        law = scene_law(cfg)  # (the loop the run takes: switch unless given or a tfp)
        contact = cfg.get("solver", {}).get("contact", "detect")
        with warming(path, law, contact) if warm else nullcontext(times) as times:
            pairs = build_pairs(frame, bearing, fid, opts, source, cfg)
    return {"fidelity": fid, "frame": frame, "deck": statics if fid == "rigid" else None,
            "statics": statics, "pairs": pairs, "bearing": bearing, "n_modes": n_modes,
            "n_modes_given": "n_modes" in t, "cb": opts, **times}  # fmt: skip


def _path(cfg: dict, source: str) -> str:
    """``solver.path`` (SceneError naming the field)."""
    path = cfg.get("solver", {}).get("path", "auto")
    if path not in PATHS:
        raise SceneError(f"{source}: solver.path: expected one of {list(PATHS)}, got {path!r}")
    return path


def build_solver(cfg: dict, source: str) -> dict:
    """The run's keywords from ``[solver]`` (as the deck scene's, and ``contact =
    "unilateral"``, which the cb and dense full rungs take; ``path`` checked on every rung)."""
    _path(cfg, source)
    return deck_solver(cfg, source, unilateral=True)


def build_motion(cfg: dict, source: str):
    """(excitation, t_end) from ``[motion]`` (as the deck scene's)."""
    return deck_motion(cfg, source)


def _run_rigid(sysd, exc, t_end, kw, out_dir: Path, say) -> dict:
    from nsdyn._numba_cache import first_compile
    from nsdyn._progress import reporter
    from nsdyn.models.isolated.building3d_response import base_force_peaks
    from nsdyn.models.isolated.deck import simulate_plane
    from nsdyn.models.isolated.deck_scene import COMPILE_ABOUT_S, kernels_cached

    deck = sysd["deck"]
    w0 = time.perf_counter()
    with first_compile("deck", COMPILE_ABOUT_S, kernels_cached(kw["law"])), \
            warnings.catch_warnings():  # fmt: skip
        warnings.simplefilter("ignore", NotedWarning)  # (a warm-up: the notes say them)
        simulate_plane(deck, {"f": 1.0, "ax": 0.0, "ay": 0.0}, t_end=0.04, law=kw["law"])
    compile_s = time.perf_counter() - w0
    w0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warnings.simplefilter("ignore", NotedWarning)  # (the scene's notes say them)
        res = simulate_plane(deck, exc, t_end=t_end, progress=reporter(say), **kw)
    wall = time.perf_counter() - w0
    for w in caught:
        say(f"building3d: warning: {w.message}")
    s = {**res.summary(), **res.energy(exc), **base_force_peaks(res, deck.ecc)}  # (as cb's)
    npz = out_dir / "building3d.npz"
    with atomic_open(npz, "wb") as fh:
        np.savez(fh, t=res.t, q=res.q, qd=res.qd, u=res.u, N=res.N, friction=res.friction,
                 restoring=res.restoring, other=res.other, positions=deck.positions,
                 origin=deck.info["origin"], **res.element_slips())  # fmt: skip
    info = deck.info
    s.update({"mass_kg": info["m"], "polar_inertia_kgm2": info["J"],
              "centre_of_mass_m": [float(v) for v in info["centre"]],
              "height_of_centre_of_mass_m": info["h"], "wall_s": wall, "compile_s": compile_s,
              "files": [str(npz), str(write_shape(out_dir, sysd["frame"],
                                                  rigid_peak_shape(sysd["frame"], deck, res)))],
              "warnings": [str(w.message) for w in caught]})  # fmt: skip
    return s


def _run_fixed(sysd, exc, source: str, out_dir: Path, say) -> dict:
    from nsdyn.models.isolated.fixed3d import few_modes_note, fixed_response_3d
    from nsdyn.structure.modes3d import mass_centre

    w0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warnings.simplefilter("ignore", NotedWarning)  # (the scene's notes say them)
        try:
            r = fixed_response_3d(sysd["frame"], exc, n_modes=sysd["n_modes"])
        except ValueError as e:
            raise SceneError(f"{source}: structure: {' '.join(str(e).split())}") from None
    wall = time.perf_counter() - w0
    for w in caught:
        say(f"building3d: warning: {w.message}")
    s = r.summary()
    c, m, _ = mass_centre(sysd["frame"])  # (the keys the isolated rungs report)
    s.update({"mass_kg": m, "centre_of_mass_m": [float(v) for v in c],
              "warnings": [str(w.message) for w in caught]})  # fmt: skip
    npz = out_dir / "building3d.npz"
    with atomic_open(npz, "wb") as fh:
        np.savez(fh, t=r.t, f_hz=r.modes.f_hz, drift_cm=r.drifts.cm, drift_corner=r.drifts.corner,
                 corners=r.drifts.corners, floor_acc=r.floor_acc, base_shear=r.base_shear,
                 torsion=r.torsion)  # fmt: skip
    shape = write_shape(out_dir, sysd["frame"], fixed_peak_shape(r), r.modes)
    s.update({"t_end_s": float(r.t[-1]), "wall_s": wall, "files": [str(npz), str(shape)]})
    given = sysd.get("n_modes_given", True)  # (the default 24 on a smaller building: no note)
    s["few_modes"] = few_modes_note(sysd["n_modes"], r.modes) if given else None
    return s


def _run_pairs(sysd, exc, t_end, kw, out_dir: Path, say, dt=None) -> dict:
    from nsdyn._progress import reporter

    system = sysd["pairs"]
    info = system.info
    compile_s = warm_pairs(info.get("path", "dense"), kw["law"], system, kw["contact"])
    compile_s += sysd.get("compile_s", 0.0)
    say(f"building3d: {info['fidelity']} rung, {path_line(info)}")
    r, s, caught = run_pairs(sysd, exc, t_end, kw, dt, reporter(say))
    for w in caught:
        say(f"building3d: warning: {w.message}")
    res = r.result
    npz = out_dir / "building3d.npz"
    with atomic_open(npz, "wb") as fh:
        np.savez(fh, t=r.t, q=res.q, qd=res.qd, u=res.u, N=res.N, friction=res.friction,
                 restoring=res.restoring, other=res.other, positions=system.positions,
                 origin=info["origin"], drift_cm=r.drifts.cm, drift_corner=r.drifts.corner,
                 corners=r.drifts.corners, floor_acc=r.floor_acc, base_shear=r.base_shear,
                 torsion=r.torsion, f_hz=info["f_hz"], **res.element_slips())  # fmt: skip
    shape = write_shape(out_dir, sysd["frame"], peak_field(system, r, exc, s, kw["eps"]))
    s.update({"reduction_s": sysd.get("build_s", float("nan")), "compile_s": compile_s,
              "files": [str(npz), str(shape)]})  # fmt: skip
    return s


def _advise(sysd, cfg, exc, kw, source: str, say) -> None:
    """fidelity "auto": the advisor's rung into ``sysd`` (its report on stderr)."""
    from nsdyn.models.isolated.building3d_advice import advise_building, elastic_probe, report

    opts = sysd["cb"]
    w0 = time.perf_counter()
    pairs = build_pairs(sysd["frame"], sysd["bearing"], "cb", opts, source)
    f0 = pairs.info["f_max"]
    pairs = elastic_probe(pairs, lambda f: build_pairs(sysd["frame"], sysd["bearing"], "cb",
                                                       {**opts, "f_max": f}, source))  # fmt: skip
    if pairs.info["f_max"] != f0:
        say(f"building3d: the cb model at f_max = {f0:g} Hz keeps no elastic mode (it is the "
            f"rigid deck again): the probe and a cb answer use f_max = "
            f"{pairs.info['f_max']:g} Hz")  # fmt: skip
    build_s = time.perf_counter() - w0
    sysd["build_s"] += build_s
    sysd["compile_s"] = warm_pairs("dense", kw["law"], pairs, kw["contact"])
    advice = advise_building(sysd["frame"], sysd["bearing"], exc, solver=kw, system=pairs)
    advice["evidence"]["cb_probe"]["build_s"] = build_s
    say(report(advice))
    fid = advice["fidelity"]
    sysd.update(fidelity=fid, advice=advice)
    if fid == "rigid":
        sysd["deck"] = sysd["statics"]
    elif fid == "cb":
        sysd["pairs"] = pairs


def build_notes(cfg: dict, sysd: dict) -> list[str]:
    """The notes of a run that its built rung decides (:func:`build_system`, its fidelity
    chosen): the keys it does not read, a cb model without a fixed-interface mode or with
    too little of a direction's effective mass (:func:`~.building3d_cb.cb_notes`)."""
    from nsdyn.models.isolated.building3d_cb import cb_notes

    if sysd["fidelity"] == "auto":  # (chosen by the run, from the motion)
        return []
    info = sysd["pairs"].info if sysd["pairs"] is not None else {}
    notes = [f"{k} not used: {w}" for k, w in unused_keys(cfg, sysd["fidelity"], info.get("path"))]
    return notes + cb_notes(info)  # (no mode below f_max, or too little of a direction's)


def run_scene(cfg: dict, *, source: str, out_dir: Path, figures: bool, quiet: bool) -> dict:
    """Run a 3D building scene; writes ``building3d.npz`` into ``out_dir``; the summary."""
    name = cfg.get("scene", {}).get("name", Path(source).stem)
    say = (lambda *a: None) if quiet else (lambda *a: print(*a, file=sys.stderr))
    st = cfg.get("structure")
    fid = st.get("fidelity") if isinstance(st, dict) else None
    exc, t_end = build_motion(cfg, source)  # their mistakes refused before a build of seconds
    if fid == "fixed" and not hasattr(exc, "dt"):
        raise SceneError(f"{source}: motion.kind: the fixed rung needs a record "
                         "(kind = 'record3'), not an orbit")  # fmt: skip
    if fid == "auto" and not hasattr(exc, "dt"):
        raise SceneError(f"{source}: structure.fidelity: 'auto' probes the rungs on a record "
                         "(kind = 'record3'), not an orbit")  # fmt: skip
    kw = build_solver(cfg, source)
    slow = fid in ("cb", "full", "auto")  # a reduction or the damped modes: seconds of build
    w0 = time.perf_counter()
    sysd = build_system(cfg, source, warm=True, notice=lambda: slow and say(
        f"building3d: {name}: building the {fid} model…"))  # fmt: skip
    sysd["build_s"] = time.perf_counter() - w0 - sysd.get("wait_s", 0.0)
    frame = sysd["frame"]
    say(f"building3d: {name}: {frame.name}, {len(frame.base_nodes)} column lines, "
        f"fidelity {sysd['fidelity']}, {getattr(exc, 'name', type(exc).__name__)}")  # fmt: skip
    notes: list = []  # one line each on stderr, and the summary's "notes"
    if sysd["bearing"] is not None:
        from nsdyn.models.isolated.building3d import weight_note

        deck = sysd["statics"]  # its static forces
        notes = bearing_notes(deck.bearings, deck.static_normal())
        weight = weight_note(frame.name, deck.info["m"], deck.info["m_z"])
        notes += [weight] if weight else []
    out_dir = Path(out_dir)
    asked = sysd["fidelity"]
    if asked == "auto":
        _advise(sysd, cfg, exc, kw, source, say)
    notes += build_notes(cfg, sysd) + [n for n in [record_end_note(cfg, exc)] if n]
    notes += [n for n in [coarse_law_note(kw["law"], kw["eps"], kw["eta"])] if n]
    for note in notes:
        say(f"building3d: note: {note}")
    if sysd["fidelity"] == "rigid":
        if kw["contact"] == "unilateral":
            raise SceneError(f"{source}: solver.contact: the rigid rung (the building as a deck, "
                             "no vertical or rocking motion) takes 'detect' or 'bilateral', "
                             "got 'unilateral'")  # fmt: skip
        with grid_fields(source):  # the run's grid: its table's field, before any step
            s = _run_rigid(sysd, exc, t_end, kw, out_dir, say)
    elif sysd["fidelity"] in ("cb", "full"):
        info = sysd["pairs"].info
        if getattr(sysd["pairs"], "has_tfp", False) and kw["contact"] == "unilateral":
            raise SceneError(f"{source}: solver.contact: a triple friction pendulum (bearing."
                             "type = 'tfp') runs on Radau IIA, whose contacts are 'detect' or "
                             "'bilateral', got 'unilateral'")  # fmt: skip
        dt = sparse_solver(cfg, source, info["path_why"]) if info["path"] == "sparse" else None
        check_sparse_step(dt, exc, t_end, source)
        with grid_fields(source):
            s = _run_pairs(sysd, exc, t_end, kw, out_dir, say, dt)
    else:
        s = _run_fixed(sysd, exc, source, out_dir, say)
        few = s.pop("few_modes")
        if few:
            notes.append(few)
            say(f"building3d: note: {few}")
    peaks = s.get("peak_resultant_displacement_per_isolator_m")
    big = slip_ratio_note(deck.bearings, peaks) if sysd["bearing"] is not None and peaks else None
    for note in (big, closure_note(s)):  # (a pendulum slip past R/4; landings, a failed run)
        if note:
            notes.append(note)
            say(f"building3d: note: {note}")
    s.update({"kind": "building3d", "name": name, "frame": frame.name,
              "fidelity": sysd["fidelity"], "notes": notes,
              "motion": getattr(exc, "name", type(exc).__name__)})  # fmt: skip
    s.update(record_scale(cfg, exc))
    if asked == "auto":
        s["advice"] = {"fidelity": sysd["fidelity"], **sysd["advice"]["evidence"]}
    say(f"building3d: done in {s['wall_s']:.3f} s")
    return s
