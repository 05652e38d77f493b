"""``nsdyn study``: many runs of a scene over parameters and records, resumable, on local
processes or Dask; then the study's analyses (design search, percentiles, fragility)."""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import signal
import sys
from contextlib import nullcontext
from pathlib import Path

from nsdyn.atomic import output_dir
from nsdyn.cli.args import EXIT_INTERRUPTED, EXIT_NUMERICS, fail, json_report, out_dir, workers

DEFAULT_OUT = "nsdyn-study"  # output directory (a subdirectory per study name)
STARTED: list[str] = []  # this command's results folder once its tasks start (an interrupt's line)
MAX_FAILED_LINES = 10  # failed tasks named one per line on the console (all are in the table)


def _address(s: str) -> str:
    """A scheduler's address: not empty (an empty one ran on the local pool without a word)."""
    if not s.strip():
        raise argparse.ArgumentTypeError("expected a scheduler address, e.g. tcp://host:8786")
    return s


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("study", help="study TOML")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--dask", type=_address, metavar="ADDR",
                       help="Dask scheduler, e.g. tcp://host:8786")  # fmt: skip
    where.add_argument(
        "--dask-local",
        type=workers,
        metavar="N",
        help="start a Dask LocalCluster of N workers",
    )
    where.add_argument(
        "--workers", type=workers, metavar="N", help="local process pool size (default: CPUs)"
    )
    p.add_argument(
        "--out", type=out_dir, metavar="DIR", help=f"output directory (default {DEFAULT_OUT}/NAME)"
    )
    p.add_argument("--fresh", action="store_true", help="discard earlier results and start over")
    p.add_argument("--retry-failed", action="store_true", help="rerun tasks recorded as failed")
    p.add_argument("--parquet", action="store_true", help="also write results.parquet (pyarrow)")
    p.add_argument("--no-figures", action="store_true", help="skip the PNG figures")
    p.add_argument("--json", action="store_true", help="print one JSON object and nothing else")


def _on_sigterm(signum, frame):
    raise KeyboardInterrupt


def study_folder(name: str) -> str:
    """The folder of a study ``name`` in ``nsdyn-study/``: its path separators as "_", a name
    of dots alone as underscores (".." wrote the table beside ``nsdyn-study/``, "." into it)."""
    stem = name.replace("/", "_").replace("\\", "_")
    return "_" * len(stem) if not stem.strip(".") else stem


def _format(name: str, run: dict, an: dict) -> str:
    lines = [
        f"study {name}: {run['n_tasks']} task{'s' * (run['n_tasks'] != 1)}, {run['n_run']} "
        "run now, "
        f"{run['n_skipped']} from before, {run['n_failed']} failed "
        + (
            f"({run['wall_s']:.1f} s on {run['workers']} worker{'s' * (run['workers'] != 1)}, "
            f"batches of {run['batch']})"
            if run["n_run"]
            else "(nothing left to run)"
        ),
        f"table: {run['table']}" + (f" (and {run['parquet']})" if run.get("parquet") else ""),
    ]
    if run.get("n_outside"):
        from nsdyn.studies.table import OUTSIDE

        lines.append(f"kept: {run['n_outside']} rows (finished or failed) of tasks not in this "
                     f"study (other parameter values or settings), in {OUTSIDE} (a study asking "
                     "for them again reuses them; --fresh forgets them)")  # fmt: skip
    d = an.get("design")
    if d:
        lines.append(
            f"design: {d['n_feasible']} of {d['n_designs']} designs feasible, "
            f"{len(d['pareto'])} on the Pareto front"
        )
        for label in ("chosen", "reference"):
            row = d.get(label)
            if row:
                lines.append(
                    f"  {label:9s} "
                    + ", ".join(
                        f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                        for k, v in row.items()
                    )
                )
    pc = an.get("percentiles")
    if pc:
        lines.append(f"percentiles: {len(pc['rows'])} group(s) in {pc['table']}")
        if pc.get("note"):
            lines.append(f"  note: {pc['note']}")
    for part in ("design", "incidence", "fragility"):  # (the percentiles' with them)
        if (an.get(part) or {}).get("note"):
            lines.append(f"{part}: note: {an[part]['note']}")
    f = an.get("fragility")
    if f:
        for r in f["fits"]:  # (a true/false outcome has no limit: it read "toppled > None")
            what = f"{f['edp']} > {r['limit']}" if r["limit"] is not None else f"{f['edp']}"
            if "theta" in r:
                lines.append(
                    f"fragility {what}: theta = {r['theta']:.4g} "
                    f"(se of ln theta {r['se_ln_theta']:.3f}), beta = {r['beta']:.3f} "
                    f"(se {r['se_beta']:.3f}), {r['n_exceed']}/{r['n']} exceed"
                    + (f" ({r['failures']})" if r.get("n_failed_as_exceedance") else "")
                )
            else:
                lines.append(f"fragility {what}: {r['error']}")
    inc = an.get("incidence")
    for r in (inc or {}).get("rows", [])[:MAX_FAILED_LINES]:
        has = [q for q in inc["quantities"] if all(  # (a round-off peak has no angle)
            isinstance(r.get(f"{q}_{k}"), int | float) and math.isfinite(r[f"{q}_{k}"])
            for k in ("max", "angle_of_max_deg"))]  # fmt: skip
        if not has and r.get("n_failed") and not r.get("n_angles"):
            group = ", ".join(str(r.get(b)) for b in inc["by"])
            lines.append(f"incidence {group}: every angle failed ({r['n_failed']})")
        for q in has:  # each quantity the group has: its largest over the angles
            top, at, low = (r[f"{q}_{k}"] for k in ("max", "angle_of_max_deg", "min"))
            group = ", ".join(str(r.get(b)) for b in inc["by"])
            k = r.get("n_failed") or 0
            gone = f" ({k} failed angle{'s' * (k > 1)} left out)" if k else ""
            if r.get("n_angles", 0) > 1 and not gone and f"{top:.4g}" == f"{low:.4g}":
                # (an isotropic case: no angle is the worst)
                lines.append(f"incidence {group}: {q} {top:.4g} at every angle (to 4 digits)")
            else:
                lines.append(f"incidence {group}: {q} max {top:.4g} at {at:g} deg "
                             f"(min {low:.4g}){gone}")  # fmt: skip
    for part in ("design", "percentiles", "fragility", "incidence"):
        if an.get(part, {}).get("figure"):
            lines.append(f"figure: {an[part]['figure']}")
    return "\n".join(lines)


