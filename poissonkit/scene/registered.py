"""Scenes runnable by name: registered by plugins, or scene files shipped with the package.

The core knows no scene by name: a plugin registers a :class:`~poissonkit.plugin.SceneEntry`
(the magnets plugin registers ``seed000`` and flags it as the default), and the commands turn
it into a :class:`~poissonkit.numerics.runspec.RunSpec` here. The scene files under
``poissonkit/scene/shipped/`` (package data) run by their stem (``poissonkit run two_magnets``).
:func:`scene_catalog` lists both kinds (``poissonkit scenes``); :func:`resolve_scene` turns a
command-line ``SCENE`` into a file or a registered name.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Literal

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


@dataclass(frozen=True)
class SceneListing:
    """One scene runnable by name.

    Attributes
    ----------
    name
        What ``poissonkit run NAME`` takes.
    kind
        ``"registered"`` (a plugin's :class:`~poissonkit.plugin.SceneEntry`) or ``"file"`` (a
        scene file shipped with the package).
    description
        One line: the entry's doc string, or the file's ``description``.
    source
        The plugin that registered it, or the file's path.
    default
        The scene ``poissonkit run`` uses without an argument.
    parameters
        What ``--param NAME=VALUE`` sets (registered scenes): one mapping per parameter with
        ``name``, ``type``, ``unit``, ``default`` (``None``: optional, the scene chooses) and
        ``doc``.
    """

    name: str
    kind: Literal["registered", "file"]
    description: str
    source: str
    default: bool = False
    parameters: list[dict[str, object]] = field(default_factory=list)


def scene_parameters(entry: object) -> list[dict[str, object]]:
    """The parameters a registered scene entry declares, as :attr:`SceneListing.parameters`."""
    from poissonkit.plugin.contributions import Entry

    if not isinstance(entry, Entry):
        return []
    return [{"name": p.name, "type": p.type, "unit": p.unit,
             "default": list(p.default) if isinstance(p.default, tuple) else p.default,
             "doc": p.doc} for p in entry.params]


def _first_line(text: str) -> str:
    lines = text.strip().splitlines()
    return lines[0].strip() if lines else ""


def scene_catalog() -> list[SceneListing]:
    """Every scene runnable by name: registered scenes first, then shipped scene files.

    Returns
    -------
    list of SceneListing
        Sorted by name within each kind.
    """
    from poissonkit.plugin.contributions import SceneEntry
    from poissonkit.plugin.manager import entries, providers
    from poissonkit.scene.loader import scene_description, shipped_scenes

    # providers, not plugin_reports: the listing loads only the plugins that register scenes
    owner = providers("scene")
    out = [SceneListing(name, "registered", _first_line(e.doc), owner.get(name, ""),
                        isinstance(e, SceneEntry) and e.default, scene_parameters(e))
           for name, e in sorted(entries("scene").items())]
    out += [SceneListing(name, "file", scene_description(path), str(path))
            for name, path in shipped_scenes().items()]
    return out


def resolve_scene(arg: str) -> Path | str:
    """What a command-line ``SCENE`` names.

    Parameters
    ----------
    arg
        A path to a scene file, a registered scene's name, or a shipped scene file's name
        (with or without ``.toml``), tried in this order.

    Returns
    -------
    Path or str
        The scene file (a ``Path``), or the registered scene's name (a ``str``).

    Raises
    ------
    SceneError
        If ``arg`` is none of these; the message lists the registered scenes and the shipped
        scene files.
    """
    from poissonkit.plugin import names
    from poissonkit.scene.loader import shipped_scenes

    path = Path(arg)
    if path.is_file():
        return path
    registered = names("scene")
    if arg in registered:
        return arg
    shipped = shipped_scenes()
    stem = arg.removesuffix(".toml")
    if stem in shipped and path.parent == Path("."):
        return shipped[stem]
    if path.exists():
        raise SceneError(f"scene {arg!r} is not a file")
    from poissonkit.plugin.registry import failed_plugins

    failed = "".join(f"; plugin {n!r} failed to load: {e}" for n, e in failed_plugins())
    raise SceneError(f"no scene file or scene named {arg!r}; registered scenes: "
                     f"{', '.join(registered) or '(none)'}; shipped scene files: "
                     f"{', '.join(shipped) or '(none)'}{failed} (see `poissonkit scenes`)")


def scene_outcome(spec: RunSpec, t: object, y: object, events: object
                  ) -> Mapping[str, object] | None:
    """What a finished run of a registered scene came to (its entry's ``outcome``, e.g. the
    Levitron's fate and its contact with the base), or ``None`` for scenes without one.

    Parameters
    ----------
    spec
        The run (its ``name`` is the registered scene's).
    t, y, events
        Saved times and states (internal units) and the event records of the run.
    """
    from poissonkit.plugin.contributions import SceneEntry
    from poissonkit.plugin import entries

    entry = entries("scene").get(spec.name)
    if not isinstance(entry, SceneEntry) or entry.outcome is None:
        return None
    return dict(entry.outcome(spec, t, y, events))
