"""Storeys of a space frame: drift ratios at the centre of mass and at the plan corners; accidental
eccentricity.

Each level (an elevation carrying a diaphragm or horizontal members, the base first:
:meth:`~nsdyn.structure.Frame3D.levels`) moves in its plane as a rigid floor
``(U_x, U_y, Θ)`` about a reference point ``c``: on a diaphragm level its master (the floor's
centre of mass) exactly; elsewhere the least-squares rigid fit of the level's nodes about
their centroid (``U`` the mean translation, ``Θ = Σ (d_x u_y − d_y u_x) / Σ |d|²``; the
mean θ_z for a single point). A plan point ``p = (x, y)`` of the floor then moves

    u_x(p) = U_x − (y − y_c) Θ,    u_y(p) = U_y + (x − x_c) Θ,

and the interstorey drift ratio of storey s (levels s and s + 1, height h_s) at p is

    δ_d(p) = (u_d(p; s + 1) − u_d(p; s)) / h_s,   d = x, y.

It is evaluated at the centre of mass of the floor above (``c`` of level s + 1) and at the
four corners of the plan (the bounding box of the frame's nodes). Torsion amplifies the
corner drifts: ``amplification = max_corners |δ_d| / |δ_d(CM)|`` per storey and direction
(1 for a floor that only translates).

Accidental eccentricity (design codes: the floor's centre of mass moved by ± a fraction,
typically 5 %, of the plan dimension perpendicular to the ground motion): every diaphragm's
master moves by ``(f_x L_x, f_y L_y)``, L the floor's plan dimensions (bounding box of its
nodes), with its mass and its polar moment about the moved centre unchanged (the floor's
mass distribution translated as a whole).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from nsdyn.structure.frame3d import DOFS_PER_NODE, Diaphragm, Frame3D, changed

__all__ = ["StoreyDrifts", "accidental_eccentricity", "floor_motions", "storey_drifts_3d"]


@dataclass(frozen=True, eq=False)
class StoreyDrifts:
    """Interstorey drift ratios of a displacement field (trailing axes of ``u`` kept).

    Attributes
    ----------
    heights : (ns,) storey heights [m].      cm_points : (ns, 2) plan centres of mass [m].
    corners : (4, 2) plan corners [m] (x_min y_min, x_max y_min, x_max y_max, x_min y_max).
    cm : (ns, 2, ...) drift ratios in x and y at the centre of mass of the floor above.
    corner : (ns, 4, 2, ...) drift ratios in x and y at each corner.
    """

    heights: np.ndarray
    cm_points: np.ndarray
    corners: np.ndarray
    cm: np.ndarray
    corner: np.ndarray

    @property
    def max_corner(self) -> np.ndarray:
        """Largest corner drift ratio magnitude, (ns, 2, ...)."""
        return np.abs(self.corner).max(axis=1)

    @property
    def amplification(self) -> np.ndarray:
        """``max_corner / |cm|``, (ns, 2, ...); nan where the centre of mass does not drift."""
        cm = np.abs(self.cm)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(cm > 0, self.max_corner / np.where(cm > 0, cm, 1.0), np.nan)


def _level_refs(frame: Frame3D):
    """Per level: elevation, reference point c (2,), and ('master', k) or ('fit', nodes)."""
    z, level_nodes = frame.levels()
    owner = {int(n): k for k, d in enumerate(frame.diaphragms) for n in d.nodes}
    _, Ml = frame.assemble(lumped=True)
    w = Ml.diagonal().reshape(-1, DOFS_PER_NODE)[:, 0]
    out = []
    for h, nodes in zip(z, level_nodes, strict=True):
        dias = sorted({owner[n] for n in nodes.tolist() if n in owner})
        if len(dias) > 1:
            raise ValueError(f"level z = {h:g} m has {len(dias)} diaphragms; drifts need one")
        if dias:
            k = dias[0]
            out.append((float(h), frame.diaphragms[k].centre, ("master", k), nodes))
        else:
            xy = frame.nodes[nodes, :2]
            ww = w[nodes]
            cm = (ww @ xy) / ww.sum() if ww.sum() > 0 else xy.mean(axis=0)
            out.append((float(h), cm, ("fit", nodes), nodes))
    return out


def _rigid(frame: Frame3D, u: np.ndarray, ref) -> np.ndarray:
    """(U_x, U_y, Θ) at the level's own reference, shape (3, ...)."""
    _, c, (kind, what), _ = ref
    U = u.reshape((frame.n_nodes, DOFS_PER_NODE) + u.shape[1:])
    if kind == "master":
        d = frame.diaphragms[what]
        n0 = int(d.nodes[0])  # a slave: its motion is the master's carried rigidly
        dx, dy = frame.nodes[n0, :2] - c
        th = U[n0, 5]
        return np.stack([U[n0, 0] + dy * th, U[n0, 1] - dx * th, th])
    nodes = what
    xy = frame.nodes[nodes, :2]
    c0 = xy.mean(axis=0)
    d = xy - c0
    ux, uy = U[nodes, 0].mean(axis=0), U[nodes, 1].mean(axis=0)
    jd = float((d**2).sum())
    extra = (1,) * (u.ndim - 1)
    if jd > 0:
        dx, dy = d[:, 0].reshape((-1,) + extra), d[:, 1].reshape((-1,) + extra)
        th = (dx * U[nodes, 1] - dy * U[nodes, 0]).sum(axis=0) / jd
    else:
        th = U[nodes, 5].mean(axis=0)
    # moved from the centroid c0 to the reference point c
    ex, ey = c - c0
    return np.stack([ux - ey * th, uy + ex * th, th])


