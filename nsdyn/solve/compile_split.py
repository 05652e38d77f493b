"""A first compilation of an integrator loop shared between two processes.

numba compiles on one thread per process, under a global lock, so a first run's ~1 min of
compilation uses one core. :func:`nsdyn.solve.methods.warmup_kernel` starts a helper process
(:class:`nsdyn._numba_cache.Helper`) on :func:`radau_helper_part` (the flat right-hand side,
its Jacobian and Newton; :func:`radau_helper_part_and_metrics` then also the metrics, which a
run needs only after its loop) while the calling process compiles :func:`radau_parts_here`
(the run's set-up, the factorisation, the start-up) and then the loop itself, which loads the
helper's kernels from numba's on-disk cache. The loop's own compilation (~8-20 s) stays
serial: it needs all of its callees first. The helper's part also serves every later process
(:func:`load_callees`): it loads the callees before the loop, whose calls then go to them.

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

Each piece is compiled for the signature the loop asks for: by calling it from Python on the
tiny problem with arguments built as the loop builds them (the default loop), or by
``Dispatcher.compile`` with the numba types of such arguments (the event loop, whose pieces
cannot run on made-up data). ``tests/solve/test_compile_helper.py`` checks that the calling
process compiles none of the helper's kernels.
"""

from __future__ import annotations

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


def radau_helper_part() -> None:
    """The helper process's share of the flat Radau loop's first compilation (see
    :func:`nsdyn.solve.methods.warmup_kernel`): the flat right-hand side, its Jacobian and
    Newton. Also what every process loads before its first default run (:func:`load_callees`;
    the factorisation's own code loaded as well made no difference, 3 alternating pairs)."""
    P, x0, t_eval, o, X, upl_t, ws = _tiny_args("radau")
    J, LUr, pr, LUc, pc, Z, Z0, W, F, dW, fr, fc, ys, iscale, err, ynew, fnew, Qd = ws[:18]
    qdd, lam, tau, modes, Fl = ws[18:23]
    y = x0.copy()
    _kflat.feval_flat(0.0, y, Fl, fnew, qdd, lam, tau, modes)
    _kflat.jac_flat(0.0, y, Fl, J, ys, qdd, lam, tau, modes)
    n = LUr.shape[0]  # factors of the identity, so that Newton runs on finite numbers
    LUr[:] = np.eye(n)
    LUc[:] = np.eye(n)
    pr[:] = np.arange(n)
    pc[:] = np.arange(n)
    iscale[:] = 1.0
    h = 1e-3
    ctl = _py(_kradau.new_control)(h, o.rtol)
    ctl[_kradau.C_LUH] = h
    stats = np.zeros(ki.N_STATS, dtype=np.int64)
    _kcolloc.newton(
        P, 0.0, y, h, ctl, stats, J, LUr, pr, LUc, pc, Z, W, F, dW, fr, fc, ys, iscale, qdd, lam,
        tau, modes, Fl, True, _kcolloc.flat_only,
    )  # fmt: skip


def radau_helper_part_and_metrics() -> None:
    """:func:`radau_helper_part`, then the flat metrics kernels (``pack_flat``,
    ``evaluate_flat_many``, ``ground_many``): the helper has nothing else to do while the
    calling process compiles the loop, and a run needs the metrics only after its loop."""
    radau_helper_part()
    methods.warmup_metrics(True)


def radau_parts_here(helper: Helper, metrics: str | None) -> None:
    """This process's share before the loop itself: the ``metrics``, the run's set-up and the
    factorisation, then (once the helper has the flat kernels) the start-up; then wait for
    Newton."""
    if metrics is not None:
        methods.warmup_metrics(metrics == "metrics")
    P, x0, t_eval, o, X, upl_t, _ = _tiny_args("radau")
    stats, rinfo, ws, y, f, lam_old = _kradau.setup(P, x0, t_eval, upl_t.size)
    _kcolloc._factor(1e-3, *ws[:5])
    helper.wait_for([_kflat.feval_flat, _kflat.jac_flat])
    _kradau.start(
        P, y, f, t_eval, o.h0, o.max_step, o.atol, o.rtol, lam_old, X, upl_t, o.uplift_mode, ws,
        stats, rinfo, _kcolloc.flat_only,
    )  # fmt: skip
    helper.wait_for([_kcolloc.newton])


# A loop's callees are compiled functions of their own (numba compiles each once), and numba
# also links a copy of each into the loop's code, optimised once more there. Which copy the
# loop calls is decided when its code is loaded: a callee whose own code is already in the
# process is bound to that (it is, in the process that compiled the loop); otherwise the
# loop's copies run. A loop loaded from numba's cache into a new process loads none of its
# callees, and its own copies of Newton and the flat right-hand side made the default run
# ~15 % slower than the same loop in the process that compiled it (51-52 against 44 ms, the
# same machine code, the same steps). The first run of a kernel in a process therefore loads
# its callees first, by the function of this module that calls them on the tiny problem with
# the loop's argument types (loading them from the cache, or compiling them). The switch
# model's loop, whose step inlines its kernels, ran 2-4 % faster so (one pair): not done.
_CALLEES = {"radau": "radau_helper_part"}
_CALLEES_LOADED: set[str] = set()


def load_callees(kernel: str) -> None:
    """Load (or compile) the callees of loop ``kernel`` that it should call in this process,
    before the loop itself is loaded (see the note above); once per process."""
    if kernel in _CALLEES_LOADED or kernel not in _CALLEES:
        return
    globals()[_CALLEES[kernel]]()
    _CALLEES_LOADED.add(kernel)


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
    _compile(_kflat.jac_flat, 0.0, y, Fl, ws[0], f, qdd, lam, tau, modes)


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
        a["X"], a["upl_t"], np.int64(o.uplift_mode), ws, a["stats"], a["rinfo"], g,
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
