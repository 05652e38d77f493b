"""What a run of the space frame on isolators (the cb and full rungs) gives the engineer.

A run of :func:`~nsdyn.models.isolated.pairs.simulate_pairs` on the pair system of
:func:`~nsdyn.models.isolated.building3d_cb.building_pairs` reports, at each output instant,
q, q̇, the normal forces λ_i and the bearings' resisting forces F_i (friction — the stick
force in stick —, restoring, damper and rim). The accelerations follow from the equations
of motion at that instant, exactly for the reported state and forces:

    M q̈ = −K q − C q̇ − M Γ [a_x, a_y, a_z + g] + Σ R_iᵀ λ_i − Σ D_iᵀ F_i.

From them and the system's linear output maps (every rigid floor's motion (U_x, U_y, Θ) about
its reference point, the drift ratios at the centres of mass and the plan corners):

- storey drift ratios in x and y at the centre of mass and at the four corners (the maps
  applied to q: the static state under gravity included);
- floor accelerations in x and y at each level's reference point (the centre of mass of a
  diaphragm floor), absolute: ``T_floor q̈ + (a_x, a_y)``; the peaks are those of the floors
  above the base: the base's own acceleration jumps when friction does (a stick-slip
  transition changes the friction force at once, and the base's apparent mass is only the
  residual mass of the truncated modes);
- base shear ``V = Σ_i F_i`` (x, y: the horizontal force the isolators pass to the ground)
  and torsional moment about the centre of mass c, ``Σ_i (X_i − c_x) F_y,i − (Y_i − c_y) F_x,i``;
- the roof's displacement relative to the ground at the four plan corners (its rigid floor
  motion carried there: ``u_x = U_x − (y − y_c) Θ``, ``u_y = U_y + (x − x_c) Θ``);
- isolator orbits: the slips u_i(t) = D_i q (the run's result).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from nsdyn._tabular import Tabular
from nsdyn.models.isolated.fixed3d import response_histories, response_peaks
from nsdyn.models.isolated.plane_ground import ground_history
from nsdyn.structure.storey3d import StoreyDrifts

__all__ = [
    "BuildingResponse3D",
    "base_force_peaks",
    "base_forces",
    "building_response",
    "ground_history",
    "isolator_forces",
    "run_building",
]


def isolator_forces(result) -> np.ndarray:
    """The bearings' resisting forces F_i (nt, ni, 2): friction + restoring + damper and rim."""
    return result.friction + result.restoring + result.other


def base_forces(result, centre) -> tuple[np.ndarray, np.ndarray]:
    """The base shear (2, nt) [N], the isolators' forces summed, and their torsional moment
    (nt,) [N m] about ``centre``, a plan point in the isolators' ``positions``' frame (the
    centre of mass)."""
    F = isolator_forces(result)  # (nt, ni, 2)
    rel = result.system.positions - np.asarray(centre, dtype=float)
    return F.sum(axis=1).T, (rel[None, :, 0] * F[..., 1] - rel[None, :, 1] * F[..., 0]).sum(axis=1)


def base_force_peaks(result, centre) -> dict:
    """The peaks of :func:`base_forces`: ``peak_base_shear_x_N``, ``…_y_N``, ``peak_base_shear_N``
    (the resultant) and ``peak_torsional_moment_Nm`` (a rigid deck's, as the cb rung's)."""
    V, T = base_forces(result, centre)
    return {"peak_base_shear_x_N": float(np.abs(V[0]).max()),
            "peak_base_shear_y_N": float(np.abs(V[1]).max()),
            "peak_base_shear_N": float(np.hypot(V[0], V[1]).max()),
            "peak_torsional_moment_Nm": float(np.abs(T).max())}  # fmt: skip


