"""Atomic output: a failed write leaves the previous file and no temporary file behind; a
finished one has the permissions of any new file under the umask. A refused checkpoint names
the settings that differ."""

import os
import stat

import pytest

from nsdyn.atomic import FILE_MODE, LOCK, OutputBusy, atomic_open, differing, output_dir


def test_failed_write_keeps_the_old_file_and_leaves_no_temporary(tmp_path):
    path = tmp_path / "table.csv"
    path.write_text("old\n")
    with pytest.raises(RuntimeError, match="disk full"):
        with atomic_open(path) as fh:
            fh.write("half a ta")
            raise RuntimeError("disk full")
    assert path.read_text() == "old\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["table.csv"]


def test_finished_write_replaces_the_file_with_umask_permissions(tmp_path):
    path = tmp_path / "sub" / "h.npz"  # the directory is created
    with atomic_open(path, "wb") as fh:
        fh.write(b"\x00\x01")
    assert path.read_bytes() == b"\x00\x01"
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(path.stat().st_mode) == FILE_MODE == 0o666 & ~mask
    assert sorted(p.name for p in path.parent.iterdir()) == ["h.npz"]
    with pytest.raises(ValueError, match="mode"):
        with atomic_open(path, "a"):
            pass
    # a file being replaced keeps its permissions
    os.chmod(path, 0o600)
    with atomic_open(path, "wb") as fh:
        fh.write(b"\x02")
    assert stat.S_IMODE(path.stat().st_mode) == 0o600 and path.read_bytes() == b"\x02"
    # a bad argument to open() leaves neither a temporary file nor an open descriptor
    n_fd = len(os.listdir("/proc/self/fd")) if os.path.isdir("/proc/self/fd") else None
    with pytest.raises(ValueError):
        with atomic_open(path, "wb", encoding="utf-8"):
            pass
    assert sorted(p.name for p in path.parent.iterdir()) == ["h.npz"]
    if n_fd is not None:
        assert len(os.listdir("/proc/self/fd")) == n_fd


def test_interrupt_right_after_the_temporary_is_created_leaves_nothing(tmp_path, monkeypatch):
    # Ctrl-C can land between the creation of the temporary file and the moment its name is
    # known to the writer (tempfile.mkstemp returned it only after creating the file): a study
    # interrupted while writing a part left such a file. The interrupt here fires as the
    # creating call returns.
    path = tmp_path / "part.csv"
    path.write_text("old\n")
    real_open = os.open

    def open_then_interrupt(*args, **kwargs):
        os.close(real_open(*args, **kwargs))  # the file exists; its name never came back
        raise KeyboardInterrupt

    monkeypatch.setattr(os, "open", open_then_interrupt)
    with pytest.raises(KeyboardInterrupt):
        with atomic_open(path) as fh:
            fh.write("new\n")
    monkeypatch.undo()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["part.csv"]
    assert path.read_text() == "old\n"


def test_differing_names_each_changed_leaf_by_its_dotted_path():
    old = {"scene": {"motion": {"pga": 3.0, "record": "a"}, "law": "switch"}, "fidelity": None}
    new = {"scene": {"motion": {"pga": 4.0, "record": "a"}, "law": "switch"}, "fidelity": "cb"}
    assert differing(old, new) == ["fidelity", "scene.motion.pga"]
    # a key on one side only, a table replaced by a value, and equal settings
    assert differing({"a": {"b": 1}}, {"a": 2, "c": 0}) == ["a", "c"]
    assert differing(old, old) == []
    assert differing([1, 2], [1, 3]) == ["(all)"]


