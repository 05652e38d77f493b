"""Three-component excitations from a ``[motion]`` table: the same objects as the direct calls,
and a one-line error naming the source and the key for every bad entry.

Expected values are the direct API calls the keys stand for (read_motion3, scaled_to_pga,
window, HarmonicPlane's helpers): the table is only another spelling of them.
"""

import numpy as np
import pytest

from nsdyn.ground import HarmonicPlane, motion3_from_table, read_motion3

SRC = "scene.toml"


def test_record_table_is_the_direct_reading():
    table = {"kind": "record3", "record": "synthetic-wn-40s", "rotate": 30.0, "pga": 4.0,
             "pga_component": "geomean", "t_end": 10.0}  # fmt: skip
    motion, duration = motion3_from_table(table, SRC)
    ref = read_motion3("synthetic-wn-40s", rotate=30.0).scaled_to_pga(4.0, "geomean")
    ref = ref.window(ref.t0, 10.0)
    assert duration == {} and motion.n == ref.n == 1001
    for c in "xyz":
        assert np.array_equal(motion.component(c), ref.component(c))
    no_vertical, _ = motion3_from_table({"kind": "record3", "record": "synthetic-kt-20s",
                                         "vertical": False})  # fmt: skip
    assert no_vertical.az is None


@pytest.mark.parametrize(
    "table, expected, duration",
    [
        ({"orbit": "circular", "frequency": 0.5, "amplitude": 2.0, "sense": -1, "t_end": 8.0},
         HarmonicPlane.circular(0.5, 2.0, -1), {"t_end": 8.0}),
        ({"orbit": "linear", "frequency": 1.0, "amplitude": 1.5, "angle": 120.0,
          "vertical_amplitude": 0.5, "n_periods": 4},
         HarmonicPlane.linear(1.0, 1.5, 120.0, az=0.5), {"n_periods": 4.0}),
        ({"orbit": "elliptical", "frequency": 2.0, "amplitude": 2.0, "amplitude_minor": 1.0,
          "angle": 30.0, "vertical_frequency": 3.0, "vertical_phase": 10.0,
          "vertical_amplitude": 1.0, "t_end": 1.0},
         HarmonicPlane.elliptical(2.0, 2.0, 1.0, 30.0, az=1.0, f_z=3.0, phase_z_deg=10.0),
         {"t_end": 1.0}),
        ({"orbit": "general", "frequency": 1.0, "amplitude_x": 1.0, "amplitude_y": 0.5,
          "phase_y": 45.0, "t_end": 2.0},
         HarmonicPlane(1.0, 1.0, 0.5, 45.0), {"t_end": 2.0}),
    ],
)  # fmt: skip
def test_orbit_table_is_the_helper(table, expected, duration):
    h, d = motion3_from_table({"kind": "orbit", **table}, SRC)
    assert h == expected and d == duration


@pytest.mark.parametrize(
    "table, key, needle",
    [
        ({"kind": "wind"}, "kind", "expected one of"),
        ({"kind": "record3"}, "record", "required"),
        ({"kind": "record3", "record": "nosuch"}, "record", "neither a file"),
        ({"kind": "record3", "record": "synthetic-wn-40s", "x": "a.AT2"}, "record", "not both"),
        ({"kind": "record3", "record": "synthetic-wn-40s", "pgaa": 3}, "pgaa", "unknown"),
        ({"kind": "record3", "record": "synthetic-wn-40s", "pga": "3"}, "pga", "finite number"),
        # a record scaled to zero is no motion at all: refused, as nsdyn run --pga 0 is
        ({"kind": "record3", "record": "synthetic-wn-40s", "pga": 0.0}, "pga", "positive"),
        ({"kind": "record3", "record": "synthetic-wn-40s", "pga": 3.0,
          "pga_component": "z"}, "pga_component", "expected one of"),
        ({"kind": "record3", "record": "synthetic-wn-40s", "trim": 1}, "trim", "true or false"),
        ({"kind": "record3", "record": "synthetic-wn-40s", "t_end": -1.0}, "t_end", "positive"),
        ({"kind": "record3", "x": "/nonexistent/x.AT2", "y": "/nonexistent/y.AT2"}, "x",
         "no such file"),
        ({"kind": "record3", "record": "synthetic-wn-40s", "units": "furlongs"}, "units",
         "unknown acceleration unit"),
        ({"kind": "orbit", "orbit": "circle"}, "orbit", "expected one of"),
        ({"kind": "orbit", "orbit": "circular", "amplitude": 1.0, "t_end": 1.0}, "frequency",
         "required"),
        ({"kind": "orbit", "orbit": "circular", "frequency": 0.0, "amplitude": 1.0,
          "t_end": 1.0}, "frequency", "positive"),
        ({"kind": "orbit", "orbit": "circular", "frequency": 1.0, "amplitude": -1.0,
          "t_end": 1.0}, "amplitude", ">= 0"),
        ({"kind": "orbit", "orbit": "elliptical", "frequency": 1.0, "amplitude": 1.0,
          "amplitude_minor": 2.0, "t_end": 1.0}, "amplitude_minor", "at most"),
        ({"kind": "orbit", "orbit": "circular", "frequency": 1.0, "amplitude": 1.0,
          "sense": 0, "t_end": 1.0}, "sense", "+1"),
        # another orbit's key is named as its (it read "unknown field; did you mean ...")
        ({"kind": "orbit", "orbit": "linear", "frequency": 1.0, "amplitude": 1.0,
          "sense": 1, "t_end": 1.0}, "sense",
         "a key of orbit 'circular' or 'elliptical', not of 'linear'"),
        ({"kind": "orbit", "orbit": "circular", "frequency": 1.0, "amplitude": 1.0,
          "amplitude_minor": 0.5, "t_end": 1.0}, "amplitude_minor",
         "a key of orbit 'elliptical', not of 'circular'"),
        ({"kind": "orbit", "orbit": "circular", "frequency": 1.0, "amplitude": 1.0,
          "t_end": 1.0, "amplitud_y": 1.0}, "amplitud_y", "unknown field; did you mean"),
        ({"kind": "orbit", "orbit": "circular", "frequency": 1.0, "amplitude": 1.0},
         "t_end", "no natural end"),
        ({"kind": "orbit", "orbit": "circular", "frequency": 1.0, "amplitude": 1.0,
          "t_end": 1.0, "n_periods": 2}, "t_end", "not both"),
        ({"kind": "orbit", "orbit": "general", "frequency": 1.0, "amplitude_x": 1.0,
          "amplitude_y": float("nan"), "t_end": 1.0}, "amplitude_y", "finite"),
        # a frequency of a component that has no amplitude was accepted and did nothing
        ({"kind": "orbit", "orbit": "circular", "frequency": 1.0, "amplitude": 1.0,
          "t_end": 1.0, "vertical_frequency": 2.0}, "vertical_frequency",
         "needs vertical_amplitude"),
        ({}, "kind", "missing; expected one of"),
        ({"kind": "orbit", "frequency": 1.0, "amplitude": 1.0, "t_end": 1.0}, "orbit",
         "'general'], got nothing (missing)"),  # (it said "got None")
    ],
)  # fmt: skip
def test_bad_table_names_source_and_key_in_one_line(table, key, needle):
    with pytest.raises(ValueError) as ei:
        motion3_from_table(table, SRC)
    msg = str(ei.value)
    assert "\n" not in msg and msg.startswith(f"{SRC}: motion.{key}")
    assert needle in msg


