"""The deck's force kernel by address, and the deck's first compilation shared by two processes.

Every kernel of the deck's time loops that evaluates the deck (the settling and switching of
the switch law, the event functions, the outputs, the right-hand side of both loops) calls the
force kernel :func:`nsdyn.models.isolated._kplane.evaluate` (the normal forces, the friction
and restoring forces, the 3 × 3 or 5 × 5 solve for q̈). Linked, numba would copy it into each
of them and LLVM would optimise and translate every copy again; called by its address
(:func:`nsdyn._kaddress.tcall`, row ``"deck.evaluate"`` of the process-wide table) it compiles
once, on its own. :func:`callees` declares it for the argument types the loops give it,
:func:`ready` puts its address in the table before a loop runs.

The switch law's settling and its mode switch at an event are called by address too (rows
``"deck.settle"``, ``"deck.switch"``). A first run compiles in two processes (numba compiles
on one thread per process): a helper (:class:`nsdyn._numba_cache.Helper`) compiles the force
kernel, the settling and the mode switch (:func:`helper_part`) while this process compiles
the time loop from the run's own argument types (:func:`warm_loop`), then loads the helper's
kernels from numba's on-disk cache. What the helper does not deliver this process compiles
itself: the kernels are the same either way.
"""

from __future__ import annotations

import functools


def tiny_args() -> tuple:
    """The arguments of the force kernel, the settling and the mode switch as the loops pass
    them, on a one-isolator deck under a harmonic orbit (made with numpy only: nothing is
    compiled)."""
    import numpy as np

    from nsdyn.models.isolated import _kplane as kp
    from nsdyn.models.isolated import _kplanerun as kr
    from nsdyn.models.isolated.bearings import Bearing, Friction
    from nsdyn.models.isolated.deck import kernel_params, pack_ground, sdof_plane
    from nsdyn.models.isolated.defaults import EPS, ETA

    system = sdof_plane(1.0e5, Bearing(Friction(0.05), radius=2.0))
    M, pos, bp, nd, sp = kernel_params(system, "switch", EPS, ETA, None)
    gk, gp, tab, _ = pack_ground({"f": 1.0, "ax": 1.0})
    ni, n = 1, 6
    modes, dirs = np.full(ni, kp.MODE_SLIP, dtype=np.int64), np.zeros((ni, 2))
    out, ws = kp.forces(ni), kp.workspace(ni)
    force = (0.0, np.zeros(n), modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, *out)
    EV, info = np.zeros((1, 6)), np.zeros(kr.N_INFO)
    settle = (*force[:13], out, EV, info)
    return force, settle, (*settle[:2], np.ones((ni, 3)), np.ones((ni, 3)), *settle[2:])


@functools.cache
def callees() -> list:
    """The deck loops' callees by address (:class:`nsdyn._kaddress.Callee`): the force
    kernel (``"deck.evaluate"``), the switch law's settling (``"deck.settle"``) and its mode
    switch at an event (``"deck.switch"``), declared for the types of :func:`tiny_args`, each
    returning a status (int64). Once per process."""
    from numba import typeof, types

    from nsdyn._kaddress import Callee
    from nsdyn.models.isolated import _kplane as kp
    from nsdyn.models.isolated import _kplanerun as kr

    force, settle, switch = (tuple(typeof(a) for a in args) for args in tiny_args())
    return [
        Callee("deck.evaluate", kp.evaluate, force, types.int64),
        Callee("deck.settle", kr.settle, settle, types.int64),
        Callee("deck.switch", kr.switch, switch, types.int64),
    ]


def _needed(switch: bool) -> list:
    """The callees a run calls: the force kernel, and the settling and the mode switch under
    the switch law."""
    return callees() if switch else callees()[:1]


def ready(switch: bool = True) -> None:
    """The table filled for a run of the deck's loops (each callee loaded from numba's cache,
    or compiled); ``switch``: a run of the switch law (it settles stick); nothing without the
    JIT or with plain numba."""
    from nsdyn._kaddress import fill_table

    fill_table(_needed(switch))


