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

from nsdyn.models.isolated.plane_ground import ground_history

__all__ = ["plane_energy"]


def _trapz(p: np.ndarray, t: np.ndarray) -> float:
    return float(np.sum(0.5 * (p[1:] + p[:-1]) * np.diff(t))) if t.size > 1 else 0.0


def _quad(qd: np.ndarray, A) -> np.ndarray:
    """q̇ᵀ A q̇ at every output (A dense, sparse or an operator with ``@``)."""
    return np.einsum("tn,nt->t", qd, np.asarray(A @ qd.T))


def plane_energy(result, ground) -> dict:
    """The energy terms [J] of a run (:class:`~nsdyn.models.isolated.plane_result.PlaneResult`
    or :class:`~nsdyn.models.isolated.pairs.PairResult`) under ``ground``, what it was run
    with (module text): ``energy_input_J`` (the ground's and the weight's work),
    ``energy_viscous_J`` (the structure's damping), ``energy_friction_J``,
    ``energy_restoring_J`` and ``energy_other_J`` (the isolators': friction, pendulum and
    rubber, damper and rim stops), ``energy_contact_J``, ``stored_change_J`` and
    ``energy_closure``, the balance's error relative to its largest term."""
    system, t, q, qd = result.system, result.t, result.q, result.qd
    a = ground_history(ground, t)  # (3, nt): a_x, a_y, a_z
    if hasattr(system, "mass_matrix"):  # a deck: q = (x, y, θ), no structure, no contacts
        M, K, C = system.mass_matrix(), None, None
        load = np.zeros((t.size, 3))
        load[:, :2] = a[:2].T  # (Γ a_g: the plate's horizontal inertia)
        p_con = np.zeros(t.size)
    else:
        M, K, C = system.M, system.K, system.C
        a[2] += system.g
        load = (np.asarray(system.Gamma) @ a).T  # (nt, n)
        p_con = np.einsum("tc,tc->t", qd @ np.asarray(system.R).T, result.N)
    p_in = -np.einsum("tn,nt->t", qd, np.asarray(M @ load.T))
    v = result.v  # (nt, ni, 2)
    works = {k: _trapz(np.einsum("tic,tic->t", v, f), t)
             for k, f in (("friction", result.friction), ("restoring", result.restoring),
                          ("other", result.other))}  # fmt: skip
    works["viscous"] = _trapz(_quad(qd, C), t) if C is not None else 0.0
    ends = [0.5 * float(_quad(qd[[k]], M)[0]) for k in (0, -1)]
    if K is not None:
        ends = [e + 0.5 * float(_quad(q[[k]], K)[0]) for e, k in zip(ends, (0, -1), strict=True)]
    w_in, w_con = _trapz(p_in, t), _trapz(p_con, t)
    d_e = ends[1] - ends[0]
    scale = max(abs(w_in), abs(w_con), *(abs(w) for w in works.values()), *ends, 1e-300)
    return {
        "energy_input_J": w_in,
        **{f"energy_{k}_J": w for k, w in works.items()},
        "energy_contact_J": w_con,
        "stored_change_J": d_e,
        "energy_closure": abs(d_e - (w_in - sum(works.values()) + w_con)) / scale,
    }
