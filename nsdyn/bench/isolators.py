"""Benchmark of bidirectional isolators: work–precision of the two laws, cost per isolator.

1. A rigid deck (2000 t, 20 m × 12 m, eccentric, h = 1.5 m) on four single friction pendulums
   (R = 2.2 m, μ 4–7 % velocity-dependent, μ_s 7.5 %) under the bundled 40 s three-component
   record: the switch law with its stick disc (events located on the dense output) and the
   regularised arctan law (ε = 7500 s/m) over rtol 1e-4 … 1e-8; error against the switch law
   at rtol 1e-10, err = max_t,i |u_i − u_i^ref| / max_t,i |u_i^ref| (resultant slip vectors).
   The regularised law's error levels off at its own modelling error (creep in stick). Also
   the error of the peak resultant slip, err_peak = |peak / peak_ref − 1|: the switch law's
   history error is set by where late, small slips come to rest (their stick instants move
   with the tolerance), its peak is resolved to the tolerance.
2. Cost per isolator: the same deck mass on n × n isolators on a grid (n = 2, 3, 4, 6), both
   laws at rtol 1e-6: wall time per run and per isolator. Then the deck on four triple friction
   pendulums (the scene deck-tfp4-3c's bearings; regularised law on Radau IIA, the series
   model's eight internal slips per isolator) at the same rtol: its cost per isolator as a
   ratio to the single pendulum's in the same run (regularised law, and switch law).
3. The planar model's cost, the baseline: the seed's office frame at the rigid fidelity (the
   building as a rigid body on its two isolators, 3 dofs) under the record's first horizontal
   component, the switch law on the event method and the arctan law on Radau IIA at their
   default tolerances, and the deck's time (rtol 1e-6, same law) as a ratio to it.
4. The regularised law's velocity tolerance (full form only): the deck at rtol 1e-6 with atol_v
   1e-8, the default PLANE_ATOL and the cap ATOL_V_EPS / eps, its error against the law's own
   solution at rtol 1e-11, atol 1e-13 (the integrator's error, not the law's).
Wall times are medians of repeats after a first run that compiles (or loads) the kernels; the
compile/load time is reported apart. Writes ``isolators-wp.csv``, ``isolators-scale.csv`` and
``isolators-wp.png`` (unless ``figures`` is False) through nsdyn.atomic.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from nsdyn.atomic import save_figure
from nsdyn.bench.common import write_csv_atomic
from nsdyn.ground import read_motion3
from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.deck import PLANE_ATOL, rigid_deck, simulate_plane
from nsdyn.models.isolated.defaults import EPS
from nsdyn.models.isolated.tfp import TripleBearing
from nsdyn.models.isolated.tolerances import ATOL_V_EPS

RECORD = "synthetic-wn-40s"
RTOLS = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
RTOLS_QUICK = (1e-4, 1e-6)
RTOL_REF = 1e-10
GRIDS = (2, 3, 4, 6)  # n x n isolators
GRIDS_QUICK = (2, 4)
REPEATS = 5
OPTIONS = ("repeats", "quiet", "figures")
FIGURES = ("isolators-wp.png",)  # the figures it draws (removed under --no-figures)
BEARING = Bearing(Friction(0.04, mu_fast=0.07, rate=30.0, mu_static=0.075), radius=2.2)
TRIPLE = dict(R1=2.2, R2=0.3, R3=0.3, R4=2.2, mu1=0.06, mu2=0.02, mu3=0.02, mu4=0.10, d1=0.40,
              d2=0.06, d3=0.06, d4=0.40)  # fmt: skip


def deck(n: int = 2, bearing=None):
    """The benchmark deck on n x n isolators over 20 m x 12 m (``bearing``: BEARING)."""
    X, Y = np.meshgrid(np.linspace(-10, 10, n), np.linspace(-6, 6, n))
    pos = np.column_stack([X.ravel(), Y.ravel()])
    m = 2.0e6
    b = BEARING if bearing is None else bearing
    return rigid_deck(m, m * (400 + 144) / 12, pos, b, ecc=(0.8, 0.5), h=1.5)


def triple_row(motion, scale: list, reps: int) -> dict:
    """The deck on four triple pendulums (regularised law, rtol 1e-6) and its cost per isolator
    over the single pendulum's at n = 2 in ``scale`` (same run, same laws' settings)."""
    dt = deck(2, TripleBearing(**TRIPLE))
    simulate_plane(dt, {"f": 1.0, "ax": 0.1, "ay": 0.1}, t_end=0.05, law="arctan")
    res, wall = _timed(lambda: simulate_plane(dt, motion, law="arctan"), reps)
    single = {r["law"]: r["wall_s"] for r in scale if r["n_isolators"] == 4}
    return {"n_isolators": 4, "wall_s": wall, "wall_per_isolator_s": wall / 4,
            "ratio_to_single_arctan": wall / single["arctan"],
            "ratio_to_single_switch": wall / single["switch"],
            "steps": res.stats["steps"], "peak_u_m": _peak(res)}  # fmt: skip


def planar_rows(scale: list, reps: int) -> list[dict]:
    """The planar baseline (module text, part 3): the rigid office frame's wall time per law and
    the four-pendulum deck's (``scale``, n = 2) over it."""
    from nsdyn import Isolation, build_system, load_frame, read_motion, simulate

    frame, motion = load_frame("office-11"), read_motion(RECORD)
    deck4 = {r["law"]: r["wall_s"] for r in scale if r["n_isolators"] == 4}
    rows = []
    for law, method in (("switch", "event"), ("arctan", "radau")):
        system = build_system(frame, Isolation(law=law), fidelity="rigid")
        simulate(system, motion.window(0.0, 0.05), method=method)  # compiles or loads
        res, wall = _timed(lambda s=system, m=method: simulate(s, motion, method=m), reps)
        rows.append({"law": law, "method": method, "wall_s": wall,
                     "deck_over_planar": deck4[law] / wall,
                     "peak_u_m": res.summary()["x_iso_max_m"]})  # fmt: skip
    return rows


