"""The stability verdict of periodic orbits: the tableaux, why they can grow, and the check.

Sources: Alexander (1977), SIAM J. Numer. Anal. 14, 1006-1021 (the SDIRK2/SDIRK3 tableaux,
gamma of SDIRK3 the root of 6 g^3 - 18 g^2 + 9 g - 1 = 0 in (1/6, 1/2)); Hairer & Wanner,
Solving ODEs II, IV.5 (order conditions), IV.3 (A- and L-stability), IV.12 (AN- and algebraic
stability, Burrage & Butcher 1979). Physics: a mass on a spring, a viscous damper c > 0 and an
arctan friction law (non-decreasing in the slip velocity) is incrementally dissipative: two
solutions' difference d obeys d/dt (m d'^2 / 2 + k d^2 / 2) = -c d'^2 - d' (F(v1) - F(v2))
<= -c d'^2, so every Floquet multiplier lies inside the unit circle.
"""

import math

import numpy as np
import pytest

from nsdyn import periodic as pr
from nsdyn.models.isolated.builders import system_from_matrices
from nsdyn.models.isolated.system import Isolation
from nsdyn.periodic.stability import check_verdict

EPS = np.finfo(float).eps
M1, W1 = 1.0, 2.0 * math.pi


def _R(A, z):
    """Stability function R(z) = 1 + z b^T (I - z A)^-1 1 (stiffly accurate: b = last row)."""
    s = A.shape[0]
    return 1.0 + z * A[-1] @ np.linalg.solve(np.eye(s) - z * A, np.ones(s))


@pytest.mark.parametrize("method", sorted(pr.TABLEAUX))
def test_tableau_order_conditions_and_stiff_accuracy(method):
    # Order conditions up to the method's order (Hairer & Wanner IV.5, Table 5.1): sum b = 1,
    # b.c = 1/2, b.c^2 = 1/3, b.A c = 1/6; c_i = sum_j a_ij; b = the last row of A. Each sum
    # has at most 9 terms of size <= 2: round-off below 20 eps.
    A, c = pr.TABLEAUX[method]()
    b = A[-1]
    p = pr.ORDER[method]
    assert np.max(np.abs(A.sum(axis=1) - c)) < 20 * EPS
    assert np.all(np.triu(A, 1) == 0) and np.all(np.diag(A) == A[0, 0])  # singly diagonal
    assert abs(b.sum() - 1.0) < 20 * EPS
    if p >= 2:
        assert abs(b @ c - 0.5) < 20 * EPS
    if p >= 3:
        assert abs(b @ c**2 - 1.0 / 3.0) < 20 * EPS
        assert abs(b @ (A @ c) - 1.0 / 6.0) < 20 * EPS
        g = A[0, 0]  # L-stability of Alexander's SDIRK3 fixes gamma
        assert abs(6 * g**3 - 18 * g**2 + 9 * g - 1) < 50 * EPS
        assert 1 / 6 < g < 1 / 2


@pytest.mark.parametrize("method", sorted(pr.TABLEAUX))
def test_stability_function_bounded_on_the_left_half_plane(method):
    # A-stability: R is analytic for Re z <= 0 (its poles are at 1/gamma > 0), so by the
    # maximum principle |R| <= 1 there iff |R(iy)| <= 1 on the imaginary axis and at infinity;
    # L-stability: R(z) -> 0 as z -> -inf. Checked on a dense sample; the tolerance is the
    # round-off of a 3x3 solve (~ 10 eps cond, cond <= 1 + |z| |A|).
    A, _ = pr.TABLEAUX[method]()
    for y in np.concatenate([[0.0], np.geomspace(1e-3, 1e6, 400)]):
        assert abs(_R(A, 1j * y)) <= 1.0 + 1e-12
    for x in -np.geomspace(1e-3, 1e8, 400):
        assert abs(_R(A, x)) <= 1.0 + 1e-12
    assert abs(_R(A, -1e12)) < 1e-9  # R(-inf) = 0
    rng = np.random.default_rng(0)
    z = -np.abs(rng.standard_normal(200)) * 10.0 ** rng.uniform(-2, 4, 200) + 1j * (
        rng.standard_normal(200) * 10.0 ** rng.uniform(-2, 4, 200)
    )
    assert all(abs(_R(A, zi)) <= 1.0 + 1e-12 for zi in z)


def _K(A, zs):
    """One step of x' = lambda(t) x with z_i = h lambda(t_n + c_i h) at the stages."""
    s = A.shape[0]
    Z = np.diag(zs)
    return 1.0 + A[-1] @ Z @ np.linalg.solve(np.eye(s) - A @ Z, np.ones(s))


def test_sdirk_tableaux_are_not_an_stable_the_cause_of_false_growth():
    # The cause of multipliers > 1 on a dissipative friction orbit: a stage where the friction
    # slope is stiff (z_1 -> -inf) followed by stages where it is not (z = 0) gives
    # K = 1 - b_1 / gamma, |K| > 1 (SDIRK3: 1.773, SDIRK2: sqrt 2), although every Re z_i <= 0.
    # Backward Euler (algebraically stable: b = 1 >= 0, M = 2 b a - b^2 = 1 >= 0) keeps |K| <= 1.
    for method, bound in (("sdirk3", 1.77), ("sdirk2", 1.41)):
        A, _ = pr.TABLEAUX[method]()
        zs = np.zeros(A.shape[0])
        zs[0] = -1e12
        k = _K(A, zs)
        assert abs(k - (1.0 - A[-1, 0] / A[0, 0])) < 1e-9 and abs(k) > bound
    A, _ = pr.TABLEAUX["euler"]()
    for z in -np.geomspace(1e-6, 1e12, 50):
        assert abs(_K(A, [z])) <= 1.0


