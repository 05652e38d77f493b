"""Physics checks of the constrained isolated system (seed 004 eqs 1-15, 23-28).

Time integration here uses scipy's Radau on the kernel right-hand side: an integrator
independent of nsdyn's own, so these tests check the equations, not the integrators.
"""

import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from nsdyn import Harmonic, Table
from nsdyn.models.isolated import _kernel as ks
from nsdyn.models.isolated.statespace import demo_frame, fixed_base_statespace, linear_statespace
from nsdyn.models.isolated.system import Isolation, build_system

G = 9.81


@pytest.fixture(scope="module")
def frame():
    return demo_frame()


def scipy_run(P, x0, t_eval, rtol=1e-8, atol=1e-11):
    def f(t, x):
        out = np.empty_like(x)
        ks.rhs(t, x, P, out)
        return out

    def jac(t, x):
        J = np.empty((x.size, x.size))
        ks.jac(t, x, P, J)
        return J

    sol = solve_ivp(
        f, (t_eval[0], t_eval[-1]), x0, "Radau", t_eval=t_eval, jac=jac, rtol=rtol, atol=atol
    )
    assert sol.success, sol.message
    return sol.y.T


@pytest.mark.parametrize("fidelity", ["rigid", "cb", "full"])
def test_static_equilibrium_carries_the_weight(frame, fidelity):
    # Statics: the normal forces carry the whole weight, lam1 + lam2 = M_s g (to round-off),
    # and the symmetric frame shares it equally.
    s = build_system(frame, Isolation(), fidelity=fidelity, f_max=20.0)
    x0, lam = s.static_equilibrium()
    Ms = frame.total_mass
    assert lam.sum() == pytest.approx(Ms * G, rel=1e-10)
    assert lam[0] == pytest.approx(lam[1], rel=1e-9)
    # the static state is an equilibrium of the dynamic equations
    ev = s.evaluate(0.0, x0)
    assert np.max(np.abs(ev["qdd"])) < 1e-8 * G
    assert np.allclose(ev["lam"], lam, rtol=1e-9)


