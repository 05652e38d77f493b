"""The 3D building's full rung on sparse operators as the building scene runs it: run and response.

:func:`run_building_sparse` runs a :func:`~nsdyn.models.isolated.pairs_sparse.
building_pairs_sparse` system by :func:`~nsdyn.models.isolated.pairs_sparse_run.
simulate_pairs_sparse` with its output map set to the rows the engineer's outputs need,

    T = [floor motions (3 nl); drift ratios at the centres of mass (2 ns); at the corners (8 ns)]

(linear maps of q, ``info`` of the system), so that the histories of T q and T q̈ are recorded
during the run and q itself need not be kept. The response is the cb rung's
(:class:`~nsdyn.models.isolated.building3d_response.BuildingResponse3D`): drift ratios, floor
accelerations (relative T q̈ plus the ground's), base shear Σ F_i, torsional moment about the
centre of mass Σ (X_i − c) × F_i and the roof corners' displacements; ``qdd`` is None (the
full accelerations are never stored).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from nsdyn.models.isolated.building3d_response import (
    BuildingResponse3D,
    ground_history,
    isolator_forces,
)
from nsdyn.structure.storey3d import StoreyDrifts

__all__ = ["run_building_sparse"]


def run_building_sparse(system, ground, *, dt: float, **kw) -> BuildingResponse3D:
    """Run ``system`` under ``ground`` at the step ``dt`` (``kw`` passed on to
    :func:`simulate_pairs_sparse`); the building's response (module text)."""
    from nsdyn.models.isolated.pairs_sparse_run import simulate_pairs_sparse

    info, n = system.info, system.n
    nl = info["floor_map"].shape[0]
    ns = info["drift_cm_map"].shape[0]
    T = np.vstack([info["floor_map"].reshape(-1, n), info["drift_cm_map"].reshape(-1, n),
                   info["drift_corner_map"].reshape(-1, n)])  # fmt: skip
    kw.setdefault("keep_q", False)
    res = simulate_pairs_sparse(dataclasses.replace(system, T=T), ground, dt=dt, **kw)
    t, nt = res.t, res.t.size
    o = res.outputs
    fm = o[:, : 3 * nl].reshape(nt, nl, 3)
    cm = o[:, 3 * nl : 3 * nl + 2 * ns].reshape(nt, ns, 2)
    co = o[:, 3 * nl + 2 * ns :].reshape(nt, ns, 4, 2)
    drifts = StoreyDrifts(info["heights"], info["cm_points"], info["corners"],
                          np.moveaxis(cm, 0, -1), np.moveaxis(co, 0, -1))  # fmt: skip
    a = ground_history(ground, t)
    acc = res.accelerations[:, : 3 * nl].reshape(nt, nl, 3)[..., :2]
    floor_acc = np.moveaxis(acc, 0, -1) + a[None, :2]
    F = isolator_forces(res)
    base_shear = F.sum(axis=1).T
    rel = system.positions - (info["centre"] - info["origin"])
    torsion = (rel[None, :, 0] * F[..., 1] - rel[None, :, 1] * F[..., 0]).sum(axis=1)
    ux, uy, th = fm[:, -1].T
    d = info["corners"] - info["level_refs"][-1]
    roof = np.stack([ux[None] - d[:, 1:] * th[None], uy[None] + d[:, :1] * th[None]], axis=1)
    return BuildingResponse3D(t, drifts, floor_acc, base_shear, torsion, roof, None, res)
