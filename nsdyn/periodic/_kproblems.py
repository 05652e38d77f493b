"""Numba right-hand sides and Jacobians of the periodic problems, dispatched on an integer id.

Problems (dispatched on an integer id, right-hand sides called as module globals so the
kernels are cached across processes):

- ``PROB_FRAME``: the isolated structure on the contact manifold (seed 004 eqs 23-27),
  ``x = [z, zd]``, ``q = Q z``, ``zdd = Q^T qdd(Q z, Q zd)`` (Q orthonormal columns): the
  constrained equations of :mod:`nsdyn.models.isolated._kernel` (its tuple ``P`` supplies the
  ground motion and friction settings) written on the manifold with the products of ``Z``
  precomputed, read from one flat array ``pf`` (:func:`pack_frame`). On the manifold this
  equals ``[Q^T 0; 0 Q^T] ks.rhs([Q z, Q zd])`` with Jacobian
  ``blockdiag(Q^T) ks.jac blockdiag(Q)`` (checked in the tests) at a fraction of the cost.
- ``PROB_DUFFING``: ``x'' + 2 zeta w0 x' + w0^2 x + gamma x^3 = F cos(w t)``,
  ``pf = [zeta, w0, gamma, F, w]``.
"""

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn._klinalg import lu_factor_flat, lu_solve_flat
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
@njit(cache=True, error_model="numpy")
def duffing_rhs(t, x, pf, out):
    zeta, w0, gamma, F, w = pf[0], pf[1], pf[2], pf[3], pf[4]
    out[0] = x[1]
    out[1] = F * np.cos(w * t) - 2.0 * zeta * w0 * x[1] - w0 * w0 * x[0] - gamma * x[0] ** 3


@njit(cache=True, error_model="numpy")
def duffing_jac(t, x, pf, J):
    zeta, w0, gamma = pf[0], pf[1], pf[2]
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0] = -w0 * w0 - 3.0 * gamma * x[0] ** 2
    J[1, 1] = -2.0 * zeta * w0


# ---- the frame's right-hand side and Jacobian from one flat array -----------------------------
# ``pf`` of PROB_FRAME: a header, the harmonic excitation's parameters, the matrices of Z in
# row-major order and scratch, at the offsets of _frame_offsets (packed by pack_frame). Reading
# them from one array instead of the tuples P and Z spares numba the reference counting of ~30
# arrays on every call (the stage Newton evaluates ~6 times per step) and the allocations.
FH_M, FH_NC, FH_NI, FH_ARCTAN, FH_FROZEN, FH_EPS, FH_G = range(7)
FH_GPAR = 7  # the excitation's parameters (ks.N_GPAR of them; harmonic)
FH_END = FH_GPAR + ks.N_GPAR
G_RTOL = 1e-14  # a pivot of G below this times its largest entry: singular (as _kernel)


O_LAM = 17  # the position of o_lam (the multipliers) in the tuple of _frame_offsets


@njit(cache=True, error_model="numpy", inline="always")
def _frame_offsets(m, nc, ni):
    """Offsets in the flat array: Kz, Cz (m, m), QG (m, 2), QMiRT (m, nc), QMiDT (m, ni), RAz,
    RAv (nc, m), RG (nc, 2), G0 (nc, nc), GD (nc, ni), DQ (ni, m), mu, L0 (ni); scratch s, s'
    (ni), G (nc, nc), its pivots (nc), lam (nc), dlam/dx (nc, 2m); the end."""
    o_kz = FH_END
    o_cz = o_kz + m * m
    o_qg = o_cz + m * m
    o_qmirt = o_qg + 2 * m
    o_qmidt = o_qmirt + m * nc
    o_raz = o_qmidt + m * ni
    o_rav = o_raz + nc * m
    o_rg = o_rav + nc * m
    o_g0 = o_rg + 2 * nc
    o_gd = o_g0 + nc * nc
    o_dq = o_gd + nc * ni
    o_mu = o_dq + ni * m
    o_l0 = o_mu + ni
    o_s = o_l0 + ni
    o_sp = o_s + ni
    o_g = o_sp + ni
    o_piv = o_g + nc * nc
    o_lam = o_piv + nc
    o_dl = o_lam + nc
    end = o_dl + 2 * m * nc
    return (o_kz, o_cz, o_qg, o_qmirt, o_qmidt, o_raz, o_rav, o_rg, o_g0, o_gd, o_dq, o_mu, o_l0,
            o_s, o_sp, o_g, o_piv, o_lam, o_dl, end)  # fmt: skip


