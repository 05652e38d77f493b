"""Fixed-base modes of a space frame: eigenpairs, participation in x, y, θz, families.

With the base nodes clamped (every reduced dof that moves a base-node dof held at zero),
the interior of the diaphragm-constrained model solves

    K_ii φ = ω² M_ii φ,    φᵀ M_ii φ = 1,

by sparse shift-invert Lanczos about σ = 0 (ARPACK through ``scipy.sparse.linalg.eigsh``;
M may be singular, e.g. massless columns) or, for small models, densely through the
Cholesky factor of K (``L⁻¹ M L⁻ᵀ ψ = ω⁻² ψ``, which also admits a singular M). A stiffness
that is not positive definite (a mechanism) is reported, never returned as modes.

Participation of mode k in the rigid motions ``r_d`` (translation x, y; rotation θz about the
frame's plan centre of mass c): ``Γ_d = φ_kᵀ M r_d``, effective-mass fractions
``Γ_x²/m``, ``Γ_y²/m``, ``Γ_θ²/J_c``. Family of a mode: each level's horizontal motion is
fitted by a rigid floor motion (translation of its mass centre U, rotation Θ; exact on a
diaphragm level), and the mode is labelled after the largest of the lumped kinetic measures
``Σ m_L U_x²`` (x), ``Σ m_L U_y²`` (y), ``Σ J_L Θ²`` (torsion), ``Σ m_i u_z,i²`` (vertical) and
the non-rigid horizontal rest (local). A degenerate eigenspace (a symmetric plan's equal x and
y frequencies) has no preferred basis; its modes are the one that follows the rigid motions
(:func:`align_degenerate`), so that a pair reads x and y, not two mixtures.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from nsdyn._checks import expect, whole
from nsdyn._lazy import LazyModule
from nsdyn.structure.frame3d import DOFS_PER_NODE, Frame3D
from nsdyn.structure.reduction import finite_pairs, lanczos_start

sla = LazyModule("scipy.linalg")
sp = LazyModule("scipy.sparse")
spla = LazyModule("scipy.sparse.linalg")

DENSE_MAX = 400  # interior dofs up to which "auto" solves densely
# "auto" also solves densely for more than 1/DENSE_FRACTION of the dofs' modes, up to
# DENSE_MANY_MAX dofs (its n x n matrices: 0.3 GB each): Lanczos for 5000 of the 3D office's
# 5181 ran for minutes without an end, the dense solve takes tens of seconds
DENSE_FRACTION = 5
DENSE_MANY_MAX = 6000
FAMILIES = ("x", "y", "torsion", "vertical", "local")


@dataclass(frozen=True, eq=False)
class Modes3D:
    """Fixed-base modes of a :class:`Frame3D`.

    Attributes
    ----------
    f_hz : (m,) frequencies, ascending.    phi : (n_red, m) mass-normalised reduced shapes.
    gamma : (m, 3) participation ``Γ`` in x, y [kg^½] and θz [kg^½ m].
    mass_fraction : (m, 3) effective-mass fractions ``Γ_x²/m``, ``Γ_y²/m``, ``Γ_θ²/J_c``.
    shares : (m, 5) kinetic measures of :data:`FAMILIES`, summing to 1.
    family : tuple of str, one of :data:`FAMILIES` per mode.
    centre : (2,) plan centre of mass [m].
    """

    frame: Frame3D
    f_hz: np.ndarray
    phi: np.ndarray
    gamma: np.ndarray
    mass_fraction: np.ndarray
    shares: np.ndarray
    family: tuple
    centre: np.ndarray

    def full(self) -> np.ndarray:
        """Mode shapes in full dofs ``T φ``, shape (n_dof, m)."""
        return self.frame.expand(self.phi)

    def of_family(self, name: str) -> np.ndarray:
        """Indices of the modes labelled ``name``, ascending frequency."""
        return np.array([k for k, f in enumerate(self.family) if f == name], dtype=np.int64)


def mass_centre(frame: Frame3D, M=None) -> tuple[np.ndarray, float, float]:
    """Plan centre of mass ``c``, total mass ``m`` and polar moment ``J_c`` about ``c``.

    From the rigid motions: ``m = r_xᵀ M r_x``, ``m x_c = r_yᵀ M r_θ``, ``m y_c = −r_xᵀ M r_θ``
    (r_θ about the origin), exact for consistent mass since rigid motion is in the element
    shape functions.
    """
    if M is None:
        M = frame.reduced()[1]
    r0 = frame.rigid_motions()
    Mr = M @ r0
    m = float(r0[:, 0] @ Mr[:, 0])
    if not m > 0.0:
        raise ValueError(
            f"frame {frame.name!r} has no horizontal mass (m = {m:g} kg): no centre of mass"
        )
    c = np.array([r0[:, 1] @ Mr[:, 3], -(r0[:, 0] @ Mr[:, 3])]) / m
    rc = frame.rigid_motions(c)[:, 3]
    return c, m, float(rc @ (M @ rc))


def _eig_dense(K, M, k):
    return finite_pairs(K.toarray(), M.toarray(), k)


def _eig_sparse(K, M, k):
    try:
        v0 = lanczos_start(K.shape[0])
        lam, V = spla.eigsh(sp.csc_array(K), k=k, M=sp.csc_array(M), sigma=0.0, which="LM", v0=v0)
    except spla.ArpackError as exc:  # e.g. M of rank close to k: the Lanczos space collapses
        raise ValueError(
            f"the sparse eigensolver failed ({exc}); if few dofs carry mass, use method='dense'"
        ) from None
    except RuntimeError as exc:  # singular factor: a mechanism
        raise ValueError(f"the fixed-base stiffness is singular (a mechanism): {exc}") from None
    if not np.all(np.isfinite(lam)) or np.any(lam <= 0):
        raise ValueError(
            f"non-positive or non-finite eigenvalues {lam[lam <= 0][:3]} (a "
            "mechanism, or a stiffness that is not positive definite)"
        )
    return lam, V


def fixed_base_modes_3d(
    frame: Frame3D, n_modes: int = 12, lumped: bool = False, method: str = "auto"
) -> Modes3D:
    """The ``n_modes`` (an integer >= 1, else a ValueError) lowest fixed-base modes of
    ``frame`` (diaphragms applied), with its consistent mass matrix, or its lumped one with
    ``lumped=True``.

    Only modes of finite frequency are returned: with massless parts (a singular M) there
    are at most as many as the dofs that carry mass.

    ``method``: ``"sparse"`` (shift-invert Lanczos), ``"dense"`` (Cholesky of K) or
    ``"auto"`` (dense up to :data:`DENSE_MAX` interior dofs, or for more than a fifth of
    them up to :data:`DENSE_MANY_MAX`).
    """
    if method not in ("auto", "sparse", "dense"):
        raise ValueError(f"method must be 'auto', 'sparse' or 'dense', got {method!r}")
    expect(
        "frame",
        frame,
        hasattr(frame, "reduced") and hasattr(frame, "diaphragms"),
        "a Frame3D (nsdyn.structure.load_frame3d(name or file))",
    )
    K, M = frame.reduced(lumped=lumped)
    b = frame.boundary_reduced
    i = np.setdiff1d(np.arange(frame.n_red), b)
    Kii, Mii = K[i][:, i], M[i][:, i]
    n = len(i)
    whole("n_modes", n_modes, 1, "an integer >= 1")
    k = min(n_modes, n)
    many = k > n // DENSE_FRACTION and n <= DENSE_MANY_MAX  # (ARPACK with k ~ n: hours)
    dense = method == "dense" or (method == "auto" and (n <= DENSE_MAX or many)) or k >= n - 1
    lam, V = _eig_dense(Kii, Mii, k) if dense else _eig_sparse(Kii, Mii, k)
    if lam.size == 0:
        raise ValueError(
            f"frame {frame.name!r}: no mode of finite frequency (no mass on the free dofs)"
        )
    order = np.argsort(lam)
    lam, V = lam[order], V[:, order]
    mn = np.einsum("ij,ij->j", V, Mii @ V)
    if np.any(mn <= 0):
        raise ValueError("a mode carries no mass (M not positive on it)")
    V = V / np.sqrt(mn)
    phi = np.zeros((frame.n_red, V.shape[1]))
    phi[i] = V
    c, m, Jc = mass_centre(frame, M)
    r = frame.rigid_motions(c)[:, [0, 1, 3]]
    gamma = (M @ phi).T @ r
    phi, gamma = align_degenerate(lam, phi, gamma)
    frac = gamma**2 / np.array([m, m, Jc])
    shares = family_shares(frame, phi)
    fam = tuple(FAMILIES[j] if row.max() > 0 else "local"  # (no measure: nothing to read)
                for j, row in zip(np.argmax(shares, axis=1), shares, strict=True))  # fmt: skip
    return Modes3D(frame, np.sqrt(lam) / (2 * np.pi), phi, gamma, frac, shares, fam, c)


DEGENERATE_RTOL = 1e-6  # eigenvalues this close (relative) share one eigenspace


def align_degenerate(lam, phi, gamma) -> tuple[np.ndarray, np.ndarray]:
    """``(phi, gamma)`` with each cluster of (nearly) equal eigenvalues ``lam`` (relative gap
    below :data:`DEGENERATE_RTOL`) given the basis of its eigenspace that follows the rigid
    motions: a solver returns any M-orthonormal basis of a degenerate eigenspace (a square
    symmetric building's x and y modes came out as two 45°-like mixtures, 39 % x and 58 % y
    each, labelled x and y by chance). The new first mode of a cluster carries all of its
    participation in the direction it participates most in (the projection of that rigid
    motion on the eigenspace), the next the rest of the next direction, and so on
    (Gram-Schmidt in the participations ``gamma``, which an orthogonal change of basis ``Q``
    maps to ``Qᵀ gamma``); shapes outside the rigid motions complete the basis."""
    n = len(lam)
    start = 0
    while start < n:
        end = start + 1
        while end < n and lam[end] - lam[start] <= DEGENERATE_RTOL * abs(lam[end]):
            end += 1
        if end - start > 1:
            G = gamma[start:end]  # (k, 3)
            norms = np.linalg.norm(G, axis=0)
            order = np.argsort(-np.round(norms / norms.max(), 6), kind="stable")  # (ties: x, y)
            dirs = [d for d in order if norms[d] > 1e-8 * norms.max()]
            Q = _orthonormal_columns([G[:, d] for d in dirs], end - start)
            phi[:, start:end] = phi[:, start:end] @ Q
            gamma[start:end] = Q.T @ G
        start = end
    return phi, gamma


def _orthonormal_columns(vectors, k: int) -> np.ndarray:
    """``k`` orthonormal columns spanning R^k: Gram-Schmidt over ``vectors`` in order (each
    skipped when it lies in the span of the earlier ones to 1e-8 of its length), then over
    the unit vectors to complete the basis."""
    Q = np.zeros((k, 0))
    for col in [*vectors, *np.eye(k)]:
        v = col - Q @ (Q.T @ col)
        v = v - Q @ (Q.T @ v)  # (twice is enough)
        nv = float(np.linalg.norm(v))
        if nv > 1e-8 * float(np.linalg.norm(col)):
            Q = np.column_stack([Q, v / nv])
        if Q.shape[1] == k:
            break
    return Q


def family_shares(frame: Frame3D, phi: np.ndarray) -> np.ndarray:
    """Lumped kinetic measures of each mode (columns of reduced ``phi``), shape (m, 5), in
    the order of :data:`FAMILIES`, each row summing to 1 (see the module docstring)."""
    _, Ml = frame.assemble(lumped=True)
    mnode = Ml.diagonal().reshape(-1, DOFS_PER_NODE)[:, :3]
    u = frame.expand(np.atleast_2d(phi.T).T).reshape(frame.n_nodes, DOFS_PER_NODE, -1)
    nm = u.shape[-1]
    ex, ey, et, ez, eres = (np.zeros(nm) for _ in range(5))
    owner = {int(n): d for d in frame.diaphragms for n in d.nodes}
    md = frame.master_dofs
    _, level_nodes = frame.levels()
    base = set(frame.base_nodes.tolist())
    for nodes in level_nodes:
        nodes = np.array([n for n in nodes.tolist() if n not in base], dtype=np.int64)
        if len(nodes) == 0:
            continue
        w, xy = mnode[nodes, 0], frame.nodes[nodes, :2]
        uh = u[nodes, :2, :]  # (k, 2, nm)
        dia = {id(owner[n]): owner[n] for n in nodes.tolist() if n in owner}
        pts_w, pts_xy = [w], [xy]
        Jextra = 0.0
        for d in dia.values():
            pts_w.append(np.array([d.mass]))
            pts_xy.append(d.centre[None, :])
            Jextra += d.inertia
        W, P = np.concatenate(pts_w), np.concatenate(pts_xy)
        mL = W.sum()
        if mL <= 0:
            continue
        c = (W[:, None] * P).sum(axis=0) / mL
        JL = float((W * ((P - c) ** 2).sum(axis=1)).sum()) + Jextra
        if dia:  # rigid: read the master of the (first) diaphragm on this level
            d = next(iter(dia.values()))
            k = frame.diaphragms.index(d)
            Ux, Uy, Th = (np.atleast_2d(phi.T).T[md[k, j]] for j in range(3))
            Ux, Uy = Ux - (c[1] - d.centre[1]) * Th, Uy + (c[0] - d.centre[0]) * Th
        else:  # mass-weighted least-squares rigid fit of the nodes' horizontal motion
            dxy = xy - c
            Ux = (w[:, None] * uh[:, 0]).sum(0) / w.sum()
            Uy = (w[:, None] * uh[:, 1]).sum(0) / w.sum()
            jw = float((w * (dxy**2).sum(1)).sum())
            mom = (w[:, None] * (dxy[:, :1] * uh[:, 1] - dxy[:, 1:] * uh[:, 0])).sum(0)
            Th = mom / jw if jw > 0 else np.zeros(nm)
        ex += mL * Ux**2
        ey += mL * Uy**2
        et += JL * Th**2
        fit_x = Ux[None] - (xy[:, 1:] - c[1]) * Th[None]
        fit_y = Uy[None] + (xy[:, :1] - c[0]) * Th[None]
        eres += (w[:, None] * ((uh[:, 0] - fit_x) ** 2 + (uh[:, 1] - fit_y) ** 2)).sum(0)
    free = np.setdiff1d(np.arange(frame.n_nodes), frame.base_nodes)
    ez = (mnode[free, 2][:, None] * u[free, 2, :] ** 2).sum(0)
    E = np.stack([ex, ey, et, ez, eres], axis=1)
    tot = E.sum(axis=1, keepdims=True)
    return E / np.where(tot > 0, tot, 1.0)


def plane_ratios(frame: Frame3D, zeta, plane: str) -> np.ndarray:
    """Damping ratios, in the frequency order of ``frame``'s fixed-base modes, of a plane
    frame's ratios ``zeta`` (its modes' in order) carried onto its 3D embedding ``frame``
    (:meth:`Frame3D.from_planar`): the k-th mode moving in ``plane`` takes the plane frame's
    k-th ratio, as the plane frame's k-th mode does, and so does the k-th mode moving out of
    it; past the list, the last ratio (:func:`~nsdyn.structure.damping_ratios`). Taken in
    frequency order as they stand, the out-of-plane modes below the in-plane ones would take
    the plane's first ratios and shift the in-plane ones. A mode moves in the plane when its
    kinetic energy φᵀMφ lies mostly on the in-plane dofs (wholly, bar a degenerate pair)."""
    from nsdyn.structure.frame3d import planar_dofs

    z = np.atleast_1d(np.asarray(zeta, float))
    if np.all(z == z[-1]):  # (one ratio for every mode: no order to keep)
        return z
    idx, _ = planar_dofs(frame.n_nodes, plane)
    _, M = frame.assemble()
    n = 2 * z.size + 4
    while True:
        modes = fixed_base_modes_3d(frame, n_modes=n)
        u = modes.full()
        e = u * (M @ u)
        inside = e[idx].sum(axis=0) > 0.5 * e.sum(axis=0)
        if min(inside.sum(), (~inside).sum()) >= z.size or modes.f_hz.size < n:
            break
        n *= 2
    k = np.where(inside, np.cumsum(inside), np.cumsum(~inside)) - 1
    return z[np.minimum(k, z.size - 1)]
