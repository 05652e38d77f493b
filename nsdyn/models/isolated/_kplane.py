"""Kernels of a rigid deck on bidirectional isolators: ground, vector friction, normal forces, q̈.

Coordinates q = (x, y, θ): plan displacement of the deck's reference point O relative to the
ground and its twist (small rotation). Isolator i at (X_i, Y_i) slips u_i = B_i q with
B_i = [[1, 0, −Y_i], [0, 1, X_i]]; its resisting force (bearings.py) is

    F_i = N_i (u_i/R_i + f̂_i) + K_lam,i u_i + c_i v_i + F_stop,i,   v_i = B_i q̇,

with the friction per unit normal force f̂_i = μ_d(|v|) (2/π) arctan(ε|v|) v/|v| (regularised
law), μ_d(|v|) v/|v| (switch law, slip, MODE_SLIP), μ_d(|v|) d_i (MODE_START: slip starting
from stick in the stick force's direction d_i, until |v| reaches η) or a constraint force τ_i
(MODE_STICK: B_i q̈ = −κ B_i q̇). A triple friction pendulum (tfp.py) resists with N_i φ_i,
its series model's force per unit normal force: a function of u_i and of its internal slips,
states after [q, q̇] whose rates :func:`rhs` appends. Pressure-dependent friction scales the
coefficients by k_p(N_i) (bearings.py). The deck (mass m, centre of mass at
(e_x, e_y) and height h above the sliding surfaces, M about O) obeys

    M q̈ = −M [a_x, a_y, 0]ᵀ − Σ B_iᵀ F_i,

and the normal forces follow from the deck's vertical and rocking equilibrium with equal vertical
isolator stiffness (the rigid-plate distribution; the vertical contact is exact, so no Baumgarte
terms are needed), N_i = w_i W + p_x,i S_X + p_y,i S_Y with

    W = m (g + a_z),   S_X = Σ N X = m e_x (g + a_z) − m h (a_x + ẍ − e_y θ̈),
                       S_Y = Σ N Y = m e_y (g + a_z) − m h (a_y + ÿ + e_x θ̈).

N_i is affine in q̈ (the overturning of the horizontal inertia forces), so friction and
restoring forces, proportional to N_i, put q̈ on both sides: the kernel solves the 3 × 3 system
(M + Σ B_iᵀ c_i n1_iᵀ) q̈ = r, with one stuck isolator the 5 × 5 saddle-point system for (q̈, τ),
and with two or more the deck is held (q̈ = −κ q̇) and the stick forces are the split that
loads each in proportion to its normal force (the least Σ |τ_i|²/N_i):
τ_i = N_i B_i G⁻¹ f, G = Σ_stuck N_i B_iᵀ B_i. A translating demand then uses every disc
alike (|τ_i|/N_i = |f|/Σ N_i), so a held deck breaks away at the demand μ_s Σ N_i Coulomb
allows, not when its lightest isolator alone is full.

Contact ``sp[S_CONTACT]``: DETECT (the loops end the run at N_i = 0) or BILATERAL (N_i < 0
held). A tensile isolator's terms in N_i, friction and N u/R (a triple pendulum's N φ), use
max(N_i, 0) = 0; its K_lam u, damper and rim stop act. The tensile set (flags ws[12]) is a
fixed point of the evaluation; under the switch law a tensile isolator is MODE_FREE.
"""

import math
from pathlib import Path

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn._kaddress import NO_NRT
from nsdyn._klinalg import lu_factor, lu_solve
from nsdyn._numba_cache import drop_stale
from nsdyn.models.isolated._kplaneground import (  # noqa: F401 (the loops' and packers' names)
    G_HARMONIC,
    G_TABLE,
    GP_AX,
    GP_AY,
    GP_AZ,
    GP_DT,
    GP_F,
    GP_FZ,
    GP_PHY,
    GP_PHZ,
    GP_T0,
    N_GP,
    ground,
    next_breakpoint,
)
from nsdyn.models.isolated._ktfp import tfp_force, tfp_speed  # noqa: F401 (the loops')
from nsdyn.models.isolated.bearings import (
    B_AREA,
    B_C,
    B_CSTOP,
    B_DCAP,
    B_IOFF,
    B_KIND,
    B_KLAM,
    B_KSTOP,
    B_MUFAST,
    B_MUSLOW,
    B_PREF,
    B_RATE,
    B_RINV,
    K_P_FLOOR,
    KIND_TFP,
    PRESSURE_BASE,
    PRESSURE_SCALE,
)

