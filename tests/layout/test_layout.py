"""The package's shape: imports point down the pipeline, modules stay small and say what they do.

Source: the layout rules in ARCHITECTURE.md (pipeline order, one job per module, ~500 lines).
"""

from __future__ import annotations

import ast
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PKG = ROOT / "nsdyn"
# the pipeline, bottom to top: a module may import its own stage or any stage before it
STAGES = [
    "atomic",
    "_textfile",
    "_brief",
    "_progress",
    "_checks",
    "_numba_light",
    "_numba_cache",
    "_kaddress",
    "_kborrow",
    "_klinalg",
    "_kdp5",
    "_lazy",
    "_bundled",
    "_tabular",
    "_model_cache",
    "structure",
    "ground",
    "models",
    "solve",
    "periodic",
    "studies",
    "plot",
    "bench",
    "cli",
]
MAX_LINES = 560  # ARCHITECTURE.md: "at most 560 lines"


def _modules() -> list[Path]:
    return sorted(p for p in PKG.rglob("*.py") if "__pycache__" not in p.parts)


def _stage(dotted: str) -> str | None:
    parts = dotted.split(".")
    if parts[0] != "nsdyn" or len(parts) < 2:
        return None
    return parts[1] if parts[1] in STAGES else None


def _dotted(path: Path) -> str:
    rel = path.relative_to(ROOT).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _imports(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    here = _dotted(path).split(".")
    if path.name != "__init__.py":
        here = here[:-1]  # the package the module lives in
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[: len(here) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            out.append(mod)
            out += [f"{mod}.{a.name}" for a in node.names]
    return out


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(ROOT)))
def test_imports_point_down_the_pipeline(path):
    own = _stage(_dotted(path)) if _dotted(path) != "nsdyn" else None
    if own is None:
        return  # nsdyn/__init__ (the public front door) and data packages
    rank = STAGES.index(own)
    above = sorted(
        {m for m in _imports(path) if (s := _stage(m)) is not None and STAGES.index(s) > rank}
    )
    assert not above, f"{path.relative_to(ROOT)} ({own}) imports later stages: {above}"


def test_every_top_level_module_has_a_stage():
    # a module missing from STAGES was never checked, nor were imports of it (seven of the
    # bottom modules were: _kaddress, _checks, _model_cache, ...)
    top = {p.stem for p in PKG.glob("*.py") if p.stem != "__init__"}
    top |= {p.name for p in PKG.iterdir() if (p / "__init__.py").is_file() and p.name != "data"}
    assert sorted(top - set(STAGES)) == []


def test_model_families_do_not_import_the_isolated_frame():
    # each family owns its kernels; only the isolated frame's consumers (solve, periodic, …) use it
    for path in (PKG / "models").rglob("*.py"):
        family = path.relative_to(PKG / "models").parts[0]
        if family in ("isolated", "__init__.py", "scenefile.py"):
            continue
        bad = [m for m in _imports(path) if m.startswith("nsdyn.models.isolated")]
        assert not bad, f"{path.relative_to(ROOT)} imports {bad}"


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(ROOT)))
def test_module_is_small_and_states_its_job(path):
    text = path.read_text(encoding="utf-8")
    n = text.count("\n")
    assert n <= MAX_LINES, f"{path.relative_to(ROOT)}: {n} lines (split it by job)"
    if text.strip():
        assert ast.get_docstring(ast.parse(text)), f"{path.relative_to(ROOT)}: no module docstring"


def test_every_package_is_installed():
    # a folder with __init__.py missing from pyproject's package list would vanish from a
    # non-editable install (what CI and users get)
    cfg = tomllib.loads((ROOT / "pyproject.toml").read_text())
    listed = set(cfg["tool"]["setuptools"]["packages"])
    found = {_dotted(p) for p in PKG.rglob("__init__.py") if "__pycache__" not in p.parts}
    found = {f for f in found if not f.startswith("nsdyn.data")}
    assert found <= listed, f"packages missing from pyproject.toml: {sorted(found - listed)}"


def test_public_api_resolves():
    import nsdyn

    missing = [n for n in nsdyn.__all__ if n != "__version__" and not hasattr(nsdyn, n)]
    assert not missing
