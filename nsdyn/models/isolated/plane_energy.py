"""The work–energy balance of a run of isolators that slide in a plane.

A deck's coordinates q = (x, y, θ) (:class:`~nsdyn.models.isolated.deck.PlaneSystem`) move
under the ground's inertia load and the isolator forces F_i = friction + restoring + other
(damper, rim stop), each against the slip velocity v_i = D_i q̇ of its isolator::

    M q̈ = −M Γ a_g − Σ D_iᵀ F_i,      Γ a_g = (a_x, a_y, 0)

a system from matrices (:class:`~nsdyn.models.isolated.pairs.PairSystem`) adds its structure,
gravity and contacts: M q̈ + C q̇ + K q = −M Γ (a_g + g e_z) + Rᵀλ − Σ D_iᵀ F_i. With the
stored energy E = ½ q̇ᵀ M q̇ + ½ qᵀ K q (K = 0 for a deck), its change over the run is the work
done on q::

    E(t_end) − E(0) = W_in − W_viscous − W_friction − W_restoring − W_other + W_contact,
    W_in = −∫ q̇ᵀ M Γ (a_g + g e_z) dt,   W_friction = ∫ Σ v_i · friction_i dt, …

(W_contact = ∫ q̇ᵀ Rᵀ λ dt, which a closed gap R q̇ = 0 keeps at the Baumgarte drift's; with
gravity it balances the weight's work.) The restoring work is no potential energy in general: a
pendulum's N u/R follows the normal force N, which the vertical ground motion and the
overturning moment vary; a deck neither lifts nor tilts, so they do no work on it. The
integrals are taken by the trapezoidal rule on the output grid, on which the ground is sampled
as the kernels see it: the closure |ΔE − ΣW| / (largest term) measures the grid as much as the
run, falling as the output step squared, and a loose tolerance or a missed event shows as a
closure the grid does not explain.
"""

from __future__ import annotations

import numpy as np

from nsdyn.models.isolated.metrics import STORED_ROUND_OFF, _trapz
from nsdyn.models.isolated.plane_ground import ground_history

__all__ = ["closure_note", "plane_energy"]


ROWS_PER_BLOCK = 1024  # outputs per product: a temporary of this many rows, not one of q's size


def _quad(X: np.ndarray, A) -> np.ndarray:
    """Xᵀ A X at every output, rows of ``X`` (A dense, sparse or a function of (n, nt)), a
    block of outputs at a time."""
    out = np.empty(X.shape[0])
    for s in range(0, X.shape[0], ROWS_PER_BLOCK):
        b = X[s : s + ROWS_PER_BLOCK]
        AX = A(b.T) if callable(A) else A @ b.T
        out[s : s + ROWS_PER_BLOCK] = np.einsum("tn,nt->t", b, np.asarray(AX))
    return out


