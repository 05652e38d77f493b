"""The bundled records' second horizontal components: reproducible, and independent of the first.

Sources: the recipes of examples/make_records.py and records/README.md (generator, parameters,
seed), seed 000 §4.1 for the modulated white noise and the Kanai–Tajimi filter of
nsdyn.ground.synthesis (the formulas in its module docstring).

Reproducibility bound (first-order error analysis of the recipe; u = 2⁻⁵³). Basic operations
are correctly rounded, so two IEEE machines differ only where (a) exp is not correctly rounded
(each within EXP_ULPS ulp), (b) a compiled loop contracts a·b + c into one fused multiply-add
(one rounding fewer: at most u|a·b|), (c) dense linear algebra (BLAS/LAPACK on the 4×4 Van Loan
matrix) sums in another order (each result within DENSE_ROUNDOFF·u of its norm). With Y the
stationary sample (modulate=False), G = 4(e^(−t/4) − e^(−t/2)) ≤ 1 and c the scale factor:

* |ΔG| ≤ 4 (2·2 EXP_ULPS u + 2u G/4) ≤ (16 EXP_ULPS + 2) u (two exps of values ≤ 1, whose
  ulp is ≤ u, on two machines; the rounded difference moves by at most the input change plus
  one rounding);
* white noise, Y = w_j + s (t − t_j): |ΔY| ≤ u (|w_j| + |w_j+1|) ≤ 2u max|w| (b);
* Kanai–Tajimi, y⁽ʲ⁾ = B_j(q)/A(q) z_j by the direct-form recursion: a perturbation e_k of
  step k reaches y⁽ʲ⁾ through the impulse response g of 1/A(q), so |Δy⁽ʲ⁾| ≤ ‖g‖₁ max|e|,
  |e| ≤ (DENSE_ROUNDOFF + 1) u (‖B_j‖₁ max|z_j| + ‖A‖₁ max|y⁽ʲ⁾|) ((c) on the coefficients,
  (b) on each product), and Y = y⁽⁰⁾ + y⁽¹⁾;
* the product G·Y: |Δ(GY)| ≤ |ΔG| max|Y| + max|G ΔY| + 2u max|GY| =: D;
* c = PGA / p_x with p_x = max|G Y_x| (the first component's peak): Δc/c ≤ D_x/p_x + 2u;
* a_y = c·(G Y_y): |Δa_y| ≤ c D_y + max|a_y| (D_x/p_x + 4u).

Independence (exact conditional distribution): a_y = c G Y_y with Y_y a zero-mean Gaussian
process independent of a_x, so given a_x the cross sum S = Σ_k a_x,k a_y,k is Gaussian with
mean 0 and variance c² Σ_jk v_j v_k Cov(Y_j, Y_k), v = G a_x. For the white noise,
Y = L w with w iid N(0, σ²), σ² = 2π S0/Δ, L the linear-interpolation weights:
Var = c² σ² ‖Lᵀ v‖². For Kanai–Tajimi, Y samples the stationary process with autocovariance
R(τ) = C e^(Aτ) P Cᵀ, A P + P Aᵀ + 2π S0 B Bᵀ = 0 (the filter's state space).
z = S/√Var is N(0, 1) under independence; the test requires |z| ≤ Z_MAX = 4.5, which an
independent pair fails with probability 6.8e-6. A modulated record of 20–40 s has few
independent degrees of freedom: for these records √Var / √(Σa_x² Σa_y²) ≈ 0.09, so the sample
correlation coefficient of an independent pair scatters by about ±0.09 (the bound allows
|r| ≲ 0.4; the bundled pairs have r = −0.14 and +0.05, i.e. z = −1.6 and +0.5).
"""

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

from nsdyn.ground import read_motion, read_motion3, shinozuka_envelope

REPO = Path(__file__).resolve().parents[2]
U = np.finfo(float).eps / 2
EXP_ULPS = 4  # assumed accuracy of any exp implementation (libm, numpy's SIMD paths): < 4 ulp
DENSE_ROUNDOFF = 4**3  # BLAS/LAPACK on the 4×4 Van Loan matrix: results within n³ u of norm
Z_MAX = 4.5
KT_WARMUP_DECAYS = 30.0  # the generator's warm-up, in time constants 1/(ζ_g ω_g)


