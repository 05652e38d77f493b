"""The library answers a newcomer's first steps: objects print in brief, the common mistakes
of the public API (a name where an object is wanted, a misspelt name, a negative PGA) raise
an error that says what was expected and how to make it."""

from __future__ import annotations

import dataclasses
import warnings
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

import nsdyn
from nsdyn._brief import WIDTH, brief, brief_repr

# ---- brief repr ------------------------------------------------------------------------------


def test_brief_shows_arrays_by_shape_and_short_values_as_themselves():
    assert brief(np.zeros((2001, 26))) == "<array (2001, 26) float64>"
    assert brief(np.array([1.0, 2.5])) == "[1. , 2.5]"
    assert brief(sp.eye(5, format="csr")) == "<sparse (5, 5) nnz=5>"
    assert brief(list(range(100))) == "<list of 100>"
    assert brief([1, 2]) == "[1, 2]" and brief(0.1 + 0.2) == "0.3" and brief(None) == "None"
    assert len(brief("x" * 500)) == WIDTH


@dataclasses.dataclass
class Small:
    a: int = 1


@dataclasses.dataclass(repr=False)
class Big:
    name: str = "b"
    x: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(1000))
    y: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros((3, 3)))
    __repr__ = brief_repr


def test_a_nested_dataclass_is_shown_whole_when_short_else_by_type_and_name():
    assert brief(Small()) == "Small(a=1)"
    assert brief(Big()) == "<Big 'b'>"
    assert repr(Big()) == "Big(name='b', x=<array (1000,) float64>, y=<array (3, 3) float64>)"


def test_a_frame_and_a_system_print_every_field_in_brief():
    frame = nsdyn.load_frame("office-11")
    system = nsdyn.build_system(frame, nsdyn.Isolation(mu=0.03), fidelity="cb")
    for obj in (frame, system):
        r = repr(obj)
        # every field named, each value within WIDTH + its name (the dataclass repr of the
        # system printed its 13x13 matrices and the 435x13 map T in full)
        names = [f.name for f in dataclasses.fields(obj) if f.repr]
        assert r.startswith(type(obj).__name__ + "(") and all(f"{n}=" in r for n in names)
        assert len(r) <= sum(len(n) + WIDTH + 3 for n in names) + 40
    assert "T=<array (435, 13) float64>" in repr(system)


def test_a_transient_result_prints_in_brief():
    system = nsdyn.build_system("office-11", nsdyn.Isolation(mu=0.03), fidelity="rigid")
    res = nsdyn.simulate(system, nsdyn.read_motion("synthetic-wn-40s"), t_end=0.5, dt_out=0.01)
    r = repr(res)
    assert r.startswith("TransientResult(system=<IsolatedSystem ")
    assert f"x=<array {res.x.shape} float64>" in r and "response=<Response>" in r
    assert len(r) < 1000  # the dataclass repr: tens of thousands of characters
    assert "x_iso=<array" in repr(res.response)


# ---- the public API's common mistakes --------------------------------------------------------


def test_build_system_takes_a_frame_name_or_path_as_load_frame_reads_it():
    by_name = nsdyn.build_system("office-11", fidelity="cb")
    by_path = nsdyn.build_system(Path(nsdyn.structure.frame_toml.FRAMES.find("office-11")))
    by_frame = nsdyn.build_system(nsdyn.load_frame("office-11"), fidelity="cb")
    for s in (by_name, by_path):
        assert np.array_equal(s.M, by_frame.M) and np.array_equal(s.K, by_frame.K)


def test_build_system_refuses_what_is_not_a_frame():
    with pytest.raises(TypeError, match=r"frame: expected a plane Frame .* got int"):
        nsdyn.build_system(11)


def test_with_isolation_takes_an_isolation_in_place_of_the_system_s_and_its_changes():
    # s.with_isolation(nsdyn.Isolation(...)) was a TypeError ("takes 1 positional argument")
    s = nsdyn.build_system("office-11", fidelity="rigid")
    iso = nsdyn.Isolation(mu=0.08, law="switch")
    assert s.with_isolation(iso).isolation == s.with_isolation(isolation=iso).isolation == iso
    assert s.with_isolation(iso, c=0.0).isolation == dataclasses.replace(iso, c=0.0)
    by_fields = s.with_isolation(mu=0.08, law="switch")
    assert by_fields.isolation == dataclasses.replace(s.isolation, mu=0.08, law="switch")
    with pytest.raises(TypeError, match=r"isolation: expected an Isolation, got dict"):
        s.with_isolation({"mu": 0.08})


