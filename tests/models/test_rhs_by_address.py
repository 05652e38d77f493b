"""The contact body's and the cylinder's right-hand sides, the cylinder's slip stop and the rocking
block's ground motion, by address.

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
from nsdyn.models.rocking import _kground as kg
from nsdyn.models.rocking import rocking_compile as rc

JIT = os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")


@pytest.mark.parametrize("module, name, kernel", [(cc, "contact.rhs", ke.rhs),
                                                  (yc, "cyl.rhs", kc.rhs),
                                                  (yc, "cyl.stop_slip", kc.stop_slip),
                                                  (rc, "rock.ground", kg.ground)])  # fmt: skip
def test_each_callee_has_a_row_a_direct_kernel_and_one_declaration(module, name, kernel):
    (callee,) = [c for c in module.callees() if c.name == name]
    assert callee.kernel is kernel
    assert name in ka.TABLE_NAMES and ka.TSLOTS[name] is kernel
    assert ka.DECLARED[name] == (callee.ret, callee.args)


_LOOPS_ALONE = """
from nsdyn.models.contact import _kevent as ke, contact_compile as cc
from nsdyn.models.cylinder import _kernel as kc, cylinder_compile as yc
from nsdyn.models.rocking import _kblock as kb, _kground as kg, rocking_compile as rc
from numba import types
cc.callees(), yc.callees(), rc.callees()
f8, i8, v, m = types.float64, types.int64, types.float64[::1], types.float64[:, ::1]
ke.integrate.compile(cc.loop_types())
work = types.Tuple((v, v, v, m, v, v, v))
kc.integrate.compile((f8, f8, m, v, v, f8, v, f8, f8, i8, f8, m, v, work))
kb.integrate.compile((v, i8, v, v, v, v, f8, f8, f8, m, m, m, v, m, m, v, v))
for loop, callee, key in ((ke.integrate, ke.rhs, "rhs"), (kc.integrate, kc.rhs, "rhs"),
                          (kc.integrate, kc.stop_slip, "stop_slip"),
                          (kb.integrate, kg.ground, "ground")):
    lib = next(iter(loop.overloads.values())).library
    linked = str({l.name for l in getattr(lib, "_linking_libraries", ())})
    print(key, len(callee.signatures), key in linked)
"""


@pytest.mark.slow  # compiles the three loops into an empty cache (~10 s)
@pytest.mark.skipif(not JIT or PLAIN, reason="calls by address only in compiled code")
def test_the_loops_compile_without_their_callees_by_address(compile_alone):
    # a fresh process with an empty cache compiles each loop alone: its callees by address are
    # neither compiled with it nor linked into its code
    rows = compile_alone(_LOOPS_ALONE)
    assert [r[0] for r in rows] == ["rhs", "rhs", "stop_slip", "ground"]
    assert all(r[1:] == ["0", "False"] for r in rows), rows
