"""The bundled example studies load, and the design-search example's numbers obey the physics.

Physics: more friction (μ) means less isolator slip — the peak isolator displacement,
averaged over records, falls as μ rises at fixed K_lam and c (seed 004 §6: larger μ widens
the stick ranges); and the design search's front is non-dominated among feasible designs.
"""

from __future__ import annotations

import importlib.util
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from nsdyn.studies.study import load_study
from nsdyn.studies.table import read_csv

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize(
    "path", sorted((EXAMPLES / "studies").glob("*.toml")), ids=lambda p: p.stem
)
def test_example_studies_load(path):
    if "kobe" in path.stem:
        from nsdyn.ground import default_shared_dir

        if default_shared_dir() is None:
            pytest.skip("the Kobe records live in shared/records (set NSDYN_SHARED)")
    study = load_study(path)
    assert study.n_tasks >= 50 and study.analysis


def test_design_search_example_quick(tmp_path):
    spec = importlib.util.spec_from_file_location(
        "study_design_search", EXAMPLES / "study_design_search.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    out = mod.main(tmp_path, quick=True, executor=ThreadPoolExecutor(1))
    assert out["n_tasks"] == 8 * 4 and out["n_failed"] == 0 and out["n_designs"] == 8
    rows = read_csv(out["design_table"])
    assert any(r["isolation.mu"] == 0.01 for r in rows)  # the loop below checks something
    for r in rows:
        if r["isolation.mu"] == 0.01:
            hi = next(
                q
                for q in rows
                if q["isolation.mu"] == 0.08
                and q["isolation.k_lam"] == r["isolation.k_lam"]
                and q["isolation.c"] == r["isolation.c"]
            )
            assert hi["x_iso_max_m_worst"] < r["x_iso_max_m_worst"]
    front = [r for r in rows if r["pareto"]]
    feas = [r for r in rows if r["feasible"]]
    assert front and feas  # a non-empty feasible set has a non-empty Pareto front
    for p in front:
        assert not any(
            q["idr_max"] <= p["idr_max"]
            and q["floor_acc_max_mps2"] <= p["floor_acc_max_mps2"]
            and (q["idr_max"] < p["idr_max"] or q["floor_acc_max_mps2"] < p["floor_acc_max_mps2"])
            for q in feas
        )


def test_a_study_over_rungs_keeps_each_rungs_fields(tmp_path, capsys):
    """The incidence example keeps fields of two rungs (the rigid deck's resultant slip and
    torsion, the fixed frame's corner drift and torsional moment): every task runs, a field
    its rung's summary lacks is an empty cell whose row says so, and no warning is given
    since each kept name is some task's."""
    from nsdyn.cli import main

    out = tmp_path / "inc"
    assert main(["study", str(EXAMPLES / "studies" / "office-3d-incidence.toml"),
                 "--out", str(out), "--no-figures"]) == 0  # fmt: skip
    assert "warning" not in capsys.readouterr().err
    rows = read_csv(out / "results.csv")
    assert len(rows) == 52 and all(r["status"] == "ok" for r in rows)
    for r in rows:
        own, other = (
            ("peak_resultant_displacement_m", "peak_corner_drift")
            if r["structure.fidelity"] == "rigid"
            else ("peak_corner_drift", "peak_resultant_displacement_m")
        )
        assert r[own] is not None and r[own] > 0
        assert r.get(other) is None and repr(other) in r["error"]  # an empty cell, said why


def test_a_kept_name_a_typo_away_stops_the_study_after_its_first_run(tmp_path, capsys):
    # 'x_iso_maxx' is two edits from the field 'x_iso_max_m' (nsdyn._checks.is_typo): the
    # study stops at its first run, exit 2 naming study.keep, rather than run every task into
    # a column of empty cells
    from nsdyn.cli import main

    study = tmp_path / "s.toml"
    study.write_text('[study]\nname = "s"\nkeep = ["x_iso_maxx", "idr_max"]\n'
                     '[base.motion]\npga = 3.0\nt_end = 1.0\n'
                     '[parameters]\n"isolation.mu" = [0.02, 0.05, 0.08, 0.11]\n')  # fmt: skip
    assert main(["study", str(study), "--out", str(tmp_path / "o"), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"error: {study}: study.keep: 'x_iso_maxx' is not" in err
    assert "did you mean 'x_iso_max_m'?" in err
    # stopped at once, its rows not stored (under the fixed name every key changes: they
    # were kept in outside-grid.csv for good), and the folder it made removed again
    assert not (tmp_path / "o").exists()
    # the key holds the kept fields: the corrected study runs its tasks again, and a field
    # present in every summary but empty (a block that never overturns) is no warning
    study.write_text(study.read_text().replace('"x_iso_maxx"', '"x_iso_max_m"'))
    assert main(["study", str(study), "--out", str(tmp_path / "o")]) == 0
    captured = capsys.readouterr()
    assert "4 run now" in captured.out and "warning" not in captured.err


def test_a_kept_typo_after_a_failed_batch_stores_no_row_and_leaves_no_folder(tmp_path, capsys):
    # a batch of failed rows before the first successful one was stored under the misspelt
    # name's keys (kept in outside-grid.csv for good after the fix); the parents --out named
    # were left empty
    from nsdyn.cli import main

    study = tmp_path / "s.toml"
    study.write_text('[study]\nname = "s"\nbatch = 1\nkeep = ["x_iso_maxx"]\n'
                     '[base.motion]\npga = 3.0\nt_end = 1.0\n'
                     '[parameters]\n"solver.max_steps" = [5, 100000]\n')  # fmt: skip
    out = tmp_path / "a" / "b" / "o"
    assert main(["study", str(study), "--out", str(out), "--workers", "1"]) == 2
    assert "study.keep: 'x_iso_maxx' is not a field" in capsys.readouterr().err
    assert not (tmp_path / "a").exists()


def test_a_kept_name_far_from_every_field_is_said_at_once_and_warned_at_the_end(tmp_path, capsys):
    # a name far from every field may be another rung's: the study runs on, says so as its
    # first run ends (a long study's empty column was only said at its end), and warns
    from nsdyn.cli import main

    study = tmp_path / "s.toml"
    study.write_text('[study]\nname = "s"\nkeep = ["peak_corner_drift", "idr_max"]\n'
                     '[base.motion]\npga = 3.0\nt_end = 1.0\n'
                     '[parameters]\n"isolation.mu" = [0.02, 0.05]\n')  # fmt: skip
    assert main(["study", str(study), "--out", str(tmp_path / "o")]) == 0
    err = capsys.readouterr().err
    assert "warning: " + f"{study}: study.keep: in no task's run summary" in err
    early = f"{study}: study.keep: 'peak_corner_drift' not in the first run's summary"
    assert err.count(early) == 1 and err.index(early) < err.index("in no task's run summary")
    # the name is a column of empty cells, kept by the compaction that reads the parts
    rows = read_csv(tmp_path / "o" / "results.csv")
    assert len(rows) == 2 and all(r["peak_corner_drift"] is None for r in rows)


def test_a_kept_field_that_is_empty_in_every_row_is_no_warning(tmp_path, capsys):
    from nsdyn.cli import main

    study = tmp_path / "r.toml"
    scene = EXAMPLES / "scenes" / "rocking-seed001-cask.toml"
    study.write_text(f'[study]\nname = "r"\nscene = "{scene}"\n'
                     'keep = ["t_overturn_s", "overturned"]\n'
                     '[base.motion]\na_p_g = 0.1\nt_end = 2.0\n'  # < tan alpha = 0.5
                     '[parameters]\n"block.mass" = [1.0e5, 2.0e5]\n')  # fmt: skip
    assert main(["study", str(study), "--out", str(tmp_path / "o"), "--no-figures"]) == 0
    assert "warning" not in capsys.readouterr().err
    rows = read_csv(tmp_path / "o" / "results.csv")
    assert all(r["overturned"] is False and r["t_overturn_s"] is None for r in rows)


def test_a_study_may_not_vary_what_its_records_replace(tmp_path):
    # each task's record dropped the pulse's value the grid gave it: N identical runs
    from nsdyn.models.scenefile import SceneError

    scene = EXAMPLES / "scenes" / "rocking-seed001-cask.toml"
    study = tmp_path / "s.toml"
    study.write_text(f'[study]\nscene = "{scene}"\n[parameters]\n"motion.a_p_g" = [0.5, 1.0]\n'
                     '[records]\nnames = ["synthetic-wn-40s"]\n')  # fmt: skip
    with pytest.raises(
        SceneError,
        match=r"parameters\.motion\.a_p_g: varies the scene's "
        "closed-form motion, which every record of \\[records\\] replaces",
    ):
        load_study(study)


HARMONIC_SCENES = ["isolated-uplift-pocket.toml", "sdof-bidirectional-circular.toml"]


@pytest.mark.parametrize("scene", HARMONIC_SCENES)
def test_records_on_a_harmonic_scene_are_refused_naming_records(tmp_path, scene):
    # a harmonic base's reader named motion.record, a key the study file does not have
    from nsdyn.models.scenefile import SceneError

    path = EXAMPLES / "scenes" / scene
    study = tmp_path / "s.toml"
    mu = "bearing.mu" if "deck" in path.read_text() else "isolation.mu"
    study.write_text(f'[study]\nscene = "{path}"\n[parameters]\n"{mu}" = [0.02, 0.03]\n'
                     '[records]\nnames = ["synthetic-wn-40s"]\n')  # fmt: skip
    with pytest.raises(SceneError, match=r"s\.toml: records: the scene's motion is harmonic"):
        load_study(study)


def test_a_field_in_another_table_is_hinted_by_its_own_name(tmp_path):
    # a deck's friction is bearing.mu; the hint used to be the nearest string, 'motion.trim'
    from nsdyn.models.scenefile import SceneError

    path = EXAMPLES / "scenes" / "sdof-bidirectional-circular.toml"
    study = tmp_path / "s.toml"
    study.write_text(f'[study]\nscene = "{path}"\n[parameters]\n"isolation.mu" = [0.02, 0.03]\n')
    hint = r"isolation\.mu: unknown scene field; did you mean 'bearing\.mu'"
    with pytest.raises(SceneError, match=hint):
        load_study(study)
    # a table given as the parameter: named as a table with its fields (it was "unknown
    # scene field; did you mean 'bearing.c'?")
    study.write_text(f'[study]\nscene = "{path}"\n[parameters]\n"bearing" = [1.0, 2.0]\n')
    with pytest.raises(SceneError, match=r"parameters\.bearing: \[bearing\] is a table; a "
                       r"parameter varies one of its fields \(bearing\.R1, "):  # fmt: skip
        load_study(study)


def test_the_never_kept_warning_names_only_the_names_no_row_has():
    # rows of two rungs: each lacks the other's field, and both the misspelt name; the
    # warning named the rigid row's whole note ('peak_torsional_moment_Nm' too, which the
    # fixed rows have) and no hint for the misspelling (the rigid summary has no near field)
    from types import SimpleNamespace

    from nsdyn.cli.study import never_kept
    from nsdyn.studies.scenes import missing_kept

    keep = ["peak_corner_drfit", "peak_torsional_moment_Nm", "peak_torsion_rad"]
    rigid = {"peak_torsion_rad": 1e-20, "peak_resultant_displacement_m": 0.06}
    fixed = {"peak_torsion_rad": 1e-4, "peak_corner_drift": 0.01, "peak_torsional_moment_Nm": 3.8e7}
    rows = [{"status": "ok", "error": missing_kept(s, keep, "s.toml")} for s in (rigid, fixed)]
    (note,) = never_kept(SimpleNamespace(keep=keep), rows)
    assert "'peak_corner_drfit';" in note and "peak_torsional_moment_Nm'" not in note.split(";")[0]
    assert "did you mean 'peak_corner_drift' for 'peak_corner_drfit'?" in note
    assert never_kept(SimpleNamespace(keep=keep[1:]), rows) == []


UNSET_FIELDS = [  # a field each scene does not set, its valid values and one out of range
    ("contact-seed002-A5.toml", "friction.C", [0.0, 5.0], -1.0),
    ("rocking-seed003-column.toml", "block.r", [0.9, 0.95], 1.5),
    ("rocking-seed003-column.toml", "solver.tol", [1e-8, 1e-9], 2.0),
    ("cylinder-uplift.toml", "cylinder.I_t", [1.5, 2.0], -1.0),
]


@pytest.mark.parametrize(("scene", "field", "values", "bad"), UNSET_FIELDS)
def test_a_study_varies_a_field_its_scene_does_not_set(tmp_path, scene, field, values, bad):
    # any key nsdyn run reads (the kind's schema) may be a parameter, set in the base scene or
    # not; the rocking, contact and cylinder kinds knew only the keys their base file set.
    # Each task's scene carries the value, and a value out of the key's declared range is
    # refused by the scene's own reader, naming the task and the field (it is read).
    from nsdyn.models.scenefile import SceneError
    from nsdyn.studies.tasks import check_tasks, expand

    path = EXAMPLES / "scenes" / scene
    table, key = field.split(".")
    assert key not in __import__("tomllib").loads(path.read_text()).get(table, {})
    study = tmp_path / "s.toml"
    study.write_text(f'[study]\nscene = "{path}"\n[parameters]\n"{field}" = {values}\n')
    s = load_study(study)
    check_tasks(s)
    assert [t.cfg[table][key] for t in expand(s)] == values
    study.write_text(f'[study]\nscene = "{path}"\n[parameters]\n"{field}" = [{bad}]\n')
    with pytest.raises(SceneError, match=rf"s\.toml: .*{key}"):
        check_tasks(load_study(study))
