"""Scenes: one TOML file naming the frame, isolation, fidelity, ground motion and solver.

Example (every table and field is optional; missing ones take the defaults below)::

    [scene]
    name = "office isolated"
    frame = "office-11"        # bundled frame name or path to a frame TOML
    fidelity = "cb"            # fixed | rigid | cb | full
    f_max = 5.0                # Craig-Bampton cut-off [Hz]

    [isolation]                # seed 004 eq (16) and §3-§4
    k_lam = 5.0e4
    c = 1.0e4
    mu = 0.03
    law = "arctan"             # arctan | switch | none
    eps = 7500.0
    contact = "detect"         # bilateral | detect | unilateral: when a normal force would
                               # turn negative, the isolator holds on (seed 004; flagged),
                               # the run stops (solver.uplift = "raise") or flags it, or the
                               # isolator lifts off and lands (methods event / radau)

    [motion]
    record = "synthetic-wn-40s"  # bundled record name or path
    pga = 3.0                  # scale the horizontal PGA to this [m/s^2] (optional: a
                               # record named without it runs as recorded)
    vertical = true            # use the vertical component when the record has one
                               # (unset: where the model feels it)
    t_end = 40.0               # stop here [s] (optional)

    [solver]
    method = "radau"
    rtol = 1e-4
    atol = [1e-8, 1e-6]        # one number, or [displacements m, velocities m/s];
                               # default [1e-8, 1e-6], [1e-8, 1e-7] for method "event"
    dt_out = 0.02              # output step [s] (default: the record's dt)
    uplift = "raise"           # raise | warn
    max_steps = 2000000        # step attempts per chunk of the run before it gives up

A structure without a frame (``[structure] kind = "shear" | "matrices"``), a harmonic ground
motion (``[motion] kind = "harmonic"``) or a force (``[force]``) are described in
:mod:`nsdyn.models.isolated.scene_structure`.
"""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np

from nsdyn._checks import INT64_MAX
from nsdyn.models.isolated.defaults import C_DAMPER, EPS, F_MAX, FRAME, K_LAM, MU
from nsdyn.models.isolated.friction import sharpness_in_range
from nsdyn.models.isolated.scene_keys import MOTION_RECORD, SCENE, SOLVER, checked_types
from nsdyn.models.isolated.scene_structure import (
    build_structure,
    check_user_isolation,
    force_excitation,
    harmonic_motion,
    structure_kind,
)
from nsdyn.models.isolated.system import (
    CONTACTS,
    FIDELITIES,
    Isolation,
    build_system,
    isolation_from_config,
)
from nsdyn.models.isolated.tolerances import RUN_RTOL
from nsdyn.models.scenefile import SceneError, read_toml, rel_tol, scaled_record, unknown_key

DEFAULT_SCENE = {
    "scene": {"name": f"{FRAME} isolated", "frame": FRAME, "fidelity": "cb", "f_max": F_MAX},
    "isolation": {"k_lam": K_LAM, "c": C_DAMPER, "mu": MU, "law": "arctan", "eps": EPS},
    "motion": {"record": "synthetic-wn-40s", "pga": 3.0},  # (vertical: felt if it can be)
    "solver": {
        "method": "auto",
        "rtol": RUN_RTOL,
        "dt_out": 0.02,
        "uplift": "raise",
    },
}

_FIELDS = checked_types(SCENE, MOTION_RECORD, SOLVER)  # declared in scene_keys


_EXTRA_TABLES = ("structure", "force")  # scene_structure's tables
_INF_OK = ("f_max",)  # float fields where inf means something (every mode kept: the full model)
_ISO_POSITIVE = ("eps", "eta", "alpha", "diaphragm_EA", "diaphragm_EI", "g")  # > 0 (not just >= 0)
_ISO_TEXT = ("law", "frozen_normal", "contact")  # the [isolation] fields that are not numbers