def failures(study, rows: list[dict]) -> list[dict]:
    """The failed rows of a table as {index, task (its label), error}, in task order."""
    from nsdyn.studies.study import task_label

    out = []
    for r in sorted(rows, key=lambda r: r.get("index", 0)):
        if r.get("status") == "ok":
            continue
        params = {p.name: r.get(p.name) for p in study.parameters if p.name in r}
        label = task_label(r.get("index", "?"), params, r.get("record") or "")
        out.append({"index": r.get("index"), "task": label, "error": r.get("error", "")})
    return out


def never_kept(study, rows: list[dict]) -> list[str]:
    """A note (or none) naming the names of ``study.keep`` that no finished task's run
    summary had (a misspelt name), with the nearest field of each: a finished row's note,
    cut to those names (a row's note also names what only its rung or kind lacks), the one
    with the most hints for them."""
    import re

    from nsdyn.studies.scenes import MISSING_MARK, missing_names

    ok = [r for r in rows if r.get("status") == "ok"]
    never = [
        k for k in study.keep or () if ok and all(k in missing_names(r.get("error")) for r in ok)
    ]
    if not never:
        return []
    best = max(ok, key=lambda r: sum(f"for {k!r}?" in r["error"] for k in never))  # (hinted)
    head, rest = best["error"].split(MISSING_MARK, 1)
    hints, _, fields = rest.split(";", 1)[1].partition(" its fields: ")
    mine = [h for h in re.findall(r"did you mean '[^']*' for '[^']*'\?", hints)
            if any(h.endswith(f"for {k!r}?") for k in never)]  # fmt: skip
    names = ", ".join(map(repr, never))
    return [f"{head}{MISSING_MARK} {names}; {' '.join([*mine, ''])}its fields: {fields}"]


def _failure_lines(failed: list[dict], table: str) -> list[str]:
    lines = [f"failed  {f['task']}: {f['error']}" for f in failed[:MAX_FAILED_LINES]]
    if len(failed) > MAX_FAILED_LINES:
        lines.append(f"        ... and {len(failed) - MAX_FAILED_LINES} more failed tasks")
    if failed:
        lines.append(
            f"{len(failed)} failed task{'s' if len(failed) > 1 else ''}: the reasons are in "
            f"the 'error' column of {table}; after a fix, rerun with --retry-failed"
        )
    return lines


def announce_compile(study) -> bool:
    """Compile (or load) the isolated frame's kernels in this process before the workers
    start, saying so on stderr when numba's cache does not hold them
    (:func:`nsdyn.studies.workers.warm_isolated`): the workers then load them instead of each
    compiling them at the same time (the other families' kernels compile in
    :func:`nsdyn.studies.execute.run_study`, before its workers start). True when they
    compiled."""
    if study.kind != "isolated":
        return False
    from nsdyn.studies.workers import warm_isolated

    method = study.base.get("solver", {}).get("method", "auto")
    law = "switch" if method == "event" else study.base.get("isolation", {}).get("law", "arctan")
    return warm_isolated(method, law)  # auto: radau for a frame of a few modes


def kept_tasks(out) -> tuple[int, int] | None:
    """(finished tasks, of them failed) that the results folder ``out`` holds (``parts/``
    while running, the table after): the ones a rerun resumes; None when a file there cannot
    be read (a count is no reason for an interrupt's report to fail)."""
    import csv

    from nsdyn.studies.table import ResultsStore

    if not Path(out).is_dir():
        return 0, 0
    try:
        return ResultsStore(out).n_finished()
    except (OSError, ValueError, csv.Error):
        return None


