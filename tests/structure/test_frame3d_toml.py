"""3D frame files: the bundled examples, the explicit and the generated forms, bad input.

Sources: the file format's contract (every error one line naming the file, the dotted field
and the expected form), tributary-length lumping of floor masses (mass conservation), and
the equality of a structure listed node by node and the same structure generated (same
matrices up to numbering, so equal eigenvalues to the round-off bound c n eps cond(K)).
"""

from __future__ import annotations

import re
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest

from nsdyn.structure import (
    FrameFileError,
    Section3D,
    bundled_frames,
    fixed_base_modes_3d,
    frame3d_from_dict,
    is_frame3d,
    load_frame,
    load_frame3d,
    regular_building_3d,
)

REPO = Path(__file__).resolve().parents[2]
PORTAL = (REPO / "frames" / "portal-3d.toml").read_text()
OFFICE = (REPO / "frames" / "office-11-3d.toml").read_text()
EPS = np.finfo(float).eps


def write(tmp_path, text, old, new, name="bad.toml"):
    assert old in text, old
    p = tmp_path / name
    p.write_text(text.replace(old, new, 1))
    return p


def test_bundled_3d_frames_load_by_name_and_path():
    assert {"office-11-3d", "portal-3d"} <= set(bundled_frames())
    assert is_frame3d("office-11-3d") and not is_frame3d("office-11")
    a, b = load_frame3d("portal-3d"), load_frame3d(REPO / "frames" / "portal-3d.toml")
    assert np.array_equal(a.nodes, b.nodes) and a.n_dof == 48
    # rho gives rho_A = rho A and the torsional inertia rho (I_y + I_z)
    assert a.rho_A[0] == pytest.approx(7850 * 0.0149, rel=1e-15)
    assert a.rho_Ip[0] == pytest.approx(7850 * (2.517e-4 + 8.563e-5), rel=1e-15)
    assert a.G[0] == pytest.approx(2.1e11 / 2.6, rel=1e-15)  # nu = 0.3


def test_plane_loader_names_a_3d_file_as_such():
    with pytest.raises(FrameFileError, match=r"^office-11-3d\.toml: frame3d: .*load_frame3d"):
        load_frame("office-11-3d")


def test_explicit_portal_equals_the_generated_one():
    # the same one-storey building listed node by node and generated: equal frequencies to
    # c n eps cond(K) relative (the matrices differ only by numbering and rounding)
    ex = frame3d_from_dict(tomllib.loads(PORTAL), "portal-3d.toml")  # the slab's weight
    col = Section3D(2.1e11, 2.1e11 / 2.6, 0.0149, 2.517e-4, 8.563e-5, 1.852e-6, 7850 * 0.0149)
    beam = Section3D(2.1e11, 2.1e11 / 2.6, 0.00845, 2.313e-4, 1.318e-5, 5.108e-7, 7850 * 0.00845)
    gen = regular_building_3d(
        "g", [6.0], [5.0], [4.0], col, beam, beam, 1, 1, 24000.0, 122000.0, 0.02
    )
    assert np.array_equal(gen.node_mass[:, 2], ex.node_mass[:, 2])
    m1 = fixed_base_modes_3d(ex, n_modes=8)
    m2 = fixed_base_modes_3d(gen, n_modes=8)
    K, _ = ex.reduced()
    i = np.setdiff1d(np.arange(ex.n_red), ex.boundary_reduced)
    eb = 10 * len(i) * EPS * np.linalg.cond(K[i][:, i].toarray())
    lam1, lam2 = m1.f_hz**2, m2.f_hz**2
    assert np.all(np.abs(lam1 - lam2) <= eb * lam2 * lam2 / lam2[0])
    assert m1.family == m2.family


