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
