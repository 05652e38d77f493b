"""The cb and full rungs of a space frame on isolators: the Craig–Bampton building as a pair system.

A :class:`~nsdyn.structure.Frame3D` on one bidirectional isolator under every base node is
reduced by Craig–Bampton (:func:`~nsdyn.structure.craig_bampton`) with its base as the
interface, ``q = [q_b; η]``, ``η`` the fixed-interface modal coordinates. Relative to the
ground,

    M q̈ + C q̇ + K q = −M Γ [a_x, a_y, a_z + g] + Σ R_iᵀ λ_i − Σ D_iᵀ F_i,
    K = diag(K_bb − K_bi K_ii⁻¹ K_ib, diag(ω²)),   M = Tᵀ M_r T,   C = diag(0, diag(2 ζ_j ω_j)),
    Γ = [r_b; 0]  (rigid translations x, y, z; T Γ = r exactly, asserted by the reduction),

with λ_i the normal force (a multiplier: normal forces from the dynamics, uplift when one
reaches zero), ``R_i q`` the vertical gap of isolator i (its base node's u_z, held at zero),
``D_i q`` its slip (u_x, u_y) and F_i the bearing's force (:mod:`nsdyn.models.isolated.pairs`
adds the bearings' rubber, damper, pendulum and rim terms; a triple friction pendulum its
series model, whose internal slips the state carries, regularised law only). Damping is the
plane ladder's choice (:mod:`nsdyn.models.isolated.system`): ``frame.zeta`` on the
fixed-interface modes in
frequency order, none on the constraint part, so that the superstructure's damping does not
damp the sliding; the isolators' dampers are the bearings'.

The base (``base``). ``"grid"`` (default): the column feet are tied, as above the isolators of
a real building and as the plane ladder's stiff base diaphragm, by massless beams between
neighbouring feet on each grid line (vertical bending and torsion of the plane ladder's
stiffness ``Isolation.diaphragm_EI``, so the columns are clamped into them) and a rigid
diaphragm through the feet (master at the isolators' plan centroid O). The interface is the
base master's (U_x, U_y, Θ) and every foot's u_z, and the slip of isolator i at (X_i, Y_i)
about O is the rigid base's motion there, ``D_i q = (U_x − Y_i Θ, U_y + X_i Θ)``. ``"pinned"``:
each foot on its own isolator, the interface ``(u_x, u_y, u_z)`` of every foot
(:func:`~nsdyn.structure.craig_bampton_3d`; base rotations condensed, the feet pinned) and
``D_i q`` its foot's (u_x, u_y). Without the grid the feet move against each other through
the first storey's columns alone, with stiff local modes (a stiff grid without the diaphragm
would put them at hundreds of Hz, which an explicit integrator cannot afford).

Rungs. ``cb``: the fixed-interface modes up to ``f_max``, optionally thinned by their
participation (below). ``full``: every fixed-interface mode (``f_max = inf``): the same
model in another basis, exact; dense, so only for frames of at most :data:`FULL_MAX`
internal dofs (larger frames are refused, naming the size and the cb rung).

Participation filter. Mode j's effective-mass fractions in the rigid motions ``r_d`` (x, y,
z translations and the rotation about the vertical through the centre of mass) are
``(φ_jᵀ M r_d)² / (r_dᵀ M r_d)`` (row j of ``M Γ`` for the translations). With ``min_mass``
the cb rung keeps only the modes whose fraction reaches it in at least one direction (the
kept set is still a Ritz space, Γ stays exact and the statics are untouched: the
constraint modes carry the dropped modes' mass quasi-statically); the dropped fractions are
reported. It is there for the office's floor beams (docs/guide/frames-3d.md: about 180 local
vertical modes between 3.9 and 4.2 Hz, each below 10⁻⁴ of every mass).

Outputs: ``T`` maps q to the rigid floor motions (U_x, U_y, Θ) of every level about its
reference point (:func:`~nsdyn.structure.floor_motions`: the diaphragm's master, the centre
of mass), row ``3 k + (0, 1, 2)`` for level k (level 0 = the base); ``info`` holds the linear
maps of the storey drift ratios at the centres of mass and the plan corners
(:func:`~nsdyn.structure.storey_drifts_3d` of the reduction's shapes) and the static state.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import replace

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from nsdyn._checks import expect, flag
from nsdyn.ground.excitation import G_EARTH
from nsdyn.models.isolated.bearings import Bearing, BearingError
from nsdyn.structure.frame3d import Diaphragm, Frame3D, changed
from nsdyn.structure.modes3d import mass_centre
from nsdyn.structure.reduction import CBModel, craig_bampton
from nsdyn.structure.reduction3d import DENSE_MAX_3D, craig_bampton_3d
from nsdyn.structure.storey3d import (
    accidental_eccentricity,
    eccentricity_pair,
    floor_motions,
    storey_drifts_3d,
)

__all__ = ["BASES", "FULL_MAX", "MIN_MASS", "RUNGS", "base_grid", "building_pairs",
           "mass_fractions", "reduce_building", "static_state"]  # fmt: skip

RUNGS = ("cb", "full")
BASES = ("grid", "pinned")  # feet tied by a stiff base grid and diaphragm, or each on its own
FULL_MAX = DENSE_MAX_3D  # internal dofs up to which the full rung (all modes, dense) is built
MIN_MASS = 1e-4  # default: a cb mode is kept if its effective-mass fraction reaches this
STATIC_ITER = 50  # passes of the pendulum terms λ/R in the static solve


def base_grid(frame: Frame3D) -> Frame3D:
    """``frame`` with its feet tied (module text): massless beams between neighbouring base
    nodes on each plan grid line (EA = ``Isolation.diaphragm_EA`` [N], EI in both planes and
    GJ = ``Isolation.diaphragm_EI`` [N m²]) and a massless rigid diaphragm through the base
    nodes, its master at their plan centroid."""
    from nsdyn.models.isolated.system import Isolation

    base = frame.base_nodes
    xy = frame.nodes[base, :2]
    tol = 1e-9 * frame.size
    pairs = []
    for a, b in ((1, 0), (0, 1)):  # lines of equal y (beams along x), then of equal x
        seen = np.zeros(len(base), bool)
        for i0 in range(len(base)):
            if seen[i0]:
                continue
            on = np.flatnonzero(np.abs(xy[:, a] - xy[i0, a]) <= tol)
            seen[on] = True
            on = on[np.argsort(xy[on, b])]
            pairs += [(int(base[i]), int(base[j])) for i, j in zip(on[:-1], on[1:], strict=True)]
    pairs = sorted(set(pairs))
    ea, ei = float(Isolation.diaphragm_EA), float(Isolation.diaphragm_EI)
    k = len(pairs)

    def add(name, v):
        return np.concatenate([getattr(frame, name), np.full(k, v)])

    out, n0 = frame, len(frame.elements)
    if k:
        try:
            out = changed(frame, elements=np.vstack([frame.elements, np.reshape(pairs, (k, 2))]),
                          vecxz=np.vstack([frame.vecxz, np.tile([0.0, 0.0, 1.0], (k, 1))]),
                          E=add("E", ea), G=add("G", ei), A=add("A", 1.0), I_y=add("I_y", ei / ea),
                          I_z=add("I_z", ei / ea), J=add("J", 1.0), rho_A=add("rho_A", 0.0),
                          rho_Ip=add("rho_Ip", 0.0))  # fmt: skip
        except ValueError as e:  # (a tie beam named as the base grid's, not by its number)
            ties = {f"elements[{n0 + i}]": f"the base grid's tie beam of nodes {a} and {b}"
                    for i, (a, b) in enumerate(pairs)}  # fmt: skip
            msg = re.sub(r"elements\[\d+\]", lambda m: ties.get(m[0], m[0]), str(e))
            raise ValueError(msg) from None
    dia = Diaphragm(base, xy.mean(axis=0))
    return changed(out, diaphragms=(*out.diaphragms, dia))


def _bearings(frame: Frame3D, bearings) -> tuple:
    nb = len(frame.base_nodes)
    if isinstance(bearings, Bearing):
        return (bearings,) * nb
    bearings = tuple(bearings) * (nb if len(bearings) == 1 else 1)  # (a list of one: all)
    if len(bearings) != nb:
        raise BearingError(f"{frame.name}.bearings: expected one bearing or {nb} (one per base "
                           f"node), got {len(bearings)}")  # fmt: skip
    return bearings


def _own_dof(frame: Frame3D, node: int, comp: int) -> int:
    """Reduced index of a node's own dof (a unit row of T)."""
    T = frame.T
    r = 6 * node + comp
    cols = T.indices[T.indptr[r] : T.indptr[r + 1]]
    return int(cols[0])


