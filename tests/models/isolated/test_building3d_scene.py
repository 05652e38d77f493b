"""3D building scenes (``kind = "building3d"``): the reader, both rungs, and its errors.

Sources: the office's mass (the sum of its member and floor masses) and the closed-form move
of its centre of mass under a 5 % accidental eccentricity (the floor masses, and only they,
move by 0.05 L_y); the symmetry of the rigid-floor kinematics (a floor that only translates
drifts equally at its corners and its centre).
"""

from __future__ import annotations

import copy
import warnings
from pathlib import Path

import numpy as np
import pytest

from nsdyn.models.isolated.building3d_scene import build_system, format_summary, run_scene
from nsdyn.models.scenefile import SceneError
from nsdyn.structure import load_frame3d

EPS = np.finfo(float).eps
REPO = Path(__file__).resolve().parents[3]
RIGID = {
    "scene": {"kind": "building3d"},
    "structure": {"frame3d": "office-11-3d", "fidelity": "rigid", "eccentricity": [0.0, 0.05]},
    "bearing": {"type": "fps", "radius": 2.2, "mu": 0.05},
    "motion": {"kind": "record3", "record": "synthetic-wn-40s", "t_end": 4.0},
}


def _cfg(**tables):
    cfg = copy.deepcopy(RIGID)
    for t, v in tables.items():
        if v is None:
            cfg.pop(t)
        else:
            cfg.setdefault(t, {}).update(v)
    return cfg


def test_rigid_scene_runs_the_office_as_a_deck(tmp_path):
    # m = sum of member and floor masses; the 5 % shift moves the floors' mass by 0.05 x 80 m
    # and the centre of mass by that times the floors' share of the mass (1e3 eps relative)
    f = load_frame3d("office-11-3d")
    s = run_scene(_cfg(), source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip
    assert s["mass_kg"] == pytest.approx(f.total_mass, rel=1e3 * EPS)
    m_floors = sum(d.mass for d in f.diaphragms)
    shift = 0.05 * 80.0 * m_floors / f.total_mass
    assert s["centre_of_mass_m"][1] == pytest.approx(40.0 + shift, rel=1e3 * EPS)
    assert s["n_isolators"] == 12 and s["peak_resultant_displacement_m"] > 0
    assert (tmp_path / "building3d.npz").is_file()
    assert "peak twist" in format_summary(s)


def test_fixed_scene_drifts_and_torsion(tmp_path):
    # without eccentricity the floors only translate (doubly symmetric office): the corner
    # drifts equal those at the centre of mass to round-off; the 5 % shift makes them larger
    cfg = _cfg(structure={"fidelity": "fixed", "n_modes": 12}, bearing=None)
    s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip
    assert s["corner_amplification_x"] > 1.05
    assert s["peak_torsional_moment_Nm"] > 0
    # the mass and its centre as the isolated rungs report them (the rigid test's sources)
    f = load_frame3d("office-11-3d")
    shift = 0.05 * 80.0 * sum(d.mass for d in f.diaphragms) / f.total_mass
    assert s["mass_kg"] == pytest.approx(f.total_mass, rel=1e3 * EPS)
    assert s["centre_of_mass_m"][1] == pytest.approx(40.0 + shift, rel=1e3 * EPS)
    assert s["warnings"] == [] and "fixed-base modes" in format_summary(s)
    cfg["structure"]["eccentricity"] = [0.0, 0.0]
    s0 = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                   quiet=True)  # fmt: skip
    assert s0["corner_amplification_x"] == pytest.approx(1.0, abs=1e-8)
    assert s0["corner_amplification_y"] == pytest.approx(1.0, abs=1e-8)


