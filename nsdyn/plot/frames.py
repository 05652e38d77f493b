"""Figures of frames and their responses: mode shapes and sweep curves (transient runs:
:mod:`nsdyn.plot.transient`).

Members are drawn deformed by Hermite interpolation of the end displacements and rotations
(the Bernoulli–Euler shape functions), so a few elements per member draw smooth curves.
Figures are ``matplotlib.figure.Figure`` objects (no pyplot, no global state).
"""

from __future__ import annotations

import numpy as np

from nsdyn._checks import expect
from nsdyn.plot.layout import fixed_margins
from nsdyn.structure import Frame, rotation

N_SUB = 8  # points per element when drawing deformed (Hermite-interpolated) members
SHAPE_SCALE = 0.08  # largest drawn displacement as a fraction of the frame's size


def deformed_shape(frame: Frame, u: np.ndarray, scale: float, n_sub: int = N_SUB) -> np.ndarray:
    """Deformed member centre lines, shape (ne, n_sub + 1, 2).

    Axial displacement is interpolated linearly and transverse displacement with the
    element's cubic Hermite shape functions, so the drawing is the finite-element solution
    itself, not a polyline through the nodes.
    """
    u = np.asarray(u, float)
    el = frame.elements
    p0, p1 = frame.nodes[el[:, 0]], frame.nodes[el[:, 1]]
    d = p1 - p0
    L = np.hypot(d[:, 0], d[:, 1])
    c, s = d[:, 0] / L, d[:, 1] / L
    ue = u[frame.element_dofs()]  # (ne, 6) global
    ul = np.einsum("eij,ej->ei", rotation(c, s), ue)  # local u1 v1 th1 u2 v2 th2
    xi = np.linspace(0.0, 1.0, n_sub + 1)
    n1, n2 = 1 - 3 * xi**2 + 2 * xi**3, xi - 2 * xi**2 + xi**3
    n3, n4 = 3 * xi**2 - 2 * xi**3, -(xi**2) + xi**3
    ax = ul[:, [0]] * (1 - xi) + ul[:, [3]] * xi
    tr = (
        ul[:, [1]] * n1
        + ul[:, [2]] * L[:, None] * n2
        + ul[:, [4]] * n3
        + ul[:, [5]] * L[:, None] * n4
    )
    base = p0[:, None, :] + xi[None, :, None] * d[:, None, :]
    dx = scale * (ax * c[:, None] - tr * s[:, None])
    dy = scale * (ax * s[:, None] + tr * c[:, None])
    return base + np.stack([dx, dy], axis=-1)


