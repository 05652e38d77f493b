"""Steps of the factor-once generalized-alpha (:mod:`nsdyn.solve.sparse`) as numba kernels.

One step from (q, v, a)_n at step size h, given the linear part of the alpha-point acceleration
``A0`` (``S a_{n+1} = ...`` with the nonlinear forces set to zero; see :mod:`nsdyn.solve.sparse`
for the derivation)::

    qt = q + (1-af) (h v + h^2 (1/2 - beta) a),   vt = v + (1-af) h (1 - gamma) a
    lam_c = -RGr^-1 c0 / kR,   c0 = kR R A0 + R (am a + 2 ab bb vt + ab^2 qt)
    phi   = mu L s(w0 + c2 Wp phi),   w0 = D vt + c2 (D A0 + DGr lam_c)     (friction Newton)
    lam   = lam_c + Lam phi,   a_{n+1} = A0 + G [lam; phi]
    q_{n+1}, v_{n+1}: Newmark update;  outputs by cubic Hermite on (t_n, t_{n+1}]

``kR = (1-am) + 2 ab bb c2 + ab^2 c1`` (``ab, bb`` the Baumgarte alpha, beta), ``L = lam_c +
Lam phi`` on the isolators' contacts (or the frozen static normal forces), ``s`` the arctan law
``(2/pi) arctan(eps v)``. The friction forces solve by Newton on the ``ni`` unknowns with a
backtracking line search. With the dense backend the whole loop runs here (``A0 = W [q; v; a;
u]``, one matrix-vector product); the sparse backend computes ``A0`` with SuperLU in Python and
calls :func:`step` once per step.
"""

import numpy as np
from numba import njit

from nsdyn import _kborrow as kb
from nsdyn._klinalg import copy_mat, copy_vec, lu_factor, lu_solve
from nsdyn._klinalg import matvec as small_mv
from nsdyn.solve import _kcommon as ki
from nsdyn.solve._kgenalpha import _hermite

NEWTON_MAXITER = 50  # Newton iterations on the friction forces per step
NEWTON_RTOL = 1e-12  # converged when |d phi| <= this * (mu L + |phi|) for every isolator
LS_MAXITER = 30  # backtracking halvings of a Newton correction
K2 = 2.0 / np.pi


@njit(cache=True, error_model="numpy", fastmath=True)
def matvec(W, y, out):
    """out = W y (row-wise sums; ``fastmath`` lets LLVM vectorise them: for the step's large
    operators; :func:`nsdyn._klinalg.matvec` keeps numpy's order for small ones)."""
    for i in range(W.shape[0]):
        s = 0.0
        for j in range(W.shape[1]):
            s += W[i, j] * y[j]
        out[i] = s


@njit(cache=True, error_model="numpy")
def long_mv(A, x):
    """``A @ x`` into a new array by :func:`matvec`: for the contact and isolator rows over all
    n coordinates (numba's ``@`` calls BLAS through SciPy, whose import a cached start would
    pay)."""
    out = np.empty(A.shape[0])
    matvec(A, x, out)
    return out


@njit(cache=True, error_model="numpy")
def _residual(phi, Lc, Ld, w0, Wp, mu, eps, L, v, r):
    """L = Lc + Ld phi, v = w0 + Wp phi, r = phi - mu L s(v); returns |r|."""
    ni = phi.shape[0]
    rr = 0.0
    for i in range(ni):
        li, vi = Lc[i], w0[i]
        for j in range(ni):
            li += Ld[i, j] * phi[j]
            vi += Wp[i, j] * phi[j]
        L[i], v[i] = li, vi
        r[i] = phi[i] - mu[i] * li * K2 * np.arctan(eps * vi)
        rr += r[i] * r[i]
    return np.sqrt(rr)


@njit(cache=True, error_model="numpy")
def friction(phi, Lc, Ld, w0, Wp, mu, eps, work):
    """Solve phi = mu L s(w0 + Wp phi), L = Lc + Ld phi, in place from the guess ``phi``.

    ``work = (J, piv, L, v, r, d, p_new)``. Returns (converged, iterations, last relative
    correction)."""
    J, piv, L, v, r, d, p_new = work
    ni = phi.shape[0]
    r0 = _residual(phi, Lc, Ld, w0, Wp, mu, eps, L, v, r)
    dn = np.inf
    for it in range(1, NEWTON_MAXITER + 1):
        for i in range(ni):
            s = K2 * np.arctan(eps * v[i])
            ds = K2 * eps / (1.0 + (eps * v[i]) ** 2)
            for j in range(ni):
                J[i, j] = (
                    (1.0 if i == j else 0.0) - mu[i] * s * Ld[i, j] - mu[i] * L[i] * ds * Wp[i, j]
                )
            d[i] = r[i]
        if not lu_factor(J, piv, 0.0):
            return False, it, np.inf
        lu_solve(J, piv, d)
        dn = 0.0
        for i in range(ni):
            dn = max(dn, abs(d[i]) / (abs(mu[i] * L[i]) + abs(phi[i]) + 1e-300))
        if not np.isfinite(dn):
            return False, it, dn
        if dn <= NEWTON_RTOL:  # quadratic convergence: this correction is the last
            for i in range(ni):
                phi[i] -= d[i]
            return True, it, dn
        step = 1.0
        rn = r0
        for _ in range(LS_MAXITER):
            for i in range(ni):
                p_new[i] = phi[i] - step * d[i]
            rn = _residual(p_new, Lc, Ld, w0, Wp, mu, eps, L, v, r)
            if rn <= (1.0 - 1e-4 * step) * r0:
                break
            step *= 0.5
        copy_vec(phi, p_new)
        r0 = rn
    return False, NEWTON_MAXITER, dn


