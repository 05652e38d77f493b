"""Figures of frames and their responses: mode shapes, transient histories, sweep curves.

Members are drawn deformed by Hermite interpolation of the end displacements and rotations
(the Bernoulli–Euler shape functions), so a few elements per member draw smooth curves.
Figures are ``matplotlib.figure.Figure`` objects (no pyplot, no global state).
"""

from __future__ import annotations

import numpy as np

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


def plot_transient(result):
    """Four panels of a transient run: x_iso, roof drift, normal forces, peak profiles."""
    from matplotlib.figure import Figure

    r = result.response
    fig = Figure(figsize=(10, 7))
    axs = fig.subplots(2, 2)
    ax = axs[0, 0]
    if r.x_iso.size:
        ax.plot(r.t, r.x_iso[:, 0], lw=0.8)
    ax.set_ylabel("x_iso [m]")
    ax.set_xlabel("t [s]")
    ax.set_title(result.system.name, fontsize=9)
    ax = axs[0, 1]
    ax.plot(r.t, r.top_drift, lw=0.8, color="C1")
    ax.set_ylabel("x_top - x_iso [m]")
    ax.set_xlabel("t [s]")
    ax = axs[1, 0]
    for k in range(r.lam.shape[1]):
        ax.plot(r.t, r.lam[:, k] / 1e3, lw=0.8, label=f"contact {k + 1}")
    ax.set_ylabel("normal force [kN]")
    ax.set_xlabel("t [s]")
    if r.lam.shape[1]:
        ax.legend(fontsize=8)
    ax = axs[1, 1]
    n = len(r.idr_by_storey)
    ax.plot(r.idr_by_storey, range(1, n + 1), "o-", ms=3, label="IDR (storey)")
    ax.set_xlabel("peak IDR [-]")
    ax.set_ylabel("storey / level")
    ax2 = ax.twiny()
    ax2.plot(r.floor_acc_by_level, range(len(r.floor_acc_by_level)), "s--", ms=3, color="C3")
    ax2.set_xlabel("peak absolute floor acceleration [m/s²]", color="C3")
    fig.tight_layout()
    return fig


def sweep_figure(results: list[dict], fixed: dict | None = None):
    """``nsdyn sweep``: IDR, a and x_iso against f (log-log), one colour per amplitude.

    Isolated-base periodic solutions solid (unstable points x, sweep-fallback points o);
    ``fixed`` maps an amplitude to :func:`nsdyn.periodic.fixed_base_response` (dashed).
    x_iso is drawn where the isolators slip at some time of the period (as in the seed);
    points with uplift (a negative normal force: outside the contact model) are omitted.
    """
    from matplotlib import rcParams
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.5, 9.5))
    axes = fig.subplots(3, 1, sharex=True)
    colors = rcParams["axes.prop_cycle"].by_key()["color"]
    for k, r in enumerate(sorted(results, key=lambda r: r["A"])):
        col = colors[k % len(colors)]
        rows = r["rows"]
        f = np.array([x["f"] for x in rows])
        idr = np.array([x["IDR"] for x in rows])
        acc = np.array([x["a"] for x in rows])
        xi = np.array([x["x_iso"] for x in rows], dtype=float)
        stick = np.array([x["stick_all_period"] is True for x in rows])
        uplift = np.array([x["uplift"] is True for x in rows])
        idr, acc, xi = (np.where(uplift, np.nan, v) for v in (idr, acc, xi))
        unstable = np.array([x["stable"] is False for x in rows])
        sweep = np.array([x["method"] == "sweep" for x in rows])
        lab = f"A = {r['A']:g} m/s²"
        for ax, y in ((axes[0], idr), (axes[1], acc)):
            ax.loglog(f, y, "-", color=col, lw=1.3, label=lab)
            ax.loglog(f[unstable], y[unstable], "x", color=col, ms=5)
            ax.loglog(f[sweep], y[sweep], "o", mfc="none", color=col, ms=4)
        xs = np.where(stick, np.nan, xi)
        axes[2].loglog(f, xs, "-", color=col, lw=1.3, label=lab)
        axes[2].loglog(f[sweep], xs[sweep], "o", mfc="none", color=col, ms=4)
        if fixed is not None and r["A"] in fixed:
            fb = fixed[r["A"]]
            axes[0].loglog(fb["f"], fb["idr"], "--", color=col, lw=0.8)
            axes[1].loglog(fb["f"], fb["acc"], "--", color=col, lw=0.8)
    axes[0].set_ylabel("IDR [-]")
    axes[1].set_ylabel("a [m/s²]")
    axes[2].set_ylabel("x̄_iso [m] (slip only)")
    axes[2].set_xlabel("f_hor [Hz]")
    axes[0].set_title("periodic solutions (solid), fixed base (dashed); x unstable, o sweep")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    return fig