def test_generator_spreads_floor_mass_and_numbers_column_lines():
    # Source: tributary-length lumping conserves each floor's mass; with diaphragms it acts
    # horizontally at the master and vertically on the nodes, without them in x, y and z.
    s = Section3D(2.1e11, 8e10, 1e-2, 1e-4, 1e-4, 1e-4, 0.0)
    for dia in (True, False):
        b = regular_building_3d(
            "t",
            [4.0, 8.0],
            [5.0],
            [3.0, 3.0],
            s,
            s,
            s,
            2,
            3,
            [1200.0, 600.0],
            zeta=0.05,
            diaphragms=dia,
        )
        assert b.total_mass == pytest.approx(1800.0, rel=1e-14)
        assert b.node_mass[:, 2].sum() == pytest.approx(1800.0, rel=1e-14)
        assert b.node_mass[:, 0].sum() == pytest.approx(0.0 if dia else 1800.0, abs=1e-9)
        assert b.column_joints.shape == (3, 6)
        z = b.nodes[b.column_joints, 2]
        assert np.allclose(z, np.array([0.0, 3.0, 6.0])[:, None])
        xy = b.nodes[b.column_joints[0], :2]
        assert xy.tolist() == [[0, 0], [4, 0], [12, 0], [0, 5], [4, 5], [12, 5]]


