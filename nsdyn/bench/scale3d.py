"""Cost of the full 3D rung against building size: nsdyn's sparse path and exported OpenSees.

``nsdyn bench scale3d`` (``scale3d.csv``) builds the office building (``frames/office-11-3d``)
and its generated relatives (:func:`building_of_size`: ``by`` × ``bx`` bays of 16 m × 15 m,
floor masses in proportion to the plan, columns meshed into ``n_v`` elements and beams into
``n_h``) from 2 712 to 29 376 nodal dofs (1 788 to 20 664 coordinates after the
diaphragms) on one friction pendulum under every column
(``BEARING``: the office scene's) and runs each on the same three-component record
(``synthetic-wn-40s``, the first ``RECORD_S`` s):

- nsdyn: the full rung on sparse operators (:mod:`nsdyn.models.isolated.pairs_sparse`,
  generalized-α factored once, the isolator rows as a Schur update, the regularised law) with
  the damping ``β K`` on the members of the OpenSees export, at the step ``DT``;
- OpenSees: the exported building on its bearings
  (:func:`nsdyn.models.isolated.opensees3d_isolated.building_data`: elastic beam-columns,
  diaphragms, the base grid, singleFPBearing elements, the same β K, Newmark at ``DT``).

Every run is a whole process (imports, model build, cache load, run, peaks), sizes and tools
interleaved, repeated (median); the cost model ``wall = a n^p`` is fitted per tool on the
whole-process time (:func:`nsdyn.bench.scale.fit_exponent`), and the peaks (isolator
displacement, drift ratios at the centre of mass and the corners, x and y) are compared:
``d = peak / peak_OpenSees − 1``. OpenSees' bearings stick elastically (k_init, 0.1 mm) and
break away at μ_slow N; nsdyn's regularised law has no static coefficient either, so the
two differ by the laws' stick models and by the integrators (Newmark average acceleration
against generalized-α at ρ∞ = 0.8).

Columns of ``scale3d.csv`` (one row per size and tool): ``size`` (``by x bx x n_v x n_h`` of
:func:`building_of_size`), ``n_dof`` (nodal dofs), ``n`` (the sparse system's coordinates,
after the diaphragms), ``isolators`` (one under every column line), ``tool`` (nsdyn or
opensees), ``whole_process_s`` and ``run_s`` (medians of the repeats), ``peak_rss_mb`` (the
largest ``VmHWM``), ``record_s``, ``repeats``, ``quick``, the peaks (``PEAKS``) and, on
nsdyn's rows, ``opensees_over_nsdyn`` (OpenSees' whole-process time over nsdyn's) and each
peak's ``d_*`` (its ratio to OpenSees' minus 1).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from nsdyn.bench import common
from nsdyn.bench.scale import _OS_CHILD, FIT_MIN_SIZES, _child, fit_exponent

__all__ = ["SIZES", "building_of_size", "run_bench", "scale3d_bench"]

OPTIONS = ("repeats", "quiet")
RECORD = "synthetic-wn-40s"
RECORD_S = 4.0
QUICK_RECORD_S = 1.0
DT = 0.005  # s, the fixed step of both
SIZES = ((5, 1, 2, 2), (5, 1, 5, 4), (10, 1, 5, 4), (14, 2, 5, 4))  # (by, bx, n_v, n_h)
QUICK_SIZES = SIZES[:2]
BEARING = {"type": "fps", "radius": 2.2, "mu_slow": 0.04, "mu_fast": 0.07, "rate": 30.0,
           "mu_static": 0.075, "d_cap": 0.35}  # fmt: skip
PEAKS = ("peak_resultant_displacement_m", "peak_drift_cm_x", "peak_drift_cm_y",
         "peak_drift_corner_x", "peak_drift_corner_y")  # fmt: skip


def building_of_size(by: int, bx: int, n_v: int, n_h: int):
    """The office building with ``by`` × ``bx`` bays and mesh (n_v, n_h); (5, 1, 5, 4) is
    the office itself (7 200 dofs, 5 253 after the diaphragms)."""
    import copy

    from nsdyn.structure.frame3d_toml import _read_frame_file, frame3d_from_dict

    data, fname = _read_frame_file("office-11-3d")
    d = copy.deepcopy(data)
    f = d["frame3d"]
    scale = (by * bx) / (len(f["bays_y"]) * len(f["bays_x"]))
    f["floor_mass"] = [m * scale for m in f["floor_mass"]]
    f["bays_y"], f["bays_x"] = [16.0] * by, [15.0] * bx
    f["n_v"], f["n_h"] = n_v, n_h
    if (by, bx) != (5, 1) or (n_v, n_h) != (5, 4):
        f["name"] = f"office-11-3d {by}x{bx} bays, mesh {n_v}/{n_h}"
    return frame3d_from_dict(d, fname)


def motion():
    from nsdyn.models.isolated.deck_scene import build_motion

    return build_motion({"motion": {"kind": "record3", "record": RECORD}}, "<bench>")[0]


def bearing():
    from nsdyn.models.isolated.bearings import bearing_from_config

    return bearing_from_config(dict(BEARING), "bearing")


def with_drift_outputs(s):
    """The sparse pair system ``s`` with its outputs the drift ratios at the centres of mass
    and at the corners (``T``: the info's drift maps)."""
    import dataclasses

    i, n = s.info, s.n
    T = np.vstack([i["drift_cm_map"].reshape(-1, n), i["drift_corner_map"].reshape(-1, n)])
    return dataclasses.replace(s, T=T)


def peaks(s, r) -> dict:
    """:data:`PEAKS` of run ``r`` of :func:`with_drift_outputs` system ``s``."""
    ns = s.info["drift_cm_map"].shape[0]
    o = r.outputs
    cm = np.abs(o[:, : 2 * ns]).reshape(-1, ns, 2).max(axis=(0, 1))
    co = np.abs(o[:, 2 * ns :]).reshape(-1, ns, 4, 2).max(axis=(0, 1, 2))
    return {"peak_resultant_displacement_m": float(r.resultant(r.u).max()),
            "peak_drift_cm_x": float(cm[0]), "peak_drift_cm_y": float(cm[1]),
            "peak_drift_corner_x": float(co[0]), "peak_drift_corner_y": float(co[1])}  # fmt: skip


_CHILD = r"""
import json, resource, sys, time
t_start = time.perf_counter()
from nsdyn.bench import scale, scale3d
from nsdyn.models.isolated.pairs_sparse import building_pairs_sparse
from nsdyn.models.isolated.pairs_sparse_run import simulate_pairs_sparse
size = tuple(int(v) for v in sys.argv[1:5])
t_end = float(sys.argv[5])
frame = scale3d.building_of_size(*size)
s = scale3d.with_drift_outputs(building_pairs_sparse(frame, scale3d.bearing(),
                                                      damping="stiffness"))
t_build = time.perf_counter()
r = simulate_pairs_sparse(s, scale3d.motion(), dt=scale3d.DT, t_end=t_end, keep_q=False)
t_run = time.perf_counter()
out = {"n_dof": int(frame.n_dof), "n": int(s.n), "build_s": t_build - t_start,
       "run_s": t_run - t_build, "setup_s": r.stats["setup_s"], "lu_nnz": r.stats["lu_nnz"],
       "newton_iterations": r.stats["newton_iterations"], **scale3d.peaks(s, r),
       "maxrss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
       "hwm_mb": scale.peak_rss_mb(), "process_s": time.perf_counter() - t_start}
print("RESULT " + json.dumps(out))
"""


def _export(size, t_end: float, out: Path) -> Path:
    from nsdyn.atomic import atomic_open
    from nsdyn.models.isolated.opensees3d_isolated import building_data, script_text_building

    data = building_data(building_of_size(*size), bearing(), motion(), DT, base="grid")
    path = out / f"opensees3d-{'x'.join(map(str, size))}.py"
    with atomic_open(path, "w") as fh:
        fh.write(script_text_building(data, path.name))
    return path


def scale3d_bench(*, quick: bool, out: Path, repeats: int | None = None, quiet=False) -> dict:
    """Run the sizes (interleaved, whole processes); write ``scale3d.csv``."""
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
        common.log(f"nsdyn bench scale3d: OpenSees skipped: {e}", quiet)
        have_os = False
    scripts = {size: _export(size, rec_s, out) for size in sizes} if have_os else {}
    _child(_CHILD, [*map(str, sizes[0]), "0.05"])  # numba cache warm
    runs: dict = {}
    for rep in range(reps):
        for size in sizes:
            for tool in ("nsdyn",) + (("opensees",) if have_os else ()):
                common.log(f"scale3d: {size}, {tool} (repeat {rep + 1}/{reps})", quiet)
                if tool == "opensees":
                    r = _child(_OS_CHILD, [str(scripts[size]), repr(rec_s)])
                else:
                    r = _child(_CHILD, [*map(str, size), repr(rec_s)])
                runs.setdefault((size, tool), []).append(r)
    rows = _rows(runs, rec_s, reps, quick)
    fits = {}
    for tool in ("nsdyn", "opensees"):
        pts = [(r["n_dof"], r["whole_process_s"]) for r in rows if r["tool"] == tool]
        if len(pts) >= FIT_MIN_SIZES:  # (two sizes: a line through two noisy points)
            fits[tool] = fit_exponent(*zip(*pts, strict=True))[0]
    path = common.write_csv_atomic(out / "scale3d.csv", rows)
    res = {"rows": rows, "fits": fits, "csv": str(path), "quick": quick}
    return res


def _rows(runs: dict, rec_s: float, reps: int, quick: bool) -> list[dict]:
    rows = []
    frames = {size: building_of_size(*size) for size, _ in runs}
    for (size, tool), rs in runs.items():
        fr = frames[size]
        row = {"size": "x".join(map(str, size)), "n_dof": fr.n_dof,
               "n": rs[0].get("n", np.nan), "isolators": len(fr.base_nodes), "tool": tool,
               "whole_process_s": float(np.median([r["whole_process_s"] for r in rs])),
               "run_s": float(np.median([r.get("run_s", r.get("wall_s", np.nan)) for r in rs])),
               "peak_rss_mb": float(max(r["hwm_mb"] for r in rs)), "record_s": rec_s,
               "repeats": reps, "quick": quick, **{k: rs[0][k] for k in PEAKS}}  # fmt: skip
        rows.append(row)
    by = {(r["size"], r["tool"]): r for r in rows}
    for r in rows:
        o = by.get((r["size"], "opensees"))
        if r["tool"] == "nsdyn" and o is not None:
            o["n"] = r["n"]  # (the sparse system's coordinates: nsdyn's child says them)
            r["opensees_over_nsdyn"] = o["whole_process_s"] / r["whole_process_s"]
            for k in PEAKS:
                r["d_" + k] = r[k] / o[k] - 1.0 if o[k] else np.nan
    return sorted(rows, key=lambda r: (r["n_dof"], r["tool"]))


def report(res: dict) -> str:
    """The printed table of ``nsdyn bench scale3d``."""
    lines = [f"{'tool':9s} {'dofs':>6s} {'process s':>9s} {'run s':>8s} {'MB':>6s} "
             f"{'OS/nsdyn':>8s}  u_iso  drift cm x/y  corner x/y (d vs OpenSees)"]  # fmt: skip
    for r in res["rows"]:
        if "opensees_over_nsdyn" in r:
            ratio = f"{r['opensees_over_nsdyn']:8.2f}"
            d = " ".join(f"{100 * r.get('d_' + k, np.nan):+6.2f}%" for k in PEAKS)
        else:  # OpenSees' own row (the reference), or nsdyn's without one
            ratio, d = f"{'-':>8s}", "reference" if r["tool"] == "opensees" else "-"
        lines.append(f"{r['tool']:9s} {r['n_dof']:6d} {r['whole_process_s']:9.2f} "
                     f"{r['run_s']:8.2f} {r['peak_rss_mb']:6.0f} {ratio}  {d}")  # fmt: skip
    for tool, p in res["fits"].items():
        lines.append(f"fitted exponent ({tool}, whole process): {p:.2f}")
    if not res["fits"]:
        lines.append(f"no cost exponent: fitted from {FIT_MIN_SIZES} sizes or more")
    from nsdyn.models.isolated.opensees import STICK_DISP

    u = [r["peak_resultant_displacement_m"] for r in res["rows"]]
    if u and max(u) < STICK_DISP:  # (the quick window: 35 and 58 µm, 39 % apart)
        lines.append(f"the isolators did not slide (peaks below {STICK_DISP * 1e3:g} mm, "
                     "OpenSees' elastic stick branch): the peaks compare the two stick "
                     "models, not the slips; run without --quick for the comparison")  # fmt: skip
    return "\n".join(lines)


def summarise(res: dict) -> dict:
    """JSON summary: the rows, the fitted exponents and the file."""
    return {"rows": res["rows"], "fits": res["fits"], "csv": res["csv"]}


run_bench = common.entry_point(scale3d_bench)
