"""A scene's fixed time step, checked before a run: the step itself (no longer than the run,
nor than the record's sampling step) and its count per chunk against the step budget; shared
by ``nsdyn run`` and a study's check of its tasks."""

from __future__ import annotations

import math

from nsdyn.models.scenefile import SceneError


def fixed_step(method: str, solver: dict, motion=None) -> float | None:
    """``solver.dt``, or for a fixed-step method without one ``FIXED_DT`` (the record's
    sampling step where that is shorter), as ``nsdyn run``."""
    from nsdyn._checks import default_step
    from nsdyn.solve.methods import METHODS

    if "dt" in solver or method not in METHODS or not METHODS[method].fixed_step:
        return solver.get("dt")
    return default_step(motion)


def checked_step(method: str, solver: dict, motion, t_eval, source: str) -> float | None:
    """:func:`fixed_step`, a fixed-step method's checked against the run and the record's
    sampling step (:func:`nsdyn._checks.check_fixed_step`; SceneError naming solver.dt)."""
    from nsdyn.models.scenefile import scene_step
    from nsdyn.solve.methods import METHODS

    dt = fixed_step(method, solver, motion)
    if method in METHODS and METHODS[method].fixed_step:
        scene_step(dt, motion, float(t_eval[-1] - t_eval[0]), source)
    return dt


def check_step_count(source: str, method: str, dt, t_eval, max_steps=None) -> None:
    """A fixed-step run whose steps do not fit ``max_steps`` is refused before it starts, and
    so is a step ``dt`` given to an adaptive method (which chooses its own steps).

    A run is integrated in chunks of ``CHUNK_S`` of simulated time (one solver call
    each, a checkpoint after each), and ``max_steps`` bounds the steps of one call: a fixed
    step ``dt`` needs ``ceil(chunk / dt)`` of them. Finding out after the budget is spent
    costs minutes and reads as stiffness; the cause is a step that is too small.
    """
    from nsdyn.solve.integrate import DEFAULT_MAX_STEPS
    from nsdyn.solve.methods import METHODS
    from nsdyn.solve.transient import CHUNK_S

    if method in METHODS and not METHODS[method].fixed_step and dt is not None:
        fixed = ", ".join(k for k, m in METHODS.items() if m.fixed_step)
        raise SceneError(
            f"{source}: solver.dt: the adaptive method {method!r} chooses its own steps; dt "
            f"(--dt) is the step of the fixed-step methods ({fixed}): remove dt, or set "
            "solver.method (--method) to one of them"
        )
    if method not in METHODS or not METHODS[method].fixed_step or not dt or len(t_eval) < 2:
        return
    span = float(t_eval[-1] - t_eval[0])
    if dt > span:
        raise SceneError(
            f"{source}: solver.dt: a fixed step of {dt:g} s is longer than the run ({span:g} s); "
            "use a step of the order of the record's sample step (the default is 0.005 s)"
        )
    chunk = min(span, CHUNK_S)  # (nsdyn.solve.checkpoint.chunks)
    per_chunk = math.ceil(chunk / dt * (1 - 1e-12))
    limit = int(max_steps or DEFAULT_MAX_STEPS)
    if per_chunk > limit:
        raise SceneError(
            f"{source}: solver.dt: a fixed step of {dt:g} s is too small for this run: it "
            f"takes {per_chunk:.3g} steps per {chunk:g} s chunk ({math.ceil(span / dt):.3g} over "
            f"{span:g} s), more than max_steps = {limit}; use a larger dt (the default is 0.005 s) "
            "or raise solver.max_steps (--max-steps)"
        )
