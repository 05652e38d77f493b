"""Space-frame Bernoulli–Euler beam-columns: 12-dof local stiffness and mass, local axes.

An element from node i to node j has local dofs, at each end,
``[u, v, w, θx, θy, θz]`` (axial, transverse along local y and z, torsion, rotations about
local y and z), so 12 in all. With linear axial and torsional and cubic Hermite transverse
shape functions,

    axial      EA/L  [[1, −1], [−1, 1]]                       (u1, u2)
    torsion    GJ/L  [[1, −1], [−1, 1]]                       (θx1, θx2)
    x–y plane  EI_z/L³ B(L)                                    (v1, θz1, v2, θz2)
    x–z plane  EI_y/L³ S B(L) S,   S = diag(1, −1, 1, −1)      (w1, θy1, w2, θy2)

with B(L) = [[12, 6L, −12, 6L], [6L, 4L², −6L, 2L²], [−12, −6L, 12, −6L], [6L, 2L², −6L, 4L²]];
S flips the sign of θy because θy = −dw/dx, while θz = dv/dx. The consistent mass uses the
same shape functions (ρA L/6 [[2, 1], [1, 2]] axially, ρI_p L/6 [[2, 1], [1, 2]] in torsion
with I_p the polar moment, ρA L/420 × the Hermite mass in each bending plane); the HRZ
lumped mass puts ρA L/2 on each translation, ρA L³/78 on each bending rotation and
ρI_p L/2 on each torsional rotation.

Local axes (the convention of OpenSees' ``geomTransf Linear $tag vecxz``):

    e_x = (X_j − X_i) / L,   e_y = (v × e_x) / |v × e_x|,   e_z = e_x × e_y,

with ``v`` the element's orientation vector ``vecxz``: the local x–z plane contains ``v``
and ``e_z`` points to its side (v · e_z > 0). ``I_z`` resists bending in the local x–y plane,
``I_y`` in the local x–z plane (OpenSees' ``elasticBeamColumn ... A E G J Iy Iz``). With
``R = [e_x; e_y; e_z]`` (rows), local = R global for each translation and rotation triple,
and element matrices transform as ``k_g = Tᵀ k T``, ``T = diag(R, R, R, R)``.
"""

from __future__ import annotations

import numpy as np

PARALLEL_SIN = 1e-6  # |v × e_x| / |v| below this: orientation vector parallel to the axis

# local dofs of the two bending planes, (transverse, rotation) at each end
_XY_DOFS = np.array([1, 5, 7, 11])  # v1, θz1, v2, θz2  (I_z)
_XZ_DOFS = np.array([2, 4, 8, 10])  # w1, θy1, w2, θy2  (I_y)
_SIGN_XZ = np.array([1.0, -1.0, 1.0, -1.0])
_POW_L = np.array([[0, 1, 0, 1], [1, 2, 1, 2], [0, 1, 0, 1], [1, 2, 1, 2]])
_B_STIFF = np.array(
    [
        [12.0, 6.0, -12.0, 6.0],
        [6.0, 4.0, -6.0, 2.0],
        [-12.0, -6.0, 12.0, -6.0],
        [6.0, 2.0, -6.0, 4.0],
    ]
)
_B_MASS = np.array(
    [
        [156.0, 22.0, 54.0, -13.0],
        [22.0, 4.0, 13.0, -3.0],
        [54.0, 13.0, 156.0, -22.0],
        [-13.0, -3.0, -22.0, 4.0],
    ]
)


def _bcast(*vals):
    return np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in vals))


def _put_pair(out, i, j, a):
    """Set the two-node bar block ``a [[1, −1], [−1, 1]]`` on local dofs i, j."""
    out[..., i, i] = out[..., j, j] = a
    out[..., i, j] = out[..., j, i] = -a


def _put_bending(out, dofs, coef, base, L, sign=None):
    blk = base * L[..., None, None] ** _POW_L
    if sign is not None:
        blk = blk * np.outer(sign, sign)
    out[..., dofs[:, None], dofs[None, :]] = coef[..., None, None] * blk


