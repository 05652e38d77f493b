"""Scene files shared by every model family: TOML reading, field checking, the scene kind.

A scene is a TOML file whose ``[scene] kind`` names the model family that runs it
(``isolated`` when absent — the frame on friction isolators). Each family has a
``nsdyn.models.<kind>.scene`` module with a ``run_scene(cfg, out_dir, figures) -> dict``
that returns the JSON summary of ``nsdyn run``; this module gives them one way to read and
check files, so every family reports bad input the same way: file, table.field, expected form,
and the nearest valid key for a misspelt one.
"""

from __future__ import annotations

import difflib
import glob
import math
import numbers
import re
import tomllib
import warnings
from collections.abc import Mapping
from contextlib import contextmanager
from pathlib import Path

from nsdyn import _textfile as textfile
from nsdyn._checks import InputWarning, did_you_mean

# [scene] kind -> its runner
KINDS = ("isolated", "rocking", "contact", "cylinder", "deck", "building3d")
# kinds whose runner is not nsdyn.models.<kind>.scene (a family's package holds it)
SCENE_MODULES = {
    "deck": "nsdyn.models.isolated.deck_scene",
    "building3d": "nsdyn.models.isolated.building3d_scene",
}


class SceneError(ValueError):
    """A scene file or option is invalid; the message names the file and field (a value given
    as a boolean quoted as TOML spells it: "got true", not Python's "got True")."""

    def __init__(self, message="", *rest):
        if isinstance(message, str):
            message = re.sub(r"\bgot (True|False)\b", lambda m: f"got {m[1].lower()}", message)
        super().__init__(message, *rest)


# the fields of every scene family that name a file (a frame, a record or its components)
FILE_FIELDS = (
    ("scene", "frame"),
    ("structure", "frame3d"),
    ("force", "record"),
    *(("motion", k) for k in ("record", "record_y", "record_z", "x", "y", "z")),
)


def resolve_paths(cfg: Mapping, folder: str | Path, source: str = "") -> dict:
    """``cfg`` with its relative file names (:data:`FILE_FIELDS`) read from ``folder``, the
    scene file's: a name with a file of that name in ``folder`` becomes that file's absolute
    path (unless it names the same file from the current folder); any other value (a bundled
    name, an absolute path, a file missing there) is kept as written, a file missing there
    but found from the current folder with an InputWarning; a bare name beside a
    file of that name and a suffix (``portal`` by ``portal.toml``) is an InputWarning."""
    folder = Path(folder)
    out = {k: dict(v) if isinstance(v, Mapping) else v for k, v in cfg.items()}
    for table, key in FILE_FIELDS:
        v = out.get(table, {}).get(key) if isinstance(out.get(table), dict) else None
        if isinstance(v, str) and not v.strip():  # (it read as the folder '.')
            raise SceneError(f"{source or folder}: {table}.{key}: expected a bundled name or "
                             f"a file's path, got {v!r}")  # fmt: skip
        if not isinstance(v, str) or Path(v).is_absolute():
            continue
        there = folder / v
        if there.is_file() and not (Path(v).is_file() and Path(v).resolve() == there.resolve()):
            out[table][key] = str(there.resolve())
        elif not there.exists() and Path(v).is_file() and folder.is_dir():
            # (the same scene read another file, or none, when started from another folder)
            out[table][key] = str(Path(v).resolve())
            warnings.warn(f"{source or folder}: {table}.{key} = {v!r} is not beside the scene "
                          f"(in {folder}); read from the current folder: {Path(v).resolve()}",
                          InputWarning, stacklevel=3)  # fmt: skip
        elif not Path(v).suffix and not there.exists() and folder.is_dir():
            me = Path(source).name  # (the scene itself, office-11.toml naming "office-11")
            near = [p.name for p in sorted(folder.glob(glob.escape(v) + ".*"))
                    if p.is_file() and _reads(key, p) and p.name != me]  # fmt: skip
            if near:  # (the bundled portal ran, the user's portal.toml beside it unread)
                warnings.warn(f"{source or folder}: {table}.{key} = {v!r} is a bundled name "
                              f"(a file is read by its whole name): {near[0]} beside the "
                              "scene is not read; "
                              f"{table}.{key} = {near[0]!r} reads it", InputWarning,
                              stacklevel=3)  # fmt: skip
    return out


