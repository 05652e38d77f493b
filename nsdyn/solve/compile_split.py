"""The default Radau loop's callees by address, and a first compilation shared by two processes.

The default run's loop (:func:`nsdyn.solve._kradau.radau_flat`) calls the flat right-hand
side, its Jacobian, the factorisation, Newton and the start-up by address
(:mod:`nsdyn._kaddress`): :class:`Callee` declares each for the argument types the loop gives
it (:func:`radau_callees`) and finds its compiled code's address; :func:`radau_calls` is the
loop's ``K``. numba would otherwise link a copy of every callee into the loop's code and
optimise it there once more (~5 s of the loop's ~9-13 s first compilation), and could compile
the loop only after all of them. The run's arrays come from numpy in the calling process
(:func:`nsdyn.solve._kradau.setup_here`: no compiled set-up), and the metrics call the flat
right-hand side by address too (:func:`flat_calls`).

numba compiles on one thread per process, under a global lock, so a first run's compilation
uses one core. :func:`nsdyn.solve.methods.warmup_kernel` starts a helper process
(:class:`nsdyn._numba_cache.Helper`) on :func:`radau_helper_part` (the flat right-hand
side, Newton, the Jacobian, the factorisation) while the calling process compiles
:func:`radau_parts_here` (the loop itself, the start-up and the metrics), then loads the
helper's kernels from numba's on-disk cache. Neither waits for the other.

The event-driven loop (:func:`nsdyn.solve._kunilateral._run`: the switch model, unilateral
contacts) has a deep call tree, each of whose kernels evaluates the ~250-block system kernel:
linked, its code was optimised and translated again in every one of them (the loop compiled in
~90 s on one core). Its callees are called by their addresses in the process-wide table of
:mod:`nsdyn._kaddress` (:func:`nsdyn._kaddress.tcall`; :func:`event_callees` declares them,
:func:`event_ready` fills the rows a run calls), the system kernel and its Jacobian among them,
and its step's by ``K`` (:func:`event_calls`). Each compiles once, on its own, so the first
compilation splits into independent pieces: the helper takes the system kernel, its Jacobian,
the friction detector, the factorisation and the step's acceptance (:func:`event_helper_part`);
this process Newton (without the flat right-hand side for a law it does not serve), the stage
evaluation (:func:`nsdyn.solve._kcolloc.general_table`, which Newton, the step and the start-up
call by address, row ``"event.general"``), the step, the start-up, the event handler, the
settling, the loop and the general metrics, which call the system kernel by address
(:func:`event_parts_here`).

Generalized-alpha calls the system kernel and its Jacobian through the table too: the helper
compiles the Jacobian (its own kernel, then the one by address that links it) and the system
kernel (:func:`system_helper_part`), this process the loop and the metrics
(:func:`genalpha_parts_here`). The general metrics of every loop but the flat Radau one
call the system kernel by address (:func:`nsdyn.solve._kcommon.evaluate_many_t`); a process
that may not have it yet compiles them without running them (:func:`metrics_here`).

genalpha-lowrank (:mod:`nsdyn.solve.sparse`) calls the system kernel only once, from Python,
for the start's accelerations: the helper compiles it (and the metrics) while this process
compiles the dense loop from the argument types the run gives it
(:func:`nsdyn.solve.sparse.loop_args`, :func:`lowrank_parts_here`).

Each piece is compiled for the signature the loop asks for, by ``Dispatcher.compile`` with the
numba types of arguments built as the loop builds them, on the tiny problem.
``tests/solve/test_compile_helper.py`` checks that the calling process compiles none of the
helper's kernels.
"""

from __future__ import annotations

import functools

import numpy as np

from nsdyn import _klinalg as kl
from nsdyn._kaddress import Callee, digest, fill_table  # noqa: F401 (callers use them)
from nsdyn._lazy import LazyModule
from nsdyn._numba_cache import Helper
from nsdyn.models.isolated import _kernel as ks
from nsdyn.solve import _kcolloc, _kflat, _kradau, methods
from nsdyn.solve import _kcommon as ki

