"""What :func:`nsdyn.solve.transient.simulate` checks of its inputs before a run: the output
times and callbacks, the friction law a method integrates (the event method's switch law), and
a vertical excitation the model cannot feel. Each says what is wrong in one line, naming the
argument."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

FIXED_DT = 0.005  # s, the fixed-step methods' step when none is given (records of 200 Hz)


def sampling_step(motion) -> float | None:
    """The sampling step [s] of a sampled excitation (a record, a table), else None."""
    dt = getattr(motion, "dt", None)
    return float(dt) if isinstance(dt, int | float) and dt > 0 else None


def default_step(motion) -> float:
    """A fixed-step method's step when none is given: ``FIXED_DT``, or the motion's sampling
    step where that is shorter (every sample is stepped on)."""
    rec = sampling_step(motion)
    return FIXED_DT if rec is None else min(FIXED_DT, rec)


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
    if progress is not None and not callable(progress):
        raise TypeError(f"progress: expected a callable(t_done, t_end, wall_s), got {progress!r}")
    if checkpoint is not None and Path(checkpoint).is_dir():
        raise ValueError(f"checkpoint: expected a file's path, got the folder {checkpoint}")
    check_fixed_step(dt, motion, t_eval)


def check_fixed_step(dt, motion, t_eval, where: str = "dt") -> None:
    """A fixed step no longer than the run (one step over everything: no run), nor than the
    sampling step of ``motion``: a longer one passes over samples, and the peaks come out
    wrong (x_iso 1.79 m against 0.2765 at dt = 1 s on the default scene's record; a normal
    force dipping below zero at 0.2 s)."""
    span = float(t_eval[-1] - t_eval[0])
    if dt is not None and np.isfinite(dt) and dt > span:
        raise ValueError(f"{where}: a fixed step of {dt:g} s is longer than the run "
                         f"({span:g} s)")  # fmt: skip
    rec = sampling_step(motion)
    if dt is not None and rec is not None and dt > rec * (1 + 1e-9):
        raise ValueError(f"{where}: a fixed step of {dt:g} s is longer than the record's "
                         f"sampling step {rec:g} s: the steps would pass over its samples; "
                         f"expected at most {rec:g} s")  # fmt: skip


def vertical_felt(system, motion) -> None:
    """A warning when ``motion`` has a vertical component that ``system`` cannot feel: no
    vertical influence (a shear building, frozen normal forces given by ``weight``)."""
    a_ver = getattr(motion, "a_ver", None)
    has = (getattr(motion, "A_ver", 0.0) != 0.0) or (a_ver is not None and np.any(a_ver != 0))
    if has and not np.any(np.asarray(system.Gamma)[:, 1]):
        warnings.warn(
            f"motion: its vertical component is not felt by {system.name!r}, which has no "
            "vertical influence (a shear building or frozen normal forces, weight=): the run "
            "is the horizontal motion's; model the vertical dofs (build_system from a frame, "
            "or system_from_matrices with contact_rows) to feel it",
            UserWarning,
            stacklevel=3,
        )


def event_law(system, method: str) -> None:
    """Method ``event`` integrates the switch law: refused for a system without friction (law
    "none": it would add friction), said in a warning for the arctan law it replaces."""
    iso = getattr(system, "isolation", None)
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
        UserWarning,
        stacklevel=3,
    )


def integrated_law(system, method: str) -> str | None:
    """The friction law a run of ``method`` integrates: ``event`` the switch law, the others
    the system's own (None without isolators)."""
    iso = getattr(system, "isolation", None)
    if iso is None:
        return None
    return "switch" if method == "event" else iso.law
