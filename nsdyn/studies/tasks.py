"""Expansion of a study into tasks, the key of each task, and batches of tasks.

A task is one scene run: the base scene with one value of every parameter and one record.
Its key is the first ``KEY_HEX`` hex digits of

    sha256(canonical JSON of {format, kind, scene cfg, record identity, record file digest,
                              the kept fields})

so the key changes whenever anything the row depends on changes (a parameter, a base field, a
record file's bytes, the bytes of any other file the scene names: a frame file, a record named
in the base scene, the set of ``study.keep``'s names) and never otherwise: the results table
is keyed by it and a resumed study runs exactly the tasks whose keys it lacks. Random
parameters are drawn here, in the main process, each from its own stream
``numpy.random.default_rng([study.seed, crc32(name)])``: raising ``samples`` keeps the values
drawn before (one stream for all shifted every parameter after the first), and the drawn
values enter the key.

Order: grid values (first parameter slowest) x samples x records (fastest), so the records of
one design sit next to each other; batches are consecutive runs of that order.
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import json
import math
import re
import zlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from nsdyn._checks import expect
from nsdyn.models.scenefile import FILE_FIELDS, SceneError
from nsdyn.studies.study import KINDS3C, RecordSpec, Study, task_label

CYLINDER_FILES = ("record", "record_y", "record_z")  # a cylinder's component files

TABLE_FORMAT = 1  # bump when the meaning of a task's inputs changes (invalidates old keys)
KEY_HEX = 16  # hex digits of the task key (64 bits: collisions negligible below 1e8 tasks)
BATCHES_PER_WORKER = 6  # automatic batching: about this many batches per worker (balance)
MAX_AUTO_BATCH = 64  # automatic batching: at most this many tasks per batch (loss on a kill)
_DIGEST_CHUNK = 1 << 20  # bytes per read when hashing record files


@dataclass(frozen=True)
class Task:
    """One run: ``cfg`` is the complete scene; ``params`` the varied fields' values."""

    index: int
    key: str
    kind: str
    cfg: dict
    params: dict
    sample: int = -1
    record: RecordSpec | None = None
    source: str = "<study>"
    keep: tuple | None = None
    extra: dict = field(default_factory=dict)

    def columns(self) -> dict:
        """The input columns of this task's row."""
        row = {"index": self.index, "key": self.key, "record": self.record_name}
        if self.sample >= 0:
            row["sample"] = self.sample
        row.update(self.params)
        return row

    @property
    def record_name(self) -> str:
        if self.record is not None:
            return self.record.name
        return str(self.cfg.get("motion", {}).get("record", ""))


