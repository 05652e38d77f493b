"""nsdyn's triple friction pendulum against OpenSees' TripleFrictionPendulum element.

Two independent implementations of the series model of a symmetric TFP (inner surfaces 2 = 3):
nsdyn's (:mod:`nsdyn.models.isolated.tfp`: four rigid-plastic pendulums R̄_k, μ_k, d̄_k in
series with one elastic spring κ_e = min μ / u_y, regularised by a Perzyna flow) and OpenSees'
(Dao et al. 2013, the element's source: three elastic-plastic pendulums with post-yield
radii 2 L1, L2 - L1, L3 - L1, friction models 1..3, circular gaps Gap2 = 2 (L1 Ubar3 / L3 +
Ubar1), Gap4 = Ubar2 (1 - L1/L2), Gap6 = Ubar3 (1 - L1/L3), each with elastic stiffness
E = 3 μ_inner / u_y and kinematic hardening H = E E_p / (E - E_p), integrated by Newton in
the element). The mapping (:func:`tfp_element_args`): L = (R2, R1, R4), Ubar = (d3, d1, d4),
friction (μ2, μ1, μ4), uy = u_y.

Tolerance (the two models' only difference, derived): both have the same elastic compliance
u_y / μ_inner (OpenSees: three springs 1/E in series) and the same play P_e[φ] (in units of φ)
per pendulum, but OpenSees' pendulum slides by P_e / H_e = P_e (R̄_e - 1/E) where nsdyn's
slides by P_e R̄_e, and its gap acts on the pendulum's whole deformation (φ/E inside it). So
at equal force history |u_OS - u_nsdyn| <= (1/E) Σ_e max(d̄_e / R̄_e, φ_max) =: T_model
(≈ 3.7 mm at φ = 0.26 for the bearing below, against slips of 0.8 m). nsdyn's regularisation
raises each element's friction by OVERSTRESS μ_min |ṡ_k| (tfp module): at most T_reg =
OVERSTRESS μ_min V Σ_k R̄_k in displacement at slip speed V. Newmark's step error at the
stick–slip transitions is at most V dt. The checks add the sampling step of the curves.

The data checks run without OpenSees; the runs skip when openseespy does not import.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from nsdyn.models.isolated import opensees as osx
from nsdyn.models.isolated import tfp
from nsdyn.models.isolated.opensees3d_isolated import (
    building_data,
    tfp_element_args,
    tfp_single,
    tfp_slip_mismatch,
    tfp_solver,
)
from nsdyn.models.isolated.tfp import TripleBearing
from nsdyn.models.scenefile import SceneError

G = 9.81
# Fenz & Constantinou 2008's typical bearing (inner R2 = R3 = 0.3 m, outer R1 = R4 = 2.2 m):
# regimes I..V start at u = 0, 0.024, 0.124, 0.748 (surface 1 at its rim), 0.848 m; inner
# rims at 0.92 m
TYPICAL = dict(R1=2.2, R2=0.3, R3=0.3, R4=2.2, mu1=0.06, mu2=0.02, mu3=0.02, mu4=0.10,
               d1=0.40, d2=0.06, d3=0.06, d4=0.40)  # fmt: skip
U_DR1 = 0.124 + 4.4 * (0.06 + 0.40 / 2.2 - 0.10)  # regime IV starts (Table 1: u_dr1)


def _has_opensees() -> bool:
    try:
        osx.load_opensees()
    except osx.OpenSeesUnavailable:
        return False
    return True


needs_opensees = pytest.mark.skipif(
    not _has_opensees(), reason='openseespy does not import (pip install "nsdyn[opensees]")'
)


def t_model(b: TripleBearing, phi_max: float) -> float:
    """T_model of the module text: (1/E) Σ_e max(d̄_e / R̄_e, φ_max), E = 3 μ_inner / u_y,
    over OpenSees' three pendulums (the inner pair as one: capacity d̄2 + d̄3 on 2 R2)."""
    el = b.elements()
    inner = (el[1, 2] + el[2, 2]) / (el[1, 0] + el[2, 0])
    caps = [inner, el[0, 2] / el[0, 0], el[3, 2] / el[3, 0]]
    E = 3.0 * b.mu2 / b.u_y
    return sum(max(c, phi_max) for c in caps) / E


