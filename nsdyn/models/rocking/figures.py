"""Figures of the rocking family (matplotlib Figure API, no pyplot state): time histories,
overturning spectra and effective restitution against ground stiffness."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure


def history_figure(t, theta, alpha: float, title: str = "", impacts=None, ground=None) -> Figure:
    """theta(t) / alpha with the overturning limits and impact instants; ``ground`` = (t_g,
    a_g [m/s²]) adds the ground acceleration above it (the title may hold two lines)."""
    rows = 2 if ground is not None else 1
    fig = Figure(figsize=(7.5, 2.2 + 2.0 * rows), layout="constrained")
    axs = np.atleast_1d(fig.subplots(rows, 1, sharex=True,
                                     height_ratios=[1, 1.6] if rows == 2 else None))  # fmt: skip
    if ground is not None:
        axg = axs[0]
        axg.plot(ground[0], ground[1], lw=0.7, color="k")
        axg.set_ylabel("ground acc. [m/s²]")
        axg.grid(alpha=0.3)
    ax = axs[-1]
    ax.plot(t, np.asarray(theta) / alpha, lw=1.0, label="θ / α")
    ax.axhline(1.0, color="0.6", lw=0.6, ls="--", label="θ = ±α (weight over the pivot)")
    ax.axhline(-1.0, color="0.6", lw=0.6, ls="--")
    if impacts is not None and len(impacts):
        ax.plot(impacts[:, 0], np.zeros(len(impacts)), "|", color="C3", ms=6, label="impacts")
    ax.legend(loc="upper right", fontsize=7)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("θ / α")
    ax.grid(alpha=0.3)
    if title:
        fig.suptitle(title, fontsize=10)
    return fig


def spectrum_figure(spectra: dict, title: str = "") -> Figure:
    """Minimum overturning amplitude a_p / (g tan alpha) (g alpha if linearised) against
    omega_p / p; ``spectra`` maps a
    label to an :class:`~nsdyn.models.rocking.spectra.OverturningSpectrum`. Frequencies without
    overturning up to a_max get a triangle at a_max (not a gap), a band safe up to a_max is
    drawn to a_max, and the search's resolution is written under the axes."""
    fig = Figure(figsize=(6.5, 4.2), layout="constrained")
    ax = fig.add_subplot()
    notes = []
    one = len(spectra) == 1  # one spectrum: its name in the title, short legend entries
    for k, (label, sp) in enumerate(spectra.items()):
        pre = "" if one else f"{label}: "
        x = sp.omega_ratio
        ax.plot(x, sp.a_min_ratio, "-", color=f"C{k}", label=f"{pre}minimum")
        hi = np.where(np.isnan(sp.safe_hi_ratio) & np.isfinite(sp.safe_lo_ratio), sp.a_max,
                      sp.safe_hi_ratio)  # fmt: skip
        if np.any(np.isfinite(sp.safe_lo_ratio)):
            ax.fill_between(x, sp.safe_lo_ratio, hi, color=f"C{k}", alpha=0.2,
                            lw=0, label=f"{pre}safe band above")  # fmt: skip
        m1 = sp.mode == 1
        if np.any(m1):
            ax.plot(x[m1], sp.a_min_ratio[m1], "o", ms=3, color=f"C{k}", mfc="white",
                    label=f"{pre}overturns after an impact (mode 1)")  # fmt: skip
        none = np.isnan(sp.a_min_ratio)
        if np.any(none):
            ax.plot(x[none], np.full(int(none.sum()), sp.a_max), "^", ms=5, color=f"C{k}",
                    label=f"{pre}no overturning up to a_max = {sp.a_max:g}")  # fmt: skip
        notes.append(f"{label}: scan x{sp.scan:g} up to a_max = {sp.a_max:g}, refined where "
                     f"the overturning mode changes, edges to {sp.rtol:g}")  # fmt: skip
    fig.supxlabel("\n".join(notes), fontsize=7, color="0.3")  # below the axes, given room
    ax.set_xlabel("ω_p / p")
    units = {sp.unit.replace("alpha", "α") for sp in spectra.values()}
    ax.set_ylabel(f"a_p / ({units.pop()})" if len(units) == 1 else "a_p / lift-off acceleration")
    head = "minimum overturning amplitude" + (f": {next(iter(spectra))}" if one else "")
    ax.set_title(title or head, fontsize=10)
    ax.legend(fontsize=7, loc="upper left")
    return fig


def restitution_figure(ratios, r_eff: dict, r_housner: float, r_seed=None) -> Figure:
    """Effective restitution of the block on corner supports against omega_v / p."""
    fig = Figure(figsize=(6.0, 3.6), layout="constrained")
    ax = fig.add_subplot()
    for label, r in r_eff.items():
        ax.semilogx(ratios, r, "o-", ms=4, label=label)
    ax.axhline(r_housner, color="k", lw=0.8, ls="--", label=f"Housner {r_housner:.3f}")
    if r_seed is not None:
        ax.axhline(r_seed, color="C3", lw=0.8, ls=":", label=f"seed 001 model 1: {r_seed:.3f}")
    ax.set_xlabel("ω_v / p (vertical contact frequency / rocking frequency parameter)")
    ax.set_ylabel("effective r")
    ax.legend(fontsize=8)
    return fig
