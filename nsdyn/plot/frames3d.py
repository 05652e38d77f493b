"""Figures of space frames: 3D mode shapes, the deformed shape at an instant, on 3D axes.

Members are drawn deformed by the element shape functions in local axes: axial u and
twist linear, transverse v (plane x–y, rotation θz = dv/dx) and w (plane x–z, θy = −dw/dx)
cubic Hermite,

    v(ξ) = N1 v1 + N2 L θz1 + N3 v2 + N4 L θz2,   w(ξ) = N1 w1 − N2 L θy1 + N3 w2 − N4 L θy2,

so the drawing is the finite-element solution itself; at the member ends (ξ = 0, 1) a drawn
point is the node moved by ``scale × (u_x, u_y, u_z)``. Figures are
``matplotlib.figure.Figure`` objects (no pyplot, no global state).

A figure needs the frame's geometry only (nodes, members, local axes, dofs): a
:class:`~nsdyn.structure.Frame3D` or a :class:`FrameGeometry` read back from the arrays a run
saved (``building3d-shape.npz``, :mod:`nsdyn.models.isolated.building3d_shape`), from which
:func:`scene_figures` draws a ``building3d`` run's deformed shape at its peak and, for the
fixed rung, its first fixed-base mode shapes.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from nsdyn.atomic import save_figure
from nsdyn.models.isolated.building3d_shape import SHAPE_FILE
from nsdyn.structure import Frame3D, Modes3D

N_SUB = 6  # points per element of a deformed member
SHAPE_SCALE = 0.08  # largest drawn displacement as a fraction of the frame's size
UNDEFORMED = "0.78"  # the grey of the undeformed frame


@dataclass(frozen=True, eq=False)
class FrameGeometry:
    """What a drawing needs of a space frame (duck-types the parts of :class:`Frame3D` the
    figures use): node coordinates, member ends, local axes, member dofs, base nodes."""

    nodes: np.ndarray  # (nn, 3)
    elements: np.ndarray  # (ne, 2)
    axes: np.ndarray  # (ne, 3, 3) rows e_x, e_y, e_z
    edofs: np.ndarray  # (ne, 12)
    base_nodes: np.ndarray
    name: str = "frame"

    @classmethod
    def from_arrays(cls, d) -> FrameGeometry:
        """From the arrays of ``building3d-shape.npz`` (or any mapping of the same names)."""
        return cls(np.asarray(d["nodes"], float), np.asarray(d["elements"], np.int64),
                   np.asarray(d["local_axes"], float), np.asarray(d["element_dofs"], np.int64),
                   np.asarray(d["base_nodes"], np.int64), str(d["name"]))  # fmt: skip

    def local_axes(self) -> np.ndarray:
        return self.axes

    def element_dofs(self) -> np.ndarray:
        return self.edofs

    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    @property
    def n_dof(self) -> int:
        return 6 * len(self.nodes)

    @property
    def size(self) -> float:
        return max(float(np.ptp(self.nodes, axis=0).max()), 1.0)


def auto_scale(frame, u: np.ndarray) -> float:
    """The scale that draws the largest nodal translation of ``u`` as SHAPE_SCALE of the
    frame's size (0 for a zero field)."""
    trans = float(np.abs(np.asarray(u, float).reshape(-1, 6)[:, :3]).max())
    return SHAPE_SCALE * frame.size / trans if trans > 0 else 0.0


def _frame_axes(a, frame, size: float) -> None:
    from matplotlib.ticker import MaxNLocator

    a.set_xlabel("x [m]", fontsize=8)
    a.set_ylabel("y [m]", fontsize=8)
    a.set_zlabel("z [m]", fontsize=8)
    a.tick_params(labelsize=7)
    for axis in (a.xaxis, a.yaxis, a.zaxis):
        axis.set_major_locator(MaxNLocator(4))
    a.set_box_aspect(tuple(np.maximum(np.ptp(frame.nodes, axis=0), 0.05 * size)))


