"""What shooting, steady-state sweeps and continuation ask of a model: the period map.

A harmonically forced model with period ``T = 1 / f`` supplies the period map

    x0  ->  phi_T(x0; f),     Phi = d phi_T / d x0  (monodromy),     w = d phi_T / d T

on a state ``x = [z, zd]`` of two equal blocks (positions, velocities; ``dim`` entries in all).
Everything else is model-independent: shooting solves ``H(x0, f) = phi_T(x0; f) - x0 = 0``
with ``dH/dx0 = Phi - I``; the Floquet multipliers ``rho`` are the eigenvalues of ``Phi``;
pseudo-arclength continuation needs ``dH/dlog f = -T w``; residuals are scaled per block by the
orbit's largest excursion from the reference state ``x_ref``. A model family reuses
:mod:`nsdyn.periodic.shooting`, :mod:`nsdyn.periodic.sweeps` and
:mod:`nsdyn.periodic.continuation` by supplying an object satisfying :class:`PeriodicModel`
(the isolated frame's and the Duffing oscillator's is
:class:`nsdyn.periodic.problem.PeriodicProblem`).

Optional: ``frozen_rows(pm) -> C (r, dim) | None``, the rows of the state that are frozen on
the orbit of the period map ``pm`` and parametrise a family of orbits (multipliers exactly 1,
``Phi - I`` singular there; e.g. the displacement of an isolator that sticks all period).
Shooting and continuation then hold ``C x0`` at the guess and solve for the rest by least
squares. A map may leave ``dxdT`` None; continuation then differentiates it in ``T``.

Optional: ``exact_map = True`` for a map that is not a discretisation (its multipliers are
the flow's; :mod:`nsdyn.periodic.stability` then checks no growth).

Optional: ``cheap_sensitivities = True`` for a map whose monodromy costs little over the map
itself: shooting's shortened line-search trials then take it at once instead of evaluating
an accepted trial a second time.

A period map reports a status: ``STATUS_OK`` (0) or a failure code of
:data:`STATUS_MESSAGES` (the codes of the fixed-step kernels).

The arguments every solver shares are checked here, once: a forcing frequency ``f > 0``
(finite; the period is ``1 / f``), a frequency range ``0 < fmin < fmax`` with ``points >= 1``
(:func:`check_frequency`, :func:`check_range`) and a finite amplitude (:func:`check_amplitude`).
"""

from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol, runtime_checkable

import numpy as np

from nsdyn._checks import MAX_POINTS, whole
from nsdyn.ground.motion import PGA_TARGET_MAX
from nsdyn.periodic import _kperiodic as kp

if TYPE_CHECKING:
    from nsdyn.periodic.discretisation import Discretisation

STATUS_OK = kp.STATUS_OK  # the period was integrated
STATUS_NOT_STEADY = 4  # sweep: no steady state within the allowed periods
STATUS_MESSAGES = {
    STATUS_NOT_STEADY: "no steady state within the allowed periods",
    kp.STATUS_OK: "ok",
    kp.STATUS_STAGE: "a stage Newton iteration did not converge (try more steps per period)",
    kp.STATUS_SINGULAR: "singular constraint system or iteration matrix",
    kp.STATUS_NONFINITE: "the state became inf/nan (try more steps per period)",
}


# the forcing frequencies a periodic solve takes [Hz]: a period of 11.6 days to 0.1 ms (below
# 1e-6 Hz the period's integration loses the load to round-off: a slip of 1.9e4 m at 1e-10 Hz
# reported as converged on the Coulomb-force scene, whose quasi-static slip is 0.029 m)
F_LOWEST, F_HIGHEST = 1e-6, 1e4


