"""``nsdyn run`` on contact scenes: read and check the TOML, run, write NPZ/PNG, summarise.

Scene (``[scene] kind = "contact"``)::

    [scene]
    kind = "contact"
    name = "seed 002 A5"
    [body]                     # a rectangle (width, height) or a convex polygon (vertices)
    width = 1.1                # [m]
    height = 1.0               # [m]
    vertices = [[x, y], ...]   # instead of width/height
    mass = 1250.0              # [kg]
    [friction]
    mu_s = 0.57
    mu_d = 0.29                # default mu_s
    C = 0.0                    # mu(v) = mu_d + (mu_s - mu_d) exp(-C |v|); omit: jump law
    [impact]
    e_n = 0.0                  # Newton restitution
    law = "newton"             # newton | housner
    [motion]                   # a record, a displacement sine or nothing (free motion)
    record = "path/or/bundled-name"
    pga = 1.6                  # [m/s^2] scale the record / the sine's acceleration amplitude
    period = 2.18              # displacement sine u = A sin(2 pi t / T), A = pga (T / 2 pi)^2
    n_cycles = 5
    start = "impulsive"        # impulsive | smooth
    t_end = 15.0               # [s]
    theta0 = 0.0               # initial tilt [rad] (or theta0_over_alpha, a fraction of alpha)
    [solver]
    method = "event"           # event | moreau
    h = 1e-3                   # Moreau-Jean step [s]
    theta = 0.5                # Moreau-Jean theta
    rtol = 1e-9                # event-driven tolerance
    dt_out = 0.005             # [s]
    [ground]                   # omit, or kind = "rigid": rigid ground (solver.method applies)
    kind = "compliant"         # tensionless spring-dashpot corners, stick spring + Coulomb
    stiffness = 1e9            # normal stiffness per base corner [N/m]
    damping = 2e4              # per corner [N s/m]; or damping_ratio (vertical contact mode)
    stick_stiffness = 1e9      # tangential stick spring per corner [N/m] (default: stiffness)
"""

from __future__ import annotations

import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from nsdyn._checks import AccuracyWarning, output_step
from nsdyn._numba_cache import compile_note, first_compile
from nsdyn.atomic import atomic_open
from nsdyn.ground import read_motion
from nsdyn.ground.excitation import G_EARTH
from nsdyn.ground.motion import PGA_TARGET, PGA_TARGET_MAX
from nsdyn.models.contact.results import MODE_NAMES, TILT_FLOOR, slenderness
from nsdyn.models.contact.scene_keys import SCHEMA
from nsdyn.models.scenefile import (
    GRID_FIELDS,
    SceneError,
    check_fields,
    grid_fields,
    number,
    record_units,
    refuse_keys,
    rel_tol,
    scaled_record,
)
from nsdyn.models.tilt import leaning_past, past_tip_over, scene_tilt

_FIELDS = SCHEMA.fields()  # table -> valid keys, declared in scene_keys
METHODS = ("event", "moreau")  # solver.method
T_END = 5.0  # default duration of free motion [s]
SINE_KEYS = ("n_cycles", "start")  # keys of the displacement sine besides motion.period
RECORD_REPLACES = ("period", *SINE_KEYS)  # the [motion] keys `nsdyn run --record` drops
# seconds a first run compiles the kernels (2-core machine, empty cache): a middling hour's,
# 1.8x the fast hour's in the family table of docs/dev/first-runs.md
COMPILE_ABOUT_S = 8.0


def kernels_cached(opts: dict) -> bool:
    """True when the kernels a run with the scene's ``opts`` (of :func:`build`) calls are
    compiled in this process or in numba's on-disk cache (the run then only loads them; else
    a first run announces their compilation)."""
    from nsdyn._numba_cache import all_cached
    from nsdyn.models.contact import _kcompliant, _kevent, _kgeom, _kmoreau

    if opts.get("ground") is not None:
        kernels = [_kcompliant.integrate]
    elif opts["method"] == "moreau":
        kernels = [_kmoreau.moreau, _kgeom.contact_rows]
    else:
        kernels = [_kevent.integrate, _kevent.rhs, _kgeom.contact_rows, _kgeom.mu_of,
                   _kgeom.solve_contacts, _kgeom.body_mode]  # fmt: skip
    return all_cached(kernels)


