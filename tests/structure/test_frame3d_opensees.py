"""OpenSees export of a space frame (fixed base): the exported model's eigenvalues against nsdyn's.

Source: the exported script is an independent FE model of the same input (OpenSees'
elasticBeamColumn, geomTransf Linear, rigidDiaphragm with the Transformation handler, its
own assembly and ARPACK eigensolver), so its lowest fixed-base frequencies must equal
:func:`nsdyn.structure.fixed_base_modes_3d`'s for the same mass choice. Tolerance: 0.1 %
(the acceptance bound for an independent model of the same input; both assemble the same
K and M, so the observed agreement is at the eigensolvers' round-off, far inside it).
Tests that need OpenSees skip when openseespy does not import.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from nsdyn.cli.app import main
from nsdyn.models.isolated import opensees as osx
from nsdyn.models.isolated.opensees3d import export_opensees_3d, opensees_data_3d
from nsdyn.structure import (
    Diaphragm,
    Frame3D,
    Section3D,
    fixed_base_modes_3d,
    load_frame3d,
    regular_building_3d,
)

RTOL = 1e-3  # 0.1 %: module docstring


def _has_opensees() -> bool:
    try:
        osx.load_opensees()
    except osx.OpenSeesUnavailable:
        return False
    return True


needs_opensees = pytest.mark.skipif(
    not _has_opensees(), reason='openseespy does not import (pip install "nsdyn[opensees]")'
)

E, G = 2.1e11, 8.1e10
COL = Section3D(E, G, 1e-2, 2e-4, 9e-5, 3e-5, 80.0)  # I_y != I_z: the local axes matter
BEAM = Section3D(E, G, 8e-3, 3e-4, 2e-5, 1e-6, 65.0, rho_Ip=0.9)  # rho_Ip != rho_A J / A


def small_building(**kw) -> Frame3D:
    """2 x 1 bays, 3 storeys, an eccentric mass and columns turned 30 degrees in plan."""
    c, s = np.cos(np.pi / 6), np.sin(np.pi / 6)
    return regular_building_3d(
        "small",
        [5.0, 7.0],
        [6.0],
        [4.0, 3.5, 3.5],
        COL,
        BEAM,
        BEAM,
        n_v=2,
        n_h=2,
        floor_mass=[3e4, 3e4, 2e4],
        mass_offset=(0.8, -0.4),
        column_vecxz=(c, s, 0.0),
        **kw,
    )


def _compare(frame: Frame3D, mass: str, n: int, tmp_path) -> None:
    path = tmp_path / f"{frame.name}_{mass}.py"
    export_opensees_3d(frame, path, mass=mass, n_modes=n)
    mod = osx.load_script(path)
    f_ops = np.array(mod.eigen_frequencies(n))
    ref = fixed_base_modes_3d(frame, n_modes=n, lumped=mass == "lumped")
    assert len(f_ops) == len(ref.f_hz) == n
    assert f_ops == pytest.approx(ref.f_hz, rel=RTOL)
    # the script stores nsdyn's frequencies of the same solve: a fixed Lanczos start
    # (structure.reduction.lanczos_start) gives the same numbers on every call
    assert mod.DATA["nsdyn_f_hz"] == ref.f_hz.tolist()


@needs_opensees
@pytest.mark.parametrize("mass", ["consistent", "lumped"])
def test_portal_frequencies_equal_opensees(mass, tmp_path):
    _compare(load_frame3d("portal-3d"), mass, 6, tmp_path)


@needs_opensees
@pytest.mark.parametrize("mass", ["consistent", "lumped"])
def test_every_mode_of_the_portal_equals_opensees(mass, tmp_path):
    # all 15 free dofs carry mass (lumped: HRZ keeps rotational inertia): more modes than
    # ARPACK returns (fewer than N - 1), so the script solves densely
    frame = load_frame3d("portal-3d")
    n = frame.n_red - len(frame.boundary_reduced)
    _compare(frame, mass, n, tmp_path)


@needs_opensees
@pytest.mark.parametrize("mass", ["consistent", "lumped"])
def test_eccentric_building_with_turned_columns_equals_opensees(mass, tmp_path):
    # x, y and torsion coupled by the eccentric mass; columns with I_y != I_z turned 30° in
    # plan test the local axes (vecxz) and beams with rho_Ip != rho_A J / A the torsional mass
    b = small_building()
    modes = fixed_base_modes_3d(b, n_modes=9)
    assert {"x", "y", "torsion"} <= set(modes.family)
    _compare(b, mass, 9, tmp_path)


@needs_opensees
@pytest.mark.slow
def test_bundled_3d_office_first_nine_modes_equal_opensees(tmp_path):
    # x, y, torsion families, three each (docs/guide/frames-3d.md); 7200 dofs, ~30 s in OpenSees
    b = load_frame3d("office-11-3d")
    _compare(b, "consistent", 9, tmp_path)


def test_exported_data_keep_the_torsional_stiffness_and_put_nsdyns_torsional_mass():
    # Source: OpenSees 3.7's consistent torsional inertia is rho J'/A per length; the export
    # sets J' = A rho_Ip / rho_A and G' = G J / J', so G'J' = GJ and rho_A J'/A = rho_Ip.
    b = small_building()
    d = opensees_data_3d(b, n_modes=3)
    GJ = np.array(d["G"]) * np.array(d["J"])
    assert GJ == pytest.approx(b.G * b.J, rel=1e-14)
    inertia = np.array(d["rho_A"]) * np.array(d["J"]) / np.array(d["A"])
    assert inertia == pytest.approx(b.rho_Ip, rel=1e-14)
    # one transformation per distinct vecxz: the turned columns, the beams (both ways)
    assert len(d["transforms"]) == 2 and len(d["diaphragms"]) == 3


def test_a_torsional_mass_without_rho_a_is_refused_for_consistent_mass():
    nodes = np.array([[0.0, 0, 0], [0, 0, 3.0], [4.0, 0, 3.0], [4.0, 0, 0]])
    fr = Frame3D(
        "t", nodes, [[0, 1], [1, 2], [3, 2]], (0, 1.0, 0), E, G, 1e-2, 1e-4, 1e-4, 1e-4,
        [80.0, 0.0, 80.0], [1.0, 2.0, 1.0], 0.0, [0, 3], [0.05],
    )  # fmt: skip
    with pytest.raises(ValueError, match="element 1: torsional inertia .* mass='lumped'"):
        opensees_data_3d(fr, n_modes=2)
    assert opensees_data_3d(fr, mass="lumped", n_modes=2)["mass"] == "lumped"


def test_a_clamped_diaphragm_node_is_refused():
    b = load_frame3d("portal-3d")
    d = Diaphragm([0, 1, 2, 3], (3.0, 2.5), 1e3, 1e3)
    from dataclasses import replace

    with pytest.raises(ValueError, match="diaphragm 1 holds a base node"):
        opensees_data_3d(replace(b, diaphragms=(*b.diaphragms, d)), n_modes=2)


@needs_opensees
def test_cli_exports_a_3d_frame_and_the_script_prints_both_frequency_lists(tmp_path, capsys):
    out = tmp_path / "portal.py"
    assert main(["export", "opensees", "portal-3d", "-o", str(out), "--modes", "4", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["frame"] == "portal-3d" and info["n_diaphragms"] == 1 and info["n_nodes"] == 8
    run = subprocess.run(
        [sys.executable, str(out), "4"], capture_output=True, text=True, check=True, timeout=120
    )
    res = json.loads(run.stdout.strip().splitlines()[-1])
    assert np.abs(res["relative_difference"]).max() <= RTOL
    assert res["nsdyn_f_hz"] == pytest.approx(info["nsdyn_f_hz"], rel=1e-12)
    # N beyond the free dofs printed 0 Hz "modes"; --help and text were int()'s ValueError
    for arg, said in (("16", "N: expected 1 to 15 (the frame's free dofs), got 16"),
                      ("abc", "invalid int value: 'abc'")):  # fmt: skip
        p = subprocess.run([sys.executable, str(out), arg], capture_output=True, text=True,
                           timeout=120)  # fmt: skip
        assert p.returncode == 2 and said in p.stderr


def test_cli_names_a_bad_mode_count(tmp_path, capsys):
    # refused by the parser, as every count flag is (status 2, its "argument" form)
    argv = ["export", "opensees", "portal-3d", "-o", str(tmp_path / "p.py"), "--modes", "0"]
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 2
    assert "argument --modes: expected at least 1" in capsys.readouterr().err


def test_cli_says_when_a_frame_has_fewer_modes_than_asked(tmp_path, capsys):
    # the portal's 4 free nodes x 6 dofs less 3 per node tied to its diaphragm, plus the
    # diaphragm's own 3: 15 modes; 200 asked were cut to 15 without a word
    argv = ["export", "opensees", "portal-3d", "-o", str(tmp_path / "p.py"), "--modes", "200"]
    assert main(argv) == 0
    assert "note: --modes 200: portal-3d has 15 modes to list" in capsys.readouterr().err
    assert main([*argv[:-1], "15"]) == 0 and "note" not in capsys.readouterr().err
