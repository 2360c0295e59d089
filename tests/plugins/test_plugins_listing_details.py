"""``poissonkit plugins`` shows what the integrator and model-family registries declare.

Truth: what the integrators are documented to do (a scipy method neither checkpoints nor needs
kernels; Wisdom–Holman needs point masses; the splittings need exact kinetic/potential flows)
and the magnets family's documented models and the body quantities its estimate reads.
"""

from __future__ import annotations

import json
import re

from poissonkit.cli import main as cli_main


def _plugin_block(out: str, name: str) -> str:
    return re.split(r"\n\S", out.split(f"\n{name} ", 1)[1], maxsplit=1)[0]


def test_integrators_are_listed_with_order_family_and_capabilities(capsys):
    assert cli_main(["plugins"]) == 0
    block = _plugin_block(capsys.readouterr().out, "core-integrators")
    lines = {ln.split()[0]: ln for ln in block.splitlines() if ln.startswith(" " * 8)}
    # the name line is unchanged and every listed integrator gets its own line
    names = re.search(r"^    integrator: (.*)$", block, re.MULTILINE).group(1).split(", ")
    assert sorted(lines) == sorted(names)
    assert lines["dop853"].strip() == "dop853 (order 8, scipy): events, adaptive"
    wh = lines["wisdom_holman"]
    assert "(order 2, hierarchical)" in wh and "point_masses_only" in wh and "checkpoint" in wh
    assert "needs_splitting" in lines["splitting4"] and "needs_splitting" not in wh


def test_model_families_are_listed_with_their_models(capsys):
    assert cli_main(["plugins"]) == 0
    block = _plugin_block(capsys.readouterr().out, "magnets")
    assert "    model_family: magnets\n" in block
    line = next(ln for ln in block.splitlines() if ln.startswith("        magnets: "))
    models = line.split(": ", 1)[1].split(" (cheapest first)")[0].split(", ")
    assert models[0] == "dipole" and set(models) >= {"dipole", "dumbbell", "cylinder"}
    assert line.endswith("; reads radius, length")


def test_json_carries_the_same_details(capsys):
    assert cli_main(["plugins", "--json"]) == 0
    listed = {r["name"]: r for r in json.loads(capsys.readouterr().out)}
    rk45 = listed["core-integrators"]["details"]["integrator"]["rk45"]
    assert {k: v for k, v in rk45.items() if k != "options"} == {
        "order": 5, "family": "scipy", "capabilities": ["events", "adaptive"]}
    assert {o["name"] for o in rk45["options"]} >= {"atol", "max_step"}
    family = listed["magnets"]["details"]["model_family"]["magnets"]
    assert family["models"][0] == "dipole" and family["reads"] == ["radius", "length"]
    assert listed["nbody"]["details"] == {}  # nothing beyond names to show


def test_integrator_options_are_listed_with_types_defaults_and_choices(capsys):
    """Truth: the Blanes et al. (2013) tables wisdom_holman offers, as named in docs/numerics.md."""
    assert cli_main(["plugins"]) == 0
    text = capsys.readouterr().out
    assert "integrator options (--option NAME=VALUE" in text
    assert re.search(r"table \(str; default ''; one of .*'10_6_4'", text)
    assert cli_main(["plugins", "--json"]) == 0
    listed = json.loads(capsys.readouterr().out)
    core = next(p for p in listed if p["name"] == "core-integrators")
    options = {o["name"]: o for o in core["details"]["integrator"]["wisdom_holman"]["options"]}
    assert set(options) == {"stages", "table", "correctors"}
    assert {"10_4", "8_6_4", "10_6_4", "h8_4_4", "h8_6_4", "h10_6_4"} <= set(
        options["table"]["choices"])
    assert options["stages"]["default"] == 1 and options["stages"]["type"] == "int"
