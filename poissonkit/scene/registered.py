"""Runs of scenes registered by plugins (``poissonkit run NAME``, ``poissonkit run``).

The core knows no scene by name: a plugin registers a :class:`~poissonkit.plugin.SceneEntry`
(the magnets plugin registers ``seed000`` and flags it as the default), and the commands turn
it into a :class:`~poissonkit.numerics.runspec.RunSpec` here.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

from poissonkit.errors import SceneError

if TYPE_CHECKING:
    from poissonkit.numerics.runspec import RunSpec


def registered_run(name: str | None, options: Mapping[str, object] | None = None
                   ) -> tuple[RunSpec, set[str]]:
    """The run of a registered scene, and which options the scene consumed.

    Parameters
    ----------
    name
        Registry name of the scene; ``None`` for the default scene
        (:func:`poissonkit.plugin.default_scene`).
    options
        Run options (``method``, ``step``, ``tol``, ``periods``, ``duration``, scene-specific
        ones ...). ``None`` values are ignored; options the entry does not declare are left to
        the caller (e.g. applied to the returned run).

    Returns
    -------
    tuple of (RunSpec, set of str)
        The run and the names of the options handed to the scene.

    Raises
    ------
    UnknownNameError
        If no scene is registered as ``name`` (the message lists the available ones).
    SceneError
        If the scene's ``load`` returns neither a scene nor a run.
    """
    from poissonkit.numerics.runspec import RunSpec
    from poissonkit.plugin.registry import default_scene, scene
    from poissonkit.scene.build import build_run
    from poissonkit.scene.schema import Scene

    entry = default_scene() if name is None else scene(name)
    declared = {p.name for p in entry.params}
    given = {k: v for k, v in (options or {}).items() if v is not None and k in declared}
    made = entry.load(**entry.resolve_params(given))
    if isinstance(made, Scene):
        made = build_run(made)
    if not isinstance(made, RunSpec):
        raise SceneError(f"scene {entry.name!r}: load() returned {type(made).__name__}, "
                         "expected a Scene or a RunSpec")
    return made, set(given)
