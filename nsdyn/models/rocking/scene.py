"""``nsdyn run`` on rocking scenes: read and check the TOML, run, write NPZ/PNG, summarise.

Scene (``[scene] kind = "rocking"``; sizes are the full width 2B and height 2H [m])::

    [scene]
    kind = "rocking"
    name = "seed 001 cask"
    model = "block"            # block | frame | compliant

    [block]                    # every model: the block or the frame's columns
    width = 2.0                # 2B [m]
    height = 4.0               # 2H [m]
    r = 0.82                   # restitution (default Housner's / the frame's)
    linear = false             # linearised equation
    mass = 124800.0            # [kg]
    gamma = 5.0                # frame only: m_beam / (2 m_column)
    omega_v_over_p = 300.0     # compliant only: vertical contact frequency / p
    zeta = 2.0                 # compliant only: contact damping ratio

    [motion]                   # a record, a pulse, or nothing (free rocking)
    record = "path/or/bundled-name"
    pga = 3.0                  # scale the record (or the pulse amplitude) [m/s²]
    vertical = true            # keep the record's vertical component
    pulse = "sine"             # sine | cosine | ricker | rect
    a_p_g = 0.4                # pulse amplitude [g] (or a_p [m/s²])
    omega_p = 12.57            # [rad/s] (or f_p [Hz])
    n_cycles = 1
    ver_ratio = 0.0
    t_end = 6.0                # [s]
    theta0_over_alpha = 0.0    # initial tilt / alpha (or theta0 [rad], not both)

    [solver]
    tol = 1e-9
    dt_out = 0.005
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

from nsdyn._checks import output_step
from nsdyn._numba_cache import compile_note, first_compile
from nsdyn.atomic import atomic_open
from nsdyn.ground import G_EARTH, read_motion
from nsdyn.ground.motion import PGA_MAX_PLAUSIBLE, PGA_TARGET_MAX
from nsdyn.ground.pulses import SHAPES, Pulse
from nsdyn.models.rocking.scene_keys import SCHEMA
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
from nsdyn.models.tilt import past_tip_over, scene_tilt

MODELS = ("block", "frame", "compliant")  # [scene] model
_FIELDS = SCHEMA.fields()  # table -> valid keys, declared in scene_keys
T_END = 10.0  # default duration without a record [s]
PULSE_KEYS = ("pulse", "a_p", "a_p_g", "omega_p", "f_p", "n_cycles", "ver_ratio", "t_start")
RECORD_REPLACES = PULSE_KEYS  # the [motion] keys `nsdyn run --record` drops
METHODS = ("dopri5",)  # the rocking integrator (event-located Dormand-Prince 5(4))
# seconds a first run compiles the kernels (2-core machine, empty cache): a middling hour's,
# 1.8x the fast hour's in the family table of docs/dev/first-runs.md
COMPILE_ABOUT_S = 4.0
# a Housner run is repeated at TOL_CHECK x its tolerance (a run takes milliseconds): its
# outcome and peak tilt / alpha (within TOL_CHECK_ABS + TOL_CHECK_REL of it) must agree. At
# solver.tol = 1e-4 a 2 x 4 m block under a 0.81 Hz sine of 1 g peaked at 1.45 alpha and
# ended "leaning past its tip-over angle", at 1e-7 and the default 1e-9 at 1.011 alpha
TOL_CHECK, TOL_CHECK_ABS, TOL_CHECK_REL = 1e-3, 0.01, 0.02


def kernels_cached(model) -> bool:
    """True when the kernel a run of ``model`` calls is compiled in this process or in numba's
    on-disk cache (the run then only loads it; else a first run announces its compilation)."""
    from nsdyn._numba_cache import all_cached
    from nsdyn.models.rocking import _kblock, _kcompliant, rocking_compile
    from nsdyn.models.rocking.compliant import CompliantBlock

    if isinstance(model, CompliantBlock):
        return all_cached([_kcompliant.integrate])
    # the loop and its callee by address (one list: the helper's share is the same)
    return all_cached([_kblock.integrate, *(c.kernel for c in rocking_compile.callees())])


def build_model(cfg: dict, source: str):
    """The block, frame or compliant block of a parsed scene."""
    from nsdyn.models.rocking.block import RockingBlock, too_slender
    from nsdyn.models.rocking.compliant import CompliantBlock, check_settlement
    from nsdyn.models.rocking.frame import RockingFrame

    check_fields(cfg, _FIELDS, source)
    model = cfg.get("scene", {}).get("model", "block")
    if model not in MODELS:
        raise SceneError(f"{source}: scene.model: expected one of {list(MODELS)}, got {model!r}")
    b = cfg.get("block", {})
    for key in ("width", "height"):
        if key not in b:
            raise SceneError(f"{source}: block.{key}: missing (a positive size in m)")
    w = number(source, "block.width", b["width"])
    h = number(source, "block.height", b["height"])
    if why := too_slender(w, h):
        raise SceneError(f"{source}: block.width: {why}")
    mass = number(source, "block.mass", b.get("mass", 1.0))
    r = None
    if "r" in b:
        r = number(source, "block.r", b["r"], positive=False)  # one message for any r
        if not (0.0 <= r <= 1.0):  # (0: a plastic impact, the block stops at it)
            raise SceneError(f"{source}: block.r: expected 0 <= r <= 1, got {b['r']!r}")
    linear = b.get("linear", False)
    if not isinstance(linear, bool):
        raise SceneError(f"{source}: block.linear: expected true or false, got {linear!r}")
    if model != "compliant":
        refuse_keys(b, source, "block", ("omega_v_over_p", "zeta"), "a key of the compliant "
                    f"model (scene.model = 'compliant'), not of a {model}")  # fmt: skip
    if model != "frame" and "gamma" in b:
        raise SceneError(f"{source}: block.gamma: the beam-to-columns mass ratio of a rocking "
                         f"frame (scene.model = 'frame'), not of a {model}")  # fmt: skip
    if model == "frame":  # (without gamma it ran the bare column, saying "model frame")
        if "gamma" not in b:
            raise SceneError(f"{source}: block.gamma: missing; expected the frame's beam-to-"
                             "columns mass ratio m_beam / (2 m_column) >= 0 (0: the columns "
                             "alone)")  # fmt: skip
        gamma = number(source, "block.gamma", b["gamma"], allow_zero=True)
        return _rocks(RockingFrame(width=w, height=h, gamma=gamma, r=r, linear=linear,
                                   g=G_EARTH, column_mass=mass), source)  # fmt: skip
    if model == "compliant":
        if r is not None or linear:
            raise SceneError(f"{source}: block.r / block.linear: not used by the compliant model")
        ratio = number(source, "block.omega_v_over_p", b.get("omega_v_over_p", 300.0))
        zeta = number(source, "block.zeta", b.get("zeta", 2.0), allow_zero=True)
        p = RockingBlock(width=w, height=h).p
        model = CompliantBlock.from_frequency(width=w, height=h, mass=mass, omega_v=ratio * p,
                                              zeta=zeta)  # fmt: skip
        try:
            check_settlement(model)  # (at the build: before a compile)
        except ValueError as e:
            raise SceneError(f"{source}: block.omega_v_over_p: {str(e).split(': ', 1)[1]}") \
                from None  # fmt: skip
        return model
    return _rocks(RockingBlock(width=w, height=h, r=r, linear=linear, g=G_EARTH, mass=mass), source)


def _rocks(model, source: str):
    """``model``, or SceneError when the restitution from its shape is not positive."""
    from nsdyn.models.rocking.block import restitution_of

    try:
        restitution_of(model)
    except ValueError as e:
        raise SceneError(f"{source}: block.{e}") from None
    return model


def build_motion(cfg: dict, source: str):
    """(excitation or None, t_end, initial tilt, description) of a parsed scene; the tilt is
    the keyword of the simulation (``{"theta0": rad}``, ``{"theta0_over_alpha": v}`` or ``{}``)."""
    mo = cfg.get("motion", {})
    t_end = number(source, "motion.t_end", mo["t_end"]) if "t_end" in mo else None
    th0 = scene_tilt(mo, source)
    units = record_units(mo, source)
    if "record" in mo:
        rec = str(mo["record"])  # a file beside the scene: made findable by read_toml
        try:
            motion = read_motion(rec, **units)
        except Exception as e:
            raise SceneError(f"{source}: motion.record: cannot read {rec!r}: {e}") from None
        refuse_keys(mo, source, "motion", PULSE_KEYS, "a pulse's key beside motion.record; give "
                    "a record or a pulse, not both")  # fmt: skip
        if mo.get("vertical", True) is False and motion.a_ver is not None:
            motion = motion.with_vertical(None)
        motion = scaled_record(motion, mo, source)  # (or refused above 100 g as read)
        t_end = t_end or motion.t0 + motion.duration
        return motion, t_end, th0, motion.name
    if "pulse" in mo:
        shape = mo["pulse"]
        if not isinstance(shape, str) or shape not in SHAPES:  # (a list: "unhashable")
            raise SceneError(f"{source}: motion.pulse: expected one of {sorted(SHAPES)}, "
                             f"got {shape!r}")  # fmt: skip
        if "a_p" in mo:
            a_p = number(source, "motion.a_p", mo["a_p"], positive=False)
        elif "a_p_g" in mo:
            a_p = G_EARTH * number(source, "motion.a_p_g", mo["a_p_g"], positive=False)
        elif "pga" in mo:  # the amplitude given as the pulse's peak [m/s²]
            a_p = 1.0
        else:
            raise SceneError(f"{source}: motion.a_p_g: missing (pulse amplitude in g, a_p in "
                             "m/s², or pga)")  # fmt: skip
        if "pga" in mo:  # replaces the amplitude (as --pga does), keeping its sign
            a_p = math.copysign(number(source, "motion.pga", mo["pga"]), a_p)
        key = "pga" if "pga" in mo else "a_p" if "a_p" in mo else "a_p_g"
        if abs(a_p) > PGA_TARGET_MAX:  # (1e6 g ran; every scene's amplitudes end at 100 g)
            raise SceneError(f"{source}: motion.{key}: expected a pulse amplitude up to "
                             f"{PGA_TARGET_MAX:g} m/s² (100 g), got {mo[key]:g}"
                             f"{' g' if key == 'a_p_g' else ''}")  # fmt: skip
        for one, other in (("a_p", "a_p_g"), ("omega_p", "f_p")):
            if one in mo and other in mo:  # each value checked first
                for k in (one, other):
                    number(source, f"motion.{k}", mo[k], positive=k[0] != "a")
                raise SceneError(f"{source}: motion.{other}: give {one} or {other}, not both")
        if "omega_p" in mo:
            w = number(source, "motion.omega_p", mo["omega_p"])
        elif "f_p" in mo:
            w = 2 * math.pi * number(source, "motion.f_p", mo["f_p"])
        else:
            raise SceneError(f"{source}: motion.omega_p: missing (the pulse's frequency: "
                             "omega_p in rad/s, or f_p in Hz)")  # fmt: skip
        n = mo.get("n_cycles", 1)
        if not isinstance(n, int) or isinstance(n, bool) or n < 1:
            raise SceneError(f"{source}: motion.n_cycles: expected an integer >= 1, got {n!r}")
        ratio = number(source, "motion.ver_ratio", mo.get("ver_ratio", 0.0), positive=False)
        t_s = number(source, "motion.t_start", mo.get("t_start", 0.0), allow_zero=True)
        pulse = Pulse(shape, a_p, w, n, t_s, ratio)
        if t_end is not None and t_s >= t_end:
            raise SceneError(f"{source}: motion.t_start: the pulse starts at {t_s:g} s, at or "
                             f"after the run's end (t_end = {t_end:g} s); expected "
                             "t_start < t_end")  # fmt: skip
        what = f"{shape} pulse"
        given = [k for k in ("a_p", "a_p_g") if k in mo]
        if "pga" in mo and given:  # (a study's motion.pga scales the scene's pulse: said)
            unit = " g" if given[0] == "a_p_g" else " m/s²"
            what += f" (its amplitude motion.pga, in place of {given[0]} = {mo[given[0]]:g}{unit})"
        return pulse, t_end or max(T_END, 3 * pulse.duration), th0, what
    if "pga" in mo:
        raise SceneError(f"{source}: motion.pga: {mo['pga']!r} m/s² needs a motion.record or "
                         "a motion.pulse to scale")  # fmt: skip
    refuse_keys(mo, source, "motion", PULSE_KEYS, "a pulse's key without motion.pulse (the "
                "shape: sine, cosine, ricker or rect)")  # fmt: skip
    return None, t_end or T_END, th0, "free rocking"


def build_solver(cfg: dict, source: str) -> tuple[float, float | None]:
    """(tol, dt_out or None) of a parsed scene's ``[solver]``, checked."""
    from nsdyn.models.rocking import block as blk

    sv = cfg.get("solver", {})
    method = sv.get("method", "dopri5")
    if method not in METHODS:
        raise SceneError(f"{source}: solver.method: rocking scenes use {list(METHODS)}, "
                         f"got {method!r}")  # fmt: skip
    tol = rel_tol(source, "solver.tol", sv.get("tol", blk.TOL))
    dt_out = number(source, "solver.dt_out", sv["dt_out"]) if "dt_out" in sv else None
    return tol, dt_out


