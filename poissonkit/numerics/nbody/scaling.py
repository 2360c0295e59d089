"""The bodies of an N-body system in internal units: state slots, masses, fixed positions.

With :class:`~poissonkit.numerics.units.Scales` every SI number is divided by its unit here
(``m/M``, ``alpha·M L²``, ``r/L``); without scales it is used as given.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple, cast

import numpy as np

from poissonkit.errors import InputError
from poissonkit.numerics.nbody.bodies import Body
from poissonkit.numerics.units import Scales


class Units(NamedTuple):
    """The internal units: length, mass, energy and time (all 1 without scales)."""

    length: float
    mass: float
    energy: float
    time: float


def units_of(scales: Scales | None) -> Units:
    """The units of ``scales`` (SI per internal unit), or ones."""
    if scales is None:
        return Units(1.0, 1.0, 1.0, 1.0)
    return Units(scales.length, scales.mass, scales.energy, scales.time)


class BodyArrays(NamedTuple):
    """Where each body lives in the state and its constants, in internal units."""

    #: indices of the moving bodies, in state order
    moving: tuple[int, ...]
    #: indices of the moving tops, in state order
    tops: tuple[int, ...]
    #: state slot of each body (``-1``: fixed)
    body_slot: np.ndarray
    #: top slot of each body (``-1``: not a moving top)
    top_slot: np.ndarray
    #: masses of the moving bodies
    mass: np.ndarray
    #: ``alpha`` of the moving tops
    alpha: np.ndarray
    #: positions of the fixed bodies (other rows zero)
    fixed_pos: np.ndarray
    #: unit axes of the fixed tops (other rows zero)
    fixed_axis: np.ndarray


def body_arrays(bodies: Sequence[Body], units: Units) -> BodyArrays:
    """The state slots and the scaled constants of ``bodies``.

    Raises
    ------
    InputError
        If a fixed top has a zero axis.
    """
    L, M = units.length, units.mass
    moving = [k for k, b in enumerate(bodies) if not b.fixed]
    tops = [k for k in moving if bodies[k].is_top]
    bslot = np.full(len(bodies), -1, dtype=np.int64)
    tslot = np.full(len(bodies), -1, dtype=np.int64)
    bslot[moving] = np.arange(len(moving))
    tslot[tops] = np.arange(len(tops))
    mass = np.array([bodies[k].mass / M for k in moving], dtype=float)
    alpha = np.array([cast(float, bodies[k].alpha) * M * L * L for k in tops], dtype=float)
    fpos = np.zeros((len(bodies), 3))
    fnu = np.zeros((len(bodies), 3))
    for k, b in enumerate(bodies):
        if b.fixed:
            fpos[k] = np.asarray(b.position, dtype=float) / L
            if b.is_top:
                ax = np.asarray(b.axis, dtype=float)
                n = np.linalg.norm(ax)
                if not n > 0:
                    raise InputError(f"fixed top {b.name!r} has a zero axis")
                fnu[k] = ax / n
    return BodyArrays(tuple(moving), tuple(tops), bslot, tslot, mass, alpha, fpos, fnu)
