"""The building's cb and full rungs as scenes and studies run them: the path, the kernels, the run.

The cb rung, and the full rung on the dense path (:func:`full_path`: a frame of at most
:data:`SPARSE_FROM` internal dofs, those off the isolator interface, or one up to
:data:`~nsdyn.models.isolated.building3d_cb.FULL_MAX` whose law or bearings need it), are
dense pair systems (:func:`~nsdyn.models.isolated.building3d_cb.building_pairs`) run by
:func:`~nsdyn.models.isolated.building3d_response.run_building` (Radau IIA or the switch
law's kernel, adaptive). The full rung on the sparse path is the same model in the frame's
nodal coordinates on sparse operators
(:func:`~nsdyn.models.isolated.pairs_sparse.building_pairs_sparse`; damping "modal", the cb
rung's diag(0, 2ζω) on the fixed-interface modes as a low-rank term, or "stiffness", β K on
the members) run by :func:`~nsdyn.models.isolated.building3d_sparse.run_building_sparse`:
generalized-α at a fixed step h with the regularised law only.

The step (:func:`sparse_step`): ``solver.dt``, else :data:`DT_SPARSE` and never above the
record's sampling step (so that every sample of the input is stepped on). Why 5 ms:
generalized-α (ρ∞ = 0.8) is second order with a relative period error ≈ (ω h)²/12, below
1 % up to 11 Hz and 0.2 % at the cb rung's default cut-off of 5 Hz (the isolated modes lie
below 1 Hz; the office's modes that carry its mass at 0.45–4.9 Hz); the modes far above,
unresolved, are damped by the scheme's high-frequency dissipation.

Both paths give the same summary (the cb rung's keys, with ``path`` and ``path_why``) and the
same displacement field at the peak roof displacement for the deformed-shape figure: the
frame's expansion of q there, where a sparse run that kept no q (too large) repeats itself up
to that instant (the same steps, so the same state).
"""

from __future__ import annotations

import math
import threading
import time
import warnings
from contextlib import contextmanager

import numpy as np

from nsdyn._checks import NotedWarning, default_step
from nsdyn.models.scenefile import SceneError, number, scene_step

__all__ = ["DT_SPARSE", "PATHS", "SPARSE_FROM", "check_sparse_step", "dense_only", "full_path",
           "pair_kernels", "path_line", "peak_field", "run_pairs", "sparse_solver",
           "sparse_step", "warm_pairs", "warming"]  # fmt: skip

DT_SPARSE = 0.005  # s: the sparse full rung's default step (module text)
# seconds the pair kernels' first compilation takes (the first-run notice) on the AMD EPYC of
# docs/dev/first-runs.md, in a middling hour: 1.9x the fast hour's (7.7 s, the family table's
# building3d row: the office's cb rung, regularised law, the force kernel compiled in a helper
# process beside the loop), 1.3x the switch law's (its loop with located events, ~11.5 s)
PAIRS_COMPILE_ABOUT_S = 15.0


PATHS = ("auto", "dense", "sparse")  # solver.path of the full rung
# internal dofs above which "auto" takes the sparse path where the scene allows it: the size
# at which the two paths cost the same at the dense path's accuracy (Radau at rtol 1e-3:
# peaks within 1e-5; the sparse path needs dt ~0.1 ms for that), between 78 (dense 2x
# cheaper) and 134 (sparse 2x cheaper). At its default step the sparse path is 11x, 21x and
# 99x faster at 78, 134 and 258, its peaks within 1-5 % (the floor accelerations; 0.03-0.2 %
# at 1 ms): examples/bench_building3d_paths.py, docs/guide/frames-3d.md
SPARSE_FROM = 100


