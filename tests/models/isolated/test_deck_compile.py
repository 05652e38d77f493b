"""The deck's force kernel, settling and mode switch by address (deck_compile).

The time loops of the deck call the force kernel, the switch law's settling and its mode
switch through the process-wide address table: each compiles once, on its own, and a first
run shares the compilation with a helper process. The histories are those of the direct
calls bit for bit (tests/solve/test_plain_numba.py runs the deck in both modes); here: what is
compiled where.
"""

import os

import numpy as np
import pytest

from nsdyn import _kaddress as ka
from nsdyn._numba_cache import PLAIN
from nsdyn.models.isolated import Bearing, Friction, rigid_deck, simulate_plane
from nsdyn.models.isolated import deck_compile as dc

JIT = os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")


def test_the_deck_rows_are_registered_and_declared_for_the_loops():
    # each callee has a fixed row, a kernel to call without addresses and one declaration
    names = [c.name for c in dc.callees()]
    assert names == ["deck.evaluate", "deck.settle", "deck.switch"]
    assert set(names) <= set(ka.TABLE_NAMES) and set(names) <= set(ka.TSLOTS)
    assert all(ka.DECLARED[c.name] == (c.ret, c.args) for c in dc.callees())


@pytest.mark.skipif(not JIT or PLAIN, reason="the table is filled only for compiled code")
def test_a_regularised_run_fills_only_the_force_kernel_and_a_switch_run_all():
    # the regularised law's loops never settle: its run takes no address of the settling
    deck = rigid_deck(1.0e6, 5.0e7, [[-5.0, -3.0], [5.0, -3.0], [5.0, 3.0], [-5.0, 3.0]],
                      Bearing(Friction(0.05), radius=2.0))  # fmt: skip
    orbit = {"f": 0.5, "ax": 2.0, "ay": 1.0, "phase_y_deg": 90.0}
    saved = ka.TABLE.copy()
    try:
        ka.TABLE[ka.index("deck.settle")] = 0
        ka.TABLE[ka.index("deck.switch")] = 0
        simulate_plane(deck, orbit, law="arctan", t_end=0.2)
        assert ka.filled("deck.evaluate") and not ka.filled("deck.settle")
        assert not ka.filled("deck.switch")
        r = simulate_plane(deck, orbit, law="switch", t_end=0.2)
        assert ka.filled("deck.settle") and ka.filled("deck.switch")
        assert np.all(np.isfinite(r.q))
    finally:
        ka.TABLE[:] = saved


_LOOP_ALONE = """
import numpy as np
from numba import typeof
from nsdyn.models.isolated import _kplane as kp, _kplanerun as kr, deck as d
from nsdyn.models.isolated import deck_compile as dc
from nsdyn.models.isolated.bearings import Bearing, Friction
system = d.sdof_plane(1.0e5, Bearing(Friction(0.05), radius=2.0))
M, pos, bp, nd, sp = d.kernel_params(system, "switch", 1e4, 1e-4, None)
gk, gp, tab, dur = d.pack_ground({"f": 1.0, "ax": 1.0})
t_eval, hmax = d.run_grid(gk, gp, dur, 0.1, None, None, None)
b = d.run_buffers("switch", 1e4, 1e-6, (1e-8, 1e-8), hmax, 1000, t_eval.size, 1, 6)
args = (np.zeros(6), t_eval, *b[:2], M, pos, bp, nd, sp, gk, gp, tab, *b[2:])
args = (*args, *dc.loop_arrays(kr.integrate, 6, 1))
dc.callees()
kr.integrate.compile(tuple(typeof(a) for a in args))
lib = next(iter(kr.integrate.overloads.values())).library
linked = str({l.name for l in getattr(lib, "_linking_libraries", ())})
for k in (kp.evaluate, kp.evaluate_at, kr.settle, kr.switch):
    print(k.py_func.__qualname__, len(k.signatures), k.py_func.__qualname__ in linked)
"""


@pytest.mark.slow  # compiles the switch law's loop into an empty cache (~10 s)
@pytest.mark.skipif(not JIT or PLAIN, reason="calls by address only in compiled code")
def test_the_switch_loop_compiles_without_its_callees(compile_alone):
    # a fresh process with an empty cache compiles the loop alone: neither the force kernel
    # (nor what it calls) nor the settling nor the mode switch is compiled with it or linked
    # into its code
    rows = compile_alone(_LOOP_ALONE)
    names = ["evaluate", "evaluate_at", "settle", "switch"]
    assert [r[0] for r in rows] == names
    assert all(r[1:] == ["0", "False"] for r in rows), rows
