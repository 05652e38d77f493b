"""The compile helper started early (:func:`nsdyn._numba_cache.start_standby`).

What must hold: the cheap guess "numba's cache never held this package's kernels" looks where
numba itself keeps them (its cache locator, read back from a dispatcher) and turns False once
one kernel is cached there; a standby process runs the target the first :class:`Helper` of the
process hands it (the same process: its imports are done) and is ended at once when released
unused; the ``nsdyn`` script starts one only for the commands that compile with a helper and
only into such a cache.
"""

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from nsdyn import _numba_cache as nc
from nsdyn._numba_cache import HELPER_ENV, Helper

JIT = os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")
SOLVE = Path(nc.__file__).parent / "solve" / "__init__.py"


@pytest.fixture
def helpers_allowed(monkeypatch):
    monkeypatch.setenv(HELPER_ENV, "1")
    if not nc.helper_enabled():
        pytest.skip("a helper process needs two usable cores and numba compiling")
    yield
    nc.release_standby()


@pytest.mark.skipif(not JIT, reason="no dispatcher cache under NUMBA_DISABLE_JIT")
def test_cache_folder_is_where_numba_keeps_the_kernels():
    # numba's own cache locator, read back from a cached kernel of the package
    from nsdyn.solve import _kradau

    assert nc.cache_folder(_kradau.__file__) == Path(_kradau.restart._cache._cache_path)


PROBE = (
    "from pathlib import Path\n"
    "import numpy as np\n"
    "from nsdyn import _numba_cache as nc\n"
    "from nsdyn.solve import _kradau\n"
    "f = Path(nc.__file__).parent / 'solve' / '__init__.py'\n"
    "before = nc.never_compiled(f)\n"
    "same = nc.cache_folder(f) == Path(_kradau.restart._cache._cache_path)\n"
    "_kradau.restart(np.zeros(_kradau.N_CTL))\n"
    "print(before, same, nc.never_compiled(f))\n"
)


@pytest.mark.skipif(not JIT, reason="nothing is cached under NUMBA_DISABLE_JIT")
def test_a_cache_never_compiled_into_until_one_kernel_is(tmp_path):
    # with NUMBA_CACHE_DIR (the other locator): an empty cache is "never compiled", and one
    # kernel of the package cached there ends it
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    out = subprocess.run(
        [sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, check=True
    )
    assert out.stdout.split() == ["True", "True", "False"]


def test_an_unknown_cache_folder_is_no_guess(tmp_path, monkeypatch):
    # a source folder numba cannot write to (here as os.access reports it, whoever runs the
    # test): numba then keeps the cache elsewhere, so no guess is made
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    src = tmp_path / "pkg"
    src.mkdir()
    assert nc.cache_folder(src / "m.py") == src / "__pycache__"  # writable: beside it
    assert nc.never_compiled(src / "m.py")  # and nothing there yet
    monkeypatch.setattr(nc.os, "access", lambda path, mode: False)
    assert nc.cache_folder(src / "m.py") is None
    assert not nc.never_compiled(src / "m.py")


def test_a_helper_takes_the_standby_and_runs_its_target(helpers_allowed):
    assert nc.start_standby("json")
    pid = nc._STANDBY.pid
    with Helper("nsdyn._numba_cache:helper_enabled") as h:
        assert h.proc.pid == pid  # the standby, not a new process
    assert h.close() == 0
    assert nc._STANDBY is None
    # the next helper is a new process; a target that fails is reported as for any helper
    assert nc.start_standby("json")
    with Helper("nsdyn.no_such_module:f") as h:
        pass
    assert h.close() not in (0, None)


def test_an_unused_standby_ends_when_released(helpers_allowed):
    assert nc.start_standby("json")
    assert not nc.start_standby("json")  # one at a time
    proc = nc._STANDBY
    nc.release_standby()
    # ended by the release itself, not left to finish its imports and read its input's end
    assert proc.returncode == -signal.SIGKILL
    assert nc._STANDBY is None


def test_a_standby_whose_process_ended_is_replaced(helpers_allowed):
    assert nc.start_standby("json")
    nc._STANDBY.kill()
    nc._STANDBY.wait()
    with Helper("nsdyn._numba_cache:helper_enabled") as h:
        pass
    assert h.close() == 0  # a new helper ran the target


def test_no_standby_where_no_helper_may_run(monkeypatch):
    monkeypatch.setenv(HELPER_ENV, "0")
    assert not nc.start_standby("json")
    assert nc._STANDBY is None


@pytest.mark.parametrize(
    "argv, never, preload",
    [
        (["run", "--t-end", "5"], True, "nsdyn.solve.compile_split"),
        (["study", "s.toml"], True, "nsdyn.solve.compile_split"),
        (["sweep", "--points", "5"], True, "nsdyn.periodic.problem"),
        (["run"], False, None),  # the cache held the package's kernels: the usual helper
        (["run", "--help"], True, None),
        (["bench", "speed"], True, None),  # no helper of its own
        ([], True, None),
    ],
)
def test_the_script_starts_a_standby_for_a_compiling_command_into_a_fresh_cache(
    monkeypatch, argv, never, preload
):
    from nsdyn.cli import app

    started = []
    monkeypatch.setattr(nc, "never_compiled", lambda f: never)
    monkeypatch.setattr(nc, "start_standby", lambda p: started.append(p))
    app._start_standby(argv)
    assert started == ([preload] if preload else [])
