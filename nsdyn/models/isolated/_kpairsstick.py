"""Stick of systems from matrices on planar isolators: the settling of the stuck isolators.

After each event of the switch law (:mod:`._kpairsrun`) and at the start, the stuck isolators
are settled: while one holds a stick force beyond its disc |τ_i| <= μ_s k_p λ_i (1 +
STICK_RTOL), the one with the largest |τ_i| / μ_s k_p λ_i starts to slip in the direction of
its stick force, with any as loaded as it to TIE_RTOL (symmetric partners break away together);
then several slip-starts are aligned with the accelerations of their slip points and the discs
are checked again, until neither changes. While the stuck isolators hold the base (their slip
rows redundant: two or more under one rigid base) the starts' slip points do not move and
keep the directions of their stick forces. The switching function of stick carries the same
bound (:func:`._kpairsrun.gfill`), so every isolator settle leaves stuck starts above zero and
its next break-away is seen.
"""

import math

import numpy as np

from nsdyn import _kaddress as ka
from nsdyn.models.isolated import _kpairs as kq
from nsdyn.models.isolated import _kplane as kp
from nsdyn.models.isolated import _kplanerun as kr
from nsdyn.models.isolated._kplanestops import tension_mode
from nsdyn.models.isolated.bearings import B_MUS

ALIGN_RELAX = 4  # relaxation weights tried in turn: 1, 1/2, 1/4, 1/8


@ka.compiled_only
def _ev(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out):
    return kq.evaluate_t(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out)


@ka.compiled_only
def settle(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, EV, info):
    """Release stuck isolators outside their disc, the worst first with its ties (released
    alone, it moved its load onto its partners), then align the slip-start directions with
    the accelerations of their slip points and check the discs again (the aligned starts
    move load onto the isolators still stuck); returns a status."""
    lam, Ff = out[1], out[2]
    ni = modes.shape[0]
    aligned = False
    for _ in range(kr.SETTLE_PASSES + 2 * ni):
        if _ev(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out) != kq.ST_OK:
            return kr.ST_SINGULAR
        worst = np.int64(-1)
        ratio = 0.0
        for i in range(ni):  # (outside: the stick switching function's g <= 0, gfill's bound)
            if modes[i] == kp.MODE_STICK:
                tau = math.sqrt(Ff[i, 0] ** 2 + Ff[i, 1] ** 2)
                lim = bp[i, B_MUS] * ws[13][i] * lam[i]
                rat = tau / lim if lim > 0.0 else math.inf
                if lim * (1.0 + kr.STICK_RTOL) - tau <= 0.0 and tau > 0.0 and rat > ratio:
                    ratio = rat
                    worst = i
        if (
            worst < 0
            and int(sp[kq.S_CONTACT]) == kp.CONTACT_BILATERAL
            and _tension_flips(t, y, modes, dirs, op, sp, ws, out, EV, info)
        ):
            aligned = False  # (settled again with the new modes)
            continue
        if worst < 0:
            if aligned:
                return kr.ST_OK
            st, moved = align_starts(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out)
            if st != kr.ST_OK or not moved:
                return st
            for k in range(min(int(info[kr.I_NEV]), EV.shape[0]) - 1, -1, -1):  # this event's
                if EV[k, 0] != t:  # starts keep their aligned directions (as the deck's)
                    break
                if EV[k, 2] == kp.MODE_STICK and EV[k, 3] == kp.MODE_START:
                    EV[k, 4], EV[k, 5] = dirs[int(EV[k, 1]), 0], dirs[int(EV[k, 1]), 1]
            aligned = True
            continue
        aligned = False
        for i in range(ni):  # (directions and ties from this evaluation)
            if modes[i] != kp.MODE_STICK:
                continue
            tau = math.sqrt(Ff[i, 0] ** 2 + Ff[i, 1] ** 2)
            lim = bp[i, B_MUS] * ws[13][i] * lam[i]
            if i == worst or (lim > 0.0 and tau >= ratio * (1.0 - kr.TIE_RTOL) * lim):
                mu_n = kp.mu_kinetic(bp, i, 0.0) * ws[13][i] * lam[i]
                ka.tcall("pairs.start_direction", (i, Ff[i, 0], Ff[i, 1], mu_n, ws, dirs))
                kr._record(EV, info, t, i, kp.MODE_STICK, kp.MODE_START, dirs)
                modes[i] = kp.MODE_START
    return kr.ST_CHATTER


@ka.compiled_only
def _tension_flips(t, y, modes, dirs, op, sp, ws, out, EV, info):
    """Each isolator's mode made to agree with the sign of its normal force as it now is
    (:func:`._kplanestops.tension_mode`: free exactly in tension), as the deck's settling
    does; whether any changed."""
    v = ws[1]
    kq.slips(y, op[kq.O_D2], out[0].shape[0], ws[0], v)
    flips = False
    for i in range(modes.shape[0]):
        speed = math.sqrt(v[2 * i] ** 2 + v[2 * i + 1] ** 2)
        new = tension_mode(modes[i], out[1][i], speed, sp[kq.S_ETA])
        if new != modes[i]:
            kr._record(EV, info, t, i, modes[i], new, dirs)
            modes[i] = new
            flips = True
    return flips