def t_reg(b: TripleBearing, speed: float) -> float:
    """T_reg of the module text at slip speed ``speed`` [m/s]."""
    return tfp.OVERSTRESS * b.friction.mu_slow * speed * float(b.elements()[:, 0].sum())


# ---- without OpenSees ----------------------------------------------------------------------


def test_mapping_gives_the_elements_series_model():
    """OpenSees' three pendulums (the element's constructor: post-yield radii 2 L1, L2 - L1,
    L3 - L1; gaps 2 (L1 Ubar3/L3 + Ubar1), Ubar2 (1 - L1/L2), Ubar3 (1 - L1/L3); total
    capacity 2 Ubar1 + Ubar2 + Ubar3 + L1 (Ubar3/L3 - Ubar2/L2), the element's manual) are
    nsdyn's series elements (inner pair in series; 1; 4) and d1 + d2 + d3 + d4, for a bearing
    with R1 != R4 and d2 != d3 (equal inner capacities d2 + d1 R2/R1 = d3 + d4 R3/R4)."""
    p = dict(TYPICAL, R4=3.0, d4=0.40 * 3.0 / 2.2 + 0.02, d3=0.06 - 0.3 * 0.02 / 3.0)
    b = TripleBearing(**p)
    a = tfp_element_args(b)
    (L1, L2, L3), (U1, U2, U3) = a["L"], a["ubar"]
    el = b.elements()
    rel = 1e-12
    assert 2 * L1 == pytest.approx(el[1, 0] + el[2, 0], rel=rel)
    assert L2 - L1 == pytest.approx(el[0, 0], rel=rel)
    assert L3 - L1 == pytest.approx(el[3, 0], rel=rel)
    assert 2 * (L1 * U3 / L3 + U1) == pytest.approx(el[1, 2] + el[2, 2], rel=rel)
    assert U2 * (1 - L1 / L2) == pytest.approx(el[0, 2], rel=rel)
    assert U3 * (1 - L1 / L3) == pytest.approx(el[3, 2], rel=rel)
    total = 2 * U1 + U2 + U3 + L1 * (U3 / L3 - U2 / L2)
    assert total == pytest.approx(b.d_cap, rel=rel)
    assert [f[0] for f in a["frn"]] == [p["mu2"], p["mu1"], p["mu4"]]
    assert a["uy"] == b.u_y


def test_velocity_dependence_maps_to_the_surfaces_sliding_speeds():
    """OpenSees evaluates friction model 1 at 0.5 x the inner pendulum's speed (= nsdyn's
    inner element's speed w, the pair sliding equally), models 2 and 3 at L2/(L2 - L1) and
    L3/(L3 - L1) x their pendulum's speed (the element's v1Fact, v3Fact, v5Fact): the rates
    are nsdyn's a, a (R1 - R2)/R1 and a (R4 - R3)/R4, so exp(-rate v) = exp(-a w) on each."""
    b = TripleBearing(**TYPICAL, rate=20.0, mu_fast1=0.09, mu_fast2=0.04, mu_fast3=0.04,
                      mu_fast4=0.12)  # fmt: skip
    a = tfp_element_args(b)
    L1, L2, L3 = a["L"]
    w = 0.37  # any element slip speed [m/s]
    for (slow, fast, rate), factor, k in zip(a["frn"], (1.0, L2 / (L2 - L1), L3 / (L3 - L1)),
                                             (2, 1, 4), strict=True):  # fmt: skip
        assert (slow, fast) == (TYPICAL[f"mu{k}"], b.fast()[k - 1])
        assert math.exp(-rate * factor * w) == pytest.approx(math.exp(-20.0 * w), rel=1e-12)


@pytest.mark.parametrize(
    "change, field",
    [
        ({"R3": 0.25}, "R3"),
        ({"mu3": 0.015}, "mu3"),
        ({"mu_fast2": 0.04, "mu_fast3": 0.05, "rate": 10.0}, "mu_fast3"),
        ({"d3": 0.05}, "d3"),
        ({"zeta_e": 1.0}, "zeta_e"),  # its elastic stage is undamped: not dropped in silence
    ],
)
def test_a_bearing_the_element_cannot_represent_is_refused_naming_the_field(change, field):
    from nsdyn.ground.motion3 import GroundMotion3
    from nsdyn.structure import Section3D, regular_building_3d

    b = TripleBearing(where="bearing", **{"zeta_e": 0.0, **TYPICAL, **change})
    if field != "zeta_e":  # (the element's own arguments; its elastic stage is the script's)
        with pytest.raises(
            SceneError, match=rf"bearing\.{field}: OpenSees' TripleFrictionPendulum"
        ):
            tfp_element_args(b, "bearing")
    sec = Section3D(2.1e13, 8.1e12, 1e-2, 2e-4, 2e-4, 1e-4, 80.0)
    frame = regular_building_3d("portal", [6.0], [5.0], [3.0], sec, sec, sec, floor_mass=2e5,
                                zeta=0.02)  # fmt: skip
    a = np.zeros(11)
    with pytest.raises(SceneError, match=rf"<b>: bearing\.{field}:") as err:
        building_data(frame, b, GroundMotion3(0.0, 0.01, a, a, None, "r"), dt=0.01, source="<b>")
    assert "\n" not in str(err.value)


