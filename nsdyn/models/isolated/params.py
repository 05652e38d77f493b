"""Packing of system matrices and excitation into the kernel parameter tuple ``P``.

The layout is defined in :mod:`nsdyn.models.isolated._kernel`; this module alone builds it.
The last entry is the kernels' scratch buffer: tuples derived with :func:`with_ground` or
:func:`with_law` share it with their parent (fine for sequential use; not across threads).

One load mechanism for every excitation: the kernels apply ``-M Gamma_e [e_hor, e_ver + g]``
with the excitation channels ``e(t)``. For a ground acceleration ``Gamma_e = Gamma`` (the
system's influence vectors); for a force ``F(t)`` with load vector ``b`` (load ``b F``) the
packer sets ``Gamma_e[:, 0] = -M^-1 b`` and ``e_hor = F`` (gravity keeps ``Gamma[:, 1]``).
"""

from __future__ import annotations

import numpy as np

from nsdyn.ground.excitation import G_EARTH, Harmonic, Table, is_force
from nsdyn.models.isolated import _kernel as ks
from nsdyn.models.isolated.defaults import ALPHA, BETA, EPS, ETA

LAWS = {
    "none": ks.LAW_NONE,
    "arctan": ks.LAW_ARCTAN,
    "switch": ks.LAW_SWITCH,
    "modes": ks.LAW_MODES,
}


def ground_arrays(ground) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
    """Return (kind, gpar, a_hor, a_ver) for a ground description.

    ``ground`` may be None (no excitation), :class:`Harmonic`, :class:`Table`, any object
    with ``as_arrays() -> (t0, dt, a_hor, a_ver)`` (e.g. ``nsdyn.ground.GroundMotion``), or a
    force excitation (its time function F(t) fills the horizontal channel).
    """
    gpar = np.zeros(ks.N_GPAR)
    if is_force(ground):
        ground = ground.channel()  # F(t) in channel 0; its load vector is packed in Gamma
    if ground is None:
        gpar[ks.G_DT] = 1.0
        return ks.GROUND_TABLE, gpar, np.zeros(0), np.zeros(0)
    if isinstance(ground, Harmonic):
        gpar[ks.G_DT] = 1.0
        gpar[ks.G_AH], gpar[ks.G_FH] = ground.A_hor, ground.f_hor
        gpar[ks.G_AV], gpar[ks.G_FV] = ground.A_ver, ground.f_ver
        gpar[ks.G_PH], gpar[ks.G_PV] = ground.phase, ground.phase_ver
        return ks.GROUND_HARMONIC, gpar, np.zeros(0), np.zeros(0)
    if isinstance(ground, Table):
        t0, dt, ah, av = ground.t0, ground.dt, ground.a_hor, ground.a_ver
    elif hasattr(ground, "as_arrays"):
        t0, dt, ah, av = ground.as_arrays()
    else:
        raise TypeError(
            "excitation: expected Harmonic, Table, HarmonicForce, ForceTable or an object "
            f"with as_arrays() (a GroundMotion), "
            f"got {type(ground).__name__}"
        )
    ah = np.ascontiguousarray(ah, dtype=float)
    av = np.zeros_like(ah) if av is None else np.ascontiguousarray(av, dtype=float)
    if av.shape != ah.shape:
        raise ValueError(f"ground excitation: a_ver has shape {av.shape}, a_hor {ah.shape}")
    if not dt > 0:
        raise ValueError(f"ground excitation: dt must be positive, got {dt}")
    gpar[ks.G_T0], gpar[ks.G_DT] = t0, dt
    return ks.GROUND_TABLE, gpar, ah, av


