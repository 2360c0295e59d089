"""``poissonkit new-plugin NAME [--dir D]``: write a plugin package from the template.

The package (``D/poissonkit-NAME``) has a ``pyproject.toml`` with the entry point, a pair
potential and a scene in ``hooks.py``, and tests (the kit's checks and the plugin's truth);
``pip install`` it and run ``pytest`` in it (``docs/plugins.md``, "Start from the template").
"""

from __future__ import annotations

import argparse


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``poissonkit new-plugin``."""
    parser.add_argument("name", help="plugin name: lower-case letters, digits and '_'")
    parser.add_argument("--dir", default=".", help="folder to create the package in "
                                                   "(default: the current one)")


def main(args: argparse.Namespace) -> int:
    """Write the package and say what to do next."""
    from poissonkit.testing.scaffold import new_plugin

    path = new_plugin(args.name, args.dir)
    print(f"wrote {path}")
    print(f"next: pip install -e {path}  &&  cd {path}  &&  pytest")
    return 0
