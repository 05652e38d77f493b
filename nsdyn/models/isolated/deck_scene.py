"""``nsdyn run`` on deck scenes (``[scene] kind = "deck"``): bidirectional isolators in a plane.

Tables:

* ``[deck]`` a rigid deck: ``m`` [kg], ``J`` [kg m²] (polar inertia about the centre of mass;
  default m (L_x² + L_y²)/12 of the isolators' plan extent), ``positions`` [[X, Y], …] [m],
  ``ecc`` [e_x, e_y] [m] (centre of mass from the plan origin), ``h`` [m] (its height above the
  sliding surfaces); or ``[mass]`` ``m`` [kg]: a single mass on one isolator (SDOF in x, y);
* ``[bearing]`` one bearing for every isolator (:func:`nsdyn.models.isolated.bearings.
  bearing_from_config`): ``type`` "fps" (``radius`` R [m]) or "flat" (``k_lam`` [N/m],
  ``c`` [N s/m]); friction ``mu``, or ``mu_slow``, ``mu_fast``, ``rate`` [s/m]; ``mu_static``;
  ``d_cap`` [m]; ``k_stop`` [N/m], ``c_stop`` [N s/m]; ``area`` [m²] and ``p_ref`` [Pa]
  (pressure-dependent friction); or "tfp", a triple friction pendulum
  (``R1`` … ``R4`` [m], ``mu1`` … ``mu4``, ``d1`` … ``d4`` [m], ``u_y`` [m], ``mu_fast1``
  … ``mu_fast4`` and ``rate`` [s/m]; law "arctan");
* ``[motion]`` a three-component record (``kind = "record3"``) or a harmonic orbit
  (``kind = "orbit"``), the keys of :mod:`nsdyn.ground.table3`;
* ``[solver]`` ``law`` ("switch" | "arctan"), ``eps`` [s/m], ``eta`` [m/s], ``rtol``,
  ``atol`` [m and m/s; default the law's ``deck.PLANE_ATOL``], ``dt_out`` [s], ``contact``
  ("detect" | "bilateral": what a normal force reaching zero does,
  :data:`nsdyn.models.isolated.deck.PLANE_CONTACTS`).

Writes ``deck.npz`` (histories) into the output directory; the summary
(:meth:`nsdyn.models.isolated.plane_result.PlaneResult.summary`, units in the key names) is what
``nsdyn run`` prints. The figure is drawn by :mod:`nsdyn.plot.isolators` from ``deck.npz``.
"""

from __future__ import annotations

import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from nsdyn._checks import MAX_AMPLITUDES, MAX_POINTS, NotedWarning
from nsdyn._numba_cache import compile_note, first_compile
from nsdyn._progress import reporter
from nsdyn.atomic import atomic_open
from nsdyn.models.isolated.bearings import (
    BEARING_KEYS,
    BearingError,
    bearing_from_config,
    bearing_notes,
    slip_ratio_note,
)
from nsdyn.models.isolated.deck import (
    PLANE_ATOL,
    contact_code,
    plan_note,
    rigid_deck,
    sdof_plane,
    simulate_plane,
)
from nsdyn.models.isolated.defaults import EPS, ETA
from nsdyn.models.isolated.friction import LAW_KEYS, coarse_law_note, sharpness_in_range
from nsdyn.models.isolated.plane_energy import closure_note
from nsdyn.models.scenefile import SceneError, check_fields, grid_fields, number, rel_tol

TABLES = {
    "scene": {"kind", "name"},
    "deck": {"m", "J", "positions", "ecc", "h"},
    "mass": {"m"},
    "bearing": BEARING_KEYS,
    "motion": None,  # checked by nsdyn.ground.table3
    "solver": {"law", "eps", "eta", "rtol", "atol", "dt_out", "contact"},
    "sweep": {"f_min", "f_max", "points", "amplitudes", "law"},  # read by nsdyn sweep
}
FIGURE_MODULE = "nsdyn.plot.isolators"  # draws the figure from deck.npz (a later stage)
RTOL = 1e-6
# seconds a first run compiles the kernels (2-core machine, empty cache: the switch law's loop
# and, in a helper process beside it, its callees): a middling hour's, 1.8x the fast hour's
# in the family table of docs/dev/first-runs.md (4.9 s)
COMPILE_ABOUT_S = 9.0


