"""Commands tried as a newcomer tries them: each mistake ends in one line naming the file,
field or option and what is expected (exit 2), before anything is computed or written; an
interrupt says truthfully how to go on (exit 130).

Source of the expected behaviour: the command-line conventions of nsdyn.cli.app (usage and
input errors exit 2 with one line; SIGINT/SIGTERM exit 130) and docs/reference/cli.md.
"""

from __future__ import annotations

import json
import os
import signal
import textwrap
from argparse import Namespace
from pathlib import Path

import pytest

from nsdyn.cli import main
from nsdyn.cli.app import _interrupt_line, build_parser
from nsdyn.models.scenefile import read_toml
from nsdyn.studies.scenes import result_columns


@pytest.mark.parametrize("method", ["radau", "dopri5", "event"])
def test_a_step_for_an_adaptive_method_is_refused_before_the_run(tmp_path, method, one_line):
    """dt is the fixed-step methods' step; an adaptive method chooses its own."""
    out = tmp_path / "out"
    rc = main(["run", "--method", method, "--dt", "0.02", "--out", str(out), "--no-figures"])
    assert rc == 2
    one_line("solver.dt", "--dt", repr(method), "genalpha")
    assert not out.exists()  # refused before the output folder is made


def test_auto_choosing_an_adaptive_method_refuses_dt_too(tmp_path, one_line):
    rc = main(["run", "--dt", "0.02", "--out", str(tmp_path / "o"), "--no-figures", "--json"])
    assert rc == 2
    one_line("solver.dt", "'radau'")


def test_a_record_that_is_zero_everywhere_names_the_scene_and_field(tmp_path, capsys):
    (tmp_path / "zeros.csv").write_text("t,a\n0,0\n0.01,0\n0.02,0\n")
    scene = tmp_path / "z.toml"
    scene.write_text('[motion]\nrecord = "zeros.csv"\nunits = "m/s2"\npga = 3.0\n')
    rc = main(["run", str(scene), "--out", str(tmp_path / "o"), "--no-figures"])
    assert rc == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and "zero at every sample" in err[0]  # the reader's warning
    assert f"{scene}: motion.pga:" in err[1] and "zero at every sample" in err[1]


def test_files_a_scene_names_are_read_beside_it_from_any_folder(tmp_path, monkeypatch):
    """A scene and its record in one folder run the same from any current folder."""
    d = tmp_path / "project"
    d.mkdir()
    (d / "rec.csv").write_text("t,a\n0,0\n0.01,1\n")
    (d / "s.toml").write_text('[motion]\nrecord = "rec.csv"\n[scene]\nframe = "office-11"\n')
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    cfg = read_toml(d / "s.toml")
    assert cfg["motion"]["record"] == str((d / "rec.csv").resolve())
    assert cfg["scene"]["frame"] == "office-11"  # a bundled name is kept as written
    monkeypatch.chdir(d)  # from the scene's own folder the name is kept as written
    assert read_toml("s.toml")["motion"]["record"] == "rec.csv"


def test_options_may_come_before_a_command_s_positionals():
    args, extra = build_parser("export").parse_known_args(
        ["export", "opensees", "--t-end", "2", "scene.toml", "-o", "y.py"]
    )
    assert not extra and args.scene == "scene.toml" and args.t_end == 2.0


def test_a_kept_field_a_summary_lacks_is_an_empty_cell_with_the_nearest_name():
    from nsdyn.studies.scenes import missing_kept, missing_names

    summary = {"x_iso_max_m": 0.1, "idr_max": 1e-3}
    assert result_columns(summary, ["idr_max"]) == {"idr_max": 1e-3}
    assert missing_kept(summary, ["idr_max"]) == ""
    cols = result_columns(summary, ["x_iso_mx_m", "idr_max"], "s.toml")
    assert cols == {"x_iso_mx_m": None, "idr_max": 1e-3}
    note = missing_kept(summary, ["x_iso_mx_m", "idr_max"], "s.toml")
    assert note.startswith("s.toml: study.keep: not in this task's run summary")
    assert "did you mean 'x_iso_max_m' for 'x_iso_mx_m'?" in note
    assert missing_names(note) == ["x_iso_mx_m"]  # the hint's name is not read as missing
    # a summary of many fields: the note fits the row's error cell and ends at a whole name
    from nsdyn.studies.scenes import ERROR_CHARS

    many = {f"field_{j:03d}_of_a_long_summary": 1.0 for j in range(60)}
    note = missing_kept(many, ["x"], "s.toml")
    assert len(note) <= ERROR_CHARS and note.endswith(", ... (60 in all)")
    assert note.split("its fields: ")[1].split(", ")[-2] in many  # the last one shown is whole


