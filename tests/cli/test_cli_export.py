"""``nsdyn export opensees``: writes a script (atomically), JSON contract, user-error exits."""

from __future__ import annotations

import json
import sys

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


def test_export_default_name_and_dt(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE)
    assert main(["export", "opensees", str(scene), "--dt", "0.01"]) == 0
    assert (tmp_path / "s_opensees.py").is_file()
    assert "wrote" in capsys.readouterr().out


def test_export_user_errors_exit_2(tmp_path, capsys):
    bad = tmp_path / "rock.toml"
    bad.write_text('[scene]\nkind = "rocking"\n')
    assert main(["export", "opensees", str(bad)]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and "isolated frame" in err
    assert main(["export", "opensees", str(tmp_path / "none.toml")]) == 2
    assert "no such scene file" in capsys.readouterr().err


def test_export_stiffness_damping_option(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE)
    out = tmp_path / "k.py"
    args = ["export", "opensees", str(scene), "-o", str(out), "--damping", "stiffness", "--json"]
    assert main(args) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["damping"] == "stiffness" and s["modal_modes"] == 0
