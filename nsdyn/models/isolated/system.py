"""The base-isolated structure: constrained equations of motion and the model ladder.

Seed 004, eqs (1)-(15) and (23)-(27). Generalised coordinates ``q`` are measured relative to the
ground; the load is ``-M Gamma u''`` with ``u'' = [u''_hor, u''_ver + g]``. With isolator ``i``
sliding by ``D_i q`` and resting on a contact whose gap is ``R_i q = 0``::

    M qdd + C* qd + K* q = -M Gamma u'' + R^T lam - D^T diag(mu s) lamf - D_stuck^T tau
    K* = K + D^T diag(K_lam) D (eq 2) + K_diaphragm,   C* = C + D^T diag(c) D
    R qdd + 2 alpha beta R qd + alpha^2 R q = 0                                     (eqs 13-14)

(``K_diaphragm``: nsdyn's stiff base beam between the base nodes, EA = EI = 1e11, for the
seed's "relatively rigid" base diaphragm; its 0.2-1.2 kHz boundary modes are undamped.)

``lam`` are the normal forces (compressive positive); the friction direction ``s`` follows the
arctan law (eq 7) or Leine's switch model (eqs 4-6, a true stick phase in which the friction
force ``tau`` is a constraint force). Every fidelity of the ladder is one instance of this form::

    fidelity  coordinates q                                superstructure matrices
    --------  -------------------------------------------  ---------------------------------
    fixed     fixed-interface modal coordinates (f<=fmax)  diag(omega^2), I, modal damping
    rigid     x, y, theta of the base (rigid body)         rigid-body mass from the FE M
    cb        [q_b, eta] Craig-Bampton at f_max            CB-reduced K, M, C
    full      every FE dof, nodal (sparse operators,       the FE K, M; modal damping on the
              nsdyn.models.isolated.fullorder)             modes below f_damp, or beta K

Every model carries ``T`` mapping ``q`` to the full FE displacement field, so response metrics
are recovered the same way for all fidelities.
"""

from __future__ import annotations

import contextlib
import numbers
import os
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from nsdyn._brief import brief_repr
from nsdyn._checks import InputWarning, NotedWarning, fields_checked, fingerprint, flag, unchanged
from nsdyn._lazy import LazyModule
from nsdyn.ground.excitation import G_EARTH
from nsdyn.models.isolated import _kernel as ks
from nsdyn.models.isolated import bearings
from nsdyn.models.isolated.defaults import ALPHA, BETA, C_DAMPER, EPS, ETA, K_LAM, MU
from nsdyn.models.isolated.friction import sharpness_in_range
from nsdyn.models.isolated.params import pack

sla = LazyModule("scipy.linalg")

FIDELITIES = ("fixed", "rigid", "cb", "full")  # models of the frame, cheapest first
DENSE_FRAME_MAX = 2000  # frames with more dofs are reduced from their sparse K, M
CONTACTS = ("bilateral", "detect", "unilateral")  # a normal force at zero: held, stop, lift off
ISOLATION_NUMBERS = ("k_lam", "c", "mu", "eps", "eta", "alpha", "beta", "kappa",  # each >= 0
                     "diaphragm_EA", "diaphragm_EI", "g")  # fmt: skip
PER_ISOLATOR = ("k_lam", "c", "mu")  # the numbers given one per isolator or one for all