# ---- OpenSees: one bearing under a weight W ------------------------------------------------


def _nsdyn_drive(b: TripleBearing, u_of_t, t_out):
    """φ_x along a prescribed slip path u(t) = (u_of_t(t), 0): nsdyn's kernel of the series
    model (its internal slips integrated by scipy's Radau)."""
    from scipy.integrate import solve_ivp

    from nsdyn.models.isolated import _kplane as kp
    from nsdyn.models.isolated.bearings import B_IOFF

    row = b.row(1.0, G)[None, :].copy()
    row[0, B_IOFF] = 6
    y, sd = np.zeros(14), np.zeros((1, 8))

    def vel(t, h=1e-6):  # (the path's slip velocity by central differences)
        return (u_of_t(t + h) - u_of_t(t - h)) / (2 * h)

    def f(t, s):
        y[6:] = s
        kp.tfp_force(y, row, 0, u_of_t(t), 0.0, vel(t), 0.0, sd)
        return sd[0].copy()

    sol = solve_ivp(f, (t_out[0], t_out[-1]), np.zeros(8), method="Radau", t_eval=t_out,
                    rtol=1e-9, atol=1e-12, max_step=1.0)  # fmt: skip
    assert sol.success
    phi = np.empty(t_out.size)
    for k in range(t_out.size):
        y[6:] = sol.y[:, k]
        phi[k] = kp.tfp_force(y, row, 0, u_of_t(t_out[k]), 0.0, vel(t_out[k]), 0.0, sd)[0]
    return phi


@needs_opensees
@pytest.mark.filterwarnings("ignore:divide by zero:RuntimeWarning")
def test_quasi_static_loop_through_regimes_one_to_four():
    """A displacement path 0 -> +A -> -A -> +A (A = 0.80 m: past u_dr1 = 0.748 m, regime IV,
    below the inner rims) at V = 1 mm/s: on every branch, the slip at equal force φ = F/W of
    OpenSees' loop and nsdyn's differs by at most T_model + T_reg(V) + the loops' sampling
    (the largest step of u along the path and of nsdyn's u between samples of φ)."""
    b = TripleBearing(**TYPICAL, zeta_e=0.0)  # OpenSees' undamped stage
    A, V, W, du = 0.80, 1e-3, 1.0e4, 4e-4
    knots = np.array([0.0, A, 3 * A, 5 * A]) / V  # times of the path's corners [s]
    vals = [0.0, A, -A, A]

    def path(t):
        return float(np.interp(t, knots, vals))

    ops = tfp_single(b, W)
    # (held past the last corner: the steps' summed time ends a round-off beyond it)
    ops.timeSeries("Path", 2, "-time", *knots.tolist(), 1.1 * knots[-1], "-values", *vals, A)
    ops.pattern("Plain", 2, 2)
    ops.sp(2, 1, 1.0)
    tfp_solver(ops)
    # the element's first sliding step from rest must stay near u_y (a longer one lost its
    # internal equilibrium, unreported): here every step is 1.6 u_y
    ops.integrator("LoadControl", du / V)
    ops.analysis("Static")
    n = int(round(5 * A / du))
    t, u_os, phi_os = np.empty(n), np.empty(n), np.empty(n)
    for k in range(n):
        assert ops.analyze(1) == 0
        assert tfp_slip_mismatch(ops) <= 1e-2 * b.u_y
        t[k], u_os[k] = ops.getTime(), ops.nodeDisp(2, 1)
        phi_os[k] = ops.eleForce(1, 7) / W
    ops.wipe()
    np.testing.assert_allclose(u_os, [path(tt) for tt in t], atol=1e-9)
    t_ns = np.linspace(0.0, knots[-1], 16001)
    phi_ns = _nsdyn_drive(b, path, t_ns)
    u_ns = np.array([path(tt) for tt in t_ns])
    phi_max = float(np.abs(phi_os).max())
    assert phi_max > TYPICAL["mu1"] + TYPICAL["d1"] / TYPICAL["R1"]  # (regime IV reached)
    worst = 0.0
    for k0, k1 in zip(knots[:-1], knots[1:], strict=True):
        o = (t > k0) & (t <= k1)
        s = (t_ns >= k0) & (t_ns <= k1)
        sign = 1.0 if vals[int(np.searchsorted(knots, k1))] > path(k0) else -1.0
        fo, uo = sign * phi_os[o], u_os[o]
        fs, us = sign * phi_ns[s], u_ns[s]
        assert np.all(np.diff(fs) > -1e-9)  # (φ rises along a loading branch)
        inside = (fo >= fs[0]) & (fo <= fs[-1])
        gap = np.abs(uo[inside] - np.interp(fo[inside], fs, us))
        sampling = du + float(np.abs(np.diff(us)).max())
        worst = max(worst, float(gap.max()) - sampling)
    tol = t_model(b, phi_max) + t_reg(b, V)
    print(f"quasi-static loop: largest slip difference at equal force, less the sampling, "
          f"{worst * 1e3:.3f} mm; bound {tol * 1e3:.3f} mm")  # fmt: skip
    assert worst <= tol


