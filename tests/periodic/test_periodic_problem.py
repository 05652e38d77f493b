"""The isolated frame as a periodic problem: manifold equations, coordinates, uplift verdicts.

References are independent of the code under test: the constrained kernel (Lagrange
multipliers) projected on the contact manifold, the orthonormality of the null-space basis Q,
and an adaptive radau probe that checks every normal force.
"""

import numpy as np
import pytest

from nsdyn import periodic as pr
from nsdyn.models.isolated import _kernel as ks
from nsdyn.models.isolated.system import Isolation, build_system
from nsdyn.periodic import _kperiodic as kp
from nsdyn.periodic.curve import _point_from_sweep


@pytest.mark.parametrize(
    "iso",
    [
        Isolation(mu=0.1, eps=50.0),
        Isolation(),
        Isolation(frozen_normal=True),
        Isolation(mu=0.0, law="none"),
    ],
    ids=["arctan-soft", "arctan", "arctan-frozen", "none"],
)
def test_manifold_rhs_and_jacobian_equal_the_projected_constrained_kernel(frame, iso):
    # The shooting right-hand side (seed eq 27 with precomputed products) against the
    # constrained kernel (Lagrange multipliers, Baumgarte) evaluated at q = Q z and projected:
    # zdd = Q^T qdd, J_z = blockdiag(Q^T) J blockdiag(Q). Same equations: round-off agreement.
    s = build_system(frame, iso, fidelity="cb")
    prob = pr.frame_problem(s, 0.7)
    P, pf = prob.at(0.46)
    Q, m, n, d = s.Q, prob.m, s.n, prob.dim
    rng = np.random.default_rng(3)
    for _ in range(3):
        x = prob.x_ref + 1e-3 * rng.standard_normal(d)
        xf = np.concatenate([Q @ x[:m], Q @ x[m:]])
        of = np.empty(2 * n)
        Jf = np.empty((2 * n, 2 * n))
        ks.rhs(0.3, xf, P, of)
        ks.jac(0.3, xf, P, Jf)
        F_ref = np.concatenate([x[m:], Q.T @ of[n:]])
        B = np.zeros((2 * n, d))
        B[:n, :m] = Q
        B[n:, m:] = Q
        J_ref = B.T @ Jf @ B
        F = np.empty(d)
        J = np.empty((d, d))
        assert kp.j_eval(prob.prob, 0.3, x, pf, F, J)
        assert np.max(np.abs(F - F_ref)) < 1e-12 * np.max(np.abs(F_ref))
        assert np.max(np.abs(J - J_ref)) < 1e-12 * np.max(np.abs(J_ref))
        # the stage iterations' evaluation (flat array, no Jacobian): the same right-hand side
        Ff = np.empty(d)
        assert kp.f_eval(prob.prob, 0.3, x, pf, Ff)
        assert np.max(np.abs(Ff - F_ref)) < 1e-12 * np.max(np.abs(F_ref))


def test_minimal_and_full_states_round_trip(frame):
    # q = Q z with orthonormal Q (a null-space basis of R): Q^T Q = I, so to_minimal inverts
    # to_full exactly (round-off), and full states satisfy the contacts R q = 0, R qd = 0.
    prob = pr.frame_problem(build_system(frame, Isolation(), fidelity="cb"), 1.0)
    Z = np.random.default_rng(0).standard_normal((5, prob.dim))
    X = prob.to_full(Z)
    n = prob.Q.shape[0]
    R = prob.system.R
    assert np.allclose(prob.to_minimal(X), Z, rtol=0, atol=1e-13)
    assert np.abs(X[:, :n] @ R.T).max() < 1e-12 and np.abs(X[:, n:] @ R.T).max() < 1e-12
    assert np.allclose(prob.to_full(Z[0]), X[0], rtol=0, atol=0)


def test_point_whose_period_cannot_be_integrated_reports_its_uplift():
    # The office frame near f_bis (0.06 Hz): at A = 2 m/s^2 the fixed-step periods fail in the
    # stage Newton within the first periods, because a contact lifts off (its normal force
    # reaches zero; the radau probe, which checks every step, finds the instant); at
    # A = 0.5 m/s^2 the converged orbit keeps every normal force positive and the probe from
    # its start agrees. The point must carry that verdict, not "unknown".
    from nsdyn import bench

    system = build_system(bench.bench_frame(), bench.bench_isolation(), fidelity="cb", f_max=5.0)
    f = 0.06
    strong = pr.frame_problem(system, 2.0)
    sw = pr.steady_state_sweep(strong, f, strong.x_ref.copy(), monodromy=False)
    assert not sw.steady
    point = _point_from_sweep(strong, sw, "test")
    assert point.quantities["uplift"] is True
    assert "outside its validity" in point.note
    # the cause leads, without advice that more steps per period would cure it (they cannot:
    # the contact model itself no longer holds)
    assert point.note.startswith("uplift") and "try more steps" not in point.note
    t_up = float(point.note.split("uplift at t = ")[1].split()[0]) if sw.x_stop is not None \
        or sw.periods_done == 0 else None  # fmt: skip
    if sw.periods_done == 0:  # no period integrated: the probe names the instant
        assert 0.0 < t_up < 1.0 / f
    elif sw.x_stop is not None:  # a later period failed (how many passed before it is the
        # round-off's to decide): the probe runs from its start, where the contact may already
        # be open (t = 0)
        assert 0.0 <= t_up < 1.0 / f
    else:  # the period integrated (bilaterally) shows the negative normal force itself
        assert point.quantities["min_normal_force"] < 0.0
    weak = pr.frame_problem(system, 0.5)
    res = pr.shoot(weak, f, weak.x_ref.copy())
    assert res.converged
    q = pr.orbit_quantities(weak, f, res.X)
    assert q["min_normal_force"] > 0 and q["uplift"] is False
    assert pr.uplift_probe(weak, f, res.x0)[0] is False


