"""Periodic solutions under harmonic ground acceleration: shooting, Floquet, continuation.

Seed 004 §6, eqs (18)-(27). Under ``u''_hor = A sin(2 pi f t)`` (``u''_ver = 0``, gravity
kept) a periodic solution on the minimal coordinates ``x = [z, zd]`` (``q = Q z``) solves

    H(x0, f) = phi_T(x0; f) - x0 = 0,      T = 1 / f                              (eq 19)

with ``phi_T`` the period map. Newton's method (eqs 20-22) uses ``dH/dx0 = Phi - I`` where the
monodromy ``Phi`` is the exact derivative of the discrete period map actually integrated
(fixed-step, L-stable SDIRK, derivative of the stage equations: see :mod:`nsdyn._kperiodic`).
Its eigenvalues are the Floquet multipliers: stable when all ``|mu| < 1``; a real multiplier
through +1 is a fold, through -1 a period doubling, a complex pair through the unit circle a
Neimark-Sacker bifurcation.

Continuation in f is either sequential (the seed's: previous solution as the guess) or
pseudo-arclength in ``(x0, log f)`` (Keller), which passes folds; where shooting fails, the
point is found by a stepped frequency sweep: plain time integration until the Poincare map
``x(kT)`` is stationary. Every point records the method that produced it and, for the sweep,
why shooting failed.

Stability caveat: the discrete map damps the undamped kHz boundary modes of the isolated frame
(L-stability, ``R(inf) = 0``); the exact flow would keep multipliers of modulus 1 for them.
The reported multipliers are those of the discretised map.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from . import _kperiodic as kp
from . import _ksystem as ks
from ._params import Harmonic, pack, with_ground

# ---- tuning constants -----------------------------------------------------------------------
SHOOT_TOL = 1e-6  # relative shooting residual for convergence (per block, to the orbit range)
SHOOT_MAXIT = 12  # Newton iterations per shooting solve
SHOOT_STALL = 10.0  # a stalled Newton (no descent) counts as converged below this x tol
LS_HALVINGS = 6  # line-search step halvings before giving up
LS_ALPHA = 1e-4  # Armijo constant of the line search
STAGE_RTOL = 1e-9  # stage Newton tolerance (relative)
STAGE_ATOL = 1e-13  # stage Newton tolerance (absolute, m and m/s)
AMP_FLOOR = 1e-12  # smallest orbit amplitude used for scaling [m, m/s]
MU_REAL = 1e-7  # |Im mu| / |mu| below which a multiplier counts as real
STABLE_MARGIN = 1e-9  # stable when max |mu| < 1 + this
STICK_UTILISATION = 0.9  # arctan law: "stick" while |s(v)| <= this (friction below 90 %)
REFINE_FACTOR = 4  # more steps per period when a period cannot be integrated
WARMUP_PERIODS = 2  # plain periods integrated before the first shooting solve
SS_TOL = 1e-6  # steady-state test of the sweep fallback (estimated distance, relative)
SS_MAX_PERIODS = 400  # longest sweep fallback [periods]
SS_MAX_TIME = 4000.0  # ... and [s] of simulated time
SS_RHO_CAP = 1e3  # largest extrapolation factor rho / (1 - rho) of the steady-state estimate
ARC_MAXIT = 8  # corrector iterations per arclength step
ARC_GOOD = 3  # corrector iterations at or below which the step grows
ARC_GROW, ARC_SHRINK = 1.5, 0.5  # step factors
ARC_DS_MIN = 1e-5  # smallest arclength step before falling back to the sweep
ARC_DS_MAX = 0.5  # largest step (scaled state units: relative change of the orbit)
ARC_COS_MIN = 0.7  # smallest cosine between successive tangents (branch-jump guard)
ARC_STATE_WEIGHT = 0.1  # weight of the (amplitude-scaled) state in the arclength norm
ARC_MAX_CORRECTION = 1.0  # corrector iterates stay within this many ds of the predictor
ARC_MAX_STEPS_FACTOR = 20  # at most this many x the requested points along a curve


# ---- SDIRK tableaux (all stiffly accurate and L-stable) -------------------------------------
def _sdirk2():
    """Alexander (1977), 2 stages, order 2, gamma = 1 - 1/sqrt(2)."""
    g = 1.0 - math.sqrt(0.5)
    return np.array([[g, 0.0], [1.0 - g, g]]), np.array([g, 1.0])


def _sdirk3():
    """Alexander (1977), 3 stages, order 3, gamma = 0.4358665215 (Hairer-Wanner IV.6)."""
    g = 0.43586652150845899942
    b1 = -(6 * g * g - 16 * g + 1) / 4
    b2 = (6 * g * g - 20 * g + 5) / 4
    A = np.array([[g, 0, 0], [(1 - g) / 2, g, 0], [b1, b2, g]])
    return A, np.array([g, (1 + g) / 2, 1.0])


TABLEAUX = {
    "euler": lambda: (np.array([[1.0]]), np.array([1.0])),  # backward Euler, order 1
    "sdirk2": _sdirk2,
    "sdirk3": _sdirk3,
}
ORDER = {"euler": 1, "sdirk2": 2, "sdirk3": 3}


@dataclass(frozen=True)
class Discretisation:
    """Fixed-step integration of one period: ``N = clip(ceil(T / dt_max), n_min, n_max)``."""

    method: str = "sdirk2"
    n_min: int = 200  # steps per period at least (high frequencies)
    dt_max: float = 0.02  # s, longest step (low frequencies: resolves the 0.5-5 Hz modes)
    n_max: int = 20000
    rtol: float = STAGE_RTOL
    atol: float = STAGE_ATOL

    def steps(self, T: float) -> int:
        return int(min(self.n_max, max(self.n_min, math.ceil(T / self.dt_max - 1e-9))))

    def tableau(self) -> tuple[np.ndarray, np.ndarray]:
        if self.method not in TABLEAUX:
            raise ValueError(f"method: expected one of {sorted(TABLEAUX)}, got {self.method!r}")
        return TABLEAUX[self.method]()


# ---- problems -------------------------------------------------------------------------------
_DUMMY_P = None


def _dummy_params() -> tuple:
    global _DUMMY_P
    if _DUMMY_P is None:
        _DUMMY_P = pack(np.eye(1), np.zeros((1, 1)), np.zeros((1, 1)), np.zeros((1, 2)))
    return _DUMMY_P


@dataclass
class PeriodicProblem:
    """A harmonically forced system whose period map the kernels integrate.

    ``x_ref`` is the unforced reference state (the static gravity equilibrium of a frame);
    the state is ``[z, zd]`` with ``m`` position coordinates. ``Z`` holds the precomputed
    manifold matrices of :mod:`nsdyn._kperiodic` (``Z[0] = Q``).
    """

    prob: int
    P: tuple
    Z: tuple
    pf: np.ndarray
    x_ref: np.ndarray
    amplitude: float
    system: object = None
    name: str = ""
    _cache: dict = field(default_factory=dict, repr=False)

    @property
    def Q(self) -> np.ndarray:
        return self.Z[kp.Z_Q]

    @property
    def m(self) -> int:
        return self.x_ref.size // 2

    @property
    def dim(self) -> int:
        return self.x_ref.size

    def to_full(self, X: np.ndarray) -> np.ndarray:
        """Minimal-coordinate states ``[z, zd]`` (shape (..., 2m)) as full states
        ``[q, qd] = [Q z, Q zd]`` (shape (..., 2n))."""
        Q, m = self.Q, self.m
        return np.concatenate([X[..., :m] @ Q.T, X[..., m:] @ Q.T], axis=-1)

    def to_minimal(self, X: np.ndarray) -> np.ndarray:
        """Full states ``[q, qd]`` as ``[Q^T q, Q^T qd]`` (Q has orthonormal columns: exact on
        the contact manifold R q = 0, its projection elsewhere)."""
        Q, n = self.Q, self.Q.shape[0]
        return np.concatenate([X[..., :n] @ Q, X[..., n:] @ Q], axis=-1)

    def at(self, f: float) -> tuple[tuple, np.ndarray]:
        """Kernel arguments (P, pf) for forcing frequency ``f`` [Hz]."""
        if self.prob == kp.PROB_FRAME:
            return with_ground(self.P, Harmonic(self.amplitude, f)), self.pf
        pf = self.pf.copy()
        pf[4] = 2 * np.pi * f
        return self.P, pf


def manifold_matrices(system, P: tuple) -> tuple:
    """The tuple Z of :mod:`nsdyn._kperiodic` (products on q = Q z precomputed once)."""
    Q = np.ascontiguousarray(system.Q)
    MiK, MiC, Gam = P[ks.I_MIK], P[ks.I_MIC], P[ks.I_GAM]
    R, MiRt, D, MiDt = P[ks.I_R], P[ks.I_MIRT], P[ks.I_D], P[ks.I_MIDT]
    ni = D.shape[0]
    parts = [None] * kp.N_Z
    parts[kp.Z_Q], parts[kp.Z_QT] = Q, Q.T
    parts[kp.Z_KZ], parts[kp.Z_CZ] = Q.T @ MiK @ Q, Q.T @ MiC @ Q
    parts[kp.Z_QG] = Q.T @ Gam
    parts[kp.Z_QMIRT], parts[kp.Z_QMIDT] = Q.T @ MiRt, Q.T @ MiDt
    parts[kp.Z_RAZ], parts[kp.Z_RAV] = R @ MiK @ Q, R @ MiC @ Q
    parts[kp.Z_RG] = R @ Gam
    parts[kp.Z_G0], parts[kp.Z_GD] = R @ MiRt, R @ MiDt
    parts[kp.Z_DQ] = D @ Q
    parts[kp.Z_MU] = P[ks.I_MU].reshape(1, ni)
    parts[kp.Z_L0] = P[ks.I_LAM0].reshape(1, ni)
    return tuple(np.ascontiguousarray(a, dtype=float) for a in parts)


def frame_problem(system, amplitude: float, *, law: str | None = None) -> PeriodicProblem:
    """The isolated ``system`` under ``u''_hor = amplitude sin(2 pi f t)`` on z = Q^T q.

    Only smooth friction laws ("arctan", "none") give a differentiable period map.
    """
    if system.isolation is None:
        raise ValueError("shooting needs an isolated model; the fixed base is linear (use FRFs)")
    law = law or system.isolation.law
    if law not in ("arctan", "none"):
        raise ValueError(f"shooting needs a smooth friction law ('arctan' or 'none'), got {law!r}")
    P = system.params(Harmonic(amplitude, 1.0), law=law)
    Z = manifold_matrices(system, P)
    Q = Z[kp.Z_Q]
    x_static, _ = system.static_equilibrium()
    z0 = Q.T @ x_static[: system.n]
    x_ref = np.concatenate([z0, np.zeros_like(z0)])
    return PeriodicProblem(
        kp.PROB_FRAME, P, Z, np.zeros(5), x_ref, float(amplitude), system, system.name
    )


_DUMMY_Z = tuple(np.zeros((1, 1)) for _ in range(kp.N_Z))


def duffing_problem(zeta: float, w0: float, gamma: float, F: float) -> PeriodicProblem:
    """``x'' + 2 zeta w0 x' + w0^2 x + gamma x^3 = F cos(2 pi f t)`` (test problem)."""
    pf = np.array([zeta, w0, gamma, F, 1.0], dtype=float)
    Z = (np.eye(1),) * 2 + _DUMMY_Z[2:]
    return PeriodicProblem(
        kp.PROB_DUFFING, _dummy_params(), Z, pf, np.zeros(2), float(F), None, "duffing"
    )