def _interface(frame: Frame3D, base: str):
    """(boundary reduced indices, D rows (ni, 2, n_b), R rows (ni, n_b)) of the base."""
    nodes = frame.base_nodes
    ni = len(nodes)
    if base == "pinned":
        b = np.array([_own_dof(frame, n, c) for n in nodes for c in (0, 1, 2)])
        D = np.zeros((ni, 2, 3 * ni))
        R = np.zeros((ni, 3 * ni))
        D[np.arange(ni), 0, 3 * np.arange(ni)] = 1.0
        D[np.arange(ni), 1, 3 * np.arange(ni) + 1] = 1.0
        R[np.arange(ni), 3 * np.arange(ni) + 2] = 1.0
        return b, D, R
    master = frame.master_dofs[-1]  # the base diaphragm (base_grid appends it last)
    d = frame.diaphragms[-1]
    b = np.concatenate([master, [_own_dof(frame, n, 2) for n in nodes]])
    X, Y = (frame.nodes[nodes, :2] - d.centre).T
    D = np.zeros((ni, 2, 3 + ni))
    D[:, 0, 0], D[:, 0, 2] = 1.0, -Y
    D[:, 1, 1], D[:, 1, 2] = 1.0, X
    R = np.zeros((ni, 3 + ni))
    R[np.arange(ni), 3 + np.arange(ni)] = 1.0
    return b, D, R


