"""Event-driven Radau loop: stick/slip events and unilateral isolator contact (lift-off, flight,
landing). ``event_switch`` runs the switch model with bilateral contacts, ``event_unilateral``
adds the contact events; both drive the one loop :func:`_run`.

Each contact ``k`` of the isolated frame (gap ``g_k = R_k q >= 0``, normal force ``lam_k >= 0``)
is either closed (its row in the constraint set, ``lam_k`` a multiplier) or open (in flight,
``P[I_OPEN][k] = 1``: ``lam_k = 0``, no friction at isolator ``k``, the gap tracked). The
switching functions are located on the Radau dense output like the stick/slip events of
:mod:`nsdyn.solve._kevent` (scan at a few points of each step, Illinois, redo the step to land
on the root)::

    closed k:  lam_k(t)           lift-off  when it crosses zero downwards
    open k:    g_k(t) = R_k q(t)  touchdown when it crosses zero downwards

Landing: Newton's impact law through the generalised mass matrix on the contact rows ``S``
that are closed after the impact (frictionless in the normal direction)::

    qd+ = qd- + M^-1 R_S^T Lam,    R_j qd+ = -e_j R_j qd-   (landing j; 0 for the others)

with ``e_j = e`` (``e = 0`` by default: a plastic landing on the bearing) and ``e_j = 0`` when
``|R_j qd-| <= V_REST`` (bounces too small to resolve end at rest: no Zeno accumulation). The
set is active: a closed contact whose impulse would pull (``Lam_j < 0``) opens, except at such
a rest landing (every contact at the ground then keeps ``v+ = 0``). The kinetic
energy change of the impulse, ``dT = Lam . R_S (qd- + qd+) / 2 <= 0`` for ``0 <= e <= 1``, is
logged. After every contact event the contact set is settled: the acceleration-level
complementarity problem over the contacts at rest at the ground (``lam_k >= 0``, ``R_k qdd +
b_k >= 0``, ``lam_k (R_k qdd + b_k) = 0`` with ``b_k`` the Baumgarte terms; Murty's
least-index pivoting, see :func:`_kimpact._settle_contacts`), then the friction modes
(:func:`_kevent._settle`, LAW_MODES only; other laws decide them in the right-hand side), and
the stepper restarts. The touchdown
scan splits each step at the extrema of the cubic gap polynomial, so that a flight shorter than
the step is not skipped.
"""

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn._klinalg import copy_vec
from nsdyn.models.isolated import _kernel as ks
from nsdyn.solve import _kcolloc as kcol
from nsdyn.solve import _kcommon as ki
from nsdyn.solve import _kevent as ke
from nsdyn.solve import _kflat as kf
from nsdyn.solve import _kradau as kr
from nsdyn.solve._kimpact import (  # noqa: F401  (CLOG_COLS: the log layout, for the front door)
    CLOG_COLS,
    KIND_LAND,
    KIND_LIFT,
    V_REST,
    _detect,
    _lam_scale,
    _land,
    _log,
    _settle_contacts,
)

GAP_ATOL = 1.0  # gaps within this x atol (displacements) count as zero (touchdown noise)
# what the main loop does with a step (see _on_target and _plan)
ACT_STEP = 0  # accept the step, no event at its end
ACT_SWITCH = 1  # accept the step, handle the event at its end
ACT_NOW = 2  # discard the step, handle the event at its start
ACT_REDO = 3  # discard the step, redo it to end on t_target


