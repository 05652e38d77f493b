"""Frame files: strict reading of a plane frame from TOML, and the frames bundled with nsdyn.

A file holds one ``[frame]`` table, either ``kind = "regular"`` (bays, storey heights, mesh
``n_v``/``n_h``, column and beam sections E [Pa], A [m²], I [m⁴], ρA [kg/m], floor masses [kg],
modal damping ratios 0 ≤ ζ < 1) built by :func:`nsdyn.structure.frame.regular_frame`, or
``kind = "explicit"`` (nodes, elements with section indices, base nodes, node masses). Every
error names the file, the dotted field and what was expected (:class:`FrameFileError`).
"""

from __future__ import annotations

import os
import tomllib
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from nsdyn import _textfile as textfile
from nsdyn._bundled import FRAMES
from nsdyn._checks import did_you_mean
from nsdyn.structure.frame import Frame, Section, regular_frame
from nsdyn.structure.geometry import ALL_BASE_FILE, section_notes


class FrameFileError(ValueError):
    """A frame file is missing, unreadable or invalid. The message names the file, the
    field (dotted path) and what was expected; ``field`` is that dotted path ("" when the
    file itself is missing or unreadable)."""

    def __init__(self, message: str, field: str = ""):
        super().__init__(message)
        self.field = field


class _Reader:
    """Strict typed access to a parsed TOML table; errors name file and dotted field."""

    def __init__(self, file: str):
        self.file = file

    def fail(self, path: str, expected: str, got: Any = None, raw: bool = False) -> None:
        got_s = got if raw else _describe(got)
        msg = f"{self.file}: {path}: expected {expected}"
        if got is not None or raw:
            msg += f", got {got_s}"
        raise FrameFileError(msg, path)

    def table(self, tbl: Mapping, key: str, path: str) -> Mapping:
        if key not in tbl:
            self.fail(path, "a table", "nothing (missing)", raw=True)
        v = tbl[key]
        if not isinstance(v, Mapping):
            self.fail(path, "a table", v)
        return v

    def known(self, tbl: Mapping, allowed: set[str], path: str) -> None:
        for k in tbl:
            if k not in allowed:
                where = f"{path}.{k}" if path else k
                hint = did_you_mean(str(k), sorted(allowed))
                allow = ", ".join(sorted(allowed))
                raise FrameFileError(
                    f"{self.file}: {where}: unknown field{hint} (allowed: {allow})", where
                )

    def string(self, tbl, key, path):
        if key not in tbl:
            self.fail(path, "a string", "nothing (missing)", raw=True)
        v = tbl[key]
        if not isinstance(v, str) or not v:
            self.fail(path, "a non-empty string", v)
        return v

    def integer(self, tbl, key, path, minimum=None):
        if key not in tbl:
            self.fail(path, "an integer", "nothing (missing)", raw=True)
        v = tbl[key]
        if isinstance(v, bool) or not isinstance(v, int) or (minimum is not None and v < minimum):
            what = "an integer" if minimum is None else f"an integer >= {minimum}"
            self.fail(path, what, v)
        return v

    def number_or_list(self, tbl, key, path, n, positive=True, nonneg=False):
        """A single number (broadcast to n) or a list of exactly n numbers."""
        kinds = "positive numbers" if positive else "numbers >= 0" if nonneg else "numbers"
        kind = kinds.replace("numbers", "number")
        # (one value, as an explicit 3D frame's section takes: "a list of 1" read oddly)
        expected = f"a {kind}" if n == 1 else f"a {kind} or a list of {n} {kinds}"
        if key not in tbl:
            self.fail(path, expected, "nothing (missing)", raw=True)
        v = tbl[key]
        if _is_number(v):
            vals = [float(v)] * n
        elif isinstance(v, list):
            if len(v) != n or not all(_is_number(x) for x in v):
                self.fail(path, expected, v)
            vals = [float(x) for x in v]
        else:
            self.fail(path, expected, v)
        self._check_sign(vals, path, expected, v, positive, nonneg)
        return vals

    def number_list(self, tbl, key, path, n=None, positive=True, nonneg=False, min_len=1):
        kind = "positive numbers" if positive else "numbers >= 0" if nonneg else "numbers"
        expected = f"a list of {n} {kind}" if n is not None else f"a non-empty list of {kind}"
        if key not in tbl:
            self.fail(path, expected, "nothing (missing)", raw=True)
        v = tbl[key]
        if (
            not isinstance(v, list)
            or not all(_is_number(x) for x in v)
            or (n is not None and len(v) != n)
            or len(v) < min_len
        ):
            self.fail(path, expected, v)
        vals = [float(x) for x in v]
        self._check_sign(vals, path, expected, v, positive, nonneg)
        return vals

    def _check_sign(self, vals, path, expected, v, positive, nonneg):
        arr = np.asarray(vals, float)
        if not np.all(np.isfinite(arr)):
            self.fail(path, expected, v)
        if positive and np.any(arr <= 0) or nonneg and np.any(arr < 0):
            bad = next(x for x in vals if (x <= 0 if positive else x < 0))
            said = _describe(v) + (f" (contains {bad:g})" if isinstance(v, list) else "")
            self.fail(path, expected, said, raw=True)  # (a scalar was echoed twice)


