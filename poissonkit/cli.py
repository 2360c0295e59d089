"""Command-line interface: ``poissonkit run | scenes | view | verify | bench | plugins | sweep``.

The entry point only: the parser and the subcommand table live in
:mod:`poissonkit.commands.parser` (re-exported here), each subcommand in
``poissonkit/commands/<name>.py`` with ``add_arguments(parser)`` and ``main(args) -> int``;
modules are imported only when their command runs.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Sequence

from poissonkit.commands.parser import COMMANDS, CommandParser, build_parser, command_of
from poissonkit.errors import PoissonkitError

__all__ = ["COMMANDS", "CommandParser", "build_parser", "main"]


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``poissonkit`` command; returns the process exit code."""
    argv = sys.argv[1:] if argv is None else list(argv)
    # only the named command's module is imported (none for `poissonkit --help`): startup time
    parser = build_parser(only=command_of(argv) or "")
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    try:
        module = importlib.import_module(COMMANDS[args.command][0])
    except ModuleNotFoundError:
        print(f"poissonkit {args.command}: not available in this build", file=sys.stderr)
        return 2
    try:
        return int(module.main(args) or 0)
    except PoissonkitError as exc:
        print(f"poissonkit {args.command}: error: {exc}", file=sys.stderr)
        return 1
