"""Systems on bidirectional isolators: a mass on one isolator (SDOF in the plane), a rigid deck.

The deck (mass m, polar inertia J about its centre of mass, centre of mass at plan position
(e_x, e_y) from the reference point O and height h above the sliding surfaces) moves in its
plane, q = (x, y, θ) of O relative to the ground, on isolators at plan positions (X_i, Y_i)
(coordinates about O). Its mass matrix about O is

    M = [[m, 0, −m e_y], [0, m, m e_x], [−m e_y, m e_x, J + m (e_x² + e_y²)]],

so an eccentric mass couples translation and torsion. The equations, the friction laws and the
normal forces are those of :mod:`nsdyn.models.isolated._kplane`. The normal forces use the
rigid-plate distribution: with N >= 4 isolators the deck is statically indeterminate, and
equal vertical isolator stiffness under a rigid deck makes N_i affine in (X_i, Y_i),

    N_i = [1, X_i, Y_i] G⁻¹ [W, Σ N X, Σ N Y]ᵀ,   G = Σ_j [1, X_j, Y_j]ᵀ [1, X_j, Y_j],

which needs one isolator (the SDOF, N = W, its moments taken by the bearing) or at least three
not on one line. The deck is vertically rigid (no vertical or rocking motion). What a normal
force reaching zero does is the ``contact`` assumption: "detect" (default) locates the uplift
and ends the run, reported with time and isolator; "bilateral" holds the contact in tension
(N_i < 0 allowed, the distribution above unchanged) and reports when and how far it went
tensile, the tensile isolator's friction and N u/R taken at max(N_i, 0) = 0. "unilateral"
(lift-off and landing) needs the vertical and rocking dofs this model does not have (systems
from matrices have them: :mod:`nsdyn.models.isolated.pairs`).
"""

from __future__ import annotations

import math
import numbers
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from nsdyn._brief import brief_repr
from nsdyn._checks import (
    NotedWarning,
    finite_numbers,
    got_array,
    number,
    output_step,
    output_times,
    rel_tol,
    whole,
)
from nsdyn.ground.excitation import G_EARTH
from nsdyn.models.isolated import _kplane as kp
from nsdyn.models.isolated import _kplaneradau as krad
from nsdyn.models.isolated import _kplanerun as kr
from nsdyn.models.isolated import deck_compile
from nsdyn.models.isolated.bearings import (
    B_IOFF,
    N_BCOL,
    Bearing,
    BearingError,
    bearing_warnings,
    gravity_note,
    stick_range_error,
)
from nsdyn.models.isolated.defaults import ALPHA, BETA, EPS, ETA
from nsdyn.models.isolated.plane_ground import orbit_of, pack_ground, tfp_start_said  # noqa: F401
from nsdyn.models.isolated.plane_result import PlaneResult
from nsdyn.models.isolated.tfp import N_INTERNAL, TripleBearing
from nsdyn.models.isolated.tolerances import arctan_atol

PLANE_LAWS = ("switch", "arctan")  # the switch law with a stick disc; the regularised law
# the contact assumptions of the planar family (system.CONTACTS) that these systems run
PLANE_CONTACTS = {"detect": kp.CONTACT_DETECT, "bilateral": kp.CONTACT_BILATERAL}
# a plan wider than this is a deck in mm, not m (isolated buildings span tens to a few hundred
# m; a 20 m x 12 m deck given in mm failed under the switch law with advice to use arctan)
PLAN_PLAUSIBLE = 1000.0  # m
# a deck lighter than this per m² of its isolators' plan is in t, not kg (a slab alone weighs
# 300-700 kg/m²; 1500 "kg" over 30 m x 10 m ran with forces 1000x too small, unsaid)
DECK_MASS_PLAUSIBLE = 50.0  # kg/m²
COLLINEAR_RTOL = 1e-9  # G's smallest/largest eigenvalue below this: isolators on one line
PLAN_MAX = 1e6  # [m] isolator positions within 1000 km of O (1e200 overflowed G)
# default absolute tolerances (displacement [m], velocity [m/s]) per law. The switch law
# locates stick at v = 0 and keeps 1e-8. The regularised law's velocity tolerance is the planar
# family's (tolerances.RUN_ATOL): on the benchmark deck under the 40 s three-component record
# (nsdyn bench isolators) its slips stay within 2e-6 of their peak of the law's own solution
# at rtol 1e-6 (3e-8 with 1e-8), in half the steps, while the law differs from the switch law
# by 4e-2 of the peak; a velocity tolerance of 1e-8 m/s sits 10^4 below the law's transition
# speed 1/eps and drives the step in every creep phase.
PLANE_ATOL = {"switch": (1e-8, 1e-8), "arctan": (1e-8, 1e-6)}


