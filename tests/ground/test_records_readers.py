"""Reading and writing ground-motion files: AT2, tables, JMA, bad files, units, round trip.

Expected values are the numbers written into each test file (exact up to the stated unit
factor), or exact identities (a written record reads back bit for bit).
"""

import dataclasses
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from nsdyn.ground import (
    G_STANDARD,
    RecordFileError,
    UnitWarning,
    modulated_white_noise,
    read_at2,
    read_jma,
    read_motion,
    read_multi_column,
    read_single_column,
    read_two_column,
    write_motion,
)
from nsdyn.ground.motion import UnitError


def write(tmp_path: Path, name: str, text: str, newline: str = "\n") -> Path:
    path = tmp_path / name
    path.write_bytes(text.replace("\n", newline).encode("latin-1"))
    return path


# ------------------------------------------------------------------------------------------
# Readers
# ------------------------------------------------------------------------------------------

AT2_VALUES = np.array([0.1, -0.2, 0.3, -0.4, 0.5, 0.25, -0.125])


def at2_body(fmt: str = "{:15.7E}", per_line: int = 5) -> str:
    vals = [fmt.format(v) for v in AT2_VALUES]
    return "\n".join("".join(vals[i : i + per_line]) for i in range(0, len(vals), per_line))


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
@pytest.mark.parametrize(
    ("header", "newline"),
    [
        # NGA-West2: NPTS=, DT= ... SEC, trailing comma and blanks, CRLF
        (
            "PEER NGA STRONG MOTION DATABASE RECORD\nTest, 1/1/2000, STA, 0\n"
            "ACCELERATION TIME SERIES IN UNITS OF G\n"
            "NPTS=      7, DT=   .0100 SEC,                          ",
            "\r\n",
        ),
        # hand-edited spacing, as in KJM000/KJM090 of PROVENANCE.md
        (
            "PEER NGA STRONG MOTION DATABASE RECORD\nKobe Japan, 1/16/1995, KJMA, 0\n"
            "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS =   7 , DT =   .010 SEC ,    ",
            "\n",
        ),
        # PEER 1999
        (
            "PEER STRONG MOTION DATABASE RECORD. PROCESSING BY PACIFIC ENGINEERING.\n"
            "IMPERIAL VALLEY 5/19/40 0439, EL CENTRO ARRAY #9, 180\n"
            "ACCELERATION TIME HISTORY IN UNITS OF G. FILTER POINTS: HP=0.2 Hz LP=15.0 Hz\n"
            "NPTS=     7, DT= .01000 SEC",
            "\n",
        ),
        # old PEER: numbers before the labels
        (
            "PEER NGA STRONG MOTION DATABASE RECORD\nKOBE 01/16/95 2046, NISHI-AKASHI, 090\n"
            "ACCELERATION TIME HISTORY IN UNITS OF G\n7    0.0100    NPTS, DT",
            "\n",
        ),
        # OpenSees "Peknold" variant: 3 free-text lines, 8F10.5 values
        (
            "Data for El Centro 1940 North South Component (Peknold Version)\n"
            "7 points at equal spacing of 0.01 sec\nThe units are (g)\nNPTS=     7, DT= .01000 SEC",
            "\n",
        ),
    ],
)
def test_at2_header_variants(tmp_path, header, newline):
    path = write(tmp_path, "rec.AT2", header + "\n" + at2_body() + "\n", newline)
    m = read_at2(path)
    assert m.n == 7 and m.dt == 0.01 and m.t0 == 0.0
    assert m.meta["file_units"] == "g"
    np.testing.assert_allclose(m.a_hor, AT2_VALUES * G_STANDARD, rtol=1e-15)
    assert read_motion(path).a_hor.tobytes() == m.a_hor.tobytes()  # auto detects AT2


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
def test_at2_fixed_width_fields_that_run_together(tmp_path):
    # 8F10.5 with values of 10 characters: "-0.12345-0.23456" has no blank between the fields
    text = (
        "title\nname\nUNITS OF G\nNPTS=  4, DT= 0.02 SEC\n  -0.12345-0.23456   0.34567   1.00000\n"
    )
    m = read_motion(write(tmp_path, "ff.at2", text), units="g")
    np.testing.assert_allclose(m.a_hor / G_STANDARD, [-0.12345, -0.23456, 0.34567, 1.0], rtol=1e-15)


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
def test_two_column(tmp_path):
    t = 2.5 + 0.02 * np.arange(6)
    a = np.array([0.0, 0.1, -0.2, 0.15, -0.05, 0.0])
    text = "".join(f"{ti:.4f}\t{ai:.6e}\n" for ti, ai in zip(t, a, strict=True))
    m = read_two_column(write(tmp_path, "tc.dat", text), units="g")
    assert (m.n, m.dt, m.t0) == (6, 0.02, 2.5)
    np.testing.assert_allclose(m.a_hor, a * G_STANDARD, rtol=1e-15)
    np.testing.assert_allclose(m.t, t, rtol=0, atol=1e-12)


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
@pytest.mark.parametrize(
    ("header", "dt"),
    [("dt = 10 ms", 0.01), ("dt: 5 msec", 0.005), ("dt = 0.02 s", 0.02), ("DT= .0050 SEC", 0.005),
     ("dt = 0.01", 0.01), ("dt = 20 (ms); npts = 3", 0.02), ("dt = 0.005 npts = 3", 0.005),
     ("dt = 0.01\n# Ms 7.1 (surface-wave magnitude)", 0.01)],  # a unit is on dt's own line
)  # fmt: skip
def test_a_header_dt_in_milliseconds_is_scaled(tmp_path, header, dt):
    # "dt = 10 ms" was read as 10 s (a 5000 s record from 500 samples)
    path = write(tmp_path, "ms.txt", f"# {header}\n0.5\n-1.5\n2.0\n")
    assert read_motion(path, units="m/s2").dt == dt


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
@pytest.mark.parametrize("codec", ["utf-8-sig", "utf-16", "utf-16-be", "utf-32"])
@pytest.mark.parametrize("header", ["", '"time","az","ax"\n'])
def test_a_byte_order_mark_or_quoted_names_change_no_sample(tmp_path, codec, header):
    # a UTF-8 mark made the first row a header (a sample lost), a UTF-16 file read as "no
    # numeric data", a quoted name was no name (az read as the horizontal): every sample,
    # and the named columns, as in the plain file
    t = 0.01 * np.arange(5)
    a = np.array([0.05, 0.0876, -0.12461, 0.3, 0.0])
    rows = "".join(f"{ti:.2f},{0.2 * ai:.6f},{ai:.6f}\n" for ti, ai in zip(t, a, strict=True))
    plain = tmp_path / "plain.csv"
    plain.write_text(header + rows)
    path = tmp_path / f"rec-{codec}.csv"
    path.write_bytes((header + rows).encode(codec))  # (utf-16-be: no mark; utf-16: a mark)
    if codec == "utf-16-be":
        with pytest.raises(RecordFileError, match="UTF-16 text without a byte-order mark"):
            read_motion(path, units="m/s2")  # (no mark: said as such, not "no numeric data")
        return
    m, ref = read_motion(path, units="m/s2"), read_motion(plain, units="m/s2")
    assert (m.n, m.t0, m.dt) == (5, 0.0, 0.01)
    np.testing.assert_array_equal(m.a_hor, a if header else ref.a_hor)
    if header:
        np.testing.assert_array_equal(m.a_ver, np.round(0.2 * a, 6))


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
@pytest.mark.parametrize(
    ("names", "factor", "v_factor", "t_scale"),
    [("time acc [g]", G_STANDARD, None, 1), ("Time (s), Acceleration (g)", G_STANDARD, None, 1),
     ("t(s) a(g)", G_STANDARD, None, 1), ("time,acc(cm/s2)", 0.01, None, 1),
     ("t [s]\ta [m/s^2]", 1.0, None, 1), ("time [ms] acc [gal]", 0.01, None, 1e-3),
     ("time acc [m/s2] ud [g]", 1.0, G_STANDARD, 1), ("time acc [g] ud", G_STANDARD, G_STANDARD, 1),
     ("# units: gal\ntime acc ud", 0.01, 0.01, 1),
     # a label after a column's unit (it was read as m/s², "units not stated")
     ("t [s], a [g] NS", G_STANDARD, None, 1), ("time (s) acc (g) (E-W)", G_STANDARD, None, 1)],
)  # fmt: skip
def test_units_in_the_column_names_are_read(tmp_path, names, factor, v_factor, t_scale):
    # "time acc [g]" was read as m/s² (a record 9.8 times too weak) with "units not stated"
    vals = np.array([0.5, -1.25, 3.0]) / factor  # written in the column's units (3 m/s² peak)
    ver = "" if v_factor is None else f" {1.5 / v_factor!r}"
    rows = "".join(f"{k / t_scale * 0.01:g} {float(v)!r}{ver}\n" for k, v in enumerate(vals))
    m = read_motion(write(tmp_path, "named.txt", f"{names}\n{rows}"))
    assert m.dt == pytest.approx(0.01, rel=1e-12)  # (time in ms scaled)
    np.testing.assert_allclose(m.a_hor, vals * factor, rtol=1e-15)  # (the one product)
    np.testing.assert_allclose(m.a_hor, [0.5, -1.25, 3.0], rtol=1e-15)  # (two roundings)
    if v_factor is not None:
        np.testing.assert_allclose(m.a_ver, 1.5, rtol=1e-15)