def pack(
    M,
    C,
    K,
    Gamma,
    R=None,
    D=None,
    mu=None,
    lam_static=None,
    *,
    law: str = "none",
    eps: float = EPS,
    eta: float = ETA,
    alpha: float = ALPHA,
    beta: float = BETA,
    kappa: float | None = None,
    g: float = G_EARTH,
    frozen_normal: bool = False,
    ground=None,
    modes=None,
) -> tuple:
    """Build the kernel tuple for ``M qdd + C qd + K q = -M Gamma u'' + R^T lam - friction``.

    Parameters
    ----------
    M, C, K : ndarray, shape (n, n)
    Gamma : ndarray, shape (n, 2)
    R : ndarray, shape (nc, n), optional      contact rows (normal gaps R q = 0)
    D : ndarray, shape (ni, n), optional      sliding rows (isolator slip D_i q)
    mu : ndarray, shape (ni,)
    lam_static : ndarray, shape (ni,)         normal forces used when ``frozen_normal``
    law : {"none", "arctan", "switch", "modes"}
    kappa : float, optional                   stick velocity stabilisation (default 2 alpha beta)
    """
    M = np.asarray(M, dtype=float)
    n = M.shape[0]
    C = np.asarray(C, dtype=float)
    K = np.asarray(K, dtype=float)
    Gamma = np.asarray(Gamma, dtype=float).reshape(n, -1)
    if Gamma.shape[1] == 1:
        Gamma = np.column_stack([Gamma[:, 0], np.zeros(n)])
    R = np.zeros((0, n)) if R is None else np.atleast_2d(np.asarray(R, dtype=float))
    D = np.zeros((0, n)) if D is None else np.atleast_2d(np.asarray(D, dtype=float))
    ni, nc = D.shape[0], R.shape[0]
    mu = np.zeros(ni) if mu is None else np.broadcast_to(np.asarray(mu, float), (ni,)).copy()
    lam0 = np.zeros(ni) if lam_static is None else np.asarray(lam_static, float).copy()
    if law not in LAWS:
        raise ValueError(f"friction law: expected one of {sorted(LAWS)}, got {law!r}")
    if law != "none" and not frozen_normal and ni > nc:
        raise ValueError(
            "each isolator's friction uses the normal force of the contact with the same index: "
            f"got {ni} isolators and {nc} contacts"
        )
    Minv = np.linalg.inv(M)
    load = ks.LOAD_GROUND
    if is_force(ground):  # load b F(t) = -M Gamma_e F(t) with Gamma_e[:, 0] = -M^-1 b
        Gamma = np.column_stack([-Minv @ ground.load_vector(n), Gamma[:, 1]])
        load = ks.LOAD_FORCE
    fpar = np.zeros(ks.N_FPAR)
    fpar[ks.F_EPS], fpar[ks.F_ETA] = eps, eta
    fpar[ks.F_ALPHA], fpar[ks.F_BETA] = alpha, beta
    fpar[ks.F_KAPPA] = 2 * alpha * beta if kappa is None else kappa
    fpar[ks.F_G] = g
    kind, gpar, ah, av = ground_arrays(ground)
    ipar = np.zeros(ks.N_IPAR, dtype=np.int64)
    ipar[ks.K_LAW] = LAWS[law]
    ipar[ks.K_FROZEN] = int(bool(frozen_normal))
    ipar[ks.K_GROUND] = kind
    ipar[ks.K_LOAD] = load
    md = np.ones(ni, dtype=np.int64) if modes is None else np.asarray(modes, np.int64).copy()
    c = np.ascontiguousarray
    return (
        c(Minv @ K),
        c(Minv @ C),
        c(Gamma),
        c(R),
        c(Minv @ R.T),
        c(D),
        c(Minv @ D.T),
        c(mu),
        c(lam0),
        fpar,
        ipar,
        gpar,
        ah,
        av,
        md,
        np.zeros(ks.work_size(n, nc, ni)),
        np.zeros(nc, dtype=np.int64),  # every contact closed
    )


def with_ground(P: tuple, ground) -> tuple:
    """The same system under another excitation of the same kind (matrices shared).

    A force excitation replaces only the time function F(t): the load vector packed in ``P``
    stays (pack again for another load vector); ground and force cannot be swapped here.
    """
    packed_force = int(P[ks.I_IPAR][ks.K_LOAD]) == ks.LOAD_FORCE
    if is_force(ground) != packed_force:
        have, got = ("force", "ground") if packed_force else ("ground", "force")
        raise ValueError(
            f"with_ground: P was packed for a {have} excitation, got a {got} excitation; "
            "build P again with system.params(excitation)"
        )
    kind, gpar, ah, av = ground_arrays(ground)
    ipar = P[ks.I_IPAR].copy()
    ipar[ks.K_GROUND] = kind
    return P[: ks.I_IPAR] + (ipar, gpar, ah, av) + P[ks.I_MODE :]


def with_law(P: tuple, law: str, modes=None) -> tuple:
    """The same system with another friction law (e.g. ``"modes"`` for event-driven runs)."""
    ipar = P[ks.I_IPAR].copy()
    ipar[ks.K_LAW] = LAWS[law]
    md = P[ks.I_MODE].copy() if modes is None else np.asarray(modes, np.int64).copy()
    return P[: ks.I_IPAR] + (ipar,) + P[ks.I_IPAR + 1 : ks.I_MODE] + (md,) + P[ks.I_MODE + 1 :]


def with_open(P: tuple, open_contacts=None) -> tuple:
    """The same system with its own copy of the contact states (1 open / in flight, 0 closed;
    default all closed): unilateral runs change them as contacts lift off and land."""
    nc = P[ks.I_R].shape[0]
    op = np.zeros(nc, np.int64) if open_contacts is None else np.asarray(open_contacts, np.int64)
    if op.shape != (nc,) or not np.all(np.isin(op, (0, 1))):
        raise ValueError(f"open contacts: expected {nc} values in (0, 1), got {open_contacts}")
    return P[: ks.I_OPEN] + (op.copy(),) + P[ks.I_OPEN + 1 :]