COL_VECXZ = "vecxz = [1.0, 0.0, 0.0]  # local z = global X: I_y resists sway in x\n"
MASS_END = "[0.0, 0.0, 6000.0], [0.0, 0.0, 6000.0],\n]"
BAD = [  # (id, file text, old, new, field, expected-form needle)
    (
        "office-no-vecxz",
        OFFICE,
        COL_VECXZ,
        "",
        r"frame3d\.columns\.vecxz",
        r"orientation vector.*missing",
    ),
    (
        "office-parallel",
        OFFICE,
        "vecxz = [1.0, 0.0, 0.0]",
        "vecxz = [0.0, 0.0, 2.0]",
        r"frame3d\.columns\.vecxz",
        r"not parallel",
    ),
    ("office-no-I_z", OFFICE, "I_z = 0.00022\n", "", r"frame3d\.beams_x\.I_z", r"positive number"),
    ("office-no-G", OFFICE, "nu = 0.3\n", "", r"frame3d\.columns\.G", r"G \[Pa\] or nu"),
    ("office-nu-high", OFFICE, "nu = 0.3", "nu = 0.6", r"frame3d\.columns\.nu", r"\(-1, 0\.5\)"),
    (
        "portal-no-vecxz",
        PORTAL,
        "vecxz = [1.0, 0.0, 0.0]\n",
        "",
        r"frame3d\.members\[0\]\.vecxz",
        r"orientation vector.*missing",
    ),
    (
        "portal-parallel",
        PORTAL,
        "vecxz = [0.0, 0.0, 1.0]",
        "vecxz = [1.0, 0.0, 0.0]",
        r"frame3d\.members\[1\]\.vecxz",
        r"not parallel.*\[4, 5\]",
    ),
    (
        "portal-one-node",
        PORTAL,
        "nodes = [4, 5, 6, 7]",
        "nodes = [4]",
        r"frame3d\.diaphragms\[0\]\.nodes",
        r">= 2 distinct",
    ),
    (
        "portal-two-levels",
        PORTAL,
        "nodes = [4, 5, 6, 7]",
        "nodes = [4, 5, 6, 0]",
        r"frame3d\.diaphragms\[0\]\.nodes",
        r"one level",
    ),
    ("portal-no-J", PORTAL, "J = 1.852e-6\n", "", r"frame3d\.sections\[0\]\.J", r"positive"),
    (
        "portal-vecxz-count",
        PORTAL,
        "vecxz = [0.0, 0.0, 1.0]",
        "vecxz = [[0.0, 0.0, 1.0]]",
        r"frame3d\.members\[1\]\.vecxz",
        r"one vector per element",
    ),
    (
        "portal-nan-node",
        PORTAL,
        "[0.0, 5.0, 4.0],   # 4-7",
        "[0.0, nan, 4.0],   # 4-7",
        r"frame3d\.nodes\[7\]",
        r"finite coordinates",
    ),
    (
        "office-offset-without-diaphragms",
        OFFICE,
        "diaphragms = true",
        "diaphragms = false\nmass_offset = [0.5, 0.0]",
        r"frame3d\.mass_offset",
        r"with diaphragms = false",
    ),
    (
        "office-offset-outside-the-plan",  # (its floors' mass outside a 15 x 80 m plan)
        OFFICE,
        "diaphragms = true",
        "diaphragms = true\nmass_offset = [100.0, 0.0]",
        r"frame3d\.mass_offset",
        r"within the plan, \|e_x\| <= 7\.5 and \|e_y\| <= 40, got \[100\.0, 0\.0\]",
    ),
    (
        "portal-negative-zeta",  # named once: the explicit builder's own checks do not wrap it
        PORTAL,
        "zeta = [0.02]",
        "zeta = [0.02, -1.0]",
        r"frame3d\.zeta",
        r"numbers >= 0, got \[0\.02, -1\.0\] \(contains -1\)$",
    ),
    (
        "portal-base-node-out-of-range",  # a short list is shown whole: the bad entry shows
        PORTAL,
        "base_nodes = [0, 1, 2, 3]",
        "base_nodes = [0, 1, 2, 13]",
        r"frame3d\.base_nodes",
        r"node indices in 0\.\.7, got \[0, 1, 2, 13\]$",
    ),
    (
        "portal-typo-field",
        PORTAL,
        "I_y = 2.517e-4  # strong axis",
        "Iy = 2.517e-4",
        r"frame3d\.sections\[0\]\.Iy",
        r"unknown field; did you mean 'I_y'\? \(allowed: A, E, G, I_y,",
    ),
    (
        "portal-missing-i_z",  # (an explicit frame's section took "a list of 1 positive number")
        PORTAL,
        "I_z = 8.563e-5",
        "",
        r"frame3d\.sections\[0\]\.I_z",
        r"expected a positive number, got nothing \(missing\)$",
    ),
    (
        "portal-both-rho",
        PORTAL,
        "rho = 7850.0",
        "rho = 7850.0\nrho_A = 117.0",
        r"frame3d\.sections\[0\]\.rho",
        r"exactly one of rho",
    ),
    # a diaphragm's mass 300 m off a 6 m plan (first mode 0.055 Hz, without a word), a floor
    # of clamped nodes (the frame hung from it: every mode "x" with 0 % mass), a negative
    # mass named by its entry
    ("portal-centre", PORTAL, "centre = [3.0, 2.5]", "centre = [300.0, 2.5]",
     r"frame3d\.diaphragms\[0\]\.centre", r"within the plan, x in \[0, 6\]"),
    ("portal-clamped-floor", PORTAL, "base_nodes = [0, 1, 2, 3]", "base_nodes = [4, 5, 6, 7]",
     r"frame3d\.diaphragms\[0\]\.nodes", r"not all base nodes"),
    ("portal-negative-mass", PORTAL, MASS_END, MASS_END.replace("6000.0]", "-6000.0]", 1),
     r"frame3d\.node_mass\[6\]", r"triple >= 0, got \[0\.0, 0\.0, -6000\.0\]"),
]  # fmt: skip


@pytest.mark.parametrize("row", BAD, ids=[r[0] for r in BAD])
def test_bad_3d_frame_file_gives_one_line_naming_file_and_field(tmp_path, row):
    rid, text, old, new, field, needle = row
    p = write(tmp_path, text, old, new, f"bad-{rid}.toml")
    with pytest.raises(FrameFileError) as ei:
        load_frame3d(p)
    msg = str(ei.value)
    assert "\n" not in msg
    assert msg.startswith(f"{p}: ")
    assert re.search(rf"^{re.escape(str(p))}: {field}: (expected|unknown field)", msg), msg
    assert re.search(needle, msg), msg


