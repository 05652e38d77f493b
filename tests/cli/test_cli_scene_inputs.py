"""Scene files written by hand: inputs that ran a model other than the one written, were
dropped without a word or ended in a traceback are refused in one line naming the file and
the field (status 2), or said in a note; a sweep says what it does not use."""

from __future__ import annotations

import json
import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from nsdyn.cli import main

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"
PENDULUM = """[scene]
kind = "deck"
[deck]
m = 2.0e6
positions = [[-10.0, -6.0], [10.0, -6.0], [10.0, 6.0], [-10.0, 6.0]]
[bearing]
type = "fps"
radius = 2.2
mu = 0.0
[motion]
kind = "orbit"
orbit = "linear"
frequency = 0.3
amplitude = 0.05
n_periods = 20
[solver]
law = "switch"
"""


def _scene(tmp_path, text: str, name: str = "s.toml") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def _refused(tmp_path, capsys, argv, needle: str) -> None:
    rc = main([*argv, "--no-figures", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and len(err.splitlines()) == 1, err
    assert needle in err, err


@pytest.mark.parametrize(
    "scene, old, new, needle",
    [
        # the event method ran the switch law under a scene's law "none" (same peaks)
        ("isolated-coulomb-force", 'law = "switch"', 'law = "none"',
         "isolation.law: 'none' with solver.method 'event'"),
        # a list on a one-value key: used (x_iso doubled) or a traceback
        ("isolated-uplift-pocket", "[isolation]", "[isolation]\ndiaphragm_EA = [1e11, 1.0]",
         "isolation.diaphragm_EA: expected one number (k_lam, c and mu take one per isolator)"),
        # a rate without the fast coefficient it leads to was dropped
        ("deck-fps4-3c", "mu_fast = 0.07", "", "bearing.rate: the rate of the change from "
         "mu_slow to mu_fast; expected mu_fast beside it"),
        # a deck on one isolator: its centre of mass off it, and no extent to derive J from
        ("deck-fps4-3c", "positions = [[-10.0, -6.0], [10.0, -6.0], [10.0, 6.0], [-10.0, 6.0]]",
         "positions = [[0.0, 0.0]]", "deck.ecc: a deck on one isolator stands on it alone"),
        ("deck-fps4-3c", "J = 9.07e7", "", None),  # (J derived from the four corners: runs)
        ("deck-fps4-3c", "mu_fast = 0.07\nrate = 30.0", "rate = 0.0", None),  # constant mu
    ],
)  # fmt: skip
def test_a_scene_that_ran_another_model_is_refused(tmp_path, capsys, scene, old, new, needle):
    text = (SCENES / f"{scene}.toml").read_text()
    assert old in text
    p = _scene(tmp_path, text.replace(old, new))
    if needle is None:
        assert main(["run", str(p), "--t-end", "0.2", "--no-figures", "--out",
                     str(tmp_path / "o")]) == 0  # fmt: skip
        return
    _refused(tmp_path, capsys, ["run", str(p), "--t-end", "0.2"], needle)


def test_one_isolator_without_its_polar_moment_says_it_is_missing(tmp_path, capsys):
    text = PENDULUM.replace("positions = [[-10.0, -6.0], [10.0, -6.0], [10.0, 6.0], "
                            "[-10.0, 6.0]]", "positions = [[0.0, 0.0]]")  # fmt: skip
    p = _scene(tmp_path, text)
    _refused(tmp_path, capsys, ["run", str(p), "--t-end", "0.2"], "deck.J: missing; a deck on one")


def test_a_sweep_of_sliders_without_a_spring_is_refused(tmp_path, capsys):
    # no restoring force: every orbit is one of a family at any offset (a "stable" 487 km
    # orbit was reported at 2.8 Hz)
    text = (SCENES / "sdof-bidirectional-sweep.toml").read_text()
    p = _scene(tmp_path, text.replace("k_lam = 9869.6", "k_lam = 0.0"))
    _refused(tmp_path, capsys, ["sweep", str(p), "--points", "3"],
             "bearing.k_lam: flat sliders without a spring")  # fmt: skip


def test_a_sweep_past_the_pendulums_radius_says_so(tmp_path, capsys):
    # a frictionless pendulum R = 2.2 m under 0.05 m/s²: resonance at sqrt(g/R)/2pi = 0.336 Hz,
    # where the linear model's slip A/|w0² - w²| runs past R; the run says so, the sweep did
    # not. Off resonance (0.2 Hz: A/(w² - w0²) = 0.05/(4.46 - 1.58) = 17 mm) nothing is said
    p = _scene(tmp_path, PENDULUM)
    argv = ["sweep", str(p), "--points", "2", "--json", "--no-figures"]
    assert main([*argv, "--fmin", "0.2", "--fmax", "0.21", "--out", str(tmp_path / "a")]) == 0
    assert "notes" not in json.loads(capsys.readouterr().out)
    f0 = math.sqrt(9.81 / 2.2) / (2 * math.pi)
    main([*argv, "--fmin", f"{f0 * 0.999:.6f}", "--fmax", f"{f0 * 1.001:.6f}",
          "--out", str(tmp_path / "b")])  # fmt: skip
    notes = json.loads(capsys.readouterr().out).get("notes") or []
    assert len(notes) == 1 and "past the sphere's edge" in notes[0], notes


def test_an_isolated_sweep_takes_a_harmonic_scenes_amplitude_and_notes_a_record(tmp_path,
                                                                               capsys):  # fmt: skip
    # [motion] was ignored: the default amplitudes 0.1, 0.5, 1, 2 were swept
    text = (SCENES / "isolated-shear-3storey.toml").read_text()
    head, _, tail = text.partition("[motion]")
    rest = tail[tail.index("\n[") :] if "\n[" in tail else ""
    harmonic = '[motion]\nkind = "harmonic"\namplitude = 0.7\nfrequency = 0.5\nn_periods = 5\n'
    p = _scene(tmp_path, head + harmonic + rest)
    argv = ["sweep", str(p), "--points", "2", "--fmin", "0.5", "--fmax", "1", "--json",
            "--no-figures"]  # fmt: skip
    assert main([*argv, "--out", str(tmp_path / "a")]) == 0
    assert [a["A"] for a in json.loads(capsys.readouterr().out)["amplitudes"]] == [0.7]
    p = _scene(tmp_path, text, "r.toml")  # the scene's record: not what a sweep runs
    main(["sweep", str(p), "--points", "2", "--fmin", "0.5", "--fmax", "1", "--amplitudes",
          "0.5", "--no-figures", "--out", str(tmp_path / "c")])  # fmt: skip
    assert "the scene's [motion] (a record) is not used" in capsys.readouterr().err


def test_notes_for_keys_that_change_nothing_or_blur_the_law(tmp_path, capsys):
    # mu under law "none" was not named among the unused keys; a switch band of 0.3 m/s let
    # "stuck" bearings creep (peak 0.188 m against the frictionless 0.112 m), without a word
    text = (SCENES / "isolated-shear-3storey.toml").read_text()
    p = _scene(tmp_path, text.replace('law = "arctan"', 'law = "none"', 1))
    assert main(["run", str(p), "--t-end", "0.2", "--no-figures", "--out",
                 str(tmp_path / "a")]) == 0  # fmt: skip
    assert "isolation.mu (the friction coefficient; the law here is none" in (
        capsys.readouterr().err
    )
    text = (SCENES / "deck-fps4-3c.toml").read_text()
    for eta, said in ((1e-3, False), (0.3, True)):
        p = _scene(tmp_path, text.replace("[solver]", f"[solver]\neta = {eta}"))
        assert main(["run", str(p), "--t-end", "0.2", "--no-figures", "--out",
                     str(tmp_path / "b")]) == 0  # fmt: skip
        assert ("solver.eta = 0.3 m/s: the switch law holds a stuck isolator only to" in
                capsys.readouterr().err) is said  # fmt: skip


@pytest.mark.parametrize(
    "text, needle",
    [
        # the name alone, without the scene or its key
        ('[scene]\nframe = "office-99"\n', "s.toml: scene.frame: office-99: no bundled frame"),
        # the isolators' list is the isolation table's ("scene.frame: isolation.mu" before)
        ("[isolation]\nmu = [0.05, 0.05, 0.05]\n",
         "s.toml: isolation.mu: expected one value or 2 (one per isolator), got 3"),
    ],
)  # fmt: skip
def test_a_frame_scenes_error_names_its_own_key(tmp_path, capsys, text, needle):
    _refused(tmp_path, capsys, ["run", str(_scene(tmp_path, text)), "--t-end", "0.2"], needle)


def test_a_3d_frame_name_of_the_wrong_type_is_not_called_missing(tmp_path, capsys):
    text = (SCENES / "building3d-office-rigid.toml").read_text()
    p = _scene(tmp_path, text.replace('frame3d = "office-11-3d"', "frame3d = 3"))
    _refused(tmp_path, capsys, ["run", str(p), "--t-end", "0.2"],
             "structure.frame3d: expected a bundled 3D frame name (office-11-3d) or a 3D frame "
             "file, got 3")  # fmt: skip


def test_the_friction_flag_settles_a_scene_law_the_event_method_would_not_run(tmp_path, capsys):
    # the scene's law 'none' with method 'event' is refused, but --friction switch gives the
    # event method its law: the run goes (it was refused by the scene's law alone)
    text = (SCENES / "isolated-coulomb-force.toml").read_text()
    p = _scene(tmp_path, text.replace('law = "switch"', 'law = "none"'))
    argv = ["run", str(p), "--t-end", "0.2", "--no-figures", "--out", str(tmp_path / "o")]
    assert main([*argv, "--friction", "switch"]) == 0
    capsys.readouterr()


def test_an_error_inside_a_scenes_frame_file_names_that_file(tmp_path, capsys):
    frame = (Path(__file__).resolve().parents[2] / "frames" / "portal.toml").read_text()
    twice = frame.replace("[3, 4, 1], [4, 5, 1]", "[3, 4, 1], [4, 3, 1], [4, 5, 1]")
    (tmp_path / "bad.toml").write_text(twice)
    p = _scene(tmp_path, '[scene]\nframe = "bad.toml"\n')
    rc = main(["run", str(p), "--t-end", "0.2", "--no-figures", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and "bad.toml: frame.elements[3]: joins nodes 4 and 3" in err
    assert "scene.frame" not in err


@pytest.mark.parametrize("how", ["scene", "flag"])
def test_a_record_named_without_a_pga_runs_as_recorded(how, tmp_path, capsys):
    # the default scene's pga = 3 m/s² (its own record's) scaled every record named without
    # one: a 0.5 m/s² sine ran six times stronger, and a record in g read as m/s² was hidden.
    # Named without a pga, the record's PGA is the run's (the sine's amplitude, exactly);
    # given, it is scaled to it
    t = [0.01 * k for k in range(301)]
    rec = tmp_path / "small.txt"
    rec.write_text("time [s], acc [m/s2]\n"
                   + "".join(f"{x:.2f}, {0.5 * math.sin(2 * math.pi * 1.5 * x + 0.3):.17g}\n"
                             for x in t))  # fmt: skip
    a_max = max(abs(0.5 * math.sin(2 * math.pi * 1.5 * x + 0.3)) for x in t[:201])  # (0-2 s)
    if how == "scene":
        argv = ["run", str(_scene(tmp_path, f'[motion]\nrecord = "{rec}"\n'))]
    else:
        argv = ["run", "--record", str(rec)]
    base = [*argv, "--no-figures", "--json", "--t-end", "2"]
    assert main([*base, "--out", str(tmp_path / "a")]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["pga_mps2"] == pytest.approx(a_max, rel=1e-15) and "record_pga_mps2" not in s
    assert main([*base, "--pga", "2", "--out", str(tmp_path / "b")]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["record_pga_mps2"] == 2.0


def test_a_scene_value_an_option_replaces_is_still_checked(tmp_path, one_line):
    # a deck scene's t_end = -1 ran when --t-end was given (the isolated frame's is refused
    # either way); the file is wrong whatever the command line says
    text = (
        (SCENES / "deck-fps4-3c.toml").read_text().replace("[motion]\n", "[motion]\nt_end = -1.0\n")
    )
    scene = _scene(tmp_path, text)
    assert (
        main(["run", str(scene), "--t-end", "1", "--no-figures", "--out", str(tmp_path / "o")]) == 2
    )
    one_line(f"{scene}: motion.t_end", "expected a finite number >= 0, got -1.0")
    # a value its kind takes stays taken: a cylinder's pga = 0 (free vibration) under --pga
    text = (
        (SCENES / "cylinder-uplift.toml").read_text().replace("[motion]\n", "[motion]\npga = 0.0\n")
    )
    argv = ["run", str(_scene(tmp_path, text, "c.toml")), "--pga", "2", "--t-end", "0.5"]
    assert main([*argv, "--no-figures", "--out", str(tmp_path / "c")]) == 0


def test_the_fixed_base_by_either_flag_takes_no_comparison(tmp_path, one_line):
    # --fixed-base --compare-fixed was refused, --fidelity fixed --compare-fixed ran the same
    # model with a note
    assert main(["run", "--fidelity", "fixed", "--compare-fixed", "--out", str(tmp_path)]) == 2
    one_line("--fidelity fixed: the clamped linear frame has no isolators; --compare-fixed")


def test_a_pga_out_of_range_is_named_by_its_field_alone(tmp_path, one_line):
    # "motion.pga (--pga): target: expected ..." carried the library's argument name
    assert main(["run", "--pga", "1e6", "--out", str(tmp_path)]) == 2
    line = one_line("motion.pga (--pga): expected a finite PGA from 0 to 1000 m/s² (100 g)")
    assert "target" not in line


def test_a_sweep_names_the_scene_tables_it_does_not_read(tmp_path, capsys):
    # a transient's [solver] method, rtol and dt_out changed no sweep (its orbits are shot by
    # their own integrator), unsaid; a landing's restitution is read (unilateral contact).
    # Said before the sweep runs (an interrupted or failed sweep says them too)
    scene = tmp_path / "s.toml"
    scene.write_text('[scene]\nfidelity = "rigid"\n[motion]\nrecord = "synthetic-wn-40s"\n'
                     '[solver]\nmethod = "dopri5"\nrtol = 1e-2\n')  # fmt: skip
    argv = ["sweep", str(scene), "--fmin", "0.5", "--fmax", "0.6", "--points", "2", "--amplitudes",
            "0.5", "--workers", "1", "--no-figures", "--out", str(tmp_path / "o")]  # fmt: skip
    assert main(argv) == 0
    notes = [ln for ln in capsys.readouterr().err.splitlines() if ": note: " in ln]
    assert notes == [
        "nsdyn sweep: note: the scene's [motion] (a record) is not used: a sweep drives the "
        "frame with harmonic base accelerations of --amplitudes",
        "nsdyn sweep: note: the scene's [solver] method, rtol: not used by a sweep, which "
        "shoots its periodic orbits with its own integrator (--tableau, --steps-factor)",
    ]


def test_a_bundled_name_beside_a_file_of_that_stem_is_said(tmp_path, capsys, monkeypatch):
    # a scene's frame = "portal" beside the user's own portal.toml ran the bundled portal (its
    # header "portal cb" either way); a bare name beside name.toml given on the command line
    # was "no bundled frame of that name" alone
    from nsdyn.models.isolated.scene import load_scene

    own = tmp_path / "portal.toml"
    own.write_text((Path(__file__).resolve().parents[2] / "frames" / "portal.toml").read_text())
    scene = tmp_path / "s.toml"
    scene.write_text('[scene]\nframe = "portal"\n')
    with pytest.warns(UserWarning, match=rf"^{re.escape(str(scene))}: scene.frame = 'portal' is "
                      r"a bundled name .*: portal.toml beside the scene is not read; "
                      r"scene.frame = 'portal.toml' reads it$"):  # fmt: skip
        load_scene(scene)
    # the scene itself and a run's outputs are no frame or record to read
    me = tmp_path / "office-11.toml"
    me.write_text('[scene]\nframe = "office-11"\n[motion]\nrecord = "synthetic-wn-40s"\n')
    (tmp_path / "synthetic-wn-40s.png").write_bytes(b"")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        load_scene(me)
    (tmp_path / "p2.toml").write_text(own.read_text())
    monkeypatch.chdir(tmp_path)
    assert main(["modes", "p2"]) == 2
    assert "p2: no bundled frame of that name (the file p2.toml is here: give its whole name)" in (
        capsys.readouterr().err
    )


def test_a_sweep_names_the_fidelity_flag_a_structure_scene_cannot_take(tmp_path, capsys):
    # it named "scene.fidelity / scene.f_max", which the scene did not give (nsdyn run names
    # the flag)
    scene = (
        Path(__file__).resolve().parents[2] / "examples" / "scenes" / "isolated-shear-3storey.toml"
    )
    assert main(["sweep", str(scene), "--fidelity", "cb", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"nsdyn sweep: error: {scene}: --fidelity: chooses among a frame's")


def test_a_building_run_takes_the_rung_flags_as_its_structure_keys(capsys, tmp_path):
    # "--fidelity applies to isolated-frame scenes only", where the building has the rungs the
    # flag lists (and nsdyn sweep took it): --fidelity and --fmax set [structure] fidelity and
    # f_max, the fixed rung then noting the bearing it does not use
    scene = (
        Path(__file__).resolve().parents[2] / "examples" / "scenes" / "building3d-office-rigid.toml"
    )
    argv = ["run", str(scene), "--fidelity", "fixed", "--t-end", "1", "--no-figures", "--json"]
    assert main([*argv, "--out", str(tmp_path)]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["fidelity"] == "fixed" and any(n.startswith("[bearing] not used") for n in s["notes"])
    # --fidelity auto asks the building's advisor, as [structure] fidelity = "auto" does (the
    # flag was dropped: the scene's rigid rung ran, without advice)
    argv[3] = "auto"
    assert main([*argv, "--out", str(tmp_path)]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["advice"]["fidelity"] == s["fidelity"]
    # the fixed base of a building is a rung: the isolated frame's flags say so
    assert main(["run", str(scene), "--compare-fixed", "--out", str(tmp_path)]) == 2
    assert capsys.readouterr().err.rstrip().endswith("a 3D building's fixed base is its rung "
                                                     "--fidelity fixed")  # fmt: skip
    assert main(["run", str(scene), "--dt", "0.002", "--out", str(tmp_path)]) == 2
    assert capsys.readouterr().err.rstrip().endswith("a 3D building's step is its [solver] dt")
    argv[3] = "rigid"  # the scene's own rung, whose note names the key --fmax set
    assert main([*argv, "--fmax", "4", "--out", str(tmp_path)]) == 0
    assert "structure.f_max not used: the cb rung's cut-off" in json.loads(
        capsys.readouterr().out)["notes"]  # fmt: skip
    # a value the flag gave is named with the flag (the file holds none); a [structure] that is
    # no table is named by the reader, flags or not (it ended in an AttributeError)
    assert main([*argv[:3], "cb", "--fmax", "inf", "--out", str(tmp_path)]) == 2
    assert "structure.f_max (--fmax): expected a positive frequency" in capsys.readouterr().err
    bad = tmp_path / "s.toml"
    text = scene.read_text().replace("[structure]", "[old]")
    bad.write_text('structure = "office-11-3d"\n' + text)
    for flags in ([], ["--fidelity", "cb"]):
        assert main(["run", str(bad), *flags, "--out", str(tmp_path)]) == 2
        assert capsys.readouterr().err.rstrip().endswith("[structure]: expected a table")
    # a rocking scene has no rung: the building's words were no help there
    rocking = SCENES / "rocking-seed003-column.toml"
    assert main(["run", str(rocking), "--resume", "--out", str(tmp_path)]) == 2
    assert (
        capsys.readouterr().err.rstrip().endswith("--resume applies to isolated-frame scenes only")
    )


def test_a_relative_file_found_only_from_the_current_folder_is_said(tmp_path, monkeypatch):
    # a scene's record = "rec.csv" with no rec.csv beside it ran the current folder's file,
    # unsaid: the same scene read another file, or none, when started elsewhere
    from nsdyn.models.scenefile import resolve_paths

    (tmp_path / "sub").mkdir()
    (tmp_path / "rec.csv").write_text("t,a\n0,0\n0.01,1\n")
    monkeypatch.chdir(tmp_path)
    cfg = {"motion": {"record": "rec.csv"}}
    said = r"^sub/s.toml: motion.record = 'rec.csv' is not beside the scene \(in sub\); read "
    with pytest.warns(UserWarning, match=said + r"from the current folder: .*rec.csv$"):
        out = resolve_paths(cfg, "sub", "sub/s.toml")
    assert out["motion"]["record"] == str((tmp_path / "rec.csv").resolve())  # (as read)
    (tmp_path / "sub" / "rec.csv").write_text("t,a\n0,0\n0.01,1\n")
    with warnings.catch_warnings():  # beside the scene: read there, without a word
        warnings.simplefilter("error")
        out = resolve_paths(cfg, "sub", "sub/s.toml")
    assert out["motion"]["record"] == str((tmp_path / "sub" / "rec.csv").resolve())


def test_a_warning_about_a_scene_read_twice_is_said_once(tmp_path, monkeypatch, capsys):
    # nsdyn run reads a scene's file twice (its kind, then the scene): the warning on a
    # record found from the current folder came twice
    (tmp_path / "sub").mkdir()
    t = np.arange(0.0, 1.0, 0.01)
    (tmp_path / "rec.csv").write_text("t,a\n" + "".join(f"{v:g},{np.sin(v):g}\n" for v in t))
    (tmp_path / "sub" / "s.toml").write_text('[scene]\nfidelity = "rigid"\n[motion]\n'
                                             'record = "rec.csv"\nunits = "m/s2"\n')  # fmt: skip
    monkeypatch.chdir(tmp_path)
    assert main(["run", "sub/s.toml", "--out", str(tmp_path / "o"), "--no-figures"]) == 0
    assert capsys.readouterr().err.count("is not beside the scene") == 1


@pytest.mark.parametrize(
    "kind, body",
    [
        ("rocking", "[block]\nwidth = 0.3\nheight = 1.2\n"),
        ("contact", "[body]\nwidth = 0.3\nheight = 1.2\n[friction]\nmu_s = 0.5\n"),
        ("cylinder", ""),
    ],
)
def test_a_one_column_record_takes_its_step_from_motion_dt_in_every_family(
    tmp_path, kind, body, capsys
):
    # the reader's refusal of a one-column file says "in a scene, [motion] dt"; the rocking
    # and contact scenes then refused motion.dt as unknown, and the cylinder's as the
    # simulated earthquake's step: no way to run the file at all. The record read with that
    # step is the file's samples (its peak, written to 6 digits, is the run's PGA)
    a = 0.1 * np.sin(np.arange(300) * 0.05)
    a[40] = 2.5  # (the peak, inside the run's first second)
    (tmp_path / "one.txt").write_text("".join(f"{v:.6f}\n" for v in a))
    text = (f'[scene]\nkind = "{kind}"\n{body}[motion]\nrecord = "one.txt"\nunits = "m/s2"\n'
            "dt = 0.01\nt_end = 1.0\n")  # fmt: skip
    scene = _scene(tmp_path, text)
    out = tmp_path / "o"
    assert main(["run", str(scene), "--no-figures", "--out", str(out), "--json"]) == 0
    s = json.loads(capsys.readouterr().out.splitlines()[-1])
    pga = next(v for k, v in s.items() if k.startswith("pga") and isinstance(v, float))
    assert pga == 2.5


def test_an_empty_record_or_frame_name_is_refused(tmp_path, one_line):
    # `--record ""` (an unset shell variable) ran the scene's own record without a word; a
    # scene's record = "" was refused as the folder "."
    for flag in ("--record", "--frame"):
        with pytest.raises(SystemExit) as e:  # (a usage error: argparse's exit)
            main(["run", flag, "", "--no-figures", "--out", str(tmp_path / "o")])
        assert e.value.code == 2
        one_line(f"argument {flag}: expected a bundled name or a file's path, got ''")
    scene = _scene(tmp_path, '[motion]\nrecord = ""\nt_end = 0.2\n')
    assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "o")]) == 2
    one_line(f"{scene}: motion.record: expected a bundled name or a file's path, got ''")


def test_a_force_scene_swept_at_other_amplitudes_is_not_warned_of_its_own_load(tmp_path, capsys):
    # --amplitudes of a force scene are its force amplitudes [N] (docs: periodic); each curve
    # was warned that the scene's F = 1635 N "is not used" of a load the user never passed
    argv = ["sweep", str(SCENES / "isolated-coulomb-force.toml"), "--amplitudes", "1000",
            "--fmin", "2", "--fmax", "2.1", "--points", "2", "--workers", "1", "--no-figures",
            "--out", str(tmp_path / "o")]  # fmt: skip
    assert main(argv) == 0
    assert "is not used" not in capsys.readouterr().err
    rows = (tmp_path / "o" / "sweep.csv").read_text().splitlines()[1:]
    assert len(rows) == 2 and all(r.split(",")[1] == "1000" for r in rows)  # (A, in N)


def test_t_end_on_the_command_line_gives_a_harmonic_ground_motion_its_end(tmp_path, capsys):
    # a [motion] kind = "harmonic" without t_end or n_periods was refused under --t-end
    # ("motion.t_end (--t-end): ... give t_end"), while a harmonic [force] and a deck's orbit
    # took it; the run ends at the given time, its last output there
    p = _scene(tmp_path, '[motion]\nkind = "harmonic"\namplitude = 1.0\nfrequency = 1.0\n')
    assert main(["run", str(p), "--t-end", "1", "--out", str(tmp_path / "o"), "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["status"] == 0 and s["t_end_s"] == pytest.approx(1.0, abs=1e-12)
    assert main(["run", str(p), "--out", str(tmp_path / "o"), "--json"]) == 2  # no end at all
    assert "motion.t_end: a harmonic excitation has no natural end" in capsys.readouterr().err
    # the file's own end stays checked under --t-end (a negative one ran), and a [motion]
    # that is no table is one line naming it (a traceback before)
    bad = _scene(tmp_path, '[motion]\nkind = "harmonic"\namplitude = 1.0\nfrequency = 1.0\n'
                 't_end = -5.0\n', "bad.toml")  # fmt: skip
    assert main(["run", str(bad), "--t-end", "2", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "bad.toml: motion.t_end" in err
    flat = _scene(tmp_path, "motion = 3\n", "flat.toml")
    assert main(["run", str(flat), "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err.strip().endswith("flat.toml: motion: expected a table "
                                                    "[motion], got 3")  # fmt: skip


def test_a_json_scene_is_told_scenes_are_toml(tmp_path, one_line):
    # a scene written as JSON was "not valid TOML: Invalid statement (at line 1, column 1)"
    p = _scene(tmp_path, '{"isolation": {"mu": 0.05}}\n', "s.json")
    assert main(["run", str(p), "--out", str(tmp_path / "o")]) == 2
    one_line("s.json: not valid TOML (a JSON file? scene files are TOML: [table] and key = ")


def test_json_text_in_a_toml_file_is_told_scenes_are_toml(tmp_path, one_line):
    p = _scene(tmp_path, '{"isolation": {"mu": 0.05}}\n', "s.toml")
    assert main(["run", str(p), "--out", str(tmp_path / "o")]) == 2
    one_line("s.toml: not valid TOML (a JSON file? scene files are TOML: [table] and key = ")


def test_a_deck_given_a_rung_flag_is_told_which_scenes_take_it(tmp_path, one_line):
    # "--fidelity applies to isolated-frame scenes only": a 3D building takes it too (and not
    # --resume, given beside it)
    p = SCENES / "deck-fps4-3c.toml"
    assert main(["run", str(p), "--fidelity", "cb", "--resume", "--out", str(tmp_path)]) == 2
    one_line("--resume applies to isolated-frame scenes only; --fidelity applies to "
             "isolated-frame scenes and 3D buildings (their [structure] rung)")  # fmt: skip
    assert main(["run", str(p), "--fmax", "10", "--out", str(tmp_path)]) == 2
    one_line(f"{p}: --fmax applies to isolated-frame scenes and 3D buildings (their [structure] "
             "rung)")  # fmt: skip
