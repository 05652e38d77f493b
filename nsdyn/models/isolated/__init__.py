"""The isolated frame (seed 004): a frame on friction isolators, every fidelity one system.

``M q̈ + C* q̇ + K* q = −M Γ ü + Rᵀλ − Σ D_iᵀ μ_i s_i λ_i``, ``R q̈ + 2αβ R q̇ + α² R q = 0``.
Isolators that slide in a plane (a disc of friction, friction pendulums, a rigid deck):
``bearings``, ``deck`` (``simulate_plane``); any system from matrices on them: ``pairs``
(``PairSystem``, ``simulate_pairs``).

The names below load on first use, so that light modules (``defaults``, ``friction``) can be
imported by the command line without compiling or importing the kernels.
"""

from nsdyn._lazy import exports

_API = {
    "FIDELITIES": "nsdyn.models.isolated.system",
    "IsolatedSystem": "nsdyn.models.isolated.system",
    "Isolation": "nsdyn.models.isolated.system",
    "build_system": "nsdyn.models.isolated.system",
    "rigid_body_modes": "nsdyn.models.isolated.system",
    "shear_building": "nsdyn.models.isolated.builders",
    "system_from_matrices": "nsdyn.models.isolated.builders",
    "Bearing": "nsdyn.models.isolated.bearings",
    "Friction": "nsdyn.models.isolated.bearings",
    "BearingError": "nsdyn.models.isolated.bearings",
    "TripleBearing": "nsdyn.models.isolated.tfp",
    "PlaneSystem": "nsdyn.models.isolated.deck",
    "rigid_deck": "nsdyn.models.isolated.deck",
    "sdof_plane": "nsdyn.models.isolated.deck",
    "simulate_plane": "nsdyn.models.isolated.deck",
    "PairSystem": "nsdyn.models.isolated.pairs",
    "PairSystemError": "nsdyn.models.isolated.pairs",
    "PairResult": "nsdyn.models.isolated.pairs",
    "simulate_pairs": "nsdyn.models.isolated.pairs",
    "building_deck": "nsdyn.models.isolated.building3d",
    "deck_constants": "nsdyn.models.isolated.building3d",
    "base_forces": "nsdyn.models.isolated.building3d_response",
    "base_force_peaks": "nsdyn.models.isolated.building3d_response",
    "FixedResponse3D": "nsdyn.models.isolated.fixed3d",
    "fixed_response_3d": "nsdyn.models.isolated.fixed3d",
}

__all__ = sorted(_API)


__getattr__, __dir__ = exports(globals(), _API)
