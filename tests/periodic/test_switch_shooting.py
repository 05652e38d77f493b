"""Shooting on the switch model: closed-form Coulomb orbits, exact monodromy, grazing.

Sources: Den Hartog, J. P. (1931), "Forced vibrations with combined Coulomb and viscous
friction", Trans. ASME APM-53-9, 107-115 (non-stop steady state of the forced Coulomb
oscillator, derived below); Leine & Nijmeijer (2004), Dynamics and Bifurcations of Non-Smooth
Mechanical Systems, ch. 3 (saltation matrices: the monodromy is the derivative of the period
map, checked by finite differences).
"""

import math

import numpy as np
import pytest

from nsdyn.ground.excitation import HarmonicForce
from nsdyn.models.isolated.builders import system_from_matrices
from nsdyn.models.isolated.system import Isolation
from nsdyn.periodic.switch import GRAZE_TOL, shoot_switch, switch_problem

M1, W1 = 1.0, 2.0 * math.pi  # kg, rad/s (natural frequency 1 Hz)


def coulomb_oscillator(mu: float, c: float = 0.0, law: str = "switch"):
    """m x'' + c x' + k x + mu m g sign(x') = load (frozen normal force m g)."""
    iso = Isolation(k_lam=0.0, c=0.0, mu=mu, law=law)
    return system_from_matrices(
        [[M1]],
        [[c]],
        [[M1 * W1**2]],
        iso_dofs=[0],
        influence=[1.0],
        isolation=iso,
        weight=M1 * iso.g,
        levels=[[0]],
    )


def den_hartog_state(r: float, fric: float, t: np.ndarray) -> np.ndarray:
    """Exact non-stop steady state [x, x'] / (P0/k, w_n P0/k) of x'' + x + fric sign(x') =
    cos(r t + phi) (time in 1/w_n, t = 0 at the displacement maximum).

    Derivation: on the half period 0 < t < tau = pi / r the velocity is negative, so
    x = fric + p(t) + C cos t + D sin t with p = cos(r t + phi) / (1 - r^2). Symmetry
    x(t + tau) = -x(t) and x'(0) = x'(tau) = 0 give D = -p'(0), C = -p'(0)(1 + cos tau)/sin tau
    and 2 fric = 2 p'(0)(1 + cos tau)/sin tau, i.e. p'(0) = fric tan(tau/2), hence C = -fric,
    D = -fric tan(tau/2), sin phi = -fric (1 - r^2) tan(tau/2) / r and the amplitude
    X0 = cos phi / (1 - r^2) = sqrt(1/(1 - r^2)^2 - fric^2 U^2), U = tan(pi/(2r)) / r
    (Den Hartog's result). Returns None where the orbit is not non-stop.
    """
    tau = math.pi / r
    tn = math.tan(tau / 2)
    sphi = -fric * (1 - r * r) * tn / r
    if abs(sphi) >= 1:
        return None
    cphi = math.copysign(math.sqrt(1 - sphi * sphi), 1 - r * r)
    phi = math.atan2(sphi, cphi)

    def half(s):
        x = fric + np.cos(r * s + phi) / (1 - r * r) - fric * np.cos(s) - fric * tn * np.sin(s)
        v = -r * np.sin(r * s + phi) / (1 - r * r) + fric * np.sin(s) - fric * tn * np.cos(s)
        return x, v

    # validity: x' < 0 inside the half period, and the turning point is not a stop
    s = np.linspace(0, tau, 2001)[1:-1]
    if np.any(half(s)[1] >= 0) or cphi * r * r / (1 - r * r) <= fric:
        return None
    t = np.mod(t, 2 * tau)
    first = t < tau
    x, v = half(np.where(first, t, t - tau))
    sign = np.where(first, 1.0, -1.0)
    return np.stack([sign * x, sign * v], axis=-1), phi