def atol_rows(d4, motion, reps: int) -> list[dict]:
    """Part 4 of the module text: the regularised law at rtol 1e-6 for three velocity
    tolerances, errors against the law's own converged solution."""
    own = simulate_plane(d4, motion, law="arctan", rtol=1e-11, atol=(1e-13, 1e-13))
    rows = []
    for atol_v in (1e-8, PLANE_ATOL["arctan"][1], ATOL_V_EPS / EPS):
        at = (PLANE_ATOL["arctan"][0], atol_v)
        res, wall = _timed(lambda at=at: simulate_plane(d4, motion, law="arctan", atol=at), reps)
        rows.append({"atol_q": at[0], "atol_v": atol_v, "wall_s": wall, "err": _err(res, own),
                     "err_peak": abs(_peak(res) / _peak(own) - 1),
                     "steps": res.stats["steps"]})  # fmt: skip
    return rows


def _err(res, ref) -> float:
    return float(np.max(np.abs(res.u - ref.u)) / np.max(np.abs(ref.u)))


def _peak(res) -> float:
    return res.summary()["peak_resultant_displacement_m"]


def _timed(fn, repeats: int):
    walls = []
    for _ in range(repeats):
        tic = time.perf_counter()
        res = fn()
        walls.append(time.perf_counter() - tic)
    return res, float(np.median(walls))


def run_bench(
    out_dir: Path,
    quick: bool,
    repeats: int | None = None,
    quiet: bool = True,
    figures: bool = True,
) -> dict:
    """Run both parts; returns the numbers and the paths of the files written (the chart only
    with ``figures``)."""
    out_dir = Path(out_dir)
    reps = repeats or (2 if quick else REPEATS)
    motion = read_motion3(RECORD)
    d4 = deck(2)
    compile_s = {}
    for law in ("switch", "arctan"):
        tic = time.perf_counter()
        simulate_plane(d4, {"f": 1.0, "ax": 0.1, "ay": 0.1}, t_end=0.05, law=law)
        compile_s[law] = time.perf_counter() - tic
    ref = simulate_plane(d4, motion, law="switch", rtol=RTOL_REF, atol=(1e-12, 1e-12))
    rows = []
    for law in ("switch", "arctan"):
        for rtol in RTOLS_QUICK if quick else RTOLS:

            def run(law=law, rtol=rtol):
                return simulate_plane(d4, motion, law=law, rtol=rtol)

            res, wall = _timed(run, reps)
            rows.append({"law": law, "rtol": rtol, "wall_s": wall, "err": _err(res, ref),
                         "err_peak": abs(_peak(res) / _peak(ref) - 1), "peak_u_m": _peak(res),
                         "steps": res.stats["steps"], "events": res.stats["events"]})  # fmt: skip
            if not quiet:
                print(f"isolators: {law} rtol {rtol:g}: {wall:.4f} s, err {rows[-1]['err']:.2e}")
    scale = []
    for n in GRIDS_QUICK if quick else GRIDS:
        dn = deck(n)
        for law in ("switch", "arctan"):
            res, wall = _timed(lambda dn=dn, law=law: simulate_plane(dn, motion, law=law), reps)
            scale.append({"law": law, "n_isolators": n * n, "wall_s": wall,
                          "wall_per_isolator_s": wall / (n * n), "steps": res.stats["steps"],
                          "events": res.stats["events"]})  # fmt: skip
    triple = triple_row(motion, scale, reps)
    planar = planar_rows(scale, reps)
    tol = [] if quick else atol_rows(d4, motion, reps)
    if not quiet:
        print(
            f"isolators: 4 triple pendulums: {triple['wall_s']:.4f} s, "
            f"{triple['ratio_to_single_arctan']:.2f} x the single pendulum's (arctan)"
        )
    files = [
        write_csv_atomic(out_dir / "isolators-wp.csv", rows),
        write_csv_atomic(out_dir / "isolators-scale.csv", scale),
    ]
    if figures:
        files.append(save_figure(figure(rows), out_dir / "isolators-wp.png"))
    if tol:
        files.append(write_csv_atomic(out_dir / "isolators-atol.csv", tol))
    return {"rows": rows, "scale": scale, "triple": triple, "planar": planar, "atol": tol,
            "compile_s": compile_s,
            "record": RECORD,
            "ref_peak_u_m": ref.summary()["peak_resultant_displacement_m"],
            "files": [str(f) for f in files]}  # fmt: skip


