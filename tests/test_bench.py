"""Benchmarks and the model advisor: failures are reported, references converge, advice holds.

No timing thresholds: only physics and exact checks with stated tolerances.
"""

from __future__ import annotations

import csv

import numpy as np
import pytest

from nsdyn import bench
from nsdyn.advisor import advise, stick_probe
from nsdyn.integrate import IntegrationError
from nsdyn.system import build_system
from nsdyn.transient import simulate


@pytest.fixture(scope="module")
def frame():
    return bench.bench_frame()


@pytest.fixture(scope="module")
def cb5(frame):
    return build_system(frame, bench.bench_isolation(), fidelity="cb", f_max=5.0)


def test_numpy_equations_equal_the_numba_kernel(cb5, frame):
    """The SciPy baseline integrates the same equations: rhs and Jacobian equal the kernel's
    to round-off (1e-12 relative) at random states, for CB-5 and the rigid model."""
    from nsdyn import _ksystem as ks

    motion = bench.bench_motion("wn", 5.0)
    rng = np.random.default_rng(1)
    for system in (cb5, build_system(frame, bench.bench_isolation(), fidelity="rigid")):
        fun, jac = bench.numpy_equations(system, motion)
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


def test_explicit_method_on_stiff_eps_is_reported_not_returned(frame):
    """eps = 1e5 makes the friction slope ~2e4 1/s and CB-5 has kHz boundary modes: dopri5
    with a step budget, dopri5 with a fixed step far beyond its stable step, and genalpha
    with a step too long for its Newton iteration all end in IntegrationError (the benchmark
    records the reason as the run's status, never a result)."""
    stiff = build_system(frame, bench.bench_isolation(eps=1e5), fidelity="cb", f_max=5.0)
    motion = bench.stability_motion(quick=True)
    with pytest.raises(IntegrationError) as e:
        simulate(stiff, motion, method="dopri5", rtol=1e-6, atol=1e-8, max_steps=2000)
    assert e.value.reason in ("max_steps", "step_underflow")
    cases = [
        ("dopri5", dict(rtol=1e-6, max_steps=2000)),
        ("dopri5", dict(dt=1e-3)),  # fixed step ~200x beyond the explicit stability limit
        ("genalpha", dict(dt=1e-2)),
    ]
    for method, kw in cases:
        run = bench.run_nsdyn(stiff, motion, method, repeats=1, **kw)
        assert run.status != "ok", (method, kw)
        assert run.x_iso is None and not run.walls
        outcome, _ = bench.classify(run, None)
        assert outcome.startswith("flagged:") or outcome == "budget"


def test_reference_agrees_with_an_independent_check(cb5):
    """The chart reference (radau, rtol 1e-10) against dopri5 (explicit, same tolerance) on a
    1 s window of the chart's record scaled to PGA 3 m/s^2: histories agree to 1e-7 of the
    peak isolator displacement and peak IDRs to 1e-7 (on the 20 s chart window they agree to
    ~4e-9, while the smallest charted error is ~3e-8)."""
    motion = bench.bench_motion("wn", 1.0)
    ref = bench.make_reference(cb5, motion, "arctan", check=True)
    assert ref.run.method == "radau" and ref.run.value == bench.REF_RTOL
    assert ref.check.method == "dopri5" and ref.check.ok
    assert ref.agreement["err_x"] < 1e-7
    assert ref.agreement["err_idr"] < 1e-7
    # and it is converged with respect to the chart's loosest setting by orders of magnitude
    loose = bench.run_nsdyn(cb5, motion, "radau", rtol=1e-3, repeats=1)
    assert bench.run_errors(loose, ref.run)["err_x"] > 100 * ref.agreement["err_x"]


def test_advisor_picks_fixed_base_when_isolators_never_slide(frame):
    """PGA 0.03 m/s^2 = 0.1 mu g: the switch model (event-driven) never leaves stick, the
    friction carries at most a fraction of mu lam, and the advice is the fixed-base model."""
    iso = bench.bench_isolation()
    motion = bench.bench_motion("wn", 10.0, pga=0.03)
    sw = build_system(frame, bench.bench_isolation("switch"), fidelity="cb", f_max=5.0)
    res = simulate(sw, motion, method="event", rtol=1e-6, atol=1e-8)
    r = res.response
    assert res.stats["n_events"] == 0
    assert np.all(r.modes == 0)
    ni = sw.n_isolators
    util = np.abs(r.tau) / (bench.MU * r.lam[:, :ni])
    assert util.max() < 1.0
    assert np.max(np.abs(r.x_iso - r.x_iso[0])) < 1e-9  # m: the base stays where gravity left it
    sp = stick_probe(frame, motion, iso)
    assert sp["verdict"] == "stick throughout"
    advice = advise(frame, motion, tol=0.05, isolation=iso)
    assert advice.fidelity == "fixed"
    assert advice.evidence["stick_probe"]["slip_events"] == 0
    assert advice.evidence["probes"] and advice.evidence["probes"][-1]["ok"]


def test_advisor_does_not_pick_fixed_base_at_pga_3(frame):
    """At PGA 3 m/s^2 (about 10 mu g) the isolators slide, so the advice is an isolated
    model, whatever the frequency content."""
    motion = bench.bench_motion("wn", 8.0)
    advice = advise(frame, motion, tol=0.05, isolation=bench.bench_isolation(), probe=False)
    assert advice.fidelity != "fixed"
    assert advice.evidence["stick_probe"]["verdict"] == "slides"
    assert advice.evidence["stick_probe"]["slip_events"] > 0


@pytest.mark.slow
def test_advisor_probes_choose_a_rung_under_tol(frame):
    """With probes, the advised rung's measured error against the next rung is under tol."""
    motion = bench.bench_motion("wn", 8.0)
    advice = advise(frame, motion, tol=0.05, isolation=bench.bench_isolation())
    assert advice.fidelity in ("rigid", "cb", "full")
    chosen = [p for p in advice.evidence["probes"] if p["ok"]]
    if advice.fidelity != "full":
        assert chosen and max(chosen[0]["errors"].values()) <= 0.05
    assert "idr" in advice.evidence["probes"][0]["errors"]
    # the rigid model has no interstorey drift: it cannot meet an IDR tolerance
    assert advice.evidence["probes"][0]["errors"]["idr"] == pytest.approx(1.0)


def test_bench_accuracy_quick_end_to_end(tmp_path, capsys):
    """``nsdyn bench accuracy --quick`` writes its CSV (one row per run with its error and
    median wall time), the reference CSV and the figure."""
    out = tmp_path / "bench"
    assert bench.main(["accuracy", "--quick", "--records", "wn", "--out", str(out)]) == 0
    rows = list(csv.DictReader(open(out / "accuracy.csv")))
    labels = {r["label"] for r in rows}
    assert {"radau", "dopri5", "genalpha", "hht", "event", "scipy-radau"} <= labels
    for r in rows:
        if r["status"] == "ok":
            assert float(r["err_x"]) >= 0 and float(r["wall_s"]) > 0
    radau = sorted((float(r["value"]), float(r["err_x"])) for r in rows if r["label"] == "radau")
    assert radau[0][1] < radau[-1][1]  # a tighter tolerance gives a smaller error
    assert (out / "accuracy-reference.csv").exists() and (out / "accuracy.png").exists()
    assert not list(out.glob(".*"))  # atomic writes leave no temporary files
    printed = capsys.readouterr().out
    assert "speed ratios at matched accuracy" in printed
