"""The default run's flat-only Radau loop (``_kradau.radau_flat``) and its fallback.

A smooth law with closed contacts runs through a loop that never compiles the general right-
hand side; where the flat form fails (a singular constraint matrix) the run is repeated
through the general loop, which computes the same steps where both apply.
"""

import os
import subprocess
import sys

import numpy as np
import pytest

from nsdyn.models.isolated.system import Isolation, build_system
from nsdyn.solve import _kcommon as ki
from nsdyn.solve import _kradau, compile_split, methods
from nsdyn.solve.transient import simulate
from nsdyn.structure import load_frame


@pytest.fixture(scope="module")
def system():
    return build_system(load_frame("office-11"), Isolation(), fidelity="cb")


def _args(P, x0, t_eval):
    n2 = x0.size
    atol = np.full(n2, 1e-6)
    return (P, x0, t_eval, atol, 1e-4, 0.0, np.inf, 100_000, False, ki.UPLIFT_WARN)


def test_flat_loop_equals_general_loop(system):
    # the two loops share the stepper; with the flat kernel applicable they take the same
    # steps through the same arithmetic, so the histories and counters are identical
    from nsdyn.ground import read_motion

    P = system.params(read_motion("synthetic-wn-40s").window(0.0, 2.0))
    x0, _ = system.static_equilibrium()
    t_eval = np.linspace(0.0, 2.0, 101)
    Xa, Xb = np.zeros((101, x0.size)), np.zeros((101, x0.size))
    nc = system.n_contacts
    ua, ub = np.full(nc, np.nan), np.full(nc, np.nan)
    sa, _ = compile_split.radau_flat(*_args(P, x0, t_eval), Xa, ua)
    sb, _ = _kradau.radau(*_args(P, x0, t_eval), Xb, ub, True)
    assert sa[ki.S_STATUS] == ki.ST_SUCCESS
    assert np.array_equal(sa, sb)
    assert np.array_equal(Xa, Xb)


def test_kernel_choice(system):
    # the flat loop serves smooth laws with closed contacts; the switch law needs the general
    P = system.params()
    assert methods.kernel_for("radau", P) == "radau"
    assert methods.kernel_for("radau", system.params(law="switch")) == "radau-general"
    assert methods.kernel_for("radau-generic", P) == "radau-general"
    assert methods.kernel_for("dopri5", P) == "dopri5"
    # the metrics: the flat ones after the flat loop (which compiled the flat right-hand side),
    # the general ones (the system kernel by address) after every loop that compiles or calls
    # the system kernel
    assert methods.metrics_for("radau") == "metrics"
    for kernel in ("radau-general", "dopri5", "genalpha", "event", "genalpha-lowrank"):
        assert methods.metrics_for(kernel) == "metrics-general"


def test_singular_flat_run_is_repeated_by_the_general_loop(system, monkeypatch):
    # a flat run that stops on a singular G leaves garbage behind; the runner clears it and
    # runs again with the general kernel (minimum-norm split): the result equals a run of
    # the general loop directly, and no uplift from the aborted attempt survives
    from nsdyn.ground import read_motion

    motion = read_motion("synthetic-wn-40s").window(0.0, 1.0)
    real = compile_split.radau_flat

    def stops_singular(P, x0, t_eval, *rest):
        X, upl_t = rest[-2], rest[-1]
        stats, rinfo = real(P, x0, t_eval, *rest)
        X[:] = 1e9
        upl_t[:] = 0.5
        stats[ki.S_STATUS] = ki.ST_SINGULAR
        return stats, rinfo

    ref = simulate(system, motion, method="radau", uplift="warn")
    monkeypatch.setattr(compile_split, "radau_flat", stops_singular)
    got = simulate(system, motion, method="radau", uplift="warn")
    assert np.array_equal(got.x, ref.x)  # same steps: the general loop evaluates flat too
    assert not got.uplift


# counts, in the process, the compilations of numba's message for a slice assigned from an
# array of another shape (``a[:] = b``): string formatting compiled once per dimension, ~2-3 s
# each in an empty cache; the default run's and the period map's kernels copy by loops
COUNT_SHAPE_MESSAGES = (
    "from numba.core import event as ev\n"
    "seen = []\n"
    "class L(ev.Listener):\n"
    "    def on_start(self, e): seen.append(e.data['dispatcher'].py_func.__qualname__)\n"
    "    def on_end(self, e): pass\n"
    "ev.register('numba:compile', L())\n"
)
SHAPE_MESSAGES = "print(sum('raise_with_shape_context' in q for q in seen))\n"


def _fresh(code: str, tmp_path) -> list[str]:
    # no compile helper: every kernel compiles in this one process, where the events are seen
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), NUMBA_DISABLE_JIT="0")
    env["NSDYN_COMPILE_HELPER"] = "0"
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    return out.stdout.split()


@pytest.mark.slow
def test_default_run_never_compiles_the_general_kernel(tmp_path):
    # A fresh process with an empty numba cache compiles what the default run's warm-up
    # needs; the general right-hand side, its Jacobian and the general loop stay untouched
    # (dispatchers without a compiled signature), and so does the slice-assignment message.
    # ~1-2 min of compilation.
    code = (
        COUNT_SHAPE_MESSAGES
        + (
            "from nsdyn.solve import methods, _kcommon as ki, _kradau as kr\n"
            "from nsdyn.models.isolated import _kernel as ks\n"
            "methods.warmup(['radau']); methods.warmup_metrics()\n"
            "print(len(ks.evaluate.signatures), len(ks.jac.signatures),"
            " len(ki.feval_called.signatures), len(kr.radau_general.signatures),"
            " len(kr.radau_flat.signatures))\n"
        )
        + SHAPE_MESSAGES
    )
    assert _fresh(code, tmp_path) == ["0", "0", "0", "0", "1", "0"]


@pytest.mark.slow
def test_period_map_compiles_no_slice_assignment_message(tmp_path):
    # the sweep's kernels (period map, SDIRK step, flat right-hand side and Jacobian) in a
    # fresh process with an empty cache: ~0.5-1 min of compilation
    code = (
        COUNT_SHAPE_MESSAGES
        + ("from nsdyn.periodic import problem\nproblem.warmup()\n")
        + SHAPE_MESSAGES
    )
    assert _fresh(code, tmp_path) == ["0"]
