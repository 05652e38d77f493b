"""Kernels of the deck's ground motion: three components from a table or a harmonic orbit.

``gk`` says which: G_TABLE, a record (t0, dt in ``gp``; rows a_x, a_y, a_z of ``tab``,
linearly interpolated, zero outside it), or G_HARMONIC, an orbit (``gp``: f, A_x, A_y, φ_y,
A_z, f_z, φ_z) with a_x = A_x sin ωt, a_y = A_y sin(ωt + φ_y), a_z = A_z sin(ω_z t + φ_z).
Packed by :func:`nsdyn.models.isolated.deck.pack_ground`; the time loops step onto the
table's samples (:func:`next_breakpoint`), the kinks of the interpolated record.
"""

import math

from numba import njit

G_TABLE, G_HARMONIC = 0, 1
GP_T0, GP_DT, GP_F, GP_AX, GP_AY, GP_PHY, GP_AZ, GP_FZ, GP_PHZ = range(9)
N_GP = 9


@njit(cache=True, error_model="numpy")
def ground(t, gk, gp, tab, ag):
    """Ground acceleration (a_x, a_y, a_z) at t into ``ag``: harmonic a_x = A_x sin ωt,
    a_y = A_y sin(ωt + φ_y), a_z = A_z sin(ω_z t + φ_z); or the table linearly interpolated
    (zero outside the record)."""
    if gk == G_HARMONIC:
        w = 2.0 * math.pi * gp[GP_F]
        ag[0] = gp[GP_AX] * math.sin(w * t)
        ag[1] = gp[GP_AY] * math.sin(w * t + gp[GP_PHY])
        ag[2] = gp[GP_AZ] * math.sin(2.0 * math.pi * gp[GP_FZ] * t + gp[GP_PHZ])
        return
    n = tab.shape[1]
    s = (t - gp[GP_T0]) / gp[GP_DT]
    k = int(math.floor(s))
    if k < 0 or k > n - 1 or n == 0:
        ag[0] = 0.0
        ag[1] = 0.0
        ag[2] = 0.0
        return
    if k == n - 1:
        for c in range(3):
            ag[c] = tab[c, k] if s == k else 0.0
        return
    f = s - k
    for c in range(3):
        ag[c] = (1.0 - f) * tab[c, k] + f * tab[c, k + 1]


@njit(cache=True, error_model="numpy")
def next_breakpoint(t, gk, gp, ntab):
    """Next sample time of a table after t (the kinks of the interpolated record); inf else."""
    if gk != G_TABLE or ntab < 2:
        return math.inf
    k = math.floor((t - gp[GP_T0]) / gp[GP_DT]) + 1.0
    tb = gp[GP_T0] + k * gp[GP_DT]
    if tb <= t + 1e-14 * (1.0 + abs(t)):  # at t to round-off: the next one (any sign of t)
        tb += gp[GP_DT]
    if k > ntab - 1 and tb > gp[GP_T0] + (ntab - 1) * gp[GP_DT] * (1.0 + 1e-14):
        return math.inf
    return tb