def warm(model) -> float:
    """Compile (or load) the kernel a run of ``model`` calls, by a tiny run, saying so on
    stderr when it compiles (:func:`nsdyn._numba_cache.first_compile`); the seconds it took.
    A run, an overturning spectrum and a study call it before their work starts."""
    from nsdyn.models.rocking import block as blk
    from nsdyn.models.rocking.compliant import CompliantBlock, simulate_compliant

    w0 = time.perf_counter()
    with first_compile("rocking", COMPILE_ABOUT_S, kernels_cached(model)):
        if isinstance(model, CompliantBlock):  # a benign block: the kernel is the same, and
            # a too-stiff contact of the scene's own spent its step budget here, where the
            # run's check would refuse it (exit 3 after 7 s instead of 2 at once)
            warm_block = CompliantBlock(width=1.0, height=2.0, mass=1e3, k=1e7, c=1e4)
            simulate_compliant(warm_block, t_end=1e-3, dt_out=1e-3)
        else:
            blk.warmup()
    return time.perf_counter() - w0


def warm_key(cfg: dict):
    """What of a scene selects the kernel its run compiles (the model): scenes with equal
    keys call the same compiled code."""
    return cfg.get("scene", {}).get("model", "block")


def warm_scene(cfg: dict, source: str) -> float:
    """:func:`warm` for a parsed scene (its model; the motion does not select the kernel)."""
    return warm(build_model(cfg, source))


