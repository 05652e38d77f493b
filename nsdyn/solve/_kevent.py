"""Events of the switch model: modes held fixed between switching instants.

This module holds the friction events (switching functions, their location, the mode
settling); the loop that drives the Radau stepper through them is
:func:`nsdyn.solve._kunilateral._run` (entry points ``event_switch`` with bilateral contacts and
``event_unilateral``), so stick/slip and lift-off/landing events share one step loop.

Between events every isolator ``i`` is in a fixed mode (``P[I_MODE][i]``, law LAW_MODES):
slip +1/-1 (friction mu_i lamf_i opposing that direction) or stick 0 (D_i qdd + kappa D_i qd
= 0, friction tau_i a constraint force). The vector field is then smooth (linear in x), and
the switching functions are

    slip  s:  g_i = s v_i                        slip -> stick/reversal when it crosses 0
    stick  :  g_i = mu_i lamf_i (1 + STICK_RTOL) - |tau_i|   stick -> slip (sign tau_i)

At a slip isolator's zero crossing the stick is accepted if the stick force evaluated with
mode 0 obeys |tau_i| <= mu_i lamf_i (1 + STICK_RTOL) (the stick function's bound, so a stick it
accepts starts at g >= 0), else the slip continues with the reversed direction
(sign of that force). Each isolator has its own state; isolators reaching their switching
surface within EVENT_TTOL of each other switch together.

Stepper: Radau IIA (:mod:`nsdyn.solve._kradau`) because the isolated frames are stiff (undamped kHz
Craig-Bampton boundary modes). Roots are bracketed by scanning g at a few points of the dense
output of each step (a stuck structure has no local error, so its steps grow while the stick
forces follow the excitation; the front door also caps the step by the excitation), located
by the Illinois method on the dense output (cubic in the step; for the stick function each
iterate evaluates the constraint forces), and the step is redone to land exactly on the root.
A new slip opposes the sliding velocity when it is resolved (|v| > V_SLIP_ATOL atol), else it
follows the stick force; a slipping isolator held at v ~ 0 by a stuck one on the same rigid
base (a ~ 0) is not a stick candidate, and sign changes at round-off level are ignored.
For slip -> stick the landing is polished by Newton corrections dt = -g/g' (g' = s a_i,
exact) with redone steps until |dt| <= EVENT_TTOL, so the isolator sticks with a residual
velocity at the integrator's accuracy. After each event the stepper restarts (fresh Jacobian,
no step history). A sign change and its reversal within one step are not seen: limit
``max_step`` if the excitation can do that.
"""

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn.models.isolated import _kernel as ks
from nsdyn.solve import _kcommon as ki
from nsdyn.solve import _kradau as kr

EVENT_TTOL = 1e-12  # s, time tolerance of the event location (and simultaneity window)
ROOT_MAXITER = 200  # Illinois iterations
SLIP_SAMPLES = 8  # dense-output samples per step scanned for a slip sign change (cheap)
STICK_SAMPLES = 4  # samples per step for a stick sign change (one force evaluation each)
POLISH_MAX = 4  # Newton corrections of a slip -> stick landing
STICK_RTOL = 1e-12  # relative slack of the stick test |tau| <= mu lamf
SETTLE_PASSES = 16  # passes to reach a consistent mode set at an event
BURST_DT = 1e-9  # s, events closer than this count as one burst
MAX_BURST = 50  # events in one burst before reporting chattering (ST_EVENTS)
MODE_AUTO = 2  # initial mode: decide from the initial state
V_AUTO = 1e-12  # m/s, |v| at or below which the initial mode is decided by the stick test
V_NOISE = 1e-12  # m/s, sliding speeds this small are round-off (an isolator locked by another)
A_NOISE = 1e-9  # m/s^2, sliding accelerations this small are round-off
V_SLIP_ATOL = 10.0  # |v| > this x atol (velocities) counts as motion when choosing a direction
# switching functions: a slipping isolator's velocity, a stuck one's force margin. Passed as
# np.int64(...) where the callee is cold: numba types a constant argument as a literal and
# compiles the callee (and what it calls with it) once per value
SLIP, STICK = 0, 1


