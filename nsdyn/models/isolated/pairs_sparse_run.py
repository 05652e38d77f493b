"""Runs of a sparse pair system: generalized-α factored once, the isolator rows as a Schur update.

For :class:`~nsdyn.models.isolated.pairs_sparse.SparsePairSystem` (equations there) one step
of generalized-α (Chung & Hulbert 1993; a_m, a_f, β, γ from ρ∞) solves, at the α point
q_α = q̃ + c₁ a, v_α = ṽ + c₂ a (c₁ = (1 − a_f) β h², c₂ = (1 − a_f) γ h; q̃, ṽ known),

    M ((1 − a_m) a + a_m a_n) + C* v_α + K q_α = −M Γ ü_g(t_α) + Rᵀ λ − D2ᵀ F,
    R ((1 − a_m) a + a_m a_n) + 2αβ R v_α + α² R q_α = 0,     F = F_b(D2 q_α, D2 v_α, λ).

With S = (1 − a_m) M + c₁ K + c₂ C (sparse, factored once by SuperLU) and the modal damping
by Woodbury, S_*⁻¹ b = y − Z (diag(1/(c₂ c)) + Uᵀ Z)⁻¹ Uᵀ y (y = S⁻¹ b, Z = S⁻¹ U),

    a = A₀ + G_R λ − G_D F,   A₀ = S_*⁻¹ b₀,   [G_R, G_D] = S_*⁻¹ [Rᵀ, D2ᵀ]  (n × 3ni, once),

and the rows close on 3ni unknowns: the contact rows give λ = λ₀ + Λ F exactly
(Λ = P_RR⁻¹ P_RD, P = [R; D2][G_R, G_D] the 3ni × 3ni Schur complement), the slip rows
D2 a = w₀ + W F (W = P_DR Λ − P_DD), and Newton solves F − F_b = 0 on 2ni unknowns
(:mod:`._kpairsparse`). A step costs one sparse solve pair, O(n m) for m damped modes,
O(n ni) and the small dense Newton: never an n × n dense array.

Outputs every ``dt_out`` (a multiple of the step); λ and F, computed at the α points, are
carried to the step's end by linear extrapolation (second order). Failures: Newton's
divergence or a non-finite state raise :class:`PlaneIntegrationError` with time and reason;
a normal force reaching zero (the contact is bilateral here) ends the run as an uplift,
reported in the result with a warning (located between α points).
"""

from __future__ import annotations

import math
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from nsdyn._checks import AccuracyWarning, check_fixed_step, got_array, number
from nsdyn.models.isolated import _kpairsparse as kz
from nsdyn.models.isolated import _kplane as kp
from nsdyn.models.isolated import _kplanerun as kr
from nsdyn.models.isolated.bearings import B_DCAP
from nsdyn.models.isolated.deck import default_dt_out, grid_note, pack_ground, run_end
from nsdyn.models.isolated.defaults import ALPHA, BETA, EPS, ETA
from nsdyn.models.isolated.pairs import PairResult
from nsdyn.models.isolated.pairs_sparse import SparsePairSystem
from nsdyn.models.isolated.plane_result import PlaneIntegrationError

__all__ = ["METHOD", "SparsePairResult", "genalpha_coefficients", "simulate_pairs_sparse"]

METHOD = "genalpha-sparse"
RHO_INF = 0.8  # default spectral radius at infinity (as the other generalized-α runs)
NEWTON_RTOL = 1e-10  # |ΔF| accepted relative to max |F| + μ λ₀
NEWTON_MAXITER = 50
PROGRESS_S = 5.0  # seconds of simulated time between two calls of ``progress``
KEEP_Q_MB = 256.0  # keep the full histories q, q̇ when they take at most this many MB
PERMC_SPECS = ("COLAMD", "MMD_AT_PLUS_A")  # SuperLU orderings tried; the sparser factors win


def genalpha_coefficients(rho_inf: float) -> tuple:
    """(a_m, a_f, β, γ) of Chung & Hulbert's generalized-α for spectral radius ρ∞."""
    r = float(rho_inf)
    if not 0.0 <= r <= 1.0:
        raise ValueError(f"rho_inf: expected a spectral radius in [0, 1], got {rho_inf!r}")
    am, af = (2 * r - 1) / (r + 1), r / (r + 1)
    gam = 0.5 - am + af
    return am, af, 0.25 * (1 - am + af) ** 2, gam


