"""Cost against model size: nsdyn's full-order and CB runs and the exported OpenSees model.

``nsdyn bench scale`` (``scale.csv``, ``scale.png``) builds regular buildings from the office
frame's storeys and sections (:func:`scale_frame`: ``bays`` copies of its 15 m bay, floor
masses scaled with them, every member meshed into ``k`` elements) from the 435-dof office frame
to over 20 000 dofs, and runs each size on the same record (PGA 3 m/s^2, its first ``RECORD_S`` s):

- nsdyn ``genalpha-lowrank`` on the full-order model in nodal coordinates (sparse, factored
  once; :mod:`nsdyn.solve.fullorder`) with the stiffness-proportional damping ``beta K`` of the
  OpenSees export's ``damping="stiffness"`` (the same model), and with nsdyn's modal damping
  (low rank) as a second row (up to ``MODAL_MAX_DOF``: the modes' Lanczos grows fast);
- nsdyn's default Craig-Bampton model (f_max = 5 Hz) with ``method="auto"`` (radau);
- OpenSees: the exported script (:func:`nsdyn.models.isolated.opensees.export_opensees`,
  ``damping="stiffness"``, Newmark at the same dt) on the same record.

Every run is a whole process (``python -c``: imports, model build, numba cache load, run, peaks;
``maxrss`` from ``resource.getrusage`` in that process), sizes and tools interleaved, repeated
(median). Memory: the peak resident set of the child (``VmHWM``, reset by ``exec``) and
``ru_maxrss`` (which Linux carries over from the forking parent, so an upper bound). The
cost model ``wall = a n^p`` is fitted (least squares in log-log) per tool on the
in-process run time and on the whole process; the peaks (isolator displacement, drift ratio,
floor acceleration) are compared with OpenSees' at each size: ``d = peak / peak_OpenSees - 1``.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from nsdyn.bench import common

__all__ = ["FIT_MIN_SIZES", "SIZES", "fit_exponent", "peak_rss_mb", "run_bench", "scale_bench",
           "scale_frame"]  # fmt: skip

OPTIONS = ("repeats", "quiet", "figures")
FIGURES = ("scale.png",)  # the figures it draws (removed under --no-figures)
RECORD_S = 4.0  # s of the bundled record (the window with its PGA)
QUICK_RECORD_S = 2.0
DT = 0.005  # s, the fixed step of nsdyn's full-order runs and of OpenSees
SIZES = ((1, 4, 5), (2, 10, 10), (4, 16, 16), (6, 30, 30), (8, 37, 37))  # (bays, n_h, n_v)
QUICK_SIZES = SIZES[:2]
PEAKS = ("x_iso_max", "idr_max", "floor_acc_max")
TIMEOUT_S = 3600.0
MODAL_MAX_DOF = 5000  # the modal (low-rank) row up to this size (its Lanczos grows fast)


def scale_frame(bays: int, n_h: int, n_v: int):
    """The office frame (``frames/office-11.toml``) widened to ``bays`` bays of 15 m (floor
    masses times ``bays``) and meshed with ``n_v`` elements per column segment and ``n_h`` per
    beam; ``(1, 4, 5)`` is the office frame itself (435 dofs)."""
    from nsdyn.structure import Section, load_frame, regular_frame

    office = load_frame("office-11")
    if (bays, n_h, n_v) == (1, 4, 5):
        return office
    ns = len(office.storey_heights)
    # the office's elements run column by column, storey by storey (regular_frame's order)
    per = 2 * 5 + 4  # elements per storey of the office: 2 columns x n_v, one beam x n_h
    cols, beams = [], []
    for s in range(ns):
        e0 = s * per
        cols.append(Section(office.E[e0], office.A[e0], office.I[e0], office.rho_A[e0]))
        eb = e0 + 2 * 5
        beams.append(Section(office.E[eb], office.A[eb], office.I[eb], office.rho_A[eb]))
    level_mass = [float(office.node_mass[np.asarray(n)].sum()) for n in office.level_nodes[1:]]
    return regular_frame(
        f"office-11 x{bays} bays, mesh {n_v}/{n_h}", [15.0] * bays, office.storey_heights,
        n_v, n_h, cols, beams, [m * bays for m in level_mass], office.zeta,
    )  # fmt: skip


def peak_rss_mb() -> float:
    """This process's peak resident set [MB] (``VmHWM`` of ``/proc/self/status``; NaN where
    there is none)."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmHWM"):
                    return float(line.split()[1]) / 1024.0
    except OSError:
        pass
    return float("nan")


FIT_MIN_SIZES = 3  # sizes a cost exponent is fitted from (two fit any line: --quick's n^0.03)


def fit_exponent(n, wall) -> tuple[float, float]:
    """(p, a) of ``wall = a n^p`` by least squares on ``log wall = log a + p log n``."""
    x, y = np.log(np.asarray(n, float)), np.log(np.asarray(wall, float))
    p, la = np.polyfit(x, y, 1)
    return float(p), float(np.exp(la))


# ---- the child processes ---------------------------------------------------------------------

