"""Argument types and exit codes shared by the subcommands (argparse lives only in nsdyn.cli)."""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path

EXIT_USER_ERROR = 2  # bad input the user can fix (same as argparse usage errors)
EXIT_NUMERICS = 3  # the numerics failed (step underflow, Newton divergence, uplift, ...)
EXIT_INTERRUPTED = 130  # stopped by SIGINT/SIGTERM (128 + SIGINT); rerun to resume


def positive_float(s: str) -> float:
    """A positive number (``inf`` allowed, e.g. ``--fmax inf``)."""
    try:
        v = float(s)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {s!r}") from None
    if not v > 0:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {s!r}")
    return v


def positive_finite(s: str) -> float:
    """A positive finite number."""
    v = positive_float(s)
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"expected a positive finite number, got {s!r}")
    return v


def _int_at_least(s: str, lowest: int) -> int:
    try:
        v = int(s)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {s!r}") from None
    if v < lowest:
        raise argparse.ArgumentTypeError(
            f"expected at least {lowest} (an integer >= {lowest}), got {s!r}"
        )
    return v


def count(s: str) -> int:
    """An integer of at least 2."""
    return _int_at_least(s, 2)


def positive_int(s: str) -> int:
    """An integer of at least 1 (a number of workers, repeats, ...)."""
    return _int_at_least(s, 1)


def amplitude_list(s: str) -> list[float]:
    """Comma-separated positive amplitudes [m/s²]."""
    try:
        vals = [float(v) for v in s.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected numbers separated by commas, got {s!r}"
        ) from None
    if not vals or any(not (v > 0 and math.isfinite(v)) for v in vals):
        raise argparse.ArgumentTypeError(f"expected positive amplitudes [m/s^2], got {s!r}")
    return vals


def _creatable(p: Path, s: str) -> None:
    """ArgumentTypeError unless directory ``p`` exists or can be made: its first existing
    ancestor is a directory this process may write into."""
    if p.exists():
        if not p.is_dir():
            raise argparse.ArgumentTypeError(f"{s!r} exists and is not a directory")
        if not os.access(p, os.W_OK | os.X_OK):
            raise argparse.ArgumentTypeError(f"directory {s!r} is not writable")
        return
    for a in p.absolute().parents:
        if a.exists():
            if not a.is_dir():
                raise argparse.ArgumentTypeError(f"cannot create {s!r}: {a} is not a directory")
            if not os.access(a, os.W_OK | os.X_OK):
                raise argparse.ArgumentTypeError(f"cannot create {s!r}: {a} is not writable")
            return


def out_dir(s: str) -> str:
    """An output directory that exists or can be created, checked when the command line is
    read, so that a bad ``--out`` fails before the work rather than after it."""
    if not s:
        raise argparse.ArgumentTypeError("expected a directory, got ''")
    _creatable(Path(s), s)
    return s


def out_file(s: str) -> str:
    """An output file whose directory exists or can be created (and that is not a directory)."""
    p = Path(s)
    if not s:
        raise argparse.ArgumentTypeError("expected a file name, got ''")
    if p.is_dir():
        raise argparse.ArgumentTypeError(f"expected a file name, got the directory {s!r}")
    _creatable(p.parent, str(p.parent))
    return s
