"""The 3D office building in OpenSees (exported script) side by side with nsdyn's building rungs.

``nsdyn bench opensees3d`` (``opensees3d.csv``): the office (``office-11-3d``, 1200 nodes,
1364 members, 11 diaphragms) with a 5 % accidental eccentricity along its length on 12 single
friction pendulums (the bundled example ``building3d-office-rigid.toml``: R = 2.2 m,
mu 0.04–0.07, rate 30 s/m) under the bundled three-component record ``synthetic-wn-40s``,
its first :data:`RECORD_S` seconds (``--quick``: :data:`QUICK_RECORD_S`):

- **isolated**, whole process: ``python model.py`` (the script of
  :func:`~nsdyn.models.isolated.opensees3d_isolated.export_building_opensees`) against
  ``nsdyn run scene.toml`` at the scene's best available rung (``cb`` when the building
  scene offers it, else ``rigid``), interleaved, medians of the repeats, the ratio; and the
  peaks: resultant isolator displacement, resultant base shear, roof corner displacement,
  storey drift ratio at the corners;
- **fixed base**, in process: the same frame clamped (OpenSees: the whole frame, Newmark;
  nsdyn: :func:`~nsdyn.models.isolated.fixed3d.fixed_response_3d`, exact per step, with the
  modal ratios ``beta omega_k / 2`` of the export's beta K): the same linear model on both
  sides, so the peaks must agree (drift, base shear, roof corner displacement).

Columns: ``wall_s`` the whole process's time on the isolated rows (on the fixed rows the
in-process call's: OpenSees' model build and run, nsdyn's modes and response), ``loop_s`` the
isolated rows' time loop alone (the script's and the run's own ``wall_s``), the peaks,
``d_<peak>`` = peak / peak_nsdyn − 1, ``time_ratio`` (isolated rows) = wall / wall_nsdyn (1
on nsdyn's row: OpenSees' says how many times longer it took), and the fixed rung's
``mass_captured_x``/``_y`` (the modal mass share of its modes).

Differences on the isolated rows are the models': a rigid deck has no drift and its roof
moves with the isolators; OpenSees' bearings stick through an elastic branch (k_init, creep
<= 0.1 mm) and break away at mu_slow N where nsdyn's switch law needs mu_static N.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from nsdyn.bench import common

__all__ = ["BEARING", "opensees3d_bench", "report", "run_bench", "summarise"]

OPTIONS = ("repeats", "quiet")
RECORD_S = 10.0  # s of the record (OpenSees takes ~0.2 s per step of the 7200-dof building)
QUICK_RECORD_S = 2.0
DT = 0.005  # s, OpenSees' Newmark step
FRAME = "office-11-3d"
RECORD = "synthetic-wn-40s"
ECCENTRICITY = (0.0, 0.05)
BEARING = {"type": "fps", "radius": 2.2, "mu_slow": 0.04, "mu_fast": 0.07, "rate": 30.0,
           "mu_static": 0.075, "d_cap": 0.35}  # fmt: skip
# nsdyn's fixed rung modes in the fixed-base comparison: the office's x/y/torsion modes at
# 4.1-5.8 Hz lie above a cluster of ~176 local floor-beam modes near 3.9 Hz; with 48 modes
# (up to 3.92 Hz) the corner drift was 2.5 % off OpenSees, with 200 (to 5.8 Hz) 0.35 %
N_MODES_FIXED = 200
PEAKS_ISO = (
    "peak_resultant_displacement_m",
    "peak_base_shear_N",
    "peak_roof_corner_displacement_m",
    "peak_drift_corner_x",
    "peak_drift_corner_y",
)
PEAKS_FIXED = (
    "peak_drift_cm_x",
    "peak_drift_cm_y",
    "peak_drift_corner_x",
    "peak_drift_corner_y",
    "peak_base_shear_x_N",
    "peak_base_shear_y_N",
    "peak_roof_corner_displacement_m",
)


def best_rung() -> str:
    """``cb`` when the building scene offers it, else ``rigid``."""
    from nsdyn.models.isolated.building3d_scene_keys import FIDELITIES

    return "cb" if "cb" in FIDELITIES else "rigid"


def scene_text(fidelity: str, t_end: float) -> str:
    """The benchmark's building3d scene (TOML)."""
    b = "\n".join(f"{k} = {json.dumps(v)}" for k, v in BEARING.items())
    return (
        f'[scene]\nkind = "building3d"\nname = "office-11-3d on 12 friction pendulums"\n\n'
        f'[structure]\nframe3d = "{FRAME}"\nfidelity = "{fidelity}"\n'
        f"eccentricity = [{ECCENTRICITY[0]}, {ECCENTRICITY[1]}]\n\n[bearing]\n{b}\n\n"
        f'[motion]\nkind = "record3"\nrecord = "{RECORD}"\nt_end = {t_end}\n\n'
        '[solver]\nlaw = "switch"\n'
    )


