"""Periodic solutions: shooting, monodromy, Floquet multipliers, continuation, fallback.

References are independent of the code under test: python-control's frequency response of the
frictionless (linear) system, finite differences of the period map, the exact multipliers
exp(lambda T) of a linear oscillator, and first-order harmonic balance of the Duffing equation.
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from nsdyn import _kperiodic as kp
from nsdyn import _ksystem as ks
from nsdyn import periodic as pr
from nsdyn.models import demo_frame, linear_statespace
from nsdyn.system import Isolation, build_system


@pytest.fixture(scope="module")
def frame():
    return demo_frame()


@pytest.fixture(scope="module")
def linear_frame(frame):
    return build_system(frame, Isolation(mu=0.0, law="none"), fidelity="cb")


@pytest.fixture(scope="module")
def smooth_frame(frame):
    # a soft arctan law (eps = 50 s/m) keeps the period map smooth enough for finite differences
    return build_system(frame, Isolation(mu=0.1, eps=50.0), fidelity="cb")


def _python_control_state(system, prob, A, f):
    """Steady state at t = 0 of u''_hor = A sin(w t) from python-control's H(jw) on z."""
    w = 2 * np.pi * f
    H = np.asarray(linear_statespace(system)(1j * w)).reshape(-1)  # q / u''_hor
    Hz = system.Q.T @ H
    x = prob.x_ref.copy()
    x[: prob.m] += A * Hz.imag
    x[prob.m :] += A * w * Hz.real
    return x, H


@pytest.mark.parametrize(
    "iso",
    [
        Isolation(mu=0.1, eps=50.0),
        Isolation(),
        Isolation(frozen_normal=True),
        Isolation(mu=0.0, law="none"),
    ],
    ids=["arctan-soft", "arctan", "arctan-frozen", "none"],
)
def test_manifold_rhs_and_jacobian_equal_the_projected_constrained_kernel(frame, iso):
    # The shooting right-hand side (seed eq 27 with precomputed products) against the
    # constrained kernel (Lagrange multipliers, Baumgarte) evaluated at q = Q z and projected:
    # zdd = Q^T qdd, J_z = blockdiag(Q^T) J blockdiag(Q). Same equations: round-off agreement.
    s = build_system(frame, iso, fidelity="cb")
    prob = pr.frame_problem(s, 0.7)
    P, pf = prob.at(0.46)
    Q, m, n, d = s.Q, prob.m, s.n, prob.dim
    rng = np.random.default_rng(3)
    for _ in range(3):
        x = prob.x_ref + 1e-3 * rng.standard_normal(d)
        xf = np.concatenate([Q @ x[:m], Q @ x[m:]])
        of = np.empty(2 * n)
        Jf = np.empty((2 * n, 2 * n))
        ks.rhs(0.3, xf, P, of)
        ks.jac(0.3, xf, P, Jf)
        F_ref = np.concatenate([x[m:], Q.T @ of[n:]])
        B = np.zeros((2 * n, d))
        B[:n, :m] = Q
        B[n:, m:] = Q
        J_ref = B.T @ Jf @ B
        F = np.empty(d)
        J = np.empty((d, d))
        assert kp.j_eval(prob.prob, 0.3, x, P, prob.Z, pf, F, J)
        assert np.max(np.abs(F - F_ref)) < 1e-12 * np.max(np.abs(F_ref))
        assert np.max(np.abs(J - J_ref)) < 1e-12 * np.max(np.abs(J_ref))


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
    # (L-stability), so only multipliers with |mu| > 1e-3 are compared.
    f, N = 1.5, 400
    prob = pr.frame_problem(linear_frame, 1.0)
    res = pr.shoot(prob, f, n_steps=N)
    mu = res.multipliers
    lam = np.linalg.eigvals(linear_statespace(linear_frame).A)
    resolved = lam[np.abs(lam) * (1 / f) / N < 0.05]
    ref = np.exp(resolved / f)
    big = mu[np.abs(mu) > 1e-3]
    assert big.size == ref.size
    for m in ref:
        assert np.min(np.abs(big - m)) < 2e-3 * max(abs(m), 1e-2)


