"""Continuation of periodic orbits in the forcing frequency f, for any periodic model.

A curve of solutions of ``H(x0, f) = phi_T(x0; f) - x0 = 0`` (``T = 1 / f``) is followed

- sequentially (seed 004 §6 takes the last solution as the next guess): at each frequency of a
  grid, Newton from the secant extrapolation in ``log f`` of the last two points (nsdyn's),
  then from the last point;
- by pseudo-arclength (Keller) in ``y = (x0, p = log f)``: predictor ``y + ds t`` along the
  unit tangent ``t`` of ``[dH/dx0, dH/dp] t = 0`` (``dH/dx0 = Phi - I``,
  ``dH/dp = -T dphi_T/dT``), corrector Newton on the bordered system

      [Phi - I, dH/dp; t^T W^2] dy = -[H; <t, y - y_pred>_W],

  which passes folds (where ``dp/ds -> 0``). ``W`` scales the state per block by the orbit
  amplitude (times ``state_weight``, AUTO's theta) and ``p`` by 1.

Where shooting fails, the point is found by the stepped sweep (plain time integration until the
Poincare map is stationary, :mod:`nsdyn.periodic.sweeps`); every point records the method that
produced it and, for the sweep, why shooting failed. Only the period map, orbit quantities and
validity notes of a :class:`nsdyn.periodic.protocol.PeriodicModel` are used, so any model
family supplying one gets continuation and bifurcation detection.
"""

from __future__ import annotations

import math
import time

import numpy as np

from nsdyn._checks import NumericalFailure, flag, number
from nsdyn.periodic.arclength import (  # (its tuning constants are arclength's own)
    _along_p,
    _corrector,
    _tangent,
    period_derivative,
)
from nsdyn.periodic.bifurcation import detect_bifurcations
from nsdyn.periodic.curve import (
    Curve,
    OrbitPoint,
    _append,
    _free,
    _point_from_shoot,
    _point_from_sweep,
    empty_curve_warning,
    failures,
    on_grid,
    problem_id,
    resumed_points,
)
from nsdyn.periodic.discretisation import (
    REFINE_FACTOR,
    Discretisation,
    after_refinement,
    checked_disc,
    refined,
)
from nsdyn.periodic.protocol import (
    PeriodicModel,
    check_frequencies,
    check_range,
)
from nsdyn.periodic.shooting import (
    SHOOT_MAXIT,
    SHOOT_TOL,
    _weights,
    orbit_amplitudes,
    shoot,
)
from nsdyn.periodic.sweeps import WARMUP_PERIODS, steady_state_sweep, warm_start

ARC_GOOD = 3  # corrector iterations at or below which the step grows
ARC_GROW, ARC_SHRINK = 1.5, 0.5  # step factors
ARC_DS_MIN = 1e-5  # smallest arclength step before falling back to the sweep
ARC_DS_MAX = 0.5  # largest step (scaled state units: relative change of the orbit)
ARC_COS_MIN = 0.7  # smallest cosine between successive tangents (branch-jump guard)
ARC_STATE_WEIGHT = 0.1  # weight of the (amplitude-scaled) state in the arclength norm
ARC_MAX_STEPS_FACTOR = 20  # at most this many x the requested points (then: sequentially)
ARC_AMP_MAX = 1e3  # an orbit's half range past this [m, rad] and ARC_AMP_GROWTH x the first's:
ARC_AMP_GROWTH = 1e3  # a branch running off to an unbounded resonance
JUMP_REL = 0.25  # a sequential step changing the orbit's start by this fraction of its size
JUMP_RATIO = 3.0  # ... and this many times the change the secant predicted: a jump candidate
F_MIN = 0.01  # default lowest forcing frequency of a curve [Hz]
F_MAX = 10.0  # default highest forcing frequency of a curve [Hz]
POINTS = 150  # default number of points of a curve


def log_frequencies(fmin: float = F_MIN, fmax: float = F_MAX, points: int = POINTS) -> np.ndarray:
    """``points`` frequencies [Hz] spaced evenly in log f from ``fmin`` to ``fmax``
    (``0 < fmin < fmax`` and ``points >= 2``, or ``fmin == fmax`` and one point: ValueError
    otherwise; one point of a range would be ``fmin`` alone, ``fmax`` dropped unsaid)."""
    lo, hi, n = check_range(fmin, fmax, points)
    if n == 1 and hi > lo:
        raise ValueError(
            f"points: expected at least 2 to span fmin = {lo:g} to fmax = {hi:g} "
            "Hz (one point is fmin alone: fmax = fmin for one frequency), got 1"
        )
    return np.geomspace(lo, hi, n)


