"""The first-run compile notice of ``nsdyn run`` and the kernel-cache probe behind it."""

from __future__ import annotations

import numpy as np
import pytest

from nsdyn.cli import run as cli_run
from nsdyn.solve import methods


def test_is_cached_after_warmup():
    # after warmup the kernels are in this process: a run only loads them, no notice due
    methods.warmup(["radau"])
    methods.warmup_metrics()
    assert methods.is_cached("radau")
    assert methods.is_cached("metrics")


def test_notice_names_the_integrator_and_reports_time(monkeypatch, capsys):
    # a cold cache (as in a fresh install) makes the run say what compiles, then how long
    monkeypatch.setattr(methods, "is_cached", lambda kernel: False)
    spent = cli_run.prepare_kernels("radau")
    err = capsys.readouterr().err
    assert "compiling the radau integrator (first run only, cached afterwards)" in err
    assert "compiled in" in err
    assert np.isfinite(spent) and spent >= 0.0


def test_no_notice_when_cached(monkeypatch, capsys):
    monkeypatch.setattr(methods, "is_cached", lambda kernel: True)
    cli_run.prepare_kernels("radau")
    assert capsys.readouterr().err == ""


def test_unknown_method_left_to_the_run():
    # the run itself rejects an unknown method with the list of valid names
    assert cli_run.prepare_kernels("no-such-method") == 0.0


def test_non_smooth_law_prepares_the_general_loop(monkeypatch, capsys):
    # the switch law cannot use the flat-only loop: the notice covers the general one
    asked = []
    monkeypatch.setattr(methods, "is_cached", lambda kernel: asked.append(kernel) or True)
    cli_run.prepare_kernels("radau", flat=False)
    assert set(asked) == {"radau-general", "metrics-general"}
    assert methods.compiled("radau-general")


@pytest.mark.parametrize(
    "friction, module, what",
    [("arctan", "nsdyn.periodic.problem", "the periodic kernels"),
     ("switch", "nsdyn.periodic.switch_compile", "the switch model's periodic kernels")],
)  # fmt: skip
def test_sweep_notice_names_its_kernels(monkeypatch, capsys, friction, module, what):
    # nsdyn sweep: a cold cache makes it say what compiles before the workers start, then how
    # long; afterwards the kernels are ready here and the workers load them: for a smooth law
    # the period map and the orbit quantities' kernel, for the
    # switch law the exact-flow period map and the system kernels of its mode-set tables
    import importlib

    from nsdyn.cli import sweep as cli_sweep

    mod = importlib.import_module(module)
    monkeypatch.setattr(mod, "kernels_cached", lambda: False)
    spent = cli_sweep.prepare_kernels(friction)
    err = capsys.readouterr().err
    assert f"compiling {what} (first use only, cached afterwards)" in err
    assert "compiled in" in err
    assert np.isfinite(spent) and spent >= 0.0
    monkeypatch.undo()
    assert mod.kernels_cached()


def test_no_sweep_notice_when_cached(monkeypatch, capsys):
    from nsdyn.cli import sweep as cli_sweep
    from nsdyn.periodic import problem, switch_compile

    monkeypatch.setattr(problem, "kernels_cached", lambda: True)
    cli_sweep.prepare_kernels("arctan")
    monkeypatch.setattr(switch_compile, "kernels_cached", lambda: True)
    cli_sweep.prepare_kernels("switch")
    assert capsys.readouterr().err == ""


def test_unilateral_sweep_compiles_its_loop_before_the_workers(monkeypatch, capsys):
    # nsdyn sweep --contact unilateral recomputes uplift points with the event-driven loop
    # (lift-off and landing) and the general metrics: compiled here, announced, before the
    # workers start (each would otherwise compile them when its first uplift point comes)
    from nsdyn.cli import sweep as cli_sweep
    from nsdyn.periodic import problem

    warmed = []
    monkeypatch.setattr(problem, "kernels_cached", lambda: True)
    monkeypatch.setattr(problem, "warmup", lambda: 0.0)
    monkeypatch.setattr(methods, "is_cached", lambda kernel: False)
    monkeypatch.setattr(methods, "warmup_unilateral", lambda: warmed.append("unilateral"))
    monkeypatch.setattr(methods, "warmup_metrics", lambda flat=True: warmed.append(flat))
    cli_sweep.prepare_kernels("arctan", "unilateral")
    err = capsys.readouterr().err
    assert "compiling the unilateral-contact loop (first use only, cached afterwards)" in err
    assert warmed == ["unilateral", False]
    warmed.clear()
    cli_sweep.prepare_kernels("arctan")  # bilateral: not needed
    assert warmed == [] and capsys.readouterr().err == ""


