"""Isolated systems built without a frame, checked against closed forms.

- Coulomb oscillator, free decay (frozen normal force N = m g, no viscous damping): each half
  cycle lasts pi/w and the amplitude drops by 2 mu g / w^2 (4 mu g / w^2 per cycle) until it
  stops inside |x| <= mu g / w^2 (textbook result; exact for Coulomb friction).
- Coulomb oscillator under F0 cos(W t): Den Hartog (1931), continuous motion without stops,
  X / X_st = sqrt(V^2 - (F_f / F0)^2 U^2), V = 1 / (1 - b^2), U = tan(pi / (2 b)) / b,
  b = W / w, X_st = F0 / k (derived again in the test's comment).
- Linear SDOF under a harmonic force: x = X sin(W t + phase - delta) in the steady state,
  X = (F0 / k) / sqrt((1 - b^2)^2 + (2 zeta b)^2); undamped from rest:
  x = X_st V (sin W t - b sin w t).
- 3-storey shear building with its isolator stuck: the fixed-base linear building
  (python-control's forced response with the same linearly interpolated record).
"""

import math

import numpy as np
import pytest

from nsdyn._checks import NotedWarning
from nsdyn.ground.excitation import Harmonic, HarmonicForce, Table
from nsdyn.models.isolated.builders import shear_building, system_from_matrices
from nsdyn.models.isolated.scene import build_scene, load_scene
from nsdyn.models.isolated.system import Isolation
from nsdyn.solve.transient import simulate

G = 9.81
M1, K1, MU1 = 1000.0, 4.0e4, 0.05  # the Coulomb oscillator of these tests
W1 = math.sqrt(K1 / M1)
SCENES = __import__("pathlib").Path(__file__).resolve().parents[3] / "examples" / "scenes"


def coulomb(law="switch", **kw):
    iso = Isolation(k_lam=K1, c=kw.pop("c", 0.0), mu=kw.pop("mu", MU1), law=law, **kw)
    return shear_building([M1], [], 0.0, isolation=iso)


def test_coulomb_free_decay_is_linear():
    # Half-cycle extremes x_j = (-1)^j (x0 - j 2 mu g / w^2) at t = j pi / w, then rest at the
    # last extreme inside the stick band |x| <= mu g / w^2. Event-driven switch model: exact.
    s = coulomb()
    x0 = 0.1
    res = simulate(
        s, None, method="event", t_end=3.0, dt_out=1e-3, x0=[x0, 0.0], rtol=1e-9, atol=1e-12
    )
    d = 2 * MU1 * G / W1**2
    j_stop = math.ceil((x0 - MU1 * G / W1**2) / d)
    q = res.x[:, 0]
    for j in range(1, j_stop + 1):
        k = int(np.argmin(np.abs(res.t - j * math.pi / W1)))
        assert q[k] == pytest.approx((-1) ** j * (x0 - j * d), abs=1e-6)
    # at rest afterwards, at the last extreme
    late = res.t > (j_stop + 0.5) * math.pi / W1
    assert np.all(np.abs(q[late] - (-1) ** j_stop * (x0 - j_stop * d)) < 1e-6)
    assert res.response.stick_fraction > 0.3
    # an SDOF has no contact geometry: no normal-force history, no uplift check
    assert s.n_contacts == 0 and res.uplift == []
    assert "min_normal_force_N" not in res.summary()


def den_hartog(F0, f, k=K1, m=M1, Ff=MU1 * M1 * G):
    # m x'' + k x + Ff sgn(x') = F0 cos(W t + phi): on a half period with x' < 0 the shifted
    # y = x - Ff/k is linear; imposing x(0) = X, x(pi/W) = -X, x' = 0 at both gives
    # X = V X_st cos(phi) and V X_st sin(phi) = -(Ff/k) tan(pi/2b)/b.
    b = 2 * math.pi * f / math.sqrt(k / m)
    V = 1.0 / (1.0 - b * b)
    U = math.tan(math.pi / (2 * b)) / b
    return F0 / k * math.sqrt(V * V - (Ff / F0) ** 2 * U * U)


@pytest.mark.parametrize("ratio", [0.2, 0.4])
def test_den_hartog_steady_state(ratio):
    # Event-driven Coulomb friction from rest; friction dissipates the free part in finite
    # time, the last two periods are the steady orbit (continuous slip for b = 1.49).
    f = 1.5
    F0 = MU1 * M1 * G / ratio
    res = simulate(
        coulomb(),
        HarmonicForce(F0, f, dofs=[0]),
        method="event",
        n_periods=40,
        dt_out=1e-3 / f,
        rtol=1e-9,
        atol=1e-12,
    )
    last = res.t > res.t[-1] - 2.0 / f
    X = 0.5 * (res.x[last, 0].max() - res.x[last, 0].min())
    assert X == pytest.approx(den_hartog(F0, f), rel=2e-4)
    # no stops, as the formula assumes: stick only at the reversal instants (|v| <= eta)
    assert np.mean(res.response.modes[last, 0] == 0) < 0.005