def _solve_point(problem, f, guesses, disc, tol, max_iter, fallback, method="shooting",
                 rest=True):  # fmt: skip
    """Shooting from each guess in turn, then from the last guess carried ``sweeps.WARMUP_PERIODS``
    periods along at ``f`` (near a grazing or an event-sequence change a guess on the
    attracting orbit's side often converges where extrapolation does not); if the period
    could not even be integrated, once more with ``REFINE_FACTOR`` times more steps, unless
    the model's probe finds a contact lifting off within ``sweeps.WARMUP_PERIODS`` periods of
    the first guess, the one the retry would shoot from (as long as the warm start carries a
    guess: the model's limit, not the step's); then the sweep from the first guess."""
    why = "no initial guess"
    integration_failed = False
    tries = list(guesses)
    if guesses:  # the warm starts, made only if needed: from the last guess, then from rest
        tries += [None, "rest"][: 1 + bool(rest)]  # (``rest``: the guesses are a curve's)
    for g in tries:
        if g is None or isinstance(g, str):
            g = warm_start(problem, f, None if isinstance(g, str) else guesses[-1], disc)
        res = shoot(problem, f, g, tol=tol, max_iter=max_iter, disc=disc)
        if res.converged:
            return _point_from_shoot(problem, res, method, disc=disc), res
        why = res.message
        integration_failed |= res.monodromy is None
    if integration_failed and guesses:
        # more steps cannot help where a contact lifts off (the model's limit): its probe decides
        # first, from the retry's guess over the warm start's periods (quantities_without_orbit)
        lifts, probe = problem.quantities_without_orbit(f, guesses[0], WARMUP_PERIODS)
        if lifts.get("uplift"):
            why = f"{why}; not retried with {REFINE_FACTOR}x steps ({probe})"
        else:
            disc = refined(disc)
            res = shoot(problem, f, guesses[0], tol=tol, max_iter=max_iter, disc=disc)
            if res.converged:
                note = f"{REFINE_FACTOR}x steps per period ({why})"
                return _point_from_shoot(problem, res, method, note, disc), res
            why = f"{why}; with {REFINE_FACTOR}x steps: {after_refinement(problem, res.message)}"
    if not fallback:
        return None, why  # (the reason, for the curve's skipped frequencies)
    sw = steady_state_sweep(problem, f, guesses[0] if guesses else None, disc=disc)
    if guesses and not sw.steady and sw.periods_done <= WARMUP_PERIODS:
        # the previous orbit can seed a transient leaving the model (a contact lifting off in
        # the first period) where the steady state stays in it: once more from rest
        calm = steady_state_sweep(problem, f, None, disc=disc)
        if calm.steady:
            why = f"{why}; the sweep from the previous orbit stopped ({sw.message}), from rest"
            sw = calm
    return _point_from_sweep(problem, sw, why, disc), None


def _options(disc, progress, fallback, keep_orbits) -> Discretisation:
    """The discretisation (the default for None), or TypeError naming the argument: a
    discretisation or progress callback of another kind failed deep inside (``'str' object
    has no attribute 'steps'``), a text flag ("no") was true."""
    disc = checked_disc(disc)
    if progress is not None and not callable(progress):
        raise TypeError(f"progress: expected a callable (pt, count, total), got "
                        f"{type(progress).__name__}")  # fmt: skip
    flag("fallback", fallback)
    flag("keep_orbits", keep_orbits)
    return disc


def _jump(problem, pts: list, disc, tol: float, max_iter: int) -> dict | None:
    """A jump between two branches at the last step of a sequential curve, or None.

    A candidate is a step whose orbit changed by more than ``JUMP_REL`` of its size and
    ``JUMP_RATIO`` times the secant's prediction (a sharp peak on a coarse grid is one too);
    it is confirmed by shooting at the previous frequency from the new orbit: a converged
    orbit there distinct from the one the curve followed means two periodic orbits coexist
    at that frequency, so the curve left its branch (at a fold, which a sequential
    continuation cannot pass) for another."""
    p, a, b = pts[-3:]
    d = float(np.linalg.norm(b.x0 - a.x0))
    size = max(float(np.linalg.norm(a.x0)), float(np.linalg.norm(b.x0)))
    r = math.log(b.f / a.f) / math.log(a.f / p.f)
    predicted = r * float(np.linalg.norm(a.x0 - p.x0))
    if not (d > JUMP_REL * size and d > JUMP_RATIO * predicted):
        return None
    res = shoot(problem, a.f, b.x0, tol=tol, max_iter=max_iter, disc=disc)
    if not (res.converged and np.linalg.norm(res.x0 - a.x0) > 0.5 * d):
        return None  # one orbit at a.f: a steep part of one branch
    return {"f_a": float(a.f), "f_b": float(b.f), "change": d / size}


