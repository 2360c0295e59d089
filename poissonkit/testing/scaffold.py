"""``new_plugin``: write a plugin package from the template (``poissonkit new-plugin NAME``).

The template (``poissonkit/testing/template``, package data) holds a ``pyproject.toml`` with
the entry point, a hooks module with a pair potential reading a body attribute and a scene,
the scene's TOML file, and tests: the kit's checks of every contribution and the plugin's own
truth. The generated package installs and passes its tests as written.
"""

from __future__ import annotations

import re
from importlib import resources
from pathlib import Path

from poissonkit.errors import InputError

#: Placeholders of the template files; ``__package__`` in a path is the package folder.
SUFFIX = ".tmpl"
_NAME = re.compile(r"[a-z][a-z0-9_]{0,39}")


def _values(name: str) -> dict[str, str]:
    from poissonkit._version import __version__
    from poissonkit.plugin.hookspecs import PLUGIN_API_VERSION

    base = re.match(r"\d+(\.\d+)*", __version__)
    return {"{{name}}": name, "{{package}}": f"poissonkit_{name}",
            "{{dist}}": f"poissonkit-{name.replace('_', '-')}", "{{api}}": PLUGIN_API_VERSION,
            "{{poissonkit_version}}": base.group(0) if base else "0"}


def _fill(text: str, values: dict[str, str]) -> str:
    for key, value in values.items():
        text = text.replace(key, value)
    return text


def new_plugin(name: str, directory: str | Path = ".") -> Path:
    """Write the plugin package ``poissonkit-NAME`` into ``directory``.

    Parameters
    ----------
    name
        The plugin's name: lower-case letters, digits and ``_``, starting with a letter (it
        names the entry point, the package ``poissonkit_NAME`` and its contributions).
    directory
        Where the package folder is created.

    Returns
    -------
    Path
        The new package folder.

    Raises
    ------
    InputError
        A malformed name, or a folder that exists already.
    """
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise InputError(f"plugin name must be lower-case letters, digits and '_', starting with "
                         f"a letter (at most 40 characters), got {name!r}")
    values = _values(name)
    target = Path(directory) / values["{{dist}}"]
    if target.exists():
        raise InputError(f"{target} exists already; choose another name or --dir")
    root = resources.files("poissonkit.testing") / "template"
    written = []
    for source, parts in _walk(root, ()):
        rel = [values["{{package}}"] if p == "__package__" else p for p in parts]
        rel[-1] = rel[-1][: -len(SUFFIX)]
        path = target.joinpath(*rel)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(_fill(source.read_text(encoding="utf-8"), values), encoding="utf-8")
        written.append(path)
    if not written:  # pragma: no cover - a broken installation
        raise InputError("the plugin template is missing from this poissonkit installation")
    return target


def _walk(folder, parts: tuple[str, ...]):
    """``(file, path parts)`` of every template file under ``folder``."""
    for item in sorted(folder.iterdir(), key=lambda t: t.name):
        if item.is_dir():
            if item.name != "__pycache__":
                yield from _walk(item, (*parts, item.name))
        elif item.name.endswith(SUFFIX):
            yield item, (*parts, item.name)
