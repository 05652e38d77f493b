"""Solve: transient integration of the models, every method behind one front door.

:func:`nsdyn.solve.integrate.solve` integrates ``ẋ = f(t, x)`` of a packed system with a method
chosen by name (``radau``, ``dopri5``, ``genalpha``, ``hht``, ``newmark``, ``event``);
:func:`nsdyn.solve.transient.simulate` runs a system under a ground motion from its static
equilibrium and returns histories and metrics.
"""

from nsdyn.solve.integrate import (
    METHODS,
    IntegrationError,
    Solution,
    UpliftError,
    UpliftWarning,
    solve,
    warmup,
)
from nsdyn.solve.transient import TransientResult, simulate

__all__ = [
    "METHODS",
    "IntegrationError",
    "Solution",
    "TransientResult",
    "UpliftError",
    "UpliftWarning",
    "simulate",
    "solve",
    "warmup",
]