def test_orbit_quantities_on_the_manifold_equal_the_general_kernel(frame, monkeypatch):
    # A smooth law's orbit is post-processed by the period map's own right-hand side on the
    # manifold (qdd = Q zdd, the contact forces its multipliers: a sweep compiles no kernel of
    # the full coordinates). The system kernel in full coordinates (Lagrange multipliers;
    # its Baumgarte terms vanish on the manifold) is an independent implementation of the
    # same equations: the same accelerations and forces, to round-off (1e-9 of the largest),
    # and the same quantities (1e-9 relative).
    from nsdyn.solve.transient import general_evaluations

    prob = pr.frame_problem(build_system(frame, Isolation(), fidelity="cb"), 0.7)
    f = 1.3
    res = pr.shoot(prob, f, prob.x_ref.copy())
    assert res.converged
    t = np.linspace(0.0, 1.0 / f, res.X.shape[0])
    P, _ = prob.at(f)

    def by_the_system_kernel(self, f, t, X):
        return general_evaluations(P, t, np.ascontiguousarray(self.to_full(X)))[:2]

    QDD, LAM = prob.orbit_forces(f, t, res.X)
    QDD_ref, LAM_ref = by_the_system_kernel(prob, f, t, res.X)
    assert np.abs(QDD - QDD_ref).max() <= 1e-9 * np.abs(QDD_ref).max()
    assert np.abs(LAM - LAM_ref).max() <= 1e-9 * np.abs(LAM_ref).max()
    manifold = pr.orbit_quantities(prob, f, res.X)
    monkeypatch.setattr(pr.PeriodicProblem, "orbit_forces", by_the_system_kernel)
    general = pr.orbit_quantities(prob, f, res.X)
    assert manifold.keys() == general.keys()
    for k, v in general.items():
        if isinstance(v, float):
            assert manifold[k] == pytest.approx(v, rel=1e-9, abs=1e-300), k
        else:
            assert manifold[k] == v, k


def test_steps_are_refined_only_where_no_contact_lifts_off(monkeypatch):
    # A point whose fixed-step period fails is retried with REFINE_FACTOR x the steps, unless
    # the radau probe (normal forces checked at every step) finds a contact lifting off within
    # WARMUP_PERIODS periods of the guess (as many as the warm start carries a guess along):
    # then the failure is the bilateral model's limit, which more steps cannot remove. Office
    # frame near f_bis at A = 2 m/s^2 (lift-off in the first period, see the test above) and
    # at A = 1 m/s^2 (lift-off in the second period only: the probe over one period finds
    # none), against A = 0.5 m/s^2 at 0.46 Hz, made to fail by an unreachable stage
    # tolerance (1e-20; no lift-off there).
    from nsdyn import bench
    from nsdyn.periodic import continuation as co
    from nsdyn.periodic.discretisation import REFINE_FACTOR, Discretisation
    from nsdyn.periodic.sweeps import WARMUP_PERIODS

    system = build_system(bench.bench_frame(), bench.bench_isolation(), fidelity="cb", f_max=5.0)
    calls = []
    refine = co.refined
    monkeypatch.setattr(co, "refined", lambda d, *a: calls.append(d) or refine(d, *a))
    f = 0.06
    strong = pr.frame_problem(system, 2.0)
    point, _ = co._solve_point(strong, f, [strong.x_ref.copy()], Discretisation(), 1e-6, 12, True)
    assert calls == []
    assert point.method == "sweep" and point.quantities["uplift"] is True
    assert f"not retried with {REFINE_FACTOR}x steps" in point.note
    # (from the start of the period that failed: the first, or a later one, as round-off
    # decides, whose start may already have the contact open, t = 0)
    assert 0.0 <= float(point.note.split("uplift at t = ")[1].split()[0].rstrip(")")) < 1.0 / f
    stiff = Discretisation(rtol=1e-20, atol=0.0)  # no period integrates: the probe decides
    later = pr.frame_problem(system, 1.0)
    assert pr.uplift_probe(later, f, later.x_ref.copy())[0] is False  # none in the first period
    point, _ = co._solve_point(later, f, [later.x_ref.copy()], stiff, 1e-6, 12, True)
    assert calls == []
    assert point.method == "sweep" and point.quantities["uplift"] is True
    assert f"not retried with {REFINE_FACTOR}x steps" in point.note
    t_up = float(point.note.split("uplift at t = ")[1].split()[0].rstrip(")"))
    assert 1.0 / f < t_up < WARMUP_PERIODS / f
    weak = pr.frame_problem(system, 0.5)
    point, _ = co._solve_point(weak, 0.46, [weak.x_ref.copy()], stiff, 1e-6, 12, True)
    assert len(calls) == 1
    assert f"with {REFINE_FACTOR}x steps:" in point.note
    assert f"no uplift over {WARMUP_PERIODS} periods" in point.note
    # the retry's failure does not advise more steps again: it says what is left
    retried = point.note.split(f"with {REFINE_FACTOR}x steps:")[1].split(";")[0]
    assert "try more steps" not in retried and "more steps did not help" in retried


