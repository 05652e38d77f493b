"""The ``nsdyn`` script ends its process without the interpreter's last full collection, and
starts without collections that traverse its start-up's objects.

After a command, every object numba's compilation left is moved to the permanent generation
(``gc.freeze``), so the interpreter's final collection does not traverse them. Before it, the
collector's first generation waits for a million new container objects
(``nsdyn._numba_cache.hold_collections``); a cached run's start makes ~150 000 that stay, so
none of Python's collections runs outside numba's compile sections (which set their own
thresholds and freeze what is alive on entry), and there is no full collection: with
Python's thresholds (700, 10, 10) a cached default run made ~170 collections and one full
one. ``main`` (the function tests and notebooks call) leaves the collector alone. Timings:
docs/dev/first-runs.md.
"""

import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

PROBE = (
    "import gc, sys; from nsdyn.cli import {fn}; "
    "code = {fn}(['run', 'no-such-scene.toml']); print(code, gc.get_freeze_count() > 0)"
)


def _probe(fn: str) -> list[str]:
    out = subprocess.run([sys.executable, "-c", PROBE.format(fn=fn)], capture_output=True,
                         text=True, check=True)  # fmt: skip
    return out.stdout.split()


def test_the_script_passes_the_exit_status_and_freezes_the_collector():
    # a user error (missing scene file): status 2, as from main
    assert _probe("script") == ["2", "True"]


def test_main_leaves_the_collector_alone():
    assert _probe("main") == ["2", "False"]


def test_the_installed_script_and_python_m_run_the_script():
    pyproject = tomllib.loads((Path(__file__).parents[2] / "pyproject.toml").read_text())
    assert pyproject["project"]["scripts"]["nsdyn"] == "nsdyn.cli:script"
    main_py = (Path(__file__).parents[2] / "nsdyn" / "cli" / "__main__.py").read_text()
    assert "sys.exit(script())" in main_py


COUNT = """
import contextlib, gc, io, json, sys
counts = [0, 0, 0]
gc.callbacks.append(lambda phase, info: phase == "stop" and counts.__setitem__(
    info["generation"], counts[info["generation"]] + 1))
from nsdyn.cli import script
with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
    code = script(["run", "--t-end", "1", "--no-figures", "--out", sys.argv[1]])
print(json.dumps([code, counts, gc.get_threshold()[0]]))
"""


@pytest.mark.skipif(
    os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0"),
    reason="a cached start is numba's: without the JIT there is nothing to load",
)
def test_a_cached_start_makes_no_full_collection(tmp_path, child_env):
    from nsdyn._numba_cache import SCRIPT_GC_THRESHOLD

    rows = []
    for i in range(2):  # the first fills numba's cache where the test session has not yet
        argv = [sys.executable, "-P", "-c", COUNT, str(tmp_path / str(i))]
        r = subprocess.run(argv, env=child_env, capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        rows.append(json.loads(r.stdout.strip().splitlines()[-1]))
    code, counts, threshold = rows[1]
    assert code == 0 and threshold == SCRIPT_GC_THRESHOLD
    assert counts[2] == 0  # no full collection


def test_a_reader_that_closes_the_pipe_ends_the_command_quietly(child_env):
    """`nsdyn modes portal --json | head -c 10`: the reader goes before the JSON is written;
    the command stops with status 141 (128 + SIGPIPE, what a process killed by the signal
    gives) and no traceback, also from the interpreter's last flush."""
    from nsdyn.cli.args import EXIT_PIPE_CLOSED

    argv = [sys.executable, "-m", "nsdyn.cli", "modes", "portal", "--json"]
    env = {k: v for k, v in child_env.items() if k != "PYTHONUNBUFFERED"}  # a buffered stdout
    p = subprocess.Popen(argv, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    p.stdout.close()  # before the child has imported anything: its first write fails
    err = p.stderr.read().decode()
    assert p.wait() == EXIT_PIPE_CLOSED == 128 + 13 and err == ""


def test_an_interrupt_during_the_commands_imports_is_one_line_and_status_130():
    # before main set its handlers (a command's module importing numpy) Ctrl-C ended in a
    # 40-line traceback and status -2, SIGTERM in status -15 and no word
    code = (
        "import signal, sys\n"
        "from nsdyn.cli import app\n"
        "def interrupted(argv=None):\n"
        "    signal.raise_signal(signal.SIGTERM)  # (the script's handler: as Ctrl-C)\n"
        "app.main = interrupted\n"
        "sys.exit(app.script(['run']))\n"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 130, p.stderr
    assert p.stderr == "nsdyn: interrupted as it started; it wrote nothing\n"
