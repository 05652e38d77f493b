"""Catalogue of interruptions: SIGINT / SIGTERM to a real ``nsdyn`` process mid-run.

Contract (the atomic-file and checkpoint rules of nsdyn.atomic and the commands):
* the process stops with status 130 and one line on stderr, no traceback;
* every file in the output directory is complete (written through atomic_open: temporary
  file + rename), and no temporary file is left behind;
* the rerun resumes from the checkpoint: the points already on file are kept as they were and
  only the rest is computed (none lost, none computed twice), giving the same result as an
  uninterrupted run;
* a checkpoint written for other settings is refused with a message, never mixed in.

The study command's own kill test (SIGKILL / SIGTERM of a pool) lives in
``tests/studies/test_study_execute.py``; this module adds SIGINT and the changed-study case.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from nsdyn.cli import main

ROOT = Path(__file__).resolve().parents[2]
SHEAR = str(ROOT / "examples" / "scenes" / "isolated-shear-3storey.toml")
DEADLINE_S = 120.0  # wall limit for a spawned command to reach the point where it is killed
EXIT_INTERRUPTED = 130


def _spawn(argv: list[str], cwd: Path) -> subprocess.Popen:
    # Ctrl-C's disposition as a terminal's foreground command has it: a shell runs background
    # jobs with SIGINT ignored, the ignore is inherited, and Python then installs no
    # KeyboardInterrupt handler (the command rightly keeps running, so the test would check
    # nothing: a CI job started in the background did exactly that)
    code = (
        "import signal, sys; signal.signal(signal.SIGINT, signal.default_int_handler); "
        f"from nsdyn.cli import main; sys.exit(main({argv!r}))"
    )
    return subprocess.Popen(
        [sys.executable, "-c", code],
        cwd=cwd,
        start_new_session=True,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )


def _interrupt_when(proc: subprocess.Popen, ready, sig) -> tuple[int, str]:
    """Send ``sig`` once ``ready()`` holds; (exit status, stderr)."""
    t0 = time.monotonic()
    while not ready():
        if proc.poll() is not None:  # finished (or failed) before the interruption point
            return proc.returncode, proc.stderr.read().decode()
        assert time.monotonic() - t0 < DEADLINE_S, "never reached the interruption point"
        time.sleep(0.005)
    os.kill(proc.pid, sig)
    try:
        rc = proc.wait(timeout=60)
    finally:
        try:
            os.killpg(proc.pid, signal.SIGKILL)  # leftovers of its process group, if any
        except ProcessLookupError:
            pass
    return rc, proc.stderr.read().decode()


def _no_temporaries(out: Path) -> None:
    left = [p for p in out.rglob("*") if p.name.endswith(".tmp")]
    assert not left, left


def _assert_interrupted(rc: int, err: str) -> None:
    assert rc == EXIT_INTERRUPTED, (rc, err)
    assert "Traceback" not in err, err
    assert "interrupted" in err.splitlines()[-1], err


# ----------------------------------------------------------------------------- nsdyn run
# a fixed-step run at a fine step: ~2 s of work after the first checkpoint (chunks of 5 s of
# record), so the signal always lands mid-run; the default adaptive run finishes its remaining
# chunks in well under 0.1 s, which a loaded machine could miss
T_END = 20.0
RUN_ARGS = ["run", "--t-end", f"{T_END:g}", "--no-figures", "--json", "--pga", "3",
            "--method", "genalpha", "--dt", "1e-4"]  # fmt: skip


def _run_checkpoint(out: Path) -> Path:
    return out / ".run-checkpoint.npz"


def _checkpoint_ready(out: Path):
    ck = _run_checkpoint(out)
    return lambda: ck.exists()


@pytest.fixture(scope="module")
def reference_run(tmp_path_factory):
    """The uninterrupted run: its histories are what every resumed run must reproduce."""
    out = tmp_path_factory.mktemp("ref")
    assert main([*RUN_ARGS, "--out", str(out)]) == 0
    return dict(np.load(out / "run-histories.npz"))


def _solve_spy(monkeypatch) -> list[tuple[float, float]]:
    """Record the (t_first, t_last) of every chunk the integrator is asked for."""
    from nsdyn.solve import integrate

    calls: list[tuple[float, float]] = []
    real = integrate.solve

    def spy(P, x0, t_eval, *a, **kw):
        calls.append((float(t_eval[0]), float(t_eval[-1])))
        return real(P, x0, t_eval, *a, **kw)

    monkeypatch.setattr(integrate, "solve", spy)
    return calls


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_run_interrupted_resumes_without_loss_or_repeat(tmp_path, monkeypatch, capsys, sig,
                                                        reference_run):  # fmt: skip
    out = tmp_path / "out"
    proc = _spawn([*RUN_ARGS, "--out", str(out)], tmp_path)
    rc, err = _interrupt_when(proc, _checkpoint_ready(out), sig)
    assert rc != 0, "the run ended before the signal arrived: lengthen RUN_ARGS' run"
    _assert_interrupted(rc, err)
    # with --json the outcome on stdout too (docs/reference/cli.md: every outcome's JSON)
    said = json.loads(proc.stdout.read().decode())
    assert said["status"] == EXIT_INTERRUPTED and said["error"].startswith("interrupted")
    _no_temporaries(out)
    assert not (out / "run-histories.npz").exists()  # no result before the run is complete
    ck = np.load(_run_checkpoint(out))  # a complete, readable checkpoint
    t_done = float(ck["t"][-1])
    assert 0.0 < t_done < T_END
    calls = _solve_spy(monkeypatch)
    assert main([*RUN_ARGS, "--out", str(out), "--resume"]) == 0
    rep = json.loads(capsys.readouterr().out)
    assert rep["resumed_from_s"] == t_done  # the summary says from where it went on
    assert calls[0][0] == pytest.approx(t_done)  # resumed where the checkpoint ends ...
    for (_, b), (a, _) in zip(calls[:-1], calls[1:], strict=True):
        assert a == b  # ... each chunk starts where the last ended: nothing twice, no gap
    assert calls[-1][1] == pytest.approx(T_END)
    got = np.load(out / "run-histories.npz")
    np.testing.assert_array_equal(got["t"], reference_run["t"])  # every output point, once
    # a fixed-step run starts every chunk from the state the last one ended at, whether that
    # state comes from memory or from the checkpoint file: the resumed run is the same run, bit
    # for bit (an adaptive method would agree only to its tolerance, its step control restarted)
    np.testing.assert_array_equal(got["x"], reference_run["x"])
    assert not _run_checkpoint(out).exists()
    _no_temporaries(out)


def test_a_signal_inside_llvms_callback_is_sent_again_after_it(monkeypatch):
    # numba compiling: LLVM's object-cache callback into Python (llvmlite, called from C)
    # printed the KeyboardInterrupt raised in it as an ignored exception with its traceback,
    # and the run went on to its end (status 0, 1 run in 3); now the signal is sent again
    import threading

    from nsdyn.cli import app

    sent = threading.Event()
    monkeypatch.setattr(os, "kill", lambda pid, sig: sent.set() if sig == signal.SIGINT else None)
    callback = compile("def notify(handler):\n    return handler(2, sys._getframe())\n",
                       "/site-packages/llvmlite/binding/executionengine.py", "exec")  # fmt: skip
    space = {"sys": sys}
    exec(callback, space)
    app._SIGNALLED[0] = False
    old = signal.signal(signal.SIGINT, app._on_signal)  # (the command's handler, installed)
    try:
        assert space["notify"](app._on_signal) is None  # not raised in the callback
        assert sent.wait(5.0) and not app._SIGNALLED[0]  # sent again, still the first signal
        with pytest.raises(KeyboardInterrupt):  # outside the callback: the interrupt
            app._on_signal(signal.SIGINT, sys._getframe())
    finally:
        signal.signal(signal.SIGINT, old)
        app._SIGNALLED[0] = False
    # a command that ended before the moment passed (its handler gone): nothing is sent
    sent.clear()
    assert space["notify"](app._on_signal) is None and not sent.wait(0.5)


def test_a_second_signal_during_the_stop_is_ignored(tmp_path, reference_run):
    # `timeout` signals the process and then its group: a second signal raised inside the
    # first one's stop gave a traceback and lost the checkpoint folder (1 run in 5). Here a
    # SIGTERM and a SIGINT back to back: both pending, the second handled inside the stop
    from nsdyn.cli import app

    app._SIGNALLED[0] = False
    with pytest.raises(KeyboardInterrupt):
        app._on_signal(signal.SIGTERM, None)
    assert app._on_signal(signal.SIGINT, None) is None  # the second: no second interrupt
    app._SIGNALLED[0] = False
    out = tmp_path / "out"
    proc = _spawn([*RUN_ARGS, "--out", str(out)], tmp_path)
    ready = _checkpoint_ready(out)
    t0 = time.monotonic()
    while not ready() and proc.poll() is None:
        assert time.monotonic() - t0 < DEADLINE_S, "never reached the interruption point"
        time.sleep(0.005)
    assert proc.poll() is None, "the run ended before the signals arrived"
    os.kill(proc.pid, signal.SIGTERM)
    os.kill(proc.pid, signal.SIGINT)
    rc = proc.wait(timeout=60)
    _assert_interrupted(rc, proc.stderr.read().decode())
    assert _run_checkpoint(out).is_file()  # the run can go on
    _no_temporaries(out)


def test_run_checkpoint_from_other_settings_is_refused(tmp_path, capsys, reference_run):
    out = tmp_path / "out"
    proc = _spawn([*RUN_ARGS, "--out", str(out)], tmp_path)
    rc, err = _interrupt_when(proc, _checkpoint_ready(out), signal.SIGINT)
    assert rc != 0, "the run ended before the signal arrived: lengthen RUN_ARGS' run"
    other = [a if a != "3" else "4" for a in RUN_ARGS]
    rc = main([*other, "--out", str(out), "--resume"])
    err = capsys.readouterr().err
    assert rc == 2 and "checkpoint" in err  # refused with a message naming what differs
    assert "differing: motion.pga)" in err


# ----------------------------------------------------------------------------- nsdyn sweep
# long enough to be caught mid-way on a quiet machine: a checkpoint is written at most every
# CHECKPOINT_EVERY_S = 2 s, and 300 points of this model took ~1.9 s (6 s for these 1 500)
SWEEP_POINTS = 1500
SWEEP_ARGS = ["sweep", SHEAR, "--amplitudes", "1", "--points", str(SWEEP_POINTS), "--fmin",
              "0.02", "--fmax", "5", "--workers", "1", "--no-figures", "--json"]  # fmt: skip


def _sweep_ckpt(out: Path) -> Path:
    return out / ".sweep-A1.ckpt.json"


@pytest.mark.slow  # ~10-30 s: the sweep must run long enough to be caught mid-way
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_sweep_interrupted_resumes_without_loss_or_repeat(tmp_path, capsys, sig):
    out = tmp_path / "out"
    proc = _spawn([*SWEEP_ARGS, "--out", str(out)], tmp_path)
    ck = _sweep_ckpt(out)
    rc, err = _interrupt_when(proc, ck.exists, sig)
    assert rc != 0, "the sweep ended before the signal arrived"
    _assert_interrupted(rc, err)
    _no_temporaries(out)
    assert not (out / "sweep.csv").exists()
    saved = json.loads(ck.read_text())  # a complete JSON document
    assert not saved["complete"]
    n_saved = len(saved["points"])
    assert 0 < n_saved < SWEEP_POINTS
    assert main([*SWEEP_ARGS, "--out", str(out)]) == 0
    rep = json.loads(capsys.readouterr().out)
    final = json.loads(ck.read_text())
    assert final["complete"] and len(final["points"]) == SWEEP_POINTS  # none lost
    fs = [p["f"] for p in final["points"]]
    assert len(set(fs)) == len(fs)  # none twice
    assert final["points"][:n_saved] == saved["points"]  # the saved points kept as they were
    with open(out / "sweep.csv") as fh:
        assert sum(1 for _ in fh) == 1 + SWEEP_POINTS
    assert rep["amplitudes"][0]["points"] == SWEEP_POINTS
    _no_temporaries(out)


def test_sweep_checkpoint_from_other_settings_is_refused(tmp_path, capsys):
    out = tmp_path / "out"
    ck = _sweep_ckpt(out)
    out.mkdir()
    from nsdyn.models.isolated.scene import load_scene
    from nsdyn.studies.sweep import SweepSettings, _identity

    ident = _identity(load_scene(SHEAR), 1.0, SweepSettings(0.02, 5.0, 7))
    ck.write_text(json.dumps({"identity": ident, "complete": False, "points": []}))
    rc = main([*SWEEP_ARGS, "--points", "3", "--out", str(out)])
    err = capsys.readouterr().err
    assert rc == 2 and "checkpoint" in err and "differing: settings.points)" in err


def test_sweep_checkpoint_from_other_settings_is_not_mixed(tmp_path, capsys):
    # a checkpoint of 7 points is not merged into a 3-point sweep of the same scene
    out = tmp_path / "out"
    base = [a for a in SWEEP_ARGS if a != str(SWEEP_POINTS)]
    i = base.index("--points")
    del base[i]
    assert main([*base, "--points", "7", "--out", str(out)]) == 0
    assert len(json.loads(_sweep_ckpt(out).read_text())["points"]) == 7
    assert main([*base, "--points", "3", "--out", str(out)]) == 0
    capsys.readouterr()
    pts = json.loads(_sweep_ckpt(out).read_text())["points"]
    assert len(pts) == 3
    assert [p["f"] for p in pts] == pytest.approx(np.geomspace(0.02, 5.0, 3))


# ----------------------------------------------------------------------------- nsdyn bench
def _complete_csv(p: Path) -> bool:
    text = p.read_text()
    rows = [r.split(",") for r in text.splitlines() if r.strip()]
    return text.endswith("\n") and len(rows) >= 1 and len({len(r) for r in rows}) == 1


@pytest.mark.slow  # ~15 s each
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_bench_interrupted_leaves_only_complete_files(tmp_path, sig):
    # the benchmark has no checkpoint (a rerun measures afresh): the contract is that an
    # interrupt leaves no temporary and no half-written table
    out = tmp_path / "out"
    proc = _spawn(["bench", "contact", "--quick", "--out", str(out), "--json"], tmp_path)
    rc, err = _interrupt_when(proc, lambda: (out / "contact-wp.csv").exists(), sig)
    assert rc != 0, "the benchmark ended before the signal arrived"
    _assert_interrupted(rc, err)
    _no_temporaries(out if out.exists() else tmp_path)
    for p in out.rglob("*.csv") if out.exists() else []:
        assert _complete_csv(p), p


# ----------------------------------------------------------------------------- nsdyn study
STUDY = """
[study]
name = "{name}"
batch = 1
keep = ["x_iso_max_m", "n_steps"]

