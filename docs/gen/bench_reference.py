"""The benchmark tables page: what each ``nsdyn bench NAME`` measures and what its CSV columns
mean, from the benchmark modules' own docstrings (the shared measures from
:mod:`nsdyn.bench.common`'s).

Read statically: the ``BENCHMARKS`` table of ``nsdyn/bench/__init__.py`` names the modules in
``nsdyn bench all``'s order, and each module's docstring is converted as the API pages convert
theirs. Nothing is imported.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def benchmarks() -> list[tuple[str, str]]:
    """``(name, module)`` of every registered benchmark, in ``nsdyn bench all``'s order."""
    tree = ast.parse((ROOT / "nsdyn" / "bench" / "__init__.py").read_text())
    for node in tree.body:
        if isinstance(node, ast.AnnAssign | ast.Assign):
            targets = [node.target] if isinstance(node, ast.AnnAssign) else node.targets
            if any(isinstance(t, ast.Name) and t.id == "BENCHMARKS" for t in targets):
                table = ast.literal_eval(node.value)
                return list(table.items())
    raise RuntimeError("nsdyn/bench/__init__.py: no BENCHMARKS table")


def _docstring(module: str) -> str:
    path = ROOT.joinpath(*module.split(".")).with_suffix(".py")
    return ast.get_docstring(ast.parse(path.read_text())) or ""


def page() -> str:
    from docstring_md import markdown_of  # the docstring rules of the API pages

    out = [
        "# Benchmark tables",
        "",
        "What each `nsdyn bench NAME` measures and what the columns of its CSV tables mean,",
        "from the benchmark's own module (generated from its docstring). How to run them and",
        "how long they take: [benchmarks](../guide/benchmarks.md); the results:",
        "[performance](../performance.md).",
        "",
        "## Shared measures (`nsdyn.bench.common`)",
        "",
        markdown_of(_docstring("nsdyn.bench.common")),
    ]
    for name, module in benchmarks():
        out += ["", f"## `nsdyn bench {name}` (`{module}`)", "", markdown_of(_docstring(module))]
    return "\n".join(out) + "\n"