@pytest.mark.parametrize("A", [2.0, 1.0], ids=["first-period", "second-period"])
def test_probe_lift_off_instant_is_where_a_full_coordinate_run_loses_contact(A):
    # The probe (SciPy's Radau on the minimal coordinates, rtol PROBE_RTOL) against an
    # independent integration: the compiled Radau loop in the full coordinates (Baumgarte
    # contacts, rtol 1e-6), continued past the lift-off (uplift="warn"). Its smallest normal
    # force must change sign within DT of the probe's instant: the probe's states are good to
    # ~PROBE_RTOL relative, so its normal forces to ~1e-4 of the static ~3.4e6 N (~350 N),
    # and near these crossings the force falls by ~5e5 N/s: ~1 ms; DT is ten times that.
    from nsdyn import bench
    from nsdyn.solve.integrate import UpliftWarning, solve
    from nsdyn.solve.transient import evaluations

    DT = 0.01
    system = build_system(bench.bench_frame(), bench.bench_isolation(), fidelity="cb", f_max=5.0)
    f = 0.06
    prob = pr.frame_problem(system, A)
    lifts, note = pr.uplift_probe(prob, f, prob.x_ref.copy(), 2)
    assert lifts is True
    t_up = float(note.split("uplift at t = ")[1].split()[0])
    assert (A == 1.0) == (t_up > 1.0 / f)  # A = 1 m/s^2 lifts off in the second period only
    P, _ = prob.at(f)
    t = np.array([0.0, t_up - DT, t_up + DT])
    with pytest.warns(UpliftWarning):
        sol = solve(P, prob.to_full(prob.x_ref.copy()), t, method="radau", uplift="warn")
    lam = evaluations(P, t, np.ascontiguousarray(sol.x))[1].min(axis=1)
    assert lam[0] > 0 and lam[1] > 0 and lam[2] < 0, lam


def _friction_oscillator(A: float):
    from nsdyn.models.isolated.builders import system_from_matrices

    iso = Isolation(k_lam=0.0, c=0.0, mu=0.3, law="arctan", eps=7500.0)
    osc = system_from_matrices([[1.0]], [[0.5]], [[(2 * np.pi) ** 2]], iso_dofs=[0],
                               influence=[1.0], isolation=iso, weight=iso.g,
                               levels=[[0]])  # fmt: skip
    return pr.frame_problem(osc, A)


def test_a_frame_stick_slip_orbit_says_its_stick_creeps_as_a_decks_does():
    # The frame's orbits gave no stick-slip note (the deck's named the arctan law's creep).
    # Exact bounds: a mass on friction mu = 0.3 sticks the whole period when the ground's
    # peak acceleration A is below 0.9 mu g (stuck, it needs a friction m |a_g| <= m A, and
    # the arctan law counts stick up to 90 % of mu m g, friction.STICK_UTILISATION), and
    # cannot stick the whole period above mu g; at 0.2 Hz, a fifth of its natural
    # frequency, A = 4 m/s² (1.36 mu g) slips and sticks in turn (a mass without its spring
    # would stick while |a_g| < mu g, 53 % of the period).
    from nsdyn.models.isolated.friction import stick_velocity

    stuck = pr.continue_sequential(_friction_oscillator(1.0), [0.2]).points[0]
    assert stuck.quantities["stick_fraction"] == 1.0 and stuck.quantities["stick_all_period"]
    assert "stick-slip" not in stuck.note
    # below STICK_SLIP_MIN a "stick" share is a reversal passing the law's stick band: no note
    from nsdyn.models.isolated.friction import STICK_SLIP_MIN, stick_slip_note

    assert stick_slip_note(0.5 * STICK_SLIP_MIN, "arctan") is None
    assert stick_slip_note(STICK_SLIP_MIN, "arctan").startswith("stick-slip orbit")
    p = pr.continue_sequential(_friction_oscillator(4.0), [0.2]).points[0]
    s = p.quantities["stick_fraction"]
    assert 0.0 < s < 1.0 and not p.quantities["stick_all_period"]
    v = stick_velocity("arctan", 7500.0)
    assert p.note == (f"stick-slip orbit (stick fraction {s:.3g}): under the arctan law its "
                      f"stick phases creep at up to {v:.2g} m/s (eps = 7500 s/m), and a small "
                      "orbit can differ from true stick's many times over (confirm with "
                      "--friction switch)")  # fmt: skip
