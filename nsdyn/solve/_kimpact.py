"""Landing of an isolator contact: Newton's impact law through the generalised mass matrix.

At the touchdown of contact ``k`` the velocities jump by an impulse on the contact rows ``S``
that are closed after the impact (frictionless in the normal direction)::

    qd+ = qd- + M^-1 R_S^T Lam,    R_j qd+ = -e_j R_j qd-   (landing j; 0 for the others)

with ``e_j = e`` (0 by default: a plastic landing) and ``e_j = 0`` for landings slower than
``V_REST``. The set is active: a closed contact whose impulse would pull (``Lam_j < 0``) opens,
except at a landing slower than ``V_REST`` (a rest landing: every contact at the ground keeps
``v+ = 0``, a small tensile impulse allowed, which ends Zeno bouncing).
The kinetic energy change ``dT = Lam . R_S (qd- + qd+) / 2 <= 0`` (0 <= e <= 1) is accumulated,
and every event is appended to the contact log (columns ``t, contact, kind, v-, impulse``).

Contact set at rest (:func:`_settle_contacts`): over the contacts at the ground with zero
normal velocity, the acceleration-level complementarity problem
``lam_k >= 0, R_k qdd + b_k >= 0, lam_k (R_k qdd + b_k) = 0`` (``b_k`` the Baumgarte terms).

Contact events on a step's dense output (:func:`_detect`, for the event-driven loop of
:mod:`nsdyn.solve._kunilateral`): a closed contact lifts off where ``lam_k`` crosses zero
downwards, an open one lands where its gap ``g_k = R_k q`` does (scanned at a few points of the
step, split at the extrema of the cubic gap, located by Illinois).
"""

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn._klinalg import copy_vec, lu_factor, lu_solve
from nsdyn.models.isolated import _kernel as ks
from nsdyn.solve import _kcommon as ki
from nsdyn.solve import _kevent as ke
from nsdyn.solve import _kradau as kr

KIND_LIFT = 2  # event kinds beside _kevent's 0 (slip -> stick/reversal) and 1 (stick -> slip)
KIND_LAND = 3
V_REST = 1e-3  # m/s, landings slower than this are plastic whatever e (ends Zeno bouncing)
V_SEP = 1e-6  # m/s, a landed contact separating faster than this rebounds (opens)
G_REST = 1e-6  # m, at such a landing open contacts this close to the ground land with it
CLOG_COLS = 5  # contact log columns: t, contact, kind, normal velocity before, impulse
LAM_RTOL = 1e-9  # normal forces above -LAM_RTOL x the static ones count as zero (no lift-off)
ACC_ATOL = 1e-8  # m/s^2, gap accelerations above -ACC_ATOL count as zero (a contact at rest)
LCP_MAXITER = 64  # pivots of the acceleration-level contact problem before giving up
SAMPLES = 8  # dense-output samples per step scanned for a lift-off (lam_k sign change)


@njit(cache=True, error_model="numpy")
def _log(clog, cnt, t, k, kind, v, imp):
    """Append a contact event; False when the log is full."""
    i = cnt[0]
    if i >= clog.shape[0]:
        return False
    clog[i, 0], clog[i, 1], clog[i, 2], clog[i, 3], clog[i, 4] = t, k, kind, v, imp
    cnt[0] += 1
    return True


