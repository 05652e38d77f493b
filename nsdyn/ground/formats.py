"""The record file layouts nsdyn reads, each parsed into a :class:`GroundMotion` and its units.

* PEER AT2 (NGA-West2, PEER 1999 and old PEER headers): ``NPTS`` values at step ``DT``;
* tables: one column ü_k (Δt from the header or the caller), two columns (t_k, ü_k), several
  columns (a time column found by name or as an increasing first column; horizontal and
  vertical acceleration columns chosen by index or name) — also the CSV nsdyn writes;
* JMA text: ``;`` comments and a ``dt peak`` line before free-format values, or JMA CSV.

Each sample is converted to m/s² by the factor of the file's units (ü = factor · value).
"""

from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from nsdyn.ground._text import (
    DT_RTOL,
    MILLISECONDS,
    NUM,
    check_time,
    column_index,
    fields,
    header_info,
    is_comment,
    looks_like_time,
    numbered,
    parse_table,
    parse_values,
    strip_comment,
    to_float,
)
from nsdyn.ground.motion import (
    CONFLICT_UNITS,
    G_STANDARD,
    UNITS_HINT,
    UNKNOWN_UNITS,
    GroundMotion,
    RecordFileError,
    UnitError,
    UnitWarning,
    header_units,
    unit_factor,
)

HEADER_SEARCH_LINES = 12  # an AT2 "NPTS, DT" line must lie within the first lines
_TIME_NAMES = {"t", "time", "time_s", "t_s", "time(s)", "t[s]", "t(s)", "time[s]", "sec", "seconds"}
# (az: the name nsdyn.write_motion3 gives the vertical)
_VERTICAL_NAMES = {"a_ver", "ver", "vertical", "ud", "up", "z", "a_z", "az", "vert", "accel_ver"}


@dataclass(frozen=True)
class ReadOptions:
    """What the caller fixed; None leaves it to the file (see :func:`nsdyn.ground.read_motion`)."""

    units: str | None = None  # units on file: "g", "cm/s2" (gal), "m/s2"
    dt: float | None = None  # sampling interval [s]
    column: int | str | None = None  # horizontal column: index over all columns, or a name
    vertical: int | str | None = None  # vertical column of the same table: index or name
    name: str | None = None  # record name


# --------------------------------------------------------------------------------------------
# PEER AT2
# --------------------------------------------------------------------------------------------

_AT2_NGA_NPTS = re.compile(r"NPTS\s*[=:]\s*(\d+)", re.I)
_AT2_NGA_DT = re.compile(rf"\bDT\s*[=:]\s*({NUM})\s*([a-z]*)", re.I)  # (a unit: SEC, MSEC)
_AT2_OLD = re.compile(rf"^\s*(\d+)\s*,?\s+({NUM})\s*,?\s*NPTS\s*,\s*DT", re.I)


def _shuffled_grid(col: np.ndarray, dt: float | None) -> bool:
    """Whether a first column that is not increasing is, sorted, a uniform time grid (of step
    ``dt``, or of any positive step for None): a time column with rows out of order, taken
    for no time column (and, with a ``dt`` given, for the acceleration) otherwise."""
    if col.size < 3 or np.all(np.diff(col) > 0):
        return False
    grid = np.sort(col) - col.min()
    h = grid[-1] / (col.size - 1) if dt is None else dt
    return bool(h > 0 and np.allclose(grid, h * np.arange(col.size), rtol=0.0, atol=1e-6 * h))


G_LIKELY_BELOW = 1.0  # a peak of unstated units under it is likelier in g than in m/s²


