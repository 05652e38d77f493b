"""`nsdyn run` end to end: JSON keys promised in the README, and the advisor's choice."""

import json

import pytest

from nsdyn.cli import main

KEYS = {
    "x_iso_max_m",
    "idr_max",
    "idr_by_storey",
    "floor_acc_max_mps2",
    "roof_drift_max_m",
    "min_normal_force_N",
    "uplift",
    "n_steps",
    "wall_s",
}


def test_run_json_has_the_documented_keys(tmp_path, capsys):
    rc = main(["run", "--t-end", "2", "--json", "--no-figures", "--out", str(tmp_path)])
    assert rc == 0
    s = json.loads(capsys.readouterr().out)
    assert KEYS <= set(s)
    # a success's JSON leads with status 0, as a failure's with its status
    assert next(iter(s)) == "status" and s["status"] == 0
    # 11 storeys in office-11 (seed §2); normal forces stay compressive in 2 s at PGA 3
    assert len(s["idr_by_storey"]) == 11
    assert s["min_normal_force_N"] > 0 and s["uplift"] == []
    assert not list(tmp_path.glob(".*checkpoint*"))  # the checkpoint is removed when done


@pytest.mark.slow  # ~45 s: the advisor tries several rungs
def test_run_fidelity_auto_prints_its_choice(tmp_path, capsys):
    rc = main(
        [
            "run",
            "--fidelity",
            "auto",
            "--t-end",
            "2",
            "--json",
            "--no-figures",
            "--out",
            str(tmp_path),
        ]
    )
    assert rc == 0
    captured = capsys.readouterr()
    assert "advised model:" in captured.err
    assert json.loads(captured.out)["fidelity"] in ("fixed", "rigid", "cb", "full")


def test_bad_scene_exits_2_with_file_and_field(tmp_path, capsys):
    bad = tmp_path / "s.toml"
    bad.write_text('[scene]\nfidelity = "medium"\n')
    assert main(["run", str(bad)]) == 2
    assert "scene.fidelity" in capsys.readouterr().err


def test_fixed_step_methods_take_a_default_or_given_step(tmp_path, capsys):
    # a fixed-step method takes exactly t_end / dt steps: 0.5 s / 0.005 s (the documented
    # default) = 100, and 0.5 s / 0.01 s = 50 with --dt
    base = ["run", "--fidelity", "rigid", "--t-end", "0.5", "--json", "--no-figures"]
    for extra, steps in (([], 100), (["--dt", "0.01"], 50)):
        rc = main([*base, "--method", "genalpha", *extra, "--out", str(tmp_path)])
        assert rc == 0
        assert json.loads(capsys.readouterr().out)["n_steps"] == steps


def test_ladder_flags_on_a_scene_without_a_frame_name_the_flag(tmp_path, capsys):
    # a scene giving its [structure] directly has no fixed-base / CB / full ladder: the
    # error names the flag the user typed (not a scene field they never wrote)
    from pathlib import Path

    scene = (
        Path(__file__).resolve().parents[2] / "examples" / "scenes" / "isolated-shear-3storey.toml"
    )
    for flags in (["--fixed-base"], ["--fidelity", "full"], ["--fmax", "8"]):
        assert main(["run", str(scene), *flags, "--no-figures", "--out", str(tmp_path)]) == 2
        err = capsys.readouterr().err
        assert flags[0] in err and "[structure]" in err and "shear" in err


def test_a_shortened_run_reports_the_peak_it_ran_and_the_pga_it_scaled_to(tmp_path, capsys):
    # the scene scales the whole record to 3 m/s², then --t-end keeps its first 2 s, whose
    # peak is lower: both are said, the run's own peak as pga_mps2
    import nsdyn

    out = str(tmp_path / "o")
    assert main(["run", "--t-end", "2", "--json", "--no-figures", "--out", out]) == 0
    s = json.loads(capsys.readouterr().out)
    ran = nsdyn.read_motion("synthetic-wn-40s").scaled_to_pga(3.0).window(0.0, 2.0)
    assert s["record_pga_mps2"] == 3.0 and s["pga_mps2"] == ran.pga < 3.0
    assert main(["run", "--t-end", "2", "--no-figures", "--out", out]) == 0
    text = capsys.readouterr().out
    assert f"(record scaled to PGA 3 m/s²; peak {ran.pga:.3g} m/s² over the run)" in text


def test_t_end_replaces_a_harmonic_scenes_number_of_periods(tmp_path, capsys):
    # the scene gives its duration as n_periods = 30; --t-end is the user's, and wins (a
    # scene could not be shortened from the command line: "give one, not both")
    from pathlib import Path

    scene = Path(__file__).resolve().parents[2] / "examples/scenes/isolated-uplift-pocket.toml"
    argv = ["run", str(scene), "--t-end", "1", "--json", "--no-figures", "--out", str(tmp_path)]
    assert main(argv) == 0
    assert json.loads(capsys.readouterr().out)["t_end_s"] == 1.0


