"""Studies of two-component records on bidirectional isolators: the incident angle as a study
parameter, the record pairs, the outputs per run, the incidence analysis, bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest

from nsdyn.cli import main
from nsdyn.ground import GroundMotion, GroundMotion3, write_motion
from nsdyn.models.scenefile import SceneError
from nsdyn.studies import load_study, run_study

EPS = np.finfo(float).eps
DT = 0.01


def _pair(tmp_path, name: str, seed: int, n: int = 500, n_y: int | None = None):
    """Two single-component record files (x, y) of a smooth random motion."""
    rng = np.random.default_rng(seed)
    t = DT * np.arange(n)
    env = np.sin(np.pi * t / t[-1]) ** 2
    files = []
    for comp, amp, f in (("x", 3.0, 0.7), ("y", 2.0, 1.1)):
        m = n if comp == "x" or n_y is None else n_y
        a = amp * env[:m] * np.sin(2 * np.pi * f * t[:m] + rng.uniform(0, 2 * np.pi))
        p = tmp_path / f"{name}_{comp}.csv"
        write_motion(GroundMotion(0.0, DT, a, None, f"{name}{comp}"), p)
        files.append(p.name)
    return files


SDOF = """
[scene]
kind = "deck"
[mass]
m = 1.0e5
[bearing]
type = "fps"
radius = 1.5
mu = 0.05
[motion]
kind = "record3"
record = "synthetic-wn-40s"
[solver]
law = "switch"
rtol = {rtol}
atol = 1e-10
"""


def _study(tmp_path, angles, extra: str = "", scene: str = "sdof.toml") -> object:
    a = _pair(tmp_path, "A", 1)
    b = _pair(tmp_path, "B", 2)
    text = f"""
