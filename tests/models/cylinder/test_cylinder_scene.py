"""Cylinder scenes: checked input, ``run_scene`` end to end, ``nsdyn run --json``, the study.

Sources: the scene contract of ``nsdyn run`` (summary keys, NPZ/PNG written); the source
study's design values (k = 9814 N/m³, c = 103.6 N s/m³, seed 000 §4.4.3) read back from the
summary; the study's finding that uplift lowers the wall stresses (seed 000 §4.4.3: peak τ_max
of the unbonded model below the bonded one).
"""

from __future__ import annotations

import copy
import json
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

from nsdyn.models.cylinder.params import CylinderParams
from nsdyn.models.cylinder.scene import build, format_summary, run_scene
from nsdyn.models.cylinder.simulate import RTOL
from nsdyn.models.cylinder.study import compare_foundations
from nsdyn.models.scenefile import SceneError, read_toml

ROOT = Path(__file__).resolve().parents[3]
SCENE = ROOT / "examples" / "scenes" / "cylinder-uplift.toml"


@pytest.fixture
def cfg():
    return read_toml(SCENE)


@pytest.mark.parametrize(
    "table, key, value, match",
    [
        ("foundation", "k", 0.0, "foundation.k: expected a positive"),
        ("cylinder", "H", -4.0, "cylinder.H: expected a positive"),
        ("foundation", "case", "glued", "foundation.case: expected one of"),
        ("motion", "seeed", 3, "motion.seeed: unknown field; did you mean 'seed'"),
        ("solver", "method", "rk4", "solver.method"),
        ("foundation", "zeta", 10, r"foundation.zeta: expected a damping ratio in \[0, 1\)"),
        ("foundation", "k", 1.0, r"foundation.k: the static settlement .* exceeds the radius"),
        # a simulated earthquake's grid (tracebacks, or an array of 1e11 samples, before)
        ("motion", "dt", 50.0, r"motion.dt: expected a step of at most half the duration"),
        # the noise's ordinates every 0.05 s sampled at 0.1 s: a traceback naming dt_ord
        ("motion", "dt", 0.1, r"motion.dt: expected a step of at most the noise.s ordinate step"),
        ("motion", "duration", 1e9, r"motion.duration: 1e\+11 samples of 0.01 s exceed 1e\+07"),
        ("motion", "t_end", 1e9, r"motion.t_end: 1e\+11 samples of 0.01 s exceed 1e\+07"),
        # an end inside the first step ran one step unsaid
        ("motion", "t_end", 1e-12, r"motion.t_end: expected an end at least one step \(0.01 s\)"),
        # a peak of 1e30 m/s² ran (the targets of every scene end at 100 g)
        ("motion", "pga", 1e30, r"motion.pga: expected a finite PGA from 0 to 1000 m/s²"),
    ],
)
def test_bad_input_names_the_field(cfg, table, key, value, match):
    bad = copy.deepcopy(cfg)
    if table == "foundation" and key == "k":
        for k in ("f_rock", "zeta"):
            bad["foundation"].pop(k)
    bad.setdefault(table, {})[key] = value
    with pytest.raises(SceneError, match=match) as e:
        build(bad, str(SCENE))
    assert str(SCENE) in str(e.value)


def test_a_bonded_base_rim_is_said_to_rise_not_to_lift(cfg, tmp_path):
    # a bonded base holds the rim down in tension: no lift-off (uplift ratio 0), yet its
    # table read "max rim lift" for the springs' stretch w + r sin(theta)
    cfg["motion"]["t_end"] = 2.0
    cfg["foundation"]["case"] = "bonded"
    s = run_scene(cfg, source=str(SCENE), out_dir=tmp_path, figures=False, quiet=True)
    assert s["max_uplift_ratio"] == 0.0 and s["max_rim_lift"] > 0
    assert "max rim rise [m]" in format_summary(s)
    assert "rim lift" not in format_summary(s)


