"""Figures of bidirectional isolators: orbits with the capacity circle, hysteresis, torsion.

Top row: the orbit u_y(u_x) of each isolator (up to four, the first ones) with its displacement
capacity |u| = d_cap drawn as a circle and the peak resultant |u| marked. Bottom row: the
resultant slip |u_i|(t), the hysteresis loops of the first isolator (total resisting force
friction + restoring + damper/stop against slip, x and y), and the torsion θ(t) of the deck
or of a pair system's rigid base (none where it has none) with the normal forces N_i(t)
(uplift where one reaches zero).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from nsdyn._checks import expect
from nsdyn.atomic import save_figure
from nsdyn.plot.layout import fixed_margins

MAX_ORBITS = 4


def _arrays(result) -> dict:
    """The arrays of a PlaneResult, or a dict / npz of the same names (``deck.npz``)."""
    result = getattr(result, "result", result)  # (a building's run: run_building(...))
    names = ("t", "q", "u", "N", "friction", "restoring", "other", "d_cap")
    plane = hasattr(result, "summary") and hasattr(result, "u") and hasattr(result, "N")
    keyed = hasattr(result, "keys") and all(k in result for k in names)
    what = f"a PlaneResult (a deck's or building's run) or deck.npz's arrays ({', '.join(names)})"
    expect("result", result, plane or keyed, what)  # (a rocking run: an AttributeError)
    if plane:
        # a deck's q is (x, y, θ, ...); a pair system's q is its own coordinates: the twist
        # of its rigid base where it has one (``twist``), else none
        theta = result.twist if hasattr(result, "twist") else result.q[:, 2]
        return {
            "t": result.t, "theta": theta, "u": result.u, "N": result.N,
            "force": result.friction + result.restoring + result.other,
            "d_cap": np.array([b.d_cap for b in result.system.bearings]),
        }  # fmt: skip
    d = dict(result)
    d["theta"] = d["q"][:, 2]
    d["force"] = d["friction"] + d["restoring"] + d["other"]
    return d


def plane_figure(result, title: str = ""):
    """The figure (matplotlib ``Figure``) of one run (PlaneResult or the arrays of deck.npz)."""
    from matplotlib.figure import Figure

    a = _arrays(result)
    t, u, theta, N, F, cap = a["t"], a["u"], a["theta"], a["N"], a["force"], a["d_cap"]
    ni = u.shape[1]
    no = min(ni, MAX_ORBITS)
    fig = Figure(figsize=(3.2 * max(no, 3), 6.4))
    grid = fig.add_gridspec(2, max(no, 3))
    ru = np.hypot(u[..., 0], u[..., 1])
    for i in range(no):
        ax = fig.add_subplot(grid[0, i])
        ax.plot(1e3 * u[:, i, 0], 1e3 * u[:, i, 1], lw=0.7)
        k = int(np.argmax(ru[:, i]))
        ax.plot(1e3 * u[k, i, 0], 1e3 * u[k, i, 1], "o", ms=4, color="C3",
                label=f"peak |u| = {1e3 * ru[k, i]:.1f} mm")  # fmt: skip
        if np.isfinite(cap[i]):
            th = np.linspace(0, 2 * np.pi, 181)
            ax.plot(1e3 * cap[i] * np.cos(th), 1e3 * cap[i] * np.sin(th), "k--", lw=0.8,
                    label=f"capacity {1e3 * cap[i]:.0f} mm")  # fmt: skip
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("u_x [mm]")
        ax.set_ylabel("u_y [mm]")
        ax.set_title(f"isolator {i}", fontsize=9)
        ax.legend(fontsize=7, loc="upper right")
    ax = fig.add_subplot(grid[1, 0])
    for i in range(ni):
        ax.plot(t, 1e3 * ru[:, i], lw=0.7, label=f"{i}" if ni <= 8 else None)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("|u| [mm] (resultant)")
    if ni <= 8:
        ax.legend(fontsize=7, title="isolator", title_fontsize=7)
    ax = fig.add_subplot(grid[1, 1])
    ax.plot(1e3 * u[:, 0, 0], 1e-3 * F[:, 0, 0], lw=0.7, label="x")
    ax.plot(1e3 * u[:, 0, 1], 1e-3 * F[:, 0, 1], lw=0.7, label="y")
    ax.set_xlabel("u [mm]")
    ax.set_ylabel("bearing force [kN]")
    ax.set_title("hysteresis, isolator 0", fontsize=9)
    ax.legend(fontsize=7)
    ax = fig.add_subplot(grid[1, 2])
    ax.set_xlabel("t [s]")
    ax2 = ax
    # a symmetric deck's twist is round-off (1e-19 rad drawn on a 1e-16 axis offset, as if a
    # response): drawn only above 1e-9 of the slips' scale [rad per m of slip]
    if theta is not None and np.abs(theta).max() <= 1e-9 * max(np.abs(u).max(), 1e-300):
        ax.set_title("no base torsion (round-off)", fontsize=9)
        theta = None
    if theta is not None:
        ax.plot(t, 1e3 * theta, color="k", lw=0.8, label="θ [mrad]")
        ax.set_ylabel("base torsion θ [mrad]")
        ax2 = ax.twinx()
    ax2.plot(t, 1e-3 * N, lw=0.5, alpha=0.6)
    ax2.axhline(0.0, color="C3", lw=0.6)
    ax2.set_ylabel("normal forces N_i [kN]")
    if title:
        fig.suptitle(title, fontsize=10)
    # the twin axis's label on the right; the orbits keep their equal aspect inside their cells
    fixed_margins(fig, 2, max(no, 3), top=0.6 if title else 0.35, right=0.75, wspace=1.15,
                  hspace=0.75)  # fmt: skip
    return fig


def scene_figures(summary: dict, out_dir: str | Path) -> list[str]:
    """Draw ``deck.png`` from the ``deck.npz`` a deck scene wrote; returns the files made."""
    out_dir = Path(out_dir)
    with np.load(out_dir / "deck.npz") as z:
        arrays = {k: z[k] for k in z.files}
    peak = 1e3 * summary["peak_resultant_displacement_m"]
    title = f"{summary.get('name', 'deck')}: peak |u| = {peak:.1f} mm, law {summary['law']}"
    png = save_figure(plane_figure(arrays, title), out_dir / "deck.png")
    return [str(png)]
