"""Checks of the integrators in nsdyn.solve.integrate against closed-form solutions.

Reference problems:
- linear damped oscillator q'' + 2 zeta w q' + w^2 q = -A sin(W t), exact free + forced response
  (any vibrations text, e.g. Chopra, *Dynamics of Structures*, sec. 2.2 and 3.2);
- Coulomb oscillator m x'' + k x = -F sign(x'): half-cycles of length pi/w about +-F/k, turning
  amplitude dropping by 2F/k per half-cycle, rest at the first turning point with |x| <= F/k
  (Den Hartog, *Mechanical Vibrations*, sec. 8.2).
Orders are fitted log-log slopes (diffrax style), not pinned error values.
"""

import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

from nsdyn import Harmonic, Table
from nsdyn.models.isolated import _kernel as ks
from nsdyn.models.isolated.params import pack
from nsdyn.models.isolated.statespace import demo_frame
from nsdyn.models.isolated.system import Isolation, build_system
from nsdyn.solve.integrate import (
    METHODS,
    IntegrationError,
    UpliftError,
    UpliftWarning,
    solve,
    warmup,
)

G = 9.81

# ---- reference problems ---------------------------------------------------------------------

W0, ZETA = 2 * np.pi, 0.05  # 1 Hz, 5 % damping
A_G, W_G = 2.0, 2 * np.pi * 0.7  # ground acceleration amplitude [m/s^2], circular frequency


def oscillator(forced: bool):
    """P for q'' + 2 zeta w q' + w^2 q = -A sin(W t) (A = 0 when not forced), no contacts."""
    ground = Harmonic(A_G, W_G / (2 * np.pi)) if forced else None
    return pack(np.eye(1), [[2 * ZETA * W0]], [[W0**2]], [[1.0, 0.0]], g=0.0, ground=ground)


def oscillator_exact(t, q0, v0, forced: bool):
    """Exact q(t): forced particular solution a sin + b cos plus the damped free response."""
    t = np.asarray(t, dtype=float)
    wd = W0 * np.sqrt(1 - ZETA**2)
    a = b = 0.0
    if forced:
        den = (W0**2 - W_G**2) ** 2 + (2 * ZETA * W0 * W_G) ** 2
        a = -A_G * (W0**2 - W_G**2) / den
        b = A_G * 2 * ZETA * W0 * W_G / den
    c1 = q0 - b
    c2 = (v0 - a * W_G + ZETA * W0 * c1) / wd
    return (
        a * np.sin(W_G * t)
        + b * np.cos(W_G * t)
        + np.exp(-ZETA * W0 * t) * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))
    )


def slope(x, y):
    return np.polyfit(np.log(x), np.log(y), 1)[0]


# Coulomb oscillator: q = [x, y], contact y = 0 carries N = m g, isolator slides along x
M_C, MU_C = 2.0, 0.3
W_C = 2 * np.pi  # 1 Hz
K_C = M_C * W_C**2
F_C = MU_C * M_C * G  # friction force
XF = F_C / K_C  # F/k


def coulomb(law="switch", eps=7500.0, ground=None, k=K_C, m=M_C):
    return pack(
        np.eye(2) * m,
        np.zeros((2, 2)),
        np.diag([k, 0.0]),
        np.eye(2),
        R=[[0.0, 1.0]],
        D=[[1.0, 0.0]],
        mu=MU_C,
        lam_static=[m * G],
        law=law,
        eps=eps,
        g=G,
        ground=ground,
    )


@pytest.fixture(scope="module", autouse=True)
def compiled():
    # compile (or load) every kernel once so per-test timings exclude JIT
    return warmup()


# ---- convergence orders ---------------------------------------------------------------------


@pytest.mark.parametrize("method", ["dopri5", "radau"])
def test_fixed_step_order_is_five(method):
    # Dormand-Prince 5(4) and Radau IIA are both order 5 (Hairer-Norsett-Wanner I, II.5;
    # Hairer-Wanner II, IV.5). Free damped vibration, error at T (a step end), dt = 2^-k/10.
    P = oscillator(forced=False)
    x0 = np.array([1.0, 0.0])
    T = 2.0
    dts = 0.1 / 2.0 ** np.arange(4)
    err = []
    for dt in dts:
        # tight rtol/atol: with adaptive=False they only set radau's Newton tolerance
        sol = solve(P, x0, [0.0, T], method=method, dt=dt, adaptive=False, rtol=1e-13, atol=1e-15)
        assert sol.n_steps == round(T / dt)
        err.append(abs(sol.q[-1, 0] - oscillator_exact(T, 1.0, 0.0, False)))
    assert slope(dts, err) == pytest.approx(5.0, abs=0.5)


