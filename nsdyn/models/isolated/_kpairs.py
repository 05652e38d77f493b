"""Kernels of a system from matrices on isolators that slide in a plane: q̈, λ and the forces.

State y = [q, q̇] (n + n) and, after them, the internal slips of triple friction pendulums
(8 per bearing at its row's B_IOFF). Isolator i slips u_i = D_i q, v_i = D_i q̇ (rows 2i, 2i+1 of the
stacked slip rows D2, shape (2ni, n)); its resisting force (bearings.py) is

    F_i = λ_i c_i + f0_i,   c_i = u_i/R_i + f̂_i,   f0_i = K_lam,i u_i + c_i v_i + F_stop,i,

with f̂_i the regularised vector law μ_d(|v|)(2/π) arctan(ε|v|) v/|v|, or the switch law's
slip μ_d v/|v| (MODE_SLIP), start μ_d d_i (MODE_START: slip from stick in the direction d_i)
or stick (MODE_STICK: the stick force τ_i a multiplier, c_i = u_i/R_i). A triple friction
pendulum has c_i = φ_i, its series model's force per unit normal force and the rates of its
internal slips from the deck's element functions (:func:`nsdyn.models.isolated._kplane.tfp_force`,
regularised law only; its λ u/R part reported in Fr, the rest in Ff). With the operators
precomputed once (M⁻¹K, M⁻¹C, M⁻¹R ᵀ, M⁻¹D2ᵀ and their products with R and D2)

    q̈ = a0 + Σ_i (M⁻¹R_iᵀ − M⁻¹D_iᵀ c_i) λ_i − Σ_stuck M⁻¹D_jᵀ τ_j,
    a0 = −M⁻¹K q − M⁻¹C q̇ − Γ [a_x, a_y, a_z + g] − Σ_i M⁻¹D_iᵀ f0_i,

and the unknowns y = [λ, τ_stuck] (m = ni + 2 n_stuck) solve the small system G y = r of the
contact rows R_k q̈ = −2αβ R_k q̇ − α² R_k q and the stick rows D_j q̈ = −κ D_j q̇, assembled
from the (ni + 2ni)² precomputed products: one evaluation costs O(n²) + O(n ni) + O(m³).
Redundant contacts (a rigid body on more contacts than it has vertical dofs) keep their r
independent rows R̃ = Qᵀ R (Q an orthonormal basis of range R) and normal forces λ = Q ξ in
range R: the split of equal contact stiffness (a rigid plate's N affine in the plan
positions), whatever the friction. Redundant stick rows (several stuck isolators under one
rigid slab) keep their independent combinations Q_sᵀ D_s (Q_s from an SVD when the modes
change) with stick forces τ = Λ Q_s ζ in proportion to the normal forces (the deck's split:
every disc fills at once). Any other singular G with a consistent right-hand side takes the
least-norm solution (G⁺ r), checked for consistency, else ST_SINGULAR.

A bilateral contact (``sp[S_CONTACT]``, the deck's CONTACT_* codes) holds λ_i < 0; there the
bearing's terms in λ_i, friction and λ u/R, use max(λ_i, 0) = 0 (c_i = 0), with the tensile
set (flags ws[19]) a fixed point of the evaluation, as in :mod:`._kplane`. A unilateral contact
(CONTACT_UNILATERAL, independent rows: Q = I) may be open (ws[20]): its row of G is the
identity's (λ_i = 0) and its c_i = 0 (lift-off and landing: :mod:`._kpairscontact`).
"""

import math
from pathlib import Path

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn._klinalg import lu_factor, lu_solve, pinv_small
from nsdyn._numba_cache import drop_stale
from nsdyn.models.isolated import _kplane as kp
from nsdyn.models.isolated.bearings import (
    B_IOFF,
    B_KIND,
    B_KLAM,
    B_RINV,
    KIND_TFP,
)

