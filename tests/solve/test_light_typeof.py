"""numba's type of an ndarray argument as nsdyn registers it (``nsdyn._numba_light``, with the
light loads): the type numba's own ``typeof`` gives — dtype, dimensions, layout, read-only
flag; tuples of arrays, nested — found without numba's check for numpy's masked arrays, which
imports ``numpy.ma``. Exact equality of numba types, against numba's own function for arrays
(``numba.core.typing.typeof._typeof_ndarray``) and its tuple rule; with plain numba, numba's
own is left in place."""

from __future__ import annotations

import numpy as np
import pytest
from numba import typeof, types
from numba.core.typing.typeof import _typeof_ndarray
from numba.extending import typeof_impl

from nsdyn._numba_cache import PLAIN
from nsdyn._numba_light import light_loads


def _readonly(a):
    a = a.copy()
    a.flags.writeable = False
    return a


def numbas(value):
    """numba's own typeof: its ndarray function, its tuple rule, the rest as registered."""
    if type(value) is np.ndarray:
        return _typeof_ndarray(value, None)
    if type(value) is tuple:
        return types.BaseTuple.from_types([numbas(v) for v in value], tuple)
    return typeof(value)


M = np.arange(12.0).reshape(3, 4)
CASES = {
    "vector": np.zeros(5),
    "int vector": np.zeros(3, np.int64),
    "bool": np.zeros(2, bool),
    "complex": np.zeros(2, complex),
    "float32": np.zeros(2, np.float32),
    "scalar array": np.array(1.5),
    "empty": np.zeros((0, 3)),
    "C matrix": M,
    "F matrix": np.asfortranarray(M),
    "strided (A)": M[:, ::2],
    "column view (A)": M[:, 1],
    "3-D": np.zeros((2, 3, 4)),
    "read-only": _readonly(M),
    "float": 1.5,
    "int": 3,
    "np.int64": np.int64(2),
    "tuple": (np.zeros(2), np.zeros((2, 2))),
    "uniform tuple": (np.zeros(2), np.ones(3)),
    "nested tuple": ((np.zeros(2), np.zeros(1, np.int64)), np.zeros(1), 1.0),
    "empty tuple": (),
    "object array": np.array([object(), None], dtype=object),
    "record array": np.zeros(2, dtype=[("a", "f8"), ("b", "i8")]),
}


@pytest.mark.parametrize("name", list(CASES))
def test_the_registered_typeof_is_numbas(name):
    light_loads()
    value = CASES[name]
    assert typeof(value) == numbas(value)


def test_it_is_registered_unless_plain():
    light_loads()
    registered = typeof_impl.dispatch(np.ndarray)
    assert (registered is _typeof_ndarray) == PLAIN


def test_a_masked_array_is_refused_as_before():
    """A masked array (a subclass of ndarray) goes to numba's own function, which refuses it."""
    light_loads()
    value = np.ma.masked_array([1.0, 2.0])
    with pytest.raises(Exception) as ours:
        typeof(value)
    with pytest.raises(Exception) as own:
        _typeof_ndarray(value, None)
    assert type(ours.value) is type(own.value) and str(ours.value) == str(own.value)
