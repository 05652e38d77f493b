"""The pair systems' force kernel and settlings by address (pairs_compile).

The time loops of a pair system (a 3D building's cb and full rungs, any PairSystem) call the
force kernel and the two settlings (stick, unilateral contacts) through the process-wide
address table: each compiles once, on its own, and a first run shares the compilation with a
helper process. The histories are those of the direct calls bit for bit
(tests/solve/test_plain_numba.py runs pair systems in both modes); here: what is registered,
what a run fills, and what is compiled where.
"""

import os

import numpy as np
import pytest

from nsdyn import _kaddress as ka
from nsdyn._numba_cache import PLAIN
from nsdyn.models.isolated import Bearing, Friction, rigid_deck
from nsdyn.models.isolated import _kpairs as kq
from nsdyn.models.isolated import _kpairscontact as kc
from nsdyn.models.isolated import _kpairsradau as kqa
from nsdyn.models.isolated import _kpairsrun as kqr
from nsdyn.models.isolated import _kplaneradau as krad
from nsdyn.models.isolated import pairs_compile as pc
from nsdyn.models.isolated.pairs import from_deck, simulate_pairs

JIT = os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")
NAMES = ["pairs.evaluate", "pairs.outputs", "pairs.settle", "pairs.settle_contacts",
         "pairs.initial_modes", "pairs.factor_real", "pairs.factor_complex", "pairs.solve_real",
         "pairs.solve_complex", "pairs.proportional_split", "pairs.least_norm",
         "pairs.stick_basis", "pairs.begin", "pairs.emit", "pairs.track_stops", "pairs.rhs",
         "pairs.jacobian", "pairs.dense", "pairs.switch", "pairs.locate_event",
         "pairs.locate_uplift", "pairs.land", "pairs.start_direction"]  # fmt: skip
# the force kernel with its least-norm solve by address, the outputs, the loops' start and
# output step, the rim contacts' tracking and the right-hand side: both loops call them
FORCE = ["pairs.evaluate", "pairs.least_norm", "pairs.outputs", *NAMES[12:16]]
# the Radau loop's: and the LU of σ I - J, the Jacobian, the dense output
RADAU = FORCE + NAMES[5:9] + NAMES[16:18]
# the event loop's: and the force kernel's stick rows (switch law only), the settlings, the
# initial modes, the mode switch, the location of events and of uplift, the start direction;
# with unilateral contacts also their landing
EVENTS = FORCE + ["pairs.stick_basis", "pairs.proportional_split", *NAMES[2:5], *NAMES[18:21],
                  "pairs.start_direction"]  # fmt: skip
LANDING = EVENTS + ["pairs.land"]


def test_the_pair_rows_are_registered_and_declared_for_the_loops():
    # each callee has a fixed row, a kernel to call without addresses and one declaration
    assert [c.name for c in pc.callees()] == NAMES
    assert set(NAMES) <= set(ka.TABLE_NAMES) and set(NAMES) <= set(ka.TSLOTS)
    assert all(ka.DECLARED[c.name] == (c.ret, c.args) for c in pc.callees())
    # what a run compiles: the Radau loop, the force kernel, the outputs and the factorisation
    # and solve (for real and complex σ); the event loop and the settlings and initial modes
    byname = {c.name: c.kernel for c in pc.callees()}
    assert pc.kernels(False) == [kqa.integrate, *(byname[n] for n in RADAU)]
    assert pc.kernels(True) == [kqr.integrate, *(byname[n] for n in EVENTS)]
    assert [byname[n] for n in NAMES[5:9]] == [kqa._factor, kqa._factor, kqa._solve, kqa._solve]
    assert [byname[n] for n in NAMES[9:12]] == [kq.proportional_split, kq.least_norm,
                                                 kq.stick_basis]  # fmt: skip
    assert [byname[n] for n in NAMES[12:]] == [kqr.begin, kqr.emit, kc.track_stops, kq.rhs,
                                                kqa._jacobian, krad._dense, kqr.switch,
                                                kqr.locate_event, kqr.locate_uplift, kc.land,
                                                kq.start_direction]  # fmt: skip
    assert pc.kernels(True, True) == [kqr.integrate, *(byname[n] for n in LANDING)]
    for events, uni in ((False, False), (True, False), (True, True)):
        # a first run's two shares: each callee compiled once, the landing here
        here, there = pc._here(events, uni), pc._helper(events)
        names = sorted(c.name for c in pc._needed(events, uni))
        assert sorted(c.name for c in here + there) == names
        assert ("pairs.land" in names) == uni and "pairs.land" not in [c.name for c in there]


