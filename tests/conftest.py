"""Shared factories of standard test systems (frames), used by tests of several modules.

Factories are plain functions exposed as fixtures returning the function (``make_cantilever``,
``make_portal``) or a ready object (``office``, ``office_km``).
"""

from __future__ import annotations

import os
from pathlib import Path

# One BLAS thread: on a shared 2-core machine threaded dense eigensolvers of a few hundred
# dofs run ~10x slower than single-threaded ones (must be set before numpy loads BLAS).
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

# the model cache (nsdyn._model_cache) of this test session, not the user's: set in the
# controller before the xdist workers start (they inherit it and share it), removed at its end
if "NSDYN_MODEL_CACHE" not in os.environ:
    import atexit
    import shutil
    import tempfile

    os.environ["NSDYN_MODEL_CACHE"] = tempfile.mkdtemp(prefix="nsdyn-test-models-")
    atexit.register(shutil.rmtree, os.environ["NSDYN_MODEL_CACHE"], True)

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from hypothesis import settings  # noqa: E402

# no per-example deadline: the first example of a test may import SciPy modules or load numba
# caches, and the shared machines are noisy; correctness, not speed, is what the tests check
settings.register_profile("nsdyn", deadline=None)
settings.load_profile("nsdyn")

from nsdyn.structure import Frame, Section, load_frame, regular_frame  # noqa: E402

# ---- one compilation before the xdist workers start -----------------------------------------
#
# Each xdist worker is a process of its own: into an empty numba cache (a fresh clone, a
# changed kernel) every worker that needs a kernel before another has saved it compiles it
# again (the switch model's event loop alone takes minutes on one core). So the controller
# process compiles the kernels most of the suite uses into numba's on-disk cache first, in
# two processes at once (one per core, each a list of warm-ups), and the workers load them.
# Controller only (never in a worker), only with workers (-n), only for the whole suite (no
# paths given), never without the JIT; NSDYN_TEST_WARMUP=0 turns it off. A warm-up that fails
# costs nothing but its time: the tests then compile what they need themselves.

WARMUP_ENV = "NSDYN_TEST_WARMUP"
# (module, function, args) per process; each warm-up only loads what is already cached
WARMUP_SLOTS = (
    (
        ("nsdyn.solve.methods", "warmup_kernel", ["event"]),
        ("nsdyn.solve.methods", "warmup_unilateral", []),
        ("nsdyn.periodic.switch_compile", "warmup", []),
        ("conftest", "warm_cylinder", []),
        ("conftest", "warm_pairs", []),
    ),
    (
        ("nsdyn.solve.methods", "warmup_kernel", ["radau", "metrics"]),
        ("nsdyn.solve.methods", "warmup_kernel", ["radau-general", "metrics-general"]),
        ("nsdyn.periodic.problem", "warmup", []),
        ("nsdyn.solve.methods", "warmup_kernel", ["genalpha"]),
        ("nsdyn.solve.methods", "warmup_kernel", ["dopri5"]),
        ("nsdyn.models.rocking.block", "warmup", []),
        ("conftest", "warm_contact", []),
        ("conftest", "warm_deck", []),
    ),
)
_WARMUP_CODE = """
import importlib, json, sys, time
sys.path.insert(0, sys.argv[2])  # the tests folder: this conftest's own warm-ups
from nsdyn._numba_cache import compiling
for module, name, args in json.loads(sys.argv[1]):
    t0, c0 = time.perf_counter(), time.process_time()
    with compiling():
        getattr(importlib.import_module(module), name)(*args)
    t, c = time.perf_counter() - t0, time.process_time() - c0
    print(f"{module}.{name}{tuple(args)}: {t:.1f} s ({c:.1f} s CPU)", flush=True)
"""


def warm_contact():
    """The planar contact solvers (event-driven and Moreau–Jean) on a rocking block."""
    from nsdyn.models.contact import (
        BaseMotion,
        FrictionLaw,
        RigidBody,
        simulate_event,
        simulate_moreau,
    )

    body = RigidBody.rectangle(0.2, 1.0, 100.0)
    law = FrictionLaw(0.57, 0.57, 0.0)
    motion = BaseMotion.displacement_sine(0.01, 0.5, 5, "impulsive")
    simulate_event(body, law, motion, t_end=0.02, dt_out=0.005)
    simulate_moreau(body, law, motion, t_end=0.02, h=5e-4, dt_out=0.005)


# a short circular orbit of the ground (x and y in quadrature) that makes a mass on a friction
# pendulum slip and stick within a tenth of a second
_WARM_ORBIT = {"f": 2.0, "ax": 3.0, "ay": 3.0, "phase_y_deg": -90.0, "az": 0.0, "f_z": 1.0}


def warm_deck():
    """The bidirectional deck's integrators: a mass on one friction pendulum under a short
    circular orbit, with the switch law (Dormand–Prince with the stick-disc events) and the
    regularised one (Radau IIA)."""
    from nsdyn.models.isolated.bearings import Bearing, Friction
    from nsdyn.models.isolated.deck import sdof_plane, simulate_plane

    s = sdof_plane(1000.0, Bearing(Friction(0.05), radius=2.0))
    for law in ("switch", "arctan"):
        simulate_plane(s, _WARM_ORBIT, law=law, t_end=0.1)


