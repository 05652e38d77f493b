"""Kernels compiled without reference counts (``nsdyn._kaddress.NO_NRT``).

The default Radau loop and the event loop, with their step, start-up, Newton and event
kernels, the sweep's step, and the deck's two time loops (Dormand–Prince under the switch law,
with its settling and mode switch; Radau IIA under the regularised law, with a triple friction
pendulum's internal slips) with the deck's force kernel are compiled without numba's
reference counting: they must
allocate no array and keep none that a counted callee returns, since nothing would free it.
numba's runtime counts every allocation and free of compiled code (its NRT statistics): over a
run, after the one that compiled the kernels, the two counts must grow alike. The histories
are those of the counted code bit for bit (``tests/solve/test_plain_numba.py``).
"""

import gc
import os

import pytest

JIT = os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")


def _counts():
    from numba.core.runtime import rtsys

    s = rtsys.get_allocation_stats()
    return s.alloc, s.free, s.mi_alloc, s.mi_free


@pytest.fixture
def nrt_stats():
    from numba.core.runtime import _nrt_python  # the statistics' switch (numba >= 0.57)

    was = _nrt_python.memsys_stats_enabled()
    _nrt_python.memsys_enable_stats()
    yield
    if not was:
        _nrt_python.memsys_disable_stats()


def _run(case: str) -> None:
    import numpy as np

    import nsdyn
    from nsdyn.ground.excitation import Harmonic
    from nsdyn.models.isolated import Isolation, system_from_matrices
    from nsdyn.models.isolated.scene import build_scene, load_scene
    from nsdyn.periodic import frame_problem, shoot
    from nsdyn.solve.integrate import solve

    if case.startswith("deck"):  # a deck on four pendulums: stick, break-away, settling
        import tomllib
        from pathlib import Path

        from nsdyn.models.isolated import deck_scene as ds
        from nsdyn.models.isolated.deck import simulate_plane

        name, law = ("deck-tfp4-3c", "arctan") if case == "deck-tfp" else ("deck-fps4-3c", "switch")
        path = Path(__file__).parents[2] / "examples" / "scenes" / f"{name}.toml"
        cfg = tomllib.loads(path.read_text())
        system, (motion, _) = ds.build_system(cfg, name), ds.build_motion(cfg, name)
        r = simulate_plane(system, motion, law=law, t_end=1.5)
        assert r.stats["steps"] > 0 and (law == "arctan" or r.stats["events"] > 0)
        return
    frame, _ = build_scene(load_scene(None))
    if case == "sweep":  # the period map's step
        assert shoot(frame_problem(frame, 0.5), 2.0).converged
    elif case == "unilateral":  # a block lifting off two isolators: the contact events too
        M, Z = np.diag([1000.0, 1000.0, 500.0]), np.zeros((3, 3))
        block = system_from_matrices(
            M, Z, Z, iso_dofs=[[1, 0, 0], [1, 0, 0]], influence=[[1, 0], [0, 1], [0, 0]],
            isolation=Isolation(k_lam=5e4, c=1e3, mu=0.1, law="switch"),
            contact_rows=[[0, 1, -1.0], [0, 1, 1.0]],
        )  # fmt: skip
        x0, _ = block.static_equilibrium()
        P = block.params(Harmonic(0.0, 0.0, A_ver=1.5 * 9.81, f_ver=2.0))
        sol = solve(P, x0, np.linspace(0.0, 0.75, 151), method="event", contact="unilateral",
                    restitution=0.5, rtol=1e-8, atol=1e-10)  # fmt: skip
        assert len(sol.contact_events) > 0
    else:
        if case == "event":
            frame = frame.with_isolation(law="switch")
        run = nsdyn.simulate(frame, Harmonic(0.5, 2.0), method=case, t_end=2.0)
        assert run.n_steps > 0  # the loop ran


@pytest.mark.skipif(not JIT, reason="no compiled code under NUMBA_DISABLE_JIT")
@pytest.mark.parametrize("method", ["radau", "event", "unilateral", "sweep", "deck", "deck-tfp"])
def test_a_run_frees_every_array_compiled_code_allocates(nrt_stats, method):
    _run(method)  # compiles (or loads) the kernels, fills the process's caches
    gc.collect()
    before = _counts()
    _run(method)
    gc.collect()
    after = _counts()
    alloc, free, mi_alloc, mi_free = (b - a for a, b in zip(before, after, strict=True))
    assert alloc == free and mi_alloc == mi_free, (alloc, free, mi_alloc, mi_free)
