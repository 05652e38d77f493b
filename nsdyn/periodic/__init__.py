"""Periodic solutions under harmonic forcing: shooting, continuation, bifurcation detection.

Seed 004 §6: a periodic orbit of period ``T = 1 / f`` solves ``phi_T(x0; f) - x0 = 0``
(``phi_T`` the period map), found by Newton shooting with the exact monodromy
``Phi = d phi_T / d x0``, whose eigenvalues (Floquet multipliers ``rho``) give stability.

Modules, bottom up: ``discretisation`` (steps and SDIRK tableau per period), ``protocol``
(what the solvers ask of a model: :class:`PeriodicModel`), ``problem`` (the isolated frame and
the Duffing oscillator as such models), ``shooting``, ``sweeps`` (steady states by time
integration), ``bifurcation``, ``curve`` (points and curves), ``arclength`` (the tangent and
corrector of pseudo-arclength), ``continuation`` (sequential and pseudo-arclength, any
:class:`PeriodicModel`), ``response`` (the frame's front door),
``switch`` (the switch model with true stick: exact period map with saltation matrices),
``uplift`` (the amplitude A*(f) at which a steady orbit's normal force first reaches zero),
``unilateral`` (steady states with lift-off and landing by the stepped sweep), ``stability``
(a growth of the discrete map checked against an algebraically stable one before an orbit is
called unstable), ``extrema`` (peaks of a sampled orbit on its dense output), ``plane`` (a mass
or a rigid deck on bidirectional isolators under a harmonic orbit; imported on its own:
``nsdyn.periodic.plane``).
"""

from pathlib import Path

from nsdyn._numba_cache import guard_family

# the kernels call each other, the isolated frame's system kernel and the shared LU
_NSDYN = Path(__file__).resolve().parents[1]
guard_family(
    __file__,
    [
        _NSDYN / "models" / "isolated" / "_kernel.py",
        _NSDYN / "_klinalg.py",
        _NSDYN / "_kborrow.py",
        _NSDYN / "_kaddress.py",
        Path(__file__).resolve().parent / "problem.py",  # the declaration of j_eval's address
    ],
)

# ruff: noqa: E402

from nsdyn.periodic.bifurcation import detect_bifurcations, multiplier_counts
from nsdyn.periodic.continuation import (
    continue_arclength,
    continue_range,
    continue_sequential,
    log_frequencies,
)
from nsdyn.periodic.curve import Curve, OrbitPoint
from nsdyn.periodic.discretisation import ORDER, TABLEAUX, Discretisation, refined
from nsdyn.periodic.problem import (
    PeriodicProblem,
    duffing_problem,
    frame_problem,
    manifold_matrices,
    orbit_quantities,
    uplift_probe,
)
from nsdyn.periodic.protocol import STATUS_MESSAGES, PeriodicModel, PeriodMap
from nsdyn.periodic.response import fixed_base_response, frequency_response
from nsdyn.periodic.shooting import (
    ShootingResult,
    floquet_multipliers,
    orbit_amplitudes,
    period_map,
    shoot,
)
from nsdyn.periodic.stability import check_verdict
from nsdyn.periodic.sweeps import SS_RHO_CAP, SweepResult, steady_state_sweep, warm_start
from nsdyn.periodic.switch import (
    SwitchProblem,
    SwitchShootingResult,
    shoot_switch,
    switch_problem,
    switch_response,
)
from nsdyn.periodic.unilateral import UnilateralPoint, unilateral_steady_state
from nsdyn.periodic.uplift import UpliftBoundary, UpliftPoint, uplift_boundary

__all__ = [
    "ORDER",
    "SS_RHO_CAP",
    "STATUS_MESSAGES",
    "TABLEAUX",
    "Curve",
    "Discretisation",
    "OrbitPoint",
    "PeriodMap",
    "PeriodicModel",
    "PeriodicProblem",
    "ShootingResult",
    "SweepResult",
    "SwitchProblem",
    "SwitchShootingResult",
    "UnilateralPoint",
    "UpliftBoundary",
    "UpliftPoint",
    "check_verdict",
    "continue_arclength",
    "continue_range",
    "continue_sequential",
    "detect_bifurcations",
    "duffing_problem",
    "fixed_base_response",
    "floquet_multipliers",
    "frame_problem",
    "frequency_response",
    "log_frequencies",
    "manifold_matrices",
    "multiplier_counts",
    "orbit_amplitudes",
    "orbit_quantities",
    "period_map",
    "refined",
    "shoot",
    "steady_state_sweep",
    "switch_problem",
    "switch_response",
    "shoot_switch",
    "unilateral_steady_state",
    "uplift_boundary",
    "uplift_probe",
    "warm_start",
]