@ka.compiled_uncounted
def _lamf(i, lam, P):
    if P[ks.I_IPAR][ks.K_FROZEN] == 1:
        return P[ks.I_LAM0][i]
    if i < lam.shape[0]:
        return lam[i]
    return 0.0


@njit(cache=True, error_model="numpy")
def _dot_row(D, i, y, off):
    s = 0.0
    for j in range(D.shape[1]):
        s += D[i, j] * y[off + j]
    return s


@ka.compiled_uncounted
def _g_stick(i, lam, tau, P):  # (the settling's bound: a stick it accepts starts at g >= 0)
    return P[ks.I_MU][i] * _lamf(i, lam, P) * (1.0 + STICK_RTOL) - abs(tau[i])


@ka.compiled_uncounted
def _v_dense(i, sgn, x, y, Qd, D):
    """Slip switching function of isolator i on the dense output at t + x h: its sliding
    velocity, signed by ``sgn``."""
    n = D.shape[1]
    v = 0.0
    for j in range(n):
        k = n + j
        v += D[i, j] * (y[k] + x * (Qd[k, 0] + x * (Qd[k, 1] + x * Qd[k, 2])))
    return sgn * v


@ka.compiled_uncounted
def _g_dense(kind, i, sgn, x, y, Qd, t, h, P, ew):
    """Switching function of isolator i on the dense output at t + x h.

    ``ew = (ys, fs, qdd, lam, tau, modes, g0, m_old, o_old)``: scratch state and right-hand
    side, then the outputs of the system kernel (lam, tau are left at t + x h for the stick
    function), then scratch of the detector, the settling and the event handler (ni floats, ni
    and nc integers: the kernels of the loop allocate nothing, :data:`nsdyn._kaddress.NO_NRT`).
    """
    ys, fs, qdd, lam, tau, modes = ew[:6]
    if kind == SLIP:
        return _v_dense(i, sgn, x, y, Qd, P[ks.I_D])
    kr.dense(y, Qd, x, ys)
    ki.feval_t(t + x * h, ys, P, fs, qdd, lam, tau, modes)
    return _g_stick(i, lam, tau, P)


@njit(cache=True, error_model="numpy")
def illinois_point(a, b, fa, fb):
    """Next Illinois iterate in [a, b]: the secant root, the midpoint if it falls outside."""
    c = (a * fb - b * fa) / (fb - fa)
    if not (a < c < b):
        c = 0.5 * (a + b)
    return c


@njit(cache=True, error_model="numpy")
def illinois_step(a, b, fa, fb, c, fc, side):
    """Shrink the bracket (fa > 0 > fb) with g(c) = fc, halving the kept end's value when the
    same end moves twice in a row. Returns (a, b, fa, fb, side, done); done: fc == 0."""
    if fc > 0.0:
        a, fa = c, fc
        if side == 1:
            fb *= 0.5
        side = 1
    elif fc < 0.0:
        b, fb = c, fc
        if side == -1:
            fa *= 0.5
        side = -1
    else:
        return a, b, fa, fb, side, True
    return a, b, fa, fb, side, False


@ka.compiled_uncounted
def _root(kind, i, sgn, a, b, fa, fb, y, Qd, t, h, P, ew, stats):
    """Illinois on x in [a, b] for g(a) = fa >= 0 > fb = g(b). Returns x with g(x) <= 0."""
    xtol = EVENT_TTOL / h
    side = np.int64(0)
    for _ in range(ROOT_MAXITER):
        if b - a <= xtol:
            break
        c = illinois_point(a, b, fa, fb)
        fc = _g_dense(kind, i, sgn, c, y, Qd, t, h, P, ew)
        if kind == STICK:
            stats[ki.S_NFEV] += 1
        a, b, fa, fb, side, done = illinois_step(a, b, fa, fb, c, fc, side)
        if done:
            return c
    return b