NOT_RECORDS = {
    ".toml",
    ".png",
    ".pdf",
    ".svg",
    ".npz",
    ".npy",
    ".json",
    ".parquet",
    ".py",
    ".md",
    ".log",
}  # fmt: skip  (a run's outputs beside a record's name)


def _reads(key: str, path: Path) -> bool:
    """Whether the scene field named ``key`` could read ``path``: a frame a .toml file, a
    record any file but a scene's or a run's output (``NOT_RECORDS``)."""
    frame = key in ("frame", "frame3d")
    return (path.suffix == ".toml") if frame else path.suffix.lower() not in NOT_RECORDS


def scaled_to_pga(motion, pga: float, source: str, field: str = "motion.pga"):
    """``motion.scaled_to_pga(pga)``, its refusal (a record that is zero everywhere, a bad
    target) a :class:`SceneError` naming the scene file and ``field``."""
    try:
        return motion.scaled_to_pga(pga)
    except ValueError as e:  # (the library names its argument, target: the field is named)
        raise SceneError(f"{source}: {field}: {str(e).removeprefix('target: ')}") from None


def scaled_record(motion, mo: dict, source: str):
    """A scene's planar record scaled to its ``[motion] pga`` when given; else as read, or a
    SceneError for one above 100 g (:func:`nsdyn.ground.motion.record_pga_said`)."""
    if "pga" in mo:  # (a positive number, as every scene's; its top: scaled_to_pga's)
        v = mo["pga"]
        if isinstance(v, bool) or not isinstance(v, numbers.Real) or not 0 < v < math.inf:
            raise SceneError(f"{source}: motion.pga: expected a finite positive number, got "
                             f"{v!r}")  # fmt: skip
        return scaled_to_pga(motion, float(v), source)
    from nsdyn.ground.motion import record_pga_said

    if said := record_pga_said(motion.pga):
        raise SceneError(f"{source}: motion.record: {mo.get('record', '')}: {said}")
    return motion


def scene_step(dt, motion, span, source: str, hint: str = "") -> None:
    """:func:`nsdyn._checks.check_fixed_step` of a scene's ``solver.dt`` (no longer than the
    run ``span`` nor the record's sampling step), its refusal a :class:`SceneError` naming the
    scene file (and ``hint``, the default step, after it)."""
    from nsdyn._checks import check_fixed_step

    try:
        check_fixed_step(dt, motion, span, "solver.dt")
    except ValueError as e:
        raise SceneError(f"{source}: {e}{hint}") from None


def record_units(mo: dict, source: str) -> dict:
    """The record reader's keywords of a scene's ``[motion]``: ``units`` and a one-column
    file's sample step ``dt`` where given (``{}`` when neither is); SceneError for units other
    than g, gal (cm/s2) or m/s2, or either without a record."""
    out = {k: mo[k] for k in ("units", "dt") if k in mo}
    if not out:
        return {}
    from nsdyn.models.scene_schema import RECORD_UNITS

    if not any(k in mo for k in ("record", "record_y", "record_z", "simulated")):
        what = "units of a record file" if "units" in out else "sample step of a record file"
        raise SceneError(f"{source}: motion.{next(iter(out))}: the {what}; this scene "
                         "reads none (motion.record)")  # fmt: skip
    if "units" in out and out["units"] not in RECORD_UNITS:
        raise SceneError(f"{source}: motion.units: expected one of {list(RECORD_UNITS)}, got "
                         f"{mo['units']!r}")  # fmt: skip
    return out


