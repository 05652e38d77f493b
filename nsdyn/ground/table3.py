"""A three-component excitation from a plain table (a scene file's ``[motion]``): record or orbit.

``motion3_from_table(table, source)`` turns the keys below into a :class:`GroundMotion3` or a
:class:`HarmonicPlane` and the run's duration keywords (``{"t_end": …}``, ``{"n_periods": …}``
or ``{}`` for a record, which ends with its last sample). Every bad key or value raises one
``ValueError`` line ``<source>: motion.<key>: expected …, got …``, which a scene reader can
re-raise as its own error.

Record (``kind = "record3"``):

    record = "synthetic-wn-40s"   # a bundled record with a second component, or a t,ax,ay[,az] CSV
    x, y, z = "…090.AT2", "…000.AT2", "…UP.AT2"   # or one file per component (z optional)
    units, dt, rotate [deg], trim, vertical (false drops a_z), pga [m/s²],
    pga_component ("resultant" | "x" | "y" | "geomean"), t_end [s]

Orbit (``kind = "orbit"``), the formulas of :mod:`nsdyn.ground.orbit`:

    orbit = "linear" | "circular" | "elliptical" | "general"
    frequency [Hz]; amplitude [m/s²] (A, or A_major); amplitude_minor (elliptical);
    angle [deg] (linear, elliptical); sense = +1 | -1 (circular, elliptical);
    amplitude_x, amplitude_y, phase_y [deg] (general);
    vertical_amplitude [m/s²], vertical_frequency [Hz], vertical_phase [deg];
    t_end [s] or n_periods (one of them: a harmonic excitation has no natural end)
"""

from __future__ import annotations

import math
import warnings
from typing import Any

from nsdyn.ground.motion import (
    G_STANDARD,
    PGA_MAX_PLAUSIBLE,
    UnitWarning,
    record_pga_said,
    unit_factor,
)
from nsdyn.ground.motion3 import GroundMotion3
from nsdyn.ground.orbit import HarmonicPlane
from nsdyn.ground.readers3 import read_motion3

RECORD3_KEYS = (
    "kind", "record", "x", "y", "z", "units", "dt", "rotate", "trim", "vertical", "pga",
    "pga_component", "t_end",
)  # fmt: skip
ORBIT_KEYS = {
    "linear": ("amplitude", "angle"),
    "circular": ("amplitude", "sense"),
    "elliptical": ("amplitude", "amplitude_minor", "angle", "sense"),
    "general": ("amplitude_x", "amplitude_y", "phase_y"),
}
_ORBIT_COMMON = (
    "kind", "orbit", "frequency", "vertical_amplitude", "vertical_frequency", "vertical_phase",
    "t_end", "n_periods",
)  # fmt: skip
KINDS3 = ("record3", "orbit")
_FIELD_KEYS = {  # HarmonicPlane's argument -> the table's key
    "f": "frequency",
    "A": "amplitude",
    "A_major": "amplitude",
    "A_minor": "amplitude_minor",
    "ax": "amplitude_x",
    "ay": "amplitude_y",
    "phase_y_deg": "phase_y",
    "az": "vertical_amplitude",
    "f_z": "vertical_frequency",
    "phase_z_deg": "vertical_phase",
}


def _err(source: str, key: str, message: str) -> ValueError:
    return ValueError(f"{source}: motion.{key}: {message}")


def _number(source: str, table: dict, key: str, default=None, *, positive=False, nonneg=False):
    if key not in table:
        if default is None:
            raise _err(source, key, "required")
        return default
    v = table[key]
    if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
        raise _err(source, key, f"expected a finite number, got {v!r}")
    if positive and not v > 0:
        raise _err(source, key, f"expected a positive number, got {v!r}")
    if nonneg and v < 0:
        raise _err(source, key, f"expected a number >= 0, got {v!r}")
    return float(v)


