"""Radau IIA (order 5) time loop of the deck under the regularised friction law.

The regularised law is stiff near stick: its slope μN(2/π)ε (ε = 7500 s/m: ~2000 1/s on a
deck) limits an explicit step to ~1 ms. This loop takes the L-stable, stiffly accurate
three-stage Radau IIA collocation method instead (Hairer & Wanner, Solving ODEs II, IV.8;
the same method as nsdyn.solve's, written here for the deck's six states, whose kernels
that package cannot call)::

    Z_i = h Σ_j a_ij f(t + c_j h, y + Z_j),   y(t + h) = y + Z_3,
    c = ((4 − √6)/10, (4 + √6)/10, 1)

solved by simplified Newton, (I − h A ⊗ J) ΔZ = −G(Z) (n = 6 states, plus 8 internal slips per
triple friction pendulum), with a forward-difference Jacobian J (kept while Newton contracts in
at most three iterations and steps are accepted, factored again when h changes). As in RADAU5
the 3n × 3n system is solved in the eigenbasis of A⁻¹ = T Λ T⁻¹ (Λ: the real eigenvalue γ and
the pair α ± iβ): with W = T⁻¹ Z it splits into one real and one complex n × n system,

    (γ/h − J) ΔW_1 = (T⁻¹F)_1 − γ W_1/h,
    ((α + iβ)/h − J)(ΔW_2 + iΔW_3) = (T⁻¹F)_2 + i (T⁻¹F)_3 − (α + iβ)(W_2 + iW_3)/h,

ΔZ = T ΔW (the same Newton iterates, at a fifth of the factorisation's cost), the embedded error
estimate of RADAU5 (I/(γ₀h) − J)⁻¹ (f(y) + Σ e_i Z_i / h) with e = (−13 − 7√6, −13 + 7√6,
−1)/3 and γ₀ h the real eigenvalue's reciprocal, steps ending on the record's samples, the
cubic collocation polynomial through (0, 0), (c_i, Z_i) as dense output and, extrapolated, as
the Newton predictor of the next step. Outputs, rim contacts
and uplift (a normal force reaching zero, located on the dense output) as in
:mod:`nsdyn.models.isolated._kplanerun`.
"""

import math

import numpy as np
from numba import njit

from nsdyn._kaddress import NO_NRT
from nsdyn._klinalg import argmin, lu_factor, lu_solve
from nsdyn.models.isolated import _kplane as kp
from nsdyn.models.isolated import _kplanerun as kr
from nsdyn.models.isolated.bearings import B_CEL, B_IOFF, B_KIND, KIND_TFP

S6 = math.sqrt(6.0)
C1, C2 = (4.0 - S6) / 10.0, (4.0 + S6) / 10.0
E1, E2, E3 = (-13.0 - 7.0 * S6) / 3.0, (-13.0 + 7.0 * S6) / 3.0, -1.0 / 3.0
MU_REAL = 3.0 + 3.0 ** (2.0 / 3.0) - 3.0 ** (1.0 / 3.0)  # 1/γ₀
# the complex eigenvalue α + iβ of A⁻¹ and its eigenbasis T, T⁻¹ (RADAU5's constants)
ALPHA_C = (12.0 - 81.0 ** (1 / 3) + 9.0 ** (1 / 3)) / 60.0
BETA_C = (81.0 ** (1 / 3) + 9.0 ** (1 / 3)) * math.sqrt(3.0) / 60.0
ALPHA_C, BETA_C = ALPHA_C / (ALPHA_C**2 + BETA_C**2), BETA_C / (ALPHA_C**2 + BETA_C**2)
T11, T12, T13 = 9.1232394870892942792e-02, -0.14125529502095420843, -3.0029194105147424492e-02
T21, T22, T23 = 0.24171793270710701896, 0.20412935229379993199, 0.38294211275726193779
T31, T32, T33 = 0.96604818261509293619, 1.0, 0.0
TI11, TI12, TI13 = 4.3255798900631553510, 0.33919925181580986954, 0.54177053993587487119
TI21, TI22, TI23 = -4.1787185915519047273, -0.32768282076106238708, 0.47662355450055045196
TI31, TI32, TI33 = -0.50287263494578687595, 2.5719269498556054292, -0.59603920482822492497
NEWTON_MAXITER = 8
NEWTON_TOL = 0.1  # scaled Newton correction accepted (RADAU5's kappa * tol, with tol ~ 1)


