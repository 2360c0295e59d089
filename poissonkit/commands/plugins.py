"""``poissonkit plugins``: every plugin, its version and what it contributes."""

from __future__ import annotations

import argparse
import json


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``poissonkit plugins``."""
    parser.add_argument("--json", action="store_true", help="machine-readable output")


def main(args: argparse.Namespace) -> int:
    """List plugins; failed and blocked ones are shown with the reason, never fatal."""
    from poissonkit.plugin import plugin_reports

    reports = plugin_reports()
    if args.json:
        print(json.dumps([r.__dict__ for r in reports], indent=2))
        return 0
    for r in reports:
        head = f"{r.name} {r.version} ({r.source})"
        if r.status != "ok":
            print(f"{head}  [{r.status.upper()}] {r.error}")
            continue
        print(head)
        for kind, names in sorted(r.contributions.items()):
            print(f"    {kind}: {', '.join(names)}")
    return 0
