"""Keep numba's on-disk cache honest across files; compile with the garbage collector held back.

numba invalidates a cached function only when its *own* source file changes, not when a kernel
it calls from another file does: after an edit of a callee the caller would silently keep the
old code compiled in. :func:`drop_stale` fingerprints every source a family's compiled kernels
depend on and deletes those kernels' cache files when the fingerprint changes. Each kernel
family calls it once at import, before any of its kernels is loaded.
"""

from __future__ import annotations

import gc
import hashlib
import os
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path


def drop_stale(folder: Path, kernel_modules: Iterable[str], sources: Iterable[Path]) -> None:
    """Delete the cache files of ``kernel_modules`` (module stems in ``folder``) when any of
    ``sources`` changed since the stamp in ``folder/__pycache__`` was written."""
    kernel_modules = list(kernel_modules)
    try:
        h = hashlib.sha1()
        for src in sources:
            h.update(Path(src).read_bytes())
        digest = h.hexdigest()
        stamp = folder / "__pycache__" / f"nsdyn-kernels-{'-'.join(kernel_modules)}.sha1"
        if stamp.is_file() and stamp.read_text() == digest:
            return
        dirs = [folder / "__pycache__"]
        if os.environ.get("NUMBA_CACHE_DIR"):
            dirs.append(Path(os.environ["NUMBA_CACHE_DIR"]))
        for d in dirs:
            if d.is_dir():
                for m in kernel_modules:
                    for f in d.rglob(f"{m}.*.nb[ic]"):
                        f.unlink(missing_ok=True)
        stamp.parent.mkdir(exist_ok=True)
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
