"""Each figure helper given another family's result, or no result, says what it draws (a
TypeError naming the argument and the result it expects), where it failed deep inside with an
AttributeError ('RockingResult' object has no attribute 'q'), a ValueError of dict() or a
'not subscriptable'."""

from __future__ import annotations

import matplotlib
import pytest

from nsdyn.plot.frames import sweep_figure
from nsdyn.plot.isolators import plane_figure
from nsdyn.plot.transient import plot_transient

matplotlib.use("Agg")


class _Other:
    """Stands for another family's result: a summary, none of the arrays drawn."""

    def summary(self) -> dict:
        return {}


@pytest.mark.parametrize("given", [_Other(), "x", None, {"t": [0.0]}])
def test_the_plane_figure_names_what_it_draws(given):
    with pytest.raises(TypeError, match=r"^result: expected a PlaneResult \(a deck's or "
                       r"building's run\) or deck\.npz's arrays \(t, q, u, N, "):  # fmt: skip
        plane_figure(given)


@pytest.mark.parametrize("given", [_Other(), None, "x"])
def test_the_transient_figure_names_what_it_draws(given):
    with pytest.raises(TypeError, match=r"^result: expected a TransientResult of an isolated "):
        plot_transient(given)


@pytest.mark.parametrize("given", [[_Other()], _Other(), None, [{"A": 1.0}]])
def test_the_sweep_figure_names_what_it_draws(given):
    with pytest.raises(TypeError, match=r"^results: expected frequency-response curves "):
        sweep_figure(given)


def test_the_sweep_figure_takes_any_iterable_of_curves_and_the_plane_figure_a_buildings_run():
    # a generator or a dict's values of curves drew before the guard (refused after it); a
    # building's run (run_building) holds its PlaneResult as .result
    rows = [{"f": f, "IDR": 1e-3, "a": 1.0, "x_iso": 0.01, "stable": True, "method": "shooting",
             "uplift": False, "stick_all_period": False} for f in (0.5, 1.0)]  # fmt: skip
    sweep_figure(r for r in [{"A": 1.0, "rows": rows}])
    sweep_figure({1.0: {"A": 1.0, "rows": rows}}.values())

    class Run:
        result = _Other()

    with pytest.raises(TypeError, match=r"^result: expected a PlaneResult"):
        plane_figure(Run())  # (its .result is read: here another family's)
