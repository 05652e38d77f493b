"""Atomic file output: write a temporary file next to the target, then rename it over it.

A reader never sees a half-written file, and an error (or an interrupt) leaves the old file, if
any, in place and no temporary file behind.
"""

from __future__ import annotations

import errno
import os
import secrets
import stat
from collections import deque
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


def _file_mode() -> int:
    """Permissions of a newly created file under the process's umask (temporaries are 0600)."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


FILE_MODE = _file_mode()
# the errors of a write itself, named with the file they hit (a full disk, a quota)
WRITE_ERRNOS = {getattr(errno, n, None) for n in ("ENOSPC", "EDQUOT", "EFBIG", "EIO")} - {None}


class CheckpointError(ValueError):
    """A checkpoint file written by another run (other system, motion, start or options)."""


def differing(old, new, path: str = "") -> list[str]:
    """The dotted keys at which two JSON-like settings differ (what a refused checkpoint
    names): nested tables are compared key by key, anything else as a whole."""
    if not (isinstance(old, dict) and isinstance(new, dict)):
        return [] if old == new else [path or "(all)"]
    keys = sorted(set(old) | set(new), key=str)
    return [
        d
        for k in keys
        for d in differing(old.get(k), new.get(k), f"{path}.{k}" if path else str(k))
    ]


# the last files this process renamed into place (an interrupted command names those it
# wrote; the command line clears it as a command starts; bounded for long library sessions)
WRITTEN: deque[str] = deque(maxlen=64)
# the note of a command that failed in its output folder on the files there it did not write
# (said after its error line: an earlier run's histories are not this one's)
EARLIER: deque[str] = deque(maxlen=1)


@contextmanager
def atomic_open(path: str | Path, mode: str = "w", **kwargs) -> Iterator:
    """``open(path, mode)`` for writing, atomically.

    Yields a file object on a temporary file in ``path``'s directory (created if missing);
    on a clean exit it is renamed over ``path`` with that file's permissions if it existed,
    else :data:`FILE_MODE`; on an error it is removed, with the directories it created when
    they are left empty. ``mode``: ``"w"`` or ``"wb"``;
    ``kwargs`` go to :func:`open` (encoding, newline).
    """
    if mode not in ("w", "wb"):
        raise ValueError(f"mode: expected 'w' or 'wb', got {mode!r}")
    path = Path(path)
    made = [d for d in (path.parent, *path.parent.parents) if not d.exists()]  # deepest first
    path.parent.mkdir(parents=True, exist_ok=True)
    try:  # a file being replaced keeps its permissions
        file_mode = stat.S_IMODE(path.stat().st_mode)
    except OSError:
        file_mode = FILE_MODE
    # the temporary's name is fixed before the file exists (mkstemp returns it only after
    # creating the file, and an interrupt between the two left it behind): whatever stops the
    # write from the creation on finds the name to remove
    tmp: Path | None = path.parent / f".{path.name}-{secrets.token_hex(8)}.tmp"
    try:
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        except FileExistsError:  # another writer's (a 64-bit name collision): not ours
            tmp = None
            raise
        try:
            fh = os.fdopen(fd, mode, **kwargs)
        except BaseException:
            os.close(fd)
            raise
        try:
            with fh:
                yield fh
        except OSError as e:  # (a full disk said "[Errno 28] No space left on device")
            if e.filename is None and e.errno in WRITE_ERRNOS:
                raise OSError(e.errno, f"{e.strerror}, writing", str(path)) from e
            raise
        os.chmod(tmp, file_mode)
        try:
            os.replace(tmp, path)
        except OSError as e:  # (it named the temporary, removed below: ".x.png-….tmp -> x.png")
            raise OSError(e.errno, f"{e.strerror}, writing", str(path)) from e
        WRITTEN.append(str(path))
    except BaseException:
        if tmp is not None:
            tmp.unlink(missing_ok=True)
        for d in made:  # (an interrupted write left the empty folder it made)
            try:
                d.rmdir()
            except OSError:
                break
        raise


def save_figure(fig, path: str | Path, dpi: int = 120) -> Path:
    """Save a matplotlib figure as PNG to ``path``, atomically; returns ``path``."""
    with atomic_open(path, "wb") as fh:
        fig.savefig(fh, format="png", dpi=dpi)
    return Path(path)


LOCK = ".nsdyn.lock"  # held in an output directory while a command writes there


class OutputBusy(OSError):
    """Another command writes into the output directory."""


def _busy(out: Path, fd: int) -> OutputBusy:
    """The error naming the command that holds ``out``'s lock (open as ``fd``, closed here)."""
    who = os.read(fd, 200).decode(errors="replace").strip() or "another nsdyn command"
    os.close(fd)
    return OutputBusy(f"{out}: {who} writes there; wait for it to end, or give another --out")


PROBE_TRIES, PROBE_WAIT_S = 10, 0.02  # a probe's lock (check_free's) lasts microseconds
try:
    import fcntl as _fcntl  # noqa: F401  (POSIX: flock)

    POSIX_LOCKS = True
except ImportError:  # (Windows: nothing is locked)
    POSIX_LOCKS = False


