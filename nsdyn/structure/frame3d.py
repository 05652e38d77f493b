"""Space frames of 12-dof beam-columns with rigid floor diaphragms: data and sparse assembly.

The undamped, unsupported structure obeys ``M q'' + K q = f`` with six dofs per node,
node ``n`` owning ``6 n + (0 … 5)`` = (u_x, u_y, u_z, θ_x, θ_y, θ_z); ``K`` and ``M`` are
assembled sparsely from the element matrices of :mod:`nsdyn.structure.elements3d` plus
translational node masses (x, y, z each).

A rigid floor diaphragm ties the in-plane dofs of the nodes ``i`` of one level to a master
point ``c`` (the floor's centre of mass) with dofs ``(U_x, U_y, Θ)``:

    u_x,i = U_x − (y_i − y_c) Θ,   u_y,i = U_y + (x_i − x_c) Θ,   θ_z,i = Θ,

so ``q = T q_r`` with ``q_r`` = the dofs of the frame that are not tied (ascending) followed
by three master dofs per diaphragm. ``K_r = Tᵀ K T`` and ``M_r = Tᵀ M T + diag(m, m, J)`` at
the masters (floor mass ``m`` and its polar moment ``J`` about ``c``); ``T`` is sparse and
nothing dense of size n × n is formed. Out-of-plane dofs (u_z, θ_x, θ_y) stay free.

A planar :class:`nsdyn.structure.Frame` is the special case :meth:`Frame3D.from_planar`:
the plane frame's (x, y) becomes (x, z) (or (y, z)) and its rotation the one about the
plane's normal.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from nsdyn._brief import brief_repr
from nsdyn._checks import flag, mapped, number
from nsdyn._lazy import LazyModule
from nsdyn.structure.elements3d import global_matrices, local_axes
from nsdyn.structure.geometry import (
    added_mass_note,
    check_geometry,
    check_stiffness_span,
    checked_base,
    checked_zeta,
    frozen,
    material_notes,
)

sp = LazyModule("scipy.sparse")

DOFS_PER_NODE = 6  # u_x, u_y, u_z, θ_x, θ_y, θ_z
GEOM_RTOL = 1e-9  # relative tolerance of "same level" and "horizontal member"
_COMP = {"ux": 0, "uy": 1, "uz": 2, "rx": 3, "ry": 4, "rz": 5, "x": 0, "y": 1, "z": 2}
# the 3D dofs (within a node) of a plane frame's (x, y, θ) and their signs: in the x–z
# plane the plane rotation (x toward z) is −θ_y; in the y–z plane (y toward z) it is +θ_x
PLANAR_DOFS = {
    "xz": (np.array([0, 2, 4]), np.array([1.0, 1.0, -1.0])),
    "yz": (np.array([1, 2, 3]), np.array([1.0, 1.0, 1.0])),
}


@dataclass(frozen=True)
class Section3D:
    """A member's section: moduli ``E``, ``G`` [Pa], area ``A`` [m²], second moments ``I_y``,
    ``I_z`` [m⁴] (bending in the local x–z and x–y planes), St Venant constant ``J`` [m⁴],
    mass per length ``rho_A`` [kg/m] and torsional inertia per length ``rho_Ip`` [kg m]
    (default ``rho_A (I_y + I_z) / A``: a homogeneous section's ρ times its polar moment)."""

    E: float
    G: float
    A: float
    I_y: float
    I_z: float
    J: float
    rho_A: float
    rho_Ip: float | None = None

    def __post_init__(self) -> None:
        for k in ("E", "G", "A", "I_y", "I_z", "J"):  # (text: a numpy error before)
            number(f"section {k}", getattr(self, k), "a positive finite number", lambda v: v > 0)
        number("section rho_A", self.rho_A, "a finite number >= 0", lambda v: v >= 0)
        if self.rho_Ip is None:
            object.__setattr__(self, "rho_Ip", self.rho_A * (self.I_y + self.I_z) / self.A)
        else:
            number("section rho_Ip", self.rho_Ip, "a finite number >= 0", lambda v: v >= 0)


SECTION_FIELDS = ("E", "G", "A", "I_y", "I_z", "J", "rho_A", "rho_Ip")


@dataclass(frozen=True, eq=False)
class Diaphragm:
    """A rigid floor: ``nodes`` (>= 2, one elevation) tied to the master point ``centre``
    (x, y) [m]; the floor's ``mass`` [kg] acts there in x and y, its polar moment
    ``inertia`` [kg m²] about the vertical axis through ``centre``."""

    nodes: np.ndarray
    centre: np.ndarray
    mass: float = 0.0
    inertia: float = 0.0

    def __post_init__(self) -> None:
        nodes = frozen(np.atleast_1d(self.nodes), np.int64)
        if nodes.ndim != 1 or len(nodes) < 2 or len(set(nodes.tolist())) != len(nodes):
            raise ValueError(f"a diaphragm needs >= 2 distinct nodes, got {nodes.tolist()}")
        object.__setattr__(self, "nodes", nodes)
        c = frozen(self.centre, float)
        if c.shape != (2,) or not np.all(np.isfinite(c)):
            raise ValueError(f"diaphragm centre must be [x, y], got {c.tolist()}")
        object.__setattr__(self, "centre", c)
        for k in ("mass", "inertia"):
            v = float(getattr(self, k))
            if not (np.isfinite(v) and v >= 0):
                raise ValueError(f"diaphragm {k} must be >= 0 and finite, got {v!r}")
            object.__setattr__(self, k, v)


@dataclass(frozen=True, eq=False, repr=False)
class Frame3D:
    """A space frame: geometry, members with local axes, masses, diaphragms, damping.

    Attributes
    ----------
    nodes : (nn, 3) coordinates [m], z up.   elements : (ne, 2) int, start and end node.
    vecxz : (ne, 3) orientation vectors (local x–z plane, :mod:`~nsdyn.structure.elements3d`).
    E, G, A, I_y, I_z, J, rho_A, rho_Ip : (ne,) per-element section data (:class:`Section3D`);
        ``rho_Ip=None`` means ``rho_A (I_y + I_z) / A``.
    node_mass : (nn, 3) added translational mass [kg] in x, y, z (a scalar or (nn,) broadcasts
        to every direction).
    base_nodes : (nb,) int; their six dofs each form the boundary set.
    zeta : modal damping ratios in frequency order (the last one for every further mode).
    diaphragms : tuple of :class:`Diaphragm`.
    column_joints : (n_levels, n_columns) int or None: the joint of each column line at
        each level (row 0 = base), set by the generator of regular buildings.
    Arrays are stored read-only; invalid data raises ``ValueError``.
    """

    __repr__ = brief_repr  # arrays by shape, not in full

    name: str
    nodes: np.ndarray
    elements: np.ndarray
    vecxz: np.ndarray
    E: np.ndarray
    G: np.ndarray
    A: np.ndarray
    I_y: np.ndarray
    I_z: np.ndarray
    J: np.ndarray
    rho_A: np.ndarray
    rho_Ip: np.ndarray
    node_mass: np.ndarray
    base_nodes: np.ndarray
    zeta: np.ndarray
    diaphragms: tuple = field(default=())
    column_joints: np.ndarray | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():  # (None named it in reports)
            raise TypeError(f"name: expected a frame's name (non-empty text), got {self.name!r}")
        obj = object.__setattr__
        nodes, el = frozen(self.nodes, float), frozen(self.elements, np.int64)
        if nodes.ndim != 2 or nodes.shape[1] != 3 or len(nodes) < 2:
            raise ValueError(f"nodes must have shape (nn, 3), got {nodes.shape}")
        if el.ndim != 2 or el.shape[1] != 2 or len(el) < 1:
            raise ValueError(f"elements must have shape (ne, 2), got {el.shape}")
        nn, ne = len(nodes), len(el)
        if el.min() < 0 or el.max() >= nn:
            raise ValueError(f"element node index out of range 0..{nn - 1}")
        groups = [np.asarray(d.nodes).tolist() for d in self.diaphragms]
        base = checked_base(self.base_nodes, nn).tolist()
        check_geometry(nodes, el, tied=sum(groups, []), base=base, groups=groups)
        obj(self, "nodes", nodes)
        obj(self, "elements", el)
        v = frozen(np.broadcast_to(np.asarray(self.vecxz, float), (ne, 3)), float)
        obj(self, "vecxz", v)
        local_axes(nodes[el[:, 0]], nodes[el[:, 1]], v)  # raises for zero length / parallel
        for key in SECTION_FIELDS:
            a = getattr(self, key)
            if key == "rho_Ip" and a is None:  # homogeneous sections: ρ I_p = ρA (I_y + I_z)/A
                a = self.rho_A * (self.I_y + self.I_z) / self.A
            a = frozen(np.broadcast_to(np.asarray(a, float), (ne,)), float)
            bad = ~((a >= 0) if key.startswith("rho") else (a > 0)) | ~np.isfinite(a)
            if np.any(bad):
                e = int(np.argmax(bad))
                raise ValueError(
                    f"element {e}: {key} must be finite and {'>= 0' if key[0] == 'r' else '> 0'}"
                    f", got {float(a[e])!r}"
                )
            obj(self, key, a)
        material_notes(self.E, self.A, self.rho_A)
        with np.errstate(over="ignore", under="ignore"):
            L, EL3 = self.lengths, 12 * self.E / self.lengths**3
            check_stiffness_span(
                {
                    "EA/L": self.E * self.A / L,
                    "12EI_y/L³": EL3 * self.I_y,
                    "12EI_z/L³": EL3 * self.I_z,
                    "GJ/L³": self.G * self.J / L**3,
                }
            )
        nm = np.asarray(self.node_mass, float)
        nm = nm[:, None] if nm.ndim == 1 and nm.shape == (nn,) else nm
        nm = frozen(np.broadcast_to(nm, (nn, 3)), float)
        if np.any(nm < 0) or not np.all(np.isfinite(nm)):
            raise ValueError("node_mass must be >= 0 and finite")
        obj(self, "node_mass", nm)
        obj(self, "base_nodes", checked_base(self.base_nodes, nn))
        obj(self, "zeta", checked_zeta(self.zeta))
        obj(self, "diaphragms", tuple(self.diaphragms))
        self._check_diaphragms()
        plan = sum(float(d.mass) for d in self.diaphragms)  # (in x and y; a node's in its own)
        added = max(float(nm[:, 0].sum()) + plan, float(nm[:, 1].sum()) + plan, nm[:, 2].sum())
        added_mass_note(
            "node and diaphragm masses", float(added), float(np.sum(self.rho_A * self.lengths))
        )
        if self.column_joints is not None:
            cj = frozen(self.column_joints, np.int64)
            if cj.ndim != 2 or cj.min() < 0 or cj.max() >= nn:
                raise ValueError("column_joints must be (n_levels, n_columns) node indices")
            obj(self, "column_joints", cj)

    def _check_diaphragms(self) -> None:
        seen: dict[int, int] = {}
        tol = GEOM_RTOL * self.size
        for k, d in enumerate(self.diaphragms):
            if not isinstance(d, Diaphragm):
                raise ValueError(f"diaphragm {k} is not a Diaphragm")
            if d.nodes.min() < 0 or d.nodes.max() >= self.n_nodes:
                raise ValueError(f"diaphragm {k}: node index out of range 0..{self.n_nodes - 1}")
            z = self.nodes[d.nodes, 2]
            if np.ptp(z) > tol:
                raise ValueError(
                    f"diaphragm {k}: nodes are not at one level (z = {z.min():g} … {z.max():g} m)"
                )
            for n in d.nodes.tolist():
                if n in seen:
                    raise ValueError(
                        f"diaphragms[{k}].nodes: node {n} is also on diaphragms"
                        f"[{seen[n]}]; expected each node on one floor at most"
                    )
                seen[n] = k

    # ---- sizes, dofs, geometry
    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    @property
    def n_dof(self) -> int:
        return DOFS_PER_NODE * len(self.nodes)

    @property
    def size(self) -> float:
        return max(float(np.ptp(self.nodes, axis=0).max()), 1.0)

    @property
    def lengths(self) -> np.ndarray:
        d = self.nodes[self.elements[:, 1]] - self.nodes[self.elements[:, 0]]
        return np.linalg.norm(d, axis=1)

    def local_axes(self) -> np.ndarray:
        """Rows e_x, e_y, e_z of each element's local frame, shape (ne, 3, 3)."""
        return local_axes(
            self.nodes[self.elements[:, 0]], self.nodes[self.elements[:, 1]], self.vecxz
        )

    def dofs(self, nodes, component: int | str) -> np.ndarray:
        """Full dof index of ``component`` (0–5 or 'ux' 'uy' 'uz' 'rx' 'ry' 'rz') at ``nodes``."""
        c = _COMP.get(component, component)
        return DOFS_PER_NODE * np.asarray(nodes, dtype=np.int64) + int(c)

    def element_dofs(self) -> np.ndarray:
        """Full dofs of each element, shape (ne, 12)."""
        e = DOFS_PER_NODE * self.elements
        r = np.arange(DOFS_PER_NODE)
        return np.concatenate([e[:, :1] + r, e[:, 1:] + r], axis=1)

    @property
    def boundary_dofs(self) -> np.ndarray:
        """The six dofs of each base node, node by node, shape (6 nb,)."""
        return (DOFS_PER_NODE * self.base_nodes[:, None] + np.arange(6)).ravel()

    @property
    def total_mass(self) -> float:
        """Members, node masses (x direction) and diaphragm masses [kg]."""
        return float(
            np.sum(self.rho_A * self.lengths)
            + self.node_mass[:, 0].sum()
            + sum(d.mass for d in self.diaphragms)
        )

    def massless_nodes(self) -> np.ndarray:
        """Nodes above the base with no mass at all: no node mass, on no diaphragm with mass
        and every member there with ``rho_A = 0`` (a cb or full rung's M is singular)."""
        held = {int(n) for d in self.diaphragms if d.mass > 0 for n in d.nodes}
        held |= set(self.elements[self.rho_A > 0].ravel().tolist())
        held |= set(np.flatnonzero(self.node_mass.any(axis=1)).tolist()) | set(self.base_nodes)
        return np.array([n for n in range(self.n_nodes) if n not in held], dtype=np.int64)

    def massless_note(self, model: str) -> str | None:
        """Why ``model``'s mass matrix is singular, naming the first of :meth:`massless_nodes`
        (None when every node has a mass)."""
        bare = self.massless_nodes()
        if not len(bare):  # (a mass that lumps translations alone: rotations without any)
            spun = set(self.elements[self.rho_A > 0].ravel().tolist()) | set(self.base_nodes)
            spin = [n for n in range(self.n_nodes) if n not in spun]
            return spin and (
                f"frame3d: nodes[{spin[0]}] (z = {self.nodes[spin[0], 2]:g} m): every member "
                f"there has no mass (a section's rho = 0), so its rotations have none (node "
                f"and floor masses lump translations) and the {model!r} model's mass matrix is "
                "singular; expected a positive rho on a member at every node, or fidelity "
                "'rigid'") or None  # fmt: skip
        return (
            f"frame3d: nodes[{bare[0]}] (z = {self.nodes[bare[0], 2]:g} m) has no mass (no "
            f"floor, node or member mass), so the {model!r} model's mass matrix is "
            "singular; expected a mass on every floor, or fidelity 'rigid'"
        )

    def levels(self) -> tuple[np.ndarray, tuple]:
        """Elevations carrying a diaphragm or a horizontal member, ascending, and the nodes
        at each (the base elevation first)."""
        tol = GEOM_RTOL * self.size
        z = self.nodes[:, 2]
        d = self.nodes[self.elements[:, 1]] - self.nodes[self.elements[:, 0]]
        flat = np.abs(d[:, 2]) <= tol
        zs = [float(z[self.base_nodes].min())] + z[self.elements[flat].ravel()].tolist()
        zs += [float(z[dd.nodes[0]]) for dd in self.diaphragms]
        heights: list[float] = []
        for v in sorted(zs):
            if not heights or v - heights[-1] > tol:
                heights.append(v)
        nodes = tuple(np.flatnonzero(np.abs(z - h) <= tol) for h in heights)
        return np.array(heights), nodes

    # ---- matrices
    def assemble(self, lumped: bool = False):
        """Sparse ``(K, M)`` (csr, n_dof × n_dof) of the free frame, without diaphragms.

        ``lumped``: HRZ-lumped element mass instead of consistent. ``M`` includes the node
        masses, not the diaphragm masses (those act on the masters: :meth:`reduced`).
        """
        lumped = flag("lumped", lumped)  # (lumped="yes" was taken as True)
        n0, n1 = self.nodes[self.elements[:, 0]], self.nodes[self.elements[:, 1]]
        ke, me = global_matrices(
            n0,
            n1,
            self.vecxz,
            self.E,
            self.G,
            self.A,
            self.I_y,
            self.I_z,
            self.J,
            self.rho_A,
            self.rho_Ip,
            lumped=lumped,
        )
        dofs = self.element_dofs()
        rows = np.repeat(dofs, 12, axis=1).ravel()
        cols = np.tile(dofs, (1, 12)).ravel()
        n = self.n_dof
        K = sp.coo_array((ke.ravel(), (rows, cols)), shape=(n, n)).tocsr()
        nm = np.zeros((self.n_nodes, DOFS_PER_NODE))
        nm[:, :3] = self.node_mass
        M = sp.coo_array((me.ravel(), (rows, cols)), shape=(n, n)) + sp.diags_array(nm.ravel())
        return ((K + K.T) / 2).tocsr(), ((M + M.T) / 2).tocsr()

    @cached_property
    def _constraint(self):
        n = self.n_dof
        slave = np.zeros(n, bool)
        for d in self.diaphragms:
            for c in (0, 1, 5):
                slave[DOFS_PER_NODE * d.nodes + c] = True
        kept = np.flatnonzero(~slave)
        nk, nd = len(kept), len(self.diaphragms)
        masters = nk + np.arange(3 * nd).reshape(nd, 3)
        rows, cols, vals = [kept], [np.arange(nk)], [np.ones(nk)]
        for d, (a, b, c) in zip(self.diaphragms, masters, strict=True):
            dx, dy = (self.nodes[d.nodes, :2] - d.centre).T
            ux, uy, rz = (DOFS_PER_NODE * d.nodes + k for k in (0, 1, 5))
            one = np.ones(len(d.nodes))
            rows += [ux, ux, uy, uy, rz]
            cols += [a * one, c * one, b * one, c * one, c * one]
            vals += [one, -dy, one, dx, one]
        T = sp.coo_array(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols).astype(np.int64))),
            shape=(n, nk + 3 * nd),
        )
        return T.tocsr(), kept, masters

    @property
    def T(self):
        """Sparse constraint transformation ``q = T q_r`` (n_dof × n_red, csr)."""
        return self._constraint[0]

    @property
    def master_dofs(self) -> np.ndarray:
        """Reduced indices of each diaphragm's ``(U_x, U_y, Θ)``, shape (n_diaphragms, 3)."""
        return self._constraint[2]

    @property
    def n_red(self) -> int:
        return self.T.shape[1]

    def reduced(self, lumped: bool = False):
        """Sparse ``(K_r, M_r)`` in the diaphragm-constrained coordinates ``q_r``."""
        K, M = self.assemble(lumped=lumped)
        T = self.T
        md = np.zeros(self.n_red)
        for d, (a, b, c) in zip(self.diaphragms, self.master_dofs, strict=True):
            md[[a, b, c]] = d.mass, d.mass, d.inertia
        Kr = (T.T @ K @ T).tocsr()
        Mr = (T.T @ M @ T + sp.diags_array(md)).tocsr()
        return ((Kr + Kr.T) / 2).tocsr(), ((Mr + Mr.T) / 2).tocsr()

    @property
    def boundary_reduced(self) -> np.ndarray:
        """Reduced dofs that move any base-node dof (clamped for fixed-base modes)."""
        B = self.T[self.boundary_dofs]
        return np.unique(B.tocoo().col).astype(np.int64)

    def rigid_motions(self, centre=None) -> np.ndarray:
        """Rigid motions in reduced coordinates, shape (n_red, 4): translations x, y, z and
        the rotation about the vertical axis through ``centre`` (default: the origin)."""
        x0, y0 = (0.0, 0.0) if centre is None else centre
        full = np.zeros((self.n_nodes, DOFS_PER_NODE, 4))
        full[:, 0, 0] = full[:, 1, 1] = full[:, 2, 2] = 1.0
        full[:, 0, 3] = -(self.nodes[:, 1] - y0)
        full[:, 1, 3] = self.nodes[:, 0] - x0
        full[:, 5, 3] = 1.0
        _, kept, masters = self._constraint
        r = np.zeros((self.n_red, 4))
        r[: len(kept)] = full.reshape(self.n_dof, 4)[kept]
        for d, (a, b, c) in zip(self.diaphragms, masters, strict=True):
            r[a, 0] = r[b, 1] = 1.0  # Θ does not move in a translation
            r[[a, b, c], 3] = -(d.centre[1] - y0), d.centre[0] - x0, 1.0
        return r

    def expand(self, q_r: np.ndarray) -> np.ndarray:
        """Full displacements ``T q_r``; ``q_r`` shape (n_red,) or (n_red, m)."""
        return mapped(self.T, q_r, "q_r")

    # ---- planar frames
    @classmethod
    def from_planar(cls, frame, plane: str = "xz", I_out=None, J=None, G=None, nu: float = 0.3):
        """The 3D frame of a plane :class:`~nsdyn.structure.Frame` (no diaphragms).

        The plane frame's y axis becomes z; its x axis becomes x (``plane="xz"``) or y
        (``"yz"``). Members get the plane's normal as orientation vector, so the plane
        bending uses ``I_z = I``; out of the plane ``I_y = I_out`` (default ``I``), torsion
        ``J`` (default ``I + I_out``), ``G`` (default ``E / 2(1 + nu)``). Node masses act
        in all three directions. See :data:`PLANAR_DOFS` for the dof correspondence. The
        plane frame's damping ratios go to the modes in the plane as in the plane frame, the
        k-th in-plane mode taking its k-th ratio, and alike to the modes out of it
        (:func:`~nsdyn.structure.modes3d.plane_ratios`): in the 3D frequency order the soft
        out-of-plane modes come first and would take the plane's first ratios.
        """
        if plane not in PLANAR_DOFS:
            raise ValueError(f"plane must be 'xz' or 'yz', got {plane!r}")
        # (a Frame3D failed on its missing I, an AttributeError)
        if not (hasattr(frame, "I") and np.shape(frame.nodes)[-1:] == (2,)):
            raise TypeError(f"frame: expected a plane Frame (nsdyn.load_frame), got "
                            f"{type(frame).__name__}")  # fmt: skip
        nodes = np.zeros((frame.n_nodes, 3))
        nodes[:, 0 if plane == "xz" else 1] = frame.nodes[:, 0]
        nodes[:, 2] = frame.nodes[:, 1]
        normal = [0.0, 1.0, 0.0] if plane == "xz" else [1.0, 0.0, 0.0]
        I_out = frame.I if I_out is None else I_out
        out = cls(
            name=frame.name if isinstance(frame.name, str) and frame.name.strip() else "planar",
            nodes=nodes,
            elements=frame.elements,
            vecxz=normal,
            E=frame.E,
            G=frame.E / (2 * (1 + nu)) if G is None else G,
            A=frame.A,
            I_y=I_out,
            I_z=frame.I,
            J=frame.I + I_out if J is None else J,
            rho_A=frame.rho_A,
            rho_Ip=frame.rho_A * (frame.I + I_out) / frame.A,
            node_mass=frame.node_mass,
            base_nodes=frame.base_nodes,
            zeta=frame.zeta,
        )
        from nsdyn.structure.modes3d import plane_ratios

        object.__setattr__(out, "zeta", plane_ratios(out, frame.zeta, plane))
        return out


def changed(frame: Frame3D, **changes) -> Frame3D:
    """``dataclasses.replace(frame, **changes)`` without its members' notes said again (a
    modulus in MPa, near-massless members: said once, as the frame was built)."""
    import warnings
    from dataclasses import replace

    from nsdyn._checks import NotedWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NotedWarning)
        return replace(frame, **changes)


def planar_dofs(n_nodes: int, plane: str = "xz") -> tuple[np.ndarray, np.ndarray]:
    """Full 3D dof indices and signs of a plane frame's dofs ``3 n + (0, 1, 2)``.

    ``q3d[idx] = sign * q2d`` embeds a plane frame's displacements (shape (3 n_nodes,)).
    """
    local, sign = PLANAR_DOFS[plane]
    idx = (DOFS_PER_NODE * np.arange(n_nodes)[:, None] + local).ravel()
    return idx, np.tile(sign, n_nodes)