@fields_checked  # (a misspelt keyword named with its nearest field)
@dataclass(frozen=True)
class Isolation:
    """Isolator parameters (one value for all isolators or one per isolator); defaults are
    the seed's design values (eq 16) and friction settings (§3-§4).

    ``k_lam`` [N/m] rubber bearing, ``c`` [N s/m] damper, ``mu`` [-] friction (μλ, λ the normal
    force), each per isolator; ``law`` "arctan" (μλ(2/π)arctan(eps v), ``eps`` [s/m]), "switch"
    (Leine's switch model, band ``eta`` [m/s]; true stick under method "event", which auto
    picks with unilateral contact) or "none"; ``frozen_normal``: friction on the static normal
    forces; ``alpha`` [1/s], ``beta`` [-]: Baumgarte, ``kappa`` [1/s] stick stabilisation
    (default 2 alpha beta); ``diaphragm_EA`` [N], ``diaphragm_EI`` [N m²]: the base beam; ``g``
    [m/s²]; ``contact``: a normal force at zero is held ("bilateral"), stops ("detect") or
    lifts off ("unilateral")."""

    k_lam: float | tuple = K_LAM  # N/m, laminated rubber bearing, per isolator
    c: float | tuple = C_DAMPER  # N s/m, viscous damper, per isolator
    mu: float | tuple = MU  # friction coefficient
    law: str = "arctan"  # "arctan", "switch" or "none"
    eps: float = EPS  # arctan sharpness [s/m]
    eta: float = ETA  # switch band half-width [m/s]
    frozen_normal: bool = False  # friction uses the static normal force (seed's modified model)
    alpha: float = ALPHA  # Baumgarte alpha [1/s]
    beta: float = BETA  # Baumgarte beta [-]
    kappa: float | None = None  # stick velocity stabilisation [1/s], default 2 alpha beta
    diaphragm_EA: float = 1.0e11  # N, axial stiffness x length of the base diaphragm beam
    diaphragm_EI: float = 1.0e11  # N m^2, bending stiffness of the base diaphragm beam
    g: float = G_EARTH
    contact: str = "detect"  # bilateral | detect | unilateral (CONTACTS: lift-off assumption)

    def __post_init__(self) -> None:
        if self.contact not in CONTACTS:
            raise ValueError(f"isolation.contact: expected one of {list(CONTACTS)}, got "
                             f"{self.contact!r}")  # fmt: skip
        if self.law not in ("arctan", "switch", "none"):
            raise ValueError(f"isolation.law: expected 'arctan', 'switch' or 'none', got "
                             f"{self.law!r}")  # fmt: skip
        # every number finite and >= 0 (mu < 0, eps < 0 feed energy in); g, the law's scale > 0
        positive = ("g", {"arctan": "eps", "switch": "eta"}.get(self.law))  # (0: said below)
        for k in ISOLATION_NUMBERS:  # (text, a bool or None: refused, not converted)
            v, vals = getattr(self, k), np.array([np.nan])
            with contextlib.suppress(TypeError, ValueError):
                if (v is None and k == "kappa") or np.asarray(v).dtype.kind in "iuf":
                    vals = np.atleast_1d(np.asarray(0.0 if v is None else v, dtype=float))
            one = k not in PER_ISOLATOR and np.ndim(v) != 0  # (a list of eps: a TypeError)
            if one or vals.size == 0 or vals.ndim != 1 or not np.all(np.isfinite(vals)
                                                                     & (vals >= 0)):  # fmt: skip
                per = " (or one per isolator)" if k in PER_ISOLATOR else ""
                a = "one (for every isolator)" if one else "a"
                raise ValueError(f"isolation.{k}: expected {a} finite "
                                 f"{'positive' if k in positive else 'non-negative'} "
                                 f"number{per}, got {v!r}")  # fmt: skip
        sharpness_in_range("isolation.eps", self.eps)
        if not self.g > 0:
            raise ValueError(f"isolation.g: expected a positive gravity [m/s²], got {self.g!r}")
        flag("isolation.frozen_normal", self.frozen_normal)  # (a text "no" read as True)
        k, what = {"arctan": ("eps", "sharpness [s/m] (the switch law: its sharp limit)"),
                   "switch": ("eta", "stick band [m/s]")}.get(self.law, ("g", ""))  # fmt: skip
        if not getattr(self, k) > 0:  # (eta = 0: stick never detected)
            raise ValueError(f"isolation.{k}: the {self.law} law needs a positive {what}, got "
                             f"{getattr(self, k)!r}")  # fmt: skip
        mu = np.atleast_1d(np.asarray(self.mu, dtype=float))  # (5 for 5 %: stuck, unsaid)
        k = int(np.argmax(mu))  # (mu 5: stuck; g 9810: friction 1000x; alpha 1e5: lift-offs)
        name = "isolation.mu" + ("" if np.ndim(self.mu) == 0 else f"[{k}]")
        for note in (self.law != "none" and bearings.high_friction_note(name, float(mu[k])),
                     bearings.gravity_note("isolation.g", self.g), self.contact == "unilateral"
                     and bearings.stabilisation_note("isolation.alpha", self.alpha)):  # fmt: skip
            if note:  # (a scene's notes say them: NotedWarning)
                warnings.warn(note, NotedWarning, 3)
        if self.law == "none" and np.any((mu != MU) & (mu != 0)):  # (a scene's note says it)
            warnings.warn(f"isolation.mu = {self.mu!r} not used: the law 'none' has no "
                          "friction", InputWarning, 3)  # fmt: skip

    def changed(self, **changes) -> Isolation:
        """A copy with ``changes``; its notes on mu, g, alpha said again only if read anew."""
        with warnings.catch_warnings():
            same = ((self.law == "none") == (changes.get("law", self.law) == "none"),
                    changes.get("contact", self.contact) == self.contact)  # fmt: skip
            for k in ("mu",) * same[0] + ("g", "alpha" * same[1]):
                if k and k not in changes:
                    warnings.filterwarnings("ignore", rf"isolation\.{k}\b", InputWarning)
            return replace(self, **changes)

    def per_isolator(self, name: str, n: int) -> np.ndarray:
        v = np.atleast_1d(np.asarray(getattr(self, name), dtype=float))
        if v.size == 1:
            return np.full(n, float(v[0]))
        if v.size != n:
            want = "one value (one isolator)" if n == 1 else f"one value or {n} (one per isolator)"
            raise ValueError(f"isolation.{name}: expected {want}, got {v.size}")
        return v


