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
(:class:`nsdyn._numba_cache.Helper`) on :func:`radau_helper_part` (``pack_flat``, the flat
right-hand side, Newton, the Jacobian; :func:`radau_helper_part_and_metrics` then also the
metrics, which a run needs only after its loop) while the calling process compiles
:func:`radau_parts_here` (the loop itself, the factorisation, the start-up), then loads the
helper's kernels from numba's on-disk cache. Neither waits for the other.

The switch model's event-driven loop (:func:`nsdyn.solve._kunilateral._run`, ~4 min into an
empty cache on one core) is split the same way: the helper takes the general kernel's
Jacobian, the general stage kernel (:func:`~nsdyn.solve._kcolloc.general_inlined`), the
start-up and the step with Newton (:func:`event_helper_part`); this process the
factorisation, the set-up, the mode settling, the flat kernels, the metrics, the contact
settling, both event detectors and the event handler (:func:`event_parts_here`), then the
loop. The order is chosen so that neither process waits for the other: the helper's start-up
comes ~50 s in, after this process has the flat kernels, and the handler's Jacobian is the
helper's first piece. The general right-hand side ``evaluate`` is needed first in both (the
Jacobian's and the settling's), so each process may compile it (~17 s, on its own core).

Each piece is compiled for the signature the loop asks for, by ``Dispatcher.compile`` with the
numba types of arguments built as the loop builds them, on the tiny problem.
``tests/solve/test_compile_helper.py`` checks that the calling process compiles none of the
helper's kernels.
"""

from __future__ import annotations

import functools

import numpy as np

from nsdyn._numba_cache import Helper
from nsdyn.models.isolated import _kernel as ks
from nsdyn.solve import _kcolloc, _kevent, _kflat, _kimpact, _kradau, _kunilateral, methods
from nsdyn.solve import _kcommon as ki


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
    return P, x0, t_eval, o, X, upl_t, ws + (_py(_kflat.pack_flat)(P),)


class Callee:
    """A compiled kernel that a run loop calls by address (:mod:`nsdyn._kaddress`), declared
    under ``name`` for the argument types ``args`` and return type ``ret``."""

    def __init__(self, name: str, kernel, args, ret):
        from nsdyn import _kaddress

        self.name, self.kernel, self.args, self.ret = name, kernel, tuple(args), ret
        _kaddress.declare(name, ret, self.args)
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
    start_args = (tP, v, v, tte, f8, f8, tatol, f8, v, tX, tupl_t, i8, tws, vi, v, tK)
    sigs = {  # name: (argument types, return type), in the order of K (_kcolloc.K_FEVAL, ...)
        "radau.feval": ((f8, v, Fl, v, qdd, lam, tau, modes), b1),
        "radau.jac": ((v, Fl, J, lam), b1),
        "radau.factor": ((f8, J, LUr, pr, LUc, pc), b1),
        "radau.newton": (newton_args, types.Tuple((b1, i8, f8, b1, b1, f8))),
        "radau.start": (start_args, types.Tuple((i8, v))),
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
    it, never writes it)."""
    return calls(radau_callees())


@functools.cache
def flat_calls():
    """``K`` of :func:`nsdyn.solve._kflat.evaluate_flat_many` (the metrics of a flat run): the
    address of :func:`nsdyn.solve._kflat.feval_flat`, declared as ``"flat.feval"`` for the
    types of the loop's ``"radau.feval"`` (:func:`calls`). Compiles (or loads) only the flat
    right-hand side."""
    feval = radau_callees()[_kcolloc.K_FEVAL]
    return calls([Callee("flat.feval", feval.kernel, feval.args, feval.ret)])


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
    return _kradau.radau_flat(
        P, x0, t_eval, atol, rtol, h0, max_step, max_steps, fixed, uplift_mode, X, upl_t, True,
        _kcolloc.flat_only, radau_calls(), owned,
    )  # fmt: skip


