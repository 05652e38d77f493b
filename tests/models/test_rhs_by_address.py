"""The contact body's and the cylinder's right-hand sides by address.

Their time loops call the right-hand side through the process-wide address table
(nsdyn._kaddress.tcall): it compiles once, on its own (in a helper process on a first run),
and the loop compiles without a copy of it. The histories equal those of direct calls bit for
bit (tests/solve/test_plain_numba.py runs both families in both modes); here: the rows, the
declarations, and what is compiled where.
"""

import os

import pytest

from nsdyn import _kaddress as ka
from nsdyn._numba_cache import PLAIN
from nsdyn.models.contact import _kevent as ke
from nsdyn.models.contact import contact_compile as cc
from nsdyn.models.cylinder import _kernel as kc
from nsdyn.models.cylinder import cylinder_compile as yc

JIT = os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")


@pytest.mark.parametrize("module, name, kernel", [(cc, "contact.rhs", ke.rhs),
                                                  (yc, "cyl.rhs", kc.rhs)])  # fmt: skip
def test_each_right_hand_side_has_a_row_a_direct_kernel_and_one_declaration(module, name, kernel):
    (callee,) = module.callees()
    assert callee.name == name and callee.kernel is kernel
    assert name in ka.TABLE_NAMES and ka.TSLOTS[name] is kernel
    assert ka.DECLARED[name] == (callee.ret, callee.args)


_LOOPS_ALONE = """
from nsdyn.models.contact import _kevent as ke, contact_compile as cc
from nsdyn.models.cylinder import _kernel as kc, cylinder_compile as yc
from numba import types
cc.callees(), yc.callees()
f8, i8, v, m = types.float64, types.int64, types.float64[::1], types.float64[:, ::1]
ke.integrate.compile(cc.loop_types())
kc.integrate.compile((f8, f8, m, v, v, f8, v, f8, f8, i8, f8, m, v))
for loop, rhs in ((ke.integrate, ke.rhs), (kc.integrate, kc.rhs)):
    lib = next(iter(loop.overloads.values())).library
    linked = str({l.name for l in getattr(lib, "_linking_libraries", ())})
    print(rhs.py_func.__module__, len(rhs.signatures), "rhs" in linked)
"""


@pytest.mark.slow  # compiles both loops into an empty cache (~5 s)
@pytest.mark.skipif(not JIT or PLAIN, reason="calls by address only in compiled code")
def test_the_loops_compile_without_their_right_hand_sides(compile_alone):
    # a fresh process with an empty cache compiles each loop alone: its right-hand side is
    # neither compiled with it nor linked into its code
    rows = compile_alone(_LOOPS_ALONE)
    assert [r[0] for r in rows] == ["nsdyn.models.contact._kevent", "nsdyn.models.cylinder._kernel"]
    assert all(r[1:] == ["0", "False"] for r in rows), rows
