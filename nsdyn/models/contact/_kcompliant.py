"""Numba kernel: a planar rigid body on compliant ground, Coulomb friction with a stick spring.

Body q = (x, y, theta) relative to the moving ground, M = diag(m, m, J); base vertex j at
d_j = R(theta) r_j from the centre of mass, penetration delta_j = -(y + d_jy), normal velocity
gd_j = ydot + thetadot d_jx, slip velocity v_Tj = xdot - thetadot d_jy.  While delta_j > 0::

    N_j = max(0, k delta_j - c gd_j)                        (tensionless spring-dashpot)
    z_j = x_cj - a_j,   T_j = -k_t z_j                       (stick spring to the anchor a_j)
    |k_t z_j| <= mu N_j  (mu = mu_s if the corner stuck at the last step, else mu(|v_Tj|));
    otherwise the anchor is dragged: z_j = sign(z_j) mu(|v_Tj|) N_j / k_t   (slip, return map)

and a corner that leaves the ground forgets its anchor (it lands unstretched).  Equations of
motion m xdd = sum T_j - m a_h, m ydd = sum N_j - m (g + a_v), J thetadd = sum d_jx N_j - d_jy T_j,
integrated by the explicit central-difference (leapfrog) scheme of explicit FE codes, velocities
at half steps, dashpots and mu(v) with v_(n-1/2)::

    v_(n+1/2) = v_(n-1/2) + h M^-1 f(t_n, q_n, v_(n-1/2)),   q_(n+1) = q_n + h v_(n+1/2).

Stable for h < 2 (sqrt(1 + zeta^2) - zeta) / omega_max.  The return map keeps the stiff slip
law out of the step-size limit (a smooth regularisation would need h ~ u_stick / |v|).
Output row (N_OUT): x, y, theta, xd, yd, thetad (at t_n, velocities averaged over the two half
steps), E_n = sum k delta^2 / 2, E_t = sum k_t z^2 / 2, W_ext (work of -m a_h, -m a_v),
W_c (work of the contact forces on the body), corners on the ground, corners slipping.
"""

import math

import numpy as np
from numba import njit

from nsdyn import _kborrow as kb
from nsdyn._klinalg import copy_vec
from nsdyn.models.contact._kgeom import ground_acc, mu_of, tipped

P_M = 0  # mass [kg]
P_J = 1  # moment of inertia about the centre of mass [kg m^2]
P_G = 2  # gravity [m/s^2]
P_K = 3  # normal stiffness per corner [N/m]
P_C = 4  # normal damping per corner [N s/m]
P_KT = 5  # tangential stick stiffness per corner [N/m]
P_MUS = 6  # static friction coefficient
P_MUD = 7  # dynamic friction coefficient
P_CDEC = 8  # decay constant C of mu(v) [s/m] (-1: jump law)
P_THOV = 9  # overturning tilt theta > 0 [rad] (RigidBody.overturn_tilts)
P_THOV_NEG = 10  # ... and -theta > 0
N_P = 11
N_OUT = 12  # columns of an output row

ST_OK = 0  # reached t_end
ST_OVER = 1  # overturned (theta at theta_ov+ or -theta_ov-)
ST_NONFINITE = -1  # non-finite state