def mass_fractions(frame: Frame3D, cb: CBModel) -> np.ndarray:
    """(m, 4): each fixed-interface mode's effective-mass fraction in the rigid x, y, z
    translations and the rotation about the vertical through the centre of mass."""
    c, _, _ = mass_centre(frame)
    rth = frame.rigid_motions(c)[:, 3]
    G = np.zeros((cb.n_red, 4))
    G[:, :3] = cb.Gamma
    G[: cb.n_b, 3] = rth[cb.boundary]  # in the constraint modes' span too (K_r r = 0)
    MG = cb.M @ G
    total = np.einsum("ij,ij->j", G, MG)
    return MG[cb.n_b :] ** 2 / total


def modal_reach(frame: Frame3D, cb: CBModel, M) -> np.ndarray:
    """(4,): the share of the rigid x, y, z and torsion masses that all the fixed-interface
    modes together carry, the fractions of :func:`mass_fractions` summed over every mode:
    (M r)_iᵀ M_ii⁻¹ (M r)_i over rᵀ M r (mass on the interface itself, a base slab's, is in
    no mode: a kept share is measured against this, not against 1)."""
    c, _, _ = mass_centre(frame, M)
    r = frame.rigid_motions(c)  # x, y, z and the torsion about the centre of mass
    Ms = sp.csc_array(M)
    i = np.setdiff1d(np.arange(M.shape[0]), cb.boundary)
    i = i[Ms.diagonal()[i] > 0]  # (massless dofs, a lumped mass's rotations: in no product)
    Mr = np.asarray(Ms @ r)
    try:
        x = spla.splu(Ms[i][:, i].tocsc()).solve(Mr[i])
    except RuntimeError:  # (a singular interior mass: the share unknown, measured against 1)
        return np.ones(4)
    total = np.einsum("ij,ij->j", r, Mr)
    return np.einsum("ij,ij->j", Mr[i], x) / np.where(total > 0, total, 1.0)


