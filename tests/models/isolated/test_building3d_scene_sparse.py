"""The building3d scene's full rung on sparse operators: the path it takes, its equality with the
dense full rung, the deformed shape of a run that keeps no q, and its errors.

References: the dense full rung of the same scene (Radau IIA, adaptive, rtol 1e-10: the same
model in the Craig–Bampton basis with every fixed-interface mode; the sparse path's "modal"
damping is its diag(0, 2ζω) exactly), and the sparse path's own convergence: generalized-α is
second order (Chung & Hulbert 1993), so its error at the step h is estimated by Richardson's
|x_h − x_2h| / 3 (within a factor 2 while the observed order is 2 ± 0.3, as
``tests/models/isolated/test_pairs_sparse.py`` checks). A peak differs from another by at most
the largest difference of the histories it is taken from, so the same bound holds for peaks.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest

from nsdyn.models.isolated import building3d_cb, building3d_pairs_run, pairs_sparse_run
from nsdyn.models.isolated.building3d_scene import build_system, format_summary, run_scene
from nsdyn.models.scenefile import SceneError

RTOL = 1e-10  # the dense reference's local tolerance
SCENE = {
    "scene": {"kind": "building3d"},
    "structure": {"frame3d": "portal-3d", "fidelity": "full"},
    "bearing": {"type": "fps", "radius": 2.2, "mu": 0.02},
    # no vertical: the columns' axial modes (hundreds of Hz) stay quiet, the reference cheap
    "motion": {
        "kind": "record3",
        "record": "synthetic-wn-40s",
        "t_end": 2.0,
        "pga": 4.0,
        "vertical": False,
    },
    # eps = 200 s/m: a smooth regularised law, so that h² is reached at h ~ 1e-3 s
    "solver": {"law": "arctan", "eps": 200.0, "rtol": RTOL, "atol": 1e-12, "dt_out": 0.01},
}
HISTORIES = ("u", "drift_cm", "drift_corner", "base_shear")
PEAKS = {"u": "peak_resultant_displacement_m", "drift_cm": "peak_drift_cm_x",
         "drift_corner": "peak_drift_corner_y", "base_shear": "peak_base_shear_x_N"}  # fmt: skip


def _run(tmp_path, name: str, **solver):
    cfg = copy.deepcopy(SCENE)
    cfg["solver"].update(solver)
    out = tmp_path / name
    out.mkdir()
    s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=out, figures=False, quiet=True)
    with np.load(out / "building3d.npz") as z:
        h = {k: z[k] for k in (*HISTORIES, "q", "qd") if k in z.files}
    with np.load(out / "building3d-shape.npz") as z:
        h["shape"] = z["u"]
    return s, h


def _refused(cfg: dict, tmp_path) -> str:
    """The one-line SceneError of running ``cfg`` (the scene refused before any run)."""
    with pytest.raises(SceneError) as e:
        run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip
    return str(e.value)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("sparse-scene")
    out = {"dense": _run(tmp, "dense", path="dense")}
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(building3d_pairs_run, "SPARSE_FROM", 0)  # "auto" sparse at any size
        out["auto"] = _run(tmp, "auto", dt=5e-4)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(building3d_cb, "FULL_MAX", 0)  # every frame above the dense limit
        for h in (1e-3, 5e-4):
            out[h] = _run(tmp, f"sparse-{h:g}", dt=h)
        mp.setattr(pairs_sparse_run, "KEEP_Q_MB", 0.0)  # q too large to keep: none kept
        out["no-q"] = _run(tmp, "no-q", dt=1e-3)
    return out


def test_the_portal_takes_the_path_asked_and_the_lowered_limit_the_sparse(runs):
    d, s = runs["dense"][0], runs[5e-4][0]
    assert d["path"] == "dense" and "(solver.path)" in d["path_why"]
    assert s["path"] == "sparse" and "above the dense limit 0" in s["path_why"]
    assert s["method"] == "genalpha-sparse" and s["dt_s"] == 5e-4 and s["law"] == "arctan"
    text = format_summary(s)
    assert "sparse" in text and "time step" in text and "peak drift corner x" in text


def test_auto_runs_the_regularised_law_on_the_sparse_path_above_its_size(runs):
    # solver.path "auto" above SPARSE_FROM internal dofs (lowered to 0) with the law, contact
    # and bearing the sparse path runs: that path, the same steps as a frame above the dense
    # limit, bit for bit
    (sa, ha), (_, h2) = runs["auto"], runs[5e-4]
    assert sa["path"] == "sparse" and "solver.path = 'dense'" in sa["path_why"]
    for key in ("q", "qd", "u", "base_shear"):  # the steps, and what the bearings' forces sum
        assert np.array_equal(ha[key], h2[key]), key
    # the drift ratios are maps T q of those q, built anew for each run: their entries may
    # differ in the last bits (SciPy 1.12's sparse products did), |Δ(T q)| <= 64 eps |T| |q|,
    # each row a difference of two storeys' displacements over the storey height h = 4 m
    bound = 64 * np.finfo(float).eps * 2 * np.abs(h2["q"]).max() / 4.0
    for key in ("drift_cm", "drift_corner"):
        np.testing.assert_allclose(ha[key], h2[key], rtol=0, atol=bound, err_msg=key)


def test_auto_keeps_a_small_frame_on_the_dense_path(tmp_path):
    # the portal: its internal dofs (those off the isolator interface) below SPARSE_FROM
    cfg = copy.deepcopy(SCENE)
    info = build_system(cfg, str(tmp_path / "s.toml"))["pairs"].info
    limit = building3d_pairs_run.SPARSE_FROM
    assert int(info["path_why"].split()[0]) <= limit
    assert info["path"] == "dense" and f"up to {limit}" in info["path_why"], info["path_why"]


@pytest.mark.parametrize(
    ("solver", "bearing", "words"),
    [
        ({"law": "switch"}, {}, "law 'switch'"),
        ({"contact": "unilateral"}, {}, "contact 'unilateral'"),
        ({"contact": "bilateral"}, {}, "contact 'bilateral'"),
        ({}, {"area": 0.05, "p_ref": 20e6}, "pressure-dependent friction"),
    ],
)
def test_auto_keeps_the_dense_path_where_the_sparse_cannot_run(solver, bearing, words,
                                                               tmp_path, monkeypatch):  # fmt: skip
    monkeypatch.setattr(building3d_pairs_run, "SPARSE_FROM", 0)
    cfg = copy.deepcopy(SCENE)
    cfg["solver"].update(solver)
    cfg["bearing"].update(bearing)
    info = build_system(cfg, str(tmp_path / "s.toml"))["pairs"].info
    assert info["path"] == "dense" and words in info["path_why"], info["path_why"]


def test_auto_never_changes_the_friction_model(tmp_path, monkeypatch):
    # without solver.law a scene runs the switch law (the deck scene's default): "auto"
    # keeps it, on the dense path, rather than run the regularised law on sparse operators
    monkeypatch.setattr(building3d_pairs_run, "SPARSE_FROM", 0)
    cfg = copy.deepcopy(SCENE)
    del cfg["solver"]["law"]
    info = build_system(cfg, str(tmp_path / "s.toml"))["pairs"].info
    assert info["path"] == "dense" and "law 'switch'" in info["path_why"], info["path_why"]


def test_a_path_that_cannot_be_taken_is_refused(tmp_path, monkeypatch):
    cfg = copy.deepcopy(SCENE)
    cfg["solver"]["path"] = "fast"
    msg = _refused(cfg, tmp_path)
    assert "\n" not in msg and "s.toml: solver.path: expected one of" in msg, msg
    monkeypatch.setattr(building3d_cb, "FULL_MAX", 0)  # above the dense limit: no dense path
    cfg["solver"]["path"] = "dense"
    msg = _refused(cfg, tmp_path)
    assert "\n" not in msg and "s.toml: solver.path: 'dense' takes frames of at most 0" in msg
    assert not (tmp_path / "building3d.npz").exists()


def test_sparse_full_rung_equals_the_dense_full_rung(runs):
    (sd, hd), (_, h1), (s2, h2) = runs["dense"], runs[1e-3], runs[5e-4]
    peak_u = float(np.abs(hd["u"]).max())
    assert peak_u > 0.05  # the isolators slide: a test of the sliding regime
    for key in HISTORIES:
        ref = np.abs(hd[key]).max()
        est = float(np.abs(h2[key] - h1[key]).max()) / 3.0  # Richardson, order 2
        # the dense reference's own global error: at most steps x rtol of the peak
        bound = 2.0 * est + sd["n_steps"] * RTOL * ref
        assert np.abs(h2[key] - hd[key]).max() <= bound, key
        assert s2[PEAKS[key]] == pytest.approx(sd[PEAKS[key]], abs=bound), key
        assert est <= 1e-3 * ref, key  # and that error is small: the bound says something


def test_a_run_that_keeps_no_q_draws_the_same_shape(runs):
    # without the q histories the state at the peak is that of the run repeated to t*: the
    # same steps in the same order (the output step only decides what is recorded), so the
    # same field to the last bit
    hk, hn = runs[1e-3][1], runs["no-q"][1]
    assert np.array_equal(hn["u"], hk["u"])
    assert np.abs(hk["shape"]).max() > 0
    assert np.array_equal(hn["shape"], hk["shape"])


@pytest.mark.parametrize(
    ("tables", "field", "words"),
    [
        ({"solver": {"law": "switch"}}, "solver.law", "expected 'arctan', got 'switch'"),
        ({"bearing": {"type": "tfp"}}, "bearing.type", "triple friction pendulum"),
    ],
)
def test_the_sparse_path_refuses_what_it_cannot_run(tables, field, words, tmp_path,
                                                    monkeypatch):  # fmt: skip
    monkeypatch.setattr(building3d_cb, "FULL_MAX", 0)
    cfg = copy.deepcopy(SCENE)
    cfg["solver"].update(tables.get("solver", {}))
    if "bearing" in tables:  # the triple friction pendulum of examples/scenes/deck-tfp4-3c
        cfg["bearing"] = {"type": "tfp", "R1": 2.2, "R2": 0.3, "R3": 0.3, "R4": 2.2,
                          "mu1": 0.06, "mu2": 0.02, "mu3": 0.02, "mu4": 0.10, "d1": 0.40,
                          "d2": 0.06, "d3": 0.06, "d4": 0.40}  # fmt: skip
    with pytest.raises(SceneError) as e:
        build_system(cfg, str(tmp_path / "s.toml"))
    msg = str(e.value)
    assert "\n" not in msg and f"s.toml: {field}:" in msg and words in msg, msg
    assert "full-sparse" not in msg and "bearings[" not in msg  # no name the user never typed


def test_stiffness_damping_reaches_the_sparse_system(tmp_path, monkeypatch):
    # "stiffness": β K on the members (C sparse, no low-rank term); "modal": the low-rank
    # fixed-interface modal damping, every one of the portal's 23 interior modes damped
    monkeypatch.setattr(building3d_cb, "FULL_MAX", 0)
    systems = {}
    for damping in ("stiffness", "modal"):
        cfg = copy.deepcopy(SCENE)
        cfg["structure"]["damping"] = damping
        systems[damping] = build_system(cfg, str(tmp_path / "s.toml"))["pairs"]
    st, mo = systems["stiffness"], systems["modal"]
    assert st.info["damping"] == "stiffness" and st.c.size == 0 and st.C.nnz > 0
    assert mo.info["damping"] == "modal" and mo.c.size == 23 and mo.C.nnz == 0


def test_f_damp_damps_exactly_the_modes_up_to_it(tmp_path, monkeypatch):
    # structure.f_damp: the low-rank term keeps the fixed-interface modes with f <= f_damp;
    # the cut-off halfway between the 10th and 11th of the portal's 23 damps exactly ten
    monkeypatch.setattr(building3d_cb, "FULL_MAX", 0)
    cfg = copy.deepcopy(SCENE)
    every = build_system(cfg, str(tmp_path / "s.toml"))["pairs"].info["damped_f_hz"]
    assert every.size == 23
    cfg["structure"]["f_damp"] = float(0.5 * (every[9] + every[10]))
    cut = build_system(cfg, str(tmp_path / "s.toml"))["pairs"]
    assert cut.c.size == 10
    # the same ten frequencies from two eigen-solutions of the same matrices: equal to the
    # solvers' convergence (ARPACK's tol is machine precision; 1e-8 leaves room for its
    # round-off), far below the closest pair's relative gap (3e-3), so none is swapped
    np.testing.assert_allclose(cut.info["damped_f_hz"], every[:10], rtol=1e-8)
    for bad in (0.0, -5.0, "50", True):
        cfg["structure"]["f_damp"] = bad
        with pytest.raises(SceneError) as e:
            build_system(cfg, str(tmp_path / "s.toml"))
        msg = str(e.value)
        assert "\n" not in msg and "s.toml: structure.f_damp: expected a positive" in msg, msg


def test_a_scene_built_again_loads_its_sparse_system_from_the_model_cache(tmp_path,
                                                                          monkeypatch):  # fmt: skip
    # the model cache (nsdyn._model_cache, a test folder of its own): the second build never
    # calls the builder and returns the stored system bit for bit
    from nsdyn.models.isolated import pairs_sparse

    monkeypatch.setattr(building3d_cb, "FULL_MAX", 0)
    cfg = copy.deepcopy(SCENE)
    first = build_system(cfg, str(tmp_path / "s.toml"))["pairs"]

    def no_build(*a, **k):
        raise AssertionError("built again")

    monkeypatch.setattr(pairs_sparse, "building_pairs_sparse", no_build)
    again = build_system(cfg, str(tmp_path / "s.toml"))["pairs"]
    assert again is not first and again.info["path"] == "sparse"
    assert np.array_equal(again.U, first.U) and np.array_equal(again.c, first.c)
    assert (again.K != first.K).nnz == 0 and (again.M != first.M).nnz == 0


@pytest.mark.parametrize("contact", ["bilateral", "unilateral"])
def test_the_sparse_path_refuses_a_contact_other_than_detect(contact, tmp_path, monkeypatch):
    # the sparse loop keeps every contact closed and detects uplift; another assumption
    # would be silently ignored, so it is refused naming the field
    monkeypatch.setattr(building3d_cb, "FULL_MAX", 0)
    cfg = copy.deepcopy(SCENE)
    cfg["solver"]["contact"] = contact
    msg = _refused(cfg, tmp_path)
    assert "\n" not in msg and "s.toml: solver.contact:" in msg and "'detect'" in msg, msg
    assert not (tmp_path / "building3d.npz").exists()


def test_the_rigid_rung_refuses_unilateral_contact(tmp_path):
    # the rigid rung is the building as a deck: no vertical or rocking motion to lift off in
    cfg = copy.deepcopy(SCENE)
    cfg["structure"]["fidelity"] = "rigid"
    cfg["solver"] = {"law": "arctan", "contact": "unilateral"}
    msg = _refused(cfg, tmp_path)
    assert "\n" not in msg and "s.toml: solver.contact:" in msg and "rigid rung" in msg, msg


def test_the_cb_rung_locates_the_same_uplift_under_all_three_contact_assumptions(tmp_path):
    # a vertical ground acceleration of 1.3 g downwards lifts the light portal's base (its
    # steel alone weighs on the isolators): "detect" stops where a normal force reaches zero,
    # "bilateral" reports the onset of tension, "unilateral" lifts off. Up to the step that
    # crosses the zero the three solve the same equations with the same steps: identical
    # histories before it. "unilateral" keeps the contact closed through that step and locates
    # the same zero (the event location's tolerance, 1e-11 s); "bilateral" drops friction
    # where lambda < 0 inside it, so its step and dense output differ there and its zero by
    # the dense output's error, about rtol N_0 / |dN/dt|
    t = np.arange(0.0, 0.5 + 1e-9, 0.005)
    w = 2.0 * np.pi
    a = np.column_stack([t, 2.0 * np.sin(1.5 * w * t), np.sin(1.1 * w * t),
                         -1.3 * 9.81 * np.sin(2.0 * w * t)])  # fmt: skip
    np.savetxt(tmp_path / "v.csv", a, delimiter=",", header="t,ax,ay,az", comments="")
    rtol = 1e-6
    outs = {}
    for contact in ("detect", "bilateral", "unilateral"):
        cfg = copy.deepcopy(SCENE)
        cfg["structure"]["fidelity"] = "cb"
        cfg["motion"] = {"kind": "record3", "record": str(tmp_path / "v.csv"), "units": "m/s2",
                         "t_end": 0.1}  # fmt: skip
        cfg["solver"] = {"law": "switch", "rtol": rtol, "atol": 1e-9, "dt_out": 0.01,
                         "contact": contact}  # fmt: skip
        out = tmp_path / contact
        out.mkdir()
        s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=out, figures=False,
                      quiet=True)  # fmt: skip
        with np.load(out / "building3d.npz") as z:
            outs[contact] = (s, z["t"].copy(), z["u"].copy(), z["N"].copy())
    sd, su, sb = outs["detect"][0], outs["unilateral"][0], outs["bilateral"][0]
    assert sd["uplift"] is not None, "the portal was expected to lift off under 1.3 g down"
    t_up, iso = sd["uplift"]["t_s"], sd["uplift"]["isolator"]
    # near the first a_z = -g: sin(4 pi t) = 1/1.3, t = 0.0698 s (the portal's vertical
    # response shifts it by a fraction of its ~20 ms rise)
    assert 0.05 < t_up < 0.08
    assert sb["uplift"] is None and su["uplift"] is None
    assert su["lift_offs"] >= 1 and abs(su["first_lift_off_s"] - t_up) < 1e-9
    tb, Nb = outs["bilateral"][1], outs["bilateral"][3][:, iso]
    k = np.searchsorted(tb, t_up)
    slope = abs(Nb[k] - Nb[k - 1]) / (tb[k] - tb[k - 1])  # |dN/dt| across the zero
    assert sb["tension"]["isolator"] == iso
    assert abs(sb["tension"]["t_first_s"] - t_up) < 10.0 * rtol * Nb[0] / slope
    for c in ("bilateral", "unilateral"):
        t, u = outs[c][1], outs[c][2]
        k = t < t_up
        td, ud = outs["detect"][1], outs["detect"][2]
        kd = td < t_up
        np.testing.assert_array_equal(t[k], td[kd])
        np.testing.assert_allclose(u[k], ud[kd], rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    ("dt", "words"),
    [(0.02, "longer than the record's sampling step 0.01 s"),  # steps over its samples
     (1e-7, "more than 2000000")],  # 2e7 steps over the 2 s run
)  # fmt: skip
def test_the_sparse_path_refuses_a_step_its_record_or_budget_cannot_take(dt, words, tmp_path,
                                                                        monkeypatch):  # fmt: skip
    """A step longer than the record's sampling step passes over samples: at 1 s the office's
    peaks came out four times the converged ones, with status 0; a step that takes more than
    SPARSE_MAX_STEPS never ends in practice. Both are refused before the run, naming dt."""
    monkeypatch.setattr(building3d_cb, "FULL_MAX", 0)
    cfg = copy.deepcopy(SCENE)
    cfg["solver"]["dt"] = dt
    msg = _refused(cfg, tmp_path)
    assert "\n" not in msg and "s.toml: solver.dt:" in msg and words in msg, msg
    assert not (tmp_path / "building3d.npz").exists()