def resolve_units(explicit: str | None, stated: str | None, source: str,
                  peak: float | None = None) -> tuple[str, float]:  # fmt: skip
    """``(unit name, factor to m/s²)``: the argument, else the header's, else m/s² (warns;
    a ``peak`` of the file's values under :data:`G_LIKELY_BELOW`, 0.1 g read as m/s², is
    likelier in g: the warning says what the PGA would be in g).
    Units the header states but nsdyn does not know are refused (unless given)."""
    if stated is not None and stated.startswith(CONFLICT_UNITS):
        both = stated.removeprefix(CONFLICT_UNITS)
        if explicit is None:
            raise UnitError(f"{source}: the header states units {both}; expected one (or "
                            f"give them: {UNITS_HINT})")  # fmt: skip
        stated = None  # the argument wins, said when it is neither of the two
        try:
            name = unit_factor(explicit)[0]
        except ValueError as e:
            raise UnitError(str(e)) from None
        if repr(name) not in both:
            warnings.warn(f"{source}: units={explicit!r} given, but the header states {both}; "
                          f"using the given {explicit!r}", UnitWarning, stacklevel=3)  # fmt: skip
    if stated is not None and stated.startswith(UNKNOWN_UNITS):
        word = stated.removeprefix(UNKNOWN_UNITS)
        if explicit is None:
            raise UnitError(
                f"{source}: the header states units {word!r}, which nsdyn does not "
                f"know; expected g, gal (cm/s2), mm/s2 or m/s2 (or give them: {UNITS_HINT})"
            )
        stated = word  # the argument wins, with the warning below
    if explicit is not None:
        try:
            name, factor = unit_factor(explicit)
        except ValueError as e:  # the caller's argument, not the file
            raise UnitError(str(e)) from None
        if stated is not None and stated != name:
            warnings.warn(
                f"{source}: units={explicit!r} given, but the file states {stated!r} (its header "
                f"or column label); using the given {explicit!r}"
                + (f" ({name})" if name != explicit else ""),
                UnitWarning,
                stacklevel=4,
            )
        return name, factor
    if stated is not None:
        return unit_factor(stated)
    in_g = ""
    if peak is not None and 0.0 < peak < G_LIKELY_BELOW:  # (0.349 g read as 0.036 g ran on)
        in_g = (f"; its peak {peak:.4g} m/s² is {peak / G_STANDARD:.3g} g, small for a record: "
                f"if the file is in g, as most strong-motion files are, the PGA is "
                f"{peak * G_STANDARD:.4g} m/s²")  # fmt: skip
    warnings.warn(
        f"{source}: the file does not state its units; assuming m/s² (give them: {UNITS_HINT})"
        + in_g,
        UnitWarning,
        stacklevel=4,
    )
    return "m/s2", 1.0


def _peak(values: np.ndarray) -> float:
    """The largest magnitude of a file's acceleration values (0 for none)."""
    return float(np.abs(values).max()) if values.size else 0.0


def at2_header_line(lines: list[tuple[int, str]]) -> int | None:
    for k, (_, s) in enumerate(lines[:HEADER_SEARCH_LINES]):
        if re.search(r"\bNPTS\b", s, re.I) and re.search(r"\bDT\b", s, re.I):
            return k
    return None


def parse_at2(text: str, source: str, opt: ReadOptions) -> tuple[GroundMotion, str]:
    """PEER AT2. Header: title lines, then one line with NPTS and DT in either layout

    * NGA-West2 / PEER 1999: ``NPTS=  5372, DT=   .0100 SEC,`` (spacing free, also
      hand-edited ``NPTS =   7500 , DT =   .020 SEC ,``);
    * old PEER: ``4096    0.0100    NPTS, DT``;

    then NPTS values, any number per line (E or F format). Units from the header
    ("IN UNITS OF G", "The units are (g)"). The line holding NPTS may be anywhere in the first
    ``HEADER_SEARCH_LINES`` lines; everything before it is header.
    """
    lines = numbered(text)
    k = at2_header_line(lines)
    if k is None:
        raise RecordFileError(
            source,
            1,
            f"expected a PEER AT2 header line with NPTS and DT within the first "
            f"{HEADER_SEARCH_LINES} lines ('NPTS= n, DT= dt SEC' or 'n dt NPTS, DT')",
        )
    lineno, s = lines[k]
    m_n, m_dt = _AT2_NGA_NPTS.search(s), _AT2_NGA_DT.search(s)
    m_old = _AT2_OLD.search(s)
    if m_n and m_dt:
        npts, dt = int(m_n.group(1)), to_float(m_dt.group(1))
        dt *= 1e-3 if m_dt.group(2).lower() in MILLISECONDS else 1.0
    elif m_old:
        npts, dt = int(m_old.group(1)), to_float(m_old.group(2))
    else:
        raise RecordFileError(
            source, lineno, f"expected 'NPTS= n, DT= dt SEC' or 'n dt NPTS, DT', found {s!r}"
        )
    if not dt > 0.0:
        raise RecordFileError(source, lineno, f"expected DT > 0, found {dt}")
    header = [h for _, h in lines[: k + 1]]
    if any(re.search(r"\b(VELOCITY|DISPLACEMENT)\b", h, re.I) for h in header[:4]) and not any(
        re.search(r"\bACCEL", h, re.I) for h in header[:4]
    ):
        raise RecordFileError(source, 1, "expected an acceleration record (header says otherwise)")
    values, last = parse_values(lines[k + 1 :], source)
    if values.size != npts:
        raise RecordFileError(
            source,
            last,
            f"header (line {lineno}) states NPTS = {npts}, found {values.size} values",
        )
    unit_name, factor = resolve_units(opt.units, header_units(header), source, _peak(values))
    title = header[1] if len(header) > 2 else header[0]
    motion = GroundMotion(
        t0=0.0,
        dt=dt,
        a_hor=values * factor,
        name=opt.name or Path(source).stem,
        source=source,
        meta={"format": "at2", "file_units": unit_name, "title": title, "header": header},
    )
    return motion, unit_name


