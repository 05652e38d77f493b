"""Histories of a result as a pandas DataFrame or an xarray Dataset (the ``frames`` extra).

Every family's result names its histories once, as an ordered mapping ``column -> 1-D array``
sampled on one time grid, the unit in each name (``theta_rad``, ``x_iso_0_m``, ``F_N``; see
docs/guide/conventions.md). This module turns that mapping into a table indexed by ``t_s``
(the grid [s]) without converting a value, so ``df[name].to_numpy()`` is the result's array bit
for bit; each array is copied, so that editing the table leaves the result (and its summary)
as they were. The result's ``summary()`` goes along as the table's ``attrs``.

pandas and xarray are imported only when a conversion is asked for; without them the error
names the extra to install (``pip install "nsdyn[frames]"``).
"""

from __future__ import annotations

import importlib

import numpy as np

from nsdyn._brief import brief_repr

EXTRA = "frames"  # pyproject's optional dependency group holding pandas and xarray
INDEX = "t_s"  # name of the time index of every table [s]


def _need(module: str):
    try:
        return importlib.import_module(module)
    except ImportError:
        raise ImportError(f"{module} is needed for this conversion: pip install "
                          f'"nsdyn[{EXTRA}]" (installs pandas and xarray)') from None  # fmt: skip


def columns(t: np.ndarray, named: dict) -> dict:
    """``named`` checked: every array one-dimensional, as long as ``t`` (a 2-D array ``a`` of
    shape (n, k) under the name ``"x_{}_m"`` is split into ``x_0_m`` … ``x_{k-1}_m``)."""
    t = np.asarray(t)
    out = {}
    for name, a in named.items():
        a = np.asarray(a)
        if a.ndim == 2:
            if "{}" not in name:
                raise ValueError(f"{name}: a 2-D history needs a '{{}}' in its name for the column")
            for j in range(a.shape[1]):
                out[name.format(j)] = a[:, j].copy()
            continue
        if a.ndim != 1 or a.shape[0] != t.shape[0]:
            raise ValueError(f"{name}: expected a history of {t.shape[0]} samples, got shape "
                             f"{a.shape}")  # fmt: skip
        out[name] = a.copy()  # (the table's own: an edit of it is not one of the result)
    return out


def to_dataframe(t: np.ndarray, named: dict, attrs: dict | None = None):
    """pandas DataFrame of the histories ``named`` (:func:`columns`), index ``t_s``."""
    pd = _need("pandas")
    cols = columns(t, named)
    df = pd.DataFrame(cols, index=pd.Index(np.array(t), name=INDEX), copy=False)
    df.attrs.update(attrs or {})
    return df


def to_xarray(t: np.ndarray, named: dict, attrs: dict | None = None):
    """xarray Dataset of the histories ``named`` (:func:`columns`) over the coordinate ``t_s``;
    ``attrs`` keeps the summary's scalars and strings (netCDF cannot store lists or None)."""
    xr = _need("xarray")
    cols = columns(t, named)
    ds = xr.Dataset({k: (INDEX, v) for k, v in cols.items()}, coords={INDEX: np.array(t)})
    for k, v in (attrs or {}).items():
        if isinstance(v, bool):
            ds.attrs[k] = int(v)
        elif isinstance(v, int | float | str):
            ds.attrs[k] = v
    return ds


def frozen(a) -> np.ndarray:
    """A read-only view of ``a``."""
    v = np.asarray(a).view()
    v.flags.writeable = False
    return v


def _read_only_of(fn, convert):
    """``fn(self)`` passed through ``convert`` (its arrays made read-only), marked as such."""
    import functools

    @functools.wraps(fn)
    def get(self):
        return convert(fn(self))

    get._read_only = True
    return get


def _frozen_if_array(a):
    return frozen(a) if isinstance(a, np.ndarray) else a


def read_only(named: dict) -> dict:
    """``named`` with each array a read-only view: the result's own data, not copied, that an
    edit cannot change (a history scaled in place changed the result's summary)."""
    return {name: frozen(a) for name, a in named.items()}


def freeze_arrays(obj) -> None:
    """``obj``'s array attributes made read-only once it is made: an edit in place (a history
    scaled to other units) changed its summary, or left the summary and the tables
    disagreeing; edit a copy. Each is a read-only view: an array the caller passed in (output
    times) stays the caller's to write."""
    for k, v in vars(obj).items():
        if isinstance(v, np.ndarray) and v.flags.writeable:
            view = v.view()
            view.flags.writeable = False
            object.__setattr__(obj, k, view)


class FrozenArrays:
    """Mix-in of a dataclass whose array fields are read-only (:func:`freeze_arrays`) once it
    is made, and again when unpickled or deep-copied (a study worker's result)."""

    def __post_init__(self) -> None:
        freeze_arrays(self)

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        freeze_arrays(self)


class Tabular(FrozenArrays):
    """Mix-in of a result with ``t``, ``histories()`` (name -> array on ``t``) and ``summary()``:
    ``to_dataframe()`` and ``to_xarray()`` of those histories, the summary as attributes.
    Its arrays are read-only (:class:`FrozenArrays`); every subclass's ``histories()`` returns
    read-only views (:func:`read_only`)."""

    __repr__ = brief_repr  # arrays by shape, not in full (its dataclasses set repr=False)

    def __init_subclass__(cls, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        for name, attr in list(cls.__dict__.items()):  # arrays computed on access (a deck's
            # slips u, v): read-only too, where an edit in place changed nothing, silently
            if isinstance(attr, property) and not getattr(attr.fget, "_read_only", False):
                getter = _read_only_of(attr.fget, _frozen_if_array)
                setattr(cls, name, property(getter, attr.fset, attr.fdel, attr.__doc__))
        own = cls.__dict__.get("histories")
        if own is not None and not getattr(own, "_read_only", False):
            cls.histories = _read_only_of(own, read_only)

    def histories(self) -> dict:  # pragma: no cover - every result defines it
        raise NotImplementedError

    def to_dataframe(self):
        """The histories as a pandas DataFrame indexed by ``t_s`` [s], one column per history
        (units in the names), ``df.attrs`` the summary (needs the ``frames`` extra)."""
        return to_dataframe(self.t, self.histories(), self.summary())

    def to_xarray(self):
        """The histories as an xarray Dataset over ``t_s`` [s], the summary's scalars as
        attributes (needs the ``frames`` extra)."""
        return to_xarray(self.t, self.histories(), self.summary())
