"""``poissonkit scenes``: the scenes ``poissonkit run`` (and ``sweep``) take by name.

Two kinds: scenes registered by plugins (:class:`~poissonkit.plugin.SceneEntry`, e.g. the
magnets plugin's ``seed000``, the default of ``poissonkit run``) and the scene files shipped
with the package (``poissonkit/scene/shipped/*.toml``, run by their stem). Each is listed with its
one-line description and, for registered scenes, the parameters ``--param NAME=VALUE`` sets
(name, unit, default, meaning); ``--json`` gives the same as a list of objects.
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Mapping, Sequence
from dataclasses import asdict


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``poissonkit scenes``."""
    parser.add_argument("--json", action="store_true", help="machine-readable output")


def main(args: argparse.Namespace) -> int:
    """Print the registered scenes, then the shipped scene files."""
    from poissonkit.scene.registered import scene_catalog

    rows = scene_catalog()
    if args.json:
        print(json.dumps([asdict(r) for r in rows], indent=2, default=str))
        return 0
    width = max((len(r.name) for r in rows), default=0)
    for kind, title in (("registered", "registered scenes (plugins)"),
                        ("file", "shipped scene files")):
        print(f"{title}:")
        shown = [r for r in rows if r.kind == kind]
        for r in shown:
            extra = f" [default; from {r.source}]" if r.default else (
                f" [from {r.source}]" if kind == "registered" and r.source else "")
            print(f"  {r.name:<{width}}  {r.description}{extra}")
            _print_parameters(r.parameters)
        if not shown:
            print("  (none)")
    print("run one with `poissonkit run NAME [--param NAME=VALUE ...]`; a path to any scene "
          "file works too")
    return 0


def _print_parameters(parameters: Sequence[Mapping[str, object]]) -> None:
    """One indented line per parameter: name, default with unit, meaning."""
    if not parameters:
        return
    width = max(len(str(p["name"])) for p in parameters)
    for p in parameters:
        unit = f" {p['unit']}" if p["unit"] else ""
        default = "(optional)" if p["default"] is None else f"= {p['default']}{unit}"
        print(f"      --param {str(p['name']):<{width}} {default:<20} {p['doc']}")
