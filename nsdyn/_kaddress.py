"""Numba kernels: calls to compiled kernels by their address, so a loop's code holds only its own.

numba compiles a called kernel once as a function of its own and then links a copy of it into
every caller's code, where LLVM optimises it once more: the default Radau loop spent ~5 s of its
~9 s first compilation on its callees' copies (Newton, the flat right-hand side, the start-up),
and could not be compiled before them. A loop that calls a kernel by address instead
(:func:`call` with ``K`` an int64 array of addresses) is compiled from its own source alone,
before or beside its callees, which each compile once.

``call(K, name, args, general)`` calls the callee registered as ``name`` (:func:`slot`: its
index in ``K`` and the kernel it stands for) on ``args``:

- ``K`` None: that kernel directly, as numba does it (a copy linked into the caller), with
  the caller's ``general`` kernel appended where the kernel takes one;
- ``K`` a 2-row int64 array: through the address ``K[0, index]`` of a compiled kernel declared
  under ``name`` (:func:`declare`: its argument types and return type), with numba's own
  calling convention (the callee's exceptions propagate). The declaration is checked three
  times: the call's argument types must equal the declared ones when the caller is typed
  (else a typing error names the callee); the address must come from a compilation for
  exactly those types returning the declared type (:class:`nsdyn.solve.compile_split.Callee`);
  and at every call ``K[1, index]``, the :func:`digest` of the declaration the address was
  taken for, must equal the digest compiled into the caller (a caller loaded from numba's
  cache was typed in another process, possibly against other declarations: it raises a
  RuntimeError instead of calling code of another type).

(A tuple of kernels would be the obvious ``K`` for direct calls, but numba types a tuple of
dispatchers as first-class function pointers, whose callers it refuses to cache.) Without the
JIT (``NUMBA_DISABLE_JIT=1``) ``call`` is plain Python and ``K`` a tuple of functions.
"""

import hashlib

from numba import types
from numba.core import cgutils, errors
from numba.extending import intrinsic, overload

# name -> (return type, argument types): what an address declared under name is compiled for
DECLARED: dict = {}
# name -> (index in K, kernel called directly, whether it also takes the caller's ``general``)
SLOTS: dict = {}


def declare(name: str, ret, args) -> None:
    """Declare the kernel that addresses under ``name`` point to: its numba return type
    ``ret`` and argument types ``args`` (once: another declaration under ``name`` raises)."""
    new = (ret, tuple(args))
    if DECLARED.setdefault(name, new) != new:
        raise ValueError(f"{name!r} is already declared with other types")


def digest(name: str) -> int:
    """A number that identifies the declaration of ``name`` in every process (63 bits)."""
    ret, args = DECLARED[name]
    text = repr((name, str(ret), tuple(str(a) for a in args)))
    return int.from_bytes(hashlib.sha1(text.encode()).digest()[:8], "little") >> 1


def slot(name: str, index: int, kernel, with_general: bool = False) -> None:
    """Register callee ``name``: its address is ``K[index]``; without addresses (``K`` None)
    ``kernel`` is called directly, with the caller's ``general`` kernel appended to the
    arguments when ``with_general``."""
    SLOTS[name] = (index, kernel, with_general)


def call(K, name, args, general):
    """Callee ``name`` on ``args``: through its address in ``K``, or (``K`` None) directly."""
    if K is None:
        index, kernel, with_general = SLOTS[name]
        return kernel(*args, general) if with_general else kernel(*args)
    return K[SLOTS[name][0]](*args)  # without the JIT: a tuple of the kernels


@intrinsic
def _at(typingctx, addr, check, name, args):
    if not isinstance(name, types.StringLiteral) or not isinstance(args, types.BaseTuple):
        return None
    if not (isinstance(addr, types.Integer) and isinstance(check, types.Integer)):
        return None
    key = name.literal_value
    if key not in DECLARED:
        raise errors.TypingError(f"call by address: no kernel declared as {key!r}")
    ret, declared = DECLARED[key]
    got = tuple(types.unliteral(t) for t in args.types)
    if got != declared:
        bad = [i for i, (a, b) in enumerate(zip(got, declared, strict=False)) if a != b]
        raise errors.TypingError(
            f"call by address of {key!r}: argument types differ from the declared ones "
            f"at positions {bad or 'count'} ({len(got)} given, {len(declared)} declared)"
        )
    sig = ret(types.int64, types.int64, name, types.Tuple(declared))
    expected = digest(key)

    def codegen(context, builder, sig, llargs):
        stale = builder.icmp_signed("!=", llargs[1], context.get_constant(types.int64, expected))
        with cgutils.if_unlikely(builder, stale):
            msg = (
                f"{key!r}: this compiled code was typed for another declaration of it than "
                "the address given (a stale entry of numba's cache): delete the cache "
                "(NUMBA_CACHE_DIR, or the __pycache__ folders in nsdyn/) and run again"
            )
            context.call_conv.return_user_exc(builder, RuntimeError, (msg,))
        fnty = context.call_conv.get_function_type(ret, declared)
        fn = builder.inttoptr(llargs[0], fnty.as_pointer())
        vals = [builder.extract_value(llargs[3], i) for i in range(len(declared))]
        status, res = context.call_conv.call_function(builder, fn, ret, declared, vals)
        with cgutils.if_unlikely(builder, status.is_error):
            context.call_conv.return_status_propagate(builder, status)
        return res

    return sig, codegen


@overload(call, prefer_literal=True, inline="always")
def _call_impl(K, name, args, general):
    if not isinstance(name, types.StringLiteral) or name.literal_value not in SLOTS:
        return None
    index, kernel, with_general = SLOTS[name.literal_value]
    if isinstance(K, types.NoneType):
        if with_general:
            return lambda K, name, args, general: kernel(*args, general)
        return lambda K, name, args, general: kernel(*args)
    if not (isinstance(K, types.Array) and K.ndim == 2 and K.dtype == types.int64):
        raise errors.TypingError(f"call of {name.literal_value!r}: K must be a 2-row int64 array")
    return lambda K, name, args, general: _at(K[0, index], K[1, index], name, args)
