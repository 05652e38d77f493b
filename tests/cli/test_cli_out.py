"""A bad ``--out`` is refused when the command line is read, before any work (a sweep or a
benchmark that ran for minutes used to fail only when it wrote its first file): one line
naming the option and what is wrong, status 2, nothing created."""

import os
from pathlib import Path

import pytest

from nsdyn.cli import main
from nsdyn.cli.args import EXIT_USER_ERROR

# every command with an output directory; a command's other required arguments where it has
# them (never read: the --out check comes first)
COMMANDS = {
    "run": [],
    "sweep": [],
    "uplift": [],
    "modes": ["office-11"],
    "spectrum": ["s.toml"],
    "study": ["s.toml"],
    "bench": ["speed"],
}


def _refused(argv, capsys, says: str, command: str) -> None:
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == EXIT_USER_ERROR
    out, err = capsys.readouterr()
    assert out == ""
    assert err.startswith(f"nsdyn {command}: error: argument ")
    assert says in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_an_out_below_a_file_is_refused_before_the_work(command, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "afile").write_text("")
    argv = [command, *COMMANDS[command], "--out", "afile/x"]
    _refused(argv, capsys, f"--out: cannot create 'afile/x': {tmp_path / 'afile'} is not a "
             "directory", command)  # fmt: skip
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]


@pytest.mark.parametrize("command", ["run", "bench"])
def test_an_out_that_is_a_file_is_refused(command, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "afile").write_text("")
    _refused([command, *COMMANDS[command], "--out", "afile"], capsys,
             "--out: 'afile' exists and is not a directory", command)  # fmt: skip


def test_an_empty_out_is_refused(capsys):
    _refused(["run", "--out", ""], capsys, "--out: expected a directory, got ''", "run")


@pytest.mark.skipif(os.geteuid() == 0 if hasattr(os, "geteuid") else True,
                    reason="root may write anywhere; a POSIX non-root user is needed")  # fmt: skip
def test_an_out_in_a_read_only_directory_is_refused(capsys, tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir(mode=0o500)
    _refused(["run", "--out", str(ro / "x")], capsys, "is not writable", "run")


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs Linux's /proc")
def test_an_out_where_no_directory_can_be_made_says_why(capsys):
    # /proc refuses a new directory with ENOENT: it read "/proc is not writable (No such file
    # or directory)", two reasons at odds
    _refused(["run", "--out", "/proc/nsdyn-x"], capsys, "cannot create '/proc/nsdyn-x': /proc "
             "takes no new directory (No such file or directory)", "run")  # fmt: skip


def test_the_export_file_is_checked_too(capsys, tmp_path):
    says = f"-o/--out: expected a file name, got the directory '{tmp_path}'"
    _refused(["export", "opensees", "s.toml", "--out", str(tmp_path)], capsys, says, "export")
    (tmp_path / "afile").write_text("")
    _refused(["export", "opensees", "s.toml", "--out", str(tmp_path / "afile" / "x.py")],
             capsys, "is not a directory", "export")  # fmt: skip


def test_a_new_nested_out_is_accepted(tmp_path):
    from nsdyn.cli.args import out_dir

    assert out_dir(str(tmp_path / "a" / "b" / "c")) == str(tmp_path / "a" / "b" / "c")
    assert not (tmp_path / "a").exists()  # checked, not made


def test_a_frame_name_with_path_separators_stays_inside_out(tmp_path, capsys):
    # name = "../../x" wrote modes-../../x.png two folders above --out (and left an empty
    # "modes-.." folder); the name is a file stem, as a scene's is
    frames = Path(__file__).resolve().parents[2] / "frames"
    text = (frames / "portal.toml").read_text()
    lines = [ln if not ln.startswith("name =") else 'name = "../../x"' for ln in text.splitlines()]
    f = tmp_path / "f.toml"
    f.write_text("\n".join(lines) + "\n")
    out = tmp_path / "a" / "b"
    assert main(["modes", str(f), "--out", str(out)]) == 0
    assert [p.name for p in out.iterdir()] == ["modes-_.._x.png"]
    assert not (tmp_path / "x.png").exists()


def test_a_file_stem_holds_no_control_character_nor_more_than_name_max_bytes():
    # a frame's name "a\x00b" was "embedded null byte", "a\nb" a file name with a newline,
    # 300 characters "File name too long"
    from nsdyn.models.scenefile import NAME_MAX, file_stem

    assert file_stem("a\x00b\nc") == "a_b_c" and file_stem("../x") == "_x"
    long = file_stem("é" * 300)
    assert len(long.encode()) <= NAME_MAX and long == "é" * (NAME_MAX // 2)
