"""``[motion] units`` on the rocking, contact and cylinder scenes, as on the isolated ones.

A record file that states no units was read as m/s² with a warning that said to give them in
the scene as ``[motion] units``, a key these scenes refused. The contract: a file's samples
times the unit's factor (g = 9.80665 m/s², gal = 0.01 m/s², exact), no warning, and units
without a record or outside the list refused naming the key.
"""

from __future__ import annotations

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
