"""Every command says a user error the same way: one line ``nsdyn <command>: error: ...``
naming what is wrong, exit status 2 (``nsdyn.cli.args.EXIT_USER_ERROR``), nothing on stdout
and nothing written (no output folder left behind)."""

import json
import re
from pathlib import Path

import pytest

from nsdyn.cli import main
from nsdyn.cli.args import EXIT_USER_ERROR

CASES = [
    ("run", ["no-such.toml"], "no-such.toml: no such scene file"),
    ("sweep", ["no-such.toml"], "no-such.toml: no such scene file"),
    ("uplift", ["no-such.toml"], "no-such.toml: no such scene file"),
    ("study", ["no-such.toml"], "no-such.toml: no such study file"),
    ("export", ["opensees", "no-such.toml"], "no-such.toml: no such scene file"),
    ("spectrum", ["no-such.toml"], "no-such.toml: no such scene file"),
    ("modes", ["no-such.toml"], "no-such.toml: no such frame file"),
    (
        "sweep",
        ["--fmin", "2", "--fmax", "1"],
        "argument --fmax: expected a frequency above --fmin (2 Hz), got 1 (see nsdyn sweep --help)",
    ),
    (
        "uplift",
        ["--fmin", "2", "--fmax", "1"],
        "argument --fmax: expected a frequency above --fmin (2 Hz), got 1 "
        "(see nsdyn uplift --help)",
    ),
]


@pytest.mark.parametrize(("command", "argv", "says"), CASES)
def test_a_user_error_is_one_line_naming_the_command(
    command, argv, says, capsys, tmp_path, monkeypatch
):
    monkeypatch.chdir(tmp_path)  # the commands' default output folders are relative
    assert main([command, *argv]) == EXIT_USER_ERROR
    out, err = capsys.readouterr()
    assert out == ""
    assert err == f"nsdyn {command}: error: {says}\n"
    assert list(tmp_path.iterdir()) == []


def test_a_step_refused_for_the_automatic_method_is_one_line_naming_the_choice(
    capsys, tmp_path, monkeypatch
):
    # (the automatic choice's line came first, so a refused run read as one that started)
    monkeypatch.chdir(tmp_path)  # (nothing is written: the check comes before any work)
    assert main(["run", "--dt", "0.01", "--t-end", "1"]) == EXIT_USER_ERROR
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and list(tmp_path.iterdir()) == []
    # (the message names --dt itself; the flag's label goes where a value of it is shown)
    assert err.startswith("nsdyn run: error: <default scene>: solver.dt: the adaptive method ")
    assert err.endswith("(method auto: 13 coordinates, arctan law -> radau (adaptive))\n")


def test_an_unknown_method_lists_auto_among_the_choices(capsys):
    from nsdyn.solve.methods import METHODS

    assert main(["run", "--method", "foo"]) == EXIT_USER_ERROR
    err = capsys.readouterr().err
    assert err == (
        "nsdyn run: error: <default scene>: solver.method (--method): unknown integrator 'foo'; "
        f"expected 'auto' or one of {sorted(METHODS)}\n"
    )


@pytest.mark.parametrize(
    ("key", "says"),
    [("pga", "scene.pga: unknown field; a key of [motion], not of [scene]; expected some of"),
     ("fidelty", "scene.fidelty: unknown field; did you mean 'fidelity'? expected some of"),
     ("pgaa", "scene.pgaa: unknown field; expected some of"),
     # a key in another table was only "unknown": the table it belongs in is named
     ("mu", "scene.mu: unknown field; a key of [isolation], not of [scene]; expected some of")],
)  # fmt: skip
def test_an_unknown_key_is_named_with_the_valid_ones(key, says, capsys, tmp_path):
    scene = tmp_path / "s.toml"
    scene.write_text(f'[scene]\nkind = "isolated"\n{key} = 3\n')
    assert main(["run", str(scene)]) == EXIT_USER_ERROR
    err = capsys.readouterr().err
    assert err.startswith(f"nsdyn run: error: {scene}: {says} [")


