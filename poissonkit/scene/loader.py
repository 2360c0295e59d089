"""Reading scene files (TOML) into validated :class:`~poissonkit.scene.schema.Scene` objects."""

from __future__ import annotations

from pathlib import Path

import tomllib

from poissonkit.errors import SceneError
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
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise SceneError(f"scene file {str(p)!r} does not exist") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(f"cannot read scene file {str(p)!r}: {exc}") from None
    return loads_scene(text, source=str(p))


def loads_scene(text: str, source: str = "") -> Scene:
    """Validate a scene given as TOML text (see :func:`load_scene`)."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        where = f" in {source!r}" if source else ""
        raise SceneError(f"invalid TOML{where}: {exc}") from None
    return scene_from_mapping(data, source=source)
