"""Plane frames of 2D Bernoulli–Euler beam elements: geometry, sections, levels and assembly.

The undamped, unsupported superstructure obeys

    M q'' + K q = f,        q = [x_0, y_0, th_0, x_1, y_1, th_1, ...],

with three dofs per node (horizontal and vertical displacement, rotation), so node ``n``
owns dofs ``3 n + (0, 1, 2)``. ``K`` and ``M`` are assembled from element matrices
(axial bar + cubic Hermite bending, :mod:`nsdyn.structure.elements`) and nodal added
translational masses. No support is applied here: the base nodes' dofs form the boundary set
that the reduction and the isolation model act on, and ``K`` keeps its three rigid-body modes.

Frames are built by :func:`regular_frame` (bays x storeys, meshed with ``n_v`` elements
per column segment and ``n_h`` per beam) or listed node by node, and are read from TOML
files by :func:`nsdyn.structure.load_frame`; see ``frames/office-11.toml`` and
``frames/portal.toml``.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from nsdyn._brief import brief_repr
from nsdyn._checks import expect, finite_numbers, flag, number, whole
from nsdyn._lazy import LazyModule
from nsdyn.structure.elements import element_matrices
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

DOFS_PER_NODE = 3  # x, y, theta
GEOM_RTOL = 1e-9  # relative tolerance for "same elevation" / "vertical member" tests
MAX_DOF = 1_000_000  # a regular frame's dofs: 50x the largest the benchmarks run (20 000)


@dataclass(frozen=True)
class Section:
    """Cross-section of a member: modulus ``E`` [Pa], area ``A`` [m^2], second moment
    ``I`` [m^4] and mass per length ``rho_A`` [kg/m] (steel plus any attached mass)."""

    E: float
    A: float
    I: float
    rho_A: float

    def __post_init__(self) -> None:  # (text, "2e11", was converted; a bool taken as 1)
        for key in ("E", "A", "I"):
            number(key, getattr(self, key), "a positive finite number", lambda v: v > 0)
        number("rho_A", self.rho_A, "a finite mass per length >= 0 [kg/m]", lambda v: v >= 0)


@dataclass(frozen=True, eq=False, repr=False)
class Frame:
    """A plane frame: geometry, members, added masses and modal damping ratios.

    Attributes
    ----------
    name : str
    nodes : ndarray, shape (nn, 2)
        Node coordinates (x, y) [m]; y is up.
    elements : ndarray of int, shape (ne, 2)
        Start and end node of each element.
    E, A, I, rho_A : ndarray, shape (ne,)
        Per-element modulus [Pa], area [m^2], second moment [m^4], mass per length [kg/m].
    node_mass : ndarray, shape (nn,)
        Added translational mass at each node [kg] (acts in x and y, not in rotation).
    base_nodes : ndarray of int, shape (nb,)
        Nodes at the isolation interface, left to right. Their dofs, node by node
        ``x1, y1, th1, x2, y2, th2, ...``, form the boundary set (:attr:`boundary_dofs`).
    zeta : ndarray, shape (nz,)
        Modal damping ratios of the fixed-base modes in frequency order. Modes beyond the
        list get the LAST listed ratio (see :func:`nsdyn.structure.reduction.damping_ratios`).
    level_nodes : tuple of ndarray of int
        Nodes at each construction level; index 0 is the base level.
    level_heights : ndarray, shape (n_levels,)
        Elevation of each level [m].
    column_joints : ndarray of int, shape (n_levels, n_columns), or None
        Column-line joint node at each level (row 0 = base), used for storey drifts.
        None when the column lines are not regular.

    When ``level_heights`` / ``level_nodes`` are not given (frames listed node by node),
    the levels are the base elevation plus every elevation carrying a horizontal member,
    and the column joints are the nodes there that touch a vertical member.
    Arrays are stored read-only.
    """

    __repr__ = brief_repr  # arrays by shape, not in full

    name: str
    nodes: np.ndarray
    elements: np.ndarray
    E: np.ndarray
    A: np.ndarray
    I: np.ndarray
    rho_A: np.ndarray
    node_mass: np.ndarray
    base_nodes: np.ndarray
    zeta: np.ndarray
    level_nodes: tuple = field(default=())
    level_heights: np.ndarray = field(default=None)
    column_joints: np.ndarray | None = None

    def __post_init__(self) -> None:
        nodes = frozen(self.nodes, float)
        elements = frozen(self.elements, np.int64)
        if nodes.ndim != 2 or nodes.shape[1] != 2 or len(nodes) < 2:
            raise ValueError(f"nodes must have shape (nn, 2), got {nodes.shape}")
        if elements.ndim != 2 or elements.shape[1] != 2 or len(elements) < 1:
            raise ValueError(f"elements must have shape (ne, 2), got {elements.shape}")
        nn, ne = len(nodes), len(elements)
        if elements.min() < 0 or elements.max() >= nn:
            raise ValueError(f"element node index out of range 0..{nn - 1}")
        check_geometry(nodes, elements, base=checked_base(self.base_nodes, nn).tolist())
        obj = object.__setattr__
        obj(self, "nodes", nodes)
        obj(self, "elements", elements)
        for key in ("E", "A", "I", "rho_A"):
            v = frozen(np.broadcast_to(np.asarray(getattr(self, key), float), (ne,)), float)
            bad = v < 0 if key == "rho_A" else v <= 0
            if np.any(bad) or not np.all(np.isfinite(v)):
                raise ValueError(f"element {key} must be positive and finite")
            obj(self, key, v)
        material_notes(self.E, self.A, self.rho_A)
        L = np.linalg.norm(nodes[elements[:, 1]] - nodes[elements[:, 0]], axis=1)
        with np.errstate(over="ignore", under="ignore"):
            check_stiffness_span(
                {"EA/L": self.E * self.A / L, "12EI/L³": 12 * self.E * self.I / L**3}
            )
        nm = np.asarray(self.node_mass, float)
        if nm.ndim > 1 or nm.size not in (1, nn):
            raise ValueError(f"node_mass: expected one value or one per node ({nn}), got "
                             f"{nm.size}")  # fmt: skip
        nm = frozen(np.broadcast_to(nm, (nn,)), float)
        if np.any(nm < 0) or not np.all(np.isfinite(nm)):
            raise ValueError("node_mass must be finite and >= 0")
        obj(self, "node_mass", nm)
        added_mass_note("node masses", float(nm.sum()), float(np.sum(self.rho_A * L)))
        obj(self, "base_nodes", checked_base(self.base_nodes, nn))
        obj(self, "zeta", checked_zeta(self.zeta))
        if self.level_heights is None or len(self.level_nodes) == 0:
            lh, ln, cj = _derive_levels(nodes, elements, self.base_nodes)
            obj(self, "level_heights", lh)
            obj(self, "level_nodes", ln)
            if self.column_joints is None:
                obj(self, "column_joints", cj)
        else:
            obj(self, "level_heights", frozen(self.level_heights, float))
            obj(self, "level_nodes", tuple(frozen(n, np.int64) for n in self.level_nodes))
        if self.column_joints is not None:
            obj(self, "column_joints", frozen(self.column_joints, np.int64))

    def massless_rotations(self) -> np.ndarray:
        """Nodes whose elements all have ``rho_A = 0``: their rotations carry no mass (node
        masses lump translations only), and the mass matrix is singular. Every element with
        mass has a positive-definite consistent mass over its six dofs, so with one at each
        node M is positive definite."""
        massive = set(self.elements[self.rho_A > 0].ravel().tolist())
        return np.array([n for n in range(self.n_nodes) if n not in massive], dtype=np.int64)

    def require_mass(self, model: str) -> None:
        """ValueError naming the first node of :meth:`massless_rotations` when ``model`` is
        one whose mass matrix must be positive definite (the ``"cb"`` and ``"full"`` rungs;
        the fixed-base modes, the rigid and the fixed-base models take a singular M)."""
        bare = self.massless_rotations() if model in ("cb", "full") else ()
        if len(bare):
            raise ValueError(
                f"nodes[{bare[0]}] of frame {self.name!r}: every element there has rho_A = 0, "
                f"so its rotation has no mass (node masses lump translations) and the "
                f"{model!r} model's mass matrix is singular; expected a positive rho_A on an "
                "element at every node, or fidelity 'rigid' or 'fixed'"
            )

    # ---- sizes and dof maps
    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    @property
    def n_dof(self) -> int:
        return DOFS_PER_NODE * len(self.nodes)

    @property
    def boundary_dofs(self) -> np.ndarray:
        """Dofs of the base nodes, ``x1, y1, th1, x2, y2, th2, ...``, shape (3 nb,)."""
        return (DOFS_PER_NODE * self.base_nodes[:, None] + np.arange(3)).ravel()

    @property
    def internal_dofs(self) -> np.ndarray:
        """All dofs not in :attr:`boundary_dofs`, ascending."""
        return np.setdiff1d(np.arange(self.n_dof), self.boundary_dofs)

    def dofs(self, nodes, component: int | str) -> np.ndarray:
        """Global dof index of ``component`` (0/'x', 1/'y', 2/'theta') at ``nodes``."""
        comp = {"x": 0, "y": 1, "theta": 2, "th": 2}.get(component, component)
        return DOFS_PER_NODE * np.asarray(nodes, dtype=np.int64) + int(comp)

    # ---- geometry
    @property
    def lengths(self) -> np.ndarray:
        d = self.nodes[self.elements[:, 1]] - self.nodes[self.elements[:, 0]]
        return np.hypot(d[:, 0], d[:, 1])

    @property
    def storey_heights(self) -> np.ndarray:
        return np.diff(self.level_heights)

    @property
    def n_levels(self) -> int:
        return len(self.level_heights)

    @property
    def height(self) -> float:
        return float(self.level_heights[-1] - self.level_heights[0])

    # ---- mass
    @property
    def total_mass(self) -> float:
        """Element mass plus added nodal mass [kg]."""
        return float(np.sum(self.rho_A * self.lengths) + np.sum(self.node_mass))

    # ---- matrices
    def element_dofs(self) -> np.ndarray:
        """Global dofs of each element, shape (ne, 6)."""
        e = DOFS_PER_NODE * self.elements
        return np.concatenate([e[:, :1] + np.arange(3), e[:, 1:] + np.arange(3)], axis=1)

    def assemble(self, lumped: bool = False, sparse: bool = True):
        """Global stiffness and mass matrices ``(K, M)`` of the free (unsupported) frame.

        Parameters
        ----------
        lumped : bool
            HRZ-lumped instead of consistent element mass
            (see :func:`nsdyn.structure.elements.beam_mass`).
        sparse : bool
            Return ``scipy.sparse.csr_array`` (default) or dense ndarrays.

        Returns
        -------
        K, M : shape (n_dof, n_dof), symmetric; M positive definite.
        """
        lumped, sparse = flag("lumped", lumped), flag("sparse", sparse)
        ke, me = element_matrices(self, lumped=lumped)
        dofs = self.element_dofs()
        rows = np.repeat(dofs, 6, axis=1).ravel()
        cols = np.tile(dofs, (1, 6)).ravel()
        n = self.n_dof
        K = sp.coo_array((ke.ravel(), (rows, cols)), shape=(n, n)).tocsr()
        nm = np.zeros(n)
        nm[0::3] = self.node_mass
        nm[1::3] = self.node_mass
        M = (sp.coo_array((me.ravel(), (rows, cols)), shape=(n, n)) + sp.diags_array(nm)).tocsr()
        K = ((K + K.T) / 2).tocsr()
        M = ((M + M.T) / 2).tocsr()
        if not sparse:
            return K.toarray(), M.toarray()
        return K, M

    def influence(self) -> np.ndarray:
        """Rigid-body influence vectors ``r``, shape (n_dof, 2): column 0 is 1 at every x
        dof (horizontal ground motion), column 1 is 1 at every y dof (vertical)."""
        r = np.zeros((self.n_dof, 2))
        r[0::3, 0] = 1.0
        r[1::3, 1] = 1.0
        return r

    def storey_drift(self, u: np.ndarray) -> np.ndarray:
        """Inter-storey drift ratio of each column line.

        Parameters
        ----------
        u : ndarray, shape (n_dof,) or (n_dof, nt)
            Displacements relative to the ground.

        Returns
        -------
        ndarray, shape (n_storeys, n_columns) or (n_storeys, n_columns, nt)
        """
        if self.column_joints is None:
            raise ValueError(f"frame {self.name!r} has no regular column lines")
        x = np.asarray(u)[DOFS_PER_NODE * self.column_joints]
        h = self.storey_heights.reshape((-1, 1) + (1,) * (x.ndim - 2))
        return np.diff(x, axis=0) / h


def base_isolation_frequency(frame: Frame, k_lam: float) -> float:
    """Base-isolation frequency [Hz] of the frame as a rigid body on its isolators.

    ``f_bis = sqrt(n_b K_lam / M_s) / (2 pi)`` with one laminated bearing of lateral
    stiffness ``k_lam`` [N/m] under each base node (seed 004 eq. 28, n_b = 2). ``frame``: a
    :class:`Frame` or a bundled frame's name or a frame file.
    """
    if isinstance(frame, str | os.PathLike):  # (as build_system takes it)
        from nsdyn.structure.frame_toml import load_frame

        frame = load_frame(frame)
    expect("frame", frame, isinstance(frame, Frame), "a Frame, a bundled frame's name or a "
           "frame file (a system's frame is system.frame)")  # fmt: skip
    if isinstance(k_lam, bool) or not (isinstance(k_lam, int | float | np.number) and k_lam > 0
                                       and np.isfinite(k_lam)):  # fmt: skip
        raise ValueError(f"k_lam: expected a positive finite stiffness [N/m], got {k_lam!r}")
    return float(np.sqrt(len(frame.base_nodes) * k_lam / frame.total_mass) / (2 * np.pi))


def _derive_levels(nodes, elements, base):
    """Levels of a frame listed node by node: base elevation plus every beam elevation."""
    scale = max(float(np.ptp(nodes[:, 1])), float(np.ptp(nodes[:, 0])), 1.0)
    tol = GEOM_RTOL * scale
    d = nodes[elements[:, 1]] - nodes[elements[:, 0]]
    horizontal = np.abs(d[:, 1]) <= tol
    vertical = np.abs(d[:, 0]) <= tol
    ys = [float(nodes[base, 1].min())] + nodes[elements[horizontal].ravel(), 1].tolist()
    heights: list[float] = []
    for y in sorted(ys):
        if not heights or y - heights[-1] > tol:
            heights.append(y)
    level_nodes = tuple(
        frozen(np.flatnonzero(np.abs(nodes[:, 1] - y) <= tol), np.int64) for y in heights
    )
    col_nodes = set(elements[vertical].ravel().tolist())
    joints = []
    for ln in level_nodes:
        j = [n for n in ln.tolist() if n in col_nodes]
        joints.append(sorted(j, key=lambda n: nodes[n, 0]))
    ok = len(joints) > 1 and all(len(j) == len(joints[0]) and len(j) > 0 for j in joints)
    cj = frozen(joints, np.int64) if ok else None
    return frozen(heights, float), level_nodes, cj


def regular_frame(
    name: str,
    bays: Sequence[float],
    storey_heights: Sequence[float],
    n_v: int,
    n_h: int,
    columns: Section | Sequence[Section],
    beams: Section | Sequence[Section],
    floor_mass: float | Sequence[float] = 0.0,
    zeta: float | Sequence[float] = 0.05,
) -> Frame:
    """Regular moment frame: ``len(bays)`` bays by ``len(storey_heights)`` storeys.

    Each column segment is meshed into ``n_v`` elements, each beam into ``n_h``. There is
    a beam at every level above the base and none at the base, whose column feet are the
    base nodes. ``columns`` is one :class:`Section` or one per storey (bottom up);
    ``beams`` one or one per level above the base. ``floor_mass`` [kg] (one value or one
    per level above the base) is spread over that level's beam nodes by tributary length.

    Nodes are numbered level by level: the base nodes first (left to right), then for each
    storey the intermediate column nodes (column by column, bottom up) followed by that
    level's beam-line nodes left to right.
    """
    if not (isinstance(name, str) and name.strip()):
        raise ValueError(f"name: expected a frame's name (text), got {name!r}")
    for what, v in (
        ("bays", bays),
        ("storey_heights", storey_heights),
        ("zeta", zeta),
        ("floor_mass", floor_mass),
    ):  # fmt: skip  (True a 1 m bay, "1e4" a mass)
        flat = [v] if isinstance(v, str) else np.ravel(np.asarray(v, dtype=object)).tolist()
        if any(isinstance(x, str | bool | np.bool_) for x in flat):
            raise ValueError(f"{what}: expected numbers, got {v!r}")
    bays = finite_numbers("bays", bays, "a list of finite bay widths [m]")
    hs = finite_numbers("storey_heights", storey_heights, "a list of finite storey heights [m]")
    for what, v in (("bays", bays), ("storey_heights", hs)):
        if np.any(v <= 0):
            raise ValueError(f"{what}: expected positive sizes [m], got {v.tolist()}")
    whole("n_v", n_v, 1, "a whole number of elements per column >= 1")
    whole("n_h", n_h, 1, "a whole number of elements per beam >= 1")
    ns, nc = len(hs), len(bays) + 1
    n_dof = 3 * (nc + ns * (nc * (n_v - 1) + len(bays) * n_h + 1))  # (before a list is built)
    if n_dof > MAX_DOF:
        raise ValueError(f"bays, storey_heights, n_v, n_h: {n_dof:.3g} dofs; expected a model "
                         f"of at most {MAX_DOF:.0e} dofs (fewer bays, storeys or elements per "
                         "member)")  # fmt: skip
    if isinstance(zeta, str) or np.ndim(zeta) == 0:
        zeta = [zeta]
    zeta = finite_numbers("zeta", zeta, "damping ratios in [0, 1)")
    col_secs = _per(columns, ns, "columns")
    beam_secs = _per(beams, ns, "beams")
    fm = np.asarray(floor_mass, float)
    if fm.ndim > 1 or fm.size not in (1, ns) or not np.all(np.isfinite(fm)) or np.any(fm < 0):
        raise ValueError(f"floor_mass: expected one finite value >= 0 or one per level above "
                         f"the base ({ns}), got {np.asarray(floor_mass).tolist()}")  # fmt: skip
    fm = np.broadcast_to(fm, (ns,))
    xcol = np.concatenate([[0.0], np.cumsum(bays)])
    ylev = np.concatenate([[0.0], np.cumsum(hs)])

    nodes: list[tuple[float, float]] = [(x, 0.0) for x in xcol]
    node_mass: list[float] = [0.0] * nc
    elems: list[tuple[int, int]] = []
    secs: list[Section] = []
    joints = [list(range(nc))]
    level_nodes = [list(range(nc))]
    for s in range(ns):
        y0, y1 = ylev[s], ylev[s + 1]
        # intermediate column nodes
        inner = []
        for c in range(nc):
            ids = []
            for k in range(1, n_v):
                ids.append(len(nodes))
                nodes.append((xcol[c], y0 + (y1 - y0) * k / n_v))
                node_mass.append(0.0)
            inner.append(ids)
        # beam line at level s + 1, left to right
        xs = [xcol[b] + bays[b] * k / n_h for b in range(len(bays)) for k in range(n_h)]
        xs = np.array([*xs, xcol[-1]])
        line = list(range(len(nodes), len(nodes) + len(xs)))
        nodes.extend((x, y1) for x in xs)
        node_mass.extend([0.0] * len(xs))
        mid = (xs[1:] + xs[:-1]) / 2
        trib = np.diff(np.concatenate([[xs[0]], mid, [xs[-1]]]))  # tributary lengths
        for n, t in zip(line, trib, strict=True):
            node_mass[n] += fm[s] * t / xcol[-1]
        colj = line[::n_h]
        joints.append(colj)
        level_nodes.append(line)
        for c in range(nc):
            chain = [joints[s][c], *inner[c], colj[c]]
            for a, b in zip(chain[:-1], chain[1:], strict=True):
                elems.append((a, b))
                secs.append(col_secs[s])
        for a, b in zip(line[:-1], line[1:], strict=True):
            elems.append((a, b))
            secs.append(beam_secs[s])
    return Frame(
        name=name,
        nodes=np.array(nodes),
        elements=np.array(elems),
        E=[q.E for q in secs],
        A=[q.A for q in secs],
        I=[q.I for q in secs],
        rho_A=[q.rho_A for q in secs],
        node_mass=np.array(node_mass),
        base_nodes=np.arange(nc),
        zeta=zeta,
        level_nodes=tuple(np.array(n) for n in level_nodes),
        level_heights=ylev,
        column_joints=np.array(joints),
    )


def _per(secs, n, what, kind=Section) -> list:
    """``n`` sections (one per storey) from one section of type ``kind`` or a list of 1 or n."""
    if isinstance(secs, kind):
        return [secs] * n
    try:  # a list, tuple, generator or array of sections; one section otherwise
        secs = [secs] if isinstance(secs, str | dict) else list(secs)  # (a dict: its keys)
    except TypeError:
        secs = [secs]
    if not all(isinstance(s, kind) for s in secs):  # (a number: "'int' object is not iterable")
        bad = next(s for s in secs if not isinstance(s, kind))
        raise TypeError(f"{what}: expected a {kind.__name__} or a list of them, got "
                        f"{type(bad).__name__}")  # fmt: skip
    if len(secs) == 1:
        return secs * n
    if len(secs) != n:
        raise ValueError(f"{what}: expected {'1' if n == 1 else f'1 or {n}'} section(s) (one "
                         f"per storey), got {len(secs)}")  # fmt: skip
    return secs
