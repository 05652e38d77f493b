"""The full-order model in nodal coordinates and its sparse path (nsdyn.solve.fullorder).

The nodal model is the Craig-Bampton model with every mode in another basis (exact in exact
arithmetic), its low-rank modal damping is the ladder's dense modal damping, and the sparse
factor-once run (SuperLU, Woodbury for the low-rank damping, numba triangular solves) solves the
same generalized-alpha equations as the dense backend of the same model.
"""

from dataclasses import replace

import numpy as np
import pytest
import scipy.sparse as sp

from nsdyn.models.isolated.fullorder import DENSE_MAX_DOF
from nsdyn.models.isolated.statespace import demo_frame
from nsdyn.models.isolated.system import Isolation, build_system
from nsdyn.solve import _kgenalpha, fullorder, sparse
from nsdyn.solve.transient import simulate

EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def frame():
    return demo_frame()


@pytest.fixture(scope="module")
def models(frame):
    iso = Isolation(mu=0.05, eps=200.0)
    return build_system(frame, iso, fidelity="full"), build_system(
        frame, iso, fidelity="cb", f_max=np.inf
    )


def test_nodal_model_is_the_craig_bampton_model_with_every_mode(frame, models):
    # The Craig-Bampton basis T at f_max = inf is square and invertible, so T^T A T of the
    # nodal M, K*, C* must equal the ladder's reduced matrices: the same FE model, and the
    # low-rank damping A diag(2 zeta omega) A^T on every mode equals the dense modal damping
    # diag(2 zeta omega) on eta. Round-off: the constraint modes Psi = -K_ii^-1 K_ib carry
    # a relative error <= n eps cond(K_ii) (backward-stable solve), every product of length n
    # adds n eps; the bound below takes 10 n eps cond(K_ii) relative to the largest entry.
    full, cb = models
    n = full.n
    b = np.asarray(frame.boundary_dofs)
    i = np.setdiff1d(np.arange(n), b)
    K, _ = frame.assemble(sparse=False)
    bound = 10 * n * EPS * np.linalg.cond(K[np.ix_(i, i)])
    T = cb.T
    for name in ("M", "K", "C"):
        A, B = getattr(full, name), getattr(cb, name)
        err = np.abs(T.T @ A @ T - B).max() / np.abs(B).max()
        assert err <= bound, (name, err, bound)


def test_modal_damping_does_not_damp_rigid_motion(frame, models):
    # Zero on rigid motion (sliding is damped by the isolators' dampers only): A^T r =
    # Phi^T M_ii (r_i - Psi r_b) = 0 since Psi r_b = r_i (K r = 0). Bound: the products of
    # length n on entries of size |A|^T |r| and the Psi solve's n eps cond(K_ii).
    full, _ = models
    mo = full.sparse
    r = frame.influence()
    n = full.n
    i = np.setdiff1d(np.arange(n), frame.boundary_dofs)
    K, _ = frame.assemble(sparse=False)
    scale = np.abs(mo.U).T @ np.abs(r)
    bound = 10 * n * EPS * np.linalg.cond(K[np.ix_(i, i)]) * scale
    assert np.all(np.abs(mo.U.T @ r) <= bound)


def _run(P, x0, t, ops=None, backend="dense"):
    coef = _kgenalpha.parameters(_kgenalpha.FAMILY_GENALPHA, 0.8)
    return sparse.integrate(P, x0, t, 0.005, coef=coef, ops=ops, backend=backend)


