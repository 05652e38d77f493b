"""The checks and notes of ``nsdyn run`` on a loaded scene, before its model is built: a
method that cannot integrate the scene's law or contact (input errors), a ``t_end`` past the
record, an output grid too coarse for a harmonic excitation, an arctan law too soft to be
friction (notes on stderr); and the fixed-base run that ``--compare-fixed`` draws beside."""

from __future__ import annotations

import math
import sys

from nsdyn._checks import DOPRI5_REAL_AXIS


def note_short_record(cfg: dict, motion) -> str | None:
    """A ``t_end`` past the record's last sample ends the run there: said in one line."""
    t_req = cfg.get("motion", {}).get("t_end")
    if t_req is None or not hasattr(motion, "n") or not hasattr(motion, "dt"):
        return None
    from nsdyn.ground.formats import past_record_note

    last = motion.t0 + (motion.n - 1) * motion.dt
    if float(t_req) > last + motion.dt:  # (a window ends within one sample of its t_end)
        return past_record_note(float(t_req), last, runs_on=False)
    return None


def note_unused_components(motion) -> str | None:
    """A record file with acceleration columns the planar model leaves out (a second
    horizontal component): said in one line, naming what it takes."""
    from nsdyn.ground.formats import unused_columns_note

    return unused_columns_note(motion, PLANAR_REMEDY)


PLANAR_REMEDY = ("a planar model takes one horizontal component and the vertical; "
                 "[motion] column (read_motion's column=) chooses another; a deck or "
                 "building3d scene takes all three")  # fmt: skip


def note_coarse_output(cfg: dict, motion) -> str | None:
    """:func:`nsdyn._checks.coarse_output_note` of a scene's ``solver.dt_out`` (said before
    the run; the run's own note of it is then not said again)."""
    from nsdyn._checks import coarse_output_note

    dt_out = cfg.get("solver", {}).get("dt_out")
    return coarse_output_note(dt_out, motion, "solver.dt_out") if isinstance(
        dt_out, int | float) else None  # fmt: skip


def note_unused_cutoff(cfg: dict) -> str | None:
    """``scene.f_max`` set (away from the default scene's) for a fidelity that has no cut-off
    (rigid, full): said in one line (``--fmax`` is refused there, :func:`check_cutoff`)."""
    from nsdyn.models.isolated.scene import unused_notes

    return next((n for n in unused_notes(cfg) if n.startswith("scene.f_max")), None)


def note_unused_isolation(cfg: dict, system, law: str | None = None) -> str | None:
    """``[isolation]`` keys the built model does not read, named with why
    (:func:`nsdyn.models.isolated.scene.unused_isolation`), in one line.
    ``law``: the law the command integrates when not the scene's (uplift's arctan)."""
    from nsdyn.models.isolated.scene import unused_isolation

    if system is None:
        return None
    iso = system.isolation
    unused = [(k, why) for k, why in unused_isolation(
        cfg, iso, given_normal=getattr(system, "normal_force", None) is not None, law=law)
        if k != "isolation.law"]  # (the event method's own warning says its law)  # fmt: skip
    if iso is None:  # the fixed-base frame
        return unused[0][1] if unused else None
    return ("not used by this model: " + ", ".join(f"{k} ({why})" for k, why in unused)
            if unused else None)  # fmt: skip


