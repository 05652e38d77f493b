"""Each kernel compiles once for the argument types it runs with.

Source: numba's typing (``numba.core.typeinfer``): a constant argument is typed as a literal
(``Literal[int](0)``, ``Literal[bool](False)``), an omitted default as ``omitted(...)``, and a
kernel called once with a constant and once with a variable of the same run-time type is
compiled twice, as is a variable first assigned a constant (``r = -1`` ... ``r = i``) and
passed to a kernel (typing resolves the call while ``r`` is still the literal). Each copy
costs a first run its typing and lowering again (the rocking block's ``ground`` three times:
about 1.5 s of a 5 s first run). The kernels pass typed values (``np.int64(0)``,
``np.bool_(False)``, module constants made with them) and write defaults out.

The check reads what this process compiled or loaded and numba's on-disk cache index, which
records every signature any process compiled for the current sources: in a fresh clone (CI),
after the suite's warm-ups, that is each family's run. A cache filled before an edit of a
caller (not of the kernel's own file) can hold a signature no current caller asks for:
clear it (``NUMBA_CACHE_DIR`` or the ``__pycache__`` folders) if this test names one.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
import types
from pathlib import Path

import numpy as np
import pytest

from nsdyn._numba_cache import repeated_compilations, runtime_types

TESTS = Path(__file__).resolve().parents[1]
PKG = TESTS.parent / "nsdyn"
JIT = not __import__("numba").config.DISABLE_JIT

# kernels specialised on purpose, with the reason (none now: the event method's switching scan
# calls the velocity alone, ``_kevent._v_dense``, instead of a literal-SLIP copy of ``_g_dense``)
SPECIALISED: set[str] = set()


def _probe_module(name: str) -> types.ModuleType:
    """A module of three small kernels: ``twice`` calls ``f`` with a literal and a variable,
    ``once`` with typed values only, ``defaults`` calls ``h`` with and without its default."""
    from numba import njit

    mod = types.ModuleType(name)

    def f(x, k):
        return x + k

    def h(x, tol=0.0):
        return x + tol

    mod.f, mod.g, mod.h = njit(f), njit(f), njit(h)

    def twice(x, i):
        return mod.f(x, 0) + mod.f(x, i)

    def once(x, i):
        return mod.g(x, np.int64(0)) + mod.g(x, i)

    def defaults(x):
        return mod.h(x) + mod.h(x, 1e-3)

    mod.twice, mod.once, mod.defaults = njit(twice), njit(once), njit(defaults)
    return mod


@pytest.mark.skipif(not JIT, reason="NUMBA_DISABLE_JIT: nothing compiles")
def test_the_rule_finds_literal_and_omitted_twins():
    """The detector on a probe module: a kernel called with ``0`` and with an int variable,
    and one called with and without its default, are found; typed values are not."""
    name = "nsdyn_compile_once_probe"
    mod = sys.modules[name] = _probe_module(name)
    try:
        assert mod.twice(1.0, 2) == 4.0 and mod.once(1.0, 2) == 4.0
        assert mod.defaults(1.0) == pytest.approx(2.001)
        found = {q.rsplit(".", 1)[-1] for q, _ in repeated_compilations(name)}
    finally:
        del sys.modules[name]
    # f: `Literal[int](0)` and `int64`; h: `omitted(default=0.0)` and `float64`; g: `int64`
    assert found == {"f", "h"}


def test_runtime_types_of_literals_and_defaults():
    """A literal stands for its plain type, an omitted default for its value's type."""
    from numba import types as nt

    sig = (nt.literal(0), nt.literal(True), nt.Omitted(0.0), nt.float64[:, ::1])
    assert runtime_types(sig) == (nt.int64, nt.boolean, nt.float64, nt.float64[:, ::1])


def _warm_families() -> None:
    """Each family's run as the suite's warm-ups make it (loaded from the cache they filled;
    compiled here when this file runs alone into an empty cache)."""
    from nsdyn.models.rocking.block import warmup as rocking
    from nsdyn.periodic.problem import warmup as periodic
    from nsdyn.solve.methods import warmup_kernel, warmup_unilateral

    warmup_kernel("radau", "metrics")
    warmup_kernel("event")
    warmup_kernel("genalpha")
    warmup_unilateral()
    periodic()
    rocking()
    spec = importlib.util.spec_from_file_location("nsdyn_tests_conftest", TESTS / "conftest.py")
    conftest = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(conftest)  # the suite's own warm-ups (tests/conftest.py)
    for name in ("warm_contact", "warm_cylinder", "warm_deck", "warm_pairs"):
        getattr(conftest, name)()


@pytest.mark.skipif(not JIT, reason="NUMBA_DISABLE_JIT: nothing compiles")
def test_every_kernel_compiles_once_per_argument_types():
    """After every family's warm-up no kernel is held twice for the same run-time types
    (this process and numba's on-disk cache index), but those specialised on purpose."""
    for path in sorted(PKG.rglob("_k*.py")):
        if "__pycache__" not in path.parts:
            rel = path.relative_to(PKG.parent).with_suffix("")
            importlib.import_module(".".join(rel.parts))
    _warm_families()
    twins = {
        q: [str(s) for s in sigs] for q, sigs in repeated_compilations() if q not in SPECIALISED
    }
    assert not twins, (
        "kernels compiled twice for the same run-time types (a literal or an omitted default "
        f"beside a typed value; pass np.int64(...) / np.bool_(...) or write the default): {twins}"
    )