@ka.compiled_uncounted
def _event_at(t, kind, idx, h_resume, run):
    """Handle an event (friction kinds 0/1, KIND_LIFT, KIND_LAND) at (t, y) and restart the
    stepper there. ``run = (y, P, f, ws, ew, ctl, burst, stats, (friction, contacts, v_tol,
    g_tol, e_rest, max_step), (log, clog, cnt, dT), lift)``: state, work arrays, settings,
    logs and the last lift-off of each contact (time; gap then, if below zero), the same objects
    all along the integration. Returns False (status set) on a full
    log, chattering or a singular impact."""
    y, P, f, ws, ew, ctl, burst, stats, opts, logs, lift = run
    friction, contacts, v_tol, g_tol, e_rest, max_step = opts
    log, clog, cnt, dT = logs
    opn = P[ks.I_OPEN]
    pm = P[ks.I_MODE]
    D = P[ks.I_D]
    n = y.shape[0] // 2
    ok = True
    if kind == KIND_LIFT:
        opn[idx] = 1
        lift[0, idx] = t
        lift[1, idx] = min(ke._dot_row(P[ks.I_R], idx, y, np.int64(0)), 0.0)
        ok = _log(clog, cnt, t, idx, np.int64(KIND_LIFT), ke._dot_row(P[ks.I_R], idx, y, n), 0.0)
    elif kind == KIND_LAND:
        was = ew[8]
        for i in range(opn.shape[0]):
            was[i] = opn[i]
        ok = ka.tcall("event.land", (t, y, P, idx, e_rest, g_tol, clog, cnt, dT))
        if friction:  # landed isolators: slip along their velocity, else the stick test
            for i in range(D.shape[0]):
                if i < opn.shape[0] and was[i] != 0 and opn[i] == 0:
                    v = ke._dot_row(D, i, y, n)
                    pm[i] = (1 if v > 0.0 else -1) if abs(v) > v_tol else ke.MODE_AUTO
    singular = not ok
    for _ in range(ke.SETTLE_PASSES if ok else 0):
        changed = False
        if contacts:
            ok, changed = ka.tcall(
                "event.settle_contacts", (t, y, P, f, ew, g_tol, clog, cnt, stats, lift)
            )
            singular = not ok
        if ok and friction:
            trig = idx if kind < KIND_LIFT else -1
            ok = ka.tcall("event.settle", (t, y, P, f, ew, trig, v_tol, log, stats))
            kind = KIND_LIFT  # the trigger is settled once
        if not ok or not changed:
            break
    if not ok:  # a full log, chattering modes, or a singular impact system
        singular = singular and cnt[0] < clog.shape[0]
        stats[ki.S_STATUS] = ki.ST_SINGULAR if singular else ki.ST_EVENTS
        return False
    ki.feval_t(t, y, P, f, ew[2], ew[3], ew[4], ew[5])
    ki.jeval_t(t, y, P, ws[0])
    stats[ki.S_NFEV] += 1
    stats[ki.S_NJEV] += 1
    kr.restart(ctl)
    ctl[kr.C_CURJ] = 1.0
    ctl[kr.C_H] = min(h_resume, max_step)
    if t - burst[0] <= ke.BURST_DT:
        burst[1] += 1.0
    else:
        burst[1] = 0.0
    burst[0] = t
    if burst[1] >= ke.MAX_BURST:
        stats[ki.S_STATUS] = ki.ST_EVENTS
        return False
    return True


@ka.compiled_only
def _on_target(ev_kind, ev_idx, polish, t_new, t_target, h, P, ynew, fnew):
    """The step ended on the located event ``t_target``. A slip -> stick landing is polished by
    Newton corrections dt = -g/g' (at most POLISH_MAX): step once more (ACT_STEP) or redo the
    step (ACT_REDO) to the corrected instant; else switch there (ACT_SWITCH).
    Returns (action, t_target, polish)."""
    if ev_kind == 0 and polish < ke.POLISH_MAX:
        n = ynew.shape[0] // 2
        D = P[ks.I_D]
        sg = float(P[ks.I_MODE][ev_idx])
        g = sg * ke._dot_row(D, ev_idx, ynew, n)
        gd = sg * ke._dot_row(D, ev_idx, fnew, n)
        dt = -g / gd if gd < 0.0 else 0.0
        if dt > ke.EVENT_TTOL and dt >= ki.step_floor(t_new):
            return ACT_STEP, t_new + dt, polish + 1
        if dt < -ke.EVENT_TTOL and dt > -h:
            return ACT_REDO, t_new + dt, polish + 1
    return ACT_SWITCH, t_target, polish


