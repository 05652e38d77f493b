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

Without the JIT (``NUMBA_DISABLE_JIT=1``) both are plain Python: ``borrowed`` returns its
argument and ``alive`` does nothing; with plain numba (``NSDYN_PLAIN_NUMBA=1``,
:data:`nsdyn._numba_cache.PLAIN`) the compiled code does the same (numba counts references
as usual), so nothing here depends on numba's array layout.
"""

from numba import types
from numba.core import cgutils, errors
from numba.extending import intrinsic, overload
from numba.np.arrayobj import make_array

from nsdyn._numba_cache import PLAIN


def borrowed(a):
    """A view of the array (or each array of the nested tuple) ``a`` without reference counts."""
    return a


def alive(owners):
    """Keep ``owners`` referenced up to this point of a compiled function."""
    return None


def _borrow_one(context, builder, aty, value):
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


@intrinsic
def _borrowed(typingctx, a):
    if not _arrays(a):
        return None

    def codegen(context, builder, sig, args):
        return _borrow(context, builder, a, args[0])

    return a(a), codegen


@intrinsic
def _alive(typingctx, owners):
    def codegen(context, builder, sig, args):
        return context.get_dummy_value()

    return types.none(owners), codegen


@overload(borrowed)
def _borrowed_impl(a):
    if not _arrays(a):
        raise errors.TypingError(f"borrowed: expected an array or a tuple of arrays, got {a}")
    if PLAIN:
        return lambda a: a
    return lambda a: _borrowed(a)


@overload(alive)
def _alive_impl(owners):
    if PLAIN:
        return lambda owners: None
    return lambda owners: _alive(owners)