# --------------------------------------------------------------------------------------------
# Tables: single column, two columns (t, a), several columns
# --------------------------------------------------------------------------------------------


def parse_table_motion(
    text: str, source: str, layout: str, opt: ReadOptions
) -> tuple[GroundMotion, str]:
    """layout: "single-column" (a; dt from header or argument), "two-column" (t, a),
    "multi-column" (time column detected by name or as an increasing first column; the rest
    acceleration columns, ``column`` picks the horizontal one — an index counted over all the
    file's columns, or a name — and a column named a_ver/UD/UP/… becomes the vertical one)."""
    tab = parse_table(text, source)
    info = header_info(tab.header)
    data, names = tab.data, tab.names
    n, ncol = data.shape
    first = int(tab.linenos[0])
    if layout == "single-column" and ncol != 1:
        raise RecordFileError(source, first, f"expected 1 column, found {ncol}")
    if layout == "two-column" and ncol != 2:
        raise RecordFileError(source, first, f"expected 2 columns (t, a), found {ncol}")

    tcol: int | None = None
    named_t = [j for j, nm in enumerate(names or ()) if nm in _TIME_NAMES]
    if named_t:  # a column named t or time, wherever it stands
        tcol = named_t[0]
    elif layout == "two-column" or (ncol >= 2 and looks_like_time(data[:, 0])):
        tcol = 0

    if "npts" in info and info["npts"] != n:
        raise RecordFileError(
            source, int(tab.linenos[-1]), f"header states npts = {info['npts']}, found {n} rows"
        )

    if tcol is not None:
        t_unit = tab.units[tcol] if tab.units is not None else None  # "time [ms]"
        t = data[:, tcol] * (1e-3 if t_unit is not None and t_unit.lower() in MILLISECONDS else 1)
        dt_file = check_time(t, tab.linenos, source)
        for label, value in (("header", info.get("dt")), ("given", opt.dt)):
            if value is not None and abs(value - dt_file) > DT_RTOL * dt_file:
                raise RecordFileError(
                    source,
                    first,
                    f"dt = {value:g} s ({label}) but the time column has {dt_file:g} s",
                    argument="dt" if label == "given" else None,
                )
        dt_used = opt.dt if opt.dt is not None else info.get("dt", dt_file)
        t0 = info.get("t0", float(t[0]))
    else:
        dt_used = opt.dt if opt.dt is not None else info.get("dt")
        if opt.dt is not None and not (math.isfinite(opt.dt) and opt.dt > 0):
            raise RecordFileError(source, first, f"dt = {opt.dt!r} (given): expected a positive "
                                  "sampling interval [s]", argument="dt")  # fmt: skip
        if opt.dt is None and dt_used is not None and not (math.isfinite(dt_used) and dt_used > 0):
            raise RecordFileError(source, first, f"expected the header's dt > 0 [s], found "
                                  f"{dt_used:g} (a decimal comma, 'dt = 0,01'?)")  # fmt: skip
        if dt_used is None and ncol >= 2 and data.shape[0] == 1:  # (blamed on "no time column")
            raise RecordFileError(source, first, f"expected at least two samples (rows), found "
                                  f"one: {data[0].tolist()}")  # fmt: skip
        steps = data[1:, 0] - data[:-1, 0] if ncol >= 2 else data[:0, 0]
        rising = steps.size > 0 and data[-1, 0] > data[0, 0] and (steps >= 0).all()
        falling = steps.size >= 2 and (steps < 0).all()  # (it was "no time column")
        if dt_used is None and (rising or falling):  # a time column with a glitch, or one
            check_time(data[:, 0], tab.linenos, source)  # running backwards: its line named
        if dt_used is None and ncol >= 2 and data.shape[0] == 2:  # (also "no time column")
            raise RecordFileError(source, first, "expected at least three samples (rows) to "
                                  "tell a time column, found two (without one, give the step "
                                  "dt)")  # fmt: skip
        if ncol >= 2 and _shuffled_grid(data[:, 0], dt_used):
            check_time(data[:, 0], tab.linenos, source)  # (it was read as the acceleration)
        if dt_used is None:
            raise RecordFileError(
                source,
                first,
                "expected a sampling interval: the file has no time column and its header "
                "states no dt; give the step dt [s] (read_motion(..., dt=...); in a scene, "
                "[motion] dt; or a header line '# dt = 0.01', which every command reads: "
                "nsdyn run --dt is the integrator's step)",
                argument="dt",
            )
        t0 = info.get("t0", 0.0)

    acc_cols = [j for j in range(ncol) if j != tcol]
    if not acc_cols:
        raise RecordFileError(source, first, "expected an acceleration column besides time")
    vcol: int | None = None
    if opt.vertical is not None:
        vcol = column_index(opt.vertical, names, ncol, source, "vertical")
    elif names is not None:
        named = [j for j in acc_cols if names[j] in _VERTICAL_NAMES]
        vcol = named[0] if named else None
    if opt.column is not None:
        hcol = column_index(opt.column, names, ncol, source)
    else:
        hcol = next((j for j in acc_cols if j != vcol), acc_cols[0])
    if hcol == tcol:
        raise RecordFileError(source, first, f"column {hcol} is the time column")

    stated = _stated_units(tab, info.get("units"), hcol, vcol, source, opt.units)
    unit_name, factor = resolve_units(opt.units, stated[0], source, _peak(data[:, hcol]))
    a_ver = None
    if vcol is not None and vcol != hcol:
        same = stated[1] == stated[0]
        a_ver = data[:, vcol] * (factor if same else resolve_units(opt.units, stated[1], source)[1])
    meta: dict[str, Any] = dict(info.get("meta", {}))
    meta.update(
        {
            "format": layout,
            "file_units": unit_name,
            "column": hcol,
            "vertical_column": vcol if a_ver is not None else None,
            # acceleration columns this planar record leaves out (a second horizontal)
            "unused_columns": [
                names[j] if names else j
                for j in acc_cols
                if j != hcol and (a_ver is None or j != vcol)
            ],  # fmt: skip
            "columns": names,
            "header": tab.header,
        }
    )
    if tab.header:
        meta.setdefault("title", tab.header[0])
    for key in ("command", "seed"):
        if key in info:
            meta.setdefault(key, info[key])
    motion = GroundMotion(
        t0=t0,
        dt=dt_used,
        a_hor=data[:, hcol] * factor,
        a_ver=a_ver,
        name=opt.name or info.get("name") or Path(source).stem,
        source=source,
        meta=meta,
    )
    return motion, unit_name


