"""What :func:`nsdyn.solve.transient.simulate` checks of its inputs before a run: the output
times and callbacks, the friction law a method integrates (the event method's switch law), and
a vertical excitation the model cannot feel. Each says what is wrong in one line, naming the
argument."""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import numpy as np

from nsdyn._checks import (  # noqa: F401 (the run's step rules, importable from here)
    FIXED_DT,
    InputWarning,
    check_fixed_step,
    default_step,
    sampling_step,
)

# a given start's contact gap or gap rate (per unit row of R) above this is not a stabilised
# run's drift (Baumgarte keeps R q near round-off) but a state off the constraint: a frame
# 5 cm in the air was pulled down over the run while its normal forces read the weight
X0_GAP = 1e-6  # m, and m/s for R qd, on rows of unit norm


def check_x0(system, x0) -> None:
    """ValueError for a given start ``x0`` that is not a state [q, qd] of ``system`` with its
    contacts closed (``R q = 0``, ``R qd = 0``; each row scaled to unit norm): the run would
    start off its constraint, whatever its contact mode (a unilateral one too)."""
    from nsdyn._checks import finite_numbers

    finite_numbers("x0", x0, "finite numbers, the state [q, qd]")
    x0 = np.asarray(x0, dtype=float).reshape(-1)
    n = system.n
    if x0.size != 2 * n:
        raise ValueError(f"x0: expected [q, qd] of length {2 * n}, got {x0.size}")
    R = getattr(system, "R", None)
    if R is None or R.shape[0] == 0:
        return
    dense = R.toarray() if hasattr(R, "toarray") else np.asarray(R)
    norm = np.maximum(np.linalg.norm(dense, axis=1), 1e-300)  # (a row's scale: its units)
    for what, v, unit in (("R q", R @ x0[:n], "m"), ("R qd", R @ x0[n:], "m/s")):
        k = int(np.argmax(np.abs(v) / norm))
        if abs(v[k]) > X0_GAP * norm[k]:
            raise ValueError(
                f"x0: its contact {k} is off the constraint ({what} = {v[k]:.3g} {unit}); "
                "expected a state with every contact closed (R q = 0, R qd = 0, as "
                "static_equilibrium() gives): a run starts with its contacts closed"
            )


def check_run_inputs(t_eval: np.ndarray, progress, checkpoint, dt=None, motion=None) -> None:
    """Given output times two or more, increasing and finite; ``progress`` callable;
    ``checkpoint`` a file's path; a fixed step ``dt`` no longer than the run, nor than the
    sampling step of ``motion`` (ValueError / TypeError naming the argument)."""
    if (
        t_eval.ndim != 1
        or t_eval.size < 2
        or not np.all(np.isfinite(t_eval))
        or np.any(np.diff(t_eval) <= 0)
    ):
        raise ValueError("t_eval: expected two or more increasing finite times [s]")
    record_span_notes(t_eval, motion, say=False)  # (times without any of the record: refused)
    if progress is not None and not callable(progress):
        raise TypeError(f"progress: expected a callable(t_done, t_end, wall_s), got {progress!r}")
    if checkpoint is not None and not isinstance(checkpoint, str | os.PathLike):
        raise TypeError(f"checkpoint: expected a file's path, got {type(checkpoint).__name__}")
    if checkpoint is not None and Path(checkpoint).is_dir():
        raise ValueError(f"checkpoint: expected a file's path, got the folder {checkpoint}")
    check_fixed_step(dt, motion, float(t_eval[-1] - t_eval[0]))


def vertical_felt(system, motion) -> None:
    """A warning when ``motion`` has a vertical component that ``system`` cannot feel: no
    vertical influence (a shear building, frozen normal forces given by ``weight``)."""
    a_ver = getattr(motion, "a_ver", None)
    has = (getattr(motion, "A_ver", 0.0) != 0.0) or (a_ver is not None and np.any(a_ver != 0))
    if has and not np.any(np.asarray(system.Gamma)[:, 1]):
        warnings.warn(
            f"motion: its vertical component is not felt by {system.name!r}, which has no "
            "vertical influence (a shear building, or normal forces frozen by a given weight): "
            "the run "
            "is the horizontal motion's; model the vertical dofs (build_system from a frame, "
            "or system_from_matrices with contact_rows) to feel it",
            InputWarning,
            stacklevel=3,
        )