def dense_only(law: str, contact: str, bearing) -> str:
    """Why the full rung of a scene with ``law``, ``contact`` and ``bearing`` needs the dense
    path ("" when the sparse path runs it: the regularised law, contact "detect", a friction
    pendulum or flat slider without pressure-dependent friction)."""
    from nsdyn.models.isolated.tfp import TripleBearing

    if law != "arctan":
        return f"law {law!r} (the sparse path has the regularised law only)"
    if contact != "detect":
        return f"contact {contact!r} (the sparse path detects uplift only)"
    if isinstance(bearing, TripleBearing):
        return "a triple friction pendulum (not on the sparse path)"
    if getattr(bearing, "area", None) is not None:
        return "pressure-dependent friction (not on the sparse path)"
    return ""


def full_path(
    frame, base: str, law: str = "arctan", contact: str = "detect", bearing=None, path: str = "auto"
) -> tuple[str, str]:
    """("dense" | "sparse", why): where the full rung of ``frame`` on ``base`` runs. ``path``
    "auto": on sparse operators above :data:`SPARSE_FROM` internal dofs when the scene allows
    it (:func:`dense_only`), and always above :data:`~nsdyn.models.isolated.building3d_cb.
    FULL_MAX`; else dense (both limits read at call time). "dense" or "sparse": as asked
    (the dense path within FULL_MAX only; SceneError)."""
    from nsdyn.models.isolated import building3d_cb as cbm

    model = cbm.base_grid(frame) if base == "grid" else frame
    n_int = model.n_red - cbm._interface(model, base)[0].size
    dense = f"{n_int} internal dofs: every fixed-interface mode, dense matrices, adaptive steps"
    sparse = f"{n_int} internal dofs: sparse operators, a fixed step without error control"
    if path == "dense":
        if n_int > cbm.FULL_MAX:
            raise SceneError(f"solver.path: 'dense' takes frames of at most {cbm.FULL_MAX} "
                             f"internal dofs, this one has {n_int}; expected 'auto' or "
                             "'sparse'")  # fmt: skip
        return "dense", f"{dense} (solver.path)"
    if path == "sparse":
        return "sparse", f"{sparse} (solver.path)"
    if n_int > cbm.FULL_MAX:
        return "sparse", f"{sparse}, above the dense limit {cbm.FULL_MAX}"
    why = dense_only(law, contact, bearing)
    if why:
        return "dense", f"{dense}, within the dense limit {cbm.FULL_MAX}; {why}"
    if n_int <= SPARSE_FROM:
        return "dense", (f"{dense}, up to {SPARSE_FROM} (where it is the cheaper of the two "
                         "at its accuracy)")  # fmt: skip
    return "sparse", (f"{sparse}, above {SPARSE_FROM} (solver.path = 'dense' runs the "
                      "dense path, adaptive)")  # fmt: skip


def sparse_solver(cfg: dict, source: str, why: str, bearing=None) -> float | None:
    """``solver.dt`` (None: :func:`sparse_step`'s default) of a run on the sparse path; its law
    checked: the regularised one, whether given or not, and its ``bearing`` one the path has
    (SceneError naming the field)."""
    off = dense_only("arctan", "detect", bearing)
    if off:
        field = "bearing.area" if getattr(bearing, "area", None) is not None else "bearing.type"
        raise SceneError(f"{source}: {field}: {off}; the full rung runs on sparse operators "
                         f"here ({why}); expected a friction pendulum ('fps') or flat slider "
                         "without area, or structure.fidelity = 'cb'")  # fmt: skip
    solver = cfg.get("solver", {})
    law = solver.get("law", "arctan")
    if law != "arctan":
        raise SceneError(f"{source}: solver.law: the full rung runs on sparse operators here "
                         f"({why}) with the regularised law only; expected 'arctan', got "
                         f"{law!r}")  # fmt: skip
    contact = solver.get("contact", "detect")
    if contact != "detect":
        raise SceneError(f"{source}: solver.contact: the full rung on sparse operators ({why}) "
                         f"detects uplift only; expected 'detect', got {contact!r}")  # fmt: skip
    return number(source, "solver.dt", solver["dt"]) if "dt" in solver else None


