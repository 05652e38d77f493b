"""Reading and writing three-component records: ``read_motion3`` and ``write_motion3``.

A three-component record (:class:`~nsdyn.ground.motion3.GroundMotion3`, a_x, a_y, a_z in m/s²
on t_k = t0 + k Δt) comes from

* three files of one station, one component each (PEER AT2 or any layout ``read_motion``
  reads), read together: the same Δt (to the relative tolerance DT_RTOL of the readers) and the
  same number of samples, or a one-line error naming the file, the field and both values;
* one nsdyn CSV with the columns ``t, ax, ay[, az]`` (header ``# columns: t ax ay az``), as
  ``write_motion3`` writes it — every value as its shortest round-trip repr, so it reads back
  bit for bit;
* the name of a bundled synthetic record that has a second horizontal component: a_x and a_z
  are the record's ``a_hor`` and ``a_ver``, a_y is the companion file ``<name>-y.txt``
  (see records/README.md).

``rotate=θ`` returns the record turned by θ counter-clockwise seen from above (x, y, z
right-handed, z up): [a_x'; a_y'] = R(θ)[a_x; a_y]. A station's components are named by their
azimuth clockwise from north, so x = 090 (east), y = 000 (north), z = up is right-handed;
x = 000, y = 090 is not (it is the mirror image).
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

from nsdyn._bundled import RECORDS
from nsdyn._checks import flag
from nsdyn.ground._text import DT_RTOL, fields, is_comment, parse_table
from nsdyn.ground.motion import GroundMotion, RecordFileError, UnitWarning
from nsdyn.ground.motion3 import GroundMotion3
from nsdyn.ground.readers import (
    COMPANION_SUFFIX,
    BundledFile,
    _resolve,
    _write_table,
    read_motion,
)

_X_NAMES = ("ax", "a_x", "x")
_Y_NAMES = ("ay", "a_y", "y")
_Z_NAMES = ("az", "a_z", "z", "a_ver", "ver", "up", "ud")


def bundled_records3() -> list[str]:
    """Names of the bundled records that have a second horizontal component
    (``read_motion3(name)`` reads all three)."""
    return [n for n in RECORDS.names() if _companion(n) is not None]


def _companion(name: str):
    root = RECORDS.root()
    item = root / f"{name}{COMPANION_SUFFIX}"
    return item if item.is_file() else None


def _bundled3(name: str, units: str | None, dt: float | None = None) -> GroundMotion3:
    item = _companion(name)
    if item is None:
        raise FileNotFoundError(
            f"{name!r}: the bundled record has one horizontal component (no "
            f"{name}{COMPANION_SUFFIX}); with two: {bundled_records3()}"
        )
    x = read_motion(name, units=units, dt=dt)  # (a given dt checked against the record's)
    y = read_motion(BundledFile(f"{name}{COMPANION_SUFFIX}"), units=units)  # (not the cwd's)
    _check_same_grid(x, y, "y")
    meta = {**x.meta, "y_source": y.source, "y_seed": y.meta.get("seed")}
    return GroundMotion3(x.t0, x.dt, x.a_hor, y.a_hor, x.a_ver, x.name, x.source, meta)


def _check_same_grid(
    x: GroundMotion, other: GroundMotion, field: str, *, length: bool = True
) -> None:
    """One record's components share Δt, t0 and (``length``) the number of samples."""
    if abs(other.dt - x.dt) > DT_RTOL * x.dt:
        raise RecordFileError(
            other.source,
            None,
            f"{field} component: dt = {other.dt:g} s, but the x component ({x.source}) has "
            f"dt = {x.dt:g} s; the components of one record share one time step",
        )
    if abs(other.t0 - x.t0) > DT_RTOL * x.dt:
        raise RecordFileError(
            other.source,
            None,
            f"{field} component: t0 = {other.t0:g} s, but the x component ({x.source}) has "
            f"t0 = {x.t0:g} s; the components of one record start together",
        )
    if length and other.n != x.n:
        raise RecordFileError(
            other.source,
            None,
            f"{field} component: npts = {other.n}, but the x component ({x.source}) has "
            f"npts = {x.n}; pass trim=True (in a scene, [motion] trim = true) to cut all "
            "components to the shortest",
        )


