"""The API reference page: every public name of ``nsdyn`` (its lazy re-exports), by stage.

Read statically from ``nsdyn/__init__.py`` (the ``_API`` table and its ``# stage`` comments);
each name is followed to the module that defines it, so mkdocstrings documents the object
itself from its docstring. Nothing is imported.
"""

from __future__ import annotations

import ast
import re
from functools import cache
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
_ENTRY = re.compile(r'^\s*"(\w+)":\s*"([\w.]+)(?::(\w+))?",')
_GROUP = re.compile(r"^\s*#\s*((?:structure|ground|models|solve|periodic|studies)\b.*?)\s*$")


def public_names(init: Path | None = None) -> list[tuple[str, str, str, str]]:
    """``(group, public name, module, attribute)`` for each entry of ``nsdyn._API``."""
    text = (init or ROOT / "nsdyn" / "__init__.py").read_text()
    body = text.split("_API = {", 1)[1].split("\n}", 1)[0]
    out, group = [], "nsdyn"
    for line in body.splitlines():
        if m := _ENTRY.match(line):
            out.append((group, m.group(1), m.group(2), m.group(3) or m.group(1)))
        elif m := _GROUP.match(line):
            group = m.group(1)
    return out


def _module_file(module: str) -> Path:
    base = ROOT.joinpath(*module.split("."))
    return base / "__init__.py" if base.is_dir() else base.with_suffix(".py")


@cache
def _tree(module: str) -> ast.Module:
    return ast.parse(_module_file(module).read_text())


def defining_object(module: str, name: str, depth: int = 0) -> str:
    """The dotted path of the object that ``module.name`` is (through imports and ``_API``)."""
    if depth > 8:
        raise RuntimeError(f"{module}.{name}: import chain too deep")
    tree = _tree(module)
    for node in tree.body:
        if isinstance(node, ast.FunctionDef | ast.ClassDef) and node.name == name:
            return f"{module}.{name}"
        if isinstance(node, ast.Assign | ast.AnnAssign):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            if any(isinstance(t, ast.Name) and t.id == name for t in targets):
                return f"{module}.{name}"
        if isinstance(node, ast.ImportFrom) and node.module:
            for alias in node.names:
                if (alias.asname or alias.name) == name:
                    return defining_object(node.module, alias.name, depth + 1)
    for node in tree.body:  # a lazy package: its own {name: "module[:attr]"} table
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Dict):
            for k, v in zip(node.value.keys, node.value.values, strict=True):
                if isinstance(k, ast.Constant) and k.value == name:
                    mod, _, attr = v.value.partition(":")
                    return defining_object(mod, attr or name, depth + 1)
    raise LookupError(f"{module}.{name}: not found")


def page() -> str:
    """The Markdown of ``reference/api.md``."""
    lines = [
        "# API reference",
        "",
        "Every public name of `nsdyn` (`import nsdyn; nsdyn.simulate(...)`), grouped by the",
        "pipeline stage that defines it. Names load lazily, so `import nsdyn` stays cheap.",
        "This page is generated from `nsdyn/__init__.py` and the docstrings; each entry",
        "names the module that defines the object.",
        "",
    ]
    group = None
    for grp, public, module, attr in public_names():
        if grp != group:
            lines += [f"## {grp[:1].upper() + grp[1:]}", ""]
            group = grp
        target = defining_object(module, attr)
        lines += [
            f"### `nsdyn.{public}`",
            "",
            f"Defined in `{target.rsplit('.', 1)[0]}`.",
            "",
            f"::: {target}",
            "    options:",
            "      show_root_heading: false",
            "      heading_level: 4",
            "",
        ]
    return "\n".join(lines)