@pytest.mark.parametrize(
    "method,rho_inf,order",
    [
        ("genalpha", 0.8, 2),  # Chung & Hulbert (1993): second order for any rho_inf
        ("genalpha", 0.0, 2),
        ("hht", 0.6, 2),  # Hilber-Hughes-Taylor: second order
        ("newmark", 1.0, 2),  # average acceleration: second order
        ("newmark", 0.6, 1),  # gamma > 1/2: first order (Hughes, The FEM, sec. 9.1)
    ],
)
def test_generalized_alpha_family_order(method, rho_inf, order):
    P = oscillator(forced=True)
    q0, v0 = 0.01, -0.02
    t_out = np.linspace(0.0, 2.0, 11)  # on every step grid below
    dts = 0.02 / 2.0 ** np.arange(4)
    err = []
    for dt in dts:
        sol = solve(P, [q0, v0], t_out, method=method, dt=dt, rho_inf=rho_inf)
        err.append(np.max(np.abs(sol.q[:, 0] - oscillator_exact(t_out, q0, v0, True))))
    assert slope(dts, err) == pytest.approx(order, abs=0.25)


@pytest.mark.parametrize("method", ["dopri5", "radau"])
def test_adaptive_error_follows_tolerance(method):
    # Per-step error control with an embedded estimator of order p_hat gives steps
    # h ~ tol^(1/(p_hat+1)) and a global error ~ tol^(p/(p_hat+1)): p/(p_hat+1) = 5/5 for
    # dopri5 and 5/4 for radau (embedded order 3). Band [0.75, 1.5] for the fitted slope.
    P = oscillator(forced=True)
    q0, v0 = 0.0, 0.05
    t = np.linspace(0.0, 3.0, 61)
    exact = oscillator_exact(t, q0, v0, True)
    amp = np.max(np.abs(exact))
    tols = np.array([1e-5, 1e-7, 1e-9])
    err = []
    for rtol in tols:
        sol = solve(P, [q0, v0], t, method=method, rtol=rtol, atol=rtol * amp)
        assert sol.success
        e = np.max(np.abs(sol.q[:, 0] - exact))
        # global error within a modest multiple of the tolerance (scipy's test criterion)
        assert e < 50 * rtol * amp
        err.append(e)
    assert np.all(np.diff(err) < 0)
    assert 0.75 <= slope(tols, err) <= 1.5


@pytest.mark.parametrize("method", ["dopri5", "radau"])
def test_outputs_come_from_dense_output_not_shorter_steps(method):
    # The output grid must not change the steps taken: same n_steps and, at shared times,
    # the same states (to round-off) for a coarse and a fine t_eval.
    P = oscillator(forced=True)
    coarse = np.linspace(0.0, 3.0, 4)
    fine = np.linspace(0.0, 3.0, 301)
    a = solve(P, [0.0, 0.05], coarse, method=method)
    b = solve(P, [0.0, 0.05], fine, method=method)
    assert a.n_steps == b.n_steps
    assert np.allclose(a.x, b.x[::100], rtol=0, atol=1e-14)
    # between steps the interpolant keeps the method's accuracy class (tolerance-scale error)
    exact = oscillator_exact(fine, 0.0, 0.05, True)
    assert np.max(np.abs(b.q[:, 0] - exact)) < 1e-3 * np.max(np.abs(exact))


# ---- event-driven switch model --------------------------------------------------------------


def coulomb_free_decay_exact(t, x0):
    """Piecewise closed form of the free Coulomb oscillator released from rest at x0 > F/k."""
    x = np.empty_like(t)
    v = np.empty_like(t)
    turns = []  # (time, position) of turning points
    amp, s, t0 = x0, -1.0, 0.0  # first slip towards -x: centre at -s F/k = +F/k
    while True:
        c = -s * XF  # centre of this half-cycle
        t1 = t0 + np.pi / W_C
        sel = (t >= t0) & (t <= t1)
        x[sel] = c + (amp - c) * np.cos(W_C * (t[sel] - t0))
        v[sel] = -(amp - c) * W_C * np.sin(W_C * (t[sel] - t0))
        amp = 2 * c - amp
        turns.append((t1, amp))
        t0, s = t1, -s
        if abs(amp) <= XF:
            sel = t > t1
            x[sel] = amp
            v[sel] = 0.0
            return x, v, turns