def test_an_orbit_names_itself_by_frequency_and_amplitudes():
    # a run's summary names the excitation (it read "HarmonicPlane", the class)
    o = HarmonicPlane(0.5, 2.0, 1.0, phase_y_deg=90.0, az=0.5, f_z=1.0)
    assert o.name == ("harmonic orbit 0.5 Hz, A_x 2, A_y 1 m/s² (phase 90°), A_z 0.5 m/s² at "
                      "1 Hz")  # fmt: skip


def test_a_bad_component_file_is_named_by_its_own_key(tmp_path):
    at2 = "PEER NGA STRONG MOTION DATABASE RECORD\nTEST\nACCELERATION TIME SERIES IN UNITS OF G\n"
    x = tmp_path / "x.AT2"
    x.write_text(at2 + "NPTS=    3, DT=   .0100 SEC,\n  0.01  0.02  0.03\n")
    y = tmp_path / "y.AT2"
    y.write_text(at2 + "NPTS=    3, DT=   .0200 SEC,\n  0.01  0.02  0.03\n")
    x2 = tmp_path / "x2.AT2"  # (x's samples in another file: one file twice is refused)
    x2.write_text(x.read_text())
    cases = [
        ({"x": str(x), "y": str(tmp_path / "nosuch.AT2")}, "y", "no such file"),
        ({"x": str(x), "y": str(y)}, "y", "dt = 0.02 s"),  # the y file's step differs from x's
        ({"x": str(x), "y": str(x2), "z": str(y)}, "z", "dt = 0.02 s"),
        ({"x": str(x), "y": str(x)}, "y", "the same file as x"),
        ({"x": str(x)}, "y", "missing component y"),  # an AT2 file holds one component
        ({"x": str(x), "z": str(x)}, "y", "second horizontal"),
    ]
    for files, key, needle in cases:
        with pytest.raises(ValueError) as ei:
            motion3_from_table({"kind": "record3", **files}, SRC)
        msg = str(ei.value)
        assert "\n" not in msg and msg.startswith(f"{SRC}: motion.{key}:") and needle in msg, msg


def test_a_misspelt_key_suggests_the_field_and_a_bad_component_names_it_once():
    base = {"kind": "record3", "record": "synthetic-wn-40s"}
    with pytest.raises(ValueError, match=r"motion\.records: unknown field; did you mean "
                                         r"'record'\? expected some of"):  # fmt: skip
        motion3_from_table({"kind": "record3", "records": "synthetic-wn-40s"}, SRC)
    with pytest.raises(ValueError) as ei:
        motion3_from_table({**base, "pga": 3.0, "pga_component": "geo"}, SRC)
    assert str(ei.value) == (f"{SRC}: motion.pga_component: expected one of ('resultant', "
                             "'x', 'y', 'geomean'), got 'geo'")  # fmt: skip


@pytest.mark.parametrize("key", ["amplitude", "vertical_amplitude"])
def test_an_orbit_amplitude_beyond_recorded_motions_asks_whether_it_is_in_gal(key):
    # a PGA above 30 m/s² is noted as probably typed in gal; an orbit's amplitude of 200
    # (gal) was not, and the deck ran into an uplift at 20 g without a word
    import warnings

    from nsdyn.ground import UnitWarning

    table = {"kind": "orbit", "orbit": "circular", "frequency": 0.5, "amplitude": 2.0,
             "t_end": 1.0, key: 200.0}  # fmt: skip
    with pytest.warns(UnitWarning, match=rf"^{SRC}: motion.{key} = 200 m/s² is above 30 m/s²"):
        motion3_from_table(table, SRC)
    table[key] = 30.0  # (the bound itself: the largest recorded PGAs, no warning)
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitWarning)
        motion3_from_table(table, SRC)