# the other methods' kernel modules: imported when their kernels are compiled or loaded
_kevent = LazyModule("nsdyn.solve._kevent")
_kgenalpha = LazyModule("nsdyn.solve._kgenalpha")
_kimpact = LazyModule("nsdyn.solve._kimpact")
_klowrank = LazyModule("nsdyn.solve._klowrank")
_kunilateral = LazyModule("nsdyn.solve._kunilateral")


def _py(kernel):
    """The Python function of a kernel (itself under ``NUMBA_DISABLE_JIT``)."""
    return getattr(kernel, "py_func", kernel)


def _tiny_args(method: str, law: str | None = None):
    """The arguments of a loop's pieces on the tiny problem, with the numba types the loop
    gives them (so that what is compiled here is what the loop calls), made without compiling
    anything: :func:`nsdyn.solve.methods.tiny_run` of ``method`` (its system with friction
    law ``law``) and the workspace ``ws`` as :func:`nsdyn.solve._kradau.setup` makes it."""
    P, x0, t_eval, o, X, upl_t = methods.tiny_run(methods.METHODS[method])
    if law is not None:
        P = methods.with_law(P, law, np.zeros(P[ks.I_D].shape[0], dtype=np.int64))
    ws = _py(_kradau.workspace)(x0.size, upl_t.size, P[ks.I_D].shape[0])
    return P, x0, t_eval, o, X, upl_t, ws + (_kflat.pack_flat(P),)


@functools.cache
def radau_callees() -> list:
    """The flat Radau loop's callees (see :func:`nsdyn.solve._kradau.radau_flat`), in the
    order of ``K``, declared for the argument types of the loop's calls on every run (its
    arrays are made by the same code whatever the model: the tiny problem's types; once per
    process)."""
    from numba import typeof, types

    P, x0, t_eval, o, X, upl_t, ws = _tiny_args("radau")
    (J, LUr, pr, LUc, pc, Z, Z0, W, F, dW, fr, fc, ys, iscale, err, ynew, fnew, Qd,
     qdd, lam, tau, modes, Fl) = (typeof(a) for a in ws)  # fmt: skip
    tP, tte, tX, tupl_t, tatol = (typeof(a) for a in (P, t_eval, X, upl_t, o.atol))
    f8, i8, b1 = types.float64, types.int64, types.boolean
    v, vi = types.float64[::1], types.int64[::1]
    tws = typeof(ws)
    newton_args = (tP, f8, v, f8, v, vi, J, LUr, pr, LUc, pc, Z, W, F, dW, fr, fc, ys, iscale,
                   qdd, lam, tau, modes, Fl, b1)  # fmt: skip
    tK = types.int64[:, ::1]  # K itself (the start-up calls the flat kernels through it)
    start_args = (tP, v, v, tte, f8, f8, tatol, f8, v, tX, tupl_t, i8, tws, vi, v, v, tK)
    sigs = {  # name: (argument types, return type), in the order of K (_kcolloc.K_FEVAL, ...)
        "radau.feval": ((f8, v, Fl, v, qdd, lam, tau, modes), b1),
        "radau.jac": ((v, Fl, J, lam), b1),
        "radau.factor": ((f8, J, LUr, pr, LUc, pc), b1),
        "radau.newton": (newton_args, types.Tuple((b1, i8, f8, b1, b1, f8))),
        "radau.start": (start_args, i8),
    }
    return [
        Callee(name, kernel, *sig)
        for (name, sig), kernel in zip(sigs.items(), _kradau.FLAT_CALLEES, strict=True)
    ]


def calls(callees) -> np.ndarray | tuple:
    """``K`` for a loop that calls ``callees`` (:class:`Callee`, in the order of their slots)
    by address: their addresses (each loaded from the cache, or compiled) over the digests of
    their declarations (see :mod:`nsdyn._kaddress`); under ``NUMBA_DISABLE_JIT`` a tuple of
    the kernels; with plain numba (:data:`nsdyn._numba_cache.PLAIN`) None: the loops call
    their callees directly, as numba links them. The callers keep it once per process: the
    addresses and declarations do not change in it."""
    from numba import config

    from nsdyn import _kaddress
    from nsdyn._numba_cache import PLAIN

    if config.DISABLE_JIT:
        return tuple(c.kernel for c in callees)
    if PLAIN:
        return None
    return np.array(
        [[c.address() for c in callees], [_kaddress.digest(c.name) for c in callees]],
        dtype=np.int64,
    )


