"""Time loop of the deck on bidirectional isolators: Dormand–Prince 5(4) with located events.

The right-hand side is :func:`nsdyn.models.isolated._kplane.rhs`; the steps the shared pair
(:mod:`nsdyn._kdp5`, error on ``atol + rtol |y|``, steps ending on a record's samples, where it
kinks). Outputs at ``t_eval`` from the dense output, forces from the right-hand side there.

Switch law with a stick disc: every isolator is in a mode (stick, slip, slip-start) held fixed
between events; the switching functions, each crossing from > 0 to <= 0, are

    slip        g = |v| − η                    → stick test
    slip-start  g = 2η − |v|                   → slip (START_EXIT: a slip-start entered at
                                                 |v| = η after a failed stick test leaves it
                                                 only once its own direction dominates)
                g = v·d                        → stick test (the start reverses)
    stick       g = μ_s N (1 + STICK_RTOL) − |τ| → slip-start, d = τ/|τ|

The stick test sticks the isolator if its stick force, computed with it stuck, lies strictly inside
the disc |τ| < μ_s k_p N (1 + STICK_RTOL) (k_p the pressure factor, 1 without pressure dependence),
else it starts slipping in the direction of that force. After each event the stuck isolators are
settled: while one violates its disc, the one with the largest |τ|/μ_s N starts to slip, with any
as loaded as it to TIE_RTOL (symmetric partners break away together); the stick switching function
carries the same bound, so every isolator settle leaves stuck starts above zero. Slip-start
directions come from :func:`kp.start_direction`, exact for one released isolator; several released
together are aligned with their accelerations (:func:`._kplanealign.starts`), and the discs checked
again. Events are located by sampling g on the dense output and bisecting the earliest sample
interval with a crossing to EVENT_TTOL; the step is cut there and restarts. A normal force reaching
zero (uplift) is located the same way and ends the run (ST_UPLIFT, its instant the last output row)
under the detecting contact; a bilateral contact goes on, each onset of tension located and counted
(info I_TTEN: the first, I_NTEN, I_NMIN: the smallest N at accepted states), and under the switch
law N_i is a switching function too: to free (no friction) where it reaches zero, back to a stick
test or slip where it returns. The regularised law runs the loop without switching functions. Rim
contacts: :mod:`._kplanestops`. Steps collapsing far beyond what the record needs (STALL_STEPS,
STALL_RATE per largest step: a stick band η too narrow for the slip direction turning near |v| = 0)
end the run with ST_STALL.
"""

import math

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn import _kdp5 as dp
from nsdyn._klinalg import argmin
from nsdyn.models.isolated import _kplane as kp
from nsdyn.models.isolated import _kplanealign as kal
from nsdyn.models.isolated._kplanestops import (  # noqa: F401 (the loops' shared names)
    EVENT_TTOL,
    P_NSTEPS,
    P_PEAK,
    P_TFIRST,
    SAMPLES,
    tension_mode,
)
from nsdyn.models.isolated._kplanestops import crossed as _crossed
from nsdyn.models.isolated._kplanestops import locate_stops as _locate_stops
from nsdyn.models.isolated._kplanestops import overshoot as _overshoot  # noqa: F401
from nsdyn.models.isolated._kplanestops import track_stops as _track_stops
from nsdyn.models.isolated.bearings import B_MUS, B_MUSLOW