_HERE = Path(__file__).resolve().parent
drop_stale(
    _HERE,
    ["_kpairs", "_kpairsrun", "_kpairsradau", "_kpairscontact", "_kpairsstick"],
    [_HERE / f for f in ("_kpairs.py", "_kpairsrun.py", "_kpairsradau.py", "_kpairscontact.py",
                         "_kpairsstick.py", "_ktfp.py",
                         "_kplane.py", "_kplaneground.py",
                         "_kplanerun.py", "_kplaneradau.py", "_kplanestops.py", "bearings.py",
                         "pairs_compile.py")]
    + [_HERE.parents[1] / f for f in ("_kdp5.py", "_klinalg.py")],
)  # fmt: skip

# operators op (a tuple of 2-D arrays)
O_MIK, O_MIC, O_GAM, O_D2, O_R, O_MIRT, O_MIDT, O_RMIRT, O_RMIDT, O_DMIRT, O_DMIDT, O_Q = range(12)
# system parameters sp
S_G, S_ALPHA, S_BETA, S_KAPPA, S_EPS, S_ETA, S_LAW, S_CONTACT = range(8)
N_SP = 8
ST_OK, ST_SINGULAR = 0, 4
PIVOT_RTOL = 1e-13  # LU pivot floor relative to G's largest entry (below: redundant rows)
REDUNDANT_RTOL = 1e-10  # singular values below this x the largest: redundant stick rows
CONSISTENT_RTOL = 1e-8  # |G y − r| allowed, relative to |G| |y| + |r|, of a least-norm split


def workspace(n, ni):
    """Work arrays of :func:`evaluate` (made once per run, in Python): u, v, c, f0 (2ni); a0 (n);
    ground (3); G, G copy (3ni, 3ni); r, r copy (3ni); pivots (3ni); row map (ni); LU flag;
    pressure factors (ni); the stick basis: its modes (ni), Q_s (2ni, 2ni), rank; G3 (3ni,
    3ni), a vector (3ni); the compression flags (ni) of a bilateral contact; a unilateral
    contact's open flags (ni) and gap offsets (ni); the rates of the triple pendulums'
    internal slips (ni, 8); the stuck columns of G3 at unit weights (3ni, 2ni) and their flag;
    the slip-start directions (ni, 2) an alignment started from."""
    mm = 3 * ni
    return (np.zeros(2 * ni), np.zeros(2 * ni), np.zeros(2 * ni), np.zeros(2 * ni), np.zeros(n),
            np.zeros(3), np.zeros((mm, mm)), np.zeros((mm, mm)), np.zeros(mm), np.zeros(mm),
            np.zeros(mm, dtype=np.int64), np.zeros(ni, dtype=np.int64),
            np.zeros(1, dtype=np.int64), np.ones(ni), np.full(ni, -1, dtype=np.int64),
            np.zeros((2 * ni, 2 * ni)), np.zeros(1, dtype=np.int64), np.zeros((mm, mm)),
            np.zeros(mm), np.ones(ni), np.zeros(ni), np.zeros(ni), np.zeros((ni, 8)),
            np.zeros((mm, 2 * ni)), np.zeros(1, dtype=np.int64), np.zeros((ni, 2)))  # fmt: skip


def outputs_at(n, ni):
    """The arrays the force kernel fills (made once per run, in Python):
    q̈ (n), λ (ni), the friction, bearing and other forces (ni, 2) each."""
    return (np.zeros(n), np.zeros(ni), np.zeros((ni, 2)), np.zeros((ni, 2)), np.zeros((ni, 2)))


@ka.compiled_only
def slips(y, D2, n, u, v):
    """u = D2 q, v = D2 q̇ (2ni)."""
    for r in range(D2.shape[0]):
        su = 0.0
        sv = 0.0
        for c in range(n):
            su += D2[r, c] * y[c]
            sv += D2[r, c] * y[n + c]
        u[r] = su
        v[r] = sv


