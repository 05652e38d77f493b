"""The accelerations and contact forces along a periodic orbit, by the period map's own
right-hand side.

On the contact manifold ``q = Q z`` the accelerations are ``qdd = Q zdd`` and the contact
forces are the multipliers ``lam`` that :func:`nsdyn.periodic._kproblems.frame_flat` solves
for (left in the scratch of its flat array ``pf``). :func:`orbit_forces` evaluates that
right-hand side at every sample of an orbit, called by its address (``K`` of
:func:`nsdyn.periodic.problem.periodic_calls`, slot ``"periodic.feval"``) as the period map
calls it: a sweep's orbit quantities then need no kernel of the full coordinates (the flat
right-hand side and its metrics kernel, ~4.4 s of a first sweep's compilation).
"""

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn.periodic._kproblems import FH_M, FH_NC, FH_NI, O_LAM, PROB_FRAME, _frame_offsets


@njit(cache=True, error_model="numpy")
def orbit_forces(prob, t, X, pf, ZDD, LAM, ok, K):
    """``ZDD[k]`` (the second half of the right-hand side at ``(t[k], X[k])``, nt x dim/2)
    and, for a frame, ``LAM[k]`` (its contact forces, nt x nc; no columns otherwise) along
    the samples of ``X`` (nt x dim); ``ok[k]`` False where the right-hand side failed
    (a singular constraint matrix: row k then holds scratch values)."""
    nt, d = X.shape
    half = d // 2
    o_lam = 0
    nc = 0
    if prob == PROB_FRAME:
        m, nc, ni = int(pf[FH_M]), int(pf[FH_NC]), int(pf[FH_NI])
        o_lam = _frame_offsets(m, nc, ni)[O_LAM]
    Y = np.empty(d)
    Fi = np.empty(d)
    for k in range(nt):
        for j in range(d):
            Y[j] = X[k, j]
        ok[k] = ka.call(K, "periodic.feval", (prob, t[k], Y, pf, Fi), None)
        for j in range(half):
            ZDD[k, j] = Fi[half + j]
        for a in range(nc):
            LAM[k, a] = pf[o_lam + a]
