"""Running a study on any ``concurrent.futures.Executor``: batches, progress, resume, failures.

``run_study(study, out_dir)`` expands the study into tasks, drops those whose key is already in
the output directory's table, submits the rest in batches (:mod:`nsdyn.studies.tasks`) and
writes each returned batch as a part of the table at once (:mod:`nsdyn.studies.table`).
The executor is a local process pool unless one is given — e.g. ``client.get_executor()`` of a
Dask ``distributed.Client`` (:func:`dask_executor` starts a ``LocalCluster`` or connects to a
scheduler). A task that raises is a ``failed`` row. A batch whose worker died (a broken
process pool, a Dask ``KilledWorker``) is split and its tasks resubmitted one by one, on a new
pool if the pool was ours; a task that takes its worker down twice is a ``failed`` row.
Kernels a worker would compile on its first task are compiled once here first
(:func:`nsdyn.studies.scenes3c.warm_kernels` for deck and building3d tasks,
:func:`nsdyn.studies.scenes.warm_scene_kernels` for rocking, contact and cylinder tasks), so
the workers load them from numba's cache.

Progress (stderr, every PROGRESS_S): tasks done / total, failed, skipped (already in the
table), elapsed wall time and the time left, estimated as
``elapsed / tasks_done_this_run * tasks_left``.
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Executor, wait
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from dataclasses import dataclass, fields
from pathlib import Path

from nsdyn._brief import brief_repr
from nsdyn._checks import flag, is_typo, whole
from nsdyn.models.scenefile import SceneError
from nsdyn.studies.scenes import missing_names, near_kept, run_batch
from nsdyn.studies.study import Study
from nsdyn.studies.table import ResultsStore, Table
from nsdyn.studies.tasks import Task, batch_size, batches, ensure_checked, expand
from nsdyn.studies.workers import Interrupts, process_pool, stop_pool

PROGRESS_S = 2.0  # seconds between progress lines
DASK_HINT = 'Dask is an optional extra: pip install "nsdyn[dask]"'


@dataclass(repr=False)
class StudyRun:
    """What a run of a study did and the table it left."""

    __repr__ = brief_repr  # arrays by shape, not in full

    table: Table
    n_tasks: int
    n_run: int
    n_skipped: int
    n_failed: int
    wall_s: float
    workers: int
    batch: int
    out_dir: Path
    n_outside: int = 0  # rows of tasks outside the grid (failed too), kept in table.OUTSIDE

    def to_dataframe(self):
        """The study's table as a pandas DataFrame (:meth:`Table.to_dataframe`)."""
        return self.table.to_dataframe()

    def as_dict(self) -> dict:
        """The counts and timings, and the path of the table (JSON-serialisable)."""
        counts = {f.name: getattr(self, f.name) for f in fields(self)}
        del counts["table"], counts["out_dir"]
        return counts | {"table": str(self.out_dir / "results.csv")}


def _failed_rows(tasks: list[Task], why: str) -> list[dict]:
    failed = {"status": "failed", "error": why, "task_s": float("nan")}
    return [dict.fromkeys(t.keep or ()) | t.columns() | failed for t in tasks]  # (kept: empty)


class _Progress:
    def __init__(self, name: str, total: int, skipped: int, report: Callable | None):
        self.name, self.total, self.skipped = name, total, skipped
        self.done = self.failed = 0
        self.t0 = self.last = time.perf_counter()
        self.report = report

    def add(self, rows: list[dict]) -> None:
        self.done += len(rows)
        self.failed += sum(r.get("status") != "ok" for r in rows)

    def line(self) -> str:
        el = time.perf_counter() - self.t0
        left = self.total - self.skipped - self.done
        eta = (f"~{el / self.done * left:.0f} s left" if self.done
               else "nothing left" if not left else "time left unknown")  # fmt: skip
        return (
            f"study {self.name}: {self.skipped + self.done}/{self.total} done "
            f"({self.done} run now, {self.failed} of them failed; {self.skipped} from before), "
            f"{el:.1f} s, {eta}"
        )

    def tick(self, force: bool = False) -> None:
        now = time.perf_counter()
        if self.report is not None and (force or now - self.last >= PROGRESS_S):
            self.last = now
            self.report(self.line())


def _first_check(study: Study, rows: list[dict], checked: bool, say=None) -> bool:
    """Whether the analyses' columns and ``keep`` are checked against a successful row:
    checked now with the first among ``rows``
    (:func:`~nsdyn.studies.analyses.check_first_row`; a kept name a typo away from a field of
    its run's summary stops the study, before its rows are stored (:func:`_kept_typo`), rather
    than end in an empty column; one
    far from every field is said to ``say`` at once, not only at the study's end)."""
    if checked:
        return True
    ok = next((r for r in rows if r.get("status") == "ok"), None)
    if ok is not None:
        from nsdyn.studies.analyses import check_first_row

        _kept_typo(study, rows)
        check_first_row(study, ok)
        far = [repr(k) for k in missing_names(ok.get("error")) if k in (study.keep or ())]
        if far and say is not None:  # (another rung's or kind's field, or a misspelt name)
            say(f"{study.source}: study.keep: {', '.join(far)} not in the first run's summary: "
                "another rung's or scene kind's field is an empty cell wherever a run lacks it; "
                "a name no run has (misspelt) stays an empty column, which nsdyn study names "
                "at the end")  # fmt: skip
    return ok is not None