def warm(body, law, motion, t_end, opts) -> float:
    """Compile (or load) the kernels a run of the built scene calls, by its first 0.02 s,
    saying so on stderr when it compiles (:func:`nsdyn._numba_cache.first_compile`); the
    seconds it took. A run and a study (before its workers start) call it."""
    w0 = time.perf_counter()
    with first_compile("contact", COMPILE_ABOUT_S, kernels_cached(opts)):
        t = min(t_end, 0.02)
        simulate(body, law, motion, t, {**opts, "dt_out": min(opts["dt_out"], t)})
    return time.perf_counter() - w0


def warm_key(cfg: dict):
    """What of a scene selects the kernels its run compiles (the ground model, the method,
    the kind of motion): scenes with equal keys call the same compiled code."""
    mo = cfg.get("motion", {})
    kind = "record" if "record" in mo else "sine" if "period" in mo else "free"
    return repr(cfg.get("ground")), cfg.get("solver", {}).get("method", "event"), kind


def warm_scene(cfg: dict, source: str) -> float:
    """:func:`warm` for a parsed scene."""
    body, law, motion, t_end, opts = build(cfg, source)
    return warm(body, law, motion, t_end, opts)


OMEGA_RATIO_MAX = 1e3  # a sine this many times faster than the rocking frequency is refused


