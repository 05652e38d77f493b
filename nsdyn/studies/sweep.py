"""Amplitude sweeps: frequency-amplitude diagrams of periodic solutions (seed 004 Figs 9-11).

For each excitation amplitude ``A`` the isolated model of a scene (a frame, a shear building
or a system from matrices) is driven by ``u''_hor = A sin(2 pi f t)`` (or, for a scene whose
``[force]`` is harmonic, by that force with amplitude ``A`` [N]) and its periodic solutions
are continued over ``f`` (shooting, with the stepped-sweep fallback; :mod:`nsdyn.periodic`).
Amplitudes run in parallel processes (any ``concurrent.futures.Executor``); each writes a
checkpoint after every point so an interrupted sweep resumes where it stopped. Results: one
CSV row per point and a PNG with IDR, absolute floor acceleration and isolator displacement
against f, the fixed-base linear frequency response (frames) dashed for comparison.

The command line (``nsdyn sweep``) is :mod:`nsdyn.cli.sweep`.
"""

from __future__ import annotations

import contextlib
import csv
import json
import math
import os
import sys
import time
import warnings
from concurrent.futures import Executor
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np

from nsdyn._checks import InputWarning
from nsdyn._progress import PointLines, curve_count
from nsdyn.atomic import atomic_open, differing
from nsdyn.models.scenefile import SceneError
from nsdyn.studies.sweep_points import (
    checkpoint_data,
    point_from_dict,
    point_to_dict,
    skipped_before,
)
from nsdyn.studies.workers import gather, process_pool, saved_on_interrupt

DEFAULT_OUT = "nsdyn-sweep"
DEFAULT_AMPLITUDES = "0.1,0.5,1,2"  # m/s^2, seed Fig. 9
CHECKPOINT_NAME = ".sweep-A{amplitude}.ckpt.json"  # one per amplitude, in the output dir


SWEEP_SOLVER_KEYS = ("restitution",)  # a scene's [solver] keys a frame's sweep reads


# said by a sweep under the switch law (its orbit's steps sample the stick onsets' jumps)
SWITCH_A_NOTE = ("under the switch law the isolation level's acceleration jumps at each stick "
                 "onset, and the column a (all levels) reads its peak at the orbit's steps: it "
                 "moves with --steps-factor where the base level sets it; a_floors (the "
                 "storeys) does not")  # fmt: skip


def unused_scene_notes(raw: dict, harmonic_motion: bool, contact: str = "") -> list[str]:
    """One line for each table of an isolated-frame scene that its sweep does not read: a
    record's [motion] (the sweep drives harmonic base accelerations) and [solver] keys other
    than :data:`SWEEP_SOLVER_KEYS` (its orbits are shot with their own integrator; a
    transient's method, rtol and dt_out changed nothing, unsaid); and the contacts'
    stabilisation, unless ``contact`` is "unilateral" (lift-off orbits feel it)."""
    notes = []
    iso = raw.get("isolation") if isinstance(raw.get("isolation"), dict) else {}
    gains = [f"isolation.{k}" for k in ("alpha", "beta") if k in iso]
    if gains and contact != "unilateral":  # (1e-6 to 1e6: the same curve, unsaid)
        notes.append(f"{' and '.join(gains)}: no effect on a sweep, whose orbits are shot on "
                     "the minimal coordinates where the contacts hold exactly (the "
                     "stabilisation acts on a drift they do not have)")  # fmt: skip
    elif contact == "unilateral" and isinstance(iso.get("alpha"), int | float):
        from nsdyn.models.isolated.bearings import stabilisation_note

        notes += [n for n in [stabilisation_note("isolation.alpha", iso["alpha"])] if n]
    if "motion" in raw and not harmonic_motion:
        notes.append("the scene's [motion] (a record) is not used: a sweep drives the frame "
                     "with harmonic base accelerations of --amplitudes")  # fmt: skip
    sv = raw.get("solver") if isinstance(raw.get("solver"), dict) else {}
    left = [k for k in sv if k not in SWEEP_SOLVER_KEYS]
    if left:
        notes.append(f"the scene's [solver] {', '.join(left)}: not used by a sweep, which "
                     "shoots its periodic orbits with its own integrator (--tableau, "
                     "--steps-factor)")  # fmt: skip
    return notes


def amplitude_tag(a: float) -> str:
    """The amplitude in a file name: ``{a:g}`` where that names it (the names of earlier
    runs), else its shortest round-trip text (0.5 and 0.5000001 shared one file)."""
    return f"{a:g}" if float(f"{a:g}") == a else repr(float(a))