def draw_deformed(a, frame, u: np.ndarray, scale: float, color: str = "C0") -> tuple:
    """On 3D axes ``a``: the undeformed members (grey, gid ``undeformed``), the members
    deformed by ``scale × u`` (gid ``deformed``) and the base nodes. Each set of members is one
    line artist, its members in element order separated by a row of NaN (one artist per member
    took seconds to draw on a building of thousands of elements; :func:`member_lines` splits
    it again). Returns the two artists (undeformed, deformed)."""
    und = _joined(deformed_lines_3d(frame, np.zeros(frame.n_dof), 0.0, n_sub=1))
    (hu,) = a.plot(und[:, 0], und[:, 1], und[:, 2], color=UNDEFORMED, lw=0.5)
    hu.set_gid("undeformed")
    dfm = _joined(deformed_lines_3d(frame, u, scale))
    (hd,) = a.plot(dfm[:, 0], dfm[:, 1], dfm[:, 2], color=color, lw=1.0)
    hd.set_gid("deformed")
    base = frame.nodes[frame.base_nodes]
    a.scatter(base[:, 0], base[:, 1], base[:, 2], marker="^", color="k", s=14)
    return hu, hd


def _joined(lines: np.ndarray) -> np.ndarray:
    """The member lines (ne, k, 3) as one polyline, a row of NaN after each member."""
    ne, k, _ = lines.shape
    out = np.full((ne, k + 1, 3), np.nan)
    out[:, :k] = lines
    return out.reshape(-1, 3)


def member_lines(artist) -> list[np.ndarray]:
    """The members' lines (each (k, 3)) of an artist drawn by :func:`draw_deformed`."""
    xyz = np.array(artist.get_data_3d(), dtype=float).T
    gaps = np.flatnonzero(np.isnan(xyz[:, 0]))
    starts = np.concatenate([[0], gaps[:-1] + 1])
    return [xyz[a:b] for a, b in zip(starts, gaps, strict=True)]


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
    return draw_mode_shapes(modes.frame, modes.full(), modes.f_hz, modes.family,
                            modes.mass_fraction, n=n, fig=fig)  # fmt: skip


def draw_mode_shapes(frame, shapes, f_hz, family, mass_fraction, n: int = 4, fig=None):
    """:func:`plot_mode_shapes_3d` from arrays: ``shapes`` (n_dof, m) in full dofs, their
    frequencies [Hz], families and effective-mass fractions (m, 3); ``frame`` a Frame3D or a
    :class:`FrameGeometry`."""
    from matplotlib.figure import Figure

    n = min(n, len(f_hz))
    if fig is None:
        fig = Figure(figsize=(3.2 * n + 0.4, 5.6), layout="constrained")
    col = {"x": 0, "y": 1, "torsion": 2}
    for k in range(n):
        a = fig.add_subplot(1, n, k + 1, projection="3d")
        u = shapes[:, k]
        draw_deformed(a, frame, u, auto_scale(frame, u))
        fam = str(family[k])
        share = f", {mass_fraction[k, col[fam]]:.0%} mass" if fam in col else ""
        a.set_title(f"mode {k + 1}: {f_hz[k]:.3g} Hz\n{fam}{share}", fontsize=9)
        _frame_axes(a, frame, frame.size)
    fig.suptitle(f"{frame.name}: fixed-base mode shapes", fontsize=10)
    return fig