def kernels_cached(law: str) -> bool:
    """True when the time loop of ``law`` is compiled in this process or in numba's cache."""
    from nsdyn._numba_cache import all_cached
    from nsdyn.models.isolated import _kplaneradau, _kplanerun

    return all_cached([_kplanerun.integrate if law == "switch" else _kplaneradau.integrate])


def warm(system, law: str) -> float:
    """Compile (or load) the time loop of ``law`` by a tiny run of ``system``, saying so on
    stderr when it compiles (:func:`nsdyn._numba_cache.first_compile`); the seconds it took.
    A run, a sweep and a study of deck scenes each call it before their work starts."""
    t0 = time.perf_counter()
    with first_compile("deck", COMPILE_ABOUT_S, kernels_cached(law)), warnings.catch_warnings():
        warnings.simplefilter("ignore", NotedWarning)  # (a warm-up: the run says them)
        simulate_plane(system, {"f": 1.0, "ax": 0.0, "ay": 0.0}, t_end=0.04, law=law)
    return time.perf_counter() - t0


def _pairs(source: str, name: str, v) -> np.ndarray:
    ok = isinstance(v, list) and v and all(
        isinstance(p, list) and len(p) == 2
        and all(isinstance(a, int | float) and not isinstance(a, bool) and math.isfinite(a)
                for a in p)
        for p in v
    )  # fmt: skip
    if not ok:
        raise SceneError(f"{source}: {name}: expected a list of finite [X, Y] pairs [m], "
                         f"got {v!r}")  # fmt: skip
    return np.array(v, dtype=float)


def build_system(cfg: dict, source: str):
    """The :class:`PlaneSystem` of a scene (SceneError naming the field)."""
    # (the motion's keys read by nsdyn.ground.table3; its name listed: [motin] is near it)
    check_fields({k: v for k, v in cfg.items() if k != "motion"},
                 {k: v or set() for k, v in TABLES.items()}, source)  # fmt: skip
    if ("deck" in cfg) == ("mass" in cfg):
        raise SceneError(f"{source}: deck: expected one table, [deck] (a rigid deck on "
                         "isolators) or [mass] (a mass on one isolator)")  # fmt: skip
    if "bearing" not in cfg:
        raise SceneError(f"{source}: bearing: missing; expected a [bearing] table "
                         "(type, radius, mu, d_cap, …)")  # fmt: skip
    try:
        bearing = bearing_from_config(cfg["bearing"], "bearing")
        if "mass" in cfg:
            t = cfg["mass"]
            if "m" not in t:
                raise SceneError(f"{source}: mass.m: missing; expected the mass [kg]")
            return sdof_plane(number(source, "mass.m", t["m"]), bearing, name="mass")
        t = cfg["deck"]
        for key in ("m", "positions"):
            if key not in t:
                what = "the mass [kg]" if key == "m" else "the isolators' [X, Y] positions [m]"
                raise SceneError(f"{source}: deck.{key}: missing; expected {what}")
        m = number(source, "deck.m", t["m"])
        pos = _pairs(source, "deck.positions", t["positions"])
        ext = pos.max(axis=0) - pos.min(axis=0)
        if "J" not in t and not ext.any():  # (it read "deck.J: ... got 0.0", never given)
            raise SceneError(f"{source}: deck.J: missing; a deck on one isolator has no plan "
                             "extent to derive its polar moment from: expected J")  # fmt: skip
        J = number(source, "deck.J", t.get("J", m * float(ext @ ext) / 12.0))
        ecc = t.get("ecc", [0.0, 0.0])
        if not (isinstance(ecc, list) and len(ecc) == 2):
            raise SceneError(f"{source}: deck.ecc: expected [e_x, e_y] [m], got {ecc!r}")
        ecc = tuple(number(source, "deck.ecc", e, positive=False) for e in ecc)
        h = number(source, "deck.h", t.get("h", 0.0), allow_zero=True)
        return rigid_deck(m, J, pos, bearing, ecc=ecc, h=h, name="deck")
    except BearingError as e:
        raise SceneError(f"{source}: {e}") from None


