"""The keys of a rocking scene (``[scene] kind = "rocking"``): blocks, frames, compliant blocks.

Declared once as a :class:`~nsdyn.models.scene_schema.Schema`; the reader
(:mod:`nsdyn.models.rocking.scene`) takes its valid keys from it and the documentation's
scene-file reference is generated from it. Sizes are the full width 2B and height 2H.
"""

from __future__ import annotations

from nsdyn.models.scene_schema import RECORD_DT_KEY, REL_TOL, UNITS_KEY, Key, Schema, Table

_POS = {"lo": 0.0, "lo_open": True}  # > 0
_NONNEG = {"lo": 0.0}  # >= 0

SCHEMA = Schema(
    "rocking",
    "rigid blocks, rocking frames and blocks on compliant corners",
    "Housner's block on rigid ground, the Makris–Vassiliou rocking frame and a block on "
    "tensionless spring–damper corners (seeds 001, 003). Without `[motion]` record or pulse "
    "the block rocks freely from its initial tilt.",
    (
        Table(
            "scene",
            "Which rocking model.",
            (
                Key("kind", "string", "the model family", required=True, choices=("rocking",)),
                Key(
                    "name",
                    "string",
                    "a name for outputs and titles (1 to 200 bytes)",
                    default="(the file's stem)",
                ),
                Key(
                    "model",
                    "string",
                    "a block, a rocking frame (two columns and a cap beam) or a "
                    "block on compliant corners",
                    default="block",
                    choices=("block", "frame", "compliant"),
                ),
            ),
        ),
        Table(
            "block",
            "The block, or the frame's columns.",
            (
                Key("width", "number", "full width 2B", "m", required=True, **_POS),
                Key("height", "number", "full height 2H", "m", required=True, **_POS),
                Key(
                    "r",
                    "number",
                    "coefficient of restitution of the angular velocity at impact "
                    "(0: plastic, the block stops at it; not for `compliant`)",
                    "—",
                    default="(Housner's, or the frame's)",
                    lo=0.0,
                    hi=1.0,
                ),
                Key(
                    "linear",
                    "boolean",
                    "the linearised equation of motion (not for `compliant`)",
                    default=False,
                ),
                Key("mass", "number", "mass of the block (a column)", "kg", default=1.0, **_POS),
                Key(
                    "gamma",
                    "number",
                    "frame only, and required there: m_beam / (2 m_column) (0: the columns "
                    "alone, a block)",
                    "—",
                    **_NONNEG,
                ),
                Key(
                    "omega_v_over_p",
                    "number",
                    "compliant only: vertical contact frequency / p",
                    "—",
                    default=300.0,
                    **_POS,
                ),
                Key(
                    "zeta",
                    "number",
                    "compliant only: damping ratio of the contact",
                    "—",
                    default=2.0,
                    **_NONNEG,
                ),
            ),
        ),
        Table(
            "motion",
            "A record, a closed-form pulse, or nothing (free rocking).",
            (
                Key(
                    "record",
                    "string",
                    "bundled record name or path (a relative path: the scene file's folder first)",
                ),
                Key(
                    "pga",
                    "number",
                    "scale the record's PGA (or the pulse amplitude) to this",
                    "m/s²",
                    **_POS,
                    hi=1000.0,
                ),
                Key("vertical", "boolean", "keep the record's vertical component", default=True),
                UNITS_KEY,
                RECORD_DT_KEY,
                Key("pulse", "string", "pulse shape", choices=("sine", "cosine", "ricker", "rect")),
                Key(
                    "a_p",
                    "number",
                    "pulse amplitude (or `a_p_g`)",
                    "m/s²",
                    range="|v| ≤ 1000 (100 g)",
                ),
                Key(
                    "a_p_g",
                    "number",
                    "pulse amplitude in g (or `a_p`)",
                    "g",
                    range="|v| g ≤ 1000 m/s²",
                ),
                Key("omega_p", "number", "pulse circular frequency (or `f_p`)", "rad/s", **_POS),
                Key("f_p", "number", "pulse frequency (or `omega_p`)", "Hz", **_POS),
                Key("n_cycles", "integer", "cycles of the pulse", default=1, lo=1.0),
                Key(
                    "ver_ratio",
                    "number",
                    "vertical pulse acceleration / horizontal",
                    "—",
                    default=0.0,
                ),
                Key("t_start", "number", "start of the pulse", "s", default=0.0, **_NONNEG),
                Key(
                    "t_end",
                    "number",
                    "end of the run",
                    "s",
                    default="(record end; max(10, 3 pulse durations); 10 free)",
                    **_POS,
                ),
                Key(
                    "theta0",
                    "number",
                    "initial tilt θ₀ (or `theta0_over_alpha`, not both)",
                    "rad",
                    default=0.0,
                ),
                Key(
                    "theta0_over_alpha",
                    "number",
                    "initial tilt θ₀/α (or `theta0`, not both)",
                    "—",
                    default=0.0,
                ),
            ),
        ),
        Table(
            "solver",
            "The event-located Dormand–Prince 5(4) integrator.",
            (
                Key("method", "string", "integrator", default="dopri5", choices=("dopri5",)),
                Key(
                    "tol",
                    "number",
                    "relative tolerance (compliant: 10× this, at most 1e-6)",
                    "—",
                    default=1e-9,
                    **REL_TOL,
                ),
                Key(
                    "dt_out",
                    "number",
                    "output step",
                    "s",
                    default="(0.01, or T_p/100 for a pulse of period T_p < 1 s, a record's own "
                    "step; compliant 0.001)",
                    **_POS,
                ),
            ),
        ),
    ),
)