class SparsePairResult(PairResult):
    """A :class:`PairResult` of the sparse path: the slips and outputs are recorded during the
    run; ``q``, ``qd`` are the full histories when kept (``keep_q``), else (nt, 0);
    ``accelerations`` = T q̈ (relative to the ground) beside ``outputs`` = T q."""

    def _slip(self, X) -> np.ndarray:
        if X is self.qd:
            return self._v
        return self._u

    @property
    def outputs(self):
        return self._out


def _splu(S):
    best = None
    for spec in PERMC_SPECS:
        try:
            lu = spla.splu(S, permc_spec=spec)
        except RuntimeError as e:
            raise PlaneIntegrationError(f"{METHOD}: singular iteration matrix ({e})") from None
        if best is None or lu.L.nnz + lu.U.nnz < best.L.nnz + best.U.nnz:
            best = lu
    return best


class _Stepper:
    """The constant operators at one step size (module text)."""

    def __init__(self, s: SparsePairSystem, h: float, coef: tuple, alpha: float, beta: float):
        am, af, be, ga = coef
        self.am = am
        self.c1, self.c2 = (1 - af) * be * h * h, (1 - af) * ga * h
        self.kq, self.ka_q, self.ka_v = (
            (1 - af) * h,
            (1 - af) * h * h * (0.5 - be),
            (1 - af) * h * (1 - ga),
        )
        self.kR = (1 - am) + 2 * alpha * beta * self.c2 + alpha**2 * self.c1
        S = sp.csc_array((1 - am) * s.M + self.c1 * s.K + self.c2 * s.C)
        self.lu = _splu(S)
        L, Uf = self.lu.L.tocsc(), self.lu.U.tocsc()
        L.sort_indices()
        Uf.sort_indices()
        i8 = np.int64
        self.fac = (L.indptr.astype(i8), L.indices.astype(i8), L.data, Uf.indptr.astype(i8),
                    Uf.indices.astype(i8), Uf.data, np.ascontiguousarray(Uf.diagonal()),
                    self.lu.perm_r.astype(i8), self.lu.perm_c.astype(i8))  # fmt: skip
        self.w = np.zeros(s.n)
        self.Ut, self.c = np.ascontiguousarray(s.U.T), s.c  # (rows: the fastest products)
        self.low = s.c.size > 0
        if self.low:
            self.Z = np.ascontiguousarray(self.lu.solve(np.asfortranarray(s.U)))
            self.UtZ = self.Ut @ self.Z
            self.cap = np.linalg.inv(np.diag(1.0 / (self.c2 * s.c)) + self.UtZ)
        ni = s.n_isolators
        B = sp.hstack([s.R.T, s.D.T]).toarray()  # (n, 3ni)
        G = self.solve(B)
        self.G = np.ascontiguousarray(G)
        self.UtG = self.Ut @ self.G  # (m, 3ni): U^T of the rows' response
        P = sp.vstack([s.R, s.D]) @ G
        Prr, Prd, Pdr, Pdd = P[:ni, :ni], P[:ni, ni:], P[ni:, :ni], P[ni:, ni:]
        if np.linalg.cond(Prr) > 1e12:
            raise PlaneIntegrationError(f"{METHOD}: the contact rows R are linearly dependent")
        self.Prr_inv = np.linalg.inv(Prr)
        self.Lam = np.ascontiguousarray(self.Prr_inv @ Prd)
        self.Pdr = Pdr
        self.W = np.ascontiguousarray(Pdr @ self.Lam - Pdd)
        self.Wlin = sp.hstack([s.K, self.kq * s.K + s.C, am * s.M + self.ka_q * s.K
                               + self.ka_v * s.C], format="csr")  # fmt: skip
        self.MG = np.ascontiguousarray(s.M @ s.Gamma)
        self.nnz_lu = int(self.lu.L.nnz + self.lu.U.nnz)

    def solve(self, B):
        """``S_*^-1 B`` for a block ``B`` (n, k) (the rows' response, once; a step solves by
        :meth:`solve_damped`)."""
        y = self.lu.solve(B)
        if self.low:
            y = y - self.Z @ (self.cap @ (self.Ut @ y))
        return y

    def solve_damped(self, r, uvt):
        """``(x, U^T x)`` of ``x = S_*^-1 (r + U diag(c) uvt)``: a step's solve with the modal
        damping's force at the α velocity, given its modal coordinates ``uvt = U^T v_α``.
        With ``y = S^-1 r`` and ``w = c uvt``, Woodbury gives ``x = y + Z xi``,
        ``xi = w - cap (U^T y + U^T Z w)``, and ``U^T x = U^T y + U^T Z xi`` (``U^T Z`` made
        once): two products with an n x m matrix (``U^T y``, ``Z xi``, each on contiguous
        rows) where applying the damping to v_α and then the solve takes four."""
        y = np.empty(r.size)
        kz.lu_solve_csc(*self.fac, np.ascontiguousarray(r, dtype=float), self.w, y)
        if not self.low:
            return y, uvt
        w = self.c * uvt
        uy = self.Ut @ y
        xi = w - self.cap @ (uy + self.UtZ @ w)
        return y + self.Z @ xi, uy + self.UtZ @ xi