@pytest.mark.parametrize(
    ("tables", "field"),
    [
        ({"bearing": None}, "bearing"),
        ({"structure": {"frame3d": "no-such-frame"}}, "structure.frame3d"),
        ({"structure": {"fidelity": "medium"}}, "structure.fidelity"),
        ({"structure": {"fidelity": "cb", "f_max": -1.0}}, "structure.f_max"),
        ({"structure": {"fidelity": "cb", "min_mass": 2.0}}, "structure.min_mass"),
        ({"structure": {"fidelity": "cb", "base": "slab"}}, "structure.base"),
        ({"structure": {"fidelity": "full", "damping": "rayleigh"}}, "structure.damping"),
        # the office is above the dense limit: its full rung is sparse, the regularised law only
        ({"structure": {"fidelity": "full"}, "solver": {"law": "switch"}}, "solver.law"),
        ({"structure": {"eccentricity": [0.0, 0.6]}}, "structure.eccentricity"),
        ({"structure": {"n_modes": 0}}, "structure.n_modes"),
        ({"structure": {"frame3": "office-11-3d"}}, "frame3"),
        # a rim inside the stick range mu R = 1.1 m: refused on the cb rung as on the rigid
        # one, before its reduction (it came as a traceback from the run, after the build)
        ({"structure": {"fidelity": "cb"}, "bearing": {"mu": 0.5, "d_cap": 0.35}}, "bearing.d_cap"),
    ],
)
def test_bad_input_names_the_field(tables, field, tmp_path):
    with pytest.raises(SceneError, match=field.replace(".", r"\.")):
        build_system(_cfg(**tables), str(tmp_path / "s.toml"))


@pytest.mark.parametrize("fidelity", ["cb", "full"])
def test_a_floor_without_mass_is_named_on_the_rungs_that_need_one(tmp_path, fidelity):
    # a roof without floor mass above massless members: the cb and full rungs' M is
    # singular; the error named "small cb-5Hz (n=8).M" and its eigenvalues, no node, no fix
    column = "I_y = 2e-4\nI_z = 1e-4\nJ = 1.0\nvecxz = [1.0, 0.0, 0.0]\n"
    beam = "I_y = 100.0\nI_z = 100.0\nJ = 100.0\nvecxz = [0.0, 0.0, 1.0]\n"
    text = ('[frame3d]\nname = "small"\nbays_x = [6.0]\nbays_y = [5.0]\n'
            "storey_heights = [4.0, 3.5]\nn_v = 1\nn_h = 1\nfloor_mass = [20000.0, 0.0]\n"
            "zeta = [0.03]\n" + "".join(f"[frame3d.{g}]\nE = 2.1e11\nnu = 0.3\nA = 10.0\n"
                                        f"rho_A = 0.0\n{own}" for g, own in (
                ("columns", column), ("beams_x", beam), ("beams_y", beam))))  # fmt: skip
    (tmp_path / "small.toml").write_text(text)
    frame = load_frame3d(tmp_path / "small.toml")
    roof = int(np.argmax(frame.nodes[:, 2]))
    bare = frame.massless_nodes()
    assert len(bare) == 4 and np.all(frame.nodes[bare, 2] == 7.5) and roof in bare
    cfg = _cfg(structure={"frame3d": str(tmp_path / "small.toml"), "fidelity": fidelity})
    said = (rf"structure: frame3d: nodes\[{bare[0]}\] \(z = 7.5 m\) has no mass .* so the "
            rf"'{fidelity}' model's mass matrix is singular; expected a mass on every floor, or "
            r"fidelity 'rigid'$")  # fmt: skip
    with pytest.raises(SceneError, match=said):
        build_system(cfg, str(tmp_path / "s.toml"))
    assert load_frame3d("office-11-3d").massless_nodes().size == 0


def test_a_frame_in_mpa_is_noted_once_and_its_grid_tie_named(tmp_path):
    # the portal with E in MPa on the cb rung: its note came twice (the second naming a bare
    # "elements[0]", from the frame rebuilt with its base grid), and the stiffness span that
    # stops it named "elements[9]", a tie beam of that grid the file does not have
    text = (REPO / "frames" / "portal-3d.toml").read_text()
    (tmp_path / "p.toml").write_text(text.replace("E = 2.1e11", "E = 2.1e5"))
    cfg = _cfg(structure={"frame3d": str(tmp_path / "p.toml"), "fidelity": "cb"})
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        with pytest.raises(SceneError, match=r"structure: the base grid's tie beam of nodes "
                           r"\d+ and \d+: its EA/L = .* times the"):  # fmt: skip
            build_system(cfg, str(tmp_path / "s.toml"))
    notes = [str(w.message) for w in said if "is it in MPa or GPa" in str(w.message)]
    assert len(notes) == 1 and "frame3d.sections[0]: E = 2.1e+05 Pa" in notes[0]