def test_event_switch_coulomb_free_decay():
    P = coulomb("switch")
    x0 = 10.3 * XF
    t = np.linspace(0.0, 4.0, 401)
    sol = solve(P, [x0, 0.0, 0.0, 0.0], t, method="event", rtol=1e-10, atol=1e-12)
    x_ex, v_ex, turns = coulomb_free_decay_exact(t, x0)
    # five half-cycles (10.3 -> 8.3 -> 6.3 -> 4.3 -> 2.3 -> 0.3 F/k), the last ends in stick
    assert len(turns) == 5
    times = [e[0] for e in sol.events]
    modes = [e[2] for e in sol.events]
    assert [e[1] for e in sol.events] == [0] * 5
    assert modes == [1, -1, 1, -1, 0]
    assert np.allclose(times, [tt for tt, _ in turns], rtol=0, atol=1e-8)
    # rest position -0.3 F/k to 1e-10 m, and it stays stuck (no creep)
    rest = turns[-1][1]
    assert rest == pytest.approx(-0.3 * XF, rel=1e-12)
    after = t > turns[-1][0] + 1e-6
    assert np.max(np.abs(sol.q[after, 0] - rest)) < 1e-10
    assert np.max(np.abs(sol.qd[after, 0])) < 1e-9
    # whole trajectory and the contact: y = 0, normal force m g
    assert np.max(np.abs(sol.q[:, 0] - x_ex)) < 1e-8
    assert np.max(np.abs(sol.q[:, 1])) < 1e-12


def test_event_switch_reversal_versus_stick_uses_stick_force():
    # Released from rest inside the stick band |x0| <= F/k the block never moves; just
    # outside it slides once and stops after a single half-cycle at 2F/k - x0.
    P = coulomb("switch")
    t = np.linspace(0.0, 2.0, 21)
    s_in = solve(P, [0.9 * XF, 0, 0, 0], t, method="event", rtol=1e-10, atol=1e-12)
    assert s_in.events == [] and np.max(np.abs(s_in.q[:, 0] - 0.9 * XF)) < 1e-12
    s_out = solve(P, [1.5 * XF, 0, 0, 0], t, method="event", rtol=1e-10, atol=1e-12)
    assert [e[2] for e in s_out.events] == [0]
    assert s_out.events[0][0] == pytest.approx(np.pi / W_C, abs=1e-8)
    assert s_out.q[-1, 0] == pytest.approx(0.5 * XF, abs=1e-10)


def test_event_run_continues_across_chunks():
    # Chunked runs (as the transient driver does) continue with the final modes and step of
    # the previous chunk and reproduce the single run.
    P = coulomb("switch")
    x0 = [10.3 * XF, 0.0, 0.0, 0.0]
    t = np.linspace(0.0, 4.0, 401)
    kw = dict(method="event", rtol=1e-10, atol=1e-12)
    full = solve(P, x0, t, **kw)
    a = solve(P, x0, t[:141], **kw)
    b = solve(P, a.x[-1], t[140:], modes0=a.modes, h0=a.h_last, **kw)
    assert [e[2] for e in a.events + b.events] == [e[2] for e in full.events]
    assert np.max(np.abs(b.q[:, 0] - full.q[140:, 0])) < 1e-8


def test_arctan_approaches_event_switch_as_eps_grows():
    # Forced stick-slip. The arctan law differs from Coulomb friction by the creep in stick
    # (v ~ 1/eps) and by a boundary layer at break-away: with the load ratio r = 1 + c t the
    # arctan slip lags in a time ~ eps^(-1/3) and leaves a velocity deficit ~ eps^(-2/3) that
    # the following slip integrates. The difference must shrink monotonically, with a
    # log-log slope in [-0.85, -0.5] (theory: -2/3), and be < 1 % of the motion at eps = 1e5.
    ground = Harmonic(5.0, 1.0)
    k = (2 * np.pi * 0.4) ** 2
    t = np.linspace(0.0, 4.0, 401)
    x0 = np.zeros(4)
    ev = solve(
        coulomb("switch", ground=ground, k=k, m=1.0), x0, t, method="event", rtol=1e-9, atol=1e-11
    )
    assert sum(1 for e in ev.events if e[2] == 0) >= 3  # genuine stick phases
    epss = np.array([1e2, 1e3, 1e4, 1e5])
    diff = []
    for eps in epss:
        a = solve(
            coulomb("arctan", eps, ground, k=k, m=1.0), x0, t, method="radau", rtol=1e-9, atol=1e-11
        )
        diff.append(np.max(np.abs(a.q[:, 0] - ev.q[:, 0])))
    assert np.all(np.diff(diff) < 0)
    assert -0.85 <= slope(epss, diff) <= -0.5
    assert diff[-1] < 0.01 * np.max(np.abs(ev.q[:, 0]))