def _check_isolation(iso, source: str) -> None:
    """``[isolation]``: known fields (nearest one suggested), numbers >= 0, slopes > 0."""
    if not isinstance(iso, dict):
        raise SceneError(f"{source}: [isolation]: expected a table")
    fields = sorted(Isolation.__dataclass_fields__)
    for key, val in iso.items():
        if key not in fields:
            raise unknown_key(source, "isolation.", key, fields, _FIELDS)
        if key == "contact" and val not in CONTACTS:
            raise SceneError(
                f"{source}: isolation.contact: expected one of {list(CONTACTS)}, got {val!r}"
            )
        if key in _ISO_TEXT:
            continue
        if isinstance(val, list) and key not in ("k_lam", "c", "mu"):  # (used, or a traceback)
            raise SceneError(f"{source}: isolation.{key}: expected one number (k_lam, c and mu "
                             f"take one per isolator), got {val!r}")  # fmt: skip
        vals = val if isinstance(val, list) else [val]
        ok = bool(vals) and all(
            isinstance(v, int | float) and not isinstance(v, bool) and abs(v) < float("inf")
            for v in vals
        )
        if not ok:
            raise SceneError(
                f"{source}: isolation.{key}: expected a finite number (or one per isolator), "
                f"got {val!r}"
            )
        if key in _ISO_POSITIVE and any(v <= 0 for v in vals):
            raise SceneError(f"{source}: isolation.{key}: expected a positive number, got {val!r}")
        if any(v < 0 for v in vals):
            raise SceneError(
                f"{source}: isolation.{key}: expected a non-negative number, got {val!r}"
            )
        if key == "eps":  # (1e300: the law's slope overflowed into a NaN blamed on the record)
            sharpness_in_range(f"{source}: isolation.eps", val, SceneError)


