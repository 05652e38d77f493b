"""The checks a frame's geometry must pass, plane or space: finite coordinates, every node on an
element (in 3D one on a diaphragm too: a diaphragm holds no vertical motion), no element of
zero length, no pair of nodes joined twice nor an element along another, no two nodes at one
place, every node joined to a base node (by elements and diaphragms; a part that floats free
is a mechanism), and no column foot at the base level standing on nothing. An element longer than
:data:`LENGTH_PLAUSIBLE` is noted (a ``NotedWarning``: coordinates in mm?).

Each is a model that runs silently wrong otherwise (a beam cut in two at a repeated node, a
member's stiffness counted twice) or one whose matrices are singular. Positions equal to
:data:`SAME_PLACE` of the frame's extent are one place. The messages name the entry
(``nodes[7]``, ``elements[5]``, or the names a file reader gives its elements).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Iterable

import numpy as np

from nsdyn._checks import NotedWarning

SAME_PLACE = 1e-9  # relative to the frame's extent: two positions closer are one place
LENGTH_PLAUSIBLE = 200.0  # [m] an element longer than this: a frame in mm? (warned)


def check_geometry(
    nodes: np.ndarray,
    elements: np.ndarray,
    *,
    tied: Iterable[int] = (),
    base: Iterable[int] | None = None,
    groups: Iterable[Iterable[int]] = (),
    element_name: Callable[[int], str] = lambda k: f"elements[{k}]",
) -> None:
    """ValueError naming the first entry that fails a check of the module text. ``tied``: nodes
    on a diaphragm (named so when on no element); ``base``: the base nodes (None: no check of
    the joins); ``groups``: sets of nodes joined otherwise (diaphragms)."""
    nodes = np.asarray(nodes, float)
    elements = np.asarray(elements, np.int64)
    axes = "[x, y]" if nodes.shape[1] == 2 else "[x, y, z]"
    bad = np.flatnonzero(~np.all(np.isfinite(nodes), axis=1))
    if bad.size:
        raise ValueError(f"nodes[{bad[0]}]: expected finite coordinates {axes} [m], got "
                         f"{nodes[bad[0]].tolist()}")  # fmt: skip
    loose = sorted(set(range(len(nodes))) - set(elements.ravel().tolist()))
    if loose and loose[0] in set(tied):
        raise ValueError(f"nodes[{loose[0]}]: on a diaphragm and no element (a diaphragm holds "
                         "its x, y and rz; its uz, rx and ry have no stiffness: a mechanism); "
                         "expected a node on a member")  # fmt: skip
    if loose:
        raise ValueError(f"nodes[{loose[0]}]: on no element (a node must belong to a member)")
    tol = SAME_PLACE * float(np.ptp(nodes, axis=0).max())
    length = np.linalg.norm(nodes[elements[:, 1]] - nodes[elements[:, 0]], axis=1)
    short = np.flatnonzero(~(length > tol))
    if short.size:
        k = int(short[0])
        extent = float(np.ptp(nodes, axis=0).max())
        raise ValueError(f"{element_name(k)}: nodes {elements[k, 0]} and {elements[k, 1]} are at "
                         f"the same place (within {SAME_PLACE:g} of the frame's {extent:.3g} m "
                         "extent); expected an element of positive length")  # fmt: skip
    seen: dict = {}
    for k, (i, j) in enumerate(elements.tolist()):
        pair = (min(i, j), max(i, j))
        if pair in seen:
            raise ValueError(f"{element_name(k)}: joins nodes {i} and {j}, as "
                             f"{element_name(seen[pair])} does; expected one element per pair "
                             "of nodes")  # fmt: skip
        seen[pair] = k
    at: dict = {}
    for n, key in enumerate(map(tuple, np.round(nodes / max(tol, 1e-300)).tolist())):
        if key in at:
            raise ValueError(f"nodes[{n}]: at the same place as nodes[{at[key]}] "
                             f"({nodes[n].tolist()}); expected one node per place (the members "
                             "meeting there share it)")  # fmt: skip
        at[key] = n
    _check_on_element(nodes, elements, tol, element_name)
    if base is not None:
        _check_base_level(nodes, elements, list(base), tol)
        _check_joined(len(nodes), elements, list(base), groups)
    k = int(np.argmax(length))
    if length[k] > LENGTH_PLAUSIBLE:  # (a portal in mm ran, 0.83 m of roof drift, unsaid)
        warnings.warn(f"{element_name(k)}: {length[k]:.4g} m long, past the "
                      f"{LENGTH_PLAUSIBLE:g} m of any building member: a frame's coordinates "
                      "are in m (storeys of 2.5-6 m); are they in mm?", NotedWarning,
                      stacklevel=3)  # fmt: skip


def _check_on_element(nodes: np.ndarray, elements: np.ndarray, tol: float, element_name) -> None:
    """No two elements overlap along their line (an element laid over others, [3, 5] over the
    chain 3-4-5: its stiffness and mass counted twice, f1 4.90 -> 5.30 Hz, without a word).
    Elements are grouped by their line (direction and the line's point nearest the origin,
    rounded to ``tol``) and sorted along it: two overlap when one starts before the one
    before it ends; a sort, so the check costs about the elements' count."""
    a, b = nodes[elements[:, 0]], nodes[elements[:, 1]]
    u = (b - a) / np.linalg.norm(b - a, axis=1)[:, None]
    first = np.argmax(np.abs(u) > 1e-6, axis=1)  # (a line's direction, one sign of it)
    u *= np.sign(u[np.arange(len(u)), first])[:, None]
    ta, tb = np.einsum("ij,ij->i", a, u), np.einsum("ij,ij->i", b, u)
    p0 = a - ta[:, None] * u  # the line's point nearest the origin
    step = max(tol, 1e-300)
    key = np.concatenate([np.round(u / 1e-9), np.round(p0 / step)], axis=1)
    start, end = np.minimum(ta, tb), np.maximum(ta, tb)
    order = np.lexsort((start, *key.T[::-1]))
    same = np.all(key[order[1:]] == key[order[:-1]], axis=1)
    over = np.flatnonzero(same & (start[order[1:]] < end[order[:-1]] - tol))
    if over.size:
        j, k = int(order[over[0]]), int(order[over[0] + 1])
        raise ValueError(f"{element_name(k)}: nodes {elements[k, 0]} to {elements[k, 1]} lie "
                         f"along {element_name(j)} (nodes {elements[j, 0]} to {elements[j, 1]}), "
                         "overlapping it; expected each stretch of a member once (an element "
                         "over others counts their stiffness and mass twice)")  # fmt: skip


