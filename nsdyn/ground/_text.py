"""Plain-text record files, line by line: numbers, comments, headers, tables and time columns.

A record file is a header of comment or title lines followed by numbers. Numbers are read in
Fortran notation too (``1.5D-3``; fields that run together, ``-0.12345-0.23456``, are split).
A time column t_k is accepted when it increases and is uniform: every step within STEP_RTOL of
the median step h, and every stamp within GRID_RTOL Δt of the grid t_0 + k Δt with
Δt = (t_{n−1} − t_0)/(n − 1), rounded to DT_DIGITS significant digits.
"""

from __future__ import annotations

import json
import math
import os
import re
from dataclasses import dataclass
from itertools import chain, islice
from pathlib import Path
from typing import Any

import numpy as np

from nsdyn.ground.motion import A_SAMPLE_MAX, RecordFileError, header_units

BELOW = f" of magnitude at most {A_SAMPLE_MAX:g}"  # (1e300 passed the file, failed as "a_hor")

STEP_RTOL = 0.05  # each time step of a time column within 5 % of the median step
GRID_RTOL = 0.01  # every time stamp within 1 % of a step of the uniform grid t0 + k dt
# times printed to a decimal place up to this fraction of a step are taken as rounded to it
# (4 decimals at 300 Hz: 0.03); a coarser place is the grid's own (0.01 for 100 Hz)
ROUNDED_MAX = 0.1
DT_RTOL = 1e-3  # dt stated in a header vs dt of the time column
DT_DIGITS = 12  # significant digits kept of a dt fitted to a printed time column

COMMENT_PREFIXES = ("#", "%", ";", "!", "//")
NUM = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][+-]?\d+)?"
MILLISECONDS = ("ms", "msec", "msecs", "millisecond", "milliseconds")  # a header's dt unit
_FORTRAN_RUN = re.compile(rf"(?:{NUM})+")
_FORTRAN_ONE = re.compile(r"[+-]?(?:\d+\.\d*|\.\d+)(?:[EeDd][+-]?\d+)?")


def to_float(tok: str) -> float:
    if "_" in tok:  # (Python's float reads "1_0" as 10)
        raise ValueError(f"not a number: {tok!r}")
    return float(tok.replace("D", "E").replace("d", "e"))


def is_comment(s: str) -> bool:
    return s.startswith(COMMENT_PREFIXES)


def strip_comment(s: str) -> str:
    for p in COMMENT_PREFIXES:
        if s.startswith(p):
            return s[len(p) :].strip()
    return s


def header_value(header: list[str], pattern: str) -> str | None:
    m = re.search(pattern, "\n".join(header), re.I | re.M)
    return m.group(1).strip() if m else None


def header_info(header: list[str]) -> dict[str, Any]:
    """What a (comment-stripped) header states: units, dt, npts, t0, name, columns, seed, …"""
    info: dict[str, Any] = {"units": header_units(header)}
    dt = header_value(header, rf"^\s*dt\s*[:=]\s*({NUM})\s*$") or header_value(
        header, rf"\bdt\s*[:=]\s*({NUM})"
    )
    if dt is not None:
        # a unit after the number: milliseconds scaled, seconds (or none) as written
        unit = header_value(header, rf"\bdt[ \t]*[:=][ \t]*{NUM}[ \t]*[\[(]?[ \t]*([a-z]+)")
        ms = unit is not None and unit.lower() in MILLISECONDS
        info["dt"] = to_float(dt) * (1e-3 if ms else 1.0)
    else:
        rate = header_value(header, rf"\bsampling\s+(?:rate|freq\w*)\s*[:=]\s*({NUM})\s*hz")
        if rate is not None:
            info["dt"] = 1.0 / to_float(rate)
    npts = header_value(header, r"\bnpts\s*[:=]\s*(\d+)")
    if npts is not None:
        info["npts"] = int(npts)
    t0 = header_value(header, rf"^\s*t0\s*[:=]\s*({NUM})\s*$")
    if t0 is not None:
        info["t0"] = to_float(t0)
    for key in ("name", "command", "seed", "source"):
        value = header_value(header, rf"^\s*{key}\s*:\s*(.+)$")
        if value is not None:
            info[key] = value
    meta = header_value(header, r"^\s*meta\s*:\s*(\{.*\})\s*$")
    if meta is not None:
        try:
            info["meta"] = json.loads(meta)
        except json.JSONDecodeError:
            pass
    columns = header_value(header, r"\bcolumns\s*:\s*([^;\n]+)")
    if columns is not None:
        info["columns"] = [c.lower() for c in re.split(r"[\s,]+", columns) if c]
    return info


