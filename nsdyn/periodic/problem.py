"""Harmonically forced problems for the periodic solvers: the isolated frame and Duffing.

Seed 004 §6, eqs (23)-(27). Under ``u''_hor = A sin(2 pi f t)`` (``u''_ver = 0``, gravity
kept) or a force ``b A sin(2 pi f t)`` (``load=HarmonicForce(...)``: its dofs, weights and
phase) the isolated structure (a frame, or a system built from matrices) moves on the
contact manifold ``R q = 0`` (``Q = I`` without contacts); with ``Q`` an orthonormal
null-space basis of ``R`` the minimal coordinates are ``z = Q^T q`` (``q = Q z``) and

    zdd = Q^T qdd(Q z, Q zd),     x = [z, zd]                                      (eq 27)

with the products ``Q^T M^-1 K Q``, ``R M^-1 K Q``, ... precomputed once
(:func:`manifold_matrices`). The test problem is the Duffing oscillator

    x'' + 2 zeta w0 x' + w0^2 x + gamma x^3 = F cos(2 pi f t).

:class:`PeriodicProblem` integrates one period of either with the fixed-step SDIRK kernels of
:mod:`nsdyn.periodic._kperiodic` and satisfies :class:`nsdyn.periodic.protocol.PeriodicModel`;
it also computes the seed's Fig. 9 quantities on an orbit.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np

from nsdyn._brief import brief_repr
from nsdyn.ground.excitation import Harmonic, HarmonicForce
from nsdyn.models.isolated.excitation import ground_many
from nsdyn.models.isolated.friction import stick_slip_note, sticks
from nsdyn.models.isolated.params import KernelParams, pack, with_ground
from nsdyn.periodic import _korbit as ko
from nsdyn.periodic import _kperiodic as kp
from nsdyn.periodic import _kproblems as kq
from nsdyn.periodic.discretisation import Discretisation
from nsdyn.periodic.extrema import dense_half_range
from nsdyn.periodic.protocol import (
    A_HIGHEST,
    MinimalStates,
    PeriodMap,
    check_amplitude,
    check_frequency,
    check_map_args,
)

DUFFING_W = 4  # index of the forcing circular frequency w in pf = [zeta, w0, gamma, F, w]
# the uplift probe (SciPy's Radau on the minimal coordinates): its tolerances (a verdict and
# an instant: on the test frames the lift-off instants at 1e-4 agree with those at 1e-6 to
# five digits, in a tenth of the steps) and its budget of right-hand sides
PROBE_RTOL, PROBE_ATOL = 1e-4, 1e-6
PROBE_STEPS = 64  # at least this many steps per period (the sign of the force at each end)
PROBE_MAX_EVALS = 200_000

_DUMMY_P = None


def _dummy_params() -> tuple:
    """A kernel tuple of the right type for problems that do not use it (Duffing)."""
    global _DUMMY_P
    if _DUMMY_P is None:
        _DUMMY_P = pack(np.eye(1), np.zeros((1, 1)), np.zeros((1, 1)), np.zeros((1, 2)))
    return _DUMMY_P


_DUMMY_Z = tuple(np.zeros((1, 1)) for _ in range(kp.N_Z))


@dataclass(repr=False)
class PeriodicProblem(MinimalStates):
    """A harmonically forced system whose period map the kernels integrate.

    ``x_ref`` is the unforced reference state (the static gravity equilibrium of a frame);
    the state is ``[z, zd]`` with ``m`` position coordinates. ``Z`` holds the precomputed
    manifold matrices of :mod:`nsdyn.periodic._kperiodic` (``Z[0] = Q``).
    """

    __repr__ = brief_repr  # arrays by shape, not in full

    prob: int
    P: tuple
    Z: tuple
    pf: np.ndarray
    x_ref: np.ndarray
    amplitude: float
    system: object = None
    name: str = ""
    _cache: dict = field(default_factory=dict, repr=False)
    load: HarmonicForce | None = None  # force excitation (None: ground acceleration)

    @property
    def Q(self) -> np.ndarray:
        return self.Z[kp.Z_Q]

    def at(self, f: float) -> tuple[tuple, np.ndarray]:
        """Kernel arguments (P, pf) for forcing frequency ``f`` [Hz]; a frame's ``pf`` is the
        flat array of :func:`nsdyn.periodic._kproblems.pack_frame`."""
        if self.prob == kp.PROB_FRAME:
            if self.load is not None:
                P = with_ground(self.P, self.load.at_frequency(f, self.amplitude))
            else:
                P = with_ground(self.P, Harmonic(self.amplitude, f))
            return P, kp.pack_frame(P, self.Z)
        pf = self.pf.copy()
        pf[DUFFING_W] = 2 * np.pi * f
        return self.P, pf

    def period_map(
        self,
        x0: np.ndarray,
        f: float,
        *,
        n_steps: int | None = None,
        disc: Discretisation | None = None,
        sens: bool = True,
        store: bool = False,
    ) -> PeriodMap:
        """Integrate one forcing period from ``x0`` (t = 0) with ``n_steps`` SDIRK steps."""
        N, args = self._map_args(x0, f, n_steps, disc, sens, store)
        xT, S, w, X, status, nfev, nsub = kp.period_map(*args, periodic_calls())
        return PeriodMap(xT, S if sens else None, w if sens else None, X if store else None,
                         int(status), N, int(nfev), int(nsub))  # fmt: skip

    def _map_args(self, x0, f, n_steps, disc, sens, store) -> tuple[int, tuple]:
        """The number of steps and the arguments of :func:`nsdyn.periodic._kperiodic.period_map`
        but its last (``K``)."""
        x0 = check_map_args(self.x_ref, x0, n_steps, disc)
        disc = disc or Discretisation()
        T = 1.0 / check_frequency(f)
        N = disc.steps(T) if n_steps is None else int(n_steps)
        A, c = disc.tableau()
        _, pf = self.at(f)
        return N, (self.prob, x0, T, N, pf, A, c, sens, store, disc.rtol, disc.atol)

    def orbit_quantities(self, f: float, X: np.ndarray) -> dict:
        """Maximum over one period (and all levels) of the seed's Fig. 9 quantities.

        ``idr``: interstorey drift ratio (column lines, all storeys; NaN for a model without
        storey heights; ``acc`` NaN without levels); ``acc``: absolute
        horizontal floor acceleration (all nodes of every level, base included);
        ``acc_floors``: the same over the levels above the isolators (``nsdyn run``'s
        ``floor_acc_max``); ``x_iso``: half the peak-to-peak isolator slip ``D q`` (largest
        isolator; extrema on the dense output, :mod:`nsdyn.periodic.extrema`);
        ``stick_all_period``: every isolator sticks over the whole period as
        :mod:`nsdyn.models.isolated.friction` defines it for the arctan law (friction below
        ``STICK_UTILISATION`` of its limit; False for other laws). For the Duffing problem:
        ``amp`` (half the peak-to-peak displacement) and ``x_max`` only.
        """
        if self.prob == kp.PROB_DUFFING:
            x = X[:, 0]
            return {"amp": 0.5 * float(x.max() - x.min()), "x_max": float(np.abs(x).max())}
        sysm = self.system
        cache = self._cache
        from nsdyn.models.isolated.metrics import level_peaks, output_rows
        from nsdyn.periodic.step_ends import step_end_peaks

        if "od" not in cache:
            cache["od"] = output_rows(sysm)
        N = X.shape[0] - 1
        t = np.linspace(0.0, 1.0 / f, N + 1)
        n = self.Q.shape[0]
        Xf = np.ascontiguousarray(self.to_full(X))
        P, _ = self.at(f)
        QDD, LAM = self.orbit_forces(f, t, X)
        G = ground_many(t, P)
        ug = np.zeros((N + 1, 1)) if self.load is not None else G[:, :1]
        od = cache["od"]
        q = Xf[:, :n]
        drift, _, _ = level_peaks(od, q, None, ug)  # the accelerations: step_end_peaks
        idr = math.nan
        if od["joints"] is not None and od["heights"] is not None:
            # max_t,c(dU / h) = max_t,c(dU) / h exactly (h > 0; rounded division is monotonic)
            idr = float(np.max(drift / np.asarray(od["heights"]))) if drift.size else 0.0
        acc = acc_floors = math.nan
        extra = {}
        if od["levels"]:  # step ends a sharp friction law spoils held (periodic.step_ends)
            acc_levels, raw, n_held = step_end_peaks(od, QDD, Xf[:, n:], 1.0 / (f * N), ug)
            if raw.max() > acc_levels.max():
                extra = {"acc_step_ends": float(raw.max()), "acc_resolved": False,
                         "acc_held": n_held}  # fmt: skip
            acc = float(acc_levels.max())
            acc_floors = float(acc_levels[1:].max()) if acc_levels.size > 1 else acc
        xi = q @ sysm.D.T
        v = Xf[:, n:] @ sysm.D.T
        x_iso = dense_half_range(xi, v, QDD @ sysm.D.T, 1.0 / (f * N))
        kpar = KernelParams(P)  # (no friction, no stick: mu = 0 was said to stick-slip; a
        rubs = np.asarray(kpar.mu) > 0.0  # frictionless isolator's slip hid the others' stick)
        rubs = rubs if kpar.law == "arctan" and rubs.any() else None
        held = None if rubs is None else np.all(sticks(v[:, rubs], "arctan", kpar.eps), axis=1)
        stick = held is not None and bool(held.all()) and bool(rubs.all())  # (every isolator)
        return {
            "idr": idr,
            "acc": acc,
            "acc_floors": acc_floors,
            "x_iso": x_iso,
            "stick_all_period": stick,
            # (the samples where every isolator sticks; the last is the period's first)
            "stick_fraction": float(held[:-1].mean()) if held is not None else math.nan,
            "v_slip_max": float(np.max(np.abs(v))) if v.size else 0.0,
            "min_normal_force": float(LAM.min()) if LAM.size else math.nan,
            "uplift": bool(LAM.size and LAM.min() <= 0.0),
            **extra,
        }

    def orbit_forces(self, f: float, t: np.ndarray, X: np.ndarray) -> tuple:
        """The accelerations ``qdd = Q zdd`` (nt, n) and contact forces (nt, nc) of a frame
        along the minimal states ``X`` at the times ``t``: the period map's right-hand side
        at each sample (:func:`nsdyn.periodic._korbit.orbit_forces`, the multipliers it
        solves for); a sample where its constraint matrix is singular by the system kernel
        (the constrained equations in full coordinates)."""
        P, pf = self.at(f)  # a new pf: its scratch holds each sample's multipliers
        nt = X.shape[0]
        nc = int(pf[kq.FH_NC]) if self.prob == kp.PROB_FRAME else 0
        ZDD, LAM = np.empty((nt, self.m)), np.empty((nt, nc))
        ok = np.ones(nt, dtype=np.bool_)
        Xc = np.array(X, dtype=float, order="C")
        tc = np.array(t, dtype=float, order="C")
        ko.orbit_forces(self.prob, tc, Xc, pf, ZDD, LAM, ok, periodic_calls())
        QDD = ZDD @ self.Q.T
        bad = np.flatnonzero(~ok)
        if bad.size:
            from nsdyn.solve.transient import general_evaluations

            part = general_evaluations(P, tc[bad], np.ascontiguousarray(self.to_full(Xc[bad])))
            QDD[bad], LAM[bad] = part[0], part[1]
        return QDD, LAM

    def quantities_without_orbit(
        self, f: float, x0: np.ndarray, periods: int = 1
    ) -> tuple[dict, str]:
        """NaN quantities for a point whose period from ``x0`` could not be integrated; for
        a frame, ``uplift`` and the note come from :func:`uplift_probe` over ``periods``."""
        keys = ("idr", "acc", "acc_floors", "x_iso", "v_slip_max", "min_normal_force",
                "stick_fraction")  # fmt: skip
        q = dict.fromkeys(keys, math.nan)
        q["stick_all_period"] = None
        q["uplift"] = None  # unknown unless the frame's probe decides
        probe = ""
        if self.prob == kp.PROB_FRAME:
            q["uplift"], probe = uplift_probe(self, f, x0, periods)
        return q, probe

    def validity_note(self, quantities: dict) -> str:
        """A contact lifts off (normal force <= 0): the bilateral contacts no longer hold; the
        fixed step did not resolve the friction law's switch (the spoilt step ends are then
        held to the velocity changes beside them, :mod:`nsdyn.periodic.step_ends`)."""
        notes = []
        if quantities.get("uplift"):
            fmin = quantities.get("min_normal_force", math.nan)
            what = (
                f"min normal force {fmin:.3g} N < 0" if np.isfinite(fmin) else "a normal force <= 0"
            )
            why = "the bilateral contact model is outside its validity"
            if quantities.get("acc_resolved") is False:  # the normal force rides on the same
                why += (  # right-hand side as the step ends' accelerations
                    "; or the step's: its friction switch is unresolved (below), which can "
                    "drive a normal force to zero; confirm with --friction switch or a smaller eps"
                )
            notes.append(f"uplift: {what} ({why})")
        if quantities.get("acc_resolved") is False:
            notes.append(
                f"accelerations: the step ends give {quantities['acc_step_ends']:.3g} m/s², "
                f"{quantities['acc_held']} of them beyond the velocity changes of the steps "
                "beside them (the friction law's switch, unresolved by any fixed step); "
                f"reported: {quantities['acc']:.3g} m/s², those held to the velocity changes "
                "(a smaller eps or the switch law resolves it)"
            )
        law = KernelParams(self.P)  # (its stick fraction: NaN but under the arctan law)
        stick_slip = stick_slip_note(quantities.get("stick_fraction"), law.law, law.eps)
        return "; ".join(notes + [stick_slip] * bool(stick_slip))  # fmt: skip


def orbit_quantities(problem: PeriodicProblem, f: float, X: np.ndarray) -> dict:
    """The quantities of the orbit ``X`` (see :meth:`PeriodicProblem.orbit_quantities`)."""
    return problem.orbit_quantities(f, X)


def uplift_probe(
    problem: PeriodicProblem, f: float, x0: np.ndarray, periods: int = 1
) -> tuple[bool | None, str]:
    """Does a contact lift off within ``periods`` periods from ``x0`` (minimal coordinates)?

    For points whose fixed-step period could not be integrated: SciPy's adaptive Radau IIA
    (``solve_ivp``, ``PROBE_RTOL``, ``PROBE_ATOL``, at least ``PROBE_STEPS`` steps per
    period) on the manifold equations with the period
    map's own right-hand side and Jacobian (:func:`nsdyn.periodic._kproblems.f_eval`,
    :func:`~nsdyn.periodic._kproblems.j_eval`, called from Python: the probe compiles nothing
    a sweep does not compile anyway), the smallest contact force ``lam`` (the multipliers the
    right-hand side solves for) an event located between steps. Returns (True: a normal force
    reached zero, False: none did, None: the probe failed too; a note saying which).
    """
    from scipy.integrate import solve_ivp

    if periods < 1:
        raise ValueError(f"periods: expected an integer >= 1, got {periods!r}")
    _, pf = problem.at(f)  # a new array: its scratch (s, G, lam) is this probe's
    d, prob = problem.dim, problem.prob
    m, nc, ni = int(pf[kq.FH_M]), int(pf[kq.FH_NC]), int(pf[kq.FH_NI])
    o_lam = getattr(kq._frame_offsets, "py_func", kq._frame_offsets)(m, nc, ni)[kq.O_LAM]
    out, F, J = np.empty(d), np.empty(d), np.empty((d, d))
    evals = [0]

    def rhs(t, x):
        evals[0] += 1
        if evals[0] > PROBE_MAX_EVALS:
            raise _ProbeFailed(t, f"gave up after {PROBE_MAX_EVALS} evaluations")
        if not kq.f_eval(prob, float(t), np.array(x, dtype=float), pf, out):
            raise _ProbeFailed(t, "singular constraint matrix G")
        return out.copy()

    def jac(t, x):
        if not kq.j_eval(prob, float(t), np.array(x, dtype=float), pf, F, J):
            raise _ProbeFailed(t, "singular constraint matrix G")
        return J.copy()

    def normal(t, x):  # the smallest contact force at (t, x)
        rhs(t, x)
        return float(pf[o_lam : o_lam + nc].min()) if nc else math.inf

    normal.terminal, normal.direction = True, -1.0
    x0 = np.array(x0, dtype=float)
    where = "radau probe from the period's start"
    if nc == 0:
        return False, f"{where}: no contact to lift off"
    try:
        if normal(0.0, x0) <= 0.0:
            return True, f"{where}: uplift at t = 0 s"
        with np.errstate(all="ignore"):  # (an overflow is the failure said below)
            sol = solve_ivp(rhs, (0.0, periods / f), x0, method="Radau", jac=jac,
                            events=normal, rtol=PROBE_RTOL, atol=PROBE_ATOL,
                            max_step=1.0 / (PROBE_STEPS * f))  # fmt: skip
    except _ProbeFailed as e:
        return None, f"{where} failed at t = {e.t:.4g} s: {e.reason}"
    except ValueError as e:  # Radau's factorisation of an overflowed Jacobian
        return None, f"{where} failed: the state or its Jacobian overflowed ({e})"
    if sol.t_events[0].size:
        return True, f"{where}: uplift at t = {sol.t_events[0][0]:.6g} s"
    if sol.status != 0:
        return None, f"{where} failed at t = {sol.t[-1]:.4g} s: {sol.message}"
    span = "one period" if periods == 1 else f"{periods} periods"
    return False, f"{where}: no uplift over {span}"


class _ProbeFailed(Exception):
    """The probe's right-hand side could not be evaluated (or it took too many)."""

    def __init__(self, t: float, reason: str):
        super().__init__(reason)
        self.t, self.reason = float(t), reason


