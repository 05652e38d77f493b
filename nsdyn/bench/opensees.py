"""The full frame in OpenSees (exported script) against nsdyn full and nsdyn's default CB-5 run.

``nsdyn bench opensees`` (``opensees.csv``): the office frame's full FE model (435 dofs) on the
benchmark isolators under the bundled record (PGA 3 m/s^2; ``--quick``: its first 3 s):

- OpenSees: the script of :func:`nsdyn.models.isolated.opensees.export_opensees`, run in this
  process (Newmark, flatSliderBearing; time of the step loop), with the export's modal damping
  and with its stiffness-proportional alternative;
- nsdyn full, ``genalpha-lowrank`` at the same dt, output every step;
- nsdyn full with the export's (modal) damping (:func:`~nsdyn.models.isolated.opensees.
  opensees_damping`): the same
  model as OpenSees but for the friction regularisation, the contact penalty and the
  integrator; and that model with a 10x sharper arctan law (closer to Coulomb);
- nsdyn CB-5 (13 dofs), radau at the run defaults: the default run.

Wall times are medians of repeats after a warm-up (numba compilation and OpenSees' first
model build excluded). Differences are relative to nsdyn full: ``d = peak / peak_full - 1``;
``time_ratio = wall_OpenSees / wall`` (the ``OS/run`` column of the printed table), against
the first row, OpenSees with the export's modal damping, for every row (its β K row: the modal
run's time over the β K run's).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from nsdyn.bench import common

__all__ = ["opensees_bench", "report", "run_bench", "summarise"]

OPTIONS = ("repeats", "quiet")
RECORD_S = 40.0  # s, the bundled record
QUICK_RECORD_S = 3.0  # s, --quick
DT = 0.005  # s, the step of both fixed-step runs
SHARP_EPS_FACTOR = 10.0  # arctan sharpness multiplier of the "closer to Coulomb" row
PEAKS = ("x_iso_max", "idr_max", "floor_acc_max")
_OS_KEYS = {"x_iso_max": "x_iso_max_m", "idr_max": "idr_max", "floor_acc_max": "floor_acc_max_mps2"}


def _nsdyn(system, motion, reps, **kw):
    from nsdyn.solve import sparse
    from nsdyn.solve.transient import simulate

    walls, res = [], None
    for _ in range(max(1, reps)):
        sparse._CACHE.clear()  # every repeat pays its own factorisation
        t0 = time.perf_counter()
        r = simulate(system, motion, **kw)
        walls.append(time.perf_counter() - t0)
        res = res or r
    peaks = {k: float(getattr(res.response, k)) for k in PEAKS}
    return peaks, float(np.median(walls)), res.n_steps


def _opensees(module, reps):
    walls, totals, out = [], [], None
    for _ in range(max(1, reps)):
        t0 = time.perf_counter()
        out = module.run()
        totals.append(time.perf_counter() - t0)
        walls.append(out["wall_s"])
    peaks = {k: float(out[v]) for k, v in _OS_KEYS.items()}
    return peaks, float(np.median(walls)), float(np.median(totals)), out["n_steps"]


def opensees_bench(*, quick: bool, out: Path, repeats: int | None = None, quiet=False) -> dict:
    """Run the comparison; write ``opensees.csv`` and the script into ``out``; return rows."""
    from nsdyn.atomic import atomic_open
    from nsdyn.models.isolated.opensees import (
        DAMPINGS,
        OpenSeesUnavailable,
        load_opensees,
        load_script,
        opensees_damping,
        opensees_data,
        script_text,
    )
    from nsdyn.models.isolated.system import build_system
    from nsdyn.solve.sparse import METHOD

    try:
        load_opensees()  # before any work
    except OpenSeesUnavailable as e:  # an optional extra: `nsdyn bench all` goes on
        common.log(f"nsdyn bench opensees: {e}", quiet)
        return {"rows": [], "status": "unavailable", "reason": str(e), "files": {}}
    reps = common.timed_repeats(quick, repeats)
    rec_s = QUICK_RECORD_S if quick else RECORD_S
    frame = common.bench_frame()
    iso = common.bench_isolation()
    full = build_system(frame, iso, fidelity="full")
    motion = common.bench_motion("wn", rec_s)
    out = Path(out)
    modules = {}
    for damping in DAMPINGS:
        data = opensees_data(full, motion, DT, damping=damping, source="nsdyn bench opensees")
        script = out / f"opensees_model_{damping}.py"
        with atomic_open(script, "w") as fh:
            fh.write(script_text(data, script.name))
        modules[damping] = (load_script(script), data, script)
    module, data, script = modules["modal"]
    compile_s = common.warmup(["radau", METHOD])
    module.build(module.load_opensees())  # OpenSees' first model build, untimed
    rows = []
    common.log(f"OpenSees: full model, Newmark dt {DT:g} on {rec_s:g} s", quiet)
    for damping, label in (("modal", "OpenSees full"), ("stiffness", "OpenSees full, beta K")):
        p, w, total, n = _opensees(modules[damping][0], reps)
        rows.append({"run": label, "n_dof": 3 * len(data["nodes"]), "steps": n, "wall_s": w,
                     "setup_s": total - w, **p})  # fmt: skip
    kw = dict(method=METHOD, dt=DT, dt_out=DT)
    cases = [
        ("nsdyn full", full, kw),
        ("nsdyn full, export's damping", opensees_damping(full, data), kw),
        (
            f"nsdyn full, export's damping, eps x{SHARP_EPS_FACTOR:g}",
            opensees_damping(full.with_isolation(eps=iso.eps * SHARP_EPS_FACTOR), data),
            kw,
        ),
        ("nsdyn CB-5 (default radau)", common.cb5_system(frame), dict(dt_out=DT)),
    ]
    for label, system, kwargs in cases:
        common.log(f"{label} on {rec_s:g} s", quiet)
        p, w, n = _nsdyn(system, motion, reps, **kwargs)
        rows.append({"run": label, "n_dof": system.n, "steps": n, "wall_s": w, "setup_s": 0.0, **p})
    ref = rows[2]
    for row in rows:
        for k in PEAKS:
            row[f"d_{k}"] = row[k] / ref[k] - 1.0
        row["time_ratio"] = rows[0]["wall_s"] / row["wall_s"]
        row.update(record_s=rec_s, dt=DT, repeats=reps, quick=quick, warmup_s=compile_s)
    path = common.write_csv_atomic(out / "opensees.csv", rows)
    files = {"csv": str(path), **{f"script_{k}": str(v[2]) for k, v in modules.items()}}
    res = {"rows": rows, "csv": str(path), "files": files}
    return res


def report(res: dict) -> str:
    """The printed table of ``nsdyn bench opensees``."""
    if not res["rows"]:
        return f"skipped: {res.get('reason', 'no rows')}"
    lines = [
        f"{'run':44s} {'dofs':>5s} {'wall s':>8s} {'OS/run':>7s} {'x_iso m':>9s} {'IDR':>9s} "
        f"{'acc m/s2':>8s}  d vs nsdyn full (x_iso, IDR, acc)"
    ]
    for r in res["rows"]:
        d = " ".join(f"{100 * r['d_' + k]:+6.1f}%" for k in PEAKS)
        lines.append(
            f"{r['run']:44s} {r['n_dof']:5d} {r['wall_s']:8.3f} {r['time_ratio']:7.2f} "
            f"{r['x_iso_max']:9.5f} {r['idr_max']:9.3e} {r['floor_acc_max']:8.3f}  {d}"
        )
    return "\n".join(lines)


def summarise(res: dict) -> dict:
    """JSON summary: the rows (or why there are none)."""
    if not res["rows"]:
        return {"status": res.get("status"), "reason": res.get("reason")}
    return {"rows": res["rows"], "csv": res["csv"]}


run_bench = common.entry_point(opensees_bench)