# the time loops (_kplanerun, _kplaneradau) compile these kernels, the shared tableau and LU
# and the bearing table's column numbers into their caches: drop all when any of them changes
_HERE = Path(__file__).resolve().parent
_LOOPS = ["_kplane", "_kplanerun", "_kplaneradau", "_kplanestops", "_kplaneground", "_ktfp"]
drop_stale(
    _HERE,
    _LOOPS,
    [_HERE / f"{k}.py" for k in [*_LOOPS, "bearings", "deck_compile"]]
    + [_HERE.parents[1] / f for f in ("_kdp5.py", "_klinalg.py", "_kaddress.py")],
)

LAW_ARCTAN, LAW_SWITCH = 0, 1
MODE_STICK, MODE_SLIP, MODE_START, MODE_FREE = 0, 1, 2, 3  # FREE: tensile (bilateral)
CONTACT_DETECT, CONTACT_BILATERAL, CONTACT_UNILATERAL = 0, 1, 2  # unilateral: _kpairscontact
TENSION_PASSES = 16  # re-evaluations settling the tensile set, at most
# system parameters sp
S_M, S_EX, S_EY, S_H, S_G, S_KAPPA, S_EPS, S_ETA, S_LAW, S_CONTACT = range(10)
N_SP = 10
ST_OK, ST_SINGULAR = 0, 4
PRESSURE_ITER = 50  # fixed-point passes of the pressure factors, at most
PRESSURE_TOL = 1e-14  # their largest change accepted


@njit(cache=True, error_model="numpy")
def mu_kinetic(bp, i, speed):
    """μ_d(|v|) = μ_fast − (μ_fast − μ_slow) exp(−a |v|) of isolator i."""
    return bp[i, B_MUFAST] - (bp[i, B_MUFAST] - bp[i, B_MUSLOW]) * math.exp(-bp[i, B_RATE] * speed)


@ka.compiled_only
def slip_kinematics(y, pos, i):
    """(u_x, u_y, v_x, v_y) of isolator i in the state y = [q, q̇]."""
    X = pos[i, 0]
    Y = pos[i, 1]
    return (y[0] - Y * y[2], y[1] + X * y[2], y[3] - Y * y[5], y[4] + X * y[5])


def workspace(ni):
    """Work arrays of :func:`evaluate` (made once per run, in Python: the loops allocate
    nothing); the last, (ni, 8), receives the
    rates of the triple friction pendulums' internal slips, the (ni,) one the pressure factors
    of the friction at the last evaluation, the last (ni,) the compression flags (1: N_i
    carries its normal-force terms, 0: tensile under a bilateral contact). After those: the
    scratch of :func:`start_direction` (a 3 × 3 factor, its pivots, two 3-vectors), the
    switch law's re-stick candidates (ni,) of its settling, and the slip-start alignment's
    scratch (:mod:`._kplanealign`: the directions it started from, (ni, 2), and (4, 3)); last
    the impasse record (3,): ρ of the last evaluation, then the time and ρ of the last
    evaluation at ρ <= 0 since the last accepted step (NaN: none; :func:`evaluate`)."""
    return (np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((5, 5)), np.zeros(5),
            np.zeros(5, dtype=np.int64), np.zeros((ni, 3)), np.zeros(ni), np.zeros((ni, 2)),
            np.zeros(3), np.zeros(3), np.zeros((ni, 8)), np.ones(ni), np.ones(ni),
            np.zeros((3, 3)), np.zeros(3, dtype=np.int64), np.zeros((2, 3)),
            np.zeros(ni, dtype=np.bool_), np.zeros((ni, 2)), np.zeros((4, 3)),
            np.array([1.0, np.nan, np.nan]))  # fmt: skip


