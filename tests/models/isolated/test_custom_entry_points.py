"""Every public entry point takes a system built without a frame; bad input gets clear errors.

Physics is asserted where an entry point returns it cheaply: for a shear building driven at
a frequency high above its isolation frequency with large friction, the isolator sticks and
every method gives the same (linear) response; energy closes for every run.
"""

import json
import math

import numpy as np
import pytest

from nsdyn._checks import InputWarning
from nsdyn.ground.excitation import ForceTable, Harmonic, HarmonicForce
from nsdyn.models.isolated.builders import MatrixError, shear_building, system_from_matrices
from nsdyn.models.isolated.scene import load_scene
from nsdyn.models.isolated.system import Isolation
from nsdyn.models.scenefile import SceneError

SCENES = __import__("pathlib").Path(__file__).resolve().parents[3] / "examples" / "scenes"
ISO = Isolation(k_lam=2.0e5, c=2.0e4, mu=0.05, law="arctan", eps=500.0)


def building(**kw):
    iso = kw.pop("isolation", ISO)
    return shear_building(
        [2.0e4, 1.0e4, 1.0e4, 1.0e4], [2.0e7, 1.5e7, 1.0e7], 0.05, isolation=iso, **kw
    )


def run_entry(name, system, tmp_path):
    """Call one public entry point on ``system``; return a dict of numbers it produced."""
    from nsdyn.periodic import continue_sequential, frame_problem, frequency_response, shoot
    from nsdyn.solve.transient import simulate

    if name.startswith("simulate-"):
        method = name.split("-", 1)[1]
        kw = {"dt": 2e-3} if method in ("genalpha", "hht", "newmark") else {}
        s = system.with_isolation(law="switch") if method == "event" else system
        r = simulate(s, Harmonic(1.0, 0.8), method=method, n_periods=2, **kw)
        return {
            "x_iso": r.response.x_iso_max,
            "closure": r.response.energy["closure"],
            "summary": r.summary(),
        }
    if name == "shoot":
        r = shoot(frame_problem(system, 1.0), 0.8, np.zeros(2 * system.n))
        assert r.converged
        return {"x_iso": float(np.ptp(r.X[:, 0]) / 2)}
    if name == "continue_sequential":
        c = continue_sequential(frame_problem(system, 1.0), [0.6, 0.8])
        return {"x_iso": c.rows()[-1]["x_iso"]}
    if name == "frequency_response":
        c = frequency_response(system, 1.0, fmin=0.6, fmax=0.8, points=2)
        return {"x_iso": c.rows()[-1]["x_iso"]}
    if name == "metrics":
        from nsdyn.models.isolated.metrics import response
        from nsdyn.solve.integrate import solve

        P = system.params(Harmonic(1.0, 0.8))
        x0, _ = system.static_equilibrium()
        t = np.linspace(0.0, 2.5, 251)
        sol = solve(P, x0, t, rtol=1e-6)
        r = response(system, sol.t, sol.x, P)
        return {"x_iso": r.x_iso_max, "closure": r.energy["closure"], "summary": r.summary()}
    raise AssertionError(name)


ENTRIES = [f"simulate-{m}" for m in ("radau", "dopri5", "genalpha", "hht", "newmark", "event")]
ENTRIES += ["shoot", "continue_sequential", "frequency_response", "metrics"]


@pytest.mark.parametrize("entry", ENTRIES)
@pytest.mark.parametrize("kind", ["shear", "sdof"])
def test_entry_points_take_systems_without_a_frame(entry, kind, tmp_path):
    if kind == "shear":
        s = building(heights=3.0)
    else:  # the single mass on an isolator: no storeys, no heights
        s = shear_building([5.0e4], [], 0.0, isolation=ISO)
    out = run_entry(entry, s, tmp_path)
    assert math.isfinite(out["x_iso"]) and out["x_iso"] > 0
    if "closure" in out:
        assert out["closure"] < 2e-2  # energy balance of the run closes
    if "summary" in out:
        sm = out["summary"]
        json.dumps(sm)
        assert ("idr_max" in sm) == (kind == "shear")  # drift ratios need storeys and heights
        assert "min_normal_force_N" not in sm  # frozen normal force: no contacts


