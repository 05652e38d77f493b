"""Shooting: Newton on the period map, its exact monodromy, Floquet multipliers.

References are independent of the code under test: python-control's frequency response of the
frictionless (linear) system, finite differences of the period map, the exact multipliers
exp(lambda T) of a linear oscillator (and Liouville's formula for their product), and Den
Hartog's closed-form steady state of a Coulomb + viscous oscillator.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from nsdyn import periodic as pr
from nsdyn.models.isolated.statespace import linear_statespace
from nsdyn.models.isolated.system import Isolation
from nsdyn.periodic.shooting import SHOOT_TOL, _weights


def _python_control_state(system, prob, A, f):
    """Steady state at t = 0 of u''_hor = A sin(w t) from python-control's H(jw) on z."""
    w = 2 * np.pi * f
    H = np.asarray(linear_statespace(system)(1j * w)).reshape(-1)  # q / u''_hor
    Hz = system.Q.T @ H
    x = prob.x_ref.copy()
    x[: prob.m] += A * Hz.imag
    x[prob.m :] += A * w * Hz.real
    return x, H


def test_linear_shooting_is_one_newton_step_to_python_control(linear_frame):
    # mu = 0: the period map is affine, so Newton converges in one step (to the map's round-off,
    # far below the shooting tolerance). The discrete solution converges to python-control's
    # steady state at the order of SDIRK2 (2, Alexander 1977): error ratio ~4 per halving of h.
    A, f = 1.0, 1.5
    prob = pr.frame_problem(linear_frame, A)
    x_ss, H = _python_control_state(linear_frame, prob, A, f)
    scale = np.abs(x_ss - prob.x_ref).max()
    errs = []
    for N in (100, 200, 400):
        res = pr.shoot(prob, f, n_steps=N)
        assert res.converged and res.iterations == 1, res.message
        errs.append(np.abs(res.x0 - x_ss).max() / scale)
    assert 3.0 < errs[0] / errs[1] < 5.0 and 3.0 < errs[1] / errs[2] < 5.0
    # discretisation tolerance at N = 200 (w h = 0.031): (w h)^2 / 10 = 1e-4
    assert errs[1] < 1e-4
    # the isolator amplitude on the orbit is |A H_iso(jw)| (half peak-to-peak of a sinusoid;
    # N = 200 samples per period bound the sampling error by (pi / N)^2 / 2 ~ 1.2e-4)
    res = pr.shoot(prob, f, n_steps=200)
    q = pr.orbit_quantities(prob, f, res.X)
    x_iso_ref = np.max(np.abs(A * (linear_frame.D @ H)))
    assert q["x_iso"] == pytest.approx(x_iso_ref, rel=3e-4)


def test_linear_frame_multipliers_are_exp_lambda_T(linear_frame):
    # Floquet multipliers of a linear time-invariant system are exp(lambda_i T) with lambda_i
    # the eigenvalues of its state matrix (python-control). The discrete map reproduces them
    # for the resolved modes (|lambda| h << 1); the kHz boundary modes are damped to ~0
    # (L-stability), so only multipliers with |rho| > 1e-3 are compared.
    f, N = 1.5, 400
    prob = pr.frame_problem(linear_frame, 1.0)
    res = pr.shoot(prob, f, n_steps=N)
    rho = res.multipliers
    lam = np.linalg.eigvals(linear_statespace(linear_frame).A)
    resolved = lam[np.abs(lam) * (1 / f) / N < 0.05]
    ref = np.exp(resolved / f)
    big = rho[np.abs(rho) > 1e-3]
    assert big.size == ref.size
    for m in ref:
        assert np.min(np.abs(big - m)) < 2e-3 * max(abs(m), 1e-2)


