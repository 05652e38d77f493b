"""Cached kernels loaded without numba's compile-time registries
(:func:`nsdyn._numba_light.light_loads`).

What must hold: a kernel loaded from the on-disk cache in a new process runs and returns the
numbers the compiled one returned, with its runtime (allocations freed) and numba's helpers
(math, exceptions) resolved, while numba's compiler contexts are never refreshed for the
load, and numba's implementation modules are not imported for the environments of the
functions it generated (an allocation); a kernel compiled afterwards in the same process
still compiles (the compiler refreshes the contexts itself), and the entries a process with
the light loads saves load in a process with plain numba; the writable cache folder is
checked once for all the kernels in it, not once per kernel; with plain numba the loader
and the checks are numba's own.
"""

import json
import os
import subprocess
import sys
import textwrap

import pytest

JIT = os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")

KERNELS = """
import math
import numpy as np
from numba import njit


@njit(cache=True, error_model="numpy")
def grown(x):
    out = np.empty(2 * x.size)  # numba's runtime allocates it (NRT)
    for i in range(x.size):
        out[2 * i] = math.sin(x[i])
        out[2 * i + 1] = math.exp(x[i])
    return out


@njit(cache=True, error_model="numpy")
def checked(x):
    if x < 0.0:
        raise ValueError("negative")  # numba's helpers rebuild the exception
    return math.sqrt(x)
"""

PROBE = """
import json, sys
import numpy as np
from numba.core import base
from numba.core.runtime import rtsys
calls = []
full = base.BaseContext.refresh
def counted(self):
    calls.append(1)
    return full(self)
base.BaseContext.refresh = counted
from nsdyn import _numba_light as nc
installed = nc.light_loads()
sys.path.insert(0, sys.argv[1])
import tempfile
checks = []
made = tempfile.TemporaryFile
def counted_file(*a, **k):
    checks.append(k.get("dir"))
    return made(*a, **k)
tempfile.TemporaryFile = counted_file
import kern  # its two kernels' dispatchers: numba checks their cache folder is writable
tempfile.TemporaryFile = made
x = np.linspace(0.0, 1.0, 7)
kern.grown(x)  # loaded (and numba's runtime started, its statistics with it)
stats0 = rtsys.get_allocation_stats()
y = kern.grown(x)
del y
stats1 = rtsys.get_allocation_stats()
try:
    kern.checked(-1.0)
    raised = ""
except ValueError as e:
    raised = str(e)
root = float(kern.checked(2.0))
loads_refreshed = len(calls)
impl_imported = "numba.np.arrayobj" in sys.modules
from numba import njit
@njit
def fresh(a):
    out = np.empty(a.size)  # an allocation again: its environment may be the loaded one
    out[:] = a * 0.5
    return np.sum(out)  # compiled now: needs the registries (numba's array math)
z = [fresh(np.ones(3))] if sys.argv[2] == "1" else [1.5]
print(json.dumps({"installed": installed, "loads_refreshed": loads_refreshed,
    "grown": kern.grown(x).tolist(), "raised": raised, "root": root,
    "allocs": stats1.alloc - stats0.alloc, "frees": stats1.free - stats0.free,
    "fresh": [float(v) for v in z], "refreshed_after": len(calls) > loads_refreshed,
    "folder_checks": len(checks), "impl_imported": impl_imported}))
"""


def _probe(tmp_path, plain: bool, compile_after: bool, fill_light: bool = False) -> dict:
    mod = tmp_path / "mod"
    mod.mkdir(exist_ok=True)
    (mod / "kern.py").write_text(textwrap.dedent(KERNELS))
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"), NUMBA_NRT_STATS="1")
    env["NSDYN_PLAIN_NUMBA"] = "1" if plain else "0"
    fill = "import sys, numpy as np; sys.path.insert(0, sys.argv[1]); "
    if fill_light:  # the light loads installed while the kernels compile and are saved
        fill += "from nsdyn import _numba_light as nc; assert nc.light_loads(); "
    fill += "import kern; "
    fill += "kern.grown(np.zeros(3)); kern.checked(1.0)"
    fill_env = dict(env, NSDYN_PLAIN_NUMBA="0" if fill_light else env["NSDYN_PLAIN_NUMBA"])
    subprocess.run([sys.executable, "-c", fill, str(mod)], env=fill_env, check=True)
    argv = [sys.executable, "-c", PROBE, str(mod), "1" if compile_after else "0"]
    r = subprocess.run(argv, env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1])


@pytest.mark.skipif(not JIT, reason="nothing is loaded from a cache under NUMBA_DISABLE_JIT")
def test_a_cached_kernel_runs_without_a_refresh_and_later_compilations_still_work(tmp_path):
    import numpy as np

    r = _probe(tmp_path, plain=False, compile_after=True)
    assert r["installed"] is True
    assert r["loads_refreshed"] == 0  # the loads skipped numba's refresh
    x = np.linspace(0.0, 1.0, 7)
    want = np.empty(14)
    want[0::2], want[1::2] = np.sin(x), np.exp(x)
    # the same libm functions through numba's math symbols: equal to 1 ulp
    assert np.allclose(r["grown"], want, rtol=2.3e-16, atol=0.0)
    assert r["raised"] == "negative"
    assert r["root"] == np.sqrt(2.0)  # IEEE square root: exact
    assert r["allocs"] == r["frees"] >= 1  # the runtime freed what it allocated
    assert r["fresh"] == [1.5]  # 3 x 0.5, exact in binary
    assert r["refreshed_after"] is True  # the compilation refreshed the contexts itself
    assert r["folder_checks"] == 1  # one folder, checked once for both kernels
    assert r["impl_imported"] is False  # the allocation's environment rebuilt without it


@pytest.mark.skipif(not JIT, reason="nothing is loaded from a cache under NUMBA_DISABLE_JIT")
def test_plain_numba_keeps_numbas_own_loader(tmp_path):
    r = _probe(tmp_path, plain=True, compile_after=False)
    assert r["installed"] is False
    assert r["loads_refreshed"] >= 1
    assert r["folder_checks"] == 2  # numba checks the folder for each kernel
    assert r["raised"] == "negative"
    assert r["impl_imported"] is True  # numba imports the allocation's module for its globals


@pytest.mark.skipif(not JIT, reason="nothing is loaded from a cache under NUMBA_DISABLE_JIT")
def test_entries_saved_with_the_light_loads_load_with_plain_numba(tmp_path):
    """The environments a light process rebuilt are saved again by numba's own rebuild's
    name, so a cache filled beside the light loads is an ordinary numba cache."""
    import numpy as np

    r = _probe(tmp_path, plain=True, compile_after=True, fill_light=True)
    x = np.linspace(0.0, 1.0, 7)
    assert np.allclose(r["grown"][0::2], np.sin(x), rtol=2.3e-16, atol=0.0)
    assert r["root"] == np.sqrt(2.0) and r["fresh"] == [1.5]
