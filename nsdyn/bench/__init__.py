"""Benchmarks: work-precision of the integrators, the model ladder, stability maps, speed.

Every benchmark measures error against cost in one run (``err = |q / q_ref - 1|`` or the
normalised history error, against the median wall time; see :mod:`nsdyn.bench.common`) and
writes its CSV tables and chart through :mod:`nsdyn.atomic`. One module per benchmark:

===============  =========================================================================
accuracy         error vs wall time of every integrator x friction law (CB-5)
fidelity         error vs cost of the model ladder rigid -> CB-5 ... CB-100 -> full
stability        largest stable fixed step vs eps and alpha, drift, shooting map
speed            the default run vs SciPy Radau on the NumPy equations, matched accuracy
periodic         shooting and the steady-state sweep: error vs time per point
rocking          rocking bodies (loaded on use)
contact          planar contact bodies (loaded on use)
cylinder         the cylinder (loaded on use)
studies          study throughput: a local process pool and a Dask LocalCluster
switch_shooting  periodic orbits of the Coulomb model: error vs time per point
full-model       the full 435-dof frame: genalpha-lowrank against radau, and CB-5
opensees         the full frame in OpenSees (exported script) against nsdyn full and CB-5
opensees3d       the 3D office building on its bearings in OpenSees against nsdyn's rung
scale            cost against model size (435 to 20 520 dofs): nsdyn full, CB-5, OpenSees
scale3d          the full 3D rung on sparse operators against building size, with OpenSees
isolators        bidirectional isolators: switch vs regularised law, cost per isolator
===============  =========================================================================

:data:`BENCHMARKS` maps each name to its module, imported on use by :func:`load_benchmark`.
A benchmark module exposes ``run_bench(out_dir: Path, quick: bool, **options) -> dict`` and may
list in ``OPTIONS`` the keyword options it takes among ``repeats``, ``records``, ``figures``,
``quiet`` and ``cold_compile`` (the command line passes only those; default none); it may also
expose ``summarise(result) -> dict`` (a JSON-serialisable summary) and ``report(result) -> str``
(the human table); the result's ``"files"`` lists what it wrote. ``nsdyn bench all`` runs them
in the table's order. The command line itself is :mod:`nsdyn.cli.bench`.
"""

from __future__ import annotations

import importlib
import importlib.util
from types import ModuleType

from nsdyn.bench.accuracy import (
    Reference,
    accuracy_bench,
    accuracy_figure,
    make_reference,
    matched_ratios,
    wall_to_reach,
)
from nsdyn.bench.baseline import numpy_equations, run_scipy_radau
from nsdyn.bench.common import (
    DEFAULT_OUT,
    MU,
    PGA,
    RECORDS,
    BenchRun,
    bench_frame,
    bench_isolation,
    bench_motion,
    cb5_system,
    rel_error,
    run_errors,
    run_nsdyn,
    write_csv_atomic,
)
from nsdyn.bench.fidelity import (
    acceleration_roundoff,
    fidelity_bench,
    fidelity_figure,
    low_frequency_motion,
    newton_noise_floor,
)
from nsdyn.bench.periodic import (
    dense_orbit_quantities,
    periodic_bench,
    periodic_figure,
    periodic_markdown,
    periodic_summary,
)
from nsdyn.bench.speed import scipy_match, speed_bench, speed_figure, speed_markdown, speed_scene
from nsdyn.bench.stability import stability_bench, stability_figure

__all__ = [
    "BENCHMARKS",
    "DEFAULT_OUT",
    "MU",
    "PGA",
    "RECORDS",
    "BenchRun",
    "BenchmarkUnavailable",
    "Reference",
    "acceleration_roundoff",
    "accuracy_bench",
    "accuracy_figure",
    "bench_frame",
    "bench_isolation",
    "bench_motion",
    "cb5_system",
    "dense_orbit_quantities",
    "fidelity_bench",
    "fidelity_figure",
    "load_benchmark",
    "low_frequency_motion",
    "make_reference",
    "matched_ratios",
    "newton_noise_floor",
    "numpy_equations",
    "periodic_bench",
    "periodic_figure",
    "periodic_markdown",
    "periodic_summary",
    "rel_error",
    "run_errors",
    "run_nsdyn",
    "run_scipy_radau",
    "scipy_match",
    "speed_bench",
    "speed_figure",
    "speed_markdown",
    "speed_scene",
    "stability_bench",
    "stability_figure",
    "wall_to_reach",
    "write_csv_atomic",
]

# name -> module, in the order ``nsdyn bench all`` runs them
BENCHMARKS: dict[str, str] = {
    "accuracy": "nsdyn.bench.accuracy",
    "fidelity": "nsdyn.bench.fidelity",
    "stability": "nsdyn.bench.stability",
    "speed": "nsdyn.bench.speed",
    "periodic": "nsdyn.bench.periodic",
    "rocking": "nsdyn.bench.rocking",
    "contact": "nsdyn.bench.contact",
    "cylinder": "nsdyn.bench.cylinder",
    "studies": "nsdyn.bench.studies",
    "switch_shooting": "nsdyn.bench.switch_shooting",
    "full-model": "nsdyn.bench.full_model",
    "opensees": "nsdyn.bench.opensees",
    "opensees3d": "nsdyn.bench.opensees3d",
    "scale": "nsdyn.bench.scale",
    "scale3d": "nsdyn.bench.scale3d",
    "isolators": "nsdyn.bench.isolators",
}


class BenchmarkUnavailable(ImportError):
    """A registered benchmark whose module is absent (``absent``) or does not import."""

    def __init__(self, message: str, *, absent: bool):
        super().__init__(message)
        self.absent = absent


def load_benchmark(name: str) -> ModuleType:
    """The module of benchmark ``name``, imported now.

    Raises ``KeyError`` for a name not in :data:`BENCHMARKS` and :class:`BenchmarkUnavailable`
    when its module is absent, fails to import, or has no ``run_bench``.
    """
    if name not in BENCHMARKS:
        raise KeyError(f"benchmark: expected one of {sorted(BENCHMARKS)}, got {name!r}")
    path = BENCHMARKS[name]
    if importlib.util.find_spec(path) is None:
        raise BenchmarkUnavailable(
            f"benchmark {name!r} is not available: module {path} does not exist", absent=True
        )
    try:
        module = importlib.import_module(path)
    except Exception as e:
        raise BenchmarkUnavailable(
            f"benchmark {name!r} is not available: module {path} failed to import: "
            f"{type(e).__name__}: {e}",
            absent=False,
        ) from e
    if not callable(getattr(module, "run_bench", None)):
        raise BenchmarkUnavailable(
            f"benchmark {name!r} is not available: module {path} has no run_bench(out_dir, quick)",
            absent=False,
        )
    return module