[base.scene]
fidelity = "rigid"

[base.motion]
pga = 3.0
t_end = 6.0

[parameters]
"isolation.mu" = {mu}

[records]
simulated = {{ n = 8, seed = 3, duration = 6.0 }}
"""


def _study(tmp_path: Path, mu: str) -> Path:
    p = tmp_path / "study.toml"
    p.write_text(textwrap.dedent(STUDY.format(name="cat", mu=mu)))
    return p


def test_study_sigint_resumes_with_every_task_once(tmp_path):
    from nsdyn.studies.execute import run_study
    from nsdyn.studies.study import load_study
    from nsdyn.studies.table import PARTS, RESULTS, read_csv
    from nsdyn.studies.tasks import expand

    sp = _study(tmp_path, "[0.02, 0.04, 0.06]")
    study = load_study(sp)
    out = tmp_path / "out"

    def n_rows() -> int:
        parts = out / PARTS
        return sum(len(read_csv(f)) for f in parts.glob("part-*.csv")) if parts.is_dir() else 0

    proc = _spawn(["study", str(sp), "--out", str(out), "--workers", "1", "--json",
                   "--no-figures"], tmp_path)  # fmt: skip
    rc, err = _interrupt_when(proc, lambda: n_rows() >= 2, signal.SIGINT)
    assert rc != 0, "the study ended before the signal arrived"
    _assert_interrupted(rc, err)
    _no_temporaries(out)
    before = n_rows()
    res = run_study(study, out, workers=1)
    keys = [r["key"] for r in res.table.rows]
    assert sorted(keys) == sorted(t.key for t in expand(study))
    assert len(set(keys)) == study.n_tasks == len(keys)
    assert res.n_skipped == before and res.n_run == study.n_tasks - before
    assert [r["key"] for r in read_csv(out / RESULTS)] == keys
    _no_temporaries(out)


def test_changed_study_reuses_only_identical_tasks(tmp_path):
    # results of another study in the same directory are never mixed in: a task is reused only
    # when its input hash (scene, parameters, record) is identical
    from nsdyn.studies.execute import run_study
    from nsdyn.studies.study import load_study

    out = tmp_path / "out"
    a = run_study(load_study(_study(tmp_path, "[0.02, 0.04]")), out, workers=1)
    b = run_study(load_study(_study(tmp_path, "[0.04, 0.06]")), out, workers=1)
    assert a.n_run == 16 and b.n_skipped == 8 and b.n_run == 8
    assert len(b.table.rows) == 16
    mus = sorted({r["isolation.mu"] for r in b.table.rows})
    assert mus == [0.04, 0.06]


# ----------------------------------------------------------------------------- SIGKILL
# A parent killed outright runs no handler: its pool workers must end by themselves (they ask
# the kernel for a signal at the parent's death and watch the parent's pid), not compute on or
# idle holding their memory. The deadline is a bound for "they end", not a timing check.
WORKERS_GONE_S = 30.0


def _proc_stat(pid: int) -> tuple[str, int] | None:
    """(state, parent pid) of a live process, None if it is gone."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    fields = text[text.rindex(")") + 2 :].split()
    return fields[0], int(fields[1])


