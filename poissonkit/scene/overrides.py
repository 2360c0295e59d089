"""Overrides of the bodies an assembly builds: for every body, or per body by index or name.

``[assembly] overrides = {...}`` applies body fields to every body; each
``[[assembly.body]]`` table applies its fields to the bodies it selects, after those, by
``index`` (an integer or a list of integers, in build order) or ``match`` (a name pattern with
``*`` and ``?``, as :func:`fnmatch.fnmatchcase`: ``"b1*"``). Besides every body field, both take
the ``spin`` shorthand of the sweep paths: the angular momentum ``m = spin nu / |nu|`` about the
body's own axis [kg m²/s, or the scene's units], for a top (``alpha`` or ``inertia``).
"""

from __future__ import annotations

import fnmatch
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from poissonkit.errors import SceneError

#: Keys of a ``[[assembly.body]]`` table that select bodies (the rest are body fields).
SELECTORS = ("index", "match")
#: The shorthand for the angular momentum about the body's axis.
SPIN = "spin"


@dataclass(frozen=True)
class BodyOverride:
    """One ``[[assembly.body]]`` table: which bodies (``indices`` or name ``pattern``) and the
    fields they get (``spin`` included)."""

    values: Mapping[str, Any] = field(default_factory=dict)
    indices: tuple[int, ...] | None = None
    pattern: str | None = None


def body_fields(raw: Any, where: str) -> dict[str, Any]:
    """Body fields of an override table (``spin`` included), each checked as the schema checks
    a body's."""
    from poissonkit.scene.schema import BODY_KEYS, _attribute, _body_keys, _number, _table

    table = dict(_table(raw, where))
    spin = table.pop(SPIN, None)
    _body_keys(table, where)
    for key in list(table):
        if key not in BODY_KEYS:
            table[key] = _attribute(table[key], f"{where}.{key}")
    if spin is not None:
        table[SPIN] = _number(spin, f"{where}.{SPIN}")
    return table


def per_body(raw: Any) -> tuple[BodyOverride, ...]:
    """The ``[[assembly.body]]`` tables."""
    if raw is None:
        return ()
    if not isinstance(raw, list):
        raise SceneError("assembly.body: must be an array of tables ([[assembly.body]])")
    out = []
    for k, item in enumerate(raw):
        where = f"assembly.body[{k}]"
        if not isinstance(item, Mapping):
            raise SceneError(f"{where}: must be a table, got {type(item).__name__}")
        given = [s for s in SELECTORS if s in item]
        if len(given) != 1:
            raise SceneError(f"{where}: select the bodies with index (a number or a list of "
                             "numbers) or match (a name pattern such as \"b1*\"): give one")
        indices = pattern = None
        if "index" in item:
            raw_index = item["index"]
            items = raw_index if isinstance(raw_index, list) else [raw_index]
            if not items or not all(isinstance(i, int) and not isinstance(i, bool) and i >= 0
                                    for i in items):
                raise SceneError(f"{where}.index: must be an integer >= 0 or a non-empty list "
                                 f"of them, got {raw_index!r}")
            indices = tuple(items)
        else:
            pattern = item["match"]
            if not isinstance(pattern, str) or not pattern:
                raise SceneError(f"{where}.match: must be a name pattern, got {pattern!r}")
        values = body_fields({k2: v for k2, v in item.items() if k2 not in SELECTORS}, where)
        out.append(BodyOverride(values, indices, pattern))
    return tuple(out)


def apply_overrides(nodes: list[dict[str, Any]], common: Mapping[str, Any],
                    bodies: tuple[BodyOverride, ...]) -> None:
    """Update the assembly's node attributes in place: ``common`` on every node, then each
    :class:`BodyOverride` on the nodes it selects; ``spin`` becomes ``m``.

    Raises
    ------
    SceneError
        An index beyond the assembly, a pattern no body's name matches, or a spin for a body
        without an axis.
    """
    spins: dict[int, tuple[float, str]] = {}
    if common:
        for k, attrs in enumerate(nodes):
            attrs.update({key: v for key, v in common.items() if key != SPIN})
            if SPIN in common:
                spins[k] = (float(common[SPIN]), "assembly.overrides.spin")
    names = [str(attrs.get("name", k)) for k, attrs in enumerate(nodes)]
    for j, override in enumerate(bodies):
        where = f"assembly.body[{j}]"
        if override.indices is not None:
            bad = [i for i in override.indices if i >= len(nodes)]
            if bad:
                raise SceneError(f"{where}.index: {bad[0]} is beyond the assembly's "
                                 f"{len(nodes)} bodies (0 … {len(nodes) - 1})")
            chosen = list(override.indices)
        else:
            assert override.pattern is not None
            chosen = [k for k, n in enumerate(names) if fnmatch.fnmatchcase(n, override.pattern)]
            if not chosen:
                raise SceneError(f"{where}.match: no body's name matches {override.pattern!r}; "
                                 f"names: {', '.join(names[:8])}{' …' if len(names) > 8 else ''}")
        for k in chosen:
            nodes[k].update({key: v for key, v in override.values.items() if key != SPIN})
            if SPIN in override.values:
                spins[k] = (float(override.values[SPIN]), f"{where}.spin")
    for k, (spin, where) in spins.items():
        attrs = nodes[k]
        nu = attrs.get("nu")
        if nu is None or (attrs.get("alpha") is None and attrs.get("inertia") is None):
            raise SceneError(f"{where}: body {names[k]!r} is not a top (no axis nu and alpha or "
                             "inertia), so it has no spin")
        axis = np.asarray(nu, dtype=float)
        norm = float(np.linalg.norm(axis))
        if norm == 0.0:
            raise SceneError(f"{where}: body {names[k]!r} has a zero axis")
        attrs["m"] = tuple(float(x) for x in spin * axis / norm)