_CHILD = r"""
import json, resource, sys, time
t_start = time.perf_counter()
from nsdyn.bench import common, scale
from nsdyn.models.isolated.system import build_system
from nsdyn.solve.transient import simulate
bays, n_h, n_v, what, rec_s = sys.argv[1:6]
frame = scale.scale_frame(int(bays), int(n_h), int(n_v))
motion = common.bench_motion("wn", float(rec_s))
iso = common.bench_isolation()
if what == "cb":
    system = build_system(frame, iso, fidelity="cb", f_max=5.0)
    kw = {}
else:
    system = build_system(frame, iso, fidelity="full", damping=what)
    kw = dict(method="genalpha-lowrank", dt=scale.DT)
t0 = time.perf_counter()
r = simulate(system, motion, **kw)
run_s = time.perf_counter() - t0
out = {k: float(getattr(r.response, k)) for k in scale.PEAKS}
out.update(n_dof=int(frame.n_dof), n=int(system.n), method=r.method, run_s=run_s,
           integrate_s=float(r.wall_s), compile_s=float(r.compile_s),
           maxrss_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
           hwm_mb=scale.peak_rss_mb(), process_s=time.perf_counter() - t_start)
print("RESULT " + json.dumps(out))
"""

_OS_CHILD = r"""
import importlib.util, json, resource, sys, time
t_start = time.perf_counter()
spec = importlib.util.spec_from_file_location("osmodel", sys.argv[1])
mod = importlib.util.module_from_spec(spec)
spec.loader.exec_module(mod)
out = mod.run(float(sys.argv[2]))
out["maxrss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
hwm = [ln for ln in open("/proc/self/status").read().splitlines() if ln.startswith("VmHWM")]
out["hwm_mb"] = float(hwm[0].split()[1]) / 1024.0 if hwm else float("nan")
out["process_s"] = time.perf_counter() - t_start
print("RESULT " + json.dumps(out))
"""


def _child(code: str, args: list[str]) -> dict:
    t0 = time.perf_counter()
    p = subprocess.run(
        [sys.executable, "-c", code, *args], capture_output=True, text=True, timeout=TIMEOUT_S
    )
    wall = time.perf_counter() - t0
    lines = [ln for ln in p.stdout.splitlines() if ln.startswith("RESULT ")]
    if p.returncode != 0 or not lines:
        tail = (p.stderr or p.stdout).strip().splitlines()[-1:] or ["no output"]
        raise RuntimeError(f"bench scale: child process failed ({args}): {tail[0]}")
    out = json.loads(lines[-1][len("RESULT ") :])
    out["whole_process_s"] = wall
    return out


def _export(size, rec_s: float, out: Path) -> Path:
    """The OpenSees script of one size (damping "stiffness", step DT)."""
    from nsdyn.atomic import atomic_open
    from nsdyn.models.isolated.opensees import opensees_data, script_text
    from nsdyn.models.isolated.system import build_system

    frame = scale_frame(*size)
    system = build_system(frame, common.bench_isolation(), fidelity="full", damping="stiffness")
    motion = common.bench_motion("wn", rec_s)
    data = opensees_data(system, motion, DT, damping="stiffness", source="nsdyn bench scale")
    path = out / f"opensees_scale_{frame.n_dof}.py"
    with atomic_open(path, "w") as fh:
        fh.write(script_text(data, path.name))
    return path


def _os_run(script: Path, rec_s: float) -> dict:
    r = _child(_OS_CHILD, [str(script), repr(rec_s)])
    r["run_s"] = r["wall_s"]
    r.update({k: r[v] for k, v in (("x_iso_max", "x_iso_max_m"), ("idr_max", "idr_max"),
                                   ("floor_acc_max", "floor_acc_max_mps2"))})  # fmt: skip
    return r


def scale_bench(
    *, quick: bool, out: Path, repeats: int | None = None, quiet=False, figures: bool = True
) -> dict:
    """Run the sizes (interleaved, whole processes); write ``scale.csv`` and (``figures``;
    else ``"png"`` is None) ``scale.png``."""
    from nsdyn.models.isolated.opensees import OpenSeesUnavailable, load_opensees

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    reps = common.timed_repeats(quick, repeats, default=1)
    rec_s = QUICK_RECORD_S if quick else RECORD_S
    sizes = QUICK_SIZES if quick else SIZES
    try:
        load_opensees()
        have_os = True
    except OpenSeesUnavailable as e:
        common.log(f"nsdyn bench scale: OpenSees skipped: {e}", quiet)
        have_os = False
    scripts = {}
    if have_os:
        for size in sizes:
            scripts[size] = _export(size, rec_s, out)
    _child(_CHILD, ["1", "4", "5", "stiffness", repr(min(rec_s, 0.1))])  # numba cache warm
    tools = ["stiffness", "modal", "cb"] + (["opensees"] if have_os else [])
    runs: dict = {}
    for rep in range(reps):
        for size in sizes:
            n_dof = scale_frame(*size).n_dof
            for tool in tools:
                if tool == "modal" and n_dof > MODAL_MAX_DOF:
                    continue
                common.log(f"scale: {n_dof} dofs, {tool} (repeat {rep + 1}/{reps})", quiet)
                if tool == "opensees":
                    r = _os_run(scripts[size], rec_s)
                else:
                    r = _child(_CHILD, [*map(str, size), tool, repr(rec_s)])
                runs.setdefault((n_dof, tool), []).append(r)
    rows = _rows(runs, have_os, rec_s, reps, quick)
    fits = _fits(rows)
    path = common.write_csv_atomic(out / "scale.csv", rows)
    png = str(_figure(rows, fits, out / "scale.png")) if figures else None
    res = {"rows": rows, "fits": fits, "csv": str(path), "png": png, "quick": quick}
    return res