@pytest.mark.parametrize("jit", [True, False], ids=["jit", "no-jit"])
def test_every_method_is_announced_with_an_empty_cache(tmp_path, jit):
    # a fresh process with an empty NUMBA_CACHE_DIR: the probe of every method's kernel (the
    # factor-once generalized-alpha's too) and of the sweeps' (either law) says "not cached",
    # so each first run announces its compilation; without the JIT (NUMBA_DISABLE_JIT=1, the
    # debugging mode) nothing compiles, so every probe says "cached" and no run announces a
    # compilation. The process's mode is set explicitly, whatever the mode this test runs in.
    import json
    import os
    import subprocess
    import sys
    from pathlib import Path

    code = (
        "import json\nfrom nsdyn.solve import methods\n"
        "from nsdyn.periodic import problem, switch_compile\n"
        "k = {m.kernel for m in methods.METHODS.values()} | {'radau-general', 'metrics'}\n"
        "out = {n: methods.is_cached(n) for n in sorted(k)}\n"
        "out['sweep'] = problem.kernels_cached()\n"
        "out['sweep-switch'] = switch_compile.kernels_cached()\nprint(json.dumps(out))"
    )
    root = str(Path(__file__).resolve().parents[2])
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), NUMBA_DISABLE_JIT="0" if jit else "1")
    env["PYTHONPATH"] = os.pathsep.join(p for p in (root, env.get("PYTHONPATH")) if p)
    res = subprocess.run([sys.executable, "-P", "-c", code], env=env, capture_output=True,
                         text=True, timeout=300)  # fmt: skip
    assert res.returncode == 0, res.stderr
    probes = json.loads(res.stdout.strip().splitlines()[-1])
    assert "genalpha-lowrank" in probes and "event" in probes
    assert probes == dict.fromkeys(probes, not jit)


def test_study_compiles_once_before_the_workers_start(monkeypatch, capsys):
    # nsdyn study of isolated-frame scenes: a cold cache makes it compile the kernels in this
    # process, saying so, before the workers start (they then load them instead of each
    # compiling them at once); nothing said when they are cached, nothing done for the other
    # families (their scene runners say so in the workers)
    from types import SimpleNamespace

    from nsdyn.cli import study as cli_study

    study = SimpleNamespace(kind="isolated", base={"solver": {"method": "event"}})
    asked, warmed = [], []
    monkeypatch.setattr(methods, "is_cached", lambda kernel: asked.append(kernel) or False)
    monkeypatch.setattr(
        methods, "warmup_kernel", lambda k, metrics=None: warmed.append((k, metrics))
    )
    assert cli_study.announce_compile(study)
    err = capsys.readouterr().err
    assert "compiling the isolated-frame kernels (event) once, before the workers start" in err
    assert "compiled in" in err
    assert asked[0] == "event"  # the switch model's loop, not the default one
    assert warmed == [("event", "metrics-general")]
    monkeypatch.setattr(methods, "is_cached", lambda kernel: True)
    assert not cli_study.announce_compile(study)  # cached: the workers load them
    monkeypatch.setattr(methods, "is_cached", lambda kernel: False)
    assert not cli_study.announce_compile(SimpleNamespace(kind="cylinder", base={}))
    assert len(warmed) == 1 and capsys.readouterr().err == ""


@pytest.mark.slow  # a two-point sweep (shooting) after the periodic kernels load
def test_sweep_json_reports_compile_apart(monkeypatch, capsys, tmp_path):
    # nsdyn sweep --json: the notice on stderr (a cold cache), compile_s apart from wall_s
    import json

    from nsdyn.cli.app import main
    from nsdyn.periodic import problem

    monkeypatch.setattr(problem, "kernels_cached", lambda: False)
    argv = ["sweep", "--points", "2", "--fmin", "1", "--fmax", "2", "--amplitudes", "1",
            "--workers", "1", "--json", "--no-figures", "--out", str(tmp_path)]  # fmt: skip
    assert main(argv) == 0
    out = capsys.readouterr()
    s = json.loads(out.out)
    assert "compiling the periodic kernels" in out.err
    assert s["compile_s"] > 0.0 and s["wall_s"] > 0.0  # each timed, apart
