"""The free-standing rigid block (2B wide, 2H high) on rigid ground; the rocking kernel's driver.

Housner (1963): rotation ``theta`` about the base corner on side ``s = sgn(theta)``::

    theta'' = -p² [(1 + ü_v/g) sin(s alpha - theta) + (ü_h/g) cos(s alpha - theta)]
    p² = m g R / I_O = 3 g / (4 R),  R = sqrt(B² + H²),  alpha = atan(B / H)

Lift-off from rest when ``|ü_h| > (g + ü_v) tan(alpha)``. Impact (theta = 0): angular momentum
about the new pivot is conserved, ``I_O theta'+ = (I_O - 2 m B²) theta'-``, i.e.
``theta'+ = r theta'-`` with Housner's ``r = 1 - (3/2) sin² alpha`` (or a given r; seed 001
Table 2). :func:`simulate_rocking` runs any model exposing ``p``, ``alpha``, ``restitution``,
``linear`` and ``g`` (a block, or a rocking frame reduced to its equivalent block).
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass

import numpy as np

from nsdyn._checks import (
    MAX_STEPS,
    InputWarning,
    NumericalFailure,
    expect,
    flag,
    number,
    output_count,
    output_step,
    rel_tol,
    whole,
)
from nsdyn.ground import G_EARTH, GroundMotion, Harmonic
from nsdyn.ground.pulses import Pulse
from nsdyn.models.rocking import _kblock as kb
from nsdyn.models.rocking._kground import GK_NONE, GK_PULSE, GK_TABLE
from nsdyn.models.rocking.fall import first_fall
from nsdyn.models.rocking.results import OUTCOMES, RockingResult
from nsdyn.models.rocking.rocking_compile import run_integrate
from nsdyn.models.tilt import initial_tilt

TOL = 1e-9  # default relative tolerance of the Dormand-Prince integrator
# the most slender block: width / height >= 1e-4 (alpha ~ 1e-4 rad). Housner's equations scaled
# by alpha do not depend on it as it shrinks, and the overturning spectrum of the seed 003
# column (omega_p / p = 1, 4.47) is the same to 8 digits from 1e-3 to 1e-5 rad; at 1e-6 a false
# safe band appeared, at 1e-12 no overturning up to a_max, at 1e-20 alpha printed as 0
ALPHA_MIN = 1e-4  # (as width / height: a block 10 000 times as tall as wide is the last one)
# fastest pulse or harmonic: 1e3 times the block's p (its steps scale with the pulse: omega_p / p
# = 1e300 ran for minutes); the overturning amplitude grows with omega_p / p, past any record's
OMEGA_RATIO_MAX = 1e3
V_REST_FRAC = 1e-6  # Zeno rest threshold: |theta'+| <= V_REST_FRAC p alpha after an impact
H_MAX_P = 0.5  # largest step, in units of 1/p
MAX_IMPACTS = 200_000  # impact buffer; more impacts raise (too many events)
MAX_PEAKS = 200_000  # peak buffer; further peaks are not stored
THETA_FALL = math.pi / 2  # |theta| at which the block lies on its side: overturned
DT_OUT = 0.01  # default output step without a record [s]


def check_frequency(model, excitation, hz: bool = False) -> None:
    """A pulse or harmonic faster than ``OMEGA_RATIO_MAX`` times the model's ``p`` is refused
    (ValueError "excitation: …", quoted in Hz when ``hz``: a scene's ``f_p``); a record passes."""
    omega = getattr(excitation, "omega_p", 2 * math.pi * getattr(excitation, "f_hor", 0.0))
    if isinstance(excitation, Pulse | Harmonic) and omega > OMEGA_RATIO_MAX * model.p:
        given = f"{omega / (2 * math.pi):.4g} Hz" if hz else f"{omega:.4g} rad/s"
        raise ValueError(f"excitation: a frequency of {given}, {omega / model.p:.6g} times the "
                         f"block's p = {model.p:.4g} /s; expected at most {OMEGA_RATIO_MAX:g} p "
                         "(its steps follow the pulse: 1e7 rad/s ran for minutes)")  # fmt: skip


def housner_restitution(alpha: float) -> float:
    """Housner's coefficient of restitution ``1 - 1.5 sin² alpha`` of a rectangular block of
    slenderness ``alpha`` in (0, pi/2) [rad] (ValueError otherwise); it is positive only for
    alpha < asin(sqrt(2/3)) = 54.7° (a run of a squatter block refuses it: ``restitution_of``)."""
    if not (isinstance(alpha, int | float) and 0.0 < alpha < math.pi / 2):
        raise ValueError(f"alpha: expected a slenderness in (0, pi/2) rad, got {alpha!r}")
    return 1.0 - 1.5 * math.sin(alpha) ** 2


def block_sizes(cls: str, args: tuple, width, height, B, H) -> tuple[float, float]:
    """(width, height) [m] of a block given by full sizes ``width``, ``height`` (the convention
    everywhere, as in scene files) or half sizes ``B``, ``H`` by name; positional sizes are the
    former half sizes (B, H), kept working with a FutureWarning. ValueError names the field."""
    if args:
        warnings.warn(f"{cls}(B, H, ...) with positional half sizes is deprecated: give the full "
                      f"sizes by name, {cls}(width=2B, height=2H, ...)", FutureWarning,
                      stacklevel=3)  # fmt: skip
        if B is not None or H is not None or width is not None or height is not None:
            raise TypeError(f"{cls}: sizes given twice (positionally and by name)")
        B, H = (tuple(args) + (None,))[:2]
    full = width is not None or height is not None
    half = B is not None or H is not None
    if full and half:
        raise ValueError(f"{cls}: give width and height (full sizes) or B and H (half sizes), "
                         "not both")  # fmt: skip
    given = (("B", B, "half width"), ("H", H, "half height")) if half else (
        ("width", width, "full width"), ("height", height, "full height"))  # fmt: skip
    for name, v, what in given:  # (the name given: H = -1 was "height: ..., got -2")
        if v is None:
            raise ValueError(f"{cls}: {name}: missing (the {what} [m])")
        # (numpy scalars are numbers: np.float32(0.3) was refused as no positive size)
        number(f"{cls}: {name}", v, "a positive size [m]", lambda x: x > 0)
    if half:
        width, height = 2 * B, 2 * H
    if why := too_slender(float(width), float(height)):
        raise ValueError(f"{cls}: width: {why}")
    return float(width), float(height)


def too_slender(width: float, height: float) -> str | None:
    """Why a block of these sizes is more slender than :data:`ALPHA_MIN` (as width / height:
    atan(1e-4) < 1e-4 refused the block 10 000 times as tall as wide the message allowed),
    or None."""
    if width >= ALPHA_MIN * height * (1.0 - 1e-12):
        return None
    return (f"width / height = {width / height:.6g}; expected at least {ALPHA_MIN:g} (a block "
            "at most 10 000 times as tall as wide)")  # fmt: skip


def former_positional(args: tuple, values: tuple) -> tuple:
    """The keyword ``values`` after the two sizes, overridden in order by the former positional
    arguments ``args[2:]`` (the pre-width/height call forms)."""
    if len(args) <= 2:
        return values
    return (tuple(args[2:]) + values[len(args) - 2 :])[: len(values)]


class HalfSizes:
    """The half sizes B and H [m] of a body stored by its full ``width`` and ``height``."""

    @property
    def B(self) -> float:
        """Half-width [m]."""
        return 0.5 * self.width

    @property
    def H(self) -> float:
        """Half-height [m]."""
        return 0.5 * self.height


@dataclass(frozen=True, init=False)
class RockingBlock(HalfSizes):
    """Rectangular rigid block of full ``width`` 2B and ``height`` 2H [m].

    ``r``: coefficient of restitution (None: Housner's); ``linear``: use the linearised
    equation; ``mass`` [kg] only scales forces and energies. The half sizes are accepted by
    name too (``RockingBlock(B=0.15, H=0.6)`` is ``RockingBlock(width=0.3, height=1.2)``);
    ``B`` and ``H`` are also read-only attributes.
    """

    width: float
    height: float
    r: float | None = None
    linear: bool = False
    g: float = G_EARTH
    mass: float = 1.0

    def __init__(
        self,
        *args,
        width: float | None = None,
        height: float | None = None,
        r: float | None = None,
        linear: bool = False,
        g: float = G_EARTH,
        mass: float = 1.0,
        B: float | None = None,
        H: float | None = None,
    ) -> None:
        # the former positional (B, H, r, linear, g, mass)
        r, linear, g, mass = former_positional(args, (r, linear, g, mass))
        w, h = block_sizes(type(self).__name__, args[:2], width, height, B, H)
        for name, v in (("width", w), ("height", h), ("r", r), ("linear", flag("linear", linear)),
                        ("g", g), ("mass", mass)):  # fmt: skip
            object.__setattr__(self, name, v)
        for name in ("g", "mass"):
            object.__setattr__(self, name, number(name, getattr(self, name), "a positive number",
                                                  lambda x: x > 0))  # fmt: skip
        if self.r is not None:  # ("0.5" or True: a TypeError, or taken as 1)
            number("r", self.r, "0 <= r <= 1", lambda v: 0.0 <= v <= 1.0)

    @property
    def alpha(self) -> float:
        """Slenderness atan(B/H) [rad]."""
        return math.atan2(self.B, self.H)

    @property
    def R(self) -> float:
        """Semi-diagonal [m]."""
        return math.hypot(self.B, self.H)

    @property
    def p(self) -> float:
        """Frequency parameter sqrt(3 g / 4R) [1/s]."""
        return math.sqrt(3.0 * self.g / (4.0 * self.R))

    @property
    def restitution(self) -> float:
        return housner_restitution(self.alpha) if self.r is None else float(self.r)

    @property
    def uplift_accel(self) -> float:
        """Lift-off ground acceleration g tan(alpha) (g alpha when linearised) [m/s²]."""
        return self.g * (self.alpha if self.linear else math.tan(self.alpha))

    @property
    def I_O(self) -> float:
        """Moment of inertia about a base corner 4 m R² / 3 [kg m²]."""
        return 4.0 * self.mass * self.R**2 / 3.0


def _excitation(excitation, t_end: float, t0: float = 0.0,
                how: str = "t0 = the record's start begins the run with it"):  # fmt: skip
    """(gk, gp, tab_h, tab_v, natural output step) for the kernel; a pulse outside the run
    [t0, t_end] is refused (it drove nothing, unsaid), one starting before t0 warned, as is a
    record starting before t0 (``how``: what begins the run with it)."""
    empty = np.zeros(1)
    if excitation is None:
        return GK_NONE, np.zeros(1), empty, empty, DT_OUT
    given = excitation  # (a Harmonic runs as a train of sine pulses from t = 0)
    if isinstance(excitation, Harmonic):  # (a train of sine pulses from rest, in phase)
        if excitation.A_ver and excitation.f_ver != excitation.f_hor:
            raise ValueError("Harmonic: a vertical component needs f_ver == f_hor here")
        if excitation.phase or (excitation.A_ver and excitation.phase_ver):  # (dropped)
            raise ValueError(f"Harmonic.phase: the rocking models start a harmonic at phase 0 "
                             f"(sine pulses from rest), got phase = {excitation.phase:g}, "
                             f"phase_ver = {excitation.phase_ver:g}")  # fmt: skip
        if excitation.A_ver and not excitation.A_hor:  # (scaled to A_hor: it was dropped)
            raise ValueError("Harmonic.A_hor: the rocking models take a vertical component with "
                             "a horizontal one (A_hor > 0); got a vertical one alone")  # fmt: skip
        ratio = excitation.A_ver / excitation.A_hor if excitation.A_hor else 0.0
        n = int(math.ceil(t_end * excitation.f_hor)) + 1
        excitation = Pulse("sine", excitation.A_hor, 2 * math.pi * excitation.f_hor, n, 0.0, ratio)
    if isinstance(given, Pulse):
        start, end = excitation.t_start, excitation.t_start + excitation.duration
        if not (end > t0 and start < t_end):
            raise ValueError(f"excitation: the pulse runs from {start:g} to {end:g} s, outside "
                             f"the run (t0 = {t0:g} to t_end = {t_end:g} s); expected a pulse "
                             "within it (Pulse t_start)")  # fmt: skip
        if start < t0:
            warnings.warn(f"excitation: the pulse starts at {start:g} s, before the run's "
                          f"start t0 = {t0:g} s: its first {t0 - start:.4g} s are not felt",
                          InputWarning, stacklevel=3)  # fmt: skip
    if isinstance(excitation, Pulse):
        return GK_PULSE, excitation.code(), empty, empty, min(DT_OUT, excitation.T_p / 100.0)
    if isinstance(excitation, GroundMotion):
        if excitation.n < 2:  # (a record of one sample ran as "rest"; the deck refuses it)
            raise ValueError(f"excitation: a record of {excitation.n} sample spans no time; "
                             "expected two samples or more")  # fmt: skip
        if not excitation.t0 < t_end:  # (the run saw none of it: "rest", as a late pulse)
            raise ValueError(f"excitation: the record starts at {excitation.t0:g} s, at or after "
                             f"the run's end t_end = {t_end:g} s; expected a record within the "
                             "run")  # fmt: skip
        from nsdyn.ground.formats import early_record_note

        if note := early_record_note(excitation.t0, t0, how):  # (ran as "rest", unsaid)
            warnings.warn(f"excitation: {note}", InputWarning, stacklevel=3)
        t0, dt, a_h, a_v = excitation.as_arrays()
        has_v = a_v is not None
        tab_v = np.ascontiguousarray(a_v, dtype=float) if has_v else empty
        gp = np.array([t0, dt, 1.0 if has_v else 0.0])
        return GK_TABLE, gp, np.ascontiguousarray(a_h, dtype=float), tab_v, dt
    raise TypeError(
        f"excitation: expected GroundMotion, Pulse, Harmonic or None, got {excitation!r}"
    )


def restitution_of(model) -> float:
    """The model's coefficient of restitution, or ValueError when the one from its shape is
    not positive: Housner's ``1 - 1.5 sin² alpha`` is ≤ 0 for alpha ≥ 54.7° (a block with
    width/height ≥ √2), whose impact in the model ends the rocking; r must then be given."""
    r = model.restitution
    if (
        getattr(model, "r", None) is None and not 0.0 < r <= 1.0
    ):  # (a given 0: plastic, the block stops there)
        raise ValueError(
            f"r: the coefficient of restitution from the shape is {r:.3g} (alpha = "
            f"{math.degrees(model.alpha):.1f}°), not positive: the model's impact would end "
            "the rocking (for a block, Housner's 1 - 1.5 sin² alpha is positive only below "
            "alpha = 54.7°, width/height < √2; a rocking frame's lower still with its beam); "
            "give r"
        )
    return r


def model_params(model, tol: float, h_max: float | None, v_rest: float | None, theta_fall: float):
    """The kernel parameter vector of a block-like model."""
    par = np.zeros(kb.N_PAR)
    p = model.p
    par[kb.P_P2] = p * p
    par[kb.P_ALPHA] = model.alpha
    par[kb.P_R] = restitution_of(model)
    par[kb.P_LINEAR] = 1.0 if model.linear else 0.0
    par[kb.P_G] = model.g
    par[kb.P_TOL] = tol
    par[kb.P_HMAX] = H_MAX_P / p if h_max is None else h_max
    par[kb.P_VREST] = V_REST_FRAC * p * model.alpha if v_rest is None else v_rest
    par[kb.P_THFALL] = theta_fall
    return par


_STATUS = {
    kb.ST_TOO_MANY: "too many impacts",  # (said with max_impacts' value below)
    kb.ST_UNDERFLOW: "step size underflow",
    kb.ST_NONFINITE: "non-finite state",
    kb.ST_FLIGHT: "vertical ground acceleration below -g: free flight is not modelled",
}


def simulate_rocking(
    model,
    excitation: GroundMotion | Pulse | Harmonic | None = None,
    *,
    t_end: float | None = None,
    theta0: float | None = None,
    thetad0: float = 0.0,
    theta0_over_alpha: float | None = None,
    t0: float = 0.0,
    tol: float = TOL,
    dt_out: float | None = None,
    h_max: float | None = None,
    v_rest: float | None = None,
    theta_fall: float = THETA_FALL,
    max_impacts: int = MAX_IMPACTS,
    max_peaks: int = MAX_PEAKS,
) -> RockingResult:
    """Rocking response of ``model`` (:class:`RockingBlock` or a rocking frame) from t0 to t_end.

    Parameters
    ----------
    excitation : GroundMotion, Pulse, Harmonic or None
        Ground acceleration (horizontal, optional vertical) [m/s²]; None: free rocking.
    t_end : float, optional
        End time [s]; default a record's end (a pulse, a harmonic and free rocking need one).
    theta0, thetad0 : float
        Initial rotation [rad] and angular velocity [rad/s].
    theta0_over_alpha : float, optional
        The initial rotation as a fraction of alpha instead of ``theta0`` (give one of them).
    tol : float
        Relative error tolerance of the integrator (absolute scales alpha and p alpha).
    dt_out : float, optional
        Output step (default: the record's dt, T_p/100 for pulses, else 0.01 s); 0: no output.
    t0 : float
        Start time [s], on the excitation's clock.
    h_max : float, optional
        Largest step [s] (default 0.5/p).
    v_rest : float, optional
        Zeno rest threshold on |theta'| after an impact (default 1e-6 p alpha).
    theta_fall : float
        |theta| at which the block has overturned and the run stops (default pi/2) [rad].
    max_impacts, max_peaks : int
        Impacts the run may resolve (more raise: too many events) and peaks it stores.

    Raises
    ------
    RuntimeError
        With the time and the reason if the integration fails (step underflow, non-finite
        state, too many impacts, free flight).
    """
    from nsdyn.models.rocking.compliant import CompliantBlock  # (it imports this module)

    if isinstance(model, CompliantBlock):
        raise TypeError(
            "model: a CompliantBlock rocks on its corner springs, not by Housner's impacts; "
            "run it with nsdyn.simulate_compliant(model, ...)"
        )
    expect(
        "model",
        model,
        hasattr(model, "alpha") and hasattr(model, "p"),
        "a RockingBlock or RockingFrame (nsdyn.RockingBlock(width=..., height=...))",
    )
    t0 = number("t0", t0, "a finite start time [s]")
    if t_end is None and isinstance(excitation, GroundMotion):  # (as nsdyn.simulate)
        t_end = excitation.t0 + excitation.duration
        if not t_end > t0:  # (the error blamed a t_end the caller never gave)
            raise ValueError(f"t_end: the record ends at {t_end:g} s, at or before t0 = "
                             f"{t0:g} s; give t_end or an earlier t0")  # fmt: skip
    elif t_end is None and isinstance(excitation, Pulse | Harmonic | None):
        what = "free rocking" if excitation is None else f"a {type(excitation).__name__}"
        raise TypeError(f"t_end: expected the run's end time [s] (only a record's end is its "
                        f"default), got none for {what}")  # fmt: skip
    elif t_end is None:  # (a record's name: the excitation's own error)
        _excitation(excitation, t0 + 1.0, t0)
    t_end = number("t_end", t_end, f"a finite end time > t0 = {t0:g} s", lambda v: v > t0)
    rel_tol("tol", tol)
    number("thetad0", thetad0, "a finite angular velocity [rad/s]")
    if h_max is not None:  # (0 never returned: steps of zero length; 1e-12 s ran for ever)
        span = t_end - t0
        what = (
            f"a largest step of at least (t_end - t0) / {MAX_STEPS:.0e} = {span / MAX_STEPS:.3g} s"
        )
        number("h_max", h_max, what, lambda v: v > 0 and span / v <= MAX_STEPS)
    if v_rest is not None:
        number("v_rest", v_rest, "a rest threshold >= 0 [rad/s]", lambda v: v >= 0)
    number("theta_fall", theta_fall, "an overturning tilt in (alpha, pi/2] [rad] (the "
           "block falls past it)", lambda v: model.alpha < v <= 0.5 * math.pi)  # fmt: skip
    for name, v in (("max_impacts", max_impacts), ("max_peaks", max_peaks)):
        whole(name, v, 1, "a whole number >= 1")
    output_step(dt_out, t_end - t0)
    check_frequency(model, excitation)
    gk, gp, tab_h, tab_v, dt_nat = _excitation(excitation, t_end, t0)
    dt_out = dt_nat if dt_out is None else dt_out
    n_out = output_count(t_end - t0, dt_out) if dt_out > 0 else 0
    out = np.zeros((n_out, 2))
    imp = np.zeros((max_impacts, 3))
    peaks = np.zeros((max_peaks, 2))
    info = np.zeros(kb.N_INFO)
    par = model_params(model, tol, h_max, v_rest, theta_fall)
    y0 = np.array([initial_tilt(theta0, theta0_over_alpha, model.alpha), float(thetad0)])
    w0 = time.perf_counter()
    work = (np.zeros((7, 2)), np.zeros((5, 2)), np.zeros(2), np.zeros(2))
    t_fall = first_fall(gk, gp, tab_v, t0, t_end, model.g)  # (free flight: the run ends there)
    t_run = t_end if t_fall is None else t_fall
    st = kb.ST_OK
    if t_run > t0:
        st = run_integrate((par, gk, gp, tab_h, tab_v, y0, float(t0), float(t_run),
                            dt_out or 1.0, out, imp, peaks, info, *work))  # fmt: skip
    wall = time.perf_counter() - w0
    if st == kb.ST_OK and t_fall is not None and OUTCOMES[int(info[kb.I_OUTCOME])] != "overturned":
        st, info[kb.I_TFAIL] = kb.ST_FLIGHT, t_fall
    if st != kb.ST_OK:
        why = _STATUS.get(st, st)
        if st == kb.ST_TOO_MANY:  # (a scene has no max_impacts to raise: its t_end it has)
            why = (f"more than max_impacts = {max_impacts} impacts (raise it, or shorten "
                   "t_end: a scene's motion.t_end)")  # fmt: skip
        raise NumericalFailure(f"rocking integration failed at t = {info[kb.I_TFAIL]:.6g} s: "
                               f"{why}")  # fmt: skip
    n = int(info[kb.I_NOUT])
    n_imp = int(info[kb.I_NIMP])
    n_pk = int(info[kb.I_NPEAK])
    return RockingResult(
        t=t0 + dt_out * np.arange(n) if n else np.zeros(0),
        theta=out[:n, 0].copy(),
        thetad=out[:n, 1].copy(),
        impacts=imp[:n_imp].copy(),
        peaks=peaks[:n_pk].copy(),
        alpha=model.alpha,
        p=model.p,
        r=model.restitution,
        linear=bool(model.linear),
        outcome=OUTCOMES[int(info[kb.I_OUTCOME])],
        t_overturn=float(info[kb.I_TOVER]),
        t_rest=float(info[kb.I_TREST]),
        t_uplift=float(info[kb.I_TUPL]),
        max_abs_theta=float(info[kb.I_MAXTH]),
        n_steps=int(info[kb.I_NSTEP]),
        n_rejected=int(info[kb.I_NREJ]),
        n_rhs=int(info[kb.I_NRHS]),
        n_uplifts=int(info[kb.I_NUPL]),
        wall_s=wall,
    )


def warmup() -> float:
    """Compile (or load from cache) the rocking kernel; returns the seconds it took."""
    w0 = time.perf_counter()
    blk = RockingBlock(width=0.4, height=2.0)
    simulate_rocking(blk, Pulse("sine", 5.0, 10.0), t_end=0.05, dt_out=0.01, max_impacts=4,
                     max_peaks=4)  # fmt: skip
    return time.perf_counter() - w0
