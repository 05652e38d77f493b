"""The unilateral stepped sweep (nsdyn.periodic.unilateral) where no contact lifts off.

With small excitation the three contact assumptions must give the same answer: when the
bilateral orbit's normal forces stay positive, the unilateral flow never opens a contact, so
its steady state is the bilateral periodic orbit. The two are computed independently — the
orbit by Newton shooting on the fixed-step SDIRK2 period map in minimal coordinates, the sweep
by adaptive Radau (rtol 1e-6 with the unilateral event loop) in full coordinates — so they
agree to the shooting discretisation's error: the README's periodic accuracy (~0.3 % on
x_iso and IDR with the default steps) bounds it; 1 % is asserted, and no lift-off at all.
"""

import numpy as np
import pytest

from nsdyn.models.isolated.system import Isolation, build_system
from nsdyn.periodic import duffing_problem, frame_problem, shoot
from nsdyn.periodic.unilateral import unilateral_steady_state
from nsdyn.structure import load_frame


@pytest.fixture(scope="module")
def office_cb():
    return build_system(load_frame("office-11"), Isolation(), fidelity="cb", f_max=5.0)


@pytest.mark.parametrize("A, f", [(0.3, 0.0588), (1.0, 0.5)])
def test_without_lift_off_the_unilateral_steady_state_is_the_bilateral_orbit(office_cb, A, f):
    pb = frame_problem(office_cb, A)
    orbit = shoot(pb, f)
    assert orbit.converged
    q = pb.orbit_quantities(f, orbit.X)
    assert q["min_normal_force"] > 0.0  # the premise: no uplift on the bilateral orbit
    # no wall-time budget: the first call compiles the unilateral kernels (minutes on a cold
    # cache and a loaded machine), which is not what this test is about
    u = unilateral_steady_state(pb, f, pb.to_full(orbit.x0), budget_s=np.inf)
    assert u.steady, u.message
    uq = u.quantities
    assert uq["lift_offs_per_period"] == 0 and uq["flight_fraction"] == 0.0
    for key in ("x_iso", "idr", "acc_floors", "min_normal_force"):
        assert uq[key] == pytest.approx(q[key], rel=1e-2), key


def test_needs_a_frame_problem():
    with pytest.raises(ValueError, match="frame problem"):
        unilateral_steady_state(duffing_problem(0.05, 1.0, 0.1, 1.0), 1.0, np.zeros(2))


def test_a_steady_rocking_orbit_above_the_uplift_boundary(office_cb):
    # 0.93 Hz, A = 13.5 m/s^2: above the uplift boundary of that pocket (A* = 12.3 m/s^2,
    # README "Where does uplift start?"), so the bilateral orbit has a negative normal force.
    # The unilateral flow settles to a period-1 orbit with flights; physics it must obey:
    # a unilateral contact never pulls (closed-contact normal forces >= 0), and in a periodic
    # orbit every flight that starts in the period ends in it (as many landings as lift-offs).
    A, f = 13.5, 0.93
    pb = frame_problem(office_cb, A)
    orbit = shoot(pb, f)
    assert orbit.converged
    assert pb.orbit_quantities(f, orbit.X)["min_normal_force"] < 0.0
    u = unilateral_steady_state(pb, f, pb.to_full(orbit.x0), max_periods=30, budget_s=np.inf)
    assert u.steady, u.message
    uq = u.quantities
    assert uq["lift_offs_per_period"] > 0
    assert uq["landings_per_period"] == uq["lift_offs_per_period"]
    assert uq["min_normal_force"] >= 0.0
    assert 0.0 < uq["flight_fraction"] < 1.0


def test_a_curves_uplift_rows_are_recomputed_and_the_others_left(office_cb):
    # unilateral_rows (the sweep's --contact unilateral pass): a row flagged uplift on the
    # bilateral orbit gets the unilateral quantities (the frame flies: 0.9 Hz, A = 13.5 m/s^2
    # is above that pocket's boundary), a row without uplift is left as it was.
    from types import SimpleNamespace

    from nsdyn.periodic.unilateral import unilateral_rows

    A, f = 13.5, 0.9
    pb = frame_problem(office_cb, A)
    orbit = shoot(pb, f)
    assert orbit.converged
    pts = [SimpleNamespace(f=f, x0=orbit.x0), SimpleNamespace(f=0.5, x0=orbit.x0)]
    rows = [{"uplift": True, "method": "shooting"}, {"uplift": False, "method": "shooting"}]
    assert unilateral_rows(pb, pts, rows, max_periods=3, budget_s=np.inf) == 1
    assert rows[0]["method"] == "unilateral" and rows[0]["flight_fraction"] > 0.0
    assert rows[0]["converged"] is False and "3 periods" in rows[0]["note"]
    assert rows[1] == {"uplift": False, "method": "shooting"}
