"""Study files: expansion and keys, and clear errors for bad files (file, field, nearest key).

Source of the expected behaviour: the study-file format in nsdyn.studies.study and the
scene-file error convention of nsdyn.models.scenefile (one line naming file and field).
"""

from __future__ import annotations

import textwrap

import pytest

from nsdyn.cli import main
from nsdyn.models.scenefile import SceneError
from nsdyn.studies.study import load_study
from nsdyn.studies.tasks import expand

GOOD = """
[study]
name = "grid"
samples = 3
seed = 5

[base.scene]
fidelity = "rigid"

[base.motion]
t_end = 2.0

[parameters]
"isolation.mu" = [0.02, 0.05]
"isolation.k_lam" = { logspace = [2.5e4, 1e5, 3] }
"motion.pga" = { uniform = [1.0, 4.0] }

[records]
names = ["synthetic-wn-40s"]
simulated = { n = 2, seed = 9, duration = 4.0 }
"""


def _write(tmp_path, text: str, name: str = "s.toml"):
    p = tmp_path / name
    p.write_text(textwrap.dedent(text))
    return p


def test_expansion_counts_orders_and_keys(tmp_path):
    study = load_study(_write(tmp_path, GOOD))
    tasks = expand(study)
    # 2 mu x 3 k_lam x 3 draws x 3 records
    assert len(tasks) == study.n_tasks == 2 * 3 * 3 * 3
    assert [t.index for t in tasks] == list(range(len(tasks)))
    assert len({t.key for t in tasks}) == len(tasks)  # every task its own key
    k = sorted({t.params["isolation.k_lam"] for t in tasks})
    assert k == pytest.approx([2.5e4, 5e4, 1e5], rel=1e-12)  # geometric grid
    pga = [t.params["motion.pga"] for t in tasks]
    assert all(1.0 <= v <= 4.0 for v in pga)
    # the same file expands to the same keys (draws are seeded); another seed changes them
    assert [t.key for t in expand(load_study(tmp_path / "s.toml"))] == [t.key for t in tasks]
    other = load_study(_write(tmp_path, GOOD.replace("seed = 5", "seed = 6"), "o.toml"))
    assert {t.key for t in expand(other)}.isdisjoint({t.key for t in tasks})


def test_more_simulated_records_keep_the_first_ones_tasks(tmp_path):
    # "editing the grid reruns exactly the tasks it changes": records named by the width of
    # n (mo-05 of 40, mo-005 of 200) renamed the first 40 and reran all of them
    text = GOOD.replace('names = ["synthetic-wn-40s"]\n', "")
    few = expand(load_study(_write(tmp_path, text.replace("n = 2,", "n = 12,"), "a.toml")))
    more = expand(load_study(_write(tmp_path, text.replace("n = 2,", "n = 120,"), "b.toml")))
    assert len({t.record_name for t in few}) == 12 and len({t.record_name for t in more}) == 120
    assert {t.key for t in few} < {t.key for t in more}


def test_records_without_a_pga_run_as_recorded(tmp_path):
    # as `nsdyn run --record`: the default scene's pga (3 m/s², its own record's) does not
    # scale a study's records; [base.motion] pga or a motion.pga parameter does
    text = GOOD.replace('"motion.pga" = { uniform = [1.0, 4.0] }\n', "").replace(
        "samples = 3\n", ""
    )
    tasks = expand(load_study(_write(tmp_path, text)))
    assert tasks and all("pga" not in t.cfg["motion"] for t in tasks)
    text = text.replace("t_end = 2.0\n", "t_end = 2.0\npga = 2.5\n")
    assert all(t.cfg["motion"]["pga"] == 2.5 for t in expand(load_study(_write(tmp_path, text))))
    # records given as a motion.record parameter alike (they were scaled to 3 m/s²)
    text = (
        textwrap.dedent(GOOD)
        .split("[records]")[0]
        .replace(
            '"motion.pga" = { uniform = [1.0, 4.0] }\n',
            '"motion.record" = ["synthetic-wn-40s", "synthetic-kt-20s"]\n',
        )
        .replace("samples = 3\n", "")
    )
    tasks = expand(load_study(_write(tmp_path, text, "p.toml")))
    assert len(tasks) == 12 and all("pga" not in t.cfg["motion"] for t in tasks)


