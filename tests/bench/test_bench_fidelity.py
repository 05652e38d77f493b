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


def _roundoff_scale(system, motion, t, x):
    """u T_i: the size of one rounding of row i of the unconstrained accelerations
    a0 = -Γ [a_h, a_v + g] - M⁻¹K* q - M⁻¹C* q̇, T = |Γ| |[a_h, a_v + g]| + |M⁻¹K*| |q| +
    |M⁻¹C*| |q̇| (u = eps / 2). Any float64 evaluation of a row sums its terms with rounded
    partial sums: its error is of the order u T_i, at most γ_m T_i with γ_m = m u / (1 - m u)
    for m terms (Higham, Accuracy and Stability of Numerical Algorithms, §3.1) — a property
    of the model and the state, the same on every machine."""
    from nsdyn.models.isolated import _kernel as ks
    from nsdyn.models.isolated.params import KernelParams

    P = system.params(motion)
    kp = KernelParams(P)
    m = kp.matrices()
    n = system.n
    ah, av = ks.ground_accel(float(t), P)
    T = (
        np.abs(m["Gamma"]) @ np.abs([ah, av + kp.g])
        + np.abs(m["MiK"]) @ np.abs(x[:n])
        + np.abs(m["MiC"]) @ np.abs(x[n:])
    )
    terms = 2 + np.count_nonzero(m["MiK"], axis=1) + np.count_nonzero(m["MiC"], axis=1)
    u = np.finfo(float).eps / 2
    return u * T, terms * u / (1 - terms * u) * T


def test_full_model_roundoff_stays_below_the_newton_tolerance(frame, cb5):
    """The 435-dof rung in nodal coordinates converges at tight tolerances: at a mid-record
    state (base 0.1 m from rest, sliding at 0.3 m/s) the float64 round-off of its
    accelerations, on the scale u (|M^-1 K||q| + |M^-1 C||qd| + |Gamma||g|) of
    :func:`_roundoff_scale`, stays below the convergence threshold of the smallest Newton
    update of genalpha and radau at rtol 1e-6, atol 1e-8 (the old modal basis with every
    fixed-interface mode reached it: its transformation T was large), and CB-5's stays 10x
    below it. These are statements on a scale that does not depend on the machine or the order
    of the sums; the round-off actually measured (against the same formulas in long double)
    must lie within the worst-case bound of the full model's dominant terms."""
    motion = common.bench_motion("wn", 2.0)
    full = build_system(frame, common.bench_isolation(), fidelity="full")
    assert full.n == 435
    t = 1.49
    scale, worst, measured = {}, {}, {}
    for name, system in (("cb5", cb5), ("full", full)):
        x, _ = system.static_equilibrium()
        slide = np.flatnonzero(system.D.sum(axis=0))
        x[slide] += 0.1
        x[system.n + slide] += 0.3
        scale[name], worst[name] = _roundoff_scale(system, motion, t, x)
        if name == "full":
            measured = fidelity.acceleration_roundoff(system, motion, t, x)
            x_full = x
        else:
            x_cb5 = x
    for method in ("genalpha", "radau"):
        floor = fidelity.newton_noise_floor
        assert floor(x_full, scale["full"], 1e-6, 1e-8, method=method) < 1.0, method
        assert floor(x_cb5, scale["cb5"], 1e-6, 1e-8, method=method) < 0.1, method
        assert floor(x_full, measured, 1e-6, 1e-8, method=method) <= floor(
            x_full, worst["full"], 1e-6, 1e-8, method=method
        ), method


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
        # each row's own tolerances (the floor row read the ladder's rtol), atol in numbers
        assert float(floor["rtol"]) == fidelity.FLOOR_RTOL == float(floor["value"])
        assert float(cb5["rtol"]) == float(cb5["value"]) > fidelity.FLOOR_RTOL
        assert float(floor["atol_m"]) < float(cb5["atol_m"]) <= float(cb5["atol_mps"])
        assert float(rigid["err_idr"]) == pytest.approx(1.0)  # a rigid body has no drift
        for key in ("err_xpeak", "err_idr", "err_acc"):
            assert float(rigid[key]) > float(cb5[key]) > 10 * float(floor[key])
    assert (out / "fidelity.png").exists() and not list(out.glob(".*"))


def test_the_report_names_each_rows_reference_and_gives_the_rigid_deck_no_drift_error():
    # the header named the first row's reference for every row, the floor rows' included
    # (those compare a rung at the ladder's tolerance with itself at 1e-8), and the rigid
    # deck, which has no storey drift, showed an IDR "error" of 1
    from nsdyn.bench.fidelity import report

    def row(model, reference, idr):
        return {"record": "broadband", "model": model, "n_dof": 3, "err_xpeak": 0.1,
                "err_idr": idr, "err_acc": 0.1, "wall_s": 0.01, "status": "ok",
                "reference": reference}  # fmt: skip

    text = report(
        {
            "rows": [
                row("rigid", "cb-10", 1.0),
                row("cb-10", "cb-10", 0.0),
                row("cb-5 rtol 1e-08", "floor: cb-5 at rtol 1e-06 vs 1e-08", 1e-9),
            ]
        }
    )
    lines = text.splitlines()
    assert lines[0].endswith("(errors vs cb-10)")
    assert lines[1].split()[4] == "—" and "1.00e+00" not in lines[1]
    assert lines[-1] == "(an 'rtol' row: the time-integration floor, cb-5 at rtol 1e-06 vs 1e-08)"
