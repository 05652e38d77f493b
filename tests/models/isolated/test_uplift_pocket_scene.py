"""The bundled uplift scene (examples/scenes/isolated-uplift-pocket.toml) end to end.

The scene shakes the office frame at 0.93 Hz with 1.1 times the uplift boundary's amplitude
there (A* = 12.3 m/s^2, from nsdyn.periodic.uplift_boundary, itself checked by transients in
tests/periodic/test_uplift_boundary.py), with unilateral contact. What must hold:

- the isolators do lift off (the amplitude is above A*), and every landing follows a lift-off
  of its contact: 0 <= lift-offs - landings <= 2 (two contacts, at most both in the air at the
  end of the run);
- a unilateral contact never pulls: the smallest normal force is >= 0;
- plastic landings (e = 0) only dissipate: the energy change at the landings is <= 0, and the
  energy balance with it (the run's relative closure error) closes to the integration
  tolerance: rtol 1e-6 over 30 periods leaves ~1e-4; 1e-3 is allowed.
"""

import json
import math
from pathlib import Path

from nsdyn.cli import main

SCENE = Path(__file__).resolve().parents[3] / "examples" / "scenes" / "isolated-uplift-pocket.toml"


def test_the_uplift_scene_lifts_off_and_lands(tmp_path, capsys):
    assert main(["run", str(SCENE), "--json", "--no-figures", "--out", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    s = json.loads(out)
    assert s["contact"] == "unilateral"
    assert s["lift_offs"] > 0
    # the model lets the isolators lift off: that is its outcome, not a departure from it
    assert s["outcome"] == "lift-off" and s["uplift"] == []
    assert "warning" not in err
    assert 0 <= s["lift_offs"] - s["landings"] <= 2
    # a unilateral contact pushes, never pulls: no negative force, not even -0.0 in the JSON
    assert s["min_normal_force_N"] >= 0.0 and math.copysign(1.0, s["min_normal_force_N"]) > 0
    assert s["impact_energy_J"] <= 0.0
    assert abs(s["energy_closure"]) <= 1e-3


def test_a_scene_s_restitution_reaches_the_landings(tmp_path, capsys):
    # solver.restitution was a Python argument only: a scene (and so a study) could not vary
    # it. 16 periods (1.5 lift-offs in the first 12.3 s): e = 0 and e = 0.5 land differently,
    # the summary says which e ran, and the balance (landings' energy included) still closes
    text = SCENE.read_text().replace("n_periods = 30", "n_periods = 16")
    runs = {}
    for e in (0.0, 0.5):
        scene = tmp_path / f"e{e}.toml"
        scene.write_text(text.replace("[solver]\n", f"[solver]\nrestitution = {e}\n"))
        out = str(tmp_path / f"o{e}")
        assert main(["run", str(scene), "--json", "--no-figures", "--out", out]) == 0
        runs[e] = json.loads(capsys.readouterr().out)
    assert runs[0.0]["restitution"] == 0.0 and runs[0.5]["restitution"] == 0.5
    assert runs[0.0]["landings"] > 0 and runs[0.5]["landings"] != runs[0.0]["landings"]
    assert all(
        abs(s["energy_closure"]) <= 1e-3 and s["impact_energy_J"] <= 0 for s in runs.values()
    )
    # refused: outside [0, 1], and without landings (a contact other than unilateral)
    for edit, said in (
        ("restitution = 1.5", "solver.restitution: expected a coefficient 0 <= e"),
        ('contact = "detect"', "solver.restitution: a landing's coefficient needs"),
    ):
        bad = text.replace("[solver]\n", "[solver]\nrestitution = 0.5\n")
        bad = bad.replace("restitution = 0.5", edit) if "restitution" in edit else bad.replace(
            'contact = "unilateral"', edit)  # fmt: skip
        scene = tmp_path / "bad.toml"
        scene.write_text(bad)
        assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "b")]) == 2
        assert said in capsys.readouterr().err
