"""Periodic orbits of the switch model (true Coulomb stick): its exact period map and shooting.

The shooting of seed 004 §6 (eqs 19-27, there with the arctan law) on minimal coordinates
``x = [z, zd]``, ``q = Q z``, here with true stick (the seed checked its curves with a switch
model with stiction, footnote 3; this map has no band η: its modes switch at v = 0 and at
the stick limit exactly). With every isolator's mode held (slip +1/-1,
stick 0: the system kernel's law LAW_MODES, stick a constraint force) the equations are

    x' = A_k x + g0_k + gs_k sin(w t) + gc_k cos(w t)

(``k`` the mode set; linear because the friction force ``mu s lamf`` and the stick force are
linear in the state for fixed modes). ``A_k`` and the forcing columns are read off the system
kernel (Jacobian ``blockdiag(Q^T) ks.jac blockdiag(Q)``, right-hand side at ``x = 0`` at
three forcing phases), the stick and normal forces likewise from ``ks.evaluate``. The period
map of :mod:`nsdyn.periodic._kswitch` integrates this exactly (matrix exponentials) and
multiplies flows and saltation matrices into the exact monodromy; Newton shooting, the
stepped sweep, sequential and pseudo-arclength continuation are those of the smooth case
(:class:`SwitchProblem` satisfies :class:`nsdyn.periodic.protocol.PeriodicModel`). On an
orbit where an isolator sticks all period its displacement is frozen: shifting it gives
another orbit (multiplier 1, ``Phi - I`` singular), so :meth:`SwitchProblem.frozen_rows`
reports it and shooting holds it at the guess (least-squares Newton step on the rest).

Isolators whose sliding velocities are one on the minimal coordinates (equal rows ``D_i Q``:
a rigid fidelity's, a rigid deck's) are tied (:func:`~nsdyn.periodic.switch_tables.
tied_groups`): held one by one, one of them stuck while another slid on at ``v = 0`` (its
switching function identically zero), and shooting converged on orbits 2.2x too large. A tied
group has one mode; its rows are the sums of its isolators': the friction force ``sum tau_i``
and the capacity ``sum mu_i lamf_i`` of its stick test ``|sum tau_i| <= sum mu_i lamf_i``
(with one stuck velocity the split of the stick force among the group is not determined, the
sum is). The normal forces reported stay each isolator's.

A grazing orbit (a slip phase shrinking to zero length: at a switch ``n^T f- -> 0``, or a
switching function touching zero without crossing) has a saltation matrix that blows up; the
period map reports the smallest normalised ``|n^T f-|`` or touch depth of the period and
points with it below ``GRAZE_TOL`` carry a note.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from nsdyn._brief import brief_repr
from nsdyn._checks import expect
from nsdyn.ground.excitation import Harmonic, HarmonicForce
from nsdyn.models.isolated import _kernel as ks
from nsdyn.models.isolated.params import with_law
from nsdyn.periodic import _kswitch as kw
from nsdyn.periodic.discretisation import Discretisation
from nsdyn.periodic.extrema import dense_half_range
from nsdyn.periodic.protocol import (
    A_HIGHEST,
    GRAZE_TOL,
    STATUS_MESSAGES,
    MinimalStates,
    PeriodMap,
    check_amplitude,
    check_frequency,
    check_map_args,
)
from nsdyn.periodic.shooting import ShootingResult, shoot
from nsdyn.periodic.switch_tables import balancing, mode_sets, mode_tables, tied_groups

MAX_ISOLATORS = 6  # 3^n mode sets are tabulated (n: isolators, tied ones counted once)
SWITCH_N_MIN = 128  # samples (steps) per period at least: event bracketing and orbit output
SWITCH_DT_MAX = 0.02  # s, longest step (the default Discretisation's, same samples)
STEP_SLIP_FACTOR = 2.0  # a step moves an isolator by at most this x its slip range ...
STEP_SLIP_FLOOR = 1e-9  # ... or this [m]
VERIFY_REL = 1e-6  # x the largest slip speed: a slip against its direction (orbit_unverified)
FROZEN_T_TOL = 1e-9  # switches before this fraction of the period freeze nothing
AMP_FLOOR_REL = 1e-9  # x the forcing's static displacement: the smallest amplitude scaled
AMP_FLOOR_CAP = 1e-9  # [m, m/s] ... and at most this (a model without stiffness: no static one)
V_ZERO = 1e-13  # m/s, |v| at the period start below which the stick test decides the mode
LAW_NAME = "switch"  # what every point of this model reports as its law
METHOD_NAME = "exact flow + saltation matrices"  # how the period map is computed

SWITCH_STATUS = {
    kw.STATUS_SINGULAR: "singular Pade denominator in the matrix exponential",
    kw.STATUS_NONFINITE: "the state became inf/nan",
    kw.STATUS_EVENTS: f"more than {kw.MAX_STEP_EVENTS} switching events in one step (chattering)",
}
for _code, _msg in SWITCH_STATUS.items():
    STATUS_MESSAGES.setdefault(_code, _msg)


def augmented(f: float, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(t, Y) of orbit samples ``X`` (N + 1, D) evenly over one period of ``f`` [Hz]: their
    times and the augmented states ``[x, 1, sin w t, cos w t]`` the mode tables act on."""
    n = X.shape[0]
    t = np.linspace(0.0, 1.0 / f, n)
    w = 2.0 * math.pi * f
    return t, np.column_stack([X, np.ones(n), np.sin(w * t), np.cos(w * t)])