def _small_pairs(sparse: bool):
    """The bundled portal's full rung on one friction pendulum: a system to compile on."""
    from nsdyn.models.isolated.bearings import Bearing, Friction
    from nsdyn.structure import load_frame3d

    frame, fps = load_frame3d("portal-3d"), Bearing(Friction(0.05), radius=2.0)
    if sparse:
        from nsdyn.models.isolated.pairs_sparse import building_pairs_sparse

        return building_pairs_sparse(frame, fps)
    from nsdyn.models.isolated.building3d_cb import building_pairs

    return building_pairs(frame, fps, fidelity="full")


def pair_kernels(path: str, law: str, contact: str = "detect") -> list:
    """The numba loops a run of the cb or full rung needs: its path's, law's and contact's."""
    from nsdyn.models.isolated import _kpairsparse, pairs_compile

    if path == "sparse":
        return [_kpairsparse.newton, _kpairsparse.lu_solve_csc]
    uni = contact == "unilateral"  # (located lift-offs and landings: the event loop)
    return pairs_compile.kernels(law == "switch" or uni, uni)  # the loop and its callees


def warm_pairs(path: str, law: str, system=None, contact: str = "detect") -> float:
    """Compile (or load) the pair kernels of ``path`` ("dense" | "sparse"), ``law`` and
    ``contact`` on a short run of ``system`` (default: the bundled portal's); the seconds
    spent."""
    from nsdyn._numba_cache import all_cached, first_compile

    sparse = path == "sparse"
    system = _small_pairs(sparse) if system is None or sparse else system
    still = {"f": 1.0, "ax": 0.0, "ay": 0.0}
    w0 = time.perf_counter()
    cached = all_cached(pair_kernels(path, law, contact))
    with first_compile("building3d", PAIRS_COMPILE_ABOUT_S, cached), warnings.catch_warnings():
        warnings.simplefilter("ignore", NotedWarning)  # (a warm-up: the scene's notes say them)
        if sparse:
            from nsdyn.models.isolated.pairs_sparse_run import simulate_pairs_sparse

            simulate_pairs_sparse(system, still, dt=0.01, t_end=0.04)
        else:
            from nsdyn.models.isolated.pairs import simulate_pairs

            simulate_pairs(system, still, t_end=0.04, law=law, y0=system.info["y0"],
                           contact=contact)  # fmt: skip
    return time.perf_counter() - w0


@contextmanager
def warming(path: str, law: str, contact: str = "detect"):
    """Around the build of a scene's pair system: a first compilation of the pair kernels of
    ``path``, ``law`` and ``contact`` (:func:`warm_pairs` on the bundled portal) on a thread
    of its own while the block builds the model, whose reduction (an eigenproblem of the
    frame, ~1.5 s of the office's cb rung) would otherwise come first and leave the compile
    helper's core idle.
    Nothing starts when the kernels are cached (or ``law`` is not one the kernels take: the
    run's check then says so). Yields a dict whose ``"compile_s"`` (the warm-up's seconds)
    and ``"wait_s"`` (the block's wait for it at its end) are set when the block ends. The
    block always waits for the thread, also when it raises (no compiling thread outlives the
    build); the warm-up's own error is raised when the block ended without one."""
    from nsdyn._numba_cache import all_cached

    times = {"compile_s": 0.0, "wait_s": 0.0}
    takes = ("arctan",) if path == "sparse" else ("arctan", "switch")
    contact = contact if contact == "unilateral" else "detect"  # (a bad one: the run's check)
    if law not in takes or all_cached(pair_kernels(path, law, contact)):
        yield times
        return
    box: dict = {}

    def work():
        try:
            box["s"] = warm_pairs(path, law, contact=contact)
        except BaseException as e:  # noqa: BLE001  (raised again on the building thread)
            box["e"] = e

    th = threading.Thread(target=work, name="nsdyn-warm-pairs", daemon=True)
    th.start()
    try:
        yield times
    finally:
        w0 = time.perf_counter()
        th.join()
        times.update(compile_s=box.get("s", 0.0), wait_s=time.perf_counter() - w0)
    if "e" in box:
        raise box["e"]


