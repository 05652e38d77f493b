"""What a cached run imports: none of SciPy's linear algebra where the model does not need it.

Importing any SciPy module that the frame's assembly and reduction use imports SciPy's
array-API layer (~0.2 s of a cached start), and so does numba's ``numba.np.arraymath`` and
``numba.np.linalg``, which numba's loader imports for a cached kernel that uses one of numba's
array reductions (``np.argmin``, ``np.all``, ``np.sum``, ...) or a matrix product (``@``): both
check for SciPy's BLAS at import. The kernels of the deck, the cylinder and the contact body
write those out (``nsdyn._klinalg.argmin``, ``all_finite``, ``max_abs``, ``min_of``, ``dot3``,
``matvec``, ``tmatvec``); these tests check they agree with numpy's and that a cached run of
each scene (and of the default one) loads neither SciPy's linear algebra nor numba's array
math or linear algebra, nor numpy's masked arrays, nor numba's array implementations (whose
module numba imports for the environment of a kernel that allocates; the light loads rebuild
it without), nor the other integration methods' kernels.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from nsdyn._klinalg import all_finite, argmin, dot3, matvec, max_abs, min_of, tmatvec
from nsdyn._numba_light import PLAIN

JIT = os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")
SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"

floats = st.floats(allow_nan=True, allow_infinity=True, width=64)


@given(st.lists(st.sampled_from([0.0, -1.0, 2.5, -1.0, np.nan, np.inf, -np.inf]) | floats,
                min_size=1, max_size=12))  # fmt: skip
def test_the_written_out_reductions_are_numpys(values):
    x = np.array(values, dtype=float)
    assert argmin(x) == np.argmin(x)  # the first minimum, or the first NaN
    assert all_finite(x) == bool(np.all(np.isfinite(x)))
    np.testing.assert_array_equal(max_abs(x), np.max(np.abs(x)))  # equal, NaN where numpy's is
    np.testing.assert_array_equal(min_of(x), np.min(x))


finite = st.floats(min_value=-1e6, max_value=1e6, width=64)


@given(st.integers(1, 5), st.integers(1, 4), st.data())
def test_the_written_out_products_are_the_sums_in_order(n, m, data):
    A = np.array(data.draw(st.lists(finite, min_size=n * m, max_size=n * m))).reshape(n, m)
    x = np.array(data.draw(st.lists(finite, min_size=m, max_size=m)))
    u = np.array(data.draw(st.lists(finite, min_size=n, max_size=n)))
    # a sum of n terms in any order is within (n - 1) eps sum|terms| of the exact one (Higham,
    # Accuracy and Stability, eq. 3.5): BLAS's and the loop's may differ by twice that
    eps = np.finfo(float).eps
    bound = 2 * max(n, m) * eps * (np.abs(A) @ np.abs(x))
    assert np.all(np.abs(matvec(A, x) - A @ x) <= bound)
    bound = 2 * max(n, m) * eps * (np.abs(A.T) @ np.abs(u))
    assert np.all(np.abs(tmatvec(A, u) - A.T @ u) <= bound)
    w = np.abs(x) + 0.5
    assert dot3(x, w, x) == sum(x[i] * w[i] * x[i] for i in range(m))  # numba's np.sum's order


PROBE = """
import contextlib, io, json, sys
from nsdyn.cli.app import main
with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
    main([*json.loads(sys.argv[1]), "--no-figures", "--out", sys.argv[2]])
names = ("scipy.linalg", "scipy.sparse", "numba.np.arraymath", "numba.np.linalg", "numpy.ma",
         "numba.np.arrayobj",
         "nsdyn.solve._kevent", "nsdyn.solve._kunilateral", "nsdyn.solve._kgenalpha",
         "nsdyn.solve._klowrank", "nsdyn.solve._kdopri")
print(json.dumps([m for m in names if m in sys.modules]))
"""


@pytest.mark.skipif(not JIT or PLAIN, reason="a light cached start: with numba's JIT, not plain")
@pytest.mark.parametrize(
    "scene", ["", "deck-fps4-3c.toml", "cylinder-uplift.toml", "contact-seed002-A5.toml",
              "--method genalpha", "--method genalpha-lowrank", "sweep"]
)  # fmt: skip
def test_a_cached_run_loads_no_scipy_linear_algebra(scene, tmp_path, child_env):
    """Nor numpy's masked arrays (``numpy.ma``, ~20 ms), which numpy 2's ``np.unique`` and
    ``np.median`` and numba's own typeof of an array import, nor the kernel modules of the
    integration methods the run does not use (numba makes a dispatcher for each of their
    kernels at import); "" is the default scene (Radau IIA). Generalized-alpha's metrics call
    the system kernel by address without the event loop's modules; genalpha-lowrank on the
    default scene (13 coordinates: its dense backend) factors with numpy's LAPACK, not
    SciPy's, and its step's products are written out (numba's ``@`` calls SciPy's BLAS).
    "sweep" is two points of the default sweep (arctan law) in one worker: the switch model's
    period map balances its matrices with SciPy, imported only when a sweep uses it."""
    loaded = []
    if scene == "sweep":
        args = ["sweep", "--points", "2", "--amplitudes", "1", "--fmin", "0.5", "--fmax", "1",
                "--workers", "1"]  # fmt: skip
        uses = set()
    elif scene.startswith("--"):
        uses = {"nsdyn.solve._kgenalpha", "nsdyn.solve._klowrank"}
        args = ["run", *scene.split(), "--t-end", "2"]
    else:
        args, uses = ["run", *([str(SCENES / scene)] if scene else [])], set()
    for i in range(2):  # the first fills numba's cache where the test session has not yet
        argv = [sys.executable, "-P", "-c", PROBE, json.dumps(args), str(tmp_path / str(i))]
        r = subprocess.run(argv, env=child_env, capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        loaded.append(set(json.loads(r.stdout.strip().splitlines()[-1])) - uses)
    assert loaded[1] == set()
