"""The switch model's periodic kernels compiled once, before a sweep's workers start.

A sweep of the switch model (``nsdyn sweep --friction switch``) runs the exact-flow period map
of :mod:`nsdyn.periodic._kswitch` and, building each problem's tables of mode sets
(:func:`nsdyn.periodic.switch_tables.mode_tables`), the system kernel, its Jacobian and
right-hand side, called from Python. Compiled in each worker, they would take every worker's
core for as long as one compilation, with nothing on screen; :func:`warmup` compiles them
once in the calling process (announced by the command), the period map here and the system
kernels in a helper process, and the workers load them from numba's cache.
"""

from __future__ import annotations

import math

import numpy as np

from nsdyn.models.isolated import _kernel as ks
from nsdyn.periodic import _kswitch as kw
from nsdyn.periodic.switch import V_ZERO, SwitchProblem, switch_problem

# what the tables of the mode sets call from Python (nsdyn.periodic.switch_tables.mode_tables)
TABLE_KERNELS = ("evaluate", "jac", "rhs")


def _warm_problem() -> SwitchProblem:
    """The switch problem of a one-dof oscillator on one isolator: the numba types of its
    kernels' arguments are those of every model's, so it compiles what any model needs."""
    from nsdyn.models.isolated.builders import system_from_matrices
    from nsdyn.models.isolated.system import Isolation

    iso = Isolation(k_lam=0.0, c=0.0, mu=0.1, law="switch")
    system = system_from_matrices(
        [[1.0]], [[0.1]], [[4.0 * math.pi**2]], iso_dofs=[0], influence=[1.0], isolation=iso,
        weight=iso.g, levels=[[0]],
    )  # fmt: skip
    return switch_problem(system, 1.0)


def kernels_cached() -> bool:
    """True when the exact-flow period map and the system kernels its tables call are compiled
    in this process or in numba's on-disk cache (a sweep then only loads them)."""
    from nsdyn._numba_cache import dispatcher_cached

    kernels = (kw.period_map, *(getattr(ks, name) for name in TABLE_KERNELS))
    return all(dispatcher_cached(d) for d in kernels)


def helper_part() -> None:
    """A helper process's share of :func:`warmup`: the system kernel, its Jacobian and
    right-hand side, as the tables of a problem call them."""
    _warm_problem()


def warmup() -> float:
    """Compile (or load) the switch model's kernels: a first use compiles the exact-flow
    period map here while a helper process (:class:`nsdyn._numba_cache.Helper`,
    :func:`helper_part`) compiles the system kernels of the tables; then one period of the
    tiny problem loads everything. Seconds spent."""
    import time
    from contextlib import nullcontext

    from nsdyn._numba_cache import Helper, compiling, helper_enabled
    from nsdyn.solve.compile_split import _compile

    t0 = time.perf_counter()
    cold = not kernels_cached()
    helper = None
    if cold and helper_enabled():
        helper = Helper("nsdyn.periodic.switch_compile:helper_part")
    with helper or nullcontext(), compiling():
        if helper is not None:  # the period map for the types a problem's call gives it
            z3, z2, z1 = np.zeros((1, 5, 5)), np.zeros((1, 5)), np.zeros(1)
            ev = (np.zeros(1), np.zeros(1, np.int64), np.zeros(1, np.int64), np.zeros(1))
            args = (z3, z2, z3, z3, z1, np.zeros(2), 1.0, 1.0, 4, V_ZERO, True, True, *ev)
            _compile(kw.period_map, *args)
            helper.wait_for([getattr(ks, name) for name in TABLE_KERNELS])
        prob = _warm_problem()
        pm = prob.period_map(prob.x_ref, 1.0, n_steps=8, sens=True, store=True)
        if pm.status == 0:
            prob.orbit_quantities(1.0, pm.X)
    return time.perf_counter() - t0