def _check(cfg: dict, source: str) -> dict:
    tables = sorted([*DEFAULT_SCENE, *_EXTRA_TABLES])
    for table in cfg:
        if table in tables and not isinstance(cfg[table], dict):  # (motion = 3: a traceback)
            raise SceneError(f"{source}: {table}: expected a table [{table}], got "
                             f"{cfg[table]!r:.60}")  # fmt: skip
        if table not in tables and not isinstance(cfg[table], dict):  # `name = ...` up top
            raise SceneError(f"{source}: {table}: a key outside any table (above the first "
                             f"[table]); expected it in one of {tables}")  # fmt: skip
        if table not in tables:
            from nsdyn._checks import did_you_mean

            hint = did_you_mean(table, tables) or ";"
            raise SceneError(f"{source}: [{table}]: unknown table{hint} expected some of "
                             f"{tables}")  # fmt: skip
    structure_kind(cfg, source)
    kind = cfg.get("motion", {}).get("kind", "harmonic")
    if kind != "harmonic":
        raise SceneError(f"{source}: motion.kind: expected 'harmonic' (a harmonic ground "
                         f"acceleration) or no kind (a record), got {kind!r}")  # fmt: skip
    if "isolation" in cfg:
        _check_isolation(cfg["isolation"], source)
    for table, fields in _FIELDS.items():
        if table == "motion" and cfg.get("motion", {}).get("kind") == "harmonic":
            harmonic_motion(cfg["motion"], source)  # checks its own fields
            continue
        for key, val in cfg.get(table, {}).items():
            if key not in fields:  # (one of [isolation]'s: named there)
                homes = {**_FIELDS, "isolation": Isolation.__dataclass_fields__}
                raise unknown_key(source, f"{table}.", key, fields, homes)
            typ = fields[key]
            if typ == "column":  # a table's column: an index from 0 or a name
                if isinstance(val, bool) or not (isinstance(val, int) and val >= 0 or
                                                 isinstance(val, str) and val.strip()):  # fmt: skip
                    raise SceneError(f"{source}: {table}.{key}: expected a column index (0, "
                                     f"1, ...) or a column name, got {val!r}")  # fmt: skip
                continue
            if typ == "tolerance":
                pair = isinstance(val, list) and len(val) == 2
                vals = val if pair else [val]
                if not (pair or not isinstance(val, list)) or not all(
                    isinstance(v, int | float) and not isinstance(v, bool) and v > 0 for v in vals
                ):
                    raise SceneError(
                        f"{source}: {table}.{key}: expected a positive number or a pair "
                        f"[displacements, velocities] of positive numbers, got {val!r}"
                    )
                continue
            if typ is int:  # a count: a positive integer (a whole float from TOML's 1e7 too)
                whole = isinstance(val, float) and val.is_integer()
                if isinstance(val, bool) or not (isinstance(val, int) or whole) or val < 1:
                    raise SceneError(
                        f"{source}: {table}.{key}: expected a positive integer, got {val!r}"
                    )
                if val > INT64_MAX:  # (a compiled loop's count)
                    raise SceneError(f"{source}: {table}.{key}: expected a positive integer "
                                     f"of at most {INT64_MAX}, got {val!r}")  # fmt: skip
                continue
            ok = (
                isinstance(val, bool)
                if typ is bool
                else isinstance(val, int | float) and not isinstance(val, bool)
                if typ is float
                else isinstance(val, str)
            )
            if not ok:
                what = {bool: "true or false", float: "a number", str: "a text"}[typ]
                raise SceneError(f"{source}: {table}.{key}: expected {what}, got {val!r}")
            if typ is float and not math.isfinite(val) and not (key in _INF_OK and val > 0):
                raise SceneError(
                    f"{source}: {table}.{key}: expected a finite positive number, got {val!r}"
                )
            if (table, key) == ("solver", "restitution"):
                if not 0.0 <= val <= 1.0:
                    raise SceneError(f"{source}: solver.restitution: expected a coefficient "
                                     f"0 <= e <= 1, got {val!r}")  # fmt: skip
                continue
            if typ is float and val <= 0:
                raise SceneError(f"{source}: {table}.{key}: expected a positive number, got {val}")
            if (table, key) == ("solver", "rtol"):
                rel_tol(source, "solver.rtol", val)
    sc = cfg.get("scene", {})
    if "fidelity" in sc and sc["fidelity"] not in FIDELITIES:
        raise SceneError(
            f"{source}: scene.fidelity: expected one of {list(FIDELITIES)}, got {sc['fidelity']!r}"
        )
    up = cfg.get("solver", {}).get("uplift")
    if up is not None and up not in ("raise", "warn"):
        raise SceneError(f"{source}: solver.uplift: expected 'raise' or 'warn', got {up!r}")
    return cfg


def merge(base: dict, override: dict) -> dict:
    out = copy.deepcopy(base)
    for table, vals in override.items():
        out.setdefault(table, {}).update(vals)
    return out


def replaces_motion(over: dict, scene: dict) -> bool:
    """True when the tables ``over`` give a motion of another kind than ``scene``'s (a
    harmonic over a record): it replaces the scene's motion table, whose keys are none of
    its own (load_scene's overrides, a study's [base.motion])."""
    kind = over.get("motion", {}).get("kind")
    return kind is not None and kind != scene.get("motion", {}).get("kind", "record")