@pytest.mark.parametrize(
    ("table", "key", "says"),
    [("bearing", "law", "bearing.law: unknown field; a key of [solver] or [sweep], not of "
      "[bearing]; expected some of"),
     ("deck", "dt_out", "deck.dt_out: unknown field; a key of [solver], not of [deck]; "
      "expected some of"),
     # the exact key elsewhere first: it only suggested the deck's mass 'm'
     ("deck", "mu", "deck.mu: unknown field; a key of [bearing], not of [deck] (or did you "
      "mean 'm'?); expected some of"),
     # a scene's kind is no hint for another table's (nor a record's dt for a solver's step);
     # a bearing's type is a deck's only one
     ("bearing", "kind", "bearing.kind: unknown field; expected some of"),
     ("deck", "type", "deck.type: unknown field; a key of [bearing], not of [deck]; expected "
      "some of")],
)  # fmt: skip
def test_a_deck_key_in_another_table_names_its_table(table, key, says, capsys, tmp_path):
    from pathlib import Path

    src = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "deck-fps4-3c.toml"
    scene = tmp_path / "d.toml"
    scene.write_text(src.read_text().replace(f"[{table}]\n", f"[{table}]\n{key} = 1\n", 1))
    assert main(["run", str(scene), "--t-end", "0.1", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"nsdyn run: error: {scene}: {says} [") and err.count("\n") == 1


# -------------------------------------------------------------- a frame file given as a scene

_PLANE = '[frame]\nname = "p"\nkind = "regular"\n'  # read_toml refuses it before any field
_SPACE = '[frame3d]\nname = "s"\n'


@pytest.mark.parametrize("command", ["run", "sweep", "export"])
def test_a_plane_frame_file_given_as_a_scene_says_how_to_run_it(command, capsys, tmp_path):
    f = tmp_path / "f.toml"
    f.write_text(_PLANE)
    argv = [command, *(["opensees"] if command == "export" else []), str(f)]
    assert main(argv) == EXIT_USER_ERROR
    err = capsys.readouterr().err
    assert err.startswith(f"nsdyn {command}: error: {f}: a frame file (its [frame] table)")
    assert f"nsdyn run --frame {f}" in err and f'[scene] frame = "{f}"' in err


def test_a_space_frame_file_given_as_a_scene_names_the_building3d_scene(capsys, tmp_path):
    f = tmp_path / "f.toml"
    f.write_text(_SPACE)
    assert main(["run", str(f)]) == EXIT_USER_ERROR
    err = capsys.readouterr().err
    assert "a 3D frame file (its [frame3d] table)" in err
    assert f"kind 'building3d' as [structure] frame3d = \"{f}\"" in err


def test_a_space_frame_given_to_frame_names_the_building3d_scene(capsys, tmp_path):
    assert main(["run", "--frame", "office-11-3d", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    said = "nsdyn run: error: <default scene>: scene.frame (--frame): office-11-3d is a 3D"
    assert err.startswith(said)
    assert "scene of kind 'building3d'" in err
    assert not (tmp_path / "o").exists()


def test_a_frame_file_without_rotational_mass_is_named_by_its_own_file(capsys, tmp_path):
    # the bundled portal with rho_A = 0 on every member and no node mass: its cb model's mass
    # matrix is singular at node 0's rotation; the refusal names the frame file and its field,
    # not the default scene that --frame edits
    f = tmp_path / "massless.toml"
    text = (Path(__file__).resolve().parents[2] / "frames" / "portal.toml").read_text()
    text = re.sub(r"rho_A = .*", "rho_A = 0.0", re.sub(r"node_mass = .*", "node_mass = 0.0", text))
    f.write_text(text)
    assert main(["run", "--frame", str(f), "--out", str(tmp_path / "o")]) == EXIT_USER_ERROR
    err = capsys.readouterr().err
    assert err.startswith(f"nsdyn run: error: {f}: frame.nodes[0] of frame 'portal': every ")
    assert err.rstrip().endswith("or <default scene>'s scene.fidelity 'rigid' or 'fixed'")
    assert not (tmp_path / "o").exists()


def test_a_units_warning_is_one_line_naming_the_command(capsys, tmp_path):
    # a record without a units header: read as m/s² with a UnitWarning, which the command
    # line shows as one line (Python's form adds the file, the line and its source)
    import warnings

    import numpy as np

    rec = tmp_path / "rec.txt"
    t = np.arange(0.0, 2.0, 0.01)
    rec.write_text("\n".join(f"{a:.3f} {b:.6e}" for a, b in zip(t, 3 * np.sin(t), strict=True)))
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        rc = main(["run", "--record", str(rec), "--t-end", "1", "--json", "--no-figures",
                   "--out", str(tmp_path / "o")])  # fmt: skip
    assert rc == 0
    out, err = capsys.readouterr()
    said = (f"{rec}: the file does not state its units; assuming m/s² (give them: in a scene "
            '[motion] units = "gal", "g" or "m/s2" (a study: [base.motion]); nsdyn run --units '
            "gal; in Python units='gal')")  # fmt: skip
    assert [ln for ln in err.splitlines() if "warning" in ln.lower()] == [
        f"nsdyn run: warning: {said}"
    ]
    assert json.loads(out)["warnings"] == [said]  # (a script reading --json sees it too)


def test_a_vertical_the_model_cannot_feel_is_one_warning_line(capsys, tmp_path):
    # an InputWarning like the units': it printed Python's "file:line: UserWarning: ..."
    import warnings

    scene = Path(__file__).resolve().parents[2] / "examples/scenes/isolated-shear-3storey.toml"
    s = tmp_path / "s.toml"
    argv = ["run", str(s), "--t-end", "0.5", "--no-figures", "--out", str(tmp_path)]
    for vertical, said in (("vertical = true", 1), ("", 0)):  # unset: dropped, no word
        s.write_text(scene.read_text().replace("vertical = false", vertical))
        with warnings.catch_warnings():
            warnings.simplefilter("always")
            assert main(argv) == 0
        err = [ln for ln in capsys.readouterr().err.splitlines() if "warning" in ln.lower()]
        assert len(err) == said
        assert all(e.startswith("nsdyn run: warning: motion: its vertical") for e in err)


def test_a_method_that_cannot_integrate_unilateral_contact_is_named(capsys, tmp_path):
    # lift-off and landing run on event and radau only: said before the model is built, one
    # line naming the field (it was a 25-line traceback from the integrator)
    scene = tmp_path / "s.toml"
    scene.write_text('[isolation]\ncontact = "unilateral"\n[solver]\nmethod = "dopri5"\n')
    assert main(["run", str(scene), "--out", str(tmp_path / "o")]) == EXIT_USER_ERROR
    out, err = capsys.readouterr()
    assert out == "" and err == (
        f"nsdyn run: error: {scene}: solver.method: 'dopri5' cannot integrate "
        "isolation.contact = 'unilateral' (lift-off and landing); expected 'auto' or one of "
        "['event', 'radau']\n"
    )


# ------------------------------------------------------------- a run shorter than its grid

_SCENES = "examples/scenes/"


@pytest.mark.parametrize(
    ("scene", "says"),
    [(None, "motion.t_end (--t-end): expected an end at least one record step (0.01 s) after the "
            "record's start (0 s), got 1e-09"),
     ("building3d-office-rigid", "motion.t_end (--t-end): expected an end at least one"),
     ("rocking-seed001-cask", "solver.dt_out: expected a positive output step no longer "
                              "than the run (1e-09 s)"),
     ("contact-seed002-A5", "solver.dt_out: expected a positive output step no longer than "
                            "the run (1e-09 s), got 0.005")],
)  # fmt: skip
def test_a_run_shorter_than_a_step_names_the_field(scene, says, capsys, tmp_path):
    # --t-end 1e-9 keeps one sample of a record (a run of no time), or is shorter than the
    # scene's output step: each family says so in one line naming the scene's field (it was
    # a traceback in the rocking, contact and 3D rigid families; the deck's: in
    # test_cli_newcomer_inputs)
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    argv = ["run"] + ([] if scene is None else [str(root / _SCENES / f"{scene}.toml")])
    out_dir = tmp_path / "o"
    rc = main([*argv, "--t-end", "1e-9", "--no-figures", "--out", str(out_dir)])
    assert rc == EXIT_USER_ERROR
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[-1].startswith("nsdyn run: error: ")  # (no start line)
    assert says in err[-1]
    assert not any(out_dir.glob("*.npz"))


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        # a prefix is not taken for the option (argparse's default would run --resume)
        (["run", "--res"], "nsdyn run: error: unrecognized arguments: --res; did you mean "
                           "'--resume'?"),
        (["modes", "--fmx", "3"], "did you mean '--fmax'?"),
        (["bench", "spd"], "nsdyn bench: error: argument BENCHMARK: unknown benchmark 'spd'; "
                           "did you mean 'speed'? (benchmarks: accuracy, "),
        (["bench", "switch_shootin"], "did you mean 'switch_shooting'?"),
        # `run --frame` typed on another command read "did you mean '--klam'?" or '--fmin'
        (["modes", "--frame", "office-12"], "--frame; frame is this command's argument (nsdyn "
                                            "modes FRAME)"),
        (["sweep", "--frame", "office-12"], "--frame; --frame is a flag of nsdyn run alone"),
    ],
)  # fmt: skip
def test_a_mistyped_option_or_benchmark_is_refused_with_the_nearest(argv, says, one_line):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == EXIT_USER_ERROR
    one_line(says)


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        # the value blamed came from the flag, not from the file (which holds no such key)
        (["run", "ROCK", "--method", "bogus"], "ROCK: solver.method (--method): rocking scenes"),
        (["run", "ROCK", "--record", "nosuch"], "ROCK: motion.record (--record): cannot read"),
        (["run", "--dt", "0.02", "--method", "genalpha"], "<default scene>: solver.dt (--dt): a"),
        (["export", "opensees", "--dt", "0.02"], "<default scene>: solver.dt (--dt): a fixed"),
        # a scene of its own [structure] takes no frame: the frame came from --frame
        (
            ["run", "SHEAR", "--frame", "office-12"],
            "SHEAR: scene.frame (--frame): 'office-12' not used with a [structure] table",
        ),
        # the file's output step against the flag's end read as the step's fault alone, and a
        # cylinder's end too long (its value not quoted) named no flag
        (
            ["run", "ROCK", "--t-end", "1e-12"],
            "ROCK: solver.dt_out: expected a positive output "
            "step no longer than the run (1e-12 s), got 0.002 (the run ends "
            "at --t-end 1e-12 s)",
        ),
        (
            ["run", "CYL", "--t-end", "1e9"],
            "CYL: motion.t_end (--t-end): 1e+11 samples of 0.01 s exceed 1e+07",
        ),
    ],
)
def test_an_error_about_a_key_a_flag_set_names_the_flag(argv, said, tmp_path, capsys):
    _flag_case(argv, said, tmp_path, capsys)


