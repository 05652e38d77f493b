"""Bearings that slide in a plane: friction laws and bearing descriptions, validated and packed.

Friction of a bidirectional isolator with normal force N and slip velocity v = (v_x, v_y):

    kinetic coefficient   μ_d(|v|) = μ_fast − (μ_fast − μ_slow) exp(−a |v|)   (PTFE/steel fit)
    static coefficient    μ_s ≥ max(μ_slow, μ_fast)                           (stick disc)
    regularised law       f = μ_d(|v|) N (2/π) arctan(ε |v|) v/|v|
    switch law            slip f = μ_d(|v|) N v/|v|;  stick |τ| ≤ μ_s N (τ a constraint force)

f and τ are the forces the bearing *resists* with (the deck feels −f). With μ_slow = μ_fast =
μ_s = μ the regularised law restricted to one line is seed 004's arctan law (eq 7) and the
switch law its switch model (eqs 4–6).

One description covers the flat slider and the single friction pendulum (the bearing's
restoring force, resisting, on slip u):

    F_r = N u / R + K_lam u,     F_d = c v,     R = inf for a flat slider (seed 004: K_lam, c)

and its displacement capacity d_cap: beyond |u| = d_cap the restrainer rim acts as a stiff
radial stop F_s = max(0, k_stop δ + c_stop δ̇) u/|u|, δ = |u| − d_cap, whose contact is
reported (first time, peak overshoot), never passed silently. Defaults of the stop: k_stop =
STOP_STIFFNESS_FACTOR × (N_0/R + K_lam) with N_0 the static normal force, c_stop =
2 ζ_stop √(k_stop N_0/g) with ζ_stop = STOP_DAMPING_RATIO.

Pressure-dependent friction (optional: the bearing's contact ``area`` and the reference pressure
``p_ref`` at which the coefficients above hold): every coefficient is scaled by

    k_p(p) = 0.7^((p − p_ref) / 50 MPa),   p = N / area      (PTFE-type composites; Kumar,
                                                             Whittaker & Constantinou 2015)

at the live normal force N, so friction falls as the contact pressure rises.
"""

from __future__ import annotations

import math
import warnings
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from nsdyn.ground.excitation import G_EARTH

STOP_STIFFNESS_FACTOR = 100.0  # default rim stiffness / post-slip stiffness at the static load
STOP_DAMPING_RATIO = 0.1  # default rim damping ratio (on the bearing's static mass share)

# columns of the packed bearing table (one row per isolator), read by _kplane
B_RINV, B_KLAM, B_C, B_MUS, B_MUSLOW, B_MUFAST, B_RATE, B_DCAP, B_KSTOP, B_CSTOP = range(10)
# the least μ_s of a packed row: the stick tests' disc |τ| <= μ_s N keeps a radius at μ_s = 0,
# so a frictionless isolator's stick function μ_s N − |τ| starts positive and its first shear
# force releases it (at 0 it would start at 0 and never cross: stuck for ever)
MU_S_FLOOR = 1e-12
# a triple friction pendulum's series model (nsdyn.models.isolated.tfp; zero for the others):
# its kind, the index of its internal slips in the state vector, the elastic stiffness and the
# flow's time constant, then (1/R, mu, d, k_stop) of its four series elements
B_KIND, B_IOFF, B_KEL, B_TAU = range(10, 14)
B_ELEM = 14  # element k: columns B_ELEM + 4 k + (0: 1/R, 1: mu, 2: d, 3: k_stop per unit N)
# pressure-dependent friction: contact area [m²] (0: none) and reference pressure [Pa]
B_AREA, B_PREF = B_ELEM + 16, B_ELEM + 17
# a triple pendulum's velocity-dependent surfaces: element k's μ_fast at B_EFAST + k, the rate a
B_EFAST, B_ERATE = B_ELEM + 18, B_ELEM + 22
B_CEL = B_ELEM + 23  # a triple pendulum's dashpot across its elastic stage (per unit N) [s/m]
N_BCOL = B_ELEM + 24
PRESSURE_BASE, PRESSURE_SCALE = 0.7, 50.0e6  # μ(p) = μ(p_ref) 0.7^((p − p_ref)/50 MPa)
# the least pressure factor: 0.7^x underflows to 0 beyond x ~ 2090, and a zero factor makes
# the stick disc μ_s k_p N a point again (stuck for ever, as MU_S_FLOOR above prevents)
K_P_FLOOR = 1e-12
KIND_SINGLE, KIND_TFP = 0, 1


