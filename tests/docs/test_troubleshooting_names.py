"""The error and warning classes the troubleshooting guide names are the package's: each is
``nsdyn.NAME``, a numerical stop (exit status 3) derives from ``nsdyn.NumericalFailure`` and a
bad input (status 2) from ``ValueError``, as the page says.

Source: docs/guide/troubleshooting.md, the table "Errors and what to do".
"""

from __future__ import annotations

import re
from pathlib import Path

import nsdyn

GUIDE = Path(__file__).resolve().parents[2] / "docs" / "guide" / "troubleshooting.md"
BUILTIN = {"TypeError", "ValueError", "FileNotFoundError", "UserWarning"}


def _rows() -> list[tuple[str, str]]:
    """(class name, first cell) of each table row naming a class of its own."""
    text = GUIDE.read_text(encoding="utf-8")
    out = []
    for line in text.splitlines():
        if not line.startswith("| `"):
            continue
        cell = line.split("|")[1]
        for name in re.findall(r"`([A-Z]\w*(?:Error|Warning|Failure))`", cell):
            if name not in BUILTIN:
                out.append((name, cell))
    return out


def test_every_named_class_is_importable_with_the_status_its_row_gives():
    rows = _rows()
    assert len({n for n, _ in rows}) >= 8  # (the page names them: the parser found them)
    for name, cell in rows:
        cls = getattr(nsdyn, name)  # AttributeError: a name a reader cannot catch
        if "(3)" in cell:
            assert issubclass(cls, nsdyn.NumericalFailure), name
        elif "(2)" in cell:
            assert issubclass(cls, ValueError), name
