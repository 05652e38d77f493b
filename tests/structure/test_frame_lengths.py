"""A frame whose coordinates are in mm ran as a building of 4000 m storeys (the portal's first
mode at 2e-5 Hz, a roof drift of 0.83 m, said like any other run). An element longer than
LENGTH_PLAUSIBLE (200 m, past any building member) is an InputWarning naming the file and the
entry; so is a Young's modulus below any structural material's (E in MPa); every bundled
frame loads without either."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import pytest

from nsdyn._checks import InputWarning
from nsdyn.structure import bundled_frames, is_frame3d, load_frame, load_frame3d
from nsdyn.structure.geometry import LENGTH_PLAUSIBLE

FRAMES = Path(__file__).resolve().parents[2] / "frames"


def _in_mm(path: Path, out: Path, centre: str | None = None) -> Path:
    """The frame file with every node coordinate (and a diaphragm centre) times 1000."""
    text = path.read_text()
    head, rest = text.split("nodes = [", 1)
    nodes, tail = rest.split("]\n", 1) if "\n]" not in rest else rest.split("\n]", 1)
    scaled = re.sub(r"-?\d+\.\d+", lambda m: repr(1000.0 * float(m.group())), nodes)
    text = head + "nodes = [" + scaled + ("\n]" if "\n]" in rest else "]\n") + tail
    if centre:
        text = text.replace(centre, "centre = [3000.0, 2500.0]")
    out.write_text(text)
    return out


@pytest.mark.parametrize(
    ("name", "load", "entry", "length", "centre"),
    [
        ("portal.toml", load_frame, "frame.elements[2]", 3000, None),  # the 3 m half-beam
        ("portal-3d.toml", load_frame3d, "frame3d.members[1].elements[0]", 6000,
         "centre = [3.0, 2.5]"),  # the 6 m beam, named as the file names it
    ],
)  # fmt: skip
def test_a_frame_in_mm_is_named_by_file_and_entry(tmp_path, name, load, entry, length, centre):
    p = _in_mm(FRAMES / name, tmp_path / name, centre)
    with pytest.warns(InputWarning) as rec:
        load(p)
    (w,) = [w for w in rec if "long, past" in str(w.message)]  # said once
    head = f"{p}: {entry}: {length} m long, past the {LENGTH_PLAUSIBLE:g} m"
    assert str(w.message).startswith(head), str(w.message)
    assert w.filename == __file__


def test_every_bundled_frame_loads_without_a_length_or_modulus_note():
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        for name in bundled_frames():
            (load_frame3d if is_frame3d(name) else load_frame)(name)


@pytest.mark.parametrize(("name", "load"), [("portal.toml", load_frame),
                                            ("portal-3d.toml", load_frame3d)])  # fmt: skip
def test_a_modulus_in_mpa_is_noted_naming_the_file(tmp_path, name, load):
    # E = 2.1e5 (steel in MPa) ran the 3D portal as a building of a 305 s period, unsaid
    from nsdyn.structure.geometry import E_PLAUSIBLE

    p = tmp_path / name
    p.write_text((FRAMES / name).read_text().replace("E = 2.1e11", "E = 2.1e5"))
    with pytest.warns(InputWarning) as rec:
        load(p)
    said = [str(w.message) for w in rec if "below any structural material" in str(w.message)]
    table = "frame3d" if load is load_frame3d else "frame"  # named by the section it is in
    assert len(said) == 1 and said[0].startswith(f"{p}: {table}.sections[0]: E = 2.1e+05 Pa")
    assert 2.1e5 < E_PLAUSIBLE < 1e10  # (between the MPa value and timber's modulus)


def test_a_modulus_in_mpa_in_a_storeys_list_is_named_by_its_entry(tmp_path):
    p = tmp_path / "office.toml"
    text = (FRAMES / "office-11.toml").read_text()
    old = "[frame.columns]  # per storey, bottom up\nE = 2.1e11"
    assert old in text
    p.write_text(text.replace(old, old[:-10] + f"E = {[2.1e11, 2.1e5] + [2.1e11] * 9}"))
    with pytest.warns(InputWarning, match=rf"^{re.escape(str(p))}: frame.columns.E\[1\]: E = "):
        load_frame(p)


def test_a_near_massless_member_is_noted_and_a_massless_one_is_not(tmp_path):
    # "massless columns" as rho_A = 0.001 kg/m on 0.02 m² (0.05 kg/m³) gave a three-storey
    # frame modes of 1e5 Hz and a run that failed with a false uplift, unsaid; rho_A = 0 is
    # the massless member (refused by the cb and full rungs, naming the node)
    from nsdyn.structure.geometry import DENSITY_PLAUSIBLE

    text = (FRAMES / "portal.toml").read_text()
    light = tmp_path / "light.toml"
    light.write_text(re.sub(r"^rho_A = \S+", "rho_A = 0.001", text, count=1, flags=re.M))
    with pytest.warns(InputWarning, match=rf"^{re.escape(str(light))}: frame.sections\[0\]: "
                      r"rho_A = 0.001 kg/m over A = .* far below any structural"):  # fmt: skip
        load_frame(light)
    bare = tmp_path / "bare.toml"
    bare.write_text(re.sub(r"^rho_A = \S+", "rho_A = 0.0", text, flags=re.M))
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        load_frame(bare)
    assert 10.0 < DENSITY_PLAUSIBLE < 500.0  # (below timber's, the lightest member material)


@pytest.mark.parametrize(("name", "load", "table", "tonnes"),
                         [("office-11.toml", load_frame, "frame", 606.5),
                          ("office-11-3d.toml", load_frame3d, "frame3d", 2957.88)])  # fmt: skip
def test_floor_masses_in_tonnes_are_noted_naming_their_sum(tmp_path, name, load, table, tonnes):
    # the office's floor masses in tonnes (57.5 for 57 500 kg) ran a frame of its members'
    # mass alone, six times lighter (the plane office's floors: 606.5 t against its members'
    # 96.6 t), unsaid; below ADDED_MASS_PLAUSIBLE of the members' mass they are noted with
    # the sum of the file's floor masses (10 x 57.5 + 31.5 t in the plane, 10 x 283.08 + 127.08
    # t in 3D)
    from nsdyn.structure.geometry import ADDED_MASS_PLAUSIBLE

    text = (FRAMES / name).read_text()
    line = re.search(r"^floor_mass = \[(.*)\]$", text, flags=re.M)
    t = [float(v) / 1000 for v in line.group(1).split(",")]
    p = tmp_path / name
    p.write_text(text.replace(line.group(0), f"floor_mass = {t}"))
    assert sum(t) == pytest.approx(tonnes, rel=1e-12)
    with pytest.warns(InputWarning, match=rf"^{re.escape(str(p))}: {table}.node_mass: the "
                      rf".* sum to {tonnes:.4g} kg, 0\.\d+% of its members' own"):  # fmt: skip
        frame = load(p)
    members = float((frame.rho_A * frame.lengths).sum())
    assert sum(t) < ADDED_MASS_PLAUSIBLE * members < 1000 * sum(t)  # (kg: above it)
