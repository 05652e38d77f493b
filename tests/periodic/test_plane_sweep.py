"""Frequency curves of a bidirectional SDOF: continuation and ``nsdyn sweep`` vs the closed form.

Source: the steady circular slip of a mass on a flat slider under circular ground acceleration
(closed form derived in test_plane.py: the friction has constant magnitude mu m g and turns with
the velocity, so R solves ((k - m w^2) R)^2 + (c w R + mu m g)^2 = (m A)^2 at every f, a
permanent slip whenever A > mu g). The example scene examples/scenes/sdof-bidirectional-sweep.toml
holds the same numbers as test_plane.py's SDOF.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
from test_plane import A0, F0, MU, circular, closed_form_multipliers, sdof, steady_circle

from nsdyn.cli import main as nsdyn_main
from nsdyn.periodic.plane import RTOL, plane_problem, plane_response
from nsdyn.periodic.shooting import SHOOT_TOL
from nsdyn.studies.plane_sweep import CSV_COLUMNS, checkpoint_path

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"
SCENE = SCENES / "sdof-bidirectional-sweep.toml"
G = 9.81
M = 1000.0


def _tolerance(f):
    """Newton's end over the contraction, as in test_plane.py (closed-form multipliers)."""
    w = 2 * math.pi * f
    R, psi = steady_circle(w, A0, MU)
    rho, cond = closed_form_multipliers(w, R, psi, MU * M * G, 0.0)
    return R, cond * (SHOOT_TOL + 1e3 * RTOL) / (1 - abs(rho[0]))


@pytest.mark.parametrize("continuation", ["sequential", "arclength"])
def test_continued_curve_is_the_closed_form_curve(continuation):
    # through the isolator's resonance (0.5 Hz alone): the peak resultant displacement of every
    # point is the closed-form radius, found by shooting, stable
    pb = plane_problem(sdof(), circular(A0, F0), law="switch")
    curve = plane_response(pb, fmin=0.3, fmax=1.5, points=5, continuation=continuation)
    assert curve.info["failures"] == []
    assert len(curve.points) >= 5
    assert curve.points[0].f == pytest.approx(0.3) and curve.points[-1].f == pytest.approx(1.5)
    for p in curve.points:
        R, tol = _tolerance(p.f)
        assert p.method in ("shooting", "arclength") and p.converged
        assert p.quantities["u_peak_m"] == pytest.approx(R, rel=tol)
        assert p.stable is True


def test_nsdyn_sweep_on_the_example_scene_gives_the_closed_form_and_resumes(tmp_path, capsys):
    out = tmp_path / "out"
    argv = ["sweep", str(SCENE), "--fmin", "0.35", "--fmax", "1.4", "--points", "4",
            "--amplitudes", f"{A0},{1.5 * A0}", "--workers", "1", "--out", str(out),
            "--json"]  # fmt: skip
    assert nsdyn_main(argv) == 0
    report = json.loads(capsys.readouterr().out)
    rows = list(csv.DictReader((out / "sweep.csv").open()))
    assert tuple(rows[0].keys()) == CSV_COLUMNS
    assert len(rows) == 8 and report["kind"] == "deck"
    # a success's JSON leads with status 0, as a failure's with its status
    assert next(iter(report)) == "status" and report["status"] == 0
    for r in rows:
        A, f = float(r["A"]), float(r["f"])
        w = 2 * math.pi * f
        R = steady_circle(w, A, MU)[0]
        assert r["converged"] == "true" and r["method"] == "shooting" and r["law"] == "switch"
        # 9 digits in the CSV; the shooting error bound of _tolerance is ~1e-5 R
        assert float(r["u_peak_m"]) == pytest.approx(R, rel=2e-5)
        assert float(r["friction_peak_N"]) == pytest.approx(MU * M * G, rel=1e-9)
        assert float(r["stick_fraction"]) == 0.0
    assert (out / "sweep.png").exists() and (out / "sweep.json").exists()
    written = json.loads((out / "sweep.json").read_text())
    assert written["amplitudes"][0]["failures"] == [] and written["status"] == 0  # (as --json)
    # the peak and its frequency under the library curve's names (Curve.summary): the
    # largest circle radius of the four frequencies, at its own frequency
    s0 = report["amplitudes"][0]
    peak = max(rows[:4], key=lambda r: float(r["u_peak_m"]))  # (the CSV's 9 digits)
    assert s0["u_peak_max_m"] == pytest.approx(float(peak["u_peak_m"]), rel=1e-8)
    assert s0["u_peak_max_f_hz"] == pytest.approx(float(peak["f"]), rel=1e-8)
    for A in (A0, 1.5 * A0):
        assert checkpoint_path(out, A).exists()
    # the same command again resumes every point from the checkpoints
    assert nsdyn_main(argv) == 0
    again = json.loads(capsys.readouterr().out)
    assert [s["resumed_points"] for s in again["amplitudes"]] == [4, 4]
    assert list(csv.DictReader((out / "sweep.csv").open())) == rows
    # the table says so: its wall time is this run's alone (the resumed points' not in it)
    assert nsdyn_main(argv[:-1]) == 0
    cap = capsys.readouterr()
    assert cap.out.count("4 of 4 points resumed from the checkpoint (wall [s]: this run's") == 2
    # ... and says so as each curve starts (an interrupted sweep's rerun began unsaid); a
    # finished curve of other settings (3 points) is started afresh, said as well
    for A in (A0, 1.5 * A0):
        said = f"[A={A:g}] resuming from {checkpoint_path(out, A).name}: 4 points on file, to "
        assert said + "f = 1.4 Hz" in cap.err
    assert nsdyn_main([*argv[:7], "3", *argv[8:-1]]) == 0
    err = capsys.readouterr().err
    assert err.count("holds a finished curve of other settings: started afresh") == 2
    assert "resuming" not in err
    checkpoint_path(out, A0).write_text('{"identity": ')  # (a file cut short)
    assert nsdyn_main([*argv[:7], "3", *argv[8:-1]]) == 0
    err = capsys.readouterr().err
    assert f"[A={A0:g}] {checkpoint_path(out, A0).name} cannot be read: started afresh" in err


