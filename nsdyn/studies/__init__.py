"""Studies: many runs of the models — amplitude sweeps of frequency–response curves, the
model advisor (the cheapest fidelity that answers a question), and distributed studies
(parameter grids × records on a process pool or Dask, resumable, with design searches,
percentile tables and fragility curves).

Importing this package loads neither Dask nor pyarrow (optional extras), nor anything else:
the names below load on first use.
"""

from nsdyn._lazy import exports

_API = {
    "LognormalFragility": "nsdyn.studies.fragility",
    "Study": "nsdyn.studies.study",
    "StudyRun": "nsdyn.studies.execute",
    "dask_executor": "nsdyn.studies.execute",
    "design_points": "nsdyn.studies.design",
    "fit_lognormal": "nsdyn.studies.fragility",
    "fit_lognormal_counts": "nsdyn.studies.fragility",
    "load_study": "nsdyn.studies.study",
    "pareto_front": "nsdyn.studies.design",
    "read_results": "nsdyn.studies.table",
    "percentile_table": "nsdyn.studies.design",
    "run_analyses": "nsdyn.studies.analyses",
    "run_scene_summary": "nsdyn.studies.scenes",
    "run_study": "nsdyn.studies.execute",
}

__all__ = sorted(_API)


__getattr__, __dir__ = exports(globals(), _API)