@pytest.mark.parametrize("motion", ["synthetic-wn-40s", Path("rec.txt"), np.zeros(10)])
def test_simulate_says_how_to_make_a_motion_from_a_name_or_an_array(motion):
    system = nsdyn.build_system("office-11", fidelity="rigid")
    with pytest.raises(TypeError, match=r"^motion: expected a ground motion or a force") as e:
        nsdyn.simulate(system, motion, t_end=1.0)
    made = "read_motion(" if isinstance(motion, str | Path) else "GroundMotion(t0, dt, a_hor)"
    assert made in str(e.value)


@pytest.mark.parametrize("pga", [-1.0, float("nan"), float("inf"), 1.0e30])
def test_scaling_to_a_negative_non_finite_or_absurd_pga_is_refused(pga):
    # 1e30 m/s² ran and reported a slip of 7.7e26 m: the targets end at 100 g
    m = nsdyn.read_motion("synthetic-wn-40s")
    with pytest.raises(ValueError, match=r"target: expected a finite PGA from 0 to 1000 m/s²"):
        m.scaled_to_pga(pga)
    with pytest.warns(nsdyn.UnitWarning, match=r"a PGA above 30 m/s² \(3.1 g\), beyond "
                      r"recorded ground motions, is given: is it in gal"):  # fmt: skip
        assert m.scaled_to_pga(1000.0).pga == pytest.approx(1000.0, rel=1e-12)  # the bound taken
    with warnings.catch_warnings():  # (30 m/s², the largest plausible, in silence)
        warnings.simplefilter("error")
        m.scaled_to_pga(30.0)


def test_a_misspelt_public_name_suggests_the_closest():
    with pytest.raises(AttributeError, match=r"no attribute 'simulat'; did you mean 'simulate'"):
        nsdyn.simulat  # noqa: B018
    with pytest.raises(AttributeError, match=r"no attribute 'zzzz'$"):
        nsdyn.zzzz  # noqa: B018
    # the hint said once: the interpreter's traceback adds its own "Did you mean" to an
    # error that names the attribute (it printed "...; did you mean 'simulate'?. Did you
    # mean: ..."); the interpreter's own printing, so a process of its own
    import subprocess
    import sys

    err = subprocess.run([sys.executable, "-c", "import nsdyn; nsdyn.simulat"],
                         capture_output=True, text=True, timeout=120).stderr  # fmt: skip
    assert err.lower().count("did you mean") == 1, err


def test_a_subpackage_loads_on_first_use_after_import_nsdyn():
    # a fresh interpreter: in this one another test may have imported nsdyn.plot already
    import subprocess
    import sys

    probe = ("import sys, nsdyn; assert 'nsdyn.plot' not in sys.modules; "
             "print(nsdyn.plot.plot_transient.__module__, nsdyn.studies.__name__)")  # fmt: skip
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["nsdyn.plot.transient", "nsdyn.studies"]


# ---- inputs of the deck, orbit and record entry points -------------------------------------


def test_an_orbit_as_a_dict_is_a_harmonic_plane():
    """A dict is read as HarmonicPlane(**dict): the same defaults (φ_y = 90°), so the same
    run bit for bit, and the same checks; an unknown key is named, not ignored."""
    from nsdyn.ground.orbit import HarmonicPlane
    from nsdyn.models.isolated.bearings import Bearing, Friction
    from nsdyn.models.isolated.deck import sdof_plane, simulate_plane

    deck = sdof_plane(1000.0, Bearing(Friction(0.04, 0.07, rate=30.0), radius=2.2))
    a = simulate_plane(deck, {"f": 0.5, "ax": 1.0, "ay": 1.0}, t_end=2.0)
    b = simulate_plane(deck, HarmonicPlane(0.5, 1.0, 1.0), t_end=2.0)
    assert np.array_equal(a.q, b.q) and np.array_equal(a.qd, b.qd)
    with pytest.raises(ValueError, match="'a_x': no such field; did you mean 'ax'"):
        simulate_plane(deck, {"f": 0.5, "a_x": 1.0}, t_end=2.0)
    with pytest.raises(ValueError, match="ax: expected an amplitude >= 0"):
        simulate_plane(deck, {"f": 0.5, "ax": -1.0}, t_end=2.0)
    with pytest.raises(ValueError, match="a harmonic orbit has no natural end"):
        simulate_plane(deck, HarmonicPlane(0.5, 1.0))
    assert sdof_plane(np.float32(1000.0), deck.bearings[0]).m == 1000.0  # numpy's numbers
    from nsdyn.periodic.plane import orbit_shape

    d = {"f": 0.5, "ax": 1.0, "ay": 1.0}  # a circle for the periodic solver too
    assert orbit_shape(d) == orbit_shape(HarmonicPlane(**d))


