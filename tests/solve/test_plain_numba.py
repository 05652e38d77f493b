"""Plain numba (``NSDYN_PLAIN_NUMBA=1``): the kernels without numba's internals.

Calls by address (``nsdyn._kaddress``) and borrowed views (``nsdyn._kborrow``) build code from
numba's private interfaces. With the switch on, the loops call their callees directly (``K``
None) and ``borrowed`` / ``alive`` are the identity and nothing: the same arithmetic in the
same order, so the same histories bit for bit (the addresses change which code is linked
where, never an operation; numba does not contract or reorder floating-point operations
without fastmath). Plain kernels keep a cache of their own (same signatures, other code).
"""

import json
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest
from numba import njit
from numba.core import errors

from nsdyn import _kborrow as kb

JIT = os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")


@njit(cache=False)
def _borrow_a_number(x):
    return kb.borrowed(x)


@pytest.mark.skipif(not JIT, reason="nothing is typed under NUMBA_DISABLE_JIT")
def test_borrowing_a_non_array_is_a_typing_error_without_deprecation():
    """numba 0.59 deprecates exceptions other than its own raised while typing (the
    old-style error capturing): the refusal is a TypingError naming the expected form."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", errors.NumbaPendingDeprecationWarning)
        with pytest.raises(errors.TypingError, match="borrowed: expected an array"):
            _borrow_a_number(3.0)


_PROBE = """
import json, os
from numba.core import config
from nsdyn._numba_cache import PLAIN, helper_enabled
from nsdyn.solve import compile_split
print(json.dumps({"plain": PLAIN, "helper": helper_enabled(),
                  "K": compile_split.calls([]) is None, "cache": config.CACHE_DIR,
                  "env": os.environ.get("NUMBA_CACHE_DIR")}))
"""


def test_the_switch_turns_off_addresses_and_the_helper_and_keeps_its_own_cache(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env.update(NSDYN_PLAIN_NUMBA="1", XDG_CACHE_HOME=str(tmp_path), NSDYN_COMPILE_HELPER="1")
    env["NUMBA_DISABLE_JIT"] = "0"  # the switch's effect on compiled code, whatever this mode
    out = subprocess.run([sys.executable, "-c", _PROBE], env=env, capture_output=True,
                         text=True, check=True).stdout  # fmt: skip
    got = json.loads(out.splitlines()[-1])
    folder = str(tmp_path / "nsdyn" / "plain-numba")
    assert got == {"plain": True, "helper": False, "K": True, "cache": folder, "env": folder}


_RUNS = """
import sys
import numpy as np
import nsdyn
from nsdyn.ground import read_motion
from nsdyn.ground.excitation import Harmonic
from nsdyn.models.isolated import Isolation, system_from_matrices
from nsdyn.models.isolated.scene import build_scene, load_scene
from nsdyn.periodic import frame_problem, shoot
from nsdyn.solve.integrate import solve
frame, _ = build_scene(load_scene(None))
motion = read_motion("synthetic-wn-40s")
out = {}
run = nsdyn.simulate(frame, motion, method="radau", t_end=1.0)  # the flat loop, by address
out["radau_x"], out["radau_idr"] = run.x, np.asarray(run.summary()["idr_max"])
ev = nsdyn.simulate(frame.with_isolation(law="switch"), Harmonic(0.5, 2.0), method="event",
                    n_periods=1)
out["event_x"] = ev.x
res = shoot(frame_problem(frame, 0.5), 2.0)  # the period map calls its Jacobian by address
out["orbit"], out["monodromy"] = res.x0, res.monodromy
# generalized-alpha calls the system kernel through the address table
ga = nsdyn.simulate(frame, motion, method="genalpha", t_end=1.0, dt=2e-3)
out["genalpha_x"] = ga.x
# a block lifting off two isolators: the event loop's contact detector, landing and settling
M, Z = np.diag([1000.0, 1000.0, 500.0]), np.zeros((3, 3))
block = system_from_matrices(M, Z, Z, iso_dofs=[[1, 0, 0], [1, 0, 0]],
                             influence=[[1, 0], [0, 1], [0, 0]],
                             isolation=Isolation(k_lam=5e4, c=1e3, mu=0.1, law="switch"),
                             contact_rows=[[0, 1, -1.0], [0, 1, 1.0]])
x0, _ = block.static_equilibrium()
P = block.params(Harmonic(0.0, 0.0, A_ver=1.5 * 9.81, f_ver=2.0))
sol = solve(P, x0, np.linspace(0.0, 0.75, 151), method="event", contact="unilateral",
            restitution=0.5, rtol=1e-8, atol=1e-10)
out["contact_x"] = sol.x
out["contact_events"] = np.array([(e[0], e[1], e[3], e[4]) for e in sol.contact_events])
# a deck on four pendulums under the switch law: force kernel, settling, mode switch by address
from nsdyn.models.isolated import Bearing, Friction, rigid_deck, simulate_plane
deck = rigid_deck(1.0e6, 5.0e7, [[-5.0, -3.0], [5.0, -3.0], [5.0, 3.0], [-5.0, 3.0]],
                  Bearing(Friction(0.04, 0.07, 30.0, 0.075), radius=2.2), ecc=(0.5, 0.3), h=1.0)