def pack_frame(P: tuple, Z: tuple) -> np.ndarray:
    """The flat array of a frame problem under the harmonic excitation of ``P`` (its header,
    excitation parameters and the matrices of ``Z``; see :func:`_frame_offsets`)."""
    ip, fp = P[ks.I_IPAR], P[ks.I_FPAR]
    if ip[ks.K_GROUND] != ks.GROUND_HARMONIC:
        raise ValueError("pack_frame: the periodic frame problem needs a harmonic excitation")
    m, nc, ni = Z[Z_KZ].shape[0], Z[Z_G0].shape[0], Z[Z_DQ].shape[0]
    head = np.zeros(FH_END)
    head[FH_M], head[FH_NC], head[FH_NI] = m, nc, ni
    head[FH_ARCTAN] = 1.0 if ip[ks.K_LAW] == ks.LAW_ARCTAN else 0.0
    head[FH_FROZEN] = 1.0 if ip[ks.K_FROZEN] == 1 else 0.0
    head[FH_EPS], head[FH_G] = fp[ks.F_EPS], fp[ks.F_G]
    head[FH_GPAR:FH_END] = P[ks.I_GPAR]
    keys = (Z_KZ, Z_CZ, Z_QG, Z_QMIRT, Z_QMIDT, Z_RAZ, Z_RAV, Z_RG, Z_G0, Z_GD, Z_DQ)
    blocks = [Z[k] for k in keys] + [Z[Z_MU][0], Z[Z_L0][0]]
    blocks.append(np.zeros(2 * ni + nc * nc + 2 * nc + 2 * m * nc))  # scratch
    F = np.concatenate([head] + [np.ascontiguousarray(b, dtype=float).ravel() for b in blocks])
    assert F.size == _frame_offsets(m, nc, ni)[-1]
    return F


@njit(cache=True, error_model="numpy")
def frame_flat(t, x, F, out):
    """The frame's right-hand side on the manifold from the flat array ``F`` of
    :func:`pack_frame`, seed eqs (25)-(27) for the smooth laws ("none", "arctan"): ``out``, and
    s, s', the factors of G and lam in its scratch. False when G is singular.

    Compiled once and called (:func:`frame_flat_jac` calls it too): inlined, numba copies a
    function's IR once per block with its whole variable scope (~5 s of a sweep's first
    compilation when the Jacobian inlined it as well).

    ``M qdd = h + R^T lam - D^T diag(mu s) L`` with ``R qdd = 0`` (R Q = 0: the Baumgarte
    terms vanish), ``L = lam`` (or the static normal forces when frozen):
    ``G lam = r``, ``G = R M^-1 R^T - [R M^-1 D^T diag(mu s)]`` (bracket only when not frozen),
    ``r = -R a0 (+ R M^-1 D^T diag(mu s) L0 when frozen)``, ``zdd = Q^T qdd``.
    """
    m, nc, ni = int(F[FH_M]), int(F[FH_NC]), int(F[FH_NI])
    (o_kz, o_cz, o_qg, o_qmirt, o_qmidt, o_raz, o_rav, o_rg, o_g0, o_gd, o_dq, o_mu, o_l0, o_s,
     o_sp, o_g, o_piv, o_lam, _, _) = _frame_offsets(m, nc, ni)  # fmt: skip
    frozen = F[FH_FROZEN] != 0.0
    eps = F[FH_EPS]
    g = FH_GPAR
    uh = F[g + ks.G_AH] * np.sin(2.0 * np.pi * F[g + ks.G_FH] * t + F[g + ks.G_PH])
    uv = F[g + ks.G_AV] * np.sin(2.0 * np.pi * F[g + ks.G_FV] * t + F[g + ks.G_PV]) + F[FH_G]
    # friction directions and their slopes
    for i in range(ni):
        si = 0.0
        spi = 0.0
        if F[FH_ARCTAN] != 0.0:
            v = 0.0
            for k in range(m):
                v += F[o_dq + i * m + k] * x[m + k]
            si = (2.0 / np.pi) * np.arctan(eps * v)
            spi = (2.0 / np.pi) * eps / (1.0 + (eps * v) ** 2)
        F[o_s + i] = si
        F[o_sp + i] = spi
    # constraint system G lam = r (nc x nc)
    for a in range(nc):
        acc = F[o_rg + 2 * a] * uh + F[o_rg + 2 * a + 1] * uv
        for k in range(m):
            acc += F[o_raz + a * m + k] * x[k] + F[o_rav + a * m + k] * x[m + k]
        F[o_lam + a] = acc
        for b in range(nc):
            F[o_g + a * nc + b] = F[o_g0 + a * nc + b]
        for i in range(ni):
            gdi = F[o_gd + a * ni + i] * F[o_mu + i] * F[o_s + i]
            if frozen:
                F[o_lam + a] += gdi * F[o_l0 + i]
            elif i < nc:
                F[o_g + a * nc + i] -= gdi
    # LU of G with partial pivoting (the pivot floor of nsdyn._klinalg.solve_small), then lam
    if not lu_factor_flat(F, o_g, nc, o_piv, G_RTOL):
        return False
    lu_solve_flat(F, o_g, o_piv, nc, F, o_lam, 1, 1)
    for k in range(m):
        acc = -(F[o_qg + 2 * k] * uh + F[o_qg + 2 * k + 1] * uv)
        for j in range(m):
            acc -= F[o_kz + k * m + j] * x[j] + F[o_cz + k * m + j] * x[m + j]
        for a in range(nc):
            acc += F[o_qmirt + k * nc + a] * F[o_lam + a]
        for i in range(ni):
            L = F[o_l0 + i] if frozen else (F[o_lam + i] if i < nc else 0.0)
            acc -= F[o_qmidt + k * ni + i] * (F[o_mu + i] * F[o_s + i] * L)
        out[k] = x[m + k]
        out[m + k] = acc
    return True


