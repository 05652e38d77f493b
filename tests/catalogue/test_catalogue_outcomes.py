"""Catalogue of outcomes: every family's text summary and figure say what happened.

Contract: the first line of ``nsdyn run``'s text summary is ``outcome ...`` naming the physical
outcome of the run (toppled / overturned / uplift / lift-off, or that it stayed standing, at
rest or in contact), the same outcome as the JSON summary's ``outcome`` field, and the figure's
title says it too. A toppled cylinder that exits 0 with a table of peaks and no word of the
toppling is the failure this guards against.

The cases are chosen by physics, not by a run of the code:
* a rigid cylinder (r = 1 m, half-height 4 m) under ground acceleration of 1000 m/s² (100 g)
  is far past any overturning threshold (quasi-static: a/g = r/H_cm = 0.25);
* a rigid block (2B = 2 m, 2H = 4 m, tan α = 0.5) does not lift off a rigid base while the
  ground acceleration stays below g tan α (Housner 1963): a 0.3 g pulse leaves it at rest;
* a body (μ_s = 0.57, b/h = 1.1) neither slides (a < μ_s g) nor rocks (a < g b/h) at 0.05 g
  of a base sine that starts smoothly (an impulsive start is a jump of the base velocity,
  which bounded friction cannot pass on: the body slides whatever the amplitude);
* a tensionless foundation lifts off only when the overturning moment exceeds M_u = k I s/r
  (seed 000's closed form): at 0.001 m/s² the moment m a H ≈ 4e-3 N m is far below it;
* a shear building's isolators carry a frozen (constant) normal force: they cannot lift off;
* the office frame at PGA 40 m/s² lifts off (the catalogue's uplift case in test_catalogue_cli).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from nsdyn.cli import main

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "examples" / "scenes"
CYL = str(SCENES / "cylinder-uplift.toml")
CASK = str(SCENES / "rocking-seed001-cask.toml")
CONTACT = str(SCENES / "contact-seed002-A5.toml")
SHEAR = str(SCENES / "isolated-shear-3storey.toml")


def _run(argv, capsys) -> tuple[str, dict]:
    """(text summary, JSON summary) of the same run."""
    assert main([*argv, "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert main(argv) == 0
    return capsys.readouterr().out, s


def _titles(monkeypatch, module: str, name: str) -> list[str]:
    """Record the ``title`` every call of ``module.name`` (a figure builder) is given."""
    import importlib

    mod = importlib.import_module(module)
    real = getattr(mod, name)
    seen: list[str] = []

    def spy(*a, **kw):
        seen.append(kw.get("title", ""))
        return real(*a, **kw)

    monkeypatch.setattr(mod, name, spy)
    return seen


# (id, argv, JSON outcome, what the outcome line must say, figure builder or None)
ROWS = [
    ("cylinder-topples", ["run", CYL, "--pga", "1000"], "toppled", "outcome TOPPLED at t = ",
     ("nsdyn.models.cylinder.figures", "motion_figure")),
    ("cylinder-full-contact", ["run", CYL, "--pga", "0.001", "--no-figures"], "full contact",
     "outcome the base stayed in full contact", None),
    ("rocking-below-uplift", ["run", CASK, "--pga", str(0.3 * 9.81)], "rest",
     "outcome no rocking: at rest", ("nsdyn.models.rocking.figures", "history_figure")),
    ("contact-at-rest", ["run", "SMOOTH_CONTACT", "--pga", "0.5"], "rest",
     "outcome stayed at rest", ("nsdyn.models.contact.figures", "history_figure")),
    # (its normal forces are fixed at the weights: "stayed in contact" claimed a check it
    # cannot make, with min_normal_force_N null beside it)
    ("shear-contact-assumed", ["run", SHEAR, "--t-end", "5", "--no-figures"], "contact assumed",
     "outcome contact assumed: each isolator's normal force is fixed", None),
    ("frame-in-contact", ["run", "--t-end", "2", "--no-figures"], "in contact",
     "outcome every isolator stayed in contact", None),
]  # fmt: skip


@pytest.mark.parametrize("row", [pytest.param(r, id=r[0]) for r in ROWS])
def test_summary_states_the_outcome(tmp_path, monkeypatch, capsys, row):
    rid, argv, word, line, figure = row
    smooth = tmp_path / "smooth.toml"
    smooth.write_text(Path(CONTACT).read_text().replace('"impulsive"', '"smooth"'))
    argv = [str(smooth) if a == "SMOOTH_CONTACT" else a for a in argv]
    titles = _titles(monkeypatch, *figure) if figure else []
    text, s = _run([*argv, "--out", str(tmp_path)], capsys)
    assert s["outcome"] == word, s["outcome"]
    assert text.splitlines()[0].startswith(line), text
    if figure:
        assert titles and all(line.removeprefix("outcome ")[:12] in t for t in titles), titles


def test_overturning_is_stated_wherever_it_happens(tmp_path, capsys):
    # whichever way a run ends, the text names it as the JSON does: an overturned block's
    # summary leads with OVERTURNED (a 3 g pulse; the JSON field decides, the line must agree)
    text, s = _run(["run", CASK, "--pga", "30", "--no-figures", "--out", str(tmp_path)], capsys)
    first = text.splitlines()[0]
    assert first.startswith("outcome OVERTURNED") == (s["outcome"] == "overturned"), (first, s)
    assert first.startswith("outcome OVERTURNED") == bool(s["overturned"])


N_OUTCOME_CASES = len(ROWS) + 1


def test_each_contact_assumption_names_its_own_outcome_of_a_negative_normal_force():
    # the same two zero crossings of N: under "detect" the run left the no-uplift model
    # (UPLIFT); the bilateral model (the seed's) held the isolator down, which would lift off
    # (it read UPLIFT, "outside the no-uplift model", against the guide); the unilateral one
    # lifted it off and landed it
    from nsdyn.models.isolated.scene import outcome

    up = [{"t_s": 2.5, "contact": 1}, {"t_s": 0.9735, "contact": 0}]
    word, line = outcome({"contact": "detect", "uplift": up})
    assert word == "uplift" and line.startswith("UPLIFT at t = 0.9735 s (contact 0); 1 more")
    word, line = outcome({"contact": "bilateral", "uplift": up, "would_lift_off": True})
    assert word == "would lift off"
    assert line.startswith("a normal force turned negative at t = 0.9735 s (contact 0); 1 more "
                           "such event: the bilateral model held")  # fmt: skip
    lifted = {"contact": "unilateral", "uplift": up, "lift_offs": 2, "landings": 2,
              "first_lift_off_s": 0.9735}  # fmt: skip
    assert outcome(lifted)[0] == "lift-off"
    assert outcome({"contact": "bilateral", "uplift": []}) == outcome({"contact": "detect"})
