"""MkDocs hooks: the generated pages and the navigation of the documentation site.

Generated at build time, never stored under ``docs/`` (so they cannot drift from their
sources):

- ``reference/scenes.md``: every scene-file key, from the schemas the scene readers check
  against (:mod:`nsdyn.models.scene_schema`);
- ``reference/studies.md``: every study-file table and key, from the study reader's lists;
- ``reference/api.md``: the public names of ``nsdyn``, from ``nsdyn/__init__.py``;
- ``reference/cli-options.md``: ``nsdyn COMMAND --help`` of every subcommand, from the parser;
- ``reference/benchmarks.md``: each benchmark's measures and CSV columns, from its module;
- ``gallery/*.md``: one page per example script, from its docstring, with its figures;
- ``validation.md``: what each test checks against what, from the test modules;
- ``figures/*.png``: the figures of ``examples/figures``, served as they are.

The navigation is ``mkdocs.yml``'s; entries whose page does not exist (a page still being
written) are dropped, and the gallery's generated pages are listed under its index.
"""

from __future__ import annotations

import logging
import sys
from pathlib import Path

from mkdocs.structure.files import File, Files

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path.insert(0, str(HERE))
log = logging.getLogger("mkdocs.plugins.nsdyn")

import api  # noqa: E402
import bench_reference  # noqa: E402
import cli  # noqa: E402
import docstring_md  # noqa: E402, F401  (the generators import it lazily)
import gallery  # noqa: E402
import scene_reference  # noqa: E402
import study_reference  # noqa: E402
import validation  # noqa: E402

_GENERATED: dict[str, str] = {}


def _generate() -> dict[str, str]:
    pages = {
        "reference/scenes.md": scene_reference.page(),
        "reference/studies.md": study_reference.page(),
        "reference/api.md": api.page(),
        "reference/cli-options.md": cli.page(),
        "reference/benchmarks.md": bench_reference.page(),
        "validation.md": validation.page(),
    }
    pages.update(gallery.pages())
    return pages


def _prune(nav, present: set[str], missing: list[str]):
    """``nav`` without the entries whose page is not in ``present`` (recorded in ``missing``)."""
    out = []
    for item in nav:
        if isinstance(item, str):
            if item in present:
                out.append(item)
            else:
                missing.append(item)
        elif isinstance(item, dict):
            ((title, value),) = item.items()
            if isinstance(value, list):
                kept = _prune(value, present, missing)
                if kept:
                    out.append({title: kept})
            elif value in present:
                out.append(item)
            else:
                missing.append(value)
    return out


def _expand_gallery(nav, pages: list[str]):
    for item in nav:
        if isinstance(item, dict):
            ((title, value),) = item.items()
            if value == "gallery/index.md":
                item[title] = ["gallery/index.md", *pages]
            elif isinstance(value, list):
                _expand_gallery(value, pages)


def on_files(files: Files, config, **kwargs) -> Files:
    """Add the generated pages and the figures; fit the navigation to the pages present."""
    _GENERATED.clear()
    _GENERATED.update(_generate())
    for uri, text in _GENERATED.items():
        if files.get_file_from_path(uri) is None:
            files.append(File.generated(config, uri, content=text))
    for png in sorted(gallery.FIGURES.glob("*.png")):
        files.append(File.generated(config, f"figures/{png.name}", abs_src_path=str(png)))
    present = {f.src_uri for f in files.documentation_pages()}
    missing: list[str] = []
    nav = _prune(config["nav"], present, missing)
    _expand_gallery(
        nav,
        sorted(u for u in _GENERATED if u.startswith("gallery/") and not u.endswith("index.md")),
    )
    config["nav"] = nav
    for uri in missing:
        log.info("nav: %s is not written yet; left out of the navigation", uri)
    return files
