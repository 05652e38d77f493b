"""Craig–Bampton reduction of a space frame with its isolator (base) nodes as the interface.

In the diaphragm-constrained coordinates ``q_r`` of :class:`~nsdyn.structure.Frame3D`
(``K_r``, ``M_r``, sparse), the boundary ``b`` is, at every base node, the two horizontal
slips and the vertical (normal contact) translation, ``(u_x, u_y, u_z)`` — or all six dofs
with ``boundary="all"`` — and everything else is internal:

    q_r ≈ T [q_b; η],   T = [[I, 0], [Ψ, Φ]],   Ψ = −K_ii⁻¹ K_ib,
    K_ii Φ = M_ii Φ diag(ω²),  Φᵀ M_ii Φ = I,  ω / 2π ≤ f_max,
    K_cb = Tᵀ K_r T = diag(K_bb − K_bi K_ii⁻¹ K_ib, diag(ω²)),   M_cb = Tᵀ M_r T

(Craig & Bampton, AIAA J. 6(7):1313–1319, 1968; :func:`nsdyn.structure.craig_bampton` does
the algebra). Ψ comes from one sparse LU of K_ii, Φ from shift-invert Lanczos about 0: no
dense matrix of the internal size is formed (dense only up to ``dense_max`` internal dofs).

Base rotations. A sliding isolator carries no moment, so by default the base rotations are
internal: the constraint modes are the static response to a unit slip or lift with zero base
moments (the rotations statically condensed), and the fixed-interface modes have pinned feet.
``boundary="all"`` keeps them as interface dofs (for a base grid or deck that restrains them;
the fixed-interface modes are then the clamped fixed-base modes).

Ground motion: the rigid translations ``r`` (x, y, z) satisfy ``K_r r = 0``, so ``Ψ r_b = r_i``
and ``T Γ = r`` with ``Γ = [r_b; 0]`` exactly (asserted): the reduced load ``−M_cb Γ ü_g`` is
exact. Accuracy: the CB space is a Ritz space, so every CB eigenvalue of the model with any
boundary springs lies above the full one, decreases as f_max grows, and (for M positive
definite) ``λ_k ≤ λ̃_k ≤ λ_k / (1 − 2 λ_k/λ_c)``, ``λ_c`` the lowest dropped ω² (> (2π f_max)²):
take the trial vectors x_j − e_j, e_j the dropped fixed-interface part of the exact mode x_j,
for which ``wᵀK w ≤ λ_k`` and ``wᵀM w ≥ 1 − 2 λ_k/λ_c`` on their span.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from nsdyn._brief import brief_repr
from nsdyn._checks import mapped
from nsdyn.structure.frame3d import DOFS_PER_NODE, Frame3D
from nsdyn.structure.reduction import CBModel, MechanismError, craig_bampton

__all__ = ["BOUNDARIES", "CBModel3D", "DENSE_MAX_3D", "craig_bampton_3d"]

BOUNDARIES = {"translations": (0, 1, 2), "all": (0, 1, 2, 3, 4, 5)}  # dofs per base node
DENSE_MAX_3D = 400  # internal dofs up to which the fixed-interface modes are solved densely
_NAMES = ("ux", "uy", "uz", "rx", "ry", "rz")


@dataclass(frozen=True, eq=False, repr=False)
class CBModel3D:
    """A space frame's Craig–Bampton model ``M q̈ + C q̇ + K q = −M Γ ü_g`` (+ interface forces).

    ``q = [q_b; η]``: ``q_b`` node by node, :attr:`components` at each base node (in
    :attr:`boundary_nodes` order), then the fixed-interface modal coordinates ``η``.
    ``Γ`` (n_cb, 3): the rigid translations x, y, z. ``cb`` holds the matrices (``T`` maps to
    the frame's diaphragm-constrained coordinates ``q_r``).
    """

    __repr__ = brief_repr  # arrays by shape, not in full

    frame: Frame3D
    cb: CBModel
    boundary_nodes: np.ndarray
    components: tuple

    K = property(lambda self: self.cb.K)
    M = property(lambda self: self.cb.M)
    C = property(lambda self: self.cb.C)
    Gamma = property(lambda self: self.cb.Gamma)
    omega = property(lambda self: self.cb.omega)
    zeta = property(lambda self: self.cb.zeta)
    f_hz = property(lambda self: self.cb.f_hz)
    n_b = property(lambda self: self.cb.n_b)
    n_modes = property(lambda self: self.cb.n_modes)
    n_red = property(lambda self: self.cb.n_red)
    f_max = property(lambda self: self.cb.f_max)

    def boundary_index(self, component: int | str) -> np.ndarray:
        """Indices in ``q`` of ``component`` ('ux', 'uy', 'uz', …) at each base node."""
        kept = [_NAMES[j] for j in self.components]
        if isinstance(component, str) and component not in _NAMES:
            raise ValueError(f"component {component!r}: expected one of {kept} (or its index)")
        c = _NAMES.index(component) if isinstance(component, str) else int(component)
        if c not in self.components:
            raise ValueError(f"component {component!r} is not an interface dof: {kept}")
        k = len(self.components)
        return np.arange(len(self.boundary_nodes)) * k + self.components.index(c)

    def expand_reduced(self, q: np.ndarray) -> np.ndarray:
        """Diaphragm-constrained coordinates ``q_r = T q``; ``q`` (n_cb,) or (n_cb, m)."""
        return mapped(self.cb.T, q)

    def expand(self, q: np.ndarray) -> np.ndarray:
        """Full nodal displacements (six per node) of ``q``; (n_cb,) or (n_cb, m)."""
        return self.frame.expand(mapped(self.cb.T, q))


def _boundary(frame: Frame3D, comps) -> np.ndarray:
    """Reduced indices of ``comps`` at each base node, node by node (T's row is a unit)."""
    T = frame.T.tocsr()
    rows = (DOFS_PER_NODE * frame.base_nodes[:, None] + np.asarray(comps)).ravel()
    out = np.empty(len(rows), dtype=np.int64)
    for k, r in enumerate(rows.tolist()):
        cols, vals = T.indices[T.indptr[r] : T.indptr[r + 1]], T.data[T.indptr[r] : T.indptr[r + 1]]
        if len(cols) != 1 or vals[0] != 1.0:
            node = int(frame.base_nodes[k // len(comps)])
            raise ValueError(
                f"base node {node} is tied by a diaphragm: an interface dof must be a node's "
                "own dof (no diaphragm at the base level)"
            )
        out[k] = cols[0]
    return out


def craig_bampton_3d(
    frame: Frame3D,
    f_max: float,
    boundary: str = "translations",
    lumped: bool = False,
    dense_max: int = DENSE_MAX_3D,
) -> CBModel3D:
    """Craig–Bampton model of ``frame`` with its base nodes as the interface (module text).

    ``f_max`` [Hz]: keep the fixed-interface modes up to it (``np.inf``: all, only for models
    of at most ``dense_max`` internal dofs); ``boundary``: ``"translations"`` (u_x, u_y, u_z
    per base node, rotations condensed) or ``"all"`` (six per node); ``lumped``: HRZ mass.
    Damping: ``frame.zeta`` on the fixed-interface modes (:func:`craig_bampton`).
    """
    if boundary not in BOUNDARIES:
        raise ValueError(f"boundary: expected one of {list(BOUNDARIES)}, got {boundary!r}")
    if not (isinstance(f_max, int | float) and f_max > 0):
        raise ValueError(f"f_max: expected a positive frequency [Hz] or inf, got {f_max!r}")
    comps = BOUNDARIES[boundary]
    b = _boundary(frame, comps)
    n_int = frame.n_red - len(b)
    if not np.isfinite(f_max) and n_int > dense_max:
        raise ValueError(
            f"f_max = inf keeps all {n_int} fixed-interface modes: a dense eigenproblem above "
            f"dense_max = {dense_max}; give a finite f_max"
        )
    K, M = frame.reduced(lumped=lumped)
    r = frame.rigid_motions()[:, :3]
    try:
        cb = craig_bampton(K, M, b, float(f_max), frame.zeta, r=r, dense_max=dense_max)
    except (RuntimeError, MechanismError) as exc:  # singular K_ii: no factor (or one whose
        # modes find it not positive definite), or Ψ r_b != r_i (NumericalFailure)
        raise ValueError(
            f"the frame with its interface dofs {[_NAMES[c] for c in comps]} held is a "
            f"mechanism or singular to working precision ({exc}); e.g. a plane frame on pins "
            "turns about its base line: use boundary='all'"
        ) from None
    return CBModel3D(frame, cb, frame.base_nodes.copy(), tuple(comps))
