"""Structure: 2D and 3D Bernoulli–Euler frame FEM, frame TOML files, Craig–Bampton reduction.

``K q = f`` and ``M q̈ + K q = f`` of the frame in global dofs (x, y, θ per node); the reduction
``q ≈ T z`` keeps boundary dofs and fixed-interface modes up to ``f_max``.
"""

from nsdyn.structure.building3d import regular_building_3d
from nsdyn.structure.elements import beam_mass, beam_stiffness, element_matrices, rotation
from nsdyn.structure.elements3d import beam3d_mass, beam3d_stiffness, local_axes
from nsdyn.structure.frame import Frame, Section, base_isolation_frequency, regular_frame
from nsdyn.structure.frame3d import Diaphragm, Frame3D, Section3D, planar_dofs
from nsdyn.structure.frame3d_toml import frame3d_from_dict, is_frame3d, load_frame3d
from nsdyn.structure.frame_toml import FrameFileError, bundled_frames, frame_from_dict, load_frame
from nsdyn.structure.modes3d import Modes3D, fixed_base_modes_3d
from nsdyn.structure.reduction import (
    CBModel,
    craig_bampton,
    damping_ratios,
    fixed_base_modes,
    kinetic_energy_shares,
    mode_type,
    reduce_frame,
)
from nsdyn.structure.reduction3d import CBModel3D, craig_bampton_3d
from nsdyn.structure.storey3d import (
    StoreyDrifts,
    accidental_eccentricity,
    floor_motions,
    storey_drifts_3d,
)

__all__ = [
    "CBModel",
    "CBModel3D",
    "StoreyDrifts",
    "accidental_eccentricity",
    "craig_bampton_3d",
    "floor_motions",
    "storey_drifts_3d",
    "Diaphragm",
    "Frame3D",
    "Modes3D",
    "Section3D",
    "beam3d_mass",
    "beam3d_stiffness",
    "fixed_base_modes_3d",
    "frame3d_from_dict",
    "is_frame3d",
    "load_frame3d",
    "local_axes",
    "planar_dofs",
    "regular_building_3d",
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
