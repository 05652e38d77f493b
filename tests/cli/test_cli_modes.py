"""``nsdyn modes``: JSON contract, readable output, figure, and user-error exit codes.

Expected dof counts are seed 004's published numbers (435 full, 13 at f_max = 5 Hz).
"""

from __future__ import annotations

import json

import pytest

from nsdyn.cli import COMMANDS, main


def test_modes_json_office(capsys):
    assert main(["modes", "office-11", "--json"]) == 0
    out = capsys.readouterr().out
    s = json.loads(out)  # the whole of stdout is one JSON object
    assert s["n_dof"] == 435 and s["n_reduced"] == 13
    # a success's JSON leads with status 0, as a failure's with its status
    assert next(iter(s)) == "status" and s["status"] == 0
    for key in ("frequencies_hz", "mode_types", "total_mass_kg", "f_bis_hz"):
        assert key in s
    assert len(s["frequencies_hz"]) == len(s["mode_types"]) == 10
    assert s["frequencies_hz"][:4] == pytest.approx([0.46, 1.27, 1.98, 2.98], rel=0.03)
    assert s["mode_types"][:4] == ["lateral"] * 4
    assert s["f_bis_hz"] == pytest.approx(0.060, abs=0.003)


def test_modes_without_a_frame_lists_the_default_scenes_frame(capsys):
    # `nsdyn run` with no scene runs office-11; `nsdyn modes` with no frame lists its modes
    assert main(["modes", "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["frame"] == "office-11" and s["n_dof"] == 435 and s["n_reduced"] == 13


def test_modes_options_change_counts_and_f_bis(capsys):
    # f_bis scales with sqrt(K_lam) (seed eq. 28): 4x K_lam doubles it.
    main(["modes", "office-11", "--json"])
    a = json.loads(capsys.readouterr().out)
    main(["modes", "office-11", "--json", "--fmax", "10", "--klam", "2e5"])
    b = json.loads(capsys.readouterr().out)
    assert b["n_reduced"] > a["n_reduced"]
    assert b["f_bis_hz"] == pytest.approx(2 * a["f_bis_hz"], rel=1e-12)


def test_a_cut_off_below_the_first_mode_is_noted(capsys):
    # f_max = 0.1 Hz under the office's first mode (0.46 Hz, seed 004): no flexible mode
    # kept, said as nsdyn run says it (modes printed 6 + 0 = 6 dofs without a word)
    assert main(["modes", "office-11", "--json", "--fmax", "0.1"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["n_modes_kept"] == 0 and s["n_reduced"] == s["n_boundary"]
    (note,) = s["notes"]
    assert note.startswith("Craig-Bampton at f_max = 0.1 Hz keeps no flexible mode")
    assert main(["modes", "office-11", "--json"]) == 0  # (5 Hz keeps seven: no note)
    assert "notes" not in json.loads(capsys.readouterr().out)


def test_a_bearing_too_stiff_to_isolate_is_noted(capsys):
    # f_bis ∝ sqrt(K_lam) (seed eq. 28): the default 0.060 Hz is 0.13 x the office's first
    # mode (0.46 Hz, no note); K_lam x 100 puts it at 0.60 Hz, above f_1/3 (the rule of thumb)
    assert main(["modes", "office-11", "--json", "--klam", "5e6"]) == 0
    s = json.loads(capsys.readouterr().out)
    ratio = s["f_bis_hz"] / s["frequencies_hz"][0]
    assert s["mode_types"][0] == "lateral" and ratio > 1.0 / 3.0
    (note,) = s["notes"]
    assert note.startswith(f"f_bis = {s['f_bis_hz']:.4g} Hz is {ratio:.3g} x the first lateral")


def test_modes_table_and_png(tmp_path, capsys):
    out_dir = tmp_path / "figs"
    assert main(["modes", "portal", "--out", str(out_dir)]) == 0
    text = capsys.readouterr().out
    assert "21 dofs" in text and "f_bis" in text and "lateral" in text
    files = list(out_dir.iterdir())
    assert [f.name for f in files] == ["modes-portal.png"]  # no temp file left behind
    assert files[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_missing_file_exits_2_with_one_line(tmp_path, capsys):
    bad = tmp_path / "nowhere.toml"
    assert main(["modes", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "nowhere.toml" in err and "Traceback" not in err


def test_invalid_file_exits_2_naming_field(tmp_path, capsys):
    p = tmp_path / "broken.toml"
    p.write_text('[frame]\nname = "x"\nkind = "regular"\nbays = [6.0]\n')
    assert main(["modes", str(p), "--json"]) == 2
    captured = capsys.readouterr()
    # --json: the failure as one JSON object on stdout, the line on stderr
    assert json.loads(captured.out) == {
        "status": 2,
        "error": captured.err.split("error: ", 1)[1].strip(),
    }
    assert "broken.toml: frame.storey_heights" in captured.err


def test_unknown_bundled_name_lists_known_ones(capsys):
    assert main(["modes", "office-12"]) == 2
    assert "office-11" in capsys.readouterr().err


def test_bad_option_is_a_usage_error():
    with pytest.raises(SystemExit) as ei:
        main(["modes", "office-11", "--fmax", "-1"])
    assert ei.value.code == 2


def test_subcommand_table():
    assert "modes" in COMMANDS
    assert callable(COMMANDS["modes"].run) and callable(COMMANDS["modes"].configure)


@pytest.mark.parametrize(
    "line, field", [("k_lam = -5", "isolation.k_lam"), ('k_lam = "abc"', "isolation.k_lam"),
                    ("muu = 0.03", "isolation.muu")],
)  # fmt: skip
def test_a_scene_nsdyn_run_refuses_is_refused_by_nsdyn_modes_too(tmp_path, capsys, line, field):
    # modes read the scene's k_lam and fell back to the default on any value it could not use:
    # f_bis of another isolator, exit 0, where nsdyn run refuses the file (exit 2)
    scene = tmp_path / "s.toml"
    scene.write_text(f"[isolation]\n{line}\n")
    assert main(["modes", str(scene), "--json"]) == 2
    err = json.loads(capsys.readouterr().out)["error"]
    assert str(scene) in err and field in err


def test_a_harmonic_scene_without_an_end_lists_its_frames_modes(tmp_path, capsys):
    # nsdyn run takes it with --t-end; modes reads no motion, so its check must not ask
    # for an end (the office frame's f_bis with the default K_lam: seed 004, 0.060 Hz)
    scene = tmp_path / "h.toml"
    scene.write_text('[motion]\nkind = "harmonic"\nfrequency = 1.0\namplitude = 1.0\n')
    assert main(["modes", str(scene), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["f_bis_hz"] == pytest.approx(0.060, abs=0.003)
