"""``nsdyn spectrum``: overturning spectrum of a rocking block or frame scene.

For each pulse frequency ω_p/p (log-spaced) the minimum pulse amplitude a_p/(g tan α) (g α for
a linearised model) that
overturns the body is bracketed and bisected
(:func:`nsdyn.models.rocking.spectra.overturning_spectrum`);
frequencies run in parallel processes.
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import sys
from pathlib import Path

import numpy as np

from nsdyn._checks import MAX_POINTS
from nsdyn.atomic import atomic_open, save_figure
from nsdyn.cli.args import (
    fraction,
    json_report,
    old_figures,
    out_dir,
    positive_finite,
    pulse_count,
    workers,
)

SHAPES = ("sine", "cosine", "ricker", "rect")
DEFAULT_OUT = "nsdyn-out"


def configure(p: argparse.ArgumentParser) -> None:
    p.epilog = (
        "The scene gives the block or frame; its own [motion] is not read (the "
        "pulses are the spectrum's). Status per frequency: 'safe band' (larger "
        "amplitudes between safe_lo and safe_hi do not overturn it), 'no safe band "
        "found' (it overturns from a_min on, as far as the search sees), 'safe up to "
        "a_max' (no overturning again from safe_lo up to --a-max), 'no overturning up "
        "to a_max' (none at all)"
    )
    p.add_argument("scene", help="rocking scene TOML ([scene] kind = 'rocking', model block|frame)")
    p.add_argument("--shape", choices=SHAPES, default="sine", help="pulse shape (default sine)")
    p.add_argument("--n", type=pulse_count, default=40, help="frequencies (default 40; at most "
                   f"{MAX_POINTS})")  # fmt: skip
    p.add_argument("--wmin", type=positive_finite, default=1.0, help="smallest ω_p/p, from 0.01 "
                   "to 1000 (default 1)")  # fmt: skip
    p.add_argument("--wmax", type=positive_finite, default=20.0, help="largest ω_p/p, from 0.01 "
                   "to 1000 (default 20)")  # fmt: skip
    p.add_argument(
        "--rtol",
        type=fraction,
        default=1e-4,
        help="relative bisection width, from 2.2e-14 to below 1 (default 1e-4)",
    )
    p.add_argument("--a-max", type=positive_finite, default=None, metavar="RATIO",
                   help="largest amplitude ratio a_p/(g tan α) (g α if linear) scanned "
                   "(default 30, at most 1e6); a frequency with no overturning up to it "
                   "reports '> a_max'")  # fmt: skip
    p.add_argument("--workers", type=workers, default=None, metavar="N",
                   help="parallel processes")  # fmt: skip
    p.add_argument(
        "--out", type=out_dir, default=DEFAULT_OUT, metavar="DIR", help="output directory"
    )
    p.add_argument("--no-figures", action="store_true", help="skip the PNG")
    p.add_argument("--json", action="store_true", help="print one JSON object and nothing else")


def run(args: argparse.Namespace) -> int:
    from nsdyn.models.rocking.scene import build_model, build_solver
    from nsdyn.models.rocking.spectra import overturning_spectrum
    from nsdyn.models.scenefile import SceneError, read_toml, scene_kind

    src = str(args.scene)
    cfg = read_toml(args.scene)
    kind = scene_kind(cfg, src)
    if kind != "rocking":
        raise SceneError(f"{src}: scene.kind: overturning spectra need a 'rocking' scene, got "
                         f"{kind!r}")  # fmt: skip
    if cfg.get("scene", {}).get("model", "block") == "compliant":
        raise SceneError(f"{src}: scene.model: spectra are computed for 'block' or 'frame'")
    from nsdyn.cli.args import fail
    from nsdyn.models.rocking.spectra import A_MAX_LIMIT, OMEGA_RATIO_MAX, OMEGA_RATIO_MIN

    for flag, v in (("--wmin", args.wmin), ("--wmax", args.wmax)):
        if not OMEGA_RATIO_MIN <= v <= OMEGA_RATIO_MAX:  # (a traceback, a step underflow)
            return fail(args, f"argument {flag}: expected a ratio omega_p / p from "
                        f"{OMEGA_RATIO_MIN:g} to {OMEGA_RATIO_MAX:g}, got {v:g} (see nsdyn "
                        "spectrum --help)")  # fmt: skip
    if args.a_max is not None and args.a_max > A_MAX_LIMIT:  # (a step underflow)
        return fail(args, f"argument --a-max: expected a ratio of at most {A_MAX_LIMIT:g}, got "
                    f"{args.a_max:g} (see nsdyn spectrum --help)")  # fmt: skip
    if not args.wmax > args.wmin:
        return fail(args, f"argument --wmax: expected a ratio above --wmin ({args.wmin:g}), "
                    f"got {args.wmax:g} (see nsdyn spectrum --help)")  # fmt: skip
    model = build_model(cfg, src)
    tol = build_solver(cfg, src)[0]  # (the scene's solver.tol was ignored)
    notes = []
    if cfg.get("motion"):  # (it was ignored without a word)
        what = "frame" if "Frame" in type(model).__name__ else "block"
        notes.append(f"{src}: [motion] not used: a spectrum drives the {what} with one "
                     f"{args.shape} pulse per run (--shape), at the amplitudes and "
                     "frequencies it searches")  # fmt: skip
    for n in notes if not args.json else ():
        print(f"nsdyn spectrum: note: {n}", file=sys.stderr)
    ratios = np.geomspace(args.wmin, args.wmax, args.n)
    from nsdyn.models.rocking.scene import warm
    from nsdyn.studies.workers import process_pool

    # the kernel compiled (or loaded) here, announced on a first use, before the workers
    # start: they load it instead of each compiling it at once
    compile_s = warm(model)

    with process_pool(args.workers) as ex:
        search = {} if args.a_max is None else {"a_max": args.a_max}
        sp = overturning_spectrum(model, ratios, args.shape, rtol=args.rtol, executor=ex, tol=tol,
                                  **search)  # fmt: skip
    out = Path(args.out)
    stem = f"spectrum-{Path(src).stem}-{args.shape}"
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(sp.COLUMNS)
    for *row, word in zip(sp.omega_ratio, sp.a_min_ratio, sp.mode, sp.safe_lo_ratio,
                          sp.safe_hi_ratio, sp.status, strict=True):  # fmt: skip
        w.writerow([repr(float(v)) if not isinstance(v, np.integer) else int(v) for v in row]
                   + [word])  # fmt: skip
    csv_path = out / f"{stem}.csv"
    if gone := old_figures(out, [f"{stem}.png"], "spectrum", args):  # (beside new results)
        notes.append(gone)
    with atomic_open(csv_path, "w") as fh:
        fh.write(buf.getvalue())
    report = {"scene": src, **sp.summary(), "compile_s": compile_s, "csv": str(csv_path),
              "notes": notes}  # fmt: skip
    report["search"]["tol"] = tol
    # each frequency's word apart from the command's status, which leads every --json
    report["frequency_status"] = report.pop("status")
    if not args.no_figures:
        from nsdyn.models.rocking.figures import spectrum_figure

        fig_path = out / f"{stem}.png"
        save_figure(spectrum_figure({f"{Path(src).stem} ({args.shape})": sp}), fig_path)
        report["figure"] = str(fig_path)
    if args.json:
        print(json_report(report))
        return 0
    print(f"{src}: {args.shape} pulses, α = {sp.alpha:.4f} rad, p = {sp.p:.4f} 1/s")
    print(f"{args.n} frequencies, {sp.n_runs} runs, {sp.wall_s:.2f} s")
    unit = sp.unit.replace("alpha", "α")
    print(f"  ω_p/p    {'a_min/(' + unit + ')':>15s}  mode  status")
    for x, a, m, s in zip(sp.omega_ratio, sp.a_min_ratio, sp.mode, sp.status, strict=True):
        a_txt = f"{a:15.5g}" if math.isfinite(a) else f"{'> ' + format(sp.a_max, 'g'):>15s}"
        s = f"{s} = {sp.a_max:g}" if s.endswith("a_max") else s  # the bound, not a word
        print(f"  {x:7.4g}  {a_txt}  {m if m else '-':>4}  {s}")
    print("(mode 1: overturns after an impact, 2: without one; > a_max: none found up to it)")
    print(f"(search: scan x{sp.scan:g} up to a_max = {sp.a_max:g}, refined where the overturning "
          f"mode changes; edges to {sp.rtol:g})")  # fmt: skip
    print(f"csv:    {csv_path}")
    if "figure" in report:
        print(f"figure: {report['figure']}")
    return 0