def continue_sequential(
    problem: PeriodicModel,
    freqs,
    x0: np.ndarray | None = None,
    *,
    disc: Discretisation | None = None,
    tol: float = SHOOT_TOL,
    max_iter: int = SHOOT_MAXIT,
    fallback: bool = True,
    progress=None,
    start: list[OrbitPoint] | None = None,
    keep_orbits: bool = False,
) -> Curve:
    """Sequential continuation (seed 004 §6): shoot at each frequency from the last solutions.

    The guess is the secant extrapolation (in log f) of the last two points (not along the
    rows the last orbit holds, see :func:`nsdyn.periodic.shooting.frozen_rows`), then the last
    point itself; if both fail, the stepped sweep produces the point (``fallback``). A step
    that leaves the branch for another (past a fold) is listed in ``info["jumps"]``
    (``f_a``, ``f_b``, ``change``: see :func:`_jump`).
    ``start`` resumes a curve (points already computed are kept, frequencies up to the last
    one skipped). Only the last point keeps its orbit ``X`` unless ``keep_orbits``.
    ``freqs``: the frequencies [Hz] in order; ``x0``: the first guess (default the problem's
    reference state); ``disc``, ``tol``, ``max_iter``: each point's :func:`~nsdyn.periodic.
    shooting.shoot`'s; ``progress(point, count, total)`` is called after each point.
    """
    disc = _options(disc, progress, fallback, keep_orbits)
    given = freqs  # (a generator: float()'s message; text "0.3": read as 0.3 in the refusal)
    try:
        freqs = np.asarray(freqs, dtype=float)
    except (TypeError, ValueError):
        freqs = np.array([np.nan])
    ok = freqs.ndim == 1 and freqs.size and np.all(np.isfinite(freqs) & (freqs > 0))
    if isinstance(given, str) or not ok or np.any(np.diff(freqs) <= 0):
        raise ValueError(f"freqs: expected increasing finite frequencies > 0 [Hz], got "
                         f"{given!r}"[:200])  # fmt: skip
    check_frequencies(freqs)
    pts: list[OrbitPoint] = resumed_points(problem, start, float(freqs[0]), float(freqs[-1]), disc)
    t0 = time.perf_counter()
    held = None
    skipped, skipped_why = [], []  # frequencies without a point (no fallback) and why
    jumps = []  # steps between two branches (see _jump)
    n_start = len(pts)
    for f in freqs:
        if pts and f <= pts[-1].f * (1 + 1e-12):
            continue
        guesses = []
        if len(pts) >= 2:
            a, b = pts[-2], pts[-1]
            r = (math.log(f) - math.log(b.f)) / (math.log(b.f) - math.log(a.f))
            guesses.append(b.x0 + r * _free(b.x0 - a.x0, held))
        guesses.append(pts[-1].x0 if pts else warm_start(problem, f, x0, disc))
        tp = time.perf_counter()
        pt, res = _solve_point(
            problem, f, guesses, disc, tol, max_iter, fallback, rest=bool(pts) or x0 is not None
        )  # fmt: skip  (x0: not rest)
        if pt is None:
            skipped.append(float(f))
            skipped_why.append(res)  # (without a point: its reason)
            continue
        held = None if res is None else res.frozen
        pt.quantities["wall_s"] = time.perf_counter() - tp
        _append(pts, pt, keep_orbits, progress, len(freqs))
        if len(pts) >= max(3, n_start + 1):
            tj = time.perf_counter()
            jump = _jump(problem, pts, disc, tol, max_iter)
            jumps += [jump] if jump else []
            pt.quantities["wall_s"] += time.perf_counter() - tj  # (its check is its cost)
    info = {"continuation": "sequential", "wall_s": time.perf_counter() - t0,
            "skipped_hz": skipped, "skipped_why": skipped_why, "jumps": jumps,
            "problem": problem_id(problem)}  # fmt: skip
    return Curve(problem.amplitude, pts, detect_bifurcations(pts), info)