@pytest.fixture(scope="module")
def recipes():
    spec = importlib.util.spec_from_file_location("make_records", REPO / "examples/make_records.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _kt_matrices(kw):
    wg, zg, S0 = kw["omega_g"], kw["zeta_g"], kw["S0"]
    A = np.array([[0.0, 1.0], [-(wg**2), -2.0 * zg * wg]])
    B = np.array([[0.0], [-1.0]])
    C = np.array([[-(wg**2), -2.0 * zg * wg]])
    return A, B, C, 2.0 * math.pi * S0 * (B @ B.T)


def _kt_filters(kw):
    """The exact (Van Loan) discretisation of the Kanai–Tajimi filter as two direct-form
    filters B_j(q)/A(q), one per white-noise input, and the warm-up length."""
    from scipy import linalg, signal

    A, _, C, Qc = _kt_matrices(kw)
    dt = kw["dt"]
    F = linalg.expm(np.block([[-A, Qc], [np.zeros((2, 2)), A.T]]) * dt)
    Phi = F[2:, 2:].T
    Qd = Phi @ F[:2, 2:]
    L = linalg.cholesky(0.5 * (Qd + Qd.T), lower=True)
    tfs = [signal.ss2tf(Phi, L, C, np.zeros((1, 2)), input=j) for j in range(2)]
    n_warm = int(math.ceil(KT_WARMUP_DECAYS / (kw["zeta_g"] * kw["omega_g"] * dt)))
    return [num[0] for num, _ in tfs], tfs[0][1], n_warm


def _stationary_error(generator, kw) -> tuple[np.ndarray, float]:
    """(Y, bound on |ΔY|) of the recipe's stationary horizontal sample."""
    Y = generator(**{**kw, "modulate": False, "vertical_ratio": None}).a_hor
    if "omega_g" not in kw:
        ratio = kw["dt_ord"] / kw["dt"]
        assert abs(ratio - round(ratio)) < 1e-9  # every ordinate is a sample: max|w| = max|Y|
        return Y, 2.0 * U * np.abs(Y).max()
    from scipy import signal

    nums, den, n_warm = _kt_filters(kw)
    z = np.random.default_rng(kw["seed"]).standard_normal((n_warm + Y.size, 2))  # first draws
    impulse = np.zeros(n_warm + Y.size)
    impulse[0] = 1.0
    g1 = np.abs(signal.lfilter([1.0], den, impulse)).sum()
    dY = 0.0
    for j, num in enumerate(nums):
        yj = signal.lfilter(num, den, z[:, j])
        e = (
            (DENSE_ROUNDOFF + 1)
            * U
            * (np.abs(num).sum() * np.abs(z[:, j]).max() + np.abs(den).sum() * np.abs(yj).max())
        )
        dY += g1 * e
    return Y, dY


def _D(Y: np.ndarray, dY: float, G: np.ndarray) -> float:
    dG = (16 * EXP_ULPS + 2) * U
    return dG * np.abs(Y).max() + G.max() * dY + 2 * U * np.abs(G * Y).max()


@pytest.mark.parametrize("stem", ["synthetic-wn-40s", "synthetic-kt-20s"])
def test_second_horizontal_component_is_reproducible(recipes, stem):
    generator, kw = recipes.RECIPES[stem]
    seed_y = recipes.SECOND_HORIZONTAL[stem]
    stored = read_motion(REPO / "records" / f"{stem}{recipes.Y_SUFFIX}")
    made = recipes.make_y(stem)
    assert stored.meta["seed"] == seed_y and stored.n == made.n and stored.dt == made.dt
    Yx, dYx = _stationary_error(generator, kw)
    Yy, dYy = _stationary_error(generator, {**kw, "seed": seed_y})
    G = shinozuka_envelope(stored.t)
    p_x = np.abs(G * Yx).max()
    c = recipes.PGA / p_x
    Dx, Dy = _D(Yx, dYx, G), _D(Yy, dYy, G)
    bound = c * Dy + np.abs(stored.a_hor).max() * (Dx / p_x + 4 * U)
    assert np.abs(stored.a_hor - made.a_hor).max() <= bound, bound
    # the stored factor is the first component's: its own peak is not the target PGA
    assert stored.meta["scale_factor"] == pytest.approx(c, rel=Dx / p_x + 4 * U)
    text = (REPO / "records" / "README.md").read_text(encoding="utf-8")
    assert f"`{stem}{recipes.Y_SUFFIX}`" in text and str(seed_y) in text


def _conditional_sd_white_noise(v: np.ndarray, kw, c: float) -> float:
    ratio = int(round(kw["dt_ord"] / kw["dt"]))
    k = np.arange(v.size)
    i, lam = k // ratio, (k % ratio) / ratio
    g = np.zeros(i.max() + 2)
    np.add.at(g, i, (1.0 - lam) * v)
    np.add.at(g, i + 1, lam * v)
    sigma2 = 2.0 * math.pi * kw["S0"] / kw["dt_ord"]
    return c * math.sqrt(sigma2) * np.linalg.norm(g)


def _conditional_sd_kanai_tajimi(v: np.ndarray, kw, c: float) -> float:
    from scipy import linalg

    A, _, C, Qc = _kt_matrices(kw)
    P = linalg.solve_continuous_lyapunov(A, -Qc)
    Phi = linalg.expm(A * kw["dt"])
    R = np.empty(v.size)
    s = P @ C.T
    for m in range(v.size):
        R[m] = (C @ s)[0, 0]
        s = Phi @ s
    return c * math.sqrt(v @ linalg.toeplitz(R) @ v)


@pytest.mark.parametrize("stem", ["synthetic-wn-40s", "synthetic-kt-20s"])
def test_the_two_horizontal_components_are_uncorrelated(recipes, stem):
    _, kw = recipes.RECIPES[stem]
    m = read_motion3(stem)
    c = read_motion(REPO / "records" / f"{stem}{recipes.Y_SUFFIX}").meta["scale_factor"]
    v = shinozuka_envelope(m.t) * m.ax
    S = float(m.ax @ m.ay)
    if "omega_g" in kw:
        sd = _conditional_sd_kanai_tajimi(v, kw, c)
    else:
        sd = _conditional_sd_white_noise(v, kw, c)
    z = S / sd
    assert abs(z) <= Z_MAX, z
    # the statistic sees a dependent pair: a copy of a_x (correlation 1) lies far outside
    assert float(m.ax @ m.ax) / sd > 2 * Z_MAX
