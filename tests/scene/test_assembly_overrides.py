"""Assemblies: per-body overrides by index or name pattern, the spin shorthand, and the
parameter tables of docs/scenes.md generated from the registry.

Truth used: the definition ``m = spin nu/|nu|`` of the sweep paths' shorthand, computed by hand
from the ring's axes; the registry's ``Param`` declarations for the docs.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from poissonkit.errors import SceneError
from poissonkit.scene.assembly_docs import BEGIN, END, assemblies_markdown, replace_section
from poissonkit.scene.build import scene_graph
from poissonkit.scene.schema import scene_from_mapping

ROOT = Path(__file__).resolve().parents[2]


def _ring(**assembly) -> dict:
    return {"name": "ring_of_tops",
            "assembly": {"name": "ring", "params": {"n": 6, "ring_radius": 0.05, "mass": 1e-3,
                                                    "alpha": 1e6, "moment": 0.1},
                         **assembly},
            "run": {"duration": 0.01, "step": 1e-4}}


def _nodes(data: dict) -> list[dict]:
    G = scene_graph(scene_from_mapping(data), edges=False)
    return [G.nodes[n] for n in G.nodes]


def test_spin_for_every_body_then_per_body_by_index_and_by_name():
    nodes = _nodes(_ring(overrides={"spin": 1e-6},
                         body=[{"index": [0, 3], "spin": -2e-6},
                               {"match": "b5", "fixed": True}]))
    for k, attrs in enumerate(nodes):
        nu = np.array(attrs["nu"]) / np.linalg.norm(attrs["nu"])
        spin = -2e-6 if k in (0, 3) else 1e-6
        np.testing.assert_allclose(attrs["m"], spin * nu, rtol=0, atol=1e-21)
        assert bool(attrs.get("fixed", False)) == (k == 5)


def test_a_name_pattern_selects_several_bodies():
    nodes = _nodes(_ring(body=[{"match": "b[12]", "moment": 0.2}]))
    assert [a["moment"] for a in nodes] == [0.1, 0.2, 0.2, 0.1, 0.1, 0.1]


@pytest.mark.parametrize("assembly, message", [
    ({"body": [{"index": 6, "fixed": True}]}, r"assembly.body\[0\].index: 6 is beyond"),
    ({"body": [{"match": "top*", "fixed": True}]}, "no body's name matches 'top\\*'"),
    ({"body": [{"fixed": True}]}, "index .* or match"),
    ({"body": [{"index": 1, "match": "b1"}]}, "give one"),
    ({"body": [{"index": 1, "colour": 3}]}, "colour: unknown key"),
    ({"overrides": {"spin": "fast"}}, "spin: must be a number"),
])
def test_bad_overrides_name_the_field(assembly, message):
    with pytest.raises(SceneError, match=message):
        _nodes(_ring(**assembly))


def test_spin_of_a_point_mass_is_refused():
    data = _ring(overrides={"spin": 1e-6})
    data["assembly"]["params"]["alpha"] = 0.0
    with pytest.raises(SceneError, match="not a top"):
        _nodes(data)


def test_assembly_parameters_in_docs_are_generated_from_the_registry():
    page = (ROOT / "docs" / "scenes.md").read_text(encoding="utf-8")
    assert BEGIN in page and END in page
    assert replace_section(page) == page, (
        "docs/scenes.md is stale: python -m poissonkit.scene.assembly_docs docs/scenes.md")
    text = assemblies_markdown()
    ring = text.split("#### `ring`")[1].split("####")[0]
    assert "`ring_radius` | float | m | required" in ring and "`spacing`" not in ring
    assert "`cluster_radius`" in text.split("#### `random_cluster`")[1]
