"""Geometry, mass properties (textbook formulas) and bad-input errors of the body."""

import math

import numpy as np
import pytest

from nsdyn.models.contact.body import RigidBody
from nsdyn.models.contact.friction import FrictionLaw


def test_rectangle_mass_properties_match_closed_forms():
    b = RigidBody.rectangle(1.1, 1.0, 2.0)
    assert b.J == pytest.approx(2.0 * (1.1**2 + 1.0**2) / 12, rel=1e-12)  # m (a^2 + c^2) / 12
    R, alpha, J_O = b.corner_geometry()
    assert R == pytest.approx(math.hypot(0.55, 0.5))
    assert alpha == pytest.approx(math.atan(1.1 / 1.0))
    assert J_O == pytest.approx(4 / 3 * 2.0 * R**2)  # J_O = 4/3 m R^2
    assert len(b.base) == 2 and b.theta_ov == pytest.approx(math.pi / 2)


def test_polygon_through_same_code_and_orientation():
    sq = [(0, 0), (0, 1), (1, 1), (1, 0)]  # clockwise: reordered
    b = RigidBody.polygon(sq, 3.0)
    assert b.J == pytest.approx(3.0 * 2 / 12)
    hexa = [(math.cos(k * math.pi / 3), math.sin(k * math.pi / 3)) for k in range(6)]
    h = RigidBody.polygon(hexa, 1.0)
    # regular hexagon of circumradius 1 resting on a vertex: J = 5/12 m R^2
    assert h.J == pytest.approx(5 / 12, rel=1e-12)
    trap = RigidBody.polygon([(-1, 0), (1, 0), (0.5, 1), (-0.5, 1)])
    assert len(trap.base) == 2 and trap.theta_ov == pytest.approx(math.pi - math.atan2(1, 0.5))


@pytest.mark.parametrize(
    "kwargs, field",
    [
        ({"vertices": [(0, 0), (2, 0), (1, 0.3), (1, 2)]}, "vertices: polygon is not convex"),
        ({"vertices": [(0, 0), (1, 1), (1, 0), (0, 1)]}, "vertices: .* or its edges crossing"),
        ({"vertices": [(0, 0), (1, 0), (1, 1), (0, 1)], "mass": -1.0}, "mass"),
        ({"vertices": [(0, 0), (1, 0)]}, "vertices"),
    ],
)
def test_bad_polygons_name_the_field(kwargs, field):
    with pytest.raises(ValueError, match=field):
        RigidBody.polygon(**kwargs)


def test_bad_friction_and_sizes():
    with pytest.raises(ValueError, match="mu_d"):
        FrictionLaw(0.3, 0.4)
    with pytest.raises(ValueError, match="mu_s"):
        FrictionLaw(-0.1)
    with pytest.raises(ValueError, match="width"):
        RigidBody.rectangle(-1.0, 1.0)
    law = FrictionLaw(0.4, 0.2, 3.0)  # seed 002 eq. 7
    assert law.mu(0.0) == pytest.approx(0.4)
    assert law.mu(1.0) == pytest.approx(0.2 + 0.2 * math.exp(-3.0))
    assert np.all(FrictionLaw(0.4, 0.2, 0.0).mu([0, 1, 5]) == 0.4)  # C = 0: mu = mu_s


@pytest.mark.parametrize("mass", [1e-12, 1e15])
def test_a_body_on_rigid_ground_moves_alike_at_any_mass(mass):
    # gravity, the base's push, the contact forces and friction all scale with the mass: the
    # motion on rigid ground is the same at every mass. At 1e-12 kg Moreau-Jean slid the seed's
    # A5 prism 1.68 m (0.0495 m at 1e-3 to 1e9 kg) and the event-driven solver missed a
    # touchdown; at 1e15 kg both found no LCP solution. Bounds: the sliding prism's J is not
    # read (to round-off); the rocking one's J / m differs in its last bit, amplified at most
    # to the event solver's tolerances (rtol 1e-9) over its impacts
    from nsdyn.models.contact import BaseMotion, simulate_event, simulate_moreau

    T = 2.18  # (seed 002's case A5: a 1.6 m/s^2 displacement sine, switched on at once)
    sine = BaseMotion.displacement_sine(1.6 * (T / (2 * math.pi)) ** 2, T, 5, "impulsive")
    law = FrictionLaw(0.57, 0.29)
    for run in (simulate_event, simulate_moreau):
        for (w, h), tilt, tol in (((1.1, 1.0), None, 1e-12), ((0.5, 1.5), 0.5, 1e-6)):
            r = [run(RigidBody.rectangle(w, h, m), law, sine, t_end=5 * T + 2,
                     theta0_over_alpha=tilt) for m in (2500.0, mass)]  # fmt: skip
            assert np.abs(r[1].q - r[0].q).max() <= tol and np.array_equal(r[1].mode, r[0].mode)


