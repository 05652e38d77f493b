"""Transient earthquake runs: one call from a model and a ground motion to response metrics.

``simulate(system, motion)`` integrates the isolated frame under the ground acceleration
``u''(t)`` (seed 004, eqs 8-15)::

    M qdd + C* qd + K* q = -M Gamma [u''_hor, u''_ver + g] + R^T lam - D^T tau

(C* and K* with the isolators' dampers and springs, ``system.C`` and ``system.K``) from the
static gravity equilibrium with the contacts active (qd = 0 and
``K* q - R^T lam = -M Gamma [0, g]``, ``R q = 0``) or a given state, in chunks (progress after
each chunk, optional checkpoint file so an interrupted run resumes), and returns the histories
with the metrics of :mod:`nsdyn.models.isolated.metrics`. The excitation may also be a force
``b F(t)`` (:class:`nsdyn.ground.HarmonicForce`, :class:`nsdyn.ground.ForceTable`).

The run ends where the excitation does (a record or table) or where the caller says: an
excitation without a natural end (harmonic) needs ``t_end`` or ``n_periods`` — no default
duration is guessed. Outputs are the record's samples, or ``HARMONIC_SAMPLES`` per period.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from nsdyn._checks import keywords_of, number, output_times, rel_tol
from nsdyn._tabular import Tabular
from nsdyn.atomic import CheckpointError
from nsdyn.ground.excitation import is_force, natural_end
from nsdyn.models.isolated.metrics import Response, evaluate_along, evaluation_arrays, response
from nsdyn.models.isolated.system import IsolatedSystem
from nsdyn.models.isolated.tolerances import FAST_ATOL, RUN_RTOL, arctan_atol, run_atol
from nsdyn.solve import integrate
from nsdyn.solve.checkpoint import CHUNK_S, Carry, chunked, chunks, holding_signals, run_key
from nsdyn.solve.checkpoint import load as load_checkpoint
from nsdyn.solve.checkpoint import save as save_checkpoint
from nsdyn.solve.resolution import between_steps, result_notes
from nsdyn.solve.run_inputs import (
    check_run_inputs,
    check_x0,
    default_step,
    event_law,
    integrated_law,
    record_span_notes,
    vertical_felt,
)

# the run defaults live in nsdyn.models.isolated.tolerances; the old names stay importable
DEFAULT_RTOL = RUN_RTOL
default_atol = run_atol
__all__ = [
    "CheckpointError",
    "DEFAULT_RTOL",
    "FAST_ATOL",
    "TransientResult",
    "default_atol",
    "describe",
    "output_grid",
    "simulate",
]

HARMONIC_SAMPLES = 100  # output instants per period of a harmonic excitation (default dt_out)


@dataclass(repr=False, eq=False)
class TransientResult(Tabular):
    """Histories and metrics of one transient run."""

    system: IsolatedSystem
    t: np.ndarray
    x: np.ndarray
    response: Response
    method: str
    n_steps: int
    wall_s: float
    compile_s: float
    stats: dict = field(default_factory=dict)
    uplift: list = field(default_factory=list)
    excitation: str = ""
    contact: str = "detect"
    contact_events: list = field(default_factory=list)  # unilateral: (t, k, kind, v_n, impulse)
    open_contacts: np.ndarray | None = None  # unilateral: (nt, nc), 1 where a contact is open
    impact_energy: float = 0.0  # unilateral: kinetic energy change of the landings [J]
    method_reason: str = ""  # why method "auto" chose the method ("given: 'radau'" if given)
    law: str | None = None  # the friction law integrated (None: no isolation)
    failure: str = ""  # on_failure="return": why the run stopped before its end (else "")
    notes: list = field(default_factory=list)  # what the run says of its own results
    restitution: float = 0.0  # unilateral: Newton's coefficient of the landings

    def contact_summary(self) -> dict:
        """The contact assumption and what it says: ``would_lift_off`` (a normal force < 0
        somewhere: outside a bilateral model's validity) or, for unilateral runs, lift-offs,
        landings, flight time per contact, peak landing velocity and impulse."""
        lam = self.response.lam
        out: dict = {"contact": self.contact}
        if lam.shape[-1]:
            out["would_lift_off"] = bool(lam.size and lam.min() < 0.0)
        if self.contact != "unilateral":
            return out
        from nsdyn.models.isolated.plane_result import flight_times

        lands = [e for e in self.contact_events if e[2] == "landing"]
        ev = sorted(self.contact_events, key=lambda e: e[0])
        open0 = None if self.open_contacts is None else (self.t[0], self.open_contacts[0])
        flight = flight_times([e[0] for e in ev], [e[1] for e in ev],
                              [e[2] == "lift-off" for e in ev], lam.shape[-1],
                              float(self.t[-1]), open0)  # fmt: skip
        out.update(
            {
                "would_lift_off": bool(self.contact_events),
                "lift_offs": sum(e[2] == "lift-off" for e in self.contact_events),
                "landings": len(lands),
                "flight_time_s": flight.tolist(),
                "max_landing_velocity_mps": max((abs(e[3]) for e in lands), default=0.0),
                "max_landing_impulse_Ns": max((e[4] for e in lands), default=0.0),
                "impact_energy_J": float(self.impact_energy),
                "restitution": float(self.restitution),
                "first_lift_off_s": min(
                    (e[0] for e in self.contact_events if e[2] == "lift-off"), default=None
                ),
            }
        )
        return out

    def histories(self) -> dict:
        """The histories on the output grid, units in the names: isolator slips, top drift (with
        levels), normal and friction forces, slip modes (+1/-1 slip, 0 stick), open contacts
        (unilateral) and the generalised coordinates q, q' of the model (its own units)."""
        r = self.response
        out = {"x_iso_{}_m": r.x_iso}
        if np.all(np.isfinite(r.top_drift)):
            out["top_drift_m"] = r.top_drift
        out.update({"lam_{}_N": r.lam, "tau_{}_N": r.tau, "slip_mode_{}": r.modes})
        if self.open_contacts is not None:
            out["open_{}"] = self.open_contacts
        n = self.x.shape[1] // 2
        out.update({"q_{}": self.x[:, :n], "qd_{}": self.x[:, n:]})
        return out

    def summary(self) -> dict:
        """Peaks, contact account, settings, costs and ``notes``; units in the key names."""
        out = self.response.summary()
        if self.system.n_isolators:  # (a fixed base: no contact, no uplift to speak of)
            out.update(self.contact_summary())
        lifts = [{"t_s": float(t), "contact": int(k)} for t, k in self.uplift]
        out.update(
            {
                "model": self.system.name,
                "fidelity": self.system.fidelity,
                "excitation": self.excitation,
                "t_start_s": float(self.t[0]),  # (a record may start before t = 0)
                "t_end_s": float(self.t[-1]),
                "dt_out_s": float(f"{self.t[1] - self.t[0]:.12g}") if self.t.size > 1 else 0.0,
                "method": self.method,
                "method_reason": self.method_reason,
                "law": self.law,
                "success": not self.failure,
                **({"failure": self.failure} if self.failure else {}),
                **({"uplift": lifts} if self.system.n_isolators else {}),
                "n_steps": int(self.n_steps),
                "wall_s": float(self.wall_s),
                "compile_s": float(self.compile_s),
                "notes": list(self.notes),
            }
        )
        return out


def _period(motion) -> float | None:
    p = getattr(motion, "period", None)
    return float(p) if p is not None and np.isfinite(p) else None


def output_grid(
    motion, dt_out: float | None = None, t_end: float | None = None, n_periods=None
) -> np.ndarray:
    """Output times from the excitation's start: the record's samples (or every ``dt_out``;
    HARMONIC_SAMPLES a period of a harmonic's fastest part) up to ``t_end``, ``n_periods``
    periods, or the record's end, the last output whatever the step (ValueError: none)."""
    t0 = float(getattr(motion, "t0", 0.0))
    if getattr(motion, "n", 2) < 2:
        raise ValueError(f"motion: a record of {motion.n} sample spans no time; give a record "
                         "of two samples or more")  # fmt: skip
    T = _period(motion)
    if t_end is not None and not np.isfinite(float(t_end)):
        raise ValueError(f"t_end: expected a finite end time [s], got {t_end}")
    if n_periods is not None:
        if t_end is not None:
            raise ValueError("give t_end or n_periods, not both")
        if T is None:
            raise ValueError("n_periods: the excitation is not periodic; give t_end [s]")
        if not n_periods > 0:
            raise ValueError(f"n_periods: expected a positive number, got {n_periods}")
        t_end = t0 + float(n_periods) * T
    if t_end is None:
        t_end = natural_end(motion)
        if t_end is None:
            what = "free vibration (motion None)" if motion is None else type(motion).__name__
            raise ValueError(f"t_end: {what} has no natural end: give the duration, t_end=... "
                             "[s] or n_periods=...")  # fmt: skip

    if dt_out is not None:  # (numpy's scalars too: np.float32(0.5) was "not positive")
        dt_out = number("dt_out", dt_out, "a positive output step [s]", lambda v: v > 0)
    T_out = getattr(motion, "fastest_period", T) if T else None  # (a vertical's, maybe)
    dt = dt_out or getattr(motion, "dt", None) or (T_out / HARMONIC_SAMPLES if T_out else None)
    if dt is None or not dt > 0:
        what = "free vibration (motion None)" if motion is None else "this excitation"
        raise ValueError(f"dt_out: {what} has no natural output step; give dt_out=... [s]")
    if not float(t_end) > t0:
        raise ValueError(f"t_end: expected a time after the start {t0:g} s, got {t_end}")
    if float(dt) > float(t_end) - t0 + 1e-9 * float(dt):
        raise ValueError(f"dt_out: an output step of {float(dt):g} s is longer than the run "
                         f"({float(t_end) - t0:g} s); expected at least two output times"
                         if dt_out else f"t_end: a run of {float(t_end) - t0:g} s is shorter "
                         f"than the motion's step {float(dt):g} s, its output step without "
                         "dt_out; expected at least two output times")  # fmt: skip
    return output_times(t0, float(t_end), float(dt))  # (ValueError beyond MAX_OUTPUTS)


def describe(excitation) -> str:
    """One line naming an excitation (for summaries)."""
    if excitation is None:
        return "none (free vibration)"
    kind = "force" if is_force(excitation) else "ground"
    name = getattr(excitation, "name", None)
    if name:
        return f"{kind}: {name}"
    F, f = getattr(excitation, "F", None), getattr(excitation, "f", None)
    if isinstance(F, int | float) and isinstance(f, int | float):  # a harmonic force
        w = excitation.weights
        even = w is None or all(x == 1.0 for x in w)
        on = f"dofs {list(excitation.dofs)}" + ("" if even else f", weights {list(w)}")
        phase = f", phase {excitation.phase:.4g} rad" if excitation.phase else ""
        return f"{kind}: harmonic, {F:g} N at {f:g} Hz{phase} on {on}"
    A, fh = getattr(excitation, "A_hor", None), getattr(excitation, "f_hor", None)
    if isinstance(A, int | float) and isinstance(fh, int | float):  # a harmonic ground motion

        def part(a, fr, phase):
            return f"{a:g} m/s² at {fr:g} Hz" + (f", phase {phase:.4g} rad" if phase else "")

        text = f"{kind}: harmonic, {part(A, fh, excitation.phase)}"
        if excitation.A_ver:
            text += f"; vertical {part(excitation.A_ver, excitation.f_ver, excitation.phase_ver)}"
        return text
    return f"{kind}: {excitation!r}"[:200]


def _prepare_kernels(method: str, P: tuple, contact: str | None) -> float:
    """Seconds spent compiling (or loading) the run's integrator kernel (the one
    :func:`nsdyn.solve.integrate.solve` picks) together with the metrics kernels the run
    evaluates after it (the flat ones for a smooth law with closed contacts): a first run
    then compiles the metrics in the compile helper beside the loop, as ``nsdyn run`` does
    (:func:`nsdyn.solve.methods.warmup_kernel`), instead of after the run. 0.0 when the kernel
    is ready, for an unknown method (``solve`` reports it) and for unilateral contacts (their
    own warm-up, :func:`nsdyn.solve.methods.warmup_unilateral`)."""
    from nsdyn.solve import methods

    if method not in methods.METHODS or contact == "unilateral":
        return 0.0
    kernel = methods.kernel_for(method, P)
    if methods.compiled(kernel):
        return 0.0
    return methods.warmup_kernel(kernel, metrics=methods.metrics_for(kernel))


def flat_evaluations(P: tuple, t: np.ndarray, X: np.ndarray) -> tuple | None:
    """Accelerations, normal forces, friction forces and modes along the history ``X``
    (every contact closed) by the flat kernel, its linear part ``-X_q (M^-1 K)^T - X_v
    (M^-1 C)^T`` one matrix product; rows where the flat form does not hold (singular ``G``)
    by the general kernel; rows with a non-finite time or state NaN (modes 0). None when the
    law is not a smooth one (the caller evaluates)."""
    from nsdyn.models.isolated import _kernel as ks
    from nsdyn.solve import _kflat as kf
    from nsdyn.solve.compile_split import flat_calls

    F = kf.pack_flat(P)
    if F[kf.H_OK] == 0.0:
        return None
    t = np.ascontiguousarray(t, dtype=float)
    X = np.ascontiguousarray(X, dtype=float)
    if not X.flags.writeable:  # the flat kernel is declared for writable rows (by address)
        X = X.copy()
    n = P[ks.I_MIK].shape[0]
    A0 = -(X[:, :n] @ P[ks.I_MIK].T)
    A0 -= X[:, n:] @ P[ks.I_MIC].T
    out = evaluation_arrays(P, t.size)
    ok = np.ones(t.size, dtype=np.bool_)
    kf.evaluate_flat_many(t, X, F, np.ascontiguousarray(A0), *out, ok, flat_calls())
    bad = np.flatnonzero(~ok)
    if bad.size:
        part = general_evaluations(P, t[bad], X[bad])
        for a, b in zip(out, part, strict=True):
            a[bad] = b
    return out


def general_evaluations(P: tuple, t: np.ndarray, X: np.ndarray, open_contacts=None) -> tuple:
    """Accelerations, normal forces, friction forces and modes along ``X`` by the system
    kernel (any law), called by its address (:func:`nsdyn.solve._kcommon.evaluate_many_t`:
    a run whose loop compiled the system kernel compiles no second copy of it for its
    metrics). Every contact closed, or with ``open_contacts`` (nt, nc; 1 open, a unilateral
    run) one evaluation per contact pattern, with its own open set."""
    from nsdyn.solve import _kcommon as ki
    from nsdyn.solve.compile_split import evaluate_inputs

    P, X = evaluate_inputs(P, X)
    return evaluate_along(ki.evaluate_many_t, P, np.ascontiguousarray(t, dtype=float), X,
                          open_contacts)  # fmt: skip


def evaluations(P: tuple, t: np.ndarray, X: np.ndarray, open_contacts=None, *, flat=True):
    """The accelerations, normal forces, friction forces and modes along ``X``:
    :func:`flat_evaluations` when ``flat`` and it serves ``P`` (a smooth law, every contact
    closed), else :func:`general_evaluations`. ``flat``: the run compiled the flat kernel
    (:func:`nsdyn.solve.methods.metrics_for`)."""
    if flat and (open_contacts is None or not np.any(open_contacts)):
        out = flat_evaluations(P, t, X)
        if out is not None:
            return out
    return general_evaluations(P, t, X, open_contacts)


def simulate(
    system: IsolatedSystem,
    motion,
    *,
    method: str = "auto",
    rtol: float = RUN_RTOL,
    atol: float | tuple | None = None,
    dt: float | None = None,
    t_eval: np.ndarray | None = None,
    t_end: float | None = None,
    n_periods: float | None = None,
    dt_out: float | None = None,
    x0: np.ndarray | None = None,
    uplift: str = "raise",
    contact: str | None = None,
    restitution: float = 0.0,
    progress=None,
    checkpoint: str | Path | None = None,
    chunk_s: float = CHUNK_S,
    **solver_options,
) -> TransientResult:
    """Integrate the IsolatedSystem ``system`` under ``motion`` from statics (or ``x0``).

    Parameters
    ----------
    motion                  ground motion (GroundMotion, Harmonic, Table), force excitation
                            (HarmonicForce, ForceTable) or None (free vibration from ``x0``)
    t_end, n_periods        end of the run [s] or in periods (required for a harmonic
                            excitation or none; default for a record: its end; past a
                            record's end the ground rests: free vibration, where
                            ``nsdyn run`` ends at the record's last sample)
    dt_out                  output step [s] (default: the record's dt, period / 100)
    x0 : ndarray (2n,)      initial state [q, qd] (default: the static equilibrium)
    method : str            a name in :data:`nsdyn.solve.integrate.METHODS`, or "auto"
                            (default): chosen from the model's size, friction law and
                            contact (:func:`nsdyn.solve.methods.choose_method`; the reason in
                            ``summary()["method_reason"]``)
    rtol, atol              tolerances (adaptive methods; ``atol`` a number or a pair
                            (displacements, velocities), default
                            :func:`nsdyn.models.isolated.tolerances.run_atol`);
                            ``dt`` [s]: the step of the fixed-step methods
    t_eval : ndarray        output times (instead of t_end / n_periods / dt_out); the run
                            starts at t_eval[0] (from ``x0``, default the static
                            equilibrium), on the excitation's own clock
    uplift : {"raise", "warn"}   what a normal force reaching zero does (contact "detect")
    contact : {"bilateral", "detect", "unilateral"}, optional   contact assumption (default:
                            the system's ``isolation.contact``; see
                            :mod:`nsdyn.solve.integrate`); "unilateral" with methods
                            ``event`` or ``radau``
    restitution : float     unilateral: Newton's coefficient of a landing (0: plastic)
    progress : callable(t_done, t_end, wall_s), optional
    checkpoint : path, optional   resume from / save to it after each chunk of ``chunk_s`` [s]
    **solver_options        :func:`nsdyn.solve.integrate.solve`'s: ``max_steps``, ``h0``,
                            ``on_failure="return"`` (a result with ``summary()["failure"]``)
    """
    if not isinstance(system, IsolatedSystem):
        raise TypeError("system: expected an IsolatedSystem (nsdyn.build_system, shear_building, "
                        f"system_from_matrices), got {type(system).__name__}")  # fmt: skip
    if hasattr(motion, "ax") and hasattr(motion, "ay"):  # a bidirectional excitation
        raise TypeError(
            f"motion: a bidirectional excitation ({type(motion).__name__}) drives the decks "
            "and 3D buildings; a plane model takes one direction of a three-component record: "
            "motion.planar() or motion.planar(angle_deg)"
        )
    if isinstance(motion, int | float):
        raise TypeError(f"motion: expected a ground motion or a force, got the number "
                        f"{motion!r}; nsdyn.Harmonic(A_hor, f_hor) is a harmonic ground "
                        "acceleration")  # fmt: skip
    if isinstance(motion, str | Path | np.ndarray | list | tuple):
        read = f"nsdyn.read_motion({str(motion)!r})" if isinstance(motion, str | Path) else (
            "nsdyn.GroundMotion(t0, dt, a_hor)")  # fmt: skip
        raise TypeError(
            f"motion: expected a ground motion or a force (GroundMotion, Harmonic, Table, "
            f"HarmonicForce, ForceTable) or None, got {type(motion).__name__}; {read} makes one"
        )
    keywords_of(integrate.solve, solver_options, skip=("P", "x0", "t_eval"),
                also=("rtol", "atol", "dt_out", "t_end"), caller="simulate() ")  # fmt: skip
    rel_tol("rtol", rtol)
    for k, v, what in (
        ("dt", dt, "a positive fixed step [s]"),
        ("t_end", t_end, "a finite end time [s] > 0"),
    ):  # (text was converted)
        if v is not None:
            number(k, v, what, lambda x: x > 0)
    if x0 is not None:  # (text: a numpy conversion error before; off the contacts: refused)
        check_x0(system, x0)
    number("chunk_s", chunk_s, "a positive duration [s]", lambda v: v > 0)  # ("5": a ufunc's)
    if t_eval is None:
        t_eval = output_grid(motion, dt_out, t_end, n_periods)
    elif t_end is not None or n_periods is not None or dt_out is not None:
        raise ValueError("give t_eval or t_end / n_periods / dt_out, not both")
    else:
        t_eval = np.asarray(t_eval, dtype=float)
    if contact is None:
        contact = getattr(system.isolation, "contact", "detect")
    if restitution != 0.0 and contact != "unilateral":  # (it was dropped without a word)
        raise ValueError(
            f"restitution: the coefficient of a landing, which a run with contact={contact!r} "
            "has none of; expected contact='unilateral'"
        )
    from nsdyn.solve.auto import given_reason, sparse_path
    from nsdyn.solve.methods import METHODS

    integrate.known_method(method)  # (a KeyError deep in the run before)
    reason = "" if method == "auto" else given_reason(system, method, contact)  # (auto's below)
    if method == "auto":
        from nsdyn.solve.auto import choose_for_system, step_reason

        method, reason = choose_for_system(system, contact)
        if METHODS[method].fixed_step:  # (the reason gives the step that runs: a given one)
            dt = default_step(motion) if dt is None else dt
            reason = step_reason(reason, dt)
        elif not METHODS[method].fixed_step and dt is not None:
            raise ValueError(
                f"dt={dt:g} is the step of a fixed-step method, but method 'auto' chose the "
                f"adaptive {method!r} ({reason}); name a fixed-step method with dt, or drop dt"
            )
    check_run_inputs(t_eval, progress, checkpoint, dt, motion)  # (after "auto" chose dt)
    event_law(system, method)
    vertical_felt(system, motion)
    if atol is None:  # the default, below the arctan law's turn (a given atol is kept)
        from nsdyn.solve.methods import METHODS

        atol = run_atol(method)
        if integrated_law(system, method) == "arctan" and not METHODS[method].fixed_step:
            atol = arctan_atol(atol, system.isolation.eps)
    if sparse_path(system, method, contact):  # else a full-order model's dense copies
        from nsdyn.solve.fullorder import simulate_full

        return between_steps(simulate_full(
            system, motion, t_eval, x0=x0, dt=dt, uplift=uplift, contact=contact,
            progress=progress, reason=reason, result=TransientResult, checkpoint=checkpoint,
            chunk_s=chunk_s, **solver_options,
        ), dt, uplift)  # fmt: skip
    if why := system.dense_refusal(contact):  # (the run's contact: lift-off is dense only)
        raise ValueError(why)
    P = system.params(motion)
    given_x0 = x0 is not None
    if x0 is None:
        x0, _ = system.static_equilibrium()
    else:
        x0 = np.asarray(x0, dtype=float).reshape(-1)  # (its size and contacts: check_x0)

    ts, xs = [t_eval[:1]], [x0[None, :]]
    k0 = 0
    carry = Carry()  # what each chunk hands to the next (and a checkpoint to a resumed run)
    carry.h0 = solver_options.pop("h0", None)  # the first step given: the first chunk's
    ckpt = Path(checkpoint) if checkpoint else None
    if ckpt is not None:
        options = dict(method=method, rtol=rtol, atol=atol, dt=dt, uplift=uplift,
                       contact=contact, restitution=restitution, **solver_options,
                       **chunked(chunk_s))  # fmt: skip
        run_id = run_key(P, x0 if given_x0 else None, t_eval, options)
        found = load_checkpoint(ckpt, run_id, t_eval) if ckpt.exists() else None
        if found is not None:
            t_done, x_done, carry = found
            ts, xs = [t_done], [x_done]
            k0 = t_done.size - 1
    wall = 0.0
    compile_s = 0.0
    failure = ""
    t_end = float(t_eval[-1])
    wall0 = time.perf_counter()
    plan = chunks(t_eval, k0, chunk_s, carry.t_at)  # every chunk_s, wherever the outputs fall
    if contact != "detect":
        solver_options.update(contact=contact)
    if contact == "unilateral":
        solver_options.update(restitution=restitution)
    if plan:  # a checkpoint may already hold the whole run
        compile_s += _prepare_kernels(method, P, contact)
    for te, a, b in plan:
        with holding_signals(ckpt is not None):  # (the chunk and its checkpoint first)
            x_start = xs[-1][-1] if carry.x_at is None else carry.x_at
            if carry.modes is not None and method == "event":
                solver_options["modes0"] = carry.modes
            if carry.open_end is not None:
                solver_options["open0"] = carry.open_end
            if carry.acc is not None:  # the generalized-alpha family's own acceleration
                solver_options["acc0"] = carry.acc
            kw = dict(method=method, rtol=rtol, atol=atol, dt=dt, uplift=uplift, **solver_options)
            try:
                # continue with the step the previous chunk would have taken next
                sol = integrate.solve(P, x_start, te, h0=carry.h0, **kw)
            except integrate.IntegrationError as err:
                if carry.h0 is None or err.reason != "step_underflow":
                    raise
                # a restart with the carried-over step can underflow where a fresh initial-step
                # estimate does not: retry the chunk once from scratch (same state, same model)
                sol = integrate.solve(P, x_start, te, h0=None, **kw)
            k = min(b - a, sol.t.size - 1)  # the outputs reached (the last maybe the chunk's end)
            carry.take(sol, contact == "unilateral", adaptive=dt is None, n_out=k)
            wall += sol.wall_s
            compile_s += getattr(sol, "compile_s", 0.0)
            ts.append(t_eval[a : a + k])
            xs.append(sol.x[1 : 1 + k])
            if not sol.success:  # on_failure="return": the run ends where the chunk stopped
                failure = sol.message
                break
            if ckpt is not None:
                save_checkpoint(ckpt, np.concatenate(ts), np.concatenate(xs), run_id, carry)
            if progress is not None:
                progress(float(sol.t[-1]), t_end, time.perf_counter() - wall0)
    t = np.concatenate(ts)
    x = np.concatenate(xs)
    law = "switch" if method == "event" else None
    Pm = system.params(motion, law=law) if law and system.isolation is not None else P
    open_hist = np.concatenate(carry.opens) if contact == "unilateral" else None
    from nsdyn.solve import methods

    flat = methods.metrics_for(methods.kernel_for(method, Pm)) == "metrics"
    evaluated = evaluations(Pm, t, x, open_hist, flat=flat)
    resp = response(system, t, x, Pm, open_hist, carry.impact, evaluated=evaluated)
    res = TransientResult(system, t, x, resp, method, carry.n_steps, wall, compile_s,
                          carry.stats, sorted(set(carry.uplifts)), describe(motion), contact,
                          carry.cevents, open_hist, carry.impact, reason,
                          integrated_law(system, method), failure)  # fmt: skip
    res.notes = record_span_notes(t_eval, motion) + result_notes(
        res, Pm, evaluated[0], dt, motion, (rtol, atol, uplift)
    )
    res.restitution = float(restitution)
    return between_steps(res, dt, uplift)