def test_a_name_with_a_slash_is_still_a_column_name(tmp_path):
    # "acc/g" is no name with a unit in brackets: it stays the column's name, as it was
    path = write(tmp_path, "slash.txt", "time acc/g ud\n0 0.5 0.1\n0.01 -0.5 0.2\n0.02 0.25 0.3\n")
    m = read_motion(path, units="m/s2", column="acc/g")
    assert m.meta["columns"] == ["time", "acc/g", "ud"] and m.a_hor.tolist() == [0.5, -0.5, 0.25]


def test_units_of_a_column_against_the_header_are_refused_unless_given(tmp_path):
    path = write(tmp_path, "both.txt", "# units: g\ntime acc [gal]\n0 50\n0.01 -50\n")
    with pytest.raises(RecordFileError, match=r"column 'acc' states units 'gal' but the header "
                       r"states 'g'; give the units"):  # fmt: skip
        read_motion(path)
    assert read_motion(path, units="gal").a_hor[0] == 0.5  # (the column's, given)
    assert read_motion(path, units="gal", column="acc [gal]").a_hor[0] == 0.5  # (its name)


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
def test_an_at2_step_in_milliseconds_is_scaled(tmp_path):
    # "DT = 20 MSEC" was read as 20 s (a 150 000 s record)
    head = "title\nname\nUNITS OF G\nNPTS =   7 , DT =   10 MSEC\n"
    m = read_at2(write(tmp_path, "ms.AT2", head + at2_body() + "\n"), units="g")
    assert m.dt == 0.01 and m.n == 7