def test_summary_rows_of_a_unilateral_run_report_lift_off_not_uplift():
    # the "uplift" row reports where the no-uplift model was violated; a run with unilateral
    # contacts models lift-off, so it reports lift-offs instead; a normal force that ends at
    # exactly zero (in flight) prints as 0, not -0 (IEEE: -0.0 + 0.0 = +0.0)
    from nsdyn.cli.run_summary import summary_rows

    base = {"min_normal_force_N": -0.0, "uplift": []}
    held = "\n".join(summary_rows({**base, "contact": "bilateral"}))
    lifted = "\n".join(summary_rows({**base, "contact": "unilateral", "lift_offs": 3,
                                     "landings": 2}))  # fmt: skip
    assert "uplift " in held and "none" in held
    assert "uplift " not in lifted and "lift-offs / landings" in lifted and "3 / 2" in lifted
    assert "minimum normal force                 0 N" in lifted and "-0" not in lifted
    # a rigid superstructure's zero drift is the model's, not a computed peak: said so
    peaks = {"idr_max": 0.0, "roof_drift_max_m": 0.0, "x_iso_max_m": 0.2}
    rigid = summary_rows({**peaks, "fidelity": "rigid"})
    assert sum(r.endswith("(rigid: the storeys do not deform)") for r in rigid) == 2
    assert not any("rigid" in r for r in summary_rows({**peaks, "fidelity": "cb"}))
    # --compare-fixed on a setback frame (no drift ratios): "-" there (a KeyError before)
    assert summary_rows({"fixed_base": {"floor_acc_max_mps2": 3.0}})[-1].endswith(
        "fixed base: IDR / floor acc. / roof  - / 3.000 m/s² / -")  # fmt: skip


@pytest.mark.parametrize("law", ["arctan", "switch"])
def test_uplift_names_the_isolation_keys_its_smooth_law_does_not_read(tmp_path, capsys, law):
    # nsdyn run said "isolation.eta not used" on this scene; nsdyn uplift, whose periodic
    # orbits take the arctan law (a switch scene's law replaced), said nothing
    scene = tmp_path / "s.toml"
    scene.write_text(f'[isolation]\nlaw = "{law}"\neta = 1e-4\n')
    argv = ["uplift", str(scene), "--points", "2", "--fmin", "1", "--fmax", "1.1", "--a-max",
            "2", "--no-figures", "--out", str(tmp_path / "o")]  # fmt: skip
    assert main(argv) == 0
    assert "note: not used by this model: isolation.eta (a key of the switch law; the law here " \
           "is arctan)" in capsys.readouterr().err  # fmt: skip