def test_run_scene_end_to_end(cfg, tmp_path):
    cfg["motion"]["t_end"] = 4.0
    s = run_scene(cfg, source=str(SCENE), out_dir=tmp_path, figures=True, quiet=True)
    assert s["kind"] == "cylinder" and s["wall_s"] >= 0 and s["compile_s"] >= 0
    assert s["k"] == pytest.approx(9814.0, abs=0.5) and s["c"] == pytest.approx(103.6, abs=0.05)
    assert s["t_end"] == pytest.approx(4.0)
    assert Path(s["histories"]).is_file() and Path(s["figure"]).is_file()
    assert s["energy_error"] < 20 * RTOL  # the balance's quadratures follow the steps' rtol
    json.dumps(s)
    assert "max tilt" in format_summary(s)
    # every file written is listed, as the other scene kinds list theirs
    assert s["files"] == [s["histories"], s["figure"]]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(Path(f).name for f in s["files"])
    assert all(f"  file                     {f}" in format_summary(s) for f in s["files"])


def test_an_end_between_samples_is_said(cfg, tmp_path):
    # the run steps on the motion's 0.01 s grid: t_end = 0.015 s ended at 0.01 s unsaid
    cfg["motion"]["t_end"] = 0.015
    s = run_scene(cfg, source=str(SCENE), out_dir=tmp_path, figures=False, quiet=True)
    assert s["t_end"] == pytest.approx(0.01, rel=1e-12)
    assert any("t_end = 0.015 s falls between the motion's samples" in n for n in s["notes"])


def test_cli_run_json(tmp_path, capsys):
    from nsdyn.cli import main

    rc = main(["run", str(SCENE), "--json", "--out", str(tmp_path), "--t-end", "2"])
    assert rc in (0, None)
    s = json.loads(capsys.readouterr().out)
    assert s["kind"] == "cylinder" and s["t_end"] == pytest.approx(2.0)


def test_comparison_over_earthquakes_with_any_executor():
    """Thread pool as the executor; uplift lowers the median peak shear stress (seed 000)."""
    with ThreadPoolExecutor(2) as ex:
        out = compare_foundations(4, CylinderParams(), executor=ex, duration=12.0, batch=2)
    st = out["stats"]
    assert set(st) == {"tensionless", "bonded", "fixed"} and st["bonded"]["n"] == 4
    assert st["bonded"]["uplift"]["p95"] == 0.0 and st["tensionless"]["uplift"]["median"] > 0.5
    assert st["tensionless"]["tau_max"]["median"] < st["bonded"]["tau_max"]["median"]
    assert st["tensionless"]["tilt"]["median"] > 5 * st["bonded"]["tilt"]["median"]


def test_example_reproduces_source_design_and_ordering():
    """examples/cylinder_uplift.py: k, c of seed 000 §4.4.3; uplift only when tensionless."""
    import sys

    sys.path.insert(0, str(ROOT / "examples"))
    from cylinder_uplift import main

    r = main(seed=2, duration=10.0)
    assert r["k"] == pytest.approx(9814.0, abs=0.5) and r["c"] == pytest.approx(103.6, abs=0.05)
    assert r["M_u"] == pytest.approx(9.81 / 4, rel=1e-12)  # mgr/4
    assert r["bonded"]["uplift"] == 0.0 and r["tensionless"]["uplift"] > 0.5
    assert r["tensionless"]["tau_max"] < r["bonded"]["tau_max"]


def test_a_record_s_t_end_is_on_its_own_clock(tmp_path):
    # a record from 10 s to 15 s cut at t_end = 12 s runs its first 2 s, as every family's
    # t_end (GroundMotion.until); beyond its end is refused naming the field
    import numpy as np

    t = 10.0 + 0.01 * np.arange(501)
    rec = tmp_path / "late.txt"
    rec.write_text("# units: m/s2\n" + "\n".join(f"{a:.2f} {0.5 * np.sin(6 * a):.6e}" for a in t))
    base = {"scene": {"kind": "cylinder"}, "cylinder": {"r": 1.0, "H": 4.0, "m": 1.0},
            "motion": {"record": str(rec), "t_end": 12.0}}  # fmt: skip
    p, dt, ag, _ = build(base, "c.toml")
    assert dt == 0.01 and len(ag) == 201  # 10.00 ... 12.00
    # and its outputs are on that clock (they read 0 ... 2 s, and a summary's t_end 2)
    s = run_scene(base, source="c.toml", out_dir=tmp_path, figures=False, quiet=True)
    assert s["t_end"] == pytest.approx(12.0, abs=1e-9)
    with np.load(next(tmp_path.glob("*.npz"))) as z:
        assert z["t"][0] == pytest.approx(10.0, abs=1e-12)
        assert z["t"][-1] == pytest.approx(s["t_end"], abs=1e-9)  # (t0 + dt·n, to round-off)
    # past the record's end (15 s) the ground is at rest: the run goes on, and says so
    base["motion"]["t_end"] = 16.0
    _, dt, ag, opts = build(base, "c.toml")
    assert len(ag) == 601 and not ag[501:].any() and ag[:501].any()  # 10.00 ... 16.00
    assert opts["notes"] == ["t_end = 16 s is past the record's end (15 s): the ground is at "
                             "rest after it, the last 1 s are free motion"]  # fmt: skip