def _check_base_level(nodes: np.ndarray, elements: np.ndarray, base: list, tol: float) -> None:
    """No column stands on nothing: a node at the level of the lowest base node whose every
    element is vertical (a column's foot, no beam or girder there) is a base node. A portal
    standing on one of its two feet ran to drift ratios of 1e10 without a word; a column on
    a base girder, a stepped base and a pit below the base are frames of their own."""
    base = [int(b) for b in base if float(b).is_integer() and 0 <= b < len(nodes)]
    if not base:
        return  # (the frame's own check names it)
    up = nodes.shape[1] - 1  # y of a plane frame, z of a space frame
    low = float(nodes[base, up].min())
    top = float(nodes[base, up].max())
    if not np.any(nodes[:, up] > top + tol) and np.any(nodes[:, up] < low - tol):
        axis = "yz"[up - 1]  # (a frame upside down ran as any other, its gravity pulling up)
        raise ValueError(f"base_nodes: every node lies at or below the base nodes ({axis} <= "
                         f"{top:g} m): a frame hung from its supports; expected the base nodes "
                         f"at the frame's foot, the frame above them ({axis} up)")  # fmt: skip
    d = np.abs(nodes[elements[:, 1]] - nodes[elements[:, 0]])
    vertical = np.all(d[:, :up] <= tol, axis=1)
    ends = elements.ravel()
    on_other = set(ends[np.repeat(~vertical, 2)].tolist())  # nodes with a non-vertical element
    feet = {int(n) for n in elements[vertical].ravel() if abs(nodes[n, up] - low) <= tol}
    free = sorted(feet - set(base) - on_other)
    if free:
        raise ValueError(f"base_nodes: node {free[0]} is a column foot at the base level "
                         f"({low:g} m) but not a base node, and nothing else holds it; "
                         "expected every column to stand on a base node (list it in "
                         "base_nodes)")  # fmt: skip


