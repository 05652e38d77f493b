"""A record built from arrays takes m/s²: a peak outside the plausible range of m/s² (a record
typed in gal, or in g) warns once, at the caller's line; a plausible, zero or sourced record and
the records derived from a warned one stay silent (the readers' own check is in
test_records_readers)."""

import warnings

import numpy as np
import pytest

from nsdyn import GroundMotion
from nsdyn.ground.motion import PGA_MAX_PLAUSIBLE, PGA_MIN_PLAUSIBLE, UnitWarning
from nsdyn.ground.motion3 import GroundMotion3

T = np.arange(0.0, 2.0, 0.01)
WAVE = np.sin(2 * np.pi * T)  # peak 1 at t = 0.25 s (a sample)


@pytest.mark.parametrize(("peak", "hint"), [(300.0, "gal"), (0.3 * PGA_MIN_PLAUSIBLE, "in g")])
def test_implausible_peak_warns_at_the_callers_line(peak, hint):
    with pytest.warns(UnitWarning, match=f"GroundMotion: horizontal PGA.*{hint}") as rec:
        m = GroundMotion(0.0, 0.01, peak * WAVE)
    assert rec[0].filename == __file__
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m.scaled_to_pga(3.0)  # a record derived from the warned one says nothing more
        m.window(0.5, 1.5)


@pytest.mark.parametrize("peak", [0.0, 3.0, PGA_MAX_PLAUSIBLE])
def test_plausible_or_zero_peak_is_silent(peak):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        GroundMotion(0.0, 0.01, peak * WAVE)
        GroundMotion(0.0, 0.01, 1e3 * WAVE, source="a test in cm/s² on purpose")


def test_three_component_record_checks_its_larger_horizontal_peak():
    with pytest.warns(UnitWarning, match="GroundMotion3: horizontal PGA = 300") as rec:
        g = GroundMotion3(0.0, 0.01, 3.0 * WAVE, 300.0 * WAVE)
    assert rec[0].filename == __file__
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        g.planar(90.0)
        g.velocity("y")
