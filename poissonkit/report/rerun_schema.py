"""What ``poissonkit run --from-summary`` accepts from a ``summary.json``: one schema.

A summary may have been edited by hand or come from elsewhere, so it is user input. Its
``options`` must be options of ``run`` (an unknown key is refused), each of the type the
command's parser gives it (``float`` options: finite numbers; ``int``: integers; flags: JSON
``true``/``false`` only — ``"no"`` is not false; text: strings without NUL; repeatable options:
lists of strings). Its ``scene_source`` must be of a known ``kind``: ``"file"`` with the
scene's ``text`` and a ``sha256`` that matches it, and a ``name`` that is a plain file name
(a string of 1–255 characters, no NUL, no folder separator, not ``.`` or ``..``), or
``"registered"`` with a scene ``name`` (a string or ``null``). The copy of the scene text in
the summary is what is run again, never the original path.

The option types come from the command's own parser (:func:`schema_of`), so the schema cannot
drift from the options ``run`` has.
"""

from __future__ import annotations

import argparse
import hashlib
import math
from collections.abc import Mapping
from dataclasses import dataclass

from poissonkit.errors import InputError

#: Longest scene name accepted (a file name on every common file system).
MAX_NAME = 255
SCENE_KINDS = ("file", "registered")


@dataclass(frozen=True)
class OptionType:
    """The JSON type of one option: ``kind`` is ``"float"``, ``"int"``, ``"bool"``, ``"str"``
    or ``"strlist"``; ``nullable``: ``null`` is accepted (an option without a default)."""

    kind: str
    nullable: bool


def schema_of(parser: argparse.ArgumentParser, extra: Mapping[str, OptionType] = {}
              ) -> dict[str, OptionType]:
    """The type of every option of ``parser`` (by destination), plus ``extra``."""
    out: dict[str, OptionType] = dict(extra)
    for action in parser._actions:  # argparse has no public list of its actions
        if action.dest in ("help", argparse.SUPPRESS):
            continue
        if isinstance(action, (argparse._StoreTrueAction, argparse._StoreFalseAction)):
            out[action.dest] = OptionType("bool", False)
        elif isinstance(action, argparse._AppendAction):
            out[action.dest] = OptionType("strlist", False)
        elif action.type in (float, int):
            out[action.dest] = OptionType(action.type.__name__, True)
        else:
            out[action.dest] = OptionType("str", True)
    return out


def _check_value(key: str, value: object, kind: OptionType) -> object:
    where = f"--from-summary: option {key!r}"
    if value is None:
        if kind.nullable:
            return None
        raise InputError(f"{where} must not be null")
    if kind.kind == "bool":
        if not isinstance(value, bool):
            raise InputError(f"{where} must be true or false, got {value!r}")
    elif kind.kind == "float":
        if isinstance(value, bool) or not isinstance(value, (int, float)) or \
                not math.isfinite(float(value)):
            raise InputError(f"{where} must be a finite number, got {value!r}")
        return float(value)
    elif kind.kind == "int":
        if isinstance(value, bool) or not isinstance(value, int):
            raise InputError(f"{where} must be an integer, got {value!r}")
    elif kind.kind == "strlist":
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise InputError(f"{where} must be a list of strings, got {value!r}")
        for v in value:
            _check_text(where, v)
    else:
        if not isinstance(value, str):
            raise InputError(f"{where} must be a string, got {value!r}")
        _check_text(where, value)
    return value


def _check_text(where: str, text: str) -> None:
    if "\x00" in text:
        raise InputError(f"{where} holds a NUL character")
    if len(text) > 4096:
        raise InputError(f"{where} is {len(text)} characters long; at most 4096")


def check_options(options: object, schema: Mapping[str, OptionType]) -> dict[str, object]:
    """The summary's ``options``, each checked against ``schema``.

    Raises
    ------
    InputError
        ``options`` is not an object, has a key ``schema`` does not know, or a value of the
        wrong type; the message names the key.
    """
    if not isinstance(options, dict):
        raise InputError("--from-summary: the summary has no 'options' object (written by a "
                         "poissonkit without provenance, or edited); run the scene again by "
                         "hand")
    unknown = sorted(str(k) for k in options if k not in schema)
    if unknown:
        raise InputError(f"--from-summary: unknown option(s) {', '.join(map(repr, unknown))}; "
                         f"`poissonkit run --help` lists the options")
    return {k: _check_value(k, v, schema[k]) for k, v in options.items()}


def check_scene_name(name: object, where: str = "--from-summary: scene_source.name") -> str:
    """``name`` if it is a plain file name (see the module docstring), else :class:`InputError`."""
    if not isinstance(name, str):
        raise InputError(f"{where} must be a string, got {name!r}")
    if not name or len(name) > MAX_NAME:
        raise InputError(f"{where} must be 1 to {MAX_NAME} characters, got {len(name)}")
    if "\x00" in name or "/" in name or "\\" in name or name in (".", ".."):
        raise InputError(f"{where} must be a plain file name (no NUL, no folder separator, "
                         f"not '.' or '..'), got {name[:40]!r}")
    return name


def check_scene_source(source: object) -> dict[str, object]:
    """The summary's ``scene_source``, checked (see the module docstring).

    Returns
    -------
    dict
        ``{"kind": "file", "name": ..., "text": ...}`` or ``{"kind": "registered", "name": ...}``.
    """
    if not isinstance(source, dict):
        raise InputError("--from-summary: the summary has no 'scene_source' object; run the "
                         "scene again by hand")
    kind = source.get("kind")
    if kind not in SCENE_KINDS:
        raise InputError(f"--from-summary: scene_source.kind must be one of "
                         f"{', '.join(SCENE_KINDS)}, got {kind!r}")
    if kind == "registered":
        name = source.get("name")
        if name is not None:
            check_scene_name(name)
        return {"kind": kind, "name": name}
    text = source.get("text")
    if not isinstance(text, str):
        raise InputError("--from-summary: scene_source.text (the scene's copy) must be a string")
    digest = source.get("sha256")
    actual = hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()
    if digest != actual:
        raise InputError("--from-summary: scene_source.sha256 does not match the scene text "
                         "(the copy was changed); refusing to run it")
    name = source.get("name", "scene.toml")
    return {"kind": kind, "name": check_scene_name(name), "text": text}