def check_frequency(f, name: str = "f") -> float:
    """``f`` as a float if it is a forcing frequency in [F_LOWEST, F_HIGHEST] Hz (text is
    refused, not converted), else a ValueError naming ``name``."""
    v = math.nan
    if not isinstance(f, str | bool):
        with contextlib.suppress(TypeError, ValueError):
            v = float(f)
    if not (F_LOWEST <= v <= F_HIGHEST):
        raise ValueError(f"{name}: expected a forcing frequency in [{F_LOWEST:g}, "
                         f"{F_HIGHEST:g}] Hz, got {f!r}")  # fmt: skip
    return v


def check_frequencies(freqs, name: str = "freqs") -> None:
    """Each entry of the 1-D array ``freqs`` a forcing frequency (:func:`check_frequency`),
    else a ValueError naming it (``freqs[3]``)."""
    for k, f in enumerate(np.asarray(freqs, dtype=float).tolist()):
        check_frequency(f, f"{name}[{k}]")


# the largest ground acceleration amplitude a periodic solve takes [m/s²]: 100 g, a record's
# largest PGA target (at 1e300 m/s² a sweep's probe overflowed into a traceback)
# normalised |n^T f-| (or touch depth) below which a switch-law orbit counts as grazing: its
# saltation matrices, and its multipliers, are then unreliable (no stability verdict)
GRAZE_TOL = 1e-3
A_HIGHEST = PGA_TARGET_MAX


def check_amplitude(a, name: str = "amplitude", highest: float = math.inf) -> float:
    """``a`` as a float if it is a finite forcing amplitude in [0, ``highest``] (a ground
    acceleration: :data:`A_HIGHEST`), else a ValueError naming ``name``."""
    v = math.nan
    if not isinstance(a, str | bool):  # (text is refused, not converted, as a frequency is)
        with contextlib.suppress(TypeError, ValueError):
            v = float(a)
    if not (math.isfinite(v) and 0 <= v <= highest):
        top = f" and <= {highest:g} m/s² (100 g)" if highest == A_HIGHEST else ""
        raise ValueError(f"{name}: expected a finite forcing amplitude >= 0{top}, got {a!r}")
    return v


def check_range(fmin, fmax, points) -> tuple[float, float, int]:
    """A frequency range of a curve: ``0 < fmin < fmax`` [Hz] and an integer ``points >= 1``
    (``fmin == fmax`` only with one point); ValueError naming the argument otherwise."""
    lo, hi = check_frequency(fmin, "fmin"), check_frequency(fmax, "fmax")
    # (10^12 points ended in numpy's MemoryError of 7 TiB)
    whole(
        "points",
        points,
        1,
        f"an integer from 1 to {MAX_POINTS} (frequencies on the curve; "
        "2 or more unless fmax = fmin)",
    )
    if points > MAX_POINTS:
        raise ValueError(f"points: expected an integer from 1 to {MAX_POINTS} (frequencies on "
                         f"the curve, each a periodic solve), got {points!r}")  # fmt: skip
    if hi < lo or (hi == lo and points > 1):
        raise ValueError(f"fmax: expected a frequency above fmin = {lo:g} Hz, got {hi:g}")
    return lo, hi, int(points)


def check_map_args(x_ref: np.ndarray, x0, n_steps, disc) -> np.ndarray:
    """The start ``x0`` of a period map as a contiguous float array of the problem's state
    (the shape of ``x_ref``, finite), with the map's options checked: ``n_steps`` None or a
    whole number >= 1 (0 steps "mapped" x0 onto itself), ``disc`` None or a
    :class:`Discretisation`. A ValueError or TypeError names the argument: a compiled map read
    past a shorter state (garbage, or a crash of the process)."""
    from nsdyn.periodic.discretisation import checked_disc

    if n_steps is not None:
        whole("n_steps", n_steps, 1, "a whole number of steps >= 1")
    checked_disc(disc)
    try:
        x = np.array(x0, dtype=float)
    except (TypeError, ValueError):
        x = np.full(1, np.nan)
    if x.shape != x_ref.shape or not np.all(np.isfinite(x)):
        bad = "" if np.all(np.isfinite(x)) else " with NaN or inf"
        raise ValueError(f"x0: expected {x_ref.size} finite numbers (the problem's state), "
                         f"got shape {x.shape}{bad}")  # fmt: skip
    return np.ascontiguousarray(x)


