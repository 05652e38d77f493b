"""Studies of 3D buildings on the cb and full rungs: the outputs of each run and the kernels
compiled once before the workers start.

Reference: symmetry. A square one-storey portal (square columns, equal beams, the floor's
centre of mass at the plan centre) on four equal friction pendulums maps onto itself under a
quarter turn about the vertical; its Craig–Bampton model keeps that symmetry when its cut-off
leaves no degenerate pair split and no participation filter thins the modes. Under the record
turned by 90° (a_x, a_y) -> (−a_y, a_x) the response is the quarter-turned response: the x
drift peaks are the y drift peaks of 0° and the resultant peaks are the same. The two
numerical solutions differ only through the integrator's error control (a componentwise
norm, not invariant under the rotation): each carries a global error of at most about
steps × rtol relative (local errors summed, the friction system dissipative), so the two
agree to 2 × steps × rtol.
"""

from __future__ import annotations

import numpy as np
import pytest

from nsdyn.studies import load_study, run_study
from nsdyn.studies.scenes3c import _pair_runs
from nsdyn.studies.tasks import Task, expand

RTOL = 1e-8
EPS = np.finfo(float).eps

SQUARE = """
[frame3d]
name = "square-portal"
kind = "explicit"
nodes = [
  [0.0, 0.0, 0.0], [6.0, 0.0, 0.0], [6.0, 6.0, 0.0], [0.0, 6.0, 0.0],
  [0.0, 0.0, 4.0], [6.0, 0.0, 4.0], [6.0, 6.0, 4.0], [0.0, 6.0, 4.0],
]
base_nodes = [0, 1, 2, 3]
zeta = [0.02]

[[frame3d.sections]]  # a square hollow column: I_y = I_z
E = 2.1e11
nu = 0.3
A = 0.0120
I_y = 1.5e-4
I_z = 1.5e-4
J = 2.3e-4
rho = 7850.0

[[frame3d.sections]]  # the beams
E = 2.1e11
nu = 0.3
A = 0.00845
I_y = 2.313e-4
I_z = 1.318e-5
J = 5.108e-7
rho = 7850.0

[[frame3d.members]]
section = 0
elements = [[0, 4], [1, 5], [2, 6], [3, 7]]
vecxz = [1.0, 0.0, 0.0]

[[frame3d.members]]
section = 1
elements = [[4, 5], [5, 6], [6, 7], [7, 4]]
vecxz = [0.0, 0.0, 1.0]

[[frame3d.diaphragms]]
nodes = [4, 5, 6, 7]
mass = 24000.0
centre = [3.0, 3.0]
inertia = 144000.0  # 24000 (6^2 + 6^2) / 12
"""

SCENE = f"""
[scene]
kind = "building3d"
[structure]
frame3d = "square.toml"
fidelity = "cb"
f_max = 30.0    # in the gap between the sway pair and torsion (4.0, 4.0, 6.9 Hz) and the
min_mass = 0.0  # next modes (61 Hz), none filtered: the model keeps the plan's symmetry
[bearing]
type = "fps"
radius = 2.2
mu = 0.05
[motion]
kind = "record3"
record = "synthetic-wn-40s"
pga = 3.0
t_end = 2.0
[solver]
law = "arctan"
eps = 200.0     # a smooth regularised law: a cheap run
rtol = {RTOL}
atol = 1e-12
"""

STUDY = """
[study]
name = "square"
scene = "scene.toml"
[parameters]
"motion.rotate" = [0.0, 90.0]
"""


@pytest.fixture
def study(tmp_path):
    (tmp_path / "square.toml").write_text(SQUARE)
    (tmp_path / "scene.toml").write_text(SCENE)
    (tmp_path / "study.toml").write_text(STUDY)
    return load_study(tmp_path / "study.toml")