@ka.compiled_only
def bearing_terms(bp, i, ux, uy, vx, vy, law, eps, mode, dx, dy, kpr):
    """(ox, oy, fx, fy): damper + rim stop of isolator i and its friction per unit normal
    force f̂ (zero in stick), the coefficients scaled by the pressure factor kpr."""
    ox, oy = kp.damper_and_rim(bp, i, ux, uy, vx, vy)
    speed = math.sqrt(vx * vx + vy * vy)
    if law == kp.LAW_ARCTAN:
        if speed > 0.0:
            s = kp.mu_kinetic(bp, i, speed) * kpr * (2.0 / math.pi) * math.atan(eps * speed)
            s /= speed
            return ox, oy, s * vx, s * vy
        return ox, oy, 0.0, 0.0
    if mode == kp.MODE_SLIP:
        s = kp.mu_kinetic(bp, i, speed) * kpr / speed
        return ox, oy, s * vx, s * vy
    if mode == kp.MODE_START:
        s = kp.mu_kinetic(bp, i, speed) * kpr
        return ox, oy, s * dx, s * dy
    return ox, oy, 0.0, 0.0


@ka.compiled_only
def evaluate(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, qdd, lam, Ff, Fr, Fo):
    """:func:`evaluate_at` with pressure-dependent friction, and a bilateral contact's tensile
    set (ws[19]) re-evaluated until it is λ_i <= 0
    (:func:`nsdyn.models.isolated._kplane.tension_flags`). In each tensile pass the pressure
    factors k_p(λ_i) (:func:`nsdyn.models.isolated._kplane.pressure_factor`) are iterated at
    the normal forces they give, from 1 to PRESSURE_TOL (left in ws[13]); ST_SINGULAR when
    they do not settle. One call of evaluate_at, inlined (numba's IR), so LLVM optimises its
    body once: two layers of kernels each linked a copy of it and optimised it again."""
    on = ws[19]
    pf = ws[13]
    uni = int(sp[S_CONTACT]) == kp.CONTACT_UNILATERAL
    bil = int(sp[S_CONTACT]) == kp.CONTACT_BILATERAL
    for i in range(on.shape[0]):
        on[i] = 0.0 if uni and ws[20][i] != 0.0 else 1.0
    st = ST_OK
    for p in range(kp.TENSION_PASSES + 1):
        if p > 0 and (not bil or st != ST_OK or not kp.tension_flags(lam, on)):
            return st
        press = kp.pressure_reset(bp, pf)
        change = math.inf
        for it in range(kp.PRESSURE_ITER + 1):
            if it > 0:
                change = kp.pressure_update(bp, lam, pf)
            st = evaluate_at(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, qdd, lam, Ff, Fr, Fo)
            if (it == 0 and not press) or st != ST_OK or change <= kp.PRESSURE_TOL:
                break
            if it == kp.PRESSURE_ITER:  # not settled
                st = ST_SINGULAR
    return st


# the force kernel by address (:func:`nsdyn._kaddress.tcall`, declared and put in the table
# by nsdyn.models.isolated.pairs_compile): the right-hand side, the settling of stick and of
# contacts, the event functions and the outputs would otherwise each link, LLVM optimise and
# translate again their own copy of it (with evaluate_at, inlined into it)
ka.tslot("pairs.evaluate", evaluate, "nsdyn.models.isolated.pairs_compile:callees")


@njit(cache=True, error_model="numpy", inline="always")
def evaluate_t(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out):
    """:func:`evaluate` into ``out = (qdd, lam, Ff, Fr, Fo)``, called by its address in the
    table of :mod:`nsdyn._kaddress`."""
    qdd, lam, Ff, Fr, Fo = out
    args = (t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, qdd, lam, Ff, Fr, Fo)
    return ka.tcall("pairs.evaluate", args)


