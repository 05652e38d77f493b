"""The rigid rung of a space frame on isolators: the whole building as a rigid deck.

A :class:`~nsdyn.structure.Frame3D` on one bidirectional isolator under every base node
(column line) becomes, when the superstructure is taken rigid, the deck of
:mod:`nsdyn.models.isolated.deck`. Its constants come from the diaphragm-constrained mass
matrix ``M`` (consistent element mass, node masses, floor masses and polar moments) and the
rigid motions ``r`` of the frame (:meth:`~nsdyn.structure.Frame3D.rigid_motions`):

    m = r_xᵀ M r_x,                 m x_c = r_yᵀ M r_θ,     m y_c = −r_xᵀ M r_θ   (r_θ about 0),
    J = r_θcᵀ M r_θc               (the rotation about the vertical through c = (x_c, y_c)),
    m h = r_xᵀ M r_φ,              r_φ: the rotation about the horizontal y axis through the
                                    isolators' level (u_x = (z − z_b) φ, u_z = −x φ, θ_y = φ),

exact for consistent element mass (the rigid motions lie in the element shape functions). So
an accidental eccentricity (:func:`nsdyn.structure.accidental_eccentricity`, which moves the
floor masses) moves ``c``. The deck's reference point ``O`` is the plan centroid of the
isolators; the isolator positions are the base nodes' plan coordinates about ``O`` and the
eccentricity is ``c − O``; ``h`` is the height of the centre of mass above the isolators.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from nsdyn._checks import expect
from nsdyn.ground.excitation import G_EARTH
from nsdyn.models.isolated.bearings import Bearing, BearingError
from nsdyn.models.isolated.deck import PlaneSystem, rigid_deck
from nsdyn.structure.frame3d import DOFS_PER_NODE, Frame3D
from nsdyn.structure.modes3d import mass_centre

__all__ = ["building_deck", "deck_constants", "weight_note"]

# |m_z / m - 1| above which the rungs' weights differ enough to say so: 5 % of the normal
# forces is 5 % of the friction and pendulum forces, and of the isolation period's square
WEIGHT_RTOL = 0.05


def _rocking_y(frame: Frame3D, z0: float) -> np.ndarray:
    """Reduced coordinates of the rigid rotation φ = 1 about the horizontal y axis through
    (0, 0, z0): u_x = (z − z0), u_z = −x, θ_y = 1. The field keeps every floor rigid in its
    plane, so it lies in the range of T and ``(TᵀT) r = Tᵀ u`` recovers r exactly."""
    full = np.zeros((frame.n_nodes, DOFS_PER_NODE))
    full[:, 0] = frame.nodes[:, 2] - z0
    full[:, 2] = -frame.nodes[:, 0]
    full[:, 4] = 1.0
    T = frame.T
    return spla.spsolve(sp.csc_array(T.T @ T), T.T @ full.ravel())


def deck_constants(frame: Frame3D) -> dict:
    """``m`` [kg], ``J`` [kg m²] about the centre of mass, ``centre`` (x_c, y_c) [m],
    ``h`` [m] above the base nodes, ``z_base`` [m] (module docstring), and ``m_z`` [kg] =
    r_zᵀ M r_z, the mass gravity acts on in the cb and full rungs (a floor mass given in
    plan only has none; the rigid deck weighs ``m``)."""
    _, M = frame.reduced()
    c, m, J = mass_centre(frame, M)
    zb = float(frame.nodes[frame.base_nodes, 2].min())
    if np.ptp(frame.nodes[frame.base_nodes, 2]) > 1e-9 * frame.size:
        raise ValueError(
            f"frame {frame.name!r}: the base nodes are not at one level; the isolators of a "
            "rigid deck slide in one plane"
        )
    r = frame.rigid_motions()
    h = float(r[:, 0] @ (M @ _rocking_y(frame, zb))) / m
    if not J > 0:
        raise ValueError(f"frame {frame.name!r}: no polar inertia (J = {J:g} kg m²)")
    m_z = float(r[:, 2] @ (M @ r[:, 2]))
    return {"m": m, "J": J, "centre": c, "h": h, "z_base": zb, "m_z": m_z}


def weight_note(name: str, m: float, m_z: float) -> str | None:
    """A note when the frame's vertical mass ``m_z`` differs from its horizontal mass ``m``
    by more than ``WEIGHT_RTOL``: the rigid deck weighs m, the cb and full rungs m_z."""
    if abs(m_z / m - 1.0) <= WEIGHT_RTOL:
        return None
    return (f"frame {name}: its vertical mass ({m_z / 1e3:.4g} t) is {100 * m_z / m:.3g} % of "
            f"its horizontal mass ({m / 1e3:.4g} t): the cb and full rungs put the vertical "
            "masses' weight on the isolators, the rigid rung the horizontal mass's, so their "
            "normal forces, friction and pendulum forces differ by that ratio; give floor "
            "masses their weight (frame3d.node_mass [m_x, m_y, m_z] on the floor's "
            "nodes)")  # fmt: skip


def building_deck(
    frame: Frame3D,
    bearings: Bearing | Sequence[Bearing],
    *,
    g: float = G_EARTH,
    name: str | None = None,
) -> PlaneSystem:
    """The rigid deck of ``frame`` on one isolator under every base node.

    ``bearings``: one :class:`~nsdyn.models.isolated.Bearing` for all or one per base node
    (in the order of ``frame.base_nodes``). The deck's ``info`` holds ``origin`` (the plan
    point O the deck's (x, y, θ) refer to), ``centre``, ``m``, ``J``, ``h``, ``m_z``,
    ``base_nodes``.
    """
    expect(
        "frame",
        frame,
        hasattr(frame, "base_nodes") and hasattr(frame, "diaphragms"),
        "a Frame3D (nsdyn.structure.load_frame3d(name or file))",
    )
    nb = len(frame.base_nodes)
    if not isinstance(bearings, Bearing):
        expect(
            "bearings",
            bearings,
            isinstance(bearings, list | tuple) and all(isinstance(b, Bearing) for b in bearings),
            "a Bearing or one per base node (nsdyn.models.isolated.Bearing(...))",
        )
        bearings = tuple(bearings) * (nb if len(bearings) == 1 else 1)  # (a list of one: all)
        if len(bearings) != nb:
            raise BearingError(
                f"{frame.name}.bearings: expected one bearing or {nb} (one per base node), "
                f"got {len(bearings)}"
            )
    k = deck_constants(frame)
    xy = frame.nodes[frame.base_nodes, :2]
    origin = xy.mean(axis=0)
    ecc = k["centre"] - origin
    try:
        deck = rigid_deck(k["m"], k["J"], xy - origin, bearings, ecc=tuple(map(float, ecc)),
                          h=max(k["h"], 0.0), g=g, name=name or frame.name)  # fmt: skip
    except BearingError as e:  # the deck's ecc is the frame's centre of mass: say so
        if ".ecc: the centre of mass" not in str(e):
            raise
        why = str(e).split(": the centre of mass ", 1)[1]
        raise BearingError(f"{frame.name}: its centre of mass, ({ecc[0]:.2f}, {ecc[1]:.2f}) m "
                           f"from the isolators' centre, {why} (a scene's "
                           "structure.eccentricity moves it)") from None  # fmt: skip
    deck.info.update(
        origin=origin, centre=k["centre"], m=k["m"], J=k["J"], h=k["h"], m_z=k["m_z"],
        base_nodes=frame.base_nodes.copy(),
    )  # fmt: skip
    return deck