def test_monodromy_is_the_derivative_of_the_period_map(smooth_frame):
    # The discrete derivative (stage equations differentiated) against central differences of
    # the period map itself, in scaled variables W x. A central difference errs by C delta^2
    # (+ round-off / delta): the discrepancy must fall ~100x when delta falls 10x, which an
    # inexact monodromy (an O(1) discrepancy) cannot do, and be small at delta = 1e-5.
    f, N = 1.0, 100
    prob = pr.frame_problem(smooth_frame, 2.0)
    x0 = pr.warm_start(prob, f, None, pr.Discretisation(), periods=3)
    pm = pr.period_map(prob, x0, f, n_steps=N, store=True)
    assert pm.status == 0
    W = pr._weights(prob, pr.orbit_amplitudes(prob, pm.X))
    d = prob.dim
    Ms = W[:, None] * pm.monodromy / W[None, :]

    def fd_error(delta):
        fd = np.empty((d, d))
        for k in range(d):
            e = np.zeros(d)
            e[k] = delta / W[k]
            xa = pr.period_map(prob, x0 + e, f, n_steps=N, sens=False).xT
            xb = pr.period_map(prob, x0 - e, f, n_steps=N, sens=False).xT
            fd[:, k] = W * (xa - xb) / (2 * delta)
        return np.max(np.abs(Ms - fd)) / np.max(np.abs(fd))

    e4, e5 = fd_error(1e-4), fd_error(1e-5)
    assert e4 / e5 > 30.0
    assert e5 < 1e-4

    # d xT / d T against a central difference in the period (same test of the rate)
    def fdT_error(rel):
        dT = rel / f
        xa = pr.period_map(prob, x0, 1 / (1 / f + dT), n_steps=N, sens=False).xT
        xb = pr.period_map(prob, x0, 1 / (1 / f - dT), n_steps=N, sens=False).xT
        fdT = W * (xa - xb) / (2 * dT)
        return np.max(np.abs(W * pm.dxdT - fdT)) / np.max(np.abs(fdT))

    t4, t5 = fdT_error(1e-4), fdT_error(1e-5)
    assert t5 < 1e-4 and (t4 / t5 > 30.0 or t4 < 1e-6)


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
        mu = res.multipliers
        errs.append(max(np.min(np.abs(mu - e)) for e in exact))
    assert errs[1] < 1e-4  # (w0 h)^2 / 10 at N = 256
    assert 3.0 < errs[0] / errs[1] < 5.0 and 3.0 < errs[1] / errs[2] < 5.0
    # a damped linear oscillator is stable
    assert res.multipliers.size == 2 and np.all(np.abs(res.multipliers) < 1)


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
        mu = pr.floquet_multipliers(pm.monodromy)
        errs.append(max(np.min(np.abs(mu - e)) for e in exact))
    slope = np.polyfit(np.log([64, 128, 256]), np.log(errs), 1)[0]
    assert -slope == pytest.approx(order, abs=0.25)


def _harmonic_balance_folds(w0, zeta, gamma, F):
    """Fold points of x'' + 2 zeta w0 x' + w0^2 x + gamma x^3 = F cos(w t), first-order HB.

    x = a cos(w t + phi) gives (Nayfeh & Mook 1979, §4.1)
        G(u, w) = [(k + 3 gamma u / 4)^2 + d^2] u - F^2 = 0,  u = a^2, k = w0^2 - w^2,
        d = 2 zeta w0 w.
    A fold is a double root in u: dG/du = (k + 3 gamma u/4)^2 + d^2 + (3 gamma u/2)(k + 3 gamma
    u/4) = 0. With G = 0 this gives e := k + 3 gamma u / 4 = -2 F^2 / (3 gamma u^2), hence
        w^2 = w0^2 + 3 gamma u / 4 - e,   and   (2 zeta w0 w)^2 = F^2 / u - e^2,
    one equation in u whose roots are the two folds. Returns [(w, a), ...].
    """

    def e(u):
        return -2 * F**2 / (3 * gamma * u**2)

    def w2(u):
        return w0**2 + 0.75 * gamma * u - e(u)

    def g(u):
        return 4 * zeta**2 * w0**2 * w2(u) - (F**2 / u - e(u) ** 2)

    us = np.geomspace(1e-3, 10.0, 4000)
    gv = np.array([g(u) for u in us])
    roots = [brentq(g, us[i], us[i + 1]) for i in np.flatnonzero(np.diff(np.sign(gv)))]
    return [(math.sqrt(w2(u)), math.sqrt(u)) for u in roots]