def bundled_frame_said(name) -> str | None:
    """The refusal of a bundled frame's name given where a scene goes (``office-11``: "no such
    scene file"), naming the key a scene names it by; None for any other name."""
    from nsdyn.structure import bundled_frames, is_frame3d

    if str(name) not in bundled_frames():
        return None
    key, of = ("[structure] frame3d", " of kind 'building3d'") if is_frame3d(str(name)) else \
        ("[scene] frame", "")  # fmt: skip
    return f'{name}: a bundled frame, not a scene; a scene{of} names it as {key} = "{name}"'


def read_toml(path: str | Path, what: str = "scene") -> dict:
    """The parsed TOML file, or :class:`SceneError` naming the file and the syntax error.

    A file without a single table or key (empty, or comments only) is refused: it would
    otherwise run the defaults, which is never what a file named on the command line means.
    ``what`` names the kind of file in the messages ("scene", "study"). A scene's file names
    are read from the scene's folder first (:func:`resolve_paths`).
    """
    p = Path(path)
    if p.is_dir():
        raise SceneError(f"{path}: a folder; expected a {what} file (.toml)")
    if not p.is_file():
        said = bundled_frame_said(path) if what == "scene" else None
        if said:
            raise SceneError(said)
        number = re.fullmatch(r"[+-]?(\d+\.?\d*|\.\d+)", str(path)) and what == "scene"
        # ("--amplitudes 0.5 1": the 1 was taken for the scene)
        hint = "; a number: an option's values are comma-separated (--amplitudes 0.5,1)"
        hint = hint if number else ""
        raise SceneError(f"{path}: no such {what} file{hint}")
    text = ""
    try:
        data = tomllib.loads(text := textfile.read(p))  # (a byte-order mark read and dropped)
    except tomllib.TOMLDecodeError as e:
        if p.suffix.lower() in textfile.RECORD_SUFFIXES and what == "scene":
            raise SceneError(
                f"{path}: not a scene (TOML) file; a ground-motion record is given to a scene "
                f'as [motion] record = "{path}", or to nsdyn run as --record {path}'
            ) from None
        json = " (a JSON file? {what} files are TOML: [table] and key = value lines)" * (
            p.suffix.lower() == ".json" or text.lstrip().startswith("{"))  # fmt: skip
        raise SceneError(f"{path}: not valid TOML{json.format(what=what)}: {e}") from None
    except ValueError as e:  # (bytes that are not UTF-8 text)
        raise SceneError(f"{path}: {e}") from None
    if not data:
        example = "[study] name = ... and [parameters]" if what == "study" else "[scene] kind"
        raise SceneError(
            f"{path}: empty {what} file (no table or key); expected TOML tables such as "
            f"{example} (see the examples)"
        )
    if what == "scene" and "study" in data:
        raise SceneError(f"{path}: a study file (its [study] table), not a scene; run it with "
                         f"nsdyn study {path}")  # fmt: skip
    if what == "study" and "study" not in data and {"frame", "frame3d"} & data.keys():
        key = "frame" if "frame" in data else "frame3d"
        where = "[base.scene] frame" if key == "frame" else "[base.structure] frame3d"
        raise SceneError(f"{path}: a frame file (its [{key}] table), not a study; name it in a "
                         f'study as {where} = "{path}"')  # fmt: skip
    scene_tables = {"scene", "motion", "isolation", "solver", "structure", "force"}
    if what == "study" and "study" not in data and scene_tables & data.keys():
        raise SceneError(f"{path}: a scene file, not a study (no [study] table); run it with "
                         f"nsdyn run {path}, or name it in a study as [study] scene = "
                         f'"{path}"')  # fmt: skip
    if what == "scene" and "scene" not in data and "frame" in data:
        raise SceneError(
            f"{path}: a frame file (its [frame] table), not a scene; a scene names it as [scene] "
            f'frame = "{path}" (nsdyn run --frame {path} runs it on the default scene)'
        )
    if what == "scene" and "scene" not in data and "frame3d" in data:
        raise SceneError(
            f"{path}: a 3D frame file (its [frame3d] table), not a scene; name it in a scene "
            f"of kind 'building3d' as [structure] frame3d = \"{path}\" "
            "(examples/scenes/building3d-office-cb.toml)"
        )
    return resolve_paths(data, p.parent, str(path)) if what == "scene" else data