ST_OK, ST_UNDERFLOW, ST_MAX_STEPS, ST_NONFINITE, ST_SINGULAR = 0, 1, 2, 3, 4
ST_UPLIFT, ST_CHATTER, ST_EVENTS, ST_NEWTON, ST_STALL = 5, 6, 7, 8, 9
STALL_STEPS = 100_000  # steps beyond 10 per largest step between two outputs, or beyond
STALL_RATE = 200  # this many per largest step since the start: collapsed steps (ST_STALL)
STICK_RTOL = 1e-9  # relative slack of the disc test |τ| <= μ_s N
START_EXIT = 2.0  # a slip-start becomes a slip at |v| = this x eta (entered at |v| <= eta)
RESTICK_MARGIN = 1e-6  # a slip-start held by a stuck deck sticks below (1 - this) mu_d(0) N
SETTLE_PASSES = 64
TIE_RTOL = 1e-8  # stuck isolators this close to the worst's |τ|/μ_s N break away with it
BAND_RTOL = 0.1  # slips within (1 + this) η join another's stick test (slowing to the band)
ALIGN_PASSES = 100  # a pair system's fixed-point passes aligning its slip-start directions
ALIGN_TOL = 1e-12  # largest change of a slip-start direction accepted as converged
BURST_DT = 1e-8  # s, events closer than this count as one burst
MAX_BURST = 200  # events in one burst before reporting chattering
H_MIN = 1e-14  # relative step floor
C_RTOL, C_ATOLQ, C_ATOLV, C_H0, C_HMAX, C_MAXSTEPS = range(6)  # cfg entries
I_NSTEP, I_NREJ, I_NFEV, I_NEV, I_TFAIL, I_IFAIL, I_NOUT, I_TTEN, I_NTEN, I_NMIN, I_EIMP = range(11)
N_INFO = 11  # info entries (I_IFAIL: uplift's / first tensile isolator; I_EIMP: landings' energy)


@njit(cache=True, error_model="numpy")
def n_stuck(modes) -> int:  # the isolators in stick
    n = 0
    for m in modes:
        n += m == kp.MODE_STICK
    return n


@ka.compiled_uncounted
def gvals(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, g):
    """Switching functions (ni, 3) at (t, y); stuck isolators (and a bilateral contact's
    normal forces, column 2) need one evaluation."""
    qdd, N, Ff, Fr, Fo = out
    ni = pos.shape[0]
    nst = n_stuck(modes)
    st = kp.ST_OK
    bil = int(sp[kp.S_CONTACT]) == kp.CONTACT_BILATERAL
    if nst > 0 or bil:
        st = kp.evaluate_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out)
    eta = sp[kp.S_ETA]
    for i in range(ni):
        _, _, vx, vy = kp.slip_kinematics(y, pos, i)
        speed = math.sqrt(vx * vx + vy * vy)
        g[i, 0], g[i, 1] = 1.0, 1.0
        g[i, 2] = (-N[i] if modes[i] == kp.MODE_FREE else N[i]) if bil else 1.0
        if modes[i] == kp.MODE_SLIP:
            g[i, 0] = speed - eta
        elif modes[i] == kp.MODE_START:
            g[i, 0] = START_EXIT * eta - speed
            if nst < 2:  # (two stuck isolators hold the deck: v = 0, no reversal to see)
                g[i, 1] = vx * dirs[i, 0] + vy * dirs[i, 1]
        elif modes[i] == kp.MODE_STICK:
            lim = bp[i, B_MUS] * ws[11][i] * N[i] * (1.0 + STICK_RTOL)  # settle's own bound
            g[i, 0] = lim - math.sqrt(Ff[i, 0] ** 2 + Ff[i, 1] ** 2)
    return st


