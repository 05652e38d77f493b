"""Command line: ``nsdyn SUBCOMMAND ...`` — the only place with argparse.

One module per subcommand (``modes``, ``run``, ``sweep``, ``bench``), each a pair
``configure(parser)`` / ``run(args) -> int`` registered in :data:`nsdyn.cli.app.COMMANDS`.
Errors the user can fix print one line naming the file and field and exit with status 2;
numerical failures print the time/frequency and reason and exit with status 3.
"""

import os

# One BLAS thread unless the user asks for more (set before numpy loads its BLAS; importing
# nsdyn does not load numpy). nsdyn's dense algebra is on small matrices (13-26 states, a few
# hundred dofs at most), where a second thread buys nothing, and an idle OpenBLAS thread
# spins for a while after each call: on a 2-core machine with other work it takes a core from
# the integrator (README, "Start-up and the default run").
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

from nsdyn.cli.app import COMMANDS, Command, build_parser, main, script  # noqa: E402

__all__ = ["COMMANDS", "Command", "build_parser", "main", "script"]
