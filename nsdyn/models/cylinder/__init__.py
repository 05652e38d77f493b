"""Rigid cylinder rocking, uplifting and rolling on a Winkler foundation in 3D (seed 000).

Base centre restrained horizontally, free vertically; unit-quaternion rotations; foundation
bonded, tensionless (contact = circular segment, closed-form resultants) or fixed.
"""

from pathlib import Path

from nsdyn._numba_cache import guard_family

# the kernels call each other across files, the shared Dormand–Prince steps and the dense LU
_NSDYN = Path(__file__).resolve().parents[2]
guard_family(__file__, [_NSDYN / "_kdp5.py", _NSDYN / "_klinalg.py", _NSDYN / "_kborrow.py"])

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