@ka.compiled_only
def _land(t, y, P, k, e_rest, g_tol, clog, cnt, dT):
    """Impact at the touchdown of contact k: velocities of ``y`` jump, contacts close or open.

    A small linear complementarity problem solved by active sets over the contacts at the
    ground (closed ones, k, open ones with g <= g_tol): an active contact whose impulse
    would pull opens, an inactive one the impulse drives into the ground joins. A landing
    slower than V_REST is a rest landing: open contacts with g <= G_REST join and every
    contact at the ground ends with v+ = 0 (this ends Zeno bouncing and rocking).
    ``dT[0]`` += the kinetic energy change. False when the log is full or the system singular.
    """
    R, MiRt = P[ks.I_R], P[ks.I_MIRT]
    opn = P[ks.I_OPEN]
    nc, n = R.shape[0], R.shape[1]
    vm = np.empty(nc)
    was = opn.copy()
    cand = np.zeros(nc, dtype=np.bool_)
    for j in range(nc):
        vm[j] = ke._dot_row(R, j, y, n)
    # a landing slower than V_REST ends the motion normal to the ground (Zeno bouncing or
    # rocking, the pivot included): every contact at the ground keeps v+ = 0, even one whose
    # impulse pulls (a tensile impulse of at most ~ V_REST x the effective mass)
    rest = abs(vm[k]) <= V_REST
    g_near = G_REST if rest else g_tol
    for j in range(nc):
        cand[j] = opn[j] == 0 or j == k or ke._dot_row(R, j, y, np.int64(0)) <= g_near
    opn[k] = 0
    lamI = np.zeros(nc)
    vp = vm.copy()
    for _ in range(2 * nc + 2):
        idx = np.flatnonzero(opn == 0)
        m = idx.shape[0]
        A = np.empty((m, m))
        rhs = np.empty(m)
        for a in range(m):
            ja = idx[a]
            e = e_rest if abs(vm[ja]) > V_REST else 0.0
            rhs[a] = -vm[ja] - e * min(vm[ja], 0.0)
            for b in range(m):
                acc = 0.0
                for c in range(n):
                    acc += R[ja, c] * MiRt[c, idx[b]]
                A[a, b] = acc
        piv = np.empty(m, dtype=np.int64)
        if m and not lu_factor(A, piv, 1e-13):
            return False
        if m:
            lu_solve(A, piv, rhs)
        lamI[:] = 0.0
        worst, wv = -1, 0.0
        for a in range(m):
            lamI[idx[a]] = rhs[a]
            if rhs[a] < wv:
                worst, wv = idx[a], rhs[a]
        if worst >= 0 and not rest:
            opn[worst] = 1  # pulling: this contact leaves the ground at the impact
            continue
        for j in range(nc):  # normal velocities after the impulse
            vp[j] = vm[j]
            for i in range(nc):
                if lamI[i] != 0.0:
                    for c in range(n):
                        vp[j] += R[j, c] * MiRt[c, i] * lamI[i]
        worst, wv = -1, -g_tol * 1e-3  # penetration speeds below this are round-off
        for j in range(nc):
            if cand[j] and opn[j] != 0 and vp[j] < wv:
                worst, wv = j, vp[j]
        if worst < 0:
            break
        opn[worst] = 0  # driven into the ground: joins
    for j in range(nc):
        if lamI[j] != 0.0:
            for c in range(n):
                y[n + c] += MiRt[c, j] * lamI[j]
    for j in range(nc):
        vpj = ke._dot_row(R, j, y, n)
        dT[0] += 0.5 * lamI[j] * (vm[j] + vpj)
        landed = was[j] != 0 and (opn[j] == 0 or lamI[j] != 0.0)
        if opn[j] == 0 and vpj > V_SEP:
            opn[j] = 1  # rebounds (e > 0): leaves the ground at once
        ok = True
        if landed:
            ok = _log(clog, cnt, t, j, np.int64(KIND_LAND), vm[j], lamI[j])
        if ok and opn[j] != 0 and (was[j] == 0 or landed):
            ok = _log(clog, cnt, t, j, np.int64(KIND_LIFT), vpj, 0.0)
        if not ok:
            return False
    return True


@njit(cache=True, error_model="numpy")
def _lam_scale(P):
    s = 1.0
    for v in P[ks.I_LAM0]:
        s = max(s, abs(v))
    return LAM_RTOL * s


@njit(cache=True, error_model="numpy")
def _baumgarte(P, k, y):
    """2 alpha beta R_k qd + alpha^2 R_k q: the closed row's stabilising terms at (q, qd)."""
    fp = P[ks.I_FPAR]
    n = y.shape[0] // 2
    al, be = fp[ks.F_ALPHA], fp[ks.F_BETA]
    R = P[ks.I_R]
    return 2.0 * al * be * ke._dot_row(R, k, y, n) + al * al * ke._dot_row(R, k, y, np.int64(0))