# keys that tables mean their own way (a scene's kind against a ground's, a record's dt against
# a solver's step): no hint of where they belong, but for the homes named here (a deck's type
# is its bearing's: no other table of its has one)
GENERIC_KEYS = frozenset({"kind", "name", "type", "dt", "case"})
GENERIC_HOMES = frozenset({("type", "bearing")})


def unknown_key(source: str, where: str, key: str, valid, tables=None) -> SceneError:
    """Error for a key not in ``valid``, suggesting the closest valid key if there is one,
    else the other tables of ``tables`` (table -> its keys) that have it: a key in the wrong
    table (a frame scene's ``[solver] mu``, a deck's ``[bearing] law``) was only "unknown"."""
    valid = sorted(valid)
    hint = did_you_mean(key, valid)
    here = where.rstrip(".")
    homes = [f"[{t}]" for t, keys in (tables or {}).items() if t != here and key in (keys or ())
             and (key not in GENERIC_KEYS or (key, t) in GENERIC_HOMES)]  # fmt: skip
    if homes:  # (an exact key elsewhere before a near one here: deck.mu is no mass 'm')
        near = f" (or{hint.removeprefix(';')})".replace("? )", "?)") if hint else ""
        hint = f"; a key of {' or '.join(homes)}, not of [{here}]{near};"
    return SceneError(
        f"{source}: {where}{key}: unknown field{hint or ';'} expected some of {valid}"
    )


def refuse_keys(table: Mapping, source: str, where: str, keys, why: str) -> None:
    """:class:`SceneError` for the first of ``keys`` present in ``table`` (``where.key``):
    a key the scene's other choices leave unused is refused with ``why``, not ignored."""
    for key in keys:
        if key in table:
            raise SceneError(f"{source}: {where}.{key}: {why}")


def check_fields(cfg: Mapping, fields: Mapping, source: str, tables=None) -> None:
    """:class:`SceneError` for a table of ``cfg`` not in ``fields`` (table -> its valid keys;
    named among ``tables``, default ``fields``'s, the scene's whole set where some are checked
    elsewhere), one that is not a table, or a key its table does not have."""
    for table, vals in cfg.items():
        if table not in fields:
            valid = sorted(fields if tables is None else tables)
            raise SceneError(f"{source}: [{table}]: unknown table{did_you_mean(table, valid)}"
                             f"{'' if did_you_mean(table, valid) else ';'} expected some of "
                             f"{valid}")  # fmt: skip
        if not isinstance(vals, dict):
            raise SceneError(f"{source}: [{table}]: expected a table")
        for key in vals:
            if key not in fields[table]:
                raise unknown_key(source, f"{table}.", key, fields[table], fields)


def scene_module(kind: str) -> str:
    """Dotted name of the module with the ``run_scene`` of a scene kind."""
    return SCENE_MODULES.get(kind, f"nsdyn.models.{kind}.scene")


NAME_MAX = 200  # bytes of a scene's name (it may name output files: a 1e5-character one ran)


def file_stem(name: str) -> str:
    """A scene's name as the stem of the files it names (a cylinder's ``NAME.npz``): its path
    separators as "_" and no leading dot (a cylinder scene named "../x" wrote its files beside
    the folder; ".x" would be a hidden file)."""
    name = "".join(c if c.isprintable() else "_" for c in str(name))  # (a frame's name is
    name = name.encode()[:NAME_MAX].decode(errors="ignore")  # not checked as a scene's is)
    return name.replace("/", "_").replace("\\", "_").lstrip(".") or "_"