def test_an_integer_field_takes_a_linspace_of_whole_numbers_as_integers(tmp_path):
    # solver.max_steps is an integer key of the isolated scene (its schema): a linspace of
    # whole numbers reaches the scene and the results table as ints, 1000 not 1000.0
    text = GOOD.replace('"isolation.mu" = [0.02, 0.05]',
                        '"solver.max_steps" = { linspace = [1000, 3000, 3] }')  # fmt: skip
    tasks = expand(load_study(_write(tmp_path, text)))
    got = sorted({t.params["solver.max_steps"] for t in tasks})
    assert got == [1000, 2000, 3000] and all(type(v) is int for v in got)


def test_a_real_field_written_with_whole_numbers_is_the_same_tasks(tmp_path):
    # isolation.mu = [1, 2] beside [1.0, 2.0]: the scene reads the same numbers and the loader
    # refuses [2, 2.0] as one value given twice, but the keys differed and every task ran again
    keys = []
    for vals in ("[1.0, 2.0]", "[1, 2]"):
        text = GOOD.replace('"isolation.mu" = [0.02, 0.05]', f'"isolation.mu" = {vals}')
        tasks = expand(load_study(_write(tmp_path, text, f"s{len(keys)}.toml")))
        assert all(type(t.params["isolation.mu"]) is float for t in tasks)
        keys.append([t.key for t in tasks])
    assert keys[0] == keys[1]


def test_key_follows_record_bytes_not_place(tmp_path):
    from nsdyn.ground import read_motion, write_motion

    m = read_motion("synthetic-kt-20s").window(0.0, 2.0)
    for d in ("a", "b"):
        write_motion(m, tmp_path / d / "rec.csv")
    text = GOOD.replace('names = ["synthetic-wn-40s"]', 'names = ["{d}/rec.csv"]')

    def keys(d: str, name: str) -> list[str]:
        tasks = expand(load_study(_write(tmp_path, text.replace("{d}", d), name)))
        return [t.key for t in tasks if t.record.name == "rec"]

    ka, kb = keys("a", "a.toml"), keys("b", "b.toml")
    assert len(ka) == 18 and ka == kb  # same bytes in another folder: same keys
    write_motion(m.scaled_to_pga(2 * m.pga), tmp_path / "b" / "rec.csv")
    assert set(keys("b", "c.toml")).isdisjoint(ka)  # other bytes: other keys


