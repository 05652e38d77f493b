"""The model cache (:mod:`nsdyn._model_cache`): a scene's model built once, loaded after.

What must hold: a model loaded from the cache is the built one bit for bit (its matrices, its
static state) and so is a run from it; its name follows every input and nsdyn's sources; a
build that warns is not stored and its warning still reaches the caller; a damaged entry is a
miss and is removed; the cache can be turned off; it keeps only the most recent entries; and
a scene run from the cache imports none of SciPy's linear algebra (the point of it).
"""

import json
import os
import subprocess
import sys
import warnings
from dataclasses import replace

import numpy as np
import pytest

from nsdyn import _model_cache as mc
from nsdyn.models.isolated.scene import build_scene_run, load_scene, with_isolation_cached
from nsdyn.solve.transient import simulate

JIT = os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv(mc.ENV, str(tmp_path / "models"))
    return tmp_path / "models"


def _entries(folder):
    return sorted(folder.glob("*" + mc.SUFFIX)) if folder.is_dir() else []


def test_a_model_from_the_cache_is_the_built_one_bit_for_bit(cache):
    cfg = load_scene(None, {"motion": {"t_end": 1.0}})
    built, motion, _ = build_scene_run(cfg)
    assert len(_entries(cache)) == 1
    loaded, _, _ = build_scene_run(cfg)
    assert loaded is not built
    for name in ("M", "C", "K", "Gamma", "R", "D", "T"):
        assert np.array_equal(getattr(loaded, name), getattr(built, name)), name
    for a, b in zip(loaded.static_equilibrium(), built.static_equilibrium(), strict=True):
        assert np.array_equal(a, b)
    t = np.linspace(0.0, 1.0, 101)
    r1, r2 = simulate(built, motion, t_eval=t), simulate(loaded, motion, t_eval=t)
    assert np.array_equal(r1.x, r2.x)  # the same arrays, the same operations: the same bits
    # the event method's switch law: its own entry, the same model as a fresh build
    sw = with_isolation_cached(built, law="switch")
    assert sw.isolation.law == "switch" and len(_entries(cache)) == 2
    assert np.array_equal(with_isolation_cached(loaded, law="switch").K, sw.K)


def test_the_name_follows_every_input_and_the_sources(monkeypatch):
    from nsdyn.models.isolated.system import Isolation

    iso = Isolation(mu=0.03)
    base = mc.key("isolated-frame", ("office-11", iso, "cb", 5.0))
    assert base == mc.key("isolated-frame", ("office-11", Isolation(mu=0.03), "cb", 5.0))
    assert base != mc.key("isolated-frame", ("office-11", replace(iso, mu=0.031), "cb", 5.0))
    assert base != mc.key("isolated-frame", ("office-11", iso, "cb", 6.0))
    assert base != mc.key("isolated-frame", ("office-11", iso, "full", 5.0))
    assert base != mc.key("other-kind", ("office-11", iso, "cb", 5.0))
    monkeypatch.setattr(mc, "_SOURCES", ["another version of the sources"])
    assert base != mc.key("isolated-frame", ("office-11", iso, "cb", 5.0))


def test_a_build_that_warns_is_not_stored_and_still_warns(cache):
    def build():
        warnings.warn("a frame without damping", UserWarning, stacklevel=1)
        return np.arange(3.0)

    with pytest.warns(UserWarning, match="without damping"):
        out = mc.cached_build("test", ("warns",), build)
    assert np.array_equal(out, [0.0, 1.0, 2.0])
    assert _entries(cache) == []
    calls = []
    mc.cached_build("test", ("quiet",), lambda: calls.append(1) or np.ones(2))
    mc.cached_build("test", ("quiet",), lambda: calls.append(1) or np.ones(2))
    assert calls == [1] and len(_entries(cache)) == 1  # built once, then loaded


def test_a_damaged_entry_is_a_miss_and_is_removed(cache):
    name = mc.key("test", ("damaged",))
    cache.mkdir(parents=True)
    (cache / (name + mc.SUFFIX)).write_bytes(b"not a pickle")
    assert mc.load(name) is None
    assert _entries(cache) == []
    assert mc.cached_build("test", ("damaged",), lambda: [1, 2]) == [1, 2]
    assert mc.load(name) == [1, 2]
    assert [p.name for p in cache.iterdir() if p.name.startswith(".tmp-")] == []  # renamed