@functools.cache
def radau_calls():
    """``K`` of the flat Radau loop: :func:`calls` of :func:`radau_callees` (the loop reads
    it, never writes it); the flat right-hand side's address also in the table's row
    ``"radau.feval"`` (:mod:`nsdyn._kaddress`), for :func:`nsdyn.solve._kcolloc.newton_flat`."""
    K = radau_callees()
    fill_table([K[_kcolloc.K_FEVAL]])
    return calls(K)


@functools.cache
def flat_callee() -> Callee:
    """:func:`nsdyn.solve._kflat.feval_flat` declared as ``"flat.feval"`` for the types of the
    loop's ``"radau.feval"``: the call of the metrics' kernel (``evaluate_flat_many``) is
    typed against it (nothing compiled; once per process)."""
    feval = radau_callees()[_kcolloc.K_FEVAL]
    return Callee("flat.feval", feval.kernel, feval.args, feval.ret)


@functools.cache
def flat_calls():
    """``K`` of :func:`nsdyn.solve._kflat.evaluate_flat_many` (the metrics of a flat run): the
    address of :func:`flat_callee` (:func:`calls`). Compiles (or loads) only the flat
    right-hand side."""
    return calls([flat_callee()])


def _declared_form(a):
    """``a`` as the loop's declarations have its arrays: C-contiguous and writable (a copy
    only when it is not)."""
    return a if a.flags.c_contiguous and a.flags.writeable else np.array(a, order="C")


def radau_flat(P, x0, t_eval, atol, rtol, h0, max_step, max_steps, fixed, uplift_mode, X, upl_t):
    """The default run's loop (:func:`nsdyn.solve._kradau.radau_flat`: the flat kernel only,
    its callees called by address); the arguments and returns of
    :func:`nsdyn.solve._kradau.radau` without ``flat``. Read-only or non-contiguous inputs
    are copied (a read-only array has another numba type than the declared one)."""
    if not all(a.flags.c_contiguous and a.flags.writeable for a in (x0, t_eval, atol, *P)):
        P = tuple(_declared_form(a) for a in P)
        x0, t_eval, atol = (_declared_form(a) for a in (x0, t_eval, atol))
    owned = _kradau.setup_here(P, x0, t_eval, upl_t.shape[0])
    _kradau.radau_flat(
        P, x0, t_eval, atol, rtol, h0, max_step, max_steps, fixed, uplift_mode, X, upl_t, True,
        radau_calls(), owned,
    )  # fmt: skip
    return owned[0], owned[1]


# the flat Radau loop's callees a helper compiles (radau_helper_part), in this order, the rest
# (the start-up) this process, with the loop and the metrics: shares of about equal CPU now
# that the helper starts with this process (nsdyn._numba_cache.start_standby). The Jacobian and
# the factorisation link the real LU factorisation: one process compiles both
RADAU_HELPER = (_kcolloc.K_JAC, _kcolloc.K_FEVAL, _kcolloc.K_NEWTON, _kcolloc.K_FACTOR)


def radau_helper_part() -> None:
    """The helper process's share of the flat Radau loop's first compilation (see
    :func:`nsdyn.solve.methods.warmup_kernel`): the Jacobian, the flat right-hand side,
    Newton (which calls it by address) and the factorisation, each for the types the loop
    calls it with."""
    K = radau_callees()
    for k in RADAU_HELPER:
        K[k].compiled()


def _compile_radau_loop() -> None:
    """The flat Radau loop alone, for the types of every run (it calls its callees by
    address, so it needs none of them compiled)."""
    P, x0, t_eval, o, X, upl_t, ws = _tiny_args("radau")
    K0 = np.zeros((2, len(radau_callees())), dtype=np.int64)  # only its type matters here
    owned = _kradau._owned(ws, x0, t_eval, upl_t.shape[0])  # as setup_here makes them
    args = (P, x0, t_eval, o.atol, o.rtol, o.h0, o.max_step, o.max_steps, False, o.uplift_mode,
            X, upl_t, True, K0, owned)  # fmt: skip
    _compile(_kradau.radau_flat, *args)


