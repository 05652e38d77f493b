"""Model advisor: the cheapest rung of the model ladder whose error stays under a tolerance.

``advise(frame, motion, tol=0.05, isolation=...) -> Advice(fidelity, f_max, evidence)``

1. **Amplitude: do the isolators ever slide?** The isolators stay stuck while the friction force
   they must carry, ``|tau_i|``, stays below ``mu lam_i``; stuck isolators lock the base, so the
   fixed-base model is exact (up to the stiff base diaphragm). PGA against ``mu g`` is only a
   hint (the base-shear demand is the structure's response, not the PGA), so the advisor runs
   the switch model event-driven over the whole record (a short, linear run while nothing
   slides) and reads the answer off it: no switching event and stick at every output instant
   means "fixed". The largest friction utilisation ``max |tau_i| / (mu lam_i)`` is the margin.
2. **Frequency content** ``f95``: the frequency below which 95 % of the record's Fourier
   energy ``|A(f)|^2`` lies. It is reported and sets the f_max a modal-truncation rule of thumb
   would pick (``f_prior``), but the choice rests on measured errors: stick-slip transitions are
   impulsive and excite modes far above a low-frequency record's band.
3. **Probes**: the ladder ``rigid, CB-5, CB-10, CB-15, CB-20`` (or, for stuck isolators,
   ``fixed`` at 5/10/20 Hz) is run over the strong-motion part of the record (start to the
   time of PROBE_ARIAS of the Arias intensity, at least PROBE_MIN_S), each rung against the
   next PROBE_AHEAD richer ones. The error estimate of a rung is its largest relative
   difference in the requested peak metrics (x_iso, IDR, floor acceleration) from those; the
   first rung under ``tol`` is chosen. If none is, the advice is the full model (the probes say
   why). Comparing with two richer rungs, not one, matters for the floor acceleration: the
   peak of the arctan model converges slowly and not monotonically in f_max (stick-slip
   transitions are nearly impulsive; see ``nsdyn bench fidelity``).

Every number used is in ``Advice.evidence``; :meth:`Advice.report` prints it.

Space frames on isolators (:func:`advise_3d`): the ladder fixed / rigid / cb, probed by
:func:`nsdyn.models.isolated.building3d_advice.advise_building` (the cb rung over the record's
strong-motion part; the rigid deck against it on the isolators' peak displacement and base
shear), returned as an :class:`Advice`.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field

import numpy as np

__all__ = [
    "Advice",
    "advise",
    "advise_3d",
    "energy_frequency",
    "stick_probe",
]

DEFAULT_TOL = 0.05  # relative error allowed on each peak metric
ENERGY_FRACTION = 0.95  # f95: fraction of the Fourier energy below the reported frequency
PROBE_ARIAS = 0.8  # probe window ends when the Arias intensity reaches this fraction
PROBE_MIN_S = 5.0  # s, shortest probe window (unless the record is shorter)
PROBE_RTOL = 1e-5  # radau tolerance of the probes (errors ~1e-6, far below any tol)
STICK_RTOL = 1e-5  # event tolerance of the stick probe
SLIDING_LADDER = [("rigid", None), ("cb", 5.0), ("cb", 10.0), ("cb", 15.0), ("cb", 20.0)]
FIXED_LADDER = [("fixed", 5.0), ("fixed", 10.0), ("fixed", 20.0)]
METRICS = ("x_iso", "idr", "floor_acc")  # peak metrics the advice guarantees by default
PROBE_AHEAD = 2  # a rung's error estimate: its largest difference from the next 2 richer rungs
STICK_MODEL_FMAX = 5.0  # Hz, Craig-Bampton cut-off of the stick probe


@dataclass
class Advice:
    """The advised model and the evidence for it."""

    fidelity: str
    f_max: float | None
    evidence: dict = field(default_factory=dict)

    @property
    def label(self) -> str:
        if self.fidelity in ("cb", "fixed"):
            return f"{self.fidelity} (f_max = {self.f_max:g} Hz)"
        return self.fidelity

    def report(self) -> str:
        """Readable account of the choice and every number behind it."""
        e = self.evidence
        lines = [f"advised model: {self.label}  (tol = {e.get('tol', float('nan')):g})"]
        if "pga_mps2" in e:
            lines.append(
                f"  PGA {e['pga_mps2']:.3g} m/s² = {e['pga_over_mu_g']:.3g} mu g; "
                f"f95 = {e['f95_hz']:.3g} Hz (rule-of-thumb f_max {e['f_prior_hz']:g} Hz)"
            )
        sp = e.get("stick_probe")
        if sp:
            lines.append(
                f"  stick probe ({sp['model']}, switch model, event-driven, "
                f"{sp['duration_s']:.3g} s): {sp['verdict']}; slip events {sp['slip_events']}, "
                f"stick fraction {sp['stick_fraction']:.3f}, max friction utilisation "
                f"{sp['max_utilisation']:.3g}"
            )
        for p in e.get("probes", []):
            errs = ", ".join(f"{k} {v:.2e}" for k, v in p["errors"].items())
            lines.append(
                f"  probe {p['model']:8s} vs {p['vs']:8s} over [{p['window_s'][0]:g}, "
                f"{p['window_s'][1]:g}] s: {errs}  -> {'ok' if p['ok'] else 'above tol'}"
            )
        if "decision" in e:
            lines.append(f"  {e['decision']}")
        return "\n".join(lines)


def energy_frequency(motion, fraction: float = ENERGY_FRACTION) -> float:
    """Frequency [Hz] below which ``fraction`` of the horizontal record's Fourier energy lies."""
    a = np.asarray(motion.a_hor, dtype=float)
    A2 = np.abs(np.fft.rfft(a - a.mean())) ** 2
    f = np.fft.rfftfreq(a.size, motion.dt)
    E = np.cumsum(A2)
    if E[-1] <= 0:
        return 0.0
    return float(f[min(np.searchsorted(E / E[-1], fraction), f.size - 1)])


