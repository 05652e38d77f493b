"""Rocking scenes: bad input names file and field; run_scene and the CLI end to end; examples."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from nsdyn.models.rocking.scene import build_model, build_motion, run_scene
from nsdyn.models.scenefile import SceneError, read_toml

ROOT = Path(__file__).resolve().parents[3]
SCENES = sorted((ROOT / "examples" / "scenes").glob("rocking-*.toml"))


def _cfg(**block):
    return {"scene": {"kind": "rocking"}, "block": {"width": 0.3, "height": 1.2, **block}}


@pytest.mark.parametrize(
    "cfg, field",
    [
        (_cfg(width=-0.3), "block.width"),
        (_cfg(r=1.2), "block.r"),
        (_cfg(r=-0.1), "block.r"),
        (_cfg(heigth=1.0), "block.heigth"),
        (_cfg(gamma=5.0), "block.gamma: the beam-to-columns mass ratio of a rocking frame"),
        ({"scene": {"kind": "rocking", "model": "compliant"},  # sinks 8e11 m under its weight
          "block": {"width": 0.3, "height": 1.2, "omega_v_over_p": 1e-6}},
         "block.omega_v_over_p: the corners' static settlement"),
        ({"scene": {"kind": "rocking", "model": "tower"}, "block": {"width": 1, "height": 2}},
         "scene.model"),
        ({"block": {"width": 1, "height": 2}, "motion": {"pulse": "square", "a_p_g": 1,
          "omega_p": 1}}, "motion.pulse"),
        ({"block": {"width": 1, "height": 2}, "motion": {"pulse": "sine", "a_p_g": 1,
          "omega_p": 10, "t_start": 5.0, "t_end": 3.0}}, "motion.t_start: the pulse starts"),
        # keys the scene's other choices leave unused are refused, not dropped
        ({"block": {"width": 1, "height": 2}, "motion": {"record": "synthetic-wn-40s",
          "pulse": "sine", "a_p_g": 0.4, "omega_p": 10}}, "motion.pulse: a pulse's key beside"),
        ({"block": {"width": 1, "height": 2}, "motion": {"record": "synthetic-wn-40s",
          "omega_p": 10}}, "motion.omega_p: a pulse's key beside motion.record"),
        ({"block": {"width": 1, "height": 2}, "motion": {"a_p_g": 0.4}},
         "motion.a_p_g: a pulse's key without motion.pulse"),
        # a pulse of 1e6 g ran (every scene's amplitudes end at 100 g = 1000 m/s²)
        ({"block": {"width": 1, "height": 2}, "motion": {"pulse": "sine", "a_p_g": -1e6,
          "omega_p": 10}}, "motion.a_p_g: expected a pulse amplitude up to 1000 m/s² (100 g), "
                           "got -1e+06 g"),
        ({"block": {"width": 1, "height": 2}, "motion": {"pulse": "sine", "a_p": 0.4,
          "pga": 1001.0, "omega_p": 10}}, "motion.pga: expected a pulse amplitude up to 1000"),
        (_cfg(omega_v_over_p=300.0), "block.omega_v_over_p: a key of the compliant model"),
        ({"scene": {"kind": "rocking", "model": "frame"}, "block": {"width": 1, "height": 2,
          "zeta": 2.0}}, "block.zeta: a key of the compliant model (scene.model = 'compliant'), "
                         "not of a frame"),
        # a frame without its beam ran the bare column, saying "model frame"
        ({"scene": {"kind": "rocking", "model": "frame"}, "block": {"width": 1, "height": 2}},
         "block.gamma: missing; expected the frame's beam-to-columns mass ratio"),
    ],
)  # fmt: skip
def test_bad_scene_input_raises_scene_error_naming_file_and_field(cfg, field):
    with pytest.raises(SceneError) as e:
        build_model(cfg, "bad.toml")
        build_motion(cfg, "bad.toml")
    msg = str(e.value)
    assert "bad.toml" in msg and field in msg


@pytest.mark.parametrize("model", ["block", "compliant"])
def test_a_pulse_too_fast_is_refused_in_its_own_unit_before_the_run_starts(model, capsys):
    # p = sqrt(3 g / 4 R), R = sqrt(0.2² + 1²) = 1.0198 m: p = 2.6856 /s; f_p = 1e6 Hz is
    # 2 pi 1e6 / p = 2.3392e6 p, past the 1000 p a run resolves (it stepped for minutes)
    block = {"width": 0.4, "height": 2.0, **({"omega_v_over_p": 100.0} if model != "block" else {})}
    cfg = {"scene": {"kind": "rocking", "model": model}, "block": block,
           "motion": {"pulse": "sine", "a_p": 5.0, "f_p": 1.0e6}}  # fmt: skip
    with pytest.raises(
        SceneError, match=r"s\.toml: motion\.f_p: a frequency of 1e\+06 Hz, 2\.3392"
    ):
        run_scene(cfg, source="s.toml", out_dir=Path("unused"), figures=False, quiet=False)
    assert "rocking:" not in capsys.readouterr().err  # refused before the run says it starts


def test_a_pulse_given_by_its_pga_is_the_pulse_of_that_amplitude():
    # motion.pga is the pulse's peak [m/s²]: alone it gives the amplitude, beside a_p_g it
    # replaces it (as nsdyn run --pga does), keeping its sign
    base = {"pulse": "sine", "omega_p": 10.0}
    by_pga, _, _, _ = build_motion({"motion": {**base, "pga": 3.0}}, "p.toml")
    by_ap, _, _, _ = build_motion({"motion": {**base, "a_p": 3.0}}, "p.toml")
    over, _, _, what = build_motion({"motion": {**base, "a_p": -1.0, "pga": 3.0}}, "p.toml")
    assert by_pga == by_ap and over.a_p == -3.0
    assert what == "sine pulse (its amplitude motion.pga, in place of a_p = -1 m/s²)"  # (said)


def test_a_scene_output_step_is_refused_in_one_form(tmp_path):
    # 0 was refused as "expected a positive number" and a step past the run's end as "...,
    # or 0 for no output": a scene has no "no output"
    for dt_out in (0.0, 100.0):
        cfg = {**_cfg(), "motion": {"theta0_over_alpha": 0.5, "t_end": 3.0},
               "solver": {"dt_out": dt_out}}  # fmt: skip
        with pytest.raises(SceneError, match=r"^s.toml: solver.dt_out: expected a positive ") as e:
            run_scene(cfg, source="s.toml", out_dir=tmp_path, figures=False, quiet=True)
        assert "0 for no output" not in str(e.value)


def test_unknown_field_suggests_the_nearest():
    with pytest.raises(SceneError, match="did you mean 'height'"):
        build_model(_cfg(heigth=1.0), "x.toml")


@pytest.mark.parametrize("path", SCENES, ids=lambda p: p.stem)
def test_run_scene_end_to_end(path, tmp_path):
    cfg = read_toml(path)
    cfg.setdefault("motion", {})["t_end"] = 2.0
    s = run_scene(cfg, source=str(path), out_dir=tmp_path, figures=True, quiet=True)
    assert s["kind"] == "rocking" and s["wall_s"] >= 0 and s["compile_s"] >= 0
    json.dumps(s)
    data = np.load(tmp_path / "rocking.npz")
    assert data["t"][-1] == pytest.approx(2.0)
    assert (tmp_path / "rocking.png").stat().st_size > 1000


def test_cli_run_json(tmp_path, capsys):
    from nsdyn.cli import main

    scene = ROOT / "examples" / "scenes" / "rocking-seed003-column.toml"
    rc = main(["run", str(scene), "--json", "--out", str(tmp_path), "--t-end", "3"])
    assert rc in (0, None)
    s = json.loads(capsys.readouterr().out)
    for key in ("max_theta_over_alpha", "overturned", "t_overturn_s", "n_impacts", "kind"):
        assert key in s
    # seed 003 Table 2 column 2: Housner r = 0.91 (printed to two decimals)
    assert s["r"] == pytest.approx(0.91, abs=0.005)


def test_an_overturned_runs_end_time_is_its_overturn(tmp_path):
    # the run stops where the block overturns: its end time is that instant (it read the
    # scene's t_end, 6 s, beside histories that end at 0.44 s)
    cfg = {**_cfg(), "motion": {"pulse": "sine", "a_p_g": 3.0, "omega_p": 4 * np.pi, "t_end": 6.0}}
    s = run_scene(cfg, source="s.toml", out_dir=tmp_path, figures=False, quiet=True)
    t = np.load(tmp_path / "rocking.npz")["t"]
    assert s["overturned"] and s["t_end_s"] == s["t_overturn_s"] < 6.0
    assert 0.0 <= s["t_end_s"] - t[-1] < np.diff(t).max()  # (its last output is before it)


def test_a_block_released_on_its_corner_is_said_balanced_not_rocking(tmp_path):
    # at theta = alpha the centre of mass is over the corner: gravity's moment
    # m g R sin(alpha - theta) is zero, the unstable equilibrium, held by the exact start (it
    # read "rocking (lifted off, still rocking at the end)" with no impact); a hair below it
    # rocks (one impact within the run)
    from nsdyn.models.rocking.scene import outcome

    def run(th):
        motion = {"theta0_over_alpha": th, "t_end": 3.0}
        cfg = {**_cfg(), "motion": motion}
        return run_scene(cfg, source="s.toml", out_dir=tmp_path, figures=False, quiet=True)

    s = run(1.0)
    assert s["n_impacts"] == 0 and outcome(s)[1].startswith("balanced on its corner")
    s = run(0.999)
    assert s["n_impacts"] >= 1 and outcome(s)[1].startswith("rocking (lifted off")


def test_a_block_past_its_corner_at_the_end_is_said_to_lean_past_it(tmp_path):
    # released a hair past alpha with the ground at rest, gravity's moment turns it away from
    # upright for good: at an end before it overturns its tilt is past alpha and growing
    # (it read "rocking (lifted off, still rocking at the end)")
    from nsdyn.models.rocking.scene import outcome

    cfg = {**_cfg(), "motion": {"theta0_over_alpha": 1.01, "t_end": 0.5}}
    s = run_scene(cfg, source="s.toml", out_dir=tmp_path, figures=False, quiet=True)
    assert not s["overturned"] and s["final_theta_rad"] > 1.01 * s["alpha_rad"]
    assert outcome(s)[1].startswith("LEANING PAST ITS TIP-OVER ANGLE at the end: theta")


def test_example_seed_studies_free_rocking_restitution():
    """examples/rocking_seed_studies.py: seed 003 Table 1 analytic restitution 0.91 of the
    2H = 1.2 m, 2B = 0.3 m column is what the impacts of the run show (theta'+ / theta'-)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "rss", ROOT / "examples" / "rocking_seed_studies.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    out = mod.main(quick=True)
    assert out["seed003_table1_r"] == pytest.approx(0.91, abs=0.005)
    assert out["seed001_housner_r"] == pytest.approx(0.700, abs=0.0005)