@dataclass
class SwitchPeriodMap(PeriodMap):
    """A :class:`PeriodMap` of the switch model with its switching events."""

    # (t, isolator group (an isolator's own index unless tied, tied_groups), new mode,
    # |n^T f-| normalised)
    events: list = field(default_factory=list)
    graze: float = math.inf  # smallest grazing measure of the period
    modes: np.ndarray | None = None  # (N + 1,) mode-set index at each sample
    period: float = math.nan  # T [s]


@dataclass(repr=False)
class SwitchProblem(MinimalStates):
    """The isolated system with the switch model under harmonic forcing, on ``z = Q^T q``.

    ``A0`` (K, D, D): augmented matrices of the 3^ni mode sets with the forcing frequency
    entries zero; ``V``, ``TAU``, ``LF``: sliding velocity, friction force and friction
    normal-force rows (see :mod:`nsdyn.periodic._kswitch`).
    """

    __repr__ = brief_repr  # arrays by shape, not in full

    system: object
    amplitude: float
    Q: np.ndarray
    x_ref: np.ndarray
    A0: np.ndarray
    V: np.ndarray
    TAU: np.ndarray
    LF: np.ndarray
    mu: np.ndarray
    P: tuple  # kernel tuple at f = 1 Hz (law "modes")
    load: HarmonicForce | None = None
    name: str = ""
    scale: np.ndarray | None = None  # (D,) state scaling of the kernel (see balancing)
    group: np.ndarray | None = None  # (ni,) tied group of each isolator (see tied_groups)
    LFI: np.ndarray | None = None  # (K, ni, D) each isolator's normal-force rows
    _cache: dict = field(default_factory=dict, repr=False)

    law = LAW_NAME
    exact_map = True  # not a discretisation: its multipliers need no check (periodic.stability)
    # the monodromy is the product of the exponentials the flow forms anyway: 4-40 % over the
    # map alone, so shooting's shortened line-search trials take it at once (protocol)
    cheap_sensitivities = True

    @property
    def amp_floor(self) -> float:
        """Smallest orbit amplitude of the shooting's scaling [m, m/s]: ``AMP_FLOOR_REL``
        times the static displacement the forcing amplitude gives (its sine and cosine
        columns' amplitude solved against the stiffness of the first mode set's slip), at
        most ``AMP_FLOOR_CAP``. An orbit stuck all period moves
        by its flow's round-off alone (1e-17 m on the rigid office), which a floor of 1e-12
        read as a residual of 1e-5: the point failed; relative to the forcing, a small
        orbit keeps its accuracy (a floor of 1e-9 m cost a 2.5e-12 m orbit 3 digits)."""
        if "amp_floor" not in self._cache:
            m, d = self.m, self.dim
            Kr = -self.A0[0, m:d, :m]  # M^-1 K on the minimal coordinates
            g = np.hypot(self.A0[0, m:d, d + 1], self.A0[0, m:d, d + 2])  # (any phase)
            u = np.linalg.lstsq(Kr, g, rcond=None)[0]
            # (no bearing stiffness, k_lam = 0: Kr is round-off and u huge; the cap holds)
            floor = min(AMP_FLOOR_REL * float(np.abs(u).max(initial=0.0)), AMP_FLOOR_CAP)
            self._cache["amp_floor"] = floor
        return self._cache["amp_floor"]

    def matrices(self, f: float) -> np.ndarray:
        """Augmented matrices (K, D, D) at forcing frequency ``f`` [Hz]."""
        AB = self.A0.copy()
        d = self.dim
        w = 2.0 * math.pi * f
        AB[:, d + 1, d + 2] = w
        AB[:, d + 2, d + 1] = -w
        return AB

    def _scaled(self) -> tuple:
        """Kernel tables in the balanced state ``y = diag(s) y_hat``: (A0_hat, V, TAU, LF
        rows times s, s). Switching functions ``c . y`` are unchanged."""
        if "scaled" not in self._cache:
            sc = np.ones(self.A0.shape[1]) if self.scale is None else self.scale
            A0 = np.ascontiguousarray(self.A0 * sc[None, None, :] / sc[None, :, None])
            tabs = tuple(np.ascontiguousarray(R * sc) for R in (self.V, self.TAU, self.LF))
            self._cache["scaled"] = (A0, *tabs, sc)
        return self._cache["scaled"]

    def steps(self, T: float, disc: Discretisation | None) -> int:
        """Samples per period: the discretisation's count, at least ``SWITCH_N_MIN``."""
        if disc is not None:
            return max(SWITCH_N_MIN, disc.steps(T))
        return max(SWITCH_N_MIN, math.ceil(T / SWITCH_DT_MAX - 1e-9))

    def period_map(
        self,
        x0: np.ndarray,
        f: float,
        *,
        n_steps: int | None = None,
        disc: Discretisation | None = None,
        sens: bool = True,
        store: bool = False,
    ) -> SwitchPeriodMap:
        """One period ``T = 1 / f`` from ``x0`` at t = 0, exact between events; ``n_steps``
        samples (default :meth:`steps`). ``dxdT`` is None: pseudo-arclength continuation
        differentiates this map in T by central differences (exact flow, events move
        smoothly with T away from grazing)."""
        x0 = check_map_args(self.x_ref, x0, n_steps, disc)
        T = 1.0 / check_frequency(f)
        N = self.steps(T, disc) if n_steps is None else int(n_steps)
        ev = (np.zeros(kw.MAX_EVENTS), np.zeros(kw.MAX_EVENTS, np.int64))
        ev = ev + (np.zeros(kw.MAX_EVENTS, np.int64), np.zeros(kw.MAX_EVENTS))
        A0, V, TAU, LF, sc = self._scaled()
        d = self.dim
        AB = A0.copy()
        w = 2.0 * math.pi * f
        AB[:, d + 1, d + 2] = w
        AB[:, d + 2, d + 1] = -w
        sx = sc[:d]
        xT, Phi, X, MK, status, nev, graze = kw.period_map(
            AB,
            V,
            TAU,
            LF,
            self.mu,
            np.ascontiguousarray(np.asarray(x0, dtype=float) / sx),
            2.0 * math.pi * f,
            T,
            N,
            V_ZERO,
            sens,
            store,
            *ev,
        )
        xT = xT * sx
        if sens:
            Phi = Phi * sx[:, None] / sx[None, :]
        if store:
            X = X * sx[None, :]
        k = min(int(nev), kw.MAX_EVENTS)
        events = [
            (float(ev[0][j]), int(ev[1][j]), int(ev[2][j]), float(ev[3][j])) for j in range(k)
        ]
        return SwitchPeriodMap(
            xT,
            Phi if sens else None,
            None,
            X if store else None,
            int(status),
            N,
            int(nev),
            0,
            events,
            float(graze),
            MK,
            T,
        )

    def orbit_unverified(self, pm: SwitchPeriodMap) -> str:
        """Why the orbit of ``pm`` (a period map stored on its samples) is not one of the
        model, or "". Between switches the map is exact, and a slip velocity that reaches
        zero is a switch, so at every sample a slipping isolator moves in its slip's
        direction. One moving against it crossed zero unseen between two samples (twice or
        more: a stick-slip chatter faster than the sampling, an isolator ringing against a
        stiff base's axial mode at kHz), and its friction pushed it on, feeding the orbit:
        Newton converged there on an orbit of this blind map alone (the office frame at
        1.16 Hz: 72 m/s² at the isolation level, the event-driven integrator from its start
        falling to the stuck neighbour's 1.72 m/s²). Tolerance: 1e-6 of the orbit's largest
        slip speed, and at least V_ZERO (a legitimate orbit's samples are on the slip's side)."""
        if pm.X is None or pm.modes is None:
            return ""
        t, Y = augmented(1.0 / pm.period, pm.X)
        v = Y @ self.V.T  # (N + 1, groups) slip velocities (a tied group's one)
        S = mode_sets(v.shape[1])[pm.modes]
        against = -S * v  # > 0: moving against its own slip's friction
        k, i = np.unravel_index(int(np.argmax(against)), against.shape)
        if not against[k, i] > max(VERIFY_REL * float(np.abs(v).max(initial=0.0)), V_ZERO):
            return ""
        iso = int(np.flatnonzero(self.groups() == i)[0])
        return (f"isolator {iso} slips against its own friction at t = {t[k]:.4g} s (v = "
                f"{v[k, i]:.2e} m/s, slip mode {S[k, i]:+d}): a switch fell between two "
                "samples, so the orbit is one of the sampled map, not taken (a curve's "
                "stepped sweep follows the map's attractor instead; more samples per period, "
                "n_steps or disc in Python, nsdyn sweep --steps-factor, resolve such "
                "switches)")  # fmt: skip

    def stuck_all_period(self, pm: SwitchPeriodMap) -> np.ndarray:
        """Indices of the isolators whose displacement is frozen for the whole period of
        ``pm``: stuck at every sample after the start and no switch of theirs after
        ``FROZEN_T_TOL T`` (a start velocity a round-off above ``V_ZERO`` is a slip of no
        duration that sticks at once)."""
        if pm.modes is None:
            return np.zeros(0, dtype=np.int64)
        group = self.groups()
        held = np.all(mode_sets(int(group.max()) + 1)[pm.modes[1:]] == 0, axis=0)
        for e in pm.events:  # (an event names its group)
            if e[0] > FROZEN_T_TOL * pm.period:
                held[e[1]] = False
        return np.flatnonzero(held[group])

    def groups(self) -> np.ndarray:
        """(ni,) the tied group of each isolator (:func:`tied_groups`; each alone without)."""
        ni = self.system.n_isolators
        return np.arange(ni) if self.group is None else self.group

    def frozen_rows(self, pm: SwitchPeriodMap) -> np.ndarray | None:
        """Rows ``[D_i Q, 0]`` of the displacements of the isolators stuck all period on the
        orbit of ``pm``. Such an orbit belongs to a family: shifting a stuck isolator's
        displacement (within its friction cone) gives another periodic orbit, so ``Phi`` has
        the multiplier 1 exactly on those directions and ``Phi - I`` is singular. Shooting
        holds these displacements at the guess (they are parameters of the family, set by the
        slips before the steady state) and solves for the rest."""
        idx = self.stuck_all_period(pm)
        if idx.size == 0:
            return None
        _, one = np.unique(self.groups()[idx], return_index=True)  # (a tied group's rows: one)
        idx = idx[np.sort(one)]
        C = np.zeros((idx.size, self.dim))
        C[:, : self.m] = self.system.D[idx] @ self.Q
        return C

    def step_limits(self, pm: SwitchPeriodMap) -> tuple[np.ndarray, np.ndarray] | None:
        """Trust region of a shooting step on the isolator displacements: rows ``[D_i Q, 0]``
        and bounds ``STEP_SLIP_FACTOR`` times each isolator's slip range over the period of
        ``pm`` (at least ``STEP_SLIP_FLOOR``). An isolator that barely slips makes the map
        nearly neutral along its displacement (a multiplier near 1, the stuck family's), and
        a Newton step would carry it far along that direction -- into other event sequences
        or to the edge of the friction cone; its displacement can only move by slipping."""
        if pm.X is None:
            return None
        L = np.zeros((self.system.n_isolators, self.dim))
        L[:, : self.m] = self.system.D @ self.Q
        xi = pm.X[:, : self.m] @ L[:, : self.m].T
        rng = xi.max(axis=0) - xi.min(axis=0)
        return L, np.maximum(STEP_SLIP_FACTOR * rng, STEP_SLIP_FLOOR)

    # ---- response quantities ------------------------------------------------------------
    def accelerations(self, f: float, X: np.ndarray, MK: np.ndarray) -> np.ndarray:
        """Minimal accelerations zdd (N + 1, m) of the orbit samples ``X`` in modes ``MK``."""
        d, m = self.dim, self.m
        Y = augmented(f, X)[1]
        A = self.A0[MK, m:d, :]  # (N + 1, m, D) (the w entries are in other rows)
        return np.einsum("tmj,tj->tm", A, Y)

    def orbit_quantities(self, f: float, X: np.ndarray) -> dict:
        """The seed's Fig. 9 quantities of the orbit ``X`` (as for the arctan problem), the
        switching events of the period from ``X[0]``, its grazing measure and the law.

        Switches before ``FROZEN_T_TOL T`` are a start velocity a round-off above ``V_ZERO``
        slipping for no time: they are not events of the orbit, and the mode at ``X[0]`` is
        then the one the orbit arrives with at ``T`` (the same state on a periodic orbit), not
        the slip of no duration (whose acceleration would enter the peaks)."""
        pm = self.period_map(X[0], f, n_steps=X.shape[0] - 1, sens=False, store=False)
        MK = pm.modes.copy()
        events = [e for e in pm.events if e[0] > FROZEN_T_TOL * pm.period]
        if len(events) < len(pm.events):
            MK[0] = MK[-1]
        sysm = self.system
        cache = self._cache
        if "od" not in cache:
            from nsdyn.models.isolated.metrics import output_rows

            od = output_rows(sysm)
            cache["od"] = od
            cache["Tj"] = None if od["joints"] is None else od["joints"] @ self.Q
        od, m = cache["od"], self.m
        QDD = self.accelerations(f, X, MK) @ self.Q.T
        N = X.shape[0] - 1
        t = np.linspace(0.0, 1.0 / f, N + 1)
        if self.load is None:
            ug = (self.amplitude * np.sin(2.0 * math.pi * f * t))[:, None]
        else:
            ug = np.zeros((N + 1, 1))
        idr = math.nan
        if cache["Tj"] is not None and od["heights"] is not None:
            U = np.einsum("lcj,tj->tlc", cache["Tj"], X[:, :m])
            drift = np.abs(np.diff(U, axis=1)) / np.asarray(od["heights"])[None, :, None]
            idr = float(drift.max()) if drift.size else 0.0
        acc_levels = [float(np.max(np.abs(QDD @ Tl.T + ug))) for Tl in od["levels"]]
        acc = max(acc_levels, default=math.nan)
        acc_floors = max(acc_levels[1:] if len(acc_levels) > 1 else acc_levels, default=math.nan)
        Xf = self.to_full(X)
        n = self.Q.shape[0]
        xi = Xf[:, :n] @ sysm.D.T
        v = Xf[:, n:] @ sysm.D.T
        stuck = self.stuck_all_period(pm).size == sysm.n_isolators
        lam = self._normal_forces(f, X, MK)
        q = {
            "idr": idr,
            "acc": acc,
            "acc_floors": acc_floors,
            "x_iso": dense_half_range(xi, v, QDD @ sysm.D.T, 1.0 / (f * N)),
            "stick_all_period": bool(stuck),
            "v_slip_max": float(np.max(np.abs(v))) if v.size else 0.0,
            "min_normal_force": float(lam.min()) if lam.size else math.nan,
            "uplift": bool(lam.size and lam.min() <= 0.0),
            "events": len(events),
            "graze": pm.graze,
            "graze_at": self.graze_at(pm),
            "law": LAW_NAME,
            "map": METHOD_NAME,
        }
        return q

    def _normal_forces(self, f, X, MK) -> np.ndarray:
        """Friction normal forces at the samples (contacts; frozen ones are constant)."""
        if self.system.n_contacts == 0:
            return np.zeros(0)
        Y = augmented(f, X)[1]
        LF = self.LF if self.LFI is None else self.LFI
        return np.einsum("tij,tj->ti", LF[MK], Y)

    def quantities_without_orbit(
        self, f: float, x0: np.ndarray, periods: int = 1
    ) -> tuple[dict, str]:
        """NaN quantities for a point whose period could not be integrated (``uplift``
        unknown: no probe here, whatever ``periods``)."""
        keys = ("idr", "acc", "acc_floors", "x_iso", "v_slip_max", "min_normal_force", "graze")
        q = dict.fromkeys(keys, math.nan)
        q.update(stick_all_period=None, uplift=None, law=LAW_NAME, map=METHOD_NAME)
        return q, ""

    def validity_note(self, quantities: dict) -> str:
        """Uplift (a normal force <= 0) or a grazing orbit (its multipliers are unreliable)."""
        notes = []
        if quantities.get("uplift"):
            fmin = quantities.get("min_normal_force", math.nan)
            notes.append(
                f"uplift: min normal force {fmin:.3g} N <= 0 (the bilateral contact model is "
                "outside its validity)"
            )
        g = quantities.get("graze", math.inf)
        if g is not None and g < GRAZE_TOL:
            notes.append(grazing_note(g, quantities.get("graze_at")))
        return "; ".join(notes)

    def graze_at(self, pm: SwitchPeriodMap) -> str:
        """Where the period's grazing measure was taken: "t = ... s, isolator i" for a switch
        (the first isolator of its tied group), or "" (a touch without a switch)."""
        for t, g, _, measure in pm.events:
            if measure == pm.graze:
                i = int(np.flatnonzero(self.groups() == g)[0])
                return f"t = {t:.6g} s of the period, isolator {i}"
        return ""


