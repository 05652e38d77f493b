"""Small dense linear algebra shared by the numba kernels of every family: LU with partial
pivoting, the pseudo-inverse of a few constraint rows, and numpy's small products and
reductions written out (numba's own import SciPy's BLAS when a cached kernel loads).

``P A = L U`` factored in place (unit-diagonal L below, U on and above the diagonal, row
swaps in ``piv``), then ``A x = b`` solved by forward and back substitution. Real or complex
matrices (numba compiles one version per type); vectors or blocks of columns on the right.
:func:`solve_small` solves a few constraint rows in place, :func:`pinv_small` (or
:func:`pinv_into`, which allocates nothing) gives the minimum-norm solution of redundant ones.
"""

import numpy as np
from numba import njit

from nsdyn._kaddress import compiled_uncounted


@njit(cache=True, error_model="numpy", inline="always")
def _mag(a):
    """Pivot size ``|Re a| + |Im a|`` (LAPACK's ``cabs1``, as its complex ``izamax`` ranks
    pivots): ``|a|`` for a real ``a``; for a complex one no ``hypot`` call, which was ~4 % of
    the default run (91 per 13 x 13 complex factorisation, ~2 700 of them per run)."""
    return abs(a.real) + abs(a.imag)


@njit(cache=True, error_model="numpy")
def lu_factor(A, piv, rtol):
    """In-place LU of the square ``A`` with row pivots ``piv``.

    Returns False on a pivot that is zero, non-finite, or (``rtol > 0``) at most ``rtol``
    times the largest entry of ``A`` (sizes as :func:`_mag`).
    """
    n = A.shape[0]
    floor = 0.0
    if rtol > 0.0:
        for i in range(n):
            for j in range(n):
                floor = max(floor, _mag(A[i, j]))
        floor *= rtol
    for k in range(n):
        p = k
        amax = _mag(A[k, k])
        for i in range(k + 1, n):
            a = _mag(A[i, k])
            if a > amax:
                amax = a
                p = i
        piv[k] = p
        if amax == 0.0 or not np.isfinite(amax) or amax <= floor:
            return False
        if p != k:
            for j in range(n):
                tmp = A[k, j]
                A[k, j] = A[p, j]
                A[p, j] = tmp
        inv = 1.0 / A[k, k]
        for i in range(k + 1, n):
            f = A[i, k] * inv
            A[i, k] = f
            if f != 0.0:
                for j in range(k + 1, n):
                    A[i, j] -= f * A[k, j]
    return True


@njit(cache=True, error_model="numpy")
def lu_solve(LU, piv, b):
    """Solve ``A x = b`` in place (``b`` a vector) with the factors of :func:`lu_factor`."""
    n = LU.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
    for i in range(n):
        s = b[i]
        for j in range(i):
            s -= LU[i, j] * b[j]
        b[i] = s
    for i in range(n - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, n):
            s -= LU[i, j] * b[j]
        b[i] = s / LU[i, i]


@njit(cache=True, error_model="numpy")
def invert_diagonal(LU):
    """Replace U's diagonal by its reciprocals, for :func:`lu_solve_inverted` (in place)."""
    for i in range(LU.shape[0]):
        LU[i, i] = 1.0 / LU[i, i]


@njit(cache=True, error_model="numpy", inline="always")
def lu_solve_inverted(LU, piv, b, o):
    """:func:`lu_solve` on ``b[o:o + n]`` in place, for factors whose U diagonal holds its
    reciprocals (:func:`invert_diagonal`): the back substitution multiplies, so a complex
    solve divides nowhere (a complex division is three real ones and two branches). Inlined:
    the Radau Newton iteration solves with it twice per iteration, and the call was ~15 % of
    the default run."""
    n = LU.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = b[o + k]
            b[o + k] = b[o + p]
            b[o + p] = tmp
    for i in range(1, n):
        s = b[o + i]
        for j in range(i):
            s -= LU[i, j] * b[o + j]
        b[o + i] = s
    for i in range(n - 1, -1, -1):
        s = b[o + i]
        for j in range(i + 1, n):
            s -= LU[i, j] * b[o + j]
        b[o + i] = s * LU[i, i]


