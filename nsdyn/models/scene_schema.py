"""Scene-file schemas: every key of every scene kind, declared once, for the readers and the docs.

A family declares its scene file as a :class:`Schema`: tables of :class:`Key` s, each with its
type, unit, default, allowed range and meaning. A table may come in variants chosen by a key of
its own (``[motion] kind = "harmonic"``, ``[structure] kind = "shear"``); ``Schema.fields()``
gives the reader the valid keys of each table (the union over its variants), which is what
:func:`nsdyn.models.scenefile.check_fields` checks a file against, so a misspelt key gets the
nearest valid one ("did you mean") from the same source. The documentation's scene-file
reference is generated from these schemas (``Schema.markdown()``), and a test checks that every
key a reader accepts is in the reference and every key of the reference is accepted, so the
docs and the readers cannot drift.

Each family's schema is the ``SCHEMA`` of the module beside its scene reader, named after it
with ``_keys`` (``nsdyn.models.rocking.scene`` -> ``nsdyn.models.rocking.scene_keys``);
:func:`schema_of` finds it for a ``[scene] kind``.

A key's range is declared as bounds ``lo <= v`` / ``lo < v`` and ``v <= hi`` / ``v < hi``
(``lo_open``, ``hi_open``) or as ``choices``; :meth:`Key.range_text` writes it for people.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field

from nsdyn._checks import RTOL_MIN

NO_DEFAULT = object()  # a key that has no default (optional, or required if ``required``)
# a relative tolerance: RTOL_MIN <= v < 1 (nsdyn._checks.rel_tol; from 1 on, any step passes
# the error test; below 100x double precision's epsilon it measures round-off)
# [motion] units of a record file, every family
RECORD_UNITS = ("g", "gal", "cm/s2", "mm/s2", "m/s2")
REL_TOL = {"lo": RTOL_MIN, "lo_open": False, "hi": 1.0, "hi_open": True}


@dataclass(frozen=True)
class Key:
    """One key of a scene table."""

    name: str
    type: str  # "number", "integer", "boolean", "string", "list of numbers", ...
    meaning: str
    unit: str = ""
    default: object = NO_DEFAULT
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    choices: tuple = ()
    required: bool = False
    range: str = ""  # a range that bounds cannot say ("< 2H", "one per isolator", ...)

    def range_text(self) -> str:
        """The allowed values in words: ``> 0``, ``0 < v ≤ 1``, ``one of …``."""
        if self.choices:
            return "one of " + ", ".join(f"`{c}`" for c in self.choices)
        parts = []
        if self.lo is not None and self.hi is not None:
            lo = "<" if self.lo_open else "≤"
            hi = "<" if self.hi_open else "≤"
            parts.append(f"{self.lo:g} {lo} v {hi} {self.hi:g}")
        elif self.lo is not None:
            parts.append(f"{'>' if self.lo_open else '≥'} {self.lo:g}")
        elif self.hi is not None:
            parts.append(f"{'<' if self.hi_open else '≤'} {self.hi:g}")
        if self.range:
            parts.append(self.range)
        return "; ".join(parts)

    def default_text(self) -> str:
        """The default as it would be written in TOML, or *required* / — (none)."""
        if self.required:
            return "*required*"
        d = self.default
        if d is NO_DEFAULT:
            return "—"
        if isinstance(d, bool):
            return "`true`" if d else "`false`"
        if isinstance(d, str):
            return f'`"{d}"`' if not d.startswith("(") else d
        if isinstance(d, float):
            return f"`{d:g}`"
        if isinstance(d, tuple | list):
            return "`[" + ", ".join(f"{v:g}" for v in d) + "]`"
        return f"`{d}`"


# the [motion] key of a record file's units, one for every family's scene
UNITS_KEY = Key(
    "units",
    "string",
    "units of the record file(s) where they state none (or others: these win, with a warning)",
    choices=RECORD_UNITS,
)


# the [motion] key of a one-column record file's sample step, one for every family's scene
RECORD_DT_KEY = Key("dt", "number", "sample step of a single-column record file", "s", lo=0.0,
                    lo_open=True)  # fmt: skip


@dataclass(frozen=True)
class Table:
    """A scene table (``[name]``), or one variant of it (``variant`` = 'kind = "shear"')."""

    name: str
    meaning: str
    keys: tuple[Key, ...]
    variant: str = ""

    def names(self) -> set[str]:
        """The valid keys of this table (variant)."""
        return {k.name for k in self.keys}


@dataclass(frozen=True)
class Schema:
    """The scene file of one model family (``[scene] kind``)."""

    kind: str
    title: str
    intro: str
    tables: tuple[Table, ...]
    notes: tuple[str, ...] = field(default=())

    def table(self, name: str, variant: str = "") -> Table:
        """The table ``[name]`` (its variant ``variant`` where it has several)."""
        for t in self.tables:
            if t.name == name and (t.variant == variant or not variant):
                return t
        raise KeyError(f"{self.kind}: no table [{name}] {variant}".strip())

    def fields(self) -> dict[str, set[str]]:
        """Table -> its valid keys (the union over the table's variants), for check_fields."""
        out: dict[str, set[str]] = {}
        for t in self.tables:
            out.setdefault(t.name, set()).update(t.names())
        return out

    def keys(self, name: str, variant: str = "") -> set[str]:
        """The valid keys of ``[name]`` (of one variant, if given)."""
        return self.table(name, variant).names() if variant else self.fields()[name]

    def markdown(self, level: int = 2) -> str:
        """This schema as a Markdown section: one table of keys per scene table (variant)."""
        h = "#" * level
        lines = [f'{h} `kind = "{self.kind}"`: {self.title}', "", self.intro, ""]
        for t in self.tables:
            head = f"[{t.name}]" + (f" with {t.variant}" if t.variant else "")
            lines += [f"{h}# `{head}`", "", t.meaning, ""]
            lines += [
                "| key | type | unit | default | allowed | meaning |",
                "|---|---|---|---|---|---|",
            ]
            for k in t.keys:
                cells = (
                    f"`{k.name}`",
                    k.type,
                    k.unit or "—",
                    k.default_text(),
                    k.range_text() or "—",
                    k.meaning,
                )
                lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
            lines.append("")
        for note in self.notes:
            lines += [note, ""]
        return "\n".join(lines)


def schema_of(kind: str) -> Schema:
    """The schema of the scene kind ``kind`` (``SCHEMA`` of its reader's ``_keys`` module)."""
    from nsdyn.models import scenefile

    reader = getattr(scenefile, "SCENE_MODULES", {}).get(kind, f"nsdyn.models.{kind}.scene")
    return importlib.import_module(reader + "_keys").SCHEMA
