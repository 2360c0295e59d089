"""The command-line parser: the subcommand table and the parser built from it.

Each subcommand lives in ``poissonkit/commands/<name>.py`` with ``add_arguments(parser)`` and
``main(args) -> int``; modules are imported only when their command runs (or when the parser
is built for them, for their options: :func:`build_parser` with ``only`` imports just the one
command module, so ``poissonkit --help`` and ``poissonkit scenes`` load no other command's
dependencies). The entry point :mod:`poissonkit.cli` sits above this module and only parses,
dispatches and turns errors into exit codes.
"""

from __future__ import annotations

import argparse
import importlib
from collections.abc import Callable, Sequence
from typing import Any

#: The CLI's one-line description (``poissonkit --help``).
DESCRIPTION = ("Command-line interface: "
               "``poissonkit run | scenes | view | verify | bench | plugins | sweep | new-plugin``.")

COMMANDS: dict[str, tuple[str, str]] = {
    "run": ("poissonkit.commands.run", "integrate a scene (default: the seed 000 orbit)"),
    "scenes": ("poissonkit.commands.scenes", "list the scenes `run` takes by name"),
    "view": ("poissonkit.commands.view", "open the interactive 3D view of a run in a browser"),
    "verify": ("poissonkit.commands.verify", "check a Poisson structure: Jacobi, rank, Casimirs"),
    "bench": ("poissonkit.commands.bench", "speed against error of every integrator on a scene"),
    "plugins": ("poissonkit.commands.plugins", "list plugins and what they contribute"),
    "sweep": ("poissonkit.commands.sweep", "run a scene over a grid or sample of parameters on Dask"),
    "new-plugin": ("poissonkit.commands.new_plugin", "write a plugin package from the template"),
}


class CommandParser(argparse.ArgumentParser):
    """The parser of one subcommand; its epilog may be built only when help is shown.

    ``epilog_factory`` (set by a command's ``add_arguments``) returns the epilog text, e.g. the
    scenes ``run --help`` lists, which needs the plugins loaded: other commands do not pay for
    it. The epilog keeps its line breaks.
    """

    epilog_factory: Callable[[], str] | None = None

    def format_help(self) -> str:
        """The help text, with the epilog built now if a factory is set."""
        if self.epilog_factory is not None:
            self.epilog = self.epilog_factory()
        return super().format_help()


class _VersionAction(argparse.Action):
    """``--version``: the installed version, read only when asked (importlib.metadata is slow
    to import, and every other call of the command line would pay for it)."""

    def __init__(self, option_strings: Sequence[str], dest: str = argparse.SUPPRESS,
                 default: str = argparse.SUPPRESS, help: str | None = None) -> None:  # noqa: A002
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
                 values: str | Sequence[Any] | None, option_string: str | None = None) -> None:
        from poissonkit._version import __version__

        print(f"poissonkit {__version__}")  # on stdout, as argparse's own version action
        parser.exit()


def command_of(argv: Sequence[str]) -> str | None:
    """The subcommand named on the command line ``argv`` (its first word that is one of
    :data:`COMMANDS`, before any option's value could be), or ``None``."""
    for word in argv:
        if word in COMMANDS:
            return word
        if not word.startswith("-"):
            return None
    return None


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The argument parser with every subcommand's options, or, with ``only``, with the
    options of that one subcommand (the others are listed, their modules not imported)."""
    parser = argparse.ArgumentParser(prog="poissonkit", description=DESCRIPTION)
    parser.add_argument("--version", action=_VersionAction,
                        help="show the installed version and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=CommandParser)
    for name, (module, help_text) in COMMANDS.items():
        p = sub.add_parser(name, help=help_text, description=help_text,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        if only is not None and name != only:
            continue
        try:
            importlib.import_module(module).add_arguments(p)
        except ModuleNotFoundError:
            pass
    return parser
