"""The uplift boundary chart: critical amplitude A*(f) against the forcing frequency.

``A*(f)`` (:mod:`nsdyn.periodic.uplift`) is the smallest amplitude of ``A sin(2 pi f t)`` at
which the steady periodic orbit's smallest isolator normal force reaches zero,
``min_t min_k lam_k(t) = 0``; above it (shaded) an isolator lifts off. Frequencies where no
uplift occurred up to the search limit ``a_hi`` and frequencies whose search failed (no orbit
found at some amplitude) get their own markers; the legend lists only what is drawn.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from nsdyn.atomic import save_figure


def status_text(status: str, a_hi: float, unit: str) -> str:
    """A point's status in words for tables and legends: the search limit named by its value
    (``no uplift below a_hi`` -> ``no uplift up to A = 30 m/s²``)."""
    return status.replace("below a_hi", f"up to A = {a_hi:g} {unit}")


def _columns(result) -> dict:
    """Arrays of an :class:`nsdyn.periodic.uplift.UpliftBoundary` or of its ``to_dict()``."""
    d = result if isinstance(result, dict) else result.to_dict()
    d = dict(d, points=sorted(d["points"], key=lambda p: p["f_hz"]))  # lines run along f

    def col(key):
        return np.array([math.nan if p[key] is None else p[key] for p in d["points"]], float)

    return {
        "f": col("f_hz"),
        "a": col("a_crit"),
        "below": col("a_below"),
        "fail": col("a_fail"),
        "status": [p["status"] for p in d["points"]],
        "stable": [p["stable_below"] for p in d["points"]],
        "a_hi": float(d["a_hi"]),
        "model": d.get("model", ""),
        "unit": "N" if "force" in d.get("excitation", "") else "m/s²",
    }


def uplift_boundary_figure(result, path: str | Path | None = None, *, dpi: int = 120):
    """Draw A*(f) on a log frequency axis; save it as PNG to ``path`` (atomically) if given.

    ``result``: an ``UpliftBoundary`` or its ``to_dict()``. Returns the matplotlib figure.
    """
    from matplotlib.figure import Figure

    c = _columns(result)
    f, a, a_hi = c["f"], c["a"], c["a_hi"]
    ok = np.array([s == "ok" for s in c["status"]])
    none = np.array([s.startswith("no uplift") for s in c["status"]])
    failed = ~ok & ~none
    finite = a[ok] if ok.any() else np.zeros(0)
    top = 1.1 * max(a_hi, float(finite.max()) if finite.size else 0.0)
    fig = Figure(figsize=(7.0, 4.6))
    ax = fig.subplots()
    if ok.any():
        y = np.where(ok, a, np.nan)
        ax.fill_between(
            f, y, top, where=ok, color="tab:red", alpha=0.15, lw=0, label="isolators lift off"
        )
        lone = ok & ~np.r_[False, ok[:-1]] & ~np.r_[ok[1:], False]  # no ok neighbour to fill to
        if lone.any():
            ax.vlines(f[lone], a[lone], top, color="tab:red", alpha=0.15, lw=6)
        ax.plot(f, y, "-o", color="tab:red", ms=3.5, lw=1.4, label="A*(f): min normal force = 0")
        unstable = ok & np.array([s is False for s in c["stable"]])
        if unstable.any():
            ax.plot(f[unstable], a[unstable], "s", mfc="none", color="k", ms=6,
                    label="orbit unstable below A*")  # fmt: skip
    if none.any():
        ax.plot(f[none], np.full(none.sum(), a_hi), "^", color="tab:green", ms=6,
                label=f"no uplift up to A = {a_hi:g} {c['unit']}")  # fmt: skip
    if failed.any():
        yf = np.where(np.isfinite(c["fail"]), c["fail"], c["below"])[failed]
        ax.plot(f[failed], yf, "X", color="k", ms=7, ls="none",
                label="search failed (no orbit found at this A)")  # fmt: skip
    ax.axhline(a_hi, color="0.5", lw=0.8, ls=":", label=f"search limit A = {a_hi:g} {c['unit']}")
    ax.set_xscale("log")
    ax.set_ylim(0.0, top)
    if f.size:
        ax.set_xlim(f.min() / 1.15, f.max() * 1.15)
    ax.set_xlabel("forcing frequency f [Hz]")
    ax.set_ylabel(f"amplitude A [{c['unit']}]")
    ax.set_title(f"uplift boundary{' — ' + c['model'] if c['model'] else ''}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="center right")
    fig.tight_layout()
    if path is not None:
        save_figure(fig, path, dpi=dpi)
    return fig