def test_a_step_of_seconds_asks_whether_the_times_are_milliseconds(tmp_path):
    # a time column 0, 10, 20, ... (ms) read as a 10 s step, without a word
    path = write(tmp_path, "ms.txt", "".join(f"{10 * k} {0.1 * k}\n" for k in range(5)))
    with pytest.warns(UnitWarning, match=r"a sampling step of 10 s > 0\.2 s .* milliseconds"):
        read_motion(path, units="m/s2")
    with warnings.catch_warnings():  # the bound itself: no word
        warnings.simplefilter("error", UnitWarning)
        read_motion(write(tmp_path, "s.txt", "0 0.1\n0.2 0.2\n0.4 0.0\n"), units="m/s2")


def test_single_column_with_dt(tmp_path):
    path = write(tmp_path, "sc.txt", "# acc in m/s2\n0.5\n-1.5\n2.0\n")
    m = read_single_column(path, dt=0.005, units="m/s2")
    assert (m.n, m.dt) == (3, 0.005)
    np.testing.assert_array_equal(m.a_hor, [0.5, -1.5, 2.0])
    with pytest.raises(RecordFileError, match=r"give the step dt \[s\]"):
        read_single_column(path, units="m/s2")


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
def test_multi_column_choose_column_and_header_dt_units(tmp_path):
    # the layout of the benchmark files: % comments, dt and units in the text, no time column
    text = (
        "%1995 Kobe. First column NS, second EW, third UD.\n"
        "% Acc. in cm/sec^2 and dt=0.005 sec.\n"
        "1.0E+00\t\t-2.0E+00\t3.0E-01\n4.0E+00\t\t5.0E+00\t-6.0E-01\n0\t\t0\t0\n"
    )
    path = write(tmp_path, "mc.txt", text, "\r\n")
    m0 = read_motion(path)
    assert (m0.n, m0.dt, m0.meta["file_units"]) == (3, 0.005, "cm/s2")
    np.testing.assert_allclose(m0.a_hor, [0.01, 0.04, 0.0], rtol=1e-15)
    assert m0.a_ver is None
    m1 = read_multi_column(path, column=1, vertical=2)
    np.testing.assert_allclose(m1.a_hor, [-0.02, 0.05, 0.0], rtol=1e-15)
    np.testing.assert_allclose(m1.a_ver, [0.003, -0.006, 0.0], rtol=1e-15)


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
def test_multi_column_with_time_and_names(tmp_path):
    text = "t,a_x,a_y,a_ver\n0.0,1,2,3\n0.1,4,5,6\n0.2,7,8,9\n"
    path = write(tmp_path, "named.csv", text)
    m = read_motion(path, units="m/s2", column="a_y")
    assert m.dt == 0.1
    np.testing.assert_array_equal(m.a_hor, [2, 5, 8])
    np.testing.assert_array_equal(m.a_ver, [3, 6, 9])  # a column named a_ver is the vertical


def test_a_column_name_on_a_file_without_names_says_so(tmp_path):
    path = write(tmp_path, "bare.csv", "0.0,1,2\n0.1,4,5\n0.2,7,8\n")
    with pytest.raises(RecordFileError, match=r"the file names no columns: give an index 0\.\.2"):
        read_motion(path, units="m/s2", column="a_y")


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
def test_jma_semicolon_layout(tmp_path):
    # the layout of raw/kobe_jma_ns_gal_tum.txt: ';' comments, 'dt peak' line, 5 values per line
    text = (
        ";Recorded at Kobe station, dt=0.02, time window = 60s, acc. in cm/s/s\n"
        ";NS  component, Peak given in unit [g]\n0.02 0.50\n"
        " -0.3289795     -0.3588867     -0.4187012     -0.3588867     -100.0\n"
        "  250.5      -1.0\n"
    )
    m = read_jma(write(tmp_path, "KOBE_NS", text))
    assert (m.n, m.dt, m.meta["file_units"], m.meta["nominal_peak"]) == (7, 0.02, "cm/s2", 0.5)
    assert m.pga == pytest.approx(2.505, rel=1e-15)  # 250.5 gal; "unit [g]" is the peak's unit


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
def test_jma_csv_layout(tmp_path):
    # JMA's CSV: KEY= value header, NS,EW,UD names, comma-separated columns
    text = (
        " SITE CODE= 6A0\n LAT.=   34.68\n LON.=  135.18\n SAMPLING RATE= 100Hz\n UNIT  = gal\n"
        " INITIAL TIME = 1995 01 17 05 46 48\n NS,EW,UD\n  -0.5,  1.0,  0.25\n"
        "  100.0, -200.0, 50.0\n  0.0, 0.0, 0.0\n"
    )
    m = read_motion(write(tmp_path, "jma.csv", text))
    assert (m.n, m.dt, m.meta["format"]) == (3, 0.01, "multi-column")
    np.testing.assert_allclose(m.a_hor, [-0.005, 1.0, 0.0], rtol=1e-15)
    np.testing.assert_allclose(m.a_ver, [0.0025, 0.5, 0.0], rtol=1e-15)
    np.testing.assert_allclose(read_motion(m.source, column="EW").a_hor, [0.01, -2.0, 0.0])


