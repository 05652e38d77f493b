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

with ``c1 = (1 - af) beta h^2``, ``c2 = (1 - af) gamma h`` and the predictors ``qt, vt`` of
:mod:`nsdyn.solve._klowrank`, so Newton runs on the Schur complement only: the contact rows
(Baumgarte at the alpha point, ``kR = (1 - am) + 2 alpha beta c2 + alpha^2 c1``, ``c0 = kR R A0
+ R (am a_n + 2 alpha beta vt + alpha^2 qt)``) are linear and give
``lam = RGr^-1 (RGd phi - c0 / kR)`` exactly; the ``ni`` friction equations
``phi - mu L(phi) s(w0 + W phi) = 0`` are solved by Newton with a backtracking line search
(the Newton matrix ``S + low rank`` never appears). Same scheme and same equations as the dense
``genalpha``; only the linear algebra differs. ``A0`` costs one product with the constant
``S^-1 [-MiK, -(1-af)h MiK - MiC, -am I - ...]`` (dense) or two sparse products and a sparse
LU solve when the kernel matrices are sparse (``BACKEND_DENSITY``). Laws: arctan and none
(live or frozen normal forces); the switch law is rejected (use ``radau``, ``genalpha`` or
``event``).

Full-order models in nodal coordinates (:mod:`nsdyn.models.isolated.fullorder`) are never
multiplied by ``M^-1`` (dense): the ``"operators"`` backend factors the sparse part
``S_s = (1 - am) M + c1 K* + c2 C_s`` once (SuperLU; ``C_s`` the damping without the modal
term) and solves with ``S_M = S_s + c2 U diag(c) U^T`` (``S = M^-1 S_M``), the low-rank modal
damping added by the Woodbury identity::

    S_M^-1 b = y - Z (diag(1 / (c2 c)) + U^T Z)^-1 U^T y,   y = S_s^-1 b,  Z = S_s^-1 U