def probe_window(motion) -> tuple[float, float]:
    """[t0, t1]: from the start to PROBE_ARIAS of the Arias intensity, at least PROBE_MIN_S."""
    a2 = np.cumsum(np.asarray(motion.a_hor, dtype=float) ** 2)
    t = motion.t
    if a2[-1] <= 0:
        return float(t[0]), float(t[-1])
    k = int(np.searchsorted(a2 / a2[-1], PROBE_ARIAS))
    t1 = max(float(t[min(k, t.size - 1)]), float(t[0]) + PROBE_MIN_S)
    return float(t[0]), float(min(t1, t[-1]))


def stick_probe(frame, motion, isolation, f_max: float = STICK_MODEL_FMAX) -> dict:
    """Run the switch model event-driven on CB-``f_max``: does any isolator ever leave stick?

    Returns the verdict ("stick throughout" or "slides"), the number of switching events, the
    stick fraction of the output instants and max_t,i |tau_i| / (mu_i lam_i).
    """

    import warnings

    from nsdyn._checks import NotedWarning
    from nsdyn.models.isolated.system import build_system
    from nsdyn.solve.integrate import IntegrationError
    from nsdyn.solve.transient import simulate

    iso = isolation.changed(law="switch")
    system = build_system(frame, iso, fidelity="cb", f_max=f_max)
    out = {"model": f"cb-{f_max:g}", "duration_s": float(motion.duration)}
    try:
        with warnings.catch_warnings():  # (a probe: the law's notes are the run's to say)
            warnings.simplefilter("ignore", NotedWarning)
            res = simulate(system, motion, method="event", rtol=STICK_RTOL,
                           atol=STICK_RTOL * 1e-2)  # fmt: skip
    except IntegrationError as e:
        out.update(
            verdict=f"failed ({e.reason}); assumed sliding",
            slip_events=-1,
            stick_fraction=float("nan"),
            max_utilisation=float("nan"),
            wall_s=0.0,
        )
        return out
    r = res.response
    mu = iso.per_isolator("mu", system.n_isolators)
    lam = r.lam[:, : system.n_isolators]
    util = float(np.max(np.abs(r.tau) / (mu[None, :] * np.maximum(lam, 1e-300))))
    n_events = int(res.stats.get("n_events", 0))
    stuck = n_events == 0 and r.stick_fraction == 1.0
    out.update(
        verdict="stick throughout" if stuck else "slides",
        slip_events=n_events,
        stick_fraction=float(r.stick_fraction),
        max_utilisation=util,
        wall_s=float(res.wall_s),
    )
    return out