@njit(cache=True, error_model="numpy")
def step(t, t_new, A0, state, ops, par, out):
    """One step [t, t_new] from the linear part ``A0`` (module text); updates ``state = (q, v,
    a, phi, lam_old)`` in place, writes the outputs in (t, t_new] and checks the contacts.

    ``ops = (G, RGr_inv, Lam, DGr, Wp, R, D)`` of the step size, ``par = (coef, baum, fr,
    uplift_mode)`` with ``coef = (am, af, beta, gamma)``, ``baum = (alpha, beta)``, ``fr = (mu,
    lam0, eps, frozen, active)``; ``out = (t_eval, X, upl_t, stats, rinfo, work)``.
    Returns (iout, stop): stop on uplift (``uplift_mode`` raise) or a failed step (status set).
    """
    q, v, a, phi, lam_old = state
    G, RGr_inv, Lam, DGr, Wp, R, D = ops
    (am, af, beta, gamma), (ab, bb), fr, uplift_mode = par
    mu, lam0, eps, frozen, active = fr
    t_eval, X, upl_t, stats, rinfo, work = out
    n = q.shape[0]
    nc, ni = R.shape[0], D.shape[0]
    h = t_new - t
    c1, c2 = (1.0 - af) * beta * h * h, (1.0 - af) * gamma * h
    kR = (1.0 - am) + 2.0 * ab * bb * c2 + ab * ab * c1
    qt = q + (1.0 - af) * (h * v + h * h * (0.5 - beta) * a)
    vt = v + (1.0 - af) * h * (1.0 - gamma) * a
    lam_c = np.zeros(nc)
    if nc:
        c0 = kR * long_mv(R, A0) + long_mv(R, am * a + 2.0 * ab * bb * vt + ab * ab * qt)
        lam_c = -small_mv(RGr_inv, c0) / kR
    if active:
        w0 = long_mv(D, vt) + c2 * (long_mv(D, A0) + small_mv(DGr, lam_c))
        Ld = np.zeros((ni, ni))  # normal forces per unit friction force (none when frozen)
        Lc = lam0.copy()
        if not frozen:
            copy_mat(Ld, Lam[:ni])
            copy_vec(Lc, lam_c[:ni])
        conv, n_it, dn = friction(phi, Lc, Ld, w0, c2 * Wp, mu, eps, work)
        stats[ki.S_NFEV] += n_it
        if not conv:
            rinfo[ki.R_T], rinfo[ki.R_H], rinfo[ki.R_RES] = t, h, dn
            fin = np.isfinite(dn) and ki.all_finite(phi)
            stats[ki.S_STATUS] = ki.ST_NEWTON if fin else ki.ST_NONFINITE
            return int(stats[ki.S_NOUT]), True
    else:
        phi[:] = 0.0
    lam_a = lam_c + small_mv(Lam, phi) if nc else np.zeros(0)
    z = np.concatenate((lam_a, phi))
    an = A0 + small_mv(G, z)
    qn = q + h * v + h * h * ((0.5 - beta) * a + beta * an)
    vn = v + h * ((1.0 - gamma) * a + gamma * an)
    if not (ki.all_finite(an) and ki.all_finite(vn)):
        stats[ki.S_STATUS] = ki.ST_NONFINITE
        rinfo[ki.R_T] = t
        return int(stats[ki.S_NOUT]), True
    iout = int(stats[ki.S_NOUT])
    while iout < t_eval.shape[0] and t_eval[iout] <= t_new:
        _hermite(t, h, q, v, a, qn, vn, an, t_eval[iout], X[iout])
        iout += 1
    stats[ki.S_NOUT] = iout
    stats[ki.S_NSTEP] += 1
    # contact monitor on the alpha-point normal forces (the step's constraint forces)
    stop = ki.check_contacts(t, t_new, lam_old, lam_a, upl_t, uplift_mode, stats, rinfo)
    copy_vec(q[:n], qn)
    copy_vec(v[:n], vn)
    copy_vec(a[:n], an)
    copy_vec(lam_old, lam_a)
    if not stop:
        rinfo[ki.R_T] = t_new
    return iout, stop


