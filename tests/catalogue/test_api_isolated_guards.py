"""The library calls of the isolated, deck and 3D-building families refuse an argument that
has no meaning or would be dropped, naming it, where before they ran on it or failed inside.

Each case gave a result without a word or a traceback from inside: a sparse full rung stepped
past the record's samples (peaks 4.6 times too large at dt = 1 s), ``frozen_normal="no"``
read as True, ``mu=None`` failed as a singular matrix at t = 0, a switch law with eta = 0
never found stick, a triple pendulum dropped a friction and radius given to it, a deck run
given both output times and an end dropped the end, β K damping dropped a modal cut-off, a
rate without mu_fast was dropped, text sizes and steps failed inside numpy.
"""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

import nsdyn
from nsdyn.ground import read_motion3
from nsdyn.models.isolated.bearings import Bearing, BearingError, Friction
from nsdyn.models.isolated.deck import rigid_deck, simulate_plane
from nsdyn.models.isolated.pairs_sparse import building_pairs_sparse
from nsdyn.models.isolated.pairs_sparse_run import simulate_pairs_sparse
from nsdyn.models.isolated.tfp import TripleBearing
from nsdyn.structure import Section3D, load_frame3d, regular_building_3d

FPS = Bearing(Friction(0.04, 0.07, rate=30.0), radius=2.2, d_cap=0.35)
TFP = dict(R1=2.2, R2=0.3, R3=0.3, R4=2.2, mu1=0.06, mu2=0.02, mu3=0.02, mu4=0.10, d1=0.3,
           d2=0.05, d3=0.05, d4=0.3)  # fmt: skip
SHEAR = nsdyn.shear_building([2e4, 1e4], [2e7], 0.05, isolation=nsdyn.Isolation())
COL = Section3D(E=2.1e11, G=8.1e10, A=1e-2, I_y=1e-4, I_z=1e-4, J=2e-4, rho_A=78.5)


@pytest.mark.parametrize(
    ("call", "err", "match"),
    [
        (lambda: nsdyn.Isolation(frozen_normal="no"), TypeError,
         r"^isolation.frozen_normal: expected True or False"),
        (lambda: nsdyn.Isolation(mu=None), ValueError, r"^isolation.mu: expected a finite"),
        (lambda: nsdyn.Isolation(mu=True), ValueError, r"^isolation.mu: expected a finite"),
        (lambda: nsdyn.Isolation(law="switch", eta=0.0), ValueError,
         r"^isolation.eta: the switch law needs a positive stick band"),
        (lambda: nsdyn.build_system("office-11", fidelity="rigid", lumped="yes"), TypeError,
         r"^lumped: expected True or False"),
        (lambda: regular_building_3d("b", [6.0], [5.0], [3.0], COL, COL, COL, 1, 1, 1e4,
                                     diaphragms="no"), TypeError,
         r"^diaphragms: expected True or False"),
        (lambda: TripleBearing(friction=Friction(0.04), **TFP), BearingError,
         r"bearing.friction: derived from the surfaces"),
        (lambda: TripleBearing(radius=2.0, **TFP), BearingError,
         r"bearing.radius: derived from the surfaces"),
        (lambda: Friction(0.04, rate=30.0), BearingError,
         r"rate: the rate of the change from mu_slow to mu_fast; expected mu_fast"),
        (lambda: rigid_deck(2e6, 9e7, [[-10, -6], [10, -6], [0, 6]], None), TypeError,
         r"^bearings: expected a Bearing"),
        (lambda: rigid_deck(2e6, 9e7, [[-10, -6], [10, -6], [0, 6]], [FPS, FPS, "x"]),
         TypeError, r"^bearings\[2\]: expected a Bearing .* got str$"),  # (it said "got list")
        (lambda: building_pairs_sparse(load_frame3d("portal-3d"), FPS, eccentricity=(0, 5.0)),
         ValueError, r"^eccentricity\[1\]: expected a fraction .* got 5\.0$"),  # (said f_y)
        (lambda: Section3D(E=2.1e11, G=8.1e10, A="x", I_y=1e-4, I_z=1e-4, J=2e-4, rho_A=1.0),
         ValueError, r"^section A: expected a positive finite number, got 'x'"),
        (lambda: nsdyn.simulate(SHEAR, nsdyn.Harmonic(1.0, 1.0), method="newmark", dt="0.01",
                                n_periods=2), ValueError, r"^dt: expected a positive fixed step"),
        (lambda: nsdyn.simulate(SHEAR, nsdyn.Harmonic(1.0, 1.0), method="newmark", dt=-1.0,
                                n_periods=2), ValueError, r"^dt: expected a positive fixed step"),
        (lambda: nsdyn.simulate(SHEAR, nsdyn.Harmonic(1.0, 1.0), t_end="2"), ValueError,
         r"^t_end: expected a finite end time"),
        (lambda: nsdyn.simulate(SHEAR, nsdyn.Harmonic(1.0, 1.0), x0="zeros", n_periods=2),
         ValueError, r"^x0: expected finite numbers, the state"),
        # messages that named another cause: "None: no bundled frame", "need at least one
        # bay", "got str" for a dict, "1 or 1 sections", frozen_normal=False asked for
        (lambda: nsdyn.load_frame(None), TypeError, r"^frame: expected a bundled frame's name"),
        (lambda: regular_building_3d("b", [-6.0], [5.0], [3.0], COL, COL, COL, 1, 1, 1e4),
         ValueError, r"^bays_x: expected positive sizes"),
        (lambda: regular_building_3d("b", [6.0], [5.0], [3.0], {"E": 1}, COL, COL, 1, 1, 1e4),
         TypeError, r"^columns: expected a Section3D or a list of them, got dict"),
        (lambda: regular_building_3d("b", [6.0], [5.0], [3.0], [COL, COL], COL, COL, 1, 1, 1e4),
         ValueError, r"^columns: expected 1 section\(s\) \(one per storey\), got 2"),
        (lambda: nsdyn.simulate(nsdyn.shear_building([2e4, 1e4], [2e7], 0.05,
                                isolation=nsdyn.Isolation(contact="unilateral")),
                                nsdyn.Harmonic(1.0, 1.0), n_periods=2), ValueError,
         r"contact 'unilateral' needs the normal forces as multipliers: contact rows"),
    ],
)  # fmt: skip
def test_calls_refuse_what_they_would_drop_or_fail_inside_on(call, err, match):
    with pytest.raises(err, match=match):
        call()


