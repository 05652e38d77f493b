"""The scene-file reference against the scene readers: every key of the generated reference
is accepted by its family's reader, every key a reader accepts is in the reference (a key the
reference does not list is refused, with the nearest valid key), and every documented bound of
a number is enforced by the reader with an error naming the key.

The independent side is the readers' behaviour: each check runs a reader on a scene built for
it and asserts on the reader's error (or its absence), not on the schema's own tables.
"""

from __future__ import annotations

import copy
import importlib
import math
import re
import sys
from dataclasses import fields
from pathlib import Path

import pytest

from nsdyn.models.isolated.scene import DEFAULT_SCENE
from nsdyn.models.scene_schema import Key, schema_of
from nsdyn.models.scenefile import KINDS, SceneError

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "docs" / "gen"))
import scene_reference  # noqa: E402

pytestmark = pytest.mark.filterwarnings("ignore::nsdyn.ground.UnitWarning")  # units= on a record

SCHEMAS = {k: schema_of(k) for k in KINDS}


def _merge(base: dict, extra: dict) -> dict:
    out = copy.deepcopy(base)
    for table, vals in extra.items():
        out.setdefault(table, {}).update(vals)
    return out


_ORBIT = {"kind": "orbit", "frequency": 0.5, "n_periods": 2}
_ORBITS = {
    "linear": {**_ORBIT, "orbit": "linear", "amplitude": 1.0},
    "circular": {**_ORBIT, "orbit": "circular", "amplitude": 1.0},
    "elliptical": {**_ORBIT, "orbit": "elliptical", "amplitude": 1.0, "amplitude_minor": 0.5},
    "general": {**_ORBIT, "orbit": "general", "amplitude_x": 1.0, "amplitude_y": 0.5},
}
# A valid scene of each table variant: the key under test is added to (or replaces a key of) it
_SHEAR = {"kind": "shear", "masses": [2e4, 1e4], "stiffnesses": [2e7], "damping_ratios": 0.05}
_ISO = {"k_lam": 2e5, "c": 2e4, "mu": 0.05}
_MATRICES = {
    "kind": "matrices",
    "M": [[1000.0]],
    "C": [[0.0]],
    "K": [[0.0]],
    "iso_dofs": [0],
    "influence": [1.0],
    "weight": 9810.0,
}
_RECORD = {"record": "synthetic-wn-40s", "t_end": 1.0}
BASE = {
    ("isolated", "", ""): _merge(DEFAULT_SCENE, {"motion": {"t_end": 1.0}}),
    ("isolated", "structure", '`kind = "shear"`'): {
        "structure": _SHEAR,
        "isolation": _ISO,
        "motion": _RECORD,
    },
    ("isolated", "structure", '`kind = "matrices"`'): {
        "structure": _MATRICES,
        "isolation": _ISO,
        "motion": _RECORD,
    },
    ("isolated", "motion", '`kind = "harmonic"`'): {
        **{k: v for k, v in DEFAULT_SCENE.items() if k != "motion"},
        "motion": {"kind": "harmonic", "amplitude": 1.0, "frequency": 1.0, "n_periods": 2},
    },
    ("isolated", "force", '`kind = "harmonic"`'): {
        "structure": _MATRICES,
        "isolation": _ISO,
        "force": {
            "kind": "harmonic",
            "dofs": [0],
            "amplitude": 1.0,
            "frequency": 1.0,
            "n_periods": 2,
        },
    },
    ("isolated", "force", '`kind = "record"`'): {
        "structure": _MATRICES,
        "isolation": _ISO,
        "force": {"kind": "record", "dofs": [0], "record": "synthetic-wn-40s", "scale": 1.0},
    },
    ("rocking", "", ""): {
        "scene": {"kind": "rocking"},
        "block": {"width": 1.0, "height": 2.0},
        "motion": {"pulse": "sine", "a_p_g": 0.3, "f_p": 1.0},
    },
    ("contact", "", ""): {
        "scene": {"kind": "contact"},
        "body": {"width": 1.0, "height": 2.0},
        "friction": {"mu_s": 0.5},
        "motion": {"t_end": 0.1},
    },
    ("cylinder", "", ""): {"scene": {"kind": "cylinder"}, "motion": {"duration": 2.0}},
    ("deck", "", ""): {
        "scene": {"kind": "deck"},
        "mass": {"m": 1000.0},
        "bearing": {"type": "fps", "radius": 2.0, "mu": 0.05},
        "motion": _ORBITS["circular"],
    },
    ("deck", "deck", ""): {
        "scene": {"kind": "deck"},
        "deck": {"m": 1e5, "positions": [[0.0, 0.0], [10.0, 0.0], [0.0, 10.0], [10.0, 10.0]]},
        "bearing": {"type": "fps", "radius": 2.0, "mu": 0.05},
        "motion": _ORBITS["circular"],
    },
    ("deck", "motion", '`kind = "record3"`'): {
        "scene": {"kind": "deck"},
        "mass": {"m": 1000.0},
        "bearing": {"type": "fps", "radius": 2.0, "mu": 0.05},
        "motion": {"kind": "record3", "record": "synthetic-wn-40s", "t_end": 1.0},
    },
}
for _shape, _motion in _ORBITS.items():
    BASE[("deck", "motion", f'`kind = "orbit"`, `orbit = "{_shape}"`')] = {
        **BASE[("deck", "", "")],
        "motion": _motion,
    }
