"""``nsdyn run`` on cylinder scenes: read and check the TOML, run, write histories and figures.

Tables: ``[cylinder]`` r, height (full; or H, the half height), m (I_t, I_a); ``[foundation]``
case and either k, c or the design targets f_rock [Hz], zeta, and ``sliding = true`` with ``mu``
for a base that slides with Coulomb friction; ``[motion]`` a simulated earthquake (seed,
duration, dt, s0_units) or a ``record`` file
(``record_y``, ``record_z``: second horizontal and vertical components), optional ``pga``
(peak horizontal acceleration after scaling), ``t_end`` and the initial tilt ``theta0`` [rad] or
``theta0_over_alpha`` (alpha = atan(r/H)) towards ``azimuth0`` [rad]; ``[solver]`` rtol, method;
``[output]`` z_section (height of the stress section, default H); ``[star]`` case = "base" or
"<q>*<factor>" with q one of k, c, H, r: one quantity of the scene scaled after the design, the
rest kept (the source study's one-at-a-time star, e.g. "k*2", "c*4", "H*0.5").

The summary holds scalars only (besides ``stress_peaks``), so a study can keep and analyse every
field: peaks of tilt, uplift ratio, rim lift, base shear, overturning moment, slip, the wall
stresses max σ₁, min σ₃, max τ_max (over the points A–E, divided by mg/πr²) and the energies.
"""

from __future__ import annotations

import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from nsdyn._checks import MAX_OUTPUTS
from nsdyn._numba_cache import compile_note, first_compile
from nsdyn.atomic import atomic_open, save_figure
from nsdyn.ground.motion import PGA_TARGET, PGA_TARGET_MAX, record_pga_said
from nsdyn.ground.synthesis import noise_step
from nsdyn.models import scenefile
from nsdyn.models.cylinder.design import (
    design_foundation,
    static_settlement,
    too_soft,
    too_stiff,
    uplift_onset,
)
from nsdyn.models.cylinder.params import FOUNDATIONS, CylinderParams
from nsdyn.models.cylinder.scene_keys import SCHEMA
from nsdyn.models.cylinder.simulate import (
    EQ_DT,
    EQ_DURATION,
    RTOL,
    S0_UNITS,
    THETA_TOPPLE,
    earthquake,
    from_motions,
    simulate,
)
from nsdyn.models.cylinder.stresses import peak_stresses
from nsdyn.models.scenefile import (
    SceneError,
    check_fields,
    file_stem,
    grid_fields,
    number,
    record_units,
    rel_tol,
)
from nsdyn.models.tilt import past_tip_over, scene_tilt

TABLES = SCHEMA.fields()  # table -> valid keys, declared in scene_keys
STAR_QUANTITIES = ("k", "c", "H", "r")  # quantities a star case may scale
METHODS = ("dopri5",)  # integrators of this family
# the simulated earthquake's [motion] keys: refused beside a record, dropped by `--record`
RECORD_REPLACES = ("seed", "duration", "dt", "s0_units")
# seconds a first run compiles the kernel (2-core machine, empty cache): a middling hour's,
# 1.8x the fast hour's in the family table of docs/dev/first-runs.md
COMPILE_ABOUT_S = 6.0


def kernels_cached(p: CylinderParams) -> bool:
    """True when the kernel a run of ``p`` calls is compiled in this process or in numba's
    on-disk cache, or when the run calls none (a fixed foundation moves with the ground):
    the run then compiles nothing (else a first run announces the compilation)."""
    from nsdyn._numba_cache import all_cached
    from nsdyn.models.cylinder import _kernel, cylinder_compile

    if p.foundation == "fixed":
        return True
    # the loop and its callees by address (one list: the helper's share is the same)
    return all_cached([_kernel.integrate, *(c.kernel for c in cylinder_compile.callees())])