def test_sparse_path_equals_the_dense_backend(models):
    # Same scheme, same equations: the sparse operators (SuperLU with the low-rank damping by
    # Woodbury) and the dense backend (dense LU of M^-1 S) differ by round-off only. Each step
    # solves to the friction Newton's tolerance 1e-12 (relative); over the steps the
    # difference stays below 1e-9 of the displacements' (velocities') largest value: the
    # round-off of one coordinate spreads to the others through the coupled dynamics, so the
    # measure is normwise over each half of the state.
    from nsdyn.ground import Harmonic

    full, _ = models
    g = Harmonic(3.0, 1.0)
    x0, _ = full.static_equilibrium()
    t = np.linspace(0.0, 1.0, 101)
    stats_d, _, Xd, _ = _run(full.params(g), x0, t)
    stats_s, _, Xs, _ = _run(full.params(g, stub=True), x0, t, ops=fullorder.full_ops(full))
    assert stats_d[0] == 0 and stats_s[0] == 0
    n = full.n
    for half in (slice(0, n), slice(n, 2 * n)):
        assert np.abs(Xs[:, half] - Xd[:, half]).max() <= 1e-9 * np.abs(Xd[:, half]).max()


def test_every_mode_damped_steps_on_the_dense_copies(frame, models):
    # The rule of fullorder.dense_step: with every fixed-interface mode damped (m ~ n) the
    # sparse step's low-rank products (4 n m + 6 m^2 flops) reach the dense solves (2 n^2),
    # so a model with dense copies steps on them (the test above: the same histories to 1e-9);
    # beta K damping (m = 0) keeps the sparse step. The reason line says which.
    from nsdyn.ground import Harmonic

    full, _ = models
    assert full.sparse.U.shape[1] > fullorder.DENSE_STEP_RANK * full.n
    assert fullorder.dense_step(full).startswith("dense: modal damping of rank")
    stiff = build_system(frame, Isolation(mu=0.05, eps=200.0), fidelity="full", damping="stiffness")
    assert not fullorder.dense_step(stiff)
    # a damping matrix put in place of the model's own counts by its nonzeros
    full_c = replace(full, C=2.0 * full.C, info=dict(full.info))  # modal: every entry
    assert fullorder.dense_step(full_c).startswith("dense: a damping matrix")
    banded = replace(stiff, C=2.0 * stiff.C, info=dict(stiff.info))  # beta K: banded
    assert not fullorder.dense_step(banded)
    r = simulate(full, Harmonic(3.0, 1.0), t_end=0.2)
    assert r.method == "genalpha-lowrank" and "dense: modal damping of rank" in r.method_reason
    assert "sparse" in simulate(stiff, Harmonic(3.0, 1.0), t_end=0.2).method_reason


def test_sparse_evaluations_equal_the_kernel(models):
    # Accelerations, normal forces and friction forces along a history, from the sparse
    # operators and from the dense kernel (ks.evaluate_many): the same constrained equations
    # solved with two factorisations. Round-off of a solve with M: n eps cond(M) relative.
    from nsdyn.ground import Harmonic
    from nsdyn.models.isolated import _kernel as ks

    full, _ = models
    g = Harmonic(3.0, 1.0)
    rng = np.random.default_rng(3)
    x0, _ = full.static_equilibrium()
    X = x0 + 1e-3 * rng.normal(size=(6, x0.size))
    t = np.linspace(0.0, 0.5, 6)
    P = full.params(g)
    out = [np.empty((6, k)) for k in (full.n, full.n_contacts, full.n_isolators)]
    ks.evaluate_many(t, X, P, *out, np.empty((6, full.n_isolators), np.int64))
    got = fullorder.full_ops(full).evaluate(full.params(g, stub=True), t, X)
    bound = 10 * full.n * EPS * np.linalg.cond(full.M)
    for a, b in zip(got[:3], out, strict=True):
        assert np.abs(a - b).max() <= bound * np.abs(b).max()


def test_replaced_damping_is_not_the_sparse_model(models):
    # A copy with other damping (e.g. the OpenSees export's) must run with its own C, not
    # the sparse model's: the operators then come from the copy's matrices.
    full, _ = models
    other = replace(full, C=2.0 * full.C, info=dict(full.info))
    ops = fullorder.full_ops(other)
    assert np.allclose(ops.model.damp(np.eye(full.n)[:, :3]), 2.0 * full.C[:, :3])


