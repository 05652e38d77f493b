"""Studies run the custom structures too (a [structure] scene through the same runner).

Source of the physics check: Coulomb friction in the isolation layer resists sliding, so under
the same record a larger μ leaves a smaller peak isolator slip (for this lightly damped layer
and these μ, far below the PGA/g ratio that would lock it).
"""

from __future__ import annotations

import csv
from pathlib import Path

from nsdyn.cli import main

SCENE = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "isolated-shear-3storey.toml"


def test_study_over_a_shear_building_scene(tmp_path, capsys):
    study = tmp_path / "s.toml"
    study.write_text(
        f'[study]\nname = "shear-mu"\nscene = "{SCENE}"\n\n'
        '[parameters]\n"isolation.mu" = [0.02, 0.05]\n\n'
        '[records]\nnames = ["synthetic-kt-20s"]\n'
    )
    assert main(["study", str(study), "--out", str(tmp_path / "out"), "--workers", "1"]) == 0
    capsys.readouterr()
    rows = list(csv.DictReader((tmp_path / "out" / "results.csv").open()))
    assert [r["status"] for r in rows] == ["ok", "ok"]
    x = {float(r["isolation.mu"]): float(r["x_iso_max_m"]) for r in rows}
    assert x[0.05] < x[0.02]
    assert all(r["fidelity"] == "shear" for r in rows)