def _locked(fd: int) -> bool:
    """Take ``flock(LOCK_EX)`` on ``fd`` without blocking; False while another holds it,
    after a few short waits: a probe of :func:`check_free` holds it only for an instant, and
    a command that met one was refused for nothing."""
    import fcntl
    import time

    for k in range(PROBE_TRIES):
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return True
        except BlockingIOError:
            if k + 1 < PROBE_TRIES:
                time.sleep(PROBE_WAIT_S)
    return False


def check_free(out: Path) -> None:
    """Raise :class:`OutputBusy` as :func:`out_lock` would if another command holds ``out``
    now, creating nothing: for a command to call before it says anything, so that a busy
    folder's error is its one line (the lock itself is still taken by :func:`out_lock`)."""
    if not POSIX_LOCKS:
        return
    try:
        fd = os.open(Path(out) / LOCK, os.O_RDONLY)
    except OSError:  # no lock file (or no folder): nobody holds it
        return
    if not _locked(fd):
        raise _busy(out, fd)
    os.close(fd)  # (its lock with it)


@contextmanager
def out_lock(out: Path, command: str) -> Iterator[None]:
    """Hold an exclusive lock on the directory ``out`` while a command writes there (a file
    :data:`LOCK` locked with ``flock``, naming the command and its process, removed at the
    end), or raise :class:`OutputBusy` naming the command that holds it: two runs into one
    folder wrote over each other's results, and one deleted the other's checkpoint. Where
    ``fcntl`` is missing (not POSIX) nothing is locked."""
    if not POSIX_LOCKS:
        yield
        return
    path = Path(out) / LOCK
    while True:  # a lock file its holder removed as we opened it: lock the one now there
        fd = os.open(path, os.O_RDWR | os.O_CREAT, FILE_MODE)
        if not _locked(fd):
            raise _busy(out, fd)
        try:
            if os.stat(path).st_ino == os.fstat(fd).st_ino:
                break
        except FileNotFoundError:
            pass
        os.close(fd)
    try:
        os.ftruncate(fd, 0)
        os.write(fd, f"nsdyn {command} (process {os.getpid()})".encode())
        try:
            yield
        finally:
            path.unlink(missing_ok=True)  # (while held)
    finally:
        os.close(fd)


def files_of(out: Path) -> dict:
    """{name: modification time [ns]} of the visible files in ``out`` (none if missing)."""
    if not Path(out).is_dir():
        return {}
    return {p.name: p.stat().st_mtime_ns for p in Path(out).iterdir()
            if p.is_file() and not p.name.startswith(".")}  # fmt: skip


RESULT_SUFFIXES = (".npz", ".png", ".csv", ".json", ".parquet")  # what the commands write


def earlier_files(out: Path, before: dict, command: str, failed: bool | str = False) -> str:
    """The note on the files in ``out`` that a command did not write (as :func:`files_of`
    saw them, ``before``, when it began: an earlier command's), or "". ``failed``: worded
    for a command that wrote none (its error said why; a text: how it ended, "interrupted"),
    and of the result files only (:data:`RESULT_SUFFIXES`: a scene kept in the folder is no
    earlier result)."""
    kept = sorted(
        n
        for n, t in files_of(out).items()
        if before.get(n) == t and (not failed or Path(n).suffix in RESULT_SUFFIXES)
    )  # (not its inputs)
    if not kept:
        return ""
    more = f" and {len(kept) - 4} more" if len(kept) > 4 else ""
    what = (
        f"holds an earlier command's files, none of this "
        f"{'failed' if failed is True else failed} {command}'s"
        if failed
        else f"also holds files this {command} did not write (an earlier command's)"
    )
    return f"{out} {what}: {', '.join(kept[:4])}{more}"


def caused_by_interrupt(exc: BaseException) -> bool:
    """True if a KeyboardInterrupt is ``exc`` or in its chain of causes (numba's dispatcher
    turns an exception raised by a signal handler during a kernel into SystemError from it)."""
    seen: set[int] = set()
    e: BaseException | None = exc
    while e is not None and id(e) not in seen:
        if isinstance(e, KeyboardInterrupt):
            return True
        seen.add(id(e))
        e = e.__cause__ or e.__context__
    return False


@contextmanager
def output_dir(out: Path, command: str = "command", say=None) -> Iterator[Path]:
    """The output directory of a command, created if missing and locked while the command
    writes there (:func:`out_lock`). A command that fails or is interrupted removes the
    directories it created, when it left them empty (an interrupted run's checkpoint, a
    sweep's finished points keep theirs); files and directories that were there before are
    never touched. ``say(line)``: told, when the command ends, of the files there that it
    did not write (an earlier command's: a rocking run's beside an isolated frame's). A
    command that fails with an error leaves that note in :data:`EARLIER`, for the command
    line to say after the error (and after an interrupt's line, which says what is on
    disk)."""
    made = [d for d in (out, *out.parents) if not d.exists()]  # deepest first
    out.mkdir(parents=True, exist_ok=True)
    before = files_of(out)
    try:
        with out_lock(out, command):
            yield out
        if say is not None and (note := earlier_files(out, before, command)):
            say(note)
    except BaseException as exc:
        how = "interrupted" if caused_by_interrupt(exc) else isinstance(exc, Exception)
        if how and (note := earlier_files(out, before, command, how)):
            EARLIER.append(note)
        for d in made:
            try:
                d.rmdir()  # only an empty directory goes
            except OSError:
                break
        raise