@njit(cache=True, error_model="numpy", inline="always")
def evaluate_at(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, qdd, lam, Ff, Fr, Fo):
    """q̈ and the isolator forces at (t, y): normal forces λ (ni,), resisting friction Ff
    (ni, 2) (the stick force τ_i of a stuck isolator), restoring Fr = λ u/R + K_lam u and
    damper + stop Fo (ni, 2). Returns ST_OK or ST_SINGULAR; leaves G's LU in ws (the
    row of stuck isolator j's τ is ws[11][j], −1 when it slips; ws[12][0] = 1: LU exact).

    The contacts enter through their independent rows R̃ = Qᵀ R (r of them, op[O_R]) with
    multipliers ξ and normal forces λ = Q ξ (op[O_Q], ni × r; Q = I without redundancy)."""
    u, v, cf, f0, a0, ag, G, G2, r, r2, piv, row, luok, pf = ws[:14]
    on = ws[19]
    MiK, MiC, Gam, D2, R, Q = op[O_MIK], op[O_MIC], op[O_GAM], op[O_D2], op[O_R], op[O_Q]
    MiRt, MiDt, RMiRt, RMiDt, DMiRt, DMiDt = (op[O_MIRT], op[O_MIDT], op[O_RMIRT],
                                              op[O_RMIDT], op[O_DMIRT], op[O_DMIDT])  # fmt: skip
    n = MiK.shape[0]
    ni = Q.shape[0]
    nr = Q.shape[1]
    kp.ground(t, gk, gp, tab, ag)
    ag[2] += sp[S_G]
    law = int(sp[S_LAW])
    eps = sp[S_EPS]
    slips(y, D2, n, u, v)
    m = nr
    for i in range(ni):
        ux, uy, vx, vy = u[2 * i], u[2 * i + 1], v[2 * i], v[2 * i + 1]
        mode = modes[i]
        ox, oy, fx, fy = bearing_terms(bp, i, ux, uy, vx, vy, law, eps, mode, dirs[i, 0],
                                       dirs[i, 1], pf[i])  # fmt: skip
        if bp[i, B_KIND] == KIND_TFP:  # the series model's force, less λ u/R reported apart
            if int(bp[i, B_IOFF]) + 8 > y.shape[0]:  # (a state without its internal slips)
                return ST_SINGULAR
            px, py = kp.tfp_force(y, bp, i, ux, uy, vx, vy, ws[22])
            fx = px - bp[i, B_RINV] * ux
            fy = py - bp[i, B_RINV] * uy
        if on[i] == 0.0:  # tensile: no terms in λ_i
            fx = fy = 0.0
        Fo[i, 0] = ox
        Fo[i, 1] = oy
        Ff[i, 0] = fx
        Ff[i, 1] = fy
        f0[2 * i] = ox + bp[i, B_KLAM] * ux
        f0[2 * i + 1] = oy + bp[i, B_KLAM] * uy
        cf[2 * i] = on[i] * (bp[i, B_RINV] * ux + fx)
        cf[2 * i + 1] = on[i] * (bp[i, B_RINV] * uy + fy)
        row[i] = -1
        if law == kp.LAW_SWITCH and mode == kp.MODE_STICK:
            row[i] = m
            m += 2
    for a in range(n):
        s = -(Gam[a, 0] * ag[0] + Gam[a, 1] * ag[1] + Gam[a, 2] * ag[2])
        for b in range(n):
            s -= MiK[a, b] * y[b] + MiC[a, b] * y[n + b]
        for k in range(2 * ni):
            s -= MiDt[a, k] * f0[k]
        a0[a] = s
    # rows: contact k (of R̃), then the stuck isolators' x, y; columns: ξ_k, then the stuck τ
    al = sp[S_ALPHA]
    be = sp[S_BETA]
    kap = sp[S_KAPPA]
    qdiag = nr == ni  # Q diagonal (one row per contact): column j of G has the term i = j only
    for i in range(ni):
        for j in range(nr):
            if i != j and Q[i, j] != 0.0:
                qdiag = False
    for k in range(m):
        e = -1  # (the slip row of a stick row)
        if k >= nr:
            for j in range(ni):
                if row[j] >= 0 and row[j] <= k < row[j] + 2:
                    e = 2 * j + k - row[j]
        rq = 0.0
        rv = 0.0
        ra = 0.0
        for b in range(n):
            c = R[k, b] if e < 0 else D2[e, b]
            rq += c * y[b]
            rv += c * y[n + b]
            ra += c * a0[b]
        r[k] = (-2.0 * al * be * rv - al * al * rq - ra) if e < 0 else (-kap * rv - ra)
        for j in range(nr):  # the multiplier ξ_j: contact forces R̃_jᵀ, friction Σ_i c_i Q_ij
            g = RMiRt[k, j] if e < 0 else DMiRt[e, j]
            for i in range(j if qdiag else 0, j + 1 if qdiag else ni):
                if Q[i, j] != 0.0:
                    if e < 0:
                        w = RMiDt[k, 2 * i] * cf[2 * i] + RMiDt[k, 2 * i + 1] * cf[2 * i + 1]
                    else:
                        w = DMiDt[e, 2 * i] * cf[2 * i] + DMiDt[e, 2 * i + 1] * cf[2 * i + 1]
                    g -= w * Q[i, j]
            G[k, j] = g
        for j in range(ni):
            if row[j] >= 0:
                for c in range(2):
                    G[k, row[j] + c] = -(RMiDt[k, 2 * j + c] if e < 0 else DMiDt[e, 2 * j + c])
    if int(sp[S_CONTACT]) == kp.CONTACT_UNILATERAL:
        for k in range(nr):  # an open contact: λ_k = 0
            if ws[20][k] != 0.0:
                for b in range(m):
                    G[k, b] = 0.0
                G[k, k] = RMiRt[k, k]
                r[k] = 0.0
    for a in range(m):
        r2[a] = r[a]
        for b in range(m):
            G2[a, b] = G[a, b]
    Gm = G[:m, :m]
    if m > nr and ka.tcall("pairs.stick_basis", (modes, row, D2, nr, m, ws)) < m - nr:
        luok[0] = 0  # redundant stick rows: their forces in proportion to λ
        uni = int(sp[S_CONTACT]) == kp.CONTACT_UNILATERAL
        if not ka.tcall("pairs.proportional_split", (Q, nr, m, ws, uni)):
            return ST_SINGULAR
    else:
        luok[0] = 1 if lu_factor(Gm, piv[:m], PIVOT_RTOL) else 0
        if luok[0] == 1:
            lu_solve(Gm, piv[:m], r[:m])
        elif not ka.tcall("pairs.least_norm", (G2[:m, :m], r2[:m], r[:m])):
            return ST_SINGULAR
    for i in range(ni):  # λ = Q ξ and the bearings' multiplier forces λ_i c_i (+ τ_i) in f0
        li = 0.0
        for j in range(nr):
            li += Q[i, j] * r[j]
        lam[i] = li
        f0[2 * i] = cf[2 * i] * li + (r[row[i]] if row[i] >= 0 else 0.0)
        f0[2 * i + 1] = cf[2 * i + 1] * li + (r[row[i] + 1] if row[i] >= 0 else 0.0)
    for a in range(n):
        s = a0[a]
        for j in range(nr):
            s += MiRt[a, j] * r[j]
        for k in range(2 * ni):
            s -= MiDt[a, k] * f0[k]
        qdd[a] = s
        if not math.isfinite(s):
            return ST_SINGULAR
    for i in range(ni):
        li = lam[i]
        Fr[i, 0] = (on[i] * li * bp[i, B_RINV] + bp[i, B_KLAM]) * u[2 * i]
        Fr[i, 1] = (on[i] * li * bp[i, B_RINV] + bp[i, B_KLAM]) * u[2 * i + 1]
        if row[i] >= 0:
            Ff[i, 0] = r[row[i]]
            Ff[i, 1] = r[row[i] + 1]
        else:
            Ff[i, 0] *= li
            Ff[i, 1] *= li
    return ST_OK


