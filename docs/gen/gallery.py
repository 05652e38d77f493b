"""The gallery: one page per example script (``examples/*.py``), from its docstring, with the
figures it writes (``examples/figures/*.png``) and its source.

A figure belongs to a script whose source names it, literally (``"speed.png"``) or through an
f-string pattern (``f"first-{name}.png"``). Nothing is copied by hand: rerun a script and the
next build shows its new figure.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
FIGURES = EXAMPLES / "figures"
_FSTRING_PNG = re.compile(r"""f["']([\w./-]*)\{[^}]*\}([\w-]*)\.png["']""")


def figures_of(source: str, figures: list[Path]) -> list[Path]:
    """The figures of ``figures`` that a script's ``source`` names."""
    pats = [
        re.compile(re.escape(a.rsplit("/", 1)[-1]) + r"[\w-]+" + re.escape(b) + r"\.png$")
        for a, b in _FSTRING_PNG.findall(source)
    ]
    return [f for f in figures if f.name in source or any(p.match(f.name) for p in pats)]


def scripts() -> list[dict]:
    """One dict per example script: name, title, docstring body, source, figures."""
    figs = sorted(FIGURES.glob("*.png"))
    out = []
    for path in sorted(EXAMPLES.glob("*.py")):
        src = path.read_text()
        doc = ast.get_docstring(ast.parse(src)) or ""
        title, _, body = doc.partition("\n")
        out.append(
            {
                "name": path.stem,
                "title": title.strip() or path.stem,
                "body": body.strip(),
                "source": src,
                "figures": figures_of(src, figs),
            }
        )
    return out


def _rst_to_md(text: str) -> str:
    from docstring_md import markdown_of  # the docstring rules of the API pages

    return markdown_of(text)


def pages() -> dict[str, str]:
    """``{path under docs: Markdown}`` of the gallery index and one page per script."""
    items = scripts()
    index = [
        "# Gallery",
        "",
        "The example scripts of `examples/`, each with the figures it draws. Every page is",
        "generated from the script's docstring and source; run a script from the repository",
        "root (`python examples/NAME.py`) to redraw its figures into `examples/figures/`.",
        "",
        "| example | what it shows | figures |",
        "|---|---|---|",
    ]
    out = {}
    for s in items:
        n = len(s["figures"])
        index.append(f"| [{s['name']}]({s['name']}.md) | {s['title']} | {n or '—'} |")
        body = [
            f"# {s['name']}",
            "",
            f"**{s['title']}**",
            "",
            _rst_to_md(s["body"]),
            "",
            f"Run: `python examples/{s['name']}.py`",
            "",
        ]
        for f in s["figures"]:
            body += [f"![{f.stem}](../figures/{f.name})", ""]
        body += [
            '??? example "Source"',
            "",
            "    ```python",
            *[("    " + line).rstrip() for line in s["source"].splitlines()],
            "    ```",
            "",
        ]
        out[f"gallery/{s['name']}.md"] = "\n".join(body)
    out["gallery/index.md"] = "\n".join(index) + "\n"
    return out
