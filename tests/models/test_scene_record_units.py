"""``[motion] units`` on the rocking, contact and cylinder scenes, as on the isolated ones.

A record file that states no units was read as m/s² with a warning that said to give them in
the scene as ``[motion] units``, a key these scenes refused. The contract: a file's samples
times the unit's factor (g = 9.80665 m/s², gal = 0.01 m/s², exact), no warning, and units
without a record or outside the list refused naming the key.
"""

from __future__ import annotations

import re
import warnings

import pytest

from nsdyn.models.scenefile import SceneError

G_STANDARD = 9.80665  # the standard gravity a record in g is read with


def _write(tmp_path, peak: float) -> str:
    path = tmp_path / "rec.csv"  # no units stated: a header of names only
    rows = "".join(f"{0.01 * i:.2f},{peak * (i % 3 - 1)!r}\n" for i in range(50))
    path.write_text("t,a\n" + rows)
    return str(path)


@pytest.fixture
def record(tmp_path):
    return _write(tmp_path, 0.1)


@pytest.mark.parametrize(
    ("units", "peak", "factor"), [("g", 0.1, G_STANDARD), ("gal", 100.0, 0.01), ("m/s2", 1.0, 1.0)]
)
def test_a_rocking_and_contact_record_is_read_in_the_scene_s_units(tmp_path, units, peak, factor):
    record = _write(tmp_path, peak)  # (a peak of a plausible PGA in each unit)
    from nsdyn.models.contact.scene import build
    from nsdyn.models.rocking.scene import build_motion

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no "does not state its units" warning
        exc = build_motion({"motion": {"record": record, "units": units}}, "s.toml")[0]
        assert exc.pga == pytest.approx(peak * factor, rel=1e-15)
        cfg = {"scene": {"kind": "contact"}, "body": {"width": 0.5, "height": 1.5},
               "friction": {"mu_s": 0.6}, "motion": {"record": record, "units": units}}  # fmt: skip
        motion = build(cfg, "s.toml")[2]  # the base's acceleration table, as read
        assert abs(motion.tab_h).max() == pytest.approx(peak * factor, rel=1e-15)


def test_a_cylinder_record_is_read_in_the_scene_s_units(record):
    from nsdyn.models.cylinder.scene import build

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ag = build({"scene": {"kind": "cylinder"}, "motion": {"record": record, "units": "g"}},
                   "s.toml")[2]  # fmt: skip
    assert abs(ag[:, 0]).max() == pytest.approx(0.1 * G_STANDARD, rel=1e-15)


@pytest.mark.parametrize(
    ("motion", "match"),
    [
        ({"units": "g", "pulse": "sine", "a_p_g": 0.3, "omega_p": 10.0},
         r"motion.units: the units of a record file; this scene reads none"),
        ({"record": "RECORD", "units": "furlongs"}, r"motion.units: expected one of \['g'"),
    ],
)  # fmt: skip
def test_units_without_a_record_or_unknown_are_refused(record, motion, match):
    from nsdyn.models.rocking.scene import build_motion

    motion = {k: (record if v == "RECORD" else v) for k, v in motion.items()}
    with pytest.raises(SceneError, match=match):
        build_motion({"motion": motion}, "s.toml")