def manifold_matrices(system, P: tuple) -> tuple:
    """The tuple Z of :mod:`nsdyn.periodic._kperiodic` (products on q = Q z precomputed once)."""
    Q = np.ascontiguousarray(system.Q)
    kpar = KernelParams(P)
    mats = kpar.matrices()
    MiK, MiC, Gam = mats["MiK"], mats["MiC"], mats["Gamma"]
    R, MiRt, D, MiDt = mats["R"], mats["MiRt"], mats["D"], mats["MiDt"]
    ni = D.shape[0]
    parts = [None] * kp.N_Z
    parts[kp.Z_Q], parts[kp.Z_QT] = Q, Q.T
    parts[kp.Z_KZ], parts[kp.Z_CZ] = Q.T @ MiK @ Q, Q.T @ MiC @ Q
    parts[kp.Z_QG] = Q.T @ Gam
    parts[kp.Z_QMIRT], parts[kp.Z_QMIDT] = Q.T @ MiRt, Q.T @ MiDt
    parts[kp.Z_RAZ], parts[kp.Z_RAV] = R @ MiK @ Q, R @ MiC @ Q
    parts[kp.Z_RG] = R @ Gam
    parts[kp.Z_G0], parts[kp.Z_GD] = R @ MiRt, R @ MiDt
    parts[kp.Z_DQ] = D @ Q
    parts[kp.Z_MU] = kpar.mu.reshape(1, ni)  # friction coefficients
    parts[kp.Z_L0] = kpar.lam_static.reshape(1, ni)
    return tuple(np.ascontiguousarray(a, dtype=float) for a in parts)