def test_pga_zero_is_free_rocking(cfg, tmp_path):
    # the ground at rest (pga = 0) and no damping: the cylinder rocks from theta0 and never
    # leans further (energy conservation), and the balance closes against the rocking's
    # kinetic energy (the ground does no work: the old scale read 1e4)
    cfg["motion"].update(pga=0.0, t_end=4.0, theta0=0.01)
    cfg["foundation"]["zeta"] = 0.0
    s = run_scene(cfg, source=str(SCENE), out_dir=tmp_path, figures=False, quiet=True)
    assert s["pga_hor"] == 0.0
    assert s["max_tilt"] == pytest.approx(0.01, rel=1e-6)
    # what is left of the balance is the integration's error: it falls with the tolerance
    # (10x tighter, at least 5x smaller)
    cfg["solver"] = {**cfg.get("solver", {}), "rtol": RTOL / 10}
    tight = run_scene(cfg, source=str(SCENE), out_dir=tmp_path, figures=False, quiet=True)
    assert 0.0 < tight["energy_error"] < s["energy_error"] / 5


@pytest.mark.parametrize("key, val", [("seed", 3), ("duration", 10.0)])
def test_a_record_refuses_the_simulated_earthquakes_keys(key, val):
    # they were dropped without a word (a study over seeds of a record ran one case N times)
    cfg = {"scene": {"kind": "cylinder"}, "motion": {"record": "synthetic-wn-40s", key: val}}
    with pytest.raises(SceneError, match=rf"c\.toml: motion\.{key}: a key of the simulated "):
        build(cfg, "c.toml")


def test_a_records_dt_is_its_sample_step_checked_against_its_time_column():
    # beside a record, dt is a one-column file's sample step (as in every family); a file
    # with a time column (the bundled record's 0.01 s) takes only its own
    cfg = {"scene": {"kind": "cylinder"},
           "motion": {"record": "synthetic-wn-40s", "dt": 0.01, "t_end": 0.5}}  # fmt: skip
    assert build(cfg, "c.toml")[1] == 0.01
    cfg["motion"]["dt"] = 0.02
    with pytest.raises(SceneError, match=r"c\.toml: motion\.record: .*dt = 0\.02 s \(given\) but "
                       r"the time column has 0\.01 s"):  # fmt: skip
        build(cfg, "c.toml")
    # a record's dt is no simulated earthquake's: --record keeps the scene's t_end (it was
    # dropped with a note calling it the closed-form motion's)
    from nsdyn.models.cylinder.scene import RECORD_REPLACES
    from nsdyn.models.scenefile import record_replaces_motion

    mo = {"record": "one.txt", "dt": 0.01, "t_end": 1.0}
    assert record_replaces_motion("cylinder", mo, RECORD_REPLACES, "c.toml") is None
    assert mo == {"record": "one.txt", "t_end": 1.0}
    simulated = {"seed": 3, "t_end": 1.0}  # (the closed form's t_end goes, said)
    assert record_replaces_motion("cylinder", simulated, RECORD_REPLACES, "c.toml")
    assert "t_end" not in simulated