@njit(cache=True, error_model="numpy", **NO_NRT)
def _dense(y, Z, s, ys):
    """Collocation polynomial at t + s h through (0, 0), (c_1, Z_1), (c_2, Z_2), (1, Z_3)."""
    l1 = s * (s - C2) * (s - 1.0) / (C1 * (C1 - C2) * (C1 - 1.0))
    l2 = s * (s - C1) * (s - 1.0) / (C2 * (C2 - C1) * (C2 - 1.0))
    l3 = s * (s - C1) * (s - C2) / ((1.0 - C1) * (1.0 - C2))
    for k in range(y.shape[0]):
        ys[k] = y[k] + l1 * Z[0, k] + l2 * Z[1, k] + l3 * Z[2, k]


@njit(cache=True, error_model="numpy", **NO_NRT)
def _locate_stops(t, hh, s_end, y, Z, ys, pos, bp, stops):
    """First rim contacts inside a step on its collocation polynomial, as
    :func:`nsdyn.models.isolated._kplanerun._locate_stops` does on the Dormand–Prince one."""
    for i in range(pos.shape[0]):
        if stops[i, kr.P_TFIRST] == stops[i, kr.P_TFIRST]:  # in contact before
            continue
        sa = 0.0
        for m in range(1, kr.SAMPLES + 1):
            sb = s_end * m / kr.SAMPLES
            _dense(y, Z, sb, ys)
            d = kr._overshoot(ys, pos, bp, i)
            if d > 0.0:
                stops[i, kr.P_PEAK] = max(stops[i, kr.P_PEAK], d)
                while (sb - sa) * hh > kr.EVENT_TTOL and sa < 0.5 * (sa + sb) < sb:
                    sm = 0.5 * (sa + sb)
                    _dense(y, Z, sm, ys)
                    if kr._overshoot(ys, pos, bp, i) > 0.0:
                        sb = sm
                    else:
                        sa = sm
                stops[i, kr.P_TFIRST] = t + sb * hh
                break
            sa = sb


@njit(cache=True, error_model="numpy", **NO_NRT)
def _tfp_columns(y, pos, bp, J, sd, base):
    """Jacobian columns of the internal slips of elements 2-4 of every triple pendulum: the
    deck's rows (q̇, q̈) from element 1's column (the force depends on Σ_k s_k), its own
    internal rows by forward differences of its flow alone, zero for the other bearings
    (``base`` (8,): scratch)."""
    n = y.shape[0]
    for i in range(pos.shape[0]):
        if bp[i, B_KIND] != KIND_TFP or bp[i, B_CEL] != 0.0:  # (damped: every column's own)
            continue
        o = int(bp[i, B_IOFF])
        ux, uy, vx, vy = kp.slip_kinematics(y, pos, i)
        kp.tfp_force(y, bp, i, ux, uy, vx, vy, sd)
        for m in range(8):
            base[m] = sd[i, m]
        for j in range(o + 2, o + 8):
            src = o + (j - o) % 2
            for r in range(n):
                J[r, j] = J[r, src] if r < 6 else 0.0
            d = 1e-8 * max(abs(y[j]), 1e-3)
            yj = y[j]
            y[j] = yj + d
            kp.tfp_force(y, bp, i, ux, uy, vx, vy, sd)
            y[j] = yj
            for m in range(8):
                J[o + m, j] = (sd[i, m] - base[m]) / d
        for m in range(8):
            sd[i, m] = base[m]


