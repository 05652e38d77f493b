"""Figures of a cylinder run (matplotlib Figure API, no pyplot state).

A 3-D series of snapshots of the body (rotations magnified by a stated factor, since the tilts
are small: θ → λθ about the same axis, q = (cos λθ/2, sin λθ/2 n)), the plan-view trace of the
tilt (θ cos φ, θ sin φ) as in the source study's polar plots, the ground acceleration and the
uplift histories; axes labelled with their units, a legend on every panel with two lines.
"""

from __future__ import annotations

import numpy as np
from matplotlib import colormaps
from matplotlib.figure import Figure

from nsdyn.models.cylinder.simulate import CylinderResult, rotation_matrices

N_RIM = 40  # points on a rim circle
N_GEN = 8  # generator lines drawn on the mantle
TARGET_VISIBLE_TILT = 0.25  # [rad] magnified peak tilt of the snapshots


def _magnified(q: np.ndarray, lam: float) -> np.ndarray:
    """Quaternions with their rotation angle multiplied by lam (same axis)."""
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    q = q * np.sign(q[:, :1] + (q[:, :1] == 0))
    ang = 2 * np.arctan2(np.linalg.norm(q[:, 1:], axis=1), q[:, 0])
    nrm = np.linalg.norm(q[:, 1:], axis=1, keepdims=True)
    ax = np.divide(q[:, 1:], nrm, out=np.zeros_like(q[:, 1:]), where=nrm > 0)
    a = lam * ang[:, None] / 2
    return np.hstack([np.cos(a), np.sin(a) * ax])


def draw_cylinder(ax, R: np.ndarray, base: np.ndarray, r: float, H: float, **kw) -> None:
    """Wireframe of the cylinder (rims and generators) with rotation R and base centre ``base``."""
    s = np.linspace(0, 2 * np.pi, N_RIM)
    ring = np.stack([r * np.cos(s), r * np.sin(s), np.zeros_like(s)])
    for z in (0.0, 2 * H):
        P = R @ (ring + np.array([[0], [0], [z]])) + base[:, None]
        ax.plot(P[0], P[1], P[2], **kw)
        kw.pop("label", None)  # one legend entry per body
    for a in np.linspace(0, 2 * np.pi, N_GEN, endpoint=False):
        seg = np.array([[r * np.cos(a)] * 2, [r * np.sin(a)] * 2, [0.0, 2 * H]])
        P = R @ seg + base[:, None]
        ax.plot(P[0], P[1], P[2], **kw)


def motion_figure(res: CylinderResult, n_snap: int = 6, title: str = "") -> Figure:
    """3-D snapshots around the peak tilt, tilt trace in plan, contact fraction and rim lift."""
    p = res.params
    fig = Figure(figsize=(12, 7.0), layout="constrained")
    gs = fig.add_gridspec(3, 2, width_ratios=[1.3, 1])
    ax3 = fig.add_subplot(gs[:, 0], projection="3d")
    th = res.tilt
    lam = TARGET_VISIBLE_TILT / th.max() if th.max() > 0 else 1.0
    lam = max(lam, 1.0)
    i_pk = int(np.argmax(th))
    span = max(1, int(round(0.5 / (res.t[1] - res.t[0]))))  # half a second around the peak
    idx = np.linspace(max(0, i_pk - span), min(len(th) - 1, i_pk + span), n_snap).astype(int)
    Rm = rotation_matrices(_magnified(res.q[idx], lam))
    cmap = colormaps["viridis"]
    for j, (i, R) in enumerate(zip(idx, Rm, strict=True)):
        base = np.array([0.0, 0.0, lam * res.w[i]])
        draw_cylinder(ax3, R, base, p.r, p.H, color=cmap(j / max(n_snap - 1, 1)), lw=1.0,
                      label=f"t = {res.t[i]:.2f} s")  # fmt: skip
    ext = 0.5 * p.H + p.r
    ax3.set(xlim=(-ext, ext), ylim=(-ext, ext), zlim=(0, 2 * p.H + p.r))
    ax3.set_box_aspect((1, 1, (2 * p.H + p.r) / (2 * ext)))
    ax3.set_title(f"snapshots, rotations magnified ×{lam:.0f}")
    ax3.set_xlabel("x [m]")
    ax3.set_ylabel("y [m]")
    ax3.set_zlabel("z [m]")
    ax3.legend(fontsize=7, loc="upper left")
    axg = fig.add_subplot(gs[0, 1])
    for k, (lab, col) in enumerate((("x", "k"), ("y", "C7"), ("z", "C9"))):
        if np.any(res.ag[:, k]):
            axg.plot(res.t, res.ag[:, k], lw=0.5, color=col, label=f"a_g,{lab}")
    pga = float(np.max(np.hypot(res.ag[:, 0], res.ag[:, 1]))) if len(res.t) else 0.0
    axg.set(xlabel="t [s]", ylabel="ground acc. [m/s²]",
            title=f"ground motion, peak horizontal {pga:.3g} m/s² ({pga / p.g:.3g} g)")  # fmt: skip
    if len(axg.get_lines()) > 1:
        axg.legend(fontsize=7, ncols=3, loc="upper right")
    axp = fig.add_subplot(gs[1, 1])
    phi = res.tilt_dir
    axp.plot(th * np.cos(phi), th * np.sin(phi), lw=0.7)
    axp.set(xlabel="θ cos φ [rad]", ylabel="θ sin φ [rad]", title="tilt trace (plan)")
    axp.set_aspect("equal", adjustable="datalim")
    axu = fig.add_subplot(gs[2, 1], sharex=axg)
    axu.plot(res.t, 1 - res.contact_fraction, label="lifted area / πr² (left)")
    axu.set(xlabel="t [s]", ylabel="lifted area / πr²")
    axr = axu.twinx()
    axr.plot(res.t, 100 * np.maximum(res.rim_lift, 0) / p.r, color="C3", lw=0.7,
             label="rim lift / r [%] (right)")  # fmt: skip
    axr.set_ylabel("rim lift / r [%]", color="C3")
    axu.legend(handles=axu.get_lines() + axr.get_lines(), fontsize=7, loc="upper right")
    if title:
        fig.suptitle(title)
    return fig


# the axes of the peaks compared (stresses over σ_st = m g / (π r²), as peak_stresses gives)
PEAK_LABELS = {"tau_max": "peak τ_max / σ_st [-]", "sigma_1": "peak σ₁ / σ_st [-]",
               "tilt": "peak tilt [rad]",
               "uplift": "peak lifted share of the base [-]"}  # fmt: skip


def comparison_figure(stats: dict, title: str = "") -> Figure:
    """Box-like plot (5/50/95 %) of peak responses per foundation case from ``study`` stats."""
    cases = list(stats)
    keys = [k for k in ("tau_max", "sigma_1", "tilt", "uplift") if k in stats[cases[0]]]
    fig = Figure(figsize=(3.2 * len(keys), 3.4), layout="constrained")
    for j, key in enumerate(keys):
        ax = fig.add_subplot(1, len(keys), j + 1)
        for i, case in enumerate(cases):
            s = stats[case][key]
            ax.plot([i, i], [s["p5"], s["p95"]], color="C0", lw=2)
            ax.plot(i, s["median"], "o", color="C3")
        ax.set_xticks(range(len(cases)), cases, rotation=20)
        ax.set_title(key)
        ax.set_ylabel(PEAK_LABELS.get(key, key))
    if title:
        fig.suptitle(title)
    return fig