@dataclass
class PeriodMap:
    """One period integrated from ``x0``: end state, derivatives, orbit, status."""

    xT: np.ndarray  # (dim,) state after one period
    monodromy: np.ndarray | None  # (dim, dim) d xT / d x0
    dxdT: np.ndarray | None  # (dim,) d xT / d T
    X: np.ndarray | None  # (N + 1, dim) states at the step points
    status: int
    n_steps: int
    n_fev: int
    n_sub: int  # steps that had to be split into substeps


class MinimalStates:
    """Sizes and full-state maps of a problem on minimal coordinates ``q = Q z``: states
    ``x = [z, zd]`` of length ``dim = 2 m``, ``Q`` (n, m) with orthonormal columns. Needs the
    attributes ``x_ref`` and ``Q``."""

    x_ref: np.ndarray
    Q: np.ndarray

    @property
    def dim(self) -> int:
        return self.x_ref.size

    @property
    def m(self) -> int:
        return self.x_ref.size // 2

    def to_full(self, X: np.ndarray) -> np.ndarray:
        """Minimal-coordinate states ``[z, zd]`` (shape (..., 2m)) as full states
        ``[q, qd] = [Q z, Q zd]`` (shape (..., 2n))."""
        Q, m = self.Q, self.m
        return np.concatenate([X[..., :m] @ Q.T, X[..., m:] @ Q.T], axis=-1)

    def to_minimal(self, X: np.ndarray) -> np.ndarray:
        """Full states ``[q, qd]`` as ``[Q^T q, Q^T qd]`` (Q has orthonormal columns: exact on
        the contact manifold R q = 0, its projection elsewhere)."""
        Q, n = self.Q, self.Q.shape[0]
        return np.concatenate([X[..., :n] @ Q, X[..., n:] @ Q], axis=-1)


@runtime_checkable
class PeriodicModel(Protocol):
    """A harmonically forced model as seen by shooting, sweeps and continuation.

    Attributes
    ----------
    x_ref : ndarray, shape (dim,)
        Unforced reference state ``[z, zd]`` (a static equilibrium): the default start and the
        origin of the orbit amplitudes that scale every residual.
    amplitude : float
        Forcing amplitude (recorded on the curves).
    dim : int
        Length of the state (even: positions then velocities).
    """

    x_ref: np.ndarray
    amplitude: float

    @property
    def dim(self) -> int: ...

    def period_map(
        self,
        x0: np.ndarray,
        f: float,
        *,
        n_steps: int | None = ...,
        disc: Discretisation | None = ...,
        sens: bool = ...,
        store: bool = ...,
    ) -> PeriodMap:
        """One period ``T = 1 / f`` from ``x0`` at t = 0 with ``n_steps`` steps (default None:
        ``disc.steps(T)``; ``disc`` None: the default :class:`Discretisation`); ``sens``
        (default True): also ``monodromy`` and ``dxdT``; ``store`` (default False): also
        ``X``."""
        ...

    def orbit_quantities(self, f: float, X: np.ndarray) -> dict:
        """Response quantities of the orbit ``X`` (shape (N + 1, dim), one period)."""
        ...

    def quantities_without_orbit(
        self, f: float, x0: np.ndarray, periods: int = 1
    ) -> tuple[dict, str]:
        """The quantities (NaN or None where unknown) of a point whose period from ``x0`` could
        not be integrated, and a note on why (may be empty); where the model can tell, whether
        a contact lifts off (``uplift``) within ``periods`` periods from ``x0``."""
        ...

    def validity_note(self, quantities: dict) -> str:
        """A remark when ``quantities`` show the model outside its validity, else ``""``."""
        ...
