"""Triple friction pendulums in systems from matrices (PairSystem, simulate_pairs, Radau IIA).

Independent references: the deck's kernels (:mod:`nsdyn.models.isolated._kplane`, its own
Radau loop; the normal force from the rigid-plate balance, not from a contact multiplier) run
the same series model, so a single mass and a rigid deck on TFPs must agree to the two
integrators' global error; and the published piecewise-linear backbone (Fenz & Constantinou
2008, Earthquake Spectra 24(4), Table 1), whose transition displacements

    u*  = (R2 + R3)(μ1 − μ2)                  (regime I → II, F = μ1 W)
    u** = u* + (R1 + R3)(μ4 − μ1)             (regime II → III, F = μ4 W)

the quasi-static loading of a mass through regimes I–III must pass (the expressions of
``tests/models/isolated/test_tfp.py``), up to the model's yield spring and overstress.
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from nsdyn.models.isolated import tfp
from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.deck import rigid_deck, sdof_plane, simulate_plane
from nsdyn.models.isolated.pairs import PairSystem, from_deck, simulate_pairs
from nsdyn.models.isolated.tfp import TripleBearing

G = 9.81
M = 1000.0
# the typical bearing of the TFP tests: inner slider R2 = R3 = 0.3 m, outer R1 = R4 = 2.2 m
TYPICAL = dict(R1=2.2, R2=0.3, R3=0.3, R4=2.2, mu1=0.06, mu2=0.02, mu3=0.02, mu4=0.10,
               d1=0.40, d2=0.06, d3=0.06, d4=0.40)  # fmt: skip


def single_mass(bearing, m=M):
    """A mass on one isolator: q = (x, y, z), slip rows x and y, the contact row on z."""
    return PairSystem(M=m * np.eye(3), K=np.zeros((3, 3)), C=np.zeros((3, 3)), Gamma=np.eye(3),
                      D=np.array([[[1.0, 0, 0], [0, 1.0, 0]]]), R=np.array([[0, 0, 1.0]]),
                      bearings=(bearing,), positions=np.zeros((1, 2)), g=G)  # fmt: skip


def test_single_mass_on_a_tfp_equals_the_deck_kernels_sdof():
    # A mass on one TFP (with velocity-dependent surfaces) under a circular orbit (3 m/s^2,
    # 0.5 Hz: regimes up to IV, surfaces 1 and 4 at their rims) and a vertical component.
    # The deck's SDOF and the PairSystem (normal force a Baumgarte multiplier, λ = m (g + a_z)
    # on the closed gap) integrate the same series model with two codes; both at rtol 1e-10,
    # so the slips, the element slips and the forces agree to the integrators' global error,
    # well below 1e-6 of their peaks. The rims reached (read from the element slips) are the
    # same surfaces, first touched within one output step.
    b = TripleBearing(**TYPICAL, rate=20.0, mu_fast2=0.03, mu_fast3=0.03)
    orbit = {"f": 0.5, "ax": 3.0, "ay": 3.0, "phase_y_deg": -90.0, "az": 0.2 * G, "f_z": 1.3}
    kw = dict(law="arctan", t_end=4.0, dt_out=0.01, rtol=1e-10, atol=(1e-12, 1e-12))
    r = simulate_pairs(single_mass(b), orbit, **kw)
    ref = simulate_plane(sdof_plane(M, b, g=G), orbit, **kw)
    peak = np.abs(ref.u).max()
    assert peak > TYPICAL["d1"] * 0.5
    assert np.abs(r.u - ref.u).max() < 1e-6 * peak
    assert r.internal.shape == ref.internal.shape == (r.t.size, 8)
    assert np.abs(r.internal - ref.internal).max() < 1e-6 * np.abs(ref.internal).max()
    w = 2 * math.pi * 1.3
    np.testing.assert_allclose(r.N[:, 0], M * (G + 0.2 * G * np.sin(w * r.t)), rtol=1e-8)
    scale = M * G * 0.3
    np.testing.assert_allclose(r.friction, ref.friction, rtol=0, atol=1e-6 * scale)
    np.testing.assert_allclose(r.restoring, ref.restoring, rtol=0, atol=1e-6 * scale)
    lim, lim_ref = r.summary()["tfp_surface_limits"], ref.summary()["tfp_surface_limits"]
    assert [c["surface"] for c in lim] == [c["surface"] for c in lim_ref]
    assert {"1", "4"} <= {c["surface"] for c in lim}
    for c, d in zip(lim, lim_ref, strict=True):
        assert abs(c["t_first_s"] - d["t_first_s"]) <= kw["dt_out"] * 1.0001


def test_rigid_deck_on_four_tfps_equals_the_deck_kernels():
    # Four TFPs under an eccentric rigid deck (centre of mass 1.5 m above the sliding
    # surfaces), an elliptical orbit and a vertical component. The deck's kernels take the
    # normal forces from the rigid-plate distribution; the PairSystem (from_deck: q = x, y,
    # θ, z, r_x, r_y, four contacts on three vertical dofs) from its independent contact
    # rows, the same forces. Both at rtol 1e-9: slips, element slips, twist and normal
    # forces agree to the integrators' global error (1e-6 of their peaks).
    pos = [(-4.0, -3.0), (4.0, -3.0), (4.0, 3.0), (-4.0, 3.0)]
    b = TripleBearing(**TYPICAL)
    d = rigid_deck(2e5, 2e5 * 8.0, pos, b, ecc=(0.6, -0.4), h=1.5, g=G)
    p = from_deck(d)
    assert p.has_tfp and p.n_states == 2 * p.n + 4 * tfp.N_INTERNAL
    orbit = {"f": 0.6, "ax": 2.0, "ay": 1.2, "phase_y_deg": -70.0, "az": 2.0, "f_z": 1.1}
    kw = dict(law="arctan", t_end=5.0, dt_out=0.02, rtol=1e-9, atol=(1e-11, 1e-11))
    r = simulate_pairs(p, orbit, **kw)
    ref = simulate_plane(d, orbit, **kw)
    peak = np.abs(ref.u).max()
    assert peak > 0.05
    assert np.abs(r.u - ref.u).max() < 1e-6 * peak
    assert np.abs(r.internal - ref.internal).max() < 1e-6 * np.abs(ref.internal).max()
    np.testing.assert_allclose(r.N, ref.N, rtol=0, atol=1e-7 * ref.N.max())
    # the twist: its share of the corner slips (5 m from O) within the slips' tolerance
    # (pendulum forces ∝ N centre the resistance on the mass, so both stay near zero)
    assert np.abs(r.q[:, 2] - ref.theta).max() * 5.0 < 1e-6 * peak


def _published_backbone(p, phi):
    """u(φ) of Table 1 through regimes I–III (μ2 = μ3, R2 = R3 here)."""
    R1, R2, R3 = p["R1"], p["R2"], p["R3"]
    m1, m2, m4 = p["mu1"], p["mu2"], p["mu4"]
    u_star = (R2 + R3) * (m1 - m2)
    u_2star = u_star + (R1 + R3) * (m4 - m1)
    f_dr1 = m1 + p["d1"] / R1  # (regime III ends with surface 1 at its rim)
    knots_f = [m2, m1, m4, f_dr1]
    knots_u = [0.0, u_star, u_2star, u_2star + (R1 + p["R4"]) * (f_dr1 - m4)]
    return np.interp(phi, knots_f, knots_u), knots_f, knots_u


def test_quasi_static_loading_passes_the_published_transitions_of_regimes_one_to_three():
    # A mass on one TFP as a PairSystem, the ground acceleration ramped slowly along x
    # (a_x = −c t up to φ = 0.13, in regime III: μ4 = 0.10 < 0.13 < μ1 + d1/R1 = 0.24). The
    # bearing's force ratio φ = F_x/N and its slip u are read from the run; the loading is
    # monotonic (asserted: the slip speed never reverses), so the plastic slip u − φ/κ_e (the
    # yield spring taken out) lies on the published backbone up to the overstress of the
    # sliding elements, OVERSTRESS min μ |v| per element, times the slope sum R1 + R4 (the
    # bound of the TFP tests), and the integrators' tolerance. The transitions u*, u** are
    # passed at φ = μ1, μ4 and the slopes inside regimes I-III are Table 1's.
    p = TYPICAL
    b = TripleBearing(**p)
    T = 40.0
    c = 0.13 * G / T
    t = np.linspace(0.0, T, 801)
    ground = (0.0, t[1] - t[0], -c * t, None, None)
    r = simulate_pairs(single_mass(b), ground, law="arctan", t_eval=t, rtol=1e-9,
                       atol=(1e-12, 1e-12))  # fmt: skip
    F = r.friction + r.restoring + r.other
    phi = F[:, 0, 0] / r.N[:, 0]
    u, v = r.u[:, 0, 0], r.v[:, 0, 0]
    assert np.all(v > -1e-6)  # monotonic loading (a premise of the comparison)
    assert np.abs(r.u[:, 0, 1]).max() < 1e-12  # nothing along y
    _, knots_f, knots_u = _published_backbone(p, 0.0)
    assert phi.max() > knots_f[2] + 0.02  # regime III reached
    u_pub, _, _ = _published_backbone(p, phi)
    u_plastic = u - phi / b.k_elastic
    tol = (p["R1"] + p["R4"]) * tfp.OVERSTRESS * p["mu2"] * np.abs(v).max() * 1.01 + 1e-6
    sliding = phi > p["mu2"] * 1.001
    assert np.all(np.abs(u_plastic - u_pub)[sliding] <= tol)
    # the transition points: u* where φ crosses μ1, u** where it crosses μ4
    for f_k, u_k in zip(knots_f[1:3], knots_u[1:3], strict=True):
        assert np.interp(f_k, phi, u_plastic) == pytest.approx(u_k, abs=tol)
    slopes = [p["R2"] + p["R3"], p["R1"] + p["R3"], p["R1"] + p["R4"]]
    for j, slope in enumerate(slopes):
        lo = knots_f[j]
        hi = knots_f[j + 1] if j < 2 else phi.max()
        k = np.flatnonzero((phi > lo + 0.3 * (hi - lo)) & (phi < lo + 0.7 * (hi - lo)))
        assert k.size > 5, j
        assert np.polyfit(phi[k], u_plastic[k], 1)[0] == pytest.approx(slope, rel=1e-2), j


def test_a_tfp_runs_only_with_the_regularised_law_on_radau():
    # the series model has no stick events (the deck's rule): a one-line error naming `law`
    s = single_mass(TripleBearing(**TYPICAL))
    orbit = {"f": 1.0, "ax": 0.1, "ay": 0.0}
    for kw in ({"law": "switch"}, {"law": "arctan", "integrator": "dopri5"},
               {"law": "arctan", "contact": "unilateral"}):  # fmt: skip
        with pytest.raises(ValueError, match=r"^law: a triple friction pendulum") as e:
            simulate_pairs(s, orbit, t_end=0.1, **kw)
        assert "\n" not in str(e.value)
    # y0 = [q, q̇] without the internal slips starts them from rest; a wrong length is refused
    r = simulate_pairs(s, orbit, t_end=0.1, law="arctan", y0=np.zeros(6))
    assert r.internal.shape == (r.t.size, 8)
    with pytest.raises(ValueError, match=r"y0: expected 6 finite numbers \[q, q̇\] \(or 14"):
        simulate_pairs(s, orbit, t_end=0.1, law="arctan", y0=np.zeros(7))


PORTAL = {
    "scene": {"kind": "building3d"},
    "structure": {"frame3d": "portal-3d", "fidelity": "cb"},
    "bearing": {"type": "tfp", **TYPICAL},
    "motion": {"kind": "record3", "record": "synthetic-wn-40s", "t_end": 3.0, "pga": 1.0},
    "solver": {"dt_out": 0.01},
}


@pytest.mark.parametrize("fidelity", ["cb", "full"])
def test_portal_on_tfps_at_the_cb_and_dense_full_rungs(fidelity, tmp_path):
    # The portal on four TFPs (the law defaults to 'arctan' for a TFP). At a PGA whose rigid
    # demand m_x PGA is a 20th of μ2 Σ N (even amplified 10x by the frame, below the inner
    # surfaces' friction) the bearings stay in their elastic range (regime 0 before I): peak
    # force ratio |F|/N < μ2, slips within μ2/κ_e (the yield spring at μ2), no rim. At
    # 1 m/s^2 they slide, within the total capacity d1 + ... + d4 and without rims (the
    # surfaces' first rim needs u_dr1 ≈ 0.75 m).
    from nsdyn.models.isolated.building3d_scene import build_system, run_scene

    cfg = copy.deepcopy(PORTAL)
    cfg["structure"]["fidelity"] = fidelity
    pairs = build_system(cfg, str(tmp_path / "s.toml"))["pairs"]
    assert pairs.has_tfp and pairs.info["path"] == "dense"
    mx = pairs.Gamma[:, 0] @ pairs.M @ pairs.Gamma[:, 0]
    n_sum = pairs.info["static_normal"].sum()
    b = TripleBearing(**TYPICAL)
    for pga in (TYPICAL["mu2"] * n_sum / mx / 20.0, 1.0):
        cfg["motion"]["pga"] = pga
        out = tmp_path / f"pga{pga:g}"
        out.mkdir()
        s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=out, figures=False,
                      quiet=True)  # fmt: skip
        assert s["law"] == "arctan" and s["tfp_surface_limits"] == [] and s["rim_contacts"] == []
        with np.load(out / "building3d.npz") as z:
            F = z["friction"] + z["restoring"] + z["other"]
            ratio = np.hypot(F[..., 0], F[..., 1]) / z["N"]
        assert s["peak_resultant_displacement_m"] <= b.d_cap
        if pga < 1.0:
            assert ratio.max() < TYPICAL["mu2"]
            assert s["peak_resultant_displacement_m"] <= TYPICAL["mu2"] / b.k_elastic
        else:
            assert ratio.max() > TYPICAL["mu2"]
            assert s["peak_resultant_displacement_m"] > 10 * TYPICAL["mu2"] / b.k_elastic


def test_the_cb_rung_refuses_a_tfp_with_the_switch_law_or_a_unilateral_contact(tmp_path):
    from nsdyn.models.isolated.building3d_scene import run_scene
    from nsdyn.models.scenefile import SceneError

    for solver, field in (({"law": "switch"}, "solver.law"),
                          ({"contact": "unilateral"}, "solver.contact")):  # fmt: skip
        cfg = copy.deepcopy(PORTAL)
        cfg["solver"].update(solver)
        with pytest.raises(SceneError) as e:
            run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                      quiet=True)  # fmt: skip
        msg = str(e.value)
        assert "\n" not in msg and f"s.toml: {field}:" in msg and "triple friction" in msg, msg


def test_a_tfp_past_its_ultimate_capacity_is_reported_with_its_whole_displacement():
    # the surfaces' stops hold each slip near its d_k, but the bearing's resultant u is the
    # slips' sum plus the elastic element's stretch under the rim forces: the part of u
    # beyond d1 + d2 + d3 + d4 is reported for each TFP (flat sliders are not TFPs)
    from types import SimpleNamespace

    from nsdyn.models.isolated.tfp import beyond_capacity

    tfp = TripleBearing(**TYPICAL)  # d1 + d2 + d3 + d4 = 0.92 m
    u = np.zeros((3, 2, 2))
    u[1, 0] = (0.57, 0.76)  # |u| = 0.95 m: 30 mm beyond
    u[2, 1] = (2.0, 0.0)  # a flat slider far out: no TFP capacity
    res = SimpleNamespace(system=SimpleNamespace(bearings=[tfp, Bearing(Friction(0.05))]), u=u)
    (c,) = beyond_capacity(res)
    assert c["isolator"] == 0 and c["capacity_m"] == pytest.approx(0.92, rel=1e-15)
    assert c["beyond_m"] == pytest.approx(0.03, rel=1e-12)
    res.u = 0.9 * u  # within its capacity (0.855 m)
    assert beyond_capacity(res) == []


def test_a_start_off_rest_without_the_element_slips_is_said():
    # as the deck's: y0 = [q, q̇] moving a mass on a TFP off its static equilibrium starts the
    # elements at zero slip (the whole offset in the elastic element): an InputWarning; the
    # static equilibrium itself, or the full state with its slips, is silent
    import warnings

    from nsdyn._checks import InputWarning

    s = single_mass(TripleBearing(**TYPICAL))
    q0, _ = s.static_equilibrium()
    kw = dict(law="arctan", t_end=0.01)
    off = np.concatenate([q0 + [0.2, 0.0, 0.0], np.zeros(3)])
    with pytest.warns(InputWarning, match="element slips start at zero"):
        simulate_pairs(s, {"f": 1.0, "ax": 0.0}, y0=off, **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        simulate_pairs(s, {"f": 1.0, "ax": 0.0}, y0=np.concatenate([q0, np.zeros(3)]), **kw)
        simulate_pairs(s, {"f": 1.0, "ax": 0.0}, y0=np.concatenate([off, np.zeros(8)]), **kw)