def test_monodromy_is_the_derivative_of_the_period_map(smooth_frame):
    # The discrete derivative (stage equations differentiated) against central differences of
    # the period map itself, in scaled variables W x. A central difference errs by C delta^2
    # (+ round-off / delta): the discrepancy must fall ~100x when delta falls 10x, which an
    # inexact monodromy (an O(1) discrepancy) cannot do, and be small at delta = 1e-5.
    # The differenced map is the one shooting iterates (with sensitivities: a fresh Jacobian
    # at every stage); the map without them lags its iteration matrix, so its end state
    # depends on how many stage iterations each step took, which a 1e-5 difference amplifies.
    f, N = 1.0, 100
    prob = pr.frame_problem(smooth_frame, 2.0)
    x0 = pr.warm_start(prob, f, None, pr.Discretisation(), periods=3)
    pm = pr.period_map(prob, x0, f, n_steps=N, store=True)
    assert pm.status == 0
    W = _weights(prob, pr.orbit_amplitudes(prob, pm.X))
    d = prob.dim
    Ms = W[:, None] * pm.monodromy / W[None, :]

    def fd_error(delta):
        fd = np.empty((d, d))
        for k in range(d):
            e = np.zeros(d)
            e[k] = delta / W[k]
            xa = pr.period_map(prob, x0 + e, f, n_steps=N, sens=True).xT
            xb = pr.period_map(prob, x0 - e, f, n_steps=N, sens=True).xT
            fd[:, k] = W * (xa - xb) / (2 * delta)
        return np.max(np.abs(Ms - fd)) / np.max(np.abs(fd))

    e4, e5 = fd_error(1e-4), fd_error(1e-5)
    assert e4 / e5 > 30.0
    assert e5 < 1e-4

    # d xT / d T against a central difference in the period (same test of the rate)
    def fdT_error(rel):
        dT = rel / f
        xa = pr.period_map(prob, x0, 1 / (1 / f + dT), n_steps=N, sens=True).xT
        xb = pr.period_map(prob, x0, 1 / (1 / f - dT), n_steps=N, sens=True).xT
        fdT = W * (xa - xb) / (2 * dT)
        return np.max(np.abs(W * pm.dxdT - fdT)) / np.max(np.abs(fdT))

    t4, t5 = fdT_error(1e-4), fdT_error(1e-5)
    assert t5 < 1e-4 and (t4 / t5 > 30.0 or t4 < 1e-6)


def test_shortened_line_search_trials_skip_the_monodromy(monkeypatch):
    # A shortened Newton step's trial period needs only its end state (the Armijo test), not
    # its monodromy: it runs without sensitivities, and the step accepted runs once more with
    # them, so the result carries the monodromy of the map at the state it returns. Duffing
    # (gamma = 1, F = 5, f = 0.2 Hz) from x0 = [0, 5] needs shortened steps. The monodromy
    # returned must equal that of a fresh period with sensitivities from the returned x0 bit
    # for bit (the same deterministic integration), the orbit its residual below tolerance.
    from nsdyn.periodic import problem as pp

    sens = []
    period_map = pp.PeriodicProblem.period_map

    def recorded(self, x0, f, **kw):
        sens.append(kw.get("sens", True))
        return period_map(self, x0, f, **kw)

    monkeypatch.setattr(pp.PeriodicProblem, "period_map", recorded)
    prob = pr.duffing_problem(0.05, 1.0, 1.0, 5.0)
    f = 0.2
    res = pr.shoot(prob, f, np.array([0.0, 5.0]))
    assert res.converged and res.residual <= SHOOT_TOL, res.message
    assert False in sens  # shortened trials ran, without sensitivities
    fresh = period_map(prob, res.x0, f, n_steps=res.n_steps, sens=True, store=True)
    assert np.array_equal(res.monodromy, fresh.monodromy)
    assert np.array_equal(res.X, fresh.X)


