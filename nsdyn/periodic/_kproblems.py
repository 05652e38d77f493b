"""Numba right-hand sides and Jacobians of the periodic problems, dispatched on an integer id.

Problems (dispatched on an integer id, right-hand sides called as module globals so the
kernels are cached across processes):

- ``PROB_FRAME``: the isolated structure on the contact manifold (seed 004 eqs 23-27),
  ``x = [z, zd]``, ``q = Q z``, ``zdd = Q^T qdd(Q z, Q zd)`` (Q orthonormal columns): the
  constrained equations of :mod:`nsdyn.models.isolated._kernel` (its tuple ``P`` supplies the
  ground motion and friction settings) written on the manifold with the products of ``Z``
  precomputed. On the manifold this equals ``[Q^T 0; 0 Q^T] ks.rhs([Q z, Q zd])`` with Jacobian
  ``blockdiag(Q^T) ks.jac blockdiag(Q)`` (checked in the tests) at a fraction of the cost.
- ``PROB_DUFFING``: ``x'' + 2 zeta w0 x' + w0^2 x + gamma x^3 = F cos(w t)``,
  ``pf = [zeta, w0, gamma, F, w]`` (``P`` is a dummy tuple of the same type).
"""

import numpy as np
from numba import njit

from nsdyn._klinalg import lu_factor, lu_solve_columns
from nsdyn.models.isolated import _kernel as ks

PROB_FRAME = 0  # isolated structure on minimal coordinates (eq 27 with precomputed Z)
PROB_DUFFING = 1  # Duffing oscillator, pf = [zeta, w0, gamma, F, w]


LU_RTOL = 1e-15  # a pivot below this times the largest entry counts as singular


# ---- layout of the manifold tuple Z (all 2-D float arrays) -------------------------------------
# q = Q z; a0 = M^-1 h = -MiK q - MiC qd - Gamma u; every product below is precomputed once.
Z_Q, Z_QT = 0, 1  # Q (n, m), Q^T (m, n)
Z_KZ, Z_CZ = 2, 3  # Q^T MiK Q, Q^T MiC Q (m, m)
Z_QG = 4  # Q^T Gamma (m, 2)
Z_QMIRT, Z_QMIDT = 5, 6  # Q^T M^-1 R^T (m, nc), Q^T M^-1 D^T (m, ni)
Z_RAZ, Z_RAV = 7, 8  # R MiK Q, R MiC Q (nc, m)
Z_RG = 9  # R Gamma (nc, 2)
Z_G0, Z_GD = 10, 11  # R M^-1 R^T (nc, nc), R M^-1 D^T (nc, ni)
Z_DQ = 12  # D Q (ni, m): sliding velocities v = D Q zd
Z_MU, Z_L0 = 13, 14  # (1, ni) friction coefficients, static normal forces
N_Z = 15


# ---- right-hand sides ----------------------------------------------------------------------
@njit(cache=True)
def duffing_rhs(t, x, pf, out):
    zeta, w0, gamma, F, w = pf[0], pf[1], pf[2], pf[3], pf[4]
    out[0] = x[1]
    out[1] = F * np.cos(w * t) - 2.0 * zeta * w0 * x[1] - w0 * w0 * x[0] - gamma * x[0] ** 3


@njit(cache=True)
def duffing_jac(t, x, pf, J):
    zeta, w0, gamma = pf[0], pf[1], pf[2]
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0] = -w0 * w0 - 3.0 * gamma * x[0] ** 2
    J[1, 1] = -2.0 * zeta * w0