# a bracket's word that is meant as a unit nsdyn does not know (not a label such as "a(t)",
# "acc (N/S)"): a rate per second, a percentage of g, or a length or milli-g
_UNIT_WORDS = {"mg", "ug", "µg", "milli-g", "mgal", "m", "cm", "mm", "in", "ft", "km"}


def _unit_like(word: str) -> bool:
    """A rate per second (in/s2, ft/s^2, m/s/s: a lower-case s, not the N/S of a direction), a
    percentage of g, or one of :data:`_UNIT_WORDS`."""
    rate = re.search(r"/\s*s(ec)?\b|s\^?2\b|s²|%\s*g", word)
    return bool(rate) or word.strip().lower() in _UNIT_WORDS


def _stated_units(tab, header, hcol: int, vcol: int | None, source: str, given) -> tuple:
    """The units the horizontal and the vertical column are in, as the file states them: a
    column's own (``acc [g]``), else the header's, else the other column's; None if none says.
    A bracket that is no acceleration unit (``a(t)``) states none; a column and the header
    stating different units is an error naming both, unless the caller ``given`` units."""
    if given is None and header is not None and header.startswith(CONFLICT_UNITS):
        resolve_units(None, header, source)  # refused: a column's own unit settles nothing
    cols = [hcol] if vcol is None else [hcol, vcol]
    own: list[str | None] = []
    known = header is not None and not header.startswith((UNKNOWN_UNITS, CONFLICT_UNITS))
    for j in cols:
        word = tab.units[j] if tab.units is not None else None
        try:
            own.append(unit_factor(word)[0] if word is not None else None)
        except ValueError:
            # (read as m/s², "units not stated"; under a header's units a label: "acc (E/W)",
            # but a unit-like word is refused there too: "a [mg]" under "units: g" read as g)
            if given is None and _unit_like(word):
                raise UnitError(f"{source}: column {tab.names[j]!r} states units {word!r}, "
                                "which nsdyn does not know; expected g, gal (cm/s2), mm/s2 or "
                                f"m/s2 (or give them: {UNITS_HINT})") from None  # fmt: skip
            own.append(None)
        if given is None and known and own[-1] is not None and own[-1] != header:
            raise RecordFileError(source, None, f"column {tab.names[j]!r} states units "
                                  f"{tab.units[j]!r} but the header states {header!r}; "
                                  f"give the units ({UNITS_HINT})")  # fmt: skip
    fallback = next((u for u in own if u is not None), None) if header is None else header
    stated = tuple(u if u is not None else fallback for u in own)
    return stated if vcol is not None else (stated[0], None)


