"""Calls to compiled kernels by address (``nsdyn._kaddress``), as the default Radau loop makes them.

What must hold: a call through an address computes what the direct call computes (the same
compiled code, bit for bit); a call whose argument types differ from the declared ones, a
kernel whose return type differs from the declared one and an address taken for another
declaration than the caller was compiled for are refused with an error naming the callee (a
wrong address type would otherwise read garbage); read-only inputs run as writable ones; the
arrays returned through addresses are freed; and the default loop compiles from its own code
alone (none of its callees compiled first, none linked into it), which is what lets a first run
compile it beside them (README, "Callees by address").
"""

import os
import subprocess
import sys

import numpy as np
import pytest
from numba import njit, types
from numba.core.errors import TypingError

from nsdyn import _kaddress as ka
from nsdyn._numba_cache import PLAIN
from nsdyn.models.isolated import _kernel as ks
from nsdyn.solve import _kcolloc, _kflat, compile_split
from nsdyn.solve import _kcommon as ki
from nsdyn.solve.integrate import _tiny_problem

JIT = os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")
no_table_in_plain_numba = pytest.mark.skipif(
    PLAIN, reason="plain numba (NSDYN_PLAIN_NUMBA=1) calls its callees directly: no table"
)


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


def test_general_metrics_by_address_equal_the_direct_calls():
    # the metrics of a run whose loop compiled the system kernel call it through its address
    # (transient.general_evaluations -> _kcommon.evaluate_many_t, no second copy compiled):
    # the same compiled arithmetic as evaluate_many's linked copy, so the same bits, for a
    # smooth law and the switch law; with a contact open on part of the history (a unilateral
    # run) each pattern is evaluated with its own open set, and an open contact carries no
    # normal force
    from nsdyn.models.isolated.metrics import evaluation_arrays
    from nsdyn.models.isolated.params import with_law, with_open
    from nsdyn.solve.transient import general_evaluations

    P, x0 = _tiny_problem()
    t = np.linspace(0.0, 0.8, 6)
    X = x0 + 1e-3 * np.sin(np.add.outer(np.arange(t.size), np.arange(x0.size)))
    for law in ("arctan", "switch"):
        Q = with_law(P, law)
        direct = evaluation_arrays(Q, t.size)
        ks.evaluate_many(t, X, Q, *direct)
        for a, b in zip(direct, general_evaluations(Q, t, X), strict=True):
            assert np.array_equal(a, b)
    nc = P[ks.I_R].shape[0]
    pattern = np.zeros((t.size, nc), np.int64)
    pattern[3:, 0] = 1
    out = general_evaluations(P, t, X, pattern)
    for rows, pat in ((slice(0, 3), pattern[0]), (slice(3, None), pattern[-1])):
        ref = evaluation_arrays(P, t[rows].size)
        ks.evaluate_many(t[rows], np.ascontiguousarray(X[rows]), with_open(P, pat), *ref)
        for a, b in zip(ref, out, strict=True):
            assert np.array_equal(a, b[rows])
    assert np.all(out[1][3:, 0] == 0.0) and np.all(out[1][:3, 0] != 0.0)


def test_metrics_by_address_equal_the_direct_calls():
    # a flat run's response metrics call the flat right-hand side through its address
    # (compile_split.flat_calls): the same bits as with it called directly, and the flat
    # array is left as packed (its "a0 given" flag cleared) for the next evaluation
    P, x0 = _tiny_problem()
    t = np.linspace(0.0, 0.8, 5)
    X = x0 + 1e-3 * np.sin(np.add.outer(np.arange(t.size), np.arange(x0.size)))
    n, nc, ni = P[ks.I_MIK].shape[0], P[ks.I_R].shape[0], P[ks.I_D].shape[0]
    A0 = np.ascontiguousarray(-(X[:, :n] @ P[ks.I_MIK].T) - X[:, n:] @ P[ks.I_MIC].T)
    outs = []
    for K in (None, compile_split.flat_calls()):
        F = _kflat.pack_flat(P)
        F0 = F.copy()
        out = (np.empty((t.size, n)), np.empty((t.size, nc)), np.empty((t.size, ni)),
               np.empty((t.size, ni), np.int64), np.zeros(t.size, np.bool_))  # fmt: skip
        _kflat.evaluate_flat_many(t, X, F, A0, *out, K)
        assert F[_kflat.H_A0IN] == 0.0 and np.array_equal(F[: _kflat.N_HEAD], F0[: _kflat.N_HEAD])
        outs.append(out)
    assert outs[0][4].all() and np.all(np.isfinite(outs[0][0]))
    for a, b in zip(*outs, strict=True):
        assert np.array_equal(a, b)


