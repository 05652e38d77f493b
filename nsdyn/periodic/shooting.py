"""Shooting for periodic orbits: the period map, Newton's method on it, Floquet multipliers.

Seed 004 §6, eqs (18)-(22). A periodic solution of period ``T = 1 / f`` solves

    H(x0, f) = phi_T(x0; f) - x0 = 0                                               (eq 19)

with ``phi_T`` the period map of a :class:`nsdyn.periodic.protocol.PeriodicModel`. Newton's
method (eqs 20-22) uses ``dH/dx0 = Phi - I`` where the monodromy ``Phi`` is the exact
derivative of the discrete period map actually integrated, with an Armijo line search on
``|W H|``, ``W`` the per-block inverse orbit amplitudes. The eigenvalues ``rho`` of ``Phi``
are the Floquet multipliers: the orbit is stable when all ``|rho| < 1``.

Stability caveat: the discrete map damps the undamped kHz boundary modes of the isolated frame
(L-stability, ``R(inf) = 0``); the exact flow would keep multipliers of modulus 1 for them.
The reported multipliers are those of the discretised map.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from nsdyn._brief import brief_repr
from nsdyn._checks import got_array, whole
from nsdyn.periodic.discretisation import N_MIN_FLOOR, N_STEPS_MAX, Discretisation, checked_disc
from nsdyn.periodic.protocol import (
    STATUS_MESSAGES,
    STATUS_OK,
    PeriodicModel,
    PeriodMap,
    check_frequency,
    check_map_args,
)

SHOOT_TOL = 1e-6  # relative shooting residual for convergence (per block, to the orbit range)
SHOOT_MAXIT = 12  # Newton iterations per shooting solve
SHOOT_STALL = 10.0  # a stalled Newton (no descent) counts as converged below this x tol (noted)
LS_HALVINGS = 6  # line-search step halvings before giving up
LS_ALPHA = 1e-4  # Armijo constant of the line search
AMP_FLOOR = 1e-12  # smallest orbit amplitude used for scaling [m, m/s] (or the model's own)
NEWTON_RCOND = 1e-10  # scaled singular values below this x the largest count as zero


def period_map(problem: PeriodicModel, x0: np.ndarray, f: float, **options) -> PeriodMap:
    """One forcing period of ``problem`` from ``x0`` (t = 0): ``problem.period_map(x0, f,
    **options)`` with the options ``n_steps``, ``disc``, ``sens``, ``store`` of
    :meth:`nsdyn.periodic.protocol.PeriodicModel.period_map`."""
    return problem.period_map(x0, check_frequency(f), **options)


def floquet_multipliers(monodromy: np.ndarray) -> np.ndarray:
    """Eigenvalues ``rho`` of the monodromy (dim, dim), sorted by decreasing modulus."""
    M = np.asarray(monodromy)
    if M.ndim != 2 or M.shape[0] != M.shape[1] or not np.all(np.isfinite(M)):
        raise ValueError(f"monodromy: expected a square matrix of finite numbers, got "
                         f"{got_array(M, (None, None))}")  # fmt: skip
    rho = np.linalg.eigvals(M)
    return rho[np.argsort(-np.abs(rho), kind="stable")]


def orbit_amplitudes(problem: PeriodicModel, X: np.ndarray) -> tuple[float, float]:
    """Largest excursion of the displacement and of the velocity block of ``X`` (samples in
    minimal coordinates) from the static state, each at least AMP_FLOOR (or the model's
    ``amp_floor``, where it has one): the scales of the
    shooting residual and closure tests."""
    m = problem.dim // 2
    dX = np.abs(X - problem.x_ref[None, :])
    floor = max(AMP_FLOOR, float(getattr(problem, "amp_floor", 0.0)))  # (a stuck orbit's)
    return max(float(dX[:, :m].max()), floor), max(float(dX[:, m:].max()), floor)


def _weights(problem: PeriodicModel, amp: tuple[float, float]) -> np.ndarray:
    """Per-entry scaling ``W`` (dim,) of a state difference: 1 / amplitude of its block."""
    m = problem.dim // 2
    return np.concatenate([np.full(m, 1.0 / amp[0]), np.full(m, 1.0 / amp[1])])


@dataclass(repr=False)
class ShootingResult:
    """Outcome of one shooting solve at frequency ``f``."""

    __repr__ = brief_repr  # arrays by shape, not in full

    f: float
    x0: np.ndarray
    converged: bool
    iterations: int
    residual: float
    monodromy: np.ndarray | None
    dxdT: np.ndarray | None
    X: np.ndarray | None
    n_steps: int
    message: str = ""
    history: list = field(default_factory=list)
    frozen: np.ndarray | None = None  # rows of the state held on this orbit (frozen_rows)

    @property
    def multipliers(self) -> np.ndarray:
        return floquet_multipliers(self.monodromy)


def frozen_rows(problem: PeriodicModel, pm: PeriodMap) -> np.ndarray | None:
    """Rows ``C`` (r, dim) of the state the model reports frozen on the orbit of ``pm`` (its
    optional ``frozen_rows`` method), or None."""
    hook = getattr(problem, "frozen_rows", None)
    if hook is None:
        return None
    C = hook(pm)
    return None if C is None or len(C) == 0 else np.atleast_2d(np.asarray(C, dtype=float))


def least_squares_step(
    J: np.ndarray,
    rhs: np.ndarray,
    scale: np.ndarray,
    C: np.ndarray | None = None,
    row_scale: np.ndarray | None = None,
    c: np.ndarray | None = None,
) -> tuple[np.ndarray, int]:
    """Minimum-norm least-squares solution ``dx`` of ``J dx = rhs`` in the scaled unknowns
    ``u = scale * dx`` and equations ``row_scale * (J dx - rhs)`` (default ``scale``),
    restricted to ``C dx = c`` (default 0; eq LS); singular values below
    ``NEWTON_RCOND`` times the largest are dropped. Returns ``(dx, rank)``, ``rank`` that of
    the (restricted) scaled matrix."""
    rows = scale if row_scale is None else row_scale
    Js = rows[:, None] * J / scale[None, :]
    b = rows * rhs
    if C is not None:
        Cs = C / scale[None, :]
        _, sv, Vt = np.linalg.svd(Cs)
        r = int(np.sum(sv > NEWTON_RCOND * max(sv.max(initial=0.0), 1e-300)))
        Nb = Vt[r:].T  # orthonormal basis of {u: Cs u = 0}
        up = np.zeros(J.shape[1])
        if c is not None:
            up = np.linalg.lstsq(Cs, c, rcond=NEWTON_RCOND)[0]
        z, _, rank, _ = np.linalg.lstsq(Js @ Nb, b - Js @ up, rcond=NEWTON_RCOND)
        u = up + Nb @ z
    else:
        u, _, rank, _ = np.linalg.lstsq(Js, b, rcond=NEWTON_RCOND)
    return u / scale, int(rank)


def newton_step(problem, pm: PeriodMap, x: np.ndarray, W: np.ndarray) -> np.ndarray:
    """The shooting step (eq LS) at ``x``: frozen rows held; then, for a model with
    ``step_limits(pm) -> (L, bound)`` (rows of the state and the largest change of each a step
    may make, a trust region on directions where the map is nearly neutral, e.g. the
    displacement of an isolator that barely slips), every row whose change exceeds its bound
    is held at the bound and the rest solved again."""
    H = pm.xT - x
    J = pm.monodromy - np.eye(x.size)
    C = frozen_rows(problem, pm)
    dx, _ = least_squares_step(J, -H, W, C)
    hook = getattr(problem, "step_limits", None)
    lim = None if hook is None else hook(pm)
    if lim is None:
        return dx
    L, bound = lim
    z = L @ dx
    over = np.abs(z) > bound
    if not np.any(over):
        return dx
    rows = [L[over]] if C is None else [C, L[over]]
    vals = [np.clip(z[over], -bound[over], bound[over])]
    if C is not None:
        vals.insert(0, np.zeros(len(C)))
    dx, _ = least_squares_step(J, -H, W, np.vstack(rows), c=np.concatenate(vals))
    return dx


def _unverified(problem, pm) -> str:
    """Why the converged orbit of ``pm`` is not one of the model
    (``problem.orbit_unverified``: the switch model's samples checked against its modes),
    or "" (consistent, or no check)."""
    check = getattr(problem, "orbit_unverified", None)
    return "" if check is None else check(pm)


def _evaluate(problem, x, f, N, disc, sens=True):
    """Period map from ``x`` with the orbit (and sensitivities, with ``sens``), its scaling
    ``W`` and the scaled residual ``max |W (phi_T(x) - x)|`` (inf when the period could not
    be integrated)."""
    pm = problem.period_map(x, f, n_steps=N, disc=disc, sens=sens, store=True)
    if pm.status != STATUS_OK:
        return pm, None, np.inf
    amp = orbit_amplitudes(problem, pm.X)
    W = _weights(problem, amp)
    H = pm.xT - x
    return pm, W, float(np.max(np.abs(W * H)))


def _check_inputs(problem, disc, n_steps, tol, max_iter) -> None:
    """The arguments of :func:`shoot` it cannot run on, named (a step count of 0 "converged"
    on x0 = 0 with every multiplier 1; a problem of another kind failed deep inside)."""
    if not (hasattr(problem, "x_ref") and hasattr(problem, "period_map")):
        raise TypeError(f"problem: expected a periodic problem (frame_problem, switch_problem, "
                        f"plane_problem, ...), got {type(problem).__name__}")  # fmt: skip
    if n_steps is not None:  # (as Discretisation's n_min: 3 steps "converged" far off)
        whole("n_steps", n_steps, N_MIN_FLOOR, f"a whole number of steps per period >= "
              f"{N_MIN_FLOOR} (fewer do not resolve it: an error of order (2 pi/N)^p)")  # fmt: skip
    if not (isinstance(tol, int | float) and 0 < tol < np.inf):
        raise ValueError(f"tol: expected a positive finite residual, got {tol!r}")
    whole("max_iter", max_iter, 0, "a whole number >= 0 (0: the start checked alone)")
    if getattr(problem, "amplitude", None) == 0:  # (its residual, scaled by an orbit of
        # round-off, read 0.46 and every point "no period-1 response")
        raise ValueError(
            "amplitude 0: no forcing, so the steady state is the static equilibrium, with "
            "no orbit to shoot; expected an amplitude > 0"
        )


def shoot(
    problem: PeriodicModel,
    f: float,
    x0: np.ndarray | None = None,
    *,
    tol: float = SHOOT_TOL,
    max_iter: int = SHOOT_MAXIT,
    disc: Discretisation | None = None,
    n_steps: int | None = None,
) -> ShootingResult:
    """Newton's method with an Armijo line search on ``H(x0) = phi_T(x0) - x0`` (eqs 19-22).

    The residual is ``max_i |H_i| / range_i`` with ``range`` the orbit's largest excursion from
    the reference state in the position and velocity blocks. ``iterations`` counts Newton
    updates (a linear system converges after one). ``f`` must be a forcing frequency from
    1e-6 to 1e4 Hz (``F_LOWEST``, ``F_HIGHEST``; ValueError otherwise), ``n_steps`` at least
    20 steps of the period (default: ``disc``'s count for it; ``disc`` the one-period
    integrator, default ``Discretisation()``). ``x0``: the start state (default the problem's
    reference state); ``tol``: the residual to reach in at most ``max_iter`` iterations.
    """
    f = check_frequency(f)
    disc = checked_disc(disc)
    _check_inputs(problem, disc, n_steps, tol, max_iter)
    N = disc.steps(1.0 / f) if n_steps is None else int(n_steps)
    if N > max(N_STEPS_MAX, disc.steps(1.0 / f)):  # (10^9 given shot for hours; the
        # discretisation's own count, refined up to 1000 times by nsdyn sweep, is its own)
        raise ValueError(f"n_steps: {N} steps of one period exceed {N_STEPS_MAX:.0e} and the "
                         f"discretisation's {disc.steps(1.0 / f)} (hours of shooting); expected "
                         "fewer")  # fmt: skip
    x = problem.x_ref.copy() if x0 is None else check_map_args(problem.x_ref, x0, None, None)
    pm, W, r = _evaluate(problem, x, f, N, disc)
    cheap = bool(getattr(problem, "cheap_sensitivities", False))
    hist = [r]
    if pm.status != STATUS_OK:
        why = f"initial period: {STATUS_MESSAGES[pm.status]}"
        return ShootingResult(f, x, False, 0, r, None, None, None, N, why, hist)
    it = 0
    msg = ""
    while r > tol:
        if it >= max_iter:
            msg = f"no convergence in {max_iter} Newton iterations (residual {r:.2e})"
            break
        H = pm.xT - x
        try:
            dx = newton_step(problem, pm, x, W)
        except np.linalg.LinAlgError:
            msg = "Newton matrix Phi - I: least-squares solve failed"
            break
        if not np.all(np.isfinite(dx)):
            msg = "Newton step not finite"
            break
        merit = float(np.linalg.norm(W * H))
        alpha = 1.0
        accepted = False
        for k in range(LS_HALVINGS + 1):
            # the full step with sensitivities (the next iteration needs them where it is
            # accepted, as it mostly is); a shortened one first without, then with them
            # where accepted: a trial without costs a fraction of one with (no monodromy),
            # unless the map's sensitivities come almost free (cheap_sensitivities)
            xt = x + alpha * dx
            sens = k == 0 or cheap
            pt, Wt, rt = _evaluate(problem, xt, f, N, disc, sens=sens)
            if pt.status == STATUS_OK:
                mt = float(np.linalg.norm(W * (pt.xT - xt)))
                if mt <= (1.0 - LS_ALPHA * alpha) * merit or rt <= tol:
                    if not sens:
                        pt, Wt, rt = _evaluate(problem, xt, f, N, disc)
                    if pt.status == STATUS_OK:
                        accepted = True
                        break
            alpha *= 0.5
        if not accepted:
            if r <= SHOOT_STALL * tol:
                # no descent left: the map's own accuracy (its steps' solves, a switch's
                # location) or a kink of it (a slip phase about to vanish) is this close
                msg = (f"converged (stalled: residual {r:.1e}, within {SHOOT_STALL:g}x the "
                       f"tolerance {tol:g}, where no Newton step lowers it: the period map's "
                       "own accuracy, or a kink of it close by)")  # fmt: skip
                C = frozen_rows(problem, pm)
                unseen = _unverified(problem, pm)
                return ShootingResult(f, x, not unseen, it, r, pm.monodromy, pm.dxdT, pm.X, N,
                                      unseen or msg, hist, C)  # fmt: skip
            msg = f"line search failed after {LS_HALVINGS} halvings (residual {r:.2e})"
            break
        x, pm, W, r = xt, pt, Wt, rt
        it += 1
        hist.append(r)
    ok = r <= tol
    msg = msg if not ok else "converged"
    unseen = _unverified(problem, pm) if ok else ""
    ok, msg = ok and not unseen, unseen or msg
    C = frozen_rows(problem, pm)
    return ShootingResult(f, x, ok, it, r, pm.monodromy, pm.dxdT, pm.X, N, msg, hist, C)