def test_arclength_passes_the_duffing_folds():
    # Hardening Duffing, weakly nonlinear (gamma a^2 ~ 0.3: the third harmonic is ~1 % of the
    # fundamental, so first-order harmonic balance is accurate to ~1 %). Pseudo-arclength must
    # turn at both folds (sequential continuation cannot), the folds must show as a real
    # multiplier through +1, and the middle branch must be unstable.
    w0, zeta, gamma, F = 1.0, 0.02, 0.3, 0.045
    folds = _harmonic_balance_folds(w0, zeta, gamma, F)
    assert len(folds) == 2
    prob = pr.duffing_problem(zeta, w0, gamma, F)
    disc = pr.Discretisation(n_min=256, dt_max=1e9)
    c = pr.continue_arclength(prob, 0.9 / (2 * np.pi), 1.25 / (2 * np.pi), points=40, disc=disc)
    w = 2 * np.pi * c.column("f")
    assert w[-1] == pytest.approx(1.25, rel=1e-9)
    turns = sorted(2 * np.pi * b["f"] for b in c.bifurcations if b["by"] == "turning point")
    by_mu = sorted(2 * np.pi * b["f"] for b in c.bifurcations if b["by"] == "multipliers")
    ref = sorted(wf for wf, _ in folds)
    assert len(turns) == 2 and len(by_mu) == 2
    for wt, wm, wr in zip(turns, by_mu, ref, strict=True):
        assert wt == pytest.approx(wr, rel=0.01)
        assert wm == pytest.approx(wr, rel=0.02)  # linear interpolation of mu across a fold
    # unstable points lie on the middle branch (between the folds in w)
    unstable = [p for p in c.points if p.stable is False]
    assert unstable
    for p in unstable:
        assert ref[0] * 0.99 <= 2 * np.pi * p.f <= ref[1] * 1.01
    # backbone: at the largest amplitude, w^2 = w0^2 + (3/4) gamma a^2 (within 1 %)
    amp = c.column("amp")
    k = int(np.argmax(amp))
    assert w[k] ** 2 == pytest.approx(w0**2 + 0.75 * gamma * amp[k] ** 2, rel=0.01)


def test_fallback_sweep_is_used_and_recorded_when_shooting_fails(smooth_frame):
    # Shooting is made to fail (no Newton iterations allowed): every point must come from the
    # stepped sweep, say why, and agree with the shooting solution (reference run) to the
    # steady-state tolerance.
    A = 2.0
    freqs = [1.0, 1.6]
    prob = pr.frame_problem(smooth_frame, A)
    ref = pr.continue_sequential(prob, freqs)
    assert all(p.method == "shooting" for p in ref.points)
    c = pr.continue_sequential(prob, freqs, max_iter=0)
    assert [p.method for p in c.points] == ["sweep", "sweep"]
    for p, r in zip(c.points, ref.points, strict=True):
        assert p.converged  # the steady-state test passed
        assert "no convergence in 0 Newton iterations" in p.note
        assert "steady after" in p.note
        for key in ("idr", "acc", "x_iso"):
            assert p.quantities[key] == pytest.approx(r.quantities[key], rel=1e-4)
        assert p.stable == r.stable
    rows = c.rows()
    assert rows[0]["method"] == "sweep" and "shooting failed" in rows[0]["note"]


def test_unfinished_sweep_returns_the_start_of_its_last_period(smooth_frame):
    # Definition: SweepResult.x0 is the state at the start of the period returned in X (and the
    # monodromy belongs to that period), also when the sweep stops before a steady state.
    prob = pr.frame_problem(smooth_frame, 2.0)
    sw = pr.steady_state_sweep(prob, 1.0, max_periods=3, tol=1e-14)
    assert not sw.steady and sw.periods_done == 3
    assert np.array_equal(sw.x0, sw.X[0])
    pm = pr.period_map(prob, sw.x0, 1.0, sens=True)
    assert np.allclose(pm.monodromy, sw.monodromy, rtol=1e-10, atol=1e-12)


def test_minimal_and_full_states_round_trip(frame):
    # q = Q z with orthonormal Q (a null-space basis of R): Q^T Q = I, so to_minimal inverts
    # to_full exactly (round-off), and full states satisfy the contacts R q = 0, R qd = 0.
    prob = pr.frame_problem(build_system(frame, Isolation(), fidelity="cb"), 1.0)
    Z = np.random.default_rng(0).standard_normal((5, prob.dim))
    X = prob.to_full(Z)
    n = prob.Q.shape[0]
    R = prob.system.R
    assert np.allclose(prob.to_minimal(X), Z, rtol=0, atol=1e-13)
    assert np.abs(X[:, :n] @ R.T).max() < 1e-12 and np.abs(X[:, n:] @ R.T).max() < 1e-12
    assert np.allclose(prob.to_full(Z[0]), X[0], rtol=0, atol=0)


