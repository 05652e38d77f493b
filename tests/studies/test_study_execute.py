"""Running studies: resume after a kill, failures recorded, the same table on any executor,
and the study's scene runner equal to ``nsdyn run``'s.

Sources: the resume contract of nsdyn.studies.execute (every task once, finished tasks not
rerun); determinism of the integrators (the same inputs give the same floats in any process);
``build_system`` as the definition of the isolated model the cached runner must reproduce.
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

from nsdyn.studies import execute
from nsdyn.studies.analyses import run_analyses
from nsdyn.studies.execute import run_study
from nsdyn.studies.scenes import _isolated_system, run_scene_summary
from nsdyn.studies.study import load_study
from nsdyn.studies.table import PARTS, RESULTS, TIMING_COLUMNS, Table, read_csv
from nsdyn.studies.tasks import expand

SMALL = """
[study]
name = "small"
batch = {batch}
keep = ["x_iso_max_m", "floor_acc_max_mps2", "n_steps", "wall_s"]

[base.scene]
fidelity = "rigid"

[base.motion]
pga = 3.0
t_end = {t_end}

[parameters]
"isolation.mu" = {mu}
"solver.method" = {methods}

[records]
names = ["synthetic-wn-40s"]
simulated = {{ n = {n_sim}, seed = 3, duration = {t_end} }}
"""


def _study(tmp_path, name="s.toml", **kw):
    spec = dict(batch=2, t_end=4.0, mu="[0.02, 0.05]", methods='["radau"]', n_sim=1) | kw
    p = tmp_path / name
    p.write_text(textwrap.dedent(SMALL.format(**spec)))
    return p


def _comparable(rows):
    return [{k: v for k, v in r.items() if k not in TIMING_COLUMNS} for r in rows]


def _uplift_study(tmp_path) -> Path:
    # PGA 40 m/s² (4 g) lifts the office frame off its isolators (the no-uplift model stops
    # with an UpliftError: seed 004's model holds for normal forces > 0 only); 3 m/s² does not
    p = _study(tmp_path)
    p.write_text(p.read_text().replace('"solver.method" = ["radau"]', '"motion.pga" = [3.0, 40.0]'))
    return p


def test_failing_task_is_recorded_not_fatal(tmp_path):
    study = load_study(_uplift_study(tmp_path))
    res = run_study(study, tmp_path / "out", executor=ThreadPoolExecutor(1))
    rows = res.table.rows
    assert len(rows) == study.n_tasks == 8
    bad = [r for r in rows if r["status"] != "ok"]
    assert bad and all(r["motion.pga"] == 40.0 and "UpliftError" in r["error"] for r in bad)
    assert all(r["x_iso_max_m"] > 0 for r in rows if r["status"] == "ok")
    assert all(r["status"] == "ok" for r in rows if r["motion.pga"] == 3.0)
    assert res.n_failed == len(bad)
    # a rerun runs nothing (failures count as done) unless asked to retry them
    again = run_study(study, tmp_path / "out", executor=ThreadPoolExecutor(1))
    assert again.n_run == 0 and again.n_skipped == 8
    retry = run_study(study, tmp_path / "out", executor=ThreadPoolExecutor(1), retry_failed=True)
    assert retry.n_run == len(bad) and len(retry.table) == 8


def test_bad_parameter_value_is_refused_before_any_task_runs(tmp_path):
    # the task's scene is checked as `nsdyn run` checks a scene file: a method that does not
    # exist is a SceneError naming the file, the task and the field, before anything is written
    from nsdyn.models.scenefile import SceneError

    p = _study(tmp_path, methods='["radau", "no-such-method"]')
    with pytest.raises(SceneError, match=r"s\.toml: task 2 .*solver\.method.*'radau'"):
        load_study(p)


def test_lost_worker_batch_is_split_and_retried(tmp_path, monkeypatch):
    # an executor-level failure (not a task's exception) on a batch of several tasks: the
    # tasks are resubmitted one by one and all finish
    real = execute.run_batch

    def flaky(tasks):
        if len(tasks) > 1:
            raise RuntimeError("worker vanished")
        return real(tasks)

    monkeypatch.setattr(execute, "run_batch", flaky)
    study = load_study(_study(tmp_path, batch=4))
    res = run_study(study, tmp_path / "out", executor=ThreadPoolExecutor(2))
    assert [r["status"] for r in res.table.rows] == ["ok"] * study.n_tasks


def test_study_runner_equals_build_system_and_nsdyn_run(tmp_path):
    # the per-process cache adds the isolators to a reduction built once: same matrices as
    # build_system, hence the same run as `nsdyn run` (cb: the reduction is the costly part)
    from nsdyn.models.isolated.scene import build_scene, load_scene
    from nsdyn.solve.transient import output_grid, simulate

    over = {
        "scene": {"fidelity": "cb"},
        "isolation": {"k_lam": 8e4, "c": 2e4, "mu": 0.04},
        "motion": {"t_end": 3.0},
    }
    cfg = load_scene(None, over)
    system, motion = build_scene(cfg)
    cached = _isolated_system(cfg, "test")
    for name in ("M", "K", "C", "Gamma", "R", "D", "T"):
        np.testing.assert_array_equal(getattr(cached, name), getattr(system, name), err_msg=name)
    assert cached.isolation == system.isolation
    sv = cfg["solver"]
    ref = simulate(
        system, motion, rtol=sv["rtol"], t_eval=output_grid(motion, sv["dt_out"])
    ).summary()
    got = run_scene_summary(cfg, "test")
    for k in ("x_iso_max_m", "idr_max", "floor_acc_max_mps2", "n_steps"):
        assert got[k] == ref[k], k


def test_same_table_on_process_pool_and_dask_local_cluster(tmp_path):
    pytest.importorskip("distributed")
    study = load_study(_study(tmp_path, mu="[0.02, 0.04, 0.06]"))
    run_scene_summary(expand(study)[0].cfg, "warm-up")  # compiled before the pool forks
    with ProcessPoolExecutor(2) as pool:
        a = run_study(study, tmp_path / "pool", executor=pool)
    with execute.dask_executor(n_local=2, processes=False) as ex:
        b = run_study(study, tmp_path / "dask", executor=ex)
    assert a.n_failed == b.n_failed == 0 and len(a.table) == study.n_tasks
    assert _comparable(a.table.rows) == _comparable(b.table.rows)
    assert _comparable(read_csv(tmp_path / "pool" / RESULTS)) == _comparable(a.table.rows)


def _rows_in(out: Path) -> list[dict]:
    rows = []
    for f in sorted((out / PARTS).glob("part-*.csv")):
        rows += read_csv(f)
    return rows


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_killed_study_resumes_with_every_row_once(tmp_path, sig):
    # 120 short tasks in batches of 1 on one worker process; killed once a few batches are in
    study_path = _study(
        tmp_path, batch=1, t_end=8.0, mu="[0.01, 0.02, 0.03, 0.04, 0.05, 0.06]", n_sim=19
    )
    study = load_study(study_path)
    out = tmp_path / "out"
    code = (
        "import sys; from nsdyn.cli import main; "
        f"sys.exit(main(['study', {str(study_path)!r}, '--out', {str(out)!r}, "
        "'--workers', '1', '--json', '--no-figures']))"
    )
    proc = subprocess.Popen(
        [sys.executable, "-c", code], start_new_session=True, stderr=subprocess.PIPE
    )
    deadline = time.monotonic() + 300
    while len(_rows_in(out)) < 3 if (out / PARTS).is_dir() else True:
        assert proc.poll() is None, proc.stderr.read().decode()
        assert time.monotonic() < deadline
        time.sleep(0.01)
    if sig == signal.SIGKILL:  # the study and its worker, as a machine going down would
        os.killpg(proc.pid, signal.SIGKILL)
    else:
        os.kill(proc.pid, signal.SIGTERM)
    rc = proc.wait(timeout=120)
    try:  # leftovers of the killed study's own process group (its pool worker)
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    if sig == signal.SIGTERM:
        assert rc == 130, proc.stderr.read().decode()
    before = {r["key"]: r for r in _rows_in(out)}
    assert 3 <= len(before) < study.n_tasks  # killed mid-way
    res = run_study(study, out, workers=2)
    keys = [r["key"] for r in res.table.rows]
    assert sorted(keys) == sorted(t.key for t in expand(study))  # every task exactly once
    assert len(set(keys)) == len(keys) == study.n_tasks
    assert res.n_skipped == len(before) and res.n_run == study.n_tasks - len(before)
    assert [r["index"] for r in res.table.rows] == list(range(study.n_tasks))
    on_file = read_csv(out / RESULTS)
    assert [r["key"] for r in on_file] == keys
    assert not list((out / PARTS).glob("*"))  # parts merged, temporaries gone
    for r in res.table.rows:  # rows finished before the kill kept as they were
        if r["key"] in before:
            assert _comparable([r]) == _comparable([before[r["key"]]])
    assert json.dumps(res.as_dict())


def test_fixed_step_task_without_dt_takes_the_run_default(tmp_path):
    # `nsdyn run --method genalpha` steps 0.005 s when the scene gives no dt; a study task of
    # the same scene must be the same run (before, every such task failed asking for dt)
    from nsdyn.models.isolated.scene import build_scene, load_scene
    from nsdyn.solve.run_inputs import FIXED_DT
    from nsdyn.solve.transient import output_grid, simulate

    cfg = load_scene(None, {"scene": {"fidelity": "rigid"}, "motion": {"t_end": 2.0},
                            "solver": {"method": "genalpha"}})  # fmt: skip
    system, motion = build_scene(cfg)
    ref = simulate(system, motion, method="genalpha", dt=FIXED_DT,
                   t_eval=output_grid(motion, cfg["solver"]["dt_out"])).summary()  # fmt: skip
    got = run_scene_summary(cfg, "test")
    assert got["n_steps"] == ref["n_steps"]
    assert got["x_iso_max_m"] == ref["x_iso_max_m"]


def test_a_fixed_step_over_the_records_samples_is_refused_before_any_task(tmp_path):
    # a step that passes over the record's samples (module solve.run_inputs) is named when the
    # study starts, with the task, as `nsdyn run` names it
    from nsdyn.models.scenefile import SceneError

    p = tmp_path / "s.toml"
    p.write_text('[study]\nname = "s"\n[base.solver]\nmethod = "genalpha"\ndt = 0.02\n'
                 '[parameters]\n"isolation.mu" = [0.05, 0.1]\n')  # fmt: skip
    says = r"task 0 .*solver.dt: a fixed step of 0.02 s is longer than the record's sampling"
    with pytest.raises(SceneError, match=says):
        run_study(load_study(p), tmp_path / "out", workers=1)
    assert not (tmp_path / "out" / RESULTS).exists()  # no task ran


def _sleep_long(s: float) -> float:
    time.sleep(s)
    return s


def _ended(proc, timeout: float = 60.0) -> bool:
    """True once worker ``proc`` has ended within ``timeout`` s. Its pool's own thread may
    reap it first, after which ``proc.join`` and ``proc.is_alive`` cannot tell (waitpid finds
    no child: multiprocessing then reports it running), so the pid is asked too: gone, or a
    zombie (ended, not yet reaped)."""
    t_end = time.monotonic() + timeout
    while time.monotonic() < t_end:
        proc.join(timeout=0.1)
        if proc.exitcode is not None:
            return True
        try:
            os.kill(proc.pid, 0)
        except ProcessLookupError:
            return True
        try:
            with open(f"/proc/{proc.pid}/stat") as fh:
                if fh.read().rsplit(")", 1)[1].split()[0] in ("Z", "X"):
                    return True
        except (OSError, IndexError):
            return True
    return False


def _interrupted_while_running() -> list:
    """Leave ``with process_pool(1)`` by a KeyboardInterrupt while its worker runs a 300 s
    task; the pool's worker processes (as they were inside the block)."""
    from nsdyn.studies.workers import process_pool

    with pytest.raises(KeyboardInterrupt):
        with process_pool(1) as pool:
            fut = pool.submit(_sleep_long, 300.0)
            while not fut.running():
                time.sleep(0.01)
            procs = list(pool._processes.values())
            raise KeyboardInterrupt
    return procs


