"""Overturning spectra: the minimum pulse amplitude that overturns a rocking block (or frame)
as a function of the pulse frequency, by bracketing and bisection.

For each ``omega_p / p`` the amplitude ratio ``a_p / (g tan alpha)`` is scanned geometrically
from 1 (no lift-off below) by the factor ``scan`` up to ``a_max``; each change of outcome
(safe <-> overturned) is then bisected to the relative width ``rtol``. Reported: the minimum
overturning amplitude with its mode (1: overturns after at least one impact, 2: without an
impact, Zhang & Makris 2001), and the first safe band above the minimum if the scan finds one
(for one-sine pulses the literature reports such a band: overturning with one impact at the
minimum, then safe, then overturning without impact). A band narrower than one scan factor
can be missed; that is the price of not using a fixed grid.

Frequencies run in parallel on any :class:`concurrent.futures.Executor` (local processes by
default); each task is a top-level function of plain values, so it pickles.
"""

from __future__ import annotations

import math
import time
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import dataclass

import numpy as np

from nsdyn.ground.pulses import Pulse
from nsdyn.models.rocking.block import TOL, simulate_rocking

RTOL = 1e-4  # relative width of the bisected amplitude brackets
SCAN = 1.1  # geometric scan factor of the amplitude
A_MAX = 30.0  # largest amplitude ratio a_p / (g tan alpha) scanned
T_AFTER_P = 25.0  # free time after the pulse, in units of 1/p (slow falls near the threshold)


@dataclass
class OverturningSpectrum:
    """Overturning amplitudes against frequency (ratios; nan where not found).

    Attributes
    ----------
    omega_ratio : ndarray, shape (n,)
        omega_p / p.
    a_min_ratio : ndarray, shape (n,)
        Minimum overturning a_p / (g tan alpha) (nan: none up to a_max).
    mode : ndarray of int, shape (n,)
        1: overturning after an impact, 2: without impact, 0: none found.
    safe_lo_ratio, safe_hi_ratio : ndarray, shape (n,)
        First safe band above the minimum (nan if none found; hi nan: safe up to a_max).
    """

    omega_ratio: np.ndarray
    a_min_ratio: np.ndarray
    mode: np.ndarray
    safe_lo_ratio: np.ndarray
    safe_hi_ratio: np.ndarray
    shape: str
    alpha: float
    p: float
    n_runs: int
    wall_s: float


def _overturns(model, shape, w, a, tol):
    """(overturned, n_impacts before overturning) under the pulse of amplitude a [m/s²]."""
    pulse = Pulse(shape, -a, w)
    t_end = pulse.duration + T_AFTER_P / model.p
    res = simulate_rocking(model, pulse, t_end=t_end, tol=tol, dt_out=0, max_peaks=1)
    return res.overturned, res.n_impacts


def _bisect(model, shape, w, a_lo, a_hi, over_lo, rtol, tol):
    """Bisect the outcome change between a_lo and a_hi; returns (a_lo, a_hi, runs, n_imp_hi)."""
    runs = 0
    n_imp = -1
    while a_hi - a_lo > rtol * a_hi:
        a_m = math.sqrt(a_lo * a_hi)
        over, ni = _overturns(model, shape, w, a_m, tol)
        runs += 1
        if over == over_lo:
            a_lo = a_m
        else:
            a_hi = a_m
            n_imp = ni
    return a_lo, a_hi, runs, n_imp


def spectrum_point(model, shape: str, omega_ratio: float, rtol: float = RTOL,
                   scan: float = SCAN, a_max: float = A_MAX, tol: float = TOL):  # fmt: skip
    """(a_min, mode, safe_lo, safe_hi, runs) at one omega_p / p (amplitudes / g tan alpha)."""
    w = omega_ratio * model.p
    a_ref = model.uplift_accel
    runs = 0
    a_prev = a_ref
    out = [math.nan, 0, math.nan, math.nan]
    state = "find_over"
    a = a_ref * (1.0 + 1e-6)
    while a <= a_max * a_ref:
        over, ni = _overturns(model, shape, w, a, tol)
        runs += 1
        if state == "find_over" and over:
            lo, hi, n, n_imp = _bisect(model, shape, w, a_prev, a, False, rtol, tol)
            runs += n
            n_imp = ni if n_imp < 0 else n_imp
            out[0], out[1] = hi / a_ref, 1 if n_imp > 0 else 2
            state = "find_safe"
        elif state == "find_safe" and not over:
            lo, hi, n, _ = _bisect(model, shape, w, a_prev, a, True, rtol, tol)
            runs += n
            out[2] = hi / a_ref
            state = "find_end"
        elif state == "find_end" and over:
            lo, hi, n, _ = _bisect(model, shape, w, a_prev, a, False, rtol, tol)
            runs += n
            out[3] = hi / a_ref
            break
        a_prev = a
        a *= scan
    return out[0], out[1], out[2], out[3], runs


def overturning_spectrum(
    model,
    omega_ratios,
    shape: str = "sine",
    *,
    rtol: float = RTOL,
    scan: float = SCAN,
    a_max: float = A_MAX,
    tol: float = TOL,
    executor: Executor | None = None,
) -> OverturningSpectrum:
    """Minimum overturning amplitude of ``model`` under one-cycle ``shape`` pulses.

    Parameters
    ----------
    model : RockingBlock or RockingFrame
    omega_ratios : array_like, shape (n,)
        omega_p / p.
    shape : {"sine", "cosine", "ricker", "rect"}
    rtol : float
        Relative width to which each amplitude is bisected.
    executor : concurrent.futures.Executor, optional
        Where the frequencies run (default: a local ProcessPoolExecutor).
    """
    x = np.asarray(omega_ratios, dtype=float)
    w0 = time.perf_counter()
    own = executor is None
    ex = ProcessPoolExecutor() if own else executor
    try:
        futs = [ex.submit(spectrum_point, model, shape, float(xi), rtol, scan, a_max, tol)
                for xi in x]  # fmt: skip
        pts = [f.result() for f in futs]
    finally:
        if own:
            ex.shutdown()
    arr = np.array([pt[:4] for pt in pts], dtype=float).reshape(-1, 4)
    return OverturningSpectrum(
        omega_ratio=x,
        a_min_ratio=arr[:, 0],
        mode=arr[:, 1].astype(int),
        safe_lo_ratio=arr[:, 2],
        safe_hi_ratio=arr[:, 3],
        shape=shape,
        alpha=model.alpha,
        p=model.p,
        n_runs=int(sum(pt[4] for pt in pts)),
        wall_s=time.perf_counter() - w0,
    )
