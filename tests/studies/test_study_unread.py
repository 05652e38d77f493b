"""Study inputs that every task would drop are refused when the study is loaded.

Before, each ran: a parameter the model does not read (a Moreau–Jean step under the event
method, springs on a fixed cylinder base) gave tasks that repeat one run, with a note only in
each row's ``notes``; a closed-form motion key in [base.motion] under [records] was replaced
by every record without a word; a landing's restitution without unilateral contact became a
column of failed rows (status 3) instead of an input error. The contract: one SceneError
naming the study file and the field, before any run (status 2 on the command line).
A harmonic scene's [base.motion] keys are checked against its own motion (they were checked
against a record's), and a given t_end replaces the scene's n_periods as --t-end does.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import pytest

from nsdyn.models.scenefile import SceneError
from nsdyn.studies.study import load_study
from nsdyn.studies.tasks import expand

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"


def _study(tmp_path, scene: str, body: str) -> Path:
    path = tmp_path / "s.toml"
    path.write_text(f'[study]\nscene = "{SCENES / scene}"\n{body}')
    return path


@pytest.mark.parametrize(
    ("scene", "body", "match"),
    [
        ("contact-seed002-A5.toml", '[parameters]\n"solver.h" = [1e-3, 5e-4]\n',
         r"parameters.solver.h: no task reads it \(solver.h not used: method 'event'"),
        ("cylinder-uplift.toml",
         '[base.foundation]\ncase = "fixed"\n[parameters]\n"foundation.f_rock" = [2.0, 6.0]\n',
         r"parameters.foundation.f_rock: no task reads it \(.*a fixed base"),
        ("rocking-seed003-column.toml",
         '[base.motion]\npulse = "rect"\na_p_g = 2.0\n[records]\nnames = ["synthetic-kt-20s"]\n',
         r"base.motion.(pulse|a_p_g): a key of the scene's closed-form motion, which every "
         r"record of \[records\] replaces"),
        ("isolated-uplift-pocket.toml",
         '[base.isolation]\ncontact = "bilateral"\n'
         '[parameters]\n"solver.restitution" = [0.0, 0.7]\n',
         r"solver.restitution: a landing's coefficient needs isolation.contact = 'unilateral'"),
    ],
)  # fmt: skip
def test_inputs_every_task_would_drop_are_refused_at_load(tmp_path, scene, body, match):
    with pytest.raises(SceneError, match=match):
        load_study(_study(tmp_path, scene, body))


def test_a_parameter_some_tasks_read_is_kept(tmp_path):
    # f_rock is read on the tensionless and bonded bases, not on the fixed one: kept
    body = (
        "[base.motion]\nduration = 2.0\n[parameters]\n"
        '"foundation.case" = ["tensionless", "fixed"]\n"foundation.f_rock" = [2.0, 6.0]\n'
    )
    assert len(expand(load_study(_study(tmp_path, "cylinder-uplift.toml", body)))) == 4


FRAME = '[study]\nname = "f"\n[base.scene]\nfidelity = "rigid"\n[base.motion]\nt_end = 1.0\n'


@pytest.mark.parametrize(
    ("isolation", "varied", "says"),
    [
        # a [base] key the model does not read, said as `nsdyn run` says it (the study was silent)
        ('eta = 0.5', '"isolation.mu" = [0.02, 0.05]',
         r"2 of 2 tasks: isolation.eta not used: a key of the switch law; the law here is arctan"),
        # a switch band that blurs the friction: the run's NotedWarning, which a study's runs
        # ignore, said once for the study (friction.coarse_law_note: eta above 1e-3 m/s)
        ('law = "switch"\neta = 0.5', '"isolation.mu" = [0.02, 0.05]',
         r"2 of 2 tasks: isolation.eta = 0.5 m/s: the switch law holds a stuck isolator only"),
    ],
)  # fmt: skip
def test_a_frame_study_says_its_base_keys_as_a_run_does(tmp_path, isolation, varied, says):
    path = tmp_path / "s.toml"
    path.write_text(f"{FRAME}[base.isolation]\n{isolation}\n[parameters]\n{varied}\n")
    with pytest.warns(UserWarning, match=says):
        load_study(path)


@pytest.mark.parametrize(
    ("varied", "says"),
    [
        # a value equal to the default counted as not given: "2 of 4 tasks do not read it"
        ('"isolation.eps" = [1000.0, 7500.0]',
         r"parameters.isolation.eps: no task reads it \(isolation.eps not used: a key of the "
         r"arctan law; the law here is switch"),
    ],
)  # fmt: skip
def test_keys_the_event_method_does_not_read_are_refused(tmp_path, varied, says):
    path = tmp_path / "s.toml"
    path.write_text(f'{FRAME}[base.solver]\nmethod = "event"\n[parameters]\n{varied}\n')
    with pytest.raises(SceneError, match=says):
        load_study(path)


def test_a_law_the_event_method_replaces_is_said(tmp_path):
    # the event method integrates the switch law: its arctan task repeats the switch one
    path = tmp_path / "s.toml"
    path.write_text(f'{FRAME}[base.solver]\nmethod = "event"\n[parameters]\n'
                    '"isolation.law" = ["arctan", "switch"]\n')  # fmt: skip
    with pytest.warns(UserWarning, match=r"parameters.isolation.law: 1 of 2 tasks do not read it "
                      r"\(isolation.law not used: the event method integrates the switch law in "
                      r"place of the arctan law\)"):  # fmt: skip
        load_study(path)


def test_an_event_study_of_the_switch_law_is_not_told_its_law_is_unread(tmp_path):
    # the event method's switch law is the law given: no "isolation.law not used" note
    path = tmp_path / "s.toml"
    path.write_text(f'{FRAME}[base.solver]\nmethod = "event"\n[base.isolation]\nlaw = "switch"\n'
                    '[parameters]\n"isolation.mu" = [0.02, 0.05]\n')  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        load_study(path)


def test_a_large_pga_over_many_tasks_is_said_once(tmp_path):
    # a PGA above 30 m/s² (in gal?) is a UnitWarning; one per value flooded a study's start
    path = tmp_path / "s.toml"
    path.write_text(f'{FRAME}[parameters]\n"motion.pga" = [31.0, 40.0, 50.0]\n')
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        load_study(path)
    assert sum("a PGA above 30 m/s²" in str(w.message) for w in said) == 1


def test_a_frame_study_varying_a_key_of_another_law_is_refused(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(f'{FRAME}[parameters]\n"isolation.eta" = [1e-4, 1e-3]\n')
    with pytest.raises(SceneError, match=r"parameters.isolation.eta: no task reads it "
                       r"\(isolation.eta not used: a key of the switch law"):  # fmt: skip
        load_study(path)


@pytest.mark.parametrize("key", ["n_periods = 2", "t_end = 2.0"])
def test_a_harmonic_scene_s_base_motion_is_its_own(tmp_path, key):
    # "base.motion.n_periods: unknown field; expected some of ['dt', 'pga', 'record', ...]"
    # and, for t_end over the scene's n_periods, "give one, not both"
    body = f'[base.motion]\n{key}\n[parameters]\n"isolation.mu" = [0.05, 0.06]\n'
    (task,) = expand(load_study(_study(tmp_path, "isolated-uplift-pocket.toml", body)))[:1]
    mo = task.cfg["motion"]
    assert mo["kind"] == "harmonic" and (mo.get("n_periods") == 2 or mo.get("t_end") == 2.0)
    assert not ("t_end" in mo and "n_periods" in mo)


def test_a_design_s_default_variables_leave_the_earthquake_seed_to_the_records(tmp_path):
    # the cylinder's simulated earthquake's seed is an excitation axis: the default design
    # variables took it, so a "design" was one particular earthquake (and a reference naming
    # no seed matched seed 0, judged on one earthquake)
    from nsdyn.studies.analyses import _grid_names

    body = ('[parameters]\n"foundation.zeta" = [0.05, 0.2]\n"foundation.f_rock" = [2.0, 4.0]\n'
            '"motion.seed" = [0, 1]\n')  # fmt: skip
    study = load_study(_study(tmp_path, "cylinder-uplift.toml", body))
    assert _grid_names(study) == ["foundation.zeta", "foundation.f_rock"]
    # a 3D record's incident angle too: a design was chosen at its most favourable angle
    body = '[parameters]\n"bearing.radius" = [2.0, 3.0]\n"motion.rotate" = [0.0, 90.0]\n'
    study = load_study(_study(tmp_path, "deck-fps4-3c.toml", body))
    assert _grid_names(study) == ["bearing.radius"]


def test_true_false_outcomes_are_numbers_to_the_analyses_and_their_percentiles_are_named():
    # 'toppled' was noted as holding "no number in any successful row, statistics NaN" while
    # the design constraint and the percentile table read it as 0/1 (p16 = 0.16, ...)
    from nsdyn.studies.analyses import boolean_note, empty_columns
    from nsdyn.studies.table import Table

    rows = [{"status": "ok", "toppled": True, "max_tilt": 0.1},
            {"status": "ok", "toppled": False, "max_tilt": 0.2},
            {"status": "failed", "toppled": None, "max_tilt": None}]  # fmt: skip
    assert empty_columns(Table(rows), ["toppled", "max_tilt"]) is None
    note = boolean_note(Table(rows), ["toppled", "max_tilt"])
    assert note.startswith("'toppled': true or false in every run") and "max_tilt" not in note
    assert boolean_note(Table(rows), ["max_tilt"]) is None


def test_a_quantity_missing_from_some_successful_runs_is_named_with_its_count():
    # a group's n counts its successful runs; a quantity without a number in one of them (a
    # setback frame's drift ratio) has its percentiles over the rest, which n overstated
    from nsdyn.studies.design import percentile_table
    from nsdyn.studies.table import Table, empty_columns

    rows = [{"status": "ok", "idr": 1.0, "x": 1.0}, {"status": "ok", "idr": None, "x": 2.0},
            {"status": "ok", "idr": 3.0, "x": 3.0}, {"status": "failed", "idr": None}]  # fmt: skip
    (row,) = percentile_table(Table(rows), ["idr", "x"], [], (50,))
    assert row["n"] == 3 and row["idr_p50"] == 2.0 and row["x_p50"] == 2.0  # (median of 1, 3)
    assert empty_columns(Table(rows), ["idr", "x"]) is None  # (a refusal's test: some number)
    assert empty_columns(Table(rows), ["idr", "x"], partly=True) == (
        "'idr' (1 of 3): no number in some successful rows; their statistics are over the "
        "rest, fewer than n in the groups that lack them"
    )


def test_another_study_s_folder_is_refused_not_merged(tmp_path):
    # a rocking study written into a cylinder study's folder took its 115 rows as "tasks
    # outside this grid" and replaced its analyses
    from nsdyn.atomic import CheckpointError
    from nsdyn.studies.table import ResultsStore

    store = ResultsStore(tmp_path)
    store.claim("cyl", "cylinder")
    store.append([{"key": "k0", "index": 0, "status": "ok"}])
    store.claim("cyl", "cylinder")  # the same study resumes
    store.claim("cyl-renamed", "cylinder")  # a renamed study file of the same family reuses
    with pytest.raises(CheckpointError, match=r"of study 'cyl-renamed' \(cylinder scenes\)"):
        store.claim("rock", "rocking")
    store.reset()  # --fresh
    store.claim("rock", "rocking")


@pytest.mark.parametrize(
    ("scene", "analysis", "match"),
    [
        # the isolated frame's default quantities: an all-NaN table on a rocking study
        ("rocking-seed003-column.toml", "[analysis.percentiles]\n",
         r"analysis.percentiles.quantities: missing; the default \(idr_max, floor_acc_max_mps2\)"),
        ("cylinder-uplift.toml", "[analysis.design]\n", r"analysis.design.objectives: missing"),
        # given, as an empty list: not "missing"
        ("cylinder-uplift.toml", "[analysis.design]\nobjectives = []\n",
         r"analysis.design.objectives: expected one column name or more, got \[\] \(drop"),
        ("rocking-seed003-column.toml", "[analysis.percentiles]\nquantities = []\n",
         r"analysis.percentiles.quantities: expected one column name or more, got \[\]"),
        # a deck's or 3D building's too (they ran to an all-NaN design table and a blank plot)
        ("deck-fps4-3c.toml", "[analysis.design]\n", r"analysis.design.objectives: missing; "
         r".* a deck scene has none of it"),
        ("building3d-office-rigid.toml", "[analysis.percentiles]\n",
         r"analysis.percentiles.quantities: missing"),
        # an empty list wrote a row "max_theta_over_alpha > None"
        ("rocking-seed003-column.toml",
         '[analysis.fragility]\nim = "motion.a_p_g"\nedp = "max_theta_over_alpha"\nlimits = []\n',
         r"analysis.fragility.limits: expected a list of numbers \(one curve each\), got \[\]"),
    ],
)  # fmt: skip
def test_analyses_without_meaning_for_the_family_are_refused(tmp_path, scene, analysis, match):
    body = f'[parameters]\n"motion.t_end" = [1.0, 2.0]\n{analysis}'
    with pytest.raises(SceneError, match=match):
        load_study(_study(tmp_path, scene, body))


def test_a_fragility_without_limits_needs_a_true_false_outcome_and_a_number(tmp_path):
    # without limits a numeric EDP was cut at 0.5 without a word; a text EDP was "runs with
    # no outcome that can be counted ... fix them and rerun"
    from nsdyn.studies.analyses import _fragility
    from nsdyn.studies.table import Table

    class S:
        name = "s"
        parameters = ()

    fell = [False, False, True, False, True, True]  # (not separated in IM: a finite fit)
    rows = [{"status": "ok", "im": 1.0 + i, "theta": 0.3 * i, "outcome": "rest", "fell": f}
            for i, f in enumerate(fell)]  # fmt: skip
    res = _fragility(S, Table(rows), {"im": "im", "edp": "theta"}, tmp_path, False)
    assert "not a true/false outcome" in res["fits"][0]["error"]
    res = _fragility(S, Table(rows), {"im": "im", "edp": "outcome", "limits": [1.0]}, tmp_path,
                     False)  # fmt: skip
    assert "'outcome' is a text column ('rest', ...)" in res["fits"][0]["error"]
    res = _fragility(S, Table(rows), {"im": "im", "edp": "fell"}, tmp_path, False)
    assert "error" not in res["fits"][0]  # a true/false outcome: counted as it is


@pytest.mark.parametrize(
    ("body", "match"),
    [
        # 5 draws of no random parameter ran the grid once without a word; keep = [] wrote a
        # table of no result
        ('[study]\nsamples = 5\n[parameters]\n"motion.t_end" = [1.0, 2.0]\n',
         r"study.samples: 5 draws of no random parameter; give one \(e.g. \{ uniform"),
        ('[study]\nkeep = []\n[parameters]\n"motion.t_end" = [1.0, 2.0]\n',
         r"study.keep: an empty list keeps no result"),
    ],
)  # fmt: skip
def test_study_settings_that_change_nothing_are_refused(tmp_path, body, match):
    path = tmp_path / "s.toml"
    path.write_text(
        body.replace("[study]\n", f'[study]\nscene = "{SCENES / "cylinder-uplift.toml"}"\n')
    )
    with pytest.raises(SceneError, match=match):
        load_study(path)


def test_a_scene_choice_is_a_parameter_whether_the_base_writes_it_or_not(tmp_path):
    # "scene.model" was "unknown scene field" unless the base scene wrote model itself
    scene = tmp_path / "blk.toml"
    scene.write_text('[scene]\nkind = "rocking"\n[block]\nwidth = 0.3\nheight = 1.2\n[motion]\n'
                     'pulse = "sine"\na_p_g = 0.4\nomega_p = 12.0\nt_end = 2.0\n')  # fmt: skip
    path = tmp_path / "s.toml"
    path.write_text(
        f'[study]\nscene = "{scene}"\n[parameters]\n"scene.model" = ["block", "compliant"]\n'
    )
    assert [t.params["scene.model"] for t in expand(load_study(path))] == ["block", "compliant"]
    path.write_text(f'[study]\nscene = "{scene}"\n[parameters]\n"scene.kind" = ["contact"]\n')
    with pytest.raises(SceneError, match=r"parameters.scene.kind: a study runs the one scene kind"):
        load_study(path)


def test_an_unknown_field_names_the_scene_s_own_tables(tmp_path):
    # on a rocking study the message's example was 'isolation.mu': the key it had refused
    body = '[parameters]\n"isolation.mu" = [0.1]\n'
    said = r"unknown scene field \(expected 'table.field' of this scene's tables: block, motion"
    with pytest.raises(SceneError, match=said):
        load_study(_study(tmp_path, "rocking-seed003-column.toml", body))


def test_simulated_records_on_a_cylinder_scene_are_said_to_be_another_scale(tmp_path):
    # they ran at 0.30-0.37 m/s² beside the scene's own 3.1-3.7 m/s² earthquakes, unsaid
    from nsdyn._checks import InputWarning

    body = ('[parameters]\n"foundation.zeta" = [0.1]\n'
            "[records]\nsimulated = { n = 1, seed = 3, duration = 2.0 }\n")  # fmt: skip
    with pytest.warns(InputWarning, match=r"records.simulated: one horizontal component"):
        load_study(_study(tmp_path, "cylinder-uplift.toml", body))
    # a table in error is refused alone (the note came first, about records never made)
    body = body.replace("n = 1, seed = 3", "n = 0, seed = 3")
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        with pytest.raises(SceneError, match=r"records\.simulated\.n: expected an integer >= 1"):
            load_study(_study(tmp_path, "cylinder-uplift.toml", body))


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ('[studdy]\nname = "s"\n', r"s.toml: \[studdy\]: unknown table; did you mean 'study'\?"),
        ('[base.moton]\nt_end = 3.0\n[parameters]\n"isolation.mu" = [0.03, 0.06]\n',
         r"s.toml: \[base.moton\]: unknown table; did you mean 'motion'\?"),
        ('[base.motion]\nt_end = 3.0\nkep = 1\n[parameters]\n"isolation.mu" = [0.03]\n',
         r"s.toml: base.motion.kep: unknown field; expected some of"),
    ],
)  # fmt: skip
def test_a_misspelt_study_table_is_named_as_a_table(tmp_path, body, message):
    # "studdy: unknown field" and "[base]: [moton]: unknown table" named them otherwise than a
    # scene names its own tables ("[isolaton]: unknown table")
    path = tmp_path / "s.toml"
    path.write_text(body)
    with pytest.raises(SceneError, match=rf"^{re.escape(str(tmp_path))}/{message}"):
        load_study(path)


def test_more_samples_keep_the_values_drawn_before(tmp_path):
    # one stream for every random parameter shifted the second parameter's draws when samples
    # grew (its first sample's c went from 8580.5 to 9144.9): all its tasks ran again
    from nsdyn.studies.tasks import expand

    def draws(n):
        body = (f'[study]\nname = "r"\nsamples = {n}\nseed = 11\n[base.scene]\n'
                'fidelity = "rigid"\n[parameters]\n"isolation.mu" = { uniform = [0.02, 0.08] }\n'
                '"isolation.c" = { lognormal = [1.0e4, 0.3] }\n')  # fmt: skip
        path = tmp_path / f"r{n}.toml"
        path.write_text(body)
        return [
            (t.params["isolation.mu"], t.params["isolation.c"]) for t in expand(load_study(path))
        ]

    three, four = draws(3), draws(4)
    assert four[:3] == three and len(set(four)) == 4


@pytest.mark.parametrize(
    ("base", "param", "match"),
    [
        ('fidelity = "fixed"', '"isolation.mu" = [0.01, 0.02]',
         r"parameters.isolation.mu: no task reads it \(\[isolation\] not used: the fixed-base "
         r"model has no isolators \(mu\)\)"),
        ('fidelity = "rigid"', '"scene.f_max" = [3.0, 8.0]',
         r"parameters.scene.f_max: no task reads it \(scene.f_max not used: the cut-off of "
         r"fidelities cb and fixed; 'rigid' has none"),
    ],
)  # fmt: skip
def test_a_frame_scene_parameter_its_model_does_not_read_is_refused(tmp_path, base, param, match):
    # the isolated frame's study ran both (rows of one drift ratio); nsdyn run notes them
    path = tmp_path / "s.toml"
    path.write_text(f'[study]\nname = "s"\n[base.scene]\n{base}\n[base.motion]\nt_end = 1.0\n'
                    f"[parameters]\n{param}\n")  # fmt: skip
    with pytest.raises(SceneError, match=match):
        load_study(path)
    read = path.read_text().replace(base, 'fidelity = "cb"')  # (the cb rung reads both)
    path.write_text(read)
    assert len(expand(load_study(path))) == 2


def test_a_base_value_a_parameter_replaces_is_said(tmp_path):
    # [base.isolation] mu beside the parameter isolation.mu: every task took the parameter's
    # value and the base's was dropped without a word
    from nsdyn._checks import InputWarning

    path = tmp_path / "s.toml"
    path.write_text('[study]\nname = "s"\n[base.isolation]\nmu = 0.05\n[base.motion]\n'
                    't_end = 1.0\n[parameters]\n"isolation.mu" = [0.01, 0.02]\n')  # fmt: skip
    with pytest.warns(InputWarning, match=r"base.isolation.mu = 0.05 not used: "
                      r"parameters.isolation.mu gives every task its value"):  # fmt: skip
        study = load_study(path)
    assert [t.cfg["isolation"]["mu"] for t in expand(study)] == [0.01, 0.02]


def test_a_note_that_names_a_table_in_its_reason_is_not_a_key_unread(tmp_path):
    # "the record's column(s) 2 not used: ... give the second horizontal as [motion]
    # record_y ..." named [motion] in its reason, not as what is unused: motion.pga, which
    # every task reads, was said unread by the tasks of that record (refused with it alone)
    import warnings

    import numpy as np

    t = np.arange(0.0, 2.0, 0.01)
    np.savetxt(tmp_path / "rec.txt", np.column_stack([t, np.sin(t), np.cos(t)]))
    body = ('[base.motion]\nunits = "m/s2"\n[records]\nnames = ["rec.txt"]\n'
            '[parameters]\n"motion.pga" = [1.0, 2.0]\n')  # fmt: skip
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        load_study(_study(tmp_path, "cylinder-uplift.toml", body))
    notes = [str(w.message) for w in said]
    assert any("column(s) 2 not used" in n for n in notes)  # (the record's own note, kept)
    assert not any("do not read it" in n for n in notes)
