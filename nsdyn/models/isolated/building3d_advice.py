"""The model ladder of a space frame on isolators: the cheapest rung that answers, from probe runs.

Rungs, cheapest first: **fixed** (the isolators never slide: the fixed-base building by modal
time histories), **rigid** (the building as a rigid deck on its isolators), **cb** (the
Craig–Bampton building on its isolators, normal forces from the dynamics); **full** (every
mode) only confirms cb on small frames. The advice rests on measured differences, as the plane
advisor's (:mod:`nsdyn.studies.advisor`):

1. **Window**: the record from its start to the time of ``PROBE_ARIAS`` of the horizontal
   Arias intensity ``∫ (a_x² + a_y²) dt`` (at least ``PROBE_MIN_S``).
2. **cb probe**: the cb rung over the window, with at least one elastic mode: a cb model
   with no fixed-interface mode below its f_max is the rigid deck again and would always
   agree with it, so its f_max is doubled (up to ``PROBE_F_CEIL``) until it keeps one. If an
   isolator lifts off, cb (only it sees the normal forces from the dynamics). If every
   isolator sticks at every output instant (the friction law's stick,
   :func:`nsdyn.models.isolated.friction.sticks`) the base is locked and the fixed rung
   answers (the grid base clamps the feet as the fixed rung does; with ``base = "pinned"``
   the stuck isolators only pin them).
3. **rigid probe**, when the asked metrics are ones the rigid deck has (the isolators' peak
   resultant displacement, the peak resultant base shear ``|Σ_i F_i|``): the relative
   difference of each from the cb probe's; all ≤ ``tol`` → rigid, else cb. Drifts and floor
   accelerations need the elastic building: cb.

Every number is in the returned evidence (the keys the plane advisor's report reads:
``probes``, ``decision``; :func:`report` prints it).
"""

from __future__ import annotations

import time

import numpy as np

__all__ = ["ADVICE_METRICS", "advise_building", "probe_window", "report"]

DEFAULT_TOL = 0.05  # relative difference allowed on each peak metric
PROBE_ARIAS = 0.8  # the window ends when the horizontal Arias intensity reaches this fraction
PROBE_MIN_S = 5.0  # s, shortest window (unless the record is shorter)
RIGID_METRICS = ("isolator_displacement", "base_shear")  # what the rigid deck can answer
ADVICE_METRICS = (*RIGID_METRICS, "drift", "floor_acc")
PROBE_F_CEIL = 200.0  # Hz: the cb probe's f_max is doubled up to this until it keeps a mode


def elastic_probe(system, build):
    """``system`` (a cb PairSystem), or when it keeps no fixed-interface mode below its f_max
    (rigid above the base) ``build(f_max)`` at f_max doubled until one is kept (at most
    PROBE_F_CEIL): the probe that can tell the rigid deck from the elastic building."""
    fm = float(system.info["f_max"])
    while system.info.get("n_modes", 1) == 0 and fm < PROBE_F_CEIL:
        fm = min(2.0 * fm, PROBE_F_CEIL)
        system = build(fm)
    return system


def probe_window(motion) -> tuple[float, float]:
    """[t0, t1]: from the start to PROBE_ARIAS of the horizontal Arias intensity, at least
    PROBE_MIN_S (the record's end if shorter)."""
    a2 = np.cumsum(np.asarray(motion.ax, float) ** 2 + np.asarray(motion.ay, float) ** 2)
    t = motion.t
    if a2[-1] <= 0:
        return float(t[0]), float(t[-1])
    k = int(np.searchsorted(a2 / a2[-1], PROBE_ARIAS))
    t1 = max(float(t[min(k, t.size - 1)]), float(t[0]) + PROBE_MIN_S)
    return float(t[0]), float(min(t1, t[-1]))


def _rel(a: float, b: float) -> float:
    return (0.0 if a == 0 else 1.0) if b == 0 else abs(a / b - 1.0)


