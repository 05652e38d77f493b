"""The ``nsdyn`` script ends its process without the interpreter's last full collection.

After a command, every object numba's compilation left is moved to the permanent generation
(``gc.freeze``), so the interpreter's final collection does not traverse them; ``main`` (the
function tests and notebooks call) leaves the collector alone. Timings: docs/dev/first-runs.md.
"""

import subprocess
import sys
import tomllib
from pathlib import Path

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
