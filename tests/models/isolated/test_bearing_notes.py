"""Bearing inputs a run accepts but that are probably mistakes are said, one line each:
a friction coefficient above 1 (sliding isolators' are 0.01-0.2: a percentage given as a
number?), and a static contact pressure N/area more than ten times from ``p_ref`` (an area
in cm² or a p_ref in MPa), with the friction factor 0.7^((p - p_ref)/50 MPa) it gives."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from nsdyn.cli import main
from nsdyn.models.isolated.bearings import Bearing, Friction, bearing_notes
from nsdyn.models.isolated.tfp import TripleBearing

TFP = dict(R1=2.2, R2=0.3, R3=0.3, R4=2.2, mu1=0.06, mu2=0.02, mu3=0.02, mu4=0.10,
           d1=0.40, d2=0.06, d3=0.06, d4=0.40)  # fmt: skip
N = [2.0e6, 3.0e6]  # static normal forces [N]


def test_plausible_bearings_have_no_notes():
    flat = Bearing(Friction(0.05, 0.08, rate=30.0, mu_static=0.09), area=0.1, p_ref=2.5e7)
    assert bearing_notes([flat, flat], N) == []  # pressures 20 and 30 MPa against 25
    assert bearing_notes([TripleBearing(**TFP)] * 2, N) == []
    assert bearing_notes([Bearing(Friction(1.0))] * 2, N) == []  # 1 itself: the bound


def test_a_coefficient_above_one_is_named_by_its_field():
    b = Bearing(Friction(0.05, 5.0, rate=30.0), where="bearing")
    assert bearing_notes([b, b], N) == [
        "bearing.mu_fast = 5: a friction coefficient above 1 (sliding isolators' are about "
        "0.01-0.2); a percentage given as a number?"
    ]
    t = TripleBearing(**{**TFP, "mu4": 6.0}, where="tfp")
    (note,) = bearing_notes([t, t], N)
    assert note.startswith("tfp.mu4 = 6: a friction coefficient above 1")


def test_a_radius_in_mm_is_said_with_its_period():
    # R = 2200 (mm for 2.2 m) ran as a pendulum of a 94 s period, unsaid; T = 2π√(R/g)
    import math

    b = Bearing(Friction(0.04), radius=2200.0)
    T = 2 * math.pi * math.sqrt(2200.0 / 9.81)
    assert bearing_notes([b], N[:1]) == [
        f"bearing.radius: R = 2200 m is a pendulum of period 2π√(R/g) = {T:.3g} s (built ones: "
        "R of 1-6 m, 2-5 s); check it is in m"
    ]
    t = TripleBearing(**{**TFP, "R1": 2200.0, "R4": 2200.0}, where="tfp")  # (its effective R)
    assert bearing_notes([t], N[:1])[0].startswith("tfp.R1 and R4: R1 + R4 = 4400 m is a ")
    t = TripleBearing(**{**TFP, "R4": 2200.0}, where="tfp")  # (the one key given in mm)
    assert bearing_notes([t], N[:1])[0].startswith("tfp.R4: R1 + R4 = 2202.2 m is a ")
    assert bearing_notes([Bearing(Friction(0.04), radius=20.0)], N[:1]) == []  # 9 s: the bound


@pytest.mark.parametrize(("area", "p_ref", "ratio"), [(0.1, 20.0, 1e6), (1000.0, 2e7, 1e-4)])
def test_a_static_pressure_far_from_p_ref_is_said_with_its_friction_factor(area, p_ref, ratio):
    # p_ref in MPa (20 Pa) or the area in cm² (1000 for 0.1 m²): the pressure at the first
    # isolator, 2e6 / area, against p_ref, and the factor of the law at that pressure
    b = Bearing(Friction(0.05), area=area, p_ref=p_ref, where="bearing")
    (note,) = bearing_notes([b, b], N)
    p = N[0] / area
    assert p / p_ref == pytest.approx(ratio, rel=1e-12)
    k_p = max(0.7 ** ((p - p_ref) / 50e6), 1e-12)
    assert note == (
        f"bearing.area: the static pressure N/area at isolator 0 is {p / 1e6:.3g} MPa, "
        f"{p / p_ref:.3g}x p_ref = {p_ref / 1e6:.3g} MPa, so its friction is {k_p:.3g}x the "
        "coefficients given; check area [m²] and p_ref [Pa]"
    )


def test_run_says_an_isolation_mu_above_one(capsys, tmp_path):
    scene = tmp_path / "s.toml"
    scene.write_text("[isolation]\nmu = [0.05, 1.5]\n[motion]\nt_end = 0.2\n")
    argv = ["run", str(scene), "--no-figures", "--out", str(tmp_path / "o")]
    assert main(argv) == 0
    err = capsys.readouterr().err.splitlines()
    said = [ln for ln in err if "a friction coefficient above 1" in ln]  # (once, its entry)
    assert len(said) == 1 and said[0].startswith("nsdyn run: note: isolation.mu[1] = 1.5: ")


def test_a_deck_run_says_its_bearing_notes(capsys, tmp_path):
    from pathlib import Path

    src = Path(__file__).resolve().parents[3] / "examples/scenes/deck-fps4-3c.toml"
    text = src.read_text().replace("d_cap = 0.35", "d_cap = 0.35\narea = 0.05\np_ref = 30.0")
    scene = tmp_path / "deck.toml"
    scene.write_text(text)
    argv = ["run", str(scene), "--t-end", "0.2", "--no-figures", "--out", str(tmp_path / "o")]
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "deck: note: bearing.area: the static pressure N/area at isolator 0 is " in err
    assert "check area [m²] and p_ref [Pa]" in err
    assert err.count("the static pressure N/area") == 1  # (said once: the run's warning too)


def test_a_python_deck_call_warns_what_a_scene_notes():
    # the Python calls said nothing where a scene notes a bearing's pressure far from p_ref
    # or a switch law's stick band eta above 1e-3 m/s (a stuck isolator creeping)
    from nsdyn._checks import NotedWarning
    from nsdyn.models.isolated.deck import sdof_plane, simulate_plane

    orbit = {"f": 1.0, "ax": 1.0, "ay": 0.0}
    deck = sdof_plane(1.0e5, Bearing(Friction(0.05), radius=2.0, area=0.05, p_ref=30.0))
    with pytest.warns(NotedWarning, match=r"^bearing.area: the static pressure N/area at "
                      r"isolator 0 is 19.6 MPa, 6.54e\+05x p_ref"):  # fmt: skip
        simulate_plane(deck, orbit, t_end=0.05)
    plain = sdof_plane(1.0e5, Bearing(Friction(0.05), radius=2.0))
    with pytest.warns(NotedWarning, match=r"^eta = 0.01 m/s: the switch law holds a stuck "
                      r"isolator only to \|v\| <= eta"):  # fmt: skip
        simulate_plane(plain, orbit, t_end=0.05, law="switch", eta=0.01)


def test_a_slip_beyond_a_quarter_of_the_radius_is_said_with_the_spheres_force():
    # the restoring force N u/R is the small-angle form of N u/sqrt(R² - u²): at u/R = 0.6
    # the sphere's is 1/0.8 - 1 = 25 % larger; up to 0.25 R (3.3 %) nothing is said, and a
    # flat slider (R = inf) has no such law
    from nsdyn.models.isolated.bearings import BearingError, slip_ratio_note

    fps, flat = Bearing(Friction(0.05), radius=2.0), Bearing(Friction(0.05), k_lam=1e5)
    assert slip_ratio_note([fps, fps], [0.5, 0.2]) is None
    assert slip_ratio_note([flat, flat], [5.0, 5.0]) is None
    note = slip_ratio_note([fps, fps, flat], [0.3, 1.2, 9.0])
    assert note.startswith("isolator 1's peak slip is 0.6 of its radius R = 2 m") and "25 %" in note
    past = slip_ratio_note([fps], [20.0])  # (it read "10 of its radius")
    assert past.startswith("isolator 0's peak slip is 10 times its radius R = 2 m: past the")
    # a capacity at or past the radius has no spherical surface to slide on: refused, named
    want = r"^bearing.d_cap: expected a displacement capacity below the radius R = 0.05 m, got"
    with pytest.raises(BearingError, match=want + r" 0.35 m$"):
        Bearing(Friction(0.05), radius=0.05, d_cap=0.35, where="bearing")


def test_a_friction_falling_with_slip_speed_is_noted_as_a_likely_swap():
    # mu_fast 0.02 beside mu_slow 0.04 (the two swapped) slid 3.4x as far as the bearing
    # given, without a word; a falling law is a model the bearing accepts: noted, not refused
    swapped = Bearing(Friction(0.04, mu_fast=0.02, rate=30.0), radius=2.2)
    (note,) = bearing_notes([swapped], N[:1])
    assert note == ("bearing.mu_fast = 0.02 < mu_slow = 0.04: friction that falls with the "
                    "slip speed (PTFE's rises: swapped?)")  # fmt: skip
    assert bearing_notes([Bearing(Friction(0.02, mu_fast=0.04, rate=30.0))], N[:1]) == []


def test_a_triple_pendulum_with_friction_far_below_a_built_ones_is_noted_before_its_run():
    # every surface at 1e-5 ran 3 min before its steps collapsed, without a word before; the
    # smallest coefficient is named (its flow rule's viscosity is OVERSTRESS min mu)
    t = TripleBearing(**{**TFP, "mu2": 3e-5, "mu3": 5e-5}, where="bearing")
    (note,) = bearing_notes([t, t], N)
    assert note.startswith("bearing.mu2 = 3e-05: far below a built bearing's friction (0.01-0.2);")
    assert "may take minutes or stop with its steps collapsed (check mu1..mu4)" in note
    at_bound = TripleBearing(**{**TFP, "mu2": 1e-4, "mu3": 1e-4})  # (1e-4: 40 s in seconds)
    assert bearing_notes([at_bound], N[:1]) == []


def test_a_deck_in_millimetres_is_said_before_its_run(capsys, tmp_path):
    # the example deck (20 m x 12 m) with its positions in mm: a plan of 20 km x 12 km, which
    # no isolated building has; said as a note before the run, and by a Python call
    from pathlib import Path

    from nsdyn._checks import NotedWarning
    from nsdyn.models.isolated.bearings import Friction
    from nsdyn.models.isolated.deck import PLAN_PLAUSIBLE, rigid_deck, simulate_plane

    src = Path(__file__).resolve().parents[3] / "examples/scenes/deck-fps4-3c.toml"
    mm = "[[-10000.0, -6000.0], [10000.0, -6000.0], [10000.0, 6000.0], [-10000.0, 6000.0]]"
    text = src.read_text()
    assert "[[-10.0, -6.0], [10.0, -6.0], [10.0, 6.0], [-10.0, 6.0]]" in text
    scene = tmp_path / "deck.toml"
    scene.write_text(text.replace("[[-10.0, -6.0], [10.0, -6.0], [10.0, 6.0], [-10.0, 6.0]]", mm))
    argv = ["run", str(scene), "--t-end", "0.05", "--no-figures", "--out", str(tmp_path / "o")]
    main(argv)  # (its run may fail on the mm scale: the note comes first)
    err = capsys.readouterr().err
    assert err.count("deck: note: deck.positions: the isolators span 20000 m x 12000 m") == 1
    assert 20.0 < PLAN_PLAUSIBLE < 20_000.0  # the example's plan passes, its mm plan does not
    pos = [[-10.0, -6.0], [10.0, -6.0], [10.0, 6.0], [-10.0, 6.0]]
    b, orbit = Bearing(Friction(0.05), radius=2.2), {"f": 1.0, "ax": 1.0, "ay": 0.0}
    with pytest.warns(NotedWarning, match="are they in mm"):
        simulate_plane(rigid_deck(2e6, 9.07e7, np.array(pos) * 1e3, b), orbit, t_end=0.05)
    with warnings.catch_warnings():
        warnings.simplefilter("error", NotedWarning)
        simulate_plane(rigid_deck(2e6, 9.07e7, pos, b), orbit, t_end=0.05)


def test_a_deck_in_tonnes_is_said_before_its_run(capsys, tmp_path):
    # a deck's mass in t (1500 "kg" on a 30 m x 10 m plan) ran with its forces 1000x too small
    # and its slips unchanged (a pendulum's response does not depend on the mass), unsaid;
    # here the example deck's 2000 t as 2000 "kg"
    from pathlib import Path

    from nsdyn._checks import NotedWarning
    from nsdyn.models.isolated.bearings import Friction
    from nsdyn.models.isolated.deck import DECK_MASS_PLAUSIBLE, rigid_deck, simulate_plane

    src = Path(__file__).resolve().parents[3] / "examples/scenes/deck-fps4-3c.toml"
    text = src.read_text()
    assert "m = 2.0e6" in text  # the example deck: 2000 t on 20 m x 12 m, 8 333 kg/m²
    scene = tmp_path / "deck.toml"
    scene.write_text(text.replace("m = 2.0e6", "m = 2000.0", 1))
    argv = ["run", str(scene), "--t-end", "0.05", "--no-figures", "--out", str(tmp_path / "o")]
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert err.count("deck: note: deck.m = 2000 kg over the isolators' 20 m x 12 m plan is "
                     "8.33 kg/m², far below any deck's or building's") == 1  # fmt: skip
    assert 8.33 < DECK_MASS_PLAUSIBLE < 8333.0  # the example passes, in t it does not
    pos = [[-10.0, -6.0], [10.0, -6.0], [10.0, 6.0], [-10.0, 6.0]]
    b, orbit = Bearing(Friction(0.05), radius=2.2), {"f": 1.0, "ax": 1.0, "ay": 0.0}
    with pytest.warns(NotedWarning, match=r"\.m = 2000 kg .* is it in t\?$"):
        simulate_plane(rigid_deck(2e3, 9.07e4, pos, b), orbit, t_end=0.05)


def test_a_pair_system_run_warns_what_a_deck_run_notes():
    # Friction(5) (a percentage) on a PairSystem ran, stuck throughout, without a word, where
    # Isolation(mu=5) and a deck's bearings are noted
    from nsdyn._checks import NotedWarning
    from nsdyn.models.isolated.pairs import PairSystem, simulate_pairs

    M, Z = np.diag([1000.0] * 3), np.zeros((3, 3))
    D = np.array([[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])
    b = Bearing(Friction(5.0), k_lam=4e4)
    s = PairSystem(M=M, K=Z, C=Z, Gamma=np.eye(3), D=D, R=np.array([[0.0, 0.0, 1.0]]),
                   bearings=(b,), positions=np.zeros((1, 2)))  # fmt: skip
    with pytest.warns(NotedWarning, match=r"= 5: a friction coefficient above 1"):
        simulate_pairs(s, {"f": 1.0, "ax": 1.0}, t_end=0.2)


def test_a_building_run_says_its_bearing_notes_once(capsys, tmp_path):
    # the cb rung's warm-up run said a bearing's note a second time, after the scene's own
    from pathlib import Path

    src = Path(__file__).resolve().parents[3] / "examples/scenes/building3d-office-cb.toml"
    text = src.read_text()
    assert "mu_fast = 0.07" in text
    scene = tmp_path / "b.toml"
    scene.write_text(text.replace("mu_fast = 0.07", "mu_fast = 0.02"))
    argv = ["run", str(scene), "--t-end", "0.1", "--no-figures", "--out", str(tmp_path / "o")]
    assert main(argv) == 0
    assert capsys.readouterr().err.count("mu_fast = 0.02 < mu_slow = 0.04") == 1


@pytest.mark.parametrize(
    "change, said",
    [
        # a percentage in a file: mu = 5 ran (a note named mu_slow) and stuck the whole run
        (("mu_slow = 0.04", "mu = 5.0"), "bearing.mu: expected a friction coefficient at most 1"),
        (("mu_static = 0.075", "mu_static = 7.5"), "bearing.mu_static: expected a friction "),
        (("radius = 2.2 ", "radius = 2200.0 "), "bearing.radius: R = 2200 m is above the 20 m"),
    ],
)
def test_a_scene_bearing_in_the_wrong_unit_is_refused_naming_its_key(change, said, tmp_path,
                                                                      capsys):  # fmt: skip
    from pathlib import Path

    src = Path(__file__).resolve().parents[3] / "examples/scenes/deck-fps4-3c.toml"
    text = src.read_text()
    assert change[0] in text
    text = text.replace(change[0], change[1])
    if change[1].startswith("mu ="):
        text = text.replace("mu_fast = 0.07\n", "").replace("rate = 30.0", "")
    scene = tmp_path / "deck.toml"
    scene.write_text(text)
    assert main(["run", str(scene), "--t-end", "0.1", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith(f"nsdyn run: error: {scene}: {said}")


@pytest.mark.parametrize(
    "change, said",
    [
        (("mu1 = 0.06", "mu1 = 6.0"), "bearing.mu1: expected a friction coefficient at most 1"),
        # the inner radius out of range is named, not the outer one it is compared with
        (("R2 = 0.3", "R2 = 300.0"), "bearing.R2: R2 = 300 m is above the 20 m of built"),
        (
            ("d2 = 0.06", "d2 = 0.6"),
            "bearing.d1: expected a displacement capacity >= the inner ones' (d2 = 0.6 m)",
        ),
    ],
)
def test_a_scene_triple_pendulum_names_the_key_at_fault(change, said, tmp_path, capsys):
    from pathlib import Path

    src = Path(__file__).resolve().parents[3] / "examples/scenes/deck-tfp4-3c.toml"
    text = src.read_text()
    assert change[0] in text
    scene = tmp_path / "tfp.toml"
    scene.write_text(text.replace(change[0], change[1]))
    assert main(["run", str(scene), "--t-end", "0.1", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith(f"nsdyn run: error: {scene}: {said}")


def test_a_triple_pendulum_key_without_its_type_says_to_add_it():
    # the user wrote no type and read "not of type 'flat'"
    from nsdyn.models.isolated.bearings import BearingError, bearing_from_config

    with pytest.raises(BearingError, match=r"^bearing.R1: a key of a triple friction pendulum "
                       r"\(type = 'tfp'\); add type = 'tfp' to the table$"):  # fmt: skip
        bearing_from_config({"mu": 0.05, "R1": 2.2}, "bearing")
    with pytest.raises(BearingError, match=r"^bearing.R1: .*; not of type 'fps'$"):
        bearing_from_config({"type": "fps", "radius": 2.0, "mu": 0.05, "R1": 2.2}, "bearing")
