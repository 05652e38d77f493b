"""The tables of the switch model's mode sets (:mod:`nsdyn.periodic.switch`): each mode set's
augmented matrix and its sliding-velocity, friction-force and normal-force rows, read off the
system kernel; the isolators tied to one sliding velocity; the state balancing.
"""

from __future__ import annotations

import numpy as np

from nsdyn._lazy import LazyModule
from nsdyn.models.isolated import _kernel as ks
from nsdyn.models.isolated.params import with_law

sla = LazyModule("scipy.linalg")  # the switch model only: an arctan-law sweep never imports it


def mode_sets(ni: int) -> np.ndarray:
    """All mode sets (3^ni, ni) in the order of :func:`nsdyn.periodic._kswitch.mode_index`."""
    K = 3**ni
    out = np.empty((K, ni), dtype=np.int64)
    for k in range(K):
        r = k
        for i in range(ni):
            out[k, i] = r % 3 - 1
            r //= 3
    return out


def tied_groups(VQ: np.ndarray) -> np.ndarray:
    """The group of each isolator (ni,): isolators whose sliding velocities are one on the
    minimal coordinates (equal rows ``D_i Q``, to round-off: a rigid deck's, a rigid
    fidelity's) share a group; the others are alone in theirs. Groups are numbered in the
    order of their first isolator."""
    ni = VQ.shape[0]
    scale = float(np.abs(VQ).max()) if VQ.size else 0.0
    group = np.full(ni, -1, dtype=np.int64)
    g = 0
    for i in range(ni):
        if group[i] >= 0:
            continue
        same = np.abs(VQ - VQ[i]).max(axis=1) <= 1e-12 * scale
        group[same & (group < 0)] = g
        g += 1
    return group


def mode_tables(system, P: tuple, Q: np.ndarray, sets: np.ndarray) -> tuple:
    """Per mode set (``sets``, (K, ni) isolator modes): A_k with the forcing columns (K, D, D)
    at w = 0, and the rows V, TAU, LF."""
    n, m = Q.shape
    d = 2 * m
    Dd = d + 3
    ni = system.n_isolators
    L = np.zeros((2 * n, d))
    L[:n, :m] = Q
    L[n:, m:] = Q
    K = sets.shape[0]
    A0 = np.zeros((K, Dd, Dd))
    TAU = np.zeros((K, ni, Dd))
    LF = np.zeros((K, ni, Dd))
    frozen = int(P[ks.I_IPAR][ks.K_FROZEN]) == 1
    lam0 = P[ks.I_LAM0]
    nc = system.n_contacts
    J = np.zeros((2 * n, 2 * n))
    out = np.zeros(2 * n)
    qdd, lam, tau, md = ks.outputs(P)
    times = (0.0, 0.25, 0.5)  # forcing at f = 1 Hz: (sin, cos) = (0, 1), (1, 0), (0, -1)
    for k in range(K):
        Pk = with_law(P, "modes", sets[k])
        ks.jac(0.0, np.zeros(2 * n), Pk, J)
        A0[k, :d, :d] = L.T @ J @ L
        g = []
        fr = []
        for t in times:
            ks.rhs(t, np.zeros(2 * n), Pk, out)
            g.append(L.T @ out)
            ks.evaluate(t, np.zeros(2 * n), Pk, qdd, lam, tau, md)
            fr.append((tau.copy(), lam.copy()))
        g0 = 0.5 * (g[0] + g[2])
        A0[k, :d, d], A0[k, :d, d + 1], A0[k, :d, d + 2] = g0, g[1] - g0, g[0] - g0
        for rows, j in ((TAU, 0), (LF, 1)):
            v0, v1, v2 = (fr[s][j] for s in range(3))
            c0 = 0.5 * (v0 + v2)
            cols = np.column_stack([c0, v1 - c0, v0 - c0])
            if j == 1:
                cols = np.vstack([cols, np.zeros((max(ni - nc, 0), 3))])[:ni]
            rows[k, :, d:] = cols
        for jj in range(d):
            ks.evaluate(0.0, L[:, jj].copy(), Pk, qdd, lam, tau, md)
            TAU[k, :, jj] = tau - fr[0][0]
            lcol = np.zeros(ni)
            lcol[: min(nc, ni)] = (lam - fr[0][1])[: min(nc, ni)]
            LF[k, :, jj] = lcol
        if frozen:
            LF[k] = 0.0
            LF[k, :, d] = lam0
    V = np.zeros((ni, Dd))
    V[:, m:d] = system.D @ Q
    return A0, V, TAU, LF


def balancing(A0: np.ndarray) -> np.ndarray:
    """Diagonal state scaling ``s`` (D,) (powers of 2) with ``diag(1/s) A_k diag(s)`` balanced
    for every mode set (Parlett-Reinsch on ``sum_k |A_k|``). The minimal coordinates mix
    metres of soft and stiff directions, so ``|A_k|_1`` is ~1e6 times its spectral radius;
    balanced, the matrix exponential needs ~20 fewer squarings and keeps its accuracy. The
    forcing states keep scale 1 (the kernel starts them at ``[1, 0, 1]``; their rotation
    block stays ``+-w``)."""
    M = np.abs(A0).sum(axis=0)
    D = M.shape[0]
    M[D - 2, D - 1] = M[D - 1, D - 2] = 1.0  # couple sin and cos as the w entries will
    _, (sc, _) = sla.matrix_balance(M, permute=False, separate=True)
    sc = np.asarray(sc, dtype=float) / 2.0 ** np.round(np.log2(sc[D - 2 :]).mean())
    sc[D - 3 :] = 1.0  # the kernel starts the forcing states at [1, 0, 1]
    return sc