def load_amplitude_note(load, amplitude) -> None:
    """An InputWarning when a curve's ``load`` states a force amplitude ``F`` other than its
    ``amplitude``: the curve's is ``amplitude`` (``load`` gives the dofs, weights and phase),
    and a HarmonicForce(500, ...) with amplitude 1 ran at 1 N without a word."""
    F = getattr(load, "F", None)
    if F is None or isinstance(amplitude, str | bool) or F == amplitude:
        return
    import warnings

    from nsdyn._checks import InputWarning

    warnings.warn(f"load: its F = {F:g} N is not used: a curve's force amplitude is amplitude "
                  f"({amplitude:g} N; load gives the dofs, weights and phase, and each "
                  "frequency is the curve's)", InputWarning, stacklevel=3)  # fmt: skip


def frame_problem(
    system, amplitude: float, *, law: str | None = None, load: HarmonicForce | None = None
) -> PeriodicProblem:
    """The isolated ``system`` under ``u''_hor = amplitude sin(2 pi f t)`` on z = Q^T q, or
    under the force ``amplitude sin(2 pi f t + phase)`` on ``load``'s dofs (its own F and f
    are replaced by ``amplitude`` and each frequency of the continuation).

    Only smooth friction laws ("arctan", "none") give a differentiable period map.
    ``amplitude`` is finite, >= 0 and, a ground acceleration, <= 1000 m/s² (100 g)
    (ValueError otherwise; 0, the unforced static state, is not shot); the isolator
    parameters were checked when ``system.isolation`` was built.
    """
    if not (hasattr(system, "isolation") and hasattr(system, "params")):  # (an AttributeError)
        raise TypeError(f"system: expected an IsolatedSystem (nsdyn.build_system, "
                        f"shear_building, ...), got {type(system).__name__}")  # fmt: skip
    amplitude = check_amplitude(amplitude, highest=A_HIGHEST if load is None else math.inf)
    if system.isolation is None:
        raise ValueError("shooting needs an isolated model; the fixed base is linear (use FRFs)")
    law = law or system.isolation.law
    if law not in ("arctan", "none"):
        raise ValueError(f"law: shooting needs a smooth friction law ('arctan' or 'none'), got "
                         f"{law!r} (the switch law's curve: nsdyn.switch_response, its "
                         "problem: switch_problem)")  # fmt: skip
    if load is not None and not isinstance(load, HarmonicForce):
        raise TypeError(f"load: expected a HarmonicForce, got {type(load).__name__}")
    exc = Harmonic(amplitude, 1.0) if load is None else load.at_frequency(1.0, amplitude)
    P = system.params(exc, law=law)
    Z = manifold_matrices(system, P)
    Q = Z[kp.Z_Q]
    x_static, _ = system.static_equilibrium()
    z0 = Q.T @ x_static[: system.n]
    x_ref = np.concatenate([z0, np.zeros_like(z0)])
    return PeriodicProblem(
        kp.PROB_FRAME, P, Z, np.zeros(5), x_ref, float(amplitude), system, system.name, load=load
    )