def _sigterm_disposition_is_default() -> bool:
    return signal.getsignal(signal.SIGTERM) == signal.SIG_DFL


def _raise_on_sigterm(signum, frame):
    raise SystemExit(143)


def test_workers_die_on_sigterm_even_when_the_parent_handles_it():
    # the commands turn SIGTERM into a clean exit (nsdyn.cli); a forked worker inherits that
    # handler, and a task's exception is only reported by the pool: the worker must not keep it
    from nsdyn.studies.workers import process_pool

    old = signal.signal(signal.SIGTERM, _raise_on_sigterm)
    try:
        with process_pool(1) as pool:
            assert pool.submit(_sigterm_disposition_is_default).result(timeout=60)
        procs = _interrupted_while_running()
    finally:
        signal.signal(signal.SIGTERM, old)
    assert all(_ended(p) for p in procs)


def test_a_pool_left_by_an_exception_ends_its_running_workers():
    # Ctrl-C inside `with process_pool(...)` must not wait for the running task (here 300 s):
    # the workers are ended and the block is left at once. The bound (60 s) is "it ended", far
    # below the task's 300 s, not a timing check.

    t0 = time.monotonic()
    procs = _interrupted_while_running()
    assert all(_ended(p) for p in procs)
    assert time.monotonic() - t0 < 60.0


