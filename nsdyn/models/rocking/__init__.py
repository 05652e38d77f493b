"""Rocking: rigid blocks and rocking frames on rigid ground, blocks on compliant supports.

- :mod:`.block` — Housner's block (exact and linearised), impacts with restitution, lift-off,
  overturning and the Zeno rest rule; :func:`simulate_rocking` drives the numba kernel.
- :mod:`.frame` — the Makris–Vassiliou rocking frame (two columns and a cap beam) as an
  equivalent block with p(gamma) and r(gamma).
- :mod:`.compliant` — a planar rigid body on tensionless spring–damper corner supports.
- :mod:`.spectra` — minimum overturning pulse amplitudes by bracketing and bisection.
- :mod:`.scene` — ``nsdyn run`` on ``[scene] kind = "rocking"``.
"""

from pathlib import Path

from nsdyn._numba_cache import guard_family

# the kernels call each other across files, the shared Dormand–Prince tableau, the small
# linear algebra and the borrowed views
_NSDYN = Path(__file__).resolve().parents[2]
guard_family(__file__, [_NSDYN / "_kdp5.py", _NSDYN / "_klinalg.py", _NSDYN / "_kborrow.py"])

# ruff: noqa: E402

from nsdyn.models.rocking.block import (
    RockingBlock,
    housner_restitution,
    simulate_rocking,
)
from nsdyn.models.rocking.results import RockingResult, rocking_energy

__all__ = [
    "RockingBlock",
    "RockingResult",
    "housner_restitution",
    "rocking_energy",
    "simulate_rocking",
]
