"""Dormand–Prince 5(4) tableau, stages, error estimate and dense output, shared by the explicit
numba kernels of the model families (rocking bodies, the cylinder).

Stages ``k_i = f(t + c_i h, y + h sum_j a_ij k_j)``, solution ``y1 = y + h sum_i b_i k_i``
(``b = a_7j``, first same as last), error ``h sum_i e_i k_i`` (5th minus 4th order), and the
4th-order continuous extension of Hairer, Nørsett & Wanner (dopri5)::

    y(t + s h) = r0 + s (r1 + (1-s) (r2 + s (r3 + (1-s) r4)))
    r0 = y, r1 = y1 - y, r2 = h k1 - r1, r3 = r1 - h k7 - r2, r4 = h sum d_i k_i
"""

from nsdyn import _kaddress as ka

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
C = (0.0, C2, C3, C4, C5, 1.0, 1.0)  # time of stage j (k_j) as a fraction of the step


@ka.compiled_only
def stage(y, k, h, j, out):
    """``out = y + h sum_m a_(j+1)m k_m``: the state at which stage ``k_j`` (j = 1..6) is
    evaluated, from the stages ``k`` (7, n) before it; j = 6 gives the solution ``y1``."""
    for i in range(y.shape[0]):
        if j == 1:
            out[i] = y[i] + h * A21 * k[0, i]
        elif j == 2:
            out[i] = y[i] + h * (A31 * k[0, i] + A32 * k[1, i])
        elif j == 3:
            out[i] = y[i] + h * (A41 * k[0, i] + A42 * k[1, i] + A43 * k[2, i])
        elif j == 4:
            out[i] = y[i] + h * (A51 * k[0, i] + A52 * k[1, i] + A53 * k[2, i] + A54 * k[3, i])
        elif j == 5:
            out[i] = y[i] + h * (
                A61 * k[0, i] + A62 * k[1, i] + A63 * k[2, i] + A64 * k[3, i] + A65 * k[4, i]
            )
        else:
            out[i] = y[i] + h * (
                A71 * k[0, i] + A73 * k[2, i] + A74 * k[3, i] + A75 * k[4, i] + A76 * k[5, i]
            )


@ka.compiled_only
def error(k, h, i):
    """Component ``i`` of the local error estimate ``h sum_m e_m k_m`` of a step of size h."""
    return h * (
        E1 * k[0, i] + E3 * k[2, i] + E4 * k[3, i] + E5 * k[4, i] + E6 * k[5, i] + E7 * k[6, i]
    )


@ka.compiled_only
def dense_coefficients(y, y1, k, h, rc):
    """The coefficients ``rc`` (5, n) of the continuous extension over the step ``y -> y1``."""
    for i in range(y.shape[0]):
        rc[0, i] = y[i]
        rc[1, i] = y1[i] - y[i]
        rc[2, i] = h * k[0, i] - rc[1, i]
        rc[3, i] = rc[1, i] - h * k[6, i] - rc[2, i]
        rc[4, i] = (
            h * (D1 * k[0, i] + D3 * k[2, i] + D4 * k[3, i] + D5 * k[4, i] + D6 * k[5, i])
            + h * D7 * k[6, i]
        )


@ka.compiled_only
def dense(rc, i, s):
    """Component ``i`` of the continuous extension at ``s`` in [0, 1]; ``rc`` shape (5, n)."""
    s1 = 1.0 - s
    return rc[0, i] + s * (rc[1, i] + s1 * (rc[2, i] + s * (rc[3, i] + s1 * rc[4, i])))


@ka.compiled_uncounted
def dense_state(rc, s, ys):
    """Every component of the continuous extension at ``s`` in [0, 1], into ``ys``."""
    for i in range(ys.shape[0]):
        ys[i] = dense(rc, i, s)


@ka.compiled_only
def new_step(h, err):
    """Next step size from the scaled error norm ``err`` of a step of size ``h``."""
    if err <= 0.0:
        return h * FAC_MAX
    fac = SAFETY * err ** (-0.2)
    return h * min(FAC_MAX, max(FAC_MIN, fac))
