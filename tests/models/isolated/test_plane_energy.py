"""The work–energy balance of decks and systems from matrices on sliding isolators.

Source: the work–energy theorem of the equations of motion (module text of
:mod:`nsdyn.models.isolated.plane_energy`): the stored energy's change equals the work of the
ground, the weight, the damping, the isolators and the contacts. Its integrals are taken by
the trapezoidal rule on the output grid, whose error is O(dt_out²): halving the output step
divides the closure by 4 (3 to 5 here, the run's own error being far below it at rtol 1e-8);
a missing or mis-signed term would leave a closure of order one at every step.
"""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest

from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.deck import sdof_plane, simulate_plane
from nsdyn.models.isolated.pairs import PairSystem, simulate_pairs

SCENES = Path(__file__).resolve().parents[3] / "examples" / "scenes"
ORBIT = {"f": 0.7, "ax": 3.0, "ay": 2.0, "phase_y_deg": 30.0, "az": 2.0, "f_z": 1.9}


def _order(run) -> float:
    """log2 of the closure's ratio between output steps 0.02 and 0.01 s."""
    c = [run(dt).energy(ORBIT)["energy_closure"] for dt in (0.02, 0.01)]
    return float(np.log2(c[0] / c[1]))


def _eccentric_deck():
    """Four pendulum bearings under a deck whose centre of mass is off the centroid, high
    above the sliding surfaces (the overturning moves N bearing by bearing)."""
    from nsdyn.models.isolated.deck import rigid_deck

    pos = [(-4.0, -3.0), (4.0, -3.0), (4.0, 3.0), (-4.0, 3.0)]
    return rigid_deck(4e5, 4e5 * 100 / 12, pos, Bearing(Friction(0.05), radius=2.0, c=2e4),
                      ecc=(1.0, 0.5), h=1.5)  # fmt: skip


@pytest.mark.parametrize("law", ["switch", "arctan"])
@pytest.mark.parametrize("deck", ["mass", "eccentric"])
def test_a_deck_s_energy_balance_closes_at_the_trapezoidal_rule_s_order(law, deck):
    # a mass on a friction pendulum with a damper, or an eccentric deck on four, under a
    # 2-component orbit and a vertical (which varies N: the pendulum's work is then no
    # potential energy; the eccentric deck twists)
    s = sdof_plane(1e5, Bearing(Friction(0.05), radius=2.0, c=2e4)) if deck == "mass" else \
        _eccentric_deck()  # fmt: skip

    def run(dt):
        return simulate_plane(s, ORBIT, law=law, t_end=8.0, dt_out=dt, rtol=1e-8)

    assert 1.6 <= _order(run) <= 2.3
    r = run(0.01)
    assert r.uplift is None and r.t[-1] == 8.0  # (the whole run: no isolator lifted off)
    e = r.energy(ORBIT)
    assert e["energy_friction_J"] > 0 and e["energy_other_J"] > 0  # (both dissipate)
    assert e["energy_viscous_J"] == e["energy_contact_J"] == 0.0  # (a deck has neither)


@pytest.mark.parametrize("law", ["switch", "arctan"])
def test_a_structure_on_an_isolator_balances_its_weight_through_the_contact(law):
    # a base mass on one pendulum bearing carrying a damped oscillator in x: q = (x_b, y_b,
    # z, x_t), gravity along z, the contact row on z; the weight's work and the contact's
    # cancel on the closed gap (R q̇ = 0, so the contact's work is the Baumgarte drift's)
    mb, mt, k, c = 2e4, 5e4, 2e6, 2e4
    K = np.zeros((4, 4))
    K[np.ix_([0, 3], [0, 3])] = k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    s = PairSystem(M=np.diag([mb, mb, mb + mt, mt]), K=K, C=K * c / k,
                   Gamma=np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 0]], float),
                   D=np.array([[[1.0, 0, 0, 0], [0, 1.0, 0, 0]]]), R=np.array([[0, 0, 1.0, 0]]),
                   bearings=(Bearing(Friction(0.05), radius=2.0),), positions=np.zeros((1, 2)),
                   g=9.81)  # fmt: skip

    def run(dt):
        return simulate_pairs(s, ORBIT, law=law, t_end=8.0, dt_out=dt, rtol=1e-8)

    assert 1.6 <= _order(run) <= 2.3
    e = run(0.01).energy(ORBIT)
    assert e["energy_viscous_J"] > 0
    assert abs(e["energy_contact_J"]) <= 1e-9 * e["energy_input_J"]


