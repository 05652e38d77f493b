"""Dormand–Prince 5(4) tableau, error weights and dense output, shared by the explicit numba
kernels of the model families (rocking bodies, the cylinder).

Stages ``k_i = f(t + c_i h, y + h sum_j a_ij k_j)``, solution ``y1 = y + h sum_i b_i k_i``
(``b = a_7j``, first same as last), error ``h sum_i e_i k_i`` (5th minus 4th order), and the
4th-order continuous extension of Hairer, Nørsett & Wanner (dopri5)::

    y(t + s h) = r0 + s (r1 + (1-s) (r2 + s (r3 + (1-s) r4)))
    r0 = y, r1 = y1 - y, r2 = h k1 - r1, r3 = r1 - h k7 - r2, r4 = h sum d_i k_i
"""

from numba import njit

C2, C3, C4, C5 = 0.2, 0.3, 0.8, 8.0 / 9.0
A21 = 0.2
A31, A32 = 3.0 / 40.0, 9.0 / 40.0
A41, A42, A43 = 44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0
A51, A52, A53, A54 = 19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0
A61, A62, A63 = 9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0
A64, A65 = 49.0 / 176.0, -5103.0 / 18656.0
A71, A73, A74 = 35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0
A75, A76 = -2187.0 / 6784.0, 11.0 / 84.0
E1, E3, E4 = 71.0 / 57600.0, -71.0 / 16695.0, 71.0 / 1920.0
E5, E6, E7 = -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0
D1, D3 = -12715105075.0 / 11282082432.0, 87487479700.0 / 32700410799.0
D4, D5 = -10690763975.0 / 1880347072.0, 701980252875.0 / 199316789632.0
D6, D7 = -1453857185.0 / 822651844.0, 69997945.0 / 29380423.0
SAFETY = 0.9  # step-size controller safety factor
FAC_MIN = 0.2  # smallest step shrink factor
FAC_MAX = 5.0  # largest step growth factor


@njit(cache=True)
def dense(rc, i, s):
    """Component ``i`` of the continuous extension at ``s`` in [0, 1]; ``rc`` shape (5, n)."""
    s1 = 1.0 - s
    return rc[0, i] + s * (rc[1, i] + s1 * (rc[2, i] + s * (rc[3, i] + s1 * rc[4, i])))


@njit(cache=True)
def new_step(h, err):
    """Next step size from the scaled error norm ``err`` of a step of size ``h``."""
    if err <= 0.0:
        return h * FAC_MAX
    fac = SAFETY * err ** (-0.2)
    return h * min(FAC_MAX, max(FAC_MIN, fac))
