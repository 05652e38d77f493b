"""3D frame files: strict reading of a space frame from TOML (one ``[frame3d]`` table).

``kind = "regular"`` gives the parameters of :func:`nsdyn.structure.building3d.regular_building_3d`
(bays in x and y, storey heights, mesh, sections of columns / beams along x / beams along y
per storey group, floor masses, diaphragms); ``kind = "explicit"`` lists nodes [x, y, z],
sections, member groups (elements, section, orientation vector) and diaphragms. A section
has E, A, I_y, I_z, J, one of G / nu (G = E / 2(1 + ν)), one of rho (ρA = ρ A,
ρI_p = ρ (I_y + I_z)) / rho_A (then ρI_p = ρA (I_y + I_z) / A unless rho_Ip is given).
Every error is one line naming the file, the dotted field and the expected form
(:class:`~nsdyn.structure.FrameFileError`).
"""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from nsdyn._checks import NotedWarning
from nsdyn.structure.building3d import regular_building_3d
from nsdyn.structure.elements3d import PARALLEL_SIN
from nsdyn.structure.frame3d import GEOM_RTOL, Diaphragm, Frame3D, Section3D
from nsdyn.structure.frame_toml import (
    FrameFileError,
    _is_number,
    _read_frame_file,
    _Reader,
    not_a_frame,
    with_file_warnings,
)
from nsdyn.structure.geometry import ALL_BASE_FILE, check_geometry, section_notes

TABLE = "frame3d"
_SECTION_KEYS = {"E", "G", "nu", "A", "I_y", "I_z", "J", "rho", "rho_A", "rho_Ip"}
_GROUP_KEYS = _SECTION_KEYS | {"vecxz"}
_COMMON = {"name", "kind", "description", "zeta"}
_REGULAR_KEYS = _COMMON | {
    "bays_x",
    "bays_y",
    "storey_heights",
    "n_v",
    "n_h",
    "floor_mass",
    "floor_inertia",
    "mass_offset",
    "diaphragms",
    "columns",
    "beams_x",
    "beams_y",
}
_EXPLICIT_KEYS = _COMMON | {"nodes", "base_nodes", "node_mass", "sections", "members", "diaphragms"}
_AXES = {"columns": (0.0, 0.0, 1.0), "beams_x": (1.0, 0.0, 0.0), "beams_y": (0.0, 1.0, 0.0)}


def _sections(rd: _Reader, tbl: Mapping, path: str, n: int) -> list[Section3D]:
    """n sections from a table whose properties are numbers or lists of n numbers."""
    col = {}
    for k in ("E", "A", "I_y", "I_z", "J"):
        col[k] = rd.number_or_list(tbl, k, f"{path}.{k}", n)
    for a, b, what in (
        ("G", "nu", "G [Pa] or nu (Poisson's ratio)"),
        ("rho", "rho_A", "rho [kg/m^3] or rho_A [kg/m]"),
    ):
        if (a in tbl) == (b in tbl):
            got = "both" if a in tbl else "nothing (missing)"
            rd.fail(f"{path}.{a}", f"exactly one of {what}", got, raw=True)
    if "G" in tbl:
        col["G"] = rd.number_or_list(tbl, "G", f"{path}.G", n)
    else:
        nu = rd.number_or_list(tbl, "nu", f"{path}.nu", n, positive=False)
        if any(not -1 < v < 0.5 for v in nu):
            rd.fail(f"{path}.nu", "Poisson's ratios in (-1, 0.5)", tbl["nu"])
        col["G"] = [e / (2 * (1 + v)) for e, v in zip(col["E"], nu, strict=True)]
    key = "rho" if "rho" in tbl else "rho_A"
    rho = rd.number_or_list(tbl, key, f"{path}.{key}", n, positive=False, nonneg=True)
    Ip = [y + z for y, z in zip(col["I_y"], col["I_z"], strict=True)]
    if key == "rho" and "rho_Ip" in tbl:  # (dropped without a word: rho gives it)
        rd.fail(
            f"{path}.rho_Ip",
            "no rho_Ip beside rho (the density gives rho (I_y + I_z)); give it with rho_A",
            tbl["rho_Ip"],
        )
    if key == "rho":
        col["rho_A"] = [r * a for r, a in zip(rho, col["A"], strict=True)]
        col["rho_Ip"] = [r * p for r, p in zip(rho, Ip, strict=True)]
    else:
        col["rho_A"] = rho
        col["rho_Ip"] = (
            rd.number_or_list(tbl, "rho_Ip", f"{path}.rho_Ip", n, positive=False, nonneg=True)
            if "rho_Ip" in tbl
            else [r * p / a for r, p, a in zip(rho, Ip, col["A"], strict=True)]
        )
    section_notes(path, tbl, col["E"], col["A"], col["rho_A"])  # (before the elements')
    keys = ("E", "G", "A", "I_y", "I_z", "J", "rho_A", "rho_Ip")
    return [Section3D(*(col[k][i] for k in keys)) for i in range(n)]


