"""Summary keys carry their unit as the conventions page says: every printed summary row of
every scene family pairs a key with the unit it prints, and the key ends in that unit's
suffix (a row without a unit has none), and the page lists every suffix in use.

Source: docs/guide/conventions.md, "Summaries carry the unit in the key".
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from nsdyn.models.contact.scene import ROWS as CONTACT_ROWS
from nsdyn.models.isolated.building3d_scene_keys import ROWS as BUILDING_ROWS
from nsdyn.models.isolated.deck_scene import ROWS as DECK_ROWS
from nsdyn.models.rocking.scene import ROWS as ROCKING_ROWS

CONVENTIONS = Path(__file__).resolve().parents[2] / "docs" / "guide" / "conventions.md"
# the unit a row prints -> the suffix its key ends in
SUFFIX = {"m": "_m", "rad": "_rad", "deg": "_deg", "s": "_s", "Hz": "_hz", "kg": "_kg",
          "kg m²": "_kgm2", "N": "_N", "N m": "_Nm", "N s": "_Ns", "J": "_J", "m/s": "_mps",
          "m/s²": "_mps2", "1/s": "_per_s"}  # fmt: skip
UNITLESS = ("", "-")  # counts, ratios, words

ROWS = {"rocking": ROCKING_ROWS, "contact": CONTACT_ROWS, "deck": DECK_ROWS,
        **{f"building3d-{k}": v for k, v in BUILDING_ROWS.items()}}  # fmt: skip


@pytest.mark.parametrize("family", sorted(ROWS))
def test_each_key_ends_in_the_unit_it_prints(family):
    for key, _label, unit in ROWS[family]:
        if unit in UNITLESS:
            assert not any(key.endswith(s) for s in SUFFIX.values()), (key, "no unit printed")
        else:
            assert unit in SUFFIX, (key, unit, "a unit the conventions do not name")
            assert key.endswith(SUFFIX[unit]), (key, unit)


def test_the_conventions_page_lists_every_suffix_in_use():
    text = CONVENTIONS.read_text(encoding="utf-8")
    para = text[text.index("**Summaries carry the unit in the key**") :].split("\n- ")[0]
    listed = set(re.findall(r"`(_[A-Za-z0-9_]+)`", para.split("a key without a suffix")[0]))
    used = {SUFFIX[u] for rows in ROWS.values() for _, _, u in rows if u not in UNITLESS}
    assert used <= listed, sorted(used - listed)
