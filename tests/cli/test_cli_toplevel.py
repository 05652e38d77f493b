"""The top level of ``nsdyn``: ``nsdyn`` alone names every command, ``--version`` prints
the versions a bug report needs, a mistyped command is answered with the closest one."""

import sys
from importlib.metadata import version

import pytest

import nsdyn
from nsdyn.cli.app import COMMANDS, main
from nsdyn.cli.args import EXIT_USER_ERROR


def test_nsdyn_alone_names_every_command_in_one_line(capsys):
    with pytest.raises(SystemExit) as e:
        main([])
    assert e.value.code == EXIT_USER_ERROR
    out, err = capsys.readouterr()
    assert out == "" and err == (
        f"nsdyn: error: a command is required: {', '.join(COMMANDS)} (see nsdyn --help)\n"
    )


def test_version_names_nsdyn_and_its_numerical_libraries(capsys):
    with pytest.raises(SystemExit) as e:
        main(["--version"])
    assert e.value.code == 0
    out = capsys.readouterr().out.strip()
    assert out.startswith(f"nsdyn {nsdyn.__version__} (Python {sys.version.split()[0]}; ")
    for lib in ("numpy", "scipy", "numba"):
        assert f"{lib} {version(lib)}" in out


@pytest.mark.parametrize(("typed", "hint"), [("rn", "; did you mean 'run'?"),
                                             ("mode", "; did you mean 'modes'?"),
                                             ("xyz", "")])  # fmt: skip
def test_a_mistyped_command_is_answered_with_the_closest(typed, hint, capsys):
    with pytest.raises(SystemExit) as e:
        main([typed])
    assert e.value.code == EXIT_USER_ERROR
    err = capsys.readouterr().err
    assert err == (f"nsdyn: error: unknown command {typed!r}{hint} (commands: "
                   f"{', '.join(COMMANDS)}) (see nsdyn --help)\n")  # fmt: skip


@pytest.mark.parametrize("argv", [["--json", "run", "--t-end", "1"], ["--pga", "3", "run"]])
def test_options_before_the_command_are_answered_with_the_order(argv, capsys):
    # they read "unrecognized arguments: --json --t-end 1" though run takes both
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == EXIT_USER_ERROR
    rest = " ".join(a for a in argv if a != "run")
    assert (
        f"nsdyn: error: options go after the command: nsdyn run {rest}" in capsys.readouterr().err
    )