def _vector(rd: _Reader, tbl: Mapping, key: str, path: str, what: str) -> list[float]:
    v = tbl.get(key)
    if key not in tbl:
        rd.fail(path, what, "nothing (missing)", raw=True)
    if not (isinstance(v, list) and len(v) == 3 and all(_is_number(c) for c in v)):
        rd.fail(path, what, v)
    if not np.all(np.isfinite(v)) or not any(v):
        rd.fail(path, f"{what}, finite and not zero", v, raw=True)
    return [float(c) for c in v]


def _check_not_parallel(rd, v, axis, path, member):
    v, axis = np.asarray(v, float), np.asarray(axis, float) / np.linalg.norm(axis)
    if np.linalg.norm(np.cross(v, axis)) <= PARALLEL_SIN * np.linalg.norm(v):
        rd.fail(
            path,
            f"an orientation vector not parallel to the axis of {member}",
            f"{v.tolist()} (axis {axis.round(6).tolist()})",
            raw=True,
        )


def _zeta(rd, tbl):
    z = rd.number_list(tbl, "zeta", f"{TABLE}.zeta", positive=False, nonneg=True)
    if any(x >= 1 for x in z):
        rd.fail(f"{TABLE}.zeta", "damping ratios in [0, 1)", z)
    return z


def _regular(rd: _Reader, f: Mapping, name: str) -> Frame3D:
    rd.known(f, _REGULAR_KEYS, TABLE)
    P = TABLE
    bx = rd.number_list(f, "bays_x", f"{P}.bays_x")
    by = rd.number_list(f, "bays_y", f"{P}.bays_y")
    hs = rd.number_list(f, "storey_heights", f"{P}.storey_heights")
    n = len(hs)
    n_v = rd.integer(f, "n_v", f"{P}.n_v", minimum=1)
    n_h = rd.integer(f, "n_h", f"{P}.n_h", minimum=1)
    groups, vecs = {}, {}
    for g, axis in _AXES.items():
        tbl = rd.table(f, g, f"{P}.{g}")
        rd.known(tbl, _GROUP_KEYS, f"{P}.{g}")
        what = "an orientation vector [x, y, z] (local x-z plane, OpenSees vecxz)"
        vecs[g] = _vector(rd, tbl, "vecxz", f"{P}.{g}.vecxz", what)
        _check_not_parallel(rd, vecs[g], axis, f"{P}.{g}.vecxz", f"the {g}")
        groups[g] = _sections(rd, tbl, f"{P}.{g}", n)
    fm = rd.number_or_list(f, "floor_mass", f"{P}.floor_mass", n, False, True)
    fi = (
        rd.number_or_list(f, "floor_inertia", f"{P}.floor_inertia", n, False, True)
        if "floor_inertia" in f
        else None
    )
    off = [0.0, 0.0]
    if "mass_offset" in f:
        off = rd.number_list(f, "mass_offset", f"{P}.mass_offset", n=2, positive=False)
    dia = f.get("diaphragms", True)
    if not isinstance(dia, bool):
        rd.fail(f"{P}.diaphragms", "true or false", dia)
    if not dia and any(off):
        rd.fail(f"{P}.mass_offset", "[0, 0] with diaphragms = false (it moves their mass)", off)
    hx, hy = sum(bx) / 2, sum(by) / 2
    if abs(off[0]) > hx or abs(off[1]) > hy:  # (an accidental eccentricity is ~5 % of L)
        rd.fail(f"{P}.mass_offset", f"an offset [e_x, e_y] [m] that keeps the floors' centre of "
                f"mass within the plan, |e_x| <= {hx:g} and |e_y| <= {hy:g}", off)  # fmt: skip
    zeta = _zeta(rd, f)  # its own error, outside the model's checks below
    try:  # (the model's own: nodes at one place from a storey of 1e-9 m, a model too large)
        return regular_building_3d(name, bx, by, hs, groups["columns"], groups["beams_x"],
                                   groups["beams_y"], n_v, n_h, fm, fi, zeta, dia, off,
                                   vecs["columns"], vecs["beams_x"], vecs["beams_y"])  # fmt: skip
    except ValueError as exc:
        why = " ".join(str(exc).split())
        raise FrameFileError(f"{rd.file}: {P}: {why} (the regular frame of bays_x, bays_y, "
                             "storey_heights, n_v and n_h)", P) from None  # fmt: skip


