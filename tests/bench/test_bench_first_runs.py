"""The first-run table of ``nsdyn bench speed --families`` (its bookkeeping; the timings
themselves live in the benchmark's output and docs/dev/first-runs.md, never in tests)."""

from __future__ import annotations

import json
import math

from nsdyn.bench import first_runs, speed
from nsdyn.cli.app import build_parser


def test_every_family_and_method_has_a_case():
    # the families and isolated-frame methods whose first run the table measures
    got = {(fam, what.split(" ")[0]) for fam, what, _ in first_runs.cases()}
    want = {("isolated", m) for m in ("radau", "event", "genalpha", "genalpha-lowrank", "sweep")}
    want |= {("rocking", "block"), ("contact", "event"), ("cylinder", "tensionless")}
    want |= {("deck", "fps"), ("study", "isolated,"), ("building3d", "cb")}
    assert got == want
    for _, _, args in first_runs.cases():  # every case writes JSON into its own directory
        assert "--json" in args and "{out}" in args


def test_reported_times_from_the_json_summaries():
    assert first_runs._reported(json.dumps({"compile_s": 2.5, "wall_s": 0.25})) == (2.5, 0.25)
    c, r = first_runs._reported("notice\n" + json.dumps({"run": {"wall_s": 3.0}}))
    assert math.isnan(c) and r == 3.0  # a study: its whole wall time
    assert all(math.isnan(v) for v in first_runs._reported("Traceback ..."))


def test_fresh_process_with_its_own_cache(tmp_path):
    # a process of `nsdyn` with NUMBA_CACHE_DIR in the given directory: its row
    row = first_runs.run_case(["bench", "--help"], str(tmp_path / "numba"), str(tmp_path))
    assert row["status"] == "ok" and row["process_s"] > 0.0 and not row["notice"]
    assert row["cpu_s"] > 0.0 or math.isnan(row["cpu_s"])  # a process ran (NaN off POSIX)
    bad = first_runs.run_case(["no-such-command"], str(tmp_path / "numba"), str(tmp_path))
    assert bad["status"].startswith("exit ") and bad["message"]


def test_markdown_names_the_misses():
    row = {"family": "contact", "what": "event", "first_status": "ok", "cached_status": "ok",
           "first_process_s": 13.7, "first_compile_s": 12.0, "first_run_s": 0.5,
           "first_notice": True, "cached_process_s": 1.5, "cached_compile_s": 0.2,
           "cached_start_s": 1.0, "first_load_1min": 2.0,
           "over_s": 13.7 - first_runs.FIRST_RUN_TARGET_S}  # fmt: skip
    met = dict(row, first_process_s=4.0, over_s=-6.0, family="rocking")
    md = first_runs.first_runs_markdown([row, met], (1.0, 2.0, 3.0))
    assert "| contact | event | 13.7 | 12.0 | 0.50 | - | yes | 1.5 | 1.0 | 0.20 | 3.7 |" in md
    assert "| rocking | event | 4.0 |" in md and "| met |" in md
    # a case that ended with an error says so after its name, inside the table's 12 columns
    # (a 13th cell after the row's last bar broke the table)
    swept = dict(met, family="isolated", what="sweep", first_status="exit 3",
                 cached_status="exit 3")  # fmt: skip
    (line,) = [x for x in first_runs.first_runs_markdown([swept]).splitlines()
               if x.startswith("| isolated")]  # fmt: skip
    assert line.startswith("| isolated | sweep (exit 3 / exit 3) | 4.0 |") and line.endswith("|")
    assert line.count("|") == 13


def test_speed_takes_the_families_option():
    args = build_parser().parse_args(["bench", "speed", "--quick", "--families"])
    assert args.families and "families" in speed.OPTIONS
    res = {"table": [], "meta": {}, "files": {}, "first_runs": [{"family": "x"}]}
    assert speed.summarise(res)["first_runs"] == [{"family": "x"}]


def test_repeats_give_medians_and_keep_a_failure():
    # a case's rows over repeats: the median of each number (NaN where a repeat reports none
    # is skipped), a notice only when every repeat printed one, a failed repeat's status kept
    reps = [{"status": "ok", "process_s": 10.0, "compile_s": math.nan, "notice": True},
            {"status": "ok", "process_s": 14.0, "compile_s": 3.0, "notice": True},
            {"status": "exit 1", "process_s": 30.0, "compile_s": 5.0, "notice": False}]  # fmt: skip
    row = first_runs._median_row(reps)
    assert row["process_s"] == 14.0 and row["compile_s"] == 4.0
    assert row["notice"] is False and row["status"] == "exit 1"
    assert first_runs._median_row(reps[:2])["status"] == "ok"