def test_an_output_folder_is_held_by_one_command_at_a_time(tmp_path):
    # two runs into one folder wrote over each other's results, and one deleted the other's
    # checkpoint: the second is refused, naming the first; the lock goes with the command
    out = tmp_path / "new" / "out"
    with output_dir(out, "run"):
        assert (out / LOCK).is_file()
        with pytest.raises(OutputBusy, match=rf"^{out}: nsdyn run \(process {os.getpid()}\) "):
            with output_dir(out, "sweep"):
                pass
        assert (out / LOCK).is_file()  # (the refused one took nothing away)
    assert not (out / LOCK).exists() and out.is_dir()
    with pytest.raises(RuntimeError):  # a failed command: its folders go, lock and all
        with output_dir(tmp_path / "made", "run"):
            raise RuntimeError
    assert not (tmp_path / "made").exists()


def test_a_failed_write_names_the_file_it_was_writing(tmp_path):
    # a full disk said "[Errno 28] No space left on device" and no more
    import errno

    path = tmp_path / "run.npz"
    with pytest.raises(OSError, match=r"No space left on device, writing: '.*run\.npz'") as ei:
        with atomic_open(path, "wb"):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    assert ei.value.errno == errno.ENOSPC and not any(tmp_path.iterdir())


def test_a_refused_rename_names_the_file_and_the_command_names_what_it_wrote(tmp_path, monkeypatch):
    # a target that cannot be replaced (an immutable file) named the temporary, removed after:
    # "'DIR/.deck.png-….tmp' -> 'DIR/deck.png'"; an interrupt between a command's files said
    # it "wrote no file" beside the one it had written
    import argparse
    import errno

    import nsdyn.atomic as atomic
    from nsdyn.cli.app import _interrupt_line

    def refuse(src, dst):
        raise PermissionError(errno.EPERM, os.strerror(errno.EPERM), str(src), None, str(dst))

    atomic.WRITTEN.clear()
    with atomic_open(tmp_path / "a.csv") as fh:
        fh.write("x\n")
    monkeypatch.setattr(atomic.os, "replace", refuse)
    with pytest.raises(OSError, match=r"not permitted, writing: '.*deck\.png'$"):
        with atomic_open(tmp_path / "deck.png", "wb") as fh:
            fh.write(b"png")
    assert [p.name for p in tmp_path.iterdir()] == ["a.csv"]  # no temporary left
    assert list(atomic.WRITTEN) == [str(tmp_path / "a.csv")]
    line = _interrupt_line(argparse.Namespace(command="spectrum", out=str(tmp_path)))
    assert line.startswith(f"nsdyn spectrum: interrupted while writing its results: "
                           f"{tmp_path / 'a.csv'} is this run's and complete")  # fmt: skip
    atomic.WRITTEN.clear()
    line = _interrupt_line(argparse.Namespace(command="spectrum", out=str(tmp_path)))
    assert line.startswith("nsdyn spectrum: interrupted before writing its results: it wrote no")
    # into a folder that does not exist, there is no earlier run's file to speak of
    line = _interrupt_line(argparse.Namespace(command="spectrum", out=str(tmp_path / "new")))
    assert "it wrote no file; this command keeps no checkpoint" in line


def test_an_interrupted_write_into_a_new_folder_leaves_no_empty_folder(tmp_path):
    # nsdyn modes / uplift interrupted while writing left the output folder they had made
    with pytest.raises(KeyboardInterrupt):
        with atomic_open(tmp_path / "a" / "b" / "x.png", "wb"):
            raise KeyboardInterrupt
    assert not any(tmp_path.iterdir())
    (tmp_path / "kept").mkdir()  # a folder that was there before stays
    with pytest.raises(KeyboardInterrupt):
        with atomic_open(tmp_path / "kept" / "x.png", "wb"):
            raise KeyboardInterrupt
    assert [p.name for p in tmp_path.iterdir()] == ["kept"]