def load_scene(path: str | Path | None = None, overrides: dict | None = None) -> dict:
    """The default scene, updated by a TOML file and then by ``overrides``, tables of keys
    (``{"motion": {"pga": 2.0}}``), each checked as merged over the scene's; a ``motion``
    override of another ``kind`` replaces the scene's motion table. SceneError naming the
    field of a mistake."""
    if overrides is not None and (not isinstance(overrides, dict) or not all(
            isinstance(v, dict) for v in overrides.values())):  # fmt: skip
        raise SceneError(f"overrides: expected tables of keys, {{'motion': {{'pga': 2.0}}}}, "
                         f"got {overrides!r}")  # fmt: skip
    cfg = copy.deepcopy(DEFAULT_SCENE)
    source = "<default scene>"
    if path is not None:
        source = str(path)
        user = read_toml(path)
        checked, ends, mo = user, (overrides or {}).get("motion", {}), user.get("motion")
        lacks = isinstance(mo, dict) and not {"t_end", "n_periods"} & mo.keys()  # (an end:
        if "t_end" in ends and lacks and mo.get("kind") == "harmonic":  # --t-end gives it)
            checked = {**user, "motion": {**mo, "t_end": ends["t_end"]}}
        _check(checked, source)
        if "force" in user and "motion" in user:
            raise SceneError(f"{source}: [force] and [motion]: one excitation per scene")
        if structure_kind(user, source) is not None:
            check_user_isolation(user, source)
            cfg["isolation"] = {}  # the user's isolators only (no frame defaults)
            cfg["scene"] = {}  # frame, fidelity, f_max and name belong to the frame
        if "force" in user or user.get("motion", {}).get("kind") == "harmonic":
            cfg["motion"] = {}  # no default record under another excitation
        cfg = merge(cfg, user)
    if replaces_motion(overrides or {}, cfg):
        cfg["motion"] = {}  # (another excitation: the scene's record is none of its keys)
    if overrides:  # each table checked as merged over the scene's (its motion's kind)
        if "t_end" in overrides.get("motion", {}):  # a given end replaces the scene's periods
            for table in ("motion", "force"):
                cfg.get(table, {}).pop("n_periods", None)
        _check({t: {**cfg.get(t, {}), **v} for t, v in overrides.items()}, "command line")
        cfg = merge(cfg, overrides)
    given = {**(user.get("motion", {}) if path is not None else {}),
             **(overrides or {}).get("motion", {})}  # fmt: skip
    as_recorded(cfg, given, "record" in given)
    cfg["_source"] = source
    return cfg


def as_recorded(cfg: dict, given: dict, named: bool) -> None:
    """In place: a record ``named`` by the user runs as recorded unless ``given`` (the user's
    own ``[motion]`` values) holds a ``pga``: the default scene's 3 m/s² is its own record's
    (it scaled every record named without one)."""
    if named and "pga" not in given:
        cfg.get("motion", {}).pop("pga", None)


def build_scene(cfg: dict):
    """(system, excitation) for a loaded scene (see :func:`build_scene_run` for its duration)."""
    system, excitation, _ = build_scene_run(cfg)
    return system, excitation


