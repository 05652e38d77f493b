"""Seed 004 §5 reproduced: the office frame, fixed-base vs isolated, on four Kobe 1995 records.

Records are read in place from ``shared/records`` (set ``NSDYN_SHARED``); they are never
copied into the project. Every record is scaled to a horizontal PGA of 3 m/s^2 (seed §5).

    python examples/seed_transient_study.py [--out DIR] [--quick]

Writes ``study_transient.json`` (all numbers quoted in docs/guide/transient.md) and the figures
``fig6_idr_acc.png`` (IDR and absolute floor acceleration per level, fixed vs isolated),
``fig7_top_drift.png`` (roof drift relative to the base), ``fig5_switch_vs_arctan.png``
(x_iso for the switch model vs arctan eps = 7500), ``fig8_rigid_vs_flexible.png``.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

import numpy as np

from nsdyn.atomic import atomic_open, save_figure
from nsdyn.cli.args import out_dir
from nsdyn.ground import default_shared_dir, kobe_records
from nsdyn.models.isolated.system import Isolation, build_system
from nsdyn.solve.transient import simulate
from nsdyn.structure import load_frame

PGA = 3.0  # m/s^2, seed §5
ISO = Isolation(k_lam=5.0e4, c=1.0e4, mu=0.03, law="arctan", eps=7500.0)  # seed eq (16)


def run_case(system, motion, **kw):
    res = simulate(system, motion, **kw)
    return res


def main(out: str | Path = "nsdyn-out/transient-study", quick: bool = False) -> dict:
    shared = default_shared_dir()
    try:  # the records first: a missing one leaves no empty output folder behind
        if shared is None and os.environ.get("NSDYN_SHARED"):
            raise FileNotFoundError(f"NSDYN_SHARED = {os.environ['NSDYN_SHARED']!r} is no "
                                    "folder; set it to the shared directory")  # fmt: skip
        if shared is None:
            raise FileNotFoundError("no shared directory beside the project, and NSDYN_SHARED "
                                    "is not set; set it to the shared directory")  # fmt: skip
        kobe = kobe_records(shared, component="000")
    except FileNotFoundError as e:  # (status 2, the path tried named: it said "set
        print(f"seed_transient_study: error: shared/records not found: {e}",  # NSDYN_SHARED"
              file=sys.stderr)  # of a set one)  # fmt: skip
        raise SystemExit(2) from None
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    frame = load_frame("office-11")
    motions = {k: m.scaled_to_pga(PGA) for k, m in kobe.items()}
    if quick:
        motions = {k: m.window(m.t0, m.t0 + 15.0) for k, m in motions.items()}
    iso = build_system(frame, ISO, fidelity="cb", f_max=5.0)
    fixed = build_system(frame, fidelity="fixed", f_max=5.0)
    variants = {
        "switch": build_system(
            frame, Isolation(**{**ISO.__dict__, "law": "switch"}), fidelity="cb"
        ),
        "rigid": build_system(frame, ISO, fidelity="rigid"),
        "frozen": build_system(
            frame, Isolation(**{**ISO.__dict__, "frozen_normal": True}), fidelity="cb"
        ),
    }
    results: dict = {}
    histories: dict = {}
    for name, m in motions.items():
        r = {}
        h = {}
        for label, sysm, mot, method in [
            ("fixed", fixed, m, "radau"),
            ("isolated", iso, m, "radau"),
            ("switch", variants["switch"], m, "event"),
            ("rigid", variants["rigid"], m, "radau"),
            ("frozen", variants["frozen"], m, "radau"),
            ("no_vertical", iso, m.with_vertical(None), "radau"),
        ]:
            res = run_case(sysm, mot, method=method, t_eval=None)
            r[label] = res.summary()
            h[label] = res
            x = r[label].get("x_iso_max_m")  # (a fixed base has no isolator: none)
            x_iso = f"{x:.4f} m" if x is not None else "-"
            print(
                f"{name:13s} {label:12s} x_iso {x_iso}  "
                f"IDR {r[label]['idr_max']:.2e}  a {r[label]['floor_acc_max_mps2']:.2f} m/s2  "
                f"wall {res.wall_s:.2f} s"
            )
        results[name] = r
        histories[name] = h
    with atomic_open(out / "study_transient.json") as fh:
        json.dump(results, fh, indent=1)
    return {"results": results, "histories": histories, "frame": frame}


def figures(study: dict, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    res, hist = study["results"], study["histories"]
    names = list(res)
    fig, axes = plt.subplots(2, len(names), figsize=(3.2 * len(names), 6.5), sharey=True)
    for j, name in enumerate(names):
        for label, style in [("fixed", "k-o"), ("isolated", "b-s")]:
            idr = res[name][label]["idr_by_storey"]
            acc = res[name][label]["floor_acc_by_level_mps2"]
            axes[0, j].plot(idr, np.arange(1, len(idr) + 1), style, ms=3, label=label)
            axes[1, j].plot(acc, np.arange(len(acc)), style, ms=3, label=label)
        axes[0, j].set_title(name)
        axes[0, j].set_xlabel("IDR [-]")
        axes[1, j].set_xlabel("a [m/s²]")
    axes[0, 0].set_ylabel("storey")
    axes[1, 0].set_ylabel("level")
    axes[0, 0].legend()
    fig.tight_layout()
    save_figure(fig, out / "fig6_idr_acc.png", dpi=110)
    plt.close(fig)

    fig, axes = plt.subplots(len(names), 1, figsize=(8, 2.2 * len(names)), sharex=True)
    for ax, name in zip(axes, names, strict=True):
        for label, c in [("fixed", "k"), ("isolated", "b")]:
            r = hist[name][label]
            ax.plot(r.t, r.response.top_drift, c, lw=0.8, label=label)
        ax.set_ylabel(f"{name}\nx_top - x_iso [m]", fontsize=8)
    axes[0].legend()
    axes[-1].set_xlabel("t [s]")
    fig.tight_layout()
    save_figure(fig, out / "fig7_top_drift.png", dpi=110)
    plt.close(fig)

    for fname, pairs in [
        ("fig5_switch_vs_arctan.png", [("isolated", "arctan ε=7500"), ("switch", "switch")]),
        ("fig8_rigid_vs_flexible.png", [("isolated", "flexible (CB)"), ("rigid", "rigid")]),
    ]:
        fig, axes = plt.subplots(len(names), 1, figsize=(8, 2.2 * len(names)), sharex=True)
        for ax, name in zip(axes, names, strict=True):
            for label, lab in pairs:
                r = hist[name][label]
                ax.plot(r.t, r.response.x_iso[:, 0], lw=0.8, label=lab)
            ax.set_ylabel(f"{name}\nx_iso [m]", fontsize=8)
        axes[0].legend()
        axes[-1].set_xlabel("t [s]")
        fig.tight_layout()
        save_figure(fig, out / fname, dpi=110)
        plt.close(fig)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=out_dir, default="nsdyn-out/transient-study")
    ap.add_argument("--quick", action="store_true", help="first 15 s of each record only")
    a = ap.parse_args()
    study = main(a.out, a.quick)
    figures(study, Path(a.out))
