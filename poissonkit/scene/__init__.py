"""Scenes: TOML schema and loader, run building, and the model-fidelity planner.

``load_scene(path) -> Scene`` reads and validates a scene file (``docs/scenes.md``);
``build_run(scene) -> RunSpec`` turns it into what ``poissonkit run`` integrates.
:mod:`poissonkit.scene.planner` chooses per pair the cheapest adequate magnet model.
"""

from poissonkit.scene.build import build_run, scene_graph
from poissonkit.scene.loader import load_scene, loads_scene
from poissonkit.scene.schema import (
    PairDecl,
    PlannerSpec,
    RunSettings,
    Scene,
    scene_from_mapping,
)

__all__ = [
    "PairDecl", "PlannerSpec", "RunSettings", "Scene", "build_run", "load_scene", "loads_scene",
    "scene_from_mapping", "scene_graph",
]
