"""Benchmark: a full-order model's generalized-α step on its dense copies or on sparse operators.

``genalpha-lowrank`` steps a full-order model that carries dense copies (up to
``DENSE_MAX_DOF`` dofs) on them when more than half of its modes are damped
(:func:`nsdyn.solve.fullorder.dense_step`), else on the sparse operators. This script times
both paths, each forced in turn, as whole :func:`nsdyn.simulate` calls on the first ``--t-end``
seconds of the bundled record (PGA 3 m/s², dt 5 ms), interleaved in one process after a
warm-up call of each, and prints the medians of ``--repeats`` calls beside the path the rule
picks: the office frame (435 dofs) and the 1 593-dof frame of ``nsdyn bench scale``, each
with modal damping (every mode damped, or those up to 50 Hz) and with β K.
Run: ``python examples/bench_dense_or_sparse_step.py [--t-end 4] [--repeats 5]``.
"""

from __future__ import annotations

import argparse
import contextlib
import time
import warnings

import numpy as np

import nsdyn
from nsdyn.bench.scale import scale_frame
from nsdyn.cli.args import positive_finite, positive_int
from nsdyn.ground import read_motion
from nsdyn.models.isolated.system import build_system
from nsdyn.solve import fullorder

RULE = fullorder.dense_step


@contextlib.contextmanager
def forced(dense: bool):
    """Every full-order model steps on its dense copies (``dense``) or on the operators."""
    fullorder.dense_step = (lambda s: "dense: forced") if dense else (lambda s: "")
    try:
        yield
    finally:
        fullorder.dense_step = RULE


def timed(system, motion, dense: bool) -> float:
    # (the fixed step's AccuracyWarning on the isolation level's peak is the same on both
    # paths and not what is timed here: said once by nsdyn run, not four times between rows)
    with forced(dense), warnings.catch_warnings():
        warnings.simplefilter("ignore", nsdyn.AccuracyWarning)
        t0 = time.perf_counter()
        nsdyn.simulate(system, motion)
        return time.perf_counter() - t0


def main(t_end: float = 4.0, repeats: int = 5) -> list[dict]:
    motion = read_motion("synthetic-wn-40s").scaled_to_pga(3.0).window(0.0, t_end)
    frames = (("office", nsdyn.load_frame("office-11")), ("scale 2x10x10", scale_frame(2, 10, 10)))
    rows = []
    for label, frame in frames:
        for damping in ("modal", "stiffness"):
            s = build_system(frame, fidelity="full", damping=damping)
            for dense in (True, False):  # warm-up: kernels, factorisations, modes
                timed(s, motion, dense)
            d, sp = [], []
            for _ in range(repeats):
                d.append(timed(s, motion, True))
                sp.append(timed(s, motion, False))
            row = {"model": label, "n": s.n, "damping": damping, "m": int(s.sparse.U.shape[1])}
            row.update(dense_s=float(np.median(d)), sparse_s=float(np.median(sp)))
            rows.append({**row, "rule": RULE(s) or "sparse"})
    return rows


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=positive_finite, default=4.0, help="seconds of the record [4]")
    ap.add_argument("--repeats", type=positive_int, default=5, help="calls of each path [5]")
    a = ap.parse_args()
    dt = read_motion("synthetic-wn-40s").dt  # a window shorter than a step holds one sample
    if a.t_end < dt:
        ap.error(f"--t-end: expected at least one step of the record ({dt:g} s), got {a.t_end:g}")
    head = ("model", "n", "damping", "m", "dense s", "sparse s")
    print("{:14s} {:>5s} {:9s} {:>4s} {:>8s} {:>8s}  rule".format(*head))
    for r in main(a.t_end, a.repeats):
        print(f"{r['model']:14s} {r['n']:5d} {r['damping']:9s} {r['m']:4d} {r['dense_s']:8.3f} "
              f"{r['sparse_s']:8.3f}  {r['rule']}")  # fmt: skip
