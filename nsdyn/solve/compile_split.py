"""A first compilation of the default Radau loop shared between two processes.

numba compiles on one thread per process, under a global lock, so a first run's ~1 min of
compilation uses one core. :func:`nsdyn.solve.methods.warmup_kernel` starts a helper process
(:class:`nsdyn._numba_cache.Helper`) on :func:`radau_helper_part` (the flat right-hand side,
its Jacobian and Newton) while the calling process compiles the metrics and
:func:`radau_parts_here` (the run's set-up, the factorisation, the start-up) and then the loop
itself, which loads the helper's kernels from numba's on-disk cache. The loop's own
compilation (~15-20 s) stays serial: it needs all of its callees first.

Each piece is compiled by calling it from Python on the tiny problem with arguments built as
the loop builds them, so the compiled signature is the one the loop asks for
(``tests/solve/test_compile_helper.py`` checks that the calling process compiles none of the
helper's kernels).
"""

from __future__ import annotations

import numpy as np

from nsdyn._numba_cache import Helper
from nsdyn.models.isolated import _kernel as ks
from nsdyn.solve import _kcolloc, _kflat, _kradau, methods
from nsdyn.solve import _kcommon as ki


def _radau_args():
    """The arguments of the flat Radau loop's pieces on the tiny problem, with the numba types
    the loop gives them (so that what is compiled here is what the loop calls), made without
    compiling anything: :func:`nsdyn.solve.methods.tiny_run` and the workspace ``ws``."""
    P, x0, t_eval, o, X, upl_t = methods.tiny_run(methods.METHODS["radau"])
    ws = _kradau.workspace.py_func(x0.size, upl_t.size, P[ks.I_D].shape[0])
    return P, x0, t_eval, o, X, upl_t, ws + (_kflat.pack_flat.py_func(P),)


def radau_helper_part() -> None:
    """The helper process's share of the flat Radau loop's first compilation (see
    :func:`nsdyn.solve.methods.warmup_kernel`): the flat right-hand side, its Jacobian and
    Newton."""
    P, x0, t_eval, o, X, upl_t, ws = _radau_args()
    J, LUr, pr, LUc, pc, Z, Z0, W, F, dW, fr, fc, ys, scale, err, ynew, fnew, Qd = ws[:18]
    qdd, lam, tau, modes, Fl = ws[18:23]
    y = x0.copy()
    _kflat.feval_flat(0.0, y, Fl, fnew, qdd, lam, tau, modes)
    _kflat.jac_flat(0.0, y, Fl, J, ys, qdd, lam, tau, modes)
    n = LUr.shape[0]  # factors of the identity, so that Newton runs on finite numbers
    LUr[:] = np.eye(n)
    LUc[:] = np.eye(n)
    pr[:] = np.arange(n)
    pc[:] = np.arange(n)
    scale[:] = 1.0
    h = 1e-3
    ctl = _kradau.new_control.py_func(h, o.rtol)
    ctl[_kradau.C_LUH] = h
    stats = np.zeros(ki.N_STATS, dtype=np.int64)
    _kcolloc.newton(
        P, 0.0, y, h, ctl, stats, J, LUr, pr, LUc, pc, Z, W, F, dW, fr, fc, ys, scale, qdd, lam,
        tau, modes, Fl, True, _kcolloc.flat_only,
    )  # fmt: skip


def radau_parts_here(helper: Helper) -> None:
    """This process's share before the loop itself: the run's set-up and the factorisation,
    then (once the helper has the flat kernels) the start-up; then wait for Newton."""
    P, x0, t_eval, o, X, upl_t, _ = _radau_args()
    stats, rinfo, ws, y, f, lam_old = _kradau.setup(P, x0, t_eval, upl_t.size)
    _kcolloc._factor(1e-3, *ws[:5])
    helper.wait_for([_kflat.feval_flat, _kflat.jac_flat])
    _kradau.start(
        P, y, f, t_eval, o.h0, o.max_step, o.atol, o.rtol, lam_old, X, upl_t, o.uplift_mode, ws,
        stats, rinfo, _kcolloc.flat_only,
    )  # fmt: skip
    helper.wait_for([_kcolloc.newton])
