"""The keys of a 3D building scene (``[scene] kind = "building3d"``): a space frame on isolators.

Declared once as a :class:`~nsdyn.models.scene_schema.Schema`, beside the reader
(:mod:`nsdyn.models.isolated.building3d_scene`); the documentation's scene-file reference is
generated from it. ``[bearing]``, ``[motion]`` and ``[solver]`` are the deck scene's tables
(:mod:`nsdyn.models.isolated.deck_scene_keys`): the rigid rung is that deck.
"""

from __future__ import annotations

from nsdyn.models.isolated.deck_scene_keys import SCHEMA as DECK
from nsdyn.models.scene_schema import Key, Schema, Table

FIDELITIES = ("rigid", "fixed")

SCHEMA = Schema(
    "building3d",
    "a space frame on bidirectional isolators: the rigid and fixed rungs",
    "A 3D frame file (or a bundled one, `office-11-3d`) run as a rigid deck on one "
    "bidirectional isolator under every column line (`fidelity = \"rigid\"`, the deck "
    "scene's `[bearing]`) or as the fixed-base elastic building by modal time histories "
    "(`fidelity = \"fixed\"`, a three-component record). The Craig–Bampton and full rungs "
    "coupled to the isolators are not available.",
    (
        Table("scene", "The family and a name.", (
            Key("kind", "string", "the model family", required=True, choices=("building3d",)),
            Key("name", "string", "a name for outputs and titles", default="(the file's stem)"),
        )),
        Table("structure", "The space frame and the rung of the model ladder.", (
            Key("frame3d", "string", "bundled 3D frame name or a 3D frame file (relative to "
                "the scene file)", required=True),
            Key("fidelity", "string", "rigid deck on isolators, or fixed base", default="rigid",
                choices=FIDELITIES),
            Key("eccentricity", "list of numbers", "[f_x, f_y]: accidental eccentricity, every "
                "floor's centre of mass moved by these fractions of its plan dimensions", "—",
                default=(0.0, 0.0), range="each in (−0.5, 0.5)"),
            Key("n_modes", "integer", "fixed-base modes of the fixed rung", "—", default=24,
                lo=1),
        )),
        *(t for t in DECK.tables if t.name in ("bearing", "motion", "solver")),
    ),
    notes=(
        "The fixed rung needs a record (`[motion] kind = \"record3\"`); `[bearing]` and "
        "`[solver]` apply to the rigid rung only.",
    ),
)  # fmt: skip