def test_a_negative_pulse_is_described_with_its_sign():
    # a_p_g = -0.4 ran mirrored (as it should) but was printed "a_p = 3.92 m/s²"
    from nsdyn.models.rocking.scene import excitation_text

    exc = build_motion({"motion": {"pulse": "sine", "a_p_g": -0.4, "omega_p": 12.0}}, "p.toml")[0]
    assert excitation_text(exc, "sine pulse") == "sine pulse, a_p = -3.92 m/s² (-0.4 g)"


def test_a_compliant_contact_beyond_the_step_budget_is_refused_at_once(tmp_path, capsys):
    # at omega_v/p = 1e9 the warm-up run (1 ms of the scene's own block) spent the step budget
    # and the run failed as numerics (exit 3, after 7 s); the run's check refuses it (exit 2)
    from nsdyn.cli import main

    scene = tmp_path / "stiff.toml"
    scene.write_text('[scene]\nkind = "rocking"\nmodel = "compliant"\n[block]\nwidth = 2.0\n'
                     'height = 4.0\nomega_v_over_p = 1e9\n[motion]\ntheta0_over_alpha = 0.5\n'
                     't_end = 2.0\n')  # fmt: skip
    assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "o")]) == 2
    assert "block.omega_v_over_p: a contact of 1.81e+09 rad/s damped at zeta = " in (
        capsys.readouterr().err
    )


