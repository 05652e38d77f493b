"""The uplift boundary A*(f): an exact threshold and an independent transient check.

References, independent of the code under test:

- a rigid frame on two bilateral supports whose isolators stick moves with the ground, so the
  base moment balance alone gives the normal forces, ``lam_1,2 = M g / 2 -+ M A h_cm / (2 b)``
  at every frequency, and ``A* = g b / h_cm`` with ``b`` half the support spacing and ``h_cm``
  the centre of mass above the supports, both from the frame's geometry and masses;
- the office frame's transient (adaptive Radau IIA, order 5, in the full coordinates with
  Baumgarte contacts; ``uplift="raise"`` checks every normal force after every step) started on
  the periodic orbit (fixed-step SDIRK2 shooting in minimal coordinates) just below and just
  above A*.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from nsdyn.ground import Harmonic
from nsdyn.models.isolated.system import Isolation, build_system
from nsdyn.periodic import Discretisation, frame_problem, shoot
from nsdyn.periodic.shooting import orbit_amplitudes
from nsdyn.periodic.uplift import uplift_boundary
from nsdyn.solve.integrate import UpliftError, solve
from nsdyn.structure import load_frame

# ±3 % in amplitude around A*: the margin min lam changes by 3 % of A* |d g / d A| there
# (1.5e4 N at 0.93 Hz to 3e5 N at 0.06 Hz on the office frame), more than the two
# integrators' disagreement on min lam: the SDIRK2 period (order 2, h = min(0.02 s, T / 200))
# errs by ~(2 pi f_k h)^2 / 12 on a frame mode f_k: <= 3e-4 relative for the 0.46 Hz mode at
# h = 0.02 s and ~1e-3 for the 2.98 Hz mode at h = T / 200 (0.93 Hz), i.e. 1e3-3e3 N of the
# 3.4e6 N static normal force; the root tolerance rtol = 1e-3 adds 0.1 % of A*.
BELOW, ABOVE = 0.97, 1.03
PERIODS = 3  # transient periods without uplift below A*
# the orbit's start is reproduced by the transient after PERIODS periods: both integrators
# follow the same stable orbit (multipliers < 1), up to the SDIRK2 error above (~3e-4)
RETURN_TOL = 1e-2
FREQS = (0.0234, 0.0588, 0.1112, 0.93)  # Hz


@pytest.fixture(scope="module")
def office():
    return load_frame("office-11")


@pytest.fixture(scope="module")
def cb5(office):
    # the bundled default scene's model: office-11, Craig-Bampton at 5 Hz (13 dofs), seed isolators
    return build_system(office, Isolation(), fidelity="cb", f_max=5.0)


def overturning_threshold(frame, g: float) -> float:
    """g b / h_cm from the frame's members (rho_A L at mid-length) and added nodal masses."""
    nodes, el = np.asarray(frame.nodes), np.asarray(frame.elements)
    length = np.linalg.norm(nodes[el[:, 1]] - nodes[el[:, 0]], axis=1)
    m_el = np.asarray(frame.rho_A) * length
    y_el = 0.5 * (nodes[el[:, 0], 1] + nodes[el[:, 1], 1])
    m_node = np.asarray(frame.node_mass)
    base = np.asarray(frame.base_nodes)
    assert len(base) == 2  # two supports: the moment balance is statically determinate
    h_cm = (m_el @ y_el + m_node @ nodes[:, 1]) / (m_el.sum() + m_node.sum())
    h_cm -= nodes[base, 1].mean()
    return g * 0.5 * np.ptp(nodes[base, 0]) / h_cm


