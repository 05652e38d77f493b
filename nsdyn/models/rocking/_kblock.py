"""Numba kernel: a rigid block (or an equivalent one-dof rocking frame) rocking on rigid ground.

Equation of motion on pivot side ``s = sgn(theta)`` (Housner; ``g_e = 1 + ü_v / g``)::

    exact:       theta'' = -p² [g_e sin(s alpha - theta) + (ü_h / g) cos(s alpha - theta)]
    linearised:  theta'' = -p² [g_e (s alpha - theta) + ü_h / g]

integrated by Dormand–Prince 5(4) with error control on ``(theta, theta')`` scaled by
``(alpha, p alpha)``. Every accepted step is scanned at ``N_SCAN`` points of its dense output for

- impact: ``s theta`` reaches 0 -> root by Illinois on the dense output, then
  ``theta'+ = r theta'-``, ``s -> -s`` (Housner's angular-momentum balance gives r);
- a peak: ``s theta'`` changes from + to -, located the same way;
- overturning: ``|theta|`` reaches ``theta_fall``.

From rest the block lifts off when ``|ü_h| / g > g_e tan(alpha)`` (``alpha`` when linearised),
located by bisection in time; it lifts towards ``s = -sgn(ü_h)``.

Zeno rule: an impact that leaves ``|theta'+| <= v_rest`` puts the block at rest (theta = 0,
theta' = 0) at the impact time, after which the uplift condition is checked again at once.
The truncated tail of the geometric impact sequence lasts about ``2 v_rest / (p² alpha (1-r))``
for free rocking (ground below threshold; at least that in the linearised equation, by a
relative (v_rest / (p alpha))² / 3, and about alpha / sin(alpha) times it in the exact one:
1 % more at alpha = 0.25), and the number of impacts stays finite.
"""

import math

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn import _kborrow as kb
from nsdyn import _kdp5 as dp
from nsdyn.models.rocking._kground import (
    GK_NONE,
    LEFT_LIMIT,
    RIGHT_LIMIT,
    ground_t,
    next_breakpoint,
    rest_step,
    step_to_breakpoint,
)

# ---- parameter vector ``par`` ----------------------------------------------------------------
P_P2 = 0  # p² [1/s²]
P_ALPHA = 1  # slenderness alpha [rad]
P_R = 2  # coefficient of restitution (angular velocity ratio)
P_LINEAR = 3  # 1: linearised equation, 0: exact
P_G = 4  # gravity [m/s²]
P_TOL = 5  # relative error tolerance of the integrator
P_HMAX = 6  # largest step [s]
P_VREST = 7  # Zeno rest threshold on |theta'| after an impact [rad/s]
P_THFALL = 8  # |theta| at which the block counts as overturned [rad]
N_PAR = 9

# components of the state (theta, theta') as typed values: one compilation of their callees
C_TH = np.int64(0)
C_THD = np.int64(1)

# ---- info vector ----------------------------------------------------------------------------
I_NIMP = 0  # impacts recorded
I_NPEAK = 1  # peaks recorded
I_TOVER = 2  # overturning time (nan if none)
I_OUTCOME = 3  # OUT_* code
I_TREST = 4  # last time the block came to rest after rocking (nan if never)
I_NSTEP = 5  # accepted steps
I_NREJ = 6  # rejected steps
I_MAXTH = 7  # max |theta|
I_NOUT = 8  # output samples filled
I_NUPL = 9  # number of lift-offs from rest
I_TUPL = 10  # first lift-off time (nan if none)
I_TFAIL = 11  # time of a failure (status != 0)
I_NRHS = 12  # right-hand-side evaluations
N_INFO = 13

ST_OK = 0  # finished
ST_TOO_MANY = 1  # impact buffer full (too many events)
ST_UNDERFLOW = 2  # step size underflow
ST_NONFINITE = 3  # non-finite state
ST_FLIGHT = 4  # vertical ground acceleration below -g: free flight is not modelled

OUT_REST = 0  # at rest at the end (never lifted off, or came to rest)
OUT_ROCKING = 1  # still rocking at the end
OUT_OVERTURNED = 2  # overturned

N_SCAN = 8  # dense-output samples scanned per step for events
ROOT_ITERS = 100  # Illinois iterations at most
ROOT_TOL = 1e-15  # root tolerance in the step fraction sigma
H_MIN = 1e-13  # step-size underflow threshold [s] (relative to 1 + |t|)
UPLIFT_BISECT = 80  # bisection iterations locating a lift-off time


