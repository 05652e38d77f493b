"""Redraw the benchmark charts from the CSV tables of ``nsdyn bench``; collect the docs'.

    python examples/bench_figures.py [DIR] [--figures FIG_DIR]

``DIR`` is where ``nsdyn bench`` wrote (default ``nsdyn-out/bench``; a missing one is an
error); the docs' PNGs go to ``FIG_DIR`` (default ``examples/figures``). No integration is
rerun: the accuracy, fidelity, speed and periodic charts are redrawn from their CSVs, the
stability chart (its drift histories are not in a CSV) and the rocking and contact charts
are copied, under the names
the docs embed (``rocking.png`` as ``rocking-bench.png``, ``contact-map.png`` as
``contact-stability.png``). Prints the tables docs/performance.md quotes (speed,
periodic, fidelity) and the speed ratios at matched accuracy; ``main`` returns them.
"""

from __future__ import annotations

import argparse
import csv
import math
import shutil
import sys
from pathlib import Path

from nsdyn import bench
from nsdyn.atomic import save_figure
from nsdyn.cli.args import out_dir

FIGURES = Path(__file__).resolve().parent / "figures"
# charts copied from the benchmarks' folder, under the names the docs embed
COPIED = {"stability.png": "stability.png", "rocking.png": "rocking-bench.png",
          "contact-wp.png": "contact-wp.png",
          "contact-map.png": "contact-stability.png"}  # fmt: skip
TABLES = {"accuracy.csv": "accuracy", "fidelity.csv": "fidelity", "speed-table.csv": "speed",
          "periodic.csv": "periodic"}  # fmt: skip
INTEGER = {
    "n_steps",
    "n_timed",
    "n_dof",
    "nfev",
    "scipy_n_steps",
    "scipy_n_timed",
    "iterations",
    "periods",
    "n_per_period",
    "repeats",
}
TEXT = {"record", "label", "role", "method", "law", "setting", "status", "message", "model"}
TEXT |= {"reference", "ratio_bound", "quick", "atol", "scene"}


def _value(key: str, v: str):
    if key in TEXT:
        return v
    if v == "":
        return float("nan")
    try:
        x = float(v)
    except ValueError:
        return v
    if key in INTEGER and math.isfinite(x):
        return int(x)
    return x


def read_rows(path: Path) -> list[dict]:
    """CSV rows with the numeric columns as numbers (empty cells become NaN)."""
    with open(path, newline="") as fh:
        return [{k: _value(k, v) for k, v in r.items()} for r in csv.DictReader(fh)]


def speed_result(out: Path) -> dict:
    """``speed_bench``'s result (table, rows, meta) from ``speed-table.csv`` and ``speed.csv``."""
    rows = read_rows(out / "speed.csv")
    table = read_rows(out / "speed-table.csv")
    ns = next(r for r in rows if r["role"] == "nsdyn")
    t0 = table[0]
    meta = {
        "model": t0.get("model") or bench.speed_scene(3.0)[1].name,
        "rtol": t0.get("rtol", ns["rtol"]),
        "atol_q": t0.get("atol_q", ns["atol_q"]),
        "atol_v": t0.get("atol_v", ns["atol_v"]),
        "dt_out": t0.get("dt_out") or bench.speed_scene(3.0)[3]["dt_out"],
        "pga": t0.get("pga", bench.PGA),
        "repeats": t0.get("repeats") or ns["n_timed"] // 2,
        "compile_s": t0["compile_s"],
        "cold_compile_s": t0.get("cold_compile_s", float("nan")),
    }
    return {"rows": rows, "table": table, "meta": meta}


def periodic_result(out: Path) -> dict:
    """``periodic_bench``'s result (rows, references, meta) from ``periodic.csv``."""
    rows = read_rows(out / "periodic.csv")
    refs = {}
    for r in rows:
        if r["label"] != "reference" or r["status"] != "ok":
            continue
        cell = (r["A_mps2"], r["f_hz"])
        chk = next(
            c for c in rows if c["label"] == "reference-check" and (c["A_mps2"], c["f_hz"]) == cell
        )
        refs[cell] = {
            "reference": {"x_iso": r["x_bar_iso_m"], "idr": r["idr"]},
            "check": {"err_xbar": chk["err_xbar"], "err_idr": chk["err_idr"]},
            "closure": r["closure"],
        }
    meta = {"model": rows[0].get("model") or "office-11 cb", "compile_s": rows[0]["compile_s"]}
    return {"rows": rows, "references": refs, "meta": meta}