def _subset(cb: CBModel, keep: np.ndarray) -> CBModel:
    """The CB model with only the fixed-interface modes ``keep`` (a Ritz subspace)."""
    nb = cb.n_b
    idx = np.concatenate([np.arange(nb), nb + np.flatnonzero(keep)])
    return replace(cb, T=cb.T[:, idx], K=cb.K[np.ix_(idx, idx)], M=cb.M[np.ix_(idx, idx)],
                   C=cb.C[np.ix_(idx, idx)], Gamma=cb.Gamma[idx], omega=cb.omega[keep],
                   zeta=cb.zeta[keep])  # fmt: skip


CAPTURED_LOW = 0.5  # a cb model keeping less of a horizontal direction's mass than this


def cb_notes(info: dict) -> list[str]:
    """The notes of a cb model (a PairSystem's ``info``): no fixed-interface mode below its
    f_max, or under :data:`CAPTURED_LOW` of the effective mass of x, y or the torsion in the
    modes it keeps (the portal at 5 Hz kept x1 and y1 and none of the torsion: its torsional
    moment read 2.3x the full model's, unsaid)."""
    if info.get("fidelity") != "cb":
        return []
    if info.get("n_modes", 1) == 0:
        return [f"the cb model keeps no fixed-interface mode below f_max = {info['f_max']:g} "
                "Hz: above the base the building is rigid in it (its drifts are round-off, its "
                "floor accelerations a rigid body's); raise structure.f_max above the "
                "building's first mode"]  # fmt: skip
    got = dict(zip(("x", "y", "torsion"), np.take(info.get("captured_mass", [1.0] * 4),
                                                  [0, 1, 3]), strict=True))  # fmt: skip
    low = [f"{100 * v:.0f} % of the {k}" for k, v in got.items() if v < CAPTURED_LOW]
    return [f"the cb model at f_max = {info['f_max']:g} Hz keeps only {' and '.join(low)} "
            "effective mass in its fixed-interface modes: the building's response there (a "
            "torsional moment, corner drifts) misses its modes above f_max; raise "
            "structure.f_max"] if low else []  # fmt: skip


