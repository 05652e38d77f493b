"""First compilation of one integrator kernel into an empty numba cache, compile helper off and on.

Each run is a fresh Python process with its own empty ``NUMBA_CACHE_DIR`` calling
:func:`nsdyn.solve.methods.warmup_kernel` (the kernel and its metrics, as ``nsdyn run`` does);
``NSDYN_COMPILE_HELPER`` alternates 0 / 1 within each pair, so a drift of the shared machine's
load hits both alike. Prints every wall time, the medians and their ratio (off / on).

    python examples/cold_compile.py                     # the switch model's loop, 2 pairs
    python examples/cold_compile.py --kernel radau --pairs 3

Each family's first run, measured the same way, is tabulated in docs/dev/first-runs.md. The
helper gains only where a second core is free: on an idle machine ``radau`` took ~9 s with
the helper and ~17 s without (2026-11-27); in an hour loaded by other jobs 23.2 s with it and
20.0 s without (one pair, 2026-12-04). ``main`` returns the numbers.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from nsdyn.cli.args import positive_int

METRICS = {"radau": "metrics", "event": "metrics-general"}
CODE = (
    "import sys; from nsdyn.solve.methods import warmup_kernel; "
    "warmup_kernel(sys.argv[1], metrics=sys.argv[2])"
)


def cold_s(kernel: str, helper: bool) -> float:
    """Wall seconds of one warm-up of ``kernel`` in a fresh process with an empty cache."""
    root = str(Path(__file__).resolve().parents[1])
    with tempfile.TemporaryDirectory(prefix="nsdyn-numba-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, NSDYN_COMPILE_HELPER="1" if helper else "0")
        env["PYTHONPATH"] = os.pathsep.join(p for p in (root, env.get("PYTHONPATH")) if p)
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", CODE, kernel, METRICS[kernel]], env=env, check=True)
        return time.perf_counter() - t0


def main(kernel: str = "event", pairs: int = 2) -> dict:
    if kernel not in METRICS:
        raise ValueError(f"kernel: expected one of {sorted(METRICS)}, got {kernel!r}")
    off, on = [], []
    for k in range(pairs):
        print(f"pair {k + 1}/{pairs}: helper off ...", flush=True)
        off.append(cold_s(kernel, False))
        print(f"pair {k + 1}/{pairs}: helper on ...", flush=True)
        on.append(cold_s(kernel, True))
        print(f"pair {k + 1}: helper off {off[-1]:.1f} s, on {on[-1]:.1f} s", flush=True)
    res = {"off_s": float(np.median(off)), "on_s": float(np.median(on)), "off": off, "on": on}
    res["ratio"] = res["off_s"] / res["on_s"]
    print(
        f"{kernel}: helper off {res['off_s']:.1f} s, on {res['on_s']:.1f} s "
        f"(medians of {pairs}; {res['ratio']:.2f}x)"
    )
    return res


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kernel", default="event", choices=sorted(METRICS))
    ap.add_argument("--pairs", type=positive_int, default=2, help="off/on pairs of runs (2)")
    a = ap.parse_args()
    main(a.kernel, a.pairs)
