"""The stepped sweep's stagnation stop (nsdyn.periodic.sweeps.steady_state_sweep).

Exact period maps of a linear 2-state model ``x_(k+1) = x* + r (x_k - x*)`` (scalar r, per
period), so the change per period is known in closed form, ``delta_k = |r|^k delta_0``:

- r = -1 (a flip: the response alternates between two states, not period-1): delta never
  contracts, so the sweep must stop at the first stagnation test, period 2 SS_WINDOW, instead
  of running all SS_MAX_PERIODS, and say why;
- r = 0.95 from |x0 - x*| = 1: the change of period k is ``r^(k-1) (1 - r)``, relative to the
  orbit's excursion ``1 + r^(k-1)`` (from x_ref = 0), so the estimate ``delta r / (1 - r)``
  = ``r^k / (1 + r^(k-1))`` falls below tol = 1e-6 at k ≈ log(1e-6) / log r ≈ 270 periods,
  inside the 400 allowed: the stop must not fire and the sweep settles on x* to tol.
"""

import math

import numpy as np

from nsdyn.periodic import sweeps
from nsdyn.periodic.protocol import STATUS_OK, PeriodMap


class LinearMap:
    """``x -> x* + r (x - x*)`` each period; the orbit is the straight line between them."""

    def __init__(self, r: float):
        self.r = r
        self.x_ref = np.zeros(2)
        self.x_star = np.array([1.0, 1.0])
        self.amplitude = 1.0

    @property
    def dim(self) -> int:
        return 2

    def period_map(self, x0, f, *, n_steps=None, disc=None, sens=True, store=False):
        xT = self.x_star + self.r * (np.asarray(x0) - self.x_star)
        X = np.linspace(x0, xT, 5) if store else None
        M = self.r * np.eye(2) if sens else None
        return PeriodMap(xT, M, None, X, STATUS_OK, 4, 0, 0)


def test_a_flip_stops_at_the_first_stagnation_test():
    sw = sweeps.steady_state_sweep(LinearMap(-1.0), 1.0, np.array([0.0, 0.0]), monodromy=False)
    assert not sw.steady
    assert sw.periods == 2 * sweeps.SS_WINDOW < sweeps.SS_MAX_PERIODS
    assert "no longer contracts" in sw.message


def test_a_slow_contraction_inside_the_budget_still_settles():
    r = 0.95
    need = math.log(1e-6) / math.log(r)  # closed form, ≈ 269.3 periods
    assert need < sweeps.SS_MAX_PERIODS
    sw = sweeps.steady_state_sweep(LinearMap(r), 1.0, np.array([2.0, 2.0]), monodromy=False)
    assert sw.steady
    assert sw.periods == math.ceil(need)
    # x0 is the start of the last period: r^(k-1) |x0 - x*| from x*, ~1e-6
    assert np.max(np.abs(sw.x0 - np.array([1.0, 1.0]))) <= 2e-6
