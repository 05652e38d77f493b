"""The guide's self-contained Python examples run as written and return what their comments
promise (the keys of the summaries they print), so the pages cannot drift from the API.

A block is self-contained when it starts with ``import``. Every other page's blocks run too,
in order, in one namespace per page (as a reader pasting them in turn would), in a fresh
folder: the README's, the getting-started and the guide pages; the periodic curves' page,
whose blocks take two minutes (150-point curves), in the slow set.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[2] / "docs"
PAGES = ("guide/transient.md", "guide/custom-systems.md", "guide/periodic.md",
         "guide/rocking.md", "guide/contact.md")  # fmt: skip


def _python_blocks(text: str) -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", text, re.S | re.M)


def _blocks():
    out = []
    for page in PAGES:
        text = (DOCS / page).read_text(encoding="utf-8")
        for i, code in enumerate(_python_blocks(text)):
            if code.startswith("import"):
                out.append(pytest.param(code, id=f"{page}-{i}"))
    return out


@pytest.mark.parametrize("code", _blocks())
def test_the_example_runs_as_written(code, capsys):
    ns: dict = {}
    exec(compile(code, "guide", "exec"), ns)  # noqa: S102
    # a summary's keys carry their units or name the outcome, as the comments say
    res = ns.get("res") or ns.get("curve")
    assert res is not None
    if hasattr(res, "summary"):
        s = res.summary()
        assert isinstance(s, dict) and s
        for key in re.findall(r"# (?:outcome, )?([\w, .]+)\.\.\.", code):
            for name in (k.strip() for k in key.split(",")):
                if name and name != "...":
                    assert name in s or any(k.startswith(name) for k in s), name


ROOT = DOCS.parent
SLOW_PAGES = ("docs/guide/periodic.md",)


def _pages():
    """Every page with Python blocks that the block test above does not run whole."""
    out = []
    for path in sorted([ROOT / "README.md", *DOCS.rglob("*.md")]):
        page = path.relative_to(ROOT).as_posix()
        blocks = _python_blocks(path.read_text(encoding="utf-8"))
        whole = page.removeprefix("docs/") in PAGES and all(b.startswith("import") for b in blocks)
        if blocks and not whole:
            marks = [pytest.mark.slow] if page in SLOW_PAGES else []
            out.append(pytest.param(page, id=page, marks=marks))
    return out


@pytest.mark.parametrize("page", _pages())
def test_every_page_runs_as_written(page, tmp_path, monkeypatch):
    text = (ROOT / page).read_text(encoding="utf-8")
    blocks = _python_blocks(text)
    work = tmp_path / "project"  # a reader's folder, with ../shared beside it when there is one
    work.mkdir()
    shared = ROOT.parent / "shared"
    if shared.is_dir():
        (tmp_path / "shared").symlink_to(shared)
    elif any("../shared" in b for b in blocks):
        pytest.skip(f"{page} reads ../shared/records, which is not beside this checkout")
    monkeypatch.chdir(work)
    ns: dict = {"__name__": "__main__"}
    for i, code in enumerate(blocks):
        exec(compile(code, f"{page} block {i}", "exec"), ns)  # noqa: S102
