"""Kernels of the sparse pair path: the bearings' forces and derivatives, the isolator Newton.

One generalized-α step (:mod:`nsdyn.models.isolated.pairs_sparse_run`) leaves, after the sparse
solve, only the isolators' forces F (2ni: F_x, F_y of each) unknown: the normal forces and the
slip accelerations are affine in them,

    λ = λ₀ + Λ F,   D2 a = w₀ + W F,   u = u_q + c₁ D2 a,   v = u_v + c₂ D2 a,

and the bearings' law closes the system, r(F) = F − F_b(u, v, λ) = 0, with isolator i's

    F_b,i = λ_i (u_i/R_i + f̂_i(v_i)) + K_lam,i u_i + c_i v_i + F_stop,i(u_i, v_i),
    f̂(v) = g(s) v/s,  g(s) = μ_d(s) (2/π) arctan(ε s),  s = |v|,
    ∂f̂/∂v = (g/s) I + (g′ − g/s) v vᵀ/s²   (→ μ_d(0)(2/π) ε I as s → 0),
    F_stop = f_s n,  n = u/|u|,  f_s = k_stop(|u| − d_cap) + c_stop v·n  (while f_s > 0).

Newton on r with its exact Jacobian I − (J_u c₁ + J_v c₂) W − J_λ Λ (2ni × 2ni, dense LU)
and a backtracking line search on |r|.
"""

import math
from pathlib import Path

import numpy as np
from numba import njit

from nsdyn._klinalg import lu_factor, lu_solve
from nsdyn._numba_cache import drop_stale
from nsdyn.models.isolated.bearings import (
    B_C,
    B_CSTOP,
    B_DCAP,
    B_KLAM,
    B_KSTOP,
    B_MUFAST,
    B_MUSLOW,
    B_RATE,
    B_RINV,
)

_HERE = Path(__file__).resolve().parent
_SOURCES = [_HERE / "_kpairsparse.py", _HERE / "bearings.py", _HERE.parents[1] / "_klinalg.py"]
drop_stale(_HERE, ["_kpairsparse"], _SOURCES)

K2 = 2.0 / math.pi
PIVOT_RTOL = 1e-14  # LU pivot floor of the Newton matrix
LS_MAXITER = 30  # line-search halvings
OK, NEWTON_FAIL, NONFINITE = 0, 1, 2


@njit(cache=True, error_model="numpy")
def mu_at(bp, i, s):
    """Bearing i's friction coefficient at the slip speed ``s``: μ_fast − (μ_fast − μ_slow)
    exp(−rate s)."""
    mf = bp[i, B_MUFAST]
    return mf - (mf - bp[i, B_MUSLOW]) * math.exp(-bp[i, B_RATE] * s)


@njit(cache=True, error_model="numpy")
def clip_friction(bp, v, lam, parts):
    """Each bearing's friction (``parts[i, 0:2]``) held to its disc μ(|v_i|) λ_i: the forces
    carried linearly from the α points to an output time left it at slip onset (27 % over
    μN at dt = 10 ms on the portal's building scene); the law never does."""
    for i in range(lam.size):
        cap = mu_at(bp, i, math.hypot(v[2 * i], v[2 * i + 1])) * max(lam[i], 0.0)
        r = math.hypot(parts[i, 0], parts[i, 1])
        if r > cap:
            parts[i, 0] *= cap / r
            parts[i, 1] *= cap / r


@njit(cache=True, error_model="numpy")
def bearing(bp, i, ux, uy, vx, vy, lam, eps, F, J, parts):
    """F (2,) = F_b,i and J (2, 5) = ∂F/∂(u_x, u_y, v_x, v_y, λ); ``parts`` (6,): friction
    λ f̂, restoring (λ/R + K_lam) u, damper + stop (x, y each)."""
    rinv = bp[i, B_RINV]
    kl = bp[i, B_KLAM]
    cd = bp[i, B_C]
    s = math.sqrt(vx * vx + vy * vy)
    mf, ms, ra = bp[i, B_MUFAST], bp[i, B_MUSLOW], bp[i, B_RATE]
    ex = math.exp(-ra * s)
    mu = mf - (mf - ms) * ex  # (mu_at, its exponential shared with gp below)
    at = math.atan(eps * s)
    if s * eps > 1e-8:
        gs = mu * K2 * at / s
        gp = (mf - ms) * ra * ex * K2 * at + mu * K2 * eps / (1.0 + eps * eps * s * s)
        ax, ay = vx / s, vy / s
        d = gp - gs
    else:  # g(s)/s -> μ(0) (2/π) ε, isotropic
        gs = mu * K2 * eps
        ax, ay, d = 0.0, 0.0, 0.0
    fx, fy = gs * vx, gs * vy
    for a in range(2):
        for b in range(5):
            J[a, b] = 0.0
    kk = lam * rinv + kl
    J[0, 0] = kk
    J[1, 1] = kk
    J[0, 2] = lam * (gs + d * ax * ax) + cd
    J[0, 3] = lam * d * ax * ay
    J[1, 2] = lam * d * ax * ay
    J[1, 3] = lam * (gs + d * ay * ay) + cd
    J[0, 4] = rinv * ux + fx
    J[1, 4] = rinv * uy + fy
    ox, oy = cd * vx, cd * vy
    r = math.sqrt(ux * ux + uy * uy)
    if r > bp[i, B_DCAP]:
        nx, ny = ux / r, uy / r
        vn = vx * nx + vy * ny
        ks, cs = bp[i, B_KSTOP], bp[i, B_CSTOP]
        fs = ks * (r - bp[i, B_DCAP]) + cs * vn
        if fs > 0.0:
            ox += fs * nx
            oy += fs * ny
            # ∂f_s/∂u = k_s n + c_s (v − (v·n) n)/r ; ∂n/∂u = (I − n nᵀ)/r
            gx = ks * nx + cs * (vx - vn * nx) / r
            gy = ks * ny + cs * (vy - vn * ny) / r
            J[0, 0] += nx * gx + fs * (1.0 - nx * nx) / r
            J[0, 1] += nx * gy - fs * nx * ny / r
            J[1, 0] += ny * gx - fs * nx * ny / r
            J[1, 1] += ny * gy + fs * (1.0 - ny * ny) / r
            J[0, 2] += cs * nx * nx
            J[0, 3] += cs * nx * ny
            J[1, 2] += cs * nx * ny
            J[1, 3] += cs * ny * ny
    parts[0], parts[1] = lam * fx, lam * fy
    parts[2], parts[3] = kk * ux, kk * uy
    parts[4], parts[5] = ox, oy
    F[0] = parts[0] + parts[2] + parts[4]
    F[1] = parts[1] + parts[3] + parts[5]