@njit
def _twice(x):
    return 2.0 * x


ka.slot("test.twice", 0, _twice)


@njit
def _call_twice(K, x):
    return ka.call(K, "test.twice", (x,), 0)


def _twice_K(ret=types.float64, name="test.twice"):
    c = compile_split.Callee(name, _twice, (types.float64,), ret)
    return np.array([[c.address()], [ka.digest(name)]], dtype=np.int64)


@pytest.mark.skipif(not JIT, reason="types are checked only when numba compiles")
def test_call_with_undeclared_argument_types_is_refused():
    K = _twice_K()
    assert _call_twice(K, 1.5) == 3.0
    with pytest.raises(TypingError, match="test.twice"):
        _call_twice(K, np.int32(2))  # an int32 where a float64 is declared
    with pytest.raises(TypingError, match="K must be a 2-row int64 array"):
        _call_twice(K.astype(np.int32), 1.5)


@pytest.mark.skipif(not JIT, reason="digests are checked only in compiled code")
def test_address_taken_for_another_declaration_is_refused():
    # a caller compiled (or loaded from numba's cache) for one declaration, given an address
    # whose digest says it was taken for another: an error, never a call of the wrong code
    K = _twice_K()
    K[1, 0] += 1
    with pytest.raises(RuntimeError, match="stale entry of numba's cache"):
        _call_twice(K, 1.5)


def test_a_name_is_declared_once():
    ka.declare("test.once", types.float64, (types.float64,))
    ka.declare("test.once", types.float64, (types.float64,))  # the same again: fine
    with pytest.raises(ValueError, match="already declared"):
        ka.declare("test.once", types.int64, (types.float64,))


@pytest.mark.skipif(not JIT, reason="return types exist only when numba compiles")
def test_kernel_with_another_return_type_is_refused():
    c = compile_split.Callee("test.twice_int", _twice, (types.float64,), types.int64)
    with pytest.raises(TypeError, match="test.twice_int.*returns float64, declared int64"):
        c.address()


def _tiny_run_inputs():
    P, x0 = _tiny_problem()
    t_eval = np.linspace(0.0, 0.3, 7)
    atol = np.full(x0.size, 1e-8)
    return P, x0, t_eval, atol


def _default_loop(P, x0, t_eval, atol):
    X = np.zeros((t_eval.size, x0.size))
    args = (1e-6, 0.0, np.inf, 100_000, False, ki.UPLIFT_WARN, X, np.full(1, np.nan))
    stats, _ = compile_split.radau_flat(P, x0, t_eval, atol, *args)
    return stats, X


def test_read_only_inputs_give_the_same_run():
    # read-only arrays have another numba type than the declared one: the default loop
    # copies them and runs, bit for bit as with writable inputs
    P, x0, t_eval, atol = _tiny_run_inputs()
    s_ref, X_ref = _default_loop(P, x0, t_eval, atol)
    frozen = [a.copy() for a in (*P, x0, t_eval, atol)]
    for a in frozen:
        a.flags.writeable = False
    s, X = _default_loop(tuple(frozen[: len(P)]), *frozen[len(P) :])
    assert s[ki.S_STATUS] == ki.ST_SUCCESS
    assert np.array_equal(s, s_ref) and np.array_equal(X, X_ref)


@pytest.mark.skipif(not JIT, reason="numba's allocation counters exist only when it compiles")
def test_arrays_returned_by_address_are_freed():
    # the start-up returns a new array through its address: every array allocated by a run
    # is freed again (numba's allocation statistics, three runs)
    from numba.core.runtime import _nrt_python as nrt
    from numba.core.runtime import rtsys

    P, x0, t_eval, atol = _tiny_run_inputs()
    _default_loop(P, x0, t_eval, atol)
    was_on = nrt.memsys_stats_enabled()
    nrt.memsys_enable_stats()
    try:
        before = rtsys.get_allocation_stats()
        for _ in range(3):
            _default_loop(P, x0, t_eval, atol)
        after = rtsys.get_allocation_stats()
    finally:
        if not was_on:
            nrt.memsys_disable_stats()
    allocated, freed = after.alloc - before.alloc, after.free - before.free
    assert allocated > 0 and allocated == freed


