"""The keys of a cylinder scene (``[scene] kind = "cylinder"``): a rigid cylinder on a Winkler
foundation in 3D.

Declared once as a :class:`~nsdyn.models.scene_schema.Schema`; the reader
(:mod:`nsdyn.models.cylinder.scene`) takes its valid keys from it and the documentation's
scene-file reference is generated from it.
"""

from __future__ import annotations

from nsdyn.models.scene_schema import REL_TOL, UNITS_KEY, Key, Schema, Table

_POS = {"lo": 0.0, "lo_open": True}  # > 0
_NONNEG = {"lo": 0.0}  # >= 0

SCHEMA = Schema(
    "cylinder",
    "a rigid cylinder rocking, lifting off and sliding on a Winkler foundation",
    "A homogeneous rigid cylinder (radius r, height 2H) on vertical Winkler springs and "
    "dashpots per unit base area (seed 000), under a simulated three-component earthquake "
    "or record files.",
    (
        Table(
            "scene",
            "The family and a name.",
            (
                Key("kind", "string", "the model family", required=True, choices=("cylinder",)),
                Key(
                    "name",
                    "string",
                    "a name for outputs and titles (1 to 200 bytes)",
                    default="(the file's stem)",
                ),
            ),
        ),
        Table(
            "cylinder",
            "The rigid cylinder.",
            (
                Key("r", "number", "radius", "m", default=1.0, **_POS),
                Key(
                    "height",
                    "number",
                    "full height 2H (or `H`, not both)",
                    "m",
                    default=8.0,
                    **_POS,
                ),
                Key(
                    "H",
                    "number",
                    "half height (or `height` = 2H, not both)",
                    "m",
                    default=4.0,
                    **_POS,
                ),
                Key("m", "number", "mass", "kg", default=1.0, **_POS),
                Key(
                    "I_t",
                    "number",
                    "centroidal inertia about a diameter",
                    "kg m²",
                    default="(solid cylinder)",
                    **_POS,
                ),
                Key(
                    "I_a",
                    "number",
                    "inertia about the axis",
                    "kg m²",
                    default="(solid cylinder)",
                    **_POS,
                ),
            ),
        ),
        Table(
            "foundation",
            "The Winkler foundation: `k` and `c`, or designed from `f_rock` and `zeta`.",
            (
                Key(
                    "case",
                    "string",
                    "springs that only push, that also pull, or rigid ground",
                    default="tensionless",
                    choices=("tensionless", "bonded", "fixed"),
                ),
                Key(
                    "k",
                    "number",
                    "spring stiffness per unit base area (not with f_rock, zeta)",
                    "N/m³",
                    default=9814.0,
                    **_POS,
                ),
                Key(
                    "c",
                    "number",
                    "dashpot per unit base area (not with f_rock, zeta)",
                    "N s/m³",
                    default=103.6,
                    **_NONNEG,
                ),
                Key(
                    "f_rock",
                    "number",
                    "design: rocking frequency of the bonded base",
                    "Hz",
                    default=3.0,
                    **_POS,
                ),
                Key(
                    "zeta",
                    "number",
                    "design: rocking damping ratio (a fraction)",
                    "—",
                    default=0.1,
                    lo=0.0,
                    hi=1.0,
                    hi_open=True,
                ),
                Key(
                    "sliding",
                    "boolean",
                    "the base slides with Coulomb friction (not on a fixed base)",
                    default=False,
                ),
                Key(
                    "mu",
                    "number",
                    "friction coefficient of the sliding base (required with sliding = true)",
                    "—",
                    **_NONNEG,
                ),
            ),
        ),
        Table(
            "motion",
            "A simulated earthquake (seed 000 §4.1) or record files.",
            (
                Key(
                    "seed", "integer", "random seed of the simulated earthquake", default=0, lo=0.0
                ),
                Key(
                    "duration",
                    "number",
                    "length of the simulated earthquake",
                    "s",
                    default=20.0,
                    **_POS,
                ),
                Key(
                    "dt",
                    "number",
                    "sample step of the simulated earthquake; beside `record`, of a "
                    "single-column record file",
                    "s",
                    default=0.01,
                    **_POS,
                ),
                Key(
                    "s0_units",
                    "string",
                    "units of the white-noise intensity S0",
                    default="g2s",
                    choices=("g2s", "m2s3"),
                ),
                Key(
                    "record",
                    "string",
                    "record file of the first horizontal component (instead of "
                    "a simulated earthquake)",
                ),
                Key("record_y", "string", "record file of the second horizontal component"),
                Key("record_z", "string", "record file of the vertical component"),
                UNITS_KEY,
                Key(
                    "pga",
                    "number",
                    "scale to this peak horizontal acceleration (0: the "
                    "ground at rest, free vibration from `theta0`)",
                    "m/s²",
                    **_NONNEG,
                    hi=1000.0,
                ),
                Key("t_end", "number", "end of the run", "s", default="(the motion's end)", **_POS),
                Key(
                    "theta0",
                    "number",
                    "initial tilt of the axis (or `theta0_over_alpha`, not "
                    "both; not for a fixed base)",
                    "rad",
                    default=0.0,
                ),
                Key(
                    "theta0_over_alpha",
                    "number",
                    "initial tilt / α, α = atan(r / H) (or `theta0`, not both)",
                    "—",
                    default=0.0,
                ),
                Key(
                    "azimuth0",
                    "number",
                    "direction the axis initially leans to, from x towards y",
                    "rad",
                    default=0.0,
                ),
            ),
        ),
        Table(
            "solver",
            "The Dormand–Prince 5(4) integrator.",
            (
                Key("rtol", "number", "relative tolerance", "—", default=1e-7, **REL_TOL),
                Key("method", "string", "integrator", default="dopri5", choices=("dopri5",)),
            ),
        ),
        Table(
            "output",
            "What the summary reports.",
            (
                Key(
                    "z_section",
                    "number",
                    "height of the stress section",
                    "m",
                    default="(H)",
                    lo=0.0,
                    range="< 2H",
                ),
            ),
        ),
        Table(
            "star",
            "One quantity scaled after the design, the rest kept (a one-at-a-time study).",
            (
                Key(
                    "case",
                    "string",
                    '`"base"` or `"<q>*<factor>"` with q one of k, c, H, r (e.g. `"k*2"`)',
                    default="base",
                ),
            ),
        ),
    ),
)