def _kept_typo(study: Study, rows: list[dict], early=()) -> None:
    """SceneError when a name ``keep`` asks for is a typo away from a field of the first
    successful run's summary among ``rows``; the parts ``early`` (stored before it: failed
    rows) are removed first."""
    ok = next((r for r in rows if r.get("status") == "ok"), {})
    for name, near in near_kept(ok.get("error")):
        if name in (study.keep or ()) and is_typo(name, [near]):
            for part in early:
                part.unlink(missing_ok=True)
            raise SceneError(f"{study.source}: study.keep: {name!r} is not a field of the "
                             f"first run's summary; did you mean {near!r}? (stopped after it, "
                             "its rows not kept: keep is part of each task's key, so the study "
                             "runs anew once the name is fixed)")  # fmt: skip


def _n_workers(executor: Executor) -> int:
    n = getattr(executor, "_max_workers", None)  # ProcessPoolExecutor, ThreadPoolExecutor
    client = getattr(executor, "_client", None)  # distributed's ClientExecutor
    if client is not None:
        n = sum(client.nthreads().values())
    return int(n or os.cpu_count() or 1)


def run_study(
    study: Study,
    out_dir: str | Path,
    *,
    executor: Executor | None = None,
    workers: int | None = None,
    fresh: bool = False,
    retry_failed: bool = False,
    progress: Callable[[str], None] | None = None,
) -> StudyRun:
    """Run the tasks of ``study`` missing from ``out_dir``'s table; return a :class:`StudyRun`
    (its counts and timings; the whole table, done before and now, is ``.table``).

    Parameters
    ----------
    executor : concurrent.futures.Executor, optional
        Default: a ``ProcessPoolExecutor(workers)`` owned (and replaced if broken) by this call.
    workers : int, optional       processes of the default pool (default: CPU count)
    fresh : bool                  forget earlier results in ``out_dir``
    retry_failed : bool           rerun tasks recorded as failed
    progress : callable(str), optional   receives a progress line every PROGRESS_S
    """
    fresh, retry_failed = flag("fresh", fresh), flag("retry_failed", retry_failed)  # ("no": True)
    if fresh and retry_failed:  # (as the command line: fresh runs every task anew)
        raise ValueError("retry_failed: with fresh every task runs anew; give one or the other")
    if progress is not None and not callable(progress):
        raise TypeError(f"progress: expected a function of one line (str), or None; got "
                        f"{type(progress).__name__}")  # fmt: skip
    if workers is not None:
        whole("workers", workers, 1, "an integer >= 1 (or None: the CPU count)")
    if executor is not None and not callable(getattr(executor, "submit", None)):
        ours = getattr(executor, "func", None) is dask_executor.__wrapped__  # (its manager)
        hint = ("; a context manager gives one: with nsdyn.dask_executor() as ex: run_study("
                "..., executor=ex)") * ours  # fmt: skip
        raise TypeError(f"executor: expected a concurrent.futures.Executor (or a Dask "
                        f"Client's), got {type(executor).__name__} {executor!r}{hint}")  # fmt: skip
    if executor is not None and workers is not None:
        raise ValueError("workers: the size of the default process pool; an executor given "
                         "has its own workers: give one or the other")  # fmt: skip
    ensure_checked(study)  # (a study changed since load_study: its tasks checked again)
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise ValueError(f"out_dir: {out} is a file; expected a folder for the study's table")
    tasks = expand(study)
    store = ResultsStore(out, [p.name for p in study.parameters], study.keep)
    store.clean_temporaries()
    if fresh:
        store.reset()
    store.claim(study.name, study.kind)
    order = {t.key: t.index for t in tasks}
    aliases = {t.extra["ordered_key"]: t.key for t in tasks if "ordered_key" in t.extra}
    store.regrid(order, aliases)  # (rows of a table keyed when keep's order was hashed)
    done = store.read()
    here = [r for k, r in done.items() if k in order]  # (not another grid's rows)
    first = _first_check(study, here, False, progress)  # (before kernels and a pool)
    todo = [
        t
        for t in tasks
        if t.key not in done or (retry_failed and done[t.key].get("status") != "ok")
    ]
    if todo:  # compiled here once, loaded by every worker
        from nsdyn.studies.scenes import warm_scene_kernels
        from nsdyn.studies.scenes3c import warm_kernels

        warm_kernels(todo)
        warm_scene_kernels(todo)
    own = executor is None
    if own:
        workers = min(workers or os.cpu_count() or 1, max(len(todo), 1))  # (no idle process)
        executor = process_pool(workers) if todo else None
    n_workers = workers if own else _n_workers(executor)
    size = batch_size(len(todo), n_workers, study.batch)
    prog = _Progress(study.name, len(tasks), len(tasks) - len(todo), progress)
    t0 = time.perf_counter()
    pending: dict = {}
    early: list = []  # parts stored before the first successful row was checked
    try:
        with Interrupts() as stop:  # signals act between waits (workers.Interrupts)
            pending = {executor.submit(run_batch, b): (b, False) for b in batches(todo, size)}
            while pending:
                finished, _ = wait(pending, timeout=PROGRESS_S, return_when=FIRST_COMPLETED)
                resubmit: list[Task] = []
                broken = False
                for f in finished:
                    b, retried = pending.pop(f)
                    try:
                        rows = f.result()
                    except Exception as e:  # the worker, not the task, failed
                        broken |= isinstance(e, BrokenProcessPool)
                        why = " ".join(f"worker lost: {type(e).__name__}: {e}".split())[:400]
                        if retried:
                            rows = _failed_rows(b, why)
                        else:
                            resubmit += b
                            continue
                    if not first:  # (rows of a misspelt kept name are never resumed: its
                        _kept_typo(study, rows, early)  # fix changes every key; not stored)
                    part = store.append(rows)
                    early += [part] * (not first)
                    prog.add(rows)
                    first = _first_check(study, rows, first, progress)
                if broken and own:
                    # every future of a broken pool fails: take them all back, start a new pool
                    for f, (b, retried) in list(pending.items()):
                        if retried:
                            continue
                        pending.pop(f)
                        resubmit += b
                    executor.shutdown(wait=False, cancel_futures=True)
                    executor = process_pool(workers)
                elif broken:
                    raise RuntimeError("the given process pool broke; rerun the study to resume")
                for t in resubmit:
                    pending[executor.submit(run_batch, [t])] = ([t], True)
                prog.tick()
                stop.check()  # a Ctrl-C or SIGTERM since the last wait: rows kept
    except BaseException:  # an interrupt or an error: the pool's running tasks are abandoned
        if own:
            stop_pool(executor, kill=True)
            executor = None
        else:  # a caller's executor (a Dask client's): its tasks not yet started are dropped
            for f in pending:
                f.cancel()
        raise
    finally:
        if own and executor is not None:  # every task is done: the pool ends before we go on
            # (shutdown without waiting lets the interpreter's exit hook write to the pool's
            # wake-up pipe while its manager thread closes it: "Bad file descriptor" at exit)
            executor.shutdown(wait=True)
    prog.tick(force=True)
    table = store.compact(order, aliases)
    return StudyRun(
        table=table,
        n_tasks=len(tasks),
        n_run=prog.done,
        n_skipped=prog.skipped,
        n_failed=sum(r.get("status") != "ok" for r in table.rows),
        wall_s=time.perf_counter() - t0,
        workers=n_workers,
        batch=size,
        out_dir=out,
        n_outside=store.n_outside,
    )


