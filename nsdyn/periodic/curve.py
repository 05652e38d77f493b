"""Frequency-response curves: one periodic orbit per point, with its provenance and stability.

A point holds the orbit's start ``x0`` at frequency ``f``, the Floquet multipliers ``rho``
(stable when ``max |rho| < 1``; a growth is checked against a second map before it is called
unstable, :mod:`nsdyn.periodic.stability`; none when that check could not decide, the note then
gives the first map's value), the response quantities of its model, and how it was found:
by shooting (``H(x0, f) = phi_T(x0) - x0 = 0`` to the shooting tolerance, sequentially or
along the arclength ``s``) or by the stepped sweep (its residual is then the estimated
distance to the steady state). A curve collects the points of one forcing amplitude and the
bifurcations detected between them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from nsdyn._brief import brief_repr
from nsdyn._checks import did_you_mean
from nsdyn.models.isolated.friction import STICK_SLIP_MIN, stick_slip
from nsdyn.periodic.bifurcation import STABLE_MARGIN, family_note
from nsdyn.periodic.discretisation import MORE_STEPS, Discretisation
from nsdyn.periodic.protocol import GRAZE_TOL, PeriodicModel
from nsdyn.periodic.shooting import ShootingResult, _evaluate, floquet_multipliers
from nsdyn.periodic.stability import check_verdict
from nsdyn.periodic.sweeps import WARMUP_PERIODS, SweepResult

# the largest scaled residual of a resumed curve's last orbit (1 % of the orbit's range: an
# orbit of this problem has the shooting tolerance; one of another amplitude, ~0.5)
START_RESIDUAL = 1e-2
# the columns of a curve's rows (the sweep CSV)
ROW_KEYS = ("f", "A", "IDR", "a", "a_floors", "x_iso", "stick_all_period", "stable",
            "max_multiplier_modulus", "method", "newton_iterations", "residual", "converged",
            "n_steps", "uplift", "note")  # fmt: skip
# the numbers of a point a curve's column can give
POINT_NUMBERS = ("f", "residual", "iterations", "n_steps", "converged", "s", "dlogf_ds",
                 "max_multiplier", "stable")  # fmt: skip


@dataclass
class OrbitPoint:
    """One periodic solution on a frequency-response curve."""

    f: float
    x0: np.ndarray
    method: str  # "shooting" (sequential), "arclength" or "sweep"
    converged: bool
    iterations: int
    residual: float
    multipliers: np.ndarray
    n_steps: int
    note: str = ""  # why shooting failed (sweep points) or other remarks
    quantities: dict = field(default_factory=dict)
    s: float = float("nan")  # arclength along the curve (arclength points)
    dlogf_ds: float = float("nan")  # tangent's parameter component
    X: np.ndarray | None = field(default=None, repr=False)

    @property
    def max_multiplier(self) -> float:
        return float(np.max(np.abs(self.multipliers))) if self.multipliers.size else math.nan

    @property
    def stable(self) -> bool | None:
        """Whether the orbit is stable; None without an orbit, or for a grazing one (its
        multipliers unreliable: its note says so, and a CSV read by stable trusted them)."""
        graze = self.quantities.get("graze")  # (a switch-law orbit's grazing measure)
        grazing = isinstance(graze, float) and graze < GRAZE_TOL
        if not self.multipliers.size or not self.converged or grazing:
            return None
        return bool(self.max_multiplier < 1.0 + STABLE_MARGIN)


@dataclass(repr=False)
class Curve:
    """A frequency-response curve of periodic solutions at one forcing amplitude."""

    __repr__ = brief_repr  # arrays by shape, not in full

    amplitude: float
    points: list[OrbitPoint]
    bifurcations: list[dict] = field(default_factory=list)
    info: dict = field(default_factory=dict)

    def column(self, name: str) -> np.ndarray:
        """A per-point value as an array: a quantity of the points (``"idr"``, ``"acc"``,
        ``"x_iso"``, ...), a number of theirs (``"f"``, ``"residual"``, ``"max_multiplier"``,
        ...) or a column of :meth:`rows` (``"IDR"``, ``"a"``, ...); ValueError naming the
        names there are."""
        quantities = {k for p in self.points for k in p.quantities}
        rows = self.rows()
        if name in quantities:  # (a failed point's: none, as in its row)
            vals = [p.quantities.get(name) if p.converged else None for p in self.points]
        elif name in POINT_NUMBERS:
            vals = [getattr(p, name) for p in self.points]
        elif rows and name in rows[0]:
            vals = [r[name] for r in rows]
        else:
            known = sorted(quantities | set(POINT_NUMBERS) | set(rows[0] if rows else ()))
            raise ValueError(f"name: expected a column of the curve, one of {known}, got "
                             f"{name!r}{did_you_mean(name, known)}")  # fmt: skip
        return np.asarray([np.nan if v is None else v for v in vals])

    def summary(self) -> dict:
        """The curve as plain values (NaN as None): ``amplitude``, ``points``, the band
        ``f_min_hz`` and ``f_max_hz``, the points ``converged``, ``unstable`` and from the
        stepped sweep (``sweep_points``, converged), the ``continuation``, the frequencies
        skipped (``skipped_hz``) and why (``skipped_why``), the ``bifurcations`` found, and
        each quantity's largest value over the converged points without uplift (a unilateral
        orbit's counts) and its frequency (``idr_max``, ``idr_max_f_hz``, ``acc_max_mps2``,
        ``x_iso_max_m``, ...; a deck's curve: ``u_peak_max_m``, the resultant slip's, and
        ``u_peak_max_f_hz``)."""
        f = self.column("f") if self.points else np.zeros(0)
        out = {"amplitude": self.amplitude, "points": len(self.points),
               "f_min_hz": float(f.min()) if f.size else None,
               "f_max_hz": float(f.max()) if f.size else None,
               "converged": sum(p.converged for p in self.points),
               "unstable": sum(p.stable is False for p in self.points),
               "sweep_points": sum(p.method == "sweep" and p.converged for p in self.points),
               "continuation": self.info.get("continuation"),
               "skipped_hz": list(self.info.get("skipped_hz", [])),
               "skipped_why": list(self.info.get("skipped_why", [])),
               "bifurcations": len(self.bifurcations)}  # fmt: skip
        # maxima over the steady states the model holds, as the sweep's table: converged, and
        # a bilateral orbit without uplift (a unilateral one that lifts off counts; a failed
        # point's numbers are none: the switch sweep left 155 m there)
        held = np.array([p.converged and (p.quantities.get("uplift") is not True
                                          or p.method == "unilateral") for p in self.points],
                        dtype=bool)  # fmt: skip
        deck = any("u_peak_m" in p.quantities for p in self.points)  # (a deck's orbits: its
        # slip's peak, not a frame's drifts, all None there)
        peaks = (("u_peak", "_m"),) if deck else (("idr", ""), ("acc", "_mps2"), ("x_iso", "_m"))
        for q, unit in peaks:
            name = "u_peak_m" if deck else q
            v = np.array([p.quantities.get(name, math.nan) for p in self.points], dtype=float)
            ok = np.isfinite(v) & held
            k = int(np.argmax(np.where(ok, v, -np.inf))) if ok.any() else None
            out[f"{q}_max{unit}"] = None if k is None else float(v[k])
            # (a peak of 0 at every point, the rigid fidelity's drift, has no frequency: the
            # first point's was given)
            out[f"{q}_max_f_hz"] = None if k is None or v[k] == 0.0 else float(f[k])
        return out

    def to_dataframe(self):
        """A pandas DataFrame of :meth:`rows`, one row per point indexed by ``f`` [Hz] (the
        sweep CSV's columns), ``df.attrs`` the summary's scalars (needs the ``frames``
        extra)."""
        from nsdyn._tabular import _need

        pd = _need("pandas")
        rows = self.rows()  # (a deck's columns are its own: the frame's gave NaN columns)
        df = pd.DataFrame(rows, columns=list(rows[0]) if rows else list(ROW_KEYS)).set_index("f")
        df.attrs.update({k: v for k, v in self.summary().items() if not isinstance(v, list)})
        return df

    def to_xarray(self):
        """:meth:`to_dataframe` as an xarray Dataset over ``f`` [Hz], the summary's scalars
        and strings as attributes (a bool as 0/1: netCDF stores no bool; needs the ``frames``
        extra)."""
        from nsdyn._tabular import _need

        _need("xarray")
        df = self.to_dataframe()
        ds = df.to_xarray()
        ds.attrs = {k: int(v) if isinstance(v, bool) else v for k, v in df.attrs.items()
                    if isinstance(v, int | float | str)}  # fmt: skip
        return ds

    def rows(self) -> list[dict]:
        """One flat record per point (the sweep CSV), keyed by :data:`ROW_KEYS`, a point
        without a steady state (``converged`` False) without its response (NaN); a deck's
        curve by the deck sweep's columns (:func:`nsdyn.periodic.plane.curve_rows`: its
        frame columns were all NaN)."""
        if any("u_peak_m" in p.quantities for p in self.points):
            from nsdyn.periodic.plane import curve_rows

            return curve_rows(self)
        out = []
        for p in self.points:
            q = p.quantities if p.converged else {}  # (a failed point's last period is no
            # steady state: the switch sweep's left 3.7e-5 m, as if one, beside "False")
            values = (p.f, self.amplitude, q.get("idr", math.nan), q.get("acc", math.nan),
                      q.get("acc_floors", math.nan), q.get("x_iso", math.nan),
                      q.get("stick_all_period", ""), "" if p.stable is None else p.stable,
                      p.max_multiplier if p.converged else math.nan,  # (no orbit: no verdict)
                      p.method, p.iterations, p.residual, p.converged,
                      p.n_steps, p.quantities.get("uplift", ""), p.note)  # fmt: skip
            out.append(dict(zip(ROW_KEYS, values, strict=True)))
        return out


def _point_from_shoot(
    problem: PeriodicModel,
    res: ShootingResult,
    method: str,
    note: str = "",
    disc: Discretisation | None = None,
) -> OrbitPoint:
    """A point from a converged shooting solve (``disc``: the map's discretisation; a growth
    is checked, :func:`nsdyn.periodic.stability.check_verdict`)."""
    rho = floquet_multipliers(res.monodromy)
    rho, verdict, why = check_verdict(problem, res.f, res.x0, rho, disc)
    rho = rho if verdict is not None else np.zeros(0)  # undecided: no multipliers (the note)
    q = problem.orbit_quantities(res.f, res.X)
    stalled = res.message if res.message.startswith("converged (stalled") else ""  # (above tol)
    notes = (note, stalled, why, problem.validity_note(q), family_note(rho))
    note = "; ".join(n for n in notes if n)
    return OrbitPoint(
        res.f,
        res.x0.copy(),
        method,
        True,
        res.iterations,
        res.residual,
        rho,
        res.n_steps,
        note,
        q,
        X=res.X,
    )


def _point_from_sweep(
    problem: PeriodicModel, sw: SweepResult, why: str, disc: Discretisation | None = None
) -> OrbitPoint:
    """A point from the stepped sweep; its 'residual' is the estimated distance to the steady
    state. Quantities are NaN, with the model's verdict on uplift, when a period could not be
    integrated: the first one, or a later one that stopped the sweep (the period before it
    would pass for the point's; the deck's loop stops at an uplift). A growth of the last
    period's multipliers is checked as for a shooting point."""
    rho = floquet_multipliers(sw.monodromy) if sw.monodromy is not None else np.zeros(0)
    rho, verdict, check = check_verdict(problem, sw.f, sw.x0, rho, disc)
    rho = rho if verdict is not None or not rho.size else np.zeros(0)
    probe = ""
    stopped = sw.periods_done > 0 and sw.x_stop is not None  # a later period failed
    if sw.periods_done > 0 and not stopped:
        q = problem.orbit_quantities(sw.f, sw.X)
    elif stopped:
        q, probe = problem.quantities_without_orbit(sw.f, sw.x_stop, 1)  # the failing period
    else:
        # the horizon of continuation's retry decision (as many periods as the warm start)
        q, probe = problem.quantities_without_orbit(sw.f, sw.x0, WARMUP_PERIODS)
    valid = problem.validity_note(q)  # (an uplift or a rim contact: no more steps cure it)
    cause = valid if q.get("uplift") is True or q.get("rim_contact") else ""
    hint = MORE_STEPS if not cause else ""  # (then the cause leads, without that advice)
    notes = (f"shooting failed: {why.replace(MORE_STEPS, hint)}",
             f"sweep: {sw.message.replace(MORE_STEPS, hint)}", check)  # fmt: skip
    notes = (cause, probe, *notes) if cause else (*notes, probe, valid)
    return OrbitPoint(
        sw.f,
        sw.x0.copy(),
        "sweep",
        sw.steady,
        0,
        sw.estimate,
        rho,
        sw.n_steps,
        "; ".join(n for n in notes if n),
        q,
        X=sw.X if sw.periods_done > 0 and not stopped else None,
    )


