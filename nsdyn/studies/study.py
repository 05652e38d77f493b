"""Study files: one TOML describing many runs of a scene, read and checked.

A study is the Cartesian product

    tasks = (grid values of every listed parameter) x (``samples`` joint random draws)
            x (records)

run on a base scene (any kind ``nsdyn run`` knows). Example::

    [study]
    name = "isolator design"
    scene = "../scenes/office.toml"   # optional; default: the isolated frame's default scene
    keep = ["x_iso_max_m", "idr_max", "floor_acc_max_mps2"]   # default: every scalar field
    samples = 0                       # joint draws of the random parameters
    seed = 1                          # seed of those draws
    batch = 0                         # tasks per batch (0: automatic)

    [base.motion]                     # scene tables merged over the scene file
    t_end = 20.0

    [parameters]
    "isolation.k_lam" = [2.5e4, 5e4, 1e5]          # values
    "isolation.mu" = { linspace = [0.01, 0.05, 5] } # or logspace = [a, b, n]
    "motion.pga" = { uniform = [1.0, 6.0] }         # random: uniform, loguniform,
                                                    # normal = [m, s], lognormal = [median, beta]
    [records]
    names = ["synthetic-wn-40s"]      # bundled names or files (relative to the study file)
    folder = "records/"               # every file in it matching glob (default "*")
    set = "kobe"                      # "kobe": the four 1995 Kobe records (shared records)
    simulated = { n = 20, seed = 7, duration = 30.0 }   # seed 000 modulated white noise
    pairs = [{ name = "KJMA", x = "KJM090.AT2", y = "KJM000.AT2", z = "KJM-UP.AT2" }]
                                      # two horizontal components (and a vertical) per entry

For the scene kinds on bidirectional isolators (``deck``, ``building3d``) every record has two
horizontal components (``pairs``, a ``t, ax, ay[, az]`` CSV, a bundled record with a second
component, or simulated pairs) and the incident angle is the parameter ``"motion.rotate"``
[deg]: each task turns the horizontal pair by it (:mod:`nsdyn.studies.scenes3c`).

    [analysis.design]    ...          # see nsdyn.studies.analyses

Every error names the file and the field and, for a misspelt key, the nearest valid one.
"""

from __future__ import annotations

import copy
import importlib
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

from nsdyn._checks import InputWarning, NotedWarning, did_you_mean
from nsdyn.ground.synthesis import NOISE_GENERATORS as GENERATORS
from nsdyn.ground.synthesis import noise_step
from nsdyn.models.scenefile import (
    SceneError,
    number,
    read_toml,
    resolve_paths,
    scene_kind,
    scene_module,
    unknown_key,
)
from nsdyn.studies.parameters import (  # noqa: F401 (their names, importable from here)
    GRID_FORMS,
    MAX_TASKS,
    NUMERIC_FIELDS,
    RANDOM_FORMS,
    Parameter,
    _err,
    parse_parameter,
    whole_numbers,
)
from nsdyn.studies.table import checked_keep

KINDS3C = ("deck", "building3d")  # scene kinds whose records have two horizontal components
PAIR_KINDS = (*KINDS3C, "cylinder")  # scene kinds that read a record's components from files

STUDY_TABLES = ("study", "base", "parameters", "records", "analysis")
STUDY_FIELDS = {"name": str, "scene": str, "keep": list, "samples": int, "seed": int, "batch": int}
RECORD_FIELDS = ("names", "folder", "glob", "set", "simulated", "pairs")
PAIR_FIELDS = ("name", "x", "y", "z")
SIMULATED_FIELDS = {"n": int, "seed": int, "duration": float, "dt": float, "generator": str}
RECORD_DIGITS = 3  # a simulated record's name: mo-000 … mo-999 (more digits past 1000)
RECORD_SETS = ("kobe", "bundled")
# dotted scene fields a parameter may vary for scene kinds whose schema the study cannot see
CONTRACT_FIELDS = ("motion.record", "motion.pga", "motion.t_end", "solver.method")


