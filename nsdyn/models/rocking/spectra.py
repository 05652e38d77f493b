"""Overturning spectra: the minimum pulse amplitude that overturns a rocking block (or frame)
as a function of the pulse frequency, by bracketing and bisection.

For each ``omega_p / p`` the amplitude ratio ``a_p / a_lift`` is scanned geometrically from 1
(no lift-off below; a_lift = g tan alpha, g alpha for a linearised model, the unit of every
amplitude it reports: :attr:`OverturningSpectrum.unit`) by the factor ``scan`` up to ``a_max``
(its last point); each change of outcome (safe <-> overturned) is then bisected to the relative
width ``rtol``. Reported: the minimum overturning amplitude with its mode (1: overturns after
at least one impact, 2: without an impact, Zhang & Makris 2001), and the first safe band above
the minimum (for one-sine pulses the literature reports such a band: overturning with one
impact at the minimum, then safe, then overturning without impact). Such a band is often
narrower than one scan factor (0.1 to 3 % of the amplitude at omega_p / p = 1 to 3), so the
scan alone steps over it. It separates the two overturning mechanisms, so where two overturning
scan points differ in mode (impact before, none after) the interval between them is searched by
bisection on the mode: a safe midpoint is the band (its edges are then bisected), otherwise the
half with the mode change is kept, down to ``rtol``. What remains unseen: a band narrower than
``rtol`` there, or one narrower than a scan factor where the mode does not change.

Each frequency gets a status word, so that NaN never stands unexplained (``STATUS``):
``no overturning up to a_max`` (a_min NaN: none found up to the scan's end, not "absent"),
``no safe band found`` (overturns from a_min on as far as the search sees), ``safe band``
(between safe_lo and safe_hi) and ``safe up to a_max`` (safe_hi NaN).

Frequencies run in parallel on any :class:`concurrent.futures.Executor` (local processes by
default); each task is a top-level function of plain values, so it pickles.
"""

from __future__ import annotations

import math
import time
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import dataclass

import numpy as np

from nsdyn._brief import brief_repr
from nsdyn._checks import RTOL_MIN, finite_numbers, number
from nsdyn.ground.pulses import SHAPES, Pulse
from nsdyn.models.rocking.block import OMEGA_RATIO_MAX, TOL, simulate_rocking

RTOL = 1e-4  # relative width of the bisected amplitude brackets
SCAN = 1.1  # geometric scan factor of the amplitude
A_MAX = 30.0  # largest amplitude ratio a_p / a_lift scanned
# slowest pulse: 1e-2 of p, quasi-static (the seed 003 column overturns at a_p = 1.0001 g tan
# alpha there); omega_p / p = 1e-300 stepped through a pulse of 1e300 s until the step underflowed
OMEGA_RATIO_MIN = 1e-2
# the largest a_max: at the fastest pulse the seed 003 column overturns at 4.2e4 g tan alpha; a
# scan with no overturning up to 1e300 ended in a step size underflow
A_MAX_LIMIT = 1e6
T_AFTER_P = 25.0  # free time after the pulse, in units of 1/p (slow falls near the threshold)
STATUS = ("no overturning up to a_max", "no safe band found", "safe band", "safe up to a_max")


def status_word(a_min: float, safe_lo: float, safe_hi: float) -> str:
    """The status of one spectrum point (module text) from its three ratios."""
    if math.isnan(a_min):
        return STATUS[0]
    if math.isnan(safe_lo):
        return STATUS[1]
    return STATUS[3] if math.isnan(safe_hi) else STATUS[2]


