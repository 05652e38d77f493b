"""The fidelity ladder: error of each model rung against the richest one, against its cost.

``nsdyn bench fidelity`` (``fidelity.csv``, ``fidelity.png``): the ladder rigid,
CB-5/10/15/20/50/100, full (435 dofs) under a low-frequency record (the white noise low-passed
at 2 Hz) and a broadband one (the Kanai-Tajimi record, f95 = 19 Hz), all with radau at the
transient defaults (what ``nsdyn run`` uses); relative errors of the peaks against the full
model (:mod:`nsdyn.bench.common`)::

    err_xpeak = |max|x_iso| / max|x_iso^ref| - 1|,  err_idr, err_acc likewise

against wall time. The integration floor is one rung at the ladder's tolerances against the
same rung at FLOOR_RTOL. Why the full model needs the transient tolerances:
:func:`acceleration_roundoff` (the float64 round-off of its accelerations) and
:func:`newton_noise_floor` (that round-off against a Newton iteration's threshold).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from nsdyn.bench import common

__all__ = [
    "acceleration_roundoff",
    "fidelity_bench",
    "fidelity_figure",
    "fidelity_motions",
    "fidelity_tolerances",
    "low_frequency_motion",
    "newton_noise_floor",
    "report",
    "run_bench",
    "rung_name",
    "summarise",
]

# the command-line options run_bench takes (nsdyn.cli.bench passes only these)
OPTIONS = ("repeats", "figures", "quiet")
FIGURES = ("fidelity.png",)  # the figures it draws (removed under --no-figures)

LOWPASS_HZ = 2.0  # Hz, corner of the low-frequency record (4th-order Butterworth, zero phase)
# The ladder, cheapest first; the last rung that runs is the reference. Every rung runs with
# radau at the transient defaults (nsdyn.solve.transient: rtol 1e-4, atol (1e-8 m, 1e-6 m/s)), what
# `nsdyn run` uses, so costs compare like with like and are the costs a user pays. The full
# 435-dof model needs them: its acceleration carries a float64 round-off of ~1e-6 m/s^2 (the
# base-diaphragm stiffness 1e11 against the tiny rotational inertia of the base nodes;
# max |M^-1 K*| ~ 6e13), which at rtol 1e-6 / atol 1e-8 exceeds what the Newton iterations of
# genalpha (dt 1e-3: it failed at t = 1.5 s) and radau (h ~ 1e-3 s) can resolve, and at rtol
# 1e-6 radau needs ~80 s per simulated second. See acceleration_roundoff() and
# newton_noise_floor().
LADDER = [
    ("rigid", None),
    ("cb", 5.0),
    ("cb", 10.0),
    ("cb", 15.0),
    ("cb", 20.0),
    ("cb", 50.0),
    ("cb", 100.0),
    ("full", None),
]
QUICK_LADDER = [("rigid", None), ("cb", 5.0), ("cb", 10.0)]
FIDELITY_METHOD = "radau"  # one integrator for every rung
FIDELITY_RTOL = None  # None: the transient defaults (DEFAULT_RTOL, default_atol("radau"))
FLOOR_RTOL = 1e-8  # the floor check: FLOOR_RUNG at the ladder's tolerances vs at FLOOR_RTOL
FLOOR_RUNG = ("cb", 20.0)
QUICK_FLOOR_RUNG = ("cb", 5.0)

# columns of the CSV tables, in order
_FID_FIELDS = (
    "record model n_dof reference status err_xpeak err_idr err_acc err_x wall_s n_timed "
    "n_steps x_iso_max_m idr_max floor_acc_max_mps2 energy_closure method setting value "
    "window_s repeats compile_s quick rtol atol_m atol_mps message"
).split()


def rung_name(fidelity: str, f_max: float | None) -> str:
    """The name of a ladder rung: "rigid", "cb-5", ..., "full"."""
    return f"cb-{f_max:g}" if fidelity == "cb" else fidelity


def low_frequency_motion(
    window_s: float = common.WINDOW_S, pga: float = common.PGA, f_c: float = LOWPASS_HZ
):
    """The synthetic white noise low-passed at ``f_c`` (4th-order Butterworth, zero phase,
    both components), then scaled to ``pga``: a record with no energy above ~2 f_c."""
    from scipy import signal

    m = common.bench_motion("wn", window_s, pga)
    sos = signal.butter(4, f_c, fs=1.0 / m.dt, output="sos")
    a_ver = None if m.a_ver is None else signal.sosfiltfilt(sos, m.a_ver)
    lp = m._replace(
        a_hor=signal.sosfiltfilt(sos, m.a_hor),
        a_ver=a_ver,
        name=f"{m.name} low-passed {f_c:g} Hz",
        meta_update={"lowpass_hz": f_c},
    )
    return lp.scaled_to_pga(pga)


def fidelity_motions(window_s: float) -> dict:
    """The two records of the fidelity chart: low-frequency and broadband."""
    return {
        "low-frequency": low_frequency_motion(window_s),
        "broadband": common.bench_motion("kt", window_s),
    }


def acceleration_roundoff(system, motion, t: float, x: np.ndarray) -> np.ndarray:
    """|qdd_float64 - qdd_exact| at (t, x): the kernel's accelerations against the same
    formulas (:func:`nsdyn.bench.baseline.numpy_equations`) evaluated in long double from the
    same float64 data (the kernel's own matrices M^-1 K*, M^-1 C*, ...).

    This is the noise floor below which no Newton iteration on the accelerations can
    converge. Arctan law with live normal forces and two contacts (every rung of the ladder).
    """
    from nsdyn.models.isolated import _kernel as ks
    from nsdyn.models.isolated.params import KernelParams

    L = np.longdouble
    n = system.n
    P = system.params(motion)
    qdd = system.evaluate(float(t), x, P=P)["qdd"]
    kp = KernelParams(P)
    mats = {k: v.astype(L) for k, v in kp.matrices().items()}
    MiK, MiC, Gam = mats["MiK"], mats["MiC"], mats["Gamma"]
    R, MiRt, D, MiDt = mats["R"], mats["MiRt"], mats["D"], mats["MiDt"]
    eps, alpha, beta, g = L(kp.eps), L(kp.alpha), L(kp.beta), L(kp.g)
    ah, av = ks.ground_accel(float(t), P)  # the kernel's own interpolation of the record
    q, qd = np.asarray(x[:n]).astype(L), np.asarray(x[n:]).astype(L)
    a0 = -(Gam @ np.array([L(ah), L(av) + g])) - MiK @ q - MiC @ qd
    s = (L(2) / L(np.pi)) * np.arctan(eps * (D @ qd))
    B = MiRt - MiDt * (kp.mu.astype(L) * s)
    G = R @ B
    r = -(R @ a0 + L(2) * alpha * beta * (R @ qd) + alpha**2 * (R @ q))
    det = G[0, 0] * G[1, 1] - G[0, 1] * G[1, 0]
    lam = np.array([G[1, 1] * r[0] - G[0, 1] * r[1], G[0, 0] * r[1] - G[1, 0] * r[0]]) / det
    return np.abs(qdd - (a0 + B @ lam).astype(float))


def newton_noise_floor(
    x: np.ndarray, da: np.ndarray, rtol: float, atol, h: float = 1e-3, method: str = "radau"
) -> float:
    """An acceleration error ``da`` as a multiple of a Newton iteration's convergence
    threshold: above 1, Newton cannot certify convergence whatever the step's Jacobian.

    ``radau``: one simplified-Newton update of the real stage moves the velocities by about
    ``(h / mu) da`` and the positions by ``(h / mu)^2 da`` (``mu`` the real eigenvalue of the
    inverse Radau IIA matrix), scaled by ``atol + rtol |x|``, RMS-averaged; threshold
    ``max(10 eps / rtol, min(0.03, rtol^0.5))`` (:mod:`nsdyn.solve._kradau`).
    ``genalpha`` (rho_inf 0.8, fixed step ``h``): the update is ``gamma h da`` and
    ``beta h^2 da``, same scaling; threshold NEWTON_TOL of :mod:`nsdyn.solve._kgenalpha`.
    """
    n = da.size
    aq, av = common.atol_pair(atol)
    if method == "radau":
        from nsdyn.solve._kradau import MU_REAL

        gv = h / MU_REAL
        gq = gv * gv
        tol = max(10.0 * np.finfo(float).eps / rtol, min(0.03, rtol**0.5))
    elif method == "genalpha":
        from nsdyn.solve._kgenalpha import FAMILY_GENALPHA, NEWTON_TOL, parameters

        _, _, beta, gamma = parameters(FAMILY_GENALPHA, 0.8)
        gq, gv, tol = beta * h * h, gamma * h, NEWTON_TOL
    else:
        raise ValueError(f"method: expected 'radau' or 'genalpha', got {method!r}")
    sq = gq * da / (aq + rtol * np.abs(x[:n]))
    sv = gv * da / (av + rtol * np.abs(x[n:]))
    return float(np.sqrt((np.sum(sq**2) + np.sum(sv**2)) / (2 * n))) / tol


def fidelity_tolerances() -> tuple[float, object]:
    """(rtol, atol) of every rung: FIDELITY_RTOL with atol ATOL_FACTOR * rtol, or the
    transient defaults when FIDELITY_RTOL is None."""
    from nsdyn.solve.transient import DEFAULT_RTOL, default_atol

    if FIDELITY_RTOL is None:
        return DEFAULT_RTOL, default_atol(FIDELITY_METHOD)
    return FIDELITY_RTOL, FIDELITY_RTOL * common.ATOL_FACTOR


def fidelity_bench(
    *,
    quick: bool = False,
    ladder: list | None = None,
    repeats: int | None = None,
    out: Path | None = common.DEFAULT_OUT,
    figures: bool = True,
    quiet: bool = False,
) -> dict:
    """Error of each rung of the model ladder against the reference rung, against its cost.

    Every rung runs with the same integrator and tolerances (:func:`fidelity_tolerances`), so
    costs compare like with like; the time-integration error is bounded by FLOOR_RUNG at
    FLOOR_RTOL (row ``<rung> rtol 1e-08``, drawn as the floor). The reference of a record is
    the last rung of the ladder that ran through it (the full model unless it failed; its row
    then records why).
    """
    from nsdyn.models.isolated.system import build_system

    repeats = common.timed_repeats(quick, repeats)
    window = common.QUICK_WINDOW_S if quick else common.WINDOW_S
    ladder = (QUICK_LADDER if quick else LADDER) if ladder is None else ladder
    floor_rung = rung_name(*(QUICK_FLOOR_RUNG if quick else FLOOR_RUNG))
    rtol, atol = fidelity_tolerances()
    compile_s = common.warmup([FIDELITY_METHOD])
    frame = common.bench_frame()
    iso = common.bench_isolation("arctan")
    systems = {}
    for fid, fm in ladder:
        systems[rung_name(fid, fm)] = build_system(frame, iso, fidelity=fid, f_max=fm)
    if floor_rung not in systems:
        fid, fm = QUICK_FLOOR_RUNG if quick else FLOOR_RUNG
        systems_floor = build_system(frame, iso, fidelity=fid, f_max=fm)
    else:
        systems_floor = systems[floor_rung]
    rows = []
    for rec, motion in fidelity_motions(window).items():
        runs = {}
        for name, system in systems.items():
            common.log(f"[fidelity] {rec}: {name} (n = {system.n})", quiet)
            runs[name] = common.run_nsdyn(
                system,
                motion,
                FIDELITY_METHOD,
                label=name,
                rtol=rtol,
                atol=atol,
                repeats=repeats,
            )
        ok = [name for name in systems if runs[name].ok]
        ref_name = ok[-1] if ok else ""
        ref = runs[ref_name] if ok else None
        for name, system in systems.items():
            br = runs[name]
            e = common.run_errors(br, ref) if ref is not None else common.nan_errors()
            rows.append(
                common.bench_row(
                    br, record=rec, model=name, n_dof=system.n, reference=ref_name, **e
                )
            )
        common.log(f"[fidelity] {rec}: {floor_rung} at rtol {FLOOR_RTOL:g} (floor check)", quiet)
        tight = common.run_nsdyn(
            systems_floor, motion, FIDELITY_METHOD, label=floor_rung, rtol=FLOOR_RTOL, repeats=1
        )
        loose = runs.get(floor_rung) or common.run_nsdyn(
            systems_floor, motion, FIDELITY_METHOD, rtol=rtol, atol=atol, repeats=1
        )
        e = common.run_errors(loose, tight) if tight.ok else common.nan_errors()
        rows.append(
            common.bench_row(
                tight,
                record=rec,
                model=f"{floor_rung} rtol {FLOOR_RTOL:g}",
                n_dof=systems_floor.n,
                reference=f"floor: {floor_rung} at rtol {rtol:g} vs {FLOOR_RTOL:g}",
                **e,
            )
        )
    meta = {
        "window_s": window,
        "repeats": repeats,
        "compile_s": compile_s,
        "quick": quick,
        "rtol": rtol,
        "atol": list(common.atol_pair(atol)),  # [m, m/s]
    }
    floor_atol = common.atol_pair(common.ATOL_FACTOR * FLOOR_RTOL)  # (run_nsdyn's default)
    for r in rows:  # each row's own tolerances: the floor row's are FLOOR_RTOL's
        floor = r["model"].endswith(f" rtol {FLOOR_RTOL:g}")
        r.update({k: v for k, v in meta.items() if k not in ("rtol", "atol")})
        r["rtol"] = FLOOR_RTOL if floor else rtol
        r["atol_m"], r["atol_mps"] = floor_atol if floor else meta["atol"]
    files = {}
    if out is not None:
        chart = ("figure", "fidelity.png", lambda: fidelity_figure(rows)) if figures else None
        files = common.write_outputs(out, {"csv": ("fidelity.csv", rows, _FID_FIELDS)}, chart)
    return {"rows": rows, "files": files, "meta": meta}


run_bench = common.entry_point(fidelity_bench)


def fidelity_figure(rows):
    """The model-ladder chart of :func:`fidelity_bench`'s rows (drawn by :mod:`nsdyn.plot`)."""
    from nsdyn import plot

    return plot.fidelity_figure(rows, method=FIDELITY_METHOD)


def summarise(res: dict) -> dict:
    """The JSON summary of :func:`fidelity_bench`'s result: the rows without messages."""
    return {
        "rows": [{k: v for k, v in r.items() if k != "message"} for r in res["rows"]],
        "files": res["files"],
    }


def report(res: dict) -> str:
    """The human table of :func:`fidelity_bench`'s result (files excluded)."""
    refs = sorted({r["reference"] for r in res["rows"] if not r["reference"].startswith("floor")})
    lines = [
        f"{'record':14s} {'model':15s} {'dofs':>5s} {'x_iso':>9s} {'IDR':>9s} {'acc':>9s} "
        f"{'wall [s]':>9s}  status  (errors vs {' / '.join(refs) or '-'})"
    ]
    floor = ""
    for r in res["rows"]:
        # the rigid deck has no storey drift: no IDR to compare (its "error" would be 1)
        idr = f"{'—':>9s}" if r["model"] == "rigid" else f"{r['err_idr']:9.2e}"
        lines.append(
            f"{r['record']:14s} {r['model']:15s} {r['n_dof']:5d} {r['err_xpeak']:9.2e} "
            f"{idr} {r['err_acc']:9.2e} {r['wall_s']:9.3f}  {r['status']}"
        )
        if r["reference"].startswith("floor"):
            floor = r["reference"].removeprefix("floor: ")
    if floor:
        lines.append(f"(an 'rtol' row: the time-integration floor, {floor})")
    return "\n".join(lines)