def read_text(path: str | os.PathLike) -> str:
    """A record file's text: its byte-order mark read and dropped (UTF-8, UTF-16), else UTF-8
    (what nsdyn writes: "cm/s²" was read as Latin-1's "cm/sÂ²", an unknown unit), else Latin-1
    (:func:`nsdyn._textfile.decode`)."""
    from nsdyn._textfile import BOMS, decode

    try:
        raw = Path(path).read_bytes()
    except IsADirectoryError:
        raise RecordFileError(path, None, "is a directory, expected a record file") from None
    marked = any(raw.startswith(bom) for bom, _ in BOMS)
    hdf5 = Path(path).suffix.lower() in (".hdf5", ".h5")  # (said by its reader: not read)
    if b"\x00" in raw and not marked and not hdf5:  # (no text has one: a binary file read
        # as Latin-1 had "no numeric data", as did UTF-16 without its mark)
        if not raw[0::2].strip(b"\x00") or not raw[1::2].strip(b"\x00"):  # (ASCII as UTF-16)
            raise RecordFileError(path, None, "UTF-16 text without a byte-order mark; save "
                                  "the file as UTF-8")  # fmt: skip
        line = raw.count(b"\n", 0, raw.index(b"\x00")) + 1
        raise RecordFileError(path, line, "a NUL byte: a binary file, expected a text record")
    try:
        return decode(raw, "utf-8")
    except ValueError as e:  # (an odd byte count after a UTF-16 mark; else not UTF-8)
        if marked:
            raise RecordFileError(path, None, str(e)) from None
    return raw.decode("latin-1")  # (every byte is a Latin-1 character)


def parse_values(lines: list[tuple[int, str]], source: str) -> tuple[np.ndarray, int]:
    """All numbers of free-format value lines (AT2, JMA blocks), in order; Fortran fields that run
    together ("-0.12345-0.23456") are split. Returns (values, number of the last data line)."""
    values: list[float] = []
    last = lines[0][0] if lines else 0
    for lineno, s in lines:
        if not s or is_comment(s):
            continue
        last = lineno
        for tok in fields(s):
            try:
                x = to_float(tok)
            except ValueError:
                if _FORTRAN_RUN.fullmatch(tok):
                    parts = _FORTRAN_ONE.findall(tok)
                    if "".join(parts) == tok:
                        values.extend(to_float(p) for p in parts)
                        continue
                raise RecordFileError(
                    source, lineno, f"expected numbers, found {tok!r} in {s!r}"
                ) from None
            if not (math.isfinite(x) and abs(x) <= A_SAMPLE_MAX):  # (1e300: no acceleration)
                raise RecordFileError(source, lineno, f"expected a finite number{BELOW}, found "
                                      f"{tok!r}")  # fmt: skip
            values.append(x)
    return np.asarray(values, dtype=np.float64), last


def numbered(text: str) -> list[tuple[int, str]]:
    return [(i, s.strip()) for i, s in enumerate(text.splitlines(), start=1)]


@dataclass
class Table:
    header: list[str]  # comment-stripped header lines
    names: list[str] | None  # lower-case column names, if the file gives them
    data: np.ndarray  # (n, m)
    linenos: np.ndarray  # (n,) file line of each row
    units: list[str | None] | None = None  # each named column's unit ("acc [g]"), if any


def _numbers(n: int) -> str:
    return "number" if n == 1 else "numbers"


def fields(s: str) -> list[str]:
    """The fields of a line split by commas, semicolons, tabs or spaces, each without the
    quotes a spreadsheet puts around it ("time","ax": a quoted name was no name, and the
    columns fell back to their order) (a decimal comma is refused before:
    :func:`_decimal_commas`)."""
    return [t.strip("\"'") for t in s.replace(",", " ").replace(";", " ").split()]


def _without_inline_comment(s: str) -> str:
    """A line that starts with a number without its trailing ``# ...`` comment (``0, 0.1 #
    first``: the first row was taken for a title and dropped, the next refused)."""
    if "#" not in s:  # (first: every line of a file of millions passes here)
        return s
    toks = fields(s)
    if not toks or not _is_float(toks[0]):
        return s
    return re.sub(r"(^|[\s,;])#.*$", "", s).strip()