def _index_list(rd, v, path, nn, min_len=1, what="node indices"):
    ok = (
        isinstance(v, list)
        and len(v) >= min_len
        and all(isinstance(b, int) and not isinstance(b, bool) and 0 <= b < nn for b in v)
        and len(set(v)) == len(v)
    )
    if not ok:
        rd.fail(path, f"a list of >= {min_len} distinct {what} in 0..{nn - 1}", v)
    return v


def _explicit(rd: _Reader, f: Mapping, name: str) -> Frame3D:
    rd.known(f, _EXPLICIT_KEYS, TABLE)
    P = TABLE
    raw = f.get("nodes")
    if not (isinstance(raw, list) and len(raw) >= 2):
        rd.fail(f"{P}.nodes", "a list of >= 2 [x, y, z] triples", raw)
    for k, p in enumerate(raw):  # (the node named: "got a list of 8" said which not)
        if not (isinstance(p, list) and len(p) == 3 and all(_is_number(c) for c in p)):
            rd.fail(f"{P}.nodes[{k}]", "a triple [x, y, z] of numbers [m]", p, raw=True)
    nodes = np.array(raw, float)
    if not np.all(np.isfinite(nodes)):
        k = int(np.flatnonzero(~np.all(np.isfinite(nodes), axis=1))[0])
        rd.fail(f"{P}.nodes[{k}]", "finite coordinates [x, y, z] [m]", raw[k], raw=True)
    nn = len(nodes)
    secs_raw = f.get("sections")
    if not isinstance(secs_raw, list) or not secs_raw:
        rd.fail(f"{P}.sections", "a non-empty array of tables [[frame3d.sections]]", secs_raw)
    secs = []
    for i, s in enumerate(secs_raw):
        p = f"{P}.sections[{i}]"
        if not isinstance(s, Mapping):
            rd.fail(p, "a table of section properties", s)
        rd.known(s, _SECTION_KEYS, p)
        secs.append(_sections(rd, s, p, 1)[0])
    mem_raw = f.get("members")
    if not isinstance(mem_raw, list) or not mem_raw:
        rd.fail(f"{P}.members", "a non-empty array of tables [[frame3d.members]]", mem_raw)
    el, sid, vec, names = [], [], [], []
    for g, m in enumerate(mem_raw):
        p = f"{P}.members[{g}]"
        if not isinstance(m, Mapping):
            rd.fail(p, "a table with elements, section, vecxz", m)
        rd.known(m, {"elements", "section", "vecxz"}, p)
        s = rd.integer(m, "section", f"{p}.section", minimum=0)
        if s >= len(secs):
            rd.fail(f"{p}.section", f"a section index in 0..{len(secs) - 1}", s)
        els = m.get("elements")
        if not (
            isinstance(els, list)
            and els
            and all(
                isinstance(e, list)
                and len(e) == 2
                and e[0] != e[1]
                and all(isinstance(c, int) and not isinstance(c, bool) and 0 <= c < nn for c in e)
                for e in els
            )
        ):
            rd.fail(f"{p}.elements", f"a list of [node_i, node_j] pairs in 0..{nn - 1}", els)
        what = "an orientation vector [x, y, z] or one per element (OpenSees vecxz)"
        v = m.get("vecxz")
        if isinstance(v, list) and v and all(isinstance(x, list) for x in v):
            if len(v) != len(els):
                rd.fail(f"{p}.vecxz", f"one vector per element ({len(els)})", v)
            vs = [_vector(rd, {"v": x}, "v", f"{p}.vecxz[{k}]", what) for k, x in enumerate(v)]
        else:
            vs = [_vector(rd, m, "vecxz", f"{p}.vecxz", what)] * len(els)
        for k, (e, vv) in enumerate(zip(els, vs, strict=True)):
            axis = nodes[e[1]] - nodes[e[0]]
            if not np.linalg.norm(axis) > 0:
                rd.fail(f"{p}.elements[{k}]", "two nodes at different places", e)
            _check_not_parallel(rd, vv, axis, f"{p}.vecxz", f"element {e}")
        el += els
        names += [f"{p}.elements[{k}]" for k in range(len(els))]
        sid += [s] * len(els)
        vec += vs
    base = _index_list(rd, f.get("base_nodes"), f"{P}.base_nodes", nn)
    if len(base) == nn:
        rd.fail(f"{P}.base_nodes", ALL_BASE_FILE.format(nn=nn), base)
    node_mass = np.zeros((nn, 3))
    if "node_mass" in f:
        v = f["node_mass"]
        if isinstance(v, list) and v and all(isinstance(x, list) for x in v):
            bad = [
                k
                for k, x in enumerate(v)
                if not (len(x) == 3 and all(_is_number(c) and 0 <= c < math.inf for c in x))
            ]
            if len(v) != nn or bad:  # (the entry named: a list of 8 said nothing of which)
                if len(v) == nn:
                    rd.fail(f"{P}.node_mass[{bad[0]}]", "a finite [m_x, m_y, m_z] triple >= 0",
                            v[bad[0]])  # fmt: skip
                rd.fail(f"{P}.node_mass", f"a list of {nn} [m_x, m_y, m_z] triples", v)
            node_mass = np.array(v, float)
        else:
            node_mass[:] = np.array(
                rd.number_or_list(f, "node_mass", f"{P}.node_mass", nn, False, True)
            )[:, None]
    dias = []
    raw_d = f.get("diaphragms", [])
    if not isinstance(raw_d, list):
        rd.fail(f"{P}.diaphragms", "an array of tables [[frame3d.diaphragms]]", raw_d)
    for k, d in enumerate(raw_d):
        p = f"{P}.diaphragms[{k}]"
        if not isinstance(d, Mapping):
            rd.fail(p, "a table with nodes, mass, inertia, centre", d)
        rd.known(d, {"nodes", "mass", "inertia", "centre"}, p)
        dn = _index_list(rd, d.get("nodes"), f"{p}.nodes", nn, 2, "node indices at one level")
        xy = nodes[dn, :2]
        c = (
            rd.number_list(d, "centre", f"{p}.centre", 2, positive=False)
            if "centre" in d
            else xy.mean(axis=0)
        )
        mass = rd.number_or_list(d, "mass", f"{p}.mass", 1, False, True)[0] if "mass" in d else 0.0
        span = np.ptp(xy, axis=0)
        inertia = (
            rd.number_or_list(d, "inertia", f"{p}.inertia", 1, False, True)[0]
            if "inertia" in d
            else mass * float(span @ span) / 12
        )
        size = max(float(np.ptp(nodes, axis=0).max()), 1.0)
        if np.ptp(nodes[dn, 2]) > GEOM_RTOL * size:
            rd.fail(f"{p}.nodes", "nodes at one level (equal z)", dn)
        if set(dn) <= set(base):  # (clamped: the frame hung from it, every mode's share 0)
            rd.fail(f"{p}.nodes", "nodes of a floor, not all base nodes (clamped, it cannot "
                    "move)", dn)  # fmt: skip
        lo, hi = nodes[:, :2].min(axis=0), nodes[:, :2].max(axis=0)
        tol = GEOM_RTOL * size
        if np.any(np.asarray(c) < lo - tol) or np.any(np.asarray(c) > hi + tol):
            rd.fail(f"{p}.centre", f"a centre of mass [x, y] within the plan, x in [{lo[0]:g}, "
                    f"{hi[0]:g}] and y in [{lo[1]:g}, {hi[1]:g}] m", list(c))  # fmt: skip
        dias.append(Diaphragm(dn, c, mass, inertia))
    tied = {int(i) for d in dias for i in d.nodes} | set(base)
    for k, d in enumerate(dias):  # (a floor of four nodes tied at three: the fourth ran free)
        z = nodes[d.nodes[0], 2]
        left = [i for i in range(nn) if i not in tied and abs(nodes[i, 2] - z) <= tol]
        if left:
            warnings.warn(f"{P}.diaphragms[{k}].nodes: the level z = {z:g} m also holds "
                          f"node(s) {left}, on no diaphragm (a floor's node left out?)",
                          NotedWarning, stacklevel=2)  # fmt: skip
    try:  # (the file's names of its elements: members[g].elements[k])
        groups = [d.nodes.tolist() for d in dias]
        check_geometry(nodes, np.array(el), tied=[n for g in groups for n in g], base=base,
                       groups=groups, element_name=names.__getitem__)  # fmt: skip
    except ValueError as exc:  # (a node by the table's name; an element carries its own)
        msg = f"{P}.{exc}" if str(exc).startswith(("nodes[", "base_nodes")) else str(exc)
        raise FrameFileError(f"{rd.file}: {msg}", P) from None
    S = [secs[i] for i in sid]
    zeta = _zeta(rd, f)  # its own error, outside the model's checks below
    try:
        return Frame3D(
            name=name,
            nodes=nodes,
            elements=np.array(el),
            vecxz=np.array(vec),
            **{
                k: [getattr(q, k) for q in S]
                for k in ("E", "G", "A", "I_y", "I_z", "J", "rho_A", "rho_Ip")
            },
            node_mass=node_mass,
            base_nodes=np.array(base),
            zeta=zeta,
            diaphragms=tuple(dias),
        )
    except ValueError as exc:  # (an element by the file's name: frame3d.members[1].elements[0])
        msg = re.sub(r"\belements\[(\d+)\]", lambda m: names[int(m.group(1))], str(exc))
        sep = "." if str(exc).startswith("diaphragms[") else ": "  # (a field: its path)
        raise FrameFileError(f"{rd.file}: {msg if msg != str(exc) else f'{TABLE}{sep}{exc}'}",
                             TABLE) from None  # fmt: skip


