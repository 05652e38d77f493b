"""The 3D building on its bearings in OpenSees: the exported script against closed forms and nsdyn.

- a stiff portal on four flat sliders under a harmonic x ground acceleration below the
  friction threshold sticks: every bearing's displacement stays within the elastic branch
  of OpenSees' bearing, |u| <= mu N_max / k_init (in stick the bearing force is below
  mu N, the branch's stiffness is k_init); the same portal above the threshold slides
  (the control: a slip two orders above that bound);
- one column on one single friction pendulum, released by a ground pulse, oscillates with
  the pendulum period 2 pi sqrt(R/g) (with Coulomb friction the motion between stops is
  harmonic about a shifted centre, so successive maxima are T apart), for two masses;
- a very stiff portal on four friction pendulums under a circular orbit: OpenSees' peak
  resultant isolator displacement equals nsdyn's rigid deck (switch law) within a bound
  argued from k_init and the superstructure's flexibility (below).

The data and text checks run without OpenSees; the runs skip when openseespy does not import.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from nsdyn.ground.excitation import G_EARTH
from nsdyn.ground.motion3 import GroundMotion3
from nsdyn.models.isolated import opensees as osx
from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.opensees3d_isolated import (
    building_data,
    export_building_opensees,
    script_text_building,
)
from nsdyn.models.scenefile import SceneError
from nsdyn.structure import Frame3D, Section3D, regular_building_3d


def _has_opensees() -> bool:
    try:
        osx.load_opensees()
    except osx.OpenSeesUnavailable:
        return False
    return True


needs_opensees = pytest.mark.skipif(
    not _has_opensees(), reason='openseespy does not import (pip install "nsdyn[opensees]")'
)

STIFF = 1e2  # the portal's E and G times this: a practically rigid superstructure
DT = 0.005


def portal(stiff: float = STIFF, floor_mass: float = 2e5) -> Frame3D:
    """One bay each way (6 m x 5 m), one 3 m storey, a diaphragm carrying the floor mass."""
    col = Section3D(2.1e11 * stiff, 8.1e10 * stiff, 1e-2, 2e-4, 2e-4, 1e-4, 80.0)
    beam = Section3D(2.1e11 * stiff, 8.1e10 * stiff, 1e-2, 3e-4, 1e-4, 1e-4, 80.0)
    return regular_building_3d("portal", [6.0], [5.0], [3.0], col, beam, beam,
                               floor_mass=floor_mass, zeta=0.02)  # fmt: skip


def column(mass: float) -> Frame3D:
    """A mass on one bearing: ``mass`` at the base node of a short stiff stub (a single
    column on a bearing that carries no moment would swing about its foot)."""
    one = np.ones(1)
    return Frame3D(
        "column", np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 2.0]]), np.array([[0, 1]]),
        np.array([[1.0, 0.0, 0.0]]), 2.1e14 * one, 8.1e13 * one, 1e-2 * one, 1e-3 * one,
        1e-3 * one, 1e-3 * one, 1.0 * one, 1.0 * one,
        np.array([[mass, mass, mass], [0.0, 0.0, 0.0]]), np.array([0]), np.array([0.02]),
    )  # fmt: skip


def record(ax, ay=None, name="test") -> GroundMotion3:
    ax = np.asarray(ax, float)
    return GroundMotion3(0.0, DT, ax, np.zeros_like(ax) if ay is None else ay, None, name)


def harmonic_x(amplitude: float, f: float, t_end: float) -> GroundMotion3:
    t = np.arange(int(round(t_end / DT)) + 1) * DT
    return record(amplitude * np.sin(2 * np.pi * f * t), name="harmonic")


def _run(frame, bearing, motion, tmp_path, name, out=None) -> tuple[dict, dict]:
    path = tmp_path / f"{name}.py"
    export_building_opensees(frame, path, bearings=bearing, motion=motion, dt=DT)
    module = osx.load_script(path)
    return module.DATA, module.run(out=out)


# ---- without OpenSees ----------------------------------------------------------------------


def test_data_maps_the_bearings_and_the_weight():
    """k_init = mu_slow N_0 / STICK_DISP per bearing; the gravity loads add up to the
    frame's weight (-g M r_z, every node and member mass); VelDependent's parameters are
    nsdyn's (mu_slow, mu_fast, rate) in that order; the normal forces are the rigid-plate
    ones (a symmetric portal: W / 4 each)."""
    frame = portal()
    b = Bearing(Friction(0.04, 0.07, rate=30.0), radius=2.0)
    d = building_data(frame, b, harmonic_x(1.0, 1.0, 1.0))
    W = frame.total_mass * G_EARTH
    assert sum(f[2] for f in d["gravity"]) == pytest.approx(-W, rel=1e-12)
    for row in d["bearings"]:
        assert row["N0"] == pytest.approx(W / 4, rel=1e-9)
        assert row["k_init"] == pytest.approx(0.04 * row["N0"] / osx.STICK_DISP, rel=1e-12)
        assert (row["type"], row["mu_slow"], row["mu_fast"], row["rate"]) == ("fps", 0.04, 0.07,
                                                                              30.0)  # fmt: skip
    text = script_text_building(d)
    assert '_friction(ops, 3 * i + 1, row["mu_slow"], row["mu_fast"], row["rate"])' in text
    assert 'ops.frictionModel("VelDependent", tag, slow, fast, rate)' in text
    compile(text, "model.py", "exec")


def test_bad_input_names_the_field(tmp_path):
    """An orbit instead of a record, a non-positive step and a missing bearing are one-line
    errors naming the field."""
    frame = portal()
    b = Bearing(Friction(0.05), radius=2.0)
    with pytest.raises(SceneError, match="motion"):
        building_data(frame, b, {"f": 1.0, "ax": 1.0})
    with pytest.raises(SceneError, match="solver.dt"):
        building_data(frame, b, harmonic_x(1.0, 1.0, 1.0), dt=-1.0)
    with pytest.raises(SceneError, match="bearing"):
        export_building_opensees(frame, motion=harmonic_x(1.0, 1.0, 1.0))
    with pytest.raises(SceneError, match="bearing"):
        building_data(frame, [b, b], harmonic_x(1.0, 1.0, 1.0))
    # pressure-dependent friction: the exported bearings have none, so it is refused rather
    # than dropped (the script would run another model)
    bp = Bearing(Friction(0.05), radius=2.0, area=0.05, p_ref=2.0e7)
    with pytest.raises(SceneError, match=r"bearing\.area: pressure-dependent friction"):
        building_data(frame, bp, harmonic_x(1.0, 1.0, 1.0))


def test_scene_export_from_the_command_line(tmp_path):
    """``nsdyn export opensees`` on a building3d scene writes the building on its bearings
    (the scene's rung rigid) and, with --fixed-base, the clamped frame."""
    scene = tmp_path / "b.toml"
    scene.write_text(
        '[scene]\nkind = "building3d"\n[structure]\nframe3d = "office-11-3d"\n'
        '[bearing]\ntype = "flat"\nmu = 0.05\nk_lam = 1e6\nc = 1e4\n'
        '[motion]\nkind = "record3"\nrecord = "synthetic-wn-40s"\nt_end = 0.5\n'
    )
    # without -o each goes to the current folder under a name of its own (the clamped one
    # replaced the isolated one's script before)
    for extra, fixed in (([], False), (["--fixed-base"], True)):
        p = subprocess.run(
            [
                sys.executable,
                "-c",
                "import sys; from nsdyn.cli import main; sys.exit(main())",
                "export",
                "opensees",
                str(scene),
                "--json",
                *extra,
            ],
            capture_output=True,
            text=True,
            check=False,
            cwd=tmp_path,
        )
        assert p.returncode == 0, p.stderr
        info = json.loads(p.stdout)
        assert info["script"] == ("b_opensees_fixed.py" if fixed else "b_opensees.py")
        assert info["fixed_base"] is fixed and info["n_elements"] == 1364
        assert info["bearings"] == ([] if fixed else ["flat"])
        assert info["duration_s"] == pytest.approx(0.5)
    assert (tmp_path / "b_opensees.py").is_file() and (tmp_path / "b_opensees_fixed.py").is_file()
    # the script's own arguments: an end within the first step ran no step and printed zero
    # peaks and "Infinity" (not JSON); an --out that is a file, or a path under one, was
    # os.makedirs' traceback
    out = "--out: expected a directory"
    for args, said in ((["--t-end", "0.001"], "--t-end: expected an end at least one step"),
                       (["--out", "b_opensees.py"], out),
                       (["--out", "b_opensees.py/sub"], out)):  # fmt: skip
        p = subprocess.run([sys.executable, "b_opensees.py", *args], capture_output=True,
                           text=True, check=False, cwd=tmp_path)  # fmt: skip
        assert p.returncode == 2 and said in p.stderr and p.stdout == ""


# ---- with OpenSees -------------------------------------------------------------------------


@needs_opensees
def test_below_the_friction_threshold_the_portal_sticks(tmp_path):
    """Flat sliders (mu = 0.1) under a_x = 0.3 mu g sin(2 pi t): the stiff portal's inertia
    force is below mu W, so every bearing stays on its elastic branch: |u_i| <= mu N_max /
    k_init,i (+ the Newton tolerance 1e-8 m). Control: at 2 mu g the bearings slide, their
    slip far above that bound."""
    frame = portal()
    mu = 0.1
    b = Bearing(Friction(mu), k_lam=0.0)
    d, r = _run(frame, b, harmonic_x(0.3 * mu * G_EARTH, 1.0, 2.0), tmp_path, "stick")
    bound = mu * r["max_normal_force_N"] / min(row["k_init"] for row in d["bearings"])
    assert max(r["peak_resultant_displacement_per_isolator_m"]) <= bound + 1e-8
    assert r["min_normal_force_N"] > 0
    _, r2 = _run(frame, b, harmonic_x(2.0 * mu * G_EARTH, 1.0, 2.0), tmp_path, "slide")
    assert r2["peak_resultant_displacement_m"] > 100 * bound


def _maxima_times(t, u, w):
    """Times of the positive maxima of u over +- w samples (parabola through the sample and
    its neighbours)."""
    out = []
    for k in range(w, len(u) - w):
        if u[k] > 0 and u[k] == u[k - w : k + w + 1].max():
            den = u[k - 1] - 2 * u[k] + u[k + 1]
            out.append(t[k] + 0.5 * (t[1] - t[0]) * (u[k - 1] - u[k + 1]) / den)
    return np.array(out)


@needs_opensees
@pytest.mark.parametrize("mass", [2e4, 2e5])
def test_friction_pendulum_period_is_the_pendulum_s(tmp_path, mass):
    """A mass on one singleFPBearing (R = 1 m, mu = 2e-5), released by a 0.1 s ground
    pulse to a small amplitude A ~ 1 cm: successive maxima of its displacement are
    T = 2 pi sqrt(R/g) apart whatever the mass (N = m g, restoring N u / R). Bound
    mu R / A + (A / R)^2 + 1e-4: with Coulomb's law the motion between stops is exactly
    harmonic, and OpenSees' elastic stick branch flips the friction force over
    2 mu N / k_init instead of at once, a force error of at most mu N against the
    restoring N A / R; OpenSees' pendulum stiffens with the amplitude (its shear force is
    N u / R (1 + (u/R)^2) to leading order: measured +0.9 % at u/R = 0.095, the period
    0.34 % short); Newmark's period error (omega dt)^2 / 12 = 2e-5 and the peak times
    located to O(dt^3) by the parabola are in the 1e-4."""
    R, mu = 1.0, 2e-5
    b = Bearing(Friction(mu), radius=R)
    a = np.zeros(int(round(8.0 / DT)) + 1)
    a[1:21] = 0.3
    _, r = _run(column(mass), b, record(a), tmp_path, f"fp{int(mass)}", out=tmp_path / "rec")
    hist = np.loadtxt(tmp_path / "rec" / "isolators_disp.out")
    t, ux = hist[:, 0], hist[:, 1]
    T = 2 * np.pi * math.sqrt(R / G_EARTH)
    tm = _maxima_times(t, ux, int(T / 4 / DT))
    assert len(tm) >= 3
    amp = np.interp(tm[:4], t, ux).min()
    np.testing.assert_allclose(np.diff(tm[:4]), T, rtol=mu * R / amp + (amp / R) ** 2 + 1e-4)
    assert amp > 100 * mu * R  # sliding, not stuck


@needs_opensees
def test_circular_orbit_opensees_against_the_rigid_deck(tmp_path):
    """Four flat sliders with rubber and damper (mu = mu_s = 0.05, K_lam for a 2.5 s period,
    c 5 % of critical) under a circular orbit 1.5 m/s² at 0.6 Hz (switched on over 1 s) for
    6 s, the same sampled record on both sides. nsdyn: the rigid deck of the portal (switch
    law: exact stick). OpenSees: the portal (E x 100, f_1 about 30 Hz) on flatSliderBearing
    with zeroLength rubber and damper. Bound: 2 mu N_max / k_init (the elastic branch adds at
    most mu N / k_init to a slip and delays the break-away by as much) + 0.5 % of the peak:
    Newmark's phase error over the run (3.6 cycles x 2 pi (omega dt)^2 / 24 < 1e-4), the
    superstructure's flexibility (f_iso / f_1)^2 < 2e-4 and the frame's normal forces
    against the rigid plate's. (A friction pendulum is not used here: OpenSees'
    singleFPBearing departs from the small-angle law N u / R by O((u/R)^2).)"""
    from nsdyn.models.isolated.building3d import building_deck
    from nsdyn.models.isolated.deck import simulate_plane

    frame = portal()
    w_share = frame.total_mass / 4
    k_lam = w_share * (2 * np.pi / 2.5) ** 2
    b = Bearing(Friction(0.05, mu_static=0.05), k_lam=k_lam,
                c=0.05 * 2 * math.sqrt(k_lam * w_share))  # fmt: skip
    t = np.arange(int(round(6.0 / DT)) + 1) * DT
    w = 2 * np.pi * 0.6
    ramp = np.minimum(t / 1.0, 1.0)  # a circular orbit switched on over 1 s
    motion = record(1.5 * ramp * np.sin(w * t), -1.5 * ramp * np.cos(w * t), name="circular")
    d, r = _run(frame, b, motion, tmp_path, "orbit")
    deck = building_deck(frame, b)
    res = simulate_plane(deck, motion, law="switch", rtol=1e-8, atol=(1e-10, 1e-10))
    u_ns = res.summary()["peak_resultant_displacement_m"]
    k0 = min(row["k_init"] for row in d["bearings"])
    bound = 2 * 0.05 * r["max_normal_force_N"] / k0 + 5e-3 * u_ns
    assert abs(r["peak_resultant_displacement_m"] - u_ns) <= bound
    assert u_ns > 20 * bound  # a real slip, far above the bound


def test_triple_pendulum_the_element_cannot_represent_is_refused():
    """OpenSees' TripleFrictionPendulum has one inner pendulum: a triple friction pendulum
    with R2 != R3 is a one-line error naming the field (the mapping of symmetric ones:
    test_tfp_opensees)."""
    from nsdyn.models.isolated.bearings import bearing_from_config

    tfp = bearing_from_config(
        {"type": "tfp", "R1": 2.0, "R2": 0.5, "R3": 0.4, "R4": 2.0, "mu1": 0.04, "mu2": 0.02,
         "mu3": 0.02, "mu4": 0.06, "d1": 0.2, "d2": 0.05, "d3": 0.05, "d4": 0.2, "zeta_e": 0.0},
        "bearing",
    )  # fmt: skip
    with pytest.raises(SceneError, match=r"bearing\.R3: OpenSees' TripleFrictionPendulum"):
        building_data(portal(), tfp, harmonic_x(1.0, 1.0, 1.0))