def test_sweep_runs_a_shear_scene(tmp_path):
    from nsdyn.studies.sweep import SweepSettings, sweep_amplitudes, write_csv

    cfg = load_scene(SCENES / "isolated-shear-3storey.toml")
    st = SweepSettings(fmin=0.5, fmax=1.0, points=3)
    res = sweep_amplitudes(cfg, [0.5], st, tmp_path, workers=1, quiet=True)
    assert res[0]["frame"] is None and len(res[0]["rows"]) == 3
    assert all(r["converged"] for r in res[0]["rows"])
    write_csv(tmp_path / "sweep.csv", res)


def test_cli_runs_both_example_scenes(tmp_path, capsys):
    from nsdyn.cli import main

    for name in ("isolated-shear-3storey.toml", "isolated-coulomb-force.toml"):
        assert (
            main(
                [
                    "run",
                    str(SCENES / name),
                    "--json",
                    "--out",
                    str(tmp_path),
                    "--t-end",
                    "2",
                    "--no-figures",
                ]
            )
            == 0
        )
        s = json.loads(capsys.readouterr().out)
        assert s["t_end_s"] == pytest.approx(2.0) and s["x_iso_max_m"] > 0
        assert s["excitation"].startswith("force" if "force" in name else "ground")


def test_advisor_needs_a_frame():
    from nsdyn.ground import read_motion
    from nsdyn.studies.advisor import advise

    with pytest.raises(ValueError, match="needs a frame"):
        advise(None, read_motion("synthetic-wn-40s"), isolation=ISO)


def test_harmonic_without_duration_is_refused():
    from nsdyn.solve.transient import simulate

    s = building()
    for exc in (Harmonic(1.0, 1.0), HarmonicForce(1e3, 1.0, dofs=[3])):
        with pytest.raises(ValueError, match="^t_end: .*no natural end.*t_end.*n_periods"):
            simulate(s, exc)
    # free vibration is named as such ("NoneType has no natural end")
    with pytest.raises(ValueError, match=r"^t_end: free vibration \(motion None\) has no natural"):
        simulate(s, None)
    r = simulate(s, HarmonicForce(1e3, 1.0, dofs=[3]), t_end=1.0)
    assert r.summary()["t_end_s"] == 1.0 and r.summary()["dt_out_s"] == pytest.approx(0.01)


def test_force_record_is_a_force_history():
    # A record applied as -m a(t) at every level equals the same record as ground motion
    # (the effective earthquake force), except for the absolute accelerations.
    from nsdyn.ground import read_motion
    from nsdyn.solve.transient import simulate

    s = building(heights=3.0)
    rec = read_motion("synthetic-wn-40s").window(0.0, 3.0).with_vertical(None)  # (not felt)
    m = np.diag(s.M)
    f = ForceTable.from_motion(rec, dofs=[0, 1, 2, 3], scale=-1.0, weights=m)
    a = simulate(s, rec, rtol=1e-8, atol=1e-11)
    b = simulate(s, f, rtol=1e-8, atol=1e-11)
    np.testing.assert_allclose(b.x, a.x, atol=1e-9 * np.max(np.abs(a.x)))
    # the same work input, whichever way the load enters (W_in = int qd^T b F dt)
    assert b.response.energy["input"] == pytest.approx(a.response.energy["input"], rel=1e-6)
    # ground motion adds u''_g to the floors' absolute accelerations, a force does not
    assert b.response.floor_acc_max != pytest.approx(a.response.floor_acc_max, rel=1e-3)


