"""Catalogue of bad command lines: every subcommand, through ``nsdyn.cli.main``.

Each row is one argument vector that must stop before any work with exit status 2 and exactly
one line on stderr naming the option (or file and field) and the expected form — an argparse
usage error or a validation error of the command, never a traceback.
"""

from __future__ import annotations

import re
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
    ("sweep-fmin-zero", ["sweep", "--fmin", "0"], r"--fmin.*positive"),
    ("sweep-fmax-inf", ["sweep", "--fmax", "inf"], r"--fmax.*finite"),
    ("sweep-fmin-ge-fmax", ["sweep", "--fmin", "5", "--fmax", "1"], r"--fmax.*--fmin"),
    ("sweep-fmin-eq-fmax", ["sweep", "--fmin", "2", "--fmax", "2"], r"--fmax.*--fmin"),
    ("sweep-amplitudes-negative", ["sweep", "--amplitudes", "1,-2"], r"--amplitudes.*positive"),
    ("sweep-amplitudes-text", ["sweep", "--amplitudes", "1,x"], r"--amplitudes.*numbers"),
    ("sweep-steps-factor-zero", ["sweep", "--steps-factor", "0"], r"--steps-factor.*positive"),
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
    # study
    ("study-missing", ["study", "nosuch-study.toml"], r"nosuch-study\.toml.*no such"),
    ("study-workers-zero", ["study", "x.toml", "--workers", "0"], r"--workers.*at least 1"),
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
    ("spectrum-workers-zero", ["spectrum", CASK, "--workers", "0"], r"--workers.*positive integer"),
    ("spectrum-not-rocking", ["spectrum", SHEAR], r"scene\.kind.*rocking"),
    ("spectrum-shape", ["spectrum", CASK, "--shape", "sinus"], r"--shape.*'sine'"),
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


N_CLI_CASES = len(CLI_ROWS)
