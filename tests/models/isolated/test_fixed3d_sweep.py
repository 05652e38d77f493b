"""The fixed rung's steady harmonic response (frequency response of the space frame): against
the direct complex solve, the resonances at the fixed-base frequencies, the quasi-static
limit, the peak of an elliptical phasor."""

from __future__ import annotations

import numpy as np
import pytest

from nsdyn.models.isolated.fixed3d_sweep import fixed_frf, peak_radius
from nsdyn.structure import fixed_base_modes_3d, load_frame3d
from nsdyn.structure.storey3d import floor_motions, storey_drifts_3d

EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def portal():
    frame = load_frame3d("portal-3d")
    return frame, fixed_base_modes_3d(frame, n_modes=60)  # every mode of finite frequency


def _clamped(frame):
    K, M = frame.reduced()
    i = np.setdiff1d(np.arange(frame.n_red), frame.boundary_reduced)
    return K.toarray()[np.ix_(i, i)], M.toarray()[np.ix_(i, i)], i


def _outputs(frame, U):
    """Roof radius and largest corner drift of a reduced complex field U (real maps)."""
    S = frame.expand(np.column_stack([U.real, U.imag]))
    roof = floor_motions(frame, S)[2][-1] @ np.array([1.0, 1j])
    corner = storey_drifts_3d(frame, S).corner @ np.array([1.0, 1j])
    return float(peak_radius(roof[:2])), float(np.abs(corner).max())


def test_peak_radius_of_line_circle_ellipse():
    # a line of amplitude a, a circle of radius a, an ellipse of semi-axes a > b: radius a
    assert peak_radius(np.array([0.6, 0.8])) == pytest.approx(1.0, rel=4 * EPS)
    assert peak_radius(np.array([2.0, -2.0j])) == pytest.approx(2.0, rel=4 * EPS)
    c, s = np.cos(0.3), np.sin(0.3)  # semi-axes 3 along 0.3 rad, 1 across, 90° apart
    P = 3.0 * np.array([c, s]) + 1.0j * np.array([-s, c])
    assert peak_radius(P) == pytest.approx(3.0, rel=8 * EPS)


def test_equals_the_direct_complex_solve(portal):
    # U(Ω) = (K − Ω² M + iΩ C)⁻¹ (−M R A) with C = M Φ diag(2 ζ ω) Φᵀ M: with every mode of
    # finite frequency kept, the modes plus the static correction are exact (the rest of the
    # space is the null space of M: static); the two agree to the solve's round-off,
    # a few eps times the condition number of the dynamic matrix
    frame, modes = portal
    Kc, Mc, i = _clamped(frame)
    phi = modes.phi[i]
    w = 2 * np.pi * modes.f_hz
    zeta = frame.zeta[np.minimum(np.arange(len(w)), len(frame.zeta) - 1)]
    Cc = Mc @ phi @ np.diag(2 * zeta * w) @ phi.T @ Mc
    A = np.array([0.8, 0.6j, 0.3])
    R = frame.rigid_motions()[:, :3]
    _, M = frame.reduced()
    load = -(M @ (R @ A))[i]
    f = np.array([0.7, modes.f_hz[0], 4.0, modes.f_hz[1], modes.f_hz[2] * 1.01, 30.0])
    frf = fixed_frf(frame, A, f, modes=modes)
    for k, fk in enumerate(f):
        Om = 2 * np.pi * fk
        D = Kc - Om**2 * Mc + 1j * Om * Cc
        U = np.zeros(frame.n_red, complex)
        U[i] = np.linalg.solve(D, load)
        roof, corner = _outputs(frame, U)
        tol = 50 * np.linalg.cond(D) * EPS
        assert frf.roof_m[k] == pytest.approx(roof, rel=tol), fk
        assert frf.corner_drift[k] == pytest.approx(corner, rel=tol), fk


