"""Unilateral contacts of systems from matrices on planar isolators: lift-off, flight, landing.

Contact i (row R_i of R; the rows independent, so R̃ = R and λ = ξ) is closed, λ_i ≥ 0 the
multiplier of R_i q̈ = −2αβ R_i q̇ − α² R_i q, or open (ws[20][i] = 1): its row leaves the
constraint set (λ_i = 0) and its bearing's terms in λ_i with it (no friction, no pendulum
force, no stick; mode MODE_FREE), its gap R_i q integrated with the rest of the state. The
loop's switching functions (column 2 of g):

    closed   g = λ_i                 → lift-off where the normal force reaches zero
    open     g = R_i q − g0_i        → landing where the gap closes

with g0_i = R_i q at the lift-off less GAP_ARM: the scan sees the gap start positive, and a
gap left slightly below zero by the Baumgarte stabilisation is not read as a landing.

Landing is Newton's impact law with restitution 0 through the generalised mass matrix,

    q̇⁺ = q̇⁻ + M⁻¹ R_Sᵀ Λ,   R_S q̇⁺ = 0,   Λ ≥ 0,

on the contact set S (the landing contact and the closed ones), solved by active sets: the
contact with the most negative impulse leaves S and opens, until every Λ_j ≥ 0. The impulse is
normal only (no friction impulse). The kinetic energy changes by ΔT = Σ_S Λ_j R_j q̇⁻ / 2 ≤ 0
(R_S q̇⁺ = 0), summed in info[I_EIMP]. A landing slower than V_REST brings every contact
at the ground (gap R_j q ≤ GAP_REST) to rest with it, a pulling impulse of at most V_REST ×
the effective mass accepted: the ever slower landings of a rocking base (Zeno: infinitely many
in finite time) end there. After each lift-off or landing the closed contacts are
settled: one whose λ ≤ 0 opens too, the most negative first (ties: a symmetric structure's
contacts lifting together). The rim contacts of the bearings (a slip reaching its disc's
capacity, "stops") are tracked here too (:func:`track_stops`).
"""

import math

import numpy as np

from nsdyn import _kaddress as ka
from nsdyn.models.isolated import _kpairs as kq
from nsdyn.models.isolated import _kplane as kp
from nsdyn.models.isolated import _kplanerun as kr
from nsdyn.models.isolated.bearings import B_DCAP

GAP_ARM = 1e-12  # m, an open gap's switching function starts at this
IMPACT_RTOL = 1e-12  # an impulse below this x the largest counts as zero (stays in S)
V_REST = 1e-3  # m/s, landings slower than this bring the contacts at the ground to rest
GAP_REST = 1e-6  # m, an open contact this close to the ground is at the ground


@ka.compiled_only
def gap(y, op, i):
    """R_i q of contact i at the state y."""
    R = op[kq.O_R]
    s = 0.0
    for c in range(R.shape[1]):
        s += R[i, c] * y[c]
    return s


@ka.compiled_only
def switching(y, op, ws, lam, i):
    """Column 2 of the switching functions: λ_i closed, R_i q − g0_i open."""
    if ws[20][i] != 0.0:
        return gap(y, op, i) - ws[21][i]
    return lam[i]


@ka.compiled_only
def open_contact(t, y, i, modes, dirs, op, ws, EV, info):
    """Lift-off of contact i at (t, y): open, its gap armed, free; the event recorded."""
    ws[20][i] = 1.0
    ws[21][i] = min(gap(y, op, i), 0.0) - GAP_ARM
    m0 = modes[i]
    modes[i] = kp.MODE_FREE
    kr._record(EV, info, t, i, m0, kp.MODE_FREE, dirs)


