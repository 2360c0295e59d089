"""The named data and scratch that the compiled N-body kernels read.

Every constant a kernel needs travels in one :class:`SystemData` (the system's ``data``) and
every scratch array in one :class:`Work` (``system.work()``). Both are ``typing.NamedTuple``:
numba compiles ``data.mass`` to the same code as a static index, so naming a slot costs
nothing at run time, and a kernel never depends on where a slot sits. The lean direct-sum
kernels (:mod:`~poissonkit.numerics.nbody.direct`) read the shorter :class:`DirectData` /
:class:`DirectWork`.

The arrays are built here and only here (:func:`system_data`, :func:`empty_field_data`,
:func:`new_work`, :func:`direct_data`), from what
:class:`~poissonkit.numerics.nbody.NBodySystem` resolved in internal units.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
from numba.typed import List


class FieldData(NamedTuple):
    """The external fields of a system (:mod:`~poissonkit.numerics.fields.compose`).

    Without fields every array is empty, so systems with and without fields share one type.
    """

    #: kernel number of each field (int64)
    kernel: np.ndarray
    #: field ``f``'s parameters are ``params[offsets[f]:offsets[f + 1]]`` (int64)
    offsets: np.ndarray
    #: the fields' parameters, end to end (float64)
    params: np.ndarray
    #: ``(n_bodies, n_fields)``: how strongly field ``f`` acts on body ``b`` (0: not at all)
    coupling: np.ndarray
    #: ``(length unit, 1 / energy unit)``: field kernels work in SI
    units: np.ndarray


class SystemData(NamedTuple):
    """The constants of one :class:`~poissonkit.numerics.nbody.NBodySystem` (internal units)."""

    #: masses of the moving bodies, in state order
    mass: np.ndarray
    #: ``alpha = 1/I_⊥`` of the moving tops, in state order
    alpha: np.ndarray
    #: state slot of each body (``-1``: fixed)
    body_slot: np.ndarray
    #: top slot of each body (``-1``: not a moving top)
    top_slot: np.ndarray
    #: positions of the fixed bodies (rows of moving bodies unused)
    fixed_pos: np.ndarray
    #: unit axes of the fixed tops (other rows unused)
    fixed_axis: np.ndarray
    #: ``(k, 3)`` listed pairs ``(i, j, kernel)`` evaluated by the general pair term
    pairs: np.ndarray
    #: the members of every all-pairs set, end to end
    set_members: np.ndarray
    #: set ``g``'s members are ``set_members[set_offsets[g]:set_offsets[g + 1]]``
    set_offsets: np.ndarray
    #: kernel number of each all-pairs set
    set_kernel: np.ndarray
    #: interaction radius (``inf``: none)
    cutoff: float
    #: per-body attributes read by the potentials, then a row of run-time parameters / units
    table: np.ndarray
    #: ``(k, 3)`` listed orientation-free pairs ``(i, j, kernel)`` (the fast path)
    radial_pairs: np.ndarray
    #: 1 for an all-pairs set evaluated by the orientation-free term
    set_central: np.ndarray
    #: whether any body is a top (else axes and torques are never read)
    any_tops: bool
    #: start of the smooth cutoff (``inf``: truncated)
    switch_start: float
    #: fewest members of a set for the parallel pair loop
    parallel_min: int
    #: the external fields
    fields: FieldData


class VerletState(NamedTuple):
    """One system's neighbour lists (:mod:`~poissonkit.numerics.nbody.verlet`)."""

    #: per set ``k``: ``ints[3k : 3k + 3]`` = slot → body, CSR offsets, first slot of each slab
    ints: List
    #: per set: the neighbour slots (uint32)
    nbrs: List
    #: per set: the positions at the last build, in slot order
    refs: List
    #: the skin (internal units)
    skin: float


class Work(NamedTuple):
    """Scratch of the general kernels; rows are all bodies."""

    #: positions
    pos: np.ndarray
    #: axes
    nu: np.ndarray
    #: forces, left here by ``kernels.forces``
    F: np.ndarray
    #: torques, left here by ``kernels.forces``
    T: np.ndarray
    #: the neighbour lists of a system with a skin, else ``None``
    lists: VerletState | None


class DirectData(NamedTuple):
    """The constants of the direct-sum kernels (moving point masses, no cutoff)."""

    mass: np.ndarray
    set_members: np.ndarray
    set_offsets: np.ndarray
    set_kernel: np.ndarray
    table: np.ndarray


class DirectWork(NamedTuple):
    """Scratch of the direct-sum kernels; rows are the bodies."""

    pos: np.ndarray
    F: np.ndarray


def empty_field_data(n_bodies: int) -> FieldData:
    """The field data of a system without external fields."""
    return FieldData(np.zeros(0, dtype=np.int64), np.zeros(1, dtype=np.int64), np.zeros(0),
                     np.zeros((n_bodies, 0)), np.array([1.0, 1.0]))


def _pairs(rows: Sequence[tuple[int, int, int]]) -> np.ndarray:
    return np.array(rows, dtype=np.int64).reshape(-1, 3)


def system_data(*, mass: np.ndarray, alpha: np.ndarray, body_slot: np.ndarray,
                top_slot: np.ndarray, fixed_pos: np.ndarray, fixed_axis: np.ndarray,
                pairs: Sequence[tuple[int, int, int]], set_members: Sequence[int],
                set_offsets: Sequence[int], set_kernel: Sequence[int], cutoff: float,
                table: np.ndarray, radial_pairs: Sequence[tuple[int, int, int]],
                set_central: Sequence[int], any_tops: bool, switch_start: float,
                parallel_min: int, fields: FieldData) -> SystemData:
    """A :class:`SystemData` with every array in the dtype and shape the kernels read."""
    return SystemData(
        mass=mass, alpha=alpha, body_slot=body_slot, top_slot=top_slot, fixed_pos=fixed_pos,
        fixed_axis=fixed_axis, pairs=_pairs(pairs),
        set_members=np.array(set_members, dtype=np.int64),
        set_offsets=np.array(set_offsets, dtype=np.int64),
        set_kernel=np.array(set_kernel, dtype=np.int64), cutoff=float(cutoff), table=table,
        radial_pairs=_pairs(radial_pairs), set_central=np.array(set_central, dtype=np.int64),
        any_tops=bool(any_tops), switch_start=float(switch_start),
        parallel_min=int(parallel_min), fields=fields)


def new_work(n_bodies: int, lists: VerletState | None = None) -> Work:
    """Fresh scratch for ``n_bodies`` bodies (and a system's neighbour lists, if it has any)."""
    return Work(np.zeros((n_bodies, 3)), np.zeros((n_bodies, 3)), np.zeros((n_bodies, 3)),
                np.zeros((n_bodies, 3)), lists)


def direct_data(data: SystemData) -> DirectData:
    """The direct-sum kernels' share of a system's data."""
    return DirectData(data.mass, data.set_members, data.set_offsets, data.set_kernel, data.table)


def new_direct_work(n_bodies: int) -> DirectWork:
    """Fresh scratch for the direct-sum kernels."""
    return DirectWork(np.zeros((n_bodies, 3)), np.zeros((n_bodies, 3)))