# ------------------------------------------------------------------------------------------
# Bad files: RecordFileError names the file and the line
# ------------------------------------------------------------------------------------------

AT2_HEAD = "PEER NGA\nX, 0\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    4, DT= .0100 SEC\n"


@pytest.mark.parametrize(
    ("name", "text", "line", "expected"),
    [
        ("nonnum.txt", "0.0 1.0\n0.1 2.0\n0.2 abc\n", 3, "expected 2 numbers"),
        ("nan.txt", "# dt = 0.01\n1.0\nnan\n2.0\n", 3, "finite"),
        ("inf.txt", "0.0 1.0\n0.1 inf\n", 2, "finite"),
        # 1e300 passed the file and failed as "a_hor: ... sample 2", no file, no line
        ("huge.txt", "0.0 1.0\n0.1 2.0\n0.2 1e300\n0.3 1.0\n", 3, "magnitude at most 1e+12"),
        ("hugecol.txt", "# dt = 0.01\n1.0\n-2e13\n2.0\n", 3, "magnitude at most 1e+12"),
        ("cols.txt", "0.0 1.0\n0.1 2.0 3.0\n", 2, "expected 2 numbers"),
        ("gap.txt", "0.00 1\n0.01 2\n0.02 3\n0.04 4\n0.05 5\n", 4, "uniform time step"),
        ("back.txt", "0.00 1\n0.01 2\n0.02 3\n0.015 4\n0.03 5\n0.04 6\n", 4, "expected time >"),
        ("empty.txt", "# only a header\n\n", 2, "expected numeric data"),
        ("short.AT2", AT2_HEAD + "  .1E-01  .2E-01  .3E-01\n", 5, "NPTS = 4, found 3"),
        ("nohdr.AT2", "a\nb\nc\n.1 .2\n", 1, "NPTS and DT"),
        ("badat2.AT2", AT2_HEAD + "  .1E-01  .2E-01\n  .3E-01  x.4\n", 6, "expected numbers"),
        ("npts.txt", "# units: g; dt = 0.01 s; npts = 5\n0.0 1\n0.01 2\n0.02 3\n", 4, "npts = 5"),
        ("comma.txt", "# units: g\n0,00\t0,00000\n0,01\t0,02440\n", 2, "decimal commas in"),
        ("semi.txt", "0,00;-1,5E-02\n0,01;2,0E-02\n", 1, "expected decimal points"),
        ("dtc.txt", "# dt = 0,01\n0.1\n0.2\n-0.1\n", 2, "a decimal comma, 'dt = 0,01'?"),
        # a time column running backwards, one or two rows: all were "the file has no time column"
        ("down.txt", "0.02 1\n0.01 2\n0.00 3\n", 2, "expected time > 0.02 s, found 0.01 s"),
        ("one.txt", "0.0 0.1\n", 1, "expected at least two samples (rows), found one"),
        ("two.txt", "0.0 0.1\n0.01 0.2\n", 1, "at least three samples (rows) to tell a time"),
        # two rows swapped in a short file: "no time column", and with the dt it asked for
        # the time column was read as the acceleration
        ("swap.txt", "0.0 0.1\n0.02 0.2\n0.01 0.3\n0.03 0.1\n", 3,
         "expected time > 0.02 s, found 0.01 s"),
    ],
)  # fmt: skip
def test_bad_files_raise_with_line(tmp_path, name, text, line, expected):
    path = write(tmp_path, name, text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnitWarning)
        with pytest.raises(RecordFileError) as info:
            read_motion(path, units="g")
    err = info.value
    assert err.line == line and expected in str(err)
    assert str(err).startswith(f"{path}:{line}: ")


@pytest.mark.parametrize(("hz", "decimals"), [(300, 4), (600, 5), (30, 3)])
def test_times_rounded_as_printed_are_a_uniform_grid(tmp_path, hz, decimals):
    # k/300 s printed to 4 decimals is off its grid by up to half of 1e-4 (1.5 % of a step),
    # and the grid fitted through the rounded first and last stamps by up to half more: the
    # file was refused for a stamp 1 % of a step off. dt comes back within a last place
    # over the span (the fit's end points), the samples unchanged
    n = 400
    a = np.sin(np.arange(n) / 7.0)
    text = "".join(f"{k / hz:.{decimals}f} {float(v)!r}\n" for k, v in enumerate(a))
    m = read_motion(write(tmp_path, "r.txt", text), units="m/s2")
    assert m.n == n and np.array_equal(m.a_hor, a)
    assert abs(m.dt - 1.0 / hz) <= 10.0**-decimals / (n - 1)
    short = "".join(f"{k / hz:.{decimals}f} 1.0\n" for k in range(6))  # (a short file too)
    assert read_motion(write(tmp_path, "s.txt", short), units="m/s2").n == 6
    # a printed place as coarse as the step is the grid itself: a missing row is still refused
    gap = "".join(f"{k / 100:.2f} 1.0\n" for k in range(50) if k != 20)
    with pytest.raises(RecordFileError, match=r"r2.txt:21: expected a uniform time step 0.01 s"):
        read_motion(write(tmp_path, "r2.txt", gap), units="m/s2")