def loop_arrays(loop, n: int, ni: int) -> tuple:
    """The scratch of the time loop ``loop`` (``_kplanerun.integrate`` or
    ``_kplaneradau.integrate``) for ``n`` states and ``ni`` isolators, its last three
    arguments: (the force kernel's workspace, its outputs, the loop's own arrays). Made here,
    in Python, so that the loops and their callees allocate nothing and compile without
    numba's reference counts (:data:`nsdyn._kaddress.NO_NRT`)."""
    import numpy as np

    from nsdyn.models.isolated import _kplane as kp
    from nsdyn.models.isolated import _kplaneradau as krad

    if loop is krad.integrate:  # Radau IIA, in the order the loop unpacks them: y, ys, f0,
        # f1, J, Z, F, r1, rc, EC, pc, LE, pe, err, sc, ynew, copied, sdw, yp, Zp, base
        v = [np.zeros(n) for _ in range(4)]
        S = (*v, np.zeros((n, n)), np.zeros((3, n)), np.zeros((3, n)), np.zeros(n),
             np.zeros(n, dtype=np.complex128), np.zeros((n, n), dtype=np.complex128),
             np.zeros(n, dtype=np.int64), np.zeros((n, n)), np.zeros(n, dtype=np.int64),
             np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n, dtype=np.bool_),
             np.zeros((ni, 8)), np.zeros(n), np.zeros((3, n)), np.zeros(8))  # fmt: skip
    else:  # Dormand-Prince: k (stages), y, y1, ys, rc (dense output), g0, g, ga
        S = (np.zeros((7, n)), np.zeros(n), np.zeros(n), np.zeros(n), np.zeros((5, n)),
             np.ones((ni, 3)), np.ones((ni, 3)), np.ones((ni, 3)))  # fmt: skip
    return kp.workspace(ni), kp.forces(ni), S


def run_loop(loop, args: tuple, switch: bool, progress=None, scratch=None):
    """``loop(*args, *scratch)`` (a time loop of the deck: ``_kplanerun.integrate`` or
    ``_kplaneradau.integrate``; ``args`` up to its ``info``, the scratch from
    :func:`loop_arrays`), its callees in the table first. A first compilation is
    shared with a helper process where one may run (:func:`nsdyn._numba_cache.helper_enabled`):
    it compiles the callees (:func:`helper_part`) while this process compiles the loop for
    ``args``' types. ``progress(t_done, t_end, wall_s)``: called every few seconds while the
    loop runs in a thread of its own (:func:`nsdyn._progress.watched`; t_done the last output
    written, ``info[I_NOUT]``). ``scratch``: the loop's arrays when the caller keeps them
    (:func:`loop_arrays`; its first, the force kernel's workspace, holds the impasse record)."""
    from nsdyn._kaddress import run_split

    if scratch is None:
        scratch = loop_arrays(loop, args[0].shape[0], args[5].shape[0])
    args = (*args, *scratch)
    target = "helper_part" if switch else "helper_force"

    def run():
        return run_split(loop, args, _needed(switch),
                         f"nsdyn.models.isolated.deck_compile:{target}")  # fmt: skip

    if progress is None:
        return run()
    from nsdyn._progress import watched
    from nsdyn.models.isolated._kplanerun import I_NOUT

    t_eval, info = args[1], args[21]
    return watched(run, lambda: float(t_eval[max(int(info[I_NOUT]) - 1, 0)]), progress,
                   float(t_eval[-1]))  # fmt: skip


def helper_part() -> None:
    """The helper's share of a first compilation of the switch law's loop: the force kernel,
    the settling and the mode switch."""
    for c in callees():
        c.compiled()


def helper_force() -> None:
    """The helper's share of a first compilation of a loop of the regularised law: the force
    kernel."""
    callees()[0].compiled()