@pytest.mark.parametrize("direction", ["x", "y"])
def test_resonance_at_the_fixed_base_frequency(portal, direction):
    # excited along x (or y) the doubly symmetric portal answers in its x (y) family only:
    # the roof's amplitude peaks where |η| does, Ω = ω √(1 − 2ζ²) (relative displacement
    # under base acceleration), found on the grid within its resolution (one step)
    frame, modes = portal
    k = int(modes.of_family(direction)[0])
    A = np.array([1.0, 0.0, 0.0]) if direction == "x" else np.array([0.0, 1.0, 0.0])
    f = np.geomspace(1.0, 20.0, 3001)
    frf = fixed_frf(frame, A, f, modes=modes)
    j = int(np.argmax(frf.roof_m))
    zeta = frame.zeta[min(k, len(frame.zeta) - 1)]
    f_res = modes.f_hz[k] * np.sqrt(1 - 2 * zeta**2)
    step = f[1] / f[0] - 1
    assert abs(f[j] / f_res - 1) <= step, (f[j], f_res)
    assert 0 < j < f.size - 1


@pytest.mark.parametrize("n_modes", [2, 60])
def test_quasi_static_limit(portal, n_modes):
    # Ω = 0: the static response to the inertia load −M R A, for any number of kept modes
    # (the kept modes' static part and the correction add up to K⁻¹ load); against a dense
    # solve, to a few eps times cond(K)
    frame, modes = portal
    if n_modes < len(modes.f_hz):
        modes = fixed_base_modes_3d(frame, n_modes=n_modes)
    Kc, _, i = _clamped(frame)
    A = np.array([0.5, -0.3, 0.2])
    R = frame.rigid_motions()[:, :3]
    _, M = frame.reduced()
    U = np.zeros(frame.n_red, complex)
    U[i] = np.linalg.solve(Kc, -(M @ (R @ A))[i])
    roof, corner = _outputs(frame, U)
    frf = fixed_frf(frame, A, [0.0], modes=modes)
    tol = 50 * np.linalg.cond(Kc) * EPS
    assert frf.roof_m[0] == pytest.approx(roof, rel=tol)
    assert frf.corner_drift[0] == pytest.approx(corner, rel=tol)
    if n_modes == 2:  # without the correction the truncated modes miss part of it
        bare = fixed_frf(frame, A, [0.0], modes=modes, static_correction=False)
        assert abs(bare.corner_drift[0] / corner - 1) > 1e3 * tol


SCENE = """
[scene]
kind = "building3d"
[structure]
frame3d = "portal-3d"
fidelity = "fixed"
n_modes = 6
[motion]
kind = "{kind}"
{motion}
"""
ORBIT = 'orbit = "linear"\nfrequency = 2.0\namplitude = 0.5\nangle = 0.0\nt_end = 5.0'


def test_cli_sweep_of_a_fixed_building(tmp_path):
    # nsdyn sweep on a fixed building3d scene: the curves and the figure; excited along x the
    # roof peaks at the x family's resonance (within the grid's step); the response is linear
    # in the amplitude (each curve the other scaled, to the round-off of one product)
    import json

    from nsdyn.cli import main
    from nsdyn.studies.table import read_csv

    p = tmp_path / "fixed.toml"
    p.write_text(SCENE.format(kind="orbit", motion=ORBIT))
    out = tmp_path / "o"
    code = main(["sweep", str(p), "--out", str(out), "--amplitudes", "0.5,1.5", "--fmin", "1",
                 "--fmax", "10", "--points", "801", "--json"])  # fmt: skip
    assert code == 0
    rep = json.loads((out / "sweep.json").read_text())
    assert (out / "sweep.png").is_file()
    fx = next(m["f_hz"] for m in rep["modes"] if m["family"] == "x")
    step = 10 ** (1 / 800) - 1
    for s in rep["amplitudes"]:
        assert abs(s["f_at_roof_max_hz"] / fx - 1) <= step + 2 * 0.02**2
    rows = read_csv(out / "sweep.csv")
    a = np.array([r["roof_displacement_m"] for r in rows if r["A"] == 0.5])
    b = np.array([r["roof_displacement_m"] for r in rows if r["A"] == 1.5])
    assert np.allclose(b, 3 * a, rtol=4 * EPS, atol=0)
    # --no-figures removes the earlier figure (it stayed beside the new curves)
    code = main(["sweep", str(p), "--out", str(out), "--points", "3", "--no-figures", "--json"])
    assert code == 0 and not (out / "sweep.png").exists()


