"""Regular buildings in three dimensions: a grid of column lines, beams both ways, floors.

``regular_building_3d`` builds the space frame of ``len(bays_x)`` × ``len(bays_y)`` bays and
``len(storey_heights)`` storeys: a column at every grid point (x_i, y_j), at every level
above the base a beam along x on each grid line y_j and one along y on each grid line x_i,
each column segment meshed into ``n_v`` elements and each beam into ``n_h``. The floor of
level s (mass m_s) is, with ``diaphragms=True``, a rigid diaphragm of all that level's
nodes whose master sits at the plan centre (plus an optional mass offset) and carries m_s
in x and y with the polar moment of a uniform rectangular slab over the plan,

    J_s = m_s (L_x² + L_y²) / 12,

while m_s acts vertically on the level's beam nodes by tributary beam length (the slab is
rigid in its plane only). Without diaphragms m_s is spread that way in x, y and z.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from nsdyn._checks import finite_numbers, flag, whole
from nsdyn.structure.frame import MAX_DOF, _per
from nsdyn.structure.frame3d import Diaphragm, Frame3D, Section3D

COLUMN_VECXZ = (1.0, 0.0, 0.0)  # columns: local z = global X, so I_y resists x-sway
BEAM_VECXZ = (0.0, 0.0, 1.0)  # beams: local z = global Z, so I_y is vertical bending


def _numbers(v, what: str, size: int | None = None) -> np.ndarray:
    """``v`` as a 1-D array of finite floats (``size`` of them when given), or ValueError
    naming ``what`` (text, nested lists and NaN failed deep inside numpy before)."""
    form = f"{size} finite numbers" if size else "a non-empty list of finite numbers"
    return finite_numbers(what, v, form, size)


def _values(v, n, what) -> np.ndarray:
    """One value >= 0 or ``n`` of them (a floor's mass or inertia), or ValueError naming
    ``what`` (a negative mass was "diaphragm mass must be >= 0", naming no argument)."""
    a = _numbers([v] if np.ndim(v) == 0 else v, what)
    if a.size not in (1, n) or np.any(a < 0):
        raise ValueError(
            f"{what}: expected one value >= 0 or {n} of them, got {np.ravel(v).tolist()}"
        )
    return np.broadcast_to(a, (n,)).copy()


def regular_building_3d(
    name: str,
    bays_x: Sequence[float],
    bays_y: Sequence[float],
    storey_heights: Sequence[float],
    columns: Section3D | Sequence[Section3D],
    beams_x: Section3D | Sequence[Section3D],
    beams_y: Section3D | Sequence[Section3D],
    n_v: int = 1,
    n_h: int = 1,
    floor_mass: float | Sequence[float] = 0.0,
    floor_inertia: float | Sequence[float] | None = None,
    zeta: float | Sequence[float] = 0.05,
    diaphragms: bool = True,
    mass_offset: Sequence[float] = (0.0, 0.0),
    column_vecxz: Sequence[float] = COLUMN_VECXZ,
    beam_x_vecxz: Sequence[float] = BEAM_VECXZ,
    beam_y_vecxz: Sequence[float] = BEAM_VECXZ,
) -> Frame3D:
    """A regular space moment frame (see the module docstring).

    ``columns`` is one :class:`Section3D` or one per storey (bottom up); ``beams_x`` and
    ``beams_y`` one or one per level above the base. ``floor_mass`` [kg] and
    ``floor_inertia`` [kg m²] (default: uniform slab) one value or one per level above the
    base. ``mass_offset`` (e_x, e_y) [m] moves every floor's centre of mass from the plan
    centre (accidental eccentricity).

    Numbering: the base grid first, column line ``j (n_x + 1) + i`` at (x_i, y_j); then per
    storey the intermediate column nodes (line by line, bottom up), the level's joints (grid
    order) and its beam nodes (x beams line by line, then y beams). ``column_joints`` holds
    the joints of every column line at every level.
    """
    bx, by, hs = (_numbers(v, w) for v, w in ((bays_x, "bays_x"), (bays_y, "bays_y"),
                                             (storey_heights, "storey_heights")))  # fmt: skip
    for what, v in (("bays_x", bx), ("bays_y", by), ("storey_heights", hs)):
        if np.any(v <= 0):  # (the message named none of them)
            raise ValueError(f"{what}: expected positive sizes [m], got {v.tolist()}")
    whole("n_v", n_v, 1, "a whole number of elements per column >= 1")
    whole("n_h", n_h, 1, "a whole number of elements per beam >= 1")
    diaphragms = flag("diaphragms", diaphragms)
    nx, ny, ns = len(bx) + 1, len(by) + 1, len(hs)  # (before a list of that size is built)
    n_dof = 6 * (nx * ny * (1 + ns * n_v) + ns * (n_h - 1) * (ny * (nx - 1) + nx * (ny - 1)))
    if n_dof > MAX_DOF:
        raise ValueError(f"bays_x, bays_y, storey_heights, n_v, n_h: {n_dof:.3g} dofs; expected "
                         f"a model of at most {MAX_DOF:.0e} dofs (fewer bays, storeys or "
                         "elements per member)")  # fmt: skip
    mass_offset = tuple(_numbers(mass_offset, "mass_offset", 2))
    column_vecxz, beam_x_vecxz, beam_y_vecxz = (
        tuple(_numbers(v, w, 3)) for v, w in ((column_vecxz, "column_vecxz"),
                                               (beam_x_vecxz, "beam_x_vecxz"),
                                               (beam_y_vecxz, "beam_y_vecxz")))  # fmt: skip
    if not diaphragms and np.any(np.asarray(mass_offset, float) != 0.0):
        raise ValueError(
            f"mass_offset {list(mass_offset)}: expected (0, 0) without diaphragms (the offset "
            "moves the diaphragms' mass; without them the floor mass sits on the beam nodes)"
        )
    ns = len(hs)
    cols, bxs, bys = (
        _per(s, ns, w, Section3D)
        for s, w in ((columns, "columns"), (beams_x, "beams_x"), (beams_y, "beams_y"))
    )
    fm = _values(floor_mass, ns, "floor_mass")
    xs, ys = np.r_[0.0, np.cumsum(bx)], np.r_[0.0, np.cumsum(by)]
    zs = np.r_[0.0, np.cumsum(hs)]
    Lx, Ly = xs[-1], ys[-1]
    ex, ey = (float(v) for v in mass_offset)
    if abs(ex) > Lx / 2 or abs(ey) > Ly / 2:
        raise ValueError(f"mass_offset {[ex, ey]}: expected the floors' centre of mass within "
                         f"the plan, |e_x| <= {Lx / 2:g} and |e_y| <= {Ly / 2:g}")  # fmt: skip
    fi = _values(
        fm * (Lx**2 + Ly**2) / 12 if floor_inertia is None else floor_inertia, ns, "floor_inertia"
    )
    nx, ny = len(xs), len(ys)
    grid = [(x, y) for y in ys for x in xs]
    nodes: list[tuple] = [(x, y, 0.0) for x, y in grid]
    el: list[tuple] = []
    sec: list[Section3D] = []
    vec: list[Sequence[float]] = []
    joints = [list(range(len(grid)))]
    levels: list[list[int]] = []
    beam_len: list[tuple] = []  # (node a, node b, length, storey) of every beam element

    def add(p) -> int:
        nodes.append(p)
        return len(nodes) - 1

    def chain(ids, s, v, storey=None):
        for a, b in zip(ids[:-1], ids[1:], strict=True):
            el.append((a, b))
            sec.append(s)
            vec.append(v)
            if storey is not None:
                beam_len.append(
                    (a, b, float(np.linalg.norm(np.subtract(nodes[b], nodes[a]))), storey)
                )

    for s in range(ns):
        z0, z1 = zs[s], zs[s + 1]
        inner = [[add((x, y, z0 + (z1 - z0) * k / n_v)) for k in range(1, n_v)] for x, y in grid]
        top = [add((x, y, z1)) for x, y in grid]
        level = list(top)
        for c in range(len(grid)):
            chain([joints[s][c], *inner[c], top[c]], cols[s], column_vecxz)
        for j in range(ny):  # beams along x on grid line y_j
            for i in range(nx - 1):
                a, b = top[j * nx + i], top[j * nx + i + 1]
                mid = [add((xs[i] + bx[i] * k / n_h, ys[j], z1)) for k in range(1, n_h)]
                level += mid
                chain([a, *mid, b], bxs[s], beam_x_vecxz, s)
        for i in range(nx):  # beams along y on grid line x_i
            for j in range(ny - 1):
                a, b = top[j * nx + i], top[(j + 1) * nx + i]
                mid = [add((xs[i], ys[j] + by[j] * k / n_h, z1)) for k in range(1, n_h)]
                level += mid
                chain([a, *mid, b], bys[s], beam_y_vecxz, s)
        joints.append(top)
        levels.append(level)

    nn = len(nodes)
    node_mass = np.zeros((nn, 3))
    for s in range(ns):
        bl = [(a, b, L) for a, b, L, st in beam_len if st == s]
        total = sum(L for _, _, L in bl)
        for a, b, L in bl:  # tributary beam length: half of each element to each end
            share = fm[s] * L / (2 * total) if total > 0 else 0.0
            for n in (a, b):
                node_mass[n, 2] += share
                if not diaphragms:
                    node_mass[n, :2] += share
    centre = np.array([Lx / 2, Ly / 2]) + np.asarray(mass_offset, float)
    dias = (
        tuple(Diaphragm(levels[s], centre, fm[s], fi[s]) for s in range(ns)) if diaphragms else ()
    )
    return Frame3D(
        name=name,
        nodes=np.array(nodes),
        elements=np.array(el),
        vecxz=np.array(vec, float),
        **{k: [getattr(q, k) for q in sec] for k in ("E", "G", "A", "I_y", "I_z", "J")},
        rho_A=[q.rho_A for q in sec],
        rho_Ip=[q.rho_Ip for q in sec],
        node_mass=node_mass,
        base_nodes=np.arange(len(grid)),
        zeta=np.atleast_1d(np.asarray(zeta, float)),
        diaphragms=dias,
        column_joints=np.array(joints),
    )
