"""Frequency responses of the isolated frame: periodic orbits, and the fixed base for reference.

Under ``u''_hor = A sin(2 pi f t)`` the isolated frame's periodic responses are continued in f
(:mod:`nsdyn.periodic.continuation` on :func:`nsdyn.periodic.problem.frame_problem`). The
fixed-base frame is linear, so its steady response is its receptance ``H(w)`` from ``u''_hor``
to the displacements ``q``, the frequency response of its state-space model:

    drift_i = A |H_top,i - H_bottom,i| / h_i,        a_abs = A |1 - w^2 H|.
"""

from __future__ import annotations

import numpy as np

from nsdyn._checks import InputWarning, expect, finite_numbers
from nsdyn.periodic.continuation import continue_range
from nsdyn.periodic.curve import Curve
from nsdyn.periodic.problem import frame_problem, load_amplitude_note
from nsdyn.periodic.protocol import A_HIGHEST, check_amplitude, check_frequencies


class BilateralOrbitWarning(InputWarning):
    """A curve of a system whose isolators' contact is unilateral shoots its bilateral orbits
    (a sweep over amplitudes says so once, for all of them)."""


def frequency_response(system, amplitude: float, *, load=None, **options) -> Curve:
    """Periodic responses of an isolated ``system`` to ``amplitude sin(2 pi f t)``: a ground
    acceleration [m/s²], or with ``load`` (a :class:`nsdyn.ground.HarmonicForce` naming the
    dofs, weights and phase) a force [N]; ``options`` (``fmin``, ``fmax``, ``points``,
    ``continuation`` and those of the continuation) as for
    :func:`nsdyn.periodic.continuation.continue_range`. The friction law is the arctan one or
    none (the switch law's curve: :func:`nsdyn.periodic.switch.switch_response`). A curve
    every frequency of which failed warns (:class:`~nsdyn.periodic.curve.EmptyCurveWarning`).
    """
    from nsdyn.models.isolated.system import IsolatedSystem

    expect(
        "system",
        system,
        isinstance(system, IsolatedSystem),
        "an IsolatedSystem (nsdyn.build_system, nsdyn.shear_building, ...)",
    )
    if isinstance(amplitude, str | bool):
        raise TypeError(f"amplitude: expected a number, got {amplitude!r}")
    if getattr(system.isolation, "contact", None) == "unilateral":  # (taken without a word)
        import warnings

        warnings.warn("system: its isolators' contact is unilateral, but a curve shoots the "
                      "bilateral orbits (a normal force below zero is flagged as uplift); the "
                      "lift-off orbits are nsdyn sweep --contact unilateral's, or "
                      "nsdyn.periodic.unilateral_steady_state at each such point",
                      BilateralOrbitWarning, stacklevel=2)  # fmt: skip
    problem = frame_problem(system, amplitude, load=load)  # (the amplitude checked first)
    load_amplitude_note(load, problem.amplitude)
    c = continue_range(problem, **options)
    c.info["model"] = system.name
    return c


def fixed_base_response(frame, amplitude, freqs, *, f_max: float = 5.0) -> dict | list[dict]:
    """Steady harmonic IDR and absolute floor acceleration of the fixed-base frame (linear).

    The receptance of the fixed-base model (fidelity ``"fixed"``) from ``u''_hor`` to the
    column-joint and level-node x displacements, ``H(w) = T (K - w^2 M + i w C)^-1 (-M Gamma)``
    (one batched solve over the frequencies: the frequency response of
    :func:`nsdyn.models.isolated.statespace.fixed_base_statespace`, without building it): a
    drift amplitude is ``A |H_top - H_bottom| / h``, an absolute acceleration ``A |1 - w^2 H|``.
    ``amplitude`` is a number in [0, 1000] m/s², or a sequence of them: the response is
    linear in it, so the solve is done once and a list of results (one per amplitude) is
    returned. ``freqs`` is a 1-D sequence of forcing frequencies (ValueError otherwise). A
    frame without regular column lines (a setback) has no drift ratios: ``idr`` NaN.
    """
    from nsdyn.models.isolated.metrics import output_dofs
    from nsdyn.models.isolated.system import build_system

    if frame is None:
        raise ValueError(
            "fixed_base_response needs a frame; a system built from matrices or a shear "
            "building has no fixed-base frame model"
        )
    freqs = finite_numbers("freqs", freqs, "a 1-D sequence of forcing frequencies [Hz]")
    check_frequencies(freqs)
    amps = [check_amplitude(a, "amplitude", A_HIGHEST) for a in np.atleast_1d(amplitude).tolist()]
    sysf = build_system(frame, fidelity="fixed", f_max=f_max)
    od = output_dofs(frame)
    jx = od["joints_x"]
    if jx is None:  # no regular column lines (a setback): no drift ratios, NaN
        jx = np.zeros((0, 0), dtype=np.int64)
    lev = od["levels_x"]
    dofs = np.concatenate([jx.ravel()] + [np.asarray(v) for v in lev])
    w = 2 * np.pi * freqs
    M, C, K = (np.asarray(a, dtype=float) for a in (sysf.M, sysf.C, sysf.K))
    Z = K[None] - (w**2)[:, None, None] * M[None] + (1j * w)[:, None, None] * C[None]
    # the load -M Gamma u''_hor (the fixed model's modal M is the identity: fixed_base_statespace
    # takes -Gamma, the same numbers)
    load = np.broadcast_to(-(M @ sysf.Gamma[:, 0]), (w.size, M.shape[0]))
    H = np.linalg.solve(Z, load[..., None])[..., 0] @ sysf.T[dofs].T  # (nf, n_out)
    nj = jx.size
    acc = np.abs(1.0 - (w**2)[:, None] * H[:, nj:]).max(axis=1)
    idr = np.full(len(w), np.nan)
    if nj:
        Hj = H[:, :nj].reshape(len(w), *jx.shape)
        idr = (np.abs(np.diff(Hj, axis=1)) / od["heights"][None, :, None]).reshape(len(w), -1)
        idr = idr.max(axis=1)
    out = [{"f": freqs, "idr": a * idr, "acc": a * acc} for a in amps]
    return out[0] if np.ndim(amplitude) == 0 else out
