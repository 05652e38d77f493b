"""Systems from matrices whose isolators slide in a plane: data, validation, statics, runs.

Generalised coordinates q (n) relative to the ground; isolator i slips u_i = D_i q ∈ R²
(D_i of shape (2, n): its x and y rows) on a contact whose gap R_i q stays zero::

    M q̈ + C q̇ + K q = −M Γ [a_x, a_y, a_z + g] + Σ R_iᵀ λ_i − Σ D_iᵀ F_i(u_i, v_i, λ_i)
    R_i q̈ + 2αβ R_i q̇ + α² R_i q = 0          (normal contact, Baumgarte; λ_i > 0 compressive)
    F_i = λ_i (u_i/R_i + f̂_i) + K_lam,i u_i + c_i v_i + F_stop,i,   v_i = D_i q̇

with the bearing's law f̂_i (:mod:`nsdyn.models.isolated.bearings`): the regularised vector law
μ_d(|v|) (2/π) arctan(ε|v|) v/|v|, or the switch law with a stick disc (slip μ_d v/|v|; stick
D_i q̈ = −κ D_i q̇ with the stick force τ_i a multiplier while |τ_i| ≤ μ_s λ_i). K and C are the
structure's own; the bearings add their rubber, damper, pendulum and rim-stop terms. The
equations and kernels are :mod:`nsdyn.models.isolated._kpairs`; the time loops
:mod:`._kpairsrun` (Dormand–Prince, located stick/slip events) and :mod:`._kpairsradau`
(Radau IIA, the regularised law). The contact assumption ``contact``: "detect" (a λ_i reaching
zero ends the run), "bilateral" (λ_i < 0 held, the bearing's terms in λ_i at max(λ_i, 0)) or
"unilateral" (lift-off, flight and plastic landing: :mod:`._kpairscontact`).

A triple friction pendulum (:class:`nsdyn.models.isolated.tfp.TripleBearing`) resists with
F_i = λ_i φ_i, the force per unit normal force of its series model, whose four elements' slips
s_k ∈ R² (8 states per bearing) follow the elastic–viscoplastic flow of :mod:`.tfp`; they are
appended to the state, y = [q, q̇, s], and run with the regularised law on Radau IIA only (the
deck's rule). Their rims are read from the element slips (:func:`.tfp.surface_limits`).

Statics first: under gravity alone (friction carries no force at rest) the saddle system

    [K + Σ K_lam,i D_iᵀD_i + Σ λ_i/R_i D_iᵀD_i   −Rᵀ] [q₀]   [−M Γ [0, 0, g]]
    [R                                           0 ] [λ₀] = [0            ]

gives q₀ and the normal forces λ₀ (iterated on λ in the pendulum terms), solved on the free
coordinates q = Z z (R Z = 0; Z drops the gap coordinates when each contact row picks one):
Cholesky of Zᵀ K* Z (least squares where K* is singular there, e.g. flat sliders without
rubber, with a consistent load), then Rᵀ λ = K* q₀ + M Γ_z g; runs start from (q₀, 0).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla

from nsdyn._brief import brief_repr
from nsdyn._checks import NotedWarning, got_array, number
from nsdyn.ground.excitation import G_EARTH
from nsdyn.models.isolated import _kpairs as kq
from nsdyn.models.isolated import _kpairsradau as kqa
from nsdyn.models.isolated import _kpairsrun as kqr
from nsdyn.models.isolated import _kplane as kp
from nsdyn.models.isolated import pairs_compile
from nsdyn.models.isolated.bearings import B_IOFF, N_BCOL, Bearing, BearingError, stick_range_error
from nsdyn.models.isolated.deck import (
    PLANE_LAWS,
    _check_run_options,
    contact_code,
    law_params,
    pack_ground,
    run_buffers,
    run_grid,
    tfp_start_said,
)
from nsdyn.models.isolated.defaults import ALPHA, BETA, EPS, ETA
from nsdyn.models.isolated.plane_result import PlaneResult
from nsdyn.models.isolated.tfp import N_INTERNAL, TripleBearing

SYMMETRY_RTOL = 1e-10  # |A − Aᵀ| allowed relative to max |A| (M, K)
SPD_RTOL = 1e-12  # M's smallest eigenvalue must exceed this times its largest
STATIC_ITER = 50  # fixed-point passes of the pendulum terms λ/R in the static solve
REDUNDANT_RTOL = 1e-10  # contact rows' singular values below this x the largest: redundant
TWIST_RTOL = 1e-9  # slip rows reproduced by a rigid plan motion to this x max |D|: a twist
STATIC_RTOL = 1e-12  # their convergence (relative change of λ) and the saddle residual bound


class PairSystemError(BearingError):
    """A PairSystem field is invalid; the message names the field and the expected form."""


def slips_held(K: np.ndarray, f: np.ndarray, D: np.ndarray) -> np.ndarray:
    """The x of ``K x = f`` with every slip ``D x`` held at zero (x = N y, N the null space of
    ``D``): the static state where no bearing resists a slip and ``K`` is singular along the
    slips (its Cholesky factor exists in round-off and gives an arbitrary offset there)."""
    N = sla.null_space(D)
    return N @ sla.lstsq(N.T @ K @ N, N.T @ f)[0]


def _matrix(name: str, A, shape: tuple, why: str = "") -> np.ndarray:
    try:
        a = np.array(A, dtype=float)
    except (TypeError, ValueError) as e:
        raise PairSystemError(f"{name}: expected an array of numbers of shape {shape} "
                              f"({e})") from None  # fmt: skip
    if a.shape != shape:
        raise PairSystemError(f"{name}: expected shape {shape}{why}, got {a.shape}")
    bad = np.argwhere(~np.isfinite(a))
    if bad.size:
        idx = tuple(int(i) for i in bad[0])
        raise PairSystemError(f"{name}: entry {list(idx)} is {a[idx]}; expected finite numbers")
    return a


def _symmetric(name: str, a: np.ndarray) -> np.ndarray:
    scale = max(float(np.max(np.abs(a))) if a.size else 0.0, 1e-300)
    d = np.abs(a - a.T)
    if a.size and float(d.max()) > SYMMETRY_RTOL * scale:
        i, j = np.unravel_index(int(np.argmax(d)), a.shape)
        raise PairSystemError(f"{name}: not symmetric ({name}[{i}, {j}] = {a[i, j]:.6g}, "
                              f"{name}[{j}, {i}] = {a[j, i]:.6g}); expected {name} = "
                              f"{name}ᵀ")  # fmt: skip
    return 0.5 * (a + a.T)


def _semidefinite(name: str, a: np.ndarray) -> np.ndarray:
    """``a`` if positive semi-definite to round-off, else PairSystemError (-K ran to 1e26 m)."""
    ev = np.linalg.eigvalsh(a) if a.size else np.zeros(1)
    if ev[0] < -SPD_RTOL * max(abs(ev[-1]), 1e-300):
        raise PairSystemError(f"{name}: expected a positive semi-definite matrix (the "
                              f"structure's; the bearings add their own), smallest eigenvalue "
                              f"{ev[0]:.6g} (largest {ev[-1]:.6g})")  # fmt: skip
    return a


@dataclass(frozen=True, repr=False)
class PairSystem:
    """A linear structure from matrices on isolators that slide in a plane (module text).

    Shapes: M, K, C (n, n); Gamma (n, 3) (columns: the ground translations x, y, z in q;
    gravity acts along the z column); D (ni, 2, n) slip rows; R (ni, n) contact rows;
    positions (ni, 2) plan positions [m]; T (m, n) optional output map.
    """

    __repr__ = brief_repr  # arrays by shape, not in full

    M: np.ndarray  # (n, n) symmetric positive definite
    K: np.ndarray  # (n, n) symmetric (structure only; the bearings add their own terms)
    C: np.ndarray  # (n, n) structure damping
    Gamma: np.ndarray  # (n, 3) rigid ground translations x, y, z in q (−M Γ üg, gravity on z)
    D: np.ndarray  # (ni, 2, n) slip rows u_i = D[i] @ q
    R: np.ndarray  # (ni, n) contact rows, gap_i = R[i] @ q = 0
    bearings: tuple  # one bearings.Bearing per isolator
    positions: np.ndarray  # (ni, 2) plan positions [m] (outputs, orbits)
    T: np.ndarray | None = None  # optional map q -> output displacements (e.g. floor masters)
    g: float = G_EARTH
    name: str = "system"
    info: dict = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        w = self.name if isinstance(self.name, str) else "system"
        Mraw = np.asarray(self.M) if not isinstance(self.M, list) else np.array(self.M, float)
        if Mraw.ndim != 2 or Mraw.shape[0] != Mraw.shape[1] or Mraw.shape[0] < 1:
            raise PairSystemError(f"{w}.M: expected a square (n, n) matrix, got shape "
                                  f"{Mraw.shape}")  # fmt: skip
        n = Mraw.shape[0]
        M = _symmetric(f"{w}.M", _matrix(f"{w}.M", self.M, (n, n)))
        ev = np.linalg.eigvalsh(M)
        if not ev[0] > SPD_RTOL * max(abs(ev[-1]), 1e-300):
            raise PairSystemError(f"{w}.M: expected a positive definite mass matrix, smallest "
                                  f"eigenvalue {ev[0]:.6g} (largest {ev[-1]:.6g})")  # fmt: skip
        by_m = f" (n = {n}, the size of M)"
        K = _semidefinite(f"{w}.K", _symmetric(f"{w}.K", _matrix(f"{w}.K", self.K, (n, n), by_m)))
        C = _semidefinite(f"{w}.C", _symmetric(f"{w}.C", _matrix(f"{w}.C", self.C, (n, n), by_m)))
        Gam = _matrix(f"{w}.Gamma", self.Gamma, (n, 3), by_m)
        Draw = np.asarray(self.D) if not isinstance(self.D, list) else np.array(self.D, float)
        if Draw.ndim != 3 or Draw.shape[1:] != (2, n) or Draw.shape[0] < 1:
            raise PairSystemError(f"{w}.D: expected slip rows of shape (ni, 2, {n}) (x and y "
                                  f"row of each isolator), got shape {Draw.shape}")  # fmt: skip
        ni = Draw.shape[0]
        D = _matrix(f"{w}.D", self.D, (ni, 2, n))
        R = _matrix(f"{w}.R", self.R, (ni, n))
        pos = _matrix(f"{w}.positions", self.positions, (ni, 2))
        for i in range(ni):
            for c, ax in enumerate("xy"):
                if not np.any(D[i, c]):
                    raise PairSystemError(f"{w}.D[{i}, {c}]: the {ax} slip row of isolator "
                                          f"{i} is zero; expected a row giving u_{ax}")  # fmt: skip
            d = np.linalg.svd(D[i], compute_uv=False)
            if not d[1] > 1e-12 * d[0]:
                raise PairSystemError(f"{w}.D[{i}]: the x and y slip rows of isolator {i} are "
                                      "parallel; expected two independent rows")  # fmt: skip
            if not np.any(R[i]):
                raise PairSystemError(f"{w}.R[{i}]: the contact row of isolator {i} is zero; "
                                      "expected the row of its vertical gap")  # fmt: skip
        if not isinstance(self.bearings, tuple | list) or len(self.bearings) != ni:
            got = len(self.bearings) if isinstance(self.bearings, tuple | list) else self.bearings
            raise PairSystemError(f"{w}.bearings: expected {ni} Bearing{'s' * (ni != 1)} (one "
                                  f"per isolator), got {got!r}")  # fmt: skip
        for i, b in enumerate(self.bearings):
            if not isinstance(b, Bearing):
                raise PairSystemError(f"{w}.bearings[{i}]: expected a Bearing (flat slider, "
                                      f"single or triple pendulum), got "
                                      f"{type(b).__name__}")  # fmt: skip
        T = None
        if self.T is not None:
            Traw = np.asarray(self.T)
            if Traw.ndim != 2 or Traw.shape[1] != n:
                raise PairSystemError(f"{w}.T: expected an output map of shape (m, {n}), got "
                                      f"shape {Traw.shape}")  # fmt: skip
            T = _matrix(f"{w}.T", self.T, Traw.shape)
        g = self.g
        ok = isinstance(g, int | float) and not isinstance(g, bool)
        if not (ok and math.isfinite(g) and g > 0):
            raise PairSystemError(f"{w}.g: expected a positive gravity [m/s²], got {g!r}")
        if not np.any(R @ Gam[:, 2]):
            raise PairSystemError(f"{w}.Gamma: its z column does not load the contacts "
                                  "(R Γ_z = 0), so gravity gives no normal force; expected the "
                                  "vertical ground translation in q")  # fmt: skip
        for k, v in (("M", M), ("K", K), ("C", C), ("Gamma", Gam), ("D", D), ("R", R),
                     ("positions", pos), ("T", T)):  # fmt: skip
            object.__setattr__(self, k, v)
        object.__setattr__(self, "bearings", tuple(self.bearings))
        object.__setattr__(self, "g", float(g))

    @property
    def n(self) -> int:
        return self.M.shape[0]

    @property
    def n_isolators(self) -> int:
        return self.D.shape[0]

    def internal_offsets(self) -> list:
        """Each isolator's internal slips (a triple pendulum's series elements; -1 for a
        single-surface bearing) as the deck counts them: 6 + their first column in the
        result's ``internal``; in the state [q, q̇, s] they sit at 2n − 6 further on."""
        out, o = [], 6
        for b in self.bearings:
            out.append(o if isinstance(b, TripleBearing) else -1)
            o += N_INTERNAL if isinstance(b, TripleBearing) else 0
        return out

    @property
    def n_states(self) -> int:
        """Length of the state vector: [q, q̇] and the internal slips."""
        return 2 * self.n + N_INTERNAL * sum(isinstance(b, TripleBearing)
                                             for b in self.bearings)  # fmt: skip

    @property
    def has_tfp(self) -> bool:
        return any(isinstance(b, TripleBearing) for b in self.bearings)

    # ---- statics -------------------------------------------------------------------------
    def static_equilibrium(self) -> tuple[np.ndarray, np.ndarray]:
        """(q₀, λ₀): the state at rest under gravity and its normal forces (module text).

        Raises :class:`PairSystemError` when the saddle system has no solution (a load that
        the structure and the contacts cannot carry) or a normal force is not compressive."""
        key = "_static"
        if key in self.info:
            q0, lam0 = self.info[key]
            return q0.copy(), lam0.copy()
        n, ni = self.n, self.n_isolators
        D2 = self.D.reshape(2 * ni, n)
        klam = np.repeat([b.k_lam for b in self.bearings], 2)
        rinv = np.repeat([0.0 if math.isinf(b.radius) else 1.0 / b.radius
                          for b in self.bearings], 2)  # fmt: skip
        Q, Rr = self.contact_basis()
        f = -self.M @ self.Gamma[:, 2] * self.g
        picks = [np.flatnonzero(row) for row in Rr]
        if all(p.size == 1 for p in picks):  # gaps of single coordinates: drop them exactly
            Z = np.eye(n)[:, np.setdiff1d(np.arange(n), [p[0] for p in picks])]
        else:
            Z = sla.null_space(Rr)
        lam = np.zeros(ni)
        q0 = np.zeros(n)
        for _ in range(STATIC_ITER):
            k_iso = klam + rinv * np.repeat(lam, 2)
            Ks = self.K + D2.T @ (k_iso[:, None] * D2)
            Kz = Z.T @ Ks @ Z
            if not np.any(k_iso):  # no bearing resists a slip (flat sliders, or the first
                # pass of pendulums): the slips are the stiffness's null directions, held by
                # friction where they start, at zero (a factor of the singular Kz would give
                # round-off's arbitrary offset, centimetres on a 3D building)
                z = slips_held(Kz, Z.T @ f, D2 @ Z)
            else:
                try:  # (Cholesky on the free coordinates: exact where K is definite there)
                    z = sla.cho_solve(sla.cho_factor(0.5 * (Kz + Kz.T)), Z.T @ f)
                except (sla.LinAlgError, ValueError):
                    z = np.linalg.lstsq(Kz, Z.T @ f, rcond=None)[0]
            q0 = Z @ z
            rhs = Ks @ q0 - f  # = R̃ᵀ ξ
            xi = np.linalg.lstsq(Rr.T, rhs, rcond=None)[0]
            res = max(np.abs(Rr.T @ xi - rhs).max(), np.abs(Kz @ z - Z.T @ f).max())
            scale = np.abs(Ks).max() * np.abs(q0).max() + np.abs(f).max()
            if not (np.all(np.isfinite(q0)) and res <= 1e3 * STATIC_RTOL * scale):
                raise PairSystemError(
                    f"{self.name}: the static equilibrium under gravity has no solution "
                    f"(residual {res:.3g} N); check K, R and Gamma's z column"
                )
            new = Q @ xi
            done = np.abs(new - lam).max() <= STATIC_RTOL * max(np.abs(new).max(), 1e-300)
            lam = new
            if done or not np.any(rinv):
                break
        if np.any(lam <= 0):
            i = int(np.argmin(lam))
            raise PairSystemError(
                f"{self.name}: isolator {i} carries no compression at rest (normal force "
                f"{lam[i]:.4g} N); check R's sign (gap rows, λ compressive positive) and Gamma"
            )
        for b in self.bearings:
            if isinstance(b, TripleBearing):  # (its surfaces' capacities checked by itself)
                continue
            said = stick_range_error(b)
            if said:
                raise PairSystemError(said)
        self.info[key] = (q0, lam)
        return q0.copy(), lam.copy()

    def bearing_table(self) -> np.ndarray:
        """(ni, N_BCOL) packed bearing rows at the static normal forces (a triple
        pendulum's B_IOFF: its internal slips' index in the state)."""
        _, lam0 = self.static_equilibrium()
        bp = np.zeros((self.n_isolators, N_BCOL))
        for i, (b, o) in enumerate(zip(self.bearings, self.internal_offsets(), strict=True)):
            bp[i] = b.row(float(lam0[i]), self.g)
            if o >= 0:
                bp[i, B_IOFF] = o - 6 + 2 * self.n
        return bp

    def contact_basis(self) -> tuple[np.ndarray, np.ndarray]:
        """(Q, R̃): Q (ni × r) an orthonormal basis of range R and R̃ = Qᵀ R its r independent
        contact rows (Q = I, R̃ = R when the rows are independent); normal forces λ = Q ξ."""
        ni = self.n_isolators
        U, sv, _ = np.linalg.svd(self.R, full_matrices=False)
        r = int(np.sum(sv > REDUNDANT_RTOL * sv[0]))
        if r == ni:
            return np.eye(ni), self.R.copy()
        Q = U[:, :r]
        return Q, Q.T @ self.R

    def operators(self) -> tuple:
        """The kernels' precomputed operators (one Cholesky of M): M⁻¹K, M⁻¹C, Γ, D2, R̃,
        M⁻¹R̃ᵀ, M⁻¹D2ᵀ, R̃ M⁻¹R̃ᵀ, R̃ M⁻¹D2ᵀ, D2 M⁻¹R̃ᵀ, D2 M⁻¹D2ᵀ, Q (D2 = D stacked
        (2ni, n); Q, R̃ from :meth:`contact_basis`)."""
        if "_operators" not in self.info:
            cho = sla.cho_factor(self.M)
            D2 = self.D.reshape(2 * self.n_isolators, self.n)
            Q, R = self.contact_basis()
            MiRt = sla.cho_solve(cho, R.T)
            MiDt = sla.cho_solve(cho, D2.T)
            ops = (sla.cho_solve(cho, self.K), sla.cho_solve(cho, self.C), self.Gamma, D2, R,
                   MiRt, MiDt, R @ MiRt, R @ MiDt, D2 @ MiRt, D2 @ MiDt, Q)  # fmt: skip
            self.info["_operators"] = tuple(np.ascontiguousarray(a, dtype=float) for a in ops)
        return self.info["_operators"]


