"""The 3D building's displacement field at the time of its peak response, for the figures.

A run of a ``building3d`` scene keeps the full displacement field (six dofs per node,
relative to the ground) at one instant t*, with the frame's geometry, in
``building3d-shape.npz``; :func:`nsdyn.plot.frames3d.scene_figures` draws from it the deformed
shape (and, for the fixed rung, the first fixed-base mode shapes). The instant is

* fixed rung: the peak of the roof's resultant displacement at its reference point (the
  centre of mass of a diaphragm roof), t* = argmax_t |(U_x, U_y)_roof(t)|, with
  ``u(t*) = Σ_k φ_k η_k(t*)`` (mode shapes in full dofs);
* rigid rung: the peak resultant isolator slip, t* = argmax_t max_i |u_i(t)|; the building
  moves rigidly with the deck, q = (x, y, θ) of the deck's reference point O:

      u_x = x − θ (Y − O_y),   u_y = y + θ (X − O_x),   θ_z = θ   at every node (X, Y).

The file (written through :mod:`nsdyn.atomic`) holds ``nodes`` (nn, 3), ``elements`` (ne, 2),
``local_axes`` (ne, 3, 3), ``element_dofs`` (ne, 12), ``base_nodes``, ``name``, ``u`` (6 nn,),
``t_peak`` [s], ``what`` (the quantity whose peak it is) and, for the fixed rung, the first
``N_MODES`` ``mode_shapes`` (6 nn, k), ``f_hz``, ``family`` and ``mass_fraction`` (k, 3).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from nsdyn.atomic import atomic_open
from nsdyn.structure.frame3d import Frame3D
from nsdyn.structure.storey3d import floor_motions

__all__ = ["SHAPE_FILE", "fixed_peak_shape", "rigid_peak_shape", "write_shape"]

SHAPE_FILE = "building3d-shape.npz"
N_MODES = 4  # fixed-base mode shapes kept for the figure


def fixed_peak_shape(r) -> dict:
    """{t_peak, u, what} of a :class:`~nsdyn.models.isolated.fixed3d.FixedResponse3D`."""
    full = r.modes.full()
    roof = floor_motions(r.frame, full)[2][-1, :2]  # (2, m): the roof's U_x, U_y per mode
    k = int(np.argmax(np.hypot(*(roof @ r.eta))))
    return {"t_peak": float(r.t[k]), "u": full @ r.eta[:, k],
            "what": "peak roof displacement (fixed base)"}  # fmt: skip


def rigid_peak_shape(frame: Frame3D, deck, res) -> dict:
    """{t_peak, u, what} of a rigid-rung run ``res`` (a PlaneResult) of ``deck``
    (:func:`~nsdyn.models.isolated.building3d.building_deck` of ``frame``)."""
    k = int(np.argmax(res.resultant(res.u).max(axis=1)))
    x, y, th = res.q[k]
    ox, oy = deck.info["origin"]
    U = np.zeros((frame.n_nodes, 6))
    U[:, 0] = x - th * (frame.nodes[:, 1] - oy)
    U[:, 1] = y + th * (frame.nodes[:, 0] - ox)
    U[:, 5] = th
    return {"t_peak": float(res.t[k]), "u": U.ravel(),
            "what": "peak isolator slip (rigid superstructure)"}  # fmt: skip


def write_shape(out_dir, frame: Frame3D, shape: dict, modes=None) -> Path:
    """Write ``building3d-shape.npz`` (module docstring) into ``out_dir``; its path."""
    arrays = {
        "nodes": frame.nodes, "elements": frame.elements, "local_axes": frame.local_axes(),
        "element_dofs": frame.element_dofs(), "base_nodes": frame.base_nodes,
        "name": np.array(frame.name), "u": np.asarray(shape["u"], float),
        "t_peak": np.array(shape["t_peak"]), "what": np.array(shape["what"]),
    }  # fmt: skip
    if modes is not None:
        k = min(N_MODES, len(modes.f_hz))
        arrays.update(mode_shapes=modes.full()[:, :k], f_hz=modes.f_hz[:k],
                      family=np.array(modes.family[:k]),
                      mass_fraction=modes.mass_fraction[:k])  # fmt: skip
    path = Path(out_dir) / SHAPE_FILE
    with atomic_open(path, "wb") as fh:
        np.savez(fh, **arrays)
    return path