def test_the_cache_can_be_turned_off(monkeypatch, tmp_path):
    monkeypatch.setenv(mc.ENV, "0")
    assert mc.folder() is None
    assert mc.store("x", [1]) is False and mc.load("x") is None
    monkeypatch.delenv(mc.ENV)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert mc.folder() == tmp_path / "nsdyn" / "models"


def test_only_the_most_recent_entries_are_kept(cache, monkeypatch):
    monkeypatch.setattr(mc, "MAX_ENTRIES", 3)
    for i in range(5):
        assert mc.store(f"entry{i}", i)
        os.utime(cache / f"entry{i}{mc.SUFFIX}", (1e9 + i, 1e9 + i))  # distinct ages
    mc.store("entry5", 5)
    assert [p.name for p in _entries(cache)] == [f"entry{i}{mc.SUFFIX}" for i in (3, 4, 5)]


PROBE = """
import contextlib, io, json, sys
from nsdyn.cli.app import main
with contextlib.redirect_stdout(io.StringIO()):
    main(["run", "--t-end", "1", "--no-figures", "--out", sys.argv[1]])
print(json.dumps(sorted(m for m in ("scipy.linalg", "scipy.sparse") if m in sys.modules)))
"""


@pytest.mark.skipif(not JIT, reason="a cached start is numba's: nothing to load without the JIT")
def test_a_scene_run_from_the_cache_imports_no_scipy_linear_algebra(tmp_path, child_env):
    env = dict(child_env, **{mc.ENV: str(tmp_path / "models")})
    runs = []
    for i in range(2):
        r = subprocess.run(
            [sys.executable, "-P", "-c", PROBE, str(tmp_path / f"out{i}")],
            env=env,
            capture_output=True,
            text=True,
        )
        assert r.returncode == 0, r.stderr
        runs.append(json.loads(r.stdout.strip().splitlines()[-1]))
    assert runs[0] == ["scipy.linalg", "scipy.sparse"]  # the build: assembly, reduction
    assert runs[1] == []  # the model loaded: no assembly, no reduction, no static solve
    h0, h1 = (np.load(tmp_path / f"out{i}" / "run-histories.npz") for i in range(2))
    assert all(np.array_equal(h0[k], h1[k]) for k in h0.files)


def _arrays(obj) -> dict:
    return {k: v for k, v in vars(obj).items() if isinstance(v, np.ndarray)}


def test_a_3d_buildings_pair_system_from_the_cache_is_the_built_one(cache):
    from nsdyn.models.isolated.bearings import Bearing, Friction
    from nsdyn.models.isolated.building3d_scene import build_pairs
    from nsdyn.structure import Section3D, regular_building_3d

    col = Section3D(2.1e11, 8.1e10, 1e-2, 2e-4, 9e-5, 3e-5, 80.0)
    beam = Section3D(2.1e11, 8.1e10, 8e-3, 3e-4, 2e-5, 1e-6, 65.0)
    frame = regular_building_3d("mc", [5.0], [6.0], [4.0, 3.5], col, beam, beam, n_v=1, n_h=1,
                                floor_mass=[3e4, 2e4], zeta=0.05)  # fmt: skip
    fps = Bearing(Friction(0.05), radius=2.0)
    opts = {"f_max": 20.0, "min_mass": None, "base": "grid"}
    built = build_pairs(frame, fps, "cb", opts, "test")
    assert len(_entries(cache)) == 1
    loaded = build_pairs(frame, fps, "cb", opts, "test")
    assert loaded is not built and loaded.info["path"] == "dense"
    a, b = _arrays(built), _arrays(loaded)
    assert a.keys() == b.keys() and len(a) >= 3
    assert all(np.array_equal(a[k], b[k]) for k in a)
    build_pairs(frame, fps, "cb", dict(opts, f_max=30.0), "test")  # another cut-off: built
    assert len(_entries(cache)) == 2
