"""Benchmark: a small building's full rung on its two paths, work against precision.

A `building3d` scene at ``fidelity = "full"`` runs on dense matrices with every
fixed-interface mode (Radau IIA, adaptive to ``rtol``) or on sparse operators (generalized-α
at a fixed step); ``solver.path = "auto"`` takes the sparse path above ``SPARSE_FROM``
internal dofs where the law, contact and bearing allow it. This script measures both paths
on regular buildings within the dense limit: 2 × 2 and 3 × 3 bays of 6 m, two storeys of
3.5 m (200 t and 150 t floors, the office's sections), one element per member (78 and 134
internal dofs), and 2 × 2 bays with two (258), on friction pendulums (the office scene's:
R 2.2 m, μ 0.04-0.07, grid base) under the first ``--t-end`` seconds of the bundled
three-component record ``synthetic-wn-40s``. Each run is a whole scene run (``run_scene``),
after a warm-up that compiles both paths and builds the models:

- dense: Radau IIA at rtol 1e-3 (the cb scene's; atol 1e-5) and 1e-5 (atol 1e-7);
- sparse: generalized-α at dt = 5 ms (the default), 2, 1 and 0.5 ms.

The error of a run is the largest relative difference of its peaks (isolator slip, base
shear, drift ratios at the centres of mass, floor accelerations) from a reference: the sparse
path at dt = 0.125 ms (second order: its own error is below 1/16 of the 0.5 ms run's, which the
table shows), checked on the small building against the dense path at rtol 1e-8. Times are
the median wall seconds of ``--repeats`` runs, interleaved; the ratio column is each run's time
over the default sparse run's, in the same process.
Run: ``python examples/bench_building3d_paths.py [--t-end 2] [--repeats 3]``.
"""

from __future__ import annotations

import argparse
import copy
import statistics
import tempfile
import time
from pathlib import Path

from nsdyn.cli.args import positive_finite, positive_int
from nsdyn.models.isolated.building3d_scene import run_scene

FRAME = """[frame3d]
name = "b{b}x{b}x2-{n}"
kind = "regular"
bays_x = {bays}
bays_y = {bays}
storey_heights = [3.5, 3.5]
n_v = {n}
n_h = {n}
floor_mass = [200000.0, 150000.0]
diaphragms = true
zeta = [0.05]
{sections}"""
SECTION = """
[frame3d.{member}]
vecxz = {vecxz}
E = 2.1e11
nu = 0.3
A = {A}
I_y = {I_y}
I_z = {I_z}
J = {J}
rho_A = {rho_A}
"""
COLUMN = {"vecxz": [1.0, 0.0, 0.0], "A": 0.0478, "I_y": 0.00146, "I_z": 0.00146, "J": 0.00219,
          "rho_A": 375.0}  # fmt: skip
BEAM = {"vecxz": [0.0, 0.0, 1.0], "A": 0.0493, "I_y": 0.00805, "I_z": 0.00022, "J": 1.2e-5,
        "rho_A": 387.0}  # fmt: skip
SCENE = {
    "scene": {"kind": "building3d"},
    "structure": {"fidelity": "full", "base": "grid"},
    "bearing": {
        "type": "fps",
        "radius": 2.2,
        "mu_slow": 0.04,
        "mu_fast": 0.07,
        "rate": 30.0,
        "mu_static": 0.075,
        "d_cap": 0.35,
    },  # fmt: skip
    "motion": {"kind": "record3", "record": "synthetic-wn-40s"},
}
PEAKS = ("peak_resultant_displacement_m", "peak_base_shear_N", "peak_drift_cm_x",
         "peak_drift_cm_y", "peak_floor_acc_x_mps2", "peak_floor_acc_y_mps2")  # fmt: skip
DENSE = ((1e-3, 1e-5), (1e-5, 1e-7))
STEPS = (5e-3, 2e-3, 1e-3, 5e-4)
DT_REF = 1.25e-4


def frame_file(folder: Path, b: int, n: int) -> str:
    """A ``b`` × ``b``-bay, two-storey building with ``n`` elements per member, written to
    ``folder``."""
    sections = "".join(SECTION.format(member=m, **s) for m, s in
                       (("columns", COLUMN), ("beams_x", BEAM), ("beams_y", BEAM)))  # fmt: skip
    path = folder / f"b{b}x{b}x2-{n}.toml"
    text = FRAME.format(b=b, n=n, bays=[6.0] * b, sections=sections)
    path.write_text(text, encoding="utf-8")
    return str(path)