def run_scene(cfg: dict, *, source: str, out_dir: Path, figures: bool, quiet: bool) -> dict:
    """Run a rocking scene; writes ``rocking.npz`` (and ``rocking.png``) into ``out_dir``."""
    from nsdyn.models.rocking import block as blk
    from nsdyn.models.rocking.compliant import CompliantBlock, simulate_compliant

    model = build_model(cfg, source)
    exc, t_end, th0, what = build_motion(cfg, source)
    tol, dt_out = build_solver(cfg, source)
    name = cfg.get("scene", {}).get("name", Path(source).stem)
    say = (lambda *a: None) if quiet else (lambda *a: print(*a, file=sys.stderr))
    mo = cfg.get("motion", {})  # (a pulse faster than the block resolves: its frequency)
    pulse_w = "motion.f_p" if isinstance(mo, dict) and "f_p" in mo else "motion.omega_p"
    fields = GRID_FIELDS | {"omega_v": "block.omega_v_over_p", "excitation": pulse_w}
    record = exc is not None and not isinstance(exc, Pulse)
    # a rigid run starts with its record (a record before t = 0 ran unfelt: "rest"); a
    # compliant run starts at t = 0, so a record before it is refused
    early = record and not isinstance(model, CompliantBlock) and exc.t0 < 0  # (a later one:
    start = {"t0": exc.t0} if early else {}  # the ground at rest before it, as before)
    if record and exc.t0 >= t_end:  # (it ran at rest: "rest", unsaid)
        raise SceneError(f"{source}: motion.t_end: the record starts at {exc.t0:g} s, at or "
                         f"after the run's end ({t_end:g} s); expected an end after its "
                         "start")  # fmt: skip
    if record and isinstance(model, CompliantBlock) and exc.t0 < 0:
        raise SceneError(f"{source}: motion.record: the record starts at t = {exc.t0:g} s, "
                         "before t = 0 where a compliant block's run starts; expected a "
                         "record whose clock starts at 0 or later")  # fmt: skip
    with grid_fields(source, fields):  # (refused before the run says it starts)
        output_step(dt_out, t_end - start.get("t0", 0.0), off=False)  # (0: refused)
        blk.check_frequency(model, exc, hz=pulse_w == "motion.f_p")
    say(f"rocking: {name}: {type(model).__name__}, {what}, t_end = {t_end:g} s")
    from nsdyn.ground.formats import past_record_note, unused_columns_note

    notes = [n for n in [unused_columns_note(exc, "a rocking block takes one horizontal "
                                             "component and the vertical")] if n]  # fmt: skip
    if exc is not None and not isinstance(exc, Pulse):  # a record (a pulse ends by itself)
        notes += [n for n in [past_record_note(t_end, exc.t0 + exc.duration)] if n]
    elif isinstance(exc, Pulse) and abs(exc.a_p) > PGA_MAX_PLAUSIBLE:  # (a_p_g = 40 for 0.40)
        notes.append(f"a pulse amplitude of {abs(exc.a_p):.4g} m/s² ({abs(exc.a_p) / G_EARTH:.3g}"
                     f" g), past the {PGA_MAX_PLAUSIBLE:g} m/s² of recorded ground motions: is "
                     "motion.a_p_g in %g, or motion.a_p in cm/s²?")  # fmt: skip
    for n in notes:
        say(f"rocking: note: {n}")
    out_dir = Path(out_dir)
    compile_s = warm(model)
    w0 = time.perf_counter()
    with grid_fields(source, fields):  # the run's grid and steps, refused before any step
        if isinstance(model, CompliantBlock):
            from nsdyn.models.rocking import compliant as cm

            res = simulate_compliant(model, exc, t_end=t_end, tol=min(tol * 10, 1e-6),
                                     dt_out=dt_out or cm.DT_OUT, **th0)  # fmt: skip
        else:
            res = blk.simulate_rocking(model, exc, t_end=t_end, tol=tol, dt_out=dt_out, **th0,
                                       **start)  # fmt: skip
    if isinstance(model, CompliantBlock):
        s = res.summary()
        arrays = {"t": res.t, "y": res.y, "theta": res.theta, "thetad": res.thetad,
                  "peaks": res.peaks(), "y_columns": np.array(Y_COLUMNS)}  # fmt: skip
        s["r_housner"] = blk.housner_restitution(model.alpha)
    else:
        s = res.summary()
        arrays = {"t": res.t, "theta": res.theta, "thetad": res.thetad, "energy": res.energy(),
                  "impacts": res.impacts, "peaks": res.peaks}  # fmt: skip
    wall = time.perf_counter() - w0  # (the run's: its tolerance check apart)
    if not isinstance(model, CompliantBlock):
        with grid_fields(source, fields):
            checked = tol_check(res, tol, lambda t2: blk.simulate_rocking(
                model, exc, t_end=t_end, tol=t2, dt_out=0.0, **th0, **start))  # fmt: skip
    files = [str(out_dir / "rocking.npz")]
    with atomic_open(out_dir / "rocking.npz", "wb") as fh:
        np.savez(fh, **arrays)
    if figures:
        from nsdyn.atomic import save_figure
        from nsdyn.models.rocking.figures import history_figure

        png = out_dir / "rocking.png"
        title = f"{name}: {type(model).__name__}, {excitation_text(exc, what)}\n{outcome(s)[1]}"
        ground = ground_of(exc, arrays["t"])
        fig = history_figure(arrays["t"], arrays["theta"], model.alpha, title=title,
                             impacts=arrays.get("impacts"), ground=ground)  # fmt: skip
        save_figure(fig, png)
        files.append(str(png))
    s.update({"kind": "rocking", "model": cfg.get("scene", {}).get("model", "block"),
              "name": name, "motion": excitation_text(exc, what), "pga_mps2": peak_of(exc),
              "t_end_s": t_end if s.get("t_overturn_s") is None else s["t_overturn_s"],
              "alpha_rad": model.alpha, "p_per_s": model.p,
              "theta0_rad": float(res.theta[0]) + 0.0 if res.t.size else 0.0,
              "wall_s": wall, "compile_s": compile_s, "files": files})  # fmt: skip
    s.setdefault("outcome", outcome(s)[0])  # (every block's summary has one)
    if not isinstance(model, CompliantBlock):
        s.update(checked)
        if checked.get("tol_note"):
            notes.append(checked["tol_note"])
            say(f"rocking: note: {checked['tol_note']}")
    if s.get("n_flights"):  # (the compliant corners let the block fly, the rigid one stops)
        notes.append(f"the block left the ground (both corners off it) {s['n_flights']} "
                     f"time(s), first at t = {s['t_first_flight_s']:.4g} s, its lower corner "
                     f"up to {s['max_flight_height_m']:.3g} m: the compliant corners let it fly "
                     "(the rigid block stops there: free flight is not modelled)")  # fmt: skip
        say(f"rocking: note: {notes[-1]}")
    if notes:
        s["notes"] = notes
    say(f"rocking: done in {wall:.3f} s ({compile_note(compile_s)})")
    return s