def file_digest(path: str | Path) -> str:
    """sha256 of a file's bytes (hex)."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        while chunk := fh.read(_DIGEST_CHUNK):
            h.update(chunk)
    return h.hexdigest()


def _canonical(obj) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), allow_nan=True, default=str)


def task_key(kind: str, cfg: dict, record: dict | None, keep=None, ordered=False) -> str:
    """The hash of a task's inputs (see the module docstring), the kept fields among them
    (a row holds them: a study whose ``keep`` gains or loses a field runs its tasks again; one
    whose ``keep`` is only reordered does not, the set of fields is hashed; ``ordered``: the
    key of tables written when the order was hashed, under which their rows are found)."""
    keep = None if keep is None else list(keep) if ordered else sorted(keep)
    payload = {"format": TABLE_FORMAT, "kind": kind, "cfg": cfg, "record": record, "keep": keep}
    return hashlib.sha256(_canonical(payload).encode()).hexdigest()[:KEY_HEX]


def _draw(study: Study) -> list[dict]:
    """``samples`` joint draws of the random parameters (empty dicts if there are none)."""
    rand = [p for p in study.parameters if p.random]
    if not rand:
        return [{}]
    cols = {}
    for p in rand:  # (one stream per parameter: more samples keep the first ones' values)
        rng = np.random.default_rng([study.seed, zlib.crc32(p.name.encode())])
        a, b = p.args
        n = study.samples
        if p.law == "uniform":
            v = rng.uniform(a, b, n)
        elif p.law == "loguniform":
            v = np.exp(rng.uniform(math.log(a), math.log(b), n))
        elif p.law == "normal":
            v = rng.normal(a, b, n)
        else:  # lognormal: median a, log-standard deviation b
            v = a * np.exp(b * rng.standard_normal(n))
        cols[p.name] = [float(x) for x in v]
    return [{k: cols[k][i] for k in cols} for i in range(study.samples)]


def _set(cfg: dict, dotted: str, value) -> None:
    table, key = dotted.split(".", 1)
    cfg.setdefault(table, {})[key] = value


def expand(study: Study) -> list[Task]:
    """Every task of ``study`` in table order, keys computed."""
    grid = [p for p in study.parameters if not p.random]
    draws = _draw(study)
    records: list[RecordSpec | None] = list(study.records) or [None]
    digests = {}
    for r in records:
        if r is not None and r.components is not None:  # the digest of the components' digests
            parts = [file_digest(f) if f else "-" for f in r.components]
            digests[r.name] = hashlib.sha256(",".join(parts).encode()).hexdigest()
        elif r is not None and r.path is not None and Path(r.path).is_file():
            digests[r.name] = file_digest(r.path)
    file_digests: dict[str, str] = {}  # every other file a task reads, hashed once
    tasks = []
    keep = tuple(study.keep) if study.keep is not None else None
    for values in itertools.product(*[p.values for p in grid]):
        for s, draw in enumerate(draws):
            for rec in records:
                cfg = copy.deepcopy(study.base)
                params = dict(zip([p.name for p in grid], values, strict=True))
                params.update(draw)
                for name, v in params.items():
                    _set(cfg, name, v)
                ident = None
                if rec is not None:
                    ident = rec.identity() | {"sha256": digests.get(rec.name)}
                    ident["path"] = None if rec.name in digests else rec.path  # bytes, not place
                    if rec.components is not None:
                        ident["components"] = None
                    _place_record(cfg, rec, study.kind)
                hashed = _files_by_bytes(_without_path(cfg, rec, digests), file_digests)
                key = task_key(study.kind, hashed, ident, study.keep)
                old = task_key(study.kind, hashed, ident, study.keep, ordered=True)
                tasks.append(
                    Task(
                        index=len(tasks),
                        key=key,
                        kind=study.kind,
                        cfg=cfg,
                        params=params,
                        sample=s if draw else -1,
                        record=rec,
                        source=study.source,
                        keep=keep,
                        extra={"ordered_key": old} if old != key else {},
                    )
                )
    return tasks


def _place_record(cfg: dict, rec: RecordSpec, kind: str) -> None:
    """Put ``rec`` into the task's ``[motion]``: ``record`` (a file or bundled name), the
    component files of a record of several components, or ``simulated``; for the kinds of
    two-component records (``deck``, ``building3d``) the other ways are removed, ``kind =
    "record3"`` is set and the files are ``x, y[, z]``; a cylinder's are ``record, record_y[,
    record_z]``, and the base scene's second and vertical files never join another record; a
    closed-form motion's keys (a rocking pulse, a contact sine, a cylinder's simulated
    earthquake: the scene module's ``RECORD_REPLACES``) give way to the record."""
    mo = cfg.setdefault("motion", {})
    from nsdyn.studies.study import record_replaces

    for key in record_replaces(kind):  # (a study varies none of them: load_study refuses it)
        mo.pop(key, None)
    if kind in KINDS3C:
        for key in ("record", "x", "y", "z", "simulated"):
            mo.pop(key, None)
        mo["kind"] = "record3"
    if kind == "cylinder":
        for key in ("record_y", "record_z"):
            mo.pop(key, None)
    if rec.components is not None:
        keys = CYLINDER_FILES if kind == "cylinder" else ("x", "y", "z")
        for key, f in zip(keys, rec.components, strict=True):
            if f is not None:
                mo[key] = f
    elif rec.path is not None:
        mo["record"] = rec.path
    else:
        mo.pop("record", None)
        mo["simulated"] = dict(rec.simulated)


def _without_path(cfg: dict, rec: RecordSpec | None, digests: dict) -> dict:
    """The cfg as hashed: a record file enters by its digest, so moving a folder keeps keys."""
    if rec is None or rec.name not in digests:
        return cfg
    out = copy.deepcopy(cfg)
    if rec.components is not None:
        for key, f in out["motion"].items():
            if isinstance(f, str) and f in rec.components:
                out["motion"][key] = f"sha256:{digests[rec.name]}:{key}"
        return out
    out["motion"]["record"] = f"sha256:{digests[rec.name]}"
    return out


def _files_by_bytes(cfg: dict, digests: dict) -> dict:
    """The cfg as hashed: every file it names (:data:`~nsdyn.models.scenefile.FILE_FIELDS`: a
    frame file, a record named in the base scene) enters by its bytes' digest, so an edit of
    the file runs the tasks again (``digests``: path -> digest, filled as files are met)."""
    out = None
    for table, key in FILE_FIELDS:
        v = cfg.get(table, {}).get(key) if isinstance(cfg.get(table), dict) else None
        if not isinstance(v, str) or v.startswith("sha256:") or not Path(v).is_file():
            continue
        if v not in digests:
            digests[v] = file_digest(v)
        out = copy.deepcopy(cfg) if out is None else out
        out[table][key] = f"sha256:{digests[v]}"
    return cfg if out is None else out


def batch_size(n_tasks: int, n_workers: int, requested: int = 0) -> int:
    """Tasks per batch: ``requested`` if positive, else about BATCHES_PER_WORKER per worker."""
    if requested > 0:
        return requested
    per = math.ceil(n_tasks / max(1, n_workers * BATCHES_PER_WORKER))
    return int(min(MAX_AUTO_BATCH, max(1, per)))


def batches(tasks: list[Task], size: int) -> list[list[Task]]:
    """Consecutive runs of ``size`` tasks."""
    return [tasks[i : i + size] for i in range(0, len(tasks), size)]


