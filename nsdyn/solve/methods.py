"""The integration methods by name: option checking, one runner per method, compilation.

Every method integrates the first-order system of the isolated frame (seed 004, eqs 8-15)::

    xd = f(t, x) = [qd, qdd(t, q, qd)],   x = [q, qd]

with its whole time loop in a numba kernel (:mod:`nsdyn.solve._kradau`,
:mod:`nsdyn.solve._kdopri`, :mod:`nsdyn.solve._kgenalpha`, :mod:`nsdyn.solve._kevent`). A
runner turns the checked options into that kernel's arguments; :data:`METHODS` maps each name
to its runner, and :func:`warmup` compiles (or loads) the kernels on a tiny system. The front
door is :func:`nsdyn.solve.integrate.solve`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from nsdyn._checks import number, rel_tol, whole
from nsdyn._lazy import LazyModule
from nsdyn._numba_cache import Helper, compiling, dispatcher_cached, helper_enabled
from nsdyn.ground.excitation import Harmonic
from nsdyn.models.isolated import _kernel as ks
from nsdyn.models.isolated.params import KernelParams, pack, with_law, with_open
from nsdyn.solve import _kcommon as ki
from nsdyn.solve import _kflat, _kradau

# the other methods' kernel modules, imported when a run of one uses them (each ~50 numba
# dispatchers made at import would be most of nsdyn's share of a cached default run's start)
_kdopri = LazyModule("nsdyn.solve._kdopri")
_kevent = LazyModule("nsdyn.solve._kevent")
_kgenalpha = LazyModule("nsdyn.solve._kgenalpha")
_kunilateral = LazyModule("nsdyn.solve._kunilateral")

__all__ = [
    "METHODS",
    "Method",
    "flat_applies",
    "is_cached",
    "kernel_for",
    "metrics_for",
    "make_options",
    "warmup",
    "warmup_kernel",
    "warmup_metrics",
    "run_unilateral",
    "warmup_unilateral",
]

MAX_EVENTS = 100_000  # switching events recorded by method "event"
EVENT_STEPS_PER_PERIOD = 8  # "event": largest step = 1/8 period of a harmonic excitation
EVENT_SAMPLES_PER_STEP = 4  # "event": largest step = 4 samples of a ground record
# default spectral radius at infinity of the generalized-alpha family (numerical damping of
# the unresolved kHz boundary modes: each step multiplies them by about rho_inf)
DEFAULT_RHO_INF = {"genalpha": 0.8, "hht": 0.8, "newmark": 1.0}


@dataclass(frozen=True)
class Options:
    """Checked options of one run (see :func:`make_options`)."""

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
    acc: np.ndarray | None = None  # generalized-alpha: its acceleration in and out (acc0)


@dataclass(frozen=True)
class Method:
    """An integration method:
    ``run(P, x0, t_eval, opts, X, upl_t) -> (stats, rinfo, events, modes)``."""

    name: str
    kernel: str  # warmup key of the numba kernel it uses
    fixed_step: bool  # needs dt
    run: Callable


def make_options(
    x0, method, rtol, atol, dt, h0, adaptive, max_step, max_steps, uplift, rho_inf, modes0
) -> Options:
    """Check the options of a run with ``method`` from state ``x0`` (length 2n). ``atol`` may
    be a number, a pair (atol_q, atol_v) or 2n values. ValueError naming the option and form."""
    n2 = x0.size
    if isinstance(rtol, str | bool) or isinstance(atol, str | bool):
        raise TypeError(f"rtol, atol: expected numbers, got {rtol!r}, {atol!r}")
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
    rel_tol("rtol", rtol)
    fixed = method.fixed_step or not adaptive  # (unread; adaptive from rest: rtol |x| = 0)
    if not (np.all(atol_arr >= 0 if fixed else atol_arr > 0) and np.all(np.isfinite(atol_arr))):
        raise ValueError(f"atol: expected values {'>=' if fixed else '>'} 0, got {atol}")
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
    whole("max_steps", max_steps, 1, "a whole number of step attempts >= 1")
    number("max_step", max_step, "a largest step > 0 [s]", lambda v: v > 0, finite=False)
    if h0 is not None:  # (0: automatic, as None)
        number("h0", h0, "a first step >= 0 [s] (0 or None: automatic)", lambda v: v >= 0)
    return Options(
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


# ---- runners -------------------------------------------------------------------------------


def _one_step_runner(kernel, *extra):
    """Runner of a one-step method with error control (dopri5, radau); ``adaptive=False``
    steps with ``dt`` instead. ``extra``: further kernel arguments (radau: ``flat``)."""

    def run(P, x0, t_eval, o: Options, X, upl_t):
        fixed = not o.adaptive
        h0 = o.dt if fixed else o.h0
        args = (P, x0, t_eval, o.atol, o.rtol, h0, o.max_step, o.max_steps, fixed, o.uplift_mode)
        stats, rinfo = kernel(*args, X, upl_t, *extra)
        return stats, rinfo, [], None

    return run


def _genalpha_runner(name, family: str):
    """The runner of the generalized-alpha family named ``family`` (``_kgenalpha``'s
    ``FAMILY_*`` constant of that name)."""

    def run(P, x0, t_eval, o: Options, X, upl_t):
        rho = DEFAULT_RHO_INF[name] if o.rho_inf is None else o.rho_inf
        coef = _kgenalpha.parameters(getattr(_kgenalpha, family), rho)
        stats, rinfo = _kgenalpha.genalpha(
            P, x0, t_eval, o.atol, o.rtol, o.dt, coef, o.max_steps, o.uplift_mode, X, upl_t, o.acc
        )
        return stats, rinfo, [], None

    return run


def _event_max_step(kp: KernelParams) -> float:
    """Step cap of the event method from the excitation: a stuck structure has no local error,
    so only this cap makes the scan of the stick forces follow the ground motion."""
    g = kp.ground
    if kp.harmonic:
        f = max(abs(g["f_hor"]) if g["A_hor"] else 0.0, abs(g["f_ver"]) if g["A_ver"] else 0.0)
        return 1.0 / (EVENT_STEPS_PER_PERIOD * f) if f > 0 else np.inf
    if g["n_samples"]:
        return EVENT_SAMPLES_PER_STEP * g["dt"]
    return np.inf


def _run_event(P, x0, t_eval, o: Options, X, upl_t):
    kp = KernelParams(P)
    ni = kp.n_isolators
    if o.modes0 is None:
        modes0 = np.full(ni, _kevent.MODE_AUTO, dtype=np.int64)
    else:
        modes0 = np.ascontiguousarray(o.modes0, dtype=np.int64).reshape(-1)
        if modes0.size != ni or not np.all(np.isin(modes0, (-1, 0, 1))):
            raise ValueError(f"modes0: expected {ni} values in (-1, 0, 1), got {o.modes0}")
    Pm = with_law(P, "modes", modes0)  # private copy of the live mode array
    max_step = min(o.max_step, _event_max_step(kp))
    log = (np.zeros(MAX_EVENTS), np.zeros(MAX_EVENTS, dtype=np.int64),
           np.zeros(MAX_EVENTS, dtype=np.int64))  # fmt: skip
    stats, rinfo = _kunilateral.event_switch(
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
        log,
    )
    ev_t, ev_i, ev_m = log
    events = [(float(ev_t[k]), int(ev_i[k]), int(ev_m[k])) for k in range(int(stats[ki.S_NEVENT]))]
    return stats, rinfo, events, KernelParams(Pm).modes.copy()


FLAT_LAWS = ("arctan", "none")  # the smooth laws the flat right-hand side serves


def flat_applies(P) -> bool:
    """True when the flat right-hand side (:mod:`nsdyn.solve._kflat`) serves ``P``: a smooth
    law (:data:`FLAT_LAWS`) with every contact closed."""
    return KernelParams(P).law in FLAT_LAWS and not np.any(P[ks.I_OPEN])


def _run_radau(P, x0, t_eval, o: Options, X, upl_t):
    """Radau through the flat-only run loop where it applies (it never compiles the general
    kernel), else, or where it stops on a singular ``G``, through the general one."""
    fixed, h0 = (False, o.h0) if o.adaptive else (True, o.dt)
    args = (P, x0, t_eval, o.atol, o.rtol, h0, o.max_step, o.max_steps, fixed, o.uplift_mode)
    if flat_applies(P):
        from nsdyn.solve.compile_split import radau_flat  # (it imports this module)

        stats, rinfo = radau_flat(*args, X, upl_t)
        if stats[ki.S_STATUS] != ki.ST_SINGULAR:
            return stats, rinfo, [], None
        X[:] = 0.0  # again from the start, with the general kernel's minimum-norm split
        upl_t[:] = np.nan
    stats, rinfo = _kradau.radau(*args, X, upl_t, True)
    return stats, rinfo, [], None


# the integration methods by the names `method=` and `--method` take (besides "auto")
METHODS: dict[str, Method] = {
    # default; kernel "radau" is the flat-only loop, the general one is "radau-general"
    "radau": Method("radau", "radau", False, _run_radau),
    # the same Radau with the general right-hand side at every stage (the speed baseline)
    "radau-generic": Method(
        "radau-generic", "radau-general", False, _one_step_runner(_kradau.radau, False)
    ),
    "dopri5": Method("dopri5", "dopri5", False, _one_step_runner(lambda *a: _kdopri.dopri5(*a))),
    "event": Method("event", "event", False, _run_event),
    "genalpha": Method(
        "genalpha", "genalpha", True, _genalpha_runner("genalpha", "FAMILY_GENALPHA")
    ),
    "hht": Method("hht", "genalpha", True, _genalpha_runner("hht", "FAMILY_HHT")),
    "newmark": Method("newmark", "genalpha", True, _genalpha_runner("newmark", "FAMILY_NEWMARK")),
}


# ---- compilation -----------------------------------------------------------------------------

_COMPILED: dict[str, float] = {}  # kernel name -> seconds its compilation took


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


def compiled(kernel: str) -> bool:
    """True when the numba kernel ``kernel`` (a ``Method.kernel``) is ready in this process."""
    return kernel in _COMPILED


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
    return {kname: _warm(kname, m) for kname, m in kernels.items()}


def kernel_for(method: str, P=None, *, flat: bool | None = None) -> str:
    """The kernel a run of ``method`` uses (``Method.kernel``, except for a Radau run the flat
    kernel cannot serve: "radau-general"); ``flat`` (default :func:`flat_applies` of ``P``)
    says whether it can."""
    m = METHODS[method]
    if flat is None:
        flat = flat_applies(P)
    if m.kernel == "radau" and not flat:
        return "radau-general"
    return m.kernel


def metrics_for(kernel: str) -> str:
    """The metrics kernels a run with ``kernel`` evaluates its history with: the flat ones
    ("metrics") after the flat Radau loop, which compiled the flat right-hand side; else the
    general ones ("metrics-general"), which call the system kernel by address (the other
    loops compile it, or call it)."""
    return "metrics" if kernel == "radau" else "metrics-general"


def warmup_kernel(kernel: str, metrics: str | None = None) -> float:
    """Compile (or load) one kernel by name and, with ``metrics`` ("metrics" or
    "metrics-general", see :func:`warmup_metrics`), the response metrics' kernels too.
    Seconds spent now (~0 when already done).

    A first compilation uses a second process where one may
    (:func:`nsdyn._numba_cache.helper_enabled`): numba compiles on one thread per process, so
    the helper compiles part of the kernels into numba's on-disk cache while this process
    compiles the rest and then loads the helper's. The loops whose callees are called by
    address (:data:`_SPLIT`: the default Radau loop, the event loop, generalized-alpha;
    genalpha-lowrank, whose loop needs no system kernel compiled) are
    split between the two (:mod:`nsdyn.solve.compile_split`), the metrics going to the process
    with the shorter share; for the other kernels the helper takes the flat metrics (the
    general ones call the system kernel by address, which the loop compiles: they follow it
    here). What the helper does not deliver, this process compiles itself: the kernels are
    the same either way.
    """
    m = next((mm for mm in METHODS.values() if mm.kernel == kernel), None)
    if m is None:
        names = sorted({mm.kernel for mm in METHODS.values()})
        raise ValueError(f"kernel: expected one of {names}")
    if metrics not in (None, "metrics", "metrics-general"):
        raise ValueError(f"metrics: expected None, 'metrics' or 'metrics-general', got {metrics!r}")
    t0 = time.perf_counter()
    target = None
    here = metrics if kernel in _SPLIT else None  # metrics compiled by this process's share
    if kernel not in _COMPILED and helper_enabled() and not is_cached(kernel):
        if kernel in _SPLIT:
            part, _, with_metrics = _SPLIT[kernel]
            if metrics in with_metrics and not is_cached(metrics):
                # the helper is idle while this process compiles the loop: it takes them
                part, here = with_metrics[metrics], None
            target = f"nsdyn.solve.compile_split:{part}"
        elif metrics == "metrics" and not is_cached(metrics):
            target = "nsdyn.solve.methods:warmup_metrics"
    if target is None:
        _warm(kernel, m)
    else:
        with Helper(target) as helper:
            _warm(kernel, m, helper, here)
    if metrics is not None:  # loaded from the cache when the helper compiled them
        warmup_metrics(metrics == "metrics")
    return time.perf_counter() - t0


def tiny_run(m: Method):
    """A run of method ``m`` on :func:`_tiny_problem` as the warm-ups make it:
    (P, x0, t_eval, options, X, upl_t)."""
    P, x0 = _tiny_problem()
    t_eval = np.linspace(0.0, 0.02, 3)
    dt = 1e-3 if m.fixed_step else None
    opts = make_options(x0, m, 1e-6, 1e-8, dt, None, True, np.inf, 1000, "warn", None, None)
    X = np.zeros((t_eval.size, x0.size))
    upl_t = np.full(KernelParams(P).n_contacts, np.nan)
    return P, x0, t_eval, opts, X, upl_t


def _warm(kname: str, m: Method, helper: Helper | None = None, metrics: str | None = None):
    """Compile (or load) kernel ``kname`` by a run of ``m`` on the tiny problem; seconds spent
    (0.0 when already done). With a ``helper`` compiling part of the loop (``kname`` in
    :data:`_SPLIT`), the ``metrics`` kernels and this process's share of the loop's pieces
    first (:mod:`nsdyn.solve.compile_split`)."""
    if kname in _COMPILED:
        return 0.0
    t0 = time.perf_counter()
    P, x0, t_eval, opts, X, upl_t = tiny_run(m)
    with compiling():
        if helper is not None and kname in _SPLIT:  # else the helper compiles the metrics only
            from nsdyn.solve import compile_split

            getattr(compile_split, _SPLIT[kname][1])(helper, metrics)
        m.run(P, x0, t_eval, opts, X, upl_t)
    _COMPILED[kname] = time.perf_counter() - t0
    return _COMPILED[kname]


# the kernels whose first compilation a helper process shares (nsdyn.solve.compile_split): the
# helper's part, this process's, and {metrics kind: the helper's part that also compiles them}
_SPLIT = {
    "radau": ("radau_helper_part", "radau_parts_here", {}),
    "event": ("event_helper_part", "event_parts_here", {}),  # the metrics here
    "genalpha": ("system_helper_part", "genalpha_parts_here", {}),
}  # fmt: skip

# the top-level numba dispatcher of each kernel (its on-disk cache entry stands for the kernel)
# (each a function: the other methods' modules are imported only when asked about)
_ENTRY = {  # the default loop's callees are compiled apart from it (nsdyn._kaddress)
    "radau": lambda: (_kradau.radau_flat, *_kradau.FLAT_CALLEES),
    "radau-general": lambda: _kradau.radau_general,
    "dopri5": lambda: _kdopri.dopri5,
    # the system kernel and its Jacobian: called by address
    "genalpha": lambda: (_kgenalpha.genalpha_loop, *ki.EVALUATE_KERNELS, *ki.JAC_KERNELS),
    "event": lambda: _kunilateral.kernels(True, False, False),  # its callees by address too
    "metrics": lambda: (_kflat.evaluate_flat_many, _kflat.feval_flat),
    "metrics-general": lambda: (ki.evaluate_many_t, *ki.EVALUATE_KERNELS),
}


def is_cached(kernel: str) -> bool:
    """True when ``kernel`` (a ``Method.kernel`` or ``"metrics"``) is compiled in this process
    or numba's on-disk cache holds it for this source, so that a run only loads it.

    False when it will be compiled (a first run, or the source changed), or when the cache
    cannot be inspected (numba internals differ): the caller then announces a compilation.
    """
    if kernel in _COMPILED:
        return True
    disp = _ENTRY[kernel]() if kernel in _ENTRY else ()
    return all(dispatcher_cached(d) for d in (disp if isinstance(disp, tuple) else (disp,)))


def warmup_metrics(flat: bool = True) -> float:
    """Compile (or load) the kernels of the response metrics on the tiny system: the flat
    kernel's (``evaluate_flat_many``, ``feval_flat``) for a smooth law with closed contacts
    (``flat``), else the general ``evaluate_many_t`` and the system kernel it calls by
    address (:func:`metrics_for`). Seconds spent now (0.0 when already done)."""
    key = "metrics" if flat else "metrics-general"
    if key in _COMPILED:
        return 0.0
    t0 = time.perf_counter()
    P, x0 = _tiny_problem()
    t = np.zeros(1)
    X = x0[None, :].copy()
    from nsdyn.solve.transient import flat_evaluations, general_evaluations

    with compiling():
        (flat_evaluations if flat else general_evaluations)(P, t, X)
    _COMPILED[key] = time.perf_counter() - t0
    return _COMPILED[key]


# ---- generalized-alpha with the linear part factored once (nsdyn.solve.sparse) ---------------
from nsdyn.solve import sparse as _sparse  # noqa: E402  (registers after the numba methods)

METHODS[_sparse.METHOD] = Method(_sparse.METHOD, _sparse.METHOD, True, _sparse.run)
_ENTRY[_sparse.METHOD] = lambda: _sparse._klowrank.run_steps  # the loop its warm-up compiles
# (the helper's system kernel takes less than this process's loop: it takes the metrics too)
_SPLIT[_sparse.METHOD] = ("evaluate_helper_part", "lowrank_parts_here",
                          {"metrics-general": "evaluate_helper_part_and_metrics"})  # fmt: skip

# ---- unilateral contact: lift-off, flight and landing (nsdyn.solve._kunilateral) -------------

MAX_CONTACT_EVENTS = 100_000  # lift-offs and landings recorded by a unilateral run


UNILATERAL_METHODS = ("event", "radau")  # event: switch model; radau: the law packed in P
CONTACT_KINDS = {"KIND_LIFT": "lift-off", "KIND_LAND": "landing"}  # _kunilateral's kinds


@dataclass
class UnilateralRun:
    """What a unilateral run adds to a method's outputs."""

    contact_events: list  # (t, contact, "lift-off" | "landing", R_k qd before, impulse)
    open_out: np.ndarray  # (nt, nc) contact states at the outputs, 1 open
    open_end: np.ndarray  # (nc,) contact states at the end (``open0`` of a follow-up run)
    impact_energy: float  # kinetic energy change of all landings [J] (<= 0)


