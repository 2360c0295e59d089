"""Energy and right-hand side of a compiled pair system, with coincident bodies diagnosed.

Shared by :class:`~poissonkit.numerics.nbody.NBodySystem` and
:class:`~poissonkit.numerics.twobody.TwoBodySystem`: a potential kernel divides by the distance,
so a non-finite result (or a division by zero) is checked against coincident bodies and
reported as :class:`OverlapError` instead of a bare number or a numba traceback.
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np
import numpy.typing as npt

from poissonkit.errors import OverlapError
from poissonkit.numerics.kernels import Kernels


class PairSystem(Protocol):
    """What :func:`evaluate_energy` and :func:`evaluate_rhs` need of a compiled pair system."""

    @property
    def kernels(self) -> Kernels:
        """The compiled kernels (``energy(y, data, work)``, ``rhs(y, data, work, out)``)."""

    @property
    def data(self) -> tuple[object, ...]:
        """The constant arrays and numbers passed to every kernel."""

    def work(self) -> tuple[object, ...]:
        """Fresh scratch arrays for the kernels."""

    def _state(self, y: npt.ArrayLike) -> np.ndarray:
        """``y`` as a contiguous float state of the system's length (else a typed error)."""

    def check_overlap(self, y: npt.ArrayLike) -> None:
        """Raise :class:`OverlapError` if two bodies of state ``y`` coincide."""


def coincident_pair(positions: np.ndarray, fixed: np.ndarray) -> tuple[int, int] | None:
    """Indices of two bodies at exactly the same position, or ``None``.

    Pairs of two fixed bodies are ignored (they exert no force on any degree of freedom).
    Sorting makes this O(n log n), so it is cheap even for large systems.
    """
    if positions.shape[0] < 2:
        return None
    order = np.lexsort(positions.T[::-1])
    ordered = positions[order]
    same = np.all(ordered[1:] == ordered[:-1], axis=1)
    # identical rows are adjacent after sorting, so a group holding a moving body has an
    # adjacent pair with a moving member
    for k in np.nonzero(same)[0]:
        a, b = int(order[k]), int(order[k + 1])
        if not (fixed[a] and fixed[b]):
            return (min(a, b), max(a, b))
    return None


def evaluate_energy(system: PairSystem, y: npt.ArrayLike) -> float | np.ndarray:
    """``H(y)`` of a compiled system (``kernels.energy``); rows of a 2-D array give one value each.

    Shared by :class:`NBodySystem` and :class:`~poissonkit.numerics.twobody.TwoBodySystem`.
    A non-finite value or a division by zero inside a potential kernel is checked against
    coincident bodies and then raises :class:`OverlapError`.
    """
    y = np.asarray(y, dtype=float)
    w = system.work()
    energy = system.kernels.energy

    def one(row: np.ndarray) -> float:
        state = system._state(row)
        try:
            value = float(energy(state, system.data, w))
        except ZeroDivisionError:
            system.check_overlap(state)
            raise
        if not math.isfinite(value):
            system.check_overlap(state)
        return value

    if y.ndim == 2:
        return np.array([one(row) for row in y])
    return one(y)


def evaluate_rhs(system: PairSystem, y: npt.ArrayLike) -> np.ndarray:
    """``ẏ`` of a compiled system (``kernels.rhs``), raising :class:`OverlapError` at coincidences."""
    y = system._state(y)
    out = np.empty_like(y)
    try:
        system.kernels.rhs(y, system.data, system.work(), out)
    except ZeroDivisionError:
        system.check_overlap(y)
        raise
    if not np.all(np.isfinite(out)):
        system.check_overlap(y)
    return out