def test_a_record_above_100_g_as_read_is_refused_unless_scaled(tmp_path, capsys):
    # a record in units it was not read in (3e5 g) ran until an isolator lifted off; pga
    # scales only up to 100 g (1000 m/s²), so a record as read beyond it is refused by the
    # same bound, naming the field and the file, in a planar, a study's and a 3-component scene
    from nsdyn.cli.app import main
    from nsdyn.ground.table3 import motion3_from_table
    from nsdyn.studies.scenes import scene_motion

    path = tmp_path / "rec.csv"
    rows = [f"{0.01 * i:.2f},{200.0 * (i % 3 - 1)!r},{50.0 * (i % 2)!r}" for i in range(50)]
    path.write_text("# units: g\nt,ax,ay\n" + "\n".join(rows) + "\n")
    said = r"motion.record.*rec.csv: the record's PGA as read is 1961 m/s², above 1000 m/s²"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (the implausible PGA's UnitWarning)
        with pytest.raises(SceneError, match=said):
            scene_motion({"motion": {"record": str(path)}}, "s.toml")
        assert scene_motion({"motion": {"record": str(path), "pga": 3.0}}).pga == 3.0
        # the 3-component scene's resultant, hypot(200, 50) g
        resultant = r"s.toml: motion.record: .*rec.csv: the record's PGA as read is 2022 m/s²"
        with pytest.raises(ValueError, match=resultant):
            motion3_from_table({"kind": "record3", "record": str(path)}, "s.toml")
        # the rocking, contact and cylinder scenes: the same bound
        from nsdyn.models.contact.scene import build as contact
        from nsdyn.models.cylinder.scene import build as cylinder
        from nsdyn.models.rocking.scene import build_motion as rocking

        for family, peak in (  # (the planar bodies' x column; the cylinder's resultant)
            (lambda mo: rocking({"motion": mo}, "s.toml"), "1961"),
            (lambda mo: contact({"scene": {"kind": "contact"}, "body": {"width": 0.5,
                                 "height": 1.5}, "friction": {"mu_s": 0.6}, "motion": mo},
                                "s.toml"), "1961"),
            (lambda mo: cylinder({"scene": {"kind": "cylinder"}, "motion": mo}, "s.toml"),
             "2022"),
        ):  # fmt: skip
            with pytest.raises(SceneError, match=said.replace("1961", peak)):
                family({"record": str(path)})
            family({"record": str(path), "pga": 3.0})
        rc = main(["run", "--frame", "portal", "--record", str(path), "--no-figures",
                   "--out", str(tmp_path / "o")])  # fmt: skip
    assert rc == 2 and re.search(said, capsys.readouterr().err)


def test_a_planar_scene_takes_the_column_it_names(tmp_path, capsys):
    # a table of two horizontals: the planar scene ran the first (NS), and said so, with no
    # key to take the other; [motion] column takes it by index or name, as read_motion does
    from nsdyn.cli.app import main
    from nsdyn.models.isolated.scene import build_scene_run, load_scene
    from nsdyn.studies.scenes import scene_motion

    path = tmp_path / "ns_ew.csv"
    rows = [f"{0.01 * i:.2f},{2.0 * (i % 3 - 1)!r},{3.5 * (i % 2)!r}" for i in range(50)]
    path.write_text("# units: m/s2\nt,ns,ew\n" + "\n".join(rows) + "\n")
    scene = tmp_path / "s.toml"
    for column, peak in ((1, 2.0), ("ns", 2.0), (2, 3.5), ("ew", 3.5)):
        col = f'"{column}"' if isinstance(column, str) else column
        scene.write_text(f'[scene]\nframe = "portal"\n[motion]\nrecord = "{path}"\n'
                         f"column = {col}\n")  # fmt: skip
        assert build_scene_run(load_scene(scene))[1].pga == peak  # exact: the file's value
        assert scene_motion({"motion": {"record": str(path), "column": column}}).pga == peak
    # the columns left out are said when the scene took the default one, not when it chose
    for column, said in (("", True), ("column = 2\n", False)):
        scene.write_text(f'[scene]\nframe = "portal"\n[motion]\nrecord = "{path}"\n{column}')
        assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "o")]) == 0
        assert ("the record's column(s) '" in capsys.readouterr().err) is said
    refused = [
        (True, r"motion.column: expected a column index \(0, 1, ...\) or a column name, got true"),
        (-1, r"motion.column: .* got -1"),
        ('"north"', r"motion.column: .*ns_ew.csv: expected a column named 'north'; has \['t', "
                    r"'ns', 'ew'\]"),
        (3, r"motion.column: .*ns_ew.csv: expected column index < 3, got 3"),
    ]  # fmt: skip
    for column, says in refused:
        scene.write_text(f'[scene]\nframe = "portal"\n[motion]\nrecord = "{path}"\n'
                         f"column = {str(column).lower()}\n")  # fmt: skip
        assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "o")]) == 2
        assert re.search(says, capsys.readouterr().err)


@pytest.mark.parametrize("pga", [0, 0.0, -1.0, "abc", True, float("inf")])
def test_a_record_s_pga_that_is_no_positive_number_is_refused_in_every_family(pga):
    # a rocking or contact record at pga = 0 ran with the ground at rest (exit 0), as the
    # pulse beside it and the isolated frame refuse it: one message, naming motion.pga
    from nsdyn.models.contact.scene import build as contact
    from nsdyn.models.rocking.scene import build_motion as rocking
    from nsdyn.studies.scenes import scene_motion

    mo = {"record": "synthetic-wn-40s", "pga": pga}
    said = r"s.toml: motion.pga: expected a finite positive number, got "
    for family in (
        lambda: rocking({"motion": mo}, "s.toml"),
        lambda: contact({"scene": {"kind": "contact"}, "body": {"width": 0.5, "height": 1.5},
                         "friction": {"mu_s": 0.6}, "motion": mo}, "s.toml"),
        lambda: scene_motion({"motion": mo}, "s.toml"),
    ):  # fmt: skip
        with pytest.raises(SceneError, match=said):
            family()


def test_a_record_s_pga_from_numpy_is_a_number():
    # a pga from a NumPy computation (a study's grid, a script's array) is a number: its
    # integer and single-precision kinds were refused as no number
    import numpy as np

    from nsdyn.studies.scenes import scene_motion

    for pga in (np.int64(3), np.float32(3.0), np.float64(3.0), 3):
        assert scene_motion({"motion": {"record": "synthetic-wn-40s", "pga": pga}}).pga == 3.0
