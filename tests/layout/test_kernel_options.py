"""Every numba kernel is compiled with ``cache=True`` and ``error_model="numpy"``.

Source: ARCHITECTURE.md (kernels) and README, "Start-up and the default run" ("Division
checks"). ``cache=True``: a kernel compiles once per install, not per process.
``error_model="numpy"``: a float division by zero gives inf or nan, which the kernels' own
finiteness checks report with time and reason (ST_NONFINITE and the like), instead of a check
and a Python exception path at every division: measured, the default run's first compilation
1.06-1.15x shorter, its results bit-identical and its run time unchanged.
"""

from __future__ import annotations

import ast
from pathlib import Path

PKG = Path(__file__).resolve().parents[2] / "nsdyn"


def _njit_calls(source: str) -> list[ast.Call | ast.Name]:
    """``njit`` as used in a source: calls ``njit(...)`` and bare ``@njit`` decorators."""
    tree = ast.parse(source)
    calls = [
        n for n in ast.walk(tree)
        if isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id == "njit"
    ]  # fmt: skip
    bare = [
        d
        for n in ast.walk(tree)
        if isinstance(n, ast.FunctionDef)
        for d in n.decorator_list
        if isinstance(d, ast.Name) and d.id == "njit"
    ]
    return calls + bare


def _missing_options(source: str) -> list[int]:
    """Lines where ``njit`` lacks ``cache=True`` or ``error_model="numpy"``."""
    bad = []
    for node in _njit_calls(source):
        kw = {}
        if isinstance(node, ast.Call):
            kw = {k.arg: k.value for k in node.keywords}
        cache = kw.get("cache")
        model = kw.get("error_model")
        ok = (
            isinstance(cache, ast.Constant) and cache.value is True
            and isinstance(model, ast.Constant) and model.value == "numpy"
        )  # fmt: skip
        if not ok:
            bad.append(node.lineno)
    return sorted(bad)


def test_detector_finds_each_omission():
    src = (
        "from numba import njit\n"
        "@njit\n"
        "def a(x): return x\n"
        "@njit(cache=True)\n"
        "def b(x): return x\n"
        '@njit(cache=True, error_model="numpy")\n'
        "def c(x): return x\n"
        'd = njit(error_model="numpy")(c)\n'
    )
    assert _missing_options(src) == [2, 4, 8]


def test_every_kernel_has_cache_and_numpy_error_model():
    bad = {}
    for path in sorted(PKG.rglob("*.py")):
        lines = _missing_options(path.read_text())
        if lines:
            bad[str(path.relative_to(PKG.parent))] = lines
    assert not bad, f'njit without cache=True, error_model="numpy": {bad}'
