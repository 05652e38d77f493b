"""A scene written as TOML loads back to exactly what was written (hypothesis).

Source: TOML's own round-trip guarantee for floats, strings and booleans (TOML 1.0 §Float: a
float written with Python's shortest repr reads back to the same double), so whatever the
loader returns beyond the defaults must be the user's values unchanged — no silent rounding,
renaming or dropped field.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from nsdyn.models.isolated.scene import DEFAULT_SCENE, load_scene

positive = st.floats(1e-6, 1e9, allow_nan=False, allow_infinity=False)
non_negative = st.one_of(st.just(0.0), positive)

isolation = st.fixed_dictionaries(
    {},
    optional={
        "k_lam": non_negative,
        "c": non_negative,
        "mu": st.floats(0.0, 1.0),
        "law": st.sampled_from(["arctan", "switch", "none"]),
        "eps": positive,
        "eta": positive,
        "frozen_normal": st.booleans(),
        "contact": st.sampled_from(["bilateral", "detect", "unilateral"]),
    },
)
motion = st.fixed_dictionaries(
    {},
    optional={
        "record": st.sampled_from(["synthetic-wn-40s", "synthetic-kt-20s"]),
        "pga": positive,
        "vertical": st.booleans(),
        "t_end": positive,
    },
)
solver = st.fixed_dictionaries(
    {},
    optional={
        "method": st.sampled_from(["radau", "dopri5", "event", "genalpha"]),
        "rtol": st.floats(1e-12, 1e-2),
        "dt_out": positive,
        "uplift": st.sampled_from(["raise", "warn"]),
    },
)
scene = st.fixed_dictionaries(
    {},
    optional={
        "fidelity": st.sampled_from(["fixed", "rigid", "cb", "full"]),
        "f_max": st.floats(0.5, 50.0),
        "name": st.text("abcdefgh xyz-_0123456789", min_size=1, max_size=20),
    },
)


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        assert math.isfinite(v)
        return repr(v)
    return '"' + str(v).replace("\\", "\\\\").replace('"', '\\"') + '"'


def _dumps(cfg: dict) -> str:
    lines = []
    for table, fields in cfg.items():
        lines.append(f"[{table}]")
        lines += [f"{k} = {_toml_value(v)}" for k, v in fields.items()]
        lines.append("")
    return "\n".join(lines)


@settings(max_examples=60)
@given(sc=scene, iso=isolation, mo=motion, sv=solver)
def test_scene_toml_round_trip(tmp_path_factory, sc, iso, mo, sv):
    user = {k: v for k, v in (("scene", sc), ("isolation", iso), ("motion", mo), ("solver", sv))}
    user = {k: v for k, v in user.items() if v}
    path = tmp_path_factory.mktemp("scene") / "s.toml"
    # an empty file is refused (tests/catalogue); with nothing drawn, one empty table
    path.write_text(_dumps(user) if user else "[scene]\n")
    cfg = load_scene(path)
    for table, fields in user.items():
        for key, val in fields.items():
            assert cfg[table][key] == val and type(cfg[table][key]) is type(val), (table, key)
    for table, fields in DEFAULT_SCENE.items():  # what the user did not set keeps its default
        for key, val in fields.items():
            if (table, key) == ("motion", "pga") and "record" in user.get("motion", {}):
                assert key in user["motion"] or key not in cfg[table]  # (runs as recorded)
            elif key not in user.get(table, {}):
                assert cfg[table][key] == val, (table, key)


def test_overrides_are_tables_and_a_motion_of_another_kind_replaces_the_scene_s():
    # a bare value raised a TypeError from the merge ('int' object is not a mapping); a
    # harmonic motion over the default scene's record was refused for that record's keys
    import nsdyn
    from nsdyn.models.isolated.scene import SceneError

    shear = Path(__file__).resolve().parents[3] / "examples/scenes/isolated-shear-3storey.toml"
    for path in (None, shear):  # (with a file, its branch read them first: a TypeError)
        for bad in ({"motion": 1}, [("motion", {})], "x"):
            with pytest.raises(SceneError, match=r"^overrides: expected tables of keys"):
                nsdyn.load_scene(path, overrides=bad)
    harmonic = {"kind": "harmonic", "amplitude": 1.0, "frequency": 1.0, "t_end": 2.0}
    assert nsdyn.load_scene(overrides={"motion": harmonic})["motion"] == harmonic
    kept = nsdyn.load_scene(overrides={"motion": {"pga": 2.0}})["motion"]
    assert kept["pga"] == 2.0 and kept["record"] == "synthetic-wn-40s"  # (the same kind)