# ---- the period map -------------------------------------------------------------------------
@dataclass
class PeriodMap:
    """One period integrated from ``x0``: end state, derivatives, orbit, status."""

    xT: np.ndarray
    monodromy: np.ndarray | None  # d xT / d x0
    dxdT: np.ndarray | None  # d xT / d T
    X: np.ndarray | None  # (N + 1, dim) states at the step points
    status: int
    n_steps: int
    n_fev: int
    n_sub: int  # steps that had to be split into substeps


STATUS_NOT_STEADY = 4  # sweep: no steady state within the allowed periods
STATUS_MESSAGES = {
    STATUS_NOT_STEADY: "no steady state within the allowed periods",
    kp.STATUS_OK: "ok",
    kp.STATUS_STAGE: "a stage Newton iteration did not converge (try more steps per period)",
    kp.STATUS_SINGULAR: "singular constraint system or iteration matrix",
    kp.STATUS_NONFINITE: "the state became inf/nan (try more steps per period)",
}


def period_map(
    problem: PeriodicProblem,
    x0: np.ndarray,
    f: float,
    *,
    n_steps: int | None = None,
    disc: Discretisation | None = None,
    sens: bool = True,
    store: bool = False,
) -> PeriodMap:
    """Integrate one forcing period from ``x0`` (t = 0) with ``n_steps`` SDIRK steps."""
    disc = disc or Discretisation()
    T = 1.0 / f
    N = disc.steps(T) if n_steps is None else int(n_steps)
    A, c = disc.tableau()
    P, pf = problem.at(f)
    xT, S, w, X, status, nfev, nsub = kp.period_map(
        problem.prob,
        np.ascontiguousarray(x0, dtype=float),
        T,
        N,
        P,
        problem.Z,
        pf,
        A,
        c,
        sens,
        store,
        disc.rtol,
        disc.atol,
    )
    return PeriodMap(
        xT,
        S if sens else None,
        w if sens else None,
        X if store else None,
        int(status),
        N,
        int(nfev),
        int(nsub),
    )


