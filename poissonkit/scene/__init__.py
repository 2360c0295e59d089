"""Scenes: TOML schema and loader, run building, and the model-fidelity planner.

``load_scene(path) -> Scene`` reads and validates a scene file (``docs/scenes.md``);
``build_scene(scene) -> BuiltScene`` turns it into a system, initial state and internal units
(the one path of runs and sweeps); ``build_run(scene) -> RunSpec`` into what ``poissonkit run``
integrates. :mod:`poissonkit.scene.limits` sets how large a scene may be.
:mod:`poissonkit.scene.planner` chooses per pair the cheapest adequate magnet model.
"""

from poissonkit.scene.build import BuiltScene, build_run, build_scene, scene_graph
from poissonkit.scene.loader import load_scene, loads_scene
from poissonkit.scene.schema import PairDecl, PlannerSpec, RunSettings, Scene, scene_from_mapping

__all__ = [
    "BuiltScene", "PairDecl", "PlannerSpec", "RunSettings", "Scene", "build_run", "build_scene",
    "load_scene", "loads_scene",
    "scene_from_mapping", "scene_graph",
]