[study]
name = "angles"
scene = "{scene}"
[parameters]
"motion.rotate" = {json.dumps(angles)}
[records]
pairs = [{{ name = "A", x = "{a[0]}", y = "{a[1]}" }}, {{ name = "B", x = "{b[0]}", y = "{b[1]}" }}]
{extra}
"""
    p = tmp_path / "study.toml"
    p.write_text(text)
    return p


# ---- rotation ----------------------------------------------------------------------------------
def test_rotation_exact_at_0_and_90_and_norm_preserving():
    # a_x' = a_x cos θ − a_y sin θ, a_y' = a_x sin θ + a_y cos θ: the identity at 0, the
    # quarter turn (a_x, a_y) -> (−a_y, a_x) at 90° exactly (cos, sin exactly 0, 1), and at any
    # angle the horizontal resultant kept to the round-off of two products and a sum (≤ 4 eps
    # of the resultant)
    rng = np.random.default_rng(0)
    ax, ay, az = rng.standard_normal((3, 200))
    m = GroundMotion3(0.0, DT, ax, ay, az)
    r0, r90 = m.rotated(0.0), m.rotated(90.0)
    assert np.array_equal(r0.ax, ax) and np.array_equal(r0.ay, ay)
    assert np.array_equal(r90.ax, -ay) and np.array_equal(r90.ay, ax)
    assert np.array_equal(r90.az, az)
    for th in (15.0, 37.0, 135.0):
        r = m.rotated(th)
        assert np.all(np.abs(np.hypot(r.ax, r.ay) - np.hypot(ax, ay)) <= 4 * EPS * np.hypot(ax, ay))


def test_study_tasks_turn_the_pair_by_the_angle(tmp_path):
    # the motion a task runs is the pair read together and turned by its motion.rotate
    from nsdyn.ground import read_motion3
    from nsdyn.models.isolated.deck_scene import build_motion
    from nsdyn.studies.tasks import expand

    (tmp_path / "sdof.toml").write_text(SDOF.format(rtol=1e-6))
    study = load_study(_study(tmp_path, [0.0, 90.0]))
    ref = read_motion3(tmp_path / "A_x.csv", tmp_path / "A_y.csv")
    for task in expand(study):
        if task.record_name != "A":
            continue
        exc, _ = build_motion(task.cfg, "task")
        if task.params["motion.rotate"] == 0.0:
            assert np.array_equal(exc.ax, ref.ax) and np.array_equal(exc.ay, ref.ay)
        else:
            assert np.array_equal(exc.ax, -ref.ay) and np.array_equal(exc.ay, ref.ax)


# ---- end to end ----------------------------------------------------------------------------------
def test_circular_isolator_same_peak_for_every_angle(tmp_path):
    # A mass on one friction pendulum is isotropic in the plane: the response to the record
    # turned by θ is the response turned by θ, so |u|(t) and its peak do not depend on θ.
    # The numerical solutions differ only through the integrator's error control (a
    # componentwise norm, not invariant under rotation): each carries a global error of at
    # most about steps × rtol relative (local errors summed, the friction system dissipative),
    # so two runs agree to 2 × steps × rtol.
    rtol = 1e-8
    (tmp_path / "sdof.toml").write_text(SDOF.format(rtol=rtol))
    study = load_study(_study(tmp_path, [0.0, 45.0, 90.0], "[analysis.incidence]"))
    res = run_study(study, tmp_path / "out", workers=1)
    rows = res.table.rows
    assert len(rows) == 6 and all(r["status"] == "ok" for r in rows), rows
    for rec in ("A", "B"):
        rs = [r for r in rows if r["record"] == rec]
        peaks = np.array([r["peak_resultant_displacement_m"] for r in rs])
        steps = max(r["n_steps"] for r in rs)
        assert peaks.min() > 0.01  # the mass slides
        assert np.ptp(peaks) <= 2 * steps * rtol * peaks.max(), (peaks, steps)
        # base shear of a single mass: its isolator force, m |ü_abs| — isotropic as well
        shear = np.array([r["peak_base_shear_N"] for r in rs])
        assert np.ptp(shear) <= 2 * steps * rtol * shear.max(), shear
        assert [r["incident_angle_deg"] for r in rs] == [0.0, 45.0, 90.0]


def test_cli_two_records_three_angles_fixed_rung(tmp_path):
    # the fixed rung is linear: the record turned by 180° (a_x, a_y -> −a_x, −a_y exactly) gives
    # the negated response, every peak the same to the last bit (negation is exact and the
    # modal recurrence is linear); 90° gives other peaks (the portal's x and y differ)
    (tmp_path / "fixed.toml").write_text("""
[scene]
kind = "building3d"
[structure]
frame3d = "portal-3d"
fidelity = "fixed"
n_modes = 6
[motion]
kind = "record3"
record = "synthetic-wn-40s"
""")
    p = _study(tmp_path, [0.0, 90.0, 180.0], "[analysis.incidence]", scene="fixed.toml")
    out = tmp_path / "o"
    assert main(["study", str(p), "--out", str(out), "--workers", "1", "--json"]) == 0
    from nsdyn.studies.table import read_csv

    rows = read_csv(out / "results.csv")
    assert len(rows) == 6 and all(r["status"] == "ok" for r in rows)
    for rec in ("A", "B"):
        by = {r["motion.rotate"]: r for r in rows if r["record"] == rec}
        for q in ("peak_base_shear_N", "peak_corner_drift", "peak_torsional_moment_Nm"):
            assert by[0.0][q] == by[180.0][q], q
        assert by[0.0]["peak_drift_cm_x"] != by[90.0]["peak_drift_cm_x"]
    assert (out / "incidence.csv").is_file() and (out / "incidence.png").is_file()
    inc = read_csv(out / "incidence.csv")
    for r in inc:
        vals = [x["peak_base_shear_N"] for x in rows if x["record"] == r["record"]]
        assert r["peak_base_shear_N_max"] == max(vals)


# ---- bad input -----------------------------------------------------------------------------------
def _one_line_error(fn, *parts):
    with pytest.raises(SceneError) as e:
        fn()
    msg = str(e.value)
    assert "\n" not in msg, msg
    for part in parts:
        assert part in msg, (part, msg)
    return msg


def test_angle_not_a_number(tmp_path):
    (tmp_path / "sdof.toml").write_text(SDOF.format(rtol=1e-6))
    p = _study(tmp_path, ["north", "east"])
    _one_line_error(lambda: load_study(p), str(p), "parameters.motion.rotate.values", "'north'",
                    "degrees")  # fmt: skip


def test_pair_of_different_lengths(tmp_path):
    (tmp_path / "sdof.toml").write_text(SDOF.format(rtol=1e-6))
    x, y = _pair(tmp_path, "C", 3, n=400, n_y=380)
    p = tmp_path / "bad.toml"
    p.write_text(f"""