def warm_pairs():
    """The matrix systems' integrators (:func:`nsdyn.models.isolated.pairs.simulate_pairs`): a
    mass on one friction pendulum (x, y slip rows, the z contact row) under the same orbit,
    with both laws."""
    from nsdyn.models.isolated.bearings import Bearing, Friction
    from nsdyn.models.isolated.pairs import PairSystem, simulate_pairs

    m = 1000.0
    s = PairSystem(M=m * np.eye(3), K=np.zeros((3, 3)), C=np.zeros((3, 3)), Gamma=np.eye(3),
                   D=np.array([[[1.0, 0, 0], [0, 1.0, 0]]]), R=np.array([[0, 0, 1.0]]),
                   bearings=(Bearing(Friction(0.05), radius=2.0),), positions=np.zeros((1, 2)),
                   g=9.81)  # fmt: skip
    for law in ("switch", "arctan"):
        simulate_pairs(s, _WARM_ORBIT, law=law, t_end=0.1)


def warm_cylinder():
    """The cylinder on its Winkler foundation."""
    from nsdyn.models.cylinder import CylinderParams
    from nsdyn.models.cylinder.simulate import simulate

    simulate(CylinderParams(), np.full((3, 3), 0.1), 0.01)


def _wants_warmup(config) -> bool:
    if os.environ.get(WARMUP_ENV, "1") == "0" or hasattr(config, "workerinput"):
        return False
    if os.environ.get("PYTEST_XDIST_WORKER") or os.environ.get("NUMBA_DISABLE_JIT", "0") != "0":
        return False
    if not getattr(config.option, "numprocesses", None):  # no workers: nothing compiles twice
        return False
    testpaths = getattr(getattr(pytest.Config, "ArgsSource", None), "TESTPATHS", None)
    return testpaths is not None and config.args_source == testpaths  # the whole suite


def pytest_configure(config):
    """Warm numba's cache for the workers (see WARMUP_SLOTS), in the controller only."""
    if not _wants_warmup(config):
        return
    import json
    import subprocess
    import sys
    import time

    t0 = time.perf_counter()
    # the nsdyn this process imported (an installed one, not the checkout beside the working
    # directory: numba's cache belongs to a source file), one compiling process per core
    env = dict(
        os.environ,
        NSDYN_COMPILE_HELPER="0",
        PYTHONPATH=os.pathsep.join(p for p in sys.path if p),
    )
    procs = [
        subprocess.Popen(
            [
                sys.executable,
                "-P",
                "-c",
                _WARMUP_CODE,
                json.dumps(slot),
                str(Path(__file__).parent),
            ],
            env=env,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        for slot in WARMUP_SLOTS
    ]
    logs = [p.communicate()[0] for p in procs]
    config._nsdyn_warmup = (time.perf_counter() - t0, [p.returncode for p in procs], logs)


def pytest_terminal_summary(terminalreporter, config):
    """What the warm-up compiled and how long it took (controller only; shown with -q too)."""
    info = getattr(config, "_nsdyn_warmup", None)
    if info is None:
        return
    seconds, codes, logs = info
    tr = terminalreporter
    tr.section("numba cache warmed before the workers started")
    tr.write_line(f"{seconds:.0f} s, exit codes {codes}")
    for log in logs:
        for line in log.splitlines()[-12:]:
            tr.write_line(f"  {line}")


@pytest.fixture
def child_env():
    """The environment of a child Python process, run with ``-P``, that imports the nsdyn this
    test process imported (an installed one: the kernels the session's warm-up compiled), not
    the checkout beside the working directory (whose kernels have a numba cache of their own)."""
    import nsdyn

    ours = os.path.dirname(os.path.dirname(os.path.abspath(nsdyn.__file__)))
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (ours, env.get("PYTHONPATH")) if p)
    return env


@pytest.fixture
def compile_alone(tmp_path):
    """``run(code)``: ``code`` run in a fresh Python process whose numba cache is an empty
    folder (a first compilation, with the JIT whatever this run's mode); its stdout's lines,
    each split into fields."""
    import subprocess
    import sys

    def run(code: str) -> list[list[str]]:
        env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), NUMBA_DISABLE_JIT="0")
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                             text=True, check=True).stdout  # fmt: skip
        return [r.split() for r in out.splitlines() if r]

    return run


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


def newton_roundoff_bound(problem, res, guess=None) -> float:
    """Round-off bound of a converged shooting residual (scaled by the orbit's ranges, as
    :func:`nsdyn.periodic.shoot` measures it) when the period map is affine near the orbit.

    Newton's step is a least-squares solve, backward stable, so the residual it leaves is at
    most ~dim u ‖J‖ ‖Δ‖ (J = Φ - I scaled, Δ the scaled correction from ``guess``, default the
    static state), plus the map's own round-off, ``n_steps`` steps of at most u ‖Φ‖ ‖x‖ each
    (x scaled from the static state); u = eps / 2. When this bound is below the shooting
    tolerance, an affine map converges after exactly one Newton update on any machine."""
    from nsdyn.periodic.shooting import orbit_amplitudes

    m = problem.dim // 2
    amp = np.repeat(orbit_amplitudes(problem, res.X), m)
    guess = problem.x_ref if guess is None else guess
    scaled = res.monodromy * amp[None, :] / amp[:, None]
    J = scaled - np.eye(problem.dim)
    dx = np.linalg.norm((res.x0 - guess) / amp)
    x = np.linalg.norm((res.x0 - problem.x_ref) / amp)
    u = np.finfo(float).eps / 2
    return float(
        u * (problem.dim * np.linalg.norm(J, 2) * dx + res.n_steps * np.linalg.norm(scaled, 2) * x)
    )


@pytest.fixture
def newton_roundoff():
    """:func:`newton_roundoff_bound`."""
    return newton_roundoff_bound