def test_a_tolerance_that_does_not_resolve_the_rocking_is_said(tmp_path):
    # a 2 x 4 m block (r 0.82) under eight cycles of a 0.81 Hz sine pulse of 1 g passes its
    # tip-over angle and comes back. Its peak converges with the tolerance (1e-9 against
    # 1e-12, within the check's bound); at 1e-4 the run peaked ten bounds higher, said like
    # any other. The scene's repeat at 1e-3 x tol now says it, and at 1e-9 finds nothing
    from nsdyn.models.rocking.scene import TOL_CHECK_ABS

    cfg = {"scene": {"kind": "rocking", "model": "block"},
           "block": {"width": 2.0, "height": 4.0, "mass": 124800.0, "r": 0.82},
           "motion": {"pulse": "sine", "a_p_g": 1.0, "f_p": 0.81, "n_cycles": 8,
                      "t_end": 12.0}}  # fmt: skip

    def run(tol):
        return run_scene({**cfg, "solver": {"tol": tol}}, source="r.toml", out_dir=tmp_path,
                         figures=False, quiet=True)  # fmt: skip

    fine, finer = run(1e-9), run(1e-12)
    peak = finer["max_theta_over_alpha"]
    assert abs(fine["max_theta_over_alpha"] - peak) < TOL_CHECK_ABS and peak > 1.0  # (past α)
    assert fine["tol_resolved"] is True and "notes" not in fine
    loose = run(1e-4)
    assert loose["tol_resolved"] is False
    assert loose["max_theta_over_alpha"] - peak > 10 * TOL_CHECK_ABS
    assert abs(loose["tol_check_peak_over_alpha"] - peak) < TOL_CHECK_ABS
    assert loose["notes"][-1].startswith("solver.tol = 0.0001 does not resolve this response")