def floquet_multipliers(monodromy: np.ndarray) -> np.ndarray:
    """Eigenvalues of the monodromy, sorted by decreasing modulus."""
    mu = np.linalg.eigvals(monodromy)
    return mu[np.argsort(-np.abs(mu), kind="stable")]


def orbit_amplitudes(problem: PeriodicProblem, X: np.ndarray) -> tuple[float, float]:
    """Largest excursion of the displacement and of the velocity block of ``X`` (samples in
    minimal coordinates) from the static state, each at least AMP_FLOOR: the scales of the
    shooting residual and closure tests."""
    m = problem.m
    dX = np.abs(X - problem.x_ref[None, :])
    return max(float(dX[:, :m].max()), AMP_FLOOR), max(float(dX[:, m:].max()), AMP_FLOOR)


def _weights(problem: PeriodicProblem, amp: tuple[float, float]) -> np.ndarray:
    m = problem.m
    return np.concatenate([np.full(m, 1.0 / amp[0]), np.full(m, 1.0 / amp[1])])


# ---- shooting -------------------------------------------------------------------------------
@dataclass
class ShootingResult:
    """Outcome of one shooting solve at frequency ``f``."""

    f: float
    x0: np.ndarray
    converged: bool
    iterations: int
    residual: float
    monodromy: np.ndarray | None
    dxdT: np.ndarray | None
    X: np.ndarray | None
    n_steps: int
    message: str = ""
    history: list = field(default_factory=list)

    @property
    def multipliers(self) -> np.ndarray:
        return floquet_multipliers(self.monodromy)


def _evaluate(problem, x, f, N, disc):
    pm = period_map(problem, x, f, n_steps=N, disc=disc, sens=True, store=True)
    if pm.status != kp.STATUS_OK:
        return pm, None, np.inf
    amp = orbit_amplitudes(problem, pm.X)
    W = _weights(problem, amp)
    H = pm.xT - x
    return pm, W, float(np.max(np.abs(W * H)))


def shoot(
    problem: PeriodicProblem,
    f: float,
    x0: np.ndarray | None = None,
    *,
    tol: float = SHOOT_TOL,
    max_iter: int = SHOOT_MAXIT,
    disc: Discretisation | None = None,
    n_steps: int | None = None,
) -> ShootingResult:
    """Newton's method with an Armijo line search on ``H(x0) = phi_T(x0) - x0`` (eqs 19-22).

    The residual is ``max_i |H_i| / range_i`` with ``range`` the orbit's largest excursion from
    the reference state in the position and velocity blocks. ``iterations`` counts Newton
    updates (a linear system converges after one).
    """
    disc = disc or Discretisation()
    N = disc.steps(1.0 / f) if n_steps is None else int(n_steps)
    x = problem.x_ref.copy() if x0 is None else np.array(x0, dtype=float)
    pm, W, r = _evaluate(problem, x, f, N, disc)
    hist = [r]
    if pm.status != kp.STATUS_OK:
        return ShootingResult(
            f,
            x,
            False,
            0,
            r,
            None,
            None,
            None,
            N,
            f"initial period: {STATUS_MESSAGES[pm.status]}",
            hist,
        )
    it = 0
    msg = ""
    while r > tol:
        if it >= max_iter:
            msg = f"no convergence in {max_iter} Newton iterations (residual {r:.2e})"
            break
        H = pm.xT - x
        Jn = pm.monodromy - np.eye(x.size)
        try:
            dx = np.linalg.solve(Jn, -H)
        except np.linalg.LinAlgError:
            msg = "singular Newton matrix Phi - I (a multiplier at +1: fold or creep mode)"
            break
        if not np.all(np.isfinite(dx)):
            msg = "Newton step not finite"
            break
        merit = float(np.linalg.norm(W * H))
        alpha = 1.0
        accepted = False
        for _ in range(LS_HALVINGS + 1):
            xt = x + alpha * dx
            pt, Wt, rt = _evaluate(problem, xt, f, N, disc)
            if pt.status == kp.STATUS_OK:
                mt = float(np.linalg.norm(W * (pt.xT - xt)))
                if mt <= (1.0 - LS_ALPHA * alpha) * merit or rt <= tol:
                    accepted = True
                    break
            alpha *= 0.5
        if not accepted:
            if r <= SHOOT_STALL * tol:
                # no descent left: the residual sits on the round-off floor of the map
                msg = f"converged (stalled at the period map's round-off, residual {r:.1e})"
                return ShootingResult(f, x, True, it, r, pm.monodromy, pm.dxdT, pm.X, N, msg, hist)
            msg = f"line search failed after {LS_HALVINGS} halvings (residual {r:.2e})"
            break
        x, pm, W, r = xt, pt, Wt, rt
        it += 1
        hist.append(r)
    ok = r <= tol
    return ShootingResult(
        f, x, ok, it, r, pm.monodromy, pm.dxdT, pm.X, N, msg if not ok else "converged", hist
    )


# ---- stepped-sweep fallback -----------------------------------------------------------------
@dataclass
class SweepResult:
    f: float
    x0: np.ndarray  # state at the start of the last period
    X: np.ndarray  # last period
    periods: int
    estimate: float  # estimated distance to the steady state (relative)
    steady: bool
    monodromy: np.ndarray | None
    n_steps: int
    message: str
    periods_done: int = 0  # periods integrated successfully (X is the last of them)