def test_large_model_stays_sparse():
    # Above DENSE_MAX_DOF the model holds no dense n x n array: M, K* sparse, T the sparse
    # identity, the dense kernels refused with a message naming the sparse method, and a run
    # carries the weight (statics: lam sum = total weight, exact to round-off).
    from nsdyn.bench.scale import scale_frame
    from nsdyn.ground import Harmonic

    frame = scale_frame(2, 10, 10)  # 1 593 dofs: below; refine the mesh to pass the limit
    frame = scale_frame(3, 12, 12) if frame.n_dof <= DENSE_MAX_DOF else frame
    assert frame.n_dof > DENSE_MAX_DOF
    s = build_system(frame, Isolation(), fidelity="full", damping="stiffness")
    assert sp.issparse(s.M) and sp.issparse(s.K) and sp.issparse(s.T)
    with pytest.raises(ValueError, match="genalpha-lowrank"):
        s.params(None)
    # under the switch law no method runs it at this size: the advice says so (it named
    # 'auto' and 'genalpha-lowrank', which had just refused the switch law)
    with pytest.raises(ValueError, match=r"dense kernels .*the sparse 'genalpha-lowrank' runs "
                       r"only the arctan or no friction law.*the cb fidelity"):  # fmt: skip
        s.with_isolation(law="switch").params(None)
    # the same advice where the run asks for lift-off, or for the switch law on the sparse
    # method (with or without its step): it said "use method 'auto' or 'genalpha-lowrank'",
    # "use 'radau', 'genalpha' or 'event'" (each refusing the model), or "needs a fixed step"
    advice = r"dense kernels .*the sparse 'genalpha-lowrank' runs only .*the cb fidelity"
    g = Harmonic(1.0, 1.0)
    switch, sparse = s.with_isolation(law="switch"), dict(method="genalpha-lowrank")
    for system, kw in ((s, dict(contact="unilateral")),
                       (s, dict(contact="unilateral", **sparse, dt=0.005)),
                       (switch, sparse), (switch, dict(sparse, dt=0.005))):  # fmt: skip
        with pytest.raises(ValueError, match=advice):
            simulate(system, g, t_end=0.05, **kw)
    _, lam = s.static_equilibrium()
    assert lam.sum() == pytest.approx(frame.total_mass * s.isolation.g, rel=1e-9)
    r = simulate(s, g, t_end=0.05)
    assert r.method == "genalpha-lowrank" and "full-order" in r.method_reason
    assert np.isfinite(r.response.x_iso_max)
    given = simulate(s, g, t_end=0.05, method="genalpha-lowrank", dt=0.005)  # which operators
    said = f"given: 'genalpha-lowrank' (full-order model, {s.n} dofs, sparse)"
    assert given.method_reason == said


def test_a_sparse_run_in_chunks_carries_the_scheme_s_acceleration(frame, monkeypatch):
    # A chunk continues with generalized-α's own a_n (not q̈(t_n), which departed from the
    # run in one piece by O(h²) at the chunk's first step): its first step after the boundary
    # is the same step up to the friction Newton's guess, which converges to a relative
    # NEWTON_RTOL in the friction forces, a part of the state's change.
    from nsdyn.ground import Harmonic
    from nsdyn.solve import _klowrank, checkpoint

    s = build_system(frame, Isolation(mu=0.05, eps=200.0), fidelity="full", damping="stiffness")
    kw = dict(t_end=0.3, dt_out=0.005)
    g = Harmonic(3.0, 1.0)
    one = simulate(s, g, chunk_s=1e9, **kw)
    two = simulate(s, g, chunk_s=0.2, **kw)
    k = int(np.searchsorted(one.t, 0.2))
    assert two.method == "genalpha-lowrank" and np.array_equal(one.x[: k + 1], two.x[: k + 1])
    bound = _klowrank.NEWTON_RTOL * np.abs(one.x[k + 1]).max()
    assert np.abs(two.x[k + 1] - one.x[k + 1]).max() <= bound
    take = checkpoint.Carry.take

    def forgetful(self, *args, **kw):
        take(self, *args, **kw)
        self.acc = None

    monkeypatch.setattr(checkpoint.Carry, "take", forgetful)
    restarted = simulate(s, g, chunk_s=0.2, **kw)
    assert np.abs(restarted.x[k + 1] - one.x[k + 1]).max() > 1e3 * bound


