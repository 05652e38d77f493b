"""The Radau stepper's Newton matrices (nsdyn.solve._kcolloc._factor/_solve) and the shared
small LU's complex pivoting (nsdyn._klinalg.lu_factor).

``_factor`` reduces ``(g I - J)`` with ``J = [[0, I], [Jq, Jv]]`` to its n x n Schur complement
and stores U's diagonal inverted; ``_solve`` must still solve the full 2n system. Checked against
numpy's dense solve of the 2n x 2n matrix (LAPACK), for the real eigenvalue of the Radau IIA
matrix and the complex one, to round-off of the condition of the matrices.
"""

import numpy as np
import pytest

from nsdyn._klinalg import lu_factor, lu_solve
from nsdyn.solve import _kcolloc as kc


def _jacobian(n, rng, stiff):
    J = np.zeros((2 * n, 2 * n))
    J[:n, n:] = np.eye(n)
    J[n:, :n] = -stiff * (np.eye(n) + 0.3 * rng.standard_normal((n, n)))
    J[n:, n:] = -0.05 * np.sqrt(stiff) * (np.eye(n) + 0.2 * rng.standard_normal((n, n)))
    return J


@pytest.mark.parametrize("stiff", [1.0, 1e4, 1e8], ids=["soft", "stiff", "kHz"])
@pytest.mark.parametrize("h", [1e-4, 5e-3, 0.5])
def test_newton_solves_equal_the_full_2n_solve(stiff, h):
    # (g I - J) x = b for g = eig_real/h (real b) and g = eig_complex/h (complex b): the Schur
    # reduction with the inverted diagonal gives numpy's solution of the 2n system to 1e-12
    # relative (the matrices' condition numbers here stay below ~1e4)
    n = 7
    rng = np.random.default_rng(int(np.log10(stiff)) + 17)
    J = _jacobian(n, rng, stiff)
    LUr, LUc = np.zeros((n, n)), np.zeros((n, n), dtype=np.complex128)
    pr, pc = np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64)
    assert kc._factor(h, J, LUr, pr, LUc, pc)
    for g, LU, piv, dtype in (
        (kc.EIG_REAL / h, LUr, pr, float),
        (kc.EIG_COMPLEX / h, LUc, pc, complex),
    ):
        b = rng.standard_normal(2 * n).astype(dtype)
        if dtype is complex:
            b = b + 1j * rng.standard_normal(2 * n)
        A = g * np.eye(2 * n) - J
        ref = np.linalg.solve(A, b)
        x = b.copy()
        kc._solve(LU, piv, J, g, x)
        assert np.linalg.norm(x - ref) <= 1e-12 * np.linalg.cond(A) * np.linalg.norm(ref)


def test_complex_pivots_rank_by_real_plus_imaginary_size():
    # LAPACK's complex izamax ranks pivots by |Re| + |Im| (cabs1): between 3.2 (modulus 3.2)
    # and 2.2 + 2.2j (modulus 3.11, cabs1 4.4) the second row is the pivot; the modulus
    # would pick the first. The factors still solve A x = b to round-off.
    A = np.array([[3.2, 1.0, 0.5], [2.2 + 2.2j, -1.0, 2.0], [0.1j, 0.3, 1.0]], dtype=complex)
    LU = A.copy()
    piv = np.zeros(3, dtype=np.int64)
    assert lu_factor(LU, piv, 0.0)
    assert piv[0] == 1
    b = np.array([1.0, 2.0 - 1j, 0.5j])
    x = b.copy()
    lu_solve(LU, piv, x)
    assert np.allclose(A @ x, b, rtol=0.0, atol=1e-14 * np.linalg.norm(b) * np.linalg.cond(A))
    # real matrices: the size is |a| as before (cabs1 of a real number)
    R = np.array([[1.0, 2.0], [-3.0, 1.0]])
    pr = np.zeros(2, dtype=np.int64)
    assert lu_factor(R.copy(), pr, 0.0) and pr[0] == 1