@dataclass(frozen=True, eq=False, repr=False)
class BuildingResponse3D(Tabular):
    """Response histories of a cb or full run (module text); ``t`` (nt,) [s].

    drifts : StoreyDrifts with a time axis (``cm`` (ns, 2, nt), ``corner`` (ns, 4, 2, nt)).
    floor_acc : (nl, 2, nt) absolute floor accelerations x, y [m/s²] (level 0 = the base).
    base_shear : (2, nt) [N].  torsion : (nt,) [N m] about the centre of mass.
    roof_corner : (4, 2, nt) the roof's x, y displacement at the plan corners [m].
    qdd : (nt, n) accelerations.  result : the run's PairResult (orbits ``u``, forces, N).
    """

    t: np.ndarray
    drifts: StoreyDrifts
    floor_acc: np.ndarray
    base_shear: np.ndarray
    torsion: np.ndarray
    roof_corner: np.ndarray
    qdd: np.ndarray
    result: object

    def summary(self) -> dict:
        """The run's isolator summary with the structure's peaks (units in the key names)."""
        s = self.result.summary()
        s.update(response_peaks(self.drifts, self.floor_acc, self.base_shear, self.torsion))
        rc = np.hypot(self.roof_corner[:, 0], self.roof_corner[:, 1])
        s["peak_roof_corner_displacement_m"] = float(rc.max()) if rc.size else float("nan")
        return s

    def histories(self) -> dict:
        """The structure's histories on ``t`` (:func:`~nsdyn.models.isolated.fixed3d.
        response_histories`) and the roof's displacement at the plan corners
        ``roof_corner_x_{}_m`` (corner c); the isolators' are the run's,
        ``self.result.histories()``."""
        rc = self.roof_corner
        return {**response_histories(self.drifts, self.floor_acc, self.base_shear, self.torsion),
                "roof_corner_x_{}_m": rc[:, 0].T, "roof_corner_y_{}_m": rc[:, 1].T}  # fmt: skip


def building_response(system, result, ground) -> BuildingResponse3D:
    """Drifts, floor accelerations, base shear and torsional moment of a run (module text).

    ``system``: the PairSystem of :func:`~nsdyn.models.isolated.building3d_cb.building_pairs`;
    ``result``: its run's PairResult; ``ground``: the excitation the run had.
    """
    info = system.info
    t, q, qd = result.t, result.q, result.qd
    a = ground_history(ground, t)  # (3, nt)
    F = isolator_forces(result)  # (nt, ni, 2)
    rhs = -(q @ system.K.T) - (qd @ system.C.T)
    rhs -= (system.M @ system.Gamma @ (a + np.array([[0.0], [0.0], [system.g]]))).T
    rhs += result.N @ system.R - np.einsum("tic,icn->tn", F, system.D)
    qdd = sla.cho_solve(sla.cho_factor(system.M), rhs.T).T
    drifts = StoreyDrifts(info["heights"], info["cm_points"], info["corners"],
                          info["drift_cm_map"] @ q.T, info["drift_corner_map"] @ q.T)  # fmt: skip
    floor_acc = info["floor_map"][:, :2] @ qdd.T + a[None, :2]
    base_shear, torsion = base_forces(result, info["centre"] - info["origin"])  # about c
    ux, uy, th = info["floor_map"][-1] @ q.T  # the roof's rigid motion about its reference
    d = info["corners"] - info["level_refs"][-1]  # (4, 2)
    roof = np.stack([ux[None] - d[:, 1:] * th[None], uy[None] + d[:, :1] * th[None]], axis=1)
    return BuildingResponse3D(t, drifts, floor_acc, base_shear, torsion, roof, qdd, result)


def run_building(system, ground, **kw) -> BuildingResponse3D:
    """Run ``system`` (:func:`~nsdyn.models.isolated.building3d_cb.building_pairs`) under
    ``ground`` by :func:`~nsdyn.models.isolated.pairs.simulate_pairs` from its static state
    (``info["y0"]``, unless ``y0`` is given), ``kw`` passed on; its response."""
    from nsdyn._checks import keywords_of
    from nsdyn.models.isolated.pairs import simulate_pairs

    keywords_of(simulate_pairs, kw, skip=("system", "ground"), caller="run_building() ")
    kw.setdefault("y0", system.info.get("y0"))
    return building_response(system, simulate_pairs(system, ground, **kw), ground)
