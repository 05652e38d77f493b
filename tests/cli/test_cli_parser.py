"""The ``nsdyn`` parser sets up only the options of the command typed.

``main`` builds the parser with ``build_parser(only=<the command>)``: the other commands are
listed (``nsdyn --help``, an unknown command's error) but their modules are not imported, so a
command's start pays for its own imports alone (``nsdyn run --help`` on a cached install:
docs/dev/first-runs.md). The typed command must parse exactly as with every command set up.
"""

import contextlib
import io
import subprocess
import sys

import pytest

from nsdyn.cli.app import COMMANDS, build_parser


def _help(parser, argv) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), pytest.raises(SystemExit) as e:
        parser.parse_args(argv)
    assert e.value.code == 0
    return out.getvalue()


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_a_command_parses_as_with_every_command_set_up(name):
    assert _help(build_parser(name), [name, "--help"]) == _help(build_parser(), [name, "--help"])


def test_the_command_list_is_complete_with_one_command_set_up():
    assert _help(build_parser("run"), ["--help"]) == _help(build_parser(), ["--help"])


def test_the_parsed_run_options_are_those_of_the_full_parser():
    argv = ["run", "--t-end", "2", "--method", "event", "--no-figures"]
    one, every = vars(build_parser("run").parse_args(argv)), vars(build_parser().parse_args(argv))
    assert one == every


def test_a_command_imports_no_other_commands_module():
    probe = (
        "import sys; from nsdyn.cli.app import main\n"
        "try:\n    main(['modes', '--help'])\nexcept SystemExit:\n    pass\n"
        "print(' '.join(m for m in sys.modules if m.startswith('nsdyn.')))"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True).stdout.split()  # fmt: skip
    assert "nsdyn.cli.modes" in out
    others = {f"nsdyn.cli.{n}" for n in COMMANDS if n != "modes"} | {"nsdyn.bench"}
    assert not others & set(out)


@pytest.mark.parametrize("name", ["run", "modes", "sweep"])
def test_an_unknown_option_is_reported_by_its_command(name, capsys):
    # argparse's top-level parser would report it as "nsdyn: error: ... (see nsdyn --help)",
    # pointing at the wrong help page: the command's own parser names itself
    from nsdyn.cli.app import EXIT_USER_ERROR, main

    with pytest.raises(SystemExit) as e:
        main([name, "--no-such-option", "1"])
    assert e.value.code == EXIT_USER_ERROR
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"nsdyn {name}: error: unrecognized arguments: --no-such-option")
    assert err.endswith(f"(see nsdyn {name} --help)")


def test_a_benchmark_name_may_be_spelt_with_a_hyphen_or_an_underscore():
    from nsdyn.bench import BENCHMARKS

    parser = build_parser("bench")
    for name in BENCHMARKS:
        for spelt in (name, name.replace("_", "-"), name.replace("-", "_")):
            assert parser.parse_args(["bench", spelt]).what == name


def test_the_run_help_names_every_scene_kind_it_runs():
    # it listed the isolated frame, rocking, contact and cylinder, not the deck on
    # bidirectional isolators or the 3D building, which `nsdyn run` runs as well
    from nsdyn.models.scenefile import KINDS

    words = {"isolated": "isolated frame", "rocking": "rocking", "contact": "contact body",
             "cylinder": "cylinder", "deck": "deck", "building3d": "3D building"}  # fmt: skip
    assert set(words) == set(KINDS)
    for argv in (["--help"], ["run", "--help"]):
        text = " ".join(_help(build_parser(), argv).split())
        assert all(w in text for w in words.values()), (argv, text)


@pytest.mark.parametrize(("name", "fresh"), [("study", "--fresh"), ("sweep", "--restart")])
def test_resume_on_a_command_that_resumes_by_rerunning_says_so(name, fresh, capsys):
    # `nsdyn study S --resume` was answered "did you mean '--fresh'?": the one flag that
    # deletes the results it meant to continue
    from nsdyn.cli.app import main

    for flag in ("--resume", "--resumes"):  # (sweep's --res: did you mean '--restart'?)
        with pytest.raises(SystemExit):
            main([name, "s.toml", flag] if name == "study" else [name, flag])
        err = capsys.readouterr().err
        assert f"; nsdyn {name} resumes by being run again as before" in err, err
        assert f"{fresh} starts over)" in err and "did you mean" not in err
    # a misspelt flag of the command's own is still that flag (a loose match read --workes,
    # --frehs or --resart as --resume)
    over = {"--fresh": "--frehs", "--restart": "--resart"}[fresh]
    for typo, meant in (("--workes", "--workers"), (over, fresh)):
        with pytest.raises(SystemExit):
            main([name, "s.toml", typo] if name == "study" else [name, typo])
        assert f"did you mean '{meant}'?" in capsys.readouterr().err
