"""The text of a user's input file (scene, study, frame, record), whatever its byte-order mark.

Editors on other machines save text with a byte-order mark: UTF-8 with BOM (Notepad, Excel's
"CSV UTF-8"), UTF-16 (Excel's "Unicode text", PowerShell's ``>``) or UTF-32. Read as plain
bytes, the mark made a record's first sample a header line (one sample lost without a word)
and a column header's first name unknown (the vertical column read as the horizontal one),
and a UTF-16 file read as "no numeric data". :func:`decode` reads the mark and drops it;
without one, the file is read in the reader's own encoding (UTF-8 for TOML; for records UTF-8,
else Latin-1: their numbers are ASCII and their headers may hold any byte), and text that is
not in it is a ValueError naming the line and saying how to save the file.
"""

from __future__ import annotations

import codecs
from pathlib import Path

# (mark, codec): UTF-32 first, since its little-endian mark begins with UTF-16's
BOMS = (
    (codecs.BOM_UTF32_LE, "utf-32"),
    (codecs.BOM_UTF32_BE, "utf-32"),
    (codecs.BOM_UTF8, "utf-8-sig"),
    (codecs.BOM_UTF16_LE, "utf-16"),
    (codecs.BOM_UTF16_BE, "utf-16"),
)

# the file names of ground-motion records (given where a scene or frame file goes: said so)
RECORD_SUFFIXES = (".csv", ".txt", ".at2", ".dat", ".acc")


def decode(raw: bytes, encoding: str = "utf-8") -> str:
    """``raw`` as text: by its byte-order mark (dropped), else in ``encoding``; a byte that
    does not decode is a ValueError "not UTF-8 text: byte 0x.. on line L (save the file as
    UTF-8)"."""
    for bom, codec in BOMS:
        if raw.startswith(bom):
            encoding = codec
            break
    try:
        return raw.decode(encoding)
    except UnicodeDecodeError as e:
        line = raw[: e.start].count(b"\n") + 1
        name = encoding.upper().replace("-SIG", "")
        raise ValueError(f"not {name} text: byte 0x{raw[e.start]:02x} on line {line} (save the "
                         "file as UTF-8)") from None  # fmt: skip


def read(path: str | Path, encoding: str = "utf-8") -> str:
    """The text of the file ``path`` (:func:`decode`); OSError as ``Path.read_bytes``."""
    return decode(Path(path).read_bytes(), encoding)
