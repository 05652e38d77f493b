"""The pair systems' force kernel by address, and their first compilation shared by two processes.

Every kernel of a pair system's time loops that evaluates it (the right-hand side of both
loops, the settling of stick and of unilateral contacts, the event functions, the outputs)
calls the force kernel :func:`nsdyn.models.isolated._kpairs.evaluate` (its tensile and
pressure passes around ``evaluate_at``, inlined: the contact and stick rows, the friction
forces, the small solve for λ and τ). Linked, numba would copy it into each of them and LLVM would
optimise and translate every copy again; called by its address
(:func:`nsdyn._kaddress.tcall`, row ``"pairs.evaluate"`` of the process-wide table) it
compiles once, on its own. :func:`callees` declares it for the argument types the loops give
it.

A first run compiles in two processes (numba compiles on one thread per process): a helper
(:class:`nsdyn._numba_cache.Helper`) compiles the force kernel (:func:`helper_part`) while
this process compiles the time loop from the run's own argument types, then loads the
helper's kernel from numba's on-disk cache (:func:`nsdyn._kaddress.run_split`). What the
helper does not deliver this process compiles itself: the kernels are the same either way.
"""

from __future__ import annotations

import functools


def tiny_args() -> tuple:
    """The arguments of the force kernel, of the settlings (and the initial modes) and of the
    outputs as the loops pass them, for one isolator and two dofs (made with numpy only:
    nothing is compiled; only their types matter): (force kernel's, settlings', outputs')."""
    import numpy as np

    from nsdyn.models.isolated import _kpairs as kq
    from nsdyn.models.isolated import _kplanerun as kr
    from nsdyn.models.isolated.bearings import N_BCOL
    from nsdyn.models.isolated.deck import pack_ground

    n, ni = 2, 1
    op = tuple(np.zeros((2, 2)) for _ in range(kq.O_Q + 1))  # the operators: 12 C arrays
    gk, gp, tab, _ = pack_ground({"f": 1.0, "ax": 1.0})
    modes, dirs = np.zeros(ni, dtype=np.int64), np.zeros((ni, 2))
    ws = kq.workspace(n, ni)
    out = kq.outputs_at(n, ni)
    bp, sp = np.zeros((ni, N_BCOL)), np.zeros(kq.N_SP)
    head = (0.0, np.zeros(2 * n), modes, dirs, op, bp, sp, gk, gp, tab, ws)
    rows = (np.zeros((1, 2 * n)), np.zeros((1, ni)), *(np.zeros((1, ni, 2)) for _ in range(3)),
            np.zeros((1, ni), dtype=np.int64))  # X, NO, FF, FR, FO, MO  # fmt: skip
    return ((*head, *out), (*head, out, np.zeros((1, 6)), np.zeros(kr.N_INFO)),
            (*head, out, np.int64(0), *rows))  # fmt: skip