def main(out_dir: str | Path = bench.DEFAULT_OUT, fig_dir: str | Path = FIGURES) -> dict:
    out, figs = Path(out_dir), Path(fig_dir)
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
        fig = bench.accuracy_figure(rows, floors, records, window)
        save_figure(fig, figs / "accuracy.png")
        result["ratios"] = {rec: bench.matched_ratios(rows, rec) for rec in records}
        result["floors"] = floors
    fid = out / "fidelity.csv"
    if fid.exists():
        rows = read_rows(fid)
        save_figure(bench.fidelity_figure(rows), figs / "fidelity.png")
        result["fidelity"] = rows
    if (out / "speed-table.csv").exists():
        res = speed_result(out)
        save_figure(bench.speed_figure(res["rows"], res["table"]), figs / "speed.png")
        result["speed"] = bench.speed_markdown(res)
    if (out / "periodic.csv").exists():
        res = periodic_result(out)
        save_figure(bench.periodic_figure(res["rows"]), figs / "periodic.png")
        result["periodic"] = bench.periodic_markdown(res)
    result["copied"] = []
    for drawn, docs_name in COPIED.items():  # charts kept as the benchmark drew them
        if (out / drawn).exists():
            figs.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(out / drawn, figs / docs_name)
            result["copied"].append(str(figs / docs_name))
    result["missing"] = [f"{name} (nsdyn bench {cmd})" for name, cmd in TABLES.items()
                         if not (out / name).exists()]  # fmt: skip
    result["figures"] = sorted(str(p) for p in figs.glob("*.png"))
    return result


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir", nargs="?", default=str(bench.DEFAULT_OUT),
                    help=f"the folder nsdyn bench wrote into ({bench.DEFAULT_OUT})")  # fmt: skip
    ap.add_argument("--figures", type=out_dir, default=str(FIGURES), metavar="FIG_DIR",
                    help="where the docs' PNGs go (examples/figures)")  # fmt: skip
    a = ap.parse_args()
    if not Path(a.dir).is_dir():  # (a fresh checkout: nothing run yet)
        why = "not a folder" if Path(a.dir).exists() else "no such folder"
        ap.error(f"DIR: expected the folder nsdyn bench wrote its tables into, got {a.dir!r} "
                 f"({why}; run nsdyn bench accuracy, fidelity, speed, periodic or stability "
                 "into it first)")  # fmt: skip
    res = main(a.dir, a.figures)
    for path in res.get("copied", []):  # (said: "no tables" alone read as nothing done)
        print(f"copied {path}", file=sys.stderr)
    if not {"ratios", "fidelity", "speed", "periodic"} & set(res) and not res.get("copied"):
        ap.exit(
            2,
            f"{ap.prog}: error: {a.dir}: no benchmark tables or charts to redraw from "
            "(run nsdyn bench accuracy, fidelity, speed, periodic or stability into it "
            "first)\n",
        )  # (it said so with status 0)
    if not {"ratios", "fidelity", "speed", "periodic"} & set(res):
        print(f"{a.dir}: no benchmark tables to redraw from (run nsdyn bench accuracy, fidelity, "
              f"speed, periodic or stability into it first); the figures already in "
              f"{a.figures}:", file=sys.stderr)  # fmt: skip
    for key in ("speed", "periodic"):
        if key in res:
            print(res[key], end="\n\n")
    for r in res.get("fidelity", []):
        # the rigid deck has no storey drift: no IDR to compare (as nsdyn bench fidelity)
        idr = f"{'—':>9s}" if r["model"] == "rigid" else f"{r['err_idr']:9.2e}"
        print(
            f"{r['record']:14s} {r['model']:16s} {r['n_dof']:4d} x_iso {r['err_xpeak']:9.2e} "
            f"IDR {idr} acc {r['err_acc']:9.2e} wall {r['wall_s']:9.3f} s {r['status']}"
        )
    for rec, qs in res.get("ratios", {}).items():
        for name, q in qs.items():
            if not math.isfinite(q["ratio"]):
                print(f"{rec}: {name}: n/a (no common error level)")
            else:
                print(f"{rec}: {name} at err_x = {q['err_x']:.2g}: {q['ratio']:.3g}x")
    if res.get("missing") and {"ratios", "fidelity", "speed", "periodic"} & set(res):
        print(f"{a.dir}: not redrawn, no table: {', '.join(res['missing'])}", file=sys.stderr)
    print("\n".join(res["figures"]))