def test_floquet_multipliers_of_a_damped_oscillator():
    # x'' + 2 zeta w0 x' + w0^2 x = F cos(w t): multipliers exp(lambda T), lambda the roots of
    # s^2 + 2 zeta w0 s + w0^2 (independent of the forcing). SDIRK2 converges at order 2.
    zeta, w0 = 0.05, 1.0
    prob = pr.duffing_problem(zeta, w0, 0.0, 0.3)
    f = 1.3 / (2 * np.pi)
    T = 1 / f
    lam = np.roots([1.0, 2 * zeta * w0, w0**2])
    exact = np.exp(lam * T)
    errs = []
    for N in (128, 256, 512):
        res = pr.shoot(prob, f, n_steps=N)
        assert res.converged
        rho = res.multipliers
        errs.append(max(np.min(np.abs(rho - e)) for e in exact))
    assert errs[1] < 1e-4  # (w0 h)^2 / 10 at N = 256
    assert 3.0 < errs[0] / errs[1] < 5.0 and 3.0 < errs[1] / errs[2] < 5.0
    # a damped linear oscillator is stable
    assert res.multipliers.size == 2 and np.all(np.abs(res.multipliers) < 1)


# SDIRK2's stability function R(z) = e^z + C z^3 + O(z^4) has |C| <= 0.042 for |z| <= 0.02
# (Alexander 1977, gamma = 1 - 1/sqrt(2): C = -0.0408 on the real axis, -0.0404 on the imaginary
# axis), so N steps of h = T / N reproduce exp(lambda T) to a relative N |C| |lambda h|^3.
SDIRK2_ERROR_CONSTANT = 0.05  # bound on |C|, with margin
W0_H = 0.01  # largest w0 h of the property test


@settings(max_examples=20, deadline=None)
@given(
    zeta=st.floats(0.01, 0.9),
    w0=st.floats(0.5, 5.0),
    w0_T=st.floats(1.0, 20.0),
)
def test_damped_oscillator_multipliers_have_modulus_exp_minus_zeta_w0_T(zeta, w0, w0_T):
    # x'' + 2 zeta w0 x' + w0^2 x = F cos(w t), zeta < 1: the eigenvalues lambda = -zeta w0 +-
    # i w0 sqrt(1 - zeta^2) give multipliers exp(lambda T) of modulus exp(-zeta w0 T), and by
    # Liouville's formula det Phi = exp(trace(A) T) = exp(-2 zeta w0 T). The discrete map
    # (w0 h <= 0.01) agrees to N |C| (w0 h)^3 = |C| w0 T (w0 h)^2 (relative; twice for det).
    f = w0 / w0_T  # Hz: T = w0_T / w0
    T = 1.0 / f
    N = math.ceil(w0_T / W0_H)
    pm = pr.period_map(pr.duffing_problem(zeta, w0, 0.0, 1.0), np.zeros(2), f, n_steps=N)
    assert pm.status == 0
    rho = pr.floquet_multipliers(pm.monodromy)
    tol = SDIRK2_ERROR_CONSTANT * w0_T * (w0 * T / N) ** 2 + 1e-9
    modulus = math.exp(-zeta * w0 * T)
    assert np.allclose(np.abs(rho), modulus, rtol=tol, atol=0)
    assert np.linalg.det(pm.monodromy) == pytest.approx(modulus**2, rel=2 * tol)


@pytest.mark.parametrize("method, order", [("euler", 1), ("sdirk2", 2), ("sdirk3", 3)])
def test_tableaux_converge_at_their_order(method, order):
    # Multipliers of x'' + 2 zeta w0 x' + w0^2 x = 0 (exact: exp(lambda T)) at N and 2N steps
    # per period: the error ratio is 2^order (Alexander 1977 for the SDIRK tableaux).
    zeta, w0 = 0.05, 1.0
    prob = pr.duffing_problem(zeta, w0, 0.0, 0.0)
    f = 1.3 / (2 * np.pi)
    exact = np.exp(np.roots([1.0, 2 * zeta * w0, w0**2]) / f)
    errs = []
    for N in (64, 128, 256):
        disc = pr.Discretisation(method=method)
        pm = pr.period_map(prob, np.zeros(2), f, n_steps=N, disc=disc)
        rho = pr.floquet_multipliers(pm.monodromy)
        errs.append(max(np.min(np.abs(rho - e)) for e in exact))
    slope = np.polyfit(np.log([64, 128, 256]), np.log(errs), 1)[0]
    assert -slope == pytest.approx(order, abs=0.25)