HEADS = "[0.0, 0.0, 4.0], [6.0, 0.0, 4.0], [6.0, 5.0, 4.0], [0.0, 5.0, 4.0],   # 4-7: column heads"
BEAMS = "elements = [[4, 5], [5, 6], [6, 7], [7, 4]]"


@pytest.mark.parametrize(
    "extra_nodes, beams, message",
    [
        # a beam listed twice: its stiffness counted twice, without a word
        ("", "[[4, 5], [5, 6], [6, 7], [7, 4], [5, 4]]",
         r"frame3d\.members\[1\]\.elements\[4\]: joins nodes 5 and 4, as "
         r"frame3d\.members\[1\]\.elements\[0\] does"),
        # a second node at a column head, a beam on it: the frame cut there, without a word
        ("[6.0, 0.0, 4.0],", "[[4, 8], [5, 6], [6, 7], [7, 4]]",
         r"frame3d\.nodes\[8\]: at the same place as nodes\[5\]"),
        # a node on no element, and a beam joined to no base node (tracebacks before)
        ("[9.0, 0.0, 4.0],", None, r"frame3d\.nodes\[8\]: on no element"),
        ("[9.0, 0.0, 4.0], [12.0, 0.0, 4.0],", "[[4, 5], [5, 6], [6, 7], [7, 4], [8, 9]]",
         r"frame3d\.nodes\[8\]: joined to no base node"),
    ],
)  # fmt: skip
def test_a_3d_frame_that_would_run_wrong_or_singular_is_refused(tmp_path, extra_nodes, beams,
                                                                message):  # fmt: skip
    text = PORTAL.replace(HEADS, HEADS.split("   #")[0] + extra_nodes)
    n_extra = extra_nodes.count("[")
    text = text.replace(MASS_END, MASS_END[:-1] + "[0.0, 0.0, 0.0],\n" * n_extra + "]")
    if beams:
        text = text.replace(BEAMS, f"elements = {beams}")
    p = tmp_path / "p.toml"
    p.write_text(text)
    with pytest.raises(FrameFileError, match=rf"^{re.escape(str(p))}: {message}") as e:
        load_frame3d(p)
    assert "\n" not in str(e.value)


