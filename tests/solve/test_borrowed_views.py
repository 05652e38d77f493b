"""Borrowed array views (``nsdyn._kborrow``): the run loops' arrays without reference counts.

A borrowed view must be the same memory as its owner, keep every member's dtype, shape and
strides, and leave the owners' reference counts as they were: a view that still carried a
memory-info block (or lost one it needed) would show as a changed count of the Python arrays
handed to a kernel, or as a crash. The loops' results are checked elsewhere (the flat-only
loop against the general one, every method against its reference solution); a borrowed loop
gives the same histories bit for bit as the reference-counted one did.
"""

import os
import sys

import numpy as np
import pytest
from numba import njit

from nsdyn import _kborrow as kb
from nsdyn.solve import _kcommon as ki
from nsdyn.solve import compile_split
from nsdyn.solve.integrate import _tiny_problem


@njit(cache=False)
def _write_through(a, t):
    b = kb.borrowed(a)
    u, (v, w) = kb.borrowed(t)  # a nested tuple
    b[1] = 7.0
    u[0, 1] = 2.0 + 3.0j
    v[2] = 5
    w[1] = -1.0
    kb.alive((a, t))
    return b.shape[0], u.shape[0], u.shape[1], w.strides[0]


def test_views_share_memory_and_layout():
    a = np.zeros(3)
    u = np.zeros((2, 2), dtype=np.complex128)
    v = np.zeros(4, dtype=np.int64)
    base = np.zeros(8)
    w = base[::2]  # a strided (non-contiguous) member
    got = _write_through(a, (u, (v, w)))
    assert got == (3, 2, 2, 16)
    assert a[1] == 7.0 and u[0, 1] == 2.0 + 3.0j and v[2] == 5 and base[2] == -1.0
    assert np.count_nonzero(a) == 1 and np.count_nonzero(base) == 1


def test_plain_python_fallback_is_the_identity():
    a = np.ones(2)
    assert kb.borrowed(a) is a
    assert kb.alive((a,)) is None


@pytest.mark.skipif(
    os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0"),
    reason="types are checked only when numba compiles",
)
def test_borrowing_something_else_is_a_typing_error():
    @njit(cache=False)
    def bad(x):
        return kb.borrowed(x)

    with pytest.raises(Exception, match="expected an array or a tuple of arrays"):
        bad(1.0)


def test_radau_loop_leaves_reference_counts_unchanged():
    # the loop borrows its arguments and its own workspace; after three runs every argument
    # array has the reference count it had before (nothing leaked, nothing released twice)
    P, x0 = _tiny_problem()
    t_eval = np.linspace(0.0, 0.5, 11)
    atol = np.full(x0.size, 1e-8)
    X = np.zeros((t_eval.size, x0.size))
    upl = np.full(1, np.nan)
    args = (P, x0, t_eval, atol, 1e-6, 0.0, np.inf, 100_000, False, ki.UPLIFT_WARN, X, upl)
    compile_split.radau_flat(*args)
    watched = (x0, t_eval, atol, X, upl) + tuple(P)
    before = [sys.getrefcount(a) for a in watched]
    for _ in range(3):
        stats, rinfo = compile_split.radau_flat(*args)
        assert stats[ki.S_STATUS] == ki.ST_SUCCESS
    del stats, rinfo
    assert [sys.getrefcount(a) for a in watched] == before
    # and the loop wrote its outputs through the borrowed views of X
    assert np.all(np.isfinite(X)) and np.any(X[-1] != x0)


def _owned(a) -> bool:
    # an array a kernel returns owns its memory through numba (base: its meminfo) or NumPy;
    # a borrowed view returned to Python would come back with neither (memory nobody owns)
    return a.base is not None or a.flags.owndata


def test_run_loops_return_only_owned_arrays():
    from nsdyn.periodic import _kperiodic as kp
    from nsdyn.periodic.discretisation import Discretisation
    from nsdyn.periodic.problem import periodic_calls
    from nsdyn.solve import _kdopri, _kgenalpha

    P, x0 = _tiny_problem()
    t_eval = np.linspace(0.0, 0.2, 5)
    atol = np.full(x0.size, 1e-8)
    upl = np.full(1, np.nan)
    X = np.zeros((t_eval.size, x0.size))
    got = list(
        compile_split.radau_flat(
            P, x0, t_eval, atol, 1e-6, 0.0, np.inf, 10**5, False, ki.UPLIFT_WARN, X, upl
        )
    )
    got += _kdopri.dopri5(
        P, x0, t_eval, atol, 1e-6, 0.0, np.inf, 10**6, False, ki.UPLIFT_WARN, X, upl
    )
    coef = _kgenalpha.parameters(_kgenalpha.FAMILY_GENALPHA, 0.9)
    got += _kgenalpha.genalpha(P, x0, t_eval, atol, 1e-6, 1e-3, coef, 10**5, ki.UPLIFT_WARN, X, upl)
    A, c = Discretisation().tableau()
    pf = np.array([0.05, 1.0, 0.1, 0.5, 1.2])  # Duffing: zeta, w0, gamma, F, w
    out = kp.period_map(kp.PROB_DUFFING, np.array([0.1, 0.0]), 5.0, 50, pf, A, c, True, True,
                        1e-9, 1e-13, periodic_calls())  # fmt: skip
    got += [a for a in out if isinstance(a, np.ndarray)]
    assert len(got) == 10
    assert all(_owned(a) for a in got)