@functools.cache
def _callees() -> tuple:
    """The period map's callees by address (:mod:`nsdyn._kaddress`), in the order of its K:
    :func:`nsdyn.periodic._kproblems.j_eval` as ``"periodic.jeval"`` (problem id, t, x, pf,
    F, J), :func:`~nsdyn.periodic._kproblems.f_eval` as ``"periodic.feval"`` (problem id, t,
    x, pf, F) and the step :func:`nsdyn.periodic._kperiodic.dirk_step` as ``"periodic.step"``,
    each declared for the types the period map and its step call it with (those of the arrays
    :func:`~nsdyn.periodic._kperiodic.period_map` makes, whatever the problem)."""
    from numba import typeof, types

    from nsdyn.solve.compile_split import Callee

    f8, i8, b1 = types.float64, types.int64, types.boolean
    v, m = types.float64[::1], types.float64[:, ::1]
    scratch = getattr(kp.step_scratch, "py_func", kp.step_scratch)  # (no JIT: the function)
    tmp = typeof(scratch(2, 2, True))
    step_args = (
        f8, f8, f8, v, m, v, b1, types.Tuple((i8, v)), types.Tuple((m, v, f8, f8)),
        types.Tuple((m, m, types.int64[::1], v, v)), tmp, types.Tuple((v, m, v)),
        types.int64[:, ::1],
    )  # fmt: skip
    return (
        Callee("periodic.jeval", kp.j_eval, (i8, f8, v, v, v, m), b1),
        Callee("periodic.feval", kp.f_eval, (i8, f8, v, v, v), b1),
        Callee("periodic.step", kp.dirk_step, step_args, types.UniTuple(i8, 2)),
    )