@dataclass(frozen=True)
class RecordSpec:
    """One ground motion of a study: a file/bundled name, or a simulated record and its seed."""

    name: str
    path: str | None = None
    simulated: dict | None = None
    components: tuple | None = None  # (x, y, z or None) files of a two-component record

    def identity(self) -> dict:
        ident = {"name": self.name, "path": self.path, "simulated": self.simulated}
        if self.components is not None:
            ident["components"] = list(self.components)
        return ident


@dataclass
class Study:
    """A checked study: base scene, parameters, records and analyses."""

    source: str
    name: str
    kind: str
    base: dict  # the scene cfg all tasks start from
    parameters: list[Parameter]
    records: list[RecordSpec]
    keep: list[str] | None = None
    samples: int = 0
    seed: int = 0
    batch: int = 0
    analysis: dict = field(default_factory=dict)

    @property
    def n_tasks(self) -> int:
        n = max(1, len(self.records))
        for p in (p for p in self.parameters if not p.random):
            n *= len(p.values)
        return n * (self.samples if any(p.random for p in self.parameters) else 1)


def _check_type(source: str, where: str, val, typ):
    if typ is int:
        ok = isinstance(val, int) and not isinstance(val, bool)
        if not ok or val < 0:
            raise _err(source, where, f"expected a non-negative integer, got {val!r}")
        return val
    if typ is float:
        return number(source, where, val)
    if not isinstance(val, typ) or isinstance(val, bool) and typ is not bool:
        what = {bool: "true or false", str: "a text", list: "a list"}.get(typ, typ.__name__)
        raise _err(source, where, f"expected {what}, got {val!r}")
    if typ is str and not val.strip():  # (a study named "" wrote into nsdyn-study/ itself)
        raise _err(source, where, f"expected a non-empty text, got {val!r}")
    return val


def _known_fields(kind: str, base: dict) -> set[str]:
    """Dotted fields a parameter may name: the base scene's own, plus the kind's schema (every
    key ``nsdyn run`` reads in a table other than ``[scene]``, set in the base or not)."""
    from nsdyn.models.scene_schema import schema_of

    known = {f"{t}.{k}" for t, vals in base.items() if isinstance(vals, dict) for k in vals}
    known |= set(CONTRACT_FIELDS)
    try:
        tables = schema_of(kind).fields()
    except (ImportError, AttributeError):  # a kind without a declared schema: the base's keys
        tables = {}
    known |= {f"{t}.{k}" for t, keys in tables.items() if t != "scene" for k in keys}
    # [scene]'s choices of model (a rocking model, a fidelity, a frame), set in the base or not
    # (scene.model was accepted only where the base scene wrote it); never its kind or name
    known |= {f"scene.{k}" for k in tables.get("scene", ()) if k not in ("kind", "name")}
    known.discard("scene.kind")  # (one family per study)
    if kind == "isolated":
        from nsdyn.models.isolated.scene import _FIELDS
        from nsdyn.models.isolated.system import Isolation

        known |= {f"{t}.{k}" for t, fields in _FIELDS.items() for k in fields}
        known |= {f"isolation.{k}" for k in Isolation.__dataclass_fields__}
    if kind in KINDS3C:
        from nsdyn.studies.scenes3c import scene_fields

        known |= scene_fields(kind)
    return known


def _integer_fields(kind: str, of=("integer",)) -> set[str]:
    """Dotted fields the kind's schema declares integer (``of``: of these types) in every
    variant of their table."""
    from nsdyn.models.scene_schema import schema_of

    try:
        tables = schema_of(kind).tables
    except (ImportError, AttributeError):
        return set()
    types: dict[str, set[str]] = {}
    for t in tables:
        for k in t.keys:
            types.setdefault(f"{t.name}.{k.name}", set()).add(k.type)
    return {f for f, ty in types.items() if ty <= set(of)}


def _resolve_path(study_dir: Path, p: str) -> Path:
    q = Path(p).expanduser()
    return q if q.is_absolute() else study_dir / q