@njit(cache=True, error_model="numpy")
def lu_solve_columns(LU, piv, B):
    """Solve ``A X = B`` in place for a block of columns ``B`` (shape (n, k)).

    One column (k = 1) is solved by :func:`lu_solve`: the column loop below, one trip per
    matrix entry, made a 22 x 22 solve of one column cost half as much as one of 22 columns.
    """
    n = LU.shape[0]
    k = B.shape[1]
    if k == 1:
        lu_solve(LU, piv, B[:, 0])
        return
    for i in range(n):
        p = piv[i]
        if p != i:
            for c in range(k):
                tmp = B[i, c]
                B[i, c] = B[p, c]
                B[p, c] = tmp
    for i in range(n):
        for j in range(i):
            f = LU[i, j]
            if f != 0.0:
                for c in range(k):
                    B[i, c] -= f * B[j, c]
    for i in range(n - 1, -1, -1):
        for j in range(i + 1, n):
            f = LU[i, j]
            if f != 0.0:
                for c in range(k):
                    B[i, c] -= f * B[j, c]
        inv = 1.0 / LU[i, i]
        for c in range(k):
            B[i, c] *= inv


# ---- the same on a block of one flat float64 array ------------------------------------------
# The flat kernels (nsdyn.solve._kflat, nsdyn.periodic._kproblems) keep their matrices, scratch
# and pivots in one array at fixed offsets: no tuples passed, nothing allocated per call.


@njit(cache=True, error_model="numpy", inline="always")
def swap_rows_flat(F, o, stride, a, b, ncols):
    """Swap rows ``a`` and ``b`` (``ncols`` entries, row stride ``stride``) of the block of F
    at offset ``o``."""
    for c in range(ncols):
        tmp = F[o + a * stride + c]
        F[o + a * stride + c] = F[o + b * stride + c]
        F[o + b * stride + c] = tmp


@njit(cache=True, error_model="numpy", inline="always")
def lu_factor_flat(F, o, n, o_piv, rtol):
    """In-place LU with partial pivoting of the n x n row-major block of F at offset ``o``:
    multipliers below the diagonal, the row swaps in ``F[o_piv : o_piv + n]`` (as floats).
    False on a pivot at most ``rtol`` times the block's largest entry (a zero block too)."""
    scale = 0.0
    for k in range(n * n):
        scale = max(scale, abs(F[o + k]))
    for k in range(n):
        p = k
        for i in range(k + 1, n):
            if abs(F[o + i * n + k]) > abs(F[o + p * n + k]):
                p = i
        if abs(F[o + p * n + k]) <= rtol * scale:
            return False
        F[o_piv + k] = p
        if p != k:
            swap_rows_flat(F, o, n, k, p, n)
        for i in range(k + 1, n):
            f = F[o + i * n + k] / F[o + k * n + k]
            for j in range(k + 1, n):
                F[o + i * n + j] -= f * F[o + k * n + j]
            F[o + i * n + k] = f
    return True


@njit(cache=True, error_model="numpy", inline="always")
def lu_solve_flat(F, o, o_piv, n, B, o_b, stride, ncols):
    """Solve ``A X = B`` in place with the factors of :func:`lu_factor_flat` (block at ``o``,
    pivots at ``o_piv``); ``B``: n rows of ``ncols`` entries at offset ``o_b`` of the array
    ``B`` (F itself or another), row stride ``stride``."""
    for k in range(n):
        p = int(F[o_piv + k])
        if p != k:
            swap_rows_flat(B, o_b, stride, k, p, ncols)
        for i in range(k + 1, n):
            f = F[o + i * n + k]
            for c in range(ncols):
                B[o_b + i * stride + c] -= f * B[o_b + k * stride + c]
    for k in range(n - 1, -1, -1):
        d = F[o + k * n + k]
        for c in range(ncols):
            acc = B[o_b + k * stride + c]
            for j in range(k + 1, n):
                acc -= F[o + k * n + j] * B[o_b + j * stride + c]
            B[o_b + k * stride + c] = acc / d


# numpy's reductions written out: numba's own (np.argmin, np.all, np.min, ...) live in
# numba.np.arraymath, which numba's loader imports for a cached kernel that uses one, and which
# imports SciPy's linear algebra to check for its BLAS (~0.2 s of every cached start)
@njit(cache=True, error_model="numpy", inline="always")
def argmin(x):
    """``np.argmin`` of a float vector: the first minimum, or the first NaN where there is one
    (as numpy's)."""
    k = 0
    for i in range(x.shape[0]):
        if x[i] != x[i]:
            return i
        if x[i] < x[k]:
            k = i
    return k