@dataclass(repr=False)
class OverturningSpectrum:
    """Overturning amplitudes against frequency (ratios; nan where not found).

    Attributes
    ----------
    omega_ratio : ndarray, shape (n,)
        omega_p / p.
    a_min_ratio : ndarray, shape (n,)
        Minimum overturning a_p / a_lift (nan: none up to a_max); a_lift is :attr:`unit`.
    mode : ndarray of int, shape (n,)
        1: overturning after an impact, 2: without impact, 0: none found.
    safe_lo_ratio, safe_hi_ratio : ndarray, shape (n,)
        First safe band above the minimum (nan if none found; hi nan: safe up to a_max).
    status : list of str
        One of ``STATUS`` per frequency: what a NaN above means.
    a_max, scan, rtol : float
        The search: amplitudes scanned up to a_max (ratio) by the factor scan, edges to rtol.
    linear : bool
        The model was linearised: its ratios are to g alpha, not g tan alpha (:attr:`unit`).
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
    status: list | None = None
    a_max: float = A_MAX
    scan: float = SCAN
    rtol: float = RTOL
    linear: bool = False

    __repr__ = brief_repr  # arrays by shape, not in full

    @property
    def unit(self) -> str:
        """The amplitudes' unit, the model's lift-off acceleration: "g tan alpha", or "g alpha"
        for a linearised model (a linear frame's 1.0001 at slow pulses was printed as if in
        g tan alpha, 20 % off at alpha = 0.7)."""
        return "g alpha" if self.linear else "g tan alpha"

    COLUMNS = ("omega_ratio", "a_min_ratio", "mode", "safe_lo_ratio", "safe_hi_ratio", "status")

    def summary(self) -> dict:
        """The spectrum as plain values (NaN as None; what ``nsdyn spectrum --json`` prints):
        the block's ``alpha_rad`` and ``p_per_s``, the pulse ``shape``, ``n_runs``, ``wall_s``,
        the ratios' ``amplitude_unit`` (:attr:`unit`), one list per column of :attr:`COLUMNS`
        and the ``search`` (a_max ratio, scan, rtol)."""

        def plain(a):
            return [None if math.isnan(v) else float(v) for v in a]

        return {"shape": self.shape, "alpha_rad": self.alpha, "p_per_s": self.p,
                "n_runs": self.n_runs, "wall_s": self.wall_s, "amplitude_unit": self.unit,
                "omega_ratio": self.omega_ratio.tolist(), "a_min_ratio": plain(self.a_min_ratio),
                "mode": self.mode.tolist(), "safe_lo_ratio": plain(self.safe_lo_ratio),
                "safe_hi_ratio": plain(self.safe_hi_ratio), "status": list(self.status or []),
                "search": {"a_max_ratio": self.a_max, "scan": self.scan,
                           "rtol": self.rtol}}  # fmt: skip

    def to_dataframe(self):
        """A pandas DataFrame, one row per frequency indexed by ``omega_ratio``, the columns of
        :attr:`COLUMNS` (NaN kept, the arrays copied), ``df.attrs`` the summary's scalars
        (needs the ``frames`` extra)."""
        from nsdyn._tabular import _need

        pd = _need("pandas")
        cols = {k: np.array(getattr(self, k)) for k in self.COLUMNS[1:]}
        cols["status"] = list(self.status or [])
        df = pd.DataFrame(cols, index=pd.Index(self.omega_ratio.copy(), name="omega_ratio"))
        df.attrs.update({k: v for k, v in self.summary().items() if not isinstance(v, list)})
        return df


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


def _find_gap(model, shape, w, lo, hi, rtol, tol):
    """A safe amplitude between ``lo`` (overturns after an impact) and ``hi`` (overturns
    without), by bisection on the mode; returns (safe amplitude or None, lo, hi, runs)."""
    runs = 0
    while hi - lo > rtol * hi:
        a_m = math.sqrt(lo * hi)
        over, ni = _overturns(model, shape, w, a_m, tol)
        runs += 1
        if not over:
            return a_m, lo, hi, runs
        if ni > 0:
            lo = a_m
        else:
            hi = a_m
    return None, lo, hi, runs


def spectrum_point(model, shape: str, omega_ratio: float, rtol: float = RTOL,
                   scan: float = SCAN, a_max: float = A_MAX, tol: float = TOL):  # fmt: skip
    """(a_min, mode, safe_lo, safe_hi, runs) at one omega_p / p (amplitudes / a_lift)."""
    w = omega_ratio * model.p
    a_ref = model.uplift_accel
    runs = 0
    a_prev = a_ref
    out = [math.nan, 0, math.nan, math.nan]
    state = "find_over"
    a = a_ref * (1.0 + 1e-6)
    ni_prev = -1  # impacts before overturning at the last overturning scan point
    while a <= a_max * a_ref:
        over, ni = _overturns(model, shape, w, a, tol)
        runs += 1
        if state == "find_safe" and over and ni == 0 and ni_prev > 0:
            # the mechanism changed between two overturning points: a band hides there?
            s, lo, hi, n = _find_gap(model, shape, w, a_prev, a, rtol, tol)
            runs += n
            if s is not None:
                _, edge, n, _ = _bisect(model, shape, w, lo, s, True, rtol, tol)
                out[2] = edge / a_ref
                _, edge, m, _ = _bisect(model, shape, w, s, hi, False, rtol, tol)
                out[3] = edge / a_ref
                runs += n + m
                break
        if over:
            ni_prev = ni
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
        a_prev = a  # the scan ends at a_max itself (a scan of 1e300 probed 1 alone and said
        a = a * scan if a >= a_max * a_ref else min(a * scan, a_max * a_ref)  # "none up to it")
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
    from nsdyn.models.rocking.compliant import CompliantBlock

    if isinstance(model, CompliantBlock) or not hasattr(model, "uplift_accel"):
        raise TypeError(f"model: expected a RockingBlock or RockingFrame (Housner's rigid "
                        f"rocking), got {type(model).__name__}")  # fmt: skip
    lo_hi = f"[{OMEGA_RATIO_MIN:g}, {OMEGA_RATIO_MAX:g}]"
    what = f"frequency ratios omega_p / p (a 1-D list) in {lo_hi}"
    one = [omega_ratios] if np.ndim(omega_ratios) == 0 else omega_ratios  # ([[1, 2]], True ran)
    x = finite_numbers("omega_ratios", one, what)
    if not np.all((x >= OMEGA_RATIO_MIN) & (x <= OMEGA_RATIO_MAX)):
        raise ValueError(f"omega_ratios: expected {what}, got {omega_ratios!r}")
    # (text: a TypeError from a comparison)
    number("rtol", rtol, f"a relative width {RTOL_MIN:.2g} <= rtol < 1 (a bisection narrower "
           "than round-off never ends)", lambda v: RTOL_MIN <= v < 1.0)  # fmt: skip
    number("scan", scan, "a growth factor > 1 of the bracketing scan", lambda v: v > 1.0)
    number("a_max", a_max, f"a largest amplitude ratio in (0, {A_MAX_LIMIT:g}]",
           lambda v: 0.0 < v <= A_MAX_LIMIT)  # fmt: skip
    number("tol", tol, "a positive integration tolerance", lambda v: v > 0.0)
    if not isinstance(shape, str) or shape not in SHAPES:  # (refused inside every worker,
        # after the pool had started)
        raise ValueError(f"shape: expected one of {sorted(SHAPES)}, got {shape!r}")
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise TypeError(f"executor: expected a concurrent.futures.Executor, got "
                        f"{type(executor).__name__}")  # fmt: skip
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
    status = [status_word(r[0], r[2], r[3]) for r in arr]
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
        status=status,
        a_max=float(a_max),
        scan=float(scan),
        rtol=float(rtol),
        linear=bool(model.linear),
    )
