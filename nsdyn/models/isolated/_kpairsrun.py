"""Time loop of a system from matrices on planar isolators: Dormand–Prince 5(4), located events.

The right-hand side is :func:`nsdyn.models.isolated._kpairs.rhs`, the steps the shared
Dormand–Prince pair (:mod:`nsdyn._kdp5`; error on ``atol + rtol |y|``, steps ending on a
record's samples). The switch law's modes, switching functions, stick test and event location
are the deck's (:mod:`nsdyn.models.isolated._kplanerun`, whose generic pieces — crossing test,
dense state, event record, smallest normal force — are imported from there), the settling of
the stuck isolators :mod:`nsdyn.models.isolated._kpairsstick`'s:

    slip        g = |v| − η            → stick test (stick if |τ| ≤ μ_s λ, else slip-start)
    slip-start  g = 2η − |v|           → slip;   g = v·d → stick test (the start reverses)
    stick       g = μ_s k_p λ (1 + STICK_RTOL) − |τ| → slip-start along τ (start_direction)

A normal force reaching zero (uplift) is located on the dense output and ends the run
(ST_UPLIFT); a bilateral contact goes on, its onsets of tension located and counted, its λ_i a
switching function of the switch law (→ free, no friction; back → stick test or slip), as in
the deck's loop. A unilateral contact lifts off where λ_i reaches zero and lands where its gap
closes (:mod:`nsdyn.models.isolated._kpairscontact`: plastic impact), events of either law.
The regularised law runs the same loop without the stick-slip events.
"""

import math

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn import _kdp5 as dp
from nsdyn.models.isolated import _kpairs as kq
from nsdyn.models.isolated import _kpairscontact as kc
from nsdyn.models.isolated import _kplane as kp
from nsdyn.models.isolated import _kplanerun as kr
from nsdyn.models.isolated.bearings import B_MUS


@ka.compiled_only
def _ev(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out):
    return kq.evaluate_t(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out)


@ka.compiled_only
def gvals(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, g):
    """Switching functions (ni, 3) at (t, y) (column 2: a bilateral contact's ±λ_i)."""
    st = _ev(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out)
    gfill(y, modes, dirs, op, bp, sp, ws, out, g)
    return st


@ka.compiled_only
def gfill(y, modes, dirs, op, bp, sp, ws, out, g):
    """:func:`gvals` from the evaluation at y already in ``out`` and ws."""
    lam, Ff = out[1], out[2]
    ni = modes.shape[0]
    v = ws[1]
    eta = sp[kq.S_ETA]
    for i in range(ni):
        vx = v[2 * i]
        vy = v[2 * i + 1]
        speed = math.sqrt(vx * vx + vy * vy)
        g[i, 0] = g[i, 1] = g[i, 2] = 1.0
        if int(sp[kq.S_CONTACT]) == kp.CONTACT_BILATERAL:
            g[i, 2] = -lam[i] if modes[i] == kp.MODE_FREE else lam[i]
        elif int(sp[kq.S_CONTACT]) == kp.CONTACT_UNILATERAL:
            g[i, 2] = kc.switching(y, op, ws, lam, i)
        if int(sp[kq.S_LAW]) != kp.LAW_SWITCH:
            continue
        if modes[i] == kp.MODE_SLIP:
            g[i, 0] = speed - eta
        elif modes[i] == kp.MODE_START:
            g[i, 0] = kr.START_EXIT * eta - speed
            g[i, 1] = vx * dirs[i, 0] + vy * dirs[i, 1]
        elif modes[i] == kp.MODE_STICK:
            lim = bp[i, B_MUS] * ws[13][i] * lam[i] * (1.0 + kr.STICK_RTOL)  # settle's bound
            g[i, 0] = lim - math.sqrt(Ff[i, 0] ** 2 + Ff[i, 1] ** 2)