@pytest.mark.parametrize("r, fric", [(0.6, 0.1), (0.8, 0.3), (1.5, 0.2), (2.0, 0.1), (3.0, 0.05)])
def test_den_hartog_non_stop_orbit(r, fric):
    """Forced Coulomb oscillator (no viscous damping) under P0 sin(w t): the shooting
    solution equals Den Hartog's closed form to 1e-6 relative (state at t = 0 and amplitude)."""
    k = M1 * W1**2
    F = fric * 1.0  # P0 = 1 N, friction fric P0
    g = coulomb_oscillator(0.1).isolation.g
    sysm = coulomb_oscillator(F / (M1 * g))
    f = r * W1 / (2 * math.pi)
    pb = switch_problem(sysm, 1.0, load=HarmonicForce(1.0, f, dofs=(0,)))
    res = shoot_switch(pb, f, tol=1e-11)
    assert res.converged, res.message
    # model t_m: sin(w t_m) = cos(w t_m - pi/2) = cos(r t + phi)  =>  t = w_n t_m - (pi/2 + phi)/r
    probe = den_hartog_state(r, fric, np.zeros(1))
    assert probe is not None, "parameters outside the non-stop regime"
    phi = probe[1]
    ts = np.array([-(math.pi / 2 + phi) / r])
    ex = den_hartog_state(r, fric, ts)[0][0]
    x_exact = ex[0] / k
    v_exact = ex[1] * W1 / k
    X0 = den_hartog_state(r, fric, np.array([0.0]))[0][0, 0] / k
    assert abs(res.x0[0] - x_exact) <= 1e-6 * X0
    assert abs(res.x0[1] - v_exact) <= 1e-6 * X0 * W1
    # two events per period (reversals), no stick: non-zero multipliers, all inside the circle
    assert [e[2] for e in res.events] in ([1, -1], [-1, 1])
    assert np.all(np.abs(res.multipliers) < 1.0)


def test_monodromy_against_finite_differences():
    """Exact monodromy (flows x saltation matrices) = central differences of the period map,
    on a stick-slip orbit of a viscous + Coulomb oscillator under base excitation."""
    sysm = coulomb_oscillator(0.2, c=2 * 0.05 * W1 * M1)
    pb = switch_problem(sysm, 2.5)
    f = 0.7
    res = shoot_switch(pb, f, tol=1e-10)
    assert res.converged, res.message
    assert any(e[2] == 0 for e in res.events), "expected a stick phase"
    x = res.x0 + np.array([1e-3, 2e-3])  # off the orbit: v != 0 at t = 0
    pm = pb.period_map(x, f, n_steps=200)
    fd = np.empty((2, 2))
    for j in range(2):
        e = np.zeros(2)
        e[j] = 1e-7 * (1e-2 if j == 0 else 5e-2)
        fd[:, j] = (
            pb.period_map(x + e, f, n_steps=200, sens=False).xT
            - pb.period_map(x - e, f, n_steps=200, sens=False).xT
        ) / (2 * e[j])
    assert np.allclose(pm.monodromy, fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max())


def test_stick_phase_gives_a_zero_multiplier():
    """On a stick-slip orbit v = 0 is held in stick: n^T S = 0, one multiplier exactly 0."""
    sysm = coulomb_oscillator(0.2, c=2 * 0.05 * W1 * M1)
    pb = switch_problem(sysm, 2.5)
    res = shoot_switch(pb, 0.7, tol=1e-10)
    rho = np.sort(np.abs(res.multipliers))
    assert rho[0] < 1e-12 and rho[1] < 1.0


def test_linear_system_one_newton_step(newton_roundoff):
    """mu = 0: the period map is affine, Newton converges after one update: the round-off
    that update leaves (``newton_roundoff``, tests/conftest.py) is below the tolerance."""
    sysm = coulomb_oscillator(0.0, c=2 * 0.02 * W1 * M1, law="none")
    pb = switch_problem(sysm, 1.0)
    res = shoot_switch(pb, 0.8, tol=1e-9)
    assert res.converged and res.residual <= newton_roundoff(pb, res) < 1e-9
    assert res.iterations == 1
    # against the FRF of the linear oscillator: x = -A sin(w t) / (k - m w^2 + i c w)
    w = 2 * math.pi * 0.8
    H = -1.0 / (W1**2 - w * w + 1j * 2 * 0.02 * W1 * w)
    x0 = (H * -1j).real  # x(t) = Re(H e^{i w t} (-i)) for sin(w t) = Re(-i e^{i w t})
    assert abs(res.x0[0] - x0) <= 1e-8 * abs(H)


