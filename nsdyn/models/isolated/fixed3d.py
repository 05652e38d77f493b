"""The fixed rung of a space frame: fixed-base linear response to a three-component record.

With the base clamped and moving rigidly with the ground, the displacements relative to the
ground ``u = Φ η`` (fixed-base modes of :func:`nsdyn.structure.fixed_base_modes_3d`,
mass-normalised) obey, mode by mode,

    η̈_k + 2 ζ_k ω_k η̇_k + ω_k² η_k = −(Γ_x,k a_x + Γ_y,k a_y + Γ_z,k a_z),   Γ_d,k = φ_kᵀ M r_d,

with ``ζ_k`` the frame's modal damping ratios in frequency order (the last for every further
mode) and ``r_d`` the rigid translations. The record is piecewise linear between samples, so
each step is exact (Nigam–Jennings): with F the matrix of the first-order system augmented by
the load p and its slope ṗ (constant over a step), ``[η, η̇, p, ṗ](t + Δt) = exp(F Δt) [η, η̇,
p, ṗ](t)``, evaluated once per mode with ``scipy.linalg.expm``. Outputs (time histories, no
modal combination rule):

- storey drift ratios in x and y at the centre of mass and the plan corners: drifts are
  linear in u, so those of each mode shape (:func:`nsdyn.structure.storey_drifts_3d`) are
  combined with η(t);
- floor accelerations at each level's reference point (the centre of mass on a diaphragm
  level), absolute: ``Σ_k U_k η̈_k + a_g`` with η̈ from the modal equation;
- base shear and torsional moment about the centre of mass from the elastic forces
  ``K u = Σ_k M φ_k ω_k² η_k``: ``V_d = Σ_k Γ_d,k ω_k² η_k``, ``T = Σ_k Γ_θ,k ω_k² η_k``.

The truncation to ``n_modes`` is reported as the effective-mass fractions captured.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from nsdyn._checks import number
from nsdyn._tabular import Tabular
from nsdyn.structure.frame3d import Frame3D
from nsdyn.structure.modes3d import Modes3D, fixed_base_modes_3d
from nsdyn.structure.storey3d import StoreyDrifts, floor_motions, storey_drifts_3d

__all__ = ["FixedResponse3D", "fixed_response_3d", "modal_histories", "response_peaks"]


def _step_matrices(omega: float, zeta: float, dt: float) -> np.ndarray:
    """exp(F Δt) of ``[η, η̇, p, ṗ]' = F [η, η̇, p, ṗ]`` (module docstring), rows 0–1."""
    F = np.zeros((4, 4))
    F[0, 1] = 1.0
    F[1, 0], F[1, 1], F[1, 2] = -(omega**2), -2.0 * zeta * omega, 1.0
    F[2, 3] = 1.0
    return sla.expm(F * dt)[:2]