@pytest.mark.slow
@pytest.mark.skipif(not JIT, reason="nothing compiles under NUMBA_DISABLE_JIT")
def test_default_loop_compiles_without_its_callees(tmp_path):
    # a fresh process with an empty cache compiles the default loop alone (~5-10 s): none of
    # its callees is compiled with it, and no callee's code is linked into it
    code = (
        "import numpy as np\n"
        "from nsdyn.solve import compile_split as cs, methods, _kradau as kr\n"
        "P, x0, t_eval, o, X, upl_t = methods.tiny_run(methods.METHODS['radau'])\n"
        "K = cs.radau_callees()\n"
        "ws = cs._tiny_args('radau')[-1]\n"
        "owned = kr._owned(ws, x0, t_eval, upl_t.shape[0])\n"
        "args = (P, x0, t_eval, o.atol, o.rtol, o.h0, o.max_step, o.max_steps, False,\n"
        "        o.uplift_mode, X, upl_t, True, np.zeros((2, len(K)), np.int64), owned)\n"
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
        "feval_flat", "jac_flat_here", "_factor", "newton_flat", "start_flat"
    }  # fmt: skip
    assert all(r[1:] == ["0", "False"] for r in rows), rows


def test_k_layout_matches_the_callees():
    # the addresses sit where the loop reads them: slot indices in the order of radau_callees
    for i, c in enumerate(compile_split.radau_callees()):
        assert ka.SLOTS[c.name][0] == i
    assert _kcolloc.K_NEWTON == [c.name for c in compile_split.radau_callees()].index(
        "radau.newton"
    )


def test_default_loop_counts_as_cached_only_with_its_callees(monkeypatch):
    # the loop compiles apart from its callees: an interrupted first compilation can leave it
    # cached without them, and the run must then still announce (and split) a compilation
    from nsdyn.solve import methods

    monkeypatch.setattr(methods, "_COMPILED", {})
    monkeypatch.setattr(methods, "dispatcher_cached", lambda d: d is not _kcolloc.newton_flat)
    assert not methods.is_cached("radau")
    monkeypatch.setattr(methods, "dispatcher_cached", lambda d: True)
    assert methods.is_cached("radau")


@pytest.mark.slow
def test_period_map_by_address_equals_the_direct_call():
    # the period map calls its step, Jacobian and right-hand side by address
    # (nsdyn.periodic.problem.periodic_calls): one period of the Duffing oscillator with
    # sensitivities, the same bits as with them called directly (K None, a second
    # compilation of the period map and its step, ~10 s)
    from nsdyn.periodic import _kperiodic as kp
    from nsdyn.periodic.problem import duffing_problem, periodic_calls

    prob = duffing_problem(0.05, 1.0, 0.1, 0.5)
    _, args = prob._map_args(np.array([0.3, 0.0]), 0.2, 40, None, True, True)
    by_address = kp.period_map(*args, periodic_calls())
    direct = kp.period_map(*args, None)
    assert by_address[4] == kp.STATUS_OK and np.all(np.isfinite(by_address[1]))
    for a, b in zip(by_address, direct, strict=True):
        assert np.array_equal(a, b)


# ---- the process-wide table (nsdyn._kaddress.tcall): the event loop's callees ------------------


@njit
def _evaluate_both(t, y, P, out_direct, out_table):
    a = ks.evaluate(t, y, P, *out_direct)
    b = ka.tcall("sys.evaluate", (t, y, P, *out_table))
    return a, b


def _switch_inputs():
    """The tiny frame with the switch model's modes (the event loop's P), a perturbed state and
    two sets of outputs (qdd, lam, tau, modes) of the system kernel."""
    P, x0, *_, ws = compile_split._tiny_args("event", "modes")
    y = x0 + 1e-3 * np.sin(np.arange(x0.size))
    outs = [tuple(np.full_like(w, -7) for w in ws[18:22]) for _ in range(2)]
    return P, y, outs


def test_call_through_the_table_equals_the_direct_call():
    # the system kernel through its row of the table (nsdyn.solve._kcommon.sys_evaluate, its
    # assembly, small solve and pseudo-inverse by address) and directly (linked): one source,
    # the same arithmetic, so the same bits (accelerations, normal and friction forces, modes)
    compile_split.event_ready(True, False, False)
    P, y, (direct, table) = _switch_inputs()
    ok_d, ok_t = _evaluate_both(0.3, y, P, direct, table)
    assert ok_d and ok_t
    assert np.all(np.isfinite(direct[0]))
    for a, b in zip(direct, table, strict=True):
        assert np.array_equal(a, b)


@pytest.mark.skipif(not JIT, reason="the table is read only by compiled code")
@no_table_in_plain_numba
def test_a_row_without_an_address_is_refused():
    # a caller whose callee's row is empty (or holds an address taken for another
    # declaration): a RuntimeError naming the callee, never a jump to address 0
    compile_split.event_ready(True, False, False)
    P, y, (direct, table) = _switch_inputs()
    i = ka.index("sys.evaluate")
    saved = ka.TABLE[i].copy()
    try:
        ka.TABLE[i] = 0
        assert not ka.filled("sys.evaluate")
        with pytest.raises(RuntimeError, match="'sys.evaluate'.*address not yet taken"):
            _evaluate_both(0.3, y, P, direct, table)
        ka.TABLE[i, 0], ka.TABLE[i, 1] = saved[0], saved[1] + 1
        with pytest.raises(RuntimeError, match="'sys.evaluate'"):
            _evaluate_both(0.3, y, P, direct, table)
    finally:
        ka.TABLE[i] = saved
    assert ka.filled("sys.evaluate")


