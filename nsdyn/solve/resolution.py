"""Whether a run's outputs report what it resolved.

A fixed-step run has no error control, so two things it reports are checked after it:

* :func:`between_steps`: a normal force that every step end kept positive but an output
  between the steps did not (the step does not resolve the response: an error, at its time);
* :func:`result_notes`: a drift no frame survives (every run's, :func:`drift_note`); a floor
  acceleration's peak read where the arctan law turns the
  friction over (and a step that does not divide the record's). The law
  ``μ N (2/π) arctan(ε v)`` turns within ~100/ε of zero slip velocity; a fixed
  step does not follow the turn, and a state it leaves inside it carries accelerations the
  motion does not have (22 m/s² at the isolation level of the default scene under
  ``genalpha`` at 5 ms, against 2.5 m/s² resolved). The velocities beside that output carry
  the motion: their central difference over ±Δ reads a harmonic of frequency f with the
  factor sin(2πfΔ)/(2πfΔ), at least 2/π up to a quarter of the output rate, so a resolved peak
  exceeds it by at most π/2. A peak above ``RATIO`` times it, at an output where an isolator
  slips inside the turn (``|v| < TURN/ε``), is named in a note with the value the velocities
  give, the time and what to do. The adaptive methods keep the slip velocity to 0.1/ε
  (:func:`nsdyn.models.isolated.tolerances.arctan_atol`) and are checked at every output, not
  only in the turn: the implicit one's error estimate at a loose ``rtol`` lets spikes through
  (301 m/s² at the isolation level of the default scene at rtol 0.9, 2.57 m/s² at 1e-3 where
  the velocities beside it give 0.35; none from 1e-4 down). A peak so found is integrated
  again over its output step at 1e-2 x the tolerances, and said only when it does not come
  back: a friction onset faster than the outputs is resolved (the portal's 3.94 m/s² at
  every rtol), and a unilateral run's landings are impulses, not checked. The explicit one
  (``dopri5``, :data:`EXPLICIT`) rings: the model's stiffness
  holds its steps at their stability limit, where the error estimate lets a ringing of the
  stiff components through into the accelerations (7.7 m/s² at the isolation level of the
  default scene, slipping at 0.19 m/s, against 2.5 m/s² resolved, at its default tolerance).
"""

from __future__ import annotations

import numpy as np

TURN = 100.0  # |v| < TURN/eps: the arctan law still turning (below 99.4 % of μN, 2/π arctan 100)
RATIO = 2.0  # above π/2, the most a resolved peak exceeds its central difference (module text)
# a peak below this fraction of g is no motion (below a strong-motion instrument's noise):
# a run without ground motion rings at round-off, which no step resolves or needs to
NEGLIGIBLE_G = 1e-6
EXPLICIT = ("dopri5",)  # adaptive explicit methods: their arctan-law peaks are checked too


def between_steps(res, dt, uplift: str):
    """``res``, unless a fixed-step run under contact "detect" (whose kernel stops at a step
    with a normal force <= 0) has one below zero between its steps, in the output: the step
    does not resolve the response (an IntegrationError at the first such output time)."""
    from nsdyn.solve import integrate
    from nsdyn.solve.methods import METHODS

    lam = res.response.lam
    if res.contact != "detect" or uplift != "raise" or res.uplift or not lam.size:
        return res
    low = lam.reshape(lam.shape[0], -1).min(axis=1)
    if not METHODS[res.method].fixed_step or low.min() >= 0.0:
        return res
    k = int(np.argmax(low < 0.0))
    raise integrate.IntegrationError(
        f"fixed step dt = {dt:g} s: a normal force between the steps reached {low.min():.4g} N "
        f"(first below zero at t = {res.t[k]:.6g} s) while every step's stayed positive: the "
        "step does not resolve the response; halve dt until the peaks settle, or use an "
        "adaptive method ('radau')",
        float(res.t[k]),
        "step too large",
    )


IDR_IMPLAUSIBLE = 0.1  # a drift ratio past this (10 %; frames collapse near 2-5 %): said