def modal_histories(omega, zeta, p: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """η and η̇ (m, n) of ``η̈ + 2ζωη̇ + ω²η = p`` from rest, p (m, n) linear between samples."""
    omega, zeta = np.asarray(omega, float), np.asarray(zeta, float)
    p = np.asarray(p, float)
    m, n = p.shape
    E = np.stack([_step_matrices(float(w), float(z), dt) for w, z in zip(omega, zeta, strict=True)])
    A = E[:, :, :2]  # (m, 2, 2) state part
    b0 = E[:, :, 2] - E[:, :, 3] / dt  # on p_i
    b1 = E[:, :, 3] / dt  # on p_{i+1}
    X = np.zeros((m, 2, n))
    x = np.zeros((m, 2))
    for i in range(n - 1):
        x = np.einsum("kij,kj->ki", A, x) + b0 * p[:, i, None] + b1 * p[:, i + 1, None]
        X[:, :, i + 1] = x
    if not np.all(np.isfinite(X)):
        i = int(np.argmax(~np.all(np.isfinite(X), axis=(0, 1))))
        raise FloatingPointError(f"modal response not finite at sample {i} (t = {i * dt:g} s)")
    return X[:, 0], X[:, 1]


@dataclass(frozen=True, eq=False, repr=False)
class FixedResponse3D(Tabular):
    """Fixed-base response histories (module docstring); ``t`` (nt,) [s].

    eta, eta_d : (m, nt) modal coordinates and velocities.   drifts : StoreyDrifts with a
    trailing time axis (``cm`` (ns, 2, nt), ``corner`` (ns, 4, 2, nt)).
    floor_acc : (nl, 2, nt) absolute floor accelerations x, y at each level's reference [m/s²]
    (level 0 = base = the ground). base_shear : (2, nt) [N].  torsion : (nt,) [N m] about the
    centre of mass.  captured : (3,) effective-mass fractions of the kept modes (x, y, θ).
    """

    frame: Frame3D
    modes: Modes3D
    t: np.ndarray
    eta: np.ndarray
    eta_d: np.ndarray
    drifts: StoreyDrifts
    floor_acc: np.ndarray
    base_shear: np.ndarray
    torsion: np.ndarray
    captured: np.ndarray

    def summary(self) -> dict:
        """Peaks with units in the key names."""
        return {
            "n_modes": int(len(self.modes.f_hz)),
            "f1_hz": float(self.modes.f_hz[0]),
            "mass_captured_x": float(self.captured[0]),
            "mass_captured_y": float(self.captured[1]),
            "mass_captured_torsion": float(self.captured[2]),
            **response_peaks(self.drifts, self.floor_acc, self.base_shear, self.torsion),
        }

    def histories(self) -> dict:
        """The response histories on ``t`` (:func:`response_histories`) and the modal
        coordinates ``eta_{}`` (mode j), for :meth:`to_dataframe` / :meth:`to_xarray`."""
        return {**response_histories(self.drifts, self.floor_acc, self.base_shear,
                                     self.torsion), "eta_{}": self.eta.T}  # fmt: skip


def response_histories(drifts: StoreyDrifts, floor_acc, base_shear, torsion) -> dict:
    """Histories (time first, units in the names) of response arrays with a trailing time
    axis: drift ratios at the centres of mass ``drift_cm_x_{}`` (storey j) and at the plan
    corners ``drift_corner_x_{}`` (column 4 j + c: storey j, corner c), floor accelerations
    ``floor_acc_x_{}_mps2`` (level j, 0 = the base), ``base_shear_x_N`` and ``torsion_Nm``
    (and the same in y)."""
    ns = drifts.cm.shape[0]
    out = {}
    for c, name in enumerate("xy"):
        out[f"drift_cm_{name}_{{}}"] = drifts.cm[:, c, :].T
        out[f"drift_corner_{name}_{{}}"] = drifts.corner[:, :, c, :].reshape(4 * ns, -1).T
    for c, name in enumerate("xy"):
        out[f"floor_acc_{name}_{{}}_mps2"] = floor_acc[:, c, :].T
    out.update({"base_shear_x_N": base_shear[0], "base_shear_y_N": base_shear[1],
                "torsion_Nm": torsion})  # fmt: skip
    return out


AMP_FLOOR = 1e-9  # drifts below this part of the largest are round-off: no amplification
DRIFT_ROUNDOFF = 1e-12  # drift ratios at or below this are round-off (a rigid building's
# ~1e-16 m of slip differences over metres of storey): no amplification either


def response_peaks(drifts: StoreyDrifts, floor_acc, base_shear, torsion) -> dict:
    """Peak drift ratios at the centres of mass and the corners (x, y), the corner
    amplification (overall and per storey), accelerations of the floors above the base
    (``floor_acc`` (nl, 2, nt), level 0 = the base left out), base shear and torsional moment
    of response histories (trailing time axis), units in the key names."""
    cm = np.abs(drifts.cm).max(axis=-1)  # (ns, 2)
    corner = np.abs(drifts.corner).max(axis=(1, -1))  # (ns, 2)
    # a ratio of drifts at round-off (a direction the record does not excite) is no
    # amplification: None (it read 835 under an x-only record, NaN, invalid JSON, at rest)
    floor = AMP_FLOOR * max(float(cm.max(initial=0.0)), float(corner.max(initial=0.0)))

    def ratio(c, m):
        return float(c / m) if m > floor and m > DRIFT_ROUNDOFF else None

    return {
        "peak_drift_cm_x": float(cm[:, 0].max()),
        "peak_drift_cm_y": float(cm[:, 1].max()),
        "peak_drift_corner_x": float(corner[:, 0].max()),
        "peak_drift_corner_y": float(corner[:, 1].max()),
        "corner_amplification_x": ratio(corner[:, 0].max(), cm[:, 0].max()),
        "corner_amplification_y": ratio(corner[:, 1].max(), cm[:, 1].max()),
        "corner_amplification_per_storey": [[ratio(c, m) for c, m in zip(*cm_c, strict=True)]
                                            for cm_c in zip(corner, cm, strict=True)],  # fmt: skip
        "peak_floor_acc_x_mps2": float(np.abs(floor_acc[1:, 0]).max()),
        "peak_floor_acc_y_mps2": float(np.abs(floor_acc[1:, 1]).max()),
        "peak_base_shear_x_N": float(np.abs(base_shear[0]).max()),
        "peak_base_shear_y_N": float(np.abs(base_shear[1]).max()),
        "peak_base_shear_N": float(np.hypot(base_shear[0], base_shear[1]).max()),  # resultant
        "peak_torsional_moment_Nm": float(np.abs(torsion).max()),
    }  # fmt: skip


def _components(motion) -> tuple[float, float, np.ndarray]:
    if not (hasattr(motion, "dt") and hasattr(motion, "ax")):  # (an AttributeError before)
        raise TypeError(f"motion: expected a three-component record (GroundMotion3: "
                        f"nsdyn.read_motion3, or GroundMotion3.from_planar of a one-component "
                        f"record), got {type(motion).__name__}")  # fmt: skip
    # (a negative dt gave another answer, unsaid; dt = 0 "modal response not finite")
    dt = number("motion.dt", motion.dt, "a positive time step [s]", lambda v: v > 0)
    t0 = number("motion.t0", getattr(motion, "t0", 0.0) or 0.0, "a finite start time [s]")
    rows = []
    for name in ("ax", "ay", "az"):
        v = getattr(motion, name, None)
        try:
            rows.append(None if v is None else np.asarray(v, dtype=float))
        except (TypeError, ValueError):
            raise ValueError(f"motion.{name}: expected an array of accelerations "
                             f"[m/s²], got {type(v).__name__}") from None  # fmt: skip
    n = -1 if rows[0] is None or rows[0].ndim != 1 else rows[0].size
    for name, v in zip(("ax", "ay", "az"), rows, strict=True):
        if v is not None and (v.shape != (n,) or n < 2):  # (numpy's vstack error before)
            what = "a 1-D array of two samples or more" if name == "ax" else f"{n} samples (as ax)"
            raise ValueError(f"motion.{name}: expected {what}, got shape {v.shape}")
    a = np.vstack([np.zeros(n) if v is None else v for v in rows])
    if not np.all(np.isfinite(a)):
        raise ValueError("motion: expected finite samples of ax, ay (az), got NaN or inf")
    return t0, dt, a


def few_modes_note(asked: int, modes: Modes3D) -> str | None:
    """One line when ``structure.n_modes`` asks for more modes than the building has (every
    one it has is used: the response is exact in them); None otherwise."""
    n = len(modes.f_hz)
    if n >= asked:
        return None
    return (f"structure.n_modes = {asked} asks for more modes than the building has: all its "
            f"{n} fixed-base modes are used")  # fmt: skip


def _own_modes(modes, K) -> None:
    """Refuse modes not of this frame: of another size (matmul's error before), or of one as
    large whose stiffness they do not diagonalise, φᵀ K φ = diag ω² (mass-normalised modes,
    consistent or lumped mass, to 1e-6 ω²_max: the eigensolvers' residuals are ~1e-12)."""
    n = K.shape[0]
    if not isinstance(modes, Modes3D) or modes.phi.shape[0] != n:
        got = (f"modes of {modes.phi.shape[0]} dofs" if isinstance(modes, Modes3D)
               else type(modes).__name__)  # fmt: skip
        raise ValueError(f"modes: expected the frame's own modes (fixed_base_modes_3d(frame), "
                         f"{n} dofs), got {got}")  # fmt: skip
    w2 = (2 * np.pi * modes.f_hz) ** 2
    G = modes.phi.T @ (K @ modes.phi)
    if w2.size and not np.allclose(G, np.diag(w2), rtol=0, atol=1e-6 * w2.max()):
        raise ValueError("modes: expected the frame's own modes (fixed_base_modes_3d(frame)), "
                         "got modes of as many dofs that do not diagonalise its stiffness "
                         "(phi^T K phi != diag(omega^2): another frame's?)")  # fmt: skip


def fixed_response_3d(
    frame: Frame3D, motion, *, n_modes: int = 24, modes: Modes3D | None = None
) -> FixedResponse3D:
    """Fixed-base response of ``frame`` to ``motion`` (a GroundMotion3 or anything with
    ``t0, dt, ax, ay, az``) from ``n_modes`` modes (or the given ``modes``)."""
    if modes is None:
        modes = fixed_base_modes_3d(frame, n_modes=n_modes)
    t0, dt, a = _components(motion)
    K, M = frame.reduced()
    _own_modes(modes, K)
    phi = modes.phi
    omega = 2 * np.pi * modes.f_hz
    nm = len(omega)
    zeta = frame.zeta[np.minimum(np.arange(nm), len(frame.zeta) - 1)]
    rz = frame.rigid_motions()[:, 2]
    gam = np.column_stack([modes.gamma[:, :2], phi.T @ (M @ rz)])  # (m, 3): x, y, z
    p = -(gam @ a)  # (m, n)
    eta, eta_d = modal_histories(omega, zeta, p, dt)
    eta_dd = p - 2 * zeta[:, None] * omega[:, None] * eta_d - omega[:, None] ** 2 * eta
    full = modes.full()
    dm = storey_drifts_3d(frame, full)  # per mode shape: cm (ns, 2, m), corner (ns, 4, 2, m)
    drifts = StoreyDrifts(dm.heights, dm.cm_points, dm.corners, dm.cm @ eta, dm.corner @ eta)
    _, _, fm = floor_motions(frame, full)  # (nl, 3, m)
    floor_acc = fm[:, :2] @ eta_dd + a[None, :2]
    w2eta = omega[:, None] ** 2 * eta
    base_shear = modes.gamma[:, :2].T @ w2eta
    torsion = modes.gamma[:, 2] @ w2eta
    captured = modes.mass_fraction.sum(axis=0)
    t = t0 + dt * np.arange(a.shape[1])
    return FixedResponse3D(frame, modes, t, eta, eta_d, drifts, floor_acc, base_shear, torsion,
                           captured)  # fmt: skip