def continue_range(
    problem: PeriodicModel,
    *,
    fmin: float = F_MIN,
    fmax: float = F_MAX,
    points: int = POINTS,
    continuation: str = "sequential",
    **options,
) -> Curve:
    """The periodic orbits of ``problem`` from ``fmin`` to ``fmax`` [Hz].

    ``continuation``: "sequential" (seed: ``points`` log-spaced frequencies, previous solution
    as the guess) or "arclength" (pseudo-arclength in (x0, log f), passes folds, at least
    ``points`` points). ``options`` go to :func:`continue_sequential` /
    :func:`continue_arclength` (``disc``, ``tol``, ``max_iter``, ``fallback``, ``progress``,
    ``start``, ...). The curve keeps its problem's :func:`problem_id` (``info["problem"]``)
    and where it has no steady state, why (``info["failures"]``, :func:`failures`).
    """
    from nsdyn._checks import keywords_of

    target = continue_sequential if continuation == "sequential" else continue_arclength
    keywords_of(target, options, skip=("problem", "freqs", "fmin", "fmax"),
                also=("fmin", "fmax", "points"))  # fmt: skip
    if continuation == "sequential":
        freqs = log_frequencies(fmin, fmax, points)
        on_grid(options.get("start"), freqs)
        curve = continue_sequential(problem, freqs, **options)
    elif continuation == "arclength":
        curve = continue_arclength(problem, fmin, fmax, points=points, **options)
    else:
        raise ValueError(f"continuation: expected 'sequential' or 'arclength', got "
                         f"{continuation!r}")  # fmt: skip
    asked = dict(options, fmin=fmin, fmax=fmax, points=points, continuation=continuation)
    curve.info["failures"] = failures(curve, asked)  # (the deck's alone had them)
    empty_curve_warning(curve, fmin, fmax)
    return curve


