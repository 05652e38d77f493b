"""Study files that ran silently wrong, or wrote where they should not, now refused or fixed.

What is asserted (behaviour, no number): a study named ".." or "." writes into a folder of
``nsdyn-study/`` like any other (its table, parts and lock landed in the working folder, and a
``--fresh`` there would have deleted them); ``scene.kind`` and ``scene.name`` are not study
parameters (a name per task repeated one run); an empty list given for objectives, quantities
or grouping columns is refused (the default ran without a word; an empty list of records keeps
the scene's own motion, as documented), as is a value given
twice (two equal rows or columns) and a ``linspace`` of count 1 that drops its end; a study
whose tasks all failed still has the kept result columns, empty; an interrupted study's folder
is said to be one when its table is read.
"""

from __future__ import annotations

import shutil

import pytest

from nsdyn.cli import main
from nsdyn.models.scenefile import SceneError
from nsdyn.studies import load_study
from nsdyn.studies.table import read_csv, read_results

HEAD = '[study]\nname = "g"\n[base.scene]\nfidelity = "rigid"\n[base.motion]\nt_end = 1.0\n'
PARAMS = '[parameters]\n"isolation.mu" = [0.02, 0.05]\n'
RECORDS = '[records]\nnames = ["synthetic-wn-40s"]\n'


def _write(tmp_path, text: str):
    p = tmp_path / "s.toml"
    p.write_text(text)
    return p


@pytest.mark.parametrize(
    ("text", "says"),
    [
        (HEAD + '[parameters]\n"scene.name" = ["a", "b"]\n',
         r"parameters\.scene\.name: names the run, not its physics"),
        (HEAD + '[parameters]\n"scene.kind" = ["isolated", "deck"]\n',
         r"parameters\.scene\.kind: a study runs the one scene kind of its base scene"),
        (HEAD + '[parameters]\n"isolation.mu" = []\n',
         r"parameters\.isolation\.mu: expected a non-empty list of values, got \[\]"),
        (HEAD + '[parameters]\n"isolation.mu" = { linspace = [0.01, 0.05, 1] }\n',
         r"linspace: a count of 1 takes `first` alone and drops `last` \(0\.05\)"),
        (HEAD + PARAMS + RECORDS + "[analysis.design]\nobjectives = []\n",
         r"analysis\.design\.objectives: expected one column name or more, got \[\]"),
        (HEAD + PARAMS + RECORDS + '[analysis.design]\nobjectives = ["idr_max", "idr_max"]\n',
         r"analysis\.design\.objectives: 'idr_max' given twice"),
        (HEAD + PARAMS + RECORDS + "[analysis.percentiles]\nquantities = []\n",
         r"analysis\.percentiles\.quantities: expected one column name or more"),
        (HEAD + PARAMS + RECORDS + '[analysis.percentiles]\nby = ["record", "record"]\n',
         r"analysis\.percentiles\.by: 'record' given twice"),
        (HEAD + PARAMS + RECORDS + "[analysis.percentiles]\npercentiles = [50, 50]\n",
         r"analysis\.percentiles\.percentiles: 50 given twice"),
        (HEAD + PARAMS + RECORDS
         + '[analysis.fragility]\nim = "pga_mps2"\nedp = "idr_max"\nlimits = [0.004, 0.004]\n',
         r"analysis\.fragility\.limits: 0\.004 given twice"),
        # the model built for that check refuses a value named (a traceback came out)
        (HEAD + "[base.solver]\ndt = 0.005\n[base.isolation]\nk_lam = [1e5, 1e5, 1e5]\n" + PARAMS,
         r"isolation\.k_lam: expected one value or 2 \(one per isolator\), got 3"),
        # and without that check: every task failed on it, one by one (office-11's two
        # isolators, one per base node: seed 004 Fig. 1)
        (HEAD + "[base.isolation]\nc = [1e4, 1e4, 1e4]\n" + PARAMS,
         r"isolation\.c: expected one value or 2 \(one per isolator\), got 3"),
        (HEAD + '[parameters]\n"solver.dt" = [0.002, 0.005]\n',
         r"solver\.dt: 0\.002 is the step of a fixed-step method, but method 'auto' chooses "
         r"the adaptive 'radau'"),
    ],
)  # fmt: skip
def test_a_study_file_that_ran_silently_otherwise_is_refused(tmp_path, text, says):
    with pytest.raises(SceneError, match=says):
        load_study(_write(tmp_path, text))


