"""The arrays of ``building3d.npz`` are those the 3D frames guide lists for each rung, with the
shapes it gives (a key the file writes and the table does not name, or the reverse, fails).

Source: docs/guide/frames-3d.md, the table of ``building3d.npz``'s arrays.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from nsdyn.models.isolated.building3d_scene import run_scene
from nsdyn.models.scenefile import read_toml

ROOT = Path(__file__).resolve().parents[2]
GUIDE = ROOT / "docs" / "guide" / "frames-3d.md"


def documented() -> dict[str, set[str]]:
    """Rung -> the keys the guide's table says its file holds."""
    text = GUIDE.read_text(encoding="utf-8")
    table = text.split("The arrays of `building3d.npz`")[1].split("\n\n")[1]
    out: dict[str, set[str]] = {}
    for line in table.splitlines()[2:]:
        cells = [c.strip() for c in line.strip("|").split("|")]
        keys = re.findall(r"`(\w+)`", cells[0])
        rungs = cells[-1].replace("all", "rigid, fixed, cb, full")
        if "on triple pendulums" in rungs:  # (the example scenes' bearings are single pendulums)
            continue
        only = re.search(r"\(`(\w+)`: ([\w, ]+)\)", rungs)  # "(`other`: cb, full)"
        for rung in re.findall(r"\b(rigid|fixed|cb|full)\b", rungs.split("(")[0]):
            out.setdefault(rung, set()).update(
                k for k in keys if not only or k != only[1] or rung in only[2]
            )
        if "corners" in cells[3]:  # the drift table's corners, named in its meaning
            for rung in re.findall(r"\b(rigid|fixed|cb|full)\b", rungs):
                out[rung].add("corners")
    return out


@pytest.mark.parametrize("rung", ["rigid", "fixed", "cb"])
def test_the_file_holds_the_arrays_the_guide_lists(rung, tmp_path):
    scene = ROOT / "examples" / "scenes" / f"building3d-office-{rung}.toml"
    cfg = read_toml(scene)
    cfg.setdefault("motion", {})["t_end"] = 0.1
    run_scene(cfg, source=str(scene), out_dir=tmp_path, figures=False, quiet=True)
    with np.load(tmp_path / "building3d.npz") as z:
        shapes = {k: z[k].shape for k in z.files}
    assert set(shapes) == documented()[rung]
    nt = shapes["t"][0]
    if "qd" in shapes:
        assert shapes["qd"] == shapes["q"] and shapes["q"][0] == nt
    if "drift_cm" in shapes:
        ns = shapes["drift_cm"][0]
        assert shapes["drift_cm"] == (ns, 2, nt) and shapes["drift_corner"] == (ns, 4, 2, nt)
        assert shapes["floor_acc"] == (ns + 1, 2, nt) and shapes["base_shear"] == (2, nt)
        assert shapes["torsion"] == (nt,) and shapes["corners"] == (4, 2)
    if "u" in shapes:
        ni = shapes["N"][1]
        assert shapes["u"] == (nt, ni, 2) and shapes["positions"] == (ni, 2)
