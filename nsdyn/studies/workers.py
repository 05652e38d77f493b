"""Local process pools whose workers die with the process that started them.

A ``ProcessPoolExecutor``'s workers outlive a parent that is killed outright (SIGKILL, the
out-of-memory killer, a crashed terminal): they keep computing, or idle holding their memory,
until someone finds them. Every pool of the studies and the command line is made by
:func:`process_pool`, whose workers

* ask the kernel for SIGKILL when their parent dies (Linux ``prctl(PR_SET_PDEATHSIG)``), and
* watch the parent's pid from a daemon thread as a portable fallback (every
  ``WATCH_S`` seconds: a worker whose parent is gone is re-parented, ``os.getppid()`` changes,
  and it exits at once).

A parent that dies between the fork and the ``prctl`` call is caught by the same pid check, made
once right after it.

A Ctrl-C or SIGTERM while a pool runs is held until the waiting loop can act on it
(:class:`Interrupts`): raised anywhere, it could leave the lock of a future held by the
waiting thread (``concurrent.futures.wait`` takes every pending future's lock), and the
pool's manager thread, which needs that lock, would then keep the process from ending.

Also here: :func:`warm_isolated`, the isolated frame's kernels compiled (or loaded) in the
parent before a pool's workers start, so that the workers load them from numba's cache instead
of each compiling them at the same time.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import signal
import sys
import threading
import time
import warnings
from concurrent.futures import FIRST_EXCEPTION, ProcessPoolExecutor, wait
from contextlib import contextmanager, suppress

from nsdyn.atomic import caused_by_interrupt

WATCH_S = 0.5  # seconds between the fallback's checks of the parent's pid
WAIT_S = 0.2  # seconds between the checks of a waiting loop for held signals (gather)
GRACE_S = 3.0  # seconds an interrupted pool's tasks get to save their checkpoints (gather)
SAVE_SIGNAL = getattr(signal, "SIGUSR1", None)  # the parent's "save and stop" to its workers
PR_SET_PDEATHSIG = 1  # <linux/prctl.h>


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by another user (a recycled pid: still "alive")
        return True
    return True


def _die_with(parent: int) -> None:
    """Pool initializer: end this worker when process ``parent`` ends, and on SIGTERM (a
    forked worker inherits its parent's handlers: the command's SIGTERM handler would turn
    the signal into an exception that the pool reports as the task's result, and the worker
    would live on)."""
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    ppid = os.getppid()  # the parent itself (fork, spawn) or a fork server started by it
    if ppid == parent and sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
            libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        except (OSError, AttributeError):  # no libc to ask: the watchdog alone
            pass

    def gone() -> bool:
        return os.getppid() != ppid or not _alive(parent)

    if gone():  # the parent died before the request took effect
        os._exit(1)

    def watch() -> None:
        while not gone():
            time.sleep(WATCH_S)
        os._exit(1)

    threading.Thread(target=watch, name="nsdyn-parent-watch", daemon=True).start()


class _Pool(ProcessPoolExecutor):
    """A process pool that, left by an exception (Ctrl-C among them) in a ``with`` block, ends
    its workers instead of waiting for their tasks (:func:`stop_pool`)."""

    def __exit__(self, exc_type, exc, tb):
        if exc_type is None:
            return super().__exit__(exc_type, exc, tb)
        stop_pool(self, kill=True)
        return False


def _worker(parent: int) -> None:
    """Pool initializer: :func:`_die_with` ``parent``; a record's units are not said again
    by every task (a study said them once, when it checked its tasks; the filter is this
    worker process's own); and a Ctrl-C is the parent's to act on (a terminal sends it to
    every process of the command: an idle worker printed a traceback), as is SAVE_SIGNAL
    outside a task that saves on it (:func:`saved_on_interrupt`)."""
    for sig in (signal.SIGINT, SAVE_SIGNAL):  # (first: a Ctrl-C during the imports below)
        if sig is not None:
            signal.signal(sig, signal.SIG_IGN)
    from nsdyn.ground import UnitWarning

    warnings.simplefilter("ignore", UnitWarning)
    _die_with(parent)


def process_pool(max_workers: int | None = None) -> ProcessPoolExecutor:
    """A ``ProcessPoolExecutor`` whose workers end when this process ends, however it ends, and
    whose ``with`` block, left by an exception, ends them at once."""
    return _Pool(max_workers=max_workers, initializer=_worker, initargs=(os.getpid(),))


def stop_pool(executor, *, kill: bool) -> None:
    """Shut ``executor`` down without waiting; cancel what has not started. With ``kill`` (the
    caller is leaving on an interrupt or an error) its worker processes are killed first: a
    running task is abandoned, not waited for, and the pool's manager thread, finding its
    workers gone, ends at once. Without it the interpreter's exit joins that thread, which
    waits for the running tasks and can hang after a cancellation (CPython's process pool,
    gh-94440), so a Ctrl-C might not end the command."""
    if executor is None:
        return
    if kill:  # SIGKILL: a task that catches or ignores SIGTERM cannot hold the worker
        for proc in list((getattr(executor, "_processes", None) or {}).values()):
            try:
                proc.kill()
            except (OSError, AttributeError):
                pass  # already gone
    executor.shutdown(wait=False, cancel_futures=True)


class Interrupts:
    """SIGINT and SIGTERM held while the block runs: a signal only sets :attr:`requested`,
    and :meth:`check` (called by the waiting loop between its waits) raises
    ``KeyboardInterrupt`` then; leaving the block restores the handlers and raises it if a
    signal came after the last check. Outside the main thread nothing is held (Python
    delivers signals to the main thread only)."""

    def __init__(self) -> None:
        self.requested = False
        self._old: dict = {}

    def _hold(self, signum, frame) -> None:
        self.requested = True

    def check(self) -> None:
        """Raise ``KeyboardInterrupt`` once for the signals held since the last check."""
        if self.requested:
            self.requested = False
            raise KeyboardInterrupt

    def __enter__(self) -> Interrupts:
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._old[sig] = signal.signal(sig, self._hold)
        return self

    def __exit__(self, exc_type, exc, tb) -> bool:
        for sig, old in self._old.items():
            signal.signal(sig, old)
        self._old.clear()
        if exc_type is None:
            self.check()
        return False


@contextmanager
def saved_on_interrupt(save):
    """Run the block; ended by an interrupt (:func:`caused_by_interrupt`), call ``save()``
    with further signals held (:class:`Interrupts`), then let the interrupt go on: a long
    task keeps what it finished since its last checkpoint."""
    main = threading.current_thread() is threading.main_thread() and SAVE_SIGNAL is not None
    old = signal.signal(SAVE_SIGNAL, _raise_interrupt) if main else None
    try:
        yield
    except BaseException as exc:
        if caused_by_interrupt(exc):
            with Interrupts():
                save()
        raise
    finally:
        if main:
            signal.signal(SAVE_SIGNAL, old)


def _raise_interrupt(signum, frame) -> None:
    raise KeyboardInterrupt


def gather(executor, futures: list) -> list:
    """The results of ``futures`` in order, signals held while waiting (:class:`Interrupts`);
    the first task's error as soon as it comes. Interrupted, the workers of a local pool
    (:func:`process_pool`) are sent SAVE_SIGNAL and given GRACE_S for their tasks to save what
    they hold (:func:`saved_on_interrupt`), then the interrupt goes on (the pool's ``with``
    block ends them); a second interrupt does not wait."""
    own = isinstance(executor, _Pool) and SAVE_SIGNAL is not None  # (another's would die of it)
    procs = list((getattr(executor, "_processes", None) or {}).values()) if own else []
    with Interrupts() as stop:
        pending = futures
        while pending:
            done, pending = wait(pending, timeout=WAIT_S, return_when=FIRST_EXCEPTION)
            for f in done:  # a task that failed: said now, not after the others' hours
                if f.exception() is not None:
                    f.result()
            if stop.requested:
                stop.requested = False
                for proc in procs:
                    with suppress(OSError):
                        os.kill(proc.pid, SAVE_SIGNAL)
                t_end = time.monotonic() + GRACE_S * bool(procs)
                while pending and not stop.requested and time.monotonic() < t_end:
                    pending = wait(pending, timeout=WAIT_S)[1]
                raise KeyboardInterrupt
    return [f.result() for f in futures]


def warm_isolated(method: str, law: str) -> bool:
    """Compile (or load from numba's cache) in this process, before a pool's workers start, the
    isolated frame's integrator and metrics kernels of runs with ``method`` ("auto" and unknown
    names: the default Radau) and friction ``law``; the workers then load them from the cache.
    Into an empty cache each worker would compile them at the same time, which on a machine
    with one core per worker costs as long as compiling them once per worker, one after the
    other; here the first compilation shares the cores with its helper process
    (:func:`nsdyn.solve.methods.warmup_kernel`). Says so on stderr, before it starts and
    with the time it took. Nothing when numba's cache holds them already. True when they
    compiled."""
    from nsdyn.solve.methods import (
        FLAT_LAWS,
        METHODS,
        is_cached,
        kernel_for,
        metrics_for,
        warmup_kernel,
    )

    method = method if method in METHODS else "radau"
    flat = law in FLAT_LAWS
    kernel = kernel_for(method, flat=flat)
    metrics = metrics_for(kernel)
    if is_cached(kernel) and is_cached(metrics):
        return False  # nothing to compile: the workers load them (loading here too costs time)
    print(f"compiling the isolated-frame kernels ({method}) once, before the workers start "
          "(first run only, cached afterwards)…", file=sys.stderr, flush=True)  # fmt: skip
    t0 = time.perf_counter()
    warmup_kernel(kernel, metrics=metrics)
    print(f"  compiled in {time.perf_counter() - t0:.1f} s", file=sys.stderr, flush=True)
    return True