def _dissipative_oscillator():
    """m x'' + c x' + k x + mu m g (2/pi) arctan(eps x') = -m a_g (c > 0, eps = 7500 s/m)."""
    iso = Isolation(k_lam=0.0, c=0.0, mu=0.3, law="arctan", eps=7500.0)
    return system_from_matrices(
        [[M1]],
        [[0.5]],
        [[M1 * W1**2]],
        iso_dofs=[0],
        influence=[1.0],
        isolation=iso,
        weight=M1 * iso.g,
        levels=[[0]],
    )


def test_sdirk3_monodromy_is_the_derivative_of_its_map_on_the_growing_orbit():
    # The growth is the map's, not an error of the sensitivities propagated through the three
    # stages: on the dissipative orbit where the SDIRK3 map has |rho| > 1 (1.83 Hz, A = 8) its
    # monodromy equals central differences of the map. A central difference errs by C delta^2
    # (+ round-off / delta): the discrepancy falls ~100x when delta falls 10x (an inexact
    # monodromy gives an O(1) discrepancy) and is small at delta = 1e-5 (scaled variables).
    prob = pr.frame_problem(_dissipative_oscillator(), 8.0)
    disc = pr.Discretisation(method="sdirk3")
    f = 1.83
    res = pr.shoot(prob, f, disc=disc)
    assert res.converged and np.max(np.abs(res.multipliers)) > 1.0
    x0, N = res.x0, res.n_steps
    pm = pr.period_map(prob, x0, f, n_steps=N, disc=disc, store=True)
    W = 1.0 / np.max(np.abs(pm.X - prob.x_ref), axis=0)
    Ms = W[:, None] * pm.monodromy / W[None, :]

    def fd_error(delta):
        fd = np.empty((2, 2))
        for k in range(2):
            e = np.zeros(2)
            e[k] = delta / W[k]
            xa = pr.period_map(prob, x0 + e, f, n_steps=N, disc=disc).xT
            xb = pr.period_map(prob, x0 - e, f, n_steps=N, disc=disc).xT
            fd[:, k] = W * (xa - xb) / (2 * delta)
        return np.max(np.abs(Ms - fd)) / np.max(np.abs(fd))

    e4, e5 = fd_error(1e-4), fd_error(1e-5)
    assert e4 / e5 > 30.0 and e5 < 1e-4


def test_dissipative_arctan_orbits_are_stable_with_sdirk3():
    # Stick-slip orbits at A = 8 m/s^2 (mu g = 2.9 m/s^2): the SDIRK3 map alone gives
    # |rho| up to ~2 at several frequencies; the reported multipliers must all lie inside the
    # unit circle (module docstring: the exact ones do) and every point be stable.
    prob = pr.frame_problem(_dissipative_oscillator(), 8.0)
    disc = pr.Discretisation(method="sdirk3")
    c = pr.continue_sequential(prob, np.geomspace(0.2, 3.0, 12), disc=disc)
    assert len(c.points) == 12
    for p in c.points:
        assert p.stable is True, (p.f, p.note)
        assert p.max_multiplier < 1.0, (p.f, p.note)
    assert not [b for b in c.bifurcations if b["by"] == "multipliers"]


def test_a_genuine_instability_is_confirmed_not_masked():
    # Hardening Duffing between its folds (harmonic balance: w in [1.066, 1.110] rad/s for these
    # values, tests/periodic/test_continuation_curves.py): the middle branch is unstable, and the
    # backward-Euler check must confirm it for both SDIRK tableaux.
    prob = pr.duffing_problem(0.02, 1.0, 0.3, 0.045)
    for method in ("sdirk2", "sdirk3"):
        disc = pr.Discretisation(method=method, n_min=256, dt_max=1e9)
        c = pr.continue_arclength(prob, 0.9 / (2 * np.pi), 1.25 / (2 * np.pi), points=40, disc=disc)
        unstable = [p for p in c.points if p.stable is False]
        assert unstable
        assert all("confirmed" in p.note and p.max_multiplier > 1.0 for p in unstable)
        # and only there: between the folds (first-order harmonic balance, accurate to ~1 %
        # at gamma a^2 ~ 0.3, as in test_continuation_curves)
        assert all(1.066 * 0.99 <= 2 * np.pi * p.f <= 1.110 * 1.01 for p in unstable)
        assert all(p.stable is not None for p in c.points)


def test_an_exact_map_or_a_stable_verdict_is_not_rechecked():
    # The check runs only on a growth from a tableau that is not AN-stable: an exact map (the
    # switch model's) or backward Euler reports its own multipliers, unchanged.
    class Exact:
        exact_map = True

    rho = np.array([1.5, 0.2])
    out, verdict, note = check_verdict(Exact(), 1.0, np.zeros(2), rho, pr.Discretisation())
    assert out is rho and verdict is False and note == ""
    out, verdict, note = check_verdict(None, 1.0, None, np.array([0.5]), pr.Discretisation())
    assert verdict is True and note == ""
    euler = pr.Discretisation(method="euler")
    out, verdict, _ = check_verdict(None, 1.0, None, rho, euler)
    assert out is rho and verdict is False
