"""Frequency–amplitude curves of deck scenes: periodic orbits on bidirectional isolators.

A scene of kind ``deck`` (a mass or a rigid deck on bidirectional isolators) or ``building3d``
at the ``rigid`` fidelity (the building as a deck) under a harmonic orbit (``[motion] kind =
"orbit"``: linear, circular, elliptical or general) is driven at each amplitude A by the
scene's orbit scaled to A (its shape kept: direction, axis ratio, sense, phases; a vertical
component at a whole multiple of f follows f), and its periodic orbits are continued over f
(:func:`nsdyn.periodic.plane.plane_response`: shooting on the period map with located
stick–slip events or the regularised law, stepped-sweep fallback). The response is the peak
resultant isolator displacement max_t |u_i(t)|. Amplitudes run in parallel processes; each
writes a checkpoint after every few points, so an interrupted sweep resumes where it stopped.
Outputs: one CSV row per point (``sweep.csv``), the whole report as JSON (``sweep.json``),
and the figure (drawn by the command line, :mod:`nsdyn.plot.plane_sweep`).

Without a range, the frequencies run from f0/4 to 4 f0 (``POINTS_DEFAULT`` log-spaced), f0
the scene's orbit frequency; without amplitudes, the scene's orbit amplitude.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import sys
import time
import warnings
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from nsdyn._progress import PointLines, curve_count
from nsdyn.atomic import atomic_open
from nsdyn.models.isolated.friction import stick_slip
from nsdyn.models.scenefile import SceneError, number
from nsdyn.studies.sweep import (
    CHECKPOINT_EVERY_S,
    amplitude_tag,
    format_csv_value,
    refuse_foreign,
    resumed_start,
)
from nsdyn.studies.sweep_points import point_to_dict
from nsdyn.studies.workers import gather, process_pool, saved_on_interrupt

KINDS = ("deck", "building3d")
RANGE_FACTOR = 4.0  # default range f0 / RANGE_FACTOR .. RANGE_FACTOR f0
POINTS_DEFAULT = 25
CSV_COLUMNS = (
    "f", "A", "u_peak_m", "u_component_peak_m", "friction_peak_N", "torsion_peak_rad",
    "normal_min_N", "stick_fraction", "events_per_period", "stable", "max_multiplier_modulus",
    "method", "newton_iterations", "residual", "converged", "samples", "uplift", "rim_contact",
    "law", "note",
)  # fmt: skip


@dataclass(frozen=True)
class PlaneSweepSettings:
    """What a deck curve depends on besides the scene (part of the checkpoint's identity)."""

    fmin: float
    fmax: float
    points: int = POINTS_DEFAULT
    continuation: str = "sequential"
    fallback: bool = True
    law: str = "switch"  # "switch" (stick disc) or "arctan" (regularised)


CHECKPOINT_NAME = ".sweep-plane-A{amplitude}.ckpt.json"  # one per amplitude, in the output dir


def plane_scene(cfg: dict, source: str) -> dict:
    """{"kind", "system" (PlaneSystem), "orbit" (HarmonicPlane), "solver" (law, eps, eta),
    "name", "sweep" (the deck scene's [sweep] keys given)} of a deck or rigid building3d
    scene under an orbit; SceneError naming the field."""
    from nsdyn.ground.orbit import NOT_AN_ORBIT, HarmonicPlane

    kind = cfg.get("scene", {}).get("kind")
    if kind == "deck":
        from nsdyn.models.isolated import deck_scene as ds

        system = ds.build_system(cfg, source)
        orbit, _ = ds.build_motion(cfg, source)
        solver = ds.build_solver(cfg, source)
        sweep = ds.build_sweep(cfg, source)
    elif kind == "building3d":
        from nsdyn.models.isolated import building3d_scene as bs

        st = cfg.get("structure")
        fid = st.get("fidelity", "rigid") if isinstance(st, dict) else "rigid"
        if fid in bs.FIDELITIES and fid != "rigid":  # (before the rung is built: its checks
            # blamed a law the sweep does not take)
            raise SceneError(f"{source}: structure.fidelity: nsdyn sweep takes a building3d "
                             "scene at the rigid fidelity (the building as a deck) or the fixed "
                             f"one (the linear steady state), got {fid!r}")  # fmt: skip
        system = bs.build_system(cfg, source)["deck"]
        orbit, _ = bs.build_motion(cfg, source)
        solver = bs.build_solver(cfg, source)
        sweep = {}
    else:
        raise SceneError(f"{source}: scene.kind: expected one of {list(KINDS)}, got {kind!r}")
    if solver.get("contact", "detect") != "detect":
        raise SceneError(f"{source}: solver.contact: nsdyn sweep's periodic orbits keep every "
                         f"contact closed (uplift detected); expected 'detect', got "
                         f"{solver['contact']!r}")  # fmt: skip
    if not isinstance(orbit, HarmonicPlane):
        raise SceneError(f"{source}: {NOT_AN_ORBIT}")
    try:
        from nsdyn.periodic.plane import orbit_shape

        orbit_shape(orbit)
    except ValueError as e:
        key = "vertical_frequency" if "f_z" in str(e) else "amplitude"
        raise SceneError(f"{source}: motion.{key}: {e}") from None
    name = cfg.get("scene", {}).get("name", Path(source).stem)
    given = cfg.get("solver", {})  # (--friction may take the law whose keys the run drops)
    keep = {"law": solver["law"], **{k: number(source, f"solver.{k}", given.get(k, solver[k]))
                                     for k in ("eps", "eta")}}  # fmt: skip
    return {"kind": kind, "system": system, "orbit": orbit, "solver": keep, "name": name,
            "sweep": sweep}  # fmt: skip


def default_range(orbit) -> tuple[float, float]:
    """(f0 / RANGE_FACTOR, RANGE_FACTOR f0) around the orbit's frequency f0."""
    return orbit.f / RANGE_FACTOR, orbit.f * RANGE_FACTOR


def _identity(cfg: dict, amplitude: float, settings: PlaneSweepSettings) -> dict:
    scene = {k: v for k, v in cfg.items() if not k.startswith("_")}
    return {"scene": scene, "amplitude": amplitude, "settings": asdict(settings)}


def checkpoint_path(out_dir: Path, amplitude: float) -> Path:
    return Path(out_dir) / CHECKPOINT_NAME.format(amplitude=amplitude_tag(amplitude))


def amplitude_job(cfg: dict, source: str, amplitude: float, settings: PlaneSweepSettings,
                  out_dir: str, restart: bool = False, quiet: bool = False) -> dict:  # fmt: skip
    """The curve at one amplitude, resumable through its checkpoint; a picklable summary
    (CSV rows, failures, bifurcations, timings)."""
    from nsdyn.periodic.plane import curve_rows, plane_problem, plane_response

    t0 = time.perf_counter()
    sc = plane_scene(cfg, source)
    from nsdyn.models.isolated.friction import LAW_KEYS

    law = settings.law  # (the keys of the law --friction may have replaced: not read)
    kw = {k: v for k, v in sc["solver"].items() if LAW_KEYS.get(k, (law,))[0] == law}
    pb = plane_problem(sc["system"], sc["orbit"], amplitude=amplitude, **{**kw, "law": law})
    ident = _identity(cfg, amplitude, settings)
    ckpt = checkpoint_path(Path(out_dir), amplitude)
    start = resumed_start(ckpt, ident, amplitude, restart, quiet)
    n_resumed = len(start or [])
    done = list(start or [])
    last = [time.perf_counter()]

    def save(points, complete=False):
        data = {"identity": ident, "complete": complete,
                "points": [point_to_dict(p) for p in points]}  # fmt: skip
        with atomic_open(ckpt, "w") as fh:
            fh.write(json.dumps(data))
        last[0] = time.perf_counter()

    walls = []  # this run's points' wall times (the estimate of the rest)
    lines = PointLines(lambda text: print(text, file=sys.stderr, flush=True))

    def progress(pt, k, n):
        done.append(pt)
        walls.append(pt.quantities.get("wall_s"))
        if time.perf_counter() - last[0] > CHECKPOINT_EVERY_S:
            save(done)
        if not quiet:
            u = pt.quantities.get("u_peak_m", math.nan)
            u = f"|u|max={u:.4g} m" if pt.converged else "no steady state"
            of, left = curve_count(k, n, walls, settings.continuation)
            wall = pt.quantities.get("wall_s", 0.0)
            line = (f"[A={amplitude:g}] {k:4d}{of} f={pt.f:8.4f} Hz {pt.method:9s} "
                    f"it={pt.iterations:2d} {u} ({wall:.2f} s")  # fmt: skip
            lines(f"{line}{left})", k, n, pt.converged, final=f"{line})")

    from nsdyn.periodic.curve import EmptyCurveWarning

    with (saved_on_interrupt(lambda: len(done) > n_resumed and save(done)),  # (for a rerun)
          warnings.catch_warnings(), contextlib.closing(lines)):  # fmt: skip
        warnings.simplefilter("ignore", EmptyCurveWarning)  # (said by its status 3)
        curve = plane_response(pb, fmin=settings.fmin, fmax=settings.fmax,
                               points=settings.points, continuation=settings.continuation,
                               fallback=settings.fallback, progress=progress,
                               start=start)  # fmt: skip
    save(curve.points, complete=True)
    rows = curve_rows(curve)
    for r in rows:
        r["law"] = settings.law
    return {"A": amplitude, "model": sc["name"], "rows": rows,
            "failures": curve.info["failures"], "bifurcations": curve.bifurcations,
            "jumps": list(curve.info.get("jumps", [])), "resumed_points": n_resumed,
            "wall_s": time.perf_counter() - t0}  # fmt: skip


def refuse_foreign_checkpoints(cfg, amplitudes, settings, out_dir) -> None:
    """CheckpointMismatch for an unfinished checkpoint written with other settings."""
    refuse_foreign((a, checkpoint_path(out_dir, a), _identity(cfg, a, settings))
                   for a in amplitudes)  # fmt: skip


def sweep_plane(cfg: dict, source: str, amplitudes, settings: PlaneSweepSettings, out_dir, *,
                workers: int | None = None, restart: bool = False,
                quiet: bool = False) -> list[dict]:  # fmt: skip
    """:func:`amplitude_job` for every amplitude (a process per amplitude, at most the CPU
    count; ``workers=1`` in this process)."""
    amplitudes = [float(a) for a in amplitudes]
    if not restart:
        refuse_foreign_checkpoints(cfg, amplitudes, settings, out_dir)
    args = [(cfg, source, a, settings, str(out_dir), restart, quiet) for a in amplitudes]
    n = workers or min(len(amplitudes), os.cpu_count() or 1)
    if n <= 1:
        return [amplitude_job(*a) for a in args]
    with process_pool(n) as ex:
        return gather(ex, [ex.submit(amplitude_job, *a) for a in args])


def write_csv(path: Path, results: list[dict]) -> None:
    """One row per point, all amplitudes (atomic write)."""
    import csv

    with atomic_open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(CSV_COLUMNS)
        for r in sorted(results, key=lambda r: r["A"]):
            for row in r["rows"]:
                w.writerow([format_csv_value(row.get(c, "")) for c in CSV_COLUMNS])


def summarise(r: dict) -> dict:
    """Per-amplitude numbers: points, failures (frequency and reason), the peak resultant
    displacement over converged points without uplift, unstable and stick-slip points, and
    the points that are one of a family of orbits (multipliers at 1: their peaks depend on
    the path)."""
    rows = r["rows"]
    good = [x for x in rows if x["converged"] and x["uplift"] is not True]
    u = np.array([x["u_peak_m"] for x in good], dtype=float)
    k = int(np.nanargmax(u)) if u.size and np.isfinite(u).any() else None
    stick = [x for x in rows if isinstance(x["stick_fraction"], float)
             and stick_slip(x["stick_fraction"])]  # fmt: skip
    return {
        "A": r["A"], "points": len(rows), "resumed_points": r["resumed_points"],
        "fallback_points": sum(x["method"] == "sweep" and x["converged"] for x in rows),
        "unconverged_points": sum(not x["converged"] for x in rows),
        "unstable_points": sum(x["stable"] is False for x in rows),
        "uplift_points": sum(x["uplift"] is True for x in rows),
        "rim_contact_points": sum(x["rim_contact"] is True for x in rows),
        "stick_slip_points": len(stick),
        "family_points": sum("family of orbits" in (x.get("note") or "") for x in rows),
        "u_peak_max_m": None if k is None else float(u[k]),
        "u_peak_max_f_hz": None if k is None else float(good[k]["f"]),
        "failures": r["failures"], "bifurcations": r["bifurcations"], "wall_s": r["wall_s"],
        "jumps": r.get("jumps", []),
    }  # fmt: skip