def test_a_bad_value_in_the_file_is_not_blamed_on_the_flag(tmp_path, capsys):
    # the file's own dt = -1 was reported as "solver.dt (--dt)" when --dt was given too
    scene = tmp_path / "s.toml"
    scene.write_text('[solver]\nmethod = "genalpha"\ndt = -1.0\n')
    argv = ["run", str(scene), "--dt", "0.005", "--t-end", "0.1", "--out", str(tmp_path / "o")]
    assert main(argv) == EXIT_USER_ERROR
    err = capsys.readouterr().err
    assert "solver.dt: expected a positive number, got -1.0" in err and "(--dt)" not in err


def _flag_case(argv, said, tmp_path, capsys):
    scenes = Path(__file__).resolve().parents[2] / "examples/scenes"
    rock = str(scenes / "rocking-seed003-column.toml")
    shear = str(scenes / "isolated-shear-3storey.toml")
    cyl = str(scenes / "cylinder-uplift.toml")
    argv = [{"ROCK": rock, "SHEAR": shear, "CYL": cyl}.get(a, a) for a in argv]
    out = ["--out", str(tmp_path / "o")] if argv[0] == "run" else ["-o", str(tmp_path / "x.py")]
    assert main([*argv, *out]) == EXIT_USER_ERROR
    said = said.replace("ROCK", rock).replace("SHEAR", shear).replace("CYL", cyl)
    assert said in capsys.readouterr().err


