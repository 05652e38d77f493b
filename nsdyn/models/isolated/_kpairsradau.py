"""Radau IIA (order 5) time loop of a system from matrices under the regularised friction law.

The collocation method of the deck's loop (:mod:`nsdyn.models.isolated._kplaneradau`: the
tableau, its dense output and predictor are imported from there), solved for n coordinates
without forming the 3·2n Newton matrix: with A⁻¹ = T Λ T⁻¹ (Λ: the real eigenvalue γ and the
block of the pair α ± iβ; T from the eigenvectors, computed and checked at import), the
simplified Newton system (Λ/h ⊗ I − I ⊗ J) ΔW = (T⁻¹ ⊗ I) F − (Λ/h ⊗ I) W, Z = (T ⊗ I) W,
splits into one real and one complex system σ I − J (Hairer & Wanner, Solving ODEs II,
IV.8), σ = γ/h and (α − iβ)/h. The first-order Jacobian J = [[0, I], [J_q, J_v]] (J_q =
∂q̈/∂q, J_v = ∂q̈/∂q̇ by forward differences, kept while Newton contracts and steps are
accepted) reduces each to n × n::

    (σ² I − σ J_v − J_q) z₁ = r₂ + (σ I − J_v) r₁,   z₂ = σ z₁ − r₁,

so a factorisation costs n³/3 real plus n³/3 complex operations. The internal slips s of
triple friction pendulums (m states after [q, q̇]; their flow reads u = D q and s, not q̇) add
the columns J_s = ∂q̈/∂s and the rows S_q = ∂ṡ/∂q, S_s = ∂ṡ/∂s (forward differences too):

    [σ² I − σ J_v − J_q   −J_s    ] [z₁]   [r₂ + (σ I − J_v) r₁]
    [−S_q                 σ I − S_s] [z₃] = [r₃                ],   z₂ = σ z₁ − r₁,

an (n + m)-system. Error estimate of RADAU5,
(γ/h I − J)⁻¹ (f(y) + Σ e_i Z_i / h); steps end on the record's samples; outputs, rim
contacts and uplift (located on the collocation polynomial) as in the Dormand–Prince loop.
"""

import math

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn._klinalg import lu_factor, lu_solve
from nsdyn.models.isolated import _kpairs as kq
from nsdyn.models.isolated import _kpairsrun as kqr
from nsdyn.models.isolated import _kplane as kp
from nsdyn.models.isolated import _kplaneradau as krad
from nsdyn.models.isolated import _kplanerun as kr


def _eigen_split():
    """(T, T⁻¹, γ, α, β) with A⁻¹ T = T [[γ, 0, 0], [0, α, β], [0, −β, α]]."""
    c = np.array([krad.C1, krad.C2, 1.0])  # collocation: Σ_j a_ij c_j^(k−1) = c_i^k / k
    V = np.vander(c, 3, increasing=True)  # V[j, k] = c_j^k
    A = np.linalg.solve(V.T, (c[None, :] ** np.arange(1, 4)[:, None]) / np.arange(1, 4)[:, None]).T
    Ai = np.linalg.inv(A)
    w, V = np.linalg.eig(Ai)
    kr_ = int(np.argmin(np.abs(w.imag)))
    kc = int(np.argmax(w.imag))
    T = np.column_stack([V[:, kr_].real, V[:, kc].real, V[:, kc].imag])
    gam, al, be = w[kr_].real, w[kc].real, w[kc].imag
    lam = np.array([[gam, 0.0, 0.0], [0.0, al, be], [0.0, -be, al]])
    if not np.allclose(Ai @ T, T @ lam, rtol=0, atol=1e-12 * np.abs(Ai).max()):
        raise ArithmeticError("Radau IIA eigen-split: A⁻¹ T != T Λ")
    return np.ascontiguousarray(T), np.ascontiguousarray(np.linalg.inv(T)), gam, al, be


