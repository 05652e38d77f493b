"""``nsdyn bench NAME --no-figures`` reaches every benchmark that draws a chart: each module whose
source saves a figure lists ``figures`` among its OPTIONS (the command line passes only those)
and its run_bench takes ``figures``, True by default. Checked on the modules' source and
signatures, without running the (slow) benchmarks."""

from __future__ import annotations

import inspect

import pytest

from nsdyn.bench import BENCHMARKS, BenchmarkUnavailable, load_benchmark


@pytest.mark.parametrize("name", list(BENCHMARKS))
def test_benchmarks_that_save_figures_take_the_figures_option(name):
    try:
        module = load_benchmark(name)
    except BenchmarkUnavailable as e:
        pytest.skip(f"benchmark {name!r} unavailable: {e}")
    if "save_figure(" not in inspect.getsource(module):
        pytest.skip(f"benchmark {name!r} saves no figure")
    assert "figures" in getattr(module, "OPTIONS", ()), name
    params = inspect.signature(module.run_bench).parameters
    assert "figures" in params, name
    assert params["figures"].default is True, name