class BearingError(ValueError):
    """A bearing or friction field is invalid; the message names the field."""


def _number(where: str, v, *, positive: bool = False, allow_inf: bool = False) -> float:
    if isinstance(v, bool) or not isinstance(v, int | float | np.floating | np.integer):
        raise BearingError(f"{where}: expected a number, got {v!r}")
    v = float(v)
    if math.isnan(v) or (math.isinf(v) and not allow_inf):
        raise BearingError(f"{where}: expected a finite number, got {v}")
    if positive and not v > 0:
        raise BearingError(f"{where}: expected a positive number, got {v:g}")
    if not positive and v < 0:
        raise BearingError(f"{where}: expected a non-negative number, got {v:g}")
    return v


@dataclass(frozen=True)
class Friction:
    """Friction coefficients of a sliding surface.

    ``mu_slow``: kinetic μ at vanishing speed; ``mu_fast`` (default ``mu_slow``): at high speed;
    ``rate`` a [s/m] of μ_d(|v|) = μ_fast − (μ_fast − μ_slow) exp(−a|v|); ``mu_static``
    (default the largest kinetic value) the radius of the stick disc, μ_s ≥ μ_d.
    """

    mu_slow: float
    mu_fast: float | None = None
    rate: float = 0.0
    mu_static: float | None = None
    where: str = "friction"

    def __post_init__(self) -> None:
        w = self.where
        slow = _number(f"{w}.mu_slow", self.mu_slow)
        fast = slow if self.mu_fast is None else _number(f"{w}.mu_fast", self.mu_fast)
        rate = _number(f"{w}.rate", self.rate)
        if rate > 0 and self.mu_fast is None:  # (a rate alone was dropped without a word)
            raise BearingError(f"{w}.rate: the rate of the change from mu_slow to mu_fast; "
                               "expected mu_fast beside it (or no rate)")  # fmt: skip
        if fast != slow and rate == 0.0:
            raise BearingError(
                f"{w}.rate: mu_fast ({fast:g}) differs from mu_slow ({slow:g}), which needs a "
                "positive rate a [s/m] of mu(v) = mu_fast - (mu_fast - mu_slow) exp(-a |v|) "
                "(with a = 0, mu is mu_slow at every speed)"
            )
        mu_d = max(slow, fast)
        if self.mu_static is not None:
            mus = _number(f"{w}.mu_static", self.mu_static)
            if mus < mu_d:
                raise BearingError(
                    f"{w}.mu_static: expected mu_static >= the kinetic coefficient "
                    f"({mu_d:g}), got {mus:g} (static friction below kinetic)"
                )

    @property
    def fast(self) -> float:
        return float(self.mu_slow if self.mu_fast is None else self.mu_fast)

    @property
    def static(self) -> float:
        if self.mu_static is None:
            return max(float(self.mu_slow), self.fast)
        return float(self.mu_static)

    def kinetic(self, speed) -> np.ndarray:
        """μ_d at the slip speed(s) |v| [m/s]."""
        s = np.abs(np.asarray(speed, dtype=float))
        return self.fast - (self.fast - float(self.mu_slow)) * np.exp(-float(self.rate) * s)


