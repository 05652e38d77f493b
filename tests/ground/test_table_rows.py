"""Rows of a record table read in one pass and line by line give the same table.

:func:`nsdyn.ground._text.parse_table` reads the rows of the common table (numbers Python's
``float`` reads, finite, as many in every row) in one pass, and any other table line by line
(Fortran exponents, or the line an error names). What must hold, exactly: both readers give
the same values and line numbers for every table the one-pass reader accepts, and these are
the printed numbers (``float(repr(x)) == x``, Python's shortest round-trip repr); a table it
declines is read, or refused with the line, as the line-by-line reader does. The median of a
time column's steps is numpy's (``np.median``: the middle value, or the mean of the middle
two), bit for bit.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from nsdyn.ground._text import _rows, _rows_at_once, median, numbered, parse_table
from nsdyn.ground.motion import RecordFileError

finite = st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False)


def _fmt(x: float, style: str) -> str:
    if style == "repr":
        return repr(x)
    if style == "E":
        return f"{x:.17E}"
    return f"{x:.17e}".replace("e", "D")  # Fortran's exponent: the line-by-line reader's


@st.composite
def tables(draw):
    ncol = draw(st.integers(1, 4))
    values = draw(arrays(float, st.tuples(st.integers(1, 30), st.just(ncol)), elements=finite))
    style = draw(st.sampled_from(["repr", "E", "D"]))
    sep = draw(st.sampled_from([" ", "  ", "\t", ", ", ","]))
    lines = ["# a header line", "t a_hor"] if draw(st.booleans()) else ["% another header"]
    for row in values:
        lines.append(sep.join(_fmt(float(x), style) for x in row))
        extra = draw(st.sampled_from(["", "", "", "blank", "comment"]))
        if extra == "blank":
            lines.append("")
        elif extra == "comment":
            lines.append("# a comment between rows")
    return "\n".join(lines) + "\n", values, style


@settings(max_examples=80, deadline=None)
@given(case=tables())
def test_one_pass_equals_line_by_line(case):
    text, values, style = case
    tab = parse_table(text, "t.txt")
    lines = numbered(text)
    first = next(i for i, (_, s) in enumerate(lines) if s and s[0] in "+-.0123456789")
    slow_data, slow_lines = _rows(lines[first:], "t.txt")
    fast_data, fast_lines = _rows_at_once(lines[first:])
    assert np.array_equal(tab.data, slow_data) and np.array_equal(tab.linenos, slow_lines)
    if style == "D":  # not Python's float: declined, read line by line
        assert fast_data is None
    else:
        assert np.array_equal(fast_data, slow_data) and np.array_equal(fast_lines, slow_lines)
    if style == "repr":  # the shortest repr reads back exactly
        assert np.array_equal(tab.data, values)


@pytest.mark.parametrize(
    ("text", "line", "expected"),
    [
        ("0.0 1.0\n0.1 2.0\n0.2 abc\n", 3, "expected 2 numbers per line"),
        ("0.0 1.0\n0.1 2.0 3.0\n", 2, "expected 2 numbers per line, found 3"),
        ("0.0 1.0\n# note\n0.1 nan\n", 3, "expected a finite number"),
        ("0.0 1.0\n0.1 1e999\n", 2, "expected a finite number"),
    ],
)
def test_a_declined_table_is_refused_with_its_line(text, line, expected):
    lines = numbered(text)
    assert _rows_at_once(lines)[0] is None
    with pytest.raises(RecordFileError) as info:
        parse_table(text, "bad.txt")
    assert info.value.line == line and expected in str(info.value)


@pytest.mark.parametrize(
    ("text", "line", "expected"),
    [  # every row after the names of text: it named the file's last line, "found none"
        ("t,ax\nnp.float64(0.0),np.float64(1.0)\nnp.float64(0.01),np.float64(2.0)\n", 2,
         "expected numbers, found 'np.float64(0.0)' in 'np.float64(0.0),np.float64(1.0)'"),
        ("t,ax\n", 1, "expected numeric data, found none"),  # names alone: none to name
        ("t1 a1 a2\n", 1, "expected numeric data, found none"),  # (names with digits too)
        ("1999-08-17 M7.4 330deg\nt ax ay\nnp.float64(0) np.float64(1) np.float64(2)\n", 3,
         "expected numbers, found 'np.float64(0)'"),  # a title before the names: not named
        ("Kobe NS EW\nt1 a1 a2\nnp.float64(0) np.float64(1) np.float64(2)\n", 3,
         "expected numbers, found 'np.float64(0)'"),  # nor the names line after a title
    ],
)  # fmt: skip
def test_a_table_without_a_row_of_numbers_names_its_first_row(text, line, expected):
    with pytest.raises(RecordFileError) as info:
        parse_table(text, "bad.csv")
    assert info.value.line == line and expected in str(info.value)


def test_the_bundled_record_reads_as_printed():
    """Every number of the bundled default record is the float its digits name."""
    from nsdyn._bundled import RECORDS

    path = RECORDS.find("synthetic-wn-40s")
    text = path.read_text(encoding="latin-1")
    tab = parse_table(text, str(path))
    rows = [ln.split(",") for ln in text.splitlines() if ln and not ln.startswith("#")]
    assert tab.data.shape == (len(rows), len(rows[0]))
    assert np.array_equal(tab.data, np.array([[float(x) for x in r] for r in rows]))


@settings(max_examples=200, deadline=None)
@given(x=arrays(float, st.integers(1, 50), elements=st.floats(-1e300, 1e300)))
def test_median_is_numpys(x):
    assert median(x) == float(np.median(x))