@pytest.mark.parametrize(
    ("change", "needle"),
    [
        (('"isolation.mu"', '"isolation.muu"'), "did you mean 'isolation.mu'"),
        (('"isolation.k_lam"', '"isolaton.k_lam"'), "did you mean 'isolation.k_lam'"),
        (("samples = 3", 'samples = "three"'), "study.samples: expected a non-negative integer"),
        (("[0.02, 0.05]", '[0.02, "high"]'), "parameters.isolation.mu.values: expected numbers"),
        (("uniform = [1.0, 4.0]", "uniform = [4.0, 1.0]"), "low < high"),
        (("logspace = [2.5e4, 1e5, 3]", "logspace = [2.5e4, 1e5]"), "[first, last, count]"),
        # a count of 1e9 built its list first: the process grew to 24 GB and was killed
        (("logspace = [2.5e4, 1e5, 3]", "linspace = [2.5e4, 1e5, 1e9]"), "a count of 1 to 1000000"),
        # a value twice made two tasks of one key, and one row of them
        (
            ("[0.02, 0.05]", "[0.02, 0.02]"),
            "isolation.mu.values: expected distinct values, got 0.02 twice",
        ),
        (("logspace = [2.5e4, 1e5, 3]", "linspace = [2.5e4, 2.5e4, 3]"), "expected distinct"),
        (('"synthetic-wn-40s"', '"synthetic-wn-04s"'), "did you mean 'synthetic-wn-40s'"),
        (('"synthetic-wn-40s"', '"no-such-record"'), "neither a file"),
        # a folder was "neither a file nor a bundled record"; the case alone off had no hint
        (('"synthetic-wn-40s"', '"."'), "records.names: '.' is a folder, expected record files"),
        (('"isolation.mu"', '"Isolation.MU"'), "did you mean 'isolation.mu'"),
        (("[0.02, 0.05]", '[0.02, "0.05"]'), "expected numbers, strings or booleans, all of one"),
        (("[records]", "[record]"), "did you mean 'records'"),
        # a name kept twice was taken as once (every other list of names refuses it)
        (
            ("seed = 5\n", 'seed = 5\nkeep = ["idr_max", "idr_max"]\n'),
            "study.keep: 'idr_max' given twice; expected distinct values",
        ),
        (("seed = 9,", "seeed = 9,"), "records.simulated.seeed: unknown field; did you mean"),
        # white-noise ordinates every 0.05 s sampled at 0.1 s (an intensity of half S0), a
        # step past the Kanai-Tajimi ground's Nyquist frequency, a step longer than the run:
        # every row failed alike before
        (
            ("duration = 4.0", "duration = 4.0, dt = 0.1"),
            "records.simulated.dt: expected a step of at most the noise's ordinate step 0.05 s",
        ),
        (
            ("duration = 4.0", 'duration = 4.0, dt = 0.25, generator = "kanai_tajimi"'),
            "records.simulated.dt: expected a positive sampling step",
        ),
        (
            ("duration = 4.0", "duration = 4.0, dt = 5.0"),
            "records.simulated.dt: expected a positive sampling step of at most the duration",
        ),
        (
            ("duration = 4.0", 'duration = 4.0, generator = "kt"'),
            "records.simulated.generator: expected one of",
        ),
        (('fidelity = "rigid"', 'fidelity = "rigidd"'), "scene.fidelity"),
        (("seed = 5", "sede = 5"), "did you mean 'seed'"),
        (('"motion.pga"', '"solver.max_steps"'), "integer field takes whole numbers"),
        (
            ('"isolation.mu" = [0.02, 0.05]', '"solver.max_steps" = { linspace = [1e3, 1001, 3] }'),
            "parameters.solver.max_steps: expected whole numbers (an integer field), got 1000.5",
        ),
    ],
)
def test_bad_study_files_name_file_and_field(tmp_path, change, needle):
    path = _write(tmp_path, GOOD.replace(*change))
    with pytest.raises(SceneError) as e:
        load_study(path)
    msg = str(e.value)
    assert msg.startswith(str(path)) and needle in msg, msg
    assert "\n" not in msg


def test_bad_analysis_and_missing_pieces(tmp_path):
    bad = GOOD + '\n[analysis.fragility]\nim = "motion.pga"\nedp = "idr_maxx"\n'
    with pytest.raises(SceneError, match="did you mean 'idr_max'"):
        load_study(_write(tmp_path, bad))
    with pytest.raises(SceneError, match="analysis.fragility.edp: missing"):
        load_study(_write(tmp_path, GOOD + '\n[analysis.fragility]\nim = "motion.pga"\n'))
    for tail, says in [
        ("[analysis]\ndesign = 3\n", r"analysis\.design: expected a table \[analysis\.design\]"),
        ("[analysis.design]\nconstraints = 0.4\n",
         r"analysis\.design\.constraints: expected a table \{name = value"),
        ("[analysis.design]\nconstraints = { x_iso_max_m = { least = 0.1 } }\n",
         r"constraints\.x_iso_max_m: expected an upper bound or a table \{min = \.\.\., max"),
        ("[analysis.design]\nconstraints = { x_iso_max_m = { min = \"a\" } }\n",
         r"constraints\.x_iso_max_m\.min: expected a number"),
    ]:  # fmt: skip
        with pytest.raises(SceneError, match=says):  # (tracebacks before: AttributeError ...)
            load_study(_write(tmp_path, GOOD + "\n" + tail))
    with pytest.raises(SceneError, match="random parameters need samples"):
        load_study(_write(tmp_path, GOOD.replace("samples = 3", "samples = 0")))
    with pytest.raises(SceneError, match="study.scene: no such scene file"):
        load_study(_write(tmp_path, GOOD.replace('name = "grid"', 'scene = "nope.toml"')))