def _parse_records(source: str, study_dir: Path, rec: dict, kind: str, base: dict) -> list:
    for key in rec:
        if key not in RECORD_FIELDS:
            raise unknown_key(source, "records.", key, RECORD_FIELDS)
    out: list[RecordSpec] = []
    names = rec.get("names", [])
    if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
        raise _err(source, "records.names", f"expected a list of strings, got {names!r}")
    for n in names:
        from nsdyn.ground import bundled_records

        path = _resolve_path(study_dir, n)
        if path.is_file():
            out.append(RecordSpec(Path(n).stem, path=str(path)))
        elif n in bundled_records():
            out.append(RecordSpec(n, path=n))
        elif path.is_dir():  # (it was "neither a file nor a bundled record")
            raise _err(source, "records.names", f"{n!r} is a folder, expected record "
                       f'files (a folder: [records] folder = "{n}", glob = "*.AT2")')  # fmt: skip
        else:
            hint = did_you_mean(n, bundled_records())
            raise _err(source, "records.names", f"{n!r} is neither a file (looked for {path}) "
                       f"nor a bundled record{hint}; bundled: {bundled_records()}")  # fmt: skip
    where = [f"records.names[{i}] ({n!r})" for i, n in enumerate(names)]  # (each record's)

    def came(field: str) -> None:  # the records added since: from this field
        where.extend(f"{field} ({r.path or r.name})" for r in out[len(where) :])

    if "folder" in rec:
        folder = _resolve_path(study_dir, _check_type(source, "records.folder", rec["folder"], str))
        pattern = _check_type(source, "records.glob", rec.get("glob", "*"), str)
        if not folder.is_dir():
            raise _err(source, "records.folder", f"no such directory: {folder}")
        files = sorted(p for p in folder.glob(pattern) if p.is_file())
        if not files:
            raise _err(source, "records.folder", f"no file matches {pattern!r} in {folder}")
        out += [RecordSpec(p.stem, path=str(p)) for p in files]
        came("records.folder")
    elif "glob" in rec:
        raise _err(source, "records.glob", "applies to records.folder only")
    if "set" in rec:
        s = rec["set"]
        if s not in RECORD_SETS:
            raise _err(source, "records.set", f"expected one of {list(RECORD_SETS)}, got {s!r}")
        out += _record_set(source, s, kind)
        came("records.set")
    if "simulated" in rec:
        out += _simulated(source, rec["simulated"], kind)
        came("records.simulated")
    if "pairs" in rec:
        if kind not in PAIR_KINDS:
            raise _err(source, "records.pairs", f"records of several components need a scene "
                       f"of kind {', '.join(PAIR_KINDS[:-1])} or {PAIR_KINDS[-1]}, this "
                       f"study's scene is {kind!r}")  # fmt: skip
        from nsdyn.studies.scenes3c import parse_pairs

        out += parse_pairs(source, study_dir, rec["pairs"])
        came("records.pairs")
    if kind in KINDS3C:
        from nsdyn.studies.scenes3c import check_two_components

        check_two_components(source, out)
    seen: dict = {}
    for k, r in enumerate(out):  # (a record's name is its file's stem: two folders' a.AT2)
        if r.name in seen:
            raise _err(source, "records", f"record name {r.name!r} appears twice: "
                       f"{where[seen[r.name]]} and {where[k]}; expected each record once "
                       "(names are the files' stems)")  # fmt: skip
        seen[r.name] = k
    if not out and not base.get("motion") and kind != "isolated":
        raise _err(source, "records", "no records and the scene names none")
    return out