@functools.cache
def callees() -> list:
    """The pair loops' callees by address (:class:`nsdyn._kaddress.Callee`): the force kernel
    (``"pairs.evaluate"``), a row of the outputs (``"pairs.outputs"``: the start, the output
    step and the Radau loop's end call it), the switch law's settling of stick
    (``"pairs.settle"``), the settling of unilateral contacts (``"pairs.settle_contacts"``)
    and the switch law's initial modes (``"pairs.initial_modes"``, called by the loops'
    start, which the Radau loop shares without the switch law), declared for the types of
    :func:`tiny_args`, each returning a status (int64); then the Radau loop's factorisation
    and solve of σ I − J for real and complex σ (``"pairs.factor_real"``,
    ``"pairs.factor_complex"``: True when factored; ``"pairs.solve_real"``,
    ``"pairs.solve_complex"``), declared for the arrays of :func:`loop_arrays`; last the
    force kernel's two rarer solves (``"pairs.proportional_split"`` with redundant stick rows,
    ``"pairs.least_norm"`` when the LU fails), each returning True when solved; then the
    basis of the stuck isolators' slip rows (``"pairs.stick_basis"``, returning its rank),
    the loops' start, output step, rim tracking and right-hand side, the Radau loop's
    Jacobian and dense output, the event loop's mode switch, location of events and of
    uplift, the landing of unilateral contacts and the start direction of a stuck isolator
    (:data:`FORCE_ROWS` ... :data:`CONTACT_ROWS` say which loop calls which). Once per
    process."""
    import numpy as np
    from numba import typeof, types

    from nsdyn._kaddress import Callee
    from nsdyn.models.isolated import _kpairs as kq
    from nsdyn.models.isolated import _kpairscontact as kc
    from nsdyn.models.isolated import _kpairsradau as kqa
    from nsdyn.models.isolated import _kpairsrun as kqr
    from nsdyn.models.isolated import _kpairsstick as kst
    from nsdyn.models.isolated import _kplaneradau as krad

    force, settle, outs = (tuple(typeof(a) for a in args) for args in tiny_args())
    real, cplx = (typeof(np.zeros(2, dtype=d)) for d in (np.float64, np.complex128))
    mat_r, mat_c = real.copy(ndim=2), cplx.copy(ndim=2)  # C-contiguous, as loop_arrays
    piv = typeof(np.zeros(2, dtype=np.int64))
    return [
        Callee("pairs.evaluate", kq.evaluate, force, types.int64),
        Callee("pairs.outputs", kqr.outputs, outs, types.int64),
        Callee("pairs.settle", kst.settle, settle, types.int64),
        Callee("pairs.settle_contacts", kc.settle_contacts, settle, types.int64),
        Callee("pairs.initial_modes", kst.initial_modes, settle, types.int64),
        Callee("pairs.factor_real", kqa._factor, (types.float64, mat_r, mat_r, piv),
               types.boolean),
        Callee("pairs.factor_complex", kqa._factor, (types.complex128, mat_r, mat_c, piv),
               types.boolean),
        Callee("pairs.solve_real", kqa._solve, (types.float64, mat_r, mat_r, piv, real, real,
                                                real), types.none),
        Callee("pairs.solve_complex", kqa._solve, (types.complex128, mat_r, mat_c, piv, cplx,
                                                   cplx, cplx), types.none),
        Callee("pairs.proportional_split", kq.proportional_split, (mat_r, types.int64,
               types.int64, typeof(kq.workspace(2, 1)), types.boolean), types.boolean),
        Callee("pairs.least_norm", kq.least_norm, (types.Array(types.float64, 2, "A"), real,
               real), types.boolean),
        Callee("pairs.stick_basis", kq.stick_basis, (force[2], piv, mat_r, types.int64,
               types.int64, force[10]), types.int64),
        Callee("pairs.begin", kqr.begin, (outs[1], types.float64, *outs[2:10], *outs[13:],
               *settle[-2:], outs[10], outs[11], outs[1]), types.int64),
        Callee("pairs.emit", kqr.emit, (*outs, mat_r), types.none),
        Callee("pairs.track_stops", kc.track_stops, (types.float64, outs[1], outs[4], outs[5],
               outs[10], mat_r), types.none),
        Callee("pairs.rhs", kq.rhs, (*settle[:12], real), types.int64),
        Callee("pairs.jacobian", kqa._jacobian, (types.float64, real, real, *settle[2:12], mat_r,
               real), types.int64),
        Callee("pairs.dense", krad._dense, (real, mat_r, types.float64, real), types.none),
        Callee("pairs.switch", kqr.switch, (types.float64, real, mat_r, mat_r, *settle[2:]),
               types.int64),
        Callee("pairs.locate_event", kqr.locate_event, (types.float64, types.float64, mat_r, real,
               real, mat_r, mat_r, mat_r, mat_r, *settle[2:12]),
               types.Tuple((types.boolean, types.float64, types.int64))),
        Callee("pairs.locate_uplift", kqr.locate_uplift, (types.float64, types.float64,
               types.float64, mat_r, real, *settle[2:12], real), types.float64),
        Callee("pairs.land", kc.land, (types.float64, real, types.int64, *settle[2:5],
               settle[10], mat_r, real, types.boolean, types.float64),
               types.UniTuple(types.float64, 2)),
        Callee("pairs.start_direction", kq.start_direction, (types.int64, types.float64,
               types.float64, types.float64, settle[10], settle[3]), types.none),
    ]  # fmt: skip