@pytest.mark.parametrize("ratio", [1.0 - 1e-7, 1.0 + 1e-7])
def test_grazing_is_reported(ratio):
    """Undamped Coulomb oscillator held at rest by friction, forced by P0 = ratio mu m g: at
    ratio = 1 the stick force touches the friction limit once per half period (grazing). The
    result says so; if Newton converged, the orbit is a genuine fixed point of the map."""
    mu = 0.1
    sysm = coulomb_oscillator(mu)
    P0 = ratio * mu * M1 * sysm.isolation.g
    f = 0.5
    pb = switch_problem(sysm, P0, load=HarmonicForce(P0, f, dofs=(0,)))
    res = shoot_switch(pb, f, tol=1e-9)
    assert res.grazing and res.graze < GRAZE_TOL
    assert "grazing" in res.message
    # and where: below the limit a touch without a switch; above it the brief slip's switch,
    # where the force P0 sin(w t) peaks (t = T/4 = 0.5 s, or 3T/4), on the one isolator
    if ratio < 1.0:
        assert "touches zero between switches" in res.message
    else:
        t = float(res.message.split("touches zero at t = ")[1].split(" s")[0])
        assert min(abs(t - 0.5), abs(t - 1.5)) < 0.01 and "isolator 0" in res.message
    if res.converged:
        pm = pb.period_map(res.x0, f, sens=False)
        assert np.all(np.abs(pm.xT - res.x0) <= 1e-6 * max(np.abs(res.x0).max(), 1e-9))


def test_sequential_continuation_says_law_and_method():
    """continue_sequential on the switch model: every point converged, says its law, and the
    stick-all-period points are exactly those without events (the stick phase is exact)."""
    from nsdyn.periodic.switch import switch_response

    sysm = coulomb_oscillator(0.2, c=2 * 0.05 * W1 * M1)
    curve = switch_response(sysm, 2.5, fmin=0.2, fmax=5.0, points=8)
    assert len(curve.points) == 8
    for p in curve.points:
        assert p.converged and p.method == "shooting"
        assert p.quantities["law"] == "switch"
        assert p.quantities["stick_all_period"] == (p.quantities["events"] == 0)
    # at 5 Hz the base stays stuck if mu m g exceeds the stick force m A = 2.5 N?  No: stuck,
    # the mass moves with the ground, the friction force is m A = 2.5 N > mu m g = 1.96 N;
    # so it slips: the last point is not stuck all period
    assert not curve.points[-1].quantities["stick_all_period"]


@pytest.mark.parametrize("fric, r0, r1", [(0.1, 0.55, 0.9), (0.2, 1.3, 3.0)])
def test_arclength_follows_den_hartog(fric, r0, r1):
    """Pseudo-arclength continuation (in (x0, log f), the switch map differentiated in T by
    central differences) on the forced Coulomb oscillator below and above resonance: every
    point, at the frequency the arclength steps chose, equals Den Hartog's closed form to 1e-6
    relative, and the curve spans the range."""
    from nsdyn.periodic.switch import switch_response

    k = M1 * W1**2
    g = coulomb_oscillator(0.1).isolation.g
    sysm = coulomb_oscillator(fric / (M1 * g))
    load = HarmonicForce(1.0, 1.0, dofs=(0,))  # P0 = 1 N, friction fric P0
    curve = switch_response(
        sysm, 1.0, load=load, continuation="arclength", fmin=r0, fmax=r1, points=10, tol=1e-11
    )
    assert curve.info["continuation"] == "arclength"
    assert curve.points[0].f == pytest.approx(r0) and curve.points[-1].f == pytest.approx(r1)
    assert len(curve.points) >= 10
    for p in curve.points:
        assert p.converged and p.method == "arclength", p.note
        r = p.f  # f_n = 1 Hz: r = f
        phi = den_hartog_state(r, fric, np.zeros(1))[1]
        ex = den_hartog_state(r, fric, np.array([-(math.pi / 2 + phi) / r]))[0][0]
        X0 = den_hartog_state(r, fric, np.array([0.0]))[0][0, 0] / k
        assert abs(p.x0[0] - ex[0] / k) <= 1e-6 * X0
        assert abs(p.x0[1] - ex[1] * W1 / k) <= 1e-6 * X0 * W1