@ka.compiled_only
def align_starts(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out):
    """Each slip-start direction d_i along the acceleration D_i q̈ its slip point gets with
    every friction in place; returns (status, whether any direction moved). Relaxed passes
    d ← (1 − w) d + w a/|a| (normalised) from the start directions, w = 1, 1/2, 1/4, 1/8 in
    turn until one converges: the plain passes (w = 1) diverge at a break-away, their gain
    μΣN/(|F| − μΣN) 1.3 on a translating base with μ_s = 0.07, μ = 0.04 (more for its
    turning), and left four equal isolators of a centred deck slipping in four directions;
    none converging, the start directions are kept. Not while the stuck isolators hold the
    base: their slip rows redundant (a rigid base on two or more, :func:`kq.stick_basis`'s
    rank below 2 n_stuck), the starts' slip points do not move and D_i q̈ is round-off
    (aligned with it, the starts loaded the stuck isolators beyond their discs). The test is
    global (one base: every isolator under it); starts on another body that stuck isolators
    elsewhere leave free are then not aligned either."""
    qdd = out[0]
    D2 = op[kq.O_D2]
    ni = modes.shape[0]
    n = qdd.shape[0]
    nst = np.sum(modes == kp.MODE_STICK)
    if np.sum(modes == kp.MODE_START) < 2:
        return kr.ST_OK, False
    d0 = ws[25]
    for i in range(ni):
        d0[i, 0] = dirs[i, 0]
        d0[i, 1] = dirs[i, 1]
    w = 1.0
    for _ in range(ALIGN_RELAX):
        for i in range(ni):
            dirs[i, 0] = d0[i, 0]
            dirs[i, 1] = d0[i, 1]
        for _ in range(kr.ALIGN_PASSES):
            if _ev(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out) != kq.ST_OK:
                return kr.ST_SINGULAR, True
            if nst > 0 and ws[16][0] < 2 * nst:  # (the rank of this evaluation's stuck rows)
                return kr.ST_OK, False
            change = 0.0
            for i in range(ni):
                if modes[i] == kp.MODE_START:
                    ax = 0.0
                    ay = 0.0
                    for b in range(n):
                        ax += D2[2 * i, b] * qdd[b]
                        ay += D2[2 * i + 1, b] * qdd[b]
                    an = math.sqrt(ax * ax + ay * ay)
                    if an > 0.0 and ax * dirs[i, 0] + ay * dirs[i, 1] > 0.0:
                        change = max(change, abs(ax / an - dirs[i, 0]) + abs(ay / an - dirs[i, 1]))
                        nx = (1.0 - w) * dirs[i, 0] + w * ax / an
                        ny = (1.0 - w) * dirs[i, 1] + w * ay / an
                        nn = math.sqrt(nx * nx + ny * ny)
                        dirs[i, 0] = nx / nn
                        dirs[i, 1] = ny / nn
            if change <= kr.ALIGN_TOL:
                moved = False
                for i in range(ni):
                    moved = moved or dirs[i, 0] != d0[i, 0] or dirs[i, 1] != d0[i, 1]
                return kr.ST_OK, moved
        w *= 0.5
    for i in range(ni):  # none converged: the start directions
        dirs[i, 0] = d0[i, 0]
        dirs[i, 1] = d0[i, 1]
    return kr.ST_OK, False


@ka.compiled_only
def initial_modes(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, EV, info):
    """Modes at the start: slip where |v| > η, else stick, then settled."""
    v = ws[1]
    kq.slips(y, op[kq.O_D2], out[0].shape[0], ws[0], v)
    for i in range(modes.shape[0]):
        sp_i = math.sqrt(v[2 * i] ** 2 + v[2 * i + 1] ** 2)
        if ws[20][i] == 0.0:  # (an open contact stays free)
            modes[i] = kp.MODE_SLIP if sp_i > sp[kq.S_ETA] else kp.MODE_STICK
    st = ka.tcall("pairs.settle", (t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, EV, info))
    if st != kr.ST_OK or int(sp[kq.S_CONTACT]) != kp.CONTACT_BILATERAL:
        return st
    if _ev(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out) != kq.ST_OK:
        return kr.ST_SINGULAR
    free = False
    for i in range(modes.shape[0]):  # tensile from the start: free
        if out[1][i] <= 0.0:
            modes[i] = kp.MODE_FREE
            free = True
    if not free:
        return st
    return ka.tcall("pairs.settle", (t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, EV, info))


# by address (declared by nsdyn.models.isolated.pairs_compile: each compiles once, on its own)
ka.tslot("pairs.settle", settle, "nsdyn.models.isolated.pairs_compile:callees")
ka.tslot("pairs.initial_modes", initial_modes, "nsdyn.models.isolated.pairs_compile:callees")
