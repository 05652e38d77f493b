"""What a run of the deck on bidirectional isolators gives the engineer: orbits, forces, peaks.

Isolator i slips u_i = B_i q (``u``, shape (nt, ni, 2)); the resultant displacement |u_i| =
√(u_x² + u_y²) is the quantity a displacement capacity is checked against (not the larger
component). The bearing's resisting forces: friction f_i (the stick force τ_i in stick),
restoring N_i u_i/R_i + K_lam u_i, damper and rim stop; their resultants are peaked the same way.
Deck torsion θ (rad) and the displacement of the deck's corner isolators follow from q.

A numerical failure (step underflow, non-finite state, singular constraint system, chattering
switch events, too many steps) raises :class:`PlaneIntegrationError` with time and reason; an
uplift (a normal force reaching zero) ends the run at its located time and is reported in the
result and its summary (``uplift``), with a warning. Under a bilateral contact the run goes on
and ``tension`` reports the first located onset of tension (time, isolator), the number of
onsets, the smallest normal force and the tensile intervals of each isolator, read on the
outputs with the zero crossings interpolated linearly between them (``contact_tension``). Under
a unilateral contact (systems from matrices) ``flights`` counts the lift-offs and landings
(the events into and out of the free mode), the flight time of each contact, the largest
landing velocity and impulse and the kinetic energy the landings took (``contact_flights``).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from nsdyn._checks import NumericalFailure
from nsdyn._tabular import Tabular
from nsdyn.models.isolated import _kplanerun as kr
from nsdyn.models.isolated.defaults import EPS, ETA
from nsdyn.models.isolated.friction import stick_velocity, sticks

MESSAGES = {
    kr.ST_UNDERFLOW: "step size underflow at t = {t:.6g} s (a stiff regularised law: lower eps, "
    "or use law 'switch')",
    kr.ST_MAX_STEPS: "too many steps before t = {t:.6g} s (raise max_steps; lower eps of the "
    "regularised law, or raise eta of the switch law: its stick band |v| <= eta)",
    kr.ST_NONFINITE: "NaN or inf in the state at t = {t:.6g} s (check the record and the bearings)",
    kr.ST_SINGULAR: "singular equations of motion at t = {t:.6g} s (check masses and positions)",
    kr.ST_CHATTER: "chattering stick-slip events at t = {t:.6g} s (use law 'arctan')",
    kr.ST_EVENTS: "too many stick-slip events before t = {t:.6g} s",
    kr.ST_STALL: f"the steps collapsed before t = {{t:.6g}} s: over {kr.STALL_STEPS:,} "
    "steps more than the record needs (the friction law is too sharp for the steps: the "
    "switch law's stick band eta = {eta:g} m/s too narrow for the velocities they resolve, "
    "or the arctan law's eps = {eps:g} s/m too large): raise eta (default "
    f"{ETA:g} m/s), lower eps (default {EPS:g} s/m), or use the other law",
    kr.ST_NEWTON: "Radau IIA's Newton iterations diverge at t = {t:.6g} s, down to the smallest "
    "step (lower eps, or use law 'switch')",
}
# the switch law has no eps: where its steps underflow the equations themselves are stiff
SWITCH_UNDERFLOW = ("step size underflow at t = {t:.6g} s (the switch law has no stiff "
                    "friction: check the mass, the inertia J and the bearings' stiffness and "
                    "damping for values orders of magnitude apart)")  # fmt: skip
# a triple pendulum's stiffness is its surfaces' elastic-plastic springs (yield displacement
# u_y), not a friction law's eps or eta: a small u_y and the inner surfaces' stiff reversals
TFP_MESSAGES = {
    kr.ST_MAX_STEPS: "too many steps before t = {t:.6g} s (a triple pendulum's surfaces yield "
    "within u_y, and each yield and reversal is stiff: the steps grow as u_y shrinks and as "
    "rtol tightens; raise u_y, loosen rtol, or raise max_steps)",
    kr.ST_STALL: f"the steps collapsed before t = {{t:.6g}} s: over {kr.STALL_STEPS:,} steps "
    "more than the record needs (a triple pendulum's surfaces yield within u_y, too small for "
    "the steps to follow): raise u_y; with friction coefficients far below a built bearing's "
    "(0.01-0.2) the stiff part is theirs (its elastic stage kappa_e u_y is min mu, whatever "
    "u_y): check mu1..mu4",
    kr.ST_SINGULAR: "the equations of motion have no solution at t = {t:.6g} s: the triple "
    "pendulum's damped elastic stage found no force (its Newton iteration failed, e.g. at an "
    "extreme zeta_e, or with R1 - R2 or R4 - R3 so small that its element is stiff): check "
    "zeta_e (default 1), u_y and the radii; or a building's normal forces on them had no "
    "solution (check masses and positions)",
}
# a run's counters (stats) as a summary names them, alike in every family
COUNTERS = {
    "steps": "n_steps",
    "rejected": "n_rejected",
    "evaluations": "n_evaluations",
    "events": "n_events",
}
MODE_NAMES = {0: "stick", 1: "slip", 2: "slip-start", 3: "free"}  # free: tensile or in flight
FREE = 3
MAX_INTERVALS = 100  # tensile intervals listed in a summary (the count says how many in all)


def impasse_message(system, impasse, t_fail: float) -> str:
    """A failed run's reason when its failing step met the impasse of the deck's normal forces
    (``impasse``: the record of :func:`nsdyn.models.isolated._kplane.evaluate`, (ρ of the last
    evaluation, then time and ρ of the last at ρ <= 0 since the last accepted step)), else
    ""; ``t_fail``: where the run stopped."""
    if impasse is None or not impasse[1] == impasse[1]:
        return ""
    h = getattr(system, "h", 0.0)
    return (
        f"the deck's equations of motion lose their solution at t = {t_fail:.6g} s (inertia "
        f"ratio {impasse[2]:.3g} in the step from there): the normal forces' share of the "
        f"friction and pendulum forces, through the overturning of a centre of mass h = "
        f"{h:g} m above the sliding surfaces, cancels the deck's inertia (Painlevé's paradox: "
        "with the bearings on one side tensile and those on the other, 2b away, slipping, the "
        "gain (h/2b)(mu + u/R) has reached 1; with one bearing stuck, the same for the turn "
        "about it). Past it the rigid deck's equations have no solution (what a real deck "
        "does there depends on its vertical and rocking flexibility, which this model does "
        "not have); lower h, widen the bearings' layout, or lower the friction"
    )


# the failures a step that met the impasse ends in (q̈ unbounded or not evaluated)
UNILATERAL_SWITCH_SINGULAR = (
    "no consistent set of stick, slip and contact modes at t = {t:.6g} s: isolators sticking, "
    "slipping and lifting off together left the switch law's equations singular; run it with "
    "law 'arctan' (the regularised law takes the same lift-offs without modes)"
)
IMPASSE_STATUSES = (kr.ST_SINGULAR, kr.ST_NONFINITE, kr.ST_UNDERFLOW, kr.ST_NEWTON, kr.ST_STALL)


class PlaneIntegrationError(NumericalFailure):
    """A run of the deck on bidirectional isolators failed; the message names time and reason."""


class UpliftWarning(UserWarning):
    """An isolator's normal force reached zero; the run ended there."""


