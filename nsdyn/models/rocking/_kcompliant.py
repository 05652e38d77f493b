"""Numba kernel: a planar rigid block on tensionless spring–damper supports at its base corners.

State ``y = [x, y, phi, x', y', phi', e_0, e_1]``: the centre of gravity relative to the moving
ground (phi counter-clockwise; the rocking angle is theta = -phi) and the stretches e_j of the
horizontal (no-slip) springs. Corner j (body point
``(s_j B, -H)``, s_j = -1, +1) at ``c_j = (x, y) + Rot(phi) (s_j B, -H)``; penetration
``d_j = -c_jy``. While ``d_j > 0``::

    N_j = max(0, k d_j + c d_j')                          (vertical, tensionless)
    T_j = -(k_t e_j + c_t c_jx'),   e_j' = c_jx'            (horizontal, no slip)

and in flight ``e_j' = -omega_v e_j`` (the spring relaxes, so a corner lands unstretched: a
spring that reappeared stretched would create energy). The body's equations::

    m x''   = sum T_j - m ü_h
    m y''   = sum N_j - m (g + ü_v)
    I phi'' = sum (r_j x F_j),  r_j = c_j - (x, y)

integrated by adaptive Dormand–Prince 5(4) (stops at excitation breakpoints; error control
resolves the contact transitions), output by cubic Hermite interpolation within each step. The
run ends where |theta| reaches pi/2 (the block on its side, overturned; the corner supports
alone would let it tumble on through the ground), located on the same interpolant.
"""

import math

import numpy as np
from numba import njit

from nsdyn import _kborrow as kb
from nsdyn import _kdp5 as dp
from nsdyn._klinalg import copy_vec
from nsdyn.models.rocking._kground import RIGHT_LIMIT, ground, step_to_breakpoint

Q_M = 0  # mass [kg]
Q_I = 1  # moment of inertia about the centre of gravity [kg m²]
Q_B = 2  # half-width [m]
Q_H = 3  # half-height [m]
Q_K = 4  # vertical support stiffness per corner [N/m]
Q_C = 5  # vertical support damping per corner [N s/m]
Q_KT = 6  # horizontal (no-slip) stiffness per corner [N/m]
Q_CT = 7  # horizontal damping per corner [N s/m]
Q_G = 8  # gravity [m/s²]
Q_TOL = 9  # relative tolerance
Q_HMAX = 10  # largest step [s]
Q_WV = 11  # relaxation rate of a lifted corner's horizontal spring [1/s]
Q_BUDGET = 12  # step attempts (accepted and rejected) before the run gives up
N_Q = 13

J_NSTEP = 0  # accepted steps
J_NREJ = 1  # rejected steps
J_NOUT = 2  # output samples filled
J_TFAIL = 3  # failure time
J_TOVER = 4  # overturning time: |theta| reaches THETA_FALL (NaN: it did not)
N_J = 5
THETA_FALL = math.pi / 2  # |theta| at which the block lies on its side: the run ends there

ST_OK = 0  # finished
ST_UNDERFLOW = 2  # step-size underflow
ST_NONFINITE = 3  # non-finite state
ST_BUDGET = 4  # the step budget q[Q_BUDGET] spent
H_MIN = 1e-14  # step-size underflow threshold [s] (relative to 1 + |t|)


@njit(cache=True, error_model="numpy")
def rhs(t, left, y, q, gk, gp, tab_h, tab_v, dy):
    """dy = f(t, y) of the block on corner supports (q[Q_WV] is the in-flight relaxation rate)."""
    ah, av = ground(t, left, gk, gp, tab_h, tab_v)
    m = q[Q_M]
    cph = math.cos(y[2])
    sph = math.sin(y[2])
    fx = -m * ah
    fy = -m * (q[Q_G] + av)
    mz = 0.0
    for j in range(2):
        sj = -1.0 if j == 0 else 1.0
        bx = sj * q[Q_B]
        by = -q[Q_H]
        rx = cph * bx - sph * by
        ry = sph * bx + cph * by
        cy = y[1] + ry
        vx = y[3] - y[5] * ry
        if cy < 0.0:
            vy = y[4] + y[5] * rx
            n = q[Q_K] * (-cy) + q[Q_C] * (-vy)
            if n < 0.0:
                n = 0.0
            tx = -(q[Q_KT] * y[6 + j] + q[Q_CT] * vx)
            fx += tx
            fy += n
            mz += rx * n - ry * tx
            dy[6 + j] = vx
        else:
            dy[6 + j] = -q[Q_WV] * y[6 + j]
    dy[0] = y[3]
    dy[1] = y[4]
    dy[2] = y[5]
    dy[3] = fx / m
    dy[4] = fy / m
    dy[5] = mz / q[Q_I]


