"""Frequency–amplitude curves of the fixed rung of a space frame: the steady harmonic response.

The fixed-base building is linear, so under the harmonic ground acceleration of a scene's orbit
(:mod:`nsdyn.ground.orbit`, the vertical at the horizontal frequency)

    a_g(t) = Im{A e^{iΩt}},   A = (A_x, A_y e^{iφ_y}, A_z e^{iφ_z}),

its steady state is exactly u(t) = Im{U(Ω) e^{iΩt}} (relative to the ground) with

    U(Ω) = (K − Ω² M + iΩ C)⁻¹ (−M R A),   R = [r_x, r_y, r_z] the rigid translations,

K, M the diaphragm-reduced matrices with the base clamped and C the frame's modal damping
(ζ_k on mode k, the last ratio for every further mode). In the mass-normalised fixed-base
modes (φ_k, ω_k, Γ_k = φ_kᵀ M R):

    U(Ω) = Σ_k φ_k η_k(Ω) + U_res,   η_k(Ω) = −Γ_k·A / (ω_k² − Ω² + 2iζ_k ω_k Ω),
    U_res = K⁻¹(−M R A) − Σ_k φ_k (−Γ_k·A) / ω_k²,

the kept modes exact and the modes above them taken quasi-statically (the mode-acceleration
correction U_res; ``static_correction=False`` drops it). So U(0) is the static response to
the inertia load −M R A for any number of kept modes, and |η_k| peaks at Ω = ω_k √(1 − 2ζ_k²).

Each output is the peak over a period of a harmonic quantity: a scalar phasor D gives |D|; the
roof's horizontal phasor P = (U_x, U_y) at its reference point (the centre of mass of a
diaphragm roof) traces an ellipse whose largest radius is

    max_t |Im(P e^{iΩt})| = √(½ (|P|² + |P_x² + P_y²|)).

Outputs per frequency: roof displacement (that radius) [m], roof twist |Θ| [rad], the largest
storey drift ratio at the plan corners and at the centres of mass (over storeys and x, y).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from nsdyn.models.scenefile import SceneError
from nsdyn.structure.frame3d import Frame3D
from nsdyn.structure.modes3d import Modes3D, fixed_base_modes_3d
from nsdyn.structure.storey3d import floor_motions, storey_drifts_3d

__all__ = ["FixedFRF", "fixed_frf", "fixed_sweep_scene", "orbit_phasor", "peak_radius"]

POINTS_DEFAULT = 400  # log-spaced frequencies (a point costs microseconds)
RANGE = (0.25, 1.25)  # default range: f_1 / 4 .. 1.25 × the highest kept mode
COLUMNS = ("f", "A", "roof_displacement_m", "roof_twist_rad", "corner_drift", "cm_drift")


def peak_radius(P: np.ndarray) -> np.ndarray:
    """max_t |Im(P e^{iΩt})| of phasors P (2, ...): √(½(|P|² + |P_x² + P_y²|))."""
    P = np.asarray(P, complex)
    return np.sqrt(0.5 * ((np.abs(P) ** 2).sum(axis=0) + np.abs((P**2).sum(axis=0))))


def orbit_phasor(orbit) -> np.ndarray:
    """A = (A_x, A_y e^{iφ_y}, A_z e^{iφ_z}) of a :class:`~nsdyn.ground.orbit.HarmonicPlane`
    (ValueError for a vertical at another frequency than the horizontal pair)."""
    az = float(orbit.az or 0.0)
    if az and not math.isclose(orbit.vertical_frequency, orbit.f, rel_tol=1e-12):
        raise ValueError(f"the steady response is one harmonic only with the vertical at the "
                         f"horizontal frequency {orbit.f:g} Hz (or none), got "
                         f"{orbit.vertical_frequency:g} Hz")  # fmt: skip
    return np.array([orbit.ax, orbit.ay * np.exp(1j * math.radians(orbit.phase_y_deg)),
                     az * np.exp(1j * math.radians(orbit.phase_z_deg))])  # fmt: skip


@dataclass(frozen=True, eq=False)
class FixedFRF:
    """Curves of :func:`fixed_frf` (module docstring) for the excitation phasor ``A``."""

    f_hz: np.ndarray
    A: np.ndarray
    modes: Modes3D
    eta: np.ndarray  # (m, nf) modal amplitudes
    roof_m: np.ndarray
    roof_twist_rad: np.ndarray
    corner_drift: np.ndarray
    cm_drift: np.ndarray
    static_correction: bool = True

    def rows(self, amplitude: float | None = None) -> list[dict]:
        """One dict per frequency (``COLUMNS``); ``amplitude`` labels the column A."""
        a = float(peak_radius(self.A[:2])) if amplitude is None else float(amplitude)
        cols = (self.f_hz, self.roof_m, self.roof_twist_rad, self.corner_drift, self.cm_drift)
        return [{"f": float(f), "A": a, "roof_displacement_m": float(r),
                 "roof_twist_rad": float(t), "corner_drift": float(c), "cm_drift": float(d)}
                for f, r, t, c, d in zip(*cols, strict=True)]  # fmt: skip


def _static(frame: Frame3D, K, load: np.ndarray) -> np.ndarray:
    """K⁻¹ load with the base clamped (reduced dofs), complex load solved as two real ones."""
    b = frame.boundary_reduced
    i = np.setdiff1d(np.arange(frame.n_red), b)
    lu = spla.splu(sp.csc_array(K[i][:, i]))
    out = np.zeros(frame.n_red, complex)
    out[i] = lu.solve(np.ascontiguousarray(load[i].real)) + 1j * lu.solve(
        np.ascontiguousarray(load[i].imag)
    )
    return out


def fixed_frf(frame: Frame3D, A, f_hz, *, n_modes: int = 24, modes: Modes3D | None = None,
              static_correction: bool = True) -> FixedFRF:  # fmt: skip
    """Steady harmonic response of ``frame`` on a fixed base to a_g = Im{A e^{iΩt}} at the
    frequencies ``f_hz`` (≥ 0), from ``n_modes`` modes (or ``modes``) and the static
    correction (module docstring)."""
    f = np.asarray(f_hz, float)
    if f.ndim != 1 or f.size < 1 or not np.all(np.isfinite(f)) or np.any(f < 0):
        raise ValueError(f"f_hz: expected finite frequencies >= 0 [Hz], got {f_hz!r}")
    A = np.asarray(A, complex).reshape(3)
    if modes is None:
        modes = fixed_base_modes_3d(frame, n_modes=n_modes)
    K, M = frame.reduced()
    phi = modes.phi
    w = 2 * np.pi * modes.f_hz
    m = len(w)
    zeta = frame.zeta[np.minimum(np.arange(m), len(frame.zeta) - 1)]
    R = frame.rigid_motions()[:, :3]
    load = -(M @ (R @ A))  # −M R A, reduced
    q = phi.T @ load  # modal loads −Γ_k·A
    Om = 2 * np.pi * f
    eta = q[:, None] / (w[:, None] ** 2 - Om[None, :] ** 2 + 2j * (zeta * w)[:, None] * Om[None, :])
    shapes = [phi]
    coef = [eta]
    if static_correction:  # real and imaginary parts as two real shapes (the maps are real)
        res = _static(frame, K, load) - phi @ (q / w**2)
        shapes.append(np.column_stack([res.real, res.imag]))
        coef.append(np.vstack([np.ones(f.size), 1j * np.ones(f.size)]))
    S = frame.expand(np.hstack(shapes))
    C = np.vstack(coef)
    roof = floor_motions(frame, S)[2][-1]  # (3, m [+1]) roof U_x, U_y, Θ
    dr = storey_drifts_3d(frame, S)
    P = roof[:2] @ C  # (2, nf)
    corner = np.abs(np.einsum("scdk,kf->scdf", dr.corner, C)).max(axis=(0, 1, 2))
    cm = np.abs(np.einsum("sdk,kf->sdf", dr.cm, C)).max(axis=(0, 1))
    out = FixedFRF(f, A, modes, eta, peak_radius(P), np.abs(roof[2] @ C), corner, cm,
                   static_correction)  # fmt: skip
    bad = ~np.isfinite(out.roof_m) | ~np.isfinite(out.corner_drift)
    if bad.any():
        raise FloatingPointError(f"steady response not finite at f = {f[bad][0]:g} Hz")
    return out


def fixed_sweep_scene(cfg: dict, source: str) -> dict:
    """{"frame", "n_modes", "orbit", "A" (unit-amplitude phasor), "amplitude", "name"} of a
    ``building3d`` scene at the fixed fidelity under a harmonic orbit (SceneError naming the
    field)."""
    from nsdyn.ground.orbit import NOT_AN_ORBIT, HarmonicPlane
    from nsdyn.models.isolated import building3d_scene as bs

    sysd = bs.build_system(cfg, source)
    if sysd["fidelity"] != "fixed":
        raise SceneError(f"{source}: structure.fidelity: the frequency response of the fixed "
                         f"rung needs fidelity = 'fixed', got {sysd['fidelity']!r}")  # fmt: skip
    orbit, _ = bs.build_motion(cfg, source)
    if not isinstance(orbit, HarmonicPlane):
        raise SceneError(f"{source}: {NOT_AN_ORBIT}")
    try:
        A = orbit_phasor(orbit)
    except ValueError as e:
        raise SceneError(f"{source}: motion.vertical_frequency: {e}") from None
    amp = float(peak_radius(A[:2]))
    if not amp > 0:
        raise SceneError(f"{source}: motion.amplitude: the horizontal amplitude is zero")
    name = cfg.get("scene", {}).get("name", Path(source).stem)
    return {"frame": sysd["frame"], "n_modes": sysd["n_modes"], "orbit": orbit, "A": A / amp,
            "amplitude": amp, "name": name,
            "n_modes_given": sysd.get("n_modes_given", True)}  # fmt: skip


def default_range(modes: Modes3D) -> tuple[float, float]:
    """(f_1 RANGE[0], f_m RANGE[1]) over the kept modes."""
    return float(modes.f_hz[0] * RANGE[0]), float(modes.f_hz[-1] * RANGE[1])
