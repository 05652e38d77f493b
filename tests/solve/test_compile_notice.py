"""The first-run compile notice of ``nsdyn run`` and the kernel-cache probe behind it."""

from __future__ import annotations

import numpy as np

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


def test_sweep_notice_names_the_periodic_kernels(monkeypatch, capsys):
    # nsdyn sweep: a cold cache makes it say what compiles before the workers start, then how
    # long; afterwards the period map and the orbit quantities' kernel are ready here
    from nsdyn.cli import sweep as cli_sweep
    from nsdyn.periodic import problem

    monkeypatch.setattr(problem, "kernels_cached", lambda: False)
    spent = cli_sweep.prepare_kernels("arctan")
    err = capsys.readouterr().err
    assert "compiling the periodic kernels (first use only, cached afterwards)" in err
    assert "compiled in" in err
    assert np.isfinite(spent) and spent >= 0.0
    monkeypatch.undo()
    assert problem.kernels_cached()


def test_no_sweep_notice_when_cached_or_for_the_switch_law(monkeypatch, capsys):
    from nsdyn.cli import sweep as cli_sweep
    from nsdyn.periodic import problem

    monkeypatch.setattr(problem, "kernels_cached", lambda: True)
    cli_sweep.prepare_kernels("arctan")
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(problem, "kernels_cached", lambda: False)
    assert cli_sweep.prepare_kernels("switch") == 0.0  # its kernels compile in the workers
    assert capsys.readouterr().err == ""
