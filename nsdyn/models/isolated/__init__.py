"""The isolated frame (seed 004): a frame on friction isolators, every fidelity one system.

``M q̈ + C* q̇ + K* q = −M Γ ü + Rᵀλ − Σ D_iᵀ μ_i s_i λ_i``, ``R q̈ + 2αβ R q̇ + α² R q = 0``.
"""

from nsdyn.models.isolated.system import (
    FIDELITIES,
    IsolatedSystem,
    Isolation,
    build_system,
    rigid_body_modes,
)

__all__ = ["FIDELITIES", "IsolatedSystem", "Isolation", "build_system", "rigid_body_modes"]
