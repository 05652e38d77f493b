"""The scene-file reference: every key of every scene kind, from the schemas the readers use.

Each family declares its keys once in ``nsdyn/models/<kind>/scene_keys.py``
(:class:`nsdyn.models.scene_schema.Schema`); the scene readers check files against the same
declarations, and ``tests/docs/test_scene_reference.py`` checks that the keys the readers accept
and the keys on this page are the same.
"""

from __future__ import annotations


def schemas():
    """The schema of every scene kind, in the order of ``nsdyn.models.scenefile.KINDS``."""
    from nsdyn.models.scene_schema import schema_of
    from nsdyn.models.scenefile import KINDS

    return [schema_of(k) for k in KINDS]


def page() -> str:
    """The Markdown of ``reference/scenes.md``."""
    lines = [
        "# Scene-file reference",
        "",
        "A scene is a TOML file that `nsdyn run SCENE.toml` runs and `nsdyn study` varies. Its",
        "`[scene] kind` names the model family (`isolated` when absent). Every key of every",
        "kind is listed below with its type, unit, default and allowed values. A key that is",
        'not listed is refused with the nearest valid one ("did you mean …?"); a value out of',
        "its range is refused with the file, the `table.key` and the expected form.",
        "",
        "This page is generated from the schemas the scene readers check files against",
        "(`nsdyn/models/<kind>/scene_keys.py`, beside each reader), so it lists exactly what",
        "the readers accept.",
        "Example scenes of every kind are in `examples/scenes/`.",
        "",
        "| kind | what it models | tables |",
        "|---|---|---|",
    ]
    for s in schemas():
        tables = ", ".join(f"`[{t}]`" for t in s.fields())
        anchor = f"kind-{s.kind}-{s.title}"
        lines.append(f"| [`{s.kind}`](#{_slug(anchor)}) | {s.title} | {tables} |")
    lines.append("")
    for s in schemas():
        lines += [s.markdown(level=2), ""]
    return "\n".join(lines)


def _slug(text: str) -> str:
    """The anchor Python-Markdown's toc gives a heading (its default slugify)."""
    import re
    import unicodedata

    value = unicodedata.normalize("NFKD", text).encode("ascii", "ignore").decode("ascii")
    value = re.sub(r"[^\w\s-]", "", value).strip().lower()
    return re.sub(r"[-\s]+", "-", value)