def _peaks(res) -> dict:
    r = res.response
    return {"x_iso": r.x_iso_max, "idr": r.idr_max, "floor_acc": r.floor_acc_max}


# the peaks below which a rung's difference is no error to choose by, a response this small
# being no design quantity (0.1 mm of slip, a drift ratio of 1e-5, 1e-3 g): a very stiff
# frame's zero drift on the rigid deck against 9e-8 from cb-5 refused the rigid rung at 100 %
PEAK_FLOOR = {"x_iso": 1e-4, "idr": 1e-5, "floor_acc": 1e-2}  # m, -, m/s²


def _rel_err(a: float, b: float, floor: float = 0.0) -> float:
    """|a - b| relative to the richer rung's peak ``b``, or to ``floor`` where that is larger."""
    scale = max(abs(b), floor)
    return 0.0 if scale == 0 and a == b else abs(a - b) / scale if scale else 1.0


def _rung(fid: str, fm: float | None) -> str:
    return f"{fid}-{fm:g}" if fm is not None else fid


def advise(
    frame,
    motion,
    tol: float = DEFAULT_TOL,
    isolation=None,
    *,
    metrics: tuple[str, ...] = METRICS,
    probe: bool = True,
) -> Advice:
    """The cheapest fidelity / f_max whose estimated error on ``metrics`` stays under ``tol``.

    Parameters
    ----------
    frame : nsdyn.structure.frame.Frame
    motion : GroundMotion         the whole record the scene will run
    tol : float                   relative error allowed on each peak metric
    isolation : Isolation         default: the seed's isolators (``Isolation()``)
    metrics : tuple of str        among "x_iso", "idr", "floor_acc" (what the scene needs)
    probe : bool                  False: decide from f95 and the stick probe only (no ladder runs)
    """
    from nsdyn.models.isolated.system import Isolation, build_system
    from nsdyn.solve.transient import simulate

    if frame is None or not hasattr(frame, "assemble"):
        raise ValueError(
            "advise: the model advisor chooses among a frame's model ladder (rigid, "
            "Craig-Bampton, full); it needs a frame, got "
            f"{'None' if frame is None else type(frame).__name__} (a system built from "
            "matrices or a shear building is used as given)"
        )
    bad = set(metrics) - set(METRICS)
    if bad or not metrics:
        raise ValueError(f"metrics: expected some of {METRICS}, got {metrics}")
    if isinstance(tol, bool) or not (isinstance(tol, numbers.Real) and math.isfinite(tol)
                                     and tol > 0):  # fmt: skip
        raise ValueError(f"tol: expected a relative error > 0 (0.05 for 5 %), got {tol!r}")
    if not motion.pga > 0:  # (its rungs differed by round-off and static drift alone)
        raise ValueError("motion: its horizontal acceleration is zero throughout: no response "
                         "to choose a model by")  # fmt: skip
    iso = Isolation() if isolation is None else isolation
    mu = float(np.max(np.atleast_1d(iso.mu)))
    f95 = energy_frequency(motion)
    ladder_f = [5.0, 10.0, 15.0, 20.0]
    f_prior = next((f for f in ladder_f if f >= f95), ladder_f[-1])
    ev: dict = {
        "tol": tol,
        "metrics": list(metrics),
        "pga_mps2": float(motion.pga),
        "mu_g_mps2": mu * iso.g,
        "pga_over_mu_g": float(motion.pga) / (mu * iso.g),
        "f95_hz": f95,
        "f_prior_hz": f_prior,
        "probes": [],
    }
    sliding = True
    if iso.law != "none" and mu > 0:
        sp = stick_probe(frame, motion, iso)
        ev["stick_probe"] = sp
        sliding = sp["verdict"] != "stick throughout"
    if not probe:
        fid, fm = ("cb", f_prior) if sliding else ("fixed", f_prior)
        ev["decision"] = f"no probes requested: f_max from f95 ({f_prior:g} Hz)"
        return Advice(fid, fm, ev)
    t0, t1 = probe_window(motion)
    win = motion.window(t0, t1)
    ladder = SLIDING_LADDER if sliding else FIXED_LADDER
    # fixed-base metrics: no isolator slip; x_iso is identically zero and not compared
    use = [m for m in metrics if sliding or m != "x_iso"]
    results: dict = {}

    def run(k):
        if k not in results:
            fid, fm = ladder[k]
            system = build_system(frame, iso, fidelity=fid, f_max=fm)
            res = simulate(system, win, method="radau", rtol=PROBE_RTOL, atol=PROBE_RTOL * 1e-2)
            results[k] = (_peaks(res), res.wall_s, system.n)
        return results[k]

    for k in range(len(ladder) - 1):
        pk, wall, n = run(k)
        richer = list(range(k + 1, min(k + 1 + PROBE_AHEAD, len(ladder))))
        errs = {m: 0.0 for m in use}
        for j in richer:
            pj = run(j)[0]
            for m in use:
                errs[m] = max(errs[m], _rel_err(pk[m], pj[m], PEAK_FLOOR[m]))
        ok = max(errs.values()) <= tol
        ev["probes"].append(
            {
                "model": _rung(*ladder[k]),
                "vs": "/".join(_rung(*ladder[j]) for j in richer),
                "window_s": [t0, t1],
                "errors": errs,
                "ok": ok,
                "n_dof": n,
                "wall_s": wall,
            }
        )
        if ok:
            fid, fm = ladder[k]
            why = "isolators stick throughout: fixed base is exact; " if not sliding else ""
            ev["decision"] = (
                f"{why}{_rung(fid, fm)} is the cheapest rung whose peak metrics differ from "
                f"the next richer rung(s) by at most {max(errs.values()):.2g} <= tol {tol:g}"
            )
            return Advice(fid, fm, ev)
    fid, fm = ladder[-1]
    if sliding:
        ev["decision"] = (
            f"no reduced rung met tol {tol:g} against the next one (last: "
            f"{max(ev['probes'][-1]['errors'].values()):.2g}); use the full model"
        )
        return Advice("full", None, ev)
    ev["decision"] = f"fixed base; richest probed f_max {fm:g} Hz (tol not met below it)"
    return Advice(fid, fm, ev)


def advise_3d(frame, bearings, motion, tol: float = DEFAULT_TOL, **kw) -> Advice:
    """The cheapest rung (fixed, rigid, cb) of the space frame ``frame`` on ``bearings`` (one
    Bearing or one per base node) under the three-component record ``motion`` whose peak
    metrics the cb probe confirms within ``tol``; ``kw``: f_max, min_mass, base, metrics
    (:data:`~nsdyn.models.isolated.building3d_advice.ADVICE_METRICS`), solver, system
    (:func:`~nsdyn.models.isolated.building3d_advice.advise_building`)."""
    from nsdyn.models.isolated.building3d_advice import advise_building

    a = advise_building(frame, bearings, motion, tol=tol, **kw)
    return Advice(a["fidelity"], a["f_max"], a["evidence"])
