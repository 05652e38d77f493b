"""Redraw the work-precision and fidelity charts from the CSV tables of ``nsdyn bench``.

    python examples/bench_figures.py [DIR]     # DIR: where `nsdyn bench` wrote (nsdyn-out/bench)

No integration is rerun: the figures and the speed ratios at matched accuracy come from
``accuracy.csv``, ``accuracy-reference.csv`` and ``fidelity.csv``. ``main`` returns the ratios
(the numbers quoted in the README) so they can be checked or reused.
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

from nsdyn import bench

NUMERIC = {
    "value",
    "err_x",
    "err_idr",
    "err_xpeak",
    "err_acc",
    "wall_s",
    "n_timed",
    "n_steps",
    "nfev",
    "x_iso_max_m",
    "idr_max",
    "floor_acc_max_mps2",
    "energy_closure",
    "window_s",
    "repeats",
    "compile_s",
    "n_dof",
}


def read_rows(path: Path) -> list[dict]:
    """CSV rows with the numeric columns as floats (empty cells become NaN)."""
    rows = []
    with open(path, newline="") as fh:
        for r in csv.DictReader(fh):
            rows.append(
                {k: (float(v) if v else float("nan")) if k in NUMERIC else v for k, v in r.items()}
            )
    for r in rows:
        for k in ("n_steps", "n_timed", "n_dof"):
            if k in r and r[k] == r[k]:
                r[k] = int(r[k])
    return rows


def main(out_dir: str | Path = bench.DEFAULT_OUT) -> dict:
    out = Path(out_dir)
    result: dict = {}
    acc = out / "accuracy.csv"
    if acc.exists():
        rows = read_rows(acc)
        refs = read_rows(out / "accuracy-reference.csv")
        floors = {
            (r["record"], r["law"]): {"err_x": r["err_x"], "err_idr": r["err_idr"]}
            for r in refs
            if r["label"] == "reference-check"
        }
        records = list(dict.fromkeys(r["record"] for r in rows))
        window = rows[0]["window_s"]
        bench._save_figure(
            bench._plot_accuracy(rows, floors, records, window), out / "accuracy.png"
        )
        result["ratios"] = {rec: bench.matched_ratios(rows, rec) for rec in records}
        result["floors"] = floors
    fid = out / "fidelity.csv"
    if fid.exists():
        bench._save_figure(bench._plot_fidelity(read_rows(fid)), out / "fidelity.png")
        result["fidelity"] = True
    return result


if __name__ == "__main__":
    res = main(sys.argv[1] if len(sys.argv) > 1 else bench.DEFAULT_OUT)
    for rec, qs in res.get("ratios", {}).items():
        for name, q in qs.items():
            print(f"{rec}: {name} at err_x = {q['err_x']:.2g}: {q['ratio']:.3g}x")
