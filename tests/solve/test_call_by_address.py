"""Calls to compiled kernels by address (``nsdyn._kaddress``), as the default Radau loop makes them.

What must hold: a call through an address computes what the direct call computes (the same
compiled code, bit for bit); a call whose argument types differ from the declared ones, and a
kernel whose return type differs from the declared one, are refused with an error naming the
callee (a wrong address type would otherwise read garbage); and the default loop compiles from
its own code alone (none of its callees compiled first, none linked into it), which is what lets
a first run compile it beside them (README, "Callees by address").
"""

import os
import subprocess
import sys

import numpy as np
import pytest
from numba import njit, types
from numba.core.errors import TypingError

from nsdyn import _kaddress as ka
from nsdyn.solve import _kcolloc, _kflat, compile_split
from nsdyn.solve.integrate import _tiny_problem

JIT = os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")


@njit
def _feval_both(K, t, y, Fl, out_direct, out_address, qdd, lam, tau, modes):
    a = ka.call(None, "radau.feval", (t, y, Fl, out_direct, qdd, lam, tau, modes), 0)
    b = ka.call(K, "radau.feval", (t, y, Fl, out_address, qdd, lam, tau, modes), 0)
    return a, b


def test_call_by_address_equals_the_direct_call():
    # the flat right-hand side of the tiny frame at a perturbed state, once directly and once
    # through its address in K: the same compiled arithmetic, so the same bits
    P, x0 = _tiny_problem()
    y = x0 + 1e-3 * np.sin(np.arange(x0.size))
    Fl = _kflat.pack_flat(P)
    ws = compile_split._tiny_args("radau")[6]
    qdd, lam, tau, modes = (w.copy() for w in ws[18:22])
    K = compile_split.radau_calls()
    out_d, out_a = np.zeros(x0.size), np.full(x0.size, np.nan)
    ok_d, ok_a = _feval_both(K, 0.3, y, Fl, out_d, out_a, qdd, lam, tau, modes)
    assert ok_d and ok_a
    assert np.all(np.isfinite(out_d)) and np.array_equal(out_d, out_a)


@njit
def _twice(x):
    return 2.0 * x


ka.slot("test.twice", 0, _twice)


@pytest.mark.skipif(not JIT, reason="types are checked only when numba compiles")
def test_call_with_undeclared_argument_types_is_refused():
    ka.declare("test.twice", types.float64, (types.float64,))

    @njit
    def caller(K, x):
        return ka.call(K, "test.twice", (x,), 0)

    K = np.array([compile_split.Callee("test.twice", _twice, (types.float64,), types.float64)
                  .address()])  # fmt: skip
    assert caller(K, 1.5) == 3.0
    with pytest.raises(TypingError, match="test.twice"):
        caller(K, np.int32(2))  # an int32 where a float64 is declared


@pytest.mark.skipif(not JIT, reason="return types exist only when numba compiles")
def test_kernel_with_another_return_type_is_refused():
    c = compile_split.Callee("test.twice", _twice, (types.float64,), types.int64)
    with pytest.raises(TypeError, match="test.twice.*returns float64, declared int64"):
        c.address()


@pytest.mark.slow
@pytest.mark.skipif(not JIT, reason="nothing compiles under NUMBA_DISABLE_JIT")
def test_default_loop_compiles_without_its_callees(tmp_path):
    # a fresh process with an empty cache compiles the default loop alone (~5-10 s): none of
    # its callees is compiled with it, and no callee's code is linked into it
    code = (
        "import numpy as np\n"
        "from nsdyn.solve import compile_split as cs, methods, _kradau as kr, _kcolloc as kc\n"
        "P, x0, t_eval, o, X, upl_t = methods.tiny_run(methods.METHODS['radau'])\n"
        "K = cs.radau_callees()\n"
        "args = (P, x0, t_eval, o.atol, o.rtol, o.h0, o.max_step, o.max_steps, False,\n"
        "        o.uplift_mode, X, upl_t, True, kc.flat_only, np.zeros(len(K), np.int64))\n"
        "cs._compile(kr.radau_flat, *args)\n"
        "lib = next(iter(kr.radau_flat.overloads.values())).library\n"
        "linked = {l.name for l in getattr(lib, '_linking_libraries', ())}\n"
        "for c in K:\n"
        "    name = c.kernel.py_func.__qualname__\n"
        "    print(name, len(c.kernel.signatures), name in linked)\n"
    )
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), NUMBA_DISABLE_JIT="0")
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    ).stdout.split("\n")
    rows = [r.split() for r in out if r]
    assert {r[0] for r in rows} == {
        "feval_flat", "jac_flat", "_factor", "newton_flat", "start_flat", "setup"
    }  # fmt: skip
    assert all(r[1:] == ["0", "False"] for r in rows), rows


def test_k_layout_matches_the_callees():
    # the addresses sit where the loop reads them: slot indices in the order of radau_callees
    for i, c in enumerate(compile_split.radau_callees()):
        assert ka.SLOTS[c.name][0] == i
    assert _kcolloc.K_NEWTON == [c.name for c in compile_split.radau_callees()].index(
        "radau.newton"
    )