def test_nsdyn_run_record_replaces_the_simulated_earthquake(tmp_path, capsys):
    # --record on a scene of a simulated earthquake (seed, duration, dt): the record runs
    from nsdyn.cli import main

    argv = ["run", str(SCENE), "--record", "synthetic-wn-40s", "--t-end", "1", "--json",
            "--no-figures", "--out", str(tmp_path)]  # fmt: skip
    assert main(argv) == 0
    s = json.loads(capsys.readouterr().out)

    from nsdyn.ground import read_motion3

    rec = read_motion3("synthetic-wn-40s").window(0.0, 1.0)  # its own peak, both components
    assert s["t_end"] == pytest.approx(1.0)
    assert s["pga_hor"] == max(abs(rec.ax).max(), abs(rec.ay).max())


def test_a_three_component_file_is_the_same_record_as_its_three_files(tmp_path):
    # nsdyn's three-column CSV (or a bundled record with a second component) gives the
    # cylinder both horizontals and the vertical: its a_y was dropped without a word. The
    # same components as three files (record, record_y, record_z) give the same input
    import numpy as np

    from nsdyn.ground import GroundMotion, read_motion3, write_motion, write_motion3

    m3 = read_motion3("synthetic-wn-40s").window(0.0, 2.0)
    write_motion3(m3, tmp_path / "r3.csv")
    for c, a in (("x", m3.ax), ("y", m3.ay), ("z", m3.az)):
        write_motion(GroundMotion(m3.t0, m3.dt, a, name=c), tmp_path / f"{c}.csv")
    one = {"scene": {"kind": "cylinder"}, "motion": {"record": str(tmp_path / "r3.csv")}}
    three = {"scene": {"kind": "cylinder"}, "motion": {
        "record": str(tmp_path / "x.csv"), "record_y": str(tmp_path / "y.csv"),
        "record_z": str(tmp_path / "z.csv")}}  # fmt: skip
    _, dt1, ag1, _ = build(one, "c.toml")
    _, dt3, ag3, _ = build(three, "c.toml")
    assert dt1 == dt3 and np.array_equal(ag1, ag3)
    np.testing.assert_array_equal(ag1, np.column_stack([m3.ax, m3.ay, m3.az]))


def test_a_fixed_base_names_no_foundation_springs():
    # case = "fixed" has no springs or dashpots: the header printed the design k and c it
    # does not use
    from nsdyn.models.cylinder.scene import foundation_text

    assert "k =" not in foundation_text("fixed", 9814.0, 103.6)
    assert foundation_text("tensionless", 9814.0, 103.6) == (
        "tensionless, k = 9814 N/m³, c = 103.6 N s/m³"
    )


def test_a_tilted_start_is_placed_on_the_foundation():
    # Released from 0.9 alpha with the ground at rest, the cylinder started at the upright
    # settlement with its axis tilted: the downhill rim 0.2 m into the springs, 131 J stored
    # for a 1 kg body (39 J upright), and it was thrown 1.1 m into the air. Placed on the
    # foundation, the foundation carries the weight at t = 0 (static_moment_tilt's root,
    # brentq to 1e-15 r), and energy conservation with no damping bounds the centre of mass:
    # m g z_G(t) <= E(0) = m g z_G(0) + V(0) (kinetic and spring energies are >= 0).
    import math

    from nsdyn.models.cylinder.foundation import resultants, static_moment_tilt
    from nsdyn.models.cylinder.params import CylinderParams
    from nsdyn.models.cylinder.simulate import simulate

    p = CylinderParams(c=0.0)
    th0 = 0.9 * math.atan2(p.r, p.H)
    r = simulate(p, np.zeros((301, 3)), 0.01, theta0=th0)
    w0 = static_moment_tilt(p, np.array([th0]))[1][0]
    assert r.w[0] == w0 and r.F[0] == pytest.approx(p.m * p.g, rel=1e-9)
    V0 = resultants(w0, (math.sin(th0), 0.0), r=p.r, k=p.k)["V"]
    z_g = r.w + p.H * np.cos(r.tilt)
    bound = w0 + p.H * math.cos(th0) + V0 / (p.m * p.g)
    assert z_g.max() <= bound + 1e-6 * p.H  # (the integration's error, rtol 1e-8 of H)
    assert r.tilt.max() <= th0 * (1 + 1e-6)  # it leans no further than released