def build_motion(cfg: dict, source: str):
    """(excitation, t_end) from ``[motion]`` (a GroundMotion3 or a HarmonicPlane)."""
    from nsdyn.ground.table3 import motion3_from_table

    if "motion" not in cfg or not isinstance(cfg["motion"], dict):
        raise SceneError(f"{source}: motion: missing; expected a [motion] table (kind = "
                         "'record3' or 'orbit')")  # fmt: skip
    try:
        exc, dur = motion3_from_table(cfg["motion"], source)
    except ValueError as e:
        raise SceneError(" ".join(str(e).split())) from None
    if "n_periods" in dur:
        return exc, dur["n_periods"] / exc.f
    return exc, dur.get("t_end")


def record_scale(cfg: dict, exc) -> dict:
    """A record's scale in a summary, as the isolated frame's (two runs at other PGAs read
    alike without it): ``pga_mps2`` of the window run (the horizontal resultant), and with a
    ``pga`` the target the whole record was scaled to and its component. Empty for an orbit."""
    if not hasattr(exc, "pga_resultant"):
        return {}
    out = {"pga_mps2": exc.pga_resultant}
    if "pga" in cfg["motion"]:
        out["record_pga_mps2"] = float(cfg["motion"]["pga"])
        out["record_pga_component"] = cfg["motion"].get("pga_component", "resultant")
    return out


def record_end_note(cfg: dict, exc) -> str | None:
    """The note of a record cut at its last sample before the scene's ``motion.t_end``, which
    falls between two samples (the run ends there: it read "past the excitation's end"), or
    past its end (a study said nothing: its table held the record's end)."""
    t_req = cfg.get("motion", {}).get("t_end")
    if t_req is None or not hasattr(exc, "n") or not hasattr(exc, "dt"):
        return None
    from nsdyn.ground.formats import between_samples_note, past_record_note

    last = exc.t0 + (exc.n - 1) * exc.dt
    return between_samples_note(float(t_req), last, exc.dt) or past_record_note(
        float(t_req), last, runs_on=False, what="excitation")  # fmt: skip


def unused_law_keys(cfg: dict) -> list[tuple[str, str]]:
    """(key, why) of the friction-law keys given that the run's law does not read
    (:func:`scene_law`): ``solver.eps`` beside the switch law, ``solver.eta`` and the bearing's
    static friction (``mu_static``) beside the arctan law, which has no stick. A run notes
    them; ``nsdyn sweep --friction`` may still read ``eps`` and ``eta``."""
    law, solver = scene_law(cfg), cfg.get("solver", {})
    bearing = cfg.get("bearing") if isinstance(cfg.get("bearing"), dict) else {}
    out = [(f"solver.{k}", f"{what}; this run's law is {law!r} (nsdyn sweep --friction {own} "
            "reads it)")
           for k, (own, what) in LAW_KEYS.items() if own != law and k in solver]  # fmt: skip
    if law == "arctan" and "mu_static" in bearing:
        out.append(("bearing.mu_static", "the friction at the start of a slip, from stick; "
                    "the arctan law has no stick"))  # fmt: skip
    return out


def build_notes(cfg: dict, system=None) -> list[str]:
    """The keys of a scene its run does not read, one note each (a study refuses a parameter
    that only such keys would vary)."""
    return [f"{k} not used: {w}" for k, w in unused_law_keys(cfg)]


def scene_law(cfg: dict) -> str:
    """The friction law a scene runs: ``solver.law``, else the switch law (the regularised
    law for a triple friction pendulum, which has no stick events)."""
    return cfg.get("solver", {}).get("law", "arctan" if _tfp(cfg) else "switch")


def _tfp(cfg: dict) -> bool:
    """Whether the scene's ``[bearing]`` is a triple friction pendulum."""
    return isinstance(cfg.get("bearing"), dict) and cfg["bearing"].get("type") == "tfp"


