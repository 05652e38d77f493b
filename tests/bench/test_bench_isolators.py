"""``nsdyn bench isolators --quick`` end to end: the work–precision rows, the cost per isolator,
the triple pendulum's row and the planar baseline, and the files.

Physics checked on the benchmark's own runs: the switch law's peak resultant slip at rtol 1e-4
and 1e-6 is its rtol-1e-10 reference's within 1e-3 (the local tolerance 1e-4 grown by at
most a factor ten over the run's ~200 located stick–slip events, each restarting from a
state within the tolerance); the regularised law (ε = 7500 s/m) differs from the switch law by
its creep in stick, bounded by 5 % on the peak resultant slip (the guide's 4 % on histories,
Sec. "Speed" of docs/guide/bidirectional-isolators.md); and the planar office frame's two laws
agree on its peak slip to the same bound (the seed's Fig. 7 comparison of the two laws).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from nsdyn.bench import isolators

CREEP = 0.05  # regularised vs switch law, relative, on a peak slip


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench-isolators")
    return isolators.run_bench(out, quick=True, repeats=1)


def test_files_and_rows(result):
    for f in result["files"]:
        assert Path(f).stat().st_size > 0
    assert {(r["law"], r["rtol"]) for r in result["rows"]} == {
        (law, rtol) for law in ("switch", "arctan") for rtol in isolators.RTOLS_QUICK
    }
    assert {r["n_isolators"] for r in result["scale"]} == {n * n for n in isolators.GRIDS_QUICK}
    assert [r["law"] for r in result["planar"]] == ["switch", "arctan"]
    text = isolators.report(result)
    assert "planar rigid office frame" in text and "tfp" in text


def test_the_switch_law_meets_its_tolerance_and_the_regularised_law_creeps_within_its_bound(result):
    for r in result["rows"]:
        if r["law"] == "switch":
            assert r["err_peak"] < 1e-3, r
    ref = result["ref_peak_u_m"]
    for r in result["rows"]:
        if r["law"] == "arctan":
            assert abs(r["peak_u_m"] / ref - 1) < CREEP, r


def test_the_planar_baseline_laws_agree_and_the_triple_pendulum_stays_within_capacity(result):
    p = {r["law"]: r["peak_u_m"] for r in result["planar"]}
    assert abs(p["arctan"] / p["switch"] - 1) < CREEP, p
    t = isolators.TRIPLE
    assert 0 < result["triple"]["peak_u_m"] < t["d1"] + t["d2"] + t["d3"] + t["d4"]
