"""The contact benchmark's error measures (nsdyn.bench.contact._errors): exact on hand-made
histories."""

from types import SimpleNamespace

import numpy as np
import pytest

from nsdyn.bench.contact import _errors


def _hist(theta, slide):
    t = np.linspace(0.0, 1.0, len(theta))
    q = np.zeros((len(t), 3))
    q[:, 2] = theta
    return SimpleNamespace(t=t, q=q, slide=np.asarray(slide, float))


def test_a_spurious_slide_is_measured_against_the_body_not_a_reference_that_does_not_slide():
    # the reference slides 1e-12 m: divided by it, 1e-5 m of spurious slip read 1e7
    ref = _hist([0.0, 0.01, 0.0], [0.0, 1e-12, 0.0])
    res = _hist([0.0, 0.011, 0.0], [0.0, 1e-5, 2e-5])
    e_theta, e_slide = _errors(res, ref, alpha=0.2, b=0.25)
    assert e_theta == pytest.approx(0.001 / 0.2, rel=1e-12)
    assert e_slide == pytest.approx((2e-5) / 0.25, rel=1e-12)
    # up to t_max only (the early error), and a run cut short has none
    assert _errors(res, ref, alpha=0.2, b=0.25, t_max=0.0)[1] == 0.0
    short = _hist([0.0, 0.01], [0.0, 0.0])
    assert all(np.isnan(_errors(short, ref, alpha=0.2, b=0.25)))