def scene_kind(cfg: Mapping, source: str = "<scene>") -> str:
    """The model family of a parsed scene (``[scene] kind``, default ``isolated``); its
    ``[scene] name``, when given, checked as text a file's stem can hold (:func:`file_stem`:
    :data:`NAME_MAX` bytes at most, no control character)."""
    kind = cfg.get("scene", {}).get("kind", "isolated")
    if kind not in KINDS:
        close = difflib.get_close_matches(str(kind), KINDS, n=1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise SceneError(f"{source}: scene.kind: expected one of {list(KINDS)}, got {kind!r}{hint}")
    name = cfg.get("scene", {}).get("name", "x")
    if isinstance(name, str) and (len(name.encode()) > NAME_MAX or not name.strip()
                                  or any(ord(c) < 32 for c in name)):  # fmt: skip
        shown = repr(name) if len(name) <= 60 else f"{name[:40]!r}... ({len(name)} characters)"
        raise SceneError(f"{source}: scene.name: expected a name of 1 to {NAME_MAX} bytes "
                         f"without control characters (it may name the output files), got "
                         f"{shown}")  # fmt: skip
    return kind


def rel_tol(source: str, name: str, val) -> float:
    """``val`` as a relative tolerance ``RTOL_MIN <= val < 1``, or :class:`SceneError` naming
    ``source: name`` (the check of :func:`nsdyn._checks.rel_tol`, before any run)."""
    from nsdyn._checks import rel_tol as check

    number(source, name, val)  # its type errors first
    try:
        return check(name, val)
    except ValueError as e:
        raise SceneError(f"{source}: {e}") from None


def number(source: str, name: str, val, *, positive: bool = True, allow_zero: bool = False):
    """``val`` as a float, or :class:`SceneError` naming ``source: name`` and the form wanted."""
    if isinstance(val, bool) or not isinstance(val, int | float):
        raise SceneError(f"{source}: {name}: expected a number, got {val!r}")
    v = float(val)
    if v != v or v in (float("inf"), float("-inf")):
        raise SceneError(f"{source}: {name}: expected a finite number, got {val!r}")
    if positive and not (v > 0 or (allow_zero and v == 0)):
        what = "a non-negative" if allow_zero else "a positive"
        raise SceneError(f"{source}: {name}: expected {what} number, got {val!r}")
    return v


GRID_FIELDS = {  # the fields of a run's grid and start, refused by a library before any step
    "t_end": "motion.t_end",
    "dt_out": "solver.dt_out",
    "theta0": "motion.theta0",
    "theta0_over_alpha": "motion.theta0_over_alpha",
}


@contextmanager
def grid_fields(source: str, fields: Mapping = GRID_FIELDS):
    """A run's grid refused by the library (ValueError "t_end: …" / "dt_out: …", raised before
    any step) as a SceneError naming the scene's field; other errors pass unchanged."""
    try:
        yield
    except ValueError as e:
        name, _, text = str(e).partition(":")
        if name not in fields or not text:
            raise
        raise SceneError(f"{source}: {fields[name]}:{text}") from None


def record_replaces_motion(kind: str, mo: dict, replaces, source: str) -> str | None:
    """Give a scene's ``[motion]`` table ``mo`` to a record (in place): the keys of the
    closed-form motion it replaces (``replaces``: a rocking pulse's, a contact sine's, a
    cylinder's simulated earthquake's) go, and with a closed-form motion present (a cylinder
    without a record always has one) so do its amplitude ``pga`` (a pulse's, a sine's: the
    record runs at its own scale) and its ``t_end`` (chosen for that motion: the record runs
    to its end). Returns a note naming the dropped ``t_end``, or None."""
    cylinder = kind == "cylinder"  # (its dt beside a record: the record file's own step)
    closed = (any(k in mo for k in replaces if not (cylinder and k == "dt" and "record" in mo))
              or (cylinder and "record" not in mo))  # fmt: skip
    for key in replaces:
        mo.pop(key, None)
    if not closed:
        return None
    if kind in ("rocking", "contact"):  # the pulse's or sine's amplitude, not a record's scale
        mo.pop("pga", None)
    if "t_end" not in mo:
        return None
    t_end = number(source, "motion.t_end", mo.pop("t_end"))
    return (f"the scene's t_end = {t_end:g} s was its closed-form motion's; the record runs to "
            "its end (--t-end to shorten it)")  # fmt: skip