@ka.compiled_uncounted
def settle(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, EV, info):
    """Release stuck isolators outside their disc, worst first, then align the slip-starts
    and check the discs again (as the pair systems' settle); returns a status."""
    qdd, N, Ff, Fr, Fo = out
    bil = int(sp[kp.S_CONTACT]) == kp.CONTACT_BILATERAL
    nst = n_stuck(modes)
    if nst >= 2:  # a held deck: its slip-starts, stopped by the others, stick again if
        # their stick force falls below the kinetic level mu_d(0) N (1 - RESTICK_MARGIN)
        cand = ws[16]
        anyc = False
        for i in range(pos.shape[0]):
            cand[i] = False
            if modes[i] == kp.MODE_START:
                _, _, vx, vy = kp.slip_kinematics(y, pos, i)
                if math.sqrt(vx * vx + vy * vy) <= sp[kp.S_ETA]:
                    modes[i] = kp.MODE_STICK
                    cand[i] = True
                    anyc = True
        if anyc:
            st = kp.evaluate_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out)
            if st != kp.ST_OK:
                return ST_SINGULAR
            for i in range(pos.shape[0]):
                if cand[i]:
                    tau = math.sqrt(Ff[i, 0] ** 2 + Ff[i, 1] ** 2)
                    if tau <= bp[i, B_MUSLOW] * ws[11][i] * N[i] * (1.0 - RESTICK_MARGIN):
                        _record(EV, info, t, i, kp.MODE_START, kp.MODE_STICK, dirs)
                    else:
                        modes[i] = kp.MODE_START
    checked = False  # the stuck discs checked under the aligned starts
    for _ in range(SETTLE_PASSES):
        st = kp.evaluate_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out)
        if st != kp.ST_OK:
            return ST_SINGULAR
        worst = np.int64(-1)
        ratio = 0.0
        for i in range(pos.shape[0]):
            if modes[i] == kp.MODE_STICK:
                tau = math.sqrt(Ff[i, 0] ** 2 + Ff[i, 1] ** 2)
                lim = bp[i, B_MUS] * ws[11][i] * N[i]
                r = tau / lim if lim > 0.0 else math.inf
                if r >= 1.0 + STICK_RTOL and r > ratio and tau > 0.0:  # kept: g > 0 strictly
                    ratio = r
                    worst = i
        if worst < 0 and checked:
            return ST_OK
        if worst < 0:
            ok = kal.starts(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out)
            for k in range(min(int(info[I_NEV]), EV.shape[0]) - 1, -1, -1):  # this event's rows
                if EV[k, 0] != t:  # (they keep the aligned directions)
                    break
                if EV[k, 3] == kp.MODE_START:
                    EV[k, 4], EV[k, 5] = dirs[int(EV[k, 1]), 0], dirs[int(EV[k, 1]), 1]
            if ok and bil and _tension(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws,
                                       out, EV, info):  # fmt: skip
                continue  # (the normal forces as the aligned starts left them)
            if not ok or n_stuck(modes) != 1:  # (none stuck, or a held deck's: as made)
                return ST_OK if ok else ST_SINGULAR
            checked = True  # (starts aligned about the one stuck load it anew: 4 mu N once)
            continue
        checked = False
        # the worst and its ties (released alone, it moved its load onto its partners)
        for i in range(pos.shape[0]):  # (directions from this evaluation, all stuck)
            lim = bp[i, B_MUS] * ws[11][i] * N[i]
            tau = math.sqrt(Ff[i, 0] ** 2 + Ff[i, 1] ** 2)
            tie = lim > 0.0 and tau >= ratio * (1.0 - TIE_RTOL) * lim
            if modes[i] == kp.MODE_STICK and (i == worst or tie):
                kp.start_direction(i, Ff[i, 0], Ff[i, 1], kp.mu_kinetic(bp, i, 0.0) * ws[11][i]
                                   * N[i], ws[0], pos, dirs, ws[13], ws[14], ws[15])  # fmt: skip
                _record(EV, info, t, i, kp.MODE_STICK, kp.MODE_START, dirs)
                modes[i] = kp.MODE_START
    return ST_CHATTER


# settling by address (compiled once, on its own: see nsdyn.models.isolated.deck_compile)
ka.tslot("deck.settle", settle, "nsdyn.models.isolated.deck_compile:callees")


@njit(cache=True, error_model="numpy", inline="always")
def settle_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, EV, info):
    """:func:`settle` called by its address in the table of :mod:`nsdyn._kaddress`."""
    return ka.tcall("deck.settle", (t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out,
                                    EV, info))  # fmt: skip