@njit(cache=True, error_model="numpy", nogil=True, **NO_NRT)  # (watched: info[I_NOUT])
def integrate(y0, t_eval, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, cfg,
              X, NO, FF, FR, FO, MO, EV, stops, info, ws, out, S):  # fmt: skip
    """Integrate from y0 at t_eval[0] to t_eval[-1]; outputs at t_eval; returns a status
    (the codes of :mod:`nsdyn.models.isolated._kplanerun`). The state is [q, q̇] and the
    internal slips of triple friction pendulums, if any (y0's length). ``ws, out, S``: its
    scratch (:func:`nsdyn.models.isolated.deck_compile.loop_arrays`)."""
    n = y0.shape[0]
    ni = pos.shape[0]
    N = out[1]
    y, ys, f0, f1, J, Z, F, r1, rc, EC, pc, LE, pe, err, sc, ynew, copied, sdw, yp, Zp, base = S
    # a triple pendulum's force depends on its internal slips through their sum only: the
    # deck's rows of the columns of its elements 2-4 are those of element 1 (copied)
    for j in range(n):
        copied[j] = False
    for i in range(ni):
        if bp[i, B_KIND] == KIND_TFP and bp[i, B_CEL] == 0.0:  # (undamped elastic stage)
            o = int(bp[i, B_IOFF])
            for j in range(o + 2, o + 8):
                copied[j] = True
    for j in range(n):
        y[j] = y0[j]
    rtol = cfg[kr.C_RTOL]
    hmax = cfg[kr.C_HMAX]
    max_steps = int(cfg[kr.C_MAXSTEPS])
    nt = t_eval.shape[0]
    t = t_eval[0]
    t_end = t_eval[nt - 1]
    ntab = tab.shape[1]
    info[kr.I_TFAIL] = np.nan
    info[kr.I_IFAIL] = -1
    k0 = np.int64(0)  # typed: one compilation of _outputs (a literal 0 would be a second)
    kr._outputs(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, k0, X, NO, FF, FR,
                FO, MO)  # fmt: skip
    iout = np.int64(1)
    bil = int(sp[kp.S_CONTACT]) == kp.CONTACT_BILATERAL
    tens = kr.tension_start(info, t, N, bil)
    if kr._min_normal(N) <= 0.0 and not bil:  # (at the start: the output there, its isolator)
        info[kr.I_TFAIL], info[kr.I_IFAIL], info[kr.I_NOUT] = t, argmin(N), iout
        return kr.ST_UPLIFT
    h = min(cfg[kr.C_H0], hmax)
    need_jac = True
    jac_here = False  # J was evaluated at the current (t, y): a new one would be the same
    f0_ready = False
    en_old = 0.0
    have_prev = False
    hp = 1.0
    lu_h = -1.0
    ok = False
    it = 0
    nstep = 0
    since_out = 0
    nrej = 0
    nfev = 0
    status = kr.ST_OK
    newton_failed = False
    faccon = 1.0
    # stop Newton on its contraction (RADAU5) for the deck's own six states; the internal
    # slips of triple pendulums flow on the yield displacement's time scale, and iterates
    # stopped early there leave errors the estimate rejects: iterated to NEWTON_TOL
    relax = n == 6  # the last step's rejection was Newton's (reported at underflow)
    while t < t_end and iout < nt:
        if nstep + nrej > max_steps:
            status = kr.ST_MAX_STEPS
            break
        if t_end - t <= 1e-12 * max(1.0, abs(t_end)):  # at the end up to round-off
            while iout < nt:
                kr._outputs(t_eval[iout], y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws,
                            out, iout, X, NO, FF, FR, FO, MO)  # fmt: skip
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
            if kp.rhs(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, f0) != 0:
                status = kr.ST_SINGULAR
                break
            nfev += 1
            f0_ready = True
        if need_jac and jac_here:  # (a rejected step's point again: the same J)
            need_jac = False
        if need_jac:  # forward differences at the step's start, kept while Newton converges
            for j in range(n):
                if copied[j]:
                    continue
                d = 1e-8 * max(abs(y[j]), 1e-3)
                yj = y[j]
                y[j] = yj + d
                kp.rhs(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, f1)
                y[j] = yj
                for k in range(n):
                    J[k, j] = (f1[k] - f0[k]) / d
                nfev += 1
            if n > 6:
                _tfp_columns(y, pos, bp, J, sdw, base)
            need_jac = False
            jac_here = True
            lu_h = -1.0
        if abs(hh - lu_h) > 1e-9 * hh:  # γ/h − J and (α + iβ)/h − J, again when h or J changed
            lam = complex(ALPHA_C / hh, BETA_C / hh)
            for k in range(n):
                for m in range(n):
                    LE[k, m] = (MU_REAL / hh if k == m else 0.0) - J[k, m]
                    EC[k, m] = (lam if k == m else 0.0) - J[k, m]
            ok = lu_factor(LE, pe, 0.0)
            ok = ok and lu_factor(EC, pc, 0.0)
            lu_h = hh
        for k in range(n):
            sc[k] = (cfg[kr.C_ATOLV] if 3 <= k < 6 else cfg[kr.C_ATOLQ]) + rtol * abs(y[k])
        converged = False
        faccon = max(faccon, 1e-16) ** 0.8  # (RADAU5: the last contraction, relaxed)
        dn_old = 0.0
        if have_prev:  # predictor: the previous step's collocation polynomial, extrapolated
            for a in range(3):
                ca = C1 if a == 0 else (C2 if a == 1 else 1.0)
                _dense(yp, Zp, 1.0 + ca * hh / hp, ys)
                for k in range(n):
                    Z[a, k] = ys[k] - y[k]
        else:
            for a in range(3):
                for k in range(n):
                    Z[a, k] = 0.0
        for it in range(NEWTON_MAXITER):  # noqa: B007  (the count is read after the loop)
            if not ok:
                break
            for a in range(3):
                ca = C1 if a == 0 else (C2 if a == 1 else 1.0)
                for k in range(n):
                    ys[k] = y[k] + Z[a, k]
                kp.rhs(t + ca * hh, ys, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out,
                       F[a])  # fmt: skip
            nfev += 3
            for k in range(n):  # in the eigenbasis: W = T⁻¹ Z, T⁻¹ F
                z1, z2, z3 = Z[0, k], Z[1, k], Z[2, k]
                w1 = TI11 * z1 + TI12 * z2 + TI13 * z3
                w2 = TI21 * z1 + TI22 * z2 + TI23 * z3
                w3 = TI31 * z1 + TI32 * z2 + TI33 * z3
                fa, fb, fc = F[0, k], F[1, k], F[2, k]
                g1 = TI11 * fa + TI12 * fb + TI13 * fc
                g2 = TI21 * fa + TI22 * fb + TI23 * fc
                g3 = TI31 * fa + TI32 * fb + TI33 * fc
                r1[k] = g1 - MU_REAL * w1 / hh
                rc[k] = complex(g2 - (ALPHA_C * w2 - BETA_C * w3) / hh,
                                g3 - (BETA_C * w2 + ALPHA_C * w3) / hh)  # fmt: skip
            lu_solve(LE, pe, r1)
            lu_solve(EC, pc, rc)
            dn = 0.0
            for k in range(n):  # ΔZ = T ΔW
                d1, d2, d3 = r1[k], rc[k].real, rc[k].imag
                for a in range(3):
                    if a == 0:
                        dz = T11 * d1 + T12 * d2 + T13 * d3
                    elif a == 1:
                        dz = T21 * d1 + T22 * d2 + T23 * d3
                    else:
                        dz = T31 * d1 + T32 * d2 + T33 * d3
                    Z[a, k] += dz
                    dn = max(dn, abs(dz) / sc[k])
            if not math.isfinite(dn):
                break
            if relax and it >= 1:  # the contraction θ: stop once θ/(1 − θ) ΔZ, the error
                theta = dn / dn_old  # left, is small; a diverging iteration (θ ≥ 0.99) stops
                if theta >= 0.99:
                    break
                faccon = theta / (1.0 - theta)
            if dn < NEWTON_TOL or (relax and faccon * dn <= NEWTON_TOL):
                converged = True
                break
            dn_old = dn
        if it >= 3:
            need_jac = True  # slow contraction: a fresh Jacobian for the next step
        newton_failed = not converged
        if not converged:
            nrej += 1
            have_prev = False
            h = 0.5 * hh
            if not ok:
                status = kr.ST_SINGULAR
                break
            need_jac = True
            continue
        # error estimate (RADAU5): (I/(γ₀ h) − J)⁻¹ (f(y) + Σ e_i Z_i / h)
        for k in range(n):
            err[k] = f0[k] + (E1 * Z[0, k] + E2 * Z[1, k] + E3 * Z[2, k]) / hh
        lu_solve(LE, pe, err)
        en = 0.0
        for k in range(n):
            ynew[k] = y[k] + Z[2, k]
            s_k = (cfg[kr.C_ATOLV] if 3 <= k < 6 else cfg[kr.C_ATOLQ]) + rtol * max(
                abs(y[k]), abs(ynew[k])
            )
            en += (err[k] / s_k) ** 2
        en = math.sqrt(en / n)
        if not math.isfinite(en):
            nrej += 1
            h = 0.25 * hh
            continue
        # safety as RADAU5 (smaller when Newton needed more iterations) and a growing error
        # damping the growth (fewer rejections where the friction slope changes)
        safety = 0.9 * (2 * NEWTON_MAXITER + 1) / (2 * NEWTON_MAXITER + it + 1)
        fac = safety * (en + 1e-10) ** -0.25
        if en_old > 0.0:  # (the ratio of the errors only: steps cut by a record's sample
            fac *= min(1.0, (en_old / (en + 1e-10)) ** 0.25)  # would shrink h / h_old)
        if en > 1.0:
            nrej += 1
            h = hh * max(0.2, fac)
            need_jac = True
            continue
        nstep += 1
        ws[19][1] = np.nan  # an accepted step met no impasse (kp.evaluate's record)
        since_out += 1  # collapsed steps end the run as the Dormand-Prince kernel's do
        if (since_out > kr.STALL_STEPS + 10.0 * (t_eval[iout] - t_eval[iout - 1]) / hmax
                or nstep > kr.STALL_STEPS + kr.STALL_RATE * (t - t_eval[0]) / hmax):  # fmt: skip
            status = kr.ST_STALL
            break
        en_old = max(en, 1e-4)
        s_end = 1.0
        # f at the step's end: the next step's f0
        if kp.rhs(t + hh, ynew, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, f1) != 0:
            status = kr.ST_SINGULAR
            break
        nfev += 1
        n_end = kr._min_normal(N)
        if n_end <= 0.0 and not tens:  # uplift (tension): the first N_i = 0, dense output
            sa = 0.0
            sb = 1.0
            while (sb - sa) * hh > kr.EVENT_TTOL and sa < 0.5 * (sa + sb) < sb:
                sm = 0.5 * (sa + sb)
                _dense(y, Z, sm, ys)
                kr._eval(t + sm * hh, ys, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out)
                if kr._min_normal(N) <= 0.0:
                    sb = sm
                else:
                    sa = sm
            _dense(y, Z, sb, ys)
            kr._eval(t + sb * hh, ys, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out)
            for i in range(ni):
                if N[i] <= 0.0 and info[kr.I_IFAIL] < 0:
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
        _locate_stops(t, hh, s_end, y, Z, ys, pos, bp, stops)
        while iout < nt and t_eval[iout] <= t_new:
            since_out = 0
            _dense(y, Z, (t_eval[iout] - t) / hh, ys)
            kr._outputs(t_eval[iout], ys, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out,
                        iout, X, NO, FF, FR, FO, MO)  # fmt: skip
            kr._track_stops(t_eval[iout], ys, pos, bp, stops)
            iout += 1
            info[kr.I_NOUT] = iout  # (the progress line's)
        if s_end < 1.0:
            _dense(y, Z, s_end, ys)
            for k in range(n):
                y[k] = ys[k]
        else:
            for k in range(n):
                yp[k] = y[k]
                y[k] = ynew[k]
                f0[k] = f1[k]
                for a in range(3):
                    Zp[a, k] = Z[a, k]
            hp = hh
        have_prev = s_end >= 1.0
        f0_ready = s_end >= 1.0
        t = t_new
        jac_here = False
        kr._track_stops(t, y, pos, bp, stops)
        if status == kr.ST_UPLIFT:
            info[kr.I_TFAIL] = t
            if iout < nt and t > t_eval[max(iout - 1, 0)]:  # the located instant: last row
                kr._outputs(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, iout, X,
                            NO, FF, FR, FO, MO)  # fmt: skip
                iout += 1
            break
        h = min(hh * min(10.0, max(0.2, fac)), hmax)
        if 1.0 <= h / hh <= 1.2:  # keep the factored step (as RADAU5 does)
            h = hh
    if status != kr.ST_OK and not info[kr.I_TFAIL] == info[kr.I_TFAIL]:
        info[kr.I_TFAIL] = t
    info[kr.I_NSTEP] = nstep
    info[kr.I_NREJ] = nrej
    info[kr.I_NFEV] = nfev
    info[kr.I_NOUT] = iout
    return status