def event_law(system, method: str) -> None:
    """Method ``event`` integrates the switch law: refused for a system without friction (law
    "none": it would add friction), said in a warning for the arctan law it replaces. A law's
    parameter that blurs its friction (:func:`~nsdyn.models.isolated.friction.coarse_law_note`)
    is said too (a NotedWarning: a scene's run notes it), as a deck's run says it."""
    iso = getattr(system, "isolation", None)
    note = law_note(iso, method)
    if note:
        from nsdyn._checks import NotedWarning

        warnings.warn(note, NotedWarning, stacklevel=3)
    if method != "event" or iso is None or iso.law == "switch":
        return
    if iso.law == "none":
        raise ValueError(
            "method 'event' integrates the switch friction law (true stick), and this system's "
            "isolation law is 'none' (no friction): use an adaptive method ('auto', 'radau'), "
            "or system.with_isolation(law='switch') for friction"
        )
    warnings.warn(
        f"method 'event' integrates the switch friction law (true stick), not this system's "
        f"arctan law (eps = {iso.eps:g} s/m): the run is the switch law's (summary()['law']); "
        "for the arctan law use 'auto' or 'radau', or pass system.with_isolation(law='switch')",
        InputWarning,
        stacklevel=3,
    )


def law_note(iso, method: str) -> str:
    """The note on a friction law's parameter that blurs the friction of isolation ``iso``
    (:func:`~nsdyn.models.isolated.friction.coarse_law_note`) as a run of ``method``
    integrates it, or "" (None: no isolators). The event method's stick phases are exact: its
    ``eta`` only reads the outputs."""
    law = None if iso is None else ("switch" if method == "event" else iso.law)
    if law not in ("switch", "arctan"):
        return ""
    from nsdyn.models.isolated.friction import coarse_law_note

    note = coarse_law_note(law, float(np.max(iso.eps)), float(np.max(iso.eta)), "isolation")
    if note and method == "event":
        note = note.split(": ", 1)[0] + (": the event method's stick phases do not depend on "
                                         "it, but its outputs count |v| <= eta as stuck "
                                         "(stick_fraction)")  # fmt: skip
    return note


def integrated_law(system, method: str) -> str | None:
    """The friction law a run of ``method`` integrates: ``event`` the switch law, the others
    the system's own (None without isolators)."""
    iso = getattr(system, "isolation", None)
    if iso is None:
        return None
    return "switch" if method == "event" else iso.law


def record_span_notes(t_eval: np.ndarray, motion, say: bool = True) -> list[str]:
    """:func:`nsdyn.ground.formats.record_span_notes` of a record ``motion`` or a sampled
    force (a ForceTable; none for other excitations), each said in a NotedWarning to the
    caller of :func:`~nsdyn.solve.transient.simulate` too, as a deck's run says them (a run
    past the record ran on as free motion with the note in ``res.notes`` alone); a ValueError
    for output times that do not overlap the samples at all (``say=False``: that check alone,
    before a run)."""
    n = getattr(motion, "n", None) or np.size(getattr(motion, "F", None))
    if not (hasattr(motion, "t0") and hasattr(motion, "dt") and n and n >= 2):
        return []
    from nsdyn._checks import NotedWarning
    from nsdyn.ground.formats import record_span_notes as notes

    t0, dt = float(motion.t0), float(motion.dt)
    said = notes(t_eval, t0, t0 + (n - 1) * dt, dt, force=hasattr(motion, "F"))
    for note in said * say:
        warnings.warn(note, NotedWarning, stacklevel=3)
    return said