# the rows of :func:`callees` by who calls them: the force kernel with its least-norm solve, the
# outputs, the loops' start, output step, rim tracking and right-hand side (both loops); the
# force kernel's stick rows, the settlings and initial modes (the loop with located events:
# the switch law runs on it); the factorisations and solves of σ I − J, the Jacobian and the
# dense output (the Radau loop, which runs the regularised law only: without stuck isolators
# its force kernel never reaches its stick rows, whose rows the run leaves empty: a call would
# raise)
FORCE_ROWS = ("pairs.evaluate", "pairs.least_norm", "pairs.outputs")
LOOP_ROWS = ("pairs.begin", "pairs.emit", "pairs.track_stops", "pairs.rhs")
EVENT_ROWS = ("pairs.stick_basis", "pairs.proportional_split", "pairs.settle",
              "pairs.settle_contacts", "pairs.initial_modes", "pairs.switch",
              "pairs.locate_event", "pairs.locate_uplift", "pairs.start_direction")  # fmt: skip
RADAU_ROWS = ("pairs.factor_real", "pairs.factor_complex", "pairs.solve_real",
              "pairs.solve_complex", "pairs.jacobian", "pairs.dense")  # fmt: skip
# the unilateral contacts' landing (the loop with located events, contact "unilateral" only)
CONTACT_ROWS = ("pairs.land",)
# this process's share of a first run beside its loop (:func:`_here`), the helper's the rest:
# the shares measured even (this process also builds the model meanwhile): the Radau loop
# with its own pieces; the event loop with the mode switch, the location of events and of
# uplift and the stick rows (the helper: the force kernel, the settlings, the start direction)
HERE_ROWS = {False: RADAU_ROWS,
             True: ("pairs.switch", "pairs.locate_event", "pairs.locate_uplift",
                    "pairs.stick_basis", "pairs.proportional_split")}  # fmt: skip


def _rows(names) -> list:
    """The callees of ``names``, in that order."""
    by_name = {c.name: c for c in callees()}
    return [by_name[n] for n in names]


def _needed(events: bool, unilateral: bool = False) -> list:
    """The callees a run calls: the force kernel (with its least-norm solve), the outputs and
    the loop's start, output step, rim tracking and right-hand side, and on the loop with
    located events the force kernel's stick rows (their basis and proportional split), the
    settlings (the switch law's stick, unilateral contacts), the initial modes, the mode
    switch and the location of events and of uplift (with ``unilateral`` contacts also their
    landing), on the Radau loop its factorisations and solves, its Jacobian and its dense
    output."""
    rows = FORCE_ROWS + LOOP_ROWS + (EVENT_ROWS if events else RADAU_ROWS)
    return _rows(rows + (CONTACT_ROWS if events and unilateral else ()))


def _here(events: bool, unilateral: bool = False) -> list:
    """The callees this process compiles after the loop while the helper compiles the others
    (:data:`HERE_ROWS`; and the landing of unilateral contacts)."""
    return _rows(HERE_ROWS[events] + (CONTACT_ROWS if events and unilateral else ()))


def _helper(events: bool) -> list:
    """The helper's share: the callees of :func:`_needed` but :data:`HERE_ROWS`'."""
    here = set(HERE_ROWS[events])
    return [c for c in _needed(events) if c.name not in here]


def kernels(events: bool, unilateral: bool = False) -> list:
    """The numba kernels a run compiles: its loop (``_kpairsrun.integrate`` with located
    events, else ``_kpairsradau.integrate``) and the callees it calls by address (with
    ``unilateral`` contacts, on the loop with located events, also their landing)."""
    from nsdyn.models.isolated import _kpairsradau as kqa
    from nsdyn.models.isolated import _kpairsrun as kqr

    loop = kqr.integrate if events else kqa.integrate
    return [loop, *(c.kernel for c in _needed(events, unilateral))]


