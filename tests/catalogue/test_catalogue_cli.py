"""Catalogue of bad command lines: every subcommand, through ``nsdyn.cli.main``.

Each row is one argument vector that must stop before any work with exit status 2 and exactly
one line on stderr naming the option (or file and field) and the expected form — an argparse
usage error or a validation error of the command, never a traceback.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from nsdyn.cli import main

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "examples" / "scenes"
SHEAR = str(SCENES / "isolated-shear-3storey.toml")
CASK = str(SCENES / "rocking-seed001-cask.toml")
CONTACT = str(SCENES / "contact-seed002-A5.toml")
CYL = str(SCENES / "cylinder-uplift.toml")

# (id, argv, regex the one stderr line must match)
CLI_ROWS = [
    # run
    ("run-pga-zero", ["run", "--pga", "0"], r"--pga.*positive"),
    ("run-pga-negative", ["run", "--pga", "-3"], r"--pga.*positive"),
    ("run-pga-text", ["run", "--pga", "3g"], r"--pga.*number"),
    ("run-pga-inf", ["run", "--pga", "inf"], r"--pga.*finite"),
    ("run-pga-nan", ["run", "--pga", "nan"], r"--pga.*positive"),
    ("run-dt-inf", ["run", "--dt", "inf"], r"--dt.*finite"),
    ("run-tend-inf", ["run", "--t-end", "inf"], r"--t-end.*finite"),
    ("run-max-steps-zero", ["run", "--max-steps", "0"], r"--max-steps.*at least 1"),
    # a fixed step too small for the step budget: refused before the run, not after minutes
    # (40 s of record at 1e-6 s: 5e6 steps per 5 s chunk against max_steps = 2e6; at 1e-7 s
    # the 4e8 steps of the whole run pass MAX_STEPS = 2e8 and are refused first)
    (
        "run-dt-too-small",
        ["run", SHEAR, "--method", "genalpha", "--dt", "1e-6"],
        r"solver\.dt.*too small.*max_steps = 2000000",
    ),
    (
        "run-dt-over-max-steps",
        ["run", SHEAR, "--method", "genalpha", "--dt", "0.001", "--max-steps", "100"],
        r"solver\.dt.*steps per.*max_steps = 100",
    ),
    ("run-max-steps-on-rocking", ["run", CASK, "--max-steps", "10"], r"--max-steps.*isolated"),
    ("run-tend-zero", ["run", "--t-end", "0"], r"--t-end.*positive"),
    ("run-fidelity", ["run", "--fidelity", "rigd"], r"--fidelity.*'rigid'"),
    ("run-friction", ["run", "--friction", "coulomb"], r"--friction.*'arctan'"),
    ("run-scene-missing", ["run", "nosuch-scene.toml"], r"nosuch-scene\.toml.*no such"),
    ("run-unknown-record", ["run", SHEAR, "--record", "nosuch-rec"], r"motion\.record.*synthetic"),
    ("run-method", ["run", SHEAR, "--method", "rk4", "--t-end", "1"], r"rk4.*radau"),
    ("run-isolated-flag-on-rocking", ["run", CASK, "--fixed-base"], r"--fixed-base.*isolated"),
    ("run-rocking-method", ["run", CASK, "--method", "radau"], r"solver\.method.*dopri5"),
    ("run-contact-method", ["run", CONTACT, "--method", "rk4"], r"solver\.method.*event"),
    ("run-cylinder-method", ["run", CYL, "--method", "rk4"], r"solver\.method.*dopri5"),
    ("run-unknown-flag", ["run", "--pgaa", "3"], r"--pgaa"),
    # sweep
    ("sweep-points-one", ["sweep", "--points", "1"], r"--points.*at least 2"),
    ("sweep-points-text", ["sweep", "--points", "many"], r"--points.*integer"),
    ("sweep-points-huge", ["sweep", "--points", "10000000"], r"--points.*at most 10000"),
    ("uplift-points-huge", ["uplift", "--points", "20000"], r"--points.*at most 10000"),
    ("sweep-fmin-zero", ["sweep", "--fmin", "0"], r"--fmin.*positive"),
    ("sweep-fmax-inf", ["sweep", "--fmax", "inf"], r"--fmax.*finite"),
    ("sweep-fmin-ge-fmax", ["sweep", "--fmin", "5", "--fmax", "1"], r"--fmax.*--fmin"),
    ("sweep-fmin-eq-fmax", ["sweep", "--fmin", "2", "--fmax", "2"], r"--fmax.*--fmin"),
    (  # --fmax not given: the error named it, as if the user had typed 10
        "sweep-fmin-above-default-fmax",
        ["sweep", "--fmin", "20"],
        r"--fmin: expected a frequency below 10 Hz \(the default top of the band",
    ),
    (
        "uplift-fmax-below-default-fmin",
        ["uplift", "--fmax", "0.001"],
        r"--fmax: expected a frequency above 0\.01 Hz \(the default bottom of the band\)",
    ),
    ("sweep-amplitudes-negative", ["sweep", "--amplitudes", "1,-2"], r"--amplitudes.*positive"),
    ("sweep-amplitudes-text", ["sweep", "--amplitudes", "1,x"], r"--amplitudes.*numbers"),
    ("sweep-steps-factor-zero", ["sweep", "--steps-factor", "0"], r"--steps-factor.*positive"),
    (
        "sweep-steps-factor-below-one",
        ["sweep", "--steps-factor", "0.01"],
        r"--steps-factor.*a factor from 1 to 1000",
    ),
    (  # the error ~0.3 %/K^2 reaches the stages' Newton tolerance 1e-9 at K = 1000; 1e9
        # steps per period ran on for minutes, deaf to Ctrl-C inside a compiled period
        "sweep-steps-factor-huge",
        ["sweep", "--steps-factor", "1e9"],
        r"--steps-factor.*a factor from 1 to 1000",
    ),
    ("sweep-tableau", ["sweep", "--tableau", "rk4"], r"--tableau.*sdirk2"),
    ("sweep-contact", ["sweep", "--contact", "sticky"], r"--contact.*'bilateral'"),
    (
        "sweep-workers-negative",
        ["sweep", SHEAR, "--workers", "-1", "--points", "2", "--amplitudes", "1", "--no-figures"],
        r"--workers.*1",
    ),
    ("sweep-scene-missing", ["sweep", "nosuch.toml"], r"nosuch\.toml.*no such"),
    ("sweep-bad-scene", ["sweep", CASK], r"scene|rocking|isolated"),
    # bench
    ("bench-name", ["bench", "acuracy"], r"'accuracy'"),
    ("bench-repeats-zero", ["bench", "accuracy", "--repeats", "0"], r"--repeats.*>= 1"),
    ("bench-records", ["bench", "accuracy", "--records", "wn,xx"], r"--records.*'kt'"),
    ("bench-records-twice", ["bench", "accuracy", "--records", "wn,wn"], r"--records.*wn twice"),
    # study
    ("study-missing", ["study", "nosuch-study.toml"], r"nosuch-study\.toml.*no such"),
    ("study-workers-zero", ["study", "x.toml", "--workers", "0"], r"--workers.*at least 1"),
    # a local Dask cluster of 1000 workers: a flood of tracebacks (4 per CPU at most)
    (
        "study-dask-local-1000",
        ["study", "x.toml", "--dask-local", "1000"],
        r"--dask-local: expected at most \d+ local processes \(4 per CPU",
    ),
    ("sweep-workers-1000", ["sweep", "--workers", "1000"], r"--workers: expected at most"),
    (
        "study-two-executors",
        ["study", "x.toml", "--workers", "2", "--dask-local", "2"],
        r"--dask-local.*--workers|not allowed",
    ),
    # modes
    ("modes-fmax-negative", ["modes", "office-11", "--fmax", "-1"], r"--fmax.*positive"),
    ("modes-klam-zero", ["modes", "office-11", "--klam", "0"], r"--klam.*positive"),
    ("modes-klam-inf", ["modes", "office-11", "--klam", "inf"], r"--klam.*finite"),
    ("modes-unknown-frame", ["modes", "office-12"], r"office-12.*office-11"),
    # spectrum
    ("spectrum-n-one", ["spectrum", CASK, "--n", "1"], r"--n.*at least 2"),
    ("spectrum-wmin-ge-wmax", ["spectrum", CASK, "--wmin", "5", "--wmax", "2"], r"--wmax.*--wmin"),
    ("spectrum-wmin-zero", ["spectrum", CASK, "--wmin", "0"], r"--wmin.*positive"),
    # a pulse 1e300 s long, a scan to 1e300 g tan α: step size underflows (exit 3, no frequency)
    (
        "spectrum-wmin-tiny",
        ["spectrum", CASK, "--wmin", "1e-300", "--wmax", "1e-299"],
        r"--wmin: expected a ratio omega_p / p from 0\.01 to 1000, got 1e-300",
    ),
    (
        "spectrum-a-max-huge",
        ["spectrum", CASK, "--a-max", "1e300"],
        r"--a-max: expected a ratio of at most 1e\+06, got 1e\+300",
    ),
    ("spectrum-workers-zero", ["spectrum", CASK, "--workers", "0"], r"--workers.*at least 1"),
    ("spectrum-not-rocking", ["spectrum", SHEAR], r"scene\.kind.*rocking"),
    ("spectrum-shape", ["spectrum", CASK, "--shape", "sinus"], r"--shape.*'sine'"),
    (  # a bisection's width below round-off stops shrinking: the search never ended
        "spectrum-rtol-below-round-off",
        ["spectrum", CASK, "--rtol", "1e-17"],
        r"--rtol.*from 2\.2e-14",
    ),
    # a folder name over 255 bytes: a traceback from the check of --out (status 1)
    ("run-out-name-too-long", ["run", "--out", "b" * 300], r"--out: cannot create .*too long"),
    ("sweep-out-deep-too-long", ["sweep", "--out", "c" * 300 + "/d"], r"--out: cannot create"),
    # no command
    ("no-command", [], r"COMMAND|required"),
    ("unknown-command", ["runn"], r"'run'"),
]


def _rc_and_err(argv, capsys) -> tuple[int, str]:
    try:
        rc = main(list(argv))
    except SystemExit as e:  # argparse usage errors
        rc = e.code
    return rc, capsys.readouterr().err


@pytest.mark.parametrize("row", [pytest.param(r, id=r[0]) for r in CLI_ROWS])
def test_bad_command_line(tmp_path, monkeypatch, capsys, row):
    rid, argv, pattern = row
    monkeypatch.chdir(tmp_path)  # nothing may be written: an output directory would land here
    rc, err = _rc_and_err(argv, capsys)
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert rc == 2, (rc, err)
    assert len(lines) == 1, err
    assert re.search(pattern, lines[0]), (pattern, lines[0])
    assert "Traceback" not in err
    assert not any(p.suffix in (".csv", ".npz", ".png") for p in tmp_path.rglob("*"))


def test_help_is_status_zero(capsys):
    with pytest.raises(SystemExit) as ei:
        main(["run", "--help"])
    assert ei.value.code == 0
    assert "--pga" in capsys.readouterr().out


# rows that need a file: (id, file text, argv with "{f}" for the file, regex of the one line)
GARBAGE_RECORD = "0,0.1\n0.01,abc\n0.02,0.3\n"
STUDY = """
[study]
name = "cat"
[base.scene]
fidelity = "rigid"
[base.motion]
t_end = 2.0
[parameters]
"isolation.mu" = [0.02, 0.05]
[records]
names = ["synthetic-wn-40s"]
"""
SHEAR_TEXT = Path(SHEAR).read_text()
FILE_ROWS = [
    # an empty scene or study file is refused (it would run the defaults)
    ("run-empty-scene", "", ["run", "{f}"], r"s\.toml: empty scene file.*\[scene\]"),
    ("run-comments-only", "# a scene\n", ["run", "{f}"], r"s\.toml: empty scene file"),
    ("sweep-empty-scene", "", ["sweep", "{f}"], r"s\.toml: empty scene file"),
    ("spectrum-empty-scene", "", ["spectrum", "{f}"], r"s\.toml: empty scene file"),
    ("study-empty", "", ["study", "{f}"], r"s\.toml: empty study file.*\[study\]"),
    # non-finite and negative motion values of frame and shear scenes
    ("run-frame-pga-inf", "[motion]\npga = inf\n", ["run", "{f}"], r"motion\.pga.*finite"),
    ("run-frame-pga-nan", "[motion]\npga = nan\n", ["run", "{f}"], r"motion\.pga.*finite"),
    (
        "run-frame-tend-negative",
        "[motion]\nt_end = -5.0\n",
        ["run", "{f}"],
        r"motion\.t_end.*positive",
    ),
    (
        "run-shear-pga-inf",
        SHEAR_TEXT.replace("pga = 3.0", "pga = inf"),
        ["run", "{f}"],
        r"motion\.pga.*finite",
    ),
    (
        "run-shear-pga-nan",
        SHEAR_TEXT.replace("pga = 3.0", "pga = nan"),
        ["run", "{f}"],
        r"motion\.pga.*finite",
    ),
    (
        "run-shear-tend-negative",
        SHEAR_TEXT.replace("pga = 3.0", "pga = 3.0\nt_end = -5.0"),
        ["run", "{f}"],
        r"motion\.t_end.*positive",
    ),
    (
        "run-max-steps-text",
        '[solver]\nmax_steps = "many"\n',
        ["run", "{f}"],
        r"solver\.max_steps.*positive integer",
    ),
    # a study's parameter values are checked on every task's scene before any task runs
    (
        "study-klam-negative",
        STUDY.replace('"isolation.mu" = [0.02, 0.05]', '"isolation.k_lam" = [5e4, -1.0]'),
        ["study", "{f}"],
        r"s\.toml: task 1 \(isolation\.k_lam = -1.*isolation\.k_lam.*non-negative",
    ),
    (
        "study-mu-nan",
        STUDY.replace("[0.02, 0.05]", "[0.02, nan]"),
        ["study", "{f}"],
        r"task 1 .*isolation\.mu.*finite",
    ),
    (
        "study-pga-inf",
        STUDY.replace('"isolation.mu" = [0.02, 0.05]', '"motion.pga" = [3.0, inf]'),
        ["study", "{f}"],
        r"task 1 .*motion\.pga.*finite",
    ),
    (
        "study-garbage-record",
        STUDY.replace('"synthetic-wn-40s"', '"garbage.csv"'),
        ["study", "{f}"],
        r"task 0 .*motion\.record.*garbage\.csv:2",
    ),
]


@pytest.mark.parametrize("row", [pytest.param(r, id=r[0]) for r in FILE_ROWS])
def test_bad_file_on_the_command_line(tmp_path, monkeypatch, capsys, row):
    rid, text, argv, pattern = row
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text(text)
    (tmp_path / "garbage.csv").write_text(GARBAGE_RECORD)
    before = sorted(tmp_path.rglob("*"))
    rc, err = _rc_and_err([a.replace("{f}", "s.toml") for a in argv], capsys)
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert rc == 2, (rc, err)
    assert len(lines) == 1, err
    assert re.search(pattern, lines[0]), (pattern, lines[0])
    assert "Traceback" not in err
    assert sorted(tmp_path.rglob("*")) == before  # nothing written, no directory made


# a run that fails (the office frame at PGA 40 m/s² lifts off its isolators: the no-uplift
# model stops with an UpliftError, status 3) leaves nothing behind: no empty output
# directory, no hidden checkpoint; files the user had in the directory stay
UPLIFT_RUN = ["run", "--fidelity", "rigid", "--pga", "40", "--t-end", "2", "--no-figures"]


def test_failed_run_leaves_nothing_behind(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    rc, err = _rc_and_err([*UPLIFT_RUN, "--out", "out/deeper"], capsys)
    assert rc == 3 and "uplift at t" in err, (rc, err)
    assert list(tmp_path.iterdir()) == []  # neither out/ nor out/deeper/ nor a checkpoint
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("kept")
    rc, err = _rc_and_err([*UPLIFT_RUN, "--out", "mine"], capsys)
    assert rc == 3
    assert sorted(p.name for p in mine.iterdir()) == ["notes.txt"]


def test_study_with_failed_tasks_names_them_and_fails(tmp_path, monkeypatch, capsys):
    # a task that fails while it runs (the office frame at PGA 40 m/s² lifts off its
    # isolators) is a row of the table, named on the console with its reason; the study's
    # status is 3, not success
    monkeypatch.chdir(tmp_path)
    study = STUDY.replace('"isolation.mu" = [0.02, 0.05]', '"motion.pga" = [3.0, 40.0]')
    (tmp_path / "s.toml").write_text(study)
    argv = ["study", "s.toml", "--out", "o", "--workers", "1", "--no-figures"]
    rc, err = _rc_and_err(argv, capsys)
    assert rc == 3, err
    named = [ln for ln in err.splitlines() if ln.startswith("failed  task")]
    assert len(named) == 1, err
    assert re.match(r"failed  task 1 \(motion\.pga = 40, record synthetic-wn-40s\): "
                    r"UpliftError: uplift at t = ", named[0]), named[0]  # fmt: skip
    assert "--retry-failed" in err and "Traceback" not in err
    rc = main([*argv, "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 3
    assert [f["index"] for f in out["run"]["failed"]] == [1]
    assert out["run"]["failed"][0]["error"].startswith("UpliftError: ")


def test_uplift_warn_is_one_clean_line(tmp_path):
    # uplift = "warn": the run goes on and says so once, without Python's warning format
    # (no source path, no code line); the summary's outcome line says it as well. A process
    # of its own: pytest would catch a raw warning before it reached stderr
    scene = tmp_path / "s.toml"
    scene.write_text(
        '[scene]\nfidelity = "rigid"\n[motion]\npga = 40.0\nt_end = 2.0\n'
        '[solver]\nuplift = "warn"\n'
    )
    argv = [sys.executable, "-m", "nsdyn.cli", "run", str(scene), "--no-figures", "--out", "o"]
    proc = subprocess.run(argv, cwd=tmp_path, capture_output=True, text=True, timeout=600)
    err = proc.stderr
    assert proc.returncode == 0, err
    lines = [ln for ln in err.splitlines() if "uplift" in ln.lower()]  # (progress lines aside)
    assert len(lines) == 1, err
    assert re.match(r"nsdyn run: warning: UPLIFT at t = \d", lines[0]), lines[0]
    assert not re.search(r"\.py:\d+", err) and "UpliftWarning" not in err
    assert proc.stdout.startswith("outcome UPLIFT at t = "), proc.stdout


N_CLI_CASES = len(CLI_ROWS) + len(FILE_ROWS) + 3