def test_den_hartog_by_shooting():
    # The periodic solver on the arctan law (eps = 1e4 s/m: creep speeds ~1e-4 m/s) lands
    # on Den Hartog's orbit to the smoothing error.
    from nsdyn.periodic import frame_problem, shoot

    s = coulomb(law="arctan", eps=1e4)
    F0, f = MU1 * M1 * G / 0.3, 1.5
    prob = frame_problem(s, F0, load=HarmonicForce(1.0, f, dofs=[0]))
    r = shoot(prob, f, np.array([0.0, 0.0]))
    assert r.converged
    X = 0.5 * (r.X[:, 0].max() - r.X[:, 0].min())
    assert X == pytest.approx(den_hartog(F0, f), rel=5e-3)


@pytest.mark.parametrize("zeta, phase", [(0.0, 0.0), (0.05, 0.7)])
def test_linear_sdof_under_harmonic_force(zeta, phase):
    # law "none": the linear oscillator m x'' + c x' + k x = F0 sin(W t + phase).
    c = 2 * zeta * math.sqrt(K1 * M1)
    s = system_from_matrices(
        [[M1]],
        [[c]],
        [[0.0]],
        iso_dofs=[0],
        influence=[1.0],
        isolation=Isolation(k_lam=K1, c=0.0, mu=0.0, law="none"),
    )
    F0, f = 500.0, 0.7
    W = 2 * math.pi * f
    b = W / W1
    if zeta == 0.0:  # the whole history from rest, phase 0
        res = simulate(s, HarmonicForce(F0, f, dofs=[0]), n_periods=5, rtol=1e-10, atol=1e-13)
        exact = F0 / K1 / (1 - b * b) * (np.sin(W * res.t) - b * np.sin(W1 * res.t))
        assert np.max(np.abs(res.x[:, 0] - exact)) < 1e-7 * np.max(np.abs(exact))
        return
    res = simulate(
        s, HarmonicForce(F0, f, dofs=[0], phase=phase), n_periods=60, rtol=1e-10, atol=1e-13
    )
    X = F0 / K1 / math.hypot(1 - b * b, 2 * zeta * b)
    delta = math.atan2(2 * zeta * b, 1 - b * b)
    late = res.t > res.t[-1] - 2 / f  # transient decayed: exp(-zeta w t) < 1e-9
    exact = X * np.sin(W * res.t[late] + phase - delta)
    assert np.max(np.abs(res.x[late, 0] - exact)) < 1e-6 * X


def three_storey(law="switch", mu=MU1):
    iso = Isolation(k_lam=2.0e5, c=2.0e4, mu=mu, law=law, eps=500.0)
    return shear_building(
        [2.0e4, 1.0e4, 1.0e4, 1.0e4], [2.0e7, 1.5e7, 1.0e7], 0.05, isolation=iso, heights=3.0
    )


def test_shear_building_toml_equals_python():
    cfg = load_scene(SCENES / "isolated-shear-3storey.toml")
    s_toml, _ = build_scene(cfg)
    s_py = three_storey(law="arctan")
    for a in ("M", "C", "K", "Gamma", "D"):
        np.testing.assert_array_equal(getattr(s_toml, a), getattr(s_py, a))
    np.testing.assert_array_equal(s_toml.normal_force, s_py.normal_force)
    assert s_toml.isolation == s_py.isolation
    # matrices of the builder: M = diag(m), K L-form, Gamma = 1, N = g sum(m)
    assert s_py.normal_force[0] == pytest.approx(G * 5.0e4, rel=1e-15)
    k = np.diag(s_py.K)  # k_lam + k1, k1 + k2, k2 + k3, k3
    np.testing.assert_allclose(k, [2.0e5 + 2.0e7, 3.5e7, 2.5e7, 1.0e7], rtol=1e-14)
    # classical damping: the fixed-base modes get exactly 5 %
    Kf, Cf, Mf = s_py.K[1:, 1:], s_py.C[1:, 1:], s_py.M[1:, 1:]
    w2, Phi = np.linalg.eigh(np.linalg.inv(np.sqrt(Mf)) @ Kf @ np.linalg.inv(np.sqrt(Mf)))
    Phi = np.linalg.inv(np.sqrt(Mf)) @ Phi
    np.testing.assert_allclose(np.diag(Phi.T @ Cf @ Phi) / (2 * np.sqrt(w2)), 0.05, rtol=1e-10)


def test_storey_heights_in_mm_are_noted():
    # heights = 3000 for 3 m ran without a word, its drift ratios 1000x too small
    iso = Isolation(k_lam=2.0e5, c=2.0e4, mu=MU1)
    with pytest.warns(NotedWarning, match=r"heights: a storey 3000 m high.* are they in mm\?"):
        shear_building([2e4, 1e4], [2e7], 0.05, isolation=iso, heights=3000.0)


