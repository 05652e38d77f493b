"""Kernels compiled without numba's Python entry point (``nsdyn._kaddress.no_entry``).

What must hold: such a kernel, called from Python, raises a TypeError naming it (numba would
jump to the entry point it never made: a crash of the process); every kernel compiled with
``NO_ENTRY`` is marked so; called from compiled code (linked, or by its address) it computes
what the kernel with its entry computes; and it is really compiled without the entry (the
option is what shortens the first compilation, see the compiled-kernels page). With plain
numba (``NSDYN_PLAIN_NUMBA=1``) and without the JIT the kernels keep their entries.
"""

import importlib
import os
import pkgutil

import numpy as np
import pytest
from numba import njit

import nsdyn
from nsdyn import _kaddress as ka
from nsdyn._numba_cache import PLAIN

JIT = os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")
needs_entryless = pytest.mark.skipif(
    not JIT or PLAIN, reason="plain numba and the interpreter keep every entry point"
)


def _kernels_without_entry() -> dict:
    """{module.name: dispatcher} of every kernel of nsdyn compiled with NO_ENTRY."""
    found = {}
    for info in pkgutil.walk_packages(nsdyn.__path__, "nsdyn."):
        if not info.name.rsplit(".", 1)[-1].startswith("_k"):
            continue
        mod = importlib.import_module(info.name)
        for obj in vars(mod).values():
            opts = getattr(obj, "targetoptions", None)
            if isinstance(opts, dict) and opts.get("no_cpython_wrapper"):
                found[f"{obj.py_func.__module__}.{obj.py_func.__qualname__}"] = obj
    return found


@needs_entryless
def test_every_entryless_kernel_raises_when_called_from_python():
    kernels = _kernels_without_entry()
    # the address-only callees of the default and the event-driven loops at least
    for name in ("_kcolloc.newton_flat", "_kradau.start_flat", "_kradau.event_step",
                 "_kevent._settle", "_kcommon.jac_table"):  # fmt: skip
        assert f"nsdyn.solve.{name}" in kernels
    for name, k in kernels.items():
        with pytest.raises(TypeError, match="compiled without a Python entry point") as err:
            k(0.0)  # refused before any argument is looked at
        assert name in str(err.value)


@needs_entryless
def test_a_kernel_with_its_entry_is_refused():
    k = njit(cache=False)(lambda x: x)
    with pytest.raises(ValueError, match="NO_ENTRY"):
        ka.no_entry(k)


@ka.no_entry
@njit(cache=False, error_model="numpy", **ka.NO_ENTRY)
def _axpy_entryless(a, x, y):
    for i in range(x.shape[0]):
        y[i] += a * x[i]
    return y.sum()


@njit(cache=False, error_model="numpy")
def _axpy(a, x, y):
    for i in range(x.shape[0]):
        y[i] += a * x[i]
    return y.sum()


@njit(cache=False, error_model="numpy")
def _calls_entryless(a, x, y):
    return _axpy_entryless(a, x, y)


def test_linked_entryless_kernel_computes_what_the_kernel_with_entry_does():
    # the same source compiled with and without the entry point, called from compiled code:
    # the same arithmetic, so the same bits
    x = np.sin(np.arange(7.0))
    y1, y2 = np.cos(np.arange(7.0)), np.cos(np.arange(7.0))
    assert _calls_entryless(0.3, x, y1) == _axpy(0.3, x, y2)
    assert np.array_equal(y1, y2)


@needs_entryless
def test_entryless_kernel_is_compiled_without_the_python_wrapper():
    # what NO_ENTRY asks numba for: the kernel's code without the wrapper that unboxes its
    # arguments from Python objects (compiled here, not loaded: the module's IR is at hand)
    from numba import types

    sig = (types.float64, types.float64[::1], types.float64[::1])
    ir = {}
    for k in (_axpy_entryless, _axpy):
        k.compile(sig)  # (nothing to do when compiled already)
        cres = k.overloads[sig]
        text = cres.library.get_llvm_str()
        assert cres.fndesc.llvm_func_name in text  # the kernel itself
        ir[k] = cres.fndesc.llvm_cpython_wrapper_name in text
    assert ir == {_axpy_entryless: False, _axpy: True}