class TensionWarning(UserWarning):
    """A bilateral contact carried tension (a normal force below zero); the run went on."""


class CapacityWarning(UserWarning):
    """An isolator reached its displacement capacity (its rim stop took the overshoot)."""


def contact_tension(t: np.ndarray, N: np.ndarray, info: np.ndarray) -> dict | None:
    """The tension record of a bilateral run (None when no normal force went tensile):
    first located onset (t_first_s, isolator), onsets, min_normal_force_N (outputs and
    accepted states) and its time, tensile_time_s per isolator and the intervals
    (isolator, t_start_s, t_end_s) where N_i <= 0 on the outputs, ends interpolated."""
    onsets = int(info[kr.I_NTEN])
    neg = N <= 0.0
    if onsets == 0 and not neg.any():
        return None
    intervals = []
    for i in range(N.shape[1]):
        d = np.diff(neg[:, i].astype(np.int8))
        starts = list(np.flatnonzero(d == 1) + 1)
        ends = list(np.flatnonzero(d == -1) + 1)
        if neg[0, i]:
            starts.insert(0, 0)
        if neg[-1, i]:
            ends.append(N.shape[0])
        for a, b in zip(starts, ends, strict=True):
            intervals.append((i, _crossing(t, N[:, i], a), _crossing(t, N[:, i], b)))
    k = np.unravel_index(np.argmin(N), N.shape)
    tt = np.zeros(N.shape[1])
    for i, a, b in intervals:
        tt[i] += b - a
    return {
        "t_first_s": float(info[kr.I_TTEN]), "isolator": int(info[kr.I_IFAIL]),
        "onsets": onsets,
        "min_normal_force_N": float(min(N.min(), info[kr.I_NMIN])) + 0.0,  # (no -0.0)
        "t_min_output_s": float(t[k[0]]),
        "tensile_time_s": [float(v) for v in tt],
        "intervals": [{"isolator": int(i), "t_start_s": float(a), "t_end_s": float(b)}
                      for i, a, b in intervals[:MAX_INTERVALS]],
        "n_intervals": len(intervals),
    }  # fmt: skip