@ka.compiled_only
def switch(t, y, g0, g, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, EV, info):
    """Mode changes at a located event (g0 before it, g just after); returns a status."""
    lam, Ff = out[1], out[2]
    ni = modes.shape[0]
    if _ev(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out) != kq.ST_OK:
        return kr.ST_SINGULAR
    v = ws[1]
    uni = int(sp[kq.S_CONTACT]) == kp.CONTACT_UNILATERAL
    law_switch = int(sp[kq.S_LAW]) == kp.LAW_SWITCH
    if uni:
        for i in range(ni):  # lift-offs and landings (the velocities may jump)
            if g0[i, 2] > 0.0 and g[i, 2] <= 0.0:
                if ws[20][i] != 0.0:
                    ka.tcall("pairs.land", (t, y, i, modes, dirs, op, ws, EV, info, law_switch,
                                            sp[kq.S_ETA]))  # fmt: skip
                else:
                    kc.open_contact(t, y, i, modes, dirs, op, ws, EV, info)
        st = ka.tcall(
            "pairs.settle_contacts", (t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, EV, info)
        )
        if st != kr.ST_OK or not law_switch:
            return st
        kq.slips(y, op[kq.O_D2], out[0].shape[0], ws[0], v)
    test = False  # a stick test at this event
    for i in range(ni):
        m0 = modes[i]
        if not uni and g0[i, 2] > 0.0 and g[i, 2] <= 0.0:  # bilateral: into / out of tension
            modes[i] = kp.MODE_FREE if m0 != kp.MODE_FREE else kp.MODE_SLIP
        elif m0 == kp.MODE_STICK and g0[i, 0] > 0.0 and g[i, 0] <= 0.0:
            mu_n = kp.mu_kinetic(bp, i, 0.0) * ws[13][i] * lam[i]
            ka.tcall("pairs.start_direction", (i, Ff[i, 0], Ff[i, 1], mu_n, ws, dirs))
            modes[i] = kp.MODE_START
        elif m0 == kp.MODE_START and g0[i, 0] > 0.0 and g[i, 0] <= 0.0:
            modes[i] = kp.MODE_SLIP
        elif (m0 == kp.MODE_SLIP and g0[i, 0] > 0.0 and g[i, 0] <= 0.0) or (
            m0 == kp.MODE_START and g0[i, 1] > 0.0 and g[i, 1] <= 0.0
        ):
            modes[i] = kp.MODE_STICK  # stick test: settle releases it if outside the disc
        if modes[i] == kp.MODE_SLIP:  # a slip needs |v| > eta for its direction v/|v|
            if math.sqrt(v[2 * i] ** 2 + v[2 * i + 1] ** 2) <= sp[kq.S_ETA]:
                modes[i] = kp.MODE_STICK
        if modes[i] != m0:
            kr._record(EV, info, t, i, m0, modes[i], dirs)
            test = test or modes[i] == kp.MODE_STICK
    if test:  # partners slowing to the band with it test together (kr.BAND_RTOL)
        for i in range(ni):
            speed = math.sqrt(v[2 * i] ** 2 + v[2 * i + 1] ** 2)
            kr.band_tie(EV, info, t, i, modes, speed, sp[kq.S_ETA], dirs)
    return ka.tcall("pairs.settle", (t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, EV, info))


@ka.compiled_only
def outputs(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, k, X, NO, FF, FR, FO, MO):
    """Row k of the output histories at the state y; returns the force kernel's status (the
    loops call it by address, row ``"pairs.outputs"``: one copy, compiled in the helper)."""
    _, lam, Ff, Fr, Fo = out
    st = _ev(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out)
    for j in range(y.shape[0]):
        X[k, j] = y[j]
    for i in range(modes.shape[0]):
        NO[k, i] = lam[i]
        MO[k, i] = modes[i]
        for c in range(2):
            FF[k, i, c] = Ff[i, c]
            FR[k, i, c] = Fr[i, c]
            FO[k, i, c] = Fo[i, c]
    return st


@njit(cache=True, error_model="numpy", inline="always")
def outputs_t(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, k, X, NO, FF, FR, FO, MO):
    """:func:`outputs` by its address."""
    a = (t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, k, X, NO, FF, FR, FO, MO)
    return ka.tcall("pairs.outputs", a)


