"""Bonded vs tensionless vs fixed base over many simulated earthquakes, as distributions.

For each seed number one three-component earthquake (the source study's modulated white noise)
drives the three foundation cases; the peaks per run (tilt, uplift ratio 1 − A/πr², rim lift,
base shear, overturning moment, wall stresses σ₁, σ₃, τ_max over the points A–E) are collected
and summarised by median and percentiles. Work is cut into batches of seeds, each a task for any
``concurrent.futures.Executor`` (a local process pool by default).
"""

from __future__ import annotations

import os
import time
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import asdict

import numpy as np

from nsdyn._checks import expect, whole
from nsdyn.models.cylinder.design import _P
from nsdyn.models.cylinder.params import CylinderParams
from nsdyn.models.cylinder.simulate import EQ_DT, EQ_DURATION, earthquake, simulate
from nsdyn.models.cylinder.stresses import peak_stresses

CASES = ("tensionless", "bonded", "fixed")  # foundation cases compared
PERCENTILES = (5, 16, 50, 84, 95)  # summary percentiles
BATCH = 8  # earthquakes per task
METRICS = ("tilt", "uplift", "rim_lift", "shear", "overturning", "slip", "sigma_1", "sigma_3",
           "tau_max")  # fmt: skip


def run_batch(
    params: dict,
    seeds: list[int],
    duration: float = EQ_DURATION,
    dt: float = EQ_DT,
    s0_units: str = "g2s",
    z_s: float | None = None,
    cases: tuple[str, ...] = CASES,
) -> list[dict]:
    """Rows {seed, case, wall_s, toppled, <metric>: peak} for every seed and case (a task)."""
    base = CylinderParams(**params)
    rows = []
    for seed in seeds:
        dt_, ag = earthquake(int(seed), duration, dt, s0_units=s0_units)
        for case in cases:
            tic = time.perf_counter()
            mu = None if case == "fixed" else base.mu  # a fixed base cannot slide
            res = simulate(base.with_(foundation=case, mu=mu), ag, dt_)
            wall = time.perf_counter() - tic
            ps = peak_stresses(res, z_s)
            rows.append(
                {
                    "seed": int(seed),
                    "case": case,
                    "wall_s": wall,
                    "toppled": res.toppled_at is not None,
                    "tilt": float(res.tilt.max()),
                    "uplift": float(1.0 - res.contact_fraction.min()),
                    "rim_lift": float(max(res.rim_lift.max(), 0.0)),
                    "shear": float(np.hypot(*res.base_shear.T).max()),
                    "overturning": float(res.overturning.max()),
                    "slip": float(res.slip.max()),
                    **ps,
                }
            )
    return rows


def summarise(rows: list[dict]) -> dict:
    """{case: {metric: {median, p5, ..., p95}}} over the runs."""
    out: dict = {}
    for case in dict.fromkeys(r["case"] for r in rows):
        sel = [r for r in rows if r["case"] == case]
        out[case] = {"n": len(sel), "toppled": int(sum(r["toppled"] for r in sel))}
        for m in METRICS:
            v = np.array([r[m] for r in sel])
            pc = np.percentile(v, PERCENTILES)
            d = {f"p{q}": float(x) for q, x in zip(PERCENTILES, pc, strict=True)}
            d["median"] = d["p50"]
            out[case][m] = d
    return out


def compare_foundations(
    n: int,
    params: CylinderParams | None = None,
    *,
    executor: Executor | None = None,
    seed0: int = 0,
    duration: float = EQ_DURATION,
    dt: float = EQ_DT,
    s0_units: str = "g2s",
    z_s: float | None = None,
    batch: int = BATCH,
) -> dict:
    """Distributions of peak responses of the three foundation cases over ``n`` earthquakes
    (seeds ``seed0 .. seed0 + n − 1``). Returns {"stats", "rows", "wall_s"}."""
    n = whole("n", n, 1, "a whole number of earthquakes >= 1")
    batch = whole("batch", batch, 1, "a whole number of runs per task >= 1")
    whole("seed0", seed0, 0, "a non-negative whole seed", hi=None)
    if params is not None:
        expect("params", params, isinstance(params, CylinderParams), _P)
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise TypeError(f"executor: expected a concurrent.futures.Executor, got "
                        f"{type(executor).__name__}")  # fmt: skip
    p = params or CylinderParams()
    pd = asdict(p)
    pd.pop("foundation")
    seeds = list(range(seed0, seed0 + n))
    chunks = [seeds[i : i + batch] for i in range(0, n, batch)]
    tic = time.perf_counter()
    own = executor is None
    ex = executor or ProcessPoolExecutor(max_workers=min(len(chunks), os.cpu_count() or 1))
    try:
        futs = [ex.submit(run_batch, pd, c, duration, dt, s0_units, z_s) for c in chunks]
        rows = [row for f in futs for row in f.result()]
    finally:
        if own:
            ex.shutdown()
    return {"stats": summarise(rows), "rows": rows, "wall_s": time.perf_counter() - tic}