def test_a_triple_pendulum_copied_by_replace_derives_its_radius_again():
    t = TripleBearing(**TFP)
    assert t.radius == TFP["R1"] + TFP["R4"] and t.friction.mu_slow == TFP["mu2"]
    u = dataclasses.replace(t, R1=3.0)
    assert u.radius == 3.0 + TFP["R4"]  # (the copy's derived values, not the old ones)


def test_deck_and_sparse_runs_refuse_what_they_would_drop():
    m3 = read_motion3("synthetic-wn-40s").window(0.0, 2.0)
    deck = rigid_deck(1e5, 1e6, [[-1.0, -1.0], [1.0, -1.0], [0.0, 1.0]], FPS)
    with pytest.raises(ValueError, match=r"^t_end: give t_eval .* or t_end and dt_out, not"):
        simulate_plane(deck, m3, t_eval=np.linspace(0.0, 1.0, 11), t_end=2.0)
    # a deck without triple pendulums has no internal slips to give (it offered "or 6")
    with pytest.raises(ValueError, match=r"^y0: expected six finite numbers \[x, y, theta, "
                       r"vx, vy, omega\], got \[1\.0\]$"):  # fmt: skip
        simulate_plane(deck, m3, y0=[1.0])
    with pytest.raises(ValueError, match=r"^phi: expected finite force ratios F/N, got \[nan\]"):
        TripleBearing(**TFP).backbone([float("nan")])  # (it gave NaN back)
    portal = load_frame3d("portal-3d")
    with pytest.raises(ValueError, match=r"^f_damp: the modal damping's cut-off"):
        building_pairs_sparse(portal, FPS, damping="stiffness", f_damp=3.0)
    s = building_pairs_sparse(portal, FPS, damping="stiffness")
    # a step past the record's 0.01 s samples skips them: the peaks came out 4.6 times large
    with pytest.raises(ValueError, match=r"^dt: a fixed step of 0.2 s is longer than the "
                                         r"record's sampling step 0.01 s"):  # fmt: skip
        simulate_pairs_sparse(s, m3, dt=0.2)
    r = simulate_pairs_sparse(s, m3, dt=np.float32(0.005), t_end=0.05)  # numpy scalars: numbers
    assert r.t[-1] == pytest.approx(0.05)


