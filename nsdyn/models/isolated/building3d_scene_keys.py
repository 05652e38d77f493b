"""The keys of a 3D building scene (``[scene] kind = "building3d"``): a space frame on isolators.

Declared once as a :class:`~nsdyn.models.scene_schema.Schema`, beside the reader
(:mod:`nsdyn.models.isolated.building3d_scene`); the documentation's scene-file reference is
generated from it. ``[bearing]``, ``[motion]`` and ``[solver]`` are the deck scene's tables
(:mod:`nsdyn.models.isolated.deck_scene_keys`): the rigid rung is that deck. :func:`unused_keys`
says which keys a rung does not read. ``ROWS`` are the summary's rows each rung prints (its
key, label and unit), :func:`format_summary` the table. ``n_modes`` counts the fixed-base modes
of the fixed rung and the fixed-interface modes a cb or dense full rung keeps.
"""

from __future__ import annotations

from nsdyn.models.isolated.deck_scene_keys import SCHEMA as DECK
from nsdyn.models.scene_schema import Key, Schema, Table

FIDELITIES = ("rigid", "fixed", "cb", "full", "auto")
BASES = ("grid", "pinned")
DAMPINGS = ("modal", "stiffness")  # the sparse full rung's (pairs_sparse.DAMPINGS)

_DECK_SOLVER = next(t for t in DECK.tables if t.name == "solver")
SOLVER = Table("solver", _DECK_SOLVER.meaning + " The full rung on sparse operators (its "
               "default where the law allows) steps at a fixed dt with the regularised law.", (
    *(k for k in _DECK_SOLVER.keys if k.name != "contact"),
    Key("contact", "string", "what a normal force reaching zero does: stop the run there "
        "(`detect`: uplift), hold the isolator down and go on (`bilateral`: tension "
        "reported), or let it lift off and land (`unilateral`: the cb and dense full rungs, "
        "switch law on Dormand–Prince). The rigid "
        "rung takes `detect` and `bilateral`, the sparse full rung `detect`",
        default="detect", choices=("detect", "bilateral", "unilateral")),
    Key("path", "string", "where the full rung runs: on sparse operators above 100 internal "
        "dofs when the law (`arctan`, given), contact (`detect`) and bearing (no `tfp`, no "
        "`area`) allow it, else dense (`auto`); or as asked: `dense` (every fixed-interface mode, "
        "adaptive steps to `rtol`; frames within the dense limit) or `sparse` (a fixed step "
        "`dt`)",
        default="auto", choices=("auto", "dense", "sparse")),
    Key("dt", "number", "fixed time step of the full rung on sparse operators (its "
        "generalized-α; at most the record's sampling step, and 2 000 000 steps per run) and "
        "of `nsdyn export opensees` (Newmark); the adaptive rungs ignore it", "s",
        default="(0.005; the sparse rung: at most the record's step)", lo=0.0, lo_open=True),
))  # fmt: skip

