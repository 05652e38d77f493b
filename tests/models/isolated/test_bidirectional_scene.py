"""Deck scenes (``[scene] kind = "deck"``) through ``nsdyn run``: summary, histories, figure.

Source: the scene reader's contract (the library run of the same system gives the same numbers;
the summary's keys carry their units) and the displacement capacity of a friction pendulum
(the rim stop is reported, never silent).
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest

from nsdyn.models.isolated import deck_scene as ds
from nsdyn.models.isolated.deck import simulate_plane
from nsdyn.models.isolated.defaults import EPS
from nsdyn.models.scenefile import SceneError

ROOT = Path(__file__).resolve().parents[3]
SCENES = ROOT / "examples" / "scenes"


def _cfg(name: str) -> dict:
    return tomllib.loads((SCENES / name).read_text())


def test_sdof_circular_scene_equals_the_library_run(tmp_path):
    cfg = _cfg("sdof-bidirectional-circular.toml")
    s = ds.run_scene(cfg, source="sdof.toml", out_dir=tmp_path, figures=False, quiet=True)
    system = ds.build_system(cfg, "sdof.toml")
    exc, t_end = ds.build_motion(cfg, "sdof.toml")
    res = simulate_plane(system, exc, t_end=t_end, dt_out=0.01)
    assert s["peak_resultant_displacement_m"] == res.summary()["peak_resultant_displacement_m"]
    assert t_end == pytest.approx(12 / 0.4, rel=1e-15)  # n_periods / f
    for key in (
        "peak_resultant_displacement_m",
        "peak_resultant_friction_N",
        "peak_resultant_restoring_N",
        "peak_torsion_rad",
        "residual_displacement_m",
    ):
        assert np.isfinite(s[key]), key  # fmt: skip
    # resultant, not the larger component: max_t |u(t)| of the saved slip history, exactly
    # (on an orbit centred at rest the two peaks coincide, so no margin between them is implied)
    with np.load(tmp_path / "deck.npz") as z:
        u = z["u"][:, 0, :]
    assert s["peak_resultant_displacement_m"] == np.hypot(u[:, 0], u[:, 1]).max()
    assert s["peak_component_displacement_m"] == np.abs(u).max()
    # friction: the disc bounds the resultant by mu m g
    assert s["peak_resultant_friction_N"] <= 0.03 * 1.0e5 * system.g * (1 + 1e-9)
    with np.load(tmp_path / "deck.npz") as z:
        assert z["u"].shape == (z["t"].size, 1, 2)
    json.dumps(s)  # the summary is JSON (nsdyn run --json)


def test_rim_contact_is_in_the_summary_and_the_printed_table(tmp_path):
    cfg = _cfg("sdof-bidirectional-circular.toml")
    cfg["bearing"] = {"type": "fps", "radius": 1.0, "mu": 0.02, "d_cap": 0.05}
    cfg["motion"].update(frequency=0.5, amplitude=1.5)
    s = ds.run_scene(cfg, source="rim.toml", out_dir=tmp_path, figures=False, quiet=True)
    assert s["rim_contacts"] and s["rim_contacts"][0]["peak_overshoot_m"] > 0
    assert any("displacement capacity" in w for w in s["warnings"])
    assert "RIM CONTACT isolator 0" in ds.format_summary(s)


def test_deck_scene_figure(tmp_path):
    pytest.importorskip("matplotlib")
    from nsdyn.plot.isolators import scene_figures

    cfg = _cfg("deck-fps4-3c.toml")
    cfg["motion"]["t_end"] = 4.0
    s = ds.run_scene(cfg, source="deck.toml", out_dir=tmp_path, figures=True, quiet=True)
    assert s["n_isolators"] == 4 and len(s["peak_resultant_displacement_per_isolator_m"]) == 4
    files = scene_figures(s, tmp_path)
    assert Path(files[0]).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_cli_runs_a_deck_scene_and_prints_json(tmp_path, capsys):
    from nsdyn.cli.app import main

    rc = main(["run", str(SCENES / "sdof-bidirectional-circular.toml"), "--out",
               str(tmp_path / "out"), "--json", "--no-figures"])  # fmt: skip
    assert rc == 0
    s = json.loads(capsys.readouterr().out)
    assert s["kind"] == "deck" and s["law"] == "switch"


def test_an_end_between_the_records_samples_is_said_as_such(tmp_path, capsys):
    # it read "t_end = 1.013 s is past the excitation's end (1.01 s)" of a 40 s record
    from nsdyn.cli.app import main

    rc = main(["run", str(SCENES / "deck-fps4-3c.toml"), "--t-end", "1.013", "--pga", "2",
               "--out", str(tmp_path / "out"), "--json", "--no-figures"])  # fmt: skip
    s = json.loads(capsys.readouterr().out)
    assert rc == 0 and s["t_end_s"] == pytest.approx(1.01, abs=1e-12)
    # the record's scale is in the summary (two runs at other PGAs read alike), as the
    # isolated frame's: the whole record's resultant scaled to --pga, the run's window below
    assert s["record_pga_mps2"] == 2.0 and 0.0 < s["pga_mps2"] <= 2.0
    assert s["record_pga_component"] == "resultant"
    said = [n for n in s["notes"] if "t_end = 1.013 s" in n]
    assert said == ["t_end = 1.013 s is not a sample time of the record (every 0.01 s); the "
                    "run ends at its last sample before it, 1.01 s"]  # fmt: skip


def test_a_bearing_error_names_the_file_and_field():
    cfg = _cfg("deck-fps4-3c.toml")
    cfg["bearing"]["radius"] = -1.0
    with pytest.raises(SceneError, match=r"^deck\.toml: bearing\.radius: expected a positive"):
        ds.build_system(cfg, "deck.toml")


def test_a_position_that_is_not_finite_names_the_positions():
    # (it was reported against deck.J, whose default the positions make)
    cfg = _cfg("deck-fps4-3c.toml")
    del cfg["deck"]["J"]
    cfg["deck"]["positions"][3][1] = float("nan")
    with pytest.raises(SceneError, match=r"^deck\.toml: deck\.positions: expected a list of fin"):
        ds.build_system(cfg, "deck.toml")


def test_tfp_scene_runs_with_the_regularised_law_and_equals_the_library_run(tmp_path):
    # the triple pendulum scene (shortened): the reader builds the series-model bearings, picks
    # the regularised law, and its summary is the library run's; a figure and JSON follow
    pytest.importorskip("matplotlib")
    from nsdyn.models.isolated.tfp import TripleBearing
    from nsdyn.plot.isolators import scene_figures

    cfg = _cfg("deck-tfp4-3c.toml")
    cfg["motion"]["t_end"] = 3.0
    del cfg["solver"]["law"]  # (the default for a TFP: the regularised law)
    system = ds.build_system(cfg, "tfp.toml")
    assert all(isinstance(b, TripleBearing) for b in system.bearings)
    assert system.bearings[0].d_cap == pytest.approx(0.92, rel=1e-12)  # d1 + d2 + d3 + d4
    s = ds.run_scene(cfg, source="tfp.toml", out_dir=tmp_path, figures=True, quiet=True)
    assert s["law"] == "arctan" and s["t_end_s"] == pytest.approx(3.0)
    exc, t_end = ds.build_motion(cfg, "tfp.toml")
    res = simulate_plane(system, exc, t_end=t_end, law="arctan", rtol=1e-6)  # (default atol)
    assert s["peak_resultant_displacement_m"] == res.summary()["peak_resultant_displacement_m"]
    assert "tfp_surface_limits" in s
    # the elements' slips are in the histories file as in the library's tables (they were not)
    with np.load(tmp_path / "deck.npz") as d:
        h = res.histories()
        for k in ("s1x", "s3y", "s4x"):
            np.testing.assert_array_equal(d[k], h[f"{k}_iso_{{}}_m"])
    files = scene_figures(s, tmp_path)
    assert Path(files[0]).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    json.dumps(s)


def test_tfp_scene_errors_name_the_field():
    cfg = _cfg("deck-tfp4-3c.toml")
    cfg["bearing"]["d4"] = 0.05  # below the inner capacities d2 = d3 = 0.06
    with pytest.raises(SceneError, match=r"^tfp\.toml: bearing\.d4: expected a displacement "
                       r"capacity >= the inner ones"):  # fmt: skip
        ds.build_system(cfg, "tfp.toml")
    cfg = _cfg("deck-tfp4-3c.toml")
    cfg["solver"]["law"] = "switch"
    with pytest.raises(SceneError, match=r"^tfp\.toml: solver\.law: a triple friction pendulum"):
        ds.build_solver(cfg, "tfp.toml")
    cfg = _cfg("deck-tfp4-3c.toml")
    cfg["bearing"]["radius"] = 2.0
    with pytest.raises(SceneError, match=r"^tfp\.toml: bearing\.radius: not a key of a triple"):
        ds.build_system(cfg, "tfp.toml")


@pytest.mark.parametrize(
    ("law", "solver", "bearing", "named"),
    [
        ("switch", {"eps": 100.0}, {}, ["solver.eps"]),
        ("arctan", {"eta": 0.1}, {"mu_static": 0.075}, ["solver.eta", "bearing.mu_static"]),
        ("switch", {"eta": 1e-4}, {"mu_static": 0.075}, []),
        ("arctan", {"eps": 1e4}, {}, []),
    ],
)
def test_a_law_key_the_runs_law_does_not_read_is_noted(law, solver, bearing, named):
    # eps under the switch law, eta and a static friction under the arctan law (no stick)
    cfg = tomllib.loads((SCENES / "deck-fps4-3c.toml").read_text())
    cfg["solver"] = {"law": law, **solver}
    cfg["bearing"] = {k: v for k, v in cfg["bearing"].items() if k != "mu_static"} | bearing
    assert [k for k, _ in ds.unused_law_keys(cfg)] == named


def test_a_deck_run_prints_the_unread_law_keys(tmp_path, capsys):
    from nsdyn.cli import main

    text = (SCENES / "sdof-bidirectional-circular.toml").read_text()
    scene = tmp_path / "s.toml"
    scene.write_text(text.replace('law = "switch"', 'law = "switch"\neps = 100.0'))
    assert main(["run", str(scene), "--no-figures", "--out", str(tmp_path / "o")]) == 0
    err = capsys.readouterr().err  # noted once, the run given the default (no warning too)
    assert err.count("deck: note: solver.eps not used: the arctan law's sharpness") == 1
    assert "eps = 100 not used" not in err and "eps = 100.0 not used" not in err
    cfg = tomllib.loads(scene.read_text())  # a sweep's --friction arctan reads the scene's eps
    assert ds.build_solver(cfg, "s.toml")["eps"] == EPS
    from nsdyn.studies.plane_sweep import plane_scene

    assert plane_scene(cfg, "s.toml")["solver"]["eps"] == 100.0