@ka.compiled_only
def land(t, y, k, modes, dirs, op, ws, EV, info, switch_law, eta):
    """Landing of contact k at (t, y): the plastic impact on the contact set (module text),
    y's velocities jumped in place; contacts whose impulse would pull open. Returns
    (landing velocity R_k q̇⁻, its impulse Λ_k); the event recorded with both (EV columns
    4 and 5)."""
    R, MiRt, RMiRt = op[kq.O_R], op[kq.O_MIRT], op[kq.O_RMIRT]
    ni = R.shape[0]
    n = R.shape[1]
    opn = ws[20]
    inS = np.zeros(ni, dtype=np.bool_)
    vrel = np.zeros(ni)
    for j in range(ni):
        inS[j] = opn[j] == 0.0 or j == k
        for c in range(n):
            vrel[j] += R[j, c] * y[n + c]
    lam = np.zeros(ni)
    slow = abs(vrel[k]) < V_REST
    if slow:
        for j in range(ni):
            inS[j] = inS[j] or gap(y, op, j) <= GAP_REST
    for _ in range(ni + 1):
        idx = np.flatnonzero(inS)
        A = np.empty((idx.size, idx.size))
        b = np.empty(idx.size)
        for a in range(idx.size):
            b[a] = -vrel[idx[a]]
            for c in range(idx.size):
                A[a, c] = RMiRt[idx[a], idx[c]]
        x = np.linalg.solve(A, b)
        worst = np.int64(-1)
        big = 0.0
        for a in range(idx.size):
            big = max(big, abs(x[a]))
        low = -IMPACT_RTOL * big
        for a in range(idx.size):
            if x[a] < low and (worst < 0 or x[a] < x[worst]):
                worst = a
        if worst < 0 or slow:
            for j in range(ni):
                lam[j] = 0.0
            for a in range(idx.size):
                lam[idx[a]] = x[a] if slow else max(x[a], 0.0)
            break
        inS[idx[worst]] = False
    de = 0.0
    for j in range(ni):
        if lam[j] != 0.0:
            de += 0.5 * lam[j] * vrel[j]
            for c in range(n):
                y[n + c] += MiRt[c, j] * lam[j]
    info[kr.I_EIMP] += de
    m0 = modes[k]
    opn[k] = 0.0
    modes[k] = kp.MODE_STICK if switch_law else kp.MODE_SLIP  # (the switch law: stick test)
    kr._record(EV, info, t, k, m0, modes[k], dirs)
    e = min(int(info[kr.I_NEV]), EV.shape[0]) - 1
    EV[e, 4] = vrel[k]
    EV[e, 5] = lam[k]
    for j in range(ni):  # a closed contact the impulse would pull leaves the ground
        if j != k and opn[j] == 0.0 and not inS[j]:
            open_contact(t, y, j, modes, dirs, op, ws, EV, info)
        elif j != k and opn[j] != 0.0 and inS[j]:  # (a slow landing: at rest with k)
            opn[j] = 0.0
            m0 = modes[j]
            modes[j] = kp.MODE_STICK if switch_law else kp.MODE_SLIP
            kr._record(EV, info, t, j, m0, modes[j], dirs)
            e = min(int(info[kr.I_NEV]), EV.shape[0]) - 1
            EV[e, 4] = vrel[j]
            EV[e, 5] = lam[j]
    if switch_law:  # the landed isolator slips where its velocity is above the band
        D2 = op[kq.O_D2]
        vx = 0.0
        vy = 0.0
        for c in range(n):
            vx += D2[2 * k, c] * y[n + c]
            vy += D2[2 * k + 1, c] * y[n + c]
        if math.sqrt(vx * vx + vy * vy) > eta:
            modes[k] = kp.MODE_SLIP
    return vrel[k], lam[k]


@ka.compiled_only
def settle_contacts(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, EV, info):
    """Open the closed contacts whose normal force is not compressive, the most negative
    first, each time re-evaluated; returns a status of the loop."""
    lam = out[1]
    opn = ws[20]
    for _ in range(opn.shape[0] + 1):
        st = kq.evaluate_t(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out)
        if st != kq.ST_OK:
            return kr.ST_SINGULAR
        worst = np.int64(-1)
        for j in range(opn.shape[0]):
            if opn[j] == 0.0 and lam[j] <= 0.0 and (worst < 0 or lam[j] < lam[worst]):
                worst = j
        if worst < 0:
            return kr.ST_OK
        open_contact(t, y, worst, modes, dirs, op, ws, EV, info)
    return kr.ST_CHATTER


# by address (compiled once, on its own: see nsdyn.models.isolated.pairs_compile)
ka.tslot("pairs.settle_contacts", settle_contacts, "nsdyn.models.isolated.pairs_compile:callees")


@ka.compiled_only
def track_stops(t, y, op, bp, ws, stops):
    """Rim contacts: first time, peak overshoot |u| − d_cap and samples in contact."""
    u = ws[0]
    kq.slips(y, op[kq.O_D2], op[kq.O_MIK].shape[0], u, ws[1])
    for i in range(bp.shape[0]):
        d = math.sqrt(u[2 * i] ** 2 + u[2 * i + 1] ** 2) - bp[i, B_DCAP]
        if d > 0.0:
            if not stops[i, kr.P_TFIRST] == stops[i, kr.P_TFIRST]:  # nan: first contact
                stops[i, kr.P_TFIRST] = t
            stops[i, kr.P_PEAK] = max(stops[i, kr.P_PEAK], d)
            stops[i, kr.P_NSTEPS] += 1


# by address (declared by pairs_compile): the Radau loop tracks the rim contacts at every step
# and the output step at every output; linked, each held a copy, optimised by LLVM again
ka.tslot("pairs.track_stops", track_stops, "nsdyn.models.isolated.pairs_compile:callees")
# the landing by address: the mode switch linked a copy, with numpy's solve (half its code)
ka.tslot("pairs.land", land, "nsdyn.models.isolated.pairs_compile:callees")