@njit(cache=True, error_model="numpy")
def _plan(t, t_new, h, x_best):
    """An event found at ``t + x_best h`` of the step [t, t_new = t + h]: switch at the step end
    (ACT_SWITCH), discard the step and switch at its start (ACT_NOW), or redo the step to land
    on the event (ACT_REDO). Returns (action, t_target)."""
    t_star = t + x_best * h
    if t_new - t_star <= ke.EVENT_TTOL:
        return ACT_SWITCH, t_new
    if t_star - t <= max(ke.EVENT_TTOL, ki.step_floor(t)):
        return ACT_NOW, t
    return ACT_REDO, t_star


# the Radau start-up and step (nsdyn.solve._kradau._start, _step), copies whose general kernel
# is the stage evaluation by its address (nsdyn.solve._kcolloc.general_t); the flat kernels, the
# factorisation and Newton (nsdyn.solve._kcolloc.newton_table, or newton_general for a law
# without flat kernels) by their addresses in K (nsdyn.solve.compile_split.event_calls)
_start = ka.compiled_uncounted(ka.specialised(kr._start, "event_start", _GENERAL=kcol.general_t))
_step = ka.compiled_uncounted(ka.specialised(kr._step, "event_step", _GENERAL=kcol.general_t))


def loop_arrays(n2: int, nc: int, ni: int) -> tuple:
    """The event loop's own arrays besides the run's (numpy): (scratch state (n2,), the last
    lift-off of each contact (2, nc): time and min(gap, 0), the current burst of events: its
    start and length, then scratch of its kernels: ni floats, ni and nc integers)."""
    lift = np.zeros((2, nc))
    lift[0] = -np.inf
    burst = np.array([-np.inf, 0.0])
    return (np.empty(n2), lift, burst, np.empty(ni), np.empty(ni, dtype=np.int64),
            np.empty(nc, dtype=np.int64))  # fmt: skip


def typing_locals(P, x0, t_eval, o, X, upl_t, ws) -> dict:
    """The loop's local variables as :func:`_run` makes them, from the run's arguments (values
    are placeholders: only their numba types matter, for the declarations of its callees by
    address, :func:`nsdyn.solve.compile_split.event_callees`)."""
    n2, nc = x0.size, upl_t.size
    a = dict(P=P, x0=x0, t_eval=t_eval, o=o, X=X, upl_t=upl_t, ws=ws, y=x0.copy())
    a["f"] = np.zeros(n2)
    a["stats"] = np.zeros(ki.N_STATS, dtype=np.int64)
    a["rinfo"] = np.zeros(ki.N_RINFO)
    a["lam_old"] = np.zeros(nc)
    scratch = loop_arrays(n2, nc, P[ks.I_D].shape[0])[3:]
    a["ew"] = (ws[12], np.empty(n2), ws[18], ws[19], ws[20], ws[21], *scratch)
    a["log"] = (np.zeros(1), np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.int64))
    a["logs"] = (a["log"], np.zeros((1, CLOG_COLS)), np.zeros(1, dtype=np.int64), np.zeros(1))
    a["lift"] = np.zeros((2, nc))
    a["i64"] = np.int64(0)
    return a