def _record_set(source: str, s: str, kind: str) -> list[RecordSpec]:
    from nsdyn.ground import bundled_records, bundled_records3, default_shared_dir

    if kind in KINDS3C and s == "kobe":  # (one horizontal component each: failed rows)
        raise _err(source, "records.set", "'kobe': one horizontal component each; a deck "
                   "or building3d study needs two: [records] pairs = [{name, x, y}]")  # fmt: skip
    if s == "bundled":  # (a two-component study: the bundled records that have two)
        return [RecordSpec(n, path=n) for n in (bundled_records3() if kind in KINDS3C
                                                  else bundled_records())]  # fmt: skip
    shared = default_shared_dir()
    d = shared and next((c for c in (shared / "records", shared) if (c / "raw").is_dir()), None)
    if d is None:
        raise _err(source, "records.set", "'kobe' needs the shared records (set NSDYN_SHARED)")
    return [
        RecordSpec("KJMA", path=str(d / "raw" / "kobe_kjma_000.AT2")),
        RecordSpec("Shin-Osaka", path=str(d / "converted" / "kobe_shi000_fema_p695.txt")),
        RecordSpec("Nishi-Akashi", path=str(d / "converted" / "kobe_nis000_fema_p695.txt")),
        RecordSpec("unidentified", path=str(d / "raw" / "kobe_unidentified_osm.dat")),
    ]


def _simulated(source: str, sim, kind: str = "") -> list[RecordSpec]:
    import numpy as np

    if not isinstance(sim, dict):
        raise _err(source, "records.simulated",
                   f"expected a table {{n = ..., seed = ...}}, got {sim!r}")  # fmt: skip
    for key in sim:
        if key not in SIMULATED_FIELDS:
            raise unknown_key(source, "records.simulated.", key, SIMULATED_FIELDS)
    for key in ("n", "seed"):
        if key not in sim:
            raise _err(source, f"records.simulated.{key}", "missing (required)")
    spec = {
        k: _check_type(source, f"records.simulated.{k}", v, SIMULATED_FIELDS[k])
        for k, v in sim.items()
    }
    if not 1 <= spec["n"] <= MAX_TASKS:  # (drawn before the grid's count is checked)
        raise _err(source, "records.simulated.n", f"expected an integer >= 1 and at most "
                   f"{MAX_TASKS} (a study's most tasks), got {spec['n']}")  # fmt: skip
    gen = spec.get("generator", GENERATORS[0])
    base = {"generator": gen, "duration": spec.get("duration", 20.0), "dt": spec.get("dt", 0.01)}
    try:  # (a step too coarse for the generator's noise: refused here, not in every row)
        noise_step(gen, base["duration"], base["dt"])
    except ValueError as e:
        key, _, text = str(e).partition(": ")
        raise _err(source, f"records.simulated.{key}", text) from None
    if kind == "cylinder":  # (their scale is not the scene's earthquake's: ten times below;
        # said once the table is checked, not before its error)
        importlib.import_module(scene_module(kind)).simulated_records_note(source)
    seeds = np.random.SeedSequence(spec["seed"]).generate_state(spec["n"])
    # names (and so task keys) that stay as n grows: three digits at least (the width of n
    # made a study grown from 40 to 200 records rename, and rerun, its first 40)
    width = max(RECORD_DIGITS, len(str(spec["n"] - 1)))
    return [
        RecordSpec(f"{gen[:2]}-{i:0{width}d}", simulated={**base, "seed": int(s)})
        for i, s in enumerate(seeds)
    ]


def _merge(base: dict, over: dict) -> dict:
    out = copy.deepcopy(base)
    for table, vals in over.items():
        out.setdefault(table, {}).update(vals)
    return out