def _next_rows(lines: list[tuple[int, str]], i: int, k: int) -> list[list[str]]:
    """The fields of the ``k`` lines after line ``i`` that are neither empty nor comments, each
    without its trailing comment (read without a copy of the file's lines)."""
    after = islice(lines, i + 1, None)
    kept = (_without_inline_comment(s) for _, s in after if s and not is_comment(s))
    return [fields(s) for s in islice(kept, k)]


def _all_numbers(toks: list[str]) -> bool:
    return bool(toks) and all(_is_float(t) for t in toks)


def _commented_row(s: str, lines: list[tuple[int, str]], i: int) -> bool:
    """Line ``i`` (``s``) is the table's first row with a trailing comment: its numbers before
    the ``#`` as many as the next line's (a title "2 # components" above rows of two is none)."""
    row = _without_inline_comment(s)
    if row == s or not _all_numbers(toks := fields(row)):
        return False
    nxt = _next_rows(lines, i, 1)
    return bool(nxt) and _all_numbers(nxt[0]) and len(nxt[0]) == len(toks)


def _row_with_text(toks: list[str], lines: list[tuple[int, str]], i: int) -> bool:
    """Line ``i`` (``toks``) is a row of the table below with text after its numbers (``0 0.1
    x``): two or more numbers first, as many as each of the next two lines holds, and its
    first (the time) a step before theirs (a title ``1995 6.9 Kobe`` is none)."""
    lead = []
    for t in toks:
        if not _is_float(t):
            break
        lead.append(to_float(t))
    nxt = _next_rows(lines, i, 2)
    if len(lead) < 2 or len(nxt) < 2 or any(len(r) != len(lead) for r in nxt):
        return False
    try:
        t1, t2 = (to_float(r[0]) for r in nxt)
    except ValueError:
        return False
    step = t2 - t1
    return step > 0 and abs((t1 - lead[0]) - step) <= 1e-6 * step


MISSING_MARKS = {"n/a", "na", "nan", "null", "none", "-", "--", "?", "#n/a", "missing"}


def _bad_first_row(toks: list[str], lines: list[tuple[int, str]], i: int) -> bool:
    """Line ``i`` (``toks``) is the table's first row with one cell that is not a number
    (``0,n/a`` above rows of two: read as a title, the record began a step late): as many
    cells as each of the next two lines, all numbers there, its first a step before theirs,
    the bad cell no word (``0.1x``, ``#VALUE!``, an empty quoted cell, ``x``) or a missing
    mark (:data:`MISSING_MARKS`). A title ``2 components`` above rows from t = 0 is none, nor
    ``0 offset`` or ``0 N-S`` above rows from t = dt (two letters or more, no digit)."""
    nxt = _next_rows(lines, i, 2)
    if len(nxt) < 2 or not _one_bad_cell(toks, len(toks)):
        return False
    bad = next(t for t in toks if not _is_float(t))
    letters = sum(c.isalpha() for c in bad)
    if (letters >= 2 and not any(c.isdigit() for c in bad) and not bad.startswith("#")
            and bad.lower() not in MISSING_MARKS):  # fmt: skip
        return False  # (a title's word: NS, N-S, acc., cm/s/s)
    if not all(len(r) == len(toks) and _all_numbers(r) for r in nxt):
        return False
    t0, t1, t2 = to_float(toks[0]), to_float(nxt[0][0]), to_float(nxt[1][0])
    step = t2 - t1
    return step > 0 and abs((t1 - t0) - step) <= 1e-6 * step


def _plain_names(toks: list[str]) -> bool:
    """Column names without units ("t1 a1 a2"): a names line, not a row of numbers written
    as text ("np.float64(0.1)" reads as a name with the unit 0.1)."""
    named = names_and_units(toks)
    return named is not None and all(u is None for u in named[1])


