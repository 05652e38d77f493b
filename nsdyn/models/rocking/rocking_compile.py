"""The rocking block's ground motion by address, and its first compilation shared by two processes.

The rocking block's time loop (:func:`nsdyn.models.rocking._kblock.integrate`) evaluates the
ground acceleration (:func:`nsdyn.models.rocking._kground.ground`: the record's interpolation
or a pulse's closed form) at seven places: its right-hand side at two, the test whether the
ground lifts a resting block at four, the impact's step estimate at one. Linked, numba would
copy it into each of them and LLVM would optimise and translate every copy again; called by
its address (:func:`nsdyn._kaddress.tcall`, row ``"rock.ground"`` of the process-wide table)
it compiles once. A first run compiles it in a helper process (:func:`helper_part`) while this
process compiles the loop (:func:`run_integrate`).
"""

from __future__ import annotations

import functools


@functools.cache
def callees() -> list:
    """The loop's callee by address (:class:`nsdyn._kaddress.Callee`): ``ground(t, left, gk,
    gp, tab_h, tab_v) -> (ü_hor, ü_ver)``. Once per process."""
    from numba import types

    from nsdyn._kaddress import Callee
    from nsdyn.models.rocking import _kground as kg

    v = types.float64[::1]
    args = (types.float64, types.boolean, types.int64, v, v, v)
    return [Callee("rock.ground", kg.ground, args, types.UniTuple(types.float64, 2))]


def run_integrate(args: tuple) -> int:
    """``_kblock.integrate(*args)`` with its callee in the table (a first compilation shared
    with a helper process, :func:`nsdyn._kaddress.run_split`)."""
    from nsdyn._kaddress import run_split
    from nsdyn.models.rocking import _kblock as kb

    return run_split(kb.integrate, args, callees(),
                     "nsdyn.models.rocking.rocking_compile:helper_part")  # fmt: skip


def helper_part() -> None:
    """The helper's share of a first compilation: the ground motion."""
    callees()[0].compiled()