@njit(cache=True, error_model="numpy")
def frame_flat_jac(t, x, F, out, J):
    """:func:`frame_flat` and its Jacobian ``J = d out / dx``, the formulas differentiated:

    ``d zdd = -Kz dz - Cz dzd + QMiRT dlam - QMiDT (diag(mu s) dL + diag(mu L s') DQ dzd)``,
    ``dlam = G^-1 (dr - dG lam)`` with ``dr = RAz dz + RAv dzd`` (``+ GD diag(mu L0 s') DQ dzd``
    frozen) and ``dG lam = -GD diag(mu lam s') DQ dzd`` (not frozen).
    """
    if not frame_flat(t, x, F, out):  # called: see frame_flat
        return False
    m, nc, ni = int(F[FH_M]), int(F[FH_NC]), int(F[FH_NI])
    (o_kz, o_cz, _, o_qmirt, o_qmidt, o_raz, o_rav, _, _, o_gd, o_dq, o_mu, o_l0, o_s, o_sp, o_g,
     o_piv, o_lam, o_dl, _) = _frame_offsets(m, nc, ni)  # fmt: skip
    frozen = F[FH_FROZEN] != 0.0
    m2 = 2 * m
    # dr/dx into dlam's rows, then dlam/dx = G^-1 dr/dx; cfr_i = d f_i / d v_i at fixed L is
    # mu_i L_i s'_i (kept in the s' slots)
    for i in range(ni):
        L = F[o_l0 + i] if frozen else (F[o_lam + i] if i < nc else 0.0)
        F[o_sp + i] = F[o_mu + i] * L * F[o_sp + i]
    for a in range(nc):
        for k in range(m):
            F[o_dl + a * m2 + k] = F[o_raz + a * m + k]
            F[o_dl + a * m2 + m + k] = F[o_rav + a * m + k]
        for i in range(ni):
            g = F[o_gd + a * ni + i] * F[o_sp + i]
            if g != 0.0:
                for k in range(m):
                    F[o_dl + a * m2 + m + k] += g * F[o_dq + i * m + k]
    lu_solve_flat(F, o_g, o_piv, nc, F, o_dl, m2, m2)
    for k in range(m):
        for j in range(m2):
            J[k, j] = 0.0
        J[k, m + k] = 1.0
    for k in range(m):
        for j in range(m):
            J[m + k, j] = -F[o_kz + k * m + j]
            J[m + k, m + j] = -F[o_cz + k * m + j]
        for a in range(nc):
            b = F[o_qmirt + k * nc + a]
            if not frozen and a < ni:
                b -= F[o_qmidt + k * ni + a] * F[o_mu + a] * F[o_s + a]
            if b != 0.0:
                for j in range(m2):
                    J[m + k, j] += b * F[o_dl + a * m2 + j]
        for i in range(ni):
            g = F[o_qmidt + k * ni + i] * F[o_sp + i]
            if g != 0.0:
                for j in range(m):
                    J[m + k, m + j] -= g * F[o_dq + i * m + j]
    return True


@njit(cache=True, error_model="numpy")
def f_eval(prob, t, x, pf, out):
    """Right-hand side of problem ``prob`` on its state ``x`` (``pf``: the flat array of
    :func:`pack_frame` for a frame, the parameters for Duffing); returns False on failure."""
    if prob == PROB_FRAME:
        return frame_flat(t, x, pf, out)
    duffing_rhs(t, x, pf, out)
    return True


@njit(cache=True, error_model="numpy")
def j_eval(prob, t, x, pf, F, J):
    """Right-hand side ``F`` and Jacobian ``J = dF/dx`` of problem ``prob``; returns ok."""
    if prob == PROB_FRAME:
        return frame_flat_jac(t, x, pf, F, J)
    duffing_rhs(t, x, pf, F)
    duffing_jac(t, x, pf, J)
    return True


# the period map's calls of the Jacobian and (from its step) the right-hand side
# (:mod:`nsdyn._kaddress`): indices 0 and 1 of its K
ka.slot("periodic.jeval", 0, j_eval)
ka.slot("periodic.feval", 1, f_eval)