def build_scene_run(cfg: dict):
    """(system, excitation, duration) for a loaded scene; ``duration`` holds ``t_end`` or
    ``n_periods`` for an excitation without a natural end (empty for a record)."""
    from nsdyn.ground import read_motion

    source = cfg.get("_source", "<scene>")
    sc, mo = cfg["scene"], cfg.get("motion", {})
    try:
        iso = isolation_from_config(cfg.get("isolation", {}), source)
    except ValueError as e:
        raise SceneError(str(e)) from None
    if structure_kind(cfg, source) is not None:
        if "fidelity" in sc or "f_max" in sc:
            raise SceneError(
                f"{source}: scene.fidelity / scene.f_max: the model ladder is a frame's; a "
                "[structure] is used as given"
            )
        system = build_structure(cfg, iso, source)
    else:
        from nsdyn.structure import FrameFileError, load_frame

        try:
            frame = load_frame(sc["frame"])
        except FrameFileError as e:
            if e.field == "":  # no such file or bundled name: the scene's key names it
                raise SceneError(f"{source}: scene.frame: {e}") from None
            if e.field != "frame3d":
                raise
            raise SceneError(
                f"{source}: scene.frame: {sc['frame']} is a 3D frame ([frame3d]); a 3D "
                "building is a scene of kind 'building3d' that names it as [structure] frame3d "
                "(examples/scenes/building3d-office-cb.toml)"
            ) from None
        try:
            fid = sc.get("fidelity", "cb")  # (rigid, full: no cut-off; run_checks notes one)
            system = _cached_system(frame, iso, fid, float(sc.get("f_max", F_MAX))
                                    if fid in ("cb", "fixed") else None)  # fmt: skip
        except ValueError as e:  # the frame's model: its cut-off, or a node without mass
            msg = str(e)  # (an isolator list's length is the isolation table's own)
            at = (f"scene.{msg}" if msg.startswith("f_max:") else msg
                  if msg.startswith("isolation.") else f"scene.frame: {msg}")  # fmt: skip
            if msg.startswith("nodes[") and Path(str(sc["frame"])).is_file():  # (its own file's
                at = f"{sc['frame']}: frame.{msg}"  # field, not the scene that names it; the
                at = at.replace("or fidelity", f"or {source}'s scene.fidelity")  # scene's remedy)
            else:
                at = f"{source}: {at}"
            raise SceneError(at) from None
    _lifts(system, source, cfg)
    _stands(system, cfg, source)
    if "force" in cfg:
        extra = {k: v for k, v in mo.items() if k != "t_end"}
        if extra:
            raise SceneError(
                f"{source}: motion.{sorted(extra)[0]}: the scene's excitation is its [force]"
            )
        force, duration = force_excitation(cfg["force"], source, mo)
        n = system.n
        if max(force.dofs) >= n:  # before the run (it stopped inside it)
            raise SceneError(f"{source}: force.dofs: expected dof indices in 0..{n - 1} (the "
                             f"system has {n} dofs), got {list(force.dofs)}")  # fmt: skip
        return system, force, duration
    if mo.get("kind") == "harmonic":
        h, duration = harmonic_motion(mo, source)
        return system, h, duration
    if "record" not in mo:
        raise SceneError(f"{source}: motion.record: required (or kind = 'harmonic', or [force])")
    kw = {k: mo[k] for k in ("units", "dt", "column") if k in mo}
    try:
        motion = read_motion(mo["record"], **kw)
    except (OSError, ValueError) as e:  # a missing file, an unknown name, a bad record
        field = getattr(e, "argument", None) or "record"  # the key the reader names, if any
        raise SceneError(f"{source}: motion.{field}: {e}") from None
    felt = bool(np.any(np.asarray(system.Gamma)[:, 1]))  # (a shear building's: not)
    if not mo.get("vertical", felt):  # unset: kept where the model feels it, without a word
        motion = motion.with_vertical(None)  # (set true where it cannot: warned by the run)
    motion = scaled_record(motion, mo, source)
    if "t_end" in mo:
        try:
            motion = motion.until(float(mo["t_end"]))
        except ValueError as e:  # an end within the record's first step
            raise SceneError(f"{source}: motion.{e}") from None
    return system, motion, {}


def check_restitution(cfg: dict, source: str) -> None:
    """SceneError for a ``solver.restitution`` without landings: a contact other than
    ``isolation.contact = "unilateral"`` (as ``simulate`` refuses it)."""
    contact = cfg.get("isolation", {}).get("contact", "detect")
    if "restitution" in cfg.get("solver", {}) and contact != "unilateral":
        raise SceneError(f"{source}: solver.restitution: a landing's coefficient needs "
                         f"isolation.contact = 'unilateral' (no isolator lands under "
                         f"{contact!r})")  # fmt: skip


def _lifts(system, source: str, cfg: dict) -> None:
    """SceneError for ``contact = "unilateral"`` on a system whose normal forces are given
    (frozen): lift-off and landing need them as the contacts' multipliers; and for a
    ``solver.restitution`` without landings (another contact)."""
    iso = system.isolation
    check_restitution(cfg, source)
    if getattr(iso, "contact", "detect") != "unilateral":
        return
    if system.normal_force is not None:  # a structure from matrices given its weight
        raise SceneError(
            f"{source}: isolation.contact: 'unilateral' needs contact rows whose normal forces "
            "are computed; this structure's are given (its weight), so it cannot lift off: use "
            "'detect' or 'bilateral'"
        )
    if iso.frozen_normal:
        raise SceneError(
            f"{source}: isolation.contact: 'unilateral' needs the normal forces as the "
            "contacts' multipliers; isolation.frozen_normal = true freezes them: set it to "
            "false, or use contact 'detect' or 'bilateral'"
        )