def test_signals_during_the_pool_wait_act_between_waits():
    # raised at an arbitrary point, the interrupt could leave a future's lock held by the
    # waiting thread (concurrent.futures.wait takes every pending future's lock) and the
    # pool's manager thread blocked on it at exit; held, it is raised by check() or at the
    # block's end, and the handlers before the block are back afterwards
    from nsdyn.studies.workers import Interrupts

    before = signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)
    with Interrupts() as stop:
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.05)  # delivered, and nothing raised here
        assert stop.requested
        with pytest.raises(KeyboardInterrupt):
            stop.check()
        stop.check()  # once: nothing held now
    assert (signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)) == before
    with pytest.raises(KeyboardInterrupt), Interrupts():
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(0.05)
    assert (signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)) == before


def _run_until_interrupted(path: str) -> None:
    """Count until interrupted, saving the count then (a sweep's amplitude and its points)."""
    from nsdyn.studies.workers import saved_on_interrupt

    n = 0
    Path(path).write_text("0")
    with saved_on_interrupt(lambda: Path(path).write_text(str(n))):
        while True:
            n += 1
            time.sleep(0.01)


def _interrupt_once_held(path) -> None:
    """SIGINT to this process once the task runs and gather holds signals."""
    while not (path.exists() and type(getattr(signal.getsignal(signal.SIGINT), "__self__",
                                              None)).__name__ == "Interrupts"):  # fmt: skip
        time.sleep(0.01)
    time.sleep(0.2)
    os.kill(os.getpid(), signal.SIGINT)