@pytest.mark.parametrize(
    ("edit", "match"),
    [
        # past the 45° criterion a run "toppled at t = 0" with a 3540 N base shear
        ({"motion": {"pga": 0.0, "theta0": 1.0}}, r"motion.theta0: a tilt of 1 rad is at or past"),
        ({"motion": {"pga": 0.0, "theta0_over_alpha": 3.5}}, r"motion.theta0_over_alpha: a tilt"),
        # a second component without the first: the simulated earthquake ran instead
        ({"motion": {"record_y": "nonexistent.txt"}}, r"motion.record_y: a second record"),
        ({"motion": {"record_z": "nonexistent.txt"}}, r"motion.record_z: a second record"),
    ],
)
def test_inputs_a_cylinder_run_dropped_are_refused(edit, match):
    cfg = {"scene": {"kind": "cylinder"}, **copy.deepcopy(edit)}
    with pytest.raises(SceneError, match=match):
        build(cfg, "s.toml")


def test_a_missing_second_component_is_named_by_its_own_field(tmp_path):
    # it read "s.toml: motion.record: s.toml: motion.record_y: 'nope.csv' is neither ..."
    x = tmp_path / "x.csv"
    x.write_text("t,a\n0,0\n0.01,1\n0.02,0\n")
    cfg = {"scene": {"kind": "cylinder"}, "motion": {"record": str(x), "record_y": "nope.csv"}}
    with pytest.raises(SceneError, match=r"^s.toml: motion.record_y: 'nope.csv' is neither"):
        build(cfg, "s.toml")


def test_the_motion_run_is_named_when_the_scene_gives_none():
    # without [motion] the run drove the cylinder with simulated earthquake 0 and never said so
    opts = build({"scene": {"kind": "cylinder"}}, "s.toml")[3]
    assert opts["what"] == "simulated earthquake (motion.seed 0, 20 s)"
    opts = build({"scene": {"kind": "cylinder"}, "motion": {"seed": 3, "pga": 2.0}}, "s.toml")[3]
    assert opts["what"] == "simulated earthquake (motion.seed 3, 20 s), scaled to PGA 2 m/s²"


def test_springs_on_a_fixed_base_are_noted_as_unused():
    # they were dropped without a word (refused they would stop a study whose
    # foundation.case runs over "tensionless", "bonded" and "fixed" on one designed base)
    cfg = {"scene": {"kind": "cylinder"}, "foundation": {"case": "fixed", "k": 9814.0, "c": 1.0}}
    notes = build(cfg, "s.toml")[3]["notes"]
    assert notes == ["foundation.k, foundation.c not used: a fixed base (rigid ground) has no "
                     "springs or dashpots"]  # fmt: skip
    cfg["foundation"]["case"] = "tensionless"
    assert build(cfg, "s.toml")[3]["notes"] == []


def test_a_cylinder_api_start_past_the_criterion_or_tilted_on_a_fixed_base_is_refused():
    from nsdyn.models.cylinder.params import CylinderParams
    from nsdyn.models.cylinder.simulate import THETA_TOPPLE, simulate

    ag = np.zeros((11, 3))
    with pytest.raises(ValueError, match=r"^theta0: a tilt of 0.7854 rad is at or past"):
        simulate(CylinderParams(), ag, 0.01, theta0=-THETA_TOPPLE)
    with pytest.raises(ValueError, match=r"^theta0, w0, omega0: a fixed base holds"):
        simulate(CylinderParams(foundation="fixed"), ag, 0.01, theta0=0.1)


@pytest.mark.filterwarnings("ignore:.*does not state its units")
def test_components_sampled_differently_are_named(tmp_path):
    x, y = tmp_path / "x.csv", tmp_path / "y.csv"
    x.write_text("t,a\n" + "".join(f"{0.01 * i:.2f},0.1\n" for i in range(20)))
    y.write_text("t,a\n" + "".join(f"{0.02 * i:.2f},0.1\n" for i in range(20)))
    cfg = {"scene": {"kind": "cylinder"}, "motion": {"record": str(x), "record_y": str(y)}}
    with pytest.raises(SceneError, match=r"motion.record_y: sampled every 0.02 s, motion.record "
                                         r"every 0.01 s"):  # fmt: skip
        build(cfg, "s.toml")