def note_default_isolation(cfg: dict, system, raw: dict | None) -> str | None:
    """A frame other than the office (a file of the user's, a bundled portal) on isolators
    whose scene file ``raw`` (None: the default scene, ``--frame FILE``) gives no ``k_lam``,
    ``c`` or ``mu`` (``mu`` only under a law with friction): the default scene's, the office's
    design values, are used, sized for office-11's weight (they ran unsaid)."""
    from pathlib import Path

    from nsdyn._bundled import FRAMES
    from nsdyn.models.isolated.defaults import C_DAMPER, K_LAM, MU

    frame, iso = cfg.get("scene", {}).get("frame"), getattr(system, "isolation", None)
    office = FRAMES.find("office-11")  # (a file with its text is the office: a checkout's
    # frames/ beside a wheel's)
    if (
        iso is None
        or frame is None
        or frame == "office-11"
        or (
            office is not None
            and Path(frame).is_file()
            and Path(frame).read_bytes() == office.read_bytes()
        )
    ):
        return None
    given = (raw or {}).get("isolation") or {}
    keys = ("k_lam", "c") + ("mu",) * (iso.law != "none")  # (the law none has no friction)
    missing = [k for k in keys if k not in given]
    if not missing:
        return None
    vals = {"k_lam": f"k_lam = {K_LAM:g} N/m", "c": f"c = {C_DAMPER:g} N s/m", "mu": f"mu = {MU:g}"}
    return (f"isolation.{', '.join(missing)} not given: the seed office's design values "
            f"({', '.join(vals[k] for k in missing)}, per isolator) are used, sized for the "
            "office-11 frame; give your isolators' own in [isolation]")  # fmt: skip


def note_loose_atol(cfg: dict, system) -> str | None:
    """A velocity tolerance given above what the friction law tells apart: the switch law's
    stick band η (stick and slip decided below the tolerance), or the arctan law's turn
    (ATOL_V_EPS/eps, the bound the default tolerance keeps): accelerations read from such
    velocities are not the motion's (the event method at atol 1e-4 read a floor acceleration
    3x the converged one)."""
    from nsdyn.models.isolated.tolerances import ATOL_V_EPS

    atol = cfg.get("solver", {}).get("atol")
    iso = getattr(system, "isolation", None)
    if atol is None or iso is None or getattr(system, "n_isolators", 1) == 0:
        return None
    a_v = atol[1] if isinstance(atol, list) and len(atol) == 2 else atol
    if not isinstance(a_v, int | float):
        return None
    law = "switch" if cfg.get("solver", {}).get("method") == "event" else iso.law
    bound, what = ((iso.eta, f"the switch law's stick band eta = {iso.eta:g} m/s")
                   if law == "switch" else
                   (ATOL_V_EPS / iso.eps, f"{ATOL_V_EPS:g}/eps = {ATOL_V_EPS / iso.eps:.2g} m/s, "
                    "within the arctan law's turn") if law == "arctan" else (None, ""))  # fmt: skip
    if bound is None or a_v <= bound:
        return None
    return (f"solver.atol: a velocity tolerance of {a_v:g} m/s is above {what}: the "
            "integrator does not tell the friction's states apart, and accelerations read "
            f"there are not the motion's; set the velocities' atol to {bound:.2g} or "
            "less")  # fmt: skip


EXPLICIT_STEPS_NOTE = 1e6  # an explicit run of more steps than this is said before it starts
# the bound's steps beyond the budget at which a run is refused: the bound holds in stick, and
# slipping the steps grow (the default scene's 5 s took 0.36 of the bound's 2.1e6)
EXPLICIT_OVER = 4.0