def tol_check(res, tol: float, rerun) -> dict:
    """``res`` (at ``tol``) against ``rerun(TOL_CHECK * tol)``: ``tol_resolved`` when their
    outcomes and peak tilts / alpha agree (module constants), else False with ``tol_note``
    saying both; None when the rerun failed or ``tol`` is at the floor of tolerances."""
    from nsdyn._checks import RTOL_MIN, NumericalFailure
    from nsdyn.models.rocking.block import TOL

    t2 = max(TOL_CHECK * tol, RTOL_MIN)
    if t2 >= tol:
        return {"tol_resolved": None}
    try:
        b = rerun(t2).summary()
    except (ValueError, NumericalFailure) as e:  # (the run stands; the check could not be made)
        return {"tol_resolved": None,
                "tol_note": f"the check at solver.tol = {t2:.2g} failed: {e}"}  # fmt: skip
    a = res.summary()
    x, y = a["max_theta_over_alpha"], b["max_theta_over_alpha"]
    ok = a["outcome"] == b["outcome"] and abs(x - y) <= TOL_CHECK_ABS + TOL_CHECK_REL * max(x, y)
    out = {"tol_resolved": ok, "tol_check_peak_over_alpha": y}
    if not ok:
        out["tol_note"] = (f"solver.tol = {tol:.2g} does not resolve this response: peak tilt "
                           f"{x:.4g} alpha, {a['outcome']}, against {y:.4g} alpha, "
                           f"{b['outcome']} at {t2:.2g}; tighten solver.tol (default "
                           f"{TOL:g})")  # fmt: skip
    return out