def reduce_building(frame: Frame3D, fidelity: str = "cb", f_max: float = 5.0,
                    min_mass: float | None = MIN_MASS, base: str = "grid",
                    lumped: bool = False) -> dict:  # fmt: skip
    """The reduction of a rung: {"frame" (with its base), "cb" (CBModel), "D", "R" (the rows
    in q), "n_modes_below_f_max", "dropped_mass" and "captured_mass" (x, y, z, torsion: the
    effective-mass fractions of the fixed-interface modes dropped by ``min_mass``, and the
    kept modes' share of what all of them carry, :func:`modal_reach`)}."""
    if fidelity not in RUNGS:
        raise ValueError(f"fidelity: expected one of {list(RUNGS)}, got {fidelity!r}")
    if base not in BASES:
        raise ValueError(f"base: expected one of {list(BASES)}, got {base!r}")
    if min_mass is not None and not (isinstance(min_mass, int | float) and 0 <= min_mass < 1):
        raise ValueError(f"min_mass: expected an effective-mass fraction in [0, 1) or None, got "
                         f"{min_mass!r}")  # fmt: skip
    if fidelity == "cb" and not (isinstance(f_max, int | float) and 0 < f_max < np.inf):
        raise ValueError(f"f_max: expected a positive frequency [Hz], got {f_max!r}")
    model = base_grid(frame) if base == "grid" else frame
    b, D, R = _interface(model, base)
    n_int = model.n_red - len(b)
    fm = np.inf if fidelity == "full" else float(f_max)
    if fidelity == "full" and n_int > FULL_MAX:
        raise ValueError(
            f"fidelity 'full': frame {frame.name!r} has {n_int} internal dofs "
            f"({frame.n_dof} dofs in all), above the dense limit {FULL_MAX} of the full rung "
            "(every fixed-interface mode, dense matrices); use fidelity 'cb' with a finite f_max"
        )
    if base == "pinned":
        cb = craig_bampton_3d(model, fm, lumped=lumped).cb
    else:
        K, M = model.reduced(lumped=lumped)
        try:
            cb = craig_bampton(K, M, b, fm, model.zeta, r=model.rigid_motions()[:, :3],
                               dense_max=DENSE_MAX_3D)  # fmt: skip
        except RuntimeError as e:  # (a NumericalFailure: Ψ r_b != r_i)
            raise ValueError(f"frame {frame.name!r} with its base held is a mechanism or "
                             f"singular to working precision ({e})") from None  # fmt: skip
    n = cb.n_red
    out = {"frame": model, "n_modes_below_f_max": cb.n_modes, "dropped_mass": [0.0] * 4,
           "captured_mass": [0.0] * 4}  # fmt: skip
    if fidelity == "cb" and cb.n_modes:
        frac = mass_fractions(model, cb)
        keep = frac.max(axis=1) >= (min_mass or 0.0)
        out["dropped_mass"] = [float(v) for v in frac[~keep].sum(axis=0)]
        reach = modal_reach(model, cb, model.reduced(lumped=lumped)[1])  # (all modes' share)
        out["captured_mass"] = [
            float(min(v / w, 1.0)) if w > 0 else 1.0
            for v, w in zip(frac[keep].sum(axis=0), reach, strict=True)
        ]
        cb = _subset(cb, keep) if min_mass else cb
        n = cb.n_red
    pad = np.zeros((D.shape[0], n - D.shape[-1]))
    out.update(cb=cb, D=np.concatenate([D, np.stack([pad, pad], axis=1)], axis=-1),
               R=np.hstack([R, pad]))  # fmt: skip
    return out


def static_state(K, M, Gamma, R, D, bearings, g: float) -> tuple[np.ndarray, np.ndarray]:
    """(q₀, λ₀) at rest under gravity: ``K* q = −M Γ_z g + Rᵀ λ``, ``R q = 0``, with
    ``K* = K + Σ (K_lam,i + λ_i/R_i) D_iᵀ D_i`` (iterated on λ in the pendulum terms).

    Every contact row picks one coordinate (a foot's u_z), so R q = 0 removes them and the
    rest is solved through a Cholesky factor of K* on the free coordinates: its conditioning
    is the structure's (the columns' axial stiffness against the bearings' lateral one), not
    that of a saddle system; when flat sliders without rubber leave the in-plane rigid
    motions free, with every slip held at zero (gravity does not load those directions and
    friction holds them where they start)."""
    from nsdyn.models.isolated.pairs import slips_held

    n = K.shape[0]
    held = np.array([int(np.flatnonzero(r)[0]) for r in R])
    free = np.setdiff1d(np.arange(n), held)
    D2 = D.reshape(-1, n)
    klam = np.repeat([b.k_lam for b in bearings], 2)
    rinv = np.repeat([0.0 if not np.isfinite(b.radius) else 1.0 / b.radius for b in bearings], 2)
    f = -M @ Gamma[:, 2] * g
    lam = np.zeros(len(held))
    q = np.zeros(n)
    for _ in range(STATIC_ITER):
        k_iso = klam + rinv * np.repeat(lam, 2)
        Ks = K + D2.T @ (k_iso[:, None] * D2)
        A, b = Ks[np.ix_(free, free)], f[free]
        if not np.any(k_iso):  # no bearing resists a slip (flat sliders without rubber, or
            # pendulums before their first normal forces): the slips are held by friction
            # where they start, at zero (K*'s null directions; its Cholesky factor exists in
            # round-off and gave centimetres of arbitrary offset)
            q[free] = slips_held(A, b, D2[:, free])
        else:
            try:
                q[free] = sla.cho_solve(sla.cho_factor(A), b)
            except sla.LinAlgError:
                w, V = np.linalg.eigh(A)
                ok = w > 1e-12 * w[-1]
                q[free] = V[:, ok] @ ((V[:, ok].T @ b) / w[ok])
        new = (Ks @ q - f)[held]  # Rᵀ λ balances the held rows
        done = np.abs(new - lam).max() <= 1e-13 * np.abs(new).max()
        lam = new
        if done or not np.any(rinv):
            break
    return q, lam