@contextmanager
def dask_executor(
    address: str | None = None, n_local: int | None = None, *, processes: bool = True
) -> Iterator[Executor]:
    """A ``concurrent.futures.Executor`` on Dask: the scheduler at ``address``, or a
    ``LocalCluster`` of ``n_local`` single-threaded workers (default 1; threads if not
    ``processes``); a context manager: ``with nsdyn.dask_executor() as ex: run_study(s, out,
    executor=ex)``. ``n_local`` with an ``address`` is refused (the scheduler's are used)."""
    if n_local is not None:
        if address is not None:
            raise ValueError("n_local: the size of a local cluster; the scheduler at address "
                             "has its own workers: give one or the other")  # fmt: skip
        whole("n_local", n_local, 1, "a number of local workers >= 1 (or None: 1)")
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise OSError(DASK_HINT) from None
    cluster = None
    if address is None:
        import logging
        import signal
        import threading

        # the workers inherit an ignored SIGINT: a Ctrl-C stops this process (which ends the
        # cluster and says how to resume), not each worker with its own traceback
        main = threading.current_thread() is threading.main_thread()
        old = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
        try:
            cluster = LocalCluster(n_workers=n_local or 1, threads_per_worker=1,  # (":0": a
                                   processes=processes, dashboard_address=":0",  # free port)
                                   silence_logs=logging.ERROR)  # fmt: skip
        finally:
            if main:
                signal.signal(signal.SIGINT, old)
        client = Client(cluster)
    else:
        try:
            client = Client(address, timeout="10s")
        except (OSError, TimeoutError, ValueError) as e:  # ValueError: not an address
            why = " ".join(str(e).split())
            raise OSError(f"no Dask scheduler at {address}: {why} (expected an address such "
                          "as tcp://host:8786)") from None  # fmt: skip
    try:
        yield client.get_executor(pure=False)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def stderr_progress(line: str) -> None:
    print(line, file=sys.stderr, flush=True)
