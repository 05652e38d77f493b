"""Write the bundled synthetic ground motions into ``records/`` (deterministic to round-off).

The generators are seeded; what may differ between machines and library versions is the
round-off of ``exp``, of fused multiply-adds and of BLAS's summation order (``--check``
compares against a bound from an error analysis of the recipe, :func:`machine_difference`;
tens of ulp of the PGA), so a rerun can rewrite the files' last digits: use ``--check``.

Run from any folder (the paths are the script's own)::

    python examples/make_records.py            # writes records/*.csv
    python examples/make_records.py --check    # regenerates in memory and compares with records/

Each record is a synthetic motion of seed 000 §4.1 (modulated white noise) or its Kanai–Tajimi
variant, with a fixed seed, scaled to a horizontal PGA of 3 m/s² (the vertical component with the
same factor). ``main()`` returns the motions so that tests can compare them with the files.

A record listed in ``SECOND_HORIZONTAL`` also gets a second horizontal component a_y in
``records/<stem>-y.txt``: the same generator and parameters with its own seed (an independent
sample of the same process, without vertical), times the *same* scale factor as the first
component, so both horizontal components have the same intensity. ``make_y(stem)`` makes it;
``read_motion3(stem)`` reads a_x, a_y and the vertical together.
"""

import dataclasses
from pathlib import Path

import numpy as np

from nsdyn.ground import (
    GroundMotion,
    kanai_tajimi,
    modulated_white_noise,
    shinozuka_envelope,
    write_motion,
)

Y_SUFFIX = "-y.txt"  # the companion file of the second horizontal component

COMMAND = "python examples/make_records.py"
PGA = 3.0  # [m/s²] the transient study's PGA (seed 004 §5)
RECORDS_DIR = Path(__file__).resolve().parents[1] / "records"

# file stem -> (generator, keyword arguments incl. seed); every value is written to the header
RECIPES = {
    "synthetic-wn-40s": (
        modulated_white_noise,
        dict(duration=40.0, S0=1.25e-4, dt_ord=0.05, dt=0.01, vertical_ratio=2 / 3, seed=40001),
    ),
    "synthetic-kt-20s": (
        kanai_tajimi,
        dict(
            duration=20.0,
            omega_g=15.6,
            zeta_g=0.6,
            S0=1.25e-4,
            dt=0.01,
            modulate=True,
            vertical_ratio=2 / 3,
            seed=20002,
        ),
    ),
}

# file stem -> seed of its second horizontal component (same recipe otherwise, no vertical)
SECOND_HORIZONTAL = {"synthetic-wn-40s": 40003, "synthetic-kt-20s": 20004}


def make(stem: str) -> GroundMotion:
    """The bundled record ``stem``, generated afresh."""
    generator, kwargs = RECIPES[stem]
    motion = generator(name=stem, **kwargs).scaled_to_pga(PGA)
    return dataclasses.replace(motion, meta={**motion.meta, "command": COMMAND, "pga_target": PGA})


def make_y(stem: str, x: GroundMotion | None = None) -> GroundMotion:
    """The second horizontal component of ``stem``: its recipe with the seed
    ``SECOND_HORIZONTAL[stem]`` and no vertical, times the first component's scale factor."""
    generator, kwargs = RECIPES[stem]
    x = make(stem) if x is None else x
    factor = x.meta["scale_factor"]
    seed = SECOND_HORIZONTAL[stem]
    y = generator(name=f"{stem}-y", **{**kwargs, "vertical_ratio": None, "seed": seed})
    meta = {
        **y.meta,
        "command": COMMAND,
        "scale_factor": factor,
        "component": f"y, the second horizontal component of {stem}",
    }
    return dataclasses.replace(y, a_hor=y.a_hor * factor, meta=meta)


