"""The isolator's default parameters (seed 004), in one place for the library, scenes and CLI.

Light on purpose (no numba, no scipy): the command line reads it while building its parser.
"""

import math

K_LAM = 5.0e4  # N/m, lateral stiffness of one laminated rubber bearing (seed 004 eq 16)
C_DAMPER = 1.0e4  # N s/m, viscous damper of one isolator (seed 004 eq 16)
MU = 0.03  # friction coefficient of the sliding isolators (seed 004 §5, eq 16)
EPS = 7500.0  # arctan law's sharpness ε [s/m] (seed 004 §4)
# the arctan law's sharpest eps [s/m]: its turn (|v| ~ 1/eps) at least ten times the velocity
# gravity adds in the solvers' smallest step (g x 1e-12 s, nsdyn.solve._kcommon.MIN_STEP):
# 1/(10 x 9.81 x 1e-12) ~ 1e10. The default scene's 40 s ran at 1e10 and stopped on step
# underflow at 1e11 (6.0 s) and 1e12 (4.5 s); at 1e300 the law's slope overflowed into a NaN
# blamed on the record. Sharper is the switch law's (true stick).
EPS_MAX = 1e10
ETA = 1e-5  # switch model's stick band η [m/s] (seed 004 §4)
ALPHA = 2 * math.pi  # Baumgarte α [1/s] (seed 004 §4, with eq 13)
BETA = 1.0  # Baumgarte β [-]
F_MAX = 5.0  # Hz, Craig–Bampton cut-off (seed 004: 13 dofs)
FRAME = "office-11"  # the default scene's frame (seed 004's office), bundled
