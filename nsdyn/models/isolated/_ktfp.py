"""Kernels of the triple friction pendulum's series model (nsdyn.models.isolated.tfp).

Bearing row i holds the elastic stage (κ_e = B_KEL, its dashpot c_e = B_CEL, both per unit
normal force), the flow's time constant τ (B_TAU), its four elements (1/R̄_k, μ_k, d̄_k, κ_s,k
at B_ELEM + 4k) and their velocity strengthening (B_EFAST + k, B_ERATE); the internal slips
s_k are the state's entries B_IOFF + 2k, 2k + 1. With e = u − Σ_k s_k the force per unit
normal force is

    φ = κ_e e + c_e ė,   ė = v − Σ_k ṡ_k(φ),
    ṡ_k(φ) = w_k(|g_k|) g_k/|g_k|,   g_k = φ − h_k,   h_k = s_k/R̄_k + κ_s,k ⟨|s_k| − d̄_k⟩ ŝ_k,

w_k = 0 while |g_k| ≤ μ_k, else the root of |g_k| = μ_k(w) + κ_e τ w (:func:`tfp_speed`). Without
the dashpot φ is explicit. With it φ solves r(φ) = φ − κ_e e − c_e v + c_e Σ_k ṡ_k(φ) = 0, the
gradient of a strongly convex function (each ṡ_k is the gradient of a convex potential of g_k):
one root, found by Newton's method on the 2 × 2 system (semismooth: the flows kink at the
discs) with an Armijo line search on F, from φ = κ_e e + c_e v (every element stuck), to a
step of STEP_RTOL (STALL_RTOL where round-off at a kink stalls it); NaN beyond, which the
loops take as a failed evaluation. The dashpot damps the elastic stage, which
otherwise rings at ω_e = √(g κ_e) (about 7 Hz) and hands its stored energy to the slip at
every break-away (docs: bidirectional isolators).
"""

import math

from numba import njit

from nsdyn.models.isolated.bearings import B_CEL, B_EFAST, B_ELEM, B_ERATE, B_IOFF, B_KEL, B_TAU

NEWTON_ITER = 60  # Newton iterations of the damped stage's force (quadratic: a handful)
NEWTON_RTOL = 1e-15  # |r| accepted, relative to the larger of |φ| and max μ_k
STEP_RTOL = 1e-11  # a Newton step this small (relative to |φ| or max μ) is the last one
STALL_RTOL = 1e-9  # ... and one this small where the iteration stalls at round-off (a kink)
BACKTRACK = 40  # halvings of a Newton step before it counts as round-off
ARMIJO = 1e-4  # sufficient decrease of F along a Newton step


@njit(cache=True, error_model="numpy")
def tfp_speed(gn, mu, mu_fast, a, rate):
    """Slip speed w of a yielding series element, |g| = μ(w) + w/rate with μ(w) = μ_fast −
    (μ_fast − μ) exp(−a w) (constant μ: w = rate (|g| − μ)); Newton from w = 0, which rises
    monotonically to the root (the left side is increasing and concave in w)."""
    dm = mu_fast - mu
    if dm <= 0.0 or a <= 0.0:
        return rate * (gn - mu)
    w = 0.0
    for _ in range(60):
        e = math.exp(-a * w)
        res = mu_fast - dm * e + w / rate - gn
        dw = res / (a * dm * e + 1.0 / rate)
        w -= dw
        if abs(dw) <= 1e-15 * w + 1e-300:
            break
    return w


@njit(cache=True, error_model="numpy")
def _flows(y, bp, i, px, py, rate, sd):
    """The element rates ṡ_k(φ) at φ = (px, py) into sd[i]; returns Σ_k ∂ṡ_k/∂φ as (xx, xy,
    yy) (d w/d|g| = 1/(μ'(w) + 1/rate) along g, w/|g| across it) and the flows' potential
    Σ_k Ψ_k (ṡ_k = ∇Ψ_k(g_k): Ψ = ∫ w d|g| = w²/(2 rate) + (μ_fast − μ)(1 − e^(−aw)(1 + aw))/a)."""
    o = int(bp[i, B_IOFF])
    jxx = jxy = jyy = pot = 0.0
    for k in range(4):
        c = B_ELEM + 4 * k
        sx = y[o + 2 * k]
        sy = y[o + 2 * k + 1]
        gx = px - bp[i, c] * sx
        gy = py - bp[i, c] * sy
        rs = math.sqrt(sx * sx + sy * sy)
        if rs > bp[i, c + 2]:
            st = bp[i, c + 3] * (rs - bp[i, c + 2]) / rs
            gx -= st * sx
            gy -= st * sy
        gn = math.sqrt(gx * gx + gy * gy)
        if gn > bp[i, c + 1]:
            mu, fast, a = bp[i, c + 1], bp[i, B_EFAST + k], bp[i, B_ERATE]
            w = tfp_speed(gn, mu, fast, a, rate)
            nx = gx / gn
            ny = gy / gn
            sd[i, 2 * k] = w * nx
            sd[i, 2 * k + 1] = w * ny
            dmu = 0.0
            pot += 0.5 * w * w / rate
            if fast > mu and a > 0.0:
                ex = math.exp(-a * w)
                dmu = (fast - mu) * a * ex
                pot += (fast - mu) * (1.0 - ex * (1.0 + a * w)) / a
            along = 1.0 / (dmu + 1.0 / rate)
            across = w / gn
            jxx += across + (along - across) * nx * nx
            jxy += (along - across) * nx * ny
            jyy += across + (along - across) * ny * ny
        else:
            sd[i, 2 * k] = 0.0
            sd[i, 2 * k + 1] = 0.0
    return jxx, jxy, jyy, pot