def forces(ni):
    """The evaluation's outputs ``out = (qdd, N, Ff, Fr, Fo)`` for ``ni`` isolators."""
    return (np.zeros(3), np.zeros(ni), np.zeros((ni, 2)), np.zeros((ni, 2)), np.zeros((ni, 2)))


@njit(cache=True, error_model="numpy")
def pressure_factor(bp, i, n):
    """k_p = 0.7^((p − p_ref)/50 MPa) ≥ K_P_FLOOR at p = max(n, 0)/area of isolator i (1: none)."""
    if bp[i, B_AREA] <= 0.0:
        return 1.0
    p = max(n, 0.0) / bp[i, B_AREA]
    return max(PRESSURE_BASE ** ((p - bp[i, B_PREF]) / PRESSURE_SCALE), K_P_FLOOR)


@njit(cache=True, error_model="numpy")
def pressure_reset(bp, pf):
    """pf (ni) = 1; True when an isolator has a contact area (pressure-dependent friction)."""
    press = False
    for i in range(pf.shape[0]):
        pf[i] = 1.0
        press = press or bp[i, B_AREA] > 0.0
    return press


@ka.compiled_only
def pressure_update(bp, N, pf):
    """One fixed-point pass of the pressure factors, pf_i = k_p(N_i); the largest change."""
    change = 0.0
    for i in range(pf.shape[0]):
        k = pressure_factor(bp, i, N[i])
        change = max(change, abs(k - pf[i]))
        pf[i] = k
    return change


@njit(cache=True, error_model="numpy", **NO_NRT)
def evaluate(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, qdd, N, Ff, Fr, Fo):
    """q̈ and the isolator forces at (t, y) (:func:`evaluate_at`); a bilateral contact's
    tensile set (ws[12]) re-evaluated until it is N_i <= 0 (a set still changing after
    TENSION_PASSES, N_i ≈ 0, is kept). Returns ST_OK or ST_SINGULAR.

    With pressure-dependent friction the coefficients carry k_p(N_i) at the live normal
    forces, which depend on q̈: in each pass N = N(q̈(k_p(N))) is iterated from k_p = 1 to
    PRESSURE_TOL (contraction: the weak overturning share of the friction, ~1e-3), the factors
    left in pf = ws[11]; ST_SINGULAR when they do not settle. One call of evaluate_at, inlined
    (numba's IR): LLVM optimises its body once.

    An evaluation whose inertia ratio ρ (:func:`inertia_ratio`) is <= 0 returns ST_SINGULAR
    and keeps its time and ρ in ws[19][1:] (the last such; the loops clear the time at each
    accepted step): the friction's feedback on the normal forces has cancelled the deck's
    inertia, and q̈ has no solution on this branch."""
    st = _settled(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, qdd, N, Ff, Fr, Fo)
    rho = ws[19]
    if st == ST_OK and rho[0] <= 0.0:
        rho[1] = t
        rho[2] = rho[0]
        return ST_SINGULAR
    return st


@njit(cache=True, error_model="numpy", inline="always", **NO_NRT)
def _settled(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, qdd, N, Ff, Fr, Fo):
    """:func:`evaluate` before its inertia check: the tensile set and the pressure factors
    settled."""
    on, pf = ws[12], ws[11]
    bil = int(sp[S_CONTACT]) == CONTACT_BILATERAL
    for i in range(on.shape[0]):
        on[i] = 1.0
    st = ST_OK
    for p in range(TENSION_PASSES + 1):
        if p > 0 and (not bil or st != ST_OK or not tension_flags(N, on)):
            return st
        press = pressure_reset(bp, pf)
        change = math.inf
        for it in range(PRESSURE_ITER + 1):
            if it > 0:
                change = pressure_update(bp, N, pf)
            st = evaluate_at(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, qdd, N, Ff,
                             Fr, Fo)  # fmt: skip
            if (it == 0 and not press) or st != ST_OK or change <= PRESSURE_TOL:
                break
            if it == PRESSURE_ITER:  # not settled
                st = ST_SINGULAR
    return st