def drift_note(res) -> list[str]:
    """A peak interstorey drift ratio past :data:`IDR_IMPLAUSIBLE`, which no frame survives
    and the linear frame model does not describe: most often a frame in other units (E in
    MPa ran with a drift ratio of 558 % and a roof drift of 22 m, said like any other run)."""
    idr = float(getattr(res.response, "idr_max", np.nan))
    if not idr > IDR_IMPLAUSIBLE:
        return []
    return [f"peak interstorey drift ratio {idr:.3g} ({100 * idr:.3g} %): far past any frame's "
            "collapse (2-5 %) and the linear frame model's range; check the frame's units "
            "(E and G in Pa, lengths in m, masses in kg) and the record's (m/s²)"]  # fmt: skip


def result_notes(res, P: tuple, QDD: np.ndarray | None, dt, motion=None,
                 tols: tuple | None = None) -> list[str]:  # fmt: skip
    """What a run ``res`` says of its own results: an implausible drift (:func:`drift_note`);
    a fixed-step, explicit or (given its ``tols``: rtol, atol, uplift) implicit adaptive run's
    :func:`_turn_notes`, and a step
    that does not divide the sampling step of the record ``motion`` (its steps then straddle
    the samples, where the piecewise-linear input kinks, and lose an order there: the
    isolator's peak on the default scene errs more at 4 ms than at 5 ms)."""
    from nsdyn.solve.methods import METHODS

    said = drift_note(res) + _warned(_output_notes(res.t, motion))  # (every run's)
    if res.method in EXPLICIT:
        why = (f"the explicit steps of {res.method!r}, held at their stability limit by the "
               "model's stiffness, do not resolve")  # fmt: skip
        fix = "use 'radau' (the default), whose implicit steps do"
        return said + _warned(_turn_notes(res, P, QDD, why, fix, turning=False))
    if not METHODS[res.method].fixed_step or not dt:
        if tols is None or res.contact == "unilateral":  # (its landings' impulses are real)
            return said
        why = f"the tolerance rtol = {tols[0]:g} of {res.method!r} does not resolve"
        fix = "tighten rtol until they settle"
        done: dict = {}  # (an output recomputed once for all its levels)

        def confirm(k):
            if k not in done:
                done[k] = _recomputed(res, P, k, *tols)
            return done[k]

        return said + _warned(_turn_notes(res, P, QDD, why, fix, turning=False, confirm=confirm))
    fix = "halve dt until they settle, or use an adaptive method ('radau')"
    out = _warned(_turn_notes(res, P, QDD, f"the fixed step dt = {dt:g} s does not resolve", fix))
    h = getattr(motion, "dt", None)
    if h and abs(h / dt - round(h / dt)) > 1e-6 * h / dt:
        out.append(f"the fixed step dt = {dt:g} s does not divide the record's sampling step "
                   f"{h:g} s: its steps straddle the samples, where the input kinks, and are "
                   f"first-order accurate there; use the record's step divided by a whole "
                   f"number ({h / 2:g}, {h / 3:.3g}, {h / 4:g} s, …)")  # fmt: skip
    return said + out


def _output_notes(t, motion) -> list[str]:
    """:func:`nsdyn._checks.coarse_output_note` of outputs at times ``t`` (their widest gap)."""
    from nsdyn._checks import coarse_output_note, output_gap

    if t.size <= 2:
        return []
    gap, field = output_gap(t)  # (output times given: named as t_eval)
    note = coarse_output_note(gap, motion, field)
    return [note] if note else []


def _warned(notes: list[str]) -> list[str]:
    """``notes`` on peaks a run did not resolve, each also an :class:`AccuracyWarning` (a
    caller reading only the summary's numbers was told nothing; the command line says each
    once, as a note)."""
    import sys
    import warnings

    from nsdyn._checks import AccuracyWarning

    level, frame = 1, sys._getframe(0)  # the warning's place: the caller's, outside nsdyn
    while frame.f_back is not None and frame.f_globals.get("__name__", "").split(".")[0] == "nsdyn":
        frame, level = frame.f_back, level + 1
    for note in notes:
        warnings.warn(note, AccuracyWarning, stacklevel=level)
    return notes


CONFIRM = 1e-2  # an adaptive run's suspect peak is recomputed at this times its tolerances
CONFIRM_REL = 0.1  # ... and said only when the recomputed one differs by more than this


