"""The command-line options page: ``nsdyn COMMAND --help`` of every subcommand, from the parser.

Built from :func:`nsdyn.cli.app.build_parser` (the one place with argparse), so the page shows
exactly the options the installed ``nsdyn`` accepts.
"""

from __future__ import annotations

import argparse
import os


def page() -> str:
    """The Markdown of ``reference/cli-options.md``."""
    os.environ["COLUMNS"] = "100"  # argparse wraps its help to the terminal width
    from nsdyn.cli.app import COMMANDS, build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    lines = [
        "# Command-line options",
        "",
        "`nsdyn COMMAND --help` of every subcommand, generated from the command-line parser.",
        "What each command is for, and the exit status, are on the",
        "[command-line](cli.md) page.",
        "",
    ]
    for name, sp in sub.choices.items():
        lines += [
            f"## `nsdyn {name}`",
            "",
            COMMANDS[name].help[:1].upper() + COMMANDS[name].help[1:] + ".",
            "",
        ]
        lines += ["```text", sp.format_help().rstrip(), "```", ""]
    return "\n".join(lines)