# the force kernel by address (:func:`nsdyn._kaddress.tcall`, declared and put in the table
# by nsdyn.models.isolated.deck_compile): the loops' kernels that evaluate the deck (settling,
# switching, events, outputs, the right-hand side) would otherwise each link, LLVM optimise
# and translate again their own copy of it
ka.tslot("deck.evaluate", evaluate, "nsdyn.models.isolated.deck_compile:callees")


@njit(cache=True, error_model="numpy", inline="always")
def evaluate_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out):
    """:func:`evaluate` into ``out = (qdd, N, Ff, Fr, Fo)``, called by its address in the
    table of :mod:`nsdyn._kaddress`."""
    qdd, N, Ff, Fr, Fo = out
    args = (t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, qdd, N, Ff, Fr, Fo)
    return ka.tcall("deck.evaluate", args)


@njit(cache=True, error_model="numpy")
def tension_flags(N, on):
    """on_i = 1 where N_i > 0, else 0; True when a flag changed."""
    changed = False
    for i in range(N.shape[0]):
        w = 1.0 if N[i] > 0.0 else 0.0
        changed = changed or w != on[i]
        on[i] = w
    return changed


@ka.compiled_only
def damper_and_rim(bp, i, ux, uy, vx, vy):
    """(F_x, F_y) of isolator i's damper c v and rim stop max(0, k_stop δ + c_stop δ̇) u/|u|
    (δ = |u| − d_cap > 0) at slip u, slip velocity v."""
    ox = bp[i, B_C] * vx
    oy = bp[i, B_C] * vy
    ru = math.sqrt(ux * ux + uy * uy)
    if ru > bp[i, B_DCAP]:
        nx = ux / ru
        ny = uy / ru
        fs = bp[i, B_KSTOP] * (ru - bp[i, B_DCAP]) + bp[i, B_CSTOP] * (vx * nx + vy * ny)
        if fs > 0.0:
            ox += fs * nx
            oy += fs * ny
    return ox, oy


