"""Slip-start directions of a rigid deck's isolators released together (switch law).

Released at one event, isolators i start to slip along d_i; consistency asks each d_i to be
the direction of its slip point's acceleration a_i = B_i q̈ with every friction μ N_i d_i in
place (maximum dissipation). With the deck's accelerations x = q̈ as the unknowns this is
three equations,

    r(x) = x − q̈(d(x)) = 0,    d_i(x) = B_i x / |B_i x|,

q̈(d) the deck's accelerations evaluated with those directions. They are solved by Newton
with a forward-difference Jacobian (3 × 3) and a halving line search on max |r|, from the
translation of the accelerations of the directions the caller made (each from its own stick
force). The fixed-point passes d ← a/|a| solve the same equations but diverge at a
break-away: on a translating deck their gain is μΣN/(|F| − μΣN), 1.3 with μ_s = 0.07 and
μ = 0.04, and larger for the deck's turning; they left four equal isolators of a centred
deck slipping in four directions under a record along x. A translating deck's solution is
exact: every d_i along the load. When Newton fails (a singular Jacobian, no descent, an
evaluation that fails) the caller's directions are kept.
"""

import math

from numba import njit

from nsdyn import _kaddress as ka
from nsdyn._klinalg import lu_factor, lu_solve
from nsdyn.models.isolated import _kplane as kp

ALIGN_NEWTON = 30  # Newton steps at most
NEWTON_TOL = 1e-12  # converged: max |r| <= this times the accelerations' size
ALIGN_FD = 1e-7  # forward-difference step relative to the accelerations' size
ALIGN_HALVINGS = 30  # line-search halvings at most


@njit(cache=True, error_model="numpy")
def _size(x, R):
    """The accelerations' size: max(|ẍ|, |ÿ|, R |θ̈|) (R the isolators' largest radius)."""
    return max(abs(x[0]), abs(x[1]), R * abs(x[2]))


@ka.compiled_uncounted
def _residual(x, rr, t, y, modes, dirs, d0, M, pos, bp, nd, sp, gk, gp, tab, ws, out, R):
    """Directions d(x), then rr = x − q̈(d(x)); returns max |rr| in the units of
    :func:`_size`, or −1 where the evaluation fails."""
    qdd = out[0]
    for i in range(pos.shape[0]):
        if modes[i] == kp.MODE_START:
            ax = x[0] - pos[i, 1] * x[2]
            ay = x[1] + pos[i, 0] * x[2]
            an = math.sqrt(ax * ax + ay * ay)
            if an > 0.0:
                dirs[i, 0] = ax / an
                dirs[i, 1] = ay / an
            else:  # (no acceleration: the caller's direction)
                dirs[i, 0] = d0[i, 0]
                dirs[i, 1] = d0[i, 1]
    if kp.evaluate_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out) != kp.ST_OK:
        return -1.0
    for a in range(3):
        rr[a] = x[a] - qdd[a]
    return max(abs(rr[0]), abs(rr[1]), R * abs(rr[2]))


@ka.compiled_uncounted
def _newton(x, t, y, modes, dirs, d0, M, pos, bp, nd, sp, gk, gp, tab, ws, out, R):
    """Newton on r(x) = 0 from ``x`` (overwritten with the solution); True when solved, the
    directions then those of the solution."""
    J = ws[13]
    piv = ws[14]
    S = ws[18]
    r, rp, xt = S[1], S[2], S[3]
    nr = _residual(x, r, t, y, modes, dirs, d0, M, pos, bp, nd, sp, gk, gp, tab, ws, out, R)
    for _ in range(ALIGN_NEWTON):
        if nr < 0.0:
            return False
        scale = _size(x, R)
        if nr <= NEWTON_TOL * scale:
            return True
        for j in range(3):
            h = ALIGN_FD * scale / (R if j == 2 and R > 0.0 else 1.0)
            for a in range(3):
                xt[a] = x[a]
            xt[j] += h
            if _residual(xt, rp, t, y, modes, dirs, d0, M, pos, bp, nd, sp, gk, gp, tab, ws,
                         out, R) < 0.0:  # fmt: skip
                return False
            for a in range(3):
                J[a, j] = (rp[a] - r[a]) / h
        if not lu_factor(J, piv, 1e-14):
            return False
        for a in range(3):
            rp[a] = -r[a]
        lu_solve(J, piv, rp)  # the step, in rp
        lam = 1.0
        took = False
        for _ in range(ALIGN_HALVINGS):
            for a in range(3):
                xt[a] = x[a] + lam * rp[a]
            # (the trial's residual into J's first row: J is refactored before its next use)
            nt = _residual(xt, J[0], t, y, modes, dirs, d0, M, pos, bp, nd, sp, gk, gp, tab,
                           ws, out, R)  # fmt: skip
            if 0.0 <= nt < nr:
                for a in range(3):
                    x[a] = xt[a]
                    r[a] = J[0, a]
                nr = nt
                took = True
                break
            lam *= 0.5
        if not took:
            return False
    if 0.0 <= nr <= NEWTON_TOL * _size(x, R):
        _residual(x, r, t, y, modes, dirs, d0, M, pos, bp, nd, sp, gk, gp, tab, ws, out, R)
        return True
    return False


@ka.compiled_uncounted
def align(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out):
    """Align the slip-start directions (``dirs`` of the MODE_START isolators) as above;
    returns False only where the first evaluation fails. Scratch: ``ws[13]`` (the Jacobian),
    ``ws[14]`` (its pivots), ``ws[17]`` (the caller's directions), ``ws[18]`` (4 × 3).

    The equations may have several solutions (the deck turning one way or the other as well
    as translating, where the normal forces follow the accelerations): Newton starts from
    the caller's translation (θ̈ = 0) and takes the solution it reaches, the least turning
    near it; from the caller's accelerations only when that start fails."""
    ni = pos.shape[0]
    d0 = ws[17]
    x = ws[18][0]
    R = 0.0
    for i in range(ni):
        d0[i, 0] = dirs[i, 0]
        d0[i, 1] = dirs[i, 1]
        R = max(R, math.sqrt(pos[i, 0] ** 2 + pos[i, 1] ** 2))
    if kp.evaluate_t(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out) != kp.ST_OK:
        return False
    q0, q1, q2 = out[0][0], out[0][1], out[0][2]
    for turn in (0.0, 1.0):
        x[0], x[1], x[2] = q0, q1, turn * q2
        if _newton(x, t, y, modes, dirs, d0, M, pos, bp, nd, sp, gk, gp, tab, ws, out, R):
            return True
    for i in range(ni):  # not solved: the caller's directions
        dirs[i, 0] = d0[i, 0]
        dirs[i, 1] = d0[i, 1]
    return True


@ka.compiled_uncounted
def starts(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out):
    """Slip-start directions consistent with the deck's motion when several are released
    together (:func:`align`); False only where the evaluation fails. One released alone is
    left as :func:`kp.start_direction` made it (exact), as are the starts of a deck that two
    stuck isolators hold (their slip points do not move)."""
    nst = 0
    nsl = 0
    for i in range(pos.shape[0]):
        if modes[i] == kp.MODE_STICK:
            nst += 1
        elif modes[i] == kp.MODE_START:
            nsl += 1
    if nsl < 2 or nst >= 2:  # none to align, one (consistent), or a held deck
        return True
    return align(t, y, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, ws, out)