@functools.cache
def periodic_calls():
    """``K`` of :func:`nsdyn.periodic._kperiodic.period_map`: the addresses of its callees
    (:func:`_callees`, :func:`nsdyn.solve.compile_split.calls`; compiles or loads only them)."""
    from nsdyn.solve.compile_split import calls

    return calls(list(_callees()))


def kernels_cached() -> bool:
    """True when the period map's kernel, its step, Jacobian and right-hand side and the orbit
    quantities' kernel are compiled in this process or in numba's on-disk cache (a sweep
    then only loads them)."""
    from nsdyn.solve.methods import dispatcher_cached

    kernels = (kp.period_map, *(c.kernel for c in _callees()), ko.orbit_forces)
    return all(dispatcher_cached(d) for d in kernels)


def _helper_callees() -> None:
    """The period map's Jacobian and right-hand side (its callees by address but the step)."""
    for c in _callees()[:2]:
        c.compiled()


def _orbit_forces_types() -> tuple:
    """Arguments of :func:`nsdyn.periodic._korbit.orbit_forces` of the types a frame's
    orbit quantities call it with (values unused; ``K`` of the period map's type)."""
    v, m = np.zeros(2), np.zeros((2, 2))
    K0 = np.zeros((2, 1), dtype=np.int64)
    return (kp.PROB_FRAME, v, m, v, m, m, np.ones(2, dtype=np.bool_), K0)


