"""Figures. All matplotlib use of the isolated frame's results lives here, imported lazily
inside the functions; figures are built with ``matplotlib.figure.Figure`` (no pyplot, no
global state), so saving them uses the Agg canvas whatever the interactive backend is.
Model families keep their own figure modules beside their kernels.
"""

from nsdyn.plot.charts import (
    fidelity_figure,
    periodic_work_precision_figure,
    speed_figure,
    stability_figure,
    work_precision_figure,
)
from nsdyn.plot.frames import deformed_shape, plot_mode_shapes, sweep_figure
from nsdyn.plot.transient import plot_transient
from nsdyn.plot.uplift import uplift_boundary_figure

__all__ = [
    "deformed_shape",
    "fidelity_figure",
    "periodic_work_precision_figure",
    "plot_mode_shapes",
    "plot_transient",
    "speed_figure",
    "stability_figure",
    "sweep_figure",
    "uplift_boundary_figure",
    "work_precision_figure",
]