def build_solver(cfg: dict, source: str, unilateral: bool = False) -> dict:
    """The run's keyword arguments from ``[solver]`` (SceneError naming the field);
    ``solver.contact = "unilateral"`` accepted only with ``unilateral`` (a family whose
    systems from matrices have independent contacts; the deck has no vertical motion)."""
    t = cfg.get("solver", {})
    tfp = _tfp(cfg)
    law = scene_law(cfg)
    if law not in ("switch", "arctan"):
        raise SceneError(f"{source}: solver.law: expected 'switch' or 'arctan', got {law!r}")
    if tfp and law != "arctan":
        raise SceneError(f"{source}: solver.law: a triple friction pendulum (bearing.type = "
                         f"'tfp') runs with the regularised law 'arctan', got {law!r}")  # fmt: skip
    kw = {"law": law}
    for key, default in (("eps", EPS), ("eta", ETA)):
        value = number(source, f"solver.{key}", t.get(key, default))
        kw[key] = value if LAW_KEYS[key][0] == law else default  # (noted, not read)
    eps = number(source, "solver.eps", t.get("eps", EPS))  # (1e300: the law's slope overflowed;
    sharpness_in_range(f"{source}: solver.eps", eps, SceneError)  # either law, as isolation.eps)
    kw["rtol"] = rel_tol(source, "solver.rtol", t.get("rtol", RTOL))
    if "atol" in t:  # one number for both, or the (displacement, velocity) pair
        a = t["atol"]
        if isinstance(a, list) and len(a) != 2:
            raise SceneError(f"{source}: solver.atol: expected a positive number or a pair "
                             f"[displacements, velocities], got {a!r}")  # fmt: skip
        kw["atol"] = (tuple(number(source, "solver.atol", v) for v in a) if isinstance(a, list)
                      else (number(source, "solver.atol", a),) * 2)  # fmt: skip
    else:
        kw["atol"] = PLANE_ATOL[law]
    kw["contact"] = t.get("contact", "detect")
    try:
        contact_code(kw["contact"], unilateral)
    except ValueError as e:
        raise SceneError(f"{source}: solver.{e}") from None
    if "dt_out" in t:
        kw["dt_out"] = number(source, "solver.dt_out", t["dt_out"])
    build_sweep(cfg, source)  # (a scene's faults all at once, before any run)
    return kw


def build_sweep(cfg: dict, source: str) -> dict:
    """The ``[sweep]`` table's given keys, checked: f_min, f_max (> 0, f_max > f_min), points
    (integer >= 2), amplitudes (a list of numbers > 0), law; SceneError naming the field."""
    t = cfg.get("sweep", {})
    if not isinstance(t, dict):
        raise SceneError(f"{source}: sweep: expected a table [sweep], got {t!r}")
    mo = cfg.get("motion")
    kind = mo.get("kind") if isinstance(mo, dict) else None
    if t and kind not in ("orbit", None):  # (a missing kind is the motion reader's to name)
        raise SceneError(f"{source}: sweep: read by nsdyn sweep, which follows an orbit "
                         f"(motion.kind = 'orbit'); this scene's motion is kind = {kind!r}: "
                         "drop [sweep], or give an orbit")  # fmt: skip
    out = {}
    for key in ("f_min", "f_max"):
        if key in t:
            v = number(source, f"sweep.{key}", t[key])
            if not (math.isfinite(v) and v > 0):
                raise SceneError(f"{source}: sweep.{key}: expected a frequency > 0 [Hz], got {v}")
            out[key] = v
    if "f_min" in out and "f_max" in out and not out["f_max"] > out["f_min"]:
        raise SceneError(f"{source}: sweep.f_max: expected a frequency above f_min "
                         f"({out['f_min']:g} Hz), got {out['f_max']:g}")  # fmt: skip
    if "points" in t:
        n = t["points"]
        if isinstance(n, bool) or not isinstance(n, int) or not 2 <= n <= MAX_POINTS:
            raise SceneError(f"{source}: sweep.points: expected an integer from 2 to "
                             f"{MAX_POINTS}, got {n!r}")  # fmt: skip
        out["points"] = n
    if "amplitudes" in t:
        a = t["amplitudes"]
        ok = isinstance(a, list) and 0 < len(a) <= MAX_AMPLITUDES
        vals = []
        for v in a if ok else ():
            if (
                isinstance(v, bool)
                or not isinstance(v, int | float)
                or not (math.isfinite(v) and v > 0)
            ):
                ok = False
                break
            vals.append(float(v))
        if not ok:
            raise SceneError(f"{source}: sweep.amplitudes: expected a list of 1 to "
                             f"{MAX_AMPLITUDES} amplitudes > 0 [m/s^2], got {a!r}")  # fmt: skip
        out["amplitudes"] = vals
    if "law" in t:
        if t["law"] not in ("switch", "arctan"):
            raise SceneError(f"{source}: sweep.law: expected 'switch' or 'arctan', "
                             f"got {t['law']!r}")  # fmt: skip
        out["law"] = t["law"]
    return out