def _den_hartog_amplitude(m, c, k, F, P, w):
    """Steady non-stop motion of m x'' + c x' + k x + F sgn(x') = P sin(w t + phi).

    Den Hartog (1931), "Forced vibrations with combined Coulomb and viscous friction", Trans.
    ASME 53, APM 107-115: the motion is symmetric (x(t + T/2) = -x(t)) with two reversals per
    period and no stop. On the half period with x' > 0, starting at the reversal x(0) = -X,
    x = e^(-s t)(C1 cos wd t + C2 sin wd t) + alpha cos w t + beta sin w t - F/k, where
    (alpha, beta) answer the forcing a cos w t + b sin w t. The four end conditions
    x(0) = -X, x'(0) = 0, x(T/2) = X, x'(T/2) = 0 are linear in (C1, C2, a, b, X, F), so
    (a, b) = X p + F r and a^2 + b^2 = P^2 is a quadratic in X. Returns (X, (C1, C2, a, b)).
    """
    wn = math.sqrt(k / m)
    z = c / (2 * m * wn)
    s, wd, h = z * wn, wn * math.sqrt(1 - z * z), math.pi / w
    Zi = np.linalg.inv(np.array([[k - m * w * w, c * w], [-c * w, k - m * w * w]]))
    e, ch, sh = math.exp(-s * h), math.cos(wd * h), math.sin(wd * h)
    # rows: x(0) = -X, x'(0) = 0, x(T/2) = X, x'(T/2) = 0 with alpha = Zi[0] @ (a, b),
    # beta = Zi[1] @ (a, b); columns C1, C2, a, b; right-hand sides per unit X and per unit F
    L = np.array(
        [
            [1.0, 0.0, *Zi[0]],
            [-s, wd, *(w * Zi[1])],
            [e * ch, e * sh, *(-Zi[0])],
            [e * (-s * ch - wd * sh), e * (-s * sh + wd * ch), *(-w * Zi[1])],
        ]
    )
    u_x = np.linalg.solve(L, [-1.0, 0.0, 1.0, 0.0])  # per unit X
    u_f = np.linalg.solve(L, [1.0 / k, 0.0, 1.0 / k, 0.0])  # per unit F
    p, r = u_x[2:], u_f[2:]
    qa, qb, qc = p @ p, 2 * F * (p @ r), F * F * (r @ r) - P * P
    X = (-qb + math.sqrt(qb * qb - 4 * qa * qc)) / (2 * qa)
    return X, X * u_x + F * u_f


def _coulomb_oscillator(m, c, k, mu, law, eps=7500.0):
    """Block on a contact (y) sliding along x: spring k, dashpot c, friction mu m g."""
    from nsdyn.models.isolated.system import IsolatedSystem

    return IsolatedSystem(
        "coulomb oscillator",
        "rigid",
        np.diag([m, m]),
        np.diag([c, 0.0]),
        np.diag([k, 0.0]),
        np.eye(2),
        np.array([[0.0, 1.0]]),
        np.array([[1.0, 0.0]]),
        np.eye(2),
        Isolation(k_lam=0.0, c=0.0, mu=mu, law=law, eps=eps),
    )