def explicit_steps(method: str, system, span: float, quiet: bool, max_steps=None) -> list[str]:
    """An explicit method (``dopri5``) bounds its step by stability, h < DOPRI5_REAL_AXIS/ρ,
    whatever the tolerance, with ρ the fastest rate of the model: its highest frequency
    ω_max, or the arctan law's slope on an isolator's own mass, μ λ₀ (2/π) ε (D M⁻¹ Dᵀ)ᵢᵢ
    (1.5e7 1/s on the full office frame, whose isolator nodes carry 33 kg). A run of more than
    EXPLICIT_STEPS_NOTE such steps is said before it starts, with the number (the full frame's
    0.3 s took minutes, silently); printed unless ``quiet``, returned. A run whose chunk
    (:data:`nsdyn.solve.transient.CHUNK_S`) needs more such steps than ``max_steps`` (default
    the solver's) is refused before it starts: it would spend them (the full frame's 2 s ran
    for 13 minutes, deaf to Ctrl-C inside its one call) and stop on the budget."""
    from nsdyn.solve.resolution import EXPLICIT

    if method not in EXPLICIT or system.n == 0:  # (dopri5)
        return []
    import numpy as np

    from nsdyn._lazy import issparse

    K, M = system.K, system.M
    if issparse(K):
        from scipy.sparse.linalg import eigsh, splu

        w2 = float(eigsh(K.tocsc(), k=1, M=M.tocsc(), which="LM", return_eigenvectors=False)[0])
        solve = splu(M.tocsc()).solve
    else:
        from scipy.linalg import cho_factor, cho_solve, eigh

        w2 = float(eigh(K, M, eigvals_only=True, subset_by_index=[system.n - 1] * 2)[0])
        c = cho_factor(M)
        solve = lambda b: cho_solve(c, b)  # noqa: E731
    rate, what = w2**0.5, f"highest frequency {w2**0.5 / (2 * math.pi):.3g} Hz"
    iso = system.isolation
    if iso is not None and iso.law == "arctan" and system.n_isolators:
        D = system.D.toarray() if issparse(system.D) else np.asarray(system.D)
        given = getattr(system, "normal_force", None)  # (no contacts: frozen normal forces)
        lam0 = np.abs(system.static_equilibrium()[1] if given is None else given)[: D.shape[0]]
        mu = iso.per_isolator("mu", D.shape[0])
        slope = mu * lam0 * (2 / math.pi) * iso.eps * np.einsum("ij,ji->i", D, solve(D.T))
        if slope.max() > rate:
            rate, what = float(slope.max()), f"arctan friction's rate {slope.max():.2g} 1/s"
    steps = span * rate / DOPRI5_REAL_AXIS
    from nsdyn.solve.integrate import DEFAULT_MAX_STEPS
    from nsdyn.solve.transient import CHUNK_S

    limit = int(max_steps or DEFAULT_MAX_STEPS)
    if min(span, CHUNK_S) * rate / DOPRI5_REAL_AXIS > EXPLICIT_OVER * limit:
        from nsdyn.models.scenefile import SceneError

        raise SceneError(f"--method dopri5: the model's {what} bounds the explicit step to "
                         f"{DOPRI5_REAL_AXIS / rate:.2g} s, about {steps:.2g} steps for this run, "
                         f"past the budget of {limit:g} per {CHUNK_S:g} s chunk "
                         f"(solver.max_steps) even at {1 / EXPLICIT_OVER:g} of them; use "
                         "'radau' (the default) or a fixed-step method")  # fmt: skip
    chunk = min(span, CHUNK_S) * rate / DOPRI5_REAL_AXIS  # (the default scene: 2.1e6, stopped)
    if steps <= EXPLICIT_STEPS_NOTE and chunk <= limit:
        return []
    at = " (its rate at rest: fewer while the isolators slide)" * what.startswith("arctan")
    over = (f", {chunk:.2g} in a {min(span, CHUNK_S):g} s chunk, past its budget of {limit:g}: "
            "it may stop part way (--max-steps)") * (chunk > limit)  # fmt: skip
    note = (
        f"dopri5 is explicit: the model's {what} bounds its step to "
        f"{DOPRI5_REAL_AXIS / rate:.2g} s, up to about {steps:.2g} steps for this run{at}"
        f"{over}; a stiff model is for 'radau' (the default) or a fixed-step method"
    )
    if not quiet:
        print(f"nsdyn run: note: {note}", file=sys.stderr)
    return [note]


def event_law(system, quiet: bool) -> list[str]:
    """The note of method ``event`` on a model of the smooth law (the default scene's arctan):
    it integrates the switch law in its place, which the run's table did not say (the
    library warns); printed unless ``quiet``, returned."""
    iso = system.isolation
    if iso is None or iso.law == "switch":
        return []
    note = (f"method 'event' integrates the switch law (true stick) in place of the scene's "
            f"{iso.law} law (eps = {iso.eps:g} s/m); the summary's law is 'switch'")  # fmt: skip
    if not quiet:
        print(f"nsdyn run: note: {note}", file=sys.stderr)
    return [note]