def test_an_interrupted_pool_lets_its_running_task_save_before_it_ends(tmp_path, capfd):
    # a sweep's amplitudes run for minutes and save their points every 2 s: on a Ctrl-C the
    # pool was killed at once and each lost up to 2 s of them. gather passes the interrupt on
    # (SAVE_SIGNAL) and waits, at most GRACE_S, for the tasks' saves; an idle worker ignores
    # it (SIGINT forwarded, it printed a traceback; killed by the signal, it broke the pool)
    import threading

    from nsdyn.studies.workers import gather, process_pool

    path = tmp_path / "saved"
    poke = threading.Thread(target=_interrupt_once_held, args=(path,), daemon=True)
    with pytest.raises(KeyboardInterrupt), process_pool(2) as pool:
        futs = [pool.submit(_run_until_interrupted, str(path)), pool.submit(int, "1")]
        poke.start()
        gather(pool, futs)
    assert int(path.read_text()) > 0  # the count at the interrupt, not the start's 0
    assert "Traceback" not in capfd.readouterr().err


def _fail_at_once() -> None:
    raise ValueError("this amplitude failed")


def test_gather_says_a_failed_task_at_once_and_leaves_a_pool_it_did_not_make_whole():
    # a task's error waited for every other task (an amplitude failing at once was said after
    # the others' hours; here 300 s, the bound 60 s is "at once", not a timing check); and
    # an interrupt sent SAVE_SIGNAL to any pool's workers: a plain ProcessPoolExecutor's
    # idle ones died of it and the caller's pool broke
    from nsdyn.studies.workers import gather, process_pool

    t0 = time.monotonic()
    with pytest.raises(ValueError, match="this amplitude failed"), process_pool(2) as pool:
        gather(pool, [pool.submit(_sleep_long, 300.0), pool.submit(_fail_at_once)])
    assert time.monotonic() - t0 < 60.0
    import threading

    with ProcessPoolExecutor(2) as plain:
        fut = plain.submit(_sleep_long, 0.5)
        poke = threading.Thread(target=_interrupt_once_held, args=(Path(__file__),), daemon=True)
        poke.start()
        with pytest.raises(KeyboardInterrupt):
            gather(plain, [fut])
        assert plain.submit(int, "7").result(timeout=60) == 7  # (not a BrokenProcessPool)