def frame3d_from_dict(data: Mapping, file: str = "<dict>") -> Frame3D:
    """Build a :class:`Frame3D` from parsed TOML data (``{"frame3d": {...}}``), strictly."""
    rd = _Reader(file)
    not_a_frame(data, file, TABLE)
    rd.known(data, {TABLE}, "")
    f = rd.table(data, TABLE, TABLE)
    name = rd.string(f, "name", f"{TABLE}.name")
    kind = f.get("kind", "regular")
    if "kind" not in f and "nodes" in f:  # (read as a grid: "frame3d.nodes: unknown field")
        raise FrameFileError(f"{rd.file}: {TABLE}.kind: missing; a frame listed node by node "
                             "is kind = 'explicit' (without kind it is 'regular', a grid of "
                             "bays)", TABLE)  # fmt: skip
    if kind not in ("regular", "explicit"):
        rd.fail(f"{TABLE}.kind", "'regular' or 'explicit'", kind)
    if "description" in f and not isinstance(f["description"], str):
        rd.fail(f"{TABLE}.description", "a string", f["description"])
    return _regular(rd, f, name) if kind == "regular" else _explicit(rd, f, name)


def is_frame3d(name_or_path) -> bool:
    """True if the frame file (or bundled name) holds a ``[frame3d]`` table."""
    data, _ = _read_frame_file(name_or_path)
    return TABLE in data


def load_frame3d(name_or_path: str | Path) -> Frame3D:
    """Load a 3D frame from a TOML file or a bundled name (``"office-11-3d"``); a
    :class:`FrameFileError` (a ValueError) names the file and field of a mistake, or says
    that no such file or bundled frame exists."""
    data, fname = _read_frame_file(name_or_path)
    if "frame" in data and "frame3d" not in data:
        raise FrameFileError(
            f"{fname}: a plane frame (its [frame] table); load it with nsdyn.load_frame, or "
            "give a 3D frame ([frame3d]; bundled: office-11-3d, portal-3d)"
        )
    return with_file_warnings(lambda: frame3d_from_dict(data, fname), fname, "frame3d")
