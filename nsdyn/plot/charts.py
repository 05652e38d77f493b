"""Benchmark charts: work–precision of the integrators, the model ladder, stability maps,
the speed table and shooting against sweeps (the data come from :mod:`nsdyn.bench`).

Figures are ``matplotlib.figure.Figure`` objects (no pyplot, no global state).
"""

from __future__ import annotations

import numpy as np

BENCH_STYLE = {
    "radau": ("C0", "o", "-"),
    "dopri5": ("C1", "v", "-"),
    "genalpha": ("C2", "s", "-"),
    "hht": ("C4", "D", "-"),
    "newmark": ("C5", "P", "-"),
    "event": ("C3", "^", "--"),
    "scipy-radau": ("0.4", "x", ":"),
}


def work_precision_figure(rows, floors, records, *, titles, unresolved_factor=3.0):
    """Error vs wall time of ``nsdyn bench accuracy``, one line per method, one column per
    record (``titles[record]`` above it); ``floors[(record, law)]`` holds the reference checks'
    agreement (err_x, err_idr), drawn as horizontal lines; errors below ``unresolved_factor``
    x that agreement are drawn hollow."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.2 * len(records), 8.0))
    axs = np.atleast_2d(fig.subplots(2, len(records), squeeze=False))
    for j, rec in enumerate(records):
        for i, (col, name) in enumerate((("err_x", "x_iso history"), ("err_idr", "peak IDR"))):
            ax = axs[i, j]
            for label in BENCH_STYLE:
                # connected in the order of the setting (loosest first), not of the cost
                run_pts = sorted(
                    (-r["value"], r["wall_s"], r[col])
                    for r in rows
                    if r["record"] == rec
                    and r["label"] == label
                    and r["status"] == "ok"
                    and np.isfinite(r.get(col, np.nan))
                    and r[col] > 0
                )
                pts = [(w, e) for _, w, e in run_pts]
                if not pts:
                    continue
                c, mk, ls = BENCH_STYLE[label]
                lab = label + (" (switch model)" if label == "event" else "")
                ax.plot(*zip(*pts, strict=True), ls=ls, marker=mk, color=c, ms=4, label=lab)
                fl = floors.get((rec, "switch" if label == "event" else "arctan"), {})
                low = [p for p in pts if p[1] < unresolved_factor * fl.get(col, np.nan)]
                if low:
                    ax.plot(*zip(*low, strict=True), ls="", marker=mk, color=c, ms=4, mfc="w")
            for law, ls in (("arctan", ":"), ("switch", "-.")):
                fl = floors.get((rec, law), {})
                if np.isfinite(fl.get(col, np.nan)):
                    ax.axhline(
                        fl[col],
                        color="0.6",
                        ls=ls,
                        lw=0.8,
                        label=f"reference check ({law})",
                    )
            bad = [r for r in rows if r["record"] == rec and r["status"] != "ok"]
            if bad and i == 0:
                ax.text(
                    0.02,
                    0.02,
                    "failed (reported by the code):\n"
                    + "\n".join(
                        f"{r['label']} {r['setting']}={r['value']:g}: {r['status']}" for r in bad
                    ),
                    transform=ax.transAxes,
                    fontsize=6,
                    va="bottom",
                )
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("wall time [s] (after compilation, median)")
            ax.set_ylabel(f"relative error, {name} (hollow: < {unresolved_factor:g}x check)")
            ax.set_title(titles[rec], fontsize=9)
            ax.grid(True, which="both", lw=0.3)
    handles = {}
    for ax in axs.flat:  # one legend below the panels: inside, it hid the slow methods' lines
        for h, lab in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(lab, h)
    fig.legend(list(handles.values()), list(handles), fontsize=7, loc="lower center", ncol=5)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    return fig


def fidelity_figure(rows, *, method):
    """Errors of the peaks against wall time for the model ladder (``nsdyn bench fidelity``),
    one panel per record; ``method``: the integrator every rung ran with (axis label)."""
    from matplotlib.figure import Figure

    recs = list(dict.fromkeys(r["record"] for r in rows))
    fig = Figure(figsize=(5.6 * len(recs), 4.6))
    axs = fig.subplots(1, len(recs), squeeze=False)[0]
    metrics = (
        ("err_xpeak", "x_iso peak", "C0"),
        ("err_idr", "IDR peak", "C2"),
        ("err_acc", "floor acc. peak", "C3"),
    )
    for ax, rec in zip(axs, recs, strict=True):
        mine = [r for r in rows if r["record"] == rec]
        ladder = [
            r for r in mine if not r["model"].startswith("floor") and "rtol" not in r["model"]
        ]
        ok = [r for r in ladder if r["status"] == "ok" and r["model"] != r["reference"]]
        ref = ladder[0]["reference"] if ladder else ""
        for key, name, c in metrics:
            pts = [(r["wall_s"], max(r[key], 1e-9), r["model"]) for r in ok]
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", color=c, ms=4, label=name)
                if key == "err_acc":
                    for w, e, m in pts:
                        ax.annotate(
                            m, (w, e), fontsize=7, xytext=(3, 3), textcoords="offset points"
                        )
        floor = [r for r in mine if "rtol" in r["model"]]
        if floor:
            f0 = np.nanmax([floor[0].get(k, np.nan) for k, _, _ in metrics])
            if np.isfinite(f0):
                ax.axhline(max(f0, 1e-9), color="0.5", ls=":", lw=0.8, label="integration floor")
        ref_wall = next((r["wall_s"] for r in ladder if r["model"] == ref), float("nan"))
        if np.isfinite(ref_wall):
            ax.axvline(ref_wall, color="0.5", ls="--", lw=0.8, label=f"{ref} (reference) cost")
        bad = [r for r in mine if r["status"] != "ok"]
        if bad:
            ax.text(
                0.02,
                0.02,
                "\n".join(f"{r['model']}: {r['status']}" for r in bad),
                transform=ax.transAxes,
                fontsize=7,
                va="bottom",
            )
        ax.set_xscale("log")
        ax.set_yscale("log")
        tol = (f"rtol {ladder[0]['rtol']:g}, atol {ladder[0]['atol_m']:g} m, "
               f"{ladder[0]['atol_mps']:g} m/s" if ladder else "")  # fmt: skip
        ax.set_xlabel(f"wall time [s] ({method}, {tol}, median)", fontsize=8)
        ax.set_ylabel(f"relative error of the peak vs {ref}")
        ax.set_title(f"{rec} record", fontsize=9)
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    return fig


def stability_figure(
    eps_bound, a_bound, cells, drift_hist, shoot_rows, *, methods, dt_top, alpha_eps, accurate
):
    """The maps of ``nsdyn bench stability``: largest stable fixed step against eps and alpha
    (``methods``; ``dt_top`` the top of the scanned range; ``alpha_eps`` the eps of the alpha
    map; dotted: the largest step with err_x <= ``accurate``), the constraint drift histories
    and the cold-start shooting map."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 8.5))
    axs = fig.subplots(2, 2)
    for ax, bound, key, xl in (
        (axs[0, 0], eps_bound, "eps", "arctan sharpness eps [s/m]"),
        (axs[0, 1], a_bound, "alpha", f"Baumgarte alpha [1/s] (eps = {alpha_eps:g})"),
    ):
        for model, ls in (("rigid", "--"), ("cb-5", "-")):
            for method in methods:
                pts = sorted(
                    (b[key], b["dt_max_stable"])
                    for b in bound
                    if b["model"] == model and b["method"] == method
                )
                if not pts:
                    continue
                c, mk, _ = BENCH_STYLE[method]
                ax.plot(
                    *zip(*pts, strict=True),
                    ls=ls,
                    marker=mk,
                    color=c,
                    ms=4,
                    label=f"{method} ({model})",
                )
                acc = sorted(
                    (b[key], b["dt_max_accurate"])
                    for b in bound
                    if b["model"] == model and b["method"] == method
                )
                ax.plot(*zip(*acc, strict=True), ls=":", color=c, lw=0.8, alpha=0.7)
        ax.axhline(dt_top, color="0.5", ls="--", lw=0.6)
        ax.text(
            0.01,
            dt_top,
            " top of the scanned range",
            fontsize=6,
            va="bottom",
            transform=ax.get_yaxis_transform(),
        )
        chk = [c for c in cells if c["map"] == key and c["outcome"].startswith("checked")]
        if chk:
            ax.plot(
                [c[key] for c in chk],
                [c["dt"] for c in chk],
                "kx",
                ms=6,
                label="success reported, energy check failed",
            )
        bad = [c for c in cells if c["map"] == key and c["outcome"] == "garbage"]
        if bad:
            ax.plot(
                [c[key] for c in bad], [c["dt"] for c in bad], "k*", ms=9, label="unflagged garbage"
            )
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xl)
        ax.set_ylabel(f"largest stable fixed step [s] (dotted: err_x <= {accurate:g})")
        ax.grid(True, which="both", lw=0.3)
    for ax in axs[0]:  # both maps: the alpha map has its own markers
        if len(ax.get_lines()) > 1:
            ax.legend(fontsize=6, ncol=2)
    ax = axs[1, 0]
    for (alpha, method, value), (t, Rq) in drift_hist.items():
        ax.semilogy(
            t,
            np.maximum(Rq, 1e-18),
            lw=0.8,
            ls="-" if alpha == 0 else "--",
            label=f"alpha = {alpha:.3g}, {method} {value:g}",
        )
    ax.set_xlabel("t [s]")
    ax.set_ylabel("constraint drift max |R q| [m]")
    ax.legend(fontsize=6)
    ax.grid(True, which="both", lw=0.3)
    ax = axs[1, 1]
    sr = [r for r in shoot_rows if "f_hz" in r]
    if sr:
        for st, mk, c in (("converged", "o", "C2"), ("failed", "x", "C3"), ("error", "s", "k")):
            pts = [(r["f_hz"], r["A_mps2"]) for r in sr if r["status"] == st]
            if pts:
                ax.plot(*zip(*pts, strict=True), mk, color=c, ms=7, ls="", label=st)
        for r in sr:
            if r["status"] != "converged":
                ax.annotate(
                    r["reason"],
                    (r["f_hz"], r["A_mps2"]),
                    fontsize=6,
                    xytext=(3, 3),
                    textcoords="offset points",
                )
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.legend(fontsize=7)
    else:
        msg = shoot_rows[0]["message"] if shoot_rows else "not run"
        ax.text(
            0.5,
            0.5,
            f"periodic module not usable:\n{msg[:80]}",
            ha="center",
            transform=ax.transAxes,
            fontsize=8,
        )
    ax.set_xlabel("forcing frequency f [Hz]")
    ax.set_ylabel("amplitude A [m/s²]")
    ax.set_title("cold-start shooting, CB-5, eps = 7500", fontsize=9)
    fig.tight_layout()
    return fig