def run_scene(cfg: dict, *, source: str, out_dir: Path, figures: bool, quiet: bool) -> dict:
    """Run a deck scene; writes ``deck.npz`` into ``out_dir``; returns the summary."""
    system = build_system(cfg, source)
    exc, t_end = build_motion(cfg, source)
    kw = build_solver(cfg, source)
    name = cfg.get("scene", {}).get("name", Path(source).stem)
    say = (lambda *a: None) if quiet else (lambda *a: print(*a, file=sys.stderr))
    say(f"deck: {name}: {system.n_isolators} isolator(s), law {kw['law']}, "
        f"{getattr(exc, 'name', type(exc).__name__)}")  # fmt: skip
    notes = bearing_notes(system.bearings, system.static_normal())  # (the summary's too)
    notes += build_notes(cfg, system)
    notes += [n for n in [plan_note(system.positions, "deck.positions", system.m),
                          coarse_law_note(kw["law"], kw["eps"], kw["eta"]),
                          record_end_note(cfg, exc)] if n]  # fmt: skip
    for note in notes:
        say(f"deck: note: {note}")
    compile_s = warm(system, kw["law"])
    w0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warnings.simplefilter("ignore", NotedWarning)  # (the scene's notes say them)
        with grid_fields(source):  # the run's grid: its table's field, before any step
            res = simulate_plane(system, exc, t_end=t_end, progress=reporter(say), **kw)
    wall = time.perf_counter() - w0
    for w in caught:
        say(f"deck: warning: {w.message}")
    s = res.summary()
    s.update(res.energy(exc))  # (its closure: the balance's check on the output grid)
    big = slip_ratio_note(system.bearings, s["peak_resultant_displacement_per_isolator_m"])
    for note in (big, closure_note(s)):  # (a TFP's bearings' effective radius; a failed run)
        if note:
            notes.append(note)
            say(f"deck: note: {note}")
    out_dir = Path(out_dir)
    npz = out_dir / "deck.npz"
    caps = np.array([b.d_cap for b in system.bearings])  # (a TFP: d1 + d2 + d3 + d4)
    with atomic_open(npz, "wb") as fh:
        np.savez(fh, t=res.t, q=res.q, qd=res.qd, u=res.u, N=res.N, friction=res.friction,
                 restoring=res.restoring, other=res.other, modes=res.modes, events=res.events,
                 positions=system.positions, d_cap=caps,
                 **res.element_slips())  # fmt: skip
    s.update({"kind": "deck", "name": name, "motion": getattr(exc, "name", type(exc).__name__),
              "wall_s": wall, "compile_s": compile_s, "files": [str(npz)],
              "warnings": [str(w.message) for w in caught], "notes": list(notes)})  # fmt: skip
    s.update(record_scale(cfg, exc))
    say(f"deck: done in {wall:.3f} s ({compile_note(compile_s)})")
    return s


PGA_ROW = ("pga_mps2", "PGA, horizontal resultant", "m/s²")  # (a record's)
ROWS = (
    PGA_ROW,
    ("peak_resultant_displacement_m", "peak |u| (resultant)", "m"),
    ("peak_component_displacement_m", "peak component of u", "m"),
    ("residual_displacement_m", "residual |u|", "m"),
    ("peak_resultant_friction_N", "peak |friction|", "N"),
    ("peak_resultant_restoring_N", "peak |restoring|", "N"),
    ("peak_torsion_rad", "peak deck torsion", "rad"),
    ("min_normal_force_N", "min normal force", "N"),
    ("max_normal_force_N", "max normal force", "N"),
    ("stick_fraction", "stick fraction", ""),
    ("energy_closure", "energy closure", ""),
    ("n_events", "switch events", ""),
    ("n_steps", "steps", ""),
    ("t_end_s", "end time", "s"),
    ("wall_s", "run time", "s"),
    ("compile_s", "compile/load time", "s"),
)