# a record's units: the base with a record in place of its closed-form or simulated motion
for _kind in ("rocking", "contact", "cylinder"):
    BASE[(_kind, "motion", "units")] = {**BASE[(_kind, "", "")], "motion": dict(_RECORD)}
# keys that exclude a key of the base scene: the base without it
for _key in ("mu_slow", "mu_fast", "rate"):
    BASE[("deck", "bearing", _key)] = {
        **BASE[("deck", "", "")],
        "bearing": {"type": "fps", "radius": 2.0, "mu_slow": 0.05},
    }
BASE[("deck", "bearing", "k_lam")] = {
    **BASE[("deck", "", "")],
    "bearing": {"type": "flat", "mu": 0.05},
}
BASE[("deck", "bearing", "c")] = BASE[("deck", "bearing", "k_lam")]
# the 3D building scene shares the deck's [bearing], [motion] and [solver]
for (_k, _t, _v), _cfg in list(BASE.items()):
    if _k == "deck" and (_t, _v) != ("deck", ""):
        BASE[("building3d", _t, _v)] = {
            **{t: v for t, v in _cfg.items() if t not in ("deck", "mass")},
            "scene": {"kind": "building3d"},
            "structure": {"frame3d": "office-11-3d"},
        }
# keys that only apply in another setting of the same scene (a model, a ground, a record)
TWEAK = {
    ("rocking", "block", "gamma"): {"scene": {"model": "frame"}},
    ("rocking", "block", "omega_v_over_p"): {"scene": {"model": "compliant"}},
    ("rocking", "block", "zeta"): {"scene": {"model": "compliant"}},
    ("contact", "motion", "n_cycles"): {"motion": {"period": 2.0}},
    ("contact", "motion", "start"): {"motion": {"period": 2.0}},
    ("contact", "motion", "pga"): {"motion": {"period": 2.0}},
    ("contact", "ground", "stiffness"): {"ground": {"kind": "compliant"}},
    ("contact", "ground", "damping"): {"ground": {"kind": "compliant", "stiffness": 1e8}},
    ("contact", "ground", "damping_ratio"): {"ground": {"kind": "compliant", "stiffness": 1e8}},
    ("contact", "ground", "stick_stiffness"): {"ground": {"kind": "compliant", "stiffness": 1e8}},
    ("cylinder", "foundation", "f_rock"): {"foundation": {"zeta": 0.1}},
    ("cylinder", "foundation", "zeta"): {"foundation": {"f_rock": 3.0}},
    ("cylinder", "foundation", "mu"): {"foundation": {"sliding": True}},
    ("deck", "motion", "pga_component"): {"motion": {"pga": 3.0}},
    ("building3d", "motion", "pga_component"): {"motion": {"pga": 3.0}},
}


def _entries():
    """(kind, table, variant, key) of every key of every schema."""
    return [
        (kind, t.name, t.variant, k)
        for kind, s in SCHEMAS.items()
        for t in s.tables
        for k in t.keys
    ]


def _id(e):
    variant = e[2].split("=")[-1].strip(' `"') if "=" in e[2] else ""
    return "-".join(x for x in (e[0], e[1], variant, e[3].name) if x)


def _base(kind: str, table: str, variant: str, key: str) -> dict:
    cfg = (
        BASE.get((kind, table, key))
        or BASE.get((kind, table, variant))
        or BASE.get((kind, "", ""))
        or {}
    )
    return _merge(cfg, TWEAK.get((kind, table, key), {}))


# kinds that studies do not run yet: their reader's own checking functions, in order
READERS = {
    "deck": ("build_system", "build_motion", "build_solver"),
    "building3d": ("build_system", "build_motion", "build_solver"),
}


def read(kind: str, cfg: dict, tmp_path: Path) -> None:
    """Check ``cfg`` as ``nsdyn run`` and ``nsdyn study`` check a scene, without running it."""
    from nsdyn.models import scenefile
    from nsdyn.studies.scenes import check_scene

    source = str(tmp_path / "scene.toml")
    if kind in READERS:
        module = getattr(scenefile, "SCENE_MODULES", {}).get(kind, f"nsdyn.models.{kind}.scene")
        mod = importlib.import_module(module)
        for name in READERS[kind]:
            getattr(mod, name)(copy.deepcopy(cfg), source)
        return
    check_scene(copy.deepcopy(cfg), source)


