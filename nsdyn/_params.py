"""Packing of system matrices and excitation into the kernel parameter tuple ``P``.

The layout is defined in :mod:`nsdyn._ksystem`. This module is the only place that builds it.
The last entry is the kernels' scratch buffer: tuples derived with :func:`with_ground` or
:func:`with_law` share it with their parent (fine for sequential use; not across threads).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _ksystem as ks

LAWS = {
    "none": ks.LAW_NONE,
    "arctan": ks.LAW_ARCTAN,
    "switch": ks.LAW_SWITCH,
    "modes": ks.LAW_MODES,
}

G_EARTH = 9.81  # m/s^2, gravitational acceleration


@dataclass(frozen=True)
class Harmonic:
    """Harmonic ground acceleration ``A_hor sin(2 pi f_hor t)`` (+ optional vertical)."""

    A_hor: float
    f_hor: float
    A_ver: float = 0.0
    f_ver: float = 0.0


@dataclass(frozen=True)
class Table:
    """Sampled ground acceleration (uniform ``dt``, linear interpolation, zero outside)."""

    t0: float
    dt: float
    a_hor: np.ndarray
    a_ver: np.ndarray | None = None


def ground_arrays(ground) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
    """Return (kind, gpar, a_hor, a_ver) for a ground description.

    ``ground`` may be None (no excitation), :class:`Harmonic`, :class:`Table`, or any object
    with ``as_arrays() -> (t0, dt, a_hor, a_ver)`` (e.g. ``nsdyn.records.GroundMotion``).
    """
    gpar = np.zeros(ks.N_GPAR)
    if ground is None:
        gpar[ks.G_DT] = 1.0
        return ks.GROUND_TABLE, gpar, np.zeros(0), np.zeros(0)
    if isinstance(ground, Harmonic):
        gpar[ks.G_DT] = 1.0
        gpar[ks.G_AH], gpar[ks.G_FH] = ground.A_hor, ground.f_hor
        gpar[ks.G_AV], gpar[ks.G_FV] = ground.A_ver, ground.f_ver
        return ks.GROUND_HARMONIC, gpar, np.zeros(0), np.zeros(0)
    if isinstance(ground, Table):
        t0, dt, ah, av = ground.t0, ground.dt, ground.a_hor, ground.a_ver
    elif hasattr(ground, "as_arrays"):
        t0, dt, ah, av = ground.as_arrays()
    else:
        raise TypeError(
            f"ground excitation: expected Harmonic, Table or an object with as_arrays(), "
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
    eps: float = 7500.0,
    eta: float = 1e-5,
    alpha: float = 2 * np.pi,
    beta: float = 1.0,
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
    )


def with_ground(P: tuple, ground) -> tuple:
    """The same system under another ground excitation (matrices shared, not copied)."""
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
