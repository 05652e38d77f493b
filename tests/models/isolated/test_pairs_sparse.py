"""The full 3D rung on sparse operators: generalized-α with the isolator rows as a Schur update.

References (independent of the sparse path):
- the dense kernel of the same equations: :func:`simulate_pairs` (Radau IIA, adaptive, at
  rtol 1e-10) on the same system made dense (``to_pairs``), and on the Craig–Bampton "full"
  rung of :func:`building_pairs` (every fixed-interface mode: the same model in another basis,
  its damping diag(0, 2ζω) the nodal model's low-rank term exactly);
- generalized-α is second order (Chung & Hulbert 1993): on a smooth run (harmonic orbit, the
  regularised law at a moderate ε) the error against the reference falls as h², so halving h
  divides it by 4 (observed order within 2 ± 0.3, the pre-asymptotic spread of three
  halvings);
- symmetry: a plan-symmetric building under x-only excitation has no y or torsional motion;
  the only source is round-off, bounded by N_steps · eps · κ(S) · max|x| (each step's solve
  with S = (1 − a_m) M + c₁ K + c₂ C* perturbs the state by at most eps κ(S) relative, and a
  damped stable scheme carries the perturbations without growth);
- memory: a dense n × n array of a 20 000-dof building takes 3.2 GB; its run within 2 GB
  shows none is formed (slow).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.building3d_cb import building_pairs
from nsdyn.models.isolated.pairs import PairSystemError, simulate_pairs
from nsdyn.models.isolated.pairs_sparse import SparsePairSystem, building_pairs_sparse
from nsdyn.models.isolated.pairs_sparse_run import (
    SparsePairResult,
    _Stepper,
    genalpha_coefficients,
    simulate_pairs_sparse,
)
from nsdyn.structure import Section3D, load_frame3d, regular_building_3d

EPS = np.finfo(float).eps
FPS = Bearing(Friction(0.05, 0.08, rate=20.0), radius=2.0, c=2e3)
ORBIT = {"f": 1.0, "ax": 3.0, "ay": 1.5, "phase_y_deg": 90.0}  # an elliptical orbit [m/s²]
LAW_EPS = 200.0  # s/m: a smooth regularised law, so that h² is reached at h ~ 1e-3 s
T_END = 2.0


@pytest.fixture(scope="module")
def portal():
    return load_frame3d("portal-3d")


@pytest.fixture(scope="module")
def runs(portal):
    s = building_pairs_sparse(portal, FPS)
    out = {"system": s}
    for h in (2e-3, 1e-3, 5e-4):
        out[h] = simulate_pairs_sparse(s, ORBIT, dt=h, t_end=T_END, dt_out=0.02, eps=LAW_EPS)
    kw = dict(law="arctan", t_end=T_END, dt_out=0.02, eps=LAW_EPS, rtol=1e-10,
              atol=(1e-12, 1e-12))  # fmt: skip
    out["dense"] = simulate_pairs(s.to_pairs(), ORBIT, **kw)
    out["cb"] = simulate_pairs(building_pairs(portal, FPS, fidelity="full"), ORBIT, **kw)
    return out


def _err(r, ref):
    return float(np.abs(r.u - ref.u).max())


def test_sparse_path_equals_the_dense_kernel_to_the_integrators_tolerance(runs):
    ref = runs["dense"]
    r = runs[5e-4]
    assert isinstance(r, SparsePairResult)
    peak = float(np.abs(ref.u).max())
    assert peak > 0.1  # the isolators slide (a test of the sliding regime)
    # the sparse run's error at h is its integrator's: C h² (next test); at h = 5e-4 s the
    # Richardson estimate |u_h − u_2h| / 3 bounds it to within a factor 2 (order 2 ± 0.3)
    est = float(np.abs(r.u - runs[1e-3].u).max()) / 3.0
    assert _err(r, ref) <= 2.0 * est + 1e-9 * peak  # (Radau at rtol 1e-10: ~1e-10 peak)
    assert _err(r, ref) <= 1e-5 * peak
    # floors (T q) alike; the normal forces too once the columns' axial modes (hundreds of
    # Hz, not resolved by h, excited by the orbit's jump a_y(0) = 1.5 m/s²) have decayed in
    # the generalized-α run (ρ∞ = 0.8): from 0.5 s on
    assert np.abs(r.outputs - ref.outputs).max() <= 1e-5 * np.abs(ref.outputs).max()
    late = r.t >= 0.5
    assert np.abs(r.N - ref.N)[late].max() <= 1e-5 * ref.N.max()


def test_nodal_full_rung_equals_the_craig_bampton_full_rung(runs):
    """The same model in the CB basis (every fixed-interface mode, damping diag(0, 2ζω)):
    the dense runs of both agree to Radau's tolerance (1e-10 relative, times the condition of
    the basis change; 1e-7 allowed)."""
    a, b = runs["dense"], runs["cb"]
    assert np.abs(a.u - b.u).max() <= 1e-7 * np.abs(b.u).max()
    assert np.abs(a.outputs - b.outputs).max() <= 1e-7 * np.abs(b.outputs).max()


def test_generalized_alpha_is_second_order(runs):
    ref = runs["dense"]
    e = [_err(runs[h], ref) for h in (2e-3, 1e-3, 5e-4)]
    orders = np.log2(np.array(e[:-1]) / np.array(e[1:]))
    assert np.all(np.abs(orders - 2.0) <= 0.3), orders


COL = Section3D(2.1e11, 8.1e10, 1e-2, 2e-4, 2e-4, 3e-5, 80.0)
BEAM = Section3D(2.1e11, 8.1e10, 8e-3, 3e-4, 2e-5, 1e-6, 65.0)


def symmetric_building():
    """2 × 2 bays of equal spans, square columns: symmetric about both plan axes."""
    return regular_building_3d("sym", [6.0, 6.0], [5.0, 5.0], [4.0, 3.5], COL, BEAM, BEAM,
                               n_v=2, n_h=2, floor_mass=[4e4, 3e4], zeta=0.05)  # fmt: skip


def test_x_excitation_of_a_symmetric_building_moves_nothing_in_y_or_torsion():
    s = building_pairs_sparse(symmetric_building(), FPS)
    dt, t_end = 2e-3, 1.5
    r = simulate_pairs_sparse(s, {"f": 1.0, "ax": 3.0}, dt=dt, t_end=t_end, dt_out=0.01)
    fm = r.outputs.reshape(r.t.size, -1, 3)  # (U_x, U_y, Θ) of every level
    xmax = float(np.abs(fm[..., 0]).max())
    assert xmax > 0.05
    am, af, be, ga = genalpha_coefficients(0.8)
    c1, c2 = (1 - af) * be * dt**2, (1 - af) * ga * dt
    S = ((1 - am) * s.M + c1 * s.K + c2 * s.C).toarray() + c2 * (s.U * s.c) @ s.U.T
    bound = (t_end / dt) * EPS * np.linalg.cond(S) * xmax
    span = 12.0  # plan width: Θ times it is a displacement
    assert np.abs(fm[..., 1]).max() <= bound
    assert span * np.abs(fm[..., 2]).max() <= bound
    assert np.abs(r.u[..., 1]).max() <= bound
    assert np.abs(r.friction[..., 1]).max() <= bound / xmax * np.abs(r.friction).max()


def test_the_step_builds_no_dense_n_by_n_array():
    s = building_pairs_sparse(symmetric_building(), FPS, f_damp=20.0)
    assert 0 < s.c.size < s.n / 4  # the damped modes up to 20 Hz
    st = _Stepper(s, 1e-3, genalpha_coefficients(0.8), 20.0, 1.0)
    n = s.n
    for k, v in vars(st).items():
        if isinstance(v, np.ndarray):
            assert v.size < n * n / 4, k  # G (n, 3ni), Z (n, m): thin
        elif sp.issparse(v):
            assert v.nnz < n * n / 4, k
    for k in ("M", "K", "C", "D", "R"):
        assert sp.issparse(getattr(s, k))


def test_the_damped_solve_is_the_woodbury_identity(portal):
    """A step's solve with the modal damping (``solve_damped``: U^T twice, Z once) against a
    dense solve of S_* x = r + U diag(c) U^T v, S_* = (1 - a_m) M + c1 K + c2 (C + U diag(c)
    U^T): backward stable solves agree to a few n eps cond(S_*) relative (Higham, ch. 7)."""
    s = building_pairs_sparse(portal, FPS)
    assert s.c.size > 0 and s.C.nnz == 0  # modal damping: the low-rank term alone
    coef = genalpha_coefficients(0.8)
    st = _Stepper(s, 1e-3, coef, 20.0, 1.0)
    rng = np.random.default_rng(7)
    r, v = rng.standard_normal(s.n), rng.standard_normal(s.n)
    x, ux = st.solve_damped(r, st.Ut @ v)
    U, c = s.U, s.c
    S = (1 - coef[0]) * s.M.toarray() + st.c1 * s.K.toarray() + st.c2 * (U * c) @ U.T
    ref = np.linalg.solve(S, r + (U * c) @ (U.T @ v))
    bound = 10 * s.n * EPS * np.linalg.cond(S) * np.abs(ref).max()
    assert np.abs(x - ref).max() <= bound
    assert np.abs(ux - U.T @ ref).max() <= bound * np.abs(U).sum(axis=0).max()


def test_progress_is_called_every_progress_s_of_simulated_time(portal, monkeypatch):
    import nsdyn.models.isolated.pairs_sparse_run as run

    monkeypatch.setattr(run, "PROGRESS_S", 0.25)
    calls = []
    simulate_pairs_sparse(building_pairs_sparse(portal, FPS), ORBIT, dt=2e-3, t_end=1.0,
                          progress=lambda *a: calls.append(a))  # fmt: skip
    np.testing.assert_allclose([c[0] for c in calls], [0.25, 0.5, 0.75, 1.0], rtol=1e-12)
    assert all(c[1] == pytest.approx(1.0, rel=1e-12) for c in calls)
    assert np.all(np.diff([c[2] for c in calls]) >= 0)  # wall time since the start


def test_the_output_grid_samples_an_orbits_faster_vertical_and_says_a_coarse_one(portal):
    # the default outputs took the horizontal's 1/50 period whatever f_z (the deck's did
    # too, and warned of its own grid); outputs 0.2 s apart under a 3 Hz vertical read the
    # peaks between samples, said by the rule the deck and the frame use
    import warnings

    from nsdyn._checks import AccuracyWarning

    s, orbit = building_pairs_sparse(portal, FPS), {"f": 0.5, "ax": 1.0, "az": 1.0, "f_z": 3.0}
    with warnings.catch_warnings():
        warnings.simplefilter("error", AccuracyWarning)
        r = simulate_pairs_sparse(s, orbit, dt=2e-3, t_end=1.0)
    assert np.diff(r.t).max() <= 1.0 / (50 * 3.0) * (1 + 1e-9)
    with pytest.warns(AccuracyWarning, match=r"^dt_out = 0.2 s samples the 3 Hz excitation"):
        simulate_pairs_sparse(s, orbit, dt=2e-3, t_end=1.0, dt_out=0.2)


def test_uplift_is_reported_with_time_and_isolator():
    """A vertical ground acceleration a_z = A sin(2π f t), A > g, takes the compression away
    when g + a_z = 0: first at t* = (π + asin(g/A)) / (2π f) for a rigid building. The portal
    is vertically stiff (axial modes above 50 Hz, a quasi-static lag below 1/(2π 50) ≈ 3 ms),
    so the bilateral contact reports the uplift within 3 ms of t* and ends the run."""
    s = building_pairs_sparse(load_frame3d("portal-3d"), FPS)
    A, f = 15.0, 2.0
    with pytest.warns(UserWarning, match="uplift"):
        r = simulate_pairs_sparse(s, {"f": f, "ax": 0.0, "az": A}, dt=1e-3, t_end=1.0)
    t_star = (np.pi + np.arcsin(s.g / A)) / (2 * np.pi * f)
    assert r.uplift is not None and abs(r.uplift["t_s"] - t_star) <= 3e-3
    assert r.t[-1] <= r.uplift["t_s"]
    # the fixed-step path writes no row at the located instant, which lies between its alpha
    # points: its rows stay on the output grid and end at or before the instant (the row
    # recorded at 0.345 s was relabelled as the uplift at 0.3449 s; before, it was kept after
    # it, carrying a tensile N of -421 N into a detecting run's histories and summary)
    with pytest.warns(UserWarning, match="uplift"):
        r = simulate_pairs_sparse(s, {"f": f, "ax": 0.0, "az": 10.5}, dt=5e-3, t_end=1.0,
                                  dt_out=5e-3)  # fmt: skip
    np.testing.assert_allclose(r.t, 5e-3 * np.arange(r.t.size), rtol=0, atol=1e-12)
    assert r.t[-1] <= r.uplift["t_s"] and r.N.min() > 0.0
    assert r.summary()["min_normal_force_N"] == 0.0  # (the uplift's, after the last row)


def test_bad_input_gives_one_line_errors():
    s = building_pairs_sparse(load_frame3d("portal-3d"), FPS)
    with pytest.raises(PairSystemError, match=r"sys\.K: not symmetric"):
        K = s.K.tolil()
        K[0, 1] += 1e3
        SparsePairSystem(M=s.M, K=K, C=s.C, Gamma=s.Gamma, D=s.D, R=s.R, bearings=s.bearings,
                         positions=s.positions, name="sys")  # fmt: skip
    with pytest.raises(PairSystemError, match=r"sys\.R: expected shape"):
        SparsePairSystem(M=s.M, K=s.K, C=s.C, Gamma=s.Gamma, D=s.D, R=s.R[:2],
                         bearings=s.bearings, positions=s.positions, name="sys")  # fmt: skip
    with pytest.raises(ValueError, match="dt: expected a positive number"):
        simulate_pairs_sparse(s, ORBIT, dt=-1.0, t_end=1.0)
    with pytest.raises(ValueError, match="damping: expected one of"):
        building_pairs_sparse(load_frame3d("portal-3d"), FPS, damping="rayleigh")


_BIG = r"""
import json, resource
from nsdyn.bench.scale3d import bearing, building_of_size, motion
from nsdyn.models.isolated.pairs_sparse import building_pairs_sparse
from nsdyn.models.isolated.pairs_sparse_run import simulate_pairs_sparse
s = building_pairs_sparse(building_of_size(14, 2, 5, 4), bearing(), damping="stiffness")
r = simulate_pairs_sparse(s, motion(), dt=0.005, t_end=0.04, keep_q=False)
print(json.dumps({"n": s.n, "steps": r.stats["steps"], "t_end": float(r.t[-1]),
                  "mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}))
"""


@pytest.mark.slow
def test_a_20000_dof_building_runs_within_2_gb():
    """A dense n × n array of this building takes n² · 8 B > 3.2 GB; the whole process (model
    build, statics, factorisation, eight steps) stays below 2 GB (its peak resident set)."""
    import json
    import subprocess
    import sys

    p = subprocess.run([sys.executable, "-c", _BIG], capture_output=True, text=True,
                       timeout=1800)  # fmt: skip
    assert p.returncode == 0, p.stderr[-2000:]
    out = json.loads(p.stdout.strip().splitlines()[-1])
    assert out["n"] ** 2 * 8 > 3.2e9
    assert out["steps"] == 8 and out["t_end"] == pytest.approx(0.04)
    assert out["mb"] < 2048.0


def test_building_response_equals_the_craig_bampton_full_rungs(runs, portal):
    """Drifts, floor accelerations, base shear and torsion of the sparse run (T q and T q̈
    recorded during the run; a_(n+1) carried from t + (a_m − a_f) h to t) against the dense
    run of the Craig–Bampton full rung (Radau, rtol 1e-10): each one's error at h = 5e-4 s is
    the generalized-α error, second order, so within 1.5 times its Richardson estimate
    |x(2h) − x(h)| / (2² − 1) (floor accelerations and torsion from 0.5 s on, as the normal
    forces)."""
    from nsdyn.models.isolated.building3d_response import run_building
    from nsdyn.models.isolated.building3d_sparse import run_building_sparse

    kw = dict(t_end=T_END, dt_out=0.02, eps=LAW_EPS)
    a = run_building_sparse(runs["system"], ORBIT, dt=5e-4, **kw)
    a2 = run_building_sparse(runs["system"], ORBIT, dt=1e-3, **kw)
    b = run_building(building_pairs(portal, FPS, fidelity="full"), ORBIT, law="arctan",
                     rtol=1e-10, atol=(1e-12, 1e-12), **kw)  # fmt: skip
    late = a.t >= 0.5

    def rel(x, y, mask=None):
        d = np.abs(x - y) if mask is None else np.abs(x - y)[..., mask]
        return d.max() / np.abs(y).max()

    for get, mask in [(lambda r: r.drifts.cm, None), (lambda r: r.drifts.corner, None),
                      (lambda r: r.floor_acc, late), (lambda r: r.base_shear, None),
                      (lambda r: r.torsion, late)]:  # fmt: skip
        err, est = rel(get(a), get(b), mask), rel(get(a2), get(a), mask) / 3.0
        assert err <= 1.5 * est
        assert est <= 1e-2  # in the asymptotic range: the h² law holds
    assert a.summary()["peak_drift_cm_x"] == pytest.approx(b.summary()["peak_drift_cm_x"], 1e-4)


def test_the_written_friction_stays_in_its_disc_at_a_coarse_step(portal):
    # the α points' forces carried linearly to the output times left the disc μ(|v|) N at slip
    # onset (10 % over μN here at dt = 10 ms); the law never leaves it: each written
    # friction is within μ(|v|) N, to the round-off of the scaling (a few eps)
    s = building_pairs_sparse(portal, FPS)
    r = simulate_pairs_sparse(s, ORBIT, dt=1e-2, t_end=T_END, dt_out=0.01, eps=7500.0)
    speed = np.linalg.norm(r.v, axis=-1)  # each bearing's slip speed at the outputs
    fric = np.linalg.norm(r.friction, axis=-1)
    mu = FPS.friction.mu_fast - (FPS.friction.mu_fast - FPS.friction.mu_slow) * np.exp(
        -FPS.friction.rate * speed)  # fmt: skip
    assert np.all(fric <= mu * r.N * (1 + 8 * EPS))
    assert np.any(fric >= 0.99 * mu * r.N)  # (it slips: the bound is reached)
