"""Studies: many runs of the models — amplitude sweeps of frequency–response curves, the
model advisor (the cheapest fidelity that answers a question), and distributed studies
(parameter grids × records on a process pool or Dask, resumable, with design searches,
percentile tables and fragility curves).

Importing this package loads neither Dask nor pyarrow (optional extras).
"""

from nsdyn.studies.analyses import run_analyses
from nsdyn.studies.design import design_points, pareto_front, percentile_table
from nsdyn.studies.execute import StudyRun, dask_executor, run_study
from nsdyn.studies.fragility import LognormalFragility, fit_lognormal, fit_lognormal_counts
from nsdyn.studies.scenes import run_scene_summary
from nsdyn.studies.study import Study, load_study

__all__ = [
    "LognormalFragility",
    "Study",
    "StudyRun",
    "dask_executor",
    "design_points",
    "fit_lognormal",
    "fit_lognormal_counts",
    "load_study",
    "pareto_front",
    "percentile_table",
    "run_analyses",
    "run_scene_summary",
    "run_study",
]