def test_an_interrupted_cylinder_run_names_the_histories_it_wrote(tmp_path, monkeypatch):
    # a cylinder run stopped while drawing its figure left its complete .npz and said only
    # "files on disk are complete; ... a rerun starts over", as if it had written nothing
    import argparse
    from pathlib import Path

    import nsdyn.atomic as atomic
    from nsdyn.cli.app import _interrupt_line

    scene = Path(__file__).resolve().parents[1] / "examples/scenes/cylinder-uplift.toml"
    args = argparse.Namespace(command="run", scene=str(scene), out=str(tmp_path))
    monkeypatch.setattr("nsdyn.cli.run.FINISHED", [])  # (an isolated run's, of this process)
    atomic.WRITTEN.clear()
    before = _interrupt_line(args)
    assert "this run's" not in before and "a cylinder scene's run keeps no" in before
    with atomic_open(tmp_path / "c.npz", "wb") as fh:
        fh.write(b"npz")
    line = _interrupt_line(args)
    assert f"{tmp_path / 'c.npz'} is this run's, its other files were not written" in line
    atomic.WRITTEN.clear()


def test_an_interrupted_command_names_an_earlier_commands_files_beside_its_own(
    tmp_path, monkeypatch, capsys
):
    # an interrupted full-model run into a folder holding a cb run's histories and figure
    # said only "interrupted; files on disk are complete, rerun it with --resume", as if
    # they were its own (a failed or finished run says whose they are), on stderr and in
    # the --json outcome
    import json

    import nsdyn.solve.transient as transient
    from nsdyn.atomic import EARLIER
    from nsdyn.cli import main

    out = tmp_path / "o"
    out.mkdir()
    (out / "run-histories.npz").write_bytes(b"an earlier run's")
    EARLIER.clear()
    with pytest.raises(KeyboardInterrupt), output_dir(out, "run"):
        raise KeyboardInterrupt
    assert list(EARLIER) == [f"{out} holds an earlier command's files, none of this "
                             "interrupted run's: run-histories.npz"]  # fmt: skip
    EARLIER.clear()  # (a signal inside a kernel: numba's SystemError from the interrupt)
    with pytest.raises(SystemError), output_dir(out, "run"):
        raise SystemError("kernel") from KeyboardInterrupt()
    assert "none of this interrupted run's" in EARLIER[0]

    def stopped(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(transient, "simulate", stopped)
    assert main(["run", "--t-end", "0.2", "--out", str(out), "--json"]) == 130
    cap = capsys.readouterr()
    err = cap.err.strip().splitlines()
    assert err[-2].startswith("nsdyn run: interrupted; ")
    note = f"{out} holds an earlier command's files, none of this interrupted run's: "
    assert err[-1] == f"nsdyn run: note: {note}run-histories.npz"
    said = json.loads(cap.out)
    assert said["status"] == 130 and said["notes"] == [f"{note}run-histories.npz"]
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == [
        "run-histories.npz"]  # fmt: skip


def test_a_probe_of_the_folder_does_not_refuse_the_command_that_writes_there(tmp_path, monkeypatch):
    # check_free takes the lock for an instant: a command whose out_lock met it was refused
    # ("another nsdyn command writes there", 295 of 9 605 tries against a probing process);
    # out_lock now waits a few short turns, as check_free does for another probe
    import fcntl
    import threading

    import nsdyn.atomic as atomic

    monkeypatch.setattr(atomic, "PROBE_TRIES", 1000)  # up to 20 s: not a timing test
    (tmp_path / LOCK).touch()
    fd = os.open(tmp_path / LOCK, os.O_RDONLY)
    fcntl.flock(fd, fcntl.LOCK_EX)  # the probe, as check_free holds it
    release = threading.Timer(0.1, lambda: os.close(fd))
    release.start()
    with atomic.out_lock(tmp_path, "sweep"):
        assert (tmp_path / LOCK).read_text().startswith("nsdyn sweep")
    release.join()
    monkeypatch.setattr(atomic, "PROBE_TRIES", 2)  # a holder that stays: refused, named
    with atomic.out_lock(tmp_path, "run"), pytest.raises(OutputBusy, match="nsdyn run \\(process"):
        atomic.check_free(tmp_path)