# --------------------------------------------------------------------------------------------
# JMA-style text
# --------------------------------------------------------------------------------------------


def parse_jma(text: str, source: str, opt: ReadOptions) -> tuple[GroundMotion, str]:
    """Two JMA-style layouts.

    * ``;``-comment layout (the JMA Kobe NS file of Mechanics_Apps): ``;`` comment lines (units
      "acc. in cm/s/s", "dt=0.02"), then one line ``dt peak`` (the peak is nominal and only kept
      in meta), then the values, any number per line.
    * JMA CSV: ``KEY = value`` header lines (``SAMPLING RATE= 100Hz``, ``UNIT = gal``), a
      ``NS,EW,UD`` names line, then comma-separated columns. Read as a table; UD is the vertical.
    """
    lines = numbered(text)
    body = [(i, s) for i, s in lines if s and not is_comment(s)]
    first = next((s for _, s in lines if s), "")
    if not first.startswith(";"):
        return parse_table_motion(text, source, "multi-column", opt)
    header = [strip_comment(s) for _, s in lines if s.startswith(";")]
    if not body:
        raise RecordFileError(source, len(lines), "expected a 'dt peak' line and data, found none")
    lineno, s = body[0]
    toks = fields(s)
    try:
        dt_line, peak = (to_float(x) for x in toks)
    except ValueError:
        raise RecordFileError(
            source, lineno, f"expected 'dt peak' (two numbers), found {s!r}"
        ) from None
    if not dt_line > 0.0:
        raise RecordFileError(source, lineno, f"expected dt > 0, found {dt_line}")
    stated_dt = header_info(header).get("dt")
    if stated_dt is not None and abs(stated_dt - dt_line) > DT_RTOL * dt_line:
        raise RecordFileError(
            source, lineno, f"dt = {dt_line:g} s here but the comment says dt = {stated_dt:g} s"
        )
    values, _ = parse_values(body[1:], source)
    if values.size == 0:
        raise RecordFileError(source, lineno, "expected acceleration values after 'dt peak'")
    unit_name, factor = resolve_units(opt.units, header_units(header), source, _peak(values))
    motion = GroundMotion(
        t0=0.0,
        dt=opt.dt if opt.dt is not None else dt_line,
        a_hor=values * factor,
        name=opt.name or Path(source).stem,
        source=source,
        meta={
            "format": "jma",
            "file_units": unit_name,
            "nominal_peak": peak,
            "title": header[0] if header else "",
            "header": header,
        },
    )
    return motion, unit_name


