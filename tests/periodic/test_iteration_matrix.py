"""The SDIRK period map's linear algebra: the iteration matrix through its Schur complement.

Reference: numpy's LAPACK solve of the full matrix ``I - hg J``. The state is [positions,
velocities], so ``J = [[0, I], [Jz, Jv]]``; ``Jz`` carries the stiff boundary modes of the
office frame (~1e10 1/s^2 against ~1 for the flexible modes), where the full matrix's
condition number is ~1e12. The Schur form must solve it to round-off in each block's norm,
and a one-column block must be solved as the vector it is.
"""

import numpy as np
import pytest

from nsdyn._klinalg import lu_factor, lu_solve, lu_solve_columns
from nsdyn.periodic import _kperiodic as kp


def _jacobian(m, rng, stiff):
    J = np.zeros((2 * m, 2 * m))
    J[:m, m:] = np.eye(m)
    K = rng.standard_normal((m, m))
    K = K @ K.T + m * np.eye(m)
    K[:2, :2] *= stiff  # two stiff (boundary) coordinates
    J[m:, :m] = -K
    J[m:, m:] = -0.1 * np.eye(m) + 0.01 * rng.standard_normal((m, m))
    return J


@pytest.mark.parametrize("stiff", [1.0, 1e10])
@pytest.mark.parametrize("ncols", [1, 5])
def test_schur_solve_equals_the_full_solve(stiff, ncols):
    rng = np.random.default_rng(7)
    m = 11
    hg = 0.02 * 0.4358665215  # a default step times SDIRK2's diagonal
    J = _jacobian(m, rng, stiff)
    LU = np.zeros((m, 2 * m))
    piv = np.zeros(m, dtype=np.int64)
    assert kp._iteration_matrix(J, hg, LU, piv)
    B = rng.standard_normal((2 * m, ncols))
    X = B.copy()
    kp._solve_scaled(LU, piv, X, hg)
    A = np.eye(2 * m) - hg * J
    # reference: LAPACK's solve, refined in extended precision (exact to ~1e-16 here)
    X_ref = np.linalg.solve(A, B)
    for _ in range(3):
        r = B.astype(np.longdouble) - A.astype(np.longdouble) @ X_ref.astype(np.longdouble)
        X_ref = X_ref + np.linalg.solve(A, r.astype(float))
    # per block (positions, velocities), normwise: what the stage Newton and the shooting
    # weights measure (both scale by block). The stiff coordinates' tiny displacements are
    # x1 = b1 + hg x2, a difference of two large numbers: componentwise they are good only to
    # eps |b1| / |x1| (~1e-8 at stiff = 1e10), which no block norm sees.
    for blk in (slice(0, m), slice(m, 2 * m)):
        err = np.max(np.abs(X[blk] - X_ref[blk])) / np.max(np.abs(X_ref[blk]))
        assert err < 1e-14, (blk, err)


def _lu_solve_bound(LU, x):
    """Largest difference of two substitutions with the same factors (L unit lower, U upper,
    of P A) in any order of their sums, per entry of the solution x: each computed solution
    solves (L U + E) x = P b with |E| <= (2 g + g^2) |L| |U|, g = n u / (1 - n u) (Higham,
    Accuracy and Stability, Thm 9.4), so it is within |(L U)^-1| (2 g + g^2) |L| |U| |x| of
    the exact one; twice that between two."""
    n = LU.shape[0]
    L = np.tril(LU, -1) + np.eye(n)
    U = np.triu(LU)
    k = n * np.finfo(float).eps / 2
    g = k / (1 - k)
    LUinv = np.abs(np.linalg.inv(L @ U))
    return 2 * (2 * g + g * g) * (LUinv @ (np.abs(L) @ (np.abs(U) @ np.abs(x))))


def test_one_column_solve_is_the_vector_solve_and_the_block_solve():
    # a block of one column goes through the vector solve (bit for bit); against the block
    # solve of the same columns it differs only in the order of round-off (_lu_solve_bound)
    rng = np.random.default_rng(1)
    n = 22
    A = rng.standard_normal((n, n))
    piv = np.zeros(n, dtype=np.int64)
    LU = A.copy()
    assert lu_factor(LU, piv, 0.0)
    B = rng.standard_normal((n, 4))
    Xb = B.copy()
    lu_solve_columns(LU, piv, Xb)
    for c in range(4):
        x1 = B[:, c : c + 1].copy()
        lu_solve_columns(LU, piv, x1)
        xv = B[:, c].copy()
        lu_solve(LU, piv, xv)
        assert np.array_equal(x1[:, 0], xv)
        assert np.all(np.abs(x1[:, 0] - Xb[:, c]) <= _lu_solve_bound(LU, Xb[:, c]))
    assert np.allclose(Xb, np.linalg.solve(A, B), rtol=1e-10, atol=1e-12)


def test_jacobian_product_equals_the_dense_product():
    # C += alpha J B using J's [[0, I], [Jz, Jv]] structure, against numpy's product of the
    # whole matrices: each entry a sum of at most 2m + 1 rounded terms in any order, within
    # g (|C0| + alpha |J| |B|) of the exact value, g = (2m + 2) u / (1 - (2m + 2) u) (Higham,
    # Accuracy and Stability, §3.1); twice that between the two
    rng = np.random.default_rng(3)
    m = 9
    J = _jacobian(m, rng, 1e4)
    for ncols in (1, 2 * m):
        B = rng.standard_normal((2 * m, ncols))
        C0 = rng.standard_normal((2 * m, ncols))
        C = C0.copy()
        kp._jac_prod_acc(C, J, B, 0.37)
        ref = C0 + 0.37 * (J @ B)
        k = (2 * m + 2) * np.finfo(float).eps / 2
        bound = 2 * k / (1 - k) * (np.abs(C0) + 0.37 * (np.abs(J) @ np.abs(B)))
        assert np.all(np.abs(C - ref) <= bound)


@pytest.mark.parametrize("amplitude,f", [(0.5, 0.02), (0.5, 0.46), (2.0, 1.5)])
def test_period_without_sensitivities_agrees_below_the_shooting_tolerance(amplitude, f):
    # Without the monodromy the period map keeps its iteration matrix until the stage Newton
    # contracts slowly and takes each converged stage's slope from the stage equation, instead
    # of a fresh Jacobian and an evaluation at every stage. Both solve the same stage
    # equations to the stage tolerance (1e-9), so the end states must agree to well below the
    # shooting tolerance SHOOT_TOL = 1e-6 of each block's orbit range (the resolution of every
    # steady state computed from them). Office frame (CB, f_max 5 Hz), its bundled isolators.
    from nsdyn import bench
    from nsdyn.models.isolated.system import build_system
    from nsdyn.periodic import frame_problem, shoot
    from nsdyn.periodic.shooting import SHOOT_TOL, orbit_amplitudes

    system = build_system(bench.bench_frame(), bench.bench_isolation(), fidelity="cb", f_max=5.0)
    prob = frame_problem(system, amplitude)
    res = shoot(prob, f, None)
    assert res.converged
    with_s = prob.period_map(res.x0, f, sens=True, store=True)
    without = prob.period_map(res.x0, f, sens=False)
    assert with_s.status == 0 and without.status == 0 and without.monodromy is None
    amp = orbit_amplitudes(prob, with_s.X)
    m = prob.dim // 2
    for blk, a in ((slice(0, m), amp[0]), (slice(m, 2 * m), amp[1])):
        err = np.max(np.abs(without.xT[blk] - with_s.xT[blk])) / a
        assert err < 0.1 * SHOOT_TOL, (blk, err)