def _check_joined(nn: int, elements: np.ndarray, base: list, groups) -> None:
    """Every node reaches a base node through elements and groups (union-find). Base nodes
    out of range are the frame's own check (it names them), as is an empty list."""
    base = [int(b) for b in base if float(b).is_integer() and 0 <= b < nn]
    if not base:
        return
    root = list(range(nn))

    def find(a: int) -> int:
        while root[a] != a:
            root[a] = root[root[a]]
            a = root[a]
        return a

    links = [tuple(e) for e in elements.tolist()]
    for g in groups:
        g = list(g)
        links += [(g[0], n) for n in g[1:]]
    for i, j in links:
        root[find(i)] = find(j)
    grounded = {find(b) for b in base}
    loose = [n for n in range(nn) if find(n) not in grounded]
    if loose:
        raise ValueError(f"nodes[{loose[0]}]: joined to no base node (with {len(loose) - 1} "
                         "other node(s) it is a part that floats free: a mechanism); expected "
                         "every node joined to a base node by elements")  # fmt: skip


def frozen(a, dtype) -> np.ndarray:
    """``a`` as a read-only array of ``dtype`` (a frame's fields cannot change under it)."""
    a = np.array(a, dtype=dtype)
    a.setflags(write=False)
    return a


def checked_base(base_nodes, nn: int) -> np.ndarray:
    """A frame's base nodes: a non-empty list of distinct node indices in ``0..nn-1`` (text,
    bools and fractions refused: "0" was read as node 0, 0.5 as node 0)."""
    raw = np.atleast_1d(np.asarray(base_nodes, dtype=object))
    if not all(isinstance(b, int | np.integer) and not isinstance(b, bool | np.bool_)
               or isinstance(b, float | np.floating) and float(b).is_integer()
               for b in raw.ravel()):  # fmt: skip
        raise ValueError(f"base_nodes must be a list of node indices (whole numbers), got "
                         f"{np.asarray(base_nodes, dtype=object).tolist()}")  # fmt: skip
    base = frozen(np.atleast_1d(base_nodes), np.int64)
    # distinct by a set: numpy 2's np.unique imports numpy.ma (~40 ms of a cached start)
    if base.ndim != 1 or len(base) == 0 or len(set(base.tolist())) != len(base):
        raise ValueError("base_nodes must be a non-empty list of distinct nodes")
    if base.min() < 0 or base.max() >= nn:
        raise ValueError(f"base node index out of range 0..{nn - 1}")
    if len(base) == nn:  # (nothing above the isolators: a run of no dofs "succeeded")
        raise ValueError(ALL_BASE.format(nn=nn))
    return base


# a frame whose every node is a base node has nothing above its isolators to move
ALL_BASE = ("base_nodes: every one of the {nn} nodes is a base node, leaving none above the "
            "isolators to move; expected the nodes on the isolators only")  # fmt: skip
ALL_BASE_FILE = "the nodes on the isolators only, not all {nn} nodes (none would be left to move)"


def checked_zeta(zeta) -> np.ndarray:
    """A frame's modal damping ratios: a non-empty list in [0, 1) (NaN refused)."""
    z = frozen(np.atleast_1d(zeta), float)
    if z.ndim != 1 or len(z) == 0 or not np.all((z >= 0) & (z < 1)):
        raise ValueError("zeta must be a non-empty list of damping ratios in [0, 1) "
                         f"(fractions: 0.05 for 5 %), got {z.tolist()}")  # fmt: skip
    return z


# the widest span of member stiffnesses a frame may have: double precision resolves 1 part in
# 2**52 = 4.5e15 of a sum, so a member stiffness below 1e-14 of another meeting it at a joint
# keeps at most a digit or two (E = 1e300 beside I = 1e-30 was a singular K or a 0.0 Hz mode)
SPAN_MAX = 1e14


def check_stiffness_span(terms: dict, element_name=lambda k: f"elements[{k}]") -> None:
    """ValueError naming the stiffest and the softest member stiffness when they span more than
    :data:`SPAN_MAX`. ``terms``: each member's stiffnesses in N/m by name (``"EA/L"``,
    ``"12EI/L³"``, ...), arrays over the elements; an overflow (inf) or an underflow (0) of
    one is refused the same way."""
    names = list(terms)
    T = np.array([np.broadcast_to(terms[k], np.shape(terms[names[0]])) for k in names], float)
    hi, lo = np.unravel_index(np.argmax(T), T.shape), np.unravel_index(np.argmin(T), T.shape)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        span = T[hi] / T[lo]
    if not span <= SPAN_MAX:
        of = (f"the {names[lo[0]]} of {element_name(int(lo[1]))}" if hi[1] != lo[1]
              else f"its {names[lo[0]]}")  # fmt: skip
        said = (f"= {T[hi]:.3g} N/m is {span:.2g} times" if np.isfinite(span) else
                f"= {T[hi]:.3g} N/m overflows or underflows double precision beside")  # fmt: skip
        raise ValueError(f"{element_name(int(hi[1]))}: its {names[hi[0]]} {said} {of} "
                         f"({T[lo]:.3g} N/m); expected member "
                         f"stiffnesses within a factor {SPAN_MAX:.0e} (double precision "
                         "resolves 1 part in 4.5e15: the softer is lost in round-off of the "
                         "stiffer, a singular K or modes of 0 Hz)")  # fmt: skip