@njit(cache=True, error_model="numpy", inline="always", **NO_NRT)
def evaluate_at(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, qdd, N, Ff, Fr, Fo):
    """:func:`evaluate` with the friction coefficients scaled by the pressure factors ws[11]."""
    Am, A3, K5, r5, piv, n1, n0, cN, fv, ag, sd, pf, on = ws[:13]
    ni = pos.shape[0]
    ground(t, gk, gp, tab, ag)
    m = sp[S_M]
    ex = sp[S_EX]
    ey = sp[S_EY]
    h = sp[S_H]
    gz = sp[S_G] + ag[2]
    law = int(sp[S_LAW])
    eps = sp[S_EPS]
    sx0 = m * ex * gz - m * h * ag[0]
    sy0 = m * ey * gz - m * h * ag[1]
    for a in range(3):
        for b in range(3):
            Am[a, b] = M[a, b]
        fv[a] = -(M[a, 0] * ag[0] + M[a, 1] * ag[1])
    nst = 0
    ist = np.int64(-1)
    for i in range(ni):
        X = pos[i, 0]
        Y = pos[i, 1]
        ux, uy, vx, vy = slip_kinematics(y, pos, i)
        n0[i] = nd[i, 0] * m * gz + nd[i, 1] * sx0 + nd[i, 2] * sy0
        n1[i, 0] = -m * h * nd[i, 1]
        n1[i, 1] = -m * h * nd[i, 2]
        n1[i, 2] = -m * h * (-ey * nd[i, 1] + ex * nd[i, 2])
        ox, oy = damper_and_rim(bp, i, ux, uy, vx, vy)
        Fo[i, 0] = ox
        Fo[i, 1] = oy
        f0x = ox + bp[i, B_KLAM] * ux
        f0y = oy + bp[i, B_KLAM] * uy
        speed = math.sqrt(vx * vx + vy * vy)
        fx = 0.0
        fy = 0.0
        if bp[i, B_KIND] == KIND_TFP:  # the series model's force, less N u/R reported apart
            if int(bp[i, B_IOFF]) + 8 > y.shape[0]:  # (a state without its internal slips)
                return ST_SINGULAR
            px, py = tfp_force(y, bp, i, ux, uy, vx, vy, sd)
            fx = px - bp[i, B_RINV] * ux
            fy = py - bp[i, B_RINV] * uy
        elif law == LAW_ARCTAN:
            if speed > 0.0:
                s = mu_kinetic(bp, i, speed) * pf[i] * (2.0 / math.pi) * math.atan(eps * speed)
                s /= speed
                fx = s * vx
                fy = s * vy
        elif modes[i] == MODE_SLIP:
            s = mu_kinetic(bp, i, speed) * pf[i] / speed
            fx = s * vx
            fy = s * vy
        elif modes[i] == MODE_START:
            s = mu_kinetic(bp, i, speed) * pf[i]
            fx = s * dirs[i, 0]
            fy = s * dirs[i, 1]
        elif modes[i] == MODE_FREE:
            pass
        else:
            nst += 1
            ist = i
        if on[i] == 0.0:  # tensile: no normal-force terms
            fx = fy = 0.0
        Ff[i, 0] = fx
        Ff[i, 1] = fy
        cx = on[i] * (bp[i, B_RINV] * ux + fx)
        cy = on[i] * (bp[i, B_RINV] * uy + fy)
        cN[i, 0] = cx
        cN[i, 1] = cy
        bt2 = -Y * cx + X * cy
        for b in range(3):
            Am[0, b] += cx * n1[i, b]
            Am[1, b] += cy * n1[i, b]
            Am[2, b] += bt2 * n1[i, b]
        gx = f0x + n0[i] * cx
        gy = f0y + n0[i] * cy
        fv[0] -= gx
        fv[1] -= gy
        fv[2] -= -Y * gx + X * gy
    kap = sp[S_KAPPA]
    ws[19][0] = inertia_ratio(Am, M, pos, np.int64(nst), ist)
    if nst == 0:
        for a in range(3):
            qdd[a] = fv[a]
            for b in range(3):
                A3[a, b] = Am[a, b]
        if not lu_factor(A3, piv[:3], 1e-14):
            return ST_SINGULAR
        lu_solve(A3, piv[:3], qdd)
    elif nst == 1:
        X = pos[ist, 0]
        Y = pos[ist, 1]
        for a in range(5):
            r5[a] = fv[a] if a < 3 else 0.0
            for b in range(5):
                K5[a, b] = Am[a, b] if (a < 3 and b < 3) else 0.0
        # A q̈ + B_sᵀ τ = r,  B_s q̈ = −κ B_s q̇, the constraint rows and τ scaled by the mass
        # sc = M[0, 0] (else the Schur complement ~ 1/m falls below the LU's pivot floor)
        sc = M[0, 0]
        K5[0, 3] = sc
        K5[1, 4] = sc
        K5[2, 3] = -Y * sc
        K5[2, 4] = X * sc
        K5[3, 0] = sc
        K5[3, 2] = -Y * sc
        K5[4, 1] = sc
        K5[4, 2] = X * sc
        _, _, vx, vy = slip_kinematics(y, pos, ist)
        r5[3] = -kap * vx * sc
        r5[4] = -kap * vy * sc
        if not lu_factor(K5, piv, 1e-14):
            return ST_SINGULAR
        lu_solve(K5, piv, r5)
        for a in range(3):
            qdd[a] = r5[a]
        Ff[ist, 0] = r5[3] * sc
        Ff[ist, 1] = r5[4] * sc
    else:
        for a in range(3):
            qdd[a] = -kap * y[3 + a]
            for b in range(3):
                A3[a, b] = 0.0
        nfloor = 1e-9 * m * gz  # (a weight for an unloaded isolator: uplift is located later)
        for i in range(ni):
            if modes[i] == MODE_STICK:
                X = pos[i, 0]
                Y = pos[i, 1]
                wn = n0[i] + n1[i, 0] * qdd[0] + n1[i, 1] * qdd[1] + n1[i, 2] * qdd[2]
                wn = max(wn, nfloor)
                cN[i, 0] = wn  # (the stuck isolator's weight; cN is not read again)
                A3[0, 0] += wn
                A3[1, 1] += wn
                A3[0, 2] -= wn * Y
                A3[2, 0] -= wn * Y
                A3[1, 2] += wn * X
                A3[2, 1] += wn * X
                A3[2, 2] += wn * (X * X + Y * Y)
        for a in range(3):
            s = fv[a]
            for b in range(3):
                s -= Am[a, b] * qdd[b]
            r5[a] = s
        if not lu_factor(A3, piv[:3], 1e-14):
            return ST_SINGULAR
        lu_solve(A3, piv[:3], r5[:3])
        for i in range(ni):
            if modes[i] == MODE_STICK:
                Ff[i, 0] = cN[i, 0] * (r5[0] - pos[i, 1] * r5[2])
                Ff[i, 1] = cN[i, 0] * (r5[1] + pos[i, 0] * r5[2])
    for i in range(ni):
        Ni = n0[i] + n1[i, 0] * qdd[0] + n1[i, 1] * qdd[1] + n1[i, 2] * qdd[2]
        N[i] = Ni
        ux, uy, _, _ = slip_kinematics(y, pos, i)
        Fr[i, 0] = (on[i] * Ni * bp[i, B_RINV] + bp[i, B_KLAM]) * ux
        Fr[i, 1] = (on[i] * Ni * bp[i, B_RINV] + bp[i, B_KLAM]) * uy
        if law == LAW_ARCTAN or modes[i] != MODE_STICK:
            Ff[i, 0] *= Ni
            Ff[i, 1] *= Ni
    for a in range(3):
        if not math.isfinite(qdd[a]):
            return ST_SINGULAR
    return ST_OK