def from_deck(deck) -> PairSystem:
    """The rigid deck or single mass ``deck`` (:class:`nsdyn.models.isolated.deck.PlaneSystem`)
    as a PairSystem: q = (x, y, θ) of O and its vertical motion (z, r_x, r_y) (z only on one
    isolator, whose bearing takes the moments); the centre of mass at (e_x, e_y, h) moves by
    A q = (x − e_y θ + h r_y, y + e_x θ − h r_x, z + e_y r_x − e_x r_y), so M = m AᵀA plus the
    polar inertia J on θ and J on r_x, r_y (held by the contacts); gaps z + Y_i r_x − X_i r_y.
    Its contacts' normal forces are the deck's rigid-plate ones (redundant contacts keep
    normal forces in the range of R: affine in the plan positions)."""
    m, (ex, ey), h = float(deck.m), (float(e) for e in deck.ecc), float(deck.h)
    ni = deck.n_isolators
    nv = 1 if ni == 1 else 3
    n = 4 + (nv - 1)
    A = np.zeros((3, n))
    A[0, 0], A[0, 2], A[1, 1], A[1, 2], A[2, 3] = 1.0, -ey, 1.0, ex, 1.0
    if nv == 3:
        A[0, 5], A[1, 4], A[2, 4], A[2, 5] = h, -h, ey, -ex
    M = m * A.T @ A
    M[2, 2] += deck.J
    if nv == 3:
        M[4, 4] += deck.J
        M[5, 5] += deck.J
    X, Y = deck.positions.T
    D = np.zeros((ni, 2, n))
    D[:, 0, 0], D[:, 0, 2], D[:, 1, 1], D[:, 1, 2] = 1.0, -Y, 1.0, X
    R = np.zeros((ni, n))
    R[:, 3] = 1.0
    if nv == 3:
        R[:, 4], R[:, 5] = Y, -X
    Gam = np.zeros((n, 3))
    Gam[0, 0] = Gam[1, 1] = Gam[3, 2] = 1.0
    Z = np.zeros((n, n))
    return PairSystem(M, Z, Z.copy(), Gam, D, R, tuple(deck.bearings), deck.positions.copy(),
                      g=deck.g, name=deck.name)  # fmt: skip