def test_a_fixed_step_varied_under_a_named_fixed_step_method_is_a_study(tmp_path):
    # the refusal above is of 'auto' choosing an adaptive method, not of solver.dt
    solver = '[base.solver]\nmethod = "genalpha"\n'
    text = HEAD + solver + '[parameters]\n"solver.dt" = [0.002, 0.005]\n'
    assert load_study(_write(tmp_path, text)).n_tasks == 2


def test_two_records_of_one_name_are_located(tmp_path):
    # a record's name is its file's stem: a/rec.txt and the folder b's rec.txt are one name,
    # refused without saying where each came from
    for d in ("a", "b"):
        (tmp_path / d).mkdir()
        (tmp_path / d / "rec.txt").write_text("0 0\n0.01 1\n")
    text = HEAD + PARAMS + '[records]\nnames = ["a/rec.txt"]\nfolder = "b"\n'
    with pytest.raises(SceneError, match=r"records: record name 'rec' appears twice: records\."
                       r"names\[0\] \('a/rec\.txt'\) and records\.folder \(.*b/rec\.txt\); "
                       r"expected each record once"):  # fmt: skip
        load_study(_write(tmp_path, text))


def test_an_empty_grouping_is_one_table_over_every_run_not_a_refusal(tmp_path):
    # by = [] pools the runs (one row); leaving by out groups by the grid parameters
    study = load_study(
        _write(tmp_path, HEAD + PARAMS + RECORDS + "[analysis.percentiles]\nby = []\n")
    )
    assert study.analysis["percentiles"]["by"] == []


@pytest.mark.parametrize(("name", "folder"), [("..", "__"), (".", "_")])
def test_a_study_named_dots_writes_inside_the_study_folder(tmp_path, monkeypatch, name, folder):
    # every task fails at once (a budget of 5 steps): the table still has the kept columns
    monkeypatch.chdir(tmp_path)
    text = HEAD.replace('"g"', f'"{name}"\nkeep = ["x_iso_max_m", "idr_max"]') + (
        "[base.solver]\nmax_steps = 5\n" + PARAMS + RECORDS
    )
    assert main(["study", str(_write(tmp_path, text)), "--workers", "1"]) == 3
    table = tmp_path / "nsdyn-study" / folder / "results.csv"
    assert table.is_file() and not (tmp_path / "results.csv").exists()
    assert not (tmp_path / "nsdyn-study" / "results.csv").exists()
    rows = read_csv(table)
    assert [r["status"] for r in rows] == ["failed", "failed"]
    assert all(r["x_iso_max_m"] is None and r["idr_max"] is None for r in rows)


def test_an_interrupted_studys_folder_is_named_as_one(tmp_path):
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "part-1.csv").write_text("index,key\n0,a\n")
    with pytest.raises(FileNotFoundError, match=r"no results\.csv yet: an interrupted study"):
        read_results(tmp_path)
    with pytest.raises(FileNotFoundError, match=r"no results\.csv; expected the folder"):
        read_results(tmp_path / "parts")


def test_a_study_interrupted_before_its_first_task_leaves_no_folder(tmp_path, monkeypatch, capsys):
    # it left a folder of its lock owner's file alone (.study.json), and an interrupt before
    # the tasks started said the generic "files on disk are complete; ... keeps no checkpoint"
    import nsdyn.studies.execute as execute
    import nsdyn.studies.study as study_mod
    from nsdyn.studies.table import OWNER

    def claimed_then_stopped(study, out, **kw):
        (out / OWNER).write_text("{}")
        raise KeyboardInterrupt

    monkeypatch.setattr(execute, "run_study", claimed_then_stopped)
    path, out = _write(tmp_path, HEAD + PARAMS + RECORDS), tmp_path / "o"
    assert main(["study", str(path), "--out", str(out)]) == 130
    assert not out.exists()
    said = "nsdyn study: interrupted before its first task finished; a rerun starts over"
    assert capsys.readouterr().err.strip() == said

    def stopped(*a, **kw):
        raise KeyboardInterrupt

    monkeypatch.setattr(study_mod, "load_study", stopped)
    assert main(["study", str(path), "--out", str(out)]) == 130
    # before the tasks start the folder is as it was: a finished table there is resumed by a
    # rerun (it said "a rerun starts over" of a --fresh study stopped while loading)
    before = ("nsdyn study: interrupted before its tasks started; the results folder is as it "
              "was (a rerun runs them)")  # fmt: skip
    assert capsys.readouterr().err.strip() == before and not out.exists()