@njit(cache=True, error_model="numpy", nogil=True, **ka.NO_NRT)  # (held_call watches it)
def _run(P, x0, t_eval, tol, steps, modes0, flags, e_rest, X, upl_t, OPEN_OUT, logs, owned, mine,
         K):  # fmt: skip
    """The event-driven loop of both entry points: Radau steps between events, friction
    (``flags[0]``) and contact (``flags[1]``) events located on the dense output, the step
    redone to land on them. ``tol = (atol, rtol)``, ``steps = (h0, max_step, max_steps)``,
    ``flags = (friction, contacts, uplift_mode)``, ``logs = (log, clog, cnt, dT)``, ``owned``
    the arrays of the run (:func:`nsdyn.solve._kradau.setup_here`), ``mine`` the loop's own
    (:func:`loop_arrays`), ``K`` the addresses of the step's callees
    (:func:`nsdyn.solve.compile_split.event_calls`). Returns nothing: the results are in the
    arrays given.

    It allocates no array and is compiled without reference counts (:data:`nsdyn._kaddress.
    NO_NRT`: 3.6 s of one core against 8.5 s for its first compilation).

    Its callees (the settling, the start-up, the step, both detectors, the step's acceptance
    and the event handler) are called by their addresses in the table of
    :mod:`nsdyn._kaddress` (:func:`tables` fills it): this loop's code holds none of theirs,
    and each of them compiles once, on its own."""
    atol, rtol = tol
    h0, max_step, max_steps = steps
    friction, contacts, uplift_mode = flags
    n = x0.shape[0] // 2
    nt = t_eval.shape[0]
    stats, rinfo, ws, y, f, lam_old, ctl = owned
    scr, lift, burst, g0, m_old, o_old = mine
    D = P[ks.I_D]
    pm = P[ks.I_MODE]
    opn = P[ks.I_OPEN]
    ynew, fnew, Qd, lam = ws[15], ws[16], ws[17], ws[19]
    ew = (ws[12], scr, ws[18], lam, ws[20], ws[21], g0, m_old, o_old)
    # velocities above v_tol are resolved motion (new slips oppose them), below: stick test
    v_tol = ke.V_SLIP_ATOL * ki.largest(atol[n:])
    g_tol = GAP_ATOL * ki.largest(atol[:n])
    t = t_eval[0]
    t_end = t_eval[-1]
    if not ki.all_finite(y):
        stats[ki.S_STATUS] = ki.ST_NONFINITE
        return
    ok = True
    # the friction modes first (the contact forces depend on them, and MODE_AUTO is not a
    # mode the right-hand side knows), then the contact set
    if friction:
        ke._initial_modes(P, y, modes0)
        auto = False
        for i in range(D.shape[0]):
            if pm[i] == ke.MODE_AUTO:
                auto = True
        if auto:
            ok = ka.tcall("event.settle", (t, y, P, f, ew, np.int64(-1), ke.V_AUTO, logs[0], stats))
    if ok and contacts:
        ok, _ = ka.tcall(
            "event.settle_contacts", (t, y, P, f, ew, g_tol, logs[1], logs[2], stats, lift)
        )
    if friction:
        stats[ki.S_NEVENT] = 0  # the initial mode choice is not an event
    if not ok:
        stats[ki.S_STATUS] = ki.ST_EVENTS
        return
    iout = ka.tcall("event.start", (
        P, y, f, t_eval, h0, max_step, atol, rtol, lam_old, X, upl_t, uplift_mode, ws, stats,
        rinfo, ctl, K,
    ))  # fmt: skip
    for k in range(max(iout, 0) if contacts else 0):
        copy_vec(OPEN_OUT[k], opn)
    if iout < 0 or iout >= nt:
        return
    t_target = np.inf  # pending event instant to land on
    # np.int64: a variable that still holds its constant initial value at a call is passed as
    # a literal, and numba would compile the callee once for it and once for int64
    ev_idx = np.int64(-1)  # isolator or contact of the pending event
    ev_kind = np.int64(0)  # 0: slip -> stick/reversal, 1: stick -> slip, KIND_LIFT, KIND_LAND
    polish = np.int64(0)
    h_resume = ctl[kr.C_H]  # step size to resume with after an event
    opts = (friction, contacts, v_tol, g_tol, e_rest, max_step)
    run = (y, P, f, ws, ew, ctl, burst, stats, opts, logs, lift)
    # not the constant False: the step's signature then has a plain bool, which a compile
    # helper (nsdyn.solve.compile_split) can ask for from Python
    fixed = np.bool_(False)
    while iout < nt:
        t_lim = min(t_end, t_target, ki.next_kink(t, P))
        st = ka.tcall("event.step", (
            P, t, y, f, t_lim, fixed, atol, rtol, max_step, max_steps, ws, ctl, stats, rinfo, K,
        ))  # fmt: skip
        if st != ki.ST_SUCCESS:
            stats[ki.S_STATUS] = st
            rinfo[ki.R_T] = t
            break
        t_new = ctl[kr.C_TNEW]
        h = ctl[kr.C_HSTEP]
        act = ACT_STEP
        if t_new == t_target:
            act, t_target, polish = _on_target(
                ev_kind, ev_idx, polish, t_new, t_target, h, P, ynew, fnew
            )
        else:
            # bracket the switching functions over the step, earliest root wins
            x_best, i_best, k_best = 2.0, -1, 0
            if friction:
                x_best, i_best, k_best = ka.tcall(
                    "event.detect_friction", (t, h, y, ynew, Qd, P, ew, stats, v_tol)
                )
            if contacts:
                x_max = min(x_best, 1.0 + 1e-15)
                xc, kc, kindc = ka.tcall(
                    "event.detect_contacts", (t, h, y, Qd, P, ew, g_tol, lift[1], x_max, stats)
                )
                if kc >= 0 and xc <= x_best:
                    x_best, i_best, k_best = xc, kc, kindc
            if i_best >= 0:
                ev_idx, ev_kind, polish = i_best, k_best, 0
                if ctl[kr.C_H] > 0.0 and not np.isfinite(t_target):
                    h_resume = max(h, ctl[kr.C_H])
                act, t_target = _plan(t, t_new, h, x_best)
        if act >= ACT_NOW:  # discard the step
            stats[ki.S_NSTEP] -= 1
            stats[ki.S_NREJ] += 1
            if act == ACT_REDO:
                ctl[kr.C_HPREV] = 0.0
                ctl[kr.C_H] = t_target - t
                continue
        else:
            i0 = iout
            iout, stop = ka.tcall("event.accept", (
                t, y, f, ctl, ws, t_eval, iout, X, lam_old, upl_t, uplift_mode, stats, rinfo
            ))  # fmt: skip
            for k in range(i0, iout if contacts else i0):
                copy_vec(OPEN_OUT[k], opn)
            t = t_new
            if stop:
                break
        if act != ACT_STEP:
            ok = ka.tcall("event.handle", (t, ev_kind, ev_idx, h_resume, run))
            copy_vec(lam_old, lam)
            if not ok:
                rinfo[ki.R_T] = t
                break
            t_target = np.inf
    rinfo[ki.R_HNEXT] = ctl[kr.C_H]