def test_point_whose_period_cannot_be_integrated_reports_its_uplift():
    # The office frame near f_bis (0.06 Hz): at A = 2 m/s^2 the fixed-step period fails in the
    # stage Newton before one period is done, because a contact lifts off (its normal force
    # reaches zero; the radau probe, which checks every step, finds the instant); at
    # A = 0.5 m/s^2 the converged orbit keeps every normal force positive and the probe from
    # its start agrees. The point must carry that verdict, not "unknown".
    from nsdyn import bench

    system = build_system(bench.bench_frame(), bench.bench_isolation(), fidelity="cb", f_max=5.0)
    f = 0.06
    strong = pr.frame_problem(system, 2.0)
    sw = pr.steady_state_sweep(strong, f, strong.x_ref.copy(), monodromy=False)
    assert sw.periods_done == 0 and not sw.steady
    point = pr._point_from_sweep(strong, sw, "test")
    assert point.quantities["uplift"] is True
    assert "uplift at t = " in point.note and "outside its validity" in point.note
    assert 0.0 < float(point.note.split("uplift at t = ")[1].split()[0]) < 1.0 / f
    weak = pr.frame_problem(system, 0.5)
    res = pr.shoot(weak, f, weak.x_ref.copy())
    assert res.converged
    q = pr.orbit_quantities(weak, f, res.X)
    assert q["min_normal_force"] > 0 and q["uplift"] is False
    assert pr.uplift_probe(weak, f, res.x0)[0] is False


def test_sweep_command_writes_csv_and_resumes_from_its_checkpoint(tmp_path, capsys):
    # `nsdyn sweep` on a small scene: one CSV row per point with the documented columns, a
    # checkpoint per amplitude, and a second run that resumes (computes no point again) and
    # reproduces the same rows.
    import csv
    import json
    from concurrent.futures import ThreadPoolExecutor

    from nsdyn import sweep
    from nsdyn.scene import load_scene

    scene = tmp_path / "portal.toml"
    scene.write_text('[scene]\nframe = "portal"\nfidelity = "cb"\nf_max = 20.0\n')
    out = tmp_path / "out"
    argv = [
        str(scene),
        "--amplitudes",
        "0.5,2",
        "--fmin",
        "1",
        "--fmax",
        "4",
        "--points",
        "4",
        "--out",
        str(out),
        "--workers",
        "1",
        "--no-figures",
        "--json",
    ]
    assert sweep.main(argv) == 0
    first = json.loads(capsys.readouterr().out)
    rows = list(csv.DictReader((out / "sweep.csv").open()))
    assert tuple(rows[0].keys()) == sweep.CSV_COLUMNS
    assert len(rows) == 8 and {r["A"] for r in rows} == {"0.5", "2"}
    assert all(r["method"] in ("shooting", "sweep") and r["converged"] == "true" for r in rows)
    # a_floors leaves out the isolation level (level 0) of a's maximum over all levels
    assert all(0 < float(r["a_floors"]) <= float(r["a"]) for r in rows)
    for A in (0.5, 2.0):
        assert sweep.checkpoint_path(out, A).exists()
    assert sweep.main(argv) == 0
    second = json.loads(capsys.readouterr().out)
    assert [a["resumed_points"] for a in second["amplitudes"]] == [4, 4]
    assert list(csv.DictReader((out / "sweep.csv").open())) == rows
    assert [a["points"] for a in first["amplitudes"]] == [4, 4]
    # any concurrent.futures.Executor runs the amplitudes
    cfg = load_scene(scene)
    settings = sweep.SweepSettings(1.0, 4.0, 3, "sequential", True)
    with ThreadPoolExecutor(2) as ex:
        res = sweep.sweep_amplitudes(
            cfg, [0.5, 2.0], settings, tmp_path / "ex", executor=ex, quiet=True
        )
    assert [r["A"] for r in res] == [0.5, 2.0] and all(len(r["rows"]) == 3 for r in res)
    # --steps-factor 2: twice the steps per period (exactly: Discretisation.steps), so the
    # checkpoint of the default run is not reused; --tableau sdirk3 changes the tableau only
    fine = out.parent / "fine"
    argv2 = [a if a != str(out) else str(fine) for a in argv if a != "--no-figures"]
    argv2 += ["--steps-factor", "2"]
    assert sweep.main(argv2 + ["--tableau", "sdirk3"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["settings"]["steps_factor"] == 2.0 and report["settings"]["tableau"] == "sdirk3"
    rows2 = list(csv.DictReader((fine / "sweep.csv").open()))
    assert [int(r["n_steps"]) for r in rows2] == [2 * int(r["n_steps"]) for r in rows]
    assert (fine / "sweep.png").stat().st_size > 0 and not list(fine.glob(".*.tmp"))
    # the default sdirk2 and sdirk3 agree to the discretisation error of the coarse default
    for r, r2 in zip(rows, rows2, strict=True):
        assert float(r2["x_iso"]) == pytest.approx(float(r["x_iso"]), rel=2e-2, abs=1e-9)


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
    from nsdyn.system import IsolatedSystem

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
    from nsdyn._params import Harmonic
    from nsdyn.integrate import solve

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
