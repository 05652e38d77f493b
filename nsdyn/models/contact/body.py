"""Planar rigid body: convex polygon geometry, mass properties and its base contacts.

A body is a convex polygon of uniform density (vertices counter-clockwise).  Mass properties of
a polygon with vertices p_k (Green's theorem, c_k = p_k x p_{k+1}):

    A = 1/2 sum c_k,   centroid = sum (p_k + p_{k+1}) c_k / (6 A),
    J_O = rho/12 sum c_k (p_k.p_k + p_k.p_{k+1} + p_{k+1}.p_{k+1}),  J = J_O - m |centroid|^2.

The contacts are the base vertices (the lowest ones in the resting pose, on the ground line).
Rocking about a base corner ends in overturning when the side edge from it lies on the ground,
at the tilt of that edge's angle from the horizontal (RigidBody.overturn_tilts: pi - phi where
the base is an edge, phi the interior angle at the corner); for a rectangle of width 2b
and height 2h: alpha = atan(b/h), R = sqrt(b^2 + h^2), p^2 = m g R / J_O = 3 g / (4 R).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nsdyn._checks import number

BASE_TOL = 1e-9  # relative height tolerance for a vertex to belong to the base
COLLINEAR_TOL = 1e-12  # relative cross-product below which three vertices are collinear


MAX_SIZE_M = 1e6  # a body's vertices lie within this of the origin [m]


def _check_polygon(verts: np.ndarray, field: str) -> np.ndarray:
    """Counter-clockwise convex polygon, or ValueError naming ``field`` and the offending vertex."""
    try:
        p = np.asarray(verts, dtype=float)
    except (TypeError, ValueError):  # text, or rows of different lengths
        raise ValueError(f"{field}: expected a list of [x, y] numbers [m], got {verts!r}") from None
    if isinstance(verts, str | bytes) or np.asarray(verts).dtype.kind in "USb":
        raise ValueError(f"{field}: expected a list of [x, y] numbers [m], got {verts!r}")
    if p.ndim != 2 or p.shape[1] != 2 or p.shape[0] < 3:
        raise ValueError(f"{field}: expected an (n, 2) array of n >= 3 vertices, got shape "
                         f"{p.shape}")  # fmt: skip
    if not np.all(np.isfinite(p)):
        raise ValueError(f"{field}: vertices must be finite numbers")
    if np.abs(p).max() > MAX_SIZE_M:
        raise ValueError(f"{field}: a vertex {np.abs(p).max():.3g} m from the origin; expected "
                         f"vertices in metres, within {MAX_SIZE_M:.0e} m")  # fmt: skip
    n = len(p)
    area2 = float(np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1]))
    size = float(np.ptp(p, axis=0).max())
    if abs(area2) <= COLLINEAR_TOL * size**2:
        raise ValueError(f"{field}: polygon has zero area (its vertices collinear, or its edges "
                         "crossing: expected a convex polygon, vertices in order)")  # fmt: skip
    if area2 < 0:
        p = p[::-1].copy()
    for k in range(n):
        a, b, c = p[k - 1], p[k], p[(k + 1) % n]
        cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])
        if cross < -COLLINEAR_TOL * size**2:
            raise ValueError(f"{field}: polygon is not convex at vertex {k} ({b[0]:g}, {b[1]:g}) "
                             "(expected a convex polygon, vertices in order)")  # fmt: skip
        if abs(cross) <= COLLINEAR_TOL * size**2:
            raise ValueError(f"{field}: vertex {k} ({b[0]:g}, {b[1]:g}) is collinear with its "
                             "neighbours or repeated (remove it)")  # fmt: skip
    # a simple polygon turns once: the turning angles sum to 2 pi
    e = np.roll(p, -1, axis=0) - p
    ang = np.arctan2(e[:, 1], e[:, 0])
    turn = np.sum((np.roll(ang, -1) - ang + np.pi) % (2 * np.pi) - np.pi)
    if abs(turn - 2 * np.pi) > 1e-6:
        raise ValueError(f"{field}: polygon is self-intersecting (expected a convex polygon)")
    return p


@dataclass(frozen=True)
class RigidBody:
    """A convex polygonal rigid body of uniform density resting on its lowest edge or vertex.

    Attributes
    ----------
    verts : (n, 2) vertices relative to the centre of mass, counter-clockwise [m]
    mass : m [kg];  J : moment of inertia about the centre of mass [kg m^2]
    base : (nb,) indices of the base (contact) vertices

    Built directly (not by :meth:`polygon` or :meth:`rectangle`), it is checked as they
    check: counter-clockwise convex vertices, positive mass and J, a base of lowest vertices.
    """

    verts: np.ndarray
    mass: float
    J: float
    base: np.ndarray

    def __post_init__(self) -> None:  # (the builders below give valid bodies; so must a call)
        v = _check_polygon(self.verts, "verts")
        if not np.array_equal(v, np.asarray(self.verts, dtype=float)):
            raise ValueError("verts: expected the vertices counter-clockwise")
        number("mass", self.mass, "a positive mass [kg]", lambda x: x > 0)
        number("J", self.J, "a positive moment of inertia [kg m^2]", lambda x: x > 0)
        b = np.asarray(self.base)
        low = v[:, 1].min() + BASE_TOL * float(np.ptp(v, axis=0).max())
        lowest = np.flatnonzero(v[:, 1] <= low)  # (all of them: a part of the base's sides
        if not (b.ndim == 1 and b.size and b.dtype.kind in "iu" and b.min() >= 0  # overturn
                and b.max() < len(v) and set(b.tolist()) == set(lowest.tolist())):  # fmt: skip
            raise ValueError(f"base: expected the indices of the lowest vertices, "
                             f"{lowest.tolist()}, got {self.base!r}")  # fmt: skip
        object.__setattr__(self, "verts", v.copy())  # (its own: not the caller's array)
        object.__setattr__(self, "base", b.astype(np.int64))

    @classmethod
    def polygon(cls, vertices, mass: float = 1.0, J: float | None = None) -> RigidBody:
        """Body from a convex polygon (any position; shifted to its centroid).

        ``J`` defaults to the uniform-density value.  Raises ValueError naming ``vertices``,
        ``mass`` or ``J`` on bad input.
        """
        m = float(mass)
        if not (m > 0 and math.isfinite(m)):
            raise ValueError(f"mass: expected a positive number [kg], got {mass!r}")
        p = _check_polygon(vertices, "vertices")
        q = np.roll(p, -1, axis=0)
        cr = p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]
        area = 0.5 * cr.sum()
        cen = ((p + q) * cr[:, None]).sum(axis=0) / (6 * area)
        rho = m / area
        j_o = rho / 12 * np.sum(cr * (np.sum(p * p, 1) + np.sum(p * q, 1) + np.sum(q * q, 1)))
        j_c = j_o - m * float(cen @ cen)
        if J is not None:
            j_c = float(J)
            if not (j_c > 0 and math.isfinite(j_c)):
                raise ValueError(f"J: expected a positive moment of inertia [kg m^2], got {J!r}")
        v = p - cen
        ymin = v[:, 1].min()
        size = float(np.ptp(v, axis=0).max())
        base = np.flatnonzero(v[:, 1] <= ymin + BASE_TOL * size)
        return cls(v, m, float(j_c), base)

    @classmethod
    def rectangle(cls, width: float, height: float, mass: float = 1.0) -> RigidBody:
        """Rectangle of full ``width`` 2b and ``height`` 2h [m] (uniform density)."""
        width, height = (number(name, val, "a positive size [m]", lambda x: x > 0)
                         for name, val in (("width", width), ("height", height)))  # fmt: skip
        b, h = width / 2, height / 2
        return cls.polygon([(-b, -h), (b, -h), (b, h), (-b, h)], mass)

    @property
    def contacts(self) -> np.ndarray:
        """(nb, 2) base vertices relative to the centre of mass."""
        return np.ascontiguousarray(self.verts[self.base])

    def unit_mass(self) -> RigidBody:
        """This body at 1 kg (J / m): on rigid ground its motion is the same (gravity, the
        base's acceleration, the contact forces and friction all scale with the mass), and the
        rigid-contact solvers run on it, so that their LCP tolerances meet forces of order g
        (at 1e-12 kg Moreau-Jean slid 1.68 m where every mass from 1e-3 to 1e9 kg slid 0.0495 m,
        and the event-driven solver missed a touchdown)."""
        return RigidBody(self.verts, 1.0, self.J / self.mass, self.base)

    @property
    def minv(self) -> np.ndarray:
        """(3,) diagonal of M^-1 = diag(1/m, 1/m, 1/J)."""
        return np.array([1 / self.mass, 1 / self.mass, 1 / self.J])

    @property
    def y0(self) -> float:
        """Height of the centre of mass above the ground when resting on the base."""
        return -float(self.verts[self.base, 1].min())

    @property
    def width(self) -> float:
        """Base width (distance between the outermost base vertices) [m]."""
        xb = self.verts[self.base, 0]
        return float(xb.max() - xb.min())

    @property
    def theta_ov(self) -> float:
        """The smaller of :attr:`overturn_tilts` [rad]."""
        return min(self.overturn_tilts)

    @property
    def overturn_tilts(self) -> tuple[float, float]:
        """(theta_ov+, theta_ov-) [rad]: the tilts theta > 0 (rocking about the left outer base
        corner) and -theta > 0 (about the right one) at which the side edge from that corner
        lies on the ground: pi less its angle from the horizontal on the left, that angle on
        the right (pi - the interior angle where the base is an edge; a body on one vertex
        has its two edges). A body with an overhanging side has two: tipping away from the
        overhang it lies down only when its other side does. The contacts are the base
        vertices, so a side edge that meets the ground before the centre of mass passes over
        the pivot (an obtuse base corner, theta_ov below that side's alpha) ends the run
        there, overturned, though the body would land on it and could rock back."""
        n = len(self.verts)
        left = self.base[np.argmin(self.verts[self.base, 0])]
        right = self.base[np.argmax(self.verts[self.base, 0])]
        el = self.verts[left - 1] - self.verts[left]  # (counter-clockwise: up the left side)
        er = self.verts[(right + 1) % n] - self.verts[right]  # (up the right side)
        return math.pi - math.atan2(el[1], el[0]), math.atan2(er[1], er[0])

    def overturned(self, theta: float) -> bool:
        """Whether the tilt ``theta`` [rad] lays the body on an edge (:attr:`overturn_tilts`)."""
        pos, neg = self.overturn_tilts
        return theta >= pos or -theta >= neg

    def corner_geometry(self, side: int = 1) -> tuple[float, float, float]:
        """(R, alpha, J_O) of rocking about the outer base corner on ``side`` (+1 right, -1 left):
        R the distance from the corner to the centre of mass, alpha the angle of that line from
        the vertical, J_O = J + m R^2."""
        xb = self.verts[self.base, 0]
        k = self.base[np.argmax(xb) if side > 0 else np.argmin(xb)]
        dx, dy = -self.verts[k]
        R = math.hypot(dx, dy)
        return R, math.atan2(abs(dx), dy), self.J + self.mass * R * R
