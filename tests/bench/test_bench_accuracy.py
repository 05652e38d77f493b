"""``nsdyn bench accuracy``: references converge and agree with an independent check;
the work-precision table is written.

No timing thresholds: only physics and exact checks with stated tolerances.
"""

from __future__ import annotations

import csv

import pytest

from nsdyn.bench import accuracy, common
from nsdyn.cli import bench as command
from nsdyn.models.isolated.system import build_system


@pytest.fixture(scope="module")
def frame():
    return common.bench_frame()


@pytest.fixture(scope="module")
def cb5(frame):
    return build_system(frame, common.bench_isolation(), fidelity="cb", f_max=5.0)


def test_reference_agrees_with_an_independent_check(cb5):
    """The chart reference (radau, rtol 1e-10) against dopri5 (explicit, same tolerance) on a
    1 s window of the chart's record scaled to PGA 3 m/s^2: histories agree to 1e-7 of the
    peak isolator displacement and peak IDRs to 1e-7 (on the 20 s chart window they agree to
    ~4e-9, while the smallest charted error is ~3e-8)."""
    motion = common.bench_motion("wn", 1.0)
    ref = accuracy.make_reference(cb5, motion, "arctan", check=True)
    assert ref.run.method == "radau" and ref.run.value == accuracy.REF_RTOL
    assert ref.check.method == "dopri5" and ref.check.ok
    assert ref.agreement["err_x"] < 1e-7
    assert ref.agreement["err_idr"] < 1e-7
    # and it is converged with respect to the chart's loosest setting by orders of magnitude
    loose = common.run_nsdyn(cb5, motion, "radau", rtol=1e-3, repeats=1)
    assert common.run_errors(loose, ref.run)["err_x"] > 100 * ref.agreement["err_x"]


@pytest.mark.slow  # ~1.5 min: every method at every tolerance of the quick chart
def test_bench_accuracy_quick_end_to_end(tmp_path, capsys):
    """``nsdyn bench accuracy --quick`` writes its CSV (one row per run with its error and
    median wall time), the reference CSV and the figure."""
    out = tmp_path / "bench"
    assert command.main(["accuracy", "--quick", "--records", "wn", "--out", str(out)]) == 0
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
    assert "(--quick: two or three settings per method" in printed  # (its ratios are coarse)