def parse_table(text: str, source: str) -> Table:
    """A header (comment lines, title lines, a line of column names) and then rows of numbers,
    every row with as many as the first; a row's trailing ``# ...`` comment is dropped."""
    lines = numbered(text)
    header: list[str] = []
    names: list[str] | None = None
    units: list[str | None] | None = None
    names_line = None  # the line that gave them (the header's last one, when a row follows)
    names_at = None  # the index in ``lines`` of the first line read as names
    first = None  # index in ``lines`` of the first row of numbers
    for i, (_, s) in enumerate(lines):
        if not s:
            continue
        if is_comment(s):
            header.append(strip_comment(s))
            continue
        if _decimal_commas(s):
            raise RecordFileError(source, lines[i][0], "expected decimal points, found decimal "
                                  f"commas in {s!r} (fields split by tabs, spaces or ';', each "
                                  "with one ',' inside); save the file with '.' as the decimal "
                                  "separator")  # fmt: skip
        if _commented_row(s, lines, i):  # ("0, 0.1 # first": a title before, the row lost)
            first = i
            break
        toks = fields(s)
        try:
            for tok in toks:
                to_float(tok)
        except ValueError:
            after_names = names is not None and header and header[-1] is names_line
            row = fields(_without_inline_comment(s))  # ("0,n/a # warm-up": a title)
            if (after_names and _one_bad_cell(row, len(names))  # a data row, not a title
                    or _row_with_text(toks, lines, i)
                    or _bad_first_row(row, lines, i)  # ("0,#VALUE!": no comment)
                    or _bad_first_row(toks, lines, i)):  # fmt: skip
                bad = next(t for t in row + toks if not _is_float(t))
                raise RecordFileError(source, lines[i][0], f"expected numbers, found {bad!r} "
                                      f"in {s.strip()!r}") from None  # fmt: skip
            header.append(s)
            named = names_and_units(toks)
            if named is not None:
                (names, units), names_line = named, s
                names_at = i if names_at is None else names_at  # (the first such line)
            continue
        first = i
        break
    if first is None:
        width = len(names) if names is not None else 0  # rows after the names, of their
        after = lines[names_at + 1 :] if names_at is not None else []  # width, digits in each
        rows = [(n, s) for n, s in after if s and not is_comment(s) and len(fields(s)) == width
                and all(any(c.isdigit() for c in t) for t in fields(s))
                and not _plain_names(fields(s))]  # fmt: skip
        if rows:  # every cell text ("np.float64(1.0)"): it named the file's last line
            n, s = rows[0]
            bad = next(t for t in fields(s) if not _is_float(t))
            raise RecordFileError(source, n, f"expected numbers, found {bad!r} in {s.strip()!r}")
        last_line = lines[-1][0] if lines else 0
        raise RecordFileError(source, max(last_line, 1), "expected numeric data, found none")
    rows = [(n, _without_inline_comment(s)) for n, s in lines[first:]]
    data, linenos = _rows_at_once(rows)
    if data is None:
        data, linenos = _rows(rows, source)
    ncol = data.shape[1]
    info_names = header_info(header).get("columns")
    if info_names is not None and len(info_names) == ncol:
        names, units = info_names, None
    if names is not None and len(names) != ncol:
        names, units = _labels_folded(names, units, ncol)
    return Table(header, names, data, linenos, units)


def _labels_folded(names: list[str], units: list, ncol: int) -> tuple:
    """``names`` and ``units`` of a header line with more names than the ``ncol`` columns,
    each name without a unit that follows a column's unit folded into that column's name as
    a label ("t [s], a [g] NS": the columns "t" and "a ns" in s and g; the units were not
    read), when that gives ``ncol`` columns; else (None, None)."""
    out_n: list[str] = []
    out_u: list = []
    for name, unit in zip(names, units, strict=True):
        if unit is None and out_u and out_u[-1] is not None:
            out_n[-1] = f"{out_n[-1]} {name}"
            continue
        out_n.append(name)
        out_u.append(unit)
    return (out_n, out_u) if len(out_n) == ncol else (None, None)


_NAME = r"[A-Za-z][\w.-]*"
_UNIT = r"[\[(]\s*([^\[\]()]+?)\s*[\])]"  # [g], (cm/s2), [ m/s^2 ]
_NAME_UNIT = re.compile(rf"({_NAME})(?:{_UNIT})?")
_NAME_ANY = r"[A-Za-z][\w()\[\]/^.-]*"  # any name a header line may give a column


def names_and_units(toks: list[str]) -> tuple[list[str], list[str | None]] | None:
    """The column names of a header line and the unit each states, or None when the line is
    no line of names: ``time acc [g]``, ``Time (s), Acceleration (g)``, ``t(s) a(g)`` give
    ``[time, acc]`` and ``[s, g]`` (a unit in brackets, glued to its name or the field after
    it; names lower-case, units as written)."""
    names: list[str] = []
    units: list[str | None] = []
    for tok in toks:
        alone = re.fullmatch(_UNIT, tok)
        if alone is not None:  # "acc [g]": the unit of the name before it
            if not names:
                return None
            if units[-1] is not None:  # "acc [g] (E-W)": a label after the unit
                names[-1] = f"{names[-1]} {tok.lower()}"
                continue
            units[-1] = alone.group(1)
            continue
        m = _NAME_UNIT.fullmatch(tok)
        if m is not None:
            names.append(m.group(1).lower())
            units.append(m.group(2))
        elif re.fullmatch(_NAME_ANY, tok):  # a name as a whole ("acc/g"), no unit read from it
            names.append(tok.lower())
            units.append(None)
        else:
            return None
    return (names, units) if names else None


