"""Reading and writing ground-motion files: the front door ``read_motion`` and ``write_motion``.

``read_motion`` takes a file or the name of a bundled record, detects the layout (see
:mod:`nsdyn.ground.formats`), converts to m/s² and attaches a vertical component from a column,
another file (same Δt, t0 and length, or both cut to the shorter with ``trim=True``) or a
ratio r (ü_ver = r ü_hor).
``write_motion`` writes the CSV that ``read_motion`` reads back bit for bit: columns
t_k = t0 + k Δt, ü_hor[, ü_ver] in m/s², every value as its shortest round-trip repr.
"""

from __future__ import annotations

import json
import math
import os
import re
from pathlib import Path

import numpy as np

from nsdyn._bundled import RECORDS
from nsdyn.atomic import atomic_open
from nsdyn.ground._text import DT_RTOL, is_comment, numbered, read_text
from nsdyn.ground.formats import (
    ReadOptions,
    at2_header_line,
    parse_at2,
    parse_jma,
    parse_table_motion,
)
from nsdyn.ground.motion import GroundMotion, RecordFileError, check_pga

_FORMATS = ("auto", "at2", "jma", "two-column", "single-column", "multi-column")
COMPANION_SUFFIX = "-y.txt"  # the second horizontal component of a bundled record <name>.csv


class BundledFile(str):
    """The name of a file among the bundled records (a record's second horizontal component
    ``<name>-y.txt``), looked up there alone: a file of that name in the working directory
    is not it."""


def _resolve(path_or_name: str | os.PathLike) -> tuple[str, str]:
    """(source label, text) of a file path or a bundled record name (``<name>`` or
    ``<name>.csv``), or of a :class:`BundledFile`; a bundled file labelled as such."""
    path = Path(path_or_name)
    bundled = isinstance(path_or_name, BundledFile)
    if not bundled and path.is_file():
        return str(path), read_text(path)
    name = str(path_or_name)
    stem = name[:-4] if name.endswith(".csv") else name
    if "/" not in stem and os.sep not in stem:
        file = name if bundled else f"{stem}{RECORDS.suffix}"
        item = RECORDS.root() / file
        if item.is_file():
            return f"{RECORDS.package}/{file}", item.read_text(encoding="latin-1")
    if path.exists():
        raise RecordFileError(path, None, "expected a record file")
    raise FileNotFoundError(
        f"{name!r} is neither a file nor a bundled record; bundled: {RECORDS.names()}"
    )


def _detect_format(source: str, text: str) -> str:
    suffix = Path(source).suffix.lower()
    if suffix in (".hdf5", ".h5"):
        return "hdf5"
    lines = numbered(text)
    k = at2_header_line(lines)
    if suffix == ".at2" or (k is not None and not is_comment(lines[k][1])):
        return "at2"
    first = next((s for _, s in lines if s), "")
    if first.startswith(";") or re.search(r"sampling\s+rate\s*=", text[:2000], re.I):
        return "jma"
    return "multi-column"


def _split_vertical(vertical) -> tuple[int | str | None, Path | None, float | None]:
    """(column of the same table, another file, ratio) from read_motion's ``vertical``."""
    if vertical is None or vertical is False:
        return None, None, None
    if isinstance(vertical, (int, np.integer)) and not isinstance(vertical, bool):
        return int(vertical), None, None
    if isinstance(vertical, (float, np.floating)):
        return None, None, float(vertical)
    if isinstance(vertical, os.PathLike) or Path(str(vertical)).is_file():
        return None, Path(vertical), None
    return str(vertical), None, None  # a column name