@pytest.mark.parametrize(
    "argv, needles",
    [
        (["uplift", "examples/scenes/rocking-seed003-column.toml"], ["scene.kind", "'rocking'"]),
        (["uplift", "examples/scenes/deck-fps4-3c.toml"], ["scene.kind", "'deck'"]),
        (["sweep", "examples/scenes/deck-fps4-3c.toml", "--fidelity", "cb"], ["--fidelity"]),
        (["modes", "examples/scenes/rocking-seed003-column.toml"], ["'rocking'", "frame"]),
        (["modes", "examples/scenes/isolated-shear-3storey.toml"], ["without a frame"]),
    ],
)
def test_a_scene_of_the_wrong_kind_is_named_as_such(tmp_path, argv, needles, one_line):
    root = os.path.dirname(os.path.dirname(os.path.dirname(__file__)))
    argv = [os.path.join(root, a) if a.endswith(".toml") else a for a in argv]
    assert main([*argv, "--out", str(tmp_path / "o")]) == 2
    one_line(*needles)


@pytest.mark.parametrize(
    "argv, needles",
    [  # a law and a method that do not go together: refused, never one of them dropped
        (["--friction", "arctan", "--method", "event"], ["--friction arctan", "switch model"]),
        # it ran the switch law silently, exit 0: x_iso 0.276 m where no friction gives 0.319
        (["--friction", "none", "--method", "event"], ["--friction none", "switch model"]),
        (["--friction", "switch", "--method", "genalpha-lowrank"],
         ["solver.method", "'genalpha-lowrank' takes the arctan law"]),
    ],
)  # fmt: skip
def test_a_friction_law_its_method_cannot_integrate_is_refused(tmp_path, argv, needles, one_line):
    assert main(["run", *argv, "--out", str(tmp_path / "o")]) == 2
    one_line(*needles)
    assert not (tmp_path / "o").exists()  # refused before the model's build


def test_modes_of_a_scene_lists_the_frame_it_names(capsys, tmp_path):
    scene = tmp_path / "s.toml"
    scene.write_text('[scene]\nframe = "office-11"\n')
    assert main(["modes", str(scene), "--json"]) == 0
    assert '"frame": "office-11"' in capsys.readouterr().out