# ---- stability and failure reporting -------------------------------------------------------


@pytest.mark.parametrize("method,rho", [("hht", 0.6), ("genalpha", 0.5)])
def test_high_frequency_dissipation_is_rho_inf(method, rho):
    # Unconditional stability with controllable dissipation: for w dt >> 1 the amplification
    # matrix has spectral radius rho_inf (Chung & Hulbert 1993, eq. 25; HHT 1977), so an
    # undamped mode at w dt = 1e4 decays like rho_inf^N (times a polynomial in N: the limit
    # matrix has a repeated eigenvalue) instead of blowing up. Fitted decay per step within
    # 10 % of rho_inf.
    w = 1e5
    P = pack(np.eye(1), [[0.0]], [[w * w]], [[1.0, 0.0]], g=0.0)
    dt, N = 0.1, 40
    sol = solve(P, [1.0, 0.0], np.arange(N + 1) * dt, method=method, dt=dt, rho_inf=rho)
    q = np.abs(sol.q[:, 0])
    assert np.all(np.isfinite(q)) and np.all(q[1:] < 1.0)
    k = np.arange(N // 2, N + 1)
    rate = np.exp(np.polyfit(k, np.log(q[k]), 1)[0])
    assert rate == pytest.approx(rho, rel=0.1)


def test_dopri5_reports_stiffness_instead_of_grinding():
    P = coulomb("arctan", eps=1e6, ground=Harmonic(5.0, 1.0))
    t = np.linspace(0.0, 1.0, 11)
    sol = solve(P, np.zeros(4), t, method="dopri5", max_steps=2000, on_failure="return")
    assert not sol.success and sol.status < 0
    assert "max_steps" in sol.message and "'radau'" in sol.message
    assert sol.t.size < t.size and sol.x.shape == (sol.t.size, 4)
    with pytest.raises(IntegrationError) as info:
        solve(P, np.zeros(4), t, method="dopri5", max_steps=2000)
    assert info.value.reason == "max_steps"
    assert 0.0 < info.value.t < 1.0
    # and radau handles the same problem
    assert solve(P, np.zeros(4), t, method="radau").success


def test_fixed_step_newton_failure_is_reported():
    # The switch law decides stick/slip inside the right-hand side: the fixed-step residual is
    # discontinuous and Newton cycles between the branches. It must stop and say so with t,
    # dt and advice, not return garbage. (With the smooth arctan law, even eps = 1e6 and
    # dt = 0.2 converge thanks to the line search: the arctan friction is monotone.)
    P = coulomb("switch", ground=Harmonic(5.0, 1.0))
    with pytest.raises(IntegrationError) as info:
        solve(P, np.zeros(4), np.linspace(0.0, 2.0, 5), method="genalpha", dt=0.05)
    e = info.value
    assert e.reason == "newton_divergence" and 0.0 < e.t < 2.0
    assert "dt = 0.05" in str(e) and "smaller dt" in str(e) and "'event'" in str(e)
    sol = solve(
        coulomb("arctan", eps=1e6, ground=Harmonic(5.0, 1.0)),
        np.zeros(4),
        np.linspace(0.0, 2.0, 5),
        method="genalpha",
        dt=0.2,
    )
    assert sol.success


@pytest.mark.parametrize("method", ["radau", "dopri5", "genalpha", "event"])
def test_nan_in_ground_record_is_reported(method):
    tab = Table(0.0, 0.01, np.full(201, 1.0))  # (Table refuses NaN samples: written after)
    tab.a_hor[100:] = np.nan  # record corrupt from t = 1 s
    P = coulomb("arctan" if method != "event" else "switch", eps=100.0, ground=tab)
    kw = {"dt": 1e-3} if method == "genalpha" else {}
    sol = solve(P, np.zeros(4), np.linspace(0, 2, 21), method=method, on_failure="return", **kw)
    assert not sol.success
    assert "NaN" in sol.message
    assert 0.9 <= sol.t[-1] <= 1.0


def test_uplift_of_a_rocking_block():
    # Rigid superstructure on two contacts 8 m apart with high friction: a strong horizontal
    # ground motion overturns it about one edge before the isolators can slide. The inertial
    # load -M a_g points to -x first (a_g = A sin), so the block tips about the left contact
    # and the right one (index 1) lifts.
    s = build_system(demo_frame(), Isolation(mu=0.8, eps=1000.0), fidelity="rigid")
    x0, lam0 = s.static_equilibrium()
    P = s.params(Harmonic(6.0, 1.0))
    t = np.linspace(0.0, 1.0, 101)
    with pytest.raises(UpliftError) as info:
        solve(P, x0, t)
    e = info.value
    assert e.contact == 1 and 0.0 < e.t < 0.5
    assert "contact 1" in str(e)
    with pytest.warns(UpliftWarning):
        sol = solve(P, x0, t, uplift="warn")
    assert sol.success and sol.t[-1] == t[-1]
    assert sol.uplift[0] == (pytest.approx(e.t, abs=1e-12), 1)
    # at the reported instant the normal force of contact 1 is ~0 (linear interpolation
    # between step ends: within 2 % of the static value)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UpliftWarning)
        fine = solve(P, x0, [0.0, e.t], uplift="warn")
    ev = s.evaluate(e.t, fine.x[-1], P=P)
    assert abs(ev["lam"][1]) < 0.02 * lam0[1]


def test_a_fixed_step_uplift_says_to_confirm_it_at_half_the_step():
    # the block above lifts off whatever the method; a fixed step's stop may also come from a
    # step that does not resolve the response (the full office frame at dt = 0.2 s stopped at an
    # "uplift" that dt = 0.02 s does not have), so its message says how to tell them apart
    s = build_system(demo_frame(), Isolation(mu=0.8, eps=1000.0), fidelity="rigid")
    x0, _ = s.static_equilibrium()
    P = s.params(Harmonic(6.0, 1.0))
    t = np.linspace(0.0, 1.0, 101)
    with pytest.raises(UpliftError, match=r"A fixed step of 0.001 s that does not resolve the "
                                          r"response can also dip a normal force to zero: "
                                          r"confirm the uplift at half the step"):  # fmt: skip
        solve(P, x0, t, method="genalpha", dt=1e-3)
    with pytest.raises(UpliftError) as info:
        solve(P, x0, t)  # adaptive: no such note
    assert "fixed step" not in str(info.value)


def test_an_explicit_uplift_says_it_may_be_a_step_past_its_stability_limit():
    # Baumgarte gains alpha = 1e6 /s: dopri5's steps (h < 3.3 / alpha) broke down at 1.4e-4 s
    # as "uplift ... reduce the excitation", under a record that lifts nothing (radau: none)
    from nsdyn.ground import read_motion
    from nsdyn.solve.transient import simulate

    s = build_system(demo_frame(), Isolation(alpha=1e6, beta=0.0), fidelity="rigid")
    rec = read_motion("synthetic-wn-40s").scaled_to_pga(3.0).window(0.0, 0.5)
    with pytest.raises(UpliftError, match=r"An explicit step past its stability limit \(a "
                       r"stiff model, or large Baumgarte gains alpha, beta\) can also dip a "
                       r"normal force to zero: confirm the uplift with 'radau'$"):  # fmt: skip
        simulate(s, rec, method="dopri5")
    assert simulate(s, rec, method="radau").response.min_normal_force > 0.0


def test_invalid_arguments_are_rejected():
    P = oscillator(forced=False)
    with pytest.raises(ValueError, match="method"):
        solve(P, [1.0, 0.0], [0.0, 1.0], method="euler")
    with pytest.raises(ValueError, match="dt"):
        solve(P, [1.0, 0.0], [0.0, 1.0], method="genalpha")
    with pytest.raises(ValueError, match="x0"):
        solve(P, [1.0, 0.0, 0.0], [0.0, 1.0])
    with pytest.raises(ValueError, match="t_eval"):
        solve(P, [1.0, 0.0], [1.0, 0.0])
    Pc = coulomb("arctan", eps=100.0, ground=Harmonic(1.0, 1.0))
    with pytest.raises(ValueError, match="atol"):
        solve(Pc, np.zeros(4), [0.0, 1.0], atol=[1e-8, 1e-8, 1e-8])
    # a (displacement, velocity) pair is the per-component array
    a = solve(Pc, np.zeros(4), [0.0, 1.0], atol=(1e-8, 1e-5))
    b = solve(Pc, np.zeros(4), [0.0, 1.0], atol=[1e-8, 1e-8, 1e-5, 1e-5])
    assert np.array_equal(a.x, b.x)


def test_warmup_and_timing_bookkeeping():
    out = warmup()
    assert set(out) == {m.kernel for m in METHODS.values()}
    assert all(v == 0.0 for v in out.values())  # already compiled by the fixture
    sol = solve(oscillator(False), [1.0, 0.0], np.linspace(0, 1, 11))
    assert sol.compile_s == 0.0 and sol.wall_s > 0.0
    assert sol.method == "radau" and sol.nfev > 0 and sol.njev >= 1 and sol.n_lu >= 2


def test_demo_frame_radau_matches_scipy_radau():
    # The same algorithm (Radau IIA, scipy's step logic) on the stiff Craig-Bampton frame with
    # the arctan law: agreement within the tolerance scale, with 10x fewer wall seconds.
    from scipy.integrate import solve_ivp

    s = build_system(demo_frame(), Isolation(), fidelity="cb")
    P = s.params(Harmonic(1.0, 1.0))
    x0, _ = s.static_equilibrium()
    t = np.linspace(0.0, 2.0, 201)
    sol = solve(P, x0, t, rtol=1e-6, atol=1e-8)

    def f(tt, x):
        out = np.empty_like(x)
        ks.rhs(tt, x, P, out)
        return out

    def jac(tt, x):
        J = np.empty((x.size, x.size))
        ks.jac(tt, x, P, J)
        return J

    ref = solve_ivp(f, (0, 2), x0, "Radau", t_eval=t, jac=jac, rtol=1e-8, atol=1e-10)
    x_iso = ref.y[0]
    assert np.max(np.abs(sol.q[:, 0] - x_iso)) < 1e-4 * np.max(np.abs(x_iso))


def test_kernels_run_without_jit():
    # Every kernel must also run as plain Python (NUMBA_DISABLE_JIT=1) on a tiny system.
    code = (
        "import numpy as np\n"
        "from nsdyn.solve.integrate import solve, METHODS, _tiny_problem\n"
        "P, x0 = _tiny_problem()\n"
        "for m in METHODS:\n"
        "    kw = {'dt': 1e-2} if METHODS[m].fixed_step else {}\n"
        "    s = solve(P, x0, np.linspace(0, 0.2, 3), method=m, **kw)\n"
        "    assert s.success, (m, s.message)\n"
        "print('ok')\n"
    )
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    env = dict(os.environ, NUMBA_DISABLE_JIT="1", PYTHONPATH=root)
    r = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120
    )
    assert r.returncode == 0, r.stderr[-2000:]
    assert r.stdout.strip().endswith("ok")


