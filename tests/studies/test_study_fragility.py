"""Lognormal fragility fit: recovery of known parameters, honest uncertainty, refusals.

Synthetic data are drawn from P = Φ((ln x − ln θ)/β) itself, so the truth is known exactly.
Tolerances come from the sample size: the maximum-likelihood estimate is asymptotically normal
with covariance I⁻¹ (I the expected Fisher information of the design at the true parameters,
computed here independently of the fit), so |estimate − truth| < 4 standard errors fails with
probability ≈ 6e-5 per check; the 95 % band's coverage over R independent replications is
binomial(R, 0.95) up to the asymptotic approximation.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy import special

from nsdyn.studies.fragility import (
    exceedance_fractions,
    fisher_information,
    fit_lognormal,
    fit_lognormal_counts,
    im_levels,
)

THETA, BETA = 2.5, 0.4  # median capacity [m/s²] and log-standard deviation


def _draw(rng, levels, runs):
    x = np.repeat(levels, runs)
    p = special.ndtr((np.log(x) - math.log(THETA)) / BETA)
    return x, rng.random(x.size) < p


def _truth_se(levels, runs):
    a, b = -math.log(THETA) / BETA, 1 / BETA
    cov = np.linalg.inv(fisher_information(a, b, levels, np.full(len(levels), runs)))
    g_lt = np.array([-1 / b, a / b**2])
    g_beta = np.array([0.0, -1 / b**2])
    return math.sqrt(g_lt @ cov @ g_lt), math.sqrt(g_beta @ cov @ g_beta)


def test_fit_recovers_parameters_within_four_standard_errors():
    rng = np.random.default_rng(20240611)
    levels = np.geomspace(0.8, 8.0, 12)  # multiple-stripe design around theta
    runs = 250  # 3000 runs: se(ln theta) ~ 0.01, se(beta) ~ 0.01
    x, y = _draw(rng, levels, runs)
    fit = fit_lognormal(x, y)
    se_lt, se_b = _truth_se(levels, runs)
    assert abs(math.log(fit.theta) - math.log(THETA)) < 4 * se_lt
    assert abs(fit.beta - BETA) < 4 * se_b
    # the fit's own standard errors agree with the information at the truth (to O(n^-1/2))
    assert fit.se_ln_theta == pytest.approx(se_lt, rel=0.15)
    assert fit.se_beta == pytest.approx(se_b, rel=0.15)
    # grouped counts (exceedance fractions) are the same likelihood: the same estimate
    lv, frac, n = exceedance_fractions(x, y, n_bins=12)
    g = fit_lognormal_counts(lv, n, np.round(frac * n))
    assert g.theta == pytest.approx(fit.theta, rel=1e-8)
    assert g.beta == pytest.approx(fit.beta, rel=1e-8)


def test_im_values_equal_to_round_off_are_one_level():
    # a scaled record's PGA column read 6.000000000000001 beside 6.0 (and 1.9999999999999998
    # beside 2.0): three levels became six, each run's outcome counted at its own, and the
    # refusal listed levels that are one
    x = np.repeat([2.0, 4.0, 6.0], 3)
    noisy = x * (1 + np.tile([0.0, 0.0, 2.2e-16], 3))  # each level's third run one ulp up
    y = np.zeros(9, dtype=bool)
    y[-1] = True  # one of the three runs at 6 exceeds: separated in IM, no finite fit
    assert np.unique(noisy).size == 6 and np.unique(im_levels(noisy)).size == 3
    with pytest.raises(ValueError, match=r"exceeding per level 2: 0/3, 4: 0/3, 6: 1/3\)"):
        fit_lognormal(noisy, y)
    assert exceedance_fractions(noisy, y)[0].size == 3  # (stripes: three, not six)


def test_estimate_is_a_maximum_of_the_likelihood():
    rng = np.random.default_rng(7)
    x, y = _draw(rng, np.geomspace(1.0, 6.0, 6), 40)
    fit = fit_lognormal(x, y)

    def ll(theta, beta):
        p = special.ndtr((np.log(x) - math.log(theta)) / beta)
        return float(np.sum(np.where(y, np.log(p), np.log1p(-p))))

    assert ll(fit.theta, fit.beta) == pytest.approx(fit.log_likelihood, rel=1e-12)
    for dt, db in [(1.01, 1), (0.99, 1), (1, 1.02), (1, 0.98)]:
        assert ll(fit.theta * dt, fit.beta * db) < fit.log_likelihood


def test_confidence_band_covers_the_true_curve_at_its_rate():
    # R replications of a small study (9 stripes x 30 runs): the 95 % band at x = theta and
    # at the 84th-percentile IM covers the true probability in ~95 % of them
    rng = np.random.default_rng(11)
    levels = np.geomspace(0.8, 8.0, 9)
    R = 400
    xs = np.array([THETA, THETA * math.exp(BETA)])
    truth = special.ndtr((np.log(xs) - math.log(THETA)) / BETA)
    hits = np.zeros(2)
    for _ in range(R):
        fit = fit_lognormal(*_draw(rng, levels, 30))
        lo, hi = fit.band(xs, 0.95)
        hits += (lo <= truth) & (truth <= hi)
    cover = hits / R
    sd = math.sqrt(0.95 * 0.05 / R)  # 0.011
    assert np.all(np.abs(cover - 0.95) < 4 * sd), cover


def test_fit_refuses_data_without_information():
    x = np.array([1.0, 2.0, 3.0, 4.0])
    with pytest.raises(ValueError, match="need some of each"):
        fit_lognormal(x, np.zeros(4, bool))
    with pytest.raises(ValueError, match=r"separate in IM \(every run at IM <= 2 survives and "
                       r"every run at IM >= 3 exceeds; exceeding per level 1: 0/1, 2: 0/1, "
                       r"3: 1/1, 4: 1/1\)"):  # fmt: skip
        fit_lognormal(x, np.array([False, False, True, True]))
    # quasi-complete: runs at one level do either, all below survive, all above exceed (it
    # was said as "every run above fails" as well): no finite maximum either
    with pytest.raises(ValueError, match=r"no run below IM = 2 exceeds and no run above it "
                       r"survives; at it, some of each; exceeding per level 1: 0/2, 2: 1/2, "
                       r"3: 2/2\)"):  # fmt: skip
        fit_lognormal(np.repeat([1.0, 2.0, 3.0], 2), np.array([0, 0, 0, 1, 1, 1], bool))
    # the same share exceeding at every level (the outcome follows another parameter, not
    # IM): the likelihood grows without bound as beta -> inf (a fit with beta 1e16 was given)
    with pytest.raises(ValueError, match=r"does not rise with IM \(beta -> inf; exceeding per "
                       r"level 1: 1/2, 2: 1/2, 3: 1/2\)"):  # fmt: skip
        fit_lognormal(np.repeat([1.0, 2.0, 3.0], 2), np.array([0, 1, 1, 0, 0, 1], bool))
    # and a share falling with IM (b creeps to 0: "Fisher scoring did not converge")
    with pytest.raises(ValueError, match=r"does not rise with IM"):
        fit_lognormal_counts([1.0, 2.0, 3.0, 4.0, 5.0], [20] * 5, [18, 14, 10, 6, 2])
    with pytest.raises(ValueError, match="positive"):
        fit_lognormal(np.array([0.0, 1.0]), np.array([False, True]))


# ---- failed runs in a study's table -----------------------------------------------------------
# A run that stopped on uplift (the frame lifted off its isolators: the no-uplift model's
# UpliftError) is past every limit of the isolated frame; dropping it, as a fit over the
# successful runs alone would, removes exceedances from the top of the IM range and biases the
# median capacity high (the curve low). The fit with them counted is the maximum-likelihood fit
# of the outcomes with those runs marked exceeded: the same likelihood, so the same estimate.
LIMIT = 0.01  # an IDR limit


def _study_table(rng, n_uplift: int, other_error: str | None = None):
    from types import SimpleNamespace

    from nsdyn.studies.table import Table

    levels = np.geomspace(0.8, 8.0, 8)
    x, y = _draw(rng, levels, 25)
    rows = [
        {"index": i, "motion.pga": float(xi), "status": "ok", "error": "",
         "idr_max": 2 * LIMIT if yi else LIMIT / 2}
        for i, (xi, yi) in enumerate(zip(x, y, strict=True))
    ]  # fmt: skip
    top = float(levels[-1])
    for k in range(n_uplift):  # the most severe runs, at the highest PGA
        rows.append({"index": len(rows), "motion.pga": top, "status": "failed",
                     "error": "UpliftError: uplift at t = 3.2 s: the normal force of contact "
                     f"{k % 2} reached zero"})  # fmt: skip
    if other_error:
        rows.append({"index": len(rows), "motion.pga": 2.0, "status": "failed",
                     "error": other_error})  # fmt: skip
    study = SimpleNamespace(
        name="frag", keep=None, parameters=[],
        analysis={"fragility": {"im": "motion.pga", "edp": "idr_max", "limits": [LIMIT]}},
    )  # fmt: skip
    exceeded = np.concatenate([y, np.ones(n_uplift, bool)])
    im = np.concatenate([x, np.full(n_uplift, top)])
    return study, Table(rows), im, exceeded


def test_uplift_failures_count_as_exceedance(tmp_path):
    from nsdyn.studies.analyses import run_analyses

    study, table, im, exceeded = _study_table(np.random.default_rng(3), n_uplift=6)
    res = run_analyses(study, table, tmp_path, figures=True)["fragility"]
    (row,) = res["fits"]
    ref = fit_lognormal(im, exceeded)
    assert row["n"] == len(table.rows) and row["n_exceed"] == int(exceeded.sum())
    assert row["theta"] == pytest.approx(ref.theta, rel=1e-12)
    assert row["beta"] == pytest.approx(ref.beta, rel=1e-12)
    assert row["n_failed_as_exceedance"] == 6
    assert "6 failed runs (uplift) counted as exceedance" in row["failures"]
    assert res["failures"] == row["failures"]
    # dropping them would have moved the median capacity up: the bias the count removes
    dropped = fit_lognormal(im[:-6], exceeded[:-6])
    assert dropped.theta > ref.theta
    csv = (tmp_path / "fragility.csv").read_text()
    assert "n_failed_as_exceedance" in csv.splitlines()[0] and "counted as exceedance" in csv
    assert (tmp_path / "fragility.png").is_file()


def test_failure_without_a_physical_outcome_refuses_the_fit(tmp_path):
    # a numerical failure says nothing about the structure: neither survived nor exceeded
    from nsdyn.studies.analyses import run_analyses

    err = "IntegrationError: Newton iteration did not converge at t = 1.2 s"
    study, table, _, _ = _study_table(np.random.default_rng(4), n_uplift=2, other_error=err)
    res = run_analyses(study, table, tmp_path, figures=True)["fragility"]
    (row,) = res["fits"]
    assert "theta" not in row
    assert re.search(r"1 runs have no outcome.*Newton.*--retry-failed", row["error"])
    assert "error" in (tmp_path / "fragility.csv").read_text().splitlines()[0]


def test_a_fit_at_one_im_level_or_without_an_edp_is_refused_naming_why(tmp_path):
    # one IM level was "the outcomes separate perfectly"; successful runs without the EDP
    # (a result they do not give) were "fix them and rerun (--retry-failed)"
    from types import SimpleNamespace

    from nsdyn.studies.analyses import run_analyses
    from nsdyn.studies.table import Table

    with pytest.raises(ValueError, match=r"every run is at one IM level \(2\); a curve needs"):
        fit_lognormal(np.full(4, 2.0), np.array([False, True, False, True]))
    rows = [{"index": i, "motion.pga": 1.0 + i, "status": "ok", "error": "",
             "toppled_at": 3.0 if i > 3 else None} for i in range(6)]  # fmt: skip
    study = SimpleNamespace(name="s", keep=None, parameters=[], analysis={
        "fragility": {"im": "motion.pga", "edp": "toppled_at", "limits": [1.0]}})  # fmt: skip
    (row,) = run_analyses(study, Table(rows), tmp_path, figures=False)["fragility"]["fits"]
    assert row["error"].startswith("fragility: 4 successful runs have no toppled_at value")
    assert "--retry-failed" not in row["error"]


def test_groups_say_their_failed_runs_and_an_all_failed_study_draws_no_empty_figure(tmp_path):
    # percentiles over the survivors alone, without a word; empty axes for every figure
    from types import SimpleNamespace

    from nsdyn.studies.analyses import run_analyses
    from nsdyn.studies.table import Table

    rows = [{"index": i, "motion.pga": 1.0 + i % 2, "status": "failed" if i in (1, 3) else "ok",
             "error": "UpliftError: x" if i in (1, 3) else "", "idr_max": 0.001 * (i + 1),
             "x_iso_max_m": 0.01 * (i + 1)} for i in range(6)]  # fmt: skip
    study = SimpleNamespace(
        name="s",
        keep=None,
        parameters=[],
        kind="isolated",
        analysis={
            "percentiles": {"quantities": ["idr_max"], "by": ["motion.pga"]},
            "design": {"variables": ["motion.pga"], "objectives": ["idr_max", "x_iso_max_m"]},
        },
    )
    res = run_analyses(study, Table(rows), tmp_path, figures=True)
    by = {r["motion.pga"]: r for r in res["percentiles"]["rows"]}
    assert (by[1.0]["n"], by[1.0]["n_failed"], by[2.0]["n"], by[2.0]["n_failed"]) == (3, 0, 1, 2)
    assert "1 of 2 group(s) leave failed runs out (2 runs" in res["percentiles"]["note"]
    assert (tmp_path / "pareto.png").is_file() and (tmp_path / "distributions.png").is_file()
    failed = [r | {"status": "failed", "error": "UpliftError: x"} for r in rows]
    res = run_analyses(study, Table(failed), tmp_path, figures=True)
    assert "no run succeeded" in res["design"]["note"]
    assert not (tmp_path / "pareto.png").exists() and not (tmp_path / "distributions.png").exists()


def test_a_design_over_a_text_variable_draws_its_figure(tmp_path):
    # the chosen design's label formatted foundation.case as a number: a traceback
    from nsdyn.studies.figures import _design_text

    assert _design_text({"foundation.case": "bonded", "isolation.mu": 0.05}) == (
        "case=bonded, mu=0.05"
    )


def test_a_fit_over_another_grid_parameter_says_it_pools_its_values(tmp_path):
    # one curve fitted over two foundations, without a word
    from types import SimpleNamespace

    from nsdyn.studies.analyses import run_analyses

    study, table, _, _ = _study_table(np.random.default_rng(5), n_uplift=0)
    for i, r in enumerate(table.rows):
        r["foundation.case"] = ("tensionless", "bonded")[i % 2]
    study.parameters = [SimpleNamespace(name=n, random=False)
                        for n in ("motion.pga", "foundation.case")]  # fmt: skip
    res = run_analyses(study, table, tmp_path, figures=False)["fragility"]
    assert "one curve over the runs of every foundation.case (2 values)" in res["note"]
    assert "motion.pga" not in res["note"]
    # an IM read from the runs that follows the grid's PGA is that axis, not a pooled one
    for r in table.rows:
        r["pga_mps2"], r["foundation.case"] = r["motion.pga"], "bonded"
    study.analysis["fragility"]["im"] = "pga_mps2"
    res = run_analyses(study, table, tmp_path, figures=False)["fragility"]
    assert "note" not in res


def test_a_true_false_fragility_is_printed_without_a_limit():
    # "fragility toppled > None": a true/false outcome has no limit to exceed
    from nsdyn.cli.study import _format

    run = {"n_tasks": 2, "n_run": 2, "n_skipped": 0, "n_failed": 0, "wall_s": 1.0,
           "workers": 1, "batch": 1, "table": "results.csv"}  # fmt: skip
    fits = [{"limit": None, "error": "fragility: 0 of 2 runs exceed the limit; need some"}]
    text = _format("s", run, {"fragility": {"edp": "toppled", "fits": fits}})
    assert "fragility toppled: fragility: 0 of 2" in text and "None" not in text


def test_runs_still_falling_at_their_end_are_said_on_an_overturning_fragility(tmp_path):
    # a block leaning past its tip-over angle at t_end is falling (gravity's moment about
    # the corner overturns it unless the ground pushes it back), yet its run reads
    # overturned = False: the fit counted it as standing, without a word
    from types import SimpleNamespace

    from nsdyn.studies.analyses import run_analyses
    from nsdyn.studies.table import Table

    over = [False, False, True, False, True, True, False, True]
    lean = [False, True, False, True, False, False, False, False]
    rows = [{"index": i, "motion.pga": 1.0 + i // 2, "status": "ok", "error": "",
             "overturned": o, "past_tip_over_at_end": p, "max_theta_over_alpha": 0.5 + i}
            for i, (o, p) in enumerate(zip(over, lean, strict=True))]  # fmt: skip
    rows.append(rows[1] | {"index": 8, "status": "failed", "error": "ValueError: x"})
    study = SimpleNamespace(name="s", keep=None, parameters=[], analysis={
        "fragility": {"im": "motion.pga", "edp": "overturned"}})  # fmt: skip
    table = Table(rows[:8])
    res = run_analyses(study, table, tmp_path, figures=False)["fragility"]
    assert re.search(
        r"^2 runs counted as not overturned end leaning past the tip-over angle "
        r"and falling \(past_tip_over_at_end\): a longer motion.t_end",
        res["note"],
    )
    study.analysis["fragility"] = {"im": "motion.pga", "edp": "max_theta_over_alpha",
                                   "limits": [1.0]}  # fmt: skip
    assert "note" not in run_analyses(study, table, tmp_path, figures=False)["fragility"]
    lone = Table([r for r in rows[:8] if r["index"] != 3] + rows[8:])  # a failed run not counted
    study.analysis["fragility"] = {"im": "motion.pga", "edp": "overturned"}
    note = run_analyses(study, lone, tmp_path, figures=False)["fragility"].get("note", "")
    assert note.startswith("1 run counted as not overturned ends leaning")


def test_counts_and_levels_that_are_not_what_a_fit_takes_are_refused_naming_them():
    # 3.5 exceedances were fitted as 3; a 2-D IM, a band at a level outside (0, 1) and a
    # negative IM gave numpy's messages or NaN
    with pytest.raises(ValueError, match=r"n_exceed: expected whole counts >= 0, got \[1.0, "
                       r"2.0, 0.5\]"):  # fmt: skip
        fit_lognormal_counts([1.0, 2.0, 3.0], [4, 4, 4], [1, 2, 0.5])
    with pytest.raises(ValueError, match=r"n_runs: expected whole counts >= 0"):
        fit_lognormal_counts([1.0, 2.0, 3.0], [np.nan, 4, 4], [0, 1, 2])
    with pytest.raises(ValueError, match=r"im: expected a 1-D array \(one value per run\), got "
                       r"shape \(2, 2\)"):  # fmt: skip
        fit_lognormal([[1.0, 2.0], [3.0, 4.0]], [[0, 1], [0, 1]])
    fit = fit_lognormal_counts([1.0, 2.0, 3.0, 4.0], [4, 4, 4, 4], [0, 1, 3, 4])
    with pytest.raises(ValueError, match=r"confidence: expected a level in \(0, 1\), got 1.5"):
        fit.band([1.0, 2.0], confidence=1.5)
    with pytest.raises(ValueError, match=r"x: expected intensity measures >= 0"):
        fit.probability([-1.0])
    with pytest.raises(ValueError, match=r"x: expected intensity measures > 0"):
        fit.band([0.0, 1.0])
    lo, hi = fit.band([np.inf, 2.0])  # P = 1 at inf, its band too (it was NaN)
    assert lo[0] == hi[0] == 1.0 and 0.0 < lo[1] < hi[1] < 1.0
    p = fit.probability([0.0, np.inf, np.nan])  # the lognormal CDF at 0 and inf, without a
    assert p[0] == 0.0 and p[1] == 1.0 and np.isnan(p[2])  # warning; NaN stays NaN