@pytest.mark.parametrize(("hz", "decimals"), [(100, 3), (1000, 4), (300, 4)])
def test_a_stamp_off_its_grid_by_a_tenth_of_a_step_is_refused(tmp_path, hz, decimals):
    # a step that is a whole number of printed places (100 Hz as 0.010) was never rounded:
    # one stamp a tenth of a step off (0.201 among 0.190, 0.210) is jitter, refused as before;
    # at 300 Hz the rounding allows one place, 3 % of a step, not a tenth
    t = np.arange(60) / hz
    t[20] += 0.1 / hz
    text = "".join(f"{v:.{decimals}f} 1.0\n" for v in t)
    with pytest.raises(RecordFileError, match=r"j.txt:2[01]: expected a uniform time step"):
        read_motion(write(tmp_path, "j.txt", text), units="m/s2")


def test_a_shuffled_time_column_is_named_with_the_step_given_too(tmp_path):
    path = write(tmp_path, "swap.txt", "0.0 0.1\n0.02 0.2\n0.01 0.3\n0.03 0.1\n")
    with pytest.raises(RecordFileError, match=r"swap.txt:3: expected time > 0.02 s"):
        read_motion(path, units="g", dt=0.01)


def test_two_column_format_requires_time(tmp_path):
    path = write(tmp_path, "x.txt", "1.0 0.5\n0.5 0.1\n2.0 0.3\n")
    with pytest.raises(RecordFileError, match=r"x.txt:2: expected time >"):
        read_two_column(path, units="g")


def test_missing_file_names_bundled():
    with pytest.raises(FileNotFoundError, match="bundled"):
        read_motion("no-such-record")


# ------------------------------------------------------------------------------------------
# Units
# ------------------------------------------------------------------------------------------


def test_unit_warnings(tmp_path):
    gal = write(tmp_path, "gal.txt", "0.0 500.0\n0.01 -300.0\n0.02 0.0\n")  # a record in cm/s²
    with pytest.warns(UnitWarning, match="does not state its units"):
        with pytest.warns(UnitWarning, match="probably in cm/s"):
            read_motion(gal)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = read_motion(gal, units="gal")
    assert m.pga == pytest.approx(5.0, rel=1e-15)
    tiny = write(tmp_path, "g.txt", "0.0 0.004\n0.01 -0.003\n0.02 0.0\n")  # 0.004 g as m/s²
    with pytest.warns(UnitWarning, match="probably in g, read as 'm/s2'"):
        read_motion(tiny, units="m/s2")
    # read as gal, a file in m/s² is 100x too small: larger units are likelier, not g alone
    ms2 = write(tmp_path, "ms2.txt", "0.0 0.5\n0.01 -0.3\n0.02 0.0\n")
    with pytest.warns(UnitWarning, match=r"probably in m/s² or g, read as 'gal'"):
        read_motion(ms2, units="gal")
    with pytest.warns(UnitWarning, match=r"probably in cm/s² \(gal\) or m/s², read as 'g'"):
        read_motion(gal, units="g")
    stated = write(tmp_path, "s.txt", "# units: g\n0.0 0.3\n0.01 -0.2\n0.02 0.1\n")
    with pytest.warns(UnitWarning, match="the file states 'g'"):
        read_motion(stated, units="m/s2")
    # a "units:" line nsdyn cannot read is refused, naming the file and the word (it was read
    # as m/s² with "the file does not state its units"); given units win, with the warning
    odd = write(tmp_path, "odd.txt", "# units: furlongs\n0.0 0.3\n0.01 -0.2\n0.02 0.1\n")
    with pytest.raises(UnitError, match=r"odd.txt: the header states units 'furlongs'"):
        read_motion(odd)
    with pytest.warns(UnitWarning, match="the file states 'furlongs' .*; using the given 'g'$"):
        assert read_motion(odd, units="g").pga == pytest.approx(0.3 * 9.80665)
    # an alias given is the one named (it read "units='gal' given ...; using 'cm/s2'")
    said = r"states 'g' \(its header or column label\); using the given 'gal' \(cm/s2\)$"
    with pytest.warns(UnitWarning, match=said):
        assert read_motion(stated, units="gal").pga == pytest.approx(0.3e-2)
    # a line that is not a units line ("time units: s") is not read as one
    timed = write(tmp_path, "tu.txt", "# time units: s\n0.0 0.3\n0.01 -0.2\n0.02 0.1\n")
    with pytest.warns(UnitWarning, match="does not state its units"):
        assert read_motion(timed).pga == 0.3


