"""A run's output times: every dt_out from the start, and the end itself.

Exact rules (``nsdyn._checks.output_times``): the grid is t0 + k dt_out; where it misses the
end by more than min(SNAP of the run, 1e-3 dt_out) the end is appended (a last interval
shorter than dt_out); where it misses it by less, the rounding of a step that divides the
run, its last sample is the end. A float32 0.02 s (0.0199999996) over 10 s left 9.9999998 and
10.0 as the last two samples, 2e-7 s apart (a float32 step errs by 6e-8 of itself, so n steps
reach the end within n 6e-8 dt_out = 6e-8 of the run: far inside SNAP = 1e-6).
"""

from __future__ import annotations

import numpy as np
import pytest

from nsdyn._checks import SNAP, output_times


@pytest.mark.parametrize("dt_out", [0.02, float(np.float32(0.02)), 0.1, float(np.float32(0.1))])
def test_a_step_that_divides_the_run_ends_on_its_end_once(dt_out):
    t = output_times(0.0, 10.0, dt_out)
    assert t.size == round(10.0 / dt_out) + 1 and t[0] == 0.0 and t[-1] == 10.0
    assert np.diff(t).min() > dt_out - SNAP * 10.0  # no sample a rounding error from another


def test_a_step_that_does_not_divide_the_run_ends_with_a_shorter_interval():
    t = output_times(0.0, 10.0, 0.033)  # 303 steps of 0.033 s reach 9.999 s
    assert t.size == 305 and t[-2] == pytest.approx(9.999, abs=1e-12) and t[-1] == 10.0
    t = output_times(0.0, 0.100005, 0.01)  # an end 5e-5 of the run past the grid: kept apart
    assert t.size == 12 and t[-2] == pytest.approx(0.1, abs=1e-15) and t[-1] == 0.100005
    t = output_times(0.0, 1000.0009, 0.01)  # 0.09 dt past the grid: a sample of its own, on a
    assert t.size == 100002 and t[-1] == 1000.0009  # long run too (within SNAP of 1000 s)
    assert t[-2] == pytest.approx(1000.0, abs=1e-9)
