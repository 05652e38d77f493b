"""The validation page: which test checks what, against which independent source, how tightly.

Generated from the test modules themselves: each module's docstring says what it checks, and
each test's docstring (or, where it has none, the comments in its body, where the house rules
put the source and the tolerance of every asserted number) says against what. Tests marked
``slow`` are flagged. Nothing is copied by hand, so the page follows the tests.
"""

from __future__ import annotations

import ast
import io
import tokenize
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TESTS = ROOT / "tests"

SECTIONS = {  # tests/<dir> -> heading and one line on what the folder covers
    "models/isolated": "The isolated frame (seed 004)",
    "solve": "Integrators of the isolated frame",
    "periodic": "Periodic solutions, continuation and the uplift boundary",
    "models/rocking": "Rocking blocks and frames (seeds 001, 003)",
    "models/contact": "Planar rigid bodies with frictional contacts (seed 002)",
    "models/cylinder": "The cylinder on a Winkler foundation (seed 000)",
    "structure": "Frames and Craig–Bampton reduction",
    "ground": "Ground motions: readers, synthesis, scaling",
    "studies": "Studies, design search and fragility",
    "bench": "Benchmarks (their physics, never their timings)",
    "cli": "The command line",
    "catalogue": "Bad input, interrupts and load: the catalogue of failures",
    "plot": "Figures",
    "docs": "The documentation (scene reference against the readers)",
    "layout": "Rules of the house (layout, kernels)",
    ".": "Top level",
}


def _comments(src: str, first: int, last: int) -> list[str]:
    """The comment texts on lines ``first..last`` of ``src``."""
    out = []
    try:
        for tok in tokenize.generate_tokens(io.StringIO(src).readline):
            if tok.type == tokenize.COMMENT and first <= tok.start[0] <= last:
                text = tok.string.lstrip("#").strip()
                if text and not text.startswith(("noqa", "fmt:", "type:")):
                    out.append(text)
    except tokenize.TokenError:
        pass
    return out


def _is_slow(node) -> bool:
    return any("slow" in ast.unparse(d) for d in node.decorator_list)


def module_entries(path: Path) -> dict:
    """The module docstring and ``(test name, slow, what it checks)`` of each test in ``path``."""
    src = path.read_text(encoding="utf-8")
    tree = ast.parse(src)
    slow_module = any(
        isinstance(n, ast.Assign)
        and any(isinstance(t, ast.Name) and t.id == "pytestmark" for t in n.targets)
        and "slow" in ast.unparse(n.value)
        for n in tree.body
    )
    tests = []
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef) and node.name.startswith("test_"):
            doc = ast.get_docstring(node)
            what = " ".join(doc.split("\n\n")[0].split()) if doc else ""
            if not what:
                what = " ".join(_comments(src, node.lineno, node.end_lineno)[:4])
            tests.append((node.name, slow_module or _is_slow(node), what))
    return {"doc": ast.get_docstring(tree) or "", "tests": tests}


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def page() -> str:
    """The Markdown of ``validation.md``."""
    from docstring_md import markdown_of

    lines = [
        "# Validation",
        "",
        "Every number nsdyn reports is checked by a test against something nsdyn did not",
        "compute itself: a closed-form solution, a conservation law, a convergence order, an",
        "enumeration, an independent integrator (SciPy, python-control, OpenSees) or a number",
        "published in a source paper — each with its tolerance and where that tolerance comes",
        "from. This page is generated from the tests: each module's docstring, then each test",
        "with its docstring or the comments that state its source and tolerance.",
        "",
        'Run them: `pytest -q -m "not slow"` (the fast selection, what CI runs), '
        "`pytest -q -m slow` (the long physics checks marked *slow* below).",
        "",
    ]
    dirs: dict[str, list[Path]] = {}
    for p in sorted(TESTS.rglob("test_*.py")):
        rel = p.parent.relative_to(TESTS).as_posix() or "."
        dirs.setdefault(rel, []).append(p)
    order = [d for d in SECTIONS if d in dirs] + sorted(d for d in dirs if d not in SECTIONS)
    for d in order:
        where = "tests" if d == "." else f"tests/{d}"
        lines += [f"## {SECTIONS.get(d, d)}", "", f"`{where}/`", ""]
        for path in dirs[d]:
            e = module_entries(path)
            rel = path.relative_to(ROOT).as_posix()
            lines += [f"### `{rel}`", ""]
            if e["doc"]:
                lines += [markdown_of(e["doc"]), ""]
            if e["tests"]:
                lines += ["| test | checks |", "|---|---|"]
                for name, slow, what in e["tests"]:
                    tag = " *(slow)*" if slow else ""
                    lines.append(f"| `{name}`{tag} | {_cell(markdown_of(what))} |")
                lines.append("")
    return "\n".join(lines)
