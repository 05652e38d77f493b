"""reStructuredText bits of nsdyn's docstrings as Markdown, for the generated pages.

The docstrings are written for ``help()`` and use a few reST forms: roles
(``:func:`nsdyn.simulate```, ``:class:`~nsdyn.ground.GroundMotion```), literal blocks
introduced by ``::`` and numpy-style sections with aligned columns. :func:`markdown_of` turns
roles into code spans, a trailing ``::`` into a single colon (the indented block after it is
already a Markdown code block) and keeps the sections as written. Used by the griffe extension
(``griffe_rst.py``) for the API and theory pages and by the gallery and validation generators;
it needs nothing beyond the standard library, so the tests can use it without the docs extra.
"""

from __future__ import annotations

import re

_LISTS = {"Parameters", "Other Parameters", "Returns", "Yields", "Attributes", "Raises",
          "Warns"}  # fmt: skip
_REFLINK = re.compile(r"\][ ]?\[")
_ROLE = re.compile(r":(?:py:)?(?:func|class|mod|meth|attr|data|obj|exc|const|ref):`~?([^`]+)`")


def _no_reference_links(line: str) -> str:
    """``[a] [b]`` or ``[a][b]`` outside code spans, escaped so Markdown does not read a
    reference link in it (docstrings write units and options in brackets: ``[m/s^2]``)."""
    parts = line.split("`")
    for i in range(0, len(parts), 2):  # the even parts are outside code spans
        parts[i] = _REFLINK.sub(lambda m: m.group(0)[:-1] + "&#91;", parts[i])
    return "`".join(parts)


def _sections(lines: list[str]) -> list[str]:
    """numpy-style sections (``Parameters`` over a line of dashes) as a bold title and, for
    the lists of names (parameters, returns, attributes, raises), the list as preformatted
    text up to the first blank line: nsdyn aligns each name's type and meaning in columns, as
    ``help()`` shows them, which a code block keeps."""
    out, i = [], 0
    while i < len(lines):
        line = lines[i]
        title = line.strip()
        if i + 1 < len(lines) and re.fullmatch(r"-{3,}", lines[i + 1].strip() or "x"):
            out += ["", f"**{title}**", ""]
            i += 2
            if title in _LISTS:
                while i < len(lines) and lines[i].strip():
                    out.append("    " + lines[i])
                    i += 1
                out.append("")
            continue
        out.append(line)
        i += 1
    return out


def markdown_of(text: str) -> str:
    """``text`` with reST roles turned into code spans, literal-block ``::`` into ``:``,
    numpy-style sections kept as written, and bracketed words kept from reading as Markdown
    reference links."""
    text = _ROLE.sub(lambda m: f"`{m.group(1)}`", text)
    lines = _sections(text.split("\n"))
    for i, line in enumerate(lines):
        stripped = line.rstrip()
        if stripped.endswith("::"):
            body = stripped[:-2].rstrip()
            stripped = body + ":" if body else ""
        lines[i] = stripped if stripped.startswith("    ") else _no_reference_links(stripped)
    return "\n".join(lines)
