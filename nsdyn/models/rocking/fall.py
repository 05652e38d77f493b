"""The first instant the ground falls at g or faster (g + ü_v <= 0) under a rigid rocking model.

Free flight is not modelled (the rigid block and frame keep a corner on the ground), so a run
stops there with a numerical failure. The kernel checks the ground at each step's start only:
a dip below -g shorter than a step went unseen, and one inside a step ending in an impact was
said at the impact. Found here before the run, exactly: a record is linear between its
samples, and a closed-form pulse's vertical is monotone between the instants taken here (its
ends, a sine's or cosine's quarter periods, a Ricker wavelet's centre and its ±√6/ω_p), so
the first segment reaching -g holds the crossing, bisected to round-off.
"""

from __future__ import annotations

import math

import numpy as np

from nsdyn.models.rocking._kground import GK_PULSE, GK_TABLE

SINE, COSINE, RECT = 1, 2, 4  # the pulse codes of nsdyn.ground.pulses.SHAPES (else Ricker)


def first_fall(gk: int, gp: np.ndarray, tab_v: np.ndarray, t0: float, t_end: float,
               g: float) -> float | None:  # fmt: skip
    """The first time in [t0, t_end] with g + ü_v <= 0 for the kernel's excitation (``gk``,
    ``gp``, ``tab_v`` of :func:`nsdyn.models.rocking.block._excitation`), or None."""
    if gk == GK_TABLE:
        return _table_fall(gp, tab_v, t0, t_end, g)
    if gk == GK_PULSE and gp[5] != 0.0:
        return _pulse_fall(gp, t0, t_end, g)
    return None


def _table_fall(gp, tab_v, t0, t_end, g):
    if gp[2] < 0.5:  # no vertical component
        return None
    t_rec = gp[0] + gp[1] * np.arange(tab_v.size)
    lo, hi = max(t0, t_rec[0]), min(t_end, t_rec[-1])  # (0 outside the record, as the
    if not lo < hi:  # kernel's: no ramp from t0 to a late record's first sample)
        return None
    inside = (t_rec > lo) & (t_rec < hi)
    ts = np.concatenate(([lo], t_rec[inside], [hi]))
    f = g + np.interp(ts, t_rec, tab_v)
    bad = np.flatnonzero(f <= 0.0)
    if bad.size == 0:
        return None
    j = int(bad[0])
    if j == 0:  # (at a late record's first sample: the jump the kernel feels there)
        return float(lo)
    return _open_end(ts[j - 1] + (ts[j] - ts[j - 1]) * f[j - 1] / (f[j - 1] - f[j]), hi)


def _open_end(t: float, hi: float) -> float | None:
    """``t``, or None at the window's end ``hi`` itself: after a record's last sample or a
    pulse's end the kernel feels no ground (its right limit, 0), and the run ends at t_end."""
    return None if t >= hi else float(t)


def _pulse_fall(gp, t0, t_end, g):
    shape, a_p, w, dur, t_s, ratio, t_c = int(gp[0]), *(float(v) for v in gp[1:7])

    def f(t):  # g + ü_v inside the pulse (its closed form, continued to the ends)
        tau = t - t_s
        if shape == SINE:
            a = math.sin(w * tau)
        elif shape == COSINE:
            a = math.cos(w * tau)
        elif shape == RECT:
            a = 1.0
        else:
            s2 = (w * (tau - t_c)) ** 2
            a = (1.0 - 0.5 * s2) * math.exp(-0.25 * s2)
        return g + ratio * a_p * a

    lo, hi = max(t0, t_s), min(t_end, t_s + dur)
    if not lo < hi:
        return None
    if shape in (SINE, COSINE):
        first = 0.5 if shape == SINE else 0.0  # extremes at (k + first) pi / w after the start
        k = np.arange(math.floor((lo - t_s) * w / math.pi - first),
                      math.ceil((hi - t_s) * w / math.pi - first) + 1)  # fmt: skip
        ext = t_s + (k + first) * math.pi / w
    elif shape == RECT:
        ext = np.zeros(0)
    else:
        ext = t_s + t_c + np.array([-1.0, 0.0, 1.0]) * math.sqrt(6.0) / w
    cuts = np.unique(np.concatenate(([lo, hi], ext[(ext > lo) & (ext < hi)])))
    for a, b in zip(cuts[:-1], cuts[1:], strict=True):
        fa, fb = f(a), f(b)
        if fa <= 0.0:
            return float(a)
        if fb <= 0.0:  # monotone on [a, b]: one crossing, bisected
            for _ in range(200):
                m = 0.5 * (a + b)
                if not a < m < b:
                    break
                if f(m) <= 0.0:
                    b = m
                else:
                    a = m
            return _open_end(b, hi)
    return None