def grazing_note(graze: float, at: str | None = None) -> str:
    """The remark on a grazing orbit (``at``: where, :meth:`SwitchProblem.graze_at`)."""
    where = f" at {at}" if at else " between switches"
    return (
        f"grazing: a switching function touches zero{where} (normalised |n^T f-| = "
        f"{graze:.1e} < {GRAZE_TOL:g}); a slip phase is about to vanish or appear, the "
        "saltation matrix and the multipliers are unreliable here"
    )


def switch_problem(system, amplitude: float, *, load: HarmonicForce | None = None) -> SwitchProblem:
    """The isolated ``system`` with the switch model (true stick) under
    ``u''_hor = amplitude sin(2 pi f t)``, or under the force ``amplitude sin(2 pi f t +
    phase)`` on ``load``'s dofs. Any isolated system: a frame model, a shear building, a system
    from matrices (frozen normal forces or contacts); ``amplitude`` finite and >= 0 (a ground
    acceleration at most A_HIGHEST)."""
    from nsdyn.models.isolated.system import IsolatedSystem

    expect("system", system, isinstance(system, IsolatedSystem), "an IsolatedSystem "
           "(nsdyn.build_system, nsdyn.shear_building, ...)")  # fmt: skip
    amplitude = check_amplitude(amplitude, highest=A_HIGHEST if load is None else math.inf)
    if system.isolation is None:
        raise ValueError("shooting needs an isolated model; the fixed base is linear (use FRFs)")
    if load is not None and not isinstance(load, HarmonicForce):
        raise TypeError(f"load: expected a HarmonicForce, got {type(load).__name__}")
    ni = system.n_isolators
    Q = np.ascontiguousarray(system.Q, dtype=float)
    group = tied_groups(system.D @ Q)
    ng = int(group.max()) + 1
    if ng > MAX_ISOLATORS:  # (tied isolators count once: one mode each group)
        raise ValueError(f"switch shooting tabulates 3^n mode sets of the n isolators (tied ones "
                         f"count once): at most {MAX_ISOLATORS}, got {ng}")  # fmt: skip
    exc = Harmonic(amplitude, 1.0) if load is None else load.at_frequency(1.0, amplitude)
    P = system.params(exc, law="switch")
    P = with_law(P, "modes", np.zeros(ni, dtype=np.int64))
    A0, V, TAU, LF = mode_tables(system, P, Q, mode_sets(ng)[:, group])
    mu = np.ascontiguousarray(P[ks.I_MU], dtype=float)
    LFI = LF
    if ng < ni:  # a tied group sticks and slips as one: its rows are the sums (module text)
        first = np.array([int(np.flatnonzero(group == g)[0]) for g in range(ng)])
        one = np.zeros((ng, ni))
        one[group, np.arange(ni)] = 1.0
        V = np.ascontiguousarray(V[first])
        TAU = np.ascontiguousarray(np.einsum("gi,kid->kgd", one, TAU))
        LF = np.ascontiguousarray(np.einsum("gi,kid->kgd", one * mu[None, :], LF))
        mu = np.ones(ng)
    x_static, _ = system.static_equilibrium()
    z0 = Q.T @ x_static[: system.n]
    x_ref = np.concatenate([z0, np.zeros_like(z0)])
    return SwitchProblem(
        system,
        float(amplitude),
        Q,
        x_ref,
        A0,
        V,
        TAU,
        LF,
        mu,
        P,
        load,
        system.name,
        scale=balancing(A0),
        group=group,
        LFI=LFI,
    )