TM, TI, GAMMA, ALPHA_C, BETA_C = _eigen_split()
E1, E2, E3 = krad.E1, krad.E2, krad.E3
NEWTON_MAXITER = 8
NEWTON_TOL = krad.NEWTON_TOL  # scaled Newton correction accepted


@ka.compiled_only
def _factor(sig, Jx, S, piv):
    """S = [[σ² I − σ J_v − J_q, −J_s], [−S_q, σ I − S_s]] (module text), factored (real or
    complex σ, S of σ's type); Jx (n + m, 2n + m): the rows of q̈ and ṡ over all states."""
    n = Jx.shape[1] - Jx.shape[0]
    k = Jx.shape[0]
    for a in range(k):
        for b in range(k):
            if a < n and b < n:
                S[a, b] = -sig * Jx[a, n + b] - Jx[a, b]
            elif b < n:
                S[a, b] = -Jx[a, b]
            else:
                S[a, b] = -Jx[a, n + b]
        S[a, a] += sig * sig if a < n else sig
    return lu_factor(S, piv, 0.0)


@ka.compiled_only
def _solve(sig, Jx, S, piv, r, z, w):
    """(σ I − J) z = r for the full state (length 2n + m) with S from _factor; w: work
    (n + m) of σ's type."""
    n = Jx.shape[1] - Jx.shape[0]
    k = Jx.shape[0]
    for a in range(k):
        if a < n:
            s = r[n + a] + sig * r[a]
            for b in range(n):
                s -= Jx[a, n + b] * r[b]
            w[a] = s
        else:
            w[a] = r[n + a]
    lu_solve(S, piv, w)
    for a in range(k):
        if a < n:
            z[a] = w[a]
            z[n + a] = sig * w[a] - r[a]
        else:
            z[n + a] = w[a]


# the Radau loop calls them by address (rows "pairs.factor_real", ...): one compilation each
# for real and for complex σ, where the loop linked copies of them and of their LU
for _row, _kernel in (("pairs.factor_real", _factor), ("pairs.factor_complex", _factor),
                      ("pairs.solve_real", _solve), ("pairs.solve_complex", _solve)):  # fmt: skip
    ka.tslot(_row, _kernel, "nsdyn.models.isolated.pairs_compile:callees")


@ka.compiled_only
def _jacobian(t, y, f0, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, Jx, f1):
    """Jx: the rows of q̈ and ṡ of f by forward differences at (t, y), f0 = f(t, y) (f1:
    work); returns a status."""
    N = y.shape[0]
    n = N - Jx.shape[0]
    for j in range(N):
        d = 1e-8 * max(abs(y[j]), 1e-3)
        yj = y[j]
        y[j] = yj + d
        st = kq.rhs_t(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, f1)
        y[j] = yj
        if st != kq.ST_OK:
            return st
        for a in range(Jx.shape[0]):
            Jx[a, j] = (f1[n + a] - f0[n + a]) / d
    return kq.ST_OK


# by address: the loop linked a copy of each (the Jacobian with its own of the right-hand side)
ka.tslot("pairs.jacobian", _jacobian, "nsdyn.models.isolated.pairs_compile:callees")
ka.tslot("pairs.dense", krad._dense, "nsdyn.models.isolated.pairs_compile:callees")