def _friction(fd: dict, case: str, source: str) -> float | None:
    """μ of a sliding base, or None (restrained) — from ``[foundation] sliding``, ``mu``."""
    sliding = fd.get("sliding", False)
    if not isinstance(sliding, bool):
        raise SceneError(f"{source}: foundation.sliding: expected true or false, got {sliding!r}")
    if not sliding:
        if "mu" in fd:
            raise SceneError(f"{source}: foundation.mu: applies with sliding = true only")
        return None
    if "mu" not in fd:
        raise SceneError(f"{source}: foundation.mu: missing (friction coefficient of sliding)")
    if case == "fixed":
        raise SceneError(f"{source}: foundation.sliding: a fixed base cannot slide")
    return number(source, "foundation.mu", fd["mu"], allow_zero=True)


def _star(p: CylinderParams, st: dict, source: str) -> CylinderParams:
    """``p`` with one quantity scaled by the ``[star] case`` "q*factor" ("base": unchanged)."""
    case = st.get("case", "base")
    if case == "base":
        return p
    form = f'expected "base" or "<q>*<factor>" with q in {list(STAR_QUANTITIES)}'
    if not isinstance(case, str) or case.count("*") != 1:
        raise SceneError(f"{source}: star.case: {form}, got {case!r}")
    q, fac = (x.strip() for x in case.split("*"))
    try:
        fac = float(fac)
    except ValueError:
        fac = math.nan
    if q not in STAR_QUANTITIES or not (math.isfinite(fac) and fac > 0):
        raise SceneError(f"{source}: star.case: {form} and a positive factor, got {case!r}")
    try:
        return p.with_(**{q: getattr(p, q) * fac})
    except ValueError as e:  # (H*1e300: an inertia that overflows)
        raise SceneError(f"{source}: star.case: {case!r} gives {e}") from None


def simulated_records_note(source: str) -> None:
    """An InputWarning for a study's ``[records] simulated`` on a cylinder scene: one
    horizontal component and the vertical at their own scale, not the scene's simulated
    earthquake (its PGA 0.3 m/s² against 3 m/s² for the scene's at g² s)."""
    import warnings

    from nsdyn._checks import InputWarning

    warnings.warn(f"{source}: records.simulated: one horizontal component and the vertical, "
                  "at their own scale, not the scene's simulated earthquake (its s0_units); "
                  "vary motion.seed for three-component earthquakes", InputWarning,
                  stacklevel=3)  # fmt: skip


def _component(mo: dict, key: str, units: dict, source: str):
    """The record of ``[motion] key`` (None when not given; SceneError naming the key)."""
    from nsdyn.ground import read_motion

    if key not in mo:
        return None
    try:
        return read_motion(mo[key], **units)
    except (OSError, ValueError) as e:
        raise SceneError(f"{source}: motion.{key}: {e}") from None


def _record_components(mo: dict, units: dict, source: str) -> tuple:
    """(x, y, z) records of ``[motion] record`` (with ``record_y`` and ``record_z``, each a
    file of one component); alone, a file or bundled name holding both horizontal components
    (nsdyn's three-column CSV, a bundled record with its second component) gives both and its
    vertical, and a one-component file x and its vertical, if any."""
    from nsdyn.ground import read_motion, read_motion3
    from nsdyn.ground.motion import RecordFileError

    if "record_y" in mo or "record_z" in mo:
        mx = read_motion(mo["record"], **units)
        my, mz = (_component(mo, key, units, source) for key in ("record_y", "record_z"))
        return mx, my, mz
    try:
        m3 = read_motion3(mo["record"], **units)
    except (RecordFileError, KeyError, ValueError):  # one horizontal component
        return read_motion(mo["record"], **units), None, None
    return m3.planar(0.0), m3.planar(90.0), None  # (x with the vertical, y)