def plane_energy(result, ground) -> dict:
    """The energy terms [J] of a run (:class:`~nsdyn.models.isolated.plane_result.PlaneResult`
    or :class:`~nsdyn.models.isolated.pairs.PairResult`, dense or sparse) under ``ground``,
    what it was run with (module text): ``energy_input_J`` (the ground's and the weight's
    work), ``energy_viscous_J`` (the structure's damping, its low-rank modal term included),
    ``energy_friction_J``, ``energy_restoring_J`` and ``energy_other_J`` (the isolators':
    friction, pendulum and rubber, damper and rim stops), ``energy_contact_J``,
    ``energy_impact_J`` (≤ 0: what plastic landings took, a unilateral run's), the stored
    energy's ``stored_change_J`` and ``energy_closure``: the balance's error over
    ``energy_scale_J``, its largest term, or the stored energy above the static equilibrium
    at either end, or the largest kinetic energy over the run, or the round-off of the
    stored energies where that is larger (the
    weight's prestrain is no scale: a weak shaking's closure was divided by 14 by it).
    ValueError for a run that kept no q, q̇."""
    system, t, q, qd = result.system, result.t, result.q, result.qd
    if q.shape[1] == 0:
        raise ValueError("result: the run kept no histories of q and q̇ (keep_q), which its "
                         "energy balance needs")  # fmt: skip
    a = ground_history(ground, t)  # (3, nt): a_x, a_y, a_z
    if hasattr(system, "mass_matrix"):  # a deck: q = (x, y, θ), no structure, no contacts
        M, K, C, q0 = system.mass_matrix(), None, None, np.zeros(3)
        MG = M @ np.diag([1.0, 1.0, 0.0])  # (Γ a_g: the plate's horizontal inertia)
        p_con = np.zeros(t.size)
    else:
        M, K, C = system.M, system.K, getattr(system, "damp", system.C)  # (C* of a sparse one)
        q0 = system.static_equilibrium()[0][: q.shape[1]]
        a[2] += system.g
        MG = np.asarray(M @ np.asarray(system.Gamma))  # (n, 3)
        p_con = np.einsum("ct,tc->t", np.asarray(system.R @ qd.T), result.N)
    p_in = -np.einsum("tk,kt->t", qd @ MG, a)  # q̇ᵀ M Γ a_g, through (nt, 3)
    v = result.v  # (nt, ni, 2)
    works = {k: _trapz(np.einsum("tic,tic->t", v, f), t)
             for k, f in (("friction", result.friction), ("restoring", result.restoring),
                          ("other", result.other))}  # fmt: skip
    works["viscous"] = _trapz(_quad(qd, C), t) if C is not None else 0.0
    ends, above = [], []  # the stored energies at the ends, and above the static equilibrium
    for k in (0, -1):
        kin = 0.5 * float(_quad(qd[[k]], M)[0])
        strain = 0.5 * float(_quad(q[[k]], K)[0]) if K is not None else 0.0
        dq = q[[k]] - q0
        ends.append(kin + strain)
        above.append(kin + (0.5 * float(_quad(dq, K)[0]) if K is not None else 0.0))
    impact = float((result.flights or {}).get("impact_energy_J", 0.0))
    w_in, w_con = _trapz(p_in, t), _trapz(p_con, t)
    d_e = ends[1] - ends[0]
    kin_max = 0.5 * float(_quad(qd, M).max())  # (a free mass at whole periods: every other
    terms = [w_in, w_con, impact, *works.values(), *above, kin_max,  # term ~0, its closure 1)
             STORED_ROUND_OFF * max(ends)]  # fmt: skip
    scale = max(*(abs(w) for w in terms), 1e-300)
    return {
        "energy_input_J": w_in,
        **{f"energy_{k}_J": w for k, w in works.items()},
        "energy_contact_J": w_con,
        "energy_impact_J": impact,
        "stored_change_J": d_e,
        "energy_scale_J": scale,
        "energy_span_s": float(t[-1] - t[0]) if t.size else 0.0,  # (what the balance covers)
        "energy_closure": abs(d_e - (w_in - sum(works.values()) + w_con + impact)) / scale,
    }


LANDING_CLOSURE_NOTE = 1e-2  # a unilateral run's closure above this is said, with its cause
CLOSURE_NOTE = 0.5  # any other run's closure above this (over MIN_SPAN_S): said, with advice
MIN_SPAN_S = 0.2  # s run, below which a closure is its few outputs' (a run of 0.01 s: 0.34)


def closure_note(s: dict) -> str | None:
    """One line when a run's summary ``s`` has an energy closure that says something, else
    None: with landings, above :data:`LANDING_CLOSURE_NOTE`, its trapezoids step over the
    landings' velocity jumps, an error first order in the output step, not the run's (the
    portal's cb rung lifted by a 1.4 g vertical: 0.10, 0.010 and 9.6e-4 at dt_out 10, 5 and
    0.2 ms); without, above :data:`CLOSURE_NOTE` on a run of :data:`MIN_SPAN_S` or more,
    a balance off by half its largest term, which a coarse grid alone rarely explains (a deck
    at rtol 0.1 under eps 1e10 closed to 1.02 and stopped on an uplift of its own making;
    the bundled decks' early stops read 0.04 to 0.34 from their grid)."""
    n, c = s.get("landings") or 0, s.get("energy_closure")
    if c is None or not c > (LANDING_CLOSURE_NOTE if n else CLOSURE_NOTE):
        return None
    if not n:
        if s.get("energy_span_s", MIN_SPAN_S) < MIN_SPAN_S:  # (a record from t0: its span)
            return None
        return (
            f"energy closure {c:.3g}: the run's energy balance is off by {c:.0%} of its "
            "largest term; if a finer solver.dt_out does not lower it, the integration is "
            "not to be trusted (a tolerance too loose for the friction law's sharpness: "
            "tighten solver.rtol)"
        )
    return (f"energy closure {c:.3g}: the balance's integrals on the output grid step over the "
            f"{n} landings' velocity jumps, an error of the grid, first order in its step, not "
            "of the run; a finer solver.dt_out lowers it")  # fmt: skip