def twist_row(system: PairSystem) -> np.ndarray | None:
    """The row Θ = a q of the base's twist when every isolator's slip is the rigid plan motion
    of one base, D_i = (a_x − Y_i a, a_y + X_i a) about the origin of the plan positions
    (least squares over the 2 ni rows, kept when it reproduces D to TWIST_RTOL of its largest
    entry); None for fewer than two isolators or slips that are not rigid (feet pinned each
    on its own isolator)."""
    ni, n = system.n_isolators, system.n
    X, Y = system.positions.T
    if ni < 2 or np.ptp(X) == 0.0 and np.ptp(Y) == 0.0:
        return None
    A = np.zeros((2 * ni, 3))
    A[0::2, 0], A[0::2, 2] = 1.0, -Y
    A[1::2, 1], A[1::2, 2] = 1.0, X
    D2 = system.D.reshape(2 * ni, n)
    coef = np.linalg.lstsq(A, D2, rcond=None)[0]
    if np.abs(A @ coef - D2).max() > TWIST_RTOL * np.abs(D2).max():
        return None
    return coef[2]


@dataclass(repr=False, eq=False)
class PairResult(PlaneResult):
    """A run of a :class:`PairSystem`: the deck's result (:class:`PlaneResult`: slips u
    (nt, ni, 2), normal forces N, friction, restoring and other forces, modes, events, rim
    contacts, uplift, summary) with ``q``, ``qd`` the full coordinates (nt, n) and the slips
    from the system's rows D; ``outputs`` = T q when the system has T; ``internal`` (nt, 8
    n_tfp) the triple pendulums' element slips."""

    def _slip(self, X) -> np.ndarray:
        return np.einsum("icn,tn->tic", self.system.D, X)

    @property
    def theta(self) -> np.ndarray:  # (no deck twist: the summary's torsion is dropped)
        return np.zeros(self.t.size)

    @property
    def twist(self) -> np.ndarray | None:
        """The rigid base's twist Θ(t) [rad] (nt,) where the slips are a rigid plan motion
        (:func:`twist_row`), else None."""
        row = twist_row(self.system)
        return None if row is None else self.q @ row

    @property
    def outputs(self) -> np.ndarray | None:
        """T q (nt, m), or None without T."""
        T = self.system.T
        return None if T is None else self.q @ T.T

    def histories(self) -> dict:
        """Coordinates q_j and per-isolator histories on ``t`` (see PlaneResult.histories)."""
        h = super().histories()
        for k in ("x_m", "y_m", "theta_rad", "vx_m_per_s", "vy_m_per_s", "omega_rad_per_s"):
            h.pop(k)
        return {"q_{}": self.q, "qd_{}": self.qd, **h}

    def summary(self) -> dict:
        s = super().summary()
        s.pop("peak_torsion_rad")
        s["n_dofs"] = int(self.system.n)
        return s