# ------------------------------------------------------------------------------------------
# Writing, bundled records
# ------------------------------------------------------------------------------------------


@pytest.mark.filterwarnings("error::UserWarning")  # no UnitWarning either
@pytest.mark.parametrize("vertical", [True, False])
def test_write_read_roundtrip_exact(tmp_path, vertical):
    m = modulated_white_noise(5.0, seed=3, vertical_ratio=2 / 3 if vertical else None)
    m = dataclasses.replace(m.scaled_to_pga(3.0).window(1.234, 4.5), name="rt")
    path = write_motion(m, tmp_path / "rt.csv", command="pytest", seed=3)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rt.csv"]  # no temp file left
    r = read_motion(path)
    assert (r.name, r.t0, r.dt, r.n) == (m.name, m.t0, m.dt, m.n)
    assert r.a_hor.tobytes() == m.a_hor.tobytes()
    assert (r.a_ver is None) == (not vertical)
    if vertical:
        assert r.a_ver.tobytes() == m.a_ver.tobytes()
    assert r.meta["seed"] == 3 and r.meta["command"] == "pytest"
    assert r.meta["scale_factor"] == m.meta["scale_factor"]


def test_a_scene_given_as_a_record_is_named_as_such(tmp_path):
    # `--record scene.toml` read the TOML as a table: "FILE:LINE: expected numeric data"
    scene = write(tmp_path, "s.toml", '[scene]\nkind = "deck"\n')
    with pytest.raises(RecordFileError, match=r"s\.toml: a TOML file \(a scene or study\?\), "
                                              r"not a ground-motion record"):  # fmt: skip
        read_motion(scene)


def test_a_row_with_a_trailing_comment_is_a_row_and_one_with_text_is_refused(tmp_path):
    # "0,0.1 # first" was taken for a title: the first sample dropped (n 3, t0 0.01), while
    # the same comment on a later row was refused
    p = write(tmp_path, "c.csv", "time [s], acc [g]\n0,0.1 # first\n0.01,0.2 # peak\n0.02,-0.3\n")
    m = read_motion(p)
    assert (m.n, m.t0) == (3, 0.0)
    np.testing.assert_array_equal(m.a_hor, np.array([0.1, 0.2, -0.3]) * G_STANDARD)
    # a row of the table with text after its numbers: refused, naming its line
    p = write(tmp_path, "x.csv", "0 0.1 x\n0.01 0.2\n0.02 -0.3\n0.03 0.05\n")
    with pytest.raises(RecordFileError, match=r"x\.csv:1: expected numbers, found 'x'"):
        read_motion(p)
    # a title that begins with numbers stays a title (its 1995 is no step before 0), and so
    # does one whose numbers before its comment are fewer than a row's
    for title in ("1995 6.9 Kobe #1", "2 # components", "1995 #3 Kobe record"):
        p = write(tmp_path, "k.csv", f"{title}\n0 0.1\n0.01 0.2\n0.02 -0.3\n")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UnitWarning)
            assert read_motion(p).n == 3, title


@pytest.mark.parametrize("unit", ["mg", "in/s2", "ft/s^2", "%g"])
def test_a_column_unit_nsdyn_does_not_know_is_refused_not_read_as_si(tmp_path, unit):
    # "a [in/s2]" was "the file does not state its units; assuming m/s²"
    p = write(tmp_path, "u.csv", f"time [s], a [{unit}]\n0,0.1\n0.01,0.2\n0.02,-0.3\n")
    with pytest.raises(UnitError, match=rf"u\.csv: column 'a' states units '{re.escape(unit)}'"):
        read_motion(p)
    assert read_motion(p, units="g").pga == pytest.approx(0.3 * G_STANDARD, rel=1e-15)


@pytest.mark.parametrize("label", ["E/W", "N/S", "H1/H2"])
def test_a_direction_in_a_column_name_is_a_label_not_a_unit(tmp_path, label):
    # under a header's units the bracket names the direction: read as g, as before
    p = write(tmp_path, "d.csv", f"# units: g\ntime, acc ({label})\n0 0.1\n0.01 0.2\n0.02 -0.3\n")
    assert read_motion(p).pga == pytest.approx(0.3 * G_STANDARD, rel=1e-15)


def test_plain_utf8_is_read_as_utf8(tmp_path):
    # written without a byte-order mark, "cm/s²" was read as Latin-1's "cm/sÂ²", no unit
    p = tmp_path / "g.csv"
    p.write_bytes("# units: cm/s²\n0 100\n0.01 -200\n0.02 50\n".encode())
    m = read_motion(p)
    assert m.meta["file_units"] == "cm/s2" and m.pga == 2.0  # 200 gal = 2 m/s² (0.01 exact)
    motion = dataclasses.replace(m, name="Zürich ²")
    assert read_motion(write_motion(motion, tmp_path / "z.csv")).name == "Zürich ²"