def radau_parts_here(helper: Helper, metrics: str | None) -> None:
    """This process's share: the loop itself, the callee :data:`RADAU_HELPER` leaves (the
    start-up) and the ``metrics``; then wait for the helper's part."""
    _compile_radau_loop()
    _radau_rest()
    metrics_here(metrics)
    helper.wait_for([radau_callees()[k].kernel for k in RADAU_HELPER])


def _radau_rest() -> None:
    """The flat Radau loop's callees that :data:`RADAU_HELPER` leaves to this process."""
    for k, callee in enumerate(radau_callees()):
        if k not in RADAU_HELPER:
            callee.compiled()


# ---- the event-driven loop (switch model; unilateral contacts) ------------------------------


def _compile(disp, *args) -> None:
    """Compile (or load) ``disp`` for the numba types of ``args`` without running it."""
    from numba import typeof

    if hasattr(disp, "compile"):  # not under NUMBA_DISABLE_JIT
        disp.compile(tuple(typeof(a) for a in args))


def _event_args():
    """The event loop's local variables on the tiny problem (their numba types)."""
    return _kunilateral.typing_locals(*_tiny_args("event", "modes"))


@functools.cache
def system_callees() -> list:
    """The system kernel, the three it calls by address, its Jacobian by address and the
    Jacobian's own kernel (:data:`SYSTEM`), declared for the parameter tuple's type on every
    run (the tiny problem's): the first of :func:`event_callees`. Once per process."""
    from numba import typeof, types

    P, f8 = typeof(_tiny_args("event", "modes")[0]), types.float64
    v, vi, m = types.float64[::1], types.int64[::1], types.float64[:, ::1]
    return [  # name, kernel, argument types, return type
        Callee("sys.evaluate", ki.sys_evaluate, (f8, v, P, v, v, v, vi), types.boolean),
        Callee("sys.assemble", ks._assemble, (f8, v, P, v, v, v, m, m, v), types.int64),
        Callee("sys.solve_small", kl.solve_small, (m, v, types.int64), types.boolean),
        Callee("sys.pinv", kl.pinv_into, (m, types.int64, m, m, m, v), types.none),
        Callee("sys.jac", ki.jac_table, (f8, v, P, m), types.none),
        Callee("sys.jac_at", ki.sys_jac_at, (f8, v, P, m, v, vi), types.none),
    ]


@functools.cache
def event_callees() -> list:
    """The event loop's callees by address (:func:`nsdyn._kaddress.tcall`), declared for the
    argument types the loop (and its callees) give them; the system kernel and its Jacobian
    first (:func:`system_callees`). Once per process (after the step's callees by ``K``, whose
    declarations the step and the start-up are typed with)."""
    from numba import typeof, types

    event_newton()
    a = _event_args()
    P, ws, ew, logs, lift = (typeof(a[k]) for k in ("P", "ws", "ew", "logs", "lift"))
    te, X, upl_t = (typeof(a[k]) for k in ("t_eval", "X", "upl_t"))
    atol = typeof(a["o"].atol)
    f8, i8, b1 = types.float64, types.int64, types.boolean
    v, vi, m = types.float64[::1], types.int64[::1], types.float64[:, ::1]
    tK = types.int64[:, ::1]  # the step's K (event_calls)
    opts = types.Tuple((b1, b1, f8, f8, f8, f8))
    run = types.Tuple((v, P, v, ws, ew, v, v, vi, opts, logs, lift))
    detected = types.Tuple((f8, i8, i8))
    sigs = {  # name: (kernel, argument types, return type)
        "event.settle": (_kevent._settle, (f8, v, P, v, ew, i8, f8, logs.types[0], vi), b1),
        "event.settle_contacts": (
            _kimpact._settle_contacts,
            (f8, v, P, v, ew, f8, m, vi, vi, lift),
            types.Tuple((b1, b1)),
        ),
        "event.start": (
            _kunilateral._start,
            (P, v, v, te, f8, f8, atol, f8, v, X, upl_t, i8, ws, vi, v, v, tK),
            i8,
        ),
        "event.step": (
            _kunilateral._step,
            (P, f8, v, v, f8, b1, atol, f8, f8, i8, ws, v, vi, v, tK),
            i8,
        ),
        "event.detect_friction": (_kevent._detect, (f8, f8, v, v, m, P, ew, vi, f8), detected),
        "event.detect_contacts": (
            _kimpact._detect,
            (f8, f8, v, m, P, ew, f8, v, f8, vi),
            detected,
        ),
        "event.accept": (
            _kradau.accept,
            (f8, v, v, v, ws, te, i8, X, v, upl_t, i8, vi, v),
            types.Tuple((i8, b1)),
        ),
        "event.handle": (_kunilateral._event_at, (f8, i8, i8, f8, run), b1),
        "event.land": (_kimpact._land, (f8, v, P, i8, f8, f8, m, vi, v), b1),
        "event.general": (
            _kcolloc.general_table,
            (f8, P, f8, v, f8, m, m, v, v, m, v, v, v, vi),
            b1,
        ),
    }
    others = [Callee(name, kernel, args, ret) for name, (kernel, args, ret) in sigs.items()]
    return [*system_callees(), *others]