def _base_scene(source: str, study_dir: Path, st: dict, base_over: dict,
                records: bool = False) -> tuple[str, dict]:  # fmt: skip
    """(kind, base cfg): the scene file (or the default scene) with [base] merged over it.
    With ``records``, the scene file's closed-form motion gives way to them as it does to
    ``nsdyn run --record`` (its keys, amplitude and t_end: the records run to their ends;
    :func:`nsdyn.models.scenefile.record_replaces_motion`); [base.motion] still sets them."""
    if not isinstance(base_over, dict) or not all(isinstance(v, dict) for v in base_over.values()):
        raise _err(source, "base", "expected scene tables, e.g. [base.motion] t_end = 20.0")
    scene_path, raw = None, {}
    if "scene" in st:
        scene_path = _resolve_path(study_dir, st["scene"])
        if not scene_path.is_file():
            raise _err(source, "study.scene", f"no such scene file: {scene_path}")
        raw = read_toml(scene_path)
    base_over = resolve_paths(base_over, study_dir, source)  # [base] files: beside the study file
    if "t_end" in base_over.get("motion", {}):  # a given end replaces the scene's periods
        for table in ("motion", "force"):
            raw.get(table, {}).pop("n_periods", None)
    merged = _merge(raw, base_over)  # (the scene's: beside the scene file, by read_toml)
    kind = scene_kind(merged, source)
    if records and isinstance(raw.get("motion"), dict) and record_replaces(kind):
        from nsdyn.models.scenefile import record_replaces_motion

        record_replaces_motion(kind, raw["motion"], record_replaces(kind), str(scene_path))
        merged = _merge(raw, base_over)
    if kind == "isolated":
        from nsdyn.models.isolated.scene import _check, as_recorded, load_scene, replaces_motion

        # each [base] table as merged over the scene's own (a harmonic scene's [base.motion]
        # n_periods was checked against a record's keys: its kind is the scene's); a motion
        # of another kind replaces the scene's, as load_scene's overrides do
        if replaces_motion(base_over, raw):
            merged = _merge({**raw, "motion": {}}, base_over)
        try:
            _check({t: merged.get(t, v) for t, v in base_over.items()}, f"{source}: [base]")
        except SceneError as e:  # ("[base]: [moton]: unknown table": the table's own name;
            msg = str(e).replace(f"{source}: [base]: [", f"{source}: [base.", 1)  # a field's
            raise SceneError(msg.replace(f"{source}: [base]: ", f"{source}: base.", 1)) from None
            # dotted path, as every other field of a study: "[base]: motion.kep")
        from nsdyn.models.isolated.system import isolation_from_config

        cfg = load_scene(scene_path, base_over)
        cfg.pop("_source", None)
        as_recorded(cfg, merged.get("motion", {}), records)  # (as `nsdyn run --record`)
        try:
            with warnings.catch_warnings():  # (its notes: said once by check_tasks)
                warnings.simplefilter("ignore", NotedWarning)
                isolation_from_config(cfg.get("isolation", {}), source)
        except ValueError as e:
            raise SceneError(str(e)) from None
        return kind, cfg
    return kind, merged