# the callees of the loop by their addresses (nsdyn._kaddress.tcall), declared there
_DECLARE = "nsdyn.solve.compile_split:event_callees"
ka.tslot("event.settle", ke._settle, _DECLARE)
ka.tslot("event.settle_contacts", _settle_contacts, _DECLARE)
ka.tslot("event.start", _start, _DECLARE)
ka.tslot("event.step", _step, _DECLARE)
ka.tslot("event.detect_friction", ke._detect, _DECLARE)
ka.tslot("event.detect_contacts", _detect, _DECLARE)
ka.tslot("event.accept", kr.accept, _DECLARE)
ka.tslot("event.handle", _event_at, _DECLARE)
ka.tslot("event.land", _land, _DECLARE)
# the names of the loop's callees in the table: those of every run, of friction events (the
# switch model) and of contact events (unilateral contacts); a run fills the rows it calls
CALLEES = (
    *ki.SYSTEM_ROWS, "event.start", "event.step", "event.accept", "event.handle",
    "event.general",
)  # fmt: skip
CALLEES_FRICTION = ("event.settle", "event.detect_friction")
CALLEES_CONTACTS = ("event.settle_contacts", "event.detect_contacts", "event.land")


def callees(friction: bool, contacts: bool) -> tuple:
    """The names of the table rows a run with friction and/or contact events calls."""
    return CALLEES + CALLEES_FRICTION * bool(friction) + CALLEES_CONTACTS * bool(contacts)


def kernels(friction: bool, contacts: bool, flat: bool) -> tuple:
    """Every compiled kernel a run of the loop needs (the loop, its callees in the table, the
    step's callees in ``K``): what a first run compiles."""
    newton = kcol.newton_table if flat else kcol.newton_general
    K = (kr._factor, newton) + (kf.feval_flat, kf.jac_flat_here) * bool(flat)
    table = tuple(ka.TSLOTS[name] for name in callees(friction, contacts))
    return (_run, *table, *K)


