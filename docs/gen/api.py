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


SUBPACKAGES = ("nsdyn.structure", "nsdyn.ground", "nsdyn.models.isolated")


def package_all(package: str) -> list[str]:
    """The names of ``package``'s ``__all__`` (a list, or ``sorted(_API)`` of a lazy table),
    read from its source."""
    tree = _tree(package)
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
            isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets
        ):
            if isinstance(node.value, ast.List):
                return [e.value for e in node.value.elts if isinstance(e, ast.Constant)]
            for other in tree.body:  # sorted(_API): the keys of the table
                if isinstance(other, ast.Assign) and isinstance(other.value, ast.Dict):
                    return sorted(k.value for k in other.value.keys)
    raise LookupError(f"{package}: no __all__")


def subpackage_names() -> list[tuple[str, str, str]]:
    """``(package, name, defining path)`` of the subpackages' public names that ``nsdyn``
    itself does not export (those are on the page already, under ``nsdyn.``)."""
    top = {defining_object(module, attr) for _, _, module, attr in public_names()}
    out = []
    for package in SUBPACKAGES:
        for name in package_all(package):
            path = defining_object(package, name)
            if path not in top:
                out.append((package, name, path))
    return out


def constant(path: str) -> tuple[str, str] | None:
    """``(code, note)`` of a module-level constant: ``NAME = value`` when the value is a short
    literal (else ``NAME: annotation``), and the comment on its line or just above it; ``None``
    for a function or a class. mkdocstrings shows neither without the root heading."""
    module, _, name = path.rpartition(".")
    lines = _module_file(module).read_text().splitlines()
    for node in _tree(module).body:
        targets = node.targets if isinstance(node, ast.Assign) else [getattr(node, "target", 0)]
        if not any(isinstance(t, ast.Name) and t.id == name for t in targets):
            continue
        first = lines[node.lineno - 1]
        code = f"{name} = {ast.unparse(node.value)}"
        try:
            ast.literal_eval(node.value)
        except ValueError:
            hint = getattr(node, "annotation", None)  # (an AnnAssign's)
            code = f"{name}: {ast.unparse(hint)}" if hint is not None else name
        note = first.partition("  # ")[2] if node.end_lineno == node.lineno else ""
        if note.startswith(("fmt:", "noqa")):
            note = ""
        above, block = node.lineno - 2, []
        while not note and above >= 0 and re.match(r"#( (?!-)|$)", lines[above]):
            block.insert(0, lines[above][2:])  # a comment block just above: all its lines
            above -= 1
        block = " ".join(b for b in block if b)  # (a bare "#" line inside it)
        return (code if len(code) <= 100 else name), (note or block).strip()
    return None


def _entry(heading: str, target: str) -> list[str]:
    out = [f"### `{heading}`", "", f"Defined in `{target.rsplit('.', 1)[0]}`.", ""]
    if (const := constant(target)) is not None:
        code, note = const
        out += ["```python", code, "```", ""] + ([note, ""] if note else [])
        return out
    return out + [f"::: {target}", "    options:", "      show_root_heading: false",
                  "      heading_level: 4", ""]  # fmt: skip


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
        lines += _entry(f"nsdyn.{public}", defining_object(module, attr))
    lines += ["## More in the subpackages", "",
              "The public names of `nsdyn.structure` (3D frames, their modes and drifts), "
              "`nsdyn.ground` (readers, three-component records, synthesis) and",
              "`nsdyn.models.isolated` (bidirectional isolators, decks, systems from matrices, "
              "3D buildings) that `nsdyn` itself does not export.", ""]  # fmt: skip
    for package, name, path in subpackage_names():
        lines += _entry(f"{package}.{name}", path)
    return "\n".join(lines)