def _drop_unfilled(out: Path, made: bool, kept: tuple[int, int] | None) -> None:
    """Empty the results folder ``out`` this study made (``made``) when it holds no finished
    task (``kept``): its owner file and an empty ``parts/`` go, so that the folder goes with
    the others :func:`nsdyn.atomic.output_dir` made (a rerun starts over anyway)."""
    from nsdyn.studies.table import OWNER, PARTS

    if made and kept == (0, 0):
        (out / OWNER).unlink(missing_ok=True)
        with contextlib.suppress(OSError):
            (out / PARTS).rmdir()


def stopped_line(out, kept: tuple[int, int] | None | bool = True) -> str:
    """What an interrupted study says of the results folder ``out`` it was running into:
    ``kept`` its count (:func:`kept_tasks`, counted here when True; the last progress line,
    up to PROGRESS_S old, can say fewer)."""
    kept = kept_tasks(out) if kept is True else kept
    if kept is None:  # (a file there it cannot read: nothing counted)
        return f"interrupted; finished tasks are kept in {out}, rerun to resume"
    n, failed = kept
    if not n:
        return "interrupted before its first task finished; a rerun starts over"
    of = f" ({failed} of them failed)" * bool(failed)
    return f"interrupted; {n} finished task{'s' * (n != 1)}{of} kept in {out}, rerun to resume"


def run(args: argparse.Namespace) -> int:
    from nsdyn.studies.analyses import run_analyses
    from nsdyn.studies.execute import dask_executor, run_study, stderr_progress
    from nsdyn.studies.study import load_study
    from nsdyn.studies.table import PARQUET, pyarrow_modules

    STARTED.clear()
    if args.fresh and args.retry_failed:  # (it was accepted and did nothing: fresh runs all)
        return fail(args, "--retry-failed: with --fresh every task runs anew; give one or the "
                    "other")  # fmt: skip
    study = load_study(args.study)
    out = Path(args.out) if args.out else Path(DEFAULT_OUT) / study_folder(study.name)
    parquet = args.parquet or (out / PARQUET).is_file()  # (once asked: a run on another grid
    # removes the copy with the old grid's analyses, and it is written anew after the run)
    try:
        if parquet:
            pyarrow_modules()  # (before the kernels and the first run, not after the last)
    except OSError as e:
        if args.parquet:
            raise
        raise OSError(f"{out / PARQUET}: kept in step with the table; {e}; or remove it") from None
    announce_compile(study)
    if args.dask or args.dask_local:
        ctx = dask_executor(args.dask, args.dask_local)
    else:
        ctx = nullcontext(None)
    made = not out.exists()
    kept: tuple[int, int] | None | bool = True  # (counted by stopped_line unless counted here)
    old = signal.signal(signal.SIGTERM, _on_sigterm)
    STARTED[:] = [str(out)]
    try:
        with output_dir(out, "study"):  # (locked while the study runs and its analyses write)
            try:
                with ctx as executor:
                    res = run_study(study, out, executor=executor, workers=args.workers,
                                    fresh=args.fresh, retry_failed=args.retry_failed,
                                    progress=None if args.json else stderr_progress)  # fmt: skip
                summary = res.as_dict()
                failed = failures(study, res.table.rows)
                summary["failed"] = [{"index": f["index"], "error": f["error"]} for f in failed]
                summary["never_kept"] = never_kept(study, res.table.rows)
                if parquet:  # (in step with the table once asked)
                    summary["parquet"] = str(res.table.to_parquet(out / PARQUET))
                an = run_analyses(study, res.table, out, figures=not args.no_figures)
            except BaseException:  # counted, and a folder of no task emptied, under the lock
                kept = kept_tasks(out)  # (output_dir then removes the folders it made)
                _drop_unfilled(out, made, kept)
                raise
    except KeyboardInterrupt:
        line = stopped_line(out, kept)
        print(f"nsdyn study: {line}", file=sys.stderr)
        if args.json:  # (an outcome too, as every command's under --json)
            print(json.dumps({"status": EXIT_INTERRUPTED, "error": line}), flush=True)
        return EXIT_INTERRUPTED
    finally:
        signal.signal(signal.SIGTERM, old)
    status = EXIT_NUMERICS if failed else 0  # a study with failed tasks is not a success
    if args.json:
        out = {"status": status, "study": study.name, "run": summary, "analysis": an}
        print(json_report(out))  # (the warnings said on stderr: in it too)
        return status
    print(_format(study.name, summary, an))
    for line in _failure_lines(failed, summary["table"]):
        print(line, file=sys.stderr)
    for note in summary["never_kept"]:  # every cell of that column is empty
        from nsdyn.studies.scenes import MISSING_MARK

        note = note.replace(MISSING_MARK, "in no task's run summary (a column of empty cells):")
        print(f"nsdyn study: warning: {note}", file=sys.stderr)
    return status