def plot_deformed_3d(frame, u: np.ndarray, *, scale: float | None = None, title: str = "",
                     fig=None):  # fmt: skip
    """The frame deformed by the full displacement field ``u`` (n_dof,) drawn ``scale`` times
    (default :func:`auto_scale`) over the undeformed frame in grey, base nodes as triangles,
    on 3D axes; the title states the scale and the largest translation. ``frame``: a
    :class:`Frame3D` or a :class:`FrameGeometry`. Returns the ``matplotlib.figure.Figure``."""
    from matplotlib.figure import Figure

    u = np.asarray(u, float)
    if u.shape != (frame.n_dof,):
        raise ValueError(f"u: expected {frame.n_dof} full dofs of {frame.name!r}, got {u.shape}")
    scale = auto_scale(frame, u) if scale is None else float(scale)
    if fig is None:
        fig = Figure(figsize=(6.4, 6.0), layout="constrained")
    a = fig.add_subplot(projection="3d")
    draw_deformed(a, frame, u, scale, color="C3")
    peak = float(np.abs(u.reshape(-1, 6)[:, :3]).max())
    a.set_title(f"{title or frame.name}\nlargest translation {peak:.3g} m, drawn × {scale:.3g}",
                fontsize=9)  # fmt: skip
    _frame_axes(a, frame, frame.size)
    return fig


def scene_figures(summary: dict, out_dir: str | Path) -> list[str]:
    """The figures of a ``building3d`` run from the ``building3d-shape.npz`` it wrote into
    ``out_dir``: ``building3d-deformed.png`` (the deformed shape at the peak) and, when the
    file holds mode shapes (fixed rung), ``building3d-modes.png``. Returns the paths."""
    out = Path(out_dir)
    path = out / SHAPE_FILE
    if not path.is_file():
        return []
    with np.load(path) as d:
        arrays = {k: d[k] for k in d.files}
    geo = FrameGeometry.from_arrays(arrays)
    title = (f"{summary.get('name', geo.name)}\n{arrays['what']} at "
             f"t = {float(arrays['t_peak']):.3f} s")  # fmt: skip
    files = [save_figure(plot_deformed_3d(geo, arrays["u"], title=title),
                         out / "building3d-deformed.png")]  # fmt: skip
    if "mode_shapes" in arrays:
        fig = draw_mode_shapes(geo, arrays["mode_shapes"], arrays["f_hz"], arrays["family"],
                               arrays["mass_fraction"])  # fmt: skip
        files.append(save_figure(fig, out / "building3d-modes.png"))
    return [str(f) for f in files]


def frf_figure(rows: list[dict], modes: list[dict], title: str = ""):
    """Frequency–amplitude curves of the fixed rung (``nsdyn sweep`` on a fixed building3d
    scene): roof displacement and the largest corner drift ratio against f, one line per
    amplitude, the fixed-base frequencies dotted (x, y, torsion families labelled).
    ``rows``: dicts with f, A, roof_displacement_m, corner_drift; ``modes``: dicts with
    f_hz, family."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 4.0), layout="constrained")
    panels = (("roof_displacement_m", "roof displacement amplitude [m]"),
              ("corner_drift", "largest corner drift ratio [-]"))  # fmt: skip
    amps = sorted({r["A"] for r in rows})
    for k, (key, label) in enumerate(panels):
        a = fig.add_subplot(1, 2, k + 1)
        for j, amp in enumerate(amps):
            pts = sorted((r["f"], r[key]) for r in rows if r["A"] == amp)
            a.loglog(*np.array(pts).T, color=f"C{j % 10}", lw=1.2, label=f"A = {amp:.3g} m/s²")
        named = set()
        for m in modes:
            if m["family"] in ("x", "y", "torsion"):
                a.axvline(m["f_hz"], color="0.6", ls=":", lw=0.8)
                if m["family"] not in named:  # the first mode of each family named
                    named.add(m["family"])
                    a.annotate(m["family"], (m["f_hz"], 1.0), xycoords=("data", "axes fraction"),
                               fontsize=7, ha="center", va="bottom", color="0.4")  # fmt: skip
        a.set_xlabel("excitation frequency f [Hz]")
        a.set_ylabel(label)
        a.grid(alpha=0.3, which="both")
        if k == 0:
            a.legend(fontsize=7)
    fig.suptitle(title or "steady harmonic response, fixed base", fontsize=9)
    return fig