@pytest.mark.parametrize("r, fric", [(0.6, 0.1), (1.5, 0.2), (2.0, 0.1)])
def test_tied_isolators_of_a_rigid_model_slide_as_one_den_hartog_oscillator(r, fric):
    """The office frame at the rigid fidelity without its dampers is Den Hartog's oscillator:
    mass M_s on 2 K_lam, friction mu (N_0 + N_1) = mu M_s g under -M_s A sin(w t). Its two
    isolators share one sliding velocity: the switch model moved one of them into stick while
    the other slid on at v = 0, and shooting converged on orbits 2.2x too large (0.41 m for
    0.18 m). Tied into one group, the orbit's half range is Den Hartog's amplitude to 1e-6
    (the orbit's dense sampling)."""
    from nsdyn import Isolation as Iso
    from nsdyn import load_frame
    from nsdyn.models.isolated.system import build_system

    frame = load_frame("office-11")
    iso = Iso(c=0.0, law="switch")
    sysm = build_system(frame, iso, fidelity="rigid")
    M, K = frame.total_mass, 2 * iso.k_lam
    A = iso.mu * iso.g / fric  # friction fric x the force amplitude M A
    f = r * math.sqrt(K / M) / (2 * math.pi)
    pb = switch_problem(sysm, A)
    assert pb.groups().tolist() == [0, 0]
    res = shoot_switch(pb, f, tol=1e-11)
    assert res.converged, res.message
    X = pb.period_map(res.x0, f, store=True, sens=False).X
    X0 = den_hartog_state(r, fric, np.zeros(1))[0][0, 0] * M * A / K
    assert pb.orbit_quantities(f, X)["x_iso"] == pytest.approx(X0, rel=1e-6)


def test_isolators_of_a_flexible_model_are_not_tied():
    # under the Craig-Bampton frame the two bearings' slips differ by the base's deformation
    from nsdyn import load_frame
    from nsdyn.models.isolated.system import build_system

    sysm = build_system(load_frame("portal"), Isolation(law="switch"), fidelity="cb")
    assert switch_problem(sysm, 1.0).groups().tolist() == [0, 1]


def test_an_orbit_stuck_all_period_converges_on_its_flows_round_off():
    # A = 0.05 m/s² < mu g = 0.29 m/s²: the rigid office sticks all period; its state moves by
    # its flow's round-off alone (1e-17 m), which an amplitude floor of 1e-12 m read as a
    # residual of 1e-5 ("line search failed"). The floor is 1e-9 of the forcing's static
    # displacement M A / (2 K_lam) = 0.35 m here (amp_floor)
    from nsdyn import Isolation as Iso
    from nsdyn import load_frame
    from nsdyn.models.isolated.system import build_system

    frame = load_frame("office-11")
    iso = Iso(law="switch")
    pb = switch_problem(build_system(frame, iso, fidelity="rigid"), 0.05)
    static = frame.total_mass * 0.05 / (2 * iso.k_lam)
    assert pb.amp_floor == pytest.approx(1e-9 * static, rel=1e-6)
    res = shoot_switch(pb, 0.1)
    assert res.converged, res.message
    q = pb.orbit_quantities(0.1, pb.period_map(res.x0, 0.1, store=True, sens=False).X)
    assert q["stick_all_period"] and q["x_iso"] < 1e-12


def test_a_model_without_bearing_stiffness_keeps_a_floor_below_its_orbits():
    # k_lam = 0: the slip's stiffness is round-off, and the forcing's "static displacement"
    # 2e16 m made a floor of 2e7 m: orbits "converged" 6.9e-3 m open on 0.32 m. The floor is
    # capped (AMP_FLOOR_CAP); the orbit closes to the shooting tolerance of its amplitude
    from nsdyn import Isolation as Iso
    from nsdyn import load_frame
    from nsdyn.models.isolated.system import build_system
    from nsdyn.periodic.switch import AMP_FLOOR_CAP

    pb = switch_problem(build_system(load_frame("office-11"), Iso(law="switch", k_lam=0.0),
                                     fidelity="rigid"), 2.0)  # fmt: skip
    assert pb.amp_floor == AMP_FLOOR_CAP
    res = shoot_switch(pb, 1.0)
    X = pb.period_map(res.x0, 1.0, store=True, sens=False).X
    amp = 0.5 * np.ptp(X[:, 0])
    assert res.converged and abs(X[-1, 0] - X[0, 0]) <= 1e-6 * amp