def test_the_cb_rung_reports_its_outputs_and_the_quarter_turn_symmetry(study, tmp_path):
    res = run_study(study, tmp_path / "out", workers=1)
    rows = {r["motion.rotate"]: r for r in res.table.rows}
    assert all(r["status"] == "ok" for r in rows.values()), res.table.rows
    r0, r90 = rows[0.0], rows[90.0]
    assert r0["fidelity"] == "cb" and r0["path"] == "dense"
    assert r0["incident_angle_deg"] == 0.0 and r90["incident_angle_deg"] == 90.0
    assert r0["peak_resultant_displacement_m"] > 0.02  # the isolators slide
    tol = 2 * max(r0["n_steps"], r90["n_steps"]) * RTOL

    def same(a, b):
        assert a == pytest.approx(b, rel=tol), (a, b, tol)

    same(r90["peak_drift_cm_x"], r0["peak_drift_cm_y"])
    same(r90["peak_drift_cm_y"], r0["peak_drift_cm_x"])
    same(r90["peak_drift_corner_x"], r0["peak_drift_corner_y"])
    same(r90["peak_base_shear_x_N"], r0["peak_base_shear_y_N"])
    same(r90["peak_base_shear_N"], r0["peak_base_shear_N"])
    same(r90["peak_resultant_displacement_m"], r0["peak_resultant_displacement_m"])
    assert r0["peak_drift_cm_x"] != pytest.approx(r0["peak_drift_cm_y"], rel=1e-3)  # not trivial
    # rigid floor, centre of mass at the plan centre: its drift is the mean of two opposite
    # corners', so the corners' peak is at least the centre's (the maps' round-off: sums of
    # ~30 shapes, ≤ 30 eps relative; 1e3 eps allowed)
    for r in (r0, r90):
        for ax in "xy":
            assert r[f"peak_drift_corner_{ax}"] >= r[f"peak_drift_cm_{ax}"] * (1 - 1e3 * EPS)
        assert r["peak_corner_drift"] == max(r["peak_drift_corner_x"], r["peak_drift_corner_y"])


def test_the_parent_compiles_the_pair_kernels_of_the_tasks_path_and_law(study):
    tasks = expand(study)
    assert _pair_runs(tasks) == {("dense", "arctan", "detect")}
    # the office's full rung is above the dense limit: the sparse kernels, the regularised law
    cfg = {**tasks[0].cfg, "structure": {"frame3d": "office-11-3d", "fidelity": "full"},
           "solver": {}}  # fmt: skip
    office = Task(0, "k", "building3d", cfg, {}, source=tasks[0].source)
    assert _pair_runs([office]) == {("sparse", "arctan", "detect")}
    switch = Task(1, "k", "building3d", {**cfg, "structure": {**cfg["structure"],
                  "fidelity": "cb"}, "solver": {"law": "switch"}}, {})  # fmt: skip
    assert _pair_runs([switch]) == {("dense", "switch", "detect")}
    # unilateral contacts: the loop with located events and their landing
    uni = Task(2, "k", "building3d", {**switch.cfg, "solver": {"law": "arctan",
               "contact": "unilateral"}}, {})  # fmt: skip
    assert _pair_runs([uni]) == {("dense", "arctan", "unilateral")}


def test_a_task_on_the_sparse_path_takes_its_own_solver(tmp_path, monkeypatch):
    # the built system is kept per structure and bearing, the solver is each task's: a task's
    # step reaches the run, and a switch law is refused even when the system is already built
    from nsdyn.models.isolated import building3d_cb
    from nsdyn.models.scenefile import SceneError
    from nsdyn.studies import scenes3c

    monkeypatch.setattr(building3d_cb, "FULL_MAX", 0)  # the portal onto the sparse path
    monkeypatch.setattr(scenes3c, "_systems", {})  # (its systems kept only for this test)
    run_summary = scenes3c.run_summary
    cfg = {"scene": {"kind": "building3d"},
           "structure": {"frame3d": "portal-3d", "fidelity": "full"},
           "bearing": {"type": "fps", "radius": 2.2, "mu": 0.05},
           "motion": {"kind": "record3", "record": "synthetic-wn-40s", "t_end": 1.0, "pga": 2.0},
           "solver": {"law": "arctan", "eps": 200.0}}  # fmt: skip
    source = str(tmp_path / "s.toml")
    for dt in (2e-3, 1e-3):
        s = run_summary("building3d", {**cfg, "solver": {**cfg["solver"], "dt": dt}}, source)
        assert s["path"] == "sparse" and s["dt_s"] == dt and s["fidelity"] == "full"
        # the portal's floor centre is its plan centre: corners at least the centre (above)
        for ax in "xy":
            assert s[f"peak_drift_corner_{ax}"] >= s[f"peak_drift_cm_{ax}"] * (1 - 1e3 * EPS)
        assert s["peak_corner_drift"] > 0 and s["incident_angle_deg"] == 0.0
    with pytest.raises(SceneError, match=r"solver\.law: .*expected 'arctan', got 'switch'"):
        run_summary("building3d", {**cfg, "solver": {"law": "switch"}}, source)
