"""``nsdyn uplift``: the uplift boundary A*(f) of a scene's isolated model (the work is in
nsdyn.periodic.uplift).

For each of ``--points`` log-spaced frequencies, the smallest amplitude A of
``u''_hor = A sin(2 pi f t)`` (a force [N] for a scene whose excitation is a harmonic force)
at which the steady periodic orbit's smallest isolator normal force reaches zero,
``min_t min_k lam_k(t) = 0``, searched up to ``--a-max``. Prints a table (f, A*, status),
writes ``uplift.json`` (the boundary's data; with ``--json`` also printed, nothing else) and
``uplift.png``. Exit status 3 when a frequency's search failed (its row says why); the
files are written either way.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

from nsdyn.atomic import atomic_open
from nsdyn.cli.args import (
    above_highest,
    band_message,
    fail,
    forcing_frequency,
    holes,
    json_report,
    old_figures,
    out_dir,
)
from nsdyn.cli.args import count as _count
from nsdyn.cli.args import positive_finite as _positive

DEFAULT_OUT = "nsdyn-uplift"
# models above this many coordinates are said to be slow before the first point (a full frame
# of 435 dofs takes minutes per frequency; the 13-coordinate cb model seconds)
SLOW_COORDS = 100
FMIN, FMAX, POINTS, A_MAX = 0.01, 10.0, 40, 20.0


def configure(p: argparse.ArgumentParser) -> None:
    p.set_defaults(command="uplift")  # its messages name it also when run alone (tests)
    p.add_argument(
        "scene", nargs="?", default=None, help="scene TOML (default: the bundled default scene)"
    )
    p.add_argument(
        "--fmin", type=forcing_frequency, default=None, metavar="HZ", help=f"default {FMIN}"
    )
    p.add_argument(
        "--fmax", type=forcing_frequency, default=None, metavar="HZ", help=f"default {FMAX}"
    )
    p.add_argument(
        "--points", type=_count, default=POINTS, help=f"log-spaced frequencies (default {POINTS})"
    )
    p.add_argument(
        "--a-max",
        type=_positive,
        default=A_MAX,
        metavar="A",
        help=f"largest amplitude searched [m/s² (at most 1000), or N for a force scene, which "
        f"needs structure.contact_rows or a frame] (default {A_MAX:g})",
    )
    p.add_argument("--fidelity", choices=["rigid", "cb", "full"], help="override the scene's")
    p.add_argument(
        "--out", type=out_dir, default=DEFAULT_OUT, metavar="DIR", help="output directory"
    )
    p.add_argument("--no-figures", action="store_true", help="skip the PNG")
    p.add_argument(
        "--json",
        action="store_true",
        help="print uplift.json (written always) in place of the table",
    )


def _fmt(v: float | None, spec: str) -> str:
    return "-" if v is None or not math.isfinite(v) else format(v, spec)


def run(args: argparse.Namespace) -> int:
    from nsdyn.ground.excitation import HarmonicForce
    from nsdyn.models.isolated.bearings import stabilisation_unsaid
    from nsdyn.models.isolated.scene import SceneError, build_scene, load_scene
    from nsdyn.periodic import log_frequencies
    from nsdyn.periodic.uplift import A_LO, uplift_boundary

    given = (args.fmin is not None, args.fmax is not None)
    args.fmin = FMIN if args.fmin is None else args.fmin
    args.fmax = FMAX if args.fmax is None else args.fmax
    overrides = {"scene": {"fidelity": args.fidelity}} if args.fidelity else None
    try:
        if args.scene is not None:
            from nsdyn.models.scenefile import read_toml, scene_kind

            kind = scene_kind(read_toml(args.scene), str(args.scene))
            if kind != "isolated":
                raise SceneError(
                    f"{args.scene}: scene.kind: nsdyn uplift takes isolated-frame scenes (kind "
                    f"'isolated'), got {kind!r}"
                )
        cfg = load_scene(args.scene, overrides)
        if cfg["scene"].get("fidelity", "cb") == "fixed":
            raise SceneError(
                f"{cfg['_source']}: scene.fidelity: the fixed-base model has no isolators to "
                "lift off; use rigid, cb or full"
            )
        with stabilisation_unsaid():  # (its orbits are bilateral: no lift-off to feel it)
            system, excitation = build_scene(cfg)
    except SceneError as e:
        return fail(args, e)
    if not args.fmax > args.fmin:
        return fail(args, band_message("uplift", args.fmin, args.fmax, given))
    if system.n_contacts == 0:
        return fail(
            args,
            f"{cfg['_source']}: [structure]: no contact rows, so no "
            "normal force can reach zero (the isolators' normal forces are frozen at the "
            "weight); give structure.contact_rows, or a frame ([scene] frame)",
        )
    load = excitation if isinstance(excitation, HarmonicForce) else None
    unit = "N" if load is not None else "m/s²"
    if load is None and (
        why := above_highest([args.a_max], "--a-max", "uplift")
    ):  # (not a force's)
        return fail(args, why)
    law = system.isolation.law
    if law not in ("arctan", "none"):
        law = "arctan"  # the periodic orbits need a smooth law
        if not args.json:
            print(
                f"nsdyn uplift: friction law {system.isolation.law!r} of the scene replaced by "
                "the smooth arctan law (same eps) for the periodic orbits",
                file=sys.stderr,
            )
    from nsdyn.cli.run_checks import note_unused_isolation

    unused = note_unused_isolation(cfg, system, law)  # (as nsdyn run says it)
    if unused and not args.json:
        print(f"nsdyn uplift: note: {unused}", file=sys.stderr)
    a_lo = min(A_LO, 0.5 * args.a_max)
    from nsdyn.plot.uplift import status_text

    def progress(pt, k, n):
        if not args.json:
            print(
                f"[{k:3d}/{n}] f={pt.f:8.4g} Hz  A*={_fmt(pt.a_crit, '.4g'):>8s}  "
                f"{pt.shootings:2d} shootings  {pt.wall_s:6.2f} s  "
                f"{status_text(pt.status, args.a_max, unit)}",
                file=sys.stderr,
                flush=True,
            )

    from nsdyn.cli.sweep import prepare_kernels

    compile_s = prepare_kernels("arctan")  # announced on a first use; apart from its wall time
    t0 = time.perf_counter()
    freqs = log_frequencies(args.fmin, args.fmax, args.points)
    if not args.json:  # before the first point, which may take minutes on a large model
        slow = (f"; {system.n} coordinates take minutes per frequency (the cb rung is the fast "
                "one)") if system.n > SLOW_COORDS else ""  # fmt: skip
        print(f"nsdyn uplift: {len(freqs)} frequencies {args.fmin:g}-{args.fmax:g} Hz, "
              f"{system.fidelity} model of {system.n} coordinates, a line per frequency as "
              f"it is found{slow}", file=sys.stderr, flush=True)  # fmt: skip
    res = uplift_boundary(
        system, freqs, a_lo=a_lo, a_hi=args.a_max, progress=progress, law=law, load=load
    )
    report = res.to_dict()
    report["wall_s"] = time.perf_counter() - t0
    report["compile_s"] = compile_s
    report["law"] = law
    out = Path(args.out)
    if gone := old_figures(out, ["uplift.png"], "uplift", args):  # (beside new results)
        report.setdefault("notes", []).append(gone)
    json_path = out / "uplift.json"  # the data, always (with --json also printed)
    report["json"] = str(json_path)
    failed = [p for p in res.points if not p.ok and not p.status.startswith("no uplift")]
    where = ", ".join(f"{p.f:.4g}" for p in failed[:5]) + (", ..." if len(failed) > 5 else "")
    said = ("uplift", len(failed), len(res.points), "frequencies",
            f"f = {where} Hz; reasons in the status column and in {json_path}")  # fmt: skip
    holes(*said, report, say=False)  # (the file's and --json's status and error, if any)
    for draw in (False, True) if not args.no_figures else (False,):  # the data first, then
        if draw:  # the figure and the data naming it (an interrupt between them leaves no
            from nsdyn.plot.uplift import uplift_boundary_figure  # new figure beside old data)

            uplift_boundary_figure(res, out / "uplift.png")
            report["figure"] = str(out / "uplift.png")
        text = json_report(report, default=float)  # (the file and --json alike)
        with atomic_open(json_path, "w", encoding="utf-8") as fh:
            fh.write(text + "\n")
    if args.json:
        print(text)
    else:
        print(
            f"model {res.model}: uplift boundary at {args.points} frequencies "
            f"{args.fmin:g}-{args.fmax:g} Hz, A up to {args.a_max:g} {unit}, {law} friction"
        )
        print(f"   f [Hz]   A* [{unit}]  shootings  status")
        for p in res.points:
            word = status_text(p.status, args.a_max, unit)
            print(f"{p.f:9.4g}  {_fmt(p.a_crit, '10.4g'):>10s}  {p.shootings:9d}  {word}")
        n_ok = int(res.ok.sum())
        print(f"{n_ok}/{len(res.points)} frequencies with A* found; wall {report['wall_s']:.1f} s")
        print(f"data:   {json_path}")
        if "figure" in report:
            print(f"figure: {report['figure']}")
    return holes(*said)