def _kernel_inputs(system: PairSystem, law: str, eps, eta, kappa, alpha, beta,
                   contact: str = "detect") -> np.ndarray:  # fmt: skip
    code = contact_code(contact, unilateral=True)
    if contact == "unilateral" and system.contact_basis()[0].shape[1] < system.n_isolators:
        raise ValueError(
            "contact: 'unilateral' needs independent contact rows R (one vertical motion per "
            f"contact), but R has rank {system.contact_basis()[0].shape[1]} for "
            f"{system.n_isolators} contacts (a rigid base on more than three isolators); "
            "expected 'detect' or 'bilateral' here"
        )
    if law not in PLANE_LAWS:
        raise ValueError(f"law: expected one of {list(PLANE_LAWS)}, got {law!r}")
    from nsdyn.models.isolated.bearings import bearing_notes

    law_params(law, eps=eps, eta=eta, alpha=alpha, beta=beta, kappa=kappa)
    for note in bearing_notes(system.bearings, system.static_equilibrium()[1]):  # (as a deck's)
        warnings.warn(note, NotedWarning, stacklevel=4)
    sp = np.zeros(kq.N_SP)
    sp[kq.S_G], sp[kq.S_ALPHA], sp[kq.S_BETA] = system.g, alpha, beta
    sp[kq.S_KAPPA] = 2 * alpha * beta if kappa is None else float(kappa)
    sp[kq.S_EPS], sp[kq.S_ETA] = eps, eta
    sp[kq.S_LAW] = kp.LAW_SWITCH if law == "switch" else kp.LAW_ARCTAN
    sp[kq.S_CONTACT] = code
    return sp


