"""The generated documentation pages cover what they promise.

- API reference: every public name of ``nsdyn`` is documented from the object it is; the
  static resolution of the generator (imports and lazy tables followed in the source) is
  checked against the import system's answer (``getattr(nsdyn, name)``).
- Gallery: one page per example script; every figure of ``examples/figures`` is shown on a
  page of the site (the gallery or a guide page), so none is left unexplained.
- Validation: every test module appears.
"""

from __future__ import annotations

import importlib
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "docs" / "gen"))
import api  # noqa: E402
import gallery  # noqa: E402
import validation  # noqa: E402


@pytest.mark.parametrize("entry", api.public_names(), ids=lambda e: e[1])
def test_each_public_name_is_documented_from_the_object_it_is(entry):
    import nsdyn

    _, public, module, attr = entry
    path = api.defining_object(module, attr)
    mod, _, name = path.rpartition(".")
    assert getattr(importlib.import_module(mod), name) is getattr(nsdyn, public)


def test_the_api_page_has_every_public_name():
    import nsdyn

    page = api.page()
    assert set(re.findall(r"^### `nsdyn\.(\w+)`", page, re.M)) == set(nsdyn._API)


def test_every_example_has_a_gallery_page():
    pages = gallery.pages()
    for script in (ROOT / "examples").glob("*.py"):
        assert f"gallery/{script.stem}.md" in pages


def test_every_figure_is_shown_on_a_page():
    shown = set()
    for text in gallery.pages().values():
        shown |= set(re.findall(r"\(\.\./figures/([\w.-]+\.png)\)", text))
    for md in (ROOT / "docs").rglob("*.md"):
        shown |= set(re.findall(r"figures/([\w.-]+\.png)\)", md.read_text(encoding="utf-8")))
    figures = {p.name for p in gallery.FIGURES.glob("*.png")}
    assert figures and figures <= shown, sorted(figures - shown)


def test_the_validation_page_lists_every_test_module():
    page = validation.page()
    for p in (ROOT / "tests").rglob("test_*.py"):
        assert f"`{p.relative_to(ROOT).as_posix()}`" in page


def test_the_api_page_has_every_public_name_of_the_subpackages():
    # each name of nsdyn.structure, nsdyn.ground and nsdyn.models.isolated is on the page,
    # under nsdyn. when the top level exports the same object, else under its package, and
    # the generator's static resolution is the import system's answer
    page = api.page()
    top = set(re.findall(r"^### `nsdyn\.(\w+)`", page, re.M))
    for package in api.SUBPACKAGES:
        mod = importlib.import_module(package)
        for name in mod.__all__:
            path = api.defining_object(package, name)
            where, _, attr = path.rpartition(".")
            assert getattr(importlib.import_module(where), attr) is getattr(mod, name)
            assert f"### `{package}.{name}`" in page or name in top, (package, name)


def test_the_api_page_shows_each_constant_with_its_value():
    # mkdocstrings shows no value of a module constant under an entry without its root
    # heading: the page writes it, read from the source, and it is the value imported
    import ast

    page = api.page()
    names = [(f"nsdyn.{p}", api.defining_object(m, a)) for _, p, m, a in api.public_names()]
    names += [(f"{pk}.{n}", path) for pk, n, path in api.subpackage_names()]
    shown = 0
    for heading, path in names:
        if (const := api.constant(path)) is None:
            continue
        mod, _, name = path.rpartition(".")
        code, note = const
        entry = page.split(f"### `{heading}`", 1)[1].split("\n### ", 1)[0]
        assert f"```python\n{code}\n```" in entry and note, heading
        if " = " in code:
            value = ast.literal_eval(code.split(" = ", 1)[1])
            assert value == getattr(importlib.import_module(mod), name), heading
            shown += 1
    assert shown >= 4  # G_EARTH, G_STANDARD, CONTACTS, FIDELITIES


def test_a_constant_s_note_is_its_whole_comment_block_and_a_call_is_shown_by_name(
    tmp_path, monkeypatch
):
    # a two-line comment above kept its last line alone; a plain assignment of a call raised
    # AttributeError (an Assign has no annotation)
    src = tmp_path / "mod.py"
    src.write_text("# the first line of a block\n#\n# that goes on here\nBLOCK = 3\n"
                   "CALLED = dict(a=1)  # made by a call\n")  # fmt: skip
    monkeypatch.setattr(api, "_module_file", lambda module: src)
    api._tree.cache_clear()
    try:
        assert api.constant("fake.BLOCK") == ("BLOCK = 3", "the first line of a block that "
                                              "goes on here")  # fmt: skip
        assert api.constant("fake.CALLED") == ("CALLED", "made by a call")
    finally:
        api._tree.cache_clear()