# no reference counts (NO_NRT): the loop allocates nothing, every array is its caller's;
# nogil: a caller may watch info[I_NOUT] (the outputs written) from another thread
@njit(cache=True, error_model="numpy", nogil=True, **ka.NO_NRT)
def integrate(y0, t_eval, modes, dirs, op, bp, sp, gk, gp, tab, cfg,
              X, NO, FF, FR, FO, MO, EV, stops, info, wk):  # fmt: skip
    """Integrate from y0 at t_eval[0] to t_eval[-1]; outputs at t_eval; returns a status
    (codes of :mod:`nsdyn.models.isolated._kplanerun`); ``wk``: ``pairs_compile.loop_arrays``."""
    N = y0.shape[0]
    n = op[kq.O_MIK].shape[0]
    ni = modes.shape[0]
    t = t_eval[0]
    ws, out, y = wk[0], wk[1], wk[2]
    bq = (y0, t, modes, dirs, op, bp, sp, gk, gp, tab, X, NO, FF, FR, FO, MO, EV, info, ws, out, y)
    st = ka.tcall("pairs.begin", bq)
    if st != kr.ST_OK:
        return st
    lam = out[1]
    bil = int(sp[kq.S_CONTACT]) == kp.CONTACT_BILATERAL
    tens = bil and kr._min_normal(lam) <= 0.0
    V6 = wk[3]
    ys, f0, f1, ynew, err, sc = V6[0], V6[1], V6[2], V6[3], V6[4], V6[5]
    Jx, Sr, Sc, pr, pc, wr, wc = wk[4], wk[5], wk[6], wk[7], wk[8], wk[9], wk[10]
    Z, W, F, rw, dW = wk[11], wk[12], wk[13], wk[14], wk[15]
    cr, cz, yp, Zp = wk[16], wk[17], wk[18], wk[19]
    rtol = cfg[kr.C_RTOL]
    hmax = cfg[kr.C_HMAX]
    max_steps = int(cfg[kr.C_MAXSTEPS])
    nt = t_eval.shape[0]
    t_end = t_eval[nt - 1]
    ntab = tab.shape[1]
    iout = np.int64(1)
    h = min(cfg[kr.C_H0], hmax)
    need_jac = True
    f0_ready = False
    en_old = 0.0
    have_prev = False
    hp = 1.0
    lu_h = -1.0
    ok = False
    it = 0
    fac = 1.0
    nstep = np.int64(0)
    since_out = np.int64(0)
    nrej = np.int64(0)
    nfev = np.int64(0)
    status = kr.ST_OK
    newton_failed = False
    while t < t_end and iout < nt:
        if nstep + nrej > max_steps:
            status = kr.ST_MAX_STEPS
            break
        if t_end - t <= 1e-12 * max(1.0, abs(t_end)):  # at the end up to round-off
            while iout < nt:
                kqr.outputs_t(t_eval[iout], y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out,
                              iout, X, NO, FF, FR, FO, MO)  # fmt: skip
                iout += 1
            break
        hh = min(h, hmax, t_end - t)
        tb = kp.next_breakpoint(t, gk, gp, ntab)
        if t + hh > tb:
            hh = tb - t
        if hh <= kr.H_MIN * max(1.0, abs(t)):
            status = kr.ST_NEWTON if newton_failed else kr.ST_UNDERFLOW
            break
        if not f0_ready:
            if kq.rhs_t(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, f0) != kq.ST_OK:
                status = kr.ST_SINGULAR
                break
            nfev += 1
            f0_ready = True
        if need_jac:
            ja = (t, y, f0, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, Jx, f1)
            if ka.tcall("pairs.jacobian", ja) != kq.ST_OK:
                status = kr.ST_SINGULAR
                break
            nfev += N
            need_jac = False
            lu_h = -1.0
        if abs(hh - lu_h) > 1e-9 * hh:
            ok = ka.tcall("pairs.factor_real", (GAMMA / hh, Jx, Sr, pr))
            sig_c = complex(ALPHA_C, -BETA_C) / hh
            ok = ka.tcall("pairs.factor_complex", (sig_c, Jx, Sc, pc)) and ok
            lu_h = hh
        for k in range(N):  # (the internal slips: displacements)
            sc[k] = (cfg[kr.C_ATOLV] if n <= k < 2 * n else cfg[kr.C_ATOLQ]) + rtol * abs(y[k])
        if have_prev:  # predictor: the previous collocation polynomial, extrapolated
            for a in range(3):
                ca = krad.C1 if a == 0 else (krad.C2 if a == 1 else 1.0)
                ka.tcall("pairs.dense", (yp, Zp, 1.0 + ca * hh / hp, ys))
                for k in range(N):
                    Z[a, k] = ys[k] - y[k]
        else:
            for a in range(3):
                for k in range(N):
                    Z[a, k] = 0.0
        for a in range(3):  # W = T⁻¹ Z
            for k in range(N):
                W[a, k] = TI[a, 0] * Z[0, k] + TI[a, 1] * Z[1, k] + TI[a, 2] * Z[2, k]
        converged = False
        for it in range(NEWTON_MAXITER):  # noqa: B007  (the count is read after the loop)
            if not ok:
                break
            bad = False
            for a in range(3):
                ca = krad.C1 if a == 0 else (krad.C2 if a == 1 else 1.0)
                for k in range(N):
                    ys[k] = y[k] + Z[a, k]
                if kq.rhs_t(t + ca * hh, ys, modes, dirs, op, bp, sp, gk, gp, tab, ws, out,
                          F[a]) != kq.ST_OK:  # fmt: skip
                    bad = True
            nfev += 3
            if bad:
                break
            for k in range(N):  # (T⁻¹ F) − (Λ/h) W
                g0 = TI[0, 0] * F[0, k] + TI[0, 1] * F[1, k] + TI[0, 2] * F[2, k]
                g1 = TI[1, 0] * F[0, k] + TI[1, 1] * F[1, k] + TI[1, 2] * F[2, k]
                g2 = TI[2, 0] * F[0, k] + TI[2, 1] * F[1, k] + TI[2, 2] * F[2, k]
                rw[0, k] = g0 - GAMMA / hh * W[0, k]
                rw[1, k] = g1 - (ALPHA_C * W[1, k] + BETA_C * W[2, k]) / hh
                rw[2, k] = g2 - (-BETA_C * W[1, k] + ALPHA_C * W[2, k]) / hh
            ka.tcall("pairs.solve_real", (GAMMA / hh, Jx, Sr, pr, rw[0], dW[0], wr))
            for k in range(N):
                cr[k] = complex(rw[1, k], rw[2, k])
            sig_c = complex(ALPHA_C, -BETA_C) / hh
            ka.tcall("pairs.solve_complex", (sig_c, Jx, Sc, pc, cr, cz, wc))
            for k in range(N):
                dW[1, k] = cz[k].real
                dW[2, k] = cz[k].imag
            dn = 0.0
            for k in range(N):
                for a in range(3):
                    W[a, k] += dW[a, k]
                for a in range(3):
                    dz = TM[a, 0] * dW[0, k] + TM[a, 1] * dW[1, k] + TM[a, 2] * dW[2, k]
                    Z[a, k] = TM[a, 0] * W[0, k] + TM[a, 1] * W[1, k] + TM[a, 2] * W[2, k]
                    dn = max(dn, abs(dz) / sc[k])
            if not math.isfinite(dn):
                break
            if dn < NEWTON_TOL:
                converged = True
                break
        if it >= 3:
            need_jac = True  # slow contraction: a fresh Jacobian for the next step
        newton_failed = not converged
        if not converged:
            if not ok:
                status = kr.ST_SINGULAR
                break
            nrej += 1
            have_prev = False
            h = 0.5 * hh
            need_jac = True
            continue
        # error estimate (RADAU5): (γ/h I − J)⁻¹ (f(y) + Σ e_i Z_i / h)
        for k in range(N):
            f1[k] = f0[k] + (E1 * Z[0, k] + E2 * Z[1, k] + E3 * Z[2, k]) / hh
        ka.tcall("pairs.solve_real", (GAMMA / hh, Jx, Sr, pr, f1, err, wr))
        en = 0.0
        for k in range(N):
            ynew[k] = y[k] + Z[2, k]
            s_k = (cfg[kr.C_ATOLV] if n <= k < 2 * n else cfg[kr.C_ATOLQ]) + rtol * max(
                abs(y[k]), abs(ynew[k])
            )
            en += (err[k] / s_k) ** 2
        en = math.sqrt(en / N)
        if not math.isfinite(en):
            nrej += 1
            h = 0.25 * hh
            continue
        safety = 0.9 * (2 * NEWTON_MAXITER + 1) / (2 * NEWTON_MAXITER + it + 1)
        fac = safety * (en + 1e-10) ** -0.25
        if en_old > 0.0:
            fac *= min(1.0, (en_old / (en + 1e-10)) ** 0.25)
        if en > 1.0:
            nrej += 1
            h = hh * max(0.2, fac)
            need_jac = True
            continue
        nstep += 1
        since_out += 1  # collapsed steps end the run as the Dormand-Prince kernel's do
        if (since_out > kr.STALL_STEPS + 10.0 * (t_eval[iout] - t_eval[iout - 1]) / hmax
                or nstep > kr.STALL_STEPS + kr.STALL_RATE * (t - t_eval[0]) / hmax):  # fmt: skip
            status = kr.ST_STALL
            break
        en_old = max(en, 1e-4)
        s_end = 1.0
        if kq.rhs_t(t + hh, ynew, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, f1) != kq.ST_OK:
            status = kr.ST_SINGULAR
            break
        nfev += 1
        n_end = kr._min_normal(lam)
        if n_end <= 0.0 and not tens:  # uplift (tension): the first λ_i = 0, dense output
            sa = 0.0
            sb = 1.0
            while (sb - sa) * hh > kr.EVENT_TTOL and sa < 0.5 * (sa + sb) < sb:
                sm = 0.5 * (sa + sb)
                ka.tcall("pairs.dense", (y, Z, sm, ys))
                kqr._ev(t + sm * hh, ys, modes, dirs, op, bp, sp, gk, gp, tab, ws, out)
                if kr._min_normal(lam) <= 0.0:
                    sb = sm
                else:
                    sa = sm
            ka.tcall("pairs.dense", (y, Z, sb, ys))
            kqr._ev(t + sb * hh, ys, modes, dirs, op, bp, sp, gk, gp, tab, ws, out)
            for i in range(ni):
                if lam[i] <= 0.0 and info[kr.I_IFAIL] < 0:
                    info[kr.I_IFAIL] = i
            if bil:  # the contact holds: recorded, the step kept
                kr.tension_onset(info, t + sb * hh)
            else:
                s_end = sb
                status = kr.ST_UPLIFT
        if bil:
            tens = n_end <= 0.0
            info[kr.I_NMIN] = min(info[kr.I_NMIN], n_end)
        t_new = t + s_end * hh
        while iout < nt and t_eval[iout] <= t_new:
            since_out = 0
            ka.tcall("pairs.dense", (y, Z, (t_eval[iout] - t) / hh, ys))
            ka.tcall("pairs.emit", (t_eval[iout], ys, modes, dirs, op, bp, sp, gk, gp, tab, ws,
                                    out, iout, X, NO, FF, FR, FO, MO, stops))  # fmt: skip
            iout += 1
            info[kr.I_NOUT] = iout  # (read by a watching thread: the progress line)
        if s_end < 1.0:
            ka.tcall("pairs.dense", (y, Z, s_end, ys))
            for k in range(N):
                y[k] = ys[k]
        else:
            for k in range(N):
                yp[k] = y[k]
                y[k] = ynew[k]
                f0[k] = f1[k]
                for a in range(3):
                    Zp[a, k] = Z[a, k]
            hp = hh
        have_prev = s_end >= 1.0
        f0_ready = s_end >= 1.0
        t = t_new
        ka.tcall("pairs.track_stops", (t, y, op, bp, ws, stops))
        if status == kr.ST_UPLIFT:
            info[kr.I_TFAIL] = t
            if iout < nt and t > t_eval[max(iout - 1, 0)]:  # the located instant: last row
                ka.tcall("pairs.emit", (t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, iout,
                                        X, NO, FF, FR, FO, MO, stops))  # fmt: skip
                iout += 1
            break
        h = min(hh * min(10.0, max(0.2, fac)), hmax)
        if 1.0 <= h / hh <= 1.2:  # keep the factored step (as RADAU5 does)
            h = hh
    return kqr.finish(status, t, nstep, nrej, nfev, iout, info)
