"""Studies of deck and 3D building scenes refuse what would repeat one run or mislead, at load:
a parameter the rung never reads (its rows were equal to the last bit), one incident direction
given twice (0 and 360 deg), a records set or a motion kind the two-component records replace;
a cb rung without a fixed-interface mode is said once for the study (its rows were a rigid
building's, drifts of round-off, without a word); a study changed after loading is checked
again by run_study; an interrupted run on another grid leaves no table or analysis of the old
grid beside its rows."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from nsdyn._checks import InputWarning
from nsdyn.models.scenefile import SceneError
from nsdyn.studies import load_study, run_study
from nsdyn.studies.analyses import fragility_outcomes
from nsdyn.studies.table import ANALYSIS_FILES, OUTSIDE, RESULTS, ResultsStore, Table, read_csv

DECK = (Path(__file__).resolve().parents[2] / "examples/scenes/deck-fps4-3c.toml").read_text()

PORTAL = """
[scene]
kind = "building3d"
[structure]
frame3d = "portal-3d"
fidelity = "{fidelity}"
{structure}
[motion]
kind = "record3"
record = "synthetic-wn-40s"
t_end = 1.0
"""

BEARING = """
[bearing]
type = "fps"
radius = 2.2
mu = 0.05
[solver]
law = "arctan"
"""


def _study(tmp_path, scene: str, body: str) -> object:
    (tmp_path / "scene.toml").write_text(scene)
    p = tmp_path / "study.toml"
    p.write_text(f'[study]\nname = "s"\nscene = "scene.toml"\n{body}')
    return p


@pytest.mark.parametrize(
    ("scene", "body", "match"),
    [
        # the switch law has no sharpness; a fixed base has no bearing and no integrator
        (DECK, '[parameters]\n"solver.eps" = [1e-3, 1e-2]\n',
         r"parameters.solver.eps: no task reads it \(solver.eps not used"),
        (PORTAL.format(fidelity="fixed", structure="n_modes = 6"),
         '[parameters]\n"bearing.mu" = [0.03, 0.08]\n',
         r"parameters.bearing.mu: no task reads it \(\[bearing\] not used: the fixed rung"),
        (PORTAL.format(fidelity="fixed", structure="n_modes = 6"),
         '[parameters]\n"structure.f_max" = [3.0, 8.0]\n',
         r"parameters.structure.f_max: no task reads it \(structure.f_max not used"),
        # the rotation turns the pair by exact cosines: 0 and 360 deg are one run
        (DECK, '[parameters]\n"motion.rotate" = [0.0, 90.0, 360.0]\n',
         r"motion.rotate.values: expected distinct values, got 360.0 and 0.0, one direction"),
        (DECK, '[parameters]\n"motion.rotate" = { linspace = [-180.0, 180.0, 5] }\n',
         r"motion.rotate.linspace: expected distinct values, got 180.0 and -180.0"),
        (DECK, '[records]\nset = "kobe"\n', r"records.set: 'kobe': one horizontal component"),
        (DECK, '[base.motion]\nkind = "record"\n[records]\nnames = ["synthetic-wn-40s"]\n',
         r"motion.kind: expected 'record3' \(the kind \[records\] drive\), got 'record'"),
        (DECK, '[parameters]\n"motion.pga" = [1.0, 2.0]\n[analysis.incidence]\n'
               'angle = "motion.pga"\n',
         r"analysis.incidence.angle: expected an angle in degrees"),
        # one angle: "max at 30 deg", a directionality of 1
        (DECK, '[parameters]\n"motion.rotate" = [30.0]\n[analysis.incidence]\n',
         r"analysis.incidence.angle: 'motion.rotate' takes one value \(30.0\); an incidence"),
        (DECK, '[parameters]\n"motion.pga" = [1.0, 2.0]\n[analysis.design]\n'
               'objectives = ["peak_resultant_displacement_m"]\n'
               "constraints = { peak_base_shear_N = { min = 5.0, max = 1.0 } }\n",
         r"constraints.peak_base_shear_N: expected min <= max"),
    ],
)  # fmt: skip
def test_what_would_repeat_one_run_or_mislead_is_refused_at_load(tmp_path, scene, body, match):
    with pytest.raises(SceneError, match=match) as e:
        load_study(_study(tmp_path, scene, body))
    assert "\n" not in str(e.value)


def test_an_empty_study_name_is_refused(tmp_path):
    p = _study(tmp_path, DECK, "")
    p.write_text(p.read_text().replace('name = "s"', 'name = ""'))
    with pytest.raises(SceneError, match=r"study.name: expected a non-empty text"):
        load_study(p)


def test_the_bundled_set_of_a_two_component_study_is_the_records_with_two():
    from nsdyn.ground import bundled_records, bundled_records3
    from nsdyn.studies.study import _record_set

    names = [r.name for r in _record_set("s.toml", "bundled", "deck")]
    assert names == list(bundled_records3())
    assert [r.name for r in _record_set("s.toml", "bundled", "isolated")] == list(bundled_records())


def test_a_cb_rung_without_a_mode_below_f_max_is_said_once_for_the_study(tmp_path):
    # the portal's first fixed-base mode is above 0.05 Hz: the cb model keeps none below it
    scene = PORTAL.format(fidelity="cb", structure="f_max = 0.05") + BEARING
    p = _study(tmp_path, scene, '[parameters]\n"bearing.mu" = [0.03, 0.08]\n')
    with pytest.warns(InputWarning, match=r"2 of 2 tasks: the cb model keeps no fixed-interface"):
        load_study(p)


@pytest.mark.parametrize("scene", [DECK, PORTAL.format(fidelity="rigid", structure="") + BEARING])
def test_a_t_end_past_the_record_is_said_once_for_the_study(tmp_path, scene, capsys):
    # the bundled three-component record ends at 40 s: a deck's or building's study at t_end =
    # 100 s ran to 40 s and its table said t_end_s = 40 without a word (nsdyn run notes it)
    body = '[base.motion]\nt_end = 100.0\n[parameters]\n"bearing.radius" = [1.5, 3.0]\n'
    p = _study(tmp_path, scene, body)
    with pytest.warns(InputWarning, match=r"2 of 2 tasks: t_end = 100 s is past the "
                      r"excitation's end \(40 s\); the run ends there$"):  # fmt: skip
        load_study(p)
    if scene is DECK:  # --json carries it too (said on stderr only)
        import json

        from nsdyn.cli import main

        argv = ["study", str(p), "--out", str(tmp_path / "o"), "--workers", "1", "--json"]
        assert main([*argv, "--no-figures"]) == 0
        said = json.loads(capsys.readouterr().out)["warnings"]
        assert any("2 of 2 tasks: t_end = 100 s is past the excitation's end" in w for w in said)


def test_a_parameter_some_tasks_do_not_read_is_said(tmp_path):
    # the fixed rung takes no bearing: beside the rigid one, its radii repeat one run (the
    # design and percentile analyses then counted the copies as designs of their own)
    scene = PORTAL.format(fidelity="rigid", structure="") + BEARING
    body = (
        '[parameters]\n"structure.fidelity" = ["rigid", "fixed"]\n"bearing.radius" = [1.5, 3.0]\n'
    )
    with pytest.warns(InputWarning, match=r"parameters\.bearing\.radius: 2 of 4 tasks do not "
                      r"read it \(\[bearing\] not used: the fixed rung"):  # fmt: skip
        load_study(_study(tmp_path, scene, body))


def test_run_study_checks_a_study_changed_after_loading(tmp_path):
    study = load_study(_study(tmp_path, DECK, '[parameters]\n"motion.rotate" = [0.0, 90.0]\n'))
    twice = replace(study, parameters=[replace(study.parameters[0], values=(0.0, 0.0))])
    with pytest.raises(SceneError, match=r"tasks 0 and 1 are one run"):
        run_study(twice, tmp_path / "o1", workers=1)
    nan = replace(study, parameters=[replace(study.parameters[0], values=(0.0, float("nan")))])
    with pytest.raises(SceneError, match=r"motion.rotate: expected a finite number, got nan"):
        run_study(nan, tmp_path / "o2", workers=1)
    # no values: no task (it wrote a results.csv of one column, and an empty table)
    none = replace(study, parameters=[replace(study.parameters[0], values=())])
    with pytest.raises(SceneError, match=r"parameters.motion.rotate: expected a non-empty list "
                       r"of values, got \[\]$"):  # fmt: skip
        run_study(none, tmp_path / "o3", workers=1)
    assert not any((tmp_path / o / RESULTS).exists() for o in ("o1", "o2", "o3"))


def test_a_run_on_another_grid_first_narrows_the_table_and_drops_the_old_analyses(tmp_path):
    store = ResultsStore(tmp_path, ["p"])
    rows = [{"index": i, "key": k, "record": "r", "p": float(i), "status": "ok", "error": "",
             "task_s": 0.1, "peak": 1.0 + i} for i, k in enumerate("ab")]  # fmt: skip
    Table(rows, ["p"]).write_csv(tmp_path / RESULTS)
    old = tmp_path / ANALYSIS_FILES[0]
    old.write_text("made from the old grid\n")
    assert not store.regrid({"a": 0, "b": 1})  # the same grid: nothing to do
    assert old.is_file()
    assert store.regrid({"a": 0, "c": 1})  # b is outside the new grid
    assert [r["key"] for r in read_csv(tmp_path / RESULTS)] == ["a"]
    assert [r["key"] for r in read_csv(tmp_path / OUTSIDE)] == ["b"]
    assert not old.exists()
    assert not store.regrid({"a": 0, "c": 1})  # rows kept outside are not another grid's
    # a grid keeping none of the rows leaves no results.csv (it left a header-only table, an
    # empty study to a script reading it while the run was interrupted) and all rows outside
    assert store.regrid({"d": 0})
    assert not (tmp_path / RESULTS).exists()
    assert sorted(r["key"] for r in read_csv(tmp_path / OUTSIDE)) == ["a", "b"]


def test_a_narrowed_grid_keeps_its_failed_rows_outside_too(tmp_path):
    # they were dropped without a word, and a grid widened again reran them without
    # --retry-failed (a resume does not); kept, a wider grid takes them back as they were
    store = ResultsStore(tmp_path, ["p"])
    status = {"a": "ok", "b": "ok", "f": "failed"}
    rows = [{"index": i, "key": k, "record": "r", "p": float(i), "status": st, "error": "",
             "task_s": 0.1} for i, (k, st) in enumerate(status.items())]  # fmt: skip
    Table(rows, ["p"]).write_csv(tmp_path / RESULTS)
    assert store.regrid({"a": 0})
    assert [r["key"] for r in read_csv(tmp_path / OUTSIDE)] == ["b", "f"]
    assert store.n_outside == 2
    assert store.read()["f"]["status"] == "failed"  # (what a wider grid reads back)


def test_a_fragility_on_a_column_no_run_has_names_it_instead_of_failed_runs():
    rows = [{"status": "ok", "motion.pga": 1.0 + i, "peak_base_shear_N": 2.0} for i in range(3)]
    out = fragility_outcomes(Table(rows), "motion.pga", "idr_max")
    assert out["refuse"].startswith("fragility: 'idr_max': no number in any successful row")
    assert "peak_base_shear_N" in out["refuse"]  # (the columns it might have meant)


def test_a_record_s_units_are_said_once_for_the_study_not_once_per_run(tmp_path, capsys):
    from nsdyn.cli import main

    t = 0.01 * np.arange(200)  # a t, ax, ay CSV without units: m/s² assumed, with a warning
    rows = "\n".join(f"{a:.2f},{np.sin(a):.6f},{np.cos(a):.6f}" for a in t)
    (tmp_path / "rec.csv").write_text("t,ax,ay\n" + rows + "\n")
    body = '[parameters]\n"motion.rotate" = [0.0, 45.0, 90.0]\n[records]\nnames = ["rec.csv"]\n'
    study = _study(tmp_path, DECK, body)
    out = str(tmp_path / "o")
    assert main(["study", str(study), "--out", out, "--workers", "1", "--no-figures"]) == 0
    err = capsys.readouterr().err
    assert err.count("does not state its units") == 1, err  # (once per task before)


def test_a_study_s_kept_systems_differ_where_the_solver_picks_the_full_rung_s_path(monkeypatch):
    # the system kept per process was keyed without [solver]: a study varying solver.path
    # (dense or sparse full rung), law or contact ran every task on the first task's path
    import nsdyn.models.isolated.building3d_scene as b3
    from nsdyn.studies import scenes3c

    built = []
    monkeypatch.setattr(b3, "build_system", lambda cfg, source: built.append(cfg) or len(built))
    monkeypatch.setattr(scenes3c, "_systems", {})
    base = {"structure": {"frame3d": "portal-3d", "fidelity": "full"}, "bearing": {"mu": 0.05}}
    for solver in ({"path": "dense"}, {"path": "sparse"}, {"path": "sparse", "rtol": 1e-4},
                   {"path": "sparse", "law": "switch"}):  # fmt: skip
        scenes3c.build_system("building3d", {**base, "solver": solver}, "s.toml")
    assert len(built) == 3  # (rtol alone does not change the model: the kept one serves)


def test_a_fragility_refusal_quotes_an_unknown_failure_whole_words_only():
    # the first unknown failure was cut at character 160, mid-word
    why = "uplift: " + " ".join(f"word{i:03d}" for i in range(40))
    rows = [{"status": "ok", "motion.pga": 1.0 + i, "idr_max": 0.01} for i in range(3)]
    rows.append({"status": "failed", "motion.pga": 4.0, "error": why})
    refuse = fragility_outcomes(Table(rows), "motion.pga", "idr_max")["refuse"]
    quoted = refuse.split("(first: ", 1)[1].split("); fix them", 1)[0]
    assert quoted.endswith(" ...") and len(quoted) <= 160
    assert why.startswith(quoted[: -len(" ...")] + " ")  # (a whole word before the cut)