def _workers(pid: int) -> set[int]:
    """The pool workers of ``pid``: its children running its own command line (forked)."""
    try:
        cmd = Path(f"/proc/{pid}/cmdline").read_bytes()
    except OSError:
        return set()
    out = set()
    for d in Path("/proc").iterdir():
        if d.name.isdigit() and (st := _proc_stat(int(d.name))) and st[1] == pid:
            try:
                if (d / "cmdline").read_bytes() == cmd:
                    out.add(int(d.name))
            except OSError:
                pass
    return out


def _running(pid: int) -> bool:
    st = _proc_stat(pid)
    return st is not None and st[0] not in ("Z", "X")  # a zombie has ended


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("command", ["study", "sweep"])
def test_pool_workers_end_with_a_killed_parent(tmp_path, command):
    out = tmp_path / "out"
    if command == "study":
        argv = ["study", str(_study(tmp_path, "[0.02, 0.03, 0.04, 0.05, 0.06]")), "--out",
                str(out), "--workers", "2", "--json", "--no-figures"]  # fmt: skip
    else:
        argv = [*SWEEP_ARGS, "--out", str(out)]
        argv[argv.index("--amplitudes") + 1] = "1,2"
        argv[argv.index("--workers") + 1] = "2"
    proc = _spawn(argv, tmp_path)
    try:
        t0 = time.monotonic()
        while len(workers := _workers(proc.pid)) < 2:
            assert proc.poll() is None, "the command ended before its pool started"
            assert time.monotonic() - t0 < DEADLINE_S, "no pool workers appeared"
            time.sleep(0.01)
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=60)
        t0 = time.monotonic()
        while (alive := {w for w in workers if _running(w)}) and (
            time.monotonic() - t0 < WORKERS_GONE_S
        ):
            time.sleep(0.05)
        assert not alive, f"pool workers {sorted(alive)} outlived their killed parent"
    finally:
        try:
            os.killpg(proc.pid, signal.SIGKILL)  # whatever is left of the process group
        except ProcessLookupError:
            pass


N_INTERRUPTIONS = 2 + 2 + 2 + 1 + 2  # run, sweep, bench (SIGINT + SIGTERM each), study
# SIGINT, study and sweep SIGKILL