def test_a_band_refused_against_the_scenes_end_names_that_end(tmp_path, capsys):
    # the scene's sweep.f_max = 2.8 Hz was called "the default top of the band"
    assert nsdyn_main(["sweep", str(SCENE), "--fmin", "3", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert f"--fmin: expected a frequency below 2.8 Hz (sweep.f_max of {SCENE}: give" in err


def test_an_arclength_sweep_counts_its_points_without_a_grid_total(tmp_path, capsys, monkeypatch):
    # the curve takes its own steps: "[A=0.981] 16/4" read as past its end; with no point
    # said for the time (WATCH_S), its first, its grid's second and its last (at fmax) are
    from nsdyn import _progress

    monkeypatch.setattr(_progress, "WATCH_S", 1.0e9)
    argv = ["sweep", str(SCENE), "--fmin", "0.35", "--fmax", "1.4", "--points", "2",
            "--continuation", "arclength", "--out", str(tmp_path), "--no-figures"]  # fmt: skip
    assert nsdyn_main(argv) == 0
    lines = [ln for ln in capsys.readouterr().err.splitlines() if ln.startswith("[A=")]
    assert len(lines) == 3 and all("(arclength) f=" in ln and "/2 " not in ln for ln in lines)
    assert "f=  1.4000 Hz" in lines[-1]


def test_default_range_and_amplitude_come_from_the_scene(tmp_path, capsys, monkeypatch):
    # f0/4 .. 4 f0 around the orbit's 0.7 Hz, at its amplitude 0.981 m/s^2 (progress on stderr;
    # a cold cache: the deck's loop compiles first, before the workers, saying so)
    from nsdyn.models.isolated import deck_scene

    monkeypatch.setattr(deck_scene, "kernels_cached", lambda law: False)
    out = tmp_path / "out"
    assert nsdyn_main(["sweep", str(SCENE), "--points", "3", "--out", str(out),
                       "--no-figures"]) == 0  # fmt: skip
    cap = capsys.readouterr()
    assert "3/3 f=" in cap.err and "|u|max" in cap.out
    assert "compiling the deck kernels once" in cap.err
    assert cap.err.index("compiling the deck kernels") < cap.err.index("1/3 f=")
    assert json.loads((out / "sweep.json").read_text())["compile_s"] >= 0.0
    rows = list(csv.DictReader((out / "sweep.csv").open()))
    f = np.array([float(r["f"]) for r in rows])
    np.testing.assert_allclose(f, [0.175, 0.7, 2.8], rtol=1e-9)
    assert {r["A"] for r in rows} == {"0.981"}
    R = steady_circle(2 * math.pi * 0.7, 0.981, MU)[0]
    assert float(rows[1]["u_peak_m"]) == pytest.approx(R, rel=2e-5)


@pytest.mark.parametrize(
    ("edit", "field"),
    [
        (("[motion]", '[motion]\nkind = "record3"\nrecord = "synthetic-wn-40s"\n[unused]'),
         "motion.kind"),
        (("n_periods = 12", "n_periods = 12\nvertical_amplitude = 1.0\nvertical_frequency = 1.1"),
         "motion.vertical_frequency"),
        (("amplitude = 0.981", "amplitude = -1.0"), "motion.amplitude"),
        (("amplitude = 0.981", "amplitude = 0.0"), "motion.amplitude"),
        (("[solver]", '[solver]\ncontact = "bilateral"'), "solver.contact"),
    ],
)  # fmt: skip
def test_bad_deck_sweeps_are_refused_in_one_line_naming_the_field(tmp_path, capsys, edit, field):
    text = SCENE.read_text()
    assert edit[0] in text
    scene = tmp_path / "bad.toml"
    text = text.replace(edit[0], edit[1])
    if "[unused]" in text:  # a record instead of the orbit: its keys dropped
        head, tail = text.split("[unused]")
        text = head + "[solver]" + tail.split("[solver]")[1]
    scene.write_text(text)
    rc = nsdyn_main(["sweep", str(scene), "--points", "2", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip()
    assert rc != 0 and len(err.splitlines()) == 1
    assert str(scene) in err and field in err


def test_a_triple_pendulum_deck_with_the_switch_law_is_refused_naming_the_law(tmp_path, capsys):
    # the series model of a triple pendulum has no stick events: the regularised law only
    text = (SCENES / "deck-tfp4-3c.toml").read_text()
    head, tail = text.split("[motion]")
    motion = (
        '[motion]\nkind = "orbit"\norbit = "circular"\nfrequency = 0.5\namplitude = 1.0\n'
        "n_periods = 9\n\n"
    )
    scene = tmp_path / "tfp.toml"
    scene.write_text(head + motion + "[solver]" + tail.split("[solver]")[1])
    rc = nsdyn_main(["sweep", str(scene), "--points", "2", "--friction", "switch",
                     "--out", str(tmp_path / "o")])  # fmt: skip
    err = capsys.readouterr().err.strip()
    assert rc != 0 and len(err.splitlines()) == 1
    assert "--friction: a triple friction pendulum runs with the regularised law" in err
    (tmp_path / "o").mkdir(exist_ok=True)  # the scene's own law, without the flag: its field
    scene.write_text(scene.read_text().replace('law = "arctan"', 'law = "switch"'))
    assert nsdyn_main(["sweep", str(scene), "--points", "2", "--out", str(tmp_path / "o")]) != 0
    assert f"{scene}: solver.law" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("flags", "why"),
    [(["--contact", "unilateral"],
      "(their orbits keep the plate's contact; an uplift ends a period)"),
     (["--steps-factor", "2"], "(their period map is integrated adaptively)")],
)  # fmt: skip
def test_isolated_only_flags_are_refused_for_a_deck_scene(tmp_path, capsys, flags, why):
    # each flag with its own reason (--steps-factor was said to be about bilateral contact)
    rc = nsdyn_main(["sweep", str(SCENE), *flags, "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert rc == 2 and f"{flags[0]}: not for deck scenes {why}" in err
    assert len(err.strip().splitlines()) == 1


def _office(tmp_path):
    """The bundled office taken rigid on 12 friction pendulums, under an elliptical orbit."""
    text = (SCENES / "building3d-office-rigid.toml").read_text()
    head, tail = text.split("[motion]")
    motion = (
        '[motion]\nkind = "orbit"\norbit = "elliptical"\nfrequency = 0.5\namplitude = 1.0\n'
        "amplitude_minor = 0.5\nangle = 30.0\nn_periods = 10\n\n"
    )
    scene = tmp_path / "office.toml"
    text = head + motion + "[solver]" + tail.split("[solver]")[1]
    scene.write_text(text)
    return scene


def test_a_rigid_building_sweeps_as_a_deck(tmp_path, capsys):
    # the building's rigid rung is a deck on its 12 pendulums (its twist in the state): every
    # orbit converges, the peak resultant displacement is at least the peak component (it is
    # sqrt(ux^2 + uy^2)), and the normal forces stay > 0 at 1 m/s^2 (no uplift)
    scene = _office(tmp_path)
    out = tmp_path / "out"
    rc = nsdyn_main(["sweep", str(scene), "--fmin", "0.6", "--fmax", "1.0", "--points", "2",
                     "--out", str(out), "--json", "--no-figures"])  # fmt: skip
    assert rc == 0
    report = json.loads(capsys.readouterr().out)
    assert report["kind"] == "building3d"
    rows = list(csv.DictReader((out / "sweep.csv").open()))
    assert len(rows) == 2
    for r in rows:
        assert r["converged"] == "true" and r["uplift"] == "false"
        assert float(r["u_peak_m"]) >= float(r["u_component_peak_m"]) * (1 - 1e-12)
        assert float(r["normal_min_N"]) > 0.0


def test_failures_are_reported_by_frequency_and_reason():
    # A vertical acceleration of 12 m/s^2 > g at the horizontal frequency takes the normal
    # force of the single isolator, N = m (g + a_z), through zero in every period (uplift):
    # no orbit of the bilateral model exists, and each frequency is reported with that reason;
    # without the fallback, the frequencies shooting missed are listed, none silently dropped
    from nsdyn.ground.orbit import HarmonicPlane

    pb = plane_problem(sdof(), HarmonicPlane.circular(0.7, A0, az=12.0), law="switch")
    curve = plane_response(pb, fmin=0.5, fmax=1.0, points=2)
    assert [p.quantities["uplift"] for p in curve.points] == [True, True]
    fails = curve.info["failures"]
    assert [d["f"] for d in fails] == pytest.approx([0.5, 1.0])
    assert all(d["reason"].startswith("uplift") for d in fails)
    from nsdyn.periodic.curve import EmptyCurveWarning

    with pytest.warns(EmptyCurveWarning, match="all 2 frequencies failed"):  # (said, not only
        bare = plane_response(pb, fmin=0.5, fmax=1.0, points=2, fallback=False)  # in info)
    assert bare.points == []
    assert [d["f"] for d in bare.info["failures"]] == pytest.approx([0.5, 1.0])
    assert all("no fallback" in d["reason"] for d in bare.info["failures"])


def test_a_stepped_sweep_stopped_by_a_later_uplift_reports_uplift_not_the_period_before():
    # the deck's loop stops at an uplift: a stepped sweep that integrated two periods and then
    # met one (injected here: which periods lift is not something a quick test can choose)
    # is a point with uplift and no quantities; the two periods before it were a transient
    # and gave a peak and "uplift: false" to a point that had left the model
    from nsdyn.periodic.curve import _point_from_sweep
    from nsdyn.periodic.plane import STATUS_UPLIFT
    from nsdyn.periodic.sweeps import steady_state_sweep

    pb = plane_problem(sdof(), circular(A0, F0), law="switch")
    run, calls = pb.run, []

    def lifting_from_the_third(x, f, samples, full=False):
        calls.append(np.array(x, dtype=float))
        st, X, out = run(x, f, samples, full)
        return (STATUS_UPLIFT if len(calls) >= 3 else st), X, out

    pb.run = lifting_from_the_third
    sw = steady_state_sweep(pb, F0, monodromy=False)
    assert (sw.periods_done, sw.status, sw.steady) == (2, STATUS_UPLIFT, False)
    np.testing.assert_array_equal(sw.x_stop, calls[2])  # the failing period's start
    pt = _point_from_sweep(pb, sw, "shooting failed")
    assert pt.quantities["uplift"] is True and math.isnan(pt.quantities["u_peak_m"])
    assert pt.X is None and not pt.converged
    assert pt.f == F0  # (and the same sweep without the failure reaches its steady state)
    pb.run = run
    assert steady_state_sweep(pb, F0, monodromy=False).steady


def test_the_plane_probe_follows_the_motion_over_the_periods_asked():
    # quantities_without_orbit integrates `periods` periods from x0, each from the last
    # state: without a vertical component the normal force is m g in every period (no
    # uplift, no failure over one or two); with 12 m/s^2 > g vertically it reaches zero in
    # the first period, which ends the probe whatever the periods asked
    from nsdyn.ground.orbit import HarmonicPlane

    flat = plane_problem(sdof(), circular(A0, F0), law="switch")
    for periods in (1, 2):
        q, why = flat.quantities_without_orbit(F0, flat.x_ref, periods)
        assert q["uplift"] is False and why == ""
    starts, ends, run = [], [], flat.run

    def recorded(x, f, samples, full=False):
        starts.append(np.array(x, dtype=float))
        out = run(x, f, samples, full)
        ends.append(out[1][-1, flat.rows])
        return out

    flat.run = recorded
    flat.quantities_without_orbit(F0, flat.x_ref, 3)
    assert len(starts) == 3  # each period from where the last one ended
    for k in (1, 2):
        np.testing.assert_array_equal(starts[k], ends[k - 1])
    assert np.abs(ends[0] - flat.x_ref).max() > 1e-3  # (the motion moved: a real check)
    with pytest.raises(ValueError, match="periods"):
        flat.quantities_without_orbit(F0, flat.x_ref, 0)
    lifting = plane_problem(sdof(), HarmonicPlane.circular(0.7, A0, az=12.0), law="switch")
    q, why = lifting.quantities_without_orbit(0.7, lifting.x_ref, 2)
    assert q["uplift"] is True and why


def _with_sweep(tmp_path, table: str) -> Path:
    text = SCENE.read_text()
    head = text.split("\n[sweep]")[0] + "\n"
    scene = tmp_path / "swept.toml"
    scene.write_text(head + "[sweep]\n" + table)
    return scene


def test_the_scenes_sweep_table_sets_the_curve_and_the_flags_win(tmp_path, capsys):
    # [sweep] f_min, f_max, points, amplitudes: the log-spaced frequencies f_min .. f_max and
    # the closed-form circle at each (steady circular slip, see the module docstring)
    scene = _with_sweep(tmp_path, "f_min = 0.35\nf_max = 1.4\npoints = 2\namplitudes = [1.2]\n")
    out = tmp_path / "a"
    assert nsdyn_main(["sweep", str(scene), "--out", str(out), "--no-figures"]) == 0
    rows = list(csv.DictReader((out / "sweep.csv").open()))
    np.testing.assert_allclose([float(r["f"]) for r in rows], [0.35, 1.4], rtol=1e-9)
    assert {r["A"] for r in rows} == {"1.2"}
    for r in rows:
        R = steady_circle(2 * math.pi * float(r["f"]), 1.2, MU)[0]
        assert float(r["u_peak_m"]) == pytest.approx(R, rel=2e-5)
    # the flags win over the table (into the same folder: every file there is this sweep's,
    # sweep.json was said to be an earlier command's)
    capsys.readouterr()
    assert nsdyn_main(["sweep", str(scene), "--fmax", "0.7", "--amplitudes", f"{A0}",
                       "--out", str(out), "--no-figures"]) == 0  # fmt: skip
    rows = list(csv.DictReader((out / "sweep.csv").open()))
    np.testing.assert_allclose([float(r["f"]) for r in rows], [0.35, 0.7], rtol=1e-9)
    assert all(float(r["A"]) == pytest.approx(A0, rel=1e-9) for r in rows)  # (9 digits)
    assert "also holds files" not in capsys.readouterr().err


@pytest.mark.parametrize(
    ("table", "field"),
    [
        ("f_min = 1.0\nf_max = 0.5\n", "sweep.f_max"),
        ("f_min = -1.0\n", "sweep.f_min"),
        ("points = 1\n", "sweep.points"),
        ("points = 2.5\n", "sweep.points"),
        ("points = 10001\n", "sweep.points"),
        ("amplitudes = [1.0, -2.0]\n", "sweep.amplitudes"),
        ("amplitudes = 1.0\n", "sweep.amplitudes"),
        ('law = "coulomb"\n', "sweep.law"),
        ("f_maximum = 2.0\n", "sweep.f_maximum"),
    ],
)
def test_a_bad_sweep_table_is_refused_in_one_line_naming_the_field(tmp_path, capsys, table,
                                                                    field):  # fmt: skip
    scene = _with_sweep(tmp_path, table)
    rc = nsdyn_main(["sweep", str(scene), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip()
    assert rc != 0 and len(err.splitlines()) == 1
    assert str(scene) in err and field in err


DECK_ORBIT = {  # four friction pendulums under an eccentric deck, an elliptical orbit
    "scene": {"kind": "deck"},
    "deck": {"m": 2.0e6, "J": 8.93e7, "ecc": [0.8, 0.5], "h": 1.5,
             "positions": [[-10.0, -6.0], [10.0, -6.0], [10.0, 6.0], [-10.0, 6.0]]},
    "bearing": {"type": "fps", "radius": 2.2, "mu_slow": 0.04, "mu_fast": 0.07, "rate": 30.0,
                "mu_static": 0.075, "d_cap": 0.35},
    "motion": {"kind": "orbit", "orbit": "elliptical", "frequency": 0.5, "amplitude": 2.0,
               "amplitude_minor": 1.0, "angle": 30.0, "n_periods": 4},
}  # fmt: skip


def test_a_fallback_seeded_off_the_model_settles_from_rest():
    """0.125-2 Hz in 5 points: the 1 Hz orbit rides the rims, shooting at 2 Hz fails from
    the curve's guess, and a sweep from that guess lifts a bearing off in its first period
    (a transient leaving the model). The steady state at 2 Hz stays in contact: Newton from
    rest finds it (N_min 4.0e6 N, 80 % of the static share), and the curve now shoots from
    rest when its guesses fail. Without Newton steps (max_iter = 0) the fallback sweeps from
    the previous orbit, leaves the model, then sweeps once more from rest and must settle on
    that orbit, not report an uplift. Tolerance 1e-4 on the peak: the sweep stops within an
    estimated 1e-6 of the orbit's excursion (SS_TOL), shooting within its own tolerance; the
    rest is the peaks' sampling."""
    from nsdyn.models.isolated import deck_scene as ds
    from nsdyn.periodic import shoot

    system = ds.build_system(DECK_ORBIT, "deck.toml")
    exc, _ = ds.build_motion(DECK_ORBIT, "deck.toml")
    pb = plane_problem(system, exc, law="switch", amplitude=2.0)
    ref = shoot(pb, 2.0)
    assert ref.converged
    u_ref = pb.orbit_quantities(2.0, ref.X)["u_peak_m"]
    last = plane_response(pb, fmin=0.125, fmax=2.0, points=5).points[-1]
    assert last.method == "shooting" and last.converged and not last.quantities["uplift"]
    assert last.quantities["u_peak_m"] == pytest.approx(u_ref, rel=1e-4)
    last = plane_response(pb, fmin=0.125, fmax=2.0, points=5, max_iter=0).points[-1]
    assert last.method == "sweep" and last.converged and not last.quantities["uplift"]
    assert "the sweep from the previous orbit stopped" in last.note
    assert last.quantities["u_peak_m"] == pytest.approx(u_ref, rel=1e-4)


@pytest.mark.parametrize("command", ["run", "sweep"])
def test_a_sweep_table_under_a_record_is_refused(tmp_path, capsys, command):
    # [sweep] follows an orbit; under a record nsdyn run ignored it without a word
    text = (SCENES / "deck-fps4-3c.toml").read_text()
    assert 'kind = "record3"' in text
    scene = tmp_path / "s.toml"
    scene.write_text(text + "\n[sweep]\nf_min = 0.2\nf_max = 2.0\n")
    rc = nsdyn_main([command, str(scene), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and len(err.splitlines()) == 1
    assert f"{scene}: sweep: read by nsdyn sweep, which follows an orbit" in err
    assert not (tmp_path / "o").exists()


def test_the_component_peak_of_a_slip_along_x_is_its_resultant_peak():
    # u = (A sin wt, 0) sampled off its peak: the component read from the samples alone lay
    # below the refined resultant (0.0533315 against 0.0533346 m), as if the slip had a y part.
    # Both are now refined alike (identical: the same interpolant), within the Hermite error
    # h^4 max|u''''| / 384 = h^4 A w^4 / 384 of the true peak A
    from nsdyn.periodic.plane import component_peak, hermite_peak

    A, w, n = 0.05, 2 * np.pi * 0.66, 37
    h = (2 * np.pi / w) / n
    t = (np.arange(n + 1) + 0.3) * h  # no sample at the peak
    u = np.zeros((n + 1, 1, 2))
    v = np.zeros((n + 1, 1, 2))
    u[:, 0, 0], v[:, 0, 0] = A * np.sin(w * t), A * w * np.cos(w * t)
    r = hermite_peak(u[:, 0], v[:, 0], h)
    assert component_peak(u, v, h) == r
    assert abs(r - A) <= h**4 * A * w**4 / 384 and np.abs(u).max() < A - h**4 * A * w**4 / 384
