"""The NumPy/SciPy baseline: the isolated system's equations in plain NumPy, integrated by SciPy.

``scipy-radau`` is :func:`scipy.integrate.solve_ivp` (method "Radau") on a plain-NumPy
re-implementation of the numba kernel's equations (:func:`numpy_equations`: arctan law, contact
forces from the same Baumgarte-stabilised constraint solve, analytic Jacobian), checked against
the kernel to round-off in the tests. With ``x = [q, qd]``::

    a0  = -Gamma [u_h, u_v + g] - M^-1 K* q - M^-1 C* qd
    B   = M^-1 R^T - M^-1 D^T diag(mu s),   s = (2/pi) arctan(eps D qd)
    lam = -(R B)^-1 (R a0 + 2 alpha beta R qd + alpha^2 R q),   qdd = a0 + B lam

Jacobian: ``d qdd = (I - B G^-1 R)(d a0 + dB lam) - B G^-1 d b`` with ``G = R B``.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from nsdyn.bench.common import ATOL_FACTOR, LONG_RUN_S, REPEATS, BenchRun, fill_from_response

__all__ = ["numpy_equations", "run_scipy_radau"]


def numpy_equations(system, motion) -> tuple[Callable, Callable]:
    """Right-hand side ``f(t, x)`` and Jacobian ``J(t, x)`` of the isolated system in plain NumPy.

    The same equations as the numba kernel (:mod:`nsdyn.models.isolated._kernel`) for the
    arctan law with the live normal force, written again from the system matrices (module
    docstring). Ground acceleration: linear interpolation of the record, zero outside it.
    """
    iso = system.isolation
    if iso is None or iso.law != "arctan" or iso.frozen_normal:
        raise ValueError("numpy_equations: only the arctan law with live normal forces")
    R, D = system.R, system.D
    n, nc, ni = system.n, R.shape[0], D.shape[0]
    if ni != nc:
        raise ValueError("numpy_equations: expects one contact per isolator")
    mu = iso.per_isolator("mu", ni)
    eps, alpha, beta, g = iso.eps, iso.alpha, iso.beta, iso.g
    Minv = np.linalg.inv(system.M)
    MiK, MiC = Minv @ system.K, Minv @ system.C
    MiRt, MiDt = Minv @ R.T, Minv @ D.T
    Gam = system.Gamma
    t0, dt, a_h, a_v = motion.as_arrays()
    tg = t0 + dt * np.arange(a_h.size)
    eye = np.eye(n)

    def parts(t, x):
        q, qd = x[:n], x[n:]
        if tg[0] <= t <= tg[-1]:
            ug = np.array([np.interp(t, tg, a_h), np.interp(t, tg, a_v) + g])
        else:
            ug = np.array([0.0, g])
        a0 = -Gam @ ug - MiK @ q - MiC @ qd
        v = D @ qd
        B = MiRt - MiDt * (mu * (2.0 / np.pi) * np.arctan(eps * v))
        G = R @ B
        b = 2.0 * alpha * beta * (R @ qd) + alpha**2 * (R @ q)
        lam = np.linalg.solve(G, -(R @ a0 + b))
        return a0, B, G, lam, v

    def fun(t, x):
        a0, B, _, lam, _ = parts(t, x)
        return np.concatenate([x[n:], a0 + B @ lam])

    def jac(t, x):
        _, B, G, lam, v = parts(t, x)
        ds = (2.0 / np.pi) * eps / (1.0 + (eps * v) ** 2)
        BG = B @ np.linalg.inv(G)
        proj = eye - BG @ R
        J = np.zeros((2 * n, 2 * n))
        J[:n, n:] = eye
        J[n:, :n] = -proj @ MiK - alpha**2 * (BG @ R)
        J[n:, n:] = proj @ (-MiC - (MiDt * (mu * ds * lam)) @ D) - 2 * alpha * beta * (BG @ R)
        return J

    return fun, jac


class _OverBudget(Exception):
    """A SciPy run exceeded its wall-time budget."""


def run_scipy_radau(
    system,
    motion,
    rtol: float,
    *,
    repeats: int = REPEATS,
    label: str = "scipy-radau",
    atol=None,
    t_eval: np.ndarray | None = None,
    budget_s: float | None = None,
) -> BenchRun:
    """:func:`scipy.integrate.solve_ivp` (Radau) on :func:`numpy_equations`; same outputs.

    ``atol`` defaults to ``ATOL_FACTOR * rtol``; a pair (displacements, velocities) is expanded
    as nsdyn does. ``t_eval`` defaults to the record's sample times. A run still going after
    ``budget_s`` seconds of wall time is stopped (status "budget").
    """
    from scipy.integrate import Radau, solve_ivp

    from nsdyn.models.isolated.metrics import response
    from nsdyn.solve.transient import output_grid

    steps = [0]

    class CountingRadau(Radau):
        """SciPy's Radau, counting accepted steps (one call per step, no other change)."""

        def _step_impl(self):
            ok, msg = super()._step_impl()
            steps[0] += ok
            return ok, msg

    br = BenchRun(label, "scipy", "arctan", "rtol", float(rtol))
    fun, jac = numpy_equations(system, motion)
    x0, _ = system.static_equilibrium()
    t_eval = output_grid(motion) if t_eval is None else np.asarray(t_eval, dtype=float)
    a = np.asarray(rtol * ATOL_FACTOR if atol is None else atol, dtype=float)
    atol_arr = np.repeat(a, system.n) if a.shape == (2,) else a
    sol = None
    for _ in range(max(1, repeats)):
        steps[0] = 0
        t0 = time.perf_counter()
        f = fun
        if budget_s is not None:
            calls = [0]

            def f(t, x, _t0=t0, _calls=calls):
                _calls[0] += 1
                if _calls[0] % 1000 == 0 and time.perf_counter() - _t0 > budget_s:
                    raise _OverBudget
                return fun(t, x)

        try:
            s = solve_ivp(
                f,
                (t_eval[0], t_eval[-1]),
                x0,
                method=CountingRadau,
                t_eval=t_eval,
                rtol=rtol,
                atol=atol_arr,
                jac=jac,
            )
        except _OverBudget:
            br.walls.append(time.perf_counter() - t0)
            br.status = "budget"
            br.message = f"stopped after {budget_s:g} s of wall time"
            return br
        br.walls.append(time.perf_counter() - t0)
        if s.status != 0:
            br.status, br.message = "scipy_failed", s.message
            return br
        if sol is None:
            sol, br.n_steps = s, int(steps[0])
        if br.walls[-1] > LONG_RUN_S:
            break
    br.nfev = int(sol.nfev)
    X = np.ascontiguousarray(sol.y.T)
    return fill_from_response(br, sol.t, X, response(system, sol.t, X, system.params(motion)))