def radau_helper_part() -> None:
    """The helper process's share of the flat Radau loop's first compilation (see
    :func:`nsdyn.solve.methods.warmup_kernel`): ``pack_flat`` (the run's set-up calls it from
    Python), the flat right-hand side, Newton (which links it) and the Jacobian, each for
    the types the loop calls it with."""
    _compile(_kflat.pack_flat, _tiny_args("radau")[0])  # the loop's set-up (setup_here) needs it
    K = radau_callees()
    for k in (_kcolloc.K_FEVAL, _kcolloc.K_NEWTON, _kcolloc.K_JAC):
        K[k].compiled()


def radau_helper_part_and_metrics() -> None:
    """:func:`radau_helper_part`, then the flat metrics kernels (``pack_flat``,
    ``evaluate_flat_many``, ``ground_many``), which a run needs only after its loop."""
    radau_helper_part()
    methods.warmup_metrics(True)


def radau_parts_here(helper: Helper, metrics: str | None) -> None:
    """This process's share: the loop itself (which calls its callees by address, so it
    needs none of them compiled), the factorisation, the start-up and the ``metrics`` (None
    when the helper takes them); then wait for the helper's part."""
    P, x0, t_eval, o, X, upl_t, ws = _tiny_args("radau")
    K = radau_callees()
    K0 = np.zeros((2, len(K)), dtype=np.int64)  # only its type matters here
    owned = _kradau._owned(ws, x0, t_eval, upl_t.shape[0])  # as setup_here makes them
    args = (P, x0, t_eval, o.atol, o.rtol, o.h0, o.max_step, o.max_steps, False, o.uplift_mode,
            X, upl_t, True, _kcolloc.flat_only, K0, owned)  # fmt: skip
    _compile(_kradau.radau_flat, *args)
    for k in (_kcolloc.K_FACTOR, _kcolloc.K_START):
        K[k].compiled()
    if metrics is not None:
        methods.warmup_metrics(metrics == "metrics")
    kernels = [K[k].kernel for k in (_kcolloc.K_FEVAL, _kcolloc.K_NEWTON, _kcolloc.K_JAC)]
    helper.wait_for([_kflat.pack_flat, *kernels])


# ---- the event-driven loop (switch model; unilateral contacts) ------------------------------


def _compile(disp, *args) -> None:
    """Compile (or load) ``disp`` for the numba types of ``args`` without running it."""
    from numba import typeof

    if hasattr(disp, "compile"):  # not under NUMBA_DISABLE_JIT
        disp.compile(tuple(typeof(a) for a in args))


def _event_args():
    """The event loop's local variables as :func:`nsdyn.solve._kunilateral._run` makes them, on
    the tiny problem (values are placeholders: only their numba types matter)."""
    P, x0, t_eval, o, X, upl_t, ws = _tiny_args("event", "modes")
    n2 = x0.size
    nc = upl_t.size
    a = dict(P=P, x0=x0, t_eval=t_eval, o=o, X=X, upl_t=upl_t, ws=ws, y=x0.copy())
    a["f"] = np.zeros(n2)
    a["stats"] = np.zeros(ki.N_STATS, dtype=np.int64)
    a["rinfo"] = np.zeros(ki.N_RINFO)
    a["lam_old"] = np.zeros(nc)
    a["ew"] = (ws[12], np.empty(n2), ws[18], ws[19], ws[20], ws[21])
    a["ctl"] = _py(_kradau.new_control)(1e-3, o.rtol)
    a["log"] = (np.zeros(1), np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.int64))
    a["logs"] = (a["log"], np.zeros((1, _kunilateral.CLOG_COLS)), np.zeros(1, dtype=np.int64),
                 np.zeros(1))  # fmt: skip
    a["lift"] = np.zeros((2, nc))
    a["i64"] = np.int64(0)
    return a