def test_the_event_method_says_it_runs_the_switch_law(tmp_path, capsys):
    # the default scene's arctan law gave way to the switch law without a word on the
    # command line (the library warns); the law given as switch needs no note
    argv = ["run", "--method", "event", "--t-end", "0.5", "--no-figures", "--json"]
    assert main([*argv, "--out", str(tmp_path / "a")]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["law"] == "switch"
    assert any(n.startswith("method 'event' integrates the switch law (true stick) in place "
                            "of the scene's arctan law") for n in s["notes"])  # fmt: skip
    assert main([*argv, "--friction", "switch", "--out", str(tmp_path / "b")]) == 0
    assert not any("in place of" in n for n in json.loads(capsys.readouterr().out)["notes"])


def test_a_reduction_without_a_flexible_mode_is_said(tmp_path, capsys):
    # f_max below the first fixed-interface mode (0.463 Hz) keeps the static modes alone: a
    # portal with one bay more ran with drift ratios 1000x smaller and nothing said
    argv = ["run", "--t-end", "0.5", "--no-figures", "--json"]
    assert main([*argv, "--fmax", "0.4", "--out", str(tmp_path / "a")]) == 0
    notes = json.loads(capsys.readouterr().out)["notes"]
    assert any(
        n.startswith("Craig-Bampton at f_max = 0.4 Hz keeps no flexible mode") for n in notes
    )
    assert main([*argv, "--fmax", "0.5", "--out", str(tmp_path / "b")]) == 0
    assert not any("no flexible mode" in n for n in json.loads(capsys.readouterr().out)["notes"])


def test_the_auto_reason_names_the_step_given(tmp_path, capsys):
    # the command line's own reason said "dt 0.005 s" of a run at --dt 2.5 ms
    argv = ["run", "--fidelity", "full", "--dt", "0.0025", "--t-end", "0.1", "--json"]
    assert main([*argv, "--no-figures", "--out", str(tmp_path)]) == 0
    s = json.loads(capsys.readouterr().out)
    assert "(dt 0.0025 s, factored once)" in s["method_reason"] and s["n_steps"] == 40


def test_a_full_models_damped_modes_are_said_before_they_are_solved(capsys):
    # above DENSE_MAX_DOF the modes are solved on first use: inside the run's first chunk,
    # a silence of 17 s at 4 635 dofs after "method ..."; said, and solved before the run
    import nsdyn
    from nsdyn.cli.run_checks import prepare_sparse

    s = nsdyn.build_system("portal", fidelity="full")
    s.sparse._U = s.sparse._c = None  # (as a model above DENSE_MAX_DOF is built)
    prepare_sparse(s, quiet=False)
    said = f"solving the damped modes of the {s.sparse.n}-dof model (once)…"
    assert said in capsys.readouterr().err.splitlines()
    assert s.sparse._U is not None and s.sparse._U.shape[0] == s.sparse.n
    prepare_sparse(s, quiet=False)  # (solved: not said again)
    assert "damped modes" not in capsys.readouterr().err


def test_compare_fixed_gives_the_fixed_base_peaks_beside_the_isolated_ones(tmp_path, capsys):
    # the fixed base was a dashed line in run.png only (refused with --no-figures): its peaks
    # are in the summary and its JSON. Seed 004's point, isolation: the isolated frame drifts
    # and accelerates less than the same frame clamped, under the same 5 s of record
    argv = ["run", "--compare-fixed", "--t-end", "5", "--no-figures", "--out", str(tmp_path)]
    assert main([*argv, "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    fb = s["fixed_base"]
    assert fb["idr_max"] > s["idr_max"] and fb["floor_acc_max_mps2"] > s["floor_acc_max_mps2"]
    assert main(argv) == 0
    row = next(x for x in capsys.readouterr().out.splitlines() if "fixed base:" in x)
    assert (f"{fb['idr_max']:.3e} / {fb['floor_acc_max_mps2']:.3f} m/s² / "
            f"{fb['roof_drift_max_m']:.4f} m") in row  # fmt: skip


@pytest.mark.parametrize(
    ("flags", "says"),
    [(["--method", "radau"], r"'radau' cannot run this model: .* too many for the dense kernels"),
     # auto's choice for the switch law, radau, cannot either: said with auto's reason
     (["--friction", "switch"], r"'radau' \(auto: switch law -> radau .*\) cannot run this "
      r"model: .*the cb fidelity \(fewer dofs\) for the switch law")],
)  # fmt: skip
def test_a_dense_method_on_a_sparse_only_model_is_refused_in_one_line(
    tmp_path, capsys, monkeypatch, flags, says
):
    # a full model above fullorder.DENSE_MAX_DOF (2000 dofs) keeps no dense copies: a dense
    # method ended in a traceback (status 1) after the build; here the office's 435 dofs
    # stand for one such, the limit lowered (and no model cache: its copies would be loaded)
    import re

    from nsdyn.models.isolated import fullorder

    monkeypatch.setattr(fullorder, "DENSE_MAX_DOF", 100)
    monkeypatch.setenv("NSDYN_MODEL_CACHE", "0")
    argv = ["run", "--fidelity", "full", *flags, "--t-end", "0.1", "--no-figures"]
    assert main([*argv, "--out", str(tmp_path)]) == 2
    assert re.search(says, capsys.readouterr().err)


def test_a_shortened_unscaled_record_s_peak_is_not_called_its_pga(tmp_path, capsys):
    # a record run as read to a t_end before its strong part printed "(PGA 0.00 m/s²)" (its
    # first 3 s) for a record of PGA 8.18 m/s²: the window's peak is said as such
    rec = tmp_path / "rec.txt"
    rows = [f"{0.01 * k:.2f} {(0.001 if k < 200 else 2.5) * (-1) ** k}" for k in range(400)]
    rec.write_text("# units: m/s2\n" + "\n".join(rows) + "\n")
    out = str(tmp_path / "o")
    assert main(["run", "--frame", "portal", "--record", str(rec), "--t-end", "1.5",
                 "--no-figures", "--out", out]) == 0  # fmt: skip
    text = capsys.readouterr().out
    assert "(peak 0.001 m/s² over the run, to t_end)" in text and "PGA" not in text
    assert main(["run", "--frame", "portal", "--record", str(rec), "--no-figures", "--out",
                 out]) == 0  # fmt: skip
    assert "(PGA 2.5 m/s²)" in capsys.readouterr().out


def test_a_switch_law_sweep_says_what_its_a_column_reads(tmp_path, capsys, monkeypatch):
    # the column a (all levels) reads the isolation level's stick-onset jumps at the orbit's
    # steps under the switch law (2.64 and 2.09 m/s² at steps factors 1 and 4, docs/guide/
    # periodic.md), a_floors does not: said before the run; the arctan law has no such jumps
    from nsdyn.cli import sweep

    class Stop(Exception):
        pass

    def stop(*a, **k):  # (the note is said before the kernels and the curves: stop there)
        raise Stop

    monkeypatch.setattr(sweep, "prepare_kernels", stop)
    argv = ["sweep", "--points", "2", "--no-figures", "--out", str(tmp_path / "o")]
    for law, said in (("switch", True), ("arctan", False)):
        with pytest.raises(Stop):
            main([*argv, "--friction", law])
        err = capsys.readouterr().err
        assert ("nsdyn sweep: note: under the switch law the isolation level's acceleration "
                "jumps at each stick onset" in err) is said  # fmt: skip