@pytest.mark.slow  # ~30 s: the switch model at rtol 1e-10
def test_stuck_shear_building_is_the_linear_fixed_base_building():
    import control

    with pytest.warns(NotedWarning, match="isolation.mu = 10: a friction coefficient"):  # meant
        s = three_storey(law="switch", mu=10.0)  # friction never saturates: the base stuck
    dt = 0.01
    t = np.arange(0.0, 4.0 + dt / 2, dt)
    a = 2.0 * np.sin(2 * np.pi * 1.3 * t) * np.sin(np.pi * t / 4.0) ** 2
    res = simulate(s, Table(0.0, dt, a), rtol=1e-10, atol=1e-13)
    assert np.max(np.abs(res.x[:, 0])) < 1e-9  # isolator slip ~ 0
    Mf, Cf, Kf = s.M[1:, 1:], s.C[1:, 1:], s.K[1:, 1:]
    Mi = np.linalg.inv(Mf)
    A = np.block([[np.zeros((3, 3)), np.eye(3)], [-Mi @ Kf, -Mi @ Cf]])
    B = np.concatenate([np.zeros(3), -np.ones(3)])[:, None]
    sysc = control.ss(A, B, np.hstack([np.eye(3), np.zeros((3, 3))]), np.zeros((3, 1)))
    y = control.forced_response(sysc, T=t, U=a).outputs
    assert np.max(np.abs(res.x[:, 1:4] - y.T)) < 1e-6 * np.max(np.abs(y))


def test_harmonic_ground_with_phase_is_exact():
    # The kernel's harmonic channel carries the phase: a rigid mass on a stiff linear
    # isolator with u''(t) = A sin(W t + phase) vs the exact linear forced solution at t = 0.
    s = system_from_matrices(
        [[M1]],
        [[0.0]],
        [[0.0]],
        iso_dofs=[0],
        influence=[1.0],
        isolation=Isolation(k_lam=K1, c=0.0, mu=0.0, law="none"),
    )
    A, f, ph = 1.0, 0.4, 1.1
    res = simulate(s, Harmonic(A, f, phase=ph), n_periods=3, rtol=1e-10, atol=1e-13)
    W = 2 * math.pi * f
    Xp = -A / (W1**2 - W**2)  # particular solution Xp sin(W t + ph); homogeneous fixes x(0)=0
    t = res.t
    exact = Xp * (
        np.sin(W * t + ph) - np.sin(ph) * np.cos(W1 * t) - W / W1 * np.cos(ph) * np.sin(W1 * t)
    )
    assert np.max(np.abs(res.x[:, 0] - exact)) < 1e-7 * abs(Xp)


def test_contact_rows_give_normal_forces_from_the_dynamics():
    # A block (x slides, y on a contact) with the geometry given: the normal force is the
    # constraint multiplier, lam = m (g + u''_ver) exactly, and uplift is checked.
    from nsdyn.solve.integrate import UpliftError

    s = system_from_matrices(
        np.eye(2) * M1,
        np.zeros((2, 2)),
        np.zeros((2, 2)),
        iso_dofs=[0],
        influence=np.eye(2),
        contact_rows=[[0.0, 1.0]],
        isolation=Isolation(k_lam=K1, c=0.0, mu=MU1, law="arctan"),
    )
    _, lam0 = s.static_equilibrium()
    assert lam0[0] == pytest.approx(M1 * G, rel=1e-12)
    exc = Harmonic(1.0, 0.5, A_ver=3.0, f_ver=2.0)
    res = simulate(s, exc, n_periods=2, rtol=1e-9, atol=1e-12)
    lam_exact = M1 * (G + 3.0 * np.sin(2 * np.pi * 2.0 * res.t))
    assert np.max(np.abs(res.response.lam[:, 0] - lam_exact)) < 1e-6 * M1 * G
    with pytest.raises(UpliftError):
        simulate(s, Harmonic(2.0, 1.0, A_ver=12.0, f_ver=1.0), n_periods=1)


def test_a_ragged_matrix_and_a_one_storey_buildings_two_ratios_are_said_as_such():
    # numpy's "setting an array element with a sequence. The requested array has an
    # inhomogeneous shape ..." stood in the message; one storey has one fixed-base mode, so
    # two ratios are one too many (the message read as if a list were not allowed)
    from nsdyn.models.isolated.builders import MatrixError

    with pytest.raises(MatrixError, match=r"^M: expected a square matrix of numbers, got rows "
                       r"of 2, 1 entries$"):  # fmt: skip
        system_from_matrices([[1.0, 0.0], [0.0]], [[0.0, 0.0]] * 2, np.eye(2), iso_dofs=[0],
                             influence=[1, 1], weight=10.0, isolation=Isolation())  # fmt: skip
    with pytest.raises(MatrixError, match=r"one storey: one fixed-base mode"):
        shear_building([1e5, 1e5], [1e7], damping_ratios=[0.05, 0.05], isolation=Isolation())