CHECKPOINT_EVERY_S = 2.0  # shortest interval between checkpoint writes [s]
CSV_COLUMNS = (
    "f",
    "A",
    "IDR",
    "a",
    "a_floors",
    "x_iso",
    "stick_all_period",
    "stable",
    "max_multiplier_modulus",
    "method",
    "newton_iterations",
    "residual",
    "converged",
    "n_steps",
    "uplift",
    "law",
    "contact",
    "flight_fraction",
    "lift_offs_per_period",
    "max_landing_impulse_Ns",
    "note",
)


@dataclass(frozen=True)
class SweepSettings:
    """What a curve depends on besides the scene (part of the checkpoint's identity)."""

    fmin: float = 0.01
    fmax: float = 10.0
    points: int = 150
    continuation: str = "sequential"
    fallback: bool = True
    tableau: str = "sdirk2"  # SDIRK of the period integration (periodic.TABLEAUX)
    steps_factor: float = 1.0  # x the default steps per period (periodic.Discretisation)
    friction: str = "arctan"  # "arctan" (the scene's smooth law) or "switch" (true stick)
    contact: str = "bilateral"  # "unilateral": uplift points recomputed with lift-off/landing

    def discretisation(self):
        """The :class:`nsdyn.periodic.Discretisation` these settings ask for."""
        from nsdyn.periodic import Discretisation, refined

        return refined(Discretisation(method=self.tableau), self.steps_factor)