def excitation_text(exc, what: str) -> str:
    """The excitation of a run in words, with its peak acceleration [m/s²]."""
    a = peak_of(exc)
    if a is None:
        return what
    if isinstance(exc, Pulse):  # signed: a negative pulse pushes the other way first
        a = float(exc.a_p)
        return f"{what}, a_p = {a:.3g} m/s² ({a / G_EARTH:.3g} g)"
    return f"{what}, PGA {a:.3g} m/s² ({a / G_EARTH:.3g} g)"


# the compliant block's state y, column by column (phi counter-clockwise: theta = -phi; e the
# horizontal springs' stretches at the left and right corners)
Y_COLUMNS = ("x_m", "y_m", "phi_rad", "xd_m_per_s", "yd_m_per_s", "phid_rad_per_s",
             "e_left_m", "e_right_m")  # fmt: skip


def peak_of(exc) -> float | None:
    """The peak ground acceleration of a record or a pulse [m/s²] (None: free rocking)."""
    if exc is None:
        return None
    return float(abs(exc.a_p)) if isinstance(exc, Pulse) else float(exc.pga)


def ground_of(exc, t: np.ndarray):
    """(t, horizontal ground acceleration [m/s²]) of a record or a pulse, None without one."""
    if exc is None:
        return None
    if isinstance(exc, Pulse):
        return t, exc.accel(t)
    return exc.t, exc.a_hor


