"""What kind of scene a run is, for choosing its figures.

One function, :func:`scene_kind`, reads the system (how many bodies, whether external fields
act on them, whether they are point masses under gravity with one dominant mass) and names one
of :data:`KINDS`. The figure registry (:mod:`poissonkit.report.figures`) keys its entries by
these names.

>>> from poissonkit.numerics.nbody import Body, NBodySystem
>>> scene_kind(NBodySystem([Body("a", 1.0), Body("b", 1.0), Body("c", 1.0)]))
'nbody'
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol, runtime_checkable

from poissonkit.contracts import HasBodies, HasExternalFields, HasGravity
from poissonkit.errors import PoissonkitError
from poissonkit.traits import offers

__all__ = ["DOMINANCE", "IN_FIELD", "KINDS", "NBODY", "PLANETARY", "TWO_BODY", "scene_kind"]

TWO_BODY = "two_body"
NBODY = "nbody"
IN_FIELD = "in_field"
PLANETARY = "planetary"
#: Every kind, in the order of :func:`scene_kind`'s rules.
KINDS: tuple[str, ...] = (IN_FIELD, PLANETARY, TWO_BODY, NBODY)
#: A mass is dominant when it is at least this many times every other mass (the Sun is 1047
#: Jupiters; the two stars of a binary are not dominant over each other).
DOMINANCE = 100.0


@runtime_checkable
class _Massive(Protocol):
    """A body with a mass (an N-body :class:`~poissonkit.numerics.nbody.Body`)."""

    @property
    def mass(self) -> float: ...


def scene_kind(system: object, *, relative: bool = False) -> str:
    """The kind of scene ``system`` is.

    Rules, first match wins:

    1. ``"in_field"``: external fields act on the bodies (one or more bodies in fields: the
       Levitron, a magnet over a magpylib source, a top in gravity).
    2. ``"planetary"``: three or more point masses (no tops) under all-pairs gravity, one of
       them at least :data:`DOMINANCE` times heavier than every other.
    3. ``"two_body"``: two bodies, or the seed's centre-of-mass form (``relative``: only a
       relative position is known).
    4. ``"nbody"``: anything else with bodies.

    Parameters
    ----------
    system
        The integrated system (bodies read through :class:`~poissonkit.contracts.HasBodies`).
    relative
        True when the run has a two-body relative position (the seed's form has no bodies).

    Returns
    -------
    str
        One of :data:`KINDS`.
    """
    if offers(system, HasExternalFields) and system.external_fields:
        return IN_FIELD
    bodies: Sequence[object] = system.bodies if offers(system, HasBodies) else ()
    if len(bodies) >= 3 and _point_masses_under_gravity(system) and _dominant(bodies):
        return PLANETARY
    if len(bodies) == 2 or (not bodies and relative):
        return TWO_BODY
    return NBODY


def _point_masses_under_gravity(system: object) -> bool:
    if not (offers(system, HasBodies) and system.n_tops == 0 and offers(system, HasGravity)):
        return False
    try:
        system.gravity_constant()
    except PoissonkitError:  # no all-pairs gravity
        return False
    return True


def _dominant(bodies: Sequence[object]) -> bool:
    masses = sorted((float(b.mass) if offers(b, _Massive) else 0.0 for b in bodies),
                    reverse=True)
    return masses[1] > 0 and masses[0] >= DOMINANCE * masses[1]