def build(cfg: dict, source: str = "<scene>") -> tuple[CylinderParams, float, np.ndarray, dict]:
    """(params, dt, ag (n, 3), solver options) from a parsed scene; :class:`SceneError` if bad."""
    check_fields(cfg, TABLES, source)
    cy = cfg.get("cylinder", {})
    geo = {
        k: number(source, f"cylinder.{k}", cy[k]) for k in ("r", "H", "m", "I_t", "I_a") if k in cy
    }
    if "height" in cy:  # the full height, as every family's sizes
        if "H" in cy:
            raise SceneError(f"{source}: cylinder.height: give the full height or the half "
                             "height H, not both")  # fmt: skip
        geo["H"] = 0.5 * number(source, "cylinder.height", cy["height"])
    fd = cfg.get("foundation", {})
    case = fd.get("case", "tensionless")
    if case not in FOUNDATIONS:
        raise SceneError(
            f"{source}: foundation.case: expected one of {list(FOUNDATIONS)}, got {case!r}"
        )
    has_kc, has_design = ("k" in fd or "c" in fd), ("f_rock" in fd or "zeta" in fd)
    springs = [f"foundation.{k}" for k in ("k", "c", "f_rock", "zeta") if k in fd]
    if has_kc and has_design:
        raise SceneError(f"{source}: foundation: give either k and c or f_rock and zeta, not both")
    try:  # (sizes whose inertias overflow: H = 1e300)
        base = CylinderParams(**{k: v for k, v in geo.items()}) if geo else CylinderParams()
    except ValueError as e:
        raise SceneError(f"{source}: [cylinder] {e}") from None
    if has_design:
        f = number(source, "foundation.f_rock", fd.get("f_rock", 3.0))
        z = number(source, "foundation.zeta", fd.get("zeta", 0.1), allow_zero=True)
        if z >= 1.0:  # 10 typed for 10 %: an overdamped rocking mode is no design target
            raise SceneError(f"{source}: foundation.zeta: expected a damping ratio in [0, 1) "
                             f"(a fraction: 0.1 for 10 %), got {fd['zeta']!r}")  # fmt: skip
        k, c = design_foundation(f, z, base.r, base.H, base.m, I_t=geo.get("I_t"))
    else:
        k = number(source, "foundation.k", fd.get("k", base.k))
        c = number(source, "foundation.c", fd.get("c", base.c), allow_zero=True)
    try:
        p = _star(base.with_(k=k, c=c, foundation=case), cfg.get("star", {}), source)
    except SceneError:
        raise
    except ValueError as e:  # (a foundation k whose moment k pi r^4 / 4 overflows)
        raise SceneError(f"{source}: [cylinder] and [foundation] {e}") from None
    p = p.with_(mu=_friction(fd, case, source))
    if too_soft(p):  # the base would sink deeper than its radius
        field = "foundation.f_rock" if has_design else "foundation.k"
        raise SceneError(f"{source}: {field}: {too_soft(p)}")
    mo = cfg.get("motion", {})
    t0 = 0.0  # the clock of the outputs: a record's own (its first sample at its t0)
    unused = None  # a record's column the run leaves out
    notes: list[str] = []  # and a t_end past the motion's end
    if case == "fixed" and springs:  # (dropped without a word; a study's case may vary)
        notes.append(f"{', '.join(springs)} not used: a fixed base (rigid ground) has no "
                     "springs or dashpots")  # fmt: skip
    # (dt: beside a record its file's sample step, else the simulated earthquake's)
    units = record_units({k: v for k, v in mo.items() if k != "dt" or "record" in mo}, source)
    lone = [k for k in ("record_y", "record_z") if k in mo]
    if lone and "record" not in mo:  # (the simulated earthquake ran instead)
        raise SceneError(f"{source}: motion.{lone[0]}: a second record component needs the "
                         "first, motion.record (the x component)")  # fmt: skip
    if "record" in mo:
        try:
            mx, my, mz = _record_components(mo, units, source)
            t0 = float(mx.t0)
            if my is None:
                from nsdyn.ground.formats import unused_columns_note

                y_too = "give the second horizontal as [motion] record_y, or a CSV t, ax, ay[, az]"
                unused = unused_columns_note(mx if mz is None else mx.with_vertical(None), y_too)
        except SceneError:  # (a second component's, named)
            raise
        except (OSError, ValueError) as e:
            raise SceneError(f"{source}: motion.record: {e}") from None
        scenefile.refuse_keys(mo, source, "motion", [k for k in RECORD_REPLACES if k != "dt"],
                              "a key of the simulated earthquake; this scene reads "
                              "motion.record")  # fmt: skip
        if "t_end" in mo:  # an end on the record's clock, as every family's t_end
            t_end = number(source, "motion.t_end", mo["t_end"])
            try:
                mx, my, mz = (None if m is None else m.until(t_end) for m in (mx, my, mz))
            except ValueError as e:
                raise SceneError(f"{source}: motion.{e}") from None
        for key, m in (("record_y", my), ("record_z", mz)):
            if m is not None and abs(m.dt - mx.dt) > 1e-12 * mx.dt:
                raise SceneError(f"{source}: motion.{key}: sampled every {m.dt:g} s, "
                                 f"motion.record every {mx.dt:g} s; expected the components "
                                 "sampled alike (resample one)")  # fmt: skip
        try:
            dt, ag = from_motions(mx, my, mz)
        except (OSError, ValueError) as e:
            raise SceneError(f"{source}: motion.record: {e}") from None
        what = "record " + " + ".join(m.name for m in (mx, my, mz) if m is not None)
    else:
        seed = mo.get("seed", 0)
        if isinstance(seed, float) and seed.is_integer():
            seed = int(seed)  # a seed from a study's linspace
        if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
            raise SceneError(
                f"{source}: motion.seed: expected a non-negative integer, got {seed!r}"
            )
        units = mo.get("s0_units", "g2s")
        if units not in S0_UNITS:
            raise SceneError(
                f"{source}: motion.s0_units: expected one of {list(S0_UNITS)}, got {units!r}"
            )
        dur = number(source, "motion.duration", mo.get("duration", EQ_DURATION))
        dt = number(source, "motion.dt", mo.get("dt", EQ_DT))
        if not 2 * dt <= dur:
            raise SceneError(f"{source}: motion.dt: expected a step of at most half the "
                             f"duration ({dur:g} s), got {dt:g}")  # fmt: skip
        if dur / dt > MAX_OUTPUTS:
            raise SceneError(f"{source}: motion.duration: {dur / dt:.3g} samples of {dt:g} s "
                             f"exceed {MAX_OUTPUTS:.0e}; expected a shorter record or a "
                             "longer step")  # fmt: skip
        try:  # (the noise's ordinates every 0.05 s sampled at a longer step: not drawn)
            noise_step("modulated_white_noise", dur, dt)
        except ValueError as e:
            raise SceneError(f"{source}: motion.{e}") from None
        dt, ag = earthquake(seed, dur, dt, s0_units=units)
        what = f"simulated earthquake (motion.seed {seed}, {dur:g} s)"
    if "pga" in mo:
        pga = number(source, "motion.pga", mo["pga"], allow_zero=True)  # 0: free vibration
        if pga > PGA_TARGET_MAX:
            raise SceneError(f"{source}: motion.pga: expected {PGA_TARGET}, got {pga:g}")
        peak = np.abs(ag[:, :2]).max()
        ag = ag * (pga / peak) if peak > 0 else ag
    elif "record" in mo and (said := record_pga_said(float(np.hypot(*ag[:, :2].T).max()))):
        raise SceneError(f"{source}: motion.record: {mo['record']}: {said}")
    if "t_end" in mo:  # cut, or run on past the motion's end with the ground at rest (noted)
        t_end = number(source, "motion.t_end", mo["t_end"])
        from nsdyn.ground.formats import past_record_note

        last = t0 + (len(ag) - 1) * dt  # (the motion's last sample, before its padding)
        if (t_end - t0) / dt > MAX_OUTPUTS:
            n_out = (t_end - t0) / dt
            raise SceneError(f"{source}: motion.t_end: {n_out:.3g} samples of {dt:g} s exceed "
                             f"{MAX_OUTPUTS:.0e}; expected an earlier end")  # fmt: skip
        if not t_end - t0 >= dt * (1 - 1e-9):  # (it was stretched to one step unsaid)
            raise SceneError(f"{source}: motion.t_end: expected an end at least one step "
                             f"({dt:g} s) after the motion's start ({t0:g} s), "
                             f"got {t_end:g}")  # fmt: skip
        n = int(math.floor((t_end - t0) / dt + 1e-9)) + 1
        ag = np.vstack((ag[:n], np.zeros((max(0, n - len(ag)), ag.shape[1]))))
        if past := past_record_note(t0 + (n - 1) * dt, last):  # (the end the run reaches)
            notes.append(past)
        if abs(t0 + (n - 1) * dt - t_end) > 1e-9 * dt:  # (the run steps on the motion's grid)
            notes.append(f"t_end = {t_end:g} s falls between the motion's samples (every "
                         f"{dt:g} s): the run ends at {t0 + (n - 1) * dt:g} s, the sample "
                         "before it")  # fmt: skip
    so = cfg.get("solver", {})
    method = so.get("method", "dopri5")
    if method not in METHODS:
        raise SceneError(
            f"{source}: solver.method: expected one of {list(METHODS)}, got {method!r}"
        )
    opts = {"rtol": rel_tol(source, "solver.rtol", so.get("rtol", RTOL)), "t0": t0}
    stiff = too_stiff(p, (len(ag) - 1) * dt)  # (said before the long run starts)
    opts["notes"] = ([unused] if unused else []) + notes + ([stiff] if stiff else [])
    opts["what"] = what + (f", scaled to PGA {mo['pga']:g} m/s²" if "pga" in mo else "")
    opts["tilt"] = scene_tilt(mo, source)
    opts["azimuth0"] = number(source, "motion.azimuth0", mo.get("azimuth0", 0.0), positive=False)
    if p.foundation == "fixed" and any(opts["tilt"].values()):
        raise SceneError(f"{source}: motion.{next(iter(opts['tilt']))}: a fixed base cannot "
                         "start tilted")  # fmt: skip
    for key, v in opts["tilt"].items():  # (a run from past it "toppled at t = 0")
        tilt = abs(v) * (math.atan2(p.r, p.H) if key == "theta0_over_alpha" else 1.0)
        if tilt >= THETA_TOPPLE:
            raise SceneError(f"{source}: motion.{key}: a tilt of {tilt:.4g} rad is at or past "
                             f"the toppling criterion ({THETA_TOPPLE:.4g} rad, 45°), where a "
                             "run stops as toppled; expected a smaller tilt")  # fmt: skip
    z_s = cfg.get("output", {}).get("z_section")
    opts["z_s"] = None if z_s is None else number(source, "output.z_section", z_s, allow_zero=True)
    if opts["z_s"] is not None and opts["z_s"] >= 2 * p.H:
        raise SceneError(f"{source}: output.z_section: expected a height in [0, 2H), got {z_s!r}")
    return p, dt, ag, opts


