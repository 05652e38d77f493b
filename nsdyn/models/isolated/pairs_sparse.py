"""Systems on isolators that slide in a plane, on sparse operators: the full 3D rung at any size.

The equations are those of :mod:`nsdyn.models.isolated.pairs` (q relative to the ground,
isolator i slipping u_i = D_i q on a contact whose gap R_i q stays zero)::

    M q̈ + C* q̇ + K q = −M Γ [a_x, a_y, a_z + g] + Rᵀ λ − D2ᵀ F,    C* = C + U diag(c) Uᵀ
    R q̈ + 2αβ R q̇ + α² R q = 0,
    F_i = λ_i (u_i/R_i + f̂_i(v_i)) + K_lam,i u_i + c_i v_i + F_stop,i

with M, K, C sparse (n × n), the superstructure's modal damping the rank-m term U diag(c) Uᵀ
(U (n, m) dense, m damped modes), Γ (n, 3), and the rows stacked sparse: D2 (2ni, n) (row 2i
u_x, 2i + 1 u_y of isolator i) and R (ni, n). No n × n array is ever dense here; the runs are
:mod:`nsdyn.models.isolated.pairs_sparse_run`.

The building (:func:`building_pairs_sparse`): a :class:`~nsdyn.structure.Frame3D` on one
isolator under every base node in its diaphragm-constrained nodal coordinates (``frame.reduced``:
sparse K, M), the base as the cb rung builds it (:mod:`nsdyn.models.isolated.building3d_cb`:
the ``"grid"`` base ties the feet, D_i q = (U_x − Y_i Θ, U_y + X_i Θ) of the base master,
R_i q = the foot's u_z; ``"pinned"``: each foot's own u_x, u_y, u_z), Γ the rigid translations.
Damping ``"modal"``: the fixed-interface modes Φ (base held, K_ii Φ = M_ii Φ Ω², Φᵀ M_ii Φ = I)
damped with 2ζ_jω_j; their coordinates are η = Φᵀ M_ii (q_i − Ψ q_b), Ψ = −K_ii⁻¹ K_ib, so

    U = [K_bi Φ Ω⁻²; M_ii Φ]   (rows: boundary, interior),   c = 2 ζ ω,

the Craig–Bampton rung's damping diag(0, 2ζω) exactly (UᵀT_cb = [0, I]); every mode while the
interior has at most ``MODAL_ALL_MAX_DOF`` dofs, above only those up to ``f_damp``
(default ``MODAL_F_MAX`` Hz; the higher ones are left to the integrator's dissipation).
``"stiffness"``: C = β K_members, β = 2ζ_1/ω_1 on the first fixed-base mode (Rayleigh's
stiffness term on the frame's own members, not on the base grid: fully sparse, and the damping
of the OpenSees export of the building on its bearings).

Statics: K* q = −M Γ_z g + Rᵀ λ, R q = 0 with K* = K + D2ᵀ diag(K_lam + λ/R) D2 (iterated on
λ in the pendulum terms), each contact row picking one coordinate: one sparse LU on the free
coordinates per pass.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from nsdyn._brief import brief_repr
from nsdyn.ground.excitation import G_EARTH
from nsdyn.models.isolated.bearings import B_KIND, KIND_TFP, N_BCOL, Bearing
from nsdyn.models.isolated.pairs import PairSystemError

__all__ = ["DAMPINGS", "SparsePairSystem", "building_pairs_sparse", "output_maps_sparse"]

DAMPINGS = ("modal", "stiffness")
SYMMETRY_RTOL = 1e-10  # |A − Aᵀ| allowed relative to max |A| (M, K)
STATIC_ITER = 50  # passes of the pendulum terms λ/R in the static solve
STATIC_RTOL = 1e-13  # their convergence (relative change of λ)
DENSE_MAX = 3000  # to_pairs(): a dense PairSystem up to this many coordinates


def _csr(w: str, A, shape: tuple) -> sp.csr_array:
    try:
        a = sp.csr_array(A, dtype=float)
    except (TypeError, ValueError) as e:
        raise PairSystemError(f"{w}: expected a (sparse) matrix of shape {shape} ({e})") from None
    if a.shape != shape:
        raise PairSystemError(f"{w}: expected shape {shape}, got {a.shape}")
    if not np.all(np.isfinite(a.data)):
        raise PairSystemError(f"{w}: expected finite entries")
    return a


def _sym(w: str, a: sp.csr_array) -> sp.csr_array:
    scale = max(float(abs(a).max()) if a.nnz else 0.0, 1e-300)
    d = a - a.T
    if d.nnz and float(abs(d).max()) > SYMMETRY_RTOL * scale:
        raise PairSystemError(f"{w}: not symmetric (|{w} − {w}ᵀ| = {float(abs(d).max()):.3g}); "
                              f"expected {w} = {w}ᵀ")  # fmt: skip
    return ((a + a.T) * 0.5).tocsr()


@dataclass(frozen=True, eq=False, repr=False)
class SparsePairSystem:
    """A structure from sparse matrices on isolators that slide in a plane (module text).

    Shapes: M, K, C (n, n) sparse; U (n, m), c (m,) the low-rank damping; Gamma (n, 3); D the
    slip rows, sparse (2ni, n) stacked or dense (ni, 2, n); R (ni, n); positions (ni, 2);
    T (k, n) optional output map (sparse or dense)."""

    __repr__ = brief_repr  # arrays by shape, not in full

    M: object
    K: object
    C: object
    Gamma: np.ndarray
    D: object
    R: object
    bearings: tuple
    positions: np.ndarray
    U: np.ndarray | None = None
    c: np.ndarray | None = None
    T: object = None
    g: float = G_EARTH
    name: str = "system"
    info: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        w = self.name if isinstance(self.name, str) else "system"
        shape = getattr(self.M, "shape", ())
        if len(shape) != 2 or shape[0] != shape[1] or shape[0] < 1:
            raise PairSystemError(f"{w}.M: expected a square (n, n) matrix, got shape {shape}")
        n = shape[0]
        M = _sym(f"{w}.M", _csr(f"{w}.M", self.M, (n, n)))
        if not np.all(M.diagonal() > 0):
            raise PairSystemError(f"{w}.M: expected a positive definite mass matrix (a "
                                  "coordinate has no positive mass on the diagonal)")  # fmt: skip
        K = _sym(f"{w}.K", _csr(f"{w}.K", self.K, (n, n)))
        C = _csr(f"{w}.C", sp.csr_array((n, n)) if self.C is None else self.C, (n, n))
        Gam = np.asarray(self.Gamma, dtype=float)
        if Gam.shape != (n, 3) or not np.all(np.isfinite(Gam)):
            raise PairSystemError(f"{w}.Gamma: expected finite numbers of shape ({n}, 3), got "
                                  f"{Gam.shape}")  # fmt: skip
        Draw = self.D
        if not sp.issparse(Draw):
            Draw = np.asarray(Draw, dtype=float)
            if Draw.ndim != 3 or Draw.shape[1:] != (2, n):
                raise PairSystemError(f"{w}.D: expected slip rows (2ni, {n}) sparse or (ni, 2, "
                                      f"{n}), got shape {Draw.shape}")  # fmt: skip
            Draw = Draw.reshape(-1, n)
        if Draw.shape[0] % 2 or Draw.shape[0] < 2:
            raise PairSystemError(f"{w}.D: expected 2 ni rows (x and y of each isolator), got "
                                  f"{Draw.shape[0]}")  # fmt: skip
        ni = Draw.shape[0] // 2
        D = _csr(f"{w}.D", Draw, (2 * ni, n))
        R = _csr(f"{w}.R", self.R, (ni, n))
        for i in range(ni):
            for k, ax in ((2 * i, "x"), (2 * i + 1, "y")):
                if D[[k]].nnz == 0:
                    raise PairSystemError(f"{w}.D: the {ax} slip row of isolator {i} is zero; "
                                          f"expected a row giving u_{ax}")  # fmt: skip
            if R[[i]].nnz == 0:
                raise PairSystemError(f"{w}.R[{i}]: the contact row of isolator {i} is zero; "
                                      "expected the row of its vertical gap")  # fmt: skip
        pos = np.asarray(self.positions, dtype=float)
        if pos.shape != (ni, 2) or not np.all(np.isfinite(pos)):
            raise PairSystemError(f"{w}.positions: expected ({ni}, 2) plan positions, got "
                                  f"{pos.shape}")  # fmt: skip
        if not isinstance(self.bearings, tuple | list) or len(self.bearings) != ni:
            raise PairSystemError(f"{w}.bearings: expected {ni} Bearing (one per isolator)")
        for i, b in enumerate(self.bearings):
            if not isinstance(b, Bearing):
                raise PairSystemError(f"{w}.bearings[{i}]: expected a Bearing, got "
                                      f"{type(b).__name__}")  # fmt: skip
            if b.row(1.0, G_EARTH)[B_KIND] == KIND_TFP:
                raise PairSystemError(f"{w}.bearings[{i}]: a triple friction pendulum is not "
                                      "on the sparse path; expected 'fps' or 'flat'")  # fmt: skip
            if getattr(b, "area", None) is not None:
                raise PairSystemError(f"{w}.bearings[{i}]: pressure-dependent friction (area) "
                                      "is not on the sparse path; expected no area")  # fmt: skip
        U = np.zeros((n, 0)) if self.U is None else np.asarray(self.U, dtype=float)
        c = np.zeros(0) if self.c is None else np.asarray(self.c, dtype=float).ravel()
        if U.ndim != 2 or U.shape[0] != n or c.shape != (U.shape[1],):
            raise PairSystemError(f"{w}.U, {w}.c: expected U ({n}, m) and c (m,), got "
                                  f"{U.shape} and {c.shape}")  # fmt: skip
        if not (np.all(np.isfinite(U)) and np.all(c > 0) and np.all(np.isfinite(c))):
            raise PairSystemError(f"{w}.c: expected positive finite modal damping coefficients")
        T = self.T
        if T is not None:
            T = sp.csr_array(T, dtype=float) if sp.issparse(T) else np.asarray(T, dtype=float)
            if T.ndim != 2 or T.shape[1] != n:
                raise PairSystemError(f"{w}.T: expected an output map (k, {n}), got {T.shape}")
        g = self.g
        if (
            isinstance(g, bool)
            or not isinstance(g, int | float)
            or not (math.isfinite(g) and g > 0)
        ):
            raise PairSystemError(f"{w}.g: expected a positive gravity [m/s²], got {g!r}")
        if not np.any(R @ Gam[:, 2]):
            raise PairSystemError(
                f"{w}.Gamma: its z column does not load the contacts "
                "(R Γ_z = 0); expected the vertical ground translation in q"
            )
        for k, v in (
            ("M", M),
            ("K", K),
            ("C", C),
            ("Gamma", np.ascontiguousarray(Gam)),
            ("D", D),
            ("R", R),
            ("positions", pos),
            ("U", np.ascontiguousarray(U)),
            ("c", c),
            ("T", T),
            ("bearings", tuple(self.bearings)),
            ("g", float(g)),
        ):
            object.__setattr__(self, k, v)  # fmt: skip

    @property
    def n(self) -> int:
        return self.M.shape[0]

    @property
    def n_isolators(self) -> int:
        return self.R.shape[0]

    has_tfp = False

    def damp(self, v: np.ndarray) -> np.ndarray:
        """C* v (a vector or an (n, k) block)."""
        out = self.C @ v
        if self.c.size:
            w = self.U.T @ v
            out = out + self.U @ (self.c[:, None] * w if w.ndim == 2 else self.c * w)
        return out

    # ---- statics -------------------------------------------------------------------------
    def static_equilibrium(self) -> tuple[np.ndarray, np.ndarray]:
        """(q₀, λ₀) at rest under gravity (module text); a normal force that is not
        compressive raises :class:`PairSystemError`."""
        if "_static" in self.info:
            q0, lam0 = self.info["_static"]
            return q0.copy(), lam0.copy()
        n, R = self.n, self.R
        held = []
        for i in range(self.n_isolators):
            row = R[[i]]
            if row.nnz != 1:
                raise PairSystemError(f"{self.name}.R[{i}]: the static solve expects each "
                                      "contact row to pick one coordinate")  # fmt: skip
            held.append(int(row.indices[0]))
        held = np.array(held)
        free = np.setdiff1d(np.arange(n), held)
        klam = np.repeat([b.k_lam for b in self.bearings], 2)
        rinv = np.repeat([0.0 if math.isinf(b.radius) else 1.0 / b.radius
                          for b in self.bearings], 2)  # fmt: skip
        f = -(self.M @ self.Gamma[:, 2]) * self.g
        DtD = (self.D.T @ self.D).tocsr()
        lam = np.zeros(len(held))
        q = np.zeros(n)
        for _ in range(STATIC_ITER):
            Ks = self.K + self.D.T @ sp.diags_array(klam + rinv * np.repeat(lam, 2)) @ self.D
            Kff = sp.csc_array(Ks.tocsr()[free][:, free])
            try:
                lu = spla.splu(Kff)
            except RuntimeError:  # flat sliders without rubber: hold the rigid sliding
                shift = 1e-12 * float(abs(Kff).max()) * sp.csc_array(DtD[free][:, free])
                lu = spla.splu(sp.csc_array(Kff + shift))
            q[free] = lu.solve(f[free])
            new = (Ks @ q - f)[held] / np.array([R[[i]].data[0] for i in range(len(held))])
            done = np.abs(new - lam).max() <= STATIC_RTOL * np.abs(new).max()
            lam = new
            if done or not np.any(rinv):
                break
        if not np.all(np.isfinite(q)) or np.any(lam <= 0):
            i = int(np.argmin(lam))
            raise PairSystemError(
                f"{self.name}: isolator {i} carries no compression at rest "
                f"(normal force {lam[i]:.4g} N); check R's sign and Gamma"
            )
        self.info["_static"] = (q.copy(), lam.copy())
        return q, lam

    def bearing_table(self) -> np.ndarray:
        """(ni, N_BCOL) packed bearing rows at the static normal forces."""
        _, lam0 = self.static_equilibrium()
        bp = np.zeros((self.n_isolators, N_BCOL))
        for i, b in enumerate(self.bearings):
            bp[i] = b.row(float(lam0[i]), self.g)
        return bp

    def to_pairs(self):
        """The same system as a dense :class:`~nsdyn.models.isolated.pairs.PairSystem`
        (small systems only: at most ``DENSE_MAX`` coordinates)."""
        from nsdyn.models.isolated.pairs import PairSystem

        if self.n > DENSE_MAX:
            raise ValueError(f"{self.name}: {self.n} coordinates, above the dense limit "
                             f"{DENSE_MAX} of to_pairs()")  # fmt: skip
        C = self.C.toarray() + (self.U * self.c) @ self.U.T
        T = self.T.toarray() if sp.issparse(self.T) else self.T
        return PairSystem(M=self.M.toarray(), K=self.K.toarray(), C=0.5 * (C + C.T),
                          Gamma=self.Gamma, D=self.D.toarray().reshape(-1, 2, self.n),
                          R=self.R.toarray(), bearings=self.bearings, positions=self.positions,
                          T=T, g=self.g, name=self.name)  # fmt: skip


def output_maps_sparse(frame) -> dict:
    """The output maps of :func:`nsdyn.models.isolated.building3d_cb.output_maps` for the
    nodal coordinates of ``frame`` (q = its reduced coordinates): floor motions (nl, 3, n),
    drift ratios at the centres of mass (ns, 2, n) and corners (ns, 4, 2, n), built from the
    dofs the levels' references read (never an n_dof × n array)."""
    from nsdyn.structure.storey3d import _level_refs, floor_motions, storey_drifts_3d

    dofs = set()
    for _, _, (kind, what), nodes in _level_refs(frame):
        ns = [int(frame.diaphragms[what].nodes[0])] if kind == "master" else nodes
        dofs.update(6 * int(k) + c for k in ns for c in (0, 1, 5))
    S = np.array(sorted(dofs))
    E = np.zeros((frame.n_dof, S.size))
    E[S, np.arange(S.size)] = 1.0
    z, refs, fm = floor_motions(frame, E)
    d = storey_drifts_3d(frame, E)
    TS = frame.T[S]  # (|S|, n) sparse

    def lift(a):  # (..., |S|) -> (..., n)
        return np.asarray((TS.T @ a.reshape(-1, S.size).T).T).reshape(a.shape[:-1] + (-1,))

    return {"levels_z": z, "level_refs": refs, "floor_map": lift(fm),
            "drift_cm_map": lift(d.cm), "drift_corner_map": lift(d.corner),
            "heights": d.heights, "cm_points": d.cm_points, "corners": d.corners}  # fmt: skip