def steady_state_sweep(
    problem: PeriodicProblem,
    f: float,
    x0: np.ndarray | None = None,
    *,
    tol: float = SS_TOL,
    max_periods: int = SS_MAX_PERIODS,
    max_time: float = SS_MAX_TIME,
    disc: Discretisation | None = None,
    monodromy: bool = True,
) -> SweepResult:
    """Time-integrate whole periods until the Poincare map ``x(kT)`` is stationary.

    The change ``delta_k = |x(kT) - x((k-1)T)|`` (per block, relative to the orbit's excursion)
    contracts by ``rho = delta_k / delta_(k-1)`` per period; the distance left to the steady
    state is estimated as ``delta_k min(rho / (1 - rho), SS_RHO_CAP)`` and must fall below
    ``tol`` (or ``delta_k`` below ``tol / 100``, the round-off floor). Each period is one kernel
    call (the per-call overhead is < 0.1 % of a period). The multipliers of the last period's
    monodromy (one extra period) are returned as an approximate stability verdict.
    """
    disc = disc or Discretisation()
    T = 1.0 / f
    N = disc.steps(T)
    x = problem.x_ref.copy() if x0 is None else np.array(x0, dtype=float)
    kmax = int(max(3, min(max_periods, math.ceil(max_time / T))))
    m = problem.m
    d_old = math.inf
    est = math.inf
    status = STATUS_NOT_STEADY
    X = None
    x_start = x  # start of the period held in X
    k = 0
    done = 0
    for k in range(1, kmax + 1):
        pm = period_map(problem, x, f, n_steps=N, disc=disc, sens=False, store=True)
        if pm.status != kp.STATUS_OK:
            status = pm.status
            break
        X = pm.X
        x_start = x
        done += 1
        amp_z, amp_v = orbit_amplitudes(problem, X)
        dx = np.abs(pm.xT - x)
        delta = max(dx[:m].max() / amp_z, dx[m:].max() / amp_v)
        rho = delta / d_old if math.isfinite(d_old) and d_old > 0 else math.inf
        est = delta * min(rho / (1.0 - rho), SS_RHO_CAP) if rho < 1.0 else math.inf
        if k >= 3 and (est < tol or delta < 0.01 * tol):
            status = kp.STATUS_OK
            est = min(est, delta)
            break
        d_old = delta
        x = pm.xT
    steady = status == kp.STATUS_OK
    msg = (
        f"steady after {k} periods (estimate {est:.1e})"
        if steady
        else f"{STATUS_MESSAGES[int(status)]} ({k} periods, estimate {est:.1e})"
    )
    x = x_start  # x0 and the monodromy belong to the period returned in X
    M = None
    if monodromy and status in (kp.STATUS_OK, STATUS_NOT_STEADY) and X is not None:
        pm = period_map(problem, x, f, n_steps=N, disc=disc, sens=True)
        if pm.status == kp.STATUS_OK:
            M = pm.monodromy
    if X is None:
        X = np.vstack([x, x])
    return SweepResult(f, x, X, int(k), float(est), steady, M, N, msg, done)


# ---- points and curves ----------------------------------------------------------------------
@dataclass
class OrbitPoint:
    """One periodic solution on a frequency-response curve."""

    f: float
    x0: np.ndarray
    method: str  # "shooting" (sequential), "arclength" or "sweep"
    converged: bool
    iterations: int
    residual: float
    multipliers: np.ndarray
    n_steps: int
    note: str = ""  # why shooting failed (sweep points) or other remarks
    quantities: dict = field(default_factory=dict)
    s: float = float("nan")  # arclength along the curve (arclength points)
    dlogf_ds: float = float("nan")  # tangent's parameter component
    X: np.ndarray | None = field(default=None, repr=False)

    @property
    def max_multiplier(self) -> float:
        return float(np.max(np.abs(self.multipliers))) if self.multipliers.size else math.nan

    @property
    def stable(self) -> bool | None:
        if not self.multipliers.size:
            return None
        return bool(self.max_multiplier < 1.0 + STABLE_MARGIN)


def multiplier_counts(mu: np.ndarray) -> tuple[int, int, int]:
    """(real > +1, real < -1, complex outside the unit circle) among multipliers ``mu``."""
    real = np.abs(mu.imag) <= MU_REAL * np.maximum(np.abs(mu), 1e-300)
    out = np.abs(mu) > 1.0 + STABLE_MARGIN
    return (
        int(np.sum(real & out & (mu.real > 0))),
        int(np.sum(real & out & (mu.real < 0))),
        int(np.sum(~real & out)),
    )


def detect_bifurcations(points: list[OrbitPoint]) -> list[dict]:
    """Bifurcations between consecutive points from changes in the multiplier counts.

    Folds are also located where f turns along an arclength curve (a local extremum of f
    between consecutive points); the fold frequency is the vertex of a parabola log f(s)
    through the three points around the turn.
    """
    out = []
    kinds = ("fold", "period-doubling", "Neimark-Sacker")
    for a, b in zip(points[:-1], points[1:], strict=False):
        if not (a.multipliers.size and b.multipliers.size):
            continue
        ca, cb = multiplier_counts(a.multipliers), multiplier_counts(b.multipliers)
        for k, kind in enumerate(kinds):
            if ca[k] != cb[k]:
                f_est = _interp_crossing(a, b, k)
                out.append(
                    {
                        "kind": kind,
                        "f": f_est,
                        "f_a": a.f,
                        "f_b": b.f,
                        "by": "multipliers",
                        "unstable_before": ca[k] > 0,
                    }
                )
    for i in range(1, len(points) - 1):
        trip = points[i - 1 : i + 2]
        if not all(p.method == "arclength" and np.isfinite(p.s) for p in trip):
            continue
        fa, fb, fc = (p.f for p in trip)
        if (fb > fa and fb > fc) or (fb < fa and fb < fc):
            out.append(
                {
                    "kind": "fold",
                    "f": _parabola_vertex(trip),
                    "f_a": fa,
                    "f_b": fc,
                    "by": "turning point",
                    "unstable_before": None,
                }
            )
    return out


def _parabola_vertex(trip: list[OrbitPoint]) -> float:
    s = np.array([p.s for p in trip])
    y = np.array([math.log(p.f) for p in trip])
    if len(trip) < 3 or not np.all(np.isfinite(s)):
        return float(np.exp(y[np.argmax(np.abs(y - y.mean()))]))
    c2, c1, c0 = np.polyfit(s - s[1], y, 2)
    if c2 == 0:
        return float(np.exp(y[1]))
    sv = -c1 / (2 * c2)
    return float(np.exp(c0 - c1 * c1 / (4 * c2)) if abs(sv) <= np.ptp(s) else np.exp(y[1]))


def _interp_crossing(a: OrbitPoint, b: OrbitPoint, kind: int) -> float:
    """Frequency where the crossing multiplier reaches the unit circle (linear in log f)."""

    def crit(p):
        mu = p.multipliers
        if kind == 0:
            r = mu[np.abs(mu.imag) <= MU_REAL * np.abs(mu)].real
            return float(r.max()) - 1.0 if r.size else math.nan
        if kind == 1:
            r = mu[np.abs(mu.imag) <= MU_REAL * np.abs(mu)].real
            return -float(r.min()) - 1.0 if r.size else math.nan
        c = mu[np.abs(mu.imag) > MU_REAL * np.abs(mu)]
        return float(np.abs(c).max()) - 1.0 if c.size else math.nan

    ga, gb = crit(a), crit(b)
    la, lb = math.log(a.f), math.log(b.f)
    if np.isfinite(ga) and np.isfinite(gb) and ga != gb:
        return float(math.exp(la + (lb - la) * ga / (ga - gb)))
    return float(math.sqrt(a.f * b.f))