def warm(p: CylinderParams, dt: float, ag: np.ndarray, opts: dict) -> float:
    """Compile (or load) the kernel a run of the built scene calls, by its first three
    samples, saying so on stderr when it compiles (:func:`nsdyn._numba_cache.first_compile`);
    the seconds it took. A run and a study (before its workers start) call it."""
    tic = time.perf_counter()
    with (
        first_compile("cylinder", COMPILE_ABOUT_S, kernels_cached(p)),
        warnings.catch_warnings(),
    ):  # (three samples' closure is no run's: not said)
        warnings.simplefilter("ignore")
        simulate(p, ag[:3], dt, rtol=opts["rtol"])
    return time.perf_counter() - tic


def warm_key(cfg: dict):
    """What of a scene selects the kernel its run compiles (the foundation's case): scenes
    with equal keys call the same compiled code."""
    return cfg.get("foundation", {}).get("case", "tensionless")


def warm_scene(cfg: dict, source: str) -> float:
    """:func:`warm` for a parsed scene."""
    p, dt, ag, opts = build(cfg, source)
    return warm(p, dt, ag, opts)


def run_scene(cfg: dict, *, source: str, out_dir: Path, figures: bool, quiet: bool) -> dict:
    """Run a cylinder scene; write histories (NPZ) and a figure (PNG); return the summary."""
    p, dt, ag, opts = build(cfg, source)
    name = cfg.get("scene", {}).get("name", Path(source).stem)
    out_dir = Path(out_dir)
    log = (lambda *a: None) if quiet else (lambda *a: print(*a, file=sys.stderr))
    log(
        f"cylinder {name}: {foundation_text(p.foundation, p.k, p.c)}; {opts['what']}, "
        f"{len(ag)} samples"
    )
    for note in opts["notes"]:
        log(f"cylinder: note: {note}")
    compile_s = warm(p, dt, ag, opts)
    tic = time.perf_counter()
    with grid_fields(source):  # the initial tilt, refused before any step
        res = simulate(p, ag, dt, rtol=opts["rtol"], azimuth0=opts["azimuth0"], **opts["tilt"])
    wall = time.perf_counter() - tic
    th_u, M_u = uplift_onset(p)
    peaks = peak_stresses(res, opts["z_s"])
    star = cfg.get("star", {}).get("case", "base")
    summary = {
        "kind": "cylinder",
        "name": name,
        "motion": opts["what"],
        "foundation": p.foundation,
        "k": p.k,
        "c": p.c,
        "t_end": float(f"{res.t[-1] + opts['t0']:.12g}"),  # (t0 + dt·n, not 20.000000000000004)
        "pga_hor": float(np.abs(ag[:, :2]).max()),
        "settlement": static_settlement(p),
        "uplift_onset_tilt": th_u,
        "uplift_onset_moment": M_u,
        "theta0_rad": float(res.tilt[0]),
        "max_tilt": float(res.tilt.max()),
        "max_uplift_ratio": float(1 - res.contact_fraction.min()),
        "max_rim_lift": float(max(res.rim_lift.max(), 0.0)),
        "max_base_shear": float(np.hypot(*res.base_shear.T).max()),
        "max_overturning": float(res.overturning.max()),
        "max_sigma_1": peaks["sigma_1"],
        "min_sigma_3": peaks["sigma_3"],
        "max_tau_max": peaks["tau_max"],
        "stress_peaks": peaks,
        "H": p.H,
        "r": p.r,
        "star": star,
        "sliding": p.sliding,
        "mu": p.mu,
        "max_slip": float(res.slip.max()),
        "final_slip": float(res.slip[-1]),
        "slip_starts": res.stats.get("slip_starts", 0),
        "dissipated_dampers": float(res.E_d[-1]),
        "dissipated_friction": float(res.E_f[-1]),
        "energy_error": res.energy_error if p.foundation != "fixed" else 0.0,
        "toppled": res.toppled_at is not None,
        "toppled_at": None if res.toppled_at is None else float(res.toppled_at + opts["t0"]),
        "alpha_rad": math.atan2(p.r, p.H),
        **res.end_tilt(),
        "outcome": "",  # set below from the fields above
        "n_steps": res.stats.get("accepted", 0),
        "wall_s": wall,
        "compile_s": compile_s,
    }
    if opts["notes"]:
        summary["notes"] = opts["notes"]
    summary["outcome"], text = outcome(summary)
    npz = out_dir / f"{file_stem(name)}.npz"
    with atomic_open(npz, "wb") as fh:
        t = res.t + opts["t0"]  # (on the record's clock)
        np.savez(fh, t=t, ag=res.ag, w=res.w, q=res.q, omega=res.omega, tilt=res.tilt,
                 tilt_dir=res.tilt_dir, contact_fraction=res.contact_fraction,
                 rim_lift=res.rim_lift, F=res.F, M=res.M, E_mech=res.E_mech, E_in=res.E_in,
                 E_d=res.E_d, u=res.u, ud=res.ud, f_base=res.f_base, E_f=res.E_f)  # fmt: skip
    summary["histories"] = str(npz)
    summary["files"] = [str(npz)]  # every file written, as the other scene kinds list them
    if figures and p.foundation != "fixed":
        from nsdyn.models.cylinder.figures import motion_figure

        png = out_dir / f"{file_stem(name)}.png"
        save_figure(motion_figure(res, title=f"{name}: {p.foundation}: {text}"), png)
        summary["figure"] = str(png)
        summary["files"].append(str(png))
    log(f"done in {wall:.3f} s ({compile_note(compile_s)})")
    return summary