def read_motion(
    path_or_name: str | os.PathLike,
    *,
    fmt: str = "auto",
    units: str | None = None,
    dt: float | None = None,
    column: int | str | None = None,
    vertical: int | str | float | os.PathLike | None = None,
    name: str | None = None,
    trim: bool = False,
) -> GroundMotion:
    """Read a ground motion from a file or by bundled name.

    Parameters
    ----------
    path_or_name : path or str
        A file, or the name of a bundled record (``bundled_records()``), e.g. "synthetic-wn-40s".
    fmt : {"auto", "at2", "jma", "two-column", "single-column", "multi-column"}
        "auto": AT2 if the file has an NPTS/DT header line (or ends in .AT2); JMA if it starts with
        a ``;`` comment or has a "SAMPLING RATE=" line; otherwise a table ("multi-column", which
        also covers one and two columns and the CSV files written by :func:`write_motion`).
    units : {"g", "cm/s2" (gal), "mm/s2", "m/s2"} or None
        Units on file. None: as the header states; if it states none, m/s² with a UnitWarning.
    dt : float, optional
        Sampling interval [s] for files without a time column or header dt.
    column : int or str, optional
        The horizontal column of a table: an index over all the file's columns (time included)
        or a column name. Default: the first acceleration column that is not a vertical one.
    vertical : int, str, float or path, optional
        Vertical component: a column (index or name) of the same table; a float ratio r
        (a_ver = r a_hor); or another file, read with the same ``units`` argument (None: in the
        units its own header states), whose dt, t0 and number of samples must match this
        record's. Default: a table column named a_ver/ver/UD/UP/z, else none.
    name : str, optional
        Record name (default: the header's ``name:`` or the file stem).
    trim : bool
        With a vertical file of another length, cut both to the shorter instead of refusing
        (a station's components often differ by a few samples at the end).

    Raises
    ------
    RecordFileError
        Naming the file, the line and what was expected, for non-numeric rows, NaN/inf,
        non-uniform time, empty files, NPTS mismatch, missing dt, a vertical file on
        another time grid.
    UnitError
        Units it does not know (given, or stated by the header and not given).
    FileNotFoundError
        Neither a file nor a bundled record's name.
    ValueError
        An unknown ``fmt``, a ``dt`` that is no positive number.

    Warns
    -----
    UnitWarning
        Units not stated and not given; units given against the header; PGA outside
        [0.01, 30] m/s² after conversion.
    """
    if not isinstance(path_or_name, str | bytes | os.PathLike):  # (pathlib's TypeError before)
        raise TypeError(f"path_or_name: expected a file path or a bundled record's name, got "
                        f"{type(path_or_name).__name__}")  # fmt: skip
    if fmt not in _FORMATS:
        raise ValueError(f"fmt must be one of {_FORMATS}, got {fmt!r}")
    if isinstance(dt, str | bool):  # (a NaN or a step <= 0 is refused naming the file)
        raise ValueError(f"dt: expected a positive sampling interval [s], got {dt!r}")
    source, text = _resolve(path_or_name)
    kind = _detect_format(source, text) if fmt == "auto" else fmt
    if Path(source).suffix.lower() == ".toml":  # (its first line that is not a number named)
        raise RecordFileError(source, None, "a TOML file (a scene or study?), not a ground-"
                              "motion record; a scene runs as nsdyn run FILE")  # fmt: skip
    if kind == "hdf5":
        raise RecordFileError(
            source,
            None,
            "HDF5 records are not read by nsdyn (it would need h5py and hdf5plugin, which are not "
            "dependencies); export the record to text first",
        )
    in_file_vertical, vertical_file, vertical_ratio = _split_vertical(vertical)
    opt = ReadOptions(units=units, dt=dt, column=column, vertical=in_file_vertical, name=name)
    if kind == "at2":
        if column not in (None, 0) or in_file_vertical is not None:
            key, val = ("column", column) if column not in (None, 0) else \
                ("vertical", in_file_vertical)  # fmt: skip
            raise RecordFileError(source, None, f"{key} = {val!r}: an AT2 file holds one "
                                  "component, no columns (a vertical is another file: "
                                  "vertical=FILE)", key)  # fmt: skip
        motion, unit_name = parse_at2(text, source, opt)
        if dt is not None and abs(dt - motion.dt) > DT_RTOL * motion.dt:
            raise RecordFileError(source, None, f"dt = {dt} given, header states {motion.dt}")
    elif kind == "jma":
        motion, unit_name = parse_jma(text, source, opt)
    else:
        motion, unit_name = parse_table_motion(text, source, kind, opt)
    if motion.n < 2:  # (a time column's file needs two rows; a header's dt took one)
        raise RecordFileError(source, None, "a record of 1 sample spans no time; expected two "
                              "samples or more")  # fmt: skip
    check_pga(motion, units)
    if vertical_ratio is not None:
        return motion.with_vertical(vertical_ratio)
    if vertical_file is None:
        return motion
    other = read_motion(vertical_file, units=units)
    if abs(other.dt - motion.dt) > DT_RTOL * motion.dt:
        raise RecordFileError(
            other.source, None, f"vertical dt = {other.dt:g} s, horizontal dt = {motion.dt:g} s"
        )
    if abs(other.t0 - motion.t0) > DT_RTOL * motion.dt:  # (a shifted vertical ran as if not)
        raise RecordFileError(other.source, None, f"vertical t0 = {other.t0:g} s, horizontal "
                              f"({motion.source}) t0 = {motion.t0:g} s; the components of "
                              "one record start together")  # fmt: skip
    if other.n != motion.n and not trim:  # (the shorter was zero-padded, unsaid)
        raise RecordFileError(other.source, None, f"vertical npts = {other.n}, horizontal "
                              f"({motion.source}) npts = {motion.n}; pass trim=True to cut "
                              "both to the shorter")  # fmt: skip
    m = min(motion.n, other.n)
    cut = {"trimmed_to": m} if m < max(motion.n, other.n) else {}
    return motion._replace(
        a_hor=motion.a_hor[:m],
        a_ver=other.a_hor[:m].copy(),
        meta_update={"vertical_source": other.source, "vertical_n": other.n, **cut},
    )


def _fmt(x: float) -> str:
    return repr(float(x))  # shortest string that reads back to the same float


