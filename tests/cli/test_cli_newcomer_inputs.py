"""More commands tried as a newcomer tries them: each mistake is refused in one line naming
the file and field and what is expected (exit 2), before anything runs or is written.

Source of the expected behaviour: the command-line conventions of nsdyn.cli.app (input errors
exit 2 with one line) and docs/reference/cli.md; the tolerance range from the adaptive step's
error test (a relative tolerance of 1 or more accepts any step: err <= rtol |y| + atol is met
by an error as large as the state itself).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from nsdyn.cli import main
from nsdyn.cli.app import build_parser

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "examples" / "scenes"


def _with_solver_field(src: Path, dst: Path, key: str, value) -> Path:
    """``src`` with ``[solver] key = value`` (the table added or the field replaced)."""
    lines = src.read_text().splitlines()
    lines = [ln for ln in lines if not ln.replace(" ", "").startswith(f"{key}=")]
    if "[solver]" not in lines:
        lines.append("[solver]")
    lines.insert(lines.index("[solver]") + 1, f"{key} = {value}")
    dst.write_text("\n".join(lines) + "\n")
    return dst


@pytest.mark.parametrize(
    "scene, key",
    [
        (None, "rtol"),  # the default isolated frame
        ("deck-fps4-3c.toml", "rtol"),
        ("building3d-office-cb.toml", "rtol"),
        ("contact-seed002-A5.toml", "rtol"),
        ("cylinder-uplift.toml", "rtol"),
        ("rocking-seed001-cask.toml", "tol"),
    ],
)
@pytest.mark.parametrize("value", [1, 2.5, 1e-300])
def test_a_relative_tolerance_outside_what_a_step_can_meet_is_refused(
    tmp_path, scene, key, value, one_line
):
    """From 1 on the error test passes any step; below 100x double precision's epsilon
    (2.2e-14) no step passes it, and the run would end in a step underflow blamed on the
    model (1e-300 with atol 1e-300 on the default scene: "(nearly) discontinuous")."""
    src = SCENES / scene if scene else tmp_path / "empty.toml"
    if scene is None:
        src.write_text("")
    bad = _with_solver_field(src, tmp_path / f"bad-{src.name}", key, value)
    out = tmp_path / "out"
    rc = main(["run", str(bad), "--out", str(out), "--no-figures"])
    assert rc == 2
    one_line(str(bad), f"solver.{key}", f"2.2e-14 <= solver.{key} < 1")
    assert not out.exists()


def test_the_library_refuses_the_same_tolerances():
    from nsdyn.models.isolated.scene import build_scene, load_scene
    from nsdyn.models.rocking.block import RockingBlock, simulate_rocking
    from nsdyn.solve.transient import simulate

    system, motion = build_scene(load_scene())
    with pytest.raises(ValueError, match="rtol: expected a relative tolerance 2.2e-14 <= rtol < 1"):
        simulate(system, motion, t_end=1.0, rtol=1.0)
    with pytest.raises(ValueError, match="tol: expected a relative tolerance 2.2e-14 <= tol < 1"):
        simulate_rocking(RockingBlock(width=0.5, height=2.0), None, t_end=1.0, tol=3.0)
    # atol 0 as a scene refuses it: a run from rest met no error test (rtol |x| = 0), and
    # failed as "the right-hand side is (nearly) discontinuous"
    with pytest.raises(ValueError, match=r"^atol: expected values > 0, got 0.0"):
        simulate(system, motion, t_end=1.0, atol=0.0)
    # the floor the messages print is the floor: 2.2e-14 itself was refused as "expected
    # 2.2e-14 <= rtol" (the floor was 100 x 2**-52 = 2.22e-14)
    from nsdyn._checks import rel_tol

    assert rel_tol("rtol", 2.2e-14) == 2.2e-14
    with pytest.raises(ValueError, match=r"expected a relative tolerance 2.2e-14 <= rtol < 1"):
        rel_tol("rtol", 2.19e-14)


def test_json_reports_usage_and_command_errors_too(capsys):
    """With --json every failure prints {"status", "error"} on stdout (docs/reference/cli.md):
    a flag argparse refuses, and a check a command makes itself (sweep's frequency range)."""
    import json

    with pytest.raises(SystemExit) as e:
        main(["run", "--pga", "-1", "--json"])
    assert e.value.code == 2
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == 2 and "--pga" in out["error"]
    assert main(["sweep", "--fmin", "2", "--fmax", "1", "--json"]) == 2
    out = json.loads(capsys.readouterr().out)
    assert out == {
        "status": 2,
        "error": "argument --fmax: expected a frequency above --fmin "
        "(2 Hz), got 1 (see nsdyn sweep --help)",
    }
    assert main(["uplift", "no-such-scene.toml", "--json"]) == 2
    assert json.loads(capsys.readouterr().out)["status"] == 2
    with pytest.raises(SystemExit):  # options are never abbreviated: --js is no --json
        main(["run", "--pga", "1", "--js"])
    out = capsys.readouterr()
    assert out.out == "" and "unrecognized arguments: --js; did you mean '--json'?" in out.err
    with pytest.raises(SystemExit):  # and nothing of it stays for the next command line
        build_parser("run").parse_args(["run", "--pga", "-1"])
    assert capsys.readouterr().out == ""


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux's /proc")
def test_an_out_that_cannot_be_made_is_refused_before_the_work(one_line):
    """/proc takes no new directory, whatever the permission bits say (also to root)."""
    with pytest.raises(SystemExit) as e:
        main(["uplift", "--out", "/proc/nsdyn-out", "--points", "2"])
    assert e.value.code == 2
    one_line("argument --out: cannot create '/proc/nsdyn-out'")


def _study(tmp_path: Path, keep: list[str], analysis: str = "") -> Path:
    p = tmp_path / "s.toml"
    keep_toml = "[" + ", ".join(f'"{k}"' for k in keep) + "]"
    p.write_text(
        f'[study]\nname = "s"\nkeep = {keep_toml}\n'
        "[base.motion]\npga = 3.0\nt_end = 1.0\n"
        '[parameters]\n"isolation.mu" = [0.02, 0.05]\n' + analysis
    )
    return p


def test_a_constraint_on_a_result_not_kept_says_to_keep_it(tmp_path, one_line):
    analysis = '[analysis.design]\nobjectives = ["idr_max"]\nconstraints = { x_iso_max_m = 0.4 }\n'
    study = _study(tmp_path, ["idr_max"], analysis)
    assert main(["study", str(study), "--out", str(tmp_path / "o")]) == 2
    one_line("'x_iso_max_m' is a result the study does not keep", "study.keep")


@pytest.mark.parametrize(
    "model, width, rocks", [("block", 1.41, True), ("block", 1.42, False), ("frame", 1.2, False)]
)
def test_a_block_too_squat_for_housner_restitution_is_refused(
    tmp_path, capsys, model, width, rocks, one_line
):
    """Housner's r = 1 - 1.5 sin² alpha (seed 003) is positive only for tan alpha =
    width/height < √2 = 1.41421...; beyond, the run would use a negative r. A rocking frame's
    r_f = (1 - 1.5 sin² alpha + 3 gamma cos 2 alpha)/(1 + 3 gamma) (seed 003) with gamma = 1
    is (1 - 1.5 sin² 50.2° + 3 cos 100.4°)/4 = -0.107 < 0 for width/height 1.2."""
    scene = tmp_path / "squat.toml"
    gamma = "gamma = 1.0\n" if model == "frame" else ""
    scene.write_text(
        f'[scene]\nkind = "rocking"\nmodel = "{model}"\n'
        f"[block]\nwidth = {width}\nheight = 1.0\n{gamma}"
        '[motion]\npulse = "sine"\na_p_g = 2.0\nf_p = 1.0\nt_end = 0.5\n'
    )
    rc = main(["run", str(scene), "--out", str(tmp_path / "o"), "--no-figures"])
    if rocks:
        assert rc == 0
        capsys.readouterr()
    else:
        assert rc == 2
        one_line(str(scene), "block.r:", "give r")


PORTAL_SECTIONS = """[[frame.sections]]
E = 2.1e11
A = 0.0149
I = 2.517e-4
rho_A = 117.0
[[frame.sections]]
E = 2.1e11
A = 0.00845
I = 2.313e-4
rho_A = 66.3
"""  # the bundled portal's columns and beams

OVERHANG = (
    """[frame]
name = "overhang"
kind = "explicit"
nodes = [[0.0, 0.0], [6.0, 0.0], [0.0, 2.0], [0.0, 4.0], [3.0, 4.0], [6.0, 4.0], [6.0, 2.0],
         [12.0, 4.0]]
elements = [[0, 2, 0], [2, 3, 0], [3, 4, 1], [4, 5, 1], [1, 6, 0], [6, 5, 0], [5, 7, 1]]
base_nodes = [0, 1]
node_mass = [0.0, 0.0, 0.0, 1000.0, 1000.0, 1000.0, 0.0, 9000.0]
zeta = [0.02]
"""
    + PORTAL_SECTIONS
)


def test_a_frame_that_cannot_stand_on_its_isolators_is_input_not_uplift(tmp_path, one_line):
    """A portal with a 9 t mass 6 m beyond its right foot: by statics (moments about the right
    foot, x = 6 m) the left isolator pulls, N_0 = -g Σ m_i (x_i - 6)/6 over the node masses
    and the members' own (columns 2 x 468 kg at x = 0 and 6, beams 397.8 kg at x = 3 and 9):
    -42 192 kg m / 6 m x g. With the default contact that is input (exit 2, naming the frame
    file), not an uplift at t = 0; a bilateral contact holds it down and is let through."""
    from nsdyn.ground.excitation import G_EARTH
    from nsdyn.models.isolated.scene import build_scene, load_scene

    frame = tmp_path / "overhang.toml"
    frame.write_text(OVERHANG)
    rc = main(["run", "--frame", str(frame), "--out", str(tmp_path / "o"), "--no-figures"])
    assert rc == 2
    err = one_line(str(frame), "under gravity alone", "cannot stand")
    n0 = float(err.split("is ")[1].split(" N")[0])
    assert n0 == pytest.approx(-42192.0 / 6.0 * G_EARTH, rel=2e-3)  # 4 digits printed
    build_scene(load_scene(None, {"scene": {"frame": str(frame)},
                                  "isolation": {"contact": "bilateral"}}))  # fmt: skip


def test_misplaced_fields_and_files_are_named_as_what_they_are(tmp_path, one_line):
    big = tmp_path / "big.toml"
    big.write_text("[solver]\ndt_out = 100.0\n")
    assert main(["run", str(big), "--out", str(tmp_path / "o"), "--no-figures"]) == 2
    one_line(f"{big}: solver.dt_out:", "longer than the run")
    scene = str(SCENES / "deck-fps4-3c.toml")
    assert main(["run", "--frame", scene, "--out", str(tmp_path / "o"), "--no-figures"]) == 2
    one_line(f"{scene}: a scene file", "not a frame file", f"nsdyn run {scene}")
    assert main(["export", "opensees", "office-11", "-o", str(tmp_path / "m.py")]) == 2
    one_line("office-11: a bundled frame, not a scene")


def test_a_large_closure_says_what_it_measures():
    """The closure is a trapezoidal check on the output grid (second order in dt_out)."""
    from nsdyn.cli.run_summary import CLOSURE_NOTE, _closure_cell

    assert _closure_cell(0.5 * CLOSURE_NOTE) == f"{0.5 * CLOSURE_NOTE:.2e}"
    assert "dt_out" in _closure_cell(2 * CLOSURE_NOTE)


def test_a_force_scene_sweeps_its_own_force_amplitude(tmp_path, capsys):
    """The Coulomb oscillator's 1 635 N exceeds its friction capacity μ m g = 0.05 x 9 810 N
    = 490.5 N, so it slips at every frequency (the default amplitudes, read as N, would
    never)."""
    import json

    scene = SCENES / "isolated-coulomb-force.toml"
    rc = main(["sweep", str(scene), "--points", "3", "--out", str(tmp_path), "--json"])
    assert rc == 0
    (amp,) = json.loads(capsys.readouterr().out)["amplitudes"]
    assert amp["A"] == 1635.0 and amp["x_iso_max_m"] > 0.0


def test_modes_of_a_scene_says_it_lists_the_bare_frame(tmp_path, capsys):
    scene = SCENES / "building3d-office-fixed.toml"
    assert main(["modes", str(scene), "--out", str(tmp_path), "--json"]) == 0
    err = capsys.readouterr().err
    assert f"the fixed-base modes of office-11-3d, the frame {scene} names" in err


def test_a_deck_that_lifts_off_ends_with_status_3_and_its_json_says_so(tmp_path, capsys):
    """The contract of docs/reference/cli.md: a failed command's JSON leads with status and
    error. A deck's centre of mass 15 m up over isolators 6 m from it along y: the
    overturning moment m a h exceeds the restoring m g 6 m once a > 0.4 g (lever rule), so
    the 12 m/s² record lifts an isolator and the run ends there."""
    scene = tmp_path / "tall.toml"
    scene.write_text((SCENES / "deck-fps4-3c.toml").read_text().replace("h = 1.5 ", "h = 15.0"))
    code = main(["run", str(scene), "--pga", "12", "--t-end", "4", "--json", "--no-figures",
                 "--out", str(tmp_path / "o")])  # fmt: skip
    import json

    s = json.loads(capsys.readouterr().out)
    assert code == 3 == s["status"] and list(s)[:2] == ["status", "error"]
    u = s["uplift"]
    assert s["error"].startswith(f"UPLIFT isolator {u['isolator']} at t = {u['t_s']:.5g} s")
    assert s["t_end_s"] <= u["t_s"] < 4.0  # the run ended at the uplift
    # the text run: the same exit, and its error line last on stderr (a warning alone before)
    code = main(["run", str(scene), "--pga", "12", "--t-end", "4", "--no-figures",
                 "--out", str(tmp_path / "o")])  # fmt: skip
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 3 and err[-1] == f"nsdyn run: error: {s['error']}"


@pytest.mark.parametrize(
    ("text", "hint"),
    [('[isolaton]\nmu = 0.05\n', "[isolaton]: unknown table; did you mean 'isolation'?"),
     ('[scene]\nkind = "deck"\n[motin]\nt_end = 1\n', "[motin]: unknown table; did you mean "
      "'motion'? expected some of ['bearing', 'deck', 'mass', 'motion', ")],
)  # fmt: skip
def test_a_misspelt_scene_table_gets_the_nearest_name(tmp_path, capsys, text, hint):
    scene = tmp_path / "s.toml"
    scene.write_text(text)
    assert main(["run", str(scene), "--out", str(tmp_path / "o")]) == 2
    assert hint in capsys.readouterr().err


def test_a_contact_problem_without_solution_is_a_numerical_failure(tmp_path, capsys):
    """Friction 2.0 on the seed's block: at the first contact instant the rigid body's LCP
    has no solution (Painlevé's paradox of rigid bodies with Coulomb friction), a failure of
    the event-driven method, not of the input: status 3 with the time and the way out. An
    earlier run's histories in the folder are said to be that run's, after the error."""
    scene = tmp_path / "mu2.toml"
    text = (SCENES / "contact-seed002-A5.toml").read_text()
    scene.write_text(text.replace("mu_s = 0.57", "mu_s = 2.0").replace("mu_d = 0.29", "mu_d = 2.0"))
    out = tmp_path / "o"
    out.mkdir()
    (out / "run-histories.npz").write_bytes(b"an isolated frame's run")
    assert main(["run", str(scene), "--no-figures", "--out", str(out)]) == 3
    err = capsys.readouterr().err
    assert "numerical failure: event-driven: contact LCP has no solution at t = 0 s" in err
    assert "Traceback" not in err and "solver.method = 'moreau'" in err
    assert err.splitlines()[-1] == (f"nsdyn run: note: {out} holds an earlier command's files, "
                                    "none of this failed run's: run-histories.npz")  # fmt: skip


def test_an_input_error_is_one_line_beside_an_earlier_runs_files(tmp_path, capsys):
    # the earlier files' note followed every input error in a used folder: nothing ran, so
    # nothing there can be mistaken for this run's
    out = tmp_path / "o"
    out.mkdir()
    (out / "run-histories.npz").write_bytes(b"an isolated frame's run")
    scene = tmp_path / "s.toml"
    scene.write_text('[scene]\nframe = "office-11"\n[solver]\nbogus = 1\n')
    assert main(["run", str(scene), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "solver.bogus" in err


def test_an_output_grid_too_coarse_for_a_harmonic_is_noted(tmp_path, capsys):
    """50 Hz sampled every 20 ms (the scene default) is one sample per period: the peaks are
    aliased (the sampling theorem asks for more than two; 20 keeps the sampled peak of a sine
    within 1.3 % of its amplitude, 1 - cos(pi / 20)). The run says so and how fine to go."""
    scene = tmp_path / "h50.toml"
    scene.write_text('[motion]\nkind = "harmonic"\namplitude = 3.0\nfrequency = 50.0\n'
                     't_end = 0.2\n')  # fmt: skip
    assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "o")]) == 0
    err = capsys.readouterr().err
    assert "dt_out = 0.02 s samples the 50 Hz excitation 1 times per period" in err
    assert "set solver.dt_out <= 0.001 s" in err
    scene.write_text(scene.read_text() + "[solver]\ndt_out = 0.001\n")
    assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "p")]) == 0
    assert "samples the" not in capsys.readouterr().err


