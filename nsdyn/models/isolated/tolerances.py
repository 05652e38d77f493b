"""Default tolerances of an earthquake run of the isolated frame (scene, ``simulate``, bench).

The low-level ``nsdyn.solve.integrate.solve`` has its own, tighter reference defaults
(``SOLVE_RTOL``, ``SOLVE_ATOL``).
"""

# Default tolerances of an earthquake run (m for displacements, m/s for velocities): every
# output converged, at 5-9x fewer steps than rtol 1e-6, atol 1e-8. Measured on the office frame
# (CB-5) under the bundled 40 s record and the four Kobe records at PGA 3 m/s^2 against runs at
# rtol 1e-8 (README, "Tolerances and accuracy"): x_iso history within 1e-6, peak IDR within
# 1e-7, peak floor acceleration within 1e-4, the base-level acceleration within 1.1e-3.
# The base level is the sensitive output: it carries the undamped kHz modes of the stiff base
# diaphragm, rung by every kink of a sampled record. A velocity atol of 1e-4 leaves them to
# Radau's damping (x_iso, IDR and the accelerations of the storeys above still within 1e-4,
# ~1.8x fewer steps) but the base-level peak acceleration is then wrong by a factor of up to 4.
# The event-driven switch model locates stick at v = 0 and its base-level jolts need 1e-7 (at
# 1e-4 it missed half of the stick phases on KJMA and doubled the peak floor acceleration; at
# 1e-6 the base-level peak was 3.5 % off on the bundled record).
RUN_RTOL = 1e-4
# what the default run (radau at RUN_RTOL, RUN_ATOL) is held to (tests/solve/test_flat_rhs.py):
# every reported response within RUN_RTOL of a much tighter run, the base-level acceleration
# within this (its kHz modes); the event method's base level is looser (transient page table)
BASE_ACC_TARGET = 2e-3
RUN_ATOL = (1e-8, 1e-6)
RUN_ATOL_BY_METHOD = {"event": (1e-8, 1e-7)}
FAST_ATOL = (1e-8, 1e-4)  # arctan + radau when the base-level acceleration is not needed
# the regularised law's velocity tolerance is at most this / eps [m/s]: its transition from
# stick to slip spans |v| ~ 1/eps, and a tolerance above that lets the error control accept
# any friction direction in stick (a held deck then slides; a sharp law's slip read 16 % low)
ATOL_V_EPS = 0.1


def run_atol(method: str) -> tuple[float, float]:
    """Default (displacement, velocity) atol of an earthquake run with ``method``."""
    return RUN_ATOL_BY_METHOD.get(method, RUN_ATOL)


def arctan_atol(atol, eps: float) -> tuple[float, float]:
    """(displacement, velocity) atol of an adaptive run of the arctan law of sharpness
    ``eps`` [s/m]: the velocity tolerance capped at ``ATOL_V_EPS / eps``."""
    a_d, a_v = (atol, atol) if isinstance(atol, int | float) else (float(atol[0]), float(atol[1]))
    return float(a_d), min(float(a_v), ATOL_V_EPS / float(eps))