def speed_figure(rows, table):
    """``nsdyn bench speed``. Left: err_x against wall time per record (SciPy's rtol search
    as a line, nsdyn at the scene's tolerances as a star); right: the wall times at matched
    accuracy and their ratio."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11.0, 4.4))
    ax, bx = fig.subplots(1, 2)
    recs = [t["record"] for t in table]
    for k, rec in enumerate(recs):
        c = f"C{k}"
        sc = sorted(
            (r["rtol"], r["wall_s"], r["err_x"])
            for r in rows
            if r["record"] == rec
            and r["role"].startswith("scipy")
            and r["status"] == "ok"
            and r["err_x"] > 0
        )[::-1]
        if sc:
            ax.plot([p[1] for p in sc], [p[2] for p in sc], "x:", color=c, ms=5)
            for rt, w, e in sc:
                ax.annotate(
                    f"{rt:.0e}",
                    (w, e),
                    fontsize=6,
                    color=c,
                    xytext=(3, 2),
                    textcoords="offset points",
                )
        ns = next(r for r in rows if r["record"] == rec and r["role"] == "nsdyn")
        if ns["status"] == "ok" and ns["err_x"] > 0:
            ax.plot(ns["wall_s"], ns["err_x"], "*", color=c, ms=11, mec="k", mew=0.5, label=rec)
        chk = next(r for r in rows if r["record"] == rec and r["role"] == "reference-check")
        if np.isfinite(chk.get("err_x", np.nan)) and chk["err_x"] > 0:
            ax.axhline(chk["err_x"], color=c, ls="-", lw=0.5, alpha=0.5)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time [s] (after compilation)")
    ax.set_ylabel("relative error of the x_iso history")
    ax.set_title(
        "★ nsdyn radau (scene tolerances); × SciPy Radau (rtol labelled); thin: reference check",
        fontsize=8,
    )
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=7)
    y = np.arange(len(recs))
    wn = [t["wall_s"] for t in table]
    ws = [t["scipy_wall_s"] if np.isfinite(t["scipy_wall_s"]) else np.nan for t in table]
    bx.barh(y + 0.2, wn, height=0.38, color="C0", label="nsdyn radau")
    bx.barh(y - 0.2, ws, height=0.38, color="0.6", label="SciPy Radau, same or smaller error")
    for k, t in enumerate(table):
        x = np.nanmax([wn[k], ws[k]])
        bx.text(x * 1.15, k, f"{t['ratio_bound']}{t['ratio']:.0f}×", va="center", fontsize=8)
    bx.set_yticks(y, recs, fontsize=8)
    bx.set_ylim(-1.5, len(recs) - 0.3)  # room for the legend below the bars
    bx.set_xscale("log")
    bx.set_xlabel("wall time [s] at matched x_iso error")
    bx.set_xlim(right=bx.get_xlim()[1] * 4)
    bx.legend(fontsize=7, loc="lower right")
    bx.grid(True, which="both", axis="x", lw=0.3)
    fig.tight_layout()
    return fig


PERIODIC_STYLE = {
    "shooting sdirk2": ("C0", "o"),
    "shooting sdirk3": ("C2", "s"),
    "sweep sdirk2": ("C3", "^"),
    "sweep sdirk2 4x steps": ("C1", "v"),
}


def periodic_work_precision_figure(rows):
    """``nsdyn bench periodic``: errors of x_bar_iso (top) and peak IDR (bottom) against the
    wall time of one point, one column per frequency; solid/dashed: the two amplitudes;
    dotted: the reference check."""
    from matplotlib.figure import Figure

    freqs = sorted({r["f_hz"] for r in rows})
    amps = sorted({r["A_mps2"] for r in rows})
    lss = ["-", "--", "-.", ":"]
    fig = Figure(figsize=(3.4 * len(freqs), 6.4))
    axs = fig.subplots(2, len(freqs), squeeze=False)
    for j, f in enumerate(freqs):
        for i, (col, name) in enumerate((("err_xbar", "x̄_iso"), ("err_idr", "peak IDR"))):
            ax = axs[i, j]
            for ia, A in enumerate(amps):
                mine = [r for r in rows if r["f_hz"] == f and r["A_mps2"] == A]
                for label, (c, mk) in PERIODIC_STYLE.items():
                    pts = [
                        (r["wall_s"], r[col])
                        for r in mine
                        if r["label"] == label and r["status"] == "ok" and r.get(col, 0) > 0
                    ]
                    if pts:
                        lab = f"{label}, A = {A:g} m/s²"
                        ax.plot(
                            *zip(*pts, strict=True),
                            ls=lss[ia % 4],
                            marker=mk,
                            color=c,
                            ms=4,
                            lw=1,
                            label=lab,
                        )
                chk = [r for r in mine if r["label"] == "reference-check"]
                if chk and chk[0].get(col, 0) > 0:
                    ax.axhline(chk[0][col], color="0.5", ls=":", lw=0.8)
                bad = [r for r in mine if r["status"] != "ok" and "reference" not in r["label"]]
                for r in bad:
                    ax.annotate(
                        f"{r['label'].split()[0]} {r['value']:g}: {r['status']}",
                        (0.02, 0.02 + 0.05 * bad.index(r)),
                        xycoords="axes fraction",
                        fontsize=5,
                    )
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.grid(True, which="both", lw=0.3)
            if i == 1:
                ax.set_xlabel("wall time per point [s]")
            if j == 0:
                ax.set_ylabel(f"relative error of {name}")
            if i == 0:
                ax.set_title(f"f = {f:g} Hz", fontsize=9)
    from matplotlib.ticker import NullFormatter

    handles = {}
    for ax in axs.flat:
        ax.xaxis.set_minor_formatter(NullFormatter())
        for h, lab in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(lab, h)
    fig.legend(list(handles.values()), list(handles), fontsize=7, loc="lower center", ncol=4)
    fig.tight_layout(rect=(0, 0.06 + 0.025 * (len(handles) // 5), 1, 1))
    return fig