_MATRICES = ("M", "C", "K", "Gamma", "R", "D")  # the static state, Q, operators made from them
_REBUILD = "build_system, system_from_matrices or shear_building with the new matrix"


@dataclass(repr=False)
class IsolatedSystem:
    """One fidelity of the isolated (or fixed-base) structure in the common form.

    Attributes
    ----------
    M, C, K : ndarray, shape (n, n)     superstructure + isolator springs/dampers (+ diaphragm)
    Gamma : ndarray, shape (n, 2)       load influence: load = -M Gamma [u_hor, u_ver + g]
    R : ndarray, shape (nc, n)          contact rows (vertical gap of each isolator)
    D : ndarray, shape (ni, n)          sliding rows (horizontal slip of each isolator)
    T : ndarray, shape (n_full, n)      maps q to the full FE displacement field
    normal_force : ndarray (ni,), optional   frozen normal forces of models without contacts
                                        (:mod:`nsdyn.models.isolated.builders`)
    """

    __repr__ = brief_repr  # arrays by shape, not in full

    name: str
    fidelity: str
    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    Gamma: np.ndarray
    R: np.ndarray
    D: np.ndarray
    T: np.ndarray
    isolation: Isolation | None
    frame: object = None
    f_max: float | None = None
    info: dict = field(default_factory=dict)
    _static: tuple | None = field(default=None, repr=False)
    normal_force: np.ndarray | None = None
    # full-order models: the sparse operators (nsdyn.models.isolated.fullorder.SparseModel)
    sparse: object = field(default=None, repr=False)
    _built: tuple = field(default=(), init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        """Per-isolator values must match the isolators, said when the system is built."""
        if isinstance(self.isolation, Isolation) and self.D is not None:
            for name in ("k_lam", "c", "mu"):
                self.isolation.per_isolator(name, self.D.shape[0])
        self._built = fingerprint(self, _MATRICES)

    @property
    def n(self) -> int:
        return self.M.shape[0]

    @property
    def n_contacts(self) -> int:
        return self.R.shape[0]

    @property
    def n_isolators(self) -> int:
        return self.D.shape[0]

    @property
    def total_mass(self) -> float:
        """Translational mass seen by a horizontal ground motion: Gamma_h^T M Gamma_h."""
        if self.fidelity == "fixed":
            return float(self.info["total_mass"])
        gh = self.Gamma[:, 0]
        return float(gh @ self.M @ gh)

    def with_isolation(self, isolation=None, *, builder=None, **changes) -> IsolatedSystem:
        """A copy with isolator or friction settings changed (matrices rebuilt if needed): an
        :class:`Isolation` in place of the system's, fields changed (``mu=0.1``), or both.

        ``builder(frame, isolation, fidelity=, f_max=, **kw)`` builds a model from a frame
        (default :func:`build_system`; the scenes pass one through the model cache)."""
        if isolation is not None and not isinstance(isolation, Isolation):
            raise TypeError(f"isolation: expected an Isolation, got {type(isolation).__name__}")
        if self.isolation is None:
            raise ValueError("a fixed-base model has no isolation to change")
        iso = (isolation or self.isolation).changed(**changes)
        if self.frame is None:  # built from matrices: the builder kept its arguments
            return self.info["rebuild"](isolation=iso)
        kw = {"damping": self.info["damping"]} if "damping" in self.info else {}
        build = builder or build_system
        f_max = self.f_max if self.f_max is not None else np.inf  # (rigid, full: no cut-off)
        return build(self.frame, iso, fidelity=self.fidelity, f_max=f_max, **kw)

    # ---- static state -------------------------------------------------------------------
    def static_equilibrium(self) -> tuple[np.ndarray, np.ndarray]:
        """State under gravity with the contacts active (KKT solve) and its normal forces.

        Solves ``K* q - R^T lam = -M Gamma [0, g]``, ``R q = 0``. Friction carries no force at
        rest (the isolator springs hold the horizontal position). Returns (x0, lam0).
        """
        unchanged(self, _MATRICES, self._built, _REBUILD)
        if self._static is not None and self._static[2:] != (self._built,):  # (a replace()'s
            self._static = None  # copy of another system's state: solved again)
        g = self.isolation.g if self.isolation is not None else G_EARTH
        if self._static is None and self.sparse is not None:  # full order: a sparse solve
            from nsdyn.models.isolated.fullorder import sparse_static

            self._static = (*sparse_static(self.sparse, self.Gamma, self.R, self.D, g), self._built)
        if self._static is None:
            f = -self.M @ self.Gamma[:, 1] * g
            Q = self.Q
            Kz = Q.T @ self.K @ Q
            try:  # (k_lam = 0 leaves the base free sideways: singular, the load consistent)
                with warnings.catch_warnings():
                    warnings.simplefilter("error", sla.LinAlgWarning)
                    z = sla.solve(Kz, Q.T @ f, assume_a="sym")
            except (sla.LinAlgError, sla.LinAlgWarning, ValueError):
                z = np.linalg.lstsq(Kz, Q.T @ f, rcond=None)[0]
            q = Q @ z
            if self.n_contacts:
                # R^T lam = K q - f  (least squares; exact since the residual lies in range R^T)
                lam = np.linalg.lstsq(self.R.T, self.K @ q - f, rcond=None)[0]
            else:
                lam = np.zeros(0)
            self._static = (np.concatenate([q, np.zeros(self.n)]), lam, self._built)
        x0, lam0 = self._static[:2]
        return x0.copy(), lam0.copy()

    # ---- kernel parameters ----------------------------------------------------------------
    def dense_refusal(self, contact: str | None = None) -> str | None:
        """Why the dense kernels cannot run this model (full-order, on sparse operators alone:
        too many dofs), with what can under a run's ``contact``; None when they can."""
        if isinstance(self.M, np.ndarray):
            return None
        iso = self.isolation
        smooth = iso is None or iso.law != "switch" and (contact or iso.contact) != "unilateral"
        use = ("use method 'auto' or 'genalpha-lowrank' (sparse)" if smooth else "the "
               "sparse 'genalpha-lowrank' runs only the arctan or no friction law under "
               "bilateral or detect contact: use one, or the cb fidelity (fewer dofs) for "
               "the switch law or lift-off")  # fmt: skip
        return (f"{self.name}: {self.n} dofs are too many for the dense kernels (radau, "
                f"dopri5, genalpha, event); {use}")  # fmt: skip

    def params(
        self, ground=None, *, law: str | None = None, stub: bool = False, **overrides
    ) -> tuple:
        """Kernel tuple of this model under ``ground`` (:mod:`nsdyn.models.isolated.params`).

        ``stub``: the tuple of a one-coordinate stand-in with this model's friction, contact
        and excitation settings (the sparse full-order path takes its matrices elsewhere)."""
        iso = self.isolation
        M, C, K, Gamma, R, D = self.M, self.C, self.K, self.Gamma, self.R, self.D
        if stub:
            M, C, K, Gamma = np.eye(1), np.zeros((1, 1)), np.zeros((1, 1)), Gamma[:1]
            R, D = np.zeros((self.n_contacts, 1)), np.zeros((self.n_isolators, 1))
        elif why := self.dense_refusal():
            raise ValueError(why)
        if iso is None:  # (else static_equilibrium checks the matrices: once per call)
            unchanged(self, _MATRICES, self._built, _REBUILD)
            return pack(M, C, K, Gamma, ground=ground, g=G_EARTH)
        _, lam0 = self.static_equilibrium()
        ni, frozen = self.n_isolators, iso.frozen_normal
        if self.normal_force is not None:  # no contacts: the given (frozen) normal forces
            lam0, frozen = self.normal_force, True
        kw = dict(law=law or iso.law, eps=iso.eps, eta=iso.eta, alpha=iso.alpha, beta=iso.beta,
                  kappa=iso.kappa, g=iso.g, frozen_normal=frozen) | overrides  # fmt: skip
        return pack(M, C, K, Gamma, R, D, iso.per_isolator("mu", ni), lam0[:ni], ground=ground,
                    **kw)  # fmt: skip

    def evaluate(self, t: float, x: np.ndarray, ground=None, P=None) -> dict:
        """Accelerations, normal forces, friction forces and isolator modes at one state."""
        P = self.params(ground) if P is None else P
        qdd, lam = np.zeros(self.n), np.zeros(self.n_contacts)
        tau = np.zeros(self.n_isolators)
        modes = np.zeros(self.n_isolators, dtype=np.int64)
        ok = ks.evaluate(float(t), np.ascontiguousarray(x, dtype=float), P, qdd, lam, tau, modes)
        if not ok:
            raise FloatingPointError(f"singular constraint system at t = {t:g} s")
        return {"qdd": qdd, "lam": lam, "tau": tau, "modes": modes}

    # ---- minimal coordinates (eqs 23-27) -------------------------------------------------
    @property
    def Q(self) -> np.ndarray:
        """Null-space basis of R (orthonormal columns): q = Q z satisfies R q = 0 (eq 24).

        When every contact row picks a single coordinate (the Craig-Bampton and full models:
        y1, y2), Q is the identity with those columns removed, so z = [x1 th1 x2 th2 q_r] as
        in the seed.
        """
        if self.info.get("Q_of") != self._built[4:5]:  # (R's; info is shared by a replace())
            R = self.R
            picks = [np.flatnonzero(r) for r in R]
            if not picks:
                Q = np.eye(self.n)
            elif all(len(p) == 1 for p in picks):
                keep = np.setdiff1d(np.arange(self.n), [p[0] for p in picks])
                Q = np.eye(self.n)[:, keep]
            else:
                Q = sla.null_space(R)
            self.info["Q"], self.info["Q_of"] = Q, self._built[4:5]
        return self.info["Q"]

    def minimal_accelerations(self, t, z, zd, ground=None, P=None) -> np.ndarray:
        """zdd on the constraint manifold: Q^T qdd(Q z, Q zd) (equal to seed eq 27)."""
        Q = self.Q
        x = np.concatenate([Q @ z, Q @ zd])
        return Q.T @ self.evaluate(t, x, ground, P)["qdd"]


# ---- builders ---------------------------------------------------------------------------


def _diaphragm_stiffness(xa: float, xb: float, EA: float, EI: float) -> np.ndarray:
    """Stiffness (6x6) of a horizontal Bernoulli-Euler beam between base nodes (x, y, th)."""
    L = abs(xb - xa)
    ka = EA / L
    k = np.zeros((6, 6))
    k[np.ix_([0, 3], [0, 3])] = ka * np.array([[1, -1], [-1, 1]])
    b = np.array([[12, 6 * L, -12, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                  [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]])  # fmt: skip
    k[np.ix_([1, 2, 4, 5], [1, 2, 4, 5])] = EI / L**3 * b
    return k


def _isolator_rows(n: int, base_x: list[int], base_y: list[int]) -> tuple[np.ndarray, np.ndarray]:
    ni = len(base_x)
    D = np.zeros((ni, n))
    R = np.zeros((ni, n))
    for i in range(ni):
        D[i, base_x[i]] = 1.0
        R[i, base_y[i]] = 1.0
    return R, D


def _add_isolators(K, C, D, iso: Isolation, contacts: bool = True, frame: bool = True):
    k_lam = iso.per_isolator("k_lam", D.shape[0])
    bearings.stiff_bearing_check(k_lam, K.diagonal() if contacts else (), frame=frame)  # (its N)
    return K + D.T @ np.diag(k_lam) @ D, C + D.T @ np.diag(iso.per_isolator("c", len(D))) @ D


def rigid_body_modes(frame) -> np.ndarray:
    """Full-field rigid-body displacement vectors [r_x, r_y, r_theta] (rotation about the
    midpoint of the base nodes at base level), shape (n_dof, 3)."""
    nodes = np.asarray(frame.nodes, dtype=float)
    base = np.asarray(frame.base_nodes)
    xm = nodes[base, 0].mean()
    ym = nodes[base, 1].mean()
    nn = nodes.shape[0]
    G = np.zeros((3 * nn, 3))
    G[0::3, 0] = 1.0
    G[1::3, 1] = 1.0
    G[0::3, 2] = -(nodes[:, 1] - ym)
    G[1::3, 2] = nodes[:, 0] - xm
    G[2::3, 2] = 1.0
    return G


def build_system(
    frame,
    isolation: Isolation | None = None,
    *,
    fidelity: str = "cb",
    f_max: float | None = None,
    lumped: bool = False,
    damping: str = "modal",
) -> IsolatedSystem:
    """Build one fidelity of the model ladder from a frame and isolation settings.

    Parameters
    ----------
    frame : nsdyn.structure.frame.Frame, or a bundled frame's name or a frame file's path
                                         (read by :func:`nsdyn.structure.load_frame`)
    isolation : Isolation, optional      ignored for ``fidelity="fixed"``; default seed values
    fidelity : {"fixed", "rigid", "cb", "full"}
    f_max : float                        Craig-Bampton / modal cut-off [Hz] ("cb", "fixed";
                                         default 5); a finite one at "rigid" or "full" warns
    lumped : bool                        HRZ-lumped element masses instead of consistent ones
    damping : {"modal", "stiffness"}     superstructure damping of the full model (nodal
                                         coordinates, :mod:`nsdyn.models.isolated.fullorder`)
    """
    from nsdyn.structure import craig_bampton, fixed_base_modes, load_frame

    if isinstance(frame, str | os.PathLike):
        frame = load_frame(frame)
    if not hasattr(frame, "assemble"):
        raise TypeError(f"frame: expected a plane Frame (nsdyn.load_frame), a bundled frame's "
                        f"name or a frame file's path, got {type(frame).__name__}")  # fmt: skip
    if fidelity not in FIDELITIES:
        raise ValueError(f"fidelity: expected one of {FIDELITIES}, got {fidelity!r}")
    iso = Isolation() if isolation is None else isolation
    if not isinstance(iso, Isolation):
        raise TypeError(f"isolation: expected an Isolation (nsdyn.Isolation(k_lam=..., mu=...)), "
                        f"got {type(iso).__name__}")  # fmt: skip
    if f_max is not None and not (isinstance(f_max, numbers.Real) and f_max > 0):  # NaN too
        raise ValueError(f"f_max: expected a positive frequency [Hz] or inf, got {f_max!r}")
    if f_max is not None and f_max < np.inf and fidelity in ("rigid", "full"):
        warnings.warn(f"f_max = {f_max:g} Hz is not used: fidelity {fidelity!r} cuts no modes "
                      "(f_max is the cut-off of 'cb' and 'fixed')", InputWarning, 2)  # fmt: skip
    f_max = 5.0 if f_max is None else f_max
    if damping not in ("modal", "stiffness"):
        raise ValueError(f"damping: expected 'modal' or 'stiffness', got {damping!r}")
    lumped = flag("lumped", lumped)
    if damping != "modal" and fidelity != "full":
        raise ValueError(f"damping: {damping!r} is a choice of the full model only")
    frame.require_mass(fidelity)  # (cb and full: a singular M is refused, naming the node)
    if fidelity == "full":  # nodal coordinates, sparse operators
        from nsdyn.models.isolated.fullorder import full_order

        fo = full_order(frame, iso, damping, lumped)
        info = fo["info"]  # (the modal damping's modes are added when first computed)
        info.update(total_mass=float(frame.total_mass), n_full=frame.n_dof)
        info["_C_of_sparse"] = fo["C"]  # a copy with other damping is not the sparse model
        name = f"{getattr(frame, 'name', 'frame')} full (n={frame.n_dof})"
        f = {k: fo[k] for k in ("M", "C", "K", "Gamma", "R", "D", "T")}
        return IsolatedSystem(name, "full", f["M"], f["C"], f["K"], f["Gamma"], f["R"], f["D"],
                              f["T"], iso, frame, np.inf, info, sparse=fo["sparse"])  # fmt: skip
    Kf, Mf = frame.assemble(lumped=lumped)
    if frame.n_dof <= DENSE_FRAME_MAX:  # large frames stay sparse (Craig-Bampton: Lanczos)
        Kf = Kf.toarray() if hasattr(Kf, "toarray") else np.asarray(Kf)
        Mf = Mf.toarray() if hasattr(Mf, "toarray") else np.asarray(Mf)
    r_full = frame.influence()
    total_mass = float(r_full[:, 0] @ Mf @ r_full[:, 0])
    nodes = np.asarray(frame.nodes, dtype=float)
    base = list(np.asarray(frame.base_nodes))
    nb_nodes = len(base)
    info = {"total_mass": total_mass, "n_full": Kf.shape[0]}

    if fidelity == "rigid":
        Tr = rigid_body_modes(frame)
        M = Tr.T @ Mf @ Tr
        n = 3
        Gamma = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])
        xm = nodes[base, 0].mean()
        R = np.zeros((nb_nodes, n))
        D = np.zeros((nb_nodes, n))
        for i, b in enumerate(base):
            R[i] = [0.0, 1.0, nodes[b, 0] - xm]
            D[i] = [1.0, 0.0, -(nodes[b, 1] - nodes[base, 1].mean())]
        K, C = _add_isolators(np.zeros((n, n)), np.zeros((n, n)), D, iso)
        return IsolatedSystem(f"{getattr(frame, 'name', 'frame')} rigid", "rigid", M, C, K, Gamma,
                              R, D, Tr, iso, frame, None, info)  # fmt: skip

    cb = craig_bampton(Kf, Mf, frame.boundary_dofs, f_max, frame.zeta)
    nb = cb.n_b
    info["omega"] = cb.omega
    info["zeta"] = cb.zeta
    info["n_modes"] = len(cb.omega)

    if fidelity == "fixed":
        if not len(cb.omega):  # nothing to run: the first mode lies above the cut-off
            f1 = fixed_base_modes(Kf, Mf, frame.boundary_dofs, n_modes=1)[0][0]
            raise ValueError(f"f_max: no fixed-base mode at or below {f_max:g} Hz (the first "
                             f"is {f1:.3g} Hz); expected an f_max above it")  # fmt: skip
        M = np.eye(len(cb.omega))
        K = np.diag(cb.omega**2)
        C = np.diag(2 * cb.zeta * cb.omega)
        Gamma = cb.M[nb:, :] @ cb.Gamma  # modal participation of the ground load (M = I)
        T = cb.T[:, nb:]
        n = M.shape[0]
        name = (f"{getattr(frame, 'name', 'frame')} fixed-base ({n} mode{'s' * (n != 1)} "
                f"<= {f_max:g} Hz)")  # fmt: skip
        return IsolatedSystem(name, "fixed", M, C, K, Gamma, np.zeros((0, n)), np.zeros((0, n)),
                              T, None, frame, f_max, info)  # fmt: skip

    n = cb.M.shape[0]
    K, C = cb.K.copy(), cb.C.copy()  # boundary order in q: x1, y1, th1, x2, y2, th2, ...
    base_x = [3 * i for i in range(nb_nodes)]
    base_y = [3 * i + 1 for i in range(nb_nodes)]
    # stiff base diaphragm between consecutive base nodes (no new nodes)
    for i in range(nb_nodes - 1):
        idx = np.arange(3 * i, 3 * i + 6)
        xa, xb = nodes[base[i], 0], nodes[base[i + 1], 0]
        K[np.ix_(idx, idx)] += _diaphragm_stiffness(xa, xb, iso.diaphragm_EA, iso.diaphragm_EI)
    R, D = _isolator_rows(n, base_x, base_y)
    K, C = _add_isolators(K, C, D, iso)
    name = f"{getattr(frame, 'name', 'frame')} {fidelity} (n={n})"
    return IsolatedSystem(
        name, fidelity, cb.M.copy(), C, K, cb.Gamma.copy(), R, D, cb.T, iso, frame, f_max, info
    )


