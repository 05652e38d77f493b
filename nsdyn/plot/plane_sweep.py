"""Figure of a deck sweep: peak resultant isolator displacement against the forcing frequency.

Top: max_t |u_i(t)| of the periodic orbit against f (log-log), one colour per amplitude; stable
points on the line, unstable ones as x, stepped-sweep fallbacks as o, points with uplift or a
rim contact (outside the model's validity) as hollow triangles off the line, failures (no
steady state) as vertical ticks at their frequency. Bottom: the stick fraction of each orbit
(0: slipping all period, 1: stuck all period), where the stick–slip transitions lie.
"""

from __future__ import annotations

import numpy as np


def plane_sweep_figure(results: list[dict], title: str = ""):
    """The figure (matplotlib ``Figure``) of :func:`nsdyn.studies.plane_sweep.sweep_plane`'s
    results."""
    from matplotlib import rcParams
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.5, 7.0))
    ax, ax2 = fig.subplots(2, 1, sharex=True, height_ratios=(3, 1))
    colors = rcParams["axes.prop_cycle"].by_key()["color"]
    for k, r in enumerate(sorted(results, key=lambda r: r["A"])):
        col = colors[k % len(colors)]
        rows = r["rows"]
        f = np.array([x["f"] for x in rows], dtype=float)
        u = np.array([x["u_peak_m"] for x in rows], dtype=float)
        bad = np.array([x["uplift"] is True or x["rim_contact"] is True for x in rows])
        ok = np.array([bool(x["converged"]) for x in rows]) & ~bad
        ax.loglog(f, np.where(ok, u, np.nan), "-", color=col, lw=1.3, label=f"A = {r['A']:g} m/s²")
        for sel, style in (
            (np.array([x["stable"] is False for x in rows]) & ok, {"marker": "x", "ls": ""}),
            (np.array([x["method"] == "sweep" for x in rows]) & ok,
             {"marker": "o", "ls": "", "mfc": "none"}),
            (bad & np.isfinite(u), {"marker": "^", "ls": "", "mfc": "none"}),
        ):  # fmt: skip
            if np.any(sel):
                ax.loglog(f[sel], u[sel], color=col, **style)
        for fail in r.get("failures", []):
            ax.axvline(fail["f"], color=col, lw=0.6, ls=":")
        s = np.array([x["stick_fraction"] for x in rows], dtype=float)
        ax2.semilogx(f, s, ".-", color=col, lw=0.8)
    peaks = [x["u_peak_m"] for r in results for x in r["rows"] if x["converged"]]
    peaks = np.array([np.nan if u is None else u for u in peaks], dtype=float)
    finite = peaks[np.isfinite(peaks)]
    if not np.any(finite > 0):  # (nothing to draw on a log axis: matplotlib warned)
        ax.set_yscale("linear")
        if finite.size:  # every orbit found stuck (none found: no word of sticking)
            ax.text(0.5, 0.75, "no slip: every orbit sticks", transform=ax.transAxes, ha="center")
    ax.set_ylabel("peak resultant |u| [m]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    if title:
        ax.set_title(title)
    ax2.set_ylabel("stick fraction")
    ax2.set_ylim(-0.05, 1.05)
    ax2.set_xlabel("forcing frequency f [Hz]")
    ax2.grid(True, which="both", alpha=0.3)
    return fig