def test_cli_bad_file_one_line_exit_2(tmp_path, capsys):
    path = _write(tmp_path, GOOD.replace('"isolation.mu"', '"isolation.muu"'))
    assert main(["study", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "did you mean 'isolation.mu'" in err[0]
    assert main(["study", str(tmp_path / "missing.toml")]) == 2


def test_fresh_start_removes_the_previous_analyses_only(tmp_path):
    """``--fresh`` forgets the table and every file the analyses write (an interrupted fresh
    run must not leave the previous run's Pareto front beside its new partial table); a file
    of the user's in the same folder stays. The names are those the analysis modules write."""
    import re
    from pathlib import Path

    import nsdyn.cli.study as cli_study
    import nsdyn.studies.analyses as analyses
    import nsdyn.studies.incidence as incidence
    from nsdyn.studies.table import ANALYSIS_FILES, RESULTS, ResultsStore

    written = set()
    for mod in (analyses, incidence, cli_study):
        written |= set(re.findall(r'out / "([^"]+)"', Path(mod.__file__).read_text()))
    assert written and written <= {RESULTS, *ANALYSIS_FILES}, written - {RESULTS, *ANALYSIS_FILES}
    for name in (RESULTS, *ANALYSIS_FILES, "notes.txt"):
        (tmp_path / name).write_text("x")
    ResultsStore(tmp_path, ["isolation.mu"]).reset()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


def test_key_follows_the_bytes_of_every_file_the_scene_reads(tmp_path):
    # a frame file and a record named in the base scene (not under [records]) are read by
    # every task: an edit of either must change the keys (a resumed study reused the rows
    # run on the old file), and a copy elsewhere with the same bytes keeps them
    from pathlib import Path

    from nsdyn.ground import read_motion, write_motion

    root = Path(__file__).resolve().parents[2]
    frame = (root / "frames" / "portal.toml").read_text()
    m = read_motion("synthetic-kt-20s").window(0.0, 2.0)
    for d in ("a", "b"):
        (tmp_path / d).mkdir()
        (tmp_path / d / "f.toml").write_text(frame)
        write_motion(m, tmp_path / d / "rec.csv")
    text = """
    [study]
    name = "files"
    [base.scene]
    frame = "{d}/f.toml"
    [base.motion]
    record = "{d}/rec.csv"
    t_end = 1.0
    [parameters]
    "isolation.mu" = [0.02, 0.05]
    """

    def keys(d: str, name: str) -> list[str]:
        return [t.key for t in expand(load_study(_write(tmp_path, text.format(d=d), name)))]

    ka = keys("a", "a.toml")
    assert len(ka) == 2 and keys("b", "b.toml") == ka  # same bytes elsewhere: same keys
    (tmp_path / "b" / "f.toml").write_text(frame.replace("[frame]", "[frame]\n# edited"))
    assert set(keys("b", "c.toml")).isdisjoint(ka)  # the frame file's bytes changed
    (tmp_path / "b" / "f.toml").write_text(frame)
    write_motion(m.scaled_to_pga(2 * m.pga), tmp_path / "b" / "rec.csv")
    assert set(keys("b", "d.toml")).isdisjoint(ka)  # the record's bytes changed


def test_nothing_beside_the_table_is_older_than_it(tmp_path, capsys):
    """A results.parquet written once stayed at the first grid's rows while the CSV grew; an
    analysis dropped from the study left its table, and --no-figures its figure."""
    pytest.importorskip("pyarrow", reason="pyarrow is not installed (the 'parquet' extra)")
    pd = pytest.importorskip("pandas", reason="pandas is not installed (the 'frames' extra)")
    from nsdyn.cli import main

    text = (
        '[study]\nname = "g"\n[base.scene]\nfidelity = "rigid"\n[base.motion]\nt_end = 1.0\n'
        '[parameters]\n"isolation.mu" = MU\n[records]\nnames = ["synthetic-wn-40s"]\n'
    )
    out = tmp_path / "o"
    p = _write(tmp_path, text.replace("MU", "[0.02, 0.05]") + "[analysis.percentiles]\n")
    assert main(["study", str(p), "--out", str(out), "--parquet", "--workers", "1"]) == 0
    assert len(pd.read_parquet(out / "results.parquet")) == 2
    assert (
        f"table: {out / 'results.csv'} (and {out / 'results.parquet'})" in capsys.readouterr().out
    )
    assert (out / "percentiles.csv").is_file() and (out / "distributions.png").is_file()
    p = _write(tmp_path, text.replace("MU", "[0.02, 0.05, 0.08]") + "[analysis.percentiles]\n")
    assert main(["study", str(p), "--out", str(out), "--no-figures", "--workers", "1"]) == 0
    assert len(pd.read_parquet(out / "results.parquet")) == 3  # in step with the table
    assert (out / "percentiles.csv").is_file() and not (out / "distributions.png").exists()
    p = _write(tmp_path, text.replace("MU", "[0.02, 0.05, 0.08]"))
    assert main(["study", str(p), "--out", str(out), "--workers", "1"]) == 0
    assert not (out / "percentiles.csv").exists()
    capsys.readouterr()


def test_a_studys_own_columns_are_never_results(tmp_path, capsys):
    """A kept ``key`` lost the table and a kept parameter emptied its column (a result of that
    name wrote over it): refused. With the default keep, a run summary's ``record`` (a
    simulated record's generator name) wrote over the task's; the task's stays."""
    from nsdyn.models.scenefile import SceneError
    from nsdyn.studies.execute import run_study
    from nsdyn.studies.tasks import expand

    head = '[study]\nname = "k"\nKEEP[base.scene]\nfidelity = "rigid"\n[base.motion]\n'
    tail = ('t_end = 1.0\n[parameters]\n"isolation.mu" = [0.02, 0.05]\n[records]\n'
            "simulated = { n = 1, seed = 3, duration = 1.0 }\n")  # fmt: skip
    for keep in ('"key"', '"isolation.mu"', '"record"'):
        p = _write(tmp_path, head.replace("KEEP", f'keep = [{keep}, "x_iso_max_m"]\n') + tail)
        name = keep.strip('"').replace(".", "[.]")
        with pytest.raises(SceneError, match=rf"study\.keep: '{name}' is a column of the table"):
            load_study(p)
    st = load_study(_write(tmp_path, head.replace("KEEP", "") + tail))
    table = run_study(st, tmp_path / "o", workers=1).table
    assert [r["record"] for r in table.rows] == [t.columns()["record"] for t in expand(st)]
    assert all(r["isolation.mu"] in (0.02, 0.05) for r in table.rows)
    capsys.readouterr()


def test_analyses_say_why_their_statistics_are_nan(tmp_path, capsys):
    """The default design constraint on a result the keep drops, and a fragility IM that is
    0 on every run (the rigid rung's drift), gave NaN or '0 of 0' without a reason; the
    fragility chart of no run with IM > 0 was a traceback."""
    from nsdyn.cli import main

    text = ('[study]\nname = "n"\nkeep = ["idr_max", "floor_acc_max_mps2"]\n[base.scene]\n'
            'fidelity = "rigid"\n[base.motion]\nt_end = 1.0\n[parameters]\n'
            '"motion.pga" = [1.0, 2.0]\n[records]\nnames = ["synthetic-wn-40s"]\n'
            '[analysis.design]\n[analysis.fragility]\nim = "idr_max"\nedp = '
            '"floor_acc_max_mps2"\nlimits = [2.0]\n')  # fmt: skip
    assert main(["study", str(_write(tmp_path, text)), "--out", str(tmp_path / "o")]) == 0
    out = capsys.readouterr().out
    assert "design: note: 'x_iso_max_m': no number in any successful row" in out
    assert "fragility: note: 2 successful runs at idr_max <= 0 left out" in out
    bad = text.replace("[analysis.design]\n", "[analysis.percentiles]\npercentiles = 50\n")
    assert main(["study", str(_write(tmp_path, bad, "b.toml")), "--out", str(tmp_path / "b")]) == 2
    assert "analysis.percentiles.percentiles: expected a list" in capsys.readouterr().err


def test_an_analysis_of_a_result_that_keep_drops_is_refused_for_every_scene_kind(tmp_path):
    # a cylinder study kept max_tilt and read max_uplift_ratio: its table said only "no
    # number in any successful row" after every run
    text = ('[study]\nname = "c"\nkeep = ["max_tilt"]\n[base.scene]\nkind = "cylinder"\n'
            '[base.motion]\nduration = 4.0\n[parameters]\n"motion.seed" = [0, 1]\n'
            '[analysis.percentiles]\nquantities = ["max_uplift_ratio"]\n')  # fmt: skip
    with pytest.raises(SceneError, match=r"analysis.percentiles.quantities: 'max_uplift_ratio' "
                       r"is a result the study does not keep; add it to study.keep"):  # fmt: skip
        load_study(_write(tmp_path, text))
    load_study(_write(tmp_path, text.replace('["max_tilt"]', '["max_tilt", "max_uplift_ratio"]')))


def test_parquet_without_pyarrow_is_refused_before_any_run(tmp_path, capsys, monkeypatch):
    """--parquet without pyarrow was said only after the study's last run (320 of them on the
    bundled design study): it is refused before the first, and no output folder is made."""
    import sys

    from nsdyn.cli import main

    monkeypatch.setitem(sys.modules, "pyarrow", None)  # an import of it raises ImportError
    text = (
        '[study]\nname = "g"\n[base.scene]\nfidelity = "rigid"\n[base.motion]\nt_end = 1.0\n'
        '[parameters]\n"isolation.mu" = [0.02]\n[records]\nnames = ["synthetic-wn-40s"]\n'
    )
    out = tmp_path / "o"
    argv = ["study", str(_write(tmp_path, text)), "--out", str(out), "--parquet", "--json"]
    assert main([*argv, "--workers", "1"]) == 2
    cap = capsys.readouterr()
    assert 'writing Parquet needs pyarrow: pip install "nsdyn[parquet]"' in cap.err + cap.out
    assert not out.exists()  # no run began


def test_a_folder_with_a_parquet_copy_names_it_when_pyarrow_is_missing(
    tmp_path, monkeypatch, capsys
):
    """A folder whose table has a Parquet copy keeps it in step, so a run there without pyarrow
    is refused; the refusal named only the extra, not the copy that asks for it."""
    import sys

    from nsdyn.cli import main

    monkeypatch.setitem(sys.modules, "pyarrow", None)
    text = (
        '[study]\nname = "g"\n[base.scene]\nfidelity = "rigid"\n[base.motion]\nt_end = 1.0\n'
        '[parameters]\n"isolation.mu" = [0.02]\n[records]\nnames = ["synthetic-wn-40s"]\n'
    )
    out = tmp_path / "o"
    out.mkdir()
    (out / "results.parquet").write_bytes(b"PAR1")
    assert main(["study", str(_write(tmp_path, text)), "--out", str(out), "--json"]) == 2
    cap = capsys.readouterr()
    said = f"{out / 'results.parquet'}: kept in step with the table; writing Parquet needs pyarrow"
    assert said in cap.err + cap.out and sorted(p.name for p in out.iterdir()) == [
        "results.parquet"
    ]


def test_a_study_refused_by_another_ones_lock_leaves_that_ones_folder(tmp_path, monkeypatch):
    """Two studies started into one new folder: the one refused by the other's lock removed
    the other's owner file (it had found the folder missing before it asked for the lock)."""
    import contextlib

    import nsdyn.cli.study as cli_study
    from nsdyn.atomic import OutputBusy
    from nsdyn.cli import main

    @contextlib.contextmanager
    def taken(out, command="command", say=None):  # the other study claims it first
        out.mkdir(parents=True)
        (out / ".study.json").write_text('{"name": "other", "kind": "isolated"}')
        raise OutputBusy(f"{out}: nsdyn study (process 1) writes there")
        yield out

    monkeypatch.setattr(cli_study, "output_dir", taken)
    text = (
        '[study]\nname = "g"\n[base.scene]\nfidelity = "rigid"\n[base.motion]\nt_end = 1.0\n'
        '[parameters]\n"isolation.mu" = [0.02]\n[records]\nnames = ["synthetic-wn-40s"]\n'
    )
    out = tmp_path / "o"
    assert main(["study", str(_write(tmp_path, text)), "--out", str(out)]) == 2
    assert (out / ".study.json").is_file()
