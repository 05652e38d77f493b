"""Craig–Bampton reduction of a linear superstructure.

Partition the full dofs into boundary ``b`` (the base nodes) and internal ``i`` ones,

    q = [q_b; q_i] ≈ T [q_b; eta],   T = [[I, 0], [Psi, Phi]],
    Psi = -K_ii^-1 K_ib             (constraint modes: static response to unit q_b),
    K_ii Phi = M_ii Phi diag(omega^2),  Phi^T M_ii Phi = I  (fixed-interface modes),

keeping the fixed-interface modes with ``omega / 2 pi <= f_max`` (Craig & Bampton, "Coupling
of substructures for dynamic analyses", AIAA J. 6(7):1313-1319, 1968). The reduced matrices
are ``K = T^T K T`` (block diagonal: the condensed boundary stiffness and diag(omega^2)) and
``M = T^T M T``. With ``f_max = inf`` all modes are kept and the reduced model is the full
model in another basis. On large models the number of modes below f_max is counted first
(Sylvester's law of inertia on ``K_ii - (2 pi f_max)^2 M_ii``) and asked for at once.

Relative coordinates: the ground-motion load on the full model is ``-M r u''`` with ``r`` the
rigid-translation influence vectors. Because ``K r = 0`` (free frame), ``K_ib r_b + K_ii r_i =
0``, i.e. ``Psi r_b = r_i``: rigid motion lies exactly in the span of the constraint modes, so
``T Gamma = r`` with ``Gamma = [r_b; 0]`` and the reduced load ``-T^T M r u'' = -M_red Gamma
u''`` is exact. :func:`craig_bampton` asserts this.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from nsdyn._brief import brief_repr
from nsdyn._checks import NumericalFailure, mapped, whole
from nsdyn._lazy import LazyModule
from nsdyn.structure.frame import Frame

sla = LazyModule("scipy.linalg")
sp = LazyModule("scipy.sparse")
spla = LazyModule("scipy.sparse.linalg")

__all__ = [
    "CBModel",
    "craig_bampton",
    "damping_ratios",
    "fixed_base_modes",
    "kinetic_energy_shares",
    "mode_type",
    "reduce_frame",
]

# above this many internal dofs, sparse shift-invert Lanczos: on the 1 593-dof scale
# frame (nsdyn bench scale) its modes below 50 Hz took 0.07 s against a dense eigh's 1.9 s
DENSE_MAX = 1000
RIGID_RTOL = 1e-6  # tolerance of the check T Gamma == r (relative to max |r|)
EIGSH_K0 = 20  # first batch of modes requested from eigsh; doubled until f_max is passed
EIGSH_PAD = 8  # modes requested beyond those counted below f_max (inertia), or asked for


@dataclass(frozen=True, eq=False, repr=False)
class CBModel:
    """A Craig–Bampton reduced model ``M q'' + C q' + K q = -M Gamma u''``.

    Attributes
    ----------
    T : ndarray, shape (n_full, n_red)
        Maps reduced ``q = [q_b, eta]`` to full dofs (in full-dof order).
    K, M, C : ndarray, shape (n_red, n_red)
        Reduced stiffness, mass and damping (dense).
    Gamma : ndarray, shape (n_red, 2)
        Reduced horizontal / vertical influence vectors, ``[r_b; 0]``.
    boundary : ndarray of int, shape (n_b,)
        Full-dof indices of the boundary dofs; ``q[:n_b]`` are these dofs.
    n_b : int
    omega : ndarray, shape (n_modes,)
        Fixed-interface circular frequencies [rad/s] of the kept modes.
    zeta : ndarray, shape (n_modes,)
        Their damping ratios.
    f_max : float
        Cut-off frequency [Hz] (``inf``: all modes).
    """

    __repr__ = brief_repr  # arrays by shape, not in full

    T: np.ndarray
    K: np.ndarray
    M: np.ndarray
    C: np.ndarray
    Gamma: np.ndarray
    boundary: np.ndarray
    n_b: int
    omega: np.ndarray
    zeta: np.ndarray
    f_max: float

    @property
    def n_red(self) -> int:
        return self.K.shape[0]

    @property
    def n_modes(self) -> int:
        return len(self.omega)

    @property
    def f_hz(self) -> np.ndarray:
        """Kept fixed-interface frequencies [Hz]."""
        return self.omega / (2 * np.pi)

    def expand(self, q: np.ndarray) -> np.ndarray:
        """Full displacements ``T q``; ``q`` shape (n_red,) or (n_red, nt)."""
        return mapped(self.T, q)


def lanczos_start(n: int) -> np.ndarray:
    """The start vector of every shift-invert Lanczos solve (``eigsh``'s ``v0``): ARPACK's
    own is random and changes from call to call, so two solves of the same model gave
    eigenvalues apart by round-off (1e-12 relative, the last Krylov iterate's accuracy); a
    fixed generic vector (pseudo-random, no mode orthogonal to it) gives the same numbers on
    every call."""
    return np.random.default_rng(1).standard_normal(n)


def damping_ratios(zeta: float | Sequence[float], n: int) -> np.ndarray:
    """Damping ratios of the first ``n`` modes: the listed ones in order, and the LAST
    listed ratio for every mode beyond the list."""
    z = np.atleast_1d(np.asarray(zeta, float))
    if z.size == 0:
        raise ValueError("zeta must list at least one ratio")
    out = np.full(n, z[-1])
    m = min(n, z.size)
    out[:m] = z[:m]
    return out


def _dense(A) -> np.ndarray:
    return A.toarray() if sp.issparse(A) else np.asarray(A, float)


def _partition(K, M, boundary):
    n = K.shape[0]
    b = np.asarray(boundary, dtype=np.int64)
    if b.ndim != 1 or len(np.unique(b)) != len(b) or (len(b) and (b.min() < 0 or b.max() >= n)):
        raise ValueError("boundary must list distinct dof indices of the model")
    i = np.setdiff1d(np.arange(n), b)
    K = sp.csr_array(K) if sp.issparse(K) else np.asarray(K, float)
    M = sp.csr_array(M) if sp.issparse(M) else np.asarray(M, float)
    return K, M, b, i


def _sub(A, r, c):
    return A[r][:, c] if sp.issparse(A) else A[np.ix_(r, c)]


def _count_below(K, M, w2) -> int | None:
    """Number of eigenvalues of ``K phi = lam M phi`` below ``w2`` (Sylvester's law of
    inertia: the negative pivots of ``K - w2 M = P L D L^T P^T``), from a sparse LU with
    symmetric pivoting only; None when that factorisation is unavailable or pivoted rows."""
    if not np.isfinite(w2):
        return None
    try:
        lu = spla.splu(
            sp.csc_array(K - w2 * M),
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
    except RuntimeError:  # w2 an eigenvalue to working precision: no factor
        return None
    if not np.array_equal(lu.perm_r, lu.perm_c):
        return None
    return int(np.count_nonzero(lu.U.diagonal() < 0))


# massless directions have mu = 1/omega^2 = 0; the symmetric eigensolver returns them within
# c n eps ||A|| = c n eps mu_1 (backward stability, c = 10): below that a mu is no mode
EIG_ROUNDOFF_C = 10.0


class MechanismError(ValueError):
    """A stiffness that is not positive definite where it must be (a mechanism)."""


def finite_pairs(K: np.ndarray, M: np.ndarray, k: int | None = None):
    """The ``k`` (default all) lowest eigenpairs ``(lam, V)`` of finite ``lam`` of dense
    ``K phi = lam M phi`` with K positive definite and M positive semi-definite (dofs without
    mass: massless members), ascending, through the Cholesky factor of K:
    ``L^-1 M L^-T psi = mu psi``, ``lam = 1/mu``; the zero ``mu`` of massless directions
    (below :data:`EIG_ROUNDOFF_C` n eps of the largest) are dropped. ValueError when K is
    not positive definite (a mechanism): a :class:`MechanismError`."""
    try:
        L = sla.cholesky(K, lower=True)
    except sla.LinAlgError:
        raise MechanismError(
            "the fixed-base stiffness is not positive definite (a mechanism or an unsupported part)"
        ) from None
    A = sla.solve_triangular(L, sla.solve_triangular(L, M, lower=True).T, lower=True)
    mu, Psi = sla.eigh((A + A.T) / 2)
    order = np.argsort(mu)[::-1][:k]
    mu, Psi = mu[order], Psi[:, order]
    keep = mu > mu[0] * EIG_ROUNDOFF_C * len(A) * np.finfo(float).eps if len(mu) else mu > 0
    return 1.0 / mu[keep], sla.solve_triangular(L.T, Psi[:, keep], lower=False)


PAIR_CHECK = 12  # the lowest pairs of LAPACK's generalized solve checked by their residuals
PAIR_RESIDUAL = 1e-6  # their relative residual's bound: well-posed pencils leave ~1e-9


def _dense_pairs(K: np.ndarray, M: np.ndarray):
    """All eigenpairs of finite eigenvalue of ``K phi = lam M phi``: LAPACK's generalized
    solver, checked, or :func:`finite_pairs` (through the Cholesky factor of K) for a
    singular M (massless members' rotations) or where the check fails. LAPACK factors M,
    and on a mass matrix of very unequal entries (members of 1e-6 kg/m beside a 12 t floor
    and a stiff beam) it returned a negative lam (a 0 Hz first mode) or 8.37 Hz for a 6.45 Hz
    portal: a lowest pair whose eigenvalue is not positive, or whose residual
    |K v - lam M v| / (|K v| + lam |M v|) exceeds :data:`PAIR_RESIDUAL`, is refused."""
    try:
        lam, V = sla.eigh(K, M)
    except sla.LinAlgError:
        return finite_pairs(K, M)
    lo, W = lam[:PAIR_CHECK], V[:, :PAIR_CHECK]
    KW, MW = K @ W, M @ W
    res = np.linalg.norm(KW - MW * lo, axis=0) / (
        np.linalg.norm(KW, axis=0) + np.abs(lo) * np.linalg.norm(MW, axis=0))  # fmt: skip
    if lo.size and (lo[0] <= 0 or not np.all(res <= PAIR_RESIDUAL)):
        return finite_pairs(K, M)
    return lam, V


def _interior_modes(Kii, Mii, f_max, n_modes, dense_max=None):
    """Lowest eigenpairs of ``Kii phi = w^2 Mii phi``, mass-normalised, by f_max / count;
    dense up to ``dense_max`` internal dofs (default :data:`DENSE_MAX`, read at the call),
    else sparse shift-invert Lanczos. ValueError for an f_max that is not a positive
    frequency (or inf) and a count below 1 (a negative f_max squared was taken as |f_max|)."""
    if f_max is not None and not (isinstance(f_max, int | float | np.number) and f_max > 0):
        raise ValueError(f"f_max: expected a positive frequency [Hz] or inf, got {f_max!r}")
    if n_modes is not None:
        whole("n_modes", n_modes, 1, "an integer >= 1")
    n = Kii.shape[0]
    dense_max = DENSE_MAX if dense_max is None else dense_max
    w2_max = (2 * np.pi * f_max) ** 2 if f_max is not None and np.isfinite(f_max) else np.inf
    sparse_ok = n > dense_max and (n_modes is not None or np.isfinite(w2_max))
    if sparse_ok:
        Kii, Mii = sp.csc_array(Kii), sp.csc_array(Mii)
        below = _count_below(Kii, Mii, w2_max) if n_modes is None else None
        k0 = n_modes if n_modes is not None else EIGSH_K0 if below is None else below + 1
        k = max(k0 + EIGSH_PAD, 1)
        while k < n - 1:  # eigsh takes k < n; (nearly) every pair is a dense solve's work
            lam, V = spla.eigsh(Kii, k=k, M=Mii, sigma=0.0, which="LM", v0=lanczos_start(n))
            order = np.argsort(lam)
            lam, V = lam[order], V[:, order]
            if (n_modes is not None and len(lam) >= n_modes) or lam[-1] > w2_max:
                break
            k *= 2
        else:
            sparse_ok = False
    if not sparse_ok:
        lam, V = _dense_pairs(_dense(Kii), _dense(Mii))
    keep = lam <= w2_max
    if n_modes is not None:
        keep &= np.arange(len(lam)) < n_modes
    lam, V = lam[keep], V[:, keep]
    # mass-normalise (eigh already does; eigsh too, but be explicit and robust)
    mnorm = np.sqrt(np.einsum("ij,ij->j", V, Mii @ V))
    V = V / mnorm
    return np.sqrt(np.clip(lam, 0.0, None)), V


def fixed_base_modes(K, M, boundary, n_modes: int | None = None, f_max: float | None = None):
    """Fixed-base (boundary-clamped) modes of the full model.

    Parameters
    ----------
    K, M : sparse or ndarray, shape (n, n)
    boundary : array of int
        Dofs held at zero.
    n_modes : int, optional
        Keep at most this many (lowest) modes.
    f_max : float, optional
        Keep modes with frequency <= f_max [Hz]. With neither limit, all modes.

    Returns
    -------
    f_hz : ndarray, shape (m,)
        Frequencies in ascending order.
    Phi : ndarray, shape (n, m)
        Mass-normalised mode shapes in full-dof order, zero at the boundary dofs.
    """
    K, M, b, i = _partition(K, M, boundary)
    omega, V = _interior_modes(_sub(K, i, i), _sub(M, i, i), f_max, n_modes)
    Phi = np.zeros((K.shape[0], V.shape[1]))
    Phi[i] = V
    return omega / (2 * np.pi), Phi


def craig_bampton(
    K,
    M,
    boundary,
    f_max: float,
    zeta: float | Sequence[float],
    r: np.ndarray | None = None,
    dense_max: int | None = None,
) -> CBModel:
    """Craig–Bampton reduction (Craig & Bampton, AIAA J. 6(7):1313-1319, 1968).

    Parameters
    ----------
    K, M : sparse or ndarray, shape (n, n)
        Stiffness and mass of the unsupported structure (rigid-body modes in ``K``'s null
        space are what makes ``Gamma = [r_b; 0]`` exact).
    boundary : array of int, shape (n_b,)
        Full-dof indices of the boundary (interface) dofs, in the order they take in ``q_b``.
    f_max : float
        Keep fixed-interface modes with frequency <= f_max [Hz]; ``np.inf`` keeps all.
    zeta : float or sequence of float
        Damping ratios of the fixed-interface modes in frequency order; modes beyond the
        list get the last listed ratio (:func:`damping_ratios`).
    r : ndarray, shape (n, 2), optional
        Full influence vectors (columns horizontal, vertical). Default: boundary dofs are
        node triples ``(x, y, theta)``, i.e. ``r_b`` = 1 at every 1st / 2nd boundary dof.
        Any number of columns (e.g. x, y, z rigid translations of a space frame).
    dense_max : int, optional
        Fixed-interface modes by dense ``eigh`` up to this many internal dofs, above it by
        sparse shift-invert Lanczos (no dense matrix of the internal size); default
        :data:`DENSE_MAX`.

    Returns
    -------
    CBModel
        ``C`` is zero on the boundary block and ``diag(2 zeta_j omega_j)`` on the modal
        block: modal damping belongs to the fixed-base modes of the superstructure, and
        rigid/boundary motion (e.g. sliding on the isolators) is not damped by the
        superstructure (a mass-proportional term would wrongly damp the sliding itself).

    Notes
    -----
    ``T @ Gamma == r`` (rigid translation is spanned by the constraint modes because
    ``Psi r_b = r_i``) is asserted, so the reduced earthquake load is exact.
    """
    K, M, b, i = _partition(K, M, boundary)
    n, nb = K.shape[0], len(b)
    Kii, Kib = _sub(K, i, i), _sub(K, i, b)
    if sp.issparse(Kii):
        lu = spla.splu(sp.csc_array(Kii))
        Psi = -lu.solve(_dense(Kib))
    else:
        Psi = -sla.solve(Kii, Kib, assume_a="sym")
    omega, Phi = _interior_modes(Kii, _sub(M, i, i), f_max, None, dense_max)
    nm = len(omega)
    T = np.zeros((n, nb + nm))
    T[b, np.arange(nb)] = 1.0
    T[np.ix_(i, np.arange(nb))] = Psi
    T[np.ix_(i, nb + np.arange(nm))] = Phi
    Kr = T.T @ (K @ T)
    Mr = T.T @ (M @ T)
    Kr = (Kr + Kr.T) / 2
    Mr = (Mr + Mr.T) / 2
    z = damping_ratios(zeta, nm)
    C = np.zeros_like(Kr)
    C[nb:, nb:] = np.diag(2 * z * omega)

    if r is None:
        r = np.zeros((n, 2))
        r[b[0::3], 0] = 1.0
        r[b[1::3], 1] = 1.0
        check_full = False
    else:
        r = np.asarray(r, float)
        check_full = True
    Gamma = np.zeros((nb + nm, r.shape[1]))
    Gamma[:nb] = r[b]
    TG = T @ Gamma
    scale = max(1.0, float(np.abs(r).max()))
    # (an assertion's traceback before: a frame in millimetres, storey heights of 6000 m)
    why = ("its stiffness matrix is too ill-conditioned for the reduction: check the frame's "
           "units (lengths in m, sections in m², m⁴, E in Pa) and its stiffness span")  # fmt: skip
    if check_full:
        err = float(np.abs(TG - r).max())
        if not err <= RIGID_RTOL * scale:
            raise NumericalFailure(f"Craig-Bampton: the static modes miss the rigid motion of "
                                   f"the base by {err:.3g} (of {scale:g}): {why}")  # fmt: skip
    else:  # T Gamma must be a rigid-body motion: K T Gamma = 0
        kn = float(np.abs(K @ TG).max())
        kscale = float(abs(K).max()) * float(np.abs(TG).max())
        if not kn <= RIGID_RTOL * kscale:
            raise NumericalFailure(f"Craig-Bampton: T Gamma is not a rigid motion (K T Gamma "
                                   f"= {kn:.3g} of {kscale:.3g}): {why}")  # fmt: skip
    return CBModel(
        T=T,
        K=Kr,
        M=Mr,
        C=C,
        Gamma=Gamma,
        boundary=b,
        n_b=nb,
        omega=omega,
        zeta=z,
        f_max=float(f_max),
    )


def reduce_frame(frame: Frame, f_max: float, lumped: bool = False) -> CBModel:
    """Craig–Bampton model of ``frame`` with its base nodes as the boundary."""
    K, M = frame.assemble(lumped=lumped)
    return craig_bampton(K, M, frame.boundary_dofs, f_max, frame.zeta, r=frame.influence())


def kinetic_energy_shares(phi: np.ndarray, M, frame: Frame) -> np.ndarray:
    """Share of a mode's kinetic energy ``phi^T M phi`` in x, y and rotation dofs.

    Returns ndarray, shape (3,) (or (3, m) for ``phi`` of shape (n, m)), summing to 1.
    """
    phi = np.asarray(phi, float)
    if phi.shape[0] != frame.n_dof:
        raise ValueError(
            f"phi has {phi.shape[0]} rows, frame {frame.name!r} has {frame.n_dof} dofs"
        )
    e = phi * (M @ phi)
    parts = np.stack([e[0::3].sum(axis=0), e[1::3].sum(axis=0), e[2::3].sum(axis=0)])
    return parts / parts.sum(axis=0)


def mode_type(phi: np.ndarray, M, frame: Frame) -> str:
    """``"lateral"`` if the x dofs hold more kinetic energy than the y dofs, else
    ``"vertical"`` (mass-weighted share, :func:`kinetic_energy_shares`)."""
    sx, sy, _ = kinetic_energy_shares(phi, M, frame)
    return "lateral" if sx >= sy else "vertical"