@functools.cache
def _event_by_name() -> dict:
    """{name: Callee} of :func:`event_callees` (once per process; copy before changing it)."""
    return {c.name: c for c in event_callees()}


# the system kernel and what it calls by address, its Jacobian (by address, its own kernel)
EVALUATE, SYSTEM = ki.EVALUATE_ROWS, ki.SYSTEM_ROWS


@functools.cache
def evaluate_table() -> None:
    """The system kernel and its callees (:data:`EVALUATE`) in the address table, for the
    general metrics (:func:`nsdyn.solve._kcommon.evaluate_many_t`). Once per process."""
    fill_table(system_callees()[: len(EVALUATE)])


def evaluate_inputs(P, X):
    """``P`` and the history ``X`` of :func:`nsdyn.solve._kcommon.evaluate_many_t`, with the
    system kernel in the table (:func:`evaluate_table`) and the arrays in its declared form
    (C-contiguous float64, writable: a copy of one that is not)."""
    evaluate_table()
    if not all(a.flags.c_contiguous and a.flags.writeable for a in P):
        P = tuple(_declared_form(a) for a in P)
    X = np.ascontiguousarray(X, dtype=float)
    return P, (X if X.flags.writeable else X.copy())


def metrics_here(metrics: str | None) -> None:
    """Compile the ``metrics`` kernels of a run (:func:`nsdyn.solve.methods.metrics_for`)
    without running them: the flat ones call the flat right-hand side by address, the
    general ones the system kernel, which the helper may still be compiling (a run here
    would compile it a second time). None: none."""
    if metrics is None:
        return
    from nsdyn.models.isolated.metrics import evaluation_arrays

    P, x0 = methods._tiny_problem()
    t, X = np.zeros(1), x0[None, :].copy()
    out = evaluation_arrays(P, 1)
    if metrics == "metrics":  # as nsdyn.solve.transient.flat_evaluations calls it
        flat_callee()  # its call of the flat right-hand side is typed against this
        K0 = np.zeros((2, 1), dtype=np.int64)  # only its type matters here
        A0, ok = np.zeros((1, x0.size // 2)), np.ones(1, dtype=np.bool_)
        _compile(_kflat.evaluate_flat_many, t, X, _kflat.pack_flat(P), A0, *out, ok, K0)
    else:
        _compile(ki.evaluate_many_t, t, X, P, *out)


@functools.cache
def system_table() -> None:
    """The system kernel and its Jacobian in the address table (:func:`fill_table`), for the
    kernels that call them so outside the event loop (generalized-alpha). Once per process."""
    fill_table(system_callees())


def system_inputs(P, x0):
    """``P`` and ``x0`` of a kernel that calls the system kernel by address (generalized-alpha),
    with the table filled (:func:`system_table`): its arrays in their declared form (a copy
    of a read-only or non-contiguous one: another numba type than the declared one)."""
    system_table()
    if not all(a.flags.c_contiguous and a.flags.writeable for a in (x0, *P)):
        P, x0 = tuple(_declared_form(a) for a in P), _declared_form(x0)
    return P, x0


def event_ready(friction: bool, contacts: bool, flat: bool):
    """The address table filled for an event-loop run with friction and/or contact events
    (:func:`nsdyn.solve._kunilateral.callees`, :func:`fill_table`); its step's ``K``
    (:func:`event_calls`)."""
    fill_table([_event_by_name()[n] for n in _kunilateral.callees(friction, contacts)])
    return event_calls(flat)


@functools.cache
def event_newton(flat: bool = False) -> Callee:
    """Newton of the event loop's step, declared as the default loop's ``"radau.newton"``
    (the same argument types): :func:`nsdyn.solve._kcolloc.newton_table` for a law the flat
    kernels serve (``flat``), else :func:`nsdyn.solve._kcolloc.newton_general`, which does
    not compile the flat right-hand side (the switch model's runs)."""
    newton = radau_callees()[_kcolloc.K_NEWTON]
    kernel = _kcolloc.newton_table if flat else _kcolloc.newton_general
    return Callee(newton.name, kernel, newton.args, newton.ret)


def _event_K(flat: bool) -> list:
    """The callees of the event loop's ``K`` (None where a run does not call them)."""
    K: list = list(radau_callees())
    K[_kcolloc.K_NEWTON] = event_newton(flat)
    K[_kcolloc.K_START] = None  # the start-up's own slot: the event loop never calls it
    if not flat:  # a law the flat kernels do not serve (F[H_OK] = 0): never called
        K[_kcolloc.K_FEVAL] = K[_kcolloc.K_JAC] = None
    return K


@functools.cache
def event_calls(flat: bool):
    """``K`` of the event loop's step and start-up (:func:`calls`): the default loop's
    factorisation, :func:`event_newton` for Newton and, for a law they serve (``flat``), the
    flat kernels; the slots a run never calls empty (a call of one would raise). Once per
    process and ``flat``."""
    from numba import config

    from nsdyn._numba_cache import PLAIN

    if config.DISABLE_JIT or PLAIN:
        K = list(radau_callees())
        K[_kcolloc.K_NEWTON] = event_newton(True)  # (the kernels themselves: either law)
        return calls(K)
    out = np.zeros((2, len(radau_callees())), dtype=np.int64)
    for i, c in enumerate(_event_K(flat)):
        if c is not None:
            out[:, i] = c.address(), digest(c.name)
    return out


# the event loop's first compilation, shared by two processes: the callees each compiles (by
# their names in the address table or in ``K``), in an order that keeps both busy; every piece
# compiles on its own (nothing is linked into the loop), so neither process waits for the
# other's. This process also takes the loop itself and the general metrics (they call the
# system kernel by address: compiled, not run, before the helper has it).
EVENT_HELPER = (*SYSTEM, "event.detect_friction", "radau.factor", "event.accept")
EVENT_HERE = ("radau.newton", "event.general", "event.step", "event.start", "event.handle",
              "event.settle")  # fmt: skip


def _event_pieces() -> dict:
    """{name: Callee} of every piece :data:`EVENT_HELPER` and :data:`EVENT_HERE` name."""
    by_name = dict(_event_by_name())
    by_name["radau.factor"] = radau_callees()[_kcolloc.K_FACTOR]
    by_name["radau.newton"] = event_newton()
    return by_name


def _event_part(names) -> None:
    by_name = _event_pieces()
    for name in names:
        by_name[name].compiled()


def event_helper_part() -> None:
    """The helper process's share of the event loop's first compilation (see
    :func:`nsdyn.solve.methods.warmup_kernel`): the callees named in :data:`EVENT_HELPER`."""
    _event_part(EVENT_HELPER)


def compile_event_loop() -> None:
    """The event loop alone (:func:`nsdyn.solve._kunilateral._run`), for the types of every
    run: it calls its callees by address, so it needs none of them compiled."""
    a = _event_args()
    owned = _kradau._owned(a["ws"], a["x0"], a["t_eval"], a["upl_t"].shape[0])
    o = a["o"]
    _compile(
        _kunilateral._run, a["P"], a["x0"], a["t_eval"], (o.atol, float(o.rtol)),
        (float(o.h0), float(o.max_step), int(o.max_steps)), np.zeros(1, dtype=np.int64),
        (True, False, 0), 0.0, a["X"], a["upl_t"], np.zeros((0, 1), dtype=np.int64),
        a["logs"], owned,
        _kunilateral.loop_arrays(a["x0"].size, a["upl_t"].size, a["P"][ks.I_D].shape[0]),
        np.zeros((2, len(radau_callees())), dtype=np.int64),
    )  # fmt: skip


def event_parts_here(helper: Helper, metrics: str | None) -> None:
    """This process's share before the loop runs: the callees named in :data:`EVENT_HERE`,
    the loop itself (which needs none of its callees compiled) and the ``metrics`` (None when
    the helper takes them); then wait for the helper's callees."""
    _event_part(EVENT_HERE)
    compile_event_loop()
    metrics_here(metrics)
    by_name = _event_pieces()
    helper.wait_for([by_name[n].kernel for n in EVENT_HELPER])


# ---- generalized-alpha and genalpha-lowrank: the system kernel in the helper ------------------


def evaluate_helper_part() -> None:
    """A helper's share of genalpha-lowrank's first compilation: :data:`EVALUATE`."""
    _event_part(EVALUATE)


def evaluate_helper_part_and_metrics() -> None:
    """:func:`evaluate_helper_part`, then the general metrics (they call it by address)."""
    evaluate_helper_part()
    methods.warmup_metrics(False)


def system_helper_part() -> None:
    """A helper's share of generalized-alpha's first compilation: the Jacobian by address
    (``jac_table``), its own kernel (:func:`nsdyn.solve._kcommon.sys_jac_at`, which
    ``jac_table`` calls by address), then the system kernel and the three both call so."""
    _event_part(SYSTEM[len(EVALUATE) :] + EVALUATE)


def genalpha_parts_here(helper: Helper, metrics: str | None) -> None:
    """This process's share of generalized-alpha's first compilation: the loop itself (which
    needs neither the system kernel nor its Jacobian compiled) and the ``metrics`` (compiled,
    not run: :func:`metrics_here`); then wait for the helper's Jacobian and system kernel
    (:func:`system_helper_part`). The loop and the metrics here, ``jac_at``, ``jac_table`` and
    the system kernel there: about even shares of CPU."""
    event_callees()  # the declarations its calls by address are typed against
    m = methods.METHODS["genalpha"]
    P, x0, t_eval, o, X, upl_t = methods.tiny_run(m)
    coef = _kgenalpha.parameters(_kgenalpha.FAMILY_GENALPHA, methods.DEFAULT_RHO_INF["genalpha"])
    _compile(
        _kgenalpha.genalpha_loop, P, x0, t_eval, o.atol, o.rtol, o.dt, coef, o.max_steps,
        o.uplift_mode, X, upl_t, np.full(x0.size // 2, np.nan),
    )  # fmt: skip
    metrics_here(metrics)
    helper.wait_for([_event_by_name()[name].kernel for name in SYSTEM])


# ---- genalpha-lowrank: its dense loop here, the system kernel in the helper ---------------------


def lowrank_parts_here(helper: Helper, metrics: str | None) -> None:
    """This process's share of genalpha-lowrank's first compilation: its dense loop, from the
    arguments the run gives it (:func:`nsdyn.solve.sparse.loop_args`, which need no system
    kernel), and the ``metrics`` unless the helper takes them; then wait for the helper's
    system kernel and the metrics' kernel (the run's start evaluates through it)."""
    from nsdyn.solve import sparse

    P, x0, t_eval, o, X, upl_t = methods.tiny_run(methods.METHODS[sparse.METHOD])
    _compile(_klowrank.run_steps, *sparse.loop_args(P, x0, t_eval, o.dt, X, upl_t,
                                                     o.uplift_mode))  # fmt: skip
    metrics_here(metrics)
    helper.wait_for([*(_event_by_name()[name].kernel for name in EVALUATE), ki.evaluate_many_t])