@ka.compiled_only
def _settle_contacts(t, y, P, f, ew, g_tol, clog, cnt, stats, lift):
    """Consistent contact set at (t, y): the acceleration-level complementarity problem over
    the contacts at rest at the ground (closed ones, and open ones with g_k <= g_tol and
    |R_k qd| <= V_SEP, except those that lifted off at this instant: ``lift[0, k]`` is the last
    lift-off time of contact k, ``lift[1, k] = min(g_k, 0)`` its gap then; updated here)::

        lam_k >= 0,  a_k = R_k qdd >= 0,  lam_k a_k = 0

    (``a_k`` plus the Baumgarte terms ``2 alpha beta R_k qd + alpha^2 R_k q``, so that an open
    contact is compared with what its closed row would impose) solved by Murty's least-index
    principal pivoting, each trial set evaluated by the right-hand side: the first contact in
    index order that violates its condition (closed with lam_k < 0: opens; open with a_k < 0:
    closes) flips, until none does. The Delassus matrix R M^-1 R^T is positive definite, so the
    pivoting terminates at the unique solution. Returns (ok, changed).

    Contacts that lifted off at this instant (within ``BURST_DT``) stay open: at a lift-off
    lam_k = 0 and a_k = 0 (the problem is degenerate there; only the sign of d lam_k / dt,
    negative at the located crossing, says that the contact separates), and
    the Baumgarte terms of a gap drifted a hair below zero would read as a pull into the
    ground and close it at once. Two contacts reaching lam = 0 together (a symmetric frame
    under vertical shaking) would otherwise close each other in turn without end. If one
    should not have opened, its gap sinks and the touchdown scan lands it."""
    qdd, lam, tau, modes = ew[2:6]
    opn = P[ks.I_OPEN]
    R = P[ks.I_R]
    nc = opn.shape[0]
    n = y.shape[0] // 2
    lam_tol = _lam_scale(P)
    ground = np.zeros(nc, dtype=np.bool_)
    for k in range(nc):
        ground[k] = opn[k] == 0 or (
            t - lift[0, k] > ke.BURST_DT
            and ke._dot_row(R, k, y, np.int64(0)) <= g_tol
            and abs(ke._dot_row(R, k, y, n)) <= V_SEP
        )
    changed = False
    for _ in range(LCP_MAXITER):
        ki.feval_t(t, y, P, f, qdd, lam, tau, modes)
        stats[ki.S_NFEV] += 1
        flip = -1
        for k in range(nc):
            if not ground[k]:
                continue
            if opn[k] == 0 and lam[k] < -lam_tol:
                flip = k
                break
            if (
                opn[k] != 0
                and ke._dot_row(R, k, qdd, np.int64(0)) + _baumgarte(P, k, y) < -ACC_ATOL
            ):
                flip = k
                break
        if flip < 0:
            return True, changed
        kind = KIND_LAND if opn[flip] != 0 else KIND_LIFT
        opn[flip] = 1 - opn[flip]
        if kind == KIND_LIFT:
            lift[0, flip] = t
            lift[1, flip] = min(ke._dot_row(R, flip, y, np.int64(0)), 0.0)
        changed = True
        if not _log(clog, cnt, t, flip, kind, ke._dot_row(R, flip, y, n), 0.0):
            return False, changed
    return False, changed


@njit(cache=True, error_model="numpy")
def _gap_dense(k, x, y, Qd, P):
    """g_k = R_k q on the dense output at t + x h (cubic in x)."""
    R = P[ks.I_R]
    g = 0.0
    for j in range(R.shape[1]):
        g += R[k, j] * (y[j] + x * (Qd[j, 0] + x * (Qd[j, 1] + x * Qd[j, 2])))
    return g


@njit(cache=True, error_model="numpy")
def _g(kind, k, x, y, Qd, t, h, P, ew, off, stats):
    """Switching function of contact k at t + x h: lam_k (closed) or g_k + off (open)."""
    if kind == KIND_LAND:
        return _gap_dense(k, x, y, Qd, P) + off
    ys, fs, qdd, lam, tau, modes = ew[:6]
    kr.dense(y, Qd, x, ys)
    ki.feval_t(t + x * h, ys, P, fs, qdd, lam, tau, modes)
    stats[ki.S_NFEV] += 1
    return lam[k]


@njit(cache=True, error_model="numpy")
def _root(kind, k, a, b, fa, fb, y, Qd, t, h, P, ew, off, stats):
    """Illinois on x in [a, b] for fa > 0 >= fb; returns x with g(x) <= 0."""
    xtol = ke.EVENT_TTOL / h
    side = np.int64(0)
    for _ in range(ke.ROOT_MAXITER):
        if b - a <= xtol:
            break
        c = ke.illinois_point(a, b, fa, fb)
        fc = _g(kind, k, c, y, Qd, t, h, P, ew, off, stats)
        a, b, fa, fb, side, done = ke.illinois_step(a, b, fa, fb, c, fc, side)
        if done:
            return c
    return b


