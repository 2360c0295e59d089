"""Scenes: TOML schema and loader, run building, and the model-fidelity planner.

``load_scene(path) -> Scene`` reads and validates a scene file (``docs/scenes.md``);
``build_scene(scene) -> BuiltScene`` turns it into a system, initial state and internal units
(the one path of runs and sweeps); ``build_run(scene) -> RunSpec`` into what ``poissonkit run``
integrates. :mod:`poissonkit.scene.limits` sets how large a scene may be.
:mod:`poissonkit.scene.planner` chooses per pair the cheapest adequate magnet model.

The names below are imported on first use (PEP 562), so that importing a light submodule
(``poissonkit.scene.loader`` for ``poissonkit scenes``) does not load the numerics (numba).
"""

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from poissonkit.scene.build import BuiltScene, build_run, build_scene, scene_graph
    from poissonkit.scene.loader import load_scene, loads_scene
    from poissonkit.scene.schema import (PairDecl, PlannerSpec, RunSettings, Scene,
                                         scene_from_mapping)

#: name -> module that defines it
_LAZY: dict[str, str] = {
    "BuiltScene": "poissonkit.scene.build", "build_run": "poissonkit.scene.build",
    "build_scene": "poissonkit.scene.build", "scene_graph": "poissonkit.scene.build",
    "load_scene": "poissonkit.scene.loader", "loads_scene": "poissonkit.scene.loader",
    "PairDecl": "poissonkit.scene.schema", "PlannerSpec": "poissonkit.scene.schema",
    "RunSettings": "poissonkit.scene.schema", "Scene": "poissonkit.scene.schema",
    "scene_from_mapping": "poissonkit.scene.schema",
}

__all__ = [
    "BuiltScene", "PairDecl", "PlannerSpec", "RunSettings", "Scene", "build_run", "build_scene",
    "load_scene", "loads_scene",
    "scene_from_mapping", "scene_graph",
]


def __getattr__(name: str) -> object:
    from poissonkit._lazy import load

    return load(globals(), _LAZY, name)


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