def test_a_study_stopped_after_its_tasks_says_they_are_kept(tmp_path, monkeypatch, capsys):
    # stopped after its tasks (its report being printed, or an analysis failing under the
    # signal), a study said "interrupted before its tasks started; ... a rerun runs them" of
    # a table that held every task
    import nsdyn.cli.study as cli_study

    def stopped(*a, **kw):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli_study, "_format", stopped)
    path, out = _write(tmp_path, HEAD + PARAMS + RECORDS), tmp_path / "o"
    assert main(["study", str(path), "--out", str(out), "--no-figures"]) == 130
    said = f"nsdyn study: interrupted; 2 finished tasks kept in {out}, rerun to resume"
    assert capsys.readouterr().err.strip().endswith(said) and (out / "results.csv").is_file()


def test_a_study_whose_stop_surfaces_as_another_error_says_what_its_folder_holds(
    tmp_path, monkeypatch, capsys
):
    # a signal can surface as another error (numba's, or a library's under the signal), past
    # the study's own handler: with finished tasks in parts/ (no table yet) it said
    # "interrupted before its tasks started ... a rerun runs them"
    import nsdyn.studies.execute as execute
    from nsdyn.cli.stop import SIGNALLED

    part = [b"index,key,status\n0,a,ok\n1,b,failed\n1,b,failed\n"]  # (b: twice, one task)

    def one_batch_then_stopped(study, out, **kw):
        (out / "parts").mkdir(parents=True)
        (out / "parts" / "part-0.csv").write_bytes(part[0])
        SIGNALLED[0] = True
        raise RuntimeError("an error the signal left")

    monkeypatch.setattr(execute, "run_study", one_batch_then_stopped)
    path, out = _write(tmp_path, HEAD + PARAMS + RECORDS), tmp_path / "o"
    assert main(["study", str(path), "--out", str(out)]) == 130
    said = (f"nsdyn study: interrupted; 2 finished tasks (1 of them failed) kept in {out}, "
            "rerun to resume")  # fmt: skip
    assert capsys.readouterr().err.strip() == said
    # a part it cannot read (not UTF-8): no count, no traceback in place of the report
    part[0] = b"index,key\n0,\xff\n"
    shutil.rmtree(out)
    assert main(["study", str(path), "--out", str(out)]) == 130
    said = f"nsdyn study: interrupted; finished tasks are kept in {out}, rerun to resume"
    assert capsys.readouterr().err.strip() == said


def test_a_json_summary_of_a_study_with_failed_tasks_says_its_status(tmp_path, capsys):
    # every task fails (a budget of 5 steps): exit 3, and --json said no status where a refused
    # study's said {"status": 2, ...}
    import json

    text = HEAD + "[base.solver]\nmax_steps = 5\n" + PARAMS + RECORDS
    argv = ["study", str(_write(tmp_path, text)), "--workers", "1", "--json"]
    assert main([*argv, "--out", str(tmp_path / "o")]) == 3
    assert json.loads(capsys.readouterr().out)["status"] == 3


def test_a_rerun_with_nothing_left_says_so_not_a_worker_count(tmp_path, capsys):
    # a finished study rerun said "(0.0 s on 1 worker, batches of 1)" with --workers 2 given
    argv = ["study", str(_write(tmp_path, HEAD + PARAMS + RECORDS)), "--workers", "2",
            "--no-figures", "--out", str(tmp_path / "o")]  # fmt: skip
    assert main(argv) == 0
    capsys.readouterr()
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "2 tasks, 0 run now, 2 from before, 0 failed (nothing left to run)" in out