@ka.compiled_uncounted
def _detect(t, h, y, ynew, Qd, P, ew, stats, v_tol):
    """Earliest switching instant in the step [t, t + h]: returns (x, isolator, kind), x = 2
    when none. The switching functions are scanned at SLIP_SAMPLES / STICK_SAMPLES points of
    the dense output (a stuck, locked structure has no local error, so its steps grow large
    while the stick forces follow the excitation) and the first bracket is refined by
    Illinois. Leaves lam, tau at the step end. A slip that starts against its velocity (a
    start from stick, g <= 0) crosses once g falls between two samples by more than the
    velocities' resolution v_tol / V_SLIP_ATOL (an isolator held by a stuck one on a stiff
    base follows its micro-vibration, whose sign changes are the integrator's noise), or
    once its velocity against its direction is resolved motion (g < −v_tol)."""
    ys, fs, qdd, lam, tau, modes = ew[:6]
    D = P[ks.I_D]
    n = D.shape[1]
    pm = P[ks.I_MODE]
    x_best = 2.0
    i_best = -1
    k_best = 0
    any_stick = False
    v_noise = max(V_NOISE, v_tol / V_SLIP_ATOL)
    for i in range(D.shape[0]):
        if ks.contact_open(P, i):
            continue  # in flight (unilateral runs): no friction, no friction event
        if pm[i] == 0:
            any_stick = True
            continue
        sg = float(pm[i])
        xa = 0.0
        ga = sg * _dot_row(D, i, y, n)
        for k in range(1, SLIP_SAMPLES + 1):
            xb = k / SLIP_SAMPLES
            if xb >= x_best:
                break
            if k == SLIP_SAMPLES:
                gb = sg * _dot_row(D, i, ynew, n)
            else:  # the velocity alone (8 samples per slipping isolator and step)
                gb = _v_dense(i, sg, xb, y, Qd, D)
            # a genuine crossing, not round-off around v = 0 (a slipping isolator held at
            # v = 0 by a stuck one on the same rigid base), nor a slip started from stick
            # against its residual velocity (|v| <= v_tol: g < 0 at its start) that speeds
            # up along its direction (g rising through the sample)
            if gb < 0.0 and (ga > V_NOISE or gb < min(ga, 0.0) - v_noise or gb < -v_tol):
                xr = _root(
                    np.int64(SLIP), i, sg, xa, xb, max(ga, 0.0), gb, y, Qd, t, h, P, ew, stats
                )
                if xr < x_best:
                    x_best, i_best, k_best = xr, i, 0
                break
            xa, ga = xb, gb
    if any_stick:
        # g at the step start, then at the samples (one evaluation each, shared by isolators)
        ni = D.shape[0]
        g0 = ew[6]
        ki.feval_t(t, y, P, fs, qdd, lam, tau, modes)
        stats[ki.S_NFEV] += 1
        for i in range(ni):
            g0[i] = _g_stick(i, lam, tau, P)
        xa = 0.0
        for k in range(1, STICK_SAMPLES + 1):
            xb = k / STICK_SAMPLES
            if xb >= x_best:
                break
            kr.dense(y, Qd, xb, ys)
            ki.feval_t(t + xb * h, ys, P, fs, qdd, lam, tau, modes)
            stats[ki.S_NFEV] += 1
            found = False
            for i in range(ni):
                if pm[i] != 0 or ks.contact_open(P, i):
                    continue
                gb = _g_stick(i, lam, tau, P)
                if gb < 0.0:
                    xr = _root(
                        np.int64(STICK),
                        i,
                        0.0,
                        xa,
                        xb,
                        max(g0[i], 0.0),
                        gb,
                        y,
                        Qd,
                        t,
                        h,
                        P,
                        ew,
                        stats,
                    )
                    if xr < x_best:
                        x_best, i_best, k_best = xr, i, 1
                    found = True
                    kr.dense(y, Qd, xb, ys)
                    ki.feval_t(t + xb * h, ys, P, fs, qdd, lam, tau, modes)
                    stats[ki.S_NFEV] += 1
                g0[i] = gb
            if found:
                break
            xa = xb
        # restore the step-end forces for the contact monitor
        ki.feval_t(t + h, ynew, P, fs, qdd, lam, tau, modes)
        stats[ki.S_NFEV] += 1
    return x_best, i_best, k_best


