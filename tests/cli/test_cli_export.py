"""``nsdyn export opensees``: writes a script (atomically), JSON contract, user-error exits."""

from __future__ import annotations

import json
import sys

import pytest

from nsdyn.cli import main

SCENE = '[scene]\nframe = "office-11"\n[motion]\nrecord = "synthetic-wn-40s"\nt_end = 1.0\n'


def test_export_writes_script(tmp_path, capsys, monkeypatch):
    # Python writes bytecode caches here (an environment may turn that off): reading the
    # script back for the summary must leave nothing beside it
    monkeypatch.setattr(sys, "dont_write_bytecode", False)
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE)
    out = tmp_path / "sub" / "m.py"
    assert main(["export", "opensees", str(scene), "-o", str(out), "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["script"] == str(out) and s["n_nodes"] == 145 and s["n_elements"] == 154
    # a success's JSON leads with status 0, as a failure's with its status
    assert next(iter(s)) == "status" and s["status"] == 0
    assert s["duration_s"] == 1.0 and s["dt"] == 0.005
    compile(out.read_text(), str(out), "exec")  # valid Python
    assert not [p for p in out.parent.iterdir() if p.name != "m.py"]  # no temporary left


def test_export_without_a_scene_writes_the_default_scene(tmp_path, capsys, monkeypatch):
    # as `nsdyn run` without a file runs it: office-11 (seed 004: 145 nodes, 154 members) on
    # its isolators under the bundled record, the whole 40 s unless cut
    monkeypatch.chdir(tmp_path)
    assert main(["export", "opensees", "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["script"] == "office-11_opensees.py" and (tmp_path / s["script"]).is_file()
    assert s["frame"] == "office-11" and s["n_nodes"] == 145 and s["n_elements"] == 154
    assert s["duration_s"] == 40.0


def test_export_default_name_and_dt(tmp_path, capsys, monkeypatch):
    # the script goes to the current folder, not beside the scene (a bundled scene's folder
    # is the package's)
    (tmp_path / "scenes").mkdir()
    scene = tmp_path / "scenes" / "s.toml"
    scene.write_text(SCENE)
    monkeypatch.chdir(tmp_path)
    assert main(["export", "opensees", str(scene), "--dt", "0.01"]) == 0
    assert (tmp_path / "s_opensees.py").is_file()
    assert not (tmp_path / "scenes" / "s_opensees.py").exists()
    assert "wrote s_opensees.py" in capsys.readouterr().out


def test_export_user_errors_exit_2(tmp_path, capsys):
    bad = tmp_path / "rock.toml"
    bad.write_text('[scene]\nkind = "rocking"\n')
    assert main(["export", "opensees", str(bad)]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and "isolated frame" in err
    assert main(["export", "opensees", str(tmp_path / "none.toml")]) == 2
    assert "no such scene file" in capsys.readouterr().err


def test_a_step_of_hours_of_stepping_is_refused_as_a_run_refuses_it(tmp_path, capsys):
    # 20 s at 1e-9 s is 2e10 Newmark steps, past the run's budget of 2e8 (MAX_STEPS); the
    # export wrote the script without a word
    from nsdyn._checks import MAX_STEPS

    out = tmp_path / "x.py"
    assert main(["export", "opensees", "--dt", "1e-9", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "solver.dt (--dt):" in err and f"exceed {MAX_STEPS:.0e}" in err
    assert not out.exists()


def test_export_stiffness_damping_option(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE)
    out = tmp_path / "k.py"
    args = ["export", "opensees", str(scene), "-o", str(out), "--damping", "stiffness", "--json"]
    assert main(args) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["damping"] == "stiffness" and s["modal_modes"] == 0


def test_export_t_end_is_an_end_time_as_a_run_s(tmp_path, capsys):
    # a record whose time column starts at 10 s: `nsdyn run --t-end 12` runs 10 … 12 s
    # (t_end on the record's clock), and the export cuts it at the same time: 2 s of record
    import numpy as np

    rec = tmp_path / "late.txt"
    t = 10.0 + 0.01 * np.arange(501)
    rows = "\n".join(f"{a:.2f} {b:.6e}" for a, b in zip(t, 0.5 * np.sin(6.0 * t), strict=True))
    rec.write_text("# units: m/s2\n" + rows + "\n")
    scene = tmp_path / "s.toml"
    scene.write_text(f'[scene]\nframe = "office-11"\n[motion]\nrecord = "{rec}"\n')
    out = tmp_path / "m.py"
    argv = ["export", "opensees", str(scene), "-o", str(out), "--json"]
    assert main([*argv, "--t-end", "12"]) == 0
    assert json.loads(capsys.readouterr().out)["duration_s"] == 2.0
    assert main([*argv, "--t-end", "10.001"]) == 2
    assert "t_end: expected an end at least one record step (0.01 s) after the record's start " \
           "(10 s), got 10.001" in capsys.readouterr().err  # fmt: skip


def test_a_building_export_past_the_records_end_is_noted(tmp_path, capsys):
    # the frame's export said so; the 3D building's wrote its 40 s silently
    from pathlib import Path

    scene = Path(__file__).resolve().parents[2] / "examples" / "scenes"
    argv = ["export", "opensees", str(scene / "building3d-office-rigid.toml"), "-o"]
    assert main([*argv, str(tmp_path / "b.py"), "--t-end", "100"]) == 0
    err = capsys.readouterr().err
    assert "--t-end 100 s is past the record's end; the script runs 40 s" in err


def test_t_end_replaces_the_scenes_end_as_in_a_run(tmp_path, capsys):
    # the script ran to the scene's [motion] t_end (1 s) and said "--t-end 3 s is past the
    # record's end" of a 40 s record; a 3D building's too
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE.replace("office-11", "portal"))
    b3 = tmp_path / "b.toml"
    b3.write_text('[scene]\nkind = "building3d"\n[structure]\nframe3d = "portal-3d"\n'
                  'fidelity = "rigid"\n[motion]\nkind = "record3"\nrecord = "synthetic-wn-40s"\n'
                  't_end = 1.0\n[bearing]\ntype = "flat"\nmu = 0.05\n')  # fmt: skip
    for path in (scene, b3):
        argv = ["export", "opensees", str(path), "-o", str(tmp_path / "m.py"), "--json"]
        assert main([*argv, "--t-end", "3"]) == 0
        out, err = capsys.readouterr()
        assert json.loads(out)["duration_s"] == 3.0 and "past the record's end" not in err
        assert main(argv) == 0  # without it, the scene's end
        assert json.loads(capsys.readouterr().out)["duration_s"] == 1.0


def test_a_fixed_base_export_of_a_building_needs_no_bearing(tmp_path, capsys):
    # --fixed-base exports the clamped frame "whatever the scene's fidelity": a scene without
    # a [bearing] table was refused for its missing bearing
    b3 = tmp_path / "b.toml"
    b3.write_text('[scene]\nkind = "building3d"\n[structure]\nframe3d = "portal-3d"\n'
                  'fidelity = "rigid"\n[motion]\nkind = "record3"\nrecord = "synthetic-wn-40s"\n'
                  't_end = 1.0\n')  # fmt: skip
    argv = ["export", "opensees", str(b3), "-o", str(tmp_path / "m.py"), "--json"]
    assert main([*argv, "--fixed-base"]) == 0
    assert json.loads(capsys.readouterr().out)["bearings"] == []
    assert main(argv) == 2  # on its bearings: refused, naming the table
    assert "bearing: missing; the building on isolators needs a [bearing] table" in \
        capsys.readouterr().err  # fmt: skip


def test_an_output_name_ending_in_a_separator_is_a_directory(tmp_path, capsys):
    # "-o x.py/" wrote the file x.py
    target = str(tmp_path / "x.py") + "/"
    with pytest.raises(SystemExit) as e:  # (argparse's exit)
        main(["export", "opensees", "-o", target])
    assert e.value.code == 2
    assert "expected a file name, got the directory" in capsys.readouterr().err
    assert not (tmp_path / "x.py").exists()


@pytest.mark.parametrize(
    ("kind", "said"),
    [
        # without t_end it asked for one first ("give t_end [s] or n_periods"), then, given
        # it, refused the harmonic motion itself
        ("harmonic", "[motion]: OpenSees export needs a ground-motion record"),
        ("harmonc", "motion.kind"),  # (a misspelt kind is named as such, not as a harmonic)
        # a force scene (no [motion] table) was refused naming [motion]
        ("force", "[force]: OpenSees export needs a ground-motion record"),
    ],
)
def test_a_harmonic_scene_is_refused_at_once_for_what_it_is(kind, said, tmp_path, capsys):
    scene = tmp_path / "h.toml"
    table = ("[force]\nkind = \"harmonic\"\nF = 1e4\nf = 1.0\ndofs = [0]\n" if kind == "force"
             else f'[motion]\nkind = "{kind}"\namplitude = 1.0\nfrequency = 1.0\n')  # fmt: skip
    scene.write_text(f'[scene]\nframe = "office-11"\n{table}')
    assert main(["export", "opensees", str(scene), "-o", str(tmp_path / "h.py")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and said in err
    assert not (tmp_path / "h.py").exists()


@pytest.mark.parametrize("extra", [[], ["--t-end", "0.05"], ["--fixed-base", "--t-end", "1"]])
def test_a_building_under_an_orbit_is_refused_with_or_without_an_end(extra, tmp_path, capsys):
    # with --t-end the orbit was cut first: AttributeError ('HarmonicPlane' object has no
    # attribute 'until'), a traceback and status 1
    b3 = tmp_path / "b.toml"
    b3.write_text('[scene]\nkind = "building3d"\n[structure]\nframe3d = "portal-3d"\n'
                  'fidelity = "rigid"\n[bearing]\nmu = 0.05\nradius = 2.0\n[motion]\n'
                  'kind = "orbit"\norbit = "circular"\nfrequency = 0.4\namplitude = 0.5\n'
                  'n_periods = 2\n')  # fmt: skip
    assert main(["export", "opensees", str(b3), "-o", str(tmp_path / "m.py"), *extra]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "motion: OpenSees export needs a three-component record " \
        "(kind = 'record3'), not an orbit" in err  # fmt: skip
    assert not (tmp_path / "m.py").exists()