def beam3d_stiffness(E, G, A, I_y, I_z, J, L) -> np.ndarray:
    """Local 12×12 stiffness of a space Bernoulli–Euler beam-column.

    Local dofs ``[u1, v1, w1, θx1, θy1, θz1, u2, v2, w2, θx2, θy2, θz2]``. Arguments broadcast;
    the result has shape ``broadcast_shape + (12, 12)`` and is exactly symmetric.
    """
    E, G, A, I_y, I_z, J, L = _bcast(E, G, A, I_y, I_z, J, L)
    k = np.zeros(E.shape + (12, 12))
    _put_pair(k, 0, 6, E * A / L)
    _put_pair(k, 3, 9, G * J / L)
    _put_bending(k, _XY_DOFS, E * I_z / L**3, _B_STIFF, L)
    _put_bending(k, _XZ_DOFS, E * I_y / L**3, _B_STIFF, L, _SIGN_XZ)
    return k


def beam3d_mass(rho_A, rho_Ip, L, lumped: bool = False) -> np.ndarray:
    """Local 12×12 mass: ``rho_A`` [kg/m] per length, ``rho_Ip`` [kg m] torsional inertia
    per length (ρ times the polar moment I_p = I_y + I_z for a homogeneous section).

    Consistent (default) or HRZ-lumped (diagonal; Hinton, Rock & Zienkiewicz 1976).
    """
    rho_A, rho_Ip, L = _bcast(rho_A, rho_Ip, L)
    m = rho_A * L
    out = np.zeros(m.shape + (12, 12))
    if lumped:
        for i in (0, 1, 2, 6, 7, 8):
            out[..., i, i] = m / 2.0
        for i in (4, 5, 10, 11):
            out[..., i, i] = m * L**2 / 78.0
        out[..., 3, 3] = out[..., 9, 9] = rho_Ip * L / 2.0
        return out
    for i, j, mm in ((0, 6, m), (3, 9, rho_Ip * L)):
        out[..., i, i] = out[..., j, j] = mm / 3.0
        out[..., i, j] = out[..., j, i] = mm / 6.0
    _put_bending(out, _XY_DOFS, m / 420.0, _B_MASS, L)
    _put_bending(out, _XZ_DOFS, m / 420.0, _B_MASS, L, _SIGN_XZ)
    return out


def local_axes(xi, xj, vecxz) -> np.ndarray:
    """Rows ``e_x, e_y, e_z`` of each element's local frame, shape (ne, 3, 3).

    ``xi, xj`` (ne, 3) end coordinates, ``vecxz`` (ne, 3) orientation vectors (OpenSees'
    ``geomTransf Linear`` convention, see the module docstring). Raises ``ValueError`` naming
    the first element whose orientation vector is zero or parallel to its axis.
    """
    xi, xj, v = (np.atleast_2d(np.asarray(a, float)) for a in (xi, xj, vecxz))
    d = xj - xi
    L = np.linalg.norm(d, axis=1)
    if np.any(L <= 0):
        raise ValueError(f"element {int(np.argmax(L <= 0))} has zero length")
    ex = d / L[:, None]
    y = np.cross(v, ex)
    ny = np.linalg.norm(y, axis=1)
    nv = np.linalg.norm(v, axis=1)
    bad = ~(ny > PARALLEL_SIN * nv)
    if np.any(bad):
        e = int(np.argmax(bad))
        raise ValueError(
            f"element {e}: orientation vector {v[e].tolist()} is zero or parallel to the "
            f"element axis {ex[e].round(6).tolist()}"
        )
    ey = y / ny[:, None]
    ez = np.cross(ex, ey)
    return np.stack([ex, ey, ez], axis=1)


def transformation(R3) -> np.ndarray:
    """12×12 ``T = diag(R, R, R, R)`` from the (ne, 3, 3) local axes: local = T global."""
    R3 = np.asarray(R3, float)
    T = np.zeros(R3.shape[:-2] + (12, 12))
    for o in (0, 3, 6, 9):
        T[..., o : o + 3, o : o + 3] = R3
    return T


def global_matrices(xi, xj, vecxz, E, G, A, I_y, I_z, J, rho_A, rho_Ip, lumped=False):
    """Element stiffness and mass in global axes, each shape (ne, 12, 12), symmetrised."""
    R3 = local_axes(xi, xj, vecxz)
    L = np.linalg.norm(np.asarray(xj, float) - np.asarray(xi, float), axis=-1)
    T = transformation(R3)
    TT = np.swapaxes(T, -1, -2)
    ke = TT @ beam3d_stiffness(E, G, A, I_y, I_z, J, L) @ T
    me = TT @ beam3d_mass(rho_A, rho_Ip, L, lumped=lumped) @ T
    ke = (ke + np.swapaxes(ke, -1, -2)) / 2
    me = (me + np.swapaxes(me, -1, -2)) / 2
    return ke, me
