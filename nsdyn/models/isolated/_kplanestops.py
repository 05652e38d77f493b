"""Rim contacts of the deck's time loops: first contact, peak overshoot, samples in contact.

Isolator i presses its rim where its resultant slip exceeds the displacement capacity,
δ_i = |u_i| − d_cap,i > 0 (u_i = B_i q, :func:`nsdyn.models.isolated._kplane.slip_kinematics`).
The loops (:mod:`._kplanerun`, :mod:`._kplaneradau`) record in a stop table (one row per
isolator; columns P_TFIRST, P_PEAK, P_NSTEPS) the first time δ_i > 0 (located on the
Dormand–Prince dense output to EVENT_TTOL, so a contact shorter than a step is seen), the
largest δ_i and the number of samples in contact.
"""

import math

from nsdyn import _kaddress as ka
from nsdyn import _kdp5 as dp
from nsdyn.models.isolated._kplane import MODE_FREE, MODE_SLIP, MODE_STICK, slip_kinematics
from nsdyn.models.isolated.bearings import B_DCAP

P_TFIRST, P_PEAK, P_NSTEPS = range(3)  # stop table columns (one row per isolator)
# s, width of a located event bracket (every event of the loops); a bisection also ends where
# the bracket's midpoint rounds onto an end (a step of 1e6 s never narrowed below 2e-10 s)
EVENT_TTOL = 1e-11
SAMPLES = 4  # dense-output samples per step scanned for a sign change


@ka.compiled_only
def track_stops(t, y, pos, bp, stops):
    for i in range(pos.shape[0]):
        ux, uy, _, _ = slip_kinematics(y, pos, i)
        d = math.sqrt(ux * ux + uy * uy) - bp[i, B_DCAP]
        if d > 0.0:
            if not stops[i, P_TFIRST] == stops[i, P_TFIRST]:  # nan: first contact
                stops[i, P_TFIRST] = t
            stops[i, P_PEAK] = max(stops[i, P_PEAK], d)
            stops[i, P_NSTEPS] += 1


@ka.compiled_only
def overshoot(ys, pos, bp, i):
    """|u_i| − d_cap,i at the state ys (> 0: isolator i presses its rim)."""
    ux, uy, _, _ = slip_kinematics(ys, pos, i)
    return math.sqrt(ux * ux + uy * uy) - bp[i, B_DCAP]


@ka.compiled_only
def locate_stops(t, hh, s_end, rc, ys, pos, bp, stops):
    """First rim contact of each isolator inside a step, located on its dense output: the
    overshoot |u| − d_cap sampled at SAMPLES points up to ``s_end``, the first positive one
    bisected to EVENT_TTOL (a contact shorter than the step, missed at its ends, is found)."""
    for i in range(pos.shape[0]):
        if stops[i, P_TFIRST] == stops[i, P_TFIRST]:  # in contact before: step ends suffice
            continue
        sa = 0.0
        for m in range(1, SAMPLES + 1):
            sb = s_end * m / SAMPLES
            dp.dense_state(rc, sb, ys)
            d = overshoot(ys, pos, bp, i)
            if d > 0.0:
                stops[i, P_PEAK] = max(stops[i, P_PEAK], d)
                while (sb - sa) * hh > EVENT_TTOL and sa < 0.5 * (sa + sb) < sb:
                    sm = 0.5 * (sa + sb)
                    dp.dense_state(rc, sm, ys)
                    if overshoot(ys, pos, bp, i) > 0.0:
                        sb = sm
                    else:
                        sa = sm
                stops[i, P_TFIRST] = t + sb * hh
                break
            sa = sb


@ka.compiled_uncounted
def crossed(g0, g):
    """Whether a switching function of ``g0`` (> 0) reached <= 0 in ``g`` (both (ni, k))."""
    for i in range(g.shape[0]):
        for k in range(g.shape[1]):
            if g0[i, k] > 0.0 and g[i, k] <= 0.0:
                return True
    return False


@ka.compiled_only
def tension_mode(mode, N, speed, eta):
    """An isolator's mode under a bilateral contact's switch law once its normal force is N:
    free exactly while N < 0 (no friction in tension), back to slip (|v| > η) or a stick test
    when N > 0; ``mode`` kept where it agrees (and at N = 0). An event that changes other
    isolators' modes moves every N at once, past the crossing of its switching function."""
    if mode == MODE_FREE and N > 0.0:
        return MODE_SLIP if speed > eta else MODE_STICK
    if mode != MODE_FREE and N < 0.0:
        return MODE_FREE
    return mode