_DECIMAL_COMMA = re.compile(r"[+-]?\d*,\d+(?:[EeDd][+-]?\d+)?")


def _decimal_commas(row: str) -> bool:
    """A row of two or more fields, split by tabs, spaces or ';', each a number written with a
    decimal comma ("0,01\t-0,0244"): read with ',' as a separator it gives wrong columns."""
    fields = re.split(r"[\s;]+", row.strip())
    return len(fields) >= 2 and all(_DECIMAL_COMMA.fullmatch(f) for f in fields)


def _is_float(tok: str) -> bool:
    try:
        to_float(tok)
    except ValueError:
        return False
    return True


def _one_bad_cell(toks: list[str], n_names: int) -> bool:
    """A row of the named table with one cell that is not a number: as many cells as names
    (two or more), a number first (the time) and every other cell a number but one. A header
    line after a title (``dt = 0.02``, ``dt: 0.02``, ``1940 El Centro``) is none."""
    numeric = [_is_float(t) for t in toks]
    return len(toks) == n_names >= 2 and numeric[0] and sum(numeric) == len(toks) - 1


def _rows_at_once(rows: list[tuple[int, str]]) -> tuple[np.ndarray | None, np.ndarray]:
    """The rows of a table read in one pass when every number is one Python ``float`` reads
    (no Fortran exponent), finite, and every row has as many as the first: the values
    :func:`_rows` reads, ~10 times sooner. (None, ...) otherwise: :func:`_rows` then reads
    them line by line and names the line that is wrong."""
    kept = [(n, s) for n, s in rows if s and not s.startswith(COMMENT_PREFIXES)]
    toks = [fields(s) for _, s in kept]
    ncol = len(toks[0])
    if any(len(t) != ncol for t in toks) or any("_" in s for _, s in kept):  # ("1_0": 10)
        return None, np.empty(0, np.int64)
    try:
        values = np.fromiter(map(float, chain.from_iterable(toks)), np.float64, len(toks) * ncol)
    except ValueError:
        return None, np.empty(0, np.int64)
    if not (np.abs(values) <= A_SAMPLE_MAX).all():  # (NaN too: read line by line, named)
        return None, np.empty(0, np.int64)
    return values.reshape(len(toks), ncol), np.array([n for n, _ in kept])


def _rows(rows: list[tuple[int, str]], source: str) -> tuple[np.ndarray, np.ndarray]:
    """The rows of a table line by line: a line that is not a row of as many numbers as the
    first, or a number that is not finite, is an error naming its line."""
    values: list[list[float]] = []
    linenos: list[int] = []
    ncol = 0
    for lineno, s in rows:
        if not s or is_comment(s):
            continue
        toks = fields(s)
        try:
            vals = [to_float(tok) for tok in toks]
        except ValueError:
            raise RecordFileError(
                source, lineno, f"expected {ncol} {_numbers(ncol)} per line, found {s!r}"
            ) from None
        if not values:
            ncol = len(vals)
        elif len(vals) != ncol:
            raise RecordFileError(
                source,
                lineno,
                f"expected {ncol} {_numbers(ncol)} per line, found {len(vals)}: {s!r}",
            )
        for tok, x in zip(toks, vals, strict=True):
            if not (math.isfinite(x) and abs(x) <= A_SAMPLE_MAX):
                raise RecordFileError(source, lineno, f"expected a finite number{BELOW}, found "
                                      f"{tok!r}")  # fmt: skip
        values.append(vals)
        linenos.append(lineno)
    return np.asarray(values, dtype=np.float64), np.asarray(linenos)


def looks_like_time(col: np.ndarray) -> bool:
    """A first column is time if it mostly increases (an accelerogram's does about half the time);
    a glitch in it is then reported by :func:`check_time` rather than taken for data."""
    return col.size >= 3 and col[-1] > col[0] and float(np.mean(np.diff(col) > 0.0)) >= 0.75


