"""Checks of the factor-once generalized-alpha (nsdyn.solve.sparse) against independent answers.

- Same scheme as the dense ``genalpha`` (Chung & Hulbert 1993): on the CB-5 office frame the
  histories agree to the dense method's Newton tolerance (its iteration stops when a
  correction is below 1e-3 of the error weights atol + rtol |x|, rtol 1e-4: ~1e-7 |q|).
- Linear undamped SDOF: the discrete solution is A^k x0 with the 3x3 amplification matrix of
  generalized-alpha, built here from the scheme's defining equations (round-off agreement),
  and the error against cos(w t) falls at least as h^2.
- The sparse LU backend equals the dense one on a banded chain (round-off).
- Full 435-dof model: second-order self-convergence of the peaks; (slow) peaks within 1e-3 of
  radau at the transient defaults at dt 0.0025.
"""

import numpy as np
import pytest

from nsdyn.bench import common
from nsdyn.models.isolated.params import pack
from nsdyn.models.isolated.system import build_system
from nsdyn.solve import _kgenalpha
from nsdyn.solve import sparse as lr
from nsdyn.solve.integrate import METHODS, solve
from nsdyn.solve.transient import simulate

WINDOW_S = common.QUICK_WINDOW_S  # s, contains the record's PGA


def test_registered():
    assert lr.METHOD in METHODS and METHODS[lr.METHOD].fixed_step


def test_cb5_equals_dense_genalpha():
    s = common.cb5_system()
    m = common.bench_motion("wn", WINDOW_S)
    dense = simulate(s, m, method="genalpha", dt=0.005)
    low = simulate(s, m, method=lr.METHOD, dt=0.005)
    n = s.n
    q_scale = np.abs(dense.x[:, :n]).max()
    v_scale = np.abs(dense.x[:, n:]).max()
    # the dense Newton's stopping error: 1e-3 of (atol + rtol |x|), rtol 1e-4, over 600 steps
    assert np.abs(low.x[:, :n] - dense.x[:, :n]).max() <= 1e-6 * q_scale
    assert np.abs(low.x[:, n:] - dense.x[:, n:]).max() <= 1e-6 * v_scale
    for key in ("x_iso_max", "idr_max", "floor_acc_max"):
        a, b = getattr(low.response, key), getattr(dense.response, key)
        assert abs(a / b - 1.0) <= 1e-5, key


def _amplification(w, h, coef):
    """3x3 map (q, v, a)_k -> (q, v, a)_{k+1} of generalized-alpha on q'' = -w^2 q, from
    (1-am) a1 + am a0 = -w^2 ((1-af) q1 + af q0) and the Newmark updates of q1, v1."""
    am, af, beta, gamma = coef
    # unknowns (q1, v1, a1); rows: Newmark q, Newmark v, balance
    L = np.array(
        [
            [1.0, 0.0, -beta * h * h],
            [0.0, 1.0, -gamma * h],
            [w * w * (1 - af), 0.0, 1 - am],
        ]
    )
    Rm = np.array(
        [
            [1.0, h, h * h * (0.5 - beta)],
            [0.0, 1.0, h * (1 - gamma)],
            [-w * w * af, 0.0, -am],
        ]
    )
    return np.linalg.solve(L, Rm)


def _sdof(w):
    return pack(np.eye(1), np.zeros((1, 1)), np.array([[w * w]]), np.zeros((1, 2)))


@pytest.mark.parametrize("rho", [0.8, 0.5])
def test_sdof_amplification_matrix(rho):
    w, h = 2 * np.pi, 0.05
    coef = _kgenalpha.parameters(_kgenalpha.FAMILY_GENALPHA, rho)
    t = h * np.arange(41)
    sol = solve(_sdof(w), np.array([1.0, 0.0]), t, method=lr.METHOD, dt=h, rho_inf=rho)
    A = _amplification(w, h, coef)
    y = np.array([1.0, 0.0, -w * w])
    ref = [y]
    for _ in range(40):
        y = A @ y
        ref.append(y)
    ref = np.array(ref)
    assert np.abs(sol.x[:, 0] - ref[:, 0]).max() <= 1e-12
    assert np.abs(sol.x[:, 1] - ref[:, 1]).max() <= 1e-12 * w


def test_sdof_second_order():
    w, T = 2 * np.pi, 5.0
    errs = []
    hs = [0.02, 0.01, 0.005]
    for h in hs:
        t = np.linspace(0.0, T, 11)
        sol = solve(_sdof(w), np.array([1.0, 0.0]), t, method=lr.METHOD, dt=h)
        errs.append(np.abs(sol.x[:, 0] - np.cos(w * t)).max())
    order = np.polyfit(np.log(hs), np.log(errs), 1)[0]
    assert order >= 1.8, (errs, order)  # at least second order (Chung & Hulbert 1993)