def _two_masses(**kw):
    mb, mt, k = 2e4, 5e4, 2e6
    K = np.zeros((4, 4))
    K[np.ix_([0, 3], [0, 3])] = k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    return dict(M=np.diag([mb, mb, mb + mt, mt]), K=K,
                Gamma=np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 0]], float),
                D=np.array([[[1.0, 0, 0, 0], [0, 1.0, 0, 0]]]), R=np.array([[0, 0, 1.0, 0]]),
                bearings=(Bearing(Friction(0.05), radius=2.0),), positions=np.zeros((1, 2)),
                g=9.81, **kw)  # fmt: skip


def test_the_sparse_path_s_balance_has_its_low_rank_damping():
    # the sparse path's damping C + U diag(c) Uᵀ: its work is the dense system's of the same
    # matrix, to the two runs' difference (the sparse path's fixed step of 1 ms against
    # Radau at rtol 1e-8: 1e-3 of the work at most); a run that kept no q is refused
    import scipy.sparse as sps

    from nsdyn.models.isolated.pairs_sparse import SparsePairSystem
    from nsdyn.models.isolated.pairs_sparse_run import simulate_pairs_sparse

    U, c = np.array([[1.0], [0.0], [0.0], [-1.0]]), np.array([2e4])
    d = _two_masses()
    ss = SparsePairSystem(**{**d, "M": sps.csr_array(d["M"]), "K": sps.csr_array(d["K"]),
                             "R": sps.csr_array(d["R"])}, C=None, U=U, c=c)  # fmt: skip
    e = simulate_pairs_sparse(ss, ORBIT, dt=1e-3, t_end=8.0, dt_out=0.01, keep_q=True)
    e = e.energy(ORBIT)
    ref = simulate_pairs(PairSystem(**d, C=(U * c) @ U.T), ORBIT, law="arctan", t_end=8.0,
                         dt_out=0.01, rtol=1e-8).energy(ORBIT)  # fmt: skip
    assert e["energy_viscous_J"] == pytest.approx(ref["energy_viscous_J"], rel=1e-3)
    lean = simulate_pairs_sparse(ss, ORBIT, dt=1e-3, t_end=0.1, dt_out=0.01, keep_q=False)
    with pytest.raises(ValueError, match="kept no histories of q"):
        lean.energy(ORBIT)


def test_a_unilateral_run_s_landings_enter_the_balance():
    # a vertical of 1.2 g lifts the base off: the plastic landings take kinetic energy
    # (the run's impact_energy_J), which the balance counts; without it the closure would be
    # that share of the largest term (here over 10x the closure left by the grid)
    s = PairSystem(**_two_masses(), C=np.zeros((4, 4)))
    orbit = {**ORBIT, "az": 12.0, "f_z": 1.0}
    r = simulate_pairs(s, orbit, law="switch", t_end=4.0, dt_out=0.01, rtol=1e-8,
                       contact="unilateral")  # fmt: skip
    e = r.energy(orbit)
    assert e["energy_impact_J"] == r.flights["impact_energy_J"] < 0
    lost = sum(e[f"energy_{k}_J"] for k in ("friction", "restoring", "other", "viscous"))
    left = e["stored_change_J"] - (e["energy_input_J"] - lost + e["energy_contact_J"])
    assert abs(left - e["energy_impact_J"]) * 10 < abs(left)  # [J]: with and without it
    # (the same sum in another order: the round-off of 1e5 J terms, 1e-10 of the residual)
    closure = abs(left - e["energy_impact_J"]) / e["energy_scale_J"]
    assert e["energy_closure"] == pytest.approx(closure, rel=1e-9)