@ka.compiled_uncounted
def _tension(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, EV, info):
    """A bilateral contact's modes made to agree with the normal forces as they now are
    (:func:`tension_mode`: free exactly in tension); whether any changed."""
    if kp.evaluate_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out) != kp.ST_OK:
        return False  # (the next step's evaluation names it)
    changed = False
    for i in range(pos.shape[0]):
        _, _, vx, vy = kp.slip_kinematics(y, pos, i)
        new = tension_mode(modes[i], out[1][i], math.sqrt(vx * vx + vy * vy), sp[kp.S_ETA])
        if new != modes[i]:
            _record(EV, info, t, i, modes[i], new, dirs)
            modes[i] = new
            changed = True
    return changed


@ka.compiled_uncounted
def _record(EV, info, t, i, old, new, dirs):
    """Row of the event table: t, isolator, old mode, new mode, its slip-start direction."""
    k = int(info[I_NEV])
    if k < EV.shape[0]:
        EV[k, 0] = t
        EV[k, 1] = i
        EV[k, 2] = old
        EV[k, 3] = new
        EV[k, 4] = dirs[i, 0] if new == kp.MODE_START else 0.0
        EV[k, 5] = dirs[i, 1] if new == kp.MODE_START else 0.0
    info[I_NEV] = k + 1


@ka.compiled_uncounted
def initial_modes(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, EV, info):
    """Modes at the start: slip where |v| > η, else stick, then settled."""
    for i in range(pos.shape[0]):
        _, _, vx, vy = kp.slip_kinematics(y, pos, i)
        modes[i] = kp.MODE_SLIP if math.sqrt(vx * vx + vy * vy) > sp[kp.S_ETA] else kp.MODE_STICK
    st = settle_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, EV, info)
    if st != ST_OK or int(sp[kp.S_CONTACT]) != kp.CONTACT_BILATERAL:
        return st
    if _eval(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out) != kp.ST_OK:
        return ST_SINGULAR
    free = False
    for i in range(pos.shape[0]):  # tensile from the start: free
        if out[1][i] <= 0.0:
            modes[i] = kp.MODE_FREE
            free = True
    if not free:
        return st
    return settle_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, EV, info)


@ka.compiled_uncounted
def band_tie(EV, info, t, i, modes, speed, eta, dirs):
    """Slip ``i`` at ``speed`` within (1 + BAND_RTOL) η joins this event's stick test (the
    deck's and the pair systems' switch)."""
    if modes[i] == kp.MODE_SLIP and speed <= eta * (1.0 + BAND_RTOL):
        modes[i] = kp.MODE_STICK
        _record(EV, info, t, i, kp.MODE_SLIP, kp.MODE_STICK, dirs)


@ka.compiled_uncounted
def switch(t, y, g0, g, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, EV, info):
    """Mode changes at a located event (g0 before it, g just after); returns a status."""
    qdd, N, Ff, Fr, Fo = out
    ni = pos.shape[0]
    # the stick forces of the modes before the event
    st = kp.evaluate_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out)
    if st != kp.ST_OK:
        return ST_SINGULAR
    test = False  # a stick test at this event
    for i in range(ni):  # every decision on the mode before the event
        m0 = modes[i]
        _, _, vx, vy = kp.slip_kinematics(y, pos, i)
        if g0[i, 2] > 0.0 and g[i, 2] <= 0.0:  # a bilateral contact into / out of tension
            modes[i] = kp.MODE_FREE if m0 != kp.MODE_FREE else kp.MODE_SLIP
        elif m0 == kp.MODE_STICK and g0[i, 0] > 0.0 and g[i, 0] <= 0.0:
            kp.start_direction(i, Ff[i, 0], Ff[i, 1], kp.mu_kinetic(bp, i, 0.0) * ws[11][i] * N[i],
                               ws[0], pos, dirs, ws[13], ws[14], ws[15])  # fmt: skip
            modes[i] = kp.MODE_START
        elif m0 == kp.MODE_START and g0[i, 0] > 0.0 and g[i, 0] <= 0.0:
            modes[i] = kp.MODE_SLIP
        elif (m0 == kp.MODE_SLIP and g0[i, 0] > 0.0 and g[i, 0] <= 0.0) or (
            m0 == kp.MODE_START and g0[i, 1] > 0.0 and g[i, 1] <= 0.0
        ):
            modes[i] = kp.MODE_STICK  # stick test: settle releases it if outside the disc
        if modes[i] == kp.MODE_SLIP:  # a slip needs |v| > eta for its direction v/|v|
            if math.sqrt(vx * vx + vy * vy) <= sp[kp.S_ETA]:
                modes[i] = kp.MODE_STICK
        if modes[i] != m0:
            _record(EV, info, t, i, m0, modes[i], dirs)
            test = test or modes[i] == kp.MODE_STICK
    if test:  # partners slowing to the band with it test together (BAND_RTOL)
        for i in range(ni):
            _, _, vx, vy = kp.slip_kinematics(y, pos, i)
            band_tie(EV, info, t, i, modes, math.sqrt(vx * vx + vy * vy), sp[kp.S_ETA], dirs)
    return settle_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, EV, info)


