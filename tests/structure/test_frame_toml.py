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
    with pytest.raises(FrameFileError, match=r"p\.toml: frame\.elements: expected"):
        load_frame(p)
    p.write_text(text.replace("base_nodes = [0, 1]", "base_nodes = [0, 0]"))
    with pytest.raises(FrameFileError, match=r"frame\.base_nodes"):
        load_frame(p)
    p.write_text(text.replace("I = 2.313e-4", "I = -2.313e-4"))
    with pytest.raises(FrameFileError, match=r"frame\.sections\[1\]\.I"):
        load_frame(p)
