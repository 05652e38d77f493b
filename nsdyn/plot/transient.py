"""The figure of a transient run of the isolated frame: what shook it, how it moved, against what.

Panels, only those the model defines (a shear building without contact rows has no normal
forces, a model without levels no profiles):

- the ground acceleration u''_g(t) [m/s²] (horizontal; vertical when the record has one), or
  the force F(t) [N] of a force excitation;
- the isolator slip x_iso(t) = D_i q [m], one line per isolator;
- the top drift x_top - x_iso [m] (eq 17), and, given a fixed-base run, the fixed-base top
  displacement relative to the ground (the same quantity without isolation);
- the normal forces lam_k(t) [kN] of the contact rows;
- the peak interstorey drift ratio per storey (the storey drift [m] without storey heights)
  and the peak absolute floor acceleration per level, isolated and fixed-base.

The title names the model, the excitation and its PGA. A panel with more than one line has a
legend. Figures are ``matplotlib.figure.Figure`` objects (no pyplot, no global state).
"""

from __future__ import annotations

import math

import numpy as np

from nsdyn._checks import expect
from nsdyn.plot.layout import fixed_margins

G = 9.81  # [m/s²], for the PGA in g of the title


def is_force(motion) -> bool:
    """A force excitation (HarmonicForce, ForceTable: a load vector) rather than the ground's."""
    return hasattr(motion, "load_vector")


def excitation_history(motion, t: np.ndarray) -> dict:
    """``{label: (t, values)}`` of the excitation: the ground acceleration [m/s²] of a record
    or a harmonic motion, or the force [N] of a force excitation; ``{}`` for none."""
    if motion is None:
        return {}
    if is_force(motion):
        if isinstance(getattr(motion, "F", None), np.ndarray):  # ForceTable
            return {"force": (motion.t0 + motion.dt * np.arange(motion.F.size), motion.F)}
        w = 2 * math.pi * motion.f
        return {"force": (t, motion.F * np.sin(w * t + motion.phase))}
    a_hor = getattr(motion, "a_hor", None)
    if isinstance(a_hor, np.ndarray):
        tm = np.asarray(motion.t)
        out = {"horizontal": (tm, a_hor)}
        if getattr(motion, "a_ver", None) is not None:
            out["vertical"] = (tm, motion.a_ver)
        return out
    if hasattr(motion, "A_hor") and hasattr(motion, "f_hor"):  # Harmonic
        w = 2 * math.pi * motion.f_hor
        out = {"horizontal": (t, motion.A_hor * np.sin(w * t + motion.phase))}
        if motion.A_ver:
            wv = 2 * math.pi * motion.f_ver
            out["vertical"] = (t, motion.A_ver * np.sin(wv * t + motion.phase_ver))
        return out
    return {}


def title_of(result, motion) -> str:
    """``model under record, t = t0-t1 s (PGA a m/s² = b g)``: what the figure shows, in one
    line."""
    if is_force(motion):
        if isinstance(getattr(motion, "F", None), np.ndarray):
            return f"{result.system.name}: force {motion.name} (peak " \
                   f"{np.max(np.abs(motion.F)):.4g} N)"  # fmt: skip
        return f"{result.system.name}: harmonic force {motion.F:.4g} N at {motion.f:g} Hz"
    name = getattr(motion, "name", None)
    what = f"{result.system.name} under {name}" if name else result.system.name
    t = getattr(result, "t", None)
    if name and t is not None and len(t) > 1:  # (the run's span: 20 s of a 40 s record)
        what += f", t = {float(t[0]):.4g}-{float(t[-1]):.4g} s"
    pga = getattr(motion, "pga", None)
    if pga is None and hasattr(motion, "A_hor"):
        pga = abs(motion.A_hor)
    if pga is not None and np.isfinite(pga):
        what += f" (PGA {pga:.3g} m/s² = {pga / G:.3g} g)"
    return what


def _legend(ax) -> None:
    if len(ax.get_lines()) > 1:
        ax.legend(fontsize=7)