def simulate_pairs_sparse(
    system: SparsePairSystem, ground, *, dt: float, t_end: float | None = None,
    dt_out: float | None = None, eps: float = EPS, alpha: float = ALPHA, beta: float = BETA,
    rho_inf: float = RHO_INF, y0=None, keep_q: bool | None = None,
    newton_maxiter: int = NEWTON_MAXITER, progress=None,
) -> SparsePairResult:  # fmt: skip
    """Integrate ``system`` under ``ground`` (as :func:`~nsdyn.models.isolated.pairs.
    simulate_pairs` takes it) with the regularised law (arctan, ``eps``) by generalized-α at
    the fixed step ``dt`` (module text), from the static equilibrium or ``y0`` = [q, q̇].
    Outputs every ``dt_out`` (default: the record's step, else 1/50 of the orbit's period;
    rounded to a whole number of steps). ``keep_q``: store q, q̇ histories (default: when
    they take at most ``KEEP_Q_MB``); slips, forces and T q are always stored. ``progress``:
    called as ``progress(t_done, t_end, wall_s)`` every ``PROGRESS_S`` of simulated time."""
    if not isinstance(system, SparsePairSystem):
        raise TypeError(f"system: expected a SparsePairSystem, got {type(system).__name__}")
    given = (("dt", dt), ("eps", eps), ("alpha", alpha), ("beta", beta))
    dt, eps, alpha, beta = (number(k, v, "a positive number", lambda x: x > 0) for k, v in given)
    coef = genalpha_coefficients(rho_inf)
    am, af, be, ga = coef
    gk, gp, tab, dur = pack_ground(ground)
    t_end = run_end(t_end, dur)
    check_fixed_step(dt, ground, t_end)  # (past the record's samples: peaks 4.6x at 1 s)
    dt_out = default_dt_out(gk, gp) if dt_out is None else dt_out  # (an orbit's vertical too)
    every = max(1, int(round(dt_out / dt)))
    coarse = grid_note(gk, gp, dur, dt * every)
    if coarse:  # (the deck's and pair systems' rule)
        import warnings

        warnings.warn(coarse, AccuracyWarning, stacklevel=2)
    t0 = gp[kp.GP_T0] * (gk == kp.G_TABLE)
    n_steps = int(math.floor(t_end / dt * (1 + 1e-12)))
    nt = n_steps // every + 1
    t_eval = t0 + dt * every * np.arange(nt)
    n, ni = system.n, system.n_isolators
    if keep_q is None:
        keep_q = 2 * nt * n * 8 <= KEEP_Q_MB * 2**20
    q, lam_s = system.static_equilibrium()
    v = np.zeros(n)
    if y0 is not None:
        y = np.asarray(y0, dtype=float).ravel()
        if y.shape != (2 * n,) or not np.all(np.isfinite(y)):
            got = got_array(y0, (2 * n,))
            raise ValueError(f"y0: expected {2 * n} finite numbers [q, q̇], got {got}")
        q, v = y[:n].copy(), y[n:].copy()
    bp = system.bearing_table()
    tw = time.perf_counter()
    st = _Stepper(system, float(dt), coef, alpha, beta)
    setup_s = time.perf_counter() - tw
    D, R = system.D, system.R
    ag = np.zeros(3)

    def ground_at(t):
        kp.ground(float(t), gk, gp, tab, ag)
        return np.array([ag[0], ag[1], ag[2] + system.g])

    # the start: a consistent acceleration with λ, F from the same row equations (h -> 0)
    a = np.zeros(n)
    st0 = _Stepper(system, 1e-9 * dt, (0.0, 0.0, be, ga), alpha, beta)  # M a = f(t0, q, v)
    F = np.zeros(2 * ni)
    lam = lam_s.copy()
    X = np.zeros((nt, 2 * n)) if keep_q else np.zeros((nt, 0))
    NO = np.full((nt, ni), np.nan)
    FF, FR, FO, UU, VV = (np.full((nt, ni, 2), np.nan) for _ in range(5))
    Tm = system.T
    OUT = np.zeros((nt, Tm.shape[0])) if Tm is not None else None
    ACC = np.zeros((nt, Tm.shape[0])) if Tm is not None else None
    mu_max = max(max(b.friction.mu_slow, b.friction.mu_fast or 0.0) for b in system.bearings)
    fscale = float(mu_max * lam_s.max() + 1e-12 * lam_s.max())
    wk = kz.workspace(ni)
    lam_w, u_w, v_w, parts = np.zeros(ni), np.zeros(2 * ni), np.zeros(2 * ni), np.zeros((ni, 6))
    stops = np.zeros((ni, 3))
    stops[:, kr.P_TFIRST] = np.nan
    info = np.zeros(kr.N_INFO)
    info[kr.I_TFAIL], info[kr.I_IFAIL] = np.nan, -1
    status = kr.ST_OK

    def record(k, t, q, v, a, lam_o, parts_o):
        if keep_q:
            X[k, :n], X[k, n:] = q, v
        uu, vv = D @ q, D @ v
        UU[k], VV[k] = uu.reshape(ni, 2), vv.reshape(ni, 2)
        NO[k] = lam_o
        parts_o = np.array(parts_o)  # (a copy: the α points' own stay as they are)
        kz.clip_friction(bp, vv, lam_o, parts_o)  # (in the disc μN, as the law)
        FF[k], FR[k], FO[k] = parts_o[:, 0:2], parts_o[:, 2:4], parts_o[:, 4:6]
        if OUT is not None:
            OUT[k], ACC[k] = Tm @ q, Tm @ a
        for i in range(ni):
            r = math.hypot(uu[2 * i], uu[2 * i + 1])
            over = r - bp[i, B_DCAP]
            if over > 0:
                if not stops[i, kr.P_TFIRST] == stops[i, kr.P_TFIRST]:
                    stops[i, kr.P_TFIRST] = t
                stops[i, kr.P_PEAK] = max(stops[i, kr.P_PEAK], over)

    def step(S, t, h, q, v, a, F, ta, uv, ua):
        # uv, ua = U^T v, U^T a: the damped modes' coordinates, carried by the same updates
        qt = q + S.kq * v + S.ka_q * a
        vt = v + S.ka_v * a
        ug = ground_at(ta)
        A0, ua1 = S.solve_damped(S.Wlin @ np.concatenate([q, v, a]) + S.MG @ ug,
                                 uv + S.ka_v * ua)  # fmt: skip
        A0, ua1 = -A0, -ua1
        rc = -S.am * (R @ a) - 2 * alpha * beta * (R @ vt) - alpha**2 * (R @ qt)
        lam0 = S.Prr_inv @ (rc / S.kR - R @ A0)
        w0 = D @ A0 + S.Pdr @ lam0
        Fn = F.copy()
        code, its = kz.newton(Fn, lam0, S.Lam, w0, S.W, D @ qt, D @ vt, S.c1, S.c2, bp,
                              float(eps), fscale, NEWTON_RTOL, newton_maxiter, lam_w, u_w, v_w,
                              parts, wk)  # fmt: skip
        if code != kz.OK:
            return code, its, None
        lam_n = lam_w.copy()
        g = np.concatenate([lam_n, -Fn])
        a1 = A0 + S.G @ g
        q1 = q + h * v + h * h * ((0.5 - be) * a + be * a1)
        v1 = v + h * ((1 - ga) * a + ga * a1)
        if S.low:
            ua1 = ua1 + S.UtG @ g
            uv = uv + h * ((1 - ga) * ua + ga * ua1)
        return code, its, (q1, v1, a1, Fn, lam_n, parts.copy(), uv, ua1)

    # consistent start: one vanishing step gives a(t0), λ(t0), F(t0)
    uv = st.Ut @ v
    code, _, res = step(st0, t0, 0.0, q, v, a, F, t0, uv, np.zeros_like(uv))
    if code != kz.OK:
        raise PlaneIntegrationError(f"{METHOD}: no consistent start at t = {t0:.6g} s (Newton "
                                    "on the isolator forces failed)")  # fmt: skip
    _, _, a, F, lam, pr, _, _ = res
    del st0  # (its factors and n x m arrays)
    ua = st.Ut @ a
    record(0, t0, q, v, a, lam, pr)
    lam_prev, parts_prev = lam, pr
    t = t0
    nit = 0
    report = max(1, int(round(PROGRESS_S / dt)))
    for k in range(1, n_steps + 1):
        h = float(dt)
        ta = t + (1 - af) * h
        code, its, res = step(st, t, h, q, v, a, F, ta, uv, ua)
        nit += its
        if code != kz.OK:
            why = ("Newton's iterations on the isolator forces diverge" if code == kz.NEWTON_FAIL
                   else "NaN or inf in the isolator forces")  # fmt: skip
            raise PlaneIntegrationError(
                f"{METHOD}: {why} at t = {ta:.6g} s (step {h:g} s; lower dt or eps, or raise "
                "newton_maxiter)"
            )
        a_old = a
        q, v, a, F, lam_a, pa, uv, ua = res
        if not (np.all(np.isfinite(q)) and np.all(np.isfinite(v))):
            raise PlaneIntegrationError(f"{METHOD}: NaN or inf in the state at t = {t + h:.6g} s")
        if np.any(lam_a <= 0.0):
            i = int(np.argmin(lam_a))
            lp = lam_prev[i]
            frac = lp / (lp - lam_a[i]) if lp > 0 else 1.0
            info[kr.I_TFAIL] = t - af * h + frac * h if k > 1 else ta
            info[kr.I_IFAIL] = i
            status = kr.ST_UPLIFT
            break
        t = t0 + k * h
        if k % every == 0:  # λ, F from the α points carried to t (linear, second order)
            lam_o = lam_a + af * (lam_a - lam_prev)
            parts_o = pa + af * (pa - parts_prev)
            a_o = a + (af - am) * (a - a_old)  # a_(n+1) is q̈ at t + (a_m − a_f) h
            record(k // every, t, q, v, a_o, lam_o, parts_o)
            info[kr.I_NOUT] = k // every + 1
        lam_prev, parts_prev = lam_a, pa
        if progress is not None and k % report == 0:
            progress(t, t0 + n_steps * dt, time.perf_counter() - tw)
    info[kr.I_NOUT] = max(info[kr.I_NOUT], 1)
    info[kr.I_NSTEP], info[kr.I_NFEV] = k if n_steps else 0, nit
    wall = time.perf_counter() - tw
    MO = np.full((nt, ni), kp.MODE_SLIP, dtype=np.int64)
    res = SparsePairResult.from_run(system, "arctan", t_eval, np.zeros((nt, 6)), NO, FF, FR,
                                    FO, MO, np.zeros((0, 6)), stops, info, int(status), eps,
                                    ETA, located=False)  # fmt: skip
    m = res.t.size
    res.q, res.qd = X[:m, :n], X[:m, n:]
    res._u, res._v = UU[:m], VV[:m]
    res._out = None if OUT is None else OUT[:m]
    res.accelerations = None if ACC is None else ACC[:m]
    res.stats.update(
        method=METHOD,
        dt_s=float(dt),
        setup_s=setup_s,
        wall_s=wall,
        newton_iterations=int(nit),
        lu_nnz=st.nnz_lu,
        n_damped=int(system.c.size),
    )
    return res