def test_modes_of_a_scene_of_tables_alone_takes_its_frame_and_k_lam(capsys, tmp_path):
    # a scene `nsdyn run` runs without a [scene] table (the default frame), and its
    # [isolation] k_lam in f_bis = sqrt(2 K_lam / M_s) / 2 pi (seed 004 eq. 28): a scene's
    # 2e5 N/m against the default 5e4 doubles it; --klam still wins
    scene = tmp_path / "s.toml"
    scene.write_text("[isolation]\nk_lam = 2e5\n")
    assert main(["modes", "--json"]) == 0
    plain = json.loads(capsys.readouterr().out)
    assert main(["modes", str(scene), "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["frame"] == "office-11" and s["k_lam_n_per_m"] == 2e5
    assert s["f_bis_hz"] == pytest.approx(2 * plain["f_bis_hz"], rel=1e-12)
    assert main(["modes", str(scene), "--json", "--klam", "5e4"]) == 0
    assert json.loads(capsys.readouterr().out)["f_bis_hz"] == plain["f_bis_hz"]
    scene.write_text("[isolation]\nk_lam = [1e5, 3e5]\n")  # per isolator: their mean, 2e5
    assert main(["modes", str(scene), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["f_bis_hz"] == pytest.approx(s["f_bis_hz"])


@pytest.mark.parametrize("made", [True, False])
def test_a_sweep_stopped_before_its_first_point_leaves_no_folder(tmp_path, monkeypatch, made):
    """Interrupted before any point finished, a sweep removes the folders it made (left empty)
    and says a rerun starts over; a folder that was there before stays."""
    import nsdyn.cli.sweep as cs

    def stop(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(cs, "prepare_kernels", lambda *a: 0.0)
    monkeypatch.setattr(cs, "sweep_amplitudes", stop)
    out = tmp_path / "new" / "deep" if made else tmp_path
    assert main(["sweep", "--points", "2", "--out", str(out), "--no-figures"]) == 130
    assert not (tmp_path / "new").exists() if made else tmp_path.is_dir()


def test_the_interrupt_line_says_how_each_command_goes_on(tmp_path, monkeypatch):
    import nsdyn.cli.run as cr

    monkeypatch.setattr(cr, "FINISHED", [])  # (no run of this process finished: a command's)
    out = tmp_path / "o"
    run = Namespace(command="run", out=str(out))
    assert "starts over" in _interrupt_line(run)  # stopped before its first checkpoint
    out.mkdir()
    (out / ".run-checkpoint.npz").write_bytes(b"")
    assert "--resume" in _interrupt_line(run)
    sweep = Namespace(command="sweep", out=str(tmp_path / "s"))
    assert "before its first checkpoint, a rerun starts over" in _interrupt_line(sweep)
    (tmp_path / "s").mkdir()
    (tmp_path / "s" / ".sweep-A1.ckpt.json").write_text("{}")
    assert "rerun the same command to resume" in _interrupt_line(sweep)
    # --restart discards the checkpoints: rerun as typed would start over again; the folder's
    # sweep.csv is the run before's (it said "files on disk are complete")
    (tmp_path / "s" / "sweep.csv").write_text("f\n")
    line = _interrupt_line(Namespace(command="sweep", out=str(tmp_path / "s"), restart=True))
    assert line.endswith("complete (its sweep.csv is an earlier run's), rerun it without "
                         "--restart to resume from them, with it to start over")  # fmt: skip
    assert "no checkpoint" in _interrupt_line(Namespace(command="uplift"))
    # a deck's or 3D building's sweep keeps its own checkpoints (it said 'starts over')
    plane = Namespace(command="sweep", out=str(tmp_path / "p"))
    (tmp_path / "p").mkdir()
    (tmp_path / "p" / ".sweep-plane-A0.981.ckpt.json").write_text("{}")
    assert "rerun the same command to resume" in _interrupt_line(plane)
    # a run of a scene kind that keeps no checkpoint says so (not 'before its first')
    deck = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "deck-fps4-3c.toml"
    line = _interrupt_line(Namespace(command="run", out=str(tmp_path / "d"), scene=deck))
    assert "a deck scene's run keeps no checkpoint, a rerun starts over" in line


def test_an_interrupted_uplift_says_the_files_in_its_folder_are_not_its_own(
    tmp_path, monkeypatch, capsys
):
    """An uplift search writes its table and figure once done; interrupted, it wrote none, and
    an earlier run's uplift.json in the same folder (a different band) stays as it was. The
    line said 'files on disk are complete', read as this run's results."""
    import nsdyn.cli.sweep as cs
    import nsdyn.periodic.uplift as pu

    def stop(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(cs, "prepare_kernels", lambda *a: 0.0)
    monkeypatch.setattr(pu, "uplift_boundary", stop)
    earlier = tmp_path / "uplift.json"
    earlier.write_text('{"earlier": true}\n')
    assert main(["uplift", "--points", "2", "--out", str(tmp_path), "--no-figures"]) == 130
    assert earlier.read_text() == '{"earlier": true}\n'
    err = capsys.readouterr().err
    assert f"it wrote no file, and any in {tmp_path} are an earlier run's" in err
    # under --json the interrupt is an outcome on stdout too (it printed nothing)
    assert main(["uplift", "--points", "2", "--out", str(tmp_path), "--json"]) == 130
    rep = json.loads(capsys.readouterr().out)
    assert rep["status"] == 130 and rep["error"].startswith("interrupted before writing")


def test_a_run_stopped_after_it_finished_says_so_and_leaves_no_earlier_figure(
    tmp_path, monkeypatch, capsys
):
    # stopped while drawing its figure, a run left its new histories beside the earlier
    # run's figure, and said it "stopped before its first checkpoint"
    import nsdyn.plot

    def stop(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(nsdyn.plot, "plot_transient", stop)
    (tmp_path / "run.png").write_bytes(b"an earlier run's figure")
    assert main(["run", "--t-end", "1", "--out", str(tmp_path)]) == 130
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run-histories.npz"]
    assert "interrupted after the run finished: its histories are" in capsys.readouterr().err


def test_an_interrupted_rerun_s_json_says_the_checkpoint_it_discarded(tmp_path, monkeypatch,
                                                                      capsys):  # fmt: skip
    # a rerun without --resume discards an interrupted run's checkpoint and says so; its own
    # interruption's --json outcome carried no note: the checkpoint gone without a word
    import nsdyn.solve.transient
    from nsdyn.cli.run_resume import CHECKPOINT

    def stop(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(nsdyn.solve.transient, "simulate", stop)  # (run.py imports it late)
    (tmp_path / CHECKPOINT).write_bytes(b"an interrupted run's state")
    assert main(["run", "--t-end", "1", "--out", str(tmp_path), "--json"]) == 130
    rep = json.loads(capsys.readouterr().out)
    assert rep["status"] == 130 and not (tmp_path / CHECKPOINT).exists()
    assert any(n.startswith("starting afresh; the checkpoint an interrupted run left in")
               for n in rep["notes"]), rep  # fmt: skip


def test_an_error_left_by_a_swallowed_interrupt_is_an_interrupt(monkeypatch, capsys):
    """numba's compiler can swallow Ctrl-C in a callback and fail later with an error of its
    own ('no compiled object yet'): after a signal, the command reports the interrupt."""
    import nsdyn.cli.modes as modes

    def swallowed(args):
        try:
            os.kill(os.getpid(), signal.SIGINT)
            signal.pthread_sigmask(signal.SIG_BLOCK, [])  # let the handler run here
        except KeyboardInterrupt:
            pass  # what a C callback does with it
        raise RuntimeError("no compiled object yet for <Library>")

    monkeypatch.setattr(modes, "run", swallowed)
    assert main(["modes"]) == 130
    assert "interrupted" in capsys.readouterr().err


def _study(tmp_path, tables: str):
    """A two-task study of the default scene with ``tables`` added."""
    study = tmp_path / "s.toml"
    grid = '[parameters]\n"isolation.mu" = [0.02, 0.05]\n[records]\nnames = ["synthetic-wn-40s"]\n'
    study.write_text(f'[study]\nname = "s"\n{grid}{textwrap.dedent(tables)}')
    return study


def test_a_study_step_for_an_adaptive_method_is_refused_before_it_starts(tmp_path, one_line):
    study = _study(tmp_path, '[base.solver]\nmethod = "radau"\ndt = 0.01\n')
    assert main(["study", str(study), "--out", str(tmp_path / "o")]) == 2
    one_line("solver.dt", "'radau'")


@pytest.mark.parametrize(
    "argv, needles",
    [
        (["run", "--fixed-base", "--fidelity", "cb"], ["--fixed-base", "--fidelity"]),
        (["run", "--fixed-base", "--friction", "switch"], ["--friction"]),
        (["sweep", "--amplitudes", "1,1"], ["distinct amplitudes"]),
        (["bench", "rocking", "--curve"], ["--curve", "'rocking'"]),
        (["bench", "cylinder", "--repeats", "3"], ["--repeats", "'cylinder'"]),
    ],
)
def test_an_option_that_cannot_apply_is_refused_not_ignored(tmp_path, argv, needles, one_line):
    try:
        status = main([*argv, "--out", str(tmp_path / "o")])
    except SystemExit as e:  # a usage error, found by the parser
        status = e.code
    assert status == 2
    one_line(*needles)
    assert not (tmp_path / "o").exists()


def test_a_folder_given_as_the_scene_is_named_as_a_folder(tmp_path, one_line):
    assert main(["run", str(tmp_path), "--out", str(tmp_path / "o")]) == 2
    one_line(f"{tmp_path}: a folder; expected a scene file")


def _short_scene(tmp_path):
    (tmp_path / "short.csv").write_text(
        "t,a\n" + "".join(f"{i / 100},{i % 3}\n" for i in range(11))
    )
    scene = tmp_path / "s.toml"
    scene.write_text(
        '[scene]\nfidelity = "rigid"\n[motion]\nrecord = "short.csv"\nunits = "m/s2"\n'
    )
    return scene


def test_a_t_end_past_the_record_is_said(tmp_path, capsys):
    """The record ends at 0.1 s: a run asked to go to 1 s ends there and says so."""
    scene = _short_scene(tmp_path)
    assert (
        main(["run", str(scene), "--t-end", "1", "--no-figures", "--out", str(tmp_path / "o")]) == 0
    )
    err = capsys.readouterr().err
    assert "t_end = 1 s is past the record's end (0.1 s); the run ends there" in err
    assert err.count("t_end = 1 s") == 1  # once (a second note said it again)
    # a t_end within the record but between two samples: the other note, once
    main(["run", str(scene), "--t-end", "0.055", "--no-figures", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert err.count("t_end = 0.055 s is not a sample time of the record") == 1, err


def test_a_plain_rerun_says_it_discards_a_checkpoint(tmp_path, capsys):
    scene, out = _short_scene(tmp_path), tmp_path / "o"
    out.mkdir()
    (out / ".run-checkpoint.npz").write_bytes(b"")
    assert main(["run", str(scene), "--no-figures", "--out", str(out)]) == 0
    assert "starting afresh; the checkpoint an interrupted run left" in capsys.readouterr().err
    assert not (out / ".run-checkpoint.npz").exists()


def test_a_benchmark_without_a_report_prints_text_not_json():
    from nsdyn.cli.bench import _plain

    lines = _plain({"compile_s": 0.123456, "rows": [{"rtol": 1e-4, "n": 12}], "sub": {"ok": True}})
    assert lines == [
        "compile_s  0.1235",
        "rows:",
        "    rtol   n",
        "  0.0001  12",
        "sub:",
        "  ok  true",
    ]
    # rows without names (a contact benchmark's work-precision points) print aligned, not
    # as Python's lists ("['event', 0.0001, 69.59288100188132, ...]")
    lines = _plain({"wp": [("event", 1e-4, 69.592881), ("moreau", 1e-3, 3.2)]})
    assert lines == ["wp:", "   event  0.0001  69.59", "  moreau   0.001    3.2"]


def _status(argv) -> int:
    try:
        return main(argv)
    except SystemExit as e:  # a usage error, found by the parser
        return e.code


def _scene(name: str) -> str:
    root = os.path.dirname(os.path.dirname(os.path.dirname(__file__)))
    return os.path.join(root, "examples", "scenes", name)


@pytest.mark.parametrize(
    "argv, needles",
    [
        (["run", "--method", "genalpha", "--dt", "5", "--t-end", "2"], ["longer than the run"]),
        # a step over the record's samples: x_iso 1.79 m against 0.2765 (OpenSees, dt = 1 s),
        # a stop at a false uplift (the full frame, dt = 0.2 s)
        (
            ["run", "--method", "genalpha", "--dt", "0.02"],
            [
                "solver.dt (--dt): a fixed step of 0.02 s is longer than the record's sampling "
                "step 0.01 s"
            ],
        ),
        (
            ["run", "--fidelity", "full", "--method", "genalpha-lowrank", "--dt", "0.2"],
            ["solver.dt (--dt): a fixed step of 0.2 s", "expected at most 0.01 s"],
        ),
        # a cut-off the fidelity has not (it was ignored)
        (["run", "--fidelity", "full", "--fmax", "3"], ["--fmax: the Craig-Bampton cut-off"]),
        (["sweep", "--amplitudes", "1,,2"], ["separated by commas"]),
        (
            ["spectrum", "rocking-seed003-column.toml", "--rtol", "2"],
            ["from 2.2e-14", "to below 1"],
        ),
        (["run", "isolated-shear-3storey.toml", "--compare-fixed"], ["needs a frame"]),
        (["run", "deck-fps4-3c.toml", "--method", "radau"], ["--method"]),
        (["export", "opensees", "--modes", "3"], ["--modes: not used"]),
        (["modes", "office-11-3d", "--fmax", "1"], ["--fmax: the Craig–Bampton cut-off of"]),
        (["uplift", "isolated-shear-3storey.toml"], ["[structure]: no contact rows"]),
        # a period of 3e4 years: a slip of 1.9e4 m reported as converged (0.029 m quasi-static)
        (["sweep", "isolated-coulomb-force.toml", "--fmin", "1e-12", "--fmax", "1e-4"],
         ["--fmin: expected a forcing frequency in [1e-06, 10000] Hz"]),
        # a traceback after the whole curve: the lift-off orbits are shot on the arctan law
        (["sweep", "isolated-coulomb-force.toml", "--contact", "unilateral", "--points", "2"],
         ["--contact unilateral: its lift-off orbits are shot on the arctan law"]),
        # minutes of stepping (omega_p / p = 1e300), an eigen solve of 1e5 modes
        (["spectrum", "rocking-seed001-cask.toml", "--wmax", "1e300"],
         ["--wmax: expected a ratio omega_p / p from 0.01 to 1000"]),
        (["export", "opensees", "portal-3d", "--modes", "1000"], ["--modes: expected at most 200"]),
        # a traceback from the uplift probe's overflow (frame); every point failed (deck)
        (["sweep", "--amplitudes", "1e300", "--points", "2"],
         ["--amplitudes: expected ground acceleration amplitudes <= 1000 m/s² (100 g)"]),
        (["sweep", "sdof-bidirectional-sweep.toml", "--amplitudes", "1,2000", "--points", "2"],
         ["--amplitudes: expected ground acceleration amplitudes <= 1000", "got 2000"]),
    ],
)  # fmt: skip
def test_more_inputs_that_cannot_apply_are_refused(tmp_path, argv, needles, one_line):
    argv = [_scene(a) if a.endswith(".toml") else a for a in argv]
    assert _status([*argv, "--out", str(tmp_path / "o")]) == 2
    one_line(*needles)


def test_a_scene_t_end_past_the_record_is_said_for_a_deck(tmp_path, capsys):
    # the deck and 3D scenes ended at the record's end without a word (--t-end said it)
    text = open(_scene("deck-fps4-3c.toml"), encoding="utf-8").read()
    text = text.replace('record = "synthetic-wn-40s"', 'record = "synthetic-kt-20s"\nt_end = 100.0')
    scene = tmp_path / "deck.toml"
    scene.write_text(text)
    assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "o")]) == 0
    assert "note: t_end = 100 s is past the excitation's end (20 s); the run ends there" in (
        capsys.readouterr().err
    )


def test_a_record_starting_before_zero_reports_its_whole_duration(tmp_path, capsys):
    # t from -1 to 0.99 s: the summary read "duration 0.98 s" and dt_out 0.019999999999999574;
    # the scene's 0.02 s output step does not divide 1.99 s, and the run ends at the record's end
    import numpy as np

    t = np.arange(-100, 100) * 0.01
    rec = tmp_path / "neg.txt"
    np.savetxt(rec, np.c_[t, 0.5 * np.sin(3 * t)], header="units: m/s2", fmt="%.6f")
    out = tmp_path / "o"
    assert main(["run", "--record", str(rec), "--fidelity", "rigid", "--no-figures", "--out",
                 str(out)]) == 0  # fmt: skip
    assert "duration / output step               1.99 s / 0.02 s (t = -1 to 0.99 s)" in (
        capsys.readouterr().out
    )
    assert main(["run", "--record", str(rec), "--fidelity", "rigid", "--no-figures", "--out",
                 str(out), "--json"]) == 0  # fmt: skip
    s = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert (s["t_start_s"], s["t_end_s"], s["dt_out_s"]) == (-1.0, 0.99, 0.02)


def test_an_export_step_over_the_records_samples_is_refused(tmp_path, one_line):
    # the exported OpenSees run at dt = 1 s peaked at x_iso 1.79 m against 0.2765 (5 ms)
    out = tmp_path / "m.py"
    assert main(["export", "opensees", "--dt", "0.1", "-o", str(out)]) == 2
    one_line(
        "solver.dt (--dt): a fixed step of 0.1 s is longer than the record's sampling step 0.01 s"
    )
    assert not out.exists()


def test_a_file_of_another_kind_is_named_for_what_it_is(tmp_path, one_line):
    study = tmp_path / "s.toml"
    study.write_text('[study]\nname = "s"\n')
    assert main(["run", str(study)]) == 2
    one_line("a study file", f"nsdyn study {study}")
    assert main(["study", _scene("rocking-seed003-column.toml")]) == 2
    one_line("a scene file, not a study", "nsdyn run")
    rec = tmp_path / "r.csv"
    rec.write_text("t,a\n0,0\n0.01,1\n")
    assert main(["run", str(rec)]) == 2
    one_line("a ground-motion record", f"--record {rec}")
    bom = tmp_path / "bom.toml"  # a byte-order mark (some editors write one) is text
    bom.write_text('\ufeff[scene]\nname = "x"\n')
    assert read_toml(bom) == {"scene": {"name": "x"}}
    bom.write_bytes('[scene]\nname = "x"\n'.encode("utf-16"))  # (Excel, PowerShell)
    assert read_toml(bom) == {"scene": {"name": "x"}}


def test_a_pulse_given_twice_is_refused(tmp_path, one_line):
    text = open(_scene("rocking-seed003-column.toml")).read()
    scene = tmp_path / "r.toml"
    scene.write_text(text.replace("a_p_g = 0.40", "a_p_g = 0.40\na_p = 3.0"))
    assert main(["run", str(scene), "--out", str(tmp_path / "o")]) == 2
    one_line("give a_p or a_p_g, not both")


def test_a_failure_under_json_prints_a_json_object(tmp_path, capsys):
    assert main(["run", "--record", "nosuch.csv", "--json", "--out", str(tmp_path)]) == 2
    out, err = capsys.readouterr()
    import json

    assert json.loads(out) == {"status": 2, "error": err.split("error: ", 1)[1].strip()}


def test_resume_without_a_checkpoint_says_so(tmp_path, capsys):
    scene = _short_scene(tmp_path)
    out = tmp_path / "o"
    assert main(["run", str(scene), "--resume", "--no-figures", "--out", str(out)]) == 0
    assert f"--resume: no checkpoint in {out}" in capsys.readouterr().err


def test_a_design_reference_off_the_grid_is_refused(tmp_path, one_line):
    tables = '[analysis.design]\nobjectives = ["idr_max"]\nreference = { "isolation.mu" = 0.03 }\n'
    study = _study(tmp_path, tables)
    assert main(["study", str(study), "--out", str(tmp_path / "o")]) == 2
    one_line("analysis.design.reference.isolation.mu: 0.03 is not a value")


@pytest.mark.parametrize(
    ("reference", "said"),
    [
        ('{ "isolation.mu" = 0.02 }', "missing ['isolation.c']"),
        (
            '{ "isolation.mu" = 0.02, "isolation.c" = 5e3, "isolation.k_lam" = 5e4 }',
            "got ['isolation.k_lam']",
        ),
        # a misspelt variable: both said (the key given was never named)
        (
            '{ "isolation.muu" = 0.02, "isolation.c" = 5e3 }',
            "missing ['isolation.mu'], got ['isolation.muu']",
        ),
    ],
)
def test_a_design_reference_gives_every_variable(reference, said, tmp_path, one_line):
    # a reference without isolation.c matched the first design with mu = 0.02, whatever its
    # c, and was reported as "the reference" (a key beyond the variables matched none)
    study = tmp_path / "s.toml"
    study.write_text(
        '[study]\nname = "s"\n[parameters]\n"isolation.mu" = [0.02, 0.05]\n'
        '"isolation.c" = [5e3, 1e4]\n[records]\nnames = ["synthetic-wn-40s"]\n'
        f'[analysis.design]\nobjectives = ["idr_max"]\nreference = {reference}\n'
    )
    assert main(["study", str(study), "--out", str(tmp_path / "o")]) == 2
    one_line(
        "analysis.design.reference: expected a value for each design variable "
        "['isolation.mu', 'isolation.c']",
        said,
    )


def test_a_deck_that_lifts_off_ends_with_status_3_and_a_zero_normal_force(tmp_path, capsys):
    """The run ends at the uplift (normal force zero there): its files are written, the
    status is that of a run outside the model's domain, and the summary's minimum is 0."""
    import json

    argv = ["run", _scene("deck-fps4-3c.toml"), "--pga", "60", "--t-end", "2", "--json"]
    assert main([*argv, "--no-figures", "--out", str(tmp_path / "o")]) == 3
    cap = capsys.readouterr()
    s = json.loads(cap.out)
    assert s["uplift"] and s["min_normal_force_N"] == 0.0
    assert s["status"] == 3 and cap.err.endswith(f"nsdyn run: error: {s['error']}\n")  # (its
    assert cap.err.count("error:") == 1  # line, once; before it the PGA of 60 m/s² is noted)


def test_a_deck_scene_json_carries_its_notes(tmp_path, capsys):
    """With --json the notes printed in text mode are the summary's notes (they were
    dropped with stderr's lines): here a t_end past the record's end (40 s)."""
    import json

    text = open(_scene("deck-fps4-3c.toml"), encoding="utf-8").read()
    scene = tmp_path / "d.toml"
    scene.write_text(text.replace("[motion]", "[motion]\nt_end = 41.0", 1))
    argv = ["run", str(scene), "--json", "--no-figures", "--out", str(tmp_path / "o")]
    assert main(argv) == 0
    cap = capsys.readouterr()
    notes = json.loads(cap.out)["notes"]
    assert cap.err == ""
    assert any("t_end = 41 s is past the excitation's end" in n for n in notes), notes


@pytest.mark.parametrize(
    "extra, field",
    [('units = "furlongs"', "motion.units"), ("dt = 0.02", "motion.dt"), ("", None)],
)
def test_a_record_error_names_the_scene_key_at_fault(tmp_path, extra, field, one_line):
    """A unit the reader does not know is the scene's motion.units; a dt that contradicts the
    record's time column (0.01 s) is its motion.dt; a record that cannot be read at all is
    its motion.record (the reader's error carries the keyword it blames)."""
    rec = tmp_path / "r.csv"
    rec.write_text("0,0.1\n0.01,0.2\n0.02,-0.3\n0.03,0.1\n" if field else "0,abc\n")
    scene = tmp_path / "s.toml"
    scene.write_text(f'[motion]\nrecord = "r.csv"\n{extra}\n')
    assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "o")]) == 2
    one_line(f"s.toml: {field or 'motion.record'}: ")


def test_modes_of_a_scene_takes_its_cut_off(capsys, tmp_path):
    # a scene's [scene] f_max is the Craig-Bampton model it runs: the counts are those of
    # `--fmax` at that value (the default 5 Hz's were shown for it); --fmax still wins
    scene = tmp_path / "s.toml"
    scene.write_text('[scene]\nframe = "office-11"\nf_max = 10.0\n')
    assert main(["modes", str(scene), "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert main(["modes", "office-11", "--fmax", "10", "--json"]) == 0
    assert s == json.loads(capsys.readouterr().out) and s["f_max_hz"] == 10.0
    assert main(["modes", str(scene), "--fmax", "5", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["f_max_hz"] == 5.0


@pytest.mark.parametrize("scene", ["rocking-seed003-column", "contact-seed002-A5",
                                   "cylinder-uplift"])  # fmt: skip
def test_a_run_past_its_records_end_says_the_ground_is_at_rest(tmp_path, capsys, scene):
    # rocking and contact ran on past a record's end without a word (free motion after it),
    # the cylinder refused such a t_end: all three run on, with the ground at rest, and say so
    import json

    import numpy as np

    rec = tmp_path / "one.txt"  # 1 s of record: t = 0 ... 1 s, every 0.01 s
    rec.write_text("".join(f"{x:.2f} {0.5 * np.sin(4 * x):.6e}\n" for x in np.arange(101) / 100))
    argv = ["run", _scene(f"{scene}.toml"), "--record", str(rec), "--t-end", "1.5", "--json",
            "--no-figures", "--out", str(tmp_path / "o")]  # fmt: skip
    assert main(argv) == 0
    s = json.loads(capsys.readouterr().out)
    assert s.get("t_end_s", s.get("t_end")) == pytest.approx(1.5, abs=1e-9)
    said = "t_end = 1.5 s is past the record's end (1 s): the ground is at rest after it"
    assert sum(said in n for n in s["notes"]) == 1, s["notes"]


def test_an_export_never_replaces_a_device_a_link_or_a_scene(tmp_path, capsys):
    # /dev/full became a regular file, a scene was written over with the script, a link
    # was replaced instead of written through
    scene = tmp_path / "my.toml"
    scene.write_text(open(_scene("building3d-office-rigid.toml"), encoding="utf-8").read())
    (tmp_path / "link.py").symlink_to(tmp_path / "elsewhere.py")
    regular = "expected a regular file's name"
    for target, says in (("/dev/null", regular), (str(scene), "expected a script's name (.py)"),
                         (str(tmp_path / "link.py"), regular)):  # fmt: skip
        assert _status(["export", "opensees", str(scene), "-o", target]) == 2
        assert says in capsys.readouterr().err
    assert scene.read_text().startswith("# The 3D office") and Path("/dev/null").is_char_device()


def test_a_run_into_a_folder_of_another_run_names_the_files_it_did_not_write(tmp_path, capsys):
    # a rocking run's files landed beside an isolated frame's without a word
    (tmp_path / "run-histories.npz").write_bytes(b"an earlier run's")
    assert main(["run", _scene("rocking-seed003-column.toml"), "--no-figures", "--out",
                 str(tmp_path)]) == 0  # fmt: skip
    err = capsys.readouterr().err
    assert f"note: {tmp_path} also holds files this run did not write (an earlier " in err
    assert "command's): run-histories.npz" in err and "rocking.npz" not in err.split("note:")[-1]
    # the isolated frame's run says the rocking run's (in its JSON notes too)
    assert main(["run", "--t-end", "1", "--no-figures", "--json", "--out", str(tmp_path)]) == 0
    notes = json.loads(capsys.readouterr().out)["notes"]
    assert any(n.endswith("command's): rocking.npz") for n in notes), notes
    assert main(["run", _scene("rocking-seed003-column.toml"), "--no-figures", "--json",
                 "--out", str(tmp_path)]) == 0  # fmt: skip
    notes = json.loads(capsys.readouterr().out)["notes"]
    assert any(n.endswith("command's): run-histories.npz") for n in notes), notes


@pytest.mark.parametrize("name", ["a\x00b", "", "x" * 201, "円" * 67])
def test_a_scene_name_that_is_no_file_name_is_refused(tmp_path, one_line, name):
    # a cylinder scene names its files by the scene's name: a 1e5-character name was echoed
    # in full; 201 bytes (67 CJK characters) ran the whole run, then failed to name its file
    text = Path(_scene("cylinder-uplift.toml")).read_text()
    scene = tmp_path / "c.toml"
    scene.write_text(text.replace('name = "cylinder-uplift"', f"name = {json.dumps(name)}"))
    assert main(["run", str(scene), "--out", str(tmp_path / "o" / "in")]) == 2
    one_line(f"{scene}: scene.name: expected a name of 1 to 200 bytes without control")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.toml"]


def test_a_scene_name_with_a_slash_names_files_inside_the_folder(tmp_path):
    # "../escaped" wrote a cylinder's files beside the output folder; "mu 0.05/0.10" is a
    # name any scene may have (its files are named by it with "_" for the separators)
    text = Path(_scene("cylinder-uplift.toml")).read_text()
    scene = tmp_path / "c.toml"
    scene.write_text(text.replace('name = "cylinder-uplift"', 'name = "../mu 0.05/0.10"'))
    out = tmp_path / "o" / "in"
    assert main(["run", str(scene), "--t-end", "1", "--out", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["_mu 0.05_0.10.npz", "_mu 0.05_0.10.png"]
    assert sorted(p.name for p in (tmp_path / "o").iterdir()) == ["in"]


def test_a_run_holds_its_folder_while_it_writes_its_results(tmp_path, monkeypatch):
    # the folder was free again while the run wrote its histories and figure: a second
    # command could write over them
    import nsdyn.cli.run as cr
    from nsdyn.atomic import OutputBusy, out_lock

    seen = []

    def check_then_save(fig, path, **kw):
        with pytest.raises(OutputBusy, match="nsdyn run"):
            with out_lock(tmp_path, "sweep"):
                pass
        seen.append(path)
        return path

    monkeypatch.setattr(cr, "save_figure", check_then_save)
    assert main(["run", "--t-end", "1", "--out", str(tmp_path)]) == 0
    assert seen == [tmp_path / "run.png"] and not (tmp_path / ".nsdyn.lock").exists()


@pytest.mark.parametrize("scene", [None, "examples/scenes/deck-fps4-3c.toml"])
def test_a_folder_another_command_writes_is_the_run_s_one_line(tmp_path, scene, one_line):
    # the isolated frame's run said its "method  auto: …" line before the busy folder's
    # error (docs/guide/troubleshooting.md: an input error is its one line alone)
    from nsdyn.atomic import out_lock

    root = Path(__file__).resolve().parents[2]
    argv = ["run", *([str(root / scene)] if scene else []), "--t-end", "1", "--no-figures"]
    with out_lock(tmp_path, "sweep"):
        assert main([*argv, "--out", str(tmp_path)]) == 2
    one_line(f"{tmp_path}: nsdyn sweep (process {os.getpid()}) writes there; wait for it to "
             "end, or give another --out")  # fmt: skip
    assert list(tmp_path.iterdir()) == []


def test_a_fixed_base_run_reports_no_isolator_keys(tmp_path, capsys):
    # it read "peak isolator displacement x_iso 0.0000 m" and "share of time all isolators
    # stick 1.00" of a model without isolators, and its JSON held x_iso_max_m = 0,
    # stick_fraction = 1, a contact assumption and an uplift list; a key the model cannot
    # define is absent (as the 3D building's fixed rung has none), and its roof drift is
    # relative to the base
    argv = ["run", "--fixed-base", "--t-end", "1", "--no-figures", "--out", str(tmp_path)]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "peak interstorey drift ratio" in out and "peak roof drift x_top - x_base" in out
    for row in ("peak isolator displacement", "isolators stick", "contact assumption"):
        assert row not in out
    assert main([*argv, "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["idr_max"] > 0 and s["roof_drift_max_m"] > 0
    for key in ("x_iso_max_m", "stick_fraction", "min_normal_force_N", "contact", "uplift"):
        assert key not in s


def test_a_cylinder_that_topples_is_not_said_to_run_past_its_excitation(tmp_path, capsys):
    # a soft foundation (k = 40 N/m³) lets the cylinder topple at 5.9 s of its 20 s record:
    # "t_end = 8 s is past the excitation's end (5.90113 s)" was said of the toppling time;
    # and the warm-up's three samples no longer say their own energy closure
    text = open(_scene("cylinder-uplift.toml"), encoding="utf-8").read()
    head, _, rest = text.partition("[foundation]")
    body = "\n".join(ln for ln in rest.splitlines()
                     if not ln.startswith(("f_rock", "zeta", "k ", "c ", "k=", "c=")))  # fmt: skip
    scene = tmp_path / "cyl.toml"
    scene.write_text(f"{head}[foundation]\nk = 40\nc = 10\n{body}\n")
    assert main(["run", str(scene), "--t-end", "8", "--no-figures", "--out",
                 str(tmp_path / "o")]) == 0  # fmt: skip
    captured = capsys.readouterr()
    assert "TOPPLED" in captured.out and "past the excitation's end" not in captured.err
