"""The body's right-hand side by address, and its first compilation shared by two processes.

The event-driven loop (:func:`nsdyn.models.contact._kevent.integrate`) evaluates the
right-hand side ``rhs`` (the contact rows and the LCP of the reactions) at seven places: the
stages of a step and the event location. Linked, numba would copy it and the LCP solver into
the loop and LLVM would optimise and translate them there again; called by its address
(:func:`nsdyn._kaddress.tcall`, row ``"contact.rhs"`` of the process-wide table) it compiles
once. A first run compiles it in a helper process (:func:`helper_part`) while this process
compiles the loop (:func:`warm`, before the run's set-up evaluates the right-hand side).
"""

from __future__ import annotations

import functools


@functools.cache
def callees() -> list:
    """The loop's callee by address (:class:`nsdyn._kaddress.Callee`): ``rhs(t, y, sig,
    closed, verts, minv, par, ex, tab_h, tab_v)`` (``verts`` (nc, 3), the others contiguous
    float64 vectors) returning (y', indicators, lam_N, lam_T, LCP status). Once per process."""
    from numba import types

    from nsdyn._kaddress import Callee
    from nsdyn.models.contact import _kevent as ke

    f8, v, m = types.float64, types.float64[::1], types.float64[:, ::1]
    args = (f8, v, v, v, m, v, v, v, v, v)
    return [Callee("contact.rhs", ke.rhs, args, types.Tuple((v, v, v, v, types.int64)))]


def warm() -> None:
    """Compile the loop for the argument types the runs give it (:func:`loop_types`) beside a
    helper that compiles the right-hand side (nothing when both are in numba's cache)."""
    from nsdyn._kaddress import compile_beside
    from nsdyn.models.contact import _kevent as ke

    compile_beside(ke.integrate, loop_types(), callees(),
                   "nsdyn.models.contact.contact_compile:helper_part")  # fmt: skip


def loop_types() -> tuple:
    """numba types of ``integrate(t, y, t_end, h, sig, closed, verts, minv, par, ex, tab_h,
    tab_v, rtol, atol, t_out, y_out, iout, max_steps, h_max)`` as the runs call it."""
    from numba import types

    f8, i8, v, m = types.float64, types.int64, types.float64[::1], types.float64[:, ::1]
    return (f8, v, f8, f8, v, v, m, v, v, v, v, v, f8, f8, v, m, i8, i8, f8)


def run_integrate(args: tuple) -> tuple:
    """``_kevent.integrate(*args)`` with its callee in the table (a first compilation shared
    with a helper process, :func:`nsdyn._kaddress.run_split`)."""
    from nsdyn._kaddress import run_split
    from nsdyn.models.contact import _kevent as ke

    return run_split(ke.integrate, args, callees(),
                     "nsdyn.models.contact.contact_compile:helper_part")  # fmt: skip


def helper_part() -> None:
    """The helper's share of a first compilation: the right-hand side."""
    callees()[0].compiled()