@njit(cache=True, error_model="numpy", inline="always")
def all_finite(x):
    """``np.all(np.isfinite(x))`` of a vector."""
    for i in range(x.shape[0]):
        if not np.isfinite(x[i]):
            return False
    return True


@njit(cache=True, error_model="numpy", inline="always")
def max_abs(x):
    """``np.max(np.abs(x))`` of a non-empty float vector (a NaN where there is one)."""
    m = abs(x[0])
    for i in range(1, x.shape[0]):
        a = abs(x[i])
        if a != a:
            return a
        if a > m:
            m = a
    return m


@njit(cache=True, error_model="numpy", inline="always")
def min_of(x):
    """``np.min(x)`` of a non-empty float vector (a NaN where there is one)."""
    m = x[0]
    for i in range(1, x.shape[0]):
        if x[i] != x[i]:
            return x[i]
        if x[i] < m:
            m = x[i]
    return m


@njit(cache=True, error_model="numpy", inline="always")
def dot3(a, w, b):
    """``np.sum(a * w * b)`` of three vectors of one length, summed in order from 0.0 (as
    numba's ``np.sum``)."""
    s = 0.0
    for i in range(a.shape[0]):
        s += a[i] * w[i] * b[i]
    return s


# matrix-vector products by loops: numba's ``@`` calls BLAS through ``numba.np.linalg``, which
# numba's loader imports for a cached kernel that uses it (SciPy's BLAS, ~0.2 s of a cached start)
@njit(cache=True, error_model="numpy", inline="always")
def matvec(A, x):
    """``A @ x`` for a 2-d ``A`` and a vector ``x``, each row summed in order (for the few
    contact rows; the low-rank step's large operators use the vectorised
    :func:`nsdyn.solve._klowrank.matvec`, whose sums LLVM may reorder)."""
    y = np.empty(A.shape[0])
    for i in range(A.shape[0]):
        s = 0.0
        for j in range(A.shape[1]):
            s += A[i, j] * x[j]
        y[i] = s
    return y


@njit(cache=True, error_model="numpy", inline="always")
def tmatvec(A, x):
    """``A.T @ x`` for a 2-d ``A`` and a vector ``x``, each column summed in order."""
    y = np.zeros(A.shape[1])
    for i in range(A.shape[0]):
        for j in range(A.shape[1]):
            y[j] += A[i, j] * x[i]
    return y


# copies by element loops: numba's slice assignment from an array (``a[:] = b``, ``A[i] = b``)
# compiles a shape-mismatch message (string formatting) once per dimension and process, ~2 s
# each of a cold start; a kernel family that never assigns slices from arrays never pays it
@njit(cache=True, error_model="numpy", inline="always")
def copy_vec(dst, src):
    """``dst[:] = src`` for 1-d arrays of one length."""
    for i in range(dst.shape[0]):
        dst[i] = src[i]


@njit(cache=True, error_model="numpy", inline="always")
def copy_mat(dst, src):
    """``dst[:, :] = src`` for 2-d arrays of one shape."""
    for i in range(dst.shape[0]):
        for j in range(dst.shape[1]):
            dst[i, j] = src[i, j]


@compiled_uncounted
def solve_small(A, y, m):
    """Solve A[:m, :m] y = y[:m] in place (Gaussian elimination, partial pivoting), for the
    constraint forces of the system kernel (nsdyn.models.isolated._kernel).

    ``A`` is overwritten by its factors. Returns False when A is (numerically) singular: a pivot
    at most 1e-14 times the largest entry. Allocates nothing (NO_NRT). Not :func:`lu_factor`
    with :func:`lu_solve`: this one eliminates the right-hand side with the rows and forms each
    multiplier by a division where lu_factor multiplies by the pivot's reciprocal, so its
    round-off differs, and the switch model's histories (stick-slip magnifies a last bit) were
    measured and published with it.
    """
    scale = 0.0
    for i in range(m):
        for j in range(m):
            scale = max(scale, abs(A[i, j]))
    if scale == 0.0 and m > 0:
        return False
    for k in range(m):
        p = k
        for i in range(k + 1, m):
            if abs(A[i, k]) > abs(A[p, k]):
                p = i
        if abs(A[p, k]) <= 1e-14 * scale:
            return False
        if p != k:
            for j in range(m):
                A[k, j], A[p, j] = A[p, j], A[k, j]
            y[k], y[p] = y[p], y[k]
        for i in range(k + 1, m):
            f = A[i, k] / A[k, k]
            for j in range(k, m):
                A[i, j] -= f * A[k, j]
            y[i] -= f * y[k]
    for k in range(m - 1, -1, -1):
        s = y[k]
        for j in range(k + 1, m):
            s -= A[k, j] * y[j]
        y[k] = s / A[k, k]
    return True


