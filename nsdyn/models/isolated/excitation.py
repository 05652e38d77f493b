"""The excitation channels of a packed system ``P`` along a history, by numpy.

:func:`ground_many` is the system kernel's :func:`nsdyn.models.isolated._kernel.ground_accel`
at many times: the same floating-point operations element by element (the record's linear
interpolation; the harmonic's sine through the C library's ``sin``, which compiled code calls
too), so the same floats, and no run compiles a kernel for it (its Python entry point alone,
for ``P``'s tuple of arrays, took ~0.6 s of a first run's compilation).
"""

from __future__ import annotations

import math

import numpy as np

from nsdyn.models.isolated import _kernel as ks


def ground_many(t, P) -> np.ndarray:
    """Ground acceleration [u_hor, u_ver] (without g) at the times ``t``, shape (nt, 2)."""
    t = np.ascontiguousarray(t, dtype=float).reshape(-1)
    gp = P[ks.I_GPAR]
    out = np.zeros((t.shape[0], 2))
    if P[ks.I_IPAR][ks.K_GROUND] == ks.GROUND_HARMONIC:
        for col, (a, f, ph) in enumerate(
            ((ks.G_AH, ks.G_FH, ks.G_PH), (ks.G_AV, ks.G_FV, ks.G_PV))
        ):
            w = 2.0 * math.pi * gp[f]  # the kernel's 2.0 * np.pi * f * t + phase, left to right
            out[:, col] = [gp[a] * math.sin(w * tk + gp[ph]) for tk in t.tolist()]
        return out
    a_h, a_v = P[ks.I_AH], P[ks.I_AV]
    npts = a_h.shape[0]
    if npts == 0:
        return out
    s = (t - gp[ks.G_T0]) / gp[ks.G_DT]
    k = np.floor(s)
    inside = (s >= 0.0) & (k < npts - 1)  # s < 0 and past the record: 0 (the kernel's)
    kk = k[inside].astype(np.int64)
    w = s[inside] - k[inside]
    out[inside, 0] = (1.0 - w) * a_h[kk] + w * a_h[kk + 1]
    out[inside, 1] = (1.0 - w) * a_v[kk] + w * a_v[kk + 1]
    last = (k == npts - 1) & (s == k)  # exactly on the last sample
    out[last, 0] = a_h[npts - 1]
    out[last, 1] = a_v[npts - 1]
    return out