def test_an_output_step_longer_than_a_flag_cut_run_names_the_flag(tmp_path, capsys):
    # the isolated frame's wording ("longer than the run") lost the --t-end hint the other
    # families' ("no longer than the run") kept; a step refused on its own gets none
    scene = tmp_path / "s.toml"
    for dt_out, hint in (("5.0", True), ("-1.0", False)):
        scene.write_text(f"[solver]\ndt_out = {dt_out}\n")
        assert main(["run", str(scene), "--t-end", "1", "--out", str(tmp_path / "o")]) == 2
        err = capsys.readouterr().err
        assert "solver.dt_out" in err and ("(the run ends at --t-end 1 s)" in err) is hint


def test_a_generic_key_is_not_sent_to_a_table_that_means_it_otherwise():
    # a rocking scene's [solver] dt was sent to [motion] (a one-column record's sample step),
    # a contact [body] kind to [ground] (rigid or compliant)
    from nsdyn.models.contact.scene import _FIELDS as contact
    from nsdyn.models.rocking.scene import _FIELDS as rocking
    from nsdyn.models.scenefile import unknown_key

    for where, key, tables in (("solver.", "dt", rocking), ("body.", "kind", contact)):
        said = str(unknown_key("s.toml", where, key, tables[where[:-1]], tables))
        assert said.startswith(f"s.toml: {where}{key}: unknown field; expected some of [")