@dataclass(frozen=True)
class Bearing:
    """One bidirectional isolator: a flat slider (``radius`` = inf) or a single friction
    pendulum (effective radius R [m]), with rubber ``k_lam`` [N/m], damper ``c`` [N s/m],
    displacement capacity ``d_cap`` [m] (inf: none) and optional rim stop ``k_stop`` [N/m],
    ``c_stop`` [N s/m] (defaults from the static normal force, see the module text).
    ``area`` [m²] and ``p_ref`` [Pa], given together: friction that depends on the contact
    pressure N/area (module text). ``where`` names the bearing in its messages. A field out
    of range raises :class:`BearingError` (a ValueError) naming it."""

    friction: Friction
    radius: float = math.inf
    k_lam: float = 0.0
    c: float = 0.0
    d_cap: float = math.inf
    k_stop: float | None = None
    c_stop: float | None = None
    where: str = "bearing"
    area: float | None = None
    p_ref: float | None = None

    def __post_init__(self) -> None:
        w = self.where
        self._check_pressure()
        if not isinstance(self.friction, Friction):
            raise BearingError(f"{w}.friction: expected a Friction, got {self.friction!r}")
        _number(f"{w}.radius", self.radius, positive=True, allow_inf=True)
        _number(f"{w}.k_lam", self.k_lam)
        _number(f"{w}.c", self.c)
        _number(f"{w}.d_cap", self.d_cap, positive=True, allow_inf=True)
        if self.k_stop is not None:
            _number(f"{w}.k_stop", self.k_stop, positive=True)
        if self.c_stop is not None:
            _number(f"{w}.c_stop", self.c_stop)
        for key in ("k_stop", "c_stop"):  # the rim's stiffness and damping act at d_cap only
            if getattr(self, key) is not None and math.isinf(self.d_cap):
                raise BearingError(f"{w}.{key}: the rim stop acts beyond the displacement "
                                   "capacity; give d_cap [m] (none: no rim)")  # fmt: skip
        if math.isfinite(self.d_cap) and self.d_cap >= self.radius:  # (past the sphere's edge)
            raise BearingError(f"{w}.d_cap: expected a displacement capacity below the radius "
                               f"R = {self.radius:g} m, got {self.d_cap:g} m")  # fmt: skip
        said = stick_range_error(self)  # (refused when the bearing is made, not at its run)
        if said:
            raise BearingError(said)
        if math.isinf(self.radius) and self.k_lam == 0.0 and math.isfinite(self.d_cap):
            if self.k_stop is None:
                raise BearingError(
                    f"{w}.k_stop: a flat slider without rubber (k_lam = 0) and a displacement "
                    "capacity needs the rim stiffness k_stop [N/m]"
                )

    def _check_pressure(self) -> None:
        if (self.area is None) != (self.p_ref is None):
            k = "p_ref" if self.p_ref is None else "area"
            raise BearingError(f"{self.where}.{k}: missing; pressure-dependent friction needs "
                               "the contact area [m²] and the reference pressure [Pa]")  # fmt: skip
        if self.area is not None:
            _number(f"{self.where}.area", self.area, positive=True)
            _number(f"{self.where}.p_ref", self.p_ref, positive=True)

    def pressure_factor(self, normal_force) -> np.ndarray:
        """μ(p)/μ(p_ref) = 0.7^((p − p_ref)/50 MPa) at p = N/area (1 without an area)."""
        n = np.asarray(normal_force, dtype=float)
        if self.area is None:
            return np.ones_like(n)
        p = np.maximum(n, 0.0) / float(self.area)
        return np.maximum(PRESSURE_BASE ** ((p - float(self.p_ref)) / PRESSURE_SCALE), K_P_FLOOR)

    def coefficients(self) -> dict:
        """The friction coefficients given, by their field names."""
        f, w = self.friction, self.where
        named = {"mu_slow": f.mu_slow, "mu_fast": f.mu_fast, "mu_static": f.mu_static}
        return {f"{w}.{k}": float(v) for k, v in named.items() if v is not None}

    @property
    def period(self) -> float:
        """Isolated period 2π√(R/g) of a pendulum without rubber [s] (inf when flat)."""
        return (
            2 * math.pi * math.sqrt(self.radius / G_EARTH)
            if math.isfinite(self.radius)
            else math.inf
        )

    def row(self, n_static: float, g: float) -> np.ndarray:
        """The packed row of this bearing at static normal force ``n_static`` [N]."""
        f = self.friction
        r = np.zeros(N_BCOL)
        r[B_RINV] = 0.0 if math.isinf(self.radius) else 1.0 / self.radius
        r[B_KLAM], r[B_C] = self.k_lam, self.c
        r[B_MUS] = max(f.static, MU_S_FLOOR)
        r[B_MUSLOW], r[B_MUFAST], r[B_RATE] = f.mu_slow, f.fast, f.rate
        r[B_DCAP] = self.d_cap
        k_post = n_static * r[B_RINV] + self.k_lam
        ks = STOP_STIFFNESS_FACTOR * k_post if self.k_stop is None else float(self.k_stop)
        m_share = max(n_static, 0.0) / g
        cs = (  # (√ks √m: their product overflowed for masses near 1e300 kg)
            2 * STOP_DAMPING_RATIO * math.sqrt(ks) * math.sqrt(m_share)
            if self.c_stop is None
            else self.c_stop
        )
        r[B_KSTOP], r[B_CSTOP] = ks, cs
        if self.area is not None:
            r[B_AREA], r[B_PREF] = self.area, self.p_ref
        return r


