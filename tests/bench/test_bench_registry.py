"""The benchmark registry and ``nsdyn bench``'s dispatch: modules load on use, an absent or
broken module is named as such, each ``run_bench`` receives only the options it names."""

from __future__ import annotations

import inspect
import json
import re
import sys

import pytest

import nsdyn.bench as registry
from nsdyn.cli import bench as command

BUILT_IN = ["accuracy", "fidelity", "stability", "speed", "periodic"]

FAKE = """
CALLS = []


OPTIONS = ("quiet",)


def run_bench(out_dir, quick, *, quiet=False):
    CALLS.append({"out_dir": str(out_dir), "quick": quick, "quiet": quiet})
    return {"files": [f"{out_dir}/fake.csv"], "peak": 1.5, "quiet": quiet}
"""


@pytest.fixture
def fake_modules(tmp_path, monkeypatch):
    """A working benchmark module, one that raises on import, and the names to register."""
    (tmp_path / "fake_bench_ok.py").write_text(FAKE)
    (tmp_path / "fake_bench_broken.py").write_text("raise RuntimeError('half written')\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    for m in ("fake_bench_ok", "fake_bench_broken"):
        monkeypatch.delitem(sys.modules, m, raising=False)
    return {
        "fake": "fake_bench_ok",
        "gone": "nsdyn.bench.no_such_benchmark",
        "broken": "fake_bench_broken",
    }


def test_built_in_benchmarks_run_first_in_order_and_accept_their_options():
    """``all`` runs the table in order: the five built-in benchmarks first; each module's
    run_bench takes (out_dir, quick), and every option its OPTIONS lists is a keyword of the
    benchmark function it calls (so the command line never passes an unknown one)."""
    assert list(registry.BENCHMARKS)[: len(BUILT_IN)] == BUILT_IN
    for name in BUILT_IN:
        module = registry.load_benchmark(name)
        params = list(inspect.signature(module.run_bench).parameters)
        assert params[:2] == ["out_dir", "quick"]
        bench_fn = getattr(module, f"{name}_bench")
        assert set(module.OPTIONS) <= set(inspect.signature(bench_fn).parameters), name


def test_unavailable_benchmarks_are_named(fake_modules, monkeypatch):
    """An absent module and a module that fails to import raise BenchmarkUnavailable naming
    the module (and the import error); an unknown name is a KeyError listing the names."""
    monkeypatch.setattr(registry, "BENCHMARKS", fake_modules)
    assert registry.load_benchmark("fake").run_bench
    with pytest.raises(registry.BenchmarkUnavailable) as e:
        registry.load_benchmark("gone")
    assert e.value.absent and "nsdyn.bench.no_such_benchmark does not exist" in str(e.value)
    with pytest.raises(registry.BenchmarkUnavailable) as e:
        registry.load_benchmark("broken")
    assert not e.value.absent
    assert "failed to import" in str(e.value) and "half written" in str(e.value)
    with pytest.raises(KeyError, match="expected one of"):
        registry.load_benchmark("nonsense")


def test_all_reports_unavailable_modules_and_passes_only_named_options(
    fake_modules, monkeypatch, tmp_path, capsys
):
    """``nsdyn bench all --json``: the working module runs once with the options it lists
    (quiet, not repeats or records); the absent one is skipped and said so (exit 0); a
    module that does not import makes the exit status 1; a benchmark asked for by name that
    is absent exits with 2 and says why. A result's files may be a list of paths."""
    monkeypatch.setattr(registry, "BENCHMARKS", {k: fake_modules[k] for k in ("fake", "gone")})
    assert command.main(["all", "--quick", "--json", "--out", str(tmp_path)]) == 0
    captured = capsys.readouterr()
    summary = json.loads(captured.out)
    assert next(iter(summary.items())) == ("status", 0)  # (as every command's JSON leads)
    assert summary["fake"] == {"files": [f"{tmp_path}/fake.csv"], "peak": 1.5, "quiet": True}
    assert summary["gone"]["status"] == "unavailable"
    assert "benchmark 'gone' is not available" in captured.err
    calls = sys.modules["fake_bench_ok"].CALLS
    assert calls == [{"out_dir": str(tmp_path), "quick": True, "quiet": True}]

    # without --json: the summary as text (no report function) and the files it lists
    assert command.main(["fake", "--out", str(tmp_path)]) == 0
    printed = capsys.readouterr().out
    assert "\n  peak  1.5\n" in printed and f"file: {tmp_path}/fake.csv" in printed
    assert "{" not in printed  # not JSON

    monkeypatch.setattr(registry, "BENCHMARKS", fake_modules)
    assert command.main(["all", "--json", "--out", str(tmp_path)]) == 1
    assert "fake_bench_broken failed to import" in capsys.readouterr().err
    assert command.main(["gone", "--out", str(tmp_path)]) == 2
    assert "does not exist" in capsys.readouterr().err


def test_every_registered_benchmark_loads_with_the_common_entry_point():
    """Each name of the table (the families' benchmarks too) imports, and its run_bench takes
    (out_dir, quick) as the command line calls it."""
    for name in registry.BENCHMARKS:
        module = registry.load_benchmark(name)
        params = list(inspect.signature(module.run_bench).parameters)
        assert params[:2] == ["out_dir", "quick"], name


def test_every_registered_benchmark_has_a_line_of_help():
    """``nsdyn bench --help`` says what each benchmark measures, not its module's name (the
    fallback for a benchmark registered from outside the package)."""
    assert set(command.HELP) == set(registry.BENCHMARKS)
    assert all(not line.startswith("nsdyn.") for line in command.HELP.values())


def test_a_benchmarks_help_lists_what_it_measures_and_the_options_it_takes(capsys):
    """``nsdyn bench speed --help`` printed the command's help, every benchmark's options
    alike. It now prints the benchmark's own page: its module's summary, the options it
    takes (each of which the command accepts for it) and none it would refuse."""
    from nsdyn.cli.app import main

    for name in registry.BENCHMARKS:
        spelt = name.replace("_", "-")
        assert main(["bench", spelt, "--help"]) == 0
        text = capsys.readouterr().out
        module = registry.load_benchmark(name)
        assert text.startswith(f"usage: nsdyn bench {name} [--quick] [--out DIR]"), name
        assert module.__doc__.splitlines()[0].replace("``", "`") in text
        about = text.split("options of this benchmark:")[0]
        # no role left unread, no constant's name for its value ("its first RECORD_S
        # seconds"), no sentence cut at a comma before its list
        assert ":data:" not in about and not re.search(r"`[A-Z][A-Z0-9_]+`", about), name
        assert about.rstrip().endswith((".", ")")), name  # (a cut one: "(more in …)")
        own = text.split("options of this benchmark:")[1].split("options of every")[0]
        for flag, option in command._GIVEN:  # listed exactly when taken (else refused)
            assert (f"  {flag}" in own) == (option in getattr(module, "OPTIONS", ())), (name, flag)
    assert main(["bench", "--out", "speed", "isolators", "--help"]) == 0  # (--out's value)
    assert capsys.readouterr().out.startswith("usage: nsdyn bench isolators ")
    with pytest.raises(SystemExit) as done:  # (without a benchmark: the command's help)
        main(["bench", "--help"])
    assert done.value.code == 0
    assert capsys.readouterr().out.startswith("usage: nsdyn bench [-h]")


def test_every_benchmark_takes_none_as_the_default_repeats():
    """The command line passes ``repeats=None`` when --repeats is not given (each benchmark's
    own default, 1 with --quick): every benchmark listing ``repeats`` takes None for it."""
    for name in registry.BENCHMARKS:
        try:
            module = registry.load_benchmark(name)
        except registry.BenchmarkUnavailable:
            continue
        if "repeats" not in getattr(module, "OPTIONS", ()):
            continue
        fns = [module.run_bench, getattr(module, f"{name.replace('-', '_')}_bench", None)]
        for fn in filter(None, fns):
            p = inspect.signature(fn).parameters.get("repeats")
            if p is not None:  # a run_bench of **options hands them on to the bench function
                assert p.default is None, (name, fn.__name__, p.default)


def test_no_figures_to_a_benchmark_that_draws_none_is_said(fake_modules, monkeypatch, tmp_path,
                                                           capsys):  # fmt: skip
    """``--no-figures`` to a benchmark without charts (no ``figures`` option) runs it and says
    the flag changes nothing (it was accepted without a word); with ``--json`` stderr stays
    quiet for scripts."""
    monkeypatch.setattr(registry, "BENCHMARKS", {"fake": fake_modules["fake"]})
    assert command.main(["fake", "--no-figures", "--out", str(tmp_path)]) == 0
    assert "benchmark 'fake' draws no figures; --no-figures changes nothing" in (
        capsys.readouterr().err)  # fmt: skip
    assert command.main(["fake", "--no-figures", "--json", "--out", str(tmp_path)]) == 0
    assert "draws no figures" not in capsys.readouterr().err


def test_no_figures_removes_the_benchmarks_earlier_figures(tmp_path, monkeypatch, capsys):
    # `bench contact --no-figures` left the earlier run's contact-wp.png beside new tables
    text = FAKE.replace('OPTIONS = ("quiet",)', 'OPTIONS = ("quiet", "figures")')
    text = text.replace("quiet=False)", "quiet=False, figures=True)") + 'FIGURES = ("fake.png",)\n'
    (tmp_path / "drawing_bench.py").write_text(text)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "drawing_bench", raising=False)
    monkeypatch.setattr(registry, "BENCHMARKS", {"fake": "drawing_bench"})
    out = tmp_path / "out"
    out.mkdir()
    (out / "fake.png").write_bytes(b"an earlier run's figure")
    assert command.main(["fake", "--no-figures", "--out", str(out)]) == 0
    assert not (out / "fake.png").exists()
    assert "removed the earlier run's fake.png (--no-figures draws none)" in capsys.readouterr().err
    # with --json the note is in the summary (stderr stays quiet for scripts)
    (out / "fake.png").write_bytes(b"an earlier run's figure")
    assert command.main(["fake", "--no-figures", "--json", "--out", str(out)]) == 0
    said = capsys.readouterr()
    assert json.loads(said.out)["notes"] == ["removed the earlier run's fake.png (--no-figures "
                                             "draws none)"] and not said.err  # fmt: skip