def _timed(cmd: list[str]) -> tuple[float, str]:
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd[:3])}…: exit {p.returncode}: {p.stderr[-800:]}")
    return wall, p.stdout


def _last_json(text: str) -> dict:
    for line in reversed(text.strip().splitlines()):
        if line.startswith("{"):
            return json.loads(line)
    raise RuntimeError(f"no JSON in the output: {text[-400:]}")


def rigid_peaks(scene: Path) -> dict:
    """The rigid rung's peaks in the script's definitions (base shear from the bearings'
    forces, roof corners from the deck's rigid motion; no drift)."""
    from nsdyn.models.isolated import building3d_scene as bs
    from nsdyn.models.isolated.deck import simulate_plane
    from nsdyn.models.scenefile import read_toml

    cfg = read_toml(scene)
    sysd = bs.build_system(cfg, str(scene))
    exc, t_end = bs.build_motion(cfg, str(scene))
    res = simulate_plane(sysd["deck"], exc, t_end=t_end, **bs.build_solver(cfg, str(scene)))
    frame, deck = sysd["frame"], sysd["deck"]
    v = np.nansum(res.friction + res.restoring + res.other, axis=1)  # (nt, 2)
    o = deck.info["origin"]
    lo, hi = frame.nodes[:, :2].min(axis=0), frame.nodes[:, :2].max(axis=0)
    x, y, th = res.q.T
    roof = max(
        float(np.hypot(x - (py - o[1]) * th, y + (px - o[0]) * th).max())
        for px, py in ((lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1]))
    )
    s = res.summary()
    return {"peak_resultant_displacement_m": s["peak_resultant_displacement_m"],
            "peak_base_shear_N": float(np.hypot(v[:, 0], v[:, 1]).max()),
            "peak_roof_corner_displacement_m": roof,
            "peak_drift_corner_x": 0.0, "peak_drift_corner_y": 0.0}  # fmt: skip


def _nsdyn_peaks(rung: str, scene: Path, summary: dict) -> dict:
    if rung == "rigid":
        return rigid_peaks(scene)
    return {k: float(summary[k]) if summary.get(k) is not None else math.nan for k in PEAKS_ISO}