def _step_pieces() -> None:
    """The step's iteration matrix (:func:`nsdyn.periodic._kperiodic._iteration_matrix`, with
    the LU factorisation it links) for the types the step calls it with: the helper compiles
    it first, and this process, which compiles the step after the period map, finds it in the
    cache (the shares of the two processes about even)."""
    from numba import types

    if hasattr(kp._iteration_matrix, "compile"):  # not under NUMBA_DISABLE_JIT
        # the step's declared work tuple (J, LU, piv, hg_lu, Fprev): _iteration_matrix(J, hg,
        # LU, piv), hg a float
        J, LU, piv = _callees()[2].args[9].types[:3]
        kp._iteration_matrix.compile((J, types.float64, LU, piv))


def helper_part() -> None:
    """A helper process's share of a first sweep's compilation (see :func:`warmup`): the
    step's iteration matrix (:func:`_step_pieces`), the Jacobian and the right-hand side the
    period map calls by address, then the orbit quantities' kernel (which calls the
    right-hand side by address too)."""
    from nsdyn.solve.compile_split import _compile

    _step_pieces()
    _helper_callees()
    _compile(ko.orbit_forces, *_orbit_forces_types())


def warmup() -> float:
    """Compile (or load) the kernels of a smooth-law sweep: the period map (one signature
    serves every problem; compiled here for a Duffing oscillator's arguments, with
    sensitivities and the stored orbit), its step, Jacobian and right-hand side (all three
    called by address, :func:`_callees`; the uplift probe calls the last two from Python)
    and the orbit quantities' kernel (:func:`nsdyn.periodic._korbit.orbit_forces`). When
    they compile, a helper process (:class:`nsdyn._numba_cache.Helper`,
    :func:`helper_part`) takes the step's iteration matrix, the Jacobian, the right-hand side
    and the orbit quantities while this one compiles the period map and then its step (which
    need none of them compiled, only declared; the step loads the iteration matrix from the
    cache). Then short runs load everything. Seconds spent."""
    import time
    from contextlib import nullcontext

    from nsdyn._numba_cache import Helper, compiling, helper_enabled
    from nsdyn.solve.compile_split import _compile

    t0 = time.perf_counter()
    prob = duffing_problem(0.05, 1.0, 0.1, 0.5)
    cold = not kernels_cached()
    helper = Helper("nsdyn.periodic.problem:helper_part") if cold and helper_enabled() else None
    with helper or nullcontext(), compiling():
        if helper is not None:
            callees = _callees()  # declared: the typing checks each call against them
            K0 = np.zeros((2, 1), dtype=np.int64)  # only its type matters here
            _, args = prob._map_args(prob.x_ref, 0.2, 4, None, True, True)
            _compile(kp.period_map, *args, K0)
            callees[2].compiled()  # the step, after the helper's iteration matrix
            helper.wait_for([c.kernel for c in callees[:2]] + [ko.orbit_forces])
        prob.period_map(prob.x_ref, 0.2, n_steps=4, sens=True, store=True)
        _compile(ko.orbit_forces, *_orbit_forces_types()[:-1], periodic_calls())
    return time.perf_counter() - t0


def duffing_problem(zeta: float, w0: float, gamma: float, F: float) -> PeriodicProblem:
    """``x'' + 2 zeta w0 x' + w0^2 x + gamma x^3 = F cos(2 pi f t)`` (test problem;
    ``zeta >= 0``, ``w0 > 0``, ``gamma`` finite, ``F >= 0``: ValueError otherwise)."""
    for name, v, ok in (("zeta", zeta, zeta >= 0), ("w0", w0, w0 > 0), ("gamma", gamma, True)):
        if not (math.isfinite(v) and ok):
            kind = {"zeta": ">= 0", "w0": "> 0 [rad/s]", "gamma": ""}[name]
            raise ValueError(f"{name}: expected a finite number {kind}, got {v!r}".rstrip())
    pf = np.array([zeta, w0, gamma, check_amplitude(F, "F"), 1.0], dtype=float)
    Z = (np.eye(1),) * 2 + _DUMMY_Z[2:]
    return PeriodicProblem(
        kp.PROB_DUFFING, _dummy_params(), Z, pf, np.zeros(2), float(F), None, "duffing"
    )
