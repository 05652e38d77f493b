"""Frequency responses of the isolated frame: periodic orbits, and the fixed base for reference.

Under ``u''_hor = A sin(2 pi f t)`` the isolated frame's periodic responses are continued in f
(:mod:`nsdyn.periodic.continuation` on :func:`nsdyn.periodic.problem.frame_problem`). The
fixed-base frame is linear, so its steady response is the frequency response ``H(j w)`` of its
state-space model from ``u''_hor`` to the displacements ``q``:

    drift_i = A |H_top,i - H_bottom,i| / h_i,        a_abs = A |1 - w^2 H|.
"""

from __future__ import annotations

import numpy as np

from nsdyn.periodic.continuation import continue_range
from nsdyn.periodic.curve import Curve
from nsdyn.periodic.problem import frame_problem


def frequency_response(system, amplitude: float, *, load=None, **options) -> Curve:
    """Periodic responses of an isolated ``system`` to ``amplitude sin(2 pi f t)``: a ground
    acceleration [m/s²], or with ``load`` (a :class:`nsdyn.ground.HarmonicForce` naming the
    dofs, weights and phase) a force [N]; ``options`` (``fmin``, ``fmax``, ``points``,
    ``continuation`` and those of the continuation) as for
    :func:`nsdyn.periodic.continuation.continue_range`.
    """
    c = continue_range(frame_problem(system, amplitude, load=load), **options)
    c.info["model"] = system.name
    return c


def fixed_base_response(frame, amplitude: float, freqs, *, f_max: float = 5.0) -> dict:
    """Steady harmonic IDR and absolute floor acceleration of the fixed-base frame (linear).

    From python-control's frequency response of
    :func:`nsdyn.models.isolated.statespace.fixed_base_statespace` with the column-joint and
    level-node x displacements as outputs: a drift amplitude is ``A |H_top - H_bottom| / h``,
    an absolute acceleration ``A |1 - w^2 H|``.
    """
    from nsdyn.models.isolated.metrics import output_dofs
    from nsdyn.models.isolated.statespace import fixed_base_statespace
    from nsdyn.models.isolated.system import build_system

    if frame is None:
        raise ValueError(
            "fixed_base_response needs a frame; a system built from matrices or a shear "
            "building has no fixed-base frame model"
        )
    sysf = build_system(frame, fidelity="fixed", f_max=f_max)
    od = output_dofs(frame)
    jx = od["joints_x"]
    lev = od["levels_x"]
    dofs = np.concatenate([jx.ravel()] + [np.asarray(v) for v in lev])
    ss = fixed_base_statespace(sysf, dofs)
    freqs = np.asarray(freqs, dtype=float)
    w = 2 * np.pi * freqs
    H = np.stack([np.asarray(ss(1j * wk)).reshape(-1) for wk in w])  # (nf, n_out)
    nj = jx.size
    Hj = H[:, :nj].reshape(len(w), *jx.shape)
    drift = np.abs(np.diff(Hj, axis=1)) / od["heights"][None, :, None]
    idr = amplitude * drift.reshape(len(w), -1).max(axis=1)
    Hl = H[:, nj:]
    acc = amplitude * np.abs(1.0 - (w**2)[:, None] * Hl).max(axis=1)
    return {"f": freqs, "idr": idr, "acc": acc}