@njit(cache=True)
def _frame_core(t, x, P, Z, out, J):
    """Seed eqs (25)-(27) on the manifold for the smooth laws ("none", "arctan").

    ``M qdd = h + R^T lam - D^T diag(mu s) L`` with ``R qdd = 0`` (R Q = 0: the Baumgarte
    terms vanish), ``L = lam`` (or the static normal forces when frozen):
    ``G lam = r``, ``G = R M^-1 R^T - [R M^-1 D^T diag(mu s)]`` (bracket only when not frozen),
    ``r = -R a0 (+ R M^-1 D^T diag(mu s) L0 when frozen)``, ``zdd = Q^T qdd``.
    The Jacobian differentiates these formulas (``dlam = G^-1 (dr - dG lam)``); it is formed
    when J is square (d x d), not for the (1, d) placeholder of :func:`f_eval` (a flag
    argument would be a literal constant at both call sites, and numba would compile this
    function twice).
    """
    want_jac = J.shape[0] == x.shape[0]
    m = Z[Z_KZ].shape[0]
    nc = Z[Z_G0].shape[0]
    ni = Z[Z_DQ].shape[0]
    ip = P[ks.I_IPAR]
    fp = P[ks.I_FPAR]
    law = ip[ks.K_LAW]
    frozen = ip[ks.K_FROZEN] == 1
    eps = fp[ks.F_EPS]
    uh, uv = ks.ground_accel(t, P)
    uv += fp[ks.F_G]
    z = x[:m]
    zd = x[m:]
    Kz, Cz, QG = Z[Z_KZ], Z[Z_CZ], Z[Z_QG]
    QMiRT, QMiDT = Z[Z_QMIRT], Z[Z_QMIDT]
    RAz, RAv, RG = Z[Z_RAZ], Z[Z_RAV], Z[Z_RG]
    G0, GD, DQ = Z[Z_G0], Z[Z_GD], Z[Z_DQ]
    mu = Z[Z_MU][0]
    L0 = Z[Z_L0][0]
    # friction directions
    s = np.zeros(ni)
    sp = np.zeros(ni)
    if law == ks.LAW_ARCTAN:
        for i in range(ni):
            v = 0.0
            for k in range(m):
                v += DQ[i, k] * zd[k]
            s[i] = (2.0 / np.pi) * np.arctan(eps * v)
            sp[i] = (2.0 / np.pi) * eps / (1.0 + (eps * v) ** 2)
    # constraint system G lam = r  (nc x nc)
    G = np.empty((nc, nc))
    r = np.empty(nc)
    for a in range(nc):
        acc = RG[a, 0] * uh + RG[a, 1] * uv  # -R a0 = R Gamma u + R MiK q + R MiC qd
        for k in range(m):
            acc += RAz[a, k] * z[k] + RAv[a, k] * zd[k]
        r[a] = acc
        for b in range(nc):
            G[a, b] = G0[a, b]
        for i in range(ni):
            if frozen:
                r[a] += GD[a, i] * mu[i] * s[i] * L0[i]
            elif i < nc:
                G[a, i] -= GD[a, i] * mu[i] * s[i]
    lam, ok = ks._small_solve(G, r, nc)
    if not ok:
        return False
    # friction force magnitudes f_i = mu s L
    fr = np.empty(ni)
    for i in range(ni):
        L = L0[i] if frozen else (lam[i] if i < nc else 0.0)
        fr[i] = mu[i] * s[i] * L
    for k in range(m):
        acc = -(QG[k, 0] * uh + QG[k, 1] * uv)
        for j in range(m):
            acc -= Kz[k, j] * z[j] + Cz[k, j] * zd[j]
        for a in range(nc):
            acc += QMiRT[k, a] * lam[a]
        for i in range(ni):
            acc -= QMiDT[k, i] * fr[i]
        out[k] = zd[k]
        out[m + k] = acc
    if not want_jac:
        return True
    # d zdd = -Kz dz - Cz dzd + QMiRT dlam - QMiDT (diag(mu s) dL + diag(mu L s') DQ dzd)
    # dlam = G^-1 (dr - dG lam), dr = RAz dz + RAv dzd (+ GD diag(mu L0 s') DQ dzd frozen),
    # dG lam = -GD diag(mu lam s') DQ dzd (not frozen)
    Glu = G.copy()
    gpiv = np.zeros(nc, dtype=np.int64)
    if not lu_factor(Glu, gpiv, LU_RTOL):
        return False
    cfr = np.empty(ni)  # d f_i / d v_i at fixed L
    for i in range(ni):
        L = L0[i] if frozen else (lam[i] if i < nc else 0.0)
        cfr[i] = mu[i] * L * sp[i]
    # dr/dx (nc, 2m), then dlam/dx = G^-1 drx
    drx = np.zeros((nc, 2 * m))
    for a in range(nc):
        for k in range(m):
            drx[a, k] = RAz[a, k]
            drx[a, m + k] = RAv[a, k]
        for i in range(ni):
            g = GD[a, i] * cfr[i]
            if g != 0.0:
                for k in range(m):
                    drx[a, m + k] += g * DQ[i, k]
    lu_solve_columns(Glu, gpiv, drx)
    dlam = drx  # (nc, 2m)
    # effective B = QMiRT - QMiDT diag(mu s) (on lam, not frozen)
    J[:, :] = 0.0
    for k in range(m):
        J[k, m + k] = 1.0
    for k in range(m):
        for j in range(m):
            J[m + k, j] = -Kz[k, j]
            J[m + k, m + j] = -Cz[k, j]
        for a in range(nc):
            b = QMiRT[k, a]
            if not frozen and a < ni:
                b -= QMiDT[k, a] * mu[a] * s[a]
            if b != 0.0:
                for j in range(2 * m):
                    J[m + k, j] += b * dlam[a, j]
        for i in range(ni):
            g = QMiDT[k, i] * cfr[i]
            if g != 0.0:
                for j in range(m):
                    J[m + k, m + j] -= g * DQ[i, j]
    return True


@njit(cache=True)
def f_eval(prob, t, x, P, Z, pf, out):
    """Right-hand side of problem ``prob`` on its state ``x``; returns False on failure."""
    if prob == PROB_FRAME:
        return _frame_core(t, x, P, Z, out, out.reshape((1, -1)))
    duffing_rhs(t, x, pf, out)
    return True


@njit(cache=True)
def j_eval(prob, t, x, P, Z, pf, F, J):
    """Right-hand side ``F`` and Jacobian ``J = dF/dx`` of problem ``prob``; returns ok."""
    if prob == PROB_FRAME:
        return _frame_core(t, x, P, Z, F, J)
    duffing_rhs(t, x, pf, F)
    duffing_jac(t, x, pf, J)
    return True
