"""``nsdyn bench opensees3d``: registered; without OpenSees it says how to install; its quick
run compares the same fixed-base linear model on both sides (peaks within 2 %).

The quick run (2 s of the record on the 7200-dof office building, a few minutes) needs
openseespy and is slow.
"""

from __future__ import annotations

import csv
import re
import sys

import pytest

from nsdyn.bench import BENCHMARKS, load_benchmark
from nsdyn.models.isolated.opensees import OpenSeesUnavailable, load_opensees


def _has_opensees() -> bool:
    try:
        load_opensees()
    except OpenSeesUnavailable:
        return False
    return True


def test_registered():
    assert BENCHMARKS["opensees3d"] == "nsdyn.bench.opensees3d"
    mod = load_benchmark("opensees3d")
    assert callable(mod.run_bench) and mod.best_rung() in ("cb", "rigid")


def test_scene_is_a_building3d_scene_with_the_window(tmp_path):
    """The benchmark's scene reads as a building3d scene with the window as motion.t_end."""
    from nsdyn.models.isolated.building3d_scene import build_motion
    from nsdyn.models.scenefile import read_toml, scene_kind

    mod = load_benchmark("opensees3d")
    p = tmp_path / "s.toml"
    p.write_text(mod.scene_text("rigid", 1.5))
    cfg = read_toml(p)
    assert scene_kind(cfg, str(p)) == "building3d"
    motion, _ = build_motion(cfg, str(p))
    assert motion.duration == pytest.approx(1.5)


def test_without_opensees_says_how_to_install(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "openseespy", None)
    monkeypatch.setitem(sys.modules, "openseespy.opensees", None)
    mod = load_benchmark("opensees3d")
    res = mod.run_bench(tmp_path, True, quiet=True)
    assert res["rows"] == [] and res["status"] == "unavailable"
    assert 'pip install "nsdyn[opensees]"' in mod.report(res)


@pytest.mark.slow
@pytest.mark.skipif(not _has_opensees(), reason='openseespy not installed: "nsdyn[opensees]"')
def test_quick_run_fixed_base_agrees(tmp_path):
    """Fixed base: OpenSees' clamped frame (Newmark, dt 0.005, beta K on all members) and
    nsdyn's fixed rung (exact per step, the same beta K as modal ratios, 200 modes to 5.8 Hz)
    are the same linear model: peaks within 2 % (Newmark's period error at the highest
    modes that matter, (2 pi 5 Hz dt)^2 / 12 = 0.2 %, the modes dropped above 5.8 Hz)."""
    mod = load_benchmark("opensees3d")
    res = mod.run_bench(tmp_path, True, repeats=1, quiet=True)
    fixed = [r for r in res["rows"] if r["case"] == "fixed"]
    assert len(fixed) == 2
    for k in mod.PEAKS_FIXED:
        assert fixed[0][k] == pytest.approx(fixed[1][k], rel=0.02), k
    iso = [r for r in res["rows"] if r["case"] == "isolated"]
    assert iso[0]["wall_s"] > 0 and iso[1]["wall_s"] > 0
    with open(res["csv"]) as fh:
        assert len(list(csv.DictReader(fh))) == len(res["rows"])


def test_the_fixed_base_table_has_its_own_headers():
    # its seven differences printed under the isolated table's six headers (|u|, V, ...)
    mod = load_benchmark("opensees3d")
    iso = {"case": "isolated", "record_s": 2.0, "repeats": 1, "run": "nsdyn cb", "wall_s": 1.0,
           "time_ratio": 1.0, "peak_resultant_displacement_m": 0.007,
           "peak_base_shear_N": 2.6e6, "peak_roof_corner_displacement_m": 0.13,
           "peak_drift_corner_x": 3e-3, "peak_drift_corner_y": 2e-3}  # fmt: skip
    fix = {"case": "fixed", "run": "OpenSees fixed base", "wall_s": 40.0,
           **{f"d_{k}": 0.001 * j for j, k in enumerate(mod.PEAKS_FIXED)}}  # fmt: skip
    lines = mod.report({"rows": [iso, fix]}).splitlines()
    k = lines.index("fixed base (the same linear model; d = OpenSees / nsdyn - 1):")
    head, row = lines[k + 1], lines[k + 2]

    def ends(line):  # where each space-separated field ends
        return [m.end() for m in re.finditer(r"\S+", line)]

    # the seven differences, each under its own header (right-aligned, as the values are)
    assert ends(row)[-7:] == ends(head.replace("dCM ", "dCM_").replace("dcor ", "dcor_")
                                  .replace("V ", "V_"))[-7:]  # fmt: skip
    assert row.split()[-7:] == [f"+{0.1 * j:.2f}%" for j in range(7)]
    assert head.split()[-1] == "roof" and "V y" in head and "dCM x" in head
