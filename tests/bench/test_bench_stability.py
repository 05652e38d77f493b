"""``nsdyn bench stability``: failures are reported, never returned as results."""

from __future__ import annotations

import math

import pytest

from nsdyn.bench import common, stability
from nsdyn.models.isolated.system import build_system
from nsdyn.solve.integrate import IntegrationError
from nsdyn.solve.transient import simulate


@pytest.fixture(scope="module")
def frame():
    return common.bench_frame()


def test_explicit_method_on_stiff_eps_is_reported_not_returned(frame):
    """eps = 1e5 makes the friction slope ~2e4 1/s and CB-5 has kHz boundary modes: dopri5
    with a step budget, dopri5 with a fixed step far beyond its stable step, and genalpha
    with a step too long for its Newton iteration all end in IntegrationError (the benchmark
    records the reason as the run's status, never a result)."""
    stiff = build_system(frame, common.bench_isolation(eps=1e5), fidelity="cb", f_max=5.0)
    motion = stability.stability_motion(quick=True)
    with pytest.raises(IntegrationError) as e:
        simulate(stiff, motion, method="dopri5", rtol=1e-6, atol=1e-8, max_steps=2000)
    assert e.value.reason in ("max_steps", "step_underflow")
    cases = [
        ("dopri5", dict(rtol=1e-6, max_steps=2000)),
        ("dopri5", dict(dt=1e-3)),  # fixed step ~200x beyond the explicit stability limit
        ("genalpha", dict(dt=1e-2)),
    ]
    for method, kw in cases:
        run = common.run_nsdyn(stiff, motion, method, repeats=1, **kw)
        assert run.status != "ok", (method, kw)
        assert run.x_iso is None and not run.walls
        outcome, _ = stability.classify(run, None)
        assert outcome.startswith("flagged:") or outcome == "budget"


def test_bench_stability_quick_end_to_end(tmp_path):
    """``nsdyn bench stability --quick``: no cell returns unflagged garbage; dopri5 beyond its
    step on the stiff CB-5 model is reported (flagged by the integrator or caught by the
    energy check); and on the rigid model with Baumgarte alpha = 1e3 its largest stable step
    is the largest scanned step below 3.306/alpha, the linear stability limit of the
    Dormand-Prince tableau on the negative real axis (Hairer & Wanner, Solving ODEs II,
    Sec. IV.2) for the constraint's double eigenvalue -alpha."""
    res = stability.stability_bench(quick=True, out=tmp_path / "bench", quiet=True)
    assert (tmp_path / "bench" / "stability.png").stat().st_size > 0
    assert res["unflagged_garbage"] == []
    bound = {
        (b["map"], b["model"], b["method"], b.get(b["map"])): b
        for b in res["eps_boundary"] + res["alpha_boundary"]
    }
    stiff = bound[("eps", "cb-5", "dopri5", 1e4)]
    # CB-5's stiffest boundary mode is at 1207 Hz (an eigenvalue of the reduced model), and
    # Dormand-Prince's stability region reaches no further than |h lambda| = 3.98: a stable
    # step is below 3.98 / (2 pi 1207 Hz) = 5.2e-4 s, whatever the friction adds
    assert stiff["dt_max_stable"] < 3.98 / (2 * math.pi * 1207.0)
    assert stiff["failure_above"].split(":")[0] in ("flagged", "checked")
    assert bound[("eps", "cb-5", "genalpha", 1e2)]["dt_max_stable"] == stability.STAB_DT[0]
    alpha = 1e3
    limit = max(dt for dt in stability.STAB_DT if dt <= 3.306 / alpha)
    assert bound[("alpha", "rigid", "dopri5", alpha)]["dt_max_stable"] == pytest.approx(limit)
