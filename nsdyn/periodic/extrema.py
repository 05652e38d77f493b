"""Extrema of a sampled orbit, located on its dense output instead of at the samples.

The largest sample of ``x(t)`` misses the true maximum by up to ``max|x''| h^2 / 8`` (h the
sample spacing; 1.2e-4 of the amplitude of a sine sampled 200 times per period). Between two
samples ``t_k`` and ``t_k + h`` where position ``x``, velocity ``v = x'`` and acceleration
``a = x''`` are known, the quintic Hermite interpolant in ``s = (t - t_k) / h``

    p(s) = c0 + c1 s + ... + c5 s^5,   c0 = x_k,  c1 = h v_k,  c2 = h^2 a_k / 2,
    c3 = 10 r0 - 4 r1 + r2 / 2,  c4 = -15 r0 + 7 r1 - r2,  c5 = 6 r0 - 3 r1 + r2 / 2,
    r0 = x_k+1 - c0 - c1 - c2,  r1 = h v_k+1 - c1 - 2 c2,  r2 = h^2 a_k+1 - 2 c2

matches all six values; for a smooth x its error is at most ``max|x^(6)| (h/2)^6 / 6!``, and
errors ``e_x, e_v, e_a`` of the data add at most ``2 e_x + h e_v + h^2 e_a`` (bounds of the
Hermite basis functions on [0, 1]). The extremum inside a step is a real root of
``p'(s)`` (a quartic) in [0, 1]. Only steps where the velocity changes sign toward the
extremum and whose samples come within ``h^2 max|a| / 2`` of the sampled extremum can hold
it, so a stick phase (velocity dithering about zero far from the extremum) costs nothing.

Friction makes the acceleration jump where an isolator sticks (at its extremum), and a
polynomial through a kink overshoots. While the acceleration keeps its sign over the step
(the speed falls to the peak and grows after it) the rise above either end is bounded by
that end's speed,

    x_peak <= min(x_k + |v_k| h,  x_k+1 + |v_k+1| h),

which a smooth peak meets with a factor 2 to spare (``x_peak - x_k+1 = a (h - t*)^2 / 2``
against ``|v_k+1| h >= a (h - t*)^2``); the interpolated peak of a step with ``a_k <= 0`` and
``a_k+1 <= 0`` is capped by it, so a step that ends stuck (``v = 0``) gives its end value, the
exact one. Where the acceleration changes sign within the step the speed can exceed both end
speeds and no cap applies.
"""

from __future__ import annotations

import numpy as np


def _quintic(x0, v0, a0, x1, v1, a1, h) -> np.ndarray:
    """Coefficients c0..c5 of the quintic Hermite interpolant on one step (module text)."""
    c0, c1, c2 = x0, h * v0, 0.5 * h * h * a0
    r0 = x1 - c0 - c1 - c2
    r1 = h * v1 - c1 - 2.0 * c2
    r2 = h * h * a1 - 2.0 * c2
    return np.array([c0, c1, c2, 10 * r0 - 4 * r1 + 0.5 * r2, -15 * r0 + 7 * r1 - r2,
                     6 * r0 - 3 * r1 + 0.5 * r2])  # fmt: skip


def _step_peak(c: np.ndarray) -> float:
    """Largest value of the quintic with coefficients ``c`` on s in [0, 1]."""
    d = np.array([5 * c[5], 4 * c[4], 3 * c[3], 2 * c[2], c[1]])
    best = max(c[0], float(np.sum(c)))
    if not np.any(d[:-1]):
        return best
    for r in np.roots(np.trim_zeros(d, "f")):
        if abs(r.imag) <= 1e-9 and -1e-12 <= r.real <= 1.0 + 1e-12:
            s = min(max(r.real, 0.0), 1.0)
            best = max(best, float(np.polyval(c[::-1], s)))
    return best


def dense_max(x: np.ndarray, v: np.ndarray, a: np.ndarray, h: float) -> float:
    """Maximum of a trajectory sampled at spacing ``h`` (``x, v, a``: (N + 1,) position,
    velocity and acceleration), on the quintic Hermite dense output."""
    top = float(np.max(x))
    if x.size < 2 or not (np.all(np.isfinite(v)) and np.all(np.isfinite(a))):
        return top
    near = top - 0.5 * h * h * float(np.max(np.abs(a)))
    hi = np.maximum(x[:-1], x[1:])
    steps = np.flatnonzero((v[:-1] >= 0.0) & (v[1:] <= 0.0) & (hi >= near))
    for k in steps:
        c = _quintic(x[k], v[k], a[k], x[k + 1], v[k + 1], a[k + 1], h)
        peak = _step_peak(c)
        if a[k] <= 0.0 and a[k + 1] <= 0.0:  # the speed bound holds while a keeps its sign
            peak = min(peak, x[k] + abs(v[k]) * h, x[k + 1] + abs(v[k + 1]) * h)
        top = max(top, peak)
    return top


def dense_half_range(X: np.ndarray, V: np.ndarray, A: np.ndarray, h: float) -> float:
    """Largest half peak-to-peak ``(max - min) / 2`` over the columns of ``X`` (samples of
    several trajectories, (N + 1, k), with velocities ``V`` and accelerations ``A``), the
    extrema on the dense output (:func:`dense_max`); 0 for no column."""
    if X.size == 0:
        return 0.0
    out = 0.0
    for j in range(X.shape[1]):
        hi = dense_max(X[:, j], V[:, j], A[:, j], h)
        lo = -dense_max(-X[:, j], -V[:, j], -A[:, j], h)
        out = max(out, 0.5 * (hi - lo))
    return out
