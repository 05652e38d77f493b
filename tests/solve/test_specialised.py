"""Copies of a kernel with other callees (``nsdyn._kaddress.specialised``).

Source: the compiled-kernels page (docs/dev/compiled-kernels.md, "Copies of one source").
A copy is the Python function with some of its global names bound to other objects; numba
compiles and caches each copy on its own, by its name. What must hold: each copy calls its
own callees, also when every copy is loaded from numba's cache in a new process (the cache
files of two copies must never be taken for each other: their signatures are the same), a
binding of a name the body does not use is refused, and a slot called directly picks the
copy made for the caller's general kernel.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest
from numba import config

from nsdyn import _kaddress as ka

JIT = not config.DISABLE_JIT

MODULE = textwrap.dedent(
    """
    from numba import njit
    from nsdyn import _kaddress as ka

    @njit(cache=True, error_model="numpy")
    def twice(x):
        return 2.0 * x

    @njit(cache=True, error_model="numpy")
    def square(x):
        return x * x

    _F = twice

    def body(x):
        return _F(x) + 1.0

    by_twice = njit(cache=True, error_model="numpy")(ka.specialised(body, "by_twice", _F=twice))
    by_square = njit(cache=True, error_model="numpy")(
        ka.specialised(body, "by_square", _F=square)
    )
    """
)


def _run(tmp_path, order: str) -> str:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"), PYTHONPATH=os.pathsep.join(
        [str(tmp_path), *sys.path]
    ))  # fmt: skip
    code = (
        "import copies\n"
        f"for name in {order!r}.split():\n"
        "    k = getattr(copies, name)\n"
        "    print(name, k(3.0), len(k.stats.cache_hits))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    return out.stdout


@pytest.mark.skipif(not JIT, reason="nothing is cached under NUMBA_DISABLE_JIT")
def test_each_copy_calls_its_own_callee_also_from_the_cache(tmp_path):
    (tmp_path / "copies.py").write_text(MODULE)
    first = _run(tmp_path, "by_twice by_square").split()
    # 2*3 + 1 and 3*3 + 1, compiled here (no cache hit)
    assert first == ["by_twice", "7.0", "0", "by_square", "10.0", "0"]
    # a new process loads both from the cache, in the other order: each its own code
    again = _run(tmp_path, "by_square by_twice").split()
    assert again == ["by_square", "10.0", "1", "by_twice", "7.0", "1"]


def test_a_copy_binds_only_names_its_body_uses():
    def body(x):
        return x + _OFFSET  # noqa: F821  (bound by the copy)

    f = ka.specialised(body, "plus_two", _OFFSET=2.0)
    assert f(1.0) == 3.0 and f.__name__ == f.__qualname__ == "plus_two"
    with pytest.raises(ValueError, match="uses no global named _SCALE"):
        ka.specialised(body, "scaled", _SCALE=2.0)


def test_a_direct_call_takes_the_copy_for_the_callers_general_kernel():
    from nsdyn.solve import _kcolloc as kc

    newton = ka.SLOTS["radau.newton"][1]
    assert ka._for_general("radau.newton", newton, kc.flat_only) is kc.newton_flat
    assert ka._for_general("radau.newton", newton, kc.general_t) is kc.newton_table
    assert ka._for_general("radau.newton", newton, kc.general_called) is kc.newton
    with pytest.raises(TypeError, match="no copy of it for the general kernel"):
        ka._for_general("radau.newton", newton, kc.jeval)
