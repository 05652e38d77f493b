"""What a study's outputs said too little of. A design whose variables leave out a grid
parameter aggregates that parameter's runs as if they were records (a design's mean over both
friction coefficients, n_records twice the records): said in the design's note, naming the
parameter and its values. A Parquet copy of the table follows it onto another grid."""

from __future__ import annotations

from nsdyn.studies.execute import run_study
from nsdyn.studies.study import load_study

STUDY = """[study]
name = "d"
[base.scene]
fidelity = "rigid"
[base.motion]
t_end = 1.0
[parameters]
"isolation.mu" = [0.03, 0.06]
"isolation.k_lam" = [5.0e4, 1.0e5]
[analysis.design]
VARIABLES
"""


def _design(tmp_path, variables: str) -> dict:
    from nsdyn.studies.analyses import run_analyses

    path = tmp_path / "s.toml"
    path.write_text(STUDY.replace("VARIABLES", variables))
    study = load_study(path)
    run = run_study(study, tmp_path / "o", workers=1)
    return run_analyses(study, run.table, tmp_path / "o", figures=False)["design"]


def test_a_grid_parameter_left_out_of_the_variables_is_named(tmp_path):
    d = _design(tmp_path, 'variables = ["isolation.k_lam"]')
    assert "each design pools the runs of every isolation.mu (2 values)" in d["note"]
    assert d["n_designs"] == 2


def test_every_grid_parameter_a_variable_says_nothing_of_pooling(tmp_path):
    d = _design(tmp_path, "")
    assert "pools" not in d.get("note", "") and d["n_designs"] == 4


def test_a_parquet_copy_follows_the_table_onto_a_narrower_grid(tmp_path, capsys):
    # results.parquet, once asked for, is written anew with the table: a run on a narrowed
    # grid deleted it without a word ("every later run into the folder rewrites it")
    import pytest

    pq = pytest.importorskip("pyarrow.parquet", reason="the parquet extra (pyarrow)")
    from nsdyn.cli import main
    from nsdyn.studies.table import PARQUET

    path, out = tmp_path / "s.toml", tmp_path / "o"
    argv = ["study", str(path), "--out", str(out), "--workers", "1", "--no-figures"]
    path.write_text(STUDY.replace("VARIABLES", ""))
    assert main([*argv, "--parquet"]) == 0
    path.write_text(STUDY.replace("VARIABLES", "").replace("[0.03, 0.06]", "[0.03]"))
    assert main(argv) == 0
    capsys.readouterr()
    assert pq.read_table(out / PARQUET).num_rows == 2  # the narrowed grid's (2 of k_lam)


def test_a_design_whose_runs_failed_is_said_to_be_left_out(tmp_path):
    # a step budget of 5 fails every run of its design: NaN objectives in design.csv, and the
    # printout said nothing of a design left out
    from nsdyn.studies.analyses import run_analyses

    path = tmp_path / "s.toml"
    path.write_text(STUDY.replace('"isolation.k_lam" = [5.0e4, 1.0e5]', '"solver.max_steps" = '
                                  "[5, 2000000]").replace("VARIABLES", ""))  # fmt: skip
    study = load_study(path)
    run = run_study(study, tmp_path / "o", workers=1)
    assert run.n_failed == 2
    d = run_analyses(study, run.table, tmp_path / "o", figures=False)["design"]
    assert "2 of 4 designs without an objective (a run failed or lacks it)" in d["note"]
