"""``nsdyn bench fidelity``: the ladder's errors and why the full rung needs its tolerances."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from nsdyn.bench import common, fidelity
from nsdyn.cli import bench as command
from nsdyn.models.isolated.system import build_system


@pytest.fixture(scope="module")
def frame():
    return common.bench_frame()


@pytest.fixture(scope="module")
def cb5(frame):
    return build_system(frame, common.bench_isolation(), fidelity="cb", f_max=5.0)


def test_full_model_roundoff_reaches_the_newton_tolerance(frame, cb5):
    """Why the 435-dof rung runs at the transient tolerances: at a mid-record state (base 0.1 m
    from rest, sliding at 0.3 m/s) the full model's float64 accelerations carry a round-off
    over 100x CB-5's (diaphragm stiffness 1e11 against the base nodes' tiny rotational
    inertia; measured against the same formulas in long double). As the smallest Newton update
    of a 1e-3 s step it exceeds the convergence threshold of genalpha and of radau at rtol
    1e-6, atol 1e-8 (where genalpha at dt 1e-3 failed on the full rung), is 20x below it at the
    ladder's tolerances, and CB-5's stays 10x below it even at the tight ones."""
    motion = common.bench_motion("wn", 2.0)
    full = build_system(frame, common.bench_isolation(), fidelity="full")
    assert full.n == 435
    rtol, atol = fidelity.fidelity_tolerances()
    for method in ("genalpha", "radau"):
        res = {}
        for name, system in (("cb5", cb5), ("full", full)):
            x, _ = system.static_equilibrium()
            slide = np.flatnonzero(system.D.sum(axis=0))
            x[slide] += 0.1
            x[system.n + slide] += 0.3
            da = fidelity.acceleration_roundoff(system, motion, 1.49, x)
            res[name] = (
                da.max(),
                fidelity.newton_noise_floor(x, da, 1e-6, 1e-8, method=method),
                fidelity.newton_noise_floor(x, da, rtol, atol, method=method),
            )
        assert res["full"][0] > 100 * res["cb5"][0]
        assert res["full"][1] > 1.0 > 20 * res["full"][2], method
        assert res["cb5"][1] < 0.1, method


def test_bench_fidelity_quick_end_to_end(tmp_path):
    """``nsdyn bench fidelity --quick``: the richest rung that ran is the reference; the rigid
    superstructure is further from it than CB-5 in every peak (it has no drift at all); and
    the integration floor (CB-5 at the ladder's tolerances against rtol 1e-8) is 10x below
    CB-5's model error, so the chart shows the models, not the integrator."""
    out = tmp_path / "bench"
    assert command.main(["fidelity", "--quick", "--out", str(out), "--json"]) == 0
    rows = list(csv.DictReader(open(out / "fidelity.csv")))
    ladder = [fidelity.rung_name(*r) for r in fidelity.QUICK_LADDER]
    for rec in ("low-frequency", "broadband"):
        mine = {r["model"]: r for r in rows if r["record"] == rec}
        assert all(mine[m]["status"] == "ok" for m in ladder)
        assert {mine[m]["reference"] for m in ladder} == {ladder[-1]}
        rigid, cb5 = mine["rigid"], mine["cb-5"]
        floor = mine[f"cb-5 rtol {fidelity.FLOOR_RTOL:g}"]
        assert float(rigid["err_idr"]) == pytest.approx(1.0)  # a rigid body has no drift
        for key in ("err_xpeak", "err_idr", "err_acc"):
            assert float(rigid[key]) > float(cb5[key]) > 10 * float(floor[key])
    assert (out / "fidelity.png").exists() and not list(out.glob(".*"))