def build(cfg: dict, source: str):
    """(body, friction law, base motion, t_end, options) of a parsed scene."""
    from nsdyn.models.contact.body import RigidBody
    from nsdyn.models.contact.excite import BaseMotion
    from nsdyn.models.contact.friction import FrictionLaw

    check_fields(cfg, _FIELDS, source)
    b = cfg.get("body", {})
    mass = number(source, "body.mass", b.get("mass", 1.0))
    try:
        if "vertices" in b:
            both = [k for k in ("width", "height") if k in b]
            if both:
                raise SceneError(f"{source}: body.{both[0]}: give the body as width and height "
                                 "(a rectangle) or as vertices, not both")  # fmt: skip
            body = RigidBody.polygon(b["vertices"], mass)
        else:
            for key in ("width", "height"):
                if key not in b:
                    raise SceneError(f"{source}: body.{key}: missing (a positive size in m, "
                                     "or body.vertices)")  # fmt: skip
            w = number(source, "body.width", b["width"])
            body = RigidBody.rectangle(w, number(source, "body.height", b["height"]), mass)
    except (ValueError, TypeError) as e:
        if isinstance(e, SceneError):
            raise
        raise SceneError(f"{source}: body.{e}") from None
    f = cfg.get("friction", {})
    if "mu_s" not in f:
        raise SceneError(f"{source}: friction.mu_s: missing (static friction coefficient)")
    mu_s = number(source, "friction.mu_s", f["mu_s"], allow_zero=True)
    mu_d = number(source, "friction.mu_d", f.get("mu_d", mu_s), allow_zero=True)
    C = number(source, "friction.C", f["C"], allow_zero=True) if "C" in f else math.inf
    try:
        law = FrictionLaw(mu_s, mu_d, C)
    except ValueError as e:
        raise SceneError(f"{source}: friction.{e}") from None
    im = cfg.get("impact", {})
    e_n = number(source, "impact.e_n", im.get("e_n", 0.0), allow_zero=True)
    if e_n > 1:
        raise SceneError(f"{source}: impact.e_n: expected 0 <= e_n <= 1, got {e_n}")
    impact_law = im.get("law", "newton")
    if impact_law not in ("newton", "housner"):
        raise SceneError(f"{source}: impact.law: expected 'newton' or 'housner', "
                         f"got {impact_law!r}")  # fmt: skip
    if impact_law == "housner":
        refuse_keys(im, source, "impact", ("e_n",), "the housner law takes its restitution from "
                    "the body's shape; e_n is the newton law's: delete it beside law = "
                    "'housner'")  # fmt: skip
    mo = cfg.get("motion", {})
    t_end = number(source, "motion.t_end", mo["t_end"]) if "t_end" in mo else None
    tilt = scene_tilt(mo, source)
    from nsdyn.models.contact.event import tilt_angle

    try:
        theta0 = tilt_angle(body, tilt.get("theta0"), tilt.get("theta0_over_alpha"))
    except ValueError as e:  # ("theta0: ..." or "theta0_over_alpha: ...")
        raise SceneError(f"{source}: motion.{e}") from None
    if "record" in mo and "period" in mo:
        raise SceneError(f"{source}: motion.period: give a record or a sine period, not both")
    if "period" not in mo:
        refuse_keys(mo, source, "motion", SINE_KEYS, "a key of the displacement sine "
                    "(motion.period), which this scene does not have")  # fmt: skip
    unused = None  # a record's column the run leaves out
    units = record_units(mo, source)
    if "record" in mo:
        rec = str(mo["record"])  # a file beside the scene: made findable by read_toml
        try:
            gm = read_motion(rec, **units)
        except Exception as e:
            raise SceneError(f"{source}: motion.record: cannot read {rec!r}: {e}") from None
        if mo.get("vertical", True) is False and gm.a_ver is not None:  # (as a rocking scene)
            gm = gm.with_vertical(None)
        gm = scaled_record(gm, mo, source)  # (or refused above 100 g as read)
        if gm.t0 < 0:  # (its part before t = 0, where the run starts, was not felt: "rest")
            raise SceneError(f"{source}: motion.record: the record starts at t = {gm.t0:g} s, "
                             "before t = 0 where a contact run starts; expected a record whose "
                             "clock starts at 0 or later")  # fmt: skip
        motion = BaseMotion.from_motion(gm)
        from nsdyn.ground.formats import past_record_note, unused_columns_note

        unused = unused_columns_note(gm, "a planar body takes one horizontal component and "
                                     "the vertical")  # fmt: skip
        t_end = t_end or gm.t0 + gm.duration
        unused = [n for n in (unused, past_record_note(t_end, gm.t0 + gm.duration)) if n]
        pga = gm.pga
        what = f"{gm.name}, PGA {pga:.3g} m/s²"
    elif "period" in mo:
        T = number(source, "motion.period", mo["period"])
        R = np.hypot(*body.contacts.T)  # the rocking frequency p about a base corner, the fastest
        p = float(np.sqrt(body.mass * G_EARTH * R / (body.J + body.mass * R**2)).max())
        if 2 * math.pi / T > OMEGA_RATIO_MAX * p:  # (1e-6 s: 25 s of steps, then a failure)
            raise SceneError(f"{source}: motion.period: {T:g} s is {2 * math.pi / T / p:.3g} "
                             f"times faster than the body's rocking frequency p = {p:.4g} /s; "
                             f"expected at most {OMEGA_RATIO_MAX:g} p (its steps follow the "
                             "sine)")  # fmt: skip
        pga = number(source, "motion.pga", mo.get("pga", 1.6))
        if pga > PGA_TARGET_MAX:  # (1e6 m/s² ran: a 120 km sine)
            raise SceneError(f"{source}: motion.pga: expected {PGA_TARGET}, got {pga:g}")
        n = mo.get("n_cycles", 5)
        if not isinstance(n, int) or isinstance(n, bool) or n < 1:
            raise SceneError(f"{source}: motion.n_cycles: expected an integer >= 1, got {n!r}")
        start = mo.get("start", "impulsive")
        if start not in ("impulsive", "smooth"):
            raise SceneError(f"{source}: motion.start: expected 'impulsive' or 'smooth', "
                             f"got {start!r}")  # fmt: skip
        A = pga * (T / (2 * math.pi)) ** 2
        try:  # (more smooth cycles than its table holds)
            motion = BaseMotion.displacement_sine(A, T, n, start)
        except ValueError as e:
            raise SceneError(f"{source}: motion.{e}") from None
        t_end = t_end or n * T + 2.0
        what = (f"displacement sine A = {A * 1e3:.0f} mm, T = {T:g} s ({start}), peak "
                f"acceleration {pga:.3g} m/s²")  # fmt: skip
    else:
        if "pga" in mo:
            raise SceneError(f"{source}: motion.pga: {mo['pga']!r} m/s² needs a motion.record "
                             "or a motion.period to scale")  # fmt: skip
        motion, what, pga = None, "free motion", None
        t_end = t_end or T_END
    sv = cfg.get("solver", {})
    method = sv.get("method", "event")
    if method not in METHODS:
        raise SceneError(f"{source}: solver.method: expected one of {list(METHODS)}, "
                         f"got {method!r}")  # fmt: skip
    opts = {
        "method": method,
        "h": number(source, "solver.h", sv.get("h", 1e-3)),
        "theta": number(source, "solver.theta", sv.get("theta", 0.5)),
        "rtol": rel_tol(source, "solver.rtol", sv.get("rtol", 1e-9)),
        "dt_out": number(source, "solver.dt_out", sv.get("dt_out", 0.005)),
        "e_n": e_n,
        "impact_law": impact_law,
        "step_check": sv.get("step_check", True),
        "theta0": theta0,
        "what": what,
        "pga": pga,  # the peak ground acceleration the run feels [m/s²] (None: free motion)
    }
    if not isinstance(opts["step_check"], bool):
        raise SceneError(f"{source}: solver.step_check: expected true or false, got "
                         f"{opts['step_check']!r}")  # fmt: skip
    if not 0.5 <= opts["theta"] <= 1:
        raise SceneError(
            f"{source}: solver.theta: expected 0.5 <= theta <= 1, got {opts['theta']!r}"
        )
    opts["ground"] = _ground(cfg.get("ground", {}), body, source)
    if opts["ground"] is None and opts["method"] == "moreau" and motion is not None:
        from nsdyn.models.contact.moreau import check_step

        try:  # before the run's banner (it was refused after it)
            check_step(opts["h"], motion)
        except ValueError as e:
            raise SceneError(f"{source}: solver.{e}") from None
    # keys the chosen integrator does not read: noted, not taken silently
    unread = ("h", "theta", "step_check") if method == "event" else ("rtol",)
    opts["notes"] = [f"solver.{k} not used: method '{method}' ("
                     + ("Moreau-Jean's keys" if method == "event" else "the event method's")
                     + ")" for k in unread if k in sv]  # fmt: skip
    opts["notes"] += unused or []
    if opts["ground"] is not None:
        given = [k for k in ("method", "h", "theta", "rtol", "step_check") if k in sv]
        if given:  # refused, not ignored: the compliant ground has one integrator
            raise SceneError(f"{source}: solver.{given[0]}: a compliant ground (ground.kind = "
                             "'compliant') runs its own integrator (its step follows the "
                             "ground's stiffness); solver.method, h, theta and rtol apply to the "
                             "rigid ground only")  # fmt: skip
        if "impact" in cfg:
            raise SceneError(f"{source}: [impact]: a compliant ground (ground.kind = "
                             "'compliant') makes its impacts with its springs and dashpots; "
                             "[impact] applies to the rigid ground only")  # fmt: skip
        opts["method"] = "compliant"
        from nsdyn.models.contact.compliant import ground_step

        gr = cfg.get("ground", {})  # (a step too small: the key of the ground that makes it)
        damping = "damping_ratio" if "damping_ratio" in gr else "damping"
        fields = {"stiffness": "ground.stiffness", "damping": f"ground.{damping}",
                  "stick_stiffness": "ground.stick_stiffness"}  # fmt: skip
        with grid_fields(source, fields):  # (before a study's tasks or the run's warm-up)
            ground_step(body, opts["ground"], t_end)
    return body, law, motion, t_end, opts


