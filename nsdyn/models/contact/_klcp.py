"""Lemke's complementary pivoting for the linear complementarity problem (numba kernel).

Find z such that  w = M z + q >= 0,  z >= 0,  w^T z = 0.  Lemke's scheme augments the problem
with an artificial variable z0 and covering vector e = 1,  w = M z + q + e z0, starts from the
almost-complementary basis {w} with z0 = -min(q), and pivots the complement of the variable that
left until z0 leaves.  The ratio test is lexicographic (rows of [b, B^-1] / d compared in order),
so the method cannot cycle on degenerate problems.  It terminates with a solution for P-matrices
and for copositive-plus matrices whenever the problem is feasible (the contact problems here).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from nsdyn._klinalg import matvec, max_abs, min_of

PIVOT_TOL = 1e-10  # a column entry must exceed this (relative to the column max) to pivot on
LEX_TOL = 1e-12  # ratios closer than this (relative) are ties broken lexicographically
MAX_PIVOTS_PER_N = 50  # pivot budget: MAX_PIVOTS_PER_N * n
# a solution is checked against the problem as given: w = M z + q >= 0 and z_i w_i = 0, each to
# ACC_TOL of the magnitudes in w (|q|, |M| |z|). Near-equal rows (two corners of one edge at a
# tilt of 1e-9 rad, or resting flat: cond(M) ~ 1e16) let round-off ruin the tableau while z0
# still leaves; the basic solution then violated the problem by up to half its data (an impact
# left a corner approaching the ground at 7.8 mm/s; Moreau-Jean steps of a prism standing on
# both corners took friction outside its cone), reported as solved. It is status 3 instead,
# for the caller's regularised retries. Solutions from such problems that are right carry
# residuals of ~1e-7 of the data (round-off times cond), hence not a tighter ACC_TOL.
ACC_TOL = 1e-6
# ... and a ray termination (or an exhausted budget) whose basic solution solves the LCP to
# round-off is a solution: two corners of one edge resting flat end Lemke with z0 at ~1e-16
RAY_ACC_TOL = 1e-12


@njit(cache=True, error_model="numpy")
def _lex_less(T, b, r1, r2, col, n):
    """Row r1 lexicographically precedes r2 in [b, B^-1] / d (B^-1: columns 0..n-1)."""
    d1 = T[r1, col]
    d2 = T[r2, col]
    x1 = b[r1] / d1
    x2 = b[r2] / d2
    sc = max(1.0, abs(x1), abs(x2))
    if x1 < x2 - LEX_TOL * sc:
        return True
    if x2 < x1 - LEX_TOL * sc:
        return False
    for j in range(n):
        y1 = T[r1, j] / d1
        y2 = T[r2, j] / d2
        sc = max(1.0, abs(y1), abs(y2))
        if y1 < y2 - LEX_TOL * sc:
            return True
        if y2 < y1 - LEX_TOL * sc:
            return False
    return r1 < r2


@njit(cache=True, error_model="numpy")
def _pivot(T, b, r, c):
    piv = T[r, c]
    for j in range(T.shape[1]):
        T[r, j] /= piv
    b[r] /= piv
    for i in range(T.shape[0]):
        if i != r:
            f = T[i, c]
            if f != 0.0:
                for j in range(T.shape[1]):
                    T[i, j] -= f * T[r, j]
                b[i] -= f * b[r]


@njit(cache=True, error_model="numpy")
def lemke(M, q):
    """Solve the LCP (M, q).

    Parameters
    ----------
    M : (n, n) array
    q : (n,) array

    Returns
    -------
    z : (n,) array
    w : (n,) array, ``M z + q``
    status : int, 0 solved (to ACC_TOL), 1 ray termination (no solution found), 2 pivot
        budget exhausted, 3 a basis reached whose solution violates the LCP beyond ACC_TOL
    """
    n = q.shape[0]
    z = np.zeros(n)
    if n == 0:
        return z, q.copy(), 0
    if min_of(q) >= 0.0:
        return z, q.copy(), 0
    # tableau for  I w - M z - e z0 = q ; columns: w 0..n-1, z n..2n-1, z0 2n
    T = np.zeros((n, 2 * n + 1))
    for i in range(n):
        T[i, i] = 1.0
        for j in range(n):
            T[i, n + j] = -M[i, j]
        T[i, 2 * n] = -1.0
    b = q.copy()
    basis = np.arange(n)
    # first pivot: z0 enters, the most negative q leaves (lexicographic tie-break)
    r = np.int64(0)
    for i in range(1, n):
        if b[i] < b[r] - LEX_TOL * max(1.0, abs(b[r])):
            r = i
    _pivot(T, b, r, 2 * n)
    leaving = basis[r]
    basis[r] = 2 * n
    status = 2
    for _ in range(MAX_PIVOTS_PER_N * n):
        entering = leaving + n if leaving < n else leaving - n
        cmax = 0.0
        for i in range(n):
            cmax = max(cmax, abs(T[i, entering]))
        tol = PIVOT_TOL * max(1.0, cmax)
        r = np.int64(-1)
        for i in range(n):
            if T[i, entering] > tol:
                if r < 0 or _lex_less(T, b, i, r, entering, n):
                    r = i
        if r < 0:
            status = 1
            break
        _pivot(T, b, r, entering)
        leaving = basis[r]
        basis[r] = entering
        if leaving == 2 * n:
            status = 0
            break
    w = np.zeros(n)
    for i in range(n):
        k = basis[i]
        val = max(b[i], 0.0)
        if k < n:
            w[k] = val
        elif k < 2 * n:
            z[k - n] = val
    # judged by the problem as given, not by the pivoting's path: a basis that round-off
    # spoilt is no solution (3), and a ray termination or an exhausted budget whose basic
    # solution already solves the LCP (the artificial variable left basic at round-off: two
    # corners of one edge resting flat) is one
    wz = matvec(M, z) + q
    if _accurate(M, q, z, wz, ACC_TOL if status == 0 else RAY_ACC_TOL):
        return z, wz, 0
    return z, w if status != 0 else wz, 3 if status == 0 else status


@njit(cache=True, error_model="numpy")
def _accurate(M, q, z, w, tol):
    """Whether ``z`` and ``w = M z + q`` satisfy the LCP to ``tol`` of w's magnitudes (|q|,
    |M| |z|, at least 1: absolute for small data, as Lemke's pivoting tolerances are)."""
    n = q.shape[0]
    zmax = 0.0
    mmax = 0.0
    for i in range(n):
        zmax = max(zmax, z[i])
        for j in range(n):
            mmax = max(mmax, abs(M[i, j]))
    ws = max(1.0, max_abs(q), mmax * zmax)
    for i in range(n):
        wi = w[i] / ws
        if wi < -tol or (zmax > 0.0 and z[i] / zmax * wi > tol):
            return False
    return True
