"""Frame files: a good file loads, every bad field is named with what was expected.

Expected values are the numbers written in the test files and in frames/portal.toml.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from nsdyn.structure import FrameFileError, bundled_frames, load_frame

REPO = Path(__file__).resolve().parents[2]

# --------------------------------------------------------------------------- TOML

GOOD = """
[frame]
name = "two"
kind = "regular"
bays = [6.0]
storey_heights = [4.0, 3.0]
n_v = 2
n_h = 2
floor_mass = 1000.0
zeta = [0.02, 0.03]

[frame.columns]
E = 2.1e11
A = [0.02, 0.01]
I = 2e-4
rho_A = 100.0

[frame.beams]
E = 2.1e11
A = 0.01
I = 1e-4
rho_A = 80.0
"""


def test_good_file_loads(tmp_path):
    p = tmp_path / "two.toml"
    p.write_text(GOOD)
    fr = load_frame(p)
    assert fr.name == "two" and fr.n_nodes == 2 + 2 * (2 * 1 + 3)
    assert fr.A.max() == 0.02 and fr.A.min() == 0.01


@pytest.mark.parametrize(
    ("old", "new", "field", "words"),
    [
        ("storey_heights = [4.0, 3.0]\n", "", "frame.storey_heights", "missing"),
        ("n_v = 2", 'n_v = "two"', "frame.n_v", "integer"),
        ("n_h = 2", "n_h = 2.5", "frame.n_h", "integer"),
        ("A = [0.02, 0.01]", "A = [0.02, 0.01, 0.01]", "frame.columns.A", "list of 2"),
        ("[4.0, 3.0]", "[4.0, -3.0]", "frame.storey_heights", "positive"),
        ("bays = [6.0]", "bays = 6.0", "frame.bays", "list"),
        ("floor_mass = 1000.0", "floor_mass = -1.0", "frame.floor_mass", ">= 0"),
        ("zeta = [0.02, 0.03]", "zeta = [0.02, 1.5]", "frame.zeta", "[0, 1)"),
        ('kind = "regular"', 'kind = "weird"', "frame.kind", "explicit"),
        ("n_h = 2\n", "n_h = 2\nbayz = 3\n", "frame.bayz", "unknown field"),
        ("I = 1e-4", "Iy = 1e-4", "frame.beams.Iy", "unknown field"),
        ("[frame.beams]", "[frame.girders]", "frame.girders", "unknown field"),
    ],
)
def test_bad_file_names_file_and_field(tmp_path, old, new, field, words):
    assert old in GOOD
    p = tmp_path / "bad.toml"
    p.write_text(GOOD.replace(old, new, 1))
    with pytest.raises(FrameFileError) as ei:
        load_frame(p)
    msg = str(ei.value)
    assert msg.startswith(f"{p}: "), msg  # the file as given
    assert field in msg and words in msg, msg


def test_a_negative_scalar_is_quoted_once(tmp_path):
    # "got -0.0493 (contains -0.0493)": the list's note followed a single number too
    p = tmp_path / "bad.toml"
    p.write_text(GOOD.replace("E = 2.1e11\nA = 0.01", "E = 2.1e11\nA = -0.01", 1))
    with pytest.raises(FrameFileError, match=r"frame\.beams\.A: expected .*, got -0\.01$"):
        load_frame(p)


def test_wrong_list_length_message(tmp_path):
    # The message format promised in the docs: file, dotted field, expectation, what came.
    p = tmp_path / "office-11.toml"
    p.write_text(GOOD.replace("I = 2e-4", "I = [2e-4, 2e-4, 2e-4]"))
    named = rf"^{re.escape(str(p))}: frame\.columns\.I: expected "  # the file as given
    with pytest.raises(FrameFileError, match=named):
        load_frame(p)
    with pytest.raises(FrameFileError, match=re.escape("got [0.0002, 0.0002, 0.0002]")):
        load_frame(p)  # a short list is shown whole
    # a long one by its length
    p.write_text(GOOD.replace("I = 2e-4", f"I = [{', '.join(['2e-4'] * 13)}]"))
    with pytest.raises(FrameFileError, match="got a list of 13$"):
        load_frame(p)


def test_a_bare_name_of_a_folder_says_a_frame_is_a_file(tmp_path, monkeypatch):
    # "nsdyn modes fr" with a folder fr here said only "no bundled frame of that name"
    monkeypatch.chdir(tmp_path)
    (tmp_path / "fr").mkdir()
    with pytest.raises(FrameFileError, match=r"^fr: no bundled frame of that name \(a folder"):
        load_frame("fr")


def test_a_bare_name_of_a_record_file_says_what_it_may_be(tmp_path, monkeypatch):
    # "nsdyn modes rec.csv" said only "no bundled frame of that name" beside the file
    monkeypatch.chdir(tmp_path)
    (tmp_path / "rec.csv").write_text("0 0\n0.01 1\n")
    with pytest.raises(FrameFileError, match=r"^rec.csv: no bundled frame of that name \(the "
                       r"file rec.csv here is no frame file: those are \.toml files; a "
                       r"ground-motion record goes in a scene's \[motion\] record\)"):  # fmt: skip
        load_frame("rec.csv")


def test_not_toml_and_missing_files(tmp_path):
    p = tmp_path / "junk.toml"
    p.write_text("[frame\nname = ")
    with pytest.raises(FrameFileError, match="junk.toml: not valid TOML"):
        load_frame(p)
    with pytest.raises(FrameFileError, match="no such frame file"):
        load_frame(tmp_path / "nope.toml")
    with pytest.raises(FrameFileError, match="office-11") as ei:
        load_frame("no-such-frame")
    assert isinstance(ei.value, ValueError)


@pytest.mark.parametrize("codec", ["utf-8-sig", "utf-16", "utf-32"])
def test_a_frame_file_with_a_byte_order_mark_is_the_same_frame(tmp_path, codec):
    # a mark (Notepad, PowerShell) was "not valid TOML (at line 1, column 1)"; scenes and
    # studies read it; text that is not UTF-8 names its line and how to save the file
    text = (REPO / "frames" / "portal.toml").read_text(encoding="utf-8")
    p = tmp_path / "portal.toml"
    p.write_bytes(text.encode(codec))
    a, b = load_frame(p), load_frame("portal")
    assert np.array_equal(a.nodes, b.nodes) and np.array_equal(a.I, b.I)
    p.write_bytes(("# Zürich\n" + text).encode("latin-1"))
    with pytest.raises(FrameFileError, match=r"portal\.toml: not UTF-8 text: byte 0xfc on line "
                       r"1 \(save the file as UTF-8\)"):  # fmt: skip
        load_frame(p)


def test_bundled_names_and_paths_agree():
    assert {"office-11", "portal"} <= set(bundled_frames())
    a = load_frame("office-11")
    b = load_frame(REPO / "frames" / "office-11.toml")
    assert np.array_equal(a.nodes, b.nodes) and np.array_equal(a.I, b.I)


def test_explicit_portal_file():
    # Source: frames/portal.toml lists 7 nodes, 6 elements, 2 base nodes, 12 t added mass.
    fr = load_frame("portal")
    assert fr.n_dof == 21 and fr.base_nodes.tolist() == [0, 1]
    assert fr.level_heights.tolist() == [0.0, 4.0]
    assert fr.column_joints.tolist() == [[0, 1], [3, 5]]
    steel = 2 * 4.0 * 117.0 + 6.0 * 66.3  # two 4 m columns + a 6 m beam
    assert fr.total_mass == pytest.approx(12000.0 + steel, rel=1e-12)


def test_explicit_file_errors(tmp_path):
    text = (REPO / "frames" / "portal.toml").read_text()
    p = tmp_path / "p.toml"
    p.write_text(text.replace("[4, 5, 1]", "[4, 9, 1]"))
    with pytest.raises(FrameFileError, match=r"p\.toml: frame\.elements\[3\]: expected"):
        load_frame(p)
    p.write_text(text.replace("base_nodes = [0, 1]", "base_nodes = [0, 0]"))
    with pytest.raises(FrameFileError, match=r"frame\.base_nodes"):
        load_frame(p)
    p.write_text(text.replace("I = 2.313e-4", "I = -2.313e-4"))
    with pytest.raises(FrameFileError, match=r"frame\.sections\[1\]\.I"):
        load_frame(p)


def test_member_stiffnesses_beyond_double_precision_are_refused(tmp_path):
    # E = 1e300 beside I = 1e-30: EA/L of a 2 m column 1e300 * 0.0149 / 2 = 7.45e297 N/m and
    # the beam's 12EI/L³ = 12 * 1e300 * 1e-30 / 3³ = 4.44e269 N/m span 1.7e28 > 1/eps: the modes
    # listed 0.0 Hz, or the factorisation stopped ("exactly singular") in a traceback
    text = (REPO / "frames" / "portal.toml").read_text()
    p = tmp_path / "p.toml"
    p.write_text(text.replace("E = 2.1e11", "E = 1e300").replace("I = 2.313e-4", "I = 1e-30"))
    head = rf"^{re.escape(str(p))}: frame\.elements\[0\]: its EA/L = 7\.45e\+297 N/m is "
    tail = r"1\.7e\+28 times the 12EI/L³ of elements\[2\] \(4\.44e\+269 N/m\); expected member"
    with pytest.raises(FrameFileError, match=head + tail):
        load_frame(p)
    # columns 1e4 times as stiff as steel (rigid links) stay a frame: EA/L = 1.56e13 N/m of a
    # column over the beam's 12EI/L³ = 2.16e4 N/m spans 7.2e8
    p.write_text(text.replace("E = 2.1e11", "E = 2.1e15", 1))
    assert load_frame(p).E.max() == 2.1e15


PORTAL_NODES = "[6.0, 4.0], [6.0, 2.0],              # 5, 6: right column"
PORTAL_ELEMENTS = "[[0, 2, 0], [2, 3, 0], [3, 4, 1], [4, 5, 1], [1, 6, 0], [6, 5, 0]]"
PORTAL_MASS = "node_mass = [0.0, 0.0, 0.0, 3000.0, 6000.0, 3000.0, 0.0]"


@pytest.mark.parametrize(
    "nodes, elements, mass, message",
    [
        # the beam's half [3, 4] listed twice: its stiffness and mass were added twice (f1
        # 4.90 -> 5.11 Hz), without a word
        (None, "[4, 3, 1], [4, 5, 1]", None,
         r"frame\.elements\[3\]: joins nodes 4 and 3, as elements\[2\] does"),
        # a second node at the midspan, the beam's right half on it: the beam was cut in two
        # (f1 4.90 -> 1.78 Hz), without a word
        ("[6.0, 4.0], [6.0, 2.0], [3.0, 4.0],", "[7, 5, 1]", 1,
         r"frame\.nodes\[7\]: at the same place as nodes\[4\] \(\[3\.0, 4\.0\]\)"),
        # an element over the beam's two halves: counted twice (f1 4.90 -> 5.30 Hz)
        (None, "[4, 5, 1], [3, 5, 1]", None,
         r"frame\.elements\[4\]: nodes 3 to 5 lie along elements\[2\] \(nodes 3 to 4\), "
         r"overlapping it"),
        # a node on no element, and a part joined to no base node (singular: tracebacks)
        ("[6.0, 4.0], [6.0, 2.0], [9.0, 4.0],", None, 1,
         r"frame\.nodes\[7\]: on no element"),
        ("[6.0, 4.0], [6.0, 2.0], [9.0, 4.0], [12.0, 4.0],", "[4, 5, 1], [7, 8, 1]",
         2, r"frame\.nodes\[7\]: joined to no base node \(with 1 other node"),
        ("[6.0, 4.0], [nan, 2.0],", None, None,
         r"frame\.nodes\[6\]: expected finite coordinates \[x, y\] \[m\], got \[nan, 2\.0\]"),
        (None, "[4, 4, 1]", None, r"frame\.elements\[3\]: expected \[node_i, node_j\] .* got "
         r"\[4, 4, 1\]"),
    ],
)  # fmt: skip
def test_a_frame_that_would_run_wrong_or_singular_is_refused(tmp_path, nodes, elements, mass,
                                                             message):  # fmt: skip
    text = (REPO / "frames" / "portal.toml").read_text()
    if nodes:
        text = text.replace(PORTAL_NODES, nodes)
    if elements:
        text = text.replace(PORTAL_ELEMENTS, PORTAL_ELEMENTS.replace("[4, 5, 1]", elements))
    if mass:
        text = text.replace(PORTAL_MASS, PORTAL_MASS.replace("]", ", 0.0" * mass + "]"))
    p = tmp_path / "p.toml"
    p.write_text(text)
    with pytest.raises(FrameFileError, match=rf"^{re.escape(str(p))}: {message}") as e:
        load_frame(p)
    assert "\n" not in str(e.value)


def test_a_frame_hung_from_its_supports_is_refused(tmp_path):
    # the portal on its beam's corners (y = 4 m), the columns hanging below: it ran as any
    # frame, the isolators above the floor mass; a pit below the base stays a frame
    text = (REPO / "frames" / "portal.toml").read_text()
    p = tmp_path / "p.toml"
    p.write_text(text.replace("base_nodes = [0, 1]", "base_nodes = [3, 5]"))
    said = r"frame: base_nodes: every node lies at or below the base nodes \(y <= 4 m\): a frame"
    with pytest.raises(FrameFileError, match=rf"^{re.escape(str(p))}: {said}"):
        load_frame(p)


def test_a_frame_of_base_nodes_alone_is_refused(tmp_path):
    # every node a base node: nothing above the isolators moves; `nsdyn modes` drew an empty
    # figure (a matplotlib traceback) and a run "succeeded" with drifts of 1e-8
    from dataclasses import replace

    text = (REPO / "frames" / "portal.toml").read_text()
    nn = load_frame("portal").n_nodes
    p = tmp_path / "p.toml"
    p.write_text(text.replace("base_nodes = [0, 1]", f"base_nodes = {list(range(nn))}"))
    said = rf"frame.base_nodes: expected the nodes on the isolators only, not all {nn} nodes"
    with pytest.raises(FrameFileError, match=rf"^{re.escape(str(p))}: {said}"):
        load_frame(p)
    with pytest.raises(ValueError, match=rf"^base_nodes: every one of the {nn} nodes is a base"):
        replace(load_frame("portal"), base_nodes=np.arange(nn))
    from nsdyn.structure import load_frame3d

    text3 = (REPO / "frames" / "portal-3d.toml").read_text()
    n3 = load_frame3d("portal-3d").n_nodes
    p3 = tmp_path / "p3.toml"
    p3.write_text(text3.replace("base_nodes = [0, 1, 2, 3]", f"base_nodes = {list(range(n3))}"))
    with pytest.raises(FrameFileError, match=rf"frame3d.base_nodes: expected the nodes on the "
                       rf"isolators only, not all {n3} nodes"):  # fmt: skip
        load_frame3d(p3)


def test_a_massless_cantilever_with_a_tip_mass_has_the_exact_frequencies():
    # massless members (rho_A = 0) and a lumped mass: M is singular (rotations and the middle
    # node carry none) and the fixed-base modes were a LinAlgError traceback. The finite modes
    # now come through the Cholesky factor of K; Bernoulli-Euler elements are exact in
    # statics, so a tip mass m on a massless cantilever of length L vibrates at
    # sqrt(3 EI / L^3 / m) laterally and sqrt(EA / L / m) axially, to round-off (1e-9:
    # eigenvalues to n eps of the largest, squared roots). Its cb and full models, whose mass
    # matrices must be positive definite, are refused naming the node
    from nsdyn.models.isolated.system import build_system
    from nsdyn.structure.frame import Frame
    from nsdyn.structure.reduction import fixed_base_modes

    E, A, I, L, m = 2e11, 1e-2, 1e-4, 6.0, 1e3
    nodes = [[0.0, 0.0], [0.0, L / 2], [0.0, L]]
    fr = Frame(name="c", nodes=nodes, elements=[[0, 1], [1, 2]], E=E, A=A, I=I, rho_A=0.0,
               node_mass=[0, 0, m], base_nodes=[0], zeta=[0.02])  # fmt: skip
    assert fr.massless_rotations().tolist() == [0, 1, 2]
    f, _ = fixed_base_modes(*fr.assemble(), fr.boundary_dofs)
    exact = np.sqrt([3 * E * I / L**3 / m, E * A / L / m]) / (2 * np.pi)
    np.testing.assert_allclose(f, exact, rtol=1e-9)
    for fidelity in ("cb", "full"):
        with pytest.raises(ValueError, match=rf"^nodes\[0\] of frame 'c': .* '{fidelity}' model"):
            build_system(fr, fidelity=fidelity)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        # 3e6 dofs were built (1.7 GB) or grew into a MemoryError traceback (here 3 (2 + 2 (2 x
        # 999 999 + 3)) = 12 000 012 dofs); a bay of 1e12 m
        # was a ValueError traceback: one line naming the file, as the 3D reader's
        ("n_v = 2", "n_v = 1000000",
         r"frame: bays, storey_heights, n_v, n_h: 1.2e\+07 dofs; expected a model of at most"),
        ("bays = [6.0]", "bays = [1e12]", r"frame: elements\[\d+\]: nodes \d+ and \d+ are at the "
         r"same place"),
        # an explicit frame without its kind was "frame.nodes: unknown field"
        ('kind = "regular"', "nodes = [[0.0, 0.0], [0.0, 3.0]]",
         r"frame\.kind: expected kind = 'explicit' for a frame of nodes and elements"),
    ],
)  # fmt: skip
def test_a_regular_frame_out_of_reach_is_one_line(tmp_path, old, new, message):
    p = tmp_path / "f.toml"
    p.write_text(GOOD.replace(old, new))
    with pytest.raises(FrameFileError, match=rf"^{re.escape(str(p))}: {message}") as e:
        load_frame(p)
    assert "\n" not in str(e.value)


@pytest.mark.parametrize(
    ("kw", "message"),
    [({"bays": ["6"]}, r"^bays: expected numbers, got \['6'\]"),
     ({"bays": [True]}, r"^bays: expected numbers"), ({"floor_mass": "1e4"}, r"^floor_mass: "),
     ({"bays": 6.0}, r"^bays: expected a list"), ({"bays": [[6.0]]}, r"^bays: expected a list"),
     ({"storey_heights": [3.0, -1.0]}, r"^storey_heights: expected positive sizes"),
     ({"n_v": True}, r"^n_v: expected a whole number"), ({"n_h": 2.0}, r"^n_h: expected a whole"),
     ({"zeta": "0.05"}, r"^zeta: expected numbers"), ({"name": None}, r"^name: expected"),
     ({"bays": [1.0] * 1000, "storey_heights": [3.0] * 1000},
      r"^bays, storey_heights, n_v, n_h: 9\.01e\+06 dofs; expected a model of at most 1e\+06")],
)  # fmt: skip
def test_the_regular_generator_refuses_what_it_would_convert_or_could_not_hold(kw, message):
    # text, bools and floats were converted ("6" a bay, True one element per column), a
    # million-storey request allocated gigabytes
    from nsdyn.structure import Section, regular_frame

    sec = Section(2.1e11, 0.01, 1e-4, 80.0)
    args = {"name": "x", "bays": [6.0], "storey_heights": [3.0], "n_v": 2, "n_h": 2,
            "columns": sec, "beams": sec, **kw}  # fmt: skip
    with pytest.raises(ValueError, match=message):
        regular_frame(**args)
    with pytest.raises(ValueError, match=r"^E: expected a positive finite number, got '2e11'"):
        Section("2e11", 0.01, 1e-4, 80.0)


def test_modes_of_a_frame_without_mass_is_one_line(tmp_path, capsys):
    # a ZeroDivisionError from its isolation frequency
    from nsdyn.cli import main

    p = tmp_path / "f.toml"
    p.write_text(GOOD.replace("rho_A = 100.0", "rho_A = 0.0").replace("rho_A = 80.0",
                 "rho_A = 0.0").replace("floor_mass = 1000.0", "floor_mass = 0.0"))  # fmt: skip
    assert main(["modes", str(p), "--out", str(tmp_path / "o")]) == 2
    assert "has no mass (rho_A = 0 on every element and no node mass)" in capsys.readouterr().err


def test_a_node_of_the_wrong_size_is_named(tmp_path):
    # "frame.nodes: expected a list of >= 2 [x, y] pairs, got a list of 7" said not which
    from nsdyn.structure import load_frame3d

    root = Path(__file__).resolve().parents[2] / "frames"
    p = tmp_path / "p.toml"
    p.write_text((root / "portal.toml").read_text().replace("[3.0, 4.0],", "[3.0, 4.0, 0.0],"))
    with pytest.raises(FrameFileError, match=r"frame\.nodes\[4\]: expected a pair \[x, y\] of "
                       r"numbers \[m\], got \[3\.0, 4\.0, 0\.0\]$"):  # fmt: skip
        load_frame(p)
    text = (root / "portal-3d.toml").read_text()
    p.write_text(text.replace("[0.0, 0.0, 0.0], [6.0", "[0.0, 0.0], [6.0", 1))
    with pytest.raises(FrameFileError, match=r"frame3d\.nodes\[0\]: expected a triple \[x, y, z\]"):
        load_frame3d(p)