def load_study(path: str | Path) -> Study:
    """Read and check a study file (:class:`SceneError` naming the file and field)."""
    source = str(path)
    raw = read_toml(path, what="study")
    study_dir = Path(path).resolve().parent
    for table in raw:
        if table not in STUDY_TABLES:  # (a table, as a scene names it: "[studdy]")
            hint = did_you_mean(table, sorted(STUDY_TABLES)) or ";"
            raise SceneError(f"{source}: [{table}]: unknown table{hint} expected some of "
                             f"{sorted(STUDY_TABLES)}")  # fmt: skip
    st = raw.get("study", {})
    for key, val in st.items():
        if key not in STUDY_FIELDS:
            raise unknown_key(source, "study.", key, STUDY_FIELDS)
        _check_type(source, f"study.{key}", val, STUDY_FIELDS[key])
    keep = checked_keep(source, st.get("keep"), raw.get("parameters", {}))
    kind, base = _base_scene(source, study_dir, st, raw.get("base", {}))
    params_raw = raw.get("parameters", {})
    known, whole = _known_fields(kind, base), _integer_fields(kind)
    real = _integer_fields(kind, ("number", "number or pair", "number or list"))  # (a whole
    # value of these is the same number as a float: [2, 3] the tasks of [2.0, 3.0])
    params = [whole_numbers(source, parse_parameter(source, k, v, known), whole, real)
              for k, v in params_raw.items()]  # fmt: skip
    records = _parse_records(source, study_dir, raw.get("records", {}), kind, base)
    named = records or (kind == "isolated" and "motion.record" in params_raw)
    if named and (record_replaces(kind) or kind == "isolated"):  # the scene file's
        # closed-form motion gives way (an isolated scene's default pga: to records as recorded)
        kind, base = _base_scene(source, study_dir, st, raw.get("base", {}), records=True)
    if records and "motion.record" in params_raw:
        raise _err(source, "parameters.motion.record", "give records in [records], not both")
    mo = base.get("motion")
    motion_kind = mo.get("kind") if isinstance(mo, dict) else None
    if records and kind in KINDS3C and motion_kind not in (None, "record3", "orbit"):
        raise _err(source, "motion.kind", f"expected 'record3' (the kind [records] drive), "
                   f"got {motion_kind!r}")  # fmt: skip
    if records and motion_kind in ("orbit", "harmonic"):
        raise _err(source, "records", f"the scene's motion is harmonic ([motion] kind = "
                   f"{motion_kind!r}, its amplitudes in the scene); records drive a scene "
                   "whose motion is a record: drop [records], or vary the harmonic motion's "
                   "keys in [parameters]")  # fmt: skip
    replaced = record_replaces(kind) if records else ()
    base_motion = raw.get("base", {}).get("motion", {})
    for key in base_motion if isinstance(base_motion, dict) else ():  # (dropped silently)
        if key in replaced:
            raise _err(source, f"base.motion.{key}", "a key of the scene's closed-form motion, "
                       "which every record of [records] replaces; drop it, or drop "
                       "[records]")  # fmt: skip
    for name in params_raw:  # each task's record would drop the value the grid gave it
        if name.startswith("motion.") and name.split(".", 1)[1] in replaced:
            raise _err(source, f"parameters.{name}", "varies the scene's closed-form motion, "
                       "which every record of [records] replaces; vary it without [records], "
                       "or vary the records' scaling (motion.pga)")  # fmt: skip
    for name in params_raw:  # (the parameter's value wins in every task: said, not dropped)
        table, _, key = name.partition(".")
        given = raw.get("base", {}).get(table)
        if isinstance(given, dict) and key in given:
            warnings.warn(f"{source}: base.{name} = {given[key]!r} not used: parameters.{name} "
                          "gives every task its value", InputWarning, stacklevel=2)  # fmt: skip
    samples = st.get("samples", 0)
    if any(p.random for p in params) and samples < 1:
        raise _err(source, "study.samples", "random parameters need samples >= 1")
    if samples >= 1 and not any(p.random for p in params):  # (ignored without a word)
        raise _err(source, "study.samples", f"{samples} draws of no random parameter; give "
                   "one (e.g. { uniform = [a, b] }) or drop samples")  # fmt: skip
    study = Study(
        source=source,
        name=st.get("name", Path(path).stem),
        kind=kind,
        base=base,
        parameters=params,
        records=records,
        keep=keep,
        samples=samples,
        seed=st.get("seed", 0),
        batch=st.get("batch", 0),
        analysis=raw.get("analysis", {}),
    )
    if study.n_tasks > MAX_TASKS:
        raise _err(source, "parameters", f"{study.n_tasks} tasks (more than {MAX_TASKS})")
    from nsdyn.studies.analyses import check_analysis
    from nsdyn.studies.tasks import check_tasks

    check_analysis(study)
    check_tasks(study)
    return study


def record_replaces(kind: str) -> tuple:
    """The [motion] keys a record replaces in a scene of ``kind`` (its scene module's
    ``RECORD_REPLACES``: a rocking pulse's, a contact sine's, a simulated earthquake's)."""
    if kind not in ("rocking", "contact", "cylinder"):
        return ()
    return importlib.import_module(scene_module(kind)).RECORD_REPLACES


def task_label(index, params: dict, record: str = "") -> str:
    """``task 3 (isolation.mu = 0.02, record kobe)``: which task, with its values."""
    vals = [f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v!r}" for k, v in params.items()]
    if record:
        vals.append(f"record {record}")
    return f"task {index}" + (f" ({', '.join(vals)})" if vals else "")


def is_finite_number(v) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