def _ground(gr: dict, body, source: str):
    """The [ground] section: None (rigid) or a CompliantGround."""
    from nsdyn.models.contact.compliant import CompliantGround, check_settlement

    kind = gr.get("kind", "rigid")
    if kind not in ("rigid", "compliant"):
        raise SceneError(f"{source}: ground.kind: expected 'rigid' or 'compliant', got {kind!r}")
    if kind == "rigid":
        extra = sorted(set(gr) - {"kind"})
        if extra:
            raise SceneError(f"{source}: ground.{extra[0]}: only for ground.kind = 'compliant'")
        return None
    if "stiffness" not in gr:
        raise SceneError(f"{source}: ground.stiffness: missing (normal stiffness per base "
                         "corner, N/m)")  # fmt: skip
    k = number(source, "ground.stiffness", gr["stiffness"])
    if "damping" in gr and "damping_ratio" in gr:
        raise SceneError(f"{source}: ground.damping_ratio: give damping or damping_ratio, "
                         "not both")  # fmt: skip
    kt = number(source, "ground.stick_stiffness", gr["stick_stiffness"]) \
        if "stick_stiffness" in gr else None  # fmt: skip
    if "damping_ratio" in gr:
        zeta = number(source, "ground.damping_ratio", gr["damping_ratio"], allow_zero=True)
        g0 = CompliantGround.from_ratio(body, k, zeta)
        gr = {**gr, "damping": g0.c}
        gr.pop("damping_ratio")
    c = number(source, "ground.damping", gr.get("damping", 0.0), allow_zero=True)
    ground = CompliantGround(k, c, kt)
    try:
        check_settlement(body, ground)
    except ValueError as e:
        raise SceneError(f"{source}: ground.{e}") from None
    return ground


