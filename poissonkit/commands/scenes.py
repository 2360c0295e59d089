"""``poissonkit scenes``: the scenes ``poissonkit run`` (and ``sweep``) take by name.

Two kinds: scenes registered by plugins (:class:`~poissonkit.plugin.SceneEntry`, e.g. the
magnets plugin's ``seed000``, the default of ``poissonkit run``) and the scene files shipped
with the package (``poissonkit/scene/shipped/*.toml``, run by their stem). Each is listed with its
one-line description; ``--json`` gives the same as a list of objects.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import asdict


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``poissonkit scenes``."""
    parser.add_argument("--json", action="store_true", help="machine-readable output")


def main(args: argparse.Namespace) -> int:
    """Print the registered scenes, then the shipped scene files."""
    from poissonkit.scene.registered import scene_catalog

    rows = scene_catalog()
    if args.json:
        print(json.dumps([asdict(r) for r in rows], indent=2))
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
        if not shown:
            print("  (none)")
    print("run one with `poissonkit run NAME`; a path to any scene file works too")
    return 0