def sparse_step(dt, exc) -> float:
    """The sparse full rung's step: ``dt`` (``solver.dt``) or :data:`DT_SPARSE`, at most the
    record's step (module text)."""
    return float(dt) if dt is not None else default_step(exc, DT_SPARSE)


SPARSE_MAX_STEPS = 2_000_000  # steps of one sparse run, at most (as a run's max_steps)


def check_sparse_step(dt: float | None, exc, t_end, source: str) -> None:
    """A given ``solver.dt`` of the sparse rung: no longer than the record's sampling step
    (a longer one steps over samples: at 1 s the peaks came out four times the converged
    ones) nor than the run, and no more than :data:`SPARSE_MAX_STEPS` steps (SceneError)."""
    if dt is None:
        return
    dur = t_end if t_end is not None else getattr(exc, "duration", None)
    dur = float(dur) if dur is not None and math.isfinite(float(dur)) else None
    scene_step(dt, exc, dur, source, f" (default min({DT_SPARSE:g}, the record's step, a "
               "harmonic's period / 20))")  # fmt: skip
    if dur is None:
        return
    if dur / dt > SPARSE_MAX_STEPS:
        raise SceneError(
            f"{source}: solver.dt: {dt:g} s takes {dur / dt:.3g} steps over the {dur:g} s run, "
            f"more than {SPARSE_MAX_STEPS}; expected a step of at least "
            f"{dur / SPARSE_MAX_STEPS:.3g} s"
        )


def run_pairs(sysd: dict, exc, t_end, kw: dict, dt: float | None = None, progress=None):
    """Run the cb or full rung of a built scene (dense or sparse path, no files; ``dt`` the
    sparse path's step, of :func:`sparse_solver`; ``progress(t_done, t_end, wall_s)`` called
    along the run): (the
    :class:`~nsdyn.models.isolated.building3d_response.BuildingResponse3D`, its summary with
    the rung's facts, the warnings caught)."""
    system = sysd["pairs"]
    info = system.info
    sparse = info.get("path") == "sparse"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warnings.simplefilter("ignore", NotedWarning)  # (the scene's notes say them)
        w0 = time.perf_counter()
        if sparse:
            from nsdyn.models.isolated.building3d_sparse import run_building_sparse

            extra = {"dt_out": kw["dt_out"]} if "dt_out" in kw else {}
            r = run_building_sparse(system, exc, dt=sparse_step(dt, exc),
                                    t_end=t_end, eps=kw["eps"], keep_q=None, progress=progress,
                                    **extra)  # fmt: skip
        else:
            from nsdyn.models.isolated.building3d_response import run_building

            r = run_building(system, exc, t_end=t_end, progress=progress, **kw)
            if kw.get("law") == "switch":
                check_friction_limit(system, r.result)
        wall = time.perf_counter() - w0
    s = r.summary()
    s.update({"path": info.get("path", "dense"), "path_why": info.get("path_why", ""),
              "f_max_hz": info["f_max"], "base": info["base"], "mass_kg": info["m"],
              "centre_of_mass_m": [float(v) for v in info["centre"]], "wall_s": wall,
              "warnings": [str(w.message) for w in caught]})  # fmt: skip
    if sparse:
        s.update(damping=info["damping"], n_damped_modes=int(system.c.size))
        if r.result.q.shape[1]:  # (kept: the balance needs q; a lean run has none)
            s.update(r.result.energy(exc))
    else:  # simulate_pairs' loops: Radau IIA for the regularised law, else located events
        radau = kw.get("law") == "arctan" and kw.get("contact") != "unilateral"
        s["method"] = "radau" if radau else "dopri5-events"
        s.update(r.result.energy(exc))  # (its closure: the balance's check on the grid)
        dm = info["dropped_mass"]
        s.update({"n_modes": int(info["n_modes"]), "dropped_mass_max": float(max(dm)),
                  "modes_dropped": int(info["n_modes_below_f_max"] - info["n_modes"])})  # fmt: skip
    return r, s, caught