def flight_times(times, contacts, lifts, n: int, t_end: float, open0=None) -> np.ndarray:
    """Time in flight per contact [s] from the located events in time order (``lifts``: True
    at a lift-off, False at a landing), a flight still open ending at ``t_end``; ``open0 =
    (t0, mask)``: the contacts already open at the run's start t0. Exact to the event times,
    whatever the output grid."""
    flight = np.zeros(n)
    since = np.full(n, np.nan)
    if open0 is not None:
        t0, mask = open0
        since[np.asarray(mask, bool)] = t0
    for t, i, new in zip(times, contacts, lifts, strict=True):
        if new:
            since[i] = t if np.isnan(since[i]) else since[i]
        elif np.isfinite(since[i]):
            flight[i] += t - since[i]
            since[i] = np.nan
    return flight + np.where(np.isfinite(since), t_end - since, 0.0)


TIE_N_RTOL = 1e-9  # a normal force this close to zero (x the run's largest) at uplift: tied


def _tied_at_zero(NO: np.ndarray, first: int) -> list[int]:
    """The isolators other than ``first`` whose normal force in the last row (the uplift's
    located instant) is zero to :data:`TIE_N_RTOL` of the run's largest: they lift with it."""
    scale = float(np.abs(NO).max()) if NO.size else 0.0
    at_zero = np.flatnonzero(NO[-1] <= TIE_N_RTOL * scale)
    return [int(i) for i in at_zero if i != first]


def contact_flights(t_end: float, EV: np.ndarray, info: np.ndarray, ni: int) -> dict:
    """The flight record of a unilateral run from its event table (lift-off: a mode change
    into MODE_FREE; landing: out of it, with the landing velocity R q̇⁻ and impulse in
    columns 4 and 5): lift_offs, landings, first_lift_off_s, flight_time_s per contact,
    max_landing_velocity_mps, max_landing_impulse_Ns, impact_energy_J (≤ 0)."""
    up = EV[:, 3] == FREE
    down = (EV[:, 2] == FREE) & ~up
    flight = flight_times(EV[:, 0], EV[:, 1].astype(int), up, ni, t_end)
    return {
        "lift_offs": int(up.sum()), "landings": int(down.sum()),
        "first_lift_off_s": float(EV[up, 0].min()) if up.any() else None,
        "flight_time_s": [float(v) for v in flight],
        "max_landing_velocity_mps": float(np.abs(EV[down, 4]).max()) if down.any() else 0.0,
        "max_landing_impulse_Ns": float(EV[down, 5].max()) if down.any() else 0.0,
        "impact_energy_J": float(info[kr.I_EIMP]),
    }  # fmt: skip


def _crossing(t: np.ndarray, n: np.ndarray, k: int) -> float:
    """Zero of n between outputs k − 1 and k by linear interpolation (t[k] at the ends)."""
    if k <= 0 or k >= t.size:
        return float(t[min(max(k, 0), t.size - 1)])
    a, b = n[k - 1], n[k]
    return float(t[k - 1] + (t[k] - t[k - 1]) * a / (a - b)) if a != b else float(t[k])


