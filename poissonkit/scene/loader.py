"""Reading scene files (TOML) into validated :class:`~poissonkit.scene.schema.Scene` objects,
and the scene files shipped with the package (``poissonkit/scene/shipped/*.toml``, runnable by name)."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from importlib import resources
from pathlib import Path

from poissonkit.errors import InputError, SceneError, UnknownNameError
from poissonkit.input_limits import loads_toml, read_text
from poissonkit.scene.schema import Scene, scene_from_mapping


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file.

    Parameters
    ----------
    path
        A TOML file following ``docs/scenes.md`` (SI units).

    Returns
    -------
    Scene
        Frozen and validated; turn it into a run with :func:`poissonkit.scene.build_run`.

    Raises
    ------
    SceneError
        If the file is missing, is not valid TOML, or a field is invalid (the message names
        the field, e.g. ``bodies[1].mass: must be > 0``).
    """
    p = Path(path)
    return loads_scene(read_text(p, "scene file", SceneError), source=str(p))


def loads_scene(text: str, source: str = "") -> Scene:
    """Validate a scene given as TOML text (see :func:`load_scene`).

    The text is parsed within the limits of :mod:`poissonkit.input_limits` (size, nesting
    depth, digits per number, valid Unicode); past them a :class:`SceneError` names the limit.
    """
    from poissonkit.plugin.manager import plugins_token

    key = (text, source, plugins_token())  # the same plugins: a reset makes a new token
    if _reuse[0] and key in _last:
        return _last[key]
    data = loads_toml(text, repr(source) if source else "scene", SceneError)
    scene = scene_from_mapping(data, source=source)
    if _reuse[0]:
        _last.clear()
        _last[key] = scene  # frozen and validated: safe to hand out twice
    return scene


#: the last scene validated inside :func:`reuse_validated`, by (text, source, plugins)
_last: dict[tuple[str, str, object], Scene] = {}
#: depth of nested :func:`reuse_validated` blocks
_reuse = [0]


@contextmanager
def reuse_validated() -> Iterator[None]:
    """Within this block, the same scene text is validated once.

    ``poissonkit run`` reads its scene file twice, to build the run and for the provenance of
    its summary; validating a 10⁵-body assembly builds and checks every body, so the second
    read reuses the first one's :class:`Scene`. Outside the block every call validates anew
    (what validation checks may change between calls: plugins, available memory).
    """
    _reuse[0] += 1
    try:
        yield
    finally:
        _reuse[0] -= 1
        if not _reuse[0]:
            _last.clear()


def shipped_scenes() -> dict[str, Path]:
    """The scene files installed with poissonkit (package data), by name (the file's stem).

    Returns
    -------
    dict of str to Path
        E.g. ``{"two_magnets": .../poissonkit/scene/shipped/two_magnets.toml, ...}``, sorted by name.
    """
    folder = resources.files("poissonkit") / "scene" / "shipped"
    if not folder.is_dir():
        return {}
    found = {Path(str(f)).stem: Path(str(f)) for f in folder.iterdir()
             if f.name.endswith(".toml") and f.is_file()}
    return dict(sorted(found.items()))


def shipped_scene(name: str) -> Path:
    """The path of the shipped scene file ``name`` (e.g. ``"two_magnets"``).

    Raises
    ------
    UnknownNameError
        If no shipped scene file has that name (the message lists the shipped ones).
    """
    found = shipped_scenes()
    if name not in found:
        raise UnknownNameError("shipped scene", name, found)
    return found[name]


def scene_description(path: str | Path) -> str:
    """The one-line ``description`` of a scene file (``""`` if it has none or cannot be read).

    Only the TOML is parsed (no validation), so listing scenes stays cheap.
    """
    try:
        data = loads_toml(read_text(path, "scene file"), str(path))
    except InputError:
        return ""
    text = data.get("description", "")
    return text.strip().splitlines()[0] if isinstance(text, str) and text.strip() else ""