def plot_mode_shapes(frame: Frame, f_hz, Phi: np.ndarray, n: int = 4, ax=None):
    """Draw the first ``n`` mode shapes of ``frame`` side by side.

    Parameters
    ----------
    frame : Frame
    f_hz : array, shape (m,)
        Frequencies [Hz] of the columns of ``Phi``.
    Phi : ndarray, shape (n_dof, m)
        Mode shapes in full-dof order (e.g. from :func:`nsdyn.structure.fixed_base_modes`).
    n : int
        Number of modes to draw (at most m).
    ax : Axes or sequence of Axes, optional
        Where to draw; default a new figure with ``n`` panels.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    n = min(n, Phi.shape[1])
    if ax is None:
        fig = Figure(figsize=(2.4 * n + 0.6, 5.2), layout="constrained")
        axes = np.atleast_1d(fig.subplots(1, n, sharey=True))
    else:
        axes = np.atleast_1d(np.asarray(ax, dtype=object))
        if len(axes) < n:
            raise ValueError(f"need {n} axes, got {len(axes)}")
        fig = axes[0].figure
    size = float(np.ptp(frame.nodes, axis=0).max())
    undeformed = deformed_shape(frame, np.zeros(frame.n_dof), 0.0, n_sub=1)
    for k in range(n):
        a = axes[k]
        phi = Phi[:, k]
        trans = np.abs(np.stack([phi[0::3], phi[1::3]])).max()
        scale = SHAPE_SCALE * size / trans if trans > 0 else 0.0
        for line in undeformed:
            a.plot(line[:, 0], line[:, 1], color="0.8", lw=0.8)
        for line in deformed_shape(frame, phi, scale):
            a.plot(line[:, 0], line[:, 1], color="C0", lw=1.4)
        base = frame.nodes[frame.base_nodes]
        a.plot(base[:, 0], base[:, 1], "k^", ms=6)
        a.set_title(f"mode {k + 1}: {f_hz[k]:.3g} Hz", fontsize=9)
        a.set_aspect("equal", adjustable="datalim")
        a.set_xlabel("x [m]")
    axes[0].set_ylabel("y [m]")
    fig.suptitle(f"{frame.name}: fixed-base mode shapes", fontsize=10)
    return fig


def sweep_figure(results: list[dict], fixed: dict | None = None):
    """``nsdyn sweep``: IDR, a and x_iso against f (log-log), one colour per amplitude;
    ``results`` the sweep's ``{"A": ..., "rows": ...}`` or the curves themselves.

    Isolated-base periodic solutions solid; unstable points x, stepped-sweep fallback points
    o; points with uplift (a normal force <= 0: outside the bilateral contact model) are cut
    out of the lines and drawn as hollow triangles at their bilateral value; ``fixed`` maps
    an amplitude to :func:`nsdyn.periodic.fixed_base_response` (dashed). x_iso is drawn where
    the isolators slip at some time of the period (as in the seed). The legend lists only
    the markers that are drawn (:func:`sweep_markers`).
    """
    from matplotlib import rcParams
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    if hasattr(results, "rows") or isinstance(results, dict):  # one curve
        results = [results]
    elif not isinstance(results, str | bytes) and hasattr(results, "__iter__"):
        results = list(results)  # (a generator, a dict's values)
    if fixed is not None and not isinstance(fixed, dict):  # (a path: failed inside matplotlib)
        raise TypeError(f"fixed: expected a dict amplitude -> fixed_base_response, got "
                        f"{type(fixed).__name__}; save the figure: fig.savefig(path)")  # fmt: skip
    for r in results if isinstance(results, list | tuple) else [results]:  # (a transient run:
        curve = hasattr(r, "rows") or isinstance(r, dict) and {"A", "rows"} <= set(r)  # TypeError)
        expect("results", r, curve, "frequency-response curves (nsdyn.frequency_response) or "
               "nsdyn sweep's results ({'A': amplitude, 'rows': rows} each)")  # fmt: skip
    results = [
        {"A": r.amplitude, "rows": r.rows()} if hasattr(r, "rows") else r for r in results
    ]  # fmt: skip  (curves as the sweep's results)
    fig = Figure(figsize=(7.5, 9.5))
    axes = fig.subplots(3, 1, sharex=True)
    colors = rcParams["axes.prop_cycle"].by_key()["color"]
    drawn = set()
    for k, r in enumerate(sorted(results, key=lambda r: r["A"])):
        col = colors[k % len(colors)]
        rows = r["rows"]
        f = np.array([x["f"] for x in rows])
        raw = {
            "idr": np.array([x["IDR"] for x in rows], dtype=float),  # (0: none on a log axis)
            "acc": np.array([x["a"] for x in rows], dtype=float),
            "xi": np.array([x["x_iso"] for x in rows], dtype=float),
        }
        raw["idr"] = np.where(raw["idr"] > 0.0, raw["idr"], np.nan)  # (a rigid model's 0s)
        stick = np.array([x["stick_all_period"] is True for x in rows])
        raw["xi"] = np.where(stick, np.nan, raw["xi"])
        marks = sweep_markers(rows)
        lab = f"A = {r['A']:g} m/s²"
        for ax, key in ((axes[0], "idr"), (axes[1], "acc"), (axes[2], "xi")):
            y_all = raw[key]
            y = np.where(marks["uplift"], np.nan, y_all)
            ax.loglog(f, y, "-", color=col, lw=1.3, label=lab)
            ok = np.isfinite(y)  # a point between two gaps: no segment draws it, a dot does
            lone = ok & ~np.r_[False, ok[:-1]] & ~np.r_[ok[1:], False]
            if np.any(lone):
                ax.loglog(f[lone], y[lone], ".", color=col, ms=6)
            for name, style in MARKER_STYLES.items():
                sel = marks[name] & np.isfinite(y_all if name == "uplift" else y)
                if np.any(sel):
                    ax.loglog(f[sel], (y_all if name == "uplift" else y)[sel], color=col, **style)
                    drawn.add(name)
        if fixed is not None and r["A"] in fixed:
            fb = fixed[r["A"]]
            axes[0].loglog(fb["f"], fb["idr"], "--", color=col, lw=0.8)
            axes[1].loglog(fb["f"], fb["acc"], "--", color=col, lw=0.8)
            drawn.add("fixed")
    if not any(
        isinstance(x.get("IDR"), int | float) and x["IDR"] > 0 for r in results for x in r["rows"]
    ):  # fmt: skip  (the isolated curves' IDR)
        if not any(np.isfinite(ln.get_ydata()).any() for ln in axes[0].get_lines()):
            axes[0].set_yscale("linear")  # (log-scaling nothing warned; a fixed base's stays)
            axes[0].set_yticks([])
        axes[0].text(0.5, 0.5, "isolated: IDR 0 at every point, the storeys do not deform "
                     "(rigid)", transform=axes[0].transAxes, ha="center", va="center")  # fmt: skip
    axes[0].set_ylabel("IDR [-]")
    axes[1].set_ylabel("a [m/s²]")
    axes[2].set_ylabel("x̄_iso [m] (slip only)")
    axes[2].set_xlabel("f_hor [Hz]")
    axes[0].set_title("periodic solutions of the isolated frame")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    handles = [
        Line2D([], [], color="0.3", label=MARKER_LABELS[name], **MARKER_STYLES[name])
        for name in MARKER_STYLES
        if name in drawn
    ]
    if "fixed" in drawn:
        handles.append(Line2D([], [], color="0.3", ls="--", lw=0.8, label="fixed base"))
    if handles:
        axes[1].legend(handles=handles, fontsize=8)
    elif len(axes[1].get_lines()) > 1:
        axes[1].legend(fontsize=8)  # the amplitudes, as on the first panel
    if len(axes[2].get_lines()) > 1:
        axes[2].legend(fontsize=8)
    fixed_margins(fig, 3, 1, top=0.4, hspace=0.25)
    return fig


MARKER_STYLES = {
    "unstable": dict(marker="x", linestyle="none", ms=5),
    "sweep": dict(marker="o", linestyle="none", mfc="none", ms=4),
    "uplift": dict(marker="^", linestyle="none", mfc="none", ms=5),
    "unilateral": dict(marker="s", linestyle="none", mfc="none", ms=4),
}
MARKER_LABELS = {
    "unstable": "unstable (a Floquet multiplier > 1)",
    "sweep": "stepped-sweep fallback",
    "uplift": "uplift: bilateral value, outside the contact model",
    "unilateral": "lift-off and landing (unilateral stepped sweep)",
}


def sweep_markers(rows: list[dict]) -> dict:
    """Boolean masks of the sweep rows that get a marker: ``unstable`` (stable False),
    ``sweep`` (made by the stepped-sweep fallback), ``uplift`` (a normal force <= 0 on the
    bilateral orbit, not recomputed) and ``unilateral`` (recomputed with lift-off and
    landing; drawn on the curve)."""
    uni = np.array([x.get("method") == "unilateral" for x in rows], dtype=bool)
    return {
        "unstable": np.array([x["stable"] is False for x in rows], dtype=bool),
        "sweep": np.array([x["method"] == "sweep" for x in rows], dtype=bool),
        "uplift": np.array([x["uplift"] is True for x in rows], dtype=bool) & ~uni,
        "unilateral": uni,
    }