@ka.compiled_only
def stick_basis(modes, row, D2, nr, m, ws):
    """Rank ρ of the stuck isolators' slip rows D_s (2n_s × n) and an orthonormal basis Q_s
    of their range (ws[15][:2n_s, :ρ]), computed when the modes change (cached in ws)."""
    msig, Qs, rho = ws[14], ws[15], ws[16]
    same = True
    for i in range(modes.shape[0]):
        same = same and msig[i] == modes[i]
    if same:
        return rho[0]
    ns2 = m - nr
    Ds = np.zeros((ns2, D2.shape[1]))
    for j in range(modes.shape[0]):
        if row[j] >= 0:
            for c in range(2):
                for b in range(D2.shape[1]):
                    Ds[row[j] - nr + c, b] = D2[2 * j + c, b]
    U, sv, _ = np.linalg.svd(Ds)
    k = 0
    for a in range(sv.shape[0]):
        if sv[a] > REDUNDANT_RTOL * sv[0]:
            k += 1
    for a in range(ns2):
        for b in range(ns2):
            Qs[a, b] = U[a, b]
    for i in range(modes.shape[0]):
        msig[i] = modes[i]
    rho[0] = k
    ws[24][0] = 0  # (proportional_split's cached columns belong to the old modes)
    return k


@ka.compiled_only
def proportional_split(Q, nr, m, ws, uni):
    """Solve the constraints with redundant stick rows (G2, r2 of :func:`evaluate_at`): rows
    and stick forces in the range of the stuck slip rows, τ = Λ Q_s ζ with Λ the stuck
    isolators' normal forces (so a rigid slab's stick force is split in proportion to
    them, as the deck's kernels split it): the nonsingular (r + ρ) system
    Tᵀ G Λ T [ξ, ζ] = Tᵀ r, T = blockdiag(I, Q_s), solved twice (Λ = I, then the first
    solution's λ). The full [ξ, τ] lands in ws[8] (r); False when singular."""
    G, G2, r, r2, piv, row, Qs, rho, G3, tv = (ws[6], ws[7], ws[8], ws[9], ws[10], ws[11],
                                               ws[15], ws[16][0], ws[17], ws[18])  # fmt: skip
    ni = Q.shape[0]
    mr = nr + rho
    for p in range(2):
        for b in range(m - nr):  # weights of the stuck rows: 1, then their λ
            j = -1
            for i in range(ni):
                if row[i] >= 0 and row[i] <= nr + b < row[i] + 2:
                    j = i
            w = 1.0
            if p == 1:
                w = 0.0
                for k in range(nr):
                    w += Q[j, k] * r[k]
            tv[b] = w
        wmax = 0.0
        for b in range(m - nr):
            wmax = max(wmax, tv[b])
        for b in range(m - nr):  # (an unloaded isolator keeps a weight: uplift is located later)
            tv[b] = max(tv[b], 1e-9 * wmax)
        # G3 = G Λ T (columns); at unit weights its stuck columns are fixed by the modes (G's
        # stuck columns are −R M⁻¹D_jᵀ, −D M⁻¹D_jᵀ) and kept (ws[23]), but for open contacts
        cache = p == 0 and not uni
        for a in range(m):
            for c in range(mr):
                if c < nr:
                    G3[a, c] = G2[a, c]
                elif cache and ws[24][0] == 1:
                    G3[a, c] = ws[23][a, c - nr]
                else:
                    g = 0.0
                    for b in range(m - nr):
                        g += G2[a, nr + b] * tv[b] * Qs[b, c - nr]
                    G3[a, c] = g
                    if cache:
                        ws[23][a, c - nr] = g
        if cache:
            ws[24][0] = 1
        for a in range(mr):  # G = Tᵀ G3 (rows), r = Tᵀ r2
            for c in range(mr):
                if a < nr:
                    G[a, c] = G3[a, c]
                else:
                    g = 0.0
                    for b in range(m - nr):
                        g += Qs[b, a - nr] * G3[nr + b, c]
                    G[a, c] = g
            if a < nr:
                r[a] = r2[a]
            else:
                g = 0.0
                for b in range(m - nr):
                    g += Qs[b, a - nr] * r2[nr + b]
                r[a] = g
        if not lu_factor(G[:mr, :mr], piv[:mr], PIVOT_RTOL):
            return False
        lu_solve(G[:mr, :mr], piv[:mr], r[:mr])
        for b in range(rho):  # ζ aside, then τ = Λ Q_s ζ
            G3[0, b] = r[nr + b]
        for b in range(m - nr):
            g = 0.0
            for c in range(rho):
                g += Qs[b, c] * G3[0, c]
            r[nr + b] = tv[b] * g
    return True


