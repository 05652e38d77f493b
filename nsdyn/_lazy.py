"""Lazy re-exports for package ``__init__`` modules (PEP 562).

A package lists its public names as ``{name: "module"}`` (or ``"module:attr"`` where the public
name differs); each loads on first use and is then cached in the package namespace, so importing
the package costs nothing until a name is used — the command line stays fast to start.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable


def exports(namespace: dict, api: dict[str, str]) -> tuple[Callable, Callable]:
    """``(__getattr__, __dir__)`` for a package whose ``globals()`` is ``namespace``."""
    package = namespace["__name__"]

    def __getattr__(name: str):
        where = api.get(name)
        if where is None:
            import difflib

            close = difflib.get_close_matches(name, list(api), n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise AttributeError(f"module {package!r} has no attribute {name!r}{hint}")
        module, _, attr = where.partition(":")
        value = getattr(importlib.import_module(module), attr or name)
        namespace[name] = value  # later lookups skip this hook
        return value

    def __dir__() -> list[str]:
        return sorted(set(api) | {k for k in namespace if not k.startswith("_")})

    return __getattr__, __dir__