def on_grid(start, freqs: np.ndarray) -> None:
    """Refuse a curve ``start`` (points or a :class:`Curve`) to resume on the sequential grid
    ``freqs`` whose grid points are not on it: resumed onto another grid they were merged
    with it (0.6 beside 0.6178 Hz, the grid's 0.4856 Hz left out). Arclength points take
    their own steps."""
    pts = getattr(start, "points", start)
    pts = [pts] if isinstance(pts, OrbitPoint) else pts if isinstance(pts, list | tuple) else []
    off = [p.f for p in pts if isinstance(p, OrbitPoint) and p.method != "arclength"
           and np.min(np.abs(freqs / p.f - 1)) > 1e-9]  # fmt: skip
    if off:
        raise ValueError(f"start: its point at {off[0]:g} Hz is not on this grid; resume with "
                         "the fmin, fmax and points it was computed with")  # fmt: skip


def problem_id(problem) -> str:
    """A digest of what ``problem``'s orbits depend on: its arrays and numbers (the model's
    matrices, friction law and settings, the amplitude and load), not its name or cache. A
    curve keeps it (``info["problem"]``): one resumed by another problem is refused."""
    import hashlib

    h = hashlib.sha1()

    def feed(v) -> None:
        if isinstance(v, np.ndarray):
            h.update(f"{v.dtype}{v.shape}".encode() + np.ascontiguousarray(v).tobytes())
        elif isinstance(v, list | tuple):
            for x in v:
                feed(x)
        elif isinstance(v, int | float | str | bool | np.generic) or v is None:
            h.update(repr(v).encode())
        elif hasattr(v, "__dict__"):  # (a load: its dofs, weights and phase)
            feed(sorted((k, x) for k, x in vars(v).items() if not k.startswith("_")))
        else:
            h.update(type(v).__name__.encode())

    feed(sorted((k, v) for k, v in vars(problem).items()
                if not k.startswith("_") and k not in ("system", "name")))  # fmt: skip
    return h.hexdigest()[:16]