def _is_number(x) -> bool:
    return isinstance(x, int | float) and not isinstance(x, bool)


def _describe(v) -> str:
    if isinstance(v, list):  # a short list shown whole, so that its bad entry shows
        text = repr(v)
        return text if len(v) <= 12 and len(text) <= 80 else f"a list of {len(v)}"
    if isinstance(v, Mapping):
        return "a table"
    if isinstance(v, bool):
        return f"boolean {str(v).lower()}"
    if isinstance(v, str):
        return f"string {v!r}"
    return repr(v)


_SECTION_KEYS = ("E", "A", "I", "rho_A")
_REGULAR_KEYS = {
    "name",
    "kind",
    "description",
    "bays",
    "storey_heights",
    "n_v",
    "n_h",
    "columns",
    "beams",
    "floor_mass",
    "zeta",
}
_EXPLICIT_KEYS = {
    "name",
    "kind",
    "description",
    "nodes",
    "elements",
    "sections",
    "base_nodes",
    "node_mass",
    "zeta",
}


def _sections_per(rd: _Reader, frame: Mapping, key: str, n: int) -> list[Section]:
    path = f"frame.{key}"
    tbl = rd.table(frame, key, path)
    rd.known(tbl, set(_SECTION_KEYS), path)
    cols = {}
    for k in _SECTION_KEYS:
        cols[k] = rd.number_or_list(
            tbl, k, f"{path}.{k}", n, positive=k != "rho_A", nonneg=k == "rho_A"
        )
    section_notes(path, tbl, cols["E"], cols["A"], cols["rho_A"])  # (before the elements')
    return [Section(*(cols[k][i] for k in _SECTION_KEYS)) for i in range(n)]


def _zeta(rd: _Reader, frame: Mapping) -> list[float]:
    z = rd.number_list(frame, "zeta", "frame.zeta", positive=False, nonneg=True)
    if any(x >= 1 for x in z):
        rd.fail("frame.zeta", "damping ratios in [0, 1)", z)
    return z


def not_a_frame(data: Mapping, file: str, table: str) -> None:
    """FrameFileError when ``data`` (without a ``[table]``) is a scene or a study file given
    where a frame is read, naming it as what it is and the command that takes it."""
    for key, what, how in (("scene", "a scene file", "nsdyn run"),
                           ("study", "a study file", "nsdyn study")):  # fmt: skip
        if key in data and table not in data:
            raise FrameFileError(f"{file}: {what} (its [{key}] table), not a frame file; "
                                 f"run it with {how} {file}")  # fmt: skip


