"""The minimum-norm split of redundant constraint forces (nsdyn._klinalg.pinv_small).

Where two stuck isolators hold the same slip (two bearings under one rigid base), the
constraint matrix G = C B of the system kernel is singular: the accelerations are determinate,
the split of the stick forces is not, and the kernel takes the minimum-norm one through G's
pseudo-inverse. Checked against LAPACK's (numpy.linalg.pinv) and the four Moore-Penrose
conditions, and in the system kernel against the physics: two identical stuck isolators carry
half each of what one of them alone carries, with the same accelerations, and the Jacobian
equals central differences of the right-hand side.
"""

import numpy as np
import pytest

from nsdyn._klinalg import PINV_RCOND, pinv_small
from nsdyn.ground import Harmonic
from nsdyn.models.isolated import _kernel as ks
from nsdyn.models.isolated.params import pack

EPS = np.finfo(float).eps


def _rank_deficient(m, rank, rng):
    if rank == 0:
        return np.zeros((m, m))
    return rng.standard_normal((m, rank)) @ rng.standard_normal((rank, m))


@pytest.mark.parametrize("m", [1, 2, 3, 5, 8])
def test_pinv_equals_lapacks_and_meets_the_penrose_conditions(m):
    # every rank 0..m of a random m x m product: the pseudo-inverse equals LAPACK's (SVD) to
    # the perturbation bound of a pseudo-inverse, |dX| / |X| <~ kappa_r * (backward error),
    # with kappa_r the ratio of the largest to the smallest non-zero singular value and a
    # backward error of a few m eps for either SVD (100 m eps kappa_r leaves a margin of ~10)
    rng = np.random.default_rng(m)
    for rank in range(m + 1):
        A = _rank_deficient(m, rank, rng)
        padded = np.zeros((m + 2, m + 2))  # the kernel passes a larger workspace: A[:m, :m]
        padded[:m, :m] = A
        X = pinv_small(padded, m)
        assert X.shape == (m, m)
        if rank == 0:
            assert np.all(X == 0.0)
            continue
        s = np.linalg.svd(A, compute_uv=False)
        kappa = s[0] / s[rank - 1]
        tol = 100 * m * EPS * kappa
        R = np.linalg.pinv(A)
        assert np.abs(X - R).max() <= tol * np.abs(R).max()
        # Moore-Penrose: A X A = A, X A X = X, A X and X A symmetric (scaled by their sizes)
        nA, nX = np.abs(A).max(), np.abs(X).max()
        assert np.abs(A @ X @ A - A).max() <= tol * nA
        assert np.abs(X @ A @ X - X).max() <= tol * nX
        assert np.abs(A @ X - (A @ X).T).max() <= tol
        assert np.abs(X @ A - (X @ A).T).max() <= tol


def test_pinv_of_a_duplicated_row_splits_evenly():
    # G = [[2, 2], [2, 2]] = 4 u u^T (u = [1, 1]/sqrt 2): G+ = u u^T / 4, every entry 1/8
    # exactly up to the rotations' round-off; a consistent right-hand side [r, r] is split
    # r/4 + r/4
    X = pinv_small(np.full((2, 2), 2.0), 2)
    assert np.abs(X - 0.125).max() <= 4 * EPS
    # below PINV_RCOND x the largest singular value counts as zero
    A = np.diag([1.0, 0.5 * PINV_RCOND])
    assert np.array_equal(pinv_small(A, 2), np.diag([1.0, 0.0]))


def test_pinv_of_a_non_finite_matrix_is_not_finite():
    # no exception inside a kernel: the caller's finiteness check reports it
    X = pinv_small(np.array([[1.0, np.nan], [0.0, 1.0]]), 2)
    assert not np.all(np.isfinite(X))


def _system(d_rows, lam):
    Kq = np.array([[3.0, -1.0, 0.0], [-1.0, 2.0, -0.5], [0.0, -0.5, 4.0]])
    ni = len(d_rows)
    return pack(
        np.diag([1.0, 2.0, 1.5]), 0.05 * Kq, Kq, np.eye(3)[:, :2], D=d_rows, mu=0.3,
        lam_static=lam, law="modes", frozen_normal=True, ground=Harmonic(2.0, 1.0),
        modes=np.zeros(ni, np.int64),
    )  # fmt: skip


def _evaluate(P, t, x):
    ni = P[ks.I_D].shape[0]
    qdd, tau, modes = np.zeros(3), np.zeros(ni), np.zeros(ni, np.int64)
    ok = ks.evaluate(t, x, P, qdd, np.zeros(0), tau, modes)
    return ok, qdd, tau


def test_two_identical_stuck_isolators_carry_half_each():
    # the same structure held by one stuck isolator on dof 0 (and one on dofs 1-2), then by
    # two identical ones on dof 0: the same accelerations, and the minimum-norm split gives
    # each twin half the single one's stick force (the duplicated row's G is singular; the
    # single one's is not). Tolerance: round-off of 2-3 unknowns with G's condition below
    # ~10 and entries O(1), 1e-12 relative leaving a margin of ~1e3
    x = np.array([0.01, 0.1, -0.05, 0.2, -0.1, 0.3])
    one = _system([[1.0, 0.0, 0.0], [0.0, 1.0, -1.0]], [5.0, 4.0])
    two = _system([[1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, -1.0]], [5.0, 5.0, 4.0])
    for t in (0.0, 0.3, 0.7):
        ok1, qdd1, tau1 = _evaluate(one, t, x)
        ok2, qdd2, tau2 = _evaluate(two, t, x)
        assert ok1 and ok2
        scale = np.abs(qdd1).max()
        assert np.abs(qdd2 - qdd1).max() <= 1e-12 * scale
        assert abs(tau2[0] - tau2[1]) <= 1e-12 * abs(tau1[0])
        assert abs(tau2[0] + tau2[1] - tau1[0]) <= 1e-12 * abs(tau1[0])
        assert abs(tau2[2] - tau1[1]) <= 1e-12 * abs(tau1[1])


def test_jacobian_with_redundant_stick_rows_equals_central_differences():
    # prescribed modes: the right-hand side is linear in the state, so central differences are
    # exact up to round-off, |f| eps / h ~ 1e-9 for h = 1e-6 (1e-8 x max|J| a margin of ~10)
    P = _system([[1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, -1.0]], [5.0, 5.0, 4.0])
    x = np.array([0.01, 0.1, -0.05, 0.2, -0.1, 0.3])
    t = 0.3
    J = np.zeros((6, 6))
    ks.jac(t, x, P, J)

    def f(z):
        out = np.zeros(6)
        ks.rhs(t, z, P, out)
        return out

    h = 1e-6
    Jfd = np.column_stack([(f(x + h * e) - f(x - h * e)) / (2 * h) for e in np.eye(6)])
    assert np.abs(J - Jfd).max() <= 1e-8 * np.abs(J).max()