def tables(friction: bool, contacts: bool, owned):
    """Fill the address table with the loop's callees for a run with friction and/or contact
    events (each loaded from numba's cache, or compiled; once per process) before the loop
    runs; ``K`` of its step (:func:`nsdyn.solve.compile_split.event_calls`, with the flat
    kernels where the law of the run's flat array ``owned[2][22]`` has them)."""
    from nsdyn.solve import compile_split  # (it imports this module)

    flat = owned[2][22][kf.H_OK] != 0.0
    return compile_split.event_ready(friction, contacts, bool(flat))


# The two entry points are plain Python: a numba wrapper around the called loop would be
# compiled on its own, and numba optimises each compiled function's LLVM module with every
# callee linked into it, so a wrapper repeats LLVM's work over the whole event loop for nothing
# at run time (~6 s in the one pair measured). Scalar arguments are coerced so that both entry
# points give the loop one signature (the compile helper's, nsdyn.solve.compile_split). The
# arrays of the run are made here (numpy, :func:`nsdyn.solve._kradau.setup_here`).


def event_unilateral(
    P, x0, t_eval, atol, rtol, h0, max_step, max_steps, modes0, friction, e_rest, X, upl_t,
    OPEN_OUT, log, clog, cnt, dT,
):  # fmt: skip
    """Integration with unilateral contacts; outputs as :func:`nsdyn.solve._kradau.radau`.

    ``P[I_OPEN]`` (the initial contact states, changed in place) and, with ``friction`` (law
    LAW_MODES), ``P[I_MODE]`` are live. ``modes0`` as :func:`event_switch`. Contact
    states at the outputs go to ``OPEN_OUT`` (nt, nc); friction events to ``log``; contact
    events to ``clog`` (rows t, contact, kind, R qd before, impulse; count ``cnt[0]``);
    ``dT[0]`` sums the kinetic energy change of the landings.
    """
    owned = kr.setup_here(P, x0, t_eval, upl_t.shape[0])
    K = tables(friction, True, owned)
    _run(
        P, x0, t_eval, (atol, float(rtol)), (float(h0), float(max_step), int(max_steps)),
        modes0, (bool(friction), True, int(ki.UPLIFT_WARN)), float(e_rest), X, upl_t,
        OPEN_OUT, (log, clog, cnt, dT), owned,
        loop_arrays(x0.shape[0], upl_t.shape[0], P[ks.I_D].shape[0]), K,
    )  # fmt: skip
    return owned[0], owned[1]


def event_switch(
    P, x0, t_eval, atol, rtol, h0, max_step, max_steps, modes0, uplift_mode, X, upl_t, log
):
    """Event-driven switch-model integration with bilateral contacts (:mod:`nsdyn.solve._kevent`
    events only); same outputs as :func:`nsdyn.solve._kradau.radau`.

    ``P`` must have law LAW_MODES; ``P[I_MODE]`` is overwritten with the live modes.
    ``modes0`` (ni,): +1/-1/0, or MODE_AUTO (slip along v if |v| > V_AUTO, else stick test).
    Events are written to ``log = (ev_t, ev_i, ev_m)`` (time, isolator, new mode); their count
    is ``stats[S_NEVENT]``. A normal force reaching zero is handled by ``uplift_mode``.
    """
    nc = P[ks.I_OPEN].shape[0]
    owned = kr.setup_here(P, x0, t_eval, upl_t.shape[0])
    K = tables(True, False, owned)
    _run(
        P, x0, t_eval, (atol, float(rtol)), (float(h0), float(max_step), int(max_steps)),
        modes0, (True, False, int(uplift_mode)), 0.0, X, upl_t,
        np.zeros((0, nc), dtype=np.int64),
        (log, np.zeros((0, CLOG_COLS)), np.zeros(1, dtype=np.int64), np.zeros(1)), owned,
        loop_arrays(x0.shape[0], nc, P[ks.I_D].shape[0]), K,
    )  # fmt: skip
    return owned[0], owned[1]