@ka.compiled_only
def least_norm(G, r, out):
    """out = G⁺ r when G y = r is consistent (redundant constraints); False otherwise."""
    m = G.shape[0]
    Gp = pinv_small(G, m)
    ny = 0.0
    nr = 0.0
    ng = 0.0
    for a in range(m):
        s = 0.0
        for b in range(m):
            s += Gp[a, b] * r[b]
            ng = max(ng, abs(G[a, b]))
        out[a] = s
        ny = max(ny, abs(s))
        nr = max(nr, abs(r[a]))
    res = 0.0
    for a in range(m):
        s = -r[a]
        for b in range(m):
            s += G[a, b] * out[b]
        res = max(res, abs(s))
    return math.isfinite(res) and res <= CONSISTENT_RTOL * (m * ng * ny + nr)


# the force kernel's two rarer solves and the stick basis by address (declared by
# pairs_compile): linked, the force kernel held a copy of each, with their LU, pseudo-inverse
# and SVD, optimised by LLVM again. The stick rows (the basis and the proportional split) exist
# only with the switch law: a run of the regularised law takes neither's address
_DECLARE = "nsdyn.models.isolated.pairs_compile:callees"
ka.tslot("pairs.proportional_split", proportional_split, _DECLARE)
ka.tslot("pairs.least_norm", least_norm, _DECLARE)
ka.tslot("pairs.stick_basis", stick_basis, _DECLARE)