def advise_building(frame, bearings, motion, *, tol: float = DEFAULT_TOL, f_max: float = 5.0,
                    min_mass=1e-4, base: str = "grid", metrics=RIGID_METRICS,
                    solver: dict | None = None, system=None) -> dict:  # fmt: skip
    """{"fidelity", "f_max", "evidence"}: the cheapest rung of ``frame`` on ``bearings``
    under the record ``motion`` (a GroundMotion3) whose ``metrics`` the cb probe confirms
    within ``tol`` (module text). ``solver``: the runs' options (law, eps, eta, rtol, atol);
    ``system``: the cb PairSystem if already built (else from f_max, min_mass, base)."""
    from nsdyn.models.isolated.building3d import building_deck
    from nsdyn.models.isolated.building3d_cb import building_pairs
    from nsdyn.models.isolated.building3d_response import isolator_forces, run_building
    from nsdyn.models.isolated.deck import simulate_plane

    bad = set(metrics) - set(ADVICE_METRICS)
    if bad or not metrics:
        raise ValueError(f"metrics: expected some of {list(ADVICE_METRICS)}, got {metrics}")
    if not (isinstance(tol, int | float) and tol > 0):
        raise ValueError(f"tol: expected a positive relative difference, got {tol!r}")
    if not hasattr(motion, "dt"):
        raise ValueError("motion: the advisor probes a record (three components), not an orbit")
    kw = dict(solver or {})
    kw.pop("dt_out", None)
    t0, t1 = probe_window(motion)
    win = motion.window(t0, t1)
    ev: dict = {"tol": tol, "metrics": list(metrics), "window_s": [t0, t1], "probes": [],
                "pga_resultant_mps2": float(motion.pga_resultant)}  # fmt: skip
    w0 = time.perf_counter()
    cb = (
        system
        if system is not None
        else building_pairs(frame, bearings, f_max=f_max, min_mass=min_mass, base=base)
    )
    cb = elastic_probe(cb, lambda f: building_pairs(frame, bearings, f_max=f,
                                                    min_mass=min_mass, base=base))  # fmt: skip
    build_s = time.perf_counter() - w0
    w0 = time.perf_counter()
    r = run_building(cb, win, **kw)
    res = r.result
    stick = float(np.mean(res.sticks()))
    peaks = {"isolator_displacement": float(res.resultant(res.u).max()),
             "base_shear": float(np.hypot(*r.base_shear).max())}  # fmt: skip
    ev["cb_probe"] = {"model": cb.name, "n_dof": int(cb.n), "build_s": build_s,
                      "f_max": float(cb.info["f_max"]), "n_modes": int(cb.info["n_modes"]),
                      "wall_s": time.perf_counter() - w0, "stick_fraction": stick,
                      "peaks": peaks, "uplift": res.uplift}  # fmt: skip
    if res.uplift is not None:
        ev["decision"] = (f"cb: an isolator's normal force reached zero at t = "
                          f"{res.uplift['t_s']:.4g} s (isolator {res.uplift['isolator']}) in "
                          "the cb probe; the rigid deck's rigid-plate normal forces and the "
                          "fixed base cannot see that")  # fmt: skip
        return {"fidelity": "cb", "f_max": cb.info["f_max"], "evidence": ev}
    lifted = bool((res.flights or {}).get("lift_offs"))  # (a unilateral run's lift-offs)
    if kw.get("contact") == "unilateral" and (lifted or stick < 1.0):  # (the rigid deck
        # refused the contact with a traceback; a base stuck all along is the fixed rung's)
        why = "an isolator lifted off in the cb probe" if lifted else "the rigid deck has none"
        ev["decision"] = (f"cb: contact 'unilateral' (lift-off and landing) needs the cb "
                          f"rung's vertical: {why}")  # fmt: skip
        return {"fidelity": "cb", "f_max": cb.info["f_max"], "evidence": ev}
    if stick == 1.0:
        ev["decision"] = ("the isolators stick at every output instant of the window: the base "
                          "is locked, the fixed rung answers")  # fmt: skip
        return {"fidelity": "fixed", "f_max": None, "evidence": ev}
    if not set(metrics) <= set(RIGID_METRICS):
        ev["decision"] = (f"{sorted(set(metrics) - set(RIGID_METRICS))} need the elastic "
                          "building: the rigid deck cannot answer them; cb")  # fmt: skip
        return {"fidelity": "cb", "f_max": cb.info["f_max"], "evidence": ev}
    w0 = time.perf_counter()
    deck = building_deck(frame, bearings, g=cb.g)
    rr = simulate_plane(deck, win, **kw)
    F = isolator_forces(rr).sum(axis=1)
    rigid = {"isolator_displacement": float(rr.resultant(rr.u).max()),
             "base_shear": float(np.hypot(F[:, 0], F[:, 1]).max())}  # fmt: skip
    errs = {m: _rel(rigid[m], peaks[m]) for m in metrics}
    ok = max(errs.values()) <= tol
    ev["probes"].append({"model": "rigid", "vs": "cb", "window_s": [t0, t1], "errors": errs,
                         "ok": ok, "n_dof": 3, "wall_s": time.perf_counter() - w0,
                         "peaks": rigid})  # fmt: skip
    worst = max(errs, key=errs.get)
    if ok:
        ev["decision"] = (f"rigid: its peaks differ from the cb rung's by at most "
                          f"{errs[worst]:.2g} ({worst}) <= tol {tol:g}")  # fmt: skip
        return {"fidelity": "rigid", "f_max": None, "evidence": ev}
    ev["decision"] = (
        f"cb: the rigid deck's {worst} differs from the cb rung's by "
        f"{errs[worst]:.2g} > tol {tol:g} (the building's flexibility matters)"
    )
    return {"fidelity": "cb", "f_max": cb.info["f_max"], "evidence": ev}


def report(advice: dict) -> str:
    """Readable account of the choice and every number behind it."""
    e = advice["evidence"]
    fm = advice.get("f_max")
    label = advice["fidelity"] + (f" (f_max = {fm:g} Hz)" if fm else "")
    lines = [f"advised model: {label}  (tol = {e['tol']:g}; window {e['window_s'][0]:g}–"
             f"{e['window_s'][1]:g} s)"]  # fmt: skip
    p = e.get("cb_probe")
    if p:
        lines.append(f"  cb probe {p['model']}: stick fraction {p['stick_fraction']:.3f}, peak "
                     f"|u| {p['peaks']['isolator_displacement']:.4g} m, peak |V| "
                     f"{p['peaks']['base_shear']:.4g} N ({p['wall_s']:.2f} s run, "
                     f"{p['build_s']:.2f} s reduction)")  # fmt: skip
    for q in e.get("probes", []):
        errs = ", ".join(f"{k} {v:.2e}" for k, v in q["errors"].items())
        lines.append(f"  probe {q['model']} vs {q['vs']}: {errs} -> "
                     f"{'ok' if q['ok'] else 'above tol'}")  # fmt: skip
    lines.append(f"  {e['decision']}")
    return "\n".join(lines)
