"""The NumPy/SciPy baseline integrates the same equations as the numba kernel."""

from __future__ import annotations

import numpy as np
import pytest

from nsdyn.bench import baseline, common
from nsdyn.models.isolated.system import build_system


@pytest.fixture(scope="module")
def frame():
    return common.bench_frame()


@pytest.fixture(scope="module")
def cb5(frame):
    return build_system(frame, common.bench_isolation(), fidelity="cb", f_max=5.0)


def test_numpy_equations_equal_the_numba_kernel(cb5, frame):
    """The SciPy baseline integrates the same equations: rhs and Jacobian equal the kernel's
    to round-off (1e-12 relative) at random states, for CB-5 and the rigid model."""
    from nsdyn.models.isolated import _kernel as ks

    motion = common.bench_motion("wn", 5.0)
    rng = np.random.default_rng(1)
    for system in (cb5, build_system(frame, common.bench_isolation(), fidelity="rigid")):
        fun, jac = baseline.numpy_equations(system, motion)
        P = system.params(motion)
        x0, _ = system.static_equilibrium()
        n = system.n
        for t in (0.0, 1.234, 2.805):
            x = x0 + np.concatenate([1e-2 * rng.normal(size=n), 1e-3 * rng.normal(size=n)])
            f = np.empty(2 * n)
            J = np.empty((2 * n, 2 * n))
            ks.rhs(t, x, P, f)
            ks.jac(t, x, P, J)
            assert np.max(np.abs(fun(t, x) - f)) <= 1e-12 * np.max(np.abs(f))
            assert np.max(np.abs(jac(t, x) - J)) <= 1e-12 * np.max(np.abs(J))