def _stands(system, cfg: dict, source: str) -> None:
    """SceneError when an isolator's normal force under gravity alone is not positive while
    the contact assumption is "detect" (the default, which stops a run at the first zero
    normal force): the structure cannot stand on its isolators (a base node missing, a mass
    off the base's span), which no excitation changes. A bilateral contact holds it down, a
    unilateral one models its lift-off, and ``[solver] uplift = "warn"`` runs it anyway."""
    iso = system.isolation
    if not system.n_contacts or getattr(iso, "contact", "detect") != "detect":
        return
    if cfg.get("solver", {}).get("uplift", "raise") == "warn":
        return
    lam0 = system.static_equilibrium()[1]
    bad = np.flatnonzero(~(lam0 > 0.0))
    if bad.size:
        where = (f"{source}: [structure]" if "structure" in cfg
                 else f"{cfg['scene']['frame']} (the frame of {source})")  # fmt: skip
        raise SceneError(
            f"{where}: the normal force of isolator {int(bad[0])} under gravity alone "
            f"is {lam0[bad[0]]:.4g} N, not positive: the structure cannot stand on its isolators "
            "(check its base nodes, node positions and masses; isolation.contact = "
            "'bilateral' holds it down, [solver] uplift = 'warn' runs it anyway)"
        )


def unused_notes(cfg: dict) -> list[str]:
    """Keys of a frame scene its model does not read, known from the scene alone (the
    command line notes them; a study refuses a parameter that only they would vary): a
    cut-off ``scene.f_max`` at a fidelity without one, ``[isolation]`` on the fixed base."""
    sc, notes = cfg.get("scene", {}), []
    fid = sc.get("fidelity", "cb")
    if sc.get("f_max", F_MAX) != F_MAX and fid in ("full", "rigid"):  # (the default's: none)
        none = "every mode" if fid == "full" else "a rigid frame"
        notes.append(f"scene.f_max not used: the cut-off of fidelities cb and fixed; {fid!r} "
                     f"has none ({none})")  # fmt: skip
    if fid == "fixed" and "structure" not in cfg:
        notes += [why for _, why in unused_isolation(cfg, None)]
    return notes


GIVEN = object()  # a value no key has: every key absent from the defaults counts as given


def unused_isolation(
    cfg: dict, iso, *, given_normal: bool = False, law: str | None = None
) -> list[tuple[str, str]]:
    """``[isolation]`` keys of ``cfg`` that a model with isolation ``iso`` (None: the fixed
    base) does not read, as (key, why): they changed nothing, without a word. The switch
    law's band and stick stabilisation under a smooth law, the arctan sharpness under another,
    the contacts' keys on given normal forces (``given_normal``), the base diaphragm's on a
    structure given directly, an arctan law under the event method; on the fixed-base frame
    one item, ("[isolation]", its note). A study's varied keys (``cfg["_varied"]``) count as
    given.
    ``law``: the law the run integrates when not the scene's (the event method's switch law
    follows from ``solver.method``; uplift's arctan is given)."""
    from nsdyn.models.isolated.friction import LAW_KEYS

    default = DEFAULT_SCENE["isolation"]  # (merged into every frame scene: not the user's)
    varied = {n.split(".", 1)[1] for n in cfg.get("_varied", ()) if n.startswith("isolation.")}
    given = [k for k, v in cfg.get("isolation", {}).items()  # (a study's parameter: given)
             if default.get(k, GIVEN) != v or k in varied]  # fmt: skip
    if not given:
        return []
    if iso is None:
        return [("[isolation]", f"[isolation] not used: the fixed-base model has no isolators "
                                f"({', '.join(given)})")]  # fmt: skip
    method = cfg.get("solver", {}).get("method", "auto")
    event = law is None and method == "event"  # (its law: the switch law, whatever is given)
    law = law or ("switch" if event else iso.law)
    why = {k: f"a key of the {own} law; the law here is {law}"
           for k, (own, _) in LAW_KEYS.items() if own != law}  # fmt: skip
    if event and iso.law == "arctan":  # (its law "none" is refused by the run)
        why["law"] = "the event method integrates the switch law in place of the arctan law"
    if law == "none":  # no friction: its coefficient changes nothing
        why["mu"] = "the friction coefficient; the law here is none: no friction"
    if given_normal:  # a structure given its weight: no contact rows
        for k in ("frozen_normal", "alpha", "beta"):
            why[k] = "a key of the contacts; this structure's normal forces are given"
    if "structure" in cfg:
        for k in ("diaphragm_EA", "diaphragm_EI"):
            why[k] = "a key of a frame's base diaphragm; this structure is given directly"
    return [(f"isolation.{k}", why[k]) for k in given if k in why]