def test_fresh_and_retry_failed_together_are_refused(tmp_path, capsys):
    # --fresh runs every task anew: --retry-failed beside it was accepted and did nothing
    argv = ["study", str(_write(tmp_path, HEAD + PARAMS + RECORDS)), "--fresh", "--retry-failed"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err == ("nsdyn study: error: --retry-failed: with --fresh every task runs anew; give "
                   "one or the other\n")  # fmt: skip
    from nsdyn.studies.execute import run_study  # (the library as the command line)

    with pytest.raises(ValueError, match=r"^retry_failed: with fresh every task runs anew"):
        run_study(load_study(_write(tmp_path, HEAD + PARAMS + RECORDS)), tmp_path / "o",
                  fresh=True, retry_failed=True)  # fmt: skip


def test_a_misspelt_kept_column_is_named_as_one_not_as_unkept(tmp_path):
    # a scene kind whose results are known only after a run: a percentile of 'max_tilt_radd'
    # was "a result the study does not keep; add it to study.keep", a misspelt name to add
    from pathlib import Path

    scene = Path(__file__).resolve().parents[2] / "examples/scenes/contact-seed002-A5.toml"
    text = (f'[study]\nname = "c"\nscene = "{scene}"\nkeep = ["max_slide_m", "max_tilt_rad"]\n'
            '[base.motion]\nt_end = 1.0\n[parameters]\n"friction.mu_s" = [0.3, 0.6]\n'
            '[analysis.percentiles]\nquantities = ["max_tilt_radd"]\n')  # fmt: skip
    with pytest.raises(SceneError, match=r"quantities: 'max_tilt_radd' is not a kept column; did "
                       r"you mean 'max_tilt_rad'\?"):  # fmt: skip
        load_study(_write(tmp_path, text))
    far = text.replace("max_tilt_radd", "overturned")  # (a true result not kept: as before)
    with pytest.raises(SceneError, match=r"'overturned' is a result the study does not keep"):
        load_study(_write(tmp_path, far))


@pytest.mark.parametrize("n", [10**8, 10**20])
def test_a_simulated_record_count_past_a_studys_most_tasks_is_refused_before_any_draw(tmp_path, n):
    # the seeds were drawn before the task count was checked: 1e8 (a typo for 100) sat
    # silent, 1e20 ended in numpy's "Maximum allowed dimension exceeded"
    p = _write(tmp_path, HEAD + f"[records]\nsimulated = {{n = {n}, seed = 1, duration = 5.0}}\n")
    with pytest.raises(SceneError, match=r"simulated\.n: expected an integer >= 1 and at most"):
        load_study(p)


@pytest.mark.parametrize(
    "text, said",
    [('[frame]\nname = "f"\n', r"a frame file \(its \[frame\] table\), not a study; name it "
      r"in a study as \[base\.scene\] frame"),
     ('[frame3d]\nname = "f"\n', r"a frame file \(its \[frame3d\] table\), not a "
      r"study; name it in a study as \[base\.structure\] frame3d"),
     ("[isolation]\nmu = 0.05\n", r"a scene file, not a study")],
)  # fmt: skip
def test_a_frame_or_a_scene_of_tables_alone_given_as_a_study_is_named_as_what_it_is(
    tmp_path, text, said
):
    # they were "[frame]: unknown table; expected some of ['analysis', 'base', ...]", where
    # the other commands say what the file is and where it goes
    with pytest.raises(SceneError, match=said):
        load_study(_write(tmp_path, text))


def test_an_interrupted_study_counts_and_empties_its_folder_under_its_lock(
    tmp_path, monkeypatch, capsys
):
    # the count and the removal ran after the lock was let go: a study that took the folder
    # in between lost its owner file
    import nsdyn.cli.study as cli_study
    import nsdyn.studies.execute as execute
    from nsdyn.atomic import LOCK
    from nsdyn.studies.table import OWNER

    locked = []
    count = cli_study.kept_tasks

    def kept_tasks(out):
        locked.append((out / LOCK).exists())
        return count(out)

    def claimed_then_stopped(study, out, **kw):
        (out / OWNER).write_text("{}")
        raise KeyboardInterrupt

    monkeypatch.setattr(cli_study, "kept_tasks", kept_tasks)
    monkeypatch.setattr(execute, "run_study", claimed_then_stopped)
    path, out = _write(tmp_path, HEAD + PARAMS + RECORDS), tmp_path / "a" / "o"
    assert main(["study", str(path), "--out", str(out)]) == 130
    assert locked == [True] and not (tmp_path / "a").exists()  # (the parents it made too)
    assert "interrupted before its first task finished" in capsys.readouterr().err