@ka.compiled_only
def accel(t, left, th, s, par, gk, gp, tab_h, tab_v):
    """theta'' on pivot side ``s``."""
    ah, av = ground_t(t, left, gk, gp, tab_h, tab_v)
    g = par[P_G]
    ge = 1.0 + av / g
    phi = s * par[P_ALPHA] - th
    if par[P_LINEAR] > 0.5:
        return -par[P_P2] * (ge * phi + ah / g)
    return -par[P_P2] * (ge * math.sin(phi) + ah / g * math.cos(phi))


@ka.compiled_only
def uplift_side(t, left, par, gk, gp, tab_h, tab_v):
    """Side (+1/-1) the ground lifts a resting block onto, 0 if none, -2 if g + ü_v <= 0."""
    ah, av = ground_t(t, left, gk, gp, tab_h, tab_v)
    g = par[P_G]
    ge = 1.0 + av / g
    if ge <= 0.0:
        return -2
    thr = par[P_ALPHA] if par[P_LINEAR] > 0.5 else math.tan(par[P_ALPHA])
    if abs(ah) / g > ge * thr:
        return -1 if ah > 0.0 else 1
    return 0


@ka.compiled_only
def _root(rc, comp, sgn, off, a, b, fa, fb):
    """Illinois root of ``sgn * y_comp(sigma) - off`` on [a, b] with fa > 0 >= fb."""
    side = np.int64(0)
    for _ in range(ROOT_ITERS):
        if b - a <= ROOT_TOL:
            break
        m = (a * fb - b * fa) / (fb - fa)
        if not (a < m < b):
            m = 0.5 * (a + b)
        fm = sgn * dp.dense(rc, comp, m) - off
        if fm > 0.0:
            a, fa = m, fm
            if side == 1:
                fb *= 0.5
            side = 1
        else:
            b, fb = m, fm
            if side == -1:
                fa *= 0.5
            side = -1
            if fm == 0.0:
                break
    return b