def note_no_modes(system) -> str | None:
    """A Craig–Bampton model that keeps no fixed-interface mode below its cut-off: its
    structure moves as the static modes alone, so drifts and floor accelerations lose their
    dynamics (a bay added to the portal moved f1 to 5.009 Hz: drift ratios fell 1000x)."""
    info = getattr(system, "info", None) or {}
    if getattr(system, "fidelity", None) != "cb" or info.get("n_modes", 1):
        return None
    return (f"Craig-Bampton at f_max = {system.f_max:g} Hz keeps no flexible mode (the "
            "first fixed-interface mode lies above it): the structure moves quasi-statically, "
            "its drifts and floor accelerations without their dynamics; raise --fmax "
            "(scene.f_max) above the first mode (nsdyn modes FRAME)")  # fmt: skip


def note_no_column_lines(system) -> str | None:
    """A frame without regular column lines (a setback, a missing column): the run reports
    its floors' accelerations and no drift ratios (they are per column line)."""
    frame = getattr(system, "frame", None)
    if frame is None or frame.column_joints is not None:
        return None
    return (
        f"frame {frame.name!r} has no regular column lines (a column missing at some "
        "level: a setback?): no interstorey drift ratios, which are per column line; the "
        "floors' accelerations and the isolators' slips are reported"
    )


def scene_notes(cfg: dict, motion, quiet: bool, system=None, raw=None) -> list[str]:
    """Every note of a loaded scene (the functions above; ``raw``: the scene file as read,
    None for the default scene), in one line each on stderr unless ``quiet``; returned (a
    --json summary's ``notes``)."""
    chose = "column" in cfg.get("motion", {})  # (the column given: the others left by choice)
    notes = [note_short_record(cfg, motion), None if chose else note_unused_components(motion),
             note_coarse_output(cfg, motion),
             note_unused_cutoff(cfg),
             note_unused_isolation(cfg, system), note_default_isolation(cfg, system, raw),
             note_loose_atol(cfg, system),
             note_no_column_lines(system), note_no_modes(system)]  # fmt: skip
    notes = [n for n in notes if n]
    from nsdyn.cli.args import SAID

    SAID.extend(("note", n) for n in notes)  # (the library's run says some of them again)
    if not quiet:
        for n in notes:
            print(f"nsdyn run: note: {n}", file=sys.stderr)
    return notes


def record_wins(args, cfg: dict, replaces, amplitude_pga: bool = False, kind: str = "") -> None:
    """``--record`` replaces a scene's closed-form motion with its keys (``replaces``: a
    rocking pulse's, a contact sine's, a simulated earthquake's); on a harmonic orbit (a deck
    or a building), whose amplitudes are the file's, ``--record`` and ``--pga`` are refused
    naming the flag (the scene's reader named motion.record, a key the file does not have).
    ``amplitude_pga``: the family's ``motion.pga`` of a closed-form motion is its amplitude
    (a rocking pulse, a contact sine), dropped with it so that the record runs at its own
    scale (or ``--pga``'s). The scene's ``motion.t_end`` was chosen for the motion replaced:
    dropped too (said in a note), so that the record runs to its end (or ``--t-end``)."""
    from nsdyn.models.scenefile import SceneError

    mo = cfg.get("motion", {})
    if not isinstance(mo, dict):  # (the scene's reader names that)
        return
    flags = [f for f, v in (("--record", args.record), ("--pga", args.pga),
                            ("--units", getattr(args, "units", None))) if v]  # fmt: skip
    if flags and mo.get("kind") in ("orbit", "harmonic"):
        raise SceneError(f"{args.scene}: {', '.join(flags)}: this scene's motion is harmonic "
                         f"([motion] kind = {mo['kind']!r}, its amplitudes in the file); "
                         f"{flags[0]} applies to a scene driven by a record")  # fmt: skip
    if args.record:  # (a 6 s pulse scene's t_end cut a record before its strong part)
        from nsdyn.models.scenefile import record_replaces_motion

        kind = kind or ("rocking" if amplitude_pga else "")
        note = record_replaces_motion(kind, mo, replaces, str(args.scene))
        if note and getattr(args, "t_end", None) is None:  # (--t-end sets it again)
            args.notes = [*getattr(args, "notes", []), note]  # (the summary's notes)
            if not getattr(args, "json", False):
                print(f"nsdyn run: note: {note}", file=sys.stderr)