def test_3d_member_stiffnesses_beyond_double_precision_are_refused(tmp_path):
    # the beams' J = 5.108e-22 m⁴: GJ/L³ of a 6 m beam 2.1e11 / 2.6 * 5.108e-22 / 6³ = 1.91e-13
    # N/m beside a 4 m column's EA/L = 2.1e11 * 0.0149 / 4 = 7.82e8 N/m spans 4.1e21 > 1/eps
    p = tmp_path / "p.toml"
    p.write_text(PORTAL.replace("J = 5.108e-7", "J = 5.108e-22"))
    # (named as the file names them: a column of members[0], the first beam of members[1])
    with pytest.raises(FrameFileError, match=rf"^{re.escape(str(p))}: frame3d\.members\[0\]\."
                       r"elements\[0\]: its EA/L = 7\.82e\+08 N/m is 4\.1e\+21 times the GJ/L³ "
                       r"of frame3d\.members\[1\]\.elements\[0\] \(1\.91e-13 N/m\)"):  # fmt: skip
        load_frame3d(p)
    # I_y = 1e300 m⁴: 12EI_y/L³ = 12 * 2.1e11 * 1e300 / 4³ overflows to inf (numpy's overflow
    # warnings, then "array must not contain infs or NaNs" naming no field)
    p.write_text(PORTAL.replace("I_y = 2.517e-4", "I_y = 1e300"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(FrameFileError, match=r": frame3d\.members\[0\]\.elements\[0\]: "
                           "its 12EI_y/L³ = inf N/m overflows or underflows"):  # fmt: skip
            load_frame3d(p)


def test_a_3d_node_on_the_diaphragm_and_no_member_is_named(tmp_path):
    # the floor's centre listed as a node of the diaphragm on no member: its uz, rx and ry had
    # no stiffness, and the modes stopped at "not positive definite" naming no node
    text = PORTAL.replace(HEADS, HEADS.split("   #")[0] + "[3.0, 2.5, 4.0],")
    text = text.replace(MASS_END, MASS_END[:-1] + "[0.0, 0.0, 0.0],\n]")
    p = tmp_path / "p.toml"
    p.write_text(text.replace("nodes = [4, 5, 6, 7]", "nodes = [4, 5, 6, 7, 8]"))
    with pytest.raises(FrameFileError, match=rf"^{re.escape(str(p))}: frame3d\.nodes\[8\]: on "
                       "a diaphragm and no element"):  # fmt: skip
        load_frame3d(p)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        # a storey of 1e-9 m: nodes at one place (a traceback naming neither file nor field)
        ("storey_heights = [6.0,", "storey_heights = [1e-9,",
         r"frame3d: elements\[\d+\]: nodes \d+ and \d+ are at the same place"),
        # 5e10 dofs: refused before a list of that size is built (a MemoryError before)
        ("\nn_v = 5", "\nn_v = 1000000000",
         r"frame3d: bays_x, bays_y, storey_heights, n_v, n_h: .* dofs; expected a model"),
    ],
)  # fmt: skip
def test_a_regular_frame_the_model_refuses_names_the_file_and_its_fields(tmp_path, old, new,
                                                                          message):  # fmt: skip
    p = tmp_path / "r.toml"
    p.write_text(OFFICE.replace(old, new, 1))
    with pytest.raises(FrameFileError, match=rf"^{re.escape(str(p))}: {message}") as e:
        load_frame3d(p)
    assert "\n" not in str(e.value) and "storey_heights, n_v and n_h" in str(e.value)


@pytest.mark.parametrize("base", ["[0, 1, 2]", "[0, 1, 2, 7]"])
def test_a_frame_stands_on_every_column_foot(tmp_path, base):
    # a free foot ran (the frame rocking on the rest: drift ratios of 1e10, without a word)
    p = write(tmp_path, PORTAL, "base_nodes = [0, 1, 2, 3]", f"base_nodes = {base}", "b.toml")
    with pytest.raises(FrameFileError, match=r"frame3d\.base_nodes: node 3 is a column foot at "
                       r"the base level \(0 m\) but not a base node, and nothing else holds "
                       r"it"):  # fmt: skip
        load_frame3d(p)
    plane = (REPO / "frames" / "portal.toml").read_text()
    two = tmp_path / "p.toml"
    two.write_text(plane.replace("base_nodes = [0, 1]", "base_nodes = [0]"))
    with pytest.raises(FrameFileError, match=r"frame: base_nodes: node 1 is a column foot"):
        load_frame(two)


def test_a_column_on_a_base_girder_a_stepped_base_and_a_pit_are_frames():
    # what the free-foot check must not refuse: a middle column on a girder between two
    # isolators, base nodes at two heights, an element hanging below the base
    from nsdyn.structure import Frame

    def frame(nodes, elements, base):
        n, e = len(nodes), len(elements)
        return Frame(name="f", nodes=nodes, elements=elements, E=[2e11] * e, A=[0.01] * e,
                     I=[1e-4] * e, rho_A=[100.0] * e, node_mass=[1000.0] * n,
                     base_nodes=base, zeta=[0.05])  # fmt: skip

    girder = frame(
        [[0, 0], [3, 0], [6, 0], [0, 3], [3, 3], [6, 3]],
        [[0, 1], [1, 2], [0, 3], [1, 4], [2, 5], [3, 4], [4, 5]],
        [0, 2],
    )
    stepped = frame([[0, 0], [6, 1], [0, 4], [6, 4]], [[0, 2], [1, 3], [2, 3]], [0, 1])
    pit = frame(
        [[0, 0], [6, 0], [0, 3], [6, 3], [3, 0], [3, -3]],
        [[0, 4], [4, 1], [0, 2], [1, 3], [2, 3], [4, 5]],
        [0, 1],
    )
    assert [len(f.base_nodes) for f in (girder, stepped, pit)] == [2, 2, 2]
    with pytest.raises(ValueError, match=r"^base_nodes must be a list of node indices \(whole "
                       r"numbers\), got \['0', '1'\]"):  # fmt: skip
        frame([[0, 0], [0, 3]], [[0, 1]], ["0", "1"])