@njit(cache=True, error_model="numpy")
def run_steps(t, t_steps, u_all, W, A0, state, ops, par, out, max_steps):
    """The steps ending at ``t_steps`` (one step size) from time ``t``: ``A0 = W [q; v; a;
    u_k]`` (dense backend), or the given ``A0`` when ``W`` is empty (one step, sparse backend).
    Stops at the last output, after ``max_steps`` steps or on a failed step (status set).
    Returns the time reached."""
    # borrowed views (nsdyn._kborrow) of the arrays each step passes on: no atomic reference
    # counts for them (``par`` mixes numbers and arrays and stays as it is)
    t_steps, u_all, W, A0, state, ops, out = kb.borrowed((t_steps, u_all, W, A0, state, ops, out))
    q, v, a = state[0], state[1], state[2]
    stats = out[3]
    n = q.shape[0]
    y_own = np.empty(W.shape[1])
    y = kb.borrowed(y_own)
    for k in range(t_steps.shape[0]):
        if stats[ki.S_NOUT] >= out[0].shape[0]:
            break
        if stats[ki.S_NSTEP] >= max_steps:
            stats[ki.S_STATUS] = ki.ST_MAX_STEPS
            break
        if W.shape[0]:
            copy_vec(y[:n], q)
            copy_vec(y[n : 2 * n], v)
            copy_vec(y[2 * n : 3 * n], a)
            copy_vec(y[3 * n :], u_all[k])
            matvec(W, y, A0)
        _, stop = step(t, t_steps[k], A0, state, ops, par, out)
        if stop:
            break
        t = t_steps[k]
    kb.alive(y_own)
    return t


# ---- the "operators" backend: sparse products and triangular solves in the loop -------------


@njit(cache=True, error_model="numpy")
def csr_matvec(indptr, indices, data, x, out):
    """out = A x for A in CSR form."""
    for i in range(out.shape[0]):
        s = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            s += data[k] * x[indices[k]]
        out[i] = s


@njit(cache=True, error_model="numpy")
def lu_solve_sparse(lu, b, work, x):
    """x = S^-1 b from SuperLU's factors ``Pr S Pc = L U`` (``lu = (Lp, Li, Lx, Up, Ui, Ux,
    Ud, perm_r, perm_c)``: L unit lower and U upper in CSC form, ``Ud`` U's diagonal)."""
    Lp, Li, Lx, Up, Ui, Ux, Ud, perm_r, perm_c = lu
    n = b.shape[0]
    for i in range(n):
        work[perm_r[i]] = b[i]
    for j in range(n):  # L y = Pr b (unit diagonal)
        wj = work[j]
        if wj != 0.0:
            for k in range(Lp[j], Lp[j + 1]):
                i = Li[k]
                if i > j:
                    work[i] -= Lx[k] * wj
    for j in range(n - 1, -1, -1):  # U z = y
        wj = work[j] / Ud[j]
        work[j] = wj
        if wj != 0.0:
            for k in range(Up[j], Up[j + 1]):
                i = Ui[k]
                if i < j:
                    work[i] -= Ux[k] * wj
    for i in range(n):
        x[i] = work[perm_c[i]]


@njit(cache=True, error_model="numpy")
def lu_solve_rows(lu, B, X):
    """Row k of X = S^-1 (row k of B), for every row."""
    work = np.empty(B.shape[1])
    for k in range(B.shape[0]):
        lu_solve_sparse(lu, B[k], work, X[k])


@njit(cache=True, error_model="numpy")
def _lowrank_apply(U, w, s):
    """s = U^T w."""
    for j in range(U.shape[1]):
        s[j] = 0.0
    for i in range(U.shape[0]):
        wi = w[i]
        for j in range(U.shape[1]):
            s[j] += U[i, j] * wi


