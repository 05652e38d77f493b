"""Rigid body on compliant ground: static settlement, energy, rigid limit, scene and CLI.

Physics checks: settlement under gravity is m g / (n k) per corner (statics); in free motion the
mechanical energy (kinetic + potential + springs) never increases, the dissipation by dashpots
and slip never decreases and the energy balance closes (work-energy theorem, O(h^2) for the
central-difference scheme); as the ground stiffens, the slide and the peak tilt of seed 002's
case B1 (slides and rocks) converge to the event-driven rigid-ground answer.
"""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from nsdyn.ground import G_EARTH
from nsdyn.models.contact import BaseMotion, FrictionLaw, RigidBody, simulate_event
from nsdyn.models.contact.compliant import CompliantGround, simulate_compliant
from nsdyn.models.contact.scene import format_summary, run_scene
from nsdyn.models.scenefile import SceneError, read_toml

SCENE = Path(__file__).parents[3] / "examples" / "scenes" / "contact-compliant-C2.toml"


@pytest.mark.parametrize("k", [1e6, 1e8])
def test_static_settlement(k):
    body = RigidBody.rectangle(1.0, 2.0, 500.0)
    gr = CompliantGround.from_ratio(body, k, 0.7)
    res = simulate_compliant(body, FrictionLaw(0.5), gr, t_end=40 / math.sqrt(2 * k / 500),
                             settled=False, dt_out=1e-4)  # fmt: skip
    delta = body.y0 - res.q[-1, 1]
    assert delta == pytest.approx(500.0 * G_EARTH / (2 * k), rel=1e-6)
    assert abs(res.q[-1, 2]) < 1e-9 and res.mode[-1] == 0  # at rest on both corners


@pytest.mark.parametrize("C", [0.0, math.inf])
def test_energy_never_increases_and_balance_closes(C):
    body = RigidBody.rectangle(0.6, 1.8, 300.0)
    gr = CompliantGround.from_ratio(body, 1e7, 0.1)
    errs = []
    for h in (2e-5, 1e-5):
        res = simulate_compliant(body, FrictionLaw(0.6, 0.3, C), gr, t_end=2.0, h=h,
                                 v0=[1.5, 0.0, 0.8], dt_out=1e-3)  # fmt: skip
        E = res.mechanical_energy(body.mass, body.J)
        D = res.dissipated(body.mass, body.J)
        scale = E[0] - E.min()
        assert scale > 100.0  # the body slid and rocked
        # never increases: up to the scheme's O(h^2) energy oscillation of the stiff springs
        assert np.all(np.diff(E) <= 1e-3 * scale)
        assert np.all(np.diff(D) >= -1e-3 * scale)
        errs.append(np.max(np.abs(E + D - E[0])) / scale)
    assert errs[1] < 1e-3
    assert errs[1] < 0.6 * errs[0]  # first order in h (dashpots and mu(v) use v(t - h/2)): 0.50


def test_converges_to_rigid_ground():
    # seed 002 case B1 (1.1 x 2.2 m, T = 2.5 s, mu = mu_s = 0.57), impulsive start: slides, rocks
    body = RigidBody.rectangle(1.1, 2.2, 2272.6 * 2.2)
    T = 2.5
    A = 1.6 * (T / (2 * math.pi)) ** 2
    law, mo = FrictionLaw(0.57, 0.29, 0.0), BaseMotion.displacement_sine(A, T, 5)
    t_end = 3.0
    ref = simulate_event(body, law, mo, t_end=t_end, dt_out=0.001).summary()
    errs = []
    for k in (1e8, 1e9, 1e10):
        s = simulate_compliant(body, law, CompliantGround.from_ratio(body, k, 1.0), mo,
                               t_end=t_end, dt_out=0.001).summary()  # fmt: skip
        errs.append((abs(s["max_slide_m"] / ref["max_slide_m"] - 1),
                     abs(s["max_tilt_rad"] / ref["max_tilt_rad"] - 1)))  # fmt: skip
    assert ref["max_tilt_rad"] > 5e-3 and ref["max_slide_m"] > 0.01
    # the error against the rigid ground falls as k^(-1/2) (the contact time scale sqrt(m / k)):
    # sqrt(10) = 3.2 per decade of k, so the compliant runs converge to the rigid one
    for j in (0, 1):
        assert 2.0 < errs[0][j] / errs[1][j] < 5.0 and 2.0 < errs[1][j] / errs[2][j] < 5.0, errs