def outcome(s: dict) -> tuple[str, str]:
    """(word, one line) of a run summary: ``toppled`` (the tilt passed the overturning limit),
    ``uplift`` (part of the base lost contact: the tensionless foundation's rocking),
    ``full contact``, or ``fixed base``; a sliding base adds its slip."""
    slip = f"; slid {s['max_slip']:.3g} m" if s.get("sliding") and s.get("max_slip") else ""
    if s.get("toppled"):
        return "toppled", f"TOPPLED at t = {s['toppled_at']:.3f} s{slip}"
    if s.get("foundation") == "fixed":
        return "fixed base", f"fixed base (no foundation to lift off){slip}"
    if s.get("past_tip_over_at_end"):  # (not toppled by the run's end, but falling)
        return "uplift", past_tip_over(s["final_tilt_rad"], s["alpha_rad"], "tilt") + slip
    if s.get("max_uplift_ratio", 0.0) > 0.0:
        return "uplift", (
            f"uplift: up to {s['max_uplift_ratio']:.0%} of the base lifted, peak tilt "
            f"{s['max_tilt']:.3g} rad, stayed standing{slip}"
        )
    return "full contact", f"the base stayed in full contact{slip}"


def foundation_text(case: str, k: float, c: float) -> str:
    """The foundation in words: a fixed base has no springs to name."""
    if case == "fixed":
        return "fixed base (rigid ground: no springs or dashpots)"
    return f"{case}, k = {k:.6g} N/m³, c = {c:.6g} N s/m³"