MU_PLAUSIBLE = 1.0  # sliding isolators' coefficients are 0.01-0.2; above 1: a percentage?
PRESSURE_RATIO_PLAUSIBLE = 10.0  # static pressure / p_ref beyond which the units are suspect
RADIUS_PLAUSIBLE = 20.0  # m: a pendulum radius past this (a period of 9 s and more) is said
# a triple pendulum's smallest friction below this is said before its run: its surfaces' flow
# rule, of viscosity OVERSTRESS min mu (tfp.py; u_y barely matters), sets its steps (the
# example deck, every surface at mu: its 40 s record in 18 000 steps at 1e-4, 540 000 (3.5 min)
# at 3e-5; at 1e-5 the steps collapsed after 3 min)
MU_TFP_LOW = 1e-4


def high_friction_note(field: str, mu: float) -> str | None:
    """A line on a friction coefficient above ``MU_PLAUSIBLE`` (None for a plausible one)."""
    if not mu > MU_PLAUSIBLE:
        return None
    return (f"{field} = {mu:g}: a friction coefficient above 1 (sliding isolators' are about "
            "0.01-0.2); a percentage given as a number?")  # fmt: skip


# an isolator spring past this many times the structure's stiffest diagonal entry, on a model
# whose normal forces are constraint forces, is refused: the run's normal forces go wrong with
# no error (the office frame, stiffest entry 2.7e10 N/m: at k_lam = 1e17 its minimum normal
# force and peaks held to 1e-5, at 1e18 the minimum fell from 3.14e6 N to 1.29e6 N, exit 0;
# its static state held to 1e-14 at both). A shear building's given normal force is unmoved.
STIFF_BEARING_RATIO = 1e6


def stiff_bearing_check(k_lam, K_diag, field: str = "isolation.k_lam", frame: bool = True):
    """ValueError naming ``field`` when an isolator spring ``k_lam`` passes
    :data:`STIFF_BEARING_RATIO` times the largest of the structure's diagonal stiffnesses
    ``K_diag`` (none, as a rigid deck's: not checked). For models with contact rows;
    ``frame``: the structure is a frame's, whose fixed-base model the message suggests."""
    k, stiff = np.max(k_lam, initial=0.0), np.max(np.abs(K_diag), initial=0.0)
    if stiff > 0 and k > STIFF_BEARING_RATIO * stiff:
        fixed = ("the frame's fixed-base model (fidelity 'fixed', nsdyn run --fixed-base)"
                 if frame else "the structure's matrices without the isolators")  # fmt: skip
        raise ValueError(f"{field}: expected an isolator spring of at most "
                         f"{STIFF_BEARING_RATIO:g}x the structure's stiffest entry ({stiff:.3g} "
                         f"N/m), got {k:g} N/m: beside so stiff a spring the run's normal "
                         f"forces go wrong; a base held fixed is {fixed}")  # fmt: skip


# a contact stabilisation alpha [1/s] past this is said where contacts lift off: its
# alpha^2 R q equals gravity at a gap of g/alpha^2 (1e-7 m at 1e4), within ten times the drift
# a run's contacts keep after landings (~1e-8 m), and the lift-offs begin to follow the
# stabilisation (the bundled uplift-pocket scene, 16 periods: 47-54 lift-offs from alpha =
# 2 pi to 1e4, 83 at 2e4, 232 at 3e4, 886 at 1e5, each with exit 0)
ALPHA_PLAUSIBLE = 1e4


@contextmanager
def stabilisation_unsaid():
    """The block's Isolation notes of :func:`stabilisation_note` left unsaid: a command whose own
    contact setting decides whether alpha acts (a sweep's --contact; uplift's bilateral orbits)
    says it, or not, itself."""
    from nsdyn._checks import NotedWarning

    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", r"isolation\.alpha = ", NotedWarning)
        yield


