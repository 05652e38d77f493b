"""Time integration of the constrained equations of motion: one front door, methods by name.

Governing equations (seed 004, eqs 8-15; kernels in :mod:`nsdyn._ksystem`), first-order state
``x = [q, qd]``::

    xd = f(t, x) = [qd, qdd(t, q, qd)],   M qdd = h(q, qd, u'') + R^T lam - D^T tau
    R qdd + 2 alpha beta R qd + alpha^2 R q = 0          (contacts, no uplift while lam > 0)

:func:`solve` integrates from ``t_eval[0]`` to ``t_eval[-1]`` and returns the state at every
``t_eval`` (from each method's dense output / interpolant, never by shortening steps). The methods
(``METHODS``) each run their whole time loop in numba:

============  ======================================================================================
``radau``     Radau IIA order 5, adaptive (default). L-stable, stiffly accurate: for the stiff
              arctan law (slope mu lam (2/pi) eps up to eps = 1e5) and the undamped kHz
              Craig-Bampton boundary modes, which it damps instead of resolving.
``dopri5``    explicit Dormand-Prince 5(4), adaptive. Cheap per step, but its stable step is
              ~1e-5 s on the isolated frames: only for non-stiff models (rigid, soft arctan).
``genalpha``  generalized-alpha (Chung & Hulbert 1993) on ``qdd = a(t, q, qd)``, fixed ``dt``,
              Newton with the analytic Jacobian; ``hht`` (Hilber-Hughes-Taylor) and ``newmark``
              are parameter choices from ``rho_inf`` (AMfe style).
``event``     event-driven switch model (Coulomb friction with true stick): isolator modes (slip
              +1/-1, stick 0) held fixed between switching instants located on the Radau dense
              output to ~1e-10 s (:mod:`nsdyn._kevent`). The reference for small systems; on
              Craig-Bampton frames the undamped kHz diaphragm mode makes the two isolators
              stick-slip against each other hundreds of times (slow; reported as chattering
              when it piles up at one instant).
============  ======================================================================================

Fixed steps: ``genalpha``/``hht``/``newmark`` always step with ``dt``; ``radau`` and ``dopri5``
do so with ``adaptive=False`` (no error control; for convergence studies). A follow-up run can
continue with ``h0=sol.h_last`` (and ``modes0=sol.modes`` for ``event``).

Error control: the scaled RMS norm of ``err / (atol + rtol |x|)`` with defaults ``rtol = 1e-6``,
``atol = 1e-8`` (m and m/s: 10 nm on displacements of centimetres to decimetres), the same
semantics as scipy's ``solve_ivp``. ``atol`` may also be a pair ``(atol_q, atol_v)`` or an
array of length 2n. The undamped kHz boundary modes of the Craig-Bampton models are rung by
every kink of a sampled ground record: a velocity atol of 1e-8 makes the L-stable Radau
method resolve part of that ringing. Earthquake runs (:func:`nsdyn.transient.simulate`) use
``rtol = 1e-4, atol = (1e-8, 1e-6)`` instead, measured to keep every response output within
1e-3 of a much tighter run at ~7x fewer steps (see :mod:`nsdyn.transient`).

Contact monitoring: every accepted step checks the normal forces; ``lam_k <= 0`` is an uplift
(``uplift="raise"`` stops with :class:`UpliftError`; ``"warn"`` records the first instant per
contact in ``Solution.uplift`` and continues).
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from . import _kdopri, _kevent, _kgenalpha, _kradau
from . import _kintegrate as ki
from . import _ksystem as ks
from ._params import Harmonic, pack, with_law

__all__ = [
    "METHODS",
    "MESSAGES",
    "IntegrationError",
    "Solution",
    "UpliftError",
    "UpliftWarning",
    "solve",
    "warmup",
]

DEFAULT_RTOL = 1e-6  # relative tolerance of the adaptive methods
DEFAULT_ATOL = 1e-8  # absolute tolerance [m, m/s]
DEFAULT_MAX_STEPS = 2_000_000  # step attempts (accepted + rejected) before giving up
MAX_EVENTS = 100_000  # switching events recorded by method "event"
EVENT_STEPS_PER_PERIOD = 8  # "event": largest step = 1/8 period of a harmonic excitation
EVENT_SAMPLES_PER_STEP = 4  # "event": largest step = 4 samples of a ground record
# default spectral radius at infinity of the generalized-alpha family (numerical damping of
# the unresolved kHz boundary modes: each step multiplies them by about rho_inf)
DEFAULT_RHO_INF = {"genalpha": 0.8, "hht": 0.8, "newmark": 1.0}

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
        "residual {res:.3g}): use a smaller dt, or the adaptive implicit method 'radau'"
    ),
    ki.ST_UPLIFT: (
        "uplift at t = {t:.6g} s: the normal force of contact {contact} reached zero, so the "
        "no-uplift assumption of the model is violated; reduce the excitation or pass "
        "uplift='warn' to continue outside the model's domain"
    ),
    ki.ST_LU_SINGULAR: (
        "singular iteration matrix at t = {t:.6g} s (step {h:.3g} s): the Jacobian is not "
        "finite or the step is degenerate; check the system matrices"
    ),
    ki.ST_EVENTS: (
        "too many switching events near t = {t:.6g} s (stick-slip chattering or Zeno "
        "behaviour): use the switch law (method 'radau') or the arctan law for this excitation"
    ),
}

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


class IntegrationError(RuntimeError):
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

    @property
    def q(self) -> np.ndarray:
        """Generalised displacements, shape (nt, n)."""
        return self.x[:, : self.x.shape[1] // 2]

    @property
    def qd(self) -> np.ndarray:
        """Generalised velocities, shape (nt, n)."""
        return self.x[:, self.x.shape[1] // 2 :]


@dataclass(frozen=True)
class _Options:
    rtol: float
    atol: np.ndarray
    dt: float
    h0: float
    adaptive: bool
    max_step: float
    max_steps: int
    uplift_mode: int
    rho_inf: float | None
    modes0: np.ndarray | None


@dataclass(frozen=True)
class Method:
    """An integration method:
    ``run(P, x0, t_eval, opts, X, upl_t) -> (stats, rinfo, events, modes)``."""

    name: str
    kernel: str  # warmup key of the numba kernel it uses
    fixed_step: bool  # needs dt
    run: Callable


# ---- runners -------------------------------------------------------------------------------


def _run_dopri5(P, x0, t_eval, o: _Options, X, upl_t):
    fixed = not o.adaptive
    h0 = o.dt if fixed else o.h0
    stats, rinfo = _kdopri.dopri5(
        P, x0, t_eval, o.atol, o.rtol, h0, o.max_step, o.max_steps, fixed, o.uplift_mode, X, upl_t
    )
    return stats, rinfo, [], None


def _run_radau(P, x0, t_eval, o: _Options, X, upl_t):
    fixed = not o.adaptive
    h0 = o.dt if fixed else o.h0
    stats, rinfo = _kradau.radau(
        P, x0, t_eval, o.atol, o.rtol, h0, o.max_step, o.max_steps, fixed, o.uplift_mode, X, upl_t
    )
    return stats, rinfo, [], None


def _genalpha_runner(name, family):
    def run(P, x0, t_eval, o: _Options, X, upl_t):
        rho = DEFAULT_RHO_INF[name] if o.rho_inf is None else o.rho_inf
        am, af, beta, gamma = _kgenalpha.parameters(family, rho)
        stats, rinfo = _kgenalpha.genalpha(
            P,
            x0,
            t_eval,
            o.atol,
            o.rtol,
            o.dt,
            am,
            af,
            beta,
            gamma,
            o.max_steps,
            o.uplift_mode,
            X,
            upl_t,
        )
        return stats, rinfo, [], None

    return run


def _event_max_step(P) -> float:
    """Step cap of the event method from the excitation: a stuck structure has no local error,
    so only this cap makes the scan of the stick forces follow the ground motion."""
    gp = P[ks.I_GPAR]
    if P[ks.I_IPAR][ks.K_GROUND] == ks.GROUND_HARMONIC:
        f = max(abs(gp[ks.G_FH]) if gp[ks.G_AH] else 0.0, abs(gp[ks.G_FV]) if gp[ks.G_AV] else 0.0)
        return 1.0 / (EVENT_STEPS_PER_PERIOD * f) if f > 0 else np.inf
    if P[ks.I_AH].size:
        return EVENT_SAMPLES_PER_STEP * gp[ks.G_DT]
    return np.inf


def _run_event(P, x0, t_eval, o: _Options, X, upl_t):
    ni = P[ks.I_D].shape[0]
    if o.modes0 is None:
        modes0 = np.full(ni, _kevent.MODE_AUTO, dtype=np.int64)
    else:
        modes0 = np.ascontiguousarray(o.modes0, dtype=np.int64).reshape(-1)
        if modes0.size != ni or not np.all(np.isin(modes0, (-1, 0, 1))):
            raise ValueError(f"modes0: expected {ni} values in (-1, 0, 1), got {o.modes0}")
    Pm = with_law(P, "modes", modes0)  # private copy of the live mode array
    max_step = min(o.max_step, _event_max_step(P))
    ev_t = np.zeros(MAX_EVENTS)
    ev_i = np.zeros(MAX_EVENTS, dtype=np.int64)
    ev_m = np.zeros(MAX_EVENTS, dtype=np.int64)
    stats, rinfo = _kevent.event_switch(
        Pm,
        x0,
        t_eval,
        o.atol,
        o.rtol,
        o.h0,
        max_step,
        o.max_steps,
        modes0,
        o.uplift_mode,
        X,
        upl_t,
        ev_t,
        ev_i,
        ev_m,
    )
    ne = int(stats[ki.S_NEVENT])
    events = [(float(ev_t[k]), int(ev_i[k]), int(ev_m[k])) for k in range(ne)]
    return stats, rinfo, events, Pm[ks.I_MODE].copy()


METHODS: dict[str, Method] = {
    "radau": Method("radau", "radau", False, _run_radau),
    "dopri5": Method("dopri5", "dopri5", False, _run_dopri5),
    "event": Method("event", "event", False, _run_event),
    "genalpha": Method(
        "genalpha", "genalpha", True, _genalpha_runner("genalpha", _kgenalpha.FAMILY_GENALPHA)
    ),
    "hht": Method("hht", "genalpha", True, _genalpha_runner("hht", _kgenalpha.FAMILY_HHT)),
    "newmark": Method(
        "newmark", "genalpha", True, _genalpha_runner("newmark", _kgenalpha.FAMILY_NEWMARK)
    ),
}


# ---- compilation -----------------------------------------------------------------------------

_COMPILED: dict[str, float] = {}


def _tiny_problem():
    """A two-dof Coulomb block (x slides on a contact at y) under harmonic ground motion."""
    M = np.eye(2)
    K = np.diag([4.0, 0.0])
    P = pack(
        M,
        np.zeros((2, 2)),
        K,
        np.eye(2),
        R=[[0.0, 1.0]],
        D=[[1.0, 0.0]],
        mu=0.2,
        lam_static=[9.81],
        law="arctan",
        eps=50.0,
        ground=Harmonic(1.0, 1.0),
    )
    x0 = np.array([0.1, 0.0, 0.0, 0.0])
    return P, x0


def warmup(methods=None) -> dict[str, float]:
    """Compile (or load from numba's cache) the integrator kernels on a tiny system.

    Parameters
    ----------
    methods : iterable of str, optional     method names (default: every kernel)

    Returns
    -------
    dict kernel name -> seconds spent now (0.0 when it was already compiled in this process).
    """
    names = list(METHODS) if methods is None else list(methods)
    kernels = {}
    for name in names:
        m = METHODS[name]
        kernels.setdefault(m.kernel, m)
    out = {}
    P, x0 = _tiny_problem()
    t_eval = np.linspace(0.0, 0.02, 3)
    for kname, m in kernels.items():
        if kname in _COMPILED:
            out[kname] = 0.0
            continue
        t0 = time.perf_counter()
        opts = _make_options(
            P,
            x0,
            m,
            1e-6,
            1e-8,
            1e-3 if m.fixed_step else None,
            None,
            True,
            np.inf,
            1000,
            "warn",
            None,
            None,
        )
        X = np.zeros((t_eval.size, x0.size))
        upl_t = np.full(P[ks.I_R].shape[0], np.nan)
        m.run(P, x0, t_eval, opts, X, upl_t)
        _COMPILED[kname] = time.perf_counter() - t0
        out[kname] = _COMPILED[kname]
    return out


# ---- front door ------------------------------------------------------------------------------


def _make_options(
    P, x0, method, rtol, atol, dt, h0, adaptive, max_step, max_steps, uplift, rho_inf, modes0
):
    n2 = x0.size
    a = np.asarray(atol, dtype=float)
    if a.ndim == 0:
        atol_arr = np.full(n2, float(a))
    elif a.shape == (2,):  # (displacements, velocities)
        atol_arr = np.repeat(a, n2 // 2)
    elif a.shape == (n2,):
        atol_arr = a.copy()
    else:
        raise ValueError(
            f"atol: expected a number, a pair (atol_q, atol_v) or {n2} values, got shape {a.shape}"
        )
    if not (rtol > 0 and np.all(atol_arr >= 0)) or not np.all(np.isfinite(atol_arr)):
        raise ValueError(f"tolerances: expected rtol > 0 and atol >= 0, got {rtol}, {atol}")
    if uplift not in ("raise", "warn"):
        raise ValueError(f"uplift: expected 'raise' or 'warn', got {uplift!r}")
    if (method.fixed_step or not adaptive) and (dt is None or not dt > 0):
        raise ValueError(
            f"method {method.name!r} with a fixed step needs dt > 0 (e.g. dt=1e-3), got {dt}"
        )
    if dt is not None and adaptive and not method.fixed_step:
        raise ValueError(
            f"dt is the fixed step of fixed-step runs; for the adaptive {method.name!r} pass "
            "adaptive=False to step with dt, or h0= for the first step"
        )
    if method.name == "event" and not adaptive:
        raise ValueError("method 'event' is adaptive only (its steps land on the events)")
    if not max_steps >= 1:
        raise ValueError(f"max_steps: expected >= 1, got {max_steps}")
    if not max_step > 0:
        raise ValueError(f"max_step: expected > 0, got {max_step}")
    return _Options(
        rtol=float(rtol),
        atol=atol_arr,
        dt=float(dt) if dt is not None else 0.0,
        h0=float(h0) if h0 is not None else 0.0,
        adaptive=bool(adaptive),
        max_step=float(max_step),
        max_steps=int(max_steps),
        uplift_mode=ki.UPLIFT_RAISE if uplift == "raise" else ki.UPLIFT_WARN,
        rho_inf=None if rho_inf is None else float(rho_inf),
        modes0=None if modes0 is None else np.asarray(modes0, dtype=np.int64),
    )


def _normalise_params(P) -> tuple:
    if not isinstance(P, tuple) or len(P) != ks.N_P:
        raise TypeError(
            f"P: expected the kernel parameter tuple of nsdyn._params.pack (length "
            f"{ks.N_P}), got {type(P).__name__}"
        )
    out = []
    for k, a in enumerate(P):
        dtype = np.int64 if k in (ks.I_IPAR, ks.I_MODE) else float
        out.append(np.ascontiguousarray(a, dtype=dtype))
    return tuple(out)


def solve(
    P: tuple,
    x0: np.ndarray,
    t_eval: np.ndarray,
    *,
    method: str = "radau",
    rtol: float = DEFAULT_RTOL,
    atol: float | np.ndarray = DEFAULT_ATOL,
    dt: float | None = None,
    h0: float | None = None,
    adaptive: bool = True,
    max_step: float = np.inf,
    max_steps: int = DEFAULT_MAX_STEPS,
    rho_inf: float | None = None,
    modes0=None,
    uplift: str = "raise",
    on_failure: str = "raise",
) -> Solution:
    """Integrate the constrained equations of motion and sample the state at ``t_eval``.

    Parameters
    ----------
    P : tuple                    kernel parameters (``IsolatedSystem.params(ground)`` or
                                 :func:`nsdyn._params.pack`)
    x0 : ndarray, shape (2n,)    initial state [q, qd] at ``t_eval[0]``
    t_eval : ndarray, shape (nt,)  sorted output times; the first is the start time
    method : str                 a key of ``METHODS``
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

    Returns
    -------
    Solution
    """
    if method not in METHODS:
        raise ValueError(f"method: expected one of {sorted(METHODS)}, got {method!r}")
    if on_failure not in ("raise", "return"):
        raise ValueError(f"on_failure: expected 'raise' or 'return', got {on_failure!r}")
    m = METHODS[method]
    P = _normalise_params(P)
    n = P[ks.I_MIK].shape[0]
    x0 = np.ascontiguousarray(x0, dtype=float).reshape(-1)
    if x0.size != 2 * n:
        raise ValueError(f"x0: expected length 2n = {2 * n}, got {x0.size}")
    t_eval = np.ascontiguousarray(t_eval, dtype=float).reshape(-1)
    if t_eval.size < 1 or np.any(np.diff(t_eval) < 0) or not np.all(np.isfinite(t_eval)):
        raise ValueError("t_eval: expected a non-empty, finite, non-decreasing array of times")
    opts = _make_options(
        P, x0, m, rtol, atol, dt, h0, adaptive, max_step, max_steps, uplift, rho_inf, modes0
    )
    compile_s = 0.0
    if m.kernel not in _COMPILED:
        compile_s = warmup([method])[m.kernel]
    nc = P[ks.I_R].shape[0]
    X = np.zeros((t_eval.size, 2 * n))
    upl_t = np.full(nc, np.nan)
    t_start = time.perf_counter()
    stats, rinfo, events, modes = m.run(P, x0, t_eval, opts, X, upl_t)
    wall = time.perf_counter() - t_start
    law = int(P[ks.I_IPAR][ks.K_LAW])
    return _finish(
        m, opts, law, t_eval, X, upl_t, stats, rinfo, events, modes, wall, compile_s, on_failure
    )


def _finish(
    m, opts, law, t_eval, X, upl_t, stats, rinfo, events, modes, wall, compile_s, on_failure
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
        stiff_advice=STIFF_ADVICE.get(m.name, "the problem is too stiff for this fixed step"),
    )
    message = MESSAGES[status].format(**fields)
    if (
        status in (ki.ST_NEWTON, ki.ST_STEP_UNDERFLOW)
        and law == ks.LAW_SWITCH
        and m.name != "event"
    ):
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
    if uplift_list and opts.uplift_mode == ki.UPLIFT_WARN:
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