def main(out_dir: Path | None = RECORDS_DIR, write: bool = True) -> dict[str, GroundMotion]:
    """Generate every bundled record; write ``<out_dir>/<stem>.csv`` (and the second horizontal
    components ``<stem>-y.txt``) when ``write``. Returns the records of ``RECIPES``."""
    motions = {stem: make(stem) for stem in RECIPES}
    if write:
        out_dir = Path(out_dir)
        out_dir.mkdir(parents=True, exist_ok=True)
        for stem, motion in motions.items():
            seed = RECIPES[stem][1]["seed"]
            write_motion(motion, out_dir / f"{stem}.csv", command=COMMAND, seed=seed)
        for stem, seed in SECOND_HORIZONTAL.items():
            y = make_y(stem, motions[stem])
            write_motion(y, out_dir / f"{stem}{Y_SUFFIX}", command=COMMAND, seed=seed)
    return motions


U = np.finfo(float).eps / 2  # unit round-off of float64
EXP_ULPS = 4  # assumed accuracy of any exp implementation (libm, numpy's SIMD paths): < 4 ulp
DENSE_ROUNDOFF = 4**3  # BLAS/LAPACK on the 4x4 Van Loan matrix: results within n³ u of their norm


def _kt_filter(kw):
    """The Kanai–Tajimi recipe's two discrete filters B_j(q)/A(q) (one per input of the Van
    Loan discretisation), built as the generator builds them, and its number of samples."""
    from scipy import linalg, signal

    wg, zg, S0, dt = kw["omega_g"], kw["zeta_g"], kw["S0"], kw["dt"]
    A = np.array([[0.0, 1.0], [-(wg**2), -2.0 * zg * wg]])
    Qc = 2.0 * np.pi * S0 * np.array([[0.0, 0.0], [0.0, 1.0]])
    F = linalg.expm(np.block([[-A, Qc], [np.zeros((2, 2)), A.T]]) * dt)
    Phi = F[2:, 2:].T
    Qd = Phi @ F[:2, 2:]
    L = linalg.cholesky(0.5 * (Qd + Qd.T), lower=True)
    C = np.array([[-(wg**2), -2.0 * zg * wg]])
    nums = [signal.ss2tf(Phi, L, C, np.zeros((1, 2)), input=j)[0][0] for j in range(2)]
    den = signal.ss2tf(Phi, L, C, np.zeros((1, 2)), input=0)[1]
    n = int(round(kw["duration"] / dt)) + 1
    return nums, den, int(np.ceil(30.0 / (zg * wg * dt))) + n