def test_a_flat_drop_on_undamped_ground_lands_and_bounces_back_as_the_spring_mass():
    """Dropped flat from H = 5 cm onto undamped corners (k = 1e8 N/m each), the block lands
    at t_l = sqrt(2 H / g) (free fall) with v = g t_l, leaves (pi + 2 atan(d w / v)) / w later
    (the spring-mass arc about the settled state d = m g / (2 k), w = sqrt(2 k / m): 7.1 ms),
    climbs back to H (no loss) and lands again 2 t_l later: in
    3.5 sqrt(2 H / g) the summary counts 4 corner touchdowns (its impacts), 2 hops and 2
    lift-offs, on the result as in its summary."""
    m, k, H = 1000.0, 1e8, 0.05
    body = RigidBody.rectangle(1.0, 1.0, m)
    t_land, w = math.sqrt(2 * H / G_EARTH), math.sqrt(2 * k / m)
    t_half = (math.pi + 2 * math.atan(m * G_EARTH / (2 * k) * w / (G_EARTH * t_land))) / w
    r = simulate_compliant(body, FrictionLaw(0.5), CompliantGround.from_ratio(body, k, 0.0),
                           t_end=3.5 * t_land, q0=[0.0, body.y0 + H, 0.0], v0=[0.0] * 3,
                           settled=False, dt_out=1e-4)  # fmt: skip
    dn = np.diff(r.n_on)
    t_change = r.t[1:][dn != 0]  # the first output past each change
    want = [t_land, t_land + t_half, 3 * t_land + t_half, 3 * t_land + 2 * t_half]
    assert np.allclose(t_change, want, atol=1.1e-4), (t_change, want)  # an output step and h
    assert list(dn[dn != 0]) == [2, -2, 2, -2]
    s = r.summary()
    assert (s["n_impacts"], s["n_hops"], s["n_liftoffs"]) == (4, 2, 2)
    assert r.n_impacts == 4  # the result's field is the summary's count (it read 0 before)


def test_a_tilted_start_rocks_as_the_rigid_block_from_its_scene_too(tmp_path):
    """Released at theta0 = alpha / 2 on stiff ground, the 0.5 x 1.5 m block rocks back to
    theta = 0 at the rigid block's time: the quadrature of I_O theta'' = -m g R sin(alpha -
    theta) gives 0.4330091 s; the ground's compliance (settlement m g / k = 1e-5 m) shifts it
    by O(1e-5) relative. A scene's motion.theta0 reaches the compliant run (it started upright
    and reported a peak tilt of 0)."""
    from scipy.integrate import solve_ivp

    body = RigidBody.rectangle(0.5, 1.5, 1000.0)
    alpha, R = math.atan(1.0 / 3.0), math.hypot(0.25, 0.75)
    i_o = 1000.0 * (0.5**2 + 1.5**2) / 12 + 1000.0 * R**2

    def down(t, y):
        return y[0]

    down.terminal, down.direction = True, -1
    ref = solve_ivp(lambda t, y: [y[1], -1000.0 * G_EARTH * R * math.sin(alpha - y[0]) / i_o],
                    [0.0, 2.0], [0.5 * alpha, 0.0], events=down, rtol=1e-12,
                    atol=1e-14).t_events[0][0]  # fmt: skip
    k = 1e9
    r = simulate_compliant(body, FrictionLaw(0.8, 0.8, 0.0), CompliantGround(k, 0.1 * math.sqrt(
        k * 1000.0)), t_end=0.5, theta0_over_alpha=0.5, dt_out=1e-4)  # fmt: skip
    th = r.q[:, 2]
    assert th[0] == pytest.approx(0.5 * alpha, rel=1e-14)
    i = int(np.argmax(th <= 0.0))
    t0 = r.t[i - 1] - th[i - 1] * (r.t[i] - r.t[i - 1]) / (th[i] - th[i - 1])
    assert t0 == pytest.approx(ref, rel=1e-4)
    cfg = read_toml(SCENE)
    cfg["motion"] = {"theta0": 0.1, "t_end": 0.2}
    s = run_scene(cfg, source=str(SCENE), out_dir=tmp_path, figures=False, quiet=True)
    assert s["max_tilt_rad"] == pytest.approx(0.1, rel=1e-3)  # (it falls back from 0.1)