@ka.compiled_only
def rhs(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, dy):
    """First-order right-hand side dy = [q̇, q̈, ṡ] (ṡ: the internal slips of triple friction
    pendulums, when y has them); ``out = (qdd, lam, Ff, Fr, Fo)`` filled."""
    qdd = out[0]
    st = evaluate_t(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out)
    n = op[O_MIK].shape[0]
    for a in range(n):
        dy[a] = y[n + a]
        dy[n + a] = qdd[a]
    if y.shape[0] > 2 * n:
        sd = ws[22]
        for i in range(bp.shape[0]):
            if bp[i, B_KIND] == KIND_TFP:
                o = int(bp[i, B_IOFF])
                for j in range(8):
                    dy[o + j] = sd[i, j]
    return st


ka.tslot("pairs.rhs", rhs, _DECLARE)  # by address: the loops' Newton, stages and Jacobian


@njit(cache=True, error_model="numpy", inline="always")
def rhs_t(t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, dy):
    """:func:`rhs` by its address."""
    return ka.tcall("pairs.rhs", (t, y, modes, dirs, op, bp, sp, gk, gp, tab, ws, out, dy))


@ka.compiled_only
def start_direction(i, tx, ty, mu_n, ws, dirs):
    """Direction in which stuck isolator i starts to slip when its stick force τ = (tx, ty)
    leaves the disc (the one it then accelerates in): its compliance W from the stick rows'
    block of G⁻¹ (the LU left in ws by :func:`evaluate` with i stuck; the τ_i block of G⁻¹
    is the inverse of the Schur complement −W), then the deck's rule
    :func:`nsdyn.models.isolated._kplane.start_direction` on A = blockdiag(W⁻¹, 1)."""
    G, piv, row, luok = ws[6], ws[10], ws[11], ws[12]
    ni = row.shape[0]
    m = 0
    for j in range(ni):
        if row[j] >= 0:
            m = max(m, row[j] + 2)
    Am = np.zeros((3, 3))
    Am[2, 2] = 1.0
    if row[i] >= 0 and luok[0] == 1:  # (else kp's rule falls back to d = τ/|τ|)
        e = np.zeros(m)
        for c in range(2):
            for a in range(m):
                e[a] = 0.0
            e[row[i] + c] = 1.0
            lu_solve(G[:m, :m], piv[:m], e)
            Am[0, c] = -e[row[i]]
            Am[1, c] = -e[row[i] + 1]
    for a in range(2):
        for b in range(2):
            if not math.isfinite(Am[a, b]):
                Am[a, b] = 0.0
    kp.start_direction(np.int64(0), tx, ty, mu_n, Am, np.zeros((1, 2)), dirs[i:],
                       np.empty((3, 3)), np.zeros(3, dtype=np.int64), np.empty((2, 3)))  # fmt: skip


# by address (declared by pairs_compile): the settling of stick and the mode switch linked a
# copy each, with its small solves
ka.tslot("pairs.start_direction", start_direction, _DECLARE)