@dataclass(repr=False)
class SwitchShootingResult(ShootingResult):
    """A :class:`ShootingResult` with the switching events and grazing measure of the orbit."""

    events: list = field(default_factory=list)
    graze: float = math.inf

    @property
    def grazing(self) -> bool:
        return self.graze < GRAZE_TOL


def shoot_switch(
    problem: SwitchProblem, f: float, x0: np.ndarray | None = None, **options
) -> SwitchShootingResult:
    """Newton shooting on the switch model (:func:`nsdyn.periodic.shoot` with its ``options``
    ``tol``, ``max_iter``, ``disc``, ``n_steps``: same line search and failure policy) and the
    events of the final orbit; a grazing orbit is said so in ``message`` (converged or not)."""
    if not isinstance(problem, SwitchProblem):  # (an arctan problem: an AttributeError after)
        got = type(problem).__name__
        raise TypeError(f"problem: expected a switch_problem(system, amplitude), got {got} "
                        "(nsdyn.periodic.shoot shoots the others)")  # fmt: skip
    res = shoot(problem, f, x0, **options)
    pm = problem.period_map(res.x0, f, n_steps=res.n_steps, sens=False)
    out = SwitchShootingResult(**vars(res), events=pm.events, graze=pm.graze)
    if out.grazing:
        out.message = f"{out.message}; {grazing_note(pm.graze, problem.graze_at(pm))}"
    return out


def switch_response(
    system, amplitude: float, *, continuation: str = "sequential", load=None, **options
):
    """Frequency-response curve of the switch model on ``points`` log-spaced frequencies:
    ``continuation`` "sequential" (:func:`nsdyn.periodic.continue_sequential`, shooting with
    the stepped-sweep fallback) or "arclength" (pseudo-arclength in (x0, log f); the map's
    ``d phi_T / dT`` by central differences in T, exact flow); ``fmin``, ``fmax``, ``points``
    and ``options`` as for :func:`nsdyn.periodic.continuation.continue_range`."""
    from nsdyn.periodic.continuation import continue_range
    from nsdyn.periodic.problem import load_amplitude_note

    problem = switch_problem(system, amplitude, load=load)  # (the amplitude checked first)
    load_amplitude_note(load, problem.amplitude)
    curve = continue_range(problem, continuation=continuation, **options)
    curve.info.update(law=LAW_NAME, map=METHOD_NAME)
    return curve