def plot_transient(result, motion=None, *, fixed=None, note: str | None = None,
                   alert: bool = False):  # fmt: skip
    """The figure of a transient run (module text).

    Parameters
    ----------
    result : TransientResult
        The run (:func:`nsdyn.simulate`).
    motion : GroundMotion or Harmonic, optional
        Its excitation: drawn in the first panel, named with its PGA in the title.
    fixed : TransientResult, optional
        A run of the fixed-base model (``build_system(frame, fidelity="fixed")``) under the
        same motion, drawn dashed for comparison.
    note : str, optional
        A second title line (e.g. the outcome).
    alert : bool
        Draw the title in red (the run left the model's domain, e.g. uplift).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure
    from matplotlib.ticker import MaxNLocator

    for name, run in (("result", result), ("fixed", fixed)):  # (a rocking run: AttributeError)
        expect(name, run, run is None and name == "fixed" or hasattr(run, "response"),
               "a TransientResult of an isolated frame (nsdyn.simulate); a deck's or building's "
               "run is drawn by nsdyn.plot.isolators.plane_figure")  # fmt: skip
    r = result.response
    fr = fixed.response if fixed is not None else None
    ground = excitation_history(motion, r.t)
    panels = []
    if ground:
        panels.append("ground")
    if r.x_iso.size:
        panels.append("x_iso")
    if np.all(np.isfinite(r.top_drift)):
        panels.append("drift")
    if r.lam.shape[-1]:
        panels.append("lam")
    if r.idr_by_storey.size or r.drift_by_storey.size:
        panels.append("storeys")
    if r.floor_acc_by_level.size:
        panels.append("levels")
    n_cols = 2 if len(panels) > 2 else 1
    n_rows = max(1, math.ceil(len(panels) / n_cols))
    fig = Figure(figsize=(10.5 if n_cols == 2 else 7, 2.9 * n_rows + 0.8))
    axes = np.atleast_1d(fig.subplots(n_rows, n_cols)).ravel()
    fixed_margins(fig, n_rows, n_cols, top=0.6 if note else 0.4)
    for ax in axes[len(panels) :]:
        ax.remove()
    iso, fb = "isolated", "fixed base"
    for ax, kind in zip(axes, panels, strict=False):
        if kind == "ground":
            for (lab, (tg, a)), col in zip(ground.items(), ("k", "C7"), strict=False):
                ax.plot(tg, a, lw=0.6, color=col, label=lab)
            ax.set_ylabel("force [N]" if is_force(motion) else "ground acceleration [m/s²]")
        elif kind == "x_iso":
            for k in range(r.x_iso.shape[1]):
                ax.plot(r.t, r.x_iso[:, k], lw=0.8, label=f"isolator {k + 1}")
            ax.set_ylabel("isolator slip x_iso [m]")
        elif kind == "drift":
            ax.plot(r.t, r.top_drift, lw=0.8, color="C1", label=f"{iso}: x_top - x_iso")
            if fr is not None and np.all(np.isfinite(fr.top_drift)):
                ax.plot(fixed.response.t, fr.top_drift, "--", lw=0.8, color="C0",
                        label=f"{fb}: x_top")  # fmt: skip
            ax.set_ylabel("top drift [m]")
        elif kind == "lam":
            for k in range(r.lam.shape[1]):
                ax.plot(r.t, r.lam[:, k] / 1e3, lw=0.8, label=f"contact {k + 1}")
            ax.set_ylabel("normal force [kN]")
        elif kind == "storeys":
            ratio = bool(r.idr_by_storey.size)
            y = r.idr_by_storey if ratio else r.drift_by_storey
            ax.plot(y, np.arange(1, y.size + 1), "o-", ms=3, color="C1", label=iso)
            if fr is not None:
                yf = fr.idr_by_storey if ratio else fr.drift_by_storey
                if yf.size == y.size:
                    ax.plot(yf, np.arange(1, y.size + 1), "s--", ms=3, color="C0", label=fb)
            ax.set_xlabel("peak interstorey drift ratio [-]" if ratio else "peak storey drift [m]")
            ax.set_ylabel("storey")
            ax.yaxis.set_major_locator(MaxNLocator(integer=True))
            ax.xaxis.set_major_locator(MaxNLocator(nbins=5))  # drift ratios: long labels
            ax.set_xlim(left=0.0)
        else:  # levels
            a = r.floor_acc_by_level
            ax.plot(a, np.arange(a.size), "o-", ms=3, color="C1", label=iso)
            if fr is not None and fr.floor_acc_by_level.size:
                af = fr.floor_acc_by_level
                lv = np.arange(a.size - af.size, a.size)  # the fixed base has no isolation level
                ax.plot(af, lv, "s--", ms=3, color="C0", label=fb)
            ax.set_xlabel("peak absolute floor acceleration [m/s²]")
            ax.set_ylabel("level (0 = base)")
            ax.yaxis.set_major_locator(MaxNLocator(integer=True))
            ax.set_xlim(left=0.0)
        if kind not in ("storeys", "levels"):
            ax.set_xlabel("t [s]")
        ax.grid(True, alpha=0.3)
        _legend(ax)
    head = title_of(result, motion)
    fig.suptitle(head + (f"\n{note}" if note else ""), fontsize=10, color="C3" if alert else "k")
    return fig
