"""Generalized-alpha family (Chung & Hulbert 1993) on ``qdd = a(t, q, qd)``, fixed step.

With ``M = I`` after the kernel's ``M^-1`` (the accelerations ``a`` already contain the
contact and friction forces), one step from (q_n, v_n, a_n) solves for a_{n+1}::

    (1 - am) a_{n+1} + am a_n = a(t_{n+1-af}, q_{n+1-af}, v_{n+1-af})
    q_{n+1} = q_n + dt v_n + dt^2 ((1/2 - beta) a_n + beta a_{n+1})
    v_{n+1} = v_n + dt ((1 - gamma) a_n + gamma a_{n+1})
    x_{n+1-af} = (1 - af) x_{n+1} + af x_n

by Newton with the Jacobian blocks Jq = da/dq, Jv = da/dqd of
:func:`nsdyn.models.isolated._kernel.jac` and a backtracking line search on |r| (the arctan
law makes plain Newton overshoot when a step crosses the sliding-velocity reversal)::

    S = (1 - am) I - (1 - af) (beta dt^2 Jq + gamma dt Jv)

Parameter choices (AMfe style; :func:`parameters`): generalized-alpha, HHT-alpha (am = 0) and
Newmark (am = af = 0) from the spectral radius at infinity rho_inf (HHT-alpha for rho_inf in
[1/2, 1] only, the others in [0, 1]). All are second-order
accurate except Newmark with rho_inf < 1. The Jacobian and its LU are kept across steps while
the iteration contracts fast and refreshed at the current iterate when it does not.
Outputs between steps are cubic Hermite interpolants (q from q, v; v from v, a).

The system kernel and its Jacobian are called by their addresses in the table of
:mod:`nsdyn._kaddress` (:func:`nsdyn.solve._kcommon.feval_t`; :func:`genalpha` fills it
before it calls the loop, :func:`genalpha_loop`): the loop's code holds none of theirs, so a
first run compiles it beside them.
"""

import numpy as np
from numba import njit

from nsdyn import _kborrow as kb
from nsdyn._klinalg import copy_vec
from nsdyn.models.isolated import _kernel as ks
from nsdyn.solve import _kcommon as ki

NEWTON_MAXITER = 25  # Newton iterations per step
NEWTON_TOL = 1e-3  # converged when the scaled state change of a correction is below this
LS_MAXITER = 12  # backtracking halvings of a Newton correction (line search on |r|)
LS_ARMIJO = 1e-4  # sufficient decrease of |r| a trial step must achieve
JAC_RATE = 0.25  # new Jacobian at the next iterate when |r| contracts slower than this
REUSE_ITERS = 2  # keep J for the next step if the step converged in this many iterations

FAMILY_GENALPHA, FAMILY_HHT, FAMILY_NEWMARK = 0, 1, 2


def parameters(family: int, rho_inf: float) -> tuple[float, float, float, float]:
    """(alpha_m, alpha_f, beta, gamma) of a member of the family from rho_inf in [0, 1].

    genalpha: Chung & Hulbert (1993), eq. (25): am = (2 rho - 1)/(rho + 1), af = rho/(rho + 1).
    hht: Hilber, Hughes & Taylor (1977), am = 0, af = (1 - rho)/(1 + rho), rho in [1/2, 1].
    newmark: am = af = 0, gamma = 1/2 + a, beta = (1 + a)^2 / 4 with a = (1 - rho)/(1 + rho)
    (rho = 1: average acceleration, second order; rho < 1: first order, dissipative).
    """
    r = float(rho_inf)
    if not 0.0 <= r <= 1.0:
        raise ValueError(f"rho_inf: expected a value in [0, 1], got {rho_inf}")
    if family == FAMILY_GENALPHA:
        am = (2.0 * r - 1.0) / (r + 1.0)
        af = r / (r + 1.0)
        gamma = 0.5 - am + af
        beta = 0.25 * (1.0 - am + af) ** 2
    elif family == FAMILY_HHT:
        if r < 0.5:
            raise ValueError(f"rho_inf: HHT-alpha needs rho_inf in [1/2, 1], got {rho_inf}")
        am = 0.0
        af = (1.0 - r) / (1.0 + r)
        gamma = 0.5 + af
        beta = 0.25 * (1.0 + af) ** 2
    else:
        a = (1.0 - r) / (1.0 + r)
        am = af = 0.0
        gamma = 0.5 + a
        beta = 0.25 * (1.0 + a) ** 2
    return am, af, beta, gamma