def stabilisation_note(field: str, alpha: float, g: float = 9.81) -> str | None:
    """A line on a Baumgarte ``alpha`` above :data:`ALPHA_PLAUSIBLE` (None below), for a
    model whose contacts lift off (``contact = "unilateral"``)."""
    if not alpha > ALPHA_PLAUSIBLE:
        return None
    return (f"{field} = {alpha:g} 1/s: the contacts' stabilisation alpha^2 R q equals gravity "
            f"at a gap of g/alpha^2 = {g / alpha**2:.2g} m, within ten times the drift a run's "
            "contacts keep after landings (~1e-8 m): lift-offs and landings then begin to "
            "follow the stabilisation, not the motion (the default is 2 pi)")  # fmt: skip


G_PLAUSIBLE = (9.7, 9.9)  # [m/s²] Earth's gravity, 9.78 at the equator to 9.83 at the poles


def gravity_note(field: str, g: float) -> str | None:
    """A line on a gravity outside :data:`G_PLAUSIBLE` (None for Earth's): the normal forces,
    and the friction with them, scale with it (g = 9810 in mm/s² ran with friction 1000x)."""
    lo, hi = G_PLAUSIBLE
    if lo <= g <= hi:
        return None
    guess = "in mm/s²?" if g > 100 * lo else "in g?" if g < 2 else "another planet's?"
    return (f"{field} = {g:g} m/s²: Earth's gravity is 9.81 m/s², and the normal forces and "
            f"their friction scale with it; {guess}")  # fmt: skip


def stick_range_error(b) -> str | None:
    """The refusal of a pendulum ``b`` whose rim lies within its stick range, d_cap <= mu_s R
    (it may rest on its rim), naming a coefficient above 1 as the likely cause; else None."""
    need = b.friction.static * b.radius
    if not (math.isfinite(b.d_cap) and math.isfinite(b.radius) and b.d_cap <= need):
        return None
    hint = high_friction_note("mu_s", b.friction.static)  # (mu = 4: the note came too late)
    if hint is None and b.radius > RADIUS_PLAUSIBLE:  # (R = 2200 in mm: the radius is named)
        return (f"{b.where}.radius: R = {b.radius:g} m is above the {RADIUS_PLAUSIBLE:g} m of "
                f"built pendulums (in cm or mm?): its stick range mu_s R = {need:g} m passes the "
                f"capacity d_cap = {b.d_cap:g} m; expected R in m")  # fmt: skip
    return (f"{b.where}.d_cap: {b.d_cap:g} m is not above the pendulum's stick range mu_s R = "
            f"{need:g} m (it may rest on its rim); expected d_cap > mu_s R"
            + (f" ({hint})" if hint else ""))  # fmt: skip


U_OVER_R_SMALL = 0.25  # a pendulum slip beyond this x R: its linear law N u/R errs > 3 %


def slip_ratio_note(bearings, peak_u) -> str | None:
    """One line when a pendulum's peak slip |u| passes U_OVER_R_SMALL of its radius: the
    restoring force N u/R is the small-angle form of the sphere's N u/√(R² − u²), which is
    1/√(1 − (u/R)²) − 1 larger there. ``peak_u``: one per isolator [m]."""
    pairs = enumerate(zip(bearings, peak_u, strict=True))
    ratios = [(float(u) / b.radius, i) for i, (b, u) in pairs if math.isfinite(b.radius)]
    if not ratios or max(ratios)[0] <= U_OVER_R_SMALL:
        return None
    r, i = max(ratios)
    of = f"{r:.3g} times" if r >= 1.0 else f"{r:.3g} of"  # (it read "10 of its radius")
    head = f"isolator {i}'s peak slip is {of} its radius R = {bearings[i].radius:g} m: "
    if r >= 1.0:  # (it read "inf % larger")
        return (head + "past the sphere's edge (no surface of radius R reaches that far): the "
                "small-angle restoring force N u/R holds there for no bearing")  # fmt: skip
    more = 1.0 / math.sqrt(1.0 - r * r) - 1.0
    return (head + "the pendulum's restoring force N u/R is its small-angle form (on the "
            f"sphere, N u/sqrt(R² - u²) is {100 * more:.3g} % larger there)")  # fmt: skip