def test_the_fixed_rung_needs_a_record(tmp_path):
    orbit = {"kind": "orbit", "orbit": "circular", "frequency": 0.5, "amplitude": 1.0,
             "n_periods": 2}  # fmt: skip
    cfg = _cfg(structure={"fidelity": "fixed"}, bearing=None)
    cfg["motion"] = orbit
    with pytest.raises(SceneError, match=r"motion\.kind"):
        run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip


@pytest.mark.parametrize(
    ("tables", "field"),
    [
        ({"structure": {"fidelity": "fixed"}, "bearing": None,
          "motion": {"kind": "orbit", "orbit": "circular", "frequency": 0.5, "amplitude": 1.0,
                     "n_periods": 2}},
         r"motion\.kind"),
        ({"structure": {"fidelity": "auto"},
          "motion": {"kind": "orbit", "orbit": "circular", "frequency": 0.5, "amplitude": 1.0,
                     "n_periods": 2}},
         r"structure\.fidelity"),
        ({"structure": {"fidelity": "cb", "eccentricity": [0.0, 0.7]}}, r"structure\.eccentricity"),
    ],
)  # fmt: skip
def test_a_refused_scene_says_nothing_of_a_build_first(tables, field, tmp_path, capsys):
    # refused before the run's header or its "building the cb model…" notice (they came first)
    cfg = _cfg(**{k: v for k, v in tables.items() if k != "motion"})
    if "motion" in tables:
        cfg["motion"] = tables["motion"]
    with pytest.raises(SceneError, match=field):
        run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                  quiet=False)  # fmt: skip
    assert capsys.readouterr().err == ""


PORTAL = {
    "structure": {"frame3d": "portal-3d", "eccentricity": [0.0, 0.0], "f_max": 40.0},
    "motion": {"pga": 1.0, "t_end": 2.0},
    "solver": {"law": "arctan", "rtol": 1e-8, "atol": 1e-10},
}


def test_cb_and_full_scenes_run_the_portal(tmp_path):
    # the cb rung at a cut-off above every portal mode is the full rung (the same model in
    # another basis): equal peaks to the integrators' global error, bounded by the step count
    # times the local tolerance rtol; every output written
    out = {}
    for fid in ("cb", "full"):
        cfg = _cfg(**{k: dict(v) for k, v in PORTAL.items()})
        cfg["structure"].update(fidelity=fid, f_max=1e6, min_mass=0.0)  # cb: every mode
        cfg["solver"]["path"] = "dense"  # full: the same model on Radau IIA at rtol
        s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                      quiet=True)  # fmt: skip
        assert s["fidelity"] == fid and s["n_isolators"] == 4 and s["uplift"] is None
        assert s["method"] == "radau" and s["law"] == "arctan"  # the dense loop run
        with np.load(tmp_path / "building3d.npz") as z:
            assert z["u"].shape == (z["t"].size, 4, 2)
            assert z["drift_corner"].shape[:3] == (1, 4, 2)
        with np.load(tmp_path / "building3d-shape.npz") as z:  # the deformed shape's field
            assert z["u"].shape == (48,) and np.abs(z["u"]).max() > 0
        text = format_summary(s)
        assert "peak drift corner x" in text and "peak base shear |V|" in text
        out[fid] = s
    bound = max(o["n_steps"] for o in out.values()) * PORTAL["solver"]["rtol"]
    assert bound < 1e-2
    for key in ("peak_resultant_displacement_m", "peak_drift_cm_x", "peak_base_shear_x_N"):
        assert out["cb"][key] == pytest.approx(out["full"][key], rel=bound)


def test_auto_scene_advises_and_runs_a_rung(tmp_path):
    cfg = _cfg(**{k: dict(v) for k, v in PORTAL.items()})
    cfg["structure"]["fidelity"] = "auto"
    s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip
    assert s["fidelity"] in ("fixed", "rigid", "cb")
    assert s["advice"]["fidelity"] == s["fidelity"] and s["advice"]["decision"]