def test_a_narrowed_grid_keeps_the_dropped_rows_for_a_wider_one(tmp_path):
    # the resume contract over grid edits: narrowing the grid takes its dropped points out of
    # results.csv but keeps their finished rows (outside-grid.csv), and widening it again
    # reruns nothing
    from nsdyn.studies.table import OUTSIDE

    wide = load_study(_study(tmp_path, t_end=1.0))
    narrow = load_study(_study(tmp_path, name="n.toml", t_end=1.0, mu="[0.02]"))
    out = tmp_path / "out"
    first = run_study(wide, out, executor=ThreadPoolExecutor(1))  # 2 mu x 2 records
    assert first.n_run == 4 and first.n_outside == 0 and not (out / OUTSIDE).exists()
    cut = run_study(narrow, out, executor=ThreadPoolExecutor(1))
    assert (cut.n_run, cut.n_skipped, cut.n_outside) == (0, 2, 2)
    assert len(read_csv(out / RESULTS)) == 2 and len(read_csv(out / OUTSIDE)) == 2
    again = run_study(wide, out, executor=ThreadPoolExecutor(1))
    assert (again.n_run, again.n_skipped, again.n_outside) == (0, 4, 0)
    assert not (out / OUTSIDE).exists()
    assert [r["x_iso_max_m"] for r in again.table.rows] == [
        r["x_iso_max_m"] for r in first.table.rows
    ]


def test_a_reordered_keep_reruns_nothing_and_orders_the_kept_columns(tmp_path):
    # the resume contract: a row depends on the set of kept fields, not on their order, so
    # reordering keep reuses every row (its columns in the new order); a field dropped (or
    # added) is a new row for every task
    first_keep = '["x_iso_max_m", "floor_acc_max_mps2", "n_steps", "wall_s"]'
    text = _study(tmp_path, t_end=1.0).read_text()
    moved = tmp_path / "moved.toml"
    moved_keep = '["n_steps", "x_iso_max_m", "floor_acc_max_mps2", "wall_s"]'
    moved.write_text(text.replace(first_keep, moved_keep))
    fewer = tmp_path / "fewer.toml"
    fewer.write_text(text.replace(first_keep, '["x_iso_max_m", "n_steps", "wall_s"]'))
    out = tmp_path / "out"
    first = run_study(load_study(tmp_path / "s.toml"), out, executor=ThreadPoolExecutor(1))
    again = run_study(load_study(moved), out, executor=ThreadPoolExecutor(1))
    assert (first.n_run, again.n_run, again.n_skipped) == (4, 0, 4)
    cols = again.table.columns
    assert cols.index("n_steps") < cols.index("x_iso_max_m") < cols.index("floor_acc_max_mps2")
    header = (out / RESULTS).read_text().splitlines()[0].split(",")
    assert header.index("n_steps") < header.index("x_iso_max_m")
    assert [r["x_iso_max_m"] for r in again.table.rows] == [
        r["x_iso_max_m"] for r in first.table.rows
    ]
    assert run_study(load_study(fewer), out, executor=ThreadPoolExecutor(1)).n_run == 4


