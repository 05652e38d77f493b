"""The cb and full rungs of a space frame on isolators: the Craig–Bampton building as a pair system.

A :class:`~nsdyn.structure.Frame3D` on one bidirectional isolator under every base node is
reduced by :func:`~nsdyn.structure.craig_bampton_3d` with the base nodes as the interface,
``q = [q_b; η]``: ``q_b`` the translations ``(u_x, u_y, u_z)`` of each base node (node by
node; the base rotations are condensed, a sliding isolator carries no moment) and ``η`` the
fixed-interface (pinned-feet) modal coordinates. Relative to the ground,

    M q̈ + C q̇ + K q = −M Γ [a_x, a_y, a_z + g] + Σ R_iᵀ λ_i − Σ D_iᵀ F_i,
    K = diag(K_bb − K_bi K_ii⁻¹ K_ib, diag(ω²)),   M = Tᵀ M_r T,   C = diag(0, diag(2 ζ_j ω_j)),
    D_i q = (u_x, u_y) of base node i (the slip),  R_i q = u_z of base node i (the gap, = 0),
    Γ = [r_b; 0]  (rigid translations x, y, z; T Γ = r exactly, asserted by the reduction),

with λ_i the normal force (a multiplier: normal forces from the dynamics, uplift when one
reaches zero) and F_i the bearing's force (:mod:`nsdyn.models.isolated.pairs`, which adds the
bearings' rubber, damper, pendulum and rim terms). Damping is the plane ladder's choice
(:mod:`nsdyn.models.isolated.system`): ``frame.zeta`` on the fixed-interface modes in
frequency order, none on the constraint part, so that the superstructure's damping does not
damp the sliding (rigid motion of the boundary); the isolators' dampers are the bearings'.

Rungs. ``cb``: the fixed-interface modes up to ``f_max``, optionally thinned by their
participation (below). ``full``: every fixed-interface mode (``f_max = inf``): the same
model in another basis, exact; dense, so only for frames of at most :data:`FULL_MAX`
internal dofs (larger frames are refused, naming the size and the cb rung).

Participation filter. Mode j's effective-mass fractions in the rigid motions ``r_d`` (x, y,
z translations and the rotation about the vertical through the centre of mass) are
``(φ_jᵀ M r_d)² / (r_dᵀ M r_d)`` (``φ_jᵀ M r_d = (M Γ)`` row j for the translations). With
``min_mass`` the cb rung keeps only the modes whose fraction reaches it in at least one
direction (the kept set is still a Ritz space, Γ stays exact and the statics are untouched:
the constraint modes carry the dropped modes' mass quasi-statically); the dropped fractions
are reported. On the office at 5 Hz (195 modes) the default 10⁻⁴ keeps 19: the 14 below
3.7 Hz (fractions ≥ 2.8 × 10⁻⁴), four more x/y/torsion modes at 4.1–4.8 Hz (4–7 × 10⁻⁴)
and the vertical mode at 4.89 Hz that carries 69 % of the vertical mass; it drops the ~176
local vertical modes of the floor beams at 3.9–4.2 Hz (each ≤ 8.2 × 10⁻⁵, together below
10⁻³ in every direction).

Outputs: ``T`` maps q to the rigid floor motions (U_x, U_y, Θ) of every level about its
reference point (:func:`~nsdyn.structure.floor_motions`: the diaphragm's master, the centre
of mass), row ``3 k + (0, 1, 2)`` for level k (level 0 = the base); ``info`` holds the linear
maps of the storey drift ratios at the centres of mass and the plan corners
(:func:`~nsdyn.structure.storey_drifts_3d` of the reduction's shapes).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from nsdyn.ground.excitation import G_EARTH
from nsdyn.models.isolated.bearings import Bearing, BearingError
from nsdyn.structure.frame3d import Frame3D
from nsdyn.structure.modes3d import mass_centre
from nsdyn.structure.reduction3d import DENSE_MAX_3D, CBModel3D, craig_bampton_3d
from nsdyn.structure.storey3d import accidental_eccentricity, floor_motions, storey_drifts_3d

__all__ = ["FULL_MAX", "MIN_MASS", "RUNGS", "building_pairs", "mass_fractions", "thin_modes"]

RUNGS = ("cb", "full")
FULL_MAX = DENSE_MAX_3D  # internal dofs up to which the full rung (all modes, dense) is built
MIN_MASS = 1e-4  # default: a cb mode is kept if its effective-mass fraction reaches this
DIRECTIONS = ("x", "y", "z", "torsion")


def mass_fractions(cb: CBModel3D) -> tuple[np.ndarray, np.ndarray]:
    """(fractions (m, 4), centre (2,)): each fixed-interface mode's effective-mass fraction in
    the rigid x, y, z translations and the rotation about the vertical through the frame's
    centre of mass (module text)."""
    frame = cb.frame
    c, _, _ = mass_centre(frame)
    r = np.column_stack([frame.rigid_motions()[:, :3], frame.rigid_motions(c)[:, 3]])
    nb = cb.n_b
    # the rotation in CB coordinates: its boundary values (it lies in the constraint modes'
    # span too, since K_r r = 0 for every rigid motion)
    G = np.zeros((cb.n_red, 4))
    G[:, :3] = cb.Gamma
    G[:nb, 3] = r[cb.cb.boundary, 3]
    MG = cb.M @ G
    total = np.einsum("ij,ij->j", G, MG)
    return MG[nb:] ** 2 / total, c


def thin_modes(fractions: np.ndarray, min_mass: float) -> np.ndarray:
    """Boolean mask of the modes kept: those whose effective-mass fraction reaches
    ``min_mass`` in at least one direction."""
    return np.asarray(fractions).max(axis=1) >= min_mass


def _subset(cb: CBModel3D, keep: np.ndarray) -> CBModel3D:
    """The CB model with only the fixed-interface modes ``keep`` (a Ritz subspace)."""
    from dataclasses import replace

    nb = cb.n_b
    idx = np.concatenate([np.arange(nb), nb + np.flatnonzero(keep)])
    m = cb.cb
    sub = replace(m, T=m.T[:, idx], K=m.K[np.ix_(idx, idx)], M=m.M[np.ix_(idx, idx)],
                  C=m.C[np.ix_(idx, idx)], Gamma=m.Gamma[idx], omega=m.omega[keep],
                  zeta=m.zeta[keep])  # fmt: skip
    return CBModel3D(cb.frame, sub, cb.boundary_nodes, cb.components)


def _bearings(frame: Frame3D, bearings) -> tuple:
    nb = len(frame.base_nodes)
    if isinstance(bearings, Bearing):
        return (bearings,) * nb
    bearings = tuple(bearings)
    if len(bearings) != nb:
        raise BearingError(f"{frame.name}.bearings: expected one bearing or {nb} (one per base "
                           f"node), got {len(bearings)}")  # fmt: skip
    return bearings


def reduce_building(frame: Frame3D, fidelity: str, f_max: float, min_mass, lumped: bool):
    """(CBModel3D, info): the reduction of a rung, with what it kept and dropped."""
    if fidelity not in RUNGS:
        raise ValueError(f"fidelity: expected one of {list(RUNGS)}, got {fidelity!r}")
    n_int = frame.n_red - 3 * len(frame.base_nodes)
    if fidelity == "full":
        if n_int > FULL_MAX:
            raise ValueError(
                f"fidelity 'full': frame {frame.name!r} has {n_int} internal dofs "
                f"({frame.n_dof} dofs in all), above the dense limit {FULL_MAX} of the full "
                "rung (every fixed-interface mode, dense matrices); use fidelity 'cb' with a "
                "finite f_max"
            )
        cb = craig_bampton_3d(frame, np.inf, lumped=lumped)
        return cb, {"n_modes_below_f_max": cb.n_modes, "dropped_mass": [0.0] * 4}
    if min_mass is not None and not (isinstance(min_mass, int | float) and 0 <= min_mass < 1):
        raise ValueError(f"min_mass: expected an effective-mass fraction in [0, 1) or None, got "
                         f"{min_mass!r}")  # fmt: skip
    cb = craig_bampton_3d(frame, f_max, lumped=lumped)
    info = {"n_modes_below_f_max": cb.n_modes, "dropped_mass": [0.0] * 4}
    if min_mass and cb.n_modes:
        frac, _ = mass_fractions(cb)
        keep = thin_modes(frac, float(min_mass))
        info["dropped_mass"] = [float(v) for v in frac[~keep].sum(axis=0)]
        cb = _subset(cb, keep)
    return cb, info


def output_maps(cb: CBModel3D) -> dict:
    """Linear maps of q: floor motions (nl, 3, n), drift ratios at the centres of mass
    (ns, 2, n) and at the corners (ns, 4, 2, n), with their geometry."""
    frame = cb.frame
    full = frame.expand(cb.cb.T)  # (n_dof, n_cb): every CB shape in nodal dofs
    z, refs, fm = floor_motions(frame, full)
    d = storey_drifts_3d(frame, full)
    return {"levels_z": z, "level_refs": refs, "floor_map": fm, "drift_cm_map": d.cm,
            "drift_corner_map": d.corner, "heights": d.heights, "cm_points": d.cm_points,
            "corners": d.corners}  # fmt: skip


def building_pairs(
    frame: Frame3D,
    bearings: Bearing | Sequence[Bearing],
    *,
    fidelity: str = "cb",
    f_max: float = 5.0,
    min_mass: float | None = MIN_MASS,
    eccentricity: Sequence[float] = (0.0, 0.0),
    lumped: bool = False,
    g: float = G_EARTH,
    name: str | None = None,
):
    """The :class:`~nsdyn.models.isolated.pairs.PairSystem` of ``frame`` on one isolator under
    every base node, rung ``fidelity`` ("cb" or "full"; module text).

    ``bearings``: one :class:`Bearing` for all or one per base node (``frame.base_nodes``
    order). ``f_max`` [Hz]: the cb rung's cut-off; ``min_mass``: its participation filter
    (None: every mode below f_max). ``eccentricity`` (f_x, f_y): accidental, every floor's
    centre of mass moved by these fractions of its plan dimensions. ``info`` holds the
    reduction (``cb``), the kept frequencies, the dropped mass fractions, ``origin`` (the
    isolators' plan centroid O; ``positions`` are about it), ``centre`` (centre of mass),
    ``base_nodes`` and the output maps of :func:`output_maps`.
    """
    from nsdyn.models.isolated.pairs import PairSystem

    bearings = _bearings(frame, bearings)
    if any(eccentricity):
        frame = accidental_eccentricity(frame, *(float(v) for v in eccentricity))
    cb, red = reduce_building(frame, fidelity, f_max, min_mass, lumped)
    ni, n = len(frame.base_nodes), cb.n_red
    D = np.zeros((ni, 2, n))
    R = np.zeros((ni, n))
    ix, iy, iz = (cb.boundary_index(c) for c in ("ux", "uy", "uz"))
    D[np.arange(ni), 0, ix] = 1.0
    D[np.arange(ni), 1, iy] = 1.0
    R[np.arange(ni), iz] = 1.0
    xy = frame.nodes[frame.base_nodes, :2]
    origin = xy.mean(axis=0)
    maps = output_maps(cb)
    nl = maps["floor_map"].shape[0]
    c, m, J = mass_centre(frame)
    info = {"fidelity": fidelity, "cb": cb, "f_max": float(cb.f_max), "f_hz": cb.f_hz.copy(),
            "n_modes": cb.n_modes, "n_b": cb.n_b, "min_mass": min_mass, **red,
            "origin": origin, "centre": c, "m": m, "J": J,
            "base_nodes": frame.base_nodes.copy(), "frame": frame, **maps}  # fmt: skip
    label = f"{fidelity}-{cb.f_max:g}Hz" if fidelity == "cb" else "full"
    return PairSystem(M=cb.M, K=cb.K, C=cb.C, Gamma=cb.Gamma, D=D, R=R, bearings=bearings,
                      positions=xy - origin, T=maps["floor_map"].reshape(3 * nl, n), g=g,
                      name=name or f"{frame.name} {label} (n={n})", info=info)  # fmt: skip
