"""``nsdyn bench NAME --no-figures`` reaches every benchmark that draws a chart: each module whose
source saves a figure lists ``figures`` among its OPTIONS (the command line passes only those)
and its run_bench takes ``figures``, True by default. Checked on the modules' source and
signatures, without running the (slow) benchmarks."""

from __future__ import annotations

import importlib.util
import inspect
from pathlib import Path

import pytest

from nsdyn.bench import BENCHMARKS, BenchmarkUnavailable, load_benchmark


def _draws(module: str) -> bool:
    """The module's source saves a figure (read from its file: nothing imported)."""
    return "save_figure(" in Path(importlib.util.find_spec(module).origin).read_text()


DRAWING = [name for name, module in BENCHMARKS.items() if _draws(module)]


def test_the_drawing_benchmarks_are_found():
    # charts the guides show (rocking.md, contact.md, cylinder.md, full-models-and-scale.md);
    # accuracy, fidelity, periodic, speed and stability draw through nsdyn.bench.common and
    # took ``figures`` before this check existed
    assert {"rocking", "contact", "cylinder", "scale"} <= set(DRAWING)


@pytest.mark.parametrize("name", DRAWING)
def test_benchmarks_that_save_figures_take_the_figures_option(name):
    try:
        module = load_benchmark(name)
    except BenchmarkUnavailable as e:  # an optional extra it imports is not installed
        pytest.skip(f"benchmark {name!r} unavailable here: {e}")
    assert "figures" in getattr(module, "OPTIONS", ()), name
    params = inspect.signature(module.run_bench).parameters
    assert "figures" in params, name
    assert params["figures"].default is True, name


def test_an_interrupted_chart_leaves_no_earlier_chart_beside_the_new_tables(tmp_path):
    # `nsdyn bench accuracy` stopped while drawing left the earlier run's accuracy.png beside
    # the new accuracy.csv: a chart of other numbers
    from nsdyn.bench.common import write_outputs

    (tmp_path / "chart.png").write_bytes(b"an earlier run's chart")

    def draw():
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_outputs(
            tmp_path, {"csv": ("t.csv", [{"a": 1.0}], None)}, ("figure", "chart.png", draw)
        )
    assert (tmp_path / "t.csv").is_file() and not (tmp_path / "chart.png").exists()


def _assigned(module: str, name: str):
    """The literal a module assigns to ``name`` at its top level (read from its file)."""
    import ast

    tree = ast.parse(Path(importlib.util.find_spec(module).origin).read_text())
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == name for t in node.targets):
            return ast.literal_eval(node.value)
    return ()


@pytest.mark.parametrize("name", list(BENCHMARKS))
def test_a_benchmark_taking_figures_names_the_files_it_draws(name):
    # --no-figures removes an earlier run's FIGURES (contact-wp.png sat beside new tables);
    # each benchmark taking `figures` lists them, and each name is one its source writes
    module = BENCHMARKS[name]
    if "figures" not in _assigned(module, "OPTIONS"):
        return
    figures = _assigned(module, "FIGURES")
    source = Path(importlib.util.find_spec(module).origin).read_text()
    assert figures and all(f'"{f}"' in source for f in figures), name