# ---- checkpoints ----------------------------------------------------------------------------
def _atomic_write_text(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` atomically."""
    with atomic_open(path, "w", newline="") as fh:
        fh.write(text)


def _identity(cfg: dict, amplitude: float, settings: SweepSettings) -> dict:
    scene = {k: v for k, v in cfg.items() if not k.startswith("_") and k not in ("motion",)}
    return {"scene": scene, "amplitude": amplitude, "settings": asdict(settings)}


def checkpoint_path(out_dir: Path, amplitude: float) -> Path:
    return Path(out_dir) / CHECKPOINT_NAME.format(amplitude=amplitude_tag(amplitude))


def load_checkpoint(path: Path, identity: dict) -> list | None:
    """Points of a checkpoint written for the same scene, amplitude and settings, else None."""
    return _checkpoint(path, identity)[0]


def _checkpoint(path: Path, identity: dict) -> tuple[list | None, str]:
    """(points, "") of a checkpoint of these settings, else (None, why not): "" (no file),
    "unreadable" or "other" (a curve of other settings, "finished" when complete)."""
    data, why = checkpoint_data(path)
    if data is None:
        return None, why
    if data.get("identity") != json.loads(json.dumps(identity)):
        return None, "finished" if data.get("complete") is True else "other"
    try:
        return [point_from_dict(d) for d in data.get("points", [])], ""
    except (KeyError, TypeError, ValueError):
        return None, "unreadable"


def resumed_start(ckpt: Path, identity: dict, amplitude: float, restart: bool,
                  quiet: bool) -> list | None:  # fmt: skip
    """The points a curve resumes from its checkpoint ``ckpt`` (None: with ``restart``, or
    none of these settings), said on stderr unless ``quiet``: how many and to which
    frequency, or why a checkpoint there is not resumed (unreadable, or a curve of other
    settings: an unfinished one was refused before, :func:`refuse_foreign_checkpoints`)."""
    if restart:
        return None
    start, why = _checkpoint(ckpt, identity)
    if not quiet and start:
        print(f"[A={amplitude:g}] resuming from {ckpt.name}: {len(start)} points on file, to f = "
              f"{start[-1].f:.4g} Hz", file=sys.stderr, flush=True)  # fmt: skip
    elif not quiet and why:
        what = {"unreadable": "cannot be read", "finished": "holds a finished curve of other "
                "settings", "other": "holds a curve of other settings"}[why]  # fmt: skip
        print(f"[A={amplitude:g}] {ckpt.name} {what}: started afresh (it will be replaced)",
              file=sys.stderr, flush=True)  # fmt: skip
    return start


# ---- one amplitude (runs in a worker process) -----------------------------------------------
def amplitude_job(
    cfg: dict,
    amplitude: float,
    settings: SweepSettings,
    out_dir: str,
    restart: bool = False,
    quiet: bool = False,
) -> dict:
    """Continue the periodic solutions at one amplitude; resumable through its checkpoint.

    Returns a picklable summary: CSV rows, bifurcations and timings (no state arrays).
    """
    from nsdyn.ground.excitation import HarmonicForce
    from nsdyn.models.isolated.bearings import stabilisation_unsaid
    from nsdyn.models.isolated.scene import build_scene
    from nsdyn.periodic import frequency_response

    t0 = time.perf_counter()
    with stabilisation_unsaid():  # (its lift-off is settings.contact's: unused_scene_notes;
        system, excitation = build_scene(cfg)  # in a worker too, whatever its start method)
    # a scene driven by a harmonic force sweeps that force (amplitudes in N), else u''_hor
    load = excitation if isinstance(excitation, HarmonicForce) else None  # (F: this amplitude)
    load = load and replace(load, F=float(amplitude))
    ident = _identity(cfg, amplitude, settings)
    ckpt = checkpoint_path(Path(out_dir), amplitude)
    start = resumed_start(ckpt, ident, amplitude, restart, quiet)
    n_resumed = len(start or [])
    pts_done: list = list(start or [])
    last_write = [time.perf_counter()]
    # frequencies without a point (--no-fallback) a finished run left: a rerun resumed every
    # point, said none of them and ended with status 0
    before = skipped_before(ckpt, start, settings)

    def save(points, complete=False, skipped=()):
        data = {
            "identity": ident,
            "complete": complete,
            "points": [point_to_dict(p) for p in points],
            "skipped": [list(x) for x in skipped],
        }
        _atomic_write_text(ckpt, json.dumps(data))
        last_write[0] = time.perf_counter()

    walls = []  # this run's points' wall times (the estimate of the rest)
    lines = PointLines(lambda text: print(text, file=sys.stderr, flush=True))

    def progress(pt, k, n):
        pts_done.append(pt)
        walls.append(pt.quantities.get("wall_s"))
        if time.perf_counter() - last_write[0] > CHECKPOINT_EVERY_S:
            save(pts_done, skipped=before)
        if not quiet:
            q = pt.quantities
            of, left = curve_count(k, n, walls, settings.continuation)
            x = f"x_iso={q.get('x_iso', math.nan):.2e}" if pt.converged else "no steady state"
            line = (f"[A={amplitude:g}] {k:4d}{of} f={pt.f:8.4f} Hz {pt.method:9s} "
                    f"it={pt.iterations:2d} {x} ({q.get('wall_s', 0.0):.2f} s")  # fmt: skip
            lines(f"{line}{left})", k, n, pt.converged, final=f"{line})")

    options = dict(
        fmin=settings.fmin,
        fmax=settings.fmax,
        points=settings.points,
        continuation=settings.continuation,
        fallback=settings.fallback,
        disc=settings.discretisation(),
        progress=progress,
        start=start,
        load=load,
    )
    from nsdyn.periodic.curve import EmptyCurveWarning
    from nsdyn.periodic.response import BilateralOrbitWarning

    with (saved_on_interrupt(lambda: len(pts_done) > n_resumed and save(pts_done, skipped=before)),
          warnings.catch_warnings(), contextlib.closing(lines)):  # fmt: skip
        warnings.simplefilter("ignore", EmptyCurveWarning)  # (said by its status 3)
        warnings.simplefilter("ignore", BilateralOrbitWarning)  # (said once: bilateral_sweep_note)
        if settings.friction == "switch":  # (interrupted: the points so far kept for a rerun)
            from nsdyn.periodic.switch import switch_response

            curve = switch_response(system, amplitude, **options)
            law = "switch"
        else:
            curve = frequency_response(system, amplitude, **options)
            law = system.isolation.law
    now = list(zip(curve.info.get("skipped_hz", []), curve.info.get("skipped_why", []),
                   strict=False))  # fmt: skip
    skipped = sorted({float(f): (float(f), str(w)) for f, w in [*before, *now]}.values())
    save(curve.points, complete=True, skipped=skipped)
    rows = curve.rows()
    for row in rows:
        row["law"] = law
        row["contact"] = "bilateral"
    if settings.contact == "unilateral":
        e = float(cfg.get("solver", {}).get("restitution", 0.0))  # (a landing's, as a run's)
        _unilateral_pass(system, amplitude, load, curve, rows, quiet, e)
    walls = np.array([p.quantities.get("wall_s", np.nan) for p in curve.points])
    fs = np.array([p.f for p in curve.points])
    new = np.arange(len(curve.points)) >= n_resumed
    return {
        "A": amplitude,
        "model": system.name,
        "rows": rows,
        "bifurcations": curve.bifurcations,
        "resumed_points": n_resumed,
        "wall_s": time.perf_counter() - t0,
        "wall_below_0.1Hz_s": float(np.nansum(walls[new & (fs < 0.1)])),
        "wall_above_0.1Hz_s": float(np.nansum(walls[new & (fs >= 0.1)])),
        "frame": system.frame,
        "f_max": system.f_max,
        "skipped_hz": [f for f, _ in skipped],  # (a finished run's before, this run's)
        "skipped_why": [w for _, w in skipped],  # (each one's reason)
        "jumps": list(curve.info.get("jumps", [])),  # (sequential steps between two branches)
        "arclength_stop": curve.info.get("arclength_stop"),
    }


def _unilateral_pass(system, amplitude, load, curve, rows, quiet, restitution=0.0) -> None:
    """The uplift points of the curve again, with lift-off and landing
    (:func:`nsdyn.periodic.unilateral.unilateral_rows`); their rows say ``contact =
    "unilateral"``."""
    from nsdyn.periodic import frame_problem
    from nsdyn.periodic.unilateral import unilateral_rows

    def progress(f, u):
        if not quiet:
            print(
                f"[A={amplitude:g}] unilateral f={f:8.4f} Hz: {u.message}",
                file=sys.stderr,
                flush=True,
            )

    pb = frame_problem(system, amplitude, load=load)
    unilateral_rows(pb, curve.points, rows, progress=progress, restitution=restitution)
    for row in rows:
        if row["method"] == "unilateral":
            row["contact"] = "unilateral"


class CheckpointMismatch(SceneError):
    """An interrupted sweep's checkpoint was written with other settings: resuming would mix
    two curves, discarding it would lose the work; the user decides (same settings or
    ``--restart``)."""


def refuse_foreign_checkpoints(cfg: dict, amplitudes, settings, out_dir) -> None:
    """Raise :class:`CheckpointMismatch` for an unfinished checkpoint of other settings.

    A finished sweep's checkpoint of other settings is simply replaced by the new sweep (its
    curve is complete in its CSV); an unfinished one is never mixed nor silently discarded.
    """
    refuse_foreign((float(a), checkpoint_path(out_dir, float(a)),
                    _identity(cfg, float(a), settings)) for a in amplitudes)  # fmt: skip


def refuse_foreign(checkpoints) -> None:
    """:class:`CheckpointMismatch` for the first of ``checkpoints`` ((amplitude, path, this
    sweep's identity) each; a deck's sweep names its own) that is unfinished and of other
    settings."""
    for a, path, identity in checkpoints:
        data, _ = checkpoint_data(path)
        ident = json.loads(json.dumps(identity))
        if data is not None and data.get("complete") is False and data.get("identity") != ident:
            diff = ", ".join(differing(data.get("identity"), ident))
            raise CheckpointMismatch(
                f"{path}: checkpoint of an interrupted sweep at A = {a:g} with other "
                f"settings (differing: {diff}); rerun with the same "
                "settings to resume it, or pass --restart to discard it"
            )


def bilateral_sweep_note(cfg: dict, settings: SweepSettings) -> str | None:
    """A line when the scene's isolators lift off (``isolation.contact = "unilateral"``) but
    the sweep keeps their contacts (``settings.contact``); None otherwise."""
    iso = cfg.get("isolation") if isinstance(cfg.get("isolation"), dict) else {}
    if iso.get("contact") != "unilateral" or settings.contact == "unilateral":
        return None
    arctan = settings.friction == "switch"  # (the lift-off orbits are the arctan law's)
    return (
        "isolation.contact = 'unilateral', but a sweep shoots the bilateral orbits and "
        "flags uplift where a normal force falls to zero; contact='unilateral' (nsdyn "
        f"sweep{' --friction arctan' * arctan} --contact unilateral) recomputes those points "
        f"with lift-off and landing{' on the arctan law' * arctan}"
    )


def sweep_amplitudes(
    cfg: dict,
    amplitudes,
    settings: SweepSettings,
    out_dir: str | Path,
    *,
    executor: Executor | None = None,
    workers: int | None = None,
    restart: bool = False,
    quiet: bool = False,
) -> list[dict]:
    """Run :func:`amplitude_job` for every amplitude, in parallel on ``executor``.

    Default: a local process pool with ``workers`` processes (one per amplitude, at most the
    CPU count); ``workers=1`` runs in this process. Any ``concurrent.futures.Executor`` works
    (e.g. Dask's ``client.get_executor()``).
    """
    amplitudes = [float(a) for a in amplitudes]
    if note := bilateral_sweep_note(cfg, settings):  # (said once, not by every amplitude)
        warnings.warn(note, InputWarning, stacklevel=2)
    if not restart:
        refuse_foreign_checkpoints(cfg, amplitudes, settings, out_dir)
    args = [(cfg, a, settings, str(out_dir), restart, quiet) for a in amplitudes]
    if executor is None:
        n = workers or min(len(amplitudes), os.cpu_count() or 1)
        if n <= 1:
            return [amplitude_job(*a) for a in args]
        with process_pool(n) as ex:
            return _run_all(ex, args)
    return _run_all(executor, args)


def _run_all(ex: Executor, args) -> list[dict]:
    return gather(ex, [ex.submit(amplitude_job, *a) for a in args])


# ---- outputs --------------------------------------------------------------------------------
def format_csv_value(v) -> str:
    """A CSV cell as the sweep writes it: empty for None/NaN, true/false, floats to 9 digits."""
    if v is None:
        return ""
    if isinstance(v, bool | np.bool_):
        return "true" if v else "false"
    if isinstance(v, float | np.floating):
        return "" if not math.isfinite(v) else f"{v:.9g}"
    return str(v)


def write_csv(path: Path, results: list[dict]) -> None:
    """One row per point, all amplitudes (atomic write)."""
    with atomic_open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(CSV_COLUMNS)
        for r in sorted(results, key=lambda r: r["A"]):
            for row in r["rows"]:
                w.writerow([format_csv_value(row.get(c, "")) for c in CSV_COLUMNS])


def summarise(r: dict) -> dict:
    """Per-amplitude numbers for the report. Maxima skip points with uplift (the bilateral
    contact model is outside its validity there) unless a unilateral sweep recomputed them,
    and unconverged points."""
    rows = r["rows"]
    f = np.array([x["f"] for x in rows])
    stick = np.array([x["stick_all_period"] is True for x in rows])
    uni = np.array([x.get("contact") == "unilateral" for x in rows])
    uplift = np.array([x["uplift"] is True for x in rows])
    # bilateral values past uplift are outside that model; unilateral ones count when settled
    good = np.array([bool(x["converged"]) for x in rows]) & (~uplift | uni)
    slip_f = f[~stick & good]
    stick_above = None  # lowest frequency above which every point sticks the whole period
    if stick.any():  # (a failed point is neither: the run goes on past it, from a stuck one)
        k = len(stick)
        while k > 0 and (stick[k - 1] or not rows[k - 1]["converged"]):
            k -= 1
        while k < len(stick) and not stick[k]:
            k += 1
        stick_above = float(f[k]) if k < len(f) else None

    def peak(key):
        v = np.array([x[key] for x in rows], dtype=float)[good]
        return float(np.nanmax(v)) if v.size and np.isfinite(v).any() else None

    return {
        "A": r["A"],
        "points": len(rows),
        "resumed_points": r["resumed_points"],
        # the points the stepped sweep answered (a failed one is counted below, not here)
        "fallback_points": int(sum(x["method"] == "sweep" and x["converged"] for x in rows)),
        "unconverged_points": int(sum(not x["converged"] for x in rows)),
        "uplift_points": int(uplift.sum()),
        "unilateral_points": int(uni.sum()),
        "unstable_points": int(sum(x["stable"] is False for x in rows)),
        "stick_all_period_above_hz": stick_above,
        "slip_frequency_range_hz": (
            [float(slip_f.min()), float(slip_f.max())] if slip_f.size else None
        ),
        "idr_max": peak("IDR"),
        "a_max_mps2": peak("a"),
        "a_floors_max_mps2": peak("a_floors"),
        "x_iso_max_m": peak("x_iso"),
        "bifurcations": r["bifurcations"],
        "wall_s": r["wall_s"],
        "wall_below_0.1Hz_s": r["wall_below_0.1Hz_s"],
        "wall_above_0.1Hz_s": r["wall_above_0.1Hz_s"],
        "skipped_hz": r.get("skipped_hz", []),
        "skipped_why": r.get("skipped_why", []),
        "jumps": r.get("jumps", []),
        "arclength_stop": r.get("arclength_stop"),
        # each point without a steady state and why (its row's note), as the deck sweep's
        "failures": [
            {"f": float(x["f"]), "reason": x.get("note") or "not converged"}
            for x in rows
            if not x["converged"]
        ],
    }
