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
  exactly those types returning the declared type (:class:`Callee`);
  and at every call ``K[1, index]``, the :func:`digest` of the declaration the address was
  taken for, must equal the digest compiled into the caller (a caller loaded from numba's
  cache was typed in another process, possibly against other declarations: it raises a
  RuntimeError instead of calling code of another type).

(A tuple of kernels would be the obvious ``K`` for direct calls, but numba types a tuple of
dispatchers as first-class function pointers, whose callers it refuses to cache.) Without the
JIT (``NUMBA_DISABLE_JIT=1``) ``call`` is plain Python and ``K`` a tuple of functions.

``tcall(name, args)`` is the same call without ``K``: through the address in row
:func:`index` of the process-wide table :data:`TABLE`, which compiled code reads through the
symbol ``nsdyn_kaddress_table`` (registered with LLVM when this module is imported, resolved
when numba loads the code, also from its cache). Deep call trees (the event-driven loop, its
detectors and handlers, each of which evaluates the system kernel) call their callees so
without passing ``K`` down; :func:`fill` (by :class:`Callee`) puts
each address and the digest of its declaration in the table before a caller runs, and every
call checks that digest (an empty row has digest 0: a RuntimeError naming the callee, never a
jump to address 0). With plain numba (:data:`nsdyn._numba_cache.PLAIN`) and without the JIT,
``tcall`` calls the kernel registered with :func:`tslot` directly.

