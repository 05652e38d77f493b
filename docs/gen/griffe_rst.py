"""Griffe extension: render nsdyn's docstrings (written for ``help()``) as Markdown.

mkdocstrings renders docstrings as Markdown; this extension rewrites each one once, when its
object is loaded, with :func:`docstring_md.markdown_of` (roles as code spans, ``::`` as ``:``,
numpy-style sections kept as written). The docstrings themselves are the one source.
"""

from __future__ import annotations

import sys
from pathlib import Path

import griffe

sys.path.insert(0, str(Path(__file__).resolve().parent))
from docstring_md import markdown_of  # noqa: E402


class RstToMarkdown(griffe.Extension):
    """Rewrite every docstring once, when its object is loaded."""

    def _fix(self, obj) -> None:
        doc = getattr(obj, "docstring", None)
        if doc is not None and not getattr(doc, "_nsdyn_md", False):
            doc.value = markdown_of(doc.value)
            doc._nsdyn_md = True

    def on_instance(self, *, obj, **kwargs) -> None:  # noqa: D102
        self._fix(obj)

    def on_object(self, *, obj, **kwargs) -> None:  # noqa: D102
        self._fix(obj)