@needs_opensees
def test_mass_on_a_tfp_under_an_elliptical_orbit():
    """A mass m on one TFP (N = m g) under a_x = 1.3 sin(ωt), a_y = 1.0 sin(ωt + 60°) m/s²,
    f = 0.35 Hz, 10 s: the orbit reaches regime IV (past u_dr1) and stays inside the inner
    rims. nsdyn: ``sdof_plane`` / ``simulate_plane`` (arctan law, Radau IIA). OpenSees: the
    same mass on TripleFrictionPendulum, Newmark average acceleration, dt = 1 ms, the ground
    samples at dt. The orbits as curves in the plane (Hausdorff distance) and the peak
    resultant displacements (1-Lipschitz in that distance) agree within T_model(φ_max) +
    T_reg(V_max) + V_max dt + the orbits' sampling step, V_max the peak slip speed."""
    from scipy.spatial import cKDTree

    from nsdyn.models.isolated.deck import sdof_plane, simulate_plane

    b = TripleBearing(**TYPICAL, zeta_e=0.0)  # OpenSees' undamped stage
    m, f, ax, ay, ph, t_end, dt = 1000.0, 0.35, 1.3, 1.0, 60.0, 10.0, 1e-3
    r = simulate_plane(sdof_plane(m, b, g=G), {"f": f, "ax": ax, "ay": ay, "phase_y_deg": ph},
                       law="arctan", t_end=t_end, dt_out=dt, rtol=1e-8,
                       atol=(1e-10, 1e-10))  # fmt: skip
    assert not r.summary()["tfp_surface_limits"] or all(
        c["surface"] in ("1", "4") for c in r.summary()["tfp_surface_limits"]
    )
    u_ns = r.u[:, 0]
    W = m * G
    ops = tfp_single(b, W, mass=m)
    n = int(round(t_end / dt))
    tt = np.arange(n + 1) * dt
    w = 2 * np.pi * f
    ops.timeSeries("Path", 2, "-dt", dt, "-values", *(ax * np.sin(w * tt)).tolist())
    ops.timeSeries(
        "Path", 3, "-dt", dt, "-values", *(ay * np.sin(w * tt + math.radians(ph))).tolist()
    )
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    ops.pattern("UniformExcitation", 3, 2, "-accel", 3)
    tfp_solver(ops)
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    u_os = np.zeros((n + 1, 2))
    phi_max = 0.0
    for k in range(n):
        assert ops.analyze(1, dt) == 0
        assert tfp_slip_mismatch(ops) <= 1e-2 * b.u_y
        u_os[k + 1] = ops.nodeDisp(2, 1), ops.nodeDisp(2, 2)
        phi_max = max(phi_max, math.hypot(ops.eleForce(1, 7), ops.eleForce(1, 8)) / W)
    ops.wipe()
    peak_ns = float(np.hypot(*u_ns.T).max())
    peak_os = float(np.hypot(*u_os.T).max())
    assert peak_ns > U_DR1 and peak_os > U_DR1  # (regime IV reached)
    d1, _ = cKDTree(u_ns).query(u_os)
    d2, _ = cKDTree(u_os).query(u_ns)
    hausdorff = max(float(d1.max()), float(d2.max()))
    v_max = float(np.hypot(*r.v[:, 0].T).max())
    sampling = max(float(np.hypot(*np.diff(c, axis=0).T).max()) for c in (u_ns, u_os))
    tol = t_model(b, phi_max) + t_reg(b, v_max) + v_max * dt + sampling
    print(f"orbit: peak nsdyn {peak_ns:.4f} m, OpenSees {peak_os:.4f} m; orbits' Hausdorff "
          f"distance {hausdorff * 1e3:.2f} mm, bound {tol * 1e3:.2f} mm")  # fmt: skip
    assert hausdorff <= tol
    assert abs(peak_os - peak_ns) <= tol