def resumed_points(problem, start, lo: float, hi: float, disc) -> list[OrbitPoint]:
    """The points of a curve to resume (its ``points``, or the :class:`Curve`), checked: of
    this problem's state, a curve from the band's start ``lo``, none past its end ``hi``
    [Hz], and the last one (if shooting converged on it) a periodic orbit of this problem. A
    curve of another amplitude or model was resumed without a word, its orbits mixed into
    the new curve's."""
    if start is None:
        return []
    whole_curve = isinstance(start, Curve)  # (points alone may resume a curve whose first
    # frequencies found no orbit: a checkpoint's, or the arclength's sequential rest)
    if isinstance(start, Curve):
        if start.amplitude != problem.amplitude:
            raise ValueError(f"start: a curve of amplitude {start.amplitude:g}, this problem's "
                             f"is {problem.amplitude:g}")  # fmt: skip
        own = problem_id(problem)  # (a digest of its matrices: made once)
        if start.info.get("problem", own) != own:
            raise ValueError("start: a curve of another model or settings (its problem's "
                             "matrices, friction law or load differ from this one's); resume "
                             "a curve of this problem, or start afresh")  # fmt: skip
        start = start.points
    try:
        pts = list(start)
    except TypeError:
        pts = [start]
    if not all(isinstance(p, OrbitPoint) for p in pts):
        raise TypeError("start: expected the OrbitPoints of a curve to resume (curve.points)")
    if not pts:
        return pts
    if any(p.x0.shape != problem.x_ref.shape for p in pts):
        raise ValueError(f"start: points of {pts[0].x0.size} states, this problem's state has "
                         f"{problem.x_ref.size}: a curve of another model")  # fmt: skip
    if pts[-1].f > hi * (1 + 1e-9):  # (nothing of the band asked for would be computed)
        raise ValueError(f"start: its points reach {pts[-1].f:g} Hz, past the band asked for "
                         f"({lo:g} to {hi:g} Hz)")  # fmt: skip
    if whole_curve and pts[0].f > lo * (1 + 1e-9):  # (the band below it: never computed)
        raise ValueError(f"start: its points begin at {pts[0].f:g} Hz, above the band's start "
                         f"({lo:g} Hz), which it would leave out; resume with fmin = "
                         f"{pts[0].f:g}, or start afresh")  # fmt: skip
    last = pts[-1]
    if last.converged and last.method != "sweep":
        # (with sensitivities, as shooting converged: the lagged-matrix period without them
        # may not get through a sharp law's switch, and an orbit of this problem read as inf)
        _, _, r = _evaluate(problem, last.x0, last.f, last.n_steps, disc)
        if not r <= START_RESIDUAL:
            raise ValueError(f"start: its last point (f = {last.f:g} Hz) is no periodic orbit "
                             f"of this problem (residual {r:.2g}): a curve of another "
                             "amplitude or model?")  # fmt: skip
    return pts