dr = simulate_plane(deck, {"f": 0.5, "ax": 3.0, "ay": 2.0, "phase_y_deg": 90.0}, law="switch",
                    t_end=3.0)
out["deck_q"], out["deck_events"] = dr.q, np.asarray(dr.events)
# pair systems: the force kernel and the settlings of stick and of contacts by address
from nsdyn.models.isolated.pairs import from_deck, simulate_pairs
orbit = {"f": 0.5, "ax": 3.0, "ay": 2.0, "phase_y_deg": 90.0}
pr = simulate_pairs(from_deck(deck), orbit, law="switch", t_end=3.0)
out["pairs_q"], out["pairs_events"] = pr.q, np.asarray(pr.events)
out["pairs_radau_q"] = simulate_pairs(from_deck(deck), orbit, law="arctan", t_end=1.0).q
tri = from_deck(rigid_deck(1.0e6, 5.0e7, [[-5.0, -3.0], [5.0, -3.0], [0.0, 4.0]],
                           Bearing(Friction(0.05), radius=2.2), h=1.0))
lift = simulate_pairs(tri, {"f": 2.0, "ax": 3.0, "az": 1.5 * 9.81}, law="switch", t_end=1.0,
                      contact="unilateral")
out["lift_q"], out["lift_offs"] = lift.q, np.array([lift.flights["lift_offs"]])
# a body dropped tilted onto the ground and a cylinder lifting off its tensionless foundation
# under a sliding base: their loops call the right-hand side by address
from nsdyn.models.contact.body import RigidBody
from nsdyn.models.contact.event import simulate_event
from nsdyn.models.contact.friction import FrictionLaw
from nsdyn.models.cylinder.params import CylinderParams
from nsdyn.models.cylinder.simulate import simulate as simulate_cylinder
body = RigidBody.polygon([(-0.4, -1), (0.5, -1), (0.3, 1.1), (-0.5, 0.9)], 2.0)
cr = simulate_event(body, FrictionLaw(0.3, 0.24), t_end=0.8, e_n=0.5,
                    q0=np.array([0.0, body.y0 + 0.1, 0.3]), v0=np.array([0.8, 0.0, -1.0]))
out["body_q"], out["body_impacts"] = cr.q, np.array([cr.n_impacts])
t = np.arange(0.0, 1.0, 1e-3)
ag = np.zeros((t.size, 3))
ag[:, 0] = 12.0 * np.sin(2 * np.pi * 2.0 * t)
cy = simulate_cylinder(CylinderParams().with_(foundation="tensionless", mu=0.3), ag, 1e-3)
out["cylinder_q"], out["cylinder_u"] = cy.q, cy.u
# a rocking block under a record-like table: its loop calls the ground motion by address
from nsdyn.ground import GroundMotion
from nsdyn.models.rocking import RockingBlock, simulate_rocking
rb = simulate_rocking(RockingBlock(width=0.4, height=2.0),
                      GroundMotion(0.0, 1e-3, 0.25 * ag[:, 0]), t_end=1.0)
out["rocking_theta"], out["rocking_impacts"] = rb.theta, rb.impacts
np.savez(sys.argv[1], **out)
"""


@pytest.mark.slow  # compiles the default loop, the event loop (friction and contact events),
# the period map, generalized-alpha, the deck's switch loop, a pair system's loops, a body's
# event loop, the cylinder's loop and the rocking block's loop as plain numba
def test_plain_numba_gives_identical_histories(tmp_path):
    files = {}
    for mode in ("0", "1"):
        env = dict(os.environ, NSDYN_PLAIN_NUMBA=mode, NSDYN_COMPILE_HELPER="0")
        if mode == "1":  # a cache of its own for the test, not the user's plain one
            env["NUMBA_CACHE_DIR"] = str(tmp_path / "plain-cache")
        files[mode] = tmp_path / f"runs-{mode}.npz"
        subprocess.run([sys.executable, "-c", _RUNS, str(files[mode])], env=env, check=True)
    by_address, plain = np.load(files["0"]), np.load(files["1"])
    assert set(by_address.files) == set(plain.files)
    assert by_address["contact_events"].shape[0] > 0  # the contact callees did run
    assert by_address["deck_events"].shape[0] > 0  # the deck settled stick
    assert by_address["pairs_events"].shape[0] > 0  # the pair system settled stick
    assert by_address["lift_offs"][0] > 0  # its contacts opened and settled
    assert by_address["body_impacts"][0] > 0  # the body's events did run
    assert np.abs(by_address["cylinder_u"]).max() > 0.0  # the cylinder's base slid
    assert by_address["rocking_impacts"].shape[0] > 0  # the block rocked and struck
    for key in by_address.files:
        assert np.array_equal(by_address[key], plain[key]), key
