"""Cached kernels loaded light: what numba does at a process's start that only a compilation
needs, left out (:func:`light_loads`, installed by :mod:`nsdyn._kaddress` and by
:func:`nsdyn._numba_cache.drop_stale`).

Four pieces, each a wrap or a registration on numba's side (the compiled-kernels page lists
what each relies on): the load of a cached kernel without numba's refresh of its compiler
contexts, without importing numba's implementation modules for their environments, numba's
type of an ndarray argument without its question about numpy's masked arrays, and the check
that a cache folder is writable once per folder, not once per kernel.
None with plain numba (:data:`PLAIN`, ``NSDYN_PLAIN_NUMBA=1``; see :mod:`nsdyn._numba_cache`).
"""

from __future__ import annotations

import os
import sys

PLAIN_ENV = "NSDYN_PLAIN_NUMBA"  # "1": plain numba (read once, when nsdyn is imported)
PLAIN = os.environ.get(PLAIN_ENV, "0") not in ("", "0")

_LIGHT_LOADS = []  # the loader light_loads installed (at most one)


def _noop() -> None:
    return None


def light_loads() -> bool:
    """Load cached kernels without numba's compile-time registries (True when installed).

    Before it loads a kernel from its on-disk cache, numba refreshes its compiler contexts:
    it imports ~60 modules of typing and lowering implementations and installs their
    registries (0.3-0.5 s of a cached start, a third of it), which only a compilation
    uses. Loading needs the code generator and the C symbols the code calls: numba's helpers
    and math functions, installed when the context is made, and its runtime's (NRT), which
    :func:`numba.core.runtime.rtsys.initialize` installs. So the loader initialises the
    runtime and skips the refresh for the load; a compilation refreshes the contexts itself
    (numba's compiler does so before it types a kernel), as does the lowering of any call it
    does not know. Also the environments of numba's own implementations rebuilt without
    importing their modules (:func:`_light_environments`), numba's type of an ndarray
    argument without ``numpy.ma`` (:func:`_light_typeof`) and its check of a cache folder
    once, not once per kernel (:func:`_light_locators`). Not with plain numba
    (:data:`PLAIN`). Installed once per process, by :mod:`nsdyn._kaddress` (which nsdyn's
    first kernels import) or the first kernel family imported (:func:`drop_stale`)."""
    if PLAIN or _LIGHT_LOADS:
        return bool(_LIGHT_LOADS)
    from numba.core import caching
    from numba.core.runtime import rtsys

    full = caching.Cache.load_overload

    def load_overload(self, sig, target_context):
        rtsys.initialize(target_context)
        outer = "refresh" in vars(target_context)  # a load within a load: the outer restores
        if not outer:  # this load only (numba loads under its compiler lock)
            target_context.refresh = _noop
        try:
            return full(self, sig, target_context)
        finally:
            if not outer:
                vars(target_context).pop("refresh", None)

    load_overload.full = full
    caching.Cache.load_overload = load_overload
    _light_environments()
    _light_typeof()
    _light_locators()
    _LIGHT_LOADS.append(load_overload)
    return True


def _light_environments() -> None:
    """A cached kernel carries an environment for each function in its code (a Python dict of
    globals and a list of constants); numba rebuilds each when it loads the kernel, by
    importing the function's module for its globals. For the functions numba generates from
    its own implementations (an array's allocation, its copy: ``numba.np.arrayobj`` and its
    imports, ~45 ms of the isolated frame's cached start) that import serves nothing: compiled
    code without numba's object mode reads an environment's constants, never its globals
    (only object-mode lowering, ``numba.core.pylowering``, looks names up in them). An
    environment of a module under ``numba.`` that is not imported yet is rebuilt with its
    constants and a globals dict holding only the module's name (which numba's cache checks
    to save it again); any other, as numba does."""
    from numba.core import environment

    full = environment._rebuild_env

    def _rebuild_env(modname, consts, env_name):
        if modname in sys.modules or not modname.startswith("numba."):
            return full(modname, consts, env_name)
        env = environment.lookup_environment(env_name)
        if env is None:
            env = environment.Environment({"__name__": modname})
            env.consts[:] = consts
            env.env_name = env_name
            environment.Environment._memo[env_name] = env
        return env

    _rebuild_env.full = full
    # an environment saved to the cache names its rebuild by numba's module and name: this one
    # is found there, and a process with plain numba loads the entry with numba's own
    _rebuild_env.__module__, _rebuild_env.__qualname__ = full.__module__, full.__qualname__
    environment._rebuild_env = _rebuild_env


def _light_locators() -> None:
    """numba checks that a kernel's cache folder is writable when it makes the kernel's
    dispatcher (at import), by creating and deleting a temporary file in it: once per kernel,
    ~100 for the default run (101 dispatchers), 20-30 ms of a cached start. Checked once per folder
    instead (a folder that fails the check is asked again, as numba would)."""
    from numba.core import caching

    checked = set()
    full = caching._CacheLocator.ensure_cache_path

    def ensure_cache_path(self):
        path = self.get_cache_path()
        if path not in checked:
            full(self)
            checked.add(path)

    ensure_cache_path.full = full
    caching._CacheLocator.ensure_cache_path = ensure_cache_path


def _light_typeof() -> None:
    """numba's type of an ndarray argument without its question whether the array is one of
    numpy's masked arrays (``isinstance(val, np.ma.MaskedArray)``), for which numpy 2 imports
    ``numpy.ma`` (~20 ms of a cached start): registered for exactly ``np.ndarray`` through
    numba's extension API (``numba.extending.typeof_impl``); any other array, a subclass (a
    masked one) or an unsupported dtype, goes to numba's own. The same types
    (``tests/solve/test_light_typeof.py``)."""
    import numpy as np
    from numba import types
    from numba.extending import typeof_impl
    from numba.np.numpy_support import from_dtype

    numbas = typeof_impl.dispatch(np.ndarray)

    @typeof_impl.register(np.ndarray)
    def _typeof_ndarray(val, c):
        if type(val) is not np.ndarray:
            return numbas(val, c)
        try:
            dtype = from_dtype(val.dtype)
        except Exception:  # noqa: BLE001  (numba's own says what it does not support)
            return numbas(val, c)
        flags = val.flags
        layout = "C" if flags.c_contiguous else "F" if flags.f_contiguous else "A"
        return types.Array(dtype, val.ndim, layout, readonly=not flags.writeable)