BAD = [
    ("not symmetric", dict(K=[[2.0, 1.0], [0.0, 2.0]]), "K: not symmetric"),
    ("M not positive definite", dict(M=[[1.0, 0.0], [0.0, -1.0]]), "M: expected positive def"),
    ("K indefinite", dict(K=[[1.0, 2.0], [2.0, 1.0]]), "K: expected positive semi-definite"),
    ("wrong shape", dict(C=np.zeros((3, 3))), r"C: expected shape \(2, 2\)"),
    ("not square", dict(M=np.ones((2, 3))), "M: expected a square matrix"),
    ("NaN", dict(C=[[0.0, np.nan], [np.nan, 0.0]]), r"C: entry \[0, 1\] is nan"),
    ("iso dof out of range", dict(iso_dofs=[2]), "iso_dofs: expected distinct dof indices"),
    ("influence shape", dict(influence=[1.0]), "influence: expected 2 finite values"),
    ("influence NaN", dict(influence=[1.0, np.nan]), r"influence: .*, got entry 1: nan$"),
    ("no normal force", dict(weight=None), "friction needs normal forces"),
]


@pytest.mark.parametrize("what, change, msg", BAD, ids=[b[0] for b in BAD])
def test_bad_matrices_are_named(what, change, msg):
    kw = dict(
        M=np.eye(2),
        C=np.zeros((2, 2)),
        K=np.array([[2.0, -1.0], [-1.0, 1.0]]),
        iso_dofs=[0],
        influence=[1.0, 1.0],
        weight=10.0,
        isolation=ISO,
    )
    kw.update(change)
    with pytest.raises(MatrixError, match=msg):
        system_from_matrices(kw.pop("M"), kw.pop("C"), kw.pop("K"), **kw)


def test_bad_shear_buildings_and_scenes(tmp_path):
    with pytest.raises(MatrixError, match="stiffnesses: expected len\\(masses\\) - 1 = 2"):
        shear_building([1.0, 1.0, 1.0], [1.0, 1.0, 1.0], 0.05, isolation=ISO)
    # text is refused naming its argument (NumPy read "1e5" as a number and failed on "abc"
    # with "could not convert string to float")
    for args, name in ((("abc", [2e7]), "masses"), ((["1e5", "1e5"], [2e7]), "masses"),
                       (([1e5, 1e5], ["x"]), "stiffnesses"), (([1e5, 1e5], [2e7], "5%"),
                       "damping_ratios")):  # fmt: skip
        args = args if len(args) == 3 else (*args, 0.05)
        with pytest.raises(MatrixError, match=f"^{name}: expected"):
            shear_building(*args, isolation=ISO)
    with pytest.raises(MatrixError, match="^heights: expected storey heights"):
        shear_building([1e5, 1e5], [2e7], 0.05, isolation=ISO, heights="3.0")
    # a name that is not text headed reports as a number, an empty one as nothing
    for name in (5, "", "  "):
        with pytest.raises(TypeError, match=r"^name: expected a label \(non-empty text\)"):
            shear_building([1e5, 1e5], [2e7], 0.05, isolation=ISO, name=name)

    good = (SCENES / "isolated-shear-3storey.toml").read_text()
    cases = [
        (
            good.replace("stiffnesses = [2.0e7, 1.5e7, 1.0e7]", "stiffnesses = [2.0e7]"),
            "structure.stiffnesses",
        ),
        (good.replace("k_lam = 2.0e5", ""), "isolation.k_lam: required"),
        (good.replace('kind = "shear"', 'kind = "sheer"'), "structure.kind"),
        (good.replace("heights = 3.0", "heigths = 3.0"), "did you mean 'heights'"),
        (good + '\n[force]\nkind = "harmonic"\n', "one excitation per scene"),
    ]
    for k, (text, msg) in enumerate(cases):
        p = tmp_path / f"bad{k}.toml"
        p.write_text(text)
        with pytest.raises(SceneError, match=msg) as e:
            from nsdyn.models.isolated.scene import build_scene

            build_scene(load_scene(p))
        assert str(p) in str(e.value)


def test_a_system_the_ground_cannot_move_is_said():
    # influence all zero horizontally: a record would leave the system at rest, unsaid
    with pytest.warns(InputWarning, match=r"^influence: all zero horizontally"):
        K = np.array([[2.0, -1.0], [-1.0, 1.0]])
        system_from_matrices(np.eye(2), np.zeros((2, 2)), K, iso_dofs=[0], influence=[0.0, 0.0],
                             weight=10.0, isolation=ISO)  # fmt: skip