def sample(key: Key):
    """A value of the key's type (the first choice where it has choices)."""
    if key.choices:
        return key.choices[0]
    return {
        "number": 1.0,
        "integer": 1,
        "integer or string": 1,
        "boolean": True,
        "string": "x",
        "number or list": 1.0,
        "number or pair": 1e-6,
        "list of numbers": [1.0],
        "list of integers": [0],
        "list of [x, y]": [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        "list or matrix": [1.0],
        "list of lists": [[0]],
        "matrix": [[1.0]],
    }[key.type]


def _unknown(msg: str) -> bool:
    return "unknown field" in msg or "unknown table" in msg


def test_the_reference_lists_exactly_the_schema_keys():
    # the generated page, parsed back: one row per key under each table heading of each kind
    page = scene_reference.page()
    listed, kind, table = set(), None, None
    for line in page.splitlines():
        if m := re.match(r'^## `kind = "(\w+)"`', line):
            kind = m.group(1)
        elif m := re.match(r"^### `\[(\w+)\]", line):
            table = m.group(1)
        elif (m := re.match(r"^\| `(\w+)` \|", line)) and kind and table:
            listed.add((kind, table, m.group(1)))
    declared = {
        (k, t, key) for k, s in SCHEMAS.items() for t, keys in s.fields().items() for key in keys
    }
    assert listed == declared


def test_the_isolation_table_is_the_isolation_dataclass():
    # the reader checks [isolation] against nsdyn.Isolation's fields, not a table of its own
    from nsdyn.models.isolated.system import Isolation

    assert SCHEMAS["isolated"].keys("isolation") == {f.name for f in fields(Isolation)}


def test_the_isolated_defaults_are_the_default_scene():
    # where the default scene sets a key, the reference's default is that value
    s = SCHEMAS["isolated"]
    for table, vals in DEFAULT_SCENE.items():
        t = s.table(table, "a record (no `kind`)" if table == "motion" else "")
        for key, v in vals.items():
            d = next(k for k in t.keys if k.name == key).default
            assert d == v, f"{table}.{key}: reference {d!r}, default scene {v!r}"


@pytest.mark.parametrize("entry", _entries(), ids=_id)
def test_every_listed_key_is_accepted_and_a_misspelt_one_refused(entry, tmp_path):
    kind, table, variant, key = entry
    base = _base(kind, table, variant, key.name)
    try:
        read(kind, _merge(base, {table: {key.name: sample(key)}}), tmp_path)
    except SceneError as e:  # a value the reader refuses is fine; the key itself is not
        assert not _unknown(str(e)), str(e)
    with pytest.raises(SceneError, match="unknown field") as err:
        read(kind, _merge(base, {table: {key.name + "x": sample(key)}}), tmp_path)
    assert f"{table}.{key.name}x" in str(err.value)


def _outside(key: Key):
    """Values just outside the key's documented bounds (none for a key without bounds)."""
    out = []
    if key.lo is not None:  # (a positive closed bound of a number: half of it is outside)
        below = key.lo / 2 if key.lo > 0 and key.type != "integer" else key.lo - 1
        out.append(key.lo if key.lo_open else below)
    if key.hi is not None:
        out.append(key.hi if key.hi_open else key.hi + 1)
    if key.type == "integer":
        out = [int(math.floor(v)) for v in out]
    return out


BOUNDED = [e for e in _entries() if _outside(e[3]) and "list" not in e[3].type]


@pytest.mark.parametrize("entry", BOUNDED, ids=_id)
def test_every_documented_bound_is_enforced(entry, tmp_path):
    kind, table, variant, key = entry
    base = _base(kind, table, variant, key.name)
    for v in _outside(key):
        with pytest.raises(SceneError) as err:
            read(kind, _merge(base, {table: {key.name: v}}), tmp_path)
        assert f"{table}.{key.name}" in str(err.value), (v, str(err.value))


@pytest.mark.parametrize("entry", [e for e in _entries() if e[3].choices], ids=_id)
def test_every_documented_choice_is_the_readers(entry, tmp_path):
    # each listed choice passes the reader's check of that key; a value not listed is refused
    kind, table, variant, key = entry
    base = _base(kind, table, variant, key.name)
    for c in key.choices:
        try:
            read(kind, _merge(base, {table: {key.name: c}}), tmp_path)
        except SceneError as e:
            assert f"{table}.{key.name}:" not in str(e), (c, str(e))
    if key.name == "kind" and table == "scene":
        return  # the family's own kind is the only one its reader is handed
    with pytest.raises(SceneError):  # named as the field, or as the record it cannot read
        read(kind, _merge(base, {table: {key.name: "no-such-choice"}}), tmp_path)


def test_every_key_of_the_example_scenes_is_in_the_reference():
    # the bundled scenes were written against the readers, before the reference existed
    import tomllib

    from nsdyn.models.scenefile import scene_kind

    listed = {k: s.fields() for k, s in SCHEMAS.items()}
    scenes = sorted((ROOT / "examples" / "scenes").glob("*.toml"))
    assert scenes
    for path in scenes:
        cfg = tomllib.loads(path.read_text())
        kind = scene_kind(cfg, str(path))
        for table, vals in cfg.items():
            assert table in listed[kind], f"{path.name}: [{table}]"
            assert set(vals) <= listed[kind][table], f"{path.name}: [{table}] {sorted(vals)}"
