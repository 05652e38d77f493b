"""Plane Bernoulli–Euler frame elements: local stiffness and mass, rotation to global axes.

An element of length L, modulus E, area A, second moment I and mass per length ρA has local
dofs ``[u1, v1, th1, u2, v2, th2]`` (axial, transverse, rotation at each end). With linear axial
and cubic Hermite transverse shape functions

    k = EA/L [[1, −1], [−1, 1]] (u)  ⊕  EI/L³ [[12, 6L, −12, 6L], [6L, 4L², −6L, 2L²], …] (v, th),
    m = ρA L/6 [[2, 1], [1, 2]] (u)  ⊕  ρA L/420 [[156, 22L, 54, −13L], [22L, 4L², 13L, −3L²], …],

or the HRZ-lumped diagonal mass. In global axes k_g = Rᵀ k R, with R the rotation by the
element angle (c, s) = (cos α, sin α) applied to each node's (x, y) pair.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from nsdyn.structure.frame import Frame


_BEND_DOFS = np.array([1, 2, 4, 5])  # the local v, th dofs of the bending block
# powers of L for each entry of the bending block (v, th, v, th)
_BEND_POW_L = np.array([[0, 1, 0, 1], [1, 2, 1, 2], [0, 1, 0, 1], [1, 2, 1, 2]])


def beam_stiffness(E, A, I, L) -> np.ndarray:
    """Local stiffness of a plane Bernoulli–Euler frame element.

    Local dofs ``[u1, v1, th1, u2, v2, th2]`` (axial, transverse, rotation at each end).
    Arguments broadcast; the result has shape ``broadcast_shape + (6, 6)``.
    """
    E, A, I, L = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (E, A, I, L)))
    a = E * A / L
    b = E * I / L**3
    k = np.zeros(E.shape + (6, 6))
    k[..., 0, 0] = k[..., 3, 3] = a
    k[..., 0, 3] = k[..., 3, 0] = -a
    bend = np.array(
        [
            [12.0, 6.0, -12.0, 6.0],
            [6.0, 4.0, -6.0, 2.0],
            [-12.0, -6.0, 12.0, -6.0],
            [6.0, 2.0, -6.0, 4.0],
        ]
    )
    k[..., _BEND_DOFS[:, None], _BEND_DOFS[None, :]] = (
        b[..., None, None] * bend * L[..., None, None] ** _BEND_POW_L
    )
    return k


def beam_mass(rho_A, L, lumped: bool = False) -> np.ndarray:
    """Local mass of a plane frame element, mass ``rho_A`` per unit length [kg/m].

    Consistent (``lumped=False``): linear axial and cubic Hermite transverse shape functions.
    Lumped: HRZ diagonal lumping (Hinton, Rock & Zienkiewicz 1976) — half the element mass
    on each translational dof, rotational inertia ``rho_A L^3 / 78`` — which keeps ``M``
    positive definite. Shape ``broadcast_shape + (6, 6)``.
    """
    rho_A, L = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (rho_A, L)))
    m = rho_A * L
    out = np.zeros(m.shape + (6, 6))
    if lumped:
        for i in (0, 1, 3, 4):
            out[..., i, i] = m / 2.0
        out[..., 2, 2] = out[..., 5, 5] = m * L**2 / 78.0
        return out
    out[..., 0, 0] = out[..., 3, 3] = m / 3.0
    out[..., 0, 3] = out[..., 3, 0] = m / 6.0
    bend = np.array(
        [
            [156.0, 22.0, 54.0, -13.0],
            [22.0, 4.0, 13.0, -3.0],
            [54.0, 13.0, 156.0, -22.0],
            [-13.0, -3.0, -22.0, 4.0],
        ]
    )
    out[..., _BEND_DOFS[:, None], _BEND_DOFS[None, :]] = (
        (m / 420.0)[..., None, None] * bend * L[..., None, None] ** _BEND_POW_L
    )
    return out


def rotation(c, s) -> np.ndarray:
    """Transformation ``u_local = R u_global`` for an element with direction (c, s).

    ``c, s`` are the cosine and sine of the element axis angle measured from the global x
    axis. Shape ``broadcast_shape + (6, 6)``; element matrices transform as ``R^T k R``.
    """
    c, s = np.broadcast_arrays(np.asarray(c, dtype=float), np.asarray(s, dtype=float))
    R = np.zeros(c.shape + (6, 6))
    for o in (0, 3):
        R[..., o, o] = c
        R[..., o, o + 1] = s
        R[..., o + 1, o] = -s
        R[..., o + 1, o + 1] = c
        R[..., o + 2, o + 2] = 1.0
    return R


def element_matrices(frame: Frame, lumped: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Element stiffness and mass in global axes, each shape (ne, 6, 6)."""
    d = frame.nodes[frame.elements[:, 1]] - frame.nodes[frame.elements[:, 0]]
    L = np.hypot(d[:, 0], d[:, 1])
    R = rotation(d[:, 0] / L, d[:, 1] / L)
    RT = np.swapaxes(R, 1, 2)
    ke = RT @ beam_stiffness(frame.E, frame.A, frame.I, L) @ R
    me = RT @ beam_mass(frame.rho_A, L, lumped=lumped) @ R
    return ke, me
