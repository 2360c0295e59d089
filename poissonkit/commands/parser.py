"""The command-line parser: the subcommand table and the parser built from it.

Each subcommand lives in ``poissonkit/commands/<name>.py`` with ``add_arguments(parser)`` and
``main(args) -> int``; modules are imported only when their command runs (or when the parser
is built, for their options). The entry point :mod:`poissonkit.cli` sits above this module and
only parses, dispatches and turns errors into exit codes.
"""

from __future__ import annotations

import argparse
import importlib
from collections.abc import Callable

from poissonkit._version import __version__

#: The CLI's one-line description (``poissonkit --help``).
DESCRIPTION = ("Command-line interface: "
               "``poissonkit run | scenes | view | verify | bench | plugins | sweep``.")

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


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every subcommand's options."""
    parser = argparse.ArgumentParser(prog="poissonkit", description=DESCRIPTION)
    parser.add_argument("--version", action="version", version=f"poissonkit {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=CommandParser)
    for name, (module, help_text) in COMMANDS.items():
        p = sub.add_parser(name, help=help_text, description=help_text,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        try:
            importlib.import_module(module).add_arguments(p)
        except ModuleNotFoundError:
            pass
    return parser