@ka.compiled_uncounted
def begin(y0, t0, modes, dirs, op, bp, sp, gk, gp, tab, X, NO, FF, FR, FO, MO, EV, info,
          ws, out, y):  # fmt: skip
    """The start of a loop into the caller's work arrays ``ws`` (:func:`kq.workspace`),
    ``out`` (:func:`kq.outputs_at`) and state ``y`` (y0 copied): the switch law's initial modes
    and the first output row; returns the status, ST_UPLIFT when a normal force is not
    compressive. Allocates nothing."""
    for j in range(y0.shape[0]):
        y[j] = y0[j]
    info[kr.I_TFAIL] = np.nan
    info[kr.I_IFAIL] = -1
    st = kr.ST_OK
    info[kr.I_EIMP] = 0.0
    uni = int(sp[kq.S_CONTACT]) == kp.CONTACT_UNILATERAL
    a = (t0, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, EV, info)
    if int(sp[kq.S_LAW]) == kp.LAW_SWITCH:  # (by address: the Radau loop never calls it)
        st = ka.tcall("pairs.initial_modes", a)
    if st == kr.ST_OK and uni:  # a contact without compression at the start is open
        st = ka.tcall("pairs.settle_contacts", a)
    if st == kr.ST_OK:
        k0 = np.int64(0)  # typed: one compilation of outputs
        outputs_t(t0, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, k0, X, NO, FF, FR, FO, MO)
        bil = int(sp[kq.S_CONTACT]) == kp.CONTACT_BILATERAL
        kr.tension_start(info, t0, out[1], bil)
        if kr._min_normal(out[1]) <= 0.0 and not (bil or uni):
            info[kr.I_IFAIL] = np.argmin(out[1])
            info[kr.I_NOUT] = 1  # (the output at the start, its uplift state)
            st = kr.ST_UPLIFT
    if st != kr.ST_OK:
        info[kr.I_TFAIL] = t0
    return st


@ka.compiled_only
def emit(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, k, X, NO, FF, FR, FO, MO, stops):
    """Row k of the outputs at the state y and the rim contacts there."""
    outputs_t(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, k, X, NO, FF, FR, FO, MO)
    ka.tcall("pairs.track_stops", (t, y, op, bp, ws, stops))


@ka.compiled_only
def finish(status, t, nstep, nrej, nfev, iout, info):
    """The run's counters into info (and its end time when it failed); returns status."""
    if status != kr.ST_OK and not info[kr.I_TFAIL] == info[kr.I_TFAIL]:
        info[kr.I_TFAIL] = t
    info[kr.I_NSTEP] = nstep
    info[kr.I_NREJ] = nrej
    info[kr.I_NFEV] = nfev
    info[kr.I_NOUT] = iout
    return status


@ka.compiled_only
def locate_uplift(t, hh, sb, rc, ys, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, info):
    """First λ_i = 0 in (0, sb] of the step (DP5 dense output ``rc``); returns its fraction."""
    lam = out[1]
    sa = 0.0
    while (sb - sa) * hh > kr.EVENT_TTOL and sa < 0.5 * (sa + sb) < sb:
        sm = 0.5 * (sa + sb)
        dp.dense_state(rc, sm, ys)
        _ev(t + sm * hh, ys, modes, dirs, op, bp, sp, gk, gp, tab, ws, out)
        if kr._min_normal(lam) <= 0.0:
            sb = sm
        else:
            sa = sm
    dp.dense_state(rc, sb, ys)
    _ev(t + sb * hh, ys, modes, dirs, op, bp, sp, gk, gp, tab, ws, out)
    for i in range(lam.shape[0]):
        if lam[i] <= 0.0 and info[kr.I_IFAIL] < 0:
            info[kr.I_IFAIL] = i
    return sb


