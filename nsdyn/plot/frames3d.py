"""Figures of space frames: 3D mode shapes (and any displacement field) on 3D axes.

Members are drawn deformed by the element shape functions in local axes: axial u and
twist linear, transverse v (plane x–y, rotation θz = dv/dx) and w (plane x–z, θy = −dw/dx)
cubic Hermite,

    v(ξ) = N1 v1 + N2 L θz1 + N3 v2 + N4 L θz2,   w(ξ) = N1 w1 − N2 L θy1 + N3 w2 − N4 L θy2,

so the drawing is the finite-element solution itself. Figures are
``matplotlib.figure.Figure`` objects (no pyplot, no global state).
"""

from __future__ import annotations

import numpy as np

from nsdyn.structure import Frame3D, Modes3D

N_SUB = 6  # points per element of a deformed member
SHAPE_SCALE = 0.08  # largest drawn displacement as a fraction of the frame's size


def deformed_lines_3d(frame: Frame3D, u: np.ndarray, scale: float, n_sub: int = N_SUB):
    """Deformed member centre lines, shape (ne, n_sub + 1, 3), of full displacements ``u``."""
    u = np.asarray(u, float)
    el = frame.elements
    p0, p1 = frame.nodes[el[:, 0]], frame.nodes[el[:, 1]]
    L = np.linalg.norm(p1 - p0, axis=1)
    R = frame.local_axes()  # rows e_x, e_y, e_z
    ue = u[frame.element_dofs()].reshape(-1, 4, 3)  # (ne, [t1, r1, t2, r2], xyz)
    ul = np.einsum("eij,ekj->eki", R, ue)  # local components
    xi = np.linspace(0.0, 1.0, n_sub + 1)
    n1, n2 = 1 - 3 * xi**2 + 2 * xi**3, xi - 2 * xi**2 + xi**3
    n3, n4 = 3 * xi**2 - 2 * xi**3, -(xi**2) + xi**3
    t1, r1, t2, r2 = (ul[:, k] for k in range(4))
    Lc = L[:, None]
    ax = t1[:, [0]] * (1 - xi) + t2[:, [0]] * xi
    v = t1[:, [1]] * n1 + r1[:, [2]] * Lc * n2 + t2[:, [1]] * n3 + r2[:, [2]] * Lc * n4
    w = t1[:, [2]] * n1 - r1[:, [1]] * Lc * n2 + t2[:, [2]] * n3 - r2[:, [1]] * Lc * n4
    disp = (
        ax[..., None] * R[:, None, 0] + v[..., None] * R[:, None, 1] + w[..., None] * R[:, None, 2]
    )
    base = p0[:, None, :] + xi[None, :, None] * (p1 - p0)[:, None, :]
    return base + scale * disp


def plot_mode_shapes_3d(modes: Modes3D, n: int = 4, fig=None):
    """Draw the first ``n`` fixed-base mode shapes of a space frame on 3D axes.

    Each panel shows the undeformed frame (grey), the mode (scaled so that its largest
    translation is :data:`SHAPE_SCALE` of the frame's size), the base nodes (triangles) and
    a title with the frequency, the family (x, y, torsion, …) and the effective-mass
    fraction of that family. Returns the ``matplotlib.figure.Figure``.
    """
    from matplotlib.figure import Figure
    from matplotlib.ticker import MaxNLocator

    frame = modes.frame
    n = min(n, len(modes.f_hz))
    if fig is None:
        fig = Figure(figsize=(3.2 * n + 0.4, 5.6), layout="constrained")
    size = frame.size
    undeformed = deformed_lines_3d(frame, np.zeros(frame.n_dof), 0.0, n_sub=1)
    full = modes.full()
    base = frame.nodes[frame.base_nodes]
    col = {"x": 0, "y": 1, "torsion": 2}
    for k in range(n):
        a = fig.add_subplot(1, n, k + 1, projection="3d")
        u = full[:, k]
        trans = np.abs(u.reshape(-1, 6)[:, :3]).max()
        scale = SHAPE_SCALE * size / trans if trans > 0 else 0.0
        for line in undeformed:
            a.plot(line[:, 0], line[:, 1], line[:, 2], color="0.82", lw=0.5)
        for line in deformed_lines_3d(frame, u, scale):
            a.plot(line[:, 0], line[:, 1], line[:, 2], color="C0", lw=1.0)
        a.scatter(base[:, 0], base[:, 1], base[:, 2], marker="^", color="k", s=14)
        fam = modes.family[k]
        share = f", {modes.mass_fraction[k, col[fam]]:.0%} mass" if fam in col else ""
        a.set_title(f"mode {k + 1}: {modes.f_hz[k]:.3g} Hz\n{fam}{share}", fontsize=9)
        a.set_xlabel("x [m]", fontsize=8)
        a.set_ylabel("y [m]", fontsize=8)
        a.set_zlabel("z [m]", fontsize=8)
        a.tick_params(labelsize=7)
        for axis in (a.xaxis, a.yaxis, a.zaxis):
            axis.set_major_locator(MaxNLocator(4))
        a.set_box_aspect(tuple(np.maximum(np.ptp(frame.nodes, axis=0), 0.05 * size)))
    fig.suptitle(f"{frame.name}: fixed-base mode shapes", fontsize=10)
    return fig