def test_a_compliant_block_that_leaves_the_ground_says_so(tmp_path):
    # a vertical pulse of 1.5 g pulls the ground away faster than gravity: both corners rise
    # off it (the lower 0.27 m), which the rigid block refuses ("free flight is not
    # modelled") and the compliant one did without a word ("standing"). Below the rocking
    # threshold g tan(alpha) = g/2 and without a vertical no corner can leave: no flight, no
    # note. A flight is checked against the geometry: both corners above the ground
    from nsdyn.models.rocking.compliant import CompliantBlock, simulate_compliant
    from nsdyn.models.rocking.scene import build_model, build_motion

    cfg = {"scene": {"kind": "rocking", "model": "compliant"},
           "block": {"width": 2.0, "height": 4.0, "mass": 124800.0, "omega_v_over_p": 300.0,
                     "zeta": 2.0},
           "motion": {"pulse": "sine", "a_p_g": 1.0, "f_p": 0.81, "n_cycles": 8,
                      "ver_ratio": 1.5, "t_end": 2.0}}  # fmt: skip
    s = run_scene(cfg, source="s.toml", out_dir=tmp_path, figures=False, quiet=True)
    assert s["n_flights"] > 0 and s["max_flight_height_m"] > 0
    assert any(n.startswith("the block left the ground") for n in s.get("notes", []))
    model, exc = build_model(cfg, "s.toml"), build_motion(cfg, "s.toml")[0]
    assert isinstance(model, CompliantBlock)
    r = simulate_compliant(model, exc, t_end=2.0)
    k = int(np.searchsorted(r.t, s["t_first_flight_s"]))
    y, phi = r.y[k, 1], r.y[k, 2]
    for sj in (-1.0, 1.0):  # each bottom corner's height: y + R(phi) (sj B, -H)
        assert y + np.sin(phi) * sj * model.B - np.cos(phi) * model.H > 0.0
    cfg["motion"].update(ver_ratio=0.0, a_p_g=0.4)  # (0.4 g < g B/H: no rocking)
    s = run_scene(cfg, source="s.toml", out_dir=tmp_path, figures=False, quiet=True)
    assert s["n_flights"] == 0 and not any(n.startswith("the block left")
                                           for n in s.get("notes", []))  # fmt: skip
