"""The keys of an isolated-frame scene (``[scene] kind = "isolated"``, the default kind).

Declared once as a :class:`~nsdyn.models.scene_schema.Schema`; the readers
(:mod:`nsdyn.models.isolated.scene`, :mod:`nsdyn.models.isolated.scene_structure`) take their
valid keys from it and the documentation's scene-file reference is generated from it. The
defaults come from their one home (:mod:`nsdyn.models.isolated.defaults`,
:mod:`nsdyn.models.isolated.tolerances`).
"""

from __future__ import annotations

from nsdyn.ground.excitation import G_EARTH
from nsdyn.models.isolated.defaults import (
    ALPHA,
    BETA,
    C_DAMPER,
    EPS,
    EPS_MAX,
    ETA,
    F_MAX,
    K_LAM,
    MU,
)
from nsdyn.models.isolated.tolerances import RUN_ATOL, RUN_RTOL
from nsdyn.models.scene_schema import RECORD_DT_KEY, REL_TOL, UNITS_KEY, Key, Schema, Table

_POS = {"lo": 0.0, "lo_open": True}  # > 0
_NONNEG = {"lo": 0.0}  # >= 0
_METHODS = (
    "auto",
    "radau",
    "radau-generic",
    "dopri5",
    "event",
    "genalpha",
    "hht",
    "newmark",
    "genalpha-lowrank",
)

_NAME = Key(
    "name",
    "string",
    "a name for the run's outputs and figure titles (1 to 200 bytes)",
    default="office-11 isolated",
)
_KIND = Key(
    "kind",
    "string",
    "the model family; absent means an isolated frame",
    default="isolated",
    choices=("isolated", "rocking", "contact", "cylinder", "deck", "building3d"),
)
_T_END = Key("t_end", "number", "end of the run", "s", **_POS)
_UNITS = UNITS_KEY
_DT_REC = RECORD_DT_KEY
_DOFS = Key(
    "dofs",
    "list of integers",
    "the dofs the force acts on",
    required=True,
    lo=0.0,
    range="indices of the structure's dofs",
)
_WEIGHTS = Key(
    "weights",
    "list of numbers",
    "weight of the force on each of `dofs`",
    default="(1 each)",
    range="one per dof",
)
_N_PERIODS = Key(
    "n_periods", "number", "duration in forcing periods (or `t_end`; one is required)", **_POS
)

SCENE = Table(
    "scene",
    "What runs: the frame, its fidelity on the model ladder and a name.",
    (
        _KIND,
        _NAME,
        Key(
            "frame",
            "string",
            "bundled frame name or path to a frame TOML (a relative path: the scene file's folder "
            "first; not with [structure])",
            default="office-11",
        ),
        Key(
            "fidelity",
            "string",
            "rung of the model ladder (fixed base, rigid superstructure, "
            "Craig–Bampton, the full FE model)",
            default="cb",
            choices=("fixed", "rigid", "cb", "full"),
        ),
        Key(
            "f_max",
            "number",
            "Craig–Bampton cut-off frequency (fidelity `cb`; `fixed` keeps the "
            "fixed-base modes up to it)",
            "Hz",
            default=F_MAX,
            **_POS,
        ),
    ),
)