def test_record_names_stay_text_in_the_table(tmp_path):
    # two records named "001" and "1" are two records: read back from the CSV they must not
    # become the number 1 (the analyses group by the record column)
    from nsdyn.studies.table import Table

    rows = [{"index": 0, "key": "0a", "record": "001", "status": "ok", "x": 0.5},
            {"index": 1, "key": "0b", "record": "1", "status": "ok", "x": 7}]  # fmt: skip
    back = read_csv(Table(rows).write_csv(tmp_path / RESULTS))
    assert [r["record"] for r in back] == ["001", "1"]
    assert [r["x"] for r in back] == [0.5, 7]


def test_a_local_dask_cluster_leaves_a_ctrl_c_to_this_process():
    # a Ctrl-C reaches the whole process group: each worker printed its own KeyboardInterrupt
    # traceback; they start with SIGINT ignored, and this process keeps its own handler
    pytest.importorskip("distributed")
    before = signal.getsignal(signal.SIGINT)
    with execute.dask_executor(n_local=1) as ex:
        assert ex.submit(signal.getsignal, signal.SIGINT).result() == signal.SIG_IGN
        assert signal.getsignal(signal.SIGINT) is before


def test_a_dask_address_that_is_not_one_is_an_oserror_naming_it():
    # the command line turns an OSError into one line, exit 2 (it was a traceback)
    pytest.importorskip("distributed")
    with pytest.raises(OSError, match=r"^no Dask scheduler at notanaddress: .*tcp://host:8786"):
        with execute.dask_executor("notanaddress"):
            pass
    # a local cluster's size: a whole number >= 1 (0 ran one worker, "2" failed inside
    # distributed), and none beside an address (its scheduler's workers are used)
    for n, match in ((0, r"^n_local: expected a number"), ("2", r"^n_local: expected"),
                     (2, r"^n_local: the size of a local cluster")):  # fmt: skip
        with pytest.raises(ValueError, match=match):
            with execute.dask_executor("tcp://localhost:1" if n == 2 else None, n_local=n):
                pass


def test_executor_settings_that_cannot_mean_anything_are_refused(tmp_path, monkeypatch):
    # workers=0 ran on the CPU count, an executor named by a string failed inside the run
    # (AttributeError), workers beside an executor were ignored, and an address left empty on
    # the command line ran on the local pool without a word
    from nsdyn.cli import main

    st = load_study(_study(tmp_path))
    for kw, err, match in (
        ({"workers": 0}, ValueError, r"^workers: expected an integer >= 1"),
        ({"executor": "dask"}, TypeError, r"^executor: expected a concurrent\.futures\.Executor"),
        ({"executor": ThreadPoolExecutor(1), "workers": 2}, ValueError, "give one or the other"),
        # fresh="no" was true: a finished study's table was wiped and run again
        ({"fresh": "no"}, TypeError, r"^fresh: expected True or False, got 'no'"),
        ({"retry_failed": 1}, TypeError, r"^retry_failed: expected True or False"),
        ({"progress": 5}, TypeError, r"^progress: expected a function of one line"),
        # dask_executor() given without `with`: its context manager, not an executor
        ({"executor": execute.dask_executor()}, TypeError, r"with nsdyn\.dask_executor\(\) as ex"),
        ({"executor": contextlib.nullcontext()}, TypeError, r"nullcontext object at \w+>$"),
    ):
        with pytest.raises(err, match=match):
            run_study(st, tmp_path / "o", **kw)
    assert not (tmp_path / "o").exists()  # refused before any file
    # a file's path for the study was an AttributeError ('str' object has no '__dict__'), a
    # file for the folder a FileExistsError
    with pytest.raises(TypeError, match=r"^study: expected a Study \(nsdyn\.load_study"):
        run_study(str(tmp_path / "s.toml"), tmp_path / "o")
    with pytest.raises(ValueError, match=r"^out_dir: .*s\.toml is a file; expected a folder"):
        run_study(st, tmp_path / "s.toml")
    with pytest.raises(SystemExit) as e:
        main(["study", str(tmp_path / "s.toml"), "--dask", ""])
    assert e.value.code == 2
    # a pool is never larger than the tasks it runs (1000 workers on 4 tasks took 100x longer)
    sizes = []
    monkeypatch.setattr(execute, "process_pool", lambda n: sizes.append(n) or ThreadPoolExecutor(1))
    run_study(st, tmp_path / "p", workers=64)
    assert sizes == [len(expand(st))]


