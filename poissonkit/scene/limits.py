"""How large a scene may be: a limit set by the memory its set-up needs.

A scene is refused before it is built when the estimated memory of building it exceeds
:data:`MEMORY_FRACTION` of the memory available on this machine (``docs/scenes.md``, "How many
bodies"). The estimate counts :data:`BYTES_PER_BODY` for every body (its validated table, graph
node, body model and numerics tables) and :data:`BYTES_PER_PAIR` for every pair the set-up
holds (graph edge and resolved parameters of each pair of an ``pairs = "all"`` scene, or of each
listed pair). Both constants were measured on all-pairs gravity scenes of a few hundred bodies
(peak traced memory divided by the counts) and rounded up.
"""

from __future__ import annotations

import os

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
