"""``nsdyn sweep`` on a ``building3d`` scene at the fixed fidelity: the exact steady harmonic
response of the linear fixed-base building (:mod:`nsdyn.models.isolated.fixed3d_sweep`) over
log-spaced frequencies, one curve per amplitude (linear: each the scene's curve scaled).
Writes sweep.csv, sweep.json and sweep.png (roof displacement and corner drift against f)."""

from __future__ import annotations

import argparse
import csv
import io
import sys
import time
from pathlib import Path

import numpy as np

from nsdyn.atomic import atomic_open, save_figure
from nsdyn.cli.args import fail, json_report, old_figures

_NOT_HERE = (  # flags of the nonlinear sweeps: (flag, attribute, its default)
    ("--friction", "friction", None), ("--contact", "contact", "bilateral"),
    ("--tableau", "tableau", "sdirk2"), ("--steps-factor", "steps_factor", 1.0),
    ("--continuation", "continuation", "sequential"), ("--no-fallback", "no_fallback", False),
    ("--workers", "workers", None),  # (one batched solve: it was taken and ignored)
)  # fmt: skip


def run_fixed3d(args: argparse.Namespace, cfg: dict) -> int:
    """The sweep of a fixed building3d scene (``args`` of ``nsdyn sweep``); exit status."""
    from nsdyn.models.isolated.fixed3d import few_modes_note
    from nsdyn.models.isolated.fixed3d_sweep import (
        COLUMNS,
        POINTS_DEFAULT,
        default_range,
        fixed_frf,
        fixed_sweep_scene,
    )
    from nsdyn.models.scenefile import SceneError
    from nsdyn.structure import fixed_base_modes_3d

    source = str(args.scene)
    unused = [flag for flag, key, off in _NOT_HERE if getattr(args, key, off) != off]
    if unused:
        return fail(
            args,
            f"{source}: {', '.join(unused)}: not for the fixed rung (a linear model: its "
            "steady state is solved exactly, frequency by frequency, in one process; no "
            "friction, contact, shooting or continuation)",
        )
    t0 = time.perf_counter()
    try:
        sc = fixed_sweep_scene(cfg, source)
        modes = fixed_base_modes_3d(sc["frame"], n_modes=sc["n_modes"])
    except (SceneError, ValueError) as e:
        return fail(args, " ".join(str(e).split()))
    lo, hi = default_range(modes)
    fmin = lo if args.fmin is None else args.fmin
    fmax = hi if args.fmax is None else args.fmax
    if not (fmax > fmin > 0):
        return fail(args, f"--fmin/--fmax: expected 0 < fmin < fmax, got {fmin:g}, {fmax:g}")
    f = np.geomspace(fmin, fmax, args.points or POINTS_DEFAULT)
    unit = fixed_frf(sc["frame"], sc["A"], f, modes=modes)  # per m/s² of the orbit's amplitude
    amplitudes = [float(a) for a in (args.amplitudes or [sc["amplitude"]])]
    rows = []
    for a in amplitudes:
        for r in unit.rows(1.0):
            rows.append({**{k: v * a for k, v in r.items() if k not in ("f", "A")},
                         "f": r["f"], "A": a})  # fmt: skip
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(COLUMNS), lineterminator="\n")
    w.writeheader()
    w.writerows({k: repr(r[k]) for k in COLUMNS} for r in rows)
    csv_path = out / "sweep.csv"
    gone = old_figures(out, ["sweep.png"], "sweep", args)  # (redrawn after the table)
    with atomic_open(csv_path, "w") as fh:
        fh.write(buf.getvalue())
    mode_list = [{"f_hz": float(fk), "family": fam} for fk, fam in zip(modes.f_hz, modes.family,
                                                                        strict=True)]  # fmt: skip
    summary = []
    for a in amplitudes:
        i, j = int(np.argmax(unit.roof_m)), int(np.argmax(unit.corner_drift))
        summary.append({"A": a, "roof_max_m": a * float(unit.roof_m[i]),
                        "f_at_roof_max_hz": float(f[i]),
                        "corner_drift_max": a * float(unit.corner_drift[j]),
                        "f_at_corner_drift_max_hz": float(f[j])})  # fmt: skip
    report = {"kind": "building3d", "fidelity": "fixed", "model": sc["name"],
              "frame": sc["frame"].name, "csv": str(csv_path), "points": int(f.size),
              "fmin_hz": fmin, "fmax_hz": fmax, "modes": mode_list,
              "mass_captured": [float(v) for v in modes.mass_fraction.sum(axis=0)],
              "amplitudes": summary, "wall_s": time.perf_counter() - t0}  # fmt: skip
    few = few_modes_note(sc["n_modes"], modes) if sc.get("n_modes_given", True) else None
    report["notes"] = [n for n in (gone, few) if n]  # (each said on stderr)
    if few and not args.json:
        print(f"nsdyn sweep: note: {few}", file=sys.stderr)
    if not args.no_figures:
        from nsdyn.plot.frames3d import frf_figure

        said = "fixed base" in sc["name"]  # (the example scene's own name says it)
        title = f"{sc['name']}: {'' if said else 'fixed base, '}steady harmonic response"
        report["figure"] = str(save_figure(frf_figure(rows, mode_list, title), out / "sweep.png"))
    json_path = out / "sweep.json"
    report["json"] = str(json_path)
    with atomic_open(json_path, "w") as fh:
        fh.write(json_report(report, indent=1))  # (its status too)
    if args.json:
        print(json_report(report))
        return 0
    print(f"building3d {sc['name']}: fixed base, {f.size} frequencies {fmin:g}-{fmax:g} Hz, "
          f"{len(modes.f_hz)} modes (f1 = {modes.f_hz[0]:.4g} Hz)")  # fmt: skip
    print("   A [m/s²]  roof max [m]  at f [Hz]  corner drift max  at f [Hz]")
    for s in summary:
        print(f"   {s['A']:8.3g}  {s['roof_max_m']:12.4g}  {s['f_at_roof_max_hz']:9.4g}  "
              f"{s['corner_drift_max']:16.4g}  {s['f_at_corner_drift_max_hz']:9.4g}")  # fmt: skip
    print(f"csv:    {csv_path}")  # (as the other sweeps list their files)
    print(f"json:   {json_path}")
    if "figure" in report:
        print(f"figure: {report['figure']}")
    return 0