@njit(cache=True, error_model="numpy")
def forces(t, q, v, verts, anchor, stuck, p, ex, tab_h, tab_v, f, info):
    """Applied force f (3,) at (t, q, v); updates the anchors (nc,) and stick flags (nc,)
    by the return map.  info (4,) = [E_n, E_t, corners on, corners slipping]."""
    m = p[P_M]
    ah, av = ground_acc(t, ex, tab_h, tab_v)
    f[0] = -m * ah
    f[1] = -m * (p[P_G] + av)
    f[2] = 0.0
    cth = math.cos(q[2])
    sth = math.sin(q[2])
    e_n = 0.0
    e_t = 0.0
    n_on = 0
    n_slip = 0
    for j in range(verts.shape[0]):
        dx = cth * verts[j, 0] - sth * verts[j, 1]
        dy = sth * verts[j, 0] + cth * verts[j, 1]
        delta = -(q[1] + dy)
        xc = q[0] + dx
        if delta <= 0.0:
            anchor[j] = np.nan  # lifted: the stick spring is released
            stuck[j] = 1.0
            continue
        if not math.isfinite(anchor[j]):
            anchor[j] = xc  # touchdown: a new, unstretched stick spring
        gd = v[1] + v[2] * dx
        vt = v[0] - v[2] * dy
        n = p[P_K] * delta - p[P_C] * gd
        if n < 0.0:
            n = 0.0
        z = xc - anchor[j]
        ft = p[P_KT] * z
        mu = p[P_MUS] if stuck[j] > 0.0 else mu_of(vt, p[P_MUS], p[P_MUD], p[P_CDEC])
        if abs(ft) <= mu * n:
            stuck[j] = 1.0
        else:
            mu = mu_of(vt, p[P_MUS], p[P_MUD], p[P_CDEC])
            if p[P_CDEC] < 0.0:
                mu = p[P_MUD]  # slipping under the jump law
            ft = math.copysign(mu * n, z)
            z = ft / p[P_KT]
            anchor[j] = xc - z
            stuck[j] = 0.0
            n_slip += 1
        n_on += 1
        e_n += 0.5 * p[P_K] * delta * delta
        e_t += 0.5 * p[P_KT] * z * z
        tx = -ft
        f[0] += tx
        f[1] += n
        f[2] += dx * n - dy * tx
    info[0] = e_n
    info[1] = e_t
    info[2] = n_on
    info[3] = n_slip


@njit(cache=True, error_model="numpy")
def integrate(t0, t1, h, q, vh, verts, anchor, stuck, p, ex, tab_h, tab_v, acc, t_out, y_out,
              iout):  # fmt: skip
    """Leapfrog from t0 to t1 in steps of about ``h`` (the last step lands on t1).

    q (3,) at t0 and vh (3,) = v(t0 - h/2) are advanced in place; acc (2,) accumulates
    [W_ext, W_c].  Output rows on the grid t_out are filled from index ``iout``.
    Returns (status, t, iout, n_steps).
    """
    n_steps = max(1, int(math.ceil((t1 - t0) / h * (1.0 - 1e-12))))
    h = (t1 - t0) / n_steps
    # borrowed views (nsdyn._kborrow): no atomic reference counts per step
    minv = np.array([1.0 / p[P_M], 1.0 / p[P_M], 1.0 / p[P_J]])
    own = (np.zeros(3), np.zeros(4), np.zeros(3), minv)
    f, info, vn, minv = kb.borrowed(own)
    q, vh, verts, anchor, stuck, p, ex, tab_h, tab_v, acc, t_out, y_out = kb.borrowed(
        (q, vh, verts, anchor, stuck, p, ex, tab_h, tab_v, acc, t_out, y_out)
    )
    t = t0
    n_out = t_out.shape[0]
    for k in range(n_steps):
        forces(t, q, vh, verts, anchor, stuck, p, ex, tab_h, tab_v, f, info)
        for i in range(3):
            vnew = vh[i] + h * minv[i] * f[i]
            vn[i] = 0.5 * (vh[i] + vnew)
            vh[i] = vnew
        # work over the step, forces at t_n times the mean velocity (the kinetic energy change)
        m = p[P_M]
        ah, av = ground_acc(t, ex, tab_h, tab_v)
        fx_ext = -m * ah
        fy_ext = -m * av
        acc[0] += h * (fx_ext * vn[0] + fy_ext * vn[1])
        acc[1] += h * ((f[0] - fx_ext) * vn[0] + (f[1] - fy_ext + m * p[P_G]) * vn[1]
                       + f[2] * vn[2])  # fmt: skip
        while iout < n_out and t_out[iout] <= t + 0.5 * h:
            copy_vec(y_out[iout, 0:3], q)
            copy_vec(y_out[iout, 3:6], vn)
            copy_vec(y_out[iout, 6:8], info[0:2])
            copy_vec(y_out[iout, 8:10], acc)
            copy_vec(y_out[iout, 10:12], info[2:4])
            iout += 1
        for i in range(3):
            q[i] += h * vh[i]
        t = t0 + (k + 1) * h
        if not (math.isfinite(q[0]) and math.isfinite(q[1]) and math.isfinite(q[2])):
            return ST_NONFINITE, t, iout, k + 1
        if tipped(q[2], p[P_THOV], p[P_THOV_NEG]):
            return ST_OVER, t, iout, k + 1
    kb.alive(own)
    return ST_OK, t1, iout, n_steps