def test_run_scene_and_cli(tmp_path, capsys):
    cfg = read_toml(SCENE)
    cfg["motion"]["t_end"] = 1.0
    s = run_scene(cfg, source=str(SCENE), out_dir=tmp_path, figures=True, quiet=True)
    assert s["kind"] == "contact" and s["solver"] == "compliant"
    assert (tmp_path / "contact.npz").exists() and (tmp_path / "contact.png").exists()
    assert s["max_uplift_m"] > 0 and "peak slide" in format_summary(s)
    from nsdyn.cli import main

    rc = main(["run", str(SCENE), "--json", "--out", str(tmp_path), "--t-end", "0.5"])
    assert rc in (0, None)
    js = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert js["solver"] == "compliant" and "n_liftoffs" in js


@pytest.mark.parametrize("ground, field", [
    ({"kind": "soft"}, "ground.kind"),
    ({"kind": "compliant"}, "ground.stiffness"),
    ({"kind": "compliant", "stiffness": -1.0}, "ground.stiffness"),
    ({"kind": "compliant", "stiffness": 1e8, "damping": 1.0, "damping_ratio": 0.1},
     "ground.damping_ratio"),
    ({"kind": "rigid", "stiffness": 1e8}, "ground.stiffness"),
    ({"kind": "compliant", "stiffnes": 1e8}, "stiffnes"),
])  # fmt: skip
def test_bad_ground(ground, field):
    cfg = read_toml(SCENE)
    cfg["ground"] = ground
    with pytest.raises(SceneError, match=field):
        run_scene(cfg, source=str(SCENE), out_dir=Path("/nonexistent"), figures=False,
                  quiet=True)  # fmt: skip


@pytest.mark.parametrize("method", ["moreau", "event"])
def test_a_method_on_a_compliant_ground_is_refused_not_ignored(method):
    cfg = read_toml(SCENE)
    cfg["ground"] = {"kind": "compliant", "stiffness": 1e8}
    cfg.setdefault("solver", {})["method"] = method
    with pytest.raises(SceneError, match="solver.method: a compliant ground"):
        run_scene(cfg, source=str(SCENE), out_dir=Path("/nonexistent"), figures=False,
                  quiet=True)  # fmt: skip


def test_a_run_ends_on_its_end_with_the_state_there():
    # the steps write their starts, so the row at t_end was never written: the histories ended
    # one output step early; the end's row is the state at t_end, and it equals the longer
    # run's row there to the sampling's O(h) (a row is the state at the nearest step start)
    body = RigidBody.rectangle(0.6, 1.8, 300.0)
    gr = CompliantGround.from_ratio(body, 1e7, 0.1)
    kw = dict(h=2e-5, v0=[1.5, 0.0, 0.8], dt_out=1e-2)
    short = simulate_compliant(body, FrictionLaw(0.6), gr, t_end=0.5, **kw)
    longer = simulate_compliant(body, FrictionLaw(0.6), gr, t_end=0.6, **kw)
    assert short.t[-1] == 0.5 and not np.isnan(short.q).any()
    k = int(np.flatnonzero(np.isclose(longer.t, 0.5))[0])
    vmax = np.abs(longer.v[k - 1 : k + 2]).max(axis=0)
    assert np.all(np.abs(short.q[-1] - longer.q[k]) <= 2e-5 * vmax + 1e-12)


def test_every_output_time_the_last_steps_leave_is_a_row():
    # output times within the last half step (0.1 and t_end = 0.100005 at h = 2e-5): the
    # first was given the end's state and the end's row dropped
    body = RigidBody.rectangle(0.6, 1.8, 300.0)
    gr = CompliantGround.from_ratio(body, 1e7, 0.1)
    r = simulate_compliant(body, FrictionLaw(0.6), gr, t_end=0.100005, h=2e-5,
                           v0=[1.5, 0.0, 0.8], dt_out=0.01)  # fmt: skip
    assert r.t.size == 12 and r.t[-1] == 0.100005 and not np.isnan(r.q).any()
    # each within h of its time: the state at the nearest step (|dq| <= |v| h)
    assert np.all(np.abs(r.q[-1] - r.q[-2]) <= 2e-5 * np.abs(r.v[-2:]).max(axis=0) + 1e-12)