def test_what_write_motion_writes_reads_back_or_is_refused(tmp_path):
    from nsdyn.ground import GroundMotion

    a = np.sin(0.1 * np.arange(50))
    # stamps of t0 = 1e7 s every 1 ms repeated at 10 digits (the reader refused the file); a
    # newline in the name began a line of data
    for m in (GroundMotion(1e7, 1e-3, a), GroundMotion(0.0, 0.01, a, name="x\n0.5,99")):
        r = read_motion(write_motion(m, tmp_path / "w.csv"))
        assert (r.t0, r.dt, r.a_hor.tobytes()) == (m.t0, m.dt, m.a_hor.tobytes())
    with pytest.raises(ValueError, match=r"^motion: a record of 1 sample; expected at least two"):
        write_motion(GroundMotion(0.0, 0.01, a[:1]), tmp_path / "one.csv")
    with pytest.raises(IsADirectoryError, match=r": a folder; expected the path of a file"):
        write_motion(m, tmp_path)
    assert not (tmp_path / "one.csv").exists()


def test_a_binary_file_given_as_a_record_is_said_to_be_one(tmp_path):
    # random bytes were read as Latin-1 text and refused as "expected numeric data, found
    # none" on some line; a NUL byte is in no text file
    path = tmp_path / "bin.csv"
    path.write_bytes(b"0.0 0.1\n0.01 0.2\n" + bytes(range(256)))
    with pytest.raises(RecordFileError, match=r"bin\.csv:3: a NUL byte: a binary file"):
        read_motion(path, units="m/s2")


def test_a_units_line_without_its_colon_states_the_units(tmp_path):
    # "units m/s^2" (no colon) on a line of its own was read as "the file does not state its
    # units; assuming m/s²" (a UnitWarning); a line of "units WORD" alone states WORD
    import warnings

    body = "0.0 0.3\n0.01 -0.2\n0.02 0.1\n"
    ms2 = write(tmp_path, "a.txt", "My record, station ABC\nunits m/s^2\ntime accel\n" + body)
    g = write(tmp_path, "b.txt", "# units g\n" + body)
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitWarning)
        assert read_motion(ms2).pga == 0.3
        assert read_motion(g).pga == pytest.approx(0.3 * 9.80665, rel=1e-15)
    # a line where the unit is followed by more words is no units line, nor is "units" on a
    # line of its own above the word
    # (and a "units:" line without its word reads none from the next line: "Units:" over
    # "Station ABC" was refused as units 'Station' nsdyn does not know)
    for i, head in enumerate(
        ("units g station 5\n", "units\ng\n", "Units:\nStation ABC\n", "# units:\n# g\n")
    ):
        with pytest.warns(UnitWarning, match="does not state its units"):
            read_motion(write(tmp_path, f"c{i}.txt", head + body))


def test_a_record_in_g_read_as_assumed_m_s2_is_given_its_pga_in_g(tmp_path):
    # 0.349 g without a units line (El Centro's file) read as m/s² is 0.0356 g, which ran with
    # the plain "assuming m/s²" warning; the warning gives its PGA in g, 0.349 x 9.80665 m/s²
    rec = write(tmp_path, "elc.txt", "0.0 0.349\n0.01 -0.2\n0.02 0.0\n")
    with pytest.warns(UnitWarning, match=r"if the file is in g, .* the PGA is 3\.423 m/s²$"):
        assert read_motion(rec).pga == 0.349
    big = write(tmp_path, "ms2.txt", "0.0 3.49\n0.01 -0.2\n0.02 0.0\n")  # a plausible m/s²
    with pytest.warns(UnitWarning, match=r"assuming m/s² \(give them: .* units='gal'\)$"):
        read_motion(big)


def test_a_vertical_file_on_another_grid_is_refused_or_cut_to_the_shorter(tmp_path):
    # the shorter of two components was zero-padded (or the longer cut) without a word
    hor = write(tmp_path, "h.txt", "# units: m/s2\n" + "".join(
        f"{0.01 * k:.2f} {np.sin(k):.6f}\n" for k in range(1, 9)))  # fmt: skip
    ver = write(tmp_path, "v.txt", "# units: m/s2\n" + "".join(
        f"{0.01 * k:.2f} {0.5 * np.cos(k):.6f}\n" for k in range(1, 6)))  # fmt: skip
    with pytest.raises(RecordFileError, match=r"v.txt: vertical npts = 5, horizontal .*"
                                              r"npts = 8; pass trim=True"):  # fmt: skip
        read_motion(hor, vertical=ver)
    m = read_motion(hor, vertical=ver, trim=True)
    assert m.n == 5 and m.meta["trimmed_to"] == 5
    np.testing.assert_array_equal(m.a_hor, np.round(np.sin(np.arange(1, 6)), 6))
    np.testing.assert_array_equal(m.a_ver, np.round(0.5 * np.cos(np.arange(1, 6)), 6))
    late = write(tmp_path, "late.txt", "# units: m/s2\n" + "".join(
        f"{0.01 * k:.2f} 0.1\n" for k in range(2, 10)))  # fmt: skip
    with pytest.raises(RecordFileError, match=r"late.txt: vertical t0 = 0.02 s, horizontal .*"
                                              r"t0 = 0.01 s"):  # fmt: skip
        read_motion(hor, vertical=late)