# the softest Young's modulus of a structural material [Pa]: timber 1e10, concrete 3e10, steel
# 2.1e11 (a modulus in MPa, 2.1e5, ran a portal of a 305 s period without a word)
E_PLAUSIBLE = 1e8
# the lightest density of a structural member [kg/m³] (timber's is about 500): rho_A of 0.001
# kg/m on a 0.02 m² section (0.05 kg/m³), "massless columns", ran into a false uplift
DENSITY_PLAUSIBLE = 100.0


# the lightest added mass of a building frame as a share of its members' own: floors (slab,
# finishes, cladding) outweigh the members that carry them, the office's six to one; masses
# in tonnes read as kilograms are a thousandth of that (0.6 % on the office)
ADDED_MASS_PLAUSIBLE = 0.02


def added_mass_note(what: str, added: float, members: float) -> None:
    """A NotedWarning when a frame's ``what`` (its node or diaphragm masses, a regular frame's
    floor masses) sum to ``added`` [kg], less than :data:`ADDED_MASS_PLAUSIBLE` of its
    members' ``members`` [kg] (none: a bare frame)."""
    if 0 < added < ADDED_MASS_PLAUSIBLE * members:
        warnings.warn(f"node_mass: the frame's {what} (a regular frame's floor_mass) sum to "
                      f"{added:.4g} kg, {added / members:.2%} of its members' own "
                      f"{members:.4g} kg, where a building's floors outweigh the members that "
                      "carry them: given in tonnes? (masses are in kg)",
                      NotedWarning, stacklevel=4)  # fmt: skip


def section_notes(path: str, tbl, E, A, rho_A) -> None:
    """:func:`material_notes` of a frame file's section table ``tbl`` at ``path``: a value
    given as a list (one entry per storey) is named by its index, ``frame.columns.E[1]``."""

    def name(key):
        return lambda k: f"{path}.{key}[{k}]" if isinstance(tbl.get(key), list) else path

    material_notes(E, A, rho_A, name("E"), name("rho" if "rho" in tbl else "rho_A"))


def material_notes(E, A, rho_A, element_name=lambda k: f"elements[{k}]", mass_name=None):
    """A NotedWarning naming the softest element when its Young's modulus ``E`` (an array over
    the elements) is below :data:`E_PLAUSIBLE` (given in MPa or GPa, not Pa?), and one naming
    the lightest member with mass when its density ``rho_A / A`` is below
    :data:`DENSITY_PLAUSIBLE` (near-massless: rho_A = 0 is the massless member)."""
    E, A, rho_A = (np.asarray(v, dtype=float) for v in (E, A, rho_A))
    k = int(np.argmin(E)) if E.size else 0
    if E.size and E[k] < E_PLAUSIBLE:
        warnings.warn(f"{element_name(k)}: E = {E[k]:.4g} Pa, below any structural material's "
                      "(timber 1e10, concrete 3e10, steel 2.1e11 Pa): a frame's moduli are in "
                      "Pa; is it in MPa or GPa?", NotedWarning, stacklevel=3)  # fmt: skip
    rho = np.where(rho_A > 0, rho_A / A, np.inf)
    k = int(np.argmin(rho)) if rho.size else 0
    if rho.size and rho[k] < DENSITY_PLAUSIBLE:
        warnings.warn(f"{(mass_name or element_name)(k)}: rho_A = {rho_A[k]:.4g} kg/m over A = "
                      f"{A[k]:.4g} m² is a density of {rho[k]:.3g} kg/m³, far below any "
                      "structural material's (timber 500, concrete 2400, steel 7850): members "
                      "this light give modes of very high frequency that runs can fail on (a "
                      "step underflow, a false uplift); rho_A = 0 makes a member massless",
                      NotedWarning, stacklevel=3)  # fmt: skip