@dataclass
class Curve:
    """A frequency-response curve of periodic solutions at one forcing amplitude."""

    amplitude: float
    points: list[OrbitPoint]
    bifurcations: list[dict] = field(default_factory=list)
    info: dict = field(default_factory=dict)

    def column(self, name: str) -> np.ndarray:
        """A per-point attribute or quantity as an array (``"f"``, ``"idr"``, ...)."""
        vals = []
        for p in self.points:
            v = p.quantities.get(name) if name in p.quantities else getattr(p, name)
            vals.append(np.nan if v is None else v)
        return np.asarray(vals)

    def rows(self) -> list[dict]:
        """One flat record per point (the sweep CSV)."""
        out = []
        for p in self.points:
            q = p.quantities
            out.append(
                {
                    "f": p.f,
                    "A": self.amplitude,
                    "IDR": q.get("idr", math.nan),
                    "a": q.get("acc", math.nan),
                    "a_floors": q.get("acc_floors", math.nan),
                    "x_iso": q.get("x_iso", math.nan),
                    "stick_all_period": q.get("stick_all_period", ""),
                    "stable": "" if p.stable is None else p.stable,
                    "max_multiplier_modulus": p.max_multiplier,
                    "method": p.method,
                    "newton_iterations": p.iterations,
                    "residual": p.residual,
                    "converged": p.converged,
                    "n_steps": p.n_steps,
                    "uplift": q.get("uplift", ""),
                    "note": p.note,
                }
            )
        return out


# ---- quantities on an orbit -----------------------------------------------------------------
def orbit_quantities(problem: PeriodicProblem, f: float, X: np.ndarray) -> dict:
    """Maximum over one period (and all levels) of the seed's Fig. 9 quantities.

    ``idr``: interstorey drift ratio (column lines, all storeys); ``acc``: absolute horizontal
    floor acceleration (all nodes of every level, base included); ``acc_floors``: the same over
    the levels above the isolators (``nsdyn run``'s ``floor_acc_max``); ``x_iso``: half the
    peak-to-peak isolator slip ``D q`` (largest isolator); ``stick_all_period``: every
    isolator's friction stays below ``STICK_UTILISATION`` of its limit over the whole period
    (arctan law: ``|v| <= tan(0.45 pi) / eps``, the creep branch). For the Duffing problem:
    ``amp`` (half the peak-to-peak displacement) only.
    """
    m = problem.m
    if problem.prob == kp.PROB_DUFFING:
        x = X[:, 0]
        return {"amp": 0.5 * float(x.max() - x.min()), "x_max": float(np.abs(x).max())}
    sysm = problem.system
    cache = problem._cache
    if "od" not in cache:
        from .metrics import output_dofs

        od = output_dofs(sysm.frame)
        T = sysm.T
        cache["od"] = od
        cache["Tj"] = T[od["joints_x"]] @ problem.Q  # (levels, cols, m)
        cache["Tl"] = [T[d] for d in od["levels_x"]]
    N = X.shape[0] - 1
    t = np.linspace(0.0, 1.0 / f, N + 1)
    n = problem.Q.shape[0]
    Xf = np.ascontiguousarray(problem.to_full(X))
    P, _ = problem.at(f)
    nc, ni = sysm.n_contacts, sysm.n_isolators
    QDD = np.empty((N + 1, n))
    LAM = np.empty((N + 1, nc))
    TAU = np.empty((N + 1, ni))
    MODES = np.empty((N + 1, ni), dtype=np.int64)
    ks.evaluate_many(t, Xf, P, QDD, LAM, TAU, MODES)
    G = ks.ground_many(t, P)
    od = cache["od"]
    U = np.einsum("lcj,tj->tlc", cache["Tj"], X[:, :m])
    drift = np.abs(np.diff(U, axis=1)) / od["heights"][None, :, None]
    idr = float(drift.max()) if drift.size else 0.0
    acc_levels = [float(np.max(np.abs(QDD @ Tl.T + G[:, :1]))) for Tl in cache["Tl"]]
    acc = max(acc_levels, default=0.0)
    acc_floors = max(acc_levels[1:] if len(acc_levels) > 1 else acc_levels, default=0.0)
    q = Xf[:, :n]
    xi = q @ sysm.D.T
    x_iso = float(0.5 * np.max(xi.max(axis=0) - xi.min(axis=0))) if xi.size else 0.0
    v = Xf[:, n:] @ sysm.D.T
    law = int(P[ks.I_IPAR][ks.K_LAW])
    if law == ks.LAW_ARCTAN:
        eps = float(P[ks.I_FPAR][ks.F_EPS])
        v_stick = math.tan(0.5 * math.pi * STICK_UTILISATION) / eps
        stick = bool(np.max(np.abs(v)) <= v_stick) if v.size else True
    else:
        stick = False
    return {
        "idr": idr,
        "acc": acc,
        "acc_floors": acc_floors,
        "x_iso": x_iso,
        "stick_all_period": stick,
        "v_slip_max": float(np.max(np.abs(v))) if v.size else 0.0,
        "min_normal_force": float(LAM.min()) if LAM.size else math.nan,
        "uplift": bool(LAM.size and LAM.min() <= 0.0),
    }


# ---- continuation ---------------------------------------------------------------------------
def _uplift_note(q: dict) -> str:
    if q.get("uplift"):
        fmin = q.get("min_normal_force", math.nan)
        what = f"min normal force {fmin:.3g} N < 0" if np.isfinite(fmin) else "a normal force <= 0"
        return f"uplift: {what} (the bilateral contact model is outside its validity)"
    return ""


def _point_from_shoot(problem, res: ShootingResult, method: str, note: str = "") -> OrbitPoint:
    mu = floquet_multipliers(res.monodromy)
    q = orbit_quantities(problem, res.f, res.X)
    note = "; ".join(n for n in (note, _uplift_note(q)) if n)
    return OrbitPoint(
        res.f,
        res.x0.copy(),
        method,
        True,
        res.iterations,
        res.residual,
        mu,
        res.n_steps,
        note,
        q,
        X=res.X,
    )