ISOLATION = Table(
    "isolation",
    "The friction isolators (seed 004 eq 16, §3–§4). A number is "
    "shared by every isolator; `k_lam`, `c` and `mu` also take one value per isolator. With a "
    "[structure] table, `k_lam`, `c` and `mu` are required.",
    (
        Key(
            "k_lam",
            "number or list",
            "lateral stiffness of the laminated rubber bearing, per isolator",
            "N/m",
            default=K_LAM,
            **_NONNEG,
        ),
        Key(
            "c",
            "number or list",
            "viscous damper, per isolator",
            "N s/m",
            default=C_DAMPER,
            **_NONNEG,
        ),
        Key("mu", "number or list", "friction coefficient", "—", default=MU, **_NONNEG),
        Key(
            "law",
            "string",
            "friction law: smooth arctan, Leine's switch model with true stick, or none",
            default="arctan",
            choices=("arctan", "switch", "none"),
        ),
        Key(
            "eps",
            "number",
            "sharpness ε of the arctan law, s = (2/π) arctan(ε v)",
            "s/m",
            default=EPS,
            **_POS,
            hi=EPS_MAX,
        ),
        Key("eta", "number", "stick band η of the switch model", "m/s", default=ETA, **_POS),
        Key(
            "frozen_normal",
            "boolean",
            "friction from the static normal force (the seed's modified model)",
            default=False,
        ),
        Key(
            "alpha",
            "number",
            "Baumgarte α of the contact constraints",
            "1/s",
            default=ALPHA,
            **_POS,
        ),
        Key(
            "beta", "number", "Baumgarte β of the contact constraints", "—", default=BETA, **_NONNEG
        ),
        Key("kappa", "number", "stick velocity stabilisation", "1/s", default="(2 α β)", **_NONNEG),
        Key(
            "diaphragm_EA",
            "number",
            "axial stiffness of the rigid base diaphragm beam",
            "N",
            default=1.0e11,
            **_POS,
        ),
        Key(
            "diaphragm_EI",
            "number",
            "bending stiffness of the rigid base diaphragm beam",
            "N m²",
            default=1.0e11,
            **_POS,
        ),
        Key("g", "number", "gravity", "m/s²", default=G_EARTH, **_POS),
        Key(
            "contact",
            "string",
            "what a normal force reaching zero does: nothing (seed), stop or "
            "flag (`solver.uplift`), or lift off and land",
            default="detect",
            choices=("bilateral", "detect", "unilateral"),
        ),
    ),
)

MOTION_RECORD = Table(
    "motion",
    "A ground-motion record (bundled name or file path).",
    (
        Key(
            "record",
            "string",
            "bundled record name or path to a record file (a relative path: the scene file's "
            "folder first)",
            default="synthetic-wn-40s",
        ),
        Key(
            "pga",
            "number",
            "scale the horizontal PGA to this (the vertical by the same factor); the default "
            "scene's 3.0 goes with its record: a record named without a pga runs as recorded",
            "m/s²",
            default=3.0,
            **_POS,
        ),
        Key(
            "vertical",
            "boolean",
            "use the record's vertical component when it has one; unset: where the model "
            "feels it (a frame, a [structure] with vertical rows), not on a shear building",
        ),
        Key(
            "column",
            "integer or string",
            "the horizontal column of a table of several: an index over the file's columns "
            "(time included) or a column name; unset: the first acceleration column that is "
            "not a vertical one",
            lo=0.0,
        ),
        _T_END,
        _UNITS,
        _DT_REC,
    ),
    variant="a record (no `kind`)",
)

MOTION_HARMONIC = Table(
    "motion",
    "A harmonic ground acceleration A sin(2π f t + φ).",
    (
        Key(
            "kind", "string", "a harmonic ground acceleration", required=True, choices=("harmonic",)
        ),
        Key("amplitude", "number", "amplitude A", "m/s²", required=True),
        Key("frequency", "number", "frequency f", "Hz", required=True, **_POS),
        Key("phase", "number", "phase φ", "rad", default=0.0),
        _T_END,
        _N_PERIODS,
    ),
    variant='`kind = "harmonic"`',
)

SOLVER = Table(
    "solver",
    "The integrator and its tolerances (see the guide's transient runs).",
    (
        Key(
            "method",
            "string",
            "integration method (auto: chosen from the model size, friction law and contact)",
            default="auto",
            choices=_METHODS,
        ),
        Key("rtol", "number", "relative tolerance", "—", default=RUN_RTOL, **REL_TOL),
        Key(
            "atol",
            "number or pair",
            "absolute tolerance: one number, or [displacements, velocities]",
            "m, m/s",
            default=RUN_ATOL,
            **_POS,
            range="`[1e-08, 1e-07]` by default for `event`",
        ),
        Key(
            "dt",
            "number",
            "fixed step of genalpha, hht, newmark and genalpha-lowrank",
            "s",
            default="(0.005 for the fixed-step methods)",
            **_POS,
        ),
        Key("dt_out", "number", "output step of the histories", "s", default=0.02, **_POS),
        Key(
            "uplift",
            "string",
            'under `contact = "detect"`: stop at uplift, or record it and go on',
            default="raise",
            choices=("raise", "warn"),
        ),
        Key(
            "restitution",
            "number",
            'Newton\'s coefficient e of a landing under `contact = "unilateral"` '
            "(0: plastic; a sensitivity study's parameter)",
            "—",
            default=0.0,
            lo=0.0,
            hi=1.0,
        ),
        Key(
            "max_steps",
            "integer",
            "step attempts per chunk of the run before it gives up",
            default=2_000_000,
            lo=1.0,
        ),
    ),
)