def test_a_cb_model_without_elastic_modes_is_noted_and_the_auto_probe_keeps_one(tmp_path):
    # Below the portal's first fixed-interface mode the cb model is the rigid deck again: its
    # drifts are round-off (a ratio of them is no amplification) and, as the advisor's probe,
    # it always agreed with the rigid deck, which was then chosen for a flexible building.
    cfg = _cfg(**{k: dict(v) for k, v in PORTAL.items()})
    cfg["structure"].update(fidelity="cb", f_max=0.01)
    s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip
    assert any("keeps no fixed-interface mode below f_max = 0.01 Hz" in n for n in s["notes"])
    assert s["corner_amplification_x"] is None and s["corner_amplification_y"] is None
    cfg["structure"]["fidelity"] = "auto"
    s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip
    probe = s["advice"]["cb_probe"]
    assert probe["n_modes"] >= 1 and probe["f_max"] > 0.01


@pytest.mark.parametrize(
    ("fid", "path", "tables", "noted"),
    [
        ("cb", None, {"structure": {"n_modes": 12, "f_max": 8.0}}, ["structure.n_modes"]),
        (
            "rigid",
            None,
            {"structure": {"f_max": 8.0, "base": "pinned"}, "solver": {"dt": 0.01}},
            ["structure.f_max", "structure.base", "solver.dt"],
        ),
        ("full", "sparse", {"solver": {"rtol": 1e-4, "dt": 0.002}}, ["solver.rtol"]),
        (
            "full",
            "dense",
            {"solver": {"dt": 0.002, "rtol": 1e-4}, "structure": {"damping": "modal"}},
            ["structure.damping", "solver.dt"],
        ),
        (
            "fixed",
            None,
            {"solver": {"law": "switch", "dt": 0.01}, "structure": {"n_modes": 6}},
            ["[bearing]", "[solver]"],
        ),
    ],
)
def test_keys_a_rung_does_not_read_are_noted(fid, path, tables, noted):
    # each rung reads its own keys (the scene reference's meanings); any other given key is
    # named, so that a value that changes nothing is never taken silently
    from nsdyn.models.isolated.building3d_scene import unused_keys

    cfg = _cfg(**tables)
    cfg["structure"]["fidelity"] = fid
    assert sorted(k for k, _ in unused_keys(cfg, fid, path)) == sorted(noted)


def test_a_run_says_which_keys_it_did_not_read(tmp_path, capsys):
    cfg = _cfg(structure={"f_max": 8.0}, motion={"t_end": 0.2})
    s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
              quiet=False)  # fmt: skip
    err = capsys.readouterr().err
    assert "note: structure.f_max not used: the cb rung's cut-off" in err
    assert "structure.f_max not used: the cb rung's cut-off" in s["notes"]  # and --json's


def test_the_switch_law_holds_every_stuck_isolator_of_a_base_within_its_disc(tmp_path):
    # Coulomb: |F_i| <= mu_s N_i at every instant, stuck or slipping. On the portal's rigid
    # base several isolators stick at once; when one breaks away it moves its load onto the
    # others, and the slip-starts aligned with their slip points' accelerations move more:
    # the settling checks the discs again after both. The disc carries the switch law's slack
    # STICK_RTOL (1e-9; its stick test and switching function alike), events are located to
    # 1e-11 s, and |F| / mu N in slip is 1 to round-off: 1e-8 bounds all three. (The
    # stuck isolators were left at 185 x their discs and the portal lifted off at 0.55 s.)
    from nsdyn.models.isolated import _kplanerun as kr

    cfg = _cfg(structure={"frame3d": "portal-3d", "fidelity": "cb", "eccentricity": None},
               motion={"pga": 2.0, "t_end": 1.0, "vertical": False},
               solver={"law": "switch", "rtol": 1e-6, "atol": 1e-9, "dt_out": 0.01})  # fmt: skip
    cfg["structure"].pop("eccentricity")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # (no friction-limit warning, no uplift)
        s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                      quiet=True)  # fmt: skip
    assert s["uplift"] is None and s["n_events"] > 0
    with np.load(tmp_path / "building3d.npz") as z:
        F = np.hypot(z["friction"][..., 0], z["friction"][..., 1])
        ratio = F / (0.05 * z["N"])
    assert ratio.max() <= 1.0 + 10 * kr.STICK_RTOL
    assert np.mean(ratio > 1.0 - 1e-6) > 0.1  # (the discs are reached: slip episodes)