def uplift_probe(problem: PeriodicProblem, f: float, x0: np.ndarray) -> tuple[bool | None, str]:
    """Does a contact lift off within one period from ``x0`` (minimal coordinates)?

    Adaptive radau in the coordinates q (Baumgarte contacts, normal forces checked at every
    step), for points whose fixed-step period could not be integrated. Returns (True: a
    normal force reached zero, False: none did, None: radau failed too; a note saying which).
    """
    from .integrate import IntegrationError, UpliftError, solve

    P, _ = problem.at(f)
    t = np.linspace(0.0, 1.0 / f, 65)
    try:
        solve(P, problem.to_full(x0), t, method="radau", uplift="raise")
    except UpliftError as e:
        return True, f"radau probe from the period's start: uplift at t = {e.t:.4g} s"
    except IntegrationError as e:
        return None, f"radau probe from the period's start failed at t = {e.t:.4g} s: {e.reason}"
    return False, "radau probe from the period's start: no uplift over one period"


def _point_from_sweep(problem, sw: SweepResult, why: str) -> OrbitPoint:
    """A point from the stepped sweep; its 'residual' is the estimated distance to the steady
    state. Quantities are NaN when not even one period could be integrated."""
    mu = floquet_multipliers(sw.monodromy) if sw.monodromy is not None else np.zeros(0)
    probe = ""
    if sw.periods_done > 0:
        q = orbit_quantities(problem, sw.f, sw.X)
    else:
        keys = ("idr", "acc", "acc_floors", "x_iso", "v_slip_max", "min_normal_force")
        q = dict.fromkeys(keys, math.nan)
        q["stick_all_period"] = None
        q["uplift"] = None  # unknown unless the frame's probe decides
        if problem.prob == kp.PROB_FRAME:
            q["uplift"], probe = uplift_probe(problem, sw.f, sw.x0)
    note = "; ".join(
        n for n in (f"shooting failed: {why}", f"sweep: {sw.message}", probe, _uplift_note(q)) if n
    )
    return OrbitPoint(
        sw.f,
        sw.x0.copy(),
        "sweep",
        sw.steady,
        0,
        sw.estimate,
        mu,
        sw.n_steps,
        note,
        q,
        X=sw.X if sw.periods_done > 0 else None,
    )


def refined(disc: Discretisation, factor: float = REFINE_FACTOR) -> Discretisation:
    """The same discretisation with ``factor`` times the steps per period (``factor`` < 1:
    fewer; at least one step)."""
    if not (factor > 0 and math.isfinite(factor)):
        raise ValueError(f"factor: expected a positive number, got {factor!r}")
    return replace(
        disc,
        n_min=max(1, int(round(disc.n_min * factor))),
        dt_max=disc.dt_max / factor,
        n_max=max(1, int(round(disc.n_max * factor))),
    )


def _solve_point(problem, f, guesses, disc, tol, max_iter, fallback, method="shooting"):
    """Shooting from each guess in turn; if the period could not even be integrated, once more
    with ``REFINE_FACTOR`` times more steps; then the sweep from the first guess."""
    why = "no initial guess"
    integration_failed = False
    for g in guesses:
        res = shoot(problem, f, g, tol=tol, max_iter=max_iter, disc=disc)
        if res.converged:
            return _point_from_shoot(problem, res, method), res
        why = res.message
        integration_failed |= res.monodromy is None
    if integration_failed and guesses:
        disc = refined(disc)
        res = shoot(problem, f, guesses[0], tol=tol, max_iter=max_iter, disc=disc)
        if res.converged:
            note = f"{REFINE_FACTOR}x steps per period ({why})"
            return _point_from_shoot(problem, res, method, note), res
        why = f"{why}; with {REFINE_FACTOR}x steps: {res.message}"
    if not fallback:
        return None, None
    sw = steady_state_sweep(problem, f, guesses[0] if guesses else None, disc=disc)
    return _point_from_sweep(problem, sw, why), None


def _append(pts: list, pt: OrbitPoint, keep_orbits: bool) -> None:
    """Append ``pt``; the previous point's orbit is dropped unless ``keep_orbits``."""
    if pts and not keep_orbits:
        pts[-1].X = None
    pts.append(pt)


def warm_start(problem, f, x0, disc, periods=WARMUP_PERIODS):
    """A shooting guess at ``f``: ``periods`` periods integrated from ``x0`` (None: the static
    state), stopping early if a period cannot be integrated."""
    x = problem.x_ref.copy() if x0 is None else np.array(x0, dtype=float)
    for _ in range(periods):
        pm = period_map(problem, x, f, disc=disc, sens=False)
        if pm.status != kp.STATUS_OK:
            break
        x = pm.xT
    return x


def continue_sequential(
    problem: PeriodicProblem,
    freqs,
    x0: np.ndarray | None = None,
    *,
    disc: Discretisation | None = None,
    tol: float = SHOOT_TOL,
    max_iter: int = SHOOT_MAXIT,
    fallback: bool = True,
    progress=None,
    start: list[OrbitPoint] | None = None,
    keep_orbits: bool = False,
) -> Curve:
    """Seed's sequential continuation: shoot at each frequency from the previous solution.

    The guess is the secant extrapolation (in log f) of the last two points, then the last
    point itself; if both fail, the stepped sweep produces the point (``fallback``).
    ``start`` resumes a curve (points already computed are kept, frequencies up to the last
    one skipped). Only the last point keeps its orbit ``X`` unless ``keep_orbits``.
    """
    disc = disc or Discretisation()
    freqs = np.asarray(freqs, dtype=float)
    pts: list[OrbitPoint] = list(start or [])
    t0 = time.perf_counter()
    for f in freqs:
        if pts and f <= pts[-1].f * (1 + 1e-12):
            continue
        guesses = []
        if len(pts) >= 2:
            a, b = pts[-2], pts[-1]
            r = (math.log(f) - math.log(b.f)) / (math.log(b.f) - math.log(a.f))
            guesses.append(b.x0 + r * (b.x0 - a.x0))
        if pts:
            guesses.append(pts[-1].x0)
        else:
            guesses.append(warm_start(problem, f, x0, disc))
        tp = time.perf_counter()
        pt, _ = _solve_point(problem, f, guesses, disc, tol, max_iter, fallback)
        if pt is None:
            continue
        pt.quantities["wall_s"] = time.perf_counter() - tp
        _append(pts, pt, keep_orbits)
        if progress is not None:
            progress(pt, len(pts), len(freqs))
    curve = Curve(
        problem.amplitude,
        pts,
        detect_bifurcations(pts),
        {"continuation": "sequential", "wall_s": time.perf_counter() - t0},
    )
    return curve