def test_records_and_starts_that_cannot_run_are_input():
    from nsdyn.models.isolated.scene import build_scene, load_scene
    from nsdyn.structure import fixed_base_modes_3d, load_frame3d

    system, motion = build_scene(load_scene())
    with pytest.raises(ValueError, match="a record of 1 sample spans no time"):
        nsdyn.simulate(system, nsdyn.GroundMotion(0.0, 0.01, np.ones(1)))
    with pytest.raises(ValueError, match="a record of 1 sample spans no time"):
        nsdyn.simulate(system, nsdyn.GroundMotion(0.0, 0.01, np.ones(1)), t_end=1.0)
    with pytest.raises(ValueError, match="x0: expected finite numbers"):
        nsdyn.simulate(system, motion, x0=np.full(2 * system.n, np.nan), t_end=1.0)
    full, _ = build_scene(load_scene(None, {"scene": {"fidelity": "full"}}))
    with pytest.raises(ValueError, match="x0: expected finite numbers"):  # the sparse path too
        nsdyn.simulate(full, motion, x0=np.full(2 * full.n, np.nan), t_end=1.0)
    for bad in (2.5, "12", True):
        with pytest.raises(ValueError, match="n_modes: expected an integer >= 1"):
            fixed_base_modes_3d(load_frame3d("portal-3d"), n_modes=bad)


# ---- mistakes a library user made (each was a deep traceback or taken without a word) ------


def test_the_isolation_frequency_takes_a_frames_name_and_refuses_a_system():
    # f_bis = sqrt(n_b K_lam / M_s) / 2 pi (seed 004 eq. 28): a name is loaded as
    # build_system loads it; a system was "'IsolatedSystem' object has no attribute"
    frame = nsdyn.load_frame("office-11")
    f = np.sqrt(len(frame.base_nodes) * 5e4 / frame.total_mass) / (2 * np.pi)
    assert nsdyn.base_isolation_frequency("office-11", 5e4) == pytest.approx(f, rel=1e-15)
    system = nsdyn.build_system("office-11", nsdyn.Isolation(), fidelity="rigid")
    with pytest.raises(TypeError, match=r"^frame: expected a Frame.*system\.frame"):
        nsdyn.base_isolation_frequency(system, 5e4)


@pytest.mark.parametrize("dofs", [[9999], "a", [], [1.5], [-1]])
def test_fixed_base_outputs_outside_the_frames_dofs_are_refused(dofs):
    from nsdyn.models.isolated.statespace import fixed_base_statespace

    fixed = nsdyn.build_system("office-11", fidelity="fixed")
    with pytest.raises(ValueError, match=r"^full_dofs: expected indices of the frame's dofs, "
                       r"0 to 434"):  # fmt: skip
        fixed_base_statespace(fixed, full_dofs=dofs)


def test_a_3d_building_refuses_a_plane_frame_and_a_misspelt_run_option():
    from nsdyn.models.isolated.bearings import Bearing, Friction
    from nsdyn.models.isolated.building3d_cb import building_pairs
    from nsdyn.models.isolated.building3d_response import run_building
    from nsdyn.structure import load_frame3d

    fps = Bearing(Friction(0.04), radius=2.2)
    with pytest.raises(TypeError, match=r"^frame: expected a 3D frame .*load_frame3d"):
        building_pairs(nsdyn.load_frame("office-11"), fps)
    system = building_pairs(load_frame3d("portal-3d"), fps)
    with pytest.raises(TypeError, match=r"^run_building\(\) .* 'rtoll'; did you mean 'rtol'"):
        run_building(system, {"f": 1.0, "ax": 0.0, "ay": 0.0}, rtoll=1e-3)


@pytest.mark.parametrize("e", ["abc", "0.5", 1.5, float("nan")])
def test_a_landings_restitution_is_a_number_from_0_to_1(e):
    # Newton's coefficient: 0 (plastic) to 1 (elastic); "abc" was float()'s own message, a
    # text "0.5" was taken where every other option's text is refused
    system = nsdyn.build_system("office-11", nsdyn.Isolation(), fidelity="rigid")
    motion = nsdyn.read_motion("synthetic-wn-40s").window(0.0, 0.1)
    with pytest.raises(ValueError, match=r"^restitution: expected Newton's coefficient"):
        nsdyn.simulate(system, motion, contact="unilateral", restitution=e)