def _half_range(X: np.ndarray, d: int) -> float:
    """An orbit's size for the runaway test: the largest half range of its displacements (the
    first half of the ``d`` states), not an offset (a flat slider's is no size)."""
    return float(np.ptp(X[:, : d // 2], axis=0).max()) / 2


def continue_arclength(
    problem: PeriodicModel,
    fmin: float,
    fmax: float,
    *,
    points: int = POINTS,
    x0: np.ndarray | None = None,
    disc: Discretisation | None = None,
    tol: float = SHOOT_TOL,
    max_iter: int = SHOOT_MAXIT,
    fallback: bool = True,
    progress=None,
    start: list[OrbitPoint] | None = None,
    state_weight: float = ARC_STATE_WEIGHT,
    keep_orbits: bool = False,
) -> Curve:
    """Pseudo-arclength continuation in ``(x0, p = log f)`` from ``fmin`` to ``fmax``.

    Unknowns are scaled per block by the orbit amplitude at the last point and the state by
    ``state_weight`` (AUTO's theta), so the step ``ds`` measures a weighted relative change of
    the orbit plus a change of log f: a small weight lets the steps follow log f where the
    curve is monotone in f (the isolated frame's orbits vary a lot with f) while folds, where
    dp/ds -> 0, are still passed. The step in log f is
    capped at ``log(fmax/fmin) / (points - 1)`` (at least ``points`` points on the curve);
    it grows after easy corrector solves and halves after failures; below ``ARC_DS_MIN`` (or a
    thousandth of the cap, in a band narrower than that) the next frequency is taken by the
    stepped sweep and continuation restarts from it. Without ``fallback`` the rest of the band
    is continued sequentially on the same frequency step (frequencies without an orbit
    skipped, ``info["skipped_hz"]``), the place and reason kept in ``info["arclength_stop"]``;
    so is it, with the fallback where given, past ``ARC_MAX_STEPS_FACTOR * points`` steps, where
    the branch turns back below fmin by half the band (from the highest frequency reached) and
    where an orbit's half range passes ``ARC_AMP_MAX`` and ``ARC_AMP_GROWTH`` x the first's
    (a branch running off to an unbounded resonance; that point's note says so).
    ``x0``, ``disc``, ``tol``, ``max_iter``, ``progress``, ``start`` and ``keep_orbits`` are
    :func:`continue_sequential`'s.
    """
    disc = _options(disc, progress, fallback, keep_orbits)
    fmin, fmax, points = check_range(fmin, fmax, points)
    number("state_weight", state_weight, "a positive finite weight", lambda v: v > 0)
    pmin, pmax = math.log(fmin), math.log(fmax)
    dp_max = (pmax - pmin) / max(points - 1, 1)
    t0 = time.perf_counter()
    pts: list[OrbitPoint] = resumed_points(problem, start, fmin, fmax, disc)
    d = problem.dim

    def add(pt, tp=None):
        if tp is not None:
            pt.quantities["wall_s"] = time.perf_counter() - tp
        _append(pts, pt, keep_orbits, progress, points)

    if not pts:
        xg = warm_start(problem, fmin, x0, disc)
        pt, res = _solve_point(
            problem, fmin, [xg], disc, tol, max_iter, fallback, "arclength", rest=x0 is not None
        )  # fmt: skip  (xg: a warm start already)
        if pt is None:
            raise NumericalFailure(f"no periodic solution found at f = {fmin:g} Hz")
        pt.s = 0.0
        add(pt)
    s_acc = pts[-1].s if np.isfinite(pts[-1].s) else 0.0
    t_prev = _along_p(d)
    ds = dp_max
    max_steps = ARC_MAX_STEPS_FACTOR * points
    steps = 0
    size0 = math.nan  # (the first orbit's size, a resumed curve's too: not its last one's)
    first = next((p for p in pts if p.converged), None)
    if first is not None:
        X0 = first.X if first.X is not None else problem.period_map(
            first.x0, first.f, disc=disc, sens=False, store=True).X  # fmt: skip
        size0 = math.nan if X0 is None else _half_range(X0, d)
    need_restart = True  # tangent must be computed from scratch at the last point
    J_last = None
    info = {"continuation": "arclength", "skipped_hz": [], "problem": problem_id(problem)}

    def sequential_rest(f_stop: float, why: str, fb: bool = False) -> list:
        """The band above f_stop on the frequency step dp_max, sequentially (``fb``: with the
        stepped-sweep fallback)."""
        info["arclength_stop"] = {"f_hz": f_stop, "reason": why}
        p0 = math.log(f_stop)
        rest = np.append(np.exp(np.arange(p0 + dp_max, pmax - 0.5 * dp_max, dp_max)), fmax)
        seq = continue_sequential(problem, rest, disc=disc, tol=tol, max_iter=max_iter,
                                  fallback=fb, progress=progress, start=pts,
                                  keep_orbits=keep_orbits)  # fmt: skip
        info["skipped_hz"], info["skipped_why"] = seq.info["skipped_hz"], seq.info["skipped_why"]
        info["jumps"] = seq.info["jumps"]  # (the sequential rest's steps between branches)
        return list(seq.points)

    while steps < max_steps:
        steps += 1
        last = pts[-1]
        p_last = math.log(last.f)
        if p_last >= pmax - 1e-12:
            break
        if p_last < pmin - 0.5 * (pmax - pmin):  # (it ended short of fmax without a word)
            f_top = max(p.f for p in pts)
            pts = sequential_rest(f_top, f"the branch turned back below fmin, to {last.f:.4g} "
                                  "Hz", fallback)  # fmt: skip
            break
        if last.X is None:  # resumed point: its orbit for the scaling
            last.X = problem.period_map(last.x0, last.f, disc=disc, sens=False, store=True).X
        amp = orbit_amplitudes(problem, last.X)
        size = _half_range(last.X, d)
        size0 = size if not math.isfinite(size0) else size0  # (the first's)
        if size > ARC_AMP_MAX and size > ARC_AMP_GROWTH * size0:  # (it ran on to 1e89 m)
            runaway = "on a branch running off to an unbounded resonance"
            if runaway not in (last.note or ""):  # (a resumed curve's last point: said once)
                last.note = "; ".join(n for n in (last.note, runaway) if n)
            pts = sequential_rest(
                last.f,
                f"the orbit's half range passed {ARC_AMP_MAX:g} m: a "
                "branch running off to an unbounded resonance",
                fallback,
            )
            break
        W = state_weight * _weights(problem, amp)
        Wf = np.concatenate([W, [1.0]])
        N = disc.steps(1.0 / last.f)
        if need_restart or J_last is None:
            res0 = shoot(problem, last.f, last.x0, tol=tol, max_iter=max_iter, disc=disc, n_steps=N)
            if not res0.converged:
                # continue from a sweep point: step on with the sweep
                f_next = min(math.exp(p_last + dp_max), fmax)
                pt, _ = _solve_point(
                    problem, f_next, [last.x0], disc, tol, max_iter, fallback, "arclength"
                )
                if pt is None:
                    pts = sequential_rest(last.f, f"no orbit at the restart: {res0.message}")
                    break
                pt.s = s_acc = s_acc + abs(math.log(f_next) - p_last)
                add(pt)
                continue
            dxdT = period_derivative(problem, res0, res0.x0, last.f, N)
            J_last = (res0.monodromy - np.eye(d), dxdT * (-1.0 / last.f), res0.x0, res0.frozen)
            need_restart = False
        Jx, Jp, xl, C_last = J_last
        tan = _tangent(Jx, Jp, W, t_prev, C_last)
        last.dlogf_ds = float(tan[d])
        # step size: cap the change of log f
        ds_cap = dp_max / max(abs(tan[d]), 1e-12)
        ds = min(ds, ds_cap, ARC_DS_MAX)
        ds_min = min(ARC_DS_MIN, 1e-3 * ds_cap)  # (a band narrower than ARC_DS_MIN: its own)
        tp = time.perf_counter()
        ok, msg, its = False, "", 0
        y0 = np.concatenate([xl, [p_last]])
        while ds >= ds_min:
            y_pred = y0 + ds * tan
            if y_pred[d] > pmax and tan[d] > 0:
                # last step: land on fmax exactly (natural-parameter corrector there)
                y_end = y0 + ((pmax - p_last) / tan[d]) * tan
                res = shoot(
                    problem, fmax, y_end[:d], tol=tol, max_iter=max_iter, disc=disc, n_steps=N
                )
                if res.converged:
                    pt = _point_from_shoot(problem, res, "arclength", disc=disc)
                    y = np.concatenate([res.x0, [pmax]])
                    s_acc += float(np.linalg.norm(Wf * (y - y0)))
                    pt.s = s_acc
                    add(pt, tp)
                    ok = True
                    break
                msg = res.message
                ds *= ARC_SHRINK
                continue
            ok, y, res, its, rr, msg = _corrector(problem, y_pred, tan, W, N, disc, tol, ds)
            if ok:
                Jx_n = res.monodromy - np.eye(d)
                Jp_n = res.dxdT * (-1.0 / math.exp(y[d]))
                tan_new = _tangent(Jx_n, Jp_n, W, tan, res.frozen)
                cosang = float((tan_new * Wf * Wf) @ tan)
                if cosang >= ARC_COS_MIN:
                    break
                ok = False
                turn = math.degrees(math.acos(max(-1.0, min(1.0, cosang))))
                msg = f"tangent turned by {turn:.0f} deg"
            ds *= ARC_SHRINK
        if ok and pts[-1].f >= fmax * (1 - 1e-12):
            break
        if not ok:
            # fallback: stepped sweep to the next frequency, then restart
            f_next = min(math.exp(p_last + dp_max), fmax)
            why = f"arclength corrector failed down to ds = {ds_min:.1e}: {msg}"
            if not fallback:  # no sweep: the rest of the band sequentially, gaps skipped
                pts = sequential_rest(last.f, why)
                break
            sw = steady_state_sweep(problem, f_next, last.x0, disc=disc)
            pt = _point_from_sweep(problem, sw, why, disc)
            pt.s = s_acc = s_acc + abs(math.log(f_next) - p_last)
            add(pt, tp)
            need_restart = True
            t_prev = _along_p(d)
            ds = dp_max
            continue
        pt = _point_from_shoot(problem, res, "arclength", disc=disc)
        pt.f = math.exp(y[d])
        s_acc += float(np.linalg.norm(Wf * (y - y0)))
        pt.s = s_acc
        pt.dlogf_ds = float(tan_new[d])
        add(pt, tp)
        J_last = (Jx_n, Jp_n, y[:d].copy(), res.frozen)
        t_prev = tan_new
        ds = ds * ARC_GROW if its <= ARC_GOOD else ds
    else:  # the step cap (a curve ending short of fmax was a finished one; a rerun went on)
        if pts[-1].f < fmax * (1 - 1e-12):  # (from the highest frequency: a turned branch's)
            pts = sequential_rest(max(p.f for p in pts), f"{max_steps} steps used", fallback)
    info.update(wall_s=time.perf_counter() - t0, steps=steps)
    return Curve(problem.amplitude, pts, detect_bifurcations(pts), info)