RIM_LABEL = {"bonded": "max rim rise [m]"}  # (no lift-off: the bonded base's springs in tension)


def format_summary(s: dict) -> str:
    """A short human table of a run summary, its outcome first."""
    lines = [
        f"outcome {outcome(s)[1]}",
        f"cylinder scene {s['name']} ({foundation_text(s['foundation'], s['k'], s['c'])})",
    ]
    rows = [
        ("pga (horizontal) [m/s²]", s["pga_hor"]),
        ("initial tilt [rad]", s.get("theta0_rad", 0.0)),
        ("max tilt [rad]", s["max_tilt"]),
        ("max uplift ratio", s["max_uplift_ratio"]),
        (RIM_LABEL.get(s["foundation"], "max rim lift [m]"), s["max_rim_lift"]),
        ("max base shear [N]", s["max_base_shear"]),
        ("max overturning [N m]", s["max_overturning"]),
        ("max tau_max / sigma_st", s["max_tau_max"]),
        ("energy closure error", s["energy_error"]),
    ]
    if s.get("sliding"):
        rows += [("max slip [m] (mu)", f"{s['max_slip']:.4g} ({s['mu']:g})"),
                 ("friction energy [J]", s["dissipated_friction"])]  # fmt: skip
    rows += [
        ("wall [s] (compile)", f"{s['wall_s']:.3f} ({s['compile_s']:.2f})"),
    ]
    lines += [f"  {k:<24} {v:.4g}" if isinstance(v, float) else f"  {k:<24} {v}" for k, v in rows]
    lines += [f"  {'file':<24} {f}" for f in s.get("files", [])]
    return "\n".join(lines)
