"""Scene tables for structures without a frame and for harmonic or force excitations.

``[structure]`` replaces ``[scene] frame`` (:mod:`nsdyn.models.isolated.builders`)::

    [structure]
    kind = "shear"                      # shear | matrices
    masses = [2.0e4, 1.0e4, 1.0e4, 1.0e4]   # kg, base slab (on the isolator) first
    stiffnesses = [2.0e7, 1.5e7, 1.0e7]     # N/m, storey k between levels k-1 and k
    damping_ratios = 0.05               # one, or one per fixed-base mode
    heights = 3.0                       # m, optional: drift ratios

    [structure]
    kind = "matrices"
    M = [[...]]  C = [[...]]  K = [[...]]   # n x n, relative to the ground
    iso_dofs = [0]                      # sliding dofs
    influence = [1.0, 1.0]              # (n) horizontal or (n x 2) [horizontal, vertical]
    weight = 2.0e5                      # N, frozen normal force — or contact_rows = [[...]]
    levels = [[0], [1]]                 # optional; heights = [...] optional

With a ``[structure]`` the ``[isolation]`` table must give ``k_lam``, ``c`` and ``mu`` (the
defaults are the seed office's isolators, meaningless for another structure).

Excitations besides a ground record (``[motion] record``)::

    [motion]                            # harmonic ground acceleration
    kind = "harmonic"
    amplitude = 1.0                     # m/s²
    frequency = 0.5                     # Hz
    phase = 0.0                         # rad (optional)
    n_periods = 20                      # or t_end [s]: required

    [force]                             # instead of [motion]: load b F(t)
    kind = "harmonic"                   # harmonic (amplitude N, frequency, phase) | record
    dofs = [3]                          # where it acts; weights = [...] optional
    amplitude = 1.0e4                   # N
    frequency = 1.0
    n_periods = 20                      # or t_end (required for harmonic)
    # kind = "record": record = "...", scale = -1.0e4 (N per m/s²), t_end optional
"""

from __future__ import annotations

from nsdyn.models.isolated.scene_keys import (
    FORCE_HARMONIC,
    FORCE_RECORD,
    MOTION_HARMONIC,
    STRUCTURE_MATRICES,
    STRUCTURE_SHEAR,
)
from nsdyn.models.scenefile import SceneError, number, unknown_key

STRUCTURE_KINDS = ("shear", "matrices")
_STRUCTURE_FIELDS = {"shear": STRUCTURE_SHEAR.names(), "matrices": STRUCTURE_MATRICES.names()}
_REQUIRED = {
    "shear": ("masses", "stiffnesses", "damping_ratios"),
    "matrices": ("M", "C", "K", "iso_dofs", "influence"),
}
ISOLATION_REQUIRED = ("k_lam", "c", "mu")  # no frame defaults for another structure
HARMONIC_MOTION_FIELDS = MOTION_HARMONIC.names()
FORCE_FIELDS = {"harmonic": FORCE_HARMONIC.names(), "record": FORCE_RECORD.names()}


def structure_kind(cfg: dict, source: str) -> str | None:
    """``[structure] kind`` ("shear", "matrices") or None for a frame scene."""
    st = cfg.get("structure")
    if st is None:
        return None
    if not isinstance(st, dict):
        raise SceneError(f"{source}: [structure]: expected a table")
    kind = st.get("kind")
    if kind not in STRUCTURE_KINDS:
        raise SceneError(
            f"{source}: structure.kind: expected one of {list(STRUCTURE_KINDS)}, got {kind!r}"
        )
    for key in st:
        if key not in _STRUCTURE_FIELDS[kind]:
            raise unknown_key(source, "structure.", key, _STRUCTURE_FIELDS[kind])
    for key in _REQUIRED[kind]:
        if key not in st:
            raise SceneError(f"{source}: structure.{key}: required for kind = {kind!r}")
    for key, val in st.items():
        if key != "kind" and not _all_numbers(val):
            raise SceneError(
                f"{source}: structure.{key}: expected a number or a (nested) list of finite "
                f"numbers, got {val!r}"
            )
    if kind == "matrices" and ("weight" in st) == ("contact_rows" in st):
        raise SceneError(
            f"{source}: structure.weight / structure.contact_rows: give exactly one (frozen "
            "normal force [N], or vertical contact rows for normal forces from the dynamics)"
        )
    if "frame" in cfg.get("scene", {}):
        raise SceneError(
            f"{source}: scene.frame: {cfg['scene']['frame']!r} not used with a "
            "[structure] table (the scene's own system); remove one"
        )
    return kind


def _all_numbers(val) -> bool:
    """True if ``val`` is a finite number or a non-empty (nested) list of them."""
    if isinstance(val, list):
        return bool(val) and all(_all_numbers(v) for v in val)
    return isinstance(val, int | float) and not isinstance(val, bool) and abs(val) < float("inf")


def check_user_isolation(user: dict, source: str) -> None:
    """A [structure] scene names its isolators: ``k_lam``, ``c``, ``mu`` are required."""
    iso = user.get("isolation", {})
    for key in ISOLATION_REQUIRED:
        if key not in iso:
            raise SceneError(
                f"{source}: isolation.{key}: required with a [structure] table (the defaults "
                "are the seed office frame's isolators)"
            )