@pytest.mark.skipif(not JIT or PLAIN, reason="the table is filled only for compiled code")
def test_a_radau_run_and_an_event_run_fill_only_the_rows_of_their_callees():
    # the Radau loop never settles stick or contacts, nor starts the switch law's modes, nor
    # has stuck isolators (the regularised law only): its run takes no address of a settling,
    # of the initial modes or of the force kernel's stick rows; the event loop takes none of
    # the Radau loop's factorisations
    deck = rigid_deck(1.0e6, 5.0e7, [[-5.0, -3.0], [5.0, -3.0], [0.0, 4.0]],
                      Bearing(Friction(0.05), radius=2.0))  # fmt: skip
    ps = from_deck(deck)
    orbit = {"f": 0.5, "ax": 2.0, "ay": 1.0, "phase_y_deg": 90.0}
    saved = ka.TABLE.copy()
    try:
        for name in NAMES:
            ka.TABLE[ka.index(name)] = 0
        simulate_pairs(ps, orbit, law="arctan", t_end=0.2)
        assert [ka.filled(n) for n in NAMES] == [n in RADAU for n in NAMES]
        for name in NAMES:
            ka.TABLE[ka.index(name)] = 0
        r = simulate_pairs(ps, orbit, law="switch", t_end=0.2)
        assert [ka.filled(n) for n in NAMES] == [n in EVENTS for n in NAMES]
        assert np.all(np.isfinite(r.q))
        for name in NAMES:
            ka.TABLE[ka.index(name)] = 0
        simulate_pairs(ps, orbit, law="switch", t_end=0.2, contact="unilateral")
        assert [ka.filled(n) for n in NAMES] == [n in LANDING for n in NAMES]
    finally:
        ka.TABLE[:] = saved


_ALONE = """
import numpy as np
from numba import typeof
from nsdyn._klinalg import lu_factor, lu_solve
from nsdyn.models.isolated import _kpairs as kq, _kpairscontact as kc, _kpairsrun as kqr
from nsdyn.models.isolated import _kpairsstick as kst
from nsdyn.models.isolated import _kpairsradau as kqa, deck as d, pairs_compile as pc
from nsdyn.models.isolated import _kplaneradau as krad
from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.pairs import _kernel_inputs, from_deck
ps = from_deck(d.rigid_deck(1.0e6, 5.0e7, [[-5.0, -3.0], [5.0, -3.0], [0.0, 4.0]],
                            Bearing(Friction(0.05), radius=2.0)))
sp = _kernel_inputs(ps, LAW, 1e4, 1e-4, None, 20.0, 1.0)
gk, gp, tab, dur = d.pack_ground({"f": 1.0, "ax": 1.0})
t_eval, hmax = d.run_grid(gk, gp, dur, 0.1, None, None, None)
b = d.run_buffers(LAW, 1e4, 1e-6, (1e-8, 1e-8), hmax, 1000, t_eval.size, 3, 2 * ps.n)
args = (np.zeros(2 * ps.n), t_eval, *b[:2], ps.operators(), ps.bearing_table(), sp, gk, gp,
        tab, *b[2:], pc.loop_arrays(LOOP, 2 * ps.n, ps.n, 3))
pc.callees()
LOOP.compile(tuple(typeof(a) for a in args))
lib = next(iter(LOOP.overloads.values())).library
linked = str({l.name for l in getattr(lib, "_linking_libraries", ())})
for k in KERNELS:
    print(k.py_func.__qualname__, len(k.signatures), k.py_func.__qualname__ in linked)
"""


def _loop_alone(law: str, loop: str, kernels: str) -> str:
    """The code of a process that compiles the pair loop ``loop`` alone (a rigid deck on three
    friction pendulums, ``law``) and prints, for each kernel of ``kernels``, its name, how
    many signatures it has compiled and whether the loop's code links it."""
    return _ALONE.replace("LAW", repr(law)).replace("LOOP", loop).replace("KERNELS", kernels)


_LOOP_ALONE = _loop_alone("switch", "kqr.integrate",
                          "(kq.evaluate, kq.evaluate_at, kst.settle, kc.settle_contacts, "
                          "kst.initial_modes, kqr.begin, kqr.emit, kq.rhs, kqr.switch, "
                          "kqr.locate_event, kqr.locate_uplift, kc.land, "
                          "kq.start_direction)")  # fmt: skip
_RADAU_ALONE = _loop_alone("arctan", "kqa.integrate",
                           "(kqa._factor, kqa._solve, lu_factor, lu_solve, kqr.begin, kqr.emit, "
                           "kc.track_stops, kq.rhs, kqa._jacobian, krad._dense)")  # fmt: skip


_FORCE_ALONE = """
from nsdyn._klinalg import lu_factor, pinv_small
from nsdyn.models.isolated import _kpairs as kq, pairs_compile as pc
cres = pc.callees()[0].compiled()  # the force kernel, for the loops' types
linked = str({l.name for l in getattr(cres.library, "_linking_libraries", ())})
for k in (kq.proportional_split, kq.least_norm, lu_factor, pinv_small, kq.stick_basis):
    print(k.py_func.__qualname__, len(k.signatures), k.py_func.__qualname__ in linked)
"""


