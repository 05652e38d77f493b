"""Design search: Pareto front against brute force, feasibility, compromise, percentiles.

Sources: the definition of dominance (minimised objectives) checked by an independent double
loop; percentiles against numpy on the group's values.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from nsdyn.studies.design import (
    compromise,
    design_points,
    few_runs_note,
    find_design,
    pareto_front,
    percentile_table,
)
from nsdyn.studies.table import Table, read_csv


def _dominated(F, i, idx):
    return any(
        all(F[j, k] <= F[i, k] for k in range(F.shape[1]))
        and any(F[j, k] < F[i, k] for k in range(F.shape[1]))
        for j in idx
        if j != i
    )


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 6), st.integers(0, 6)), min_size=1, max_size=25))
def test_pareto_front_is_the_non_dominated_set(pts):
    F = np.array(pts, dtype=float)
    got = set(pareto_front(F).tolist())
    want = {i for i in range(len(F)) if not _dominated(F, i, range(len(F)))}
    assert got == want


def _table():
    # designs (mu, c) over 3 records; objectives f1 = mu-ish, f2 = 1/mu-ish; x_iso decreases
    rows, rng = [], np.random.default_rng(0)
    for mu in (0.01, 0.03, 0.05):
        for c in (1e4, 2e4):
            for rec in ("a", "b", "c"):
                rows.append(
                    {
                        "record": rec,
                        "isolation.mu": mu,
                        "isolation.c": c,
                        "status": "ok",
                        "idr_max": mu * (1 + 0.1 * rng.random()) + c * 1e-7,
                        "floor_acc_max_mps2": 0.01 / mu + c * 1e-6,
                        "x_iso_max_m": 0.008 / mu,
                    }
                )
    rows[0]["status"] = "failed"  # one failed run: its design is not judged
    return Table(rows, ["isolation.mu", "isolation.c"])


def test_design_points_constraint_front_and_choice():
    t = _table()
    objs = ["idr_max", "floor_acc_max_mps2"]
    pts = design_points(t, ["isolation.mu", "isolation.c"], objs, {"x_iso_max_m": 0.4})
    assert len(pts) == 6 and all(p.n_records == 3 for p in pts)
    by = {(p.values["isolation.mu"], p.values["isolation.c"]): p for p in pts}
    assert by[(0.01, 1e4)].n_failed == 1 and not by[(0.01, 1e4)].feasible
    assert not by[(0.01, 2e4)].feasible  # x_iso = 0.8 m > 0.4 m gap
    assert by[(0.03, 1e4)].feasible and by[(0.05, 1e4)].feasible
    # c = 2e4 raises both objectives: dominated by c = 1e4 at the same mu
    front = {k for k, p in by.items() if p.pareto}
    assert front == {(0.03, 1e4), (0.05, 1e4)}
    f = [r["idr_max"] for r in t.rows if r["isolation.mu"] == 0.03 and r["isolation.c"] == 1e4]
    assert by[(0.03, 1e4)].objectives["idr_max"] == pytest.approx(np.mean(f), rel=1e-14)
    chosen = compromise(pts, objs)
    assert chosen.pareto
    assert find_design(pts, {"isolation.mu": 0.03, "isolation.c": 1e4}) is by[(0.03, 1e4)]


def test_a_lower_bound_takes_the_smallest_record():
    # {min = g} holds when the smallest value over a design's records is >= g (the worst
    # record of a lower bound); a number stays an upper bound on the largest
    t = _table()
    for r in t.rows:  # a stick margin that falls with the record: a, b, c -> 1.0, 0.8, 0.6 mu/0.05
        r["stick_margin"] = r["isolation.mu"] / 0.05 * {"a": 1.0, "b": 0.8, "c": 0.6}[r["record"]]
    objs = ["idr_max", "floor_acc_max_mps2"]
    cons = {"x_iso_max_m": 0.4, "stick_margin": {"min": 0.3}}
    pts = design_points(t, ["isolation.mu", "isolation.c"], objs, cons)
    by = {(p.values["isolation.mu"], p.values["isolation.c"]): p for p in pts}
    p = by[(0.03, 1e4)]
    assert p.constraints["stick_margin_least"] == pytest.approx(0.03 / 0.05 * 0.6, rel=1e-14)
    assert p.constraints["x_iso_max_m_worst"] == pytest.approx(0.008 / 0.03, rel=1e-14)
    assert p.feasible  # 0.36 >= 0.3
    assert not by[(0.01, 2e4)].feasible  # 0.12 < 0.3 (and x_iso 0.8 m > 0.4 m)
    both = design_points(t, ["isolation.mu", "isolation.c"], objs,
                         {"stick_margin": {"min": 0.3, "max": 0.7}})  # fmt: skip
    feasible = {(q.values["isolation.mu"], q.values["isolation.c"]) for q in both if q.feasible}
    assert feasible == {(0.03, 1e4), (0.03, 2e4)}  # mu 0.05: record a's 1.0 > 0.7


def test_percentile_table_matches_numpy():
    t = _table()
    rows = percentile_table(t, ["idr_max"], ["isolation.mu"], q=(16, 50, 84))
    assert [r["isolation.mu"] for r in rows] == [0.01, 0.03, 0.05]
    for r in rows:
        v = np.array(
            [
                x["idr_max"]
                for x in t.rows
                if x["isolation.mu"] == r["isolation.mu"] and x["status"] == "ok"
            ]
        )
        assert r["n"] == v.size
        for q in (16, 50, 84):
            assert r[f"idr_max_p{q}"] == pytest.approx(np.percentile(v, q), rel=1e-14)


def test_few_runs_note_marks_the_groups_whose_outer_percentiles_only_interpolate():
    # the bound n >= 1 + 100/p (8 runs for p16 and p84) against numpy itself: with 7 runs the
    # 16th percentile lies between the two lowest runs, with 8 past the second lowest
    for n, inside in ((7, True), (8, False)):
        x = np.arange(1.0, n + 1)
        assert bool(np.percentile(x, 16) < x[1]) is inside
        assert bool(np.percentile(x, 84) > x[-2]) is inside
    rows = [{"n": 2}, {"n": 8}, {"n": 7}]
    note = few_runs_note(rows, (16, 50, 84))
    assert note.startswith("2 of 3 group(s) with fewer than 8 successful runs (fewest 2)")
    assert "there p16, p50, p84 are interpolated" in note  # the median of 2 is their mean too
    assert few_runs_note([{"n": 8}], (16, 50, 84)) is None
    assert few_runs_note([{"n": 2}], (0, 100)) is None  # min and max: no interpolation
    assert "fewer than 11" in few_runs_note([{"n": 10}], (10, 90))
    # a group whose every run failed has no percentile at all: said as such (it was counted
    # among the groups "interpolated between the extreme runs")
    assert few_runs_note([{"n": 0}, {"n": 8}], (16, 50, 84)) == (
        "1 of 2 group(s) without a successful run (their percentiles are empty)"
    )
    both = few_runs_note([{"n": 0}, {"n": 3}], (16, 50, 84))
    assert both.startswith("1 of 2 group(s) without a successful run") and "(fewest 3)" in both
    # a group of one run: every percentile is its value (np.percentile of one number)
    assert np.percentile([0.3], 16) == np.percentile([0.3], 84) == 0.3
    assert "or the one run's value in a group of one" in few_runs_note([{"n": 1}], (16, 84))


def test_a_fixed_base_design_meets_the_default_gap(tmp_path, capsys):
    # a fixed base has no isolator to cross the 400 mm seismic gap (seed 004 §5): its rows
    # have no x_iso_max_m (NaN when read back from results.csv), which made every fixed-base
    # design infeasible; its worst isolator displacement is 0, with a keep list that drops
    # the fidelity column and when the study is run again from its table
    from nsdyn.cli import main

    p = tmp_path / "s.toml"
    p.write_text('[study]\nname = "fx"\nkeep = ["x_iso_max_m", "idr_max", "floor_acc_max_mps2"]\n'
                 '[base.motion]\nt_end = 0.5\n[parameters]\n'
                 '"scene.fidelity" = ["fixed", "rigid"]\n[records]\nnames = ["synthetic-wn-40s"]\n'
                 '[analysis.design]\nvariables = ["scene.fidelity"]\n'
                 'objectives = ["idr_max", "floor_acc_max_mps2"]\n')  # fmt: skip
    out = tmp_path / "o"
    for _ in range(2):  # run, then again from its table (every task from before)
        assert main(["study", str(p), "--out", str(out), "--no-figures"]) == 0
        design = {r["scene.fidelity"]: r for r in read_csv(out / "design.csv")}
        assert float(design["fixed"]["x_iso_max_m_worst"]) == 0.0
        assert design["fixed"]["feasible"] in ("true", "True", True)
        assert float(design["rigid"]["x_iso_max_m_worst"]) > 0.0
    capsys.readouterr()


@pytest.mark.parametrize(
    ("call", "error", "message"),
    [  # a typo read as NaN made every design infeasible; a string gave one column per letter
        (lambda t: design_points(t, ["isolation.mu"], ["idr_mx"], {}), KeyError,
         "objectives: 'idr_mx': no such column; did you mean 'idr_max'?"),
        (lambda t: design_points(t, ["isolation.nu"], ["idr_max"], {}), KeyError,
         "variables: 'isolation.nu': no such column; did you mean 'isolation.mu'?"),
        (lambda t: design_points(t, ["isolation.mu"], ["idr_max"], {"x_iso_mx_m": 0.4}),
         KeyError, "constraints: 'x_iso_mx_m': no such column; did you mean 'x_iso_max_m'?"),
        (lambda t: design_points(t, ["isolation.mu"], "idr_max", {}), TypeError,
         "objectives: expected a list of column names, got 'idr_max'"),
        (lambda t: design_points(t, ["isolation.mu"], [], {}), ValueError,
         "objectives: expected one column name or more, got []"),
        (lambda t: design_points(t, ["isolation.mu"], ["idr_max"], {"x_iso_max_m": "big"}),
         ValueError, "constraints['x_iso_max_m']: expected a number (an upper bound) "
         "or {'min': a, 'max': b}, got 'big'"),
        (lambda t: design_points(t, ["isolation.mu"], ["idr_max"], {"x_iso_max_m": {"mn": 1}}),
         ValueError, "constraints['x_iso_max_m']: expected a number"),
        (lambda t: design_points(t, {"isolation.mu"}, ["idr_max"], {}), TypeError,
         "variables: expected a list of column names, got {'isolation.mu'}"),  # (no order)
        (lambda t: design_points(t, ["isolation.mu"], ["idr_max"], {"idr_max": {"max": -1e999}}),
         ValueError, "constraints['idr_max']: {'max': -inf}: no design can meet it"),
        (lambda t: design_points(t, ["isolation.mu"], ["idr_max"],
                                 {np.str_("idr_max"): {"min": 1.0, "max": 0.0}}),
         ValueError, "constraints['idr_max']: {'min': 1.0, 'max': 0.0}: no design can meet it"),
        (lambda t: design_points(t, np.array(["isolation.nu"]), ["idr_max"], {}), KeyError,
         "variables: 'isolation.nu': no such column"),  # (not np.str_('isolation.nu'))
        (lambda t: percentile_table(t, ["idr_mx"], ["isolation.mu"]), KeyError,
         "quantities: 'idr_mx': no such column; did you mean 'idr_max'?"),
        (lambda t: percentile_table(t, "idr_max", ["isolation.mu"]), TypeError,
         "quantities: expected a list of column names, got 'idr_max'"),
        (lambda t: percentile_table(t, ["idr_max"], ["isolation.mu"], q=[150]), ValueError,
         "q: expected a list of percentiles in [0, 100], got [150]"),
        (lambda t: percentile_table(t, ["idr_max"], ["isolation.mu"], q=50), ValueError,
         "q: expected a list of percentiles in [0, 100], got 50"),
        (lambda t: pareto_front(np.array([[1.0, 2], [2, 1], [3, 3]]), [True, False]),
         ValueError, "mask: expected 3 booleans (one per row of F), got shape (2,)"),
        (lambda t: pareto_front(np.array([1.0, 2, 3])), ValueError,
         "F: expected an (n, k) array of n designs' k objectives, got shape (3,)"),
    ],
)  # fmt: skip
def test_a_design_or_percentile_call_with_a_bad_argument_names_it(call, error, message):
    with pytest.raises(error) as exc:
        call(_table())
    assert message in str(exc.value)


def test_a_study_s_analyses_read_a_missing_column_as_nan_and_an_empty_table_has_no_designs():
    # strict=False: a study whose tasks all failed lacks its output columns (its note says
    # so); an empty table has no designs (it was a reshape error)
    t = _table()
    pts = design_points(t, ["isolation.mu"], ["idr_mx"], {}, strict=False)
    assert pts and all(np.isnan(p.objectives["idr_mx"]) and not p.feasible for p in pts)
    assert design_points(Table([]), ["isolation.mu"], ["idr_max"], {}) == []


def test_names_and_numbers_come_as_any_sequence_and_any_real_number():
    # a numpy array or pandas Index of names, numpy numbers as bounds and percentiles, a
    # range of percentiles and no constraints (None) are what they say, as before the checks
    t = _table()
    by_list = design_points(t, ["isolation.mu", "isolation.c"], ["idr_max"], {"x_iso_max_m": 0.4})
    by_array = design_points(t, np.array(["isolation.mu", "isolation.c"]), ("idr_max",),
                             {"x_iso_max_m": np.float32(0.4)})  # fmt: skip
    assert [p.row() for p in by_list] == [p.row() for p in by_array]
    assert all(p.feasible or p.n_failed for p in design_points(t, ["isolation.mu"], ["idr_max"],
                                                                None))  # fmt: skip
    rows = percentile_table(t, np.array(["idr_max"]), ["isolation.mu"], q=range(0, 101, 50))
    same = percentile_table(t, ["idr_max"], ["isolation.mu"],
                            q=[np.int64(0), Fraction(1, 2) * 100, 100.0])  # fmt: skip
    assert rows == same and "idr_max_p50" in rows[0]