def build_structure(cfg: dict, isolation, source: str):
    """The :class:`IsolatedSystem` of a ``[structure]`` table (SceneError on bad input)."""
    from nsdyn.models.isolated.builders import shear_building, system_from_matrices

    st = cfg["structure"]
    kind = st["kind"]
    name = cfg.get("scene", {}).get("name")
    try:
        if kind == "shear":
            return shear_building(
                st["masses"],
                st["stiffnesses"],
                st["damping_ratios"],
                isolation=isolation,
                heights=st.get("heights"),
                name=name,
            )
        return system_from_matrices(
            st["M"],
            st["C"],
            st["K"],
            iso_dofs=st["iso_dofs"],
            influence=st["influence"],
            isolation=isolation,
            weight=st.get("weight"),
            contact_rows=st.get("contact_rows"),
            levels=st.get("levels"),
            heights=st.get("heights"),
            name=name or "matrices",
        )
    except (ValueError, TypeError) as e:  # MatrixError names the matrix; add file and table
        msg = str(e)
        field = msg.split(":", 1)[0] if ":" in msg else "?"
        table = "" if field.startswith("isolation.") else "structure."  # (k_lam: its own table)
        raise SceneError(f"{source}: {table}{field}: {msg.split(':', 1)[-1].strip()}") from None


def _duration(tab: dict, where: str, source: str, required: bool) -> dict:
    if "t_end" in tab and "n_periods" in tab:
        raise SceneError(f"{source}: {where}.t_end / {where}.n_periods: give one, not both")
    if "t_end" in tab:
        return {"t_end": number(source, f"{where}.t_end", tab["t_end"])}
    if "n_periods" in tab:
        return {"n_periods": number(source, f"{where}.n_periods", tab["n_periods"])}
    if required:
        raise SceneError(
            f"{source}: {where}.t_end: a harmonic excitation has no natural end; give t_end "
            "[s] or n_periods"
        )
    return {}


def _dofs(tab: dict, where: str, source: str) -> tuple:
    d = tab.get("dofs")
    if not isinstance(d, list) or not d or not all(isinstance(k, int) and k >= 0 for k in d):
        raise SceneError(f"{source}: {where}.dofs: expected a list of dof indices, got {d!r}")
    w = tab.get("weights")
    if w is not None and (
        not isinstance(w, list)
        or len(w) != len(d)
        or not all(isinstance(x, int | float) and not isinstance(x, bool) for x in w)
    ):
        n = f"{len(d)} number{'s' if len(d) != 1 else ''}"
        raise SceneError(f"{source}: {where}.weights: expected {n} (one per dof), got {w!r}")
    return tuple(d), None if w is None else tuple(float(x) for x in w)


def harmonic_motion(mo: dict, source: str):
    """(Harmonic, duration keywords) of ``[motion] kind = "harmonic"``."""
    from nsdyn.ground.excitation import Harmonic

    for key in mo:
        if key not in HARMONIC_MOTION_FIELDS:
            raise unknown_key(source, "motion.", key, HARMONIC_MOTION_FIELDS)
    for key in ("amplitude", "frequency"):
        if key not in mo:
            raise SceneError(f"{source}: motion.{key}: required for kind = 'harmonic'")
    h = Harmonic(
        number(source, "motion.amplitude", mo["amplitude"], positive=False),
        number(source, "motion.frequency", mo["frequency"]),
        phase=number(source, "motion.phase", mo.get("phase", 0.0), positive=False),
    )
    return h, _duration(mo, "motion", source, required=True)


def force_excitation(fo: dict, source: str, motion_overrides: dict | None = None):
    """(HarmonicForce or ForceTable, duration keywords) of a ``[force]`` table."""
    from nsdyn.ground import read_motion
    from nsdyn.ground.excitation import ForceTable, HarmonicForce

    kind = fo.get("kind")
    if kind not in FORCE_FIELDS:
        raise SceneError(
            f"{source}: force.kind: expected one of {list(FORCE_FIELDS)}, got {kind!r}"
        )
    fo = dict(fo)
    if motion_overrides and "t_end" in motion_overrides:  # --t-end on the command line
        fo.pop("n_periods", None)
        fo["t_end"] = motion_overrides["t_end"]
    for key in fo:
        if key not in FORCE_FIELDS[kind]:
            raise unknown_key(source, "force.", key, FORCE_FIELDS[kind])
    dofs, weights = _dofs(fo, "force", source)
    if kind == "harmonic":
        for key in ("amplitude", "frequency"):
            if key not in fo:
                raise SceneError(f"{source}: force.{key}: required for kind = 'harmonic'")
        F = HarmonicForce(
            number(source, "force.amplitude", fo["amplitude"], positive=False),
            number(source, "force.frequency", fo["frequency"]),
            dofs,
            weights,
            number(source, "force.phase", fo.get("phase", 0.0), positive=False),
        )
        return F, _duration(fo, "force", source, required=True)
    for key in ("record", "scale"):
        if key not in fo:
            raise SceneError(f"{source}: force.{key}: required for kind = 'record'")
    kw = {k: fo[k] for k in ("units", "dt") if k in fo}
    if "dt" in kw:
        kw["dt"] = number(source, "force.dt", kw["dt"])
    try:
        motion = read_motion(fo["record"], **kw)
    except (OSError, ValueError) as e:  # a missing file, an unknown name, a bad record
        raise SceneError(f"{source}: force.record: {' '.join(str(e).split())}") from None
    if "t_end" in fo:
        try:
            motion = motion.until(number(source, "force.t_end", fo["t_end"]))
        except ValueError as e:  # an end within the record's first step
            raise SceneError(f"{source}: force.{e}") from None
    scale = number(source, "force.scale", fo["scale"], positive=False)
    return ForceTable.from_motion(motion, dofs, scale, weights), {}