@njit(cache=True, error_model="numpy")
def linear_part(q, v, a, u, lin, lr, y, r, work, modal, A0):
    """A0 = -S_M^-1 (W [q; v; a] + M Gamma u + U diag(c) U^T (v + ka_v a)) with the
    Woodbury correction of the low-rank damping (:mod:`nsdyn.solve.sparse`), and its modal
    coordinates U^T A0. The damping force enters through ``uv, ua = U^T v, U^T a`` (``modal
    = (uv, ua, uA0, s1, s2)``, carried by :func:`run_steps_ops`): with ``y = S^-1 r`` and
    ``w = c (uv + ka_v ua)``, ``-A0 = y + Z xi``, ``xi = w - cap (U^T y + U^T Z w)`` and
    ``-U^T A0 = U^T y + U^T Z xi``: two passes over n x m arrays (``U^T y``, ``Z xi``), each
    a row-wise :func:`matvec`."""
    Wp, Wi, Wx, MG, lu = lin
    Ut, c, kav, Z, capi, UtZ, _ = lr
    uv, ua, uA0, s1, s2 = modal
    n, m = q.shape[0], c.shape[0]
    copy_vec(y[:n], q)
    copy_vec(y[n : 2 * n], v)
    copy_vec(y[2 * n :], a)
    csr_matvec(Wp, Wi, Wx, y, r)
    for i in range(n):
        r[i] += MG[i, 0] * u[0] + MG[i, 1] * u[1]
    lu_solve_sparse(lu, r, work, A0)
    if m:
        for j in range(m):
            s1[j] = c[j] * (uv[j] + kav * ua[j])  # w
        matvec(Ut, A0, uA0)  # U^T y
        matvec(UtZ, s1, s2)
        for j in range(m):
            work[j] = uA0[j] + s2[j]
        matvec(capi, work[:m], s2)
        for j in range(m):
            s2[j] = s1[j] - s2[j]  # xi
        matvec(Z, s2, r)
        for i in range(n):
            A0[i] += r[i]
        matvec(UtZ, s2, s1)
        for j in range(m):
            uA0[j] = -(uA0[j] + s1[j])
    for i in range(n):
        A0[i] = -A0[i]


@njit(cache=True, error_model="numpy")
def run_steps_ops(t, t_steps, u_all, lin, lr, A0, state, ops, par, out, max_steps):
    """The steps ending at ``t_steps`` (one step size) of the ``"operators"`` backend: the
    linear part by :func:`linear_part`, the rest by :func:`step`, and the damped modes'
    coordinates ``U^T v``, ``U^T a`` carried along (``U^T a_(n+1) = U^T A0 + (U^T G) [lam;
    phi]``, then the Newmark update of ``U^T v``). Returns the time reached."""
    q, v, a, phi, lam = state[0], state[1], state[2], state[3], state[4]
    stats = out[3]
    gamma = par[0][3]
    n, m = q.shape[0], lr[1].shape[0]
    Ut, UtG = lr[0], lr[6]
    nc = lam.shape[0]
    y, r, work = np.empty(3 * n), np.empty(n), np.empty(max(n, m))
    modal = (np.empty(m), np.empty(m), np.empty(m), np.empty(m), np.empty(m))
    uv, ua, uA0 = modal[0], modal[1], modal[2]
    if m:
        matvec(Ut, v, uv)
        matvec(Ut, a, ua)
    z = np.empty(UtG.shape[1])
    for k in range(t_steps.shape[0]):
        if stats[ki.S_NOUT] >= out[0].shape[0]:
            break
        if stats[ki.S_NSTEP] >= max_steps:
            stats[ki.S_STATUS] = ki.ST_MAX_STEPS
            break
        linear_part(q, v, a, u_all[k], lin, lr, y, r, work, modal, A0)
        _, stop = step(t, t_steps[k], A0, state, ops, par, out)
        if stop:
            break
        if m:  # a_(n+1) = A0 + G [lam; phi]: its modal coordinates, then v's update
            h = t_steps[k] - t
            copy_vec(z[:nc], lam)
            copy_vec(z[nc:], phi)
            for j in range(m):
                acc = uA0[j]
                for i in range(z.shape[0]):
                    acc += UtG[j, i] * z[i]
                uv[j] += h * ((1.0 - gamma) * ua[j] + gamma * acc)
                ua[j] = acc
        t = t_steps[k]
    return t


@njit(cache=True, error_model="numpy")
def accelerations_rows(X, u, lin0, lr0, A0):
    """Row k of A0 = -M^-1 (W0 x_k + M Gamma u_k + U diag(c) U^T qd_k) for the states
    ``x_k = [q; qd]`` (rows of ``X``): the linear part of the accelerations along a history
    (``lin0 = (W0 CSR = [K*, C], M Gamma, M's LU)``, ``lr0 = (U, c)``)."""
    Wp, Wi, Wx, MG, lu = lin0
    U, c = lr0
    nt, n = A0.shape
    m = c.shape[0]
    r, work, s1 = np.empty(n), np.empty(n), np.empty(m)
    for k in range(nt):
        x = X[k]
        csr_matvec(Wp, Wi, Wx, x, r)
        for i in range(n):
            r[i] += MG[i, 0] * u[k, 0] + MG[i, 1] * u[k, 1]
        if m:
            _lowrank_apply(U, x[n:], s1)
            for j in range(m):
                s1[j] *= c[j]
            matvec(U, s1, work)
            for i in range(n):
                r[i] += work[i]
        row = A0[k]
        lu_solve_sparse(lu, r, work, row)
        for i in range(n):
            row[i] = -row[i]
