"""Property tests of ground-motion transformations (hypothesis).

Sources: linear interpolation reproduces the samples it interpolates (so refining a grid by an
integer factor and coming back is the identity, up to the round-off of the grid positions);
the trapezoidal velocity of a constant acceleration is exact; windowing keeps the samples it
keeps.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from nsdyn.ground import GroundMotion

samples = arrays(
    float,
    st.integers(4, 200),
    elements=st.floats(-20.0, 20.0, allow_nan=False, allow_infinity=False),
)
dts = st.sampled_from([0.005, 0.01, 0.02, 0.05])

# arbitrary samples, tiny peaks among them, are meant here: not a record typed in g
pytestmark = pytest.mark.filterwarnings("ignore::nsdyn.ground.motion.UnitWarning")


@settings(max_examples=60, deadline=None)
@given(a=samples, dt=dts, k=st.integers(2, 8))
def test_linear_refinement_and_back_is_the_identity(a, dt, k):
    m = GroundMotion(t0=0.0, dt=dt, a_hor=a)
    back = m.resampled(dt / k, method="linear").resampled(dt, method="linear")
    assert back.n == m.n
    scale = max(1.0, float(np.max(np.abs(a))))
    assert np.allclose(back.a_hor, a, rtol=0.0, atol=1e-9 * scale)


@settings(max_examples=60, deadline=None)
@given(a=samples, dt=dts, k=st.integers(2, 8))
def test_linear_refinement_keeps_the_original_samples(a, dt, k):
    fine = GroundMotion(t0=0.0, dt=dt, a_hor=a).resampled(dt / k, method="linear")
    scale = max(1.0, float(np.max(np.abs(a))))
    assert np.allclose(fine.a_hor[::k][: a.size], a, rtol=0.0, atol=1e-9 * scale)


@given(c=st.floats(-10.0, 10.0), dt=dts, n=st.integers(2, 300))
def test_velocity_of_a_constant_acceleration_is_exact(c, dt, n):
    m = GroundMotion(t0=0.0, dt=dt, a_hor=np.full(n, c))
    v = m.velocity()
    assert np.allclose(v, c * dt * np.arange(n), rtol=1e-12, atol=1e-12)


@given(a=samples, dt=dts, i=st.integers(0, 3), j=st.integers(0, 3))
def test_window_keeps_its_samples(a, dt, i, j):
    m = GroundMotion(t0=0.0, dt=dt, a_hor=a)
    lo, hi = i, a.size - 1 - j
    assume(hi > lo)
    w = m.window(lo * dt, hi * dt)
    assert np.array_equal(w.a_hor, a[lo : hi + 1])
