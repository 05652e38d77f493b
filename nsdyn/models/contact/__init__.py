"""Planar rigid bodies on the ground with frictional unilateral contacts: slide, rock, hop, tip.

Body (x, y, theta) with Signorini contacts at its base corners, Newton (or Housner) impacts and
Coulomb friction mu(v) = mu_d + (mu_s - mu_d) exp(-C |v|); solved event-driven (acceleration-level
LCP by Lemke's method between events, impacts at velocity level) or by Moreau-Jean time stepping.
"""

from pathlib import Path

from nsdyn._numba_cache import guard_family

# the kernels call each other across files, the small linear algebra and the borrowed views
_NSDYN = Path(__file__).resolve().parents[2]
guard_family(__file__, [_NSDYN / "_klinalg.py", _NSDYN / "_kborrow.py"])

# ruff: noqa: E402
from nsdyn.models.contact.body import RigidBody
from nsdyn.models.contact.compliant import CompliantGround, CompliantResult, simulate_compliant
from nsdyn.models.contact.event import simulate_event
from nsdyn.models.contact.excite import BaseMotion
from nsdyn.models.contact.friction import FrictionLaw
from nsdyn.models.contact.moreau import simulate_moreau
from nsdyn.models.contact.onset import onset_mode
from nsdyn.models.contact.results import ContactResult

__all__ = ["BaseMotion", "CompliantGround", "CompliantResult", "ContactResult", "FrictionLaw",
           "RigidBody", "onset_mode", "simulate_compliant", "simulate_event",
           "simulate_moreau"]  # fmt: skip