SCHEMA = Schema(
    "building3d",
    "a space frame on bidirectional isolators: the rigid, fixed, cb and full rungs",
    "A 3D frame file (or a bundled one, `office-11-3d`) on one bidirectional isolator under "
    "every column line (the deck scene's `[bearing]`): taken rigid (`fidelity = \"rigid\"`, "
    "the rigid deck), elastic by Craig–Bampton (`\"cb\"`) or with every mode (`\"full\"`: "
    "dense on small frames or where the law needs it, else on sparse operators) with the "
    "normal forces from the dynamics, or on a fixed base by modal time histories "
    "(`\"fixed\"`, a three-component record); `\"auto\"` asks the model advisor for the "
    "cheapest rung that answers and runs it.",
    (
        Table("scene", "The family and a name.", (
            Key("kind", "string", "the model family", required=True, choices=("building3d",)),
            Key("name", "string", "a name for outputs and titles (1 to 200 bytes)",
                default="(the file's stem)"),
        )),
        Table("structure", "The space frame and the rung of the model ladder.", (
            Key("frame3d", "string", "bundled 3D frame name or a 3D frame file (relative to "
                "the scene file)", required=True),
            Key("fidelity", "string", "the rung: rigid deck, fixed base, Craig–Bampton or full "
                "model on isolators, or the advisor's choice", default="rigid",
                choices=FIDELITIES),
            Key("eccentricity", "list of numbers", "[f_x, f_y]: accidental eccentricity, every "
                "floor's centre of mass moved by these fractions of its plan dimensions", "—",
                default=(0.0, 0.0), range="each in (−0.5, 0.5)"),
            Key("n_modes", "integer", "fixed-base modes of the fixed rung", "—", default=24,
                lo=1),
            Key("f_max", "number", "Craig–Bampton cut-off of the cb rung", "Hz", default=5.0,
                lo=0.0, lo_open=True),
            Key("min_mass", "number", "cb rung: keep a fixed-interface mode only if its "
                "effective-mass fraction in x, y, z or torsion reaches this (0: every mode "
                "below f_max)", "—", default=1e-4, lo=0.0, hi=1.0, hi_open=True),
            Key("base", "string", "cb and full rungs: feet tied by a stiff base grid and a "
                "rigid base diaphragm, or each foot pinned on its own isolator", default="grid",
                choices=BASES),
            Key("damping", "string", "full rung on sparse operators: the frame's ratios on "
                "its fixed-interface modes as the cb rung (\"modal\", low rank), or β K on "
                "the members, β = 2ζ₁/ω₁ (\"stiffness\", the OpenSees export's; far cheaper "
                "on large frames)", default="modal",
                choices=DAMPINGS),
            Key("f_damp", "number", "full rung on sparse operators with modal damping: the "
                "fixed-interface modes damped are those up to this frequency (default: every "
                "mode up to 1 000 interior dofs, else those up to 50 Hz)", "Hz", lo=0.0,
                lo_open=True),
        )),
        *(t for t in DECK.tables if t.name in ("bearing", "motion")),
        SOLVER,
    ),
    notes=(
        "The fixed rung needs a record (`[motion] kind = \"record3\"`) and ignores "
        "`[bearing]` and `[solver]`; the rigid, cb and full rungs need `[bearing]`.",
        "`fidelity = \"full\"` runs on sparse operators (a fixed step `solver.dt`) above 100 "
        "internal dofs whenever the scene allows it: the regularised law (`solver.law = "
        "\"arctan\"`), contact `detect`, friction pendulums and flat sliders (no `tfp`, no "
        "`area`); else on dense matrices with adaptive steps, for frames within the dense "
        "limit of the full rung, 400 (see the 3D guide). `solver.path` overrides the choice.",
        "`fidelity = \"auto\"` runs the rigid and cb rungs over the record's strong-motion "
        "part and picks the cheapest that answers (see the 3D guide); it needs a record.",
    ),
)  # fmt: skip


def unused_keys(cfg: dict, fid: str, path: str | None) -> list[tuple[str, str]]:
    """(key, why) of the keys given that the rung ``fid`` (on ``path``, the full rung's) does
    not read: a run notes them rather than take them silently."""
    st, solver = cfg.get("structure", {}), cfg.get("solver", {})
    sparse = fid == "full" and path == "sparse"
    rules = {
        "structure.n_modes": (st, fid != "fixed", "the fixed rung's modes"),
        "structure.f_max": (st, fid != "cb", "the cb rung's cut-off"),
        "structure.min_mass": (st, fid != "cb", "the cb rung's filter"),
        "structure.base": (st, fid not in ("cb", "full"), "the cb and full rungs' base"),
        "structure.damping": (st, not sparse, "the full rung's on sparse operators"),
        "structure.f_damp": (st, not sparse or st.get("damping") == "stiffness",
                             "the modal damping's cut-off of the full rung on sparse operators"),
        "solver.dt": (solver, not sparse, "the fixed step of the full rung on sparse operators"),
        "solver.path": (solver, fid != "full", "the full rung's"),
        "solver.rtol": (solver, sparse, "the sparse path steps at solver.dt (solver.path = "
                        "'dense' runs adaptive)"),
        "solver.atol": (solver, sparse, "the sparse path steps at solver.dt (solver.path = "
                        "'dense' runs adaptive)"),
    }  # fmt: skip
    out = [(k, why) for k, (table, unused, why) in rules.items()
           if unused and k.split(".")[1] in table]  # fmt: skip
    if fid != "fixed":  # the friction law's own keys (the fixed rung has no bearing)
        from nsdyn.models.isolated.deck_scene import unused_law_keys

        out += unused_law_keys(cfg)
    if fid == "fixed":  # no bearing, no integration: the tables as a whole
        out = [(k, w) for k, w in out if not k.startswith("solver.")]
        out += [(f"[{t}]", "the fixed rung (a fixed base, modal histories)")
                for t in ("bearing", "solver") if cfg.get(t)]  # fmt: skip
    return out