def test_cli_sweep_fidelity_flag_selects_the_fixed_rung_and_names_the_sweepable_ones(
    tmp_path, capsys
):
    # --fidelity fixed on a rigid scene is the fixed scene's sweep (the same table, exactly:
    # one model, one solve); cb is refused naming the field and the two rungs a sweep takes
    from nsdyn.cli import main
    from nsdyn.studies.table import read_csv

    fixed = tmp_path / "fixed.toml"
    fixed.write_text(SCENE.format(kind="orbit", motion=ORBIT))
    rigid = tmp_path / "rigid.toml"
    rigid.write_text(fixed.read_text().replace('fidelity = "fixed"', 'fidelity = "rigid"')
                     + '\n[bearing]\ntype = "fps"\nradius = 2.2\nmu = 0.05\n')  # fmt: skip
    argv = ["--amplitudes", "0.5", "--fmin", "1", "--fmax", "10", "--points", "41",
            "--no-figures", "--json"]  # fmt: skip
    assert main(["sweep", str(fixed), "--out", str(tmp_path / "a"), *argv]) == 0
    assert main(["sweep", str(rigid), "--fidelity", "fixed", "--out", str(tmp_path / "b"),
                 *argv]) == 0  # fmt: skip
    assert read_csv(tmp_path / "a" / "sweep.csv") == read_csv(tmp_path / "b" / "sweep.csv")
    capsys.readouterr()
    assert main(["sweep", str(rigid), "--fidelity", "cb", "--out", str(tmp_path / "c")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "structure.fidelity (--fidelity)" in err and "rigid" in err
    # the full rung with the law the sweep was given: it blamed the scene's switch law, which
    # --friction arctan had replaced, and not the rung the sweep cannot take
    assert main(["sweep", str(rigid), "--fidelity", "full", "--friction", "arctan", "--out",
                 str(tmp_path / "c")]) == 2  # fmt: skip
    err = capsys.readouterr().err.strip()
    assert "structure.fidelity (--fidelity): nsdyn sweep takes a building3d scene at the " in err


def test_cli_sweep_of_a_fixed_building_needs_an_orbit(tmp_path, capsys):
    from nsdyn.cli import main

    p = tmp_path / "rec.toml"
    p.write_text(SCENE.format(kind="record3", motion='record = "synthetic-wn-40s"'))
    assert main(["sweep", str(p), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and str(p) in err and "motion.kind" in err and "orbit" in err
    # the [motion] it suggests sweeps (the record scenes bundled had no sweep to try)
    example = err.split("e.g. [motion] ", 1)[1].split(" (its shape", 1)[0]
    p.write_text(SCENE.format(kind="orbit", motion=example.split(", ", 1)[1].replace(", ", "\n")))
    assert main(["sweep", str(p), "--out", str(tmp_path / "o"), "--points", "3",
                 "--no-figures"]) == 0  # fmt: skip


def test_n_modes_beyond_the_building_is_said_in_run_and_sweep(tmp_path, capsys):
    # the portal has 15 fixed-base dofs: 4 roof nodes' (uz, rx, ry) and the roof diaphragm's
    # (ux, uy, rz); n_modes = 500 used all 15 without a word (run and sweep alike)
    import json

    from nsdyn.cli import main

    text = SCENE.replace("n_modes = 6", "n_modes = 500")
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(text.format(kind="orbit", motion=ORBIT))
    out = tmp_path / "s"
    assert main(["sweep", str(sweep), "--out", str(out), "--points", "3", "--no-figures"]) == 0
    said = "structure.n_modes = 500 asks for more modes than the building has: all its 15 "
    assert said in capsys.readouterr().err
    rep = json.loads((out / "sweep.json").read_text())
    assert len(rep["modes"]) == 15 and rep["notes"][0].startswith(said)
    run = tmp_path / "run.toml"
    run.write_text(text.format(kind="record3", motion='record = "synthetic-wn-40s"\nt_end = 0.5'))
    out = tmp_path / "r"
    assert main(["run", str(run), "--out", str(out), "--no-figures", "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["n_modes"] == 15 and any(n.startswith(said) for n in s["notes"])
    # within the building's count, or the default 24 the scene did not give: no note
    for edit in ("n_modes = 15", ""):
        run.write_text(text.replace("n_modes = 500", edit).format(
            kind="record3", motion='record = "synthetic-wn-40s"\nt_end = 0.5'))  # fmt: skip
        assert main(["run", str(run), "--out", str(out), "--no-figures", "--json"]) == 0
        assert not any("n_modes" in n for n in json.loads(capsys.readouterr().out)["notes"])