def unused_columns_note(motion, remedy: str) -> str | None:
    """One line naming a record file's acceleration columns the reader left out (a second
    horizontal component, in ``meta["unused_columns"]``) and the columns taken, with the
    model's ``remedy``; None when every column is used."""
    meta = getattr(motion, "meta", None) or {}
    left = meta.get("unused_columns") or []
    if not left:
        return None
    names = meta.get("columns")
    vertical = meta.get("vertical_column") if getattr(motion, "a_ver", None) is not None else None
    took = [names[j] if names else j for j in (meta.get("column"), vertical) if j is not None]
    return (f"the record's column(s) {', '.join(map(repr, left))} not used: the run takes "
            f"{', '.join(map(repr, took))} ({remedy})")  # fmt: skip


def record_span_notes(t_eval, first: float, last: float, dt: float,
                      force: bool = False) -> list[str]:  # fmt: skip
    """Notes of a run over output times ``t_eval`` outside its record's samples, from
    ``first`` to ``last`` [s] every ``dt`` (``force``: a sampled force's): the ground is at
    rest (the force zero) before the first sample and after the last, which a run takes as
    it is told but should say."""
    what, rest = (
        ("force table", "the force is zero") if force else ("record", "the ground is at rest")
    )
    if t_eval[0] > last + dt or t_eval[-1] < first - 1e-9 * dt:  # (none of it is felt)
        raise ValueError(f"t_eval: the run's times ({t_eval[0]:g} to {t_eval[-1]:g} s) do not "
                         f"overlap the {what}'s samples ({first:g} to {last:g} s): it would feel "
                         "none of it; expected output times within them")  # fmt: skip
    notes = []
    if t_eval[0] < first - 1e-9 * dt:
        notes.append(f"the run starts at t = {t_eval[0]:g} s, before the {what}'s first "
                     f"sample ({first:g} s): {rest} before it")  # fmt: skip
    if t_eval[-1] > last + dt:  # (within one sample: the record's own end)
        free = f"the last {t_eval[-1] - max(last, t_eval[0]):.4g} s are free motion"
        notes.append(f"the run ends at t = {t_eval[-1]:g} s, past the {what}'s end ({last:g} "
                     f"s): {rest} after it, {free}")  # fmt: skip
    return notes


def between_samples_note(t_end: float, last: float, dt: float) -> str | None:
    """One line for a run cut at its record's ``last`` sample before ``t_end``, which falls
    within one sampling step ``dt`` after it (not a sample time); None otherwise (a ``t_end``
    further past the record is :func:`past_record_note`'s)."""
    if not 1e-9 * dt < t_end - last < dt * (1 + 1e-9):
        return None
    return (f"t_end = {t_end:g} s is not a sample time of the record (every {dt:g} s); the run "
            f"ends at its last sample before it, {last:g} s")  # fmt: skip


def early_record_note(first: float, start: float, how: str) -> str | None:
    """One line for a record whose first sample (``first`` [s]) comes before the run's
    ``start``: that part is not felt; ``how`` says what starts the run with it. None when the
    record starts at or after the run."""
    if not first < start - 1e-12 * max(1.0, abs(start)):
        return None
    return (f"the record starts at t = {first:g} s, before the run's start at {start:g} s: its "
            f"first {start - first:.4g} s are not felt ({how})")  # fmt: skip


def past_record_note(t_end: float, end: float, runs_on: bool = True,
                     what: str = "record") -> str | None:  # fmt: skip
    """One line for a run whose ``t_end`` is past the end of its record (or other
    excitation, ``what``); None when it ends within it. ``runs_on``: the ground is at rest
    after it and the rest of the run is free motion (rocking, contact, cylinder), else the
    run ends there (the isolated frames, decks and buildings)."""
    if not t_end > end * (1 + 1e-9) + 1e-12:
        return None
    head = f"t_end = {t_end:g} s is past the {what}'s end ({end:g} s)"
    if not runs_on:
        return f"{head}; the run ends there"
    return f"{head}: the ground is at rest after it, the last {t_end - end:.4g} s are free motion"
