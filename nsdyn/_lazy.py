"""Lazy re-exports for package ``__init__`` modules (PEP 562).

A package lists its public names as ``{name: "module"}`` (or ``"module:attr"`` where the public
name differs); each loads on first use and is then cached in the package namespace, so importing
the package costs nothing until a name is used — the command line stays fast to start. A
subpackage loads the same way (``import nsdyn`` then ``nsdyn.plot.plot_transient``).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable


def exports(namespace: dict, api: dict[str, str]) -> tuple[Callable, Callable]:
    """``(__getattr__, __dir__)`` for a package whose ``globals()`` is ``namespace``."""
    package = namespace["__name__"]

    def __getattr__(name: str):
        where = api.get(name)
        if where is None and not name.startswith("_") and _is_submodule(package, name):
            return importlib.import_module(f"{package}.{name}")  # nsdyn.plot after import nsdyn
        if where is None:
            from nsdyn._checks import did_you_mean

            hint = did_you_mean(name, list(api))
            err = AttributeError(f"module {package!r} has no attribute {name!r}{hint}")
            if hint:  # (said: Python's own "Did you mean" said it again)
                err.name = None
            raise err
        module, _, attr = where.partition(":")
        value = getattr(importlib.import_module(module), attr or name)
        namespace[name] = value  # later lookups skip this hook
        return value

    def __dir__() -> list[str]:
        return sorted(set(api) | {k for k in namespace if not k.startswith("_")})

    return __getattr__, __dir__


def _is_submodule(package: str, name: str) -> bool:
    import importlib.util

    try:
        return importlib.util.find_spec(f"{package}.{name}") is not None
    except (ImportError, ValueError):
        return False


class LazyModule:
    """A module imported on its first attribute lookup: ``sp = LazyModule("scipy.sparse")`` at
    the top of a module, ``sp.csr_array(...)`` in its functions. For the SciPy modules the
    frame's assembly and reduction use: importing any of them imports SciPy's array-API layer
    (~0.2 s), which a run of a model loaded from the model cache
    (:mod:`nsdyn._model_cache`) never needs; and for the kernel modules of the integration
    methods a run does not use (numba makes a dispatcher for each kernel at import)."""

    __slots__ = ("_name", "_module")

    def __init__(self, name: str):
        object.__setattr__(self, "_name", name)
        object.__setattr__(self, "_module", None)

    def __getattr__(self, attr: str):
        module = self._module
        if module is None:
            module = importlib.import_module(self._name)
            object.__setattr__(self, "_module", module)
        return getattr(module, attr)

    def __repr__(self) -> str:
        return f"<lazy module {self._name!r}{'' if self._module is None else ' (imported)'}>"


def issparse(x) -> bool:
    """``scipy.sparse.issparse(x)`` without importing SciPy: a matrix can only be sparse when
    ``scipy.sparse`` has been imported already."""
    import sys

    sparse = sys.modules.get("scipy.sparse")
    return sparse is not None and bool(sparse.issparse(x))