def _tangent(Jx, Jp, W, t_prev):
    """Unit tangent of H(x, p) = 0 (scaled norm) oriented along ``t_prev``."""
    d = Jx.shape[0]
    Wf = np.concatenate([W, [1.0]])
    Aug = np.zeros((d + 1, d + 1))
    Aug[:d, :d] = Jx
    Aug[:d, d] = Jp
    Aug[d, :] = t_prev * Wf * Wf
    rhs = np.zeros(d + 1)
    rhs[d] = 1.0
    t = np.linalg.solve(Aug, rhs)
    t /= np.linalg.norm(Wf * t)
    if (t * Wf * Wf) @ t_prev < 0:
        t = -t
    return t


def continue_arclength(
    problem: PeriodicProblem,
    fmin: float,
    fmax: float,
    *,
    points: int = 150,
    x0: np.ndarray | None = None,
    disc: Discretisation | None = None,
    tol: float = SHOOT_TOL,
    max_iter: int = SHOOT_MAXIT,
    fallback: bool = True,
    progress=None,
    start: list[OrbitPoint] | None = None,
    state_weight: float = ARC_STATE_WEIGHT,
    keep_orbits: bool = False,
) -> Curve:
    """Pseudo-arclength continuation in ``(x0, p = log f)`` from ``fmin`` to ``fmax``.

    Unknowns are scaled per block by the orbit amplitude at the last point and the state by
    ``state_weight`` (AUTO's theta), so the step ``ds`` measures a weighted relative change of
    the orbit plus a change of log f: a small weight lets the steps follow log f where the
    curve is monotone in f (the isolated frame's orbits vary a lot with f) while folds, where
    dp/ds -> 0, are still passed. The step in log f is
    capped at ``log(fmax/fmin) / (points - 1)`` (at least ``points`` points on the curve);
    it grows after easy corrector solves and halves after failures; below ``ARC_DS_MIN`` the
    next frequency is taken by the stepped sweep and continuation restarts from it.
    """
    disc = disc or Discretisation()
    pmin, pmax = math.log(fmin), math.log(fmax)
    dp_max = (pmax - pmin) / max(points - 1, 1)
    t0 = time.perf_counter()
    pts: list[OrbitPoint] = list(start or [])
    d = problem.dim
    if not pts:
        xg = warm_start(problem, fmin, x0, disc)
        pt, res = _solve_point(problem, fmin, [xg], disc, tol, max_iter, fallback, "arclength")
        if pt is None:
            raise RuntimeError(f"no periodic solution found at f = {fmin:g} Hz")
        pt.s = 0.0
        _append(pts, pt, keep_orbits)
        if progress is not None:
            progress(pt, 1, points)
    s_acc = pts[-1].s if np.isfinite(pts[-1].s) else 0.0
    t_prev = np.zeros(d + 1)
    t_prev[d] = 1.0
    ds = dp_max
    max_steps = ARC_MAX_STEPS_FACTOR * points
    steps = 0
    need_restart = True  # tangent must be computed from scratch at the last point
    J_last = None
    while steps < max_steps:
        steps += 1
        last = pts[-1]
        p_last = math.log(last.f)
        if p_last >= pmax - 1e-12 or p_last < pmin - 0.5 * (pmax - pmin):
            break
        if last.X is None:  # resumed point: its orbit for the scaling
            last.X = period_map(problem, last.x0, last.f, disc=disc, sens=False, store=True).X
        amp = orbit_amplitudes(problem, last.X)
        W = state_weight * _weights(problem, amp)
        N = disc.steps(1.0 / last.f)
        if need_restart or J_last is None:
            res0 = shoot(problem, last.f, last.x0, tol=tol, max_iter=max_iter, disc=disc, n_steps=N)
            if not res0.converged:
                # continue from a sweep point: step on with the sweep
                f_next = min(math.exp(p_last + dp_max), fmax)
                pt, _ = _solve_point(
                    problem, f_next, [last.x0], disc, tol, max_iter, fallback, "arclength"
                )
                if pt is None:
                    break
                pt.s = s_acc = s_acc + abs(math.log(f_next) - p_last)
                _append(pts, pt, keep_orbits)
                if progress is not None:
                    progress(pt, len(pts), points)
                continue
            J_last = (res0.monodromy - np.eye(d), res0.dxdT * (-1.0 / last.f), res0.x0)
            need_restart = False
        Jx, Jp, xl = J_last
        tan = _tangent(Jx, Jp, W, t_prev)
        last.dlogf_ds = float(tan[d])
        # step size: cap the change of log f
        ds_cap = dp_max / max(abs(tan[d]), 1e-12)
        ds = min(ds, ds_cap, ARC_DS_MAX)
        tp = time.perf_counter()
        ok, msg, its = False, "", 0
        y0 = np.concatenate([xl, [p_last]])
        while ds >= ARC_DS_MIN:
            y_pred = y0 + ds * tan
            if y_pred[d] > pmax and tan[d] > 0:
                # last step: land on fmax exactly (natural-parameter corrector there)
                y_end = y0 + ((pmax - p_last) / tan[d]) * tan
                res = shoot(
                    problem, fmax, y_end[:d], tol=tol, max_iter=max_iter, disc=disc, n_steps=N
                )
                if res.converged:
                    pt = _point_from_shoot(problem, res, "arclength")
                    y = np.concatenate([res.x0, [pmax]])
                    s_acc += float(np.linalg.norm(np.concatenate([W, [1.0]]) * (y - y0)))
                    pt.s = s_acc
                    pt.quantities["wall_s"] = time.perf_counter() - tp
                    _append(pts, pt, keep_orbits)
                    if progress is not None:
                        progress(pt, len(pts), points)
                    ok = True
                    break
                msg = res.message
                ds *= ARC_SHRINK
                continue
            ok, y, res, its, rr, msg = _corrector(problem, y_pred, tan, W, N, disc, tol, ds)
            if ok:
                Jx_n = res.monodromy - np.eye(d)
                Jp_n = res.dxdT * (-1.0 / math.exp(y[d]))
                tan_new = _tangent(Jx_n, Jp_n, W, tan)
                Wf = np.concatenate([W, [1.0]])
                cosang = float((tan_new * Wf * Wf) @ tan)
                if cosang >= ARC_COS_MIN:
                    break
                ok = False
                turn = math.degrees(math.acos(max(-1.0, min(1.0, cosang))))
                msg = f"tangent turned by {turn:.0f} deg"
            ds *= ARC_SHRINK
        if ok and pts[-1].f >= fmax * (1 - 1e-12):
            break
        if not ok:
            # fallback: stepped sweep to the next frequency, then restart
            f_next = min(math.exp(p_last + dp_max), fmax)
            why = f"arclength corrector failed down to ds = {ARC_DS_MIN:.0e}: {msg}"
            if not fallback:
                break
            sw = steady_state_sweep(problem, f_next, last.x0, disc=disc)
            pt = _point_from_sweep(problem, sw, why)
            pt.s = s_acc = s_acc + abs(math.log(f_next) - p_last)
            pt.quantities["wall_s"] = time.perf_counter() - tp
            _append(pts, pt, keep_orbits)
            need_restart = True
            t_prev = np.zeros(d + 1)
            t_prev[d] = 1.0
            ds = dp_max
            if progress is not None:
                progress(pt, len(pts), points)
            continue
        pt = _point_from_shoot(problem, res, "arclength")
        pt.f = math.exp(y[d])
        s_acc += float(np.linalg.norm(np.concatenate([W, [1.0]]) * (y - y0)))
        pt.s = s_acc
        pt.dlogf_ds = float(tan_new[d])
        pt.quantities["wall_s"] = time.perf_counter() - tp
        _append(pts, pt, keep_orbits)
        if progress is not None:
            progress(pt, len(pts), points)
        J_last = (Jx_n, Jp_n, y[:d].copy())
        t_prev = tan_new
        ds = ds * ARC_GROW if its <= ARC_GOOD else ds
    curve = Curve(
        problem.amplitude,
        pts,
        detect_bifurcations(pts),
        {"continuation": "arclength", "wall_s": time.perf_counter() - t0, "steps": steps},
    )
    return curve


