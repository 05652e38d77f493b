"""Figures of a study: Pareto front, fragility curves with their band, distributions.

Built on ``matplotlib.figure.Figure`` (no pyplot, no backend switch); saved by the caller
through :func:`nsdyn.atomic.save_figure`.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from nsdyn.studies.fragility import exceedance_fractions

LABELS = {  # axis labels of common columns
    "idr_max": "peak interstorey drift ratio IDR [-]",
    "floor_acc_max_mps2": "peak absolute floor acceleration a [m/s²]",
    "x_iso_max_m": "peak isolator displacement x_iso [m]",
    "motion.pga": "PGA [m/s²]",
    "pga_mps2": "PGA [m/s²]",
}


def _label(name: str) -> str:
    return LABELS.get(name, name)


def _design_text(values: dict) -> str:
    """``mu=0.05, case=bonded``: numbers to three digits, text as it is (a design variable
    such as foundation.case, formatted as a number, was a traceback)."""
    return ", ".join(f"{k.split('.')[-1]}={v:.3g}" if isinstance(v, int | float)
                     and not isinstance(v, bool) else f"{k.split('.')[-1]}={v}"
                     for k, v in values.items())  # fmt: skip


def pareto_figure(points, objectives, chosen=None, reference=None, title: str = "") -> Figure:
    """Designs in the plane of two objectives: infeasible grey, feasible blue, front joined."""
    fig = Figure(figsize=(6.4, 4.8))
    ax = fig.add_subplot()
    k1, k2 = objectives
    xy = np.array([[p.objectives[k1], p.objectives[k2]] for p in points]).reshape(-1, 2)
    feas = np.array([p.feasible for p in points], dtype=bool)
    front = np.array([p.pareto for p in points], dtype=bool)
    ax.scatter(*xy[~feas].T, s=14, c="0.7", label="violates the constraint")
    ax.scatter(*xy[feas & ~front].T, s=16, c="tab:blue", label="feasible")
    order = np.argsort(xy[front, 0])
    ax.plot(*xy[front][order].T, "o-", c="tab:red", ms=5, label="Pareto front")
    for point, name, style in (
        (reference, "reference", dict(marker="s", mfc="none", ms=11)),
        (chosen, "compromise", dict(marker="*", c="gold", ms=14)),
    ):
        if point is not None:
            x, y = point.objectives[k1], point.objectives[k2]
            label = f"{name} ({_design_text(point.values)})"
            ax.plot(x, y, ls="none", mec="k", label=label, **style)
    ax.set_xlabel(_label(k1))
    ax.set_ylabel(_label(k2))
    ax.set_title(title or "design search")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def fragility_figure(fits, im: str, edp: str, confidence: float, title: str = "") -> Figure:
    """Fitted curves with their pointwise band and the observed exceedance fractions.

    ``fits``: (limit, LognormalFragility or None, im values, exceeded) per limit.
    """
    fig = Figure(figsize=(6.4, 4.6))
    ax = fig.add_subplot()
    all_im = np.concatenate([f[2] for f in fits]) if fits else np.ones(0)
    all_im = all_im if all_im.size else np.ones(1)  # (no run with an IM > 0: an empty chart)
    x = np.geomspace(all_im.min() * 0.5, all_im.max() * 2.0, 200)
    for i, (lim, fit, xs, ys) in enumerate(fits):
        c = f"C{i}"
        name = f"{edp} > {lim:g}" if lim is not None else edp
        xo, fo, _ = exceedance_fractions(xs, ys)
        ax.plot(xo, fo, "o", c=c, ms=4)
        if fit is None:
            ax.plot([], [], "o", c=c, label=f"{name}: no fit")
            continue
        lo, hi = fit.band(x, confidence)
        ax.fill_between(x, lo, hi, color=c, alpha=0.2, lw=0)
        ax.plot(
            x,
            fit.probability(x),
            c=c,
            label=f"{name}: θ={fit.theta:.3g}, β={fit.beta:.2f} ({confidence:.0%} band)",
        )
    ax.set_xscale("log")
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlabel(_label(im))
    ax.set_ylabel("probability of exceedance")
    ax.set_title(title or "fragility")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    return fig


def distribution_figure(table, quantities, title: str = "") -> Figure:
    """Histograms of each quantity over the successful runs, 16/50/84 % marked."""
    n = max(1, len(quantities))
    fig = Figure(figsize=(3.2 * n, 3.2))
    for i, q in enumerate(quantities):
        ax = fig.add_subplot(1, n, i + 1)
        v = table.column(q, False)
        v = v[np.isfinite(v)]
        if v.size:
            ax.hist(v, bins=min(30, max(5, v.size // 4)), color="tab:blue", alpha=0.7)
            for p, ls in ((16, ":"), (50, "-"), (84, ":")):
                ax.axvline(np.percentile(v, p), c="k", ls=ls, lw=1)
        ax.set_xlabel(_label(q), fontsize=8)
        ax.set_ylabel("runs" if i == 0 else "")
    fig.suptitle(title or "distributions", fontsize=9)
    fig.tight_layout()
    return fig


def throughput_figure(rows: list[dict], projection: list[dict]) -> Figure:
    """Left: tasks per second and per-task overhead by engine and batching; right: projected
    wall time of the benchmark's studies against the number of workers."""
    fig = Figure(figsize=(10, 4))
    ax = fig.add_subplot(1, 2, 1)
    labels = [f"{r['engine']}\nbatch {r['batch']}" for r in rows]
    ax.bar(labels, [r["tasks_per_s"] for r in rows], color="tab:blue")
    ax.set_ylabel("tasks per second (40 s CB-5 runs)")
    for i, r in enumerate(rows):
        ax.annotate(
            f"{1e3 * r['overhead_per_task_s']:.0f} ms/task\noverhead",
            (i, r["tasks_per_s"]),
            ha="center",
            va="bottom",
            fontsize=7,
        )
    ax.tick_params(axis="x", labelsize=7)
    ax2 = fig.add_subplot(1, 2, 2)
    for name in dict.fromkeys(p["study"] for p in projection):
        pts = [p for p in projection if p["study"] == name]
        ax2.loglog([p["workers"] for p in pts], [p["wall_s"] for p in pts], "o-", label=name)
    ax2.set_xlabel("workers")
    ax2.set_ylabel("projected wall time [s]")
    ax2.legend(fontsize=7)
    ax2.grid(alpha=0.3, which="both")
    fig.tight_layout()
    return fig