LABELS = {
    "stiffness": "nsdyn full, genalpha-lowrank, beta K",
    "modal": "nsdyn full, genalpha-lowrank, modal (low rank)",
    "cb": "nsdyn CB-5, auto (radau)",
    "opensees": "OpenSees full (exported, beta K)",
}


def _rows(runs: dict, have_os: bool, rec_s: float, reps: int, quick: bool) -> list[dict]:
    rows = []
    for (n_dof, tool), rs in runs.items():
        med = {k: float(np.median([r[k] for r in rs])) for k in ("run_s", "whole_process_s")}
        r0 = rs[0]
        row = {"n_dof": n_dof, "tool": tool, "run": LABELS[tool], **med,
               "maxrss_mb": float(max(r["maxrss_mb"] for r in rs)),
               "peak_rss_mb": float(max(r["hwm_mb"] for r in rs)),
               "record_s": rec_s, "repeats": reps,
               "quick": quick, **{k: r0[k] for k in PEAKS}}  # fmt: skip
        rows.append(row)
    if have_os:
        ref = {r["n_dof"]: r for r in rows if r["tool"] == "opensees"}
        for row in rows:
            o = ref[row["n_dof"]]
            for k in PEAKS:
                row[f"d_{k}"] = row[k] / o[k] - 1.0
            row["os_over_run"] = o["run_s"] / row["run_s"]
            row["os_over_process"] = o["whole_process_s"] / row["whole_process_s"]
    return sorted(rows, key=lambda r: (r["tool"], r["n_dof"]))


def _fits(rows: list[dict]) -> dict:
    fits = {}
    for tool in dict.fromkeys(r["tool"] for r in rows):
        rr = [r for r in rows if r["tool"] == tool]
        if len(rr) >= FIT_MIN_SIZES:
            n = [r["n_dof"] for r in rr]
            fits[tool] = {
                "p_run": fit_exponent(n, [r["run_s"] for r in rr])[0],
                "p_process": fit_exponent(n, [r["whole_process_s"] for r in rr])[0],
            }
    return fits


def _figure(rows, fits, path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from nsdyn.atomic import save_figure

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, key, title in ((axes[0], "run_s", "run (in process)"),
                           (axes[1], "whole_process_s", "whole process")):  # fmt: skip
        for tool in dict.fromkeys(r["tool"] for r in rows):
            rr = [r for r in rows if r["tool"] == tool]
            p = fits.get(tool, {}).get("p_run" if key == "run_s" else "p_process")
            fit = "" if p is None else f" (n^{p:.2f})"  # (none from fewer sizes: not n^nan)
            ax.loglog([r["n_dof"] for r in rr], [r[key] for r in rr], "o-",
                      label=f"{LABELS[tool]}{fit}")  # fmt: skip
        ax.set_xlabel("dofs of the full FE model")
        ax.set_ylabel("wall time [s]")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    out = save_figure(fig, path)
    plt.close(fig)
    return out


def report(res: dict) -> str:
    """The printed table of ``nsdyn bench scale``."""
    lines = [f"{'run':48s} {'dofs':>6s} {'run s':>8s} {'process s':>9s} {'OS/run':>7s} "
             f"{'OS/proc':>7s} {'MB':>6s}  d vs OpenSees (x_iso, IDR, acc)"]  # fmt: skip
    for r in res["rows"]:
        d = " ".join(f"{100 * r.get('d_' + k, np.nan):+6.2f}%" for k in PEAKS)
        lines.append(
            f"{r['run']:48s} {r['n_dof']:6d} {r['run_s']:8.3f} {r['whole_process_s']:9.3f} "
            f"{r.get('os_over_run', np.nan):7.2f} {r.get('os_over_process', np.nan):7.2f} "
            f"{r['peak_rss_mb']:6.0f}  {d}"
        )
    for tool, f in res["fits"].items():
        p_run, p_proc = f["p_run"], f["p_process"]
        lines.append(f"fit {LABELS[tool]}: run ~ n^{p_run:.2f}, process ~ n^{p_proc:.2f}")
    if not res["fits"]:
        lines.append(f"no cost exponent: fitted from {FIT_MIN_SIZES} sizes or more")
    return "\n".join(lines)


def summarise(res: dict) -> dict:
    """JSON summary: the rows, the fitted exponents and the files."""
    return {"rows": res["rows"], "fits": res["fits"], "csv": res["csv"], "png": res["png"]}


run_bench = common.entry_point(scale_bench)
