"""Inputs of the contact family's kernel-form base motion: refused where they are made.

Source of the expected behaviour: the library's input convention (a ValueError naming the
argument and its expected form, never an error deep in a solver).
"""

from __future__ import annotations

import numpy as np
import pytest


@pytest.mark.parametrize(
    "kw, field",
    [({"ex": [1.0, 2.0], "tab_h": [1.0], "tab_v": []}, "ex"),
     ({"ex": [0.0] * 8, "tab_h": [0.0, float("nan")], "tab_v": []}, "tab_h"),
     ({"ex": [0.0] * 8, "tab_h": [0.0, 1.0, 2.0], "tab_v": [0.0]}, "tab_v"),
     ({"ex": [0.0] * 8, "tab_h": [], "tab_v": [], "jumps": [1.0, 2.0, 3.0]}, "jumps")],
)  # fmt: skip
def test_a_base_motion_in_kernel_form_is_checked_where_it_is_made(kw, field):
    # a list reached the solver as "'list' object has no attribute 'size'", a NaN table as a
    # step underflow at t = 0
    from nsdyn.models.contact.excite import BaseMotion

    with pytest.raises(ValueError, match=rf"^{field}: expected finite numbers of shape"):
        BaseMotion(**kw)


@pytest.mark.parametrize(
    "args, field", [((-1e9,), "k"), ((1e9, -1.0), "c"), ((1e9, 0.0, "x"), "k_t"),
                    ((1e9, 0.0, 0.0), "k_t")],
)  # fmt: skip
def test_compliant_ground_names_its_own_arguments(args, field):
    # a Python caller typed k, c, k_t; the messages named the scene's fields (stiffness,
    # damping, stick_stiffness), and a text k_t was math.isfinite's TypeError
    from nsdyn.models.contact.compliant import CompliantGround

    with pytest.raises(ValueError, match=rf"^{field}: expected"):
        CompliantGround(*args)


def test_a_base_motion_of_lists_is_the_kernels_arrays_and_a_ratio_checks_its_stiffness():
    # lists are taken (float64, C-contiguous: the kernels' one layout, no second compile);
    # from_ratio's negative k was sqrt's "math domain error", its zeta named damping_ratio
    from nsdyn.models.contact.body import RigidBody
    from nsdyn.models.contact.compliant import CompliantGround
    from nsdyn.models.contact.excite import BaseMotion

    m = BaseMotion([0.0] * 8, np.arange(3.0)[::2], [], np.asfortranarray([[0.5, 1.0]] * 2))
    for a in (m.ex, m.tab_h, m.tab_v, m.jumps):  # (a strided table, Fortran-order jumps)
        assert a.dtype == np.float64 and a.flags.c_contiguous
    assert m.tab_h.tolist() == [0.0, 2.0] and m.jumps.tolist() == [[0.5, 1.0]] * 2
    with pytest.raises(ValueError, match=r"^tab_h: expected finite numbers of shape \(n,\)"):
        BaseMotion([0.0] * 8, np.array(5.0), [])  # (a 0-D value is no table)
    body = RigidBody.rectangle(1.0, 2.0, 1000.0)
    with pytest.raises(ValueError, match=r"^k: expected a positive stiffness"):
        CompliantGround.from_ratio(body, -1e9, 0.1)
    with pytest.raises(ValueError, match=r"^zeta: expected a non-negative damping ratio"):
        CompliantGround.from_ratio(body, 1e9, -0.1)


def test_an_output_step_longer_than_the_run_is_refused_by_either_solver():
    # Moreau-Jean took dt_out = 0.005 s over a 0.002 s run and returned its one sample at
    # t = 0, a "final" tilt of the start; the event-driven solver refuses it
    from nsdyn.models.contact.body import RigidBody
    from nsdyn.models.contact.event import simulate_event
    from nsdyn.models.contact.friction import FrictionLaw
    from nsdyn.models.contact.moreau import simulate_moreau

    body, law = RigidBody.rectangle(1.1, 1.0, 2500.0), FrictionLaw(0.57, 0.29)
    for run in (simulate_event, simulate_moreau):
        with pytest.raises(ValueError, match=r"^dt_out: expected a positive output step no "
                           r"longer than the run \(0\.002 s\), got 0\.005$"):  # fmt: skip
            run(body, law, None, t_end=0.002, dt_out=0.005)
    assert simulate_moreau(body, law, None, t_end=0.002, dt_out=0.002).t[-1] == 0.002
