"""Continuation: pseudo-arclength through folds, the stepped-sweep fallback, the sweep command.

References are independent of the code under test: first-order harmonic balance of the Duffing
equation (folds and backbone), and shooting itself as the reference for the sweep fallback.
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from nsdyn import periodic as pr


def _harmonic_balance_folds(w0, zeta, gamma, F):
    """Fold points of x'' + 2 zeta w0 x' + w0^2 x + gamma x^3 = F cos(w t), first-order HB.

    x = a cos(w t + phi) gives (Nayfeh & Mook 1979, §4.1)
        G(u, w) = [(k + 3 gamma u / 4)^2 + d^2] u - F^2 = 0,  u = a^2, k = w0^2 - w^2,
        d = 2 zeta w0 w.
    A fold is a double root in u: dG/du = (k + 3 gamma u/4)^2 + d^2 + (3 gamma u/2)(k + 3 gamma
    u/4) = 0. With G = 0 this gives e := k + 3 gamma u / 4 = -2 F^2 / (3 gamma u^2), hence
        w^2 = w0^2 + 3 gamma u / 4 - e,   and   (2 zeta w0 w)^2 = F^2 / u - e^2,
    one equation in u whose roots are the two folds. Returns [(w, a), ...].
    """

    def e(u):
        return -2 * F**2 / (3 * gamma * u**2)

    def w2(u):
        return w0**2 + 0.75 * gamma * u - e(u)

    def g(u):
        return 4 * zeta**2 * w0**2 * w2(u) - (F**2 / u - e(u) ** 2)

    us = np.geomspace(1e-3, 10.0, 4000)
    gv = np.array([g(u) for u in us])
    roots = [brentq(g, us[i], us[i + 1]) for i in np.flatnonzero(np.diff(np.sign(gv)))]
    return [(math.sqrt(w2(u)), math.sqrt(u)) for u in roots]


def test_arclength_passes_the_duffing_folds():
    # Hardening Duffing, weakly nonlinear (gamma a^2 ~ 0.3: the third harmonic is ~1 % of the
    # fundamental, so first-order harmonic balance is accurate to ~1 %). Pseudo-arclength must
    # turn at both folds (sequential continuation cannot), the folds must show as a real
    # multiplier through +1, and the middle branch must be unstable.
    w0, zeta, gamma, F = 1.0, 0.02, 0.3, 0.045
    folds = _harmonic_balance_folds(w0, zeta, gamma, F)
    assert len(folds) == 2
    prob = pr.duffing_problem(zeta, w0, gamma, F)
    disc = pr.Discretisation(n_min=256, dt_max=1e9)
    c = pr.continue_arclength(prob, 0.9 / (2 * np.pi), 1.25 / (2 * np.pi), points=40, disc=disc)
    w = 2 * np.pi * c.column("f")
    assert w[-1] == pytest.approx(1.25, rel=1e-9)
    # each fold listed once: the turn of f(s), the multiplier through +1 beside it merged in
    both = [b for b in c.bifurcations if b["by"] == "turning point and multipliers"]
    assert len(both) == 2 and len(c.bifurcations) == 2, c.bifurcations
    turns = sorted(2 * np.pi * b["f"] for b in both)
    by_rho = sorted(2 * np.pi * b["f_multipliers"] for b in both)
    ref = sorted(wf for wf, _ in folds)
    for wt, wm, wr in zip(turns, by_rho, ref, strict=True):
        assert wt == pytest.approx(wr, rel=0.01)
        assert wm == pytest.approx(wr, rel=0.02)  # linear interpolation of rho across a fold
    # unstable points lie on the middle branch (between the folds in w)
    unstable = [p for p in c.points if p.stable is False]
    assert unstable
    for p in unstable:
        assert ref[0] * 0.99 <= 2 * np.pi * p.f <= ref[1] * 1.01
    # backbone: at the largest amplitude, w^2 = w0^2 + (3/4) gamma a^2 (within 1 %)
    amp = c.column("amp")
    k = int(np.argmax(amp))
    assert w[k] ** 2 == pytest.approx(w0**2 + 0.75 * gamma * amp[k] ** 2, rel=0.01)


def test_fallback_sweep_is_used_and_recorded_when_shooting_fails(smooth_frame):
    # Shooting is made to fail (no Newton iterations allowed): every point must come from the
    # stepped sweep, say why, and agree with the shooting solution (reference run) to the
    # steady-state tolerance.
    A = 2.0
    freqs = [1.0, 1.6]
    prob = pr.frame_problem(smooth_frame, A)
    ref = pr.continue_sequential(prob, freqs)
    assert all(p.method == "shooting" for p in ref.points)
    c = pr.continue_sequential(prob, freqs, max_iter=0)
    assert [p.method for p in c.points] == ["sweep", "sweep"]
    for p, r in zip(c.points, ref.points, strict=True):
        assert p.converged  # the steady-state test passed
        assert "no convergence in 0 Newton iterations" in p.note
        assert "steady after" in p.note
        for key in ("idr", "acc", "x_iso"):
            assert p.quantities[key] == pytest.approx(r.quantities[key], rel=1e-4)
        assert p.stable == r.stable
    rows = c.rows()
    assert rows[0]["method"] == "sweep" and "shooting failed" in rows[0]["note"]


def test_unfinished_sweep_returns_the_start_of_its_last_period(smooth_frame):
    # Definition: SweepResult.x0 is the state at the start of the period returned in X (and the
    # monodromy belongs to that period), also when the sweep stops before a steady state.
    prob = pr.frame_problem(smooth_frame, 2.0)
    sw = pr.steady_state_sweep(prob, 1.0, max_periods=3, tol=1e-14)
    assert not sw.steady and sw.periods_done == 3
    assert np.array_equal(sw.x0, sw.X[0])
    pm = pr.period_map(prob, sw.x0, 1.0, sens=True)
    assert np.allclose(pm.monodromy, sw.monodromy, rtol=1e-10, atol=1e-12)


def test_sweep_command_writes_csv_and_resumes_from_its_checkpoint(tmp_path, capsys):
    # `nsdyn sweep` on a small scene: one CSV row per point with the documented columns, a
    # checkpoint per amplitude, and a second run that resumes (computes no point again) and
    # reproduces the same rows.
    import csv
    import json
    from concurrent.futures import ThreadPoolExecutor

    from nsdyn.cli import main as nsdyn_main
    from nsdyn.models.isolated.scene import load_scene
    from nsdyn.studies import sweep

    scene = tmp_path / "portal.toml"
    scene.write_text('[scene]\nframe = "portal"\nfidelity = "cb"\nf_max = 20.0\n')
    out = tmp_path / "out"
    argv = [
        "sweep",
        str(scene),
        "--amplitudes",
        "0.5,2",
        "--fmin",
        "1",
        "--fmax",
        "4",
        "--points",
        "4",
        "--out",
        str(out),
        "--workers",
        "1",
        "--no-figures",
        "--json",
    ]
    assert nsdyn_main(argv) == 0
    first = json.loads(capsys.readouterr().out)
    rows = list(csv.DictReader((out / "sweep.csv").open()))
    assert tuple(rows[0].keys()) == sweep.CSV_COLUMNS
    assert len(rows) == 8 and {r["A"] for r in rows} == {"0.5", "2"}
    assert all(r["method"] in ("shooting", "sweep") and r["converged"] == "true" for r in rows)
    # a_floors leaves out the isolation level (level 0) of a's maximum over all levels
    assert all(0 < float(r["a_floors"]) <= float(r["a"]) for r in rows)
    for A in (0.5, 2.0):
        assert sweep.checkpoint_path(out, A).exists()
    assert nsdyn_main(argv) == 0
    second = json.loads(capsys.readouterr().out)
    # a success's JSON leads with status 0, as a failure's with its status
    assert first["status"] == second["status"] == 0
    assert [a["resumed_points"] for a in second["amplitudes"]] == [4, 4]
    assert list(csv.DictReader((out / "sweep.csv").open())) == rows
    assert [a["points"] for a in first["amplitudes"]] == [4, 4]
    # any concurrent.futures.Executor runs the amplitudes
    cfg = load_scene(scene)
    settings = sweep.SweepSettings(1.0, 4.0, 3, "sequential", True)
    with ThreadPoolExecutor(2) as ex:
        res = sweep.sweep_amplitudes(
            cfg, [0.5, 2.0], settings, tmp_path / "ex", executor=ex, quiet=True
        )
    assert [r["A"] for r in res] == [0.5, 2.0] and all(len(r["rows"]) == 3 for r in res)
    # --steps-factor 2: twice the steps per period (exactly: Discretisation.steps), so the
    # checkpoint of the default run is not reused; --tableau sdirk3 changes the tableau only
    fine = out.parent / "fine"
    argv2 = [a if a != str(out) else str(fine) for a in argv if a != "--no-figures"]
    argv2 += ["--steps-factor", "2"]
    assert nsdyn_main(argv2 + ["--tableau", "sdirk3"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["settings"]["steps_factor"] == 2.0 and report["settings"]["tableau"] == "sdirk3"
    rows2 = list(csv.DictReader((fine / "sweep.csv").open()))
    assert [int(r["n_steps"]) for r in rows2] == [2 * int(r["n_steps"]) for r in rows]
    assert (fine / "sweep.png").stat().st_size > 0 and not list(fine.glob(".*.tmp"))
    # the default sdirk2 and sdirk3 agree to the discretisation error of the coarse default
    for r, r2 in zip(rows, rows2, strict=True):
        assert float(r2["x_iso"]) == pytest.approx(float(r["x_iso"]), rel=2e-2, abs=1e-9)


def test_amplitudes_that_differ_have_checkpoints_of_their_own(tmp_path):
    # 0.5 and 0.5000001 shared '.sweep-A0.5.ckpt.json' ({A:g}), written by two workers; an
    # amplitude that {A:g} names keeps its name (earlier runs resume)
    from nsdyn.studies import plane_sweep, sweep

    for mod in (sweep, plane_sweep):
        a, b = mod.checkpoint_path(tmp_path, 0.5), mod.checkpoint_path(tmp_path, 0.5000001)
        assert a != b and a.name.endswith("A0.5.ckpt.json")
        assert mod.checkpoint_path(tmp_path, 2.0).name.endswith("A2.ckpt.json")


def _duffing():
    w0, zeta, gamma, F = 1.0, 0.02, 0.3, 0.045
    return pr.duffing_problem(zeta, w0, gamma, F), pr.Discretisation(n_min=128, dt_max=1e9)


def test_arclength_on_a_band_narrower_than_its_smallest_step_still_shoots():
    # The step in log f is capped at the band / (points - 1): over a relative band of 1e-7 the
    # cap is below the corrector's absolute floor (1e-5), so no step was tried and every point
    # came from the stepped sweep with an empty reason. The floor now scales with the cap:
    # every point is an arclength (shooting) point and the curve ends on fmax.
    prob, disc = _duffing()
    f0 = 1.1 / (2 * np.pi)
    c = pr.continue_arclength(prob, f0, f0 * (1 + 1e-7), points=5, disc=disc)
    assert c.points[-1].f == pytest.approx(f0 * (1 + 1e-7), rel=1e-15)
    assert all(p.method in ("shooting", "arclength") for p in c.points)
    assert "arclength_stop" not in c.info and c.info["skipped_hz"] == []


@pytest.mark.parametrize("continuation", ["sequential", "arclength"])
def test_without_the_fallback_a_curve_walks_the_whole_band_and_names_its_gaps(
    continuation, monkeypatch
):
    # Shooting allowed no Newton iteration (max_iter = 0, and no corrector iteration for
    # arclength) after a first converged point, and no stepped sweep. The arclength curve used
    # to stop at its first failure in silence (the sequential one skipped the points,
    # unlisted). Both must walk the band to fmax on its frequency step dp = log(fmax / fmin) /
    # (points - 1) from the last point found and list every frequency without an orbit, the
    # last fmax; arclength also says where it stopped and why (an arclength step small enough
    # for its predictor alone may still land).
    prob, disc = _duffing()
    fmin, fmax, points = 0.9 / (2 * np.pi), 1.0 / (2 * np.pi), 5
    dp = math.log(fmax / fmin) / (points - 1)
    first = pr.continue_sequential(prob, [fmin], disc=disc).points
    kw = dict(disc=disc, max_iter=0, fallback=False, start=first)
    if continuation == "sequential":
        c = pr.continue_sequential(prob, pr.log_frequencies(fmin, fmax, points), **kw)
        assert len(c.points) == 1
    else:
        monkeypatch.setattr(pr.arclength, "ARC_MAXIT", 0)  # (the corrector's module)
        c = pr.continue_arclength(prob, fmin, fmax, points=points, **kw)
        stop = c.info["arclength_stop"]
        assert stop["f_hz"] == c.points[-1].f and "no convergence" in stop["reason"]
    sk = np.array(c.info["skipped_hz"])
    assert sk.size >= 1 and sk[-1] == pytest.approx(fmax, rel=1e-12)
    # each with its reason (it was dropped: the report said "skipped" and nothing of why)
    why = c.info["skipped_why"]
    assert len(why) == sk.size and all(w.startswith("no convergence in 0 Newton") for w in why)
    steps = np.diff(np.log(np.r_[c.points[-1].f, sk]))
    np.testing.assert_allclose(steps[:-1], dp, rtol=1e-9)
    assert 0 < steps[-1] <= 1.5 * dp
    from nsdyn.cli.sweep import gap_lines

    lines = gap_lines({"skipped_hz": list(sk), "skipped_why": why,
                       "arclength_stop": c.info.get("arclength_stop")})  # fmt: skip
    assert f"{sk.size} frequencies without a periodic orbit skipped" in lines[-1]
    assert lines[-1].endswith(f"(first: {why[0]})")
    assert f"{fmax:.4g}" in lines[-1]
    assert (continuation == "arclength") == lines[0].startswith("arclength stopped at f = ")
    # a curve with skipped frequencies is not a success (it exited 0): status 3, and the line
    # counts them beside the points
    from nsdyn.cli.args import EXIT_NUMERICS
    from nsdyn.cli.sweep import _holes

    summary = {"unconverged_points": 0, "points": len(c.points), "skipped_hz": list(sk)}
    assert _holes([summary], "sweep.csv") == EXIT_NUMERICS
    assert _holes([{**summary, "skipped_hz": []}], "sweep.csv") == 0
    # a --json report of a curve with holes carries the status and the line, as every
    # failed command's JSON does (it had neither: a script read a success)
    report: dict = {}
    assert _holes([summary], "sweep.csv", report) == EXIT_NUMERICS
    assert report["status"] == EXIT_NUMERICS and report["error"].startswith(f"{sk.size} of ")
    report = {}
    assert _holes([{**summary, "skipped_hz": []}], "sweep.csv", report) == 0 and report == {}


def test_a_jump_to_the_sweep_fallback_is_no_bifurcation():
    # An arclength branch past a fold (one real multiplier > 1, unstable) whose corrector then
    # failed; the stepped sweep's point is the attracting orbit on the other branch (all
    # multipliers inside). The two are not neighbours on one branch: the change between them
    # is a jump, not a fold. Between two arclength points the same change is a fold.
    from nsdyn.periodic.bifurcation import detect_bifurcations
    from nsdyn.periodic.curve import OrbitPoint

    def pt(f, rho, method, s):
        return OrbitPoint(f, np.zeros(2), method, True, 3, 0.0, np.array(rho), 10, s=s)

    unstable, stable = [1.5, 0.2], [0.5, 0.2]
    branch = [pt(0.70, unstable, "arclength", 0.0), pt(0.69, unstable, "arclength", 1.0)]
    jump = detect_bifurcations([*branch, pt(0.78, stable, "sweep", math.nan)])
    assert jump == []
    fold = detect_bifurcations([*branch, pt(0.68, stable, "arclength", 2.0)])
    assert [(b["kind"], b["by"]) for b in fold] == [("fold", "multipliers")]


def test_sequential_jump_at_the_duffing_fold_is_listed_and_a_steep_branch_is_not():
    # Hardening Duffing swept up (sequential: it cannot turn at a fold): the curve follows the
    # upper branch to its fold and lands on the lower branch. That step is listed as a jump,
    # between the two points that bracket the upper fold of first-order harmonic balance
    # (accurate to ~1 % here, see test_arclength_passes_the_duffing_folds); no other step is.
    from nsdyn.cli.sweep import jump_lines
    from nsdyn.periodic.continuation import JUMP_RATIO, JUMP_REL

    w0, zeta, gamma, F = 1.0, 0.02, 0.3, 0.045
    upper = max(wf for wf, _ in _harmonic_balance_folds(w0, zeta, gamma, F))
    disc = pr.Discretisation(n_min=256, dt_max=1e9)
    w = np.linspace(0.9, 1.25, 36)
    c = pr.continue_sequential(pr.duffing_problem(zeta, w0, gamma, F), w / (2 * np.pi), disc=disc)
    (jump,) = c.info["jumps"]
    wa, wb = 2 * np.pi * jump["f_a"], 2 * np.pi * jump["f_b"]
    assert wb == pytest.approx(wa + 0.01, rel=1e-12)  # neighbours on the grid
    assert wa * (1 - 0.01) <= upper <= wb * (1 + 0.01)
    (line,) = jump_lines({"jumps": c.info["jumps"]})
    assert f"between f = {jump['f_a']:.4g} and {jump['f_b']:.4g} Hz" in line
    # the linear oscillator has one periodic orbit at each frequency: on a coarse grid over
    # its resonance the steps are large (the screen fires), and the check finds no second
    # orbit, so nothing is listed
    lin = pr.continue_sequential(pr.duffing_problem(zeta, w0, 0.0, F),
                                 np.array([0.8, 0.9, 0.97, 1.0, 1.03, 1.1, 1.2]) / (2 * np.pi),
                                 disc=disc)  # fmt: skip
    x = [p.x0 for p in lin.points]
    f = [p.f for p in lin.points]
    fired = 0
    for i in range(2, len(x)):
        d = np.linalg.norm(x[i] - x[i - 1])
        r = math.log(f[i] / f[i - 1]) / math.log(f[i - 1] / f[i - 2])
        pred = r * np.linalg.norm(x[i - 1] - x[i - 2])
        size = max(np.linalg.norm(x[i]), np.linalg.norm(x[i - 1]))
        fired += d > JUMP_REL * size and d > JUMP_RATIO * pred
    assert fired >= 1 and lin.info["jumps"] == []


def test_a_curve_resumes_from_an_orbit_shooting_converged_on_past_uplift():
    # The default scene at A = 1 m/s²: its 12th point of a 60-point grid (0.0509 Hz)
    # converges (residual 6e-6) with a normal force below zero (uplift flagged), where the
    # sharp arctan switch stops the period map's lagged-matrix stages. Resuming checked it
    # with that map, read the residual as inf and refused the curve as "of another amplitude
    # or model" (a checkpointed `nsdyn sweep` interrupted there ended in that traceback).
    # Checked as shooting converged on it, the curve resumes and extends.
    from nsdyn.models.isolated.scene import build_scene, load_scene

    system, _ = build_scene(load_scene(None))
    problem = pr.frame_problem(system, 1.0)
    freqs = np.geomspace(0.02, 3.0, 60)
    first = pr.continue_sequential(problem, freqs[:12])
    assert first.points[-1].converged and first.points[-1].quantities["uplift"]
    more = pr.continue_sequential(problem, freqs[:14], start=first.points)
    assert [p.f for p in more.points] == list(freqs[:14])
    assert all(a is b for a, b in zip(more.points[:12], first.points, strict=True))


def test_a_curve_resumed_onto_another_grid_is_refused():
    # a 3-point curve of 0.3-0.6 Hz resumed onto 6 points of 0.3-1 Hz was merged with it:
    # 0.6 beside 0.6178 Hz, the new grid's 0.4856 Hz never computed
    problem = pr.duffing_problem(0.05, 2 * math.pi * 0.5, 0.0, 0.2)
    first = pr.continue_range(problem, fmin=0.3, fmax=0.6, points=3)
    with pytest.raises(ValueError, match=r"^start: its point at 0.424264 Hz is not on this grid"):
        pr.continue_range(problem, fmin=0.3, fmax=1.0, points=6, start=first)
    more = pr.continue_range(problem, fmin=0.3, fmax=0.6, points=5, start=first.points[:1])
    assert len(more.points) == 5  # (a start on the grid: its first point, 0.3 Hz)


def test_a_peak_of_zero_everywhere_has_no_frequency():
    # the rigid fidelity's storeys do not deform: its IDR is 0 at every point, and the summary
    # gave the first point's frequency as where that "peak" is
    import nsdyn
    from nsdyn.models.isolated.system import build_system

    s = build_system(nsdyn.load_frame("office-11"), nsdyn.Isolation(), fidelity="rigid")
    c = pr.continue_range(pr.frame_problem(s, 0.5), fmin=0.2, fmax=0.3, points=2)
    out = c.summary()
    assert out["idr_max"] == 0.0 and out["idr_max_f_hz"] is None
    assert out["x_iso_max_m"] > 0 and out["x_iso_max_f_hz"] in (0.2, 0.3)


def test_a_point_without_a_steady_state_has_no_response_and_is_listed(smooth_frame, monkeypatch):
    # Shooting allowed no Newton iteration and the stepped sweep three periods, far too few
    # for a steady state to 1e-6: the points are no orbits. Their rows gave the last period's
    # x_iso beside converged False, and a frame's curve listed no failures (the deck's alone
    # did): every curve of continue_range now lists each such frequency with its reason
    real = pr.continuation.steady_state_sweep
    monkeypatch.setattr(pr.continuation, "steady_state_sweep",
                        lambda *a, **k: real(*a, **k, max_periods=3))  # fmt: skip
    prob = pr.frame_problem(smooth_frame, 2.0)
    c = pr.continue_range(prob, fmin=1.0, fmax=1.6, points=2, max_iter=0)
    assert [p.converged for p in c.points] == [False, False]
    assert all(p.quantities["x_iso"] > 0 for p in c.points)  # (the last period's)
    for row in c.rows():
        assert row["converged"] is False and row["stable"] == ""
        assert all(math.isnan(row[k]) for k in ("IDR", "a", "a_floors", "x_iso"))
        assert math.isnan(row["max_multiplier_modulus"])  # (no orbit: a 0.998 read as a verdict)
    fails = c.info["failures"]
    assert [d["f"] for d in fails] == pytest.approx([1.0, 1.6], rel=1e-12)
    # (after "near a stick-slip transition; ": this soft law's stick velocity, tan(0.45 pi)/50
    # s/m = 0.13 m/s, holds part of each point's last period, a stick fraction from
    # STICK_SLIP_MIN to below 1)
    from nsdyn.models.isolated.friction import STICK_SLIP_MIN

    assert all(STICK_SLIP_MIN <= p.quantities["stick_fraction"] < 1.0 for p in c.points)
    assert all(d["reason"].startswith("near a stick-slip transition; no steady state; shooting "
                                      "failed") for d in fails)  # fmt: skip
    assert c.summary()["converged"] == 0 and c.summary()["x_iso_max_m"] is None


def _den_hartog_oscillator():
    """A mass on a spring with Coulomb friction, no damper, under a ground acceleration A:
    F0 = m A = 1635 N against friction mu m g = 490 N, F_f / F0 = 0.3 < pi/4, so Den Hartog's
    steady amplitude grows without bound at f_n = sqrt(k/m) / 2 pi = 1.0066 Hz."""
    from nsdyn.models.isolated.builders import system_from_matrices
    from nsdyn.models.isolated.system import Isolation

    m, k = 1000.0, 4e4
    iso = Isolation(k_lam=k, c=0.0, mu=0.05, law="switch")
    osc = system_from_matrices([[m]], [[0.0]], [[0.0]], iso_dofs=[0], influence=[1.0],
                               isolation=iso, weight=m * iso.g, levels=[[0]])  # fmt: skip
    return osc, math.sqrt(k / m) / (2 * math.pi)


def test_arclength_stops_at_an_unbounded_resonance_and_covers_the_band_sequentially():
    # arclength followed the branch up the asymptote at f_n to x = 1e89 m, "converged,
    # stable", and never reached fmax
    osc, fn = _den_hartog_oscillator()
    c = pr.switch_response(osc, 1.635, continuation="arclength", fmin=0.7, fmax=2.0, points=6)
    stop = c.info["arclength_stop"]
    assert "unbounded resonance" in stop["reason"] and stop["f_hz"] == pytest.approx(fn, rel=1e-3)
    f = np.array([p.f for p in c.points])
    x = np.array([r["x_iso"] for r in c.rows()])
    assert f[-1] == pytest.approx(2.0, rel=1e-12) and np.all(np.isfinite(x))
    assert x.max() < 1e4  # stopped within one step past ARC_AMP_MAX = 1e3 m (steps < 10x)
    # the point past the cap is marked; every other one, below and above f_n, is Den
    # Hartog's continuous-slip amplitude X = F0/k sqrt(V^2 - (U F_f/F0)^2), V = 1/(1 - b^2),
    # U = sin(pi/b) / (b (1 + cos(pi/b))), b = f/f_n (the switch map's flow is exact: the
    # peaks read from its samples, 1e-4)
    marked = ["unbounded resonance" in p.note for p in c.points]
    assert sum(marked) == 1 and x[marked.index(True)] > 1e3
    m, k, g = 1000.0, 4e4, osc.isolation.g
    F0, Ff = m * 1.635, 0.05 * m * g
    b = f / fn
    V, U = 1 / (1 - b * b), np.sin(np.pi / b) / (b * (1 + np.cos(np.pi / b)))
    dh = F0 / k * np.sqrt(V * V - (U * Ff / F0) ** 2)
    keep = ~np.array(marked)
    assert x[keep] == pytest.approx(dh[keep], rel=1e-4)
    # resumed from its checkpoint up to the marked point: the runaway is measured against
    # the curve's first orbit, not the resumed last one (which let it climb 1e3 x further)
    j = marked.index(True) + 1
    r = pr.switch_response(osc, 1.635, continuation="arclength", fmin=0.7, fmax=2.0, points=6,
                           start=c.points[:j])  # fmt: skip
    assert r.info["arclength_stop"]["f_hz"] == pytest.approx(f[j - 1], rel=1e-12)
    assert [r["x_iso"] for r in r.rows()] == pytest.approx(list(x), rel=1e-9)
    assert sum(p.note.count("unbounded resonance") for p in r.points) == 1


def test_a_branch_turning_back_below_fmin_covers_the_rest_of_the_band_sequentially(monkeypatch):
    # a branch that folds back and runs below fmin by half the band ended there, short of
    # fmax, without an arclength_stop; it is started downwards here (as a fold turns it)
    osc, fn = _den_hartog_oscillator()
    down = lambda d: -np.eye(d + 1)[d]  # noqa: E731  (the start's tangent: down in log f)
    monkeypatch.setattr(pr.continuation, "_along_p", down)
    c = pr.switch_response(osc, 1.635, continuation="arclength", fmin=0.7, fmax=2.0, points=6)
    stop = c.info["arclength_stop"]
    assert stop["reason"].startswith("the branch turned back below fmin") and stop["f_hz"] == 0.7
    f = np.array([p.f for p in c.points])
    assert f.min() < 0.7 * (0.7 / 2.0) ** 0.5 and f[-1] == pytest.approx(2.0, rel=1e-12)
    k = int(np.argmin(f)) + 1
    rest = f[k:]
    assert np.all(np.diff(rest) > 0) and rest.size >= 5  # the band above fmin, stepped on
    # every point in the band, on the branch and on the rest, is Den Hartog's continuous-slip
    # amplitude (as above, 1e-4; below fmin the orbits stick part of the period, outside it)
    m, k_, g = 1000.0, 4e4, osc.isolation.g
    F0, Ff = m * 1.635, 0.05 * m * g
    band = f >= 0.7 * (1 - 1e-12)
    b = f[band] / fn
    V, U = 1 / (1 - b * b), np.sin(np.pi / b) / (b * (1 + np.cos(np.pi / b)))
    dh = F0 / k_ * np.sqrt(V * V - (U * Ff / F0) ** 2)
    xa = np.array([r["x_iso"] for r in c.rows()])[band]
    assert band.sum() >= 6 and xa == pytest.approx(dh, rel=1e-4)


def test_arclength_out_of_steps_covers_the_rest_of_the_band_sequentially(monkeypatch):
    # a curve that used its 20 x points steps short of fmax was reported finished (a rerun
    # then went on from its checkpoint)
    osc, _ = _den_hartog_oscillator()
    monkeypatch.setattr(pr.continuation, "ARC_MAX_STEPS_FACTOR", 1)  # 6 steps for 6 points
    c = pr.switch_response(osc, 1.635, continuation="arclength", fmin=0.7, fmax=2.0, points=6)
    assert c.info["arclength_stop"]["reason"] == "6 steps used"
    assert c.points[-1].f == pytest.approx(2.0, rel=1e-12)


def test_a_curve_without_a_point_warns_with_each_frequencys_reason():
    # every frequency failed and the fallback is off: the library returned an empty curve
    # without a word (its reasons in info alone; the command line ends with status 3)
    from nsdyn.periodic.curve import EmptyCurveWarning

    prob, disc = _duffing()
    with pytest.warns(EmptyCurveWarning, match=r"all 3 frequencies failed") as rec:
        c = pr.continue_range(prob, fmin=0.15, fmax=0.16, points=3, disc=disc, max_iter=0,
                              fallback=False)  # fmt: skip
    assert not c.points and [d["f"] for d in c.info["failures"]] == pytest.approx(
        pr.log_frequencies(0.15, 0.16, 3), rel=1e-12
    )
    assert all("no convergence in 0 Newton" in d["reason"] for d in c.info["failures"])
    assert "no convergence in 0 Newton" in str(rec[0].message)