def test_a_friction_coefficient_above_one_is_said():
    # 5 for 5 %: mu = 5 holds the isolators stuck below 5 g of ground acceleration, a run
    # that looked like any other (a slip of 1.8e-6 m); said as a scene notes it, naming the
    # isolator's entry, once (not again for each copy a run makes); mu = 1 (the Coulomb
    # bound of any sliding bearing's data) and a law without friction are not said
    import warnings

    said = (r"^isolation.mu = 5: a friction coefficient above 1 \(sliding isolators' are about "
            r"0\.01-0\.2\); a percentage given as a number\?$")  # fmt: skip
    with pytest.warns(nsdyn.NotedWarning, match=said):
        iso = nsdyn.Isolation(mu=5)
    with pytest.warns(nsdyn.NotedWarning, match=r"^isolation.mu\[1\] = 5: "):
        nsdyn.Isolation(mu=(0.05, 5.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error", nsdyn.InputWarning)
        nsdyn.Isolation(mu=1.0)
        nsdyn.Isolation(mu=(0.05, 1.0))
        iso.changed(law="switch")  # (a copy a run makes: said when made)
        iso.changed(g=9.8)  # (another g: its own note, if any, not the mu's again)
    with pytest.warns(nsdyn.NotedWarning, match=r"^isolation.g = 9810 m/s²") as got:
        iso.changed(g=9810.0)
    assert [str(w.message) for w in got if "isolation.mu" in str(w.message)] == []
    with pytest.warns(nsdyn.InputWarning, match=r"^isolation.mu = 5.0 not used") as got:
        nsdyn.Isolation(mu=5.0, law="none")  # (unread: not said as too high)
    assert [str(w.message) for w in got if "above 1" in str(w.message)] == []


def test_a_friction_coefficient_the_law_none_leaves_unread_is_said():
    # Isolation(law="none", mu=0.2) ran without friction and without a word, while a scene
    # notes its unread mu; said once (not again for a copy changing another field, nor by a
    # scene's isolation, whose note of unused keys says it), and again for a new mu or a new
    # law "none"; the default mu or a zero one with the law "none" is not said
    import warnings

    from nsdyn.models.isolated.system import isolation_from_config

    said = r"^isolation.mu = 0.2 not used: the law 'none' has no friction"
    with pytest.warns(nsdyn.InputWarning, match=said):
        iso = nsdyn.Isolation(law="none", mu=0.2)
    with warnings.catch_warnings():
        warnings.simplefilter("error", nsdyn.InputWarning)
        nsdyn.Isolation(law="none")
        nsdyn.Isolation(law="none", mu=(0.0, 0.0))
        iso.changed(c=1.0e5)
        iso.changed(law="arctan")
        isolation_from_config({"law": "none", "mu": 0.2}, "scene.toml")
    with pytest.warns(nsdyn.InputWarning, match=r"^isolation.mu = 0.3 not used"):
        iso.changed(mu=0.3)
    with pytest.warns(nsdyn.InputWarning, match=said):
        nsdyn.Isolation(mu=0.2).changed(law="none")


@pytest.mark.parametrize(("g", "guess"), [(9810.0, "in mm/s²?"), (1.0, "in g?")])
def test_a_gravity_in_other_units_is_said(g, guess):
    # the normal forces, and their friction, are m g: g = 9810 (mm/s²) ran with friction
    # 1000x and an isolator slip of 0.4 mm for 26 mm, said like any other run; Earth's
    # 9.78-9.83 m/s² (and the 9.80665 standard) are not said
    import warnings

    said = rf"^isolation.g = {g:g} m/s²: Earth's gravity is 9.81 m/s².*; {re.escape(guess)}$"
    with pytest.warns(nsdyn.NotedWarning, match=said):
        nsdyn.Isolation(g=g)
    with pytest.warns(nsdyn.NotedWarning, match=rf"^deck.g = {g:g} m/s²: "):
        rigid_deck(m=1.0e4, J=1.0e4, positions=[(0.0, 0.0)],
                   bearings=[Bearing(Friction(0.05))], g=g)  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("error", nsdyn.InputWarning)
        for earth in (9.78, 9.80665, 9.81, 9.83):
            nsdyn.Isolation(g=earth)