def test_switch_and_arctan_steady_states_approach_den_hartogs_solution():
    # Harmonic base excitation u'' = A sin(w t) of a Coulomb + viscous oscillator (load -m u'',
    # so P = m A). References: Den Hartog's closed-form non-stop steady state (derived in
    # _den_hartog_amplitude; for c = 0 it must equal his published formula
    # X k / P = sqrt(V^2 - (F/P)^2 U^2), V = 1/(1 - b^2), U = sin(pi/b) / (b (1 + cos(pi/b)))).
    m, wn, zeta, mu, A = 1.0, 2 * np.pi, 0.05, 0.3, 5.0
    k, c = m * wn**2, 2 * zeta * m * wn
    F, P0 = mu * m * 9.81, m * A
    for b in (0.7, 1.5, 2.0):
        V, U = 1 / (1 - b * b), math.sin(math.pi / b) / (b * (1 + math.cos(math.pi / b)))
        X0, _ = _den_hartog_amplitude(m, 0.0, k, F, P0, b * wn)
        assert X0 == pytest.approx(P0 / k * math.sqrt(V * V - (F / P0) ** 2 * U * U), rel=1e-12)
    from nsdyn import Harmonic
    from nsdyn.solve.integrate import solve

    for b in (0.7, 1.5):
        w = b * wn
        f, T = w / (2 * np.pi), 2 * np.pi / w
        X, (C1, C2, a, bb) = _den_hartog_amplitude(m, c, k, F, P0, w)
        # the closed form is valid: the velocity stays positive on the half period, and at the
        # reversal the spring and forcing (k X + a) overcome the friction (no stop)
        Zi = np.linalg.inv(np.array([[k - m * w * w, c * w], [-c * w, k - m * w * w]]))
        beta = Zi[1] @ [a, bb]
        s, wd = zeta * wn, wn * math.sqrt(1 - zeta**2)
        tt = np.linspace(0, T / 2, 2001)[1:-1]
        v = np.exp(-s * tt) * (
            (-s * C1 + wd * C2) * np.cos(wd * tt) + (-s * C2 - wd * C1) * np.sin(wd * tt)
        ) + w * (-(Zi[0] @ [a, bb]) * np.sin(w * tt) + beta * np.cos(w * tt))
        assert v.min() > 0 and k * X + a > F
        # Switch model (event-driven, true stick) from rest for 80 s: the transient has decayed
        # below exp(-zeta wn 80 s) ~ 1e-11 of X; steady reversals only (no stick event), and
        # the amplitude read at the reversal instants agrees with Den Hartog's X to 1e-9 (the
        # integration tolerance is rtol 1e-10, atol 1e-12 m on X ~ 0.05-0.2 m; the reversals
        # are located to 1e-12 s).
        n = math.ceil(80.0 / T)
        Ps = _coulomb_oscillator(m, c, k, mu, "switch").params(Harmonic(A, f), law="switch")
        kw = dict(method="event", rtol=1e-10, atol=1e-12)
        run = solve(Ps, np.zeros(4), [0.0, (n - 1) * T, n * T], **kw)
        last = [e for e in run.events if e[0] > (n - 1) * T]
        assert len(last) == 2 and sorted(e[2] for e in last) == [-1, 1]
        t_rev = [(n - 1) * T] + [e[0] for e in last] + [n * T]
        rev = solve(Ps, run.x[1], t_rev, **kw)
        x_rev = rev.q[1:3, 0]
        assert 0.5 * abs(x_rev[0] - x_rev[1]) == pytest.approx(X, rel=1e-9)
        # Arctan law, periodic solution by shooting (3200 steps per period resolve the law at
        # these eps): away from reversals it lacks 2F/(pi eps |v|) of the Coulomb force, so the
        # amplitude converges to X as eps grows, at least 3x per decade (theory: eps^-1 up to a
        # log factor, eps^-2/3 where a reversal nearly sticks), and within 1 % at eps = 1e4
        # (the seed's eps = 7500 is chosen to make the two laws indistinguishable, its Fig. 5).
        disc = pr.Discretisation(n_min=3200, dt_max=1e9)
        diff = []
        for eps in (1e2, 1e3, 1e4):
            prob = pr.frame_problem(_coulomb_oscillator(m, c, k, mu, "arctan", eps), A)
            res = pr.shoot(prob, f, pr.warm_start(prob, f, None, disc, periods=5), disc=disc)
            assert res.converged, res.message
            diff.append(abs(0.5 * np.ptp(res.X[:, 0]) - X) / X)
        assert diff[0] / diff[1] > 3 and diff[1] / diff[2] > 3
        assert diff[2] < 0.01