def _modal(K, M, b: np.ndarray, zeta, f_damp) -> tuple[np.ndarray, np.ndarray, dict]:
    """(U, c, info) of the fixed-interface modal damping (module text)."""
    from nsdyn.models.isolated.fullorder import MODAL_ALL_MAX_DOF, MODAL_F_MAX
    from nsdyn.structure import damping_ratios, fixed_base_modes

    n = K.shape[0]
    i = np.setdiff1d(np.arange(n), b)
    f_max = f_damp
    if f_max is None:
        f_max = None if i.size <= MODAL_ALL_MAX_DOF else MODAL_F_MAX
    f_hz, Phi = fixed_base_modes(K, M, b, f_max=f_max)
    om = 2.0 * np.pi * f_hz
    z = damping_ratios(zeta, om.size)
    Pi = Phi[i]
    U = np.zeros((n, om.size))
    U[i] = M[i][:, i] @ Pi
    U[b] = (K[b][:, i] @ Pi) / om**2
    keep = z > 0
    info = {"damped_f_hz": f_hz[keep], "damped_zeta": z[keep], "n_damped": int(keep.sum())}
    return U[:, keep], (2.0 * z * om)[keep], info


def building_pairs_sparse(
    frame, bearings, *, damping: str = "modal", f_damp: float | None = None,
    eccentricity=(0.0, 0.0), base: str = "grid", lumped: bool = False, g: float = G_EARTH,
    name: str | None = None,
) -> SparsePairSystem:  # fmt: skip
    """The full rung of ``frame`` on one isolator under every base node as a
    :class:`SparsePairSystem` in nodal coordinates (module text); the D/R/Γ conventions,
    bearings, eccentricity and base of
    :func:`~nsdyn.models.isolated.building3d_cb.building_pairs`. ``damping``: "modal" (low
    rank on the fixed-interface modes up to ``f_damp`` Hz) or "stiffness" (β K). ``info``
    holds ``frame`` (with its base), ``origin``, ``centre``, ``m``, ``J``, the static state
    ``y0`` and ``static_normal``, the damped modes and the output maps."""
    from nsdyn.models.isolated.building3d_cb import BASES, _bearings, _interface, base_grid
    from nsdyn.structure.modes3d import mass_centre
    from nsdyn.structure.storey3d import accidental_eccentricity, eccentricity_pair

    if damping not in DAMPINGS:
        raise ValueError(f"damping: expected one of {list(DAMPINGS)}, got {damping!r}")
    if base not in BASES:
        raise ValueError(f"base: expected one of {list(BASES)}, got {base!r}")
    if f_damp is not None and not (isinstance(f_damp, int | float) and f_damp > 0):
        raise ValueError(f"f_damp: expected a positive frequency [Hz] or None, got {f_damp!r}")
    if f_damp is not None and damping != "modal":  # (β K has no cut-off: it was dropped)
        raise ValueError("f_damp: the modal damping's cut-off; damping = 'stiffness' has none")
    bearings = _bearings(frame, bearings)
    ecc = eccentricity_pair(eccentricity)
    if any(ecc):
        frame = accidental_eccentricity(frame, *ecc)
    model = base_grid(frame) if base == "grid" else frame
    b, Db, Rb = _interface(model, base)
    K, M = model.reduced(lumped=lumped)
    n, ni = K.shape[0], Db.shape[0]
    Dc = sp.coo_array(Db.reshape(2 * ni, -1))
    D = sp.csr_array((Dc.data, (Dc.row, b[Dc.col])), shape=(2 * ni, n))
    Rc = sp.coo_array(Rb)
    R = sp.csr_array((Rc.data, (Rc.row, b[Rc.col])), shape=(ni, n))
    Gam = model.rigid_motions()[:, :3]
    info: dict = {"fidelity": "full", "base": base, "frame": model, "damping": damping,
                  "boundary": b}  # fmt: skip
    U = c = None
    C = sp.csr_array((n, n))
    if damping == "modal":
        U, c, mi = _modal(K, M, b, model.zeta, f_damp)
        info.update(mi)
    else:  # β K on the members (not the base grid), β from the first fixed-base mode
        from nsdyn.structure import fixed_base_modes_3d

        f1 = float(fixed_base_modes_3d(frame, n_modes=1).f_hz[0])
        beta = 2.0 * float(np.atleast_1d(frame.zeta)[0]) / (2.0 * np.pi * f1)
        Km = frame.assemble(lumped=lumped)[0]  # base_grid adds members, never nodes
        C = (beta * (model.T.T @ Km @ model.T)).tocsr()
        C = ((C + C.T) * 0.5).tocsr()
        info.update(beta_k=beta, f_1=f1, n_damped=0)
    xy = frame.nodes[frame.base_nodes, :2]
    origin = xy.mean(axis=0)
    maps = output_maps_sparse(model)
    nl = maps["floor_map"].shape[0]
    cm, m, J = mass_centre(frame)
    info.update(origin=origin, centre=cm, m=m, J=J, base_nodes=frame.base_nodes.copy(), **maps)
    # the keys the cb rung's summaries read: every mode kept, the damped ones named
    f_hz = info.get("damped_f_hz", np.zeros(0))
    info.update(f_max=float("inf"), f_hz=f_hz, n_modes=int(f_hz.size),
                n_modes_below_f_max=int(f_hz.size), dropped_mass=[0.0] * 4)  # fmt: skip
    sys_ = SparsePairSystem(M=M, K=K, C=C, Gamma=Gam, D=D, R=R, bearings=bearings,
                            positions=xy - origin, U=U, c=c,
                            T=maps["floor_map"].reshape(3 * nl, n), g=g,
                            name=name or f"{frame.name} full-sparse (n={n})",
                            info=info)  # fmt: skip
    q0, lam0 = sys_.static_equilibrium()
    info.update(y0=np.concatenate([q0, np.zeros(n)]), static_normal=lam0)
    return sys_