PINV_RCOND = 1e-13  # singular values at most this x the largest count as zero (pinv_small)
JACOBI_SWEEPS = 40  # most sweeps of pinv_small's rotations (a few suffice for small m)


@njit(cache=True, error_model="numpy")
def pinv_small(A, m):
    """The Moore-Penrose pseudo-inverse of ``A[:m, :m]`` (a new m x m array; :func:`pinv_into`)."""
    out = np.empty((m, m))
    pinv_into(A, m, out, np.empty((m, m)), np.empty((m, m)), np.empty(m))
    return out


@compiled_uncounted
def pinv_into(A, m, out, U, V, s2):
    """``out[:m, :m]`` = the Moore-Penrose pseudo-inverse of ``A[:m, :m]`` (all NaN when ``A``
    holds a non-finite entry), with ``U``, ``V`` (at least m x m) and ``s2`` (m) as scratch:
    allocates nothing (:data:`nsdyn._kaddress.NO_NRT`).

    One-sided Jacobi SVD (Hestenes): plane rotations ``V`` of the columns of ``U = A`` until
    every pair is orthogonal to working precision, so ``A V = U`` with the column norms of
    ``U`` the singular values ``s_j``; then ``A+ = sum_j v_j u_j^T / s_j^2`` over the
    ``s_j > PINV_RCOND max(s)``. The threshold: the callers' ``A`` (a product ``C B`` of two
    rows-of-n matrices) carries relative errors of ~n machine epsilons, and singular values
    below that are round-off of exact zeros (redundant constraints). A few hundred flops for
    the callers' m <= ~10, and a few lines where LAPACK's SVD through numba compiled
    for seconds.
    """
    for i in range(m):
        for j in range(m):
            out[i, j] = 0.0
            V[i, j] = 0.0
            U[i, j] = A[i, j]
        V[i, i] = 1.0
    for i in range(m):
        for j in range(m):
            if not np.isfinite(A[i, j]):
                for r in range(m):
                    for c in range(m):
                        out[r, c] = np.nan  # no pseudo-inverse: NaN, for the caller's check
                return
    eps = 2.220446049250313e-16
    for _ in range(JACOBI_SWEEPS):
        rotated = False
        for p in range(m - 1):
            for q in range(p + 1, m):
                a = 0.0
                b = 0.0
                g = 0.0
                for k in range(m):
                    a += U[k, p] * U[k, p]
                    b += U[k, q] * U[k, q]
                    g += U[k, p] * U[k, q]
                # orthogonal to working precision; or a column whose squares underflowed
                if a == 0.0 or b == 0.0 or not abs(g) > eps * np.sqrt(a) * np.sqrt(b):
                    continue
                rotated = True
                zeta = (b - a) / (2.0 * g)  # |zeta| may pass 1e154: hypot, not sqrt(1 + zeta^2)
                t = (1.0 if zeta >= 0.0 else -1.0) / (abs(zeta) + np.hypot(1.0, zeta))
                c = 1.0 / np.sqrt(1.0 + t * t)
                s = c * t
                for k in range(m):
                    up = U[k, p]
                    uq = U[k, q]
                    U[k, p] = c * up - s * uq
                    U[k, q] = s * up + c * uq
                    vp = V[k, p]
                    vq = V[k, q]
                    V[k, p] = c * vp - s * vq
                    V[k, q] = s * vp + c * vq
        if not rotated:
            break
    smax = 0.0
    for j in range(m):
        acc = 0.0
        for k in range(m):
            acc += U[k, j] * U[k, j]
        s2[j] = acc
        smax = max(smax, np.sqrt(acc))
    cut = PINV_RCOND * smax
    for j in range(m):
        if not np.sqrt(s2[j]) > cut:
            continue
        w = 1.0 / s2[j]
        for r in range(m):
            vr = V[r, j] * w
            for c in range(m):
                out[r, c] += vr * U[c, j]