def run(folder: Path, frame: str, t_end: float, path: str, **solver) -> dict:
    """One scene run: the summary, with ``wall`` the whole run's seconds (build cached)."""
    cfg = copy.deepcopy(SCENE)
    cfg["structure"]["frame3d"] = frame
    cfg["motion"]["t_end"] = t_end
    cfg["solver"] = {"law": "arctan", "path": path, **solver}
    out = folder / "out"
    out.mkdir(exist_ok=True)
    w0 = time.perf_counter()
    s = run_scene(cfg, source=str(folder / "scene.toml"), out_dir=out, figures=False, quiet=True)
    s["wall"] = time.perf_counter() - w0
    return s


def error(s: dict, ref: dict) -> float:
    """The largest relative difference of the peaks of ``s`` from those of ``ref``."""
    return max(abs(s[k] - ref[k]) / abs(ref[k]) for k in PEAKS)


def sizes_arg(s: str) -> tuple:
    """``--sizes``: comma-separated ``B:N`` pairs, B bays each way and N elements per member,
    each an integer >= 1."""
    form = "comma-separated B:N (B bays each way, N elements per member; integers >= 1)"
    out = []
    for z in s.split(","):
        parts = z.split(":")
        try:
            b, n = (int(v) for v in parts)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {form}, got {s!r}") from None
        if b < 1 or n < 1:
            raise argparse.ArgumentTypeError(f"expected {form}, got {s!r}")
        out.append((b, n))
    return tuple(out)


def main(t_end: float = 2.0, repeats: int = 3, sizes=((2, 1), (3, 1), (2, 2))) -> list[dict]:
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for b, n in sizes:
            frame = frame_file(folder, b, n)
            cases = [("dense", f"rtol {r:g}", {"rtol": r, "atol": a}) for r, a in DENSE]
            cases += [("sparse", f"dt {h * 1e3:g} ms", {"dt": h}) for h in STEPS]
            for _, _, kw in cases:  # warm-up: compile, build the models into the cache
                run(folder, frame, 0.05, "dense" if "rtol" in kw else "sparse", **kw)
            times: dict = {label: [] for _, label, _ in cases}
            last: dict = {}
            for _ in range(repeats):  # interleaved
                for path, label, kw in cases:
                    last[label] = run(folder, frame, t_end, path, **kw)
                    times[label].append(last[label]["wall"])
            ref = run(folder, frame, t_end, "sparse", dt=DT_REF)
            check = (
                run(folder, frame, t_end, "dense", rtol=1e-8, atol=1e-10)
                if n == 1 and b == 2
                else None
            )
            base = statistics.median(times["dt 5 ms"])
            for path, label, _ in cases:
                wall = statistics.median(times[label])
                rows.append({"internal_dofs": int(last[label]["path_why"].split()[0]),
                             "path": path, "run": label, "wall_s": wall,
                             "ratio_to_sparse_5ms": wall / base,
                             "peak_error": error(last[label], ref)})  # fmt: skip
            if check is not None:
                rows.append({"internal_dofs": rows[-1]["internal_dofs"], "path": "dense",
                             "run": "rtol 1e-08 (the reference's check)",
                             "wall_s": check["wall"], "ratio_to_sparse_5ms": check["wall"] / base,
                             "peak_error": error(check, ref)})  # fmt: skip
    print("| internal dofs | path | run | wall [s] | / sparse 5 ms | peak error |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['internal_dofs']} | {r['path']} | {r['run']} | {r['wall_s']:.3g} | "
              f"{r['ratio_to_sparse_5ms']:.3g} | {r['peak_error']:.2g} |")  # fmt: skip
    return rows


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--t-end", type=positive_finite, default=2.0,
                    help="seconds of the record (default 2)")  # fmt: skip
    ap.add_argument("--repeats", type=positive_int, default=3, help="runs of each case (default 3)")
    ap.add_argument("--sizes", type=sizes_arg, default="2:1,3:1,2:2", metavar="B:N,...",
                    help="B bays each way : N elements per member (2:1,3:1,2:2)")  # fmt: skip
    a = ap.parse_args()
    main(a.t_end, a.repeats, a.sizes)
