"""Numba kernels: borrowed array views, which the hot loops pass around without reference counts.

numba counts references to every array it passes to a compiled function that is not inlined,
takes out of a tuple or binds to a new variable: an atomic increment and decrement of the
array's memory-info block, each a locked instruction that drains the store buffer. A Radau
step of the default run passes ~40 arrays (the workspace and the 17 arrays of the system
tuple) through Newton's iteration and seven right-hand-side calls: ~480 such operations per
step, ~15 % of the run.

``borrowed(a)`` returns a view of ``a`` (same data, shape and strides) without a memory-info
block: numba's reference counting skips it (a null check instead of an atomic operation).
For (nested) tuples of arrays it borrows every member. The view does not keep ``a`` alive, so

- the owner must outlive every use of the view: a run loop borrows what it owns (or what its
  caller owns) and ends with ``alive(owners)``, which keeps its own arrays referenced until
  there (numba releases a variable after its last use);
- a borrowed view must never be returned to Python (boxing it would give NumPy an array
  whose memory nobody owns): a kernel returns its owned arrays.

Both are typed and lowered at each call site (numba's low-level extension API,
``type_callable`` and ``lower_builtin``): an ``@overload`` would compile a function of its own
for each argument type, ~0.5 s of a first run's compilation.

Without the JIT (``NUMBA_DISABLE_JIT=1``) both are plain Python: ``borrowed`` returns its
argument and ``alive`` does nothing; with plain numba (``NSDYN_PLAIN_NUMBA=1``,
:data:`nsdyn._numba_cache.PLAIN`) the compiled code does the same (numba counts references
as usual), so nothing here depends on numba's array layout.
"""

from numba import types
from numba.core import cgutils, errors
from numba.extending import lower_builtin, overload, type_callable

from nsdyn._numba_cache import PLAIN


def borrowed(a):
    """A view of the array (or each array of the nested tuple) ``a`` without reference counts."""
    return a


def alive(owners):
    """Keep ``owners`` referenced up to this point of a compiled function."""
    return None


def _borrow_one(context, builder, aty, value):
    from numba.np.arrayobj import make_array  # compiling only: its import is ~50 ms

    src = make_array(aty)(context, builder, value=value)
    dst = make_array(aty)(context, builder)
    dst.meminfo = cgutils.get_null_value(dst.meminfo.type)
    dst.parent = cgutils.get_null_value(dst.parent.type)
    dst.nitems = src.nitems
    dst.itemsize = src.itemsize
    dst.data = src.data
    dst.shape = src.shape
    dst.strides = src.strides
    return dst._getvalue()


def _arrays(a):
    """True for an array or a (nested) tuple of arrays."""
    if isinstance(a, types.Array):
        return True
    return isinstance(a, types.BaseTuple) and all(_arrays(t) for t in a.types)


def _borrow(context, builder, aty, value):
    if isinstance(aty, types.Array):
        return _borrow_one(context, builder, aty, value)
    out = cgutils.get_null_value(context.get_value_type(aty))
    for i, t in enumerate(aty.types):
        member = builder.extract_value(value, i)
        out = builder.insert_value(out, _borrow(context, builder, t, member), i)
    return out


def _typer_borrowed(context):
    def typer(a):
        if not _arrays(a):
            raise errors.TypingError(f"borrowed: expected an array or a tuple of arrays, got {a}")
        return a

    return typer


def _typer_alive(context):
    def typer(owners):
        return types.none

    return typer


if PLAIN:

    @overload(borrowed)
    def _borrowed_plain(a):
        _typer_borrowed(None)(a)  # the same typing error for anything but arrays
        return lambda a: a

    @overload(alive)
    def _alive_plain(owners):
        return lambda owners: None

else:
    # typed and lowered at the call site (numba's low-level extension API): no function of
    # their own to compile for each argument type, as an overload's implementation would be
    type_callable(borrowed)(_typer_borrowed)
    type_callable(alive)(_typer_alive)

    @lower_builtin(borrowed, types.Any)
    def _lower_borrowed(context, builder, sig, args):
        return _borrow(context, builder, sig.args[0], args[0])

    @lower_builtin(alive, types.Any)
    def _lower_alive(context, builder, sig, args):
        return context.get_dummy_value()