def test_an_output_grid_too_coarse_for_a_record_is_noted(tmp_path, capsys):
    """Outputs 0.5 s apart under a 100 Hz record read the peaks every 50 samples: a floor
    response of 2.5 Hz is sampled less than once per period. The run says so; the scene
    default (0.02 s, two samples: 20 a period, a peak read within 1 - cos(pi/20) = 1.2 %)
    does not."""
    scene = tmp_path / "coarse.toml"
    scene.write_text("[motion]\nt_end = 3.0\n[solver]\ndt_out = 0.5\n")
    args = ["run", str(scene), "--fidelity", "rigid", "--no-figures", "--out"]
    assert main([*args, str(tmp_path / "o")]) == 0
    err = capsys.readouterr().err
    assert err.count("dt_out = 0.5 s reads the peaks every 50 samples of the record (0.01 s)") == 1
    assert "set solver.dt_out <= 0.02 s" in err  # (said once: before the run, the field named)
    scene.write_text("[motion]\nt_end = 3.0\n")
    assert main([*args, str(tmp_path / "p")]) == 0
    assert "reads the peaks" not in capsys.readouterr().err


def test_an_arctan_law_too_soft_to_be_friction_is_noted(tmp_path, capsys):
    """eps = 1e-9 s/m: the arctan friction mu N (2/pi) atan(eps v) reaches 90 % of mu N at
    v = tan(0.45 pi) / eps = 6.3e9 m/s, so the law is a viscous damper and every instant
    counts as stick. The run says so; the scene default (7500 s/m: 8.4e-4 m/s) does not."""
    scene = tmp_path / "soft.toml"
    scene.write_text("[isolation]\neps = 1e-9\n[motion]\nt_end = 0.2\n")
    assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "o")]) == 0
    err = capsys.readouterr().err
    assert "isolation.eps = 1e-09 s/m: the arctan friction reaches 90% of mu N only at a " \
           "slip velocity of 6.3e+09 m/s" in err  # fmt: skip
    scene.write_text("[motion]\nt_end = 0.2\n")
    assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "p")]) == 0
    assert "arctan friction reaches" not in capsys.readouterr().err


