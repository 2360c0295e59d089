"""``poissonkit plugins``: every plugin, its version, the plugin API version it was written for
and what it contributes (after a first line naming this poissonkit's plugin API version).

Under each kind the contributed names are listed on one line; integrators and model families
then get one line each with what their registry entry declares: an integrator's order, family
and capabilities (:class:`~poissonkit.plugin.contributions.Capabilities`), a model family's
models (cheapest first) and the body quantities its error estimate reads. A plugin with hook
implementations no hook specification knows (a misspelt hook name) is listed with a warning.
"""

from __future__ import annotations

import argparse
import json

from poissonkit.plugin.contributions import Entry, IntegratorEntry, ModelFamily


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``poissonkit plugins``."""
    parser.add_argument("--json", action="store_true", help="machine-readable output")


def _integrator_details(entry: IntegratorEntry) -> dict[str, object]:
    return {"order": entry.order, "family": entry.family,
            "capabilities": list(entry.capabilities.names()),
            "options": [{"name": o.name, "type": o.type, "default": o.default,
                         "choices": list(o.choices) if o.choices else None, "doc": o.doc}
                        for o in entry.options()]}


def _family_details(entry: ModelFamily) -> dict[str, object]:
    return {"models": list(entry.models), "defaults": list(entry.defaults),
            "reads": list(entry.reads)}


def details(kind: str, entry: Entry) -> dict[str, object] | None:
    """What the listing shows of one registry entry beyond its name (``None``: nothing)."""
    if kind == "integrator" and isinstance(entry, IntegratorEntry):
        return _integrator_details(entry)
    if kind == "model_family" and isinstance(entry, ModelFamily):
        return _family_details(entry)
    return None


def _line(name: str, entry: Entry) -> str | None:
    """One indented line of what an integrator or model family declares (else ``None``)."""
    if isinstance(entry, IntegratorEntry):
        caps = ", ".join(entry.capabilities.names()) or "-"
        return f"        {name} (order {entry.order}, {entry.family or '-'}): {caps}"
    if isinstance(entry, ModelFamily):
        line = f"        {name}: {', '.join(entry.models)} (cheapest first)"
        return line + (f"; reads {', '.join(entry.reads)}" if entry.reads else "")
    return None


def main(args: argparse.Namespace) -> int:
    """List plugins; failed and blocked ones are shown with the reason, warnings (unknown hook
    implementations, a plugin API version that does not match) under their plugin; never
    fatal. The first line names this poissonkit's plugin API version."""
    from poissonkit.plugin import entries, plugin_reports
    from poissonkit.plugin.hookspecs import PLUGIN_API_VERSION

    reports = plugin_reports()

    def registered(kind: str, names: list[str]) -> list[tuple[str, Entry]]:
        found = entries(kind)
        return [(n, found[n]) for n in names if n in found]

    if args.json:
        listed = []
        for r in reports:
            item = dict(r.__dict__)
            item["details"] = {}
            for kind, names in sorted(r.contributions.items()):
                shown = {n: d for n, e in registered(kind, names)
                         if (d := details(kind, e)) is not None}
                if shown:
                    item["details"][kind] = shown
            listed.append(item)
        print(json.dumps(listed, indent=2))
        return 0
    print(f"plugin API {PLUGIN_API_VERSION}")
    for r in reports:
        head = f"{r.name} {r.version} ({r.source}) [plugin API {r.api}]"
        if r.status != "ok":
            print(f"{head}  [{r.status.upper()}] {r.error}")
            continue
        print(head + (f"  [{len(r.warnings)} WARNING{'S' if len(r.warnings) > 1 else ''}]"
                      if r.warnings else ""))
        for w in r.warnings:
            print(f"    warning: {w}")
        for kind, names in sorted(r.contributions.items()):
            print(f"    {kind}: {', '.join(names)}")
            for name, entry in registered(kind, names):
                line = _line(name, entry) if details(kind, entry) is not None else None
                if line is not None:
                    print(line)
    from poissonkit.numerics.solve_options import options_text

    print(options_text())
    return 0