FRICTION_LIMIT_RTOL = 1e-2  # a friction force this far above μ_s k_p N is flagged
# ... where N_i is at least this share of the mean static normal force (not at an uplift,
# where the limit vanishes and the run stops: its own warning)
FRICTION_LIMIT_N_MIN = 0.1


def check_friction_limit(system, res) -> float:
    """The largest |F_i| / (μ_s k_p(N_i) N_i) of a switch-law run's outputs; a warning when it
    exceeds 1 + FRICTION_LIMIT_RTOL (a stuck isolator held beyond its stick disc, which the
    settling of stick, :mod:`._kpairsstick`, exists to prevent: Coulomb's law checked on what
    the run reports; the regularised law has no stick forces)."""
    F = np.hypot(res.friction[..., 0], res.friction[..., 1])
    N = np.asarray(res.N, dtype=float)
    lim = np.stack([b.friction.static * b.pressure_factor(N[:, i]) * N[:, i]
                    for i, b in enumerate(system.bearings)], axis=1)  # fmt: skip
    loaded = N > FRICTION_LIMIT_N_MIN * float(np.mean(N[0])) if N.size else N > 0.0
    ratio = np.where(loaded & (lim > 0.0), F / np.where(lim > 0.0, lim, 1.0), 0.0)
    worst = float(ratio.max()) if ratio.size else 0.0
    if worst > 1.0 + FRICTION_LIMIT_RTOL:
        k, i = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
        warnings.warn(f"switch law: isolator {i}'s friction reached {worst:.3g} x its limit "
                      f"mu_s N at t = {float(res.t[k]):.4g} s (a stuck isolator held beyond "
                      "its stick disc; solver.law = 'arctan' has no stick forces)",
                      RuntimeWarning, stacklevel=2)  # fmt: skip
    return worst


def peak_field(system, r, exc, s: dict, eps: float) -> dict:
    """The displacement field at the peak roof displacement (the deformed-shape figure's)."""
    info, res = system.info, r.result
    nl = info["floor_map"].shape[0]
    roof = res.outputs[:, 3 * nl - 3 : 3 * nl - 1]  # the roof's (U_x, U_y) relative to the ground
    k = int(np.argmax(np.hypot(roof[:, 0], roof[:, 1])))
    what = f"peak roof displacement ({info['fidelity']} rung, {info.get('path', 'dense')})"
    if info.get("path") != "sparse":
        q = info["cb"].T @ res.q[k]
    elif res.q.shape[1] == system.n:
        q = res.q[k]
    else:  # q not kept (too large): the run repeated to t*, deterministic, its end state kept
        from nsdyn.models.isolated.pairs_sparse_run import simulate_pairs_sparse

        span = float(r.t[k] - r.t[0])
        q = info["y0"][: system.n]
        if k:
            from nsdyn._checks import AccuracyWarning, NotedWarning

            with warnings.catch_warnings():  # (its one output, at t*, is no grid to judge;
                warnings.simplefilter("ignore", AccuracyWarning)  # its step: the run's, said)
                warnings.simplefilter("ignore", NotedWarning)
                q = simulate_pairs_sparse(system, exc, dt=s["dt_s"], t_end=span, dt_out=span,
                                          eps=eps, keep_q=True).q[-1]  # fmt: skip
    return {"t_peak": float(r.t[k]), "u": info["frame"].expand(q), "what": what}


def path_line(info: dict) -> str:
    """The path line of a pair system's run: "dense path: <why>" or "sparse path: <why>"."""
    return f"{info.get('path', 'dense')} path: {info.get('path_why', '')}"