so a step costs sparse products, one sparse triangular solve pair and O(n m) for m damped
modes; ``A0 = S_M^-1 (-am M a - K* qt - C* vt - M Gamma u)`` and ``G = S_M^-1 [R^T, -D^T]``
(the kernel's step is the same).

This module factors and caches the operators (:class:`Stepper`); the steps themselves run in
the numba kernel :mod:`nsdyn.solve._klowrank` (the whole loop with the dense backend; with the
sparse ones, SuperLU gives ``A0`` here and the kernel does the rest of each step). The dense
backend factors with numpy's LAPACK (``gesv``) and the kernel's products are written out, so a
dense run (a reduced model) imports none of SciPy's linear algebra.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from nsdyn._lazy import LazyModule
from nsdyn.models.isolated import _kernel as ks
from nsdyn.models.isolated.excitation import ground_many
from nsdyn.models.isolated.params import KernelParams
from nsdyn.solve import _kcommon as ki

_kgenalpha = LazyModule("nsdyn.solve._kgenalpha")  # imported when a run uses the method
_klowrank = LazyModule("nsdyn.solve._klowrank")

__all__ = ["METHOD", "RHO_INF", "Stepper", "integrate", "run", "setup_stats"]

METHOD = "genalpha-lowrank"  # registry name
RHO_INF = 0.8  # default spectral radius at infinity (as the dense genalpha)
BACKEND_DENSITY = 0.05  # sparse LU when nnz(MiK, MiC) / (2 n^2) is below this
SPARSE_MIN_N = 50  # below this many dofs the dense backend is always used
PERMC_SPECS = ("MMD_AT_PLUS_A", "COLAMD")  # SuperLU orderings tried; the sparser factors win
CACHE_SIZE = 4  # factorisations kept (one per step size and model) across chunked calls

_CACHE: list = []  # most recent Stepper first
_NO_W = np.zeros((0, 0))  # no dense operator: the kernel takes the given A0
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
    W: np.ndarray | None  # dense backend: A0 = W [q; v; a; u]
    G: np.ndarray  # (n, nc + ni): [Gr, -Gd]
    RGr_inv: np.ndarray
    RGd: np.ndarray
    DGr: np.ndarray
    DGd: np.ndarray
    setup_s: float
    Lam: np.ndarray = None  # lam per unit phi from the contact rows: RGr^-1 RGd
    Wp: np.ndarray = None  # sliding velocity per unit phi (/ c2): DGr Lam - DGd
    lin: tuple = None  # "operators": (W CSR, M Gamma, LU factors) of _klowrank.linear_part
    lr: tuple = None  # "operators": (U^T, c, ka_v, Z, capacitance^-1, U^T Z, U^T G): the damping

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
            G = np.ascontiguousarray(G)
            W = None

            def apply(q, v, a, u):
                qt = q + kq * v + ka_q * a
                vt = v + ka_v * a
                return -lu.solve(am * a + Ks @ qt + Cs @ vt + Gam @ u)

        elif backend == "dense":
            S = (1.0 - am) * np.eye(n) + c1 * MiK + c2 * MiC
            if not np.all(np.isfinite(S)):
                raise FloatingPointError(f"{METHOD}: iteration matrix not finite at step {h:g} s")
            # A0 = W [q; v; a] + Wg u with W = -S^-1 [MiK, kq MiK + MiC, am I + ka_q MiK + ...]
            rhs = np.hstack([MiK, kq * MiK + MiC, am * np.eye(n) + ka_q * MiK + ka_v * MiC, Gam, B])
            try:  # LAPACK's gesv (LU with partial pivoting) through numpy: no SciPy to import
                X = np.linalg.solve(S, rhs)
            except np.linalg.LinAlgError as e:
                raise FloatingPointError(
                    f"{METHOD}: singular iteration matrix at step {h:g} s"
                ) from e
            W = np.ascontiguousarray(-X[:, : 3 * n + 2])
            G = np.ascontiguousarray(X[:, 3 * n + 2 :])
            y = np.empty(3 * n + 2)

            def apply(q, v, a, u):
                y[:n], y[n : 2 * n], y[2 * n : 3 * n], y[3 * n :] = q, v, a, u
                A0 = np.empty(n)
                _klowrank.matvec(W, y, A0)
                return A0

        else:
            raise ValueError(f"backend: expected 'auto', 'dense' or 'sparse', got {backend!r}")
        return cls._finish(P, h, coef, backend, apply, W, G, R, D, t0)

    @classmethod
    def build_operators(cls, P: tuple, ops, h: float, coef: tuple) -> Stepper:
        """The ``"operators"`` backend on a full-order model's ``ops`` (:class:`FullOps`)."""
        import scipy.sparse as sp

        t0 = time.perf_counter()
        am, af, beta, gamma = coef
        mo, R, D = ops.model, ops.R, ops.D
        c1, c2 = (1.0 - af) * beta * h * h, (1.0 - af) * gamma * h
        kq, ka_q = (1.0 - af) * h, (1.0 - af) * h * h * (0.5 - beta)
        ka_v = (1.0 - af) * h * (1.0 - gamma)
        S = sp.csc_array((1.0 - am) * mo.M + c1 * mo.K + c2 * mo.C)
        lu = _sparse_lu(S, h)
        U, c = mo.U, mo.c
        low = c.size and c2 > 0.0
        m = c.size if low else 0
        Z, cap_inv = np.zeros((mo.n, 0)), np.zeros((0, 0))
        if low:
            Z = np.ascontiguousarray(lu.solve(np.asfortranarray(U)))
            cap_inv = np.ascontiguousarray(np.linalg.inv(np.diag(1.0 / (c2 * c)) + U.T @ Z))

        def solve(b):
            y = lu.solve(b)
            if low:
                y -= Z @ (cap_inv @ (U.T @ y))
            return y

        # -rhs = W [q; v; a] + M Gamma u + U diag(c) U^T (v + ka_v a)   (module text)
        W = sp.hstack([mo.K, kq * mo.K + mo.C, am * mo.M + ka_q * mo.K + ka_v * mo.C], format="csr")
        MG = np.ascontiguousarray(mo.M @ ops.Gamma)
        n = mo.n
        y3 = np.empty(3 * n)

        def apply(q, v, a, u):
            y3[:n], y3[n : 2 * n], y3[2 * n :] = q, v, a
            r = W @ y3
            r += MG @ u
            if c.size:
                r += U @ (c * (U.T @ (v + ka_v * a)))
            return -solve(r)

        B = np.hstack([R.T, -D.T])
        G = np.ascontiguousarray(solve(B)) if B.shape[1] else np.zeros((n, 0))
        st = cls._finish(P, h, coef, "operators", apply, None, G, R, D, t0)
        W.sort_indices()
        st.lin = (W.indptr.astype(np.int64), W.indices.astype(np.int64), W.data, MG,
                  lu_arrays(lu))  # fmt: skip
        Ut = np.ascontiguousarray(U[:, :m].T) if m else np.zeros((0, n))
        UtZ = np.ascontiguousarray(Ut @ Z) if m else np.zeros((0, 0))
        UtG = np.ascontiguousarray(Ut @ G) if m else np.zeros((0, G.shape[1]))
        st.lr = (Ut, np.ascontiguousarray(c[:m]), float(ka_v), Z, cap_inv, UtZ, UtG)
        return st

    @classmethod
    def _finish(cls, P, h, coef, backend, apply, W, G, R, D, t0) -> Stepper:
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
        Lam, Wp = np.ascontiguousarray(Lam), np.ascontiguousarray(Wp)
        return cls(P, h, coef, backend, apply, W, G, RGr_inv, RGd, DGr, DGd, dt_s, Lam, Wp)

    def matches(self, P: tuple, h: float, coef: tuple, backend: str) -> bool:
        if backend == "operators" or self.backend == "operators":
            same = self.P is P  # the ops tuple of a full-order model (identity)
            ok_h = abs(self.h - h) <= 1e-12 * max(h, 1e-300)
            return same and ok_h and self.coef == coef and backend == self.backend
        same = all(a is b for a, b in zip(self.P[: ks.I_MU + 2], P[: ks.I_MU + 2], strict=True))
        ok_backend = backend in ("auto", self.backend)
        return same and abs(self.h - h) <= 1e-12 * h and self.coef == coef and ok_backend


def _sparse_lu(S, h: float = 0.0):
    """SuperLU of ``S`` with the fill-reducing ordering of :data:`PERMC_SPECS` that fills
    least (the cost of every step's solve is proportional to the factors' nonzeros)."""
    import scipy.sparse.linalg as spla

    best = None
    for spec in PERMC_SPECS:
        try:
            lu = spla.splu(S, permc_spec=spec)
        except RuntimeError as e:
            raise FloatingPointError(f"{METHOD}: singular iteration matrix at step {h:g} s") from e
        if best is None or lu.L.nnz + lu.U.nnz < best.L.nnz + best.U.nnz:
            best = lu
    return best


def lu_arrays(lu) -> tuple:
    """SuperLU's factors ``Pr S Pc = L U`` as the arrays of
    :func:`nsdyn.solve._klowrank.lu_solve_sparse`."""
    L, U = lu.L.tocsc(), lu.U.tocsc()
    L.sort_indices()
    U.sort_indices()
    i64 = np.int64
    return (
        L.indptr.astype(i64), L.indices.astype(i64), L.data, U.indptr.astype(i64),
        U.indices.astype(i64), U.data, np.ascontiguousarray(U.diagonal()),
        lu.perm_r.astype(i64), lu.perm_c.astype(i64),
    )  # fmt: skip


def _stepper(P: tuple, h: float, coef: tuple, backend: str, ops=None) -> Stepper:
    """The factorisation of ``P`` (or of a full-order model's ``ops``) at step ``h`` (cached:
    chunked runs reuse it)."""
    key = P if ops is None else ops
    for k, st in enumerate(_CACHE):
        if st.matches(key, h, coef, backend):
            _CACHE.insert(0, _CACHE.pop(k))
            return st
    if ops is not None:
        st = Stepper.build_operators(ops, ops, h, coef)
    else:
        st = Stepper.build(P, h, coef, backend)
    _CACHE.insert(0, st)
    del _CACHE[CACHE_SIZE:]
    return st


class _Friction:
    """The friction law of the run, as the kernel's ``fr`` tuple (``mu, lam0, eps, frozen,
    active``)."""

    def __init__(self, kp: KernelParams):
        self.law = kp.law
        if self.law not in ("arctan", "none"):
            raise ValueError(
                f"method {METHOD!r}: friction law {self.law!r} is not supported (arctan or "
                "none); use 'radau', 'genalpha' or 'event' for the switch model"
            )
        mu = np.ascontiguousarray(kp.mu, float)
        active = self.law == "arctan" and kp.n_isolators > 0 and bool(np.any(mu != 0.0))
        lam0 = np.ascontiguousarray(kp.lam_static, float)
        self.fr = (mu, lam0, float(kp.eps), bool(kp.frozen_normal), active)


def integrate(
    P, x0, t_eval, dt, *, coef=None, max_steps=10**9, uplift_mode=ki.UPLIFT_RAISE, X=None,
    upl_t=None, backend="auto", ops=None, acc=None,
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
    ops : FullOps, optional      a full-order model's sparse operators
                                 (:class:`nsdyn.solve.fullorder.FullOps`): the
                                 ``"operators"`` backend; ``P`` then gives only the friction
                                 law, Baumgarte parameters and the excitation
    acc : ndarray, shape (n,), optional  the algorithmic acceleration in and out, as
                                 :func:`nsdyn.solve._kgenalpha.genalpha_loop`'s ``acc``

    Returns
    -------
    (stats, rinfo, X, upl_t) in the layout of :mod:`nsdyn.solve._kcommon`.
    """
    coef = _kgenalpha.parameters(_kgenalpha.FAMILY_GENALPHA, RHO_INF) if coef is None else coef
    coef = tuple(float(c) for c in coef)
    am, af, beta, gamma = coef
    kp = KernelParams(P)
    fr = _Friction(kp)
    if ops is None:
        m = kp.matrices()
        R, D = m["R"], m["D"]
        n = kp.n
    else:
        R, D, n = ops.R, ops.D, ops.model.n
        backend = "operators"
    nc, ni = R.shape[0], D.shape[0]
    nt = t_eval.shape[0]
    X = np.zeros((nt, 2 * n)) if X is None else X
    upl_t = np.full(nc, np.nan) if upl_t is None else upl_t
    stats = np.zeros(ki.N_STATS, dtype=np.int64)
    rinfo = np.zeros(ki.N_RINFO)
    fp = P[ks.I_FPAR]
    alpha_b, beta_b = fp[ks.F_ALPHA], fp[ks.F_BETA]
    q, v = x0[:n].copy(), x0[n:].copy()
    t = float(t_eval[0])
    rinfo[ki.R_T], rinfo[ki.R_H], rinfo[ki.R_HNEXT] = t, dt, dt
    if ops is None:  # the system kernel of the metrics' table (compile_split.lowrank_parts_here)
        from nsdyn.models.isolated.metrics import evaluation_arrays
        from nsdyn.solve.compile_split import evaluate_inputs

        Pt, X0 = evaluate_inputs(P, x0[None, :])
        ev = evaluation_arrays(Pt, 1)
        ok = ki.evaluate_many_t(np.array([t]), X0, Pt, *ev) == 0
        qdd, lam, tau = ev[0][0], ev[1][0], ev[2][0]
    else:
        ev = ops.evaluate(P, np.array([t]), x0[None, :])
        qdd, lam, tau, ok = ev[0][0], ev[1][0], ev[2][0], True
    stats[ki.S_NFEV] += 1
    if not (np.all(np.isfinite(x0)) and np.all(np.isfinite(qdd))):
        stats[ki.S_STATUS] = ki.ST_NONFINITE
        return stats, rinfo, X, upl_t
    if not ok:
        stats[ki.S_STATUS] = ki.ST_SINGULAR
        return stats, rinfo, X, upl_t
    a = qdd.copy() if acc is None or np.isnan(acc[0]) else np.array(acc, dtype=float)
    lam_old = lam.copy()
    phi = np.where(fr.fr[4], tau, 0.0) if ni else np.zeros(0)  # fr[4]: friction active
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
    u_all = ground_many(t0 + (k_all + (1.0 - af)) * dt, P)
    u_all[:, 1] += kp.g
    # the step grid: steps of dt, the last one ending on t_end (shortened if need be)
    t_steps = t0 + (k_all + 1.0) * dt
    t_steps[t_steps > t_end - 1e-9 * dt] = t_end
    state = (q, v, a, phi, lam_old)
    par, out = _loop_inputs(coef, fr, alpha_b, beta_b, uplift_mode, ni, t_eval, X, upl_t, stats,
                            rinfo)  # fmt: skip
    A0 = np.empty(n)  # the sparse backend's linear part, given to the kernel step by step
    # segments of constant step size: the regular steps, then a shortened last one (its own
    # factorisation) when dt does not divide the span
    h_last = float(t_steps[-1] - (t0 + (n_steps - 1) * dt)) if n_steps else dt
    short = abs(h_last - dt) > 1e-12 * dt
    for k0, k1, h in ((0, n_steps - short, dt), (n_steps - 1, n_steps * short, h_last)):
        if k1 <= k0 or stats[ki.S_STATUS] != ki.ST_SUCCESS or stats[ki.S_NOUT] >= nt:
            continue
        st = _stepper(P, h, coef, backend, ops)
        u = u_all[k0:k1]
        if h != dt:
            u = ground_many(np.array([t + (1.0 - af) * h]), P)
            u[:, 1] += kp.g
        # the step's low-rank parts (not ``ops``: the full-order operators serve the next
        # segment's stepper too)
        parts = (st.G, st.RGr_inv, st.Lam, st.DGr, st.Wp, R, D)
        if st.lin is not None:  # full-order operators: the whole segment in the kernel
            t = _klowrank.run_steps_ops(
                t, t_steps[k0:k1], u, st.lin, st.lr, A0, state, parts, par, out, max_steps
            )
            continue
        if st.W is not None:  # dense: the whole segment in the kernel
            t = _klowrank.run_steps(
                t, t_steps[k0:k1], u, st.W, A0, state, parts, par, out, max_steps
            )
            continue
        for k in range(k0, k1):  # sparse: A0 by SuperLU here, the rest of the step in the kernel
            if stats[ki.S_STATUS] != ki.ST_SUCCESS or stats[ki.S_NOUT] >= nt:
                break
            A0[:] = st.apply(q, v, a, u[k - k0])
            t = _klowrank.run_steps(
                t, t_steps[k : k + 1], u[k - k0 : k - k0 + 1], _NO_W, A0, state, parts, par, out,
                max_steps,
            )  # fmt: skip
    if acc is not None:
        acc[:] = a
    return stats, rinfo, X, upl_t


def _loop_inputs(coef, fr, alpha_b, beta_b, uplift_mode, ni, t_eval, X, upl_t, stats, rinfo):
    """``(par, out)`` of :func:`nsdyn.solve._klowrank.run_steps` (its parameters, and the
    output arrays with the scratch of the isolators' Newton)."""
    par = (coef, (float(alpha_b), float(beta_b)), fr.fr, int(uplift_mode))
    work = (np.empty((ni, ni)), np.zeros(ni, np.int64)) + tuple(np.empty(ni) for _ in range(5))
    return par, (t_eval, X, upl_t, stats, rinfo, work)


def loop_args(P, x0, t_eval, dt, X, upl_t, uplift_mode) -> tuple:
    """The arguments :func:`integrate` gives :func:`nsdyn.solve._klowrank.run_steps` on the
    dense backend for a run of ``P`` from ``x0`` at step ``dt``, the values that integrate
    computes by the system kernel (q̈, λ, the friction state) as placeholders: their numba
    types are the loop's, so the loop compiles from them before the system kernel has (the
    first compilation's split, :func:`nsdyn.solve.compile_split.lowrank_parts_here`)."""
    coef = _kgenalpha.parameters(_kgenalpha.FAMILY_GENALPHA, RHO_INF)
    coef = tuple(float(c) for c in coef)
    kp = KernelParams(P)
    m = kp.matrices()
    R, D, n = m["R"], m["D"], kp.n
    nc, ni = R.shape[0], D.shape[0]
    fp = P[ks.I_FPAR]
    stats, rinfo = np.zeros(ki.N_STATS, dtype=np.int64), np.zeros(ki.N_RINFO)
    state = (x0[:n].copy(), x0[n:].copy(), np.zeros(n), np.zeros(ni), np.zeros(nc))
    par, out = _loop_inputs(coef, _Friction(kp), fp[ks.F_ALPHA], fp[ks.F_BETA], uplift_mode, ni,
                            t_eval, X, upl_t, stats, rinfo)  # fmt: skip
    st = _stepper(P, dt, coef, "dense")
    ops = (st.G, st.RGr_inv, st.Lam, st.DGr, st.Wp, R, D)
    u = ground_many(np.array([float(t_eval[0])]), P)
    t_steps = float(t_eval[0]) + dt * np.arange(1.0, 2.0)
    return float(t_eval[0]), t_steps, u, st.W, np.empty(n), state, ops, par, out, 10**9


def run(P, x0, t_eval, o, X, upl_t):
    """Runner of the method registry: ``(stats, rinfo, events, modes)``; ``o`` the checked
    options (``dt``, ``max_steps``, ``uplift_mode``, ``rho_inf``)."""
    rho = RHO_INF if o.rho_inf is None else o.rho_inf
    coef = _kgenalpha.parameters(_kgenalpha.FAMILY_GENALPHA, rho)
    try:
        stats, rinfo, _, _ = integrate(
            P, x0, t_eval, o.dt, coef=coef, max_steps=o.max_steps, uplift_mode=o.uplift_mode,
            X=X, upl_t=upl_t, acc=o.acc,
        )  # fmt: skip
    except FloatingPointError:
        stats = np.zeros(ki.N_STATS, dtype=np.int64)
        rinfo = np.zeros(ki.N_RINFO)
        stats[ki.S_STATUS] = ki.ST_LU_SINGULAR
        rinfo[ki.R_T], rinfo[ki.R_H] = float(t_eval[0]), o.dt
    return stats, rinfo, [], None