[study]
scene = "sdof.toml"
[records]
pairs = [{{ x = "{x}", y = "{y}" }}]
""")
    _one_line_error(lambda: load_study(p), str(p), "records.pairs[0].y", "npts = 380", "400")
    assert main(["study", str(p), "--out", str(tmp_path / "o")]) == 2


def test_pairs_need_a_two_component_scene(tmp_path):
    x, y = _pair(tmp_path, "D", 4)
    p = tmp_path / "iso.toml"
    p.write_text(f"""
[records]
pairs = [{{ x = "{x}", y = "{y}" }}]
""")
    _one_line_error(lambda: load_study(p), str(p), "records.pairs", "deck, building3d or cylinder")


def test_simulated_pairs_run_with_independent_components(tmp_path):
    # a simulated record of a two-component study: a_x is the planar studies' record of the
    # seed, a_y the same generator on an independent stream (not a copy of a_x); the study runs
    from nsdyn.studies.scenes import simulated_motion
    from nsdyn.studies.scenes3c import simulated_pair

    spec = {"generator": "modulated_white_noise", "duration": 4.0, "dt": 0.01, "seed": 11}
    pair = simulated_pair(spec)
    assert np.array_equal(pair.ax, simulated_motion(spec).a_hor)
    r = np.corrcoef(pair.ax, pair.ay)[0, 1]
    # independent streams: the sample correlation of n_ord independent ordinates (one per
    # 0.05 s, seed 000's spacing, interpolated between) has a spread of about 1/sqrt(n_ord)
    assert abs(r) < 5 / np.sqrt(spec["duration"] / 0.05)
    (tmp_path / "sdof.toml").write_text(SDOF.format(rtol=1e-6))
    p = tmp_path / "sim.toml"
    p.write_text("""