def isolation_from_config(cfg: dict, source: str = "<config>") -> Isolation:
    """Isolation settings from a TOML table (e.g. a scene's ``[isolation]``), validated."""
    allowed = {f for f in Isolation.__dataclass_fields__}
    unknown = set(cfg) - allowed
    if unknown:
        raise ValueError(f"{source}: isolation: unknown field(s) {sorted(unknown)}; expected "
                         f"some of {sorted(allowed)}")  # fmt: skip
    out = {}
    for k, v in cfg.items():
        if k == "contact":
            if v not in CONTACTS:
                raise ValueError(f"{source}: isolation.contact: expected one of "
                                 f"{list(CONTACTS)}, got {v!r}")  # fmt: skip
            out[k] = v
        elif k == "law":
            if v not in ("arctan", "switch", "none"):
                raise ValueError(
                    f"{source}: isolation.law: expected 'arctan', 'switch' or 'none', got {v!r}"
                )
            out[k] = v
        elif k == "frozen_normal":
            if not isinstance(v, bool):
                raise ValueError(f"{source}: isolation.frozen_normal: expected true/false")
            out[k] = v
        else:
            vals = v if isinstance(v, list) else [v]
            if not vals or not all(isinstance(a, int | float) and not isinstance(a, bool)
                                   for a in vals):  # fmt: skip
                raise ValueError(f"{source}: isolation.{k}: expected a number or list of numbers")
            if any(a < 0 for a in vals):
                raise ValueError(f"{source}: isolation.{k}: expected non-negative, got {v}")
            out[k] = tuple(float(a) for a in vals) if isinstance(v, list) else float(v)
    with warnings.catch_warnings():  # (a mu above 1: its NotedWarning, a scene's note)
        warnings.filterwarnings("ignore", r"isolation\.mu = .* not used", InputWarning)
        return Isolation(**out)  # (law "none": the scene's note of unused keys says its mu)