@njit(cache=True, error_model="numpy")
def _hermite(t, dt, q0, v0, a0, q1, v1, a1, tout, out):
    n = q0.shape[0]
    s = (tout - t) / dt
    h00 = (1.0 + 2.0 * s) * (1.0 - s) ** 2
    h10 = s * (1.0 - s) ** 2
    h01 = s * s * (3.0 - 2.0 * s)
    h11 = s * s * (s - 1.0)
    for i in range(n):
        out[i] = h00 * q0[i] + h10 * dt * v0[i] + h01 * q1[i] + h11 * dt * v1[i]
        out[n + i] = h00 * v0[i] + h10 * dt * a0[i] + h01 * v1[i] + h11 * dt * a1[i]


@njit(cache=True, error_model="numpy")
def _update(h, q, v, a, an, beta, gamma, qn, vn):
    """Newmark update: q_{n+1}, v_{n+1} into qn, vn from (q, v, a)_n and a_{n+1} = an."""
    for i in range(q.shape[0]):
        qn[i] = q[i] + h * v[i] + h * h * ((0.5 - beta) * a[i] + beta * an[i])
        vn[i] = v[i] + h * ((1.0 - gamma) * a[i] + gamma * an[i])


@njit(cache=True, error_model="numpy")
def _residual(ta, h, q, v, a, an, coef, P, gw):
    """Balance residual r(a_{n+1}) at the alpha point; returns (|r|_2 or inf, ok).

    ``coef = (am, af, beta, gamma)``; ``gw = (qn, vn, xa, fa, r, qdd, lam, tau, modes)``:
    out q_{n+1}, v_{n+1}, the alpha-point state and its right-hand side, the residual, and
    the outputs of the system kernel there."""
    am, af, beta, gamma = coef
    qn, vn, xa, fa, r, qdd, lam, tau, modes = gw
    n = q.shape[0]
    _update(h, q, v, a, an, beta, gamma, qn, vn)
    for i in range(n):
        xa[i] = (1.0 - af) * qn[i] + af * q[i]
        xa[n + i] = (1.0 - af) * vn[i] + af * v[i]
    ok = ki.feval_t(ta, xa, P, fa, qdd, lam, tau, modes)
    if not ki.all_finite(fa):
        return np.inf, True
    s = 0.0
    for i in range(n):
        r[i] = (1.0 - am) * an[i] + am * a[i] - fa[n + i]
        s += r[i] * r[i]
    return np.sqrt(s), ok


@njit(cache=True, error_model="numpy")
def _iteration_matrix(ta, h, coef, P, gw, J, S, piv, t, stats, rinfo):
    """S = (1 - am) I - (1 - af)(beta h^2 Jq + gamma h Jv) with the Jacobian at the alpha
    point ``gw[2]``, LU in place. Returns False (status ST_LU_SINGULAR at t) when singular."""
    am, af, beta, gamma = coef
    n = S.shape[0]
    stats[ki.S_NJEV] += 1
    stats[ki.S_NLU] += 1
    ki.jeval_t(ta, gw[2], P, J)
    c1 = (1.0 - af) * beta * h * h
    c2 = (1.0 - af) * gamma * h
    for i in range(n):
        for j in range(n):
            S[i, j] = -(c1 * J[n + i, j] + c2 * J[n + i, n + j])
        S[i, i] += 1.0 - am
    if ki.lu_factor(S, piv, 0.0):
        return True
    stats[ki.S_STATUS] = ki.ST_LU_SINGULAR
    rinfo[ki.R_T] = t
    return False


@njit(cache=True, error_model="numpy")
def _below_resolution(d, h, q, v, a, an, beta, gamma):
    """True when a correction d changes q_{n+1}, v_{n+1} by less than the rounding of their
    update formulas: no further decrease of |r| is possible in double precision (huge
    w dt, where a ~ w^2 q and the Newmark update cancels large terms)."""
    c = 8.0 * 2.220446049250313e-16
    for i in range(d.shape[0]):
        sq = abs(q[i]) + h * abs(v[i]) + h * h * (abs(0.5 - beta) * abs(a[i]) + beta * abs(an[i]))
        sv = abs(v[i]) + h * (abs(1.0 - gamma) * abs(a[i]) + gamma * abs(an[i]))
        if beta * h * h * abs(d[i]) > c * sq or gamma * h * abs(d[i]) > c * sv:
            return False
    return True