@ka.compiled_only
def slip_only(modes, sp):
    """True when the switching functions are the slip velocities' alone: the switch law, no
    isolator stuck and contacts only watched (no λ among them), so :func:`gslip` gives them."""
    if int(sp[kq.S_LAW]) != kp.LAW_SWITCH or int(sp[kq.S_CONTACT]) != kp.CONTACT_DETECT:
        return False
    for i in range(modes.shape[0]):
        if modes[i] == kp.MODE_STICK:
            return False
    return True


@ka.compiled_only
def gslip(rc, s, ys, modes, dirs, op, sp, ws, g):
    """:func:`gvals` at the dense output's s when :func:`slip_only`: the slip velocities
    v = D2 q̇ (the same sums as :func:`nsdyn.models.isolated._kpairs.slips`) from the dense
    velocities (ys[n:2n]) alone, no right-hand side evaluated (ws[1] left with v)."""
    D2 = op[kq.O_D2]
    n = D2.shape[1]
    v = ws[1]
    for j in range(n, 2 * n):
        ys[j] = dp.dense(rc, j, s)
    for r in range(D2.shape[0]):
        sv = 0.0
        for c in range(n):
            sv += D2[r, c] * ys[n + c]
        v[r] = sv
    eta = sp[kq.S_ETA]
    for i in range(modes.shape[0]):
        vx = v[2 * i]
        vy = v[2 * i + 1]
        g[i, 0] = g[i, 1] = g[i, 2] = 1.0
        if modes[i] == kp.MODE_SLIP:
            g[i, 0] = math.sqrt(vx * vx + vy * vy) - eta
        elif modes[i] == kp.MODE_START:
            g[i, 0] = kr.START_EXIT * eta - math.sqrt(vx * vx + vy * vy)
            g[i, 1] = vx * dirs[i, 0] + vy * dirs[i, 1]


@ka.compiled_only
def end_state(rc, ys, y1):
    """ys = the dense state at s = 1; True when it is y1 bit for bit (signs of zeros too)."""
    dp.dense_state(rc, 1.0, ys)
    for j in range(ys.shape[0]):
        if ys[j] != y1[j] or math.copysign(1.0, ys[j]) != math.copysign(1.0, y1[j]):
            return False
    return True


@ka.compiled_only
def locate_event(t, hh, rc, ys, y1, g0, g, ga, ge, modes, dirs, op, bp, sp, gk, gp, tab, ws,
                 out):  # fmt: skip
    """(found, s, evaluations): the earliest switching-function crossing in the step, from
    SAMPLES samples of the dense output and bisection to EVENT_TTOL; g at the cut (and the
    state there in ys). Samples while :func:`slip_only` cost no evaluation (:func:`gslip`);
    the one at the step's end reuses its last stage's evaluation (at y1, left in ``out``:
    its g kept in ``ge``) when the dense state there is y1 bit for bit."""
    sa = 0.0
    nfev = 0
    fast = slip_only(modes, sp)
    if not fast:
        gfill(y1, modes, dirs, op, bp, sp, ws, out, ge)
    for m in range(1, kr.SAMPLES + 1):
        sb = m / kr.SAMPLES
        if fast:
            gslip(rc, sb, ys, modes, dirs, op, sp, ws, g)
        elif m == kr.SAMPLES and end_state(rc, ys, y1):
            for i in range(g.shape[0]):
                for c in range(3):
                    g[i, c] = ge[i, c]
        else:
            dp.dense_state(rc, sb, ys)
            gvals(t + sb * hh, ys, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, g)
            nfev += 1
        if kr._crossed(g0, g):
            while (sb - sa) * hh > kr.EVENT_TTOL and sa < 0.5 * (sa + sb) < sb:
                sm = 0.5 * (sa + sb)
                if fast:
                    gslip(rc, sm, ys, modes, dirs, op, sp, ws, ga)
                else:
                    dp.dense_state(rc, sm, ys)
                    gvals(t + sm * hh, ys, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, ga)
                    nfev += 1
                if kr._crossed(g0, ga):
                    sb = sm
                else:
                    sa = sm
            dp.dense_state(rc, sb, ys)
            if fast:
                gslip(rc, sb, ys, modes, dirs, op, sp, ws, g)
            else:
                gvals(t + sb * hh, ys, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, g)
            return True, sb, nfev
        sa = sb
    if fast:
        dp.dense_state(rc, 1.0, ys)
    return False, 1.0, nfev


