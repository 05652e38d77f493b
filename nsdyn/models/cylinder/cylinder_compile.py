"""The cylinder's right-hand side by address, and its first compilation shared by two processes.

The time loop (:func:`nsdyn.models.cylinder._kernel.integrate`), the friction mode switch
(``set_mode``) and the output (``store``) each evaluate the right-hand side ``rhs`` (the
foundation's resultants, the 6 × 6 or 4 × 4 solve). Linked, numba would copy it into each of
them and LLVM would optimise and translate every copy again; called by its address
(:func:`nsdyn._kaddress.tcall`, row ``"cyl.rhs"`` of the process-wide table) it compiles once.
The slip stop (``stop_slip``, row ``"cyl.stop_slip"``) is called so too: it links the mass
matrix and the block solve that the right-hand side links, so the two compile in one process.
A first run compiles both in a helper process (:func:`helper_part`) while this process compiles
the loop (:func:`run_integrate`).
"""

from __future__ import annotations

import functools


@functools.cache
def callees() -> list:
    """The loop's callees by address (:class:`nsdyn._kaddress.Callee`): ``rhs(y, ag, p, fr,
    dy, aux)``, six contiguous float64 vectors, and ``stop_slip(y, p)``, two, each returning
    nothing. Once per process."""
    from numba import types

    from nsdyn._kaddress import Callee
    from nsdyn.models.cylinder import _kernel as K

    v = types.float64[::1]
    return [Callee("cyl.rhs", K.rhs, (v,) * 6, types.none),
            Callee("cyl.stop_slip", K.stop_slip, (v, v), types.none)]  # fmt: skip


def run_integrate(args: tuple) -> int:
    """``_kernel.integrate(*args)`` with its callees in the table (a first compilation shared
    with a helper process, :func:`nsdyn._kaddress.run_split`)."""
    from nsdyn._kaddress import run_split
    from nsdyn.models.cylinder import _kernel as K

    return run_split(K.integrate, args, callees(),
                     "nsdyn.models.cylinder.cylinder_compile:helper_part")  # fmt: skip


def helper_part() -> None:
    """The helper's share of a first compilation: the right-hand side, then the slip stop
    (which links the right-hand side's mass matrix and block solve, compiled by then)."""
    for c in callees():
        c.compiled()
