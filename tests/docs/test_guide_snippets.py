"""The guide's self-contained Python examples run as written and return what their comments
promise (the keys of the summaries they print), so the pages cannot drift from the API.

A block is self-contained when it starts with ``import``; the pages whose examples take
minutes (the uplift boundary, the first ten minutes' switch-model run) are left to the
example scripts' own tests.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[2] / "docs"
PAGES = ("guide/transient.md", "guide/custom-systems.md", "guide/periodic.md",
         "guide/rocking.md", "guide/contact.md")  # fmt: skip


def _blocks():
    out = []
    for page in PAGES:
        text = (DOCS / page).read_text(encoding="utf-8")
        for i, code in enumerate(re.findall(r"^```python\n(.*?)^```", text, re.S | re.M)):
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
