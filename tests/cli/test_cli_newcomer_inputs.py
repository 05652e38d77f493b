"""More commands tried as a newcomer tries them: each mistake is refused in one line naming
the file and field and what is expected (exit 2), before anything runs or is written.

Source of the expected behaviour: the command-line conventions of nsdyn.cli.app (input errors
exit 2 with one line) and docs/reference/cli.md; the tolerance range from the adaptive step's
error test (a relative tolerance of 1 or more accepts any step: err <= rtol |y| + atol is met
by an error as large as the state itself).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from nsdyn.cli import main

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
@pytest.mark.parametrize("value", [1, 2.5])
def test_a_relative_tolerance_of_one_or_more_is_refused(tmp_path, scene, key, value, one_line):
    src = SCENES / scene if scene else tmp_path / "empty.toml"
    if scene is None:
        src.write_text("")
    bad = _with_solver_field(src, tmp_path / f"bad-{src.name}", key, value)
    out = tmp_path / "out"
    rc = main(["run", str(bad), "--out", str(out), "--no-figures"])
    assert rc == 2
    one_line(str(bad), f"solver.{key}", f"0 < solver.{key} < 1")
    assert not out.exists()


def test_the_library_refuses_the_same_tolerances():
    from nsdyn.models.isolated.scene import build_scene, load_scene
    from nsdyn.models.rocking.block import RockingBlock, simulate_rocking
    from nsdyn.solve.transient import simulate

    system, motion = build_scene(load_scene())
    with pytest.raises(ValueError, match="rtol: expected a relative tolerance 0 < rtol < 1"):
        simulate(system, motion, t_end=1.0, rtol=1.0)
    with pytest.raises(ValueError, match="tol: expected a relative tolerance 0 < tol < 1"):
        simulate_rocking(RockingBlock(width=0.5, height=2.0), None, t_end=1.0, tol=3.0)


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
    assert out == {"status": 2, "error": "--fmax (1) must exceed --fmin (2)"}
    assert main(["uplift", "no-such-scene.toml", "--json"]) == 2
    assert json.loads(capsys.readouterr().out)["status"] == 2


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


def test_a_misspelt_keep_ends_the_study_with_no_row_written(tmp_path, one_line):
    study = _study(tmp_path, ["x_iso_maxx", "idr_max"])
    out = tmp_path / "out"
    assert main(["study", str(study), "--out", str(out)]) == 2
    err = one_line("study.keep: 'x_iso_maxx' (did you mean 'x_iso_max_m'?)")
    assert str(study) in err
    assert not list(out.glob("*.csv")) if out.exists() else True


def test_a_constraint_on_a_result_not_kept_says_to_keep_it(tmp_path, one_line):
    analysis = '[analysis.design]\nobjectives = ["idr_max"]\nconstraints = { x_iso_max_m = 0.4 }\n'
    study = _study(tmp_path, ["idr_max"], analysis)
    assert main(["study", str(study), "--out", str(tmp_path / "o")]) == 2
    one_line("'x_iso_max_m' is a result the study does not keep", "study.keep")


@pytest.mark.parametrize("width, rocks", [(1.41, True), (1.42, False)])
def test_a_block_too_squat_for_housner_restitution_is_refused(
    tmp_path, capsys, width, rocks, one_line
):
    """Housner's r = 1 - 1.5 sin² alpha (seed 003) is positive only for tan alpha =
    width/height < √2 = 1.41421...; beyond, the run would use a negative r."""
    scene = tmp_path / "squat.toml"
    scene.write_text(
        '[scene]\nkind = "rocking"\nmodel = "block"\n'
        f"[block]\nwidth = {width}\nheight = 1.0\n"
        '[motion]\npulse = "sine"\na_p_g = 2.0\nf_p = 1.0\nt_end = 0.5\n'
    )
    rc = main(["run", str(scene), "--out", str(tmp_path / "o"), "--no-figures"])
    if rocks:
        assert rc == 0
        capsys.readouterr()
    else:
        assert rc == 2
        one_line(str(scene), "block.r:", "give r")


def test_a_frame_that_cannot_stand_on_its_isolators_is_input_not_uplift(tmp_path, one_line):
    """One base node under a two-column portal: the static normal force under gravity is not
    positive, which no excitation changes (exit 2 naming the frame file, not exit 3)."""
    text = (ROOT / "frames" / "portal.toml").read_text()
    lines = [ln for ln in text.splitlines() if not ln.startswith("base_nodes")]
    i = lines.index("[frame]") + 1
    frame = tmp_path / "one-foot.toml"
    frame.write_text("\n".join([*lines[:i], "base_nodes = [0]", *lines[i:]]) + "\n")
    rc = main(["run", "--frame", str(frame), "--out", str(tmp_path / "o"), "--no-figures"])
    assert rc == 2
    one_line(str(frame), "under gravity alone", "cannot stand")


def test_misplaced_fields_and_files_are_named_as_what_they_are(tmp_path, one_line):
    big = tmp_path / "big.toml"
    big.write_text("[solver]\ndt_out = 100.0\n")
    assert main(["run", str(big), "--out", str(tmp_path / "o"), "--no-figures"]) == 2
    one_line(f"{big}: solver.dt_out:", "longer than the run")
    scene = str(SCENES / "deck-fps4-3c.toml")
    assert main(["run", "--frame", scene, "--out", str(tmp_path / "o"), "--no-figures"]) == 2
    one_line(f"{scene}: a scene file", "not a frame file", f"nsdyn run {scene}")
    assert main(["export", "opensees", "office-11", "-o", str(tmp_path / "m.py")]) == 2
    one_line("office-11: a bundled plane frame, not a scene")


def test_a_large_closure_says_what_it_measures():
    """The closure is a trapezoidal check on the output grid (second order in dt_out)."""
    from nsdyn.cli.run import CLOSURE_NOTE, _closure_cell

    assert _closure_cell(0.5 * CLOSURE_NOTE) == f"{0.5 * CLOSURE_NOTE:.2e}"
    assert "dt_out" in _closure_cell(2 * CLOSURE_NOTE)