ROWS = {
    "rigid": (
        ("mass_kg", "mass", "kg"),
        ("polar_inertia_kgm2", "polar inertia", "kg m²"),
        ("height_of_centre_of_mass_m", "height of the CM", "m"),
        ("peak_resultant_displacement_m", "peak |u| (resultant)", "m"),
        ("residual_displacement_m", "residual |u|", "m"),
        ("peak_torsion_rad", "peak twist", "rad"),
        ("peak_base_shear_N", "peak base shear |V|", "N"),
        ("peak_torsional_moment_Nm", "peak torsional moment", "N m"),
        ("min_normal_force_N", "min normal force", "N"),
        ("max_normal_force_N", "max normal force", "N"),
        ("stick_fraction", "stick fraction", ""),
    ),
    "fixed": (
        ("n_modes", "fixed-base modes", ""),
        ("f1_hz", "first frequency", "Hz"),
        ("mass_captured_x", "mass captured x", ""),
        ("mass_captured_y", "mass captured y", ""),
        ("mass_captured_torsion", "mass captured torsion", ""),
        ("peak_drift_cm_x", "peak drift CM x", ""),
        ("peak_drift_cm_y", "peak drift CM y", ""),
        ("peak_drift_corner_x", "peak drift corner x", ""),
        ("peak_drift_corner_y", "peak drift corner y", ""),
        ("corner_amplification_x", "corner/CM x", ""),
        ("corner_amplification_y", "corner/CM y", ""),
        ("peak_floor_acc_x_mps2", "peak floor acc x", "m/s²"),
        ("peak_floor_acc_y_mps2", "peak floor acc y", "m/s²"),
        ("peak_base_shear_x_N", "peak base shear x", "N"),
        ("peak_base_shear_y_N", "peak base shear y", "N"),
        ("peak_torsional_moment_Nm", "peak torsional moment", "N m"),
    ),
}
ROWS["cb"] = (
    ("path", "path", ""),
    ("path_why", "why", ""),
    ("n_dofs", "coordinates", ""),
    ("law", "friction law", ""),
    ("n_modes", "fixed-interface modes", ""),
    ("modes_dropped", "modes dropped (participation)", ""),
    ("peak_resultant_displacement_m", "peak |u| (resultant)", "m"),
    ("residual_displacement_m", "residual |u|", "m"),
    ("min_normal_force_N", "min normal force", "N"),
    ("max_normal_force_N", "max normal force", "N"),
    ("stick_fraction", "stick fraction", ""),
    *ROWS["fixed"][5:],
    ("peak_base_shear_N", "peak base shear |V|", "N"),
    ("peak_roof_corner_displacement_m", "peak roof corner |u|", "m"),
    ("compile_s", "compile/load time", "s"),
)
ROWS["full"] = (*ROWS["cb"][:3], ("damping", "damping (sparse)", ""),
                ("n_damped_modes", "damped modes (sparse)", ""),
                ("method", "integrator", ""), ("dt_s", "time step", "s"),
                *ROWS["cb"][3:])  # fmt: skip


def format_summary(s: dict) -> str:
    """A short human table of a run, every number with its unit; rim contacts and uplift
    first (never silent)."""
    from nsdyn.models.isolated.deck_scene import PGA_ROW, summary_table  # (the keys: no numba)

    head = f"building3d {s.get('name', '')}: {s['frame']}, fidelity {s['fidelity']}"
    rows = (PGA_ROW, *ROWS[s["fidelity"]], ("energy_closure", "energy closure", ""),
            ("t_end_s", "end time", "s"), ("wall_s", "run time", "s"))  # fmt: skip
    return summary_table(head, s, rows)
