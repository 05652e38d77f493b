"""Load: a study of a few thousand tiny tasks runs to the end with bounded memory and no leak.

Measured: peak RSS of this process (``resource.getrusage``, kB on Linux) before and after,
open file descriptors (``/proc/self/fd``) and temporary files left in the output directory.
The bound: the peak grows by less than 200 MB over 3000 tasks (the table holds a few numbers
per task: ~1 kB each), the descriptor count returns to its start, no ``*.tmp`` remains.
"""

from __future__ import annotations

import os
import resource
import textwrap
import time

import pytest

N_MU = 100  # grid values of isolation.mu
N_REC = 30  # simulated records -> N_MU * N_REC tasks
RSS_GROWTH_MAX_KB = 200_000  # bound on peak-RSS growth over the study [kB]

STUDY = f"""
[study]
name = "load"
batch = 50
keep = ["x_iso_max_m"]

[base.scene]
fidelity = "rigid"

[base.motion]
pga = 3.0
t_end = 0.2

[parameters]
"isolation.mu" = {{ linspace = [0.01, 0.1, {N_MU}] }}

[records]
simulated = {{ n = {N_REC}, seed = 5, duration = 0.5 }}
"""


def _fds() -> int:
    return len(os.listdir("/proc/self/fd"))


@pytest.mark.slow
def test_thousands_of_tasks_bounded_memory_no_leak(tmp_path):
    from nsdyn.studies.execute import run_study
    from nsdyn.studies.study import load_study

    p = tmp_path / "load.toml"
    p.write_text(textwrap.dedent(STUDY))
    study = load_study(p)
    assert study.n_tasks == N_MU * N_REC
    fd0 = _fds()
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    t0 = time.perf_counter()
    res = run_study(study, tmp_path / "out", workers=1)
    wall = time.perf_counter() - t0
    rss1 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    print(f"LOAD tasks={study.n_tasks} wall={wall:.1f}s rss0={rss0}kB rss1={rss1}kB "
          f"children_max={children}kB fd0={fd0} fd1={_fds()}")  # fmt: skip
    assert res.n_failed == 0 and len(res.table.rows) == study.n_tasks
    assert rss1 - rss0 < RSS_GROWTH_MAX_KB
    assert _fds() <= fd0
    assert not [q for q in (tmp_path / "out").rglob("*") if q.name.endswith(".tmp")]