def outcome(s: dict) -> tuple[str, str]:
    """(word, one line) of a run summary: ``overturned`` (with its time), ``rocking`` (the
    block lifted off a corner and still rocks at the end), ``rest``."""
    word = s.get("outcome") or ("overturned" if s.get("overturned") else "")
    peak = s.get("max_theta_over_alpha")
    tilt = f", peak tilt {peak:.3g} alpha" if isinstance(peak, float) else ""
    if word == "overturned":
        t = s.get("t_overturn_s")
        return word, "OVERTURNED" + (f" at t = {t:.3f} s" if isinstance(t, float) else "")
    if word == "rocking" and not s.get("n_impacts") and abs((peak or 0.0) - 1.0) < 1e-9:
        return word, ("balanced on its corner to the end (theta = alpha, the unstable "
                      "equilibrium: any disturbance rocks or topples it)")  # fmt: skip
    if s.get("past_tip_over_at_end"):  # (not overturned by t_end, but falling)
        return word, f"{past_tip_over(s['final_theta_rad'], s['alpha_rad'], 'theta')}{tilt}"
    if word == "rocking":
        return word, f"rocking (lifted off, still rocking at the end){tilt}"
    if word == "rest":
        rocked = s.get("n_impacts") or s.get("n_uplifts")
        return word, ("rocked and came to rest" if rocked else "no rocking: at rest") + tilt
    return "standing", f"standing (did not overturn){tilt}"