def fixed_comparison(frame, motion, script_module) -> dict:
    """OpenSees' clamped frame against nsdyn's fixed rung with the same damping: peaks and
    in-process walls."""
    from dataclasses import replace

    from nsdyn.models.isolated.fixed3d import fixed_response_3d
    from nsdyn.models.isolated.opensees3d_isolated import rayleigh_zeta
    from nsdyn.structure import fixed_base_modes_3d, floor_motions

    t0 = time.perf_counter()
    os_out = script_module.run()
    os_wall = time.perf_counter() - t0
    t0 = time.perf_counter()
    modes = fixed_base_modes_3d(frame, n_modes=N_MODES_FIXED)
    damped = replace(frame, zeta=rayleigh_zeta(frame, modes.f_hz))
    r = fixed_response_3d(damped, motion, modes=modes)
    ns_wall = time.perf_counter() - t0
    s = r.summary()
    _, c, fm = floor_motions(frame, modes.full())  # (nl, 3, m)
    top = fm[-1] @ r.eta  # (3, nt) about the top level's reference
    lo, hi = frame.nodes[:, :2].min(axis=0), frame.nodes[:, :2].max(axis=0)
    roof = max(
        float(np.hypot(top[0] - (py - c[-1][1]) * top[2], top[1] + (px - c[-1][0]) * top[2]).max())
        for px, py in ((lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1]))
    )
    s["peak_roof_corner_displacement_m"] = roof
    rows = []
    for label, src, wall in (
        ("OpenSees fixed base", os_out, os_wall),
        (f"nsdyn fixed rung ({N_MODES_FIXED} modes)", s, ns_wall),
    ):
        rows.append({"case": "fixed", "run": label, "wall_s": wall,
                     **{k: float(src[k]) for k in PEAKS_FIXED}})  # fmt: skip
    for k in PEAKS_FIXED:
        rows[0][f"d_{k}"] = rows[0][k] / rows[1][k] - 1.0
        rows[1][f"d_{k}"] = 0.0
    rows[1]["mass_captured_x"] = s["mass_captured_x"]
    rows[1]["mass_captured_y"] = s["mass_captured_y"]
    return {"rows": rows, "opensees": os_out}


def opensees3d_bench(*, quick: bool, out: Path, repeats: int | None = None, quiet=False) -> dict:
    """Run the comparison; write ``opensees3d.csv``, the scenes and the scripts into ``out``."""
    from nsdyn.atomic import atomic_open
    from nsdyn.models.isolated.opensees import OpenSeesUnavailable, load_opensees, load_script
    from nsdyn.models.isolated.opensees3d_isolated import export_building_opensees

    try:
        load_opensees()
    except OpenSeesUnavailable as e:
        common.log(f"nsdyn bench opensees3d: {e}", quiet)
        return {"rows": [], "status": "unavailable", "reason": str(e), "files": {}}
    reps = common.timed_repeats(quick, repeats)
    rec_s = QUICK_RECORD_S if quick else RECORD_S
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    rung = best_rung()
    files = {}
    for fid in (rung, "fixed"):
        path = out / f"opensees3d_scene_{fid}.toml"
        with atomic_open(path, "w") as fh:
            fh.write(scene_text(fid, rec_s))
        files[f"scene_{fid}"] = path
    iso_script, fix_script = out / "opensees3d_model.py", out / "opensees3d_model_fixed.py"
    export_building_opensees(files[f"scene_{rung}"], iso_script, dt=DT)
    export_building_opensees(files["scene_fixed"], fix_script, dt=DT)
    files.update(script=iso_script, script_fixed=fix_script)
    os_cmd = [sys.executable, str(iso_script)]
    ns_cmd = [sys.executable, "-c", "import sys; from nsdyn.cli import main; sys.exit(main())",
              "run", str(files[f"scene_{rung}"]), "--json", "--no-figures",
              "--out", str(out / "opensees3d_nsdyn_run")]  # fmt: skip
    common.log(f"warm-up: nsdyn run ({rung}) once, untimed", quiet)
    _timed(ns_cmd)  # numba's cache filled before the timed runs
    os_walls, ns_walls, os_out, ns_out = [], [], None, None
    for k in range(reps):  # interleaved: both see the same machine load
        common.log(f"repeat {k + 1}/{reps}: OpenSees ({rec_s:g} s, dt {DT:g}), nsdyn {rung}",
                   quiet)  # fmt: skip
        w, text = _timed(os_cmd)
        os_walls.append(w)
        os_out = _last_json(text)
        w, text = _timed(ns_cmd)
        ns_walls.append(w)
        ns_out = _last_json(text)
    ns_peaks = _nsdyn_peaks(rung, files[f"scene_{rung}"], ns_out)
    os_w, ns_w = float(np.median(os_walls)), float(np.median(ns_walls))
    rows = [
        {"case": "isolated", "run": "OpenSees (whole frame, bearings)", "wall_s": os_w,
         "loop_s": os_out["wall_s"], **{k: float(os_out[k]) for k in PEAKS_ISO},
         "min_normal_force_N": os_out["min_normal_force_N"]},
        {"case": "isolated", "run": f"nsdyn {rung}", "wall_s": ns_w,
         "loop_s": float(ns_out.get("wall_s", math.nan)), **ns_peaks,
         "min_normal_force_N": ns_out.get("min_normal_force_N")},
    ]  # fmt: skip
    for k in PEAKS_ISO:
        ref = rows[1][k]
        rows[0][f"d_{k}"] = rows[0][k] / ref - 1.0 if ref else math.nan
        rows[1][f"d_{k}"] = 0.0 if ref else math.nan
    rows[0]["time_ratio"], rows[1]["time_ratio"] = os_w / ns_w, 1.0
    common.log("fixed base: OpenSees and nsdyn's fixed rung, in process", quiet)
    from nsdyn.models.isolated.building3d_scene import build_motion, build_system
    from nsdyn.models.scenefile import read_toml

    cfg = read_toml(files["scene_fixed"])
    frame = build_system(cfg, str(files["scene_fixed"]))["frame"]
    motion, _ = build_motion(cfg, str(files["scene_fixed"]))
    fixed = fixed_comparison(frame, motion.window(motion.t0, motion.t0 + rec_s),
                             load_script(fix_script))  # fmt: skip
    rows += fixed["rows"]
    for row in rows:
        row.update(record_s=rec_s, dt=DT, repeats=reps, quick=quick, rung=rung)
    path = common.write_csv_atomic(out / "opensees3d.csv", rows)
    files = {"csv": str(path), **{k: str(v) for k, v in files.items()}}
    return {"rows": rows, "csv": str(path), "files": files, "rung": rung,
            "walls": {"opensees": os_walls, "nsdyn": ns_walls}}  # fmt: skip