@njit(cache=True, error_model="numpy")
def residual(F, lam0, Lam, w0, W, uq, vq, c1, c2, bp, eps, lam, u, v, r, Jall, parts):
    """r = F − F_b at F (module text); λ, u, v and the bearings' Jacobians (ni, 2, 5) filled.
    Returns |r|₂."""
    ni = lam0.shape[0]
    m = 2 * ni
    for k in range(ni):
        s = lam0[k]
        for j in range(m):
            s += Lam[k, j] * F[j]
        lam[k] = s
    for k in range(m):
        s = w0[k]
        for j in range(m):
            s += W[k, j] * F[j]
        u[k] = uq[k] + c1 * s
        v[k] = vq[k] + c2 * s
    Fb = np.empty(2)
    nr = 0.0
    for i in range(ni):
        bearing(bp, i, u[2 * i], u[2 * i + 1], v[2 * i], v[2 * i + 1], lam[i], eps, Fb,
                Jall[i], parts[i])  # fmt: skip
        for p in range(2):
            r[2 * i + p] = F[2 * i + p] - Fb[p]
            nr += r[2 * i + p] ** 2
    return math.sqrt(nr)


@njit(cache=True, error_model="numpy")
def newton(F, lam0, Lam, w0, W, uq, vq, c1, c2, bp, eps, fscale, rtol, maxit, lam, u, v, parts,
           work):  # fmt: skip
    """Solve r(F) = 0 from the given F (module text); λ, u, v, ``parts`` (ni, 6) at the
    solution. Returns (status, iterations)."""
    ni = lam0.shape[0]
    m = 2 * ni
    r, dF, F1, A, piv, Jall = work
    nr = residual(F, lam0, Lam, w0, W, uq, vq, c1, c2, bp, eps, lam, u, v, r, Jall, parts)
    if not math.isfinite(nr):
        return NONFINITE, 0
    for it in range(maxit):
        for i in range(ni):
            Ji = Jall[i]
            for p in range(2):
                row = 2 * i + p
                for j in range(m):
                    a = 0.0
                    for q in range(2):
                        a += (c1 * Ji[p, q] + c2 * Ji[p, 2 + q]) * W[2 * i + q, j]
                    a += Ji[p, 4] * Lam[i, j]
                    A[row, j] = -a
                A[row, row] += 1.0
                dF[row] = -r[row]
        if not lu_factor(A, piv, PIVOT_RTOL):
            return NEWTON_FAIL, it
        lu_solve(A, piv, dF)
        step = 1.0
        big = 0.0
        for j in range(m):
            big = max(big, abs(dF[j]))
        for _ in range(LS_MAXITER):
            for j in range(m):
                F1[j] = F[j] + step * dF[j]
            n1 = residual(F1, lam0, Lam, w0, W, uq, vq, c1, c2, bp, eps, lam, u, v, r, Jall,
                          parts)  # fmt: skip
            if math.isfinite(n1) and n1 <= (1.0 - 1e-4 * step) * nr:
                break
            step *= 0.5
        for j in range(m):
            F[j] = F1[j]
        nr = n1
        if not math.isfinite(nr):
            return NONFINITE, it + 1
        fmax = 0.0
        for j in range(m):
            fmax = max(fmax, abs(F[j]))
        if step * big <= rtol * (fmax + fscale) or nr <= 1e-3 * rtol * (fmax + fscale):
            return OK, it + 1
    return NEWTON_FAIL, maxit


@njit(cache=True, error_model="numpy")
def lu_solve_csc(Lp, Li, Lx, Up, Ui, Ux, Ud, pr, pc, b, w, x):
    """x = S⁻¹ b from SuperLU's factors Pr S Pc = L U (L unit lower, U upper, both CSC with
    sorted indices; ``Ud`` U's diagonal, ``pr``/``pc`` the permutations); ``w`` work (n)."""
    n = b.shape[0]
    for i in range(n):
        w[pr[i]] = b[i]
    for j in range(n):
        wj = w[j]
        if wj != 0.0:
            for k in range(Lp[j], Lp[j + 1]):
                r = Li[k]
                if r > j:
                    w[r] -= Lx[k] * wj
    for j in range(n - 1, -1, -1):
        wj = w[j] / Ud[j]
        w[j] = wj
        if wj != 0.0:
            for k in range(Up[j], Up[j + 1]):
                r = Ui[k]
                if r < j:
                    w[r] -= Ux[k] * wj
    for i in range(n):
        x[i] = w[pc[i]]


def workspace(ni: int) -> tuple:
    """Work arrays of :func:`newton` (made once per run)."""
    m = 2 * ni
    return (np.zeros(m), np.zeros(m), np.zeros(m), np.zeros((m, m)), np.zeros(m, np.int64),
            np.zeros((ni, 2, 5)))  # fmt: skip
