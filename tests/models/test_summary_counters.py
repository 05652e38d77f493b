"""Every family's run summary names its counters alike.

What is asserted (a naming contract, no number): the summary of a rocking, contact, cylinder
and deck scene run counts its integration steps as ``n_steps`` (a whole number), and none uses
the bare names ``steps``, ``events``, ``rejected`` or ``evaluations`` (the deck and cylinder
summaries did): a study's ``keep`` list or a notebook reading ``summary["n_steps"]`` works on
any family.
"""

from __future__ import annotations

import importlib

import pytest

SCENES = {
    "rocking": {"scene": {"kind": "rocking", "model": "block"},
                "block": {"width": 0.4, "height": 2.0}, "motion": {"t_end": 0.05}},
    "contact": {"scene": {"kind": "contact"}, "body": {"width": 1.1, "height": 1.0, "mass": 1.0},
                "friction": {"mu_s": 0.5}, "motion": {"t_end": 0.05}},
    "cylinder": {"scene": {"kind": "cylinder"}, "motion": {"duration": 0.1}},
    "deck": {"scene": {"kind": "deck"}, "mass": {"m": 1.0e5},
             "bearing": {"type": "flat", "mu": 0.03, "k_lam": 5.0e4, "c": 1.0e4},
             "motion": {"kind": "orbit", "orbit": "circular", "frequency": 0.4,
                        "amplitude": 0.5, "n_periods": 1}},
}  # fmt: skip
RUNNER = {"rocking": "nsdyn.models.rocking.scene", "contact": "nsdyn.models.contact.scene",
          "cylinder": "nsdyn.models.cylinder.scene",
          "deck": "nsdyn.models.isolated.deck_scene"}  # fmt: skip
BARE = {"steps", "events", "rejected", "evaluations"}


@pytest.mark.parametrize("family", SCENES)
def test_a_summary_counts_its_steps_as_n_steps(family, tmp_path):
    mod = importlib.import_module(RUNNER[family])
    s = mod.run_scene(SCENES[family], source="t.toml", out_dir=tmp_path, figures=False,
                      quiet=True)  # fmt: skip
    assert isinstance(s["n_steps"], int) and s["n_steps"] >= 0  # (a block at rest: none)
    assert BARE.isdisjoint(s), sorted(BARE & set(s))