def median(x: np.ndarray) -> float:
    """The median of a non-empty 1-D array of finite numbers, as ``np.median`` gives it (the mean
    of the middle two of an even count), without numpy 2's import of ``numpy.ma`` (~40 ms of
    a cached start) that ``np.median`` makes."""
    s = np.sort(x)
    m = s.size // 2
    return float(s[m]) if s.size % 2 else float((s[m - 1] + s[m]) / 2.0)


def rounding_place(t: np.ndarray, dt: float) -> float:
    """The decimal place the times were rounded to as printed (1e-4 for k/300 s printed as
    ``0.0033``), or 0 when they were not: times on a coarser place than ROUNDED_MAX of a step,
    or a step ``dt`` (fitted through the end stamps) that is a whole multiple of the place
    (100 Hz printed as ``0.010`` is exact: a stamp off its grid there is jitter). Rounded, a
    stamp is off by half the place and the fitted grid by half more."""
    place = 0.0
    for d in range(13):
        scaled = t * 10.0**d  # (a printed decimal reads to within 1e-16 of it, relative)
        if np.all(np.abs(scaled - np.round(scaled)) <= 1e-9 * np.maximum(1.0, np.abs(scaled))):
            place = 10.0**-d
            break
    if not 0.0 < place <= ROUNDED_MAX * dt:
        return 0.0
    r = dt / place  # (a whole number when the end stamps are exact: no stamp was rounded)
    return place if abs(r - round(r)) > 1e-6 * r else 0.0


def check_time(t: np.ndarray, linenos: np.ndarray, source: str) -> float:
    """Validate a time column (increasing, uniform) and return its dt: its steps within
    STEP_RTOL of their median and its stamps within GRID_RTOL of a step of the uniform grid,
    or within the decimal place they were rounded to (:func:`rounding_place`) when that is
    more."""
    if t.size < 2:
        raise RecordFileError(source, int(linenos[0]), "expected at least two time samples")
    d = np.diff(t)
    bad = np.flatnonzero(d <= 0.0)
    if bad.size:
        k = int(bad[0]) + 1
        raise RecordFileError(
            source, int(linenos[k]),
            f"expected time > {t[k - 1] + 0.0:.10g} s, found {t[k] + 0.0:.10g} s",  # (no -0)
        )  # fmt: skip
    h = median(d)
    dt = (float(t[-1]) - float(t[0])) / (t.size - 1)
    ulp = rounding_place(t, dt)  # stamps rounded to it: each step off by up to one of it
    bad = np.flatnonzero(np.abs(d - h) > max(STEP_RTOL * h, ulp * (1 + 1e-6)))
    if bad.size:
        k = int(bad[0]) + 1
        raise RecordFileError(
            source,
            int(linenos[k]),
            f"expected a uniform time step {h:.6g} s (±{STEP_RTOL:.0%}), found "
            f"{d[k - 1]:.6g} s (t = {t[k - 1]:.10g} → {t[k]:.10g} s)",
        )
    dev = np.abs(t - (t[0] + dt * np.arange(t.size)))
    bad = np.flatnonzero(dev > max(GRID_RTOL * dt, ulp * (1 + 1e-6)))  # (and t0, dt: fitted)
    if bad.size:
        k = int(bad[0])
        raise RecordFileError(
            source,
            int(linenos[k]),
            f"expected t = {t[0] + k * dt:.10g} s on the uniform grid (dt = {dt:.6g} s), "
            f"found {t[k]:.10g} s",
        )
    return float(f"{dt:.{DT_DIGITS}g}")


def column_index(spec: int | str, names: list[str] | None, ncol: int, source: str,
                 argument: str = "column") -> int:  # fmt: skip
    """The index of the column ``spec`` (an index, negative from the end, or a name) of a
    table of ``ncol`` columns; a RecordFileError whose ``argument`` names the reader's key."""
    if isinstance(spec, str):
        if names is None:
            raise RecordFileError(source, None, f"expected a column named {spec!r}; the file "
                                  f"names no columns: give an index 0..{ncol - 1}",
                                  argument)  # fmt: skip
        named = names_and_units(fields(spec))  # a name given with its unit, "acc [g]"
        key = named[0][0] if named is not None and len(named[0]) == 1 else spec.lower()
        if key not in names:
            raise RecordFileError(source, None, f"expected a column named {spec!r}; has {names}",
                                  argument)  # fmt: skip
        return names.index(key)
    idx = int(spec)
    if not -ncol <= idx < ncol:
        raise RecordFileError(source, None, f"expected column index < {ncol}, got {spec}",
                              argument)  # fmt: skip
    return idx % ncol
