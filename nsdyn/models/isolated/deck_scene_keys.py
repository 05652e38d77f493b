"""The keys of a deck scene (``[scene] kind = "deck"``): bidirectional isolators in a plane.

Declared once as a :class:`~nsdyn.models.scene_schema.Schema`, beside the reader
(:mod:`nsdyn.models.isolated.deck_scene`); the documentation's scene-file reference is
generated from it, and ``tests/docs/test_scene_reference.py`` checks it against the reader's
behaviour both ways. ``[motion]`` is a three-component table read by
:mod:`nsdyn.ground.table3` (a record, or a harmonic orbit of one of four shapes).
"""

from __future__ import annotations

from nsdyn.models.isolated.defaults import EPS, EPS_MAX, ETA
from nsdyn.models.scene_schema import RECORD_UNITS, REL_TOL, Key, Schema, Table

_POS = {"lo": 0.0, "lo_open": True}  # > 0
_NONNEG = {"lo": 0.0}  # >= 0
_MU = {"lo": 0.0, "hi": 1.0}  # a coefficient, not a percentage (0.05 for 5 %)

_T_END = Key("t_end", "number", "end of the run (or `n_periods`; one is required)", "s", **_POS)
_ORBIT_COMMON = (
    Key("kind", "string", "a harmonic orbit", required=True, choices=("orbit",)),
    Key("frequency", "number", "frequency f of the horizontal orbit", "Hz", required=True, **_POS),
    Key("vertical_amplitude", "number", "amplitude of a vertical harmonic", "m/s²", default=0.0,
        **_NONNEG),
    Key("vertical_frequency", "number", "its frequency", "Hz", default="(f)", **_POS),
    Key("vertical_phase", "number", "its phase", "deg", default=0.0),
    _T_END,
    Key("n_periods", "number", "duration in periods (or `t_end`)", "—", **_POS),
)  # fmt: skip


def _orbit(shape: str, meaning: str, *keys: Key) -> Table:
    orbit = Key("orbit", "string", "the orbit's shape", required=True, choices=(shape,))
    return Table("motion", meaning, (*_ORBIT_COMMON[:1], orbit, *_ORBIT_COMMON[1:], *keys),
                 variant=f'`kind = "orbit"`, `orbit = "{shape}"`')  # fmt: skip


_AMPLITUDE = Key("amplitude", "number", "amplitude A of the ground acceleration", "m/s²",
                 required=True, **_NONNEG)  # fmt: skip
_ANGLE = Key("angle", "number", "direction of the line (major axis) from x", "deg", default=0.0)
_SENSE = Key("sense", "integer", "sense of rotation: +1 counter-clockwise, −1 clockwise",
             default=1, choices=(1, -1))  # fmt: skip

_TFP = "tfp only"
_TFP_KEYS = (
    *(Key(f"R{j}", "number", f"effective radius of surface {j} ({w})", "m", **_POS,
          range=_TFP + ("; R1 > R2" if j == 1 else "; R4 > R3" if j == 4 else ""))
      for j, w in ((1, "outer, lower"), (2, "inner slider, lower"), (3, "inner slider, upper"),
                   (4, "outer, upper"))),
    *(Key(f"mu{j}", "number", f"friction coefficient of surface {j}", "—", **_POS, hi=1.0,
          range=_TFP + ("; mu2, mu3 ≤ mu1, mu4" if j in (2, 3) else ""))
      for j in range(1, 5)),
    *(Key(f"mu_fast{j}", "number", f"friction of surface {j} at high slip speed (with `rate`)",
          "—", default=f"(mu{j})", **_MU, range=_TFP + f"; ≥ mu{j}")
      for j in range(1, 5)),
    *(Key(f"d{j}", "number", f"displacement capacity of surface {j}", "m", **_POS,
          range=_TFP + ("; d1, d4 ≥ d2, d3" if j in (1, 4) else ""))
      for j in range(1, 5)),
    Key("u_y", "number", "yield displacement: the elastic slip before the first surface "
        "slides", "m", default=2.5e-4, **_POS, range=_TFP),
    Key("zeta_e", "number", "damping ratio of the elastic stage (a dashpot across its spring; "
        "0: undamped)", "—", default=1.0, **_NONNEG, hi=1e4, range=_TFP),
)  # fmt: skip


