"""Harmonic excitations: a frequency that is not positive is refused where it is built.

Before, ``Harmonic(1, -0.1)`` was accepted and a run later said "dt_out: expected a positive
output step", ``f = 0`` raised ZeroDivisionError and ``f = nan`` "cannot convert float NaN to
integer". The contract: one ValueError naming the field and the expected form.
"""

import math

import pytest

from nsdyn.ground.excitation import Harmonic, HarmonicForce


@pytest.mark.parametrize("f", [-0.1, 0.0, math.nan, -math.inf])
def test_harmonic_needs_a_positive_frequency(f):
    with pytest.raises(ValueError, match=r"^Harmonic\.f_hor: expected a"):
        Harmonic(1.0, f)
    with pytest.raises(ValueError, match=r"^Harmonic\.f_ver: expected a"):
        Harmonic(1.0, 1.0, A_ver=2.0, f_ver=f)
    with pytest.raises(ValueError, match=r"^HarmonicForce\.f: expected a"):
        HarmonicForce(1e3, f, dofs=[0])


def test_a_component_without_amplitude_needs_no_frequency():
    # a vertical-only motion (no horizontal component) and the default no-vertical component
    h = Harmonic(0.0, 0.0, A_ver=3.0, f_ver=2.0)
    assert h.period == math.inf
    assert Harmonic(1.0, 0.5).f_ver == 0.0
    with pytest.raises(ValueError, match=r"positive frequency \[Hz\] \(a non-zero amplitude"):
        Harmonic(1.0, 0.0)
    with pytest.raises(ValueError, match=r"^Harmonic\.f_hor: expected a positive frequency"):
        Harmonic(0.0, -1.0)