@ka.compiled_uncounted
def _settle(t, y, P, f, ew, trigger, v_tol, log, stats):
    """Consistent mode set at an event (t, y); records the changes in ``log = (ev_t, ev_i,
    ev_m)``. Returns ok (False: the event buffer is full).

    A slipping isolator reaching v = 0 (the trigger, or any other decelerating to v = 0
    within EVENT_TTOL; not one held at v ~ 0 by a stuck isolator on the same rigid base,
    whose acceleration is ~ 0) is tried in stick; a stuck isolator whose stick force leaves
    the friction cone slips. A new slip direction opposes the velocity when |v| > v_tol
    (Coulomb), else it follows the stick force it replaces.
    """
    qdd, lam, tau, modes = ew[2:6]
    ev_t, ev_i, ev_m = log
    pm = P[ks.I_MODE]
    D = P[ks.I_D]
    mu = P[ks.I_MU]
    n = D.shape[1]
    ni = D.shape[0]
    old = ew[7]
    for i in range(ni):
        old[i] = pm[i]
    ki.feval_t(t, y, P, f, qdd, lam, tau, modes)
    stats[ki.S_NFEV] += 1
    for i in range(ni):
        v = _dot_row(D, i, y, n)
        if ks.contact_open(P, i):
            continue  # in flight: its mode waits for the landing
        if pm[i] == MODE_AUTO:
            pm[i] = 0
        elif pm[i] != 0:
            s = float(pm[i])
            ga = s * _dot_row(D, i, qdd, np.int64(0))
            if i == trigger or (-ga > A_NOISE and s * v <= EVENT_TTOL * -ga):
                if abs(v) > v_tol:
                    pm[i] = 1 if v > 0.0 else -1
                else:
                    pm[i] = 0
        elif i == trigger or _g_stick(i, lam, tau, P) < 0.0:
            if abs(v) > v_tol:
                pm[i] = 1 if v > 0.0 else -1
            else:
                pm[i] = 1 if tau[i] >= 0.0 else -1
    for _ in range(SETTLE_PASSES):
        ki.feval_t(t, y, P, f, qdd, lam, tau, modes)
        stats[ki.S_NFEV] += 1
        changed = False
        for i in range(ni):
            if ks.contact_open(P, i):
                continue
            if pm[i] == 0 and abs(tau[i]) > mu[i] * _lamf(i, lam, P) * (1.0 + STICK_RTOL):
                v = _dot_row(D, i, y, n)
                if abs(v) > v_tol:
                    pm[i] = 1 if v > 0.0 else -1
                else:
                    pm[i] = 1 if tau[i] >= 0.0 else -1
                changed = True
        if not changed:
            break
    for i in range(ni):
        if pm[i] != old[i]:
            k = stats[ki.S_NEVENT]
            if k >= ev_t.shape[0]:
                return False
            ev_t[k] = t
            ev_i[k] = i
            ev_m[k] = pm[i]
            stats[ki.S_NEVENT] += 1
    return True


@ka.compiled_uncounted
def _initial_modes(P, y, modes0):
    pm = P[ks.I_MODE]
    D = P[ks.I_D]
    n = D.shape[1]
    for i in range(D.shape[0]):
        m = modes0[i]
        if m == MODE_AUTO:
            v = _dot_row(D, i, y, n)
            if abs(v) > V_AUTO:
                m = 1 if v > 0.0 else -1
        pm[i] = m
