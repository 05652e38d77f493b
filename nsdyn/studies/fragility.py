"""Lognormal fragility curves: maximum-likelihood fit on binary outcomes, confidence band.

The fragility of a limit state is

    P[EDP > limit | IM = x] = Φ((ln x − ln θ) / β)

(θ the median capacity in IM units, β the log-standard deviation). Writing it as a probit
regression ``P = Φ(a + b u)``, ``u = ln x``, ``a = −ln θ / β``, ``b = 1 / β``, the
log-likelihood of outcomes y_i ∈ {0, 1} (or of z_j exceedances in n_j runs at level x_j: the
"fit to exceedance fractions" of multiple-stripe analysis, the same likelihood grouped)

    ℓ(a, b) = Σ_j [ z_j ln Φ(η_j) + (n_j − z_j) ln Φ(−η_j) ],   η_j = a + b u_j

is maximised by Fisher scoring with the expected information

    I(a, b) = Σ_j n_j w_j [1, u_j]ᵀ[1, u_j],   w = φ(η)² / (Φ(η) Φ(−η)).

Cov(a, b) ≈ I⁻¹ at the estimate; the delta method gives the standard errors of ln θ and β
and the pointwise band ``Φ(η(x) ± z_{1−α/2} sd η(x))``, ``var η(x) = [1, ln x] Cov [1, ln x]ᵀ``.
Data that separate (every run below some level survives, every run above fails)
have no finite maximum: the fit refuses them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np
from scipy import special  # (not scipy.stats: half a second to import; norm.ppf is ndtri)

LEANING = "past_tip_over_at_end"  # a body's summary: not overturned by t_end, but falling
FALL_OUTCOMES = ("overturned", "toppled")  # the rocking/contact and cylinder outcome columns
MAX_ITER = 100  # Fisher-scoring iterations
STEP_TOL = 1e-10  # convergence: Newton step in (a, b), relative to 1 + |(a, b)|
MAX_B = 1e4  # b = 1/beta beyond this: the data separate perfectly (beta -> 0)
MIN_B = 1e-2  # b below this (beta > 100): the outcome does not rise with IM (beta -> inf)
CONFIDENCE = 0.95  # default level of the confidence band


@dataclass(frozen=True)
class LognormalFragility:
    """A fitted fragility curve and its uncertainty."""

    theta: float  # median IM at which P = 1/2
    beta: float  # log-standard deviation
    se_ln_theta: float  # standard error of ln theta
    se_beta: float  # standard error of beta
    cov_ab: np.ndarray  # (2, 2) covariance of the probit coefficients (a, b)
    n: int  # runs
    n_exceed: int  # runs past the limit
    log_likelihood: float

    def probability(self, x) -> np.ndarray:
        """P[EDP > limit | IM = x] at intensity measures ``x`` >= 0 (0 at 0)."""
        with np.errstate(divide="ignore"):  # (ln 0 = -inf: P = 0)
            u = np.log(_intensities(x))
        return special.ndtr((u - math.log(self.theta)) / self.beta)

    def band(self, x, confidence: float = CONFIDENCE) -> tuple[np.ndarray, np.ndarray]:
        """Pointwise (lower, upper) confidence band of the curve at ``x`` > 0, at the level
        ``confidence`` in (0, 1)."""
        if isinstance(confidence, bool) or not 0 < confidence < 1:
            raise ValueError(f"confidence: expected a level in (0, 1), got {confidence!r}")
        x = _intensities(x, positive=True)
        top = np.isposinf(x)  # (P = 1 there, band and all: it was NaN)
        u = np.log(np.where(top, 1.0, x))
        a, b = -math.log(self.theta) / self.beta, 1.0 / self.beta
        eta = a + b * u
        J = np.stack([np.ones_like(u), u], axis=-1)
        sd = np.sqrt(np.einsum("...i,ij,...j->...", J, self.cov_ab, J))
        zc = special.ndtri(0.5 + confidence / 2)
        lo, hi = special.ndtr(eta - zc * sd), special.ndtr(eta + zc * sd)
        return np.where(top, 1.0, lo)[()], np.where(top, 1.0, hi)[()]  # (a scalar for one)

    def as_dict(self) -> dict:
        """The scalar fields (all but ``cov_ab``)."""
        return {f.name: getattr(self, f.name) for f in fields(self) if f.name != "cov_ab"}


def _intensities(x, positive: bool = False) -> np.ndarray:
    """``x`` as floats, each >= 0 (> 0 with ``positive``); a ValueError otherwise (a negative
    IM gave NaN and a RuntimeWarning). NaN stays NaN, and P(inf) = 1."""
    a = np.asarray(x, dtype=float)
    if np.any(a <= 0 if positive else a < 0):
        raise ValueError(f"x: expected intensity measures {'>' if positive else '>='} 0, "
                         f"got {x!r}")  # fmt: skip
    return a


def _loglik(eta: np.ndarray, n: np.ndarray, z: np.ndarray) -> float:
    return float(np.sum(z * special.log_ndtr(eta) + (n - z) * special.log_ndtr(-eta)))


def fisher_information(a: float, b: float, im, n) -> np.ndarray:
    """Expected information of (a, b) for ``n`` runs at each IM level ``im``."""
    u = np.log(np.asarray(im, dtype=float))
    eta = a + b * u
    p, q = special.ndtr(eta), special.ndtr(-eta)
    phi = np.exp(-0.5 * eta**2) / math.sqrt(2 * math.pi)
    w = np.asarray(n, dtype=float) * phi**2 / np.maximum(p * q, 1e-300)
    X = np.stack([np.ones_like(u), u], axis=1)
    return X.T @ (w[:, None] * X)


def _per_level(x, n, z) -> str:
    """Each level with runs as "IM: exceeding/runs", for a message."""
    return ", ".join(f"{xi:g}: {zi:g}/{ni:g}" for xi, ni, zi in zip(x, n, z, strict=True) if ni > 0)


def fit_lognormal_counts(im, n_runs, n_exceed) -> LognormalFragility:
    """Maximum-likelihood fragility from ``n_exceed`` of ``n_runs`` past the limit at ``im``."""
    x = im_levels(im)  # (levels equal to 12 digits: one, as one outcome per run's)
    n = np.asarray(n_runs, dtype=float)
    z = np.asarray(n_exceed, dtype=float)
    if x.shape != n.shape or x.shape != z.shape or x.ndim != 1:
        raise ValueError("im, n_runs, n_exceed: expected 1-D arrays of one length")
    if not np.all(x > 0) or not np.all(np.isfinite(x)):
        raise ValueError("im: expected positive finite intensity measures")
    for name, c in (("n_runs", n), ("n_exceed", z)):  # (3.5 exceedances were fitted as 3)
        if not np.all(np.isfinite(c)) or np.any(c < 0) or np.any(c != np.round(c)):
            raise ValueError(f"{name}: expected whole counts >= 0, got {c.tolist()}")
    if np.any(z > n):
        raise ValueError("n_exceed: expected 0 <= n_exceed <= n_runs")
    N, Z = int(n.sum()), int(z.sum())
    if Z == 0 or Z == N:
        raise ValueError(f"fragility: {Z} of {N} runs exceed the limit (or, for a true/false "
                         "outcome, are true); need some of each")  # fmt: skip
    u = np.log(x)
    if np.unique(x[n > 0]).size < 2:  # (it was "the outcomes separate perfectly")
        raise ValueError(f"fragility: every run is at one IM level ({x[n > 0][0]:g}); a curve "
                         "needs runs at two levels or more")  # fmt: skip
    if u[z < n].max() <= u[z > 0].min():  # (quasi-)complete separation: no finite maximum
        lo, hi = float(x[z < n].max()), float(x[z > 0].min())
        where = (f"every run at IM <= {lo:g} survives and every run at IM >= {hi:g} exceeds"
                 if lo < hi else f"no run below IM = {lo:g} exceeds and no run above it "
                 "survives; at it, some of each")  # fmt: skip
        counts = _per_level(x, n, z)
        raise ValueError(
            f"fragility: the outcomes separate in IM ({where}; exceeding per "
            f"level {counts}): beta -> 0, no finite maximum-likelihood fit"
        )

    # start: a moment estimate (theta at the weighted median of u, beta from its spread)
    sd = math.sqrt(max(float(np.average((u - np.average(u, weights=n)) ** 2, weights=n)), 1e-6))
    frac = np.clip(Z / N, 0.05, 0.95)
    b = 1.0 / sd
    a = special.ndtri(frac) - b * float(np.average(u, weights=n))
    ll = _loglik(a + b * u, n, z)
    for _ in range(MAX_ITER):
        eta = a + b * u
        p, q = special.ndtr(eta), special.ndtr(-eta)
        phi = np.exp(-0.5 * eta**2) / math.sqrt(2 * math.pi)
        r = phi * (z - n * p) / np.maximum(p * q, 1e-300)
        score = np.array([r.sum(), (r * u).sum()])
        try:
            step = np.linalg.solve(fisher_information(a, b, x, n), score)
        except np.linalg.LinAlgError:
            raise ValueError(
                "fragility: singular information (too few distinct IM levels)"
            ) from None
        t = 1.0
        while t > 1e-8:  # halve until the likelihood does not drop
            a1, b1 = a + t * step[0], b + t * step[1]
            ll1 = _loglik(a1 + b1 * u, n, z)
            if b1 > 0 and ll1 >= ll - 1e-12 * abs(ll):
                break
            t /= 2
        a, b, ll = a1, b1, ll1
        if b > MAX_B:
            raise ValueError(
                "fragility: the outcomes separate in IM (beta -> 0); "
                "no finite maximum-likelihood fit"
            )
        if t * np.linalg.norm(step) < STEP_TOL * (1 + math.hypot(a, b)):
            break
    else:
        if b >= 10 * MIN_B:  # (a share falling with IM creeps towards b = 0: said below)
            raise ValueError(f"fragility: Fisher scoring did not converge in {MAX_ITER} "
                             "iterations")  # fmt: skip
        b = 0.0
    if b < MIN_B:  # (beta 1e16 and its standard error 4e32 were printed as a fit)
        counts = _per_level(x, n, z)
        raise ValueError(f"fragility: the share of runs exceeding does not rise with IM (beta "
                         f"-> inf; exceeding per level {counts}): no fragility curve; the "
                         "outcome follows another parameter, or IM is not the one")  # fmt: skip
    cov = np.linalg.inv(fisher_information(a, b, x, n))
    # ln theta = -a/b, beta = 1/b: gradients for the delta method
    g_lt = np.array([-1.0 / b, a / b**2])
    g_beta = np.array([0.0, -1.0 / b**2])
    return LognormalFragility(
        theta=math.exp(-a / b),
        beta=1.0 / b,
        se_ln_theta=float(math.sqrt(g_lt @ cov @ g_lt)),
        se_beta=float(math.sqrt(g_beta @ cov @ g_beta)),
        cov_ab=cov,
        n=N,
        n_exceed=Z,
        log_likelihood=ll,
    )


def im_levels(x: np.ndarray) -> np.ndarray:
    """``x`` with values equal to 12 significant digits made one (a scaled record's PGA read
    6.000000000000001 beside 6.0: two levels, and a fit of three levels was refused as of
    too few)."""
    a = np.asarray(x, dtype=float)
    return np.array([float(f"{v:.12g}") for v in a.ravel()]).reshape(a.shape)


def fit_lognormal(im, exceeded) -> LognormalFragility:
    """Maximum-likelihood fragility from one outcome per run (``exceeded``: bool per ``im``),
    IM values equal to 12 digits counted as one level (:func:`im_levels`)."""
    x = im_levels(im)
    y = np.asarray(exceeded, dtype=bool)
    if x.ndim != 1:
        raise ValueError(f"im: expected a 1-D array (one value per run), got shape {x.shape}")
    if x.shape != y.shape:
        raise ValueError(f"im {x.shape} and exceeded {y.shape}: expected one outcome per run")
    levels, inv = np.unique(x, return_inverse=True)
    n = np.bincount(inv, minlength=levels.size)
    z = np.bincount(inv, weights=y.astype(float), minlength=levels.size)
    return fit_lognormal_counts(levels, n, z)


def exceedance_fractions(im, exceeded, n_bins: int = 8) -> tuple[np.ndarray, ...]:
    """Observed (IM, fraction exceeding, runs) in ``n_bins`` log-spaced IM bins (for plots);
    distinct IM levels (stripes) are kept as they are when there are at most ``n_bins``."""
    x = im_levels(im)
    y = np.asarray(exceeded, dtype=float)
    levels = np.unique(x)
    if levels.size <= n_bins:
        inv = np.searchsorted(levels, x)
        centres = levels
    else:
        edges = np.geomspace(x.min(), x.max() * (1 + 1e-12), n_bins + 1)
        inv = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, n_bins - 1)
        centres = np.sqrt(edges[:-1] * edges[1:])
    n = np.bincount(inv, minlength=centres.size)
    z = np.bincount(inv, weights=y, minlength=centres.size)
    m = n > 0
    return centres[m], z[m] / n[m], n[m]


def check_spec(src: str, f: dict, numeric_edp: bool) -> None:
    """The ``limits`` and ``confidence`` of an ``[analysis.fragility]`` table ``f`` of the
    study file ``src`` (SceneError naming the field): without limits the EDP must be a
    true/false outcome, so a number (``numeric_edp``: a known numeric result, or a first
    run's value) is refused before the runs, not after all of them."""
    from nsdyn.models.scenefile import SceneError, number
    from nsdyn.studies.table import once

    if "limits" not in f and numeric_edp:
        raise SceneError(f"{src}: analysis.fragility.limits: missing, and {f['edp']!r} is a "
                         "number, not a true/false outcome: give the limits its exceedance "
                         "is counted at, e.g. limits = [0.005, 0.01]")  # fmt: skip
    lim = f.get("limits", [])
    if not isinstance(lim, list) or ("limits" in f and not lim):  # ([]: no limit at all)
        raise SceneError(f"{src}: analysis.fragility.limits: expected a list of numbers "
                         f"(one curve each), got {lim!r}")  # fmt: skip
    for i, v in enumerate(lim):
        number(src, f"analysis.fragility.limits[{i}]", v)
    once(src, "analysis.fragility.limits", lim)
    c = number(src, "analysis.fragility.confidence", f.get("confidence", CONFIDENCE))
    if not c < 1:
        raise SceneError(f"{src}: analysis.fragility.confidence: expected in (0, 1)")


def failure_note(counted: dict) -> str:
    """``3 failed runs (uplift) counted as exceedance`` (empty without such failures)."""
    n = sum(counted.values())
    if not n:
        return ""
    return f"{n} failed runs ({', '.join(sorted(counted))}) counted as exceedance"


def leaning_note(edp_name: str, table) -> str:
    """The note on the successful runs of ``table`` (:class:`~nsdyn.studies.table.Table`) a
    fragility of ``edp_name`` (an overturning outcome, 0/1) counts as standing that end leaning
    past their tip-over angle (the LEANING column, when kept): they are falling when the run
    stops, and a longer motion.t_end may count them as overturned (empty for other EDPs or
    without such runs)."""
    if edp_name not in FALL_OUTCOMES:
        return ""
    ok = np.array([r.get("status") == "ok" for r in table.rows], dtype=bool)
    edp, lean = (table.column(n, False)[ok] for n in (edp_name, LEANING))
    n = int(np.sum((edp == 0.0) & (lean == 1.0)))
    if not n:
        return ""
    return (f"{n} run{'s' * (n != 1)} counted as not {edp_name} end{'s' * (n == 1)} leaning "
            f"past the tip-over angle and falling ({LEANING}): a longer motion.t_end shows "
            "whether they fall")  # fmt: skip
