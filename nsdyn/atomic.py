"""Atomic file output: write a temporary file next to the target, then rename it over it.

A reader never sees a half-written file, and an error (or an interrupt) leaves the old file, if
any, in place and no temporary file behind.
"""

from __future__ import annotations

import os
import stat
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


def _file_mode() -> int:
    """Permissions of a newly created file under the process's umask (mkstemp makes 0600)."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


FILE_MODE = _file_mode()


@contextmanager
def atomic_open(path: str | Path, mode: str = "w", **kwargs) -> Iterator:
    """``open(path, mode)`` for writing, atomically.

    Yields a file object on a temporary file in ``path``'s directory (created if missing);
    on a clean exit it is renamed over ``path`` with that file's permissions if it existed,
    else :data:`FILE_MODE`; on an error it is removed. ``mode``: ``"w"`` or ``"wb"``;
    ``kwargs`` go to :func:`open` (encoding, newline).
    """
    if mode not in ("w", "wb"):
        raise ValueError(f"mode: expected 'w' or 'wb', got {mode!r}")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    try:  # a file being replaced keeps its permissions
        file_mode = stat.S_IMODE(path.stat().st_mode)
    except OSError:
        file_mode = FILE_MODE
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}-", suffix=".tmp")
    try:
        try:
            fh = os.fdopen(fd, mode, **kwargs)
        except BaseException:
            os.close(fd)
            raise
        with fh:
            yield fh
        os.chmod(tmp, file_mode)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def save_figure(fig, path: str | Path, dpi: int = 120) -> Path:
    """Save a matplotlib figure as PNG to ``path``, atomically; returns ``path``."""
    with atomic_open(path, "wb") as fh:
        fig.savefig(fh, format="png", dpi=dpi)
    return Path(path)