def figure(rows):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.5, 4.0), layout="constrained")
    ax = fig.add_subplot()
    for law, mk in (("switch", "o-"), ("arctan", "s--")):
        r = [x for x in rows if x["law"] == law]
        ax.loglog([x["wall_s"] for x in r], [max(x["err"], 1e-16) for x in r], mk, label=law)
    ax.set_xlabel("wall time per 40 s run [s]")
    ax.set_ylabel("max |u − u_ref| / max |u_ref|")
    ax.set_title("rigid deck on 4 friction pendulums, 3-component record", fontsize=9)
    ax.legend()
    return fig


def summarise(result: dict) -> dict:
    best = {law: min((r for r in result["rows"] if r["law"] == law), key=lambda r: r["wall_s"])
            for law in ("switch", "arctan")}  # fmt: skip
    return {"compile_s": result["compile_s"],
            "wall_s_rtol_1e-4": {k: v["wall_s"] for k, v in best.items()},
            "scale": result["scale"], "triple": result.get("triple"),
            "planar": result.get("planar"), "atol": result.get("atol"),
            "files": result["files"]}  # fmt: skip


def report(result: dict) -> str:
    lines = [f"bidirectional isolators, deck on 4 pendulums, {result['record']} (40 s)",
             "  compile/load: " + ", ".join(f"{k} {v:.2f} s" for k, v in
                                             result["compile_s"].items()),
             f"  {'law':8s} {'rtol':>7s} {'wall [s]':>9s} {'error':>9s} {'peak err':>9s} "
             f"{'steps':>7s} {'events':>7s}"]  # fmt: skip
    for r in result["rows"]:
        lines.append(f"  {r['law']:8s} {r['rtol']:7.0e} {r['wall_s']:9.4f} {r['err']:9.2e} "
                     f"{r['err_peak']:9.2e} {r['steps']:7d} {r['events']:7d}")  # fmt: skip
    lines.append(f"  {'law':8s} {'isolators':>9s} {'wall [s]':>9s} {'per isolator':>13s}")
    for r in result["scale"]:
        lines.append(f"  {r['law']:8s} {r['n_isolators']:9d} {r['wall_s']:9.4f} "
                     f"{r['wall_per_isolator_s']:13.5f}")  # fmt: skip
    tr = result.get("triple")
    if tr:
        lines.append(
            f"  {'tfp':8s} {tr['n_isolators']:9d} {tr['wall_s']:9.4f} "
            f"{tr['wall_per_isolator_s']:13.5f}  (x {tr['ratio_to_single_arctan']:.2f} "
            f"the single pendulum, arctan; x {tr['ratio_to_single_switch']:.2f} switch)"
        )
    for r in result.get("planar") or []:
        lines.append(
            f"  planar rigid office frame, {r['law']} ({r['method']}): "
            f"{r['wall_s']:.4f} s; the 4-pendulum deck x {r['deck_over_planar']:.2f}"
        )
    for r in result.get("atol") or []:
        lines.append(
            f"  arctan rtol 1e-6, atol ({r['atol_q']:.0e} m, {r['atol_v']:.1e} m/s): "
            f"{r['wall_s']:.4f} s, {r['steps']} steps, error {r['err']:.1e} "
            f"(peak {r['err_peak']:.1e}) against the law's own solution"
        )
    return "\n".join(lines)


def pairs_scale(motion, grids=GRIDS, repeats: int = REPEATS) -> list[dict]:
    """Cost per isolator of the same decks as systems from matrices (PairSystem via
    ``from_deck``: vertical and rocking dofs, contacts as multipliers), both laws at rtol
    1e-6: rows like ``isolators-scale.csv`` with ``model = "pairs"`` and the deck's own
    wall time for the same run (``deck_wall_s``)."""
    from nsdyn.models.isolated.pairs import from_deck, simulate_pairs

    rows = []
    for n in grids:
        dn = deck(n)
        pn = from_deck(dn)
        for law in ("switch", "arctan"):
            simulate_pairs(pn, {"f": 1.0, "ax": 0.1, "ay": 0.1}, t_end=0.05, law=law)
            res, wall = _timed(lambda pn=pn, law=law: simulate_pairs(pn, motion, law=law), repeats)
            _, wall_d = _timed(lambda dn=dn, law=law: simulate_plane(dn, motion, law=law), repeats)
            rows.append({"model": "pairs", "law": law, "n_isolators": n * n, "wall_s": wall,
                         "wall_per_isolator_s": wall / (n * n), "deck_wall_s": wall_d,
                         "steps": res.stats["steps"], "events": res.stats["events"]})  # fmt: skip
    return rows