# rows of the text summary: key, label, unit ("" for a dimensionless number or a word)
ROWS = (
    ("name", "name", ""),
    ("model", "model", ""),
    ("motion", "motion", ""),
    ("alpha_rad", "slenderness alpha", "rad"),
    ("p_per_s", "frequency parameter p", "1/s"),
    ("r", "restitution r", "-"),
    ("r_housner", "Housner's r", "-"),
    ("theta0_rad", "initial tilt theta0", "rad"),
    ("outcome", "outcome", ""),
    ("max_theta_rad", "peak tilt", "rad"),
    ("max_theta_over_alpha", "peak tilt / alpha", "-"),
    ("n_impacts", "impacts", ""),
    ("t_uplift_s", "first lift-off", "s"),
    ("t_overturn_s", "overturned at", "s"),
    ("t_rest_s", "last came to rest at", "s"),  # (an overturned run may have rested first)
    ("t_end_s", "end time", "s"),
    ("wall_s", "run time", "s"),
    ("compile_s", "compile/load time", "s"),
)


def format_summary(s: dict) -> str:
    """A short human table of a rocking run, its outcome first, every number with its unit."""
    lines = [f"outcome {outcome(s)[1]}"]
    for k, label, unit in ROWS:
        v = s.get(k)
        if v is None:
            continue
        text = f"{v:.6g}" if isinstance(v, float) else str(v)
        lines.append(f"  {label:22s} {text}" + (f" {unit}" if unit else ""))
    lines.extend(f"  {'file':22s} {f}" for f in s.get("files", []))
    return "\n".join(lines)