@dataclass(repr=False, eq=False)
class PlaneResult(Tabular):
    """Histories of one run (outputs at ``t``) and its summary (:meth:`summary`)."""

    system: object
    law: str
    t: np.ndarray  # (nt,) s
    q: np.ndarray  # (nt, 3) x [m], y [m], theta [rad] of O relative to the ground
    qd: np.ndarray  # (nt, 3)
    N: np.ndarray  # (nt, ni) normal forces [N]
    friction: np.ndarray  # (nt, ni, 2) resisting friction force [N]
    restoring: np.ndarray  # (nt, ni, 2) N u/R + K_lam u [N]
    other: np.ndarray  # (nt, ni, 2) damper + rim stop [N]
    modes: np.ndarray  # (nt, ni) 0 stick, 1 slip, 2 slip-start (switch law)
    events: np.ndarray  # (ne, 6) t, isolator, old mode, new mode, slip-start direction (x, y)
    stops: list  # rim contacts: dicts isolator, t_first_s, peak_overshoot_m
    uplift: dict | None  # {t_s, isolator[, also_isolators]} when a normal force reached zero
    stats: dict
    eps: float = EPS  # the laws' parameters of this run
    eta: float = ETA
    internal: np.ndarray | None = None  # (nt, 8 n_tfp) internal slips of triple pendulums
    contact: str = "detect"  # the contact assumption: detect | bilateral
    tension: dict | None = None  # a bilateral run's tension record (contact_tension)
    flights: dict | None = None  # a unilateral run's lift-offs and landings (contact_flights)

    @classmethod
    def from_run(cls, system, law, t, X, NO, FF, FR, FO, MO, EV, stops, info, status, eps, eta,
                 contact="detect", impasse=None, located=True):  # fmt: skip
        if status not in (kr.ST_OK, kr.ST_UPLIFT):
            msg = MESSAGES.get(status, f"integration failed (status {status}) at t = {{t:.6g}} s")
            if getattr(system, "has_tfp", False) and status in TFP_MESSAGES:  # its own advice
                msg = TFP_MESSAGES[status]
            if status == kr.ST_UNDERFLOW and law == "switch":
                msg = SWITCH_UNDERFLOW
            if status == kr.ST_SINGULAR and law == "switch" and contact == "unilateral":
                msg = UNILATERAL_SWITCH_SINGULAR  # (masses and positions are not the cause)
            msg = msg.format(t=info[kr.I_TFAIL], eta=eta, eps=eps)
            if status in IMPASSE_STATUSES:  # (the failing step met the impasse: its reason)
                msg = impasse_message(system, impasse, info[kr.I_TFAIL]) or msg
            raise PlaneIntegrationError(msg)
        nout = int(info[kr.I_NOUT])
        ne = min(int(info[kr.I_NEV]), EV.shape[0])
        if int(info[kr.I_NEV]) > EV.shape[0]:
            warnings.warn(
                f"{int(info[kr.I_NEV])} stick-slip events: the event table keeps the first "
                f"{EV.shape[0]} (summary 'n_events' counts all)",
                UserWarning,
                stacklevel=3,
            )
        contacts = [
            {"isolator": i, "t_first_s": float(stops[i, kr.P_TFIRST]),
             "peak_overshoot_m": float(stops[i, kr.P_PEAK])}
            for i in range(stops.shape[0]) if np.isfinite(stops[i, kr.P_TFIRST])
        ]  # fmt: skip
        uplift = None
        if status == kr.ST_UPLIFT:
            uplift = {"t_s": float(info[kr.I_TFAIL]), "isolator": int(info[kr.I_IFAIL])}
            tied = _tied_at_zero(NO[:nout], uplift["isolator"]) if located and nout else []
            if tied:  # (a symmetric deck's partners under the switch law; the arctan law's
                # friction breaks the symmetry by 1e-7 to 1e-3 of N: the kernel's first alone)
                uplift["also_isolators"] = tied
            also = f" (and {', '.join(map(str, tied))}, at the same instant)" if tied else ""
            warnings.warn(
                f"uplift at t = {uplift['t_s']:.6g} s: the normal force of isolator "
                f"{uplift['isolator']}{also} reached zero; the run ends there",
                UpliftWarning,
                stacklevel=3,
            )
            if not located:  # (a fixed-step loop's rows and rim contacts past the instant,
                # between its alpha points: not the run's)
                contacts = [c for c in contacts if c["t_first_s"] <= uplift["t_s"]]
                nout = max(1, int(np.searchsorted(t[:nout], uplift["t_s"], side="right")))
        for c in contacts:
            warnings.warn(
                f"isolator {c['isolator']} reached its displacement capacity at "
                f"t = {c['t_first_s']:.4g} s (peak overshoot {1e3 * c['peak_overshoot_m']:.3g} mm, "
                "taken by the rim stop)",
                CapacityWarning,
                stacklevel=3,
            )
        stats = {"steps": int(info[kr.I_NSTEP]), "rejected": int(info[kr.I_NREJ]),
                 "evaluations": int(info[kr.I_NFEV]), "events": int(info[kr.I_NEV])}  # fmt: skip
        k = slice(0, nout)
        tension = contact_tension(t[k], NO[k], info) if contact == "bilateral" else None
        if tension is not None:
            warnings.warn(
                f"the bilateral contact carried tension: the normal force of isolator "
                f"{tension['isolator']} went below zero at t = {tension['t_first_s']:.6g} s "
                f"({tension['onsets']} onsets, smallest {tension['min_normal_force_N']:.4g} N); "
                "an isolator in tension has no friction and no pendulum force",
                TensionWarning,
                stacklevel=3,
            )
        tk = t[k].copy()
        if located and uplift and nout and tk[-1] > uplift["t_s"]:  # (the kernel's row there;
            # ``located``: the loop writes one, as the fixed-step sparse path does not)
            tk[-1] = uplift["t_s"]
        res = cls(system, law, tk, X[k, :3], X[k, 3:6], NO[k], FF[k], FR[k], FO[k], MO[k],
                  EV[:ne].copy(), contacts, uplift, stats, eps, eta, X[k, 6:], contact,
                  tension)  # fmt: skip
        if contact == "unilateral":
            res.flights = contact_flights(float(res.t[-1]), EV[:ne], info, stops.shape[0])
        if getattr(system, "has_tfp", False):  # a triple pendulum's inner slider at its rims:
            from nsdyn.models.isolated.tfp import surface_limits  # the bearing's capacity

            for c in surface_limits(res):
                if c["surface"] in ("2", "3"):
                    warnings.warn(
                        f"isolator {c['isolator']} reached its displacement capacity at "
                        f"t = {c['t_first_s']:.4g} s (triple pendulum: surface {c['surface']} "
                        f"of the inner slider at its rim, peak overshoot "
                        f"{1e3 * c['peak_overshoot_m']:.3g} mm)",
                        CapacityWarning,
                        stacklevel=3,
                    )
        return res

    # ---- derived histories ------------------------------------------------------------
    def _slip(self, X) -> np.ndarray:
        pos = self.system.positions
        out = np.empty((X.shape[0], pos.shape[0], 2))
        out[:, :, 0] = X[:, [0]] - X[:, [2]] * pos[:, 1]
        out[:, :, 1] = X[:, [1]] + X[:, [2]] * pos[:, 0]
        return out

    @property
    def u(self) -> np.ndarray:
        """Isolator slips (nt, ni, 2) [m]."""
        return self._slip(self.q)

    @property
    def v(self) -> np.ndarray:
        """Isolator slip velocities (nt, ni, 2) [m/s]."""
        return self._slip(self.qd)

    @property
    def theta(self) -> np.ndarray:
        return self.q[:, 2]

    def resultant(self, a: np.ndarray) -> np.ndarray:
        """|a| over the last axis (x, y)."""
        return np.hypot(a[..., 0], a[..., 1])

    def sticks(self) -> np.ndarray:
        """(nt, ni) booleans: the isolator sticks (:func:`nsdyn.models.isolated.friction.sticks`,
        the one definition: the switch law's stick mode or band, the arctan law's friction
        below its utilisation limit), judged on the resultant slip speed |v|; a triple
        pendulum's on its surfaces' slip speeds (:func:`.tfp.surfaces_stuck`)."""
        speed = self.resultant(self.v)
        modes = self.modes if self.law == "switch" else None
        stick = sticks(speed, self.law, eps=self.eps, eta=self.eta, modes=modes)
        if self.internal is None or not getattr(self.system, "has_tfp", False):
            return stick
        from nsdyn.models.isolated.tfp import surfaces_stuck  # a TFP: no surface slides

        offs = [o - 6 if o >= 0 else -1 for o in self.system.internal_offsets()]
        v = stick_velocity(self.law, self.eps, self.eta)
        return surfaces_stuck(self.internal, self.t, offs, v, stick)

    def histories(self) -> dict:
        """Deck motion and per-isolator histories on ``t`` (units in the names; column j of a
        per-isolator array is isolator j): for :meth:`to_dataframe` / :meth:`to_xarray`."""
        u, v = self.u, self.v
        return {
            "x_m": self.q[:, 0], "y_m": self.q[:, 1], "theta_rad": self.q[:, 2],
            "vx_m_per_s": self.qd[:, 0], "vy_m_per_s": self.qd[:, 1],
            "omega_rad_per_s": self.qd[:, 2],
            "ux_iso_{}_m": u[..., 0], "uy_iso_{}_m": u[..., 1],
            "vx_iso_{}_m_per_s": v[..., 0], "vy_iso_{}_m_per_s": v[..., 1],
            "N_iso_{}_N": self.N,
            "friction_x_iso_{}_N": self.friction[..., 0],
            "friction_y_iso_{}_N": self.friction[..., 1],
            "restoring_x_iso_{}_N": self.restoring[..., 0],
            "restoring_y_iso_{}_N": self.restoring[..., 1],
            "other_x_iso_{}_N": self.other[..., 0], "other_y_iso_{}_N": self.other[..., 1],
            "mode_iso_{}": self.modes,
            **self._element_slips(),
        }  # fmt: skip

    def _element_slips(self) -> dict:
        """The series elements' slips as :meth:`histories` names them: ``s1x_iso_{}_m`` …"""
        return {f"{k}_iso_{{}}_m": a for k, a in self.element_slips().items()}

    def element_slips(self) -> dict:
        """The series elements' slips of triple pendulums [m] (nt, ni) per element and
        component, NaN for single-surface isolators: ``s1x`` … ``s4y`` (empty without triple
        pendulums)."""
        offs = getattr(self.system, "internal_offsets", lambda: [])()
        if self.internal is None or not any(o >= 0 for o in offs):
            return {}
        out = {}
        for k in range(4):
            for c, name in enumerate("xy"):
                a = np.full((self.t.size, len(offs)), np.nan)
                for i, o in enumerate(offs):
                    if o >= 0:
                        a[:, i] = self.internal[:, o - 6 + 2 * k + c]
                out[f"s{k + 1}{name}"] = a
        return out

    def energy(self, ground) -> dict:
        """The run's work–energy balance under ``ground``, what it was run with (terms in J
        and ``energy_closure``: :func:`~nsdyn.models.isolated.plane_energy.plane_energy`)."""
        from nsdyn.models.isolated.plane_energy import plane_energy

        return plane_energy(self, ground)

    def peak_resultant_displacement(self) -> np.ndarray:
        """max_t |u_i(t)| per isolator [m]."""
        return self.resultant(self.u).max(axis=0)

    def summary(self) -> dict:
        """Scalars (and short per-isolator lists) with units in the key names."""
        ru = self.resultant(self.u)
        rf = self.resultant(self.friction)
        rr = self.resultant(self.restoring)
        ux, uy = self.u[..., 0], self.u[..., 1]
        located = self.uplift and len(self.t) > 1 and self.t[-1] == self.uplift["t_s"]
        s = {
            "law": self.law,
            "n_isolators": int(self.system.n_isolators),
            # where the run ended: an uplift's located instant (its last output row)
            "t_end_s": float(self.uplift["t_s"]) if self.uplift else float(self.t[-1]),
            "peak_resultant_displacement_m": float(ru.max()),
            "peak_resultant_displacement_per_isolator_m": [float(v) for v in ru.max(axis=0)],
            "peak_component_displacement_m": float(max(np.abs(ux).max(), np.abs(uy).max())),
            # (a run ended by uplift has none: its last output is no rest)
            "residual_displacement_m": None if self.uplift else float(ru[-1].max()),
            "peak_resultant_friction_N": float(rf.max()),
            "peak_resultant_restoring_N": float(rr.max()),
            "peak_torsion_rad": float(np.abs(self.theta).max()),
            # the uplift instant's normal force is zero: its row's, located to 1e-11 s, is the
            # bisection's side at or below zero; at the start's it is below (an uplift there)
            "min_normal_force_N": min(0.0, float(self.N[:-1].min() if located else self.N.min()))
            if self.uplift
            else float(self.N.min()),
            "max_normal_force_N": float(self.N.max()),
            "stick_fraction": float(np.mean(self.sticks())),
            "rim_contacts": self.stops,
            "uplift": self.uplift,
            "contact": self.contact,
        }
        if self.contact == "bilateral":
            s["tension"] = self.tension
            s["would_lift_off"] = self.tension is not None
        if self.flights is not None:
            s.update(self.flights)
        if getattr(self.system, "has_tfp", False):
            from nsdyn.models.isolated.tfp import beyond_capacity, surface_limits

            s["tfp_surface_limits"] = surface_limits(self)
            s["tfp_beyond_capacity"] = beyond_capacity(self)
        # counters as every family names them (n_steps, n_rejected, n_evaluations, n_events)
        s.update({COUNTERS.get(k, k): v for k, v in self.stats.items()})
        return s