def test_rho_ip_beside_rho_is_refused(tmp_path):
    # rho_Ip was dropped without a word (rho gives rho (I_y + I_z))
    text = (REPO / "frames" / "portal-3d.toml").read_text()
    m = re.search(r"^rho = .*$", text, re.M)  # (its sections give the density)
    p = write(tmp_path, text, m.group(0), m.group(0) + "\nrho_Ip = 999.0", "r.toml")
    with pytest.raises(FrameFileError, match=r"rho_Ip: expected no rho_Ip beside rho"):
        load_frame3d(p)


def test_an_element_along_another_is_refused(tmp_path):
    # a node on a beam's line and an element from the beam's end to it: the stretch counted
    # twice (spurious local modes, without a word)
    text = PORTAL.replace(HEADS, HEADS.split("   #")[0] + "[3.0, 0.0, 4.0],")
    text = text.replace(MASS_END, MASS_END[:-1] + "[0.0, 0.0, 0.0],\n]")
    text = text.replace(BEAMS, "elements = [[4, 5], [5, 6], [6, 7], [7, 4], [4, 8]]")
    p = tmp_path / "p.toml"
    p.write_text(text)
    with pytest.raises(FrameFileError, match=r"nodes 4 to 8 lie along .* \(nodes 4 to 5\), "
                       r"overlapping it"):  # fmt: skip
        load_frame3d(p)


def test_a_floor_node_left_off_its_diaphragm_is_noted(tmp_path):
    # the portal's slab tied at three of its four column heads: the fourth ran free in plan,
    # without a word (a roof-only diaphragm over other floors is no such slip: not noted)
    from nsdyn._checks import NotedWarning

    p = write(tmp_path, PORTAL, "nodes = [4, 5, 6, 7]", "nodes = [4, 5, 6]", "part.toml")
    with pytest.warns(NotedWarning, match=r"part.toml: frame3d.diaphragms\[0\].nodes: the level "
                      r"z = 4 m also holds node\(s\) \[7\], on no diaphragm"):  # fmt: skip
        load_frame3d(p)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        load_frame3d(write(tmp_path, PORTAL, "zeta = [0.02]", "zeta = [0.02]", "whole.toml"))


def test_a_frame_listed_by_nodes_without_its_kind_is_told_so(tmp_path):
    # read as the default grid, it was refused as "frame3d.nodes: unknown field"
    p = write(tmp_path, PORTAL, 'kind = "explicit"\n', "", "no-kind.toml")
    with pytest.raises(FrameFileError, match=rf"^{re.escape(str(p))}: frame3d\.kind: missing; "
                       r"a frame listed node by node is kind = 'explicit'"):  # fmt: skip
        load_frame3d(p)


def test_a_node_on_two_floors_names_the_diaphragm_and_the_form(tmp_path):
    # (it said "frame3d: node 5 is in diaphragms 0 and 1", naming no field nor what to give)
    p = tmp_path / "two.toml"
    p.write_text(PORTAL + "\n[[frame3d.diaphragms]]\nnodes = [5, 6]\nmass = 1000.0\n")
    with pytest.raises(FrameFileError, match=rf"^{re.escape(str(p))}: frame3d\.diaphragms\[1\]"
                       r"\.nodes: node 5 is also on diaphragms\[0\]; expected each node on one "
                       r"floor at most$"):  # fmt: skip
        load_frame3d(p)