@pytest.mark.parametrize(
    ("text", "bad"),
    [
        ("0,n/a\n0.01,0.2\n0.02,0.1\n0.03,0.3\n", "n/a"),
        ("0,0.1,0.1x\n0.01,0.2,0.1\n0.02,0.1,0.2\n", "0.1x"),
        ("0,? # warm-up\n0.01,0.2\n0.02,0.1\n0.03,0.3\n", r"\?"),
        ("0,#VALUE!\n0.01,0.2\n0.02,0.1\n0.03,0.3\n", "#VALUE!"),
        ('0,""\n0.01,0.2\n0.02,0.1\n0.03,0.3\n', ""),
        ("# units: g\ntime,acc\n0,abc\n0.01,0.2\n0.02,0.1\n", "abc"),
    ],
)
def test_a_first_row_with_a_cell_not_a_number_is_refused_not_read_as_a_title(tmp_path, text, bad):
    # "0,n/a" was taken for a title: the record began a step late and a sample short, unsaid
    p = write(tmp_path, "r.csv", text)
    with pytest.raises(RecordFileError, match=rf"r\.csv:\d: expected numbers, found '{bad}'"):
        read_motion(p, units="g")


@pytest.mark.parametrize(
    "title", ["2 components", "0 offset", "0 NS", "0.00 UTC", "0 N-S", "0 cm/s/s", "0 acc."]
)
def test_a_title_of_numbers_and_words_above_a_table_is_still_a_title(tmp_path, title):
    # the rule above needs the row's time a step before the next rows' ("2 components" is
    # none) and its bad cell a mangled number or a missing mark ("0 offset" above rows from
    # t = dt is a title, as OpenSees writes them)
    p = write(tmp_path, "t.csv", f"{title}\n0.01,0.1\n0.02,0.2\n0.03,-0.3\n")
    assert read_motion(p, units="g").n == 3


def test_a_column_unit_nsdyn_does_not_know_is_refused_under_a_header_s_units_too(tmp_path):
    # "a [mg]" under "# units: g" was read as g, 1000 times the file's values
    p = write(tmp_path, "m.csv", "# units: g\ntime [s], a [mg]\n0,0.1\n0.01,0.3\n0.02,0\n")
    with pytest.raises(UnitError, match=r"m\.csv: column 'a' states units 'mg', which nsdyn"):
        read_motion(p)


def test_a_header_stating_two_units_is_refused_unless_units_are_given(tmp_path):
    # the first pattern's won, unsaid ("units: g" over "units: gal" below it)
    p = write(tmp_path, "u.csv", "# units: g\n# units: gal\ntime,acc\n0,100\n0.01,-300\n")
    with pytest.raises(UnitError, match=r"u\.csv: the header states units 'g' and 'cm/s2'; "
                       r"expected one"):  # fmt: skip
        read_motion(p)
    assert read_motion(p, units="gal").pga == pytest.approx(3.0, rel=1e-15)
    with pytest.warns(UnitWarning, match=r"units='m/s2' given, but the header states 'g' and"):
        read_motion(p, units="m/s2")
    col = write(tmp_path, "c.csv", "# units: g\n# units: gal\ntime,acc [m/s2]\n0,1\n0.01,-3\n")
    with pytest.raises(UnitError, match=r"c\.csv: the header states units 'g' and 'cm/s2'"):
        read_motion(col)  # (the column's own unit settles nothing: it was read in m/s²)
    weaker = write(tmp_path, "w.txt", "# Acc. in cm/s/s\n# Peak given in units of g\n"
                   "time acc\n0 100\n0.01 -300\n")  # fmt: skip
    assert read_motion(weaker).pga == pytest.approx(3.0, rel=1e-15)  # (a peak's unit: aside)
    pga = write(tmp_path, "p.txt", "# PGA units: gal\n# Acc. in g\ntime acc\n0 0.1\n0.01 -0.3\n")
    assert read_motion(pga).pga == pytest.approx(0.3 * G_STANDARD, rel=1e-15)  # (the samples')
    late = write(tmp_path, "l.txt", "# Acc. history, max = 0.3 g, units: gal\n# Acc. in g\n"
                 "time acc\n0 100\n0.01 -3\n")  # fmt: skip
    with pytest.raises(UnitError, match=r"the header states units 'cm/s2' and 'g'; expected"):
        read_motion(late)  # (a peak earlier on the line: the units' own phrase is no aside)
    two = write(tmp_path, "t.txt", "# units: g\n# Acc. in cm/s/s\ntime acc\n0 100\n0.01 -3\n")
    with pytest.raises(UnitError, match=r"the header states units 'g' and 'cm/s2'; expected"):
        read_motion(two)  # (two phrases about the samples: the first ranked won, unsaid)
    same = write(tmp_path, "s.csv", "# units: gal\n# Acc. in cm/s2\ntime,acc\n0,100\n0.01,-300\n")
    assert read_motion(same).pga == pytest.approx(3.0, rel=1e-15)  # (one unit, said twice)


def test_a_number_with_an_underscore_is_refused_at_its_line(tmp_path):
    # Python's float reads "1_0" as 10: a PGA of 10 g from a typo, unsaid
    p = write(tmp_path, "u.csv", "time,acc\n0,0.1\n0.01,0.2\n0.02,1_0\n0.03,0.1\n")
    with pytest.raises(RecordFileError, match=r"u\.csv:4: expected 2 numbers per line"):
        read_motion(p, units="g")