def run_unilateral(P, x0, t_eval, o: Options, X, upl_t, method: str, e_rest: float, open0):
    """Integrate with unilateral contacts (:func:`_kunilateral.event_unilateral`): method
    ``"event"`` with the switch model's stick/slip events, ``"radau"`` with the law of ``P``.
    Returns (stats, rinfo, events, modes, UnilateralRun)."""
    if method not in UNILATERAL_METHODS:
        raise ValueError(
            f"contact 'unilateral': method expected one of {list(UNILATERAL_METHODS)}, got "
            f"{method!r}"
        )
    if not 0.0 <= e_rest <= 1.0:
        raise ValueError(f"restitution: expected 0 <= e <= 1, got {e_rest}")
    kp = KernelParams(P)
    if kp.frozen_normal:
        raise ValueError("contact 'unilateral' needs the normal forces as multipliers: contact "
                         "rows (build_system, system_from_matrices(contact_rows=...)) and "
                         "frozen_normal=False; this model's are fixed")  # fmt: skip
    ni = kp.n_isolators
    friction = method == "event"
    if o.modes0 is None:
        modes0 = np.full(ni, _kevent.MODE_AUTO, dtype=np.int64)
    else:
        modes0 = np.ascontiguousarray(o.modes0, dtype=np.int64).reshape(-1)
    max_step = o.max_step
    if friction:
        P = with_law(P, "modes", modes0)
        max_step = min(max_step, _event_max_step(kp))
    P = with_open(P, open0)  # private copy of the live contact states
    log = (np.zeros(MAX_EVENTS), np.zeros(MAX_EVENTS, dtype=np.int64),
           np.zeros(MAX_EVENTS, dtype=np.int64))  # fmt: skip
    clog = np.zeros((MAX_CONTACT_EVENTS, _kunilateral.CLOG_COLS))
    cnt = np.zeros(1, dtype=np.int64)
    dT = np.zeros(1)
    open_out = np.zeros((t_eval.size, kp.n_contacts), dtype=np.int64)
    stats, rinfo = _kunilateral.event_unilateral(
        P, x0, t_eval, o.atol, o.rtol, o.h0, max_step, o.max_steps, modes0, friction,
        float(e_rest), X, upl_t, open_out, log, clog, cnt, dT,
    )  # fmt: skip
    ev_t, ev_i, ev_m = log
    events = [(float(ev_t[k]), int(ev_i[k]), int(ev_m[k])) for k in range(int(stats[ki.S_NEVENT]))]
    kinds = {getattr(_kunilateral, k): name for k, name in CONTACT_KINDS.items()}
    cev = [
        (float(r[0]), int(r[1]), kinds[int(r[2])], float(r[3]), float(r[4]))
        for r in clog[: int(cnt[0])]
    ]
    kpm = KernelParams(P)
    extra = UnilateralRun(cev, open_out, kpm.open_contacts.copy(), float(dT[0]))
    return stats, rinfo, events, kpm.modes.copy() if friction else None, extra


def warmup_unilateral() -> float:
    """Compile (or load) the unilateral kernel on the tiny system (the switch model's event
    loop, :func:`warmup_kernel` ``("event")``, then a tiny run of each unilateral method);
    seconds spent now."""
    if "unilateral" in _COMPILED:
        return 0.0
    t0 = time.perf_counter()
    # both methods run the switch model's event loop, with the same compiled signature: its
    # warm-up shares a first compilation with a helper process
    warmup_kernel("event")
    for method in UNILATERAL_METHODS:
        P, x0, t_eval, opts, X, upl_t = tiny_run(METHODS[method])
        run_unilateral(P, x0, t_eval, opts, X, upl_t, method, 0.0, None)
    _COMPILED["unilateral"] = time.perf_counter() - t0
    return _COMPILED["unilateral"]


_ENTRY["unilateral"] = lambda: _kunilateral.kernels(True, True, True)