def bearing_notes(bearings, n_static) -> list[str]:
    """Inputs a run accepts that are probably mistakes, one line each: a friction coefficient
    above 1, a static contact pressure N/area more than 10× from ``p_ref`` (area in cm²,
    p_ref in MPa?), with the friction factor it gives, a friction that falls with the slip
    speed, a triple pendulum's friction below :data:`MU_TFP_LOW` (a long run), or a pendulum
    radius above :data:`RADIUS_PLAUSIBLE` (in mm?). ``bearings``: one per isolator."""
    n_static = np.asarray(n_static, dtype=float)
    notes: list[str] = []
    for k, v in {k: v for b in bearings for k, v in b.coefficients().items()}.items():
        notes += [n for n in [high_friction_note(k, v)] if n]
    for i, b in enumerate(bearings):
        if b.area is None or not n_static[i] > 0:
            continue
        p = n_static[i] / b.area
        if max(p / b.p_ref, b.p_ref / p) > PRESSURE_RATIO_PLAUSIBLE:
            k_p = float(b.pressure_factor(n_static[i]))
            notes.append(
                f"{b.where}.area: the static pressure N/area at isolator {i} is {p / 1e6:.3g} "
                f"MPa, {p / b.p_ref:.3g}x p_ref = {b.p_ref / 1e6:.3g} MPa, so its friction is "
                f"{k_p:.3g}x the coefficients given; check area [m²] and p_ref [Pa]"
            )
            break  # one line names the mistake
    for b in bearings:  # (mu_fast 0.02 beside mu_slow 0.04 slid 3.4x as far, unsaid)
        f = getattr(b, "friction", None)
        if getattr(f, "mu_fast", None) is not None and f.mu_fast < f.mu_slow:
            notes.append(f"{b.where}.mu_fast = {f.mu_fast:g} < mu_slow = {f.mu_slow:g}: friction "
                         "that falls with the slip speed (PTFE's rises: swapped?)")  # fmt: skip
            break
    for b in bearings:
        mu = {j: float(getattr(b, f"mu{j}")) for j in range(1, 5)} if hasattr(b, "R1") else {}
        if mu and min(mu.values()) < MU_TFP_LOW:
            j = min(mu, key=mu.get)
            notes.append(f"{b.where}.mu{j} = {mu[j]:g}: far below a built bearing's friction "
                         "(0.01-0.2); the triple pendulum's steps shrink with its smallest "
                         "friction, and the run may take minutes or stop with its steps "
                         "collapsed (check mu1..mu4)")  # fmt: skip
            break
    for b in bearings:  # (a radius in mm ran as a pendulum of a 94 s period, unsaid)
        if math.isfinite(b.radius) and b.radius > RADIUS_PLAUSIBLE:
            T = 2.0 * math.pi * math.sqrt(b.radius / G_EARTH)
            if getattr(b, "R1", None) is not None:  # a triple's R1 + R4: its own keys named
                keys = " and ".join(f"R{k}" for k in (1, 4) if getattr(b, f"R{k}") > 1e2) or "R1"
                notes.append(f"{b.where}.{keys}: R1 + R4 = {b.radius:g} m is a pendulum of "
                             f"period 2π√(R/g) = {T:.3g} s (built ones: R of 1-6 m, 2-5 s); "
                             "check they are in m")  # fmt: skip
                break
            notes.append(f"{b.where}.radius: R = {b.radius:g} m is a pendulum of period "
                         f"2π√(R/g) = {T:.3g} s (built ones: R of 1-6 m, 2-5 s); check it is "
                         "in m")  # fmt: skip
            break
    return notes


def bearing_warnings(system) -> None:
    """A NotedWarning for each input of the system's bearings that is probably a mistake
    (:func:`~nsdyn.models.isolated.bearings.bearing_notes`: a friction coefficient above 1, a
    static contact pressure far from p_ref), as a scene notes them."""
    import warnings

    from nsdyn._checks import NotedWarning

    if getattr(system, "bearings", None):
        for note in bearing_notes(system.bearings, system.static_normal()):
            warnings.warn(note, NotedWarning, stacklevel=4)


def scene_coefficients(cfg: dict, where: str, keys) -> None:
    """BearingError for a scene's friction coefficient (``keys`` of ``cfg``) above
    MU_PLAUSIBLE: in a file it is a percentage written as a number (mu = 5 ran with a note
    that named another key, and a pendulum stuck for the whole run); Python's Friction(5)
    is said in a note instead."""
    for k in keys:
        v = cfg.get(k)
        if isinstance(v, int | float) and not isinstance(v, bool) and v > MU_PLAUSIBLE:
            raise BearingError(f"{where}.{k}: expected a friction coefficient at most 1 "
                               "(sliding isolators' are about 0.01-0.2: 0.05 for 5 %), got "
                               f"{v:g}")  # fmt: skip