def _columns(source: str, text: str) -> dict[str, str] | None:
    """{"x": name, "y": name[, "z": name]} of a table with named a_x, a_y columns, else None."""
    try:
        names = parse_table(text, source).names
    except RecordFileError:
        if _names_x_and_y(text):  # a table of x and y with a bad row: its own error
            raise
        return None
    if names is None:
        return None
    found = {}
    for key, aliases in (("x", _X_NAMES), ("y", _Y_NAMES), ("z", _Z_NAMES)):
        hit = next((a for a in aliases if a in names), None)
        if hit is not None:
            found[key] = hit
    return found if {"x", "y"} <= set(found) else None


def _names_x_and_y(text: str) -> bool:
    """Whether the header's ``columns:`` line or the first line that is not a comment names an
    x and a y column."""

    def names(s: str) -> bool:
        toks = {t.lower() for t in fields(s)}
        return bool(toks & set(_X_NAMES)) and bool(toks & set(_Y_NAMES))

    for line in text.splitlines():
        s = line.strip()
        if s and is_comment(s):
            head, _, rest = s.lstrip("#%;!/ ").partition(":")
            if head.strip().lower() == "columns" and names(rest):
                return True
        elif s:
            return names(s)
    return False


def _read_column(path, cols: dict[str, str], key: str, units, dt) -> tuple:
    """(the planar record of component ``key``, the warnings its read gave)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m = read_motion(path, fmt="multi-column", column=cols[key], vertical=cols.get("z"),
                        units=units, dt=dt)  # fmt: skip
    return m, caught


def _table3(path, source: str, cols: dict[str, str], units, dt) -> GroundMotion3:
    (x, wx), (y, wy) = (_read_column(path, cols, k, units, dt) for k in ("x", "y"))
    top = max(x.pga, y.pga)
    # the file's units and peak are the larger component's: its warnings all; the other's
    # besides its units (a small x beside a plausible y is no sign of g), none said twice
    major, minor = (wx, wy) if x.pga >= y.pga else (wy, wx)
    texts: list = []
    for w in [*major, *(w for w in minor if not issubclass(w.category, UnitWarning))]:
        text = str(w.message)  # (one zero component is a motion along the other: no warning)
        if text not in texts and ("zero at every sample" not in text or top == 0.0):
            texts.append(text)
            warnings.warn(w.message, stacklevel=3)
    meta = {**x.meta, "columns3": cols}
    return GroundMotion3(x.t0, x.dt, x.a_hor, y.a_hor, x.a_ver, x.name, source, meta)


def read_motion3(
    x: str | os.PathLike | None = None,
    y: str | os.PathLike | None = None,
    z: str | os.PathLike | None = None,
    *,
    units: str | None = None,
    dt: float | None = None,
    rotate: float = 0.0,
    trim: bool = False,
    name: str | None = None,
) -> GroundMotion3:
    """Read a three-component record (see the module docstring for the three sources).

    Parameters
    ----------
    x : path or str
        The first horizontal component's file; or, alone, an nsdyn CSV with columns
        t, ax, ay[, az], or the name of a bundled record with a second horizontal component
        (``bundled_records3()``).
    y : path, optional
        The second horizontal component's file, 90° counter-clockwise of x seen from above.
    z : path, optional
        The vertical component's file (up); None: no vertical.
    units : {"g", "cm/s2" (gal), "mm/s2", "m/s2"} or None
        Units on file of every component (None: as each header states, see ``read_motion``).
    dt : float, optional
        Sampling interval [s] for files that state none.
    rotate : float
        Angle θ [degrees] to turn the record by, counter-clockwise seen from above.
    trim : bool
        Cut the components to the shortest instead of refusing different lengths (the
        components of a PEER NGA-West2 station often differ by a few samples at the end).
    name : str, optional
        Record name (default: the x component's).

    Raises
    ------
    RecordFileError
        A component file with another dt or length than the x component (naming the file and
        both values), and every error of ``read_motion``.
    ValueError
        A missing component: x not given, or y not given for a one-component x.
    UnitError, FileNotFoundError
        As ``read_motion``: units it does not know; a file or bundled name that is not there.
    """
    flag("trim", trim)
    if x is None:
        raise ValueError("read_motion3: x: expected a file, a three-column CSV or a bundled name")
    if y is None:
        if z is not None:
            raise ValueError(f"read_motion3: y: expected the second horizontal file with z={z}")
        motion = _read_one_source(x, units, dt)
    else:
        for key, other in (("y", y), ("z", z)):  # (x == y ran with both from column 0)
            if other is not None and Path(other).is_file() and Path(x).is_file() \
                    and Path(other).resolve() == Path(x).resolve():  # fmt: skip
                raise ValueError(f"read_motion3: {key}: the same file as x ({x}); a file of "
                                 "several components is given alone, as x, with columns "
                                 "named t, ax, ay[, az]")  # fmt: skip
        motion = _read_files(x, y, z, units, dt, trim)
    if name is not None:
        motion = motion._replace(name=name)
    return motion.rotated(rotate) if rotate else motion


def _one_component_or_its_error(x, units, dt) -> None:
    """Raise the one-component reader's error when ``x`` is no record of one component either
    (an empty file, a bad row, an AT2 file's wrong NPTS); a file that lacks only its sampling
    interval counts as one (its missing second component is the error to say)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            read_motion(x, units=units, dt=dt)
        except RecordFileError:
            if dt is not None:
                raise
            read_motion(x, units=units, dt=1.0)  # (fails again: not for want of a dt)


def _read_one_source(x, units, dt) -> GroundMotion3:
    path = Path(x)
    if not path.is_file():
        stem = str(x)[:-4] if str(x).endswith(".csv") else str(x)
        if "/" not in stem and os.sep not in stem and RECORDS.find(stem) is not None:
            return _bundled3(stem, units, dt)
    source, text = _resolve(x)
    cols = _columns(source, text)
    if cols is None:
        _one_component_or_its_error(x, units, dt)
        raise RecordFileError(
            source,
            None,
            "missing component y: expected a CSV whose header names the columns t, ax, "
            "ay[, az] (a first line 't,ax,ay,az' or '# columns: t ax ay az'; columns without "
            "names are not taken for x, y and z), or one file per component (a scene's "
            "[motion] x, y and z; in Python read_motion3(x, y=..., z=...))",
        )
    return _table3(path, source, cols, units, dt)


def _read_files(x, y, z, units, dt, trim: bool) -> GroundMotion3:
    files = {"x": x, "y": y, "z": z}
    parts: dict[str, GroundMotion] = {}
    for key, f in files.items():
        if f is None:
            continue
        if not Path(f).is_file():
            raise FileNotFoundError(f"read_motion3: {key}: no such file {str(f)!r}")
        parts[key] = read_motion(f, units=units, dt=dt)
        if parts[key].a_ver is not None and key != "x":
            parts[key] = parts[key].with_vertical(None)  # one component per file
    px = parts["x"]
    if px.a_ver is not None and "z" in parts:
        raise RecordFileError(px.source, None, "has a vertical column and z= is given too")
    n = min(p.n for p in parts.values())
    for key in ("y", "z"):
        if key in parts:
            _check_same_grid(px, parts[key], key, length=not trim)
    cut = {k: p.a_hor[:n] for k, p in parts.items()}
    az = cut["z"] if "z" in cut else (None if px.a_ver is None else px.a_ver[:n])
    source = ", ".join(f"{k}={p.source}" for k, p in parts.items())
    meta = {
        "format": px.meta.get("format"),
        "file_units": {k: p.meta.get("file_units") for k, p in parts.items()},
        "files": {k: p.source for k, p in parts.items()},
        "npts_on_file": {k: p.n for k, p in parts.items()},
    }
    if any(p.n != n for p in parts.values()):
        meta["trimmed_to"] = n
    return GroundMotion3(px.t0, px.dt, cut["x"], cut["y"], az, px.name, source, meta)


def write_motion3(
    motion: GroundMotion3,
    path: str | os.PathLike,
    *,
    command: str | None = None,
    seed: int | str | None = None,
) -> Path:
    """Write ``motion`` as an nsdyn CSV (columns t, ax, ay[, az] in m/s², ``#`` header with
    name, units, t0, dt, npts, command, seed and the JSON meta) that :func:`read_motion3` reads
    back bit for bit. Atomic (temporary file, then rename)."""
    if not isinstance(motion, GroundMotion3):
        raise TypeError(f"motion: expected a GroundMotion3, got {type(motion).__name__}"
                        + ("; write_motion writes a one-component record"
                           if hasattr(motion, "a_hor") else ""))  # fmt: skip
    cols = [motion.ax, motion.ay] + ([motion.az] if motion.az is not None else [])
    names = ["t", "ax", "ay", "az"][: len(cols) + 1]
    title = "nsdyn ground motion, three components"
    return _write_table(motion, path, title, names, cols, command, seed)
