"""Command line: ``nsdyn SUBCOMMAND ...`` — the only place with argparse.

One module per subcommand (``modes``, ``run``, ``sweep``, ``bench``), each a pair
``configure(parser)`` / ``run(args) -> int`` registered in :data:`nsdyn.cli.app.COMMANDS`.
Errors the user can fix print one line naming the file and field and exit with status 2;
numerical failures print the time/frequency and reason and exit with status 3.
"""

from nsdyn.cli.app import COMMANDS, Command, build_parser, main

__all__ = ["COMMANDS", "Command", "build_parser", "main"]
