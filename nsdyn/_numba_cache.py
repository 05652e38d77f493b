"""Keep numba's on-disk cache honest across files; compile with the garbage collector held back.

numba invalidates a cached function only when its *own* source file changes, not when a kernel
it calls from another file does: after an edit of a callee the caller would silently keep the
old code compiled in. :func:`drop_stale` fingerprints every source a family's compiled kernels
depend on and deletes those kernels' cache files when the fingerprint changes. Each kernel
family calls it once at import, before any of its kernels is loaded.

Also here: :func:`compiling` (the garbage collector held back while numba compiles),
:class:`Helper` (a second process
that compiles part of a first run into the cache while this one compiles the rest) and the
switch :data:`PLAIN` (``NSDYN_PLAIN_NUMBA=1``): plain numba, without the techniques that rely
on numba's internals (calls by address, borrowed views, the helper), for
a numba whose internals changed; the kernels compute the same numbers either way.
"""

from __future__ import annotations

import gc
import hashlib
import os
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

from nsdyn._numba_light import PLAIN, PLAIN_ENV, light_loads  # noqa: F401  (re-exported)


def _plain_cache_dir() -> None:
    """Plain numba compiles the same signatures to other code (no borrowed views), so its
    cache lives apart: ``NUMBA_CACHE_DIR`` when given, else a folder of the user's cache.
    Set here, before any kernel that borrows is defined (they all import this module first)."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    folder = os.path.join(base, "nsdyn", "plain-numba")
    os.environ["NUMBA_CACHE_DIR"] = folder
    from numba.core import config

    config.CACHE_DIR = folder


if PLAIN:
    _plain_cache_dir()


def drop_stale(folder: Path, kernel_modules: Iterable[str], sources: Iterable[Path]) -> None:
    """Delete the cache files of ``kernel_modules`` (module stems in ``folder``) when any of
    ``sources`` changed since the stamp in ``folder/__pycache__`` was written. Every kernel
    family calls it at import, before its kernels load: it also installs
    :func:`nsdyn._numba_light.light_loads`."""
    light_loads()
    kernel_modules = list(kernel_modules)
    try:
        h = hashlib.sha1()
        for src in sources:
            h.update(Path(src).read_bytes())
        digest = h.hexdigest()
        name = f"nsdyn-kernels-{'-'.join(kernel_modules)}.sha1"
        if PLAIN:  # its own cache (see _plain_cache_dir), its own stamps, never the other's
            root = Path(os.environ["NUMBA_CACHE_DIR"])
            tag = hashlib.sha1(str(folder).encode()).hexdigest()[:12]
            stamp, dirs = root / "nsdyn-stamps" / f"{tag}-{name}", [root]
        else:
            stamp, dirs = folder / "__pycache__" / name, [folder / "__pycache__"]
            if os.environ.get("NUMBA_CACHE_DIR"):
                dirs.append(Path(os.environ["NUMBA_CACHE_DIR"]))
        if stamp.is_file() and stamp.read_text() == digest:
            return
        for d in dirs:
            if d.is_dir():
                for m in kernel_modules:
                    for f in d.rglob(f"{m}.*.nb[ic]"):
                        f.unlink(missing_ok=True)
        stamp.parent.mkdir(parents=True, exist_ok=True)
        stamp.write_text(digest)
    except OSError:  # read-only install or a concurrent cleaner: numba's own checks remain
        pass


def guard_family(package_init: str, extra_sources: Iterable[Path] = ()) -> None:
    """:func:`drop_stale` for every ``_k*.py`` kernel module beside ``package_init`` (a
    package's ``__file__``), which depend on each other and on ``extra_sources``."""
    folder = Path(package_init).resolve().parent
    kernels = sorted(folder.glob("_k*.py"))
    drop_stale(folder, [p.stem for p in kernels], [*kernels, *extra_sources])


COMPILE_GC_THRESHOLDS = (50_000, 20, 100)  # while numba compiles (Python default: 700, 10, 10)
SCRIPT_GC_THRESHOLD = 1_000_000  # the first generation's, for the nsdyn script's process


def hold_collections() -> None:
    """For the ``nsdyn`` script's own process: the cyclic garbage collector's first generation
    collected after a million new container objects instead of 700.

    A cached start makes ~150 000 objects that live as long as the process (the modules,
    numba's types, the loaded kernels) and little cyclic garbage; with Python's thresholds
    it traversed them in ~190 collections, ~0.1 s of a ~1.1 s start (one full collection
    ~50 ms). Held back: none. Garbage that reference counting frees does not count towards
    the threshold, so what waits is cyclic garbage or live objects, a million at most
    (:func:`compiling` collects more often while numba compiles, and restores this on exit).
    Not for callers that go on (tests, notebooks): they keep Python's."""
    gc.set_threshold(SCRIPT_GC_THRESHOLD, *gc.get_threshold()[1:])


@contextmanager
def compiling() -> Iterator[None]:
    """Python's cyclic garbage collector held back while numba compiles: the objects alive on
    entry are frozen out of the collections (:func:`gc.freeze`) and the collections run ~70x
    less often; both are restored on exit.

    numba's compiler allocates millions of short-lived objects (its inliner deep-copies IR
    blocks with their variable scopes), and each default collection traverses the young
    objects again, each full one the whole heap: in a cold ``nsdyn run --t-end 1`` ~5 000
    collections took 8-9 s of ~70 s of compilation, and the inlining itself ran ~2x slower
    with them. Held back: 64 collections, 2 s, and the first run's compilation 1.17x shorter
    (CPU time, two pairs of fresh processes). The garbage is collected, later and in larger
    batches, so memory stays bounded.
    """
    old = gc.get_threshold()
    gc.freeze()
    gc.set_threshold(*COMPILE_GC_THRESHOLDS)
    try:
        yield
    finally:
        gc.set_threshold(*old)
        gc.unfreeze()


# ---- a second process compiling beside this one ----------------------------------------------

HELPER_ENV = "NSDYN_COMPILE_HELPER"  # "0": compile everything in the calling process


def jit_disabled() -> bool:
    """True under ``NUMBA_DISABLE_JIT``: the kernels run as plain Python, nothing compiles."""
    return os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0")


def compile_note(compile_s: float) -> str:
    """``"+ 1.23 s compile/load"`` for a run's report, or that nothing compiled (a run under
    ``NUMBA_DISABLE_JIT`` printed "+ 0.00 s compile/load" as though it had loaded a cache)."""
    if jit_disabled():
        return "JIT off: NUMBA_DISABLE_JIT, kernels run as Python"
    return f"+ {compile_s:.2f} s compile/load"


def helper_enabled() -> bool:
    """True when a first compilation may use a helper process: numba compiles (no
    ``NUMBA_DISABLE_JIT``), this process may use at least two cores, it is not itself a worker
    of a process pool (a study's workers keep the other cores busy), not :data:`PLAIN` (the
    helper splits the loops whose callees are called by address), and
    ``NSDYN_COMPILE_HELPER`` is not ``0``."""
    import multiprocessing

    if PLAIN or os.environ.get(HELPER_ENV, "1") == "0":
        return False
    if jit_disabled():
        return False
    if multiprocessing.parent_process() is not None:
        return False
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        cores = os.cpu_count() or 1
    return cores >= 2


class Helper:
    """A process that compiles numba kernels into the on-disk cache while this one compiles
    others (numba compiles on one thread per process, under a global lock).

    ``target`` is ``"module:function"``; the helper imports the module and calls the function
    with the garbage collector held back (:func:`compiling`). Where a standby process is
    waiting (:func:`start_standby`, its imports done beside this process's), it is the helper;
    else a new process starts. It shares this process's
    environment, hence numba's cache directory. This process waits for what it needs with
    :meth:`wait_for` and then loads it from the cache; whatever the helper did not deliver
    (it failed, was slower, or the cache is not writable) this process compiles itself, so the
    results never depend on the helper. Use as a context manager: on exit the helper is waited
    for, or, when leaving on an exception (Ctrl-C), stopped.
    """

    POLL_S = 0.05

    def __init__(self, target: str):
        self.target = target
        self.proc = _take_standby(target)  # one started early (:func:`start_standby`), or
        if self.proc is None:  # a new one (None: none can start, this process compiles all)
            self.proc = _spawn(_HELPER_CODE, target)

    def running(self) -> bool:
        return self.proc is not None and self.proc.poll() is None

    def wait_for(self, dispatchers, timeout: float = 600.0) -> bool:
        """Wait until numba's cache holds every one of ``dispatchers`` or the helper has ended
        (or ``timeout`` seconds passed). True when all are cached."""
        import time

        t_end = time.monotonic() + timeout
        while True:
            if all(dispatcher_cached(d) for d in dispatchers):
                return True
            if not self.running() or time.monotonic() > t_end:
                return all(dispatcher_cached(d) for d in dispatchers)
            time.sleep(self.POLL_S)

    def close(self, stop: bool = False) -> int | None:
        """Wait for the helper (``stop``: terminate it first); its exit code (None: none ran)."""
        if self.proc is None:
            return None
        if stop and self.proc.poll() is None:
            self.proc.terminate()
        return self.proc.wait()

    def __enter__(self) -> Helper:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        self.close(stop=exc_type is not None)


_HELPER_CODE = (
    "import sys; from nsdyn._numba_cache import helper_main; sys.exit(helper_main(sys.argv[1:]))"
)
_STANDBY_CODE = (
    "import sys; from nsdyn._numba_cache import standby_main; sys.exit(standby_main(sys.argv[1:]))"
)


def _spawn(code: str, *argv: str, stdin=None):
    """A Python process running ``code`` with ``argv`` (its output discarded); None when none
    can start. ``stdin``: ``subprocess.PIPE`` for a standby, else nothing to read."""
    import subprocess
    import sys

    # the same nsdyn as this process: the folder it was imported from first, then this
    # process's path (also where a script put it there by hand); -P: not the working
    # directory first (``nsdyn run`` in a source checkout with nsdyn installed: the helper
    # imported the checkout's nsdyn, whose kernels have another cache, and this process found
    # nothing the helper compiled), unless this process's nsdyn is the checkout's (``python
    # -c`` there: the working directory, '' on its path, comes before the installed one)
    ours = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    path = [ours, *(p for p in sys.path if p and os.path.abspath(p) != ours)]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(path))
    try:
        return subprocess.Popen(
            [sys.executable, "-P", "-c", code, *argv],
            env=env,
            stdin=subprocess.DEVNULL if stdin is None else stdin,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    except OSError:
        return None


def helper_main(argv: list[str]) -> int:
    """What a :class:`Helper` process runs: ``argv = ["module:function"]``.

    Its kernels are in the cache when ``function`` returns; the process then only ends, and
    the calling process waits for that (:meth:`Helper.close`). So every object left is moved
    out of the garbage collector's reach first (:func:`gc.freeze`), as the ``nsdyn`` script
    does for itself (:func:`nsdyn.cli.app.script`): the interpreter's last collections would
    otherwise traverse all that numba's compilation left behind, and the calling process sat
    idle for it (0.4-1.0 s of a first run in a slow hour, 0-0.2 s with the objects frozen;
    docs/dev/first-runs.md)."""
    import importlib

    if len(argv) != 1 or ":" not in argv[0]:
        return 2
    module, name = argv[0].split(":", 1)
    fn = getattr(importlib.import_module(module), name)
    with compiling():
        fn()
    gc.freeze()
    return 0


# ---- a helper started early: its imports beside this process's --------------------------------

_STANDBY = None  # the process start_standby started, until a Helper takes it or it is released


def start_standby(preload: str = "nsdyn.solve.compile_split") -> bool:
    """Start a helper process now, before its target is known: it imports numba and
    ``preload`` (the modules every helper of a family imports, ~1 s: a process of its own
    takes as long to start as this one takes to reach its first compilation) and waits for
    the target the first :class:`Helper` of this process hands it (:func:`standby_main`).
    Unused, :func:`release_standby` ends it; it also ends when this process does (its
    standard input closes). True when one was started. Only where a helper may run
    (:func:`helper_enabled`) and none is waiting already."""
    global _STANDBY
    import subprocess

    if _STANDBY is not None or not helper_enabled():
        return False
    _STANDBY = _spawn(_STANDBY_CODE, preload, stdin=subprocess.PIPE)
    return _STANDBY is not None


def _take_standby(target: str):
    """The waiting standby process, given ``target`` to run (None: none is waiting, or it
    ended)."""
    global _STANDBY
    proc, _STANDBY = _STANDBY, None
    if proc is None:
        return None
    try:
        proc.stdin.write((target + "\n").encode())
        proc.stdin.close()
    except (OSError, ValueError):  # it ended (its pipe is closed): start a new helper
        proc.wait()
        return None
    return proc


def release_standby() -> None:
    """End a standby process no :class:`Helper` took (nothing compiled, all was cached, or a
    command that ended early: a usage error, a missing scene): it is killed at once, its imports
    unfinished or not (it has written nothing), so that a short command does not wait for
    them."""
    global _STANDBY
    proc, _STANDBY = _STANDBY, None
    if proc is None:
        return
    proc.kill()  # no error if it has exited already
    try:
        proc.stdin.close()
    except OSError:  # a broken pipe: it has exited
        pass
    proc.wait()


def standby_main(argv: list[str]) -> int:
    """What a standby process runs (:func:`start_standby`): import the modules in ``argv``,
    then run the ``"module:function"`` of its first input line as :func:`helper_main` does;
    exit at once on an empty input."""
    import importlib
    import sys

    try:
        for module in argv:
            importlib.import_module(module)
    except ImportError:  # the target's own imports will say what is missing, if it runs
        pass
    line = sys.stdin.readline().strip()
    return helper_main([line]) if line else 0


def cache_folder(py_file: str | Path) -> Path | None:
    """The folder where numba keeps the cache files of the kernels of ``py_file``, found
    without importing numba (as numba's cache locators find it: ``NUMBA_CACHE_DIR`` and a
    folder named after the source's, else ``__pycache__`` beside the source); None where numba
    would choose another (a source folder that is not writable)."""
    folder = os.path.dirname(os.path.abspath(py_file))
    root = os.environ.get("NUMBA_CACHE_DIR")
    if root:
        tag = hashlib.sha1(folder.encode()).hexdigest()
        return Path(root) / f"{os.path.basename(folder)}_{tag}"
    pycache = os.path.join(folder, "__pycache__")
    if not os.access(pycache if os.path.isdir(pycache) else folder, os.W_OK):
        return None
    return Path(pycache)


def never_compiled(py_file: str | Path) -> bool:
    """True when numba's cache holds no kernel of the folder of ``py_file`` at all: its
    kernels have never been compiled into this cache (a fresh install, a new
    ``NUMBA_CACHE_DIR``), a first run's cheap guess, made before numba is imported. False when
    it holds some (they may still be stale: the run's own probe decides then) or the folder
    is unknown."""
    folder = cache_folder(py_file)
    if folder is None:
        return False
    try:
        return not any(name.endswith(".nbi") for name in os.listdir(folder))
    except FileNotFoundError:
        return True
    except OSError:
        return False


def _cache_index(disp) -> tuple:
    """numba's on-disk cache file of the dispatcher ``disp`` and its index for the current
    source ({key: data file}; keys start with the signature): private numba API, read here
    only (raises whatever numba's internals raise)."""
    cf = disp._cache._cache_file
    return cf, cf._load_index()


def dispatcher_cached(disp) -> bool:
    """True when the numba dispatcher ``disp`` is compiled in this process or numba's on-disk
    cache holds it for its current source (False: its first call compiles, or the cache
    cannot be inspected). Always True under ``NUMBA_DISABLE_JIT`` (nothing compiles)."""
    if not hasattr(disp, "signatures"):  # NUMBA_DISABLE_JIT: a plain function
        return True
    if disp.signatures:
        return True
    try:
        cf, index = _cache_index(disp)  # {} when absent or stale
        # numba writes the index before the data file (each atomically): an entry whose
        # file is not there yet is not loadable yet (a helper is still saving it)
        return bool(index) and all(os.path.exists(cf._data_path(f)) for f in index.values())
    except Exception:  # noqa: BLE001  (a private numba API: any failure means "unknown")
        return False


# ---- a notice before a first compilation ---------------------------------------------------


def all_cached(dispatchers: Iterable) -> bool:
    """True when every numba dispatcher of ``dispatchers`` is ready (:func:`dispatcher_cached`):
    a family's run then only loads its kernels."""
    return all(dispatcher_cached(d) for d in dispatchers)


@contextmanager
def first_compile(family: str, about_s: float, cached: bool) -> Iterator[bool]:
    """Around the first call of a family's kernels: unless ``cached``, one line on stderr
    *before* numba starts compiling (``compiling the <family> kernels once (about N s; cached
    afterwards)…``) and, when the block ends without an error, how long it took. Yields True
    when the kernels compile now. Printed also for ``--json`` runs (stderr is not the JSON)."""
    import sys
    import time

    cold = not cached
    if cold:
        print(
            f"compiling the {family} kernels once (about {about_s:.0f} s; cached afterwards)…",
            file=sys.stderr,
            flush=True,
        )
    t0 = time.perf_counter()
    yield cold
    if cold:
        print(f"  compiled in {time.perf_counter() - t0:.1f} s", file=sys.stderr, flush=True)


# ---- one compilation per kernel and argument types ------------------------------------------


def runtime_types(sig: tuple) -> tuple:
    """The argument types ``sig`` stands for at run time: a literal argument (``0``, ``True``,
    ``-1`` written in the caller) as its plain type, an omitted default as its value's type."""
    from numba import typeof, types

    out = []
    for t in sig:
        if isinstance(t, types.Omitted):
            t = typeof(t.value)
        out.append(types.unliteral(t))
    return tuple(out)


def _on_disk_signatures(disp) -> list[tuple]:
    """The signatures numba's on-disk cache holds for ``disp``'s current source (any process
    may have compiled them: a compile helper, a test worker); [] when it cannot be read."""
    try:
        return [key[0] for key in _cache_index(disp)[1]]
    except Exception:  # noqa: BLE001  (a private numba API: any failure means "none known")
        return []


def repeated_compilations(prefix: str = "nsdyn") -> list[tuple[str, list[tuple]]]:
    """The kernels of the loaded modules under ``prefix`` compiled more than once for the same
    run-time argument types (in this process or, as numba's on-disk cache records, in any
    other), with their signatures.

    numba compiles a kernel once per signature, and a constant argument is a signature of its
    own: ``f(x, 0)`` beside ``f(x, i)`` compiles ``f`` twice, as does ``g(A, piv)`` beside
    ``g(A, piv, tol)``. The kernels pass such arguments as typed values (``np.int64(0)``,
    ``np.bool_(True)``) and write defaults out, so that each compiles once."""
    import sys

    from numba.core.dispatcher import Dispatcher

    seen: dict[int, tuple[str, list[tuple]]] = {}
    for name, mod in list(sys.modules.items()):
        if mod is None or not (name == prefix or name.startswith(prefix + ".")):
            continue
        for obj in list(vars(mod).values()):
            if not isinstance(obj, Dispatcher) or id(obj) in seen:
                continue
            sigs = list(dict.fromkeys([*obj.signatures, *_on_disk_signatures(obj)]))
            if len({runtime_types(s) for s in sigs}) < len(sigs):
                qual = f"{obj.py_func.__module__}.{obj.py_func.__qualname__}"
                seen[id(obj)] = (qual, sigs)
    return sorted(seen.values(), key=lambda r: r[0])