def _append(pts: list, pt: OrbitPoint, keep_orbits: bool, progress=None, total: int = 0) -> None:
    """Append ``pt`` and report it to ``progress(pt, count, total)``; the previous point's
    orbit is dropped unless ``keep_orbits``."""
    if pts and not keep_orbits:
        pts[-1].X = None
    pts.append(pt)
    if progress is not None:
        progress(pt, len(pts), total)


def _free(dx: np.ndarray, C: np.ndarray | None) -> np.ndarray:
    """``dx`` without its change of the held rows ``C`` (``C dx = 0`` after): a frozen
    displacement stays where the last orbit left it instead of being extrapolated."""
    if C is None:
        return dx
    return dx - np.linalg.pinv(C) @ (C @ dx)


class EmptyCurveWarning(RuntimeWarning):
    """A curve without a point: every frequency failed (its reasons in ``info["failures"]``;
    ``nsdyn sweep`` says so and ends with status 3)."""


def empty_curve_warning(curve: Curve, fmin: float, fmax: float) -> None:
    """Warn (:class:`EmptyCurveWarning`) when ``curve`` has no point but failures: the empty
    curve a library call returned said nothing (its reasons sat in ``info``)."""
    fails = curve.info.get("failures") or []
    if curve.points or not fails:
        return
    import warnings

    first = fails[0]
    hint = "; fallback=True gives each the stepped sweep's point" * ("no fallback" in str(fails))
    warnings.warn(f"no periodic orbit from {fmin:g} to {fmax:g} Hz: all {len(fails)} "
                  f"frequencies failed (f = {first['f']:.4g} Hz: {first['reason']}; each in "
                  f"curve.info['failures']){hint}", EmptyCurveWarning, stacklevel=4)  # fmt: skip


