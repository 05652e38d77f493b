"""Kernel sources assign no array to a slice (``a[:] = b``, ``A[i, :] = b``).

Source: numba's compile events (README, "Start-up and the default run", copies by loops). For
a slice assigned from an array numba compiles a formatted shape-mismatch message (string
formatting: ``str.join``, ``str(int)``) once per array dimension and process, 2-3 s each of a
cold start; the kernels copy through ``nsdyn._klinalg.copy_vec`` / ``copy_mat`` instead.
So does an in-place operation on a slice (``T[i, :] -= f * T[r, :]``: 2.5 s of the contact
model's first run). Assigning a constant to a slice (``a[:] = 0.0``, ``J[:, :] = np.nan``)
compiles no message and stays allowed. A row assigned by an integer index (``X[i] = y``) is
the same case but cannot be told from a scalar store without types: the fresh-cache checks
of the default run and the period map (``tests/solve/test_flat_only_loop.py``, slow) count
the messages compiled, whatever their source.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PKG = Path(__file__).resolve().parents[2] / "nsdyn"
CONSTANTS = {"np.nan", "np.inf", "-np.inf", "math.nan", "math.inf"}


def _is_njit(expr: ast.expr) -> bool:
    f = expr.func if isinstance(expr, ast.Call) else expr
    return isinstance(f, ast.Name) and f.id == "njit"


def _is_copy(expr: ast.expr) -> bool:
    """``specialised(...)`` or ``ka.specialised(...)`` (nsdyn._kaddress: a kernel's copy)."""
    f = expr.func if isinstance(expr, ast.Call) else None
    name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", None)
    return name == "specialised"


def _jitted(tree: ast.Module) -> list[ast.FunctionDef]:
    """Functions compiled by numba: decorated with ``njit``, wrapped as ``njit(...)(f)``, or
    copied by ``specialised(f, ...)`` (which is then compiled)."""
    wrapped = {
        node.args[0].id
        for node in ast.walk(tree)
        if isinstance(node, ast.Call) and (_is_njit(node.func) or _is_copy(node)) and node.args
        and isinstance(node.args[0], ast.Name)
    }  # fmt: skip
    return [
        node
        for node in ast.walk(tree)
        if isinstance(node, ast.FunctionDef)
        and (any(_is_njit(d) for d in node.decorator_list) or node.name in wrapped)
    ]


def _slice_copies(source: str) -> list[str]:
    """``target = value`` and ``target op= value`` statements of numba-compiled functions with
    a slice in the target and a non-constant value."""
    hits = []
    for fn in _jitted(ast.parse(source)):
        for node in ast.walk(fn):
            if not isinstance(node, (ast.Assign, ast.AugAssign)):
                continue
            for t in node.targets if isinstance(node, ast.Assign) else [node.target]:
                if not isinstance(t, ast.Subscript):
                    continue
                parts = t.slice.elts if isinstance(t.slice, ast.Tuple) else [t.slice]
                if not any(isinstance(p, ast.Slice) for p in parts):
                    continue
                v = node.value
                if isinstance(v, ast.UnaryOp):
                    v = v.operand
                if isinstance(v, ast.Constant) or ast.unparse(node.value) in CONSTANTS:
                    continue
                hits.append(f"{node.lineno}: {ast.unparse(node)}")
    return hits


def _kernel_modules() -> list[Path]:
    return sorted(p for p in PKG.rglob("_k*.py") if "__pycache__" not in p.parts)


def test_the_rule_finds_slice_copies():
    # the detector itself: array values flagged, constants and element stores not
    body = (
        "    a[:] = b\n    A[i, :] = b[2:]\n    A[:, :] = B @ C\n    y[:n] = -x\n"
        "    a[:] = 0.0\n    J[:, :] = np.nan\n    b[:] = -1.0\n    F[i] = acc\n"
        "    X[i, j] = y[j]\n    T[i, :] -= f * T[r, :]\n    T[r, :] /= 2.0\n"
    )
    src = (
        f"@njit(cache=True)\ndef k(a, b):\n{body}"
        f"def w(a, b):\n{body}"
        f"@njit\ndef k2(a, b):\n    a[:] = b\n"
        f"def k3(a, b):\n    a[1:] = b\nk3i = njit(inline='always')(k3)\n"
        f"def k4(a, b):\n    a[2:] = b\nk4c = compiled_only(ka.specialised(k4, 'k4c', g=1))\n"
    )
    hits = [h.split(":")[0] for h in _slice_copies(src)]
    assert hits == ["3", "4", "5", "6", "12", "28", "30", "33"]


def test_kernel_modules_exist():
    names = {p.name for p in _kernel_modules()}
    assert {"_kradau.py", "_kflat.py", "_kperiodic.py", "_kgenalpha.py"} <= names


@pytest.mark.parametrize("path", _kernel_modules(), ids=lambda p: str(p.relative_to(PKG)))
def test_no_slice_assigned_from_an_array(path):
    hits = _slice_copies(path.read_text())
    assert not hits, f"{path}: copy with copy_vec/copy_mat (nsdyn._klinalg): {hits}"