def test_a_study_table_reads_back_as_a_dataframe_cell_for_cell(tmp_path):
    # a study's table in a notebook: the rows read back from results.csv, in one DataFrame
    pd = pytest.importorskip("pandas")
    from nsdyn.studies import read_results

    rows = [{"index": 0, "key": "a1", "record": "001", "status": "ok", "error": "",
             "isolation.mu": 0.05, "x_iso_max_m": 0.125, "toppled": False},
            {"index": 1, "key": "b2", "record": "002", "status": "failed",
             "error": "UpliftError: x", "isolation.mu": 0.1, "x_iso_max_m": None,
             "toppled": None}]  # fmt: skip
    table = Table(rows, ["isolation.mu"])  # (as a study's: the parameters before status)
    table.write_csv(tmp_path / RESULTS)
    df = read_results(tmp_path).to_dataframe()
    # in the study's own order (read back, the parameters came after status, error, task_s)
    assert list(df.columns) == table.columns and len(df) == 2
    assert df["record"].tolist() == ["001", "002"]  # (text: not records 1 and 2)
    assert df.loc[0, "x_iso_max_m"] == 0.125 and pd.isna(df.loc[1, "x_iso_max_m"])
    with pytest.raises(FileNotFoundError, match="no results.csv; expected the folder a study"):
        read_results(tmp_path / "nope")
    assert read_results(tmp_path / RESULTS).rows == read_results(tmp_path).rows  # (the file)
    # a misspelt column read as all NaN; a table printed as an object's address
    assert table.column("x_iso_max_m")[0] == 0.125
    with pytest.raises(KeyError, match="'x_iso_mx_m': no such column; did you mean 'x_iso_max_m'"):
        table.column("x_iso_mx_m")
    # a text column read as all NaN: named, with the call that gives it
    with pytest.raises(ValueError, match=r"'record' holds text, not numbers: table.values"):
        table.column("record")
    assert table.values("record") == ["001", "002"]
    assert repr(table).startswith("<study Table: 2 rows; columns index, key, record, ")
    # a table cut short (a row of fewer cells) was a TypeError; an empty file 0 rows; both
    # are the input errors nsdyn study says in one line, status 2 (a traceback, status 1)
    from nsdyn.atomic import CheckpointError

    (tmp_path / "cut").mkdir()
    (tmp_path / "cut" / RESULTS).write_text(table.to_csv() + "2,c3\n")
    with pytest.raises(CheckpointError, match=r"results\.csv: line 4: fewer cells than the "
                       r"header .* or rerun the study with --fresh$"):  # fmt: skip
        read_results(tmp_path / "cut")
    (tmp_path / "cut" / RESULTS).write_text("")
    with pytest.raises(CheckpointError, match=r"results\.csv: empty; expected the table a study"):
        read_results(tmp_path / "cut")
    (tmp_path / "cut" / "results.parquet").write_bytes(b"PAR1")  # (not "no results.csv")
    with pytest.raises(FileNotFoundError, match=r"results\.parquet: not a study's folder or its "
                       r"results\.csv \(a results\.parquet reads with pandas"):  # fmt: skip
        read_results(tmp_path / "cut" / "results.parquet")
    # the analyses take a study's Table, not its DataFrame copy (an AttributeError 'rows')
    with pytest.raises(TypeError, match=r"^table: expected a study's Table"):
        run_analyses(load_study(_study(tmp_path)), df, tmp_path / "a")