@needs_opensees
def test_portal_on_four_tfps_exported_against_the_rigid_deck(tmp_path):
    """The 3D export with TFP bearings runs: a stiff portal (E x 100) on four TYPICAL triple
    pendulums under a circular orbit 1.5 m/s² at 0.5 Hz (switched on over 1 s), 8 s, the same
    sampled record on both sides. nsdyn: the portal's rigid deck (arctan law). OpenSees: the
    exported script (TripleFrictionPendulum under each foot, Newmark dt = 5 ms). The peak
    resultant isolator displacements agree within T_model(φ_max) + T_reg(V_max) + V_max dt
    (module text) + 0.5 % of the peak: the superstructure's flexibility and its normal forces
    against the rigid plate's, as for the flat sliders (test_opensees3d_bearings)."""
    from nsdyn.ground.motion3 import GroundMotion3
    from nsdyn.models.isolated.building3d import building_deck
    from nsdyn.models.isolated.deck import simulate_plane
    from nsdyn.models.isolated.opensees3d_isolated import export_building_opensees
    from nsdyn.structure import Section3D, regular_building_3d

    col = Section3D(2.1e13, 8.1e12, 1e-2, 2e-4, 2e-4, 1e-4, 80.0)
    beam = Section3D(2.1e13, 8.1e12, 1e-2, 3e-4, 1e-4, 1e-4, 80.0)
    frame = regular_building_3d("portal", [6.0], [5.0], [3.0], col, beam, beam,
                                floor_mass=2e5, zeta=0.02)  # fmt: skip
    b = TripleBearing(**TYPICAL, zeta_e=0.0)  # OpenSees' undamped stage
    dt = 0.005
    t = np.arange(int(round(8.0 / dt)) + 1) * dt
    ramp = np.minimum(t / 1.0, 1.0)
    w = 2 * np.pi * 0.5
    motion = GroundMotion3(0.0, dt, 1.5 * ramp * np.sin(w * t), -1.5 * ramp * np.cos(w * t),
                           None, "circular")  # fmt: skip
    path = tmp_path / "tfp.py"
    text = export_building_opensees(frame, path, bearings=b, motion=motion, dt=dt)
    assert text.count('"type":"tfp"') == 4
    r = osx.load_script(path).run()
    res = simulate_plane(building_deck(frame, b), motion, law="arctan", rtol=1e-8,
                         atol=(1e-10, 1e-10))  # fmt: skip
    u_ns = res.summary()["peak_resultant_displacement_m"]
    F = res.friction + res.restoring + res.other
    phi_max = float((np.hypot(F[..., 0], F[..., 1]) / res.N).max())
    v_max = float(np.hypot(res.qd[:, 0], res.qd[:, 1]).max())
    tol = t_model(b, phi_max) + t_reg(b, v_max) + v_max * dt + 5e-3 * u_ns
    print(f"portal on four TFPs: peak nsdyn (rigid deck) {u_ns:.4f} m, OpenSees "
          f"{r['peak_resultant_displacement_m']:.4f} m, bound {tol * 1e3:.2f} mm")  # fmt: skip
    assert r["peak_resultant_displacement_m"] > 0.3  # (regime III: far past the inner pair)
    assert abs(r["peak_resultant_displacement_m"] - u_ns) <= tol
    assert r["min_normal_force_N"] > 0  # (no uplift)