def test_radau_eigenvalues_are_those_of_the_inverse_coefficient_matrix():
    # Radau IIA order 5 coefficients (Hairer & Wanner II, table IV.5.6); the eigen-split of
    # the Newton matrices uses the eigenvalues of A^-1: one real, one complex pair.
    from nsdyn.solve import _kradau

    s6 = np.sqrt(6.0)
    A = np.array(
        [
            [(88 - 7 * s6) / 360, (296 - 169 * s6) / 1800, (-2 + 3 * s6) / 225],
            [(296 + 169 * s6) / 1800, (88 + 7 * s6) / 360, (-2 - 3 * s6) / 225],
            [(16 - s6) / 36, (16 + s6) / 36, 1 / 9],
        ]
    )
    eig = np.linalg.eigvals(np.linalg.inv(A))
    assert np.min(np.abs(eig - _kradau.EIG_REAL)) < 1e-12
    assert np.min(np.abs(eig - _kradau.EIG_COMPLEX)) < 1e-12
    assert np.allclose(A @ np.ones(3), _kradau.C, rtol=0, atol=1e-15)  # row sums = nodes


def test_stale_cache_guard_covers_every_kernel_module():
    # The guard fingerprints the kernel sources: every numba module here must be listed.
    from pathlib import Path

    from nsdyn.solve import _kcommon

    here = Path(_kcommon.__file__).parent
    assert set(_kcommon.KERNEL_MODULES) == {p.stem for p in here.glob("_k*.py")}