ka.tslot("deck.switch", switch, "nsdyn.models.isolated.deck_compile:callees")


@ka.compiled_uncounted
def _outputs(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, k, X, NO, FF, FR, FO, MO):
    qdd, N, Ff, Fr, Fo = out
    kp.evaluate_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out)
    for j in range(min(y.shape[0], X.shape[1])):  # [q, q̇] and internal slips (X's columns)
        X[k, j] = y[j]
    for i in range(pos.shape[0]):
        NO[k, i] = N[i]
        MO[k, i] = modes[i]
        for c in range(2):
            FF[k, i, c] = Ff[i, c]
            FR[k, i, c] = Fr[i, c]
            FO[k, i, c] = Fo[i, c]


@ka.compiled_uncounted
def _eval(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out):
    qdd, N, Ff, Fr, Fo = out
    return kp.evaluate_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out)


@ka.compiled_uncounted
def tension_start(info, t, N, bil):
    """A bilateral run's tension record at its start (N_min, an onset if tensile); tensile?"""
    info[I_TTEN] = np.nan
    info[I_NTEN] = 0.0
    info[I_NMIN] = _min_normal(N)
    if bil and info[I_NMIN] <= 0.0:
        info[I_IFAIL] = argmin(N)
        tension_onset(info, t)
    return bil and info[I_NMIN] <= 0.0


@njit(cache=True, error_model="numpy", **ka.NO_NRT)
def tension_onset(info, t):
    """Count a located onset of tension at t (the first kept in I_TTEN)."""
    if not info[I_TTEN] == info[I_TTEN]:
        info[I_TTEN] = t
    info[I_NTEN] += 1.0


@ka.compiled_uncounted
def _min_normal(N):
    v = math.inf
    for i in range(N.shape[0]):
        v = min(v, N[i])
    return v