def notes_first(args, s: dict) -> None:
    """The notes said before the run (``args.notes``, e.g. :func:`record_wins`') at the head of
    the summary's ``notes``."""
    if getattr(args, "notes", None):
        s["notes"] = [*args.notes, *s.get("notes", [])]


def check_method(method: str, cfg: dict) -> None:
    """``solver.method`` must be ``auto`` or name an integrator (a SceneError naming the field
    otherwise)."""
    from nsdyn.models.scenefile import SceneError
    from nsdyn.solve.methods import METHODS, UNILATERAL_METHODS

    source = cfg.get("_source", "<scene>")
    if method != "auto" and method not in METHODS:
        raise SceneError(
            f"{source}: solver.method: unknown integrator {method!r}; expected 'auto' or one "
            f"of {sorted(METHODS)}"
        )
    if method == "genalpha-lowrank" and cfg.get("isolation", {}).get("law") == "switch":
        raise SceneError(
            f"{source}: solver.method: 'genalpha-lowrank' takes the arctan law (or none); the "
            "switch law's stick and slip events need 'event', 'radau' or 'genalpha' (or 'auto')"
        )
    unilateral = cfg.get("isolation", {}).get("contact") == "unilateral"
    if unilateral and method != "auto" and method not in UNILATERAL_METHODS:
        raise SceneError(
            f"{source}: solver.method: {method!r} cannot integrate isolation.contact = "
            f"'unilateral' (lift-off and landing); expected 'auto' or one of "
            f"{list(UNILATERAL_METHODS)}"
        )


def check_cutoff(fmax, fidelity) -> None:
    """``--fmax`` is the Craig-Bampton cut-off: refused for the fidelities without one (it
    was ignored without a word)."""
    if fmax and fidelity in ("full", "rigid"):
        from nsdyn.models.scenefile import SceneError

        raise SceneError(f"--fmax: the Craig-Bampton cut-off, and fidelity {fidelity!r} has no "
                         "cut-off (full keeps every mode, rigid none)")  # fmt: skip


def duration_text(s: dict, t_end: float) -> str:
    """The summary's duration and output step; a record's start before t = 0 is said."""
    t0 = s.get("t_start_s", 0.0)
    span = f" (t = {t0:g} to {t_end:g} s)" if t0 else ""
    return f"{t_end - t0:g} s / {s['dt_out_s']:g} s{span}"


def fixed_base_run(system, motion, t_eval, quiet: bool):
    """The fixed-base frame of ``system`` under ``motion`` on the same output grid (the
    comparison of ``--compare-fixed``); None when the model has no frame or is the fixed base."""
    from nsdyn.models.isolated.system import build_system
    from nsdyn.solve.transient import simulate

    if system.frame is None or system.fidelity == "fixed":
        if not quiet:
            print("nsdyn run: --compare-fixed: this model has no separate fixed-base frame",
                  file=sys.stderr)  # fmt: skip
        return None
    fb = build_system(system.frame, fidelity="fixed", f_max=system.f_max or 5.0)
    if not quiet:
        print(f"fixed-base comparison: {fb.name}", file=sys.stderr)
    return simulate(fb, motion, method="radau", t_eval=t_eval)


def prepare_sparse(system, quiet: bool) -> float:
    """The sparse path's kernels compiled or loaded (seconds spent, said on stderr when it
    compiles), then a full-order model's damped modes solved if not yet (a large model's
    shift-invert Lanczos: seconds, said first unless ``quiet``; it was a silence of 17 s at
    4 635 dofs before the first progress line)."""
    from nsdyn.solve.fullorder import warmup_operators

    compile_s = warmup_operators(lambda text: print(text, file=sys.stderr, flush=True))
    sparse = getattr(system, "sparse", None)
    if sparse is not None and getattr(sparse, "_U", 0) is None:
        if not quiet:
            print(f"solving the damped modes of the {sparse.n}-dof model (once)…",
                  file=sys.stderr, flush=True)  # fmt: skip
        sparse.U  # noqa: B018  (solved here, not inside the run's first chunk)
    return compile_s