def _check_keys(source: str, table: dict, valid) -> None:
    import difflib

    for key in table:
        if key not in valid:
            close = difflib.get_close_matches(key, sorted(valid), n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            raise _err(source, key, f"unknown field; {hint}expected some of {sorted(valid)}")


def motion3_from_table(
    table: dict[str, Any], source: str = "<scene>"
) -> tuple[GroundMotion3 | HarmonicPlane, dict[str, float]]:
    """(excitation, duration keywords) of a ``[motion]`` table (see the module docstring)."""
    if not isinstance(table, dict):  # (a text: AttributeError 'get')
        raise TypeError(f"table: expected a [motion] table (a dict), got {type(table).__name__}")
    kind = table.get("kind")
    if kind == "record3":
        return _record3(table, source), {}
    if kind == "orbit":
        return _orbit(table, source)
    if kind is None:
        raise _err(source, "kind", f"missing; expected one of {list(KINDS3)} (a three-component "
                   "record, or a harmonic orbit)")  # fmt: skip
    raise _err(source, "kind", f"expected one of {list(KINDS3)}, got {kind!r}")


def _record3(table: dict, source: str) -> GroundMotion3:
    _check_keys(source, table, RECORD3_KEYS)
    files = {k: table[k] for k in ("x", "y", "z") if k in table}
    if "record" in table and files:
        raise _err(source, "record", "give record or x/y/z files, not both")
    if "record" not in table and "x" not in table:
        raise _err(source, "record", "required (a bundled name or a CSV), or x= and y= files")
    for key in ("record", *files, "units", "pga_component"):
        if key in table and not isinstance(table[key], str):
            raise _err(source, key, f"expected a string, got {table[key]!r}")
    for key in ("trim", "vertical"):
        if key in table and not isinstance(table[key], bool):
            raise _err(source, key, f"expected true or false, got {table[key]!r}")
    kw: dict[str, Any] = {"trim": table.get("trim", False)}
    if "units" in table:
        try:
            unit_factor(table["units"])
        except ValueError as e:
            raise _err(source, "units", str(e)) from None
        kw["units"] = table["units"]
    if "dt" in table:
        kw["dt"] = _number(source, table, "dt", positive=True)
    kw["rotate"] = _number(source, table, "rotate", 0.0)
    try:
        if "record" in table:
            motion = read_motion3(table["record"], **kw)
        else:
            motion = read_motion3(files.get("x"), files.get("y"), files.get("z"), **kw)
    except (OSError, ValueError) as e:  # a missing file, an unknown name, a bad record
        raise _err(source, _culprit(table, files, str(e)), str(e)) from None
    if not table.get("vertical", True):
        motion = motion._replace(az=None)
    if "pga" in table:
        comp = table.get("pga_component", "resultant")
        pga = _number(source, table, "pga", positive=True)  # its own message, named once
        try:
            motion = motion.scaled_to_pga(pga, comp)
        except ValueError as e:  # GroundMotion3 names its argument ("component: ...")
            key = "pga_component" if "component" in str(e) else "pga"
            text = str(e).removeprefix("component: ").removeprefix("target: ")
            raise _err(source, key, text) from None
    elif "pga_component" in table:
        raise _err(source, "pga_component", "given without pga")
    elif said := record_pga_said(motion.pga_resultant):  # (x and y: the resultant's)
        key = "record" if "record" in table else "x"
        raise _err(source, key, f"{table[key]}{' and ' + table['y'] if 'y' in table else ''}: "
                   + said)  # fmt: skip
    if "t_end" in table:
        t_end = _number(source, table, "t_end", positive=True)
        try:
            motion = motion.until(t_end)
        except ValueError as e:  # an end within the record's first step
            raise _err(source, "t_end", str(e).removeprefix("t_end: ")) from None
    return motion


def _culprit(table: dict, files: dict[str, str], message: str) -> str:
    """The key whose file a reading error is about: "record" for a record, "y" for an x file
    without its second horizontal component, the key the reader names ("read_motion3: <key>:
    …"), else the file named first in the message (a component file's own errors start with
    its path; a grid mismatch names the x file last)."""
    if "record" in table:
        return "record"
    if "y" not in files and "missing component y" in message:
        return "y"
    key = message.removeprefix("read_motion3: ").partition(":")[0]
    if message.startswith("read_motion3: ") and key in ("x", "y", "z"):
        return key  # the reader's own "read_motion3: <key>: …"
    named = {k: message.find(str(f)) for k, f in files.items()}
    named = {k: i for k, i in named.items() if i >= 0}
    return min(named, key=named.get) if named else "x"


def _orbit(table: dict, source: str) -> tuple[HarmonicPlane, dict[str, float]]:
    shape = table.get("orbit")
    if shape not in ORBIT_KEYS:
        got = "nothing (missing)" if shape is None else repr(shape)
        raise _err(source, "orbit", f"expected one of {list(ORBIT_KEYS)}, got {got}")
    for key in table:  # another orbit's key: named as such (it read "did you mean 'amplitude'")
        owner = [o for o, ks in ORBIT_KEYS.items() if key in ks and key not in ORBIT_KEYS[shape]]
        if owner:
            raise _err(source, key, f"a key of orbit {' or '.join(map(repr, owner))}, not of "
                       f"{shape!r}; expected "
                       f"some of {sorted(_ORBIT_COMMON + ORBIT_KEYS[shape])}")  # fmt: skip
    _check_keys(source, table, _ORBIT_COMMON + ORBIT_KEYS[shape])
    f = _number(source, table, "frequency", positive=True)
    vertical = {
        "az": _number(source, table, "vertical_amplitude", 0.0, nonneg=True),
        "phase_z_deg": _number(source, table, "vertical_phase", 0.0),
    }
    if "vertical_frequency" in table:
        if not vertical["az"]:
            raise _err(source, "vertical_frequency", "needs vertical_amplitude (a vertical "
                       "component of zero amplitude has no frequency)")  # fmt: skip
        vertical["f_z"] = _number(source, table, "vertical_frequency", positive=True)
    sense = table.get("sense", 1)
    if sense not in (1, -1) or isinstance(sense, bool):
        raise _err(source, "sense", f"expected +1 (counter-clockwise) or -1, got {sense!r}")
    angle = _number(source, table, "angle", 0.0)
    if shape == "general":
        amps = [_number(source, table, k) for k in ("amplitude_x", "amplitude_y")]
        amps.append(_number(source, table, "phase_y", 90.0))
    else:
        amps = [_number(source, table, "amplitude")]
        if shape == "elliptical":
            amps.append(_number(source, table, "amplitude_minor"))
    try:
        if shape == "linear":
            h = HarmonicPlane.linear(f, amps[0], angle, **vertical)
        elif shape == "circular":
            h = HarmonicPlane.circular(f, amps[0], sense, **vertical)
        elif shape == "elliptical":
            h = HarmonicPlane.elliptical(f, amps[0], amps[1], angle, sense, **vertical)
        else:
            h = HarmonicPlane(f, *amps, **vertical)
    except ValueError as e:  # "HarmonicPlane.<field>: expected …" -> the table's key
        field, _, rest = str(e).removeprefix("HarmonicPlane.").partition(": ")
        raise _err(source, _FIELD_KEYS.get(field, field), rest) from None
    amp_keys = ("amplitude", "amplitude_minor", "amplitude_x", "amplitude_y", "vertical_amplitude")
    high = [k for k in amp_keys if abs(table.get(k, 0.0)) > PGA_MAX_PLAUSIBLE]
    if high:  # (as a PGA above it is: 200 typed in gal ran at 20 g into an uplift)
        warnings.warn(f"{source}: motion.{high[0]} = {table[high[0]]:g} m/s² is above "
                      f"{PGA_MAX_PLAUSIBLE:g} m/s² ({PGA_MAX_PLAUSIBLE / G_STANDARD:.2g} g), "
                      "beyond recorded ground motions: is it in gal (cm/s²)? An orbit's "
                      "amplitudes are in m/s²", UnitWarning, stacklevel=3)  # fmt: skip
    if "t_end" in table and "n_periods" in table:
        raise _err(source, "t_end / motion.n_periods", "give one, not both")
    if "t_end" in table:
        return h, {"t_end": _number(source, table, "t_end", positive=True)}
    if "n_periods" in table:
        return h, {"n_periods": _number(source, table, "n_periods", positive=True)}
    raise _err(source, "t_end", "a harmonic excitation has no natural end; give t_end or n_periods")