@pytest.mark.slow  # compiles the force kernel of a pair system into an empty cache (~8 s)
@pytest.mark.skipif(not JIT or PLAIN, reason="calls by address only in compiled code")
def test_the_force_kernel_compiles_without_its_rarer_solves_and_stick_basis(compile_alone):
    # the proportional split (redundant stick rows), the least-norm solve and the stick basis
    # (an SVD) are called by address: compiling the force kernel alone compiles none of them,
    # nor the pseudo-inverse; the LU it calls itself is compiled
    rows = compile_alone(_FORCE_ALONE)
    names = ["proportional_split", "least_norm", "lu_factor", "pinv_small", "stick_basis"]
    assert [r[0] for r in rows] == names
    assert [r[1] for r in rows] == ["0", "0", "1", "0", "0"], rows


@pytest.mark.slow  # compiles the Radau loop of a pair system into an empty cache (~10 s)
@pytest.mark.skipif(not JIT or PLAIN, reason="calls by address only in compiled code")
def test_the_radau_loop_compiles_without_its_factorisation_and_solve(compile_alone):
    # a fresh process with an empty cache compiles the Radau loop alone: the factorisation and
    # solve of σ I - J (nor the LU they call), the loop's start and output step, the rim
    # contacts' tracking, the right-hand side, the Jacobian and the dense output are neither
    # compiled with it nor linked into it
    rows = compile_alone(_RADAU_ALONE)
    names = ["_factor", "_solve", "lu_factor", "lu_solve", "begin", "emit", "track_stops", "rhs",
             "_jacobian", "_dense"]  # fmt: skip
    assert [r[0] for r in rows] == names
    assert all(r[1:] == ["0", "False"] for r in rows), rows


@pytest.mark.slow  # compiles the event loop of a pair system into an empty cache (~25 s)
@pytest.mark.skipif(not JIT or PLAIN, reason="calls by address only in compiled code")
def test_the_event_loop_compiles_without_its_callees(compile_alone):
    # a fresh process with an empty cache compiles the loop alone: neither the force kernel
    # (nor what it calls) nor either settling nor the initial modes is compiled with it or
    # linked into its code, nor its start, output step, right-hand side, mode switch (with the
    # landing and the start direction it calls) and location of events and of uplift
    rows = compile_alone(_LOOP_ALONE)
    names = ["evaluate", "evaluate_at", "settle", "settle_contacts", "initial_modes", "begin",
             "emit", "rhs", "switch", "locate_event", "locate_uplift", "land",
             "start_direction"]  # fmt: skip
    assert [r[0] for r in rows] == names
    assert all(r[1:] == ["0", "False"] for r in rows), rows


def _slow_warm(calls: list, fail: bool = False):
    import time

    def warm(path, law, contact="detect"):
        time.sleep(0.2)
        calls.append((path, law) if contact == "detect" else (path, law, contact))
        if fail:
            raise RuntimeError("warm-up failed")
        return 0.2

    return warm


def _warm_threads() -> list:
    import threading

    return [t for t in threading.enumerate() if t.name == "nsdyn-warm-pairs"]


def test_the_warm_up_beside_a_build_is_waited_for_even_when_the_build_fails(monkeypatch):
    # a scene's first run compiles the pair kernels on a thread while its model builds: the
    # build's error comes out only once the thread has ended (no compiling thread at exit)
    from nsdyn.models.isolated import building3d_pairs_run as bpr

    calls: list = []
    monkeypatch.setattr(bpr, "warm_pairs", _slow_warm(calls))
    monkeypatch.setattr("nsdyn._numba_cache.all_cached", lambda ks: False)
    with pytest.raises(ValueError, match="bad frame"):
        with bpr.warming("dense", "switch"):
            raise ValueError("bad frame")
    assert calls == [("dense", "switch")] and not _warm_threads()
    with bpr.warming("sparse", "arctan") as times:
        pass  # the build ends before the warm-up: its wait is the warm-up's rest
    assert calls[-1] == ("sparse", "arctan") and times["compile_s"] == 0.2
    assert 0.0 < times["wait_s"] and not _warm_threads()
    # unilateral contacts warm the loop with located events and the landing; a contact the run
    # does not take warms the default's (the run's check names the bad one)
    for contact in ("unilateral", "sideways"):
        with bpr.warming("dense", "arctan", contact):
            pass
    assert calls[-2:] == [("dense", "arctan", "unilateral"), ("dense", "arctan")]


def test_the_warm_up_s_error_is_raised_and_nothing_starts_when_not_needed(monkeypatch):
    from nsdyn.models.isolated import building3d_pairs_run as bpr

    calls: list = []
    monkeypatch.setattr(bpr, "warm_pairs", _slow_warm(calls, fail=True))
    monkeypatch.setattr("nsdyn._numba_cache.all_cached", lambda ks: False)
    with pytest.raises(RuntimeError, match="warm-up failed"):
        with bpr.warming("dense", "arctan"):
            pass
    # a law the path does not take (the run's check names it) or kernels already cached
    for path, law in (("dense", "coulomb"), ("sparse", "switch")):
        with bpr.warming(path, law) as times:
            pass
        assert times == {"compile_s": 0.0, "wait_s": 0.0}
    monkeypatch.setattr("nsdyn._numba_cache.all_cached", lambda ks: True)
    with bpr.warming("dense", "arctan"):
        pass
    assert calls == [("dense", "arctan")]
