"""Rigid cylinder rocking, uplifting and rolling on a Winkler foundation in 3D (seed 000).

Base centre restrained horizontally, free vertically; unit-quaternion rotations; foundation
bonded, tensionless (contact = circular segment, closed-form resultants) or fixed.
"""

from nsdyn._numba_cache import guard_family

guard_family(__file__)  # the kernels call each other across files

# ruff: noqa: E402

from nsdyn.models.cylinder.design import (
    design_foundation,
    rocking_frequency,
    static_settlement,
    uplift_onset,
)
from nsdyn.models.cylinder.params import FOUNDATIONS, CylinderParams
from nsdyn.models.cylinder.simulate import (
    CylinderResult,
    SimulationError,
    earthquake,
    from_motions,
    simulate,
)
from nsdyn.models.cylinder.study import compare_foundations

__all__ = [
    "FOUNDATIONS",
    "CylinderParams",
    "CylinderResult",
    "SimulationError",
    "compare_foundations",
    "design_foundation",
    "earthquake",
    "from_motions",
    "rocking_frequency",
    "simulate",
    "static_settlement",
    "uplift_onset",
]
