"""How large a scene may be: a limit set by the memory its set-up needs.

A scene is refused before it is built when the estimated memory of building it exceeds
:data:`MEMORY_FRACTION` of the memory available on this machine (``docs/scenes.md``, "How many
bodies"). The estimate counts :data:`BYTES_PER_BODY` for every body (its validated table, graph
node, body model and numerics tables) and :data:`BYTES_PER_PAIR` for every pair the set-up
holds (:func:`held_pairs`: graph edge and resolved parameters of each listed pair, or of every
pair of a scene whose pairs differ in more than what they read from the bodies; a scene whose
pairs are all alike holds none, it becomes one all-pairs interaction). Both constants were
measured on all-pairs gravity scenes of a few hundred bodies (peak traced memory divided by
the counts) and rounded up; ``docs/performance.md`` has the measured peaks up to 10⁵ bodies.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence

from poissonkit.errors import SceneError

#: Bytes one body costs while a scene is validated and built (measured, rounded up).
BYTES_PER_BODY = 8_192
#: Bytes one interacting pair costs while a scene is built (measured, rounded up).
BYTES_PER_PAIR = 2_048
#: Share of the available memory a scene's set-up may take.
MEMORY_FRACTION = 0.5
#: Memory assumed available where the operating system does not say [bytes].
FALLBACK_MEMORY = 4 * 2**30


class SceneTooLargeError(SceneError):
    """A scene whose set-up would need more memory than the limit allows."""


def available_memory() -> int:
    """Memory available to this process now [bytes] (physical pages not in use; the
    :data:`FALLBACK_MEMORY` where the system does not report them)."""
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return FALLBACK_MEMORY


def estimate_bytes(bodies: int, pairs: int) -> int:
    """Estimated memory [bytes] of setting up a scene of ``bodies`` bodies and ``pairs`` pairs."""
    return bodies * BYTES_PER_BODY + pairs * BYTES_PER_PAIR


def check_memory(bodies: int, pairs: int, where: str = "bodies",
                 available: int | None = None) -> int:
    """The estimate of :func:`estimate_bytes`, or an error if it exceeds the limit.

    Parameters
    ----------
    bodies, pairs
        Size of the scene.
    where
        Field the error message starts with.
    available
        Available memory [bytes] (default: :func:`available_memory`).

    Raises
    ------
    SceneTooLargeError
        If the estimate exceeds ``MEMORY_FRACTION * available``; the message gives both.
    """
    need = estimate_bytes(bodies, pairs)
    have = available_memory() if available is None else int(available)
    limit = MEMORY_FRACTION * have
    if need > limit:
        raise SceneTooLargeError(
            f"{where}: a scene of {bodies} bodies and {pairs} interacting pairs needs about "
            f"{need / 2**20:,.0f} MiB to set up, more than {MEMORY_FRACTION:g} of the "
            f"{have / 2**20:,.0f} MiB available; use fewer bodies, pairs = \"listed\", or a "
            "machine with more memory (docs/scenes.md, \"How many bodies\")")
    return need


#: Body fields a magnet's parameters are derived from together (``moment`` from
#: ``magnetization`` and the cylinder, ``half_length`` from ``length``).
_MAGNET_FIELDS = ("moment", "magnetization", "radius", "length", "half_length")
#: Structural edges per body that an assembly with ``interactions = "neighbours"`` holds
#: (chains, rings and lattices at most three per site; a dense ``random_cluster`` may hold
#: more, which the estimate does not see).
NEIGHBOURS_PER_BODY = 3


def all_pairs_alike(potential: object, given: Mapping[str, object],
                    bodies: Sequence[Mapping[str, object]]) -> bool:
    """True if every pair of these bodies gets the same parameters of ``potential`` up to
    those it reads from each body (``body_params``): then the scene is built as one all-pairs
    interaction and holds no pair (the same test as
    :func:`poissonkit.scene.assembly.uniform_all_pairs`, on the raw tables).

    Parameters
    ----------
    potential
        The name of a registered pair potential (anything else: ``False``).
    given
        The scene's ``interactions.params``.
    bodies
        Body tables with ``[defaults]`` merged in.
    """
    from poissonkit.plugin.contributions import PairPotential
    from poissonkit.plugin.manager import entries

    entry = entries("potential").get(potential) if isinstance(potential, str) else None
    if not isinstance(entry, PairPotential) or not isinstance(given, Mapping):
        return False
    if any(b.get("fixed") is True for b in bodies):
        return False
    bound = {name for name, _attr, _which in entry.body_params}
    for param in entry.params:
        name = param.name
        if name in given or name in bound or name[-1:] not in ("1", "2"):
            continue
        base = name[:-1]
        fields = _MAGNET_FIELDS if base in _MAGNET_FIELDS else (base,)
        first = [bodies[0].get(f) for f in fields] if bodies else []
        if any([b.get(f) for f in fields] != first for b in bodies):
            return False
    return True


def held_pairs(bodies: int, data: Mapping[str, object],
               tables: Sequence[Mapping[str, object]] | None = None,
               assembly: Mapping[str, object] | None = None) -> int:
    """Pairs a scene of ``bodies`` bodies holds while it is built (for :func:`check_memory`).

    The listed ones with ``interactions.pairs = "listed"``; none when every pair interacts
    through one potential alike (:func:`all_pairs_alike`: built as one all-pairs interaction);
    at most :data:`NEIGHBOURS_PER_BODY` per body for an assembly of neighbour pairs; otherwise
    every pair.

    Parameters
    ----------
    bodies
        Number of bodies.
    data
        The scene mapping (its ``interactions`` and ``planner``).
    tables
        The body tables with ``[defaults]`` merged in (for ``[[bodies]]``).
    assembly
        The resolved parameters of the scene's assembly (for ``[assembly]``; its bodies share
        one template, so only its ``interactions`` and default ``potential`` matter).
    """
    every = bodies * (bodies - 1) // 2
    inter = data.get("interactions", {})
    if not isinstance(inter, Mapping):
        return every
    listed = inter.get("pair", [])
    n_listed = len(listed) if isinstance(listed, list) else 0
    if inter.get("pairs", "all") == "listed":
        return n_listed
    given = inter.get("params", {})
    if assembly is not None:
        joins = assembly.get("interactions")
        if joins == "neighbours":
            return NEIGHBOURS_PER_BODY * bodies + n_listed
        if joins != "complete" or n_listed or "planner" in data:
            return every
        table = data.get("assembly", {})
        overrides = table.get("overrides", {}) if isinstance(table, Mapping) else {}
        template = dict(overrides) if isinstance(overrides, Mapping) else {}
        alike = all_pairs_alike(inter.get("potential", assembly.get("potential")), given,
                                [template])
        return 0 if alike else every
    if n_listed or "planner" in data or tables is None:
        return every
    return 0 if all_pairs_alike(inter.get("potential"), given, tables) else every