def _flat_kernels(ws, y, f) -> None:
    qdd, lam, tau, modes, Fl = ws[18:23]
    _compile(_kflat.feval_flat, 0.0, y, Fl, f, qdd, lam, tau, modes)
    _compile(_kflat.jac_flat_here, y, Fl, ws[0], lam)


def event_helper_part() -> None:
    """The helper process's share of the event loop's first compilation (see
    :func:`nsdyn.solve.methods.warmup_kernel`): the general Jacobian, the general stage
    kernel, the start-up, then the step (with Newton)."""
    a = _event_args()
    P, y, ws, o, f = a["P"], a["y"], a["ws"], a["o"], a["f"]
    qdd, lam, tau, modes, Fl = ws[18:23]
    J, Z, F, ys = ws[0], ws[5], ws[8], ws[12]
    g = _kcolloc.general_inlined
    _compile(ki.jeval, 0.0, y, P, J)
    _compile(g, _kcolloc.G_ONE, P, 0.0, y, 0.0, Z, F, ys, f, J, qdd, lam, tau, modes)
    _compile(
        _kradau.start, P, y, f, a["t_eval"], float(o.h0), float(o.max_step), o.atol,
        float(o.rtol), a["lam_old"],
        a["X"], a["upl_t"], np.int64(o.uplift_mode), ws, a["stats"], a["rinfo"], None, g,
    )  # fmt: skip
    _compile(
        _kradau.radau_step, P, 0.0, y, f, 0.0, False, o.atol, float(o.rtol), float(o.max_step),
        np.int64(o.max_steps), ws, a["ctl"], a["stats"], a["rinfo"], g,
    )  # fmt: skip


def event_parts_here(helper: Helper, metrics: str | None) -> None:
    """This process's share before the loop itself (the factorisation, the set-up, the
    settling of modes and contacts, the flat kernels, the ``metrics``, the detectors, the
    event handler); then wait for the helper's step."""
    a = _event_args()
    P, y, ws, o, f, ew, stats = a["P"], a["y"], a["ws"], a["o"], a["f"], a["ew"], a["stats"]
    i64, lift, logs, ctl = a["i64"], a["lift"], a["logs"], a["ctl"]
    Qd, ynew, fnew = ws[17], ws[15], ws[16]
    _compile(_kcolloc._factor, 1e-3, *ws[:5])  # the helper's step loads it
    _compile(_kradau.setup, P, a["x0"], a["t_eval"], i64)
    _compile(_kevent._initial_modes, P, y, P[ks.I_MODE])
    _compile(_kevent._settle, 0.0, y, P, f, ew, i64, 0.0, a["log"], stats)
    _flat_kernels(ws, y, f)  # the helper's start-up needs them after its general kernels
    if metrics is not None:
        methods.warmup_metrics(metrics == "metrics")
    _compile(_kimpact._settle_contacts, 0.0, y, P, f, ew, 0.0, logs[1], logs[2], stats, lift)
    _compile(_kevent._detect, 0.0, 0.0, y, ynew, Qd, P, ew, stats)
    _compile(_kunilateral._detect, 0.0, 0.0, y, Qd, P, ew, 0.0, lift[1], 0.0, stats)
    _compile(
        _kradau.accept, 0.0, y, f, ctl, ws, a["t_eval"], i64, a["X"], a["lam_old"], a["upl_t"],
        np.int64(o.uplift_mode), stats, a["rinfo"],
    )  # fmt: skip
    _compile(_kunilateral._on_target, i64, i64, i64, 0.0, 0.0, 0.0, P, ynew, fnew)
    opts = (True, True, 0.0, 0.0, 0.0, 0.0)
    run = (y, P, f, ws, ew, ctl, np.zeros(2), stats, opts, logs, lift)
    helper.wait_for([ki.jeval])  # the handler's Jacobian: the helper's first piece
    _compile(_kunilateral._event_at, 0.0, i64, i64, 0.0, run)
    helper.wait_for([_kradau.radau_step])