``call`` (with ``K`` an array) and ``tcall`` are typed and lowered at their call sites
(numba's low-level extension API, ``type_callable`` and ``lower_builtin``); an
``@overload``'s implementation would be a function of its own, compiled for every callee
(~1.8 s of the event method's first compilation).

A kernel that only compiled code calls (by address or linked) is compiled without numba's
Python entry point (:data:`NO_ENTRY`, :func:`no_entry`): the entry unboxes every argument
from Python objects, ~0.2-0.5 s of the first compilation of a kernel with ~25 arguments
(~2 s of the event method's). Called from Python, such a kernel raises a TypeError (numba
itself would jump to the missing entry).

A run loop that allocates nothing is compiled without numba's reference counting
(:data:`NO_NRT`): numba otherwise emits an increment and a decrement for every array of every
tuple it copies, passes or drops, each unpacking the whole tuple's type. The event loop's
unoptimised code was 39 000 lines, 28 000 of them such unpacking (the parameter tuple ``P``
holds 17 arrays, the workspace 23), and its first compilation took 8.5 s of one core; without
reference counting, 3.6 s. Such a kernel gets every array it uses from its caller (Python,
which keeps them alive), calls kernels that return no new arrays, and returns none itself.
"""

import hashlib

import numpy as np
from llvmlite import binding as llvm
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils, errors
from numba.extending import intrinsic, lower_builtin, overload, type_callable

from nsdyn._numba_cache import PLAIN
from nsdyn._numba_light import light_loads

light_loads()  # before any kernel is defined: nsdyn's first kernels import this module

# the options of a kernel only compiled code calls (:func:`no_entry`): no Python entry point,
# no C entry point (numba's own options; plain numba keeps both)
NO_ENTRY = {} if PLAIN else {"no_cpython_wrapper": True, "no_cfunc_wrapper": True}
# the options of a run loop that allocates no array (numba's internal ``_nrt``: no reference
# counts; plain numba counts them)
NO_NRT = {} if PLAIN else {"_nrt": False}

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


def slot(name: str, index: int, kernel) -> None:
    """Register callee ``name``: its address is ``K[index]``; without addresses (``K`` None)
    ``kernel`` is called directly, or, where ``kernel`` is a dict, the kernel it gives for the
    caller's ``general`` kernel (the callee's copy made for it, :func:`specialised`)."""
    SLOTS[name] = (index, kernel)


def _for_general(name: str, kernel, general):
    """The kernel of slot ``name`` called directly by a caller whose ``general`` kernel is
    ``general`` (a dispatcher, or the Python function without the JIT)."""
    if not isinstance(kernel, dict):
        return kernel
    key = getattr(general, "py_func", general)
    for g, k in kernel.items():
        if getattr(g, "py_func", g) is key:
            return k
    raise TypeError(f"call of {name!r}: no copy of it for the general kernel {key!r}")


def call(K, name, args, general):
    """Callee ``name`` on ``args``: through its address in ``K``, or (``K`` None) directly."""
    if K is None:
        return _for_general(name, SLOTS[name][1], general)(*args)
    return K[SLOTS[name][0]](*args)  # without the JIT: a tuple of the kernels


def _checked(name, args):
    """(key, return type, declared argument types) of a call of ``name`` on ``args`` (numba
    types); a TypingError naming the callee when undeclared or of other argument types."""
    key = name.literal_value
    if key not in DECLARED and key in DECLARE_HOOKS:  # declared on demand (see tslot)
        import importlib

        module, function = DECLARE_HOOKS[key].split(":")
        getattr(importlib.import_module(module), function)()
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
    return key, ret, declared


def _codegen_call(key, ret, declared, fetch):
    """The code of a call by address: ``fetch(context, builder, llargs)`` gives the address
    and the digest it was taken for (int64 values); the call's arguments are ``llargs[-1]``."""
    expected = digest(key)

    def codegen(context, builder, sig, llargs):
        addr, check = fetch(context, builder, llargs)
        stale = builder.icmp_signed("!=", check, context.get_constant(types.int64, expected))
        with cgutils.if_unlikely(builder, stale):
            msg = (
                f"{key!r}: this compiled code was typed for another declaration of it than "
                "the address given (a stale entry of numba's cache, or an address not yet "
                "taken): delete the cache (NUMBA_CACHE_DIR, or the __pycache__ folders in "
                "nsdyn/) and run again"
            )
            context.call_conv.return_user_exc(builder, RuntimeError, (msg,))
        fnty = context.call_conv.get_function_type(ret, declared)
        fn = builder.inttoptr(addr, fnty.as_pointer())
        vals = [builder.extract_value(llargs[-1], i) for i in range(len(declared))]
        status, res = context.call_conv.call_function(builder, fn, ret, declared, vals)
        with cgutils.if_unlikely(builder, status.is_error):
            context.call_conv.return_status_propagate(builder, status)
        return res

    return codegen


@intrinsic
def _at(typingctx, addr, check, name, args):
    if not isinstance(name, types.StringLiteral) or not isinstance(args, types.BaseTuple):
        return None
    if not (isinstance(addr, types.Integer) and isinstance(check, types.Integer)):
        return None
    key, ret, declared = _checked(name, args)
    sig = ret(types.int64, types.int64, name, types.Tuple(declared))
    return sig, _codegen_call(key, ret, declared, lambda c, b, llargs: (llargs[0], llargs[1]))


@overload(call, prefer_literal=True, inline="always")
def _call_impl(K, name, args, general):
    if not isinstance(name, types.StringLiteral) or name.literal_value not in SLOTS:
        return None
    index, kernel = SLOTS[name.literal_value]
    if isinstance(K, types.NoneType):
        gen = getattr(general, "dispatcher", None)
        kernel = _for_general(name.literal_value, kernel, gen)
        return lambda K, name, args, general: kernel(*args)
    if not (isinstance(K, types.Array) and K.ndim == 2 and K.dtype == types.int64):
        raise errors.TypingError(f"call of {name.literal_value!r}: K must be a 2-row int64 array")
    if not PLAIN:
        return None  # typed and lowered at the call site (_type_call, _lower_call)
    return lambda K, name, args, general: _at(K[0, index], K[1, index], name, args)


def _type_call(context):
    def typer(K, name, args, general):
        if not isinstance(K, types.Array) or not isinstance(name, types.StringLiteral):
            return None
        if name.literal_value not in SLOTS or not isinstance(args, types.BaseTuple):
            return None
        if not (K.ndim == 2 and K.dtype == types.int64):
            raise errors.TypingError(
                f"call of {name.literal_value!r}: K must be a 2-row int64 array"
            )
        ret, declared = _checked(name, args)[1:]
        return ret(K, name, types.Tuple(declared), general)

    return typer


def _k_entry(context, builder, kty, kval, column):
    """(K[0, column], K[1, column]) of the int64 array ``K``."""
    from numba.np.arrayobj import make_array  # compiling only: its import is ~50 ms

    arr = make_array(kty)(context, builder, value=kval)
    shape = cgutils.unpack_tuple(builder, arr.shape)
    strides = cgutils.unpack_tuple(builder, arr.strides)
    col = context.get_constant(types.intp, column)
    out = []
    for row in (0, 1):
        inds = [context.get_constant(types.intp, row), col]
        ptr = cgutils.get_item_pointer2(
            context, builder, arr.data, shape, strides, kty.layout, inds, wraparound=False
        )
        out.append(builder.load(ptr))
    return out


if not PLAIN:
    # with K an array, typed and lowered at the call site (numba's low-level extension API):
    # no function of its own to compile for each callee, as the overload's implementation
    type_callable(call)(_type_call)

    @lower_builtin(call, types.Array, types.StringLiteral, types.BaseTuple, types.Any)
    def _lower_call(context, builder, sig, llargs):
        key = sig.args[1].literal_value
        ret, declared = DECLARED[key]
        column = SLOTS[key][0]
        kty = sig.args[0]

        def fetch(c, b, llargs):
            return _k_entry(c, b, kty, llargs[0], column)

        codegen = _codegen_call(key, ret, declared, fetch)
        return codegen(context, builder, sig, (llargs[0], llargs[2]))


# ---- the process-wide table: calls by address without ``K`` ----------------------------------

TABLE_SYMBOL = "nsdyn_kaddress_table"  # the name compiled code reads the table by
TABLE_ROWS = 64  # rows of the table (a caller's row index is compiled into its code)
# the names the table has rows for, in the order of their rows (append only: an index changes
# only with this file, whose change drops the cached callers, see nsdyn._numba_cache)
TABLE_NAMES = (
    "sys.evaluate",
    "sys.jac",
    "event.settle",
    "event.settle_contacts",
    "event.start",
    "event.step",
    "event.detect_friction",
    "event.detect_contacts",
    "event.accept",
    "event.handle",
    "event.land",
    "deck.evaluate",
    "deck.settle",
    "cyl.rhs",
    "contact.rhs",
    "deck.switch",
    "radau.feval",
    "sys.jac_at",
    "pairs.evaluate",
    "pairs.settle",
    "pairs.settle_contacts",
    "rock.ground",
    "cyl.stop_slip",
    "pairs.initial_modes",
    "pairs.outputs",
    "event.general",
    "sys.assemble",
    "sys.solve_small",
    "sys.pinv",
    "pairs.factor_real",
    "pairs.factor_complex",
    "pairs.solve_real",
    "pairs.solve_complex",
    "pairs.proportional_split",
    "pairs.least_norm",
    "pairs.stick_basis",
    "pairs.begin",
    "pairs.emit",
    "pairs.track_stops",
    "pairs.rhs",
    "pairs.jacobian",
    "pairs.dense",
    "pairs.switch",
    "pairs.locate_event",
    "pairs.locate_uplift",
    "pairs.land",
    "pairs.start_direction",
)
assert len(TABLE_NAMES) <= TABLE_ROWS
# row i: the address of the kernel declared as TABLE_NAMES[i], the digest of its declaration
TABLE = np.zeros((TABLE_ROWS, 2), dtype=np.int64)
llvm.add_symbol(TABLE_SYMBOL, TABLE.ctypes.data)  # TABLE lives as long as the process
TSLOTS: dict = {}  # name -> the kernel called directly (plain numba, no JIT)
# name -> "module:function" that declares it: a caller typed before the declaration was made
# would otherwise fail, and numba keeps a failed typing (the caller would fail for good)
DECLARE_HOOKS: dict = {}


def index(name: str) -> int:
    """The row of ``name`` in :data:`TABLE`."""
    return TABLE_NAMES.index(name)


def tslot(name: str, kernel, declare: str | None = None) -> None:
    """Register ``kernel`` as the callee ``name`` of :func:`tcall` (called directly with plain
    numba and without the JIT); ``declare``: "module:function" that makes its declaration,
    called when a caller is typed before it was made."""
    index(name)  # a ValueError for a name without a row
    TSLOTS[name] = kernel
    if declare is not None:
        DECLARE_HOOKS[name] = declare


def fill(name: str, address: int) -> None:
    """Put the address of the compiled kernel declared as ``name`` in its row of the table."""
    i = index(name)
    TABLE[i, 0] = address
    TABLE[i, 1] = digest(name)


def filled(name: str) -> bool:
    """True when the row of ``name`` holds an address for its current declaration."""
    i = index(name)
    return bool(TABLE[i, 0]) and name in DECLARED and TABLE[i, 1] == digest(name)


def tcall(name, args):
    """Callee ``name`` on ``args``: through its address in :data:`TABLE`, or directly."""
    return TSLOTS[name](*args)


def _table_entry(context, builder, row):
    """(address, digest) of ``row`` of the table, read through its symbol."""
    mod = builder.module
    rowty = ir.ArrayType(ir.IntType(64), 2)
    try:
        gv = mod.get_global(TABLE_SYMBOL)
    except KeyError:
        gv = ir.GlobalVariable(mod, ir.ArrayType(rowty, TABLE_ROWS), TABLE_SYMBOL)
        gv.linkage = "external"
    i32 = ir.IntType(32)
    zero, r = ir.Constant(i32, 0), ir.Constant(i32, row)
    addr = builder.load(builder.gep(gv, [zero, r, ir.Constant(i32, 0)]))
    check = builder.load(builder.gep(gv, [zero, r, ir.Constant(i32, 1)]))
    return addr, check


def _type_tcall(context):
    def typer(name, args):
        if not isinstance(name, types.StringLiteral) or not isinstance(args, types.BaseTuple):
            return None
        ret, declared = _checked(name, args)[1:]
        return ret(name, types.Tuple(declared))

    return typer


if PLAIN:

    @overload(tcall, prefer_literal=True, inline="always")
    def _tcall_plain(name, args):
        if not isinstance(name, types.StringLiteral) or name.literal_value not in TSLOTS:
            return None
        kernel = TSLOTS[name.literal_value]
        return lambda name, args: kernel(*args)

else:
    # typed and lowered at the call site (numba's low-level extension API): no function of
    # its own to compile for each callee, as an overload's implementation would be
    type_callable(tcall)(_type_tcall)

    @lower_builtin(tcall, types.StringLiteral, types.BaseTuple)
    def _lower_tcall(context, builder, sig, llargs):
        key = sig.args[0].literal_value
        ret, declared = DECLARED[key]
        row = index(key)
        fetch = lambda c, b, llargs: _table_entry(c, b, row)  # noqa: E731
        return _codegen_call(key, ret, declared, fetch)(context, builder, sig, llargs)


# ---- the callees: declared, compiled, their addresses in the table ---------------------------


class Callee:
    """A compiled kernel that a run loop calls by address, declared under ``name`` for the
    argument types ``args`` and return type ``ret`` (:func:`declare`)."""

    def __init__(self, name: str, kernel, args, ret):
        self.name, self.kernel, self.args, self.ret = name, kernel, tuple(args), ret
        declare(name, ret, self.args)
        self._address = 0

    def compiled(self):
        """The kernel's compilation for ``args`` (loaded from the cache, or compiled)."""
        self.kernel.compile(self.args)
        cres = self.kernel.overloads[self.args]
        if cres.signature.return_type != self.ret:
            raise TypeError(
                f"{self.name}: {self.kernel.py_func.__qualname__} returns "
                f"{cres.signature.return_type}, declared {self.ret}"
            )
        return cres

    def address(self) -> int:
        """The address of the compiled kernel's code (numba's calling convention)."""
        if not self._address:
            cres = self.compiled()
            self._address = cres.library.get_pointer_to_function(cres.fndesc.llvm_func_name)
        return self._address


def fill_table(callees) -> None:
    """Put the addresses of ``callees`` (:class:`Callee`, each loaded from numba's cache, or
    compiled) in :data:`TABLE`; nothing under ``NUMBA_DISABLE_JIT`` or with plain numba
    (:data:`nsdyn._numba_cache.PLAIN`: the callers call them directly)."""
    from numba import config

    if config.DISABLE_JIT or PLAIN:
        return
    for c in callees:
        if not filled(c.name):
            fill(c.name, c.address())


def compile_beside(loop, argtypes: tuple, callees, helper: str, here=()) -> None:
    """Compile ``loop`` (a numba dispatcher that calls ``callees`` by address) for the numba
    types ``argtypes`` unless it and its callees are in numba's cache: where a helper process
    may run (:func:`nsdyn._numba_cache.helper_enabled`), ``helper`` ("module:function")
    compiles the callees meanwhile but those of ``here``, which this process compiles after
    the loop, and this process then loads the helper's from the cache (what the helper does
    not deliver this process compiles itself when it takes the addresses)."""
    from nsdyn._numba_cache import Helper, all_cached, helper_enabled

    kernels = [c.kernel for c in callees]
    if helper_enabled() and not all_cached([loop, *kernels]):
        with Helper(helper) as h:
            loop.compile(argtypes)
            for c in here:
                c.compiled()
            h.wait_for([c.kernel for c in callees if c not in here])


def run_split(loop, args: tuple, callees, helper: str, here=()):
    """``loop(*args)`` with the addresses of its ``callees`` (:class:`Callee`) in the table; a
    first compilation (for ``args``' types) shared with a helper (:func:`compile_beside`;
    ``here``: the callees this process compiles)."""
    from numba import typeof

    from nsdyn._numba_cache import all_cached

    if not all_cached([loop]):
        compile_beside(loop, tuple(typeof(a) for a in args), callees, helper, here)
    fill_table(callees)
    return loop(*args)


# ---- kernels without a Python entry point ----------------------------------------------------


def _no_entry_class(base):
    class NoEntry(base):
        """A kernel compiled without numba's Python entry point (:data:`NO_ENTRY`)."""

        def __call__(self, *args, **kws):
            name = self.py_func.__qualname__
            raise TypeError(
                f"{self.py_func.__module__}.{name} is compiled without a Python entry point: "
                "compiled code calls it (by its address or linked), Python calls its caller"
            )

    return NoEntry


_NO_ENTRY_CLASSES: dict = {}


def no_entry(kernel):
    """Mark ``kernel``, an ``njit(..., **NO_ENTRY)`` dispatcher, as called from compiled
    code only: a call from Python raises a TypeError instead of crashing. Unchanged with plain
    numba and without the JIT (a plain function)."""
    if not NO_ENTRY or not hasattr(kernel, "targetoptions"):
        return kernel
    if any(kernel.targetoptions.get(k) is not v for k, v in NO_ENTRY.items()):
        raise ValueError(f"{kernel.py_func.__qualname__}: compile it with njit(..., **NO_ENTRY)")
    base = type(kernel)
    kernel.__class__ = _NO_ENTRY_CLASSES.setdefault(base, _no_entry_class(base))
    return kernel


def compiled_only(func):
    """The decorator of a kernel that only compiled code calls (by its address or linked):
    ``njit(cache=True, error_model="numpy", **NO_ENTRY)``, then :func:`no_entry`."""
    return no_entry(njit(cache=True, error_model="numpy", **NO_ENTRY)(func))


def compiled_uncounted(func):
    """:func:`compiled_only` without numba's reference counts (:data:`NO_NRT`), for a kernel
    that allocates no array and returns none (plain numba counts them)."""
    return no_entry(njit(cache=True, error_model="numpy", **NO_ENTRY, **NO_NRT)(func))


def specialised(func, name: str, **bindings):
    """A copy of the Python function ``func`` named ``name`` in which the global names given
    in ``bindings`` refer to the objects given: one source, compiled as separate kernels that
    each call their own callees (Newton with the general kernel of the table, with the flat
    right-hand side by address, ...).

    It replaces a kernel whose body was only an ``inline="always"`` call of ``func`` with
    those callees as arguments: numba inlines a function by copying its IR once per block
    together with the function's whole variable scope (blocks x variables): 1.4-1.7 s of
    one core for Newton (numba's ``inline_inlinables`` pass, docs/dev/first-runs.md), to make
    the code the copy compiles from directly.
    The copy sees ``func``'s module globals as they are when it is made (make it after
    everything its body uses is defined), and numba caches it apart from ``func`` and from
    the other copies by its name (the cache files are named by the module's file and the
    kernel's qualified name): ``name`` must be unique among the kernels of ``func``'s file.
    """
    import types as pytypes

    func = getattr(func, "py_func", func)
    unknown = sorted(set(bindings) - set(func.__code__.co_names))
    if unknown:
        raise ValueError(f"{func.__qualname__} uses no global named {', '.join(unknown)}")
    env = dict(func.__globals__)
    env.update(bindings)
    code = func.__code__.replace(co_name=name, co_qualname=name)
    out = pytypes.FunctionType(code, env, name, func.__defaults__, func.__closure__)
    out.__qualname__ = name
    out.__module__ = func.__module__
    out.__doc__ = func.__doc__
    return out