# no reference counts (NO_NRT): the loop allocates nothing, every array is its caller's
@njit(cache=True, error_model="numpy", **ka.NO_NRT)
def integrate(
    par, gk, gp, tab_h, tab_v, y0, t0, t_end, out_dt, out, imp, peaks, info, k, rc, y, y1
):
    """Integrate from ``y0 = (theta, theta')`` at ``t0`` to ``t_end``; returns an ST_* status.

    ``out`` (n_out, 2): theta, theta' at ``t0 + k out_dt`` (filled up to ``info[I_NOUT]``);
    ``imp`` (n_imp_max, 3): impact time, theta' before, theta' after; ``peaks`` (n_pk_max, 2):
    time and theta of each extremum of |theta|; ``info`` (N_INFO,): see the I_* indices.
    Workspace (overwritten): ``k`` (7, 2) the stages, ``rc`` (5, 2) the dense output's
    coefficients, ``y`` and ``y1`` (2,) a step's start and a stage's state (the caller
    allocates them: the kernel then compiles without numba's allocation routines).
    """
    p2 = par[P_P2]
    alpha = par[P_ALPHA]
    r = par[P_R]
    tol = par[P_TOL]
    hmax = par[P_HMAX]
    vrest = par[P_VREST]
    thfall = par[P_THFALL]
    g = par[P_G]
    sc0 = alpha
    sc1 = math.sqrt(p2) * alpha
    n_out = out.shape[0]
    n_tab = tab_h.size
    for i in range(N_INFO):
        info[i] = 0.0
    info[I_TOVER] = np.nan
    info[I_TREST] = np.nan
    info[I_TUPL] = np.nan
    info[I_TFAIL] = np.nan
    # borrowed views (nsdyn._kborrow): no atomic reference counts per stage and step
    own = (k, rc, y, y1)
    k, rc, y, y1 = kb.borrowed(own)
    par, gp, tab_h, tab_v, y0, out, imp, peaks, info = kb.borrowed(
        (par, gp, tab_h, tab_v, y0, out, imp, peaks, info)
    )
    t = t0
    th = y0[0]
    thd = y0[1]
    rocking = not (th == 0.0 and thd == 0.0)
    s = 1.0
    if th != 0.0:
        s = 1.0 if th > 0.0 else -1.0
    elif thd != 0.0:
        s = 1.0 if thd > 0.0 else -1.0
    h = min(hmax, 0.01 / math.sqrt(p2))
    fsal = False
    check_now = True
    n_imp = 0
    n_pk = 0
    k_out = 0
    n_step = 0
    n_rej = 0
    n_rhs = 0
    n_upl = 0
    maxth = abs(th)
    status = ST_OK
    overturned = False
    t_stop = t_end - 1e-15 * abs(t_end) - 1e-300  # (t_end (1 - 1e-15) lay past a negative t_end)
    while t < t_stop:
        if not rocking:
            side = 0
            if check_now:
                side = uplift_side(t, RIGHT_LIMIT, par, gk, gp, tab_h, tab_v)
            check_now = True
            if side == -2:
                status = ST_FLIGHT
                info[I_TFAIL] = t
                break
            if side == 0:
                if gk == GK_NONE:
                    t_next = t_end
                else:
                    t_next = min(t + rest_step(t, gk, gp, n_tab), next_breakpoint(t, gk, gp, n_tab))
                    t_next = min(t_next, t_end)
                side2 = uplift_side(t_next, LEFT_LIMIT, par, gk, gp, tab_h, tab_v)
                if side2 == 0:
                    while k_out < n_out and t0 + k_out * out_dt <= t_next:
                        out[k_out, 0] = 0.0
                        out[k_out, 1] = 0.0
                        k_out += 1
                    t = t_next
                    continue
                a = t
                b = t_next
                for _ in range(UPLIFT_BISECT):
                    m = 0.5 * (a + b)
                    if uplift_side(m, RIGHT_LIMIT, par, gk, gp, tab_h, tab_v) != 0:
                        b = m
                    else:
                        a = m
                    if b - a <= 1e-14 * (1.0 + abs(b)):
                        break
                t = b
                side = uplift_side(t, RIGHT_LIMIT, par, gk, gp, tab_h, tab_v)
                if side == 0:
                    side = side2
                if side == -2:
                    status = ST_FLIGHT
                    info[I_TFAIL] = t
                    break
                while k_out < n_out and t0 + k_out * out_dt <= t:
                    out[k_out, 0] = 0.0
                    out[k_out, 1] = 0.0
                    k_out += 1
            rocking = True
            s = float(side)
            th = 0.0
            thd = 0.0
            n_upl += 1
            if n_upl == 1:
                info[I_TUPL] = t
            fsal = False
            h = min(hmax, 0.01 / math.sqrt(p2))
            continue

        # ---- one Dormand-Prince step on side s ------------------------------------------------
        if 1.0 + ground_t(t, RIGHT_LIMIT, gk, gp, tab_h, tab_v)[1] / par[P_G] <= 0.0:
            status = ST_FLIGHT  # the ground falls faster than g under the rocking block (checked
            info[I_TFAIL] = t  # at each step's start: a record's samples bound the steps)
            break
        h_before = min(h, hmax)
        hh, at_bp = step_to_breakpoint(t, h_before, t_end, gk, gp, n_tab)
        y[0] = th
        y[1] = thd
        if not fsal:
            k[0, 0] = thd
            k[0, 1] = accel(t, RIGHT_LIMIT, th, s, par, gk, gp, tab_h, tab_v)
            n_rhs += 1
        for j in range(1, 7):  # the last stage is evaluated at the solution y1
            dp.stage(y, k, hh, j, y1)
            k[j, 0] = y1[1]
            k[j, 1] = accel(t + dp.C[j] * hh, at_bp and j >= 5, y1[0], s, par, gk, gp, tab_h, tab_v)
        n_rhs += 6
        err = 0.0
        for i in range(2):
            sci = tol * ((sc0 if i == 0 else sc1) + max(abs(y[i]), abs(y1[i])))
            err += (dp.error(k, hh, i) / sci) ** 2
        err = math.sqrt(0.5 * err)
        if not math.isfinite(err):
            if hh <= H_MIN * (1.0 + abs(t)):
                status = ST_NONFINITE
                info[I_TFAIL] = t
                break
            h = 0.2 * hh
            n_rej += 1
            fsal = True
            continue
        if err > 1.0:
            h = dp.new_step(hh, err)
            n_rej += 1
            fsal = True
            if h <= H_MIN * (1.0 + abs(t)):
                status = ST_UNDERFLOW
                info[I_TFAIL] = t
                break
            continue
        n_step += 1
        dp.dense_coefficients(y, y1, k, hh, rc)

        # ---- events: impact (s theta -> 0) or overturning (s theta -> theta_fall) -------------
        event = 0
        sig = 1.0
        sg_prev = 0.0
        g_prev = s * th
        for j in range(1, N_SCAN + 1):
            sg = j / N_SCAN
            gj = s * dp.dense(rc, C_TH, sg)
            if gj >= thfall:
                sig = _root(rc, C_TH, -s, -thfall, sg_prev, sg, thfall - g_prev, thfall - gj)
                event = 2
                break
            if gj < 0.0:
                a = sg_prev
                fa = g_prev
                if fa <= 0.0:  # starts on the ground: find where it is airborne first
                    m = sg
                    fa = -1.0
                    for _ in range(50):
                        m *= 0.5
                        fm = s * dp.dense(rc, C_TH, m)
                        if fm > 0.0:
                            a = m
                            fa = fm
                            break
                if fa <= 0.0:
                    sig = 0.0
                    event = 3  # no flight at all: the block stays on the ground
                else:
                    sig = _root(rc, C_TH, s, 0.0, a, sg, fa, gj)
                    event = 1
                break
            sg_prev = sg
            g_prev = gj

        # ---- peaks of |theta| (s theta' from + to -) up to sig --------------------------------
        if sig > 0.0:
            v_prev = s * dp.dense(rc, C_THD, 0.0)
            sp = 0.0
            for j in range(1, N_SCAN + 1):
                sg = sig * j / N_SCAN
                vj = s * dp.dense(rc, C_THD, sg)
                if v_prev > 0.0 and vj <= 0.0:
                    sk = _root(rc, C_THD, s, 0.0, sp, sg, v_prev, vj)
                    thk = dp.dense(rc, C_TH, sk)
                    if n_pk < peaks.shape[0]:
                        peaks[n_pk, 0] = t + sk * hh
                        peaks[n_pk, 1] = thk
                        n_pk += 1
                    maxth = max(maxth, abs(thk))
                v_prev = vj
                sp = sg
        t_ev = t + sig * hh
        while k_out < n_out and t0 + k_out * out_dt <= t_ev:
            sk = (t0 + k_out * out_dt - t) / hh
            out[k_out, 0] = dp.dense(rc, C_TH, sk)
            out[k_out, 1] = dp.dense(rc, C_THD, sk)
            k_out += 1
        maxth = max(maxth, abs(dp.dense(rc, C_TH, sig)))

        if event == 2:
            info[I_TOVER] = t_ev
            overturned = True
            t = t_ev
            break
        if event == 1 or event == 3:
            thd_m = dp.dense(rc, C_THD, sig)
            t = t_ev
            th = 0.0
            fsal = False
            h = min(dp.new_step(hh, err), hmax)
            if event == 3:
                rocking = False
                check_now = False
                thd = 0.0
                info[I_TREST] = t
                continue
            if n_imp >= imp.shape[0]:
                status = ST_TOO_MANY
                info[I_TFAIL] = t
                break
            thd = r * thd_m
            imp[n_imp, 0] = t
            imp[n_imp, 1] = thd_m
            imp[n_imp, 2] = thd
            n_imp += 1
            s = -s
            if abs(thd) <= vrest:
                rocking = False
                check_now = True
                thd = 0.0
                info[I_TREST] = t
                continue
            ah, av = ground_t(t, RIGHT_LIMIT, gk, gp, tab_h, tab_v)
            dec = p2 * ((1.0 + av / g) * math.sin(alpha) - abs(ah) / g * math.cos(alpha))
            if dec > 0.0:
                h = min(h, abs(thd) / dec)  # half the estimated flight time 2|theta'|/dec
            continue
        t = t + hh
        th = y1[0]
        thd = y1[1]
        if at_bp:
            fsal = False
        else:
            k[0, 0] = k[6, 0]
            k[0, 1] = k[6, 1]
            fsal = True
        h = min(dp.new_step(hh, err), hmax)
        if at_bp:  # a step shortened to meet a breakpoint says little about the next one
            h = min(max(h, h_before), hmax)

    if status == ST_OK and not overturned and not rocking:
        while k_out < n_out and t0 + k_out * out_dt <= t_end + 1e-15 * abs(t_end):
            out[k_out, 0] = 0.0
            out[k_out, 1] = 0.0
            k_out += 1
    info[I_NIMP] = n_imp
    info[I_NPEAK] = n_pk
    info[I_OUTCOME] = OUT_OVERTURNED if overturned else (OUT_ROCKING if rocking else OUT_REST)
    info[I_NSTEP] = n_step
    info[I_NREJ] = n_rej
    info[I_MAXTH] = maxth
    info[I_NOUT] = k_out
    info[I_NUPL] = n_upl
    info[I_NRHS] = n_rhs
    kb.alive(own)
    return status