def test_a_body_with_an_overhang_overturns_on_each_side_at_its_own_tilt():
    # a quadrilateral whose right side leans out over its base: rocking about the right corner
    # (theta < 0) it lies on that side at atan(0.5) = pi - its interior angle there; about the
    # left corner (theta > 0) only at pi / 2, where its vertical left side meets the ground.
    # Both solvers applied the smaller angle to both sides: launched about the left corner
    # with the energy to reach 0.6 rad (below the centre of mass's angle there, 1.31 rad) it
    # was "overturned" at 0.4636 rad, and theta0 = 0.5 was refused
    from nsdyn.models.contact import simulate_event, simulate_moreau

    body = RigidBody.polygon([(-1, 0), (0.5, 0), (1.5, 0.5), (-1, 0.5)], 100.0)
    assert body.overturn_tilts == pytest.approx((math.pi / 2, math.atan(0.5)), rel=1e-12)
    assert body.overturned(-0.47) and not body.overturned(1.5)
    R, alpha, J_O = body.corner_geometry(-1)
    from nsdyn.models.contact.results import slenderness  # (tip-over: the pivot side's alpha)

    assert slenderness(body, 0.3) == alpha and slenderness(body, -0.3) == slenderness(body) < 1.1
    peak = 0.6  # energy: J_O w^2 / 2 = m g R (cos(alpha - peak) - cos alpha)
    w = math.sqrt(2 * body.mass * 9.81 * R * (math.cos(alpha - peak) - math.cos(alpha)) / J_O)
    c = body.contacts[np.argmin(body.contacts[:, 0])]  # the left corner: v = w x (0 - c)
    q0, v0 = [0.0, body.y0, 0.0], [w * c[1], -w * c[0], w]
    law = FrictionLaw(2.0, 2.0)  # (no slip: rocking alone)
    for run in (simulate_event, simulate_moreau):
        s = run(body, law, None, t_end=3.0, q0=q0, v0=v0).summary()
        assert not s["overturned"]
        assert s["max_tilt_rad"] == pytest.approx(peak, abs=2e-3)  # (Moreau-Jean: O(h))
    simulate_event(body, law, None, t_end=0.1, theta0=0.5)  # (refused before)
    # past a side's tilt every solver refuses the start (Moreau-Jean ran one step, overturned)
    for run in (simulate_event, simulate_moreau):
        with pytest.raises(ValueError, match=r"^theta0_over_alpha: a tilt of -0.5282 rad starts"):
            run(body, law, None, t_end=0.1, theta0_over_alpha=-0.5)
    # a body on one vertex: each side's edge from it (a kite on its lowest vertex: pi - 3 pi / 4
    # to lay its left edge down, atan(0.5) its right; pi - the interior angle gave 1.25 both)
    kite = RigidBody.polygon([(0, 0), (2, 1), (0, 2), (-1, 1)])
    assert kite.overturn_tilts == pytest.approx((math.pi / 4, math.atan(0.5)), rel=1e-12)


def test_a_start_tilt_past_a_side_is_refused_in_a_scene_naming_its_key(tmp_path, capsys):
    # the scene named "motion: theta0:"; and a side past pi / 2 offered a range the pi / 2 cap
    # of every start tilt refused
    from nsdyn.cli import main
    from nsdyn.models.contact.event import tilt_angle

    tri = RigidBody.polygon([(0, 0), (1, 0), (3, 1)])  # (sides 2.82 and atan(0.5) rad)
    with pytest.raises(ValueError, match=r"expected a tilt between -0.4636 and 1.571 rad$"):
        tilt_angle(tri, -0.5, None)
    p = tmp_path / "s.toml"
    p.write_text('[scene]\nkind = "contact"\n[body]\nvertices = [[0, 0], [1, 0], [3, 1]]\n'
                 "[friction]\nmu_s = 0.5\nmu_d = 0.5\n"
                 "[motion]\ntheta0 = -0.5\nt_end = 1.0\n")  # fmt: skip
    assert main(["run", str(p), "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err.startswith(
        f"nsdyn run: error: {p}: motion.theta0: a tilt of -0.5 rad starts the body overturned"
    )


def test_a_body_leaning_past_its_tip_over_angle_is_measured_by_that_side_s_alpha(tmp_path):
    # a quadrilateral with alpha 0.412 rad about its left corner and 0.602 about its right
    # (atan of each corner's horizontal over vertical distance to the centre of mass), started
    # at -0.65 rad about the right corner and falling: the outcome read |theta| / 0.412 = 1.64
    # alpha, the other side's; the side it leans on puts it at 0.677 / 0.602 = 1.12 alpha
    from nsdyn.models.contact.results import slenderness
    from nsdyn.models.contact.scene import outcome, run_scene

    V = [[-0.3, 0.0], [0.3, 0.0], [0.0, 1.2], [-0.3, 1.2]]
    body = RigidBody.polygon(V, 1.0)
    cx, cy = _centroid(V)  # (the centre of mass, relative to which alpha is measured)
    assert slenderness(body, 0.1) == pytest.approx(math.atan2(cx + 0.3, cy), rel=1e-12)
    assert slenderness(body, -0.1) == pytest.approx(math.atan2(0.3 - cx, cy), rel=1e-12)
    cfg = {"scene": {"kind": "contact"}, "body": {"vertices": V, "mass": 100.0},
           "friction": {"mu_s": 0.8, "C": 0.0}, "motion": {"theta0": -0.65, "t_end": 0.3},
           "solver": {"method": "event"}}  # fmt: skip
    s = run_scene(cfg, source="t.toml", out_dir=tmp_path, figures=False, quiet=True)
    assert s["past_tip_over_at_end"] and not s["overturned"]
    ratio = abs(s["final_tilt_rad"]) / slenderness(body, -0.1)
    assert f"({ratio:.3g} alpha)" in outcome(s)[1] and 1 < ratio < 1.2


def _centroid(V):
    """Area centroid of a polygon (shoelace)."""
    x, y = np.asarray(V, float).T
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    cr = x * y1 - x1 * y
    a = cr.sum() / 2
    return ((x + x1) * cr).sum() / (6 * a), ((y + y1) * cr).sum() / (6 * a)