def simulate(body, law, motion, t_end, opts):
    """Run the scene's solver; returns a ContactResult."""
    from nsdyn.models.contact.event import simulate_event
    from nsdyn.models.contact.moreau import simulate_moreau

    if opts.get("ground") is not None:
        from nsdyn.models.contact.compliant import simulate_compliant

        return simulate_compliant(body, law, opts["ground"], motion, t_end=t_end,
                                  theta0=opts["theta0"], dt_out=opts["dt_out"])  # fmt: skip
    if opts["method"] == "moreau":
        with warnings.catch_warnings():  # (hops unchecked: the scene checks, or chose not to)
            warnings.simplefilter("ignore", AccuracyWarning)
            return simulate_moreau(body, law, motion, t_end=t_end, h=opts["h"],
                                   theta=opts["theta"], e_n=opts["e_n"], theta0=opts["theta0"],
                                   dt_out=max(opts["dt_out"], opts["h"]))  # fmt: skip
    return simulate_event(body, law, motion, t_end=t_end, e_n=opts["e_n"],
                          impact_law=opts["impact_law"], theta0=opts["theta0"],
                          rtol=opts["rtol"], atol=opts["rtol"] * 1e-3,
                          dt_out=opts["dt_out"])  # fmt: skip


def moreau_step_check(body, law, motion, t_end, opts, res) -> dict:
    """The Moreau-Jean run ``res`` repeated at half its step, with the same outputs
    (:func:`nsdyn.models.contact.moreau.half_step_check`, its advice in the scene's keys)."""
    from nsdyn.models.contact.moreau import half_step_check

    def rerun(h2):
        return simulate(
            body, law, motion, t_end, opts | {"h": h2, "dt_out": max(opts["dt_out"], opts["h"])}
        )

    return half_step_check(res, body, opts["h"], rerun, "solver.h", "solver.method = 'event'")


def run_scene(cfg: dict, *, source: str, out_dir: Path, figures: bool, quiet: bool) -> dict:
    """Run a contact scene; writes ``contact.npz`` (and ``contact.png``) into ``out_dir``."""
    body, law, motion, t_end, opts = build(cfg, source)
    name = cfg.get("scene", {}).get("name", Path(source).stem)
    say = (lambda *a: None) if quiet else (lambda *a: print(*a, file=sys.stderr))
    fields = GRID_FIELDS | {"h": "solver.h"}
    with grid_fields(source, fields):  # (before the start is said)
        if opts["method"] == "moreau" and opts.get("ground") is None:
            from nsdyn.models.contact.moreau import step_grid

            step_grid(t_end, opts["h"], opts["dt_out"])
        else:
            output_step(opts["dt_out"], t_end, off=False)
    say(f"contact: {name}: {opts['what']}, {opts['method']}, t_end = {t_end:g} s")
    for note in opts["notes"]:
        say(f"contact: note: {note}")
    with grid_fields(source, fields):  # refused before any step
        compile_s = warm(body, law, motion, t_end, opts)
        w0 = time.perf_counter()
        res = simulate(body, law, motion, t_end, opts)
    wall = time.perf_counter() - w0
    out_dir = Path(out_dir)
    s = res.summary()
    if opts["method"] == "moreau" and opts.get("ground") is None and opts["step_check"]:
        s.update(moreau_step_check(body, law, motion, t_end, opts, res))
        if s["step_resolved"] is not True:
            say(f"contact: note: {s['step_note']}")
    s["alpha_rad"] = slenderness(body)
    s["alpha_end_rad"] = slenderness(body, s["final_tilt_rad"])  # (the side it leans on)
    s["past_tip_over_at_end"] = not s["overturned"] and leaning_past(
        s["final_tilt_rad"], s["final_omega_rad_per_s"], s["alpha_end_rad"]
    )
    s["outcome"], text = outcome(s)
    files = [str(out_dir / "contact.npz")]
    with atomic_open(out_dir / "contact.npz", "wb") as fh:
        np.savez(
            fh,
            t=res.t,
            q=res.q,
            v=res.v,
            mode=res.mode,
            slide=res.slide,
            mode_names=np.array(MODE_NAMES),
            energy=(getattr(res, "mechanical_energy", None) or res.energy)(
                body.mass, body.J, G_EARTH
            ),  # (the energy history the guide asks to check: kinetic + potential [J])
        )  # mode k is mode_names[k]
    if figures:
        from nsdyn.atomic import save_figure
        from nsdyn.models.contact.figures import history_figure

        png = out_dir / "contact.png"
        fig = history_figure(res, body, title=f"{name}: {opts['what']}\n{text}", motion=motion)
        save_figure(fig, png)
        files.append(str(png))
    s.update({"kind": "contact", "name": name, "motion": opts["what"], "pga_mps2": opts["pga"],
              "t_end_s": t_end if s.get("t_overturn_s") is None else s["t_overturn_s"],
              "theta0_rad": opts["theta0"], "notes": opts["notes"],
              "wall_s": wall, "compile_s": compile_s, "files": files})  # fmt: skip
    say(f"contact: done in {wall:.3f} s ({compile_note(compile_s)})")
    return s


