"""The full 435-dof frame at factor-once cost: generalized-alpha (low-rank Newton) against radau.

``nsdyn bench full-model`` (``full_model.csv``): the full model (nodal coordinates, every
fixed-interface mode damped; :mod:`nsdyn.models.isolated.fullorder`) of the office frame under
the bundled 40 s record (PGA 3 m/s^2) with ``genalpha-lowrank`` on its sparse operators
(:mod:`nsdyn.solve.fullorder`) at dt 0.005 and 0.0025, radau (dense kernels) at the transient
defaults on a window of ``RADAU_WINDOW_S`` s (its time scaled to the whole record, said in the
row), and the CB-5 model with radau on the whole record. Wall times are medians of
``--repeats`` runs in one process; the factorisation (``setup_s``) and numba compilation
(``warmup_s``) are reported apart. Accuracy: relative errors of the peaks (isolator
displacement, IDR, floor acceleration) against radau on the common window::

    err_k = |peak_k / peak_k^radau - 1|

Columns of ``full_model.csv``: ``run`` (the model, method and step), ``model`` (its
fidelity), ``n_dof``, ``method``, ``window_s`` (the simulated time of the row), ``n_steps``,
``wall_s`` (median wall of the row's run), ``setup_s`` (its factorisations), ``compile_s``
(the kernels compiled or loaded by the row's own run: 0 after the warm-up), ``wall_40s_s``
(the wall for the whole record, 40 s, or 3 s with ``--quick``; radau's window scaled to it,
``scaled`` true), ``x_iso_max``, ``idr_max``, ``floor_acc_max`` (the peaks) and their
``err_*`` against radau (rows on the window), ``build_full_s`` (building the full model),
``warmup_s`` (the numba compilation or cache load before the timed runs), ``repeats``,
``quick``.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from nsdyn.bench import common

__all__ = ["full_model_bench", "run_bench"]

OPTIONS = ("repeats", "quiet")  # options run_bench takes
RECORD_S = 40.0  # s, the bundled record's length
QUICK_RECORD_S = 3.0  # s, --quick: the window with the PGA
RADAU_WINDOW_S = 6.0  # s, radau on the full model (~5 s of wall per simulated second)
LOWRANK_DTS = (0.005, 0.0025)  # s, steps of the factor-once method
PEAKS = ("x_iso_max", "idr_max", "floor_acc_max")


def _timed(system, motion, repeats, **kw):
    from nsdyn.solve import sparse
    from nsdyn.solve.transient import simulate

    walls, setups, res = [], [], None
    for _ in range(max(1, repeats)):
        sparse.setup_stats(reset=True)
        sparse._CACHE.clear()  # every repeat pays its own factorisation
        t0 = time.perf_counter()
        r = simulate(system, motion, **kw)
        walls.append(time.perf_counter() - t0)
        setups.append(sparse.setup_stats()["setup_s"])
        res = res or r
    return res, float(np.median(walls)), float(np.median(setups))


def _row(label, r, wall, setup, window, ref=None, scaled_to=None):
    row = {
        "run": label,
        "model": r.system.fidelity,
        "n_dof": r.system.n,
        "method": r.method,
        "window_s": window,
        "n_steps": r.n_steps,
        "wall_s": wall,
        "setup_s": setup,
        "compile_s": r.compile_s,
        "wall_40s_s": wall * (scaled_to / window) if scaled_to else wall,
        "scaled": bool(scaled_to and scaled_to != window),
    }
    for k in PEAKS:
        row[k] = float(getattr(r.response, k))
        if ref is not None:
            row[f"err_{k}"] = abs(row[k] / float(getattr(ref.response, k)) - 1.0)
    return row


def full_model_bench(*, quick: bool, out: Path, repeats: int | None = None, quiet=False) -> dict:
    """Run the comparison; write ``full_model.csv`` into ``out``; return the rows."""
    from nsdyn.models.isolated.system import build_system
    from nsdyn.solve.sparse import METHOD

    reps = common.timed_repeats(quick, repeats)
    rec_s = QUICK_RECORD_S if quick else RECORD_S
    win_s = min(RADAU_WINDOW_S, rec_s)
    frame = common.bench_frame()
    t0 = time.perf_counter()
    full = build_system(frame, common.bench_isolation(), fidelity="full")
    build_s = time.perf_counter() - t0
    cb5 = common.cb5_system(frame)
    compile_s = common.warmup(["radau", METHOD])
    motion = common.bench_motion("wn", rec_s)
    window = common.bench_motion("wn", win_s)
    rows = []
    common.log(f"full model: radau on {win_s:g} s", quiet)
    ref, w, _ = _timed(full, window, 1, method="radau")
    rows.append(_row("full radau", ref, w, 0.0, win_s, scaled_to=rec_s))
    for dt in LOWRANK_DTS:
        common.log(f"full model: {METHOD} dt {dt:g} on {win_s:g} s and {rec_s:g} s", quiet)
        r, w, su = _timed(full, window, 1, method=METHOD, dt=dt)
        rows.append(_row(f"full {METHOD} dt={dt:g} (window)", r, w, su, win_s, ref))
        r, w, su = _timed(full, motion, reps, method=METHOD, dt=dt)
        rows.append(_row(f"full {METHOD} dt={dt:g}", r, w, su, rec_s))
    common.log(f"CB-5: radau on {rec_s:g} s", quiet)
    r, w, _ = _timed(cb5, motion, reps, method="radau")
    rows.append(_row("cb-5 radau", r, w, 0.0, rec_s))
    for row in rows:
        row.update(build_full_s=build_s, warmup_s=compile_s, repeats=reps, quick=quick)
    path = common.write_csv_atomic(Path(out) / "full_model.csv", rows)
    return {"rows": rows, "csv": str(path)}  # (the table: report)


def _table(rows: list[dict]) -> str:
    """A short table of the rows: wall time of the run and of the whole record (the radau
    window's scaled, marked *), the factorisation, and the peaks' errors against radau on
    the window (rows on the window only; - elsewhere)."""
    rec = max(r["window_s"] for r in rows)
    errs_head = " ".join(f"{'err ' + k.removesuffix('_max'):>13s}" for k in PEAKS)
    lines = [f"{'run':41s} {'steps':>6s} {'wall s':>8s} {f'{rec:g} s rec':>9s} {'setup':>6s} "
             f"{errs_head}"]  # fmt: skip
    for r in rows:
        errs = " ".join(f"{r[f'err_{k}']:13.1e}" if f"err_{k}" in r else f"{'-':>13s}"
                        for k in PEAKS)  # fmt: skip
        tag = "*" if r["scaled"] else " "
        whole = r["window_s"] == rec or r["scaled"]  # (a window's row: its own time alone)
        rec_s = f"{r['wall_40s_s']:8.2f}" if whole else f"{'-':>8s}"
        lines.append(
            f"{r['run']:41s} {r['n_steps']:6d} {r['wall_s']:8.3f} {rec_s}{tag} "
            f"{r['setup_s']:6.3f} {errs}"
        )
    if any(r["scaled"] for r in rows):
        lines.append("* scaled from the radau window to the whole record")
    return "\n".join(lines)


def report(res: dict) -> str:
    """The printed table of ``nsdyn bench full-model``."""
    return _table(res["rows"])


run_bench = common.entry_point(full_model_bench)