@dataclass(frozen=True, repr=False)
class PlaneSystem:
    """A rigid deck (or a single mass) on bidirectional isolators (see the module text)."""

    __repr__ = brief_repr  # arrays by shape, not in full

    m: float
    J: float
    positions: np.ndarray  # (ni, 2) plan positions of the isolators about O [m]
    bearings: tuple  # one Bearing per isolator
    ecc: tuple = (0.0, 0.0)  # plan position of the centre of mass about O [m]
    h: float = 0.0  # height of the centre of mass above the sliding surfaces [m]
    g: float = G_EARTH
    name: str = "deck"
    info: dict = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        for k in ("m", "J", "g"):  # (a g of 0 or NaN was blamed on ecc or the positions)
            v = getattr(self, k)
            real = isinstance(v, numbers.Real) and not isinstance(v, bool)  # numpy's too
            if not (real and math.isfinite(v) and v > 0):
                raise BearingError(f"{self.name}.{k}: expected a positive number, got {v!r}")
            object.__setattr__(self, k, float(v))
        if gravity_note(f"{self.name}.g", self.g):
            warnings.warn(gravity_note(f"{self.name}.g", self.g), NotedWarning, 3)
        try:  # (text or a dict: numpy's conversion error)
            pos = np.asarray(self.positions, dtype=float)
        except (TypeError, ValueError):
            pos = np.empty(0)
        if (
            pos.ndim != 2
            or pos.shape[1] != 2
            or pos.shape[0] < 1
            or not np.all(np.abs(pos) <= PLAN_MAX)
        ):  # fmt: skip  (NaN too)
            far = pos.ndim == 2 and pos.shape[1:] == (2,) and np.all(np.isfinite(pos))
            got = (f"{np.abs(pos).max():g} m" if far and pos.size else got_array(pos, (None, 2))
                   if pos.size else repr(self.positions)[:80])  # fmt: skip
            raise BearingError(f"{self.name}.positions: expected (X, Y) pairs [m] within "
                               f"{PLAN_MAX:g} m, got {got}")  # fmt: skip
        object.__setattr__(self, "positions", pos)
        _, first, count = np.unique(pos, axis=0, return_index=True, return_counts=True)
        if np.any(count > 1):
            i = int(first[np.argmax(count > 1)])
            j = int(np.flatnonzero(np.all(pos == pos[i], axis=1))[1])
            raise BearingError(f"{self.name}.positions: isolators {i} and {j} share the "
                               f"position {pos[i].tolist()}; expected distinct positions (two "
                               "bearings at one point act as one of twice the "
                               "properties)")  # fmt: skip
        if len(self.bearings) != pos.shape[0]:
            raise BearingError(f"{self.name}.bearings: expected {pos.shape[0]} (one per "
                               f"isolator position), got {len(self.bearings)}")  # fmt: skip
        for b in self.bearings:
            if not isinstance(b, Bearing):
                raise BearingError(f"{self.name}.bearings: expected Bearing, got {b!r}")
        try:  # (text, None, True, a number for ecc: a TypeError from inside)
            h = number(f"{self.name}.h", self.h, "a non-negative height [m]", lambda v: v >= 0)
            ecc = tuple(finite_numbers(f"{self.name}.ecc", self.ecc, "(e_x, e_y) [m]", 2).tolist())
        except ValueError as e:
            raise BearingError(str(e)) from None
        object.__setattr__(self, "h", h)
        object.__setattr__(self, "ecc", ecc)
        off = np.abs(np.array(ecc) - pos[0]).max() > 1e-9 * max(1.0, np.abs(pos[0]).max())
        if len(self.bearings) == 1 and off:  # (it twisted 0.4 rad; 0.1 + 0.2 is 0.3 here)
            raise BearingError(f"{self.name}.ecc: a deck on one isolator stands on it alone: "
                               f"expected its centre of mass over it (ecc = {pos[0].tolist()}, "
                               f"the isolator's position), got {list(ecc)}")  # fmt: skip
        nd = self.normal_distribution()
        n0 = self.static_normal(nd)
        if np.any(n0 <= 0):
            i = int(np.argmin(n0))
            raise BearingError(
                f"{self.name}.ecc: the centre of mass lies outside the kern of the isolators "
                f"(rigid-plate normal forces): isolator {i} would carry {n0[i]:.4g} N at rest"
            )
        for b in self.bearings:
            if isinstance(b, TripleBearing):  # (its surfaces' capacities checked by itself)
                continue
            said = stick_range_error(b)
            if said:
                raise BearingError(said)

    @property
    def n_isolators(self) -> int:
        return self.positions.shape[0]

    def internal_offsets(self) -> list:
        """Index in the state vector of each isolator's internal slips (the series elements
        of a triple friction pendulum, after [q, q̇]); -1 for a single-surface bearing."""
        out, o = [], 6
        for b in self.bearings:
            if isinstance(b, TripleBearing):
                out.append(o)
                o += N_INTERNAL
            else:
                out.append(-1)
        return out

    @property
    def n_states(self) -> int:
        """Length of the state vector: [q, q̇] and the internal slips."""
        return 6 + N_INTERNAL * sum(isinstance(b, TripleBearing) for b in self.bearings)

    @property
    def has_tfp(self) -> bool:
        return any(isinstance(b, TripleBearing) for b in self.bearings)

    def mass_matrix(self) -> np.ndarray:
        ex, ey = (float(e) for e in self.ecc)
        m = self.m
        return np.array([[m, 0.0, -m * ey], [0.0, m, m * ex],
                         [-m * ey, m * ex, self.J + m * (ex * ex + ey * ey)]])  # fmt: skip

    def normal_distribution(self) -> np.ndarray:
        """(ni, 3) rows (w_i, p_x,i, p_y,i): N_i = w_i W + p_x,i Σ N X + p_y,i Σ N Y."""
        pos = self.positions
        ni = pos.shape[0]
        if ni == 1:
            return np.array([[1.0, 0.0, 0.0]])
        # about the isolators' centroid c, scaled by their extent s (far from O, G's eigenvalues
        # in O's coordinates told a 20 m deck 1 km away collinear): P = Pc A, G⁻¹ = A⁻¹ Gc⁻¹ A⁻ᵀ
        c = pos.mean(axis=0)
        s = max(float(np.abs(pos - c).max()), 1e-300)
        Pc = np.column_stack([np.ones(ni), (pos - c) / s])
        Gc = Pc.T @ Pc
        w = np.linalg.eigvalsh(Gc[1:, 1:])
        if ni == 2 or w[0] <= COLLINEAR_RTOL * w[-1]:
            raise BearingError(
                f"{self.name}.positions: the isolators lie on one line; a deck needs one "
                "isolator or at least three not on one line"
            )
        A_inv = np.array([[1.0, -c[0], -c[1]], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
        return Pc @ np.linalg.inv(Gc) @ np.diag([1.0, 1 / s, 1 / s]) @ A_inv.T

    def static_normal(self, nd: np.ndarray | None = None) -> np.ndarray:
        """Normal forces at rest [N]."""
        nd = self.normal_distribution() if nd is None else nd
        ex, ey = (float(e) for e in self.ecc)
        W = self.m * self.g
        return nd[:, 0] * W + nd[:, 1] * W * ex + nd[:, 2] * W * ey

    def bearing_table(self) -> np.ndarray:
        n0 = self.static_normal()
        bp = np.zeros((self.n_isolators, N_BCOL))
        for i, (b, o) in enumerate(zip(self.bearings, self.internal_offsets(), strict=True)):
            bp[i] = b.row(float(n0[i]), self.g)
            if o >= 0:
                bp[i, B_IOFF] = o
        return bp


def sdof_plane(
    m: float, bearing: Bearing, *, g: float = G_EARTH, name: str = "sdof"
) -> PlaneSystem:
    """A mass ``m`` [kg] on one bidirectional isolator (x, y; its twist carries no load)."""
    return PlaneSystem(m=m, J=m, positions=np.zeros((1, 2)), bearings=(bearing,), g=g, name=name)


def rigid_deck(m: float, J: float, positions: Sequence, bearings: Bearing | Sequence[Bearing], *,
               ecc: tuple = (0.0, 0.0), h: float = 0.0, g: float = G_EARTH,
               name: str = "deck") -> PlaneSystem:  # fmt: skip
    """A rigid deck of mass ``m`` [kg] and polar inertia ``J`` [kg m²] about its centre of
    mass, on isolators at ``positions`` ((X_i, Y_i) [m] about the reference point O, the
    plan's centroid for a centred deck, not a corner: the centre of mass must lie inside
    their kern, else a BearingError), with ``bearings`` (one ``Bearing`` or ``TripleBearing``
    for all, or one each). ``ecc`` (e_x, e_y) [m]: the centre of mass about O; ``h`` [m]: its
    height above the sliding surfaces (the overturning); ``g`` [m/s²]; ``name`` labels its
    messages. Returns a :class:`PlaneSystem`."""
    n = np.shape(positions)[0] if np.ndim(positions) == 2 else 1
    if isinstance(bearings, Bearing):
        bearings = (bearings,) * n
    elif not isinstance(bearings, list | tuple):
        raise TypeError(f"bearings: expected a Bearing (Bearing(Friction(mu), radius=R)) or one "
                        f"per position, got {type(bearings).__name__}")  # fmt: skip
    elif bad := [i for i, b in enumerate(bearings) if not isinstance(b, Bearing)]:  # (the entry)
        raise TypeError(f"bearings[{bad[0]}]: expected a Bearing (Bearing(Friction(mu), "
                        f"radius=R)), got {type(bearings[bad[0]]).__name__}")  # fmt: skip
    return PlaneSystem(m=m, J=J, positions=positions, bearings=tuple(bearings), ecc=ecc, h=h,
                       g=g, name=name)  # fmt: skip


def contact_code(contact: str, unilateral: bool = False) -> int:
    """The kernels' code of a contact assumption; one-line errors for others ("unilateral"
    only where ``unilateral``: systems from matrices with independent contacts)."""
    if contact == "unilateral" and unilateral:
        return kp.CONTACT_UNILATERAL
    if contact == "unilateral":
        raise ValueError("contact: 'unilateral' (lift-off and landing) is not available on the "
                         "rigid deck (vertically rigid); expected 'detect' or "
                         "'bilateral'")  # fmt: skip
    if contact not in PLANE_CONTACTS:
        names = [*PLANE_CONTACTS, "unilateral"] if unilateral else list(PLANE_CONTACTS)
        raise ValueError(f"contact: expected one of {names}, got {contact!r}")
    return PLANE_CONTACTS[contact]


def positive_params(**values) -> None:
    """Each given law and stabilisation parameter (eps, eta, alpha, beta, kappa; None: the
    default) a positive finite number, or ValueError naming it."""
    from nsdyn.models.isolated.friction import sharpness_in_range

    for k, v in values.items():
        if v is not None:
            number(k, v, "a positive number", lambda x: x > 0)
    sharpness_in_range("eps", values.get("eps"))


def law_params(law: str, **values) -> None:
    """:func:`positive_params`, and an InputWarning naming each of eps, eta and kappa given
    away from its default when ``law`` does not read it (a run would drop it without a word;
    a scene notes it and passes the default)."""
    import warnings

    from nsdyn._checks import InputWarning, NotedWarning
    from nsdyn.models.isolated.friction import LAW_KEYS, coarse_law_note, unread_law_keys

    positive_params(**values)
    law_keys = {k: values[k] for k in ("eps", "eta", "kappa") if k in values}
    for k in unread_law_keys(law, **law_keys):
        own, what = LAW_KEYS[k]
        warnings.warn(f"{k} = {values[k]!r} not used: {what}; this run's law is {law!r}",
                      InputWarning, stacklevel=4)  # fmt: skip
    coarse = coarse_law_note(law, **{k: v for k, v in law_keys.items() if k != "kappa"},
                             where="")  # fmt: skip
    if coarse:  # (a scene notes it: NotedWarning)
        warnings.warn(coarse, NotedWarning, stacklevel=4)


def plan_note(positions, where: str, m: float | None = None) -> str | None:
    """A note when the isolators' plan extent passes :data:`PLAN_PLAUSIBLE` (in mm?), or when
    the mass ``m`` over their plan's bounding box is below :data:`DECK_MASS_PLAUSIBLE` (in t?)."""
    pos = np.asarray(positions, dtype=float).reshape(-1, 2)
    ext = pos.max(axis=0) - pos.min(axis=0)
    area = float(ext[0] * ext[1]) if m is not None else 0.0
    if ext.max() <= PLAN_PLAUSIBLE and area > 0 and m / area < DECK_MASS_PLAUSIBLE:
        return (f"{where.rsplit('.', 1)[0]}.m = {m:g} kg over the isolators' {ext[0]:.4g} m x "
                f"{ext[1]:.4g} m plan is {m / area:.3g} kg/m², far below any deck's or building's "
                "(a floor slab alone weighs 300-700 kg/m²): is it in t?")  # fmt: skip
    if ext.max() <= PLAN_PLAUSIBLE:
        return None
    return (
        f"{where}: the isolators span {ext[0]:.6g} m x {ext[1]:.6g} m in plan, wider than "
        "any isolated building's (tens to hundreds of m): are they in mm?"
    )


def kernel_params(
    system: PlaneSystem, law: str, eps: float, eta: float, kappa: float | None,
    contact: str = "detect",
) -> tuple:  # fmt: skip
    """(M, pos, bp, nd, sp) of the kernels."""
    code = contact_code(contact)
    if law not in PLANE_LAWS:
        raise ValueError(f"law: expected one of {list(PLANE_LAWS)}, got {law!r}")
    law_params(law, eps=eps, eta=eta, kappa=kappa)
    bearing_warnings(system)
    if plan := plan_note(system.positions, f"{system.name}.positions", system.m):
        warnings.warn(plan, NotedWarning, stacklevel=3)
    sp = np.zeros(kp.N_SP)
    sp[kp.S_M] = system.m
    sp[kp.S_EX], sp[kp.S_EY] = (float(e) for e in system.ecc)
    sp[kp.S_H] = system.h
    sp[kp.S_G] = system.g
    sp[kp.S_KAPPA] = 2 * ALPHA * BETA if kappa is None else float(kappa)
    sp[kp.S_EPS] = eps
    sp[kp.S_ETA] = eta
    sp[kp.S_LAW] = kp.LAW_SWITCH if law == "switch" else kp.LAW_ARCTAN
    sp[kp.S_CONTACT] = code
    M = system.mass_matrix()
    pos = np.ascontiguousarray(system.positions)
    return M, pos, system.bearing_table(), system.normal_distribution(), sp


def _check_run_options(rtol, atol, max_step, max_steps) -> None:
    """One-line errors for tolerances and step limits (rtol > 0, atol = (≥ 0, ≥ 0), ...)."""
    rel_tol("rtol", rtol)
    try:
        aq, av = (float(a) for a in atol)
    except (TypeError, ValueError):
        raise ValueError(f"atol: expected (displacement [m], velocity [m/s]), got "
                         f"{atol!r}") from None  # fmt: skip
    if not all(math.isfinite(a) and a > 0 for a in (aq, av)):  # (0: NaN from the error norm
        raise ValueError(f"atol: expected two positive numbers, got {atol!r}")  # of a rest)
    if max_step is not None:
        number("max_step", max_step, "a positive step [s]", lambda v: v > 0)
    whole("max_steps", max_steps, 1, "a positive integer")


def run_end(t_end, dur: float) -> float:
    """The end of a run on a ground of duration ``dur`` (:func:`pack_ground`): ``t_end``, or
    the record's end; ValueError for an orbit (no natural end) without ``t_end``, or a
    ``t_end`` that is not a positive duration."""
    if t_end is None and not math.isfinite(dur):
        raise ValueError("t_end: a harmonic orbit has no natural end: give the duration, "
                         "t_end=... [s]")  # fmt: skip
    t_end = dur if t_end is None else t_end
    real = isinstance(t_end, numbers.Real) and not isinstance(t_end, bool)
    if not (real and math.isfinite(t_end) and t_end > 0):
        raise ValueError(f"t_end: expected a positive duration [s], got {t_end!r}")
    return float(t_end)


def orbit_frequency(gp) -> float | None:
    """The highest frequency [Hz] of an orbit's components that move (None: none moves)."""
    fs = [gp[kp.GP_F]] * bool(gp[kp.GP_AX] or gp[kp.GP_AY]) + [gp[kp.GP_FZ]] * bool(gp[kp.GP_AZ])
    return max(fs) if fs else None


def default_dt_out(gk, gp) -> float:
    """A run's output step when none is given: the record's step, or 1/50 of the period of
    an orbit's fastest moving component (:func:`orbit_frequency`)."""
    if gk == kp.G_TABLE:
        return float(gp[kp.GP_DT])
    return 1.0 / (50.0 * (orbit_frequency(gp) or gp[kp.GP_F]))


def grid_note(gk, gp, dur: float, dt_out: float, field: str = "dt_out") -> str | None:
    """:func:`nsdyn._checks.coarse_grid_note` of outputs ``dt_out`` apart on the ground (gk,
    gp) of :func:`pack_ground` (a record of duration ``dur``, or an orbit)."""
    from nsdyn._checks import coarse_grid_note

    if gk == kp.G_TABLE:
        return coarse_grid_note(dt_out, None, float(gp[kp.GP_DT]), dur, field)
    return coarse_grid_note(dt_out, orbit_frequency(gp), None, 0.0, field)


def run_grid(gk, gp, dur, t_end, dt_out, t_eval, max_step) -> tuple[np.ndarray, float]:
    """(t_eval, max_step) of a run on the ground (gk, gp) of :func:`pack_ground`: outputs
    every ``dt_out`` (default: the record's step, or 1/50 period of an orbit) up to ``t_end``
    (default: the record's duration ``dur``), the last output, unless ``t_eval`` is given;
    the largest step defaults to the record's step or 1/20 of the shorter period."""
    if t_eval is not None and (t_end is not None or dt_out is not None):  # (they were dropped)
        given = "t_end" if t_end is not None else "dt_out"
        raise ValueError(f"{given}: give t_eval (the output times) or t_end and dt_out, not both")
    if t_eval is None:
        t_end = run_end(t_end, dur)
        if dt_out is None:  # (an orbit's faster component: its vertical, f_z, may be)
            dt_out = default_dt_out(gk, gp)
        else:
            output_step(dt_out, t_end, off=False)
        t0 = gp[kp.GP_T0] * (gk == kp.G_TABLE)
        t_eval = output_times(t0, t0 + t_end, dt_out)  # (t_end the last output)
    t_eval = np.ascontiguousarray(t_eval, dtype=float)
    if (t_eval.ndim != 1 or t_eval.size < 2 or not np.all(np.isfinite(t_eval))
            or not np.all(np.diff(t_eval) > 0)):  # fmt: skip
        raise ValueError("t_eval: expected at least two increasing finite times")
    import warnings

    from nsdyn._checks import AccuracyWarning, NotedWarning, output_gap

    if gk == kp.G_TABLE:  # outputs outside the record: the ground at rest there, said
        from nsdyn.ground.formats import record_span_notes

        t0, dt = float(gp[kp.GP_T0]), float(gp[kp.GP_DT])
        for note in record_span_notes(t_eval, t0, t0 + dur, dt):
            warnings.warn(note, NotedWarning, stacklevel=3)
    coarse = grid_note(gk, gp, dur, *output_gap(t_eval)) if t_eval.size > 2 else None
    if coarse:  # (the frame's simulate says it too; outputs 1 s apart read 15 % low)
        warnings.warn(coarse, AccuracyWarning, stacklevel=3)
    if max_step is None:
        max_step = (
            gp[kp.GP_DT] if gk == kp.G_TABLE else 1.0 / (20.0 * max(gp[kp.GP_F], gp[kp.GP_FZ]))
        )
    return t_eval, max_step


def run_buffers(law, eps, rtol, atol, max_step, max_steps, nt, ni, ns) -> tuple:
    """The loops' arrays: (modes, dirs, cfg, X, NO, FF, FR, FO, MO, EV, stops, info) for
    ``nt`` outputs of ``ns`` states and ``ni`` isolators; the regularised law's velocity
    tolerance capped at ATOL_V_EPS / eps."""
    modes = np.full(ni, kp.MODE_SLIP, dtype=np.int64)
    dirs = np.zeros((ni, 2))
    atol_v = float(atol[1])
    if law == "arctan":  # the law's transition |v| ~ 1/eps must lie above the error tolerance
        atol_v = arctan_atol(atol, eps)[1]
    cfg = np.array([rtol, atol[0], atol_v, min(1e-4, max_step), max_step, float(max_steps)])
    X = np.full((nt, ns), np.nan)
    NO = np.full((nt, ni), np.nan)
    FF, FR, FO = (np.full((nt, ni, 2), np.nan) for _ in range(3))
    MO = np.zeros((nt, ni), dtype=np.int64)
    EV = np.zeros((100_000, 6))
    stops = np.zeros((ni, 3))
    stops[:, kr.P_TFIRST] = np.nan
    info = np.zeros(kr.N_INFO)
    return modes, dirs, cfg, X, NO, FF, FR, FO, MO, EV, stops, info


def simulate_plane(
    system: PlaneSystem,
    ground,
    *,
    law: str = "switch",
    t_end: float | None = None,
    dt_out: float | None = None,
    t_eval=None,
    eps: float = EPS,
    eta: float = ETA,
    kappa: float | None = None,
    rtol: float = 1e-6,
    atol: tuple | None = None,
    max_step: float | None = None,
    max_steps: int = 5_000_000,
    y0=None,
    integrator: str = "auto",
    contact: str = "detect",
    progress=None,
):
    """Integrate the system under ``ground`` (a record, or an orbit: ``phase_y_deg`` = 90°
    unless given) from rest (or ``y0`` = [q, q̇], a triple pendulum's element slips after).

    ``law``: "switch" (stick disc, events located on the dense output) or "arctan" (the
    regularised vector law). Outputs every ``dt_out`` (default: the record's step, or 1/50
    period of an orbit) or at ``t_eval``. ``integrator``: "auto" (the switch law on the
    explicit Dormand–Prince pair, whose smooth phases are not stiff; the stiff regularised law
    on Radau IIA), "dopri5" or "radau" (the regularised law only). ``atol`` = (displacement
    [m], velocity [m/s]), by default the law's ``PLANE_ATOL``; the regularised law's velocity
    tolerance is capped at ``ATOL_V_EPS / eps``. ``contact``: "detect" (an uplift ends the
    run, reported in ``result.uplift`` with a warning) or "bilateral" (the contact holds in
    tension; reported in ``result.tension`` with a warning). Returns a :class:`PlaneResult`.
    ``eps`` [s/m], ``eta`` [m/s], ``kappa`` [1/s]: the laws' parameters (the arctan law's
    sharpness; the switch law's stick band and stick-velocity stabilisation, default 2αβ);
    ``rtol``, ``max_step`` [s] and ``max_steps`` bound the adaptive steps.
    ``progress(t_done, t_end, wall_s)``: called every few seconds of wall time while the
    compiled loop runs (:func:`nsdyn._progress.watched`; a Ctrl-C stops the wait at once).
    """
    if not isinstance(system, PlaneSystem):  # (None: an AttributeError 'm')
        raise TypeError(f"system: expected a PlaneSystem (rigid_deck(...) or sdof_plane(...)), "
                        f"got {type(system).__name__}")  # fmt: skip
    if progress is not None and not callable(progress):  # (5: a TypeError mid-run)
        raise TypeError(f"progress: expected a function (t_done, t_end, wall_s), got "
                        f"{type(progress).__name__}")  # fmt: skip
    if integrator not in ("auto", "dopri5", "radau"):
        raise ValueError(f"integrator: expected 'auto', 'dopri5' or 'radau', got {integrator!r}")
    if integrator == "radau" and law == "switch":
        raise ValueError("integrator: the switch law runs on 'dopri5' (its events need it)")
    if getattr(system, "has_tfp", False) and (law != "arctan" or integrator == "dopri5"):
        raise ValueError(
            "law: a triple friction pendulum runs with the regularised law 'arctan' on Radau "
            "IIA (its series model has no stick events and is stiff), got law "
            f"{law!r}, integrator {integrator!r}"
        )
    loop = kr.integrate
    if law == "arctan" and integrator in ("auto", "radau"):
        loop = krad.integrate
    M, pos, bp, nd, sp = kernel_params(system, law, eps, eta, kappa, contact)
    if atol is None:
        atol = PLANE_ATOL[law]
    _check_run_options(rtol, atol, max_step, max_steps)
    gk, gp, tab, dur = pack_ground(ground)
    t_eval, max_step = run_grid(gk, gp, dur, t_end, dt_out, t_eval, max_step)
    ni = system.n_isolators
    nt = t_eval.size
    ns = getattr(system, "n_states", 6)
    try:  # (text: numpy's conversion error)
        y = np.zeros(6) if y0 is None else np.ascontiguousarray(y0, dtype=float).copy()
    except (TypeError, ValueError):
        y = np.empty(0)
    if y.shape not in ((6,), (ns,)) or not np.all(np.isfinite(y)):
        extra = f" (or {ns} with the internal slips)" if ns > 6 else ""  # (a triple pendulum's)
        raise ValueError(f"y0: expected six finite numbers [x, y, theta, vx, vy, omega]{extra}, "
                         f"got {y0!r}")  # fmt: skip
    tfp_start_said(y[:3], np.zeros(3), getattr(system, "has_tfp", False) and y.size < ns)
    y = np.concatenate([y, np.zeros(ns - y.size)])  # (internal slips from rest)
    modes, dirs, cfg, X, NO, FF, FR, FO, MO, EV, stops, info = run_buffers(
        law, eps, rtol, atol, max_step, max_steps, nt, ni, ns
    )
    args = (y, t_eval, modes, dirs, M, pos, bp, nd, sp, gk, gp, tab, cfg,
            X, NO, FF, FR, FO, MO, EV, stops, info)  # fmt: skip
    scratch = deck_compile.loop_arrays(loop, ns, ni)
    status = deck_compile.run_loop(loop, args, law == "switch", progress, scratch)
    return PlaneResult.from_run(system, law, t_eval, X, NO, FF, FR, FO, MO, EV, stops, info,
                                int(status), eps, eta, contact, impasse=scratch[0][19])  # fmt: skip