def test_the_weight_s_prestrain_is_no_scale_of_the_closure():
    # a top mass on a vertical spring over the base: gravity compresses it by m_t g / k_z,
    # a stored energy (m_t g)² / 2 k_z = 1.2e5 J that a weak shaking's work (~1e3 J) does not
    # change; measured against it, the closure read 10⁻³ of what it is. The scale is the
    # largest work or the stored energy above the static equilibrium
    mb, mt, kx, kz, g = 2e4, 5e4, 2e6, 1e6, 9.81
    K = np.zeros((5, 5))
    K[np.ix_([0, 3], [0, 3])] = kx * np.array([[1.0, -1.0], [-1.0, 1.0]])
    K[np.ix_([2, 4], [2, 4])] = kz * np.array([[1.0, -1.0], [-1.0, 1.0]])
    s = PairSystem(M=np.diag([mb, mb + mt, mb, mt, mt]), K=K, C=K * 1e-2,
                   Gamma=np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 0], [0, 0, 1]], float),
                   D=np.array([[[1.0, 0, 0, 0, 0], [0, 1.0, 0, 0, 0]]]),
                   R=np.array([[0, 0, 1.0, 0, 0]]), bearings=(Bearing(Friction(0.05), radius=2.0),),
                   positions=np.zeros((1, 2)), g=g)  # fmt: skip
    weak = {"f": 0.7, "ax": 0.3, "ay": 0.2, "phase_y_deg": 30.0}
    e = simulate_pairs(s, weak, law="arctan", t_end=8.0, dt_out=0.01, rtol=1e-8).energy(weak)
    prestrain = (mt * g) ** 2 / (2 * kz)
    terms = [abs(e[k]) for k in e if k.startswith("energy_") and k.endswith("_J")
             and k != "energy_scale_J"]  # fmt: skip
    assert max(terms) <= e["energy_scale_J"] < 0.1 * prestrain


def test_the_balance_taken_in_blocks_of_outputs_equals_it_in_one(monkeypatch):
    # the quadratic forms a block of outputs at a time (no temporary of q's size): the same
    # products row by row, so the same numbers bit for bit as in one block
    import nsdyn.models.isolated.plane_energy as pe

    res = simulate_plane(_eccentric_deck(), ORBIT, t_end=2.0, dt_out=0.01)
    d = _two_masses()
    pair = simulate_pairs(PairSystem(**d, C=2e3 * np.eye(4)), ORBIT, law="arctan", t_end=2.0,
                          dt_out=0.01)  # fmt: skip
    one = [r.energy(ORBIT) for r in (res, pair)]
    monkeypatch.setattr(pe, "ROWS_PER_BLOCK", 7)  # 201 outputs: 29 blocks, the last short
    assert [r.energy(ORBIT) for r in (res, pair)] == one


def test_a_unilateral_building_says_when_its_closure_is_the_grid_s_over_landings(tmp_path):
    # the portal's cb rung lifted by a 1.4 g vertical: each landing jumps q̇ (and the weight's
    # power m (g + a_z) v_z) inside an output step, which the trapezoid misses by up to
    # dt_out/2 times the jump: first order in dt_out. The note says so exactly when the
    # closure is above its threshold; at 0.1 ms (100 x finer than the default 10 ms) it is
    # below it, as a first-order error must be
    from nsdyn.models.isolated.building3d_scene import run_scene
    from nsdyn.models.isolated.plane_energy import LANDING_CLOSURE_NOTE

    cfg = {"scene": {"kind": "building3d"},
           "structure": {"frame3d": "portal-3d", "fidelity": "cb"},
           "bearing": {"type": "fps", "radius": 2.2, "mu_slow": 0.05, "mu_static": 0.06},
           "motion": {"kind": "orbit", "orbit": "linear", "frequency": 1.0, "amplitude": 1.0,
                      "vertical_amplitude": 14.0, "vertical_frequency": 2.0,
                      "n_periods": 1.5},
           "solver": {"law": "switch", "contact": "unilateral"}}  # fmt: skip
    closures = []
    for dt_out in (None, 1e-4):
        if dt_out:
            cfg["solver"]["dt_out"] = dt_out
        s = run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path, figures=False,
                      quiet=True)  # fmt: skip
        said = [n for n in s["notes"] if n.startswith("energy closure")]
        assert s["landings"] > 0
        assert bool(said) == (s["energy_closure"] > LANDING_CLOSURE_NOTE)
        closures.append(s["energy_closure"])
    assert closures[1] < LANDING_CLOSURE_NOTE and closures[1] < closures[0] / 10


