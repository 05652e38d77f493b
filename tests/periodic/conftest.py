"""Frames shared by the periodic-solution tests (the demo portal frame, Craig-Bampton)."""

import pytest

from nsdyn.models.isolated.statespace import demo_frame
from nsdyn.models.isolated.system import Isolation, build_system


@pytest.fixture(scope="module")
def frame():
    return demo_frame()


@pytest.fixture(scope="module")
def linear_frame(frame):
    return build_system(frame, Isolation(mu=0.0, law="none"), fidelity="cb")


@pytest.fixture(scope="module")
def smooth_frame(frame):
    # a soft arctan law (eps = 50 s/m) keeps the period map smooth enough for finite differences
    return build_system(frame, Isolation(mu=0.1, eps=50.0), fidelity="cb")