@pytest.mark.parametrize("fidelity", ["rigid", "cb"])
def test_static_equilibrium_without_isolator_springs_is_quiet(frame, fidelity):
    # k_lam = 0 leaves the base free sideways (friction holds it): a singular stiffness whose
    # gravity load is consistent. Its static state is the same equilibrium, found without
    # scipy's LinAlgWarning (two raw warning lines preceded every such run's table)
    import warnings

    s = build_system(frame, Isolation(k_lam=0.0), fidelity=fidelity, f_max=20.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        x0, lam = s.static_equilibrium()
    assert lam.sum() == pytest.approx(frame.total_mass * G, rel=1e-10)
    ev = s.evaluate(0.0, x0)
    assert np.max(np.abs(ev["qdd"])) < 1e-8 * G


def test_gamma_carries_total_mass(frame):
    # Gamma^T M Gamma = total mass for every fidelity with boundary coordinates (exact).
    for fid in ("rigid", "cb", "full"):
        s = build_system(frame, fidelity=fid, f_max=20.0)
        for k in range(2):
            g = s.Gamma[:, k]
            assert g @ s.M @ g == pytest.approx(frame.total_mass, rel=1e-12)


def test_rigid_isolation_frequency_is_eq28(frame):
    # Seed eq (28): f_bis = (1/2pi) sqrt(2 K_lam / M_s) for the rigid superstructure without
    # friction -- exact for the rigid model on the contact manifold.
    k_lam = 5.0e4
    s = build_system(frame, Isolation(k_lam=k_lam, mu=0.0, law="none"), fidelity="rigid")
    Q = s.Q
    w2 = np.linalg.eigvals(np.linalg.solve(Q.T @ s.M @ Q, Q.T @ s.K @ Q)).real
    f = np.sqrt(np.min(w2)) / (2 * np.pi)
    f_bis = np.sqrt(2 * k_lam / frame.total_mass) / (2 * np.pi)
    assert f == pytest.approx(f_bis, rel=1e-10)
    # The flexible frame's isolation mode is softer (springs in series), but close: the
    # superstructure is ~100x stiffer than the isolators.
    cb = build_system(frame, Isolation(k_lam=k_lam, mu=0.0, law="none"), fidelity="cb")
    Qc = cb.Q
    w2c = np.linalg.eigvals(np.linalg.solve(Qc.T @ cb.M @ Qc, Qc.T @ cb.K @ Qc)).real
    fc = np.sqrt(np.min(w2c)) / (2 * np.pi)
    assert f_bis * 0.97 < fc < f_bis


def test_frictionless_steady_state_matches_python_control(frame):
    # mu = 0: the isolated system is linear. Start on python-control's steady state for
    # u''_hor = A sin(w t) (plus the static gravity state) and integrate two periods with an
    # independent integrator: the kernel's equations must keep the solution on that orbit.
    # a softer base diaphragm keeps the boundary modes below 1 kHz so the reference
    # integration stays cheap; the check itself does not depend on it
    soft = Isolation(mu=0.0, law="none", diaphragm_EA=1e9, diaphragm_EI=1e9)
    s = build_system(frame, soft, fidelity="cb", f_max=20.0)
    A, f = 1.0, 1.5
    w = 2 * np.pi * f
    sys = linear_statespace(s)
    H = np.asarray(sys(1j * w)).reshape(-1)  # q / u''_hor
    x_static, _ = s.static_equilibrium()
    n = s.n
    x0 = x_static.copy()
    x0[:n] += A * H.imag
    x0[n:] += A * w * H.real
    t = np.linspace(0.0, 2.0 / f, 81)
    P = s.params(Harmonic(A, f))
    X = scipy_run(P, x0, t)
    q_ss = x_static[:n] + A * np.imag(np.outer(np.exp(1j * w * t), H))
    amp = A * np.max(np.abs(H))
    assert np.max(np.abs(X[:, :n] - q_ss)) < 1e-5 * amp


def test_baumgarte_decay_of_constraint_violation(frame):
    # Eq (13)-(14) with beta = 1: an initial violation g0 of R q = 0 decays as
    # g(t) = g0 (1 + alpha t) exp(-alpha t) (critically damped), independently of the loads.
    alpha = 2 * np.pi
    iso = Isolation(alpha=alpha, beta=1.0, diaphragm_EA=1e9, diaphragm_EI=1e9)
    s = build_system(frame, iso, fidelity="cb")
    x0, _ = s.static_equilibrium()
    g0 = 1e-3
    x0[: s.n] += s.R.T @ np.full(s.n_contacts, g0)
    t = np.linspace(0.0, 2.0, 41)
    X = scipy_run(s.params(Harmonic(0.5, 1.0)), x0, t)
    g = X[:, : s.n] @ s.R.T
    exact = g0 * (1 + alpha * t) * np.exp(-alpha * t)
    assert np.max(np.abs(g - exact[:, None])) < 1e-7 * g0


def _random_manifold_state(s, rng, v_scale=0.05):
    x0, _ = s.static_equilibrium()
    Q = s.Q
    z = Q.T @ x0[: s.n] + 1e-5 * rng.standard_normal(Q.shape[1])
    zd = v_scale * rng.standard_normal(Q.shape[1])
    return z, zd


@pytest.mark.parametrize("fidelity", ["rigid", "cb"])
@pytest.mark.parametrize("frozen", [False, True])
def test_minimal_coordinates_equal_seed_eq27(frame, fidelity, frozen):
    # Seed eqs (26)-(27), written out here independently with numpy, against the kernel's
    # Lagrange-multiplier form projected on the manifold (q = Q z).
    iso = Isolation(mu=0.1, eps=50.0, frozen_normal=frozen)
    s = build_system(frame, iso, fidelity=fidelity)
    rng = np.random.default_rng(1)
    _, lam_static = s.static_equilibrium()
    A, f, t = 2.0, 0.8, 0.37
    for _ in range(5):
        z, zd = _random_manifold_state(s, rng)
        Q, M, R, D = s.Q, s.M, s.R, s.D
        q, qd = Q @ z, Q @ zd
        ug = np.array([A * np.sin(2 * np.pi * f * t), G])
        h = -s.C @ qd - s.K @ q - M @ s.Gamma @ ug  # eq (9)
        sdir = (2 / np.pi) * np.arctan(iso.eps * (D @ qd))
        Minv = np.linalg.inv(M)
        if frozen:
            h = h - D.T @ (iso.mu * sdir * lam_static)
            S = np.zeros_like(R.T)
        else:
            S = D.T * (iso.mu * sdir)  # eq (12): column i is mu s_i at isolator i's slip dof
        lam = -np.linalg.solve(R @ Minv @ (R.T - S), R @ Minv @ h)  # eq (26)
        Mbar = Q.T @ M @ Q
        zdd_seed = np.linalg.solve(Mbar, Q.T @ (h - S @ lam))  # eq (25) with Q^T R^T = 0
        zdd = s.minimal_accelerations(t, z, zd, Harmonic(A, f))
        assert np.allclose(zdd, zdd_seed, rtol=1e-9, atol=1e-9 * np.abs(zdd_seed).max())
        # and the seed's compact eq (27)
        zdd27 = np.linalg.solve(
            Mbar,
            Q.T @ (np.eye(s.n) + S @ np.linalg.solve(R @ Minv @ (R.T - S), R @ Minv)) @ h,
        )
        assert np.allclose(zdd, zdd27, rtol=1e-9, atol=1e-9 * np.abs(zdd27).max())


def _fd_jacobian(P, t, x, h=1e-7):
    n = x.size
    J = np.zeros((n, n))
    for j in range(n):
        dx = h * max(1.0, abs(x[j]))
        xp, xm = x.copy(), x.copy()
        xp[j] += dx
        xm[j] -= dx
        fp, fm = np.empty(n), np.empty(n)
        ks.rhs(t, xp, P, fp)
        ks.rhs(t, xm, P, fm)
        J[:, j] = (fp - fm) / (2 * dx)
    return J


@pytest.mark.parametrize(
    "law,frozen,v_scale",
    [
        ("arctan", False, 0.05),
        ("arctan", True, 0.05),
        ("switch", False, 0.05),  # slipping
        ("switch", False, 0.0),  # in the band: stick or transition
        ("none", False, 0.05),
    ],
)
@pytest.mark.parametrize("fidelity", ["rigid", "cb"])
def test_analytic_jacobian_matches_finite_differences(frame, law, frozen, v_scale, fidelity):
    # Central differences (truncation O(h^2)) against the analytic Jacobian of the kernel.
    iso = Isolation(mu=0.2, eps=200.0, law=law, frozen_normal=frozen)
    s = build_system(frame, iso, fidelity=fidelity)
    P = s.params(Harmonic(1.0, 0.7))
    rng = np.random.default_rng(3)
    z, zd = _random_manifold_state(s, rng, v_scale)
    x = np.concatenate([s.Q @ z, s.Q @ zd])
    x[s.n :] += 1e-4 * rng.standard_normal(s.n) * (v_scale > 0)  # off-manifold too
    J = np.empty((x.size, x.size))
    ks.jac(0.3, x, P, J)
    Jfd = _fd_jacobian(P, 0.3, x)
    scale = np.abs(J).max()
    assert np.max(np.abs(J - Jfd)) < 1e-5 * scale


@pytest.mark.parametrize("law", ["arctan", "switch"])
def test_friction_dissipates(frame, law):
    # Friction opposes sliding: the friction power -tau_i v_i is never positive in slip, and
    # its magnitude never exceeds mu lam (Coulomb bound) for either law.
    iso = Isolation(mu=0.1, law=law, eps=7500.0)
    s = build_system(frame, iso, fidelity="cb")
    P = s.params(Harmonic(3.0, 0.5))
    rng = np.random.default_rng(5)
    n_checked = 0
    for _ in range(50):
        z, zd = _random_manifold_state(s, rng, v_scale=0.1)
        x = np.concatenate([s.Q @ z, s.Q @ zd])
        ev = s.evaluate(rng.uniform(0, 2), x, P=P)
        v = s.D @ x[s.n :]
        if np.any(ev["lam"] <= 0):  # uplift: outside the model's domain
            continue
        n_checked += 1
        # slip: outside the switch band (inside it, Leine's transition phase lets friction
        # oppose the applied force rather than the tiny velocity: power <= mu lam eta)
        slip = (ev["modes"] != 0) & (np.abs(v) > iso.eta)
        assert np.all(ev["tau"][slip] * v[slip] >= 0.0)
        assert np.all(ev["tau"] * v >= -iso.mu * ev["lam"] * iso.eta)
        assert np.all(np.abs(ev["tau"]) <= iso.mu * ev["lam"] * (1 + 1e-12))
    assert n_checked >= 25


def test_switch_stick_force_within_cone_and_transition_saturates(frame):
    # Leine's switch model in the band |v| <= eta: stick while |tau| <= mu lam, otherwise the
    # friction saturates at mu lam with the sign of the would-be stick force.
    s = build_system(frame, Isolation(mu=0.03, law="switch"), fidelity="rigid")
    x0, lam0 = s.static_equilibrium()
    Ms = frame.total_mass
    for a, expect_stick in [(0.1, True), (1.0, False)]:
        # constant ground acceleration a: stick needs a friction force Ms a (< or > mu Ms g)
        P = s.params(Table(0.0, 1.0, np.full(3, a), np.zeros(3)))
        ev = s.evaluate(0.5, x0, P=P)
        if expect_stick:
            assert np.all(ev["modes"] == 0)
            assert ev["tau"].sum() == pytest.approx(-Ms * a, rel=1e-9)
            assert np.all(np.abs(ev["tau"]) <= 0.03 * ev["lam"])
        else:
            assert np.all(ev["modes"] != 0)
            assert np.abs(ev["tau"]).sum() == pytest.approx(0.03 * Ms * G, rel=1e-9)
            # friction resists the inertial load: the block accelerates at -(a - mu g)
            assert ev["qdd"][0] == pytest.approx(-(a - 0.03 * G), rel=1e-9)


def test_arctan_creep_matches_estimate_and_switch_holds(frame):
    # A rigid block (no springs) under a constant ground acceleration a < mu g: the switch
    # model sticks forever, the arctan law creeps at the speed where friction balances the
    # load, v = tan(pi a / (2 mu g)) / eps (exact for constant load; the estimate in
    # ARCHITECTURE.md "arctan law").
    mu, a, eps = 0.3, 1.0, 7500.0
    t = np.linspace(0.0, 0.5, 11)
    motion = Table(0.0, 0.5, np.full(3, a), np.zeros(3))
    iso = Isolation(k_lam=0.0, c=0.0, mu=mu, eps=eps, law="arctan")
    s = build_system(frame, iso, fidelity="rigid")
    x0, _ = s.static_equilibrium()
    X = scipy_run(s.params(motion), x0, t)
    v_creep = -X[-1, s.n]  # the block creeps against the inertial load -Ms a
    assert v_creep == pytest.approx(np.tan(np.pi * a / (2 * mu * G)) / eps, rel=1e-6)
    sw = build_system(frame, Isolation(k_lam=0.0, c=0.0, mu=mu, law="switch"), fidelity="rigid")
    Xs = scipy_run(sw.params(motion), x0, t)
    assert np.max(np.abs(Xs[:, 0])) < 1e-12


def test_stuck_isolators_behave_as_fixed_base(frame):
    # Large mu, small excitation: the switch model never leaves stick and the isolated frame's
    # drift equals the fixed-base frame's. Not exactly: the base diaphragm (EA, EI finite)
    # lets the column feet rotate a little, so the agreement is set by its stiffness.
    iso = Isolation(mu=0.5, law="switch")
    s = build_system(frame, iso, fidelity="cb", f_max=20.0)
    fb = build_system(frame, fidelity="fixed", f_max=20.0)
    motion = Harmonic(0.3, 2.0)
    t = np.linspace(0.0, 3.0, 301)
    X = scipy_run(s.params(motion), s.static_equilibrium()[0], t)
    Xf = scipy_run(fb.params(motion), fb.static_equilibrium()[0], t)
    top = frame.column_joints[-1, 0]
    ux = 3 * top
    base_x = 3 * frame.base_nodes[0]
    drift_iso = X[:, : s.n] @ (s.T[ux] - s.T[base_x])
    drift_fix = Xf[:, : fb.n] @ fb.T[ux]
    P = s.params(motion)
    modes = [s.evaluate(tt, xx, P=P)["modes"] for tt, xx in zip(t[::10], X[::10], strict=True)]
    assert np.all(np.array(modes) == 0)
    slip = X[:, : s.n] @ s.D.T
    assert np.max(np.abs(slip - slip[0])) < 1e-9  # no sliding away from the static state
    err = np.max(np.abs(drift_iso - drift_fix)) / np.max(np.abs(drift_fix))
    assert err < 0.02


def test_fixed_base_statespace_matches_modal_model(frame):
    # The python-control fixed-base model has the fixed-base frequencies as its poles.
    fb = build_system(frame, fidelity="fixed", f_max=50.0)
    sys = fixed_base_statespace(fb)
    wn = np.sort(np.abs(np.asarray(sys.poles())))[::2]
    assert np.allclose(wn, np.sort(fb.info["omega"]), rtol=1e-8)


def test_office_frame_static_shares_and_isolation_frequency():
    # Seed 004: the symmetric office frame carries M_s g equally on its two isolators, and
    # its rigid-superstructure isolation frequency is eq (28), ~0.06 Hz (seed §6).
    from nsdyn.structure import load_frame

    office = load_frame("office-11")
    s = build_system(office, Isolation(), fidelity="cb", f_max=5.0)
    assert s.n == 13  # seed §2: 13 generalised dofs at f_max = 5 Hz
    _, lam = s.static_equilibrium()
    assert lam.sum() == pytest.approx(office.total_mass * G, rel=1e-10)
    assert lam[0] == pytest.approx(lam[1], rel=1e-9)
    r = build_system(office, Isolation(mu=0.0, law="none"), fidelity="rigid")
    Q = r.Q
    w2 = np.linalg.eigvals(np.linalg.solve(Q.T @ r.M @ Q, Q.T @ r.K @ Q)).real
    assert np.sqrt(w2.min()) / (2 * np.pi) == pytest.approx(0.060, abs=0.003)


@pytest.mark.parametrize("fidelity", ["rigid", "full", "cb"])
def test_a_new_law_keeps_the_model(frame, fidelity):
    # the event method's switch law on a rigid or full model (no cut-off: f_max None) raised
    # "f_max: expected a positive frequency"; the model is the one built with that law
    s = build_system(frame, Isolation(mu=0.05), fidelity=fidelity)
    sw = s.with_isolation(law="switch")
    direct = build_system(frame, Isolation(mu=0.05, law="switch"), fidelity=fidelity)
    assert sw.isolation.law == "switch" and sw.n == direct.n
    for name in ("M", "K", "C"):
        a, b = getattr(sw, name), getattr(direct, name)
        a, b = (a.toarray(), b.toarray()) if hasattr(a, "toarray") else (a, b)
        np.testing.assert_array_equal(a, b)


def test_a_rigid_superstructure_reports_no_drift(frame):
    # the rigid rung's storeys do not deform: its drifts are exactly 0 (they read 2.6e-18,
    # the round-off of its nodes' motion), while its isolators slide
    from nsdyn.ground import harmonic
    from nsdyn.solve.transient import simulate

    s = build_system(frame, Isolation(k_lam=5.0e4, mu=0.05, law="arctan"), fidelity="rigid")
    res = simulate(s, harmonic(3.0, 0.5, 2.0, 0.01), method="radau")
    r = res.response
    assert np.abs(r.x_iso).max() > 1e-3
    assert not r.drift_by_storey.any() and not r.idr_by_storey.any() and not r.top_drift.any()


@pytest.mark.parametrize("fidelity", ["rigid", "full"])
def test_a_cut_off_where_no_modes_are_cut_is_said(frame, fidelity):
    # f_max is the Craig-Bampton / modal cut-off of "cb" and "fixed"; the rigid deck and the
    # nodal full model cut no modes, so a finite one given there was silently unused
    from nsdyn._checks import InputWarning

    with pytest.warns(InputWarning, match=f"f_max = 12 Hz is not used: fidelity '{fidelity}'"):
        s = build_system(frame, fidelity=fidelity, f_max=12.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        plain = build_system(frame, fidelity=fidelity)  # default and inf: nothing to say
        build_system(frame, fidelity=fidelity, f_max=np.inf)
        build_system(frame, fidelity="cb", f_max=12.0)
    assert s.n == plain.n


def test_a_matrix_edited_after_the_build_is_refused_not_answered_from_the_old_one(frame):
    # the static state (normal forces: the friction's scale) is solved once from M, K, Gamma,
    # R; a mass doubled in place afterwards was answered with the old normal forces while
    # the run used the new mass. A copy or a pickle's round trip is the same model.
    import copy
    import pickle

    s = build_system(frame, Isolation(), fidelity="rigid")
    _, lam = s.static_equilibrium()
    assert lam.sum() == pytest.approx(s.total_mass * G, rel=1e-9)  # (vertical equilibrium)
    pickle.loads(pickle.dumps(s)).params()
    copy.deepcopy(s).static_equilibrium()
    s.M[:] *= 2.0
    with pytest.raises(ValueError, match=r"M was changed after the model was built"):
        s.static_equilibrium()
    s = build_system(frame, Isolation(), fidelity="cb")
    s.K = 1.01 * s.K
    with pytest.raises(ValueError, match=r"K was changed after the model was built"):
        s.params()
    # a copy by dataclasses.replace with another mass solves its own static state (it held
    # the first system's): the normal forces carry the new weight
    import dataclasses

    s = build_system(frame, Isolation(), fidelity="rigid")
    _, lam = s.static_equilibrium()
    _, lam2 = dataclasses.replace(s, M=2.0 * s.M).static_equilibrium()
    assert lam2.sum() == pytest.approx(2.0 * lam.sum(), rel=1e-9)