def test_a_friction_force_beyond_its_stick_disc_is_flagged():
    # Coulomb: an isolator's friction never exceeds mu_s k_p N. The switch-law runs of the
    # pair rungs check their outputs against it: 1.5 mu_s N is flagged with its factor, the
    # disc's rim itself is not, nor an isolator near uplift (N below a tenth of the mean)
    from types import SimpleNamespace

    from nsdyn.models.isolated.bearings import Bearing, Friction
    from nsdyn.models.isolated.building3d_pairs_run import check_friction_limit

    mu, n = 0.05, 1.0e5
    system = SimpleNamespace(bearings=[Bearing(Friction(mu), radius=2.0)] * 2)
    t = np.array([0.0, 0.1, 0.2])
    N = np.full((3, 2), n)
    F = np.zeros((3, 2, 2))
    F[1, 0] = (mu * n, 0.0)  # on the rim
    res = SimpleNamespace(t=t, N=N, friction=F)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert check_friction_limit(system, res) == pytest.approx(1.0, rel=1e-12)
        N[2, 1], F[2, 1] = 0.05 * n, (0.0, mu * n)  # 20x its vanishing limit, near uplift
        assert check_friction_limit(system, res) == pytest.approx(1.0, rel=1e-12)
    F[2, 0] = (0.0, 1.5 * mu * n)
    with pytest.warns(RuntimeWarning, match=r"isolator 0's friction reached 1.5 x its limit "
                                            r"mu_s N at t = 0.2 s"):  # fmt: skip
        assert check_friction_limit(system, res) == pytest.approx(1.5, rel=1e-12)


def test_a_frame_whose_floor_has_no_weight_is_noted(tmp_path):
    # the portal with its slab's mass in plan only: gravity acts on the members alone,
    # m_z = Σ ρ A L (4 columns of 4 m, 22 m of beams), against m = m_z + 24 t in plan; the
    # bundled portal carries the slab's weight on its column heads and is not noted
    from nsdyn.models.isolated.building3d import deck_constants
    from nsdyn.structure import load_frame3d as load

    text = (REPO / "frames" / "portal-3d.toml").read_text()
    start = text.index("node_mass = [")
    end = text.index("\n]\n", start) + 3
    light = tmp_path / "light-portal.toml"
    light.write_text(text[:start] + text[end:])
    k = deck_constants(load(light))
    m_z = 7850.0 * (0.0149 * 4 * 4.0 + 0.00845 * (2 * 6.0 + 2 * 5.0))
    assert k["m_z"] == pytest.approx(m_z, rel=1e-12)
    assert k["m"] == pytest.approx(m_z + 24000.0, rel=1e-12)
    assert deck_constants(load("portal-3d"))["m_z"] == pytest.approx(k["m"], rel=1e-12)
    notes = {}
    for name, frame in (("light", str(light)), ("bundled", "portal-3d")):
        cfg = _cfg(structure={"frame3d": frame, "eccentricity": [0.0, 0.0]}, motion={"t_end": 0.2})
        s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                      quiet=True)  # fmt: skip
        notes[name] = [n for n in s["notes"] if "vertical mass" in n]
    assert notes["bundled"] == []
    assert len(notes["light"]) == 1 and f"{100 * m_z / k['m']:.3g} %" in notes["light"][0]
    assert "frame3d.node_mass" in notes["light"][0]


