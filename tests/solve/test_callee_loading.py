"""A loop's callees are in the process before the loop (nsdyn.solve.compile_split.load_callees).

numba links a copy of every callee into a loop's code; a loop loaded from the on-disk cache
calls those copies unless the callees' own code is loaded first, and for the default loop that
made the run ~15 % slower than in the process that compiled it (README, "Where a cached loop's
calls go"). The speed is the benchmark's to show; this checks the order that gives it.
"""

from nsdyn.solve import _kcommon as ki
from nsdyn.solve import _kradau, compile_split, methods


def test_default_loop_runs_after_its_callees_are_loaded(monkeypatch):
    # a process's first default run loads Newton and the flat right-hand side (the helper's
    # part of the first compilation, called here on the tiny problem) before the loop, once
    order = []
    monkeypatch.setattr(compile_split, "_CALLEES_LOADED", set())
    part, loop = compile_split.radau_helper_part, _kradau.radau_flat

    def spy_part():
        order.append("callees")
        part()

    def spy_loop(*args):
        order.append("loop")
        return loop(*args)

    monkeypatch.setattr(compile_split, "radau_helper_part", spy_part)
    monkeypatch.setattr(_kradau, "radau_flat", spy_loop)
    m = methods.METHODS["radau"]
    for _ in range(2):
        P, x0, t_eval, o, X, upl_t = methods.tiny_run(m)
        stats, _, _, _ = m.run(P, x0, t_eval, o, X, upl_t)
        assert stats[ki.S_STATUS] == ki.ST_SUCCESS
    assert order == ["callees", "loop", "loop"]