@njit(cache=True, error_model="numpy", inline="always")
def _det3(A):
    return (A[0, 0] * (A[1, 1] * A[2, 2] - A[1, 2] * A[2, 1])
            - A[0, 1] * (A[1, 0] * A[2, 2] - A[1, 2] * A[2, 0])
            + A[0, 2] * (A[1, 0] * A[2, 1] - A[1, 1] * A[2, 0]))  # fmt: skip


@njit(cache=True, error_model="numpy")
def inertia_ratio(Am, M, pos, nst, ist):
    """ρ: what is left of the deck's inertia once the normal forces' dependence on q̈ is in.

    Friction and pendulum forces proportional to N_i, with N_i affine in q̈, make the deck's
    effective mass Am = M + Σ B_iᵀ c_i n1_iᵀ (:func:`evaluate_at`). With every isolator
    slipping ρ = det Am / det M; with one stuck at (X, Y) the deck can only turn about it,
    n = (Y, −X, 1) (B_s n = 0), and ρ = nᵀ Am n / nᵀ M n; with two or more stuck it is held,
    ρ = 1. ρ = 1 without overturning (h = 0, or one isolator) and falls as the overturning
    gain (h/b)(μ + u/R) grows (b the bearings' lever); at ρ = 0 q̈ is unbounded and past it
    the equations have no solution continuing the motion (Painlevé's paradox)."""
    if nst == 0:
        return _det3(Am) / _det3(M)
    if nst == 1:
        nx = pos[ist, 1]
        ny = -pos[ist, 0]
        num = 0.0
        den = 0.0
        for a in range(3):
            na = nx if a == 0 else (ny if a == 1 else 1.0)
            for b in range(3):
                nb = nx if b == 0 else (ny if b == 1 else 1.0)
                num += na * Am[a, b] * nb
                den += na * M[a, b] * nb
        return num / den
    return 1.0


