"""Numba kernel: equations of motion of the rigid cylinder, restrained or sliding on its base.

State y = (w, q₀..q₃, ẇ, ω_x, ω_y, ω_z, E_in, E_d, u_x, u_y, u̇_x, u̇_y, E_f): base-centre height
above the undeformed ground, unit quaternion of the body, their rates (ω in world axes), the work
of the ground (inertial) load, the energy dissipated by the dashpots, the horizontal slip u of
the base centre relative to the ground, its rate, and the energy dissipated by friction.
With ρ = H e₃ (base centre → centre of mass), J = I_t 𝟙 + (I_a − I_t) e₃e₃ᵀ, a horizontal base
force f at the base centre and x = (ü_x, ü_y, ẅ, ω̇), Newton and Euler about the accelerating base
centre give the symmetric positive 6×6 system

    m ü + m e_h·(ω̇ × ρ)                    = f − m a_g,h − m (ω×(ω×ρ))_h
    m ẅ + m e_z·(ω̇ × ρ)                    = F − mg − m a_gz − m e_z·(ω×(ω×ρ))
    m Σ ρ×e_i ẍ_i + (J + m(|ρ|²𝟙 − ρρᵀ)) ω̇ = M − mg ρ×e_z − ω×Jω − m ρ×a_g − m ρ×(ω×(ω×ρ))

with q̇ = ½ (0, ω) ⊗ q, Ė_in = −m a_g·v_rel (v_rel = u̇ + ẇ e_z + ω×ρ), Ė_d = D, Ė_f = −f·u̇.
F and M = (m_a e₁ + m_b e₂) × e_z come from ``_kfound.resultants``.

Base friction (mode in ``fr`` = (mode, d_x, d_y)): *stick* (and the restrained base, μ < 0):
ü = 0 and f = f_req = m a_c,h, the lower-right 4×4 block is solved; *slip*: Coulomb
f = −μ N d with N = max(F, 0) and d = u̇/|u̇|, the full 6×6 system is solved. The reference d_r
of ``fr`` is the slip direction at the start of the step (at the start of the slip: opposite to
the stick force). Slower than ``V_REG``, d = (u̇ + λ V_REG d_r)/|·| with λ = 1 − |u̇|/V_REG:
the direction of a 2D Coulomb slip turns at a rate ∝ 1/|u̇| (stiff as |u̇| → 0), and the blend
bounds that rate while moving the force by at most V_REG of velocity. Where u̇ has turned past
90° from d_r inside a step, d = d_r: the force stays continuous within a step, and a passage of
u̇ through zero is an event of ``integrate``, not a jump for the error control.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn import _kborrow as kb
from nsdyn import _kdp5 as dp
from nsdyn._klinalg import all_finite, copy_vec, lu_factor, lu_solve
from nsdyn.models.cylinder._kfound import contact_moments, resultants

NY = 16  # state size
IU, IUD, IEF = 11, 13, 15  # indices of u, u̇ and E_f in the state
NAUX = 9  # aux: F, M_x, M_y, A, V_spring, D, E_mech, f_x, f_y
NOUT = 1 + NY + 6 + NAUX  # history row: t, y, (ü_x, ü_y, ẅ, ω̇), aux
V_REG = 1e-4  # [m/s] below this slip speed the direction blends into the slip's initial one
STICK, SLIP = 0, 1  # friction modes

# status codes
OK, UNDERFLOW, NONFINITE, TOPPLED, MAXSTEPS = 0, 1, 2, 3, 4


@ka.compiled_only
def rotation(q: np.ndarray, R: np.ndarray) -> None:
    """R = rotation matrix of the quaternion q (normalised here)."""
    n = math.sqrt(q[0] ** 2 + q[1] ** 2 + q[2] ** 2 + q[3] ** 2)
    w, x, y, z = q[0] / n, q[1] / n, q[2] / n, q[3] / n
    R[0, 0] = 1 - 2 * (y * y + z * z)
    R[0, 1] = 2 * (x * y - w * z)
    R[0, 2] = 2 * (x * z + w * y)
    R[1, 0] = 2 * (x * y + w * z)
    R[1, 1] = 1 - 2 * (x * x + z * z)
    R[1, 2] = 2 * (y * z - w * x)
    R[2, 0] = 2 * (x * z - w * y)
    R[2, 1] = 2 * (y * z + w * x)
    R[2, 2] = 1 - 2 * (x * x + y * y)


@ka.compiled_only
def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


@ka.compiled_only
def solve_block(M: np.ndarray, b: np.ndarray, o: int) -> np.ndarray:
    """x with M[o:, o:] x = b[o:] (dense LU; nan if the block is singular or not finite)."""
    A = M[o:, o:].copy()
    x = b[o:].copy()
    piv = np.empty(x.shape[0], np.int64)
    if not lu_factor(A, piv, 0.0):
        x[:] = np.nan
        return x
    lu_solve(A, piv, x)
    return x


@ka.compiled_only
def mass(e3: np.ndarray, p: np.ndarray, Mm: np.ndarray) -> None:
    """Mm = 6×6 mass matrix of x = (ü_x, ü_y, ẅ, ω̇) for the body axis e3."""
    m, H, It, Ia = p[0], p[1], p[3], p[4]
    rho = H * e3
    # columns ρ × e_x, ρ × e_y, ρ × e_z
    rxe = np.array([[0.0, -rho[2], rho[1]], [rho[2], 0.0, -rho[0]], [-rho[1], rho[0], 0.0]])
    rr = rho[0] ** 2 + rho[1] ** 2 + rho[2] ** 2
    Mm[:, :] = 0.0
    for a in range(3):
        Mm[a, a] = m
        for i in range(3):
            Mm[a, 3 + i] = m * rxe[i, a]
            Mm[3 + i, a] = m * rxe[i, a]
    for i in range(3):
        for j in range(3):
            Jij = (Ia - It) * e3[i] * e3[j] + (It + m * rr if i == j else 0.0)
            Mm[3 + i, 3 + j] = Jij - m * rho[i] * rho[j]


@ka.compiled_only
def stop_slip(y: np.ndarray, p: np.ndarray) -> None:
    """Bring the slip velocity to zero by a horizontal impulse P at the base centre:
    M Δv = (P, 0), Δu̇ = −u̇, so P = −(M⁻¹)_hh⁻¹ u̇; dissipates ½ u̇ᵀ((M⁻¹)_hh)⁻¹u̇ ≥ 0."""
    R = np.empty((3, 3))
    rotation(y[1:5], R)
    Mm = np.empty((6, 6))
    mass(R[:, 2].copy(), p, Mm)
    G = np.empty((6, 2))  # columns of M⁻¹ for unit impulses along x and y
    for j in range(2):
        e = np.zeros(6)
        e[j] = 1.0
        copy_vec(G[:, j], solve_block(Mm, e, np.int64(0)))
    det = G[0, 0] * G[1, 1] - G[0, 1] * G[1, 0]
    ux, uy = y[IUD], y[IUD + 1]
    px = -(G[1, 1] * ux - G[0, 1] * uy) / det
    py = -(-G[1, 0] * ux + G[0, 0] * uy) / det
    y[IUD] = 0.0
    y[IUD + 1] = 0.0
    y[5] += G[2, 0] * px + G[2, 1] * py
    for i in range(3):
        y[6 + i] += G[3 + i, 0] * px + G[3 + i, 1] * py


@ka.compiled_only
def rhs(
    y: np.ndarray, ag: np.ndarray, p: np.ndarray, fr: np.ndarray, dy: np.ndarray, aux: np.ndarray
) -> None:
    """dy = f(y) under ground acceleration ag (3,); p = (m, H, r, I_t, I_a, k, c, g, bonded, μ)
    with μ < 0 for a restrained base; fr = (mode, d_x, d_y) of the base friction."""
    m, H, r, It, Ia, k, c, g = p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]
    bonded = p[8] > 0.5
    mu = p[9]
    slip = mu >= 0.0 and fr[0] > 0.5
    R = np.empty((3, 3))
    rotation(y[1:5], R)
    nq = math.sqrt(y[1] ** 2 + y[2] ** 2 + y[3] ** 2 + y[4] ** 2)
    q0, q1, q2, q3 = y[1] / nq, y[2] / nq, y[3] / nq, y[4] / nq
    w, wd = y[0], y[5]
    om = y[6:9].copy()
    ud = y[IUD : IUD + 2].copy()
    e3 = R[:, 2].copy()
    gx, gy = R[2, 0], R[2, 1]
    gxd = om[0] * R[1, 0] - om[1] * R[0, 0]  # ω·(e₁ × e_z)
    gyd = om[0] * R[1, 1] - om[1] * R[0, 1]
    fnd = np.empty(6)
    resultants(np.array([w, gx, gy, wd, gxd, gyd]), r, k, c, bonded, fnd)
    F = fnd[0]
    mw = fnd[1] * R[:, 0] + fnd[2] * R[:, 1]
    Mf = np.array([mw[1], -mw[0], 0.0])  # mw × e_z
    rho = H * e3
    Jom = It * om + (Ia - It) * e3 * (e3[0] * om[0] + e3[1] * om[1] + e3[2] * om[2])
    cen = cross(om, cross(om, rho))
    Mm = np.empty((6, 6))
    mass(e3, p, Mm)
    rxe = np.array([[0.0, -rho[2], rho[1]], [rho[2], 0.0, -rho[0]], [-rho[1], rho[0], 0.0]])
    b = np.empty(6)
    b[0] = -m * ag[0] - m * cen[0]
    b[1] = -m * ag[1] - m * cen[1]
    b[2] = F - m * g - m * ag[2] - m * cen[2]
    t1 = cross(om, Jom)
    t2 = cross(rho, ag)
    t3 = cross(rho, cen)
    for i in range(3):
        b[3 + i] = Mf[i] - m * g * rxe[i, 2] - t1[i] - m * t2[i] - m * t3[i]
    acc = np.zeros(6)
    if slip:
        lam = max(0.0, 1.0 - math.sqrt(ud[0] ** 2 + ud[1] ** 2) / V_REG)
        vx = ud[0] + lam * V_REG * fr[1]
        vy = ud[1] + lam * V_REG * fr[2]
        s = math.sqrt(vx * vx + vy * vy)
        if vx * fr[1] + vy * fr[2] > 0.0:
            dx, dyy = vx / s, vy / s
        else:  # u̇ turned past 90° from the reference within the step: an event follows
            dx, dyy = fr[1], fr[2]
        N = max(F, 0.0)
        fx, fy = -mu * N * dx, -mu * N * dyy
        b[0] += fx
        b[1] += fy
        copy_vec(acc, solve_block(Mm, b, np.int64(0)))
    else:
        copy_vec(acc[2:], solve_block(Mm, b, np.int64(2)))
        # force that keeps ü = 0: the horizontal rows with ü = 0
        fx = -b[0] + Mm[0, 3] * acc[3] + Mm[0, 4] * acc[4] + Mm[0, 5] * acc[5]
        fy = -b[1] + Mm[1, 3] * acc[3] + Mm[1, 4] * acc[4] + Mm[1, 5] * acc[5]
    dy[0] = wd
    dy[1] = -0.5 * (om[0] * q1 + om[1] * q2 + om[2] * q3)
    dy[2] = 0.5 * (q0 * om[0] + om[1] * q3 - om[2] * q2)
    dy[3] = 0.5 * (q0 * om[1] + om[2] * q1 - om[0] * q3)
    dy[4] = 0.5 * (q0 * om[2] + om[0] * q2 - om[1] * q1)
    dy[5] = acc[2]
    dy[6] = acc[3]
    dy[7] = acc[4]
    dy[8] = acc[5]
    vrel = cross(om, rho)
    vrel[0] += ud[0]
    vrel[1] += ud[1]
    vrel[2] += wd
    dy[9] = -m * (ag[0] * vrel[0] + ag[1] * vrel[1] + ag[2] * vrel[2])
    dy[10] = fnd[5]
    dy[IU] = ud[0]
    dy[IU + 1] = ud[1]
    dy[IUD] = acc[0]
    dy[IUD + 1] = acc[1]
    dy[IEF] = -(fx * ud[0] + fy * ud[1])
    aux[0] = F
    aux[1] = Mf[0]
    aux[2] = Mf[1]
    aux[3] = fnd[3]
    aux[4] = fnd[4]
    aux[5] = fnd[5]
    T = 0.5 * m * (vrel[0] ** 2 + vrel[1] ** 2 + vrel[2] ** 2)
    T += 0.5 * (om[0] * Jom[0] + om[1] * Jom[1] + om[2] * Jom[2])
    aux[6] = T + m * g * (w + H * e3[2]) + fnd[4]
    aux[7] = fx
    aux[8] = fy


# the right-hand side by address (:func:`nsdyn._kaddress.tcall`, declared and put in the table
# by nsdyn.models.cylinder.cylinder_compile): the mode switch, the output and the time loop
# would otherwise each link, LLVM optimise and translate again their own copy of it
ka.tslot("cyl.rhs", rhs, "nsdyn.models.cylinder.cylinder_compile:callees")


@njit(cache=True, error_model="numpy", inline="always")
def rhs_t(y, ag, p, fr, dy, aux) -> None:
    """:func:`rhs` called by its address in the table of :mod:`nsdyn._kaddress`."""
    ka.tcall("cyl.rhs", (y, ag, p, fr, dy, aux))


# the slip stop by address too, compiled in the helper beside the right-hand side, whose mass
# matrix and block solve it shares (linked into the loop, this process compiled them as well)
ka.tslot("cyl.stop_slip", stop_slip, "nsdyn.models.cylinder.cylinder_compile:callees")


@njit(cache=True, error_model="numpy", inline="always")
def stop_slip_t(y, p) -> None:
    """:func:`stop_slip` called by its address in the table of :mod:`nsdyn._kaddress`."""
    ka.tcall("cyl.stop_slip", (y, p))


@ka.compiled_only
def contact_kind(y: np.ndarray, r: float) -> int:
    """0 lifted off, 1 partial contact, 2 full contact (tensionless foundation)."""
    R = np.empty((3, 3))
    rotation(y[1:5], R)
    mom = np.empty(11)
    return contact_moments(y[0], R[2, 0], R[2, 1], r, np.bool_(False), mom)


@ka.compiled_only
def friction_event(yn: np.ndarray, fr: np.ndarray, aux: np.ndarray, mu: float) -> int:
    """Mode change due at the end yn of a step (aux: rhs at yn in the current mode).

    0 none; 1 stick → slip (|f_req| > μN); 2 the slip velocity turned by more than 90° within
    the step (it passed through zero: stop, or reverse in 1D).
    """
    if mu < 0.0:
        return 0
    if fr[0] < 0.5:
        return 1 if math.hypot(aux[7], aux[8]) > mu * max(aux[0], 0.0) else 0
    return 2 if yn[IUD] * fr[1] + yn[IUD + 1] * fr[2] <= 0.0 else 0


@ka.compiled_only
def set_mode(y, a, p, fr, k1, aux) -> None:
    """Stick if the force that keeps the base still is within the friction cone, else slip
    starting in the direction opposite to that force; k1 = rhs(y) in the chosen mode."""
    fr[0] = STICK
    rhs_t(y, a, p, fr, k1, aux)
    fmag = math.hypot(aux[7], aux[8])
    if fmag > p[9] * max(aux[0], 0.0):
        fr[0] = SLIP
        fr[1] = -aux[7] / fmag
        fr[2] = -aux[8] / fmag
        rhs_t(y, a, p, fr, k1, aux)


@ka.compiled_only
def store(hist: np.ndarray, i: int, t: float, y: np.ndarray, ag, p, fr, dy, aux) -> None:
    rhs_t(y, ag, p, fr, dy, aux)
    hist[i, 0] = t
    copy_vec(hist[i, 1 : 1 + NY], y)
    hist[i, 1 + NY] = dy[IUD]
    hist[i, 2 + NY] = dy[IUD + 1]
    copy_vec(hist[i, 3 + NY : 7 + NY], dy[5:9])
    copy_vec(hist[i, 7 + NY :], aux)


def workspace() -> tuple:
    """The time loop's workspace: dy, aux, the friction state fr, the Dormand-Prince stages k
    (7, NY), a stage's state yn, the ground acceleration a at a stage and its slope sl."""
    return (np.empty(NY), np.empty(NAUX), np.zeros(3), np.empty((7, NY)), np.empty(NY),
            np.empty(3), np.empty(3))  # fmt: skip


