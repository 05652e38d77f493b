"""Fixtures shared by the model families' tests: the check of the table export of a result."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from nsdyn._tabular import columns


def _assert_round_trip(res) -> None:
    """Every history of ``res`` (name -> array on ``res.t``) comes back exactly from the
    DataFrame and the Dataset, nothing is added, and the summary rides along as attributes.

    Exact equality is the tolerance: the export computes nothing, it only labels the arrays."""
    pd = pytest.importorskip("pandas", reason="pandas is not installed (the 'frames' extra)")
    xr = pytest.importorskip("xarray", reason="xarray is not installed (the 'frames' extra)")
    want = columns(res.t, res.histories())
    assert want, "a result with no histories"
    df = res.to_dataframe()
    assert isinstance(df, pd.DataFrame) and df.index.name == "t_s"
    np.testing.assert_array_equal(df.index.to_numpy(), res.t)
    assert list(df.columns) == list(want)
    for name, a in want.items():
        got = df[name].to_numpy()
        assert got.dtype == a.dtype, name
        np.testing.assert_array_equal(got, a, err_msg=name)
    assert df.attrs == res.summary()
    ds = res.to_xarray()
    assert isinstance(ds, xr.Dataset)
    np.testing.assert_array_equal(ds["t_s"].values, res.t)
    assert sorted(ds.data_vars) == sorted(want)
    for name, a in want.items():
        np.testing.assert_array_equal(ds[name].values, a, err_msg=name)
    # the tables are copies: zeroing them leaves the result's histories as they were (a
    # Dataset edited in place zeroed the result's arrays, its summary still the old peaks)
    for name in want:
        ds[name].values[:] = 0.0
    again = columns(res.t, res.histories())
    for name, a in want.items():
        np.testing.assert_array_equal(again[name], a, err_msg=name)
    # the histories are the result's own arrays, read-only: an edit in place raises (scaling
    # a history in place changed the result's summary)
    for name, a in res.histories().items():
        assert not a.flags.writeable, name
        with pytest.raises(ValueError, match="read-only"):
            a[...] = 0.0
    # and so are the result's own arrays (res.theta scaled in place changed the summary, and
    # left it disagreeing with the tables)
    for name, a in vars(res).items():
        if isinstance(a, np.ndarray):
            assert not a.flags.writeable, name
    # and the arrays its properties compute (a deck's slips u, v were writable: an edit in
    # place changed nothing the result holds, silently)
    props = [n for n in dir(type(res)) if isinstance(getattr(type(res), n), property)]
    for name in props:
        a = getattr(res, name)
        if isinstance(a, np.ndarray):
            assert not a.flags.writeable, name
    # as are those of a result's response (r.response.x_iso edited in place changed the
    # summary's x_iso_max_m), and a result compares without numpy's ambiguous truth value
    response = getattr(res, "response", None)  # (an isolated frame's Response)
    for name, a in (vars(response) if hasattr(response, "__dict__") else {}).items():
        if isinstance(a, np.ndarray):
            assert not a.flags.writeable, f"response.{name}"
    twin = copy.deepcopy(res)  # (a pickled result, as a study worker's, is copied alike)
    assert (twin == res) is False  # (as objects: arrays have no one truth value)
    for obj in (twin, getattr(twin, "response", None)):
        for name, a in (vars(obj) if hasattr(obj, "__dict__") else {}).items():
            if isinstance(a, np.ndarray):
                assert not a.flags.writeable, f"a copy's {name}"


@pytest.fixture
def assert_round_trip():
    """The round-trip check of ``to_dataframe()`` / ``to_xarray()`` (see _assert_round_trip)."""
    return _assert_round_trip
