"""Inputs of the contact family's kernel-form base motion: refused where they are made.

Source of the expected behaviour: the library's input convention (a ValueError naming the
argument and its expected form, never an error deep in a solver).
"""

from __future__ import annotations

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
