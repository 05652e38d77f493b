"""Figures of contact runs (Figure objects, no pyplot state): mode history and body snapshots."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from nsdyn.models.contact.results import MODE_NAMES, TILT_FLOOR, slenderness


def tilt_limits(theta, alpha: float) -> tuple[float, float]:
    """y limits of the tilt axis [rad]: the data with a margin, never narrower than
    ±TILT_FLOOR alpha, so round-off tilts (1e-15 rad) stay a flat line at zero."""
    peak = float(np.max(np.abs(theta))) if len(theta) else 0.0
    half = max(1.1 * peak, TILT_FLOOR * alpha)
    return -half, half


def ground_history(motion, t: np.ndarray) -> np.ndarray:
    """Horizontal ground acceleration [m/s²] of a BaseMotion at the times ``t`` (the kernels'
    own evaluation, :func:`nsdyn.models.contact._kgeom.ground_acc`)."""
    from nsdyn.models.contact._kgeom import ground_acc

    return np.array([ground_acc(float(x), motion.ex, motion.tab_h, motion.tab_v)[0] for x in t])


def history_figure(res, body, title: str = "", n_snap: int = 8, motion=None) -> Figure:
    """Tilt, slide and mode against time, and snapshots of the body (ground frame); with the
    ``motion`` (a BaseMotion) its horizontal acceleration above, velocity jumps marked."""
    fig = Figure(figsize=(9, 8.6 if motion is not None else 7), layout="constrained")
    if motion is not None:
        axg, *ax = fig.subplots(5, 1, height_ratios=[1.4, 2, 2, 1, 2])
        axg.plot(res.t, ground_history(motion, res.t), lw=0.7, color="k",
                 label="ground acceleration")  # fmt: skip
        if len(motion.jumps):
            axg.plot(motion.jumps[:, 0], np.zeros(len(motion.jumps)), "|", color="C3", ms=10,
                     label="ground velocity jump (impulse)")  # fmt: skip
            axg.legend(fontsize=7, loc="upper right")
        axg.set_ylabel("ground acc. [m/s²]")
        axg.grid(alpha=0.3)
        axg.tick_params(labelbottom=False)
    else:
        ax = fig.subplots(4, 1, height_ratios=[2, 2, 1, 2])
    alpha = slenderness(body)
    ax[0].plot(res.t, res.q[:, 2], lw=1)
    ax[0].set_ylim(*tilt_limits(res.q[:, 2], alpha))
    ax[0].set_ylabel("tilt θ [rad]")
    if np.max(np.abs(res.q[:, 2]), initial=0.0) < TILT_FLOOR * alpha:
        ax[0].text(0.01, 0.92, f"|θ| < {TILT_FLOOR:.0%} of α = {alpha:.3g} rad: no rocking",
                   transform=ax[0].transAxes, fontsize=8, va="top", color="0.3")  # fmt: skip
    ax[1].plot(res.t, 1e3 * res.slide, lw=1)
    ax[1].set_ylabel("slide [mm]")
    ax[2].step(res.t, res.mode, where="post", lw=1)
    ax[2].set_yticks(range(len(MODE_NAMES)), MODE_NAMES, fontsize=7)
    for a in ax[:2]:
        a.tick_params(labelbottom=False)
    ax[2].set_xlabel("t [s]")
    for a in ax[:3]:
        a.grid(alpha=0.3)
    idx = np.linspace(0, len(res.t) - 1, n_snap).astype(int)
    span = float(np.ptp(body.verts[:, 0])) * 1.6
    for k, i in enumerate(idx):
        x, y, th = res.q[i]
        c, s = np.cos(th), np.sin(th)
        p = body.verts @ np.array([[c, s], [-s, c]]) + [x + k * span, y]
        ax[3].fill(p[:, 0], p[:, 1], alpha=0.5)
        ax[3].text(k * span, -0.15 * span, f"{res.t[i]:.2f} s", ha="center", fontsize=7)
    ax[3].axhline(0, color="k", lw=1)
    ax[3].set_aspect("equal")
    ax[3].axis("off")
    fig.suptitle(title, fontsize=10)
    return fig