@pytest.mark.parametrize(("fidelity", "noted"), [("rigid", True), ("full", True), ("cb", False)])
def test_a_cutoff_the_fidelity_does_not_read_is_noted(tmp_path, capsys, fidelity, noted):
    # scene.f_max is the Craig-Bampton cut-off: the rigid and full rungs have none, and
    # the run says it did not use it (--fmax is refused there); cb reads it
    scene = tmp_path / "fmax.toml"
    scene.write_text(f'[scene]\nfidelity = "{fidelity}"\nf_max = 8.0\n[motion]\nt_end = 0.1\n')
    assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "o")]) == 0
    err = capsys.readouterr().err
    assert ("note: scene.f_max not used" in err) == noted, err
    # --json prints nothing but its object, which carries the notes
    assert main(["run", str(scene), "--no-figures", "--json", "--out", str(tmp_path / "j")]) == 0
    out, err = capsys.readouterr()
    notes = json.loads(out)["notes"]
    assert "note:" not in err and any("scene.f_max not used" in n for n in notes) == noted


def test_a_very_sharp_arctan_law_runs_to_the_switch_law(tmp_path, capsys):
    """eps = 1e8 s/m on the default scene. The switch law is the arctan law's limit
    eps -> inf, so its event-driven run is the reference. Radau holds its velocity tolerance
    at 0.1/eps, which keeps the law's turn resolved. Before that cap it stopped at a false
    'uplift' at 0.81 s, while the switch law keeps every normal force above 2e6 N."""
    scene = tmp_path / "sharp.toml"
    scene.write_text("[isolation]\neps = 1e8\n[motion]\nt_end = 1.0\n")
    argv = ["run", str(scene), "--json", "--no-figures"]
    assert main([*argv, "--out", str(tmp_path / "o")]) == 0
    sharp = json.loads(capsys.readouterr().out)
    rc = main([*argv, "--friction", "switch", "--method", "event", "--out", str(tmp_path / "p")])
    assert rc == 0
    ref = json.loads(capsys.readouterr().out)
    assert ref["min_normal_force_N"] > 2e6 and sharp["min_normal_force_N"] > 2e6
    for k in ("x_iso_max_m", "idr_max", "floor_acc_max_mps2"):  # the limit, to 1 %
        assert sharp[k] == pytest.approx(ref[k], rel=0.01), k


@pytest.mark.parametrize(
    "extra, args, field",
    [("", ["--t-end", "1e-9"], "motion.t_end (--t-end): expected an end at least one record step "
                               "(0.01 s) after the record's start (0 s), got 1e-09"),
     ("dt_out = 100.0\n", ["--t-end", "5"], "solver.dt_out: expected a positive output step")],
)  # fmt: skip
def test_a_deck_run_grid_out_of_range_is_an_input_error(tmp_path, capsys, extra, args, field):
    """A deck run's end and output step are fields of the scene: refused as input (status 2,
    the field named), not a traceback."""
    scene = tmp_path / "deck.toml"
    text = (SCENES / "deck-fps4-3c.toml").read_text()
    scene.write_text(text.replace("[solver]\n", "[solver]\n" + extra))
    rc = main(["run", str(scene), *args, "--no-figures", "--out", str(tmp_path / "o")])
    assert rc == 2
    err = capsys.readouterr().err
    assert f"{scene}: {field}" in err and "Traceback" not in err


def test_friction_flag_on_a_deck_scene_is_its_solver_law(tmp_path, capsys):
    """--friction on a deck scene sets its [solver] law (as nsdyn sweep already did): the
    same run, to the bit, as the scene file with that law; 'none' is refused (a deck's
    bearings keep their friction)."""
    src = SCENES / "deck-fps4-3c.toml"
    scene = tmp_path / "arctan.toml"
    scene.write_text(src.read_text().replace('law = "switch"', 'law = "arctan"'))
    runs = []
    for argv in (["run", str(src), "--friction", "arctan"], ["run", str(scene)]):
        rc = main([*argv, "--t-end", "1", "--json", "--no-figures",
                   "--out", str(tmp_path / str(len(runs)))])  # fmt: skip
        assert rc == 0
        runs.append(json.loads(capsys.readouterr().out))
    assert runs[0]["law"] == runs[1]["law"] == "arctan"
    assert runs[0]["peak_resultant_displacement_m"] == runs[1]["peak_resultant_displacement_m"]
    rc = main(["run", str(src), "--friction", "none", "--no-figures", "--out", str(tmp_path)])
    assert rc == 2 and "--friction none: a deck scene's bearings keep" in capsys.readouterr().err
    # a law the scene's bearings refuse names the flag that gave it (the file says "arctan")
    tfp = SCENES / "deck-tfp4-3c.toml"
    rc = main(["run", str(tfp), "--friction", "switch", "--no-figures", "--out", str(tmp_path)])
    assert rc == 2 and f"{tfp}: solver.law (--friction): a triple" in capsys.readouterr().err


def test_the_friction_flag_overrides_the_scene_law(tmp_path, capsys):
    """``--friction arctan`` on a switch-law scene is the scene with law = "arctan" (it
    stopped with a traceback: shooting refused the scene's switch law)."""
    import csv

    scene = SCENES / "isolated-coulomb-force.toml"
    text = scene.read_text()
    assert 'law = "switch"' in text
    edited = tmp_path / "arctan.toml"
    edited.write_text(text.replace('law = "switch"', 'law = "arctan"'))
    rows = {}
    for name, args in (("flag", [str(scene), "--friction", "arctan"]), ("scene", [str(edited)])):
        out = tmp_path / name
        rc = main(["sweep", *args, "--points", "3", "--out", str(out), "--no-figures", "--json"])
        assert rc == 0
        with open(out / "sweep.csv", newline="") as f:
            rows[name] = list(csv.DictReader(f))
    capsys.readouterr()
    assert {r["law"] for r in rows["flag"]} == {"arctan"}
    assert [r["x_iso"] for r in rows["flag"]] == [r["x_iso"] for r in rows["scene"]]