def test_a_table_keyed_by_keeps_order_is_resumed_not_rerun(tmp_path, monkeypatch):
    # tables written when the key hashed keep in its order (unsorted here) hold rows under
    # those keys: a resume finds them (re-keyed) instead of running the whole study anew
    from nsdyn.studies import tasks as study_tasks

    key = study_tasks.task_key
    study = load_study(_study(tmp_path, t_end=1.0))
    assert list(study.keep) != sorted(study.keep)  # (else both keys are one)
    out = tmp_path / "out"
    with monkeypatch.context() as m:
        m.setattr(study_tasks, "task_key", lambda *a, ordered=False: key(*a, ordered=True))
        first = run_study(study, out, executor=ThreadPoolExecutor(1))
    again = run_study(load_study(tmp_path / "s.toml"), out, executor=ThreadPoolExecutor(1))
    assert (first.n_run, again.n_run, again.n_skipped, again.n_outside) == (4, 0, 4, 0)
    assert {r["key"] for r in read_csv(out / RESULTS)} == {t.key for t in expand(study)}
    assert [r["x_iso_max_m"] for r in again.table.rows] == [
        r["x_iso_max_m"] for r in first.table.rows
    ]


def test_rows_under_an_earlier_key_in_another_grid_come_back_when_it_widens(tmp_path, monkeypatch):
    # an old table narrowed (its dropped rows kept outside under their old keys) and widened
    # again reruns nothing, and no task sits both inside and outside the grid
    from nsdyn.studies import tasks as study_tasks
    from nsdyn.studies.table import OUTSIDE

    key = study_tasks.task_key
    wide = load_study(_study(tmp_path, t_end=1.0))
    narrow = load_study(_study(tmp_path, name="n.toml", t_end=1.0, mu="[0.02]"))
    out = tmp_path / "out"
    with monkeypatch.context() as m:
        m.setattr(study_tasks, "task_key", lambda *a, ordered=False: key(*a, ordered=True))
        assert run_study(wide, out, executor=ThreadPoolExecutor(1)).n_run == 4
    cut = run_study(narrow, out, executor=ThreadPoolExecutor(1))
    assert (cut.n_run, cut.n_skipped, cut.n_outside) == (0, 2, 2)
    again = run_study(load_study(tmp_path / "s.toml"), out, executor=ThreadPoolExecutor(1))
    assert (again.n_run, again.n_skipped, again.n_outside) == (0, 4, 0)
    assert not (out / OUTSIDE).exists()
    assert sorted(r["key"] for r in read_csv(out / RESULTS)) == sorted(t.key for t in expand(wide))


def test_a_harmonic_base_motion_replaces_a_record_scene_s_motion(tmp_path):
    # [base.motion] kind = "harmonic" over a scene file with a record was refused for that
    # record's keys; it now replaces the scene's motion as load_scene's overrides do, and each
    # task is the scene run directly under that harmonic motion (the same x_iso to round-off)
    import nsdyn

    scene = Path(__file__).resolve().parents[2] / "examples/scenes/isolated-shear-3storey.toml"
    harmonic = {"kind": "harmonic", "amplitude": 1.0, "frequency": 0.5, "t_end": 4.0}
    p = tmp_path / "h.toml"
    p.write_text(
        textwrap.dedent(f"""\
        [study]
        name = "harmonic-base"
        scene = "{scene.as_posix()}"
        keep = ["x_iso_max_m"]
        [base.motion]
        kind = "harmonic"
        amplitude = 1.0
        frequency = 0.5
        t_end = 4.0
        [parameters]
        "isolation.mu" = [0.02]
        """)
    )
    res = run_study(load_study(p), tmp_path / "out", executor=ThreadPoolExecutor(1))
    (row,) = res.table.rows
    assert row["status"] == "ok", row.get("error")
    cfg = nsdyn.load_scene(scene, overrides={"motion": harmonic, "isolation": {"mu": 0.02}})
    system, excitation, _ = nsdyn.build_scene_run(cfg)
    direct = nsdyn.simulate(system, excitation, t_end=4.0).summary()["x_iso_max_m"]
    assert row["x_iso_max_m"] == pytest.approx(direct, rel=1e-12)