def frame_from_dict(data: Mapping, file: str = "<dict>") -> Frame:
    """Build a :class:`Frame` from parsed TOML data (``{"frame": {...}}``), strictly.

    Raises :class:`FrameFileError` naming ``file``, the dotted field and what was expected.
    """
    rd = _Reader(file)
    if "frame3d" in data:
        rd.fail("frame3d", "a plane [frame] table (a 3D frame file is read by load_frame3d)")
    not_a_frame(data, file, "frame")
    rd.known(data, {"frame"}, "")
    frame = rd.table(data, "frame", "frame")
    name = rd.string(frame, "name", "frame.name")
    kind = frame.get("kind", "regular")
    if kind not in ("regular", "explicit"):
        rd.fail("frame.kind", "'regular' or 'explicit'", kind)
    if "kind" not in frame and ("nodes" in frame or "elements" in frame):  # (it said "nodes:
        rd.fail(
            "frame.kind",
            "kind = 'explicit' for a frame of nodes and elements (without "
            "it a frame is 'regular', of bays and storeys)",
        )  # unknown field")
    if "description" in frame and not isinstance(frame["description"], str):
        rd.fail("frame.description", "a string", frame["description"])
    if kind == "regular":
        rd.known(frame, _REGULAR_KEYS, "frame")
        bays = rd.number_list(frame, "bays", "frame.bays")
        hs = rd.number_list(frame, "storey_heights", "frame.storey_heights")
        n = len(hs)
        n_v = rd.integer(frame, "n_v", "frame.n_v", minimum=1)
        n_h = rd.integer(frame, "n_h", "frame.n_h", minimum=1)
        cols = _sections_per(rd, frame, "columns", n)
        beams = _sections_per(rd, frame, "beams", n)
        fm = rd.number_or_list(frame, "floor_mass", "frame.floor_mass", n, False, True)
        zeta = _zeta(rd, frame)
        try:
            return regular_frame(name, bays, hs, n_v, n_h, cols, beams, fm, zeta)
        except ValueError as exc:  # (a size out of reach, nodes at one place: a traceback)
            why = " ".join(str(exc).split())
            raise FrameFileError(f"{rd.file}: frame: {why}", "frame") from None

    rd.known(frame, _EXPLICIT_KEYS, "frame")
    raw_nodes = frame.get("nodes")
    if not isinstance(raw_nodes, list) or len(raw_nodes) < 2:
        rd.fail("frame.nodes", "a list of >= 2 [x, y] pairs", raw_nodes)
    for k, p in enumerate(raw_nodes):  # (the node named: "got a list of 7" said which not)
        if not (isinstance(p, list) and len(p) == 2 and all(_is_number(c) for c in p)):
            rd.fail(f"frame.nodes[{k}]", "a pair [x, y] of numbers [m]", p, raw=True)
    nodes = np.array(raw_nodes, float)
    nn = len(nodes)
    raw_secs = frame.get("sections")
    if not isinstance(raw_secs, list) or not raw_secs:
        rd.fail("frame.sections", "a non-empty array of tables [[frame.sections]]", raw_secs)
    secs = []
    for i, s in enumerate(raw_secs):
        p = f"frame.sections[{i}]"
        if not isinstance(s, Mapping):
            rd.fail(p, "a table with E, A, I, rho_A", s)
        rd.known(s, set(_SECTION_KEYS), p)
        vals = [
            rd.number_or_list(s, k, f"{p}.{k}", 1, positive=k != "rho_A", nonneg=k == "rho_A")[0]
            for k in _SECTION_KEYS
        ]
        secs.append(Section(*vals))
        section_notes(p, s, *([v] for v in vals[:2]), [vals[3]])
    raw_el = frame.get("elements")
    form = (f"[node_i, node_j] or [node_i, node_j, section] with two different nodes in "
            f"0..{nn - 1} and section in 0..{len(secs) - 1}")  # fmt: skip
    if not isinstance(raw_el, list) or not raw_el:
        rd.fail("frame.elements", f"a non-empty list of {form}", raw_el)
    el, sid = [], []
    for k, e in enumerate(raw_el):
        good = (
            isinstance(e, list)
            and len(e) in (2, 3)
            and all(isinstance(c, int) and not isinstance(c, bool) for c in e)
            and 0 <= e[0] < nn
            and 0 <= e[1] < nn
            and e[0] != e[1]
            and (len(e) == 2 or 0 <= e[2] < len(secs))
        )
        if not good:
            rd.fail(f"frame.elements[{k}]", form, e)
        el.append(e[:2])
        sid.append(e[2] if len(e) == 3 else 0)
    raw_base = frame.get("base_nodes")
    if (
        not isinstance(raw_base, list)
        or not raw_base
        or not all(isinstance(b, int) and not isinstance(b, bool) and 0 <= b < nn for b in raw_base)
        or len(set(raw_base)) != len(raw_base)
    ):
        rd.fail("frame.base_nodes", f"a list of distinct node indices in 0..{nn - 1}", raw_base)
    if len(raw_base) == nn:
        rd.fail("frame.base_nodes", ALL_BASE_FILE.format(nn=nn), raw_base)
    node_mass = (
        rd.number_or_list(frame, "node_mass", "frame.node_mass", nn, False, True)
        if "node_mass" in frame
        else np.zeros(nn)
    )
    zeta = _zeta(rd, frame)
    S = [secs[i] for i in sid]
    try:
        return Frame(
            name=name,
            nodes=nodes,
            elements=np.array(el),
            E=[s.E for s in S],
            A=[s.A for s in S],
            I=[s.I for s in S],
            rho_A=[s.rho_A for s in S],
            node_mass=node_mass,
            base_nodes=np.array(raw_base),
            zeta=zeta,
        )
    except ValueError as exc:  # (an entry's own message names it: frame.nodes[7]: ...)
        sep = "." if str(exc).startswith(("nodes[", "elements[", "node_mass:")) else ": "
        raise FrameFileError(f"{file}: frame{sep}{exc}", field="frame") from None