def test_a_free_mass_at_whole_periods_closes_against_its_kinetic_energy():
    # no friction, spring or damper: a mass the orbit shakes back to rest each period. At
    # t = 5 s (2 periods of 0.4 Hz) the ends' stored energies and every work are ~0, and the
    # closure, over them, read 1 for a run whose error is ~1e-3 J of ~8 kJ of kinetic energy
    # passed through; the scale now holds the largest kinetic energy
    m, orbit = 1e5, {"f": 0.4, "ax": 0.5, "ay": 0.5, "phase_y_deg": 90.0}
    s = sdof_plane(m, Bearing(Friction(0.0)))
    r = simulate_plane(s, orbit, law="arctan", t_end=5.0, dt_out=0.01, rtol=1e-8)
    e = r.energy(orbit)
    v_peak = 2 * 0.5 / (2 * np.pi * 0.4)  # |v| of a free mass under a circular a_g from rest
    assert e["energy_scale_J"] >= 0.5 * m * v_peak**2 * 0.99
    assert e["energy_closure"] < 1e-3


def test_a_deck_whose_integration_fails_its_balance_says_so_and_doubts_its_uplift(tmp_path):
    # eps = 1e10 at rtol 0.1: the run diverged into an "uplift" at 0.78 s with closure 1.02,
    # reported as the structure's; now a note says the run is not to be trusted, and the
    # uplift error says its closure
    from nsdyn.models.isolated.deck_scene import run_scene, uplift_error
    from nsdyn.models.isolated.plane_energy import CLOSURE_NOTE
    from nsdyn.models.scenefile import read_toml

    cfg = read_toml(str(SCENES / "deck-fps4-3c.toml"))
    cfg["solver"] = {**cfg.get("solver", {}), "law": "arctan", "eps": 1e10, "rtol": 0.1}
    cfg["motion"]["t_end"] = 2.0
    s = run_scene(cfg, source=str(tmp_path / "d.toml"), out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip
    assert s["energy_closure"] > CLOSURE_NOTE
    assert any(n.startswith("energy closure") and "not to be trusted" in n for n in s["notes"])
    assert s.get("uplift") and "the uplift may be the numerics'" in uplift_error(s)
    good = copy.deepcopy(cfg)
    good["solver"]["rtol"] = 1e-3  # the same sharp law at a tolerance it needs: no note
    s = run_scene(good, source=str(tmp_path / "d.toml"), out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip
    assert s["energy_closure"] < CLOSURE_NOTE and not s.get("uplift")
    assert not any(n.startswith("energy closure") for n in s["notes"])
    # a correct run of a few outputs, whose closure is its grid's (0.16 at 30 ms, any rtol):
    # no note (a first threshold of 5e-2 called it untrustworthy)
    tfp = read_toml(str(SCENES / "deck-tfp4-3c.toml"))
    tfp["motion"]["t_end"] = 0.03
    s = run_scene(tfp, source=str(tmp_path / "t.toml"), out_dir=tmp_path, figures=False,
                  quiet=True)  # fmt: skip
    assert s["energy_closure"] > 0.05 and not any(n.startswith("energy closure")
                                                 for n in s["notes"])  # fmt: skip