def format_summary(s: dict) -> str:
    """A short human table of a deck run, every number with its unit; rim contacts and uplift
    first (never silent)."""
    head = f"deck {s.get('name', '')}: law {s['law']}, {s['n_isolators']} isolator(s)"
    text = summary_table(head, s, ROWS)
    for c in s.get("tfp_surface_limits", []):  # a triple pendulum's surfaces at their rims
        text += (
            f"\n  TFP RIM isolator {c['isolator']} surface {c['surface']} at "
            f"t = {c['t_first_s']:.4g} s, peak overshoot {c['peak_overshoot_m']:.3g} m"
        )
    for c in s.get("tfp_beyond_capacity", []):  # the whole bearing past d1 + d2 + d3 + d4
        text += (
            f"\n  TFP BEYOND CAPACITY isolator {c['isolator']}: peak |u| {c['peak_m']:.4g} m, "
            f"{1e3 * c['beyond_m']:.3g} mm past d1+d2+d3+d4 = {c['capacity_m']:.4g} m (the rim "
            "forces stretch its elastic element; its friction then includes them)"
        )
    return text


def _lifted(u: dict) -> str:
    """The isolators of an uplift record: the located one, then those at zero with it."""
    return ", ".join(str(i) for i in (u["isolator"], *u.get("also_isolators", [])))


def uplift_error(s: dict, files: bool = True) -> str | None:
    """The error of a deck or building run ended by uplift (its normal force reached zero), or
    None: what ``nsdyn run`` reports with exit status 3 (``files``: that its files hold the
    run up to the uplift) and a study records as a failed row."""
    u = s.get("uplift")
    if not u:
        return None
    whose = "their normal forces" if u.get("also_isolators") else "its normal force"
    c, doubt = s.get("energy_closure"), ""
    if closure_note(s) and not s.get("landings"):  # (a balance off by half: said with it)
        doubt = (
            f"; its energy closure {c:.3g} up to it: if a finer solver.dt_out does not "
            "lower it, the uplift may be the numerics' (tighten solver.rtol)"
        )
    return (f"UPLIFT isolator {_lifted(u)} at t = {u['t_s']:.5g} s: {whose} reached "
            "zero and the run ended there" + (" (the files hold the run up to it)" if files
                                              else "") + doubt)  # fmt: skip


def summary_table(head: str, s: dict, rows) -> str:
    """The table under ``head``: rim contacts and uplift first, then one line per
    ``(key, label, unit)`` of ``rows`` present in ``s``, then the files written. Shared by
    the deck and building3d scenes."""
    lines = [head]
    for c in s.get("rim_contacts", []):
        lines.append(f"  RIM CONTACT isolator {c['isolator']} at t = {c['t_first_s']:.4g} s, "
                     f"peak overshoot {c['peak_overshoot_m']:.4g} m")  # fmt: skip
    if s.get("uplift"):
        u = s["uplift"]
        lines.append(f"  UPLIFT isolator {_lifted(u)} at t = {u['t_s']:.5g} s (run ended)")
    if s.get("tension"):
        u = s["tension"]
        lines.append(f"  TENSION isolator {u['isolator']} at t = {u['t_first_s']:.5g} s "
                     f"(bilateral contact held it; {u['onsets']} onsets, min normal force "
                     f"{u['min_normal_force_N']:.4g} N over every step)")  # fmt: skip
    if s.get("lift_offs"):  # a unilateral run of a system from matrices
        lines.append(f"  LIFT-OFF {s['lift_offs']} lift-offs and {s['landings']} landings, the "
                     f"first at t = {s['first_lift_off_s']:.5g} s, largest landing velocity "
                     f"{s['max_landing_velocity_mps']:.3g} m/s")  # fmt: skip
    for k, label, unit in rows:
        v = s.get(k)
        if v is None:
            continue
        text = f"{v:.4g}" if isinstance(v, float) and math.isfinite(v) else str(v)
        lines.append(f"  {label:22s} {text}" + (f" {unit}" if unit else ""))
    lines.extend(f"  {'file':22s} {f}" for f in s.get("files", []))
    return "\n".join(lines)
