"""Response metrics on exact displacement fields, and scene-file validation."""

import numpy as np
import pytest

from nsdyn.models.isolated import _kernel as ks
from nsdyn.models.isolated.metrics import response
from nsdyn.models.isolated.scene import SceneError, load_scene
from nsdyn.models.isolated.statespace import demo_frame
from nsdyn.models.isolated.system import Isolation, build_system, rigid_body_modes


def test_drift_of_a_rigid_rotation_is_the_angle():
    # Kinematics: a rigid rotation theta about the base has interstorey drift ratio |theta| in
    # every storey and roof drift -H theta (small-rotation field u_x = -y theta). The "full"
    # fidelity's T is square and invertible, so the field is represented exactly.
    frame = demo_frame()
    s = build_system(frame, Isolation(), fidelity="full")
    theta = 1e-3
    u = rigid_body_modes(frame)[:, 2] * theta
    q = np.linalg.solve(s.T, u)
    t = np.array([0.0, 0.1])
    X = np.zeros((2, 2 * s.n))
    X[:, : s.n] = q
    r = response(s, t, X, s.params(None))
    assert np.allclose(r.idr_by_storey, theta, rtol=1e-9)
    H = frame.level_heights[-1]
    assert np.allclose(r.top_drift, -H * theta, rtol=1e-9)


def test_drifts_and_floor_accelerations_follow_their_definitions():
    # Definitions on an arbitrary field (full fidelity, T square): storey drift = the largest
    # |u_x(joint above) - u_x(joint below)| over time and column lines, IDR = drift / storey
    # height, floor acceleration = the largest |qdd_x + u_g| over time and the level's nodes.
    # Exact up to round-off of the products (1e-12).
    from nsdyn.models.isolated.metrics import output_dofs

    frame = demo_frame()
    s = build_system(frame, Isolation(), fidelity="full")
    od = output_dofs(frame)
    rng = np.random.default_rng(7)
    nt = 5
    U = rng.normal(size=(nt, s.n))  # physical displacements and accelerations
    A = rng.normal(size=(nt, s.n))
    X = np.zeros((nt, 2 * s.n))
    X[:, : s.n] = np.linalg.solve(s.T, U.T).T
    QDD = np.linalg.solve(s.T, A.T).T
    t = np.linspace(0.0, 1.0, nt)
    nc, ni = s.n_contacts, s.n_isolators
    ev = (QDD, np.ones((nt, nc)), np.zeros((nt, ni)), np.zeros((nt, ni), dtype=np.int64))
    r = response(s, t, X, s.params(None), evaluated=ev)
    J = od["joints_x"]  # (levels, lines)
    drift = [np.abs(U[:, J[k + 1]] - U[:, J[k]]).max() for k in range(J.shape[0] - 1)]
    assert np.allclose(r.drift_by_storey, drift, rtol=1e-12, atol=0)
    assert np.allclose(r.idr_by_storey, np.array(drift) / od["heights"], rtol=1e-12, atol=0)
    acc = [np.abs(A[:, d]).max() for d in od["levels_x"]]  # no ground motion: u_g = 0
    assert np.allclose(r.floor_acc_by_level, acc, rtol=1e-12, atol=0)
    assert np.allclose(r.top_drift, U[:, J[-1, 0]] - U[:, J[0, 0]], rtol=1e-12, atol=1e-12)


def test_floor_acceleration_at_rest_is_ground_acceleration():
    # At the static state under a constant ground acceleration a with all isolators stuck
    # (switch model, large mu) the structure moves with the ground: absolute acceleration a.
    from nsdyn import Table

    frame = demo_frame()
    s = build_system(frame, Isolation(mu=0.5, law="switch"), fidelity="cb")
    a = 0.7
    P = s.params(Table(0.0, 1.0, np.full(4, a), np.zeros(4)))
    x0, _ = s.static_equilibrium()
    t = np.array([0.0, 1.0])
    X = np.vstack([x0, x0])
    r = response(s, t, X, P)
    # relative accelerations at rest only come from the elastic response to the sudden load
    qdd = np.empty(s.n)
    lam = np.empty(2)
    tau = np.empty(2)
    modes = np.empty(2, dtype=np.int64)
    ks.evaluate(0.5, x0, P, qdd, lam, tau, modes)
    assert np.all(modes == 0)
    # base level: stuck, so it moves with the ground exactly
    assert r.floor_acc_by_level[0] == pytest.approx(a, rel=1e-9)


def test_scene_errors_name_file_and_field(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[scene]\nfidelity = "medium"\n')
    with pytest.raises(SceneError, match=r"bad.toml: scene.fidelity: expected one of"):
        load_scene(bad)
    bad.write_text("[solver]\nrtol = -1\n")
    with pytest.raises(SceneError, match=r"solver.rtol: expected a positive number"):
        load_scene(bad)
    bad.write_text("[motion]\nrecrod = 'x'\n")
    with pytest.raises(SceneError, match=r"motion.recrod: unknown field"):
        load_scene(bad)
    bad.write_text("[isolation\n")
    with pytest.raises(SceneError, match="not valid TOML"):
        load_scene(bad)
    with pytest.raises(SceneError, match="no such scene file"):
        load_scene(tmp_path / "missing.toml")


def test_scene_atol_is_a_number_or_a_pair(tmp_path):
    ok = tmp_path / "ok.toml"
    ok.write_text("[solver]\natol = [1e-9, 1e-5]\n")
    assert load_scene(ok)["solver"]["atol"] == [1e-9, 1e-5]
    ok.write_text("[solver]\natol = 1e-7\n")
    assert load_scene(ok)["solver"]["atol"] == 1e-7
    for bad in ("[1e-8, 1e-4, 1e-3]", "[1e-8, -1.0]", "'tight'", "[]"):
        ok.write_text(f"[solver]\natol = {bad}\n")
        with pytest.raises(SceneError, match=r"ok.toml: solver.atol: expected a positive number"):
            load_scene(ok)