def test_an_uplift_under_detect_is_a_model_limit_not_a_numerical_failure(tmp_path, capsys):
    """The pocket scene lifts off within its 13 s (its 1.4 g shaking; docs/guide/uplift.md);
    under contact "detect" the run stops there with status 3, its line naming the model's
    limit and the time."""
    text = (SCENES / "isolated-uplift-pocket.toml").read_text()
    assert '\ncontact = "unilateral"' in text
    scene = tmp_path / "detect.toml"
    scene.write_text(text.replace('\ncontact = "unilateral"', '\ncontact = "detect"'))
    code = main(["run", str(scene), "--t-end", "13", "--no-figures", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 3
    head = "nsdyn run: model limit: uplift at t = "
    assert err[-1].startswith(head)
    assert 0.0 < float(err[-1][len(head) :].split()[0]) < 13.0  # within the run, stopped there


def test_a_sweep_without_figures_removes_the_earlier_runs_figure(tmp_path, capsys):
    # the earlier run's sweep.png sat beside the new sweep.csv, a figure of other settings
    out = tmp_path / "o"
    base = ["sweep", "--points", "2", "--fmin", "0.5", "--fmax", "1", "--out", str(out)]
    assert main([*base, "--amplitudes", "0.5"]) == 0 and (out / "sweep.png").exists()
    assert main([*base, "--amplitudes", "1", "--no-figures"]) == 0
    assert not (out / "sweep.png").exists() and (out / "sweep.csv").exists()
    assert "removed the earlier run's sweep.png" in capsys.readouterr().err
    assert main([*base, "--amplitudes", "0.5"]) == 0  # (--json: among the notes)
    assert main([*base, "--amplitudes", "0.5", "--no-figures", "--json"]) == 0
    notes = json.loads(capsys.readouterr().out.splitlines()[-1])["notes"]
    assert "removed the earlier run's sweep.png (--no-figures draws none)" in notes


@pytest.mark.parametrize("scene, figure", [("isolated-shear-3storey", "run.png"),
                                           ("rocking-seed003-column", "rocking.png"),
                                           ("cylinder-uplift", "cylinder-uplift.png")])  # fmt: skip
def test_a_run_without_figures_removes_the_earlier_runs_figure(tmp_path, capsys, scene, figure):
    # as a sweep's: the earlier figure sat beside the new histories, a figure of another run
    out = tmp_path / "o"
    path = Path(__file__).resolve().parents[2] / "examples" / "scenes" / f"{scene}.toml"
    base = ["run", str(path), "--t-end", "1", "--out", str(out)]
    (out / "notes.png").parent.mkdir()
    (out / "notes.png").write_text("the user's")  # a file of another name stays
    assert main(base) == 0 and (out / figure).exists()
    assert main([*base, "--no-figures"]) == 0
    assert not (out / figure).exists() and (out / "notes.png").exists()
    assert f"removed the earlier run's {figure}" in capsys.readouterr().err
    assert main(base) == 0 and main([*base, "--no-figures", "--json"]) == 0  # (said there too)
    notes = json.loads(capsys.readouterr().out.splitlines()[-1])["notes"]
    assert f"removed the earlier run's {figure} (--no-figures draws none)" in notes


def test_a_resumed_sweep_says_its_wall_time_is_this_runs(tmp_path, capsys):
    # rerun, every point comes from the checkpoint: the wall column times this run alone
    argv = ["sweep", "--points", "2", "--fmin", "0.5", "--fmax", "1", "--amplitudes", "0.5",
            "--no-figures", "--out", str(tmp_path / "o")]  # fmt: skip
    assert main(argv) == 0
    assert "points resumed" not in capsys.readouterr().out
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "A = 0.5: 2 of 2 points resumed from the checkpoint (wall [s]: this run's" in out


def test_a_sweep_with_a_point_without_steady_state_exits_3(tmp_path, capsys, monkeypatch):
    # a curve with holes is not a success (as a study with failed tasks): status 3 and one
    # line naming the count and the file, the files written as usual. The hole is put in the
    # summary: which points fail to converge is not something a quick test can choose
    import nsdyn.cli.sweep as cli_sweep

    real = cli_sweep.summarise
    monkeypatch.setattr(cli_sweep, "summarise", lambda r: {**real(r), "unconverged_points": 1})
    out = tmp_path / "o"
    argv = ["sweep", "--points", "2", "--fmin", "0.5", "--fmax", "1", "--amplitudes", "0.5",
            "--no-figures", "--out", str(out)]  # fmt: skip
    assert main(argv) == 3
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1] == f"nsdyn sweep: 1 of 2 points failed ({out / 'sweep.csv'} lists each one)"
    assert (out / "sweep.csv").exists()
    monkeypatch.setattr(cli_sweep, "summarise", real)
    assert main(argv) == 0  # the same sweep, every point converged


def test_a_plane_sweeps_file_carries_the_status_its_json_prints(tmp_path, capsys, monkeypatch):
    # sweep.json of a plane sweep was written before its holes were counted: the file read as
    # a success where the command exited 3 and its --json said status 3 with the error line.
    # The hole is put in the summary (which points fail is not for a quick test to choose)
    import nsdyn.studies.plane_sweep as ps

    real = ps.summarise
    monkeypatch.setattr(ps, "summarise", lambda r: {**real(r), "unconverged_points": 1})
    out = tmp_path / "o"
    argv = ["sweep", str(SCENES / "sdof-bidirectional-sweep.toml"), "--points", "2",
            "--no-figures", "--out", str(out)]  # fmt: skip
    line = f"1 of 2 points failed ({out / 'sweep.json'} lists each one)"
    for json_flag in ([], ["--json"]):
        assert main([*argv, *json_flag]) == 3
        said = capsys.readouterr()
        assert said.err.count(line) == 1
        saved = json.loads((out / "sweep.json").read_text())
        assert (saved["status"], saved["error"]) == (3, line)
        if json_flag:
            printed = json.loads(said.out.splitlines()[-1])
            assert (printed["status"], printed["error"]) == (3, line)


def test_a_sweeps_report_lists_each_point_without_steady_state_and_why():
    # the JSON of a frame sweep names its failed points with their row's note (as the deck
    # sweep's does); converged points, with or without uplift, are not failures
    from nsdyn.studies.sweep import summarise

    def row(f, converged, note=""):
        return {"f": f, "converged": converged, "note": note, "stick_all_period": False,
                "uplift": False, "contact": "bilateral", "method": "shooting", "stable": True,
                "IDR": 1e-3, "a": 1.0, "a_floors": 1.0, "x_iso": 0.1}  # fmt: skip

    rows = [row(0.1, True), row(0.2, False, "uplift at t = 3.1 s"), row(0.3, False), row(0.4, True)]
    r = {"A": 1.0, "rows": rows, "resumed_points": 0, "bifurcations": [], "wall_s": 0.0,
         "wall_below_0.1Hz_s": 0.0, "wall_above_0.1Hz_s": 0.0}  # fmt: skip
    s = summarise(r)
    assert s["unconverged_points"] == 2
    assert s["failures"] == [{"f": 0.2, "reason": "uplift at t = 3.1 s"},
                             {"f": 0.3, "reason": "not converged"}]  # fmt: skip
    from nsdyn.cli.sweep import gap_lines

    assert gap_lines(s) == ["2 points without a steady state, f = 0.2-0.3 Hz (first: uplift "
                            "at t = 3.1 s)"]  # fmt: skip
    # the points stuck all period from 0.3 Hz up, a failed one (no stick flag: no orbit)
    # among them: the stuck band is not cut short by it, nor started at it
    for k, st in ((0, False), (1, False), (2, True), (3, True)):
        rows[k]["stick_all_period"] = st
    rows[2]["converged"], rows[3]["converged"] = True, False
    rows[1]["converged"] = True
    assert summarise(r)["stick_all_period_above_hz"] == 0.3
    rows[3]["stick_all_period"] = ""  # (a failed point's row: no flag)
    assert summarise(r)["stick_all_period_above_hz"] == 0.3
    rows[2]["converged"], rows[2]["stick_all_period"] = False, ""
    rows[3]["stick_all_period"] = True
    assert summarise(r)["stick_all_period_above_hz"] == 0.4


def test_unilateral_contact_on_given_normal_forces_is_refused_up_front(tmp_path, one_line):
    # lift-off needs the normal forces as the contacts' multipliers: a structure from matrices
    # given its weight, or frozen_normal = true, has none (a ValueError traceback, exit 1)
    scenes = Path(__file__).resolve().parents[2] / "examples" / "scenes"
    text = (scenes / "isolated-shear-3storey.toml").read_text()
    shear = tmp_path / "s.toml"
    shear.write_text(text.replace("[isolation]", '[isolation]\ncontact = "unilateral"', 1))
    frozen = tmp_path / "f.toml"
    frozen.write_text('[isolation]\ncontact = "unilateral"\nfrozen_normal = true\n')
    for scene, says in ((shear, "its weight"), (frozen, "isolation.frozen_normal = true")):
        assert main(["run", str(scene), "--t-end", "1", "--out", str(tmp_path / "o")]) == 2
        one_line(f"{scene}: isolation.contact: 'unilateral' needs", says)


def test_a_pga_flag_with_nothing_to_scale_is_named(tmp_path, capsys):
    # a free-rocking scene has no record or pulse: the error blamed motion.pga, a key the
    # file does not hold; it names the flag that set it
    scene = Path(__file__).resolve().parents[2] / "examples/scenes/rocking-seed001-compliant.toml"
    assert main(["run", str(scene), "--pga", "5", "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err == (
        f"nsdyn run: error: {scene}: motion.pga (--pga): 5.0 m/s² needs a motion.record or a "
        "motion.pulse to scale\n"
    )


def test_run_record_replaces_a_rocking_pulse(tmp_path, capsys):
    # --record on a pulse scene runs the record (the pulse's keys are dropped, as --t-end
    # replaces n_periods); in the file, a record beside pulse keys is refused
    scene = Path(__file__).resolve().parents[2] / "examples/scenes/rocking-seed003-column.toml"
    argv = ["run", str(scene), "--record", "synthetic-wn-40s", "--t-end", "1", "--json",
            "--no-figures", "--out", str(tmp_path)]  # fmt: skip
    assert main(argv) == 0
    assert json.loads(capsys.readouterr().out)["motion"].startswith("synthetic-wn-40s, PGA")
    # the scene's t_end (6 s) was the pulse's: the record runs to its end (40 s), said once
    # (it cut a Kobe record before its strong part: "at rest" for a 0.51 g record)
    argv = ["run", str(scene), "--record", "synthetic-kt-20s", "--no-figures", "--out",
            str(tmp_path)]  # fmt: skip
    assert main(argv) == 0
    out, err = capsys.readouterr()
    assert "the scene's t_end = 6 s was its closed-form motion's" in err
    assert "t_end = 20 s" in err and "end time               20 s" in out


def test_the_summary_says_the_ground_acceleration_the_run_felt(tmp_path, capsys):
    # --pga replaces a pulse's amplitude (the scene's name still says 0.40 g): the summary
    # records the peak the run felt, exactly the flag's value; a contact run's npz names its
    # modes (mode k is mode_names[k], the results' own table)
    import numpy as np

    from nsdyn.models.contact.results import MODE_NAMES

    scenes = Path(__file__).resolve().parents[2] / "examples/scenes"
    argv = ["run", str(scenes / "rocking-seed003-column.toml"), "--pga", "3", "--json",
            "--no-figures", "--out", str(tmp_path)]  # fmt: skip
    assert main(argv) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["pga_mps2"] == 3.0 and "a_p = 3 m/s²" in s["motion"]
    argv = ["run", str(scenes / "contact-seed002-A5.toml"), "--pga", "2", "--t-end", "0.5",
            "--json", "--no-figures", "--out", str(tmp_path)]  # fmt: skip
    assert main(argv) == 0
    assert json.loads(capsys.readouterr().out)["pga_mps2"] == 2.0
    with np.load(tmp_path / "contact.npz") as d:
        assert list(d["mode_names"]) == list(MODE_NAMES)
    # the compliant block's state columns are named; its angle column is phi = -theta
    argv = ["run", str(scenes / "rocking-seed001-compliant.toml"), "--t-end", "1",
            "--no-figures", "--out", str(tmp_path)]  # fmt: skip
    assert main(argv) == 0
    with np.load(tmp_path / "rocking.npz") as d:
        k = list(d["y_columns"]).index("phi_rad")
        assert np.array_equal(d["y"][:, k], -d["theta"]) and d["y"].shape[1] == 8


@pytest.mark.parametrize(
    "text, says",
    [
        ('name = "x"\n[scene]\n', "name: a key outside any table (above the first [table])"),
        ('[motion]\npga = "3"\n', "motion.pga: expected a number, got '3'"),  # not "float"
        ('[motion]\npga = true\n', "motion.pga: expected a number, got true"),  # not "True"
        ('[motion]\nkind = "sine"\n', "motion.kind: expected 'harmonic' (a harmonic ground "
                                      "acceleration) or no kind (a record), got 'sine'"),
        ('[scene]\nkind = "deck"\n[deck]\nm = 1e5\npositions = [[-1, -1], [1, -1], [1, 1], '
         '[-1, 1]]\n[bearing]\ntype = "fps"\nradius = 2.0\nmu = 0.05\n[motion]\n'
         'record = "synthetic-wn-40s"\n', "motion.kind: missing; expected one of ['record3', "
                                          "'orbit']"),
    ],
)  # fmt: skip
def test_a_misplaced_key_or_kind_is_named_as_what_it_is(text, says, tmp_path, one_line):
    scene = tmp_path / "s.toml"
    scene.write_text(text)
    assert main(["run", str(scene), "--out", str(tmp_path / "o")]) == 2
    one_line(f"{scene}: ", says)


def test_isolation_keys_the_model_does_not_read_are_noted(tmp_path, capsys):
    # they changed nothing without a word: the switch law's band under the arctan law, any
    # isolator key on the fixed-base frame; the default scene's own keys are not the user's
    def notes(text):
        scene = tmp_path / "s.toml"
        scene.write_text(text)
        argv = ["run", str(scene), "--t-end", "0.5", "--json", "--no-figures", "--out",
                str(tmp_path / "o")]  # fmt: skip
        assert main(argv) == 0
        return json.loads(capsys.readouterr().out)["notes"]

    (n,) = [x for x in notes("[isolation]\nkappa = 3.0\n") if "not used" in x]
    assert "isolation.kappa (a key of the switch law; the law here is arctan)" in n
    (n,) = [x for x in notes('[scene]\nfidelity = "fixed"\n[isolation]\nmu = 0.2\n')
            if "not used" in x]  # fmt: skip
    assert n == "[isolation] not used: the fixed-base model has no isolators (mu)"
    assert not [x for x in notes('[isolation]\nlaw = "switch"\n') if "not used" in x]


def test_a_deck_takes_its_absolute_tolerance_as_a_pair(tmp_path, capsys):
    # the default is a pair (the switch law's 1e-8 for both): written out, the same run
    scenes = Path(__file__).resolve().parents[2] / "examples" / "scenes"
    text = (scenes / "deck-fps4-3c.toml").read_text()
    pair = tmp_path / "p.toml"
    pair.write_text(text.replace("[solver]", "[solver]\natol = [1e-8, 1e-8]", 1))
    runs = []
    for scene in (scenes / "deck-fps4-3c.toml", pair):
        argv = ["run", str(scene), "--t-end", "2", "--json", "--no-figures", "--out",
                str(tmp_path / scene.stem)]  # fmt: skip
        assert main(argv) == 0
        runs.append(json.loads(capsys.readouterr().out))
    assert runs[0]["peak_resultant_displacement_m"] == runs[1]["peak_resultant_displacement_m"]


@pytest.mark.parametrize("flag", [["--record", "synthetic-wn-40s"], ["--pga", "3"]])
@pytest.mark.parametrize("name", ["sdof-bidirectional-circular", "isolated-uplift-pocket"])
def test_record_flags_on_a_harmonic_motion_name_the_flag(flag, name, tmp_path, one_line):
    # the scene's reader named motion.record / motion.pga, keys the file does not have
    scene = Path(__file__).resolve().parents[2] / "examples" / "scenes" / f"{name}.toml"
    assert main(["run", str(scene), *flag, "--out", str(tmp_path)]) == 2
    one_line(f"{scene}: {flag[0]}: this scene's motion is harmonic")


def test_a_record_replacing_a_sine_runs_at_its_own_scale():
    # the sine's pga is its amplitude: dropped with it (the record was scaled to 1.6 m/s²);
    # a record scene's pga scales whatever record replaces it, and --pga still applies after
    import argparse

    from nsdyn.cli.run_checks import record_wins

    args = argparse.Namespace(scene="s.toml", record="synthetic-wn-40s", pga=None)
    sine = {"motion": {"period": 2.18, "pga": 1.6, "n_cycles": 5}}
    record_wins(args, sine, ("period", "n_cycles", "start"), True)
    assert sine["motion"] == {}
    rec = {"motion": {"record": "synthetic-kt-20s", "pga": 2.0}}
    record_wins(args, rec, ("period", "n_cycles", "start"), True)
    assert rec["motion"] == {"record": "synthetic-kt-20s", "pga": 2.0}


def test_a_deck_atol_of_the_wrong_length_names_the_pair_form(tmp_path, one_line):
    scenes = Path(__file__).resolve().parents[2] / "examples" / "scenes"
    text = (scenes / "deck-fps4-3c.toml").read_text()
    bad = tmp_path / "b.toml"
    bad.write_text(text.replace("[solver]", "[solver]\natol = [1e-8]", 1))
    assert main(["run", str(bad), "--out", str(tmp_path / "o")]) == 2
    one_line(
        f"{bad}: solver.atol: expected a positive number or a pair [displacements, "
        "velocities], got [1e-08]"
    )


@pytest.mark.parametrize(
    ("solver", "bound"),
    [('method = "event"\n', 1e-5), ("", 0.1 / 7500.0)],  # eta; ATOL_V_EPS / eps (defaults)
)
def test_a_velocity_tolerance_above_the_laws_resolution_is_noted(tmp_path, capsys, solver, bound):
    """The event method at atol 1e-4 (10x the stick band eta = 1e-5 m/s) read a floor
    acceleration of 7.5 m/s² against 2.6; the arctan law's runs keep 0.1/eps by default."""
    scene = tmp_path / "a.toml"
    for factor, noted in ((1.01, True), (0.99, False)):
        scene.write_text(
            f"[motion]\nt_end = 0.5\n[solver]\n{solver}atol = [1e-8, {factor * bound!r}]\n"
        )
        args = ["run", str(scene), "--fidelity", "rigid", "--no-figures", "--out"]
        assert main([*args, str(tmp_path / f"o{factor}")]) == 0
        err = capsys.readouterr().err
        assert ("solver.atol: a velocity tolerance of" in err) is noted


@pytest.mark.parametrize("scene", ["rocking-seed003-column", "contact-seed002-A5",
                                   "cylinder-uplift"])  # fmt: skip
def test_a_record_column_a_family_leaves_out_is_said(tmp_path, capsys, scene):
    # a file of two horizontal components (no names, as PEER's paired text files): the run
    # takes the first; the second was dropped without a word in these families (the isolated
    # frame said so). The note is in the JSON's notes, and the cylinder's names record_y
    import numpy as np

    t = np.arange(0.0, 2.0, 0.01)
    rec = tmp_path / "two.txt"
    rec.write_text("% two horizontal components, acc. in m/s2 and dt=0.01 sec\n" + "".join(
        f"{0.5 * np.sin(4 * x):.6e}\t{0.3 * np.cos(3 * x):.6e}\n" for x in t))  # fmt: skip
    path = Path(__file__).resolve().parents[2] / "examples" / "scenes" / f"{scene}.toml"
    argv = ["run", str(path), "--record", str(rec), "--t-end", "1", "--json", "--no-figures",
            "--out", str(tmp_path / "o")]  # fmt: skip
    assert main(argv) == 0
    notes = json.loads(capsys.readouterr().out)["notes"]
    said = [n for n in notes if "the record's column(s) 1 not used: the run takes 0" in n]
    assert len(said) == 1 and (scene != "cylinder-uplift" or "record_y" in said[0]), notes


def test_a_record_replaces_a_closed_form_motion_in_a_study_as_in_a_run(tmp_path):
    # the cask scene's t_end (12 s) was its 8-cycle sine's: a study's records run to their
    # ends, as `nsdyn run --record` does; a study's own [base.motion] t_end still applies. A
    # cylinder scene without a record is a simulated earthquake even with only defaults
    import argparse

    from nsdyn.cli.run_checks import record_wins
    from nsdyn.studies import load_study

    scene = Path(__file__).resolve().parents[2] / "examples/scenes/rocking-seed001-cask.toml"
    head = f'[study]\nname = "s"\nscene = "{scene}"\n'
    tail = '[parameters]\n"block.r" = [0.82]\n[records]\nnames = ["synthetic-kt-20s"]\n'
    for base, t_end in (("", None), ("[base.motion]\nt_end = 5.0\n", 5.0)):
        (tmp_path / "s.toml").write_text(head + base + tail)
        mo = load_study(tmp_path / "s.toml").base["motion"]
        assert mo.get("t_end") == t_end and not {"pulse", "a_p_g", "f_p"} & set(mo), mo
    args = argparse.Namespace(scene="c.toml", record="synthetic-kt-20s", pga=None, t_end=None,
                              json=True)  # fmt: skip
    cyl = {"motion": {"t_end": 3.0}}
    record_wins(args, cyl, ("seed", "duration", "dt", "s0_units"), False, "cylinder")
    assert cyl["motion"] == {} and "t_end = 3 s was its closed-form motion's" in args.notes[0]


def test_an_empty_record_list_leaves_the_scene_s_own_motion(tmp_path):
    # [records] names = [] gives no record to replace the pulse with: the scene keeps it
    from nsdyn.studies import load_study

    scene = Path(__file__).resolve().parents[2] / "examples/scenes/rocking-seed001-cask.toml"
    (tmp_path / "s.toml").write_text(f'[study]\nname = "s"\nscene = "{scene}"\n[parameters]\n'
                                     '"block.r" = [0.82]\n[records]\nnames = []\n')  # fmt: skip
    mo = load_study(tmp_path / "s.toml").base["motion"]
    assert mo["pulse"] == "sine" and mo["t_end"] == 12.0


def test_sweep_flags_and_tables_that_would_repeat_or_do_nothing_are_refused(tmp_path, one_line):
    # a fixed building's steady state is solved exactly: --no-fallback and --continuation
    # changed nothing; a deck scene's amplitude given twice computed and wrote it twice
    fixed = SCENES / "building3d-office-fixed.toml"
    text = fixed.read_text().split("[motion]")[0]
    scene = tmp_path / "fixed-orbit.toml"
    scene.write_text(text + '[motion]\nkind = "orbit"\norbit = "linear"\nfrequency = 0.5\n'
                     "amplitude = 1.0\nn_periods = 6\n")  # fmt: skip
    out = str(tmp_path / "o")
    assert main(["sweep", str(scene), "--no-fallback", "--points", "3", "--out", out]) == 2
    one_line("--no-fallback: not for the fixed rung")
    # --workers alike: one batched solve (it was taken and ignored)
    assert main(["sweep", str(scene), "--workers", "2", "--points", "3", "--out", out]) == 2
    one_line(f"{scene}: --workers: not for the fixed rung")  # (the file named, as every refusal)
    deck = (SCENES / "sdof-bidirectional-sweep.toml").read_text()
    dup = tmp_path / "dup.toml"
    dup.write_text(deck.replace("amplitudes = [0.981]", "amplitudes = [1.0, 1.0]"))
    assert main(["sweep", str(dup), "--points", "2", "--out", out]) == 2
    one_line("sweep.amplitudes: expected distinct amplitudes, got [1.0, 1.0]")
    dup.write_text(deck.replace("amplitudes = [0.981]", "amplitudes = [1.0, 1.0e300]"))
    assert main(["sweep", str(dup), "--points", "2", "--out", out]) == 2
    one_line("sweep.amplitudes: expected ground acceleration amplitudes <= 1000 m/s²")
    # the help's "at most 1000" was not held: 1001 curves started, a checkpoint each
    many = ",".join(f"{0.001 * (k + 1):g}" for k in range(1001))
    with pytest.raises(SystemExit, match="2"):
        main(["sweep", "--amplitudes", many, "--out", out])
    one_line("argument --amplitudes: expected at most 1000 amplitudes (a curve each), got 1001")
    dup.write_text(deck.replace("amplitudes = [0.981]", f"amplitudes = [{many}]"))
    assert main(["sweep", str(dup), "--points", "2", "--out", out]) == 2
    one_line("sweep.amplitudes: expected a list of 1 to 1000 amplitudes > 0")


def test_a_force_sweep_of_a_frame_draws_its_figure_without_a_fixed_base_curve(tmp_path, capsys):
    # the figure's fixed-base reference is a ground acceleration's: a force amplitude of
    # 5000 N was passed to it as 5000 m/s² (refused above 100 g: a traceback after the sweep)
    scene = tmp_path / "f.toml"
    scene.write_text('[scene]\nfidelity = "rigid"\n[force]\nkind = "harmonic"\ndofs = [0]\n'
                     "amplitude = 5000.0\nfrequency = 1.0\nn_periods = 5\n")  # fmt: skip
    out = tmp_path / "o"
    argv = ["sweep", str(scene), "--points", "2", "--fmin", "1", "--fmax", "1.1", "--out"]
    assert main([*argv, str(out)]) == 0
    assert (out / "sweep.png").stat().st_size > 0 and (out / "sweep.csv").is_file()


SETBACK = (
    """[frame]
name = "setback"
kind = "explicit"
nodes = [[0.0,0.0],[6.0,0.0],[12.0,0.0],[0.0,4.0],[6.0,4.0],[12.0,4.0],[0.0,8.0],[6.0,8.0]]
elements = [[0,3],[1,4],[2,5],[3,4,1],[4,5,1],[3,6],[4,7],[6,7,1]]
base_nodes = [0,1,2]
node_mass = [0,0,0,5000,5000,5000,4000,4000]
zeta = [0.02]
"""
    + PORTAL_SECTIONS
)


def test_a_frame_with_a_setback_runs_without_drift_ratios_and_says_so(tmp_path, capsys):
    # two bays below, one above: no column line runs through every level, and every run
    # ended after its integration in a TypeError (output dofs of no column joints)
    frame = tmp_path / "setback.toml"
    frame.write_text(SETBACK)
    for extra in ([], ["--fixed-base"], ["--fidelity", "full"]):
        out = tmp_path / f"o{len(extra)}"
        argv = ["run", "--frame", str(frame), "--t-end", "1", "--json", "--no-figures"]
        assert main([*argv, *extra, "--out", str(out)]) == 0
        s = json.loads(capsys.readouterr().out)
        assert "idr_max" not in s and s["floor_acc_max_mps2"] > 0
        assert any("no regular column lines" in n for n in s["notes"])
    from nsdyn import load_frame
    from nsdyn.periodic import fixed_base_response

    r = fixed_base_response(load_frame(str(frame)), 1.0, [0.5, 1.0])
    assert np.isnan(r["idr"]).all() and np.all(r["acc"] > 0)


def test_a_records_units_are_given_on_the_command_line(tmp_path, capsys, one_line):
    # a plain file in gal could not be run as such without a scene file: it ran as m/s²
    # (PGA 250 m/s², "probably in cm/s²") and stopped at an uplift. --units gal reads it as
    # the scene's [motion] units does: PGA 2.5 m/s² (250 gal, the file's largest sample)
    t = np.arange(0.0, 2.0, 0.01)
    a = 250.0 * np.sin(2 * np.pi * t)
    np.savetxt(tmp_path / "gal.txt", np.column_stack([t, a]))
    argv = ["run", "--record", str(tmp_path / "gal.txt"), "--no-figures", "--json"]
    assert main([*argv, "--units", "gal", "--out", str(tmp_path / "o")]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["pga_mps2"] == pytest.approx(np.abs(a).max() / 100.0, rel=1e-9)
    assert not any("units" in w for w in s.get("warnings", []))
    # a scene without a record file has no units to give: the flag is named, not the file
    cask = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "rocking-seed001-cask.toml"
    assert main(["run", str(cask), "--units", "g", "--out", str(tmp_path / "c")]) == 2
    one_line("motion.units (--units): the units of a record file; this scene reads none")
    orbit = cask.with_name("sdof-bidirectional-circular.toml")  # (it said "unknown field")
    assert main(["run", str(orbit), "--units", "g", "--out", str(tmp_path / "c")]) == 2
    one_line("--units: this scene's motion is harmonic", "--units applies to a scene driven "
             "by a record")  # fmt: skip


def test_a_step_budget_past_what_a_compiled_loop_counts_is_refused(tmp_path, capsys):
    # a count beyond 2^63 - 1 overflowed in the kernel's call (a traceback, exit 1): the
    # option, the scene field and the library argument say the largest instead
    big = "99999999999999999999"
    with pytest.raises(SystemExit) as e:
        main(["run", "--max-steps", big, "--t-end", "1", "--out", str(tmp_path / "o")])
    assert e.value.code == 2 and "at most 9223372036854775807" in capsys.readouterr().err
    scene = tmp_path / "s.toml"
    scene.write_text(f"[solver]\nmax_steps = {big}\n")
    out = tmp_path / "out"
    assert main(["run", str(scene), "--t-end", "1", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "solver.max_steps" in err and "at most 9223372036854775807" in err
    assert not out.exists()


@pytest.mark.parametrize(
    "kw, field", [({"max_steps": 10.5}, "max_steps"), ({"max_steps": True}, "max_steps"),
                  ({"h0": float("nan")}, "h0"), ({"h0": -1.0}, "h0"),
                  ({"max_step": 0}, "max_step")],
)  # fmt: skip
def test_step_options_of_simulate_that_mean_nothing_are_refused(kw, field):
    # 10.5 step attempts ran as 10, True as 1; a NaN first step ended in a step-size
    # failure blamed on the model ("nearly discontinuous")
    from nsdyn.models.isolated.scene import build_scene, load_scene
    from nsdyn.solve.transient import simulate

    system, motion = build_scene(load_scene())
    with pytest.raises(ValueError, match=rf"^{field}: expected"):
        simulate(system, motion, t_end=0.1, **kw)


def test_a_files_own_bad_end_is_not_blamed_on_the_flag_given_beside_it(tmp_path, capsys):
    # the file's t_end = -1 is refused (a file's own end stays checked) but its message
    # read "motion.t_end (--t-end): ... got -1", pointing at a flag whose value was 1
    scene = tmp_path / "s.toml"
    scene.write_text("[motion]\nt_end = -1\n")
    assert main(["run", str(scene), "--t-end", "1", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "motion.t_end: expected a positive number, got -1" in err and "(--t-end)" not in err


@pytest.mark.parametrize(
    ("isolation", "said"),
    [
        ('law = "arctan"\n', "isolation.k_lam, c, mu not given: the seed office's design values "
         "(k_lam = 50000 N/m, c = 10000 N s/m, mu = 0.03, per isolator) are used"),
        ("k_lam = 1e5\nmu = 0.05\n", "isolation.c not given: the seed office's design values "
         "(c = 10000 N s/m, per isolator) are used, sized for the office-11 frame"),
        ("k_lam = 1e5\nmu = 0.05\nc = 0.0\n", None),
        ('law = "none"\nk_lam = 1e5\nc = 0.0\n', None),  # (no friction: no mu to give)
    ],
)  # fmt: skip
def test_an_own_frame_on_the_default_isolators_is_noted(isolation, said, tmp_path, capsys):
    # a frame of the user's own whose scene gave no k_lam, c or mu ran on the default scene's
    # (the office's design values, sized for its 6.9 MN), without a word; a law without
    # friction needs no mu
    frame = tmp_path / "myportal.toml"
    frame.write_text((Path(__file__).resolve().parents[2] / "frames/portal.toml").read_text())
    scene = tmp_path / "s.toml"
    scene.write_text(f'[scene]\nframe = "myportal.toml"\nfidelity = "rigid"\n'
                     f"[isolation]\n{isolation}[motion]\nt_end = 0.1\n")  # fmt: skip
    assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "o")]) == 0
    notes = [x for x in capsys.readouterr().err.splitlines() if "not given" in x]
    assert len(notes) == (0 if said is None else 1)
    if said:
        assert notes[0].startswith(f"nsdyn run: note: {said}")
        assert notes[0].endswith("give your isolators' own in [isolation]")
    # the office frame (the values' own design) is not noted, by name or by its file's path;
    # the bundled portal is, as its copy is
    office = Path(__file__).resolve().parents[2] / "frames/office-11.toml"
    for frame, noted in (("office-11", False), (str(office), False), ("portal", said)):
        scene.write_text(f'[scene]\nframe = "{frame}"\nfidelity = "rigid"\n[isolation]\n'
                         f'{isolation}[motion]\nt_end = 0.1\n')  # fmt: skip
        assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "o2")]) == 0
        assert ("not given" in capsys.readouterr().err) == bool(noted)


def test_a_misspelt_option_before_any_command_is_named(one_line):
    # `nsdyn --versoin` said "the following arguments are required: COMMAND"; a subcommand's
    # misspelt flag was named with the closest one, and now so is the script's own
    with pytest.raises(SystemExit) as done:
        main(["--versoin"])
    assert done.value.code == 2
    one_line("unrecognized option '--versoin'", "did you mean '--version'?")


def test_a_record_given_for_a_frame_is_named_as_a_record(one_line):
    # `nsdyn modes records/….csv` said "not valid TOML: Expected '=' after a key", where a
    # scene command names the record as what it is
    record = Path(__file__).resolve().parents[2] / "records" / "synthetic-kt-20s.csv"
    assert main(["modes", str(record)]) == 2
    one_line(f"{record}: not a frame (TOML) file; a ground-motion record goes in a scene's")


@pytest.mark.parametrize("command", ["run", "uplift", "spectrum"])
def test_a_bundled_frames_name_given_as_the_scene_is_named_as_a_frame(command, one_line):
    # `nsdyn uplift office-11` said "no such scene file" (export named it as a frame)
    assert main([command, "office-11"]) == 2
    one_line('office-11: a bundled frame, not a scene; a scene names it as [scene] frame = '
             '"office-11"')  # fmt: skip
    # a path whose .toml sits beside it is no bundled frame: no such scene file
    stem = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "deck-fps4-3c"
    assert main([command, str(stem)]) == 2
    one_line(f"{stem}: no such scene file")


def test_a_note_of_the_scene_and_of_the_library_on_one_field_is_said_once(tmp_path, capsys):
    # a fixed step coarser than T/20 of a harmonic force is noted by the scene's check
    # (solver.dt) and by the run's (dt): said once, on stderr and in the JSON notes
    scene = Path(__file__).resolve().parents[2] / "examples/scenes/isolated-coulomb-force.toml"
    text = scene.read_text().replace('method = "event"', 'method = "genalpha"\ndt = 0.04')
    src = tmp_path / "coarse.toml"
    src.write_text(text.replace('law = "switch"', 'law = "arctan"'))
    assert main(["run", str(src), "--out", str(tmp_path / "o"), "--no-figures", "--json"]) == 0
    cap = capsys.readouterr()
    notes = [n for n in json.loads(cap.out)["notes"] if "of the forcing period" in n]
    assert len(notes) == 1 and notes[0].startswith("solver.dt: a fixed step of 0.04 s is T/16.7")
    assert cap.err.count("of the forcing period") == 1


def test_a_run_out_of_memory_is_one_line_naming_the_outputs(monkeypatch, one_line):
    # a 3D building's cb run at dt_out = 1e-5 s (4e6 outputs) ended in numpy's
    # _ArrayMemoryError traceback; the command says it in one line, exit 2 (an input to change)
    from nsdyn.cli import run as run_command

    def no_memory(args):
        raise MemoryError("Unable to allocate 1007. MiB for an array with shape (4000001, 33)")

    monkeypatch.setattr(run_command, "run", no_memory)
    assert main(["run", "--no-figures"]) == 2
    one_line("out of memory (Unable to allocate 1007. MiB", "a larger solver.dt_out")


def test_notes_are_merged_only_when_they_name_one_field_two_ways():
    # a scene's key and the library's argument (solver.dt, dt) name one field: said once;
    # two files, or two fields ending alike, are two notes
    from nsdyn.cli.args import same_said

    assert same_said("solver.dt: a fixed step of 0.04 s", "dt: a fixed step of 0.04 s")
    assert not same_said("a.toml: solver.dt: X", "b.toml: solver.dt: X")
    assert not same_said("rec1.csv: 3 samples", "rec2.csv: 3 samples")
    assert not same_said("motion.dt: a step", "solver.dt: a step")
    assert not same_said("solver.dt: a step", "dt: another step")


def test_a_rerun_of_a_sweep_without_fallback_still_says_its_skipped_frequency(
    tmp_path, monkeypatch, capsys
):
    # a finished --no-fallback sweep's skipped frequency was not in its checkpoint: a rerun
    # resumed every point, said nothing of it and ended with status 0 (the first said 3)
    import json

    import nsdyn.periodic.continuation as cont

    solve = cont._solve_point

    def first_fails(problem, f, *a, **kw):  # (shooting's failure at the grid's first point)
        return (None, "forced failure") if f < 0.5 else solve(problem, f, *a, **kw)

    monkeypatch.setattr(cont, "_solve_point", first_fails)
    scene = tmp_path / "sdof.toml"
    scene.write_text(SDOF.replace("MU", "0.05"))
    argv = ["sweep", str(scene), "--amplitudes", "1", "--fmin", "0.4", "--fmax", "1.6",
            "--points", "3", "--no-fallback", "--workers", "1", "--json",
            "--out", str(tmp_path / "o")]  # fmt: skip
    for _ in range(2):  # the run, then the rerun resuming every point
        assert main(argv) == 3
        (amp,) = json.loads(capsys.readouterr().out)["amplitudes"]
        assert amp["skipped_hz"] == [0.4] and amp["skipped_why"] == ["forced failure"]
    # an interrupted run's checkpoint (written as it goes) keeps no reason: the gap is
    # found on the grid, and said
    (ckpt,) = (tmp_path / "o").glob(".sweep-A*.ckpt.json")
    data = json.loads(ckpt.read_text())
    data.pop("skipped")
    ckpt.write_text(json.dumps({**data, "complete": False}))
    assert main(argv) == 3
    (amp,) = json.loads(capsys.readouterr().out)["amplitudes"]
    assert amp["skipped_hz"] == [0.4] and "interrupted" in amp["skipped_why"][0]


SDOF = ('[structure]\nkind = "matrices"\nM = [[1000.0]]\nC = [[0.0]]\nK = [[0.0]]\n'
        "iso_dofs = [0]\ninfluence = [1.0]\nweight = 9810.0\n[isolation]\n"
        'k_lam = 4.0e4\nc = 800.0\nmu = MU\nlaw = "arctan"\n')  # fmt: skip


def _cell(v):  # a sweep.csv cell as the sweep wrote it: true/false, empty for None, numbers
    if v in ("true", "false", ""):
        return {"true": True, "false": False, "": None}[v]
    try:
        return float(v)
    except ValueError:
        return v


def test_a_frictionless_sweep_has_no_stick_and_a_failed_fallback_is_no_fallback(tmp_path, capsys):
    # mu = 0 under the arctan law read its slow samples as stick ("stick-slip orbit ...
    # confirm with --friction switch"); a point the stepped sweep did not settle was counted
    # in fallback_points, which counts the points it answered
    import csv
    import json

    from nsdyn.studies.sweep import summarise

    scene = tmp_path / "sdof.toml"
    scene.write_text(SDOF.replace("MU", "0.0"))
    argv = ["sweep", str(scene), "--amplitudes", "1", "--fmin", "0.5", "--fmax", "2",
            "--points", "4", "--workers", "1", "--json", "--out", str(tmp_path / "o")]  # fmt: skip
    assert main(argv) == 0
    (amp,) = json.loads(capsys.readouterr().out)["amplitudes"]
    assert amp["stick_all_period_above_hz"] is None and not amp.get("notes")
    with open(tmp_path / "o" / "sweep.csv", newline="") as fh:
        rows = [{k: _cell(v) for k, v in r.items()} for r in csv.DictReader(fh)]
    rows[1].update(method="sweep", converged=False)
    rows[2].update(method="sweep", converged=True)
    r = {"A": 1.0, "rows": rows, "resumed_points": 0, "bifurcations": []}
    s = summarise(r | dict.fromkeys(("wall_s", "wall_below_0.1Hz_s", "wall_above_0.1Hz_s"), 0.0))
    assert s["fallback_points"] == 1 and s["unconverged_points"] == 1


def test_a_number_taken_for_a_scene_is_said_to_be_one(tmp_path, one_line):
    # "--amplitudes 0.5 1" read 1 as the scene: "1: no such scene file"
    assert main(["sweep", "--amplitudes", "0.5", "1", "--out", str(tmp_path / "o")]) == 2
    one_line("1: no such scene file; a number: an option's values are comma-separated "
             "(--amplitudes 0.5,1)")  # fmt: skip


def test_an_arclength_curve_keeps_the_skipped_frequencies_its_checkpoint_holds(tmp_path):
    # a finished arclength --no-fallback curve's rerun stops at once (its last point is
    # fmax) and saved an empty list over the kept one: the rerun said none, status 0
    import json
    from types import SimpleNamespace

    from nsdyn.studies.sweep_points import skipped_before

    ckpt = tmp_path / "c.json"
    ckpt.write_text(json.dumps({"skipped": [[0.8, "forced"], [3.0, "above"]]}))
    settings = SimpleNamespace(fallback=False, continuation="arclength")
    start = [SimpleNamespace(f=0.5), SimpleNamespace(f=2.0)]
    assert skipped_before(ckpt, start, settings) == [(0.8, "forced")]
    assert skipped_before(ckpt, start, SimpleNamespace(fallback=True)) == []