def write_motion(
    motion: GroundMotion,
    path: str | os.PathLike,
    *,
    command: str | None = None,
    seed: int | str | None = None,
) -> Path:
    """Write ``motion`` as CSV (columns t, a_hor[, a_ver] in m/s²) with a ``#`` header holding
    name, units, t0, dt, npts, command, seed and the JSON meta. Values are written with the
    shortest round-trip repr, so :func:`read_motion` returns them bit for bit. Atomic: written to
    a temporary file in the same directory, then renamed."""
    if not isinstance(motion, GroundMotion):  # (a GroundMotion3 or a pulse: AttributeError)
        raise TypeError(f"motion: expected a GroundMotion, got {type(motion).__name__}"
                        + ("; write_motion3 writes a three-component record"
                           if hasattr(motion, "ax") else ""))  # fmt: skip
    cols = [motion.a_hor] + ([motion.a_ver] if motion.a_ver is not None else [])
    names = ["t", "a_hor", "a_ver"][: len(cols) + 1]
    return _write_table(motion, path, "nsdyn ground motion", names, cols, command, seed)


def _write_table(motion, path, title: str, names: list[str], cols: list, command, seed) -> Path:
    """The nsdyn CSV of ``motion`` (a planar or three-component record): the ``#`` header
    (title, name, units, t0, dt, npts, command, seed, source, JSON meta, column names), then
    t and the columns ``cols`` [m/s²] in their shortest round-trip repr. Atomic."""
    path = Path(path)
    if str(path) in ("", ".") or path.is_dir():  # (an OSError of the temporary file's rename)
        raise IsADirectoryError(f"{path}: a folder; expected the path of a file to write")
    if motion.n < 2:  # (written, then refused by the reader)
        raise ValueError(f"motion: a record of {motion.n} sample; expected at least two (a "
                         "record file's time column needs a step)")  # fmt: skip
    command = command if command is not None else motion.meta.get("command", "")
    seed = seed if seed is not None else motion.meta.get("seed", "")
    meta = {k: v for k, v in motion.meta.items() if k != "header"}
    meta.update(command=command, seed=seed)

    def one_line(v) -> str:  # (a newline in a name began a line of data or of header)
        return " ".join(str(v).splitlines())

    head = [
        title,
        f"name: {one_line(motion.name)}",
        "units: m/s2",
        f"t0: {_fmt(motion.t0)}",
        f"dt: {_fmt(motion.dt)}",
        f"npts: {motion.n}",
        f"command: {one_line(command)}",
        f"seed: {one_line(seed)}",
        f"source: {one_line(motion.source)}",
        f"meta: {json.dumps(meta, default=str, sort_keys=True)}",
        f"columns: {' '.join(names)}",
    ]
    t = motion.t
    # the time stamps to a tenth of a step at least (t0 = 1e7 s at 1 ms repeated its stamps at
    # 10 digits): 10 digits, more as the stamps grow over the step
    span = max(abs(float(t[0])), abs(float(t[-1])))
    digits = min(17, max(10, math.ceil(math.log10(max(span / motion.dt, 1.0))) + 2))
    lines = [f"# {h}" for h in head]
    lines += [",".join([f"{t[k]:.{digits}g}"] + [_fmt(c[k]) for c in cols])
              for k in range(motion.n)]  # fmt: skip
    with atomic_open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write("\n".join(lines) + "\n")
    return path


def read_at2(path: str | os.PathLike, *, units: str | None = None, name: str | None = None):
    """Read a PEER AT2 file (NGA-West2, PEER 1999 or old PEER header). Returns a GroundMotion."""
    return read_motion(path, fmt="at2", units=units, name=name)


def read_two_column(
    path: str | os.PathLike, *, units: str | None = None, dt: float | None = None, name=None
) -> GroundMotion:
    """Two columns ``t a`` (whitespace or commas; ``#``/``%``/``;`` comments). The time column must
    be increasing and uniform (each step within 5 % of the median, each stamp within 1 % of a step
    of the grid); ``dt``, if given, is checked against it."""
    return read_motion(path, fmt="two-column", units=units, dt=dt, name=name)


def read_single_column(
    path: str | os.PathLike, dt: float | None = None, *, units: str | None = None, name=None
) -> GroundMotion:
    """One acceleration value per line; ``dt`` from the argument or the header (``dt = …``)."""
    return read_motion(path, fmt="single-column", units=units, dt=dt, name=name)


def read_multi_column(
    path: str | os.PathLike,
    *,
    column: int | str | None = None,
    vertical: int | str | None = None,
    dt: float | None = None,
    units: str | None = None,
    name: str | None = None,
) -> GroundMotion:
    """Several columns; see :func:`read_motion` for ``column`` and ``vertical``."""
    return read_motion(
        path, fmt="multi-column", units=units, dt=dt, column=column, vertical=vertical, name=name
    )


def read_jma(
    path: str | os.PathLike,
    *,
    units: str | None = None,
    column: int | str | None = None,
    vertical: int | str | None = None,
    name: str | None = None,
) -> GroundMotion:
    """Read a JMA-style text record (``;`` comments + ``dt peak`` line, or JMA CSV)."""
    return read_motion(path, fmt="jma", units=units, column=column, vertical=vertical, name=name)