def _corrector(problem, y_pred, tan, W, N, disc, tol, ds):
    """Newton on [H(x, p); <t, y - y_pred>_W] = 0 (Keller's pseudo-arclength).

    Iterates that leave the ball of radius ``ARC_MAX_CORRECTION * ds`` around the predictor
    are rejected (the step is then halved): a converged point far away would be on another
    part of the curve.
    """
    d = problem.dim
    Wf = np.concatenate([W, [1.0]])
    Wf2 = Wf**2
    y = y_pred.copy()
    res = None
    msg = ""
    for it in range(ARC_MAXIT + 1):
        f = math.exp(y[d])
        pm, Wr, r = _evaluate(problem, y[:d], f, N, disc)
        if pm.status != kp.STATUS_OK:
            return False, y, None, it, np.inf, STATUS_MESSAGES[pm.status]
        H = pm.xT - y[:d]
        g = float((tan * Wf2) @ (y - y_pred))
        res = ShootingResult(f, y[:d].copy(), r <= tol, it, r, pm.monodromy, pm.dxdT, pm.X, N)
        if r <= tol and abs(g) <= 1e-6:
            return True, y, res, it, r, "converged"
        if it == ARC_MAXIT:
            break
        Aug = np.zeros((d + 1, d + 1))
        Aug[:d, :d] = pm.monodromy - np.eye(d)
        Aug[:d, d] = pm.dxdT * (-1.0 / f)
        Aug[d, :] = tan * Wf2
        try:
            dy = np.linalg.solve(Aug, -np.concatenate([H, [g]]))
        except np.linalg.LinAlgError:
            return False, y, None, it, r, "singular bordered Newton matrix"
        y = y + dy
        dist = float(np.linalg.norm(Wf * (y - y_pred)))
        if dist > ARC_MAX_CORRECTION * ds:
            return False, y, None, it + 1, r, f"corrector left the predictor by {dist / ds:.1f} ds"
    msg = f"no convergence in {ARC_MAXIT} corrector iterations (residual {r:.1e})"
    return False, y, res, ARC_MAXIT, r, msg


# ---- front door -----------------------------------------------------------------------------
def log_frequencies(fmin: float = 0.01, fmax: float = 10.0, points: int = 150) -> np.ndarray:
    return np.geomspace(fmin, fmax, points)


def frequency_response(
    system,
    amplitude: float,
    *,
    fmin: float = 0.01,
    fmax: float = 10.0,
    points: int = 150,
    continuation: str = "sequential",
    **options,
) -> Curve:
    """Periodic responses of an isolated ``system`` to ``amplitude sin(2 pi f t)``.

    ``continuation``: "sequential" (seed: ``points`` log-spaced frequencies, previous solution
    as the guess) or "arclength" (pseudo-arclength in (x0, log f), passes folds, at least
    ``points`` points). ``options`` go to :func:`continue_sequential` /
    :func:`continue_arclength` (``disc``, ``tol``, ``max_iter``, ``fallback``, ``progress``,
    ``start``, ...).
    """
    problem = frame_problem(system, amplitude)
    if continuation == "sequential":
        c = continue_sequential(problem, log_frequencies(fmin, fmax, points), **options)
    elif continuation == "arclength":
        c = continue_arclength(problem, fmin, fmax, points=points, **options)
    else:
        raise ValueError(
            f"continuation: expected 'sequential' or 'arclength', got {continuation!r}"
        )
    c.info["model"] = system.name
    return c


# ---- linear references ----------------------------------------------------------------------
def fixed_base_response(frame, amplitude: float, freqs, *, f_max: float = 5.0) -> dict:
    """Steady harmonic IDR and absolute floor acceleration of the fixed-base frame (linear).

    From python-control's frequency response of :func:`nsdyn.models.fixed_base_statespace`
    with the column-joint and level-node x displacements as outputs: a drift amplitude is
    ``A |H_top - H_bottom| / h``, an absolute acceleration ``A |1 - w^2 H|``.
    """
    from .metrics import output_dofs
    from .models import fixed_base_statespace
    from .system import build_system

    sysf = build_system(frame, fidelity="fixed", f_max=f_max)
    od = output_dofs(frame)
    jx = od["joints_x"]
    lev = od["levels_x"]
    dofs = np.concatenate([jx.ravel()] + [np.asarray(v) for v in lev])
    ss = fixed_base_statespace(sysf, dofs)
    freqs = np.asarray(freqs, dtype=float)
    w = 2 * np.pi * freqs
    H = np.stack([np.asarray(ss(1j * wk)).reshape(-1) for wk in w])  # (nf, n_out)
    nj = jx.size
    Hj = H[:, :nj].reshape(len(w), *jx.shape)
    drift = np.abs(np.diff(Hj, axis=1)) / od["heights"][None, :, None]
    idr = amplitude * drift.reshape(len(w), -1).max(axis=1)
    Hl = H[:, nj:]
    acc = amplitude * np.abs(1.0 - (w**2)[:, None] * Hl).max(axis=1)
    return {"f": freqs, "idr": idr, "acc": acc}