def test_a_sparse_run_reports_each_chunk_and_resumes_as_the_same_run(frame, tmp_path):
    # The sparse path runs in chunks of chunk_s as the dense path does: progress after each,
    # and a run interrupted after a chunk resumes from its checkpoint as the same run (each
    # chunk starts from the state the last ended in, the factorisation is the same), so its
    # histories equal the uninterrupted run's bit for bit. The checkpoint's key holds the
    # operators: a model with other damping does not continue it.
    from nsdyn.atomic import CheckpointError
    from nsdyn.ground import Harmonic

    s = build_system(frame, Isolation(mu=0.05, eps=200.0), fidelity="full", damping="stiffness")
    assert "sparse" in simulate(s, Harmonic(3.0, 1.0), t_end=0.05).method_reason
    kw = dict(t_end=0.6, dt_out=0.01, chunk_s=0.2)
    g = Harmonic(3.0, 1.0)
    seen = []
    whole = simulate(s, g, progress=lambda t, t_end, w: seen.append((t, t_end)), **kw)
    np.testing.assert_allclose(seen, [(0.2, 0.6), (0.4, 0.6), (0.6, 0.6)], rtol=1e-12)

    class Stop(Exception):
        pass

    def stop_after_one(t, t_end, wall):
        raise Stop

    ck = tmp_path / "ck.npz"
    with pytest.raises(Stop):
        simulate(s, g, checkpoint=ck, progress=stop_after_one, **kw)
    resumed = simulate(s, g, checkpoint=ck, **kw)
    assert np.array_equal(resumed.t, whole.t) and np.array_equal(resumed.x, whole.x)
    assert resumed.n_steps == whole.n_steps == 120 and resumed.stats == whole.stats
    other = replace(s, C=2.0 * s.C, info=dict(s.info))
    with pytest.raises(CheckpointError, match="written by another run"):
        simulate(other, g, checkpoint=ck, method="genalpha-lowrank", dt=0.005, **kw)


def test_metrics_of_a_full_model_on_its_sparse_operators_equal_the_dense_products(frame):
    # the metrics read a full model's damping power through its sparse operators and its
    # output rows (single dofs) as CSR: the dense products were 3x the run's integration at
    # 1 593 dofs. The rows are the same rows; the damping power's sums differ by round-off
    # (each output's qd C qd summed in another order: a few eps of its size, n terms)
    from nsdyn.ground.excitation import Harmonic
    from nsdyn.models.isolated import metrics

    s = build_system(frame, Isolation(mu=0.05, eps=200.0), fidelity="full", damping="stiffness")
    assert isinstance(s.C, np.ndarray) and s.sparse is not None  # a dense copy and operators
    exc = Harmonic(3.0, 1.0)
    r = simulate(s, exc, t_end=0.5, method="genalpha-lowrank", dt=0.005)
    P = s.params(exc)
    _, LAM, TAU, _ = metrics.evaluate_along(metrics.ks.evaluate_many, P, r.t, r.x)
    G = metrics.ground_many(r.t, P)
    fast = metrics.energy_balance(s, r.t, r.x, P, LAM, TAU, G)
    dense = replace(s, info={**s.info, "_C_of_sparse": None})  # its dense copy of C
    slow = metrics.energy_balance(dense, r.t, r.x, P, LAM, TAU, G)
    bound = 4 * EPS * s.n * abs(slow["viscous"])
    assert slow["viscous"] > 0 and abs(fast["viscous"] - slow["viscous"]) <= bound
    od = metrics.output_rows(s)
    L, _ = metrics.level_rows(od)
    assert sp.issparse(L)
    np.testing.assert_array_equal(
        L.toarray(), np.concatenate([np.asarray(x) for x in od["levels"]])
    )