@njit
def _evaluate_at_an_integer_time(y, P, out):
    return ka.tcall("sys.evaluate", (np.int64(1), y, P, *out))


@pytest.mark.skipif(not JIT, reason="types are checked only when numba compiles")
@no_table_in_plain_numba
def test_table_call_with_undeclared_argument_types_is_refused():
    compile_split.event_callees()  # the declarations
    P, y, (out, _) = _switch_inputs()
    with pytest.raises(TypingError, match="sys.evaluate.*positions \\[0\\]"):
        _evaluate_at_an_integer_time(y, P, out)


def test_table_rows_are_fixed_and_each_callee_registered():
    # a row index is compiled into its callers: names keep their rows, and every name of the
    # event loop's callees has a row and a kernel to call without addresses
    from nsdyn.solve import _kunilateral as ku

    assert ka.TABLE.shape == (ka.TABLE_ROWS, 2) and len(ka.TABLE_NAMES) <= ka.TABLE_ROWS
    assert len(set(ka.TABLE_NAMES)) == len(ka.TABLE_NAMES)
    names = ku.callees(True, True)
    assert set(names) <= set(ka.TSLOTS) and set(names) <= set(ka.TABLE_NAMES)
    assert {c.name for c in compile_split.event_callees()} == set(names)
    with pytest.raises(ValueError):
        ka.tslot("no.such.row", _twice)


@pytest.mark.slow
@pytest.mark.skipif(not JIT, reason="nothing compiles under NUMBA_DISABLE_JIT")
@no_table_in_plain_numba
def test_event_loop_compiles_without_its_callees(tmp_path):
    # a fresh process with an empty cache compiles the event loop alone: none of its callees
    # (in the table or in K) is compiled with it, and no callee's code is linked into it
    code = (
        "from nsdyn.solve import compile_split as cs, _kunilateral as ku\n"
        "cs.event_callees()\n"
        "cs.compile_event_loop()\n"
        "lib = next(iter(ku._run.overloads.values())).library\n"
        "linked = {l.name for l in getattr(lib, '_linking_libraries', ())}\n"
        "for k in ku.kernels(True, True, True)[1:]:\n"
        "    name = k.py_func.__module__ + '.' + k.py_func.__qualname__\n"
        "    print(name, len(k.signatures), k.py_func.__qualname__ in str(linked))\n"
    )
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), NUMBA_DISABLE_JIT="0")
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    ).stdout.split("\n")
    rows = [r.split() for r in out if r]
    event_rows = [n for n in ka.TABLE_NAMES if n.split(".")[0] in ("sys", "event")]
    assert len(rows) == len(event_rows) + 4  # the callees, K's four
    assert all(r[1:] == ["0", "False"] for r in rows), rows


_TYPED_FIRST = """
import numpy as np
from nsdyn.solve import _kgenalpha
from nsdyn.solve import _kcommon as ki
from nsdyn.solve.integrate import _tiny_problem
P, x0 = _tiny_problem()
t = np.linspace(0.0, 0.2, 5)
args = (t, np.full(x0.size, 1e-8), 1e-6, 1e-3, _kgenalpha.parameters(0, 0.9), 10**5,
        ki.UPLIFT_WARN, np.zeros((t.size, x0.size)), np.full(1, np.nan),
        np.full(x0.size // 2, np.nan))
try:
    _kgenalpha.genalpha_loop(P, x0, *args)
except RuntimeError as e:
    print("empty row:", "'sys.evaluate'" in str(e))
print("front:", _kgenalpha.genalpha(P, x0, *args)[0][0])
"""


@pytest.mark.skipif(not JIT, reason="declarations are read only when numba types a caller")
@no_table_in_plain_numba
def test_a_caller_typed_before_any_declaration_compiles():
    # a fresh process calls the generalized-alpha loop itself before anything declared its
    # callees: the declaration is made while typing (numba keeps a failed typing for good,
    # so the loop would never compile in that process), the empty table row raises a
    # RuntimeError naming the callee, and the front that fills the table then runs
    out = subprocess.run(
        [sys.executable, "-c", _TYPED_FIRST], capture_output=True, text=True, check=True
    ).stdout
    assert "empty row: True" in out and "front: 0" in out, out