STRUCTURE_SHEAR = Table(
    "structure",
    "A shear building instead of a frame (replaces `scene.frame`).",
    (
        Key("kind", "string", "a shear building", required=True, choices=("shear",)),
        Key(
            "masses",
            "list of numbers",
            "level masses, base slab (on the isolators) first",
            "kg",
            required=True,
            **_POS,
        ),
        Key(
            "stiffnesses",
            "list of numbers",
            "storey stiffness between levels k−1 and k",
            "N/m",
            required=True,
            **_POS,
        ),
        Key(
            "damping_ratios",
            "number or list",
            "fixed-base modal damping ratios (one, or one per mode)",
            "—",
            required=True,
            **_NONNEG,
        ),
        Key("heights", "number or list", "storey heights, for drift ratios", "m", **_POS),
    ),
    variant='`kind = "shear"`',
)

STRUCTURE_MATRICES = Table(
    "structure",
    "Any linear superstructure from its matrices (coordinates relative to the ground).",
    (
        Key("kind", "string", "a structure from matrices", required=True, choices=("matrices",)),
        Key("M", "matrix", "mass matrix, n × n", "kg", required=True),
        Key("C", "matrix", "damping matrix, n × n", "N s/m", required=True),
        Key("K", "matrix", "stiffness matrix, n × n", "N/m", required=True),
        Key("iso_dofs", "list of integers", "the sliding dofs (one per isolator)", required=True),
        Key(
            "influence",
            "list or matrix",
            "load influence: (n) horizontal, or (n × 2) [horizontal, vertical]",
            required=True,
        ),
        Key(
            "weight", "number", "frozen normal force (or `contact_rows`; exactly one)", "N", **_POS
        ),
        Key(
            "contact_rows",
            "matrix",
            "vertical contact rows, for normal forces from the dynamics (or `weight`)",
        ),
        Key("levels", "list of lists", "the dofs of each level, for floor accelerations"),
        Key("heights", "number or list", "storey heights, for drift ratios", "m", **_POS),
    ),
    variant='`kind = "matrices"`',
)

FORCE_HARMONIC = Table(
    "force",
    "A harmonic load b F(t) instead of a [motion].",
    (
        Key("kind", "string", "a harmonic force", required=True, choices=("harmonic",)),
        _DOFS,
        _WEIGHTS,
        Key("amplitude", "number", "force amplitude", "N", required=True),
        Key("frequency", "number", "frequency", "Hz", required=True, **_POS),
        Key("phase", "number", "phase", "rad", default=0.0),
        _T_END,
        _N_PERIODS,
    ),
    variant='`kind = "harmonic"`',
)

FORCE_RECORD = Table(
    "force",
    "A load proportional to a record, F(t) = scale × ü(t).",
    (
        Key("kind", "string", "a force from a record", required=True, choices=("record",)),
        _DOFS,
        _WEIGHTS,
        Key("record", "string", "bundled record name or path", required=True),
        Key("scale", "number", "force per unit record acceleration", "N/(m/s²)", required=True),
        _T_END,
        _UNITS,
        _DT_REC,
    ),
    variant='`kind = "record"`',
)

SCHEMA = Schema(
    "isolated",
    "a frame (or any linear structure) on friction isolators",
    "Seed 004's model: every table and key is optional for a frame, and missing ones take the "
    "defaults below (the default scene is `nsdyn run` without a file; a file needs one table "
    "or key at least: an empty one is refused as a slip). A `[structure]` "
    "replaces the frame; a harmonic `[motion]` or a `[force]` replaces the record.",
    (
        SCENE,
        ISOLATION,
        MOTION_RECORD,
        MOTION_HARMONIC,
        SOLVER,
        STRUCTURE_SHEAR,
        STRUCTURE_MATRICES,
        FORCE_HARMONIC,
        FORCE_RECORD,
    ),
)

_PY = {
    "number": float,
    "string": str,
    "boolean": bool,
    "integer": int,
    "number or pair": "tolerance",
    "integer or string": "column",
}


def checked_types(*tables: Table) -> dict[str, dict[str, object]]:
    """``{table: {key: type}}`` of ``tables`` in the form the scene reader checks values by:
    ``float``, ``str``, ``bool``, ``int``, ``"tolerance"`` (a number or a pair) or
    ``"column"`` (an index from 0 or a name)."""
    return {t.name: {k.name: _PY[k.type] for k in t.keys} for t in tables}