def _cached_system(frame, iso, fidelity: str, f_max: float | None, **kw):
    """:func:`build_system` through the model cache (:mod:`nsdyn._model_cache`): a scene run
    again loads its model, static state included, instead of assembling and reducing the frame
    (and importing SciPy) again."""
    from nsdyn._model_cache import cached_build

    return cached_build(
        "isolated-frame",
        (frame, iso, fidelity, f_max, sorted(kw.items())),
        lambda: build_system(frame, iso, fidelity=fidelity, f_max=f_max, **kw),
        prepare=lambda system: system.static_equilibrium(),
    )


def with_isolation_cached(system, **changes):
    """``system.with_isolation(**changes)`` (the event method's switch law) through the model
    cache, for a model built from a frame; otherwise as it is."""
    return system.with_isolation(builder=_cached_system, **changes)


def outcome(s: dict) -> tuple[str, str]:
    """(word, one line) of a run summary: did the frame stay on its isolators?

    ``uplift``: a normal force reached zero under ``contact = "detect"`` with ``uplift =
    "warn"`` (the run went on outside the no-uplift model); ``lift-off``: the unilateral model
    lifted an isolator off and landed it; ``would lift off``: a bilateral run whose normal
    force turned negative (held down by the model); ``contact assumed`` for fixed normal forces
    (nothing to check); ``in contact`` otherwise.
    """
    if s.get("fidelity") == "fixed":
        return "fixed base", "fixed base (no isolators to lift off)"
    up = s.get("uplift") or []
    first = min(up, key=lambda u: u["t_s"]) if up else None
    more = f"; {len(up) - 1} more uplift event{'s' * (len(up) > 2)}" if len(up) > 1 else ""
    # the unilateral model lets them lift off, the bilateral one holds them down
    if up and s.get("contact") not in ("unilateral", "bilateral"):
        return "uplift", (
            f"UPLIFT at t = {first['t_s']:.4f} s (contact {first['contact']}){more}: a normal "
            "force reached zero, the results after it are outside the no-uplift model"
        )
    if s.get("contact") == "unilateral" and s.get("lift_offs"):
        return "lift-off", (
            f"LIFT-OFF: {s['lift_offs']} lift-offs and {s.get('landings', 0)} landings, the "
            f"first at t = {s['first_lift_off_s']:.4f} s"
        )
    if s.get("would_lift_off") or (up and s.get("contact") == "bilateral"):
        held = more.replace("uplift event", "such event")  # (held down: no uplift)
        at = f" at t = {first['t_s']:.4f} s (contact {first['contact']}){held}" if up else ""
        return "would lift off", (
            f"a normal force turned negative{at}: the bilateral model held the isolator down "
            "(rerun with isolation.contact = 'unilateral' to let it lift off)"
        )
    if s.get("min_normal_force_N") is None:  # (no contact rows: a shear building's)
        return "contact assumed", (
            "contact assumed: each isolator's normal force is fixed at "
            "the weight it carries, so no uplift is modelled or checked"
        )
    return "in contact", "every isolator stayed in contact (no uplift)"