@pytest.mark.parametrize(
    ("structure", "n_iso"), [({}, 12), ({"frame3d": "portal-3d", "fidelity": "full"}, 4)]
)
def test_triple_pendulum_slips_are_in_the_histories_file(structure, n_iso, tmp_path):
    # On triple pendulums building3d.npz holds the elements' slips s1x … s4y (it held only
    # their sum u), on the rigid rung and on the flexible ones. The series closes as in the
    # deck's tables: with the elastic stage undamped (zeta_e = 0) u - Σ_k s_k = φ/κ_e, φ the
    # bearing force per unit normal force (nsdyn.models.isolated.tfp), to round-off of the
    # slips (1e-12 relative)
    from nsdyn.models.isolated.tfp import TripleBearing

    tfp = {"R1": 2.2, "R2": 0.3, "R3": 0.3, "R4": 2.2, "mu1": 0.06, "mu2": 0.02, "mu3": 0.02,
           "mu4": 0.10, "d1": 0.40, "d2": 0.06, "d3": 0.06, "d4": 0.40, "zeta_e": 0.0}  # fmt: skip
    cfg = _cfg(bearing={"type": "tfp", **tfp}, motion={"t_end": 2.0, "pga": 4.0},
               solver={"law": "arctan"}, structure=structure)  # fmt: skip
    del cfg["bearing"]["radius"], cfg["bearing"]["mu"]
    if structure:
        del cfg["structure"]["eccentricity"]
    run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False, quiet=True)
    k_e = TripleBearing(**tfp).k_elastic
    with np.load(tmp_path / "building3d.npz") as d:
        assert d["s1x"].shape == d["N"].shape == (d["t"].size, n_iso)
        F = d["friction"] + d["restoring"] + d["other"]
        for c, name in enumerate("xy"):
            s = sum(d[f"s{k}{name}"] for k in range(1, 5))
            assert np.abs(s).max() > 1e-3  # (the elements slide)
            u = d["u"][..., c]
            np.testing.assert_allclose(u - s, F[..., c] / d["N"] / k_e, rtol=0,
                                       atol=1e-12 * (1 + np.abs(u).max()))  # fmt: skip


def test_auto_with_unilateral_contact_takes_the_cb_rung(tmp_path):
    # lift-off and landing need the building's vertical: the rigid deck (vertically rigid)
    # refused the contact inside the advisor's probe, a traceback; the advice is the cb rung
    cfg = _cfg(**{k: dict(v) for k, v in PORTAL.items()})
    cfg["structure"]["fidelity"] = "auto"
    cfg["solver"]["contact"] = "unilateral"
    s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip
    assert s["fidelity"] == "cb" and "contact 'unilateral'" in s["advice"]["decision"]


def test_a_cb_model_without_the_torsion_mode_says_so(tmp_path):
    # the portal's fixed-interface modes below 5 Hz are x1 and y1 (0.97 of their effective
    # masses) and none of its torsion (above 5 Hz): its torsional moment read 2.3x the full
    # model's with flat sliders, unsaid. At 40 Hz every portal mode is kept: no note
    cfg = _cfg(**{k: dict(v) for k, v in PORTAL.items()})
    cfg["structure"].update(fidelity="cb", f_max=5.0)
    s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip
    said = [n for n in s["notes"] if "effective mass in its fixed-interface modes" in n]
    assert len(said) == 1 and "% of the torsion effective" in said[0]
    assert "of the x" not in said[0] and "of the y" not in said[0]
    cfg["structure"]["f_max"] = 40.0
    s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip
    assert not any("effective mass in its fixed-interface" in n for n in s["notes"])


def test_mass_on_the_base_is_no_mode_s_and_no_cause_for_the_note(tmp_path):
    # 8 t on each base node is on the interface, in no fixed-interface mode: measured against
    # the whole rigid mass the modes kept 0.45 of x with every mode kept, and the note said
    # to raise f_max, which cannot help. Against what all the modes carry, they keep it all
    from nsdyn.models.isolated.bearings import Bearing, Friction
    from nsdyn.models.isolated.building3d_cb import building_pairs, cb_notes

    text = (Path(__file__).resolve().parents[3] / "frames" / "portal-3d.toml").read_text()
    heavy = text.replace("  [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0],",
                         "  " + ", ".join(["[8000.0, 8000.0, 8000.0]"] * 4) + ",", 1)  # fmt: skip
    assert heavy != text
    (tmp_path / "heavy.toml").write_text(heavy)
    frame = load_frame3d(str(tmp_path / "heavy.toml"))
    s = building_pairs(frame, Bearing(Friction(0.05), radius=2.0), fidelity="cb",
                       f_max=1000.0, min_mass=None)  # fmt: skip
    assert s.info["n_modes"] == s.info["n_modes_below_f_max"]  # (every mode kept)
    assert cb_notes(s.info) == []
    low = building_pairs(frame, Bearing(Friction(0.05), radius=2.0), fidelity="cb", f_max=5.0)
    assert "% of the torsion effective mass" in cb_notes(low.info)[0]