@njit(cache=True, error_model="numpy")
def _residual(y, bp, i, px, py, bx, by, ce, rate, sd):
    """(|r|, r_x, r_y, ∂Σṡ as xx, xy, yy, F) of r = ∇F, F = |φ − b|²/2 + c_e Σ_k Ψ_k
    (b = κ_e e + c_e v), the rates left in sd[i]."""
    jxx, jxy, jyy, pot = _flows(y, bp, i, px, py, rate, sd)
    rx = px - bx
    ry = py - by
    for k in range(4):
        rx += ce * sd[i, 2 * k]
        ry += ce * sd[i, 2 * k + 1]
    f = 0.5 * ((px - bx) ** 2 + (py - by) ** 2) + ce * pot
    return math.sqrt(rx * rx + ry * ry), rx, ry, jxx, jxy, jyy, f


@njit(cache=True, error_model="numpy")
def tfp_force(y, bp, i, ux, uy, vx, vy, sd):
    """Force per unit normal force φ of the triple friction pendulum of row i at slip (ux, uy)
    and slip velocity (vx, vy), its internal slips s_k read from y[B_IOFF + 2k], and their
    rates ṡ_k into sd[i] (the module text); NaN when the damped stage's Newton fails."""
    o = int(bp[i, B_IOFF])
    ke = bp[i, B_KEL]
    ce = bp[i, B_CEL]
    ex = ux
    ey = uy
    for k in range(4):
        ex -= y[o + 2 * k]
        ey -= y[o + 2 * k + 1]
    rate = 1.0 / (ke * bp[i, B_TAU])
    bx = ke * ex + ce * vx
    by = ke * ey + ce * vy
    res, rx, ry, jxx, jxy, jyy, f = _residual(y, bp, i, bx, by, bx, by, ce, rate, sd)
    if ce == 0.0:
        return bx, by
    mu_max = 0.0
    for k in range(4):
        mu_max = max(mu_max, bp[i, B_ELEM + 4 * k + 1])
    px = bx
    py = by
    dx = dy = math.inf
    scale = mu_max
    for _ in range(NEWTON_ITER):
        scale = max(mu_max, math.sqrt(px * px + py * py))  # (the iterate's, not its history)
        if res <= NEWTON_RTOL * scale:
            return px, py
        a = 1.0 + ce * jxx
        b = ce * jxy
        d = 1.0 + ce * jyy
        det = a * d - b * b
        dx = -(d * rx - b * ry) / det
        dy = -(a * ry - b * rx) / det
        if math.sqrt(dx * dx + dy * dy) <= STEP_RTOL * scale:  # (quadratic: converged)
            return px, py
        slope = rx * dx + ry * dy  # (< 0: J is I + c_e × positive semidefinite)
        step = 1.0
        ok = False
        for _ in range(BACKTRACK):  # Armijo on F: Newton's step is a descent direction of F
            r1, sx, sy, kxx, kxy, kyy, f1 = _residual(y, bp, i, px + step * dx, py + step * dy,
                                                      bx, by, ce, rate, sd)  # fmt: skip
            # (near the root F's decrease r·d falls below its round-off: |r| halving counts)
            if f1 <= f + ARMIJO * step * slope or r1 <= 0.5 * res:
                ok = True
                break
            step *= 0.5
        if not ok:  # no decrease: as far as doubles go (the rates at φ again)
            _residual(y, bp, i, px, py, bx, by, ce, rate, sd)
            break
        px += step * dx
        py += step * dy
        res, rx, ry, jxx, jxy, jyy, f = r1, sx, sy, kxx, kxy, kyy, f1
    if math.sqrt(dx * dx + dy * dy) <= STALL_RTOL * scale:
        return px, py
    return math.nan, math.nan