@njit(cache=True, error_model="numpy")
def _monotone_breaks(k, Qd, P, xs):
    """0, the extrema of the cubic gap g_k(x) inside (0, 1) in order, 1 into ``xs``; count."""
    R = P[ks.I_R]
    b1 = b2 = b3 = 0.0
    for j in range(R.shape[1]):
        b1 += R[k, j] * Qd[j, 0]
        b2 += R[k, j] * Qd[j, 1]
        b3 += R[k, j] * Qd[j, 2]
    # g'(x) = b1 + 2 b2 x + 3 b3 x^2
    nx = 1
    xs[0] = 0.0
    r0, r1 = 2.0, 2.0
    if b3 != 0.0:
        disc = b2 * b2 - 3.0 * b3 * b1
        if disc > 0.0:
            qq = -(b2 + np.copysign(np.sqrt(disc), b2))
            r0 = qq / (3.0 * b3)
            r1 = b1 / qq if qq != 0.0 else 2.0
    elif b2 != 0.0:
        r0 = -b1 / (2.0 * b2)
    if r1 < r0:
        r0, r1 = r1, r0
    for r in (r0, r1):
        if 0.0 < r < 1.0:
            xs[nx] = r
            nx += 1
    xs[nx] = 1.0
    return nx + 1


@ka.compiled_only
def _detect(t, h, y, Qd, P, ew, g_tol, g_lift, x_max, stats):
    """Earliest contact event in the step before ``x_max``: (x, contact, kind), contact -1
    when none. Leaves lam, tau at the step end.

    An open contact's gap is measured from ``g_lift[k] = min(g_k, 0)`` at its lift-off: a gap
    that the constraint stabilisation left a hair below zero when the contact opened is drift,
    not penetration, and must not read as an immediate touchdown."""
    nc = P[ks.I_R].shape[0]
    opn = P[ks.I_OPEN]
    lam_tol = _lam_scale(P)
    x_best, k_best, kind_best = 2.0, -1, 0
    any_closed = False
    xs = np.empty(4)
    for k in range(nc):
        if opn[k] == 0:
            any_closed = True
            continue
        # the gap is a cubic in x on the step: split [0, 1] at its extrema into monotone
        # pieces, so that a flight shorter than the step (a small bounce) is never skipped
        nx = _monotone_breaks(k, Qd, P, xs)
        g0 = g_lift[k]
        xa, ga = 0.0, _gap_dense(k, 0.0, y, Qd, P) - g0
        for s in range(1, nx):
            xb = xs[s]
            if xa >= x_best:
                break
            gb = _gap_dense(k, xb, y, Qd, P) - g0
            # a crossing from above, or sinking below the noise band (not a contact that
            # opened a hair below zero and rises)
            if gb <= 0.0 and (ga > g_tol or (gb < -g_tol and gb < ga)):
                if ga > 0.0:
                    xr = _root(
                        np.int64(KIND_LAND), k, xa, xb, ga, gb, y, Qd, t, h, P, ew, -g0, stats
                    )
                elif ga > -g_tol:  # starts in the noise band: touchdown where it leaves it
                    xr = _root(
                        np.int64(KIND_LAND),
                        k,
                        xa,
                        xb,
                        ga + g_tol,
                        gb + g_tol,
                        y,
                        Qd,
                        t,
                        h,
                        P,
                        ew,
                        g_tol - g0,
                        stats,
                    )
                else:
                    xr = xa
                if xr < x_best:
                    x_best, k_best, kind_best = xr, k, KIND_LAND
                break
            xa, ga = xb, gb
    if any_closed:
        ys, fs, qdd, lam, tau, modes = ew[:6]
        la = np.empty(nc)
        ki.feval_t(t, y, P, fs, qdd, lam, tau, modes)
        stats[ki.S_NFEV] += 1
        copy_vec(la, lam)
        xa = 0.0
        for s in range(1, SAMPLES // 2 + 1):
            xb = s / (SAMPLES // 2)
            if xb >= x_best:
                break
            kr.dense(y, Qd, xb, ys)
            ki.feval_t(t + xb * h, ys, P, fs, qdd, lam, tau, modes)
            stats[ki.S_NFEV] += 1
            lb = lam.copy()
            for k in range(nc):
                if opn[k] == 0 and lb[k] < 0.0 and (la[k] > lam_tol or lb[k] < -lam_tol):
                    xr = xa
                    if la[k] > 0.0:
                        xr = _root(
                            np.int64(KIND_LIFT),
                            k,
                            xa,
                            xb,
                            la[k],
                            lb[k],
                            y,
                            Qd,
                            t,
                            h,
                            P,
                            ew,
                            0.0,
                            stats,
                        )
                    if xr < x_best:
                        x_best, k_best, kind_best = xr, k, KIND_LIFT
            if k_best >= 0 and kind_best == KIND_LIFT:
                break
            copy_vec(la, lb)
            xa = xb
        kr.dense(y, Qd, 1.0, ys)
        ki.feval_t(t + h, ys, P, fs, qdd, lam, tau, modes)
        stats[ki.S_NFEV] += 1
    return x_best, k_best, kind_best
