"""Built models kept on disk between runs, as numba keeps compiled kernels.

A scene's run builds its model (the frame's assembly, the Craig–Bampton reduction, the static
state under gravity; for a 3D building its pair system) before it integrates; run again, it
loads the model it built. The entry is named by the SHA-256 of what the model is built from
(its inputs, pickled: a dataclass by its fields), of nsdyn's own
sources and of the numpy and SciPy versions, so any change of an input, of the code or of
the linear algebra builds anew; the model is the pickled object, loaded as it was stored
(its arrays bit for bit, so a run from it equals a run from a fresh build bit for bit).

A model is stored only when its build emitted no warning (a run from the cache would not
repeat it), and only up to :data:`MAX_ENTRY_BYTES`; the folder keeps the :data:`MAX_ENTRIES`
most recently used. Written to a temporary file, then renamed: a reader never sees half an
entry, and an entry that fails to load is a miss (and is removed). The folder is
``NSDYN_MODEL_CACHE`` when set (``0``: no cache), else ``nsdyn/models`` in the user's cache
folder (``$XDG_CACHE_HOME``, else ``~/.cache``). Its entries are pickles: like numba's cache,
it trusts what the user's own cache folder holds.
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
import pickle
import tempfile
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

T = TypeVar("T")

ENV = "NSDYN_MODEL_CACHE"  # a folder; "0" (or empty): no model cache
MAX_ENTRIES = 64
MAX_ENTRY_BYTES = 64 * 2**20
SUFFIX = ".model.pickle"

_SOURCES: list[str] = []  # the digest of nsdyn's sources, computed once per process


def folder() -> Path | None:
    """The cache folder (None: the cache is off)."""
    given = os.environ.get(ENV)
    if given is not None:
        return None if given.strip() in ("", "0") else Path(given)
    base = os.environ.get("XDG_CACHE_HOME")
    if not base:
        home = os.path.expanduser("~")
        if home.startswith("~"):  # no home folder known: no cache (never a "~" folder here)
            return None
        base = os.path.join(home, ".cache")
    return Path(base) / "nsdyn" / "models"


def sources_digest() -> str:
    """SHA-256 of nsdyn's Python sources (paths and contents) and of the numpy and SciPy
    versions, found without importing SciPy."""
    if _SOURCES:
        return _SOURCES[0]
    import importlib.util

    import numpy as np

    root = os.path.dirname(os.path.abspath(__file__))
    paths = []
    for top, dirs, files in os.walk(root):
        dirs[:] = [d for d in dirs if d != "__pycache__"]  # numba's and Python's caches: unread
        paths += [os.path.join(top, f) for f in files if f.endswith(".py")]
    h = hashlib.sha256()
    for path in sorted(paths):
        h.update(os.path.relpath(path, root).encode())
        with open(path, "rb") as src:
            h.update(src.read())
    h.update(np.__version__.encode())
    spec = importlib.util.find_spec("scipy")
    if spec is not None and spec.origin:
        version = Path(spec.origin).with_name("version.py")
        h.update(version.read_bytes() if version.is_file() else spec.origin.encode())
    _SOURCES.append(h.hexdigest())
    return _SOURCES[0]


def _defining(x):
    """``x`` by what defines it: a dataclass instance as its class and fields (not what it
    computed and kept since, as a ``cached_property``), tuples and lists item by item."""
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        fields = tuple((f.name, _defining(getattr(x, f.name))) for f in dataclasses.fields(x))
        return (type(x).__module__, type(x).__qualname__, fields)
    if type(x) in (tuple, list):
        return type(x)(_defining(v) for v in x)
    return x


def key(kind: str, inputs) -> str:
    """The entry name of a model of ``kind`` built from ``inputs`` (picklable; dataclasses
    count by their fields)."""
    h = hashlib.sha256(kind.encode())
    h.update(sources_digest().encode())
    h.update(pickle.dumps(_defining(inputs), protocol=5))
    return h.hexdigest()


def load(name: str):
    """The model stored under ``name``; None when there is none or it cannot be loaded."""
    where = folder()
    if where is None:
        return None
    path = where / (name + SUFFIX)
    try:
        data = path.read_bytes()
    except OSError:
        return None
    try:
        model = pickle.loads(data)
    except Exception:  # noqa: BLE001  (a damaged or foreign entry: build anew)
        path.unlink(missing_ok=True)
        return None
    try:
        os.utime(path)  # most recently used: kept longest
    except OSError:
        pass
    return model


def store(name: str, model) -> bool:
    """Store ``model`` under ``name`` (True when stored); never raises for the cache's sake."""
    where = folder()
    if where is None:
        return False
    try:
        data = pickle.dumps(model, protocol=5)
    except Exception:  # noqa: BLE001  (a model that does not pickle is not cached)
        return False
    if len(data) > MAX_ENTRY_BYTES:
        return False
    try:
        where.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=where, prefix=".tmp-", suffix=SUFFIX)
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(data)
            os.replace(tmp, where / (name + SUFFIX))
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
        _prune(where)
    except OSError:  # a read-only or full disk: run without the cache
        return False
    return True


def _prune(where: Path) -> None:
    entries = []
    for p in where.glob("*" + SUFFIX):
        if p.name.startswith(".tmp-"):
            continue
        try:
            entries.append((p.stat().st_mtime, p))
        except OSError:
            pass
    entries.sort(reverse=True)
    for _, p in entries[MAX_ENTRIES:]:
        p.unlink(missing_ok=True)


def cached_build(kind: str, inputs, build: Callable[[], T], prepare=None) -> T:
    """The model of ``kind`` built from ``inputs``: loaded from the cache, else ``build()``,
    then ``prepare(model)`` (work a run would do later, done once before storing: the static
    state), then stored when nothing warned. The build's warnings reach the caller as usual."""
    name = key(kind, inputs)
    model = load(name)
    if model is not None:
        return model
    caught: list = []
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            model = build()
            ready = True
            if prepare is not None:
                try:
                    prepare(model)
                except Exception:  # noqa: BLE001  (the run reports it where it needs it)
                    ready = False
    finally:  # also when the build fails: the caller's filters decide, as if not caught
        for w in caught:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno, source=w.source)
    if ready and not caught:
        store(name, model)
    return model