@pytest.mark.parametrize(
    ("rows", "args", "says"),
    [  # a record the run cannot use is named with what is wrong with it, not the solver's step
        ("time [s], acc [m/s2]\n0.0, 0.1\n0.01, 0.2\n", [],
         r"solver.dt_out: an output step of 0.02 s is longer than the run \(0.01 s\).* \(the run "
         r"is the record's span: .*rec.txt, 2 samples at 0.01 s\)$"),
        ("# dt = 0.01\n# units: m/s2\n0.1\n", [],  # (a header's dt read one sample: n = 1)
         r"motion.record \(--record\): .*rec.txt: a record of 1 sample spans no time"),
        ("# units: m/s2\n0.1\n0.2\n0.3\n", ["--dt", "0.01"],  # --dt is not the record's step
         r"give the step dt .* a header line '# dt = 0.01', which every command reads: nsdyn run "
         r"--dt is the integrator's step\)$"),
    ],
)  # fmt: skip
def test_a_record_too_short_or_without_its_step_is_named(rows, args, says, capsys, tmp_path):
    rec = tmp_path / "rec.txt"
    rec.write_text(rows)
    argv = ["run", "--frame", "portal", "--record", str(rec), *args, "--no-figures", "--out",
            str(tmp_path / "o")]  # fmt: skip
    assert main(argv) == EXIT_USER_ERROR
    errors = [ln for ln in capsys.readouterr().err.splitlines() if "error:" in ln]
    assert len(errors) == 1 and re.search(says, errors[0]), errors
