"""``nsdyn modes`` on a 3D frame file and the 3D mode-shape figure.

Sources: the command's contract (a 3D file is recognised by its [frame3d] table and listed
with mode families and effective-mass fractions, which sum to at most 1 per direction:
Σ_k Γ_k² = rᵀ M r over a complete mass-normalised basis), and the figure's contract (one
labelled 3D panel per mode).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from nsdyn.cli.app import main
from nsdyn.plot.frames3d import deformed_lines_3d, plot_mode_shapes_3d
from nsdyn.structure import fixed_base_modes_3d, load_frame3d


def test_modes_command_lists_families_of_a_3d_frame(capsys, tmp_path):
    assert main(["modes", "portal-3d", "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["kind"] == "3d" and s["n_dof"] == 48
    f = np.array(s["frequencies_hz"])
    assert np.all(np.diff(f) >= 0) and len(s["families"]) == len(f)
    assert {"x", "y", "torsion"} <= set(s["families"])
    frac = np.array(s["mass_fractions_x_y_theta"])
    assert np.all(frac.sum(axis=0) <= 1 + 1e-9)
    assert main(["modes", "portal-3d", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "torsion" in out and (tmp_path / "modes-portal-3d.png").stat().st_size > 0


def test_deformed_lines_follow_the_nodal_displacements():
    # Source: the shape functions interpolate: the drawn line ends at the displaced nodes.
    b = load_frame3d("portal-3d")
    m = fixed_base_modes_3d(b, n_modes=3)
    u = m.full()[:, 2]
    lines = deformed_lines_3d(b, u, scale=2.0)
    disp = u.reshape(-1, 6)[:, :3]
    for e, (i, j) in enumerate(b.elements):
        assert np.allclose(lines[e, 0], b.nodes[i] + 2.0 * disp[i], rtol=0, atol=1e-12)
        assert np.allclose(lines[e, -1], b.nodes[j] + 2.0 * disp[j], rtol=0, atol=1e-12)
    fig = plot_mode_shapes_3d(m, n=3)
    axes = fig.get_axes()
    assert len(axes) == 3 and all(a.name == "3d" for a in axes)
    assert axes[0].get_zlabel() == "z [m]" and "Hz" in axes[2].get_title()


def test_drawn_members_leave_the_nodes_at_the_nodal_rotations():
    # Source: θz = dv/dx and θy = −dw/dx (the element's bending planes): a beam along x with
    # vecxz = Z (e_y = Y, e_z = Z) given only an end rotation θ leaves that end with slope
    # dy/dx = θ (about z) or dz/dx = −θ (about y), to O(h) of the one-sided difference.
    b = load_frame3d("portal-3d")
    e = next(k for k, (i, j) in enumerate(b.elements) if b.nodes[j, 0] - b.nodes[i, 0] > 1)
    j = b.elements[e, 1]
    for comp, row, sign in ((5, 1, 1.0), (4, 2, -1.0)):
        u = np.zeros(b.n_dof)
        u[6 * j + comp] = 1e-3
        line = deformed_lines_3d(b, u, scale=1.0, n_sub=400)[e]
        slope = (line[-1, row] - line[-2, row]) / (line[-1, 0] - line[-2, 0])
        assert slope == pytest.approx(sign * 1e-3, rel=3 * 2 / 400)  # error ½|w''|h = 2θ/400


@pytest.mark.parametrize(
    ("scene", "message"),
    [
        # nsdyn run refuses these scenes; modes listed the plane frame or the 3D one as if fine
        ('[scene]\nkind = "building3d"\n[structure]\nframe3d = "office-11"\n',
         r"structure.frame3d: expected a 3D frame \(\[frame3d\]; bundled: office-11-3d"),
        ('[scene]\nframe = "portal-3d"\n[isolation]\nk_lam = 5e4\n',
         r"scene.frame: expected a plane frame \(a 3D frame is a building3d scene's"),
        # the missing file named by the scene's field, not alone
        ('[scene]\nkind = "building3d"\n[structure]\nframe3d = "nosuch3d.toml"\n',
         r"structure.frame3d: .*nosuch3d.toml: no such frame file"),
    ],
)  # fmt: skip
def test_modes_refuses_a_scene_as_run_does_naming_its_field(tmp_path, capsys, scene, message):
    import re

    p = tmp_path / "s.toml"
    p.write_text(scene)
    assert main(["modes", str(p), "--json"]) == 2
    err = json.loads(capsys.readouterr().out)["error"]
    assert re.match(rf"{re.escape(str(p))}: {message}", err), err


def test_modes_of_a_frame_without_mass_or_with_plane_flags_is_one_line(tmp_path, capsys):
    text = (Path(__file__).resolve().parents[2] / "frames" / "portal-3d.toml").read_text()
    text = text.replace("rho = 7850.0", "rho = 0.0").replace("6000.0", "0.0")
    text = text.replace("mass = 24000.0", "mass = 0.0").replace("inertia = ", "inertia = 0.0 #")
    p = tmp_path / "massless.toml"
    p.write_text(text)
    assert main(["modes", str(p), "--json"]) == 2  # (a traceback before)
    assert "no mode of finite frequency" in json.loads(capsys.readouterr().out)["error"]
    assert main(["modes", "portal-3d", "--klam", "5e4"]) == 2
    assert "--klam: the bearing stiffness of f_bis of a plane frame" in capsys.readouterr().err
    assert main(["modes", str(tmp_path)]) == 2
    assert "not a file (a folder?)" in capsys.readouterr().err


def test_a_frame_whose_members_have_no_mass_names_the_node_on_the_cb_rung(tmp_path, capsys):
    # the portal with rho = 0 keeps its floor and node masses (translations) and nothing on
    # its rotations: the cb rung was refused naming its internal matrix ("portal-3d cb-5Hz
    # (n=8).M: expected a positive definite mass matrix"); now the first such node
    root = Path(__file__).resolve().parents[2]
    frame = tmp_path / "bare.toml"
    frame.write_text((root / "frames" / "portal-3d.toml").read_text().replace(
        "rho = 7850.0", "rho = 0.0"))  # fmt: skip
    scene = (root / "examples" / "scenes" / "building3d-office-cb.toml").read_text()
    scene = re.sub(r"(?m)^frame3d = .*$", f'frame3d = "{frame}"', scene)
    p = tmp_path / "s.toml"
    p.write_text(scene)
    out = str(tmp_path / "o")
    assert main(["run", str(p), "--t-end", "0.2", "--no-figures", "--out", out]) == 2
    err = capsys.readouterr().err.strip()
    said = (r"s\.toml: structure: frame3d: nodes\[\d+\] \(z = 4 m\): every member there has "
            r"no mass \(a section's rho = 0\), so its rotations have none")  # fmt: skip
    assert re.search(said, err), err
