"""Pseudo-arclength's linear algebra for :mod:`nsdyn.periodic.continuation`: the period
derivative ``d phi_T / dT``, the unit tangent of ``H(x0, p) = 0`` in ``y = (x0, p = log f)``
and Keller's corrector on the bordered system

    [Phi - I, dH/dp; t^T W^2] dy = -[H; <t, y - y_pred>_W]

(rows ``[C, 0]`` of a held state appended where an orbit is one of a family).
"""

from __future__ import annotations

import math

import numpy as np

from nsdyn.periodic.protocol import STATUS_MESSAGES, STATUS_OK
from nsdyn.periodic.shooting import (
    ShootingResult,
    _evaluate,
    frozen_rows,
    least_squares_step,
)

ARC_MAXIT = 8  # corrector iterations per arclength step
ARC_MAX_CORRECTION = 1.0  # corrector iterates stay within this many ds of the predictor
ARC_PHASE_TOL = 1e-6  # corrector: largest |<t, y - y_pred>_W| at convergence
DT_REL = 1e-6  # relative period step of the central difference d phi_T / dT


def period_derivative(problem, pm, x: np.ndarray, f: float, N: int) -> np.ndarray:
    """``d phi_T / dT`` at ``x``: the map's own ``dxdT``, else (a map that does not supply it,
    e.g. the switch model's) central differences of the map in ``T`` with ``N`` steps and
    ``dT = DT_REL T`` (error ~ ``DT_REL^2`` plus round-off / ``DT_REL``)."""
    if pm.dxdT is not None:
        return pm.dxdT
    T = 1.0 / f
    dT = DT_REL * T
    ends = []
    for Ts in (T + dT, T - dT):
        pt = problem.period_map(x, 1.0 / Ts, n_steps=N, sens=False)
        if pt.status != STATUS_OK:
            return np.full(x.size, np.nan)
        ends.append(pt.xT)
    return (ends[0] - ends[1]) / (2.0 * dT)


def _bordered(Jx, Jp, C):
    """``[Jx, Jp]`` with the rows ``[C, 0]`` of the held state appended (None: none)."""
    if C is None:
        return np.column_stack([Jx, Jp]), 0
    return np.vstack([np.column_stack([Jx, Jp]), np.column_stack([C, np.zeros(len(C))])]), len(C)


def _tangent(Jx, Jp, W, t_prev, C=None):
    """Unit tangent of H(x, p) = 0 (scaled norm) oriented along ``t_prev``; with ``C`` (held
    rows of a family of orbits, see :func:`nsdyn.periodic.shooting.frozen_rows`) also
    ``C dx = 0``, by least squares."""
    d = Jx.shape[0]
    Wf = np.concatenate([W, [1.0]])
    top, r = _bordered(Jx, Jp, C)
    Aug = np.vstack([top, t_prev * Wf * Wf])
    rhs = np.zeros(d + r + 1)
    rhs[-1] = 1.0
    rows = np.concatenate([W, np.ones(r + 1)])
    t, _ = least_squares_step(Aug, rhs, Wf, row_scale=rows)
    t /= np.linalg.norm(Wf * t)
    if (t * Wf * Wf) @ t_prev < 0:
        t = -t
    return t


def _along_p(d: int) -> np.ndarray:
    """The tangent (0, ..., 0, 1): straight up in log f."""
    t = np.zeros(d + 1)
    t[d] = 1.0
    return t


def _corrector(problem, y_pred, tan, W, N, disc, tol, ds):
    """Newton on [H(x, p); <t, y - y_pred>_W] = 0 (Keller's pseudo-arclength).

    Iterates that leave the ball of radius ``ARC_MAX_CORRECTION * ds`` around the predictor
    are rejected (the step is then halved): a converged point far away would be on another
    part of the curve.
    """
    d = problem.dim
    Wf = np.concatenate([W, [1.0]])
    Wf2 = Wf**2
    y = y_pred.copy()
    res = None
    for it in range(ARC_MAXIT + 1):
        f = math.exp(y[d])
        pm, _, r = _evaluate(problem, y[:d], f, N, disc)
        if pm.status != STATUS_OK:
            return False, y, None, it, np.inf, STATUS_MESSAGES[pm.status]
        H = pm.xT - y[:d]
        g = float((tan * Wf2) @ (y - y_pred))
        dxdT = period_derivative(problem, pm, y[:d], f, N)
        C = frozen_rows(problem, pm)
        res = ShootingResult(f, y[:d].copy(), r <= tol, it, r, pm.monodromy, dxdT, pm.X, N)
        res.frozen = C
        if r <= tol and abs(g) <= ARC_PHASE_TOL:  # (not an orbit of the sampled map alone)
            why = getattr(problem, "orbit_unverified", lambda _: "")(pm)
            return not why, y, None if why else res, it, r, why or "converged"
        if it == ARC_MAXIT:
            break
        top, nc = _bordered(pm.monodromy - np.eye(d), dxdT * (-1.0 / f), C)
        Aug = np.vstack([top, tan * Wf2])
        rhs = -np.concatenate([H, np.zeros(nc), [g]])
        rows = np.concatenate([W, np.ones(nc + 1)])
        try:
            dy, _ = least_squares_step(Aug, rhs, Wf, row_scale=rows)
        except np.linalg.LinAlgError:
            return False, y, None, it, r, "bordered Newton matrix: least-squares solve failed"
        if not np.all(np.isfinite(dy)):
            return False, y, None, it, r, "bordered Newton step not finite"
        y = y + dy
        dist = float(np.linalg.norm(Wf * (y - y_pred)))
        if dist > ARC_MAX_CORRECTION * ds:
            return False, y, None, it + 1, r, f"corrector left the predictor by {dist / ds:.1f} ds"
    msg = f"no convergence in {ARC_MAXIT} corrector iterations (residual {r:.1e})"
    return False, y, res, ARC_MAXIT, r, msg