NOT_USED = re.compile(r"^(\[?[\w.]+\]?(?:, \[?[\w.]+\]?)*) not used\b")  # "[bearing] not used: …"


def _unused_keys(note: str) -> str:
    """The keys or tables a "… not used: why" note is about ("" for any other note, as the
    record's "column(s) 2 not used", which is said for the study)."""
    m = NOT_USED.match(note)
    return m.group(1) if m else ""


def check_tasks(study: Study) -> None:
    """Every task's complete scene checked as ``nsdyn run`` checks a scene file, before any
    runs: a bad parameter value or record is a :class:`SceneError` naming the study file, the
    task and the field, not a column of failed rows. A parameter no task reads (every task's
    scene notes it as not used: a Moreau-Jean step under the event method, springs on a fixed
    base) is refused too: its values would repeat one run."""
    import warnings

    from nsdyn._checks import InputWarning
    from nsdyn.studies.scenes import check_scene

    for p in study.parameters:  # (a study changed in Python: no tasks, an empty table)
        if not p.random and not p.values:
            raise SceneError(f"{study.source}: parameters.{p.name}: expected a non-empty list "
                             "of values, got []")  # fmt: skip
    read = {p.name: [] for p in study.parameters}  # per parameter: a task that reads it
    # the whole key in a note (solver.h is not solver.h_max), or its table ("[bearing] not
    # used"), compiled once for every task
    keys = {n: re.compile(rf"(?<![\w.]){re.escape(n)}(?![\w.])|\[{re.escape(n.split('.')[0])}\]")
            for n in read}  # fmt: skip
    other: dict[str, int] = {}  # a note that is not about keys: the tasks it holds for
    dead: dict[str, int] = {}  # a note about keys no parameter varies (said if every task's)
    tasks = expand(study)
    with warnings.catch_warnings(record=True) as said:  # a record's units: once here (the
        warnings.simplefilter("always")  # runs do not repeat them), as every other warning
        for task in tasks:
            label = task_label(task.index, task.params, task.record_name)
            cfg = {**task.cfg, "_varied": list(read)} if task.kind == "isolated" else task.cfg
            notes = check_scene(cfg, f"{study.source}: {label}")  # (varied keys: given)
            about = {n: _unused_keys(n) for n in notes}  # (the keys a note is about: not
            for name, why in read.items():  # a key its reason names, "as [motion] record_y")
                unused = [n for n, k in about.items() if k and keys[name].search(k)]
                why.append(unused[0] if unused else None)
            for n, k in about.items():  # (a [base] key no task reads: below)
                other[n] = other.get(n, 0) + (not k)
                dead[n] = dead.get(n, 0) + bool(k and not any(r.search(k) for r in keys.values()))
    for text, category in dict.fromkeys((str(w.message), w.category) for w in said):
        warnings.warn(text, category, stacklevel=2)
    other.update({n: c for n, c in dead.items() if c == len(tasks)})  # ([bearing] beside a
    for note, count in other.items():  # fixed rung and a rigid: read by some, not said)
        if count:  # (a cb model without modes: said, not hidden in rows)
            warnings.warn(f"{study.source}: {count} of {len(tasks)} tasks: {note}",
                          InputWarning, stacklevel=2)  # fmt: skip
    for name, why in read.items():  # every task repeats one run: its values change nothing
        if why and all(why):
            raise SceneError(f"{study.source}: parameters.{name}: no task reads it ({why[0]}); "
                             "its values would repeat one run")  # fmt: skip
        if any(why):  # (some: a fixed rung beside an isolated one ran its radii twice)
            n, first = sum(map(bool, why)), next(w for w in why if w)
            warnings.warn(f"{study.source}: parameters.{name}: {n} of {len(why)} tasks do not "
                          f"read it ({first}); their values of it repeat one run",
                          InputWarning, stacklevel=2)  # fmt: skip
    seen: dict[str, Task] = {}
    for t in tasks:  # (a value given twice past load_study, by a caller's replace())
        if t.key in seen:
            raise SceneError(f"{study.source}: parameters: tasks {seen[t.key].index} and "
                             f"{t.index} are one run ({t.params}); expected distinct "
                             "values")  # fmt: skip
        seen[t.key] = t
    study.__dict__["_checked"] = _as_checked(study)


def _as_checked(study: Study) -> str:
    """What of ``study`` its check read (base, parameters, records, draws)."""
    return _canonical([study.kind, study.base, study.parameters, study.records, study.keep,
                      study.samples, study.seed])  # fmt: skip


def ensure_checked(study: Study) -> None:
    """:func:`check_tasks` unless ``study`` is as it was checked: a study changed after
    :func:`~nsdyn.studies.study.load_study` is checked again (its analyses are checked where
    they run: a narrowed grid may leave out a design's reference). Anything but a Study is a
    TypeError saying how to make one (a file's path was an AttributeError)."""
    expect("study", study, isinstance(study, Study), "a Study (nsdyn.load_study(path) reads one)")
    if study.__dict__.get("_checked") != _as_checked(study):
        check_tasks(study)