def simulate_pairs(
    system: PairSystem,
    ground,
    *,
    law: str = "switch",
    t_end: float | None = None,
    dt_out: float | None = None,
    t_eval=None,
    eps: float = EPS,
    eta: float = ETA,
    kappa: float | None = None,
    alpha: float = ALPHA,
    beta: float = BETA,
    rtol: float = 1e-6,
    atol: tuple = (1e-8, 1e-8),
    max_step: float | None = None,
    max_steps: int = 5_000_000,
    y0=None,
    integrator: str = "auto",
    contact: str = "detect",
    progress=None,
) -> PairResult:
    """Integrate ``system`` under ``ground`` from its static equilibrium (or ``y0`` = [q, q̇]).

    ``ground``: a three-component record, a harmonic orbit or raw arrays (``pack_ground``),
    until ``t_end`` [s]. ``law``: "switch" (stick disc of band ``eta`` [m/s], located events,
    on Dormand–Prince) or "arctan" (the regularised vector law of sharpness ``eps`` [s/m], on
    Radau IIA unless ``integrator="dopri5"``). Outputs every ``dt_out`` (default: the record's
    step or 1/50 period) or at ``t_eval``; ``rtol``, ``atol`` = (displacement [m], velocity
    [m/s]; the regularised law's velocity tolerance capped at ATOL_V_EPS / eps), ``max_step``
    [s] and ``max_steps`` bound the steps; ``alpha`` [1/s], ``beta``: the contact rows'
    Baumgarte gains, κ (stick rows) 2αβ by default. A failure raises PlaneIntegrationError
    with time and reason. ``contact``: "detect" (an uplift ends the run, ``result.uplift``
    and a warning), "bilateral" (contacts hold in tension, λ_i < 0; ``result.tension`` and a
    warning) or "unilateral" (lift-off, flight and plastic landing, independent contact rows,
    on Dormand–Prince; ``result.flights``). Triple friction pendulums run with the arctan law
    on Radau IIA only, their element slips from zero (``y0`` may omit them). Returns a
    PairResult; ``progress(t_done, t_end, wall_s)`` is called every few s while it runs.
    """
    if not isinstance(system, PairSystem):
        raise TypeError(f"system: expected a PairSystem, got {type(system).__name__}")
    if integrator not in ("auto", "dopri5", "radau"):
        raise ValueError(f"integrator: expected 'auto', 'dopri5' or 'radau', got {integrator!r}")
    if integrator == "radau" and law == "switch":
        raise ValueError("integrator: the switch law runs on 'dopri5' (its events need it)")
    if integrator == "radau" and contact == "unilateral":
        raise ValueError("integrator: contact 'unilateral' runs on 'dopri5' (its lift-off and "
                         "landing events need it)")  # fmt: skip
    if system.has_tfp and (law != "arctan" or integrator == "dopri5" or contact == "unilateral"):
        raise ValueError(
            "law: a triple friction pendulum runs with the regularised law 'arctan' on Radau "
            "IIA (its series model has no stick events and is stiff; not with contact "
            f"'unilateral'), got law {law!r}, integrator {integrator!r}, contact {contact!r}"
        )
    sp = _kernel_inputs(system, law, eps, eta, kappa, alpha, beta, contact)
    _check_run_options(rtol, atol, max_step, max_steps)
    loop = kqr.integrate
    if law == "arctan" and integrator in ("auto", "radau") and contact != "unilateral":
        loop = kqa.integrate
    gk, gp, tab, dur = pack_ground(ground)
    if dt_out is not None:
        number("dt_out", dt_out, "a positive step [s]", lambda v: v > 0)
    t_eval, max_step = run_grid(gk, gp, dur, t_end, dt_out, t_eval, max_step)
    n, ni, nt, ns = system.n, system.n_isolators, t_eval.size, system.n_states
    q0, _ = system.static_equilibrium()
    y = np.concatenate([q0, np.zeros(ns - n)])
    if y0 is not None:
        y = np.array(y0, dtype=float).ravel()
        if y.shape not in ((2 * n,), (ns,)) or not np.all(np.isfinite(y)):
            extra = f" (or {ns} with the internal slips)" if ns > 2 * n else ""
            raise ValueError(f"y0: expected {2 * n} finite numbers [q, q̇]{extra}, got "
                             f"{got_array(y0, (2 * n,), (ns,))}")  # fmt: skip
        tfp_start_said(y[:n], q0, system.has_tfp and y.size < ns)
        y = np.concatenate([y, np.zeros(ns - y.size)])  # (internal slips from rest)
    modes, dirs, cfg, X, NO, FF, FR, FO, MO, EV, stops, info = run_buffers(
        law, eps, rtol, atol, max_step, max_steps, nt, ni, ns
    )
    args = (y, t_eval, modes, dirs, system.operators(), system.bearing_table(), sp, gk, gp,
            tab, cfg, X, NO, FF, FR, FO, MO, EV, stops, info)  # fmt: skip
    args = (*args, pairs_compile.loop_arrays(loop, ns, n, ni))  # (the loops make none)
    status = pairs_compile.run_loop(loop, args, contact == "unilateral", progress)
    # the deck's result handles statuses, events, rim contacts and uplift; q is n wide here,
    # the internal slips are the deck's columns 6 on (its q, q̇ replaced below)
    Xd = np.concatenate([np.zeros((nt, 6)), X[:, 2 * n :]], axis=1)
    res = PairResult.from_run(system, law, t_eval, Xd, NO, FF, FR, FO, MO, EV, stops, info,
                              int(status), eps, eta, contact)  # fmt: skip
    k = res.t.size
    res.q, res.qd = X[:k, :n].copy(), X[:k, n : 2 * n].copy()
    return res