def output_maps(frame: Frame3D, cb: CBModel) -> dict:
    """Linear maps of q: floor motions (nl, 3, n), drift ratios at the centres of mass
    (ns, 2, n) and at the corners (ns, 4, 2, n), with their geometry."""
    full = frame.expand(cb.T)  # (n_dof, n): every CB shape in nodal dofs
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
    base: str = "grid",
    lumped: bool = False,
    g: float = G_EARTH,
    name: str | None = None,
):
    """The :class:`~nsdyn.models.isolated.pairs.PairSystem` of ``frame`` on one isolator under
    every base node, rung ``fidelity`` ("cb" or "full"; module text).

    ``bearings``: one :class:`Bearing` for all or one per base node (``frame.base_nodes``
    order). ``f_max`` [Hz]: the cb rung's cut-off; ``min_mass``: its participation filter
    (None or 0: every mode below f_max). ``eccentricity`` (f_x, f_y): accidental, every
    floor's centre of mass moved by these fractions of its plan dimensions. ``base``: "grid"
    or "pinned" (module text). ``info`` holds the reduction (``cb``, ``frame`` with its
    base), the kept frequencies ``f_hz``, the dropped mass fractions, ``origin`` (the
    isolators' plan centroid O; ``positions`` are about it), ``centre`` (centre of mass),
    ``m``, ``J``, the static state ``y0`` = [q₀, 0] and normal forces ``static_normal``, and
    the output maps of :func:`output_maps`.
    """
    from nsdyn.models.isolated.pairs import PairSystem

    expect("frame", frame, isinstance(frame, Frame3D), "a 3D frame (nsdyn.structure."
           "load_frame3d; a plane frame's model is nsdyn.build_system)")  # fmt: skip
    bearings = _bearings(frame, bearings)
    lumped = flag("lumped", lumped)
    ecc = eccentricity_pair(eccentricity)
    if any(ecc):
        frame = accidental_eccentricity(frame, *ecc)
    red = reduce_building(frame, fidelity, f_max, min_mass, base, lumped)
    cb, model, D, R = red.pop("cb"), red.pop("frame"), red.pop("D"), red.pop("R")
    n = cb.n_red
    xy = frame.nodes[frame.base_nodes, :2]
    origin = xy.mean(axis=0)
    maps = output_maps(model, cb)
    nl = maps["floor_map"].shape[0]
    c, m, J = mass_centre(frame)
    q0, lam0 = static_state(cb.K, cb.M, cb.Gamma, R, D, bearings, g)
    info = {"fidelity": fidelity, "base": base, "cb": cb, "frame": model,
            "f_max": float(cb.f_max), "f_hz": cb.f_hz.copy(), "n_modes": cb.n_modes,
            "n_b": cb.n_b, "min_mass": min_mass, **red, "origin": origin, "centre": c, "m": m,
            "J": J, "base_nodes": frame.base_nodes.copy(),
            "y0": np.concatenate([q0, np.zeros(n)]), "static_normal": lam0, **maps,
            # the pair system's own rest state (its bearing table's normal forces) is this
            # one: its saddle-system solve loses it to the conditioning of a building on
            # isolators (axial column stiffness against the pendulums' lateral one)
            "_static": (q0.copy(), lam0.copy())}  # fmt: skip
    label = f"cb-{cb.f_max:g}Hz" if fidelity == "cb" else "full"
    return PairSystem(M=cb.M, K=cb.K, C=cb.C, Gamma=cb.Gamma, D=D, R=R, bearings=bearings,
                      positions=xy - origin, T=maps["floor_map"].reshape(3 * nl, n), g=g,
                      name=name or f"{frame.name} {label} (n={n})", info=info)  # fmt: skip