def outcome(s: dict) -> tuple[str, str]:
    """(word, one line) of a run summary: ``overturned`` (with its time) or the body's first
    motion (``rest``, ``slide``, ``rock``, ``slide_rock``, ...) and its peaks."""
    if s.get("overturned"):
        t = s.get("t_overturn_s")
        return "overturned", "OVERTURNED" + (f" at t = {t:.3f} s" if isinstance(t, float) else "")
    first = s.get("first_motion") or "rest"
    if first == "rest":
        return "rest", "stayed at rest (no sliding, no rocking)"
    rows = [("peak slide", "max_slide_m", "m")]
    alpha = s.get("alpha_rad")
    tilt = s.get("max_tilt_rad")
    if isinstance(tilt, float) and isinstance(alpha, float) and tilt < TILT_FLOOR * alpha:
        rows = rows + [(f"no rocking (peak tilt below {TILT_FLOOR:.0%} of alpha)", None, "")]
    else:
        rows.append(("peak tilt", "max_tilt_rad", "rad"))
    peaks = ", ".join(
        label if k is None else f"{label} {s[k]:.3g} {unit}"
        for label, k, unit in rows
        if k is None or isinstance(s.get(k), float)
    )
    head = "did not overturn"
    if s.get("past_tip_over_at_end"):  # (not overturned by t_end, but falling)
        head = past_tip_over(s["final_tilt_rad"], s.get("alpha_end_rad", alpha), "tilt")
    return first, f"{head}; first motion {first}" + (f", {peaks}" if peaks else "")


# rows of the text summary: key, label, unit ("" for a count or a word)
ROWS = (
    ("name", "name", ""),
    ("motion", "motion", ""),
    ("solver", "solver", ""),
    ("theta0_rad", "initial tilt", "rad"),
    ("first_motion", "first motion", ""),
    ("t_first_motion_s", "first motion at", "s"),
    ("max_slide_m", "peak slide", "m"),
    ("max_tilt_rad", "peak tilt", "rad"),
    ("max_uplift_m", "peak uplift", "m"),
    ("n_hops", "hops", ""),
    ("n_impacts", "impacts", ""),
    ("n_liftoffs", "lift-offs", ""),
    ("overturned", "overturned", ""),
    ("t_overturn_s", "overturned at", "s"),
    ("step_resolved", "Moreau-Jean step resolved (h, h/2)", ""),
    ("t_end_s", "duration", "s"),
    ("wall_s", "run time", "s"),
    ("compile_s", "compile/load time", "s"),
)


def format_summary(s: dict) -> str:
    """A short human table of a contact run, its outcome first, every number with its unit."""
    lines = [f"outcome {outcome(s)[1]}"]
    for k, label, unit in ROWS:
        v = s.get(k)
        if v is None:
            continue
        text = f"{v:.6g}" if isinstance(v, float) else str(v)
        lines.append(f"  {label:18s} {text}" + (f" {unit}" if unit else ""))
    for m, v in s.get("time_in_mode_s", {}).items():
        lines.append(f"  {'time in ' + m:18s} {v:.4g} s")
    lines.extend(f"  {'file':18s} {f}" for f in s.get("files", []))
    return "\n".join(lines)