@njit(cache=True, error_model="numpy")
def integrate(
    t0: float,
    dt: float,
    ag: np.ndarray,
    y: np.ndarray,
    p: np.ndarray,
    rtol: float,
    atol: np.ndarray,
    h_kink: float,
    h_min: float,
    max_steps: int,
    cos_topple: float,
    hist: np.ndarray,
    stats: np.ndarray,
    work: tuple,
) -> int:
    """Integrate over the samples of ag (n, 3); hist (n, NOUT) rows at the sample times.

    Steps never cross a sample time (the record is piecewise linear). A step whose end has
    another contact kind (tensionless), is due a friction-mode change or passes the toppling
    tilt is halved until no longer than ``h_kink`` (bisection onto the event), then the mode
    is switched (or the run stops, toppled, at that step's end); a slip that
    stops has its residual velocity (|u̇| ≲ h_kink |ü|) removed by a base impulse
    (``stop_slip``) and the kinetic energy it takes booked in E_f. stats = (t reached,
    accepted, rejected, event halvings, rhs calls, slip starts). Returns the status.
    ``y``: the initial state, overwritten by the state reached; ``work``: the workspace of
    :func:`workspace` (from the caller: the loop allocates nothing).
    """
    n = ag.shape[0]
    # borrowed views (nsdyn._kborrow): no atomic reference counts per stage and step
    dy, aux, fr, k, yn, a, sl = kb.borrowed(work)
    y, ag, p, atol, hist, stats = kb.borrowed((y, ag, p, atol, hist, stats))
    tensionless = p[8] < 0.5
    r = p[2]
    mu = p[9]
    nerr = 9 if mu < 0.0 else 13
    fr[:] = 0.0
    if mu >= 0.0:
        set_mode(y, ag[0], p, fr, k[0], aux)
    else:
        rhs_t(y, ag[0], p, fr, k[0], aux)
    slips = int(fr[0])
    store(hist, np.int64(0), t0, y, ag[0], p, fr, dy, aux)
    nfev = 2
    h = min(dt, 1e-3)
    acc = 0
    rej = 0
    kinks = 0
    t = t0
    status = OK
    for i in range(n - 1):
        ta = t0 + i * dt
        tb = ta + dt
        for c in range(3):
            sl[c] = (ag[i + 1, c] - ag[i, c]) / dt
        t = ta
        while tb - t > 1e-12 * dt:
            hs = min(h, tb - t)
            trunc = hs < h
            if fr[0] > 0.5:  # slip: reference direction = direction of u̇ at the step start
                s = math.hypot(y[IUD], y[IUD + 1])
                if s >= V_REG:
                    fr[1] = y[IUD] / s
                    fr[2] = y[IUD + 1] / s
            for j in range(1, 7):  # the last stage is evaluated at the solution yn
                tau = t + dp.C[j] * hs - ta
                for c in range(3):
                    a[c] = ag[i, c] + sl[c] * tau
                dp.stage(y, k, hs, j, yn)
                rhs_t(yn, a, p, fr, k[j], aux)
            nfev += 6
            err = 0.0
            for j in range(NY):
                if j == 9 or j == 10 or j == IEF:
                    continue  # energy quadratures: not under error control
                sc = atol[j] + rtol * max(abs(y[j]), abs(yn[j]))
                err += (dp.error(k, hs, j) / sc) ** 2
            err = math.sqrt(err / nerr)
            if not (err == err) or not all_finite(yn):
                if hs > h_min:
                    h = 0.25 * hs
                    rej += 1
                    continue
                stats[0] = t
                status = NONFINITE
                break
            if err <= 1.0:
                if tensionless and hs > h_kink and contact_kind(y, r) != contact_kind(yn, r):
                    h = 0.5 * hs
                    kinks += 1
                    continue
                if hs > h_kink and 1.0 - 2.0 * (yn[2] ** 2 + yn[3] ** 2) < cos_topple:
                    h = 0.5 * hs  # toppling located to h_kink, not at the step's end
                    kinks += 1
                    continue
                ev = friction_event(yn, fr, aux, mu)
                if ev != 0 and hs > h_kink:
                    h = 0.5 * hs
                    kinks += 1
                    continue
                t += hs
                nq = math.sqrt(yn[1] ** 2 + yn[2] ** 2 + yn[3] ** 2 + yn[4] ** 2)
                for j in range(1, 5):
                    yn[j] /= nq
                copy_vec(y, yn)
                copy_vec(k[0], k[6])
                acc += 1
                if ev == 2:  # the slip stopped: impulse onto u̇ = 0, its energy loss booked
                    e_before = aux[6]
                    stop_slip_t(y, p)
                    rhs_t(y, a, p, fr, dy, aux)
                    y[IEF] += e_before - aux[6]
                if ev != 0:
                    set_mode(y, a, p, fr, k[0], aux)
                    slips += int(fr[0])
                    nfev += 2
                hn = dp.new_step(hs, err)
                h = max(h, hn) if trunc else hn
                if 1.0 - 2.0 * (y[2] ** 2 + y[3] ** 2) < cos_topple:
                    status = TOPPLED
                    break
            else:
                rej += 1
                h = dp.new_step(hs, err)
            if h < h_min:
                status = UNDERFLOW
                break
            if acc + rej > max_steps:
                status = MAXSTEPS
                break
        if status == TOPPLED:  # the last row: the instant of toppling, not the last output
            for c in range(3):
                a[c] = ag[i, c] + sl[c] * (t - ta)
            store(hist, i + 1, t, y, a, p, fr, dy, aux)
        if status != OK:
            break
        store(hist, i + 1, tb, y, ag[i + 1], p, fr, dy, aux)
        nfev += 1
    stats[0] = t
    stats[1] = acc
    stats[2] = rej
    stats[3] = kinks
    stats[4] = nfev
    stats[5] = slips
    return status