def _chain(n=80, law="arctan"):
    """Shear chain: lumped masses, tridiagonal K and stiffness-proportional C, one isolator on
    dof 0 with a frozen normal force (no contacts): banded kernel matrices."""
    m, k = 1e3, 1e6
    K = np.diag(np.full(n, 2 * k)) - np.diag(np.full(n - 1, k), 1) - np.diag(np.full(n - 1, k), -1)
    K[-1, -1] = k
    K[0, 0] = k + 5e4  # the isolator spring above dof 0 plus the chain
    M = np.eye(n) * m
    C = 1e-3 * K
    D = np.zeros((1, n))
    D[0, 0] = 1.0
    Gam = np.column_stack([np.ones(n), np.zeros(n)])
    motion = common.bench_motion("wn", 2.0)
    P = pack(
        M, C, K, Gam, D=D, mu=0.05, lam_static=[n * m * 9.81], law=law, eps=1e3,
        frozen_normal=True, ground=motion,
    )  # fmt: skip
    return P, n


def test_sparse_backend_equals_dense():
    P, n = _chain()
    MiK = P[0]
    assert lr._is_sparse(MiK, P[1])
    t = np.linspace(0.0, 2.0, 101)
    x0 = np.zeros(2 * n)
    out = {}
    for b in ("dense", "sparse"):
        stats, rinfo, X, _ = lr.integrate(P, x0, t, 0.005, backend=b)
        assert stats[0] == 0
        out[b] = X
    scale = np.abs(out["dense"]).max(axis=0)
    assert np.all(np.abs(out["sparse"] - out["dense"]).max(axis=0) <= 1e-9 * scale + 1e-15)


def test_switch_law_rejected():
    P, n = _chain(law="switch")
    with pytest.raises(ValueError, match="switch"):
        lr.integrate(P, np.zeros(2 * n), np.linspace(0, 0.1, 3), 0.01)


@pytest.fixture(scope="module")
def full_system():
    return build_system(common.bench_frame(), common.bench_isolation(), fidelity="full")


def test_full_model_second_order(full_system):
    m = common.bench_motion("wn", WINDOW_S)
    peaks = []
    for dt in (0.005, 0.0025, 0.00125):
        r = simulate(full_system, m, method=lr.METHOD, dt=dt)
        peaks.append([r.response.x_iso_max, r.response.idr_max])
    p = np.array(peaks)
    d1, d2 = np.abs(p[0] - p[1]), np.abs(p[1] - p[2])
    # Richardson: successive differences shrink by 2^p = 4 for a second-order scheme
    ratio = d1 / d2
    assert np.all((ratio > 2.8) & (ratio < 5.7)), ratio


@pytest.mark.slow
def test_full_model_matches_radau(full_system):
    # the factor-once generalized-alpha and Radau integrate the same equations, so a peak's
    # difference is generalized-alpha's error (plus Radau's at rtol 1e-6, at most ~10 rtol):
    # - x_iso and IDR converge at order 2: bounded by the Richardson estimate from dt and dt/2,
    #   e(dt) ~ (p(dt) - p(dt/2)) 4/3, with 1.5x for the estimate's own error;
    # - the floor acceleration's peak (a maximum over the output grid of a response with kinks
    #   at the record's samples) is not in its asymptotic range at these steps; converging at
    #   least linearly with ratio <= 1/2, its error at dt is at most its change from 2 dt
    m = common.bench_motion("wn", WINDOW_S)
    ref = simulate(full_system, m, method="radau", rtol=1e-6)
    runs = [simulate(full_system, m, method=lr.METHOD, dt=dt) for dt in (0.005, 0.0025, 0.00125)]
    for key in ("x_iso_max", "idr_max", "floor_acc_max"):
        a1, a, a2 = (getattr(r.response, key) for r in runs)
        b = getattr(ref.response, key)
        bound = 1.5 * abs(a - a2) * 4.0 / 3.0 if key != "floor_acc_max" else abs(a1 - a)
        assert abs(a - b) <= bound + 10 * 1e-6 * abs(b), key


@pytest.mark.parametrize("backend", ["dense", "sparse"])
def test_a_step_that_does_not_divide_the_span_ends_with_a_shortened_step(backend):
    """33 steps of 3 ms and a last one of 1 ms (its own factorisation): the run reaches
    t_end, and the states it shares with the run that stops after 33 steps are the same
    steps, so equal bit for bit."""
    P, n = _chain()
    x0 = np.zeros(2 * n)
    t_full, t_cut = np.array([0.0, 0.05, 0.1]), np.array([0.0, 0.05, 0.099])
    stats, _, X, _ = lr.integrate(P, x0, t_full, 0.003, backend=backend)
    stats_c, _, Xc, _ = lr.integrate(P, x0, t_cut, 0.003, backend=backend)
    assert stats[0] == stats_c[0] == 0
    assert np.array_equal(X[:2], Xc[:2]) and np.all(np.isfinite(X[2]))
