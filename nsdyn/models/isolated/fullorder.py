"""The full-order frame in nodal coordinates: sparse stiffness and mass, damping sparse + low rank.

The ``full`` rung of the model ladder (:mod:`nsdyn.models.isolated.system`) keeps every dof of
the FE model, so its coordinates are the nodal dofs themselves (``q``: x, y, theta of every
node, relative to the ground; ``T = I``)::

    M qdd + C* qd + K* q = -M r [u''_hor, u''_ver + g] + R^T lam - D^T phi
    K* = K + K_diaphragm + D^T diag(k_lam) D          (sparse: element and bearing stencils)
    C* = D^T diag(c) D + C_s                           (isolator dampers + superstructure)

``r`` the rigid-translation influence vectors, ``R``/``D`` the base nodes' vertical/horizontal
dofs. The superstructure damping ``C_s`` is one of

- ``"modal"`` (default): the fixed-interface modes ``Phi`` (``K_ii Phi = M_ii Phi Omega^2``,
  ``Phi^T M_ii Phi = I``) damped with ``2 zeta_j omega_j``, as the Craig-Bampton rungs do.
  Their coordinates are ``eta = Phi^T M_ii (q_i - Psi q_b)`` (``Psi = -K_ii^-1 K_ib``), so
  ``C_s = A diag(2 zeta omega) A^T`` with ``A = E^T M_ii Phi`` (n x m, ``E q = q_i - Psi
  q_b``): a rank-m term, never formed as a matrix by the sparse solver. Every mode is damped
  while the frame has at most ``MODAL_ALL_MAX_DOF`` dofs (the same damping as the
  Craig-Bampton model at f_max = inf); above, the modes up to ``MODAL_F_MAX`` Hz (shift-invert
  Lanczos) and the higher ones are left to the integrator's numerical dissipation.
- ``"stiffness"``: ``C_s = beta K`` on the members, ``beta = 2 zeta_1 / omega_1`` (the first
  fixed-base mode matches, mode j gets ``zeta_1 omega_j / omega_1``): fully sparse, the damping
  of the OpenSees export's ``damping="stiffness"``.

Up to ``DENSE_MAX_DOF`` dofs the system also carries M, C*, K* as dense arrays (the dense
kernels, Radau and the event method, run on them); beyond, M and K* are sparse arrays, C* a
linear operator, and only the sparse methods run (:mod:`nsdyn.solve.sparse`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from nsdyn._brief import brief_repr
from nsdyn.models.isolated.bearings import stiff_bearing_check

__all__ = [
    "DAMPINGS",
    "DENSE_MAX_DOF",
    "MODAL_ALL_MAX_DOF",
    "MODAL_F_MAX",
    "SparseModel",
    "full_order",
    "sparse_static",
]

DAMPINGS = ("modal", "stiffness")
DENSE_MAX_DOF = 2000  # dense copies of M, C*, K* (for the dense kernels) up to this many dofs
MODAL_ALL_MAX_DOF = 1000  # "modal" damps every fixed-interface mode up to this many dofs
MODAL_F_MAX = 50.0  # Hz, above MODAL_ALL_MAX_DOF: the damped modes' cut-off (as the export)


@dataclass(eq=False, repr=False)
class SparseModel:
    """The operators of a full-order model: ``M``, ``K`` (K*) and ``C`` (sparse part of C*,
    CSR) and the low-rank damping ``C* = C + U diag(c) U^T`` (``U`` (n, m), ``c`` (m,) > 0;
    computed by ``lowrank()`` on first use)."""

    __repr__ = brief_repr  # arrays by shape, not in full

    M: sp.csr_array
    K: sp.csr_array
    C: sp.csr_array
    _U: np.ndarray | None
    _c: np.ndarray | None
    damping: str
    lowrank: object = None  # () -> (U, c): computed on first use when U, c are None

    @property
    def n(self) -> int:
        return self.M.shape[0]

    def _ensure(self) -> None:
        if self._U is None:
            self._U, self._c = self.lowrank()

    @property
    def U(self) -> np.ndarray:
        self._ensure()
        return self._U

    @property
    def c(self) -> np.ndarray:
        self._ensure()
        return self._c

    def damp(self, V: np.ndarray) -> np.ndarray:
        """``C* V`` for a vector or an (n, k) block."""
        out = self.C @ V
        if self.c.size:
            W = self.U.T @ V
            out = out + self.U @ (self.c[:, None] * W if W.ndim == 2 else self.c * W)
        return out

    def dense_damping(self) -> np.ndarray:
        """C* as a dense array (small models only)."""
        return self.C.toarray() + (self.U * self.c) @ self.U.T

    def operator(self) -> spla.LinearOperator:
        """C* as a linear operator (symmetric)."""
        n = self.n
        return spla.LinearOperator((n, n), matvec=self.damp, matmat=self.damp, dtype=float)

    @classmethod
    def from_dense(cls, M, C, K) -> SparseModel:
        """The operators of a model given by (dense or sparse) matrices; no low-rank part."""
        csr = sp.csr_array
        n = M.shape[0]
        return cls(csr(M), csr(K), csr(C), np.zeros((n, 0)), np.zeros(0), "matrices")


def own_sparse(system) -> SparseModel | None:
    """``system.sparse`` when the system's damping is that model's own, else None (no sparse
    model, or a damping matrix put in place of it: ``system.C`` is then another array)."""
    mo = getattr(system, "sparse", None)
    own = mo is not None and system.info.get("_C_of_sparse", system.C) is system.C
    return mo if own else None


def _diaphragm(frame, iso, n: int) -> sp.csr_array:
    """The stiff base diaphragm between consecutive base nodes (the ladder's, on nodal dofs)."""
    from nsdyn.models.isolated.system import _diaphragm_stiffness

    nodes = np.asarray(frame.nodes, dtype=float)
    base = np.asarray(frame.base_nodes)
    rows, cols, vals = [], [], []
    for a, b in zip(base[:-1], base[1:], strict=True):
        k = _diaphragm_stiffness(nodes[a, 0], nodes[b, 0], iso.diaphragm_EA, iso.diaphragm_EI)
        idx = np.concatenate([3 * a + np.arange(3), 3 * b + np.arange(3)])
        rows.append(np.repeat(idx, 6))
        cols.append(np.tile(idx, 6))
        vals.append(k.ravel())
    if not rows:
        return sp.csr_array((n, n))
    return sp.coo_array(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    ).tocsr()


def _modal_damping(frame, Kf, Mf) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(A, 2 zeta omega, omega, zeta) of the damped fixed-interface modes (module text)."""
    from nsdyn.structure import damping_ratios, fixed_base_modes

    n = Kf.shape[0]
    b = np.asarray(frame.boundary_dofs)
    i = np.setdiff1d(np.arange(n), b)
    f_max = None if n <= MODAL_ALL_MAX_DOF else MODAL_F_MAX
    f_hz, Phi = fixed_base_modes(Kf, Mf, b, f_max=f_max)
    omega = 2.0 * np.pi * f_hz
    zeta = damping_ratios(frame.zeta, omega.size)
    Kii = sp.csc_array(Kf[i][:, i])
    Psi = -spla.splu(Kii).solve(Kf[i][:, b].toarray())  # constraint modes (n_i, n_b)
    Y = Mf[i][:, i] @ Phi[i]  # M_ii Phi
    A = np.zeros((n, omega.size))
    A[i] = Y
    A[b] = -(Psi.T @ Y)
    return A, 2.0 * zeta * omega, omega, zeta


def full_order(frame, iso, damping: str = "modal", lumped: bool = False) -> dict:
    """The full-order model's matrices and rows (module text) as a dict of the
    :class:`~nsdyn.models.isolated.system.IsolatedSystem` fields and ``sparse``."""
    from nsdyn.structure import fixed_base_modes

    if damping not in DAMPINGS:
        raise ValueError(f"damping: expected one of {list(DAMPINGS)}, got {damping!r}")
    Kf, Mf = frame.assemble(lumped=lumped)
    Kf, Mf = sp.csr_array(Kf), sp.csr_array(Mf)
    n = Kf.shape[0]
    base = np.asarray(frame.base_nodes)
    ni = base.size
    D = np.zeros((ni, n))
    R = np.zeros((ni, n))
    D[np.arange(ni), 3 * base] = 1.0
    R[np.arange(ni), 3 * base + 1] = 1.0
    k_lam, c_iso = iso.per_isolator("k_lam", ni), iso.per_isolator("c", ni)
    bearing = sp.coo_array((k_lam, (3 * base, 3 * base)), shape=(n, n))
    K = (Kf + _diaphragm(frame, iso, n)).tocsr()
    stiff_bearing_check(k_lam, K.diagonal())
    K = (K + bearing).tocsr()
    C = sp.coo_array((c_iso, (3 * base, 3 * base)), shape=(n, n)).tocsr()
    info: dict = {"damping": damping}
    U, c, lowrank = np.zeros((n, 0)), np.zeros(0), None
    if damping == "modal":  # the modes when first needed (a large model's Lanczos is costly)
        U = c = None

        def lowrank():
            A, cd, omega, zeta = _modal_damping(frame, Kf, Mf)
            info.update(omega=omega, zeta=zeta, n_modes=int(omega.size))
            keep = cd > 0.0
            return np.ascontiguousarray(A[:, keep]), cd[keep]
    else:
        f1, _ = fixed_base_modes(Kf, Mf, frame.boundary_dofs, n_modes=1)
        beta = 2.0 * float(frame.zeta[0]) / (2.0 * np.pi * float(f1[0]))
        C = (C + beta * Kf).tocsr()
        info.update(beta_k=beta, n_modes=0)
    model = SparseModel(Mf, K, C, U, c, damping, lowrank)
    if n <= DENSE_MAX_DOF:
        out = {"M": Mf.toarray(), "K": K.toarray(), "C": model.dense_damping(), "T": np.eye(n)}
        out["C"] = 0.5 * (out["C"] + out["C"].T)
    else:
        out = {"M": Mf, "K": K, "C": model.operator(), "T": sp.identity(n, format="csr")}
    out.update(Gamma=frame.influence(), R=R, D=D, sparse=model, info=info)
    return out


def sparse_static(model: SparseModel, Gamma, R, D, g: float) -> tuple[np.ndarray, np.ndarray]:
    """Gravity equilibrium ``K* q - R^T lam = -M Gamma[:, 1] g``, ``R q = 0`` by a sparse
    solve on the dofs the contact rows leave free (each row of ``R`` picks one dof).
    Returns (x0 = [q, 0], lam)."""
    n = model.n
    picks = [np.flatnonzero(r) for r in np.atleast_2d(R)]
    if any(p.size != 1 for p in picks):
        raise ValueError("contact rows: expected each row of R to pick one dof")
    held = np.array([p[0] for p in picks], dtype=np.int64)
    free = np.setdiff1d(np.arange(n), held)
    f = -(model.M @ Gamma[:, 1]) * g
    Kff = sp.csc_array(model.K[free][:, free])
    try:
        lu = spla.splu(Kff)
    except RuntimeError:  # no horizontal spring (k_lam = 0): hold the rigid sliding
        shift = 1e-12 * float(abs(Kff).max()) * sp.csc_array((D.T @ D)[free][:, free])
        lu = spla.splu(sp.csc_array(Kff + shift))
    q = np.zeros(n)
    q[free] = lu.solve(f[free])
    resid = model.K @ q - f  # = R^T lam: nonzero on the held dofs only
    lam = np.array([resid[h] / float(R[k, h]) for k, h in enumerate(held)])
    return np.concatenate([q, np.zeros(n)]), lam