@njit(cache=True, error_model="numpy")
def _increment_norm(d, h, beta, gamma, qn, vn, atol, rtol):
    """Scaled RMS of the state change (beta h^2 d, gamma h d) a Newton correction d causes."""
    n = d.shape[0]
    s = 0.0
    for i in range(n):
        s += (beta * h * h * d[i] / (atol[i] + rtol * abs(qn[i]))) ** 2
        s += (gamma * h * d[i] / (atol[n + i] + rtol * abs(vn[i]))) ** 2
    return np.sqrt(s / (2 * n))


def genalpha(P, x0, t_eval, atol, rtol, dt, coef, max_steps, uplift_mode, X, upl_t, acc=None):
    """:func:`genalpha_loop` with the address table filled and ``P``, ``x0`` in the declared
    form of the kernels it calls by address (:func:`nsdyn.solve.compile_split.system_inputs`;
    a plain Python function: a call of the loop itself would find the table empty).
    ``acc``: the algorithmic acceleration in and out (:func:`genalpha_loop`); None starts from
    the acceleration of the equations of motion."""
    from nsdyn.solve.compile_split import system_inputs  # (it imports this module)

    P, x0 = system_inputs(P, x0)
    if acc is None:
        acc = np.full(x0.shape[0] // 2, np.nan)
    return genalpha_loop(P, x0, t_eval, atol, rtol, dt, coef, max_steps, uplift_mode, X, upl_t, acc)


@njit(cache=True, error_model="numpy", nogil=True)  # (a watched chunk: checkpoint.held_call)
def genalpha_loop(P, x0, t_eval, atol, rtol, dt, coef, max_steps, uplift_mode, X, upl_t, acc):
    """Fixed-step generalized-alpha from ``t_eval[0]`` to ``t_eval[-1]``; state at t_eval in X.

    ``coef = (am, af, beta, gamma)`` (:func:`parameters`). Returns (stats, rinfo) as
    :func:`nsdyn.solve._kdopri.dopri5`; ``rinfo[R_RES]`` is the scaled Newton increment of the
    failing step.

    ``acc`` (n,): the algorithmic acceleration a_n to start from, and on return the one of the
    last step taken. It is not the acceleration of the equations of motion at t_n (their
    weighted mean at the alpha point is), so a run continued in pieces carries it: a piece
    started from q̈(t_n) instead departs from the run in one piece by O(h²) (1e-5 relative at
    5 ms on the default scene). NaN in ``acc[0]`` starts from q̈(t_0).
    """
    am, af, beta, gamma = coef
    n2 = x0.shape[0]
    n = n2 // 2
    nc = upl_t.shape[0]
    nt = t_eval.shape[0]
    stats = np.zeros(ki.N_STATS, dtype=np.int64)
    rinfo = np.zeros(ki.N_RINFO)
    q = x0[:n].copy()
    v = x0[n:].copy()
    a = np.empty(n)
    an = np.empty(n)
    xe = np.empty(n2)  # state at the step end
    fe = np.empty(n2)
    d = np.empty(n)
    a_old = np.empty(n)
    J = np.empty((n2, n2))
    S = np.empty((n, n))
    piv = np.empty(n, dtype=np.int64)
    qdd, lam, tau, modes = ks.outputs(P)
    lam_old = np.empty(nc)
    # q_{n+1}, v_{n+1}, the state at the alpha point and its right-hand side, the residual
    gw = (np.empty(n), np.empty(n), np.empty(n2), np.empty(n2), np.empty(n), qdd, lam, tau, modes)
    # the loop works on borrowed views (nsdyn._kborrow) of these and of its arguments: no
    # atomic reference counts for the arrays each step passes on; the owned stats/rinfo return
    own = (stats, rinfo, q, v, a, an, xe, fe, d, a_old, J, S, piv, lam_old, gw)
    stats, rinfo, q, v, a, an, xe, fe, d, a_old, J, S, piv, lam_old, gw = kb.borrowed(own)
    qdd, lam, tau, modes = gw[5], gw[6], gw[7], gw[8]
    P = kb.borrowed(P)
    x0, t_eval, atol, X, upl_t = kb.borrowed((x0, t_eval, atol, X, upl_t))
    qn, vn, r = gw[0], gw[1], gw[4]
    t0 = t_eval[0]
    t_end = t_eval[-1]
    t = t0
    rinfo[ki.R_T] = t
    rinfo[ki.R_H] = dt
    rinfo[ki.R_HNEXT] = dt
    ok = ki.feval_t(t, x0, P, fe, qdd, lam, tau, modes)  # (ki.start, by address)
    iout = ki.start_from(ok, t, x0, fe, lam, t_eval, X, lam_old, upl_t, uplift_mode, stats, rinfo)
    if iout < 0:
        return own[0], own[1]
    if np.isnan(acc[0]):
        copy_vec(a, qdd)
    else:
        copy_vec(a, acc)
    have_lu = False
    h_lu = 0.0
    k = 0
    while iout < nt:
        if stats[ki.S_NSTEP] >= max_steps:
            stats[ki.S_STATUS] = ki.ST_MAX_STEPS
            break
        t_new = t0 + (k + 1) * dt
        if t_new > t_end - 1e-9 * dt:
            t_new = t_end
        h = t_new - t
        ta = t + (1.0 - af) * h
        # predictor: constant acceleration; Newton with a backtracking line search on |r|
        copy_vec(an, a)
        rn, ok = _residual(ta, h, q, v, a, an, coef, P, gw)
        stats[ki.S_NFEV] += 1
        if not ok:
            stats[ki.S_STATUS] = ki.ST_SINGULAR
            rinfo[ki.R_T] = t
            return own[0], own[1]
        converged = False
        fresh = False
        dw = np.inf
        n_it = 0
        for _ in range(NEWTON_MAXITER):
            n_it += 1
            if not np.isfinite(rn):
                break
            if not have_lu or abs(h_lu - h) > 1e-12 * h:
                if not _iteration_matrix(ta, h, coef, P, gw, J, S, piv, t, stats, rinfo):
                    return own[0], own[1]
                have_lu = True
                h_lu = h
                fresh = True
            copy_vec(d, r)
            ki.lu_solve(S, piv, d)
            dw = _increment_norm(d, h, beta, gamma, qn, vn, atol, rtol)
            if not np.isfinite(dw):
                break
            if dw <= NEWTON_TOL or _below_resolution(d, h, q, v, a, an, beta, gamma):
                an -= d
                converged = True
                break
            copy_vec(a_old, an)
            r0 = rn
            step = 1.0
            for _ in range(LS_MAXITER):
                for i in range(n):
                    an[i] = a_old[i] - step * d[i]
                rn, ok = _residual(ta, h, q, v, a, an, coef, P, gw)
                stats[ki.S_NFEV] += 1
                if rn <= (1.0 - LS_ARMIJO * step) * r0:
                    break
                if not fresh:
                    # stale Jacobian: refresh it at the current iterate, restart the search
                    copy_vec(an, a_old)
                    rn, ok = _residual(ta, h, q, v, a, an, coef, P, gw)
                    stats[ki.S_NFEV] += 1
                    if not _iteration_matrix(ta, h, coef, P, gw, J, S, piv, t, stats, rinfo):
                        return own[0], own[1]
                    fresh = True
                    copy_vec(d, r)
                    ki.lu_solve(S, piv, d)
                    step = 1.0
                    continue
                step *= 0.5
            if rn > JAC_RATE * r0:
                have_lu = False  # slow contraction: Jacobian at the new iterate (full Newton)
                fresh = False
        if not converged:
            rinfo[ki.R_T] = t
            rinfo[ki.R_H] = h
            rinfo[ki.R_RES] = dw
            nonfin = not (ki.all_finite(an) and np.isfinite(dw))
            stats[ki.S_STATUS] = ki.ST_NONFINITE if nonfin else ki.ST_NEWTON
            break
        if n_it > REUSE_ITERS:
            have_lu = False
        _update(h, q, v, a, an, beta, gamma, qn, vn)
        copy_vec(xe[:n], qn)
        copy_vec(xe[n:], vn)
        ok = ki.feval_t(t_new, xe, P, fe, qdd, lam, tau, modes)
        stats[ki.S_NFEV] += 1
        if not (ki.all_finite(xe) and ki.all_finite(fe)):
            stats[ki.S_STATUS] = ki.ST_NONFINITE
            rinfo[ki.R_T] = t
            break
        while iout < nt and t_eval[iout] <= t_new:
            _hermite(t, h, q, v, a, qn, vn, an, t_eval[iout], X[iout])
            iout += 1
        stats[ki.S_NOUT] = iout
        stats[ki.S_NSTEP] += 1
        stop = ki.check_contacts(t, t_new, lam_old, lam, upl_t, uplift_mode, stats, rinfo)
        copy_vec(q, qn)
        copy_vec(v, vn)
        copy_vec(a, an)
        copy_vec(lam_old, lam)
        t = t_new
        k += 1
        if stop:
            break
        rinfo[ki.R_T] = t
    copy_vec(acc, a)
    kb.alive(own)
    return own[0], own[1]
