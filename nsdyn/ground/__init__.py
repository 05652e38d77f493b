"""Ground: the excitations every model is driven by.

Ground motions (``GroundMotion``: ü_hor(t), ü_ver(t) in m/s² on t_k = t0 + k Δt), their readers
and writers, the bundled and shared record libraries, synthesis (modulated white noise,
Kanai–Tajimi, sine pulses) and the analytic excitations (``Harmonic``, ``Table``) the kernels
evaluate directly. Three components: ``GroundMotion3`` (a_x, a_y, a_z; rotation of the horizontal
pair) and ``HarmonicPlane`` (linear, circular and elliptical harmonic orbits).
"""

from nsdyn.ground.excitation import G_EARTH, ForceTable, Harmonic, HarmonicForce, Table
from nsdyn.ground.library import bundled_records, default_shared_dir, kobe_records
from nsdyn.ground.motion import (
    G_STANDARD,
    GroundMotion,
    RecordFileError,
    UnitError,
    UnitWarning,
    unit_factor,
)
from nsdyn.ground.motion3 import GroundMotion3
from nsdyn.ground.orbit import HarmonicPlane
from nsdyn.ground.readers import (
    read_at2,
    read_jma,
    read_motion,
    read_multi_column,
    read_single_column,
    read_two_column,
    write_motion,
)
from nsdyn.ground.readers3 import bundled_records3, read_motion3, write_motion3
from nsdyn.ground.synthesis import (
    harmonic,
    kanai_tajimi,
    kanai_tajimi_psd,
    modulated_white_noise,
    shinozuka_envelope,
    sine_pulse,
)
from nsdyn.ground.table3 import motion3_from_table

__all__ = [
    "ForceTable",
    "HarmonicForce",
    "G_EARTH",
    "G_STANDARD",
    "GroundMotion",
    "GroundMotion3",
    "Harmonic",
    "HarmonicPlane",
    "RecordFileError",
    "Table",
    "UnitError",
    "UnitWarning",
    "bundled_records",
    "bundled_records3",
    "default_shared_dir",
    "harmonic",
    "kanai_tajimi",
    "kanai_tajimi_psd",
    "kobe_records",
    "modulated_white_noise",
    "motion3_from_table",
    "read_at2",
    "read_jma",
    "read_motion",
    "read_motion3",
    "read_multi_column",
    "read_single_column",
    "read_two_column",
    "shinozuka_envelope",
    "sine_pulse",
    "unit_factor",
    "write_motion",
    "write_motion3",
]
