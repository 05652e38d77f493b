"""The command line keeps BLAS to one thread unless the user asks for more.

An idle OpenBLAS thread spins after each call; on a 2-core machine with other work it takes a
core from the integrator. The setting must be in place before numpy loads its BLAS, which
importing nsdyn and its command line does not do, and must not override the user's own.
"""

import os
import subprocess
import sys

PROBE = (
    "import os, sys; import nsdyn.cli; "
    "print(os.environ['OPENBLAS_NUM_THREADS'], os.environ['OMP_NUM_THREADS'], "
    "'numpy' in sys.modules)"
)


def _probe(env_extra):
    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    env.update(env_extra)
    out = subprocess.run(
        [sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, check=True
    )
    return out.stdout.split()


def test_one_blas_thread_set_before_numpy_loads():
    assert _probe({}) == ["1", "1", "False"]


def test_the_users_thread_count_is_kept():
    assert _probe({"OPENBLAS_NUM_THREADS": "2", "OMP_NUM_THREADS": "3"}) == ["2", "3", "False"]