def bundled_frames() -> list[str]:
    """Names of the frames shipped with nsdyn (``frames/*.toml``)."""
    return FRAMES.names()


def load_frame(name_or_path: str | Path) -> Frame:
    """Load a frame from a TOML file, or a bundled frame by bare name (``"office-11"``).

    A string without a path separator and without the ``.toml`` suffix is a bundled name;
    anything else is a file path. Raises :class:`FrameFileError` for a missing file, an
    unknown bundled name (listing the known ones), bad TOML or invalid fields.
    """
    data, fname = _read_frame_file(name_or_path)
    return with_file_warnings(lambda: frame_from_dict(data, fname), fname, "frame")


def with_file_warnings(build, fname: str, table: str):
    """``build()``, its input warnings (:class:`~nsdyn._checks.InputWarning`: an element of
    3000 m, a frame in mm?) said once each as ``FILE: table.entry: ...`` at the caller's
    line (a frame's own checks name the entry, not the file), also when ``build`` then
    fails; other warnings pass on as they came (once per place, as Python shows them)."""
    from nsdyn._checks import InputWarning

    caught: list = []
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", InputWarning)
            return build()
    finally:  # (outside the recording: what it says is shown, not recorded again)
        _said_with_file(caught, fname, table)


_SHOWN: dict = {}  # the registry of the warnings passed on (Python's once-per-place)


def _said_with_file(caught, fname: str, table: str) -> None:
    from nsdyn._checks import InputWarning

    seen = set()
    for w in caught:
        if not issubclass(w.category, InputWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno, registry=_SHOWN)
            continue
        msg = str(w.message)
        tail = msg.split(": ", 1)[-1]  # (the file's check and the model's name one element
        if tail not in seen:  # by two names: said once, by the file's)
            seen.add(tail)
            head = msg if msg.startswith(f"{table}.") else f"{table}.{msg}"
            warnings.warn(f"{fname}: {head}", w.category, stacklevel=4)


def _read_frame_file(name_or_path: str | Path) -> tuple[dict, str]:
    """(parsed TOML, file name for messages) of a frame file or a bundled frame's bare name
    (the rule of :func:`load_frame`); plane and space frame files alike."""
    if not isinstance(name_or_path, str | os.PathLike):  # ("None: no bundled frame" before)
        raise TypeError(f"frame: expected a bundled frame's name or a file's path, got "
                        f"{type(name_or_path).__name__} {name_or_path!r}")  # fmt: skip
    s = str(name_or_path)
    is_path = isinstance(name_or_path, Path) or "/" in s or "\\" in s or s.endswith(".toml")
    if is_path:
        path = Path(s)
        if not path.is_file():  # (a folder or a device is there, but no frame file)
            what = "not a file (a folder?)" if path.is_dir() else "not a regular file"
            raise FrameFileError(f"{s}: {what if path.exists() else 'no such frame file'}")
        try:
            text, fname = path.read_bytes(), s  # messages name the file as it was given
        except OSError as exc:
            raise FrameFileError(f"{s}: cannot be read ({exc.strerror})") from None
    else:
        f = FRAMES.find(s)
        if f is None:
            known = ", ".join(bundled_frames()) or "(none found)"
            there = " (a folder of that name is here: a frame is a .toml file)" * Path(s).is_dir()
            if Path(s + ".toml").is_file():  # (portal2bay given beside portal2bay.toml)
                there = f" (the file {s}.toml is here: give its whole name)"
            elif Path(s).is_file():  # (a record given where a frame goes: "no bundled frame")
                record = Path(s).suffix.lower() in textfile.RECORD_SUFFIXES
                to = "; a ground-motion record goes in a scene's [motion] record" * record
                there = f" (the file {s} here is no frame file: those are .toml files{to})"
            raise FrameFileError(f"{s}: no bundled frame of that name{there} (bundled: {known})")
        text, fname = f.read_bytes(), f"{s}.toml"
    try:
        text = textfile.decode(text)  # (a byte-order mark read and dropped)
    except ValueError as exc:
        raise FrameFileError(f"{fname}: {exc}") from None
    try:
        return tomllib.loads(text), fname
    except tomllib.TOMLDecodeError as exc:
        if Path(fname).suffix.lower() in textfile.RECORD_SUFFIXES:  # (a record given for it)
            raise FrameFileError(f"{fname}: not a frame (TOML) file; a ground-motion record "
                                 "goes in a scene's [motion] record") from None  # fmt: skip
        raise FrameFileError(f"{fname}: not valid TOML: {exc}") from None
