"""Generalized-alpha for large models: the linear part factored once, the nonlinear part low-rank.

The kernel form of the isolated frame (:mod:`nsdyn.models.isolated._kernel`, ``M = I`` after
``M^-1``) is linear but for a few rows: the contact multipliers ``lam`` (rows ``R``) and the
friction forces ``phi`` on the sliding rows ``D``::

    qdd = -MiK q - MiC qd - Gamma u'' + MiRt lam - MiDt phi
    R qdd + 2 alpha beta R qd + alpha^2 R q = 0,      phi_i = mu_i L_i s(D_i qd)

(``s`` the arctan law, ``L_i = lam_i`` or the frozen static normal force). One step of
generalized-alpha (Chung & Hulbert 1993, the scheme of :mod:`nsdyn.solve._kgenalpha`) solves
``(1 - am) a_{n+1} + am a_n = qdd(t_a, q_a, v_a)`` at the alpha point, where
``q_a = qt + c1 a_{n+1}``, ``v_a = vt + c2 a_{n+1}`` (``c1 = (1-af) beta h^2``,
``c2 = (1-af) gamma h``; ``qt, vt`` the parts known from step n). The acceleration is affine
in the few nonlinear forces::

    S a_{n+1} = -am a_n - MiK qt - MiC vt - Gamma u''(t_a) + MiRt lam - MiDt phi
    S = (1 - am) I + c1 MiK + c2 MiC                (constant: factored once per step size)
    a_{n+1} = A0 + Gr lam - Gd phi,   Gr = S^-1 MiRt,  Gd = S^-1 MiDt

so Newton runs on the Schur complement only: the contact rows are linear and give
``lam = RGr^-1 (RGd phi - c0 / kR)`` exactly; the ``ni`` friction equations
``phi - mu L(phi) s(w0 + W phi) = 0`` are solved by Newton with a backtracking line search
(the Newton matrix ``S + low rank`` never appears). Same scheme and same equations as the dense
``genalpha``; only the linear algebra differs. ``A0`` costs one product with the constant
``S^-1 [-MiK, -(1-af)h MiK - MiC, -am I - ...]`` (dense) or two sparse products and a sparse
LU solve when the kernel matrices are sparse (``BACKEND_DENSITY``). Laws: arctan and none
(live or frozen normal forces); the switch law is rejected (use ``radau`` or ``event``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from nsdyn.models.isolated import _kernel as ks
from nsdyn.models.isolated.params import KernelParams
from nsdyn.solve import _kcommon as ki
from nsdyn.solve import _kgenalpha

__all__ = ["METHOD", "RHO_INF", "Stepper", "integrate", "run", "setup_stats"]

METHOD = "genalpha-lowrank"  # registry name
RHO_INF = 0.8  # default spectral radius at infinity (as the dense genalpha)
BACKEND_DENSITY = 0.05  # sparse LU when nnz(MiK, MiC) / (2 n^2) is below this
SPARSE_MIN_N = 50  # below this many dofs the dense backend is always used
NEWTON_MAXITER = 50  # Newton iterations on the friction forces per step
NEWTON_RTOL = 1e-12  # converged when |d phi| <= this * (mu L + |phi|) for every isolator
LS_MAXITER = 30  # backtracking halvings of a Newton correction
# elements per gemv: OpenBLAS runs a gemv below 2304 * 4 elements on one thread; waking its
# threads between steps costs ~1 ms on a loaded machine, more than the product itself
GEMV_BLOCK = 9000
CACHE_SIZE = 4  # factorisations kept (one per step size and model) across chunked calls

_CACHE: list = []  # most recent Stepper first
_STATS = {"setup_s": 0.0, "n_setup": 0}  # factorisation time spent in this process


def setup_stats(reset: bool = False) -> dict:
    """Seconds spent factoring (``setup_s``) and factorisations done (``n_setup``) so far."""
    out = dict(_STATS)
    if reset:
        _STATS.update(setup_s=0.0, n_setup=0)
    return out


def _is_sparse(MiK: np.ndarray, MiC: np.ndarray) -> bool:
    n = MiK.shape[0]
    if n < SPARSE_MIN_N:
        return False
    return (np.count_nonzero(MiK) + np.count_nonzero(MiC)) / (2.0 * n * n) < BACKEND_DENSITY


@dataclass
class Stepper:
    """The constant operators of one model at one step size ``h`` (see the module docstring)."""

    P: tuple
    h: float
    coef: tuple
    backend: str  # "dense" or "sparse"
    apply: object  # (q, v, a, u) -> A0
    G: np.ndarray  # (n, nc + ni): [Gr, -Gd]
    RGr_inv: np.ndarray
    RGd: np.ndarray
    DGr: np.ndarray
    DGd: np.ndarray
    setup_s: float
    Lam: np.ndarray = None  # lam per unit phi from the contact rows: RGr^-1 RGd
    Wp: np.ndarray = None  # sliding velocity per unit phi (/ c2): DGr Lam - DGd

    @classmethod
    def build(cls, P: tuple, h: float, coef: tuple, backend: str = "auto") -> Stepper:
        t0 = time.perf_counter()
        am, af, beta, gamma = coef
        m = KernelParams(P).matrices()
        MiK, MiC, Gam = m["MiK"], m["MiC"], m["Gamma"]
        R, D, MiRt, MiDt = m["R"], m["D"], m["MiRt"], m["MiDt"]
        n = MiK.shape[0]
        c1, c2 = (1.0 - af) * beta * h * h, (1.0 - af) * gamma * h
        kq, ka_q = (1.0 - af) * h, (1.0 - af) * h * h * (0.5 - beta)
        ka_v = (1.0 - af) * h * (1.0 - gamma)
        if backend == "auto":
            backend = "sparse" if _is_sparse(MiK, MiC) else "dense"
        B = np.hstack([MiRt, -MiDt])
        if backend == "sparse":
            import scipy.sparse as sp
            import scipy.sparse.linalg as spla

            Ks, Cs = sp.csr_array(MiK), sp.csr_array(MiC)
            S = sp.csc_array((1.0 - am) * sp.identity(n) + c1 * Ks + c2 * Cs)
            lu = spla.splu(S)
            G = lu.solve(np.ascontiguousarray(B)) if B.shape[1] else np.zeros((n, 0))

            def apply(q, v, a, u):
                qt = q + kq * v + ka_q * a
                vt = v + ka_v * a
                return -lu.solve(am * a + Ks @ qt + Cs @ vt + Gam @ u)

        elif backend == "dense":
            import scipy.linalg as sla

            S = (1.0 - am) * np.eye(n) + c1 * MiK + c2 * MiC
            lu = sla.lu_factor(S, check_finite=True)
            # A0 = W [q; v; a] + Wg u with W = -S^-1 [MiK, kq MiK + MiC, am I + ka_q MiK + ...]
            rhs = np.hstack([MiK, kq * MiK + MiC, am * np.eye(n) + ka_q * MiK + ka_v * MiC, Gam, B])
            X = sla.lu_solve(lu, rhs)
            # row blocks small enough for a single-threaded gemv each (one batched matmul)
            rows = max(1, min(n, GEMV_BLOCK // (3 * n + 2)))
            nb = -(-n // rows)
            W = np.zeros((nb * rows, 3 * n + 2))
            W[:n] = -X[:, : 3 * n + 2]
            W = W.reshape(nb, rows, 3 * n + 2)
            G = np.ascontiguousarray(X[:, 3 * n + 2 :])
            y = np.empty(3 * n + 2)

            def apply(q, v, a, u):
                y[:n], y[n : 2 * n], y[2 * n : 3 * n], y[3 * n :] = q, v, a, u
                return (W @ y).reshape(-1)[:n]

        else:
            raise ValueError(f"backend: expected 'auto', 'dense' or 'sparse', got {backend!r}")
        nc = R.shape[0]
        if not np.all(np.isfinite(G)):
            raise FloatingPointError(f"{METHOD}: singular iteration matrix at step {h:g} s")
        RGr = R @ G[:, :nc]
        if nc and np.linalg.cond(RGr) > 1e12:
            raise FloatingPointError(f"{METHOD}: contact rows R are linearly dependent")
        RGr_inv = np.linalg.inv(RGr) if nc else np.zeros((0, 0))
        dt_s = time.perf_counter() - t0
        _STATS["setup_s"] += dt_s
        _STATS["n_setup"] += 1
        RGd, DGr, DGd = -R @ G[:, nc:], D @ G[:, :nc], -D @ G[:, nc:]
        Lam = RGr_inv @ RGd if nc else np.zeros((0, D.shape[0]))
        Wp = DGr @ Lam - DGd
        return cls(P, h, coef, backend, apply, G, RGr_inv, RGd, DGr, DGd, dt_s, Lam, Wp)

    def matches(self, P: tuple, h: float, coef: tuple, backend: str) -> bool:
        same = all(a is b for a, b in zip(self.P[: ks.I_MU + 2], P[: ks.I_MU + 2], strict=True))
        ok_backend = backend in ("auto", self.backend)
        return same and abs(self.h - h) <= 1e-12 * h and self.coef == coef and ok_backend


def _stepper(P: tuple, h: float, coef: tuple, backend: str) -> Stepper:
    """The factorisation of ``P`` at step ``h`` (cached: chunked runs reuse it)."""
    for k, st in enumerate(_CACHE):
        if st.matches(P, h, coef, backend):
            _CACHE.insert(0, _CACHE.pop(k))
            return st
    st = Stepper.build(P, h, coef, backend)
    _CACHE.insert(0, st)
    del _CACHE[CACHE_SIZE:]
    return st


def _hermite(t, h, q0, v0, a0, q1, v1, a1, tout, out):
    s = (tout - t) / h
    h00 = (1.0 + 2.0 * s) * (1.0 - s) ** 2
    h10 = s * (1.0 - s) ** 2
    h01 = s * s * (3.0 - 2.0 * s)
    h11 = s * s * (s - 1.0)
    n = q0.shape[0]
    out[:n] = h00 * q0 + h10 * h * v0 + h01 * q1 + h11 * h * v1
    out[n:] = h00 * v0 + h10 * h * a0 + h01 * v1 + h11 * h * a1


class _Friction:
    """The friction equations of one step, reduced to the ``ni`` friction forces phi."""

    def __init__(self, kp: KernelParams):
        self.law = kp.law
        if self.law not in ("arctan", "none"):
            raise ValueError(
                f"method {METHOD!r}: friction law {self.law!r} is not supported (arctan or "
                "none); use 'radau', 'genalpha' or 'event' for the switch model"
            )
        self.mu = np.asarray(kp.mu, float)
        self.frozen = kp.frozen_normal
        self.lam0 = np.asarray(kp.lam_static, float)
        self.eps = kp.eps
        self.ni, self.nc = kp.n_isolators, kp.n_contacts
        self.active = self.law == "arctan" and self.ni > 0 and bool(np.any(self.mu != 0.0))

    def solve(self, phi, lam_c, Lam, w0, Wp):
        """phi with phi = mu L s(w0 + Wp phi), L = lam_c + Lam phi (live) or lam0.

        Returns (phi, converged, iterations, last relative correction)."""
        ni = self.ni
        mu, eps, k2 = self.mu, self.eps, 2.0 / np.pi
        Ld = np.zeros((ni, ni)) if self.frozen else Lam[:ni]
        Lc = self.lam0 if self.frozen else lam_c[:ni]
        eye = np.eye(ni)
        L = Lc + Ld @ phi
        v = w0 + Wp @ phi
        r = phi - mu * L * (k2 * np.arctan(eps * v))
        dn = np.inf
        for it in range(1, NEWTON_MAXITER + 1):
            s = k2 * np.arctan(eps * v)
            ds = k2 * eps / (1.0 + (eps * v) ** 2)
            d = _small_solve(eye - (mu * s)[:, None] * Ld - (mu * L * ds)[:, None] * Wp, r)
            dn = float(np.max(np.abs(d) / (np.abs(mu * L) + np.abs(phi) + 1e-300)))
            if not np.isfinite(dn):
                return phi, False, it, dn
            if dn <= NEWTON_RTOL:  # quadratic convergence: this correction is the last
                return phi - d, True, it, dn
            r0 = np.sqrt(r @ r)
            step = 1.0
            for _ in range(LS_MAXITER):
                p_new = phi - step * d
                L = Lc + Ld @ p_new
                v = w0 + Wp @ p_new
                r = p_new - mu * L * (k2 * np.arctan(eps * v))
                if np.sqrt(r @ r) <= (1.0 - 1e-4 * step) * r0:
                    break
                step *= 0.5
            phi = p_new
        return phi, False, NEWTON_MAXITER, dn


def _small_solve(J: np.ndarray, r: np.ndarray) -> np.ndarray:
    """J^-1 r for the ni x ni friction Jacobian (closed form for one or two isolators)."""
    if J.shape[0] == 1:
        return r / J[0, 0]
    if J.shape[0] == 2:
        det = J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0]
        return np.array(
            [(J[1, 1] * r[0] - J[0, 1] * r[1]) / det, (J[0, 0] * r[1] - J[1, 0] * r[0]) / det]
        )
    return np.linalg.solve(J, r)


def integrate(
    P, x0, t_eval, dt, *, coef=None, max_steps=10**9, uplift_mode=ki.UPLIFT_RAISE, X=None,
    upl_t=None, backend="auto",
):  # fmt: skip
    """Fixed-step generalized-alpha with the factor-once / low-rank Newton of this module.

    Parameters
    ----------
    P : tuple                    kernel tuple (``system.params(ground)``)
    x0 : ndarray, shape (2n,)    state [q, qd] at ``t_eval[0]``
    t_eval : ndarray, shape (nt,)  output times (cubic Hermite between steps, as ``genalpha``)
    dt : float                   step [s]
    coef : tuple                 (am, af, beta, gamma), default genalpha at RHO_INF
    backend : {"auto", "dense", "sparse"}

    Returns
    -------
    (stats, rinfo, X, upl_t) in the layout of :mod:`nsdyn.solve._kcommon`.
    """
    coef = _kgenalpha.parameters(_kgenalpha.FAMILY_GENALPHA, RHO_INF) if coef is None else coef
    coef = tuple(float(c) for c in coef)
    am, af, beta, gamma = coef
    kp = KernelParams(P)
    fr = _Friction(kp)
    m = kp.matrices()
    R, D = m["R"], m["D"]
    n, nc, ni = kp.n, kp.n_contacts, kp.n_isolators
    nt = t_eval.shape[0]
    X = np.zeros((nt, 2 * n)) if X is None else X
    upl_t = np.full(nc, np.nan) if upl_t is None else upl_t
    stats = np.zeros(ki.N_STATS, dtype=np.int64)
    rinfo = np.zeros(ki.N_RINFO)
    fp = P[ks.I_FPAR]
    alpha_b, beta_b = fp[ks.F_ALPHA], fp[ks.F_BETA]
    q, v = x0[:n].copy(), x0[n:].copy()
    qdd, lam, tau, modes = ks.outputs(P)
    t = float(t_eval[0])
    rinfo[ki.R_T], rinfo[ki.R_H], rinfo[ki.R_HNEXT] = t, dt, dt
    ok = ks.evaluate(t, np.ascontiguousarray(x0), P, qdd, lam, tau, modes)
    stats[ki.S_NFEV] += 1
    if not (np.all(np.isfinite(x0)) and np.all(np.isfinite(qdd))):
        stats[ki.S_STATUS] = ki.ST_NONFINITE
        return stats, rinfo, X, upl_t
    if not ok:
        stats[ki.S_STATUS] = ki.ST_SINGULAR
        return stats, rinfo, X, upl_t
    a = qdd.copy()
    lam_old = lam.copy()
    phi = np.where(fr.active, tau, 0.0) if ni else np.zeros(0)
    iout = 0
    while iout < nt and t_eval[iout] <= t:
        X[iout] = x0
        iout += 1
    stats[ki.S_NOUT] = iout
    if ki.check_contacts(t, t, lam, lam, upl_t, uplift_mode, stats, rinfo):
        return stats, rinfo, X, upl_t
    t0, t_end = float(t_eval[0]), float(t_eval[-1])
    # excitation at every alpha point of the regular steps, one kernel call
    n_steps = int(np.ceil((t_end - t0) / dt - 1e-9))
    k_all = np.arange(n_steps)
    u_all = ks.ground_many(t0 + (k_all + (1.0 - af)) * dt, P)
    u_all[:, 1] += kp.g
    # the step grid: steps of dt, the last one ending on t_end (shortened if need be)
    t_steps = t0 + (k_all + 1.0) * dt
    t_steps[t_steps > t_end - 1e-9 * dt] = t_end
    st = _stepper(P, dt, coef, backend) if n_steps else None
    for k in range(n_steps):
        if iout >= nt:
            break
        if stats[ki.S_NSTEP] >= max_steps:
            stats[ki.S_STATUS] = ki.ST_MAX_STEPS
            break
        t_new, u = float(t_steps[k]), u_all[k]
        h = t_new - t
        if abs(h - dt) > 1e-12 * dt:  # a shortened last step: its own factorisation
            st = _stepper(P, h, coef, backend)
            u = ks.ground_many(np.array([t + (1.0 - af) * h]), P)[0]
            u[1] += kp.g
        c1, c2 = (1.0 - af) * beta * h * h, (1.0 - af) * gamma * h
        kR = (1.0 - am) + 2.0 * alpha_b * beta_b * c2 + alpha_b * alpha_b * c1
        A0 = st.apply(q, v, a, u)
        # known parts of the alpha-point state (a_{n+1} = 0)
        qt = q + (1.0 - af) * (h * v + h * h * (0.5 - beta) * a)
        vt = v + (1.0 - af) * h * (1.0 - gamma) * a
        if nc:
            c0 = kR * (R @ A0) + R @ (am * a + 2.0 * alpha_b * beta_b * vt + alpha_b**2 * qt)
            lam_c = -st.RGr_inv @ (c0 / kR)
        else:
            lam_c = np.zeros(0)
        Lam = st.Lam
        if fr.active:
            w0 = D @ vt + c2 * (D @ A0 + st.DGr @ lam_c)
            phi, conv, n_it, dn = fr.solve(phi, lam_c, Lam, w0, c2 * st.Wp)
            stats[ki.S_NFEV] += n_it
            if not conv:
                rinfo[ki.R_T], rinfo[ki.R_H], rinfo[ki.R_RES] = t, h, dn
                fin = np.isfinite(dn) and np.all(np.isfinite(phi))
                stats[ki.S_STATUS] = ki.ST_NEWTON if fin else ki.ST_NONFINITE
                break
        else:
            phi = np.zeros(ni)
        lam_a = lam_c + Lam @ phi
        an = A0 + st.G @ np.concatenate([lam_a, phi])
        qn = q + h * v + h * h * ((0.5 - beta) * a + beta * an)
        vn = v + h * ((1.0 - gamma) * a + gamma * an)
        if not (np.all(np.isfinite(an)) and np.all(np.isfinite(vn))):
            stats[ki.S_STATUS] = ki.ST_NONFINITE
            rinfo[ki.R_T] = t
            break
        # outputs in (t, t_new]: Hermite interpolation of the step (as the dense kernel)
        i_end = int(np.searchsorted(t_eval, t_new, side="right"))
        for i in range(iout, i_end):
            _hermite(t, h, q, v, a, qn, vn, an, t_eval[i], X[i])
        iout = stats[ki.S_NOUT] = i_end
        stats[ki.S_NSTEP] += 1
        # contact monitor on the alpha-point normal forces (the step's constraint forces)
        stop = bool(np.any(lam_a <= 0.0)) and ki.check_contacts(
            t, t_new, lam_old, lam_a, upl_t, uplift_mode, stats, rinfo
        )
        q, v, a = qn, vn, an
        lam_old = lam_a
        t = t_new
        if stop:
            break
        rinfo[ki.R_T] = t
    return stats, rinfo, X, upl_t


def run(P, x0, t_eval, o, X, upl_t):
    """Runner of the method registry: ``(stats, rinfo, events, modes)``; ``o`` the checked
    options (``dt``, ``max_steps``, ``uplift_mode``, ``rho_inf``)."""
    rho = RHO_INF if o.rho_inf is None else o.rho_inf
    coef = _kgenalpha.parameters(_kgenalpha.FAMILY_GENALPHA, rho)
    try:
        stats, rinfo, _, _ = integrate(
            P, x0, t_eval, o.dt, coef=coef, max_steps=o.max_steps, uplift_mode=o.uplift_mode,
            X=X, upl_t=upl_t,
        )  # fmt: skip
    except FloatingPointError:
        stats = np.zeros(ki.N_STATS, dtype=np.int64)
        rinfo = np.zeros(ki.N_RINFO)
        stats[ki.S_STATUS] = ki.ST_LU_SINGULAR
        rinfo[ki.R_T], rinfo[ki.R_H] = float(t_eval[0]), o.dt
    return stats, rinfo, [], None