_LAW_OF_CODE = {code: name for name, code in LAWS.items()}


class KernelParams:
    """Named read access to a kernel tuple ``P`` (the only reader of its layout besides the
    kernels and :func:`pack`): ``KernelParams(P).eps``, ``.law``, ``.matrices()`` …"""

    __slots__ = ("P",)

    def __init__(self, P: tuple):
        self.P = P

    @staticmethod
    def normalised(P) -> tuple:
        """``P`` with every entry a contiguous array of the kernels' dtype (int64 for the
        integer parameters and the modes, float64 otherwise); TypeError if ``P`` is not a
        kernel tuple of :func:`pack`."""
        if not isinstance(P, tuple) or len(P) != ks.N_P:
            raise TypeError(
                "P: expected the kernel parameter tuple of nsdyn.models.isolated.params.pack "
                f"(length {ks.N_P}), got {type(P).__name__}"
            )
        ints = (ks.I_IPAR, ks.I_MODE, ks.I_OPEN)
        return tuple(
            np.ascontiguousarray(a, dtype=np.int64 if k in ints else float) for k, a in enumerate(P)
        )

    n = property(lambda self: self.P[ks.I_MIK].shape[0], doc="number of coordinates q")
    n_contacts = property(lambda self: self.P[ks.I_R].shape[0], doc="normal contacts (rows of R)")
    n_isolators = property(lambda self: self.P[ks.I_D].shape[0], doc="isolators (rows of D)")
    law = property(lambda self: _LAW_OF_CODE[int(self.P[ks.I_IPAR][ks.K_LAW])], doc="law name")
    frozen_normal = property(lambda self: bool(self.P[ks.I_IPAR][ks.K_FROZEN]))
    eps = property(lambda self: float(self.P[ks.I_FPAR][ks.F_EPS]), doc="arctan sharpness [s/m]")
    eta = property(lambda self: float(self.P[ks.I_FPAR][ks.F_ETA]), doc="stick band [m/s]")
    alpha = property(lambda self: float(self.P[ks.I_FPAR][ks.F_ALPHA]), doc="Baumgarte α")
    beta = property(lambda self: float(self.P[ks.I_FPAR][ks.F_BETA]), doc="Baumgarte β")
    kappa = property(lambda self: float(self.P[ks.I_FPAR][ks.F_KAPPA]), doc="stick stabilisation")
    g = property(lambda self: float(self.P[ks.I_FPAR][ks.F_G]), doc="gravity [m/s²]")
    mu = property(lambda self: self.P[ks.I_MU], doc="friction coefficients (ni,)")
    lam_static = property(lambda self: self.P[ks.I_LAM0], doc="static normal forces (ni,)")
    modes = property(lambda self: self.P[ks.I_MODE], doc="prescribed modes (ni,), 0 = stick")
    open_contacts = property(lambda self: self.P[ks.I_OPEN], doc="contact states (nc,), 1 open")
    force = property(
        lambda self: int(self.P[ks.I_IPAR][ks.K_LOAD]) == ks.LOAD_FORCE,
        doc="True when channel 0 is a force history (load b F), False for a ground motion",
    )
    harmonic = property(
        lambda self: int(self.P[ks.I_IPAR][ks.K_GROUND]) == ks.GROUND_HARMONIC,
        doc="True for a harmonic ground excitation, False for a sampled one",
    )

    @property
    def ground(self) -> dict:
        """The excitation: ``t0, dt, n_samples`` (sampled) and ``A_hor, f_hor, A_ver, f_ver``."""
        gp = self.P[ks.I_GPAR]
        return {
            "t0": float(gp[ks.G_T0]),
            "dt": float(gp[ks.G_DT]),
            "n_samples": int(self.P[ks.I_AH].shape[0]),
            "A_hor": float(gp[ks.G_AH]),
            "f_hor": float(gp[ks.G_FH]),
            "A_ver": float(gp[ks.G_AV]),
            "f_ver": float(gp[ks.G_FV]),
            "phase_hor": float(gp[ks.G_PH]),
            "phase_ver": float(gp[ks.G_PV]),
        }

    def matrices(self) -> dict:
        """``MiK, MiC, Gamma, R, MiRt, D, MiDt`` (M⁻¹K*, M⁻¹C*, Γ, R, M⁻¹Rᵀ, D, M⁻¹Dᵀ)."""
        P = self.P
        return {
            "MiK": P[ks.I_MIK],
            "MiC": P[ks.I_MIC],
            "Gamma": P[ks.I_GAM],
            "R": P[ks.I_R],
            "MiRt": P[ks.I_MIRT],
            "D": P[ks.I_D],
            "MiDt": P[ks.I_MIDT],
        }