def friction_from_config(cfg: dict, where: str) -> Friction:
    """A :class:`Friction` from a TOML table: ``mu`` (constant) or ``mu_slow``/``mu_fast``/
    ``rate``, optional ``mu_static``."""
    scene_coefficients(cfg, where, ("mu", "mu_slow", "mu_fast", "mu_static"))
    if "mu" in cfg and ("mu_slow" in cfg or "mu_fast" in cfg):
        raise BearingError(f"{where}.mu: give either mu or mu_slow/mu_fast, not both")
    if "mu" not in cfg and "mu_slow" not in cfg:
        raise BearingError(f"{where}.mu: missing; expected the friction coefficient mu "
                           "(or mu_slow, mu_fast, rate)")  # fmt: skip
    rate = cfg.get("rate", 0.0)  # (a positive rate without mu_fast was dropped)
    if isinstance(rate, int | float) and rate > 0 and "mu_fast" not in cfg:
        raise BearingError(f"{where}.rate: the rate of the change from mu_slow to mu_fast; "
                           "expected mu_fast beside it (or no rate)")  # fmt: skip
    slow = cfg.get("mu", cfg.get("mu_slow"))
    return Friction(
        mu_slow=_number(f"{where}.{'mu' if 'mu' in cfg else 'mu_slow'}", slow),
        mu_fast=None if "mu_fast" not in cfg else _number(f"{where}.mu_fast", cfg["mu_fast"]),
        rate=_number(f"{where}.rate", cfg.get("rate", 0.0)),
        mu_static=None if "mu_static" not in cfg else cfg["mu_static"],
        where=where,
    )


BEARING_KEYS = {"type", "mu", "mu_slow", "mu_fast", "rate", "mu_static", "radius", "k_lam", "c",
                "d_cap", "k_stop", "c_stop", "area", "p_ref",
                "R1", "R2", "R3", "R4", "mu1", "mu2", "mu3", "mu4", "d1", "d2", "d3", "d4",
                "u_y", "zeta_e", "mu_fast1", "mu_fast2", "mu_fast3", "mu_fast4"}  # fmt: skip
_TFP_ONLY = ("R1", "R2", "R3", "R4", "mu1", "mu2", "mu3", "mu4", "d1", "d2", "d3", "d4", "u_y",
             "zeta_e", "mu_fast1", "mu_fast2", "mu_fast3", "mu_fast4")  # fmt: skip


def bearing_from_config(cfg: dict, where: str) -> Bearing:
    """A :class:`Bearing` from a TOML table (``type = "fps"`` needs ``radius``; ``"flat"``;
    ``"tfp"``: a triple friction pendulum, :func:`nsdyn.models.isolated.tfp.tfp_from_config`)."""
    kind = cfg.get("type", "fps" if "radius" in cfg else "flat")
    if kind not in ("fps", "flat", "tfp"):
        raise BearingError(f"{where}.type: expected 'fps', 'flat' or 'tfp', got {kind!r}")
    if kind == "tfp":
        from nsdyn.models.isolated.tfp import tfp_from_config

        return tfp_from_config(cfg, where)
    for k in _TFP_ONLY:
        if k in cfg:
            said = (f"not of type {kind!r}" if "type" in cfg else  # (the user wrote no type)
                    "add type = 'tfp' to the table")  # fmt: skip
            raise BearingError(f"{where}.{k}: a key of a triple friction pendulum "
                               f"(type = 'tfp'); {said}")  # fmt: skip
    if kind == "fps" and "radius" not in cfg:
        raise BearingError(f"{where}.radius: missing; a friction pendulum needs its effective "
                           "radius R [m]")  # fmt: skip
    if kind == "flat" and "radius" in cfg:
        raise BearingError(f"{where}.radius: a flat slider has no radius (type = 'flat')")
    kw = {}
    for k in ("radius", "d_cap", "k_stop", "area", "p_ref"):
        if k in cfg:
            kw[k] = _number(f"{where}.{k}", cfg[k], positive=True)
    for k in ("k_lam", "c", "c_stop"):
        if k in cfg:
            kw[k] = _number(f"{where}.{k}", cfg[k])
    return Bearing(friction_from_config(cfg, where), where=where, **kw)