def machine_difference(stem: str) -> dict:
    """Largest difference [m/s²] between this recipe's record made on two IEEE machines, per
    component (hor, ver), by a first-order error analysis of the recipe.

    Basic operations (+ − × ÷ √) are correctly rounded, so bit-identical on every machine;
    what may differ is (a) exp (not correctly rounded): each machine within EXP_ULPS ulp of
    the exact value; (b) compiled loops that contract a·b + c into one fused multiply-add
    (np.interp, lfilter's recursion): one rounding fewer, at most u |a·b| per contraction;
    (c) BLAS/LAPACK (matrix exponential, Cholesky, eigenvalues behind the filter): other
    summation orders, each result within DENSE_ROUNDOFF·u of its norm. With y the stationary
    sample (ordinates or filter output) and p = max |G y| the peak before scaling:

    - envelope G = 4 (e^(−t/4) − e^(−t/2)), e ≤ 1: |ΔG| ≤ 4·2·(2·EXP_ULPS·u), so |Δ(G y)| ≤
      |ΔG| max|y| + |Δy| (the product itself is correctly rounded);
    - white noise, linear interpolation y = w_j + s (t − t_j): |Δy| ≤ u (|w_j| + |w_j+1|);
    - Kanai–Tajimi, y = Σ_j B_j(q)/A(q) z_j (direct form): a perturbation e_k of the recursion
      at step k reaches y through the impulse response g of 1/A(q), so |Δy| ≤ ‖g‖₁ max|e|,
      with |e| ≤ Σ_j ‖ΔB_j‖₁ max|z_j| + ‖ΔA‖₁ max|y| (coefficients, (c)) + u (Σ_j ‖B_j‖₁
      max|z_j| + ‖A‖₁ max|y|) (one contraction per term, (b));
    - scaling by PGA / p: p is one of the ordinates, so the factor moves by at most
      max|Δ(G y_hor)| / p relative, and |Δa| ≤ (PGA / p) (|Δ(G y)| + |G y| max|Δ(G y_hor)| / p).
    """
    generator, kw = RECIPES[stem]
    pga = PGA
    stationary = generator(name=stem, **{**kw, "modulate": False})
    r = kw["vertical_ratio"]
    y = {"hor": stationary.a_hor, "ver": stationary.a_ver / r}
    dG = 4.0 * 2.0 * 2.0 * EXP_ULPS * U
    if "omega_g" in kw:
        from scipy import signal

        nums, den, n_all = _kt_filter(kw)
        impulse = np.zeros(n_all)
        impulse[0] = 1.0
        g1 = np.abs(signal.lfilter([1.0], den, impulse)).sum()
        z = np.random.default_rng(kw["seed"]).standard_normal((2, n_all, 2))  # hor, ver draws
        dy = {}
        for c, zc in zip(("hor", "ver"), z, strict=True):
            # max|y| over the warm-up too: y starts from rest and is stationary, so the kept
            # part's maximum is taken with a margin of 2
            ymax = 2.0 * np.abs(y[c]).max()
            zmax = np.abs(zc).max(axis=0)
            terms = sum(np.abs(b).sum() * zm for b, zm in zip(nums, zmax, strict=True))
            terms += np.abs(den).sum() * ymax
            dy[c] = g1 * (DENSE_ROUNDOFF * U + 2 * U) * terms
    else:
        w = {c: np.abs(y[c]).max() for c in y}  # the ordinates are samples of y
        dy = {c: 2.0 * U * w[c] for c in y}
    G = shinozuka_envelope(stationary.t)
    p = np.abs(G * y["hor"]).max()
    dGy = {c: dG * np.abs(y[c]).max() + dy[c] + U * np.abs(G * y[c]).max() for c in y}
    out = {}
    for c, factor in (("hor", 1.0), ("ver", r)):
        peak_c = np.abs(G * y[c]).max()
        out[c] = factor * (pga / p) * (dGy[c] + peak_c * dGy["hor"] / p)
    return out


if __name__ == "__main__":
    import argparse

    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument(
        "--check", action="store_true", help="regenerate and compare with records/ (no writing)"
    )
    if ap.parse_args().check:
        from nsdyn.ground import read_motion

        for stem, motion in main(write=False).items():
            stored = read_motion(RECORDS_DIR / f"{stem}.csv")
            # what two IEEE machines may differ by (the file format round-trips bit for bit)
            tol = machine_difference(stem)
            dev = {"hor": np.max(np.abs(stored.a_hor - motion.a_hor)),
                   "ver": np.max(np.abs(stored.a_ver - motion.a_ver))}  # fmt: skip
            ok = all(dev[c] <= tol[c] for c in dev)
            ulp = max(dev.values()) / np.spacing(stored.pga)
            verdict = "identical" if ulp == 0 else f"within {ulp:.0f} ulp of the PGA"
            print(f"{stem}: {verdict if ok else 'DIFFERS'} (bound {tol['hor']:.2g} m/s²)")
            if stem in SECOND_HORIZONTAL:
                # (the x component's bound: the same process, length and scale factor)
                y_stored = read_motion(RECORDS_DIR / f"{stem}{Y_SUFFIX}")
                dev = np.max(np.abs(y_stored.a_hor - make_y(stem, motion).a_hor))
                verdict = (
                    "identical" if dev == 0 else f"within {dev / np.spacing(stored.pga):.0f} ulp"
                )
                print(f"{stem}{Y_SUFFIX}: {verdict if dev <= tol['hor'] else 'DIFFERS'}")
    else:
        for stem, motion in main().items():
            print(f"{RECORDS_DIR / (stem + '.csv')}: {motion}")
