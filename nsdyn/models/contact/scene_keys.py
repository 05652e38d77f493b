"""The keys of a contact scene (``[scene] kind = "contact"``): a planar rigid body on the ground.

Declared once as a :class:`~nsdyn.models.scene_schema.Schema`; the reader
(:mod:`nsdyn.models.contact.scene`) takes its valid keys from it and the documentation's
scene-file reference is generated from it.
"""

from __future__ import annotations

from nsdyn.models.scene_schema import RECORD_DT_KEY, REL_TOL, UNITS_KEY, Key, Schema, Table

_POS = {"lo": 0.0, "lo_open": True}  # > 0
_NONNEG = {"lo": 0.0}  # >= 0

SCHEMA = Schema(
    "contact",
    "a planar rigid body that sticks, slides, rocks, hops and overturns",
    "A rectangle or convex polygon on rigid or compliant ground with frictional unilateral "
    "corner contacts (seed 002), driven by a record, a displacement sine or nothing.",
    (
        Table(
            "scene",
            "The family and a name.",
            (
                Key("kind", "string", "the model family", required=True, choices=("contact",)),
                Key(
                    "name",
                    "string",
                    "a name for outputs and titles (1 to 200 bytes)",
                    default="(the file's stem)",
                ),
            ),
        ),
        Table(
            "body",
            "A rectangle (`width`, `height`) or a convex polygon (`vertices`).",
            (
                Key(
                    "width",
                    "number",
                    "width (along the motion)",
                    "m",
                    **_POS,
                    range="required unless `vertices`",
                ),
                Key("height", "number", "height", "m", **_POS, range="required unless `vertices`"),
                Key(
                    "vertices",
                    "list of [x, y]",
                    "corners of a convex polygon, instead of width and height",
                    "m",
                ),
                Key("mass", "number", "mass", "kg", default=1.0, **_POS),
            ),
        ),
        Table(
            "friction",
            "Coulomb friction μ(v) = μ_d + (μ_s − μ_d) exp(−C |v|) at the corners.",
            (
                Key("mu_s", "number", "static friction coefficient", "—", required=True, **_NONNEG),
                Key(
                    "mu_d",
                    "number",
                    "dynamic friction coefficient (at most mu_s)",
                    "—",
                    default="(mu_s)",
                    **_NONNEG,
                ),
                Key(
                    "C",
                    "number",
                    "decay of μ with slip speed; omit for the static/dynamic jump law",
                    "s/m",
                    **_NONNEG,
                ),
            ),
        ),
        Table(
            "impact",
            "The impact law at a touchdown.",
            (
                Key(
                    "e_n", "number", "Newton's normal restitution", "—", default=0.0, lo=0.0, hi=1.0
                ),
                Key(
                    "law",
                    "string",
                    "Newton's law, or Housner's plastic sticking impact",
                    default="newton",
                    choices=("newton", "housner"),
                ),
            ),
        ),
        Table(
            "motion",
            "A record, a displacement sine or nothing (free motion).",
            (
                Key(
                    "record",
                    "string",
                    "bundled record name or path (a relative path: the scene file's folder "
                    "first); not with `period`",
                ),
                Key("vertical", "boolean", "keep the record's vertical component", default=True),
                UNITS_KEY,
                RECORD_DT_KEY,
                Key(
                    "pga",
                    "number",
                    "scale the record, or the sine's acceleration amplitude",
                    "m/s²",
                    default="(1.6 for a sine)",
                    **_POS,
                    hi=1000.0,
                ),
                Key(
                    "period",
                    "number",
                    "period T of the displacement sine u = A sin(2πt/T), A = pga (T/2π)²",
                    "s",
                    **_POS,
                ),
                Key("n_cycles", "integer", "cycles of the sine", default=5, lo=1.0),
                Key(
                    "start",
                    "string",
                    "start of the sine: a velocity jump, or a sin² ramp over one period",
                    default="impulsive",
                    choices=("impulsive", "smooth"),
                ),
                Key(
                    "t_end",
                    "number",
                    "end of the run",
                    "s",
                    default="(record end; n T + 2 s for a sine; 5 free)",
                    **_POS,
                ),
                Key(
                    "theta0",
                    "number",
                    "initial tilt (or `theta0_over_alpha`, not both)",
                    "rad",
                    default=0.0,
                ),
                Key(
                    "theta0_over_alpha",
                    "number",
                    "initial tilt / the base corner's slenderness α (or `theta0`, not both)",
                    "—",
                    default=0.0,
                ),
            ),
        ),
        Table(
            "solver",
            "Event-driven (rigid ground) or Moreau–Jean time stepping.",
            (
                Key(
                    "method",
                    "string",
                    "solver on rigid ground",
                    default="event",
                    choices=("event", "moreau"),
                ),
                Key("h", "number", "Moreau–Jean step", "s", default=1e-3, **_POS),
                Key("theta", "number", "Moreau–Jean θ", "—", default=0.5, lo=0.5, hi=1.0),
                Key("rtol", "number", "event-driven tolerance", "—", default=1e-9, **REL_TOL),
                Key("dt_out", "number", "output step", "s", default=0.005, **_POS),
                Key(
                    "step_check",
                    "boolean",
                    "Moreau–Jean: repeat the run at h/2 and say when the peaks move by more "
                    "than 10 % (about twice the run's time)",
                    default=True,
                ),
            ),
        ),
        Table(
            "ground",
            "Rigid ground (omit the table), or tensionless spring–dashpot corners "
            "with a stick spring and Coulomb friction.",
            (
                Key(
                    "kind",
                    "string",
                    "rigid or compliant ground",
                    default="rigid",
                    choices=("rigid", "compliant"),
                ),
                Key(
                    "stiffness",
                    "number",
                    "normal stiffness per base corner (required if compliant)",
                    "N/m",
                    **_POS,
                ),
                Key(
                    "damping",
                    "number",
                    "dashpot per corner (or `damping_ratio`)",
                    "N s/m",
                    default=0.0,
                    **_NONNEG,
                ),
                Key(
                    "damping_ratio",
                    "number",
                    "damping ratio of the vertical contact mode (or `damping`)",
                    "—",
                    **_NONNEG,
                ),
                Key(
                    "stick_stiffness",
                    "number",
                    "tangential stick spring per corner",
                    "N/m",
                    default="(stiffness)",
                    **_POS,
                ),
            ),
        ),
    ),
)
