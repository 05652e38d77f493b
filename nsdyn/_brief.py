"""Brief ``repr`` of the package's dataclasses: every field, arrays by shape and dtype.

A dataclass's own ``repr`` prints every array in full: a transient result's ran to 66 000
characters (its system's matrices, every history), a screenful of numbers where a notebook
user wanted to see what the object is. :func:`brief_repr` keeps the dataclass form, one
``name=value`` per field, with arrays, sparse matrices, nested models and long containers
shown by what they are (``x=<array (2001, 26) float64>``); short values as themselves.
"""

from __future__ import annotations

import dataclasses

import numpy as np

WIDTH = 60  # a value's repr longer than this is shown in brief


def brief(v) -> str:
    """One value in at most about ``WIDTH`` characters."""
    if isinstance(v, np.ndarray):
        if v.ndim <= 1 and v.size <= 4:
            return np.array2string(v, precision=4, separator=", ")
        return f"<array {v.shape} {v.dtype}>"
    if hasattr(v, "nnz") and hasattr(v, "shape"):  # a scipy.sparse matrix or array
        return f"<sparse {tuple(v.shape)} nnz={v.nnz}>"
    if isinstance(v, float):
        return f"{v:.6g}"
    r = repr(v)
    if len(r) <= WIDTH:
        return r
    if dataclasses.is_dataclass(v) and not isinstance(v, type):
        name = getattr(v, "name", None)
        return f"<{type(v).__name__}{f' {name!r}' if isinstance(name, str) else ''}>"
    if isinstance(v, list | tuple | dict | set):
        return f"<{type(v).__name__} of {len(v)}>"
    return r[: WIDTH - 3] + "..."


def brief_repr(self) -> str:
    """``Class(field=value, ...)`` of a dataclass instance, each value :func:`brief`."""
    parts = (
        f"{f.name}={brief(getattr(self, f.name, None))}" for f in dataclasses.fields(self) if f.repr
    )
    return f"{type(self).__name__}({', '.join(parts)})"