@njit(cache=True, error_model="numpy", nogil=True, **ka.NO_NRT)  # (watched: info[I_NOUT])
def integrate(y0, t_eval, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, cfg,
              X, NO, FF, FR, FO, MO, EV, stops, info, ws, out, S):  # fmt: skip
    """Integrate from y0 at t_eval[0] to t_eval[-1]; outputs at t_eval; returns a status.
    ``ws, out, S``: its scratch (:func:`nsdyn.models.isolated.deck_compile.loop_arrays`)."""
    n = 6
    ni = pos.shape[0]
    N = out[1]
    k, y, y1, ys, rc, g0, g, ga = S
    for i in range(ni):
        for c in range(3):
            g0[i, c] = 1.0
            g[i, c] = 1.0
            ga[i, c] = 1.0
    for j in range(n):
        y[j] = y0[j]
    bil = int(sp[kp.S_CONTACT]) == kp.CONTACT_BILATERAL
    switching = int(sp[kp.S_LAW]) == kp.LAW_SWITCH
    rtol = cfg[C_RTOL]
    hmax = cfg[C_HMAX]
    max_steps = int(cfg[C_MAXSTEPS])
    nt = t_eval.shape[0]
    t = t_eval[0]
    t_end = t_eval[nt - 1]
    ntab = tab.shape[1]
    info[I_TFAIL] = np.nan
    info[I_IFAIL] = -1
    if switching:
        st = initial_modes(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, EV, info)
        if st != ST_OK:
            info[I_TFAIL] = t
            return st
    k0 = np.int64(0)  # typed: one compilation of _outputs (a literal 0 would be a second)
    _outputs(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, k0, X, NO, FF, FR, FO, MO)
    iout = np.int64(1)
    tens = tension_start(info, t, N, bil)
    if _min_normal(N) <= 0.0 and not bil:  # (at the start: the output there, its isolator)
        info[I_TFAIL], info[I_IFAIL], info[I_NOUT] = t, argmin(N), iout
        return ST_UPLIFT
    fresh = True
    h = min(cfg[C_H0], hmax)
    nstep = 0
    nrej = 0
    nfev = 0
    burst_t = -math.inf
    burst_n = 0
    since_out = 0
    status = ST_OK
    while t < t_end and iout < nt:
        if fresh:
            if kp.rhs(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, k[0]) != 0:
                status = ST_SINGULAR
                break
            nfev += 1
            if switching:
                gvals(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, g0)
            fresh = False
        hh = min(h, hmax, t_end - t)
        tb = kp.next_breakpoint(t, gk, gp, ntab)
        if t + hh > tb:
            hh = tb - t
        bad = False
        for j in range(1, 7):
            dp.stage(y, k, hh, j, y1)
            if kp.rhs(t + dp.C[j] * hh, y1, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out,
                      k[j]) != 0:  # fmt: skip
                bad = True
        nfev += 6
        err = 0.0
        for i in range(n):
            sc = (cfg[C_ATOLQ] if i < 3 else cfg[C_ATOLV]) + rtol * max(abs(y[i]), abs(y1[i]))
            err += (dp.error(k, hh, i) / sc) ** 2
        err = math.sqrt(err / n)
        if bad or not math.isfinite(err) or err > 1.0:
            nrej += 1
            h = dp.new_step(hh, err) if (math.isfinite(err) and not bad) else 0.25 * hh
            if h <= H_MIN * max(1.0, abs(t)):
                status = ST_UNDERFLOW if (math.isfinite(err) and not bad) else ST_NONFINITE
                break
            continue
        nstep += 1
        ws[19][1] = np.nan  # no impasse in an accepted step (a bad stage shrinks h at once)
        if nstep + nrej > max_steps:
            status = ST_MAX_STEPS
            break
        since_out += 1  # the record needs ~ (time span)/hmax steps, a few more per event
        if (since_out > STALL_STEPS + 10.0 * (t_eval[iout] - t_eval[iout - 1]) / hmax
                or nstep > STALL_STEPS + STALL_RATE * (t - t_eval[0]) / hmax):  # fmt: skip
            status = ST_STALL
            break
        n_end_min = _min_normal(N)  # the last stage is the step's end
        dp.dense_coefficients(y, y1, k, hh, rc)
        s_end = 1.0
        event = False
        if switching:  # earliest sample interval with a crossing, then bisection
            sa = 0.0
            for m in range(1, SAMPLES + 1):
                sb = m / SAMPLES
                dp.dense_state(rc, sb, ys)
                gvals(t + sb * hh, ys, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, g)
                nfev += 1
                if _crossed(g0, g):
                    event = True
                    while (sb - sa) * hh > EVENT_TTOL and sa < 0.5 * (sa + sb) < sb:
                        sm = 0.5 * (sa + sb)
                        dp.dense_state(rc, sm, ys)
                        gvals(t + sm * hh, ys, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws,
                              out, ga)  # fmt: skip
                        nfev += 1
                        if _crossed(g0, ga):
                            sb = sm
                        else:
                            sa = sm
                    s_end = sb
                    dp.dense_state(rc, sb, ys)
                    gvals(t + sb * hh, ys, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, g)
                    break
                sa = sb
        n_cut = n_end_min
        if event or n_end_min <= 0.0:  # normal force at the cut (or step end)
            dp.dense_state(rc, s_end, ys)
            _eval(t + s_end * hh, ys, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out)
            n_cut = _min_normal(N)
            if n_cut <= 0.0 and not tens:  # uplift (tension): locate the first N_i = 0
                sa = 0.0
                sb = s_end
                while (sb - sa) * hh > EVENT_TTOL and sa < 0.5 * (sa + sb) < sb:
                    sm = 0.5 * (sa + sb)
                    dp.dense_state(rc, sm, ys)
                    _eval(t + sm * hh, ys, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws,
                                out)  # fmt: skip
                    if _min_normal(N) <= 0.0:
                        sb = sm
                    else:
                        sa = sm
                dp.dense_state(rc, sb, ys)
                _eval(t + sb * hh, ys, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out)
                for i in range(ni):
                    if N[i] <= 0.0 and info[I_IFAIL] < 0:
                        info[I_IFAIL] = i
                if bil:  # the contact holds: recorded, the step kept
                    tension_onset(info, t + sb * hh)
                else:
                    s_end = sb
                    event = False
                    status = ST_UPLIFT
        if bil:
            tens = n_cut <= 0.0
            info[I_NMIN] = min(info[I_NMIN], n_cut)
        t_new = t + s_end * hh if s_end < 1.0 else t + hh
        _locate_stops(t, hh, s_end, rc, ys, pos, bp, stops)
        while iout < nt and t_eval[iout] <= t_new:
            s = (t_eval[iout] - t) / hh
            dp.dense_state(rc, s, ys)
            _outputs(t_eval[iout], ys, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, iout,
                     X, NO, FF, FR, FO, MO)  # fmt: skip
            _track_stops(t_eval[iout], ys, pos, bp, stops)
            iout += 1
            info[I_NOUT] = iout  # (the progress line's)
            since_out = 0
        if s_end < 1.0:
            dp.dense_state(rc, s_end, ys)
            for j in range(n):
                y[j] = ys[j]
        else:
            for j in range(n):
                y[j] = y1[j]
        t = t_new
        _track_stops(t, y, pos, bp, stops)
        if status == ST_UPLIFT:
            info[I_TFAIL] = t
            if iout < nt and t > t_eval[max(iout - 1, 0)]:  # the located instant: last row
                _outputs(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, iout, X, NO,
                         FF, FR, FO, MO)  # fmt: skip
                iout += 1
            break
        if event:
            if t - burst_t < BURST_DT:
                burst_n += 1
                if burst_n > MAX_BURST:
                    status = ST_CHATTER
                    info[I_TFAIL] = t
                    break
            else:
                burst_t = t
                burst_n = 0
            st = ka.tcall("deck.switch", (t, y, g0, g, modes, dirs, M, pos, bp, nd, sp, gk, gp,
                                          tab, ws, out, EV, info))  # fmt: skip
            if st != ST_OK:
                status = st
                info[I_TFAIL] = t
                break
            fresh = True
            h = hh
        else:
            for j in range(n):
                k[0, j] = k[6, j]
            if switching:
                for i in range(ni):
                    for c in range(3):
                        g0[i, c] = g[i, c]
            h = min(dp.new_step(hh, err), hmax)
    if status != ST_OK and not info[I_TFAIL] == info[I_TFAIL]:
        info[I_TFAIL] = t
    info[I_NSTEP], info[I_NREJ], info[I_NFEV], info[I_NOUT] = nstep, nrej, nfev, iout
    return status