# by address (declared by nsdyn.models.isolated.pairs_compile: each compiles once, on its own):
# linked, every caller held a copy, optimised by LLVM again (the mode switch alone was 45 % of
# the event loop's code)
_BY_ADDRESS = {"outputs": outputs, "begin": begin, "emit": emit, "switch": switch,
               "locate_event": locate_event, "locate_uplift": locate_uplift}  # fmt: skip
for _row, _kernel in _BY_ADDRESS.items():
    ka.tslot(f"pairs.{_row}", _kernel, "nsdyn.models.isolated.pairs_compile:callees")


@njit(cache=True, error_model="numpy", nogil=True)  # (a watching thread: info[I_NOUT])
def integrate(y0, t_eval, modes, dirs, op, bp, sp, gk, gp, tab, cfg,
              X, NO, FF, FR, FO, MO, EV, stops, info, wk):  # fmt: skip
    """Integrate from y0 at t_eval[0] to t_eval[-1]; outputs at t_eval; returns a status
    (codes of :mod:`nsdyn.models.isolated._kplanerun`); ``wk``: ``pairs_compile.loop_arrays``."""
    n2 = y0.shape[0]
    ni = modes.shape[0]
    t = t_eval[0]
    ws, out, y = wk[0], wk[1], wk[2]
    bq = (y0, t, modes, dirs, op, bp, sp, gk, gp, tab, X, NO, FF, FR, FO, MO, EV, info, ws, out, y)
    st = ka.tcall("pairs.begin", bq)
    if st != kr.ST_OK:
        return st
    n = n2 // 2
    lam = out[1]
    k, y1, ys, rc, g0, g, ga, ge = wk[3], wk[4], wk[5], wk[6], wk[7], wk[8], wk[9], wk[10]
    bil = int(sp[kq.S_CONTACT]) == kp.CONTACT_BILATERAL
    tens = bil and kr._min_normal(lam) <= 0.0
    uni = int(sp[kq.S_CONTACT]) == kp.CONTACT_UNILATERAL
    switching = int(sp[kq.S_LAW]) == kp.LAW_SWITCH or uni  # (events located)
    rtol = cfg[kr.C_RTOL]
    hmax = cfg[kr.C_HMAX]
    max_steps = int(cfg[kr.C_MAXSTEPS])
    nt = t_eval.shape[0]
    t_end = t_eval[nt - 1]
    ntab = tab.shape[1]
    iout = np.int64(1)
    fresh = True
    h = min(cfg[kr.C_H0], hmax)
    nstep = np.int64(0)
    nrej = np.int64(0)
    nfev = np.int64(0)
    burst_t = -math.inf
    burst_n = 0
    status = kr.ST_OK
    while t < t_end and iout < nt:
        if fresh:
            if kq.rhs_t(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, k[0]) != kq.ST_OK:
                status = kr.ST_SINGULAR
                break
            nfev += 1
            if switching:
                gvals(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, g0)
            fresh = False
        hh = min(h, hmax, t_end - t)
        tb = kp.next_breakpoint(t, gk, gp, ntab)
        if t + hh > tb:
            hh = tb - t
        bad = False
        for j in range(1, 7):
            dp.stage(y, k, hh, j, y1)
            if kq.rhs_t(t + dp.C[j] * hh, y1, modes, dirs, op, bp, sp, gk, gp, tab, ws, out,
                      k[j]) != kq.ST_OK:  # fmt: skip
                bad = True
        nfev += 6
        err = 0.0
        for i in range(n2):
            a_i = cfg[kr.C_ATOLQ] if i < n else cfg[kr.C_ATOLV]
            sc = a_i + rtol * max(abs(y[i]), abs(y1[i]))
            err += (dp.error(k, hh, i) / sc) ** 2
        err = math.sqrt(err / n2)
        if bad or not math.isfinite(err) or err > 1.0:
            nrej += 1
            h = dp.new_step(hh, err) if math.isfinite(err) else 0.25 * hh
            if h <= kr.H_MIN * max(1.0, abs(t)):
                status = kr.ST_UNDERFLOW if (math.isfinite(err) and not bad) else kr.ST_NONFINITE
                break
            continue
        nstep += 1
        if nstep + nrej > max_steps:
            status = kr.ST_MAX_STEPS
            break
        n_end_min = kr._min_normal(lam)  # the last stage is the step's end
        dp.dense_coefficients(y, y1, k, hh, rc)
        s_end = 1.0
        event = False
        if switching:
            event, s_end, ne = ka.tcall("pairs.locate_event", (t, hh, rc, ys, y1, g0, g, ga, ge,
                                        modes, dirs, op, bp, sp, gk, gp, tab, ws, out))  # fmt: skip
            nfev += ne
        n_cut = n_end_min
        if not uni and (event or n_end_min <= 0.0):  # normal force at the cut (or step end)
            dp.dense_state(rc, s_end, ys)
            _ev(t + s_end * hh, ys, modes, dirs, op, bp, sp, gk, gp, tab, ws, out)
            n_cut = kr._min_normal(lam)
            if n_cut <= 0.0 and not tens:
                sb = ka.tcall("pairs.locate_uplift", (t, hh, s_end, rc, ys, modes, dirs, op, bp,
                                                      sp, gk, gp, tab, ws, out, info))  # fmt: skip
                if bil:  # the contact holds: recorded, the step kept
                    kr.tension_onset(info, t + sb * hh)
                else:
                    s_end = sb
                    event = False
                    status = kr.ST_UPLIFT
        if bil:
            tens = n_cut <= 0.0
            info[kr.I_NMIN] = min(info[kr.I_NMIN], n_cut)
        t_new = t + s_end * hh if s_end < 1.0 else t + hh
        while iout < nt and t_eval[iout] <= t_new:
            dp.dense_state(rc, (t_eval[iout] - t) / hh, ys)
            ka.tcall("pairs.emit", (t_eval[iout], ys, modes, dirs, op, bp, sp, gk, gp, tab, ws,
                                    out, iout, X, NO, FF, FR, FO, MO, stops))  # fmt: skip
            iout += 1
            info[kr.I_NOUT] = iout  # (the progress line's)
        if s_end < 1.0:
            dp.dense_state(rc, s_end, ys)
            for j in range(n2):
                y[j] = ys[j]
        else:
            for j in range(n2):
                y[j] = y1[j]
        t = t_new
        ka.tcall("pairs.track_stops", (t, y, op, bp, ws, stops))
        if status == kr.ST_UPLIFT:
            info[kr.I_TFAIL] = t
            if iout < nt and t > t_eval[max(iout - 1, 0)]:  # the located instant: last row
                ka.tcall("pairs.emit", (t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, iout,
                                        X, NO, FF, FR, FO, MO, stops))  # fmt: skip
                iout += 1
            break
        if event:
            if t - burst_t < kr.BURST_DT:
                burst_n += 1
                if burst_n > kr.MAX_BURST:
                    status = kr.ST_CHATTER
                    info[kr.I_TFAIL] = t
                    break
            else:
                burst_t = t
                burst_n = 0
            sw = (t, y, g0, g, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, EV, info)
            st = ka.tcall("pairs.switch", sw)
            if st != kr.ST_OK:
                status = st
                info[kr.I_TFAIL] = t
                break
            fresh = True
            h = hh
        else:
            for j in range(n2):
                k[0, j] = k[6, j]
            if switching:
                for i in range(ni):
                    for c in range(3):
                        g0[i, c] = g[i, c]
            h = min(dp.new_step(hh, err), hmax)
    return finish(status, t, nstep, nrej, nfev, iout, info)