@ka.compiled_uncounted
def rhs(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out, dy):
    """First-order right-hand side dy = [q̇, q̈, ṡ] (ṡ: the internal slips of triple friction
    pendulums, after [q, q̇], when y has them); ``out = (qdd, N, Ff, Fr, Fo)`` filled."""
    qdd, N, Ff, Fr, Fo = out
    st = evaluate_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out)
    for a in range(3):
        dy[a] = y[3 + a]
        dy[3 + a] = qdd[a]
    if y.shape[0] > 6:  # the internal slips of triple friction pendulums
        sd = ws[10]
        for i in range(pos.shape[0]):
            if bp[i, B_KIND] == KIND_TFP:
                o = int(bp[i, B_IOFF])
                for j in range(8):
                    dy[o + j] = sd[i, j]
    return st


@ka.compiled_uncounted
def start_direction(i, tx, ty, mu_n, Am, pos, dirs, A3, piv, C):
    """Direction d_i in which a stuck isolator starts to slip when its stick force
    τ = (tx, ty) leaves the disc: the one in which it then accelerates (maximum dissipation).

    Released, the slip point accelerates by a = W (τ − μ N d) with W = B_i A⁻¹ B_iᵀ (A the
    deck's matrix ``Am`` of :func:`evaluate` with isolator i stuck); a ∥ d, a·d > 0 gives
    d = (λ W⁻¹ + μN I)⁻¹ τ with the λ >= 0 that makes |d| = 1 (|d| falls monotonically from
    |τ|/μN > 1 at λ = 0), found by bisection. A single mass (W = I/m) gives d = τ/|τ|.
    Writes ``dirs[i]``; ``A3`` (3 × 3), ``piv`` (3,) and ``C`` (2, 3) are its scratch."""
    X = pos[i, 0]
    Y = pos[i, 1]
    for a in range(3):
        piv[a] = 0
        for b in range(3):
            A3[a, b] = Am[a, b]
    tn = math.sqrt(tx * tx + ty * ty)
    if tn == 0.0:  # (no stick force, an unloaded isolator: any direction, its friction is 0)
        dirs[i, 0] = 1.0
        dirs[i, 1] = 0.0
        return
    if not lu_factor(A3, piv, 1e-14) or not mu_n > 0.0 or not tn > mu_n:
        dirs[i, 0] = tx / tn
        dirs[i, 1] = ty / tn
        return
    cx = C[0]
    cy = C[1]
    cx[0], cx[1], cx[2] = 1.0, 0.0, -Y
    cy[0], cy[1], cy[2] = 0.0, 1.0, X
    lu_solve(A3, piv, cx)
    lu_solve(A3, piv, cy)
    w11 = cx[0] - Y * cx[2]  # W = B A⁻¹ Bᵀ
    w21 = cx[1] + X * cx[2]
    w12 = cy[0] - Y * cy[2]
    w22 = cy[1] + X * cy[2]
    det = w11 * w22 - w12 * w21
    v11, v12, v21, v22 = w22 / det, -w12 / det, -w21 / det, w11 / det  # W⁻¹
    lo, hi = 0.0, 1.0 / (abs(w11) + abs(w22))
    dx = tx / tn
    dy = ty / tn
    for _ in range(200):  # grow hi until |d(hi)| < 1
        k11, k12, k21, k22 = hi * v11 + mu_n, hi * v12, hi * v21, hi * v22 + mu_n
        kd = k11 * k22 - k12 * k21
        ex = (k22 * tx - k12 * ty) / kd
        ey = (-k21 * tx + k11 * ty) / kd
        if ex * ex + ey * ey < 1.0:
            break
        lo = hi
        hi *= 2.0
    for _ in range(100):
        lam = 0.5 * (lo + hi)
        k11, k12, k21, k22 = lam * v11 + mu_n, lam * v12, lam * v21, lam * v22 + mu_n
        kd = k11 * k22 - k12 * k21
        ex = (k22 * tx - k12 * ty) / kd
        ey = (-k21 * tx + k11 * ty) / kd
        if ex * ex + ey * ey < 1.0:
            hi = lam
        else:
            lo = lam
            dx, dy = ex, ey
        if hi - lo <= 1e-15 * hi:
            break
    r = math.sqrt(dx * dx + dy * dy)
    dirs[i, 0] = dx / r
    dirs[i, 1] = dy / r
