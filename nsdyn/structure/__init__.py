"""Structure: 2D Bernoulli–Euler frame FEM, frame TOML files, Craig–Bampton reduction.

``K q = f`` and ``M q̈ + K q = f`` of the frame in global dofs (x, y, θ per node); the reduction
``q ≈ T z`` keeps boundary dofs and fixed-interface modes up to ``f_max``.
"""

from nsdyn.structure.elements import beam_mass, beam_stiffness, element_matrices, rotation
from nsdyn.structure.frame import Frame, Section, base_isolation_frequency, regular_frame
from nsdyn.structure.frame_toml import FrameFileError, bundled_frames, frame_from_dict, load_frame
from nsdyn.structure.reduction import (
    CBModel,
    craig_bampton,
    damping_ratios,
    fixed_base_modes,
    kinetic_energy_shares,
    mode_type,
    reduce_frame,
)

__all__ = [
    "CBModel",
    "Frame",
    "FrameFileError",
    "Section",
    "base_isolation_frequency",
    "beam_mass",
    "beam_stiffness",
    "bundled_frames",
    "craig_bampton",
    "damping_ratios",
    "element_matrices",
    "fixed_base_modes",
    "frame_from_dict",
    "kinetic_energy_shares",
    "load_frame",
    "mode_type",
    "reduce_frame",
    "regular_frame",
    "rotation",
]