def loop_arrays(loop, n_states: int, n: int, ni: int) -> tuple:
    """The arrays of a run of the time loop ``loop`` (``_kpairsradau.integrate`` or
    ``_kpairsrun.integrate``) for ``n_states`` states of n coordinates and ``ni`` isolators,
    its last argument, in the order the loop unpacks them: the force kernel's workspace and
    outputs, the state, then the loop's scratch. Made here, in Python, so that the loops
    allocate nothing: the Radau loop compiles without numba's reference counts
    (:data:`nsdyn._kaddress.NO_NRT`); the Dormand-Prince loop keeps them, since the unilateral
    contacts' landing, a callee, allocates its small solve."""
    import numpy as np

    from nsdyn.models.isolated import _kpairs as kq
    from nsdyn.models.isolated import _kpairsradau as kqa

    N, k1, c = n_states, n_states - n, np.complex128  # k1: the rows of q̈ and ṡ
    head = (kq.workspace(n, ni), kq.outputs_at(n, ni), np.zeros(N))
    if loop is kqa.integrate:  # V6 (ys, f0, f1, ynew, err, sc), Jx, Sr, Sc, pr, pc, wr, wc,
        # Z, W, F, rw, dW, cr, cz, yp, Zp
        return (*head, np.zeros((6, N)), np.zeros((k1, N)), np.zeros((k1, k1)),
                np.zeros((k1, k1), dtype=c), np.zeros(k1, dtype=np.int64),
                np.zeros(k1, dtype=np.int64), np.zeros(k1), np.zeros(k1, dtype=c),
                *(np.zeros((3, N)) for _ in range(5)), np.zeros(N, dtype=c),
                np.zeros(N, dtype=c), np.zeros(N), np.zeros((3, N)))  # fmt: skip
    # Dormand-Prince: the stages k, a stage y1, a dense state ys, the dense coefficients rc,
    # four arrays of switching functions
    return (*head, np.zeros((7, N)), np.zeros(N), np.zeros(N), np.zeros((5, N)),
            *(np.ones((ni, 3)) for _ in range(4)))  # fmt: skip


def run_loop(loop, args: tuple, unilateral: bool = False, progress=None):
    """``loop(*args)`` (a time loop of a pair system: ``_kpairsrun.integrate``, which locates
    events, or ``_kpairsradau.integrate``), the addresses of its callees in the table first
    (``unilateral``: the run's contacts are, and the loop locates their landings).
    ``progress(t_done, t_end, wall_s)``: called every few seconds while the loop runs in a
    thread of its own (:func:`nsdyn._progress.watched`; t_done the last output written,
    ``info[I_NOUT]``).
    A first compilation is shared with a helper process where one may run
    (:func:`nsdyn._numba_cache.helper_enabled`): it compiles the callees (:func:`helper_part`
    or :func:`helper_force`) while this process compiles the loop for ``args``' types."""
    from nsdyn._kaddress import run_split
    from nsdyn.models.isolated import _kpairsradau as kqa

    events = loop is not kqa.integrate
    target = "helper_part" if events else "helper_force"

    def run():
        return run_split(loop, args, _needed(events, unilateral),
                         f"nsdyn.models.isolated.pairs_compile:{target}",
                         _here(events, unilateral))  # fmt: skip

    if progress is None:
        return run()
    from nsdyn._progress import watched
    from nsdyn.models.isolated._kplanerun import I_NOUT

    t_eval, info = args[1], args[19]
    return watched(run, lambda: float(t_eval[max(int(info[I_NOUT]) - 1, 0)]), progress,
                   float(t_eval[-1]))  # fmt: skip


def helper_part() -> None:
    """The helper's share of a first compilation of the loop with located events: the force
    kernel with its solves and stick rows, the outputs, the start, output step, rim tracking
    and right-hand side, both settlings, the initial modes and the start direction."""
    for c in _helper(True):
        c.compiled()


def helper_force() -> None:
    """The helper's share of a first compilation of the Radau IIA loop: the force kernel with
    its least-norm solve, the outputs, the start, output step, rim tracking and right-hand
    side."""
    for c in _helper(False):
        c.compiled()
