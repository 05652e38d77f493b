"""Shared factories of standard test systems (frames), used by tests of several modules.

Factories are plain functions exposed as fixtures returning the function (``make_cantilever``,
``make_portal``) or a ready object (``office``, ``office_km``).
"""

from __future__ import annotations

import os

# One BLAS thread: on a shared 2-core machine threaded dense eigensolvers of a few hundred
# dofs run ~10x slower than single-threaded ones (must be set before numpy loads BLAS).
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from hypothesis import settings  # noqa: E402

# no per-example deadline: the first example of a test may import SciPy modules or load numba
# caches, and the shared machines are noisy; correctness, not speed, is what the tests check
settings.register_profile("nsdyn", deadline=None)
settings.load_profile("nsdyn")

from nsdyn.structure import Frame, Section, load_frame, regular_frame  # noqa: E402

# A slender steel-like bar: L / radius of gyration = 10 / sqrt(1e-5 / 1e-2) ~ 316, so the
# first axial frequency lies far above the first two bending frequencies.
CANTILEVER = {"L": 10.0, "E": 2.1e11, "A": 1e-2, "I": 1e-5, "rho_A": 78.5}


def cantilever(
    n_el: int,
    L: float = CANTILEVER["L"],
    E: float = CANTILEVER["E"],
    A: float = CANTILEVER["A"],
    I: float = CANTILEVER["I"],
    rho_A: float = CANTILEVER["rho_A"],
    angle: float = 0.0,
) -> Frame:
    """Straight bar of ``n_el`` equal elements from the origin at ``angle`` [rad] from x.

    Node 0 is the only base node, so clamping the boundary dofs makes it a cantilever and
    the tip is node ``n_el``.
    """
    s = np.linspace(0.0, L, n_el + 1)
    nodes = np.c_[s * np.cos(angle), s * np.sin(angle)]
    el = np.c_[np.arange(n_el), np.arange(1, n_el + 1)]
    return Frame("cantilever", nodes, el, E, A, I, rho_A, 0.0, [0], [0.02])


def portal(
    h: float = 4.0,
    L: float = 6.0,
    I_c: float = 2.5e-4,
    I_b: float = 2.3e-4,
    A: float = 1.5e-2,
    E: float = 2.1e11,
    rho_A: float = 100.0,
    n_v: int = 1,
    n_h: int = 1,
    floor_mass: float = 0.0,
) -> Frame:
    """One-bay, one-storey portal frame, columns ``I_c``, beam ``I_b``, both area ``A``."""
    return regular_frame(
        "portal",
        [L],
        [h],
        n_v,
        n_h,
        Section(E, A, I_c, rho_A),
        Section(E, A, I_b, rho_A),
        floor_mass,
        [0.02],
    )


@pytest.fixture
def cantilever_props() -> dict:
    """The slender bar's section and length (:data:`CANTILEVER`)."""
    return dict(CANTILEVER)


@pytest.fixture
def make_cantilever():
    return cantilever


@pytest.fixture
def make_portal():
    return portal


@pytest.fixture(scope="session")
def office() -> Frame:
    return load_frame("office-11")


@pytest.fixture(scope="session")
def office_km(office):
    """Sparse consistent ``(K, M)`` of the office frame."""
    return office.assemble()