def test_rigid_frame_on_sticking_isolators_lifts_off_at_g_b_over_h(office):
    # mu = 0.8 > b / h_cm (0.26): the friction capacity mu M g exceeds the base shear M A* at
    # the threshold, so the isolators stick (arctan creep only). The creep velocity
    # v = tan(pi A / (2 mu g)) / eps (~8e-5 m/s) accelerates the frame by at most
    # 2 pi f v <= 1e-3 m/s² at 2 Hz, i.e. <= 4e-4 of A*: tolerance 1e-3 (root rtol 1e-5).
    iso = Isolation(mu=0.8)
    s = build_system(office, iso, fidelity="rigid")
    exact = overturning_threshold(office, iso.g)
    res = uplift_boundary(s, [0.05, 0.5, 2.0], rtol=1e-5)
    assert res.status == ["ok"] * 3, res.status
    assert np.allclose(res.a_crit, exact, rtol=1e-3, atol=0.0), (res.a_crit, exact)


@pytest.fixture(scope="module")
def office_boundary(cb5):
    # below the isolation frequency (0.06 Hz), at it (lowest A*), above it, and in the pocket
    # near 0.93 Hz where the margin falls again at large amplitudes (A* ~ 12 m/s²) between
    # frequencies without uplift below 20 m/s²
    return uplift_boundary(cb5, FREQS)


def _orbit_start(system, point, A):
    """Periodic orbit at amplitude A (near the bracket), by shooting from the scaled point."""
    prob = frame_problem(system, A)
    guess = prob.x_ref + (A / point.a_below) * (point.x0_below - prob.x_ref)
    sh = shoot(prob, point.f, guess)
    assert sh.converged, sh.message
    return prob, sh


def _transient(system, prob, x0, A, f, periods):
    T = 1.0 / f
    t = np.linspace(0.0, periods * T, 64 * periods + 1)
    return solve(system.params(Harmonic(A, f)), prob.to_full(x0), t, uplift="raise")


def _check_point(system, point):
    assert point.ok, point.status
    assert point.a_below < point.a_crit <= point.a_above
    assert point.g_below > 0.0 >= point.g_above
    f = point.f
    # below: PERIODS periods without any normal force reaching zero, back on the orbit
    A = BELOW * point.a_crit
    prob, sh = _orbit_start(system, point, A)
    sol = _transient(system, prob, sh.x0, A, f, PERIODS)
    amp_z, amp_v = orbit_amplitudes(prob, sh.X)
    d = prob.to_minimal(sol.x[-1]) - sh.x0
    m = prob.m
    assert np.abs(d[:m]).max() / amp_z < RETURN_TOL
    assert np.abs(d[m:]).max() / amp_v < RETURN_TOL
    # above: a normal force reaches zero within the first period of the orbit
    A = ABOVE * point.a_crit
    prob, sh = _orbit_start(system, point, A)
    with pytest.raises(UpliftError) as ei:
        _transient(system, prob, sh.x0, A, f, PERIODS)
    assert 0.0 <= ei.value.t <= 1.0 / f


@pytest.mark.parametrize("k", range(len(FREQS)), ids=[f"{f:g}Hz" for f in FREQS])
def test_transient_from_the_orbit_lifts_off_only_above_the_boundary(cb5, office_boundary, k):
    _check_point(cb5, office_boundary.points[k])


def test_a_point_without_an_orbit_reports_its_amplitude_and_reason(cb5):
    # a stage tolerance no Newton iteration can meet: no period can be integrated, so every
    # amplitude fails; the point says where and why instead of returning a bare NaN
    res = uplift_boundary(cb5, [0.3], disc=Discretisation(rtol=1e-30, atol=0.0))
    p = res.points[0]
    assert math.isnan(p.a_crit) and not p.ok
    assert p.status.startswith("shooting failed at A=")
    assert "stage Newton iteration did not converge" in p.status
    assert float(p.status.split("A=")[1].split(":")[0]) == pytest.approx(p.a_fail, rel=1e-3)
    assert p.to_dict()["a_crit"] is None


def test_static_margin_is_the_smallest_static_normal_force(cb5):
    # g(f, 0): the weight on the two isolators of the symmetric frame, M g / 2 each
    res = uplift_boundary(cb5, [5.0], a_hi=1.0)
    assert res.static_force == pytest.approx(cb5.total_mass * cb5.isolation.g / 2, rel=1e-9)
    assert res.points[0].status == "no uplift below a_hi"