_FIXED_HEADS = {"peak_drift_cm_x": "dCM x", "peak_drift_cm_y": "dCM y",
                "peak_drift_corner_x": "dcor x", "peak_drift_corner_y": "dcor y",
                "peak_base_shear_x_N": "V x", "peak_base_shear_y_N": "V y",
                "peak_roof_corner_displacement_m": "roof"}  # fmt: skip


def report(res: dict) -> str:
    """The printed tables of ``nsdyn bench opensees3d``."""
    if not res["rows"]:
        return f"skipped: {res.get('reason', 'no rows')}"
    iso = [r for r in res["rows"] if r["case"] == "isolated"]
    fix = [r for r in res["rows"] if r["case"] == "fixed"]
    lines = [f"isolated ({iso[0]['record_s']:g} s, whole process, median of {iso[0]['repeats']}):",
             f"{'run':34s} {'wall s':>8s} {'ratio':>6s} {'|u| m':>9s} {'V N':>10s} "
             f"{'roof m':>8s} {'corner dx':>9s} {'corner dy':>9s}"]  # fmt: skip
    for r in iso:
        lines.append(
            f"{r['run']:34s} {r['wall_s']:8.2f} {r['time_ratio']:6.1f} "
            f"{r['peak_resultant_displacement_m']:9.5f} {r['peak_base_shear_N']:10.4g} "
            f"{r['peak_roof_corner_displacement_m']:8.4f} {r['peak_drift_corner_x']:9.3e} "
            f"{r['peak_drift_corner_y']:9.3e}"
        )
    lines.append("fixed base (the same linear model; d = OpenSees / nsdyn - 1):")
    heads = [_FIXED_HEADS.get(k, k) for k in PEAKS_FIXED]
    lines.append(f"{'run':34s} {'wall s':>8s}  " + " ".join(f"{h:>6s}" for h in heads))
    for r in fix:
        d = " ".join(f"{100 * r['d_' + k]:+5.2f}%" for k in PEAKS_FIXED)
        lines.append(f"{r['run']:34s} {r['wall_s']:8.2f}  {d}")
    return "\n".join(lines)


def summarise(res: dict) -> dict:
    """JSON summary: the rows (or why there are none)."""
    if not res["rows"]:
        return {"status": res.get("status"), "reason": res.get("reason")}
    return {"rows": res["rows"], "csv": res["csv"], "rung": res["rung"]}


run_bench = common.entry_point(opensees3d_bench)
