"""Time integration of the constrained equations of motion: one front door, methods by name.

Governing equations (seed 004, eqs 8-15; kernels in :mod:`nsdyn.models.isolated._kernel`),
first-order state ``x = [q, qd]``::

    xd = f(t, x) = [qd, qdd(t, q, qd)],   M qdd = h(q, qd, u'') + R^T lam - D^T tau
    R qdd + 2 alpha beta R qd + alpha^2 R q = 0          (contacts, no uplift while lam > 0)

:func:`solve` integrates from ``t_eval[0]`` to ``t_eval[-1]`` and returns the state at every
``t_eval`` (from each method's dense output / interpolant, never by shortening steps). The methods
(``METHODS``, :mod:`nsdyn.solve.methods`) run their time loops in numba (the sparse backend of
``genalpha-lowrank`` solves each step's linear part with SuperLU from Python)::

    radau             Radau IIA order 5, adaptive (default). L-stable, stiffly accurate: for
                      the stiff arctan law (slope mu lam (2/pi) eps up to eps = 1e5) and the
                      undamped Craig-Bampton boundary modes (0.2-1.2 kHz on the office frame,
                      up to 10 kHz on the portal), which it damps instead of resolving.
    radau-generic     the same Radau with the general right-hand side at every stage (the
                      speed baseline of nsdyn bench speed).
    dopri5            explicit Dormand-Prince 5(4), adaptive. Cheap per step, but its stable
                      step is ~2e-6 s on the office frame's cb model (largest Jacobian
                      eigenvalue 1.6e6 /s, from the arctan slope at eps = 7500; its
                      boundary modes alone allow ~4e-4 s): only for non-stiff models (rigid,
                      soft arctan).
    genalpha          generalized-alpha (Chung & Hulbert 1993) on qdd = a(t, q, qd), fixed
                      dt, Newton with the analytic Jacobian; hht (Hilber-Hughes-Taylor) and
                      newmark are parameter choices from rho_inf (AMfe style).
    genalpha-lowrank  generalized-alpha with the linear part factored once and the friction
                      forces by Newton on the isolator rows (nsdyn.solve.sparse): fixed dt,
                      smooth laws; the fast method of full-order models ("auto" picks it).
    event             event-driven switch model (Coulomb friction with true stick): isolator
                      modes (slip +1/-1, stick 0) held fixed between switching instants
                      located on the Radau dense output to 1e-12 s (nsdyn.solve._kevent). The
                      reference for small systems; on Craig-Bampton frames the undamped
                      diaphragm mode makes the two isolators stick-slip against each other
                      hundreds of times (slow; reported as chattering when it piles up at
                      one instant).

Fixed steps: ``genalpha``/``hht``/``newmark`` always step with ``dt``; ``radau`` and ``dopri5``
do so with ``adaptive=False`` (no error control; for convergence studies, where Radau's Newton
iteration still stops at ``rtol``/``atol``: on a friction model the defaults cap the observed
order near 2 to 3, and rtol = 1e-10, atol = 1e-13 show its order 5). A follow-up run can
continue with ``h0=sol.h_last`` (and ``modes0=sol.modes`` for ``event``).

Error control: the scaled RMS norm of ``err / (atol + rtol |x|)`` with defaults ``rtol = 1e-6``,
``atol = 1e-8`` (m and m/s: 10 nm on displacements of centimetres to decimetres), the same
semantics as scipy's ``solve_ivp``. ``atol`` may also be a pair ``(atol_q, atol_v)`` or an
array of length 2n. The undamped kHz boundary modes of the Craig-Bampton models are rung by
every kink of a sampled ground record: a velocity atol of 1e-8 makes the L-stable Radau
method resolve part of that ringing. Earthquake runs (:func:`nsdyn.solve.transient.simulate`) use
``rtol = 1e-4, atol = (1e-8, 1e-6)`` instead (``(1e-8, 1e-7)`` for ``event``), measured to
keep the displacements, drifts and storey accelerations within 1e-4 and the base-level
acceleration within 1.1e-3 of runs at rtol 1e-8, at 5-9x fewer steps
(:mod:`nsdyn.models.isolated.tolerances`, ``examples/tolerance_study.py``).

Contact assumptions (``contact=``): ``"detect"`` (default) checks the normal forces after
every accepted step; ``lam_k <= 0`` is an uplift (``uplift="raise"`` stops with
:class:`UpliftError`; ``"warn"`` records the first instant per contact in ``Solution.uplift``
and continues). ``"bilateral"`` lets the normal forces go negative (seed 004's assumption: the
isolators hold the structure down) and only records where they do. ``"unilateral"`` integrates
lift-off, flight and landing (:mod:`nsdyn.solve._kunilateral`; methods ``event`` and ``radau``):
contact events in ``Solution.contact_events``, the contact states at the outputs in
``Solution.open_contacts``.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from nsdyn._checks import NumericalFailure, number
from nsdyn.models.isolated.bearings import ALPHA_PLAUSIBLE
from nsdyn.models.isolated.params import KernelParams
from nsdyn.solve import _kcommon as ki
from nsdyn.solve.checkpoint import held_call
from nsdyn.solve.methods import (
    METHODS,
    _tiny_problem,
    compiled,
    kernel_for,
    make_options,
    run_unilateral,
    warmup,
    warmup_kernel,
    warmup_unilateral,
)

CONTACTS = ("bilateral", "detect", "unilateral")  # contact assumptions, see the module text

__all__ = [
    "CONTACTS",
    "METHODS",
    "MESSAGES",
    "IntegrationError",
    "Solution",
    "UpliftError",
    "UpliftWarning",
    "solve",
    "warmup",
]
_ = _tiny_problem  # the no-JIT test builds its system with it (``from ... import _tiny_problem``)

SOLVE_RTOL = 1e-6  # solve()'s relative tolerance (references; runs use the scene's)
SOLVE_ATOL = 1e-8  # solve()'s absolute tolerance [m, m/s]
DEFAULT_MAX_STEPS = 2_000_000  # step attempts (accepted + rejected) before giving up
# an atol below this [m, m/s] can stall an adaptive run's steps and events near a zero
# velocity, a failure read as the model's: the Coulomb oscillator's event run (rtol 1e-8)
# reported chattering at atol 1e-13 to 1e-16 and ran at 1e-12 (said with such failures)
ATOL_STALL = 1e-12

# status -> message (advice). Fields: t, h, res, contact, method, max_steps, floor
MESSAGES = {
    ki.ST_SUCCESS: "integration reached t = {t:.6g} s",
    ki.ST_STEP_UNDERFLOW: ("step size fell below {floor:.0e} s at t = {t:.6g} s: {stiff_advice}"),
    ki.ST_MAX_STEPS: (
        "too many steps (max_steps = {max_steps}) before t = {t:.6g} s, last step {h:.3g} s: "
        "{stiff_advice}; or increase max_steps"
    ),
    ki.ST_NONFINITE: (
        "NaN or inf in the state or right-hand side at t = {t:.6g} s: check the ground record "
        "and the system matrices for NaN/inf; with a fixed step, reduce dt"
    ),
    ki.ST_SINGULAR: (
        "singular constraint system at t = {t:.6g} s: the contact and stick rows are linearly "
        "dependent (check R, D and which isolators stick)"
    ),
    ki.ST_NEWTON: (
        "Newton iteration did not converge at t = {t:.6g} s with dt = {h:.3g} s (scaled "
        "residual {res:.3g}): {newton_advice}"
    ),
    ki.ST_UPLIFT: (
        "uplift at t = {t:.6g} s: the normal force of contact {contact} reached zero, so the "
        "no-uplift assumption of the model is violated; reduce the excitation, or pass "
        "uplift='warn' (in a scene: [solver] uplift = \"warn\") to continue outside the "
        "model's domain, or integrate lift-off and landing (isolation.contact = 'unilateral')"
    ),
    ki.ST_LU_SINGULAR: (
        "singular iteration matrix at t = {t:.6g} s (step {h:.3g} s): the Jacobian is not "
        "finite or the step is degenerate; check the system matrices"
    ),
    ki.ST_EVENTS: (
        "too many switching events near t = {t:.6g} s (chattering stick-slip or contact "
        "events, or Zeno behaviour): for stick-slip, the smooth arctan law (method 'radau', "
        "law 'arctan') has no events; for lift-off and landing, try a restitution e = 0 or "
        "tighter tolerances"
    ),
}

# an arctan law from this sharpness on [s/m] turns over within 1e-6 m/s of slip: on the office
# frame Radau then underflows its step (1e6), spends its step budget (1e7) or stops at an
# uplift the switch law's event-driven run of the same scene does not have (1e8, 1e9)
EPS_SHARP = 1e6

# advice when a method runs into stiffness (step underflow / step budget)
STIFF_ADVICE = {
    "dopri5": (
        "the problem is stiff for 'dopri5' (sharp friction law or kHz boundary modes); use "
        "'radau' or lower eps"
    ),
    "radau": (
        "the right-hand side is (nearly) discontinuous for 'radau'; lower eps, or use "
        "method 'event' for the switch model"
    ),
    "event": "the modes switch faster than the stepper can follow; check the excitation",
}
# a fixed step spends (t_end - t_start) / dt steps whatever the problem: the budget runs out
# because the step is small, not because the problem is stiff
FIXED_STEP_ADVICE = (
    "the fixed step is too small for this span ((t_end - t_start) / dt steps); use a larger dt"
)


def known_method(method: str) -> None:
    """ValueError naming ``method`` unless it is "auto" or a name in :data:`METHODS`."""
    if method != "auto" and method not in METHODS:
        raise ValueError(f"method: expected 'auto' or one of {sorted(METHODS)}, got {method!r}")


class IntegrationError(NumericalFailure):
    """A time integration failed. ``t``: time reached; ``reason``: status name;
    ``solution``: the partial :class:`Solution`."""

    def __init__(self, message: str, t: float, reason: str, solution=None):
        super().__init__(message)
        self.t = t
        self.reason = reason
        self.solution = solution


class UpliftError(IntegrationError):
    """A normal force reached zero (``lam <= 0``): the no-uplift model no longer applies.
    ``contact``: index of the contact."""

    def __init__(self, message: str, t: float, contact: int, solution=None):
        super().__init__(message, t, "uplift", solution)
        self.contact = contact


class UpliftWarning(UserWarning):
    """A contact lifted off during a run with ``uplift="warn"``."""


_STATUS_NAMES = {
    ki.ST_SUCCESS: "success",
    ki.ST_STEP_UNDERFLOW: "step_underflow",
    ki.ST_MAX_STEPS: "max_steps",
    ki.ST_NONFINITE: "nonfinite",
    ki.ST_SINGULAR: "singular_constraints",
    ki.ST_NEWTON: "newton_divergence",
    ki.ST_UPLIFT: "uplift",
    ki.ST_LU_SINGULAR: "singular_iteration_matrix",
    ki.ST_EVENTS: "too_many_events",
}


@dataclass
class Solution:
    """Result of :func:`solve` (a plain record).

    Attributes
    ----------
    t : ndarray, shape (nt,)       output times reached (all of ``t_eval`` on success)
    x : ndarray, shape (nt, 2n)    states [q, qd] at ``t``
    status : int                   0 success, < 0 failure (see ``MESSAGES``)
    events : list of (t, isolator, new_mode)   switching events (method "event")
    uplift : list of (t, contact)  first uplift instant per contact
    wall_s : float                 run time excluding JIT compilation
    compile_s : float              JIT compilation/loading time spent in this call
    h_last : float                 step size to continue with (pass as ``h0`` to a follow-up
                                   run; ``dt`` for fixed-step methods)
    modes : ndarray of int, optional  isolator modes at the end (method "event"; pass as
                                   ``modes0`` to a follow-up run)
    acc_end : ndarray (n,), optional  the generalized-alpha family's algorithmic
                                   acceleration at the end (pass as ``acc0`` to a follow-up)
    contact : str                  the contact assumption of the run (``CONTACTS``)
    contact_events : list of (t, contact, kind, v_n, impulse)   unilateral runs: "lift-off"
                                   or "landing", normal velocity R_k qd before [m/s], landing
                                   impulse [N s]
    open_contacts : ndarray of int (nt, nc), optional  unilateral: 1 where a contact is open
    open_end : ndarray of int (nc,), optional   unilateral: states at the end (``open0``)
    impact_energy : float          unilateral: kinetic energy change of the landings [J] (<= 0)
    """

    t: np.ndarray
    x: np.ndarray
    status: int
    message: str
    success: bool
    method: str
    n_steps: int = 0
    n_rejected: int = 0
    nfev: int = 0
    njev: int = 0
    n_lu: int = 0
    n_events: int = 0
    events: list = field(default_factory=list)
    uplift: list = field(default_factory=list)
    wall_s: float = 0.0
    compile_s: float = 0.0
    h_last: float = 0.0
    modes: np.ndarray | None = None
    acc_end: np.ndarray | None = None
    contact: str = "detect"
    contact_events: list = field(default_factory=list)
    open_contacts: np.ndarray | None = None
    open_end: np.ndarray | None = None
    impact_energy: float = 0.0

    @property
    def q(self) -> np.ndarray:
        """Generalised displacements, shape (nt, n)."""
        return self.x[:, : self.x.shape[1] // 2]

    @property
    def qd(self) -> np.ndarray:
        """Generalised velocities, shape (nt, n)."""
        return self.x[:, self.x.shape[1] // 2 :]


# ---- front door ------------------------------------------------------------------------------


def solve(
    P: tuple,
    x0: np.ndarray,
    t_eval: np.ndarray,
    *,
    method: str = "radau",
    rtol: float = SOLVE_RTOL,
    atol: float | np.ndarray = SOLVE_ATOL,
    dt: float | None = None,
    h0: float | None = None,
    adaptive: bool = True,
    max_step: float = np.inf,
    max_steps: int = DEFAULT_MAX_STEPS,
    rho_inf: float | None = None,
    modes0=None,
    uplift: str = "raise",
    on_failure: str = "raise",
    contact: str = "detect",
    restitution: float = 0.0,
    open0=None,
    acc0=None,
) -> Solution:
    """Integrate the constrained equations of motion and sample the state at ``t_eval``.

    Parameters
    ----------
    P : tuple                    kernel parameters (``IsolatedSystem.params(ground)`` or
                                 :func:`nsdyn.models.isolated.params.pack`)
    x0 : ndarray, shape (2n,)    initial state [q, qd] at ``t_eval[0]``
    t_eval : ndarray, shape (nt,)  sorted output times; the first is the start time
    method : str                 a key of ``METHODS``, or "auto" (:mod:`nsdyn.solve.auto`)
    rtol, atol : float           error tolerances of the adaptive methods (``atol`` may be a
                                 pair (displacements, velocities) or an array of length 2n)
    dt : float                   fixed step (``genalpha``/``hht``/``newmark``, or an adaptive
                                 method with ``adaptive=False``: no error control)
    h0 : float                   first step of the adaptive methods (default: automatic)
    max_step : float             largest step of the adaptive methods
    max_steps : int              step attempts before giving up
    rho_inf : float              spectral radius at infinity of the generalized-alpha family
    modes0 : array of int        initial isolator modes for ``event`` (default: from x0)
    uplift : {"raise", "warn"}   what a normal force lam <= 0 does
    on_failure : {"raise", "return"}  raise :class:`IntegrationError` (:class:`UpliftError`)
                                 or return the partial solution with ``success = False``
    contact : {"bilateral", "detect", "unilateral"}   contact assumption (module text);
                                 ``uplift`` applies to ``"detect"`` only
    restitution : float          unilateral: Newton's coefficient e of a landing (0: plastic)
    open0 : array of int (nc,)   unilateral: initial contact states, 1 open (default closed)
    acc0 : ndarray (n,)          generalized-alpha family: the algorithmic acceleration to
                                 start from (a run's ``acc_end``; default q̈ at the start)

    Returns
    -------
    Solution
    """
    if method == "auto":  # nsdyn.solve.auto: by size, friction law and contact
        from nsdyn.solve.auto import AUTO_DT, choose_method

        kp0 = KernelParams(P)
        method = choose_method(kp0.n, kp0.law, contact)[0]
        dt = AUTO_DT if dt is None and METHODS[method].fixed_step else dt
    known_method(method)
    if on_failure not in ("raise", "return"):
        raise ValueError(f"on_failure: expected 'raise' or 'return', got {on_failure!r}")
    m = METHODS[method]
    P = KernelParams.normalised(P)
    kp = KernelParams(P)
    n = kp.n
    x0 = np.ascontiguousarray(x0, dtype=float).reshape(-1)
    if x0.size != 2 * n:
        raise ValueError(f"x0: expected length 2n = {2 * n}, got {x0.size}")
    t_eval = np.ascontiguousarray(t_eval, dtype=float).reshape(-1)
    if t_eval.size < 1 or np.any(np.diff(t_eval) < 0) or not np.all(np.isfinite(t_eval)):
        raise ValueError("t_eval: expected a non-empty, finite, non-decreasing array of times")
    if contact not in CONTACTS:
        raise ValueError(f"contact: expected one of {list(CONTACTS)}, got {contact!r}")
    restitution = number("restitution", restitution, "Newton's coefficient of a landing, "
                         "0 <= e <= 1 (0: plastic)", lambda v: 0.0 <= v <= 1.0)  # fmt: skip
    if contact != "detect":
        uplift = "warn"  # recorded, never stopping (bilateral) / handled by the kernel
    opts = make_options(
        x0, m, rtol, atol, dt, h0, adaptive, max_step, max_steps, uplift, rho_inf, modes0
    )
    carries_acc = m.kernel == "genalpha" or m.name == "genalpha-lowrank"
    if carries_acc:  # (in and out: the kernel leaves the last step's there)
        acc = np.full(n, np.nan) if acc0 is None else np.array(acc0, dtype=float).reshape(-1)
        if acc.size != n or (acc0 is not None and not np.all(np.isfinite(acc))):
            raise ValueError(f"acc0: expected {n} finite accelerations, got {acc0!r}")
        opts = replace(opts, acc=acc)
    elif acc0 is not None:
        raise ValueError(f"acc0: the generalized-alpha family's; method {method!r} has none")
    compile_s = 0.0
    X = np.zeros((t_eval.size, 2 * n))
    upl_t = np.full(kp.n_contacts, np.nan)
    extra = None
    if contact == "unilateral":
        compile_s = warmup_unilateral()
        t_start = time.perf_counter()
        stats, rinfo, events, modes, extra = held_call(lambda: run_unilateral(
            P, x0, t_eval, opts, X, upl_t, method, float(restitution), open0))  # fmt: skip
    else:
        kname = kernel_for(method, P)
        if not compiled(kname):
            compile_s = warmup_kernel(kname)
        t_start = time.perf_counter()
        stats, rinfo, events, modes = held_call(lambda: m.run(P, x0, t_eval, opts, X, upl_t))
    wall = time.perf_counter() - t_start
    sol = _finish(
        m,
        opts,
        kp.law,
        t_eval,
        X,
        upl_t,
        stats,
        rinfo,
        events,
        modes,
        wall,
        compile_s,
        on_failure,
        warn_uplift=contact == "detect",
        extra=extra,
        eps=kp.eps,
        alpha=kp.alpha if contact == "unilateral" else None,
    )
    sol.contact = contact
    if carries_acc and np.all(np.isfinite(opts.acc)):  # (what the kernel left: it ran)
        sol.acc_end = opts.acc
    return sol


def _finish(
    m,
    opts,
    law,
    t_eval,
    X,
    upl_t,
    stats,
    rinfo,
    events,
    modes,
    wall,
    compile_s,
    on_failure,
    warn_uplift=True,
    extra=None,
    eps=None,
    alpha=None,
):
    status = int(stats[ki.S_STATUS])
    nout = int(stats[ki.S_NOUT])
    uplift_list = sorted((float(tk), k) for k, tk in enumerate(upl_t) if np.isfinite(tk))
    fields = dict(
        t=float(rinfo[ki.R_T]),
        h=float(rinfo[ki.R_H]),
        res=float(rinfo[ki.R_RES]),
        contact=int(stats[ki.S_CONTACT]),
        method=m.name,
        max_steps=opts.max_steps,
        floor=ki.MIN_STEP,
        stiff_advice=STIFF_ADVICE.get(m.name, FIXED_STEP_ADVICE),
        newton_advice="use a smaller dt, or the adaptive implicit method 'radau'",
    )
    if law == "switch" and m.fixed_step:  # (a smaller dt fails alike: 5 ms to 0.1 ms, 1.4 s)
        fields["newton_advice"] = ("the switch law's stick is a set-valued force, which a fixed "
                                   "step passes over at a velocity reversal (a smaller dt does "
                                   "not help: 5 ms to 0.1 ms stop alike on the default scene): "
                                   "use method 'event' (its stick exact) or 'radau'")  # fmt: skip
    small = status == ki.ST_MAX_STEPS and opts.max_steps < DEFAULT_MAX_STEPS  # a given budget
    if small:
        fields["stiff_advice"] = (f"the budget given is below the default {DEFAULT_MAX_STEPS}; "
                                  "raise it (if a larger one runs out too: "
                                  f"{fields['stiff_advice']})")  # fmt: skip
    if alpha is not None and alpha > ALPHA_PLAUSIBLE:  # (the cause to rule out first)
        fields["stiff_advice"] = (
            f"the contacts' Baumgarte gain alpha = {alpha:g} 1/s, above "
            f"{ALPHA_PLAUSIBLE:g}, stiffens the lifting rows: lower it "
            f"(default 2 pi) first; else {fields['stiff_advice']}"
        )
    message = MESSAGES[status].format(**fields)
    if small:
        message = message.removesuffix("; or increase max_steps")
    if status == ki.ST_UPLIFT and law == "arctan" and eps is not None and eps >= EPS_SHARP:
        message += (
            f". With eps = {eps:.3g} s/m the friction turns over within {1.0 / eps:.1g} m/s of "
            "slip, finer than the steps resolve: a normal force evaluated across such a switch "
            "can dip to zero without the structure lifting off. Confirm with the switch law "
            "(law 'switch', method 'event'; nsdyn run --friction switch --method event) or a "
            "smaller eps"
        )
    elif status == ki.ST_UPLIFT and m.fixed_step:
        message += (
            f". A fixed step of {fields['h']:.3g} s that does not resolve the response can also "
            "dip a normal force to zero: confirm the uplift at half the step, or with an "
            "adaptive method ('radau')"
        )
    elif status == ki.ST_UPLIFT and m.name == "dopri5":  # (α = 1e6: "reduce the excitation")
        message += (
            ". An explicit step past its stability limit (a stiff model, or large Baumgarte "
            "gains alpha, beta) can also dip a normal force to zero: confirm the uplift with "
            "'radau'"
        )
    if status == ki.ST_NEWTON and law == "arctan" and m.fixed_step and eps:
        message += (
            f"; the arctan law turns the friction over within {1.0 / eps:.2g} m/s of slip "
            f"(eps = {eps:.3g} s/m), which a step of {fields['h']:.3g} s passes in one: a smaller "
            "eps (a softer law) or dt lets Newton follow it"
        )
    stalled = (ki.ST_STEP_UNDERFLOW, ki.ST_MAX_STEPS, ki.ST_EVENTS)
    if status in stalled and not m.fixed_step and opts.atol.min() < ATOL_STALL:
        message += (
            f"; atol = {opts.atol.min():.3g} is far below the states' size: an error test this "
            "tight can stall steps and events near a zero velocity (a run failing so at 1e-13 "
            f"runs at {ATOL_STALL:g}); retry with a larger atol before reading this as the model's"
        )
    if status == ki.ST_STEP_UNDERFLOW and law == "switch" and m.name != "event":
        message += (
            "; the switch law is discontinuous (stick/slip decided inside the right-hand "
            "side): use method 'event'"
        )
    sol = Solution(
        t=t_eval[:nout].copy(),
        x=X[:nout],
        status=status,
        message=message,
        success=status == ki.ST_SUCCESS,
        method=m.name,
        n_steps=int(stats[ki.S_NSTEP]),
        n_rejected=int(stats[ki.S_NREJ]),
        nfev=int(stats[ki.S_NFEV]),
        njev=int(stats[ki.S_NJEV]),
        n_lu=int(stats[ki.S_NLU]),
        n_events=int(stats[ki.S_NEVENT]),
        events=events,
        uplift=uplift_list,
        wall_s=wall,
        compile_s=compile_s,
        h_last=float(rinfo[ki.R_HNEXT]),
        modes=modes,
    )
    if extra is not None:
        sol.contact_events = extra.contact_events
        sol.open_contacts = extra.open_out[:nout]
        sol.open_end = extra.open_end
        sol.impact_energy = extra.impact_energy
    if uplift_list and opts.uplift_mode == ki.UPLIFT_WARN and warn_uplift:
        where = ", ".join(f"contact {k} at t = {tk:.6g} s" for tk, k in uplift_list)
        warnings.warn(
            f"uplift ({where}): normal forces reached zero, outside the no-uplift model",
            UpliftWarning,
            stacklevel=3,
        )
    if status != ki.ST_SUCCESS and on_failure == "raise":
        if status == ki.ST_UPLIFT:
            raise UpliftError(message, fields["t"], fields["contact"], sol)
        raise IntegrationError(message, fields["t"], _STATUS_NAMES[status], sol)
    return sol