@njit(cache=True, error_model="numpy")
def _fall_fraction(rc):
    """The fraction s of a step at which |phi| of its cubic interpolant ``rc`` reaches
    THETA_FALL (below it at s = 0, at or above it at s = 1), by bisection to 1e-12."""
    lo = 0.0
    hi = 1.0
    i_phi = rc.shape[1] - 6  # phi's column, 2 (a run-time index: dense compiles for int64 once)
    for _ in range(45):
        mid = 0.5 * (lo + hi)
        if abs(dp.dense(rc, i_phi, mid)) >= THETA_FALL:
            hi = mid
        else:
            lo = mid
    return hi


@njit(cache=True, error_model="numpy")
def integrate(q, atol, gk, gp, tab_h, tab_v, y0, t0, t_end, out_dt, out, info):
    """Integrate from ``y0`` (8,) at ``t0`` to ``t_end``; ``out`` (n_out, 8) on the grid
    ``t0 + k out_dt``; returns an ST_* status, counters in ``info`` (``info[J_TOVER]``: the
    time |theta| reached THETA_FALL, where the run ended; NaN if it did not)."""
    n = 8
    k = np.zeros((7, n))
    y = y0.copy()
    y1 = np.zeros(n)  # a stage's state; after the last stage the step's solution
    rc = np.zeros((5, n))
    # borrowed views (nsdyn._kborrow): no atomic reference counts per stage and step
    own = (k, y, y1, rc)
    k, y, y1, rc = kb.borrowed(own)
    q, atol, gp, tab_h, tab_v, out, info = kb.borrowed((q, atol, gp, tab_h, tab_v, out, info))
    tol = q[Q_TOL]
    hmax = q[Q_HMAX]
    n_out = out.shape[0]
    n_tab = tab_h.size
    t = t0
    h = min(hmax, 1e-4)
    k_out = 0
    n_step = 0
    n_rej = 0
    fsal = False
    status = ST_OK
    info[J_TFAIL] = np.nan
    info[J_TOVER] = np.nan
    while k_out < n_out and t0 + k_out * out_dt <= t:
        copy_vec(out[k_out, :], y)
        k_out += 1
    while t < t_end - 1e-15 * abs(t_end):  # (t_end (1 - 1e-15) lay past a negative t_end)
        if n_step + n_rej >= q[Q_BUDGET]:
            status = ST_BUDGET
            info[J_TFAIL] = t
            break
        hh, at_bp = step_to_breakpoint(t, min(h, hmax), t_end, gk, gp, n_tab)
        if not fsal:
            rhs(t, RIGHT_LIMIT, y, q, gk, gp, tab_h, tab_v, k[0])
        for j in range(1, 7):  # the last stage is evaluated at the solution y1
            dp.stage(y, k, hh, j, y1)
            rhs(t + dp.C[j] * hh, at_bp and j >= 5, y1, q, gk, gp, tab_h, tab_v, k[j])
        err = 0.0
        for i in range(n):
            sci = atol[i] + tol * max(abs(y[i]), abs(y1[i]))
            err += (dp.error(k, hh, i) / sci) ** 2
        err = math.sqrt(err / n)
        if not math.isfinite(err) or err > 1.0:
            h = dp.new_step(hh, err) if math.isfinite(err) else 0.2 * hh
            n_rej += 1
            fsal = True
            if h <= H_MIN * (1.0 + abs(t)):
                status = ST_UNDERFLOW if math.isfinite(err) else ST_NONFINITE
                info[J_TFAIL] = t
                break
            continue
        n_step += 1
        s_end = 1.0
        if abs(y1[2]) >= THETA_FALL:  # overturned within the step: end there
            dp.dense_coefficients(y, y1, k, hh, rc)
            rc[4, :] = 0.0
            s_end = _fall_fraction(rc)
            info[J_TOVER] = t + s_end * hh
        if k_out < n_out and t0 + k_out * out_dt <= t + s_end * hh:
            dp.dense_coefficients(y, y1, k, hh, rc)
            rc[4, :] = 0.0  # cubic Hermite output
            while k_out < n_out and t0 + k_out * out_dt <= t + s_end * hh:
                s = (t0 + k_out * out_dt - t) / hh
                for i in range(n):
                    out[k_out, i] = dp.dense(rc, i, s)
                k_out += 1
        if info[J_TOVER] == info[J_TOVER]:
            break
        t += hh
        for i in range(n):
            y[i] = y1[i]
        if at_bp:
            fsal = False
        else:
            for i in range(n):
                k[0, i] = k[6, i]
            fsal = True
        h = min(dp.new_step(hh, err), hmax)
    info[J_NSTEP] = n_step
    info[J_NREJ] = n_rej
    info[J_NOUT] = k_out
    kb.alive(own)
    return status