def floor_motions(frame: Frame3D, u: np.ndarray):
    """Rigid floor motions of every level: (elevations (nl,), references (nl, 2), motions
    (nl, 3, ...) = U_x, U_y, Θ about each level's reference point). ``u``: full
    displacements, (n_dof,) or (n_dof, ...)."""
    u = np.asarray(u, float)
    if u.shape[0] != frame.n_dof:
        raise ValueError(f"u has {u.shape[0]} rows, frame {frame.name!r} has {frame.n_dof} dofs")
    refs = _level_refs(frame)
    z = np.array([r[0] for r in refs])
    c = np.array([r[1] for r in refs])
    return z, c, np.stack([_rigid(frame, u, r) for r in refs])


def _at(motion: np.ndarray, c: np.ndarray, p: np.ndarray) -> np.ndarray:
    """(u_x, u_y) at plan point p of a floor moving by ``motion`` (3, ...) about c."""
    ux, uy, th = motion
    return np.stack([ux - (p[1] - c[1]) * th, uy + (p[0] - c[0]) * th])


def storey_drifts_3d(frame: Frame3D, u: np.ndarray) -> StoreyDrifts:
    """Interstorey drift ratios of the full displacement field ``u`` (module docstring).

    ``u``: (n_dof,) or (n_dof, ...) (e.g. a time history); ``frame.expand(q_r)`` gives it
    from diaphragm-constrained coordinates.
    """
    z, c, mot = floor_motions(frame, u)
    if len(z) < 2:
        raise ValueError(f"frame {frame.name!r} has no storey (fewer than two levels)")
    lo, hi = frame.nodes[:, :2].min(axis=0), frame.nodes[:, :2].max(axis=0)
    corners = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
    h = np.diff(z)
    cm, cor = [], []
    for s in range(len(h)):
        p = c[s + 1]
        cm.append((_at(mot[s + 1], c[s + 1], p) - _at(mot[s], c[s], p)) / h[s])
        cor.append(
            np.stack(
                [(_at(mot[s + 1], c[s + 1], q) - _at(mot[s], c[s], q)) / h[s] for q in corners]
            )
        )
    return StoreyDrifts(h, c[1:].copy(), corners, np.stack(cm), np.stack(cor))


def eccentricity_pair(eccentricity) -> tuple[float, float]:
    """``(f_x, f_y)`` of an ``eccentricity`` argument, or ValueError naming it (a scalar was
    "'float' object is not iterable", text was read character by character)."""
    try:
        fx, fy = (float(v) for v in eccentricity)
        ok = not isinstance(eccentricity, str | bytes) and not any(
            isinstance(v, bool | str | bytes) for v in eccentricity)  # fmt: skip
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"eccentricity: expected a pair (f_x, f_y) of fractions of the plan "
                         f"dimensions, got {eccentricity!r}")  # fmt: skip
    for i, v in enumerate((fx, fy)):  # (named f_y by the call it is passed on to)
        if not (np.isfinite(v) and abs(v) < 0.5):
            raise ValueError(f"eccentricity[{i}]: expected a fraction of the plan dimension in "
                             f"(-0.5, 0.5), got {v!r}")  # fmt: skip
    return fx, fy


def accidental_eccentricity(frame: Frame3D, f_x: float = 0.0, f_y: float = 0.0) -> Frame3D:
    """``frame`` with every diaphragm's centre of mass moved by ``(f_x L_x, f_y L_y)``
    (fractions of the floor's plan dimensions, signed; module docstring)."""
    for k, v in (("f_x", f_x), ("f_y", f_y)):
        if not (isinstance(v, int | float) and np.isfinite(v) and abs(v) < 0.5):
            raise ValueError(f"{k}: expected a fraction of the plan dimension in (-0.5, 0.5), "
                             f"got {v!r}")  # fmt: skip
    if not frame.diaphragms:
        raise ValueError(
            f"frame {frame.name!r} has no diaphragms: accidental eccentricity moves floor masses"
        )
    out = []
    for d in frame.diaphragms:
        L = np.ptp(frame.nodes[d.nodes, :2], axis=0)
        out.append(Diaphragm(d.nodes, d.centre + np.array([f_x, f_y]) * L, d.mass, d.inertia))
    return changed(frame, diaphragms=tuple(out))  # (its notes were said as it was built)