def failures(curve: Curve, options: dict) -> list[dict]:
    """Frequencies where shooting failed: each ``{"f", "reason"}`` (the stepped sweep's point
    with shooting's message, the stick-slip transition it lies near where the points give
    their ``stick_fraction``; a requested frequency with no point when the fallback is off).
    ``options``: those of :func:`nsdyn.periodic.continuation.continue_range`; every curve it
    returns holds this list as ``info["failures"]``."""
    out = []
    pts = curve.points
    for k, p in enumerate(pts):
        if p.method != "sweep":
            continue
        if p.quantities.get("uplift"):  # (a frame's bilateral steady state may hold there)
            held = "" if p.converged else "; no steady state computed"
            why = (f"uplift: a normal force reaches zero in the period (outside the bilateral "
                   f"contact model{held})")  # fmt: skip
            out.append({"f": float(p.f), "reason": why})
            continue
        why = [p.note or "shooting failed"]
        if not p.converged:
            why.insert(0, "no steady state")
        near = [pts[j].quantities.get("stick_fraction") for j in (k - 1, k, k + 1)
                if 0 <= j < len(pts)]  # fmt: skip
        near = [s for s in near if s is not None and math.isfinite(s)]
        lo = STICK_SLIP_MIN  # (below it: a slip reversal passing the law's band, no stick)
        if near and (min(near) < lo <= max(near) or any(map(stick_slip, near))):
            why.insert(0, "near a stick-slip transition")
        out.append({"f": float(p.f), "reason": "; ".join(why)})
    if options.get("continuation", "sequential") == "sequential" and not options.get(
        "fallback", True
    ):
        from nsdyn.periodic.continuation import F_MAX, F_MIN, POINTS, log_frequencies

        want = log_frequencies(options.get("fmin", F_MIN), options.get("fmax", F_MAX),
                               options.get("points", POINTS))  # fmt: skip
        have = np.array([p.f for p in pts])
        info = curve.info
        said = dict(zip(info.get("skipped_hz", []), info.get("skipped_why", []), strict=False))
        for f in want:
            if not have.size or np.min(np.abs(have / f - 1.0)) > 1e-9:
                why = next((w for s, w in said.items() if abs(s / f - 1.0) <= 1e-9), None)
                out.append({"f": float(f), "reason": "shooting did not converge (no fallback)"
                            + (f": {why}" if why else "")})  # fmt: skip
        out.sort(key=lambda d: d["f"])
    return out