def _recomputed(res, P: tuple, k: int, rtol: float, atol, uplift="raise") -> np.ndarray | None:
    """The accelerations (n,) at output ``k`` of the adaptive run ``res``, integrated again
    from output k - 1 at :data:`CONFIRM` times its tolerances (a resolved peak comes back, a
    spike its error estimate let through does not); None where that cannot be made."""
    from nsdyn._checks import RTOL_MIN
    from nsdyn.solve import integrate
    from nsdyn.solve.transient import evaluations

    if k < 1:
        return None
    t, X = res.t[k - 1 : k + 1], res.x[k - 1]
    try:
        sol = integrate.solve(
            P,
            X,
            t,
            method=res.method,
            rtol=max(CONFIRM * rtol, RTOL_MIN),
            atol=CONFIRM * np.asarray(atol, float),
            contact=res.contact,
            uplift=uplift,  # (the run's: a peak at an uplift it went on through is its own)
        )
    except (ValueError, integrate.IntegrationError):
        return None
    return evaluations(P, t[1:], np.ascontiguousarray(sol.x[-1:]), flat=False)[0][0]


def _turn_notes(res, P: tuple, QDD: np.ndarray | None, why: str, fix: str,
                turning: bool = True, confirm=None) -> list[str]:  # fmt: skip
    """Notes (at most one) on the floor-acceleration peaks of an arctan-law run ``res``
    read inside the law's turn (module text); ``P`` its kernel tuple,
    ``QDD`` (nt, n) the accelerations its metrics evaluated; ``why`` and ``fix`` the note's
    words on the method; ``turning=False``: a peak at any output is checked, not only where
    an isolator slips inside the turn (an explicit method rings wherever its steps sit at
    their stability limit); ``confirm(k)``: the accelerations at output k computed again,
    a peak they give within :data:`CONFIRM_REL` of its value resolved (an adaptive run's)."""
    from nsdyn.models.isolated.excitation import ground_many
    from nsdyn.models.isolated.metrics import level_rows, output_rows
    from nsdyn.models.isolated.params import KernelParams

    system, t, X = res.system, res.t, res.x
    if res.law != "arctan" or t.size < 3 or QDD is None:  # (result_notes: its method's)
        return []
    od = output_rows(system)
    if not od["levels"] or system.D.shape[0] == 0:
        return []
    kp = KernelParams(P)
    eps, n = float(kp.eps), system.n
    ug_hor = np.zeros(t.size) if kp.force else ground_many(t, P)[:, 0]
    L, starts = level_rows(od)
    A = np.abs(np.asarray(L @ QDD.T) + ug_hor[None, :])  # (rows, nt) absolute
    V = np.asarray(L @ X[:, n:].T)
    fd = np.full_like(A, np.inf)  # (the first and last outputs: no difference there)
    fd[:, 1:-1] = np.abs((V[:, 2:] - V[:, :-2]) / (t[2:] - t[:-2]) + ug_hor[None, 1:-1])
    slow = np.abs(X[:, n:] @ system.D.T).min(axis=1) < TURN / eps  # (nt,) an isolator turning
    slow |= not turning
    found = []
    for lev, (i0, i1) in enumerate(zip(starts, [*starts[1:], A.shape[0]], strict=True)):
        row, k = np.unravel_index(np.argmax(A[i0:i1]), A[i0:i1].shape)
        beside = fd[i0 + row, max(k - 1, 0) : k + 2].max()
        if slow[k] and A[i0 + row, k] > max(RATIO * beside, NEGLIGIBLE_G * kp.g):
            again, more = confirm(k) if confirm is not None else None, ""
            if again is not None:
                a = abs(float(np.asarray(L @ again[:, None]).ravel()[i0 + row]) + ug_hor[k])
                if abs(a - A[i0 + row, k]) <= CONFIRM_REL * A[i0 + row, k]:
                    continue  # (a fast event between the outputs, resolved: found again)
                more = f"; its step again at {CONFIRM:g} x the tolerances {a:.3g}"
            found.append(f"level {lev} {A[i0 + row, k]:.3g} m/s² at t = {t[k]:.6g} s (the "
                         f"velocities beside it give {beside:.3g}{more})")  # fmt: skip
    if not found:
        return []
    where = (f"read inside the arctan law's turn (slip below {TURN:g}/eps = {TURN / eps:.2g} "
             "m/s)" if turning else "above what the velocities beside them give")  # fmt: skip
    return [f"floor acceleration peaks {where}, which {why}: {'; '.join(found)}; {fix}"]
