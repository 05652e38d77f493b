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
(Radau IIA, the regularised law).

Statics first: under gravity alone (friction carries no force at rest) the saddle system

    [K + Σ K_lam,i D_iᵀD_i + Σ λ_i/R_i D_iᵀD_i   −Rᵀ] [q₀]   [−M Γ [0, 0, g]]
    [R                                           0 ] [λ₀] = [0            ]

gives q₀ and the normal forces λ₀ (iterated on λ in the pendulum terms; a singular K part with
a consistent load takes the least-squares solution). The run starts from (q₀, 0) unless y0 is
given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from nsdyn.ground.excitation import G_EARTH
from nsdyn.models.isolated.bearings import N_BCOL, Bearing, BearingError

SYMMETRY_RTOL = 1e-10  # |A − Aᵀ| allowed relative to max |A| (M, K)
SPD_RTOL = 1e-12  # M's smallest eigenvalue must exceed this times its largest
STATIC_ITER = 50  # fixed-point passes of the pendulum terms λ/R in the static solve
STATIC_RTOL = 1e-12  # their convergence (relative change of λ) and the saddle residual bound


class PairSystemError(BearingError):
    """A PairSystem field is invalid; the message names the field and the expected form."""


def _matrix(name: str, A, shape: tuple) -> np.ndarray:
    try:
        a = np.array(A, dtype=float)
    except (TypeError, ValueError) as e:
        raise PairSystemError(f"{name}: expected an array of numbers of shape {shape} "
                              f"({e})") from None  # fmt: skip
    if a.shape != shape:
        raise PairSystemError(f"{name}: expected shape {shape}, got {a.shape}")
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


@dataclass(frozen=True)
class PairSystem:
    """A linear structure from matrices on isolators that slide in a plane (module text).

    Shapes: M, K, C (n, n); Gamma (n, 3) (columns: the ground translations x, y, z in q;
    gravity acts along the z column); D (ni, 2, n) slip rows; R (ni, n) contact rows;
    positions (ni, 2) plan positions [m]; T (m, n) optional output map.
    """

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
        K = _symmetric(f"{w}.K", _matrix(f"{w}.K", self.K, (n, n)))
        C = _matrix(f"{w}.C", self.C, (n, n))
        Gam = _matrix(f"{w}.Gamma", self.Gamma, (n, 3))
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
            raise PairSystemError(f"{w}.bearings: expected {ni} Bearing (one per isolator), "
                                  f"got {got!r}")  # fmt: skip
        for i, b in enumerate(self.bearings):
            if not isinstance(b, Bearing):
                raise PairSystemError(f"{w}.bearings[{i}]: expected a Bearing, got "
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
        f = np.concatenate([-self.M @ self.Gamma[:, 2] * self.g, np.zeros(ni)])
        lam = np.zeros(ni)
        sol = None
        for _ in range(STATIC_ITER):
            Ks = self.K + D2.T @ ((klam + rinv * np.repeat(lam, 2))[:, None] * D2)
            A = np.block([[Ks, -self.R.T], [self.R, np.zeros((ni, ni))]])
            sol = np.linalg.lstsq(A, f, rcond=None)[0]
            res = np.abs(A @ sol - f).max()
            scale = np.abs(A).max() * np.abs(sol).max() + np.abs(f).max()
            if not res <= 1e3 * STATIC_RTOL * scale:
                raise PairSystemError(
                    f"{self.name}: the static equilibrium under gravity has no solution "
                    f"(saddle residual {res:.3g}); check K, R and Gamma's z column"
                )
            new = sol[n:]
            done = np.abs(new - lam).max() <= STATIC_RTOL * max(np.abs(new).max(), 1e-300)
            lam = new
            if done or not np.any(rinv):
                break
        q0 = sol[:n]
        if np.any(lam <= 0):
            i = int(np.argmin(lam))
            raise PairSystemError(
                f"{self.name}: isolator {i} carries no compression at rest (normal force "
                f"{lam[i]:.4g} N); check R's sign (gap rows, λ compressive positive) and Gamma"
            )
        for b in self.bearings:
            need = b.friction.static * b.radius
            if math.isfinite(b.d_cap) and math.isfinite(b.radius) and b.d_cap <= need:
                raise PairSystemError(
                    f"{b.where}.d_cap: {b.d_cap:g} m is not above the pendulum's stick range "
                    f"mu_s R = {need:g} m (it may rest on its rim); expected d_cap > mu_s R"
                )
        self.info[key] = (q0, lam)
        return q0.copy(), lam.copy()

    def bearing_table(self) -> np.ndarray:
        """(ni, N_BCOL) packed bearing rows at the static normal forces."""
        _, lam0 = self.static_equilibrium()
        bp = np.zeros((self.n_isolators, N_BCOL))
        for i, b in enumerate(self.bearings):
            bp[i] = b.row(float(lam0[i]), self.g)
        return bp