SCHEMA = Schema(
    "deck",
    "bidirectional isolators: a rigid deck or a mass sliding in a plane",
    "A rigid deck on friction pendulum or flat sliding bearings that slide in two horizontal "
    "directions, or a single mass on one bearing, under a three-component record or a "
    "harmonic orbit. Give `[deck]` or `[mass]`, one `[bearing]` for every isolator and a "
    "`[motion]`.",
    (
        Table("scene", "The family and a name.", (
            Key("kind", "string", "the model family", required=True, choices=("deck",)),
            Key("name", "string", "a name for outputs and titles (1 to 200 bytes)",
                default="(the file's stem)"),
        )),
        Table("deck", "A rigid deck on isolators (or `[mass]`).", (
            Key("m", "number", "mass of the deck", "kg", required=True, **_POS),
            Key("J", "number", "polar inertia about the centre of mass", "kg m²",
                default="(m (L_x² + L_y²)/12 of the isolators' plan extent)", **_POS),
            Key("positions", "list of [x, y]", "plan positions [X, Y] of the isolators", "m",
                required=True),
            Key("ecc", "list of numbers", "[e_x, e_y]: centre of mass from the plan origin", "m",
                default=(0.0, 0.0)),
            Key("h", "number", "height of the centre of mass above the sliding surfaces", "m",
                default=0.0, **_NONNEG),
        )),
        Table("mass", "A single mass on one isolator (or `[deck]`).", (
            Key("m", "number", "the mass", "kg", required=True, **_POS),
        )),
        Table("bearing", "One bearing for every isolator: a friction pendulum (`radius`), a "
              "flat slider (`k_lam`, `c`), with a displacement capacity and its restrainer rim, "
              "or a triple friction pendulum (`type = \"tfp\"`: `R1` … `R4`, `mu1` … `mu4`, "
              "`d1` … `d4`).", (
            Key("type", "string", "friction pendulum, flat slider or triple friction pendulum",
                default="(fps with a radius, else flat)", choices=("fps", "flat", "tfp")),
            Key("mu", "number", "friction coefficient (or `mu_slow`, `mu_fast`, `rate`)", "—",
                **_MU),
            Key("mu_slow", "number", "kinetic coefficient at low slip speed", "—", **_MU),
            Key("mu_fast", "number", "kinetic coefficient at high slip speed", "—",
                default="(mu_slow)", **_MU),
            Key("rate", "number", "a of μ_d(|v|) = μ_fast − (μ_fast − μ_slow) exp(−a |v|)", "s/m",
                default=0.0, **_NONNEG),
            Key("mu_static", "number", "static coefficient of the stick disc (switch law)", "—",
                default="(the kinetic coefficient)", hi=1.0, range="≥ the kinetic coefficient"),
            Key("radius", "number", "effective radius R of a friction pendulum", "m", **_POS,
                range="required for fps, not for flat"),
            Key("k_lam", "number", "lateral stiffness of a laminated bearing", "N/m", default=0.0,
                **_NONNEG),
            Key("c", "number", "viscous damper", "N s/m", default=0.0, **_NONNEG),
            Key("d_cap", "number", "displacement capacity: the restrainer rim acts beyond it",
                "m", default="(none)", range="μ_s R < d_cap < R", **_POS),
            Key("k_stop", "number", "stiffness of the rim", "N/m",
                default="(100 × the post-slip stiffness at the static load)", **_POS),
            Key("c_stop", "number", "damping of the rim", "N s/m",
                default="(10 % of critical on the bearing's mass share)", **_NONNEG),
            Key("area", "number", "contact area of the slider: friction scaled by "
                "0.7^((N/area − p_ref)/50 MPa) (with `p_ref`)", "m²", **_POS),
            Key("p_ref", "number", "contact pressure at which the friction coefficients hold "
                "(with `area`)", "Pa", **_POS),
            *_TFP_KEYS,
        )),
        Table("motion", "A three-component record: one file with two horizontal components "
              "(and a vertical one), or one file per component.", (
            Key("kind", "string", "a three-component record", required=True,
                choices=("record3",)),
            Key("record", "string", "bundled record with a second horizontal component, or a "
                "t, ax, ay[, az] CSV (or `x`, `y`, `z`)"),
            Key("x", "string", "record file of the x component"),
            Key("y", "string", "record file of the y component"),
            Key("z", "string", "record file of the vertical component (optional)"),
            Key("units", "string", "units of the record files (where a header states others, "
                "these win, with a warning)", choices=RECORD_UNITS),
            Key("dt", "number", "sample step of single-column files", "s", **_POS),
            Key("rotate", "number", "rotate the horizontal pair by this angle", "deg",
                default=0.0),
            Key("trim", "boolean", "cut the components to their common time span",
                default=False),
            Key("vertical", "boolean", "keep the vertical component", default=True),
            Key("pga", "number", "scale to this peak horizontal acceleration", "m/s²",
                **_POS),
            Key("pga_component", "string", "which peak `pga` sets", default="resultant",
                choices=("resultant", "x", "y", "geomean")),
            Key("t_end", "number", "end of the run", "s", default="(the record's end)", **_POS),
        ), variant='`kind = "record3"`'),
        _orbit("linear", "A harmonic ground acceleration along a line.", _AMPLITUDE, _ANGLE),
        _orbit("circular", "A circular orbit of the ground acceleration.", _AMPLITUDE, _SENSE),
        _orbit("elliptical", "An elliptical orbit: `amplitude` along the major axis.",
               _AMPLITUDE,
               Key("amplitude_minor", "number", "amplitude along the minor axis (at most "
                   "`amplitude`)", "m/s²", required=True),
               _ANGLE, _SENSE),
        _orbit("general", "Two harmonics of one frequency, along x and y with a phase.",
               Key("amplitude_x", "number", "amplitude along x", "m/s²", required=True),
               Key("amplitude_y", "number", "amplitude along y", "m/s²", required=True),
               Key("phase_y", "number", "phase φ_y of a_y = A_y sin(ωt + φ_y) against a_x = A_x "
                   "sin ωt (90: y leads x, a clockwise turn)", "deg", default=90.0)),
        Table("sweep", "`nsdyn sweep`'s frequency curve of this scene (under an orbit only: "
              "refused beside a record); its flags `--fmin`, `--fmax`, `--points`, "
              "`--amplitudes`, `--friction` win.", (
            Key("f_min", "number", "lowest frequency", "Hz", default="(f/4)", **_POS),
            Key("f_max", "number", "highest frequency, above f_min", "Hz", default="(4 f)",
                **_POS),
            Key("points", "integer", "log-spaced frequencies", "—", default="(nsdyn sweep's)",
                lo=2, hi=10_000),
            Key("amplitudes", "list of numbers", "amplitudes A of the orbit's acceleration, "
                "1 to 1000, each > 0 (the orbit's shape kept)", "m/s²", default="(the orbit's)"),
            Key("law", "string", "friction law of the sweep", default="(solver.law)",
                choices=("switch", "arctan")),
        )),
        Table("solver", "The friction law and the integrator's tolerances.", (
            Key("law", "string", "switch law with a stick disc, or the regularised arctan law",
                default="switch", choices=("switch", "arctan")),
            Key("eps", "number", "sharpness ε of the arctan law", "s/m", default=EPS, **_POS,
                hi=EPS_MAX),
            Key("eta", "number", "stick band η of the switch law", "m/s", default=ETA, **_POS),
            Key("rtol", "number", "relative tolerance", "—", default=1e-6, **REL_TOL),
            Key("atol", "number or pair", "absolute tolerance: one number for displacements and "
                "velocities, or [displacements, velocities]; default 1e-8 for both with the "
                "switch law, [1e-8 m, 1e-6 m/s] with the arctan law", "m, m/s", **_POS),
            Key("dt_out", "number", "output step", "s",
                default="(the record's sample step; an orbit's period / 50)", **_POS),
            Key("contact", "string", "what a normal force reaching zero does: stop the run "
                "there (uplift), or hold the isolator down and go on (tension reported; "
                "`unilateral` lift-off is not available here)", default="detect",
                choices=("detect", "bilateral")),
        )),
    ),
)  # fmt: skip
