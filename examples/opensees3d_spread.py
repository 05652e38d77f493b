"""How far OpenSees' own peaks move when its input moves by round-off: the 3D isolated building.

``nsdyn bench scale3d`` compares nsdyn's full 3D rung with the exported OpenSees model of the
same building on its friction pendulum bearings. Before reading the differences of the peaks,
this script measures the reference's own spread: the smallest of the benchmark's buildings
(``office-11-3d`` with 5 × 1 bays and a coarse mesh, 2 712 dofs; or ``--size``) under the first
``--t-end`` seconds of the benchmark's record, run by OpenSees ``--runs`` times with the
Rayleigh coefficient β multiplied by (1 + k·10⁻¹³), k = 0, 1, …, and by nsdyn with its
damping matrix scaled the same way. A perturbation of 10⁻¹³ is far below any modelling
choice: a well-conditioned solution moves by about that much. Each OpenSees run is a whole
process; two run at a time. Needs openseespy.

Run: ``python examples/opensees3d_spread.py [--runs 5] [--t-end 4] [--size 5,1,2,2]``.
"""

from __future__ import annotations

import argparse
import dataclasses
import re
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from nsdyn.bench import scale3d
from nsdyn.bench.scale import _OS_CHILD, _child
from nsdyn.cli.args import positive_finite, positive_int
from nsdyn.models.isolated.pairs_sparse import building_pairs_sparse
from nsdyn.models.isolated.pairs_sparse_run import simulate_pairs_sparse

KEYS = ("peak_resultant_displacement_m", "peak_drift_cm_x", "peak_drift_cm_y")
STEP = 1e-13  # relative perturbation of beta per run


def opensees_runs(size, t_end: float, runs: int, work: Path) -> list[dict]:
    """Peaks of OpenSees runs with beta x (1 + k STEP), k < ``runs``."""
    script = scale3d._export(size, t_end, work)
    text = script.read_text(encoding="utf-8")
    m = re.search(r'"beta_k":([0-9.eE+-]+)', text)
    beta = float(m.group(1))
    paths = []
    for k in range(runs):
        p = work / f"opensees-{k}.py"
        p.write_text(text.replace(m.group(0), f'"beta_k":{beta * (1 + k * STEP)!r}'), "utf-8")
        paths.append(p)
    with ThreadPoolExecutor(2) as pool:
        res = list(pool.map(lambda p: _child(_OS_CHILD, [str(p), repr(t_end)]), paths))
    return [{k: float(r[k]) for k in KEYS} for r in res]


def nsdyn_runs(size, t_end: float, runs: int) -> list[dict]:
    """Peaks of nsdyn's full rung with C x (1 + k STEP), k < ``runs``."""
    s = scale3d.with_drift_outputs(building_pairs_sparse(
        scale3d.building_of_size(*size), scale3d.bearing(), damping="stiffness"))  # fmt: skip
    out = []
    for k in range(runs):
        sk = dataclasses.replace(s, C=s.C * (1 + k * STEP))
        r = simulate_pairs_sparse(sk, scale3d.motion(), dt=scale3d.DT, t_end=t_end, keep_q=False)
        p = scale3d.peaks(sk, r)
        out.append({key: p[key] for key in KEYS})
    return out


def spread(rows: list[dict]) -> dict:
    """(min, max, (max - min) / min) of each peak over the runs."""
    return {k: (min(r[k] for r in rows), max(r[k] for r in rows),
                max(r[k] for r in rows) / min(r[k] for r in rows) - 1) for k in KEYS}  # fmt: skip


def size_arg(s: str) -> tuple:
    """``--size``: four integers >= 1, bays y, bays x, n_v, n_h."""
    form = "four integers >= 1, 'bays y,bays x,n_v,n_h' (e.g. 5,1,2,2)"
    try:
        v = tuple(int(x) for x in s.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected {form}, got {s!r}") from None
    if len(v) != 4 or min(v) < 1:
        raise argparse.ArgumentTypeError(f"expected {form}, got {s!r}")
    return v


def main(runs: int = 5, t_end: float = 4.0, size=(5, 1, 2, 2)) -> dict:
    with tempfile.TemporaryDirectory() as d:
        os_rows = opensees_runs(size, t_end, runs, Path(d))
    ns_rows = nsdyn_runs(size, t_end, runs)
    return {"size": size, "t_end": t_end, "opensees": os_rows, "nsdyn": ns_rows,
            "opensees_spread": spread(os_rows), "nsdyn_spread": spread(ns_rows)}  # fmt: skip


def _print(out: dict) -> None:
    print(f"building {out['size']}, first {out['t_end']:g} s; beta (OpenSees) and C (nsdyn) "
          f"x (1 + k {STEP:g})")  # fmt: skip
    print(f"{'run':10s} " + " ".join(f"{k[5:]:>24s}" for k in KEYS))
    for tool in ("opensees", "nsdyn"):
        for k, r in enumerate(out[tool]):
            print(f"{tool:8s} {k:1d} " + " ".join(f"{r[key]:24.7e}" for key in KEYS))
    for tool in ("opensees", "nsdyn"):
        sp = out[f"{tool}_spread"]
        print(f"{tool} spread (max/min - 1): "
              + ", ".join(f"{k[5:]} {v[2]:.1e}" for k, v in sp.items()))  # fmt: skip


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=positive_int, default=5, help="runs of each tool, >= 2 (5)")
    ap.add_argument("--t-end", type=positive_finite, default=4.0, help="seconds of the record (4)")
    ap.add_argument("--size", type=size_arg, default="5,1,2,2",
                    help="bays y, bays x, n_v, n_h (5,1,2,2)")  # fmt: skip
    a = ap.parse_args()
    if a.runs < 2:
        ap.error(f"--runs: expected at least 2 (a spread needs two runs), got {a.runs}")
    if a.t_end < scale3d.DT:
        ap.error(f"--t-end: expected at least one step ({scale3d.DT:g} s), got {a.t_end:g}")
    _print(main(a.runs, a.t_end, a.size))