[study]
scene = "sdof.toml"
[parameters]
"motion.rotate" = [0.0, 30.0]
[records]
simulated = { n = 1, seed = 5, duration = 4.0 }
""")
    res = run_study(load_study(p), tmp_path / "out", workers=1)
    assert [r["status"] for r in res.table.rows] == ["ok", "ok"], res.table.rows


def test_incidence_analysis_needs_the_angle_as_a_grid_parameter(tmp_path):
    (tmp_path / "sdof.toml").write_text(SDOF.format(rtol=1e-6))
    p = _study(tmp_path, [0.0, 90.0], '[analysis.incidence]\nangle = "motion.phase_y_deg"')
    _one_line_error(lambda: load_study(p), str(p), "analysis.incidence.angle",
                    "motion.phase_y_deg", "not a grid parameter")  # fmt: skip
    p = _study(tmp_path, [0.0, 90.0], '[analysis.incidence]\nquantities = "peak_base_shear_N"')
    _one_line_error(lambda: load_study(p), str(p), "analysis.incidence.quantities", "list")


def test_a_deck_run_ended_by_uplift_is_a_failed_row(tmp_path):
    # a mass on one pendulum under a vertical ramp a_z = −2g·t/(1 s), no horizontal motion:
    # N = m (g + a_z) reaches zero at t = 0.5 s (the sphere's own vertical motion is nil at
    # rest), where the no-uplift model ends. A study row of such a run is a failure naming the
    # uplift (as a frame's UpliftError is), not an "ok" row with the peaks of 0.5 s of record
    from nsdyn.ground import write_motion3

    g = 9.80665
    t = DT * np.arange(101)
    rec = write_motion3(GroundMotion3(0.0, DT, 0 * t, 0 * t, -2 * g * t, "ramp"),
                        tmp_path / "ramp.csv")  # fmt: skip
    (tmp_path / "sdof.toml").write_text(SDOF.format(rtol=1e-8).replace(
        'record = "synthetic-wn-40s"', f'record = "{rec}"'))  # fmt: skip
    study = tmp_path / "study.toml"
    study.write_text('[study]\nname = "up"\nscene = "sdof.toml"\n[parameters]\n'
                     '"bearing.mu" = [0.05]\n')  # fmt: skip
    res = run_study(load_study(study), tmp_path / "out", workers=1)
    (row,) = res.table.rows
    assert row["status"] == "failed" and row["error"].startswith("UpliftError: UPLIFT isolator")
    t_up = float(row["error"].split(" at t = ")[1].split(" s")[0])
    assert abs(t_up - 0.5) <= 2 * DT  # the output grid's resolution around the crossing
    # the motion's columns stay (a fragility on the resultant PGA counts it as an exceedance)
    assert row["pga_resultant_mps2"] == 0.0 and row["incident_angle_deg"] == 0.0
    assert "peak_resultant_displacement_m" not in row  # no peaks of a run cut short


def test_an_isotropic_incidence_names_no_worst_angle():
    # a peak equal at every angle (an isotropic bearing) has no worst angle: the report said
    # "max 0.06271 at 30 deg (min 0.06271)", naming an arbitrary one
    from nsdyn.cli.study import _format

    run = {"n_tasks": 2, "n_run": 2, "n_skipped": 0, "n_failed": 0, "wall_s": 1.0,
           "workers": 1, "batch": 1, "table": "results.csv"}  # fmt: skip
    q = "peak_resultant_displacement_m"

    def row(top, low):
        return {"record": "A", "n_angles": 4, "n_failed": 0, f"{q}_max": top,
                f"{q}_angle_of_max_deg": 30.0, f"{q}_min": low}  # fmt: skip

    for top, low, says in ((0.0627123, 0.0627119, f"{q} 0.06271 at every angle"),
                           (0.0627, 0.0500, f"{q} max 0.0627 at 30 deg (min 0.05)")):  # fmt: skip
        an = {"incidence": {"quantities": [q], "by": ["record"], "rows": [row(top, low)]}}
        assert says in _format("s", run, an)


def test_failed_angles_are_counted_and_never_hidden_behind_a_tie():
    # Record A: 0° and 90° equal, 45° failed (an uplift: the worst angle, without a value);
    # record B: every angle failed. A's line must not claim "at every angle", and B is a row
    from nsdyn.cli.study import _format
    from nsdyn.studies.incidence import incidence_rows
    from nsdyn.studies.table import Table

    q = "peak_base_shear_N"
    rows = [{"record": "A", "motion.rotate": 0.0, "status": "ok", q: 5.0},
            {"record": "A", "motion.rotate": 45.0, "status": "failed", "error": "UpliftError"},
            {"record": "A", "motion.rotate": 90.0, "status": "ok", q: 5.0},
            {"record": "B", "motion.rotate": 0.0, "status": "failed", "error": "UpliftError"},
            ]  # fmt: skip
    out = incidence_rows(Table(rows), "motion.rotate", [q], ["record"])
    a, b = sorted(out, key=lambda r: r["record"])
    assert (a["n_angles"], a["n_failed"], a[f"{q}_max"]) == (2, 1, 5.0)
    assert (b["n_angles"], b["n_failed"]) == (0, 1) and np.isnan(b[f"{q}_max"])
    run = {"n_tasks": 4, "n_run": 4, "n_skipped": 0, "n_failed": 3, "wall_s": 1.0,
           "workers": 1, "batch": 1, "table": "results.csv"}  # fmt: skip
    b[f"{q}_max"] = None  # (the analyses' JSON-safe NaN)
    text = _format("s", run, {"incidence": {"quantities": [q], "by": ["record"], "rows": [a, b]}})
    assert f"incidence A: {q} max 5 at 0 deg (min 5) (1 failed angle left out)" in text
    assert "at every angle (to" not in text and "incidence B: every angle failed (1)" in text


def test_a_quantity_at_round_off_at_every_angle_has_no_worst_angle(tmp_path):
    # a symmetric deck's torsion is 1e-19 rad at every angle: its "directionality" of 1.80
    # at a worst angle of 90 deg was the ratio of two round-offs
    from nsdyn.studies.incidence import ROUND_OFF, incidence_rows, run
    from nsdyn.studies.study import Study
    from nsdyn.studies.table import Table

    t, s = "peak_torsion_rad", "peak_base_shear_N"
    rows = [{"record": "A", "motion.rotate": a, "status": "ok", t: v, s: 5.0 + a / 90}
            for a, v in ((0.0, 1e-19), (90.0, 1.8e-19))]  # fmt: skip
    (out,) = incidence_rows(Table(rows), "motion.rotate", [t, s], ["record"])
    assert np.isnan(out[f"{t}_directionality"]) and np.isnan(out[f"{t}_angle_of_max_deg"])
    assert out[f"{s}_directionality"] == 6.0 / 5.0 and out[f"{s}_angle_of_max_deg"] == 90.0
    study = Study(name="s", source="s.toml", kind="deck", base={}, parameters=[], records=[])
    res = run(study, Table(rows), {"quantities": [t, s]}, tmp_path, figures=False)
    assert res["note"] == (
        f"'{t}': at most {ROUND_OFF:g} at every angle (round-off of a "
        "response the model does not have): no worst angle, no directionality"
    )
    # the printout names the first quantity that has a worst angle (it raised a TypeError on
    # the round-off one's None after every run)
    from nsdyn.cli.study import _format
    from nsdyn.studies.analyses import _finite

    run_ = {"n_tasks": 2, "n_run": 2, "n_skipped": 0, "n_failed": 0, "wall_s": 1.0,
            "workers": 1, "batch": 1, "table": "results.csv"}  # fmt: skip
    inc = _finite({"quantities": [t, s], "by": ["record"], "rows": [out]})
    assert f"incidence A: {s} max 6 at 90 deg (min 5)" in _format("s", run_, {"incidence": inc})


def test_a_tie_reports_its_smallest_angle_and_a_real_difference_its_own():
    # the fixed rung's peaks at 0 and 180 deg differ in the last bits on the office (a vertical
    # component's round-off beside the negated horizontal response): the worst angle was 180
    # for one record and 0 for another, by round-off alone
    from nsdyn.studies.incidence import TIE_REL, incidence_figure, incidence_rows
    from nsdyn.studies.table import Table

    q, v = "peak_base_shear_N", 6553289.227321559
    for up, angle in ((1.0 + 16 * np.finfo(float).eps, 0.0), (1.0 + 100 * TIE_REL, 180.0)):
        rows = [{"record": "A", "motion.rotate": a, "status": "ok", q: w}
                for a, w in ((0.0, v), (90.0, 0.5 * v), (180.0, v * up))]  # fmt: skip
        (out,) = incidence_rows(Table(rows), "motion.rotate", [q], ["record"])
        assert out[f"{q}_angle_of_max_deg"] == angle and out[f"{q}_max"] == v * up
        # the figure's star marks that angle, not the last bit's largest
        fig = incidence_figure(Table(rows), "motion.rotate", [q], ["record"])
        (star,) = [ln for ln in fig.axes[0].lines if ln.get_marker() == "*"]
        assert star.get_xdata()[0] == angle
    # peaks of round-off alone (a symmetric deck's torsion): no angle in the table, no star
    rows = [{"record": "A", "motion.rotate": a, "status": "ok", q: 1e-19 * (1 + a)}
            for a in (0.0, 90.0)]  # fmt: skip
    (out,) = incidence_rows(Table(rows), "motion.rotate", [q], ["record"])
    fig = incidence_figure(Table(rows), "motion.rotate", [q], ["record"])
    assert np.isnan(out[f"{q}_angle_of_max_deg"])
    assert not [ln for ln in fig.axes[0].lines if ln.get_marker() == "*"]
